"""Algorithm 3.2: the GC1 piecewise Timmer curve with shape control (§5.5)."""
from __future__ import annotations

import numpy as np

from ..._validation import check_bool
from ..piecewise import Spline
from ..tangents import _chords
from .pieces import _make_spline, _matching_labels, _segment_values, _tangent_input, scaled_points

# ----------------------------------------------------------------------------------------------------------
# Algorithm 3.2: GC1 with shape control
# ----------------------------------------------------------------------------------------------------------
def timmer_gc1(points, *, closed: bool = False, alpha=None, beta=None, tangents=None,
               shape_scale=None) -> Spline:
    """:math:`G^1` piecewise Timmer curve with shape control (Algorithm 3.2; §5.5).

    Unit tangents from eqs 3.106-3.109 (closed outlines: the interior formula cyclically), or the given
    ``tangents`` normalised, and user tangent scales :math:`\\alpha_i,\\beta_i>0` per piece, rendered with
    §5.1 (eq 3.92 with erratum E14). The unit tangent is continuous, so the curve is :math:`G^1`;
    it is :math:`C^1` at joint :math:`i` iff :math:`\\beta_{i-1}=\\alpha_i` (status ``"c1"``, else ``"g1"``).

    Scale: the end speed is :math:`4/\\alpha_i`, so with pixel coordinates :math:`\\alpha\\approx1..20` already
    gives nearly straight pieces. The scale-free alternative ``shape_scale`` :math:`s_i` sets
    :math:`\\alpha_i=\\beta_i=4/(s_i\\|P_{i+1}-P_i\\|)`: the tangent length is :math:`s_i` times the chord
    (``s = 1`` puts the Bézier inner points at a third of the chord; 0 would be the polygon).

    Parameters
    ----------
    points : array_like, shape (n, 2)
    closed : bool
    alpha, beta : float or array_like, shape (m,), optional
        Tangent scales per piece (> 0). ``beta`` defaults to ``alpha``.
    tangents : array_like, shape (n, 2), optional
    shape_scale : float or array_like, shape (m,), optional
        Scale-free control, exclusive with ``alpha``/``beta``. When neither is given, ``shape_scale=1``.

    Returns
    -------
    Spline
        ``info``: ``form="timmer_gc1"``, ``alpha``, ``beta``, ``shape_scale`` (or ``None``), ``joint_status``,
        ``curvature_jump``. ``auxiliary``: ``Q1``, ``Q2``, ``tangents`` (unit).
    """
    closed = check_bool(closed, "closed")
    pts, exponent = scaled_points(points, closed)
    tan = _tangent_input(pts, tangents, closed)
    chords = np.linalg.norm(_chords(pts, closed), axis=1)
    m = chords.shape[0]
    if shape_scale is not None and (alpha is not None or beta is not None):
        raise ValueError("give either shape_scale or alpha/beta, not both")
    if alpha is None and beta is not None:
        raise ValueError("beta given without alpha; pass alpha (beta defaults to alpha)")
    scale_values = None
    if alpha is None:
        scale_values = _segment_values(1.0 if shape_scale is None else shape_scale, m, "shape_scale")
        alpha_values = 4.0 / (scale_values * chords)
        beta_values = alpha_values.copy()
    else:
        alpha_values = _scaled_scale(_segment_values(alpha, m, "alpha"), exponent, "alpha")  # units of 1 / length
        beta_values = alpha_values.copy() if beta is None else _scaled_scale(_segment_values(beta, m, "beta"),
                                                                              exponent, "beta")
    labels = _matching_labels(np.roll(beta_values, 1), alpha_values, "c1", "g1")   # k = 0: closing joint
    extra = {"shape_scale": None if scale_values is None else scale_values.tolist()}
    return _make_spline("timmer_gc1", pts, tan, alpha_values, beta_values, closed, labels, extra, exponent=exponent)


def _scaled_scale(values, exponent, name):
    """User tangent scales in the units of the scaled points (times ``2^exponent``), checked to stay in range."""
    with np.errstate(over="ignore", under="ignore"):
        scaled = np.ldexp(values, exponent)
    bad = ~(np.isfinite(scaled) & (scaled > 0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name}[{i}] = {float(values[i])!r} is out of range for points of this size "
                         f"({name} times the size of the points leaves the float64 range)")
    return scaled
