"""The local-support basis form of the generic cubic spline (thesis section 3.2; §4).

The curve ``P(t) = sum_j B_j(t) P_j`` is built from control points ``P_j`` with B-spline-like basis functions
``B_j`` of support ``(t_{j-2}, t_{j+2})``. Every ``B_j`` -- hence every curve -- satisfies the weighted nu-spline
joint constraint of §2.2 at each knot, with a point tension ``v_j`` per control point and an interval weight
``omega_i`` per leg ``P_i P_{i+1}``. With ``v = 0`` and ``omega = 1`` the ``B_j`` are the cubic B-splines on the
same knots (uniform knots: ``F_i = (P_{i-1} + 4 P_i + P_{i+1}) / 6``).

Everything comes from the closed forms of §4.2-4.3 (thesis eqs 3.53-3.65, 3.81-3.84, errata E9, E10):

    a_i = h_i / omega_i,   d_i = a_{i-1} + a_i + a_{i-1} a_i v_i / 2,
    D_i = h_{i-1} d_{i-1} d_i + a_i (h_{i-1} + h_i) d_{i-1} + a_{i-2} (h_{i-2} + h_{i-1}) d_i,
    lambda_i = a_i h_i d_{i-1} / D_i,  mu_i = a_{i-1} h_{i-1} d_{i+1} / D_{i+1},
    rho_i = a_{i-1} (h_{i-1} + h_i) d_{i+1} / D_{i+1},  sigma_{i+1} = a_{i+1} (h_i + h_{i+1}) d_i / D_{i+1},

and segment ``i`` is the exact Bézier ``[F_i, (1-rho_i) P_i + rho_i P_{i+1}, sigma_{i+1} P_i + (1-sigma_{i+1}) P_{i+1}, F_{i+1}]``
with ``F_i = lambda_i P_{i-1} + (1 - lambda_i - mu_i) P_i + mu_i P_{i+1}``. All vectorised, O(n), no solve.
"""
from __future__ import annotations

import numbers

import numpy as np

from .._validation import as_float_array, as_points, check_bool, check_choice, check_strictly_increasing, per_item
from .knots import KNOT_EXPONENTS, check_distinct, leg_lengths
from .piecewise import Spline
from .scaling import even_exponent, knot_exponent, unscale_knots
from .interpolant import _DERIVATIVE_OVERFLOW, check_interval_ratio
from .segment import check_class_points

__all__ = ["basis_spline", "basis_functions", "tension_spans", "BASIS_ENDS"]

#: Accepted ``ends`` values for open basis curves (§4.4).
BASIS_ENDS = ("floating", "clamped")

#: Most control points :func:`basis_functions` takes (its result holds 4 values per parameter, the colour
#: curve 8 coordinates per control point).
MAX_BASIS_FUNCTIONS = 10_000_000

# |D_i| <= DEGENERATE_RTOL * (sum of the absolute values of its three terms) counts as vanishing.
DEGENERATE_RTOL = 1e-12
_OVERFLOW_MESSAGE = ("the basis form overflows float64 with these point_tension and interval_weights "
                     "(a closed form of §4.2 leaves the float64 range); use values of moderate size")


def _leg_steps(control_points, knots, closed, ends, n_control):
    """Knot values and the interval length ``h`` of every leg that carries an interval.

    Returns ``(values, steps)``: ``values`` are the knot values that the curve's pieces use (floating:
    ``t_0..t_{n+1}``, one per control point; clamped: ``t_1..t_n``; closed: ``t_0..t_N``) and ``steps`` their
    differences.
    """
    if closed:
        count, first_leg, last_leg = n_control + 1, 0, n_control  # legs 0..N-1 (last closes the loop)
    elif ends == "clamped":
        count, first_leg, last_leg = n_control - 2, 1, n_control - 2  # legs 1..n-1
    else:
        count, first_leg, last_leg = n_control, 0, n_control - 1  # legs 0..n
    if isinstance(knots, str):
        if knots not in KNOT_EXPONENTS:
            raise ValueError(f"knots must be one of {sorted(KNOT_EXPONENTS)} or an increasing array, got {knots!r}")
        exponent = KNOT_EXPONENTS[knots]
        if exponent == 0.0:
            steps = np.ones(count - 1)
        else:
            lengths = leg_lengths(control_points, closed)[first_leg:last_leg]
            if not closed:
                check_distinct(control_points[first_leg : last_leg + 1], False, name="control_points", lengths=lengths)
                steps = lengths
            else:
                check_distinct(control_points, True, name="control_points", lengths=lengths)
                steps = lengths
            if exponent != 1.0:
                steps = np.sqrt(steps)
        values = np.empty(count)
        values[0] = float(first_leg) if exponent == 0.0 else 0.0
        np.cumsum(steps, out=values[1:])
        values[1:] += values[0]
        return values, steps
    values = as_float_array(knots, "knots", ndim=1)
    if values.shape[0] != count:
        what = {
            True: f"N + 1 = {count} for a closed curve of N = {n_control} control points",
            False: (f"n_control - 2 = {count} (t_1..t_n) with clamped ends" if ends == "clamped"
                    else f"one per control point ({count})"),
        }[closed]
        raise ValueError(f"knots has length {values.shape[0]} but needs {what}")
    check_strictly_increasing(values, "knots")
    return values, np.diff(values)


def _basis_coefficients(steps, weights, tension, closed, ends):
    """Per-joint and per-segment coefficients of §4.2-4.3, vectorised with slices.

    Returns ``joint`` (lambda, mu, lambda_hat, mu_hat at the joints) and ``segment`` (rho, sigma), as
    arrays over the joints ``J`` (floating/clamped: thesis ``i = 1..n``; closed: ``0..N-1``) and the
    segments ``S`` (``1..n-1``; closed ``0..N-1``).
    """
    n_control = tension.shape[0]
    if closed:
        # indices mod N: pad two entries on each side, offset 2 (thesis i -> array i + 2)
        a = steps / weights
        h_ext = np.concatenate([steps[-2:], steps, steps[:2]])
        a_ext = np.concatenate([a[-2:], a, a[:2]])
        v_ext = np.concatenate([tension[-2:], tension, tension[:2]])
        off = v_off = 2
        first, count = 0, n_control  # joints 0..N-1
        n_segments = n_control
    else:
        n = n_control - 2
        if ends == "clamped":
            # triple end knots: h_{-1} = h_0 = 0 = h_n = h_{n+1} (§4.4)
            zeros = np.zeros(2)
            h_ext = np.concatenate([zeros, steps, zeros])
            a_ext = np.concatenate([zeros, steps / weights[1:-1], zeros])
        else:
            # h_{-1} := h_0, h_{n+1} := h_n, omega likewise (§4.4, E12)
            a = steps / weights
            h_ext = np.concatenate([steps[:1], steps, steps[-1:]])
            a_ext = np.concatenate([a[:1], a, a[-1:]])
        off, v_off = 1, 0  # h_ext[i + 1] = h_i for i = -1..n+1; v_ext[i] = v_i for i = 0..n+1
        v_ext = tension
        first, count = 1, n  # joints 1..n
        n_segments = n - 1

    def h(i, length):  # h_i .. h_{i+length-1}
        return h_ext[i + off : i + off + length]

    def a(i, length):
        return a_ext[i + off : i + off + length]

    # d over i = first-1 .. first+count (length count + 2): dd[k] = d_{first - 1 + k}
    length = count + 2
    a_left, a_right = a(first - 2, length), a(first - 1, length)
    dd = a_left + a_right + 0.5 * a_left * a_right * v_ext[first - 1 + v_off : first - 1 + v_off + length]
    # D over i = first .. first+count (length count + 1)
    length = count + 1
    h_m2, h_m1, h_0 = h(first - 2, length), h(first - 1, length), h(first, length)
    d_prev, d_here = dd[:-1], dd[1:]
    t1 = h_m1 * d_prev * d_here
    t2 = a(first, length) * (h_m1 + h_0) * d_prev
    t3 = a(first - 2, length) * (h_m2 + h_m1) * d_here
    D = t1 + t2 + t3
    size = np.abs(t1) + np.abs(t2) + np.abs(t3)
    if not np.isfinite(size).all():  # an overflow, not a vanishing D (e.g. two neighbouring tensions > 1e154)
        raise ValueError(_OVERFLOW_MESSAGE)
    degenerate = (np.abs(D) <= DEGENERATE_RTOL * size) | (size == 0)
    if not closed and ends == "clamped":
        degenerate[0] = degenerate[-1] = False  # D_1 = D_{n+1} = 0 by construction; limits below
    if degenerate.any():
        k = int(np.flatnonzero(degenerate)[0])
        index = first + k
        left = (index - 1) % n_control if closed else index - 1
        right = index % n_control if closed else index
        raise ValueError(
            f"the basis is degenerate at knot {index}: D_{index} = {D[k]:.3g} vanishes (§4.5), caused by "
            f"point_tension[{left}] and point_tension[{right}]; keep every "
            f"point_tension[i] > -2 (omega_(i-1)/h_(i-1) + omega_i/h_i) (then d_i > 0 and the basis is non-negative)"
        )
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = 1.0 / D
        inv_here, inv_next = inverse[:-1], inverse[1:]
        a_j, a_jm1 = a(first, count), a(first - 1, count)
        lam_hat = 3.0 * a_j * dd[:count] * inv_here
        lam = lam_hat * h(first, count) * (1.0 / 3.0)
        mu_hat = 3.0 * a_jm1 * dd[2:] * inv_next
        mu = mu_hat * h(first - 1, count) * (1.0 / 3.0)
        # segments S = first .. first+n_segments-1: rho_S, sigma_{S+1} use D_{S+1}
        inv_s = inverse[1 : n_segments + 1]
        h_s = h(first, n_segments)
        rho = a(first - 1, n_segments) * (h(first - 1, n_segments) + h_s) * dd[2 : n_segments + 2] * inv_s
        sigma = a(first + 1, n_segments) * (h_s + h(first + 1, n_segments)) * dd[1 : n_segments + 1] * inv_s
    if not closed and ends == "clamped":
        # limits at the triple knots (§4.4): lambda_1 = 1, lambda_hat_1 = 3/h_1, mu_n = 1, mu_hat_n = 3/h_{n-1}
        lam[0], lam_hat[0] = 1.0, 3.0 / float(h(1, 1)[0])
        mu[-1], mu_hat[-1] = 1.0, 3.0 / float(h(count - 1, 1)[0])
        rho[0] = 0.0
        sigma[-1] = 0.0
    return (lam, mu, lam_hat, mu_hat), (rho, sigma)


def _prepare(control_points, closed, point_tension, interval_weights, knots, ends, tension_scale="absolute",
             name="control_points"):
    closed = check_bool(closed, "closed")
    ends = check_choice(ends, "ends", BASIS_ENDS)
    tension_scale = check_choice(tension_scale, "point_tension_scale", ("absolute", "relative"))
    if closed and ends != "floating":
        raise ValueError("ends applies to open curves only; a closed basis curve has no ends")
    control_points = as_points(control_points, name, min_count=3 if closed else 4)
    n_control = control_points.shape[0]
    # the closed forms run on points scaled by an exact power of two (any float64 scale; see scaling.py)
    exponent = even_exponent(control_points)
    scaled = np.ldexp(control_points, -exponent) if exponent else control_points
    values, steps = _leg_steps(scaled, knots, closed, ends, n_control)
    # named knots scale with the points; explicit ones by their own power of two (0 at moderate sizes)
    knot_scale = knot_exponent(knots, exponent) if isinstance(knots, str) else even_exponent(values)
    if not isinstance(knots, str) and knot_scale:
        values, steps = np.ldexp(values, -knot_scale), np.ldexp(steps, -knot_scale)
    legs = n_control if closed else n_control - 1
    weights = per_item(interval_weights, legs, "interval_weights", what=f"one per control-polygon leg, {legs}")
    if not (weights > 0).all():
        i = int(np.flatnonzero(~(weights > 0))[0])
        raise ValueError(f"interval_weights[{i}] = {float(weights[i])!r} must be > 0")
    tension = per_item(point_tension, n_control, "point_tension", what=f"one per control point, {n_control}")
    given_weights = weights[1:-1] if not closed and ends == "clamped" else weights  # the ones that act (§4.4)
    # The closed forms of §4.2 are homogeneous in omega when v has the units of omega / h (§2.5 Units): run
    # them on weights divided by an exact power of two 2^w near their size, and v likewise, so that a
    # constant weight of 1e200 (a and a^2 in D_i under- or overflow) gives the curve of weight 1, as in
    # the interpolant. Only the weights that act set w (clamped ends ignore the end legs' weights).
    weight_scale = even_exponent(given_weights)
    if weight_scale:
        weights = np.ldexp(weights, -weight_scale)
    with np.errstate(over="ignore", under="ignore", divide="ignore"):
        ratio = steps / (weights if closed or ends == "floating" else weights[1:-1])
    check_interval_ratio(ratio, given_weights, "h_i / omega_i", steps, "control_points")
    if not closed and ends == "clamped":
        if not (steps > 0).all():  # explicit knots already checked; chord/centripetal checked by check_distinct
            raise ValueError("knots must be strictly increasing")
    if tension_scale == "relative":
        tension = _absolute_tension(tension, steps, weights, closed, ends)
    elif knot_scale - weight_scale:
        tension = np.ldexp(tension, knot_scale - weight_scale)  # v has the units of omega / h (§2.5 Units)
    return closed, ends, scaled, values, steps, weights, tension, (exponent, knot_scale)


def tension_spans(steps, weights, closed, ends):
    """``c_{j-1} + c_j`` per control point, ``c_i = omega_i / h_i`` in the index convention of §4.4.

    Floating ends extend the legs (``h_{-1} := h_0``, ``h_{n+1} := h_n``, omega likewise, E12), so the
    end control points count their one leg twice; the end legs of clamped ends carry no interval
    (``c = 0``). Then ``d_j = a_{j-1} + a_j + a_{j-1} a_j v_j / 2`` (§4.2, ``a = 1/c``) is positive iff
    ``v_j > -2 (c_{j-1} + c_j)``. Returns ``(spans, acts)``: ``acts[j]`` is False where ``v_j`` has no
    effect (the first two and last two control points with clamped ends).
    """
    if closed:
        c = weights / steps
        return np.roll(c, 1) + c, np.ones(c.shape[0], dtype=bool)
    legs = weights.shape[0]
    c = np.zeros(legs + 2)  # c_{-1}, c_0 .. c_n, c_{n+1}
    if ends == "clamped":
        c[2:-2] = weights[1:-1] / steps
    else:
        c[1:-1] = weights / steps
        c[0], c[-1] = c[1], c[-2]
    left, right = c[:-1], c[1:]
    return left + right, (left > 0) & (right > 0)


def _absolute_tension(nu, steps, weights, closed, ends):
    """``v_j = nu_j (c_{j-1} + c_j)`` after checking the safe domain ``nu_j > -2`` (§2.5 Units, §4.5)."""
    spans, acts = tension_spans(steps, weights, closed, ends)
    unsafe = acts & ~(nu > -2.0)
    if unsafe.any():
        j = int(np.flatnonzero(unsafe)[0])
        raise ValueError(
            f"point_tension[{j}] = {float(nu[j]):.6g} (relative) must be > -2 in the basis form: at nu_j <= -2, "
            f"d_{j} <= 0, the basis functions can vanish or turn negative and the curve leaves the convex hull "
            f"of its control points (§4.5; the absolute bound is v_{j} > {-2.0 * float(spans[j]):.6g})"
        )
    return nu * spans


def _assemble(control_points, values, steps, weights, tension, closed, ends):
    """Planar Bézier pieces ``(4, d, m)``, knot points F and tangents M ``(d, joints)`` (§4.3)."""
    (lam, mu, lam_hat, mu_hat), (rho, sigma) = _basis_coefficients(steps, weights, tension, closed, ends)
    P = np.ascontiguousarray(control_points.T)  # planar (d, n_control)
    if closed:
        prev_p, here_p, next_p = np.roll(P, 1, axis=1), P, np.roll(P, -1, axis=1)
        seg_here, seg_next = P, next_p
        knots = values
    else:
        prev_p, here_p, next_p = P[:, :-2], P[:, 1:-1], P[:, 2:]  # joints i = 1..n use P_{i-1}, P_i, P_{i+1}
        seg_here, seg_next = P[:, 1:-2], P[:, 2:-1]  # segments i = 1..n-1 use P_i, P_{i+1}
        knots = values[1:-1] if ends == "floating" else values
    back = here_p - prev_p
    ahead = next_p - here_p
    F = here_p - lam * back + mu * ahead  # = lam P_{i-1} + (1 - lam - mu) P_i + mu P_{i+1}
    M = lam_hat * back + mu_hat * ahead
    d, m = seg_here.shape
    planar = np.empty((4, d, m))
    planar[0] = F[:, :m]
    leg = seg_next - seg_here
    np.add(seg_here, rho * leg, out=planar[1])
    np.subtract(seg_next, sigma * leg, out=planar[2])
    if closed:
        planar[3, :, :-1] = F[:, 1:]
        planar[3, :, -1] = F[:, 0]
    else:
        planar[3] = F[:, 1:]
    return planar, np.array(knots, dtype=float), F, M


def basis_spline(control_points, *, closed=False, point_tension=0.0, interval_weights=1.0, alpha=3.0, beta=3.0,
                 knots="uniform", ends="floating", point_tension_scale="absolute") -> Spline:
    """Local-support (basis form) generic cubic spline from control points (thesis section 3.2; §4).

    ``P(t) = sum_j B_j(t) P_j``. With fixed knot values (``"uniform"`` or explicit), moving one control point
    changes at most the four segments it supports; with ``"chord"`` or ``"centripetal"`` knots the point also
    moves the knots of its two legs, and so up to six segments change. At
    every joint the curve is ``C^1`` and satisfies the weighted nu-spline constraint
    ``omega_i P''(t_i^+) = v_i P'(t_i) + omega_{i-1} P''(t_i^-)`` (§2.2). Built in O(n) from the closed
    forms of §4.2-4.3 (thesis 3.53-3.65 with errata E9, E10): no linear solve.

    **The class parameters do not change the curve (erratum E1).** ``alpha``/``beta`` cancel out; they only
    position the class polygon points ``V_i = F_i + h_i M_i / alpha_i``, ``W_i = F_{i+1} - h_i M_{i+1} / beta_i``
    (stored in ``auxiliary`` for drawing).

    **Joints are G² only where neighbouring interval weights are equal (erratum E2):**
    ``kappa(t_i^+) = (omega_{i-1} / omega_i) kappa(t_i^-)``; :meth:`Spline.joint_curvature` shows the jump.

    Parameters
    ----------
    control_points : array_like, shape (n_control, d)
        Finite control points. Open curves need at least 4, closed curves at least 3. Consecutive
        coincident control points are allowed with uniform or explicit knots (as in B-splines) but not with
        ``"chord"``/``"centripetal"`` knots, where they would give an empty interval.
    closed : bool
        Closed (periodic) curve: indices are taken mod N (§4.4), ``N`` segments.
    point_tension : float or array_like, shape (n_control,)
        ``v_j``, one per control point. ``v -> +inf`` pulls the curve to ``P_j`` (a cusp there). Negative values
        are allowed while the closed forms stay well defined; ``v_j > -2 (omega_{j-1}/h_{j-1} + omega_j/h_j)``
        (all ``v >= 0`` included) guarantees ``d_j > 0``, non-negative basis functions and the convex-hull
        property. Beyond it the basis can go negative, and where ``D_i`` vanishes (relative ``1e-12``, e.g.
        ``h = omega = 1``, ``v = -4``) a ``ValueError`` names the knot and the control points (§4.5).
        With clamped ends ``v`` of the first two and last two control points has no effect.
    interval_weights : float or array_like, shape (n_control - 1,) or (N,) when closed
        ``omega_i > 0``, one per leg ``P_i P_{i+1}``. Large values straighten segment ``i`` towards the leg.
        With clamped ends the first and last leg carry no interval and their weights have no effect.
    alpha, beta : float or array_like, one per segment
        Finite, non-zero class parameters (Ball 2, Bézier 3, Timmer 4); only ``V``, ``W`` depend on them.
    knots : {"uniform", "chord", "centripetal"} or array_like
        The knots belong to the control polygon: ``h_i = |P_{i+1} - P_i|^e`` (§3), uniform ``h = 1`` by
        default. Explicit strictly increasing values: one per control point ``t_0..t_{n+1}`` for floating
        ends (the curve runs over ``[t_1, t_n]``), ``t_1..t_n`` (``n_control - 2`` values) for clamped ends,
        ``N + 1`` values for a closed curve. Uniform knots are ``t_j = j``.
    ends : {"floating", "clamped"}
        ``"floating"``: the curve does not pass through ``P_0`` or ``P_{n+1}`` (``h_{-1} := h_0``,
        ``h_{n+1} := h_n``, erratum E12). ``"clamped"``: triple end knots, so the curve starts at ``P_0`` tangent
        to ``P_0 P_1`` and ends at ``P_{n+1}`` tangent to ``P_n P_{n+1}`` (four control points give one Bézier).
    point_tension_scale : {"absolute", "relative"}
        ``"relative"`` reads ``point_tension`` as the dimensionless ``nu_j`` with
        ``v_j = nu_j (c_{j-1} + c_j)``, ``c_i = omega_i / h_i`` (§2.5 Units; legs as in §4.4: floating ends
        count the end leg twice, the end legs of clamped ends carry no interval), so that a value acts the
        same at every scale and knot spacing. Every ``nu_j`` that has an effect must then be ``> -2``, the
        safe domain of §4.5 (``d_j > 0``, non-negative basis, convex hull); others raise ``ValueError``
        naming ``j`` and the bound. ``"absolute"`` (default) takes the thesis's raw ``v``.

    Returns
    -------
    Spline
        ``n_control - 3`` segments (floating or clamped) or ``N`` (closed). ``auxiliary``:
        ``'control_points'``, ``'F'`` (knot points), ``'tangents'`` (``M_i``), ``'V'``, ``'W'``. ``info``:
        ``form='basis'``, ``ends``, ``knots``, ``alpha``, ``beta``, ``point_tension_scale`` and ``leg_offset``
        (piece ``i`` lies over the control-polygon leg ``i + leg_offset``: 1 for open curves, 0 closed;
        see :meth:`Spline.piece_leg`).

    Raises
    ------
    TypeError, ValueError
        Naming the argument and index, for too few points, NaN/inf, coincident consecutive points with
        chord/centripetal knots, ``interval_weights[i] <= 0``, zero ``alpha``/``beta``, mismatched array
        lengths, non-increasing explicit knots, or a degenerate basis (vanishing ``D_i``).
    """
    closed, ends, scaled, values, steps, weights, tension, (exponent, knot_scale) = _prepare(
        control_points, closed, point_tension, interval_weights, knots, ends, point_tension_scale
    )
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        planar, knot_values, F, M = _assemble(scaled, values, steps, weights, tension, closed, ends)
    if not (np.isfinite(planar).all() and np.isfinite(M).all()):
        raise ValueError(_OVERFLOW_MESSAGE)
    if exponent or knot_scale:
        planar, F = np.ldexp(planar, exponent), np.ldexp(F, exponent)
        with np.errstate(over="ignore"):
            M = np.ldexp(M, exponent - knot_scale)
        if not np.isfinite(M).all():
            raise ValueError(_DERIVATIVE_OVERFLOW)
        knot_values = unscale_knots(knot_values, knot_scale, knots, "control_points")
        scaled = np.ldexp(scaled, exponent)
    alphas, betas = _class_parameters(alpha, beta, planar.shape[2])
    # V_i = F_i + h_i M_i / alpha_i = b0 + 3 (b1 - b0) / alpha_i, W_i likewise (§2.1, E1)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        V = planar[0] + (3.0 / alphas) * (planar[1] - planar[0])
        W = planar[3] - (3.0 / betas) * (planar[3] - planar[2])
    check_class_points(V, W, alphas, betas)
    info = {
        "form": "basis",
        "ends": "closed" if closed else ends,
        "knots": knots if isinstance(knots, str) else "explicit",
        "alpha": float(alphas[0]) if (alphas == alphas[0]).all() else "per-segment",
        "beta": float(betas[0]) if (betas == betas[0]).all() else "per-segment",
        "point_tension_scale": point_tension_scale,
        "leg_offset": 0 if closed else 1,
    }
    auxiliary = {"control_points": np.array(scaled), "F": F.T, "tangents": M.T, "V": V.T, "W": W.T}
    return Spline._from_trusted(planar, knot_values, closed=closed, auxiliary=auxiliary, info=info)


def _class_parameters(alpha, beta, m):
    """``alpha``, ``beta`` per segment: finite and non-zero (§2.1)."""
    segment_what = f"one per segment, {m}"
    alphas = per_item(alpha, m, "alpha", what=segment_what)
    betas = per_item(beta, m, "beta", what=segment_what)
    for name, values in (("alpha", alphas), ("beta", betas)):
        if not (values != 0).all():
            i = int(np.flatnonzero(values == 0)[0])
            raise ValueError(f"{name}[{i}] = 0: the class parameters must be non-zero (V_i, W_i divide by them)")
    return alphas, betas


def basis_functions(t, knots_or_n, *, point_tension=0.0, interval_weights=1.0, closed=False, ends="floating",
                    point_tension_scale="absolute"):
    """Values of all basis functions ``B_j(t)`` as a ``scipy.sparse.csr_array`` of shape ``(len(t), n_control)``
    (§4.1-4.3).

    At any ``t`` only the four ``B_j`` of the piece holding ``t`` can be non-zero (local support,
    ``B_j = 0`` outside ``(t_{j-2}, t_{j+2})``), so each row stores 4 entries: memory and time are
    ``O(len(t) + n_control)``. ``.toarray()`` gives the dense matrix; rows sum to 1 (partition of
    unity). The values come from one basis curve in four "colour" dimensions whose control points are
    unit vectors, coloured so that the four control points of every piece differ: piece ``k`` reads its
    four ``B_j`` off its own Bézier points.

    Parameters
    ----------
    t : float or array_like
        Parameters in the curve's domain (floating: ``[t_1, t_n]``; clamped: ``[t_1, t_n]``; closed: wraps).
    knots_or_n : int or array_like
        The number of control points (uniform knots ``t_j = j``), or explicit knot values as in
        :func:`basis_spline` (their count fixes ``n_control``).
    point_tension, interval_weights, closed, ends, point_tension_scale
        As in :func:`basis_spline`.
    """
    from scipy.sparse import csr_array

    closed = check_bool(closed, "closed")
    ends = check_choice(ends, "ends", BASIS_ENDS)
    if isinstance(knots_or_n, numbers.Integral) and not isinstance(knots_or_n, (bool, np.bool_)):
        n_control = int(knots_or_n)
        knots = "uniform"
    else:
        knots = as_float_array(knots_or_n, "knots_or_n", ndim=1)
        n_control = knots.shape[0] - 1 if closed else (knots.shape[0] + 2 if ends == "clamped" else knots.shape[0])
    minimum = 3 if closed else 4
    if n_control < minimum:
        raise ValueError(f"basis_functions needs at least {minimum} control points, got {n_control}")
    if n_control > MAX_BASIS_FUNCTIONS:
        raise ValueError(f"basis_functions takes at most {MAX_BASIS_FUNCTIONS} control points, got {n_control}")
    colours = _colours(n_control, closed)
    spline = basis_spline(np.eye(8)[colours], closed=closed, point_tension=point_tension,
                          interval_weights=interval_weights, knots=knots, ends=ends,
                          point_tension_scale=point_tension_scale)
    parameters = spline._check_parameters(t)
    flat = parameters.reshape(-1)
    try:
        piece, theta, _h = spline._locate(flat)
    except ValueError as exc:  # the curve's advice names its own extrapolate=, which this function does not take
        raise ValueError(str(exc).replace("; pass extrapolate=True to extend the end pieces",
                                          " (the basis functions are defined on the domain only)")) from None
    values = spline._evaluate(piece, theta, None, 0)  # (8, k): the value of colour c at each t
    first = piece - 1 if closed else piece  # piece k uses the control points first .. first + 3
    columns = (first[:, None] + np.arange(4)) % n_control  # (k, 4)
    data = np.take_along_axis(values.T, colours[columns], axis=1)
    if closed and n_control < 4:  # a control point twice in one window: its colour holds the sum, once
        repeated = np.zeros(columns.shape, dtype=bool)
        repeated[:, 3] = True
        data[repeated] = 0.0
    rows = np.repeat(np.arange(flat.shape[0]), 4)
    matrix = csr_array((data.reshape(-1), (rows, columns.reshape(-1))), shape=(flat.shape[0], n_control))
    matrix.sum_duplicates()
    return matrix


def _colours(n_control, closed):
    """A colour in 0..7 per control point, different for any four consecutive (cyclically when closed) ones."""
    colours = np.arange(n_control) % 4
    if closed and n_control >= 4:
        colours[-4:] = 4 + np.arange(4)  # the windows that wrap around see colours 4..7 next to 0..3
    return colours
