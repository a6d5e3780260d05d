"""splinecraft: design and capture planar shapes with smooth generic cubic splines.

Layers (data flows one way, top to bottom):

* :mod:`splinecraft.spline`  -- the math engine (numpy/scipy only): generic cubic segment, GC^2
  interpolant, local-support basis form, Timmer schemes; every curve is a :class:`Spline` of
  exact cubic Bezier pieces.
* :mod:`splinecraft.capture` -- outline capture: bitmap -> chain-code boundaries -> corners ->
  spline fit per piece -> knot insertion with snapshots.
* :mod:`splinecraft.widgets` -- anywidget front ends (imported lazily, so the engine never needs
  a Jupyter stack); :mod:`splinecraft.cli` -- the command line.
"""
from .spline import *  # noqa: F401,F403
from .spline import __all__ as _spline_all
from .capture import *  # noqa: F401,F403
from .capture import __all__ as _capture_all
from . import datasets  # noqa: F401  (thesis-like test bitmaps, teaching shapes, demo points)

__version__ = "0.1.0"

_WIDGETS = ("SplineEditor", "TraceExplorer")


def __getattr__(name):
    # Widgets import anywidget/ipywidgets: load them only when asked for.
    if name in _WIDGETS:
        from . import widgets

        return getattr(widgets, name)
    raise AttributeError(f"module 'splinecraft' has no attribute {name!r}")


__all__ = [*_spline_all, *_capture_all, *_WIDGETS]
