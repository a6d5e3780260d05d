"""The TraceExplorer's convergence plot: :class:`splinecraft.plot.convergence.ConvergencePlot` fed from it."""
from __future__ import annotations

from ..plot.convergence import ConvergencePlot as _ConvergencePlot, convergence_data  # noqa: F401

__all__ = ["ConvergencePlot", "convergence_data"]


class ConvergencePlot(_ConvergencePlot):
    """The live convergence plot of one TraceExplorer (see ``TraceExplorer.convergence_figure``)."""

    def update(self, explorer) -> None:
        self.show(explorer.result, explorer.epsilon, explorer.snapshot_index)

    def mark(self, explorer_or_index) -> None:
        index = explorer_or_index if isinstance(explorer_or_index, int) else explorer_or_index.snapshot_index
        super().mark(index)
