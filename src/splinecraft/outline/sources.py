"""Outlines from a trace, from SVG, from knot lists and from Bézier curves (:func:`as_outline` picks one).

* :func:`from_trace`: a :class:`~splinecraft.capture.trace.TraceResult` (or one of its iterations): every
  boundary's curve exactly (:func:`~splinecraft.outline.bezier.contour_from_bezier`, with the trace's corners
  as corners), its contour polyline as the source for the deviation, and the bitmap.
* :func:`from_svg`: a file, a document or bare path data of closed cubic / line subpaths, such as the
  project's own exports and potrace's (``transform`` attributes of the path and its groups are applied;
  numbers follow the SVG grammar, exponents included, in path data and transforms; an unknown or malformed
  transform is refused; the written precision is taken as rounding, so
  smooth knots of a rounded export stay smooth).
  Arcs, quadratic and smooth commands are refused naming the subpath; so are unclosed subpaths unless
  ``close_open=True`` (a straight closing segment is added).
  Only what a viewer draws is read (SVG 1.1/2 rendering rules): the content of ``<defs>``, ``<symbol>``,
  ``<mask>``, ``<clipPath>``, ``<marker>``, ``<pattern>`` (drawn only through references, which are not
  followed: ``<use>`` is ignored), elements of other XML namespaces and ``display="none"`` /
  ``style="display:none"`` subtrees are skipped (CSS ``<style>`` sheets are not read), and so are shapes
  with ``fill="none"`` (or ``transparent``; attribute or ``style``, inherited from their groups): a stroke
  encloses no ink, and a stroked frame read as a fill would turn the picture inside it into holes. Drawn basic shapes:
  ``<rect>`` (square corners) and ``<polygon>`` are read exactly as closed line subpaths, ``<polyline>`` as an
  open one; ``<circle>``, ``<ellipse>``, rounded ``<rect>`` (arcs, like ``A`` in path data) and ``<line>``
  (no area) are refused naming the element.
  The document's ``viewBox`` is applied (SVG 1.1 section 7.7, ``preserveAspectRatio`` included): curves and
  frame are in the coordinates a viewer shows at the document's ``width``/``height`` in px (unitless, px,
  in, cm, mm, pt, pc at 96 px to the inch; ``%`` reads as absent; other units are refused). A size in a
  physical unit with a viewBox (potrace writes ``pt``) is taken as a print size: the picture is read in the
  viewBox's units (see ``_frame``).
  The ``fill-rule`` of each path (attribute or ``style``, inherited from its groups; ``nonzero`` by default) is
  read into the outline's nesting rule (:mod:`splinecraft.outline.model`), which is direction-free: a contour
  inside another as a whole is a hole, partly overlapping contours fill as their union. Under ``evenodd`` the
  subpaths are taken as they are. Under ``nonzero`` overlapping subpaths of the same direction stay outer
  (their union, as the viewer draws them), and a subpath lying wholly inside others with ink on both of its
  sides (winding number nonzero inside and out, e.g. an inner contour drawn the same way as the outer one) adds
  nothing to the fill and is dropped. What neither rule can hold without boolean operations is not
  reproduced: the hole ``evenodd`` leaves where subpaths partly overlap, or a nonzero overlap of opposite
  directions. Bare path data has no fill rule; its subpaths are taken as they are.
* :func:`from_knots`: contours given as knots with corner flags.
"""
from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from .._validation import check_int
from .bezier import contour_from_bezier, drop_degenerate_pieces
from .contour import Contour
from .model import Outline
from .transforms import check_reach

__all__ = ["as_outline", "from_trace", "from_svg", "from_knots", "from_bezier"]

_SVG_NS = "{http://www.w3.org/2000/svg}"
_SUPPORTED = set("MmCcLlHhVvZz")
#: Path data: a moveto command and its first coordinate (SVG 1.1 section 8.3.9: every path starts so).
_PATH_DATA = re.compile(r"\s*[Mm]\s*[-+.\d]")


def from_bezier(curves, *, corners=None, rounding=0.0, **frame) -> Outline:
    """An outline of closed Bézier curves (a list of ``(m, 4, 2)`` arrays), reproduced exactly.

    ``corners`` (optional): per curve, booleans forcing corners at its knots. ``rounding`` (optional; one
    number, or one per curve): how far the coordinates may be from the exact curves (rounded text); smooth
    knots bent by it stay smooth and the outline is within a few times ``rounding`` of the curves
    (:func:`~splinecraft.outline.bezier.contour_from_bezier`). ``frame``: keyword arguments of
    :class:`Outline` (``width``, ``height``, ``sources``, ``bitmap``, ``baseline``, ``name``).
    """
    contours = []
    curves = list(curves)
    roundings = np.broadcast_to(np.asarray(rounding, dtype=float), (len(curves),)) if np.ndim(rounding) == 0 \
        else np.asarray(rounding, dtype=float)
    if roundings.shape != (len(curves),):
        raise ValueError(f"rounding must be one number or one per curve ({len(curves)}), got shape {roundings.shape}")
    for k, curve in enumerate(curves):
        bezier = np.asarray(curve, float)
        if bezier.ndim != 3 or bezier.shape[1:] != (4, 2):
            raise ValueError(f"curves[{k}] must have shape (m, 4, 2), got {bezier.shape}")
        if not np.isfinite(bezier).all():
            raise ValueError(f"curves[{k}] has non-finite coordinates")
        check_reach(bezier, f"curves[{k}]", given=True)  # before any area or length of it overflows
        forced = None if corners is None else np.asarray(corners[k])
        if forced is not None and forced.shape != (bezier.shape[0],):
            raise ValueError(f"corners[{k}] must hold one flag per knot of curves[{k}] ({bezier.shape[0]}), got "
                             f"shape {forced.shape}")
        if forced is None:
            bezier = drop_degenerate_pieces(bezier)
        if bezier.shape[0] == 0:
            raise ValueError(f"curves[{k}] has no piece of non-zero length")
        if not np.allclose(bezier[-1, 3], bezier[0, 0], rtol=0, atol=1e-9 * max(1.0, np.abs(bezier).max())):
            raise ValueError(f"curves[{k}] is not closed: it ends at {bezier[-1, 3].tolist()}, not at its start "
                             f"{bezier[0, 0].tolist()}")
        contours.append(contour_from_bezier(bezier, forced, rounding=roundings[k]))
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


def _snapshot_index(iteration, count) -> int:
    """``iteration`` checked against the ``count`` snapshots of a trace (negative ones count from the end)."""
    iteration = check_int(iteration, "iteration")
    if count == 0:
        raise ValueError(f"iteration={iteration}: the trace kept no snapshots (traced with keep_snapshots=False); "
                         "pass iteration=None for its final outline, or trace with keep_snapshots=True")
    if not -count <= iteration < count:
        raise ValueError(f"iteration={iteration} is out of range: the trace has {count} snapshots, iterations "
                         f"0..{count - 1} (negative values count from the last)")
    return iteration


def from_trace(result, iteration=None, *, name=None) -> Outline:
    """The outline of a :class:`~splinecraft.capture.trace.TraceResult` (its final curves, or those of
    ``result.snapshots[iteration]``), with the contour polylines as sources and the bitmap."""
    if iteration is None:
        curves = [spline.bezier() for spline in result.splines]
        knot_lists = [fit.knot_indices for fit in result.fits]
    else:
        snapshot = result.snapshots[_snapshot_index(iteration, len(result.snapshots))]
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
#: One transform function of an SVG ``transform`` list and the argument counts SVG 1.1 section 7.6 allows.
_TRANSFORM = re.compile(r"\s*,?\s*([A-Za-z]+)\s*\(([^)]*)\)\s*,?")
_TRANSFORM_ARGUMENTS = {"matrix": (6,), "translate": (1, 2), "scale": (1, 2), "rotate": (1, 3), "skewX": (1,),
                        "skewY": (1,)}


def _transform_matrix(text):
    """3x3 matrix of an SVG ``transform`` attribute (matrix, translate, scale, rotate, skewX, skewY).

    Arguments follow the SVG number grammar (``translate(10-5)`` is two numbers, as in path data); an unknown
    function (CSS's ``translateX``), a wrong count of arguments or text that is not a transform list is a
    ``ValueError`` naming it, since skipping it would place the curves wrongly."""
    matrix = np.eye(3)
    text = text or ""
    position = 0
    while position < len(text.rstrip()):
        found = _TRANSFORM.match(text, position)
        if found is None:
            raise ValueError(f"cannot read the SVG transform {text!r} at {text[position:position + 20]!r}")
        position = found.end()
        name, arguments = found.groups()
        values = [float(match.group(0)) for match in _NUMBER.finditer(arguments)]
        if name not in _TRANSFORM_ARGUMENTS or len(values) not in _TRANSFORM_ARGUMENTS[name] or (
                _NUMBER.sub(" ", arguments).replace(",", " ").strip()):
            raise ValueError(f"cannot read the SVG transform {name}({arguments}): SVG allows matrix(a b c d e f), "
                             "translate(x [y]), scale(x [y]), rotate(a [cx cy]), skewX(a), skewY(a)")
        step = np.eye(3)
        if name == "matrix":
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
        else:
            step[1, 0] = np.tan(np.radians(values[0]))
        matrix = matrix @ step
    return matrix


#: Elements whose content is never drawn by itself (templates and resources, drawn only through a reference:
#: ``<use>``, ``clip-path``, ``mask``, ``marker``, ``fill="url(...)"``), SVG 1.1 sections 5.3, 5.5, 11.6, 14.3, 14.4, 13.3.
_NOT_RENDERED = {"defs", "symbol", "mask", "clipPath", "marker", "pattern", "linearGradient", "radialGradient",
                 "filter", "metadata", "foreignObject", "title", "desc", "style", "script"}
#: CSS absolute lengths in px (CSS Values 3: 1in = 96px = 2.54cm = 72pt = 6pc).
_UNITS = {"": 1.0, "px": 1.0, "in": 96.0, "cm": 96.0 / 2.54, "mm": 9.6 / 2.54, "pt": 96.0 / 72.0, "pc": 16.0}
_LENGTH = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([a-zA-Z%]*)\s*$")


def _parse_length(element, attribute, *, percent=False):
    """The length attribute as ``(number, unit)`` (``None`` when absent): unitless or px, in, cm, mm, pt, pc
    (and ``%`` when ``percent``); other units are refused naming the element and attribute."""
    value = element.get(attribute)
    if value is None or value.strip() in ("", "auto"):
        return None
    match = _LENGTH.match(value)
    unit = match.group(2).lower() if match else None
    if unit not in _UNITS and not (unit == "%" and percent):
        tag = element.tag.replace(_SVG_NS, "")
        raise ValueError(f"<{tag}> {attribute}={value!r} is not read: lengths must be numbers, unitless or in "
                         f"px, in, cm, mm, pt or pc{' (or % for the document size)' if percent else ''}")
    return float(match.group(1)), unit


def _length(element, attribute):
    """The length attribute in px (96 px to the inch), ``None`` when absent (:func:`_parse_length`)."""
    length = _parse_length(element, attribute)
    return None if length is None else length[0] * _UNITS[length[1]]


def _hidden(element):
    """Whether ``display`` is ``none`` (the ``style`` property overrides the presentation attribute)."""
    display = element.get("display")
    for declaration in (element.get("style") or "").split(";"):
        key, _, value = declaration.partition(":")
        if key.strip().lower() == "display":
            display = value
    return display is not None and display.replace("!important", "").strip().lower() == "none"


def _shape_data(element, tag):
    """Path data (and the text its rounding is read from) of a drawn basic shape (SVG 1.1 section 9): ``<rect>`` (without rounded corners) and
    ``<polygon>`` as closed line subpaths, ``<polyline>`` as an open one; ``None`` when it draws nothing.
    Circles, ellipses, rounded rectangles (arcs) and lines (no area) are refused naming the element."""
    if tag in ("circle", "ellipse"):
        raise ValueError(f"SVG <{tag}> elements are not converted (their arcs would need an approximation); "
                         "convert them to <path> with cubic Béziers first")
    if tag == "line":
        raise ValueError("an SVG <line> encloses no area and is not read; draw the shape as a closed <path>")
    if tag == "rect":
        x, y = _length(element, "x") or 0.0, _length(element, "y") or 0.0
        width, height = _length(element, "width"), _length(element, "height")
        if any(_length(element, radius) for radius in ("rx", "ry")):
            raise ValueError("an SVG <rect> with rounded corners (rx/ry) is not converted (its corners are arcs); "
                             "convert it to <path> with cubic Béziers first")
        if width is None or height is None or width == 0 or height == 0:
            return None  # SVG 1.1 section 9.2: a zero width or height disables rendering
        if width < 0 or height < 0:
            raise ValueError(f"an SVG <rect> has a negative width or height ({width:g} x {height:g})")
        written = " ".join(element.get(name) or "0" for name in ("x", "y", "width", "height"))
        return f"M{x!r} {y!r} H{x + width!r} V{y + height!r} H{x!r} Z", written
    points = element.get("points", "")
    from ..capture.svg import _TOKEN

    values = _TOKEN.findall(points)
    if any(not _NUMBER.fullmatch(value) for value in values) or len(values) % 2:
        raise ValueError(f"SVG <{tag}> points must be an even count of numbers (x, y pairs), got {points!r}")
    if not values:
        return None
    return "M" + " ".join(values) + (" Z" if tag == "polygon" else ""), points


_FILL_RULE = re.compile(r"(?:^|;)\s*fill-rule\s*:\s*([A-Za-z]+)")


def _fill_rule(element, inherited):
    """The ``fill-rule`` of ``element``: its ``style`` declaration, else its attribute, else ``inherited``."""
    found = _FILL_RULE.search(element.get("style") or "")
    value = (found.group(1) if found else element.get("fill-rule") or "").strip().lower()
    return value if value in ("nonzero", "evenodd") else inherited


_FILL = re.compile(r"(?:^|;)\s*fill\s*:\s*([^;]*)")


def _fills(element, inherited):
    """Whether ``element`` paints its interior: its ``fill`` (``style`` declaration, else attribute, else
    ``inherited``; SVG 1.1 section 11.2, default black) is not ``none`` or ``transparent``. A stroked frame
    drawn with ``fill="none"`` around a picture encloses no ink."""
    found = _FILL.search(element.get("style") or "")
    value = (found.group(1) if found else element.get("fill") or "").replace("!important", "").strip().lower()
    if not value or value == "inherit":
        return inherited
    return value not in ("none", "transparent")


def _paths(element, matrix, found, viewport=None, rule="nonzero", fills=True, unfilled=None):
    """Collect ``(label, path data, matrix, written numbers, fill rule)`` of what ``element`` draws: its own and its
    groups' ``transform`` (and, for the document, ``viewport``: the viewBox mapping) applied, the ``fill-rule``
    inherited; elements that are
    never drawn (:data:`_NOT_RENDERED`, other XML namespaces) and ``display: none`` subtrees are skipped."""
    if element.tag.startswith("{") and not element.tag.startswith(_SVG_NS):
        return
    tag = element.tag.replace(_SVG_NS, "")
    if tag in _NOT_RENDERED or _hidden(element):
        return
    if tag == "svg" and viewport is None and any(element.get(key) for key in ("viewBox", "x", "y")):
        raise ValueError("a nested <svg> with its own viewBox or x/y is not read; flatten it into a group first")
    matrix = matrix @ _transform_matrix(element.get("transform"))
    if viewport is not None:
        matrix = matrix @ viewport
    rule = _fill_rule(element, rule)
    fills = _fills(element, fills)
    if not fills and tag != "g" and tag != "svg":
        if unfilled is not None:
            unfilled.append(tag)
        return  # an unfilled shape (a stroke only) draws no area; a group's children may fill again
    if tag == "path":
        found.append((f"path {len(found)}", element.get("d", ""), matrix, element.get("d", ""), rule))
    elif tag in ("rect", "circle", "ellipse", "polygon", "polyline", "line"):
        shape = _shape_data(element, tag)
        if shape is not None:
            found.append((f"<{tag}> (shape {len(found)})", shape[0], matrix, shape[1], rule))
    for child in element:
        _paths(child, matrix, found, rule=rule, fills=fills, unfilled=unfilled)


def _nonzero_covered(curves):
    """Indices of the subpaths of one nonzero-filled path that add nothing to its fill: each lies wholly inside
    others (:func:`~splinecraft.outline.model.nesting`) and the winding number of the path is nonzero on both of
    its sides (counting the subpaths it is nested in; partly overlapping ones do not change its sides' fill)."""
    from .contour import bezier_signed_area
    from .model import nesting

    inside = nesting(curves)
    turns = np.sign([bezier_signed_area(c) for c in curves]).astype(int)
    around = turns @ inside  # winding just outside each subpath, from those it lies in
    return [k for k in range(len(curves)) if around[k] != 0 and around[k] + turns[k] != 0]


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


#: Byte-order marks of UTF-16 and UTF-32 (an XML document in those encodings starts with one, or with ``<`` in them).
_WIDE_MARKS = (b"\xff\xfe", b"\xfe\xff", b"<\x00", b"\x00<")


def _file_text(path):
    """``(document, text)`` of an SVG file: an XML document as its bytes (``document``; the XML parser decodes
    them by their byte-order mark or declared encoding, UTF-8 by default) and ``text`` "" then; path data as
    UTF-8 text (``document`` None), a byte-order mark dropped."""
    raw = path.read_bytes()
    if raw.lstrip(b"\xef\xbb\xbf").lstrip().startswith(b"<") or raw.startswith(_WIDE_MARKS):
        return raw, ""
    try:
        return None, raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{str(path)!r} is neither an XML document nor UTF-8 path data ({exc.reason} at byte "
                         f"{exc.start})") from None


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
    The frame is the document's ``width``/``height`` in px (or its ``viewBox`` size), and the curves are mapped
    into it by the viewBox transform: ``viewBox="-20 -20 40 40"`` moves the origin to the frame's centre,
    ``width="200" viewBox="0 0 20 20"`` scales by 10; with a physical size (``width="40pt"``) the frame is
    in the viewBox's units. Path data alone gets the bounding box of its curves. Paths that are never drawn
    (in ``<defs>``, ``<clipPath>``, ... or under ``display:none``) are skipped; ``<rect>``/``<polygon>``/
    ``<polyline>`` are read as lines, other shapes refused (module docstring). Numbers written with few decimals (the default ``to_svg(decimals=4)``) are
    taken as rounded: knots whose handles are collinear up to that rounding stay smooth when a smooth
    contour reproduces the numbers within a few times the rounding (``rounding`` of :func:`from_bezier`).
    """
    from ..capture.svg import parse_path_data

    text = source.lstrip("\ufeff") if isinstance(source, str) else source  # a byte-order mark is no text
    if isinstance(source, str) and not text.strip():  # Path("") is ".", which reads as "no SVG file '.'"
        raise ValueError("the SVG source is empty: pass a file name, an SVG document or path data")
    document = None  # the bytes of a file that holds an XML document: the parser decodes them
    if isinstance(source, os.PathLike) or (isinstance(source, str) and not _is_inline(text)):
        path = Path(os.fspath(source))
        if not _is_file(path):
            raise FileNotFoundError(f"no SVG file {str(path)!r}")
        document, text = _file_text(path)
    if not isinstance(text, str):
        raise TypeError(f"source must be a path, an SVG document or path data, got {type(source).__name__}")
    width = height = None
    if document is not None or text.lstrip().startswith("<"):
        try:
            root = ET.fromstring(document if document is not None else
                                 text.encode("utf-8") if text.lstrip().startswith("<?xml") else text)
        except ET.ParseError as exc:
            raise ValueError(f"not a readable SVG document: {exc}") from None
        width, height, viewport = _frame(root)
        found, unfilled = [], []
        _paths(root, np.eye(3), found, viewport, unfilled=unfilled)
    else:
        # no document, no fill rule: taken as it is
        found, unfilled = [("path 0", text, np.eye(3), text, "evenodd")], []
    curves, roundings = [], []
    for label, d, matrix, written, rule in found:
        path_curves = []
        where = f"{label}, " if len(found) > 1 or not label.startswith("path") else ""
        _check_commands(d, where)
        rounding = _rounding(written) * float(np.linalg.norm(matrix[:2, :2], 2))  # this path's own numbers
        for s, (bezier, closed) in enumerate(parse_path_data(d)):
            if not closed:
                if not close_open:
                    raise ValueError(f"{where}subpath {s} is not closed (no Z); close it, or pass close_open=True "
                                     "to add a straight closing segment")
                start, end = bezier[0, 0], bezier[-1, 3]
                if not np.allclose(start, end):
                    bezier = np.vstack([bezier, [[end, end + (start - end) / 3, end + 2 * (start - end) / 3, start]]])
            path_curves.append(bezier @ matrix[:2, :2].T + matrix[:2, 2])
        if rule == "nonzero" and len(path_curves) > 1:
            covered = set(_nonzero_covered(path_curves))
            path_curves = [c for k, c in enumerate(path_curves) if k not in covered]
        curves.extend(path_curves)
        roundings.extend([rounding] * len(path_curves))
    if not curves:
        skipped = (f" ({len(unfilled)} shape(s) with fill=\"none\" draw only a stroke and were skipped)"
                   if unfilled else "")
        raise ValueError(f"the SVG has no path with a closed subpath{skipped}")
    return from_bezier(curves, rounding=roundings, width=width, height=height, name=name)


def _frame(root):
    """The frame (``width``, ``height``) of the document and the matrix from its user space (the ``viewBox``)
    to the frame: the SVG 1.1 section 7.7 viewBox transform, ``preserveAspectRatio`` included.

    ``width``/``height`` are unitless, px, in, cm, mm, pt or pc (96 px to the inch), or ``%`` (read as
    absent). Without a viewBox the frame is that size in px (user units are px) and the matrix is the identity
    (an absent size gives ``None``: the curves' bounding box). With a viewBox, an absent size is the viewBox
    size (one absent side follows the viewBox's aspect ratio), and the viewBox is translated by
    ``-min-x, -min-y`` and scaled into the frame. When a side is given in a physical unit (potrace writes
    ``pt``), that is a print size of the picture: the frame and the matrix are divided by the viewBox's scale
    (the smaller of x and y), so the curves keep the viewBox's units (potrace's pixels).
    """
    lengths = [_parse_length(root, side, percent=True) for side in ("width", "height")]
    lengths = [None if length is None or length[1] == "%" else length for length in lengths]
    units = {length[1] for length in lengths if length is not None}
    physical = bool(units - {"", "px"})
    same = len(units) == 1  # a physical size in one unit is read in that unit (the result does not depend on it)
    width, height = (None if length is None else length[0] * (1.0 if physical and same else _UNITS[length[1]])
                     for length in lengths)
    box = (root.get("viewBox") or "").strip()
    if not box:
        return width, height, np.eye(3)
    try:
        vx, vy, vw, vh = (float(v) for v in re.split(r"[\s,]+", box))
    except ValueError:
        vx = vy = vw = vh = float("nan")
    if not (np.isfinite([vx, vy, vw, vh]).all() and vw > 0 and vh > 0):
        raise ValueError(f"the SVG viewBox {box!r} must be four numbers: min-x, min-y, width > 0, height > 0")
    if width is None and height is None:
        width, height = vw, vh
    elif width is None:
        width = height * vw / vh
    elif height is None:
        height = width * vh / vw
    if not (width > 0 and height > 0):
        raise ValueError(f"the SVG width and height must be > 0, got {width:g} x {height:g}")
    sx, sy = width / vw, height / vh
    words = [word for word in (root.get("preserveAspectRatio") or "").split() if word != "defer"]
    align = words[0] if words else "xMidYMid"
    if align != "none":
        sx = sy = max(sx, sy) if words[1:2] == ["slice"] else min(sx, sy)
        fractions = {"Min": 0.0, "Mid": 0.5, "Max": 1.0}
        fx, fy = fractions.get(align[1:4], 0.5), fractions.get(align[5:8], 0.5)
    else:
        fx = fy = 0.0
    matrix = np.array([[sx, 0.0, (width - vw * sx) * fx - vx * sx],
                       [0.0, sy, (height - vh * sy) * fy - vy * sy],
                       [0.0, 0.0, 1.0]])
    if physical:
        scale = min(sx, sy)
        matrix[:2] /= scale
        width, height = width / scale, height / scale
    return width, height, matrix


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
