"""Compiled loops of the ``"lsq"`` fit (docs/capture.md §12, "The lsq method" and "Stopping rule").

The per-point work of every knot round -- the cubic B-spline basis at each contour point and the weighted
normal equations it feeds, the spline's values on its knot intervals, one Hoschek parameter correction,
Bézier points and samples, the windowed point-to-polyline distances of the deviation and per-group maxima --
is a loop over a few thousand points that numpy runs as dozens of small array operations per round. These
kernels run it as one pass each (numba, compiled on first use and cached on disk, ``cache=True``). They are
the only implementation: every caller in :mod:`.bspline`, :mod:`.lsq_model` and :mod:`.geometry` goes
through them.

Each compiled loop (``_*_into``) writes into arrays its Python wrapper allocates (no allocation in compiled
code keeps the first-call compile short) and performs the floating-point operations of the vectorized
formulation it replaced, in the same order (no ``fastmath``: no reassociation, no fused multiply-add), so
its results are bit for bit those of the plain numpy expressions written out in ``tests/test_kernels.py``.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import HELPER_OPTIONS, JIT_OPTIONS, compact, insertion_sort, pyclip, pymax, pymin

__all__ = ["basis_matrix", "normal_equations", "normal_work", "DENSE_LIMIT", "spline_values", "fit_step", "hoschek_update",
           "windowed_distance", "eval_bezier",
           "interval_samples", "group_max", "curve_points", "hook_tests", "zone_window", "zone_points_beside", "seed_knots", "knot_vector", "contour_tables", "corner_radii",
           "corner_tables", "corner_weights", "anchor_bounds", "crack_normals", "interval_worst",
           "removal_scores", "closed_polyline_distance",
           "search_sorted", "deviation_measures", "warm_up",
           "warm_up_solves", "warm_up_checks", "warm_up_deviation"]

_JIT, _HELPER = JIT_OPTIONS, HELPER_OPTIONS


def _floats(values):
    return np.ascontiguousarray(values, dtype=np.float64)


def _ints(values):
    return np.ascontiguousarray(values, dtype=np.int64)


# Empty arguments of the kernels' unused outputs (one compiled signature for both uses of a kernel).
_NO_FLOATS, _NO_INTS, _NO_POINTS = np.empty(0), np.empty(0, np.int64), np.empty((0, 2))
_NO_BOOLS, _NO_CUBE, _NO_MATRIX = np.empty(0, np.bool_), np.empty((0, 0, 0)), np.empty((0, 0))
# The band row ``s - r`` of each pair ``(r, s)`` of basis functions, ``r <= s``, in the order r, then s
# (:func:`_normal_into`; a loop over the 10 rows of ``partial``, not over r and s: LLVM unrolled those loops into 10
# vectorized copies of the inner loop, about 15 % of the compiled code of the fit's solves).
_BAND_ROW = np.array([0, 1, 2, 3, 0, 1, 2, 0, 1, 0], dtype=np.int64)


@njit(**_HELPER)
def _next_index(k, m):
    """``(k + 1) % m`` for ``0 <= k < m``, without the integer division of a remainder."""
    k += 1
    return 0 if k == m else k


@njit(**_HELPER)
def _wrapped(e, m):
    """``e % m`` (Python's remainder: in ``[0, m)`` for ``m > 0``) for an index at most a few windows outside
    ``[0, m)``, by adding or taking ``m`` instead of an integer division (each step is exact)."""
    while e < 0:
        e += m
    while e >= m:
        e -= m
    return e


@njit(**_HELPER)
def _right_of(values, x):
    """The number of ``values`` (sorted) that are ``<= x``: ``numpy.searchsorted(values, x, side="right")``."""
    lo, hi = np.int64(0), values.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if x < values[mid]:
            hi = mid
        else:
            lo = mid + 1
    return lo


@njit(**_HELPER)
def _basis(full, i, u):
    """The four non-zero cubic B-splines ``N_{i-3} .. N_i`` at ``u``: the Cox-de Boor recurrence
    ``new_r = saved + right_{r+1} temp``, ``saved = left_{j-r} temp``, ``temp = old_r / (right_{r+1} +
    left_{j-r})`` for j = 1, 2, 3, written out. The values read as ``float``: interpreted (:mod:`.._interpreted`)
    Python floats are ~3x faster than numpy's scalars; compiled the same code."""
    x = float(u)
    left1, left2, left3 = x - float(full[i]), x - float(full[i - 1]), x - float(full[i - 2])
    right1, right2, right3 = float(full[i + 1]) - x, float(full[i + 2]) - x, float(full[i + 3]) - x
    denom = right1 + left1
    temp = 1.0 / (denom if denom > 0 else 1.0)  # j = 1
    b0, b1 = 0.0 + right1 * temp, left1 * temp
    denom = right1 + left2
    temp = b0 / (denom if denom > 0 else 1.0)  # j = 2
    c0, saved = 0.0 + right1 * temp, left2 * temp
    denom = right2 + left1
    temp = b1 / (denom if denom > 0 else 1.0)
    c1, c2 = saved + right2 * temp, left1 * temp
    denom = right1 + left3
    temp = c0 / (denom if denom > 0 else 1.0)  # j = 3
    d0, saved = 0.0 + right1 * temp, left3 * temp
    denom = right2 + left2
    temp = c1 / (denom if denom > 0 else 1.0)
    d1, saved = saved + right2 * temp, left2 * temp
    denom = right3 + left1
    temp = c2 / (denom if denom > 0 else 1.0)
    d2, d3 = saved + right3 * temp, left1 * temp
    return d0, d1, d2, d3


@njit(**_JIT)
def _basis_into(full, i, u, out):
    for j in range(u.shape[0]):
        out[j, 0], out[j, 1], out[j, 2], out[j, 3] = _basis(full, i[j], u[j])


def basis_matrix(full, i, u):
    """The (n, 4) non-zero cubic B-splines ``N_{i-3} .. N_i`` at every ``u[j]`` in its interval ``i[j]``."""
    u = _floats(u)
    out = np.empty((u.shape[0], 4))
    _basis_into(_floats(full), _ints(i), u, out)
    return out


@njit(**_JIT)
def _normal_into(full, u, extra, weights, targets, m, regularization, penalize, dense, band, rhs, partial, normal):
    for a in range(m):  # the sums start from zero (the arrays may hold an earlier system: work arrays)
        for d in range(rhs.shape[1]):
            rhs[a, d] = 0.0
        for row in range(4):
            band[row, a] = 0.0
        for pair in range(10):
            partial[pair, a] = 0.0
    # the parameters of the points, then those of the extra points (the corner pins): one sum in that order (one
    # loop over both: the loop's body compiled once)
    at = np.int64(0)  # the previous point's search answer (the parameters are sorted but for the pins at the end)
    last = full.shape[0] - 5
    points = u.shape[0]
    for j in range(points + extra.shape[0]):
        x = u[j] if j < points else extra[j - points]
        at = _walk_right(full, x, at)
        i = pyclip(at - 1, 3, last)  # bspline.interval_index
        n0, n1, n2, n3 = _basis(full, i, x)
        w = float(weights[j])
        w0 = n0 * w  # one assignment a line: four or more targets at once build and unpack a tuple (compile time)
        w1 = n1 * w
        w2 = n2 * w
        w3 = n3 * w
        # (i - 6) % m .. (i - 3) % m: one remainder, the next three by a step and a wrap (a remainder is an integer
        # division, several times the cost of the rest of a basis function)
        k0 = (i - 6) % m
        k1 = _next_index(k0, m)
        k2 = _next_index(k1, m)
        k3 = _next_index(k2, m)
        for d in range(targets.shape[1]):
            t = float(targets[j, d])
            rhs[k0, d] += w0 * t
            rhs[k1, d] += w1 * t
            rhs[k2, d] += w2 * t
            rhs[k3, d] += w3 * t
        partial[0, k0] += w0 * n0
        partial[1, k0] += w0 * n1
        partial[2, k0] += w0 * n2
        partial[3, k0] += w0 * n3
        partial[4, k1] += w1 * n1
        partial[5, k1] += w1 * n2
        partial[6, k1] += w1 * n3
        partial[7, k2] += w2 * n2
        partial[8, k2] += w2 * n3
        partial[9, k3] += w3 * n3
    for pair in range(partial.shape[0]):  # the pairs (r, s) in the order r, then s: band row s - r
        row = _BAND_ROW[pair]
        for a in range(m):
            band[row, a] += partial[pair, a]
    if not penalize:
        return
    # + pen * D^T D: pen = regularization * max(band[0]) (NaN sticks, as in numpy's max; 1 for an all-zero diagonal)
    scale = band[0, 0]
    for a in range(m):
        if not band[0, a] <= scale:
            scale = band[0, a]
    if scale == 0.0:
        scale = 1.0
    pen = regularization * scale
    for a in range(m):
        band[0, a] += 6 * pen
        band[1, a] += -4 * pen
        band[2, a] += 1 * pen
    if not dense:
        return
    for a in range(m):
        for b in range(m):
            normal[a, b] = 0.0
    for a in range(m):
        normal[a, a] = band[0, a]
    for k in range(1, 4):
        for a in range(m):
            normal[a, (a + k) % m] += band[k, a]
        for a in range(m):
            normal[(a + k) % m, a] += band[k, a]


def normal_work(m, dimensions=2):
    """Work arrays of :func:`normal_equations` for ``m`` coefficients (band, right-hand sides, the basis pairs'
    sums, the dense matrix): kept by a caller that solves many systems of one size (the fit's rounds)."""
    return np.empty((4, m)), np.empty((m, dimensions)), np.empty((10, m)), np.empty((m, m) if m <= DENSE_LIMIT else (0, 0))


#: Largest coefficient count whose normal equations are solved as a dense matrix (:func:`~.bspline.fit_coefficients`).
DENSE_LIMIT = 64


def normal_equations(full, u, weights, targets, m, regularization=None, extra=_NO_FLOATS, work=None):
    """Weighted least-squares normal equations of a periodic cubic spline with ``m`` coefficients on the full
    knot vector ``full`` (:func:`~.bspline.fit_coefficients`) at the parameters ``u`` and then ``extra`` (rows of
    ``weights`` and ``targets`` in that order): the cyclic band ``band[k, a] = A[a, (a + k) % m]`` (k = 0..3; the
    pairs ``(r, s)`` of basis functions, each a sum over the points, added in the order r, then s) and the
    right-hand sides ``rhs`` (m, d), each a sum over the points in their order. With ``regularization``, ``pen *
    D^T D`` added to the band (``D`` the cyclic second difference, rows 1, -2, 1; ``pen = regularization *
    max(band[0])``, the scale 1 for an all-zero diagonal) and, for ``m <=`` :data:`DENSE_LIMIT`, the full
    symmetric (m, m) matrix of the band (wrapped entries added up, also for m < 7), else None. Returns ``(band,
    rhs, normal)``; ``work``: the arrays to fill (:func:`normal_work`), else new ones."""
    targets = _floats(targets)
    band, rhs, partial, normal = normal_work(m, targets.shape[1]) if work is None else work
    penalize = regularization is not None
    dense = penalize and m <= DENSE_LIMIT
    _normal_into(_floats(full), _floats(u), _floats(extra), _floats(weights), targets, int(m),
                 float(regularization) if penalize else 0.0, penalize, dense, band, rhs, partial, normal)
    return band, rhs, normal if dense else None


@njit(**_JIT)
def _step_into(coef, full, m, starts, ends, theta, mix, values, mixed, u, points, piece_of, gate, du, res, worst, low,
               high, fixed, base, moved, u_bits, moved_bits):
    """The spline's values on its knot intervals (``coef`` not empty) mixed into ``mixed`` (``mix`` not empty),
    then the Newton step of the points ``u`` (not empty) on the pieces ``mixed``: :func:`fit_step`. Returns
    whether the stepped parameters ``moved`` are ``u`` bit for bit (their bits ``moved_bits``, ``u_bits``)."""
    for k in range(starts.shape[0] if coef.shape[0] else 0):
        width = ends[k] - starts[k]
        i = pyclip(_right_of(full, starts[k] + 0.5 * width) - 1, 3, full.shape[0] - 5)  # bspline.interval_index
        for t in range(theta.shape[0]):
            n0, n1, n2, n3 = _basis(full, i, starts[k] + width * theta[t])
            for d in range(coef.shape[1]):
                values[k, t, d] = (n0 * coef[(i - 6) % m, d] + n1 * coef[(i - 5) % m, d]
                                   + n2 * coef[(i - 4) % m, d] + n3 * coef[(i - 3) % m, d])
        for row in range(mix.shape[0]):  # numpy.einsum("rt,ktd->krd", mix, values): from 0, in the order of t
            for d in range(coef.shape[1]):
                total = 0.0
                for t in range(theta.shape[0]):
                    total += mix[row, t] * values[k, t, d]
                mixed[k, row, d] = total
    if not u.shape[0]:
        return False
    bez = mixed
    last = starts.shape[0] - 1
    at = np.int64(0)  # the previous point's search answer (the parameters are sorted)
    for j in range(u.shape[0]):
        at = _walk_right(starts, u[j], at)
        seg = pyclip(at - 1, 0, last)
        h = ends[seg] - starts[seg]
        theta_j = float((u[j] - starts[seg]) / h)  # numpy's division (h == 0 gives inf), read as float
        r0 = r1 = p0 = p1 = q0 = q1 = 0.0
        for d in range(2):  # the values read as float (see _basis)
            b0 = float(bez[seg, 0, d])
            b1 = float(bez[seg, 1, d])
            b2 = float(bez[seg, 2, d])
            b3 = float(bez[seg, 3, d])
            c1 = 3.0 * (b1 - b0)
            c2 = 3.0 * (b0 - 2.0 * b1 + b2)
            c3 = b3 - b0 + 3.0 * (b1 - b2)
            r = b0 + theta_j * (c1 + theta_j * (c2 + theta_j * c3)) - float(points[j, d])
            first = (c1 + theta_j * (2.0 * c2 + 3.0 * theta_j * c3)) / h
            second = (2.0 * c2 + 6.0 * theta_j * c3) / (h * h)
            if d == 0:
                r0, p0, q0 = r, first, second
            else:
                r1, p1, q1 = r, first, second
        speed2 = p0 * p0 + p1 * p1
        den = speed2 + r0 * q0 + r1 * q1
        if not den > 0.1 * speed2:
            den = speed2
        step = -(r0 * p0 + r1 * p1) / pymax(den, 1e-300)
        du[j] = pyclip(step, -2.0, 2.0)
        res[j] = np.hypot(r0, r1)
    for g in range(worst.shape[0]):
        worst[g] = -np.inf
    for j in range(u.shape[0]):
        worst[piece_of[j]] = pymax(worst[piece_of[j]], res[j])
    for j in range(u.shape[0]):
        if worst[piece_of[j]] > gate:
            du[j] = 0.0
    if moved.shape[0] != u.shape[0]:
        return False
    # the new parameters: numpy.clip(u + du, low, high), base where fixed, numpy.maximum.accumulate (numpy's
    # maximum and minimum: the first operand where it is NaN or wins strictly, else the second)
    previous = 0.0
    for j in range(u.shape[0]):
        x = u[j] + du[j]
        if not (x != x or x > low[j]):
            x = low[j]
        if not (x != x or x < high[j]):
            x = high[j]
        if fixed[j]:
            x = base[j]
        if j > 0 and (previous != previous or previous > x):
            x = previous
        moved[j] = previous = x
    for j in range(u.shape[0]):
        if moved_bits[j] != u_bits[j]:
            return False
    return True


def spline_values(coef, full, m, starts, ends, theta, mix=None):
    """Values of the periodic spline (coefficients ``coef`` (m, d)) at ``starts[k] + (ends[k] - starts[k]) *
    theta[q]`` for every knot interval ``k`` and fraction ``theta[q]``, evaluated in the interval that holds
    the interval's midpoint: an array (k, len(theta), d). With a matrix ``mix`` (r, len(theta)) instead the
    values mixed by it per interval, ``numpy.einsum("rq,kqd->krd", mix, values)`` (a product sum from 0 in the
    order of q, as einsum adds; :func:`~.bspline.bezier_of_intervals`)."""
    coef, starts = _floats(coef), _floats(starts)
    values = np.empty((starts.shape[0], len(theta), coef.shape[1]))
    rows = 0 if mix is None else mix.shape[0]
    mixed = np.empty((starts.shape[0] if rows else 0, rows, coef.shape[1]))
    _step_into(coef, _floats(full), int(m), starts, _floats(ends), _floats(theta),
               _floats(mix) if rows else _NO_MATRIX, values, mixed, _NO_FLOATS, _NO_POINTS, _NO_INTS, 0.0,
               _NO_FLOATS, _NO_FLOATS, _NO_FLOATS, _NO_FLOATS, _NO_FLOATS, _NO_BOOLS, _NO_FLOATS, _NO_FLOATS, _NO_INTS,
               _NO_INTS)
    return mixed if rows else values


def fit_step(coef, full, m, starts, ends, theta, mix, u, points, piece_of, piece_count, gate, bounds=None,
             values=None):
    """The Bézier pieces of the spline ``coef`` on its knot intervals (:func:`spline_values` with the matrix
    ``mix``; ``coef`` None: ``mix`` is the pieces themselves), then one Newton step of the foot-point equation
    ``(S(u) - Q) . S'(u) = 0`` per contour point ``Q = points[j]`` on them
    (:meth:`~.lsq_model.OutlineRegression.fit`): the steps ``du`` (clipped to +-2), zero in the pieces
    (``piece_of``, non-decreasing) whose largest residual exceeds ``gate``. With ``bounds = (low, high, fixed,
    base)`` instead of the steps the stepped parameters, ``numpy.maximum.accumulate`` of ``numpy.clip(u + du, low,
    high)`` with ``base`` where ``fixed``. Returns ``(pieces, steps or parameters, same)``, ``same``: the stepped
    parameters are ``u`` bit for bit (signed zeros included; False without ``bounds``); ``values``: a work array
    (k, len(theta), 2) of the values. The arrays are the fit's own, float64 (``piece_of`` int64) and contiguous:
    taken as they are."""
    count = u.shape[0]
    du, res, worst = np.empty(count), np.empty(count), np.empty(int(piece_count))
    if bounds is None:
        low = high = base = moved = _NO_FLOATS
        fixed, u_bits, moved_bits = _NO_BOOLS, _NO_INTS, _NO_INTS
    else:
        low, high, fixed, base = bounds
        moved = np.empty(count)
        u_bits, moved_bits = u.view(np.int64), moved.view(np.int64)
    if coef is None:
        coef, mixed, values, mix = _NO_MATRIX, mix, _NO_CUBE, _NO_MATRIX
    else:
        mixed = np.empty((starts.shape[0], mix.shape[0], coef.shape[1]))
        if values is None:
            values = np.empty((starts.shape[0], theta.shape[0], coef.shape[1]))
    same = _step_into(coef, full, int(m), starts, ends, theta, mix, values, mixed, u, points, piece_of, float(gate), du,
                      res, worst, low, high, fixed, base, moved, u_bits, moved_bits)
    return mixed, (du if bounds is None else moved), same


def hoschek_update(u, points, bez, starts, ends, piece_of, piece_count, gate, bounds=None):
    """One Newton step of the foot-point equation on the given Bézier pieces ``bez`` (:func:`fit_step` without
    the spline): the steps ``du``, or with ``bounds`` the stepped parameters."""
    bounds = None if bounds is None else (_floats(bounds[0]), _floats(bounds[1]),
                                          np.ascontiguousarray(bounds[2], dtype=np.bool_), _floats(bounds[3]))
    return fit_step(None, _NO_FLOATS, 1, _floats(starts), _floats(ends), _NO_FLOATS, _floats(bez), _floats(u),
                    _floats(points), _ints(piece_of), piece_count, gate, bounds)[1]


@njit(**_JIT)
def _windowed_into(points, centre, lo, hi, ax, ay, dx, dy, inverse, window, wrap, clip, out):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for j in range(points.shape[0]):
        best = np.inf
        for offset in range(-window, window + 1):
            e = centre[j] + offset
            if clip:
                e = pyclip(e, lo[j], hi[j])
            if wrap:
                e %= wrap
            px = points[j, 0] - ax[e]
            py = points[j, 1] - ay[e]
            t = (px * dx[e] + py * dy[e]) * inverse[e]
            t = pyclip(t, 0.0, 1.0)
            px -= t * dx[e]
            py -= t * dy[e]
            squared = px * px + py * py
            if squared < best:
                best = squared
        out[j] = np.sqrt(best)


def windowed_distance(points, centre, lo, hi, edges, window, wrap):
    """Distance from ``points[j]`` to the polyline edges ``centre[j] - window .. centre[j] + window``
    (clipped to ``[lo[j], hi[j]]`` unless ``lo`` is None, then modulo ``wrap`` when > 0), exact
    point-to-segment distances on the :func:`~.geometry.edge_table` ``edges``."""
    points, centre = _floats(points), _ints(centre)
    clip = lo is not None
    lo, hi = (_ints(lo), _ints(hi)) if clip else (centre, centre)
    out = np.empty(points.shape[0])
    _windowed_into(points, centre, lo, hi, *(_floats(column) for column in edges), int(window), int(wrap), clip, out)
    return out


@njit(**_JIT)
def _nearest_segments_into(px, py, ax, ay, dx, dy, inverse, out):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for i in range(px.shape[0]):
        for p in range(px.shape[1]):
            best = np.inf
            for e in range(ax.shape[1]):
                rx = px[i, p] - ax[i, e]
                ry = py[i, p] - ay[i, e]
                t = (rx * dx[i, e] + ry * dy[i, e]) * inverse[i, e]
                t = pyclip(t, 0.0, 1.0)
                rx -= t * dx[i, e]
                ry -= t * dy[i, e]
                squared = rx * rx + ry * ry
                if squared < best:
                    best = squared
            out[i, p] = np.sqrt(best)


def nearest_segment_distance(px, py, ax, ay, dx, dy):
    """Per row ``i`` and point ``p``: the distance from ``(px, py)[i, p]`` (``(I, P)``) to the nearest of the
    segments ``a -> a + d`` of its row (``(I, E)``, ``E >= 1``), exact point-to-segment distances (a segment of
    zero length is its point). The small-outline fit's two-sided deviation (:mod:`.small`) in one pass instead
    of an ``(I, P, E)`` grid; bit for bit ``sqrt(rx² + ry²).min(axis=2)`` of the grid (the square root is
    correctly rounded and monotonic, so the minimum commutes with it)."""
    px, py, ax, ay, dx, dy = (_floats(values) for values in (px, py, ax, ay, dx, dy))
    den = dx * dx + dy * dy
    inverse = 1.0 / np.where(den > 0, den, 1.0)
    out = np.empty(px.shape)
    _nearest_segments_into(px, py, ax, ay, dx, dy, inverse, out)
    return out


@njit(**_HELPER)
def _bezier_point(bez, k, theta, out, row):
    """``out[row]`` = the cubic Bézier piece ``bez[k]`` at ``theta`` (Bernstein weights, summed in order)."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    s = 1.0 - theta
    t2, s2 = theta * theta, s * s
    w0 = s2 * s
    w1 = 3.0 * theta * s2
    w2 = 3.0 * t2 * s
    w3 = t2 * theta
    for d in range(bez.shape[2]):
        out[row, d] = w0 * bez[k, 0, d] + w1 * bez[k, 1, d] + w2 * bez[k, 2, d] + w3 * bez[k, 3, d]


def eval_bezier(bez, piece, theta):
    """Points of the Bézier pieces ``bez[piece[j]]`` at ``theta[j]`` (:func:`~.geometry.eval_bezier`)."""
    bez, theta = _floats(bez), _floats(theta)
    out = np.empty((theta.shape[0], bez.shape[2]))
    _curve_into(bez, _NO_FLOATS, _NO_FLOATS, theta, _ints(piece), True, out)
    return out


@njit(**_JIT)
def _curve_into(bez, starts, ends, u, piece, given, out):
    """``out[j]`` = the piece ``piece[j]`` at the fraction ``u[j]`` when ``given``, else the piece of ``u[j]``
    (searchsorted right in ``starts``, clipped to the pieces) at its fraction of ``[starts, ends]``."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    last = starts.shape[0] - 1
    for j in range(u.shape[0]):
        if given:
            seg, theta = piece[j], u[j]
        else:
            seg = pyclip(_right_of(starts, u[j]) - 1, 0, last)
            theta = (u[j] - starts[seg]) / (ends[seg] - starts[seg])
        _bezier_point(bez, seg, theta, out, j)  # one call: each call is a copy of the (inlined) helper


@njit(**_HELPER)
def _curve_point(bez, starts, ends, u, out, row):
    """``out[row]`` = the piecewise curve at ``u`` (the piece of ``u`` by searchsorted right in ``starts``, clipped
    to the pieces, at its fraction of ``[starts, ends]``): :func:`curve_points` at one parameter."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    seg = pyclip(_right_of(starts, u) - 1, 0, starts.shape[0] - 1)
    _bezier_point(bez, seg, (u - starts[seg]) / (ends[seg] - starts[seg]), out, row)


@njit(**_JIT)
def _hook_tests_into(bez, starts, ends, at, corner_points, limit, radius, fitted, u, given, samples, count, row, axis,
                     along_start, across_start, slack, hooked, beside, row_finite):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for c in range(at.shape[0]):  # the displacement test: the fitted corner point against the limit
        _curve_point(bez, starts, ends, at[c], fitted, c)
        disp = np.hypot(fitted[c, 0] - corner_points[c, 0], fitted[c, 1] - corner_points[c, 1])
        hooked[c] = disp > limit[c] and radius[c] > 0
    if not given:
        for s in range(u.shape[0]):
            _curve_point(bez, starts, ends, u[s], samples, s)
    for r in range(row_finite.shape[0]):
        row_finite[r] = True
        for s in range(r * count, (r + 1) * count):
            if not (np.isfinite(samples[s, 0]) and np.isfinite(samples[s, 1])):
                row_finite[r] = False
                break
    for p in range(row.shape[0]):
        beside[p] = row_finite[row[p]]  # a row with a NaN sample: its least gap is NaN, no point of it is beside
        first = row[p] * count
        for s in range(first, first + count if beside[p] else first):
            along = samples[s, axis[p]] - along_start[p]
            gap = np.hypot(along - pyclip(along, 0.0, 1.0), samples[s, 1 - axis[p]] - across_start[p])
            if gap <= slack:  # a sample within the slack: the point passes (its least gap is no larger)
                beside[p] = False
                break


def hook_tests(bez, starts, ends, at, corner_points, limit, radius, u, rows, row, axis, along_start, across_start,
               slack, samples=None):
    """The two corner tests after a fit (:meth:`~.lsq_model.OutlineRegression.hook_releases`) in one pass over
    the pieces ``bez`` on ``[starts, ends]`` (:func:`curve_points`):

    * per corner, whether its fitted point ``S(at)`` lies farther than ``limit`` from ``corner_points``
      (``hypot`` of the differences) while ``radius > 0`` (the displacement test of ``hooked_corners``);
    * per point ``p`` of the zone test (``row``, ``axis``, ``along_start``, ``across_start``): whether every curve
      sample of its row (the curve at ``u``: ``rows`` rows of equally many; ``samples`` (rows, count, 2): the
      samples given instead) lies farther than ``slack`` from the point's pixel-centre segment, ``hypot(along -
      clip(along, 0, 1), across)`` with ``along = sample[axis[p]] - along_start[p]`` and ``across = sample[1 -
      axis[p]] - across_start[p]``: ``numpy.min`` of those distances ``> slack``, each point stopping at its
      first sample within the slack; a row with a sample that is not finite has no point beside (its points'
      least distance is NaN then).

    Returns ``(hooked, beside)``. The arrays are float64 (``row`` and ``axis`` int64) and contiguous: taken as
    they are."""
    given = samples is not None
    samples = _floats(samples).reshape(-1, 2) if given else np.empty((u.shape[0], 2))
    rows = int(rows)
    hooked, beside = np.empty(at.shape[0], np.bool_), np.empty(row.shape[0], np.bool_)
    _hook_tests_into(bez, starts, ends, at, corner_points, limit, radius, np.empty((at.shape[0], 2)), u, given, samples,
                     samples.shape[0] // rows if rows else 0, row, axis, along_start, across_start, float(slack), hooked,
                     beside, np.empty(rows, np.bool_))
    return hooked, beside


@njit(**_JIT)
def _zone_window_into(radius, excluded, nearest, corner_distance, corner_par, gap_before, gap_after, crack_y, points,
                      period, spacing, tested, half, sizes, u, row, axis, along_start, across_start, owner):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    corners = radius.shape[0]
    for c in range(corners):
        tested[c] = -1
    count = np.int64(0)
    for j in range(points.shape[0]):  # the points within an active corner's reach, max(r, 1) px of arc
        c = nearest[j]
        if radius[c] > 0 and not excluded[c] and corner_distance[j] < _larger(radius[c], 1.0):
            owner[count] = c
            tested[c] = 0
            axis[count] = 1 if crack_y[j] == 1.0 else 0  # 0: normal (1, 0), 1: normal (0, 1)
            along_start[count] = points[j, axis[count]] - 0.5
            across_start[count] = points[j, 1 - axis[count]]
            count += 1
    rows = np.int64(0)
    widest = -np.inf
    for c in range(corners):  # each tested corner's row, in corner order; its half window
        if tested[c] < 0:
            continue
        tested[c] = rows
        half[rows] = _larger(radius[c], 1.0) + _larger(gap_before[c], gap_after[c]) + 2.0
        if not half[rows] <= widest:  # numpy's max: NaN sticks
            widest = half[rows]
        rows += 1
    sizes[0], sizes[1] = count, rows
    if not rows:
        return
    samples = np.int64(np.ceil(2.0 * widest / spacing)) + 1
    sizes[2] = samples
    if rows * samples > u.shape[0]:
        return  # the caller's buffer is too small: it calls again with one of this size
    # numpy.linspace(-1.0, 1.0, samples) in its arithmetic: k * step + start, the last one the stop
    step = 2.0 / (samples - 1)
    r = np.int64(0)
    for c in range(corners):
        if tested[c] < 0:
            continue
        for k in range(samples):
            fraction = k * step + -1.0 if k < samples - 1 else 1.0
            u[r * samples + k] = (corner_par[c] + half[r] * fraction) % period
        r += 1
    for p in range(count):
        row[p] = tested[owner[p]]


def zone_window(radius, excluded, nearest, corner_distance, corner_par, gap_before, gap_after, crack_y, points,
                period, spacing, bound=0):
    """The zone test's window (:meth:`~.lsq_model.OutlineRegression._zone_window`), or None where no point is
    tested: per corner with ``radius > 0`` that is not ``excluded``, the contour points (``points``; their
    ``nearest`` corner and ``corner_distance``) within ``max(r, 1)`` px of arc of it; per tested corner (in corner
    order) a row of curve parameters ``mod(corner_par + half * linspace(-1, 1, count), period)`` over its half window
    ``max(r, 1) + max(gap_before, gap_after) + 2``, ``count = ceil(2 max(half) / spacing) + 1``; per point its
    corner's row, the axis of its crack normal (``crack_y == 1``: 1, the y axis, else 0), the coordinate along it
    of the pixel centre at the segment's start (the point's less 0.5) and the other coordinate, and its corner.
    Returns ``(u, rows, row, axis, along_start, across_start, owner)``; ``bound``: a first guess of the parameters'
    count."""
    n, corners = points.shape[0], radius.shape[0]
    tested, half, sizes = np.empty(corners, np.int64), np.empty(corners), np.zeros(3, np.int64)
    row, axis, owner = np.empty(n, np.int64), np.empty(n, np.int64), np.empty(n, np.int64)
    along_start, across_start = np.empty(n), np.empty(n)
    arguments = (_floats(radius), np.ascontiguousarray(excluded, dtype=np.bool_), _ints(nearest),
                 _floats(corner_distance), _floats(corner_par), _floats(gap_before), _floats(gap_after),
                 _floats(crack_y), _floats(points), float(period), float(spacing), tested, half, sizes)
    u = np.empty(int(bound))
    _zone_window_into(*arguments, u, row, axis, along_start, across_start, owner)
    count, rows, samples = sizes.tolist()
    if not count:
        return None
    if rows * samples > u.shape[0]:
        u = np.empty(rows * samples)
        _zone_window_into(*arguments, u, row, axis, along_start, across_start, owner)
    return (u[: rows * samples], rows, row[:count], axis[:count], along_start[:count], across_start[:count],
            owner[:count])


@njit(**_JIT)
def _seed_knots_into(points, arc, perimeter, corner_distance, cornered, bounds, density, epsilon, min_gap, seeds,
                     stage, least, angle, kappa, box, cum, out):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    n = points.shape[0]
    a = 4  # the chords over +-4 contour steps, their turn between +-4 steps (callers have n >= 16 points)
    for i in range(n):
        ahead = i + a if i + a < n else i + a - n
        behind = i - a if i >= a else i - a + n
        angle[i] = np.arctan2(points[ahead, 1] - points[behind, 1], points[ahead, 0] - points[behind, 0])
    two_pi = 2.0 * np.pi
    for i in range(n):
        ahead = i + a if i + a < n else i + a - n
        behind = i - a if i >= a else i - a + n
        turn = (angle[ahead] - angle[behind] + np.pi) % two_pi - np.pi
        # the arc lengths a points ahead and behind, across the seam continued by the perimeter
        far = arc[i + a] if i + a < n else perimeter + arc[i + a - n]
        near = arc[i - a] if i >= a else arc[n - a + i] - perimeter
        kappa[i] = turn / _larger(far - near, 1e-9)
    width = 8  # the box average over +-8 steps: prefix sums of the rates padded by 8 on both sides
    box[0] = 0.0
    for k in range(n + 2 * width):
        value = kappa[_wrapped(k - width, n)]
        box[k + 1] = value if k == 0 else box[k] + value
    for i in range(n):
        kappa[i] = np.abs(box[i + 2 * width + 1] - box[i]) / (2 * width + 1)
        if kappa[i] < least:
            kappa[i] = 0.0
    if stage < 1:
        return 0
    # the knot density (density kappa^3 / epsilon)^(1/4), 0 on straight runs and within 6 px of a corner; its
    # integral along the contour (numpy.cumsum of density times step, after a 0)
    cum[0] = 0.0
    for i in range(n):
        lam = 0.0
        if kappa[i] != 0.0 and not (cornered and corner_distance[i] < 6.0):
            lam = (density * kappa[i] ** 3.0 / epsilon) ** 0.25
        value = lam * (arc[i + 1] - arc[i])
        cum[i + 1] = value if i == 0 else cum[i] + value
    if stage < 2:
        return 0
    count = np.int64(0)
    for k in range(seeds.shape[0]):
        out[count] = seeds[k]
        count += 1
    at = np.int64(0)
    for p in range(bounds.shape[0] - 1):  # each piece: its targets cum[first] + total i / (targets + 1)
        first, last = bounds[p], bounds[p + 1]
        total = cum[last] - cum[first]
        floor = np.floor(total)
        targets = np.int64(floor if floor < last - first else last - first)
        for i in range(1, targets + 1):
            at = _walk_left(cum, cum[first] + total * i / (targets + 1), at)
            j = pyclip(at, first, last + 1)
            if j - first >= min_gap and last - j >= min_gap:
                out[count] = j
                count += 1
    insertion_sort(out, count)  # sorted (the knots come nearly sorted), then each once
    unique = np.int64(0)
    for k in range(count):
        if k == 0 or out[k] != out[k - 1]:
            out[unique] = out[k]
            unique += 1
    kept = np.int64(0)  # at least min_gap steps after the knot before it (not the one kept before it)
    previous = -min_gap
    for k in range(unique):
        value = out[k]
        if value - previous >= min_gap:
            out[kept] = value
            kept += 1
        previous = value
    return kept


def seed_knots(points, arc, perimeter, corner_distance, cornered, bounds, seeds, density, epsilon, min_gap, least,
               stage=2):
    """The first knots of ``"lsq"`` by the contour's curvature in one pass (:func:`~.lsq_setup.curvature_knots`):
    the curvature rate per contour point (``points``, ``n >= 16``, ``arc`` its ``n + 1`` cumulative arc lengths
    around ``perimeter``): the turn of the chord directions over +-4 contour steps between +-4 steps (``numpy``'s
    ``arctan2`` and remainder arithmetic), per arc length, averaged over +-8 steps by prefix sums, rates below
    ``least`` set to 0 (``stage`` 0: returned); the integral of the knot density ``(density kappa^3 /
    epsilon)^(1/4)`` (0 within 6 px of a corner, ``corner_distance``, where ``cornered``) from 0 along
    the contour (``stage`` 1: returned); else per piece ``bounds[p] .. bounds[p + 1]`` the knots where the integral
    crosses the piece's total times ``i / (count + 1)``, ``count = min(floor(total), steps)`` (numpy's searchsorted
    from the left, clipped to the piece), at least ``min_gap`` steps inside it, with ``seeds`` sorted, each once,
    and each at least ``min_gap`` steps after the knot before it."""
    n = points.shape[0]
    seeds = _ints(seeds)
    angle, kappa, box, cum = np.empty(n), np.empty(n), np.empty(n + 17), np.empty(n + 1)
    out = np.empty(seeds.shape[0] + n + 1, np.int64) if stage >= 2 else _NO_INTS
    bounds = _ints(bounds)
    kept = _seed_knots_into(_floats(points), _floats(arc), float(perimeter), _floats(corner_distance), bool(cornered),
                            bounds, float(density), float(epsilon), int(min_gap), seeds, int(stage), float(least), angle,
                            kappa, box, cum, out)
    return (kappa, cum, out[:kept])[min(stage, 2)]


@njit(**_JIT)
def _knot_vector_into(corner_values, values, multiplicity, period, knots, full, distinct, sizes):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    m = np.int64(0)
    c = v = np.int64(0)
    while c < corner_values.shape[0] or v < values.shape[0]:  # the two sorted lists merged
        if v >= values.shape[0] or (c < corner_values.shape[0] and corner_values[c] <= values[v]):
            for _ in range(3):
                knots[m] = corner_values[c]
                m += 1
            c += 1
        else:
            for _ in range(multiplicity[v]):
                knots[m] = values[v]
                m += 1
            v += 1
    for e in range(m + 7):  # knots[idx % m] + period * floor_divide(idx, m), idx = -3 .. m + 3
        idx = e - 3
        wraps = idx // m
        full[e] = knots[idx - wraps * m] + period * wraps
    k = np.int64(0)
    for e in range(m):
        if k == 0 or knots[e] != distinct[k - 1]:
            distinct[k] = knots[e]
            k += 1
    if k == 0 or period != distinct[k - 1]:
        distinct[k] = period
        k += 1
    sizes[0], sizes[1] = m, k


def knot_vector(corner_values, values, multiplicity, period):
    """The knots of one period of a periodic cubic spline, sorted: ``corner_values`` three times each and
    ``values`` ``multiplicity`` times each (both sorted; ``numpy.sort`` of their repeats); its full knot vector
    ``tau_{-3} .. tau_{M+3}`` (``knots[idx % M] + period * floor_divide(idx, M)``); and the starts and ends of its
    knot intervals (the knots each once, and ``period``: ``numpy.unique``). Returns ``(knots, full, starts,
    ends)`` (:meth:`~.lsq_model.OutlineRegression.knot_values`, :func:`~.bspline.periodic_knot_vector`)."""
    values, multiplicity = _floats(values), _ints(multiplicity)
    bound = 3 * corner_values.shape[0] + int(multiplicity.sum()) if multiplicity.shape[0] else 3 * corner_values.shape[0]
    knots, full, distinct = np.empty(bound), np.empty(bound + 7), np.empty(bound + 1)
    sizes = np.empty(2, np.int64)
    _knot_vector_into(_floats(corner_values), values, multiplicity, float(period), knots, full, distinct, sizes)
    m, k = sizes.tolist()
    return knots[:m], full[: m + 7], distinct[: k - 1], distinct[1:k]


@njit(**_JIT)
def _contour_into(closed, bounds, corners, edges, arc, corner_arc, piece_of, distance, nearest):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for e in range(closed.shape[0] - 1):  # the edge table (geometry.edge_table) and the cumulative arc lengths
        dx = closed[e + 1, 0] - closed[e, 0]
        dy = closed[e + 1, 1] - closed[e, 1]
        den = dx * dx + dy * dy
        edges[0, e] = closed[e, 0]
        edges[1, e] = closed[e, 1]
        edges[2, e] = dx
        edges[3, e] = dy
        edges[4, e] = 1.0 / (den if den > 0 else 1.0)
        if arc.shape[0]:
            step = np.hypot(dx, dy)
            arc[e + 1] = step if e == 0 else arc[e] + step
    if not arc.shape[0]:
        return
    arc[0] = 0.0
    pieces = bounds.shape[0] - 1
    at = np.int64(0)
    for j in range(piece_of.shape[0]):
        at = _walk_right(bounds, j, at)
        piece_of[j] = pyclip(at - 1, 0, pieces - 1)
    if not corners:
        for j in range(distance.shape[0]):
            distance[j] = np.inf
            nearest[j] = 0
        return
    for c in range(bounds.shape[0]):
        corner_arc[c] = arc[bounds[c]]
    at = np.int64(0)
    for j in range(distance.shape[0]):  # the arc length to the nearest corner (the period end is corner 0)
        at = _walk_left(corner_arc, arc[j], at)
        k = pyclip(at, 1, corners)
        left, right = arc[j] - corner_arc[k - 1], corner_arc[k] - arc[j]
        distance[j] = left if (left != left or left < right) else right  # numpy.minimum
        nearest[j] = (k - 1 if left <= right else k) % corners


def contour_tables(closed, bounds, corners, edges_only=False):
    """Per edge of the closed polyline ``closed`` (the first point again at the end): start x, start y, dx, dy and
    ``1 / |d|^2`` (1 for a zero-length edge), the rows of one ``(5, edges)`` array (:func:`~.geometry.edge_table`);
    unless ``edges_only``, also the cumulative arc lengths (from 0, ``numpy.cumsum`` of the edges' ``hypot``), the
    piece of every point (``bounds``: the pieces' first points, then the closing index; ``numpy.searchsorted``
    right, less 1, clipped to the pieces) and, with ``corners`` (the pieces' first points are corners, the closing
    index corner 0 again), the arc length to the nearest corner and its number (the earlier one on a tie;
    without corners infinity and 0): :class:`~.lsq_setup.RotatedContour`. Returns ``edges`` or ``(edges, arc,
    piece_of_point, corner_distance, nearest_corner)``."""
    closed = _floats(closed)
    count = closed.shape[0]
    edges = np.empty((5, count - 1))
    if edges_only:
        _contour_into(closed, _NO_INTS, 0, edges, _NO_FLOATS, _NO_FLOATS, _NO_INTS, _NO_FLOATS, _NO_INTS)
        return edges
    bounds = _ints(bounds)
    arc, piece_of, distance, nearest = np.empty(count), np.empty(count, np.int64), np.empty(count), \
        np.empty(count, np.int64)
    _contour_into(closed, bounds, int(corners), edges, arc, np.empty(bounds.shape[0]), piece_of, distance, nearest)
    return edges, arc, piece_of, distance, nearest


@njit(**_HELPER)
def _interp(x, xp, fp, at):
    """``numpy.interp(x, xp, fp)`` at one ``x`` in numpy's arithmetic (``xp`` increasing, ``at`` the search's
    start): the end values outside ``xp``, ``fp[j]`` where ``x == xp[j]`` (the last of repeated ``xp``), else the
    slope times ``x - xp[j]`` plus ``fp[j]``, and its retries where that is NaN."""
    compact()  # optimized for size, as its callers are (_jit.compact)
    n = xp.shape[0]
    if x != x:
        return x
    if x < xp[0]:
        return fp[0]
    if x > xp[n - 1]:
        return fp[n - 1]
    j = _walk_right(xp, x, at) - 1
    if j >= n - 1 or xp[j] == x:
        return fp[j]
    return _interpolated(x, xp, fp, j)


@njit(**_HELPER)
def _interpolated(x, xp, fp, j):
    """``numpy.interp``'s value at ``x`` strictly inside ``xp[j] .. xp[j + 1]``: the slope times ``x - xp[j]`` plus
    ``fp[j]``, where that is NaN from the other end, and ``fp[j]`` where that is NaN too and the values agree."""
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    value = slope * (x - xp[j]) + fp[j]
    if value != value:
        value = slope * (x - xp[j + 1]) + fp[j + 1]
        if value != value and fp[j] == fp[j + 1]:
            value = fp[j]
    return value


@njit(**_HELPER)
def _smaller(a, b):
    """``numpy.minimum(a, b)`` of two floats: ``a`` where it is NaN or smaller, else ``b``."""
    if a != a or a < b:
        return a
    return b


@njit(**_JIT)
def _corner_radii_into(arc, xs, ys, points, bounds, corner_radius, radius, theta):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    corners = bounds.shape[0] - 1
    perimeter = arc[arc.shape[0] - 1]
    for c in range(corners):
        length = arc[bounds[c + 1]] - arc[bounds[c]]
        p = c - 1 if c > 0 else corners - 1
        before = arc[bounds[p + 1]] - arc[bounds[p]]
        corner_arc = arc[bounds[c]]
        # the points min(6, 0.4 piece) px of arc away on both sides (numpy.interp along the closed polyline)
        back = (corner_arc - _smaller(6.0, 0.4 * before)) % perimeter
        ahead = (corner_arc + _smaller(6.0, 0.4 * length)) % perimeter
        corner = bounds[c] % points.shape[0]
        # the searches walk from the corner (exact from any start; from 0 every corner cost a walk over the
        # contour: quadratic on outlines of many corners)
        start = np.int64(bounds[c])
        ax = _interp(back, arc, xs, start) - points[corner, 0]
        ay = _interp(back, arc, ys, start) - points[corner, 1]
        bx = _interp(ahead, arc, xs, start) - points[corner, 0]
        by = _interp(ahead, arc, ys, start) - points[corner, 1]
        cos = (ax * bx + ay * by) / _larger(np.hypot(ax, ay) * np.hypot(bx, by), 1e-300)
        theta[c] = np.arccos(pyclip(cos, -1.0, 1.0))
        r = 0.0
        if corner_radius > 0:
            r = pyclip(corner_radius / _larger(np.tan(0.5 * theta[c]), 1e-6), 1.0, 3.0 * corner_radius)
        radius[c] = _smaller(r, 0.2 * _smaller(before, length))


def corner_radii(arc, closed, bounds, corner_radius):
    """Per corner (``bounds``: the corners' indices into ``closed``, the closed contour polyline of cumulative arc
    lengths ``arc``, then the closing index): the interior angle ``theta`` of the chords to the points ``min(6, 0.4
    piece)`` px of arc away on both sides (``numpy.interp``; the cosine ``a0 b0 + a1 b1`` over the chords' lengths,
    clipped), and ``corner_radius / tan(theta / 2)`` clipped to ``[1, 3 corner_radius]`` (0 where ``corner_radius``
    is 0) and to a fifth of either neighbouring piece: :func:`~.lsq_setup.corner_radii`. Returns ``(radius,
    theta)``."""
    corners = bounds.shape[0] - 1
    radius, theta = np.empty(corners), np.empty(corners)
    _corner_radii_into(arc, np.ascontiguousarray(closed[:, 0]), np.ascontiguousarray(closed[:, 1]), closed[:-1],
                       _ints(bounds), float(corner_radius), radius, theta)
    return radius, theta


@njit(**_JIT)
def _corner_tables_into(zone_radius, radius, allowance_kept, tip_allowance, nearest, corner_distance, fixed, dense,
                        zone, allowance, probe_zone, probe_allowance, weights):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    n = weights.shape[0] if weights.shape[0] else zone.shape[0] - 1
    if weights.shape[0]:  # min(1, (distance / r)^2) within an extrapolated corner's radius r, its point 0; >= 1e-3
        for j in range(n):
            r = radius[nearest[j]]
            w = 1.0
            if r > 0:
                x = corner_distance[j] / r
                square = x * x
                w = 1.0 if 1.0 <= square else square  # numpy.minimum(1.0, x ** 2)
                if fixed[j]:
                    w = 0.0
            weights[j] = _larger(w, 1e-3)
        return
    for j in range(n + 1):  # the zones of the corners whose tip is extrapolated (or keeps its allowance)
        c = nearest[j]
        r = zone_radius[c]
        inside = r > 0 and (radius[c] > 0 or allowance_kept[c]) and corner_distance[j] < 2.0 * r + 1.0
        zone[j] = 1.0 if inside else 0.0
        allowance[j] = tip_allowance[c] if inside else 0.0
    for j in range(probe_zone.shape[0]):
        if not dense:
            probe_zone[j] = zone[j] > 0
            probe_allowance[j] = allowance[j]
        elif j % 2 == 0:
            probe_zone[j] = zone[j // 2] > 0
            probe_allowance[j] = allowance[j // 2]
        else:
            probe_zone[j] = zone[j // 2] > 0 or zone[j // 2 + 1] > 0
            probe_allowance[j] = _larger(allowance[j // 2], allowance[j // 2 + 1])


def corner_tables(zone_radius, radius, allowance_kept, tip_allowance, nearest, corner_distance, dense):
    """Per contour point (``nearest`` corner and ``corner_distance``, n + 1 of them) whether it lies in the zone of its
    corner (within ``2 r + 1`` px of arc, ``r`` its ``zone_radius``, while its tip is extrapolated, ``radius > 0``,
    or keeps its allowance, ``allowance_kept``) as floats, the corner's ``tip_allowance`` there (else 0), and per
    probe (the contour points; ``dense``: and the edge midpoints between, in a zone where either end is, with the
    larger allowance) the same: ``(zone, allowance, probe_zone, probe_allowance)``
    (:meth:`~.lsq_model.OutlineRegression.zone`, ``_zones``)."""
    n = nearest.shape[0] - 1
    zone, allowance = np.empty(n + 1), np.empty(n + 1)
    probe_zone, probe_allowance = np.empty(2 * n if dense else n, np.bool_), np.empty(2 * n if dense else n)
    _corner_tables_into(_floats(zone_radius), _floats(radius), np.ascontiguousarray(allowance_kept, dtype=np.bool_),
                        _floats(tip_allowance), _ints(nearest), _floats(corner_distance), _NO_BOOLS, bool(dense), zone,
                        allowance, probe_zone, probe_allowance, _NO_FLOATS)
    return zone, allowance, probe_zone, probe_allowance


def corner_weights(radius, nearest, corner_distance, fixed):
    """The fit's weight of every contour point (``nearest`` corner, ``corner_distance``, ``fixed``; n of them):
    ``min(1, (distance / r)^2)`` within the radius ``r`` of an extrapolated corner (``r > 0``; a fixed point 0),
    else 1; at least 1e-3 (:meth:`~.lsq_model.OutlineRegression.weights`)."""
    weights = np.empty(nearest.shape[0])
    _corner_tables_into(_NO_FLOATS, _floats(radius), _NO_BOOLS, _NO_FLOATS, _ints(nearest), _floats(corner_distance),
                        np.ascontiguousarray(fixed, dtype=np.bool_), False, _NO_FLOATS, _NO_FLOATS, _NO_BOOLS,
                        _NO_FLOATS, weights)
    return weights


@njit(**_JIT)
def _anchors_into(anchor, base, low, high):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    n = low.shape[0]
    before = np.int64(0)
    for j in range(n):
        if anchor[j]:
            before = j
        low[j] = base[before]
    after = n  # the closing index counts as anchored
    for j in range(n - 1, -1, -1):
        if anchor[j]:
            after = j
        high[j] = base[after]


def anchor_bounds(anchor, base):
    """Per point ``j < n`` (``anchor``: n flags; ``base``: n + 1 values) the ``base`` of the last anchored point at or
    before it (point 0 where none) and of the first at or after it (the closing index ``n`` where none):
    ``(low, high)`` (:meth:`~.lsq_model.OutlineRegression._parameter_bounds`)."""
    n = anchor.shape[0]
    low, high = np.empty(n), np.empty(n)
    _anchors_into(np.ascontiguousarray(anchor, dtype=np.bool_), _floats(base), low, high)
    return low, high


@njit(**_JIT)
def _crack_normals_into(points, normals):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for j in range(points.shape[0]):
        fx = points[j, 0] - np.floor(points[j, 0])
        fy = points[j, 1] - np.floor(points[j, 1])
        whole_x = fx < 1e-9 or fx > 1.0 - 1e-9
        whole_y = fy < 1e-9 or fy > 1.0 - 1e-9
        half_x = np.abs(fx - 0.5) < 1e-9
        half_y = np.abs(fy - 0.5) < 1e-9
        if whole_x and half_y:  # a vertical crack
            normals[j, 0], normals[j, 1] = 1.0, 0.0
        elif half_x and whole_y:
            normals[j, 0], normals[j, 1] = 0.0, 1.0
        else:
            return False
    return True


def crack_normals(points):
    """Per point of a crack outline the unit normal of its crack, ``(1, 0)`` for a vertical crack (integer x,
    half-integer y, both within 1e-9), ``(0, 1)`` for a horizontal one; None when not every point is such a midpoint
    (:func:`~.lsq_setup.crack_normals`)."""
    normals = np.empty(points.shape)
    return normals if _crack_normals_into(_floats(points), normals) else None


@njit(**_JIT)
def _removal_scores_into(bezier, starts, ends, values, bend, scores):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    k = starts.shape[0]
    at = np.int64(0)
    for q in range(values.shape[0]):
        at = _walk_left(starts, values[q], at)
        right = pyclip(at, 0, k - 1)  # the interval starting at the knot, and the one before it
        left = right - 1 if right > 0 else k - 1
        h_left, h_right = ends[left] - starts[left], ends[right] - starts[right]
        jump0 = jump1 = bend0 = bend1 = 0.0
        for d in range(2):
            # the third derivative of each cubic, 6 (b3 - 3 b2 + 3 b1 - b0) / h^3, and the second at the start of the
            # right one and the end of the left one, 6 (b2 - 2 b1 + b0) / h^2 and 6 (b3 - 2 b2 + b1) / h^2
            third_right = 6.0 * (bezier[right, 3, d] - 3 * bezier[right, 2, d] + 3 * bezier[right, 1, d]
                                 - bezier[right, 0, d]) / h_right ** 3.0
            third_left = 6.0 * (bezier[left, 3, d] - 3 * bezier[left, 2, d] + 3 * bezier[left, 1, d]
                                - bezier[left, 0, d]) / h_left ** 3.0
            second_start = 6.0 * (bezier[right, 2, d] - 2 * bezier[right, 1, d] + bezier[right, 0, d]) / (
                h_right * h_right)
            second_end = 6.0 * (bezier[left, 3, d] - 2 * bezier[left, 2, d] + bezier[left, 1, d]) / (h_left * h_left)
            if d == 0:
                jump0, bend0 = third_right - third_left, second_start - second_end
            else:
                jump1, bend1 = third_right - third_left, second_start - second_end
        span = 0.5 * (h_left + h_right)
        score = np.hypot(jump0, jump1) * span ** 3.0 / 48.0
        if bend:
            score = np.hypot(bend0, bend1) * (span * span) / 16.0 + score
        scores[q] = score


def removal_scores(bezier, starts, ends, values, bend):
    """Per knot at ``values`` (parameters of knots of the pieces ``bezier`` on ``[starts, ends]``): the jump of the
    third derivative across it times ``h^3 / 48`` (``h`` the mean of the two intervals beside it; the interval
    before the first is the last), plus with ``bend`` (knots where the second derivative may jump) that jump times
    ``h^2 / 16``, in numpy's arithmetic (``h ** 3`` its ``pow``;
    :meth:`~.lsq_model.OutlineRegression.removal_scores`)."""
    values = _floats(values)
    scores = np.empty(values.shape[0])
    _removal_scores_into(_floats(bezier), _floats(starts), _floats(ends), values, bool(bend), scores)
    return scores


def zone_points_beside(samples, row, axis, along_start, across_start, slack):
    """The zone test of :func:`hook_tests` on given samples (rows, count, 2): per point, whether every sample of
    its row lies farther than ``slack`` from its pixel-centre segment."""
    return hook_tests(_NO_CUBE, _NO_FLOATS, _NO_FLOATS, _NO_FLOATS, _NO_POINTS, _NO_FLOATS, _NO_FLOATS, _NO_FLOATS,
                      samples.shape[0], row, axis, along_start, across_start, slack, samples)[1]


@njit(**_HELPER)
def _nearer_edges(px, py, line, j, least):
    """The least of ``least`` and the squared distances of ``(px, py)`` from the two edges at vertex ``j`` of the
    closed polyline ``line`` (from it, and to it): the arithmetic of :func:`~.geometry.segment_squared_distances`."""
    m = line.shape[0]
    for e in (j, j - 1 if j > 0 else m - 1):
        f = e + 1 if e + 1 < m else 0
        abx, aby = line[f, 0] - line[e, 0], line[f, 1] - line[e, 1]
        apx, apy = px - line[e, 0], py - line[e, 1]
        denom = abx * abx + aby * aby
        t = pyclip((apx * abx + apy * aby) / (denom if denom > 0 else 1.0), 0.0, 1.0)
        rx, ry = apx - t * abx, apy - t * aby
        squared = rx * rx + ry * ry
        if squared < least:
            least = squared
    return least


@njit(**_JIT)
def _closed_polyline_into(points, line, half_edge, offsets, candidates, out):
    """:func:`closed_polyline_distance` into ``out``: per point the vertices ``candidates[offsets[i]:offsets[i +
    1]]`` (every vertex where ``offsets`` is empty), the nearest of them, then the edges at those within reach."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    m = line.shape[0]
    every = offsets.shape[0] == 0
    for i in range(points.shape[0]):
        px, py = points[i, 0], points[i, 1]
        count = m if every else offsets[i + 1] - offsets[i]
        nearest = np.inf
        for r in range(count):
            j = r if every else candidates[offsets[i] + r]
            dx, dy = line[j, 0] - px, line[j, 1] - py
            squared = dx * dx + dy * dy
            if squared < nearest:
                nearest = squared
        reach = np.sqrt(nearest) + half_edge + 1e-6
        reach *= reach
        least = np.inf
        for r in range(count):
            j = r if every else candidates[offsets[i] + r]
            dx, dy = line[j, 0] - px, line[j, 1] - py
            if dx * dx + dy * dy <= reach:
                least = _nearer_edges(px, py, line, j, least)
        out[i] = np.sqrt(least)


#: Above this many point-vertex pairs, :func:`closed_polyline_distance` first narrows each point's vertices to a
#: ball that holds every vertex within its reach (a k-d tree): an outline of many corners (a comb, noise) has as
#: many tips as corners, and every tip against every vertex grew with the square of its size.
POLYLINE_PAIRS = 1 << 22


def closed_polyline_distance(points, line, half_edge):
    """Distance (px) of each of ``points`` from the closed polyline ``line`` (first point not repeated), exact:
    the least point-to-segment distance over the edges with an end within the nearest vertex's distance plus
    ``half_edge`` (half the longest edge, and 1e-6: no other edge comes nearer), each the arithmetic of
    :func:`~.geometry.segment_squared_distances`, then its square root (the corner tips' distance from the
    contour, :func:`~.tips.tip_estimates`; one pass instead of a points-by-vertices grid). Above
    :data:`POLYLINE_PAIRS` point-vertex pairs each point looks only at the vertices of a ball (``scipy``'s k-d
    tree) a little larger than its reach, which holds every vertex the pass would use: the same result."""
    points, line = _floats(points), _floats(line)
    out = np.empty(points.shape[0])
    offsets, candidates = _NO_INTS, _NO_INTS
    if points.shape[0] * line.shape[0] > POLYLINE_PAIRS:
        from scipy.spatial import cKDTree

        tree = cKDTree(line)
        nearest = tree.query(points)[0]
        balls = tree.query_ball_point(points, nearest * (1.0 + 1e-9) + half_edge + 1e-5, return_sorted=True)
        sizes = np.fromiter((len(ball) for ball in balls), np.int64, len(balls))
        offsets = np.zeros(len(balls) + 1, np.int64)
        np.cumsum(sizes, out=offsets[1:])
        candidates = np.fromiter((j for ball in balls for j in ball), np.int64, int(offsets[-1]))
    _closed_polyline_into(points, line, float(half_edge), offsets, candidates, out)
    return out


def curve_points(bez, starts, ends, u):
    """Points of the piecewise curve whose piece ``k`` is ``bez[k]`` on ``[starts[k], ends[k]]`` at the
    parameters ``u`` (the piece of ``u`` by searchsorted right, clipped to the pieces;
    :meth:`~.lsq_model.OutlineRegression.curve_at`)."""
    bez, u = _floats(bez), _floats(u)
    out = np.empty((u.shape[0], bez.shape[2]))
    _curve_into(bez, _floats(starts), _floats(ends), u, _NO_INTS, False, out)
    return out


@njit(**_JIT)
def _samples_into(bez, spacing, starts, ends, counts, count_only, points, params, interval):
    """With ``count_only``: per piece ``max(3, ceil(length of its control polygon / spacing))`` into ``counts``;
    returns their sum. Else the samples of the pieces by those counts into ``points``, ``params`` and
    ``interval``."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    if count_only:
        total = np.int64(0)
        for k in range(bez.shape[0]):
            length = np.hypot(bez[k, 1, 0] - bez[k, 0, 0], bez[k, 1, 1] - bez[k, 0, 1])
            length += np.hypot(bez[k, 2, 0] - bez[k, 1, 0], bez[k, 2, 1] - bez[k, 1, 1])
            length += np.hypot(bez[k, 3, 0] - bez[k, 2, 0], bez[k, 3, 1] - bez[k, 2, 1])
            counts[k] = pymax(3, np.int64(np.ceil(length / spacing)))
            total += counts[k]
        return total
    row = np.int64(0)  # not the literal 0: that would compile _bezier_point a second time
    for k in range(bez.shape[0]):
        width = ends[k] - starts[k]
        for q in range(counts[k]):
            theta = q / counts[k]
            _bezier_point(bez, k, theta, points, row)
            params[row] = starts[k] + theta * width
            interval[row] = k
            row += 1
    return row


def interval_samples(bez, starts, ends, spacing, closed=None):
    """Samples of every knot interval's Bézier about ``spacing`` apart by the length of its control polygon
    (at least 3, the interval's end left to the next one): points, parameters and interval numbers
    (:meth:`~.lsq_model.OutlineRegression.deviations`, docs/capture.md §12, "Stopping rule"). With ``closed``, the
    parameters have that value appended (the period: the closed parameters of :func:`deviation_measures`)."""
    bez = _floats(bez)
    starts, ends, spacing = _floats(starts), _floats(ends), float(spacing)
    counts = np.empty(bez.shape[0], np.int64)
    total = _samples_into(bez, spacing, starts, ends, counts, True, _NO_POINTS, _NO_FLOATS, _NO_INTS)
    extra = closed is not None
    points, params, interval = np.empty((total, 2)), np.empty(total + extra), np.empty(total, np.int64)
    _samples_into(bez, spacing, starts, ends, counts, False, points, params, interval)
    if extra:
        params[total] = closed
    return points, params, interval


@njit(**_JIT)
def _group_max_into(groups, values, best, at):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for j in range(groups.shape[0]):
        _group_update(best, at, 0, groups[j], values[j], j)
    _group_close(best, at)


@njit(**_HELPER)
def _group_update(best, at, row, g, v, j):
    """One member ``j`` (value ``v``) of group ``g`` into row ``row`` of :func:`group_max`'s ``best`` and ``at``: the
    first member, a larger value, or a NaN where the best is not NaN takes the group."""
    if at[row, g] < 0 or v > best[row, g] or (np.isnan(v) and not np.isnan(best[row, g])):
        best[row, g], at[row, g] = v, j


@njit(**_HELPER)
def _group_close(best, at):
    """The index 0 for the empty groups and the NaN maxima of :func:`group_max`."""
    for row in range(best.shape[0]):
        for g in range(best.shape[1]):
            if at[row, g] < 0 or np.isnan(best[row, g]):
                at[row, g] = 0


@njit(**_JIT)
def _interval_worst_into(data_iv, data_zone, d_data, tol_data, curve_iv, curve_zone, d_curve, tol_curve, best, at):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for j in range(data_iv.shape[0]):
        excess = d_data[j] - tol_data[j]
        _group_update(best, at, 0, data_iv[j], -np.inf if data_zone[j] else excess, j)
        _group_update(best, at, 2, data_iv[j], excess if data_zone[j] else -np.inf, j)
    for j in range(curve_iv.shape[0]):
        excess = d_curve[j] - tol_curve[j]
        _group_update(best, at, 1, curve_iv[j], -np.inf if curve_zone[j] else excess, j)
        _group_update(best, at, 3, curve_iv[j], excess if curve_zone[j] else -np.inf, j)
    _group_close(best, at)


def interval_worst(data_iv, data_zone, d_data, tol_data, curve_iv, curve_zone, d_curve, tol_curve, count):
    """Per knot interval (``count`` of them) the worst excess ``d - tol`` of the probes (``data_iv``, ``data_zone``,
    ``d_data``, ``tol_data``) and of the curve samples (``curve_*``) outside the corner zones (``-inf`` inside) and
    inside them (``-inf`` outside), each with the index where it occurs: :func:`group_max` of the four, rows
    ``(data outside, curve outside, data inside, curve inside)`` of ``(best, at)``
    (:meth:`~.lsq_model.OutlineRegression.insert`)."""
    best, at = np.full((4, int(count)), -np.inf), np.full((4, int(count)), -1, np.int64)
    _interval_worst_into(_ints(data_iv), np.ascontiguousarray(data_zone, dtype=np.bool_), _floats(d_data),
                         _floats(tol_data), _ints(curve_iv), np.ascontiguousarray(curve_zone, dtype=np.bool_),
                         _floats(d_curve), _floats(tol_curve), best, at)
    return best, at


@njit(**_JIT)
def _search_into(values, keys, right, out):
    """Per key the count of ``values`` (sorted, no NaN) below it (``right``: not above it), from the
    previous key's answer: a galloping search forwards, a binary search backwards (linear total work for
    sorted keys, any order allowed)."""
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    n = values.shape[0]
    position = 0
    for j in range(keys.shape[0]):
        x = keys[j]
        if x != x:  # NaN sorts after every value
            out[j] = n
            continue
        if position > 0 and not (values[position - 1] <= x if right else values[position - 1] < x):
            lo, hi = 0, position - 1
        else:
            lo, hi, step = position, position, 1
            while hi < n and (values[hi] <= x if right else values[hi] < x):
                lo, hi, step = hi + 1, pymin(hi + step, n), 2 * step
        while lo < hi:
            mid = (lo + hi) // 2
            if values[mid] <= x if right else values[mid] < x:
                lo = mid + 1
            else:
                hi = mid
        position = out[j] = lo


def search_sorted(values, keys, side="left"):
    """``numpy.searchsorted(values, keys, side)`` for sorted ``values`` without NaN, in one pass that walks
    forward from each key's answer to the next (the keys of the fit's deviation check are sorted)."""
    keys = _floats(keys)
    out = np.empty(keys.shape[0], np.int64)
    _search_into(_floats(values), keys, side == "right", out)
    return out


def group_max(groups, values, count):
    """Per group ``g < count`` (``groups`` non-decreasing): the maximum of ``values`` (``-inf`` if empty; NaN
    wins, as in ``numpy.maximum``) and the first index where it occurs (0 for empty groups and NaN maxima)."""
    best, at = np.full((1, int(count)), -np.inf), np.full((1, int(count)), -1, np.int64)  # the empty groups' answers
    _group_max_into(_ints(groups), _floats(values), best, at)
    return best[0], at[0]


_WARM = []


@njit(**_JIT)
def _separating_slope_into(t_ink, y_ink, t_paper, y_paper, slopes, step, rounds, grid, out):
    compact()  # run time negligible or no slower: code optimized for size (_jit.compact)
    for _ in range(rounds):
        best, best_gap = np.int64(0), -np.inf
        for i in range(slopes.shape[0]):
            above = np.inf
            for j in range(t_ink.shape[0]):
                value = y_ink[j] - slopes[i] * t_ink[j]
                if value < above:
                    above = value
            below = -np.inf
            for j in range(t_paper.shape[0]):
                value = y_paper[j] - slopes[i] * t_paper[j]
                if value > below:
                    below = value
            gap = above - below
            if gap > best_gap:  # the first of equal gaps, as numpy.argmax
                best, best_gap = i, gap
        slope = slopes[best]
        # the next grid: numpy.linspace(slope - step, slope + step, n) in its arithmetic (tips._slope_grid)
        start, stop = slope - step, slope + step
        n = grid.shape[0]
        delta = (stop - start) / (n - 1)
        for k in range(n):
            grid[k] = (k * delta if delta != 0 else k / (n - 1) * (stop - start)) + start
        grid[n - 1] = stop
        slopes = grid
        step = step / 8
        out[0] = slope


def separating_slope(t_ink, y_ink, t_paper, y_paper, first_slopes, step, rounds):
    """The slope ``c1`` of :func:`~.tips._separating_line`'s search: per round, of the grid ``slopes`` the one
    with the largest gap between the lowest ink offset ``y - c1 t`` and the highest paper offset (the first
    of equal ones), then a grid of as many slopes from ``c1 - step`` to ``c1 + step`` and ``step / 8``;
    ``rounds`` rounds. Bit for bit the numpy formulation it replaced (``tests/test_kernels.py``)."""
    out = np.empty(1)
    grid = np.empty(first_slopes.shape[0])
    _separating_slope_into(_floats(t_ink), _floats(y_ink), _floats(t_paper), _floats(y_paper),
                           _floats(first_slopes), float(step), int(rounds), grid, out)
    return float(out[0])


def warm_up():
    """Compile (empty cache) or load (``cache=True``) every kernel that a fit uses, once per process, on
    tiny inputs: :func:`~splinecraft.capture.trace.trace` calls this before its time budget starts, so the
    first-call cost never eats into the budget (docs/capture.md §12, "Time budget"). Two halves of about equal
    compile time, :func:`warm_up_solves` and :func:`warm_up_checks`, which :func:`.._jit.warm_up` may run in
    two processes at once."""
    if _WARM:
        return
    warm_up_solves()
    warm_up_checks()
    _WARM.append(True)


def _tiny_fit():
    """The tiny inputs of the warm-ups: knots, parameters, two Bézier segments, their intervals, an index."""
    knots = np.arange(7.0)
    full = np.concatenate([knots[-3:] - 7.0, knots, knots[:4] + 7.0])
    return (full, np.linspace(0.0, 6.5, 8), np.cumsum(np.ones((2, 4, 2)), axis=1), np.array([0.0, 1.0]),
            np.array([1.0, 2.0]), np.zeros(2, np.int64))


def warm_up_solves():
    """The first half of :func:`warm_up`: the normal equations, their solve, the spline's values, the
    parameter correction and the first knots (the separating line's slope search of extrapolated tips compiles with
    its caller, the tips' warm-up task: ``_tip_kernels.warm_up``). (Bézier evaluation,
    :func:`eval_bezier`, is the kernel of :func:`curve_points`: :func:`warm_up_checks` compiles it once, where
    both halves compiled it when they ran in separate processes.)"""
    full, u, bez, starts, ends, index = _tiny_fit()
    normal_equations(full, u, np.ones(10), np.ones((10, 2)), 7, 1e-8, np.array([0.5, 6.0]))
    fit_step(np.ones((7, 2)), full, 7, starts, ends, np.array([0.0, 0.5]), np.ones((4, 2)), np.array([0.5, 1.5]),
             np.ones((2, 2)), index, 1, 1.0, (np.zeros(2), np.full(2, 2.0), np.zeros(2, np.bool_), np.zeros(2)))
    seed_knots(np.ones((16, 2)), np.arange(17.0), 16.0, np.zeros(16), True, np.array([0, 16]), np.zeros(1, np.int64),
               1.0, 1.0, 1, 0.0)
    knot_vector(np.array([0.0]), np.array([2.0, 3.0]), np.ones(2, np.int64), 7.0)
    removal_scores(bez, starts, ends, np.array([1.0]), True)
    closed = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [0.0, 0.0]])
    corner_radii(np.array([0.0, 2.0, 4.0, 6.0]), closed, np.array([0, 2, 3]), 2.0)
    corner_tables(np.ones(2), np.ones(2), np.zeros(2, np.bool_), np.zeros(2), index, np.zeros(2), True)
    corner_weights(np.ones(2), index, np.zeros(2), np.zeros(2, np.bool_))
    anchor_bounds(np.ones(2, np.bool_), np.zeros(3))
    crack_normals(np.full((1, 2), 0.5))
    contour_tables(np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [0.0, 0.0]]), np.array([0, 2, 3]), 2)
    closed_polyline_distance(np.ones((1, 2)), np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]), 1.0)


def warm_up_deviation():
    """The first step of :func:`warm_up_checks`: the curve's samples and the dense deviation check, which a
    background compile runs before its tasks (``_jit.BACKGROUND_FIRST``)."""
    _, _, bez, starts, ends, index = _tiny_fit()
    samples, params, iv = interval_samples(bez, starts, ends, 0.5, 2.0)
    deviation_measures(bez, starts, ends, samples, params, iv, np.array([0.0, 2.0]), np.array([0, 3]), True,
                       np.array([0.0, 0.7, 1.4, 2.0]), np.array([0.0, 0.7, 1.4, 2.0]), np.ones((5, 3)),
                       np.ones((2, 2)), np.array([0.5, 1.5]), index, np.ones(2, np.bool_), np.ones(4), np.zeros(4),
                       np.zeros(2), 1.0, 0.0, 2)


def warm_up_checks():
    """The second half of :func:`warm_up`: the dense deviation check first (the costliest kernel where a cold first
    trace runs the kernels interpreted: compiled first, it is in place the sooner, docs/capture.md), then curve
    points, the corner tests after a fit and their window, the per-group maxima, the small-outline fit's nearest
    segments (``windowed_distance`` and ``search_sorted`` are no longer in a trace and compile where used); the
    task's last kernel, ``_nearest_segments_into``, tells whether it is cold (``_jit.WARM_UP_TASKS``)."""
    _, _, bez, starts, ends, index = _tiny_fit()
    warm_up_deviation()
    curve_points(bez, starts, ends, np.array([0.1, 1.5]))
    hook_tests(bez, starts, ends, np.array([0.5]), np.ones((1, 2)), np.ones(1), np.ones(1), np.array([0.2, 1.2]), 1,
               np.zeros(1, np.int64), np.ones(1, np.int64), np.zeros(1), np.zeros(1), 0.1)
    zone_window(np.ones(1), np.zeros(1, np.bool_), np.zeros(2, np.int64), np.zeros(2), np.zeros(1), np.zeros(1),
                np.zeros(1), np.ones(2), np.ones((2, 2)), 4.0, 0.1)
    group_max(index, np.ones(2), 1)
    interval_worst(index, np.zeros(2, np.bool_), np.ones(2), np.ones(2), index, np.ones(2, np.bool_), np.ones(2), np.ones(2), 1)
    nearest_segment_distance(*(np.ones((1, 2)),) * 6)


@njit(**_HELPER)
def _walk_right(values, x, position):
    """``numpy.searchsorted(values, x, "right")`` for ``values`` sorted without NaN, walked from the answer
    ``position`` of a nearby key (linear total work for sorted keys, exact from any start). Two functions, not
    one with a flag: the literal flag of each call would compile a version of its own."""
    n = values.shape[0]
    if x != x:  # NaN sorts after every value
        return n
    while position > 0 and values[position - 1] > x:
        position -= 1
    while position < n and values[position] <= x:
        position += 1
    return position


@njit(**_HELPER)
def _walk_left(values, x, position):
    """``numpy.searchsorted(values, x, "left")``, walked as :func:`_walk_right`."""
    n = values.shape[0]
    if x != x:
        return n
    while position > 0 and values[position - 1] >= x:
        position -= 1
    while position < n and values[position] < x:
        position += 1
    return position


@njit(**_HELPER)
def _larger(a, b):
    """``numpy.maximum(a, b)`` of two floats: ``a`` where it is NaN or larger, else ``b``."""
    if a != a or a > b:
        return a
    return b


@njit(**_JIT)
def _deviation_into(bez, starts, ends, samples, closed_params, iv, corner_par, bounds, cornered, parameter, base, edges,
                    probes, probe_u, fill_u, probe_piece, is_point, zone, allowance, probe_allowance, epsilon, loose_above,
                    reach, point_side, probe_side_sign, curve_out, curve_zone, data_out, data_iv, excess, piece_out):
    """:func:`deviation_measures` into ``curve_out`` (rows d_curve, tol_curve), ``data_out`` (rows d_data,
    tol_data), ``excess`` and ``piece_out`` (rows piece_dev, piece_err, piece_excess; these two filled with -inf
    by the wrapper): outputs of one length share an array, and so do the edge table's five columns (every array
    argument costs its unboxing in the compiled Python wrapper)."""
    n = parameter.shape[0] - 1
    pieces = piece_out.shape[1]
    k = starts.shape[0]
    total = samples.shape[0]
    last = k - 1
    # curve -> contour: each sample to the contour edges around its corresponding contour position
    # the searches' answers for the previous key (not the literal 0: that would compile the walks twice)
    at_corner = at_parameter = at_base = at_base_right = np.int64(0)
    for s in range(total):
        u = closed_params[s]
        at_corner = _walk_right(corner_par, u, at_corner)
        at_parameter = _walk_left(parameter, u, at_parameter)
        piece = pyclip(at_corner - 1, 0, pieces - 1)
        centre = pyclip(at_parameter - 1, 0, n - 1)
        best = np.inf
        best_side = 0.0
        # values read once as float (interpreted, Python floats are ~3x faster than numpy's scalars; compiled the
        # same code): the same operations in the same order
        sx, sy = float(samples[s, 0]), float(samples[s, 1])
        for offset in range(-1, 2):
            e = centre + offset
            if cornered:  # the piece's own edges, and 3 more across each corner
                e = pyclip(e, bounds[piece] - 3, bounds[piece + 1] + 2)
            e = _wrapped(e, n)
            ex, ey = float(edges[2, e]), float(edges[3, e])
            px = sx - float(edges[0, e])
            py = sy - float(edges[1, e])
            side = ex * py - ey * px
            t = (px * ex + py * ey) * float(edges[4, e])
            t = pyclip(t, 0.0, 1.0)
            px -= t * ex
            py -= t * ey
            squared = px * px + py * py
            if squared < best:
                best = squared
                best_side = side
        d = np.sqrt(best)
        curve_out[0, s] = d
        # numpy.interp(u, base, zone) > 0 in numpy's arithmetic: the interval base[j] <= u < base[j + 1], the
        # end values outside it, zone[j] at u == base[j], else slope * (u - base[j]) + zone[j] (and its retries)
        if u != u:
            value = u
        elif u > base[n]:
            value = zone[n]
        elif u < base[0]:
            value = zone[0]
        else:
            at_base_right = _walk_right(base, u, at_base_right)
            j = at_base_right - 1
            if j >= n or base[j] == u:
                value = zone[pymin(j, n)]
            elif zone[j] == zone[j + 1]:  # slope 0 (base increases): 0 * (u - base[j]) + zone[j] for finite u
                value = zone[j]
            else:
                value = _interpolated(u, base, zone, j)
        inside = value > 0
        curve_zone[s] = inside
        extra = 0.0
        if inside:
            at_base = _walk_left(base, u, at_base)
            nearest = pyclip(at_base, 0, n)
            a, b = allowance[nearest], allowance[pymax(nearest - 1, 0)]
            extra = _larger(a, b)
            if point_side.shape[0] and best_side * point_side[nearest] > 0.0:
                extra = 0.0  # the curve on the other side of the contour than the corner's tip: no allowance
        curve_out[1, s] = epsilon + extra
        ex_curve = d - curve_out[1, s]
        excess[iv[s]] = _larger(excess[iv[s]], ex_curve)
        piece_out[0, piece] = _larger(piece_out[0, piece], d)
        piece_out[2, piece] = _larger(piece_out[2, piece], ex_curve)
    # contour -> curve: each probe to its corresponding curve point, refined where loose by the nearest chord
    # of the curve samples (closed by the last piece's end point) within ``reach`` samples
    at_start = at_end = at_lo = at_hi = at_centre = np.int64(0)
    for p in range(probe_u.shape[0]):
        if fill_u:  # the dense probes: the contour points' parameters and their edge midpoints' means, alternating
            half = p // 2
            probe_u[p] = parameter[half] if p - 2 * half == 0 else 0.5 * (parameter[half] + parameter[half + 1])
        u = probe_u[p]
        at_start = _walk_right(starts, u, at_start)
        seg = pyclip(at_start - 1, 0, last)
        theta = (u - starts[seg]) / (ends[seg] - starts[seg])
        s1 = 1.0 - theta
        t2, s2 = theta * theta, s1 * s1
        w0 = s2 * s1
        w1 = 3.0 * theta * s2
        w2 = 3.0 * t2 * s1
        w3 = t2 * theta
        cx = w0 * bez[seg, 0, 0] + w1 * bez[seg, 1, 0] + w2 * bez[seg, 2, 0] + w3 * bez[seg, 3, 0]
        cy = w0 * bez[seg, 0, 1] + w1 * bez[seg, 1, 1] + w2 * bez[seg, 2, 1] + w3 * bez[seg, 3, 1]
        d = np.hypot(cx - probes[p, 0], cy - probes[p, 1])
        # the probe's side of the curve (its tangent there): on the paper side the curve cuts into the ink
        tx = s2 * (bez[seg, 1, 0] - bez[seg, 0, 0]) + 2.0 * theta * s1 * (bez[seg, 2, 0] - bez[seg, 1, 0]) \
            + t2 * (bez[seg, 3, 0] - bez[seg, 2, 0])
        ty = s2 * (bez[seg, 1, 1] - bez[seg, 0, 1]) + 2.0 * theta * s1 * (bez[seg, 2, 1] - bez[seg, 1, 1]) \
            + t2 * (bez[seg, 3, 1] - bez[seg, 2, 1])
        probe_side = tx * (probes[p, 1] - cy) - ty * (probes[p, 0] - cx)
        if d > loose_above:
            piece = probe_piece[p]
            at_lo = _walk_left(closed_params, corner_par[piece], at_lo)
            at_hi = _walk_right(closed_params, corner_par[piece + 1], at_hi)
            at_centre = _walk_left(closed_params, u, at_centre)
            lo = at_lo
            hi = pymax(at_hi - 2, lo)
            centre = pyclip(at_centre, lo, hi)
            best = np.inf
            qx, qy = float(probes[p, 0]), float(probes[p, 1])
            for offset in range(-reach, reach + 1):
                e = centre + offset
                if cornered:  # the piece's own chords and a window across its corners
                    e = pyclip(e, lo - reach, hi + reach)
                e = _wrapped(e, total)
                ax, ay = float(samples[e, 0]), float(samples[e, 1])
                if e + 1 < total:
                    bx, by = float(samples[e + 1, 0]), float(samples[e + 1, 1])
                else:
                    bx, by = float(bez[last, 3, 0]), float(bez[last, 3, 1])
                dx, dy = bx - ax, by - ay
                den = dx * dx + dy * dy
                inverse = 1.0 / (den if den > 0 else 1.0)
                px = qx - ax
                py = qy - ay
                t = (px * dx + py * dy) * inverse
                t = pyclip(t, 0.0, 1.0)
                px -= t * dx
                py -= t * dy
                squared = px * px + py * py
                if squared < best:
                    best = squared
            near = np.sqrt(best)
            if near < d or near != near:
                d = near
        data_out[0, p] = d
        data_out[1, p] = epsilon + (0.0 if probe_side_sign.shape[0] and probe_side * probe_side_sign[p] < 0.0
                                    else probe_allowance[p])
        at_end = _walk_left(ends, u, at_end)
        interval = pyclip(at_end, 0, last)
        data_iv[p] = interval
        ex_data = d - data_out[1, p]
        excess[interval] = _larger(excess[interval], ex_data)
        piece = probe_piece[p]
        piece_out[0, piece] = _larger(piece_out[0, piece], d)
        piece_out[2, piece] = _larger(piece_out[2, piece], ex_data)
        if is_point[p]:
            piece_out[1, piece] = _larger(piece_out[1, piece], d)
    for g in range(pieces):
        piece_out[0, g] = _larger(piece_out[0, g], 0.0)
        piece_out[1, g] = _larger(piece_out[1, g], 0.0)


def deviation_measures(bez, starts, ends, samples, closed_params, iv, corner_par, bounds, cornered, parameter, base,
                       edges, probes, probe_u, probe_piece, is_point, zone, allowance, probe_allowance, epsilon,
                       loose_above, reach, point_side=_NO_FLOATS, probe_side_sign=_NO_FLOATS):
    """The deviation check of the current fit in one pass (:meth:`~.lsq_model.OutlineRegression.deviations`,
    docs/capture.md §12, "Stopping rule"), the operations of its numpy formulation in their order:
    the windowed closest-point distance of every curve sample (``samples``, ``closed_params`` -- the samples'
    parameters and the period --, interval ``iv``) to the contour edges (``edges``, :func:`~.geometry.edge_table`),
    its tolerance (``epsilon``, plus the largest ``allowance`` of the two contour points around it where
    ``numpy.interp`` of ``zone`` is positive) and its piece; every probe's distance to its corresponding curve point
    (``probe_u``; None: the dense probes' parameters, the contour points' ``parameter`` and their edge midpoints'
    means alternating, returned as ``"probe_u"``), refined above ``loose_above`` by the chords of the curve samples
    within ``reach`` samples (clipped to the probe's piece and ``reach`` more); then the per-interval worst excess
    and the per-piece maxima (``-inf`` for empty groups, NaN wins, as :func:`group_max` and ``numpy.maximum``).
    Returns the dict entries of ``deviations``. The arrays are the fit's own (float64, int64 or bool, contiguous):
    taken as they are."""
    total, count, pieces = samples.shape[0], probes.shape[0], corner_par.shape[0] - 1
    fill_u = probe_u is None
    probe_u = np.empty(count) if fill_u else probe_u
    curve_out, curve_zone = np.empty((2, total)), np.empty(total, np.bool_)
    data_out, data_iv = np.empty((2, count)), np.empty(count, np.int64)
    excess, piece_out = np.full(starts.shape[0], -np.inf), np.full((3, pieces), -np.inf)
    _deviation_into(bez, starts, ends, samples, closed_params, iv, corner_par, bounds, bool(cornered), parameter, base,
                    edges, probes, probe_u, fill_u, probe_piece, is_point, zone, allowance, probe_allowance,
                    float(epsilon), float(loose_above), int(reach), point_side, probe_side_sign, curve_out, curve_zone,
                    data_out, data_iv, excess, piece_out)
    return {"excess": excess, "piece_dev": piece_out[0], "piece_err": piece_out[1], "piece_excess": piece_out[2],
            "d_data": data_out[0], "tol_data": data_out[1], "data_iv": data_iv, "d_curve": curve_out[0],
            "tol_curve": curve_out[1], "curve_zone": curve_zone, "probe_u": probe_u}
