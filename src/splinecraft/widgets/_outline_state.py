"""The OutlineEditor's pure parts: its synced lists <-> its outline, the checks of what the page sends
(selection pairs, transform matrices), the fitted view, and the bitmap it shows (PNG bytes)."""
from __future__ import annotations

import io

import numpy as np

from .._validation import plain
from ..outline import Contour, Outline
from ._editor_state import MAX_COORDINATE, check_reach

__all__ = ["OUTLINE_TRAITS", "MAX_COORDINATE", "DeviationCache", "check_outline_reach", "check_reach", "clean_selection", "fitted_view",
           "grouped_by_contour", "outline_from_lists", "page_matrix", "png_of_mask", "synced_tables"]

#: The synced lists that hold the outline, and the contour field each one shows (handles: ``[dx, dy]`` per corner,
#: ``None`` at smooth knots and at corners without a handle).
OUTLINE_TRAITS = {"contours": "points", "corners": "corners", "point_tension": "point_tension",
                  "interval_weights": "interval_weights", "handles_in": "handles_in", "handles_out": "handles_out"}
_HANDLES = ("handles_in", "handles_out")
#: How far (in sizes of the box of a contour's knots and handle ends) an edited contour's control points may
#: lie outside that box. The curve through a knot dropped (nearly) onto a neighbour with fixed handles takes
#: tangents of the order of the handle over the remaining gap: 4e-6 px apart, a 280-px glyph reached 1e7 px.
MAX_SPREAD = 10.0


def _spread(contour) -> float:
    """How far (px) the control points of ``contour`` lie outside the box of its knots and handle ends, in
    sizes of that box."""
    ends = [contour.points]
    for handles in (contour.handles_in, contour.handles_out):
        given = ~np.isnan(handles).any(axis=1)
        ends.append(contour.points[given] + handles[given])
    anchors = np.concatenate(ends)
    low, high = anchors.min(axis=0), anchors.max(axis=0)
    size = max(float((high - low).max()), 1e-300)
    control = contour.bezier().reshape(-1, 2)
    beyond = np.maximum(low - control, control - high).max()
    return max(float(beyond), 0.0) / size


def check_outline_reach(outline: Outline, before: Outline | None = None) -> Outline:
    """``outline`` when every control point of its pieces lies within ±:data:`MAX_COORDINATE` and, in each
    contour that is not one of ``before``'s (an edit's result against the outline it edited), within
    :data:`MAX_SPREAD` sizes of the box of the contour's knots and handle ends; else a ``ValueError`` naming the
    contour (and the point, as :func:`check_reach`)."""
    kept = set() if before is None else {id(contour) for contour in before.contours}
    for k, contour in enumerate(outline.contours):
        try:
            check_reach(contour.bezier(), "control point")
        except ValueError as exc:
            raise ValueError(f"contour {k}: {exc}") from None
        spread = 0.0 if id(contour) in kept else _spread(contour)
        if spread > MAX_SPREAD:
            raise ValueError(f"contour {k}: the edit would throw the curve {spread:.3g} times its size "
                             "beyond its knots and handles (a knot dropped onto its neighbour?)")
    return outline


def _row(contour, field) -> list:
    """The synced row of ``contour``'s ``field`` (handles: ``None`` where there is none)."""
    values = getattr(contour, field)
    if field in _HANDLES:
        return [None if np.isnan(h).any() else [float(h[0]), float(h[1])] for h in values]
    return values.tolist()


def _handles_of_row(row, name) -> np.ndarray:
    """The ``(n, 2)`` handles of a synced row: ``None`` (no handle) or two finite numbers per knot."""
    handles = np.full((len(row), 2), np.nan)
    for i, entry in enumerate(row):
        if entry is None:
            continue
        if (not isinstance(entry, (list, tuple)) or len(entry) != 2
                or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in entry)):
            raise TypeError(f"{name}[{i}] must be None or [dx, dy] (two numbers), got {plain(entry)!r:.40}")
        if not all(np.isfinite(entry)):
            raise ValueError(f"{name}[{i}] = {plain(list(entry))!r} must be finite")
        handles[i] = entry
    return handles


def _per_knot(rows, k, n, default):
    """Row ``k`` of a per-knot table when it has ``n`` entries, else ``default``."""
    return rows[k] if k < len(rows) and isinstance(rows[k], list) and len(rows[k]) == n else default


def _contour_from_lists(contour, points, corners, tension, weights, handles=(None, None)):
    points = np.asarray(points, dtype=float)
    if points.ndim == 2 and points.shape[1:] == (2,) and np.isfinite(points).all():
        check_reach(points)  # NaN and a wrong shape: the contour names them
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
    for name, row in zip(_HANDLES, handles):  # given rows set every handle (ignored at smooth knots)
        if row is not None:
            data[name] = _handles_of_row(row, name)
    data.update(corners=corners, point_tension=np.asarray(_or(tension, n, candidate.point_tension), float),
                interval_weights=np.asarray(_or(weights, n, candidate.interval_weights), float))
    return candidate.replace(**data)


def _or(values, n, default):
    return values if values is not None and len(values) == n else default


def outline_from_lists(outline: Outline, contours, corners, point_tension, interval_weights, handles_in=None,
                       handles_out=None, *, changed: str | None = None) -> Outline:
    """``outline`` with the knots, corner flags, tensions, weights and (when given) corner handles of the
    editor's lists.

    Knots that moved keep their handles and rescale the steps of the changed intervals
    (:meth:`Contour.moved`); a contour whose knot count changed is rebuilt from its knots (chord steps).
    Every list must have one row per contour of ``outline``; the rows of the list named ``changed`` (the one
    just set; not ``contours``) one entry per knot. Raises ``TypeError``/``ValueError`` naming the list or
    the contour for anything the outline refuses.
    """
    tables = {"contours": contours, "corners": corners, "point_tension": point_tension,
              "interval_weights": interval_weights, "handles_in": handles_in, "handles_out": handles_out}
    tables = {name: rows for name, rows in tables.items() if rows is not None or name not in _HANDLES}
    if not all(isinstance(r, list) for r in tables.values()):
        raise TypeError("contours, corners, point_tension, interval_weights and the handles must be lists")
    for name, rows in tables.items():
        if len(rows) != len(outline):
            raise ValueError(f"{name} must list {len(outline)} contours (add or remove contours with the outline's "
                             f"methods), got {len(rows)}")
    if changed in tables and changed != "contours":
        for k, row in enumerate(tables[changed]):
            n = len(contours[k]) if isinstance(contours[k], list) else len(outline.contours[k])
            if not isinstance(row, list) or len(row) != n:
                raise ValueError(f"{changed}[{k}] must be a list of {n} entries (one per knot of contour {k}), "
                                 f"got {_length(row)}")
    built = []
    for k, contour in enumerate(outline.contours):
        n = len(contours[k]) if isinstance(contours[k], list) else -1
        try:
            handles = tuple(None if rows_of is None else _per_knot(rows_of, k, n, None)
                            for rows_of in (handles_in, handles_out))
            built.append(_contour_from_lists(contour, contours[k], _per_knot(corners, k, n, None),
                                             _per_knot(point_tension, k, n, None),
                                             _per_knot(interval_weights, k, n, None), handles))
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"contour {k}: {exc}") from None
    return outline.with_contours(built)


def _length(row) -> str:
    return f"{len(row)} entries" if isinstance(row, list) else f"{type(row).__name__}"


def synced_tables(outline: Outline, current: dict, changed=None) -> dict:
    """The synced lists of ``outline`` (name -> table, see :data:`OUTLINE_TRAITS`) that differ from ``current``.

    With ``changed`` (contour indices) and tables of the outline's length, only those rows are rebuilt and a
    table whose rows did not change is left out; otherwise every table is rebuilt.
    """
    whole = changed is None or any(len(current[name]) != len(outline) for name in OUTLINE_TRAITS)
    rows = range(len(outline)) if whole else sorted(changed)
    tables = {}
    for name, field in OUTLINE_TRAITS.items():
        values = {k: _row(outline.contours[k], field) for k in rows}
        if whole:
            tables[name] = [values[k] for k in rows]
        elif any(current[name][k] != values[k] for k in rows):
            tables[name] = [values.get(k, row) for k, row in enumerate(current[name])]
    return tables


def clean_selection(value, sizes) -> list:
    """``value`` as distinct ``[contour, knot]`` pairs of integers, in order, for contours of ``sizes`` knots.

    Raises ``ValueError`` naming the first pair that is not two integers or not a knot of the outline.
    """
    cleaned = []
    for pair in value:
        if (not isinstance(pair, (list, tuple)) or len(pair) != 2
                or not all(isinstance(v, int) and not isinstance(v, bool) for v in pair)):
            raise ValueError(f"selection must be [contour, knot] pairs of integers, got {pair!r:.40}")
        if not (0 <= pair[0] < len(sizes) and 0 <= pair[1] < sizes[pair[0]]):
            raise ValueError(f"selection: no knot {pair[1]} in contour {pair[0]}")
        if list(pair) not in cleaned:
            cleaned.append([int(pair[0]), int(pair[1])])
    return cleaned


def grouped_by_contour(pairs) -> dict:
    """``[contour, knot]`` pairs as ``{contour: [knot, ...]}`` (first-seen order)."""
    groups = {}
    for contour, knot in pairs:
        groups.setdefault(contour, []).append(knot)
    return groups


def page_matrix(values) -> list:
    """The 2x3 matrix ``[[a, c, e], [b, d, f]]`` of a page's transform ``[a, b, c, d, e, f]`` (SVG order:
    ``x' = a x + c y + e``, ``y' = b x + d y + f``); ``ValueError`` unless it is six plain numbers."""
    if not isinstance(values, list) or len(values) != 6 or any(type(v) not in (int, float) for v in values):
        raise ValueError("matrix must be 6 numbers [a, b, c, d, e, f]")
    a, b, c, d, e, f = values
    return [[a, c, e], [b, d, f]]


def fitted_view(outline: Outline) -> list:
    """The data rectangle ``[x0, y0, x1, y1]`` that shows the outline (and its bitmap's frame, if it has one)
    with a 5 % margin."""
    low, high = outline.bounds()
    if outline.bitmap is not None:
        low = np.minimum(low, 0.0)
        high = np.maximum(high, [outline.width, outline.height])
    pad = 0.05 * float(max(high - low))
    return [float(low[0] - pad), float(low[1] - pad), float(high[0] + pad), float(high[1] + pad)]


class DeviationCache:
    """Piece deviations of each contour from its source contour, measured once per contour object."""

    def __init__(self):
        self._measured = {}  # contour index -> (contour, deviations)

    def get(self, outline: Outline, k: int, measure: bool = True):
        """Deviations of contour ``k``; ``None`` without a source, or when ``measure`` is False and the contour
        changed since it was measured (mid-gesture: measured when the gesture ends)."""
        contour, source = outline.contours[k], outline.sources[k]
        if source is None:
            return None
        cached = self._measured.get(k)
        if cached is None or cached[0] is not contour:
            if not measure:
                return None
            from ..outline import contour_deviation

            cached = self._measured[k] = (contour, contour_deviation(contour, source))
        return cached[1]


def png_of_mask(mask) -> bytes:
    """PNG bytes of a bool mask (ink dark grey on white); empty without a mask."""
    if mask is None:
        return b""
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(np.where(np.asarray(mask, bool), 40, 255).astype(np.uint8)).save(buffer, format="PNG")
    return buffer.getvalue()
