"""Result types of the outline fit: :class:`Snapshot` (one iteration) and :class:`FitResult` (docs/capture.md §12).

The bottom of the fitting package: every fitting family returns these, so they import nothing of the package
except its defaults.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...spline import Spline
from .._lazy import LazyList
from .options import DEFAULT_EPSILON, DEFAULT_METHOD

__all__ = ["Snapshot", "FitResult", "BoundaryList"]


@dataclass(eq=False)
class Snapshot:
    """One iteration of a fit (docs/capture.md §12).

    Attributes
    ----------
    iteration : int
        0 for the initial fit (corners only), then one per knot-insertion (or knot-removal) round.
    knot_indices : list of ndarray
        Per piece, sorted indices into the contour points, corners at both ends included (a piece that wraps
        past index 0 lists its indices in contour order, e.g. ``[950, 990, 3, 40]``).
    bezier : ndarray (m, 4, 2)
        All Bézier pieces of the outline at this iteration (draw with these).
    piece_max_error : ndarray (pieces,)
        Thesis error per piece: max over its contour points of the distance to the corresponding curve point.
    piece_hausdorff : ndarray (pieces,)
        Geometric deviation per piece in px (symmetric closest-point distance, both directions; an upper bound).
    candidates : list of dict
        ``{"piece", "index", "point", "accepted", "reason", "membership", "action"}``; ``action`` is
        ``"insert"`` (a knot candidate), ``"remove"``/``"restore"`` (lsq knot removal) or ``"release"`` (lsq: a
        corner's tip extrapolation was reduced).
    phase : str
        ``"initial"``, ``"insert"`` or ``"remove"`` (lsq's final knot-removal rounds; knots only grow before).
    thesis_stop : bool
        The thesis's own rule (no candidate passed ``d > epsilon`` in this iteration) would stop here.
    finished : ndarray of bool (pieces,)
        Pieces within their tolerance.
    knots : ndarray (m + 1,)
        Parameter values of the Bézier pieces (for :meth:`spline`).
    closed : bool
    """

    iteration: int
    knot_indices: list
    bezier: np.ndarray
    piece_max_error: np.ndarray
    piece_hausdorff: np.ndarray
    candidates: list = field(default_factory=list)
    phase: str = "insert"
    thesis_stop: bool = False
    finished: np.ndarray = None
    knots: np.ndarray = None
    closed: bool = True

    def spline(self) -> Spline:
        """The outline at this iteration as a :class:`~splinecraft.spline.Spline` (closed)."""
        knots = self.knots if self.knots is not None else np.arange(len(self.bezier) + 1, dtype=float)
        return Spline(self.bezier, knots, closed=self.closed, info={"form": "outline_fit_snapshot",
                                                                    "iteration": int(self.iteration)})

    @property
    def max_error(self) -> float:
        return float(np.max(self.piece_max_error)) if len(self.piece_max_error) else 0.0

    @property
    def hausdorff(self) -> float:
        return float(np.max(self.piece_hausdorff)) if len(self.piece_hausdorff) else 0.0


@dataclass(eq=False)
class FitResult:
    """Result of :func:`~splinecraft.capture.fitting.fit_outline` (docs/capture.md §12).

    Attributes
    ----------
    spline : Spline
        The fitted outline (closed when ``closed=True``), one cubic Bézier per knot interval.
    pieces : list of (int, int)
        Per piece, the contour indices of its start and end corner.
    knot_indices : list of ndarray
        Per piece, the contour indices of its knots (corners included), as in :class:`Snapshot`.
    snapshots : list of Snapshot
        First = initial fit (corners only), last = this result (empty if ``keep_snapshots=False``).
    iterations : int
        Knot-insertion (and removal) rounds run.
    max_error : float
        Thesis error (max distance of a contour point to its corresponding curve point), px.
    hausdorff : float
        Geometric deviation between the curve and the contour polyline (both directions), px.
    converged : bool
        Every piece within its tolerance (the guarantee of docs/capture.md §12).
    knots_inserted : int
        Knot points of the result that are not corners (for the thesis's tables).
    method, epsilon : the method and tolerance used.
    thesis_stop_iteration : int or None
        First iteration after which the thesis's own stopping rule would have stopped.
    corners_used : ndarray
        The corner indices the pieces start at (after dropping duplicates).
    """

    spline: Spline
    pieces: list
    knot_indices: list
    snapshots: list
    iterations: int
    max_error: float
    hausdorff: float
    converged: bool
    knots_inserted: int
    method: str = DEFAULT_METHOD
    epsilon: float = DEFAULT_EPSILON
    thesis_stop_iteration: int | None = None
    corners_used: np.ndarray = None
    info: dict = field(default_factory=dict)


class BoundaryList(LazyList):
    """A list of per-boundary results of which some are made on first access, then kept (docs/capture.md
    §12, "Time budget"): ``items[k]`` is the result of boundary ``k``, or ``None`` where ``make(k)`` builds it.

    Indexing, slicing, iteration, ``len`` and assignment behave as on a list. A bitmap of noise leaves 10^5
    boundaries to the polygon fit; their ``FitResult`` and ``Spline`` objects cost about 50 us and a few kB each,
    and are made only for the boundaries read.
    """

    def __repr__(self) -> str:
        return f"BoundaryList({len(self)} boundaries, {self.made()} made)"
