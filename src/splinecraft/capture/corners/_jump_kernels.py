"""Compiled steps of tangent-jump (:func:`._jump.tangent_jump`, docs/capture.md §11 and "Compiled kernels").

Four kernels (session 30; before it only the arm search was compiled, and the Python and small numpy calls around
it took most of the detector's time): :func:`_starts_into` forms a closed outline's levels, canonical
starts and congruent starts; :func:`_resample_into` and :func:`_corners_into` run steps 1-6 from one start (the
resampling; the smoothing, the arm search below, the turn, the peaks, the spread turns, the location and step 6b's
test); :func:`_union_into` reduces a symmetric outline's runs. Each does the floating-point operations of the numpy
formulation it replaced in the same order (``tests/test_jump_steps.py`` keeps that formulation and pins these
kernels to it bit for bit).

The arm search (step 2: straight arms).

At every sample of the smoothed outline two arms, backwards and forwards, are the longest window of the arm ladder
when every sample of it stays within the tolerance of its least-squares line (step 0, the probe), and otherwise grow
through the lengths of the ladder while every sample of the arm stays within the tolerance of the arm's
least-squares line. The loop below decides each window that an arm needs once per length (the forward arm of sample
``i`` is the backward arm of ``i + L - 1``) as the vectorized numpy formulation it replaced decides it, and gives
the lines of that formulation bit for bit (``tests/test_kernels.py`` keeps it and pins the kernel to it): the
window's mean is the running sum of its samples divided by its length, the slope the running sum of ``t / sum(t^2)``
times the samples, the residual ``(x - mean) - t slope``; the straightness test compares the squared residuals with
``tolerance**2`` and falls back to ``hypot`` within a relative ``1e-12`` of it, where rounding could decide. Most
windows are decided without that scan, from second moments taken in constant time from compensated prefix sums of
the outline (:func:`_moment_verdict`: the sum of squared distances from the line bounds the largest from above and
from below, with margins for rounding that keep every decision the scan's); a scanned window stops at its first
sample that is certainly too far, and an arm whose longest window is straight skips the shorter ones (on a pixel
staircase the moments rarely decide them, so the ladder scanned most of them). Only the last straight window of each
arm has its line formed (in the order above). numba, compiled on first use and cached on disk (``cache=True``); the
loop writes into arrays its wrapper allocates.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import HELPER_OPTIONS, JIT_OPTIONS, compact, insertion_sort, pyclip, pymax, pymin

__all__ = ["arm_lines", "corners_of", "resample", "starts_of", "union_drops", "warm_up"]


@njit(**HELPER_OPTIONS)
def _window_fit(padded, start, length, centred, weights, tolerance, line):
    """The line of the window of ``length`` samples from row ``start`` into ``line[0:4]`` (its mean point, the
    running sum of its samples over ``length``, and its slope, the running sum of ``weights`` times them) and, for
    a ``tolerance`` > 0, whether every sample lies within it of that line (``max hypot <= tolerance``; False
    where a sample is NaN); True for a ``tolerance`` of 0 (no test). Array values are read once each as ``float``:
    interpreted (:mod:`.._interpreted`) Python floats are ~3x faster than numpy's scalars; compiled the same code."""
    compact()  # optimized for size, as its caller is (_jit.compact)
    sx, sy = float(padded[start, 0]), float(padded[start, 1])
    w = float(weights[0])
    kx, ky = 0.0 + w * sx, 0.0 + w * sy
    for t in range(1, length):
        x, y = float(padded[start + t, 0]), float(padded[start + t, 1])
        w = float(weights[t])
        sx += x
        sy += y
        kx += w * x
        ky += w * y
    line[0] = sx / length  # one assignment a line: four targets at once build and unpack a tuple (compile time)
    line[1] = sy / length
    line[2] = kx
    line[3] = ky
    if tolerance <= 0:
        return True
    limit = tolerance * tolerance
    low, high = limit * (1.0 - 1e-12), limit * (1.0 + 1e-12)
    worst = 0.0
    mx, my = float(line[0]), float(line[1])
    for t in range(length):
        c = float(centred[t])
        dx = (float(padded[start + t, 0]) - mx) - c * kx
        dy = (float(padded[start + t, 1]) - my) - c * ky
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
    # every value read once as float (see _window_fit)
    inverse, inverse_squares, square_rounding, cross_rounding = \
        float(bounds[0]), float(bounds[1]), float(bounds[2]), float(bounds[3])
    distances, rounding = 0.0, 8.0 * length * epsilon * spread * spread
    for q in range(2):
        total = (float(sums[stop, q]) - float(sums[start, q])) + (float(sums[stop, 6 + q]) - float(sums[start, 6 + q]))
        squares = (float(sums[stop, 2 + q]) - float(sums[start, 2 + q])) + \
            (float(sums[stop, 8 + q]) - float(sums[start, 8 + q]))
        moment = (float(sums[stop, 4 + q]) - float(sums[start, 4 + q])) + \
            (float(sums[stop, 10 + q]) - float(sums[start, 10 + q]))
        centred = squares - total * total * inverse
        cross = moment - (start + 0.5 * (length - 1)) * total
        slope = cross * cross * inverse_squares
        distances += centred - slope
        rounding += square_rounding + (2.0 * abs(cross) + cross_rounding) * cross_rounding * inverse_squares + \
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
    not), ``sums``, ``nans`` and ``bounds`` (per row and one
    more, :func:`_prefix_moments`; 5, :func:`_moment_verdict`), ``memo`` and
    ``fitted`` (per start: a window line and its rung, -1 none)."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    m = alive.shape[1]
    spread = _prefix_moments(padded, sums, nans)
    top = ladder.shape[0] - 1
    # step 0 probes the longest windows: an arm whose longest window is straight is that window, and skips the
    # ladder; steps 1.. are the ladder's lengths for the other arms
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
                    if verdict == 0:  # the probe's too: a straight longest window is the arm
                        verdict = 1 if _window_fit(padded, start, length, centred[rung], weights[rung],
                                                   tolerance, memo[start]) else 2
                        fitted[start] = rung
                    state[start] = verdict
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
    for table in (lengths, centred, weights):  # read-only (kept or not: one type for the kernels)
        table.flags.writeable = False
    if len(_LADDER_TABLES) < LADDER_TABLES_KEPT:
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


# ----------------------------------------------------------------------------------------------------------
# steps 1-6 of one start (docs/capture.md §11): resampling, smoothing, turn, peaks, spread, location
# ----------------------------------------------------------------------------------------------------------
#: The largest float (``np.nan_to_num``'s replacement of inf).
_LARGEST = np.finfo(np.float64).max


@njit(**JIT_OPTIONS)
def _resample_into(P, closed, per_point, arc, samples, where, step):
    """Step 1's resampling of the polyline ``P`` (``n`` rows) at uniform arc length, as numpy's formulation computed
    it (``np.cumsum`` of ``np.hypot``, ``np.arange`` or ``np.linspace`` positions, ``np.interp`` and its formula
    ``slope (x - x_j) + y_j``): the cumulative arc length of every point (closed: and back to the first) into
    ``arc`` (``n + 1`` rows), the samples and their arc positions into ``samples`` and ``where`` (at least
    ``per_point n + 1`` rows), the step, ``max(1, total / (per_point n))``, into ``step[0]``. Returns the number of
    samples, or -1 when the length overflows."""
    compact()  # run time negligible: code optimized for size (_jit.compact)
    n = P.shape[0]
    ring = n + 1 if closed else n
    arc[0] = 0.0
    for k in range(1, ring):
        j = k if k < n else 0
        arc[k] = arc[k - 1] + np.hypot(P[j, 0] - P[k - 1, 0], P[j, 1] - P[k - 1, 1])
    total = arc[ring - 1]
    if not np.isfinite(total):
        return -1
    step[0] = pymax(1.0, total / (per_point * n))
    count = int(np.rint(total / step[0]))
    size = count if closed else count + 1
    spacing = total / pymax(count, 1)  # np.arange(count) times it, or np.linspace(0, total, count + 1)
    j = 0
    for i in range(size):
        x = total if not closed and i == count and count > 0 else i * spacing
        while j < ring - 1 and arc[j + 1] <= x:
            j += 1
        where[i] = x
        k = j if j < n else 0
        after = j + 1 if j + 1 < n else 0
        for c in range(2):
            if j >= ring - 1 or arc[j] == x:
                samples[i, c] = P[k, c]
                continue
            slope = (P[after, c] - P[k, c]) / (arc[j + 1] - arc[j])
            value = slope * (x - arc[j]) + P[k, c]
            if np.isnan(value):  # np.interp: NaN one way, the other way; then the equal ends
                value = slope * (x - arc[j + 1]) + P[after, c]
                if np.isnan(value) and P[k, c] == P[after, c]:
                    value = P[k, c]
            samples[i, c] = value
    return size


@njit(**HELPER_OPTIONS)
def _turn(ax, ay, bx, by):
    """The signed angle (degrees) from ``a`` to ``b``, as numpy's ``np.degrees(np.arctan2(cross, np.sum(a * b)))``
    computed it (the row sum of two products: their sum, a zero of either sign as +0)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    return np.degrees(np.arctan2(ax * by - ay * bx, (ax * bx + ay * by) + 0.0))


@njit(**HELPER_OPTIONS)
def _sorted_median(values, count):
    """The median of ``values[:count]`` (sorted here in place, ``count`` > 0) as numpy's ``np.median`` and
    ``np.nanmedian`` compute it: the middle value, or the mean ``(a + b) / 2`` of the two middle ones."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    insertion_sort(values, count)  # a flank has a few dozen values
    half = count // 2
    low = half if count % 2 else half - 1
    return (values[low] + values[half]) / 2


@njit(**HELPER_OPTIONS)
def _peaks(turn, closed, min_turn, min_excess, separation, flank, chosen, flanks):
    """Steps 4-5 of the turn ``J`` (``turn``) into ``chosen``: the samples whose ``|J|`` is the largest within
    ``separation`` samples (NaN counting as -inf) and at least ``min_turn``, and whose excess over the median of
    its flanks (``flank``: the offsets; beyond an open curve's ends and NaN left out, as ``np.nanmedian``) is at
    least ``min_excess``; of those within ``separation`` samples after another one (around the end when
    ``closed``) only the first (a plateau of equal maxima keeps its first sample). ``flanks``: work array of the
    flank's length. Returns how many."""
    compact()  # optimized for size, as its caller is (_jit.compact)
    m = turn.shape[0]
    count = 0
    for i in range(m):
        size = abs(turn[i])
        if not size >= min_turn:
            continue
        largest = True
        for offset in range(-separation, separation + 1):
            k = i + offset
            if closed:
                k = k % m
            elif k < 0 or k >= m:
                continue
            other = abs(turn[k])
            if other > size:  # (NaN: -inf, never larger)
                largest = False
                break
        if not largest:
            continue
        values = 0
        for f in range(flank.shape[0]):
            k = i + flank[f]
            if closed:
                k = k % m
            elif k < 0 or k >= m:
                continue
            if not np.isnan(turn[k]):  # (np.nanmedian where the turn has NaN: open ends)
                flanks[values] = turn[k]
                values += 1
        baseline = _sorted_median(flanks, values) if values else np.nan
        if abs(turn[i] - baseline) >= min_excess:
            chosen[count] = i
            count += 1
    # plateaus keep their first sample
    if count > 1:
        kept = 1
        wrap = closed and chosen[0] + m - chosen[count - 1] <= separation
        for k in range(1, count):
            if chosen[k] - chosen[k - 1] > separation and not (wrap and k == count - 1):
                chosen[kept] = chosen[k]
                kept += 1
        count = kept
    return count


@njit(**JIT_OPTIONS)
def _corners_into(P, arc, perimeter, closed, taps, samples, where, smoothed, reach, ladder, centred, weights, settings, flank,
                  padded, alive, last, state, sums, nans, bounds, memo, fitted, lines, turn, work, chosen, nearest,
                  ends):
    """Steps 1 (the smoothing) to 6 and the test of step 6b of :func:`._jump.tangent_jump` on the resampled outline
    ``samples`` (``m`` rows; ``P`` its points, ``arc`` their arc positions), each as the numpy formulation they
    replaced computed it (``tests/test_jump_helpers.py`` keeps it and pins this kernel to it):

    * the smoothing by the normalized Gaussian ``taps`` (none: empty) into ``smoothed``, cyclic when closed, else
      with the end samples repeated: the sums of ``np.convolve`` in its order, from 0 (numpy's dot product of a
      kernel shorter than 16 taps, the only ones passed here: longer ones are smoothed by numpy and passed as the
      samples with no taps);
    * the arms of every sample (:func:`_arm_lines_into`, ``lines``) and their signed turn into ``turn``;
    * the peaks (steps 4-5: ``|J|`` the largest within ``separation`` samples and at least ``min_turn``, the excess
      over the flanks' median at least ``min_excess``, the first of a plateau), the spread turns released (step 5b)
      and each corner's input point (step 6) into ``chosen`` and ``nearest``;
    * step 6b's test of each corner into ``ends`` (rows: whether it may be a stroke's end, the first and the
      longest long arm behind and ahead, in samples, and the turn between the longest ones).

    ``settings`` holds ``min_turn``, ``min_excess``, ``spread``, ``tolerance``, ``separation``, ``stroke_ends``;
    ``flank`` the flank offsets. Work arrays: those of :func:`_arm_lines_into` (``padded`` has ``m + 2 reach``
    rows) and ``work`` (float, ``m`` + the flank's length). Returns the number of corners."""
    compact()  # run time negligible: code optimized for size (_jit.compact)
    m = samples.shape[0]
    n = P.shape[0]
    min_turn, min_excess, spread, tolerance = settings[0], settings[1], settings[2], settings[3]
    separation, stroke_ends, spread_reach = int(settings[4]), settings[5] > 0, int(settings[6])
    end_reach, end_arm, end_turn = int(settings[7]), settings[8], settings[9]
    # step 1: the smoothing (np.convolve of the padded samples, valid part)
    width = taps.shape[0]
    half = width // 2
    for i in range(m):
        for c in range(2):
            if width == 0:
                smoothed[i, c] = samples[i, c]
                continue
            total = 0.0
            for t in range(width):
                k = i + t - half
                k = k % m if closed else pyclip(k, 0, m - 1)
                total += samples[k, c] * taps[width - 1 - t]
            smoothed[i, c] = total
    # step 2: the arms (the padded curve: wrapped around, or NaN beyond the ends)
    rows = m + 2 * reach
    amplitude = 0.0
    for k in range(rows):
        for c in range(2):
            if closed:
                padded[k, c] = smoothed[(k - reach) % m, c]
            else:
                padded[k, c] = smoothed[k - reach, c] if reach <= k < m + reach else np.nan
    for i in range(m):
        amplitude = pymax(amplitude, pymax(abs(smoothed[i, 0]), abs(smoothed[i, 1])))
    for side in range(2):
        for i in range(m):
            alive[side, i] = True
            last[side, i] = 0
    for k in range(rows):
        state[k] = 0
        fitted[k] = -1
    for q in range(5):
        bounds[q] = 0.0
    _arm_lines_into(padded, reach, ladder, centred, weights, tolerance, amplitude, alive, last, state, sums, nans,
                    bounds, memo, fitted, lines)
    # step 3: the turn; steps 4-5: its peaks (strength: |J|, NaN as -inf; its maximum over the separation)
    for i in range(m):
        turn[i] = _turn(lines[0, i, 2], lines[0, i, 3], lines[1, i, 2], lines[1, i, 3])
    count = _peaks(turn, closed, min_turn, min_excess, separation, flank, chosen, work[m:])
    # step 5b: spread turns (the turn from the backward arm 8 samples before to the forward arm 8 after)
    if spread > 0 and count > 0:
        gaps = work[:count]  # to the nearest other corner (around the shorter way when closed)
        for k in range(count):
            if count < 2:
                gaps[k] = m
                continue
            ahead = chosen[k + 1] - chosen[k] if k + 1 < count else (chosen[0] + m - chosen[k] if closed else m)
            behind = chosen[k] - chosen[k - 1] if k > 0 else (chosen[0] + m - chosen[count - 1] if closed else m)
            if closed:
                ahead, behind = pymin(ahead, m - ahead), pymin(behind, m - behind)
            gaps[k] = pymin(ahead, behind)
        kept = 0
        for k in range(count):
            i = chosen[k]
            before, after = i - spread_reach, i + spread_reach
            valid = True
            if closed:
                before, after = before % m, after % m
            else:
                valid = before >= 0 and after < m
                before, after = pymax(before, 0), pymin(after, m - 1)
            wide = _turn(lines[0, before, 2], lines[0, before, 3], lines[1, after, 2], lines[1, after, 3])
            jump = turn[i]
            if not (valid and gaps[k] > 2 * spread_reach and jump * wide > 0 and abs(jump) < spread * abs(wide)):
                chosen[kept] = i
                kept += 1
        count = kept
    # step 6: the input point of each corner (within 3 px of arc: nearest the arms' apex, or farthest out)
    for k in range(count):
        i = chosen[k]
        pos = where[i]
        low, high = 0, n  # np.searchsorted(arc[:n], pos)
        while low < high:
            middle = (low + high) // 2
            if arc[middle] < pos:
                low = middle + 1
            else:
                high = middle
        right = pymin(low, n - 1)
        left = pymax(right - 1, 0)
        near = left if abs(arc[left] - pos) <= abs(arc[right] - pos) else right
        if closed and (perimeter - pos) < abs(arc[near] - pos):  # the closing chord leads back to point 0
            near = 0
        ax, ay, bx, by = lines[0, i, 2], lines[0, i, 3], lines[1, i, 2], lines[1, i, 3]
        det = ax * by - ay * bx  # the apex: where the arms' lines cross (NaN where nearly parallel)
        along_a = ((lines[1, i, 0] - lines[0, i, 0]) * by - (lines[1, i, 1] - lines[0, i, 1]) * bx) / det
        px, py = lines[0, i, 0] + along_a * ax, lines[0, i, 1] + along_a * ay
        if abs(det) <= 1e-9 * np.hypot(ax, ay) * np.hypot(bx, by):
            px, py = np.nan, np.nan
        apex_ok = np.isfinite(px) and np.isfinite(py) and np.hypot(px - smoothed[i, 0], py - smoothed[i, 1]) <= 3.0 \
            and abs(turn[i]) < 100.0
        length_a, length_b = np.hypot(ax, ay), np.hypot(bx, by)
        ox, oy = ax / length_a - bx / length_b, ay / length_a - by / length_b  # the bisector, to the apex
        nearest_gap, near_apex, farthest, tip = np.inf, 0, -np.inf, 0
        for j in range(13):
            q = near + j - 6
            q = q % n if closed else pyclip(q, 0, n - 1)
            along = abs(arc[q] - pos)
            if closed:
                along = pymin(along, perimeter - along)
            within = along <= 3.0
            distance = np.hypot(P[q, 0] - px, P[q, 1] - py)
            distance = pymin(distance, _LARGEST) if within and not np.isnan(distance) else np.inf
            outward = P[q, 0] * ox + P[q, 1] * oy
            outward = (-np.inf if np.isnan(outward) else pyclip(outward, -_LARGEST, _LARGEST)) if within else -_LARGEST
            if j == 0 or distance < nearest_gap:  # the first of equal ones (np.argmin, np.argmax)
                nearest_gap, near_apex = distance, q
            if j == 0 or outward > farthest:
                farthest, tip = outward, q
        nearest[k] = (near_apex if apex_ok else tip) if np.isfinite(ox) and np.isfinite(oy) else near
        # step 6b's test: the sides (the first long arms within reach, the longest), turning back, both long
        if not stroke_ends:
            continue
        inside = True
        first_before, first_after, longest_before, longest_after = 0, 0, 1, 1
        length_before, length_after = 0.0, 0.0
        for r in range(1, end_reach + 1):
            behind, ahead = i - r, i + r
            if closed:
                behind, ahead = behind % m, ahead % m
            else:
                inside = inside and behind >= 0 and ahead < m
                behind, ahead = pymax(behind, 0), pymin(ahead, m - 1)
            arm_before = 2.0 * np.hypot(smoothed[behind, 0] - lines[0, behind, 0],
                                        smoothed[behind, 1] - lines[0, behind, 1])
            arm_after = 2.0 * np.hypot(smoothed[ahead, 0] - lines[1, ahead, 0], smoothed[ahead, 1] - lines[1, ahead, 1])
            if first_before == 0 and arm_before >= end_arm:
                first_before = r
            if first_after == 0 and arm_after >= end_arm:
                first_after = r
            # np.argmax: the first of the largest, the first NaN where there is one
            if r == 1 or (not np.isnan(length_before) and (np.isnan(arm_before) or arm_before > length_before)):
                length_before, longest_before = arm_before, r
            if r == 1 or (not np.isnan(length_after) and (np.isnan(arm_after) or arm_after > length_after)):
                length_after, longest_after = arm_after, r
        behind, ahead = i - longest_before, i + longest_after
        behind = behind % m if closed else pymax(behind, 0)
        ahead = ahead % m if closed else pymin(ahead, m - 1)
        side_turn = abs(_turn(lines[0, behind, 2], lines[0, behind, 3], lines[1, ahead, 2], lines[1, ahead, 3]))
        ends[k, 0] = 1.0 if inside and first_before > 0 and first_after > 0 and side_turn >= end_turn else 0.0
        ends[k, 1] = pymax(first_before, 1)
        ends[k, 2] = pymax(first_after, 1)
        ends[k, 3] = longest_before
        ends[k, 4] = longest_after
        ends[k, 5] = side_turn
    return count



# ----------------------------------------------------------------------------------------------------------
# the starts of a closed outline and the union of a symmetric outline's runs (docs/capture.md §11)
# ----------------------------------------------------------------------------------------------------------
@njit(**HELPER_OPTIONS)
def _read_sign(levels, i, way_i, j, way_j, stop):
    """The sign of the first difference of ``levels`` read from ``j`` (way ``way_j``) less those read from ``i``
    (way ``way_i``), offsets 0 .. ``stop`` - 1 (cyclically); 0 where they agree."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    n = levels.shape[0]
    for d in range(stop):
        a, b = levels[(i + way_i * d) % n], levels[(j + way_j * d) % n]
        if a != b:
            return 1 if b > a else -1
    return 0


@njit(**HELPER_OPTIONS)
def _congruent(A, start_a, way_a, B, start_b, way_b):
    """Whether the closed outline ``A`` read from its point ``start_a`` (way ``way_a``) and ``B`` read from ``start_b``
    (both relative to those points, of one length) are one the image of the other under a quarter turn or a
    reflection of the frame (one of the eight maps: x and y swapped or not, either sign flipped or not), exactly."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    n = A.shape[0]
    if B.shape[0] != n:
        return False
    for mapping in range(8):
        swap, sign_x, sign_y = mapping >= 4, 1.0 if mapping % 4 < 2 else -1.0, 1.0 if mapping % 2 == 0 else -1.0
        same = True
        for d in range(n):
            a, b = (start_a + way_a * d) % n, (start_b + way_b * d) % n
            ax, ay = A[a, 0] - A[start_a, 0], A[a, 1] - A[start_a, 1]
            if swap:
                ax, ay = ay, ax
            if ax * sign_x != B[b, 0] - B[start_b, 0] or ay * sign_y != B[b, 1] - B[start_b, 1]:
                same = False
                break
        if same:
            return True
    return False


@njit(**HELPER_OPTIONS)
def _key_sign(levels, i, j):
    """The order of the comparison keys of points ``i`` and ``j`` (:func:`._jump._symmetric_union`): 1 where that
    of ``j`` is lexicographically larger, -1 where smaller, 0 where they are equal."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    n = levels.shape[0]
    sign = _read_sign(levels, i, _way(levels, i), j, _way(levels, j), n)
    return sign if sign != 0 else _read_sign(levels, i, 1, j, 1, n)


@njit(**JIT_OPTIONS)
def _starts_into(P, levels, given, point, way, source):
    """The canonical starts of the closed outline ``P`` (:func:`._jump._canonical_starts`) into ``point`` and
    ``way`` (at least ``2 n`` rows; sorted by point, along the outline first) and, for each, the first start before
    it (itself where there is none) whose outline read from it is the image of its own under a quarter turn or a
    reflection of the frame, exactly (the same corners, :func:`._jump._starts`), into ``source``. ``levels``:
    the points' levels (:func:`._jump._distance_levels`), ``given`` or formed here by its exact rule for
    coordinates that are multiples of ``2**-k`` (``k`` <= 16) within int64; returns the number of starts, or -1
    where that rule does not apply (then the caller forms them and calls again)."""
    compact()  # run time negligible: code optimized for size (_jit.compact)
    n = P.shape[0]
    if not given:
        scale = 0.0
        for k in range(17):  # the coordinates times 2**k integers, below 2**52
            factor = 2.0 ** k
            whole, largest = True, 0.0
            for i in range(n):
                for c in range(2):
                    value = P[i, c] * factor
                    whole = whole and value == np.floor(value)
                    largest = pymax(largest, abs(value))
            if whole and largest < 2.0 ** 52:
                scale = factor
                break
        if scale == 0.0:
            return -1
        low_x, low_y, high_x, high_y = np.inf, np.inf, -np.inf, -np.inf
        for i in range(n):
            low_x, high_x = pymin(low_x, P[i, 0] * scale), pymax(high_x, P[i, 0] * scale)
            low_y, high_y = pymin(low_y, P[i, 1] * scale), pymax(high_y, P[i, 1] * scale)
        extent = pymax(high_x - low_x, high_y - low_y)
        if not 8.0 * n * (extent + 1.0) ** 2 < 2.0 ** 62:
            return -1
        total_x, total_y = 0, 0
        for i in range(n):
            total_x += np.int64(P[i, 0] * scale - low_x)
            total_y += np.int64(P[i, 1] * scale - low_y)
        for i in range(n):
            x, y = np.int64(P[i, 0] * scale - low_x), np.int64(P[i, 1] * scale - low_y)
            levels[i] = x * (n * x - 2 * total_x) + y * (n * y - 2 * total_y)
    top = levels[0]
    for i in range(n):
        top = pymax(top, levels[i])
    count = 0  # the candidates: the farthest points, both ways round; the lexicographically largest kept
    for i in range(n):
        if levels[i] != top:
            continue
        for direction in (1, -1):
            sign = _read_sign(levels, point[0], way[0], i, direction, n) if count else 0
            if sign > 0:
                count = 0
            if sign >= 0:
                point[count], way[count] = i, direction
                count += 1
    # sorted by point, way +1 first: the candidates come by point, +1 first, and so stay
    for s in range(count):
        source[s] = s
        if count < 2:
            break
        for r in range(s):
            if source[r] != r:
                continue
            congruent = _congruent(P, point[r], way[r], P, point[s], way[s])
            if congruent:
                source[s] = r
                break
    return count


@njit(**dict(HELPER_OPTIONS, forceinline=False))  # recursive: not inlined
def _pairwise_sum(values, first, count):
    """``np.sum`` of ``values[first:first + count]`` (indices modulo its length) as numpy adds it up: pairwise, in
    blocks of at most 128 terms with 8 accumulators, fewer than 8 one by one."""
    compact()  # optimized for size, as its caller is (_jit.compact)
    n = values.shape[0]
    if count < 8:
        total = -0.0
        for t in range(count):
            total += values[(first + t) % n]
        return total
    if count <= 128:
        r0, r1, r2, r3 = values[first % n], values[(first + 1) % n], values[(first + 2) % n], values[(first + 3) % n]
        r4, r5, r6, r7 = values[(first + 4) % n], values[(first + 5) % n], values[(first + 6) % n], \
            values[(first + 7) % n]
        t = 8
        while t < count - count % 8:
            r0 += values[(first + t) % n]
            r1 += values[(first + t + 1) % n]
            r2 += values[(first + t + 2) % n]
            r3 += values[(first + t + 3) % n]
            r4 += values[(first + t + 4) % n]
            r5 += values[(first + t + 5) % n]
            r6 += values[(first + t + 6) % n]
            r7 += values[(first + t + 7) % n]
            t += 8
        total = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
        while t < count:
            total += values[(first + t) % n]
            t += 1
        return total
    half = count // 2
    half -= half % 8
    return _pairwise_sum(values, first, half) + _pairwise_sum(values, first + half, count - half)


@njit(**HELPER_OPTIONS)
def _way(levels, i):
    """The way round of the first half of the comparison key of point ``i`` (:func:`._jump._symmetric_union`): -1 where
    the levels behind it are larger."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    return -1 if _read_sign(levels, i, 1, i, -1, levels.shape[0]) > 0 else 1


@njit(**JIT_OPTIONS)
def _union_into(P, segment, union, member, levels, reach, dropped):
    """The corners ``union`` (sorted indices into the closed outline ``P``; ``member[a, r]``: corner ``a`` is in run
    ``r``) of a symmetric outline's runs that :func:`._jump._symmetric_union` drops, flagged in ``dropped``: of two
    corners of different runs within ``reach`` px of arc (the sum of the outline's ``segment`` lengths between them,
    numpy's ``np.sum``), the one whose comparison key (:func:`._jump._symmetric_union`) is smaller."""
    compact()  # run time negligible: code optimized for size (_jit.compact)
    m, n = union.shape[0], levels.shape[0]
    for a in range(m):
        dropped[a] = False
    if m < 2:
        return
    for a in range(m):
        c = union[(a + 1) % m]
        # the arc from a corner to the next is at least their chord: where it exceeds the reach (with a margin far
        # above the sums' rounding) there is nothing to do for that corner
        if not np.hypot(P[c, 0] - P[union[a], 0], P[c, 1] - P[union[a], 1]) <= reach * (1.0 + 1e-9):
            continue
        for step in range(1, m):
            b = (a + step) % m
            i, j = union[a], union[b]
            if _pairwise_sum(segment, i, j - i if j > i else n - i + j) > reach:
                break
            shared = False
            for r in range(member.shape[1]):
                shared = shared or (member[a, r] and member[b, r])
            if shared:
                continue
            sign = _key_sign(levels, i, j)
            if sign != 0:
                dropped[a if sign > 0 else b] = True


def starts_of(P, levels):
    """:func:`_starts_into` of the closed outline ``P``: its levels, its canonical starts (a list of ``(point,
    direction)``) and the index of the start whose corners each start takes (a list); ``levels`` ``None``: formed
    by the exact int64 rule, and ``None`` returned where that does not apply."""
    P = np.ascontiguousarray(P, dtype=np.float64)
    n = P.shape[0]
    given = levels is not None
    levels = np.ascontiguousarray(levels, dtype=np.int64) if given else np.empty(n, np.int64)
    point, way, source = np.empty(2 * n, np.int64), np.empty(2 * n, np.int64), np.empty(2 * n, np.int64)
    count = _starts_into(P, levels, given, point, way, source)
    if count < 0:
        return None
    return levels, list(zip(point[:count].tolist(), way[:count].tolist())), source[:count].tolist()


def union_drops(P, union, runs, levels, reach):
    """:func:`_union_into` of the sorted corners ``union`` of the ``runs`` (arrays of indices into the closed
    outline ``P``): which of them to drop (bool)."""
    P = np.ascontiguousarray(P, dtype=np.float64)
    segment = np.hypot(*np.diff(np.vstack([P, P[:1]]), axis=0).T)
    member = np.zeros((len(union), len(runs)), np.bool_)
    for r, run in enumerate(runs):
        member[np.searchsorted(union, run), r] = True
    dropped = np.empty(len(union), np.bool_)
    _union_into(P, segment, np.ascontiguousarray(union, dtype=np.int64), member,
                np.ascontiguousarray(levels, dtype=np.int64), float(reach), dropped)
    return dropped


def resample(P, closed, per_point):
    """:func:`_resample_into` of the points ``P``: the samples, their arc positions, the arc positions of the
    points and of the end (closed: back at the first point), the step; ``None`` where the length overflows."""
    P = np.ascontiguousarray(P, dtype=np.float64)
    n = P.shape[0]
    arc, samples, where, step = np.empty(n + 1), np.empty((per_point * n + 1, 2)), np.empty(per_point * n + 1), \
        np.empty(1)
    size = _resample_into(P, closed, float(per_point), arc, samples, where, step)
    if size < 0:
        return None
    return samples[:size], where[:size], arc[:n + 1 if closed else n], float(step[0])


def corners_of(P, arc, perimeter, closed, taps, samples, where, ladder, operators, settings, flank):
    """:func:`_corners_into` of an outline resampled by :func:`resample` (``taps``: the smoothing kernel, empty
    for none or when ``samples`` are smoothed already; ``ladder``, ``operators`` as :func:`arm_lines` takes them;
    ``settings`` and ``flank`` as :func:`_corners_into` takes them). Returns the corners' samples and input
    points, step 6b's rows of them, the smoothed samples, the arm lines (2, m, 4) and their turn."""
    m = samples.shape[0]
    lengths, centred, weights = _ladder_tables(tuple(int(length) for length in ladder), operators)
    reach = int(max(ladder))
    rows = m + 2 * reach
    chosen, nearest, ends = np.empty(m, np.int64), np.empty(m, np.int64), np.empty((m, 6))
    smoothed, lines, turn = np.empty((m, 2)), np.empty((2, m, 4)), np.empty(m)
    count = _corners_into(P, arc, float(perimeter), bool(closed), taps, samples, where, smoothed, reach, lengths,
                          centred, weights, settings, flank, np.empty((rows, 2)), np.empty((2, m), np.bool_),
                          np.empty((2, m), np.int16), np.empty(rows, np.int8), np.empty((rows + 1, 12)),
                          np.empty(rows + 1, np.int64), np.empty(5), np.empty((rows, 4)), np.empty(rows, np.int16),
                          lines, turn, np.empty(m + flank.shape[0]), chosen, nearest, ends)
    return chosen[:count], nearest[:count], ends[:count], smoothed, lines, turn


_WARM = []


def warm_up():
    """Compile or load the kernels once per process (see :func:`..fitting._kernels.warm_up`): tangent-jump's steps
    on a closed outline (the arm search with them) and the starts and union of a symmetric one (a 4 x 4 square)."""
    if _WARM:
        return

    def operators(length):
        centred = np.arange(length) - (length - 1) / 2
        return centred, centred / np.sum(centred ** 2)
    side = np.arange(4.0) + 0.5
    square = np.concatenate([np.column_stack([side, np.zeros(4)]), np.column_stack([np.full(4, 4.0), side]),
                             np.column_stack([side[::-1], np.full(4, 4.0)]), np.column_stack([np.zeros(4), side[::-1]])])
    levels = starts_of(square, None)[0]
    samples, where, arc, _ = resample(square, True, 4)
    taps = np.array([0.25, 0.5, 0.25])
    settings = np.array([25.0, 25.0, 0.5, 0.3, 2.0, 1.0, 8.0, 6.0, 7.0, 150.0])
    flank = np.array([-3, -2, 2, 3], np.int64)
    for table in (taps, settings, flank):  # read-only, as tangent-jump passes them
        table.flags.writeable = False
    nearest = corners_of(square, arc[:16], arc[16], True, taps, samples, where, [3, 4], operators, settings, flank)[1]
    union = np.unique(np.concatenate([nearest, [0, 4, 8, 12]]))
    union_drops(square, union, [union, union[:1]], levels, 3.0)
    _WARM.append(True)
