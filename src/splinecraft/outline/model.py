"""The editable outline: several closed contours (outer boundaries, holes, components) in one frame.

An :class:`Outline` is immutable: every edit and transform returns a new outline, rebuilding only the
contours it changed with the engine (:class:`~splinecraft.outline.contour.Contour`), so an edit history is
a list of outlines that share their unchanged contours. The frame is the bitmap's pixel frame of
docs/capture.md (x right, y down, ``width x height``).

Fill (the nesting rule). A contour is *nested* in another when it lies inside it as a whole (at least 90 % of
the samples of its curve inside the other and at most 10 % of the other's inside it, so a fitted hole that
grazes its outer curve at a thin wall stays a hole; :func:`nesting`); its nesting depth is
the number of contours it is nested in (:func:`nesting_depths`). Even depth is ink, odd depth a hole, and
contours that only partly overlap are not nested in each other, so overlapping outer contours fill as their
union. The stored orientation of a contour does not matter: the exports orient every contour by its depth
(:meth:`Outline.oriented_bezier`: outer contours positive signed area, holes negative), and with those
orientations the nonzero rule -- the rule of fonts and the SVG default -- draws exactly this fill (the even-odd
rule would punch a hole where outer contours overlap), so :meth:`Outline.to_svg` writes ``fill-rule="nonzero"``
and fonts use the same depths (:mod:`splinecraft.font`). Traced outlines never overlap; for them the rule is
the plain even-odd nesting of their boundaries.

Knots are addressed as ``(contour, knot)`` pairs; transforms take ``contours=`` (whole contours: exact
affine images, thesis section 3.3) and/or ``knots=`` (single knots); with neither they act on the whole shape.
"""
from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from .._validation import blank_text, check_number, file_path
from .bezier import curve_bounds
from .contour import Contour, _indices, _single_index
from .transforms import affine_parts, check_reach, reflection, rotation, scaling, shearing, translation

__all__ = ["Outline", "contour_deviation", "nesting_depths", "DEVIATION_SPACING"]

#: Curve samples per piece of the nesting test (:func:`nesting_depths`).
NESTING_SAMPLES = 16
#: Point x edge pairs per block of the vectorised ray test.
_RAY_BLOCK = 1 << 22
#: Curve sampling step (px) of the deviation measure.
DEVIATION_SPACING = 0.25
#: Most curve samples of one contour's deviation measure: a longer contour (a knot dragged a million pixels
#: away) is sampled more coarsely instead of filling the memory (65536 px of curve at the usual spacing).
MAX_DEVIATION_SAMPLES = 1 << 18
_FORMAT = "splinecraft.Outline"


def _sample_pieces(bezier, spacing, max_samples=MAX_DEVIATION_SAMPLES):
    """Points about ``spacing`` apart on every piece (ends included) and the piece of each point.

    At most about ``max_samples`` points in all (3 per piece at least): longer curves get a wider spacing.
    """
    lengths = np.hypot(*np.diff(bezier, axis=1).transpose(2, 0, 1)).sum(axis=1)
    spacing = max(spacing, float(lengths.sum()) / max_samples)
    counts = np.maximum(2, np.ceil(lengths / spacing).astype(np.int64)) + 1
    piece = np.repeat(np.arange(bezier.shape[0]), counts)
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    theta = (np.arange(piece.size) - first[piece]) / (counts[piece] - 1)
    one = 1.0 - theta
    weights = np.stack([one ** 3, 3 * one * one * theta, 3 * one * theta * theta, theta ** 3], axis=1)
    return np.einsum("nk,nkd->nd", weights, bezier[piece]), piece


def _ring(bezier, samples=NESTING_SAMPLES):
    """``samples`` points per piece of closed Bézier pieces ``(m, 4, 2)``, as a closed polygon ``(m samples, 2)``."""
    theta = np.linspace(0.0, 1.0, samples, endpoint=False)
    one = 1.0 - theta
    weights = np.stack([one ** 3, 3 * one * one * theta, 3 * one * theta * theta, theta ** 3], axis=1)
    return np.einsum("sk,pkd->psd", weights, np.asarray(bezier, float)).reshape(-1, 2)


def _inside(points, polygon):
    """Even-odd ray test of ``points`` (n, 2) against the closed ``polygon`` (m, 2), vectorised in blocks."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    rise = b[:, 1] - a[:, 1]
    slope = np.divide(b[:, 0] - a[:, 0], rise, out=np.zeros_like(rise), where=rise != 0)
    result = np.empty(len(points), bool)
    step = max(1, _RAY_BLOCK // max(len(polygon), 1))
    for start in range(0, len(points), step):
        x, y = points[start:start + step, :1], points[start:start + step, 1:]
        straddle = (a[:, 1] > y) != (b[:, 1] > y)
        crossing = a[:, 0] + (y - a[:, 1]) * slope
        result[start:start + step] = np.count_nonzero(straddle & (x < crossing), axis=1) % 2 == 1
    return result


#: Share of a contour's curve samples that must lie inside another for it to be nested there (:func:`nesting`).
NESTED_SHARE = 0.9


def nesting(curves) -> np.ndarray:
    """``inside[j, k]``: contour ``k`` lies inside contour ``j`` as a whole (closed Bézier pieces ``(m, 4, 2)``
    each): at least ``NESTED_SHARE`` of the curve samples of ``k`` are inside ``j`` and at most ``1 -
    NESTED_SHARE`` of those of ``j`` inside ``k``. Contours that only partly overlap are not nested either way
    (module docstring); a fitted hole that grazes its outer curve at a thin wall, within the fit's tolerance,
    is still nested."""
    rings = [_ring(b) for b in curves]
    low = np.array([r.min(axis=0) for r in rings]).reshape(-1, 2)
    high = np.array([r.max(axis=0) for r in rings]).reshape(-1, 2)
    inside = np.zeros((len(rings), len(rings)), bool)
    for j, outer in enumerate(rings):
        for k, inner in enumerate(rings):
            if j == k or (high[k] < low[j]).any() or (low[k] > high[j]).any():  # boxes apart
                continue
            inside[j, k] = (np.mean(_inside(inner, outer)) >= NESTED_SHARE
                            and np.mean(_inside(outer, inner)) <= 1.0 - NESTED_SHARE)
    return inside


def nesting_depths(curves) -> np.ndarray:
    """How many other contours each contour lies inside as a whole (:func:`nesting`): even = ink, odd = hole."""
    return nesting(curves).sum(axis=0).astype(int)


def contour_deviation(contour, source, spacing=DEVIATION_SPACING) -> np.ndarray:
    """Max distance (px) of every piece of ``contour`` from the closed source polyline ``source`` (M, 2).

    Both directions, as in the fit's own measure (``capture.fitting.piece_deviation``): curve samples to the
    polyline, and the polyline's vertices and edge midpoints to the sampled curve, each attributed to the piece
    of its nearest curve sample. An upper bound of the Hausdorff distance up to the sampling (``spacing / 2``).
    """
    from scipy.spatial import cKDTree

    from ..capture.fitting import polyline_distance

    samples, piece = _sample_pieces(contour.bezier(), spacing)
    source = np.asarray(source, float)
    result = np.zeros(len(contour))
    np.maximum.at(result, piece, polyline_distance(samples, source, closed=True))
    probes = np.vstack([source, 0.5 * (source + np.roll(source, -1, axis=0))])
    to_curve = polyline_distance(probes, samples, closed=True)
    _, nearest = cKDTree(samples).query(probes)
    np.maximum.at(result, piece[nearest], to_curve)
    return result


def _source(value, name) -> np.ndarray:
    """A source contour: a finite ``(M, 2)`` float array (a closed polyline, :func:`contour_deviation`)."""
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be an (M, 2) array of numbers (a closed polyline) or None") from None
    if array.ndim != 2 or array.shape[1] != 2 or array.shape[0] < 2:
        raise ValueError(f"{name} must have shape (M, 2) with M >= 2 (a closed polyline), got {array.shape}")
    if not np.isfinite(array).all():
        raise ValueError(f"{name} has non-finite coordinates")
    return array


def _default_extent(high, axis, name):
    """The frame's default ``name`` (width or height): the curves' largest ``axis`` coordinate ``high`` rounded up,
    plus a margin of 1. The frame starts at the origin, so curves that lie wholly below it have none."""
    extent = float(math.ceil(high) + 1)
    if not extent > 0:
        raise ValueError(f"the curves lie at {axis} < 0 (at most {high:g}), and an outline's frame runs from 0 to its "
                         f"{name}: translate them to {axis} >= 0 or give {name}= (an SVG: a viewBox that covers them)")
    return extent


class Outline:
    """Closed contours in one frame, with the source contours and bitmap they were captured from.

    Parameters
    ----------
    contours : sequence of Contour
    width, height : float, optional
        The frame (default: the bounding box of the curves, rounded up, with a margin of 1).
    sources : sequence of (M, 2) arrays or None, optional
        Per contour, the closed polyline it was fitted to (for :meth:`deviation`).
    bitmap : (H, W) bool array, optional
        The binarized image it came from (drawn under the editor).
    baseline : float, optional
        y of the baseline in the frame (fonts; default: the bottom of the curves).
    name : str, optional
    """

    def __init__(self, contours, *, width=None, height=None, sources=None, bitmap=None, baseline=None, name=None):
        contours = tuple(contours)
        if not contours:
            raise ValueError("an outline needs at least one contour")
        for k, contour in enumerate(contours):
            if not isinstance(contour, Contour):
                raise TypeError(f"contours[{k}] must be a Contour, got {type(contour).__name__}")
        if sources is None:
            sources = (None,) * len(contours)
        sources = tuple(sources)
        if len(sources) != len(contours):
            raise ValueError(f"sources must have one entry per contour ({len(contours)}), got {len(sources)}")
        sources = tuple(None if s is None else _source(s, f"sources[{k}]") for k, s in enumerate(sources))
        self.contours = contours
        self.sources = sources
        self.bitmap = None if bitmap is None else np.asarray(bitmap, bool)
        low, high = self.bounds()
        width = width if width is not None else _default_extent(high[0], "x", "width")
        height = height if height is not None else _default_extent(high[1], "y", "height")
        # checked here, not at export: a NaN baseline from a JSON file failed in font.build as "cannot convert
        # float NaN to integer", a name of another type in to_svg
        self.width = check_number(width, "width", minimum=0.0, inclusive=False)
        self.height = check_number(height, "height", minimum=0.0, inclusive=False)
        self.baseline = None if baseline is None else check_number(baseline, "baseline")
        if not (name is None or isinstance(name, str)):
            raise TypeError(f"name must be a string or None, got {type(name).__name__}")
        if name and blank_text(name):  # '' stays "no name"; ' ' became an SVG title of spaces and a glyph key error
            raise ValueError(f"name is {blank_text(name)}: give a name, or None for none")
        self.name = name

    def _with(self, contours, sources=None, **changes) -> "Outline":
        options = {"width": self.width, "height": self.height, "bitmap": self.bitmap, "baseline": self.baseline,
                   "name": self.name}
        options.update(changes)
        return Outline(contours, sources=self.sources if sources is None else sources, **options)

    def with_contours(self, contours, sources=None) -> "Outline":
        """The same frame, bitmap and (unless given) sources with other contours."""
        return self._with(contours, sources)

    def __repr__(self):
        knots = sum(len(c) for c in self.contours)
        corners = sum(int(c.corners.sum()) for c in self.contours)
        return (f"Outline({len(self.contours)} contours, {knots} knots, {corners} corners, "
                f"frame {self.width:g} x {self.height:g})")

    def __len__(self):
        return len(self.contours)

    # ------------------------------------------------------------------ geometry
    def bezier(self) -> list:
        """Bézier control points of every contour, a list of ``(N_k, 4, 2)`` arrays."""
        return [contour.bezier() for contour in self.contours]

    def splines(self) -> list:
        """The closed :class:`~splinecraft.spline.Spline` of every contour."""
        return [contour.spline for contour in self.contours]

    def bounds(self):
        """``(low, high)`` corners of the control points' bounding box (contains the curves)."""
        points = np.concatenate([b.reshape(-1, 2) for b in self.bezier()])
        return points.min(axis=0), points.max(axis=0)

    def curve_bounds(self):
        """``(low, high)`` corners of the curves' own (tight) bounding box, from the cubic extrema
        (:func:`~splinecraft.outline.bezier.curve_bounds`); inside :meth:`bounds`."""
        return curve_bounds(self.bezier())

    def nesting_depths(self) -> np.ndarray:
        """Per contour, how many others it lies inside as a whole (module docstring): even = ink, odd = hole."""
        return nesting_depths(self.bezier())

    def oriented_bezier(self) -> list:
        """:meth:`bezier` with every contour oriented by its nesting depth: outer contours (even depth) with
        positive signed area in the frame, holes negative (a contour running the other way is reversed). Drawn
        with the nonzero rule this is the outline's fill, overlapping outer contours included."""
        from .contour import bezier_signed_area

        curves = self.bezier()
        for k, depth in enumerate(nesting_depths(curves)):
            if (bezier_signed_area(curves[k]) > 0) != (depth % 2 == 0):
                curves[k] = curves[k][::-1, ::-1].copy()
        return curves

    def knot_points(self) -> list:
        return [np.array(contour.points) for contour in self.contours]

    def deviation(self) -> list:
        """Per contour, the max distance (px) of each piece from its source contour (``None`` without one)."""
        return [None if source is None else contour_deviation(contour, source)
                for contour, source in zip(self.contours, self.sources)]

    def max_deviation(self):
        """The largest piece deviation over all contours with a source (``None`` when none has one)."""
        values = [d.max() for d in self.deviation() if d is not None]
        return float(max(values)) if values else None

    def nearest_point(self, point):
        """``(contour, piece, theta, distance)`` of the curve point closest to ``point`` (``Spline.nearest``)."""
        best = None
        for k, spline in enumerate(self.splines()):
            found = spline.nearest(point)
            if best is None or found.distance < best[3]:
                knots = spline.knots
                theta = (found.parameter - knots[found.piece]) / (knots[found.piece + 1] - knots[found.piece])
                best = (k, int(found.piece), float(min(max(theta, 0.0), 1.0)), float(found.distance))
        return best

    # ------------------------------------------------------------------ edits
    def _contour_index(self, contour, name="contour"):
        """One contour index (negative ones count from the end); a list, a float or one out of range is an
        error naming ``name``, never its first item or another contour."""
        return _single_index(contour, len(self.contours), name, "an outline of {n} contours")

    def _replace(self, changes: dict) -> "Outline":
        contours = list(self.contours)
        for k, contour in changes.items():
            contours[k] = contour
        return self._with(contours)

    def replace_contour(self, contour, new) -> "Outline":
        k = self._contour_index(contour)
        if not isinstance(new, Contour):
            raise TypeError(f"the new contour must be a Contour, got {type(new).__name__}")
        return self._replace({k: new})

    def move_knot(self, contour, knot, position) -> "Outline":
        """Knot ``knot`` of contour ``contour`` moved to ``position`` (x, y)."""
        k = self._contour_index(contour)
        return self._replace({k: self.contours[k].moved(knot, position)})

    def move_handle(self, contour, knot, side, position) -> "Outline":
        """The ``side`` handle ("in" or "out") of corner ``knot`` ends at ``position`` (x, y); see
        :meth:`Contour.with_handle`."""
        k = self._contour_index(contour)
        return self._replace({k: self.contours[k].with_handle(knot, side, position)})

    def set_corner(self, contour, knot, corner=True, *, keep_shape=False) -> "Outline":
        """Toggle a knot between corner and smooth (GC² joint); see :meth:`Contour.with_corner`."""
        k = self._contour_index(contour)
        return self._replace({k: self.contours[k].with_corner(knot, corner, keep_shape=keep_shape)})

    def insert_knot(self, contour, piece, theta=0.5) -> "Outline":
        """A knot inserted on a piece at its local parameter ``theta``; it becomes knot ``piece + 1``."""
        k = self._contour_index(contour)
        return self._replace({k: self.contours[k].inserted(piece, theta)})

    def delete_knot(self, contour, knot) -> "Outline":
        """Knot deleted; refused (``ValueError``) when the contour would keep fewer than 3 knots."""
        k = self._contour_index(contour)
        return self._replace({k: self.contours[k].removed(knot)})

    def set_point_tension(self, contour, knots, value) -> "Outline":
        k = self._contour_index(contour)
        return self._replace({k: self.contours[k].with_point_tension(knots, value)})

    def set_interval_weight(self, contour, pieces, value) -> "Outline":
        k = self._contour_index(contour)
        return self._replace({k: self.contours[k].with_interval_weight(pieces, value)})

    def remove_contour(self, contour) -> "Outline":
        k = self._contour_index(contour)
        if len(self.contours) == 1:
            raise ValueError("cannot remove the only contour of an outline")
        keep = [j for j in range(len(self.contours)) if j != k]
        return self._with([self.contours[j] for j in keep], sources=[self.sources[j] for j in keep])

    def add_contour(self, contour, source=None) -> "Outline":
        if not isinstance(contour, Contour):
            contour = Contour(contour)
        return self._with([*self.contours, contour], sources=[*self.sources, source])

    # ------------------------------------------------------------------ transforms (thesis section 3.3)
    def _selection(self, contours, knots):
        """contour index -> knot indices (``None`` = the whole contour). Neither ``contours`` nor ``knots`` given
        selects the whole shape; given but empty (``[]``) selects nothing, which is refused (ValueError)."""
        if contours is None and knots is None:
            return {k: None for k in range(len(self.contours))}
        chosen = {}
        if isinstance(contours, (str, bytes, dict)):
            raise TypeError(f"contours must be a contour index or a list of them, got {type(contours).__name__}")
        for position, c in enumerate([] if contours is None else np.atleast_1d(np.asarray(contours, dtype=object))):
            chosen[self._contour_index(c, f"contours[{position}]")] = None
        if isinstance(knots, (str, bytes, dict)):
            raise TypeError(f"knots must be a list of (contour, knot) pairs, got {type(knots).__name__}")
        pairs = []
        for position, pair in enumerate([] if knots is None else knots):
            if isinstance(pair, (str, bytes)) or not hasattr(pair, "__len__") or len(pair) != 2:
                raise ValueError(f"knots must be (contour, knot) pairs, got knots[{position}] = {pair!r:.40}")
            k = self._contour_index(pair[0], f"knots[{position}][0] (a contour)")
            pairs.append((k, _single_index(pair[1], len(self.contours[k]), f"knots[{position}][1] (a knot)",
                                           f"contour {k} of {{n}} knots")))
        for k, index in pairs:
            if not (k in chosen and chosen[k] is None):
                chosen.setdefault(k, set()).add(index)
        if not chosen:
            raise ValueError("the selection is empty (contours=" + repr(contours) + ", knots=" + repr(knots)
                             + "): give contour indices or (contour, knot) pairs, or neither for the whole shape")
        for k, value in chosen.items():
            if value is not None and len(value) == len(self.contours[k]):
                chosen[k] = None
        return chosen

    def selection_center(self, contours=None, knots=None):
        """Centre of the bounding box of the selected knots (the default pivot of the transforms)."""
        selected = self._selection(contours, knots)
        points = np.concatenate([self.contours[k].points if knots_ is None else self.contours[k].points[sorted(knots_)]
                                 for k, knots_ in selected.items()])
        return (points.min(axis=0) + points.max(axis=0)) / 2.0

    def transform(self, matrix, *, contours=None, knots=None) -> "Outline":
        """Affine map (2x3 or 3x3 matrix) of the selected knots and their handles (the whole shape by
        default). The selected knots land exactly where the map sends them and keep their class (smooth or
        corner); whole contours, and runs between two corners whose knots are all selected, map exactly (the
        new curve is the affine image of the old one; :meth:`Contour.transformed`). Singular or non-finite
        matrices, and maps that take a coordinate beyond ±``transforms.MAX_COORDINATE``, raise ``ValueError``."""
        linear, offset = affine_parts(matrix)
        selected = self._selection(contours, knots)
        changes = {}
        for k, index in selected.items():
            check_reach(self.contours[k].bezier() @ linear.T + offset)  # (the image of every control point)
            try:
                changes[k] = self.contours[k].transformed(linear, offset, None if index is None else sorted(index))
            except ValueError as exc:  # e.g. a scale so small that knots merge in float64
                raise ValueError(f"the transform leaves contour {k} invalid: {exc}") from None
        return self._replace(changes)

    def _pivot(self, center, contours, knots):
        return self.selection_center(contours, knots) if center is None else np.asarray(center, float).reshape(2)

    def translate(self, dx, dy, *, contours=None, knots=None) -> "Outline":
        return self.transform(translation(dx, dy), contours=contours, knots=knots)

    def rotate(self, degrees, *, center=None, contours=None, knots=None) -> "Outline":
        """Rotation by ``degrees`` (clockwise on screen, y down) about ``center`` (default: the selection's)."""
        return self.transform(rotation(degrees, self._pivot(center, contours, knots)), contours=contours, knots=knots)

    def scale(self, sx, sy=None, *, center=None, contours=None, knots=None) -> "Outline":
        """Uniform (``sy=None``) or per-axis scale about ``center``."""
        return self.transform(scaling(sx, sy, self._pivot(center, contours, knots)), contours=contours, knots=knots)

    def shear(self, kx, ky=0.0, *, center=None, contours=None, knots=None) -> "Outline":
        """Shear ``x' = x + kx y``, ``y' = y + ky x`` about ``center``."""
        return self.transform(shearing(kx, ky, self._pivot(center, contours, knots)), contours=contours, knots=knots)

    def slant(self, degrees, *, center=None, contours=None, knots=None) -> "Outline":
        """Italic slant: the top leans right by ``degrees`` (a shear ``kx = -tan(degrees)`` in the y-down frame)."""
        return self.shear(-math.tan(math.radians(degrees)), 0.0, center=center, contours=contours, knots=knots)

    def reflect(self, axis="vertical", *, center=None, contours=None, knots=None) -> "Outline":
        """Mirror about a line through ``center``: ``"vertical"``, ``"horizontal"`` or an angle in degrees."""
        return self.transform(reflection(axis, self._pivot(center, contours, knots)), contours=contours, knots=knots)

    # ------------------------------------------------------------------ export
    def svg_path_data(self, *, decimals=4) -> str:
        from ..spline.svg import path_data

        return path_data(self.oriented_bezier(), decimals=decimals)

    def to_svg(self, *, decimals=4, fill="black", title=None) -> str:
        """Standalone SVG: one ``<path>`` of exact cubic Béziers oriented by nesting (:meth:`oriented_bezier`),
        ``fill-rule="nonzero"`` (overlapping outer contours fill as their union; module docstring), in the frame
        (``width``/``height``/``viewBox``); ``decimals=None`` writes exact floats. A ``title`` (default the
        name) or ``fill`` with a character XML cannot hold (a control character) is a ``ValueError``."""
        from ..spline.svg import svg_document

        title = title if title is not None else self.name
        width, height = int(math.ceil(self.width)), int(math.ceil(self.height))
        return svg_document(self.svg_path_data(decimals=decimals), width, height, fill=fill, title=title,
                            fill_rule="nonzero")

    def save_svg(self, path, **options) -> Path:
        """Write :meth:`to_svg` to ``path``; returns the path. A blank ``path`` ('' is the current folder to
        ``pathlib``, ' ' a file called space) is a ``ValueError``."""
        path = file_path(path, "outline.svg")
        path.write_text(self.to_svg(**options), encoding="utf-8")
        return path

    def to_dict(self, *, include_sources=True) -> dict:
        """Plain JSON types: the contours exactly (knots, corners, handles, steps, tensions, weights), the frame
        and, optionally, the source contours (the bitmap is not stored)."""
        data = {"type": _FORMAT, "version": 1, "width": self.width, "height": self.height,
                "baseline": self.baseline, "name": self.name,
                "contours": [contour.to_dict() for contour in self.contours]}
        if include_sources:
            data["sources"] = [None if s is None else s.tolist() for s in self.sources]
        return data

    def to_json(self, *, indent=None, include_sources=True) -> str:
        return json.dumps(self.to_dict(include_sources=include_sources), indent=indent, allow_nan=False)

    @classmethod
    def from_dict(cls, data) -> "Outline":
        if not isinstance(data, dict):
            raise TypeError(f"from_dict expects a dict, got {type(data).__name__}")
        if data.get("type") != _FORMAT:
            raise ValueError(f"not a {_FORMAT} dict: type={data.get('type')!r}")
        if data.get("version", 1) != 1:
            raise ValueError(f"{_FORMAT} version {data.get('version')!r} is not read (this splinecraft reads version 1)")
        if "contours" not in data or not isinstance(data["contours"], list):
            raise ValueError("an outline dict needs a list 'contours'")
        contours = []
        for k, entry in enumerate(data["contours"]):
            try:
                contours.append(Contour.from_dict(entry))
            except (TypeError, ValueError) as exc:
                raise type(exc)(f"contours[{k}]: {exc}") from None
        return cls(contours, width=data.get("width"), height=data.get("height"), sources=data.get("sources"),
                   baseline=data.get("baseline"), name=data.get("name"))

    @classmethod
    def from_json(cls, text) -> "Outline":
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"not valid JSON: {exc}") from None
        return cls.from_dict(data)
