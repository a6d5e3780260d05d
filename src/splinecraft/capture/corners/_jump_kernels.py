"""Compiled arm search of tangent-jump (:func:`._jump.tangent_jump`, step 2: straight arms).

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

__all__ = ["arm_lines", "warm_up"]


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
    _WARM.append(True)
