"""Corner detectors for digital outlines (thesis chapter 2 and section 4.1.2; §6).

Every detector takes an ``(n, 2)`` polyline -- normally a :class:`~splinecraft.capture.contour.Boundary`
``outline`` (crack midpoints, spacing 1 px on straight runs and 0.71 px where the outline turns) or its
``pixels`` chain -- and returns the **sorted indices** of the points it marks as corners.

=================  ==================================================================================
``"srm05"``        the thesis's three-phase slope detector (ZCT, DT, TA), :func:`srm05`
``"rj73"``         Rosenfeld & Johnston 1973, k-cosine with per-point scale, :func:`rj73`
``"rw75"``         Rosenfeld & Weszka 1975, averaged k-cosine, :func:`rw75`
``"fd77"``         Freeman & Davis 1977, chain cornerity with straight arms, :func:`fd77`
``"bt87"``         Beus & Tiu 1987, FD77 averaged over scales with bounded arms, :func:`bt87`
``"ipan99"``       Chetverikov & Szabo 1999, inscribed triangles, :func:`ipan99`
``"tc89"``         Teh & Chin 1989, region of support + k-cosine, :func:`tc89`
``"tangent-jump"`` this project's detector for outline capture, :func:`tangent_jump` (recommended)
=================  ==================================================================================

Conventions shared by all detectors
-----------------------------------
* ``closed=True`` treats the points as a closed outline (first point not repeated; a repeated closing
  point is ignored). For an open polyline the two end points are never reported (they are piece
  boundaries anyway) and points whose window runs off an end cannot be corners.
* Consecutive duplicate points are merged before detection; returned indices refer to the input and,
  inside a run of duplicates, to its first point.
* Input validation: ``points`` must be a real ``(n, 2)`` array (``TypeError`` / ``ValueError``
  otherwise); a NaN or infinite coordinate raises ``ValueError`` naming its index. A parameter outside
  its domain raises ``ValueError`` naming the parameter. An outline with too few points for the
  detector's window (for example the 4-point outline of a single-pixel speck) has **no corners**: the
  detectors return an empty array rather than raise, so that tracing can run every detector on every
  boundary of an image.
* Vectorized with numpy over all points (windows are gathered as ``(n, k)`` arrays); the only Python
  loops run over scales, over candidate corners (a handful per outline), over SRM05's slope runs and
  over the removal steps of SRM05's phase 3.

Measured accuracy and speed on rasterized shapes are in ``BENCHMARKS.md`` ("Corner detectors"), made by
``benchmarks/bench_corners.py``.
"""
from __future__ import annotations

import heapq
import numbers
import warnings

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

__all__ = [
    "corners",
    "CORNER_METHODS",
    "CAPTURE_DEFAULT",
    "srm05",
    "rj73",
    "rw75",
    "fd77",
    "bt87",
    "ipan99",
    "tc89",
    "tangent_jump",
]

#: The detector recommended for outline capture (see ``BENCHMARKS.md``, "Corner detectors").
CAPTURE_DEFAULT = "tangent-jump"

_EMPTY = np.zeros(0, dtype=np.intp)


# ----------------------------------------------------------------------------------------------------------
# validation
# ----------------------------------------------------------------------------------------------------------
def _check_bool(value, name):
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def _check_real(value, name, *, low=None, high=None, low_open=False, high_open=False):
    """A finite real number inside [low, high] (ends open when asked); ValueError names ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if low is not None and (value < low or (low_open and value == low)):
        raise ValueError(f"{name} must be {'>' if low_open else '>='} {low:g}, got {value:g}")
    if high is not None and (value > high or (high_open and value == high)):
        raise ValueError(f"{name} must be {'<' if high_open else '<='} {high:g}, got {value:g}")
    return value


def _check_int(value, name, *, low=None, high=None):
    """An integer (Python or numpy, not bool) inside [low, high]; ValueError names ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)) \
                and float(value).is_integer():
            value = int(value)
        else:
            raise TypeError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if low is not None and value < low:
        raise ValueError(f"{name} must be >= {low}, got {value}")
    if high is not None and value > high:
        raise ValueError(f"{name} must be <= {high}, got {value}")
    return value


def _prepare(points, closed):
    """Validate ``points``; merge consecutive duplicates.

    Returns ``(P, keep)``: the distinct points as a float ``(m, 2)`` array and, for each of them, its
    index in the input (the first point of a run of duplicates).
    """
    closed = _check_bool(closed, "closed")
    if isinstance(points, (str, bytes)):
        raise TypeError(f"points must be an (n, 2) array of numbers, got {type(points).__name__}")
    if np.iscomplexobj(points):
        raise TypeError("points must be real, got complex values")
    try:
        array = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"points must be an (n, 2) array of numbers: {exc}") from None
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got shape {array.shape}")
    finite = np.isfinite(array).all(axis=1)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        raise ValueError(f"points[{bad}] is not finite: {array[bad].tolist()}")
    if len(array) == 0:
        return array, _EMPTY
    keep = np.ones(len(array), dtype=bool)
    keep[1:] = np.any(array[1:] != array[:-1], axis=1)
    index = np.flatnonzero(keep)
    if closed and len(index) > 1 and np.array_equal(array[index[-1]], array[0]):
        index = index[:-1]
    return array[index], index


def _result(found, keep):
    """Map indices into the merged points back to the input; sorted, unique, intp."""
    found = np.asarray(found, dtype=np.intp).reshape(-1)
    if found.size == 0:
        return _EMPTY.copy()
    return np.unique(keep[found]).astype(np.intp)


# ----------------------------------------------------------------------------------------------------------
# shared geometry
# ----------------------------------------------------------------------------------------------------------
def _offset_points(P, offsets, closed):
    """``P[i + k]`` for every point ``i`` and offset ``k``: array (n, len(offsets), 2).

    Closed outlines wrap around; for open ones positions beyond an end are NaN.
    """
    n = len(P)
    offsets = np.asarray(offsets, dtype=np.intp)
    idx = np.arange(n)[:, None] + offsets[None, :]
    if closed:
        return P[idx % n]
    inside = (idx >= 0) & (idx < n)
    out = P[np.clip(idx, 0, n - 1)]
    out[~inside] = np.nan
    return out


def _k_cosines(P, kmax, closed):
    """k-cosines ``c[i, k-1] = cos angle(P[i-k] - P[i], P[i+k] - P[i])`` for k = 1..kmax (RJ73 eq. 1).

    -1 on a straight line, +1 at a spike; NaN where a vector leaves an open polyline or is zero.
    """
    ks = np.arange(1, kmax + 1)
    a = _offset_points(P, -ks, closed) - P[:, None, :]
    b = _offset_points(P, ks, closed) - P[:, None, :]
    na, nb = np.hypot(a[..., 0], a[..., 1]), np.hypot(b[..., 0], b[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.sum(a * b, axis=-1) / (na * nb)
    cos[(na == 0) | (nb == 0)] = np.nan
    return np.clip(cos, -1.0, 1.0)


def _circular_max_filter(values, half_width, closed, fill=-np.inf):
    """Maximum of ``values`` over ``[i - half_width, i + half_width]`` (cyclic when closed)."""
    if half_width <= 0:
        return values.copy()
    n = len(values)
    if closed:
        reps = -(-(2 * half_width + 1) // n) + 1
        tiled = np.tile(values, 2 * reps + 1)
        start = reps * n - half_width
        windows = sliding_window_view(tiled[start:start + n + 2 * half_width], 2 * half_width + 1)
    else:
        padded = np.concatenate([np.full(half_width, fill), values, np.full(half_width, fill)])
        windows = sliding_window_view(padded, 2 * half_width + 1)
    return windows.max(axis=1)


def _thin_by_strength(candidates, strength, P, min_distance):
    """Greedy non-maximum suppression: strongest first, drop candidates within ``min_distance`` (Euclidean)
    of an already kept one. Ties go to the smaller x, then y (not to the index, so that the result does
    not depend on where a closed outline starts). Returns the kept candidate indices (sorted)."""
    candidates = np.asarray(candidates, dtype=np.intp)
    if candidates.size <= 1 or min_distance <= 0:
        return np.sort(candidates)
    order = candidates[np.lexsort((P[candidates, 1], P[candidates, 0], -strength[candidates]))]
    kept = []
    for c in order:
        if not kept or np.min(np.hypot(*(P[kept] - P[c]).T)) > min_distance:
            kept.append(int(c))
    return np.sort(np.asarray(kept, dtype=np.intp))


def _variable_window_maxima(strength, half_widths, closed):
    """``strength[i] >= strength[j]`` for all ``j`` with ``|i - j| <= half_widths[i]`` (NaN never wins)."""
    n = len(strength)
    hmax = int(np.max(half_widths)) if n else 0
    if hmax <= 0:
        return np.isfinite(strength)
    offsets = np.arange(-hmax, hmax + 1)
    idx = np.arange(n)[:, None] + offsets[None, :]
    if closed:
        neighbour = strength[idx % n]
    else:
        neighbour = np.where((idx >= 0) & (idx < n), strength[np.clip(idx, 0, n - 1)], -np.inf)
    neighbour = np.where(np.abs(offsets)[None, :] <= half_widths[:, None], neighbour, -np.inf)
    neighbour = np.nan_to_num(neighbour, nan=-np.inf)
    return np.isfinite(strength) & (strength >= neighbour.max(axis=1))


# ----------------------------------------------------------------------------------------------------------
# SRM05: the thesis's detector (chapter 2, thesis section 4.1.2)
# ----------------------------------------------------------------------------------------------------------
def _thesis_tangents(P, closed):
    """Tangent estimates of thesis eqs 2.1-2.4 (§6.1-§6.2): the bisector of the two unit chords,
    scaled by ``d- d+ / (d- + d+)``, at every point of a closed outline and at the interior points of an
    open one; the second-order one-sided differences 2.1/2.2 at open ends. A reversal
    (``|u- + u+| < 1e-9``) falls back to ``u+`` (§6.2)."""
    n = len(P)
    prev = np.roll(P, 1, axis=0)
    nxt = np.roll(P, -1, axis=0)
    d_minus = np.hypot(*(P - prev).T)
    d_plus = np.hypot(*(nxt - P).T)
    with np.errstate(invalid="ignore", divide="ignore"):
        u_minus = (P - prev) / d_minus[:, None]
        u_plus = (nxt - P) / d_plus[:, None]
        bisector = u_minus + u_plus
        reversal = np.hypot(*bisector.T) < 1e-9
        bisector[reversal] = u_plus[reversal]
        tangent = (d_minus * d_plus / (d_minus + d_plus))[:, None] * bisector
    if not closed:
        tangent[0] = 2.0 * (P[1] - P[0]) - 0.5 * (P[2] - P[0]) if n > 2 else P[1] - P[0]
        tangent[-1] = 2.0 * (P[-1] - P[-2]) - 0.5 * (P[-1] - P[-3]) if n > 2 else P[-1] - P[-2]
    return tangent


def _slope_states(tangent):
    """Slope state of every tangent (thesis section 2.1.1): +1 increasing, -1 decreasing, 0 constant (moving
    along an axis: one component is zero up to 1e-9 of the length). The sign is that of dy/dx in the
    frame of the points; the y-down pixel frame flips it, which maps the set of transitions onto itself."""
    tx, ty = tangent[:, 0], tangent[:, 1]
    length = np.hypot(tx, ty)
    on_axis = np.minimum(np.abs(tx), np.abs(ty)) <= 1e-9 * np.maximum(length, 1e-300)
    return np.where(on_axis, 0, np.sign(tx * ty)).astype(np.int8)


def _runs(states, closed):
    """Run-length encoding ``(starts, lengths, values)``; a closed sequence is rotated so that no run
    wraps (``starts`` then refers to the original indices modulo ``n``)."""
    n = len(states)
    change = np.flatnonzero(states != np.roll(states, 1)) if closed else \
        np.concatenate([[0], np.flatnonzero(states[1:] != states[:-1]) + 1])
    if closed and change.size == 0:
        return np.array([0]), np.array([n]), states[:1].copy()
    starts = change
    ends = np.concatenate([starts[1:], [starts[0] + n if closed else n]])
    return starts, ends - starts, states[starts]


def _srm05_phase1(states, zct, closed, rule="zero-runs"):
    """Phase 1 of SRM05: candidate indices from slope transitions (see :func:`srm05` for the rules).

    ``rule`` selects the interpretation of the thesis's vague text (the benchmark compares them):
    ``"zero-runs"`` (the default of :func:`srm05`), ``"four-transitions"`` (only the four transitions
    listed in thesis section 2.1.1, so a direct +/- flip is not a candidate) and ``"all-runs"`` (ZCT applies to runs of
    every state, not only to zero runs).
    """
    n = len(states)
    starts, lengths, values = _runs(states, closed)
    if len(starts) == 1:
        return _EMPTY
    values = values.copy()
    # jaggies: short runs take the state of the run before them ("keep record of our last transition state")
    short = lengths < zct
    if rule != "all-runs":
        short &= values == 0
    if short.all():
        return _EMPTY
    # a run takes the value of the closest preceding run that is not short (cyclically when closed)
    long_idx = np.flatnonzero(~short)
    pos = np.searchsorted(long_idx, np.arange(len(values)), side="right") - 1
    if closed:
        source = long_idx[pos % len(long_idx)]           # pos = -1 wraps to the last long run
    else:
        source = np.where(pos >= 0, long_idx[np.maximum(pos, 0)], long_idx[0])
    values = values[source]
    # merge equal neighbours: boundaries are where the (relabelled) state changes
    if closed:
        boundary = values != np.roll(values, 1)
    else:
        boundary = np.concatenate([[False], values[1:] != values[:-1]])
    if not boundary.any():
        return _EMPTY
    previous = np.roll(values, 1)
    if rule == "four-transitions":
        boundary &= (values == 0) | (previous == 0)
    candidates = [starts[boundary]]                        # first point after each transition
    # a line (a zero run that survived) contributes its last point as well ("the end points of a line")
    merged_start = np.flatnonzero(boundary)
    if closed:
        merged_end = np.roll(merged_start, -1)            # next boundary (cyclically)
    else:
        merged_end = np.concatenate([merged_start[1:], [len(values)]])
    for b0, b1 in zip(merged_start, merged_end):
        if values[b0] == 0:
            last_run = (b1 - 1) % len(values)
            candidates.append([starts[last_run] + lengths[last_run] - 1])
    found = np.concatenate([np.asarray(c, dtype=np.intp) for c in candidates]) % n
    if not closed:
        found = found[(found > 0) & (found < n - 1)]
    return np.unique(found)


def _srm05_phase2(P, candidates, dt, closed, pick="middle"):
    """Phase 2 of SRM05: merge candidates closer than ``dt`` (Euclidean, thesis section 2.1.2).

    Walking along the outline (a closed one from the candidate after the largest index gap), a cluster
    starts at a candidate and takes every following candidate within ``dt`` of the cluster's first
    member; the cluster is replaced by its middle member (``pick="middle"``, lower middle for an even
    count) or by its first member (``pick="first"``, the greedy reading; compared in the benchmark).
    """
    m = len(candidates)
    if m <= 1 or dt <= 0:
        return candidates
    order = np.asarray(candidates)
    if closed:
        gaps = np.diff(np.concatenate([order, [order[0] + len(P)]]))
        start = (int(np.argmax(gaps)) + 1) % m
        order = np.roll(order, -start)
    kept = []
    cluster = [order[0]]
    for c in order[1:]:
        if np.hypot(*(P[c] - P[cluster[0]])) <= dt:
            cluster.append(c)
        else:
            kept.append(cluster[(len(cluster) - 1) // 2] if pick == "middle" else cluster[0])
            cluster = [c]
    kept.append(cluster[(len(cluster) - 1) // 2] if pick == "middle" else cluster[0])
    return np.sort(np.asarray(kept, dtype=np.intp))


def _interior_angle(a, b, c):
    """Interior angle at ``b`` of the polyline a-b-c in degrees (§6.2, E21): 180 when collinear;
    180 as well when a vector is zero (a duplicate adds nothing to the shape)."""
    u, v = a - b, c - b
    nu, nv = np.hypot(*u), np.hypot(*v)
    if nu == 0 or nv == 0:
        return 180.0
    return float(np.degrees(np.arctan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v)))


def _srm05_phase3(P, candidates, ta, closed):
    """Phase 3 of SRM05: drop the middle point of every nearly collinear triple (thesis section 2.1.3, eq 2.5).

    The interior angle at a candidate between its two neighbouring candidates (E21: 180 deg when
    collinear) is compared with TA; while some candidate's angle exceeds TA, the one with the largest
    angle is removed and its two neighbours are re-measured (so the result does not depend on where the
    outline starts). An open outline uses its two end points as fixed neighbours of the first and last
    candidates; a closed one needs at least three candidates.
    """
    cand = [int(c) for c in candidates]
    if closed:
        if len(cand) < 3:
            return np.asarray(cand, dtype=np.intp)
        nodes = cand
    else:
        nodes = [0] + cand + [len(P) - 1]
    count = len(nodes)
    prev = [(i - 1) % count for i in range(count)]
    nxt = [(i + 1) % count for i in range(count)]
    fixed = [False] * count
    if not closed:
        fixed[0] = fixed[-1] = True
    alive = [True] * count
    version = [0] * count
    heap = []

    def push(i):
        if fixed[i]:
            return
        angle = _interior_angle(P[nodes[prev[i]]], P[nodes[i]], P[nodes[nxt[i]]])
        if angle > ta:
            heapq.heappush(heap, (-angle, nodes[i], version[i], i))

    for i in range(count):
        push(i)
    remaining = count - (0 if closed else 2)
    while heap and (remaining > 2 or (not closed and remaining > 0)):
        _, _, ver, i = heapq.heappop(heap)
        if not alive[i] or ver != version[i]:
            continue
        alive[i] = False
        remaining -= 1
        p, q = prev[i], nxt[i]
        nxt[p], prev[q] = q, p
        for j in (p, q):
            version[j] += 1
            push(j)
    return np.asarray(sorted(nodes[i] for i in range(count) if alive[i] and not fixed[i]), dtype=np.intp)


def _srm05(points, closed, zct, dt, ta, rule="zero-runs", pick="middle"):
    P, keep = _prepare(points, closed)
    if len(P) < 3:
        return _EMPTY.copy()
    states = _slope_states(_thesis_tangents(P, closed))
    candidates = _srm05_phase1(states, zct, closed, rule)
    candidates = _srm05_phase2(P, candidates, dt, closed, pick)
    candidates = _srm05_phase3(P, candidates, ta, closed)
    return _result(candidates, keep)


def srm05(points, *, closed=True, zct=7, dt=5.0, ta=152.0):
    """SRM05, the thesis's corner detector: slope transitions, then distance and angle clean-up.

    Thesis chapter 2 (thesis sections 2.1.1-2.1.4, summary in thesis section 4.1.2); tangents by eqs 2.1-2.4 (§6.1-§6.2),
    angle test by eq 2.5 read as the interior angle (§6.2, erratum **E21**). Defaults are the
    thesis's: ZCT = 7, DT = 5, TA = 152 deg.

    The thesis describes phase 1 only in words; this is the precise reading implemented (its
    alternatives are measured in ``BENCHMARKS.md``):

    **Phase 1 (slope transitions, ZCT).** Every point gets the tangent of eqs 2.1-2.4 and from it a slope
    state: 0 ("constant, moving along an axis": one tangent component is zero), +1 or -1 (sign of the
    slope). The states are run-length encoded (cyclically when closed). A *zero* run shorter than ZCT
    points is a jaggy: it takes the state of the run before it ("we ignore it and keep record of our last
    transition state"); a zero run of ZCT points or more is a line. After this relabelling, the first
    point after every change of state is a candidate -- the four transitions of thesis section 2.1.1
    (+ -> 0, 0 -> -, - -> 0, 0 -> +) and also a direct sign flip + <-> -, which is what a sharp apex
    (say a diamond's tip, whose one axis-parallel tangent formed a jaggy) leaves after the jaggy is
    removed. The last point of every line (zero run) is a candidate too ("in case of a line the end points
    of it as corner points").

    **Phase 2 (DT).** Walking along the outline, a cluster takes every following candidate within DT
    (Euclidean) of its first member and is replaced by its middle member (thesis section 2.1.2, "close coordinates").

    **Phase 3 (TA).** While some candidate makes an interior angle larger than TA with its two
    neighbouring candidates (collinear = 180 deg), the one with the largest angle is dropped (thesis section 2.1.3).

    Parameters
    ----------
    points : array_like, shape (n, 2)
        Outline points (crack midpoints or pixel chain), roughly unit spaced.
    closed : bool
        Closed outline (default) or open polyline.
    zct : int, default 7
        Zero Count Threshold: zero-slope runs shorter than this are jaggies. Integer >= 0 (0 and 1 keep
        every run).
    dt : float, default 5
        Distance Threshold (px) of phase 2, >= 0 (0 keeps every candidate).
    ta : float, default 152
        Tolerance Angle (degrees) of phase 3, in the open interval (0, 180).

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices into ``points``; empty for fewer than 3 distinct points.

    Raises
    ------
    TypeError, ValueError
        Bad ``points`` (NaN/inf names the index) or a parameter outside its domain (named).
    """
    zct = _check_int(zct, "zct", low=0)
    dt = _check_real(dt, "dt", low=0.0)
    ta = _check_real(ta, "ta", low=0.0, high=180.0, low_open=True, high_open=True)
    return _srm05(points, closed, zct, dt, ta)


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


def _check_m(m, n):
    """RJ73/RW75's largest k: ``n / 10`` for None (the paper's choice), at most ``(n - 1) // 2``."""
    m = max(1, int(round(n / 10))) if m is None else _check_int(m, "m", low=1)
    return min(m, (n - 1) // 2)


def _k_cosine_input(points, closed, m, max_angle):
    """Arguments of RJ73 / RW75 checked and their k-cosine table: ``(P, keep, m, cosines, max_angle)``, or
    None for fewer than 5 distinct points (``m`` and ``max_angle`` are validated first either way)."""
    max_angle = _check_real(max_angle, "max_angle", low=0.0, high=180.0, low_open=True)
    P, keep = _prepare(points, closed)
    if m is not None:
        _check_int(m, "m", low=1)
    if len(P) < 5:
        return None
    m = _check_m(m, len(P))
    return P, keep, m, _k_cosines(P, m, closed), max_angle


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
        Largest k; at most ``(n - 1) // 2`` is used. The paper takes ``m = n / 10`` (pass None) on curves of
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
        Smoothing length (points), >= 2.
    threshold : float, default 1000
        Minimum cornerity (degrees x points), >= 0. The default was chosen on the project's synthetic
        shapes (``benchmarks/bench_corners.py``); the paper tunes it per curve.

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than ``2 s + 3`` distinct points.
    """
    s = _check_int(s, "s", low=2)
    threshold = _check_real(threshold, "threshold", low=0.0)
    P, keep = _prepare(points, closed)
    if len(P) < 2 * s + 3:
        return _EMPTY.copy()
    K = _fd_cornerity(P, s, closed)
    return _result(_peaks(K, threshold, s, closed, P, 1.5), keep)


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
        Range of smoothing lengths, ``2 <= s_min <= s_max``.
    arm_limit : int, default 15
        Upper bound of the arm lengths (points), >= 1.
    threshold : float, default 300
        Minimum averaged cornerity (degrees x points), >= 0. ``arm_limit`` and ``threshold`` were chosen
        on the project's synthetic shapes (``benchmarks/bench_corners.py``); the paper tunes them per curve.

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than ``2 s_max + 3`` distinct points.
    """
    s_min = _check_int(s_min, "s_min", low=2)
    s_max = _check_int(s_max, "s_max", low=2)
    if s_max < s_min:
        raise ValueError(f"s_max must be >= s_min, got s_min={s_min}, s_max={s_max}")
    arm_limit = _check_int(arm_limit, "arm_limit", low=1)
    threshold = _check_real(threshold, "threshold", low=0.0)
    P, keep = _prepare(points, closed)
    if len(P) < 2 * s_max + 3:
        return _EMPTY.copy()
    K = np.mean([_fd_cornerity(P, s, closed, arm_limit) for s in range(s_min, s_max + 1)], axis=0)
    return _result(_peaks(K, threshold, s_max, closed, P, 1.5), keep)


# ----------------------------------------------------------------------------------------------------------
# IPAN99
# ----------------------------------------------------------------------------------------------------------
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
        Arm length range (px), ``0 <= d_min <= d_max``, ``d_max > 0``.
    alpha_max : float, default 150
        Largest opening angle (degrees) of a corner, in (0, 180].

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices; empty for fewer than 5 distinct points.
    """
    d_min = _check_real(d_min, "d_min", low=0.0)
    d_max = _check_real(d_max, "d_max", low=0.0, low_open=True)
    if d_max < d_min:
        raise ValueError(f"d_max must be >= d_min, got d_min={d_min:g}, d_max={d_max:g}")
    alpha_max = _check_real(alpha_max, "alpha_max", low=0.0, high=180.0, low_open=True)
    P, keep = _prepare(points, closed)
    n = len(P)
    if n < 5:
        return _EMPTY.copy()
    step = np.hypot(*np.diff(np.vstack([P, P[:1]]) if closed else P, axis=0).T)
    reach = int(min(np.ceil(d_max / step.min()) + 1, (n - 1) // 2))
    ks = np.arange(1, reach + 1)
    fwd = _offset_points(P, ks, closed) - P[:, None, :]           # (n, K, 2)
    bwd = _offset_points(P, -ks, closed) - P[:, None, :]
    dist_f = np.hypot(fwd[..., 0], fwd[..., 1])
    dist_b = np.hypot(bwd[..., 0], bwd[..., 1])
    # the search outwards stops at the first point farther than d_max (NaN beyond an open end stops too)
    with np.errstate(invalid="ignore"):
        near_f = np.cumprod(dist_f <= d_max, axis=1).astype(bool)
        near_b = np.cumprod(dist_b <= d_max, axis=1).astype(bool)
        ok_f = near_f & (dist_f >= d_min)
        ok_b = near_b & (dist_b >= d_min)
    # opening angle of every (p-, p+) pair: (n, K, K)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.einsum("nad,nbd->nab", bwd, fwd) / (dist_b[:, :, None] * dist_f[:, None, :])
    alpha = np.degrees(np.arccos(np.clip(cos, -1, 1)))
    admissible = ok_b[:, :, None] & ok_f[:, None, :] & (alpha <= alpha_max)
    alpha = np.where(admissible, alpha, np.inf).reshape(n, -1).min(axis=1)
    candidate = np.isfinite(alpha)
    if not closed:
        candidate[[0, -1]] = False
    sharpness = np.where(candidate, 180.0 - alpha, -np.inf)
    chosen = np.flatnonzero(candidate)
    return _result(_thin_by_strength(chosen, sharpness, P, d_max), keep)


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
    max_angle = _check_real(max_angle, "max_angle", low=0.0, high=180.0, low_open=True)
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


# ----------------------------------------------------------------------------------------------------------
# tangent-jump: the project's detector for outline capture
# ----------------------------------------------------------------------------------------------------------
#: Arm lengths tried (samples at 1 px spacing); an arm grows through them while it stays straight.
_ARM_LADDER = (3, 4, 5, 6, 8, 10, 12, 15, 19, 24, 30, 38, 48, 60, 76, 96, 120)
_ARM_OPERATORS = {}


def _arm_operators(length, side):
    """Index offsets of an arm of ``length`` samples ending (side -1) or starting (side +1) at the point,
    those offsets centred, and the least-squares slope weights ``t / sum(t^2)`` of the line fit
    ``x(t) = mean + slope t`` (the slope points along travel)."""
    key = (length, side)
    if key not in _ARM_OPERATORS:
        offsets = np.arange(length) if side > 0 else np.arange(-length + 1, 1)
        centred = offsets - offsets.mean()
        _ARM_OPERATORS[key] = (offsets, centred, centred / np.sum(centred ** 2))
    return _ARM_OPERATORS[key]


def _resample(P, closed, step=1.0):
    """Resample the polyline at uniform arc length ``step``; returns the samples, their arc positions, the
    arc positions of the input points and the total length."""
    ring = np.vstack([P, P[:1]]) if closed else P
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(ring, axis=0).T))])
    total = arc[-1]
    count = int(round(total / step))
    if closed:
        where = np.arange(count) * (total / max(count, 1))
    else:
        where = np.linspace(0.0, total, count + 1)
    samples = np.column_stack([np.interp(where, arc, ring[:, 0]), np.interp(where, arc, ring[:, 1])])
    return samples, where, arc[:len(P)], total


def _smooth(samples, sigma, closed):
    """Gaussian smoothing of a sampled curve along its length (sigma in samples); cyclic when closed."""
    if sigma <= 0:
        return samples
    half = int(np.ceil(3 * sigma))
    kernel = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma) ** 2)
    kernel /= kernel.sum()
    m = len(samples)
    if closed:
        idx = np.arange(-half, m + half) % m
        padded = samples[idx]
    else:
        padded = np.pad(samples, ((half, half), (0, 0)), mode="edge")
    return np.column_stack([np.convolve(padded[:, 0], kernel, "valid"),
                            np.convolve(padded[:, 1], kernel, "valid")])


def _arm_fit(padded, starts, length, tolerance=None):
    """Least-squares lines ``x(t) = mean + slope t`` of the arms (windows) of ``length`` samples starting at
    the rows ``starts`` of ``padded``: their mean points, slopes (along travel) and, given a
    ``tolerance``, whether every sample of the window lies within ``tolerance`` of its line (else None;
    False where a window holds a NaN).

    The windows are gathered as one ``(length, k, 2)`` block, sample-major, so that every sum over a
    window runs as ``length`` vectorized additions over all windows at once; the mean is that running sum
    divided by ``length`` and the slope the running sum of ``t / sum(t^2)`` times the samples -- in
    floating point the same operations, in the same order, as a per-window mean and dot product.

    The straightness test is ``max hypot(residual) <= tolerance``. It compares the squared distances with
    ``tolerance**2`` (``hypot`` is several times slower) and calls ``hypot`` only for the windows whose
    largest squared distance is within a relative ``1e-12`` of ``tolerance**2`` (or NaN), where rounding
    could decide; the answer is therefore exactly that of ``hypot``.
    """
    _, centred, slope_weights = _arm_operators(length, 1)
    arm = np.take(padded, np.arange(length)[:, None] + starts[None, :], axis=0)      # (length, k, 2)
    mean = arm.sum(axis=0) / length
    slope = np.einsum("l,lad->ad", slope_weights, arm)
    if tolerance is None:
        return mean, slope, None
    arm -= mean
    arm -= centred[:, None, None] * slope                       # residuals from the line
    dx, dy = arm[..., 0], arm[..., 1]
    squared = np.square(arm)
    worst = (squared[..., 0] + squared[..., 1]).max(axis=0)
    limit = tolerance * tolerance
    with np.errstate(invalid="ignore"):
        straight = worst < limit * (1.0 - 1e-12)
        unsure = ~straight & ~(worst > limit * (1.0 + 1e-12))   # near the limit, or NaN
        if unsure.any():
            straight[unsure] = np.hypot(dx[:, unsure], dy[:, unsure]).max(axis=0) <= tolerance
    return mean, slope, straight


def _signed_arm_turn(R, closed, tolerance, ladder):
    """Signed turn (degrees, + = left in the frame of the points) between the straight arms before and
    after every sample of ``R``, and the two arm directions (along travel).

    Each arm starts at the sample and grows through ``ladder`` while every sample of it stays within
    ``tolerance`` of its least-squares line (the first length is always accepted); its direction is the
    slope of that line. NaN where an arm of an open curve runs off an end.

    Implementation: the backward arm of length ``L`` at sample ``i`` is the window of ``L`` samples of
    the padded curve ending at ``i``, the forward arm the window starting there, so the forward arm of
    ``i`` is the backward arm of ``i + L - 1``. For each length of the ladder, the line of every window
    that a still growing arm needs is fitted once, for all those windows at once (:func:`_arm_fit`); an arm
    stops at its first length that is not straight and keeps the line of the length before.
    """
    m = len(R)
    reach = max(ladder)
    if closed:
        padded = R[np.arange(-reach, m + reach) % m]
    else:
        padded = np.vstack([np.full((reach, 2), np.nan), R, np.full((reach, 2), np.nan)])
    sides = (-1, 1)
    alive = {side: np.arange(m) for side in sides}
    # points and directions travel as complex numbers x + iy (a view of the float pairs, same bits):
    # gathering and scattering 1-D arrays is many times faster than rows of (k, 2) arrays
    directions = {side: np.full(m, complex(np.nan, np.nan)) for side in sides}
    centres = {side: np.full(m, complex(np.nan, np.nan)) for side in sides}
    line = {}                               # side -> (mean, slope) of the last straight arm of each alive sample
    for rung, length in enumerate(ladder):
        first = {-1: alive[-1] + (reach - length + 1), 1: alive[1] + reach}    # window starts in padded
        needed = np.zeros(len(padded) - length + 1, dtype=bool)
        for side in sides:
            needed[first[side]] = True
        row_of_start = np.cumsum(needed) - 1
        mean, slope, straight = _arm_fit(padded, np.flatnonzero(needed), length,
                                         tolerance if rung > 0 else None)
        mean, slope = (np.ascontiguousarray(x).view(np.complex128).ravel() for x in (mean, slope))
        for side in sides:
            row = row_of_start[first[side]]
            if rung > 0:                    # arms that stop here keep the line of the previous length
                keep = straight[row]
                stopped = ~keep
                directions[side][alive[side][stopped]] = line[side][1][stopped]
                centres[side][alive[side][stopped]] = line[side][0][stopped]
                alive[side], row = alive[side][keep], row[keep]
            line[side] = (mean[row], slope[row])
        if not (alive[-1].size or alive[1].size):
            break
    for side in sides:                      # arms that reached the last length
        directions[side][alive[side]] = line[side][1]
        centres[side][alive[side]] = line[side][0]
    directions, centres = ({side: x[side].view(np.float64).reshape(m, 2) for side in sides}
                           for x in (directions, centres))
    a, b = directions[-1], directions[1]
    turn = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.sum(a * b, axis=1)))
    return turn, (centres[-1], a, centres[1], b)


def _line_intersection(c1, a, c2, b):
    """Intersection of the lines ``c1 + t a`` and ``c2 + u b`` (rows); NaN where nearly parallel."""
    det = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    d = c2 - c1
    with np.errstate(invalid="ignore", divide="ignore"):
        t = (d[:, 0] * b[:, 1] - d[:, 1] * b[:, 0]) / det
        point = c1 + t[:, None] * a
        parallel = np.abs(det) <= 1e-9 * np.hypot(*a.T) * np.hypot(*b.T)
    point[parallel] = np.nan
    return point


def tangent_jump(points, *, closed=True, smoothing=1.0, tolerance=0.3, min_turn=25.0, min_excess=25.0,
                 flank=(4, 10), max_arm=40, separation=2):
    """Corners as jumps of the tangent direction between straight arms (this project's detector).

    Designed for crack outlines of rasterized shapes (staircase noise of about half a pixel) and tuned on
    the project's own synthetic shapes (``benchmarks/bench_corners.py``: polygons, stars, serif letters,
    mixed line/arc shapes, font glyphs, and smooth shapes that must have no corner); parameters are in
    pixels and degrees.

    1. The outline is resampled at 1 px arc length and smoothed by a Gaussian of ``smoothing`` px, which
       removes single-pixel bumps of the staircase.
    2. **Arms.** At every sample two arms grow, one backwards and one forwards, through the lengths
       3, 4, 5, 6, 8, ... ``max_arm`` samples for as long as every sample of the arm stays within
       ``tolerance`` px of the arm's least-squares line. The arm direction is that line's (long arms on
       straight sides give directions good to a degree or two).
    3. **Turn.** ``J`` is the signed angle from the backward to the forward arm. Along a straight side it
       is ~0; at a corner it is the corner's turn; along an arc of radius ``r`` it is about
       ``arm / r`` -- large on tight arcs, but the same all along the arc.
    4. **Excess.** A corner concentrates its turn: ``E = J - median(J)`` over the flanks
       ``flank[0]..flank[1]`` samples away on both sides. On an arc, and across a tangent-continuous
       join of a line and an arc, ``E`` is ~0 (the arc's turn is in the flanks too); at a corner it is the
       corner's turn, also when another corner lies in one flank (the median ignores it).
    5. A sample is a corner when ``|J|`` is the largest within ``separation`` samples, ``|J| >= min_turn``
       and ``|E| >= min_excess``.
    6. **Location.** Each corner goes to an input point within 3 px (arc length) of its sample: for a
       turn below 100 deg the one nearest to the apex where the two arm lines meet; for a sharper turn,
       whose rasterized tip is cut off (the apex lies beyond the outline), the one farthest out along the
       bisector ``a/|a| - b/|b|`` of the arm directions, where the vertex of the two sides is extreme.

    Corners are joins turning by more than 30 degrees (the yardstick's definition); ``min_excess`` sits a
    little below that because ``E`` underestimates obtuse corners next to staircase-noisy sides. Limits
    (measured in ``BENCHMARKS.md``): two corners closer than about 3 px merge; a bend tighter than about
    10 px radius of curvature at the end of an elongated shape may count as a corner (a circle of radius
    5 px does not: its curvature is uniform); turns of 25-30 deg count as corners.

    Parameters
    ----------
    points : array_like (n, 2)
        Outline in pixel units (roughly unit spaced; any polyline works, it is resampled).
    closed : bool
    smoothing : float, default 1.0
        Gaussian sigma (px) applied after resampling, >= 0 (0 = none).
    tolerance : float, default 0.3
        Largest distance (px) of an arm sample from the arm's line, > 0.
    min_turn : float, default 25
        Smallest turn |J| (degrees) of a corner, in [0, 180).
    min_excess : float, default 25
        Smallest excess |E| (degrees) of a corner, in [0, 180).
    flank : (int, int), default (4, 10)
        Nearest and farthest flank offsets (samples) of the excess baseline, ``1 <= flank[0] <= flank[1]``.
    max_arm : int, default 40
        Longest arm (samples), >= 3. Longer arms (60) find the same corners on the 335 shapes of
        ``bench_corners.py``'s synthetic sets (seeds 0 and 1) and the yardstick (the same true and false
        positives) and cost 1.2-2x the time on outlines with long straight sides.
    separation : int, default 2
        Half width (samples) of the non-maximum suppression, >= 1.

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices into ``points``; empty when the outline is shorter than 8 px.
    """
    smoothing = _check_real(smoothing, "smoothing", low=0.0)
    tolerance = _check_real(tolerance, "tolerance", low=0.0, low_open=True)
    min_turn = _check_real(min_turn, "min_turn", low=0.0, high=180.0, high_open=True)
    min_excess = _check_real(min_excess, "min_excess", low=0.0, high=180.0, high_open=True)
    if isinstance(flank, (str, bytes)) or np.ndim(flank) != 1 or len(flank) != 2:
        raise TypeError(f"flank must be a pair of integers (near, far), got {flank!r}")
    near = _check_int(flank[0], "flank[0]", low=1)
    far = _check_int(flank[1], "flank[1]", low=near)
    max_arm = _check_int(max_arm, "max_arm", low=3)
    separation = _check_int(separation, "separation", low=1)
    P, keep = _prepare(points, closed)
    if len(P) < 3:
        return _EMPTY.copy()
    if closed:                              # resample from the lowest-then-leftmost point: the result then
        start = int(np.lexsort((P[:, 0], P[:, 1]))[0])     # does not depend on where the outline starts
        P, keep = np.roll(P, -start, axis=0), np.roll(keep, -start)
    samples, where, arc, perimeter = _resample(P, closed)
    m = len(samples)
    if m < 8:
        return _EMPTY.copy()
    samples = _smooth(samples, smoothing, closed)
    ladder = [length for length in _ARM_LADDER if length <= max_arm and 2 * length < m] or [3]
    turn, arms = _signed_arm_turn(samples, closed, tolerance, ladder)
    offsets = np.concatenate([np.arange(-far, -near + 1), np.arange(near, far + 1)])
    idx = np.arange(m)[:, None] + offsets[None, :]
    if closed:
        flanks = turn[idx % m]
    else:
        flanks = np.where((idx >= 0) & (idx < m), turn[np.clip(idx, 0, m - 1)], np.nan)
    if np.isnan(flanks).any():              # open ends
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)      # all-NaN flanks at open ends
            baseline = np.nanmedian(flanks, axis=1)
    else:                                   # the median of an even count, as np.median computes it, 5x faster
        ordered = np.sort(flanks, axis=1)
        half = flanks.shape[1] // 2         # 2 (far - near + 1) flank samples
        baseline = (ordered[:, half - 1] + ordered[:, half]) / 2
    with np.errstate(invalid="ignore"):
        excess = np.abs(turn - baseline)
        size = np.abs(turn)
        strength = np.nan_to_num(size, nan=-np.inf)
        peak = (strength >= _circular_max_filter(strength, separation, closed)) \
            & (size >= min_turn) & (excess >= min_excess)
    chosen = np.flatnonzero(peak)
    if chosen.size > 1:                     # a plateau of equal maxima keeps its first sample
        first = np.ones(chosen.size, dtype=bool)
        first[1:] = np.diff(chosen) > separation
        if closed and chosen[0] + m - chosen[-1] <= separation:
            first[-1] = False
        chosen = chosen[first]
    # step 6: the input point of each corner
    pos = where[chosen]
    right = np.clip(np.searchsorted(arc, pos), 0, len(arc) - 1)
    left = np.clip(right - 1, 0, len(arc) - 1)
    nearest = np.where(np.abs(arc[left] - pos) <= np.abs(arc[right] - pos), left, right)
    if closed:                              # past the last point the closing chord leads back to point 0
        wrap = (perimeter - pos) < np.abs(arc[nearest] - pos)
        nearest[wrap] = 0
    if nearest.size:
        n = len(P)
        around = nearest[:, None] + np.arange(-6, 7)[None, :]
        if closed:
            around %= n
            along = np.abs(arc[around] - pos[:, None])
            along = np.minimum(along, perimeter - along)
        else:
            around = np.clip(around, 0, n - 1)
            along = np.abs(arc[around] - pos[:, None])
        rows = np.arange(len(nearest))
        within = along <= 3.0
        apex = _line_intersection(*(x[chosen] for x in arms))
        apex_ok = np.isfinite(apex).all(axis=1) & (np.hypot(*(apex - samples[chosen]).T) <= 3.0) \
            & (size[chosen] < 100.0)
        gap_to_apex = np.hypot(*(P[around] - apex[:, None, :]).transpose(2, 0, 1))
        gap_to_apex = np.where(within, np.nan_to_num(gap_to_apex, nan=np.inf), np.inf)
        near_apex = around[rows, np.argmin(gap_to_apex, axis=1)]
        a, b = arms[1][chosen], arms[3][chosen]
        outward = a / np.hypot(*a.T)[:, None] - b / np.hypot(*b.T)[:, None]       # points to the apex
        reach = np.where(within, np.einsum("kjd,kd->kj", P[around], outward), -np.inf)
        tip = around[rows, np.argmax(np.nan_to_num(reach, nan=-np.inf), axis=1)]
        tip = np.where(apex_ok, near_apex, tip)
        nearest = np.where(np.isfinite(outward).all(axis=1), tip, nearest)
    if not closed:
        nearest = nearest[(nearest > 0) & (nearest < len(P) - 1)]
    return _result(nearest, keep)


# ----------------------------------------------------------------------------------------------------------
# registry and dispatcher
# ----------------------------------------------------------------------------------------------------------
#: Detector name -> function. Every function takes ``(points, *, closed=True, **its own parameters)``.
CORNER_METHODS = {
    "srm05": srm05,
    "rj73": rj73,
    "rw75": rw75,
    "fd77": fd77,
    "bt87": bt87,
    "ipan99": ipan99,
    "tc89": tc89,
    "tangent-jump": tangent_jump,
}


def corners(points, method="srm05", *, closed=True, **params):
    """Corner indices of an outline by the detector ``method`` (a key of :data:`CORNER_METHODS`).

    ``"srm05"`` (the default) is the thesis's detector (chapter 2); for outline capture the project
    recommends ``"tangent-jump"`` (:data:`CAPTURE_DEFAULT`), see ``BENCHMARKS.md``.

    Parameters
    ----------
    points : array_like (n, 2)
        Closed outline (first point not repeated) or open polyline, roughly unit spaced, pixel units.
    method : str
        Detector name.
    closed : bool
        Closed outline (default) or open polyline (its end points are never reported).
    **params
        The detector's own parameters (see its docstring); an unknown name raises ``TypeError``.

    Returns
    -------
    numpy.ndarray of intp
        Sorted, unique indices into ``points``.
    """
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {method!r}")
    try:
        detector = CORNER_METHODS[method]
    except KeyError:
        raise ValueError(f"unknown corner method {method!r}; choose one of {sorted(CORNER_METHODS)}") from None
    return detector(points, closed=closed, **params)
