"""The SplineEditor's live figures: :class:`splinecraft.plot.basis.BasisPlot` and
:class:`splinecraft.plot.curvature.CurvaturePlot`, fed from the editor."""
from __future__ import annotations

from ..plot.basis import LIVE_LIMIT, BasisPlot as _BasisPlot, basis_plot_data  # noqa: F401
from ..plot.curvature import CurvaturePlot as _CurvaturePlot

__all__ = ["BasisPlot", "CurvaturePlot", "basis_plot_data"]


class BasisPlot(_BasisPlot):
    """The live basis plot of one SplineEditor (see :attr:`SplineEditor.basis_figure`)."""

    def update(self, editor, *, final: bool = True) -> None:
        """Recompute from the editor's state; during drags with many points only on ``final``."""
        if not final and len(editor.points) > LIVE_LIMIT:
            return
        self.show(editor.form, editor.points, point_tension=editor.point_tension,
                  point_tension_scale=editor.tension_scale, interval_weights=editor.interval_weights,
                  alpha=editor.alpha, beta=editor.beta, closed=editor.closed, knots=editor.knots,
                  end_condition=editor.end_condition, selected=editor.selected)


class CurvaturePlot(_CurvaturePlot):
    """The live κ(t) plot of one SplineEditor (see :attr:`SplineEditor.curvature_figure`)."""

    def update(self, editor, *, final: bool = True) -> None:
        """Redraw for the editor's curve; during drags with many points only on ``final``."""
        if final or len(editor.points) <= LIVE_LIMIT:
            self.show(editor.spline)
