"""SRM05, the thesis's corner detector (thesis chapter 2, section 4.1.2; §6.2, erratum E21)."""
from __future__ import annotations

import heapq

import numpy as np

from ._common import _EMPTY, _check_int, _check_real, _plain, _prepare, _result

#: Largest ZCT (points of a zero-slope run) and DT (px) of :func:`srm05`: the bounds of the classic detectors'
#: windows and distances (``_classic.MAX_SCALE``, ``_classic.MAX_DISTANCE``), 40 and 28 times the thesis's values.
MAX_ZCT = 200
MAX_DT = 200.0


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
        Zero Count Threshold: zero-slope runs shorter than this are jaggies. Integer in ``[0, MAX_ZCT]``
        = [0, 200] (0 and 1 keep every run).
    dt : float, default 5
        Distance Threshold (px) of phase 2, in ``[0, MAX_DT]`` = [0, 200] (0 keeps every candidate).
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
    settings = check_srm05_params(zct=zct, dt=dt, ta=ta)
    return _srm05(points, closed, settings["zct"], settings["dt"], settings["ta"])


def check_srm05_params(*, zct, dt, ta, label=_plain):
    """SRM05's parameters checked against their documented domains (the one rule, used by :func:`srm05` and by
    :func:`~splinecraft.capture.corners.check_params`); ``label(key)`` names a parameter in messages."""
    return {
        "zct": _check_int(zct, label("zct"), low=0, high=MAX_ZCT),
        "dt": _check_real(dt, label("dt"), low=0.0, high=MAX_DT),
        "ta": _check_real(ta, label("ta"), low=0.0, high=180.0, low_open=True, high_open=True),
    }
