"""Per-iteration convergence plot of knot insertion (bqplot): the TraceExplorer's, or any trace's.

Left axis: the number of knots after each iteration (iteration 0 = corners only). Right axis: the largest
thesis error over all pieces (spline point vs its contour point, px) and the true two-sided Hausdorff
deviation; the dashed line is the threshold ε, the vertical line the iteration shown in the explorer.
"""
from __future__ import annotations

import numpy as np

from ._figure import MARGIN, assemble, legend_marks, legend_width
from ._ticks import log_ticks, nice_ticks, tick_format

__all__ = ["ConvergencePlot", "convergence_data"]


def convergence_data(result) -> dict:
    """Arrays ``iteration``, ``knots``, ``max_error``, ``hausdorff`` over the merged snapshots of a trace."""
    snapshots = result.snapshots
    return {
        "iteration": np.array([s.iteration for s in snapshots], dtype=float),
        "knots": np.array([s.knots for s in snapshots], dtype=float),
        "max_error": np.array([s.max_error for s in snapshots], dtype=float),
        "hausdorff": np.array([s.hausdorff for s in snapshots], dtype=float),
    }


KNOT_COLOR, ERROR_COLOR, HAUSDORFF_COLOR, EPSILON_COLOR = "#1565c0", "#c2185b", "#ef6c00", "#455a64"
_LEGEND = [("knots", KNOT_COLOR, "solid"), ("max error (px)", ERROR_COLOR, "solid"),
           ("Hausdorff (px)", HAUSDORFF_COLOR, "dash_dotted"), ("ε", EPSILON_COLOR, "dashed")]
#: Pixels between the plot area and the legend: room for the right axis's tick labels and its title.
_RIGHT_AXIS_PX = 64


class ConvergencePlot:
    """A bqplot Figure of one trace's knots (left axis) and errors (right, log) per iteration.

    :meth:`show` draws a :class:`~splinecraft.capture.TraceResult`, :meth:`mark` moves the marker of the
    shown iteration. Ticks are round (whole iterations and knots, decades of error), the legend stands
    right of the error axis, outside the data.
    """

    HEIGHT = 250

    def __init__(self):
        import bqplot as bq

        self.x_scale = bq.LinearScale()
        self.knot_scale = bq.LinearScale(min=0.0)
        self.error_scale = bq.LogScale()  # the first fit's error is often 100x epsilon
        knot_scales = {"x": self.x_scale, "y": self.knot_scale}
        error_scales = {"x": self.x_scale, "y": self.error_scale}
        self.knots = bq.Lines(x=[0.0], y=[0.0], scales=knot_scales, colors=[KNOT_COLOR], stroke_width=2,
                              marker="circle", marker_size=16)
        self.error = bq.Lines(x=[0.0], y=[1.0], scales=error_scales, colors=[ERROR_COLOR], stroke_width=2)
        self.hausdorff = bq.Lines(x=[0.0], y=[1.0], scales=error_scales, colors=[HAUSDORFF_COLOR], stroke_width=1.5,
                                  line_style="dash_dotted")
        self.threshold = bq.Lines(x=[0.0, 1.0], y=[1.0, 1.0], scales=error_scales, colors=[EPSILON_COLOR],
                                  line_style="dashed", stroke_width=1.2)
        self.current = bq.Lines(x=[0.0, 0.0], y=[0.1, 1.0], scales=error_scales, colors=["#90a4ae"], stroke_width=6,
                                opacities=[0.35])
        self.x_axis = bq.Axis(scale=self.x_scale, label="iteration", grid_lines="none", tick_format="d")
        self.knot_axis = bq.Axis(scale=self.knot_scale, side="left", label="knots",
                                 grid_lines="dashed", grid_color="#eceff1", color=KNOT_COLOR, tick_format="d",
                                 label_offset="40px")
        self.error_axis = bq.Axis(scale=self.error_scale, side="right", label="error (px)",
                                  grid_lines="none", color=ERROR_COLOR, label_offset="44px")
        margin = dict(MARGIN, right=_RIGHT_AXIS_PX + legend_width([label for label, _, _ in _LEGEND]))
        legend = legend_marks(_LEGEND, self.HEIGHT - margin["top"] - margin["bottom"], offset=_RIGHT_AXIS_PX)
        self.figure = assemble([self.current, self.threshold, self.hausdorff, self.error, self.knots, *legend],
                               [self.x_axis, self.knot_axis, self.error_axis],
                               title="Knot insertion: knots and error per iteration", width=890, height=self.HEIGHT,
                               margin=margin)
        self.data = None

    def show(self, result, epsilon: float, current: int = 0) -> None:
        """Draw the snapshots of ``result`` with the threshold ``epsilon``; mark iteration ``current``."""
        if not result.snapshots:
            return
        data = convergence_data(result)
        self.data = data
        x = data["iteration"]
        values = np.concatenate([data["max_error"], data["hausdorff"], [epsilon]])
        values = values[np.isfinite(values) & (values > 0)]
        top = float(values.max()) * 1.3 if values.size else 1.0
        bottom = float(values.min()) / 1.3 if values.size else 0.1
        last = float(max(x[-1], x[0] + 1))
        with self.knots.hold_sync(), self.error.hold_sync(), self.hausdorff.hold_sync(), self.threshold.hold_sync():
            self.knots.x, self.knots.y = x, data["knots"]
            self.error.x, self.error.y = x, data["max_error"]
            self.hausdorff.x, self.hausdorff.y = x, data["hausdorff"]
            self.threshold.x = [float(x[0]), last]
            self.threshold.y = [epsilon, epsilon]
        self.error_scale.min, self.error_scale.max = bottom, top
        error_ticks = log_ticks(bottom, top)
        self.error_axis.tick_values = error_ticks
        self.error_axis.tick_format = tick_format(error_ticks, log=True)
        self.x_scale.min, self.x_scale.max = float(x[0]), last
        iteration_ticks = nice_ticks(x[0], last, 10)
        self.x_axis.tick_values = iteration_ticks[iteration_ticks == np.round(iteration_ticks)]  # whole iterations
        top_knots = float(max(data["knots"].max(), 1.0))
        knot_ticks = nice_ticks(0.0, top_knots, 4)
        knot_ticks = knot_ticks[knot_ticks == np.round(knot_ticks)]
        self.knot_scale.max = float(max(knot_ticks[-1], top_knots) * 1.05)
        self.knot_axis.tick_values = knot_ticks
        self.mark(current)

    def mark(self, index: int) -> None:
        """Move the vertical marker to snapshot ``index``."""
        if self.data is None:
            return
        iterations = self.data["iteration"]
        x = float(iterations[min(int(index), len(iterations) - 1)])
        with self.current.hold_sync():
            self.current.x = [x, x]
            self.current.y = [float(self.error_scale.min or 0.1), float(self.error_scale.max or 1.0)]
