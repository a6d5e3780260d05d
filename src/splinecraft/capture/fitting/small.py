"""Direct fit of small closed outlines, the small-outline path of ``"lsq"`` (docs/capture.md §12, "Small
outlines").

Noisy or speckled bitmaps have thousands of tiny components (single pixels, dominos, small blobs, thin
diagonal chains: 4-60 crack points each). The regression machinery (:mod:`.lsq`) costs a few milliseconds of
fixed Python-level work per outline whatever its size, so all small outlines of a call are fitted *together*
here: every round is a few stacked dense solves (one per block size) and one batch of nearest-segment
distances for all outlines still refining.

Model: the thesis's interpolant (§2, thesis section 4.2.1, eqs 4.1-4.9) with ``v = 0``, ``omega = 1``
(erratum E2: the plain C² cubic) through knot points that are contour points, parameterized by the contour's
arc length: without corners one periodic loop, with corners one open piece per pair of consecutive corners
with natural ends (§2.4), the pieces meeting at the corner points. A knot interval is finished when the
two-sided deviation between its curve and its contour section is within ``epsilon``; every failing interval
of two or more contour steps gets a knot at its contour point farthest from the curve (kept in the middle
half of the interval). Once an outline is within ``epsilon``, knot-removal rounds (snapshot phase
``"remove"``) drop every other inner knot, put back those whose interval then fails and go back to the
round's start if the outline still fails, as long as removals stick. Acute corners of outlines that pass
:func:`_tip_candidates` get the extrapolated tip of ``"lsq"`` (:func:`_corner_tips`), and so do the corners beside
a pixel corner of a crack outline (a turn between two axis-aligned straight runs, :mod:`.._pixel_corners`), whose
tip is that vertex: the tip is the knot point of both chains that meet there, and the corner's zone has the
allowance of ``"lsq"`` in the deviation check.
When every contour point is a knot the curve interpolates them all, so a crack outline converges for any
``epsilon`` above that interpolant's own deviation (about 0.1-0.2 px; up to 0.4 px beside a corner, where the
natural ends overshoot the staircase); below it the result says so (``FitResult.info["reason"]``), and with the
option ``fallback`` the callers fit such an outline (``info["stuck"]``) by the regression spline of ``"lsq"``
too, and keep that where it converges.
"""
from __future__ import annotations

import numpy as np

from ...spline import Spline
from .._pixel_corners import corner_vertices
from ...spline.segment import bezier_signed_area
from ._kernels import nearest_segment_distance
from ._threads import one_blas_thread
from .budget import BUDGET_REASON
from .lsq_setup import CornerTips, RotatedContour
from .options import LSQ_DEFAULTS, check_corners, check_points
from .results import FitResult, Snapshot
from .tips import LONGEST_SIDE, MIN_CROSSING, SHORTEST_SIDE

__all__ = ["fit_small_trusted", "check_outlines", "MIN_AREA_SHARE", "keeps_area"]

#: Spacing (px) of the curve samples of the deviation check.
_SMALL_SPACING = 0.25
#: Section-length caps (contour steps) of the vectorized deviation buckets.
_SMALL_BUCKETS = (1, 2, 4, 8, 16, 32, 64)
#: Longest initial knot interval (contour steps); only the fallback of larger outlines has longer chains. It
#: bounds the sections (contour edges per interval) of the deviation check.
_SMALL_SECTION = 64
#: Knot-removal rounds after convergence (each tries every other inner knot of a piece).
_REMOVAL_ROUNDS = 4
#: Fewest knots knot removal leaves on a loop (an outline without corners). The C² interpolant through three
#: points is a rounded triangle whichever three they are: on a round dot of 5-20 px it was lopsided (its
#: centroid a median 0.22-0.24 px off, twice the ink pixels' own error), while four knots, as the loop starts
#: with, follow the dot on both axes (``benchmarks/bench_dots.py``, BENCHMARKS "Session 21").
MIN_LOOP_KNOTS = 4
#: Pre-test of the corners whose tip is extrapolated (:func:`_tip_candidates`): both sides at least
#: ``_TIP_TEST_SIDE`` px of arc, the contour's angle (chords of up to 6 steps) below ``_TIP_TEST_ANGLE``, both side
#: windows of :func:`~.tips.tip_estimates` (from its window start to 0.8 of the side) at least
#: :data:`~.tips.SHORTEST_SIDE` long, and the contour points of both (at most ``_TIP_TEST_WINDOW`` steps) within
#: ``_TIP_TEST_RESIDUAL`` px of a parabola, their axes crossing at :data:`~.tips.MIN_CROSSING` or more. Only
#: those corners are measured by :mod:`.tips` (speckle rarely passes).
_TIP_TEST_SIDE = 8.0
_TIP_TEST_ANGLE = np.radians(100.0)
_TIP_TEST_WINDOW = 24
_TIP_TEST_RESIDUAL = 0.7


#: :func:`keeps_area`: the least share of its contour's signed area a small-outline fit must enclose.
MIN_AREA_SHARE = 0.5


def keeps_area(outline, bezier):
    """Whether the closed curve ``bezier`` (``(m, 4, 2)``) fitted to the closed contour ``outline`` (``(n, 2)``)
    encloses at least ``MIN_AREA_SHARE`` of the contour's signed area (shoelace), with the same orientation.

    The small-outline fit accepts a knot interval when its two-sided distance to the contour is within
    ``epsilon`` (0.8 px by default). On a stroke of ink or paper narrower than about ``2 epsilon`` (a dash 1-2
    px wide, a fragment of a hairline, a slit between two spikes, a diagonal chain of speckle) both sides of
    the stroke can pass that test on one chord through its middle, or cross over: a curve of little or no area,
    or one turned inside out, that draws nothing where the pixels have ink. A faithful fit keeps about the
    contour's area (the deviation moves it by a fraction of a pixel per unit of length), so ``fit_outline`` and
    ``trace`` fit an outline that fails this test by the regression spline of ``"lsq"`` instead, which follows the cracks
    (docs/capture.md §12, "Small outlines")."""
    points = np.asarray(outline, float)
    x, y = points[:, 0], points[:, 1]
    contour_area = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    if contour_area == 0.0:
        return True
    return bezier_signed_area(bezier) / contour_area >= MIN_AREA_SHARE


def _small_chains(lengths, corner_lists):
    """Chains of the small-outline model: per outline one periodic loop (no corners) or one open chain per
    pair of consecutive corners (with one corner, the open chain from it round to itself). Returns the
    outline, loop flag, first contour index (unwrapped) and step count of every chain, and the initial knots
    (chain id, unwrapped contour index) sorted by chain and index."""
    chain_outline, chain_loop, chain_start, chain_steps = [], [], [], []
    knot_chain, knot_index = [], []
    for b, (n, corners) in enumerate(zip(lengths, corner_lists)):
        if corners.size == 0:
            c = len(chain_outline)
            chain_outline.append(b), chain_loop.append(True), chain_start.append(0), chain_steps.append(n)
            count = max(min(4, n), -(-n // _SMALL_SECTION))
            knots = np.append(np.arange(count) * n // count, n)  # the seam knot at both ends
            knot_chain.append(np.full(knots.shape[0], c)), knot_index.append(knots)
            continue
        ends = np.append(corners, corners[0] + n)
        for a, z in zip(ends[:-1], ends[1:]):
            c = len(chain_outline)
            chain_outline.append(b), chain_loop.append(False), chain_start.append(int(a))
            chain_steps.append(int(z - a))
            count = max(2 if corners.size == 1 else 1, -(-(z - a) // _SMALL_SECTION))
            knots = a + np.arange(count + 1) * (z - a) // count
            knot_chain.append(np.full(len(knots), c)), knot_index.append(np.asarray(knots, dtype=np.int64))
    return (np.asarray(chain_outline, dtype=np.int64), np.asarray(chain_loop, dtype=bool),
            np.asarray(chain_start, dtype=np.int64), np.asarray(chain_steps, dtype=np.int64),
            np.concatenate(knot_chain).astype(np.int64), np.concatenate(knot_index).astype(np.int64))


def _small_moments(knot_chain, u, F, chain_loop):
    """Second derivatives ``M`` at the knots of the C² cubic interpolants of all chains (stacked dense solves).

    §2.2 with ``v = 0`` (no point tension), ``omega = 1``: the classical moment equations
    ``h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 ((F_{i+1} - F_i) / h_i - (F_i - F_{i-1}) / h_{i-1})``
    with the contour arc length as parameter. Open chains (between corners) have natural ends (``M = 0``,
    §2.4); a loop's last entry is its seam knot again (``M_last = M_first``) and its first row wraps
    round to the entry before the seam. The matrix is block diagonal (one block per chain of at most 65
    knots); the blocks are solved as dense stacks, one ``numpy.linalg.solve`` per block size, so an outline's
    result does not depend on the other outlines of the batch (bit for bit)."""
    count = knot_chain.shape[0]
    entry = np.arange(count)
    first = np.concatenate([[True], knot_chain[1:] != knot_chain[:-1]])
    last = np.concatenate([knot_chain[1:] != knot_chain[:-1], [True]])
    first_of = np.maximum.accumulate(np.where(first, entry, 0))  # first entry of each entry's chain
    last_at = np.flatnonzero(last)
    last_of = last_at[np.cumsum(first) - 1]
    loop = chain_loop[knot_chain]
    prev = np.where(first, last_of - 1, entry - 1)  # a loop's first row wraps to the entry before the seam
    nxt = np.minimum(entry + 1, count - 1)
    h_prev = np.where(first, u[last_of] - u[np.maximum(last_of - 1, 0)], u - u[prev])
    h_next = u[nxt] - u
    interior = ~first & ~last
    cyclic_first = first & loop
    row_eq = interior | cyclic_first  # moment equation rows; the others are M = 0 or M_seam = M_first
    safe_prev = np.where(row_eq, h_prev, 1.0)
    safe_next = np.where(row_eq, h_next, 1.0)
    rhs = np.where(row_eq[:, None], 6.0 * ((F[nxt] - F) / safe_next[:, None] - (F - F[prev]) / safe_prev[:, None]),
                   0.0)
    eq = np.flatnonzero(row_eq)
    seam = np.flatnonzero(last & loop)
    rows = np.concatenate([eq, eq, entry, seam])
    cols = np.concatenate([prev[eq], nxt[eq], entry, first_of[seam]])
    diag = np.where(row_eq, 2.0 * (h_prev + h_next), 1.0)
    data = np.concatenate([h_prev[eq], h_next[eq], diag, -np.ones(seam.shape[0])])
    size = last_of - first_of + 1  # entries of each entry's chain
    moments = np.empty((count, 2))
    for block in np.unique(size):
        members = np.flatnonzero(size == block)
        starts, position = np.unique(first_of[members], return_inverse=True)
        matrices = np.zeros((starts.shape[0], block, block))
        mine = size[rows] == block
        which = np.searchsorted(starts, first_of[rows[mine]])
        np.add.at(matrices, (which, rows[mine] - first_of[rows[mine]], cols[mine] - first_of[rows[mine]]), data[mine])
        right = np.zeros((starts.shape[0], block, 2))
        right[position, members - first_of[members]] = rhs[members]
        moments[members] = np.linalg.solve(matrices, right)[position, members - first_of[members]]
    return moments


def _small_bezier(F0, F1, M0, M1, h):
    """Bézier control points (k, 4, 2) of the cubic with end values ``F0, F1``, end second derivatives
    ``M0, M1`` over a parameter interval of length ``h`` (the Bézier form of §2.3)."""
    h = h[:, None]
    slope = (F1 - F0) / h
    start_tangent = slope - h * (2.0 * M0 + M1) / 6.0
    end_tangent = slope + h * (M0 + 2.0 * M1) / 6.0
    return np.stack([F0, F0 + h * start_tangent / 3.0, F1 - h * end_tangent / 3.0, F1], axis=1)


def _bernstein(bezier, theta):
    """Points (I, T, 2) of the Bézier pieces ``bezier`` (I, 4, 2) at ``theta`` (I, T), elementwise (the same
    bits for a piece whatever else is in the batch)."""
    s = 1.0 - theta
    w0, w1, w2, w3 = s * s * s, 3.0 * theta * s * s, 3.0 * theta * theta * s, theta * theta * theta
    return (w0[..., None] * bezier[:, None, 0] + w1[..., None] * bezier[:, None, 1]
            + w2[..., None] * bezier[:, None, 2] + w3[..., None] * bezier[:, None, 3])


def _small_interval_errors(bezier, a, steps, contour_point, contour_arc, u0, h, zones=None):
    """Per knot interval: the two-sided deviation between its Bézier and its contour section (contour
    points ``a .. a + steps``), the thesis error (contour point vs the curve point at its chord-length
    parameter, thesis eq 4.11), the contour point farthest from the curve (beyond its allowance) and the
    deviation beyond the allowance (the deviation itself without ``zones``).

    ``zones`` (per interval: the arc length of its chain's first end, that end's zone and allowance, the same
    for the last end) gives the corner zones of extrapolated tips: a contour point or curve sample (at its
    parameter, the contour's arc length) within the zone of an end counts its distance less that end's
    allowance.

    Intervals are grouped by section length (caps ``_SMALL_BUCKETS``; shorter sections repeat their last
    point, which changes no minimum) and by sample count (powers of two), and done bucket by bucket with
    one compiled pass of nearest-segment distances (``_kernels.nearest_segment_distance``): curve samples
    ``<= _SMALL_SPACING`` px apart (by the control-polygon length) to the section's edges, and the section's
    points and edge midpoints to the chords between the samples.
    """
    count = a.shape[0]
    deviation = np.zeros(count)
    excess = deviation if zones is None else np.zeros(count)
    thesis = np.zeros(count)
    worst = a.copy()

    def allowed(rows, at):  # allowance at arc lengths ``at`` (rows, m) of the intervals ``rows``
        lo, lo_zone, lo_allow, hi, hi_zone, hi_allow = (z[rows, None] for z in zones)
        return np.maximum(np.where(at - lo < lo_zone, lo_allow, 0.0), np.where(hi - at < hi_zone, hi_allow, 0.0))
    control_length = np.hypot(*np.diff(bezier, axis=1).transpose(2, 0, 1)).sum(axis=1)
    # per interval ceil(length / spacing) + 1 >= 3 samples; the last one is repeated up to the bucket's count
    # (repeats change no minimum or maximum, so each interval's numbers do not depend on the batch)
    sample_count = np.maximum(np.ceil(control_length / _SMALL_SPACING).astype(np.int64) + 1, 3)
    buckets = _SMALL_BUCKETS  # longer sections (the fallback of larger outlines): further powers of two
    while buckets[-1] < steps.max(initial=0):
        buckets = buckets + (2 * buckets[-1],)
    cap_of = np.searchsorted(buckets, steps)
    sample_cap = np.ceil(np.log2(sample_count)).astype(np.int64)
    bucket_of = cap_of * 64 + sample_cap
    for bucket in np.unique(bucket_of):
        rows = np.flatnonzero(bucket_of == bucket)
        cap = buckets[bucket // 64]
        offsets = np.minimum(np.arange(cap + 1)[None, :], steps[rows, None])
        index = a[rows, None] + offsets  # unwrapped contour indices of the section, (I, cap + 1)
        vertices = contour_point(rows, index)
        samples_per = sample_count[rows]
        theta = np.minimum(np.arange(2 ** (bucket % 64))[None, :] / (samples_per[:, None] - 1.0), 1.0)
        samples = _bernstein(bezier[rows], theta)
        vx, vy = vertices[..., 0], vertices[..., 1]
        ex, ey = np.diff(vx, axis=1), np.diff(vy, axis=1)
        curve_near = nearest_segment_distance(samples[..., 0], samples[..., 1], vx[:, :-1], vy[:, :-1], ex, ey)
        curve_side = curve_near.max(axis=1)
        probes_x = np.concatenate([vx, 0.5 * (vx[:, :-1] + vx[:, 1:])], axis=1)
        probes_y = np.concatenate([vy, 0.5 * (vy[:, :-1] + vy[:, 1:])], axis=1)
        sx, sy = samples[..., 0], samples[..., 1]
        to_curve = nearest_segment_distance(probes_x, probes_y, sx[:, :-1], sy[:, :-1], np.diff(sx, axis=1),
                                            np.diff(sy, axis=1))
        deviation[rows] = np.maximum(curve_side, to_curve.max(axis=1))
        index_arc = contour_arc(rows, index)
        if zones is not None:
            sample_arc = u0[rows, None] + theta * h[rows, None]
            curve_near -= allowed(rows, sample_arc)
            to_curve -= allowed(rows, np.concatenate([index_arc, 0.5 * (index_arc[:, :-1] + index_arc[:, 1:])],
                                                     axis=1))
            excess[rows] = np.maximum(curve_near.max(axis=1), to_curve.max(axis=1))
        worst[rows] = index[np.arange(rows.shape[0]), np.argmax(to_curve[:, : cap + 1], axis=1)]
        # thesis error: contour point j vs the curve at theta = (s_j - s_a) / h
        theta_j = np.clip((index_arc - u0[rows, None]) / h[rows, None], 0.0, 1.0)
        at = _bernstein(bezier[rows], theta_j)
        thesis[rows] = np.hypot(*(at - vertices).transpose(2, 0, 1)).max(axis=1)
    return deviation, thesis, worst, excess


def _tip_candidates(points, offsets, lengths, arc, perimeter, corners, pixel_corners=None):
    """Outlines of the batch with a corner whose tip may be extrapolated: a cheap vectorized pre-test of
    :func:`~.tips.tip_estimates`' conditions (both sides long enough for a side window of their own, an acute
    contour angle, both side windows close to a parabola; constants ``_TIP_TEST_*``), or a corner beside a pixel
    corner (:func:`.._pixel_corners.corner_vertices`, whose tip is that vertex; ``pixel_corners``: the outlines'
    :class:`~.._pixel_corners.PixelCorners` where the caller found them, else found there). Returns the
    outlines with such a corner (boolean per outline) and the corners that pass (boolean, the outlines' corners
    one after the other)."""
    counts = np.array([c.shape[0] for c in corners], dtype=np.int64)
    wanted = np.zeros(lengths.shape[0], bool)
    if not counts.any():
        return wanted, np.zeros(0, bool)
    outline = np.repeat(np.arange(lengths.shape[0]), counts)
    c = np.concatenate([np.asarray(k, dtype=np.int64) for k in corners])
    n = lengths[outline]
    entry = np.arange(c.shape[0])
    first = np.concatenate([[True], outline[1:] != outline[:-1]])
    last = np.concatenate([outline[1:] != outline[:-1], [True]])
    first_of = np.maximum.accumulate(np.where(first, entry, 0))
    last_of = np.flatnonzero(last)[np.cumsum(first) - 1]
    following = np.where(last, c[first_of] + n, c[np.minimum(entry + 1, c.shape[0] - 1)])  # the next corner
    steps_after = following - c
    steps_before = np.where(first, steps_after[last_of], np.roll(steps_after, 1))

    def at(i, rows=slice(None)):  # global point indices of unwrapped contour indices (rows of corners first)
        shape = (-1,) + (1,) * (np.ndim(i) - 1)
        return offsets[outline[rows]].reshape(shape) + i % n[rows].reshape(shape)

    side_after = arc[at(following)] + (following // n) * perimeter[outline] - arc[at(c)]
    side_before = np.where(first, side_after[last_of], np.roll(side_after, 1))
    reach = np.minimum(6, (0.4 * np.minimum(steps_before, steps_after)).astype(np.int64))
    a, b = points[at(c - reach)] - points[at(c)], points[at(c + reach)] - points[at(c)]
    theta = np.arccos(np.clip((a * b).sum(axis=1) / np.maximum(np.hypot(*a.T) * np.hypot(*b.T), 1e-12), -1.0, 1.0))
    # the side windows of tip_estimates (from the window start to 0.8 of the side), none of them short
    cotangent = 1.0 / np.maximum(np.tan(0.5 * theta), 1e-6)
    radius = np.minimum(np.clip(LSQ_DEFAULTS["corner_radius"] * cotangent, 1.0, 3.0 * LSQ_DEFAULTS["corner_radius"]),
                        0.2 * np.minimum(side_before, side_after))
    start = np.maximum(radius, np.clip(cotangent, 1.0, 6.0))
    window = np.minimum(0.8 * np.minimum(side_before, side_after), start + LONGEST_SIDE) - start
    ok = (theta < _TIP_TEST_ANGLE) & (window >= SHORTEST_SIDE) & (np.minimum(side_before, side_after)
                                                                  >= _TIP_TEST_SIDE)
    j = np.arange(1, _TIP_TEST_WINDOW + 1)[None, :]
    direction = np.zeros((2, ok.shape[0]))  # of both windows' principal axes (radians)
    for side, (sign, steps) in enumerate(((-1, steps_before), (1, steps_after))):
        rows = np.flatnonzero(ok)
        if not rows.size:
            break
        near = np.ceil(start[rows])[:, None]
        far = np.clip((0.8 * steps[rows]).astype(np.int64), 4, _TIP_TEST_WINDOW)[:, None]
        mask = ((j >= near) & (j <= far)).astype(float)
        mask[mask.sum(axis=1) < 3] = 1.0
        window_points = points[at(c[rows, None] + sign * np.minimum(j, far), rows)]
        weight = mask / mask.sum(axis=1, keepdims=True)
        d = window_points - (weight[..., None] * window_points).sum(axis=1)[:, None]
        sxx, syy = (weight * d[..., 0] ** 2).sum(axis=1), (weight * d[..., 1] ** 2).sum(axis=1)
        phi = 0.5 * np.arctan2(2.0 * (weight * d[..., 0] * d[..., 1]).sum(axis=1), sxx - syy)[:, None]
        t = d[..., 0] * np.cos(phi) + d[..., 1] * np.sin(phi)  # along the principal direction
        y = d[..., 1] * np.cos(phi) - d[..., 0] * np.sin(phi)
        design = np.stack([np.ones_like(t), t, t * t], axis=2) * mask[..., None]
        normal = np.einsum("ijk,ijl->ikl", design, design) + 1e-9 * np.eye(3)
        coefficients = np.linalg.solve(normal, np.einsum("ijk,ij->ik", design, y)[..., None])[..., 0]
        residual = np.abs(y * mask - np.einsum("ijk,ik->ij", design, coefficients)).max(axis=1)
        ok[rows] &= residual <= _TIP_TEST_RESIDUAL
        direction[side, rows] = phi[:, 0]
    # sides meeting at less than tips.MIN_CROSSING give no tip
    ok &= np.abs(np.sin(direction[0] - direction[1])) >= np.sin(MIN_CROSSING)
    # the corners beside a pixel corner: their tip is its vertex (tips.tip_estimates)
    ok |= np.isfinite(corner_vertices(points, lengths, outline, c, pixel_corners)[:, 0])
    wanted[outline[ok]] = True
    return wanted, ok


def _corner_tips(outline, corners, measured, pixel_corners=None):
    """The extrapolated tips of one outline's corners ``measured`` (boolean per corner), by the machinery of
    ``"lsq"`` (:meth:`~.lsq_setup.CornerTips.measure` at the ``"lsq"`` defaults, :func:`~.tips.tip_estimates`;
    ``pixel_corners``: the outline's :class:`~.._pixel_corners.PixelCorners`, or ``None``: found there):
    per corner (in the order of ``corners``) the tip (NaN where there is none), the zone radius (px of arc: the
    zone of "Guarantee" is ``2 r + 1``) and the allowance in that zone (``corner_allowance``, or the tip's
    distance from the contour if larger)."""
    contour = RotatedContour(outline, corners, pixel_corners)
    tips = CornerTips.measure(contour, LSQ_DEFAULTS["corner_radius"], LSQ_DEFAULTS["tip_gap"], True,
                              LSQ_DEFAULTS["corner_allowance"], measured)
    # the rotated contour starts at corners[0], so its corners are in the caller's order
    return tips.estimate, 2.0 * tips.zone_radius + 1.0, tips.allowance


def check_outlines(outlines, corner_lists):
    """The contours (float arrays) and corner index arrays of :func:`fit_small_outlines`, checked as
    :func:`~.options.check_points` and :func:`~.options.check_corners` would check each one."""
    outlines = [np.ascontiguousarray(o, dtype=float) for o in outlines]
    corner_lists = [None] * len(outlines) if corner_lists is None else list(corner_lists)
    if len(corner_lists) != len(outlines):
        raise ValueError(f"corner_lists has {len(corner_lists)} entries for {len(outlines)} outlines")
    if not outlines:
        return [], []
    lengths = np.array([o.shape[0] if o.ndim == 2 else -1 for o in outlines], dtype=np.int64)
    shaped = np.array([o.shape[1:] == (2,) for o in outlines])
    if (lengths < 4).any() or not shaped.all():
        check_points(outlines[int(np.flatnonzero((lengths < 4) | ~shaped)[0])])  # raises the precise error
    points = np.concatenate(outlines)
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    outline_of_point = np.repeat(np.arange(lengths.shape[0]), lengths)
    if not np.isfinite(points).all():
        check_points(outlines[int(outline_of_point[np.flatnonzero(~np.isfinite(points).all(axis=1))[0]])])
    following = np.arange(points.shape[0]) + 1
    following[offsets + lengths - 1] = offsets  # the closing edge of every outline
    step = np.hypot(*(points[following] - points).T)
    if (step <= 0).any():
        check_points(outlines[int(outline_of_point[np.flatnonzero(step <= 0)[0]])])
    return outlines, [check_corners(c, int(n)) for c, n in zip(corner_lists, lengths)]


def fit_small_trusted(outlines, corners, epsilon, max_iterations, keep_snapshots, deadline=None, pixel_corners=None):
    """The small-outline fit of checked contours (float ``(n, 2)`` arrays, ``n >= 4``, no coincident
    neighbours) with sorted unique corner indices: one :class:`FitResult` per outline. ``deadline`` (a
    :class:`~.budget.Deadline`) stops the insertion rounds once it has passed (no removal rounds then); an
    outline left failing says so in ``info["reason"]`` (:data:`~.budget.BUDGET_REASON`). ``pixel_corners``: the
    :class:`~.._pixel_corners.PixelCorners` of every outline where the caller has found them (trace's corner
    stage); ``None``: found here."""
    if not outlines:
        return []
    with one_blas_thread():  # the dense solves of long chains: see _threads
        batch = _SmallBatch(outlines, corners, epsilon, max_iterations, keep_snapshots, deadline, pixel_corners)
        batch.insert_knots()
        if not batch.out_of_time:
            batch.remove_knots()
        return batch.results()


class _SmallBatch:
    """All small outlines of a call, refined side by side. Knots are entries ``(chain, unwrapped contour
    index)`` sorted by chain and index; an outline's numbers never depend on the rest of the batch."""

    def __init__(self, outlines, corners, epsilon, max_iterations, keep_snapshots, deadline=None, pixel_corners=None):
        self.epsilon, self.max_iterations, self.keep = epsilon, max_iterations, keep_snapshots
        self.deadline, self.out_of_time = deadline, False
        self.corners = corners
        lengths = self.lengths = np.array([o.shape[0] for o in outlines], dtype=np.int64)
        points = self.points = np.concatenate(outlines)
        offsets = self.offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
        following = np.arange(points.shape[0]) + 1
        following[offsets + lengths - 1] = offsets  # the closing edge of every outline
        step = np.hypot(*(points[following] - points).T)
        # arc length at every point from its outline's first point, and the perimeters: cumulative sums per
        # outline (a stack per contour length), so each outline's values do not depend on the batch
        self.arc = np.empty(points.shape[0])
        self.perimeter = np.empty(lengths.shape[0])
        for length in np.unique(lengths):
            members = np.flatnonzero(lengths == length)
            index = offsets[members, None] + np.arange(length)[None, :]
            running = np.cumsum(step[index], axis=1)
            self.arc[index] = running - step[index]
            self.perimeter[members] = running[:, -1]
        (self.chain_outline, self.chain_loop, self.chain_start, self.chain_steps, self.knot_chain,
         self.knot_index) = _small_chains(lengths, corners)
        count = self.count = lengths.shape[0]
        self.chains_first = np.searchsorted(self.chain_outline, np.arange(count))  # first chain of every outline
        self._measure_tips(outlines, corners, pixel_corners)
        self.history = [[] for _ in range(count)]
        self.pending = {}  # candidates of the next snapshot, per outline
        self.iterations = np.zeros(count, dtype=np.int64)
        self.failed = np.zeros(count, bool)

    def _measure_tips(self, outlines, corners, pixel_corners=None):
        """Extrapolated tips of acute corners (docs/capture.md §12, "Small outlines"): the outlines that pass
        :func:`_tip_candidates` are measured by :func:`_corner_tips`; a kept tip replaces its corner as the knot
        point of both chains that meet there (``knot_points``), and every chain gets the zone (px of arc from
        its end) and allowance of the tip at either end (``zone_lo``, ``allow_lo``, ``zone_hi``, ``allow_hi``;
        0 where there is none). ``pixel_corners``: those of every outline (:class:`~.._pixel_corners.PixelCorners`),
        or ``None``: found where needed."""
        self.knot_points = self.points
        chains = self.chain_outline.shape[0]
        self.zone_lo, self.allow_lo = np.zeros(chains), np.zeros(chains)
        self.zone_hi, self.allow_hi = np.zeros(chains), np.zeros(chains)
        self.tip_allowance = np.zeros(self.count)  # largest allowance per outline
        wanted, passing = _tip_candidates(self.points, self.offsets, self.lengths, self.arc, self.perimeter,
                                          corners, pixel_corners)
        first = np.cumsum([0] + [c.shape[0] for c in corners])  # of every outline's corners in ``passing``
        for b in np.flatnonzero(wanted):
            estimate, zone, allowance = _corner_tips(outlines[b], corners[b], passing[first[b]:first[b + 1]],
                                                     None if pixel_corners is None else pixel_corners[b])
            kept = np.flatnonzero(np.isfinite(estimate[:, 0]))
            if not kept.size:
                continue
            if self.knot_points is self.points:
                self.knot_points = self.points.copy()
            n = int(self.lengths[b])
            self.knot_points[self.offsets[b] + corners[b][kept]] = estimate[kept]
            self.tip_allowance[b] = allowance[kept].max()
            mine = np.flatnonzero(self.chain_outline == b)
            for k in kept:
                at_lo = mine[self.chain_start[mine] % n == corners[b][k]]
                at_hi = mine[(self.chain_start[mine] + self.chain_steps[mine]) % n == corners[b][k]]
                self.zone_lo[at_lo], self.allow_lo[at_lo] = zone[k], allowance[k]
                self.zone_hi[at_hi], self.allow_hi[at_hi] = zone[k], allowance[k]

    def wrap(self, outline, index):
        return self.offsets[outline] + index % self.lengths[outline]

    def arc_of(self, outline, index):
        return self.arc[self.wrap(outline, index)] + (index // self.lengths[outline]) * self.perimeter[outline]

    def evaluate(self, k_chain, k_index):
        """Solve and measure the chains of the given knot entries (sorted by chain, then contour index)."""
        k_outline = self.chain_outline[k_chain]
        u = self.arc_of(k_outline, k_index)
        knot_points = self.knot_points[self.wrap(k_outline, k_index)]
        moments = _small_moments(k_chain, u, knot_points, self.chain_loop)
        left = np.flatnonzero(k_chain[:-1] == k_chain[1:])  # interval = knot entry and its successor
        right = left + 1
        h = u[right] - u[left]
        bezier = _small_bezier(knot_points[left], knot_points[right], moments[left], moments[right], h)
        i_outline = k_outline[left]
        steps = k_index[right] - k_index[left]
        i_chain = k_chain[left]
        zones = None
        if self.knot_points is not self.points:  # tips: each interval's distances to its chain's ends
            chain_lo = self.arc_of(self.chain_outline[i_chain], self.chain_start[i_chain])
            chain_hi = self.arc_of(self.chain_outline[i_chain], self.chain_start[i_chain] + self.chain_steps[i_chain])
            zones = (chain_lo, self.zone_lo[i_chain], self.allow_lo[i_chain], chain_hi, self.zone_hi[i_chain],
                     self.allow_hi[i_chain])
        deviation, thesis, worst, excess = _small_interval_errors(
            bezier, k_index[left], steps, lambda rows, index: self.points[self.wrap(i_outline[rows, None], index)],
            lambda rows, index: self.arc_of(i_outline[rows, None], index), u[left], h, zones)
        return {"k_chain": k_chain, "k_index": k_index, "k_outline": k_outline, "u": u, "left": left,
                "bezier": bezier, "i_outline": i_outline, "steps": steps, "deviation": deviation,
                "thesis": thesis, "worst": worst, "excess": excess, "failing": excess > self.epsilon}

    def states(self, ev, wanted, phase, candidates):
        """Per outline with ``wanted[b]`` in ``ev``: its state (snapshot and flags), a dict."""
        i_outline, k_outline = ev["i_outline"], ev["k_outline"]
        bounds = np.flatnonzero(np.concatenate([[True], i_outline[1:] != i_outline[:-1], [True]]))
        k_bounds = np.flatnonzero(np.concatenate([[True], k_outline[1:] != k_outline[:-1], [True]]))
        present = i_outline[bounds[:-1]]
        out = {}
        for position in np.flatnonzero(wanted[present]):
            b = int(present[position])
            out[b] = _small_state(bounds[position], bounds[position + 1], k_bounds[position], k_bounds[position + 1],
                                  ev, int(self.lengths[b]), int(self.iterations[b]), self.epsilon, phase,
                                  candidates.pop(b, []))
        return out

    def record(self, b, chain, index, accepted, reason, action):
        """A snapshot candidate of outline ``b`` for its next snapshot."""
        self.pending.setdefault(b, []).append(_candidate(
            chain - self.chains_first[b], index % self.lengths[b], self.points[self.wrap(b, int(index))], accepted,
            reason, action))

    def insert_knots(self):
        """Knot insertion: every failing interval of >= 2 contour steps gets its farthest contour point."""
        active = np.ones(self.count, bool)
        while True:
            in_play = active[self.chain_outline[self.knot_chain]]
            ev = self.evaluate(self.knot_chain[in_play], self.knot_index[in_play])
            i_outline, k_index_ev, left = ev["i_outline"], ev["k_index"], ev["left"]
            splittable = ev["failing"] & (ev["steps"] >= 2)
            inserting = np.bincount(i_outline[splittable], minlength=self.count) > 0
            stop = active & (~inserting | (self.iterations >= self.max_iterations))
            self.failed |= stop & (np.bincount(i_outline[ev["failing"]], minlength=self.count) > 0)
            if self.keep:
                for b, state in self.states(ev, active, "insert", self.pending).items():
                    self.history[b].append(state["snapshot"])
            active &= ~stop
            if not active.any():
                return
            if self.deadline is not None and self.deadline.passed():  # the outlines still failing stay so
                self.out_of_time = True
                self.failed |= active
                return
            adds = np.flatnonzero(splittable & active[i_outline])
            quarter = np.maximum(1, ev["steps"][adds] // 4)
            new_index = np.clip(ev["worst"][adds], k_index_ev[left[adds]] + quarter,
                                k_index_ev[left[adds] + 1] - quarter)
            if self.keep:
                for j, index in zip(adds, new_index):
                    self.record(int(i_outline[j]), ev["k_chain"][left[j]], index, True,
                                f"farthest contour point of a knot interval {ev['deviation'][j]:.3g} px from the "
                                f"curve (> epsilon {self.epsilon:g})", "insert")
            knot_chain = np.concatenate([self.knot_chain, ev["k_chain"][left[adds]]])
            knot_index = np.concatenate([self.knot_index, new_index])
            order = np.lexsort((knot_index, knot_chain))
            self.knot_chain, self.knot_index = knot_chain[order], knot_index[order]
            self.iterations[active] += 1

    def _removal_candidates(self, removing, round_number):
        """Knot entries to try removing this round: every other inner knot of a chain (alternating parity),
        a loop keeping at least :data:`MIN_LOOP_KNOTS` distinct knots."""
        knot_chain = self.knot_chain
        total = knot_chain.shape[0]
        entry = np.arange(total)
        first = np.concatenate([[True], knot_chain[1:] != knot_chain[:-1]])
        last = np.concatenate([knot_chain[1:] != knot_chain[:-1], [True]])
        first_of = np.maximum.accumulate(np.where(first, entry, 0))
        last_of = np.flatnonzero(last)[np.cumsum(first) - 1]
        position = entry - first_of
        entry_outline = self.chain_outline[knot_chain]
        candidate = removing[entry_outline] & ~first & ~last & (position % 2 == 1 - round_number % 2)
        # a loop keeps at least MIN_LOOP_KNOTS distinct knots (its entries are the knots plus the seam again)
        rank = np.cumsum(candidate) - np.cumsum(candidate)[first_of] + candidate[first_of]
        allowed = np.where(self.chain_loop[knot_chain], last_of - first_of - MIN_LOOP_KNOTS, total)
        return candidate & (rank <= allowed), entry_outline

    def _removal_kept(self, candidate, entry_outline, part):
        """Which knot entries stay after removing the candidates of the outlines ``part``: removed knots whose
        interval then fails come back; an outline that still fails goes back to the round's start."""
        count = self.count
        reduced = part[entry_outline] & ~candidate
        ev = self.evaluate(self.knot_chain[reduced], self.knot_index[reduced])
        # the interval of the reduced fit that holds each removed knot
        key_scale = 4 * int(self.lengths.max()) + 4
        start_keys = ev["k_chain"][ev["left"]] * key_scale + ev["k_index"][ev["left"]]
        removed = np.flatnonzero(candidate)
        holder = np.searchsorted(start_keys, self.knot_chain[removed] * key_scale + self.knot_index[removed],
                                 side="right") - 1
        restore = ev["failing"][holder]
        keep = ~candidate
        keep[removed[restore]] = True
        restored_outlines = np.bincount(entry_outline[removed[restore]], minlength=count) > 0
        # the curve of a chain is global (C²): an interval without a removed knot can fail too
        revert = (np.bincount(ev["i_outline"][ev["failing"]], minlength=count) > 0) & ~restored_outlines
        if restored_outlines.any():
            check = keep & restored_outlines[entry_outline]
            ev_check = self.evaluate(self.knot_chain[check], self.knot_index[check])
            still = np.bincount(ev_check["i_outline"][ev_check["failing"]], minlength=count) > 0
            revert |= restored_outlines & still
        keep |= revert[entry_outline]
        return keep, removed

    def remove_knots(self):
        """Knot removal on the converged outlines, while removals stick (both parities tried without success:
        stop), at most :data:`_REMOVAL_ROUNDS` rounds."""
        count = self.count
        removing = ~self.failed & (self.iterations < self.max_iterations)
        idle = np.zeros(count, dtype=np.int64)  # consecutive removal rounds without a removal that stuck
        for round_number in range(_REMOVAL_ROUNDS):
            if not removing.any():
                return
            candidate, entry_outline = self._removal_candidates(removing, round_number)
            part = removing & (np.bincount(entry_outline[candidate], minlength=count) > 0)
            removing &= part
            if not part.any():
                return
            keep, removed = self._removal_kept(candidate, entry_outline, part)
            net = np.bincount(entry_outline[removed[~keep[removed]]], minlength=count)
            if self.keep:
                for j in removed:
                    kept = bool(keep[j])
                    self.record(int(entry_outline[j]), self.knot_chain[j], self.knot_index[j], not kept,
                                "restored: its removal broke the tolerance" if kept else
                                "removed: the fit stays within the tolerance", "restore" if kept else "remove")
            self.knot_chain, self.knot_index = self.knot_chain[keep], self.knot_index[keep]
            self.iterations[part] += 1
            if self.keep:
                in_play = part[self.chain_outline[self.knot_chain]]
                ev = self.evaluate(self.knot_chain[in_play], self.knot_index[in_play])
                for b, state in self.states(ev, part, "remove", self.pending).items():
                    self.history[b].append(state["snapshot"])
            idle = np.where(net > 0, 0, idle + 1)
            removing &= (idle < 2) & (self.iterations < self.max_iterations)

    def results(self):
        final = self.states(self.evaluate(self.knot_chain, self.knot_index), np.ones(self.count, bool), "insert", {})
        results = []
        for b in range(self.count):
            state = final[b]
            if self.keep:  # the same knots as its last snapshot, so the same numbers: use that object
                state["snapshot"] = self.history[b][-1]
            results.append(_small_result(state, self.history[b], self.corners[b], self.lengths[b], self.epsilon,
                                         self.max_iterations, float(self.tip_allowance[b])))
            if self.out_of_time and state["failing"]:
                results[-1].info["reason"] = BUDGET_REASON.format(budget=self.deadline.budget)
                results[-1].info["stuck"] = False
        return results

def _candidate(piece, index, point, accepted, reason, action):
    return {"piece": int(piece), "index": int(index), "point": tuple(map(float, point)), "accepted": bool(accepted),
            "reason": reason, "membership": None, "action": action}


def _small_state(lo, hi, klo, khi, ev, n, iteration, epsilon, phase, candidates):
    """One outline's fit in an evaluation of :func:`fit_small_outlines`: intervals ``lo:hi`` and knot entries
    ``klo:khi`` of the evaluation ``ev``; its snapshot and the numbers of its result."""
    entry_chain = ev["k_chain"][klo:khi]
    u = ev["u"]
    piece_first = np.flatnonzero(np.concatenate([[True], entry_chain[1:] != entry_chain[:-1]]))
    piece_end = np.append(piece_first[1:], khi - klo)
    knot_lists = [ev["k_index"][klo + s: klo + e] % n for s, e in zip(piece_first, piece_end)]
    interval_first = piece_first - np.arange(piece_first.shape[0])  # each piece has one interval less
    piece_dev = np.maximum.reduceat(ev["deviation"][lo:hi], interval_first)
    piece_err = np.maximum.reduceat(ev["thesis"][lo:hi], interval_first)
    starts = u[klo:khi - 1][entry_chain[1:] == entry_chain[:-1]]
    snapshot = Snapshot(iteration=iteration, knot_indices=knot_lists, bezier=ev["bezier"][lo:hi],
                        piece_max_error=piece_err, piece_hausdorff=piece_dev, candidates=candidates,
                        phase="initial" if iteration == 0 else phase, thesis_stop=False,
                        finished=np.maximum.reduceat(ev["excess"][lo:hi], interval_first) <= epsilon,
                        knots=np.append(starts, u[khi - 1]), closed=True)
    failing = ev["failing"][lo:hi]
    return {"snapshot": snapshot, "failing": bool(failing.any()),
            "splittable": bool((failing & (ev["steps"][lo:hi] >= 2)).any()), "iteration": iteration}


def _small_result(state, history, corners, n, epsilon, max_iterations, allowance=0.0):
    """FitResult of one outline of :func:`fit_small_outlines` from its final round."""
    snapshot = state["snapshot"]
    bezier = np.asarray(snapshot.bezier)
    planar = np.ascontiguousarray(bezier.transpose(1, 2, 0))
    knots = np.asarray(snapshot.knots, dtype=float)
    pieces_count = len(snapshot.knot_indices)
    spline = Spline._from_trusted(planar, knots, closed=True, auxiliary={"F": bezier[:, 0].copy()},
                                  info={"form": "outline_fit", "method": "lsq", "epsilon": epsilon,
                                        "pieces": pieces_count, "small_outline": True})
    converged = not state["failing"]
    reason = None
    if not converged:
        worst = float(np.max(snapshot.piece_hausdorff))
        if not state["splittable"]:
            reason = (f"deviation {worst:.3g} px > epsilon {epsilon:g} in a knot interval between two neighbouring "
                      "contour points (no knot can be inserted there: the interpolant through every contour point "
                      "of that stretch cannot get closer)")
        else:
            reason = f"max_iterations={max_iterations} reached with a deviation of {worst:.3g} px"
    distinct_knots = sum(len(k) - 1 for k in snapshot.knot_indices)  # piece ends are the next piece's start
    return FitResult(
        spline=spline,
        pieces=[(int(k[0]), int(k[-1])) for k in snapshot.knot_indices],
        knot_indices=list(snapshot.knot_indices), snapshots=history, iterations=int(state["iteration"]),
        max_error=float(np.max(snapshot.piece_max_error)), hausdorff=float(np.max(snapshot.piece_hausdorff)),
        converged=bool(converged), knots_inserted=int(distinct_knots - corners.shape[0]),
        method="lsq", epsilon=epsilon, thesis_stop_iteration=None, corners_used=corners.copy(),
        info={"small_outline": True, "reason": reason, "stuck": bool(not converged and not state["splittable"]),
              "tolerance_near_corners": epsilon + allowance,
              "model": "C2 cubic interpolant through contour points (v = 0, omega = 1), arc-length parameter, "
                       "natural ends at corners"},
    )
