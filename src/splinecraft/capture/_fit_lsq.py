"""Least-squares machinery of the default knot method ``"lsq"`` (private to :mod:`~splinecraft.capture.fitting`).

Model
-----
The whole closed outline is one periodic cubic spline ``S(u)`` in the contour's arc-length parameter ``u``:
every corner is a knot of multiplicity 3 (the curve is ``C^0`` there: the two pieces share the corner point
and nothing else) and every inserted knot is simple (``C^2``). Between two corners this is exactly the
family of the thesis's GC² interpolant with ``v = 0`` and ``omega = 1`` (§2.2-2.4, Type 1 clamped ends):
a ``C^2`` cubic on given knots is fixed by its knot points ``F_i`` and its two end tangents, and every choice
of those is such a spline (§4.5, cross-check). The interpolant is *linear* in ``(F_1..F_n, M_1, M_n)``,
so choosing them to minimise the squared distance to all contour points of the piece is a linear least-squares
problem (a regression spline in the generic model). It is solved here in the B-spline basis of the same
space, for the whole outline at once, with the corner points as shared unknowns: corners move to where both
neighbouring pieces want them (for acute corners beyond the truncated pixel tip).

Everything is vectorized: the basis values of all data points (Cox-de Boor, four non-zero functions per point),
one banded normal-equation solve, Hoschek parameter correction (one Newton projection step of every contour
point onto the curve), Bézier extraction of every knot interval and windowed closest-point deviations.
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import solveh_banded

# Bézier control points from the values at theta = 0, 1/3, 2/3, 1 (inverse cubic Bernstein matrix).
_THETA4 = np.array([0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0])
_FROM_SAMPLES = np.linalg.inv(
    np.stack([(1 - _THETA4) ** 3, 3 * _THETA4 * (1 - _THETA4) ** 2, 3 * _THETA4**2 * (1 - _THETA4), _THETA4**3],
             axis=1)
)


def periodic_knot_vector(knots: np.ndarray, period: float) -> np.ndarray:
    """Full knot vector ``tau_{-3} .. tau_{M+3}`` (length ``M + 7``) of a periodic cubic spline whose knots in
    one period are ``knots = tau_0 .. tau_{M-1}`` in ``[0, period)`` (a repeated value is a multiple knot)."""
    m = knots.shape[0]
    idx = np.arange(-3, m + 4)
    return knots[idx % m] + period * np.floor_divide(idx, m)


def interval_index(full: np.ndarray, u: np.ndarray, side: str = "right") -> np.ndarray:
    """Index ``i`` into ``full`` with ``full[i] <= u < full[i + 1]`` and ``full[i] < full[i + 1]``
    (``side="left"``: ``full[i] < u <= full[i + 1]``, the interval ending at ``u``). Restricted to the
    period ``[full[3], full[-4]]``."""
    i = np.searchsorted(full, u, side=side) - 1
    return np.clip(i, 3, full.shape[0] - 5)


def cubic_basis(full: np.ndarray, i: np.ndarray, u: np.ndarray, derivatives: int = 0):
    """The four non-zero cubic B-splines ``N_{i-3} .. N_i`` at ``u`` (in interval ``i`` of ``full``) and
    optionally their first and second derivatives: a list of ``(n, 4)`` arrays (Cox-de Boor, vectorized)."""
    n = u.shape[0]
    left = np.empty((n, 4))
    right = np.empty((n, 4))
    for j in range(1, 4):
        left[:, j] = u - full[i + 1 - j]
        right[:, j] = full[i + j] - u
    levels = [np.ones((n, 1))]
    N = np.ones((n, 1))
    for j in range(1, 4):
        new = np.zeros((n, j + 1))
        saved = np.zeros(n)
        for r in range(j):
            denom = right[:, r + 1] + left[:, j - r]
            temp = N[:, r] / np.where(denom > 0, denom, 1.0)
            new[:, r] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        new[:, j] = saved
        N = new
        levels.append(N)
    out = [N]
    if derivatives >= 1:
        out.append(_derivative(full, i, levels[2], 3))
    if derivatives >= 2:
        d1_deg2 = _derivative(full, i, levels[1], 2)  # derivatives of the quadratic basis (n, 3)
        out.append(_lift(full, i, d1_deg2, 3))
    return out


def _derivative(full, i, lower, p):
    """Derivatives of the degree-``p`` basis ``N_{i-p} .. N_i`` from the degree ``p - 1`` values ``lower``
    (``N_{i-p+1} .. N_i``): ``N'_{k,p} = p (N_{k,p-1} / (t_{k+p} - t_k) - N_{k+1,p-1} / (t_{k+p+1} - t_{k+1}))``."""
    n = lower.shape[0]
    padded = np.zeros((n, p + 2))
    padded[:, 1:p + 1] = lower
    out = np.zeros((n, p + 1))
    for r in range(p + 1):
        k = i - p + r
        d0 = full[k + p] - full[k]
        d1 = full[k + p + 1] - full[k + 1]
        a = np.where(d0 > 0, padded[:, r] / np.where(d0 > 0, d0, 1.0), 0.0)
        b = np.where(d1 > 0, padded[:, r + 1] / np.where(d1 > 0, d1, 1.0), 0.0)
        out[:, r] = p * (a - b)
    return out


def _lift(full, i, lower_deriv, p):
    """Second derivatives of the degree-``p`` basis from the first derivatives of degree ``p - 1``."""
    return _derivative(full, i, lower_deriv, p)


def folded_columns(i: np.ndarray, m: int) -> np.ndarray:
    """Coefficient indices (n, 4) of ``N_{i-3} .. N_i`` for a periodic spline with ``m`` coefficients
    (``full`` index ``i`` belongs to ``tau_{i-3}``)."""
    return (i[:, None] - 6 + np.arange(4)[None, :]) % m


def evaluate(coef: np.ndarray, cols: np.ndarray, basis: np.ndarray) -> np.ndarray:
    """``sum_k basis[:, k] coef[cols[:, k]]`` (curve points or derivatives)."""
    c = coef[cols]
    return (basis[:, 0, None] * c[:, 0] + basis[:, 1, None] * c[:, 1] + basis[:, 2, None] * c[:, 2]
            + basis[:, 3, None] * c[:, 3])


def solve_normal(cols: np.ndarray, basis: np.ndarray, weights: np.ndarray, targets: np.ndarray, m: int,
                 regularization: float = 1e-8) -> np.ndarray:
    """Weighted least squares ``min sum_j w_j |sum_k N_k(u_j) c_k - Q_j|^2`` for the ``m`` periodic
    coefficients (two right-hand sides, x and y).

    The normal matrix is cyclic with band 3. A tiny second-difference penalty keeps it positive definite
    when a coefficient is barely constrained. Solved as a symmetric banded system (LAPACK ``pbsv``) after
    cutting the cyclic coupling with a Schur complement on the last three coefficients, so the cost is
    O(m) for any outline length.
    """
    wb = basis * weights[:, None]
    flat_cols = cols.reshape(-1)
    rhs = np.empty((m, targets.shape[1]))
    for d in range(targets.shape[1]):
        rhs[:, d] = np.bincount(flat_cols, weights=(wb * targets[:, d, None]).reshape(-1), minlength=m)
    # cyclic band: entry (a, b) with b = a + k (mod m), k = 0..3, stored as band[k, a]
    band = np.zeros((4, m))
    for r in range(4):
        for s_ in range(r, 4):
            band[s_ - r] += np.bincount(cols[:, r], weights=wb[:, r] * basis[:, s_], minlength=m)
    scale = float(band[0].max()) or 1.0
    pen = regularization * scale
    band[0] += 6 * pen  # + pen * D^T D, D the cyclic second difference (rows 1, -2, 1)
    band[1] += -4 * pen
    band[2] += 1 * pen
    if m <= 64:  # small: assemble the dense cyclic matrix (wrapped entries add up, also for m < 7)
        normal = np.zeros((m, m))
        idx = np.arange(m)
        normal[idx, idx] = band[0]
        for k in (1, 2, 3):
            normal[idx, (idx + k) % m] += band[k]
            normal[(idx + k) % m, idx] += band[k]
        return np.linalg.solve(normal, rhs)
    return _solve_cyclic_band(band, rhs)


def _solve_cyclic_band(band, rhs):
    """Solve the symmetric cyclic matrix with upper band ``band[k, a] = A[a, (a + k) % m]`` (k <= 3)."""
    m = band.shape[1]
    w = 3
    # split unknowns: x = [y (m - w), z (w)]; A = [[B, C], [C^T, D]] with B banded (non-cyclic part)
    nb = m - w
    ab = np.zeros((4, nb))  # upper form for solveh_banded: ab[3 - k, j] = B[j - k, j]
    for k in range(4):
        ab[3 - k, k:] = band[k, : nb - k]
    C = np.zeros((nb, w))
    Dm = np.zeros((w, w))
    for k in range(4):
        for a in range(nb - 3, m):
            b = (a + k) % m
            if k == 0 and a >= nb:
                Dm[a - nb, a - nb] += band[0, a]
                continue
            val = band[k, a]
            if val == 0.0 or k == 0:
                continue
            ia, ib = a, b
            if ia < nb and ib < nb:
                continue  # inside B (already stored when b = a + k without wrap)
            if ia >= nb and ib >= nb:
                Dm[ia - nb, ib - nb] += val
                Dm[ib - nb, ia - nb] += val
            elif ia < nb:
                C[ia, ib - nb] += val
            else:
                C[ib, ia - nb] += val
    # B entries that wrapped are none (B is the leading block without wrap); band entries with a < nb,
    # b = a + k < nb are in ab; those with a + k >= m wrap to b < a: handled above (ib < nb, ia >= nb or not)
    rhs_y, rhs_z = rhs[:nb], rhs[nb:]
    sol = solveh_banded(ab, np.hstack([rhs_y, C]), check_finite=False)
    By, BC = sol[:, : rhs.shape[1]], sol[:, rhs.shape[1]:]
    schur = Dm - C.T @ BC
    z = np.linalg.solve(schur, rhs_z - C.T @ By)
    y = By - BC @ z
    return np.vstack([y, z])


def bezier_of_intervals(coef: np.ndarray, full: np.ndarray, m: int, starts: np.ndarray, ends: np.ndarray):
    """Exact Bézier control points (k, 4, 2) of the spline on its knot intervals ``[starts, ends]``."""
    params = (starts[:, None] + (ends - starts)[:, None] * _THETA4[None, :]).reshape(-1)
    i = np.repeat(interval_index(full, starts + 0.5 * (ends - starts)), 4)
    (basis,) = cubic_basis(full, i, params)
    values = evaluate(coef, folded_columns(i, m), basis).reshape(-1, 4, 2)
    return np.einsum("ij,kjd->kid", _FROM_SAMPLES, values)


def sorted_group_max(groups: np.ndarray, values: np.ndarray, count: int) -> np.ndarray:
    """Per group ``g < count`` the maximum of ``values`` (``-inf`` if empty), for non-decreasing ``groups``."""
    out = np.full(count, -np.inf)
    if groups.shape[0] == 0:
        return out
    starts = np.flatnonzero(np.concatenate([[True], groups[1:] != groups[:-1]]))
    out[groups[starts]] = np.maximum.reduceat(values, starts)
    return out


def group_max(groups: np.ndarray, values: np.ndarray, count: int):
    """Per group ``g < count`` (``groups`` non-decreasing): the maximum of ``values`` and the first index where
    it occurs (``-inf`` and 0 for empty groups)."""
    best = sorted_group_max(groups, values, count)
    at = np.zeros(count, dtype=np.int64)
    hits = np.flatnonzero(values == best[groups])
    if hits.size:
        g = groups[hits]
        first = np.concatenate([[True], g[1:] != g[:-1]])
        at[g[first]] = hits[first]
    return best, at


def eval_bezier(bezier: np.ndarray, piece: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Points of the Bézier pieces ``bezier[piece]`` at ``theta`` (vectorized, cubic Bernstein weights)."""
    s = 1.0 - theta
    t2, s2 = theta * theta, s * s
    weights = np.empty((theta.shape[0], 4))
    weights[:, 0] = s2 * s
    weights[:, 1] = 3.0 * theta * s2
    weights[:, 2] = 3.0 * t2 * s
    weights[:, 3] = t2 * theta
    return np.einsum("nj,njd->nd", weights, bezier[piece])


def edge_table(line: np.ndarray):
    """Per edge ``line[e] -> line[e + 1]`` of a polyline: start x, start y, dx, dy and ``1 / |d|^2`` (1 for a
    zero-length edge), the input of :func:`windowed_distance`."""
    dx, dy = np.diff(line[:, 0]), np.diff(line[:, 1])
    den = dx * dx + dy * dy
    return line[:-1, 0].copy(), line[:-1, 1].copy(), dx, dy, 1.0 / np.where(den > 0, den, 1.0)


def windowed_distance(points, centre, lo, hi, edges, window, wrap=0):
    """Distance from ``points[j]`` to the polyline edges ``e = centre[j] - window .. centre[j] + window``,
    clipped to ``[lo[j], hi[j]]`` (if given), then taken modulo ``wrap`` (if > 0); ``edges`` is the
    polyline's :func:`edge_table`.

    Exact point-to-segment distances; the minimum over a subset of the edges, so never below the true
    closest-point distance to the polyline (an upper bound that is tight when the window holds the closest edge,
    which the fit's parameterization ensures)."""
    e = centre[:, None] + np.arange(-window, window + 1)[None, :]
    if lo is not None:
        np.clip(e, lo[:, None], hi[:, None], out=e)
    if wrap:
        e %= wrap
    ax, ay, dx, dy, inverse = edges
    px = points[:, 0, None] - ax.take(e)
    py = points[:, 1, None] - ay.take(e)
    ex, ey = dx.take(e), dy.take(e)
    t = (px * ex + py * ey) * inverse.take(e)
    np.clip(t, 0.0, 1.0, out=t)
    px -= t * ex
    py -= t * ey
    px *= px
    py *= py
    px += py
    return np.sqrt(px.min(axis=1))


class OutlineLSQ:
    """Least-squares fit state of one closed outline (the default method of :func:`fit_outline`).

    Parameters
    ----------
    points : (n, 2) closed contour polyline (first point not repeated).
    corners : sorted unique corner indices into ``points`` (may be empty).
    epsilon : tolerance (px) of the stopping rule.
    corner_radius : contour points closer than this (arc length, px) to a corner get the weight
        ``(distance / corner_radius)^2`` in the fit, so the pieces extrapolate to the corner instead of
        following the pixel-truncated tip.
    corner_allowance : extra tolerance (px) inside a corner zone (arc distance ``< 2 corner_radius + 1``) of a
        corner that is extrapolated; the issue's ``+ half a pixel``. A corner whose zone cannot meet
        ``epsilon + corner_allowance`` is refitted without extrapolation (allowance 0 there).
    min_gap : fewest contour steps between two knots.
    sample_spacing : spacing (px) of the curve samples used for the curve-to-contour deviation.
    hoschek_gate : parameter correction is applied in a piece only once its residuals are below this (px).
    """

    def __init__(self, points, corners, epsilon, *, corner_radius=2.0, corner_allowance=0.5, min_gap=3,
                 sample_spacing=0.5, hoschek_gate=2.0, initial_knots=4, weight_profile="quadratic", tip_gap=0.5,
                 geometric_corners=True, corner_pin=0.0):
        points = np.asarray(points, float)
        n = points.shape[0]
        corners = np.unique(np.asarray(corners, dtype=np.int64))
        self.n = n
        self.K = K = corners.shape[0]
        self.rot = int(corners[0]) if K else 0
        self.Q = np.roll(points, -self.rot, axis=0)
        self.Qe = np.vstack([self.Q, self.Q[:1]])
        self.contour_edges = edge_table(self.Qe)
        self.s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(self.Qe, axis=0).T))])
        self.arc_length = float(self.s[-1])
        self.epsilon = float(epsilon)
        self.corner_radius = float(corner_radius)
        self.corner_allowance = float(corner_allowance)
        self.min_gap = int(min_gap)
        self.sample_spacing = float(sample_spacing)
        self.hoschek_gate = float(hoschek_gate)
        self.weight_profile = weight_profile
        if K:
            self.cb = np.append((corners - self.rot) % n, n)
            self.simple = np.zeros(0, dtype=np.int64)
        else:
            self.cb = np.array([0, n])
            count = max(4, int(initial_knots))
            self.simple = np.unique(np.round(np.arange(count) * n / count).astype(np.int64))
        pieces = self.cb.shape[0] - 1
        self.piece_of = np.clip(np.searchsorted(self.cb, np.arange(n + 1), side="right") - 1, 0, pieces - 1)
        self.tip_gap_scale = float(tip_gap)
        self.geometric_corners = bool(geometric_corners)
        self.corner_pin = float(corner_pin)
        self.fixed = np.zeros(n + 1, bool)
        if K:
            self.fixed[self.cb] = True
        else:
            self.fixed[0] = True
        # arc distance to the nearest corner and which corner
        if K:
            cs = self.s[self.cb]  # includes the period end (= corner 0)
            k = np.clip(np.searchsorted(cs, self.s), 1, cs.shape[0] - 1)
            left, right = self.s - cs[k - 1], cs[k] - self.s
            self.corner_dist = np.minimum(left, right)
            self.nearest_corner = np.where(left <= right, k - 1, k) % K
        else:
            self.corner_dist = np.full(n + 1, np.inf)
            self.nearest_corner = np.zeros(n + 1, dtype=np.int64)
        if K:
            self.radius, theta = self._corner_radii()
            self.theta = theta
            self.zone_radius = self.radius.copy()  # the zone keeps its size when the extrapolation is reduced
            self.allowance_kept = np.zeros(K, bool)
            # parameter gap on each side of a corner: the pixel tip is truncated by about
            # 0.5 / sin(theta / 2) - 0.5 px, and the pieces need that much parameter to reach the true corner
            self.tip_gap = np.clip(self.tip_gap_scale * (1.0 / np.maximum(np.sin(0.5 * theta), 0.1) - 1.0), 0.0, 3.0)
            self.gap_before, self.gap_after = self.tip_gap.copy(), self.tip_gap.copy()
            self.corner_target = np.full((K, 2), np.nan)
            if self.geometric_corners:
                self._geometric_gaps()
        else:
            self.radius, self.tip_gap = np.zeros(1), np.zeros(1)
            self.theta = np.full(1, np.pi)
            self.zone_radius = np.zeros(1)
            self.allowance_kept = np.zeros(1, bool)
            self.gap_before = self.gap_after = np.zeros(1)
            self.corner_target = np.full((1, 2), np.nan)
        self.p = self._parameters()
        self.period = float(self.p[-1])
        self.lo_par = self.p[self.cb[self.piece_of]]
        self.hi_par = self.p[self.cb[self.piece_of + 1]]
        self.u = self.p.copy()
        self.coef = None
        self.seed_min_curvature = 1.0 / 150.0

    def seed_knots(self, density):
        """Initial simple knots from the contour's curvature, before any insertion round.

        The error of a cubic spline on a knot interval of length ``h`` is about ``c h^4 |S^(4)|``, and on an arc
        of curvature ``kappa`` (arc-length parameter) ``|S^(4)|`` is about ``kappa^3``: an interval meets the
        tolerance when ``h <= (epsilon / (c kappa^3))^(1/4)``. The knots are placed where the integral of the
        knot density ``lambda = (density kappa^3 / epsilon)^(1/4)`` along each piece crosses a multiple of its
        total over ``floor(total) + 1`` (equidistributed error, de Boor's knot placement). ``kappa`` is the
        turn of the chord directions (chords over +-4 contour steps) between +-4 steps, per arc length, which
        averages out the pixel staircase, then averaged over +-8 steps; rates below ``seed_min_curvature``
        (1/150 px, what is left of the staircase on long straight sides) count as straight, and contour points
        within 6 px of a corner are left out (the corner's pieces end there). ``density = 0`` keeps the corners
        as the only knots (four equally spaced knots on an outline without corners)."""
        n, Q, s = self.n, self.Q, self.s
        if density <= 0 or n < 16:
            return
        a = 4
        idx = np.arange(n)
        chord = Q[(idx + a) % n] - Q[(idx - a) % n]
        phi = np.arctan2(chord[:, 1], chord[:, 0])
        turn = phi[(idx + a) % n] - phi[(idx - a) % n]
        turn = (turn + np.pi) % (2.0 * np.pi) - np.pi
        ahead = np.where(idx + a < n, s[np.minimum(idx + a, n)], self.arc_length + s[(idx + a) % n])
        behind = np.where(idx - a >= 0, s[np.maximum(idx - a, 0)], s[(idx - a) % n] - self.arc_length)
        kappa = turn / np.maximum(ahead - behind, 1e-9)
        # the staircase of a straight side turns both ways: average the signed rate over +-8 steps
        width = 8
        padded = np.concatenate([kappa[-width:], kappa, kappa[:width]])
        box = np.concatenate([[0.0], np.cumsum(padded)])
        kappa = np.abs(box[2 * width + 1:] - box[: -2 * width - 1]) / (2 * width + 1)
        kappa[kappa < self.seed_min_curvature] = 0.0  # what is left of the staircase on long straight sides
        lam = (density * kappa**3 / self.epsilon) ** 0.25
        if self.K:
            lam[self.corner_dist[:n] < 6.0] = 0.0
        cum = np.concatenate([[0.0], np.cumsum(lam * np.diff(s))])  # integral up to point j (n + 1 values)
        new = [self.simple if self.K else np.zeros(1, dtype=np.int64)]  # an outline without corners: seam knot 0
        for p in range(self.cb.shape[0] - 1):
            first, last = self.cb[p], self.cb[p + 1]
            total = cum[last] - cum[first]
            count = int(np.floor(total))
            if count < 1:
                continue
            targets = cum[first] + total * np.arange(1, count + 1) / (count + 1)
            j = np.searchsorted(cum[first:last + 1], targets) + first
            new.append(j[(j - first >= self.min_gap) & (last - j >= self.min_gap)])
        merged = np.unique(np.concatenate(new)).astype(np.int64)
        merged = merged[np.diff(merged, prepend=-self.min_gap) >= self.min_gap]  # at least min_gap steps apart
        if self.K or merged.shape[0] >= 4:  # a periodic spline needs four knots
            self.simple = merged

    def _corner_radii(self):
        """Per corner: the arc length (px) over which the pixel data near the corner is truncated, about
        ``corner_radius / tan(theta / 2)`` for the interior angle ``theta`` measured on the contour (chords to
        the points ``min(6, 0.4 piece)`` px away on both sides), clipped to ``[1, 3 corner_radius]``."""
        K, s, L = self.K, self.s, self.arc_length
        cs = s[self.cb[:-1]]
        piece_len = np.diff(s[self.cb])
        before = np.roll(piece_len, 1)
        reach_back = np.minimum(6.0, 0.4 * before)
        reach_fwd = np.minimum(6.0, 0.4 * piece_len)
        q_back = self._point_at_arc((cs - reach_back) % L)
        q_fwd = self._point_at_arc((cs + reach_fwd) % L)
        corner = self.Q[self.cb[:-1] % self.n]
        a, b = q_back - corner, q_fwd - corner
        cos = np.einsum("kd,kd->k", a, b) / np.maximum(np.hypot(*a.T) * np.hypot(*b.T), 1e-300)
        theta = np.arccos(np.clip(cos, -1.0, 1.0))
        radius = self.corner_radius / np.maximum(np.tan(0.5 * theta), 1e-6)
        radius = np.clip(radius, 1.0, 3.0 * self.corner_radius) if self.corner_radius > 0 else np.zeros(K)
        # at most a fifth of either neighbouring piece, so that most of a short piece still carries weight
        radius = np.minimum(radius, 0.2 * np.minimum(before, piece_len))
        return radius, theta

    def _parameters(self):
        """Base parameter of every contour point (n + 1 values): arc length, plus the gap ``tip_gap`` on
        both sides of each corner (the corner's own point sits in the middle of its gap)."""
        if not self.K:
            return self.s.copy()
        after, before = self.gap_after, self.gap_before
        lengths = np.diff(self.s[self.cb])
        # piece k: corner k, gap_after[k], the piece's arc length, gap_before[k + 1], corner k + 1
        corner_par = np.concatenate([[0.0], np.cumsum(after + lengths + np.roll(before, -1))])
        k = self.piece_of
        p = corner_par[k] + after[k] + self.s - self.s[self.cb[k]]
        p[self.cb] = corner_par
        return p

    def _geometric_gaps(self):
        """Where the contour is straight enough on both sides of a corner, intersect total-least-squares lines
        fitted to the contour just outside the truncated tip (arc distance ``r .. r + 8`` px, at most 0.45 of the
        piece) and set the parameter gaps so that the parameter is the distance along those lines: the pieces
        then reach the intersection without bending. Also remembers the intersection (``corner_target``).
        Corners whose lines are nearly parallel, or whose intersection is more than 3 px from the contour
        corner, keep the angle-based gaps."""
        s, L, K = self.s, self.arc_length, self.K
        lengths = np.diff(s[self.cb])
        before_len, after_len = np.roll(lengths, 1), lengths
        for c in range(K):
            ic = self.cb[c]
            sc = s[ic]
            lines, anchors = [], []
            for sign, side_len in ((-1, before_len[c]), (1, after_len[c])):
                a0 = max(self.radius[c], 1.0)
                a1 = min(a0 + 8.0, 0.45 * side_len)
                if a1 - a0 < 2.0:
                    break
                arc = (sc + sign * np.linspace(a0, a1, max(4, int(a1 - a0) * 2))) % L
                pts = self._point_at_arc(arc)
                centre = pts.mean(axis=0)
                _, _, vt = np.linalg.svd(pts - centre, full_matrices=False)
                lines.append((centre, vt[0]))
                anchors.append(self._point_at_arc(np.array([(sc + sign * a0) % L]))[0])
            if len(lines) < 2:
                continue
            (c1, d1), (c2, d2) = lines
            cross = d1[0] * d2[1] - d1[1] * d2[0]
            if abs(cross) < 0.2:  # nearly parallel (or a corner of less than ~12 deg): no reliable intersection
                continue
            delta = c2 - c1
            t1 = (delta[0] * d2[1] - delta[1] * d2[0]) / cross
            X = c1 + t1 * d1
            corner_point = self.Q[ic % self.n]
            if not np.isfinite(X).all() or np.hypot(*(X - corner_point)) > 3.0:
                continue
            a0 = max(self.radius[c], 1.0)
            self.gap_before[c] = float(np.clip(np.hypot(*(X - anchors[0])) - a0, 0.0, 3.0))
            self.gap_after[c] = float(np.clip(np.hypot(*(X - anchors[1])) - a0, 0.0, 3.0))
            self.corner_target[c] = X

    def _point_at_arc(self, arc):
        return np.column_stack([np.interp(arc, self.s, self.Qe[:, 0]), np.interp(arc, self.s, self.Qe[:, 1])])

    def _pins(self):
        """Virtual data points at the geometric corner estimates (weight ``corner_pin``), or None."""
        if not self.K or self.corner_pin <= 0:
            return None
        ok = np.isfinite(self.corner_target[:, 0]) & (self.radius > 0)
        if not ok.any():
            return None
        idx = np.flatnonzero(ok)
        return self.p[self.cb[idx]], self.corner_target[idx], np.full(idx.shape[0], self.corner_pin)

    def displacement_violations(self):
        """Corners (still extrapolated) whose fitted point lies farther from the contour corner point than
        the tip of a pixel shape can be truncated: ``0.5 / sin(theta / 2)`` for the interior angle ``theta``,
        at least 0.75 px, at most ``epsilon + corner_allowance``. Such a corner is a misfit of the pieces'
        extensions (a hook), not a truncated tip."""
        if not self.K:
            return np.zeros(0, dtype=np.int64)
        fitted = self.curve_at(self.p[self.cb[:-1]])
        disp = np.hypot(*(fitted - self.Q[self.cb[:-1] % self.n]).T)
        limit = np.clip(0.5 / np.maximum(np.sin(0.5 * self.theta), 1e-3), 0.75,
                        self.epsilon + self.corner_allowance)
        return np.flatnonzero((disp > limit) & (self.radius > 0))

    def release(self, corner):
        """Halve the extrapolation radius of a corner (0 below 0.75 px: the pieces then follow the pixel tip).
        Returns True if the corner was still extrapolated."""
        if self.radius[corner] <= 0:
            return False
        self.radius[corner] = 0.5 * self.radius[corner] if self.radius[corner] >= 1.5 else 0.0
        return True

    # ---------------------------------------------------------------- knots and weights
    def tau(self):
        corners = np.repeat(self.p[self.cb[:-1]], 3) if self.K else np.zeros(0)
        return np.sort(np.concatenate([corners, self.p[self.simple]]))

    def knot_indices(self):
        """Sorted rotated indices of all knots (corners once, simple knots) and the closing index n."""
        return np.unique(np.concatenate([self.cb, self.simple]))

    def zone(self):
        """Boolean per point (n + 1): within ``2 r + 1`` px (arc length) of a corner whose tip is still
        extrapolated, ``r`` its initial weighting radius; the tolerance there is ``epsilon + corner_allowance``."""
        if not self.K:
            return np.zeros(self.n + 1, bool)
        r = self.zone_radius[self.nearest_corner]
        active = (self.radius > 0) | self.allowance_kept
        return (r > 0) & active[self.nearest_corner] & (self.corner_dist < 2.0 * r + 1.0)

    def weights(self):
        if not self.K:
            return np.ones(self.n)
        r = self.radius[self.nearest_corner]
        x = self.corner_dist / np.where(r > 0, r, 1.0)
        if self.weight_profile == "quadratic":
            w = np.minimum(1.0, x**2)
        elif self.weight_profile == "step":
            w = (x >= 1.0).astype(float)
        else:  # ramp from 0 at r to 1 at 2r
            w = np.clip(x - 1.0, 0.0, 1.0)
        w = np.where(r > 0, w, 1.0)
        w[self.fixed & (r > 0)] = 0.0
        return np.maximum(w[: self.n], 1e-3)

    # ---------------------------------------------------------------- fitting
    def fit(self, hoschek_steps=1):
        tau = self.tau()
        m = tau.shape[0]
        full = periodic_knot_vector(tau, self.period)
        w = self.weights()
        n = self.n
        u = self.u[:n]
        tu = np.unique(np.append(tau, self.period))
        starts, ends = tu[:-1], tu[1:]
        pieces = self.cb.shape[0] - 1
        pins = self._pins()
        for step in range(hoschek_steps + 1):
            uu = u if pins is None else np.concatenate([u, pins[0]])
            i = interval_index(full, uu)
            (N,) = cubic_basis(full, i, uu)
            coef = solve_normal(folded_columns(i, m), N, w if pins is None else np.concatenate([w, pins[2]]),
                                self.Q if pins is None else np.vstack([self.Q, pins[1]]), m)
            if step == hoschek_steps:
                break
            # Hoschek: one Newton step of the foot-point equation (S(u) - Q) . S'(u) = 0, with S, S', S'' from
            # the power form of each knot interval's Bézier piece
            bez = bezier_of_intervals(coef, full, m, starts, ends)
            seg = np.clip(np.searchsorted(starts, u, side="right") - 1, 0, starts.shape[0] - 1)
            h = (ends - starts)[seg]
            theta = (u - starts[seg]) / h
            b0, b1, b2, b3 = (bez[seg, j] for j in range(4))
            c1, c2, c3 = 3.0 * (b1 - b0), 3.0 * (b0 - 2.0 * b1 + b2), b3 - b0 + 3.0 * (b1 - b2)
            th = theta[:, None]
            r = b0 + th * (c1 + th * (c2 + th * c3)) - self.Q
            d1 = (c1 + th * (2.0 * c2 + 3.0 * th * c3)) / h[:, None]
            d2 = (2.0 * c2 + 6.0 * th * c3) / (h * h)[:, None]
            speed2 = d1[:, 0] ** 2 + d1[:, 1] ** 2
            den = speed2 + r[:, 0] * d2[:, 0] + r[:, 1] * d2[:, 1]
            den = np.where(den > 0.1 * speed2, den, speed2)
            du = -(r[:, 0] * d1[:, 0] + r[:, 1] * d1[:, 1]) / np.maximum(den, 1e-300)
            np.clip(du, -2.0, 2.0, out=du)
            res = np.hypot(r[:, 0], r[:, 1])
            # only in pieces that already fit roughly (projecting onto a bad curve scrambles the parameters)
            piece_res = sorted_group_max(self.piece_of[:n], res, pieces)
            du[piece_res[self.piece_of[:n]] > self.hoschek_gate] = 0.0
            un = np.clip(u + du, self.lo_par[:n], self.hi_par[:n])
            un[self.fixed[:n]] = self.p[:n][self.fixed[:n]]
            u = np.maximum.accumulate(un)
        self.u[:n] = u
        self.coef, self.full, self.m, self.tau_values = coef, full, m, tau
        self._starts, self._ends = starts, ends
        self._bezier = bezier_of_intervals(coef, full, m, starts, ends)
        return coef

    # ---------------------------------------------------------------- geometry of the current fit
    def intervals(self):
        """Starts and ends of the knot intervals of the current fit (multiple knots once)."""
        return self._starts, self._ends

    def bezier(self):
        """Bézier control points (k, 4, 2) of the current fit on its knot intervals."""
        return self._bezier

    def curve_at(self, u):
        """Points ``S(u)`` of the current fit (``u`` in ``[0, period]``)."""
        starts, ends = self.intervals()
        seg = np.clip(np.searchsorted(starts, u, side="right") - 1, 0, starts.shape[0] - 1)
        return eval_bezier(self._bezier, seg, (u - starts[seg]) / (ends - starts)[seg])

    def deviations(self, dense=False):
        """Closest-point deviations of the current fit, both directions (upper bounds, see module docstring).

        * curve -> contour: curve samples (``sample_spacing`` px apart; ``dense``: 0.25 px) to the contour
          edges in a window around the sample's corresponding contour position (the piece's own edges and
          three more across each corner);
        * contour -> curve: every contour point (``dense``: and every edge midpoint) to its corresponding curve
          point ``S(u_j)``; where that is more than ``epsilon / 2``, to the nearest chord of the curve samples
          within 4 px of parameter instead.

        Returns a dict: per knot interval the worst excess over the tolerance (``epsilon``, plus
        ``corner_allowance`` in the zone of an extrapolated corner), per piece the max deviation, the thesis
        error (contour point to its corresponding curve point) and the worst excess, and the per-probe arrays
        that :meth:`insert` needs."""
        n = self.n
        starts, ends = self.intervals()
        bez = self.bezier()
        k = starts.shape[0]
        spacing = min(self.sample_spacing, 0.25) if dense else self.sample_spacing
        lengths = np.hypot(*np.diff(bez, axis=1).transpose(2, 0, 1)).sum(axis=1)
        counts = np.maximum(3, np.ceil(lengths / spacing).astype(np.int64))
        iv = np.repeat(np.arange(k), counts)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]])
        theta = (np.arange(iv.shape[0]) - first[iv]) / counts[iv]
        samples = eval_bezier(bez, iv, theta)
        params = starts[iv] + theta * (ends - starts)[iv]
        pieces = self.cb.shape[0] - 1
        corner_par = self.p[self.cb]
        spiece = np.clip(np.searchsorted(corner_par, params, side="right") - 1, 0, pieces - 1)
        centre = np.clip(np.searchsorted(self.u, params) - 1, 0, n - 1)
        window = 1
        if self.K:  # the piece's own edges, and 3 more across each corner (the corner belongs to both pieces)
            d_curve = windowed_distance(samples, centre, self.cb[spiece] - 3, self.cb[spiece + 1] + 2,
                                        self.contour_edges, window, n)
        else:
            d_curve = windowed_distance(samples, centre, None, None, self.contour_edges, window, n)
        # probes: contour points (and edge midpoints), in parameter order
        if dense:
            probes = np.empty((2 * n, 2))
            probes[0::2], probes[1::2] = self.Q, 0.5 * (self.Qe[:-1] + self.Qe[1:])
            probe_u = np.empty(2 * n)
            probe_u[0::2], probe_u[1::2] = self.u[:n], 0.5 * (self.u[:-1] + self.u[1:])
            probe_piece = np.repeat(self.piece_of[:n], 2)
            is_point = np.tile([True, False], n)
        else:
            probes, probe_u, probe_piece = self.Q, self.u[:n], self.piece_of[:n]
            is_point = np.ones(n, bool)
        d_data = np.hypot(*(self.curve_at(probe_u) - probes).T)
        # the bound is tight where Hoschek converged; refine it where it matters: above the tolerance (and, in
        # the dense check that reports the final deviation, above epsilon / 2)
        loose = np.flatnonzero(d_data > (0.5 * self.epsilon if dense else self.epsilon))
        if loose.size:
            closed_samples = np.vstack([samples, bez[-1:, 3]])
            closed_params = np.append(params, self.period)
            lo = np.searchsorted(closed_params, corner_par[probe_piece[loose]], side="left")
            hi = np.maximum(np.searchsorted(closed_params, corner_par[probe_piece[loose] + 1], side="right") - 2, lo)
            centre_p = np.clip(np.searchsorted(closed_params, probe_u[loose]), lo, hi)
            reach = int(np.ceil(3.0 / spacing))
            wrap = closed_samples.shape[0] - 1
            if self.K:  # the piece's own chords and a window across its corners
                near = windowed_distance(probes[loose], centre_p, lo - reach, hi + reach, edge_table(closed_samples),
                                         reach, wrap)
            else:
                near = windowed_distance(probes[loose], centre_p, None, None, edge_table(closed_samples), reach, wrap)
            d_data[loose] = np.minimum(d_data[loose], near)
        zone = self.zone()
        allowance = self.corner_allowance
        if dense:
            probe_zone = np.empty(2 * n, bool)
            probe_zone[0::2], probe_zone[1::2] = zone[:n], zone[:n] | zone[1:]
        else:
            probe_zone = zone[:n]
        tol_data = self.epsilon + allowance * probe_zone
        curve_zone = np.interp(params, self.p, zone.astype(float)) > 0
        tol_curve = self.epsilon + allowance * curve_zone
        data_iv = np.clip(np.searchsorted(ends, probe_u, side="left"), 0, k - 1)
        ex_curve, ex_data = d_curve - tol_curve, d_data - tol_data
        excess = np.maximum(sorted_group_max(iv, ex_curve, k), sorted_group_max(data_iv, ex_data, k))
        piece_dev = np.maximum(sorted_group_max(spiece, d_curve, pieces), sorted_group_max(probe_piece, d_data, pieces))
        piece_dev = np.maximum(piece_dev, 0.0)
        piece_err = np.maximum(sorted_group_max(probe_piece[is_point], d_data[is_point], pieces), 0.0)
        piece_excess = np.maximum(sorted_group_max(spiece, ex_curve, pieces),
                                  sorted_group_max(probe_piece, ex_data, pieces))
        return {
            "starts": starts, "ends": ends, "excess": excess, "piece_dev": piece_dev, "piece_err": piece_err,
            "piece_excess": piece_excess, "d_data": d_data, "tol_data": tol_data, "data_iv": data_iv,
            "probe_u": probe_u, "probe_zone": probe_zone, "d_curve": d_curve, "tol_curve": tol_curve,
            "curve_iv": iv, "curve_params": params, "curve_zone": curve_zone, "bezier": bez, "dense": dense,
        }

    # ---------------------------------------------------------------- knot insertion
    def insert(self, dev, strategy="worst"):
        """Insert one knot into every failing knot interval, at its worst point outside the corner zones,
        kept in the middle half of the interval (``strategy="middle"``: at the middle). Where an interval fails
        only inside the zone of an extrapolated corner, knots cannot help (the fit ignores the truncated
        tip), so that corner stops being extrapolated instead.

        Returns (new knots as (rotated index, interval, excess), intervals that could not be split because
        their knots are fewer than ``2 min_gap`` steps apart, released corners)."""
        n = self.n
        excess = dev["excess"]
        failing = np.flatnonzero(excess > 0)
        if failing.size == 0:
            return [], [], []
        k = excess.shape[0]
        data_zone = dev["probe_zone"]
        curve_zone = dev["curve_zone"]
        data_ex = dev["d_data"] - dev["tol_data"]
        curve_ex = dev["d_curve"] - dev["tol_curve"]
        u_data = dev["probe_u"]
        # worst excess per interval outside / inside the corner zones, with its parameter
        out_d, out_d_at = group_max(dev["data_iv"], np.where(data_zone, -np.inf, data_ex), k)
        out_c, out_c_at = group_max(dev["curve_iv"], np.where(curve_zone, -np.inf, curve_ex), k)
        in_d, in_d_at = group_max(dev["data_iv"], np.where(data_zone, data_ex, -np.inf), k)
        in_c, in_c_at = group_max(dev["curve_iv"], np.where(curve_zone, curve_ex, -np.inf), k)
        knots = self.knot_indices()
        knot_values = self.p[knots]
        new, stuck, released = [], [], []
        for f in failing:
            a, b = dev["starts"][f], dev["ends"][f]
            if max(out_d[f], out_c[f]) <= 0:
                in_data = in_d[f] >= in_c[f]
                best = in_d[f] if in_data else in_c[f]
                where = u_data[in_d_at[f]] if in_data else dev["curve_params"][in_c_at[f]]
                c = int(self.nearest_corner[int(np.clip(np.searchsorted(self.u, where), 0, n))])
                if self.release(c):
                    released.append(c)
                    continue
                # the corner already follows the pixels: a knot may still help
            elif out_d[f] >= out_c[f]:
                best, where = out_d[f], u_data[out_d_at[f]]
            else:
                best, where = out_c[f], dev["curve_params"][out_c_at[f]]
            if strategy == "middle":
                where = 0.5 * (a + b)
            quarter = 0.25 * (b - a)
            where = min(max(where, a + quarter), b - quarter)
            left = int(knots[min(np.searchsorted(knot_values, a - 1e-9), knots.shape[0] - 1)])
            right = int(knots[min(np.searchsorted(knot_values, b - 1e-9), knots.shape[0] - 1)])
            if right - left < 2 * self.min_gap:
                stuck.append(int(f))
                continue
            j = int(np.clip(np.searchsorted(self.u[:n], where), left + self.min_gap, right - self.min_gap))
            new.append((j, int(f), float(best)))
        if new:
            self.simple = np.unique(np.concatenate([self.simple, [j for j, _, _ in new]]).astype(np.int64))
        return new, stuck, released

    def release_corners(self, dev, stuck):
        """Reduce the extrapolation of the corners near a stuck interval (knots too close to split it); a corner
        that already follows the pixels keeps the corner allowance in its zone instead (a ragged, truncated tip
        that a C² piece cannot follow within epsilon). Returns the corner numbers."""
        released = []
        if not self.K:
            return released
        r = self.zone_radius[self.nearest_corner]
        zone = (r > 0) & (self.corner_dist < 2.0 * r + 1.0)
        for f in stuck:
            a, b = dev["starts"][f], dev["ends"][f]
            j0, j1 = np.searchsorted(self.p, a), np.searchsorted(self.p, b)
            inside = np.flatnonzero(zone[j0: j1 + 1]) + j0
            for c in np.unique(self.nearest_corner[inside]):
                if self.release(int(c)):
                    released.append(int(c))
                elif not self.allowance_kept[c]:
                    self.allowance_kept[c] = True
                    released.append(int(c))
        return released

    # ---------------------------------------------------------------- knot removal
    def removal_scores(self, bezier):
        """For every simple knot: (rotated index, score) with score = |jump of S'''| * h^3 / 48, about the
        deviation that removing the knot causes (the size of the cubic's departure from one polynomial)."""
        starts, ends = self.intervals()
        h = ends - starts
        third = 6.0 * (bezier[:, 3] - 3 * bezier[:, 2] + 3 * bezier[:, 1] - bezier[:, 0]) / (h[:, None] ** 3)
        values = self.p[self.simple]
        right = np.searchsorted(starts, values)  # interval starting at the knot
        right = np.clip(right, 0, starts.shape[0] - 1)
        left = (right - 1) % starts.shape[0]
        jump = np.hypot(*(third[right] - third[left]).T)
        span = 0.5 * (h[left] + h[right])
        return jump * span**3 / 48.0

    def remove(self, indices):
        """Remove simple knots (never the seam knot at index 0 of an outline without corners, where the
        knot intervals start)."""
        keep = ~np.isin(self.simple, indices) | (self.simple == 0)
        self.simple = self.simple[keep]

    _FIT_STATE = ("simple", "u", "coef", "full", "m", "tau_values", "_starts", "_ends", "_bezier")

    def save(self):
        """The knots and the current fit (to go back to without refitting)."""
        return {name: getattr(self, name) for name in self._FIT_STATE} | {"u": self.u.copy()}

    def load(self, saved):
        for name, value in saved.items():
            setattr(self, name, value)
        self.u = self.u.copy()

    def restore(self, indices):
        self.simple = np.unique(np.concatenate([self.simple, np.asarray(indices, dtype=np.int64)]))
