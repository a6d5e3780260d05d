"""Ready-made figures of :mod:`splinecraft.plot`: a spline with its polygon and comb, basis functions,
a traced outline, a bitmap. Each is a pure function returning a widget to display."""
from __future__ import annotations

import numpy as np

from ._figure import INK, PALETTE, chart, figure
from ._layers import comb, control_polygon, curve, line, outline, points as point_layer

__all__ = ["spline_figure", "basis_figure", "outline_figure", "bitmap"]


def spline_figure(spline, *, data_points=None, polygon=False, show_comb=False, title="", width=330, height=290,
                  color=PALETTE[0], label=None):
    """A spline (its exact curve) with optional data points, its polygon (dashed) and curvature comb.

    ``polygon=True`` draws the spline's own knot polygon; pass points to draw those instead (closed like
    the spline).
    """
    layers = []
    if polygon is not False and polygon is not None:
        layers.append(control_polygon(spline if polygon is True else polygon, closed=spline.closed))
    if show_comb:
        layers.append(comb(spline))
    layers.append(curve(spline, color, label=label))
    if data_points is not None:
        layers.append(point_layer(data_points, INK, 22))
    return figure(*layers, title=title, width=width, height=height)


def basis_figure(t, values, *, labels=None, show_sum=True, title="", xlabel="t", y_range=None, width=330,
                 height=260, colors=PALETTE):
    """Basis (or blending) functions over ``t``: ``values`` (len(t), k), one line each; dashed: their sum."""
    t = np.asarray(t, dtype=float).ravel()
    values = np.asarray(values, dtype=float)
    if values.ndim != 2 or values.shape[0] != t.shape[0]:
        raise ValueError(f"values must have shape (len(t), k) = ({t.shape[0]}, k), got {values.shape}")
    if labels is not None and len(labels) != values.shape[1]:
        raise ValueError(f"labels must name each of the {values.shape[1]} functions, got {len(labels)}")
    layers = [line(np.c_[t, values[:, j]], colors[j % len(colors)], 1.8, label=None if labels is None else labels[j])
              for j in range(values.shape[1])]
    if show_sum:
        layers.append(line(np.c_[t, values.sum(axis=1)], INK, 1.5, dashed=True, label="sum"))
    if y_range is None:
        low = min(0.0, float(np.nanmin(values)))
        y_range = (low - 0.05 if low < 0 else -0.05, max(1.05, float(np.nanmax(values)) + 0.05))
    return chart(*layers, title=title, width=width, height=height, xlabel=xlabel, x_range=(t[0], t[-1]),
                 y_range=y_range)


def outline_figure(result, iteration=-1, *, title=None, width=420, height=290, bounds=None):
    """A traced outline at one iteration of knot insertion (see :func:`splinecraft.plot.outline`)."""
    if title is None:
        if result.snapshots:
            shown = result.snapshots[iteration]
            title = f"iteration {shown.iteration}: {shown.knots} knots"
        else:
            title = f"{sum(s.n_segments for s in result.splines)} segments"
    return figure(outline(result, iteration), title=title, width=width, height=height, bounds=bounds)


def bitmap(mask, height=150):
    """A bool image (True = ink) as an ``ipywidgets.Image`` ``height`` px tall (nearest-neighbour scaling)."""
    import io

    import ipywidgets as ipw
    from PIL import Image

    mask = np.asarray(mask)
    if mask.ndim != 2 or mask.size == 0:
        raise ValueError(f"mask must be a 2-d image, got shape {mask.shape}")
    image = Image.fromarray(np.where(mask.astype(bool), 30, 255).astype(np.uint8))
    image = image.resize((max(1, round(mask.shape[1] * height / mask.shape[0])), int(height)), Image.NEAREST)
    buffer = io.BytesIO()
    image.save(buffer, format="PNG")
    return ipw.Image(value=buffer.getvalue(), format="png")
