"""SVG for traced outlines: one ``<path>`` of exact cubic Béziers, even-odd fill.

The document is in the bitmap's pixel frame (docs/capture.md): ``width``/``height`` and
``viewBox="0 0 W H"`` are the bitmap size, x right, y down, pixel corners on integers -- the frame
potrace writes and the yardstick scores in. Every closed curve is a subpath ``M x0,y0 C ... Z``; with
``fill-rule="evenodd"`` holes stay empty whatever their orientation.

The writer (:func:`format_number`, :func:`path_data`, :func:`svg_document`) is the engine's
(:mod:`splinecraft.spline.svg`), re-exported here. :func:`parse_path_data` reads path data back
(``M``/``m``, ``C``/``c``, ``L``/``l``, ``H``/``h``, ``V``/``v``, ``Z``/``z``) into Bézier arrays, so
outputs can be checked against the splines they came from.
"""
from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import numpy as np

from ..spline.svg import format_number, path_data, svg_document

__all__ = ["format_number", "path_data", "svg_document", "parse_path_data", "read_svg_paths"]

_TOKEN = re.compile(r"[MmCcLlHhVvZz]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[^\s,]")
_SVG_NS = "http://www.w3.org/2000/svg"


def parse_path_data(d: str) -> list:
    """Parse path data into cubic Bézier subpaths.

    Lines (``L``, ``H``, ``V`` and the closing segment of ``Z`` when the subpath does not end at its
    start) become exact cubics with control points at 1/3 and 2/3. Arcs and quadratics are rejected.

    Returns
    -------
    list of (bezier (m, 4, 2) ndarray, closed bool)
        One entry per subpath with at least one segment.
    """
    tokens = _TOKEN.findall(d)
    subpaths = []
    segments, start, position, command, i = [], None, None, None, 0

    def numbers(count):
        nonlocal i
        if i + count > len(tokens):
            raise ValueError(f"path data ends in the middle of a {command!r} command")
        try:
            values = [float(t) for t in tokens[i:i + count]]
        except ValueError:
            raise ValueError(f"expected {count} numbers after {command!r}, got {tokens[i:i + count]}") from None
        i += count
        return np.array(values)

    def line(p, q):
        return np.array([p, p + (q - p) / 3.0, p + 2.0 * (q - p) / 3.0, q])

    def finish(closed):
        nonlocal segments
        if segments:
            subpaths.append((np.array(segments), closed))
        segments = []

    while i < len(tokens):
        token = tokens[i]
        if token.isalpha():
            command, i = token, i + 1
        elif command is None:
            raise ValueError(f"path data must start with a command, got {token!r}")
        if command is None or not command.isalpha() or command.upper() not in "MCLHVZ":
            raise ValueError(f"unsupported path command {command!r}")
        relative = command.islower()
        upper = command.upper()
        if upper == "Z" and not token.isalpha():  # SVG 1.1 section 8.3.3: closepath takes no numbers
            raise ValueError(f"path data has {token!r} after {command!r}, which takes no numbers; start the next "
                             "subpath with M or a drawing command")
        if upper == "Z":
            if segments and not np.allclose(position, start, rtol=0, atol=1e-12):
                segments.append(line(position, start))
            finish(True)
            position = start
            continue
        if upper != "M" and position is None:
            raise ValueError(f"path data must start with M, got {command!r}")
        base = position if relative and position is not None else np.zeros(2)
        if upper == "M":
            finish(False)
            position = start = base + numbers(2)
            command = "l" if relative else "L"  # further pairs are implicit line-tos
        elif upper == "C":
            values = numbers(6).reshape(3, 2) + base
            segments.append(np.vstack([position, values]))
            position = values[-1]
        elif upper == "L":
            target = base + numbers(2)
            segments.append(line(position, target))
            position = target
        else:  # H, V
            value = numbers(1)[0]
            target = position.copy()
            axis = 0 if upper == "H" else 1
            target[axis] = value + (position[axis] if relative else 0.0)
            segments.append(line(position, target))
            position = target
    finish(False)
    return subpaths


def read_svg_paths(text: str) -> dict:
    """Read an SVG document written by :func:`svg_document`: size, viewBox, fill rule and subpaths."""
    root = ET.fromstring(text)
    paths = root.findall(f"{{{_SVG_NS}}}path") or root.findall("path")
    return {
        "width": root.get("width"),
        "height": root.get("height"),
        "viewBox": root.get("viewBox"),
        "paths": [
            {"fill_rule": p.get("fill-rule"), "fill": p.get("fill"), "subpaths": parse_path_data(p.get("d", ""))}
            for p in paths
        ],
    }
