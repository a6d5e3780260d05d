"""SVG path writing for cubic Bézier curves: the one writer of the package (§0).

Splines (:meth:`~splinecraft.spline.piecewise.Spline.to_svg_path`), traced outlines and the editor's
export all write their numbers and path data here. A curve is one subpath ``M x0,y0 C x1,y1 x2,y2 x3,y3
... [Z]`` of its exact Bézier pieces; numbers are rounded to ``decimals`` places with trailing zeros
dropped, or written exactly (``decimals=None``, shortest round-trip text).
"""
from __future__ import annotations

import numbers
import re
from xml.sax.saxutils import quoteattr

import numpy as np

from .._validation import check_bool, check_int, check_number

__all__ = ["format_number", "path_data", "svg_document", "MAX_DECIMALS"]

#: Largest accepted ``decimals`` (float64 carries at most 17 significant digits; more places only
#: matter for coordinates far below 1).
MAX_DECIMALS = 64

_SVG_NS = "http://www.w3.org/2000/svg"


def _check_decimals(decimals, name="decimals"):
    if decimals is None:
        return None
    return check_int(decimals, name, minimum=0, maximum=MAX_DECIMALS)


def _formatter(decimals):
    """A function float -> text for already checked ``decimals`` (None: exact)."""
    if decimals is None:
        def exact(value):
            text = repr(value)
            return "0" if text in ("0.0", "-0.0") else (text[:-2] if text.endswith(".0") else text)
        return exact
    spec = f".{decimals}f"

    def rounded(value):
        text = format(value, spec)
        if "." in text:
            text = text.rstrip("0").rstrip(".")
        return "0" if text in ("-0", "") else text
    return rounded


def format_number(value: float, decimals: int | None = 4) -> str:
    """Shortest text for ``value`` rounded to ``decimals`` places; ``None``: exact round trip (``repr``).

    ``decimals`` is an integer in ``[0, MAX_DECIMALS]`` or ``None``; a non-finite ``value`` is a
    ``ValueError`` (SVG has no NaN).
    """
    decimals = _check_decimals(decimals)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"value must be a real number, got {type(value).__name__}")
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"cannot write a non-finite coordinate {value!r} to SVG")
    return _formatter(decimals)(value)


def _closed_flags(closed, count):
    if isinstance(closed, (bool, np.bool_)):
        return [bool(closed)] * count
    flags = [check_bool(flag, f"closed[{i}]") for i, flag in enumerate(closed)]
    if len(flags) != count:
        raise ValueError(f"closed has {len(flags)} flags for {count} curves")
    return flags


def path_data(curves, *, decimals: int | None = 4, closed=True) -> str:
    """SVG path data for cubic curves, one subpath per curve.

    Parameters
    ----------
    curves : iterable of array_like (m, 4, 2)
        Bézier control points of each curve (piece ``i`` ends where piece ``i + 1`` starts).
    decimals : int or None
        Decimal places of the coordinates (trailing zeros dropped); ``None`` writes exact floats.
    closed : bool or sequence of bool
        Whether each subpath ends with ``Z`` (one flag for all curves, or one per curve). A closed
        curve's last piece already returns to its first point.

    Returns
    -------
    str
        ``"M x0,y0 C x1,y1 x2,y2 x3,y3 ... Z M ..."``.
    """
    fmt = _formatter(_check_decimals(decimals))
    curves = list(curves)
    flags = _closed_flags(closed, len(curves))
    parts = []
    for index, (curve, is_closed) in enumerate(zip(curves, flags)):
        try:
            bezier = np.asarray(curve, dtype=float)
        except (TypeError, ValueError):
            raise TypeError(f"curves[{index}] must be a numeric (m, 4, 2) array") from None
        if bezier.ndim != 3 or bezier.shape[1:] != (4, 2) or bezier.shape[0] < 1:
            raise ValueError(f"curves[{index}] must have shape (m, 4, 2) with m >= 1, got {bezier.shape}")
        if not np.isfinite(bezier).all():
            raise ValueError(f"curves[{index}] has a non-finite coordinate; SVG has no NaN or inf")
        texts = [fmt(value) for value in bezier.reshape(-1).tolist()]
        pairs = [f"{texts[k]},{texts[k + 1]}" for k in range(0, len(texts), 2)]  # 4 per piece
        parts.append("M " + pairs[0])
        parts.extend("C " + " ".join(pairs[4 * i + 1: 4 * i + 4]) for i in range(bezier.shape[0]))
        if is_closed:
            parts.append("Z")
    return " ".join(parts)


#: Characters XML 1.0 does not allow in a document (C0 controls but tab and newlines, lone surrogates such as a
#: file name's undecodable bytes from ``os.fsdecode``, U+FFFE and U+FFFF).
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def xml_safe(text: str) -> str:
    """``text`` with every character XML cannot hold replaced by U+FFFD (for titles made from file names)."""
    return _NOT_XML.sub("\ufffd", text)


def _check_xml_text(text, label):
    bad = _NOT_XML.search(text) if isinstance(text, str) else None
    if bad:
        raise ValueError(f"{label} {text!r} contains U+{ord(bad.group()):04X}, a character XML cannot hold "
                         "(splinecraft.spline.svg.xml_safe replaces such characters)")


def _size_text(value, name, fmt):
    number = check_number(value, name, minimum=0.0)
    return str(int(number)) if float(number).is_integer() else fmt(number)


def svg_document(d: str, width, height, *, fill: str = "black", title: str | None = None, view_box=None,
                 stroke: str | None = None, stroke_width=None, fill_rule: str = "evenodd",
                 decimals: int | None = 4) -> str:
    """A standalone SVG document with one path ``d``.

    By default it is the filled outline of a traced bitmap: ``width x height`` pixels, ``viewBox="0 0 W
    H"``, even-odd fill, no stroke. ``view_box=(x, y, w, h)`` sets another frame (e.g. a curve's
    bounding box), ``fill="none"`` with a ``stroke`` colour and ``stroke_width`` draws a line.
    ``decimals`` rounds the view box and sizes that are not integers. A ``title``, ``fill`` or ``stroke``
    with a character XML cannot hold (a control character, a lone surrogate) is a ``ValueError``; one that is
    not a string (``fill``: not ``None`` either) a ``TypeError``.
    """
    if not isinstance(d, str):
        raise TypeError(f"d must be SVG path data (str), got {type(d).__name__}")
    for label, text, optional in (("title", title, True), ("fill", fill, False), ("stroke", stroke, True)):
        if not (isinstance(text, str) or (optional and text is None)):
            what = "a string or None" if optional else 'a string (an SVG paint: "black", "#1565c0", "none")'
            raise TypeError(f"{label} must be {what}, got {type(text).__name__}")
        _check_xml_text(text, label)
    fmt = _formatter(_check_decimals(decimals))
    width_text = _size_text(width, "width", fmt)
    height_text = _size_text(height, "height", fmt)
    if view_box is None:
        box = f"0 0 {width_text} {height_text}"
    else:
        values = [check_number(value, f"view_box[{i}]") for i, value in enumerate(view_box)]
        if len(values) != 4:
            raise ValueError(f"view_box must be (x, y, width, height), got {len(values)} values")
        box = " ".join(fmt(value) for value in values)
    title_element = f"  <title>{_escape(title)}</title>\n" if title else ""
    paint = f"fill={quoteattr(fill)} fill-rule={quoteattr(fill_rule)} stroke={quoteattr(stroke or 'none')}"
    if stroke_width is not None:
        paint += f' stroke-width="{fmt(check_number(stroke_width, "stroke_width", minimum=0.0))}"'
        paint += ' stroke-linejoin="round"'
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="{_SVG_NS}" version="1.1" width="{width_text}" height="{height_text}" '
        f'viewBox="{box}">\n'
        f"{title_element}"
        f'  <path {paint} d="{d}"/>\n'
        "</svg>\n"
    )
