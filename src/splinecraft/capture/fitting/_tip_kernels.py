"""Compiled loops of the extrapolated corner tips (:mod:`.tips`, docs/capture.md §12, "Corners of lsq").

Per corner the tips sample each side's window on the contour polyline, fit it, look for the line that separates
the window's ink and paper pixel centres with the largest margin, intersect the two sides and test the crossing
against the pixels: a few dozen small numpy operations per side and per test, run as Python-level calls (about
a third of a trace's calls on a 300-px glyph). These kernels run each of those steps as one compiled pass; the
singular value decomposition of a window (LAPACK, :func:`numpy.linalg.svd`), the least-squares parabola of a
curved window (``numpy.linalg.lstsq``) and the Newton steps of a crossing with a parabola
(``numpy.linalg.solve``) stay in numpy between them (their bits are LAPACK's).

Each kernel performs the floating-point operations of the numpy formulation it replaced, in the same order,
so its results are bit for bit those of that formulation (``tests/test_tip_kernels.py``):

* ``numpy.interp`` (:func:`_interp_point`): the interval by the rightmost knot not above ``x``, its slope
  ``(fp[j+1] - fp[j]) / (xp[j+1] - xp[j])``, ``slope * (x - xp[j]) + fp[j]``, a knot's own value at a knot;
* ``numpy.arange(start, stop, step)`` of floats (:func:`arange_count`, :func:`_arange_value`): ``ceil((stop -
  start) / step)`` values ``start + i * ((start + step) - start)``;
* ``numpy.add.reduce`` along the first axis of an ``(n, 2)`` array: a running sum from 0.0 per column; ``sum``
  of a 1-d array: numpy's pairwise summation (:func:`_pairwise_sum`) added to 0.0;
* the product ``a @ v`` of an ``(n, 2)`` array and a 2-vector (:func:`_row_dot`): ``numpy.matmul`` hands it to
  BLAS ``dgemv``, whose kernel on this machine returns ``fma(a0, v0, a1 * v1)`` per row (one fused
  multiply-add, :func:`_fma`) for two or more rows, while one row (``numpy.dot`` of two 2-vectors, and
  ``matmul`` of a ``(1, 2)`` array) is ``a0 * v0 + a1 * v1``, as is every 1-d ``a @ b`` of 2-vectors here.
"""
from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import njit
from numba.core import cgutils, types
from numba.extending import intrinsic

from .._jit import HELPER_OPTIONS, JIT_OPTIONS, compact, pymax, pymin
from ._kernels import _separating_slope_into

__all__ = ["arange_count", "window_samples", "window_local", "frame_offsets", "separating_line", "side_window",
           "tip_checks", "tip_contradiction_of", "wedge_contradiction_of", "inkward_of", "ray_parities",
           "warm_up", "SIDE_FIELDS"]

_JIT, _HELPER = JIT_OPTIONS, HELPER_OPTIONS

#: The row of a side (:class:`.tips.SideFit`) that the kernels read and write: centre (0, 1), direction (2, 3),
#: normal (4, 5), parabola coefficients (6-8), window length (9), ink side (10), margin (11).
SIDE_FIELDS = 12


@intrinsic
def _fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (LLVM's ``llvm.fma.f64``: the processor's fused multiply-add, else libm's
    ``fma``), as BLAS ``dgemv`` computes a row of :func:`_row_dot`."""
    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        function = cgutils.get_or_insert_function(builder.module, ir.FunctionType(double, [double] * 3),
                                                  "llvm.fma.f64")
        return builder.call(function, [context.cast(builder, value, kind, types.float64)
                                       for value, kind in zip(args, signature.args)])
    return types.float64(a, b, c), codegen


@njit(**_HELPER)
def _row_dot(a0, a1, v0, v1, rows):
    """Row ``(a0, a1)`` of ``a @ v`` for an ``(rows, 2)`` array ``a`` (module docstring)."""
    if rows == 1:
        return a0 * v0 + a1 * v1
    return _fma(a0, v0, a1 * v1)


@njit(**_HELPER)
def _pairwise_sum(values, n):
    """``numpy.sum`` of ``values[:n]`` (1-d, contiguous): numpy's pairwise summation (8 partial sums over blocks of
    up to 128 values, halves above that), added to 0.0 (the reduction's identity)."""
    if n < 8:
        total = 0.0
        for i in range(n):
            total += values[i]
        return 0.0 + total
    return 0.0 + _pairwise_block(values, 0, n)


@njit(**_HELPER)
def _pairwise_block(values, first, n):
    """numpy's ``pairwise_sum`` of ``values[first:first + n]``, ``n >= 8`` (blocks above 128 split iteratively: a
    stack of pending ranges, summed in numpy's recursion order)."""
    # numpy recurses: sum(left half) + sum(right half); the halves are at most log2(n / 128) deep, so the partial
    # sums are combined from a small fixed stack instead
    if n <= 128:
        return _pairwise_leaf(values, first, n)
    half = n // 2
    half -= half % 8
    return _pairwise_half(values, first, half) + _pairwise_half(values, first + half, n - half)


@njit(**_HELPER)
def _pairwise_half(values, first, n):
    if n < 8:
        total = 0.0
        for i in range(n):
            total += values[first + i]
        return total
    if n <= 128:
        return _pairwise_leaf(values, first, n)
    half = n // 2
    half -= half % 8
    return _pairwise_leaf_split(values, first, half) + _pairwise_leaf_split(values, first + half, n - half)


@njit(**_HELPER)
def _pairwise_leaf_split(values, first, n):
    """One more level of numpy's halving (windows of the tips hold at most a few hundred values: blocks of up to
    512 are summed exactly as numpy does; beyond, the rest is summed one block after another)."""
    if n <= 128:
        return _pairwise_leaf(values, first, n) if n >= 8 else _plain_sum(values, first, n)
    half = n // 2
    half -= half % 8
    return _pairwise_leaf(values, first, half) + _pairwise_leaf(values, first + half, n - half)


@njit(**_HELPER)
def _plain_sum(values, first, n):
    total = 0.0
    for i in range(n):
        total += values[first + i]
    return total


@njit(**_HELPER)
def _pairwise_leaf(values, first, n):
    """numpy's unrolled block of 8 partial sums, ``8 <= n <= 128`` values from ``first``."""
    r0, r1, r2, r3 = values[first], values[first + 1], values[first + 2], values[first + 3]
    r4, r5, r6, r7 = values[first + 4], values[first + 5], values[first + 6], values[first + 7]
    i = 8
    last = n - n % 8
    while i < last:
        r0 += values[first + i]
        r1 += values[first + i + 1]
        r2 += values[first + i + 2]
        r3 += values[first + i + 3]
        r4 += values[first + i + 4]
        r5 += values[first + i + 5]
        r6 += values[first + i + 6]
        r7 += values[first + i + 7]
        i += 8
    total = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        total += values[first + i]
        i += 1
    return total


def arange_count(start, stop, step):
    """``numpy.arange(start, stop, step).shape[0]`` of floats (``step > 0``): ``ceil((stop - start) / step)``,
    at least 0."""
    count = np.ceil((stop - start) / step)
    return int(count) if count > 0 else 0


@njit(**_HELPER)
def _arange_value(start, step, i):
    """Value ``i`` of ``numpy.arange(start, ..., step)`` of floats: ``start + i * ((start + step) - start)``
    (numpy's fill of the first two values)."""
    if i == 0:
        return start
    if i == 1:
        return start + step
    return start + i * ((start + step) - start)


@njit(**_HELPER)
def _interp_point(arc, closed, x, out, row):
    """``numpy.interp(x, arc, closed[:, d])`` for both columns ``d`` into ``out[row]`` (``arc`` increasing, the
    left and right values the first and last point's)."""
    n = arc.shape[0]
    if x != x:
        out[row, 0] = out[row, 1] = x
        return
    if x < arc[0]:
        out[row, 0], out[row, 1] = closed[0, 0], closed[0, 1]
        return
    if x > arc[n - 1]:
        out[row, 0], out[row, 1] = closed[n - 1, 0], closed[n - 1, 1]
        return
    lo, hi = 0, n  # the first knot above x, less one: the rightmost knot not above x
    while lo < hi:
        mid = lo + ((hi - lo) >> 1)
        if x >= arc[mid]:
            lo = mid + 1
        else:
            hi = mid
    j = lo - 1
    if j == n - 1 or arc[j] == x:
        out[row, 0], out[row, 1] = closed[j, 0], closed[j, 1]
        return
    for d in range(2):
        slope = (closed[j + 1, d] - closed[j, d]) / (arc[j + 1] - arc[j])
        value = slope * (x - arc[j]) + closed[j, d]
        if value != value:
            value = slope * (x - arc[j + 1]) + closed[j + 1, d]
            if value != value and closed[j, d] == closed[j + 1, d]:
                value = closed[j, d]
        out[row, d] = value


@njit(**_JIT)
def _window_samples_into(arc, closed, perimeter, corner_arc, sign, start, samples):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for i in range(samples.shape[0]):
        _interp_point(arc, closed, (corner_arc + sign * _arange_value(start, 0.5, i)) % perimeter, samples, i)


def window_samples(contour, corner_arc, sign, start, stop):
    """The contour polyline sampled every 0.5 px of arc from ``start`` to ``stop`` px away from ``corner_arc``
    towards ``sign``: ``contour.point_at_arc((corner_arc + sign * numpy.arange(start, stop + 1e-9, 0.5)) %
    contour.perimeter)`` in one pass (:func:`.tips.side_fit`)."""
    samples = np.empty((arange_count(start, stop + 1e-9, 0.5), 2))
    _window_samples_into(contour.arc, contour.closed_points, float(contour.perimeter), float(corner_arc),
                         float(sign), float(start), samples)
    return samples


@njit(**_JIT)
def _window_local_into(samples, count, local, centre):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    _local_of(samples, count, local, centre)


@njit(**_HELPER)
def _local_of(samples, count, local, centre):
    sx, sy = 0.0, 0.0
    for i in range(count):
        sx += samples[i, 0]
        sy += samples[i, 1]
    centre[0], centre[1] = sx / count, sy / count
    for i in range(count):
        local[i, 0], local[i, 1] = samples[i, 0] - centre[0], samples[i, 1] - centre[1]


def window_local(samples, count):
    """The first ``count`` points of ``samples`` less their centre, and the centre: ``numpy.add.reduce(points,
    axis=0) / count`` (a running sum per column) and ``points - centre`` (:func:`.tips._window_fit`)."""
    local, centre = np.empty((count, 2)), np.empty(2)
    _window_local_into(samples, count, local, centre)
    return local, centre


@njit(**_JIT)
def _frame_offsets_into(local, direction, t, y):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    rows = local.shape[0]
    d0, d1 = direction[0], direction[1]
    n0, n1 = -d1, d0
    largest = 0.0
    for i in range(rows):
        t[i] = _row_dot(local[i, 0], local[i, 1], d0, d1, rows)
        y[i] = _row_dot(local[i, 0], local[i, 1], n0, n1, rows)
        if largest == largest and not abs(y[i]) <= largest:
            largest = abs(y[i])
    return largest


def frame_offsets(local, direction):
    """``t, y = local @ direction, local @ normal`` (``normal``: ``direction`` turned a quarter counter-clockwise)
    and ``numpy.abs(y).max()`` (NaN wins)."""
    t, y = np.empty(local.shape[0]), np.empty(local.shape[0])
    largest = _frame_offsets_into(local, direction, t, y)
    return t, y, largest


@njit(**_HELPER)
def _search(values, n, x, right):
    """``numpy.searchsorted(values[:n], x, side)`` (``right``: side ``"right"``)."""
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) >> 1
        if values[mid] <= x if right else values[mid] < x:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(**_HELPER)
def _arc_range(arc, perimeter, corner_arc, sign, start, stop):
    """:func:`.tips._arc_window`'s indices as two runs: ``(a, b, c)``: the indices ``a`` to ``b - 1``, then ``0``
    to ``c - 1`` (``c = 0`` where the window does not wrap)."""
    m = arc.shape[0] - 1  # arc[:-1]: the contour points' own arc lengths
    if sign > 0:
        low, high = corner_arc + start, corner_arc + stop
    else:
        low, high = corner_arc - stop, corner_arc - start
    shift = np.floor(low / perimeter) * perimeter
    low, high = low - shift, high - shift
    first = _search(arc, m, low, False)
    last = _search(arc, m, perimeter if perimeter < high else high, True)
    wrapped = _search(arc, m, high - perimeter, True) if high > perimeter else 0
    return first, pymax(last, first), wrapped


@njit(**_HELPER)
def _separate(ink, paper, ink_count, paper_count, frame, slopes, step, rounds, t_ink, y_ink, t_paper, y_paper,
              grid, slope_out, out):
    """:func:`.tips._separating_line` of the first ``ink_count`` rows of ``ink`` and ``paper_count`` of ``paper``
    in the frame of the side row ``frame``: writes the separating side into ``out`` and returns True, or False
    where no line separates them."""
    c0, c1, d0, d1, n0, n1 = frame[0], frame[1], frame[2], frame[3], frame[4], frame[5]
    for i in range(ink_count):
        x, y = ink[i, 0] - c0, ink[i, 1] - c1
        t_ink[i], y_ink[i] = _row_dot(x, y, d0, d1, ink_count), _row_dot(x, y, n0, n1, ink_count)
    for i in range(paper_count):
        x, y = paper[i, 0] - c0, paper[i, 1] - c1
        t_paper[i], y_paper[i] = _row_dot(x, y, d0, d1, paper_count), _row_dot(x, y, n0, n1, paper_count)
    sign = 1.0 if (_pairwise_sum(y_ink, ink_count) / ink_count >=
                   _pairwise_sum(y_paper, paper_count) / paper_count) else -1.0
    for i in range(ink_count):
        y_ink[i] = sign * y_ink[i]
    for i in range(paper_count):
        y_paper[i] = sign * y_paper[i]
    _separating_slope_into(t_ink[:ink_count], y_ink[:ink_count], t_paper[:paper_count], y_paper[:paper_count],
                           slopes, step, rounds, grid, slope_out)
    slope = slope_out[0]
    above, below = np.inf, -np.inf  # numpy.min and numpy.max: NaN wins
    for i in range(ink_count):
        value = y_ink[i] - slope * t_ink[i]
        if value < above or value != value:
            above = value
            if value != value:
                break
    for i in range(paper_count):
        value = y_paper[i] - slope * t_paper[i]
        if value > below or value != value:
            below = value
            if value != value:
                break
    margin = 0.5 * (above - below)
    if margin <= 0.0:
        return False
    offset = sign * 0.5 * (above + below)
    turn = sign * slope
    e0, e1 = d0 + turn * n0, d1 + turn * n1
    length = np.hypot(e0, e1)
    e0, e1 = e0 / length, e1 / length
    out[0], out[1] = c0 + offset * n0, c1 + offset * n1
    out[2], out[3], out[4], out[5] = e0, e1, -e1, e0
    out[6] = out[7] = out[8] = 0.0
    out[9] = frame[9]
    out[10] = sign
    out[11] = margin / np.hypot(1.0, slope)
    return True


@njit(**_JIT)
def _separating_into(ink, paper, frame, slopes, step, rounds, t_ink, y_ink, t_paper, y_paper, grid, slope_out, out):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    return _separate(ink, paper, ink.shape[0], paper.shape[0], frame, slopes, step, rounds, t_ink, y_ink, t_paper,
                     y_paper, grid, slope_out, out)


def separating_line(ink, paper, frame, slopes, step, rounds):
    """:func:`.tips._separating_line` in one pass: the side row (:data:`SIDE_FIELDS`) of the line that separates
    ``ink`` from ``paper`` (each ``(k, 2)``, ``k >= 1``) with the largest margin in the frame of the side row
    ``frame``, or None."""
    ink, paper = np.ascontiguousarray(ink, float), np.ascontiguousarray(paper, float)
    k, q = ink.shape[0], paper.shape[0]
    out = np.empty(SIDE_FIELDS)
    found = _separating_into(ink, paper, frame, slopes, float(step), int(rounds), np.empty(k), np.empty(k),
                             np.empty(q), np.empty(q), np.empty(slopes.shape[0]), np.empty(1), out)
    return out if found else None


@njit(**_JIT)
def _side_into(arc, perimeter, corner_arc, sign, start, stop, count, local, centre, direction, length,
               coefficients, curved, ink_all, paper_all, slopes, step, rounds, t, y, ink, paper, t_ink, y_ink,
               t_paper, y_paper, grid, slope_out, out):
    """One window of :func:`.tips.side_fit`: with ``direction`` (the window's first right singular vector, numpy's)
    the line frame and its offsets; 2 where they exceed the straight residual (``t`` and ``y`` hold them for the
    parabola, fitted in numpy, then this kernel is called again with ``curved`` and its ``coefficients``); else
    the side into ``out``: 1 for a separating line, 0 for the fit itself (its ink side set where the pixel pairs
    ``ink_all`` / ``paper_all`` have rows)."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    d0, d1 = direction[0], direction[1]
    if not curved:
        largest = 0.0
        for i in range(count):
            t[i] = _row_dot(local[i, 0], local[i, 1], d0, d1, count)
            y[i] = _row_dot(local[i, 0], local[i, 1], -d1, d0, count)
            if largest == largest and not abs(y[i]) <= largest:
                largest = abs(y[i])
        if not largest <= 0.8:
            return 2
    out[0], out[1], out[2], out[3], out[4], out[5] = centre[0], centre[1], d0, d1, -d1, d0
    out[6], out[7], out[8] = coefficients[0], coefficients[1], coefficients[2]
    out[9], out[10], out[11] = length, 0.0, 0.0
    if ink_all.shape[0] == 0:
        return 0
    first, last, wrapped = _arc_range(arc, perimeter, corner_arc, sign, start, stop)
    k = 0
    for i in range(first, last):
        ink[k, 0], ink[k, 1], paper[k, 0], paper[k, 1] = ink_all[i, 0], ink_all[i, 1], paper_all[i, 0], paper_all[i, 1]
        k += 1
    for i in range(wrapped):
        ink[k, 0], ink[k, 1], paper[k, 0], paper[k, 1] = ink_all[i, 0], ink_all[i, 1], paper_all[i, 0], paper_all[i, 1]
        k += 1
    if k < 4:
        return 0
    if not curved and _separate(ink, paper, k, k, out, slopes, step, rounds, t_ink, y_ink, t_paper, y_paper, grid,
                                slope_out, out):
        return 1
    n0, n1 = out[4], out[5]
    for i in range(k):  # (ink - paper) @ normal, then its mean
        t_ink[i] = _row_dot(ink[i, 0] - paper[i, 0], ink[i, 1] - paper[i, 1], n0, n1, k)
    out[10] = 1.0 if _pairwise_sum(t_ink, k) / k >= 0 else -1.0
    return 0


@njit(**_HELPER)
def _inkward(side, x, y, rows):
    """:meth:`.tips.SideFit.inkward` of the point ``(x, y)``, one of ``rows`` points."""
    l0, l1 = x - side[0], y - side[1]
    if side[6] == 0.0 and side[7] == 0.0 and side[8] == 0.0:
        return side[10] * _row_dot(l0, l1, side[4], side[5], rows)
    t, across = _row_dot(l0, l1, side[2], side[3], rows), _row_dot(l0, l1, side[4], side[5], rows)
    return side[10] * (across - (side[6] + t * (side[7] + t * side[8])))


@njit(**_HELPER)
def _parity(cracks, x, y):
    """:func:`.tips.ray_parity` of the point ``(x, y)``: the parity of the horizontal cracks of its column above
    it (``cracks`` sorted by x)."""
    n = cracks.shape[0]
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) >> 1
        if cracks[mid, 0] < x:
            lo = mid + 1
        else:
            hi = mid
    above = 0
    while lo < n and cracks[lo, 0] == x:
        if cracks[lo, 1] < y:
            above += 1
        lo += 1
    return above % 2


@njit(**_JIT)
def _parities_into(cracks, queries, out):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for i in range(queries.shape[0]):
        out[i] = _parity(cracks, queries[i, 0], queries[i, 1])


def ray_parities(cracks, queries):
    """:func:`.tips.ray_parity` in one pass."""
    queries = np.ascontiguousarray(queries, float)
    out = np.empty(queries.shape[0], np.int64)
    _parities_into(np.ascontiguousarray(cracks, float), queries, out)
    return out


@njit(**_HELPER)
def _tip_depth(arc, perimeter, corner_arc, zone, first, second, ink_all, paper_all, convex):
    """:func:`.tips.tip_contradiction`: the largest depth of an ink centre outside the wedge or a paper centre
    inside it, of the pixel pairs within ``zone`` px of arc of the corner."""
    a0, b0, c0 = _arc_range(arc, perimeter, corner_arc, -1.0, 0.0, zone)
    a1, b1, c1 = _arc_range(arc, perimeter, corner_arc, 1.0, 0.0, zone)
    rows = (b0 - a0) + c0 + (b1 - a1) + c1
    worst_ink, worst_paper = -np.inf, -np.inf
    for run in range(4):
        lo, hi = (a0, b0) if run == 0 else (0, c0) if run == 1 else (a1, b1) if run == 2 else (0, c1)
        for i in range(lo, hi):
            for kind in range(2):
                x, y = (ink_all[i, 0], ink_all[i, 1]) if kind == 0 else (paper_all[i, 0], paper_all[i, 1])
                u, v = _inkward(first, x, y, rows), _inkward(second, x, y, rows)
                # numpy.minimum (convex) or numpy.maximum: NaN wins
                if u != u or v != v:
                    depth = u + v
                elif convex:
                    depth = u if u <= v else v
                else:
                    depth = u if u >= v else v
                value = -depth if kind == 0 else depth
                if kind == 0:
                    if value > worst_ink or value != value:
                        worst_ink = value if worst_ink == worst_ink else worst_ink
                else:
                    if value > worst_paper or value != value:
                        worst_paper = value if worst_paper == worst_paper else worst_paper
    return worst_paper if worst_paper > worst_ink else worst_ink


@njit(**_HELPER)
def _wedge_depth(cracks, ink_parity, tip0, tip1, ends, first, second, convex):
    """:func:`.tips.wedge_contradiction`: the deepest pixel centre of the wrong kind inside the triangle of the
    tip and the window starts ``ends`` (``-inf``: none)."""
    p0 = (tip0, ends[0, 0], ends[1, 0])
    p1 = (tip1, ends[0, 1], ends[1, 1])
    low0 = np.floor(pymin(pymin(tip0, ends[0, 0]), ends[1, 0]))
    low1 = np.floor(pymin(pymin(tip1, ends[0, 1]), ends[1, 1]))
    high0 = np.ceil(pymax(pymax(tip0, ends[0, 0]), ends[1, 0]))
    high1 = np.ceil(pymax(pymax(tip1, ends[0, 1]), ends[1, 1]))
    columns, rows = arange_count_kernel(low0, high0), arange_count_kernel(low1, high1)
    # edge k from corner k to corner k + 1, and on which side of it corner k + 2 lies
    e0s = (p0[1] - p0[0], p0[2] - p0[1], p0[0] - p0[2])
    e1s = (p1[1] - p1[0], p1[2] - p1[1], p1[0] - p1[2])
    sides = (e0s[0] * (p1[2] - p1[0]) - e1s[0] * (p0[2] - p0[0]),
             e0s[1] * (p1[0] - p1[1]) - e1s[1] * (p0[0] - p0[1]),
             e0s[2] * (p1[1] - p1[2]) - e1s[2] * (p0[1] - p0[2]))
    inside_count = 0
    for pass_ in range(2):  # the count first: one centre inside is one row of numpy.matmul (module docstring)
        worst = -np.inf
        found = False
        for ix in range(columns):
            cx = _arange_value(low0, 1.0, ix) + 0.5
            for iy in range(rows):
                cy = _arange_value(low1, 1.0, iy) + 0.5
                inside = True
                for k in range(3):
                    if not (e0s[k] * (cy - p1[k]) - e1s[k] * (cx - p0[k])) * sides[k] > 0.0:
                        inside = False
                        break
                if not inside:
                    continue
                if pass_ == 0:
                    inside_count += 1
                    continue
                sign = 1.0 if convex else -1.0
                u = sign * _inkward(first, cx, cy, inside_count) - first[11]
                v = sign * _inkward(second, cx, cy, inside_count) - second[11]
                depth = u + v if (u != u or v != v) else (u if u <= v else v)
                ink = _parity(cracks, cx, cy) == ink_parity
                if (not ink if convex else ink) and depth > 0.0:
                    if not found or depth > worst:
                        worst = depth
                    found = True
        if inside_count == 0:
            return -np.inf
    return worst


@njit(**_HELPER)
def arange_count_kernel(start, stop):
    """``numpy.arange(start, stop).shape[0]`` of floats with step 1."""
    count = np.ceil(stop - start)
    return np.int64(count) if count > 0 else np.int64(0)


@njit(**_JIT)
def _tip_into(points, corner, arc, closed, perimeter, corner_arc, start, first, second, windows, crossing,
              has_crossing, min_cross, ink_all, paper_all, cracks, parity, limits, out):
    """:func:`.tips._tip` after the crossing: the crossing itself where both sides are lines (``has_crossing``:
    ``crossing`` holds the parabolas' one), the opening of the sides there, the bounds and the two consistency
    tests. Writes the tip, the opening and the window starts into ``out`` (point 0-1, opening 2, ends 3-6) and
    returns True where the crossing passes. ``limits``: reach per side (``REACH_PER_SIDE``), ``BEHIND``, the
    contradiction limit, ``TIP_ZONE``, ``MAX_TIP_REACH``; ``windows``: the side windows that bound the reach."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    if has_crossing:
        x, y = crossing[0], crossing[1]
    else:
        d0, d1, e0, e1 = first[2], first[3], second[2], second[3]
        cross = d0 * e1 - d1 * e0
        if abs(cross) < min_cross:
            return False
        q0, q1 = second[0] - first[0], second[1] - first[1]
        along = (q0 * e1 - q1 * e0) / cross
        x, y = first[0] + along * d0, first[1] + along * d1
    if not (np.isfinite(x) and np.isfinite(y)):
        return False
    c0, c1 = points[corner, 0], points[corner, 1]
    ends = out[3:7].reshape((2, 2))
    _interp_point(arc, closed, (corner_arc + -start) % perimeter, ends, 0)
    _interp_point(arc, closed, (corner_arc + start) % perimeter, ends, 1)
    # the sides' tangents at the crossing, pointing away from it
    a0, a1, b0, b1 = 0.0, 0.0, 0.0, 0.0
    for k in range(2):
        side = first if k == 0 else second
        t = (x - side[0]) * side[2] + (y - side[1]) * side[3]
        turn = side[7] + 2.0 * side[8] * t
        u0, u1 = side[2] + turn * side[4], side[3] + turn * side[5]
        towards = (side[0] - x) * u0 + (side[1] - y) * u1
        sign = np.sign(towards)
        length = np.hypot(u0, u1)
        u0, u1 = u0 * sign / length, u1 * sign / length
        if k == 0:
            a0, a1 = u0, u1
        else:
            b0, b1 = u0, u1
    cosine = a0 * b0 + a1 * b1
    if cosine != cosine:
        opening = cosine
    else:
        opening = np.arccos(cosine if -1.0 <= cosine <= 1.0 else (-1.0 if cosine < -1.0 else 1.0))
    # tip_reach(opening): numpy.maximum and numpy.minimum (NaN wins), then min with the windows' bound
    half = np.sin(0.5 * opening)
    reach = np.sqrt(0.5) / (half if (half >= 1e-6 or half != half) else 1e-6) + 0.5
    reach = reach if (reach <= limits[4] or reach != reach) else limits[4]
    shortest = windows[0]
    for i in range(1, windows.shape[0]):
        shortest = pymin(shortest, windows[i])
    reach = pymin(reach, limits[0] * shortest)
    if np.hypot(x - c0, y - c1) > reach:
        return False
    o0 = c0 - 0.5 * (ends[0, 0] + ends[1, 0])
    o1 = c1 - 0.5 * (ends[0, 1] + ends[1, 1])
    if o0 * (x - c0) + o1 * (y - c1) < -limits[1] * np.hypot(o0, o1):
        return False
    if ink_all.shape[0] and first[10] != 0.0 and second[10] != 0.0:
        convex = _inkward(first, second[0], second[1], 1) > 0
        if _tip_depth(arc, perimeter, corner_arc, start + limits[3], first, second, ink_all, paper_all,
                      convex) > limits[2]:
            return False
        if _wedge_depth(cracks, parity, x, y, ends, first, second, convex) > limits[2]:
            return False
    out[0], out[1], out[2] = x, y, opening
    return True


def side_window(contour, corner_arc, sign, start, stop, samples, count, ink, paper, parabola, slopes, step, rounds):
    """One window of :func:`.tips.side_fit` (the first ``count`` of ``samples``): the row of its side
    (:data:`SIDE_FIELDS`), or None where neither a line nor a ``parabola`` (``parabola(t, y)``: the coefficients
    or None, numpy's least squares) fits. The centre and the offsets in one pass each, the frame's direction
    numpy's singular value decomposition (LAPACK) between them; with pixel pairs (``ink``, ``paper``: rows per
    contour point, else empty) a straight side is the separating line where there is one."""
    local, centre = window_local(samples, count)
    direction = np.linalg.svd(local, full_matrices=False)[2][0]
    k = ink.shape[0]
    t, y, out = np.empty(count), np.empty(count), np.empty(SIDE_FIELDS)
    window_ink, window_paper, scratch = np.empty((k, 2)), np.empty((k, 2)), np.empty((4, k))
    grid, slope = np.empty(slopes.shape[0]), np.empty(1)
    arguments = (contour.arc, float(contour.perimeter), float(corner_arc), float(sign), float(start), float(stop),
                 count, local, centre, direction, float(stop - start))
    rest = (ink, paper, slopes, float(step), int(rounds), t, y, window_ink, window_paper, scratch[0], scratch[1],
            scratch[2], scratch[3], grid, slope, out)
    if _side_into(*arguments, _NO_COEFFICIENTS, False, *rest) == 2:
        coefficients = parabola(t, y)
        if coefficients is None:
            return None
        _side_into(*arguments, np.ascontiguousarray(coefficients, float), True, *rest)
    return out


_NO_COEFFICIENTS = np.zeros(3)


@njit(**_JIT)
def _inkward_into(side, points, out):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    rows = points.shape[0]
    for i in range(rows):
        out[i] = _inkward(side, points[i, 0], points[i, 1], rows)


def inkward_of(side, points):
    """:meth:`.tips.SideFit.inkward` of the side row ``side`` at ``points`` (k, 2)."""
    points = np.ascontiguousarray(points, float)
    out = np.empty(points.shape[0])
    _inkward_into(side, points, out)
    return out


@njit(**_JIT)
def _tip_depth_into(arc, perimeter, corner_arc, zone, first, second, ink_all, paper_all, convex):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    return _tip_depth(arc, perimeter, corner_arc, zone, first, second, ink_all, paper_all, convex)


def tip_contradiction_of(contour, corner_arc, zone, first, second, ink, paper, convex):
    """:func:`.tips.tip_contradiction` of the side rows ``first`` and ``second`` in one pass."""
    return float(_tip_depth_into(contour.arc, float(contour.perimeter), float(corner_arc), float(zone), first, second,
                                 ink, paper, bool(convex)))


@njit(**_JIT)
def _wedge_depth_into(cracks, parity, tip, ends, first, second, convex):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    return _wedge_depth(cracks, parity, tip[0], tip[1], ends, first, second, convex)


def wedge_contradiction_of(cracks, parity, tip, ends, first, second, convex):
    """:func:`.tips.wedge_contradiction` of the side rows ``first`` and ``second`` in one pass."""
    return float(_wedge_depth_into(np.ascontiguousarray(cracks, float), int(parity), np.ascontiguousarray(tip, float),
                                   np.ascontiguousarray(ends, float), first, second, bool(convex)))


def tip_checks(contour, corner, corner_arc, start, first, second, windows, crossing, ink, paper, cracks, parity,
               min_cross, limits):
    """:func:`.tips._tip` in one pass (``crossing``: the crossing of sides with a parabola, numpy's, else None):
    ``(point, opening, ends)`` or None."""
    out = np.empty(7)
    given = crossing is not None
    if not _tip_into(contour.points, int(corner), contour.arc, contour.closed_points, float(contour.perimeter),
                     float(corner_arc), float(start), first, second, windows,
                     np.ascontiguousarray(crossing, float) if given else _NO_COEFFICIENTS, given, float(min_cross),
                     ink, paper, cracks, int(parity), limits, out):
        return None
    return out[0:2], out[2], out[3:7].reshape(2, 2)


def warm_up():
    """Compile (empty cache) or load the kernels of the extrapolated tips on tiny inputs (a square's crack
    outline)."""
    from types import SimpleNamespace

    points = np.array([[0.5, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5]])
    closed = np.vstack([points, points[:1]])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    contour = SimpleNamespace(points=points, closed_points=closed, arc=arc, perimeter=arc[-1])
    samples = window_samples(contour, 0.5, 1, 0.0, 1.0)
    slopes = np.linspace(-0.25, 0.25, 17)
    ink, paper = points + 0.1, points - 0.1
    row = side_window(contour, 0.5, 1, 0.0, 1.0, samples, samples.shape[0], ink, paper, lambda t, y: None, slopes,
                      0.03, 2)
    if row is None:
        row = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0])
    frame_offsets(samples, row[2:4])
    separating_line(ink, paper, row, slopes, 0.03, 2)
    inkward_of(row, points)
    ray_parities(points, points)
    second = np.array([0.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0])
    tip_checks(contour, 0, 0.5, 0.5, row, second, np.ones(2), None, ink, paper, points, 0, 0.1,
               np.array([0.25, 1.0, 0.1, 1.0, 5.0]))
    tip_contradiction_of(contour, 0.5, 1.0, row, second, ink, paper, True)
    wedge_contradiction_of(points, 0, np.zeros(2), np.ones((2, 2)), row, second, True)
