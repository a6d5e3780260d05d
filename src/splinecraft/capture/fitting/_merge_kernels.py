"""Compiled passes of the segment merging (:mod:`.merge`, docs/capture.md §12, "Merged segments"): the fitted
segments cut at their extrema with the pieces' tangents, turns and joins (:func:`prepare`), the candidate runs
fitted, checked and grown (:func:`candidates`), and the dynamic programme that picks the fewest of them
(:func:`choose`). Compiled (numba, cached on disk like :mod:`._kernels`); the wrappers allocate every output.

Per run the cubic keeps the run's end points ``p0``, ``p3`` and the handle directions ``d0``, ``d1``; its two
handle lengths solve the 2 x 2 least-squares problem on about ``fit_points`` of the run's contour points (evenly
spread, both ends included) at their current parameters, followed by a foot-point Newton step of those
parameters, ``steps`` times. Every covered point then gets its parameter interpolated between the fitted ones
and one Newton step, and its distance to the cubic (to the tangent line at the run's end where its foot lies
beyond it: the G1 neighbour continues along that line), computed only where it may raise the run's largest
excess so far (:data:`SURE`) (:func:`_fit_run`).

Every value is computed by the arithmetic of the numpy formulation these passes replaced, in its order: sums in
the order of their terms (``numpy.bincount``, ``numpy.cumsum``), ``numpy.power(s, 3)`` as ``s ** 3.0`` (the C
library's ``pow`` in both), the turns ``|angle(exp(i x))|`` as ``|atan2(sin x, cos x)|`` (the C library's
``cexp`` of a pure imaginary number is ``cos x + i sin x``); the 3 x 3 solves of :func:`prepare`'s parabolas stay
``numpy.linalg.solve`` (LAPACK) between the passes. The tests pin each pass to that formulation bit for bit.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._jit import HELPER_OPTIONS as _HELPER, JIT_OPTIONS, compact, pyclip, pymax, pymin

__all__ = ["prepare", "candidates", "choose", "warm_up", "TANGENTIAL"]

#: Weight of the tangential part of the residuals after the first solve (the normal part has weight 1): a
#: little of it keeps the solve well posed where the points are nearly straight.
TANGENTIAL = 0.0
#: Damping of the later solves towards the previous handle lengths, relative to the normal matrix's trace.
DAMPING = 1e-3
#: A point's squared distance below ``SURE`` times the square of a bound puts its distance (``numpy.hypot``, within
#: an ulp or two of the rounded square root) below that bound for certain, so :func:`_fit_run` computes the
#: distance only where it may raise a running maximum: the maximum is bit for bit the same.
SURE = 1.0 - 1e-12
#: Room for the parameters of the qualifying runs' points that :func:`candidates` allocates first, per contour
#: point (and :data:`T_ROOM_EXTRA` more): where the runs need more, the pass runs once more with what they need
#: (the yardstick's merges need up to 11.9 and 14.3 per point on ``shapes/`` and ``shapes2/``; a second pass costs
#: the whole pass again).
T_ROOM = 24
T_ROOM_EXTRA = 256


@njit(**_HELPER)
def _coefficients(c):
    """The control points of the cubic ``c`` (x then y) and the differences of its derivatives, the values
    the point of :func:`_fit_run` and :func:`_newton` take (computed once per cubic instead of once per
    point). Read as ``float``: the same values, and interpreted (:mod:`.._interpreted`) the arithmetic of
    :func:`_newton` then runs on Python floats, about 3x faster than on numpy's scalars (compiled, ``float`` of a
    double is no instruction)."""
    c0x, c1x, c2x, c3x = float(c[0, 0]), float(c[1, 0]), float(c[2, 0]), float(c[3, 0])
    c0y, c1y, c2y, c3y = float(c[0, 1]), float(c[1, 1]), float(c[2, 1]), float(c[3, 1])
    e0x, e1x, e2x = c1x - c0x, c2x - c1x, c3x - c2x
    e0y, e1y, e2y = c1y - c0y, c2y - c1y, c3y - c2y
    return (c0x, c1x, c2x, c3x, c0y, c1y, c2y, c3y, e0x, e1x, e2x, e0y, e1y, e2y,
            e1x - e0x, e2x - e1x, e1y - e0y, e2y - e1y)


@njit(**_HELPER)
def _newton(k, qx, qy, t):
    """One foot-point Newton step of ``(B(t) - q) . B'(t) = 0`` on the cubic of coefficients ``k``
    (:func:`_coefficients`), clipped to [0, 1]. Callers pass ``qx``, ``qy`` and ``t`` as ``float`` (see
    :func:`_coefficients`)."""
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


@njit(**dict(_HELPER, forceinline=False))
def _fit_run(p0x, p0y, p3x, p3y, d0x, d0y, d1x, d1y, lo, n, points, u, start, span, tol, fitted, steps, fit_points,
             limit_excess, limit_drift, scratch, c, t_out):
    """One run: the cubic into ``c`` (4, 2) from ``(p0x, p0y)`` to ``(p3x, p3y)``, its handles along ``d0`` and
    ``d1``, fitted to the ``n`` contour points from ``lo`` whose parameters ``u`` map to [0, 1] by ``start`` and
    ``span``; the points' parameters on it into ``t_out[:n]``. Returns the handle lengths, the largest excess of
    the points' distances over ``tol``, the largest and the summed squared distance of their curve points from
    ``fitted``; the points stop being measured once the excess or drift so far exceeds its limit (the run cannot
    qualify then: its excess or drift is above the limit, its later parameters and its spread are not measured).
    ``scratch``: (n + 2, 2) floats at least. Called, not inlined: inlined into :func:`_candidates_into` it was
    compiled twice (its own code, then the caller's) for the same run time (BENCHMARKS.md, "Session 30: merge
    speed")."""
    stride = pymax(1, n // fit_points)
    m = np.int64(0)  # the fitted points: j = 0, stride, 2 stride, ..., and n - 1
    j = np.int64(0)
    while j < n:
        scratch[m, 0] = j
        scratch[m, 1] = pyclip((u[lo + j] - start) / span, 0.0, 1.0)
        m += 1
        j += stride
    if n > 0 and scratch[m - 1, 0] != n - 1:
        scratch[m, 0] = n - 1
        scratch[m, 1] = pyclip((u[lo + n - 1] - start) / span, 0.0, 1.0)
        m += 1
    chord = np.hypot(p3x - p0x, p3y - p0y)
    bound = 4.0 * chord + 1.0
    c[0, 0] = c[1, 0] = p0x
    c[0, 1] = c[1, 1] = p0y
    c[3, 0] = c[2, 0] = p3x
    c[3, 1] = c[2, 1] = p3y
    k = _coefficients(c)  # the chord (the first solve does not use it)
    a = b = 0.0
    p0x, p0y, p3x, p3y = float(p0x), float(p0y), float(p3x), float(p3y)  # as float (see _coefficients)
    d0x, d0y, d1x, d1y = float(d0x), float(d0y), float(d1x), float(d1y)
    for step in range(steps + 1):
        # the first solve minimises the distances to the points at their parameters; the later ones the
        # distances along the curve's normal at the points' feet (plus TANGENTIAL times the rest), which
        # converges in a few steps where the first alone crawls
        m11 = m12 = m22 = r1 = r2 = 0.0
        for i in range(m):
            t = float(scratch[i, 1])
            q = lo + np.int64(scratch[i, 0])
            s = 1.0 - t
            b0 = s * s * s
            b1 = 3.0 * s * s * t
            b2 = 3.0 * s * t * t
            b3 = t * t * t
            restx = points[q, 0] - p0x * (b0 + b1) - p3x * (b2 + b3)
            resty = points[q, 1] - p0y * (b0 + b1) - p3y * (b2 + b3)
            a1x, a1y = d0x * b1, d0y * b1
            a2x, a2y = -d1x * b2, -d1y * b2
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
            r1 += mu * a
            r2 += mu * b
        det = np.float64(m11 * m22 - m12 * m12)  # numpy's division below (0 gives inf or NaN), interpreted too
        a = pyclip((m22 * r1 - m12 * r2) / det, -bound, bound)
        b = pyclip((m11 * r2 - m12 * r1) / det, -bound, bound)
        c[1, 0] = p0x + a * d0x
        c[1, 1] = p0y + a * d0y
        c[2, 0] = p3x - b * d1x
        c[2, 1] = p3y - b * d1y
        k = _coefficients(c)
        if step == steps:
            break
        for i in range(m):
            q = lo + np.int64(scratch[i, 0])
            qx, qy = float(points[q, 0]), float(points[q, 1])
            t = _newton(k, qx, qy, float(scratch[i, 1]))
            scratch[i, 1] = _newton(k, qx, qy, t)
    # every covered point: parameter interpolated between the fitted ones, one Newton step, distance (until
    # the run can no longer qualify: its excess or drift above the limits)
    worst, far, total = -np.inf, 0.0, 0.0
    i = np.int64(0)
    for j in range(n):
        if worst > limit_excess or far > limit_drift:
            break
        while i + 1 < m and scratch[i + 1, 0] < j:
            i += 1
        if i + 1 < m and scratch[i + 1, 0] > scratch[i, 0]:
            w = (j - scratch[i, 0]) / (scratch[i + 1, 0] - scratch[i, 0])
            t = float(scratch[i, 1] + pyclip(w, 0.0, 1.0) * (scratch[i + 1, 1] - scratch[i, 1]))
        else:
            t = float(scratch[i, 1])
        q = lo + j
        qx, qy = float(points[q, 0]), float(points[q, 1])
        t = _newton(k, qx, qy, t)
        t_out[j] = t
        s = 1.0 - t  # the point at t: Bernstein weights of the control points in k
        b0 = s * s * s
        b1 = 3.0 * s * s * t
        b2 = 3.0 * s * t * t
        b3 = t * t * t
        px = b0 * k[0] + b1 * k[1] + b2 * k[2] + b3 * k[3]
        py = b0 * k[4] + b1 * k[5] + b2 * k[6] + b3 * k[7]
        gx, gy = px - qx, py - qy
        tq = float(tol[q])
        if t <= 0.0 or t >= 1.0:
            k0, k1 = (0, 1) if t <= 0.0 else (2, 3)
            dx, dy = c[k1, 0] - c[k0, 0], c[k1, 1] - c[k0, 1]
            length = np.hypot(dx, dy)
            dist = abs(gx * dy - gy * dx) / length if length > 0 else np.hypot(gx, gy)
            worst = pymax(worst, dist - tq)
        else:  # the distance itself only where it may raise the largest excess (see SURE)
            reach = worst + tq
            if not (reach > 0.0 and gx * gx + gy * gy < SURE * (reach * reach)):
                worst = pymax(worst, np.hypot(gx, gy) - tq)
        off = np.hypot(px - float(fitted[q, 0]), py - float(fitted[q, 1]))
        far = pymax(far, off)
        total += off * off
    return a, b, worst, far, total


@njit(**_HELPER)
def _search(u, period, wide, value, right):
    """``numpy.searchsorted(u, value, side="right" if right else "left")``, or where ``wide`` on the three copies
    ``u - period``, ``u``, ``u + period`` one after the other (the contour once more on either side of the seam).
    Callers pass ``wide`` and ``right`` as booleans of no literal value (``numpy.bool_(...)``): each literal would
    compile the helper once more."""
    n = u.shape[0]
    lo = np.int64(0)
    hi = np.int64(3 * n if wide else n)
    while lo < hi:
        mid = (lo + hi) >> 1
        if not wide:
            x = u[mid]
        elif mid < n:
            x = u[mid] - period
        elif mid < 2 * n:
            x = u[mid - n]
        else:
            x = u[mid - 2 * n] + period
        if x < value or (right and x == value):
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(**_HELPER)
def _sort4(t):
    """``t`` (4 values) sorted in place as ``numpy.sort`` does: ascending, NaN last."""
    for i in range(1, 4):
        x = t[i]
        j = i
        while j > 0 and (x < t[j - 1] or (t[j - 1] != t[j - 1] and x == x)):
            t[j] = t[j - 1]
            j -= 1
        t[j] = x


@njit(**_HELPER)
def _unit_into(x, y, out, at):
    """``(x, y)`` over its length (``numpy.hypot``; as it is where that is 0) into ``out[at], out[at + 1]``."""
    length = np.hypot(x, y)
    if not length > 0:
        length = 1.0
    out[at] = x / length
    out[at + 1] = y / length


# Columns of the pieces' table of :func:`prepare` (one row a piece, rows k + 1): the cubic (x, y of its four control
# points), its parameter interval, its unit end tangents, the turn of the pieces before it, the new direction of
# its start join (:func:`candidates`).
_BEZ, _START, _END, _HEAD, _TAIL, _TURN, _DIRECTION, _PIECE_COLUMNS = 0, 8, 9, 10, 12, 14, 15, 17
# Rows of the pieces' integers: the fitted segment of each, its piece between corners, whether the join at its
# start is inside a piece; per interior join its piece and how many points its parabola's window holds.
_ORIGIN, _SEG_PIECE, _INTERIOR, _JOIN, _COUNT = 0, 1, 2, 3, 4
# Columns of the joins' table: the half-width of the window, the parabola's slope b (:func:`.merge.merge_segments`
# puts it), its normal equations (3 x 3, then 3).
_REACH, _SLOPE, _M, _RHS, _JOIN_COLUMNS = 0, 1, 2, 11, 14
# Rows of the candidates' integers (their floats: the spread, then the cubic).
_FIRST, _LENGTH, _S0, _S1, _REFIT, _T_COUNT, _T_START = 0, 1, 2, 3, 4, 5, 6


@njit(**JIT_OPTIONS)
def _prepare_into(fit_bez, fit_starts, fit_ends, corner_par, points, u, settings, roots, pieces, ints, joins):
    """:func:`prepare` into its tables; returns the pieces and the interior joins counted."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    min_gap, piece_count, cornered = settings[0], np.int64(settings[1]), settings[2] > 0
    period, window = settings[3], settings[4]
    k = np.int64(0)
    for i in range(fit_bez.shape[0]):
        c = fit_bez[i]
        h = fit_ends[i] - fit_starts[i]
        # where dx/dt or dy/dt is zero: the roots of a t^2 + b t + c of the derivative's Bernstein differences
        for d in range(2):
            d0, d1, d2 = c[1, d] - c[0, d], c[2, d] - c[1, d], c[3, d] - c[2, d]
            a, b, cc = d0 - 2 * d1 + d2, 2 * (d1 - d0), d0
            disc = b * b - 4 * a * cc
            root = np.sqrt(disc) if disc >= 0 else np.nan
            if abs(a) > 1e-12 * (abs(b) + abs(cc) + 1e-300):
                roots[d] = (-b + -1.0 * root) / (2 * a)
                roots[2 + d] = (-b + 1.0 * root) / (2 * a)
            else:
                roots[d] = np.nan
                roots[2 + d] = -cc / b
        low = pymin(min_gap / pymax(h, 1e-12), 0.5)
        for j in range(4):
            if not (roots[j] > low and roots[j] < 1 - low):
                roots[j] = np.nan
        _sort4(roots)
        previous = -np.inf
        for j in range(4):  # cuts closer than low to the one before: one
            x = roots[j]
            if not x - previous > low:
                roots[j] = np.nan
            previous = x
        _sort4(roots)
        cuts = np.int64(0)
        while cuts < 4 and roots[cuts] == roots[cuts]:
            cuts += 1
        ta = 0.0
        for p in range(cuts + 1):  # the piece [ta, tb] of the segment: its end points and derivatives there
            tb = roots[p] if p < cuts else 1.0
            width = tb - ta
            for d in range(2):
                e0, e1, e2 = c[1, d] - c[0, d], c[2, d] - c[1, d], c[3, d] - c[2, d]
                for at in range(2):  # the start, then the end
                    t = tb if at else ta
                    s = 1.0 - t
                    point = s ** 3.0 * c[0, d] + 3 * s * s * t * c[1, d] + 3 * s * t * t * c[2, d] + t ** 3.0 * c[3, d]
                    speed = 3 * (s * s * e0 + 2 * s * t * e1 + t * t * e2)
                    if at:
                        pieces[k, _BEZ + 4 + d] = point - width * speed / 3.0
                        pieces[k, _BEZ + 6 + d] = c[3, d] if p == cuts else point
                    else:
                        pieces[k, _BEZ + d] = c[0, d] if p == 0 else point
                        pieces[k, _BEZ + 2 + d] = point + width * speed / 3.0
            pieces[k, _START] = fit_starts[i] + ta * h
            pieces[k, _END] = fit_starts[i] + tb * h
            ints[_ORIGIN, k] = i
            ta = tb
            k += 1
    pieces[0, _TURN] = 0.0
    for i in range(k):
        row = pieces[i]
        # the unit tangents at the ends (the next control point where the first coincides)
        x, y = row[2] - row[0], row[3] - row[1]
        if not np.hypot(x, y) > 1e-9:
            x, y = row[4] - row[0], row[5] - row[1]
        _unit_into(x, y, row, np.int64(_HEAD))
        x, y = row[6] - row[4], row[7] - row[5]
        if not np.hypot(x, y) > 1e-9:
            x, y = row[6] - row[2], row[7] - row[3]
        _unit_into(x, y, row, np.int64(_TAIL))
        # the turn of the control polygon (its two angles, each in [-pi, pi]), summed along the pieces
        a0 = math.atan2(row[3] - row[1], row[2] - row[0])
        a1 = math.atan2(row[5] - row[3], row[4] - row[2])
        a2 = math.atan2(row[7] - row[5], row[6] - row[4])
        x, y = a1 - a0, a2 - a1
        pieces[i + 1, _TURN] = row[_TURN] + (abs(math.atan2(math.sin(x), math.cos(x)))
                                             + abs(math.atan2(math.sin(y), math.cos(y))))
        # the piece between corners of the piece's start (numpy.searchsorted(corner_par, start, "right") - 1)
        lo = np.int64(0)
        hi = np.int64(corner_par.shape[0])
        while lo < hi:
            mid = (lo + hi) >> 1
            if corner_par[mid] <= row[_START]:
                lo = mid + 1
            else:
                hi = mid
        ints[_SEG_PIECE, i] = pymin(pymax(lo - 1, 0), piece_count - 1)
    # the joins inside a piece (the seam of an outline without corners is one too) and their parabolas' sums
    ints[_INTERIOR, 0] = ints[_INTERIOR, k] = not cornered
    for i in range(1, k):
        ints[_INTERIOR, i] = ints[_SEG_PIECE, i] == ints[_SEG_PIECE, i - 1]
    r = np.int64(0)
    n = points.shape[0]
    wide, left, right = np.bool_(not cornered), np.bool_(False), np.bool_(True)
    for j in range(k):
        if not ints[_INTERIOR, j]:
            continue
        before = j - 1 if j > 0 else k - 1
        start = pieces[j, _START]
        reach = window * pymax(pieces[j, _END] - start, pieces[before, _END] - pieces[before, _START])
        low_b, high_b = -np.inf, np.inf
        if cornered:
            low_b, high_b = corner_par[ints[_SEG_PIECE, j]], corner_par[ints[_SEG_PIECE, j] + 1]
        lo = _search(u, period, wide, pymax(start - reach, low_b), left)
        hi = _search(u, period, wide, pymin(start + reach, high_b), right)
        scale = pymax(reach, 1.0)
        s1 = s2 = s3 = s4 = y0 = y1 = y2 = 0.0
        px, py = pieces[j, _BEZ], pieces[j, _BEZ + 1]
        tx, ty = pieces[j, _HEAD], pieces[j, _HEAD + 1]
        for q in range(lo, hi):
            at = q
            while at >= n:
                at -= n
            rx, ry = points[at, 0] - px, points[at, 1] - py
            x = (rx * tx + ry * ty) / scale
            y = ry * tx - rx * ty
            x2 = x * x
            s1 += x
            s2 += x2
            s3 += x2 * x
            s4 += x2 * x2
            y0 += y
            y1 += y * x
            y2 += y * x2
        count = pymax(hi - lo, 0)
        row = joins[r]
        row[_REACH], row[_SLOPE] = reach, 0.0
        row[_M], row[_M + 1], row[_M + 2] = count + 1e-9, s1, s2
        row[_M + 3], row[_M + 4], row[_M + 5] = s1, s2 + 1e-9, s3
        row[_M + 6], row[_M + 7], row[_M + 8] = s2, s3, s4 + 1e-9
        row[_RHS], row[_RHS + 1], row[_RHS + 2] = y0, y1, y2
        ints[_JOIN, r] = j
        ints[_COUNT, r] = count
        r += 1
    return k, r


@njit(**_HELPER)
def _keep(at, f, size, c, cand_i, cand_f):
    """Candidate ``at``: the fitted curve as it was from piece ``f`` on, ``size`` pieces (the cubic ``c`` as a row
    of eight; states 0, 0; cost 0; its points keep their parameters)."""
    cand_i[_FIRST, at], cand_i[_LENGTH, at], cand_i[_S0, at], cand_i[_S1, at] = f, size, 0, 0
    cand_i[_REFIT, at], cand_i[_T_COUNT, at], cand_i[_T_START, at] = 0, 0, 0
    cand_f[at, 0] = 0.0
    for e in range(8):
        cand_f[at, 1 + e] = c[e]


@njit(**JIT_OPTIONS)
def _candidates_into(pieces, ints, joins, fit_bez, points, u, tol, fitted, settings, scratch, t_scratch, c, state,
                     cand_i, cand_f, t_values):
    """:func:`candidates` into its tables; returns the candidates and their points' parameters counted (written
    where the tables have room)."""
    tolerance, max_turn, margin = settings[0], settings[1], settings[2]
    max_run, misses, steps, fit_points = np.int64(settings[3]), settings[4], np.int64(settings[5]), \
        np.int64(settings[6])
    k = np.int64(settings[7])
    # the new direction of each join with a parabola of six points or more (the fitted curve's direction elsewhere)
    for i in range(k):
        pieces[i, _DIRECTION], pieces[i, _DIRECTION + 1] = pieces[i, _HEAD], pieces[i, _HEAD + 1]
    for r in range(joins.shape[0]):
        if ints[_COUNT, r] >= 6:
            j = ints[_JOIN, r]
            slope = joins[r, _SLOPE] / pymax(joins[r, _REACH], 1.0)
            tx, ty = pieces[j, _HEAD], pieces[j, _HEAD + 1]
            _unit_into(tx + slope * -ty, ty + slope * tx, pieces[j], np.int64(_DIRECTION))
    # the fitted segments as they were: their pieces, and each whole where it was cut (states 0, 0; cost 0)
    count = np.int64(0)
    for i in range(k):
        _keep(count, i, np.int64(1), pieces[i], cand_i, cand_f)
        count += 1
    i = np.int64(0)
    while i < k:
        size = np.int64(1)
        while i + size < k and ints[_ORIGIN, i + size] == ints[_ORIGIN, i]:
            size += 1
        if size > 1:
            _keep(count, i, size, fit_bez[ints[_ORIGIN, i]], cand_i, cand_f)
            count += 1
        i += size
    # the runs, one length at a time, each start in every state its two end joins may take, while the start stays
    # in its piece and turn and has not failed more than ``misses`` lengths in a row (length 1 always passes)
    t_used = np.int64(0)
    narrow, right = np.bool_(False), np.bool_(True)
    alive, missed, passed = state[0], state[1], state[2]
    for i in range(k):
        alive[i] = 1
        missed[i] = 0
    for size in range(1, pymin(max_run, k) + 1):
        for i in range(k):
            last = i + size - 1
            alive[i] = (alive[i] != 0 and missed[i] <= misses and last < k
                        and ints[_SEG_PIECE, last] == ints[_SEG_PIECE, i]
                        and pieces[last + 1, _TURN] - pieces[i, _TURN] <= max_turn)
            passed[i] = size == 1
        for ends in range(4):  # the end states (a, b): 0 the fitted curve's direction, 1 the join's new one
            a, b = ends >> 1, ends & 1
            for i in range(k):
                if not alive[i]:
                    continue
                last = i + size - 1
                head_join, tail_join = ints[_INTERIOR, i] != 0, ints[_INTERIOR, last + 1] != 0
                # an end at a join takes the new direction if asked (a == 1), and a longer run wherever it may; a
                # single segment in states (0, 0) is the segment as it was
                if size == 1:
                    if ends == 0 or (a == 1 and not head_join) or (b == 1 and not tail_join):
                        continue
                elif head_join != (a == 1) or tail_join != (b == 1):
                    continue
                head, tail = pieces[i], pieces[last + 1 if last + 1 < k else 0]
                d0x, d0y = (head[_DIRECTION], head[_DIRECTION + 1]) if a else (head[_HEAD], head[_HEAD + 1])
                d1x, d1y = (tail[_DIRECTION], tail[_DIRECTION + 1]) if b else (pieces[last, _TAIL],
                                                                               pieces[last, _TAIL + 1])
                start, end = head[_START], pieces[last, _END]
                lo = _search(u, 0.0, narrow, start, narrow)
                n = pymax(_search(u, 0.0, narrow, end, right) - lo, 0)
                ha, hb, excess, drift, cost = _fit_run(head[_BEZ], head[_BEZ + 1], pieces[last, _BEZ + 6],
                                                       pieces[last, _BEZ + 7], d0x, d0y, d1x, d1y, lo, n, points, u,
                                                       start, end - start, tol, fitted, steps, fit_points, -margin,
                                                       tolerance, scratch, c, t_scratch)
                # within the tolerance of the points (less the margin) and of the fitted curve, both handles
                # positive, at least four points
                chord = np.hypot(c[3, 0] - c[0, 0], c[3, 1] - c[0, 1])
                if not (excess + margin <= 0 and drift <= tolerance and ha > 1e-3 * chord and hb > 1e-3 * chord
                        and n >= 4):
                    continue
                passed[i] = 1
                if count < cand_i.shape[1] and t_used + n <= t_values.shape[0]:
                    cand_i[_FIRST, count], cand_i[_LENGTH, count], cand_i[_S0, count], cand_i[_S1, count] = \
                        i, size, a, b
                    cand_i[_REFIT, count], cand_i[_T_COUNT, count], cand_i[_T_START, count] = 1, n, t_used
                    cand_f[count, 0] = cost
                    for e in range(4):
                        cand_f[count, 1 + 2 * e], cand_f[count, 2 + 2 * e] = c[e, 0], c[e, 1]
                    for j in range(n):
                        t_values[t_used + j] = t_scratch[j]
                count += 1
                t_used += n
        for i in range(k):
            missed[i] = 0 if passed[i] else missed[i] + 1
    return count, t_used


@njit(**JIT_OPTIONS)
def _choose_into(cand_i, cand_f, count, allowed, periodic, order, table, totals, chosen):
    """:func:`choose` into ``chosen``; returns how many were chosen."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    k = chosen.shape[0]
    # table rows: 0 the allowed candidates by their end, in their order (table[0, j - 1] .. table[0, j] those
    # ending at j); 1 + s the candidate that ends a chain best at each join in state s, 3 + s its segments (totals:
    # its cost)
    for j in range(k + 2):
        table[0, j] = 0
    for c in range(count):
        if allowed[c]:
            table[0, cand_i[_FIRST, c] + cand_i[_LENGTH, c] + 1] += 1
    for j in range(1, k + 2):
        table[0, j] += table[0, j - 1]
    for c in range(count):
        if allowed[c]:
            end = cand_i[_FIRST, c] + cand_i[_LENGTH, c]
            order[table[0, end]] = c
            table[0, end] += 1
    never = np.int64(1) << 60
    found = np.int64(-1)
    found_count, found_total, found_size = never, 0.0, np.int64(0)
    for seam in range(2 if periodic else 1):
        for j in range(k + 1):
            for s in range(2):
                table[1 + s, j], table[3 + s, j], totals[s, j] = -1, never, 0.0
        table[3 + seam, 0], totals[seam, 0] = 0, 0.0
        for j in range(1, k + 1):
            for at in range(table[0, j - 1], table[0, j]):
                c = order[at]
                f, s = cand_i[_FIRST, c], cand_i[_S0, c]
                size = table[3 + s, f]
                if size == never:
                    continue
                size += 1
                total = totals[s, f] + cand_f[c, 0]
                s = cand_i[_S1, c]
                if size < table[3 + s, j] or (size == table[3 + s, j] and total < totals[s, j]):
                    table[1 + s, j], table[3 + s, j], totals[s, j] = c, size, total
        size, total = table[3 + seam, k], totals[seam, k]
        if size == never or (found >= 0 and not (size < found_count or (size == found_count
                                                                          and total < found_total))):
            continue
        found, found_count, found_total = seam, size, total
        j, s, size = k, seam, np.int64(0)
        while j > 0:
            c = table[1 + s, j]
            chosen[size] = c
            size += 1
            j, s = cand_i[_FIRST, c], cand_i[_S0, c]
        for e in range(size // 2):
            chosen[e], chosen[size - 1 - e] = chosen[size - 1 - e], chosen[e]
        found_size = size
    return found_size if found >= 0 else np.int64(-1)


def prepare(fit_bez, fit_starts, fit_ends, min_gap, corner_par, piece_count, cornered, points, u, period, window):
    """The fitted segments ``fit_bez`` on ``[fit_starts, fit_ends]`` cut where their tangent is horizontal or
    vertical (at least ``min_gap`` parameter units from either end of a segment; cuts closer than that to the one
    before: one), and per piece and join what the candidates need (:func:`.merge.merge_segments`). Returns a
    dict: the pieces ``bez`` (k, 4, 2), ``starts``, ``ends``, and the tables :func:`candidates` reads: per piece
    the fitted segment it comes from, its unit end tangents, the turn of the pieces' control polygons summed from
    the first, its piece between corners (by ``corner_par``), whether its start join is inside a piece (with
    ``cornered`` false the seam is); per interior join the half-width of its parabola's window (``window`` times
    the longer parameter length beside it, within its piece; an outline without corners measures around its seam,
    ``period``) and the normal equations ``m``, ``rhs`` of that parabola ``y = a + b x + c x^2`` in the frame of
    the join's tangent, x over ``max(reach, 1)``, ``good`` where six points or more are in the window; the
    caller puts each good parabola's ``b`` into ``slope``."""
    size = 5 * fit_bez.shape[0]
    pieces, ints = np.empty((size + 1, _PIECE_COLUMNS)), np.empty((5, size + 1), np.int64)
    joins = np.empty((size, _JOIN_COLUMNS))
    settings = np.array([min_gap, piece_count, 1.0 if cornered else 0.0, period, window])
    k, r = _prepare_into(fit_bez, fit_starts, fit_ends, corner_par, points, u, settings, np.empty(4), pieces, ints,
                         joins)
    return {"bez": pieces[:k, _BEZ:_BEZ + 8].reshape(k, 4, 2), "starts": pieces[:k, _START],
            "ends": pieces[:k, _END], "origin": ints[_ORIGIN, :k], "head": pieces[:k, _HEAD:_HEAD + 2],
            "tail": pieces[:k, _TAIL:_TAIL + 2], "turn": pieces[:k + 1, _TURN], "pieces": pieces, "ints": ints, "joins": joins[:r],
            "m": joins[:r, _M:_M + 9].reshape(r, 3, 3), "rhs": joins[:r, _RHS:_RHS + 3].reshape(r, 3, 1),
            "good": ints[_COUNT, :r] >= 6, "slope": joins[:r, _SLOPE], "k": k}


def candidates(prepared, fit_bez, points, u, tol, fitted, tolerance, max_run, max_turn, misses, steps, fit_points,
               margin):
    """Every qualifying run of the pieces of :func:`prepare` (:func:`.merge.merge_segments`, step 3) with the
    direction states of its two end joins (0: the fitted curve's direction, 1: the join's new one, only at
    interior joins: the parabola's direction ``(1, b)`` in the frame of the fitted curve's tangent, ``b`` from
    ``prepared["slope"]``, where the parabola is ``good``; the fitted curve's direction elsewhere), grown one
    segment at a time from every start while it stays in its piece, turns by at most ``max_turn`` and has failed
    at most ``misses`` lengths in a row (one of its states qualifies), up to ``max_run`` segments. A run
    qualifies when its cubic (:func:`_fit_run`, ``steps`` and ``fit_points``) stays within ``tol`` less
    ``margin`` of its contour points and within ``tolerance`` of the ``fitted`` curve there, with both handles
    positive (above 1e-3 times the chord) and four points or more. Candidates ``0 .. k - 1`` are the pieces as
    they were (states 0, 0; cost 0), then each fitted segment cut into pieces, whole; the others follow by run
    length, then end states ``(s0, s1)`` in the order (0, 0), (0, 1), (1, 0), (1, 1), then start. Returns a
    dict: per candidate ``first``, ``length``, ``s0``, ``s1``, ``spread`` (the summed squared distance from the
    fitted curve at its points: the cost), ``cubic``, ``refit`` (not a fitted segment as it was), ``t_count``,
    ``t_start`` (its points' parameters on the cubic are ``t[t_start: t_start + t_count]``), the tables
    ``cand_i`` and ``cand_f`` :func:`choose` reads, and ``direction`` (per join)."""
    k, n = prepared["k"], points.shape[0]
    size = k + fit_bez.shape[0] + (min(max_run, k) + 2) * k  # the singles of three states, then one a start
    cand_i, cand_f = np.empty((7, size), np.int64), np.empty((size, 9))
    settings = np.array([tolerance, max_turn, margin, max_run, misses, steps, fit_points, k], dtype=np.float64)
    room = T_ROOM * n + T_ROOM_EXTRA
    flat = fit_bez.reshape(fit_bez.shape[0], 8)  # a row per segment, as the pieces' table has them
    while True:
        t = np.empty(room)
        count, used = _candidates_into(prepared["pieces"], prepared["ints"], prepared["joins"], flat, points, u,
                                       tol, fitted, settings, np.empty((n + 2, 2)), np.empty(n), np.empty((4, 2)),
                                       np.empty((3, k), np.int64), cand_i, cand_f, t)
        if used <= room:
            break
        room = used  # the parameters did not all fit: once more with room for them
    pieces = prepared["pieces"]
    return {"first": cand_i[_FIRST, :count], "length": cand_i[_LENGTH, :count], "s0": cand_i[_S0, :count],
            "s1": cand_i[_S1, :count], "spread": cand_f[:count, 0], "cubic": cand_f[:count, 1:].reshape(count, 4, 2),
            "refit": cand_i[_REFIT, :count] != 0, "t_count": cand_i[_T_COUNT, :count],
            "t_start": cand_i[_T_START, :count], "t": t[:used], "cand_i": cand_i, "cand_f": cand_f,
            "direction": pieces[:k, _DIRECTION:_DIRECTION + 2]}


def choose(k, cand, allowed, periodic):
    """Fewest segments for the chain of ``k`` segments from the ``allowed`` candidate runs of :func:`candidates`,
    each join in the direction state its two runs agree on (with ``periodic`` the chain's two ends are one join,
    in either state, else state 0), ties broken by the smallest total cost (``spread``), then by the candidates'
    order; the chosen candidates' indices in chain order (:func:`.merge.merge_segments`, step 4)."""
    chosen = np.empty(k, np.int64)
    count = allowed.shape[0]
    size = _choose_into(cand["cand_i"], cand["cand_f"], count, allowed, bool(periodic), np.empty(count, np.int64),
                        np.empty((5, k + 2), np.int64), np.empty((2, k + 1)), chosen)
    return chosen[:size]


_WARM = []


def warm_up():
    """Compile (empty cache) or load the kernels once per process (see :func:`._kernels.warm_up`): the merge of
    an ellipse's four arcs without corners and with two."""
    if _WARM:
        return
    angle = np.linspace(0.0, 2 * np.pi, 40, endpoint=False)
    points = np.column_stack([10 * np.cos(angle), 6 * np.sin(angle)])
    u = np.arange(40.0)
    fit_bez = np.empty((4, 4, 2))
    for i in range(4):
        a, b = angle[10 * i], angle[(10 * i + 10) % 40] + (2 * np.pi if i == 3 else 0.0)
        for e in range(4):
            x = a + (b - a) * e / 3
            fit_bez[i, e] = 10 * np.cos(x), 6 * np.sin(x)
    starts, ends = np.arange(0.0, 40.0, 10.0), np.arange(10.0, 50.0, 10.0)
    for corner_par, pieces, cornered in ((np.array([0.0, 40.0]), 1, False), (np.array([0.0, 20.0, 40.0]), 2, True)):
        prepared = prepare(fit_bez, starts, ends, 2.0, corner_par, pieces, cornered, points, u, 40.0, 0.5)
        cand = candidates(prepared, fit_bez, points, u, np.full(40, 0.8), points, 0.5, 12, 0.8 * np.pi, 2, 4, 32,
                          0.0)
        choose(prepared["k"], cand, np.ones(cand["first"].shape[0], bool), not cornered)
    _WARM.append(True)
