"""Compiled arm search of tangent-jump (:func:`._jump.tangent_jump`, step 2: straight arms), and its peaks of a
closed outline (steps 4-5, :func:`closed_peaks`).

At every sample of the smoothed outline two arms grow, backwards and forwards, through the lengths of the
arm ladder while every sample of the arm stays within the tolerance of the arm's least-squares line. The
loop below fits each window that a growing arm needs once per length (the forward arm of sample ``i`` is the
backward arm of ``i + L - 1``) and performs the floating-point operations of the vectorized numpy
formulation it replaced, in the same order (``tests/test_kernels.py`` keeps that formulation and pins the
kernel to it bit for bit): the window's mean is the running sum of its samples divided by its length, the
slope the running sum of ``t / sum(t^2)`` times the samples, the residual ``(x - mean) - t slope``; the
straightness test compares the squared residuals with ``tolerance**2`` and falls back to ``hypot`` within a
relative ``1e-12`` of it, where rounding could decide. A window stops being scanned at its first sample
that is certainly too far. numba, compiled on first use and cached on disk (``cache=True``); the loop
writes into arrays its wrapper allocates.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import HELPER_OPTIONS, JIT_OPTIONS, compact, pymax

__all__ = ["arm_lines", "closed_peaks", "warm_up"]


@njit(**HELPER_OPTIONS)
def _window_fit(padded, start, length, centred, weights, tolerance, line):
    """Mean point and slope of the window of ``length`` samples from row ``start`` into ``line[0:4]``, and,
    for a ``tolerance`` > 0, whether every sample lies within it of that line (``max hypot <= tolerance``;
    False where a sample is NaN); True for a ``tolerance`` of 0 (no test)."""
    sx, sy = padded[start, 0], padded[start, 1]
    kx, ky = 0.0 + weights[0] * sx, 0.0 + weights[0] * sy
    for t in range(1, length):
        x, y = padded[start + t, 0], padded[start + t, 1]
        sx += x
        sy += y
        kx += weights[t] * x
        ky += weights[t] * y
    line[0] = sx / length  # one assignment a line: four targets at once build and unpack a tuple (compile time)
    line[1] = sy / length
    line[2] = kx
    line[3] = ky
    if tolerance <= 0:
        return True
    limit = tolerance * tolerance
    low, high = limit * (1.0 - 1e-12), limit * (1.0 + 1e-12)
    worst = 0.0
    for t in range(length):
        dx = (padded[start + t, 0] - line[0]) - centred[t] * line[2]
        dy = (padded[start + t, 1] - line[1]) - centred[t] * line[3]
        squared = dx * dx + dy * dy
        if not squared <= high:  # certainly too far, or NaN
            return False
        worst = pymax(worst, squared)
    if worst < low:
        return True
    farthest = 0.0
    for t in range(length):
        dx = (padded[start + t, 0] - line[0]) - centred[t] * line[2]
        dy = (padded[start + t, 1] - line[1]) - centred[t] * line[3]
        farthest = pymax(farthest, np.hypot(dx, dy))
    return farthest <= tolerance


@njit(**JIT_OPTIONS)
def _arm_lines_into(padded, reach, ladder, centred, weights, tolerance, alive, state, memo, lines):
    """For both sides (0 backward, 1 forward) and every sample the mean point and slope of its last straight
    arm into ``lines[side, i, 0:4]``; ``alive`` (per side and sample), ``state`` (per window start: 0 not
    fitted, 1 straight, 2 not) and ``memo`` (window lines by start) are work arrays."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    m = alive.shape[1]
    for rung in range(ladder.shape[0]):
        length = ladder[rung]
        for start in range(state.shape[0]):
            state[start] = 0
        any_alive = np.bool_(False)
        for side in range(2):
            for i in range(m):
                if not alive[side, i]:
                    continue
                start = i + reach if side == 1 else i + reach - length + 1
                if state[start] == 0:  # the first length is always accepted
                    straight = _window_fit(padded, start, length, centred[rung], weights[rung],
                                           tolerance if rung > 0 else 0.0, memo[start])
                    state[start] = 1 if straight else 2
                if state[start] == 2:  # the arm stops: it keeps the line of the previous length
                    alive[side, i] = False
                    continue
                for q in range(4):
                    lines[side, i, q] = memo[start, q]
                any_alive = True
        if not any_alive:
            return


@njit(**JIT_OPTIONS)
def _closed_peaks_into(padded, pad, near, far, separation, min_turn, min_excess, flank, peak):
    """Steps 4-5 of tangent-jump on a closed outline whose turns hold no NaN (``padded``: the ``m`` turns with
    ``pad`` wrapped ones before and after, at least ``far`` and ``separation``): per sample whether its ``|J|`` is the largest within ``separation``
    samples, at least ``min_turn``, and exceeds the median of its flanks (the turns ``near .. far`` samples
    before and after it) by ``min_excess``, into ``peak``. The median is the mean of the two middle flank values
    in sorted order, as numpy's median of an even count computes it; ``flank`` (``2 (far - near + 1)`` values)
    holds them sorted, from one sample to the next the two that leave replaced by the two that enter. (Where
    two zeros of opposite signs tie, the one removed may be the other: the middle values' sum then differs at
    most in the sign of a zero, which ``|J - median|`` does not see.)"""
    compact()  # run time negligible: code optimized for size (_jit.compact)
    m = peak.shape[0]
    count, half = 2 * (far - near + 1), far - near + 1
    for k in range(count):  # the flanks of sample 0, sorted by insertion
        value = padded[pad - near - k // 2] if k % 2 == 0 else padded[pad + near + k // 2]
        j = k
        while j > 0 and flank[j - 1] > value:
            flank[j] = flank[j - 1]
            j -= 1
        flank[j] = value
    for i in range(m):
        if i > 0:  # before: turn i - 1 - far leaves, i - near enters; after: i - 1 + near leaves, i + far enters
            for side in range(2):
                gone = padded[i - 1 + pad - far] if side == 0 else padded[i - 1 + pad + near]
                new = padded[i + pad - near] if side == 0 else padded[i + pad + far]
                j = 0
                while j < count - 1 and flank[j] != gone:
                    j += 1
                while j + 1 < count and flank[j + 1] < new:  # the gap moves up to where ``new`` belongs ...
                    flank[j] = flank[j + 1]
                    j += 1
                while j > 0 and flank[j - 1] > new:  # ... or down
                    flank[j] = flank[j - 1]
                    j -= 1
                flank[j] = new
        baseline = (flank[half - 1] + flank[half]) / 2
        turn = padded[i + pad]
        size = abs(turn)
        largest = size
        for offset in range(1, separation + 1):
            largest = pymax(largest, abs(padded[i + pad - offset]))
            largest = pymax(largest, abs(padded[i + pad + offset]))
        peak[i] = size >= largest and size >= min_turn and abs(turn - baseline) >= min_excess


def closed_peaks(turn, near, far, separation, min_turn, min_excess):
    """:func:`_closed_peaks_into` (steps 4-5 of :func:`._jump.tangent_jump` on a closed outline without NaN
    turns): a boolean per sample."""
    m, pad = turn.shape[0], max(int(far), int(separation))
    padded = np.ascontiguousarray(turn[np.arange(-pad, m + pad) % m], dtype=np.float64)
    peak = np.empty(m, np.bool_)
    _closed_peaks_into(padded, pad, int(near), int(far), int(separation), float(min_turn), float(min_excess),
                       np.empty(2 * (int(far) - int(near) + 1)), peak)
    return peak


def arm_lines(padded, reach, ladder, operators, tolerance):
    """Mean points and slopes (along travel) of the straight arms before (side 0) and after (side 1) every
    sample: an array (2, m, 4) of ``mean_x, mean_y, slope_x, slope_y``, for the ``m = len(padded) - 2 reach``
    samples of ``padded`` (the samples with ``reach`` rows of wrap-around or NaN on both ends). ``operators``
    gives the centred offsets and slope weights of each length of ``ladder``."""
    padded = np.ascontiguousarray(padded, dtype=np.float64)
    lengths = np.asarray(ladder, dtype=np.int64)
    centred, weights = np.zeros((lengths.shape[0], lengths.max())), np.zeros((lengths.shape[0], lengths.max()))
    for rung, length in enumerate(lengths):
        centred[rung, :length], weights[rung, :length] = operators(int(length))
    m = padded.shape[0] - 2 * int(reach)
    lines = np.full((2, m, 4), np.nan)
    _arm_lines_into(padded, int(reach), lengths, centred, weights, float(tolerance), np.ones((2, m), np.bool_),
                    np.zeros(padded.shape[0], np.int8), np.empty((padded.shape[0], 4)), lines)
    return lines


_WARM = []


def warm_up():
    """Compile or load the kernel once per process (see :func:`..fitting._kernels.warm_up`)."""
    if _WARM:
        return

    def operators(length):
        centred = np.arange(length) - (length - 1) / 2
        return centred, centred / np.sum(centred ** 2)
    samples = np.column_stack([np.arange(12.0), np.zeros(12)])
    arm_lines(samples, 3, [3, 4], operators, 0.3)
    closed_peaks(np.arange(12.0), 4, 10, 2, 25.0, 25.0)
    _WARM.append(True)
