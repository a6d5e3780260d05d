"""Layers and the two figure builders of :mod:`splinecraft.plot` (bqplot).

A :class:`Layer` is plain data -- points and a style -- made by the functions of ``_layers.py``.
:func:`figure` draws layers of geometry (equal axis scales, y pointing down: the frame of the widgets and
of bitmaps, so a figure and an editor show a shape the same way up); :func:`chart` draws functions (free
aspect, y up, optional log y axis). Both set round tick values explicitly (``_ticks.py``) and draw the
legend in the right margin, outside the data, with swatches that show solid, dashed and dotted lines as
they are drawn.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .._validation import plain
from ._ticks import log_ticks, nice_limits, nice_ticks, tick_format

__all__ = ["Layer", "PALETTE", "figure", "chart", "grid", "table", "legend_marks"]

#: Colours of the figures (colour-blind safe order: blue, orange, green, purple, red, teal, brown, indigo).
PALETTE = ("#1565c0", "#ef6c00", "#2e7d32", "#8e24aa", "#c62828", "#00838f", "#6d4c41", "#5e35b1")
GREY, INK = "#90a4ae", "#263238"
MARGIN = {"top": 36, "bottom": 40, "left": 56, "right": 16}
LEGEND_FONT_PX = 11
LEGEND_ROW_PX = 17
_CHAR_PX = 6.6            # average width of one legend character at 11 px (sans-serif), for the margin
_SWATCH = {"solid": "━━", "dashed": "╍╍", "dash_dotted": "━ ·", "dots": "●"}


@dataclass(frozen=True)
class Layer:
    """What to draw: ``kind`` "line" (``xy`` (n, 2)), "lines" (``xy`` (k, n, 2): k polylines) or "dots" (n, 2)."""

    kind: str
    xy: np.ndarray
    color: str = PALETTE[0]
    width: float = 2.0
    line_style: str = "solid"
    label: Optional[str] = None
    opacity: float = 1.0
    size: float = 28.0
    marker: str = "circle"

    def __post_init__(self):
        if self.kind not in ("line", "lines", "dots"):
            raise ValueError(f"kind must be 'line', 'lines' or 'dots', got {self.kind!r}")
        xy = np.asarray(self.xy, dtype=float)
        expected = 3 if self.kind == "lines" else 2
        if self.kind == "dots":
            xy = xy.reshape(-1, 2)
        if xy.ndim != expected or xy.shape[-1] != 2:
            raise ValueError(f"a {self.kind!r} layer needs xy of shape {'(k, n, 2)' if expected == 3 else '(n, 2)'}, "
                             f"got {xy.shape}")
        object.__setattr__(self, "xy", xy)

    def finite_points(self) -> np.ndarray:
        points = self.xy.reshape(-1, 2)
        return points[np.isfinite(points).all(axis=1)]


def _flatten(layers):
    for item in layers:
        if item is None:
            continue
        if isinstance(item, Layer):
            yield item
        elif isinstance(item, (list, tuple)):
            yield from _flatten(item)
        else:
            raise TypeError(f"layers must be Layer objects (from splinecraft.plot), got {type(item).__name__}")


def _marks(layers, scales, log_y=False):
    import bqplot as bq

    marks = []
    for layer in layers:
        xy = layer.xy
        if log_y and layer.kind != "lines":
            xy = xy[xy[:, 1] > 0]                     # a log axis leaves out values <= 0
        common = {"scales": scales, "apply_clip": True}
        if layer.kind == "dots":
            if not len(xy):
                continue
            marks.append(bq.Scatter(x=xy[:, 0], y=xy[:, 1], colors=[layer.color], default_size=layer.size,
                                    marker=layer.marker, stroke="white" if layer.size >= 20 else None,
                                    opacities=[layer.opacity],
                                    **common))
        elif layer.kind == "line":
            marks.append(bq.Lines(x=xy[:, 0], y=xy[:, 1], colors=[layer.color], stroke_width=layer.width,
                                  line_style=layer.line_style, opacities=[layer.opacity], **common))
        elif xy.shape[0]:
            marks.append(bq.Lines(x=xy[..., 0], y=xy[..., 1], colors=[layer.color] * len(xy),
                                  stroke_width=layer.width, line_style=layer.line_style,
                                  opacities=[layer.opacity] * len(xy), **common))
    return marks


def legend_marks(entries, plot_height: float, offset: int = 0):
    """Legend drawn in the right margin: ``entries`` are ``(label, color, style)`` with style "solid",
    "dashed", "dash_dotted" or "dots". Returns bqplot Label marks (not clipped, at pixel offsets from the
    plot area's right edge -- ``offset`` more px to clear a right axis -- so the legend never covers data
    and stays put when the figure is resized)."""
    import bqplot as bq

    if not entries:
        return []
    x_scale = bq.LinearScale(min=0.0, max=1.0)
    y_scale = bq.LinearScale(min=0.0, max=float(plot_height), reverse=True)
    scales = {"x": x_scale, "y": y_scale}
    rows = 6.0 + LEGEND_ROW_PX * (np.arange(len(entries)) + 0.5)
    ones = np.ones(len(entries))
    swatches = bq.Label(x=ones, y=rows, text=[_SWATCH.get(style, _SWATCH["solid"]) for _, _, style in entries],
                        colors=[color for _, color, _ in entries], default_size=LEGEND_FONT_PX + 1, align="start", font_weight="normal",
                        x_offset=10 + int(offset), y_offset=4, scales=scales, apply_clip=False)
    texts = bq.Label(x=ones, y=rows, text=[label for label, _, _ in entries], colors=["#37474f"] * len(entries),
                     default_size=LEGEND_FONT_PX, align="start", font_weight="normal", x_offset=38 + int(offset), y_offset=4, scales=scales,
                     apply_clip=False)
    return [swatches, texts]


def _legend_entries(layers):
    entries = []
    for layer in layers:
        if layer.label:
            style = "dots" if layer.kind == "dots" else layer.line_style
            entries.append((layer.label, layer.color, style))
    return entries


def _plot_area(width, height, entries):
    """The margins (the right one holds the legend of ``entries``) and the plot area (px); a ``ValueError`` that
    names what leaves it no room: the size, or the legend's labels."""
    margin = dict(MARGIN, right=legend_width([label for label, _, _ in entries]))
    area = np.array([width - margin["left"] - margin["right"], height - margin["top"] - margin["bottom"]], float)
    if min(area) < 20:
        if area[1] >= 20 and margin["right"] > MARGIN["right"]:
            longest = max((label for label, _, _ in entries), key=len)
            raise ValueError(f"the legend takes {margin['right']} px of the {width} px width (its longest label, "
                             f"{longest!r}, has {len(longest)} characters): shorten the labels or widen the figure")
        raise ValueError(f"width and height leave no room for the plot ({width} x {height} px)")
    return margin, area


def legend_width(labels) -> int:
    """Right margin (px) that holds a legend of ``labels``."""
    longest = max((len(label) for label in labels), default=0)
    return int(46 + _CHAR_PX * longest) if longest else MARGIN["right"]


def _axis(scale, ticks, *, log=False, vertical=False, label=""):
    import bqplot as bq

    options = {"side": "left", "label_offset": "40px"} if vertical else {}
    return bq.Axis(scale=scale, label=label, tick_values=np.asarray(ticks, float), tick_format=tick_format(ticks, log=log),
                   grid_lines="none", **options)


def assemble(marks, axes, *, title, width, height, margin):
    """The bqplot Figure of every builder here: fixed pixel size, 13 px title, no animation."""
    import bqplot as bq
    import ipywidgets as ipw

    return bq.Figure(marks=marks, axes=axes, title=title, fig_margin=margin,
                     layout=ipw.Layout(width=f"{int(width)}px", height=f"{int(height)}px"),
                     title_style={"font-size": "13px"}, animation_duration=0, min_aspect_ratio=0.01,
                     max_aspect_ratio=100.0)


def _check_size(width, height):
    for name, value in (("width", width), ("height", height)):
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) or not 80 <= value <= 4000:
            raise ValueError(f"{name} must be a number of pixels between 80 and 4000, got {plain(value)!r}")


def figure(*layers, title: str = "", width: int = 330, height: int = 290, bounds=None, y_down: bool = True,
           xlabel: str = "", ylabel: str = ""):
    """A bqplot Figure of geometry layers with equal axis scales (y pointing down unless ``y_down=False``).

    ``bounds`` ``(x0, y0, x1, y1)`` fixes the window (a zoom); otherwise it fits every layer with a small
    border. Layers may be nested lists; ``None`` is skipped.
    """
    import bqplot as bq

    _check_size(width, height)
    layers = list(_flatten(layers))
    entries = _legend_entries(layers)
    margin, area = _plot_area(width, height, entries)
    if bounds is not None:
        x0, y0, x1, y1 = map(float, bounds)
        low, high = np.array([min(x0, x1), min(y0, y1)]), np.array([max(x0, x1), max(y0, y1)])
    else:
        points = [layer.finite_points() for layer in layers]
        points = np.vstack(points) if points else np.zeros((0, 2))
        low, high = (points.min(axis=0), points.max(axis=0)) if len(points) else (np.zeros(2), np.ones(2))
    # a flat or one-point layer gets a span of its own: 1e-9 of the other axis's, at least the numbers' resolution
    # (1e-15 of their size; an absolute floor of 1e-9 left a curve 1e-15 across a speck in the middle)
    floor = max(1e-9 * float((high - low).max()), 1e-15 * float(np.abs(high).max())) or 1e-9
    span = np.maximum(high - low, floor) * (1.0 if bounds is not None else 1.08)
    half = (span / area).max() * area / 2           # same data units per pixel on both axes
    middle = (low + high) / 2
    x_scale = bq.LinearScale(min=float(middle[0] - half[0]), max=float(middle[0] + half[0]))
    y_scale = bq.LinearScale(min=float(middle[1] - half[1]), max=float(middle[1] + half[1]), reverse=bool(y_down))
    marks = _marks(layers, {"x": x_scale, "y": y_scale}) + legend_marks(entries, area[1])
    count = lambda pixels: max(3, int(pixels // 55))  # noqa: E731 - one tick per ~55 px
    axes = [_axis(x_scale, nice_ticks(x_scale.min, x_scale.max, count(area[0])), label=xlabel),
            _axis(y_scale, nice_ticks(y_scale.min, y_scale.max, count(area[1])), vertical=True, label=ylabel)]
    return assemble(marks, axes, title=title, width=width, height=height, margin=margin)


def chart(*layers, title: str = "", width: int = 420, height: int = 260, xlabel: str = "", ylabel: str = "",
          x_range=None, y_range=None, log_y: bool = False):
    """A bqplot Figure of function graphs: free aspect, y up, round ticks, legend outside on the right.

    ``x_range``/``y_range`` fix an axis; otherwise it spans the data, widened to round values. ``log_y``
    draws the y axis in decades (values <= 0 are left out).
    """
    import bqplot as bq

    _check_size(width, height)
    layers = list(_flatten(layers))
    entries = _legend_entries(layers)
    margin, area = _plot_area(width, height, entries)
    points = [layer.finite_points() for layer in layers]
    points = np.vstack(points) if points else np.zeros((0, 2))
    if log_y:
        points = points[points[:, 1] > 0]

    def limits(column, given, log=False):
        if given is not None:
            return tuple(map(float, given))
        values = points[:, column] if len(points) else np.array([0.0, 1.0] if not log else [1.0, 10.0])
        low, high = float(values.min()), float(values.max())
        if log:
            low_decade = 10.0 ** np.floor(np.log10(low) + 1e-9)
            return float(low_decade), float(max(10.0 ** np.ceil(np.log10(high) - 1e-9), 10 * low_decade))
        return nice_limits(low, high, max(2, int(area[column] // 70)))

    (x0, x1), (y0, y1) = limits(0, x_range), limits(1, y_range, log_y)
    x_scale = bq.LinearScale(min=x0, max=x1)
    y_scale = bq.LogScale(min=y0, max=y1) if log_y else bq.LinearScale(min=y0, max=y1)
    marks = _marks(layers, {"x": x_scale, "y": y_scale}, log_y=log_y) + legend_marks(entries, area[1])
    y_ticks = log_ticks(y0, y1) if log_y else nice_ticks(y0, y1, max(2, int(area[1] // 50)))
    axes = [_axis(x_scale, nice_ticks(x0, x1, max(2, int(area[0] // 70))), label=xlabel),
            _axis(y_scale, y_ticks, log=log_y, vertical=True, label=ylabel)]
    return assemble(marks, axes, title=title, width=width, height=height, margin=margin)


def grid(*figures, columns: int = 3):
    """Figures (or any widgets) in rows of ``columns``: an ``ipywidgets.VBox`` to display."""
    import ipywidgets as ipw

    if isinstance(columns, bool) or not isinstance(columns, (int, np.integer)) or columns < 1:
        raise ValueError(f"columns must be a positive integer, got {plain(columns)!r}")
    items = list(figures)
    return ipw.VBox([ipw.HBox(items[i:i + columns]) for i in range(0, len(items), columns)])


def table(header, rows, digits: int = 4):
    """A small Markdown table to display; floats rounded to ``digits`` significant digits."""
    from IPython.display import Markdown

    def cell(value):
        if isinstance(value, (float, np.floating)):
            return f"{value:.{digits}g}"
        return str(value).replace("|", "\\|")

    header = list(header)
    lines = ["| " + " | ".join(cell(h) for h in header) + " |", "|" + " --- |" * len(header)]
    for row in rows:
        row = list(row)
        if len(row) != len(header):
            raise ValueError(f"every row needs {len(header)} cells like the header, got {len(row)}: {row!r}")
        lines.append("| " + " | ".join(cell(v) for v in row) + " |")
    return Markdown("\n".join(lines))
