"""Per-iteration convergence plot of knot insertion beside the TraceExplorer (bqplot).

Left axis: the number of knots after each iteration (iteration 0 = corners only). Right axis: the largest
thesis error over all pieces (spline point vs its contour point, px) and the true two-sided Hausdorff
deviation; the dashed line is the threshold ε, the vertical line the iteration shown in the explorer.
"""
from __future__ import annotations

import numpy as np

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


class ConvergencePlot:
    """A bqplot Figure kept in sync with one TraceExplorer (see ``TraceExplorer.convergence_figure``)."""

    def __init__(self):
        import bqplot as bq
        import ipywidgets

        self.x_scale = bq.LinearScale()
        self.knot_scale = bq.LinearScale(min=0.0)
        self.error_scale = bq.LogScale()  # the first fit's error is often 100x epsilon
        knot_scales = {"x": self.x_scale, "y": self.knot_scale}
        error_scales = {"x": self.x_scale, "y": self.error_scale}
        self.knots = bq.Lines(x=[0.0], y=[0.0], scales=knot_scales, colors=["#1565c0"], stroke_width=2,
                              marker="circle", marker_size=16, labels=["knots"], display_legend=True)
        self.error = bq.Lines(x=[0.0], y=[1.0], scales=error_scales, colors=["#c2185b"], stroke_width=2,
                              labels=["max error (px)"], display_legend=True)
        self.hausdorff = bq.Lines(x=[0.0], y=[1.0], scales=error_scales, colors=["#ef6c00"], stroke_width=1.5,
                                  line_style="dash_dotted", labels=["Hausdorff (px)"], display_legend=True)
        self.threshold = bq.Lines(x=[0.0, 1.0], y=[1.0, 1.0], scales=error_scales, colors=["#455a64"],
                                  line_style="dashed", stroke_width=1.2, labels=["ε"], display_legend=True)
        self.current = bq.Lines(x=[0.0, 0.0], y=[0.1, 1.0], scales=error_scales, colors=["#90a4ae"], stroke_width=6,
                                opacities=[0.35])
        x_axis = bq.Axis(scale=self.x_scale, label="iteration", grid_lines="none", tick_format="d")
        self.x_axis = x_axis
        knot_axis = bq.Axis(scale=self.knot_scale, side="left", label="knots",
                            grid_lines="dashed", grid_color="#eceff1", color="#1565c0", tick_format="d")
        error_axis = bq.Axis(scale=self.error_scale, side="right", label="error, px (log)",
                             grid_lines="none", color="#c2185b", tick_format=".2~g")
        self.figure = bq.Figure(
            marks=[self.current, self.threshold, self.hausdorff, self.error, self.knots],
            axes=[x_axis, knot_axis, error_axis],
            title="Knot insertion: knots and error per iteration",
            fig_margin={"top": 36, "bottom": 42, "left": 56, "right": 60},
            legend_location="right",
            legend_style={"fill": "white", "stroke": "#d0d7de", "font-size": "11px"},
            title_style={"font-size": "13px"},
            layout=ipywidgets.Layout(width="890px", height="250px"),
            animation_duration=0,
        )
        self.data = None

    def update(self, explorer) -> None:
        result = explorer.result
        if not result.snapshots:
            return
        data = convergence_data(result)
        self.data = data
        x = data["iteration"]
        values = np.concatenate([data["max_error"], data["hausdorff"], [explorer.epsilon]])
        values = values[np.isfinite(values) & (values > 0)]
        top = float(values.max()) * 1.3 if values.size else 1.0
        bottom = float(values.min()) / 1.3 if values.size else 0.1
        with self.knots.hold_sync(), self.error.hold_sync(), self.hausdorff.hold_sync(), self.threshold.hold_sync():
            self.knots.x, self.knots.y = x, data["knots"]
            self.error.x, self.error.y = x, data["max_error"]
            self.hausdorff.x, self.hausdorff.y = x, data["hausdorff"]
            self.threshold.x = [float(x[0]), float(max(x[-1], x[0] + 1))]
            self.threshold.y = [explorer.epsilon, explorer.epsilon]
        self.error_scale.min, self.error_scale.max = bottom, top
        self.x_scale.min, self.x_scale.max = float(x[0]), float(max(x[-1], x[0] + 1))
        # whole-number ticks only (iterations are integers)
        self.x_axis.tick_values = np.unique(np.round(np.linspace(x[0], max(x[-1], x[0] + 1), 9)))
        self.mark(explorer)

    def mark(self, explorer) -> None:
        """Move the vertical marker to the iteration shown in the explorer."""
        if self.data is None:
            return
        x = float(self.data["iteration"][min(explorer.snapshot_index, len(self.data["iteration"]) - 1)])
        with self.current.hold_sync():
            self.current.x = [x, x]
            self.current.y = [float(self.error_scale.min or 0.1), float(self.error_scale.max or 1.0)]
