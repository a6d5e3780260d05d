"""tangent-jump's compiled steps (capture/corners/_jump_kernels.py, docs/capture.md §11) pinned to the numpy
formulation they replaced, kept here as the reference (the module's functions before session 30, docstrings left
out): steps 1-6 of one start (``_detect``: the resampling, the smoothing, the arms' turn, the peaks, the spread
turns, the location and step 6b's test), the levels, canonical starts and congruent starts of a closed outline, and
the union of a symmetric outline's runs. The same answers, bit for bit, not just close ones."""
from __future__ import annotations

import importlib
import warnings

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import splinecraft.capture.corners  # noqa: F401  (the package first: its modules import each other)
from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.corners._common import _circular_max_filter, _prepare
from splinecraft.capture.corners._jump_kernels import arm_lines

jump = importlib.import_module("splinecraft.capture.corners._jump")
_ARM_LADDER, _forward_operators, _line_intersection, _smooth, SAMPLES_PER_POINT = (
    jump._ARM_LADDER, jump._forward_operators, jump._line_intersection, jump._smooth,
    jump.SAMPLES_PER_POINT)
STROKE_END_TURN, STROKE_END_ARM, STROKE_END_REACH, STROKE_END_ON_SIDE, STROKE_END_WIDTH, STROKE_END_PARALLEL = (
    jump.STROKE_END_TURN, jump.STROKE_END_ARM, jump.STROKE_END_REACH, jump.STROKE_END_ON_SIDE, jump.STROKE_END_WIDTH,
    jump.STROKE_END_PARALLEL)
TIP_TRUNCATION, STROKE_END_SLACK, SIDE_REACH, SPREAD_REACH = (jump.TIP_TRUNCATION, jump.STROKE_END_SLACK,
                                                             jump.SIDE_REACH, jump.SPREAD_REACH)
_LARGEST = np.finfo(np.float64).max
_FRAME_MAPS = [(swap, sx, sy) for swap in (False, True) for sx in (1.0, -1.0) for sy in (1.0, -1.0)]
_CONGRUENT_HEAD = 8


# ----------------------------------------------------------------------------------------------------------
# the reference: the numpy formulation before session 30
# ----------------------------------------------------------------------------------------------------------
def _sample_step(total, count):
    return max(1.0, float(total) / (SAMPLES_PER_POINT * count))


def ref_arc_lengths(P, closed):
    ring = np.vstack([P, P[:1]]) if closed else P
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(ring, axis=0).T))])
    if not np.isfinite(arc[-1]):
        raise ValueError("points: the outline's length overflows float64 (coordinates near 1e308); scale the "
                         "points down")
    return ring, arc


def ref_resample(P, closed):
    ring, arc = ref_arc_lengths(P, closed)
    total = arc[-1]
    step = _sample_step(total, len(P))
    count = int(round(total / step))
    if closed:
        where = np.arange(count) * (total / max(count, 1))
    else:
        where = np.linspace(0.0, total, count + 1)
    samples = np.column_stack([np.interp(where, arc, ring[:, 0]), np.interp(where, arc, ring[:, 1])])
    return samples, where, arc[:len(P)], total, step


def ref_signed_arm_turn(R, closed, tolerance, ladder):
    m = len(R)
    reach = max(ladder)
    if closed:                              # R[np.arange(-reach, m + reach) % m], from slices where reach <= m
        padded = np.concatenate([R[m - reach:], R, R[:reach]]) if reach <= m else R[np.arange(-reach, m + reach) % m]
    else:
        padded = np.vstack([np.full((reach, 2), np.nan), R, np.full((reach, 2), np.nan)])
    lines = arm_lines(padded, reach, ladder, _forward_operators, tolerance)
    centres, directions = {-1: lines[0, :, :2], 1: lines[1, :, :2]}, {-1: lines[0, :, 2:], 1: lines[1, :, 2:]}
    a, b = directions[-1], directions[1]
    turn = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.sum(a * b, axis=1)))
    return turn, (centres[-1], a, centres[1], b)


def ref_split_stroke_ends(P, arc, perimeter, samples, where, arms, chosen, nearest, closed):
    m = len(samples)
    centres_before, before, centres_after, after = arms
    # the sides: the first long arm ending g1 samples before each corner and starting g2 after it, and their
    # turn (all corners at once; the few that turn back are examined one by one below)
    reach = np.arange(1, STROKE_END_REACH + 1)
    behind, ahead = chosen[:, None] - reach, chosen[:, None] + reach
    if closed:
        behind, ahead = behind % m, ahead % m
    inside = (behind >= 0).all(axis=1) & (ahead < m).all(axis=1)
    behind, ahead = np.maximum(behind, 0), np.minimum(ahead, m - 1)     # np.clip(., 0, m - 1) of each
    to_before = samples.take(behind, axis=0) - centres_before.take(behind, axis=0)
    to_after = samples.take(ahead, axis=0) - centres_after.take(ahead, axis=0)
    length_before = 2.0 * np.hypot(*to_before.transpose(2, 0, 1))
    length_after = 2.0 * np.hypot(*to_after.transpose(2, 0, 1))
    long_before, long_after = length_before >= STROKE_END_ARM, length_after >= STROKE_END_ARM
    found = inside & long_before.any(axis=1) & long_after.any(axis=1)
    first_before, first_after = reach[long_before.argmax(axis=1)], reach[long_after.argmax(axis=1)]
    rows = np.arange(chosen.size)
    # the sides' directions from the longest arm within reach (an arm of 7 samples beside a thin tip turns by a
    # few degrees with the pixels of a side near an axis, and a wedge of 11 degrees then measured 3)
    longest_before, longest_after = reach[length_before.argmax(axis=1)], reach[length_after.argmax(axis=1)]
    d1s = before[behind[rows, longest_before - 1]]
    d2s = after[ahead[rows, longest_after - 1]]
    with np.errstate(invalid="ignore"):
        side_turn = np.degrees(np.abs(np.arctan2(d1s[:, 0] * d2s[:, 1] - d1s[:, 1] * d2s[:, 0],
                                                 np.sum(d1s * d2s, axis=1))))
        found &= side_turn >= STROKE_END_TURN
    # the few corners that pass: the module's own loop (not compiled), on the rows the kernel forms
    ends = np.column_stack([found, first_before, first_after, longest_before, longest_after, side_turn])
    lines = np.stack([np.hstack([centres_before, before]), np.hstack([centres_after, after])])
    return jump._split_stroke_ends(P, arc, perimeter, samples, where, lines, chosen, nearest, ends, closed)


def ref_jump_peaks(turn, closed, settings):
    m = len(turn)
    near, far, separation = settings["near"], settings["far"], settings["separation"]
    offsets = np.concatenate([np.arange(-far, -near + 1), np.arange(near, far + 1)])
    with np.errstate(invalid="ignore"):
        size = np.abs(turn)
        strength = np.where(np.isnan(size), -np.inf, size)  # |J| is finite or NaN
        rows = np.flatnonzero((strength >= _circular_max_filter(strength, separation, closed))
                              & (size >= settings["min_turn"]))
    idx = rows[:, None] + offsets[None, :]
    if closed:  # turn[(i + offsets) % m]
        flanks = turn[idx % m]
        ends = np.isnan(turn).any()
    else:       # NaN beyond the ends (the first and last rows reach there)
        flanks = np.where((idx >= 0) & (idx < m), turn[np.clip(idx, 0, m - 1)], np.nan)
        ends = True
    if ends:                                # open ends
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)      # all-NaN flanks at open ends
            baseline = np.nanmedian(flanks, axis=1) if rows.size else np.zeros(0)
    else:                                   # the median of an even count, as np.median computes it, 5x faster
        ordered = flanks                    # a gathered copy: sorted in place
        ordered.sort(axis=1)
        half = flanks.shape[1] // 2         # 2 (far - near + 1) flank samples
        baseline = (ordered[:, half - 1] + ordered[:, half]) / 2
    with np.errstate(invalid="ignore"):
        excess = np.abs(turn[rows] - baseline)
        chosen = rows[excess >= settings["min_excess"]]
    return ref_plateau_starts(chosen, m, separation, closed), size


def ref_plateau_starts(chosen, m, separation, closed):
    if chosen.size > 1:
        first = np.ones(chosen.size, dtype=bool)
        first[1:] = chosen[1:] - chosen[:-1] > separation
        if closed and chosen[0] + m - chosen[-1] <= separation:
            first[-1] = False
        chosen = chosen[first]
    return chosen


def ref_release_spread(chosen, turn, arms, closed, spread):
    if spread <= 0 or chosen.size == 0:
        return chosen
    m, reach = len(turn), SPREAD_REACH
    before, after = chosen - reach, chosen + reach
    if closed:
        before, after = before % m, after % m
        valid = np.ones(chosen.size, dtype=bool)
    else:
        valid = (before >= 0) & (after < m)
        before, after = np.maximum(before, 0), np.minimum(after, m - 1)     # np.clip(., 0, m - 1) of each
    a, b = arms[1].take(before, axis=0), arms[3].take(after, axis=0)
    wide = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.sum(a * b, axis=1)))
    alone = ref_nearest_other_gap(chosen, m, closed) > 2 * reach
    j = turn[chosen]
    with np.errstate(invalid="ignore"):
        spread_out = valid & alone & (j * wide > 0) & (np.abs(j) < spread * np.abs(wide))
    return chosen[~spread_out]


def ref_nearest_other_gap(chosen, m, closed):
    if chosen.size < 2:
        return np.full(chosen.size, m, dtype=np.int64)
    step = (chosen[1:] - chosen[:-1]).astype(np.int64)       # the gap from each to the next
    if closed:
        step = np.append(step, chosen[0] + m - chosen[-1])      # the last to the first, across the wrap
        step = np.minimum(step, m - step)                       # around the shorter way
        return np.minimum(step, np.concatenate([step[-1:], step[:-1]]))   # to the next, from the previous
    ahead = np.append(step, m)
    behind = np.insert(step, 0, m)
    return np.minimum(ahead, behind)


def ref_locate(P, arc, perimeter, pos, at, arms, size, closed):
    right = np.minimum(np.searchsorted(arc, pos), len(arc) - 1)   # np.clip(., 0, n - 1) of indices >= 0
    left = np.maximum(right - 1, 0)
    nearest = np.where(np.abs(arc[left] - pos) <= np.abs(arc[right] - pos), left, right)
    if closed:                              # past the last point the closing chord leads back to point 0
        wrap = (perimeter - pos) < np.abs(arc[nearest] - pos)
        nearest[wrap] = 0
    if not nearest.size:
        return nearest
    n = len(P)
    around = nearest[:, None] + np.arange(-6, 7)[None, :]
    if closed:
        around %= n
        along = np.abs(arc[around] - pos[:, None])
        along = np.minimum(along, perimeter - along)
    else:
        around = np.minimum(np.maximum(around, 0), n - 1)
        along = np.abs(arc[around] - pos[:, None])
    rows = np.arange(len(nearest))
    within = along <= 3.0
    apex = _line_intersection(*arms)
    apex_ok = np.isfinite(apex).all(axis=1) & (np.hypot(*(apex - at).T) <= 3.0) & (size < 100.0)
    gap_to_apex = np.hypot(*(P.take(around, axis=0) - apex[:, None, :]).transpose(2, 0, 1))
    near_apex = around[rows, ref_nearest_within(gap_to_apex, within)]
    a, b = arms[1], arms[3]
    outward = a / np.hypot(*a.T)[:, None] - b / np.hypot(*b.T)[:, None]       # points to the apex
    tip = around[rows, ref_farthest_within(np.einsum("kjd,kd->kj", P[around], outward), within)]
    tip = np.where(apex_ok, near_apex, tip)
    return np.where(np.isfinite(outward).all(axis=1), tip, nearest)


def ref_nearest_within(gap, within):
    return np.argmin(np.where(within & ~np.isnan(gap), np.minimum(gap, _LARGEST), np.inf), axis=1)


def ref_farthest_within(reach, within):
    clipped = np.where(within, np.minimum(np.maximum(reach, -_LARGEST), _LARGEST), -_LARGEST)
    return np.argmax(np.where(np.isnan(reach) & within, -np.inf, clipped), axis=1)


def ref_detect(P, closed, settings):
    P = jump._relative(P, settings["scale"])
    samples, where, arc, perimeter, step = ref_resample(P, closed)
    if len(samples) < 8:
        return None
    samples = _smooth(samples, settings["smoothing"] / step, closed)
    ladder = [length for length in _ARM_LADDER if length <= settings["max_arm"] and 2 * length < len(samples)] \
        or [3]
    turn, arms = ref_signed_arm_turn(samples, closed, settings["tolerance"], ladder)
    chosen, size = ref_jump_peaks(turn, closed, settings)
    chosen = ref_release_spread(chosen, turn, arms, closed, settings["spread"])
    nearest = ref_locate(P, arc, perimeter, where[chosen], samples.take(chosen, axis=0),
                      tuple(x.take(chosen, axis=0) for x in arms), size[chosen], closed)
    if settings["stroke_ends"] and chosen.size:
        nearest = ref_split_stroke_ends(P, arc, perimeter, samples, where, arms, chosen, nearest, closed)
    if not closed:
        nearest = nearest[(nearest > 0) & (nearest < len(P) - 1)]
    return np.asarray(nearest, dtype=np.intp)


def ref_distance_levels(P):
    n = len(P)
    scaled = jump._dyadic(P)
    if scaled is None:
        return jump._wide_levels(P)  # rounded (not compiled)
    x, y = scaled[:, 0], scaled[:, 1]
    x, y = x - x.min(), y - y.min()                      # integers in [0, extent]
    extent = max(float(x.max()), float(y.max()))
    if 8.0 * n * (extent + 1.0) ** 2 < 2.0 ** 62:
        x, y = x.astype(np.int64), y.astype(np.int64)
        tx, ty = int(x.sum()), int(y.sum())
        return x * (n * x - 2 * tx) + y * (n * y - 2 * ty)
    return jump._wide_levels(P)  # exact with Python integers (not compiled)


def ref_later(a, b):
    differ = np.flatnonzero(a != b)
    return bool(differ.size) and b[differ[0]] > a[differ[0]]


def ref_point_comparison(levels):
    n = len(levels)
    blocks = []  # the offsets of each block, from and to
    start, size = 0, 16
    while start < n:
        blocks.append((start, min(start + size, n)))
        start, size = start + size, 4 * size
    tripled = np.concatenate([levels, levels, levels])   # levels[(i + d) % n] is tripled[n + i + d], |d| < n
    ways = {}

    def read(i, way, first, stop):
        """``levels[(i + way * d) % n]`` for the offsets ``first <= d < stop``."""
        return tripled[n + i + first:n + i + stop] if way > 0 else tripled[n + i - stop + 1:n + i - first + 1][::-1]

    def first_difference(i, way_i, j, way_j):
        """The sign of the first difference of the levels read from ``j`` (way ``way_j``) less those from ``i``."""
        for first, stop in blocks:
            a, b = read(i, way_i, first, stop), read(j, way_j, first, stop)
            differ = a != b
            at = int(differ.argmax())
            if differ[at]:
                return 1 if b[at] > a[at] else -1
        return 0

    def way(i):
        """The way round of the first half of the key of ``i``: -1 where the levels behind are larger."""
        if i not in ways:
            ways[i] = -1 if first_difference(i, 1, i, -1) > 0 else 1
        return ways[i]

    def later(i, j):
        sign = first_difference(i, way(i), j, way(j)) or first_difference(i, 1, j, 1)
        return None if sign == 0 else sign > 0
    return later


def ref_canonical_starts(levels):
    """The candidates narrowed block by block with the lexicographically largest row found one by one (the loop
    before session 29, which a symmetric outline's tied starts now skip)."""
    n = len(levels)
    top = np.flatnonzero(levels == levels.max())
    point, way = np.concatenate([top, top]), np.repeat([1, -1], len(top))
    offset, block = 1, 16
    while point.size > 1 and offset < n:
        ahead = np.arange(offset, min(offset + block, n))
        rows = levels[(point[:, None] + way[:, None] * ahead[None, :]) % n]
        best = rows[0]
        for row in rows[1:]:
            if ref_later(best, row):
                best = row
        keep = np.all(rows == best, axis=1)
        point, way = point[keep], way[keep]
        offset, block = offset + len(ahead), 4 * block
    order = np.lexsort((-way, point))
    return [(int(i), int(d)) for i, d in zip(point[order], way[order])]


def ref_congruent(a, b):
    if a.shape != b.shape:
        return False
    head_a, head_b = a[:_CONGRUENT_HEAD].tolist(), b[:_CONGRUENT_HEAD].tolist()
    for swap, sx, sy in _FRAME_MAPS:
        if all((y if swap else x) * sx == u and (x if swap else y) * sy == v
               for (x, y), (u, v) in zip(head_a, head_b)) and \
                np.array_equal((a[:, ::-1] if swap else a) * (sx, sy), b):
            return True
    return False


def ref_symmetric_union(P, runs, later, reach=3.0):
    segment = np.hypot(*np.diff(np.vstack([P, P[:1]]), axis=0).T)
    union = np.unique(np.concatenate(runs))
    sets = [set(run.tolist()) for run in runs]
    member = np.array([[index in found for found in sets] for index in union.tolist()])
    dropped = np.zeros(len(union), dtype=bool)
    m = len(union)
    # the arc from a corner to the next is at least their chord: where the chord exceeds ``reach`` (with a margin
    # far above the sums' rounding) the loop below stops at once for that corner, with nothing else to do
    chord = np.hypot(*(P.take(union[(np.arange(m) + 1) % m], axis=0) - P.take(union, axis=0)).T)
    near = np.flatnonzero(chord <= reach * (1.0 + 1e-9)) if m > 1 else np.zeros(0, dtype=np.int64)
    for a in near.tolist():                 # pairs (a, b) with b at most ``reach`` ahead of a
        for step in range(1, m):
            b = (a + step) % m
            i, j = int(union[a]), int(union[b])
            gap = segment[i:j] if j > i else np.concatenate([segment[i:], segment[:j]])
            if np.sum(gap) > reach:
                break
            if (member[a] & member[b]).any():
                continue
            b_later = later(i, j)
            if b_later is not None:
                dropped[a if b_later else b] = True
    return union[~dropped]


def ref_tangent_jump(P, closed, settings):
    n = len(P)
    levels = ref_distance_levels(P) if closed else None
    starts = ref_canonical_starts(levels) if closed else [(0, 1)]
    runs, done = [], []
    for start, direction in starts:         # one, or one per symmetry of a symmetric outline
        # the outline from ``start`` that way round, P[(start + direction * arange(n)) % n], from two slices
        outline = np.concatenate([P[start:], P[:start]] if direction > 0 else [P[start::-1], P[:start:-1]])
        relative = outline - P[start] if len(starts) > 1 else None
        # a start whose outline is a quarter turn or reflection of one already run gives that run's corners
        found = next((found for other, found in done if ref_congruent(relative, other)), None)
        if found is None:
            found = ref_detect(outline, closed, settings)
            if found is None:
                return np.zeros(0, dtype=np.intp)
            done.append((relative, found))
        runs.append((start + direction * found) % n)
    nearest = runs[0] if len(runs) == 1 else ref_symmetric_union(P, runs, ref_point_comparison(levels))
    assert not (settings["fillets"] or settings["wedge"])  # steps 7-8 (not compiled) are not compared here
    return np.unique(np.asarray(nearest, dtype=np.intp))


# ----------------------------------------------------------------------------------------------------------
# outlines and settings
# ----------------------------------------------------------------------------------------------------------
def _crack_outlines(rng, size, symmetry):
    """The crack outlines of a random blob of about ``size`` pixels, made symmetric (0: not; 1: mirrored; 2: a
    quarter turn; 3: both), the kind of outline a trace detects corners on."""
    mask = rng.uniform(size=(size, size)) < 0.55
    for _ in range(2):  # a blob, not noise: a pixel takes its neighbours' majority
        padded = np.pad(mask, 1)
        count = sum(np.roll(np.roll(padded, dy, 0), dx, 1) for dy in (-1, 0, 1) for dx in (-1, 0, 1))[1:-1, 1:-1]
        mask = count >= 5
    if symmetry & 1:
        mask = mask | mask[:, ::-1]
    if symmetry & 2:
        mask = mask | np.rot90(mask) | np.rot90(mask, 2) | np.rot90(mask, 3)
    return [np.asarray(boundary.outline, dtype=float) for boundary in trace_boundaries(np.pad(mask, 2))]


def _walk(rng, count, closed):
    """A random walk of straight runs and turns (open), or a random star polygon's densified outline (closed)."""
    if closed:
        corners = rng.integers(3, 12)
        angle = np.sort(rng.uniform(0, 2 * np.pi, corners))
        radius = rng.uniform(5, 40, corners)
        vertices = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
        edges = [np.linspace(vertices[k], vertices[(k + 1) % corners], int(rng.integers(2, 12)), endpoint=False)
                 for k in range(corners)]
        curve = np.concatenate(edges)
    else:
        heading = np.cumsum(np.where(rng.uniform(size=count) < 0.1, rng.normal(0, 1.2, count), 0.0))
        curve = np.cumsum(np.column_stack([np.cos(heading), np.sin(heading)]), axis=0)
    return curve + rng.normal(0, rng.choice([0.0, 0.05, 0.3]), curve.shape) + rng.uniform(-300, 300, 2)


def _settings(rng):
    """tangent-jump's settings: the defaults, or random ones (a smoothing of more than 7/3 samples takes numpy's
    smoothing, :data:`.._jump.COMPILED_TAPS`)."""
    if rng.uniform() < 0.4:
        return jump.check_tangent_jump_params(smoothing=1.0, tolerance=0.3, min_turn=25.0, min_excess=25.0,
                                              flank=(4, 10), max_arm=40, separation=2, fillets=False, wedge=False)
    near = int(rng.integers(1, 6))
    return jump.check_tangent_jump_params(
        smoothing=float(rng.choice([0.0, 0.5, 1.0, 2.0, 2.4, 4.0])), tolerance=float(rng.choice([0.1, 0.3, 0.8])),
        min_turn=float(rng.choice([0.0, 10.0, 25.0])), min_excess=float(rng.choice([0.0, 10.0, 25.0])),
        flank=(near, near + int(rng.integers(0, 10))), max_arm=int(rng.choice([3, 8, 40, 120])),
        separation=int(rng.integers(1, 5)), spread=float(rng.choice([0.0, 0.5, 1.0])), fillets=False, wedge=False,
        scale=float(rng.choice([1.0, 1.0, 2.0, 3.5])), stroke_ends=bool(rng.uniform() < 0.8))


def _same(got, expected):
    assert (got is None) == (expected is None)
    if got is not None:
        np.testing.assert_array_equal(got, expected)


# ----------------------------------------------------------------------------------------------------------
# the tests
# ----------------------------------------------------------------------------------------------------------
@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), kind=st.sampled_from(["crack", "walk", "polygon"]), size=st.integers(3, 30))
def test_detect_is_the_numpy_formulation(seed, kind, size):
    """Steps 1-6 (:func:`_jump._detect`, the compiled :func:`_jump_kernels.corners_of`) give the corners of the numpy
    formulation, on crack outlines, noisy open walks and polygons, with the default and random settings."""
    rng = np.random.default_rng(seed)
    if kind == "crack":
        curves = [(outline, True) for outline in _crack_outlines(rng, size, 0)[:3]]
    else:
        closed = kind == "polygon"
        curves = [(_walk(rng, 8 * size, closed), closed)]
    for curve, closed in curves:
        P, _ = _prepare(curve, closed)
        if len(P) < 3:
            continue
        options = _settings(rng)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            _same(jump._detect(P, closed, options), ref_detect(P, closed, options))


@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), size=st.integers(2, 24), symmetry=st.integers(0, 3))
def test_symmetric_outlines_are_the_numpy_formulation(seed, size, symmetry):
    """The levels, canonical starts, congruent starts and the union of the runs of symmetric crack outlines
    (:func:`_jump._starts`, :func:`_jump._symmetric_union`, compiled) give the corners of the numpy formulation; the
    levels and starts are those of the numpy functions, also where the coordinates are not dyadic."""
    rng = np.random.default_rng(seed)
    options = _settings(rng) if seed % 3 == 0 else jump.check_tangent_jump_params(
        smoothing=1.0, tolerance=0.3, min_turn=25.0, min_excess=25.0, flank=(4, 10), max_arm=40, separation=2,
        fillets=False, wedge=False)
    for outline in _crack_outlines(rng, size, symmetry)[:3]:
        P, _ = _prepare(outline, True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            _same(jump._tangent_jump(P, True, options), ref_tangent_jump(P, True, options))
        for points in (P, P * (1.0 + 1e-3 * rng.uniform()), P * 2.0 ** 30):  # exact, rounded, Python integers
            levels, starts, source = jump._starts(points)
            expected = ref_distance_levels(points)
            np.testing.assert_array_equal(levels, expected)
            assert starts == ref_canonical_starts(expected)
            assert jump._canonical_starts(expected) == starts
            relative = [np.concatenate([points[s:], points[:s]] if d > 0 else [points[s::-1], points[:s:-1]]) - points[s]
                        for s, d in starts]
            for k in range(len(starts)):
                first = next((r for r in range(k) if source[r] == r and ref_congruent(relative[k], relative[r])), k) \
                    if len(starts) > 1 else k
                assert source[k] == first


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 300), closed=st.booleans(),
       spread=st.sampled_from([0.5, 1.0, 30.0, 1e-3]))
def test_resampling_is_the_numpy_formulation(seed, n, closed, spread):
    """Step 1's resampling (compiled) gives numpy's samples, arc positions, length and step, also on outlines whose
    points lie far apart (a step above 1)."""
    rng = np.random.default_rng(seed)
    P = np.cumsum(rng.normal(0, spread, (n, 2)), axis=0)
    got, expected = jump._resample(P, closed), ref_resample(P, closed)
    for a, b in zip(got, expected):
        np.testing.assert_array_equal(a, b)
