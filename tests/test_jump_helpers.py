"""tangent-jump's helpers (capture/corners/_jump.py and _jump_kernels.py, docs/capture.md §11) pinned to the
formulations they replaced (kept here as the reference): steps 4-5 with the flanks' median only where a peak can be
(the compiled ``_peaks``); on symmetric outlines the eight frame maps compared point by point (the compiled
``_congruent``), the corners of the union (``_symmetric_union``) whose chord to the next one already exceeds the
reach passed over without summing their arc, and the points' keys compared up to their first difference (the
compiled ``_key_sign``). The same answers, not just close ones."""
from __future__ import annotations

import importlib

import numba
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import splinecraft.capture.corners  # noqa: F401  (the package first: its modules import each other)
from splinecraft.capture.corners._common import _circular_max_filter
from test_jump_steps import ref_canonical_starts, ref_later as _later, ref_plateau_starts as _plateau_starts  # one copy

jump = importlib.import_module("splinecraft.capture.corners._jump")
_jump_kernels = importlib.import_module("splinecraft.capture.corners._jump_kernels")
_FRAME_MAPS = [(swap, sx, sy) for swap in (False, True) for sx in (1.0, -1.0) for sy in (1.0, -1.0)]


def reference_congruent(a, b):
    return any(np.array_equal((a[:, ::-1] if swap else a) * (sx, sy), b) for swap, sx, sy in _FRAME_MAPS)


def reference_symmetric_union(P, runs, key, reach=3.0):
    """The loop before session 28, pair by pair: every corner of the union with each one after it while the arc
    between them (the sum of the outline's edges) stays within ``reach``; of two that no run has both, the one
    whose whole key is smaller is dropped."""
    segment = np.hypot(*np.diff(np.vstack([P, P[:1]]), axis=0).T)

    def arc(i, j):
        return np.sum(segment[i:j] if j > i else np.concatenate([segment[i:], segment[:j]]))
    union = np.unique(np.concatenate(runs)).tolist()
    found = [set(run.tolist()) for run in runs]
    dropped = set()
    for a, first in enumerate(union):
        step = 1
        while step < len(union) and arc(first, union[(a + step) % len(union)]) <= reach:
            b = (a + step) % len(union)
            if not any(first in corners and union[b] in corners for corners in found):
                ka, kb = key(first), key(union[b])
                if not np.array_equal(ka, kb):
                    dropped.add(a if _later(ka, kb) else b)
            step += 1
    return np.array([index for k, index in enumerate(union) if k not in dropped], dtype=np.int64)


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 40), mapped=st.integers(-1, 7), flip=st.booleans())
def test_congruent_is_the_eight_maps_compared_one_by_one(seed, n, mapped, flip):
    rng = np.random.default_rng(seed)
    a = rng.integers(-3, 4, (n, 2)).astype(float) * 0.5
    a = a - a[0]  # outlines relative to their first points, as the starts compare them
    if mapped >= 0:  # b the image of a under one map (or of a changed copy)
        swap, sx, sy = _FRAME_MAPS[mapped]
        b = (a[:, ::-1] if swap else a) * (sx, sy)
        if flip:
            b = b.copy()
            b[rng.integers(n)] += 0.5
    else:
        b = rng.integers(-3, 4, (n, 2)).astype(float) * 0.5
    b = b - b[0] + 0.0 * rng.integers(0, 2)  # signed zeros compare equal, as in numpy.array_equal
    assert _congruent(a, b) == reference_congruent(a, b)
    assert _congruent(a, -0.0 * a) == reference_congruent(a, -0.0 * a)
    if n > 1:  # read from other points, the other way round: the outlines relative to those points
        at, back = int(rng.integers(n)), int(rng.integers(n))
        a_read = np.roll(a, -at, axis=0)
        b_read = np.roll(b, -back, axis=0)[::-1]
        b_read = np.roll(b_read, 1, axis=0)  # b read from ``back`` against the outline
        assert _congruent_from(a, at, 1, b, back, -1) == reference_congruent(a_read - a_read[0], b_read - b_read[0])


@numba.njit
def _congruent_from(a, start_a, way_a, b, start_b, way_b):
    """The compiled congruence test (a helper: no Python wrapper of its own)."""
    return _jump_kernels._congruent(a, start_a, way_a, b, start_b, way_b)


def _congruent(a, b):
    """The compiled congruence test of two outlines given relative to their first points."""
    return _congruent_from(np.ascontiguousarray(a, dtype=np.float64), 0, 1, np.ascontiguousarray(b, dtype=np.float64),
                           0, 1)


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(8, 200), runs=st.integers(1, 4), corners=st.integers(1, 12))
def test_symmetric_union_is_the_loop_over_every_pair(seed, n, runs, corners):
    rng = np.random.default_rng(seed)
    # a crack-like outline (steps of 0.5 and 1 px and their diagonals) and corners that cluster, so that many
    # pairs lie within the reach
    steps = rng.choice([0.5, 1.0], (n, 2)) * rng.choice([-1.0, 1.0], (n, 2)) * (rng.random((n, 2)) < 0.7)
    P = np.cumsum(steps, axis=0)
    centres = rng.integers(0, n, corners)
    found = [np.unique((centres + rng.integers(-3, 4, corners)) % n) for _ in range(runs)]
    levels = rng.integers(0, 3, n).astype(np.int64)
    key = _point_order(levels)
    for reach in (0.0, 1.0, 3.0, 10.0):
        assert np.array_equal(jump._symmetric_union(P, found, levels, reach),
                              reference_symmetric_union(P, found, key, reach))


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 400), period=st.integers(1, 40), levels=st.integers(1, 3))
def test_key_comparison_orders_as_the_whole_keys(seed, n, period, levels):
    rng = np.random.default_rng(seed)
    # long ties: periodic and palindromic sequences (symmetric outlines), whose keys agree far into them
    base = rng.integers(0, levels, period)
    sequence = np.resize(np.concatenate([base, base[::-1]]) if seed % 2 else base, n).astype(np.int64)
    key = _point_order(sequence)
    for i, j in rng.integers(0, n, (12, 2)).tolist():
        ka, kb = key(i), key(j)
        expected = 0 if np.array_equal(ka, kb) else 1 if _later(ka, kb) else -1
        assert _key_sign(sequence, i, j) == expected


@numba.njit
def _key_sign(levels, i, j):
    """The compiled comparison of two points' keys (a helper: no Python wrapper of its own)."""
    return _jump_kernels._key_sign(levels, i, j)


def _point_order(levels):
    """Comparison key of the points of a closed outline: its ``levels`` read from the point both ways along the
    outline, the larger of the two sequences first, then the sequence along the outline's own way round (the key
    the compiled union compares up to its first difference). Returns a function ``key(i)``."""
    n = len(levels)
    ring = np.arange(n)

    def key(i):
        ahead, behind = levels[(i + ring) % n], levels[(i - ring) % n]
        return np.concatenate([behind if _later(ahead, behind) else ahead, ahead])
    return key


def reference_jump_peaks(turn, closed, settings):
    """Steps 4-5 with the flanks' median at every sample (the formulation before session 28)."""
    import warnings
    from numpy.lib.stride_tricks import sliding_window_view

    m = len(turn)
    near, far, separation = settings["near"], settings["far"], settings["separation"]
    offsets = np.concatenate([np.arange(-far, -near + 1), np.arange(near, far + 1)])
    if closed:
        flanks = sliding_window_view(turn[np.arange(-far, m + far) % m], 2 * far + 1)[:, offsets + far]
        ends = np.isnan(turn).any()
    else:
        idx = np.arange(m)[:, None] + offsets[None, :]
        flanks = np.where((idx >= 0) & (idx < m), turn[np.clip(idx, 0, m - 1)], np.nan)
        ends = True
    if ends:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            baseline = np.nanmedian(flanks, axis=1)
    else:
        ordered = np.sort(flanks, axis=1)
        half = flanks.shape[1] // 2
        baseline = (ordered[:, half - 1] + ordered[:, half]) / 2
    with np.errstate(invalid="ignore"):
        excess = np.abs(turn - baseline)
        size = np.abs(turn)
        strength = np.where(np.isnan(size), -np.inf, size)
        peak = (strength >= _circular_max_filter(strength, separation, closed)) \
            & (size >= settings["min_turn"]) & (excess >= settings["min_excess"])
    return _plateau_starts(np.flatnonzero(peak), m, separation, closed), size


@settings(max_examples=400, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), m=st.integers(1, 300), closed=st.booleans(), nan=st.booleans(),
       near=st.integers(1, 6), extra=st.integers(0, 12), separation=st.integers(1, 5),
       min_turn=st.sampled_from([0.0, 10.0, 25.0]), min_excess=st.sampled_from([0.0, 25.0, 60.0]))
def test_jump_peaks_take_the_median_where_it_can_choose(seed, m, closed, nan, near, extra, separation, min_turn,
                                                        min_excess):
    rng = np.random.default_rng(seed)
    # staircase noise of a few degrees, corners of 20-150 degrees, plateaus of equal maxima, NaN at open ends
    turn = rng.normal(0.0, 4.0, m)
    spikes = rng.integers(0, m, max(1, m // 25))
    turn[spikes] = rng.choice([-1.0, 1.0], spikes.shape[0]) * rng.uniform(20.0, 150.0, spikes.shape[0])
    turn[np.minimum(spikes + 1, m - 1)[: spikes.shape[0] // 3]] = turn[spikes[: spikes.shape[0] // 3]]
    turn = np.round(turn, 1)
    if nan:
        turn[rng.integers(0, m, max(1, m // 30))] = np.nan
    options = {"near": near, "far": near + extra, "separation": separation, "min_turn": min_turn,
               "min_excess": min_excess}
    flank = np.concatenate([np.arange(-near - extra, -near + 1), np.arange(near, near + extra + 1)])
    chosen = np.empty(m, np.int64)
    count = _peaks(turn, closed, float(min_turn), float(min_excess), separation, flank, chosen,
                   np.empty(flank.shape[0]))
    expected, _ = reference_jump_peaks(turn, closed, options)
    assert np.array_equal(chosen[:count], expected)


@numba.njit
def _peaks(turn, closed, min_turn, min_excess, separation, flank, chosen, flanks):
    """The compiled steps 4-5 (a helper: no Python wrapper of its own)."""
    return _jump_kernels._peaks(turn, closed, min_turn, min_excess, separation, flank, chosen, flanks)


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 400), period=st.integers(1, 40), levels=st.integers(1, 4))
def test_canonical_starts_are_the_loop_over_rows(seed, n, period, levels):
    rng = np.random.default_rng(seed)
    # periodic and palindromic sequences (the starts of symmetric outlines tie), and random ones
    base = rng.integers(0, levels, period)
    sequence = np.resize(np.concatenate([base, base[::-1]]) if seed % 3 == 1 else base, n).astype(np.int64)
    if seed % 3 == 2:
        sequence = rng.integers(0, levels, n).astype(np.int64)
    assert jump._canonical_starts(sequence) == ref_canonical_starts(sequence)


@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), m=st.integers(1, 60), sigma=st.sampled_from([0.3, 1.0, 4.0, 30.0]))
def test_closed_smoothing_wraps_around_as_the_gather_did(seed, m, sigma):
    """The closed outline padded by slices for the smoothing (by the modulo gather where the kernel's half width
    exceeds the outline) is ``samples[np.arange(-half, m + half) % m]``: the same smoothed samples."""
    samples = np.random.default_rng(seed).normal(0, 5, (m, 2))
    half = int(np.ceil(3 * sigma))
    kernel = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma) ** 2)
    kernel /= kernel.sum()
    padded = samples[np.arange(-half, m + half) % m]
    expected = np.column_stack([np.convolve(padded[:, 0], kernel, "valid"), np.convolve(padded[:, 1], kernel, "valid")])
    np.testing.assert_array_equal(jump._smooth(samples, sigma, True), expected)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(3, 60), st.booleans(), st.integers(0, 12), st.integers(0, 12))
def test_stroke_ends_look_for_a_second_corner_as_the_scan_over_every_corner(seed, m, closed, before, after):
    """Step 6b's test for a second corner at a stroke end (by bisection in the sorted corners, a window that
    wraps on a closed outline) answers as the scan over every corner it replaced (quadratic on outlines of many
    ends), including windows that reach the cut at m // 2."""
    rng = np.random.default_rng(seed)
    chosen = rng.choice(m, size=int(rng.integers(1, m + 1)), replace=bool(rng.integers(0, 2)))
    ordered = np.sort(chosen)
    low, high = -before - 2, after + 2
    for i in set(chosen.tolist()):
        others = (chosen - i) % m if closed else chosen - i
        others = np.where(others > m // 2, others - m, others) if closed else others
        expected = bool(np.any((others != 0) & (others >= low) & (others <= high)))
        assert jump._other_corner_near(ordered, chosen, i, low, high, m, closed) == expected


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(2, 200), st.booleans(), st.floats(0.0, 1.0), st.floats(0.0, 40.0))
def test_stroke_ends_window_holds_every_point_the_scan_took(seed, n, closed, at, span):
    """Step 6b's points near an end (``_arc_window``, by bisection on the arc lengths) hold every point whose
    arc from the end's start the scan over all points put within its windows, ``-SIDE_REACH .. span +
    SIDE_REACH``."""
    rng = np.random.default_rng(seed)
    arc = np.concatenate([[0.0], np.cumsum(rng.choice([0.5, 1.0, np.sqrt(0.5), 2.0], n))])
    perimeter, arc = float(arc[-1]), arc[:-1]
    first = float(at * perimeter)
    along = (arc - first) % perimeter if closed else arc - first
    along = np.where(along > perimeter - jump.SIDE_REACH, along - perimeter, along)
    wanted = np.flatnonzero((along >= -jump.SIDE_REACH) & (along <= span + jump.SIDE_REACH))
    near = jump._arc_window(arc, perimeter, first, span + jump.SIDE_REACH, closed)
    assert np.all(np.diff(near) > 0)
    assert set(wanted.tolist()) <= set(near.tolist())
