"""Compiled loops of the ``"lsq"`` fit (docs/capture.md §12, "The lsq method" and "Stopping rule").

The per-point work of every knot round -- the cubic B-spline basis at each contour point and the weighted
normal equations it feeds, the spline's values on its knot intervals, one Hoschek parameter correction and
the windowed point-to-polyline distances of the deviation -- is a loop over a few thousand points that numpy
runs as dozens of small array operations per round. These kernels run it as one pass each (numba, compiled
on first use and cached on disk, ``cache=True``). They are the only implementation: every caller in
:mod:`.bspline`, :mod:`.lsq_model` and :mod:`.geometry` goes through them.

Each kernel performs the floating-point operations of the vectorized formulation it replaced, in the same
order (no ``fastmath``: no reassociation, no fused multiply-add), so its results are bit for bit those of
the plain numpy expressions written out in the tests (``tests/test_kernels.py``).
"""
from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["basis_matrix", "normal_equations", "spline_values", "hoschek_update", "windowed_distance", "eval_bezier",
           "interval_samples"]


@njit(cache=True, nogil=True)
def _interval(full, u):
    """``i`` with ``full[i] <= u < full[i + 1]`` (searchsorted right, minus one), clipped to the period
    ``[3, len(full) - 5]``: :func:`~.bspline.interval_index`."""
    i = np.searchsorted(full, u, side="right") - 1
    return min(max(i, 3), full.shape[0] - 5)


@njit(cache=True, nogil=True)
def _basis(full, i, u, out, left, right):
    """The four non-zero cubic B-splines ``N_{i-3} .. N_i`` at ``u`` into ``out`` (Cox-de Boor, operation for
    operation the vectorized recurrence of ``tests/test_kernels.py``); ``left``, ``right``: scratch of 4."""
    for j in range(1, 4):
        left[j] = u - full[i + 1 - j]
        right[j] = full[i + j] - u
    out[0] = 1.0
    for j in range(1, 4):
        saved = 0.0
        for r in range(j):
            denom = right[r + 1] + left[j - r]
            temp = out[r] / (denom if denom > 0 else 1.0)
            value = saved + right[r + 1] * temp
            saved = left[j - r] * temp
            out[r] = value
        out[j] = saved


@njit(cache=True, nogil=True)
def basis_matrix(full, i, u):
    """The (n, 4) non-zero cubic B-splines ``N_{i-3} .. N_i`` at every ``u[j]`` in its interval ``i[j]``."""
    out = np.empty((u.shape[0], 4))
    left, right = np.empty(4), np.empty(4)
    for j in range(u.shape[0]):
        _basis(full, i[j], u[j], out[j], left, right)
    return out


@njit(cache=True, nogil=True)
def normal_equations(full, u, weights, targets, m):
    """Weighted least-squares normal equations of a periodic cubic spline with ``m`` coefficients on the
    full knot vector ``full`` (eq. of :func:`~.bspline.solve_normal`): the cyclic band ``band[k, a] =
    A[a, (a + k) % m]`` (k = 0..3, the pairs ``(r, s)`` of basis functions summed in the order r, then s) and
    the right-hand sides ``rhs`` (m, d), each a sum over the points in their order."""
    n = u.shape[0]
    dims = targets.shape[1]
    rhs = np.zeros((m, dims))
    partial = np.zeros((10, m))  # one running sum per pair (r <= s), as one bincount each
    basis, left, right = np.empty(4), np.empty(4), np.empty(4)
    cols = np.empty(4, np.int64)
    for j in range(n):
        i = _interval(full, u[j])
        _basis(full, i, u[j], basis, left, right)
        w = weights[j]
        for r in range(4):
            cols[r] = (i - 6 + r) % m
        for r in range(4):
            wb = basis[r] * w
            for d in range(dims):
                rhs[cols[r], d] += wb * targets[j, d]
        pair = 0
        for r in range(4):
            wb = basis[r] * w
            for s in range(r, 4):
                partial[pair, cols[r]] += wb * basis[s]
                pair += 1
    band = np.zeros((4, m))
    pair = 0
    for r in range(4):
        for s in range(r, 4):
            for a in range(m):
                band[s - r, a] += partial[pair, a]
            pair += 1
    return band, rhs


@njit(cache=True, nogil=True)
def spline_values(coef, full, m, starts, ends, theta):
    """Values of the periodic spline (coefficients ``coef`` (m, d)) at ``starts[k] + (ends[k] - starts[k]) *
    theta[q]`` for every knot interval ``k`` and fraction ``theta[q]``, evaluated in the interval that holds
    the interval's midpoint: an array (k, len(theta), d) (:func:`~.bspline.bezier_of_intervals`)."""
    count = starts.shape[0]
    q = theta.shape[0]
    dims = coef.shape[1]
    out = np.empty((count, q, dims))
    basis, left, right = np.empty(4), np.empty(4), np.empty(4)
    for k in range(count):
        width = ends[k] - starts[k]
        i = _interval(full, starts[k] + 0.5 * width)
        for t in range(q):
            _basis(full, i, starts[k] + width * theta[t], basis, left, right)
            for d in range(dims):
                out[k, t, d] = (basis[0] * coef[(i - 6) % m, d] + basis[1] * coef[(i - 5) % m, d]
                                + basis[2] * coef[(i - 4) % m, d] + basis[3] * coef[(i - 3) % m, d])
    return out


@njit(cache=True, nogil=True)
def hoschek_update(u, points, bez, starts, ends, piece_of, piece_count, gate):
    """One Newton step of the foot-point equation ``(S(u) - Q) . S'(u) = 0`` per contour point
    (:meth:`~.lsq_model.OutlineRegression._hoschek_step`): the steps ``du`` (clipped to +-2), zero in the
    pieces (``piece_of``, non-decreasing) whose largest residual exceeds ``gate``."""
    n = u.shape[0]
    last = starts.shape[0] - 1
    du = np.empty(n)
    res = np.empty(n)
    rr, d1, d2 = np.empty(2), np.empty(2), np.empty(2)
    for j in range(n):
        seg = min(max(np.searchsorted(starts, u[j], side="right") - 1, 0), last)
        h = ends[seg] - starts[seg]
        theta = (u[j] - starts[seg]) / h
        for d in range(2):
            b0, b1, b2, b3 = bez[seg, 0, d], bez[seg, 1, d], bez[seg, 2, d], bez[seg, 3, d]
            c1 = 3.0 * (b1 - b0)
            c2 = 3.0 * (b0 - 2.0 * b1 + b2)
            c3 = b3 - b0 + 3.0 * (b1 - b2)
            rr[d] = b0 + theta * (c1 + theta * (c2 + theta * c3)) - points[j, d]
            d1[d] = (c1 + theta * (2.0 * c2 + 3.0 * theta * c3)) / h
            d2[d] = (2.0 * c2 + 6.0 * theta * c3) / (h * h)
        speed2 = d1[0] * d1[0] + d1[1] * d1[1]
        den = speed2 + rr[0] * d2[0] + rr[1] * d2[1]
        if not den > 0.1 * speed2:
            den = speed2
        step = -(rr[0] * d1[0] + rr[1] * d1[1]) / max(den, 1e-300)
        du[j] = min(max(step, -2.0), 2.0)
        res[j] = np.hypot(rr[0], rr[1])
    worst = np.full(piece_count, -np.inf)
    for j in range(n):
        worst[piece_of[j]] = max(worst[piece_of[j]], res[j])
    for j in range(n):
        if worst[piece_of[j]] > gate:
            du[j] = 0.0
    return du


@njit(cache=True, nogil=True)
def windowed_distance(points, centre, lo, hi, ax, ay, dx, dy, inverse, window, wrap, clip):
    """Distance from ``points[j]`` to the polyline edges ``centre[j] - window .. centre[j] + window``
    (clipped to ``[lo[j], hi[j]]`` when ``clip``, then modulo ``wrap`` when > 0), exact point-to-segment
    distances on the edge table ``ax, ay, dx, dy, inverse`` (:func:`~.geometry.windowed_distance`)."""
    n = points.shape[0]
    out = np.empty(n)
    for j in range(n):
        best = np.inf
        for offset in range(-window, window + 1):
            e = centre[j] + offset
            if clip:
                e = min(max(e, lo[j]), hi[j])
            if wrap:
                e %= wrap
            px = points[j, 0] - ax[e]
            py = points[j, 1] - ay[e]
            t = (px * dx[e] + py * dy[e]) * inverse[e]
            t = min(max(t, 0.0), 1.0)
            px -= t * dx[e]
            py -= t * dy[e]
            squared = px * px + py * py
            if squared < best:
                best = squared
        out[j] = np.sqrt(best)
    return out


@njit(cache=True, nogil=True)
def _bezier_point(bez, k, theta, out, row):
    """``out[row]`` = the cubic Bézier piece ``bez[k]`` at ``theta`` (Bernstein weights, summed in order)."""
    s = 1.0 - theta
    t2, s2 = theta * theta, s * s
    w0, w1, w2, w3 = s2 * s, 3.0 * theta * s2, 3.0 * t2 * s, t2 * theta
    for d in range(bez.shape[2]):
        out[row, d] = w0 * bez[k, 0, d] + w1 * bez[k, 1, d] + w2 * bez[k, 2, d] + w3 * bez[k, 3, d]


@njit(cache=True, nogil=True)
def eval_bezier(bez, piece, theta):
    """Points of the Bézier pieces ``bez[piece[j]]`` at ``theta[j]`` (:func:`~.geometry.eval_bezier`)."""
    out = np.empty((theta.shape[0], bez.shape[2]))
    for j in range(theta.shape[0]):
        _bezier_point(bez, piece[j], theta[j], out, j)
    return out


@njit(cache=True, nogil=True)
def interval_samples(bez, starts, ends, spacing):
    """Samples of every knot interval's Bézier about ``spacing`` apart by the length of its control polygon
    (at least 3, the interval's end left to the next one): points, parameters and interval numbers
    (:meth:`~.lsq_model.OutlineRegression.deviations`, docs/capture.md §12, "Stopping rule")."""
    count = bez.shape[0]
    counts = np.empty(count, np.int64)
    for k in range(count):
        length = 0.0
        for q in range(3):
            length += np.hypot(bez[k, q + 1, 0] - bez[k, q, 0], bez[k, q + 1, 1] - bez[k, q, 1])
        counts[k] = max(3, np.int64(np.ceil(length / spacing)))
    total = counts.sum()
    points = np.empty((total, 2))
    params = np.empty(total)
    interval = np.empty(total, np.int64)
    row = 0
    for k in range(count):
        width = ends[k] - starts[k]
        for q in range(counts[k]):
            theta = q / counts[k]
            _bezier_point(bez, k, theta, points, row)
            params[row] = starts[k] + theta * width
            interval[row] = k
            row += 1
    return points, params, interval
