"""Timmer parametric cubic splines (§5, thesis section 3.3, eqs 3.85-3.133).

A Timmer piece through :math:`P_i, P_{i+1}` with tangents :math:`T_i, T_{i+1}` and tangent scales
:math:`\\alpha_i, \\beta_i > 0` is (§5.1, thesis eq 3.89 with errata E13, E14)

.. math::
    H_i(\\theta)=f_0P_i+f_1Q_{i,1}+f_2Q_{i,2}+f_3P_{i+1},\\qquad
    Q_{i,1}=P_i+T_i/\\alpha_i,\\quad Q_{i,2}=P_{i+1}-T_{i+1}/\\beta_i,

with the blending functions :math:`f_0=(1-2\\theta)(1-\\theta)^2`, :math:`f_1=4\\theta(1-\\theta)^2`,
:math:`f_2=4\\theta^2(1-\\theta)`, :math:`f_3=(2\\theta-1)\\theta^2`. Its exact Bézier points are
:math:`b_1=P_i+\\tfrac43T_i/\\alpha_i`, :math:`b_2=P_{i+1}-\\tfrac43T_{i+1}/\\beta_i`; every piece runs over a unit
parameter interval (knots ``0, 1, ..., m``; §5.1: :math:`h=1`). Note that thesis section 3.3 uses
:math:`\\alpha,\\beta` as *tangent scales* (the end speed is :math:`4/\\alpha`), not as the class parameter of §1.

Three schemes build a whole curve (every one returns a :class:`~splinecraft.spline.piecewise.Spline`; one module each):

* :func:`timmer_g2` -- Algorithm 3.1 (§5.4, errata E16-E18): unit tangents, one
  :math:`\\alpha_i=\\beta_i` per piece chosen joint by joint so that the curvature is continuous.
* :func:`timmer_gc1` -- Algorithm 3.2 (§5.5): unit tangents and user tangent scales; :math:`G^1`.
* :func:`timmer_gc2` -- Algorithm 3.3 (§5.6, errata E19, E20): the tangents solve one banded system;
  the thesis joint (:math:`C^2` only when :math:`\\alpha_i=\\beta_{i-1}`) or the true :math:`G^2` joint.

Every result carries ``info`` (JSON-able) with ``form``, the per-piece ``alpha``/``beta`` and, per knot
(the rows of :meth:`Spline.joint_curvature`), ``joint_status`` and ``curvature_jump``
(:math:`\\kappa(t_i^+)-\\kappa(t_i^-)` measured on the Bézier pieces; ``None`` at the ends of an open curve,
for a loop the last entry repeats the first), and ``auxiliary`` with ``'Q1'``, ``'Q2'`` (the Timmer
polygon points, one per piece) and ``'tangents'`` (one per point).
"""
from .g2 import _g2_sweep, timmer_g2  # noqa: F401 (_g2_sweep: for tests of the sweep)
from .gc1 import timmer_gc1
from .gc2 import timmer_gc2
from .pieces import JOINT_STATUSES, timmer_bezier, timmer_blending_functions, timmer_end_curvatures

__all__ = [
    "timmer_blending_functions",
    "timmer_bezier",
    "timmer_end_curvatures",
    "timmer_g2",
    "timmer_gc1",
    "timmer_gc2",
    "JOINT_STATUSES",
]
