"""The numpy formulation of the segment merging's steps 1 to 4 as it stood before they were compiled
(session 30; docs/capture.md §12, "Merged segments"): the reference :mod:`test_merge` pins the compiled passes of
:mod:`splinecraft.capture.fitting._merge_kernels` to, bit for bit. The candidates are fitted ``PHASE`` lengths
a pass with the growth rule applied afterwards (:func:`_grown`), each run's cubic by the kernel's own
``_fit_run`` (:func:`fit_runs`)."""
from __future__ import annotations

import numpy as np
from numba import njit

from splinecraft.capture._jit import JIT_OPTIONS
from splinecraft.capture.fitting import _merge_kernels
from splinecraft.capture.fitting._kernels import curve_points
from splinecraft.capture.fitting.merge import FIT_POINTS, MARGIN, MAX_RUN, MAX_TURN, MIN_SPLIT, MISSES, \
    NEWTON_STEPS, WINDOW

#: Run lengths fitted in one pass of :func:`_candidates`.
PHASE = 4


@njit(**dict(JIT_OPTIONS, cache=False))
def _fit_runs_into(p0, p3, d0, d1, lo, count, offsets, points, u, start, span, tol, fitted, steps, fit_points,
                   limits, scratch, cubic, handles, t_out, excess, drift, spread):
    for r in range(p0.shape[0]):
        a, b, worst, far, total = _merge_kernels._fit_run(
            p0[r, 0], p0[r, 1], p3[r, 0], p3[r, 1], d0[r, 0], d0[r, 1], d1[r, 0], d1[r, 1], lo[r], count[r], points,
            u, start[r], span[r], tol, fitted, steps, fit_points, limits[0], limits[1], scratch, cubic[r],
            t_out[offsets[r]:])
        handles[r, 0], handles[r, 1] = a, b
        excess[r], drift[r], spread[r] = worst, far, total


def kernel_fit_runs(p0, p3, d0, d1, lo, count, points, u, start, span, tol, fitted, steps, fit_points,
                    limits=(np.inf, np.inf)):
    """Per run: the cubic, its handle lengths, the offsets of its points' parameters in the next, the
    parameters, the largest excess over ``tol``, the largest and the summed squared distance from ``fitted``
    (``_merge_kernels._fit_run`` run by run; the session 29 kernel ``fit_runs``)."""
    f = lambda a: np.ascontiguousarray(a, dtype=np.float64)  # noqa: E731
    count = np.ascontiguousarray(count, dtype=np.int64)
    r = count.shape[0]
    offsets = np.zeros(r, np.int64)
    if r:
        offsets[1:] = np.cumsum(count)[:-1]
    scratch = np.empty((int(count.max()) + 2 if r else 2, 2))
    cubic, handles = np.empty((r, 4, 2)), np.empty((r, 2))
    t_out = np.empty(int(count.sum()) + 1)
    excess, drift, spread = np.empty(r), np.empty(r), np.empty(r)
    _fit_runs_into(f(p0), f(p3), f(d0), f(d1), np.ascontiguousarray(lo, dtype=np.int64), count, offsets, f(points),
                   f(u), f(start), f(span), f(tol), f(fitted), int(steps), int(fit_points),
                   np.array(limits, dtype=np.float64), scratch, cubic, handles, t_out, excess, drift, spread)
    return cubic, handles, offsets, t_out[:-1], excess, drift, spread


def _unit(v):
    length = np.hypot(v[:, 0], v[:, 1])
    return v / np.where(length > 0, length, 1.0)[:, None], length


def _turns(bez):
    """Per segment the total turn (radians) of its control polygon, and the turn at its start join."""
    d = bez[:, 1:] - bez[:, :-1]  # (k, 3, 2)
    ang = np.arctan2(d[..., 1], d[..., 0])
    inner = np.abs(np.angle(np.exp(1j * (ang[:, 1:] - ang[:, :-1])))).sum(axis=1)
    return inner


def _tangents(bez):
    start = bez[:, 1] - bez[:, 0]
    start = np.where((np.hypot(*start.T) > 1e-9)[:, None], start, bez[:, 2] - bez[:, 0])
    end = bez[:, 3] - bez[:, 2]
    end = np.where((np.hypot(*end.T) > 1e-9)[:, None], end, bez[:, 3] - bez[:, 1])
    return _unit(start)[0], _unit(end)[0]


def fit_runs(bez, starts, ends, points, u, first, length, directions, tol, fitted, limits=(np.inf, np.inf)):
    """One cubic per run from the run's first end point to its last, its handles along ``directions = (d0,
    d1)`` (unit vectors per run) with their two lengths fitted by least squares to the contour points whose
    parameter lies in the run (:func:`._merge_kernels.fit_runs`). Returns a dict: the cubics (r, 4, 2), the
    handle lengths (r, 2), the covered points (``lo``, ``count`` per run), their parameters ``t`` on the
    cubics (grouped by run), and per run the largest excess over ``tol``, the largest (``drift``) and the
    summed squared distance (``spread``) from the ``fitted`` curve at the same points; a run stops measuring once
    its excess or drift exceeds ``limits`` (:func:`._merge_kernels.fit_runs`: it cannot qualify then)."""
    last = first + (length - 1)
    start, end = starts[first], ends[last]
    lo = np.searchsorted(u, start, side="left")
    count = np.searchsorted(u, end, side="right") - lo
    np.maximum(count, 0, out=count)
    cubic, handles, offsets, t, excess, drift, spread = kernel_fit_runs(
        bez[:, 0].take(first, axis=0), bez[:, 3].take(last, axis=0), directions[0], directions[1], lo, count,
        points, u, start, end - start, tol, fitted, NEWTON_STEPS, FIT_POINTS, limits)
    return {"cubic": cubic, "handles": handles, "lo": lo, "count": count, "t": t, "excess": excess,
            "drift": drift, "spread": spread}


def _qualify(fit, tolerance, margin):
    """Which runs qualify: within the tolerance of their contour points (less ``margin``), within
    ``tolerance`` of the fitted curve, both handles positive, at least four points."""
    chord = np.hypot(*(fit["cubic"][:, 3] - fit["cubic"][:, 0]).T)
    return ((fit["excess"] + margin <= 0) & (fit["drift"] <= tolerance)
            & (np.minimum(fit["handles"][:, 0], fit["handles"][:, 1]) > 1e-3 * chord) & (fit["count"] >= 4))


_HANKEL = np.add.outer(np.arange(3), np.arange(3))  # the power of x in each entry of a parabola's normal matrix
_DIAGONAL = np.arange(3)


def join_directions(bez, starts, ends, points, u, interior, bounds, window=WINDOW, head=None):
    """Tangent direction at every join ``j`` (the start of segment ``j``) where ``interior[j]``: a parabola
    ``y = a + b x + c x^2`` fitted by least squares to the contour points within ``window`` times the longer
    neighbouring segment's parameter length of the join (inside ``bounds``, per join), in the frame of the
    fitted curve's tangent there; the direction is ``(1, b)`` in that frame. Elsewhere (and where fewer than
    six points fall in the window) the fitted curve's own direction (``head``: the segments' start tangents, when
    the caller has them)."""
    k = bez.shape[0]
    if head is None:
        head, _ = _tangents(bez)
    out = head.copy()
    j = np.flatnonzero(interior)
    if not j.size:
        return out
    h = ends - starts
    reach = window * np.maximum(h[j], h[j - 1])
    lo = np.searchsorted(u, np.maximum(starts[j] - reach, bounds[0][j]), side="left")
    hi = np.searchsorted(u, np.minimum(starts[j] + reach, bounds[1][j]), side="right")
    count = np.maximum(hi - lo, 0)
    grp = np.repeat(np.arange(j.shape[0]), count)
    ends_at = np.cumsum(count)
    idx = np.repeat(lo - (ends_at - count), count) + np.arange(grp.shape[0])  # lo, lo + 1, ... per join
    # rows gathered by ``take`` (the same values as indexing, several times faster for rows of two)
    p, tx = bez[:, 0].take(j, axis=0), head.take(j, axis=0)
    rel = points.take(idx, axis=0) - p.take(grp, axis=0)
    along = tx.take(grp, axis=0)
    x = (rel[:, 0] * along[:, 0] + rel[:, 1] * along[:, 1]) / np.maximum(reach, 1.0).take(grp)
    y = rel[:, 1] * along[:, 0] - rel[:, 0] * along[:, 1]
    r = j.shape[0]
    # the sums of x^e (e = 0..4) and y x^e (e = 0..2) per join; x^0 = 1: the count and the sum of y
    x2 = x * x
    sums = np.empty((r, 5))
    sums[:, 0] = count
    sums[:, 1], sums[:, 2] = np.bincount(grp, x, r), np.bincount(grp, x2, r)
    sums[:, 3], sums[:, 4] = np.bincount(grp, x2 * x, r), np.bincount(grp, x2 * x2, r)
    rhs = np.empty((r, 3, 1))
    rhs[:, 0, 0], rhs[:, 1, 0], rhs[:, 2, 0] = np.bincount(grp, y, r), np.bincount(grp, y * x, r), \
        np.bincount(grp, y * x2, r)
    m = sums[:, _HANKEL]  # m[:, a, b] = sums of x^(a + b)
    m[:, _DIAGONAL, _DIAGONAL] += 1e-9
    good = count >= 6
    coef = np.zeros((r, 3))
    if good.any():
        coef[good] = np.linalg.solve(m.compress(good, axis=0), rhs.compress(good, axis=0))[..., 0]
    slope = coef[:, 1] / np.maximum(reach, 1.0)
    normal = np.column_stack([-tx[:, 1], tx[:, 0]])
    d = _unit(tx + slope[:, None] * normal)[0]
    out[j[good]] = d.compress(good, axis=0)
    return out


def split_at_extrema(bez, starts, ends, min_gap=MIN_SPLIT):
    """The fitted segments cut (exactly) where their tangent is horizontal or vertical, a font's usual join
    points, at least ``min_gap`` parameter units from either end of a segment: the Bézier pieces, their
    parameter intervals and the segment each comes from."""
    d0, d1, d2 = bez[:, 1] - bez[:, 0], bez[:, 2] - bez[:, 1], bez[:, 3] - bez[:, 2]
    a, b, c = d0 - 2 * d1 + d2, 2 * (d1 - d0), d0
    h = ends - starts
    disc = b * b - 4 * a * c
    quadratic = np.abs(a) > 1e-12 * (np.abs(b) + np.abs(c) + 1e-300)
    t = np.empty((bez.shape[0], 4))  # (k, 4): x and y roots
    with np.errstate(divide="ignore", invalid="ignore"):
        root, twice, lin = np.sqrt(np.where(disc >= 0, disc, np.nan)), 2 * a, -c / b
        t[:, :2] = np.where(quadratic, (-b + -1.0 * root) / twice, np.nan)
        t[:, 2:] = np.where(quadratic, (-b + 1.0 * root) / twice, lin)
    low = np.minimum(min_gap / np.maximum(h, 1e-12), 0.5)[:, None]
    t = np.where((t > low) & (t < 1 - low), t, np.nan)
    t.sort(axis=1)
    gap = np.empty_like(t)  # numpy.diff(t, axis=1, prepend=-inf) without its set-up
    gap[:, 0] = t[:, 0] - -np.inf
    np.subtract(t[:, 1:], t[:, :-1], out=gap[:, 1:])
    t = np.where(gap > low, t, np.nan)  # cuts closer than that: one
    t.sort(axis=1)
    cuts = (~np.isnan(t)).sum(axis=1)
    pieces = cuts + 1
    origin = np.repeat(np.arange(bez.shape[0]), pieces)
    bounds = np.empty((bez.shape[0], 6))
    bounds[:, 0], bounds[:, 1:5], bounds[:, 5] = 0.0, np.where(np.isnan(t), 2.0, t), 1.0
    bounds.sort(axis=1)
    pos = np.arange(origin.shape[0]) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    at = origin * bounds.shape[1] + pos  # bounds[origin, pos], flat
    ta, tb = bounds.take(at), bounds.take(at + 1)
    both = np.concatenate([origin, origin])  # each piece's start and end in one pass (the same arithmetic)
    c_, tt = bez.take(both, axis=0), np.concatenate([ta, tb])
    point, speed, half = _curve(c_, tt), _speed(c_, tt), origin.shape[0]
    pa, pb, va, vb = point[:half], point[half:], speed[:half], speed[half:]
    width = (tb - ta)[:, None]
    out = np.stack([pa, pa + width * va / 3.0, pb - width * vb / 3.0, pb], axis=1)
    out[pos == 0, 0] = bez[:, 0].take(origin[pos == 0], axis=0)
    last = pos == pieces[origin] - 1
    out[last, 3] = bez[:, 3].take(origin[last], axis=0)
    return out, starts[origin] + ta * h[origin], starts[origin] + tb * h[origin], origin


def _curve(c, t):
    s = (1.0 - t)[:, None]
    t = t[:, None]
    return s**3 * c[:, 0] + 3 * s * s * t * c[:, 1] + 3 * s * t * t * c[:, 2] + t**3 * c[:, 3]


def _speed(c, t):
    s = (1.0 - t)[:, None]
    t = t[:, None]
    return 3 * (s * s * (c[:, 1] - c[:, 0]) + 2 * s * t * (c[:, 2] - c[:, 1]) + t * t * (c[:, 3] - c[:, 2]))


def choose_runs(k, cand, allowed, periodic=False):
    """Fewest segments for the chain of ``k`` segments from the allowed candidate runs, each join in the
    direction state its two runs agree on (0: the fitted curve's direction, 1: the new one; with ``periodic``
    the chain's two ends are one join, in either state, else state 0), ties broken by the smallest total cost;
    returns the chosen candidates' indices in chain order."""
    first, length = cand["first"].tolist(), cand["length"].tolist()
    s0, s1, cost = cand["s0"].tolist(), cand["s1"].tolist(), cand["spread"].tolist()
    by_end = {}
    for c in np.flatnonzero(allowed).tolist():
        by_end.setdefault(first[c] + length[c], []).append(c)
    never = (1 << 60, 0.0)
    result = None
    for seam in ((0, 1) if periodic else (0,)):
        best = [[never, never] for _ in range(k + 1)]
        back = [[-1, -1] for _ in range(k + 1)]
        best[0][seam] = (0, 0.0)
        for j in range(1, k + 1):
            for c in by_end.get(j, ()):
                count, total = best[first[c]][s0[c]]
                if count == never[0]:
                    continue
                option = (count + 1, total + cost[c])
                if option < best[j][s1[c]]:
                    best[j][s1[c]], back[j][s1[c]] = option, c
        if best[k][seam][0] == never[0] or (result is not None and best[k][seam] >= result[0]):
            continue
        chosen, j, state = [], k, seam
        while j > 0:
            c = back[j][state]
            chosen.append(c)
            j, state = first[c], s0[c]
        result = (best[k][seam], chosen[::-1])
    return np.asarray(result[1], dtype=np.int64)


def _candidates(bez, starts, ends, points, u, tol, fitted, tolerance, seg_piece, interior, direction, o_head,
                o_tail, fit_bez, origin):
    """Every qualifying run with the direction states of its two end joins (0: the fitted curve's direction,
    1: :func:`join_directions`, only at interior joins), grown one segment at a time from every start while one
    of its states qualifies or it has failed at most :data:`MISSES` lengths in a row (potrace's opticurve stops
    at the first failure). Candidates ``0 .. k - 1`` are the segments as they were (states 0, 0; cost 0); the
    others follow by run length, then end states, then start (:func:`choose_runs` breaks ties by this order).

    The runs are fitted :data:`PHASE` lengths at a time in one compiled pass (:func:`fit_runs`): the runs of a
    phase's first length are those the growth rule reaches, the later ones those it may reach (a start that
    fails the lengths before them may stop growing: its runs are fitted and left out, :func:`_grown`)."""
    k = bez.shape[0]
    turn = np.concatenate([[0.0], np.cumsum(_turns(bez))])
    # the fitted segments as they were: their pieces between extrema, and each whole (states 0, 0; cost 0)
    heads = np.flatnonzero(np.concatenate([[True], origin[1:] != origin[:-1]]))  # where origin changes
    whole = np.empty_like(heads)  # pieces per fitted segment
    np.subtract(heads[1:], heads[:-1], out=whole[:-1])
    whole[-1] = k - heads[-1]
    kept = k + int((whole > 1).sum())
    out = {"first": [np.arange(k), heads[whole > 1]], "length": [np.ones(k, np.int64), whole[whole > 1]],
           "s0": [np.zeros(kept, np.int64)], "s1": [np.zeros(kept, np.int64)],
           "spread": [np.zeros(kept)], "cubic": [bez, fit_bez.take(origin[heads[whole > 1]], axis=0)],
           "refit": [np.zeros(kept, bool)], "t": [np.zeros(0)], "t_count": [np.zeros(kept, np.int64)]}
    # a run's start direction in state a is head_dir[a * k + first], its end direction in state b
    # tail_dir[b * k + last] (the new direction of the join after its last segment); a run's states are
    # (a, b) = divmod(state, 2)
    head_dir = np.concatenate([o_head, direction])
    tail_dir = np.concatenate([o_tail, direction[1:], direction[:1]])
    longest = min(MAX_RUN, k)
    # per run length (rows) and start (columns): the run's last segment, and whether it stays in one piece and
    # turns by at most MAX_TURN at this length and every shorter one (a start that fails stops growing)
    first = np.arange(k)
    last = first[None, :] + np.arange(longest)[:, None]
    inside = last < k
    last = np.minimum(last, k - 1)
    within = inside & (seg_piece[last] == seg_piece[None, :]) & (turn[last + 1] - turn[None, :k] <= MAX_TURN)
    within = np.logical_and.accumulate(within, axis=0)
    # the end states (a, b) in the order (0, 0), (0, 1), (1, 0), (1, 1): an end at a join takes the new direction
    # if asked (a == 1), and a longer run takes it wherever it may: its end keeps the old one only where the join
    # has no new direction (a kept segment beside it is refitted as a run of one instead); a single segment in
    # states (0, 0) is the segment as it was
    head_join, tail_join = interior[:k], interior[last + 1]  # per start; per length and start
    head_fixed, tail_fixed = ~head_join, ~tail_join  # ends at a join without a new direction
    valid = np.empty((longest, 4, k), bool)
    valid[:, 0], valid[:, 1] = head_fixed & tail_fixed, head_fixed & tail_join
    valid[:, 2], valid[:, 3] = head_join & tail_fixed, head_join & tail_join
    valid[0, 0], valid[0, 1], valid[0, 2] = False, tail_join[0], head_join
    valid &= within[:, None, :]
    passed = np.zeros((longest, k), bool)  # per length and start: one of the run's states qualifies
    passed[0] = True  # every segment starts runs
    fits = []
    for low in range(0, longest, PHASE):
        high = min(low + PHASE, longest)
        # the starts that reach length low + 1 (every start within its piece and turn at length 1)
        grown = _grown(passed[:low], within[:low + 1])[-1] if low else within[0]
        lengths, states, rows = np.nonzero(valid[low:high] & grown[None, None, :])
        if not rows.size:
            break
        lengths += low + 1
        sa, sb = states >> 1, states & 1
        end = rows + (lengths - 1)
        directions = head_dir.take(sa * k + rows, axis=0), tail_dir.take(sb * k + end, axis=0)
        fit = fit_runs(bez, starts, ends, points, u, rows, lengths, directions, tol, fitted,
                       (-MARGIN, tolerance))  # a run stops measuring where it fails _qualify
        ok = _qualify(fit, tolerance, MARGIN)
        passed[lengths[ok] - 1, rows[ok]] = True
        passed[0] = True
        fits.append((lengths, sa, sb, rows, fit, ok))
    grown = _grown(passed, within)
    for lengths, sa, sb, rows, fit, ok in fits:
        taken = ok & grown[lengths - 1, rows]
        chosen = np.flatnonzero(taken)
        out["first"].append(rows[chosen])
        out["length"].append(lengths[chosen])
        out["s0"].append(sa[chosen])
        out["s1"].append(sb[chosen])
        out["spread"].append(fit["spread"][chosen])
        out["cubic"].append(fit["cubic"].take(chosen, axis=0))
        out["refit"].append(np.ones(chosen.shape[0], bool))
        # the parameters of the covered points on each taken cubic (a chosen run takes them)
        out["t"].append(fit["t"][np.repeat(taken, fit["count"])])
        out["t_count"].append(fit["count"][chosen])
    cand = {key: np.concatenate(value) for key, value in out.items()}
    cand["t_start"] = np.cumsum(cand["t_count"]) - cand["t_count"]
    cand["direction"], cand["o_head"], cand["o_tail"] = direction, o_head, o_tail
    return cand


def _grown(passed, within):
    """Per run length (rows, from 1) and start (columns): whether the growth rule of :func:`_candidates` reaches
    the run: the start stays ``within`` a piece and the turn at every length so far, and it has not failed
    ``MISSES + 1`` lengths in a row before (``passed``: one of the run's states qualifies, per length before;
    length 1 always does)."""
    grown = within.copy()
    failed = ~passed
    streak = failed[MISSES:]
    for back in range(1, MISSES + 1):
        streak = streak & failed[MISSES - back: failed.shape[0] - back]
    # a start stops after the last length of a streak: from the length after it on
    stopped = np.logical_or.accumulate(streak, axis=0)
    grown[MISSES + 1: MISSES + 1 + stopped.shape[0]] &= ~stopped[: max(grown.shape[0] - MISSES - 1, 0)]
    return grown


def merge_steps(model, dev, tolerance):
    """Steps 1 to 3 of ``merge.merge_segments`` on the fit of ``model`` as they were: the pieces (Bézier
    segments, starts, ends, origin), the joins' directions and the candidates (the reference of
    ``_merge_kernels.prepare`` and ``candidates``)."""
    fit_bez = dev["bezier"]
    contour = model.contour
    n = contour.size
    bez, starts, ends, origin = split_at_extrema(fit_bez, dev["starts"], dev["ends"])
    k = bez.shape[0]
    corner_par = model.base_parameter[contour.corner_bounds]
    seg_piece = np.minimum(np.maximum(np.searchsorted(corner_par, starts, side="right") - 1, 0),
                           contour.piece_count - 1)
    u = model.parameter[:n]
    points = contour.points
    tol = np.ascontiguousarray(dev["tol_data"][0::2] if dev["dense"] else dev["tol_data"])
    fitted = curve_points(fit_bez, dev["starts"], dev["ends"], u)
    cornered = contour.corner_count > 0
    interior = np.zeros(k + 1, bool)
    interior[1:k] = seg_piece[1:] == seg_piece[:-1]
    o_head, o_tail = _tangents(bez)
    if cornered:
        direction = join_directions(bez, starts, ends, points, u, interior[:k],
                                    (corner_par[seg_piece], corner_par[seg_piece + 1]), head=o_head)
    else:
        interior[0] = interior[k] = True
        period = model.period
        wide = np.concatenate([u - period, u, u + period])
        direction = join_directions(bez, starts, ends, np.vstack([points] * 3), wide, interior[:k],
                                    (np.full(k, -np.inf), np.full(k, np.inf)), head=o_head)
    cand = _candidates(bez, starts, ends, points, u, tol, fitted, tolerance, seg_piece, interior, direction,
                       o_head, o_tail, fit_bez, origin)
    return (bez, starts, ends, origin), cand
