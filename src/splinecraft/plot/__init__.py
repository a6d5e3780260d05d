"""Figures for splines and outlines in notebooks (bqplot): ``import splinecraft as sc`` then ``sc.plot``.

Two levels, both pure functions (nothing is drawn until a figure is displayed):

* **Layers** -- plain data: :func:`curve`, :func:`comb`, :func:`polygon`, :func:`control_polygon`,
  :func:`auxiliary_polygons`, :func:`points`, :func:`line`, :func:`segments`, :func:`bezier_pieces`,
  :func:`outline`. Combine any of them with :func:`figure` (geometry: equal axis scales, y pointing down as
  in the widgets and in bitmaps) or :func:`chart` (functions: free aspect, y up, optional log axis).
* **Ready-made figures** -- :func:`spline_figure`, :func:`basis_figure`, :func:`curvature_figure` (κ(t)
  with the one-sided jumps at joints), :func:`outline_figure`, :func:`bitmap`; :func:`grid` lays figures
  out in rows and :func:`table` makes a small Markdown table.

Every axis has round ticks (``nice_ticks``, ``log_ticks``) and every legend stands in the right margin,
outside the data. The live figures of the widgets are here too: :class:`BasisPlot` (the editor's basis
functions), :class:`ConvergencePlot` (knot insertion per iteration) and :class:`CurvaturePlot`.

Example::

    import splinecraft as sc
    heart = sc.datasets.sample_points("heart")
    spline = sc.interpolate(heart, closed=True)
    sc.plot.figure(sc.plot.polygon(heart, closed=True), sc.plot.comb(spline), sc.plot.curve(spline),
                   sc.plot.points(heart), title="heart")
"""
from ._ticks import log_ticks, nice_limits, nice_step, nice_ticks, tick_format
from ._figure import PALETTE, Layer, chart, figure, grid, table
from ._layers import (auxiliary_polygons, bezier_pieces, comb, comb_teeth, control_polygon, curve, line, outline,
                      points, polygon, segments)
from ._charts import basis_figure, bitmap, outline_figure, spline_figure
from .curvature import CurvaturePlot, curvature_figure, curvature_profile
from .basis import BasisPlot, basis_plot_data
from .convergence import ConvergencePlot, convergence_data

__all__ = [
    "nice_ticks", "nice_limits", "nice_step", "log_ticks", "tick_format",
    "PALETTE", "Layer", "figure", "chart", "grid", "table",
    "line", "polygon", "points", "segments", "curve", "comb", "comb_teeth", "control_polygon",
    "auxiliary_polygons", "bezier_pieces", "outline",
    "spline_figure", "basis_figure", "outline_figure", "bitmap",
    "curvature_profile", "curvature_figure", "CurvaturePlot",
    "BasisPlot", "basis_plot_data", "ConvergencePlot", "convergence_data",
]
