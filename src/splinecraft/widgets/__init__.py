"""anywidget front ends for JupyterLab: :class:`SplineEditor` and :class:`TraceExplorer`.

The ES modules that draw them live in ``js/`` at the top of the repository (installed as
``splinecraft/widgets/static``). The kernel computes every curve; the page only draws.
"""
from .spline_editor import SplineEditor, SplineEditorWarning
from .trace_explorer import TraceExplorer

__all__ = ["SplineEditor", "SplineEditorWarning", "TraceExplorer"]
