"""anywidget front ends for JupyterLab: :class:`SplineEditor` and :class:`TraceExplorer`.

The ES modules that draw them live in ``js/`` at the top of the repository (installed as
``splinecraft/widgets/static``). The kernel computes every curve; the page only draws.
``TraceExplorer`` loads the capture layer on first use, so the editor needs only the engine.
"""
from .spline_editor import SplineEditor, SplineEditorWarning

__all__ = ["SplineEditor", "SplineEditorWarning", "TraceExplorer", "TraceExplorerWarning", "OutlineEditor",
           "OutlineEditorWarning"]


def __getattr__(name):
    if name in ("TraceExplorer", "TraceExplorerWarning"):
        from . import trace_explorer

        return getattr(trace_explorer, name)
    if name in ("OutlineEditor", "OutlineEditorWarning"):
        from . import outline_editor

        return getattr(outline_editor, name)
    raise AttributeError(f"module 'splinecraft.widgets' has no attribute {name!r}")
