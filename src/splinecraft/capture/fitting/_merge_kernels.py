"""Compiled loop of the segment merging (:mod:`.merge`, docs/capture.md §12, "Merged segments"): one cubic per
candidate run of segments fitted to the contour points it covers and checked against them, one pass per run.

Per run the cubic keeps the run's end points ``p0``, ``p3`` and the handle directions ``d0``, ``d1``; its two
handle lengths solve the 2 x 2 least-squares problem on about ``fit_points`` of the run's contour points (evenly
spread, both ends included) at their current parameters, followed by a foot-point Newton step of those
parameters, ``steps`` times. Every covered point then gets its parameter interpolated between the fitted ones
and one Newton step, and its distance to the cubic (to the tangent line at the run's end where its foot lies
beyond it: the G1 neighbour continues along that line), computed only where it may raise the run's largest
excess so far (:data:`SURE`). Compiled (numba, cached on disk like
:mod:`._kernels`); the wrapper allocates every output.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import HELPER_OPTIONS as _HELPER, JIT_OPTIONS, pyclip, pymax

__all__ = ["fit_runs", "warm_up", "TANGENTIAL"]

#: Weight of the tangential part of the residuals after the first solve (the normal part has weight 1): a
#: little of it keeps the solve well posed where the points are nearly straight.
TANGENTIAL = 0.0
#: Damping of the later solves towards the previous handle lengths, relative to the normal matrix's trace.
DAMPING = 1e-3
#: A point's squared distance below ``SURE`` times the square of a bound puts its distance (``numpy.hypot``, within
#: an ulp or two of the rounded square root) below that bound for certain, so :func:`_fit_runs_into` computes the
#: distance only where it may raise a running maximum: the maximum is bit for bit the same.
SURE = 1.0 - 1e-12


@njit(**_HELPER)
def _coefficients(c):
    """The control points of the cubic ``c`` (x then y) and the differences of its derivatives, the values
    the point of :func:`_fit_runs_into` and :func:`_newton` take (computed once per cubic instead of once per
    point)."""
    e0x, e1x, e2x = c[1, 0] - c[0, 0], c[2, 0] - c[1, 0], c[3, 0] - c[2, 0]
    e0y, e1y, e2y = c[1, 1] - c[0, 1], c[2, 1] - c[1, 1], c[3, 1] - c[2, 1]
    return (c[0, 0], c[1, 0], c[2, 0], c[3, 0], c[0, 1], c[1, 1], c[2, 1], c[3, 1], e0x, e1x, e2x, e0y, e1y, e2y,
            e1x - e0x, e2x - e1x, e1y - e0y, e2y - e1y)


@njit(**_HELPER)
def _newton(k, qx, qy, t):
    """One foot-point Newton step of ``(B(t) - q) . B'(t) = 0`` on the cubic of coefficients ``k``
    (:func:`_coefficients`), clipped to [0, 1]."""
    c0x, c1x, c2x, c3x, c0y, c1y, c2y, c3y, e0x, e1x, e2x, e0y, e1y, e2y, f0x, f1x, f0y, f1y = k
    s = 1.0 - t
    rx = s * s * s * c0x + 3.0 * s * s * t * c1x + 3.0 * s * t * t * c2x + t * t * t * c3x - qx
    ry = s * s * s * c0y + 3.0 * s * s * t * c1y + 3.0 * s * t * t * c2y + t * t * t * c3y - qy
    fx = 3.0 * (s * s * e0x + 2.0 * s * t * e1x + t * t * e2x)
    fy = 3.0 * (s * s * e0y + 2.0 * s * t * e1y + t * t * e2y)
    gx = 6.0 * (s * f0x + t * f1x)
    gy = 6.0 * (s * f0y + t * f1y)
    speed2 = fx * fx + fy * fy
    den = speed2 + rx * gx + ry * gy
    if not den > 0.1 * speed2:
        den = speed2
    if not den > 1e-300:
        return t
    step = -(rx * fx + ry * fy) / den
    step = pyclip(step, -0.25, 0.25)
    return pyclip(t + step, 0.0, 1.0)


@njit(**JIT_OPTIONS)
def _fit_runs_into(p0, p3, d0, d1, lo, count, offsets, points, u, start, span, tol, fitted, steps, fit_points,
                   limits, scratch, cubic, handles, t_out, excess, drift, spread):
    for r in range(p0.shape[0]):
        n = count[r]
        stride = pymax(1, n // fit_points)
        m = np.int64(0)  # the fitted points: j = 0, stride, 2 stride, ..., and n - 1
        j = np.int64(0)
        while j < n:
            scratch[m, 0] = j
            scratch[m, 1] = pyclip((u[lo[r] + j] - start[r]) / span[r], 0.0, 1.0)
            m += 1
            j += stride
        if n > 0 and scratch[m - 1, 0] != n - 1:
            scratch[m, 0] = n - 1
            scratch[m, 1] = pyclip((u[lo[r] + n - 1] - start[r]) / span[r], 0.0, 1.0)
            m += 1
        chord = np.hypot(p3[r, 0] - p0[r, 0], p3[r, 1] - p0[r, 1])
        bound = 4.0 * chord + 1.0
        c = cubic[r]
        for d in range(2):
            c[0, d] = c[1, d] = p0[r, d]
            c[3, d] = c[2, d] = p3[r, d]
        k = _coefficients(c)  # the chord (the first solve does not use it)
        for step in range(steps + 1):
            # the first solve minimises the distances to the points at their parameters; the later ones the
            # distances along the curve's normal at the points' feet (plus TANGENTIAL times the rest), which
            # converges in a few steps where the first alone crawls
            m11 = m12 = m22 = r1 = r2 = 0.0
            for i in range(m):
                t = scratch[i, 1]
                q = lo[r] + np.int64(scratch[i, 0])
                s = 1.0 - t
                b0 = s * s * s
                b1 = 3.0 * s * s * t
                b2 = 3.0 * s * t * t
                b3 = t * t * t
                restx = points[q, 0] - p0[r, 0] * (b0 + b1) - p3[r, 0] * (b2 + b3)
                resty = points[q, 1] - p0[r, 1] * (b0 + b1) - p3[r, 1] * (b2 + b3)
                a1x, a1y = d0[r, 0] * b1, d0[r, 1] * b1
                a2x, a2y = -d1[r, 0] * b2, -d1[r, 1] * b2
                if step == 0:
                    m11 += a1x * a1x + a1y * a1y
                    m12 += a1x * a2x + a1y * a2y
                    m22 += a2x * a2x + a2y * a2y
                    r1 += a1x * restx + a1y * resty
                    r2 += a2x * restx + a2y * resty
                else:
                    e0x = k[8]
                    e1x = k[9]
                    e2x = k[10]
                    e0y = k[11]
                    e1y = k[12]
                    e2y = k[13]
                    tx = s * s * e0x + 2.0 * s * t * e1x + t * t * e2x
                    ty = s * s * e0y + 2.0 * s * t * e1y + t * t * e2y
                    norm = np.hypot(tx, ty)
                    if norm > 0:
                        tx, ty = tx / norm, ty / norm
                    else:
                        tx, ty = 1.0, 0.0
                    nx, ny = -ty, tx
                    an1, at1 = a1x * nx + a1y * ny, a1x * tx + a1y * ty
                    an2, at2 = a2x * nx + a2y * ny, a2x * tx + a2y * ty
                    rn, rt = restx * nx + resty * ny, restx * tx + resty * ty
                    m11 += an1 * an1 + TANGENTIAL * at1 * at1
                    m12 += an1 * an2 + TANGENTIAL * at1 * at2
                    m22 += an2 * an2 + TANGENTIAL * at2 * at2
                    r1 += an1 * rn + TANGENTIAL * at1 * rt
                    r2 += an2 * rn + TANGENTIAL * at2 * rt
            if step == 0:
                m11 += 1e-9
                m22 += 1e-9
            else:  # damped towards the previous lengths (the normal distances alone do not fix them on a line)
                mu = DAMPING * (m11 + m22) + 1e-9
                m11 += mu
                m22 += mu
                r1 += mu * handles[r, 0]
                r2 += mu * handles[r, 1]
            det = m11 * m22 - m12 * m12
            a = pyclip((m22 * r1 - m12 * r2) / det, -bound, bound)
            b = pyclip((m11 * r2 - m12 * r1) / det, -bound, bound)
            handles[r, 0], handles[r, 1] = a, b
            for d in range(2):
                c[1, d] = p0[r, d] + a * d0[r, d]
                c[2, d] = p3[r, d] - b * d1[r, d]
            k = _coefficients(c)
            if step == steps:
                break
            for i in range(m):
                q = lo[r] + np.int64(scratch[i, 0])
                t = _newton(k, points[q, 0], points[q, 1], scratch[i, 1])
                scratch[i, 1] = _newton(k, points[q, 0], points[q, 1], t)
        # every covered point: parameter interpolated between the fitted ones, one Newton step, distance (until
        # the run can no longer qualify: its excess or drift above ``limits``)
        worst, far, total = -np.inf, 0.0, 0.0
        i = np.int64(0)
        for j in range(n):
            if worst > limits[0] or far > limits[1]:
                break
            while i + 1 < m and scratch[i + 1, 0] < j:
                i += 1
            if i + 1 < m and scratch[i + 1, 0] > scratch[i, 0]:
                w = (j - scratch[i, 0]) / (scratch[i + 1, 0] - scratch[i, 0])
                t = scratch[i, 1] + pyclip(w, 0.0, 1.0) * (scratch[i + 1, 1] - scratch[i, 1])
            else:
                t = scratch[i, 1]
            q = lo[r] + j
            t = _newton(k, points[q, 0], points[q, 1], t)
            t_out[offsets[r] + j] = t
            s = 1.0 - t  # the point at t: Bernstein weights of the control points in k
            b0 = s * s * s
            b1 = 3.0 * s * s * t
            b2 = 3.0 * s * t * t
            b3 = t * t * t
            px = b0 * k[0] + b1 * k[1] + b2 * k[2] + b3 * k[3]
            py = b0 * k[4] + b1 * k[5] + b2 * k[6] + b3 * k[7]
            gx, gy = px - points[q, 0], py - points[q, 1]
            if t <= 0.0 or t >= 1.0:
                k0, k1 = (0, 1) if t <= 0.0 else (2, 3)
                dx, dy = c[k1, 0] - c[k0, 0], c[k1, 1] - c[k0, 1]
                length = np.hypot(dx, dy)
                dist = abs(gx * dy - gy * dx) / length if length > 0 else np.hypot(gx, gy)
                worst = pymax(worst, dist - tol[q])
            else:  # the distance itself only where it may raise the largest excess (see SURE)
                reach = worst + tol[q]
                if not (reach > 0.0 and gx * gx + gy * gy < SURE * (reach * reach)):
                    worst = pymax(worst, np.hypot(gx, gy) - tol[q])
            off = np.hypot(px - fitted[q, 0], py - fitted[q, 1])
            far = pymax(far, off)
            total += off * off
        excess[r], drift[r], spread[r] = worst, far, total


def fit_runs(p0, p3, d0, d1, lo, count, points, u, start, span, tol, fitted, steps, fit_points,
             limits=(np.inf, np.inf)):
    """Per run (rows of ``p0``, ``p3``, ``d0``, ``d1``, ``lo``, ``count``, ``start``, ``span``): the cubic
    (r, 4, 2), its handle lengths (r, 2), the parameters of its ``count`` contour points from ``lo`` (grouped by
    run), the largest excess of their distances over ``tol``, the largest and the summed squared distance of
    their curve points from ``fitted`` (the fitted curve at the same contour points). ``limits = (excess,
    drift)``: a run stops measuring its points once its excess or drift so far exceeds them (it cannot
    qualify then): its excess or drift is still above the limit, its parameters from there on and its spread are
    not measured."""
    f = lambda a: np.ascontiguousarray(a, dtype=np.float64)  # noqa: E731
    count = np.ascontiguousarray(count, dtype=np.int64)
    r = count.shape[0]
    offsets = np.zeros(r, np.int64)
    if r:
        offsets[1:] = np.cumsum(count)[:-1]
    total = int(count.sum())
    scratch = np.empty((int(count.max()) + 2 if r else 2, 2))
    cubic, handles = np.empty((r, 4, 2)), np.empty((r, 2))
    t_out = np.empty(total)
    excess, drift, spread = np.empty(r), np.empty(r), np.empty(r)
    _fit_runs_into(f(p0), f(p3), f(d0), f(d1), np.ascontiguousarray(lo, dtype=np.int64), count, offsets, f(points),
                   f(u), f(start), f(span), f(tol), f(fitted), int(steps), int(fit_points),
                   np.array(limits, dtype=np.float64), scratch, cubic, handles, t_out, excess, drift, spread)
    return cubic, handles, offsets, t_out, excess, drift, spread


_WARM = []


def warm_up():
    """Compile (empty cache) or load the kernel once per process (see :func:`._kernels.warm_up`)."""
    if _WARM:
        return
    pts = np.column_stack([np.linspace(0.0, 3.0, 4), np.zeros(4)])
    one = np.array([[0.0, 0.0]]), np.array([[3.0, 0.0]]), np.array([[1.0, 0.0]]), np.array([[1.0, 0.0]])
    fit_runs(*one, np.array([0]), np.array([4]), pts, np.arange(4.0), np.array([0.0]), np.array([3.0]),
             np.full(4, 0.8), pts, 1, 32)
    _WARM.append(True)
