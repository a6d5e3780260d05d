"""Result objects of :func:`~splinecraft.capture.trace.trace`: :class:`TraceResult` (everything the pipeline
computed, with SVG and JSON writers) and :class:`TraceSnapshot` (all boundaries at one iteration).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from .._json import to_jsonable
from ._lazy import LazyList
from ..spline.svg import path_data, svg_document

__all__ = ["TraceResult", "TraceSnapshot", "merge_snapshots", "jsonable"]


@dataclass(eq=False)
class TraceSnapshot:
    """All boundaries at one iteration of knot insertion (the merged view for stepping).

    Attributes
    ----------
    iteration : int
        Iteration number (0 = the initial fit with corners only).
    snapshots : list of fitting.Snapshot
        Per boundary, the snapshot in force at this iteration: its own snapshot of that iteration, or its
        last one when the boundary finished earlier.
    finished : ndarray of bool
        Per boundary: it had already finished (no snapshot later than this iteration).
    """

    iteration: int
    snapshots: list
    finished: np.ndarray

    @property
    def bezier(self) -> np.ndarray:
        """All pieces of all boundaries, shape ``(pieces, 4, 2)``."""
        return np.concatenate([np.asarray(s.bezier, dtype=float) for s in self.snapshots], axis=0)

    @property
    def piece_boundary(self) -> np.ndarray:
        """Boundary index of every row of :attr:`bezier`."""
        counts = [len(s.bezier) for s in self.snapshots]
        return np.repeat(np.arange(len(counts)), counts)

    @property
    def piece_max_error(self) -> np.ndarray:
        """Thesis error of every piece (spline point vs its contour point), concatenated."""
        return np.concatenate([np.asarray(s.piece_max_error, dtype=float) for s in self.snapshots])

    @property
    def piece_hausdorff(self) -> np.ndarray:
        """Geometric deviation (two-sided, px) of every piece, concatenated."""
        return np.concatenate([np.asarray(s.piece_hausdorff, dtype=float) for s in self.snapshots])

    @property
    def knots(self) -> int:
        """Number of knots (corners included) over all boundaries."""
        return int(sum(_knot_count(s.knot_indices) for s in self.snapshots))

    @property
    def max_error(self) -> float:
        return float(self.piece_max_error.max(initial=0.0))

    @property
    def hausdorff(self) -> float:
        return float(self.piece_hausdorff.max(initial=0.0))

    def splines(self) -> list:
        """The curve of every boundary at this iteration (:class:`~splinecraft.spline.Spline`)."""
        return [s.spline() for s in self.snapshots]

    def to_svg(self, width, height, *, decimals=4) -> str:
        """SVG of the outline at this iteration (same frame and form as :meth:`TraceResult.to_svg`)."""
        return svg_document(path_data([s.bezier for s in self.snapshots], decimals=decimals), width, height)


@dataclass(eq=False)
class TraceResult:
    """Everything :func:`~splinecraft.capture.trace.trace` computed (docs/capture.md).

    Attributes
    ----------
    mask : ndarray (H, W) bool
        The binarized bitmap (True = ink).
    boundaries : list of Boundary
        Outer boundaries and holes of all components (see :func:`~splinecraft.capture.contour.trace_boundaries`).
    points : list of ndarray (n, 2)
        The contour fitted for each boundary (``Boundary.outline`` or ``Boundary.pixels``).
    corners : list of ndarray of int
        Corner indices into ``points[k]``.
    fits : sequence of fitting.FitResult
        Per boundary: pieces, knot indices, snapshots, errors, convergence. A list-like
        ``fitting.results.BoundaryList``: the polygons of the boundaries a spent time budget left (docs/capture.md
        §12, "Time budget") are made when first read, so a noise image with 10^5 of them stays light.
    splines : sequence of Spline
        The final closed curve of every boundary, in the pixel frame (``splines[k] is fits[k].spline``; made on
        first read like ``fits``).
    snapshots : list of TraceSnapshot
        Merged per-iteration view (iteration 0 .. max over boundaries); empty when
        ``keep_snapshots=False``. The last one equals the result.
    boundary_snapshots : list of list of fitting.Snapshot
        Per boundary, its own snapshots (``fits[k].snapshots``).
    stats : dict
        The columns of thesis tables 4.1-4.61 and more; see :func:`~splinecraft.capture.trace.trace`.
    params : dict
        The settings used (defaults resolved to names).
    notes : list of str
        Fallbacks taken (e.g. a contour too short for corner detection).
    """

    mask: np.ndarray
    boundaries: list
    points: list
    corners: list
    fits: list
    splines: list
    snapshots: list
    stats: dict
    params: dict
    notes: list = field(default_factory=list)

    @property
    def width(self) -> int:
        return int(self.mask.shape[1])

    @property
    def height(self) -> int:
        return int(self.mask.shape[0])

    @property
    def boundary_snapshots(self) -> list:
        return [list(fit.snapshots) for fit in self.fits]

    def bezier(self) -> list:
        """Bézier control points of every boundary's final curve, a list of ``(m, 4, 2)`` arrays."""
        return [spline.bezier() for spline in self.splines]

    def svg_path_data(self, *, decimals=4) -> str:
        """The ``d`` attribute of :meth:`to_svg`: one closed subpath of cubic Béziers per boundary."""
        return path_data(self.bezier(), decimals=decimals)

    def to_svg(self, *, decimals=4, fill="black", title=None) -> str:
        """Standalone SVG: one ``<path>`` of exact cubic Béziers, ``fill-rule="evenodd"`` (holes stay
        empty), ``width``/``height``/``viewBox`` = the bitmap size in its pixel frame.

        ``decimals`` rounds coordinates (``None``: exact floats).
        """
        return svg_document(self.svg_path_data(decimals=decimals), self.width, self.height, fill=fill,
                            title=title)

    def edit(self, iteration=None, **params):
        """This outline (or that of ``snapshots[iteration]``) in an ``OutlineEditor`` widget (JupyterLab).

        A convenience for ``sc.OutlineEditor(result, iteration=...)``. Capture imports nothing of the
        widget layer: the editor is looked up at call time through the package's lazy top-level names.
        """
        import splinecraft

        return splinecraft.OutlineEditor(self, iteration=iteration, **params)

    def to_dict(self, *, include_points=False, include_snapshots=False) -> dict:
        """JSON-able summary: size, settings, stats and, per boundary, its chain code, corners, knots and
        final spline (``Spline.to_dict``). Optionally the fitted contour points and all snapshots.
        Non-finite numbers become ``None``.
        """
        boundaries = []
        for k, (boundary, points, corner_idx, fit, spline) in enumerate(
            zip(self.boundaries, self.points, self.corners, self.fits, self.splines)
        ):
            entry = {  # plain JSON values as built (not walked again below)
                "index": k,
                "is_hole": bool(boundary.is_hole),
                "parent": None if boundary.parent is None else int(boundary.parent),
                "component": int(boundary.component),
                "connectivity": (str(boundary.connectivity) if isinstance(boundary.connectivity, str)
                                 else int(boundary.connectivity)),
                "area": int(boundary.area),
                "chain_start": jsonable(list(boundary.start), "TraceResult['boundaries'][...]['chain_start']"),
                "chain_code": str(boundary.chain_string),
                "contour_points": int(len(points)),
                "corners": np.asarray(corner_idx).tolist(),
                "pieces": [[int(a), int(b)] for a, b in fit.pieces],
                "knot_indices": [np.asarray(k_idx).tolist() for k_idx in fit.knot_indices],
                "knots_inserted": int(fit.knots_inserted),
                "iterations": int(fit.iterations),
                "converged": bool(fit.converged),
                "max_error": _finite_or_none(fit.max_error),
                "hausdorff": _finite_or_none(fit.hausdorff),
                "spline": spline.to_dict(),  # plain lists of finite floats (Spline.to_dict), its info checked
            }
            entry["spline"]["info"] = jsonable(entry["spline"]["info"],
                                               f"TraceResult['boundaries'][{k}]['spline']['info']")
            if include_points:
                entry["points"] = np.asarray(points, dtype=float).tolist()
            if include_snapshots:
                entry["snapshots"] = jsonable([_snapshot_dict(s) for s in fit.snapshots],
                                              f"TraceResult['boundaries'][{k}]['snapshots']")
            boundaries.append(entry)
        out = jsonable({
            "type": "splinecraft.TraceResult",
            "version": 1,
            "width": self.width,
            "height": self.height,
            "params": self.params,
            "stats": self.stats,
            "notes": list(self.notes),
        })
        # the boundaries and the path data (a string) are plain as built: walked item by item again, they cost
        # more than the trace on a large result (a noise image's 25 000 boundaries)
        out["boundaries"] = boundaries
        out["svg_path"] = self.svg_path_data(decimals=None)
        return out

    def to_json(self, *, indent=None, include_points=False, include_snapshots=False) -> str:
        """:meth:`to_dict` as strict JSON (no NaN)."""
        return json.dumps(
            self.to_dict(include_points=include_points, include_snapshots=include_snapshots),
            indent=indent, allow_nan=False,
        )

    def __repr__(self) -> str:
        s = self.stats
        return (
            f"TraceResult({self.width}x{self.height}, boundaries={s['boundaries']} (holes={s['holes']}), "
            f"contour_points={s['contour_points']}, corners={s['corners']}, "
            f"knots_inserted={s['knots_inserted']}, iterations={s['iterations']}, segments={s['segments']}, "
            f"hausdorff={s['hausdorff']:.3g} px, time={s['time_s'] * 1e3:.1f} ms)"
        )


def _knot_count(knot_indices) -> int:
    """Distinct knots (corners included) of one outline: the distinct contour indices over all pieces."""
    arrays = [np.asarray(k, dtype=np.int64).reshape(-1) for k in knot_indices]
    return int(np.unique(np.concatenate(arrays)).size) if arrays else 0


def _finite_or_none(value):
    value = float(value)
    return value if math.isfinite(value) else None


def jsonable(value, where="TraceResult"):
    """Plain JSON values (numpy arrays and scalars converted, non-finite numbers as ``None``, other objects
    and keys as strings)."""
    return to_jsonable(value, where, non_finite="none", coerce=True)


def _snapshot_dict(snapshot) -> dict:
    return jsonable({
        "iteration": snapshot.iteration,
        "knot_indices": [np.asarray(k) for k in snapshot.knot_indices],
        "bezier": np.asarray(snapshot.bezier),
        "piece_max_error": np.asarray(snapshot.piece_max_error),
        "piece_hausdorff": np.asarray(snapshot.piece_hausdorff),
        "candidates": list(snapshot.candidates),
    })




def merge_snapshots(fits) -> list:
    """One TraceSnapshot per iteration 0 .. max, each boundary at its latest snapshot up to then.

    ``fits`` may be a :class:`~splinecraft.capture.fitting.results.BoundaryList` whose unread items are the
    polygons of a spent time budget (docs/capture.md §12, "Time budget"): each has one snapshot, at iteration 0
    and finished, so it stands in every merged snapshot without being made; a merged snapshot makes it when read.
    """
    pending = set(fits.missing()) if isinstance(fits, LazyList) else set()
    made = [k for k in range(len(fits)) if k not in pending]
    per_boundary = {k: list(fits[k].snapshots) for k in made}
    if any(not snaps for snaps in per_boundary.values()):
        return []
    iterations = {k: np.array([s.iteration for s in snaps]) for k, snaps in per_boundary.items()}
    last = max((int(its[-1]) for its in iterations.values()), default=0)
    merged = []
    for iteration in range(last + 1):
        chosen, finished = [None] * len(fits), np.ones(len(fits), bool)
        for k in made:
            its = iterations[k]
            position = max(int(np.searchsorted(its, iteration, side="right")) - 1, 0)
            chosen[k] = per_boundary[k][position]
            finished[k] = iteration >= its[-1]
        snapshots = LazyList(chosen, _FirstSnapshot(fits)) if pending else chosen
        merged.append(TraceSnapshot(iteration=iteration, snapshots=snapshots, finished=finished))
    return merged


class _FirstSnapshot:
    """Boundary ``k`` -> the one snapshot of its (polygon) fit, made when read (a picklable maker)."""

    def __init__(self, fits):
        self.fits = fits

    def __call__(self, k):
        return self.fits[k].snapshots[0]
