"""The compiled kernels of the extrapolated corner tips (``fitting._tip_kernels``) pinned bit for bit to the numpy
formulation they replaced (written out here, as ``tips.py`` had it before session 30), on crack outlines of
rendered polygons and on random points."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from splinecraft.capture.fitting import _tip_kernels, tips
from splinecraft.capture.fitting.lsq_setup import RotatedContour

from test_tips import render


# --- the numpy formulation -------------------------------------------------------------------------------------
def _inkward(side, points):
    local = points - side.centre
    if not side.coefficients.any():
        return side.ink * (local @ side.normal)
    t, y = local @ side.direction, local @ side.normal
    c0, c1, c2 = side.coefficients
    return side.ink * (y - (c0 + t * (c1 + t * c2)))


def _point_at_arc(contour, arc):
    return np.column_stack([np.interp(arc, contour.arc, contour.closed_points[:, 0]),
                            np.interp(arc, contour.arc, contour.closed_points[:, 1])])


def _arc_window(contour, corner_arc, sign, start, stop):
    arc, perimeter = contour.arc[:-1], contour.perimeter
    low, high = (corner_arc + start, corner_arc + stop) if sign > 0 else (corner_arc - stop, corner_arc - start)
    shift = np.floor(low / perimeter) * perimeter
    low, high = low - shift, high - shift
    indices = np.arange(np.searchsorted(arc, low, side="left"),
                        np.searchsorted(arc, min(high, perimeter), side="right"))
    if high > perimeter:
        indices = np.concatenate([indices, np.arange(0, np.searchsorted(arc, high - perimeter, side="right"))])
    return indices


def _window_fit(points, length):
    centre = np.add.reduce(points, axis=0) / points.shape[0]
    local = points - centre
    direction = np.linalg.svd(local, full_matrices=False)[2][0]
    normal = np.array([-direction[1], direction[0]])
    t, y = local @ direction, local @ normal
    if np.abs(y).max() <= tips.STRAIGHT_RESIDUAL:
        return tips.SideFit(centre, direction, np.zeros(3), length)
    coefficients = tips._parabola(t, y)
    return None if coefficients is None else tips.SideFit(centre, direction, coefficients, length)


def _separating_line(fit, ink, paper):
    from splinecraft.capture.fitting._kernels import separating_slope

    ink_local, paper_local = ink - fit.centre, paper - fit.centre
    t_ink, y_ink = ink_local @ fit.direction, ink_local @ fit.normal
    t_paper, y_paper = paper_local @ fit.direction, paper_local @ fit.normal
    sign = 1.0 if y_ink.sum() / y_ink.shape[0] >= y_paper.sum() / y_paper.shape[0] else -1.0
    y_ink, y_paper = sign * y_ink, sign * y_paper
    slope = separating_slope(t_ink, y_ink, t_paper, y_paper, tips._FIRST_SLOPES, tips.SLOPE_SEARCH / 8, 5)
    above, below = (y_ink - slope * t_ink).min(), (y_paper - slope * t_paper).max()
    margin = 0.5 * (above - below)
    if margin <= 0.0:
        return None
    offset = sign * 0.5 * (above + below)
    direction = fit.direction + sign * slope * fit.normal
    direction /= np.hypot(*direction)
    return tips.SideFit(fit.centre + offset * fit.normal, direction, np.zeros(3), fit.length, sign,
                        float(margin / np.hypot(1.0, slope)))


def _side_fit(contour, corner_arc, sign, start, stop, pairs=None):
    if stop - start < tips.SHORTEST_SIDE:
        return None
    offsets = np.arange(start, stop + 1e-9, 0.5)
    samples = _point_at_arc(contour, (corner_arc + sign * offsets) % contour.perimeter)
    count = offsets.shape[0]
    while stop - start >= tips.SHORTEST_SIDE:
        fit = _window_fit(samples[:count], stop - start)
        if fit is not None:
            if pairs is not None:
                window = _arc_window(contour, corner_arc, sign, start, stop)
                if window.size >= 4:
                    ink, paper = pairs[0].take(window, axis=0), pairs[1].take(window, axis=0)
                    separating = None if fit.coefficients.any() else _separating_line(fit, ink, paper)
                    if separating is not None:
                        return separating
                    across = (ink - paper) @ fit.normal
                    fit.ink = 1.0 if np.add.reduce(across) / across.shape[0] >= 0 else -1.0
            return fit
        stop = start + 0.75 * (stop - start)
        count = np.arange(start, stop + 1e-9, 0.5).shape[0]
    return None


def _ray_parity(cracks, queries):
    run = cracks[np.searchsorted(cracks[:, 0], queries[:, 0].min(), side="left"):
                 np.searchsorted(cracks[:, 0], queries[:, 0].max(), side="right")]
    above = (run[None, :, 0] == queries[:, None, 0]) & (run[None, :, 1] < queries[:, None, 1])
    return above.sum(axis=1) % 2


def _is_convex(sides):
    return _inkward(sides[0], sides[1].centre[None])[0] > 0


def _tip_contradiction(contour, corner_arc, zone, sides, pairs, convex):
    zone_points = np.concatenate([_arc_window(contour, corner_arc, -1, 0.0, zone),
                                  _arc_window(contour, corner_arc, 1, 0.0, zone)])
    ink, paper = pairs[0].take(zone_points, axis=0), pairs[1].take(zone_points, axis=0)
    combine = np.minimum if convex else np.maximum
    ink_depth = combine(_inkward(sides[0], ink), _inkward(sides[1], ink))
    paper_depth = combine(_inkward(sides[0], paper), _inkward(sides[1], paper))
    return float(max((-ink_depth).max(), paper_depth.max()))


def _wedge_contradiction(cracks, pairs, tip, ends, sides, convex, ink_parity):
    corners = np.empty((3, 2))
    corners[0], corners[1:] = tip, ends
    low, high = np.floor(corners.min(axis=0)), np.ceil(corners.max(axis=0))
    xs, ys = np.arange(low[0], high[0]) + 0.5, np.arange(low[1], high[1]) + 0.5
    grid = np.empty((xs.shape[0], ys.shape[0], 2))
    grid[:, :, 0], grid[:, :, 1] = xs[:, None], ys[None, :]
    centres = grid.reshape(-1, 2)
    inside = np.ones(centres.shape[0], bool)
    for k in range(3):
        first, second, opposite = corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]
        edge = second - first
        side = edge[0] * (opposite[1] - first[1]) - edge[1] * (opposite[0] - first[0])
        inside &= (edge[0] * (centres[:, 1] - first[1]) - edge[1] * (centres[:, 0] - first[0])) * side > 0.0
    if not inside.any():
        return -np.inf
    centres = centres.compress(inside, axis=0)
    sign = 1.0 if convex else -1.0
    wedge_depth = np.minimum(sign * _inkward(sides[0], centres) - sides[0].margin,
                             sign * _inkward(sides[1], centres) - sides[1].margin)
    ink = _ray_parity(cracks, centres) == ink_parity
    wrong = (~ink if convex else ink) & (wedge_depth > 0.0)
    return float(wedge_depth[wrong].max()) if wrong.any() else -np.inf


def _tip(contour, c, sides, is_shared, corner_arc, start, pairs, cracks, parity):
    windows = [side.length for side, shared in zip(sides, is_shared) if not shared]
    point = tips._crossing(*sides)
    if point is None or not np.isfinite(point).all():
        return None
    corner_point = contour.points[contour.corner_bounds[c] % contour.size]
    ends = _point_at_arc(contour, (corner_arc + np.array([-start, start])) % contour.perimeter)
    away = [side.tangent(side.local(point)) for side in sides]
    away = [a * np.sign((side.centre - point) @ a) / np.hypot(*a) for a, side in zip(away, sides)]
    opening = np.arccos(np.clip(away[0] @ away[1], -1.0, 1.0))
    if np.hypot(*(point - corner_point)) > min(tips.tip_reach(opening), tips.REACH_PER_SIDE * min(windows)):
        return None
    outward = corner_point - 0.5 * (ends[0] + ends[1])
    if outward @ (point - corner_point) < -tips.BEHIND * np.hypot(*outward):
        return None
    if pairs is not None and sides[0].ink and sides[1].ink:
        convex = _is_convex(sides)
        if _tip_contradiction(contour, corner_arc, start + tips.TIP_ZONE, sides, pairs, convex) > \
                tips.CONTRADICTION or \
                _wedge_contradiction(cracks, pairs, point, ends, sides, convex, parity) > tips.CONTRADICTION:
            return None
    return point, opening, ends


# --- outlines --------------------------------------------------------------------------------------------------
def _outline(seed):
    """The crack outline of a rendered random star-like polygon (acute and obtuse corners, straight and
    slanted sides), as a contour with a corner at every vertex's nearest outline point."""
    from test_tips import crack_outline

    rng = np.random.default_rng(seed)
    count = int(rng.integers(3, 8))
    angles = np.sort(rng.uniform(0, 2 * np.pi, count))
    radii = rng.uniform(12, 34, count)
    centre = 40 + rng.uniform(-0.5, 0.5, 2)
    vertices = centre + radii[:, None] * np.column_stack([np.cos(angles), np.sin(angles)])
    mask = render(vertices, 80)
    points = crack_outline(mask)
    nearest = np.unique([int(np.argmin(np.hypot(*(points - v).T))) for v in vertices])
    return RotatedContour(points, nearest), tips.pixel_pairs(points)


def _same_side(got, want):
    if want is None:
        return got is None
    return got is not None and np.array_equal(got.row, want.row, equal_nan=True)


@pytest.mark.parametrize("seed", range(12))
def test_side_fits_and_tips_match_the_numpy_formulation(seed):
    """Every corner's sides (windows shrunk and grown, with and without pixel pairs) and the tip tests of their
    crossing: bit for bit the numpy formulation."""
    contour, pairs = _outline(seed)
    cracks = tips.horizontal_cracks(contour.points)
    parity = int(_ray_parity(cracks, pairs[0][:1])[0])
    assert tips.ray_parity(cracks, pairs[0][:1])[0] == parity
    rng = np.random.default_rng(seed)
    tested = 0
    for c in range(contour.corner_count):
        corner_arc = contour.arc[contour.corner_bounds[c]]
        for start, length in ((1.0, 48.0), (rng.uniform(1.0, 6.0), rng.uniform(4.0, 30.0)), (2.0, 5.0)):
            sides, reference = [], []
            for k in (0, 1):
                for with_pairs in (None, pairs):
                    got = tips.side_fit(contour, corner_arc, 2 * k - 1, start, start + length, with_pairs)
                    want = _side_fit(contour, corner_arc, 2 * k - 1, start, start + length, with_pairs)
                    assert _same_side(got, want)
                sides.append(got)
                reference.append(want)
            if any(side is None for side in sides):
                continue
            tested += 1
            for shared in ((False, False), (True, False)):
                got = tips._tip(contour, c, sides, shared, corner_arc, start, pairs, cracks, parity)
                want = _tip(contour, c, reference, shared, corner_arc, start, pairs, cracks, parity)
                assert (got is None) == (want is None)
                if got is not None:
                    for a, b in zip(got, want):
                        assert np.array_equal(a, b)
            convex = _is_convex(reference)
            assert tips.is_convex(sides) == convex
            assert tips.tip_contradiction(contour, corner_arc, start + 1.0, sides, pairs) == \
                _tip_contradiction(contour, corner_arc, start + 1.0, reference, pairs, convex)
            tip = contour.points[contour.corner_bounds[c]] + rng.uniform(-3, 3, 2)
            ends = _point_at_arc(contour, (corner_arc + np.array([-start, start])) % contour.perimeter)
            assert tips.wedge_contradiction(cracks, pairs, tip, ends, sides) == \
                _wedge_contradiction(cracks, pairs, tip, ends, reference, convex, parity)
    assert tested


@pytest.mark.parametrize("seed", range(12))
def test_batched_sides_and_line_tips_are_the_single_ones(seed):
    """``side_fits`` (windows of many lengths, some too short, straight and curved, with and without pixel pairs)
    gives each side ``side_fit`` gives, and ``line_tip_checks`` each corner's ``tip_checks`` (between two lines),
    bit for bit: the batches run the same operations per side and corner."""
    contour, pairs = _outline(seed)
    cracks = tips.horizontal_cracks(contour.points)
    rng = np.random.default_rng(seed)
    requests = []
    for c in range(contour.corner_count):
        corner_arc = contour.arc[contour.corner_bounds[c]]
        for start, length in ((1.0, 48.0), (rng.uniform(1.0, 6.0), rng.uniform(2.0, 30.0)), (2.0, 5.0)):
            requests += [(corner_arc, sign, start, start + length) for sign in (-1, 1)]
    for with_pairs in (None, pairs):
        got = tips.side_fits(contour, requests, with_pairs)
        assert len(got) == len(requests)
        for request, side in zip(requests, got):
            assert _same_side(side, tips.side_fit(contour, *request, with_pairs))
    assert tips.side_fits(contour, [], pairs) == []
    sides = tips.side_fits(contour, requests, pairs)
    corners, rows, windows, starts = [], [], [], []
    for c in range(contour.corner_count):
        first, second = sides[6 * c], sides[6 * c + 1]
        if first is None or second is None or first.coefficients.any() or second.coefficients.any():
            continue
        corners.append(c)
        rows.append((first.row, second.row))
        windows.append([first.length] if c % 2 else [first.length, second.length])
        starts.append(requests[6 * c][2])
    assert corners
    ink, paper = pairs
    checked = _tip_kernels.line_tip_checks(
        contour, [contour.corner_bounds[c] % contour.size for c in corners],
        [contour.arc[contour.corner_bounds[c]] for c in corners], starts, [r[0] for r in rows], [r[1] for r in rows],
        windows, ink, paper, cracks, tips._SIN_MIN_CROSSING, tips._TIP_LIMITS)
    for c, (first, second), window, start, got in zip(corners, rows, windows, starts, checked):
        want = _tip_kernels.tip_checks(contour, contour.corner_bounds[c] % contour.size,
                                       contour.arc[contour.corner_bounds[c]], start, first, second, np.array(window),
                                       None, ink, paper, cracks, -1, tips._SIN_MIN_CROSSING, tips._TIP_LIMITS)
        assert (got is None) == (want is None)
        if got is not None:
            for a, b in zip(got, want):
                assert np.asarray(a).tobytes() == np.asarray(b).tobytes()


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 120), st.integers(1, 120), st.integers(0, 10_000), st.booleans())
def test_separating_lines_and_offsets_match_the_numpy_formulation(inks, papers, seed, curved):
    """``tips._separating_line`` and ``SideFit.inkward`` (one point and many; straight and curved sides) in any
    frame, on centres either side of a line or mixed: bit for bit the numpy formulation."""
    rng = np.random.default_rng(seed)
    slope, offset = rng.uniform(-0.3, 0.3), rng.uniform(-1, 1)
    t_ink, t_paper = rng.uniform(-20, 20, inks), rng.uniform(-20, 20, papers)
    ink = np.column_stack([t_ink, slope * t_ink + offset + rng.uniform(0.05, 1.5, inks)])
    paper = np.column_stack([t_paper, slope * t_paper + offset - rng.uniform(-0.2 * (seed % 2), 1.5, papers)])
    turn = rng.uniform(0, 2 * np.pi)
    rotation = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    ink, paper = ink @ rotation.T + 40.0, paper @ rotation.T + 40.0
    direction = rotation[:, 0] + rng.normal(0, 0.05, 2)
    direction /= np.hypot(*direction)
    fit = tips.SideFit(rng.uniform(30, 50, 2), direction, rng.normal(0, 0.1, 3) if curved else np.zeros(3), 20.0,
                       ink=float(rng.choice([-1.0, 1.0])), margin=rng.uniform(0, 0.5))
    if not curved:
        assert _same_side(tips._separating_line(fit, ink, paper), _separating_line(fit, ink, paper))
    for points in (ink, paper[:1], ink[:1]):
        np.testing.assert_array_equal(fit.inkward(points), _inkward(fit, points))


@njit
def _pairwise(values, n):
    return _tip_kernels._pairwise_sum(values, n)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 240), st.integers(0, 10_000))
def test_pairwise_sum_is_numpy_sum(n, seed):
    """numpy's pairwise summation of up to 240 values (every window of the tips)."""
    values = np.random.default_rng(seed).normal(size=n) * 10.0 ** np.random.default_rng(seed).integers(-3, 6, n)
    assert _pairwise(values, n) == values.sum()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.floats(0.0, 8.0), st.floats(0.0, 60.0), st.sampled_from([-1, 1]))
def test_window_samples_and_centre_match_numpy(seed, start, length, sign):
    """The window's samples (``numpy.arange`` offsets, ``numpy.interp`` of the polyline), their centre
    (``numpy.add.reduce`` along the first axis) and offsets from it; the frame offsets of a direction (``a @ v``
    of BLAS) and the straight test."""
    contour, _ = _outline(seed % 12)
    corner_arc = contour.arc[contour.corner_bounds[0]] + (seed % 7) * 1.3
    stop = start + length
    samples, local, centre = _tip_kernels.window_samples(contour, corner_arc, sign, start, stop)
    offsets = np.arange(start, stop + 1e-9, 0.5)
    want = _point_at_arc(contour, (corner_arc + sign * offsets) % contour.perimeter)
    np.testing.assert_array_equal(samples, want)
    if not want.shape[0]:
        return
    np.testing.assert_array_equal(centre, np.add.reduce(want, axis=0) / want.shape[0])
    np.testing.assert_array_equal(local, want - centre)
    direction = np.array([np.cos(seed), np.sin(seed)])
    t, y, straight = _tip_kernels.frame_offsets(local, direction)
    np.testing.assert_array_equal(t, local @ direction)
    np.testing.assert_array_equal(y, local @ np.array([-direction[1], direction[0]]))
    assert straight == (np.abs(y).max() <= tips.STRAIGHT_RESIDUAL)


def test_the_straight_residual_is_the_tips_one():
    assert _tip_kernels._STRAIGHT == tips.STRAIGHT_RESIDUAL
