"""The math engine: pure numpy/scipy, no imports from the layers above (§0-§8 of docs/math.md)."""
from .piecewise import Spline
from .interpolant import interpolate
from .basis import basis_spline, basis_functions
from .segment import generic_segment, CLASS_PRESETS
from .timmer import timmer_g2, timmer_gc1, timmer_gc2
from .tangents import estimate_tangents

__all__ = [
    "Spline",
    "interpolate",
    "basis_spline",
    "basis_functions",
    "generic_segment",
    "CLASS_PRESETS",
    "timmer_g2",
    "timmer_gc1",
    "timmer_gc2",
    "estimate_tangents",
]
