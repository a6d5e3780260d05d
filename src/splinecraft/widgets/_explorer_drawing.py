"""What the TraceExplorer's page draws: float32 buffers of the bitmap's boundaries, corners and fits.

:func:`base_geometry` is sent once per trace (boundaries, corners, final fit); :func:`snapshot_geometry` once
per iteration shown (the fit of that iteration, its knots, the accepted / rejected candidates, the removed
knots and the piece with the largest error). :func:`stats_html` is the row of thesis tables 4.1-4.61.
"""
from __future__ import annotations

import html
import math
import numbers

import numpy as np

from ._base import f32

__all__ = ["base_geometry", "snapshot_geometry", "iteration_note", "worst_piece", "stats_html"]


def base_geometry(result) -> dict:
    """Boundaries (NaN-separated closed rings), corner points and the final fit of a trace result."""
    rings = [np.vstack([points, points[:1], [[np.nan, np.nan]]]) for points in result.points]
    corners = [np.asarray(points)[np.asarray(idx, dtype=int)] for points, idx in zip(result.points, result.corners)
               if len(idx)]
    final = np.concatenate([s.bezier() for s in result.splines], axis=0)
    return {
        "boundaries": f32(np.vstack(rings)) if rings else b"",
        "corners": f32(np.vstack(corners)) if corners else b"",
        "final": f32(final),
    }


def _candidates(result, merged):
    """Knot points and the accepted / rejected / removed candidate points of one merged snapshot."""
    knots, accepted, rejected, removed = [], [], [], []
    for points, snapshot in zip(result.points, merged.snapshots):
        indices = np.unique(np.concatenate([np.asarray(k, dtype=int).reshape(-1) for k in snapshot.knot_indices])) \
            if len(snapshot.knot_indices) else np.zeros(0, dtype=int)
        knots.append(np.asarray(points)[indices % len(points)])
        for candidate in snapshot.candidates or []:
            point = candidate.get("point")
            if point is None:
                continue
            action = candidate.get("action", "insert")
            if action == "insert":
                (accepted if candidate.get("accepted") else rejected).append(point)
            elif action == "remove" and candidate.get("accepted"):
                removed.append(point)
    as_xy = lambda values: np.asarray(values, dtype=float).reshape(-1, 2)  # noqa: E731
    return (np.vstack(knots) if knots else np.zeros((0, 2))), as_xy(accepted), as_xy(rejected), as_xy(removed)


def snapshot_geometry(result, merged) -> tuple:
    """``(geometry, counts)`` of merged snapshot ``merged`` (None: the final splines, no snapshots kept)."""
    if merged is None:
        bezier = np.concatenate([s.bezier() for s in result.splines], axis=0)
        return {"bezier": f32(bezier)}, {"iteration": 0, "pieces": len(bezier)}
    knots, accepted, rejected, removed = _candidates(result, merged)
    worst, worst_contour = worst_piece(result, merged)
    geometry = {
        "iteration": int(merged.iteration), "bezier": f32(merged.bezier), "worst": f32(worst),
        "worst_contour": f32(worst_contour), "knots": f32(knots), "accepted": f32(accepted),
        "rejected": f32(rejected), "removed": f32(removed),
    }
    counts = {
        "iteration": int(merged.iteration), "knots": int(merged.knots), "pieces": int(len(merged.bezier)),
        "max_error": float(merged.max_error), "hausdorff": float(merged.hausdorff),
        "accepted": len(accepted), "rejected": len(rejected), "removed": len(removed),
    }
    return geometry, counts


def iteration_note(result, merged, index: int, removed: int) -> str:
    """What iteration ``index`` shows, in a sentence or three (first fit, removal round, finished boundaries)."""
    finished = int(np.sum(merged.finished)) if len(merged.finished) else 0
    total = len(merged.snapshots)
    phases = {getattr(s, "phase", "insert") for s, done in zip(merged.snapshots, merged.finished) if not done}
    notes = []
    if index == 0:
        if result.params.get("method") == "lsq":
            notes.append("Iteration 0 is the first fit: the corners, and knots where the contour's curvature "
                         "calls for them.")
        else:
            notes.append("Iteration 0 is the first fit, with the corners as the only knots.")
    elif "remove" in phases:
        notes.append(f"Knot removal round: {removed} knot(s) dropped where the fit stays within ε.")
    if finished and finished < total and index > 0:
        notes.append(f"{finished} of {total} boundaries have already finished.")
    if index > 0 and any(getattr(s, "thesis_stop", False) for s in merged.snapshots):
        notes.append("The thesis's stopping rule (no candidate above ε) would stop here.")
    return " ".join(notes)


def worst_piece(result, merged):
    """Bézier segments and contour points of the corner-to-corner piece with the largest thesis error.

    ``piece_max_error`` has one entry per piece between corners; piece ``k`` of a boundary is drawn by
    ``len(knot_indices[k]) - 1`` consecutive Bézier segments and approximates the contour points from its
    first to its last knot index (wrapping past index 0).
    """
    best = None
    offset = 0
    for boundary, snapshot in enumerate(merged.snapshots):
        errors = np.asarray(snapshot.piece_max_error, dtype=float)
        counts = [len(k) - 1 for k in snapshot.knot_indices]
        if errors.size and np.isfinite(errors).any() and len(counts) == errors.size:
            k = int(np.nanargmax(errors))
            if best is None or errors[k] > best[0]:
                best = (float(errors[k]), boundary, k, offset + sum(counts[:k]), counts[k])
        offset += len(snapshot.bezier)
    if best is None:
        return np.zeros((0, 4, 2)), np.zeros((0, 2))
    _error, boundary, k, first_row, count = best
    segments = merged.bezier[first_row:first_row + count]
    points = np.asarray(result.points[boundary])
    indices = merged.snapshots[boundary].knot_indices[k]
    first, last = int(indices[0]), int(indices[-1])
    span = np.arange(first, last + 1 if last > first else last + len(points) + 1) % len(points)
    return segments, points[span]

def stats_html(result) -> str:
    stats = result.stats
    params = result.params

    def number(value, digits=2):
        if value is None:
            return "—"
        if isinstance(value, (bool, np.bool_)):
            return "yes" if value else "no"
        if isinstance(value, numbers.Integral):
            return f"{int(value):,}"
        if isinstance(value, numbers.Real):
            return "—" if not math.isfinite(value) else f"{value:.{digits}f}"
        return html.escape(str(value))

    columns = [
        ("Total number of points on contour", number(stats.get("contour_points"))),
        ("Number of corner points", number(stats.get("corners"))),
        ("Number of knots inserted", number(stats.get("knots_inserted"))),
        ("Total number of iterations", number(stats.get("iterations"))),
        ("Execution time (s)", number(stats.get("time_s"), 3)),
        ("Threshold value ε (px)", number(params.get("epsilon"))),
        ("% reduction in dataset (Table 4.61)", number(stats.get("data_reduction_pct_thesis"))),
        ("% reduction, stored numbers", number(stats.get("data_reduction_pct"))),
        ("Cubic segments", number(stats.get("segments"))),
        ("Max error, thesis (px)", number(stats.get("max_error"), 3)),
        ("Hausdorff distance (px)", number(stats.get("hausdorff"), 3)),
        ("Converged", number(stats.get("converged"))),
    ]
    head = "".join(f"<th>{html.escape(label)}</th>" for label, _value in columns)
    row = "".join(f"<td>{value}</td>" for _label, value in columns)
    caption = html.escape(
        f"Algorithm {params.get('method')}, corners {params.get('corner_method')}, seed {params.get('seed')}. "
        "The first six columns are those of thesis Tables 4.1–4.60.")
    return (f'<table class="sc-table" data-testid="stats-table"><thead><tr>{head}</tr></thead>'
            f'<tbody><tr>{row}</tr></tbody></table><div class="sc-caption">{caption}</div>')
