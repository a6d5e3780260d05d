"""Time budgets of the outline fit, and the polygon fit of the boundaries that get no time (docs/capture.md
§12, "Time budget").

A bitmap of noise has hundreds of thousands of boundaries: no smooth fit of every one of them ends in
seconds. :func:`~splinecraft.capture.trace.trace` gives corner detection and fitting together a time budget
(``time_budget``, :data:`DEFAULT_TIME_BUDGET`); every boundary started within it gets its full fit, and
the knot rounds of ``"lsq"`` stop at the budget's end (``reason`` names it). Boundaries not started within
it get :func:`polygon_fits`: straight pieces between the turning points of the contour, which *is* the
contour (deviation 0, so within any ``epsilon``), in linear time and without corner detection.
"""
from __future__ import annotations

import operator
import time
from collections.abc import Sequence

import numpy as np
from numba import njit

from ...spline import Spline
from .._jit import JIT_OPTIONS, compact
from .results import FitResult, Snapshot

__all__ = ["DEFAULT_TIME_BUDGET", "SMALL_CHUNK", "Deadline", "polygon_fits", "PolygonFits", "BUDGET_REASON",
           "FALLBACK_BUDGET_REASON", "STOPPED_FIT_LIMIT", "warm_up"]

#: Seconds for corner detection and fitting of all boundaries of one :func:`~splinecraft.capture.trace.trace`
#: call (``None`` = no budget).
DEFAULT_TIME_BUDGET = 5.0
#: Small outlines are fitted in batches of this many, the budget checked before each batch.
SMALL_CHUNK = 1024
#: ``reason`` of a boundary whose knot rounds were stopped by the budget (formatted with the budget, s).
BUDGET_REASON = "the time budget of {budget:g} s ran out during its knot rounds (trace(time_budget=))"
#: ``reason`` of a boundary whose regression spline got stuck when the budget had run out: its fallback fit
#: (``fit_outline``'s ``fallback``) is not started.
FALLBACK_BUDGET_REASON = ("the time budget of {budget:g} s ran out before the fallback fit of its stuck knot rounds "
                          "(trace(time_budget=))")
#: A boundary whose knot rounds the budget stopped keeps its fit while the fit's Hausdorff deviation from the contour
#: is at most this many times the fit's tolerance; further off, it gets the polygon of its contour instead (deviation
#: 0). The first rounds of the regression spline on a long noisy boundary (thousands of corners) can be far off
#: it: on a 300 x 300 image of random pixels the fit of its largest boundary, stopped after 1 to 9 rounds, was 120
#: to 2500 px from it (the fit's spikes crossed the whole picture), where the finished fit is within 2.8 px; without a
#: budget the fallback fit (``fit_outline``'s ``fallback``) replaces such a fit, but no time is left for it. A fit
#: stopped near its tolerance (a glyph of a page whose budget ran out mid-fit) keeps its smooth curve.
STOPPED_FIT_LIMIT = 2.0


class Deadline:
    """The end of a time budget: ``Deadline(None)`` never passes."""

    def __init__(self, budget):
        self.budget = budget
        self.end = None if budget is None else time.perf_counter() + float(budget)

    def passed(self) -> bool:
        return self.end is not None and time.perf_counter() > self.end

    def extend(self, seconds):
        """Move the end later by ``seconds`` (work the budget does not cover, done while it ran)."""
        if self.end is not None:
            self.end += float(seconds)


def polygon_fits(outlines, epsilon, keep_snapshots):
    """Every closed polyline of ``outlines`` as a spline: one straight cubic Bézier (control points at thirds)
    per run between turning points (where the step direction changes), so its deviation from the contour is
    0. The turning points of all outlines are found in one compiled pass; the objects of each outline are made
    when first read (:class:`PolygonFits`)."""
    if not outlines:
        return []
    lengths = np.fromiter(map(len, outlines), np.int64, len(outlines))
    offsets = np.zeros(lengths.shape[0] + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    points = np.ascontiguousarray(np.concatenate(outlines), dtype=float)
    turning = np.empty(points.shape[0], dtype=np.bool_)
    bounds = np.empty(lengths.shape[0] + 1, dtype=np.int64)
    vertices = _turning_into(points, offsets, turning, bounds)
    planar = np.empty((4, 2, vertices), dtype=float)
    knots = np.empty(vertices + lengths.shape[0], dtype=float)
    pairs = np.empty((vertices, 2), dtype=np.int64)
    _polygons_into(points, offsets, turning, bounds, planar, knots, pairs)
    return PolygonFits(planar, knots, pairs, bounds, epsilon, keep_snapshots)


@njit(**JIT_OPTIONS)
def _turning_into(points, offsets, turning, bounds):
    """Flag the turning points of every closed polyline ``points[offsets[b]:offsets[b + 1]]`` (the step direction
    changes there: ``|cross| + (1 - dot) > 1e-9`` of the unit steps before and after; all points of a polyline
    with fewer than 3), the vertex offsets of each polyline into ``bounds``; returns the number of vertices."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    total = np.int64(0)
    bounds[0] = 0
    for outline in range(offsets.shape[0] - 1):
        lo, hi = offsets[outline], offsets[outline + 1]
        count = np.int64(0)
        for i in range(lo, hi):
            after = i + 1 if i + 1 < hi else lo
            before = i - 1 if i > lo else hi - 1
            step_x, step_y = points[after, 0] - points[i, 0], points[after, 1] - points[i, 1]
            length = np.hypot(step_x, step_y)
            direction_x, direction_y = step_x / length, step_y / length
            step_x, step_y = points[i, 0] - points[before, 0], points[i, 1] - points[before, 1]
            length = np.hypot(step_x, step_y)
            before_x, before_y = step_x / length, step_y / length
            turning[i] = (abs(direction_x * before_y - direction_y * before_x)
                          + (1.0 - (direction_x * before_x + direction_y * before_y))) > 1e-9
            count += turning[i]
        if count < 3:  # cannot happen for >= 4 distinct points
            turning[lo:hi] = True
            count = hi - lo
        total += count
        bounds[outline + 1] = total
    return total


@njit(**JIT_OPTIONS)
def _polygons_into(points, offsets, turning, bounds, planar, knots, pairs):
    """The straight Bezier pieces between consecutive turning points (control points at thirds), into
    ``planar`` (4, 2, vertices); the chord-length knots of outline ``b``, from 0, into
    ``knots[bounds[b] + b: bounds[b + 1] + b + 1]`` (differences of one running sum over all outlines); the
    contour indices of each piece's ends into ``pairs``."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    running = 0.0
    for outline in range(offsets.shape[0] - 1):
        lo, hi = offsets[outline], offsets[outline + 1]
        first = bounds[outline]
        vertex = first
        for i in range(lo, hi):
            if turning[i]:
                pairs[vertex, 0] = i - lo
                vertex += 1
        base = running
        knots[first + outline] = 0.0
        for vertex in range(first, bounds[outline + 1]):
            following = vertex + 1 if vertex + 1 < bounds[outline + 1] else first
            pairs[vertex, 1] = pairs[following, 0]
            start, end = lo + pairs[vertex, 0], lo + pairs[following, 0]
            for axis in range(2):
                chord = points[end, axis] - points[start, axis]
                planar[0, axis, vertex] = points[start, axis]
                planar[1, axis, vertex] = points[start, axis] + chord / 3.0
                planar[2, axis, vertex] = points[start, axis] + 2.0 * chord / 3.0
                planar[3, axis, vertex] = points[end, axis]
            running += np.hypot(points[end, 0] - points[start, 0], points[end, 1] - points[start, 1])
            knots[vertex + outline + 1] = running - base


class PolygonFits(Sequence):
    """The polygon :class:`FitResult` of every outline of one :func:`polygon_fits` call, each made on first
    access from the shared arrays of all (then kept): a noise image leaves 10^5 boundaries to the polygon and
    needs none of their objects to count its segments (:attr:`segments`) or write its statistics."""

    def __init__(self, planar, knots, pairs, bounds, epsilon, keep_snapshots):
        self._planar, self._knots, self._pairs = planar, knots, pairs
        self._bounds = bounds.tolist()
        self._epsilon, self._keep = float(epsilon), bool(keep_snapshots)
        self._fits, self._splines = {}, {}
        #: Bezier pieces of every outline's polygon.
        self.segments = np.diff(bounds)

    def __len__(self) -> int:
        return len(self._bounds) - 1

    def __getitem__(self, b):
        if isinstance(b, slice):
            return [self[k] for k in range(*b.indices(len(self)))]
        b = _index(b, len(self))
        fit = self._fits.get(b)
        if fit is None:
            lo, hi = self._bounds[b], self._bounds[b + 1]
            fit = self._fits[b] = _polygon(self.spline(b), self._pairs[lo:hi], self._epsilon, self._keep)
        return fit

    def spline(self, b) -> Spline:
        """The spline of outline ``b`` (that of its fit, ``self[b].spline``)."""
        b = _index(b, len(self))
        spline = self._splines.get(b)
        if spline is None:
            lo, hi = self._bounds[b], self._bounds[b + 1]
            planar = np.ascontiguousarray(self._planar[:, :, lo:hi])
            spline = self._splines[b] = Spline._from_trusted(
                planar, self._knots[lo + b: hi + b + 1].copy(), closed=True, auxiliary={"F": planar[0].T.copy()},
                info={"form": "outline_fit", "method": "polygon", "epsilon": self._epsilon, "pieces": hi - lo})
        return spline


def _index(k, length) -> int:
    k = operator.index(k)
    if not -length <= k < length:
        raise IndexError(f"index {k} out of range for {length} outlines")
    return k % length


def _polygon(spline, pairs, epsilon, keep_snapshots):
    """The :class:`FitResult` of one polygon: ``spline`` its curve, ``pairs`` the contour indices of each piece's
    ends."""
    m = pairs.shape[0]
    planar, knots = spline._planar, spline.knots
    knot_lists = list(pairs)
    snapshots = [Snapshot(iteration=0, knot_indices=knot_lists, bezier=planar.transpose(2, 0, 1).copy(),
                          piece_max_error=np.zeros(m), piece_hausdorff=np.zeros(m), candidates=[], phase="initial",
                          finished=np.ones(m, bool), knots=knots, closed=True)] if keep_snapshots else []
    return FitResult(
        spline=spline, pieces=list(map(tuple, pairs.tolist())), knot_indices=knot_lists, snapshots=snapshots,
        iterations=0, max_error=0.0, hausdorff=0.0, converged=True, knots_inserted=0, method="polygon",
        epsilon=float(epsilon), thesis_stop_iteration=None, corners_used=pairs[:, 0].copy(),
        info={"polygon": True, "reason": None, "tolerance_near_corners": float(epsilon),
              "model": "the contour itself: straight pieces between its turning points (time budget spent)"})


def warm_up():
    """Compile (empty cache) or load (``cache=True``) the polygon kernels, on one tiny square."""
    polygon_fits([np.array([[0.0, 0.5], [0.5, 0.0], [1.0, 0.5], [0.5, 1.0]])], 1.0, False)
