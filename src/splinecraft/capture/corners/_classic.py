"""The classic detectors the thesis compares with: RJ73, RW75 (k-cosine), FD77, BT87 (chain cornerity),
IPAN99 (inscribed triangles), TC89 (region of support)."""
from __future__ import annotations

import numpy as np

from ._common import (_EMPTY, _check_int, _check_real, _circular_max_filter, _k_cosines, _offset_points, _plain,
                      _prepare, _result, _thin_by_strength, _variable_window_maxima)



# ----------------------------------------------------------------------------------------------------------
# k-cosine detectors: RJ73, RW75
# ----------------------------------------------------------------------------------------------------------
def _largest_k_of_increase(cos, top):
    """RJ73's scale ``h_i``: the largest ``h <= top_i`` with ``c_{i,top} < c_{i,top-1} < ... < c_{i,h}``
    (the cosines increase as ``k`` decreases from ``top_i`` and stop increasing at ``h``).
    ``cos`` is ``(n, m)`` for k = 1..m; ``top`` the per-point usable maximum ``k`` (>= 1)."""
    n, m = cos.shape
    if m == 1:
        return np.ones(n, dtype=np.intp)
    # rising[:, j] for k = j + 2: c_{k-1} > c_k  (j = 0..m-2)
    with np.errstate(invalid="ignore"):
        rising = cos[:, :-1] > cos[:, 1:]
    ks = np.arange(2, m + 1)
    rising |= ks[None, :] > top[:, None]               # beyond the usable top: skip over
    # count the run of True from k = m downwards
    run = np.cumprod(rising[:, ::-1], axis=1).sum(axis=1)
    return np.maximum(m - run, 1).astype(np.intp)


def _usable_top(n, m, closed):
    """Largest usable k per point: m (closed, already limited to (n-1)//2), distance to the ends (open)."""
    if closed:
        return np.full(n, m, dtype=np.intp)
    i = np.arange(n)
    return np.minimum(m, np.minimum(i, n - 1 - i)).astype(np.intp)


def _kcos_select(P, closed, strength_table, m, max_angle):
    """Shared selection of RJ73/RW75: scale ``h_i`` by :func:`_largest_k_of_increase`, strength
    ``c_{i,h_i}``, keep ``i`` when its strength is the largest within ``|i - j| <= h_i / 2``, and the
    angle ``arccos c`` is at most ``max_angle``."""
    n = len(P)
    top = _usable_top(n, m, closed)
    h = _largest_k_of_increase(strength_table, top)
    strength = strength_table[np.arange(n), h - 1]
    strength[top < 1] = np.nan
    selected = _variable_window_maxima(strength, h // 2, closed)
    with np.errstate(invalid="ignore"):
        selected &= np.degrees(np.arccos(np.clip(strength, -1, 1))) <= max_angle
    if not closed:
        selected[[0, -1]] = False
    # a plateau of equal strength (the two crack midpoints either side of an axis-aligned pixel corner)
    # keeps one point
    return _thin_by_strength(np.flatnonzero(selected), np.nan_to_num(strength, nan=-2), P, 1.5)


#: Upper bounds of the classic detectors' scale parameters (points, px): far beyond useful values, they keep
#: the k-cosine and cornerity tables of one call at ``O(n)`` memory.
MAX_SCALE = 200
MAX_DISTANCE = 200.0


def check_k_cosine_params(*, m, max_angle, label=_plain):
    """RJ73's and RW75's parameters checked against their documented domains (the one rule, used by the
    detectors and by :func:`~splinecraft.capture.corners.check_params`); ``label(key)`` names a parameter in
    messages."""
    return {"m": None if m is None else _check_int(m, label("m"), low=1, high=MAX_SCALE),
            "max_angle": _check_real(max_angle, label("max_angle"), low=0.0, high=180.0, low_open=True)}


def _check_m(m, n):
    """RJ73/RW75's largest k (``m`` checked): ``n / 10`` for None (the paper's choice), at most ``(n - 1) // 2``
    and ``MAX_SCALE``."""
    m = max(1, int(round(n / 10))) if m is None else m
    return min(m, (n - 1) // 2, MAX_SCALE)


def _k_cosine_input(points, closed, m, max_angle):
    """Arguments of RJ73 / RW75 checked and their k-cosine table: ``(P, keep, m, cosines, max_angle)``, or
    None for fewer than 5 distinct points (``m`` and ``max_angle`` are validated first either way)."""
    settings = check_k_cosine_params(m=m, max_angle=max_angle)
    P, keep = _prepare(points, closed)
    if len(P) < 5:
        return None
    m = _check_m(settings["m"], len(P))
    return P, keep, m, _k_cosines(P, m, closed), settings["max_angle"]


def rj73(points, *, closed=True, m=5, max_angle=120.0):
    """Rosenfeld & Johnston (1973), "Angle detection on digital curves", IEEE Trans. Computers C-22.

    The k-cosine ``c_ik = cos angle(P_{i-k} - P_i, P_{i+k} - P_i)`` (-1 on a line, +1 at a spike) is
    computed for k = 1..m. Each point gets the scale ``h_i``: going down from ``k = m`` while the cosine
    increases, ``h_i`` is where it stops increasing (``c_im < ... < c_ih >= c_i,h-1``). Point ``i`` is an
    angle point when ``c_{i,h_i} >= c_{j,h_j}`` for all ``|i - j| <= h_i / 2``.

    The paper has no threshold (on a digital straight line every point ties and would be kept), so an
    angle point must also have ``arccos c_{i,h_i} <= max_angle`` (set 180 for the bare method), and of a
    plateau of equal strength only one point is kept. On crack outlines every staircase step makes a
    135-degree angle at k = 1, so ``max_angle`` must stay below 135.

    Parameters
    ----------
    points : array_like (n, 2)
    closed : bool
    m : int or None, default 5
        Largest k, at most ``MAX_SCALE`` (200); at most ``(n - 1) // 2`` is used. The paper takes ``m = n / 10`` (pass None) on curves of
        some 60 points; on outlines of hundreds of points a fixed m does much better (``BENCHMARKS.md``).
    max_angle : float, default 120
        Largest k-cosine angle (degrees, in (0, 180]) of an angle point. The defaults of ``m`` and
        ``max_angle`` were chosen on the project's synthetic shapes (``benchmarks/bench_corners.py``).

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than 5 distinct points.
    """
    prepared = _k_cosine_input(points, closed, m, max_angle)
    if prepared is None:
        return _EMPTY.copy()
    P, keep, m, table, max_angle = prepared
    return _result(_kcos_select(P, closed, table, m, max_angle), keep)


def rw75(points, *, closed=True, m=10, max_angle=120.0):
    """Rosenfeld & Weszka (1975), "An improved method of angle detection on digital curves",
    IEEE Trans. Computers C-24.

    As :func:`rj73`, with the k-cosine replaced by its average over the scales ``floor(k/2)..k``
    (``2/(k+2) sum_{j=k/2}^{k} c_ij`` for even k, ``2/(k+3) sum_{j=(k-1)/2}^{k} c_ij`` for odd k; the
    term ``j = 0`` of k = 1 does not exist and is left out), which smooths the measure across scales.

    Parameters are those of :func:`rj73` (defaults ``m = 10``, ``max_angle = 120``, chosen the same way).
    """
    prepared = _k_cosine_input(points, closed, m, max_angle)
    if prepared is None:
        return _EMPTY.copy()
    P, keep, m, cos, max_angle = prepared
    # cumulative sums along k (NaN -> excluded by propagating NaN)
    csum = np.concatenate([np.zeros((len(P), 1)), np.cumsum(cos, axis=1)], axis=1)   # csum[:, k] = sum_{j<=k}
    k = np.arange(1, m + 1)
    lo = np.maximum(k // 2, 1)
    averaged = (csum[:, k] - csum[:, lo - 1]) / (k - lo + 1)
    return _result(_kcos_select(P, closed, averaged, m, max_angle), keep)


# ----------------------------------------------------------------------------------------------------------
# chain cornerity: FD77, BT87
# ----------------------------------------------------------------------------------------------------------
def _run_lengths(flags, closed):
    """For a boolean sequence: length of the run of True ending at i, and starting at i (0 where False).
    Cyclic when closed (an all-True cycle gives n everywhere)."""
    n = len(flags)
    if closed:
        if flags.all():
            full = np.full(n, n, dtype=np.intp)
            return full, full.copy()
        work = np.concatenate([flags, flags])
    else:
        work = flags
    idx = np.arange(len(work))
    last_false = np.maximum.accumulate(np.where(~work, idx, -1))
    ending = idx - last_false
    rev = work[::-1]
    last_false_r = np.maximum.accumulate(np.where(~rev, idx, -1))
    starting = (idx - last_false_r)[::-1]
    if closed:
        ending = ending[n:]
        starting = starting[:n]
    return ending.astype(np.intp), starting.astype(np.intp)


def _fd_cornerity(P, s, closed, arm_limit=None):
    """Freeman-Davis cornerity ``K_i = sqrt(t1) * |turn_i| * sqrt(t2)`` (degrees x points) at every node.

    ``theta_i`` is the direction of the s-segment ``P_i - P_{i-s}``; the incremental curvature is
    ``delta_i = theta_{i+1} - theta_{i-1}``; a node is on a straight arm when ``|delta_i| <= arctan(1/(s-1))``.
    ``t1`` is the length of the straight run ending at ``i-1``, ``t2`` of the one starting at ``i+s+1``
    (each capped at ``arm_limit`` when given), and ``turn_i = theta_{i+s} - theta_i`` is the angle between
    the incoming and the outgoing s-segment at node ``i``. NaN where a segment leaves an open polyline.
    """
    n = len(P)
    back = _offset_points(P, [-s], closed)[:, 0]
    theta = np.arctan2(P[:, 1] - back[:, 1], P[:, 0] - back[:, 0])          # NaN off an open end
    th_next = np.roll(theta, -1)
    th_prev = np.roll(theta, 1)
    delta = np.angle(np.exp(1j * (th_next - th_prev)))
    if not closed:
        delta[[0, -1]] = np.nan
    limit = np.arctan(1.0 / (s - 1)) if s > 1 else np.pi / 4
    with np.errstate(invalid="ignore"):
        straight = np.abs(delta) <= limit
    ending, starting = _run_lengths(straight, closed)
    t1 = np.roll(ending, 1).astype(float)                    # run ending at i - 1
    t2 = np.roll(starting, -(s + 1)).astype(float)           # run starting at i + s + 1
    if not closed:
        i = np.arange(n)
        t1[i - 1 < 0] = np.nan
        t2[i + s + 1 > n - 1] = np.nan
    if arm_limit is not None:
        t1 = np.minimum(t1, arm_limit)
        t2 = np.minimum(t2, arm_limit)
    th_out = np.roll(theta, -s)
    if not closed:
        th_out[n - s:] = np.nan
    turn = np.degrees(np.abs(np.angle(np.exp(1j * (th_out - theta)))))
    return np.sqrt(t1) * turn * np.sqrt(t2)


def _peaks(strength, threshold, half_width, closed, P, separation):
    """Indices where ``strength >= threshold`` and is the maximum within ``half_width`` points,
    plateaus thinned to one point per ``separation`` px."""
    filled = np.nan_to_num(strength, nan=-np.inf)
    local_max = filled >= _circular_max_filter(filled, half_width, closed)
    chosen = np.flatnonzero(local_max & (filled >= threshold))
    if not closed:
        chosen = chosen[(chosen > 0) & (chosen < len(P) - 1)]
    return _thin_by_strength(chosen, filled, P, separation)


def fd77(points, *, closed=True, s=5, threshold=1000.0):
    """Freeman & Davis (1977), "A corner-finding algorithm for chain-coded curves", IEEE Trans.
    Computers C-26.

    A corner is a turn between two straight arms. With s-segments (the chord over ``s`` points), the
    incremental curvature ``delta_i = theta_{i+1} - theta_{i-1}`` is small (``<= arctan(1/(s-1))``) along a
    straight arm; the cornerity of node ``i`` is ``K_i = sqrt(t1) * turn_i * sqrt(t2)``, with ``t1`` and
    ``t2`` the lengths (points) of the straight arms before and after the corner region and ``turn_i`` the
    angle (degrees) between the s-segments ending and starting at ``i``. Corners are the nodes with
    ``K >= threshold`` that are maxima within ``s`` points. The paper works on chain codes; here the nodes
    are the given points (unit spaced for crack outlines), which changes nothing in the definitions.

    Parameters
    ----------
    points : array_like (n, 2)
    closed : bool
    s : int, default 5
        Smoothing length (points), in ``[2, MAX_SCALE]`` (200).
    threshold : float, default 1000
        Minimum cornerity (degrees x points), >= 0. The default was chosen on the project's synthetic
        shapes (``benchmarks/bench_corners.py``); the paper tunes it per curve.

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than ``2 s + 3`` distinct points.
    """
    s, threshold = check_fd77_params(s=s, threshold=threshold).values()
    P, keep = _prepare(points, closed)
    if len(P) < 2 * s + 3:
        return _EMPTY.copy()
    K = _fd_cornerity(P, s, closed)
    return _result(_peaks(K, threshold, s, closed, P, 1.5), keep)


def check_fd77_params(*, s, threshold, label=_plain):
    """FD77's parameters checked against their documented domains (used by :func:`fd77` and by
    :func:`~splinecraft.capture.corners.check_params`); ``label(key)`` names a parameter in messages."""
    return {"s": _check_int(s, label("s"), low=2, high=MAX_SCALE),
            "threshold": _check_real(threshold, label("threshold"), low=0.0)}


def bt87(points, *, closed=True, s_min=3, s_max=7, arm_limit=15, threshold=300.0):
    """Beus & Tiu (1987), "An improved corner detection algorithm based on chain-coded plane curves",
    Pattern Recognition 20(3).

    Two changes to :func:`fd77`: the arm lengths ``t1``, ``t2`` are capped at ``arm_limit`` (so one long
    straight side no longer makes any small turn a corner), and the cornerity is averaged over the
    smoothing lengths ``s_min..s_max`` (so no single ``s`` has to suit every corner). Corners are maxima
    of the averaged cornerity within ``s_max`` points that reach ``threshold``.

    Parameters
    ----------
    points : array_like (n, 2)
    closed : bool
    s_min, s_max : int, default 3 and 7
        Range of smoothing lengths, ``2 <= s_min <= s_max <= MAX_SCALE`` (200).
    arm_limit : int, default 15
        Upper bound of the arm lengths (points), in ``[1, 100 MAX_SCALE]``.
    threshold : float, default 300
        Minimum averaged cornerity (degrees x points), >= 0. ``arm_limit`` and ``threshold`` were chosen
        on the project's synthetic shapes (``benchmarks/bench_corners.py``); the paper tunes them per curve.

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than ``2 s_max + 3`` distinct points.
    """
    s_min, s_max, arm_limit, threshold = check_bt87_params(s_min=s_min, s_max=s_max, arm_limit=arm_limit,
                                                           threshold=threshold).values()
    P, keep = _prepare(points, closed)
    if len(P) < 2 * s_max + 3:
        return _EMPTY.copy()
    K = np.mean([_fd_cornerity(P, s, closed, arm_limit) for s in range(s_min, s_max + 1)], axis=0)
    return _result(_peaks(K, threshold, s_max, closed, P, 1.5), keep)


def check_bt87_params(*, s_min, s_max, arm_limit, threshold, label=_plain):
    """BT87's parameters checked against their documented domains (used by :func:`bt87` and by
    :func:`~splinecraft.capture.corners.check_params`); ``label(key)`` names a parameter in messages."""
    s_min = _check_int(s_min, label("s_min"), low=2, high=MAX_SCALE)
    s_max = _check_int(s_max, label("s_max"), low=2, high=MAX_SCALE)
    if s_max < s_min:
        raise ValueError(f"{label('s_max')} must be >= {label('s_min')}, got s_min={s_min}, s_max={s_max}")
    return {"s_min": s_min, "s_max": s_max,
            "arm_limit": _check_int(arm_limit, label("arm_limit"), low=1, high=100 * MAX_SCALE),
            "threshold": _check_real(threshold, label("threshold"), low=0.0)}


# ----------------------------------------------------------------------------------------------------------
# IPAN99
# ----------------------------------------------------------------------------------------------------------
#: IPAN99 searches at most this many points on each side of a point (an admissible triangle ends at the
#: first point farther than d_max, so this matters only for outlines denser than d_max / 256 px).
IPAN_MAX_REACH = 256
_IPAN_BLOCK = 1 << 21                       # triangles per block of points: bounds the memory of one call


def _ipan_sharpest(P, rows, reach, closed, d_min, d_max, alpha_max):
    """IPAN99 pass 1 for the points ``rows``: the smallest admissible opening angle (inf where none)."""
    n = len(P)
    ks = np.arange(1, reach + 1)
    idx_f, idx_b = rows[:, None] + ks[None, :], rows[:, None] - ks[None, :]
    if closed:
        fwd, bwd = P[idx_f % n] - P[rows, None, :], P[idx_b % n] - P[rows, None, :]
    else:
        fwd = np.where(((idx_f >= 0) & (idx_f < n))[..., None], P[np.clip(idx_f, 0, n - 1)], np.nan) - P[rows, None]
        bwd = np.where(((idx_b >= 0) & (idx_b < n))[..., None], P[np.clip(idx_b, 0, n - 1)], np.nan) - P[rows, None]
    dist_f = np.hypot(fwd[..., 0], fwd[..., 1])
    dist_b = np.hypot(bwd[..., 0], bwd[..., 1])
    # the search outwards stops at the first point farther than d_max (NaN beyond an open end stops too)
    with np.errstate(invalid="ignore"):
        ok_f = np.cumprod(dist_f <= d_max, axis=1).astype(bool) & (dist_f >= d_min)
        ok_b = np.cumprod(dist_b <= d_max, axis=1).astype(bool) & (dist_b >= d_min)
    # opening angle of every (p-, p+) pair: (rows, K, K)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.einsum("nad,nbd->nab", bwd, fwd) / (dist_b[:, :, None] * dist_f[:, None, :])
    alpha = np.degrees(np.arccos(np.clip(cos, -1, 1)))
    admissible = ok_b[:, :, None] & ok_f[:, None, :] & (alpha <= alpha_max)
    return np.where(admissible, alpha, np.inf).reshape(len(rows), -1).min(axis=1)


def ipan99(points, *, closed=True, d_min=7.0, d_max=9.0, alpha_max=150.0):
    """Chetverikov & Szabo (1999), "A simple and efficient algorithm for detection of high curvature
    points in planar curves", Proc. 23rd Workshop of the Austrian Pattern Recognition Group (IPAN99).

    **Pass 1.** For every point ``p``, triangles ``(p-, p, p+)`` are inscribed with ``p+`` (``p-``) taken
    forward (backward) along the curve, starting next to ``p`` and stopping at the first point farther
    than ``d_max``; a triangle is admissible when ``d_min <= |p - p+|, |p - p-| <= d_max`` and its
    opening angle ``alpha`` at ``p`` is at most ``alpha_max``. A point with an admissible triangle is a
    candidate with sharpness ``180 - min alpha`` (degrees).

    **Pass 2.** A candidate is dropped when a candidate within ``d_max`` (Euclidean) is sharper; of equal
    ones the first is kept.

    Parameters
    ----------
    points : array_like (n, 2)
    closed : bool
    d_min, d_max : float, default 7 and 9
        Arm length range (px), ``0 <= d_min <= d_max <= MAX_DISTANCE`` (200), ``d_max > 0``; at most
        ``IPAN_MAX_REACH`` (256) points are searched on each side, and the triangles are formed in blocks
        of points, so memory stays bounded on any outline.
    alpha_max : float, default 150
        Largest opening angle (degrees) of a corner, in (0, 180].

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than 5 distinct points.
    """
    d_min, d_max, alpha_max = check_ipan99_params(d_min=d_min, d_max=d_max, alpha_max=alpha_max).values()
    P, keep = _prepare(points, closed)
    n = len(P)
    if n < 5:
        return _EMPTY.copy()
    step = np.hypot(*np.diff(np.vstack([P, P[:1]]) if closed else P, axis=0).T)
    reach = int(min(np.ceil(d_max / step.min()) + 1, (n - 1) // 2, IPAN_MAX_REACH))
    alpha = np.concatenate([_ipan_sharpest(P, rows, reach, closed, d_min, d_max, alpha_max)
                            for rows in np.array_split(np.arange(n), -(-n * reach * reach // _IPAN_BLOCK))])
    candidate = np.isfinite(alpha)
    if not closed:
        candidate[[0, -1]] = False
    sharpness = np.where(candidate, 180.0 - alpha, -np.inf)
    chosen = np.flatnonzero(candidate)
    return _result(_thin_by_strength(chosen, sharpness, P, d_max), keep)


def check_ipan99_params(*, d_min, d_max, alpha_max, label=_plain):
    """IPAN99's parameters checked against their documented domains (used by :func:`ipan99` and by
    :func:`~splinecraft.capture.corners.check_params`); ``label(key)`` names a parameter in messages."""
    d_min = _check_real(d_min, label("d_min"), low=0.0, high=MAX_DISTANCE)
    d_max = _check_real(d_max, label("d_max"), low=0.0, low_open=True, high=MAX_DISTANCE)
    if d_max < d_min:
        raise ValueError(f"{label('d_max')} must be >= {label('d_min')}, got d_min={d_min:g}, d_max={d_max:g}")
    return {"d_min": d_min, "d_max": d_max,
            "alpha_max": _check_real(alpha_max, label("alpha_max"), low=0.0, high=180.0, low_open=True)}


# ----------------------------------------------------------------------------------------------------------
# TC89
# ----------------------------------------------------------------------------------------------------------
def _region_of_support(P, closed):
    """Teh-Chin region of support ``k_i`` (TC89, section III, step 1).

    With the chord ``l_ik = |P_{i+k} - P_{i-k}|`` and the signed distance ``d_ik`` of ``P_i`` from it,
    ``k`` grows from 1 until ``l_ik >= l_{i,k+1}`` or ``d_ik / l_ik >= d_{i,k+1} / l_{i,k+1}`` (for
    ``d_ik > 0``; ``<=`` for ``d_ik < 0``); ``k_i`` is that ``k``. The loop runs over ``k`` (vectorized over
    the points still growing), up to ``(n - 1) // 2`` (closed) or the distance to the nearer end (open).
    """
    n = len(P)
    top = _usable_top(n, (n - 1) // 2, closed)
    support = np.zeros(n, dtype=np.intp)
    growing = np.flatnonzero(top >= 1)

    def chord_terms(i, k):
        a = P[(i - k) % n]
        b = P[(i + k) % n]
        chord = b - a
        length = np.hypot(chord[:, 0], chord[:, 1])
        cross = chord[:, 0] * (P[i, 1] - a[:, 1]) - chord[:, 1] * (P[i, 0] - a[:, 0])
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(length > 0, cross / length ** 2, 0.0)     # d / l with d = cross / l
        return length, ratio

    k = 1
    length_k, ratio_k = chord_terms(growing, k)
    while growing.size:
        usable = k + 1 <= top[growing]
        length_next, ratio_next = chord_terms(growing, k + 1)
        stop = ~usable | (length_k >= length_next) \
            | ((ratio_k > 0) & (ratio_k >= ratio_next)) \
            | ((ratio_k < 0) & (ratio_k <= ratio_next))
        support[growing[stop]] = k
        growing, length_k, ratio_k = growing[~stop], length_next[~stop], ratio_next[~stop]
        k += 1
    return support


def tc89(points, *, closed=True, max_angle=120.0):
    """Teh & Chin (1989), "On the detection of dominant points on digital curves", IEEE PAMI 11(8).

    1. Region of support ``k_i`` of every point (see :func:`_region_of_support`): the largest scale
       before the chord stops growing or the point's relative distance from the chord stops growing.
    2. Significance: the k-cosine at ``k = k_i`` (TC89's k-cosine measure).
    3. Non-maximum suppression: ``i`` survives when no ``j`` with ``|i - j| <= k_i / 2`` is more
       significant.
    4. A survivor with ``k_i = 1`` is dropped unless it is more significant than both neighbours.

    TC89 is a dominant-point (polygonal approximation) method without a threshold; to serve as a corner
    detector a dominant point must also have a k-cosine angle of at most ``max_angle`` (180 gives the
    bare method), and of a plateau of equal significance one point is kept. Crack-outline staircase steps
    have 135-degree k-cosine angles with k = 1, so ``max_angle`` must stay below 135.

    Parameters
    ----------
    points : array_like (n, 2)
    closed : bool
    max_angle : float, default 120
        Largest k-cosine angle (degrees, in (0, 180]) of a reported point (chosen on the project's
        synthetic shapes, ``benchmarks/bench_corners.py``).

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than 5 distinct points.
    """
    max_angle = check_tc89_params(max_angle=max_angle)["max_angle"]
    P, keep = _prepare(points, closed)
    n = len(P)
    if n < 5:
        return _EMPTY.copy()
    support = _region_of_support(P, closed)
    i = np.arange(n)
    valid = support >= 1
    k = np.maximum(support, 1)
    a = P[(i - k) % n] - P
    b = P[(i + k) % n] - P
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.sum(a * b, axis=1) / (np.hypot(*a.T) * np.hypot(*b.T))
    significance = np.where(valid, np.clip(cos, -1, 1), np.nan)
    alive = _variable_window_maxima(significance, support // 2, closed)
    left = significance[(i - 1) % n]
    right = significance[(i + 1) % n]
    with np.errstate(invalid="ignore"):
        alive &= ~((support == 1) & ((significance <= left) | (significance <= right)))
        alive &= np.degrees(np.arccos(np.nan_to_num(significance, nan=-1.0))) <= max_angle
    if not closed:
        alive[[0, -1]] = False
    chosen = np.flatnonzero(alive)
    return _result(_thin_by_strength(chosen, np.nan_to_num(significance, nan=-2), P, 1.5), keep)


def check_tc89_params(*, max_angle, label=_plain):
    """TC89's parameter checked against its documented domain (used by :func:`tc89` and by
    :func:`~splinecraft.capture.corners.check_params`); ``label(key)`` names it in messages."""
    return {"max_angle": _check_real(max_angle, label("max_angle"), low=0.0, high=180.0, low_open=True)}
