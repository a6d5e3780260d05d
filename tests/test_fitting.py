"""Tests of capture/fitting.py: the thesis's knot insertion (Algs 4.1-4.6) and the default ``"lsq"`` method.

Test shapes are rasterized here (pixel ink when its centre is inside the exact outline), traced with the
project's own crack-outline tracer; corners are the outline points nearest to the exact polygon vertices, so
the tests do not depend on a corner detector. Geometric deviations are re-measured independently (dense
samples of the result, ``scipy.spatial.cKDTree``, exact point-to-segment distances).
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import cKDTree

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.fitting import (
    DEFAULT_METHOD,
    KNOT_METHODS,
    THESIS_METHODS,
    FitResult,
    Snapshot,
    fit_outline,
    piece_deviation,
)
from splinecraft.spline import Spline

THESIS = list(THESIS_METHODS)
ALL = ["lsq"] + THESIS


# ------------------------------------------------------------------------------------------ test shapes

def _inside_polygon(x, y, vertices):
    """Even-odd point-in-polygon, vectorized over points (x, y)."""
    inside = np.zeros(x.shape, bool)
    vx, vy = vertices[:, 0], vertices[:, 1]
    for i in range(len(vertices)):
        x0, y0, x1, y1 = vx[i - 1], vy[i - 1], vx[i], vy[i]
        crosses = (y0 > y) != (y1 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
        inside ^= crosses & (x < xc)
    return inside


def raster(vertices, size):
    yy, xx = np.mgrid[0:size, 0:size]
    return _inside_polygon(xx + 0.5, yy + 0.5, np.asarray(vertices, float))


def polygon_shape(vertices, size):
    """(outline, corner indices, dense exact outline) of a rasterized polygon."""
    vertices = np.asarray(vertices, float)
    outline = trace_boundaries(raster(vertices, size))[0].outline
    corners = np.unique(cKDTree(outline).query(vertices)[1])
    dense = np.concatenate([np.linspace(vertices[i - 1], vertices[i], 400, endpoint=False)
                            for i in range(len(vertices))])
    return outline, corners, dense


def disc_shape(radius, centre, size):
    a = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    dense = np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)])
    yy, xx = np.mgrid[0:size, 0:size]
    mask = (xx + 0.5 - centre[0]) ** 2 + (yy + 0.5 - centre[1]) ** 2 < radius**2
    return trace_boundaries(mask)[0].outline, np.zeros(0, int), dense


def blob_shape(size=56):
    a = np.linspace(0, 2 * np.pi, 3000, endpoint=False)
    r = 18 * (1 + 0.18 * np.cos(3 * a + 0.4) + 0.1 * np.sin(5 * a))
    dense = np.column_stack([size / 2 + r * np.cos(a), size / 2 + r * np.sin(a)])
    mask = raster(dense, size)
    return trace_boundaries(mask)[0].outline, np.zeros(0, int), dense


def star_vertices(n=5, r_out=22.0, r_in=10.0, centre=(28.3, 27.6)):
    a = -np.pi / 2 + np.pi * np.arange(2 * n) / n
    r = np.where(np.arange(2 * n) % 2 == 0, r_out, r_in)
    return np.column_stack([centre[0] + r * np.cos(a), centre[1] + r * np.sin(a)])


SHAPES = {
    "disc": lambda: disc_shape(14.3, (20.2, 19.7), 40),
    "square": lambda: polygon_shape([(6.3, 7.1), (33.6, 5.2), (35.4, 32.8), (8.1, 34.5)], 42),
    "star": lambda: polygon_shape(star_vertices(), 56),
    "blob": blob_shape,
}
_CACHE = {}


def shape(name):
    if name not in _CACHE:
        _CACHE[name] = SHAPES[name]()
    return _CACHE[name]


# ------------------------------------------------------------------------------------------ independent checks

def _dense_samples(bezier, step=0.05):
    out = []
    for b in np.asarray(bezier, float):
        length = np.hypot(*np.diff(b, axis=0).T).sum()
        t = np.linspace(0, 1, max(4, int(np.ceil(length / step)) + 1))[:, None]
        out.append((1 - t) ** 3 * b[0] + 3 * t * (1 - t) ** 2 * b[1] + 3 * t**2 * (1 - t) * b[2] + t**3 * b[3])
    return np.concatenate(out)


def _dist_to_polyline(points, line):
    """Exact distance from points to a closed polyline (brute force over the 8 nearest edge midpoints)."""
    a, b = line, np.roll(line, -1, axis=0)
    _, idx = cKDTree((a + b) / 2).query(points, k=min(8, len(line)))
    aa, ab = a[idx], (b - a)[idx]
    ap = points[:, None, :] - aa
    t = np.clip((ap * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-18), 0, 1)
    return np.hypot(*(ap - t[..., None] * ab).transpose(2, 0, 1)).min(axis=1)


def hausdorff(bezier, outline):
    """Symmetric Hausdorff distance between Bézier pieces and a closed polyline, measured independently."""
    curve = _dense_samples(bezier)
    probes = np.vstack([outline, 0.5 * (outline + np.roll(outline, -1, axis=0))])
    return max(_dist_to_polyline(curve, outline).max(), _dist_to_polyline(probes, curve).max())


def tolerance(result):
    """The guarantee of the module docstring: epsilon, + 0.5 px near extrapolated corners for lsq."""
    return result.epsilon + (0.5 if result.method == "lsq" else 0.0)


# ------------------------------------------------------------------------------------------ every method reaches eps

@pytest.mark.parametrize("method", ALL)
@pytest.mark.parametrize("name", list(SHAPES))
def test_every_method_reaches_epsilon_with_the_geometric_guarantee(method, name):
    outline, corners, _ = shape(name)
    result = fit_outline(outline, corners, epsilon=1.0, method=method, seed=3, max_iterations=3000,
                         keep_snapshots=False)
    assert isinstance(result, FitResult) and isinstance(result.spline, Spline)
    assert result.converged
    assert result.hausdorff <= tolerance(result) + 1e-9
    measured = hausdorff(result.spline.bezier(), outline)
    # the reported deviation is an upper bound of the independently measured one, and the guarantee holds
    assert measured <= result.hausdorff + 0.05
    assert measured <= tolerance(result) + 0.05
    assert result.spline.closed


@pytest.mark.parametrize("method", THESIS)
def test_thesis_methods_interpolate_the_contour_at_their_knots(method):
    outline, corners, _ = shape("square")
    result = fit_outline(outline, corners, method=method, seed=1, max_iterations=3000, keep_snapshots=False)
    knot_points = result.spline.knot_points[:-1]
    expected = outline[np.concatenate([k[:-1] for k in result.knot_indices])]
    np.testing.assert_allclose(knot_points, expected, atol=1e-9)


# ------------------------------------------------------------------------------------------ seeds

@pytest.mark.parametrize("method", THESIS)
def test_seeded_runs_are_reproducible_and_seeds_differ(method):
    outline, corners, _ = shape("blob")
    kwargs = dict(epsilon=1.0, method=method, max_iterations=3000, keep_snapshots=False)
    a = fit_outline(outline, corners, seed=11, **kwargs)
    b = fit_outline(outline, corners, seed=11, **kwargs)
    c = fit_outline(outline, corners, seed=12, **kwargs)
    assert [k.tolist() for k in a.knot_indices] == [k.tolist() for k in b.knot_indices]
    np.testing.assert_array_equal(a.spline.bezier(), b.spline.bezier())
    assert [k.tolist() for k in a.knot_indices] != [k.tolist() for k in c.knot_indices]
    # a Generator can be passed instead of a seed
    d = fit_outline(outline, corners, seed=np.random.default_rng(11), **kwargs)
    assert [k.tolist() for k in a.knot_indices] == [k.tolist() for k in d.knot_indices]


def test_lsq_is_deterministic():
    outline, corners, _ = shape("star")
    a = fit_outline(outline, corners, seed=1)
    b = fit_outline(outline, corners, seed=2)
    np.testing.assert_array_equal(a.spline.bezier(), b.spline.bezier())


# ------------------------------------------------------------------------------------------ snapshots

@pytest.mark.parametrize("method", ALL)
@pytest.mark.parametrize("name", ["square", "blob"])
def test_snapshots_are_consistent(method, name):
    outline, corners, _ = shape(name)
    result = fit_outline(outline, corners, epsilon=1.0, method=method, seed=5, max_iterations=3000)
    snaps = result.snapshots
    assert snaps and all(isinstance(s, Snapshot) for s in snaps)
    first, last = snaps[0], snaps[-1]
    assert first.iteration == 0 and first.phase == "initial"
    if len(corners) >= 2:
        # first snapshot = corners only: every piece is [corner, next corner]
        assert [k.tolist() for k in first.knot_indices] == [[a, b] for a, b in result.pieces]
        assert sorted(a for a, _ in result.pieces) == sorted(corners.tolist())
    # last snapshot equals the result
    np.testing.assert_allclose(last.bezier, result.spline.bezier(), atol=1e-6)
    assert [k.tolist() for k in last.knot_indices] == [k.tolist() for k in result.knot_indices]
    assert np.isclose(last.hausdorff, result.hausdorff) and np.isclose(last.max_error, result.max_error)
    iterations = [s.iteration for s in snaps]
    assert iterations == sorted(iterations)
    # knot sets only grow per piece (lsq: during its insertion phase; its final phase removes knots)
    growing = [s for s in snaps if s.phase in ("initial", "insert")]
    for before, after in zip(growing, growing[1:]):
        for k0, k1 in zip(before.knot_indices, after.knot_indices):
            assert set(k0.tolist()) <= set(k1.tolist())
    for s in snaps:
        assert s.bezier.shape[1:] == (4, 2)
        assert len(s.piece_hausdorff) == len(s.piece_max_error) == len(result.pieces)
        spline = s.spline()
        assert spline.n_segments == len(s.bezier) and spline.closed
        for c in s.candidates:
            assert set(c) >= {"piece", "index", "point", "accepted", "reason", "membership"}
            assert isinstance(c["reason"], str) and c["reason"]
    assert result.iterations == snaps[-1].iteration


def test_fuzzy_candidates_report_losers_and_memberships():
    outline, corners, _ = shape("blob")
    result = fit_outline(outline, corners, method="fuzzy", seed=2, max_iterations=3000)
    cands = [c for s in result.snapshots for c in s.candidates]
    losers = [c for c in cands if c["reason"].startswith("fuzzy loser")]
    assert losers and all(not c["accepted"] for c in losers)
    assert all(c["membership"] is not None and 0.0 <= c["membership"] <= 1.0 for c in cands)
    accepted = [c for c in cands if c["accepted"]]
    assert accepted and all("d=" in c["reason"] for c in accepted)


def test_nearness_constraints_reject_candidates_near_knots():
    outline, corners, _ = shape("square")
    result = fit_outline(outline, corners, method="euclidean", tau=8.0, seed=4, max_iterations=3000)
    reasons = [c["reason"] for s in result.snapshots for c in s.candidates]
    assert any(r.startswith("within tau=8 px") for r in reasons)
    result = fit_outline(outline, corners, method="positional", tau=20.0, seed=4, max_iterations=3000)
    reasons = [c["reason"] for s in result.snapshots for c in s.candidates]
    assert any(r.startswith("within tau=20%") for r in reasons)


def test_thesis_rule_stops_before_the_geometric_rule():
    """The thesis stops at the first iteration without an accepted candidate; the geometric rule goes on."""
    outline, corners, _ = shape("blob")
    result = fit_outline(outline, corners, method="random", seed=0, max_iterations=3000)
    assert result.thesis_stop_iteration is not None
    stop = result.snapshots[result.thesis_stop_iteration]
    assert stop.thesis_stop
    assert result.thesis_stop_iteration <= result.iterations


# ------------------------------------------------------------------------------------------ default vs fuzzy

def test_default_needs_fewer_knots_and_iterations_than_fuzzy():
    assert DEFAULT_METHOD == "lsq"
    knots_lsq, knots_fuzzy, it_lsq, it_fuzzy = [], [], [], []
    for name in SHAPES:
        outline, corners, _ = shape(name)
        lsq = fit_outline(outline, corners, keep_snapshots=False)
        fuzzy = [fit_outline(outline, corners, method="fuzzy", seed=s, max_iterations=3000, keep_snapshots=False)
                 for s in range(3)]
        knots_lsq.append(lsq.knots_inserted + len(corners))
        knots_fuzzy.append(np.mean([f.knots_inserted + len(corners) for f in fuzzy]))
        it_lsq.append(lsq.iterations)
        it_fuzzy.append(np.mean([f.iterations for f in fuzzy]))
    assert np.mean(knots_lsq) < 0.7 * np.mean(knots_fuzzy)
    assert np.mean(it_lsq) < np.mean(it_fuzzy)


# ------------------------------------------------------------------------------------------ analytic outlines

ANALYTIC = {
    "disc": lambda: disc_shape(31.3, (40.2, 39.7), 80),
    "square": lambda: polygon_shape([(10.3, 12.1), (70.6, 6.2), (75.4, 66.8), (14.1, 71.5)], 84),
    "star": lambda: polygon_shape(star_vertices(5, 45.0, 21.0, (52.3, 51.6)), 104),
    "blob": blob_shape,
}


@pytest.mark.parametrize("name", list(ANALYTIC))
def test_lsq_fit_is_close_to_the_analytic_outline(name):
    """The fit of a rasterized analytic shape is within epsilon + 0.5 px of the exact outline (shapes of a few
    dozen px; a 46 degree star tip is truncated by about 1.3 px in the bitmap and must be extrapolated)."""
    outline, corners, dense = ANALYTIC[name]()
    result = fit_outline(outline, corners, epsilon=1.0)
    curve = _dense_samples(result.spline.bezier())
    deviation = max(_dist_to_polyline(curve, dense).max(), _dist_to_polyline(dense, curve).max())
    assert deviation <= result.epsilon + 0.5


def test_lsq_extrapolates_acute_corners_beyond_the_pixel_tip():
    outline, corners, dense = ANALYTIC["star"]()
    tips = star_vertices(5, 45.0, 21.0, (52.3, 51.6))[0::2]
    result = fit_outline(outline, corners)
    fitted = result.spline.knot_points
    pixel_tip = outline[cKDTree(outline).query(tips)[1]]
    fitted_tip = fitted[cKDTree(fitted).query(tips)[1]]
    assert np.hypot(*(fitted_tip - tips).T).mean() < np.hypot(*(pixel_tip - tips).T).mean()


@pytest.mark.parametrize("name", ["square", "star", "blob"])
def test_lsq_result_is_the_thesis_interpolant_through_its_knot_points(name):
    """With C2 joints (``joint_continuity=2``) every piece of the result is interpolate(F, knots, clamped) of
    the engine (v = 0, omega = 1), and an outline without corners is the engine's periodic interpolant through
    its knot points. Of the fit before merging (``merge_tolerance=0``): the merged outline is G1 only
    (docs/capture.md §12, "Merged segments"; test_merge)."""
    from splinecraft.spline import interpolate

    outline, corners, _ = shape(name)
    result = fit_outline(outline, corners, epsilon=0.6, joint_continuity=2, merge_tolerance=0.0)
    bez = result.spline.bezier()
    knots = result.spline.knots
    F = result.spline.knot_points
    assert result.spline.info["method"] == "lsq"
    intervals_per_piece = [len(k) - 1 for k in result.knot_indices]
    assert sum(intervals_per_piece) == bez.shape[0]
    if len(result.corners_used) == 0:
        assert F.shape[0] in (bez.shape[0], bez.shape[0] + 1)
        rebuilt = interpolate(F[:bez.shape[0]], closed=True, knots=knots).bezier()
        np.testing.assert_allclose(rebuilt, bez, atol=1e-7 * np.abs(bez).max())
        return
    first = 0
    for count in intervals_per_piece:
        sub = bez[first:first + count]
        t = knots[first:first + count + 1]
        points = np.vstack([sub[:, 0], sub[-1:, 3]])
        m0 = 3 * (sub[0, 1] - sub[0, 0]) / (t[1] - t[0])
        m1 = 3 * (sub[-1, 3] - sub[-1, 2]) / (t[-1] - t[-2])
        rebuilt = interpolate(points, knots=t, end_condition="clamped", end_tangents=(m0, m1)).bezier()
        np.testing.assert_allclose(rebuilt, sub, atol=1e-7 * np.abs(bez).max())
        first += count


# ------------------------------------------------------------------------------------------ property test

@settings(max_examples=25, deadline=None)
@given(st.integers(3, 7), st.floats(0.0, 1.0), st.floats(0.6, 1.6), st.integers(0, 10_000))
def test_lsq_guarantee_on_random_convex_polygons(count, rotation, epsilon, seed):
    rng = np.random.default_rng(seed)
    angles = np.sort(rng.uniform(0, 2 * np.pi, count)) + rotation
    gaps = np.diff(np.append(angles, angles[0] + 2 * np.pi))
    if gaps.max() > 0.8 * np.pi:  # keep it a proper convex polygon around the centre
        angles = rotation + 2 * np.pi * np.arange(count) / count
    radius = rng.uniform(10, 20)
    vertices = np.column_stack([24 + radius * np.cos(angles), 24 + radius * np.sin(angles)])
    outline, corners, _ = polygon_shape(vertices, 48)
    result = fit_outline(outline, corners, epsilon=epsilon, keep_snapshots=False)
    assert result.converged
    # docs/capture.md §12 "Guarantee": epsilon + 0.5 px near extrapolated tips, or the tip's distance from the
    # pixels where that is more, which the sharpest angle of the polygon bounds (tip_reach)
    from splinecraft.capture.fitting.tips import tip_reach

    edges = np.roll(vertices, -1, axis=0) - vertices
    previous = np.roll(edges, 1, axis=0)
    turn = np.arctan2(previous[:, 0] * edges[:, 1] - previous[:, 1] * edges[:, 0],
                      np.einsum("ij,ij->i", previous, edges))
    sharpest = np.pi - np.abs(turn).max()
    allowance = result.info["tolerance_near_corners"] - epsilon
    assert allowance <= max(0.5, tip_reach(sharpest - np.radians(10.0))) + 1e-9
    assert hausdorff(result.spline.bezier(), outline) <= epsilon + max(0.5, allowance) + 0.05


# ------------------------------------------------------------------------------------------ deviation helper

def test_piece_deviation_matches_closed_forms():
    # a straight Bézier 2 px above a straight polyline: deviation 2
    bez = np.array([[[0, 2], [1, 2], [2, 2], [3, 2]]], float)
    line = np.array([[0, 0], [1.5, 0], [3, 0]], float)
    assert piece_deviation(bez, line) == pytest.approx(2.0, abs=1e-9)
    # a quarter circle (Bézier approximation) against its own chord polyline: sagitta r (1 - cos(pi/8))
    k = 4 * (np.sqrt(2) - 1) / 3
    arc = np.array([[[10, 0], [10, 10 * k], [10 * k, 10], [0, 10]]], float)
    chord = np.array([[10, 0], [10 * np.cos(np.pi / 4), 10 * np.sin(np.pi / 4)], [0, 10]])
    assert piece_deviation(arc, chord) == pytest.approx(10 * (1 - np.cos(np.pi / 8)), abs=0.02)


# ------------------------------------------------------------------------------------------ bad input

@pytest.mark.parametrize("key, value", [("initial_density", -0.1), ("initial_density", float("nan")),
                                        ("corner_radius", -1.0), ("sample_spacing", 0.0), ("min_gap", 0)])
def test_lsq_options_are_validated(key, value):
    outline, corners, _ = shape("square")
    with pytest.raises(ValueError, match=key):
        fit_outline(outline, corners, **{key: value})


def test_curvature_seeded_knots_save_rounds_and_keep_the_guarantee():
    """Seeding the knots from the curvature (the default) starts a curved outline with knots where it bends,
    so it needs fewer insertion rounds than starting from four knots; both meet epsilon."""
    a = np.linspace(0, 2 * np.pi, 6000, endpoint=False)
    r = 90 * (1 + 0.18 * np.cos(3 * a + 0.4) + 0.1 * np.sin(5 * a))
    mask = raster(np.column_stack([120 + r * np.cos(a), 120 + r * np.sin(a)]), 240)
    outline, corners = trace_boundaries(mask)[0].outline, np.zeros(0, int)
    seeded = fit_outline(outline, corners, epsilon=0.8)
    plain = fit_outline(outline, corners, epsilon=0.8, initial_density=0.0)
    assert seeded.converged and plain.converged
    assert seeded.hausdorff <= 0.8 + 1e-9 and plain.hausdorff <= 0.8 + 1e-9
    first_seeded = sum(len(k) for k in seeded.snapshots[0].knot_indices)
    first_plain = sum(len(k) for k in plain.snapshots[0].knot_indices)
    assert first_seeded > first_plain
    assert seeded.iterations < plain.iterations


def test_bad_input_raises():
    outline, corners, _ = shape("square")
    with pytest.raises(ValueError, match="epsilon"):
        fit_outline(outline, corners, epsilon=0)
    with pytest.raises(ValueError, match="epsilon"):
        fit_outline(outline, corners, epsilon=-1.0)
    with pytest.raises(ValueError, match="epsilon"):
        fit_outline(outline, corners, epsilon=float("nan"))
    bad = outline.copy()
    bad[7, 1] = np.nan
    with pytest.raises(ValueError, match=r"points\[7, 1\]"):
        fit_outline(bad, corners)
    with pytest.raises(ValueError, match="at least 4"):
        fit_outline(outline[:3], [0])
    with pytest.raises(ValueError, match="shape"):
        fit_outline(outline[:, :1], corners)
    with pytest.raises(ValueError, match="coincide"):
        fit_outline(np.vstack([outline, outline[:1]]), corners)
    with pytest.raises(ValueError, match="tau"):
        fit_outline(outline, corners, method="positional", tau=60)
    with pytest.raises(ValueError, match="tau"):
        fit_outline(outline, corners, method="positional", tau=-1)
    with pytest.raises(ValueError, match="tau"):
        fit_outline(outline, corners, method="euclidean", tau=-0.5)
    with pytest.raises(ValueError, match="tau"):
        fit_outline(outline, corners, method="fuzzy", tau=3)
    with pytest.raises(ValueError, match="unknown method"):
        fit_outline(outline, corners, method="magic")
    with pytest.raises(ValueError, match="corner_indices"):
        fit_outline(outline, [0, len(outline)])
    with pytest.raises(TypeError, match="corner_indices"):
        fit_outline(outline, [0.5, 3.0])
    with pytest.raises(ValueError, match="closed"):
        fit_outline(outline, corners, closed=False)
    with pytest.raises(ValueError, match="max_iterations"):
        fit_outline(outline, corners, max_iterations=0)
    with pytest.raises(TypeError, match="unexpected option"):
        fit_outline(outline, corners, wobble=3)
    with pytest.raises(ValueError, match="thesis methods"):
        fit_outline(outline, corners, point_tension=1.0)
    with pytest.raises(ValueError, match="w > v"):
        fit_outline(outline, corners, method="fuzzy", fuzzy_weights=(0.2, 0.5))
    with pytest.raises(TypeError):
        fit_outline("not points", corners)


def test_engine_options_reach_the_thesis_interpolant():
    outline, corners, _ = shape("square")
    plain = fit_outline(outline, corners, method="fuzzy", seed=1, max_iterations=1, keep_snapshots=False)
    tense = fit_outline(outline, corners, method="fuzzy", seed=1, max_iterations=1, keep_snapshots=False,
                        point_tension=5.0)
    assert not np.allclose(plain.spline.bezier(), tense.spline.bezier()) or \
        [len(k) for k in plain.knot_indices] == [2] * len(corners)
    assert set(KNOT_METHODS) == {"lsq", "random", "euclidean", "positional", "random3", "equal3", "fuzzy"}


# ------------------------------------------------------------------------------------------ lsq internals

@settings(max_examples=30, deadline=None)
@given(st.integers(5, 60), st.integers(0, 4), st.integers(0, 10_000))
def test_windowed_distance_is_the_exact_distance_to_its_edges_and_an_upper_bound(count, window, seed):
    """Each value is the exact point-to-segment distance to the nearest edge of its window (brute force per
    edge) and never below the closest-point distance to the whole closed polyline."""
    from splinecraft.capture.fitting import geometry

    rng = np.random.default_rng(seed)
    line = np.cumsum(rng.normal(size=(count, 2)), axis=0)
    closed = np.vstack([line, line[:1]])
    points = rng.normal(size=(40, 2)) * 3 + line[rng.integers(0, count, 40)]
    centre = rng.integers(0, count, 40)
    got = geometry.windowed_distance(points, centre, None, None, geometry.edge_table(closed), window, count)

    def segment_distance(q, a, b):
        d = b - a
        t = 0.0 if not d.any() else float(np.clip((q - a) @ d / (d @ d), 0.0, 1.0))
        return float(np.hypot(*(q - a - t * d)))

    for j, q in enumerate(points):
        edges = [(centre[j] + k) % count for k in range(-window, window + 1)]
        assert got[j] == pytest.approx(min(segment_distance(q, closed[e], closed[e + 1]) for e in edges), abs=1e-9)
        everywhere = min(segment_distance(q, closed[e], closed[e + 1]) for e in range(count))
        assert got[j] >= everywhere - 1e-9


# ------------------------------------------------------------------------------------------ small outlines
# Contours of fewer than SMALL_OUTLINE points take the batched direct path of "lsq" (fit_small_outlines).

def _small_mask(name):
    masks = {
        "pixel": np.ones((1, 1), bool),
        "domino": np.ones((1, 2), bool),
        "diagonal3": np.eye(3, dtype=bool),
        "block2x2": np.ones((2, 2), bool),
        "tromino": np.array([[1, 0], [1, 1]], bool),
        "rect3x10": np.ones((3, 10), bool),
        "square10": np.ones((10, 10), bool),
        "plus": np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], bool),
    }
    return np.pad(masks[name], 3)


def _small_outline(name):
    (boundary,) = [b for b in trace_boundaries(_small_mask(name)) if not b.is_hole]
    return np.asarray(boundary.outline, float)


SMALL_NAMES = ["pixel", "domino", "diagonal3", "block2x2", "tromino", "rect3x10", "square10", "plus"]


def _pixel_corner_knots(name, outline, corners):
    """Per corner: the pixel corner beside it (docs/capture.md §12, "Small outlines": its knot point is that
    vertex), or NaN. Worked out from the mask here: a block of ink of any size has its four corners as pixel
    corners, and a corner index names one when its point is a crack midpoint half a pixel from
    one of them."""
    mask = _small_mask(name)
    rows, cols = np.nonzero(mask)
    top, left, bottom, right = rows.min(), cols.min(), rows.max() + 1, cols.max() + 1
    out = np.full((len(corners), 2), np.nan)
    if mask.sum() != (bottom - top) * (right - left):
        return out
    vertices = np.array([(left, top), (right, top), (right, bottom), (left, bottom)], float)
    for j, c in enumerate(corners):
        near = np.flatnonzero(np.isclose(np.hypot(*(vertices - outline[c]).T), 0.5))
        if near.size:
            out[j] = vertices[near[0]]
    return out


@pytest.mark.parametrize("name", SMALL_NAMES)
@pytest.mark.parametrize("epsilon", [0.3, 0.8])
@pytest.mark.parametrize("with_corners", [False, True])
def test_small_outlines_converge_within_epsilon_everywhere(name, epsilon, with_corners):
    """Tiny crack outlines (4-40 points) converge; the reported deviation is the real two-sided one
    (re-measured independently) and within epsilon everywhere: corners are interpolated, no allowance."""
    from splinecraft.capture.fitting import SMALL_OUTLINE

    outline = _small_outline(name)
    assert len(outline) < SMALL_OUTLINE
    corners = [0, len(outline) // 2] if with_corners else []
    result = fit_outline(outline, corners, epsilon=epsilon)
    small_path = bool(result.info.get("small_outline"))
    if not small_path:
        # the small path's own fit collapsed (two corners across a 1-px outline: both pieces on one chord), so
        # fit_outline took the regression spline (small.keeps_area); the guarantees below hold all the same
        from splinecraft.capture.fitting import fit_small_outlines
        from splinecraft.capture.fitting.small import keeps_area

        own = fit_small_outlines([outline], [corners], epsilon=epsilon)[0]
        assert with_corners and not keeps_area(outline, own.spline.bezier())
    assert result.method == "lsq"
    assert result.converged and result.info["reason"] is None
    vertices = _pixel_corner_knots(name, outline, corners)
    pixel = np.isfinite(vertices[:, 0])
    if not pixel.any():
        assert result.hausdorff <= epsilon
        measured = hausdorff(result.spline.bezier(), outline)
        assert measured <= epsilon + 0.01  # the report samples the curve every 0.25 px
        assert result.hausdorff >= measured - 0.01  # and is not an underestimate beyond the sampling
    else:
        # a corner beside a pixel corner has the vertex as its knot point (0.35 px outside the contour's chamfer,
        # 0.5 px from the contour points beside it): within epsilon + its allowance in its zone, within epsilon
        # of the contour farther than 1.5 px from those vertices
        tolerance_near = result.info["tolerance_near_corners"]
        assert result.hausdorff <= tolerance_near
        measured = hausdorff(result.spline.bezier(), outline)
        assert measured <= tolerance_near + 0.01
        assert result.hausdorff >= measured - 0.01
        curve = _dense_samples(result.spline.bezier())
        probes = np.vstack([outline, 0.5 * (outline + np.roll(outline, -1, axis=0))])
        away = [np.hypot(*(q[:, None, :] - vertices[pixel][None]).transpose(2, 0, 1)).min(axis=1) > 1.5
                for q in (curve, probes)]
        # (a block of 1-2 px has no point that far: there the vertices and the allowance are all)
        assert _dist_to_polyline(curve[away[0]], outline).max(initial=0.0) <= epsilon + 0.01
        assert _dist_to_polyline(probes[away[1]], curve).max(initial=0.0) <= epsilon + 0.01
    if with_corners and small_path:  # the pieces meet at the corner points
        np.testing.assert_array_equal(result.corners_used, corners)
        starts = [k[0] for k in result.knot_indices]
        assert sorted(starts) == corners
        expected = vertices[0] if pixel[0] else outline[corners[0]]
        np.testing.assert_allclose(result.spline.bezier()[0, 0], expected)


@pytest.mark.parametrize("name", SMALL_NAMES)
def test_small_outline_is_the_c2_interpolant_through_its_knot_points(name):
    """Independent reference: scipy's CubicSpline through the knot points at the reported knots (periodic
    without corners, natural ends per piece with corners) gives the same curve. The small path's own fit
    (``fit_outline`` takes the regression spline instead where it collapses: two corners across a 1-2 px block,
    whose pieces lie on one chord between two vertices)."""
    from scipy.interpolate import CubicSpline

    from splinecraft.capture.fitting import fit_small_outlines

    outline = _small_outline(name)
    for corners in ([], [0, len(outline) // 2]):
        result = fit_small_outlines([outline], [corners], epsilon=0.3)[0]
        bezier, knots = result.spline.bezier(), np.asarray(result.spline.knots)
        knot_points = outline[np.concatenate([k[:-1] for k in result.knot_indices])]
        if corners:  # the pieces start at the corners; a corner beside a pixel corner has the vertex as knot point
            vertices = _pixel_corner_knots(name, outline, corners)
            starts = np.cumsum([0] + [len(k) - 1 for k in result.knot_indices[:-1]])
            for start, knot_list in zip(starts, result.knot_indices):
                j = corners.index(int(knot_list[0]))
                if np.isfinite(vertices[j, 0]):
                    knot_points[start] = vertices[j]
        np.testing.assert_allclose(bezier[:, 0], knot_points)
        theta = np.array([0.2, 0.5, 0.9])
        ours = np.einsum("tj,mjd->mtd", np.stack([(1 - theta) ** 3, 3 * theta * (1 - theta) ** 2,
                                                  3 * theta**2 * (1 - theta), theta**3], axis=1), bezier)
        params = knots[:-1, None] + theta[None, :] * np.diff(knots)[:, None]
        if not corners:
            values = np.vstack([bezier[:, 0], bezier[:1, 0]])
            reference = CubicSpline(knots, values, bc_type="periodic")(params)
        else:
            reference = np.empty_like(ours)
            first = 0
            for knot_list in result.knot_indices:
                count = len(knot_list) - 1
                rows = slice(first, first + count)
                values = np.vstack([bezier[rows, 0], bezier[first + count - 1, 3]])
                reference[rows] = CubicSpline(knots[first:first + count + 1], values, bc_type="natural")(params[rows])
                first += count
        np.testing.assert_allclose(ours, reference, atol=1e-9)


def _random_blob_outlines(seed, size=7, density=0.45):
    rng = np.random.default_rng(seed)
    mask = np.pad(rng.random((size, size)) < density, 2)
    return [np.asarray(b.outline, float) for b in trace_boundaries(mask)]


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 100_000), st.sampled_from([0.3, 0.5, 0.8, 1.5]))
def test_small_outline_batch_equals_one_by_one_and_meets_epsilon(seed, epsilon):
    """Random specks and blobs (outer boundaries and holes): the batch gives exactly the fits of the single
    calls (outlines do not influence each other), every one converges within epsilon (re-measured)."""
    from splinecraft.capture.fitting import fit_small_outlines

    outlines = [o for o in _random_blob_outlines(seed) if len(o) < 64]
    if not outlines:
        return
    from splinecraft.capture.fitting.small import keeps_area

    batch = fit_small_outlines(outlines, epsilon=epsilon)
    for outline, fit in zip(outlines, batch):
        single = fit_outline(outline, [], epsilon=epsilon)
        assert fit.converged and fit.hausdorff <= epsilon
        assert hausdorff(fit.spline.bezier(), outline) <= epsilon + 0.01
        if not keeps_area(outline, fit.spline.bezier()):  # collapsed: fit_outline takes the regression spline
            assert not single.info.get("small_outline") and single.converged
            assert hausdorff(single.spline.bezier(), outline) <= epsilon + 0.01
            continue
        np.testing.assert_array_equal(fit.spline.bezier(), single.spline.bezier())
        assert fit.iterations == single.iterations and fit.hausdorff == single.hausdorff


def test_small_outline_snapshots_are_consistent():
    outline = _small_outline("square10")
    result = fit_outline(outline, [], epsilon=0.15)
    snaps = result.snapshots
    assert [s.iteration for s in snaps] == list(range(result.iterations + 1))
    phases = [s.phase for s in snaps]
    assert phases[0] == "initial" and "insert" in phases and "remove" in phases
    assert phases == sorted(phases, key=["initial", "insert", "remove"].index)  # insertion, then removal
    for before, after in zip(snaps, snaps[1:]):
        old, new = set(np.concatenate(before.knot_indices)), set(np.concatenate(after.knot_indices))
        if after.phase == "insert":  # every new knot is a candidate
            assert new > old and {c["index"] for c in after.candidates} == new - old
        else:  # removal: the accepted candidates are the knots that went away
            assert new <= old and {c["index"] for c in after.candidates if c["accepted"]} == old - new
            assert after.finished.all()
    np.testing.assert_array_equal(snaps[-1].bezier, result.spline.bezier())
    assert snaps[-1].hausdorff == result.hausdorff and snaps[-1].finished.all()
    assert not snaps[0].finished.all()
    np.testing.assert_array_equal(snaps[-1].spline().bezier(), result.spline.bezier())
    lean = fit_outline(outline, [], epsilon=0.15, keep_snapshots=False)
    assert lean.snapshots == []
    np.testing.assert_array_equal(lean.spline.bezier(), result.spline.bezier())


def test_small_outline_reports_why_it_did_not_converge():
    pixel = _small_outline("pixel")  # its 4 points are all knots from the start
    stuck = fit_outline(pixel, [], epsilon=0.01)
    assert not stuck.converged and "every contour point" in stuck.info["reason"]
    capped = fit_outline(_small_outline("square10"), [], epsilon=0.05, max_iterations=1)
    assert not capped.converged and capped.iterations == 1 and "max_iterations" in capped.info["reason"]


def test_small_outline_threshold_and_validation():
    outline = _small_outline("square10")
    full = fit_outline(outline, [], small_outline=0)
    assert "small_outline" not in full.info  # the full lsq machinery
    assert fit_outline(outline, [], small_outline=len(outline) + 1).info["small_outline"]
    assert "small_outline" not in fit_outline(outline, [], small_outline=len(outline)).info
    assert "small_outline" not in fit_outline(outline, [], method="random").info  # thesis methods unchanged
    for bad, error in ((-1, ValueError), (True, TypeError), (2.5, TypeError)):
        with pytest.raises(error, match="small_outline"):
            fit_outline(outline, [], small_outline=bad)
    from splinecraft.capture.fitting import fit_small_outlines

    with pytest.raises(ValueError, match="at least 4 points"):
        fit_small_outlines([outline, outline[:3]])
    with pytest.raises(ValueError, match="coincide"):
        fit_small_outlines([np.vstack([outline[:1], outline])])
    with pytest.raises(ValueError, match="corner_lists"):
        fit_small_outlines([outline], [[0], [1]])
    with pytest.raises(ValueError, match="outside"):
        fit_small_outlines([outline], [[len(outline)]])
    assert fit_small_outlines([]) == []


@pytest.mark.parametrize("epsilon", [0.5, 0.8])
def test_small_outline_knot_removal_never_leaves_a_fit_outside_epsilon(epsilon):
    """Thousands of speck outlines of a noise image: after the knot-removal rounds every fit is still within
    epsilon (a removal changes the whole C² curve of its piece, so intervals without a removed knot must be
    checked too)."""
    from splinecraft.capture.fitting import fit_small_outlines

    mask = np.random.default_rng(0).random((200, 200)) < 0.3
    outlines = [np.asarray(b.outline, float) for b in trace_boundaries(mask) if len(b.outline) < 64]
    fits = fit_small_outlines(outlines, epsilon=epsilon, keep_snapshots=False)
    assert len(fits) > 2000
    assert all(fit.converged and fit.hausdorff <= epsilon for fit in fits)
    assert any(len(fit.snapshots) == 0 and fit.iterations > 0 for fit in fits)


def test_lsq_falls_back_to_the_interpolant_path_when_its_pieces_are_too_short():
    """On a speckle outline with a corner every few steps the regression spline cannot place knots min_gap
    steps apart and stops above epsilon; the default then refits the outline through its contour points
    (the small-outline path), which reaches epsilon, and records the first attempt."""
    from splinecraft.capture.corners import corners as detect_corners

    mask = np.random.default_rng(0).random((60, 60)) < 0.3
    stuck = 0
    for boundary in trace_boundaries(mask):
        outline = boundary.outline
        if len(outline) < 64:
            continue
        corners = detect_corners(outline, method="tangent-jump")
        plain = fit_outline(outline, corners, fallback=False)
        result = fit_outline(outline, corners)
        if plain.converged:
            assert "fallback_from" not in result.info and result.hausdorff == plain.hausdorff
            continue
        stuck += 1
        assert result.converged and result.hausdorff <= result.epsilon + 1e-9
        assert result.info["fallback_from"]["hausdorff"] == pytest.approx(plain.hausdorff)
        assert result.snapshots[-1].knot_indices is not None
        np.testing.assert_array_equal(result.snapshots[-1].bezier, result.spline.bezier())
    assert stuck >= 1


def test_large_speckle_outline_converges_through_the_fallback():
    """A 1000+ point outline of a half-inked noise bitmap (hundreds of corners) stalls the regression spline;
    the fallback covers outlines of any size whose pieces are short, and the trace converges within
    epsilon (+ 0.5 px at the lsq outlines' corner tips)."""
    from splinecraft.capture.trace import trace

    # (seed 1: the 2672-point outline of seed 0 no longer stalls since stuck intervals get their arc-length
    # parameters back, docs/capture.md §12, "The lsq method"; the lsq fit converges there with 353 segments)
    mask = np.random.default_rng(1).random((70, 70)) < 0.5
    # no time budget: this is about the fallback converging, and under a loaded machine the default 5 s budget
    # can end the fit first (the budget has its own tests in test_trace_budget.py)
    result = trace(mask, epsilon=0.8, keep_snapshots=False, noise_factor=0, time_budget=None)
    assert result.stats["converged"] and result.stats["hausdorff"] <= 0.8 + 0.5 + 1e-9
    rescued = [k for k, fit in enumerate(result.fits) if "fallback_from" in fit.info]
    assert any(len(result.points[k]) > 512 for k in rescued)
    for k in rescued:
        assert result.fits[k].hausdorff <= 0.8 + 1e-9 < result.fits[k].info["fallback_from"]["hausdorff"]


def test_a_stuck_small_outline_is_fitted_by_the_regression_spline():
    # a 32-point blob (a blurred-noise component) whose corner at (33, 19.5) the interpolant through every contour
    # point overshoots by 0.38 px with its natural end: at epsilon 0.3 the small-outline path is stuck there (one
    # contour step, no knot fits); the regression spline's corner zone converges within its tolerance
    points = np.array([[29.5, 19.0], [30.5, 19.0], [31.5, 19.0], [32.5, 19.0], [33.0, 19.5], [33.0, 20.5],
                       [33.0, 21.5], [32.5, 22.0], [32.0, 22.5], [32.0, 23.5], [31.5, 24.0], [31.0, 24.5],
                       [31.0, 25.5], [30.5, 26.0], [29.5, 26.0], [28.5, 26.0], [27.5, 26.0], [26.5, 26.0],
                       [25.5, 26.0], [25.0, 25.5], [24.5, 25.0], [24.0, 24.5], [24.0, 23.5], [24.0, 22.5],
                       [24.0, 21.5], [24.5, 21.0], [25.0, 20.5], [25.5, 20.0], [26.5, 20.0], [27.5, 20.0],
                       [28.5, 20.0], [29.0, 19.5]])
    corners = [4, 20, 24]
    stuck = fit_outline(points, corners, epsilon=0.3, fallback=False)
    assert stuck.info["small_outline"] and stuck.info["stuck"] and not stuck.converged
    assert "no knot can be inserted" in stuck.info["reason"]
    fitted = fit_outline(points, corners, epsilon=0.3)
    assert fitted.converged and fitted.info["fallback_from"]["method"] == "small-outline"
    assert fitted.info["fallback_from"]["hausdorff"] == stuck.hausdorff
    assert fitted.hausdorff <= fitted.info["tolerance_near_corners"] + 1e-9


@pytest.mark.parametrize("corner", [30, 102, 159])
def test_one_corner_anywhere_starts_and_ends_every_knot_list(corner):
    """With one corner the loop is split at the half-way point and reported as one piece from the corner round to
    it: the knot lists start and end there wherever it lies (a corner past the half-way point gave lists that
    started at the half-way point), and the fuzzy method keeps its weights in info."""
    angle = np.linspace(0, 2 * np.pi, 160, endpoint=False)
    points = np.column_stack([40 * np.cos(angle), 40 * np.sin(angle)])
    fit = fit_outline(points, [corner], method="fuzzy", epsilon=0.3, seed=0)
    assert fit.pieces == [(corner, corner)]
    for knots in [fit.knot_indices[0]] + [s.knot_indices[0] for s in fit.snapshots]:
        assert knots[0] == knots[-1] == corner
    np.testing.assert_allclose(fit.spline.bezier()[0, 0], points[corner], atol=1e-9)
    assert fit.info["fuzzy_weights"] == [0.7, 0.3]


def test_small_outline_is_refused_for_the_thesis_methods():
    points = np.column_stack([np.cos(np.linspace(0, 6.2, 40)), np.sin(np.linspace(0, 6.2, 40))]) * 20
    with pytest.raises(ValueError, match="small_outline is used by the method 'lsq' only"):
        fit_outline(points, [], method="random", small_outline=10)
    from splinecraft.capture.trace import trace

    with pytest.raises(ValueError, match=r"fit_params\['small_outline'\] is used by the method 'lsq' only"):
        trace(np.pad(np.ones((20, 20), bool), 5), method="random", fit_params={"small_outline": 10})
    assert fit_outline(points, [], small_outline=10).converged is not None  # lsq takes it
