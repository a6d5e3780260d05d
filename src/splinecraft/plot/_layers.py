"""Layer functions of :mod:`splinecraft.plot`: each returns plain data (:class:`Layer`), nothing is drawn yet.

Splines are drawn from their exact cubic Bézier pieces (:meth:`Spline.sample`), the curvature comb as
in §7 (teeth proportional to κ, outside the curve, both one-sided teeth at every joint) and traced outlines
from the Bézier pieces of a :class:`~splinecraft.capture.TraceResult` snapshot (docs/capture.md).
"""
from __future__ import annotations

import numpy as np

from ._figure import GREY, INK, PALETTE, Layer

#: The longest comb tooth drawn, in units of the 90th-percentile tooth.
COMB_CAP = 1.6

__all__ = ["line", "polygon", "points", "segments", "curve", "comb", "comb_teeth", "control_polygon",
           "auxiliary_polygons", "bezier_pieces", "outline"]


def _xy(values, name):
    array = np.asarray(values, dtype=float)
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"{name} must be an array of (x, y) points, shape (n, 2), got {array.shape}")
    return array


def line(xy, color=PALETTE[0], width=2.0, *, dashed=False, label=None, closed=False, opacity=1.0):
    """A polyline through ``xy`` (n, 2); ``closed`` joins the last point to the first."""
    xy = _xy(xy, "xy")
    if closed and len(xy):
        xy = np.vstack([xy, xy[:1]])
    return Layer("line", xy, color=color, width=width, line_style="dashed" if dashed else "solid", label=label,
                 opacity=opacity)


def polygon(xy, *, closed=False, color=GREY, width=1.2, label=None):
    """A data or control polygon: a thin dashed grey polyline (closed for a loop)."""
    return line(xy, color, width, dashed=True, closed=closed, label=label)


def points(xy, color=INK, size=28, *, marker="circle", label=None):
    """Dots at ``xy`` (n, 2) (``size`` is the marker area in px²)."""
    return Layer("dots", _xy(np.asarray(xy, dtype=float).reshape(-1, 2), "xy"), color=color, size=size,
                 marker=marker, label=label)


def segments(paths, color=PALETTE[0], width=1.0, *, dashed=False, opacity=1.0, label=None):
    """Many polylines of one length in one layer: ``paths`` (k, n, 2)."""
    paths = np.asarray(paths, dtype=float)
    if paths.size == 0:
        paths = np.zeros((0, 2, 2))
    return Layer("lines", paths, color=color, width=width, line_style="dashed" if dashed else "solid",
                 opacity=opacity, label=label)


def _check_spline(spline, name="spline"):
    from ..spline import Spline

    if not isinstance(spline, Spline):
        raise TypeError(f"{name} must be a splinecraft Spline, got {type(spline).__name__}")
    return spline


def curve(spline, color=PALETTE[0], width=2.5, *, label=None, dashed=False, samples_per_segment=32):
    """The curve of a :class:`~splinecraft.Spline`, sampled on its exact Bézier pieces."""
    _, xy = _check_spline(spline).sample(samples_per_segment=samples_per_segment)
    return line(xy, color, width, label=label, dashed=dashed)


def comb_teeth(spline, relative_length=0.12, samples_per_segment=20):
    """Curvature comb teeth (k, 2, 2), scaled for display (§7).

    The teeth are proportional to κ, so the longest ones of sharp turns would dwarf the rest: the
    90th-percentile tooth is ``relative_length`` of the curve's size and every tooth is capped at
    :data:`COMB_CAP` times that (the caps keep the comb on the figure; the shape of the comb stays readable).
    """
    spline = _check_spline(spline)
    extent = float(np.ptp(spline.bezier().reshape(-1, 2), axis=0).max()) or 1.0
    # teeth of about the curve's size (kappa ~ 1 / size): tips - base keeps their digits where the coordinates
    # are large (teeth of scale 1, ~1 / size, vanished in the rounding of a base at 1e7); the display scale below
    # makes the result independent of this one
    base, tips = spline.curvature_comb(scale=extent * min(extent, 1e100), samples_per_segment=samples_per_segment)
    teeth = tips - base
    lengths = np.linalg.norm(teeth, axis=1)
    if not len(lengths):
        return np.zeros((0, 2, 2))
    size = float(np.ptp(base, axis=0).max()) or 1.0
    target = float(relative_length) * size
    scale = target / max(float(np.percentile(lengths, 90)), 1e-300)
    factor = np.minimum(scale, COMB_CAP * target / np.maximum(lengths, 1e-300))
    return np.stack([base, base + teeth * factor[:, None]], axis=1)


def comb(spline, relative_length=0.12, color=PALETTE[3], *, samples_per_segment=20, label=None):
    """The curvature comb of a planar spline as one layer of teeth (see :func:`comb_teeth`)."""
    return segments(comb_teeth(spline, relative_length, samples_per_segment), color, 1.0, opacity=0.7,
                    label=label)


def control_polygon(spline_or_points, *, closed=None, color=GREY, label=None):
    """The control (or data) polygon: of a Spline its knot points, else the given points."""
    from ..spline import Spline

    if isinstance(spline_or_points, Spline):
        xy = spline_or_points.knot_points
        closed = spline_or_points.closed if closed is None else closed
        if closed:
            xy = xy[:-1]
    else:
        xy = spline_or_points
    return polygon(xy, closed=bool(closed), color=color, label=label)


def auxiliary_polygons(spline, color=GREY, width=1.2, *, label=None):
    """The polygons Fᵢ Vᵢ Wᵢ Fᵢ₊₁ of an interpolant's pieces (thesis eqs 3.10-3.12; ``spline.auxiliary``)."""
    aux = _check_spline(spline).auxiliary
    if not all(key in aux for key in ("F", "V", "W")):
        raise ValueError("this spline has no auxiliary points F, V, W (only interpolants and segments keep them)")
    F = np.asarray(aux["F"], dtype=float)
    V, W = np.asarray(aux["V"], float), np.asarray(aux["W"], float)
    if F.shape[0] == V.shape[0]:  # a closed curve keeps one F per piece (the first is not repeated): wrap round
        F = np.vstack([F, F[:1]])
    stacked = np.stack([F[:-1], V, W, F[1:]], axis=1)
    return segments(stacked, color, width, dashed=True, label=label)


def _bezier_samples(bezier, samples):
    theta = np.linspace(0.0, 1.0, samples)[:, None]
    weights = np.hstack([(1 - theta) ** 3, 3 * (1 - theta) ** 2 * theta, 3 * (1 - theta) * theta ** 2, theta ** 3])
    return np.einsum("kj,mjd->mkd", weights, bezier)


def bezier_pieces(bezier, color=PALETTE[0], width=1.8, *, joints=True, samples=16, label=None):
    """Cubic Bézier pieces (m, 4, 2) -- a traced outline or ``spline.bezier()`` -- with dots where they join."""
    bezier = np.asarray(bezier, dtype=float)
    if bezier.ndim != 3 or bezier.shape[1:] != (4, 2):
        raise ValueError(f"bezier must have shape (m, 4, 2), got {bezier.shape}")
    layers = [segments(_bezier_samples(bezier, samples), color, width, label=label)]
    if joints:
        layers.append(points(bezier[:, 0], color, 10))
    return layers


def outline(result, iteration=-1, *, color=PALETTE[0], contour_color="#bdbdbd", corner_color=PALETTE[1]):
    """A traced outline: the contours (grey), their corners and the Bézier pieces at ``iteration``.

    ``result`` is a :class:`~splinecraft.capture.TraceResult`; ``iteration`` indexes ``result.snapshots``
    (0: corners only; -1: the final fit). Without snapshots the final splines are drawn.
    """
    if not hasattr(result, "points") or not hasattr(result, "corners"):
        raise TypeError(f"result must be a TraceResult (from splinecraft.trace), got {type(result).__name__}")
    layers = [line(contour, contour_color, 1.0, closed=True) for contour in result.points]
    if result.snapshots:
        bezier = result.snapshots[iteration].bezier
    else:
        bezier = np.concatenate([s.bezier() for s in result.splines]) if result.splines else np.zeros((0, 4, 2))
    layers += bezier_pieces(bezier, color)
    corners = [np.asarray(contour)[np.asarray(index, dtype=int)] for contour, index in zip(result.points, result.corners)]
    if corners:                                   # on top: every corner is also a joint of two pieces
        layers.append(points(np.vstack(corners), corner_color, 26))
    return layers
