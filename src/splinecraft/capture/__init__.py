"""Outline capture: bitmap -> chain-code boundaries -> corners -> spline fit -> knot insertion.

Shared file: each module owner edits only the import line(s) of their own module.
"""
from .image import load_bitmap
from .contour import Boundary, Boundaries, trace_boundaries
from .corners import corners, CORNER_METHODS
from .fitting import fit_outline, FitResult, Snapshot, KNOT_METHODS
from .trace import trace, TraceResult
from .trace_stages import TraceStages

__all__ = [
    "load_bitmap",
    "Boundary",
    "Boundaries",
    "trace_boundaries",
    "corners",
    "CORNER_METHODS",
    "fit_outline",
    "FitResult",
    "Snapshot",
    "KNOT_METHODS",
    "trace",
    "TraceResult",
    "TraceStages",
]
