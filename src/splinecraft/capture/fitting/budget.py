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

from ...spline import Spline
from .results import FitResult, Snapshot

__all__ = ["DEFAULT_TIME_BUDGET", "SMALL_CHUNK", "Deadline", "polygon_fits", "PolygonFits", "BUDGET_REASON"]

#: Seconds for corner detection and fitting of all boundaries of one :func:`~splinecraft.capture.trace.trace`
#: call (``None`` = no budget).
DEFAULT_TIME_BUDGET = 5.0
#: Small outlines are fitted in batches of this many, the budget checked before each batch.
SMALL_CHUNK = 1024
#: ``reason`` of a boundary whose knot rounds were stopped by the budget (formatted with the budget, s).
BUDGET_REASON = "the time budget of {budget:g} s ran out during its knot rounds (trace(time_budget=))"


class Deadline:
    """The end of a time budget: ``Deadline(None)`` never passes."""

    def __init__(self, budget):
        self.budget = budget
        self.end = None if budget is None else time.perf_counter() + float(budget)

    def passed(self) -> bool:
        return self.end is not None and time.perf_counter() > self.end


def polygon_fits(outlines, epsilon, keep_snapshots) -> list:
    """Every closed polyline of ``outlines`` as a spline: one straight cubic Bézier (control points at thirds)
    per run between turning points (where the step direction changes), so its deviation from the contour is
    0. The turning points of all outlines are found in one pass."""
    if not outlines:
        return []
    lengths = np.array([o.shape[0] for o in outlines], dtype=np.int64)
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    points = np.concatenate(outlines).astype(float, copy=False)
    following = np.arange(points.shape[0]) + 1
    following[offsets + lengths - 1] = offsets
    preceding = np.arange(points.shape[0]) - 1
    preceding[offsets] = offsets + lengths - 1
    step = points[following] - points
    direction = step / np.hypot(step[:, 0], step[:, 1])[:, None]
    before = direction[preceding]
    turning = (np.abs(direction[:, 0] * before[:, 1] - direction[:, 1] * before[:, 0])
               + (1.0 - np.einsum("ij,ij->i", direction, before))) > 1e-9
    outline_of = np.repeat(np.arange(lengths.shape[0]), lengths)
    few = np.bincount(outline_of[turning], minlength=lengths.shape[0]) < 3
    turning[np.isin(outline_of, np.flatnonzero(few))] = True  # cannot happen for >= 4 distinct points
    vertex = np.flatnonzero(turning)
    bounds = np.searchsorted(outline_of[vertex], np.arange(lengths.shape[0] + 1))
    # the next vertex of every vertex, wrapping within its outline
    after = np.arange(1, vertex.shape[0] + 1)
    after[bounds[1:] - 1] = bounds[:-1]
    start, end = points[vertex], points[vertex[after]]
    chord = end - start
    planar = np.stack([start, start + chord / 3.0, start + 2.0 * chord / 3.0, end]).transpose(0, 2, 1)
    # knots of all outlines in one array: outline b owns entries bounds[b] + b .. bounds[b + 1] + b, from 0
    running = np.cumsum(np.hypot(chord[:, 0], chord[:, 1]))
    base = np.concatenate([[0.0], running])[bounds[:-1]]
    knots = np.zeros(vertex.shape[0] + lengths.shape[0])
    knots[np.arange(vertex.shape[0]) + outline_of[vertex] + 1] = running - base[outline_of[vertex]]
    local = vertex - offsets[outline_of[vertex]]
    pairs = np.column_stack([local, local[after]])
    return PolygonFits(planar, knots, pairs, bounds, epsilon, keep_snapshots)


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
