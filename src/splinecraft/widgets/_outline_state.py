"""The OutlineEditor's synced lists <-> its outline, and the bitmap it shows (PNG bytes)."""
from __future__ import annotations

import io

import numpy as np

from ..outline import Contour, Outline

__all__ = ["outline_from_lists", "png_of_mask"]


def _per_knot(rows, k, n, default):
    """Row ``k`` of a per-knot table when it has ``n`` entries, else ``default``."""
    return rows[k] if k < len(rows) and isinstance(rows[k], list) and len(rows[k]) == n else default


def _contour_from_lists(contour, points, corners, tension, weights):
    points = np.asarray(points, dtype=float)
    if points.shape == contour.points.shape:
        candidate = contour if np.array_equal(points, contour.points) else contour.moved(np.arange(len(contour)), points)
    else:
        candidate = Contour(points)
    n = len(candidate)
    corners = np.asarray(corners if corners is not None and len(corners) == n else candidate.corners, dtype=object)
    if any(type(v) not in (bool, np.bool_) for v in corners.tolist()):
        raise TypeError("corner flags must be booleans")
    corners = corners.astype(bool)
    data = candidate.fields()
    became = corners & ~candidate.corners  # a new corner starts without handles (Contour.with_corner)
    data["handles_in"][became] = np.nan
    data["handles_out"][became] = np.nan
    data.update(corners=corners, point_tension=np.asarray(_or(tension, n, candidate.point_tension), float),
                interval_weights=np.asarray(_or(weights, n, candidate.interval_weights), float))
    return candidate.replace(**data)


def _or(values, n, default):
    return values if values is not None and len(values) == n else default


def outline_from_lists(outline: Outline, contours, corners, point_tension, interval_weights) -> Outline:
    """``outline`` with the knots, corner flags, tensions and weights of the editor's lists.

    Knots that moved keep their handles and rescale the steps of the changed intervals
    (:meth:`Contour.moved`); a contour whose knot count changed is rebuilt from its knots (chord steps).
    Raises ``TypeError``/``ValueError`` naming the contour for anything the outline refuses.
    """
    rows = (contours, corners, point_tension, interval_weights)
    if not all(isinstance(r, list) for r in rows):
        raise TypeError("contours, corners, point_tension and interval_weights must be lists")
    if len(contours) != len(outline):
        raise ValueError(f"contours must list {len(outline)} contours (add or remove contours with the outline's "
                         f"methods), got {len(contours)}")
    built = []
    for k, contour in enumerate(outline.contours):
        n = len(contours[k]) if isinstance(contours[k], list) else -1
        try:
            built.append(_contour_from_lists(contour, contours[k], _per_knot(corners, k, n, None),
                                             _per_knot(point_tension, k, n, None),
                                             _per_knot(interval_weights, k, n, None)))
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"contour {k}: {exc}") from None
    return outline.with_contours(built)


def png_of_mask(mask) -> bytes:
    """PNG bytes of a bool mask (ink dark grey on white); empty without a mask."""
    if mask is None:
        return b""
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(np.where(np.asarray(mask, bool), 40, 255).astype(np.uint8)).save(buffer, format="PNG")
    return buffer.getvalue()
