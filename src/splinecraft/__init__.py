"""splinecraft: design and capture planar shapes with smooth generic cubic splines.

Layers (data flows one way, top to bottom):

* :mod:`splinecraft.spline`  -- the math engine (numpy/scipy only): generic cubic segment, GC^2
  interpolant, local-support basis form, Timmer schemes; every curve is a :class:`Spline` of
  exact cubic Bezier pieces.
* :mod:`splinecraft.capture` -- outline capture: bitmap -> chain-code boundaries -> corners ->
  spline fit per piece -> knot insertion with snapshots.
* :mod:`splinecraft.widgets` -- anywidget front ends (imported lazily, so the engine never needs
  a Jupyter stack); :mod:`splinecraft.cli` -- the command line; :mod:`splinecraft.batch` --
  :func:`trace_many`, many bitmaps at once (local processes or dask).
"""
from .spline import *  # noqa: F401,F403
from .spline import __all__ as _spline_all

__version__ = "0.1.0"

# Capture (scikit-image, PIL), widgets (anywidget, ipywidgets) and datasets load on first use, so that the
# engine imports fast and never needs the layers above it.
_CAPTURE = (
    "load_bitmap", "Boundary", "trace_boundaries", "corners", "CORNER_METHODS",
    "fit_outline", "FitResult", "Snapshot", "KNOT_METHODS", "trace", "TraceResult",
)
_WIDGETS = ("SplineEditor", "TraceExplorer", "OutlineEditor")
_BATCH = ("trace_many",)
_SUBMODULES = ("spline", "capture", "widgets", "plot", "datasets", "cli", "outline", "font", "batch")


def __getattr__(name):
    import importlib

    if name in _CAPTURE:
        return getattr(importlib.import_module(".capture", __name__), name)
    if name in _WIDGETS:
        return getattr(importlib.import_module(".widgets", __name__), name)
    if name in _BATCH:
        return getattr(importlib.import_module(".batch", __name__), name)
    if name in _SUBMODULES:
        return importlib.import_module("." + name, __name__)
    raise AttributeError(f"module 'splinecraft' has no attribute {name!r}")


def __dir__():
    return sorted({*globals(), *_CAPTURE, *_WIDGETS, *_BATCH, *_SUBMODULES})


__all__ = [*_spline_all, *_CAPTURE, *_WIDGETS, *_BATCH]
