"""The live basis-function plot of the SplineEditor (bqplot), and the data it shows.

Basis and interpolant forms: the local-support basis functions ``B_j(t)`` of the current points used as a
control polygon, with the same knots, point tensions and interval weights (§4.1-4.3): every curve
of §4 is ``sum_j B_j(t) P_j``. The dashed line is ``sum_j B_j(t)``, which is 1 everywhere (partition of
unity); the selected point's ``B_j`` is drawn thick, and it vanishes outside four intervals (local support).
Single-segment mode: the four blending functions of the generic segment (§1) for the current
``alpha, beta``. Timmer forms: Timmer's blending functions ``f_0..f_3`` (§5.1).
"""
from __future__ import annotations

import numpy as np

from ..spline import basis_functions
from ..spline.knots import KNOT_EXPONENTS
from ..spline.segment import blending_functions
from ..spline.timmer import timmer_blending_functions
from ._figure import MARGIN, assemble, legend_marks, legend_width
from ._ticks import nice_ticks, tick_format

__all__ = ["BasisPlot", "basis_plot_data", "basis_knot_values"]

PALETTE = ["#1565c0", "#ef6c00", "#2e7d32", "#8e24aa", "#00838f", "#c62828", "#6d4c41", "#5e35b1",
           "#f9a825", "#37474f"]
Y_RANGE = (-0.15, 1.15)
#: Above this many control points the plot is refreshed only when a drag ends (not on every move).
LIVE_LIMIT = 120
#: Above this many control points only a window of basis functions around the selection is drawn.
WINDOW_LIMIT = 40


def basis_knot_values(points: np.ndarray, knots: str, closed: bool, ends: str):
    """Knot values for :func:`splinecraft.basis_functions` matching :func:`splinecraft.basis_spline` (§3, §4.4).

    Returns ``(knots_or_n, domain)``: the int ``n_control`` for uniform knots, else explicit values (one per
    control point for floating ends, ``n_control - 2`` for clamped, ``N + 1`` closed), and the curve's
    parameter interval.
    """
    n = points.shape[0]
    exponent = KNOT_EXPONENTS[knots]
    legs = np.diff(np.vstack([points, points[:1]]) if closed else points, axis=0)
    steps = np.hypot(legs[:, 0], legs[:, 1]) ** exponent if exponent else np.ones(len(legs))
    if not closed and ends == "clamped":
        steps = steps[1:-1]
    values = np.concatenate([[0.0], np.cumsum(steps)])
    if closed or ends == "clamped":
        domain = (float(values[0]), float(values[-1]))
        if exponent == 0 and not closed:  # uniform clamped knots are the integers 1 .. n - 2 of the floating ones
            domain = (domain[0] + 1.0, domain[1] + 1.0)
    else:
        domain = (float(values[1]), float(values[-2]))
    return (n if exponent == 0 else values), domain


def basis_plot_data(form, points, *, point_tension, interval_weights, alpha, beta, closed, knots, end_condition,
                    selected=-1, samples=None, point_tension_scale="absolute") -> dict:
    """What the basis plot shows for an editor state: ``t``, a 2-d array of curves, labels, title, knots.

    ``point_tension_scale`` as in :func:`splinecraft.basis_spline` (``"relative"``: the scale-free nu of §2.5).

    Raises ``ValueError`` when the basis is not defined for this state (too few points, degenerate).
    """
    points = np.asarray(points, dtype=float)
    if form in ("segment",) or form.startswith("timmer"):
        theta = np.linspace(0.0, 1.0, 201)
        if form == "segment":
            values = blending_functions(theta, alpha, beta)
            title = f"Generic segment blending functions, α = {alpha:g}, β = {beta:g} (eq 3.5): Σ = 1"
            labels = ["F₀: (1−θ)²(1+(2−α)θ)", "V: αθ(1−θ)²", "W: βθ²(1−θ)", "F₁: θ²(1+(2−β)(1−θ))"]
        else:
            values = timmer_blending_functions(theta)
            title = "Timmer blending functions f₀..f₃ (eqs 3.85–3.88): Σ = 1, f₀, f₃ dip below 0"
            labels = ["f₀ (Pᵢ)", "f₁ (Q₁)", "f₂ (Q₂)", "f₃ (Pᵢ₊₁)"]
        return {"t": theta, "values": values.T, "labels": labels, "title": title, "knots": np.array([0.0, 1.0]),
                "highlight": None, "x_label": "θ"}
    ends = "floating" if form == "interpolant" else (end_condition if end_condition in ("floating", "clamped") else "floating")
    n = points.shape[0]
    if n < (3 if closed else 4):
        raise ValueError(f"the local-support basis needs at least {3 if closed else 4} control points")
    knots_or_n, (t0, t1) = basis_knot_values(points, knots, closed, ends)
    first, last = 0, n
    if n > WINDOW_LIMIT:
        centre = selected if 0 <= selected < n else 0
        first, last = max(0, centre - 6), min(n, centre + 7)
    knot_values = (np.arange(n + 1 if closed else n, dtype=float) if isinstance(knots_or_n, int)
                   else np.asarray(knots_or_n, dtype=float))
    if n > WINDOW_LIMIT:
        lo_index = max(first - 2, 0)
        hi_index = min(last + 2, len(knot_values) - 1)
        t0, t1 = max(t0, float(knot_values[lo_index])), min(t1, float(knot_values[hi_index]))
    count = samples or int(np.clip(40 * (last - first), 300, 2000))
    t = np.linspace(t0, t1, count)
    values = basis_functions(t, knots_or_n, point_tension=point_tension, interval_weights=interval_weights,
                             closed=closed, ends=ends, point_tension_scale=point_tension_scale)
    total = np.asarray(values.sum(axis=1)).reshape(-1)
    shown = values[:, first:last].toarray().T
    labels = [f"B{j}" for j in range(first, last)]
    where = "" if form == "basis" else " (these points as control points)"
    title = f"Local-support basis B_j(t){where}: Σ B_j = 1, each B_j lives on 4 intervals"
    if n > WINDOW_LIMIT:
        title += f" — B{first}..B{last - 1} of {n}"
    in_range = knot_values[(knot_values >= t0 - 1e-12) & (knot_values <= t1 + 1e-12)]
    highlight = values[:, [selected]].toarray()[:, 0] if 0 <= selected < n else None
    return {"t": t, "values": shown, "sum": total, "labels": labels, "title": title, "knots": in_range,
            "highlight": highlight, "x_label": "t"}


class BasisPlot:
    """A bqplot Figure of the basis functions of one editor state, redrawn in place by :meth:`show`.

    ``figure`` is the Figure; ``lines`` (every shown Bⱼ), ``sum_line`` (Σ Bⱼ, dashed), ``highlight`` (the
    selected Bⱼ, thick) and ``knot_ticks`` are its marks. The y axis is fixed to [-0.15, 1.15] with ticks
    0, 0.5, 1; the x axis gets round ticks on every :meth:`show`; the legend is in the right margin.
    """

    HEIGHT = 240

    def __init__(self):
        import bqplot as bq

        self.x_scale = bq.LinearScale()
        self.y_scale = bq.LinearScale(min=Y_RANGE[0], max=Y_RANGE[1])
        scales = {"x": self.x_scale, "y": self.y_scale}
        self.knot_ticks = bq.Lines(x=[[0.0, 0.0]], y=[[-0.15, -0.08]], scales=scales, colors=["#90a4ae"],
                                   stroke_width=1.2)
        self.lines = bq.Lines(x=[0.0, 1.0], y=[[0.0, 0.0]], scales=scales, colors=PALETTE, stroke_width=1.6,
                              opacities=[0.9])
        self.highlight = bq.Lines(x=[0.0, 1.0], y=[0.0, 0.0], scales=scales, colors=["#e53935"], stroke_width=3.5,
                                  visible=False)
        self.sum_line = bq.Lines(x=[0.0, 1.0], y=[1.0, 1.0], scales=scales, colors=["#263238"], stroke_width=1.5,
                                 line_style="dashed")
        self.x_axis = bq.Axis(scale=self.x_scale, label="t", grid_lines="none")
        y_axis = bq.Axis(scale=self.y_scale, side="left", label="value",
                         tick_values=[0.0, 0.5, 1.0], tick_format=".1f", grid_lines="dashed", grid_color="#e0e0e0",
                         label_offset="40px")
        margin = dict(MARGIN, right=legend_width(["selected Bⱼ", "Σ Bⱼ = 1"]))
        plot_height = self.HEIGHT - margin["top"] - margin["bottom"]
        legend = legend_marks([("Σ Bⱼ = 1", "#263238", "dashed"), ("selected Bⱼ", "#e53935", "solid")], plot_height)
        self.figure = assemble([self.knot_ticks, self.lines, self.sum_line, self.highlight, *legend],
                               [self.x_axis, y_axis], title="", width=890, height=self.HEIGHT, margin=margin)
        self.data = None
        self.error = None

    def show(self, form, points, **state) -> None:
        """Redraw for an editor state (the arguments of :func:`basis_plot_data`).

        A state without a basis (too few points, degenerate) keeps the last curves and puts the reason in
        the title (``error``).
        """
        try:
            data = basis_plot_data(form, points, **state)
        except ValueError as exc:
            self.error = str(exc)
            self.figure.title = f"Basis plot: {exc}"
            return
        self.error = None
        self.data = data
        t = data["t"]
        with self.lines.hold_sync(), self.sum_line.hold_sync(), self.highlight.hold_sync(), self.knot_ticks.hold_sync():
            self.lines.x = t
            self.lines.y = data["values"]
            self.lines.labels = data["labels"]
            total = data.get("sum")
            if total is None:
                total = data["values"].sum(axis=0)
            self.sum_line.x = t
            self.sum_line.y = total
            if data["highlight"] is not None:
                self.highlight.x = t
                self.highlight.y = data["highlight"]
                self.highlight.visible = True
            else:
                self.highlight.visible = False
            knots = data["knots"]
            self.knot_ticks.x = np.repeat(knots[:, None], 2, axis=1)
            self.knot_ticks.y = np.tile([-0.15, -0.08], (len(knots), 1))
        low, high = float(t[0]), float(t[-1])
        self.x_scale.min, self.x_scale.max = low, high
        ticks = nice_ticks(low, high, 8)
        self.x_axis.tick_values = ticks
        self.x_axis.tick_format = tick_format(ticks)
        self.x_axis.label = data["x_label"]
        self.figure.title = data["title"]
