"""Compiled arm search of tangent-jump (:func:`._jump.tangent_jump`, step 2: straight arms).

At every sample of the smoothed outline two arms grow, backwards and forwards, through the lengths of the
arm ladder while every sample of the arm stays within the tolerance of the arm's least-squares line. The
loop below decides each window that a growing arm needs once per length (the forward arm of sample ``i`` is
the backward arm of ``i + L - 1``) as the vectorized numpy formulation it replaced decides it, and gives the
lines of that formulation bit for bit (``tests/test_kernels.py`` keeps it and pins the kernel to it): the
window's mean is the running sum of its samples divided by its length, the slope the running sum of
``t / sum(t^2)`` times the samples, the residual ``(x - mean) - t slope``; the straightness test compares the
squared residuals with ``tolerance**2`` and falls back to ``hypot`` within a relative ``1e-12`` of it, where
rounding could decide. Most windows are decided without that scan, from second moments taken in constant time
from compensated prefix sums of the outline (:func:`_moment_verdict`: the sum of squared distances from the
line bounds the largest from above and from below, with margins for rounding that keep every decision the
scan's); a scanned window stops at its
first sample that is certainly too far, and an arm whose longest window is certainly straight skips the
shorter ones (each is then too). Only the last straight window of each arm has its line formed (in the order
above). numba, compiled on first use and cached on disk (``cache=True``); the loop writes into
arrays its wrapper allocates.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import HELPER_OPTIONS, JIT_OPTIONS, compact, pymax

__all__ = ["arm_lines", "warm_up"]


@njit(**HELPER_OPTIONS)
def _window_fit(padded, start, length, centred, weights, tolerance, line):
    """The line of the window of ``length`` samples from row ``start`` into ``line[0:4]`` (its mean point, the
    running sum of its samples over ``length``, and its slope, the running sum of ``weights`` times them) and, for
    a ``tolerance`` > 0, whether every sample lies within it of that line (``max hypot <= tolerance``; False
    where a sample is NaN); True for a ``tolerance`` of 0 (no test)."""
    compact()  # optimized for size, as its caller is (_jit.compact)
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


@njit(**dict(HELPER_OPTIONS, forceinline=False))  # called once a call: not inlined, 0.03 s less to compile
def _prefix_moments(padded, sums, nans):
    """Prefix sums over the rows of ``padded`` relative to its first finite row: ``sums[j, q]`` and its
    compensation ``sums[j, 6 + q]`` (Neumaier's summation: the two add up to the exact prefix to a rounding or
    two) of ``x``, ``y``, ``x^2``, ``y^2``, ``k x``, ``k y`` over the rows ``k < j``, NaN rows counted in ``nans``
    and summed as 0. Returns the largest magnitude of a coordinate relative to that origin."""
    compact()  # optimized for size, as its caller is (_jit.compact)
    rows = padded.shape[0]
    ox, oy = 0.0, 0.0
    for j in range(rows):
        if padded[j, 0] == padded[j, 0] and padded[j, 1] == padded[j, 1]:
            ox, oy = padded[j, 0], padded[j, 1]
            break
    amplitude = 0.0
    for q in range(12):
        sums[0, q] = 0.0
    nans[0] = 0
    for j in range(rows):
        x, y = padded[j, 0] - ox, padded[j, 1] - oy
        finite = x == x and y == y
        nans[j + 1] = nans[j] + (0 if finite else 1)
        if finite:
            amplitude = pymax(amplitude, pymax(abs(x), abs(y)))
        else:
            x, y = 0.0, 0.0
        for q in range(6):
            coordinate = x if q % 2 == 0 else y
            term = coordinate * (1.0 if q < 2 else coordinate if q < 4 else j)
            total = sums[j, q]
            updated = total + term
            sums[j + 1, q] = updated
            lost = (total - updated) + term if abs(total) >= abs(term) else (term - updated) + total
            sums[j + 1, 6 + q] = sums[j, 6 + q] + lost
    return amplitude


@njit(**HELPER_OPTIONS)
def _moment_verdict(sums, nans, start, length, tolerance, amplitude, spread, bounds):
    """What the second moments of the window of ``length`` samples from row ``start`` decide of
    :func:`_window_fit`: 1 certainly straight, 2 certainly not, 0 undecided (then the samples are scanned).

    The sum of squared distances ``S`` of the samples from their least-squares line in the row index ``k`` comes
    from the prefix sums of :func:`_prefix_moments` (``spread``: their largest coordinate magnitude) in constant
    time; every sample lies within ``sqrt(S)`` of the line and one at least ``sqrt(S / length)`` from it. Both
    bounds hold with margins for the rounding of ``S`` and of the scan's own residuals (``8 (length + 4) eps``
    times ``amplitude``, the largest magnitude of a coordinate), so the verdict is the scan's exactly. A window
    with a NaN sample is not straight; a NaN bound decides nothing.

    The rounding of ``S``: a prefix of ``rows`` terms is within ``2 eps + 4 rows eps^2`` times the sum of its
    terms' magnitudes (at most ``rows`` times ``spread``, ``spread^2``, ``rows spread``), each operation after it
    within ``4 eps`` of the magnitudes of its inputs (generously), the shift to the prefixes' origin within
    ``8 length eps spread^2``; all of it twice over. ``bounds`` holds what depends only on the length (formed
    when ``bounds[4]`` is not ``length``): ``1 / length``, ``12 / (length (length^2 - 1))`` (the centred offsets'
    sum of squares, inverted), the rounding of a centred sum of squares and that of a cross moment."""
    compact()  # optimized for size, as its caller is (_jit.compact)
    stop = start + length
    if nans[stop] != nans[start]:
        return 2
    epsilon = 2.220446049250313e-16
    if bounds[4] != length:
        rows = sums.shape[0]
        bounds[0] = 1.0 / length
        bounds[1] = 12.0 / (length * (length * length - 1.0))
        prefix = (4.0 * (2.0 * epsilon + 4.0 * rows * epsilon * epsilon) + 16.0 * epsilon) * rows * spread
        total, squares = length * spread, length * spread * spread
        bounds[2] = prefix * spread + (2.0 * total + prefix) * prefix * bounds[0] + 8.0 * epsilon * squares
        bounds[3] = prefix * rows + rows * prefix + 8.0 * epsilon * rows * total
        bounds[4] = length
    distances, rounding = 0.0, 8.0 * length * epsilon * spread * spread
    for q in range(2):
        total = (sums[stop, q] - sums[start, q]) + (sums[stop, 6 + q] - sums[start, 6 + q])
        squares = (sums[stop, 2 + q] - sums[start, 2 + q]) + (sums[stop, 8 + q] - sums[start, 8 + q])
        moment = (sums[stop, 4 + q] - sums[start, 4 + q]) + (sums[stop, 10 + q] - sums[start, 10 + q])
        centred = squares - total * total * bounds[0]
        cross = moment - (start + 0.5 * (length - 1)) * total
        slope = cross * cross * bounds[1]
        distances += centred - slope
        rounding += bounds[2] + (2.0 * abs(cross) + bounds[3]) * bounds[3] * bounds[1] + \
            8.0 * epsilon * (abs(centred) + slope)
    rounding *= 2.0 * (1.0 + 4.0 * epsilon)
    residual = 8.0 * (length + 4) * epsilon * amplitude
    limit = tolerance * tolerance
    if distances + rounding + (2.0 * tolerance + residual) * residual <= limit * (1.0 - 1e-9):
        return 1
    if distances - rounding > length * (tolerance + residual) * (tolerance + residual) * (1.0 + 1e-9):
        return 2
    return 0


@njit(**JIT_OPTIONS)
def _arm_lines_into(padded, reach, ladder, centred, weights, tolerance, amplitude, alive, last, state, sums, nans,
                    bounds, memo, fitted, lines):
    """For both sides (0 backward, 1 forward) and every sample the mean point and slope of its last straight
    arm into ``lines[side, i, 0:4]``. Work arrays: ``alive`` and ``last`` (per side and sample: growing, the
    rung of its last straight arm), ``state`` (per window start: 0 not decided at this length, 1 straight, 2
    not, 3 undecided by the probe of the longest windows), ``sums``, ``nans`` and ``bounds`` (per row and one
    more, :func:`_prefix_moments`; 5, :func:`_moment_verdict`), ``memo`` and
    ``fitted`` (per start: a window line and its rung, -1 none)."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    m = alive.shape[1]
    spread = _prefix_moments(padded, sums, nans)
    top = ladder.shape[0] - 1
    # step 0 probes the longest windows: an arm whose longest window is certainly straight skips the ladder (a
    # shorter window of the same arm is as close to its own line as to the longer one's, so its sum of squared
    # distances is at most the longer's); steps 1.. are the ladder's lengths
    for step in range(0 if top > 0 and tolerance > 0 else 1, ladder.shape[0] + 1):
        probe = step == 0
        rung = top if probe else step - 1
        length = ladder[rung]
        for start in range(state.shape[0]):
            state[start] = 0
        any_alive = np.bool_(False)
        for side in range(2):
            for i in range(m):
                if not alive[side, i]:
                    continue
                start = i + reach if side == 1 else i + reach - length + 1
                if state[start] == 0:  # the first length is always accepted, any with a tolerance of 0
                    verdict = 1 if rung == 0 or tolerance <= 0 else \
                        _moment_verdict(sums, nans, start, length, tolerance, amplitude, spread, bounds)
                    if verdict == 0 and not probe:
                        verdict = 1 if _window_fit(padded, start, length, centred[rung], weights[rung],
                                                   tolerance, memo[start]) else 2
                        fitted[start] = rung
                    state[start] = verdict if verdict > 0 else 3  # 3: undecided by the probe
                if probe:
                    if state[start] == 1:
                        alive[side, i] = False
                        last[side, i] = top
                    continue
                if state[start] == 2:  # the arm stops: it keeps the line of the previous length
                    alive[side, i] = False
                    continue
                last[side, i] = rung
                any_alive = True
        if not any_alive and not probe:
            break
    for side in range(2):  # the lines of the last straight arms, each window fitted once
        for i in range(m):
            rung = last[side, i]
            length = ladder[rung]
            start = i + reach if side == 1 else i + reach - length + 1
            if fitted[start] != rung:
                _window_fit(padded, start, length, centred[rung], weights[rung], 0.0, memo[start])
                fitted[start] = rung
            for q in range(4):
                lines[side, i, q] = memo[start, q]


#: :func:`_ladder_tables` by ladder and ``operators`` function (tangent-jump's: one function, a ladder per
#: ``max_arm`` and short outline), at most ``LADDER_TABLES_KEPT`` of them.
_LADDER_TABLES = {}
LADDER_TABLES_KEPT = 64


def _ladder_tables(ladder, operators):
    """The lengths of ``ladder`` (a tuple) and the centred offsets and slope weights of each, rows padded with 0;
    kept (read-only) for the next call with the same ladder and ``operators`` function."""
    key = (ladder, operators)
    if key in _LADDER_TABLES:
        return _LADDER_TABLES[key]
    lengths = np.asarray(ladder, dtype=np.int64)
    centred, weights = np.zeros((len(ladder), max(ladder))), np.zeros((len(ladder), max(ladder)))
    for rung, length in enumerate(ladder):
        centred[rung, :length], weights[rung, :length] = operators(length)
    if len(_LADDER_TABLES) < LADDER_TABLES_KEPT:
        for table in (lengths, centred, weights):
            table.flags.writeable = False
        _LADDER_TABLES[key] = lengths, centred, weights
    return lengths, centred, weights


def arm_lines(padded, reach, ladder, operators, tolerance):
    """Mean points and slopes (along travel) of the straight arms before (side 0) and after (side 1) every
    sample: an array (2, m, 4) of ``mean_x, mean_y, slope_x, slope_y``, for the ``m = len(padded) - 2 reach``
    samples of ``padded`` (the samples with ``reach`` rows of wrap-around or NaN on both ends). ``operators``
    gives the centred offsets and slope weights of each length of ``ladder``."""
    padded = np.ascontiguousarray(padded, dtype=np.float64)
    lengths, centred, weights = _ladder_tables(tuple(int(length) for length in ladder), operators)
    reach, rows = int(reach), padded.shape[0]
    m = rows - 2 * reach
    amplitude = float(np.abs(padded[reach:rows - reach]).max()) if m > 0 else 0.0   # the samples (finite)
    lines = np.full((2, m, 4), np.nan)
    _arm_lines_into(padded, reach, lengths, centred, weights, float(tolerance), amplitude, np.ones((2, m), np.bool_),
                    np.zeros((2, m), np.int16), np.zeros(rows, np.int8), np.empty((rows + 1, 12)),
                    np.empty(rows + 1, np.int64), np.zeros(5), np.empty((rows, 4)), np.full(rows, -1, np.int16), lines)
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
