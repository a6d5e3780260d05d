"""One Timmer piece (§5.1-§5.3), the joint report, and the step every Timmer scheme ends with."""
from __future__ import annotations

import numpy as np

from ..._validation import as_float_array
from ..piecewise import Spline
from ..scaling import even_exponent
from ..tangents import _chords, _validate_points, estimate_tangents, unit_tangents

JOINT_STATUSES = {
    "end": "open end of the curve (no joint)",
    "g2": "curvature continuous (Alg 3.1 root, Alg 3.3 'g2' joint, or a closing joint that was matched)",
    "c2": "second derivative continuous (Alg 3.3 'thesis' joint with alpha_i == beta_{i-1})",
    "c1": "first derivative continuous, curvature may jump (Alg 3.2 with beta_{i-1} == alpha_i)",
    "g1": "unit tangent continuous, curvature may jump",
    "g1_no_root": "Alg 3.1: the joint quadratic has no positive real root; fallback alpha, curvature jumps",
    "g1_degenerate": "Alg 3.1: S_i = C_i = 0, kappa_i(0) = 0 for every alpha but the target is not 0",
    "g1_closing": "Alg 3.1, closed: the closing joint is not curvature continuous (no alpha_0 found, or alpha0 given)",
    "degenerate": "zero end speed on a side of the joint (a tangent vanished); curvature undefined",
}

# Relative tolerances.
_ZERO_RTOL = 1e-12          # S_i (relative to the chord) and C_i treated as zero below this
_G2_RTOL = 1e-9             # closing-joint curvature match (relative to the curvature scale)
_EQUAL_RTOL = 1e-12         # alpha_i == beta_{i-1} test for the c1 / c2 labels
_RCOND_MIN = 1e-12          # reciprocal condition number below which Alg 3.3 is rejected

_G2_CODES = ("g2", "g1_no_root", "g1_degenerate")

#: Points below 2^-MIN_TIMMER_EXPONENT are refused: alpha = 4 / chord of unit tangents would overflow.
MIN_TIMMER_EXPONENT = 1000


# ----------------------------------------------------------------------------------------------------------
# one piece
# ----------------------------------------------------------------------------------------------------------
def timmer_blending_functions(theta) -> np.ndarray:
    """Timmer blending functions :math:`f_0..f_3` (§5.1, thesis eqs 3.85-3.88, E13: 3.88 is :math:`f_3`).

    .. math::
        f_0=(1-2\\theta)(1-\\theta)^2,\\quad f_1=4\\theta(1-\\theta)^2,\\quad f_2=4\\theta^2(1-\\theta),\\quad
        f_3=(2\\theta-1)\\theta^2.

    They sum to 1 and :math:`f_i(1-\\theta)=f_{3-i}(\\theta)`; :math:`f_0` and :math:`f_3` dip to :math:`-1/27`
    (at :math:`\\theta=2/3` and :math:`1/3`), so a Timmer piece need not lie in its convex hull. Values
    (E15): :math:`f(0)=(1,0,0,0)`, :math:`f(1)=(0,0,0,1)`, :math:`f(\\tfrac12)=(0,\\tfrac12,\\tfrac12,0)`.

    Parameters
    ----------
    theta : float or array_like
        Local parameters (any shape; normally in [0, 1]).

    Returns
    -------
    numpy.ndarray, shape ``theta.shape + (4,)``
    """
    t = as_float_array(theta, "theta")
    s = 1.0 - t
    return np.stack([(1.0 - 2.0 * t) * s * s, 4.0 * t * s * s, 4.0 * t * t * s, (2.0 * t - 1.0) * t * t],
                    axis=-1)


def _segment_values(value, count: int, name: str) -> np.ndarray:
    """A positive finite scalar broadcast to ``(count,)`` or a ``(count,)`` array of them (one per piece)."""
    array = as_float_array(value, name)
    if array.ndim == 0:
        array = np.full(count, float(array))
    elif array.shape != (count,):
        raise ValueError(f"{name} must be a scalar or have shape ({count},) (one value per piece), "
                         f"got shape {array.shape}")
    bad = np.flatnonzero(~(array > 0.0))
    if bad.size:
        where = "" if np.ndim(value) == 0 else f"[{bad[0]}]"
        raise ValueError(f"{name}{where} must be > 0, got {float(array[bad[0]])!r}")
    return array


def _planar_points(points, closed: bool) -> np.ndarray:
    pts = _validate_points(points, closed=closed)
    if pts.shape[1] != 2:
        raise ValueError(f"points must be planar, shape (n, 2), got shape {pts.shape}")
    return pts


def _segment_ends(points: np.ndarray, closed: bool):
    """Start and end points of every piece (``n-1`` open, ``n`` closed)."""
    if closed:
        return points, np.roll(points, -1, axis=0)
    return points[:-1], points[1:]


def timmer_bezier(points, tangents, alpha, beta, *, closed: bool = False):
    """Bézier control points of the Timmer pieces through ``points`` (§5.1, eqs 3.89-3.91 with E14).

    Piece ``i`` (from ``points[i]`` to ``points[i+1]``, cyclically when ``closed``) is
    :math:`[P_i,\\ P_i+\\tfrac43T_i/\\alpha_i,\\ P_{i+1}-\\tfrac43T_{i+1}/\\beta_i,\\ P_{i+1}]`, and its Timmer
    polygon points are :math:`Q_{i,1}=P_i+T_i/\\alpha_i`, :math:`Q_{i,2}=P_{i+1}-T_{i+1}/\\beta_i` (E14: the
    thesis's first line of 3.91 prints :math:`+T_{i+1}/\\beta_i`).

    Parameters
    ----------
    points : array_like, shape (n, d)
    tangents : array_like, shape (n, d)
        :math:`T_i` (unit or not) at every point.
    alpha, beta : float or array_like, shape (m,)
        Tangent scales per piece, > 0 (``m = n - 1`` open, ``n`` closed).
    closed : bool

    Returns
    -------
    bezier : numpy.ndarray, shape (m, 4, d)
    q1, q2 : numpy.ndarray, shape (m, d)
    """
    pts = _validate_points(points, closed=closed)
    tan = as_float_array(tangents, "tangents")
    if tan.shape != pts.shape:
        raise ValueError(f"tangents must have shape {pts.shape} (one per point), got {tan.shape}")
    count = pts.shape[0] if closed else pts.shape[0] - 1
    alpha = _segment_values(alpha, count, "alpha")
    beta = _segment_values(beta, count, "beta")
    return _bezier_from(pts, tan, alpha, beta, closed)


def _bezier_from(pts, tan, alpha, beta, closed):
    start, end = _segment_ends(pts, closed)
    t_start, t_end = _segment_ends(tan, closed)
    q1 = start + t_start / alpha[:, None]
    q2 = end - t_end / beta[:, None]
    bezier = np.stack([start, start + (4.0 / 3.0) * t_start / alpha[:, None],
                       end - (4.0 / 3.0) * t_end / beta[:, None], end], axis=1)
    return bezier, q1, q2


def _cross(u, w):
    return u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]


def timmer_end_curvatures(points, tangents, alpha, beta, *, closed: bool = False):
    """Curvature at both ends of every Timmer piece, for unit tangents (§5.3, eqs 3.116-3.118).

    With :math:`S_i=T_i\\times(P_{i+1}-P_i)`, :math:`U_i=T_{i+1}\\times(P_{i+1}-P_i)` and
    :math:`C_i=T_i\\times T_{i+1}`:

    .. math::
        \\kappa_i(0)=\\tfrac38\\alpha_i^2S_i-\\frac{\\alpha_i^2}{2\\beta_i}C_i,\\qquad
        \\kappa_i(1)=-\\tfrac38\\beta_i^2U_i-\\frac{\\beta_i^2}{2\\alpha_i}C_i.

    With :math:`\\beta_i=\\alpha_i` these are thesis eqs 3.117 and 3.118.

    Parameters
    ----------
    points : array_like, shape (n, 2)
    tangents : array_like, shape (n, 2)
        Normalised to unit length here (zero rows are rejected).
    alpha, beta : float or array_like, shape (m,)
    closed : bool

    Returns
    -------
    kappa_start, kappa_end : numpy.ndarray, shape (m,)
    """
    pts = _planar_points(points, closed)
    tan = unit_tangents(tangents)
    if tan.shape != pts.shape:
        raise ValueError(f"tangents must have shape {pts.shape} (one per point), got {tan.shape}")
    count = pts.shape[0] if closed else pts.shape[0] - 1
    alpha = _segment_values(alpha, count, "alpha")
    beta = _segment_values(beta, count, "beta")
    s_term, u_term, c_term = _timmer_cross_terms(pts, tan, closed)
    kappa_start = 0.375 * alpha**2 * s_term - alpha**2 / (2.0 * beta) * c_term
    kappa_end = -0.375 * beta**2 * u_term - beta**2 / (2.0 * alpha) * c_term
    return kappa_start, kappa_end


def _timmer_cross_terms(pts, unit_tan, closed):
    """:math:`S_i, U_i, C_i` of §5.3 for every piece."""
    chords = _chords(pts, closed)
    t_start, t_end = _segment_ends(unit_tan, closed)
    return _cross(t_start, chords), _cross(t_end, chords), _cross(t_start, t_end)


# ----------------------------------------------------------------------------------------------------------
# joint reporting
# ----------------------------------------------------------------------------------------------------------
def _joint_report(curve: Spline, joint_labels: list) -> tuple[list, list]:
    """Per-knot ``joint_status`` and ``curvature_jump`` lists (length m+1), measured on ``curve``.

    ``joint_labels`` gives the label of joint ``k`` for ``k = 0..m-1`` (index 0 is the closing joint of a
    loop and ignored for an open curve). The jump is :math:`\\kappa(t_k^+)-\\kappa(t_k^-)` from
    :meth:`Spline.joint_curvature` (§7). A joint with a vanished end speed is labelled
    ``"degenerate"`` with jump ``None``.
    """
    m = curve.n_segments
    kappa = curve.joint_curvature()
    jump = kappa[:, 1] - kappa[:, 0]
    status = np.array(joint_labels + joint_labels[:1], dtype=object)
    defined = np.isfinite(jump)
    status[~defined] = "degenerate"
    if not curve.closed:
        status[[0, m]] = "end"
        defined[[0, m]] = False
    jumps = np.where(defined, jump, 0.0).tolist()
    for k in np.flatnonzero(~defined).tolist():
        jumps[k] = None
    return status.tolist(), jumps


def _matching_labels(before, after, equal_label, other_label) -> list:
    """Joint labels: ``equal_label`` where :math:`\\beta_{k-1}=\\alpha_k` (relative 1e-12), else ``other_label``."""
    equal = np.abs(before - after) <= _EQUAL_RTOL * np.maximum(before, after)
    return np.where(equal, equal_label, other_label).tolist()


def scaled_points(points, closed):
    """Validated planar points and the exponent ``k`` of their exact scaling by ``2^-k`` (§0; scaling.py).

    The schemes run on ``points / 2^k`` (unit size, any float64 scale works) and :func:`_make_spline`
    scales the curve back. Tangent scales ``alpha`` of unit tangents have the units of one over a length
    (the handle is ``T / alpha``), so they scale by ``2^k``.
    """
    pts = _planar_points(points, closed)
    exponent = even_exponent(pts)
    if exponent < -MIN_TIMMER_EXPONENT:
        raise ValueError(
            f"points are too small for the Timmer schemes (largest coordinate {float(np.max(np.abs(pts))):.3g}): "
            f"their tangent scales alpha ~ 4 / chord (§5.1) would exceed the float64 range; scale the points up"
        )
    return (np.ldexp(pts, -exponent) if exponent else pts), exponent


def unscale_alpha(values, exponent):
    """Tangent scales of unit tangents back in the units of the input points (times ``2^-exponent``)."""
    with np.errstate(over="ignore"):
        result = np.ldexp(np.asarray(values, dtype=float), -exponent)
    return result


def _make_spline(form, pts, tan, alpha, beta, closed, joint_labels, extra_info, *, exponent=0,
                 unit_tangents=True):
    """The Timmer curve of the scaled problem, scaled back by ``2^exponent``, with its joint report.

    ``unit_tangents``: the tangents are unit vectors and ``alpha``, ``beta`` have the units of one over a
    length (Algorithms 3.1, 3.2); otherwise the tangents are lengths and the scales dimensionless (3.3).
    """
    with np.errstate(over="ignore"):
        bezier, q1, q2 = _bezier_from(pts, tan, alpha, beta, closed)
    if exponent:
        bezier, q1, q2 = (np.ldexp(array, exponent) for array in (bezier, q1, q2))
        if unit_tangents:
            alpha, beta = unscale_alpha(alpha, exponent), unscale_alpha(beta, exponent)
        else:
            tan = np.ldexp(tan, exponent)
    if not np.isfinite(bezier).all():
        i = int(np.flatnonzero(~np.isfinite(bezier).all(axis=(1, 2)))[0])
        raise ValueError(
            f"the Bézier handles of piece {i} overflow float64: alpha[{i}] = {float(alpha[i]):.3g} and "
            f"beta[{i}] = {float(beta[i]):.3g} are too small for points of this size (the handle length is "
            f"4/3 |T| / alpha, §5.1)"
        )
    knots = np.arange(bezier.shape[0] + 1, dtype=float)
    status, jumps = _joint_report(Spline(bezier, knots, closed=closed), joint_labels)
    info = {
        "form": form,
        "closed": bool(closed),
        "alpha": alpha.tolist(),
        "beta": beta.tolist(),
        "joint_status": status,
        "curvature_jump": jumps,
        "leg_offset": 0,
    }
    info.update(extra_info)
    return Spline(bezier, knots, closed=closed, info=info, auxiliary={"Q1": q1, "Q2": q2, "tangents": tan})


def _tangent_input(pts, tangents, closed, name="tangents"):
    """Unit tangents: the given ones normalised, or the §6 estimates (eq 3.110 with E16)."""
    if tangents is None:
        return unit_tangents(estimate_tangents(pts, closed=closed))
    tan = as_float_array(tangents, name)
    if tan.shape != pts.shape:
        raise ValueError(f"{name} must have shape {pts.shape} (one per point), got {tan.shape}")
    return unit_tangents(tan, name=name)


