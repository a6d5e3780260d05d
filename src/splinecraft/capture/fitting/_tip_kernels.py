"""Compiled loops of the extrapolated corner tips (:mod:`.tips`, docs/capture.md §12, "Corners of lsq").

Per corner the tips sample each side's window on the contour polyline, fit it, look for the line that separates
the window's ink and paper pixel centres with the largest margin, intersect the two sides and test the crossing
against the pixels: a few dozen small numpy operations per side and per test, run as Python-level calls (about
a third of a trace's calls on a 300-px glyph). These kernels run each of those steps as one compiled pass; the
singular value decomposition of a window (LAPACK, :func:`numpy.linalg.svd`), the least-squares parabola of a
curved window (``numpy.linalg.lstsq``) and the Newton steps of a crossing with a parabola
(``numpy.linalg.solve``) stay in numpy between them (their bits are LAPACK's). The first window of every side
of an outline runs in one batch (:func:`window_sides`: two compiled passes around the windows' decompositions,
stacked by window length), and so do the crossings of corners between two lines (:func:`line_tip_checks`).

Each kernel performs the floating-point operations of the numpy formulation it replaced, in the same order,
so its results are bit for bit those of that formulation (``tests/test_tip_kernels.py``):

* ``numpy.interp`` (:func:`_interp_point`): the interval by the rightmost knot not above ``x``, its slope
  ``(fp[j+1] - fp[j]) / (xp[j+1] - xp[j])``, ``slope * (x - xp[j]) + fp[j]``, a knot's own value at a knot;
* ``numpy.arange(start, stop, step)`` of floats (:func:`arange_count`, :func:`_window_into`): ``ceil((stop -
  start) / step)`` values ``start + i * ((start + step) - start)``;
* ``numpy.add.reduce`` along the first axis of an ``(n, 2)`` array: a running sum from 0.0 per column; ``sum``
  of a 1-d array: numpy's pairwise summation (:func:`_pairwise_sum`) added to 0.0;
* the product ``a @ v`` of an ``(n, 2)`` array and a 2-vector: ``numpy.matmul`` hands it to
  BLAS ``dgemv``, whose kernel on this machine returns ``fma(a0, v0, a1 * v1)`` per row (one fused
  multiply-add, :func:`_fma`) for two or more rows, while one row (``numpy.dot`` of two 2-vectors, and
  ``matmul`` of a ``(1, 2)`` array) is ``a0 * v0 + a1 * v1``, as is every 1-d ``a @ b`` of 2-vectors here.
  (OpenBLAS picks its kernel by processor: where its ``dgemv`` does not fuse, traces differ from the numpy
  formulation's there in the last bits, as they already differ between such machines.)

Few, large kernels, each compiled once (``compact``): the side of a window (:func:`_side_into`, which also
serves the separating line of given pixel centres), the tip tests (:func:`_tip_into`, which also serves the
two contradiction measures on their own), the window's samples and centre, the offsets of points from a side,
the parity of rays. numpy's scalar functions are called through :mod:`math` (the same libm functions, typed
faster).
"""
from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit
from numba.core import cgutils, types
from numba.extending import intrinsic

from .. import _interpreted
from .._jit import HELPER_OPTIONS, JIT_OPTIONS, compact, pymax, pymin
from ._kernels import _separating_slope_into
from ._linalg import svd_direction, svd_directions

__all__ = ["SIDE_FIELDS", "arange_count", "window_samples", "window_local", "side_window", "separating_line",
           "window_sides", "curved_side", "frame_offsets", "inkward_of", "ray_parities", "tip_checks",
           "line_tip_checks", "tip_contradiction_of", "wedge_contradiction_of", "warm_up"]

_JIT, _HELPER = JIT_OPTIONS, HELPER_OPTIONS
#: Helpers called from several places of a kernel: compiled once, called (not inlined).
_CALLED = dict(HELPER_OPTIONS, forceinline=False)

#: The row of a side (:class:`.tips.SideFit`) that the kernels read and write: centre (0, 1), direction (2, 3),
#: normal (4, 5), parabola coefficients (6-8), window length (9), ink side (10), margin (11).
SIDE_FIELDS = 12
# Constant arguments of helpers as typed values, not literals: numba compiles a helper anew for each literal
_ZERO, _ONE, _LEFT, _RIGHT = np.int64(0), np.int64(1), np.bool_(False), np.bool_(True)
#: :data:`.tips.STRAIGHT_RESIDUAL` (``tests/test_tip_kernels.py`` pins them equal; :mod:`.tips` imports this module).
_STRAIGHT = 0.8


@intrinsic
def _fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (LLVM's ``llvm.fma.f64``: the processor's fused multiply-add, else libm's
    ``fma``), as BLAS ``dgemv`` computes a row of ``a @ v`` (module docstring)."""
    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        function = cgutils.get_or_insert_function(builder.module, ir.FunctionType(double, [double] * 3),
                                                  "llvm.fma.f64")
        return builder.call(function, [context.cast(builder, value, kind, types.float64)
                                       for value, kind in zip(args, signature.args)])
    return types.float64(a, b, c), codegen


_interpreted.stand_in(_fma, _interpreted.fused_multiply_add)  # the kernels interpreted (_interpreted)


@njit(**_CALLED)
def _pairwise_sum(values, n):
    """``numpy.sum`` of ``values[:n]`` (1-d, contiguous): numpy's pairwise summation, added to 0.0 (the
    reduction's identity). Per block of up to 128 values one running sum below 8 values, else 8 partial sums
    over the runs of 8 combined pairwise, then the rest one by one; above 128 values the sum of the two halves
    (split at a multiple of 8), each one block: numpy's up to 240 values (where neither half exceeds 128; numpy
    halves a longer half again). A side window holds at most about 70 pixel centres (48 px of arc)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    half = n
    if n > 128:
        half = n // 2
        half -= half % 8
    total = 0.0
    for block in range(1 if n <= 128 else 2):
        first, m = (0, half) if block == 0 else (half, n - half)
        if m < 8:
            part = 0.0
            for i in range(m):
                part += values[first + i]
        else:
            r0, r1, r2, r3 = values[first], values[first + 1], values[first + 2], values[first + 3]
            r4, r5, r6, r7 = values[first + 4], values[first + 5], values[first + 6], values[first + 7]
            i = 8
            last = m - m % 8
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
            part = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
            while i < m:
                part += values[first + i]
                i += 1
        total = part if block == 0 else total + part
    return 0.0 + total


def arange_count(start, stop, step):
    """``numpy.arange(start, stop, step).shape[0]`` of floats (``step > 0``): ``ceil((stop - start) / step)``,
    at least 0."""
    count = math.ceil((stop - start) / step)
    return count if count > 0 else 0


@njit(**_CALLED)
def _interp_point(arc, closed, x, out, row):
    """``numpy.interp(x, arc, closed[:, d])`` for both columns ``d`` into ``out[row]`` (``arc`` increasing, the
    values left and right of it the first and last point's)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
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
    j = _search(arc, n, x, _RIGHT) - 1  # the rightmost knot not above x
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


@njit(**_HELPER)
def _search(values, n, x, right):
    """``numpy.searchsorted(values[:n], x, side)`` (``right``: side ``"right"``)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) >> 1
        if values[mid] <= x if right else values[mid] < x:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(**_JIT)
def _window_into(arc, closed, perimeter, corner_arc, sign, start, samples, fill, count, local, centre):
    """With ``fill``: the contour points every 0.5 px of arc from ``start`` px towards ``sign`` from
    ``corner_arc`` into ``samples`` (``point_at_arc((corner_arc + sign * numpy.arange(start, ..., 0.5)) %
    perimeter)``); then the centre of the first ``count`` (``numpy.add.reduce(points, axis=0) / count``: a
    running sum per column) and the points less it into ``local``."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    if fill:
        step = (start + 0.5) - start  # numpy.arange's values: start, start + 0.5, then start + i * step
        for i in range(samples.shape[0]):
            offset = start if i == 0 else start + 0.5 if i == 1 else start + i * step
            _interp_point(arc, closed, (corner_arc + sign * offset) % perimeter, samples, i)
    sx, sy = 0.0, 0.0
    for i in range(count):
        sx += samples[i, 0]
        sy += samples[i, 1]
    centre[0], centre[1] = sx / count, sy / count
    for i in range(count):
        local[i, 0], local[i, 1] = samples[i, 0] - centre[0], samples[i, 1] - centre[1]


def window_samples(contour, corner_arc, sign, start, stop):
    """The contour polyline sampled every 0.5 px of arc from ``start`` to ``stop`` px away from ``corner_arc``
    towards ``sign``: ``contour.point_at_arc((corner_arc + sign * numpy.arange(start, stop + 1e-9, 0.5)) %
    contour.perimeter)``, with the centre of all of them and the samples less it (:func:`.tips.side_fit`)."""
    samples = np.empty((arange_count(start, stop + 1e-9, 0.5), 2))
    local, centre = np.empty(samples.shape), np.empty(2)
    _window_into(contour.arc, contour.closed_points, float(contour.perimeter), float(corner_arc), float(sign),
                 float(start), samples, True, samples.shape[0], local, centre)
    return samples, local, centre


def window_local(samples, count):
    """The first ``count`` points of ``samples`` less their centre, and the centre (:func:`.tips._window_fit`)."""
    local, centre = np.empty((count, 2)), np.empty(2)
    _window_into(_NO_FLOATS, samples, 1.0, 0.0, 0.0, 0.0, samples, False, count, local, centre)
    return local, centre


@njit(**_HELPER)
def _arc_range(arc, perimeter, corner_arc, sign, start, stop):
    """The indices of ``tips``' arc window (the contour points ``start`` to ``stop`` px of arc from ``corner_arc``
    towards ``sign``) as two runs ``(a, b, c)``: ``a`` to ``b - 1``, then ``0`` to ``c - 1`` (``c = 0`` where the
    window does not wrap round)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    m = arc.shape[0] - 1  # arc[:-1]: the contour points' own arc lengths
    if sign > 0:
        low, high = corner_arc + start, corner_arc + stop
    else:
        low, high = corner_arc - stop, corner_arc - start
    shift = math.floor(low / perimeter) * perimeter
    low, high = low - shift, high - shift
    first = _search(arc, m, low, _LEFT)
    last = _search(arc, m, perimeter if perimeter < high else high, _RIGHT)
    wrapped = _search(arc, m, high - perimeter, _RIGHT) if high > perimeter else 0
    return first, pymax(last, first), wrapped


@njit(**_CALLED)
def _separate(ink, paper, ink_count, paper_count, frame, slopes, step, rounds, t_ink, y_ink, t_paper, y_paper,
              grid, slope_out, out):
    """:func:`.tips._separating_line` of the first ``ink_count`` rows of ``ink`` and ``paper_count`` of ``paper``
    in the frame of the side row ``frame``: the separating side into ``out`` (True), or False where no line
    separates them. The offsets ``y - c1 t`` of a slope ``c1``: ``numpy.min`` and ``numpy.max`` (NaN wins)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    c0, c1, d0, d1, n0, n1, length = frame[0], frame[1], frame[2], frame[3], frame[4], frame[5], frame[9]
    for i in range(ink_count):
        x, y = ink[i, 0] - c0, ink[i, 1] - c1
        if ink_count == 1:  # a @ v (module docstring)
            t_ink[i], y_ink[i] = x * d0 + y * d1, x * n0 + y * n1
        else:
            t_ink[i], y_ink[i] = _fma(x, d0, y * d1), _fma(x, n0, y * n1)
    for i in range(paper_count):
        x, y = paper[i, 0] - c0, paper[i, 1] - c1
        if paper_count == 1:
            t_paper[i], y_paper[i] = x * d0 + y * d1, x * n0 + y * n1
        else:
            t_paper[i], y_paper[i] = _fma(x, d0, y * d1), _fma(x, n0, y * n1)
    sign = 1.0 if (_pairwise_sum(y_ink, ink_count) / ink_count >=
                   _pairwise_sum(y_paper, paper_count) / paper_count) else -1.0
    for i in range(ink_count):
        y_ink[i] = sign * y_ink[i]
    for i in range(paper_count):
        y_paper[i] = sign * y_paper[i]
    _separating_slope_into(t_ink[:ink_count], y_ink[:ink_count], t_paper[:paper_count], y_paper[:paper_count],
                           slopes, step, rounds, grid, slope_out)
    slope = slope_out[0]
    above, below = math.inf, -math.inf
    for i in range(ink_count):
        value = y_ink[i] - slope * t_ink[i]
        if not value >= above:
            above = value
            if value != value:
                break
    for i in range(paper_count):
        value = y_paper[i] - slope * t_paper[i]
        if not value <= below:
            below = value
            if value != value:
                break
    margin = 0.5 * (above - below)
    if margin <= 0.0:
        return False
    offset = sign * 0.5 * (above + below)
    turn = sign * slope
    e0, e1 = d0 + turn * n0, d1 + turn * n1
    norm = math.hypot(e0, e1)
    e0, e1 = e0 / norm, e1 / norm
    out[0], out[1] = c0 + offset * n0, c1 + offset * n1
    out[2], out[3], out[4], out[5] = e0, e1, -e1, e0
    out[6] = out[7] = out[8] = 0.0
    out[9], out[10], out[11] = length, sign, margin / math.hypot(1.0, slope)
    return True


@njit(**_JIT)
def _side_into(arc, perimeter, corner_arc, sign, start, stop, local, centre, direction, length, coefficients, mode,
               ink_all, paper_all, slopes, step, rounds, t, y, ink, paper, t_ink, y_ink, t_paper, y_paper, grid,
               slope_out, out):
    """A side of :mod:`.tips` into ``out`` (a side row). ``mode`` 0: the window ``local`` (its points less their
    ``centre``) in the frame of ``direction`` (its first right singular vector, numpy's): its offsets ``t`` and
    ``y``, and 2 where they exceed the straight residual (the parabola is fitted in numpy, then this kernel is
    called again in ``mode`` 1 with its ``coefficients``); else the line, and with pixel pairs (``ink_all`` and
    ``paper_all`` per contour point) the separating line of the window's (returns 1) or the line with its ink
    side (returns 0). ``mode`` 1: the parabola with its ink side (0). ``mode`` 3: the separating line of the
    pixel centres ``ink_all`` and ``paper_all`` themselves (1), else 0. ``mode`` 4: the offsets
    (:meth:`.tips.SideFit.inkward`) of the points ``ink_all`` from the side row ``out`` into ``t``."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    if mode == 4:
        rows = ink_all.shape[0]
        for i in range(rows):
            t[i] = _inkward(out, ink_all[i, 0], ink_all[i, 1], rows)
        return 0
    d0, d1 = direction[0], direction[1]
    count = local.shape[0]
    if mode == 0:
        largest = 0.0  # numpy.abs(y).max(): NaN wins
        for i in range(count):
            x, z = local[i, 0], local[i, 1]
            t[i], y[i] = (x * d0 + z * d1, x * -d1 + z * d0) if count == 1 else (_fma(x, d0, z * d1),
                                                                                 _fma(x, -d1, z * d0))
            if largest == largest and not abs(y[i]) <= largest:
                largest = abs(y[i])
        if not largest <= _STRAIGHT:
            return 2
    out[0], out[1], out[2], out[3], out[4], out[5] = centre[0], centre[1], d0, d1, -d1, d0
    out[6], out[7], out[8] = coefficients[0], coefficients[1], coefficients[2]
    out[9], out[10], out[11] = length, 0.0, 0.0
    if mode == 3:
        return 1 if _separate(ink_all, paper_all, ink_all.shape[0], paper_all.shape[0], out, slopes, step, rounds,
                              t_ink, y_ink, t_paper, y_paper, grid, slope_out, out) else 0
    if ink_all.shape[0] == 0:
        return 0
    first, last, wrapped = _arc_range(arc, perimeter, corner_arc, sign, start, stop)
    k = 0
    for r in range(last - first + wrapped):
        i = first + r if r < last - first else r - (last - first)
        ink[k, 0], ink[k, 1] = ink_all[i, 0], ink_all[i, 1]
        paper[k, 0], paper[k, 1] = paper_all[i, 0], paper_all[i, 1]
        k += 1
    if k < 4:
        return 0
    if mode == 0 and _separate(ink, paper, k, k, out, slopes, step, rounds, t_ink, y_ink, t_paper, y_paper, grid,
                               slope_out, out):
        return 1
    n0, n1 = out[4], out[5]
    for i in range(k):  # (ink - paper) @ normal, then its mean
        x, z = ink[i, 0] - paper[i, 0], ink[i, 1] - paper[i, 1]
        t_ink[i] = _fma(x, n0, z * n1)  # k >= 4 rows
    out[10] = 1.0 if _pairwise_sum(t_ink, k) / k >= 0 else -1.0
    return 0


class _Buffers:
    """The arrays one :func:`_side_into` call writes: the side row, the window's offsets and pixel centres, the
    slope search's."""

    def __init__(self, count, rows, slopes):
        self.out, self.t, self.y = np.empty(SIDE_FIELDS), np.empty(count), np.empty(count)
        self.ink, self.paper, scratch = np.empty((rows, 2)), np.empty((rows, 2)), np.empty((4, rows))
        self.scratch = scratch[0], scratch[1], scratch[2], scratch[3]
        self.grid, self.slope = np.empty(slopes.shape[0]), np.empty(1)


def side_window(contour, corner_arc, sign, start, stop, samples, count, local, centre, ink, paper, parabola, slopes,
                step, rounds):
    """One window of :func:`.tips.side_fit` (the first ``count`` of ``samples``; ``local`` and ``centre``: theirs,
    or None): the row of its side (:data:`SIDE_FIELDS`), or None where neither a line nor a ``parabola``
    (``parabola(t, y)``: the coefficients or None, numpy's least squares) fits. The frame's direction is numpy's
    singular value decomposition (LAPACK); with pixel pairs (``ink``, ``paper``: rows per contour point, else
    empty) a straight side is the separating line where there is one."""
    if local is None:
        local, centre = window_local(samples, count)
    direction = svd_direction(local)
    b = _Buffers(count, ink.shape[0], slopes)
    frame = (contour.arc, float(contour.perimeter), float(corner_arc), float(sign), float(start), float(stop), local,
             centre, direction, float(stop - start))
    rest = (ink, paper, slopes, float(step), int(rounds), b.t, b.y, b.ink, b.paper, *b.scratch, b.grid, b.slope,
            b.out)
    if _side_into(*frame, _NO_COEFFICIENTS, 0, *rest) == 2:
        return curved_side(contour, corner_arc, sign, start, stop, local, centre, direction, b.t, b.y, ink, paper,
                           parabola, slopes, step, rounds, b)
    return b.out


def curved_side(contour, corner_arc, sign, start, stop, local, centre, direction, t, y, ink, paper, parabola, slopes,
                step, rounds, buffers=None):
    """:func:`side_window`'s window that is not straight (``t``, ``y``: its frame offsets): the side row of its
    ``parabola`` (``parabola(t, y)``: the coefficients or None) with its ink side, or None where none fits.
    ``buffers``: the window's :class:`_Buffers`, else new ones."""
    coefficients = parabola(t, y)
    if coefficients is None:
        return None
    b = _Buffers(local.shape[0], ink.shape[0], slopes) if buffers is None else buffers
    _side_into(contour.arc, float(contour.perimeter), float(corner_arc), float(sign), float(start), float(stop), local,
               centre, direction, float(stop - start), np.ascontiguousarray(coefficients, float), 1, ink, paper,
               slopes, float(step), int(rounds), b.t, b.y, b.ink, b.paper, *b.scratch, b.grid, b.slope, b.out)
    return b.out


@njit(**_JIT)
def _sides_into(arc, closed, perimeter, corner_arcs, signs, starts, stops, offsets, fill, samples, local, centres,
                directions, coefficients, mode, ink_all, paper_all, slopes, step, rounds, t, y, ink, paper, t_ink,
                y_ink, t_paper, y_paper, grid, slope_out, rows, status):
    """:func:`window_sides` in two passes over its windows (rows ``offsets[r]`` to ``offsets[r + 1]`` of
    ``samples``, ``local``, ``t`` and ``y``): with ``fill`` each window's samples, centre and local points
    (:func:`_window_into`), else each window's side from its ``directions[r]`` (:func:`_side_into` in ``mode`` 0:
    its status into ``status[r]``, its row into ``rows[r]``, its frame offsets into ``t`` and ``y``); the other work
    arrays are :class:`_Buffers`' for the longest window."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for r in range(corner_arcs.shape[0]):
        first, last = offsets[r], offsets[r + 1]
        if fill:
            _window_into(arc, closed, perimeter, corner_arcs[r], signs[r], starts[r], samples[first:last], _RIGHT,
                         last - first, local[first:last], centres[r])
        else:
            status[r] = _side_into(arc, perimeter, corner_arcs[r], signs[r], starts[r], stops[r], local[first:last],
                                   centres[r], directions[r], stops[r] - starts[r], coefficients, mode, ink_all,
                                   paper_all, slopes, step, rounds, t[first:last], y[first:last], ink, paper, t_ink,
                                   y_ink, t_paper, y_paper, grid, slope_out, rows[r])


def window_sides(contour, corner_arcs, signs, starts, stops, ink, paper, slopes, step, rounds):
    """The first window of :func:`.tips.side_fit` for many sides at once: per side (the corner's arc length
    ``corner_arcs[r]``, towards ``signs[r]``, from ``starts[r]`` to ``stops[r]`` px of arc) the row and status of
    :func:`side_window` on its whole window before any parabola: 0 or 1 a line (1: the separating line of the
    window's pixel centres ``ink`` and ``paper``), 2 not straight (the caller fits the parabola,
    :func:`curved_side`). The same operations as one :func:`window_samples` and :func:`side_window` per side, so
    the same bits: the samples and the sides in two compiled passes, and the windows' singular value
    decompositions (LAPACK) stacked by window length, one call per length (:func:`~._linalg.svd_directions`),
    where each side window cost a dozen Python-level calls (BENCHMARKS.md, "Session 34"). Returns a dict:
    ``rows``, ``status``, ``offsets`` (side ``r`` has rows ``offsets[r]`` to ``offsets[r + 1]`` of) ``samples``,
    ``local``, ``t``, ``y`` (its frame offsets), and per side ``centres`` and ``directions``."""
    count = len(corner_arcs)
    corner_arcs, signs = np.asarray(corner_arcs, float), np.asarray(signs, float)
    starts, stops = np.asarray(starts, float), np.asarray(stops, float)
    # arange_count(start, stop + 1e-9, 0.5) of each: the same operations on arrays
    lengths = np.maximum(np.ceil(((stops + 1e-9) - starts) / 0.5), 0.0).astype(np.int64)
    offsets = np.zeros(count + 1, np.int64)
    np.cumsum(lengths, out=offsets[1:])
    samples, local = np.empty((offsets[-1], 2)), np.empty((offsets[-1], 2))
    t, y = np.empty(offsets[-1]), np.empty(offsets[-1])
    centres, directions = np.empty((count, 2)), np.empty((count, 2))
    rows, status = np.empty((count, SIDE_FIELDS)), np.empty(count, np.int64)
    b = _Buffers(0, ink.shape[0], slopes)  # (each window's frame offsets go to its rows of t and y)
    passes = (contour.arc, contour.closed_points, float(contour.perimeter), corner_arcs, signs, starts, stops, offsets)
    rest = (_NO_COEFFICIENTS, 0, ink, paper, slopes, float(step), int(rounds), t, y, b.ink, b.paper,
            *b.scratch, b.grid, b.slope, rows, status)
    _sides_into(*passes, True, samples, local, centres, directions, *rest)
    for length in np.unique(lengths):
        members = np.flatnonzero(lengths == length)
        if members.shape[0] == 1:
            first = offsets[members[0]]
            directions[members[0]] = svd_direction(local[first:first + length])
        else:
            directions[members] = svd_directions(local[offsets[members][:, None] + np.arange(length)])
    _sides_into(*passes, False, samples, local, centres, directions, *rest)
    return {"rows": rows, "status": status, "offsets": offsets, "samples": samples, "local": local, "t": t, "y": y,
            "centres": centres, "directions": directions}


def frame_offsets(local, direction):
    """``t, y = local @ direction, local @ normal`` (``normal``: ``direction`` turned a quarter counter-clockwise)
    and whether ``numpy.abs(y).max()`` is at most the straight residual (0.8 px, :data:`.tips.STRAIGHT_RESIDUAL`)."""
    b = _Buffers(local.shape[0], 0, _NO_FLOATS)
    status = _side_into(_NO_FLOATS, 1.0, 0.0, 1.0, 0.0, 0.0, local, _NO_COEFFICIENTS, direction, 0.0,
                        _NO_COEFFICIENTS, 0, _NO_POINTS, _NO_POINTS, _NO_FLOATS, 0.0, 0, b.t, b.y, b.ink, b.paper,
                        *b.scratch, b.grid, b.slope, b.out)
    return b.t, b.y, status != 2


def separating_line(ink, paper, frame, slopes, step, rounds):
    """:func:`.tips._separating_line` in one pass: the side row (:data:`SIDE_FIELDS`) of the line that separates
    ``ink`` from ``paper`` (each ``(k, 2)``, ``1 <= k <= 240``) with the largest margin in the frame of the side
    row ``frame``, or None."""
    ink, paper = np.ascontiguousarray(ink, float), np.ascontiguousarray(paper, float)
    b = _Buffers(0, max(ink.shape[0], paper.shape[0]), slopes)
    found = _side_into(_NO_FLOATS, 1.0, 0.0, 1.0, 0.0, 0.0, _NO_POINTS, frame[0:2].copy(), frame[2:4].copy(),
                       float(frame[9]), _NO_COEFFICIENTS, 3, ink, paper, slopes, float(step), int(rounds), b.t, b.y,
                       b.ink, b.paper, *b.scratch, b.grid, b.slope, b.out)
    return b.out if found == 1 else None


_NO_FLOATS, _NO_POINTS, _NO_COEFFICIENTS = np.empty(0), np.empty((0, 2)), np.zeros(3)


@njit(**_CALLED)
def _inkward(side, x, y, rows):
    """:meth:`.tips.SideFit.inkward` of the point ``(x, y)``, one of ``rows`` points."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    l0, l1 = x - side[0], y - side[1]
    if rows == 1:  # a @ v (module docstring)
        t, across = l0 * side[2] + l1 * side[3], l0 * side[4] + l1 * side[5]
    else:
        t, across = _fma(l0, side[2], l1 * side[3]), _fma(l0, side[4], l1 * side[5])
    if side[6] == 0.0 and side[7] == 0.0 and side[8] == 0.0:
        return side[10] * across
    return side[10] * (across - (side[6] + t * (side[7] + t * side[8])))


@njit(**_CALLED)
def _parity(cracks, x, y):
    """:func:`.tips.ray_parity` of the point ``(x, y)``: the parity of the horizontal cracks of its column above
    it (``cracks`` sorted by x)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
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
def _parities_into(cracks, points, parities):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for i in range(points.shape[0]):
        parities[i] = _parity(cracks, points[i, 0], points[i, 1])


def inkward_of(side, points):
    """:meth:`.tips.SideFit.inkward` of the side row ``side`` at ``points`` (k, 2), in :func:`_side_into`."""
    points = np.ascontiguousarray(points, float)
    b = _Buffers(points.shape[0], 0, _NO_FLOATS)
    b.out[:] = side
    _side_into(_NO_FLOATS, 1.0, 0.0, 1.0, 0.0, 0.0, _NO_POINTS, _NO_COEFFICIENTS, _NO_COEFFICIENTS, 0.0,
               _NO_COEFFICIENTS, 4, points, _NO_POINTS, _NO_FLOATS, 0.0, 0, b.t, b.y, b.ink, b.paper, *b.scratch, b.grid,
               b.slope, b.out)
    return b.t


def ray_parities(cracks, queries):
    """:func:`.tips.ray_parity` in one pass (not in a trace: compiled on first use)."""
    queries = np.ascontiguousarray(queries, float)
    out = np.empty(queries.shape[0], np.int64)
    _parities_into(np.ascontiguousarray(cracks, float), queries, out)
    return out


_NO_ENDS = np.empty((2, 2))


@njit(**_CALLED)
def _tip_depth(arc, perimeter, corner_arc, zone, first, second, ink_all, paper_all, convex):
    """:func:`.tips.tip_contradiction`: the largest depth of an ink centre outside the wedge or a paper centre
    inside it (``numpy.minimum`` of the two sides' offsets for a ``convex`` wedge, else ``numpy.maximum``; then
    ``max`` of the ink's and the paper's largest), over the pixel pairs within ``zone`` px of arc of the
    corner."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    a0, b0, c0 = _arc_range(arc, perimeter, corner_arc, -1.0, 0.0, zone)
    a1, b1, c1 = _arc_range(arc, perimeter, corner_arc, 1.0, 0.0, zone)
    n0, n1 = b0 - a0, c0
    rows = n0 + n1 + (b1 - a1) + c1
    worst_ink, worst_paper = -math.inf, -math.inf
    for r in range(rows):
        i = a0 + r if r < n0 else r - n0 if r < n0 + n1 else a1 + r - n0 - n1 if r < rows - c1 else r - (rows - c1)
        for kind in range(2):
            points = ink_all if kind == 0 else paper_all
            u = _inkward(first, points[i, 0], points[i, 1], rows)
            v = _inkward(second, points[i, 0], points[i, 1], rows)
            if u != u or v != v:
                depth = u + v
            elif convex:
                depth = u if u <= v else v
            else:
                depth = u if u >= v else v
            if kind == 0:
                if worst_ink == worst_ink and not -depth <= worst_ink:
                    worst_ink = -depth
            elif worst_paper == worst_paper and not depth <= worst_paper:
                worst_paper = depth
    return worst_paper if worst_paper > worst_ink else worst_ink


@njit(**_CALLED)
def _wedge_depth(cracks, ink_parity, tip0, tip1, ends, first, second, convex):
    """:func:`.tips.wedge_contradiction`: the deepest pixel centre of the wrong kind (by its ray parity) inside
    the triangle of the tip and the window starts ``ends``, each side moved inwards by its margin (``-inf``:
    none). Centres by ``numpy.arange`` from the triangle's floor to its ceiling, x-major; a centre is inside
    where it lies strictly on the side of each edge where the opposite corner lies."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    ax, ay, bx, by, cx, cy = tip0, tip1, ends[0, 0], ends[0, 1], ends[1, 0], ends[1, 1]
    low_x, low_y = math.floor(pymin(pymin(ax, bx), cx)), math.floor(pymin(pymin(ay, by), cy))
    columns = math.ceil(pymax(pymax(ax, bx), cx)) - low_x
    rows = math.ceil(pymax(pymax(ay, by), cy)) - low_y
    # the edges a-b, b-c, c-a, and the side of each where the opposite corner lies
    abx, aby, bcx, bcy, cax, cay = bx - ax, by - ay, cx - bx, cy - by, ax - cx, ay - cy
    side_c = abx * (cy - ay) - aby * (cx - ax)
    side_a = bcx * (ay - by) - bcy * (ax - bx)
    side_b = cax * (by - cy) - cay * (bx - cx)
    sign = 1.0 if convex else -1.0
    inside = 0
    worst = -math.inf
    for run in range(2):  # the count first: one centre inside is one row of numpy.matmul (module docstring)
        for ix in range(columns):
            x = float(low_x + ix) + 0.5  # numpy.arange(low, high) + 0.5 of whole numbers: exact
            for iy in range(rows):
                y = float(low_y + iy) + 0.5
                if not ((abx * (y - ay) - aby * (x - ax)) * side_c > 0.0 and
                        (bcx * (y - by) - bcy * (x - bx)) * side_a > 0.0 and
                        (cax * (y - cy) - cay * (x - cx)) * side_b > 0.0):
                    continue
                if run == 0:
                    inside += 1
                    continue
                u = sign * _inkward(first, x, y, inside) - first[11]
                v = sign * _inkward(second, x, y, inside) - second[11]
                depth = u + v if (u != u or v != v) else (u if u <= v else v)
                ink = _parity(cracks, x, y) == ink_parity
                if (not ink if convex else ink) and depth > 0.0 and not depth <= worst:
                    worst = depth
    return worst


@njit(**_JIT)
def _tip_into(points, corner, arc, closed, perimeter, corner_arc, start, first, second, windows, crossing, mode,
              min_cross, ink_all, paper_all, cracks, parity, limits, out, ends):
    """``mode`` 0 and 1: :func:`.tips._tip` after the crossing of the side rows ``first`` and ``second``: the
    crossing itself where both are lines (``mode`` 0; 1: ``crossing`` holds the parabolas', numpy's), the opening
    of the sides there, the bounds and the two consistency tests; the tip, the opening and the window starts
    into ``out`` (point 0-1, opening 2, ends 3-6) and True where the crossing passes. ``limits``: the reach per
    side window, ``BEHIND``, the contradiction limit, ``TIP_ZONE`` and ``MAX_TIP_REACH`` of :mod:`.tips`;
    ``windows``: the side windows that bound the reach; ``parity``: the ray parity of the ink centre
    ``ink_all[0]`` (:func:`.tips.ray_parity`), found here where negative. ``mode`` 2: :func:`.tips.tip_contradiction` (zone
    ``start``, ``corner`` 1 for a convex wedge) into ``out[0]``; ``mode`` 3: :func:`.tips.wedge_contradiction`
    of the tip ``crossing`` and the window starts ``ends`` (``corner`` as in ``mode`` 2) into ``out[0]``."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    if mode == 2:
        out[0] = _tip_depth(arc, perimeter, corner_arc, start, first, second, ink_all, paper_all, corner == 1)
        return True
    if mode == 3:
        if parity < 0:
            parity = _parity(cracks, ink_all[0, 0], ink_all[0, 1])
        out[0] = _wedge_depth(cracks, parity, crossing[0], crossing[1], ends, first, second, corner == 1)
        return True
    if mode == 1:
        x, y = crossing[0], crossing[1]
    else:
        d0, d1, e0, e1 = first[2], first[3], second[2], second[3]
        cross = d0 * e1 - d1 * e0
        if abs(cross) < min_cross:
            return False
        q0, q1 = second[0] - first[0], second[1] - first[1]
        along = (q0 * e1 - q1 * e0) / cross
        x, y = first[0] + along * d0, first[1] + along * d1
    if not (math.isfinite(x) and math.isfinite(y)):
        return False
    c0, c1 = points[corner, 0], points[corner, 1]
    row = _ZERO
    _interp_point(arc, closed, (corner_arc + -start) % perimeter, ends, row)
    row += 1
    _interp_point(arc, closed, (corner_arc + start) % perimeter, ends, row)
    # the sides' tangents at the crossing, pointing away from it (numpy.sign: 0 at 0, NaN at NaN)
    cosine = 1.0
    a0, a1 = 0.0, 0.0
    for k in range(2):
        side = first if k == 0 else second
        t = (x - side[0]) * side[2] + (y - side[1]) * side[3]
        turn = side[7] + 2.0 * side[8] * t
        u0, u1 = side[2] + turn * side[4], side[3] + turn * side[5]
        towards = (side[0] - x) * u0 + (side[1] - y) * u1
        sign = 1.0 if towards > 0 else -1.0 if towards < 0 else 0.0 if towards == 0 else towards
        norm = math.hypot(u0, u1)
        u0, u1 = u0 * sign / norm, u1 * sign / norm
        if k == 0:
            a0, a1 = u0, u1
        else:
            cosine = a0 * u0 + a1 * u1
    opening = cosine if cosine != cosine else math.acos(-1.0 if cosine < -1.0 else 1.0 if cosine > 1.0 else cosine)
    # tip_reach(opening) (numpy.maximum and numpy.minimum: NaN wins), then min with the windows' bound
    half = math.sin(0.5 * opening)
    reach = math.sqrt(0.5) / (half if (half >= 1e-6 or half != half) else 1e-6) + 0.5
    reach = reach if (reach <= limits[4] or reach != reach) else limits[4]
    shortest = windows[0]
    for i in range(1, windows.shape[0]):
        shortest = pymin(shortest, windows[i])
    if math.hypot(x - c0, y - c1) > pymin(reach, limits[0] * shortest):
        return False
    o0 = c0 - 0.5 * (ends[0, 0] + ends[1, 0])
    o1 = c1 - 0.5 * (ends[0, 1] + ends[1, 1])
    if o0 * (x - c0) + o1 * (y - c1) < -limits[1] * math.hypot(o0, o1):
        return False
    if ink_all.shape[0] and first[10] != 0.0 and second[10] != 0.0:
        if parity < 0:  # the ray parity of the outline's first ink centre
            parity = _parity(cracks, ink_all[0, 0], ink_all[0, 1])
        convex = _inkward(first, second[0], second[1], _ONE) > 0
        if _tip_depth(arc, perimeter, corner_arc, start + limits[3], first, second, ink_all, paper_all,
                      convex) > limits[2]:
            return False
        if _wedge_depth(cracks, parity, x, y, ends, first, second, convex) > limits[2]:
            return False
    out[0], out[1], out[2] = x, y, opening
    return True


def tip_checks(contour, corner, corner_arc, start, first, second, windows, crossing, ink, paper, cracks, parity,
               min_cross, limits):
    """:func:`.tips._tip` in one pass (``crossing``: the crossing of sides with a parabola, numpy's, else None):
    ``(point, opening, ends)`` or None."""
    out, ends = np.empty(3), np.empty((2, 2))
    if not _tip_into(contour.points, int(corner), contour.arc, contour.closed_points, float(contour.perimeter),
                     float(corner_arc), float(start), first, second, windows,
                     _NO_COEFFICIENTS if crossing is None else np.ascontiguousarray(crossing, float),
                     0 if crossing is None else 1, float(min_cross), ink, paper, cracks, int(parity), limits, out,
                     ends):
        return None
    return out[0:2], out[2], ends


@njit(**_JIT)
def _tips_into(points, corners, arc, closed, perimeter, corner_arcs, starts, firsts, seconds, windows, sizes, crossing,
               min_cross, ink_all, paper_all, cracks, parity, limits, outs, ends, passed):
    """:func:`_tip_into` in ``mode`` 0 (two lines) for the corners ``corners[r]``, their side rows ``firsts[r]`` and
    ``seconds[r]`` and side windows ``windows[r, :sizes[r]]``, into ``outs[r]``, ``ends[r]`` and ``passed[r]``."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for r in range(corners.shape[0]):
        passed[r] = _tip_into(points, corners[r], arc, closed, perimeter, corner_arcs[r], starts[r], firsts[r],
                              seconds[r], windows[r, :sizes[r]], crossing, 0, min_cross, ink_all, paper_all, cracks,
                              parity, limits, outs[r], ends[r])


def line_tip_checks(contour, corners, corner_arcs, starts, firsts, seconds, windows, ink, paper, cracks, min_cross,
                    limits):
    """:func:`tip_checks` of many corners whose two sides are lines, in one compiled pass (the same operations per
    corner): per corner ``r`` (its contour index ``corners[r]``, arc length ``corner_arcs[r]``, window start
    ``starts[r]``, side rows ``firsts[r]`` and ``seconds[r]``, the side windows ``windows[r]`` that bound its
    reach, one or two) ``(point, opening, ends)`` or None."""
    count = len(corners)
    sizes = np.array([len(w) for w in windows], np.int64)
    table = np.zeros((count, 2))
    for r, w in enumerate(windows):
        table[r, :len(w)] = w
    outs, ends, passed = np.empty((count, 3)), np.empty((count, 2, 2)), np.empty(count, np.bool_)
    _tips_into(contour.points, np.asarray(corners, np.int64), contour.arc, contour.closed_points,
               float(contour.perimeter), np.asarray(corner_arcs, float), np.asarray(starts, float), np.stack(firsts),
               np.stack(seconds), table, sizes, _NO_COEFFICIENTS, float(min_cross), ink, paper, cracks, -1, limits,
               outs, ends, passed)
    return [(outs[r, 0:2], outs[r, 2], ends[r]) if passed[r] else None for r in range(count)]


def tip_contradiction_of(contour, corner_arc, zone, first, second, ink, paper, convex):
    """:func:`.tips.tip_contradiction` of the side rows ``first`` and ``second`` in one pass."""
    out = np.empty(3)
    _tip_into(_NO_POINTS, int(bool(convex)), contour.arc, _NO_POINTS, float(contour.perimeter), float(corner_arc),
              float(zone), first, second, _NO_FLOATS, _NO_COEFFICIENTS, 2, 0.0, ink, paper, _NO_POINTS, 0,
              _NO_FLOATS, out, _NO_ENDS)
    return float(out[0])


def wedge_contradiction_of(cracks, parity, ink, tip, ends, first, second, convex):
    """:func:`.tips.wedge_contradiction` of the side rows ``first`` and ``second`` in one pass (``parity``: that of
    the ink centre ``ink[0]``, None: found here)."""
    out = np.empty(3)
    _tip_into(_NO_POINTS, int(bool(convex)), _NO_FLOATS, _NO_POINTS, 1.0, 0.0, 0.0, first, second, _NO_FLOATS,
              np.ascontiguousarray(tip, float), 3, 0.0, ink, _NO_POINTS, np.ascontiguousarray(cracks, float),
              -1 if parity is None else int(parity), _NO_FLOATS, out, np.ascontiguousarray(ends, float).reshape(2, 2))
    return float(out[0])


def warm_up():
    """Compile (empty cache) or load the kernels of the extrapolated tips on tiny inputs (a square's crack
    outline)."""
    from types import SimpleNamespace

    points = np.array([[0.5, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5]])
    closed = np.vstack([points, points[:1]])
    arc = np.array([0.0, 0.75, 1.5, 2.25, 3.0])
    contour = SimpleNamespace(points=points, closed_points=closed, arc=arc, perimeter=3.0)
    samples, local, centre = window_samples(contour, 0.5, 1, 0.0, 1.0)
    slopes = np.linspace(-0.25, 0.25, 17)
    ink, paper = points + 0.1, points - 0.1
    row = side_window(contour, 0.5, 1, 0.0, 1.0, samples, samples.shape[0], local, centre, ink, paper,
                      lambda t, y: None, slopes, 0.03, 2)
    if row is None:
        row = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0])
    separating_line(ink, paper, row, slopes, 0.03, 2)
    inkward_of(row, points)
    second = np.array([0.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0])
    limits = np.array([0.25, 1.0, 0.1, 1.0, 5.0])
    window_sides(contour, [0.5, 0.5], [1.0, -1.0], [0.0, 0.0], [1.0, 1.0], ink, paper, slopes, 0.03, 2)
    line_tip_checks(contour, [0], [0.5], [0.5], [row], [second], [[1.0, 1.0]], ink, paper, points, 0.1, limits)
    tip_checks(contour, 0, 0.5, 0.5, row, second, np.ones(2), None, ink, paper, points, -1, 0.1, limits)
