"""The statistics of :func:`~splinecraft.capture.trace.trace` (the columns of thesis tables 4.1-4.61 and the
per-boundary details, see its docstring), written column by column: the polygons a spent time budget leaves
(docs/capture.md §12, "Time budget") enter with their known values (no iterations, no knots inserted,
deviation 0, converged) and the segment counts of their batch, without making their objects; the totals
``converged`` is over the fitted boundaries only, and ``polygons`` counts the others.
"""
from __future__ import annotations

import numpy as np

from .contour import Boundaries

__all__ = ["trace_stats", "unconverged_reason"]


def unconverged_reason(fit, max_iterations):
    """Why a boundary's fit did not converge (``None`` when it did)."""
    if fit.converged:
        return None
    if fit.info.get("reason"):
        return str(fit.info["reason"])
    if fit.iterations >= max_iterations:
        return f"max_iterations={max_iterations} reached with a deviation of {fit.hausdorff:.3g} px"
    return (f"knot insertion stopped after {fit.iterations} iterations with a deviation of {fit.hausdorff:.3g} px: "
            "no failing interval could take another knot (knots must stay min_gap contour steps apart) and no "
            "corner was left to release")


def trace_stats(boundaries, points_list, corner_list, fits, polygons, budget_state, max_iterations) -> dict:
    """``stats`` of a trace; ``polygons`` as made by ``trace._lazy_fits`` (``left``: the boundaries given their
    polygon, ``segments``: its pieces, ``fitted``: the others), ``budget_state`` per boundary."""
    count = len(points_list)
    lengths = np.fromiter(map(len, points_list), np.int64, count)
    contour_points = int(lengths.sum())
    segments = np.zeros(count, dtype=np.int64)
    segments[polygons["left"]] = polygons["segments"]
    fitted = polygons["fitted"]
    fitted_fits = [fits[k] for k in fitted]
    segments[fitted] = [fit.spline.n_segments for fit in fitted_fits]
    is_hole = (boundaries.is_hole if isinstance(boundaries, Boundaries)
               else np.array([b.is_hole for b in boundaries], dtype=bool))
    holes = int(is_hole.sum())
    # per-boundary columns, the polygons' values first, then those of the fitted boundaries
    knots, iterations, max_error, hausdorff = [0] * count, [0] * count, [0.0] * count, [0.0] * count
    converged, small_outline, reason = [True] * count, [False] * count, [None] * count
    for k, fit in zip(fitted, fitted_fits):
        knots[k], iterations[k] = int(fit.knots_inserted), int(fit.iterations)
        max_error[k], hausdorff[k], converged[k] = float(fit.max_error), float(fit.hausdorff), bool(fit.converged)
        small_outline[k] = bool(fit.info.get("small_outline", False))
        reason[k] = unconverged_reason(fit, max_iterations)
    corners = [len(c) for c in corner_list]
    per_boundary = [
        {"is_hole": hole, "contour_points": n, "corners": c, "knots_inserted": ki, "iterations": it, "segments": sg,
         "max_error": me, "hausdorff": hd, "converged": cv, "small_outline": so, "reason": why, "budget": state}
        for hole, n, c, ki, it, sg, me, hd, cv, so, why, state in zip(
            is_hole.tolist(), lengths.tolist(), corners, knots, iterations, segments.tolist(), max_error, hausdorff,
            converged, small_outline, reason, budget_state)
    ]
    some_polygon = [0.0] if len(polygons["left"]) else []  # the polygons' iterations, errors and deviations
    total_segments = int(segments.sum())
    knots_inserted = int(sum(knots))
    return {
        "boundaries": len(boundaries),
        "outer": len(boundaries) - holes,
        "holes": holes,
        "contour_points": contour_points,
        "corners": int(sum(corners)),
        "knots_inserted": knots_inserted,
        "iterations": int(max(some_polygon + [iterations[k] for k in fitted])),
        "segments": total_segments,
        "data_reduction_pct": 100.0 * (1.0 - 6.0 * total_segments / (2.0 * contour_points)),
        "data_reduction_pct_thesis": 100.0 * (1.0 - knots_inserted / contour_points),
        "max_error": float(max(some_polygon + [max_error[k] for k in fitted])),
        "hausdorff": float(max(some_polygon + [hausdorff[k] for k in fitted])),
        "converged": bool(all(converged[k] for k in fitted)),
        "polygons": int(len(polygons["left"])),
        "per_boundary": per_boundary,
    }
