"""tangent-jump's helpers (capture/corners/_jump.py, docs/capture.md §11) pinned to the formulations they
replaced (kept here as the reference): steps 4-5 with the flanks' median only where a peak can be (``_jump_peaks``);
on symmetric outlines the eight frame maps passed over on their first points (``_congruent``), the corners of the
union (``_symmetric_union``) whose chord to the next one already exceeds the reach passed over without summing their
arc, and the points' keys compared up to their first difference (``_point_comparison``). The same answers, not
just close ones."""
from __future__ import annotations

import importlib

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import splinecraft.capture.corners  # noqa: F401  (the package first: its modules import each other)

jump = importlib.import_module("splinecraft.capture.corners._jump")


def reference_congruent(a, b):
    return any(np.array_equal((a[:, ::-1] if swap else a) * (sx, sy), b) for swap, sx, sy in jump._FRAME_MAPS)


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
                    dropped.add(a if jump._later(ka, kb) else b)
            step += 1
    return np.array([index for k, index in enumerate(union) if k not in dropped], dtype=np.int64)


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 40), mapped=st.integers(-1, 7), flip=st.booleans())
def test_congruent_is_the_eight_maps_compared_one_by_one(seed, n, mapped, flip):
    rng = np.random.default_rng(seed)
    a = rng.integers(-3, 4, (n, 2)).astype(float) * 0.5
    if mapped >= 0:  # b the image of a under one map (or of a changed copy)
        swap, sx, sy = jump._FRAME_MAPS[mapped]
        b = (a[:, ::-1] if swap else a) * (sx, sy)
        if flip:
            b = b.copy()
            b[rng.integers(n)] += 0.5
    else:
        b = rng.integers(-3, 4, (n, 2)).astype(float) * 0.5
    b = b + 0.0 * rng.integers(0, 2)  # signed zeros compare equal, as in numpy.array_equal
    assert jump._congruent(a, b) == reference_congruent(a, b)
    assert jump._congruent(a, -0.0 * a) == reference_congruent(a, -0.0 * a)


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
    key, later = jump._point_order(levels), jump._point_comparison(levels)
    for reach in (0.0, 1.0, 3.0, 10.0):
        assert np.array_equal(jump._symmetric_union(P, found, later, reach),
                              reference_symmetric_union(P, found, key, reach))


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 400), period=st.integers(1, 40), levels=st.integers(1, 3))
def test_point_comparison_orders_as_the_whole_keys(seed, n, period, levels):
    rng = np.random.default_rng(seed)
    # long ties: periodic and palindromic sequences (symmetric outlines), whose keys agree far into them
    base = rng.integers(0, levels, period)
    sequence = np.resize(np.concatenate([base, base[::-1]]) if seed % 2 else base, n).astype(np.int64)
    key, later = jump._point_order(sequence), jump._point_comparison(sequence)
    for i, j in rng.integers(0, n, (12, 2)).tolist():
        ka, kb = key(i), key(j)
        expected = None if np.array_equal(ka, kb) else jump._later(ka, kb)
        assert later(i, j) == expected


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
        peak = (strength >= jump._circular_max_filter(strength, separation, closed)) \
            & (size >= settings["min_turn"]) & (excess >= settings["min_excess"])
    return jump._plateau_starts(np.flatnonzero(peak), m, separation, closed), size


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
    chosen, size = jump._jump_peaks(turn, closed, options)
    expected, expected_size = reference_jump_peaks(turn, closed, options)
    assert np.array_equal(chosen, expected)
    assert np.array_equal(size, expected_size, equal_nan=True)


def reference_canonical_starts(levels):
    """The candidates narrowed block by block with the lexicographically largest row found one by one (the loop
    before session 29, which a symmetric outline's tied starts now skip)."""
    n = len(levels)
    top = np.flatnonzero(levels == levels.max())
    point, way = np.concatenate([top, top]), np.repeat([1, -1], len(top))
    offset, block = 1, 16
    while point.size > 1 and offset < n:
        ahead = np.arange(offset, min(offset + block, n))
        rows = levels[(point[:, None] + way[:, None] * ahead[None, :]) % n]
        best = rows[0]
        for row in rows[1:]:
            if jump._later(best, row):
                best = row
        keep = np.all(rows == best, axis=1)
        point, way = point[keep], way[keep]
        offset, block = offset + len(ahead), 4 * block
    order = np.lexsort((-way, point))
    return [(int(i), int(d)) for i, d in zip(point[order], way[order])]


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 400), period=st.integers(1, 40), levels=st.integers(1, 4))
def test_canonical_starts_are_the_loop_over_rows(seed, n, period, levels):
    rng = np.random.default_rng(seed)
    # periodic and palindromic sequences (the starts of symmetric outlines tie), and random ones
    base = rng.integers(0, levels, period)
    sequence = np.resize(np.concatenate([base, base[::-1]]) if seed % 3 == 1 else base, n).astype(np.int64)
    if seed % 3 == 2:
        sequence = rng.integers(0, levels, n).astype(np.int64)
    assert jump._canonical_starts(sequence) == reference_canonical_starts(sequence)


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), rows=st.integers(0, 5), columns=st.integers(1, 5))
def test_step_6_picks_are_the_nan_to_num_formulation(seed, rows, columns):
    """The point nearest the apex and the farthest out among those within reach (``_locate``) are those of the
    ``np.nan_to_num`` formulation before session 29, also among NaN, inf and -inf values and rows with none within."""
    rng = np.random.default_rng(seed)
    values = rng.choice([0.5, 1.0, 2.0, np.nan, np.inf, -np.inf, 1.7e308, -1.7e308], (rows, columns))
    within = rng.uniform(size=(rows, columns)) < 0.6
    gap = np.abs(values)
    with np.errstate(invalid="ignore"):
        assert np.array_equal(jump._nearest_within(gap, within),
                              np.argmin(np.where(within, np.nan_to_num(gap, nan=np.inf), np.inf), axis=1))
        assert np.array_equal(jump._farthest_within(values, within),
                              np.argmax(np.nan_to_num(np.where(within, values, -np.inf), nan=-np.inf), axis=1))


def test_signed_arm_turn_wraps_a_closed_outline_around_as_the_gather_did():
    """The closed outline padded by slices (and by the modulo gather where the longest arm exceeds the outline)
    gives the arms of ``R[np.arange(-reach, m + reach) % m]``."""
    from splinecraft.capture.corners import _jump_kernels

    rng = np.random.default_rng(5)
    ladder = [3, 4, 5, 6, 8, 10, 12]
    for m in (10, 12, 40):
        R = np.cumsum(rng.normal(0, 1, (m, 2)), axis=0)
        lines = _jump_kernels.arm_lines(R[np.arange(-12, m + 12) % m], 12, ladder, jump._forward_operators, 0.3)
        a, b = lines[0, :, 2:], lines[1, :, 2:]
        turn = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.sum(a * b, axis=1)))
        got, arms = jump._signed_arm_turn(R, True, 0.3, ladder)
        np.testing.assert_array_equal(got, turn)
        np.testing.assert_array_equal(arms[3], b)


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
