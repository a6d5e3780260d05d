"""Segment merging after the ``"lsq"`` fit (option ``merge_tolerance``; docs/capture.md §12, "Merged
segments"): blobs, discs, ellipses and polygons rendered here, fitted with and without merging, and checked
against their pixels (independent symmetric deviation of test_fitting), against each other (merging never adds
segments, corners stay) and at the joins (G1: one tangent direction on both sides).
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.fitting import fit_outline
from test_fitting import hausdorff as deviation, polygon_shape
from test_fitting_size import render_blob

MERGE = 0.5


def render_ellipse(a, b, angle=0.0, offset=(0.37, 0.21)):
    """Crack outline and dense exact outline of an ellipse of semi-axes ``a``, ``b`` turned by ``angle``: a pixel
    is ink when its centre lies inside (exact test)."""
    size = int(np.ceil(2 * max(a, b))) + 8
    centre = np.array([size / 2 + offset[0], size / 2 + offset[1]])
    yy, xx = np.mgrid[0:size, 0:size]
    dx, dy = xx + 0.5 - centre[0], yy + 0.5 - centre[1]
    c, s = np.cos(angle), np.sin(angle)
    mask = ((c * dx + s * dy) / a) ** 2 + ((-s * dx + c * dy) / b) ** 2 < 1.0
    t = np.linspace(0, 2 * np.pi, int(40 * max(a, b)), endpoint=False)
    x, y = a * np.cos(t), b * np.sin(t)
    dense = centre + np.column_stack([c * x - s * y, s * x + c * y])
    return trace_boundaries(mask)[0].outline, dense


def joins_inside_pieces(fit):
    """Indices ``i`` of the segments whose end joins the next segment inside a piece (not at a corner)."""
    corners = set(int(c) for c in np.concatenate([k[[0, -1]] for k in fit.knot_indices]))
    ends = np.concatenate([k[1:] for k in fit.knot_indices])
    return np.flatnonzero([int(e) not in corners for e in ends])


def assert_g1(fit):
    """At every join inside a piece the two segments share the point and the tangent direction."""
    bez = fit.spline.bezier()
    scale = np.abs(bez).max()
    inner = joins_inside_pieces(fit)
    nxt = (inner + 1) % bez.shape[0]
    np.testing.assert_allclose(bez[inner, 3], bez[nxt, 0], atol=1e-9 * scale)
    out = bez[inner, 3] - bez[inner, 2]
    into = bez[nxt, 1] - bez[nxt, 0]
    cross = out[:, 0] * into[:, 1] - out[:, 1] * into[:, 0]
    norms = np.hypot(*out.T) * np.hypot(*into.T)
    assert (np.abs(cross) <= 1e-7 * norms).all()
    assert ((out * into).sum(1) > 0).all()


harmonic = st.tuples(st.floats(-0.12, 0.12), st.floats(0.0, 2 * np.pi))


@settings(max_examples=8, deadline=None)
@given(st.lists(harmonic, min_size=1, max_size=3), st.floats(24.0, 40.0), st.sampled_from([1, 2, 4]))
def test_merged_blobs_stay_within_epsilon_with_no_more_segments(harmonics, radius, scale):
    """Merging keeps the guarantee (docs/capture.md §12: within epsilon of the pixels, measured here
    independently), only removes joins of the fit it starts from, and leaves G1 joins."""
    outline, _ = render_blob(radius * scale, harmonics)
    plain = fit_outline(outline, np.zeros(0, int), epsilon=0.8, merge_tolerance=0.0, keep_snapshots=False)
    fit = fit_outline(outline, np.zeros(0, int), epsilon=0.8, merge_tolerance=MERGE, keep_snapshots=False)
    assert plain.converged and fit.converged
    assert deviation(fit.spline.bezier(), outline) <= 0.8 + 0.05
    assert fit.spline.bezier().shape[0] <= plain.spline.bezier().shape[0]
    assert sum(len(k) - 1 for k in fit.knot_indices) == fit.spline.bezier().shape[0]
    assert_g1(fit)


@settings(max_examples=10, deadline=None)
@given(st.integers(3, 7), st.floats(0.0, 1.0), st.integers(0, 10_000), st.sampled_from([1, 3]))
def test_merged_polygons_keep_the_guarantee_and_their_corners(count, rotation, seed, scale):
    """Polygons (corners extrapolated or not): the merged fit keeps its corners and pieces, stays within the
    tolerance near corners (docs/capture.md §12, "Guarantee") and has no more segments per piece."""
    rng = np.random.default_rng(seed)
    angles = rotation + 2 * np.pi * (np.arange(count) + rng.uniform(-0.2, 0.2, count)) / count
    radius = rng.uniform(10, 20) * scale
    size = int(2 * radius + 16)
    vertices = np.column_stack([size / 2 + radius * np.cos(angles), size / 2 + radius * np.sin(angles)])
    outline, corners, _ = polygon_shape(vertices, size)
    plain = fit_outline(outline, corners, merge_tolerance=0.0, keep_snapshots=False)
    fit = fit_outline(outline, corners, merge_tolerance=MERGE, keep_snapshots=False)
    assert fit.converged
    np.testing.assert_array_equal(fit.corners_used, plain.corners_used)
    assert fit.pieces == plain.pieces
    for merged, kept in zip(fit.knot_indices, plain.knot_indices):
        assert len(merged) <= len(kept) and merged[0] == kept[0] and merged[-1] == kept[-1]
    bound = fit.info["tolerance_near_corners"]
    assert deviation(fit.spline.bezier(), outline) <= bound + 0.05
    assert_g1(fit)


@pytest.mark.parametrize("radius", [40.0, 160.0])
@pytest.mark.parametrize("offset", [(0.37, 0.21), (0.05, 0.5)])
def test_a_disc_merges_to_four_segments(radius, offset):
    """Four cubics with G1 joins (the quarter-circle Bézier) are within 2.7e-4 r of a circle of radius r:
    0.04 px at r = 160, so where the C2 fit needs more than four segments the merged fit of a disc has four,
    a font's count, and stays within about a pixel of the true circle."""
    outline, dense = render_blob(radius, [], offset=offset)
    plain = fit_outline(outline, np.zeros(0, int), merge_tolerance=0.0, keep_snapshots=False)
    fit = fit_outline(outline, np.zeros(0, int), merge_tolerance=MERGE, keep_snapshots=False)
    assert fit.converged
    assert fit.spline.bezier().shape[0] <= 4
    assert deviation(fit.spline.bezier(), outline) <= 0.8 + 0.05
    assert deviation(fit.spline.bezier(), dense) <= 1.0


@pytest.mark.parametrize("angle", [0.0, 0.3])
def test_an_ellipse_merges_to_four_segments(angle):
    """A quarter ellipse is the affine image of a quarter circle, so four G1 cubics joined at the ends of the
    axes are within 2.7e-4 a of an ellipse of semi-major axis a (0.07 px at a = 240); turned, the arcs between
    its points of horizontal and vertical tangent are affine images of circular arcs of about a quarter turn,
    as close. Merging may cut the fitted segments at those points (a font's nodes), so the merged fit of a
    480 x 280 px ellipse has four segments, upright or turned."""
    outline, dense = render_ellipse(240.0, 140.0, angle)
    fit = fit_outline(outline, np.zeros(0, int), merge_tolerance=MERGE, keep_snapshots=False)
    assert fit.converged
    assert fit.spline.bezier().shape[0] <= 4
    assert deviation(fit.spline.bezier(), outline) <= 0.8 + 0.05
    assert deviation(fit.spline.bezier(), dense) <= 1.0
    assert_g1(fit)


def test_merging_is_on_by_default_and_checked():
    """``merge_tolerance=0.5`` px is the default (docs/capture.md §12, "Merged segments"); ``merge_tolerance=0``
    is the C2 fit as it was, which has no fewer segments and whose last snapshot is its own; a negative
    tolerance is refused."""
    outline, _ = render_blob(120.0, [(0.08, 0.4)])
    default = fit_outline(outline, np.zeros(0, int))
    merged = fit_outline(outline, np.zeros(0, int), merge_tolerance=0.5)
    off = fit_outline(outline, np.zeros(0, int), merge_tolerance=0.0)
    np.testing.assert_array_equal(default.spline.bezier(), merged.spline.bezier())
    assert default.spline.bezier().shape[0] < off.spline.bezier().shape[0]
    np.testing.assert_allclose(off.snapshots[-1].bezier, off.spline.bezier(), rtol=0,
                               atol=1e-9 * np.abs(off.spline.bezier()).max())
    assert len(default.snapshots) == len(off.snapshots) + 1
    for a, b in zip(default.snapshots, off.snapshots):  # the knot-insertion history is the unmerged fit's
        np.testing.assert_array_equal(a.bezier, b.bezier)
    with pytest.raises(ValueError, match="merge_tolerance"):
        fit_outline(outline, np.zeros(0, int), merge_tolerance=-1.0)


def test_merge_snapshot_records_the_joins_removed():
    """The merge is the last snapshot, of phase "remove", and its removed joins are the knots that went."""
    outline, _ = render_blob(120.0, [(0.08, 0.4)])
    plain = fit_outline(outline, np.zeros(0, int), merge_tolerance=0.0)
    fit = fit_outline(outline, np.zeros(0, int), merge_tolerance=MERGE)
    gone = set(plain.knot_indices[0].tolist()) - set(fit.knot_indices[0].tolist())
    assert gone
    last = fit.snapshots[-1]
    assert last.phase == "remove"
    np.testing.assert_allclose(last.bezier, fit.spline.bezier(), rtol=0, atol=1e-9 * np.abs(last.bezier).max())
    assert {c["index"] for c in last.candidates if c["action"] == "remove"} == gone


def _compare_merges(monkeypatch, outline, corners):
    """Fit ``outline`` with merging; at each merge, steps 1 to 4 of ``merge.merge_segments`` against their numpy
    formulation as it was (:mod:`merge_reference`), bit for bit: the pieces, the joins' directions, every
    candidate, and the dynamic programme's choice with every candidate allowed and with random ones left out.
    Returns how many merges were compared."""
    import merge_reference as reference
    from splinecraft.capture.fitting import _merge_kernels, lsq, merge

    compared = [0]
    rng = np.random.default_rng(7)

    def comparing(model, dev, tolerance):
        if dev["bezier"].shape[0] >= 2:
            (bez, starts, ends, origin), expected = reference.merge_steps(model, dev, tolerance)
            prepared, cand = merge.candidate_runs(model, dev, tolerance)
            for got, want in ((prepared["bez"], bez), (prepared["starts"], starts), (prepared["ends"], ends),
                              (prepared["origin"], origin), (cand["direction"], expected["direction"])):
                np.testing.assert_array_equal(got, want)
            for key in ("first", "length", "s0", "s1", "spread", "cubic", "refit", "t_count", "t_start", "t"):
                np.testing.assert_array_equal(cand[key], expected[key], err_msg=key)
            k, periodic = bez.shape[0], model.contour.corner_count == 0
            for attempt in range(4):
                allowed = np.ones(cand["first"].shape[0], bool)
                if attempt:
                    allowed &= rng.random(allowed.shape[0]) < 0.7
                    allowed[~cand["refit"]] = True
                np.testing.assert_array_equal(_merge_kernels.choose(k, cand, allowed, periodic),
                                              reference.choose_runs(k, expected, allowed, periodic))
            compared[0] += 1
        return merge_segments(model, dev, tolerance)

    merge_segments = lsq.merge_segments
    monkeypatch.setattr(lsq, "merge_segments", comparing)
    fit_outline(outline, corners, merge_tolerance=MERGE, keep_snapshots=False)
    monkeypatch.undo()
    return compared[0]


def test_merge_passes_are_the_numpy_formulation_bit_for_bit(monkeypatch):
    """The compiled passes of the merge (``_merge_kernels.prepare``, ``candidates``, ``choose``: the pieces cut at
    extrema, the joins' parabolas, the candidate runs grown one length at a time, the dynamic programme) give
    bit for bit what the numpy formulation they replaced gave (:mod:`merge_reference`: the candidates fitted
    four lengths a pass and the growth rule applied afterwards), on blobs, ellipses and polygons."""
    compared = 0
    for seed in range(3):
        rng = np.random.default_rng(seed)
        outline, _ = render_blob(rng.uniform(60, 90), [(rng.uniform(-0.12, 0.12), rng.uniform(0, 2 * np.pi))
                                                      for _ in range(3)])
        count = 5
        angles = 2 * np.pi * (np.arange(count) + rng.uniform(-0.2, 0.2, count)) / count
        vertices = np.column_stack([60 + 50 * np.cos(angles), 60 + 50 * np.sin(angles)])
        polygon, corners, _ = polygon_shape(vertices, 120)
        ellipse, _ = render_ellipse(rng.uniform(60, 120), rng.uniform(30, 60), rng.uniform(0, np.pi))
        for points, at in ((outline, np.zeros(0, int)), (polygon, corners), (ellipse, np.zeros(0, int))):
            compared += _compare_merges(monkeypatch, points, at)
    assert compared >= 9


def test_merge_candidates_parameters_need_no_first_guess(monkeypatch):
    """``_merge_kernels.candidates`` allocates room for the qualifying runs' parameters from a guess and runs once
    more where they need more: with no room at first the merged fits are those of the default."""
    from splinecraft.capture.fitting import _merge_kernels

    outline, _ = render_blob(120.0, [(0.08, 0.4)])
    default = fit_outline(outline, np.zeros(0, int), merge_tolerance=MERGE, keep_snapshots=False)
    monkeypatch.setattr(_merge_kernels, "T_ROOM", 0)
    monkeypatch.setattr(_merge_kernels, "T_ROOM_EXTRA", 1)
    again = fit_outline(outline, np.zeros(0, int), merge_tolerance=MERGE, keep_snapshots=False)
    np.testing.assert_array_equal(again.spline.bezier(), default.spline.bezier())


_coordinate = st.one_of(st.integers(-4, 4).map(float), st.floats(-50, 50, allow_nan=False, allow_infinity=False))


@settings(max_examples=300, deadline=None)
@given(st.lists(st.lists(st.tuples(_coordinate, _coordinate), min_size=4, max_size=4), min_size=1, max_size=6),
       st.floats(0.01, 40.0), st.sampled_from([0.0, 2.0, 0.5]))
def test_prepare_cuts_pieces_as_numpy_did(controls, length, min_gap):
    """``_merge_kernels.prepare``'s pieces (cut where the tangent is horizontal or vertical, at least ``min_gap``
    from either end, cuts closer than that one), their parameter intervals, origins, end tangents and summed
    turns are bit for bit those of the numpy formulation (:mod:`merge_reference`), on random cubics and on
    degenerate ones (control points on a small grid: straight, coincident, symmetric)."""
    import merge_reference as reference
    from splinecraft.capture.fitting import _merge_kernels

    fit_bez = np.array(controls, dtype=float)
    k0 = fit_bez.shape[0]
    starts = np.arange(k0) * length
    ends = starts + length
    points = fit_bez[:, 0].copy()
    u = starts.copy()
    prepared = _merge_kernels.prepare(fit_bez, starts, ends, min_gap, np.array([0.0, k0 * length]), 1, True, points,
                                      u, k0 * length, 0.5)
    bez, p_starts, p_ends, origin = reference.split_at_extrema(fit_bez, starts, ends, min_gap)
    head, tail = reference._tangents(bez)
    turn = np.concatenate([[0.0], np.cumsum(reference._turns(bez))])
    for got, want in ((prepared["bez"], bez), (prepared["starts"], p_starts), (prepared["ends"], p_ends),
                      (prepared["origin"], origin), (prepared["head"], head), (prepared["tail"], tail),
                      (prepared["turn"], turn)):
        np.testing.assert_array_equal(got, want)


@settings(max_examples=300, deadline=None)
@given(st.integers(1, 9), st.integers(0, 2**32 - 1), st.booleans())
def test_choose_is_the_dynamic_programme_as_it_was(k, seed, periodic):
    """``_merge_kernels.choose`` against the Python dynamic programme it replaced (:mod:`merge_reference`): the
    same runs, on random candidate sets (the segments as they were always among them, costs with many ties, some
    candidates not allowed)."""
    import merge_reference as reference
    from splinecraft.capture.fitting import _merge_kernels

    rng = np.random.default_rng(seed)
    extra = int(rng.integers(0, 4 * k + 1))
    first = np.concatenate([np.arange(k), rng.integers(0, k, extra)]).astype(np.int64)
    length = np.concatenate([np.ones(k, np.int64), [rng.integers(1, k - f + 1) for f in first[k:]]]).astype(np.int64)
    s0 = np.concatenate([np.zeros(k, np.int64), rng.integers(0, 2, extra)]).astype(np.int64)
    s1 = np.concatenate([np.zeros(k, np.int64), rng.integers(0, 2, extra)]).astype(np.int64)
    spread = np.concatenate([np.zeros(k), rng.choice([0.0, 0.5, 1.0, 0.1 + 0.2, 0.3], extra)])
    count = k + extra
    cand_i, cand_f = np.zeros((7, count + 3), np.int64), np.zeros((count + 3, 9))
    cand_i[0, :count], cand_i[1, :count], cand_i[2, :count], cand_i[3, :count] = first, length, s0, s1
    cand_f[:count, 0] = spread
    allowed = rng.random(count) < 0.8
    allowed[:k] = True
    cand = {"first": first, "length": length, "s0": s0, "s1": s1, "spread": spread, "cand_i": cand_i,
            "cand_f": cand_f}
    np.testing.assert_array_equal(_merge_kernels.choose(k, cand, allowed, periodic),
                                  reference.choose_runs(k, cand, allowed, periodic))


def _run_distances(fit, lo, count, points):
    """Per run of a ``merge_reference.kernel_fit_runs`` result: its points' distances from its cubic at the parameters the
    kernel gave them, each computed (``numpy.hypot``; beyond an end, to the tangent line there), and the rounded
    square roots of their squared distances."""
    cubic, _, offsets, t = fit[:4]
    distances, roots = [], []
    for run in range(cubic.shape[0]):
        c, at = cubic[run], t[offsets[run]: offsets[run] + count[run]]
        s = 1.0 - at
        weights = [s * s * s, 3.0 * s * s * at, 3.0 * s * at * at, at * at * at]
        curve = [weights[0] * c[0, d] + weights[1] * c[1, d] + weights[2] * c[2, d] + weights[3] * c[3, d]
                 for d in range(2)]
        covered = points[lo[run]: lo[run] + count[run]]
        gx, gy = curve[0] - covered[:, 0], curve[1] - covered[:, 1]
        dist = np.hypot(gx, gy)
        for beyond, (a, b) in ((at <= 0.0, (0, 1)), (at >= 1.0, (2, 3))):
            dx, dy = c[b] - c[a]
            if np.hypot(dx, dy) > 0:
                dist[beyond] = np.abs(gx[beyond] * dy - gy[beyond] * dx) / np.hypot(dx, dy)
        distances.append(dist)
        roots.append(np.sqrt(gx * gx + gy * gy))
    return distances, roots


@settings(max_examples=150, deadline=None)
@given(st.integers(1, 6), st.integers(0, 2**32 - 1), st.sampled_from(["random", "tied", "roots"]))
def test_merge_kernel_largest_excess_is_that_of_every_distance(runs, seed, tolerances):
    """The merge kernel measures a point's distance (``numpy.hypot``) only where its squared distance may raise
    the run's largest excess so far (``_merge_kernels.SURE``): the largest excess is bit for bit that of every
    distance, on random runs of noisy arcs, with random tolerances, with tolerances that put every point's excess
    of a run within a few ulps of one value, and with tolerances that do so for the rounded square roots of the
    squared distances (the borderline of the rule)."""
    from merge_reference import kernel_fit_runs

    rng = np.random.default_rng(seed)
    pieces, counts, params = [], [], []
    p0, p3, d0, d1 = (np.empty((runs, 2)) for _ in range(4))
    for run in range(runs):
        count = int(rng.integers(0, 120))
        control = rng.uniform(-40, 40, (4, 2))
        at = np.sort(rng.uniform(0, 1, count))[:, None]
        arc = (1 - at) ** 3 * control[0] + 3 * (1 - at) ** 2 * at * control[1] + 3 * (1 - at) * at**2 * control[2] \
            + at**3 * control[3]
        pieces.append(arc + rng.normal(0, rng.uniform(0, 1.0), arc.shape))
        counts.append(count)
        params.append(run + at[:, 0])
        p0[run], p3[run] = control[0], control[3]
        for direction, vector in ((d0, control[1] - control[0]), (d1, control[3] - control[2])):
            vector = vector + rng.normal(0, 3.0, 2)
            direction[run] = vector / max(np.hypot(*vector), 1e-9)
    points, u = np.concatenate(pieces), np.concatenate(params)
    count = np.array(counts)
    lo = np.cumsum(count) - count
    fitted = points + rng.normal(0, 0.3, points.shape)
    tol = rng.uniform(0.2, 1.5, points.shape[0])

    def fit(tol):
        return kernel_fit_runs(p0, p3, d0, d1, lo, count, points, u, np.arange(runs, dtype=float), np.ones(runs),
                               tol, fitted, 4, 32)

    if tolerances != "random":  # the fit does not depend on tol: the same parameters, excesses near one value
        distances, roots = _run_distances(fit(tol), lo, count, points)
        for run in range(runs):
            near = distances[run] if tolerances == "tied" else roots[run]
            wobble = rng.integers(-3, 4, count[run]) * np.spacing(np.maximum(near, 1e-300))
            tol[lo[run]: lo[run] + count[run]] = near + rng.uniform(-0.3, 0.3) + wobble
    result = fit(tol)
    distances, _ = _run_distances(result, lo, count, points)
    expected = [(dist - tol[lo[run]: lo[run] + count[run]]).max() if count[run] else -np.inf
                for run, dist in enumerate(distances)]
    np.testing.assert_array_equal(result[4], expected)



def test_a_fit_with_one_segment_per_piece_has_nothing_to_merge(monkeypatch):
    """``merge_segments`` returns at once where the fit has one segment per piece between corners (a run stays
    within its piece): on random polygons the candidate runs and the dynamic programme, run anyway, choose no
    fewer segments there."""
    from splinecraft.capture.fitting import _merge_kernels, lsq, merge

    checked = [0]

    def checking(model, dev, tolerance):
        result = merge_segments(model, dev, tolerance)
        pieces = model.contour.corner_count
        if pieces and dev["bezier"].shape[0] == pieces:
            assert result[0] is dev and not len(result[1])
            prepared, cand = merge.candidate_runs(model, dev, tolerance)
            chosen = _merge_kernels.choose(prepared["k"], cand, np.ones(cand["first"].shape[0], bool), False)
            assert chosen.shape[0] >= pieces
            checked[0] += 1
        return result

    merge_segments = lsq.merge_segments
    monkeypatch.setattr(lsq, "merge_segments", checking)
    rng = np.random.default_rng(11)
    for count in (3, 4, 5, 6, 7) * 4:
        angles = rng.uniform(0, 1) + 2 * np.pi * (np.arange(count) + rng.uniform(-0.2, 0.2, count)) / count
        radius = rng.uniform(10, 30)
        size = int(2 * radius + 16)
        vertices = np.column_stack([size / 2 + radius * np.cos(angles), size / 2 + radius * np.sin(angles)])
        outline, corners, _ = polygon_shape(vertices, size)
        fit_outline(outline, corners, merge_tolerance=MERGE, keep_snapshots=False)
    assert checked[0] >= 5
