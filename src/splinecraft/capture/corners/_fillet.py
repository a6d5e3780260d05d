"""The fillet test of tangent-jump (``fillets=True``): a detected corner is kept only where the pixels support a
tangent discontinuity (docs/capture.md §11, step 7).

A corner of interior angle ``theta`` rounded by a circular fillet of radius ``r`` lies
``r (1 / sin(theta / 2) - 1)`` inside the point where its two sides cross; a sharp corner's rendering lies at
most ``sqrt(1/2) / sin(theta / 2)`` inside it (a pixel centre must be inside the wedge, so the crack outline
stops up to half a pixel diagonal, moved along the bisector, short of the tip). The test fits both sides of a
corner on windows beyond a fillet of a few pixels, intersects them and measures how far the crossing lies
beyond the outline (:func:`rounding_depths`). Where that depth exceeds what a sharp tip can leave, by more than
the side lines' own uncertainty, the corner is a fillet and is released.

Both bounds scale with ``1 / sin(theta / 2)``, so the test compares ``depth * sin(theta / 2)`` with
:data:`SHARP_TRUNCATION` + :data:`DEPTH_MARGIN`: a fillet is released when its radius exceeds
``(SHARP_TRUNCATION + DEPTH_MARGIN) / (1 - sin(theta / 2))`` plus the slack of the fitted lines (about 3 px at
90 degrees). Everything is in pixels and the same under rotations and reflections of the outline. The margin
and the slack were chosen on the project's synthetic shapes (``benchmarks/bench_corners.py``, seed 0, with its
family of polygons with fillets of 1-8 px), nowhere else.
"""
from __future__ import annotations

import numpy as np

#: How far (px) the crack outline of a sharp tip may stop short of it, times ``sin(theta / 2)``.
SHARP_TRUNCATION = float(np.sqrt(0.5))
#: Allowance (px, times ``sin(theta / 2)``) beyond the truncation of a sharp tip.
DEPTH_MARGIN = 0.1
#: Where the side windows start (px of arc from the corner).
WINDOW_STARTS = (1.0, 2.0, 3.0, 4.0, 5.0, 6.5)
#: Tilt (px over the window's length) that a line fitted to a window of staircase may have; the depth is
#: reduced by ``TILT * (distance to the window's middle) / (window length)`` per side (half of each).
TILT = 0.2
#: Farthest (px of arc) the test moves a corner towards the outline point nearest to its sides' crossing.
RECENTRE = 3.0
#: Lengths (px of arc) of the side windows at each start.
WINDOW_LENGTHS = (6.0, 12.0, 24.0)
#: Largest distance (px) of a window's points from its line for a straight side; a window that strays
#: farther is fitted by a parabola (the staircase of a straight side stays within about half a pixel).
STRAIGHT_RESIDUAL = 0.6
#: Shortest chord (px of arc) of a short side that still gives a direction.
SHORTEST_CHORD = 1.5
#: A side shorter than this (px of arc, to the neighbouring corner) is fitted whole, end to end.
SHORT_SIDE = 8.5
#: Samples per side window (at uniform arc length), and of the outline around a corner.
WINDOW_SAMPLES = 25
NEAR_SAMPLES = 53
#: Newton steps that refine the crossing of two parabolas from the crossing of their lines.
NEWTON_STEPS = 6


def _along(P, arc, perimeter, closed, where):
    """Points of the outline polyline at arc positions ``where`` (any shape; wrapped on closed outlines,
    clamped to the ends of open ones): an array of ``where.shape + (2,)``."""
    if closed:
        ring = np.vstack([P, P[:1]])
        knots = np.concatenate([arc, [perimeter]])
        where = np.mod(where, perimeter)
    else:
        ring, knots = P, arc
    flat = np.ravel(where)
    return np.stack([np.interp(flat, knots, ring[:, 0]), np.interp(flat, knots, ring[:, 1])],
                    axis=-1).reshape(np.shape(where) + (2,))


def _window_spans(room, starts):
    """First and last arc offsets (px from the corner) of the side windows at every window start
    (``starts``, (k, S)) and length of :data:`WINDOW_LENGTHS` on sides of ``room`` px (to the neighbouring
    corner), and whether each fits (3 px clear of that corner); a side shorter than :data:`SHORT_SIDE` has
    one window, its whole chord half a pixel clear of both corners. Arrays (k, S, lengths)."""
    lengths = np.asarray(WINDOW_LENGTHS)
    short = (room < SHORT_SIDE)[:, None, None]
    first = np.where(short, 0.5, starts[:, :, None] + 0.0 * lengths)
    last = np.where(short, room[:, None, None] - 0.5, starts[:, :, None] + lengths)
    fits = np.where(short, room[:, None, None] - 1.0 >= SHORTEST_CHORD, last <= room[:, None, None] - 3.0)
    return first, last, fits & (~short | (np.arange(len(lengths)) == 0))      # a chord counts once


def _side_windows(P, arc, perimeter, closed, at, sign, first, last):
    """Samples (k, S, lengths, :data:`WINDOW_SAMPLES`, 2) of the side windows ``first``..``last`` px of arc
    from the corners at ``at`` towards ``sign``."""
    steps = np.linspace(0.0, 1.0, WINDOW_SAMPLES)
    where = at[:, None, None, None] + sign * (first[..., None] + (last - first)[..., None] * steps)
    return _along(P, arc, perimeter, closed, where)


def _side_curves(points, fits, corner, sign):
    """Curves of side windows ``points`` (..., lengths, samples, 2): centre, unit direction along travel
    (away from the ``corner`` point for ``sign`` +1, towards it for -1) and parabola coefficients
    ``(c0, c1, c2)`` of ``y = c0 + c1 t + c2 t^2`` in the frame of the window's total-least-squares line.

    The bend ``c2`` of a side is its farthest fitting window's own least-squares parabola where that window
    strays more than :data:`STRAIGHT_RESIDUAL` from its line, else 0 (a straight side: lines); every window of
    the side keeps that bend and fits ``c0``, ``c1`` to it, so a curved side is followed to second order
    while the turn of a fillet near the corner does not bend the sides."""
    centre = points.mean(axis=-2)
    local = points - centre[..., None, :]
    sxx, syy = np.sum(local[..., 0] ** 2, axis=-1), np.sum(local[..., 1] ** 2, axis=-1)
    sxy = np.sum(local[..., 0] * local[..., 1], axis=-1)
    angle = 0.5 * np.arctan2(2.0 * sxy, sxx - syy)
    direction = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    flip = np.einsum("...d,...d->...", centre - corner[:, None, None, :], direction) * sign < 0
    direction[flip] *= -1.0
    normal = np.stack([-direction[..., 1], direction[..., 0]], axis=-1)
    t = np.einsum("...md,...d->...m", local, direction)
    y = np.einsum("...md,...d->...m", local, normal)
    far = np.maximum(np.sum(fits, axis=-1) - 1, 0)                  # the longest window that fits
    pick = (*np.indices(far.shape), far)
    tf, yf = t[pick], y[pick]
    design = np.stack([np.ones_like(tf), tf, tf * tf], axis=-1)
    gram = np.einsum("...mi,...mj->...ij", design, design) + 1e-9 * np.eye(3)
    bend = np.linalg.solve(gram, np.einsum("...mi,...m->...i", design, yf)[..., None])[..., 2, 0]
    bend = np.where(np.abs(yf).max(axis=-1) > STRAIGHT_RESIDUAL, bend, 0.0)[..., None]
    rest = y - bend[..., None] * t * t
    spread = np.sum(t * t, axis=-1)
    c1 = np.where(spread > 0, np.sum(t * rest, axis=-1) / np.where(spread > 0, spread, 1.0), 0.0)
    coefficients = np.stack([rest.mean(axis=-1), c1, np.broadcast_to(bend, c1.shape)], axis=-1)
    coefficients = np.where(bend[..., None] != 0, coefficients, 0.0)
    return centre, direction, normal, coefficients


def _curve(side, t):
    """Points and tangents of side curves at their parameters ``t``."""
    centre, direction, normal, (c0, c1, c2) = side
    point = centre + t[..., None] * direction + (c0 + t * (c1 + t * c2))[..., None] * normal
    return point, direction + (c1 + 2.0 * c2 * t)[..., None] * normal


def _crossings(before, after):
    """Crossing points of every pair of side curves (broadcast): the lines' crossing, refined by Newton
    steps on the parabolas; NaN within 8 degrees of parallel or where a step fails."""
    (c1, d1, _, _), (c2, d2, _, _) = before, after
    cross = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
    delta = c2 - c1
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (delta[..., 0] * d2[..., 1] - delta[..., 1] * d2[..., 0]) / cross
        t2 = (delta[..., 0] * d1[..., 1] - delta[..., 1] * d1[..., 0]) / cross
        for _ in range(NEWTON_STEPS if (before[3][2] != 0).any() or (after[3][2] != 0).any() else 0):
            p1, g1 = _curve(before, t1)
            p2, g2 = _curve(after, t2)
            det = -g1[..., 0] * g2[..., 1] + g1[..., 1] * g2[..., 0]
            rhs = p2 - p1
            t1 = t1 + (-rhs[..., 0] * g2[..., 1] + rhs[..., 1] * g2[..., 0]) / det
            t2 = t2 + (g1[..., 0] * rhs[..., 1] - g1[..., 1] * rhs[..., 0]) / det
        point = _curve(before, t1)[0]
    point[(np.abs(cross) < np.sin(np.radians(8.0))) | ~np.isfinite(point).all(axis=-1)] = np.nan
    return point


def _last_two_starts(rooms_before, rooms_after):
    """Per corner, the last two window starts of :data:`WINDOW_STARTS` at which both sides have a window
    that fits (the last one twice where only one fits; (k, 2)), and whether any fits."""
    starts = np.broadcast_to(np.asarray(WINDOW_STARTS), (len(rooms_before), len(WINDOW_STARTS)))
    fit = _window_spans(rooms_before, starts)[2].any(axis=-1) & _window_spans(rooms_after, starts)[2].any(axis=-1)
    # fitting is monotone in the start (a later start needs more room), so the fitting starts come first
    count = fit.sum(axis=1)
    rows = np.arange(len(rooms_before))[:, None]
    pick = np.clip(np.stack([count - 2, count - 1], axis=1), 0, None)
    pick[:, 0] = np.where(count >= 2, pick[:, 0], pick[:, 1])
    return starts[rows, pick], count > 0


def _smallest_valid(values, valid):
    """Smallest entry over the last axis where ``valid`` (NaN where there is none)."""
    smallest = np.where(valid, values, np.inf).min(axis=-1)
    return np.where(valid.any(axis=-1), smallest, np.nan)


def _depths(P, arc, perimeter, closed, at, room_before, room_after, tilt):
    """:func:`rounding_depths` at the arc positions ``at`` as given, and the arc offset (px) from each of
    them to the outline point nearest to the crossing of its sides (the median over the window pairs of the
    last start that fits)."""
    starts, any_fits = _last_two_starts(room_before, room_after)
    corner = _along(P, arc, perimeter, closed, at)
    sides = []
    for sign, room in ((-1.0, room_before), (1.0, room_after)):
        first, last, fits = _window_spans(room, starts)
        points = _side_windows(P, arc, perimeter, closed, at, sign, first, last)
        # a line fitted to L px of staircase may be tilted by about a pixel's fraction over L, which moves
        # it at the corner by that fraction of (distance to the window's middle) / L
        slack = tilt * (0.5 * (first + last)) / np.maximum(last - first, 1e-9)
        sides.append((_side_curves(points, fits, corner, sign), fits, slack))
    (before, fits_before, slack_before), (after, fits_after, slack_after) = sides

    def spread(side, axis):                 # window lengths of one side along axis 2, of the other along 3
        pad = (lambda x: x[:, :, :, None]) if axis == 0 else (lambda x: x[:, :, None, :])
        return (*(pad(x) for x in side[:3]), tuple(pad(c) for c in np.moveaxis(side[3], -1, 0)))

    first, second = spread(before, 0), spread(after, 1)
    apex = _crossings(first, second)                                             # (k, 2, L, L, 2)
    offsets = WINDOW_STARTS[-1] * np.linspace(-1, 1, NEAR_SAMPLES)
    near = _along(P, arc, perimeter, closed, at[:, None] + offsets)
    gaps = apex[..., None, :] - near[:, None, None, None, :, :]
    distance = np.hypot(gaps[..., 0], gaps[..., 1])
    nearest = np.argmin(np.nan_to_num(distance, nan=np.inf), axis=-1)
    gap = np.take_along_axis(gaps, nearest[..., None, None], axis=-2)[..., 0, :]
    outward = first[1] - second[1]                  # from the bend towards the crossing of the sides
    cosine = np.clip(np.sum(first[1] * second[1], axis=-1), -1.0, 1.0)
    depth = np.hypot(gap[..., 0], gap[..., 1]) * np.sin(0.5 * (np.pi - np.arccos(cosine)))
    depth = np.nan_to_num(np.where(np.sum(gap * outward, axis=-1) > 0, depth, 0.0), nan=0.0)
    pair_fits = (fits_before[:, :, :, None] & fits_after[:, :, None, :]).reshape(len(at), 2, -1)
    depth = depth - 0.5 * (slack_before[:, :, :, None] + slack_after[:, :, None, :])
    per_start = _smallest_valid(depth.reshape(len(at), 2, -1), pair_fits)
    found = pair_fits[:, 1] & np.isfinite(apex[:, 1, ..., 0]).reshape(len(at), -1)
    shift = np.where(found, offsets[nearest[:, 1]].reshape(len(at), -1), np.nan)
    with np.errstate(all="ignore"):
        shift = np.sort(np.where(found, shift, np.inf), axis=-1)[np.arange(len(at)),
                                                                  np.maximum(found.sum(axis=-1) - 1, 0) // 2]
    shift = np.where(found.any(axis=-1), shift, 0.0)
    return np.where(any_fits, np.nan_to_num(per_start, nan=0.0).min(axis=1), 0.0), shift


def rounding_depths(P, arc, perimeter, closed, at, room_before, room_after, tilt=None):
    """How far beyond the outline (px) the crossing of each corner's sides lies, times ``sin(theta / 2)``
    (``theta`` the interior angle of the sides' lines); corners at arc positions ``at``, with
    ``room_before`` / ``room_after`` px of arc to the neighbouring corners (or the ends of an open outline).

    At the last two window starts of :data:`WINDOW_STARTS` where both sides have room, the windows lie
    beyond a fillet of a few pixels. There the sides are fitted on windows of the lengths
    :data:`WINDOW_LENGTHS` (:func:`_side_curves`) and every pair of a window before and one after the corner
    is crossed; the depth at a start is the smallest over the pairs (a single staircase step in a short
    window of a nearly axis-parallel side tilts its line by several degrees, and the longer windows do not
    share that error); 0 for a crossing on the other side of the outline or of nearly parallel sides. The result
    is the smaller of the two; 0 where nothing fits. The test runs twice: the second time from the outline
    point nearest to the first crossing (at most :data:`RECENTRE` px away), so that a corner the arms put off
    the middle of a fillet is measured from its middle."""
    at = np.asarray(at, float)
    room_before, room_after = np.asarray(room_before, float), np.asarray(room_after, float)
    tilt = TILT if tilt is None else tilt
    _, shift = _depths(P, arc, perimeter, closed, at, room_before, room_after, tilt)
    shift = np.clip(shift, -np.minimum(RECENTRE, room_before - 1.0), np.minimum(RECENTRE, room_after - 1.0))
    shift = np.where(room_before - 1.0 < 0, 0.0, shift)
    at = np.mod(at + shift, perimeter) if closed else at + shift
    return _depths(P, arc, perimeter, closed, at, room_before + shift, room_after - shift, tilt)[0]


def _rooms(at, perimeter, closed):
    """Arc length before and after each corner (arc positions ``at``, sorted) to its neighbour or an end."""
    if closed:
        gaps = np.diff(np.concatenate([at, [at[0] + perimeter]]))
        return np.roll(gaps, 1), gaps
    return np.diff(np.concatenate([[0.0], at])), np.diff(np.concatenate([at, [perimeter]]))


def release_fillets(P, arc, perimeter, closed, found):
    """The corners ``found`` (sorted indices into the outline ``P``, arc positions ``arc``) whose
    :func:`rounding_depths` stay within :data:`SHARP_TRUNCATION` + :data:`DEPTH_MARGIN`; the others are
    fillets and are released. Every corner's sides end at its detected neighbours (one pass: a released
    corner still bounds its neighbours' windows, since its outline is not straight)."""
    found = np.asarray(found, dtype=np.intp)
    if not found.size:
        return found
    before, after = _rooms(arc[found], perimeter, closed)
    depth = rounding_depths(P, arc, perimeter, closed, arc[found], before, after)
    return found[depth <= SHARP_TRUNCATION + DEPTH_MARGIN]


#: Where the side lines of the wedge test start (px of arc from the corner, at most this fraction of the room
#: to the neighbouring corner), and their longest length (px of arc).
WEDGE_START = 4.0
WEDGE_START_SHARE = 0.3
WEDGE_LENGTH = 24.0
#: How far (px) a paper pixel centre may lie inside (or an ink centre outside) the sharp wedge of a corner's
#: two separating side lines before the pixels contradict a sharp corner there.
WEDGE_CONTRADICTION = 0.2
#: Shortest side window (px of arc) of the wedge test; a corner with a shorter side is not tested (a short
#: window fixes its line's slope too loosely to extrapolate it to the corner).
WEDGE_SHORTEST = 12.0


class _Polyline:
    """The few attributes of a closed outline that :func:`~splinecraft.capture.fitting.tips.side_fit` reads."""

    def __init__(self, P, arc, perimeter):
        self.points, self.closed_points = P, np.vstack([P, P[:1]])
        self.arc, self.perimeter = np.concatenate([arc, [perimeter]]), perimeter

    def point_at_arc(self, where):
        return np.column_stack([np.interp(where, self.arc, self.closed_points[:, 0]),
                                np.interp(where, self.arc, self.closed_points[:, 1])])


def wedge_contradictions(P, arc, perimeter, at, room_before, room_after):
    """Per corner at arc positions ``at`` of a closed crack outline ``P``: how far (px) the pixels near it
    contradict a sharp corner, the wedge of its two sides (docs/capture.md §11, step 7). Each side is the
    line that separates the ink and paper pixel centres of a window from ``min(WEDGE_START, WEDGE_START_SHARE
    * room)`` px of arc on with the largest margin (the centre of the digital straight segment's preimage,
    :func:`~splinecraft.capture.fitting.tips.side_fit`); the pixel centres beside the outline nearer the
    corner than the windows must then lie on their own side of the wedge (ink inside, paper outside,
    :func:`~splinecraft.capture.fitting.tips.tip_contradiction`). A fillet leaves paper centres inside the
    wedge of its sides (its rounding is about ``r^2 (tan(phi / 2) - phi / 2)`` px^2 for a turn ``phi``); a
    sharp corner leaves none but for the lines' own error, bounded by each line's margin (the half-width of
    its preimage at the window) grown linearly to the corner (``margin (1 + 2 d / L)`` at ``d`` px from the
    window's centre, ``L`` its length), which is subtracted. NaN where a side is not a digital straight segment
    or the outline is not a crack outline (no test)."""
    from ..fitting.tips import pixel_pairs, side_fit, tip_contradiction
    at = np.asarray(at, float)
    out = np.full(at.shape, np.nan)
    pairs = pixel_pairs(P)
    if pairs is None:
        return out
    outline = _Polyline(P, arc, perimeter)
    for k, corner_arc in enumerate(at):
        start = min(WEDGE_START, WEDGE_START_SHARE * room_before[k], WEDGE_START_SHARE * room_after[k])
        sides = []
        for sign, room in ((-1, room_before[k]), (1, room_after[k])):
            stop = min(start + WEDGE_LENGTH, room - 2.0)
            sides.append(side_fit(outline, corner_arc, sign, start, stop, pairs) if stop - start >= WEDGE_SHORTEST else None)
        if any(s is None or s.margin <= 0.0 or s.coefficients.any() for s in sides):
            continue
        if abs(sides[0].direction @ sides[1].direction) > np.cos(np.radians(20.0)):
            continue                                    # nearly straight through: no wedge to speak of
        base = tip_contradiction(outline, corner_arc, start, sides, pairs)
        # slack: each side's preimage half-width (its margin) grown to the corner over the window
        slack = 0.0
        for s in sides:
            d = abs(s.local(outline.point_at_arc(np.array([corner_arc % perimeter]))[0]))
            slack = max(slack, s.margin * (1.0 + 2.0 * d / max(s.length, 1e-9)))
        out[k] = base - slack
    return out


def release_wedge_fillets(P, arc, perimeter, closed, found):
    """The corners ``found`` (sorted indices into a closed crack outline ``P``) whose pixels do not contradict
    the sharp wedge of their sides by more than :data:`WEDGE_CONTRADICTION` px (:func:`wedge_contradictions`);
    the others are fillets and are released. Open outlines and other contour forms are returned as given."""
    found = np.asarray(found, dtype=np.intp)
    if not found.size or not closed:
        return found
    before, after = _rooms(arc[found], perimeter, closed)
    contradiction = wedge_contradictions(P, arc, perimeter, arc[found], before, after)
    return found[~(contradiction > WEDGE_CONTRADICTION)]
