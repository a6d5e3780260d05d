"""The thesis's randomized knot insertion, Algorithms 4.1-4.6 (thesis section 4.3; docs/capture.md §12).

Per piece between two corners, the interpolant through the knot points (thesis section 4.2.1, eqs 4.1-4.9)
with clamped ends; random candidates drawn by eq 4.10, filtered by the nearness rules of Algs 4.2, 4.3 and
the fuzzy selection of Alg 4.6 (eqs 4.17-4.21). Definitions where the thesis is silent, and the stopping
rule with its guarantee: docs/capture.md §12.
"""
from __future__ import annotations

import math

import numpy as np

from ...spline import Spline, interpolate
from .budget import BUDGET_REASON
from .geometry import piece_deviation
from .options import STALL_ITERATIONS
from .results import FitResult, Snapshot

__all__ = ["fit_thesis"]


def _distinct(points, knots, closed):
    """The sorted knots (local indices) without those whose point repeats the previous kept knot's: the pixel
    chain of a stroke one pixel wide visits its pixel centres twice, and the interpolant takes distinct
    consecutive points. On an open piece both ends stay (an inner knot on an end's point goes); on a loop the
    last kept knot differs from the first too."""
    kept = [int(knots[0])]
    for knot in knots[1:-1] if not closed else knots[1:]:
        if not np.array_equal(points[knot], points[kept[-1]]):
            kept.append(int(knot))
    if closed:
        while len(kept) > 1 and np.array_equal(points[kept[-1]], points[kept[0]]):
            kept.pop()
    else:
        while len(kept) > 1 and np.array_equal(points[kept[-1]], points[knots[-1]]):
            kept.pop()
        kept.append(int(knots[-1]))
    return np.array(kept, dtype=np.int64)


def _unit(vector):
    norm = float(np.hypot(*vector))
    return vector / norm if norm > 0 else vector


class _ThesisPiece:
    """One piece of a thesis-method fit: its contour points, knots (local indices), interpolant and errors."""

    def __init__(self, number, index, points, engine, stride):
        self.number = number
        self.index = index  # global contour indices, in order (corners at both ends)
        self.points = points[index]
        self.size = self.points.shape[0]
        self.arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(self.points, axis=0).T))])
        self.knots = np.array([0, self.size - 1], dtype=np.int64)
        self.engine = engine
        self.stride = stride
        self.finished = False
        self.stalled = 0  # iterations without an accepted candidate
        self.tangents = self._end_tangents()

    def _end_tangents(self):
        """Unit tangents at both ends: thesis eqs 2.1 / 2.2 on ``P_0, P_s, P_2s`` (docs/capture.md §12)."""
        points, size = self.points, self.size
        if size < 3:
            chord = _unit(points[-1] - points[0])
            return chord, chord
        s = max(1, min(self.stride, (size - 1) // 2))
        start = _unit(0.5 * (-3.0 * points[0] + 4.0 * points[s] - points[2 * s]))
        end = _unit(0.5 * (3.0 * points[-1] - 4.0 * points[-1 - s] + points[-1 - 2 * s]))
        if not np.isfinite(start).all() or np.hypot(*start) == 0:
            start = _unit(points[1] - points[0])
        if not np.isfinite(end).all() or np.hypot(*end) == 0:
            end = _unit(points[-1] - points[-2])
        return start, end

    def fit(self):
        self.knots = _distinct(self.points, self.knots, closed=False)
        knot_points = self.points[self.knots]
        # M = T |F_2 - F_1| / h_1, which is T for chord-length knots
        self.spline = interpolate(knot_points, end_condition="clamped", end_tangents=self.tangents, knots="chord",
                                  **self.engine)
        self._measure(self.knots, np.arange(self.size), self.points)
        return self

    def _measure(self, knots, j, contour):
        """Corresponding parameters of the contour points ``j`` (chord length between the ``knots``, thesis
        eq 4.11), their curve points, the errors and the piece's deviation from the polyline ``contour``."""
        t = self.spline.knots
        seg = np.clip(np.searchsorted(knots, j, side="right") - 1, 0, knots.shape[0] - 2)
        k0, k1 = knots[seg], knots[seg + 1]
        frac = (self.arc[j] - self.arc[k0]) / (self.arc[k1] - self.arc[k0])
        self.t_of_point = t[seg] + frac * (t[seg + 1] - t[seg])
        self.curve_points = self.spline(self.t_of_point)
        self.errors = np.hypot(*(self.curve_points - self.points).T)
        self.bezier = self.spline.bezier()
        self.deviation = piece_deviation(self.bezier, contour)

    def bracket(self, loc):
        """The knots (local indices) left and right of local index ``loc``."""
        pos = np.searchsorted(self.knots, loc, side="right")
        left = self.knots[max(pos - 1, 0)]
        right = self.knots[min(pos, self.knots.shape[0] - 1)]
        return int(left), int(right)

    def draw_loc(self, rng, lo=1, hi=None):
        """Thesis eq 4.10 on the points ``lo .. hi`` (default 1 .. size - 1)."""
        return _draw(rng, lo, self.size - 1 if hi is None else hi)


def _draw(rng, lo, hi):
    """One random contour position in ``lo .. hi``: ``LOC = ceil(x / 100 * count)``, thesis eq 4.10."""
    count = hi - lo + 1
    x = 100.0 * rng.random()
    return int(lo - 1 + min(max(math.ceil(x / 100.0 * count), 1), count))


def _draw_candidates(piece, method, rng):
    """Candidate positions of one piece: one (Algs 4.1-4.3), three (4.4, 4.6) or one per third (4.5)."""
    n_last = piece.size - 1  # P_1 .. P_n with P_n the end corner
    if method in ("random", "euclidean", "positional"):
        return [piece.draw_loc(rng, 1, n_last)]
    if method in ("random3", "fuzzy"):
        return [piece.draw_loc(rng, 1, n_last) for _ in range(3)]
    edges = np.linspace(1, n_last, 4)  # equal3: one draw in each third of 1 .. n - 1
    locs = []
    for a, b in zip(edges[:-1], edges[1:]):
        lo, hi = int(math.ceil(a)), max(int(math.floor(b)), int(math.ceil(a)))
        locs.append(piece.draw_loc(rng, lo, min(hi, n_last)))
    return locs


def _fuzzy_choice(info, weights):
    """Alg 4.6: membership ``mu_E^w mu_P^v`` of every candidate (eqs 4.17-4.21); the best one is chosen.
    Returns (chosen positions, rejection reasons, memberships)."""
    distance = np.array([c["d"] for c in info])
    total = distance.sum()
    mu_e = distance / total if total > 0 else np.zeros_like(distance)
    span = np.array([max(c["right"] - c["left"], 1) for c in info], dtype=float)
    positional = np.array([min(c["loc"] - c["left"], c["right"] - c["loc"]) for c in info], dtype=float)
    mu_p = np.clip(positional / (span / 2.0), 0.0, 1.0)
    w, v = weights
    member = mu_e**w * mu_p**v
    best = int(np.argmax(member))
    reasons = {j: f"fuzzy loser (membership {member[j]:.3g} < {member[best]:.3g})"
               for j in range(len(info)) if j != best}
    return [best], reasons, {j: float(member[j]) for j in range(len(info))}


def _nearness(piece, method, tau, candidate):
    """Why a candidate is too near its bracketing knots (Alg 4.2: eqs 4.13-4.15; Alg 4.3: eq 4.16), or None."""
    loc = candidate["loc"]
    if method == "euclidean":
        d_l = float(np.hypot(*(piece.curve_points[loc] - piece.points[candidate["left"]])))
        d_r = float(np.hypot(*(piece.curve_points[loc] - piece.points[candidate["right"]])))
        if d_l < tau or d_r < tau:
            return f"within tau={tau:g} px of knot (d_l={d_l:.2f}, d_r={d_r:.2f})"
    elif method == "positional":
        idx = math.ceil(tau / 100.0 * piece.size)
        d_l, d_r = loc - candidate["left"], candidate["right"] - loc
        if d_l <= idx or d_r <= idx:
            return f"within tau={tau:g}% (IDX={idx}) of knot (d_l={d_l}, d_r={d_r})"
    return None


def _decide(piece, d, near, epsilon):
    """Step 1.5 and the stopping rule of docs/capture.md §12 for one chosen candidate at distance ``d``:
    (accepted, reason, whether the thesis's own test passes)."""
    passes = d > epsilon and near is None
    if piece.finished:
        return False, (f"piece finished (deviation {piece.deviation:.2f} <= eps); thesis rule: "
                       + (f"d={d:.2f} > eps would insert" if passes else (near or f"d={d:.2f} <= eps"))), passes
    stalled = piece.stalled >= STALL_ITERATIONS
    if near is not None and not stalled:
        return False, near, passes
    if passes:
        return True, f"d={d:.2f} > eps", passes
    if stalled:
        return True, (f"stall rule: {STALL_ITERATIONS} iterations without an accepted candidate while the piece "
                      f"deviation is {piece.deviation:.2f} > eps; accepted "
                      + (near if near is not None else f"d={d:.2f} <= eps")), passes
    if float(piece.errors.max()) <= epsilon:
        return True, (f"stall rule: d={d:.2f} <= eps but piece deviation {piece.deviation:.2f} > eps and no "
                      "contour point is farther than eps from its curve point"), passes
    return False, f"d={d:.2f} <= eps (piece deviation {piece.deviation:.2f} > eps: not finished)", passes


def _thesis_iteration(pieces, method, epsilon, tau, weights, rng):
    """One iteration of Algs 4.1-4.6 over all pieces. Returns (candidates, new knots per piece, thesis_pass)."""
    candidates = []
    additions = {}
    thesis_pass = False
    for piece in pieces:
        if piece.size < 3:
            continue
        info = []
        for loc in _draw_candidates(piece, method, rng):
            left, right = piece.bracket(loc)
            info.append({"loc": loc, "d": float(piece.errors[loc]), "left": left, "right": right})
        chosen, reasons, memberships = list(range(len(info))), {}, {}
        if method == "fuzzy":
            chosen, reasons, memberships = _fuzzy_choice(info, weights)
        for j, c in enumerate(info):
            loc = c["loc"]
            record = {"piece": piece.number, "index": int(piece.index[loc]),
                      "point": tuple(map(float, piece.points[loc])), "accepted": False, "reason": "",
                      "membership": memberships.get(j), "action": "insert"}
            candidates.append(record)
            if j not in chosen:
                record["reason"] = reasons[j]
                continue
            if loc in piece.knots:
                record["reason"] = "already a knot (d=0)"
                continue
            record["accepted"], record["reason"], passes = _decide(piece, c["d"], _nearness(piece, method, tau, c),
                                                                   epsilon)
            thesis_pass = thesis_pass or passes
            if record["accepted"]:
                additions.setdefault(piece.number, set()).add(loc)
        if not piece.finished:
            piece.stalled = 0 if piece.number in additions else piece.stalled + 1
    return candidates, additions, thesis_pass


def _closed_pieces(n, corners):
    """Index arrays of the pieces of a closed contour (corners at both ends, wrapping), and (start, end)."""
    out = []
    K = corners.shape[0]
    for k in range(K):
        a, b = int(corners[k]), int(corners[(k + 1) % K])
        if b <= a:
            idx = np.concatenate([np.arange(a, n), np.arange(0, b + 1)])
        else:
            idx = np.arange(a, b + 1)
        out.append(idx)
    return out


def _stopped(deadline):
    """``info["reason"]`` of a fit whose rounds ``deadline`` (a :class:`~.budget.Deadline` or None) stopped (None:
    it did not)."""
    return BUDGET_REASON.format(budget=deadline.budget) if deadline is not None and deadline.passed() else None


def fit_thesis(points, corners, epsilon, method, tau, rng, max_iterations, keep, opts, deadline=None):
    """Algs 4.1-4.6 on a checked contour (corners sorted and unique; ``opts`` from ``check_options``); the
    insertion rounds stop once ``deadline`` (a :class:`~.budget.Deadline`) has passed, with ``info["reason"]``
    saying so."""
    n = points.shape[0]
    engine, stride, weights = opts["engine"], opts["tangent_stride"], opts["fuzzy_weights"]
    if corners.shape[0] == 0:
        return _fit_thesis_periodic(points, epsilon, method, tau, rng, max_iterations, keep, opts, deadline)
    if corners.shape[0] == 1:  # split the loop at the half-way point (two distinct consecutive knots); the first
        c = int(corners[0])   # piece starts at the corner, which _merge_single_corner's knot lists start and end at
        corners_for_pieces = np.array([c, (c + n // 2) % n])
    else:
        corners_for_pieces = corners
    pieces = [_ThesisPiece(k, idx, points, engine, stride)
              for k, idx in enumerate(_closed_pieces(n, corners_for_pieces))]
    for piece in pieces:
        piece.fit()
        piece.finished = piece.deviation <= epsilon

    def snap(iteration, candidates, phase, thesis_stop):
        bezier, knots = _concat(pieces)
        return Snapshot(iteration=iteration, knot_indices=[p.index[p.knots].copy() for p in pieces], bezier=bezier,
                        piece_max_error=np.array([p.errors.max() for p in pieces]),
                        piece_hausdorff=np.array([p.deviation for p in pieces]), candidates=candidates,
                        phase=phase, thesis_stop=thesis_stop, finished=np.array([p.finished for p in pieces]),
                        knots=knots)

    snapshots = [snap(0, [], "initial", False)] if keep else []
    thesis_stop_iteration = None
    iteration = 0
    while not all(p.finished for p in pieces) and iteration < max_iterations and not _stopped(deadline):
        iteration += 1
        candidates, additions, thesis_pass = _thesis_iteration(pieces, method, epsilon, tau, weights, rng)
        if not thesis_pass and thesis_stop_iteration is None:
            thesis_stop_iteration = iteration
        for number, locs in additions.items():
            piece = pieces[number]
            piece.knots = np.unique(np.concatenate([piece.knots, np.fromiter(locs, dtype=np.int64)]))
            piece.fit()
            piece.finished = piece.deviation <= epsilon
        if keep:
            snapshots.append(snap(iteration, candidates, "insert", not thesis_pass))
    knots_inserted = int(sum(p.knots.shape[0] - 2 for p in pieces))
    if corners.shape[0] == 1:
        knots_inserted += 1  # the half-way seed point is a knot, not a corner
    result = FitResult(
        spline=_outline_spline(pieces, method, epsilon), pieces=[(int(p.index[0]), int(p.index[-1])) for p in pieces],
        knot_indices=[p.index[p.knots].copy() for p in pieces], snapshots=snapshots, iterations=iteration,
        max_error=float(max(p.errors.max() for p in pieces)), hausdorff=float(max(p.deviation for p in pieces)),
        converged=all(p.finished for p in pieces), knots_inserted=knots_inserted, method=method, epsilon=epsilon,
        thesis_stop_iteration=thesis_stop_iteration, corners_used=corners.copy(),
        info={"tau": tau, "tangent_stride": stride, "fuzzy_weights": list(weights) if method == "fuzzy" else None,
              "reason": None if all(p.finished for p in pieces) else _stopped(deadline)})
    return result if corners.shape[0] != 1 else _merge_single_corner(result, corners)


def _closed_pieces(n, corners):
    """Index arrays of the pieces of a closed contour (corners at both ends, wrapping)."""
    out = []
    count = corners.shape[0]
    for k in range(count):
        a, b = int(corners[k]), int(corners[(k + 1) % count])
        out.append(np.concatenate([np.arange(a, n), np.arange(0, b + 1)]) if b <= a else np.arange(a, b + 1))
    return out


def _merge_single_corner(result, corners):
    """With one corner, the two internal pieces (split at the half-way seed) are reported as one piece."""
    first, second = result.knot_indices
    for s in result.snapshots:
        s.knot_indices = [np.concatenate([s.knot_indices[0], s.knot_indices[1][1:]])]
        s.piece_max_error = np.array([s.piece_max_error.max()])
        s.piece_hausdorff = np.array([s.piece_hausdorff.max()])
        s.finished = np.array([bool(np.all(s.finished))])
        for c in s.candidates:
            c["piece"] = 0
    c = int(corners[0])
    result.pieces = [(c, c)]
    result.knot_indices = [np.concatenate([first, second[1:]])]
    return result


def _concat(pieces):
    """All Bézier pieces of a list of piece fits and their running knot values."""
    bezier = np.concatenate([p.bezier for p in pieces], axis=0)
    knots = [0.0]
    for p in pieces:
        t = p.spline.knots
        knots.extend(knots[-1] + (t[1:] - t[0]))
    return bezier, np.asarray(knots)


def _outline_spline(pieces, method, epsilon):
    bezier, knots = _concat(pieces)
    knot_points = np.concatenate([p.points[p.knots[:-1]] for p in pieces], axis=0)
    return Spline(bezier, knots, closed=True, auxiliary={"F": knot_points},
                  info={"form": "outline_fit", "method": method, "epsilon": epsilon, "pieces": len(pieces)})


class _PeriodicThesisPiece(_ThesisPiece):
    """The single piece of a corner-free outline: a periodic interpolant through the knot points."""

    def __init__(self, points, engine, seeds):
        self.number = 0
        self.points = points
        self.size = points.shape[0]
        self.index = np.arange(self.size)
        self.closed_points = np.vstack([points, points[:1]])
        self.arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(self.closed_points, axis=0).T))])
        self.knots = np.asarray(seeds, dtype=np.int64)
        self.engine = engine
        self.finished = False
        self.stalled = 0

    def fit(self):
        knots = _distinct(self.points, self.knots, closed=True)
        if knots.shape[0] < 3:  # seeds on a tiny loop's repeated points: every point of the loop, once in a row
            knots = _distinct(self.points, np.arange(self.size), closed=True)
        if knots.shape[0] < 3:
            raise ValueError(f"the contour has {knots.shape[0]} distinct points in a row; a closed interpolant "
                             "takes 3 (method 'lsq' fits any contour)")
        self.knots = knots
        self.spline = interpolate(self.points[self.knots], closed=True, knots="chord", **self.engine)
        # the closing knot is index size (= index 0 again)
        self._measure(np.append(self.knots, self.size), np.arange(self.size), self.closed_points)
        return self

    def bracket(self, loc):
        closed_knots = np.append(self.knots, self.size)
        pos = np.searchsorted(closed_knots, loc, side="right")
        return int(closed_knots[max(pos - 1, 0)]), int(closed_knots[min(pos, closed_knots.shape[0] - 1)])


def _fit_thesis_periodic(points, epsilon, method, tau, rng, max_iterations, keep, opts, deadline=None):
    n = points.shape[0]
    piece = _PeriodicThesisPiece(points, opts["engine"], [0, n // 3, (2 * n) // 3])
    piece.fit()
    piece.finished = piece.deviation <= epsilon

    def snap(iteration, candidates, phase, thesis_stop):
        return Snapshot(iteration=iteration, knot_indices=[np.append(piece.knots, piece.knots[0])],
                        bezier=piece.bezier, piece_max_error=np.array([piece.errors.max()]),
                        piece_hausdorff=np.array([piece.deviation]), candidates=candidates, phase=phase,
                        thesis_stop=thesis_stop, finished=np.array([piece.finished]),
                        knots=np.array(piece.spline.knots))

    snapshots = [snap(0, [], "initial", False)] if keep else []
    iteration, thesis_stop_iteration = 0, None
    while not piece.finished and iteration < max_iterations and not _stopped(deadline):
        iteration += 1
        # candidates anywhere on the loop except index 0 (eq 4.10 over P_1 .. P_{n-1})
        candidates, additions, thesis_pass = _thesis_iteration([_PeriodicView(piece)], method, epsilon, tau,
                                                               opts["fuzzy_weights"], rng)
        if not thesis_pass and thesis_stop_iteration is None:
            thesis_stop_iteration = iteration
        if additions:
            piece.knots = np.unique(np.concatenate([piece.knots, np.fromiter(additions[0], dtype=np.int64)]))
            piece.fit()
            piece.finished = piece.deviation <= epsilon
        if keep:
            snapshots.append(snap(iteration, candidates, "insert", not thesis_pass))
    spline = Spline(piece.bezier, piece.spline.knots, closed=True, auxiliary={"F": piece.points[piece.knots]},
                    info={"form": "outline_fit", "method": method, "epsilon": epsilon, "pieces": 1})
    return FitResult(spline=spline, pieces=[(0, 0)], knot_indices=[np.append(piece.knots, piece.knots[0])],
                     snapshots=snapshots, iterations=iteration, max_error=float(piece.errors.max()),
                     hausdorff=float(piece.deviation), converged=bool(piece.finished),
                     knots_inserted=int(piece.knots.shape[0]), method=method, epsilon=epsilon,
                     thesis_stop_iteration=thesis_stop_iteration, corners_used=np.zeros(0, dtype=np.int64),
                     info={"tau": tau, "reason": None if piece.finished else _stopped(deadline)})


class _PeriodicView:
    """The periodic piece as :func:`_thesis_iteration` sees it (points 0 .. n, with n = 0 again)."""

    def __init__(self, piece):
        self._piece = piece
        self.number = 0
        self.size = piece.size + 1
        self.index = np.append(piece.index, 0)
        self.points = piece.closed_points
        self.knots = np.append(piece.knots, piece.size)
        self.errors = np.append(piece.errors, piece.errors[0])
        self.curve_points = np.vstack([piece.curve_points, piece.curve_points[:1]])
        self.finished = piece.finished
        self.deviation = piece.deviation

    @property
    def stalled(self):
        return self._piece.stalled

    @stalled.setter
    def stalled(self, value):
        self._piece.stalled = value

    def bracket(self, loc):
        return self._piece.bracket(loc)

    def draw_loc(self, rng, lo, hi):
        return _draw(rng, lo, hi)
