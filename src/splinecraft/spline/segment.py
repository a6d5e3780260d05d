"""The generic cubic segment (§1; thesis eqs 3.5-3.9, 3.16-3.22) and the Hermite-to-Bézier step.

A generic segment is designed by four points ``F_i, V_i, W_i, F_{i+1}`` and two class parameters
``alpha_i, beta_i``:

    P(theta) = (1-theta)^2 {1 + (2-alpha) theta} F_i + alpha theta (1-theta)^2 V_i
               + beta theta^2 (1-theta) W_i + theta^2 {1 + (2-beta)(1-theta)} F_{i+1}.

With ``V, W`` held fixed, ``alpha`` and ``beta`` really change the shape (:func:`generic_segment`).
The named classes are Ball (``alpha = beta = 2``), Bézier (3) and Timmer (4), see :data:`CLASS_PRESETS`.

In the interpolant (§2) and the local-support basis form (§4), however, ``V_i`` and ``W_i`` are
*derived* from the knot tangents, ``V_i = F_i + h_i M_i / alpha_i`` and ``W_i = F_{i+1} - h_i M_{i+1} / beta_i``,
and then ``alpha, beta`` cancel exactly (§2.1, erratum E1): those curves do not depend on the class at all,
only the drawn class polygon ``F_i V_i W_i F_{i+1}`` does.
"""
from __future__ import annotations

import numpy as np

from .._validation import as_float_array, check_strictly_increasing
from .piecewise import Spline
from .scaling import even_exponent

__all__ = [
    "bezier_signed_area",
    "CLASS_PRESETS",
    "generic_segment",
    "blending_functions",
    "segment_bezier",
    "hermite_bezier",
    "hermite_planar",
    "class_polygon",
    "check_class_points",
]

#: Named classes of the generic cubic (§1): ``name -> (alpha, beta)``.
CLASS_PRESETS = {"ball": (2.0, 2.0), "bezier": (3.0, 3.0), "timmer": (4.0, 4.0)}


def blending_functions(theta, alpha=3.0, beta=3.0) -> np.ndarray:
    """The four coefficient functions of ``F_i, V_i, W_i, F_{i+1}`` in the generic segment (§1, eq 3.5).

    Parameters
    ----------
    theta : float or array_like
        Local parameter(s) in ``[0, 1]`` (other values extrapolate the polynomials).
    alpha, beta : float or array_like
        Class parameters, broadcast against ``theta``.

    Returns
    -------
    ndarray, shape ``theta.shape + (4,)``
        ``[(1-θ)²(1+(2-α)θ), αθ(1-θ)², βθ²(1-θ), θ²(1+(2-β)(1-θ))]``. They sum to 1 for every
        ``alpha, beta``. ``alpha = beta = 2`` gives Ball's basis, 3 the Bernstein (Bézier) basis with
        ``V, W`` as inner control points, 4 Timmer's basis (§1, §5.1).
    """
    theta = as_float_array(theta, "theta")
    alpha = as_float_array(alpha, "alpha")
    beta = as_float_array(beta, "beta")
    s = 1.0 - theta
    return np.stack(
        np.broadcast_arrays(
            s * s * (1.0 + (2.0 - alpha) * theta),
            alpha * theta * s * s,
            beta * theta * theta * s,
            theta * theta * (1.0 + (2.0 - beta) * s),
        ),
        axis=-1,
    )


def segment_bezier(F0, V, W, F1, alpha, beta) -> np.ndarray:
    """Exact Bézier control points ``(..., 4, d)`` of generic segments (§1).

    ``b0 = F_i``, ``b1 = F_i + alpha/3 (V_i - F_i)``, ``b2 = F_{i+1} + beta/3 (W_i - F_{i+1})``, ``b3 = F_{i+1}``.
    Arguments broadcast; ``alpha``/``beta`` broadcast against the leading (segment) axes.
    """
    alpha = np.asarray(alpha, dtype=float)[..., None]
    beta = np.asarray(beta, dtype=float)[..., None]
    F0, V, W, F1 = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (F0, V, W, F1)))
    b1 = F0 + (alpha / 3.0) * (V - F0)
    b2 = F1 + (beta / 3.0) * (W - F1)
    return np.stack(np.broadcast_arrays(F0, b1, b2, F1), axis=-2)


def generic_segment(F0, V, W, F1, alpha=3.0, beta=3.0, *, knots=(0.0, 1.0)) -> Spline:
    """A single generic cubic segment designed by its points ``F_i, V_i, W_i, F_{i+1}`` (§1, eqs 3.5-3.9).

    Here ``V`` and ``W`` are given, so the class parameters ``alpha`` and ``beta`` genuinely change the
    shape: the Bézier inner points are ``b1 = F_i + alpha/3 (V - F_i)`` and ``b2 = F_{i+1} + beta/3 (W - F_{i+1})``,
    the end derivatives ``P'(t_i) = alpha/h (V - F_i)`` and ``P'(t_{i+1}) = beta/h (F_{i+1} - W)`` (eqs 3.10, 3.11).
    Presets: :data:`CLASS_PRESETS` (Ball 2, Bézier 3, Timmer 4), e.g.
    ``generic_segment(F0, V, W, F1, *CLASS_PRESETS["timmer"])``.
    (This is the only construction where ``alpha, beta`` shape the curve: in :func:`~splinecraft.interpolate`
    and :func:`~splinecraft.basis_spline` they cancel out, erratum E1.)

    Parameters
    ----------
    F0, V, W, F1 : array_like, shape (d,)
        End points and class control points, all finite and of the same dimension.
    alpha, beta : float
        Finite class parameters. ``alpha = 0`` (``beta = 0``) removes the influence of ``V`` (``W``).
    knots : (float, float), optional
        Parameter interval ``[t_i, t_{i+1}]`` with ``t_i < t_{i+1}``; derivatives are per unit of it.

    Returns
    -------
    Spline
        One piece; ``auxiliary`` holds ``'V'``, ``'W'`` (shape ``(1, d)``) and ``'F'`` (shape ``(2, d)``).
    """
    names = ("F0", "V", "W", "F1")
    arrays = [as_float_array(x, name, ndim=1) for x, name in zip((F0, V, W, F1), names)]
    dims = {a.shape[0] for a in arrays}
    if len(dims) != 1 or 0 in dims:
        raise ValueError(
            "F0, V, W, F1 must be points of the same dimension, got lengths "
            + ", ".join(f"{n}={a.shape[0]}" for n, a in zip(names, arrays))
        )
    alpha_value = float(as_float_array(alpha, "alpha", ndim=0))
    beta_value = float(as_float_array(beta, "beta", ndim=0))
    interval = as_float_array(knots, "knots", ndim=1)
    if interval.shape != (2,):
        raise ValueError(f"knots must be (t_i, t_i+1), got {interval.shape[0]} values")
    check_strictly_increasing(interval, "knots")
    F0, V, W, F1 = arrays
    # b1 = F0 + alpha/3 (V - F0) on points scaled by an exact power of two (scaling.py): V - F0 of points
    # near the float64 limit would overflow although b1 (= V for the Bézier class) is representable
    exponent = even_exponent(np.stack(arrays))
    scaled = [np.ldexp(x, -exponent) for x in arrays] if exponent else arrays
    bezier = segment_bezier(*scaled, alpha_value, beta_value)[None]
    if exponent:
        with np.errstate(over="ignore"):
            bezier = np.ldexp(bezier, exponent)
        bezier[0, 0], bezier[0, 3] = F0, F1  # the end points bit for bit (a tiny coordinate next to a huge one)
    if not np.isfinite(bezier).all():
        which = "b1 = F0 + alpha/3 (V - F0)" if not np.isfinite(bezier[0, 1]).all() else "b2 = F1 + beta/3 (W - F1)"
        raise ValueError(
            f"the Bézier point {which} (§1) lies beyond the float64 range with alpha = {alpha_value!r}, "
            f"beta = {beta_value!r}: a class parameter this large, or points this close to the float64 limit, "
            f"put it there"
        )
    return Spline(
        bezier,
        interval,
        auxiliary={"V": V[None], "W": W[None], "F": np.stack([F0, F1])},
        info={"form": "generic_segment", "alpha": alpha_value, "beta": beta_value},
    )


def hermite_bezier(points: np.ndarray, tangents: np.ndarray, steps: np.ndarray, closed: bool) -> np.ndarray:
    """Bézier pieces of the ``C^1`` cubic Hermite curve through ``(t_i, F_i, M_i)`` (§2.1).

    ``b1 = F_i + h_i M_i / 3``, ``b2 = F_{i+1} - h_i M_{i+1} / 3``; no class parameter enters (E1).
    ``points``/``tangents`` have one row per knot (``m + 1`` open, ``m`` closed); ``steps`` are the ``h_i``.
    """
    m = steps.shape[0]
    d = points.shape[1]
    bezier = np.empty((m, 4, d))
    third = (steps / 3.0)[:, None]
    bezier[:, 0] = points[:m]
    bezier[:, 1] = points[:m] + third * tangents[:m]
    if closed:
        bezier[:-1, 3] = points[1:]
        bezier[-1, 3] = points[0]
        bezier[:-1, 2] = points[1:] - third[:-1] * tangents[1:]
        bezier[-1, 2] = points[0] - third[-1] * tangents[0]
    else:
        bezier[:, 3] = points[1:]
        bezier[:, 2] = points[1:] - third * tangents[1:]
    return bezier


def hermite_planar(points, tangents, steps, closed, alpha, beta):
    """Planar Hermite pieces and class polygon in one pass (internal fast path of §2.1).

    ``points``/``tangents`` are planar ``(d, n)`` (one row per coordinate, one column per knot; ``n = m + 1``
    open, ``m`` closed), ``steps`` the ``h_i``; ``alpha``/``beta`` scalars or ``(m,)``. Returns the planar
    Bézier array ``(4, d, m)`` (``b1 = F_i + h_i M_i / 3``, ``b2 = F_{i+1} - h_i M_{i+1} / 3``, no class
    parameter, E1) and ``V = F_i + h_i M_i / alpha_i``, ``W = F_{i+1} - h_i M_{i+1} / beta_i``, each ``(d, m)``.
    """
    d = points.shape[0]
    m = steps.shape[0]
    planar = np.empty((4, d, m))
    third = steps / 3.0
    start_offset = tangents[:, :m] * third  # h_i M_i / 3
    if closed:
        planar[3, :, :-1] = points[:, 1:]
        planar[3, :, -1] = points[:, 0]
        end_offset = np.empty((d, m))
        np.multiply(tangents[:, 1:], third[:-1], out=end_offset[:, :-1])
        np.multiply(tangents[:, 0], third[-1], out=end_offset[:, -1])
    else:
        planar[3] = points[:, 1:]
        end_offset = tangents[:, 1:] * third  # h_i M_{i+1} / 3
    planar[0] = points[:, :m]
    np.add(planar[0], start_offset, out=planar[1])
    np.subtract(planar[3], end_offset, out=planar[2])
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        start_offset *= 3.0 / np.asarray(alpha, dtype=float)
        end_offset *= 3.0 / np.asarray(beta, dtype=float)
        V = start_offset
        V += planar[0]
        W = np.subtract(planar[3], end_offset, out=end_offset)
    check_class_points(V, W, alpha, beta)
    return planar, V, W


def check_class_points(V, W, alpha, beta):
    """Raise ``ValueError`` naming ``alpha[i]``/``beta[i]`` when ``V_i``/``W_i`` (planar ``(d, m)``) overflow.

    ``V_i = F_i + h_i M_i / alpha_i`` (§2.1) leaves the float64 range for a class parameter far below the
    size of ``h_i M_i / F_i``; the curve itself does not depend on it (E1), but its class polygon would be inf.
    """
    for name, points, values in (("alpha", V, alpha), ("beta", W, beta)):
        finite = np.isfinite(points).all(axis=0)
        if not finite.all():
            i = int(np.flatnonzero(~finite)[0])
            value = float(np.broadcast_to(np.asarray(values, dtype=float), finite.shape)[i])
            label = name if np.ndim(values) == 0 else f"{name}[{i}]"
            point = "V" if name == "alpha" else "W"
            raise ValueError(
                f"the class point {point}_{i} = F + h M / {name} (§2.1) lies beyond the float64 range, with "
                f"{label} = {value!r}: a |{name}| this close to 0, or points this close to the float64 limit, "
                f"put it there"
            )


def class_polygon(bezier: np.ndarray, steps: np.ndarray, alpha, beta):
    """Class control points ``V_i, W_i`` of each piece (§2.1): ``V_i = F_i + h_i M_i / alpha_i``,
    ``W_i = F_{i+1} - h_i M_{i+1} / beta_i``.

    Computed from the Bézier pieces (``h_i M_i = 3 (b1 - b0)``, ``h_i M_{i+1} = 3 (b3 - b2)``), so this is the
    only place where ``alpha, beta`` enter; they must be non-zero. Returns ``(V, W)``, each ``(m, d)``.
    """
    alpha = np.asarray(alpha, dtype=float)
    beta = np.asarray(beta, dtype=float)
    if alpha.ndim:
        alpha = alpha[:, None]
    if beta.ndim:
        beta = beta[:, None]
    V = bezier[:, 0] + (3.0 / alpha) * (bezier[:, 1] - bezier[:, 0])
    W = bezier[:, 3] - (3.0 / beta) * (bezier[:, 3] - bezier[:, 2])
    return V, W


_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(3)


def bezier_signed_area(bezier) -> float:
    """Signed area of closed cubic Bézier pieces ``(m, 4, 2)``: ``1/2 \\oint (x dy - y dx)``, exact (the
    integrand is a polynomial of degree 5, integrated by 3-point Gauss-Legendre). The area of a closed curve
    does not depend on the origin, so it is integrated about the first point: far from the origin (a shape at
    ``x = 1e9``) the products ``x dy`` would otherwise cancel away the area and its sign."""
    bezier = np.asarray(bezier, float)
    if bezier.size:
        bezier = bezier - bezier.reshape(-1, 2)[0]
    t = 0.5 * (_GAUSS_NODES + 1.0)
    one = 1.0 - t
    basis = np.stack([one ** 3, 3 * one * one * t, 3 * one * t * t, t ** 3])  # (4, q)
    derivative = np.stack([-3 * one * one, 3 * one * (one - 2 * t), 3 * t * (2 * one - t), 3 * t * t])
    value = np.einsum("iq,pid->pqd", basis, bezier)
    slope = np.einsum("iq,pid->pqd", derivative, bezier)
    cross = value[..., 0] * slope[..., 1] - value[..., 1] * slope[..., 0]
    return float(0.25 * np.einsum("pq,q->", cross, _GAUSS_WEIGHTS))
