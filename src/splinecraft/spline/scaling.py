"""Exact rescaling of a problem to unit size, so that the solvers work at every float64 scale (§2.5 Units).

The constructions scale their input points by ``2^-k`` for an even ``k`` chosen so that the largest
coordinate lies in ``[1, 4)``, solve, and scale the results back by ``2^k``. Multiplying by a power of
two is exact in floating point (away from the subnormal range), so at moderate scales (``k = 0``) and
at any other scale the results are those of the unscaled arithmetic, without its overflow (squares of
1e200) or underflow (squares of 1e-170). Quantities with units follow the points: chord-length knots
scale by ``2^k``, centripetal ones by ``2^(k/2)`` (hence even ``k``), uniform and explicit knots not at
all, and a point tension ``v`` (units of ``omega / h``) scales like the knots.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["even_exponent", "knot_exponent", "unscale_knots", "MODERATE_EXPONENT"]

#: Inputs whose largest coordinate lies within 2^-MODERATE_EXPONENT .. 2^MODERATE_EXPONENT are not rescaled.
MODERATE_EXPONENT = 100


def even_exponent(points: np.ndarray) -> int:
    """An even ``k`` with ``max |points| / 2^k`` in ``[1, 4)``; 0 for moderate sizes or all-zero points."""
    size = float(np.max(np.abs(points))) if points.size else 0.0
    if size == 0.0:
        return 0
    exponent = math.frexp(size)[1] - 1  # 2^exponent <= size < 2^(exponent + 1)
    if -MODERATE_EXPONENT <= exponent <= MODERATE_EXPONENT:
        return 0
    return exponent - (exponent % 2)


def knot_exponent(knots, exponent: int) -> int:
    """How the knots scale when the points scale by ``2^exponent``: their power of two (§3)."""
    if not isinstance(knots, str) or knots == "uniform":
        return 0
    return exponent if knots == "chord" else exponent // 2


def unscale_knots(values, knot_scale: int, knots, points_name="points"):
    """Knots of the scaled problem back in the input's units (times ``2^knot_scale``), refused when they
    leave the float64 range (the total chord length of points near the float64 limit can)."""
    with np.errstate(over="ignore"):
        result = np.ldexp(values, knot_scale)
    if not np.isfinite(result).all():
        raise ValueError(
            f"knots: the {knots!r} knot values of these {points_name} exceed the float64 range (the total length "
            f"of the polygon is beyond 1.8e308); pass knots='uniform' or explicit knot values"
        )
    return result
