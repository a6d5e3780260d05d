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

Three schemes build a whole curve (every one returns a :class:`~splinecraft.spline.piecewise.Spline`):

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
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import lapack, solve_banded

from .._validation import as_float_array, check_bool, check_choice, check_positive_number
from .piecewise import Spline
from .tangents import _chords, _validate_points, estimate_tangents, unit_tangents

__all__ = [
    "timmer_blending_functions",
    "timmer_bezier",
    "timmer_end_curvatures",
    "timmer_g2",
    "timmer_gc1",
    "timmer_gc2",
    "JOINT_STATUSES",
]

#: Meaning of the per-knot ``info['joint_status']`` values.
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
        raise ValueError(f"{name}{where} must be > 0, got {array[bad[0]]!r}")
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


def _make_spline(form, pts, tan, alpha, beta, closed, joint_labels, extra_info):
    bezier, q1, q2 = _bezier_from(pts, tan, alpha, beta, closed)
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


# ----------------------------------------------------------------------------------------------------------
# Algorithm 3.1: G2 piecewise Timmer
# ----------------------------------------------------------------------------------------------------------
def _solve_joint(s_i, c_i, target, alpha_ref, chord, clamp):
    """Solve :math:`\\tfrac38S\\alpha^2-\\tfrac12C\\alpha-K^*=0` for a batch of targets (§5.4 steps 2-4).

    ``target`` has shape (G,); ``s_i, c_i, alpha_ref, chord`` are scalars. Returns ``alpha`` (G,) and the
    status code (G,) as an index into ``_G2_CODES``. The roots use the cancellation-free form
    :math:`q=-\\tfrac12(b+\\operatorname{sgn}(b)\\sqrt{b^2-4ac})`, :math:`\\alpha\\in\\{q/a,\\ c/q\\}` with
    :math:`b^2-4ac=(C^2+6SK^*)/4` (E18). Call inside ``np.errstate(divide/invalid/over="ignore")``.
    """
    alpha = np.full(target.shape, alpha_ref)
    code = np.zeros(target.shape, dtype=np.int8)
    if abs(s_i) <= _ZERO_RTOL * chord:
        if abs(c_i) <= _ZERO_RTOL:
            # kappa_i(0) = 0 for every alpha: a G2 joint only if the target curvature is 0 too
            code[np.abs(target) * chord > 1e-9] = 2
            return alpha, code
        best = -2.0 * target / c_i                    # linear case: -C/2 alpha - K* = 0
        ok = (best > 0.0) & np.isfinite(best)
        vertex = -1.0
    else:
        disc = c_i * c_i + 6.0 * s_i * target
        b = -0.5 * c_i
        q = -0.5 * (b + (0.5 if b >= 0.0 else -0.5) * np.sqrt(disc))     # NaN where disc < 0
        root_1 = q / (0.375 * s_i)
        root_2 = np.where(q != 0.0, -target / q, np.nan)
        ok_1 = (root_1 > 0.0) & np.isfinite(root_1)
        ok_2 = (root_2 > 0.0) & np.isfinite(root_2)
        distance_1 = np.where(ok_1, np.abs(np.log(np.where(ok_1, root_1, 1.0) / alpha_ref)), np.inf)
        distance_2 = np.where(ok_2, np.abs(np.log(np.where(ok_2, root_2, 1.0) / alpha_ref)), np.inf)
        best = np.where(distance_2 < distance_1, root_2, root_1)
        ok = ok_1 | ok_2
        vertex = 2.0 * c_i / (3.0 * s_i)
    alpha[ok] = best[ok]
    if not ok.all():
        # Step 4: vertex of the parabola kappa_i(0)(alpha) if positive, else alpha_ref (clamped)
        value = vertex if vertex > 0.0 else alpha_ref
        if clamp is not None:
            value = min(max(value, alpha_ref / clamp), alpha_ref * clamp)
        alpha[~ok] = value
        code[~ok] = 1
    return alpha, code


def _solve_joint_scalar(s_i, c_i, target, alpha_ref, chord, clamp):
    """Scalar twin of :func:`_solve_joint` (plain floats; same formulas, same root choice)."""
    if abs(s_i) <= _ZERO_RTOL * chord:
        if abs(c_i) <= _ZERO_RTOL:
            return alpha_ref, (0 if abs(target) * chord <= 1e-9 else 2)
        root = -2.0 * target / c_i
        if root > 0.0 and math.isfinite(root):
            return root, 0
        vertex = -1.0
    else:
        disc = c_i * c_i + 6.0 * s_i * target
        best, best_distance = None, math.inf
        if disc >= 0.0:
            b = -0.5 * c_i
            q = -0.5 * (b + (0.5 if b >= 0.0 else -0.5) * math.sqrt(disc))
            candidates = (q / (0.375 * s_i), -target / q) if q != 0.0 else (q / (0.375 * s_i),)
            for root in candidates:
                if root > 0.0 and math.isfinite(root):
                    distance = abs(math.log(root / alpha_ref))
                    if distance < best_distance:
                        best, best_distance = root, distance
        if best is not None:
            return best, 0
        vertex = 2.0 * c_i / (3.0 * s_i)
    value = vertex if vertex > 0.0 else alpha_ref
    if clamp is not None:
        value = min(max(value, alpha_ref / clamp), alpha_ref * clamp)
    return value, 1


def _g2_sweep(alpha_first, s_term, u_term, c_term, alpha_ref, chords, clamp):
    """Run Algorithm 3.1 from :math:`\\alpha_0` for a batch of start values (vectorised over the batch).

    Returns ``alpha`` (G, m) and ``code`` (G, m), where ``code[:, i]`` is the status of the joint at the
    start of piece ``i`` (``i >= 1``); column 0 is left 0 (the caller decides about a closing joint).
    The recurrence is sequential in the joints; a single start value runs on plain floats, a batch
    runs every joint as one numpy step over the batch.
    """
    batch = np.atleast_1d(np.asarray(alpha_first, dtype=float))
    m = s_term.shape[0]
    if batch.shape[0] == 1:
        alpha, code = [float(batch[0])], [0]
        s_list, u_list, c_list = s_term.tolist(), u_term.tolist(), c_term.tolist()
        ref_list, chord_list = alpha_ref.tolist(), chords.tolist()
        previous = alpha[0]
        for i in range(1, m):
            target = -0.375 * (previous * previous) * u_list[i - 1] - 0.5 * previous * c_list[i - 1]
            previous, status = _solve_joint_scalar(s_list[i], c_list[i], target, ref_list[i], chord_list[i],
                                                   clamp)
            alpha.append(previous)
            code.append(status)
        return np.array([alpha]), np.array([code], dtype=np.int8)
    alpha = np.empty((batch.shape[0], m))
    code = np.zeros((batch.shape[0], m), dtype=np.int8)
    alpha[:, 0] = batch
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for i in range(1, m):
            previous = alpha[:, i - 1]
            target = -0.375 * previous**2 * u_term[i - 1] - 0.5 * previous * c_term[i - 1]   # kappa_{i-1}(1)
            alpha[:, i], code[:, i] = _solve_joint(s_term[i], c_term[i], target, alpha_ref[i], chords[i], clamp)
    return alpha, code


def _closing_mismatch(alpha, s_term, u_term, c_term):
    """:math:`\\kappa_0(0)-\\kappa_{m-1}(1)` for every row of ``alpha`` (G, m) (with :math:`\\beta=\\alpha`),
    and the size below which it counts as zero (relative to the curvatures there, at least
    ``1/mean chord`` passed in as ``curvature_scale``)."""
    first, last = alpha[:, 0], alpha[:, -1]
    kappa_start = 0.375 * first**2 * s_term[0] - 0.5 * first * c_term[0]
    kappa_end = -0.375 * last**2 * u_term[-1] - 0.5 * last * c_term[-1]
    return kappa_start - kappa_end, np.maximum(np.abs(kappa_start), np.abs(kappa_end))


def _is_matched(mismatch, magnitude, curvature_scale):
    return np.abs(mismatch) <= _G2_RTOL * np.maximum(magnitude, curvature_scale)


def _search_closing_alpha(s_term, u_term, c_term, alpha_ref, chords, clamp, curvature_scale):
    """Choose :math:`\\alpha_0` of a closed Algorithm 3.1 curve so that the closing joint is :math:`G^2` too.

    The closing mismatch :math:`\\kappa_0(0)-\\kappa_{N-1}(1)` is a function of :math:`\\alpha_0` alone. It is
    scanned on a log grid of 129 values over :math:`[\\alpha_{ref,0}/R, R\\,\\alpha_{ref,0}]` (``R = clamp`` or
    16), all grid values in one vectorised sweep. Grid values that already close to round-off, and sign
    changes between neighbouring grid values with the same joint-status pattern (so the mismatch is
    continuous between them unless the chosen root switches branch), are candidates. They are tried in
    order of fewest fallback joints, then the tamest chain (smallest
    :math:`\\max_i|\\log(\\alpha_i/\\alpha_{ref,i})|`); brackets are refined with ``scipy.optimize.brentq``
    and accepted only where the status pattern holds and the mismatch really vanishes. Returns
    ``(alpha_0, converged)``; without a zero, ``(alpha_ref_0, False)`` (the open-curve default; the
    closing joint is then reported ``g1_closing``).
    """
    from scipy.optimize import brentq

    ratio = 16.0 if clamp is None else clamp
    grid = alpha_ref[0] * np.geomspace(1.0 / ratio, ratio, 129)

    def sweep(alpha_first):
        with np.errstate(over="ignore", invalid="ignore"):
            alpha, code = _g2_sweep(alpha_first, s_term, u_term, c_term, alpha_ref, chords, clamp)
            mismatch, size = _closing_mismatch(alpha, s_term, u_term, c_term)
            wildness = np.max(np.abs(np.log(alpha / alpha_ref)), axis=1)
        return code[:, 1:], mismatch, np.maximum(size, curvature_scale), wildness

    codes, mismatch, size, wildness = sweep(grid)
    fallbacks = (codes != 0).sum(axis=1)
    exact = np.abs(mismatch) <= 1e-13 * size
    same = (codes[:-1] == codes[1:]).all(axis=1) & np.isfinite(mismatch[:-1]) & np.isfinite(mismatch[1:])
    change = same & (np.sign(mismatch[:-1]) * np.sign(mismatch[1:]) <= 0) & ~exact[:-1] & ~exact[1:]
    # candidates: (fallbacks, wildness, kind, index); kind 0 = exact grid value, 1 = bracket [k, k+1]
    candidates = [(int(fallbacks[k]), float(wildness[k]), 0, int(k)) for k in np.flatnonzero(exact)]
    candidates += [(int(fallbacks[k]), float(max(wildness[k], wildness[k + 1])), 1, int(k))
                   for k in np.flatnonzero(change)]
    candidates.sort()

    def closing(log_alpha):
        return float(sweep(np.array([math.exp(log_alpha)]))[1][0])

    for _, _, kind, k in candidates[:12]:
        if kind == 0:
            return float(grid[k]), True
        try:
            root = brentq(closing, math.log(grid[k]), math.log(grid[k + 1]), xtol=1e-15, rtol=1e-15,
                          maxiter=200)
        except (ValueError, RuntimeError):
            continue
        alpha_0 = math.exp(root)
        code_r, mismatch_r, size_r, _ = sweep(np.array([alpha_0]))
        if (code_r[0] == codes[k]).all() and abs(mismatch_r[0]) <= _G2_RTOL * size_r[0]:
            return alpha_0, True
    return float(alpha_ref[0]), False


def timmer_g2(points, *, closed: bool = False, tangents=None, alpha0=None, clamp=16.0) -> Spline:
    """:math:`G^2` piecewise Timmer curve through ``points`` (Algorithm 3.1; §5.4, thesis section 3.3.3).

    One tangent scale :math:`\\alpha_i=\\beta_i` per piece, chosen joint by joint so that the curvature is
    continuous (thesis eqs 3.106-3.122 with errata E16-E18):

    1. Unit tangents :math:`T_i=\\tilde T_i/\\|\\tilde T_i\\|` for **all** :math:`i=0..n` (E16: eq 3.110 writes
       :math:`D_i` and :math:`i=1..n-1`), from :func:`~splinecraft.spline.tangents.estimate_tangents`
       (eqs 3.106-3.109) unless ``tangents`` is given.
    2. :math:`\\alpha_0` given; default :math:`\\alpha_{ref,0}=4/\\|P_1-P_0\\|` (tangent length = chord,
       Bézier inner points at a third of the chord).
    3. For the joints :math:`i=1..n-1` (E17: not :math:`1..n`, and the loop does not start at 0): target
       :math:`K^*=\\kappa_{i-1}(1)` (§5.3 with :math:`\\alpha_{i-1}`), then solve eq 3.120/3.121
       :math:`\\tfrac38S_i\\alpha^2-\\tfrac12C_i\\alpha-K^*=0`, whose roots are
       :math:`2[C_i\\pm\\sqrt{C_i^2+6S_iK^*}]/(3S_i)` (E18: eq 3.122 prints :math:`-6S_iK^*`). Solved with the
       cancellation-free quadratic formula; :math:`S_i=0` is the linear case :math:`\\alpha=-2K^*/C_i`.
    4. Among positive real roots, the one closest to :math:`\\alpha_{ref,i}=4/\\|P_{i+1}-P_i\\|` in
       :math:`|\\log(\\alpha/\\alpha_{ref,i})|` (a spec choice, the thesis says only "positive").
    5. No positive root (common: 12-15% of joints even on clean ellipse samples): the vertex
       :math:`2C_i/(3S_i)` if positive (it minimises :math:`|\\kappa_i(0)-K^*|` over :math:`\\alpha>0`), else
       :math:`\\alpha_{ref,i}`, clamped to :math:`[\\alpha_{ref,i}/\\text{clamp},\\ \\text{clamp}\\,\\alpha_{ref,i}]`. The joint
       is then only :math:`G^1`: status ``"g1_no_root"`` with its curvature jump. :math:`S_i=C_i=0` (a straight
       piece with aligned tangents) gives :math:`\\kappa_i(0)\\equiv0`: ``"g2"`` if :math:`K^*=0`, else
       ``"g1_degenerate"``. Roots are never clamped (they are what makes the joint :math:`G^2`).

    Closed curves (:math:`N` distinct points, :math:`N` pieces, tangents by the interior formula
    cyclically): the sweep runs over the joints :math:`1..N-1`; the closing joint at :math:`P_0` depends
    on :math:`\\alpha_0` alone. Unless ``alpha0`` is given, :math:`\\alpha_0` is searched on a log grid
    over :math:`[\\alpha_{ref,0}/R, R\\,\\alpha_{ref,0}]` (``R = clamp`` or 16) with refinement, for a value that
    makes the closing joint :math:`G^2` (status ``"g2"``), preferring values with the fewest fallback
    joints elsewhere, then the tamest chain of :math:`\\alpha_i/\\alpha_{ref,i}`. If there is none, :math:`\\alpha_0=\\alpha_{ref,0}` and the closing joint is reported
    ``"g1_closing"`` with its jump. ``info['closing_converged']`` tells which. With ``alpha0`` given, the
    closing joint is simply reported as it comes out.

    Parameters
    ----------
    points : array_like, shape (n+1, 2)
        Open: at least 2 points; closed: at least 3 distinct points, the first not repeated.
    closed : bool
    tangents : array_like, shape (n+1, 2), optional
        Tangent directions to use instead of the §6 estimates (normalised here).
    alpha0 : float, optional
        Tangent scale of the first piece (> 0).
    clamp : float or None
        Clamp ratio (> 1) for fallback values; ``None`` disables clamping.

    Returns
    -------
    Spline
        Knots ``0..m``. ``info``: ``form="timmer_g2"``, ``alpha`` = ``beta`` (per piece), ``joint_status``
        and ``curvature_jump`` per knot, ``alpha0``, ``alpha_ref``, ``closing_converged`` (closed only).
        ``auxiliary``: ``Q1``, ``Q2``, ``tangents`` (unit).

    Raises
    ------
    ValueError
        Bad points (non-finite, duplicates, too few, not planar), bad ``tangents``, ``alpha0 <= 0``,
        ``clamp <= 1``. A joint without a positive root is *not* an error (see step 5).
    """
    closed = check_bool(closed, "closed")
    pts = _planar_points(points, closed)
    tan = _tangent_input(pts, tangents, closed)
    if clamp is not None:
        clamp = check_positive_number(clamp, "clamp")
        if clamp <= 1.0:
            raise ValueError(f"clamp must be > 1 (a ratio around alpha_ref) or None, got {clamp!r}")
    chord_vectors = _chords(pts, closed)
    chords = np.linalg.norm(chord_vectors, axis=1)
    alpha_ref = 4.0 / chords
    s_term, u_term, c_term = _timmer_cross_terms(pts, tan, closed)
    m = chords.shape[0]
    curvature_scale = 1.0 / float(np.mean(chords))

    extra = {"alpha_ref": alpha_ref.tolist()}
    converged = None
    if alpha0 is not None:
        alpha0 = check_positive_number(alpha0, "alpha0")
    elif closed:
        alpha0, converged = _search_closing_alpha(s_term, u_term, c_term, alpha_ref, chords, clamp,
                                                  curvature_scale)
    else:
        alpha0 = float(alpha_ref[0])
    alpha, code = _g2_sweep([alpha0], s_term, u_term, c_term, alpha_ref, chords, clamp)
    alpha, code = alpha[0], code[0]
    labels = [_G2_CODES[c] for c in code]
    if closed:
        mismatch, size = _closing_mismatch(alpha[None, :], s_term, u_term, c_term)
        labels[0] = "g2" if _is_matched(mismatch, size, curvature_scale)[0] else "g1_closing"
        if converged is None:
            converged = labels[0] == "g2"
        extra["closing_converged"] = bool(converged)
    extra["alpha0"] = float(alpha0)
    return _make_spline("timmer_g2", pts, tan, alpha, alpha.copy(), closed, labels, extra)


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
    pts = _planar_points(points, closed)
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
        alpha_values = _segment_values(alpha, m, "alpha")
        beta_values = alpha_values.copy() if beta is None else _segment_values(beta, m, "beta")
    labels = _matching_labels(np.roll(beta_values, 1), alpha_values, "c1", "g1")   # k = 0: closing joint
    extra = {"shape_scale": None if scale_values is None else scale_values.tolist()}
    return _make_spline("timmer_gc1", pts, tan, alpha_values, beta_values, closed, labels, extra)


# ----------------------------------------------------------------------------------------------------------
# Algorithm 3.3: "GC2" with shape control
# ----------------------------------------------------------------------------------------------------------
def _interleave(count: int) -> np.ndarray:
    """Order ``0, n-1, 1, n-2, 2, ...``: makes a cyclic tridiagonal matrix pentadiagonal (bandwidth 2)."""
    order = np.empty(count, dtype=int)
    order[0::2] = np.arange((count + 1) // 2)
    order[1::2] = count - 1 - np.arange(count // 2)
    return order


def _band_rcond(band: np.ndarray, lower: int, upper: int) -> float:
    """Reciprocal 1-norm condition number of a banded matrix (LAPACK dgbtrf + dgbcon)."""
    count = band.shape[1]
    storage = np.zeros((2 * lower + upper + 1, count))
    storage[lower:] = band
    lu, pivots, info = lapack.dgbtrf(storage, lower, upper)
    if info > 0:
        return 0.0
    # 1-norm of the matrix: the largest column sum of the band
    anorm = float(np.max(np.abs(band).sum(axis=0)))
    rcond, info = lapack.dgbcon(lower, upper, lu, pivots, anorm)
    return float(rcond)


def _solve_tridiagonal(lower, diag, upper, rhs, cyclic: bool):
    """Solve ``lower[k] x[k-1] + diag[k] x[k] + upper[k] x[k+1] = rhs[k]`` (indices mod n when cyclic).

    One ``scipy.linalg.solve_banded`` call with all right-hand-side columns: bandwidth (1, 1) for an open
    chain; a cyclic system is reordered by :func:`_interleave` into bandwidth (2, 2). Returns the solution
    and ``rcond`` (``None`` when every row is strictly diagonally dominant with a margin that bounds the
    condition number below 1e12; then no estimate is needed). Raises ``ValueError`` if singular or
    ill-conditioned.
    """
    count = diag.shape[0]
    off = np.abs(lower) + np.abs(upper)
    margin = np.abs(diag) - off
    dominant = bool(np.all(margin > 0.0))
    if dominant:
        # ||A||_inf * ||A^-1||_inf <= max row sum / min margin
        bound = float(np.max(np.abs(diag) + off) / np.min(margin))
        dominant = bound < 1.0 / _RCOND_MIN
    if cyclic:
        order = _interleave(count)
        position = np.empty(count, dtype=int)
        position[order] = np.arange(count)
        lower_bw = upper_bw = 2
        rows = position[np.arange(count)]
        band = np.zeros((5, count))
        for offset, values in ((-1, lower), (0, diag), (1, upper)):
            cols = position[(np.arange(count) + offset) % count]
            np.add.at(band, (upper_bw + rows - cols, cols), values)
        rhs_perm = rhs[order]
    else:
        lower_bw = upper_bw = 1
        band = np.zeros((3, count))
        band[0, 1:] = upper[:-1]
        band[1] = diag
        band[2, :-1] = lower[1:]
        rhs_perm = rhs
    rcond = None
    if not dominant:
        rcond = _band_rcond(band, lower_bw, upper_bw)
        if not rcond > _RCOND_MIN:
            raise ValueError(f"the Timmer GC2 tangent system is singular or ill-conditioned "
                             f"(rcond = {rcond:.3g})")
    try:
        solution = solve_banded((lower_bw, upper_bw), band, rhs_perm, check_finite=False)
    except np.linalg.LinAlgError as exc:
        raise ValueError(f"the Timmer GC2 tangent system is singular: {exc}") from None
    if not np.all(np.isfinite(solution)):
        raise ValueError("the Timmer GC2 tangent system gave non-finite tangents (singular system)")
    if cyclic:
        unpermuted = np.empty_like(solution)
        unpermuted[order] = solution
        solution = unpermuted
    return solution, rcond, bool(np.all(margin > 0.0))


def timmer_gc2(points, *, closed: bool = False, alpha=4.0, beta=None, end_derivatives=None,
               joint: str = "thesis") -> Spline:
    """Piecewise Timmer curve whose tangents solve a tridiagonal system (Algorithm 3.3; §5.6).

    Unknowns: non-unit tangents :math:`T_1..T_n` (thesis 1-based; array index ``k = i - 1``). With
    :math:`A=\\alpha_{i-1}, B=\\beta_{i-1}, a=\\alpha_i, b=\\beta_i` the joint rows at :math:`i=2..n-1` are

    * ``joint="thesis"``: :math:`H_{i-1}''(1)=H_i''(0)` (eq 3.123), i.e. eqs 3.126-3.130
      :math:`4abB\\,T_{i-1}+8Ab(a+B)\\,T_i+4AaB\\,T_{i+1}=3ABab\\,(P_{i+1}-P_{i-1})` (correct as printed; the
      derivatives 3.124/3.125 they come from have sign errors, E19). This joint is :math:`C^2` (status
      ``"c2"``) only where :math:`\\alpha_i=\\beta_{i-1}`; elsewhere
      :math:`\\kappa_i(0)=(\\alpha_i/\\beta_{i-1})^2\\kappa_{i-1}(1)` (E20, status ``"g1"``).
    * ``joint="g2"``: :math:`H_i''(0)=(B/a)^2H_{i-1}''(1)`, true :math:`G^2` for any :math:`\\alpha,\\beta` (§5.6):
      :math:`4bB^2\\,T_{i-1}+8Ab(a+B)\\,T_i+4Aa^2\\,T_{i+1}=3Ab\\,[a^2(P_{i+1}-P_i)+B^2(P_i-P_{i-1})]`.

    End rows (eq 3.131, open curves): :math:`T_1=\\alpha_1\\hat D_1/4` and :math:`T_n=\\beta_{n-1}\\hat D_n/4`, so
    that :math:`H_1'(0)=\\hat D_1` and :math:`H_{n-1}'(1)=\\hat D_n`; by default :math:`\\hat D` are the raw
    estimates 2.1/2.2 (per unit piece parameter). Closed curves use the joint row at every point,
    cyclically. The matrix is the same for x and y: one ``solve_banded`` call with two right-hand-side
    columns (a cyclic system is reordered to bandwidth 2 rather than split by Sherman-Morrison). Rows
    are diagonally dominant for the thesis joint iff :math:`2/B+2/a>1/A+1/b` (e.g. all scales equal),
    for the ``"g2"`` joint iff :math:`2(a+B)>B^2/A+a^2/b` (a different condition: the spec's test does
    not carry over; :math:`A=a=1`, :math:`B=b=(3+\\sqrt5)/2` passes it but makes a closed ``"g2"`` system
    with an even number of points singular); otherwise the system is still solved, with partial pivoting, after an O(n) LAPACK condition
    estimate; a singular or ill-conditioned system (rcond < 1e-12) raises ``ValueError``. With constant
    :math:`\\alpha=\\beta` the thesis joint gives the uniform-knot :math:`C^2` cubic spline with end slopes
    :math:`\\hat D` (the scales only matter through their ratios). Rendered with §5.1 (eq 3.89; E20:
    the thesis's Step 3 cites 3.130).

    Parameters
    ----------
    points : array_like, shape (n, 2)
        Open: ``n >= 2``; closed: ``n >= 3`` distinct points.
    closed : bool
    alpha : float or array_like, shape (m,)
        Tangent scales :math:`\\alpha_i>0` per piece (default 4, Timmer's own value).
    beta : float or array_like, shape (m,), optional
        :math:`\\beta_i>0`; defaults to ``alpha``.
    end_derivatives : pair of array_like (2,), optional
        :math:`(\\hat D_1,\\hat D_n)` per unit piece parameter (open curves only).
    joint : {"thesis", "g2"}

    Returns
    -------
    Spline
        ``info``: ``form="timmer_gc2"``, ``joint``, ``alpha``, ``beta``, ``joint_status``, ``curvature_jump``,
        ``diagonally_dominant``, ``rcond`` (``None`` if not needed), ``end_derivatives``.
        ``auxiliary``: ``Q1``, ``Q2``, ``tangents`` (the solved non-unit :math:`T_i`).
    """
    closed = check_bool(closed, "closed")
    joint = check_choice(joint, "joint", ("thesis", "g2"))
    pts = _planar_points(points, closed)
    count = pts.shape[0]
    m = count if closed else count - 1
    alpha_values = _segment_values(alpha, m, "alpha")
    beta_values = alpha_values.copy() if beta is None else _segment_values(beta, m, "beta")

    if closed:
        if end_derivatives is not None:
            raise ValueError("end_derivatives apply to open curves only (closed curves have no ends)")
        joints = np.arange(count)
    else:
        joints = np.arange(1, count - 1)
    # Row coefficients at the joints (A, B: piece before; a, b: piece after).
    big_a = alpha_values[joints - 1]
    big_b = beta_values[joints - 1]
    small_a = alpha_values[joints % m]
    small_b = beta_values[joints % m]
    previous = pts[joints - 1]
    current = pts[joints]
    following = pts[(joints + 1) % count]
    diag_j = 8.0 * big_a * small_b * (small_a + big_b)
    if joint == "thesis":
        lower_j = 4.0 * small_a * small_b * big_b
        upper_j = 4.0 * big_a * small_a * big_b
        rhs_j = (3.0 * big_a * big_b * small_a * small_b)[:, None] * (following - previous)
    else:
        lower_j = 4.0 * small_b * big_b**2
        upper_j = 4.0 * big_a * small_a**2
        rhs_j = (3.0 * big_a * small_b)[:, None] * (
            (small_a**2)[:, None] * (following - current) + (big_b**2)[:, None] * (current - previous))
    # normalise every row by its diagonal (scale-free conditioning estimates)
    lower_j, upper_j, rhs_j = lower_j / diag_j, upper_j / diag_j, rhs_j / diag_j[:, None]

    extra = {"joint": joint}
    if closed:
        lower, diag, upper, rhs = lower_j, np.ones(count), upper_j, rhs_j
        extra["end_derivatives"] = None
    else:
        if end_derivatives is None:
            raw = estimate_tangents(pts, closed=False)
            first, last = raw[0], raw[-1]
        else:
            if not isinstance(end_derivatives, (tuple, list)) and np.ndim(end_derivatives) != 2:
                raise TypeError("end_derivatives must be a pair (D_1, D_n) of 2-vectors")
            if len(end_derivatives) != 2:
                raise ValueError(f"end_derivatives must be a pair (D_1, D_n), got {len(end_derivatives)} items")
            first = as_float_array(end_derivatives[0], "end_derivatives[0]")
            last = as_float_array(end_derivatives[1], "end_derivatives[1]")
            for name, value in (("end_derivatives[0]", first), ("end_derivatives[1]", last)):
                if value.shape != (2,):
                    raise ValueError(f"{name} must have shape (2,), got {value.shape}")
        lower = np.concatenate([[0.0], lower_j, [0.0]])
        upper = np.concatenate([[0.0], upper_j, [0.0]])
        diag = np.ones(count)
        rhs = np.vstack([alpha_values[0] * first / 4.0, rhs_j, beta_values[-1] * last / 4.0])
        extra["end_derivatives"] = [first.tolist(), last.tolist()]

    tangents, rcond, dominant = _solve_tridiagonal(lower, diag, upper, rhs, closed)
    extra["diagonally_dominant"] = dominant
    extra["rcond"] = rcond
    if joint == "g2":
        labels = ["g2"] * m
    else:
        labels = _matching_labels(np.roll(beta_values, 1), alpha_values, "c2", "g1")
    return _make_spline("timmer_gc2", pts, tangents, alpha_values, beta_values, closed, labels, extra)
