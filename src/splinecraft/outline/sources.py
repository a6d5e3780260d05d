"""Outlines from a trace, from SVG, from knot lists and from Bézier curves (:func:`as_outline` picks one).

* :func:`from_trace`: a :class:`~splinecraft.capture.trace.TraceResult` (or one of its iterations): every
  boundary's curve exactly (:func:`~splinecraft.outline.bezier.contour_from_bezier`, with the trace's corners
  as corners), its contour polyline as the source for the deviation, and the bitmap.
* :func:`from_svg`: a file, a document or bare path data of closed cubic / line subpaths, such as the
  project's own exports and potrace's (``transform`` attributes of the path and its groups are applied;
  numbers follow the SVG grammar, exponents included; the written precision is taken as rounding, so
  smooth knots of a rounded export stay smooth).
  Arcs, quadratic and smooth commands are refused naming the subpath; so are unclosed subpaths unless
  ``close_open=True`` (a straight closing segment is added).
* :func:`from_knots`: contours given as knots with corner flags.
"""
from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from .bezier import contour_from_bezier, drop_degenerate_pieces
from .contour import Contour
from .model import Outline

__all__ = ["as_outline", "from_trace", "from_svg", "from_knots", "from_bezier"]

_SVG_NS = "{http://www.w3.org/2000/svg}"
_SUPPORTED = set("MmCcLlHhVvZz")
#: Path data: a moveto command and its first coordinate (SVG 1.1 section 8.3.9: every path starts so).
_PATH_DATA = re.compile(r"\s*[Mm]\s*[-+.\d]")


def from_bezier(curves, *, corners=None, rounding=0.0, **frame) -> Outline:
    """An outline of closed Bézier curves (a list of ``(m, 4, 2)`` arrays), reproduced exactly.

    ``corners`` (optional): per curve, booleans forcing corners at its knots. ``rounding`` (optional): how far
    the coordinates may be from the exact curves (rounded text); smooth knots bent by it stay smooth and
    the outline is within a few times ``rounding`` of the curves
    (:func:`~splinecraft.outline.bezier.contour_from_bezier`). ``frame``: keyword arguments of
    :class:`Outline` (``width``, ``height``, ``sources``, ``bitmap``, ``baseline``, ``name``).
    """
    contours = []
    for k, curve in enumerate(curves):
        bezier = np.asarray(curve, float)
        if bezier.ndim != 3 or bezier.shape[1:] != (4, 2):
            raise ValueError(f"curves[{k}] must have shape (m, 4, 2), got {bezier.shape}")
        if not np.isfinite(bezier).all():
            raise ValueError(f"curves[{k}] has non-finite coordinates")
        forced = None if corners is None else corners[k]
        if forced is None:
            bezier = drop_degenerate_pieces(bezier)
        if bezier.shape[0] == 0:
            raise ValueError(f"curves[{k}] has no piece of non-zero length")
        if not np.allclose(bezier[-1, 3], bezier[0, 0], rtol=0, atol=1e-9 * max(1.0, np.abs(bezier).max())):
            raise ValueError(f"curves[{k}] is not closed: it ends at {bezier[-1, 3].tolist()}, not at its start "
                             f"{bezier[0, 0].tolist()}")
        contours.append(contour_from_bezier(bezier, forced, rounding=rounding))
    return Outline(contours, **frame)


def _trace_corners(corners_used, knot_indices, pieces):
    """Corner flags of one boundary's Bézier knots: the starts of the fit's pieces (none without corners)."""
    mask = np.zeros(pieces, bool)
    if corners_used is None or len(corners_used) == 0:
        return mask
    counts = [len(np.asarray(k).reshape(-1)) - 1 for k in knot_indices]
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.intp)
    mask[starts[starts < pieces]] = True
    return mask


def from_trace(result, iteration=None, *, name=None) -> Outline:
    """The outline of a :class:`~splinecraft.capture.trace.TraceResult` (its final curves, or those of
    ``result.snapshots[iteration]``), with the contour polylines as sources and the bitmap."""
    if iteration is None:
        curves = [spline.bezier() for spline in result.splines]
        knot_lists = [fit.knot_indices for fit in result.fits]
    else:
        snapshot = result.snapshots[iteration]
        curves = [np.asarray(s.bezier, float) for s in snapshot.snapshots]
        knot_lists = [s.knot_indices for s in snapshot.snapshots]
    corners = [_trace_corners(fit.corners_used, knot_indices, len(curve))
               for fit, knot_indices, curve in zip(result.fits, knot_lists, curves)]
    return from_bezier(curves, corners=corners, width=result.width, height=result.height,
                       sources=[np.asarray(p, float) for p in result.points], bitmap=result.mask, name=name)


def from_knots(contours, **frame) -> Outline:
    """An outline of contours given as knots: each item an ``(N, 2)`` array (all smooth), a
    ``(points, corners)`` pair, a dict of :class:`Contour` fields, or a :class:`Contour`."""
    if isinstance(contours, np.ndarray) and contours.ndim == 2:
        contours = [contours]
    built = []
    for k, item in enumerate(contours):
        try:
            if isinstance(item, Contour):
                built.append(item)
            elif isinstance(item, dict):
                built.append(Contour.from_dict(item))
            elif isinstance(item, (tuple, list)) and len(item) == 2 and np.ndim(item[1]) == 1 and np.ndim(item[0]) == 2:
                built.append(Contour(item[0], item[1]))
            else:
                built.append(Contour(item))
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"contours[{k}]: {exc}") from None
    return Outline(built, **frame)


# ---------------------------------------------------------------------------------------------- SVG
def _transform_matrix(text):
    """3x3 matrix of an SVG ``transform`` attribute (matrix, translate, scale, rotate, skewX, skewY)."""
    matrix = np.eye(3)
    for name, arguments in re.findall(r"(matrix|translate|scale|rotate|skewX|skewY)\s*\(([^)]*)\)", text or ""):
        values = [float(v) for v in re.split(r"[\s,]+", arguments.strip()) if v]
        step = np.eye(3)
        if name == "matrix" and len(values) == 6:
            step[:2] = np.array(values).reshape(3, 2).T
        elif name == "translate":
            step[:2, 2] = [values[0], values[1] if len(values) > 1 else 0.0]
        elif name == "scale":
            step[0, 0], step[1, 1] = values[0], values[1] if len(values) > 1 else values[0]
        elif name == "rotate":
            angle = np.radians(values[0])
            cx, cy = (values[1], values[2]) if len(values) == 3 else (0.0, 0.0)
            rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
            step[:2, :2] = rot
            step[:2, 2] = np.array([cx, cy]) - rot @ [cx, cy]
        elif name == "skewX":
            step[0, 1] = np.tan(np.radians(values[0]))
        elif name == "skewY":
            step[1, 0] = np.tan(np.radians(values[0]))
        else:
            raise ValueError(f"cannot read the SVG transform {name}({arguments})")
        matrix = matrix @ step
    return matrix


def _paths(element, matrix, found):
    matrix = matrix @ _transform_matrix(element.get("transform"))
    tag = element.tag.replace(_SVG_NS, "")
    if tag == "path":
        found.append((element.get("d", ""), matrix))
    elif tag in ("rect", "circle", "ellipse", "polygon", "polyline", "line"):
        raise ValueError(f"SVG <{tag}> elements are not read; convert them to <path> first")
    for child in element:
        _paths(child, matrix, found)


def _check_commands(d, where):
    """Refuse commands the reader does not convert, naming the subpath they are in. The data is split into
    tokens as the SVG path grammar reads it (:func:`~splinecraft.capture.svg.parse_path_data`), so the ``e``
    of a number's exponent (``1e-05``) is part of the number, not a command."""
    from ..capture.svg import _TOKEN

    subpath = -1
    for command in (token for token in _TOKEN.findall(d) if token.isalpha()):
        if command in "Mm":
            subpath += 1
        elif command not in _SUPPORTED:
            kind = {"A": "an elliptical arc", "Q": "a quadratic Bézier", "T": "a smooth quadratic",
                    "S": "a smooth cubic"}.get(command.upper(), "an unknown command")
            raise ValueError(f"{where}subpath {max(subpath, 0)} uses {kind} ({command!r}), which is not converted; "
                             "convert it to cubic Béziers (C) and lines (L) first")


def _is_file(text):
    """Whether ``text`` names an existing file (False for text no file can be named by: too long, NUL)."""
    try:
        return Path(text).is_file()
    except (OSError, ValueError):
        return False


def _is_inline(source):
    """Whether the string ``source`` is an SVG document or path data rather than a file name: it starts
    with ``<``, or it reads as path data (a moveto and a number) and names no existing file."""
    if not isinstance(source, str):
        return False
    return source.lstrip().startswith("<") or (bool(_PATH_DATA.match(source)) and not _is_file(source))


#: A number of SVG path data: mantissa digits after the point, and the exponent.
_NUMBER = re.compile(r"[-+]?(?:\d+\.?(\d*)|\.(\d+))(?:[eE]([-+]?\d+))?")


def _rounding(d):
    """Half a unit of the finest decimal place written in the path data ``d``: how far its numbers may be
    from the exact ones if they were rounded (writers round to a fixed number of places and drop
    trailing zeros, so the finest place is the one they kept)."""
    places = [len(point or fraction) - int(exponent or 0) for point, fraction, exponent in _NUMBER.findall(d)]
    return 0.5 * 10.0 ** -max(places) if places else 0.0


def from_svg(source, *, close_open=False, name=None) -> Outline:
    """An outline from an SVG file path, an SVG document or bare path data (see the module docstring).

    A string is a document when it starts with ``<``, path data when it starts with a moveto and a number
    (``"M 0,0 ..."``) unless a file of that name exists, and else a file name (``"moon.svg"``).
    The frame is the document's ``width``/``height`` (or its ``viewBox`` size); path data alone gets the
    bounding box of its curves. Numbers written with few decimals (the default ``to_svg(decimals=4)``) are
    taken as rounded: knots whose handles are collinear up to that rounding stay smooth when a smooth
    contour reproduces the numbers within a few times the rounding (``rounding`` of :func:`from_bezier`).
    """
    from ..capture.svg import parse_path_data

    text = source
    if isinstance(source, os.PathLike) or (isinstance(source, str) and not _is_inline(source)):
        path = Path(os.fspath(source))
        if not _is_file(path):
            raise FileNotFoundError(f"no SVG file {str(path)!r}")
        text = path.read_text(encoding="utf-8")
    if not isinstance(text, str):
        raise TypeError(f"source must be a path, an SVG document or path data, got {type(source).__name__}")
    width = height = None
    if text.lstrip().startswith("<"):
        try:
            root = ET.fromstring(text.encode("utf-8") if text.lstrip().startswith("<?xml") else text)
        except ET.ParseError as exc:
            raise ValueError(f"not a readable SVG document: {exc}") from None
        found = []
        _paths(root, np.eye(3), found)
        width, height = _frame(root)
    else:
        found = [(text, np.eye(3))]
    curves, rounding = [], 0.0
    for p, (d, matrix) in enumerate(found):
        where = f"path {p}, " if len(found) > 1 else ""
        _check_commands(d, where)
        rounding = max(rounding, _rounding(d) * float(np.linalg.norm(matrix[:2, :2], 2)))
        for s, (bezier, closed) in enumerate(parse_path_data(d)):
            if not closed:
                if not close_open:
                    raise ValueError(f"{where}subpath {s} is not closed (no Z); close it, or pass close_open=True "
                                     "to add a straight closing segment")
                start, end = bezier[0, 0], bezier[-1, 3]
                if not np.allclose(start, end):
                    bezier = np.vstack([bezier, [[end, end + (start - end) / 3, end + 2 * (start - end) / 3, start]]])
            mapped = bezier @ matrix[:2, :2].T + matrix[:2, 2]
            curves.append(mapped)
    if not curves:
        raise ValueError("the SVG has no path with a closed subpath")
    return from_bezier(curves, rounding=rounding, width=width, height=height, name=name)


def _frame(root):
    def number(value):
        if value is None:
            return None
        match = re.match(r"\s*([-+]?\d*\.?\d+(?:[eE][-+]?\d+)?)", value)
        return float(match.group(1)) if match else None

    width, height = number(root.get("width")), number(root.get("height"))
    box = root.get("viewBox")
    if box and (width is None or height is None):
        values = [float(v) for v in re.split(r"[\s,]+", box.strip()) if v]
        if len(values) == 4:
            width, height = values[2], values[3]
    return width, height


# ---------------------------------------------------------------------------------------------- dispatch
def as_outline(source, **options) -> Outline:
    """An :class:`Outline` from any supported source.

    ``source``: an Outline (returned as is), an editor (its ``outline``), a TraceResult (``iteration=`` picks a
    snapshot), an SVG file / document / path data, a ``.json`` file or text of :meth:`Outline.to_json`, a list
    of contours of knots (:func:`from_knots`) or of closed Bézier arrays (:func:`from_bezier`).
    """
    from ..capture import TraceResult

    if isinstance(source, Outline):
        return source
    outline = getattr(source, "outline", None)
    if isinstance(outline, Outline):
        return outline
    if isinstance(source, TraceResult):
        return from_trace(source, **options)
    if isinstance(source, (str, os.PathLike)):
        text = os.fspath(source)
        if isinstance(source, str) and text.lstrip().startswith("{"):
            return Outline.from_json(text)
        if not _is_inline(source) and Path(text).suffix.lower() == ".json":
            if not _is_file(text):
                raise FileNotFoundError(f"no JSON file {text!r}")
            return Outline.from_json(Path(text).read_text(encoding="utf-8"))
        return from_svg(source, **options)
    if isinstance(source, (list, tuple)) and source and all(
            isinstance(item, np.ndarray) and item.ndim == 3 for item in source):
        return from_bezier(source, **options)
    if isinstance(source, (list, tuple, np.ndarray)):
        return from_knots(source, **options)
    raise TypeError(f"cannot make an outline from {type(source).__name__}: pass a TraceResult, an SVG, "
                    "a list of contours (knots with corner flags) or an Outline")
