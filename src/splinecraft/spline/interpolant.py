"""The interpolant form of the generic cubic spline (thesis sections 3.1 and 4.2.1; §2-3).

Given points ``F_1..F_n`` the curve passes through every point. At each interior knot it is ``C^1`` and
satisfies the weighted nu-spline joint constraint (§2.2, thesis eqs 3.13, 3.14)

    omega_i P''(t_i^+) = v_i P'(t_i) + omega_{i-1} P''(t_i^-),

with a point tension ``v_i`` per point and an interval weight (interval tension) ``omega_i`` per interval.
The tangents ``M_i = P'(t_i)`` solve one tridiagonal system (cyclic for closed curves), with the same matrix
for every coordinate (§2.3, thesis eq 3.1 with errata E3, E4).
"""
from __future__ import annotations

import numbers

import numpy as np
from scipy.linalg.lapack import dgtsv

from .._validation import as_float_array, as_points, check_bool, check_choice, check_number, per_item
from .knots import check_distinct, parameterize
from .scaling import even_exponent, knot_exponent, unscale_knots
from .piecewise import Spline
from .segment import check_class_points, hermite_planar

__all__ = ["interpolate", "END_CONDITIONS", "end_derivative_estimates", "solve_tangents"]

#: The curve fits float64 but its tangents (derivatives with respect to the knot parameter) do not.
_DERIVATIVE_OVERFLOW = ("the tangents (derivatives along the knots) overflow float64: the points are too large for "
                        "knots this close together; use larger knot steps, or named knots ('chord', "
                        "'centripetal', 'uniform'), which scale with the points")

#: Accepted ``end_condition`` values (§2.4).
END_CONDITIONS = ("natural", "natural_v", "clamped", "periodic")

#: Condition-number bound above which a tangent system is rejected (§2.5).
MAX_CONDITION = 1e12


def end_derivative_estimates(points: np.ndarray, steps: np.ndarray):
    """End derivatives ``(M_1, M_n)`` from the 3-point parabola (§6.3), exact for quadratics.

    ``M_1 = ((2 h_1 + h_2) Δ_1 - h_1 Δ_2) / (h_1 + h_2)`` and its mirror image at the end; for two points
    both are the chord slope ``Δ_1``. ``steps`` are the ``h_i`` (``n - 1`` of them).
    """
    slopes = np.diff(points, axis=0) / steps[:, None]
    if steps.shape[0] == 1:
        return slopes[0].copy(), slopes[0].copy()
    h1, h2 = steps[0], steps[1]
    first = ((2.0 * h1 + h2) * slopes[0] - h1 * slopes[1]) / (h1 + h2)
    hn, hp = steps[-1], steps[-2]
    last = ((2.0 * hn + hp) * slopes[-1] - hn * slopes[-2]) / (hp + hn)
    return first, last


def _dominance_error(k, v, span, relative, row_kind):
    """ValueError for a point tension in the non-dominant band (§2.5)."""
    neighbours = "(c_{k-1} + c_k)" if row_kind == "interior" else ("c_1" if k == 0 else "c_{n-1}")
    if relative:
        where = f"point_tension[{k}] = {v / span:.6g} (relative)"
        low, high = -6.0, -2.0
        band = f"[-6, -2] (in units of {neighbours} = {span:.6g})"
    else:
        where = f"point_tension[{k}] = {v:.6g}"
        low, high = -6.0 * span, -2.0 * span
        band = f"[-6, -2] * {neighbours} = [{low:.6g}, {high:.6g}]"
    return ValueError(
        f"{where} makes row {k} of the tangent system not diagonally dominant: it lies in {band}, where the "
        f"system can be singular (§2.5). Use point_tension[{k}] > {high:.6g} (safe domain, unique energy "
        f"minimiser) or < {low:.6g} (unique solution, but the tangent at point {k} reverses and the curve loops)."
    )


def solve_tangents(lower, diag, upper, rhs, *, closed=False, off=None, describe_row=None):
    """Solve the (cyclic) tridiagonal tangent system for several right-hand sides (§2.3, §2.5).

    Row ``k`` reads ``lower[k] M_{k-1} + diag[k] M_k + upper[k] M_{k+1} = rhs[:, k]``; ``rhs`` is *planar*,
    shape ``(d, n)`` (one row per coordinate), and so is the returned solution. ``lower[0]`` and
    ``upper[-1]`` are the cyclic corners when ``closed`` and are ignored otherwise.

    Checks strict diagonal dominance row by row and Varah's bound
    ``cond_inf(A) <= |A|_inf / min_k(|a_kk| - sum_{j != k} |a_kj|)`` against :data:`MAX_CONDITION`, then solves
    with LAPACK ``gtsv`` (the tridiagonal solver behind ``scipy.linalg.solve_banded``), one call for all
    columns. Closed systems use Sherman-Morrison with the extra column in the same call (O(n)), with a
    residual check and a sparse-LU fallback. ``off`` (optional) is the precomputed ``|lower| + |upper|``
    per row; ``describe_row(k)`` returns the ``ValueError`` for a non-dominant row ``k``.
    """
    n = diag.shape[0]
    if off is None:
        off = np.abs(lower) + np.abs(upper)
        if not closed:
            off[0] = abs(upper[0])
            off[-1] = abs(lower[-1])
    absdiag = np.abs(diag)
    margin = absdiag - off
    if not (margin > 0).all():
        k = int(np.flatnonzero(~(margin > 0))[0])
        if describe_row is not None:
            raise describe_row(k)
        raise ValueError(f"row {k} of the tangent system is not diagonally dominant (§2.5)")
    # Varah's bound on the row-scaled matrix D^-1 A (D = diag): a row with a huge diagonal (a large point
    # tension, v -> +inf) is as good as an identity row, whatever the other rows' sizes.
    relative_margin = margin / absdiag
    worst = int(np.argmin(relative_margin))
    bound = float(np.max(1.0 + off / absdiag)) / float(relative_margin[worst])
    if bound > MAX_CONDITION:
        raise ValueError(
            f"the tangent system is ill-conditioned (condition bound {bound:.3g} > {MAX_CONDITION:.0e}), "
            f"worst at row {worst}: point_tension[{worst}] lies just outside the band of §2.5 where the system "
            f"is singular; move it further from the band"
        )
    if not closed:
        _, _, _, solution, info = dgtsv(lower[1:], diag, upper[:-1], rhs.T, overwrite_b=True)
        if info != 0:
            raise ValueError(f"the tangent system is singular (LAPACK gtsv info={info})")
        return solution.T
    # Sherman-Morrison for the cyclic corners (Numerical Recipes, section 2.7): A = T + u w^T with
    # u = (gamma, 0, .., 0, bottom), w = (1, 0, .., 0, top / gamma), gamma = -diag[0].
    top = float(lower[0])  # A[0, n-1]
    bottom = float(upper[-1])  # A[n-1, 0]
    gamma = -float(diag[0])
    modified = diag.copy()
    modified[0] -= gamma
    modified[-1] -= bottom * top / gamma
    d = rhs.shape[0]
    columns = np.empty((d + 1, n))
    columns[:d] = rhs
    columns[d] = 0.0
    columns[d, 0] = gamma
    columns[d, -1] = bottom
    _, _, _, both, info = dgtsv(lower[1:], modified, upper[:-1], columns.T, overwrite_b=True)
    if info != 0:
        raise ValueError(f"the cyclic tangent system is singular (LAPACK gtsv info={info})")
    both = both.T
    x, z = both[:d], both[d]
    denominator = 1.0 + z[0] + top * z[-1] / gamma
    factor = (x[:, 0] + top * x[:, -1] / gamma) / denominator
    solution = x - factor[:, None] * z
    # Sherman-Morrison can lose accuracy when 1 + w^T T^-1 u is small: verify the residual.
    residual = diag * solution + lower * np.roll(solution, 1, axis=1) + upper * np.roll(solution, -1, axis=1) - rhs
    scale = float(np.max(absdiag + off)) * float(np.max(np.abs(solution))) + float(np.max(np.abs(rhs)))
    if not np.isfinite(residual).all() or float(np.max(np.abs(residual))) > 1e-10 * scale:
        from scipy.sparse import diags
        from scipy.sparse.linalg import splu

        matrix = diags([lower[1:], diag, upper[:-1], [bottom], [top]], [-1, 0, 1, -(n - 1), n - 1], format="csc")
        solution = np.ascontiguousarray(splu(matrix).solve(np.ascontiguousarray(rhs.T)).T)
    return solution


def interpolate(points, *, closed=False, point_tension=0.0, interval_weights=1.0, alpha=3.0, beta=3.0,
                end_condition="natural", end_tangents=None, knots="chord", point_tension_scale="absolute"):
    """Interpolating generic cubic spline through ``points`` (thesis sections 3.1, 4.2.1; §2-3).

    The curve passes through every point; it is ``C^1`` and at each interior knot satisfies the weighted
    nu-spline joint constraint ``omega_i P''(t_i^+) = v_i P'(t_i) + omega_{i-1} P''(t_i^-)`` (§2.2,
    thesis 3.13-3.14). The tangents ``M_i`` solve one tridiagonal system (cyclic when closed), shared by all
    coordinates (§2.3, eq 3.1 with errata E3, E4), in O(n); the pieces are then the exact cubic
    Béziers ``[F_i, F_i + h_i M_i/3, F_{i+1} - h_i M_{i+1}/3, F_{i+1}]``.

    **The class parameters do not change the curve (erratum E1).** ``alpha``/``beta`` (Ball 2, Bézier 3,
    Timmer 4, see :data:`~splinecraft.CLASS_PRESETS`) cancel out of the interpolant exactly: they only move
    the auxiliary class polygon points ``V_i = F_i + h_i M_i / alpha_i`` and ``W_i = F_{i+1} - h_i M_{i+1} / beta_i``
    (§2.1), stored in ``spline.auxiliary`` for drawing. The curve is never computed through them.

    **Joints are G² only where neighbouring interval weights are equal (erratum E2).** The one-sided
    curvatures satisfy ``kappa(t_i^+) = (omega_{i-1} / omega_i) kappa(t_i^-)`` for any ``v_i``; see
    :meth:`Spline.joint_curvature` and :meth:`Spline.curvature_comb`, which show the jump.

    Parameters
    ----------
    points : array_like, shape (n, d)
        Data points ``F_1..F_n``: finite, ``n >= 2`` (``N >= 3`` distinct points when closed; do not
        repeat the first point at the end), consecutive points distinct (§3).
    closed : bool
        Closed loop with the periodic end condition (§2.4 Type 3, erratum E6). ``closed=True``
        implies ``end_condition="periodic"`` and vice versa.
    point_tension : float or array_like, shape (n,)
        Point tension ``v_i`` (one per point). ``v > 0`` tightens the curve towards the polygon
        (§2.5, erratum E22); ``v -> +inf`` gives zero tangents (a polygon with cusps). The end values
        act only with ``end_condition="natural_v"`` (and for every point of a closed curve).
        **Sign rule (§2.5):** row ``k`` must be strictly diagonally dominant, i.e.
        ``v_k > -2 (c_{k-1} + c_k)`` (safe domain: unique minimiser of the energy of §2.2) or
        ``v_k < -6 (c_{k-1} + c_k)`` (accepted and unique, but the tangent at ``F_k`` reverses relative to the
        chords and the curve loops or bulges, thesis Figs 3.8-3.11). Values in the band
        ``[-6, -2] (c_{k-1} + c_k)``, where the system can be singular, raise ``ValueError`` naming ``k`` and
        the bounds. Here ``c_i = omega_i / h_i``; at an open end only the one existing ``c`` counts.
    interval_weights : float or array_like, shape (n-1,) or (N,) when closed
        Interval weights ``omega_i > 0`` (interval tension): larger values straighten interval ``i``.
    alpha, beta : float or array_like, shape (n-1,) or (N,)
        Class parameters per segment (finite, non-zero). They only position ``V_i``, ``W_i`` (see above).
    end_condition : {"natural", "natural_v", "clamped", "periodic"}
        ``"natural"``: ``P'' = 0`` at both ends (§2.4 Type 2, the default). ``"natural_v"``: the free-end
        energy minimiser of thesis eq 3.3 (§2.4 Type 2v, erratum E5), with ``P''(t_1) = v_1 M_1 / omega_1``;
        its end rows need ``v_1 > -2 c_1`` and ``v_n > -2 c_{n-1}`` (or below ``-6 c``). ``"clamped"``: given
        end derivatives (Type 1). ``"periodic"``: closed curve (Type 3).
    end_tangents : (M_1, M_n), optional
        End derivatives ``dP/dt`` in the knot parameter for ``"clamped"`` (either may be ``None``). Default:
        the 3-point parabola estimate of §6.3 (exact for quadratics). Only valid with ``"clamped"``.
    knots : {"chord", "centripetal", "uniform"} or array_like
        Knot parameterization (§3), or explicit strictly increasing values: ``n`` for an open curve,
        ``N + 1`` for a closed one (the last closes the loop).
    point_tension_scale : {"absolute", "relative"}
        ``"relative"`` reads ``point_tension`` as the dimensionless ``nu_k`` with
        ``v_k = nu_k (c_{k-1} + c_k)`` (§2.5 Units), which acts the same at every scale and knot spacing
        (safe iff ``nu_k > -2``); useful for sliders.

    Returns
    -------
    Spline
        ``n - 1`` pieces (``N`` when closed). ``auxiliary``: ``'F'`` (the points), ``'tangents'`` (``M_i``),
        ``'V'``, ``'W'`` (class polygon). ``info``: ``form='interpolant'``, ``end_condition``, ``knots``,
        ``alpha``, ``beta``, ``point_tension_scale``, ``leg_offset=0`` (piece ``i`` runs from point ``i`` to
        ``i + 1``; see :meth:`Spline.piece_leg`).

    Raises
    ------
    TypeError
        Non-numeric arrays, non-bool ``closed``, non-string options.
    ValueError
        Naming the argument and index: fewer than 2 points (3 when closed); NaN or inf anywhere;
        consecutive coincident points; ``interval_weights[i] <= 0``; ``alpha``/``beta`` zero; array lengths
        that do not match the number of points or intervals; non-increasing explicit knots; a point tension
        in the non-dominant band (or an ill-conditioned system, condition bound > 1e12); conflicting
        ``closed``/``end_condition``; ``end_tangents`` of the wrong shape or without ``"clamped"``.
    """
    closed, end_condition, point_tension_scale = _check_options(closed, end_condition, point_tension_scale,
                                                               end_tangents)
    points = as_points(points, "points", min_count=3 if closed else 2)
    n, d = points.shape
    m = n if closed else n - 1
    # Solve in coordinates scaled by an exact power of two 2^k (any float64 scale works; §2.5 Units: v has
    # the units of c = omega / h, so it scales with the knots). At moderate scales k = 0.
    exponent = even_exponent(points)
    planar_points = np.ascontiguousarray(np.ldexp(points.T, -exponent) if exponent else points.T)  # (d, n)
    legs = np.empty((d, m))
    np.subtract(planar_points[:, 1:], planar_points[:, :-1], out=legs[:, : n - 1])
    if closed:
        np.subtract(planar_points[:, 0], planar_points[:, -1], out=legs[:, -1])
    lengths = np.sqrt(np.einsum("dk,dk->k", legs, legs))
    extent = float(np.max(planar_points.max(axis=1) - planar_points.min(axis=1)))
    check_distinct(planar_points.T, closed, lengths=lengths, extent=extent)
    t = parameterize(planar_points.T, knots, closed=closed, lengths=lengths)
    # the knots of the scaled points are t / 2^knot_scale: named ones scale with the points, explicit ones are
    # scaled by their own power of two (0 at moderate sizes), so that c = omega / h neither over- nor underflows
    knot_scale = knot_exponent(knots, exponent) if isinstance(knots, str) else even_exponent(t)
    if not isinstance(knots, str):
        t = np.ldexp(t, -knot_scale)  # a copy: never freeze (read-only flag) or alias the caller's array
    steps = np.diff(t)
    interval_what = f"one per interval, {m} for {n} {'closed ' if closed else ''}points"
    weights = _interval_weights(interval_weights, m, interval_what)
    tension = _maybe_scalar(point_tension, n, "point_tension", f"one per point, {n}")
    alphas = _class_parameter(alpha, m, "alpha", interval_what)
    betas = _class_parameter(beta, m, "beta", interval_what)
    relative = point_tension_scale == "relative"
    # the system is homogeneous in omega (with v in the units of omega / h): divide both by 2^w, too
    given = (weights, steps if not knot_scale else np.ldexp(steps, knot_scale))  # as the caller knows them
    weight_scale = even_exponent(np.asarray(weights))
    if weight_scale:
        weights = np.ldexp(weights, -weight_scale)
    if not relative and knot_scale - weight_scale:
        tension = np.ldexp(tension, knot_scale - weight_scale)  # v_scaled = v 2^knot_scale / 2^w
    ends = None
    if end_condition == "clamped":
        ends = _end_tangents(end_tangents, points, planar_points.T, steps, d, exponent - knot_scale)
    system = _tangent_system(planar_points, legs, steps, weights, tension, relative, end_condition, closed, ends,
                             given)
    tangents = solve_tangents(*system[:4], closed=closed, off=system[4], describe_row=system[5])
    if not np.isfinite(tangents).all():
        raise ValueError("the tangent system produced non-finite tangents (§2.5): point_tension and "
                         "interval_weights of extreme size; use values of moderate size")
    planar, V, W = hermite_planar(planar_points, tangents, steps, closed, alphas, betas)
    if exponent or knot_scale:
        with np.errstate(over="ignore"):
            planar, V, W = (np.ldexp(array, exponent) for array in (planar, V, W))
        check_class_points(V, W, alphas, betas)
        with np.errstate(over="ignore"):
            tangents = np.ldexp(tangents, exponent - knot_scale)
        if not np.isfinite(tangents).all():
            raise ValueError(_DERIVATIVE_OVERFLOW)
        planar_points = np.ascontiguousarray(points.T)
        t = unscale_knots(t, knot_scale, knots)
    info = {
        "form": "interpolant",
        "end_condition": end_condition,
        "knots": knots if isinstance(knots, str) else "explicit",
        "alpha": _summary(alphas),
        "beta": _summary(betas),
        "point_tension_scale": point_tension_scale,
        "leg_offset": 0,
    }
    auxiliary = {"F": planar_points.T.copy(), "tangents": tangents.T, "V": V.T, "W": W.T}
    return Spline._from_trusted(planar, t, closed=closed, auxiliary=auxiliary, info=info)


def _check_options(closed, end_condition, point_tension_scale, end_tangents):
    closed = check_bool(closed, "closed")
    end_condition = check_choice(end_condition, "end_condition", END_CONDITIONS)
    point_tension_scale = check_choice(point_tension_scale, "point_tension_scale", ("absolute", "relative"))
    if end_condition == "periodic":
        closed = True
    elif closed and end_condition != "natural":
        raise ValueError(
            f"closed=True uses the periodic end condition; end_condition={end_condition!r} applies to open curves"
        )
    if closed:
        end_condition = "periodic"
    if end_tangents is not None and end_condition != "clamped":
        raise ValueError(f"end_tangents is only used with end_condition='clamped', not {end_condition!r}")
    return closed, end_condition, point_tension_scale


def _tangent_system(planar_points, legs, steps, weights, tension, relative, end_condition, closed, ends, given=None):
    """``(lower, diag, upper, rhs, off, describe_row)`` of the tangent system (§2.3, §2.4, eq 3.1, E3-E6).

    ``weights`` and ``steps`` are those of the rescaled problem; ``given`` (optional) is the pair
    ``(interval_weights, h)`` in the caller's units, for the messages.
    """
    d, n = planar_points.shape
    with np.errstate(over="ignore", under="ignore"):
        c = weights / steps  # c_i = omega_i / h_i
    if given is None:
        check_interval_ratio(c, weights, "omega_i / h_i", steps)
    elif not (np.isfinite(c) & (c > 0)).all():
        i = int(np.flatnonzero(~(np.isfinite(c) & (c > 0)))[0])
        given_weights, given_steps = np.broadcast_to(given[0], c.shape), np.broadcast_to(given[1], c.shape)
        raise ValueError(
            f"interval {i} has h_{i} = {float(given_steps[i]):.3g} (knot interval of points) and "
            f"interval_weights[{i}] = {float(given_weights[i])!r}: its omega_i / h_i, measured against the largest "
            f"interval weight, is beyond the float64 range (§2.2); neighbouring points this close compared with "
            f"their coordinates, or weights this far apart, cannot be represented in one tangent system"
        )
    slopes = legs
    slopes /= steps  # Delta_i (legs is no longer needed)
    weighted = c * slopes  # c_i Delta_i, planar (d, m)
    rhs = np.empty((d, n))
    if closed:
        c_prev = np.roll(c, 1)
        spans = c_prev + c
        v = tension * spans if relative else tension
        diag = 2.0 * spans
        diag += 0.5 * v
        lower, upper, off = c_prev, c, spans
        np.add(weighted, np.roll(weighted, 1, axis=1), out=rhs)
        rhs *= 3.0
    else:
        spans = np.empty(n)
        spans[0] = c[0]
        spans[-1] = c[-1]
        np.add(c[:-1], c[1:], out=spans[1:-1])
        v = tension * spans if relative else tension
        diag = 2.0 * spans
        diag[1:-1] += 0.5 * (v if np.ndim(v) == 0 else v[1:-1])
        lower = np.empty(n)
        upper = np.empty(n)
        lower[0] = upper[-1] = 0.0
        lower[1:] = c
        upper[:-1] = c
        off = spans.copy()
        np.add(weighted[:, :-1], weighted[:, 1:], out=rhs[:, 1:-1])
        rhs[:, 1:-1] *= 3.0
        if end_condition == "clamped":
            first, last = ends
            # rows c_1 M_1 = c_1 M̂_1 and c_{n-1} M_n = c_{n-1} M̂_n (scaled like the interior rows)
            diag[0], upper[0], rhs[:, 0] = c[0], 0.0, c[0] * first
            diag[-1], lower[-1], rhs[:, -1] = c[-1], 0.0, c[-1] * last
            off[0] = off[-1] = 0.0
        else:
            if end_condition == "natural_v":
                v_ends = np.broadcast_to(v, (n,))
                diag[0] += 0.5 * v_ends[0]
                diag[-1] += 0.5 * v_ends[-1]
            rhs[:, 0] = 3.0 * weighted[:, 0]
            rhs[:, -1] = 3.0 * weighted[:, -1]

    def describe_row(k):
        interior = closed or 0 < k < n - 1
        if not interior and end_condition != "natural_v":
            return ValueError(f"row {k} of the tangent system is not diagonally dominant (§2.5)")
        return _dominance_error(k, float(np.broadcast_to(v, (n,))[k]), float(spans[k]), relative,
                                "interior" if interior else "end")

    return lower, diag, upper, rhs, off, describe_row


def check_interval_ratio(ratio, weights, what, steps, points_name="points"):
    """``ValueError`` naming the interval, its points and ``interval_weights[i]`` when ``omega_i / h_i`` (or
    ``h_i / omega_i``) leaves the float64 range."""
    ratio = np.broadcast_to(ratio, np.shape(ratio))
    bad = ~(np.isfinite(ratio) & (ratio > 0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        weight = float(np.broadcast_to(weights, bad.shape)[i])
        raise ValueError(
            f"interval {i} has h_{i} = {float(steps[i]):.3g} (knot interval of {points_name}) and "
            f"interval_weights[{i}] = {weight!r}: {what} = {float(ratio[i])!r} is beyond the float64 range "
            f"(§2.2); neighbouring {points_name} this close compared with their coordinates, or weights this "
            f"extreme, cannot be represented"
        )


def _maybe_scalar(value, count, name, what):
    """A finite Python float for scalar input (the common case, no array work), else a checked array."""
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        return check_number(value, name)
    return per_item(value, count, name, what=what)


def _interval_weights(value, count, what):
    weights = _maybe_scalar(value, count, "interval_weights", what)
    if np.ndim(weights) == 0:
        if not weights > 0:
            raise ValueError(f"interval_weights = {weights!r} must be > 0")
        return weights
    if not (weights > 0).all():
        i = int(np.flatnonzero(~(weights > 0))[0])
        raise ValueError(f"interval_weights[{i}] = {float(weights[i])!r} must be > 0")
    return weights


def _class_parameter(value, count, name, what):
    values = _maybe_scalar(value, count, name, what)
    if np.ndim(values) == 0:
        if values == 0:
            raise ValueError(f"{name} = 0: the class parameters must be non-zero (V_i, W_i divide by them)")
        return values
    if not (values != 0).all():
        i = int(np.flatnonzero(values == 0)[0])
        raise ValueError(f"{name}[{i}] = 0: the class parameters must be non-zero (V_i, W_i divide by them)")
    return values


def _summary(values):
    """A scalar when all per-segment values are equal, else 'per-segment' (keeps info small)."""
    if np.ndim(values) == 0:
        return float(values)
    first = float(values[0])
    return first if (values == first).all() else "per-segment"


def _end_tangents(end_tangents, points, scaled_points, steps, d, exponent):
    """Clamped end derivatives in the scaled problem: given ones times ``2^-exponent``, else §6.3's."""
    default_first, default_last = end_derivative_estimates(scaled_points, steps)
    if end_tangents is None:
        return default_first, default_last
    try:
        pair = isinstance(end_tangents, (list, tuple, np.ndarray)) and len(end_tangents) == 2
    except TypeError:  # a 0-d array
        pair = False
    if not pair:
        raise ValueError("end_tangents must be a pair (M_1, M_n) of derivative vectors (either may be None)")
    out = []
    for label, value, default in (("M_1", end_tangents[0], default_first), ("M_n", end_tangents[1], default_last)):
        if value is None:
            out.append(default)
            continue
        vector = as_float_array(value, f"end_tangents {label}")
        if vector.shape != (d,):
            raise ValueError(f"end_tangents {label} must be a vector of length {d}, got shape {vector.shape}")
        out.append(np.ldexp(vector, -exponent) if exponent else vector)
    return out[0], out[1]
