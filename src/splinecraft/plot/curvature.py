"""The curvature profile κ(t) of a planar spline, with the one-sided jumps at its joints (bqplot).

The interpolant is C¹ at its knots, and G² only where neighbouring interval weights are equal (§2.2,
erratum E2): there ``κ(tᵢ⁺) = (ωᵢ₋₁/ωᵢ) κ(tᵢ⁻)``. Timmer's Algorithm 3.1 leaves joints without a positive
root G¹ (§5), and Algorithm 3.3's thesis joint jumps by ``(αᵢ/βᵢ₋₁)²`` (E20). A comb shows such a jump as a
step; this figure shows it as a number: each piece's κ(t) (``Spline.curvature_profile``, §7) is drawn on
its own, ending in its one-sided limits, and every joint where the two one-sided values
(``Spline.joint_curvature``) differ gets a red bar from κ(tᵢ⁻) to κ(tᵢ⁺).
"""
from __future__ import annotations

import numpy as np

from ._figure import MARGIN, PALETTE, assemble, legend_marks, legend_width
from ._ticks import nice_limits, nice_ticks, tick_format

__all__ = ["curvature_profile", "curvature_figure", "CurvaturePlot", "JUMP_TOLERANCE"]

#: A joint "jumps" when ``|κ⁺ - κ⁻|`` exceeds this fraction of the curve's largest |κ| (rounding stays far below).
JUMP_TOLERANCE = 1e-6
CURVE_COLOR, JUMP_COLOR, JOINT_COLOR = PALETTE[0], "#d32f2f", "#607d8b"
_LEGEND = [("κ(t)", CURVE_COLOR, "solid"), ("jump at a joint", JUMP_COLOR, "solid"),
           ("G² joint", JOINT_COLOR, "dots")]


def curvature_profile(spline, samples_per_piece: int = 48) -> dict:
    """κ(t) piece by piece and the one-sided values at the joints of a planar :class:`~splinecraft.Spline`.

    From :meth:`Spline.curvature_profile` (§7), arranged for drawing. Returns a dict: ``t`` and ``kappa``
    (pieces, samples) -- each row one piece from ``tᵢ`` to ``tᵢ₊₁``, its last sample the left-hand limit
    κ(tᵢ₊₁⁻); ``knots``; ``joints`` (knot indices where two pieces meet: interior knots, and for a loop the
    closing knot ``m``); ``left``/``right`` = κ(tᵢ⁻), κ(tᵢ⁺) there; ``jumps`` (bool per joint, see
    :data:`JUMP_TOLERANCE`).
    """
    from ..spline import Spline

    if not isinstance(spline, Spline):
        raise TypeError(f"spline must be a splinecraft Spline, got {type(spline).__name__}")
    if spline.dim != 2:
        raise ValueError(f"the curvature profile needs a planar curve (d = 2), this curve has d = {spline.dim}")
    profile = spline.curvature_profile(samples_per_piece=samples_per_piece)
    m = spline.n_segments
    t = np.asarray(profile.parameters, dtype=float).reshape(m, -1)
    kappa = np.asarray(profile.curvature, dtype=float).reshape(m, -1)
    joints = np.arange(1, m + 1 if spline.closed else m)
    one_sided = np.asarray(profile.joint_curvature, dtype=float)[joints]
    left, right = one_sided[:, 0], one_sided[:, 1]
    finite = np.abs(kappa[np.isfinite(kappa)])
    scale = float(finite.max()) if finite.size else 0.0
    with np.errstate(invalid="ignore"):
        jumps = np.abs(right - left) > JUMP_TOLERANCE * max(scale, 1e-300)
    return {"t": t, "kappa": kappa, "knots": np.asarray(profile.knots, dtype=float), "joints": joints,
            "left": left, "right": right, "jumps": np.asarray(jumps, dtype=bool)}


class CurvaturePlot:
    """A bqplot Figure of κ(t) for one spline, redrawn in place by :meth:`show` (for a live editor).

    Marks: ``pieces`` (κ(t) of every piece), ``jump_bars`` (red, κ⁻ to κ⁺ at each jumping joint),
    ``joint_dots`` (the one-sided values at every joint: red where they differ, grey at G² joints),
    ``knot_lines`` (faint verticals at the knots).
    Curvature is in 1/px, so small: the marks hold κ × ``display_scale`` (a power of ten, named on the
    y axis) and :attr:`profile` the values themselves.
    """

    def __init__(self, width: int = 560, height: int = 260):
        import bqplot as bq

        self.height = int(height)
        self.x_scale, self.y_scale = bq.LinearScale(), bq.LinearScale()
        scales = {"x": self.x_scale, "y": self.y_scale}
        self.knot_lines = bq.Lines(x=[[0.0, 0.0]], y=[[0.0, 0.0]], scales=scales, colors=["#cfd8dc"], stroke_width=1,
                                   apply_clip=True)
        self.zero_line = bq.Lines(x=[0.0, 1.0], y=[0.0, 0.0], scales=scales, colors=["#b0bec5"], stroke_width=1,
                                  apply_clip=True)
        self.pieces = bq.Lines(x=[[0.0, 1.0]], y=[[0.0, 0.0]], scales=scales, colors=[CURVE_COLOR], stroke_width=2,
                               apply_clip=True)
        self.jump_bars = bq.Lines(x=[[0.0, 0.0]], y=[[0.0, 0.0]], scales=scales, colors=[JUMP_COLOR], stroke_width=4,
                                  apply_clip=True, visible=False)
        self.joint_dots = bq.Scatter(x=[0.0], y=[0.0], scales=scales, colors=[JOINT_COLOR], default_size=22,
                                     stroke="white", apply_clip=True)
        self.x_axis = bq.Axis(scale=self.x_scale, label="t", grid_lines="none")
        self.y_axis = bq.Axis(scale=self.y_scale, side="left", label="κ", grid_lines="none",
                              label_offset="46px")
        margin = dict(MARGIN, left=64, right=legend_width([label for label, _, _ in _LEGEND]))
        legend = legend_marks(_LEGEND, self.height - margin["top"] - margin["bottom"])
        self.figure = assemble([self.knot_lines, self.zero_line, self.pieces, self.jump_bars, self.joint_dots, *legend],
                               [self.x_axis, self.y_axis], title="Curvature κ(t)", width=width, height=self.height,
                               margin=margin)
        self.profile = None
        self.display_scale = 1.0
        self.clipped = False

    def show(self, spline, samples_per_piece: int = 48) -> "CurvaturePlot":
        """Draw the curvature profile of ``spline``; returns self."""
        profile = curvature_profile(spline, samples_per_piece)
        self.profile = profile
        t, kappa, knots = profile["t"], profile["kappa"], profile["knots"]
        joints, left, right, jumps = profile["joints"], profile["left"], profile["right"], profile["jumps"]
        shown, clipped = _axis_range(kappa, left[jumps], right[jumps])
        power = _display_power(shown)                    # κ is in 1/px: show κ × 10^power with round ticks
        self.display_scale = 10.0 ** power
        kappa, left, right = (array * self.display_scale for array in (kappa, left, right))
        low, high = nice_limits(shown[0] * self.display_scale, shown[1] * self.display_scale, 4)
        joint_t = knots[joints]
        with self.pieces.hold_sync(), self.jump_bars.hold_sync(), self.joint_dots.hold_sync(), \
                self.knot_lines.hold_sync(), self.zero_line.hold_sync():
            self.pieces.x, self.pieces.y = t, kappa
            self.pieces.colors = [CURVE_COLOR] * len(t)
            self.knot_lines.x = np.repeat(knots[:, None], 2, axis=1)
            self.knot_lines.y = np.tile([low, high], (len(knots), 1))
            self.knot_lines.colors = ["#cfd8dc"] * len(knots)
            self.zero_line.x = [float(knots[0]), float(knots[-1])]
            if jumps.any():
                self.jump_bars.x = np.repeat(joint_t[jumps][:, None], 2, axis=1)
                self.jump_bars.y = np.stack([left[jumps], right[jumps]], axis=1)
                self.jump_bars.colors = [JUMP_COLOR] * int(jumps.sum())
            self.jump_bars.visible = bool(jumps.any())
            dots_t = np.concatenate([joint_t, joint_t])
            dots_kappa = np.concatenate([left, right])
            dots_color = np.where(np.concatenate([jumps, jumps]), JUMP_COLOR, JOINT_COLOR)
            keep = np.isfinite(dots_kappa)
            self.joint_dots.x, self.joint_dots.y = dots_t[keep], dots_kappa[keep]
            self.joint_dots.colors = dots_color[keep].tolist()
        self.x_scale.min, self.x_scale.max = float(knots[0]), float(knots[-1])
        self.y_scale.min, self.y_scale.max = low, high
        x_ticks, y_ticks = nice_ticks(knots[0], knots[-1], 8), nice_ticks(low, high, 4)
        self.x_axis.tick_values, self.x_axis.tick_format = x_ticks, tick_format(x_ticks)
        self.y_axis.tick_values, self.y_axis.tick_format = y_ticks, tick_format(y_ticks)
        self.y_axis.label = f"κ × 10{_superscript(power)}" if power else "κ"
        count, total = int(jumps.sum()), len(joints)
        self.figure.title = (f"Curvature κ(t): {count} of {total} joints jump (red)" if count
                             else f"Curvature κ(t): G² at all {total} joints")
        self.clipped = clipped
        if clipped:
            self.figure.title += "; the sharpest peaks run off the axis"
        return self


def _axis_range(kappa, *marked):
    """The κ range to show: all of it, unless a few sharp peaks (near-cusps) would flatten the rest.

    Then the 5th-95th percentile of the samples, widened by half on each side and always holding 0 and
    the one-sided values in ``marked`` (the jumps). Returns ``((low, high), clipped)``.
    """
    samples = kappa[np.isfinite(kappa)]
    extra = np.concatenate([np.asarray(m, dtype=float).ravel() for m in marked] + [np.zeros(1)])
    extra = extra[np.isfinite(extra)]
    if not samples.size:
        return (-1.0, 1.0), False
    full = (float(min(samples.min(), extra.min())), float(max(samples.max(), extra.max())))
    low, high = np.percentile(samples, [5.0, 95.0])
    pad = 0.5 * max(high - low, 1e-300)
    robust = (float(min(low - pad, extra.min())), float(max(high + pad, extra.max())))
    if full[1] - full[0] > 3.0 * (robust[1] - robust[0]):
        return robust, True
    return full, False


def _display_power(values) -> int:
    """The power of ten that brings the largest |κ| into [1, 1000) when it is below 0.1 (else 0)."""
    largest = float(np.abs(values).max()) if len(values) else 0.0
    if not largest or largest >= 0.1:
        return 0
    return int(-np.floor(np.log10(largest)))


def _superscript(power: int) -> str:
    return str(power).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))


def curvature_figure(spline, *, width: int = 560, height: int = 260, samples_per_piece: int = 48):
    """A bqplot Figure of κ(t) along ``spline``, one-sided jumps at the joints marked red (see module doc)."""
    return CurvaturePlot(width, height).show(spline, samples_per_piece).figure
