"""tangent-jump, the project's corner detector for outline capture."""
from __future__ import annotations

import warnings

import numpy as np

from ._common import _EMPTY, _check_bool, _check_int, _check_real, _plain, _prepare, _result
from ._fillet import release_fillets, release_wedge_fillets
from ._jump_kernels import corners_of, resample, starts_of, union_drops
from .._pixel_corners import with_pixel_corners



# ----------------------------------------------------------------------------------------------------------
# tangent-jump: the project's detector for outline capture
# ----------------------------------------------------------------------------------------------------------
#: Arm lengths tried (samples at 1 px spacing); an arm grows through them while it stays straight.
_ARM_LADDER = (3, 4, 5, 6, 8, 10, 12, 15, 19, 24, 30, 38, 48, 60, 76, 96, 120)
_ARM_OPERATORS = {}
#: At most this many resampled points per input point (see :func:`_resample`).
SAMPLES_PER_POINT = 4
#: Upper bounds of tangent-jump's parameters (px, samples); each is far beyond any useful value and keeps
#: the work of one call proportional to the number of points.
MAX_SMOOTHING = 50.0
MAX_TOLERANCE = 50.0
MAX_FLANK = 500
MAX_SEPARATION = 500
#: Largest detection ``scale`` of :func:`tangent_jump`.
MAX_SCALE = 64.0
#: :func:`detection_scale`: the scales tried, smallest first, the roughness a clean pixel staircase stays
#: within (px, robust spread of the outline about its Gaussian smoothing at ``ROUGHNESS_SIGMA`` px) and that
#: smoothing.
SCALE_LADDER = (1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0)
CLEAN_ROUGHNESS = 0.2
ROUGHNESS_SIGMA = 2.0
#: :func:`detection_scale`: the fewest samples an outline must have at a scale ``k`` (its length over ``k``) for
#: that scale to be tried: :func:`tangent_jump`'s flanks (10 samples either side) and longer arms need room, and
#: the roughness measured with a smoothing of ``2 k`` px on a shorter outline is that of its own shape.
SAMPLES_AT_SCALE = 64
#: :func:`outline_roughness` reads the spread from this quantile of the absolute deviations (the quarter of
#: the samples nearest the median: robust to corners on up to three quarters of a small outline's samples),
#: divided by the same quantile of a standard normal's, ``ROUGHNESS_QUANTILE_NORMAL`` (0.3186).
ROUGHNESS_QUANTILE = 0.25
ROUGHNESS_QUANTILE_NORMAL = 0.31863936396437514   # scipy.stats.norm.ppf(0.5 + ROUGHNESS_QUANTILE / 2)


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


def _forward_operators(length):
    """The centred offsets and slope weights of a forward arm of ``length`` samples (:func:`_arm_operators`), as
    :func:`._jump_kernels.arm_lines` takes them (one function: its tables are formed once per ladder)."""
    return _arm_operators(length, 1)[1:]


def _resample(P, closed):
    """Resample the polyline at uniform arc length; returns the samples, their arc positions, the arc positions of
    the input points, the total length and the step (compiled: :func:`._jump_kernels.resample`); ValueError when
    the coordinates are so large that the length overflows. The step is 1 px, or coarser on outlines whose ``n``
    points are far apart (``total`` px long): ``max(1, total / (SAMPLES_PER_POINT n))``, at most
    ``SAMPLES_PER_POINT`` samples per input point, so memory and time grow with the number of points, not with the
    coordinates' scale."""
    resampled = resample(P, closed, SAMPLES_PER_POINT)
    if resampled is None:
        raise ValueError("points: the outline's length overflows float64 (coordinates near 1e308); scale the "
                         "points down")
    samples, where, arc, step = resampled
    return samples, where, arc[:len(P)], arc[-1], step


#: The smoothing kernels of :func:`_gaussian` by sigma, at most ``GAUSSIANS_KEPT`` of them.
_GAUSSIANS = {}
GAUSSIANS_KEPT = 64
#: Kernels shorter than this are applied by the compiled step 1 (:func:`._jump_kernels.corners_of`): numpy's
#: ``np.convolve`` sums their products one by one from 0 (its BLAS dot product does below 16 terms), which the
#: kernel repeats; longer ones by :func:`_smooth` (numpy).
COMPILED_TAPS = 16
_NO_TAPS = np.zeros(0)
_NO_TAPS.flags.writeable = False


def _gaussian(sigma):
    """The normalized Gaussian kernel of :func:`_smooth` (``sigma`` in samples, > 0): ``2 ceil(3 sigma) + 1``
    taps; kept (read-only) for the next call with the same sigma."""
    kernel = _GAUSSIANS.get(sigma)
    if kernel is None:
        half = int(np.ceil(3 * sigma))
        with np.errstate(over="ignore"):  # a subnormal sigma: the offsets overflow to inf, their weights to 0
            kernel = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma) ** 2)
        kernel /= kernel.sum()
        kernel.flags.writeable = False  # (kept or not: one type for the kernel)
        if len(_GAUSSIANS) < GAUSSIANS_KEPT:
            _GAUSSIANS[sigma] = kernel
    return kernel


def _smooth(samples, sigma, closed):
    """Gaussian smoothing of a sampled curve along its length (sigma in samples); cyclic when closed."""
    if sigma <= 0:
        return samples
    kernel = _gaussian(sigma)
    half = len(kernel) // 2
    m = len(samples)
    if closed:                              # samples[np.arange(-half, m + half) % m], from slices where half <= m
        padded = np.concatenate([samples[m - half:], samples, samples[:half]]) if half <= m else \
            samples[np.arange(-half, m + half) % m]
    else:
        padded = np.pad(samples, ((half, half), (0, 0)), mode="edge")
    return np.column_stack([np.convolve(padded[:, 0], kernel, "valid"),
                            np.convolve(padded[:, 1], kernel, "valid")])


def outline_roughness(points, sigma, closed=True):
    """Robust spread (px) of an outline about its own Gaussian smoothing of ``sigma`` px: the outline resampled
    at 1 px (:func:`_resample`), its residuals from the smoothed samples along the smoothed normals, and
    the ``ROUGHNESS_QUANTILE`` (0.25) quantile of their absolute deviations from their median, divided by the
    same quantile of a standard normal's (so a normal's standard deviation). The median takes out the
    smoothing's pull towards the centre of curvature (the same along an arc); the low quantile ignores the
    samples beside corners, even on a small polygon where they are most of them (the median absolute
    deviation read a clean 84-point polygon as rough at every scale up to 4 and lost three of its four
    corners). 0 for an outline of fewer than 8 samples."""
    return _roughness(*_roughness_samples(points, closed), sigma, closed)


def _roughness_samples(points, closed, checked=False):
    """The outline (checked and its consecutive duplicates merged, unless ``checked``) resampled at
    the step of :func:`_resample` (1 px on crack outlines), relative to its first point, and that step; ``None`` samples
    when there are fewer than 8."""
    P = np.asarray(points, dtype=float) if checked else _prepare(points, closed)[0]
    if len(P) < 3:
        return None, 1.0
    P = P - P[0]
    samples, step = _resample(P, closed)[::4]
    return (samples if len(samples) >= 8 else None), step


def _roughness(samples, step, sigma, closed):
    """:func:`outline_roughness` of an outline resampled at ``step`` px (:func:`_roughness_samples`)."""
    if samples is None:
        return 0.0
    smooth = _smooth(samples, sigma / step, closed)
    offset = samples - smooth                                     # sample minus its smoothed point
    tangent = np.empty_like(smooth)                               # the smoothed curve's central differences
    tangent[1:-1] = smooth[2:] - smooth[:-2]
    tangent[0], tangent[-1] = (smooth[1] - smooth[-1], smooth[0] - smooth[-2]) if closed else \
        (smooth[1] - smooth[0], smooth[-1] - smooth[-2])
    residual = (offset[:, 1] * tangent[:, 0] - offset[:, 0] * tangent[:, 1]) / \
        np.maximum(np.hypot(tangent[:, 0], tangent[:, 1]), 1e-12)
    deviation = np.abs(residual - _median(residual))
    return float(_quantile(deviation, ROUGHNESS_QUANTILE) / ROUGHNESS_QUANTILE_NORMAL)


def _median(values):
    """``np.median`` of a 1-D float array without NaN, as numpy computes it (the middle value, or the mean
    ``(a + b) / 2`` of the two middle ones), from one partition: without ``np.median``'s overhead."""
    n = values.shape[0]
    half = n // 2
    if n % 2:
        return np.partition(values, half)[half]
    part = np.partition(values, (half - 1, half))
    return (part[half - 1] + part[half]) / 2


def _quantile(values, q):
    """``np.quantile(values, q)`` (method "linear") of a 1-D float array without NaN, as numpy computes it: the
    virtual index ``(n - 1) q``, the values at its floor and the next index from one partition, and numpy's
    interpolation between them (``a + (b - a) g``, or ``b - (b - a) (1 - g)`` from ``g = 0.5`` on), without
    ``np.quantile``'s overhead."""
    n = values.shape[0]
    virtual = (n - 1) * float(q)
    below = int(np.floor(virtual))
    above = min(below + 1, n - 1)
    part = np.partition(values, (below, above))
    a, b = part[below], part[above]
    gamma = virtual - below
    difference = b - a
    return b - difference * (1 - gamma) if gamma >= 0.5 else a + difference * gamma


def detection_scale(points, closed=True):
    """The scale at which :func:`tangent_jump` sees an outline as a clean one: the smallest ``k`` of
    :data:`SCALE_LADDER` (1 .. 8) whose outline, divided by ``k``, is as smooth as a clean pixel staircase,
    ``outline_roughness(points, ROUGHNESS_SIGMA * k) <= CLEAN_ROUGHNESS * k`` (2 px and 0.2 px). A clean crack
    outline is 0-0.2 px rough at 2 px (median 0.006 over the 60 outlines of the tuning set of
    ``benchmarks/synthetic_shapes.py`` at 200 px), so it gets 1; scan-like ones (blurred, noisy, thresholded bitmaps)
    1.25-8 (BENCHMARKS.md, "Session 18"). Only the scales ``k`` at which the outline is at least
    ``SAMPLES_AT_SCALE`` (64) samples long are tried (its length is at least ``64 k`` px): on a shorter one the
    detector's flanks and arms reach past the neighbouring corners, and the smoothing of ``2 k`` px measures the
    shape itself (a clean 8 x 8 square read 1.4 px rough at 4 and got 4, where the detector finds none of its
    corners; a noisy 24-px square got 8 and came back as a blob). An outline that is rough at every scale it is
    long enough for gets the largest of them; one rough at every scale of the ladder has no shape for the
    detector to see (the boundary of a noise image): 1, the pixel scale, whose many short pieces also fit
    fastest. The outline is resampled once for all scales."""
    return _scale_of(*_roughness_samples(points, closed), closed)


def checked_detection_scale(points):
    """:func:`detection_scale` of a closed outline known to be finite and without consecutive duplicates
    (a crack outline of :mod:`~splinecraft.capture.contour`), not checked again."""
    return _scale_of(*_roughness_samples(points, True, checked=True), True)


def _scale_of(samples, step, closed):
    if samples is None:
        return 1.0
    largest = len(samples) * step / SAMPLES_AT_SCALE      # the outline holds SAMPLES_AT_SCALE samples at scale k
    ladder = [k for k in SCALE_LADDER if k <= largest] or [1.0]
    for k in ladder:
        if _roughness(samples, step, ROUGHNESS_SIGMA * k, closed) <= CLEAN_ROUGHNESS * k:
            return k
    # rough at every scale it can be seen at: too small for a coarser one (its largest), or noise all through
    return ladder[-1] if len(ladder) < len(SCALE_LADDER) else 1.0


#: Step 6b (:func:`_split_stroke_ends`): the least turn (degrees) between the two sides of a stroke's end, the
#: shortest arm (samples) that gives a side's line, how far (samples) from the corner that arm may end, how close
#: (px) to its side's line the outline counts as on it, the least and largest distance (px) between the two
#: departures (the end's width), and the least ratio of the sides' crossing distance (from the end) to the end's
#: width.
STROKE_END_TURN = 150.0
STROKE_END_ARM = 7.0
STROKE_END_REACH = 6
STROKE_END_ON_SIDE = 0.5
STROKE_END_WIDTH = (1.0, 5.0)
STROKE_END_PARALLEL = 5.0
#: A rendering cuts a sharp tip of opening ``theta`` where it narrows below a pixel: its sides cross at most
#: ``TIP_TRUNCATION / sin(theta / 2)`` px beyond the crack outline (half a pixel diagonal, where the sides moved
#: inwards by it meet; :data:`..fitting.tips.SHARP_TRUNCATION`). Sides crossing farther beyond an end than that
#: (plus ``STROKE_END_SLACK`` px, how well the end's departures are found) belong to a cut end, not a tip.
TIP_TRUNCATION = np.sqrt(0.5)
STROKE_END_SLACK = 1.0
#: How far (px of arc) beyond a departure the corner that replaces it may lie.
SIDE_REACH = 3.0


def _split_stroke_ends(P, arc, perimeter, samples, where, lines, chosen, nearest, ends, closed):
    """Step 6b: a corner between two straight sides that turn back (by ``STROKE_END_TURN`` or more) and do not meet
    near it (parallel, or crossing farther beyond the end than a pixel-truncated tip of their opening can lie,
    ``TIP_TRUNCATION / sin(opening / 2) + STROKE_END_SLACK``, and than ``STROKE_END_PARALLEL`` end widths) is the
    end of a stroke, square or tapered: it becomes two corners, where the outline leaves each side's line.
    Returns the input indices.

    The sides of each corner and their turn come from the compiled steps (``ends``, rows of
    :func:`._jump_kernels.corners_of`): the first long arm (``STROKE_END_ARM`` samples) ending within
    ``STROKE_END_REACH`` samples before the corner and starting within as many after it, the longest ones there
    (an arm of 7 samples beside a thin tip turns by a few degrees with the pixels of a side near an axis, and a
    wedge of 11 degrees then measured 3), and the turn between those; the few corners whose sides are both long
    and turn back are examined here one by one."""
    found = np.flatnonzero(ends[:, 0] > 0)
    if not found.size:
        return nearest
    m = len(samples)
    centres_before, before, centres_after, after = lines[0, :, :2], lines[0, :, 2:], lines[1, :, :2], lines[1, :, 2:]
    out = [[corner] for corner in nearest.tolist()]
    ordered = np.sort(chosen)
    for k in found.tolist():
        i, g1, g2 = int(chosen[k]), int(ends[k, 1]), int(ends[k, 2])
        if _other_corner_near(ordered, chosen, i, -g1 - 2, g2 + 2, m, closed):
            continue                        # the end has its own second corner
        c1, d1 = centres_before[(i - g1) % m], before[(i - g1) % m]
        c2, d2 = centres_after[(i + g2) % m], after[(i + g2) % m]
        n1 = np.array([-d1[1], d1[0]]) / np.hypot(*d1)
        n2 = np.array([-d2[1], d2[0]]) / np.hypot(*d2)
        l1, l2 = int(ends[k, 3]), int(ends[k, 4])
        side1 = centres_before[(i - l1) % m], before[(i - l1) % m]
        side2 = centres_after[(i + l2) % m], after[(i + l2) % m]
        k1 = i - g1
        while k1 < i + g2 and abs((samples[(k1 + 1) % m] - c1) @ n1) <= STROKE_END_ON_SIDE:
            k1 += 1
        k2 = i + g2
        while k2 > k1 and abs((samples[(k2 - 1) % m] - c2) @ n2) <= STROKE_END_ON_SIDE:
            k2 -= 1
        width = float(np.hypot(*(samples[k2 % m] - samples[k1 % m])))
        if not (k1 <= i <= k2 and STROKE_END_WIDTH[0] <= width <= STROKE_END_WIDTH[1]):
            continue
        crossing = _line_intersection(side1[0][None], side1[1][None], side2[0][None], side2[1][None])[0]
        middle = 0.5 * (samples[k1 % m] + samples[k2 % m])
        # a pixel-truncated tip: the sides cross at most TIP_TRUNCATION / sin(opening / 2) beyond the end (where
        # the tip narrows below a pixel), the end found within STROKE_END_SLACK; and at most STROKE_END_PARALLEL
        # end widths away (a guard for sharp wedges whose measured sides are a few degrees off)
        opening = np.radians(max(180.0 - float(ends[k, 5]), 1e-3))
        limit = max(TIP_TRUNCATION / np.sin(0.5 * opening) + STROKE_END_SLACK, STROKE_END_PARALLEL * width)
        if np.isfinite(crossing).all() and np.hypot(*(crossing - middle)) < limit:
            continue
        # each corner: the input point nearest to where its side's line crosses the end's line (the principal
        # line of the samples from one departure to the other), among the points of its half of the end
        end = samples[np.arange(k1, k2 + 1) % m]
        centre = end.mean(axis=0)
        direction = np.linalg.svd(end - centre)[2][0]
        first = where[k1 % m]
        span = (where[k2 % m] - first) % perimeter if closed else where[k2 % m] - first   # arc of the end
        # the input points near the end: their arc from the first departure (only those that can lie within
        # SIDE_REACH of the end, found by bisection: every point of the outline for every end was quadratic)
        near = _arc_window(arc, perimeter, first, span + SIDE_REACH, closed)
        along = (arc[near] - first) % perimeter if closed else arc[near] - first
        along = np.where(along > perimeter - SIDE_REACH, along - perimeter, along)   # just before the first
        picks = []
        for c, d, low, high in ((c1, d1, -SIDE_REACH, 0.5 * span), (c2, d2, 0.5 * span, span + SIDE_REACH)):
            target = _line_intersection(c[None], d[None], centre[None], direction[None])[0]
            candidates = near[(along >= low) & (along <= high)]
            if not np.isfinite(target).all() or not candidates.size:
                break
            picks.append(int(candidates[np.argmin(np.hypot(*(P[candidates] - target).T))]))
        if len(picks) == 2 and picks[0] != picks[1]:
            out[k] = picks
    return np.asarray([corner for pair in out for corner in pair], dtype=np.intp)


def _other_corner_near(ordered, chosen, i, low, high, m, closed):
    """Whether a corner of ``chosen`` other than ``i`` lies ``low .. high`` samples from it (cyclically on a closed
    outline of ``m`` samples, offsets taken in ``(-(m - m // 2), m // 2]``): by bisection in the sorted corners
    ``ordered``, or over every corner where the window reaches that cut."""
    if closed and (high > m // 2 or -low >= m - m // 2):
        others = (chosen - i) % m
        others = np.where(others > m // 2, others - m, others)
        return bool(np.any((others != 0) & (others >= low) & (others <= high)))
    first, last = i + low, i + high
    ranges = [(first, last)]
    if closed and first < 0:
        ranges = [(first + m, m - 1), (0, last)]
    elif closed and last >= m:
        ranges = [(first, m - 1), (0, last - m)]
    count = sum(int(np.searchsorted(ordered, b, "right") - np.searchsorted(ordered, a, "left")) for a, b in ranges)
    return count > int(np.searchsorted(ordered, i, "right") - np.searchsorted(ordered, i, "left"))


def _arc_window(arc, perimeter, first, reach, closed):
    """Indices (ascending) of the input points whose arc length lies within ``SIDE_REACH`` before ``first`` up to
    ``reach`` after it, a pixel more on both sides (cyclically on a closed outline; on an open one also the last
    ``SIDE_REACH`` of the outline, which step 6b reads as just before its start): every point the end's windows
    can take."""
    margin = SIDE_REACH + 1.0
    spans = [(first - margin, first + reach + 1.0)]
    if closed:
        if reach + margin + 1.0 >= perimeter:
            return np.arange(arc.shape[0])
        low, high = spans[0]
        if low < 0.0:
            spans = [(low + perimeter, np.inf), (-np.inf, high)]
        elif high >= perimeter:
            spans = [(low, np.inf), (-np.inf, high - perimeter)]
    else:
        spans.append((perimeter + first - margin, np.inf))
    parts = [np.arange(np.searchsorted(arc, low, "left"), np.searchsorted(arc, high, "right")) for low, high in spans]
    return np.unique(np.concatenate(parts))


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
                 flank=(4, 10), max_arm=40, separation=2, spread=0.5, fillets=False, wedge=False,
                 pixel_corners=True, scale=1.0, stroke_ends=True):
    """Corners as jumps of the tangent direction between straight arms (this project's detector).

    Designed for crack outlines of rasterized shapes (staircase noise of about half a pixel) and tuned on
    the project's own synthetic shapes (``benchmarks/bench_corners.py``: polygons, stars, serif letters,
    mixed line/arc shapes, font glyphs, and smooth shapes that must have no corner); parameters are in
    pixels and degrees.

    1. The outline is resampled at 1 px arc length and smoothed by a Gaussian of ``smoothing`` px, which
       removes single-pixel bumps of the staircase. An outline whose points lie more than
       ``SAMPLES_PER_POINT`` (4) px apart on average is resampled at ``perimeter / (4 n)`` instead, so a call
       costs ``O(n)`` memory whatever the scale of the coordinates (the sample counts below are then in
       that step). A closed outline is resampled from a start and a direction the shape picks
       (:func:`_canonical_starts`: the farthest point from the centroid, exact ties going to the point and
       way round whose followers are farther), relative to that point, so the corners do not depend on
       where the outline starts and turn or reflect with the pixel frame exactly. Where a symmetry of the
       outline ties several starts, steps 1-6 run from each and :func:`_symmetric_union` keeps one version
       of every corner, so the corners are as symmetric as the outline.
    2. **Arms.** At every sample two arms, one backwards and one forwards: the longest length of the ladder
       3, 4, 5, 6, 8, ... ``max_arm`` samples when every sample of that window stays within ``tolerance`` px
       of its least-squares line, else the arm grows through the lengths for as long as every sample of the
       arm stays within ``tolerance`` px of the arm's least-squares line. The arm direction is that line's
       (long arms on straight sides give directions good to a degree or two).
    3. **Turn.** ``J`` is the signed angle from the backward to the forward arm. Along a straight side it
       is ~0; at a corner it is the corner's turn; along an arc of radius ``r`` it is about
       ``arm / r`` -- large on tight arcs, but the same all along the arc.
    4. **Excess.** A corner concentrates its turn: ``E = J - median(J)`` over the flanks
       ``flank[0]..flank[1]`` samples away on both sides. On an arc, and across a tangent-continuous
       join of a line and an arc, ``E`` is ~0 (the arc's turn is in the flanks too); at a corner it is the
       corner's turn, also when another corner lies in one flank (the median ignores it).
    5. A sample is a corner when ``|J|`` is the largest within ``separation`` samples, ``|J| >= min_turn``
       and ``|E| >= min_excess``.
    5b. **Spread turns.** A corner is dropped when the turn ``T`` from the backward arm 8 samples before it
       to the forward arm 8 samples after it goes the same way as ``J`` and ``|J| < spread * |T|``, and no
       other corner of step 5 lies within 16 samples (compiled, :func:`._jump_kernels.corners_of`): the outline keeps turning
       beyond the arms, as at the end of an ellipse or on a fillet, where the flank median of step 4 sees
       the flatter outline farther out and ``E`` overstates the concentration.
    6. **Location.** Each corner goes to an input point within 3 px (arc length) of its sample: for a
       turn below 100 deg the one nearest to the apex where the two arm lines meet; for a sharper turn,
       whose rasterized tip is cut off (the apex lies beyond the outline), the one farthest out along the
       bisector ``a/|a| - b/|b|`` of the arm directions, where the vertex of the two sides is extreme.

    6b. **Stroke ends** (``stroke_ends``, default True; :func:`_split_stroke_ends`). Steps 1-5 merge two corners
       closer than about 3 px into one, as at the square end of a stroke 1-5 px wide: one corner of 100-150 deg in
       the middle of the end, which the fit then rounds (a 3-px bar turned by 45 degrees came back 1.4 px off its
       rectangle). A corner is taken for such an end when the sides beside it (the first arms of at least
       ``STROKE_END_ARM`` samples within ``STROKE_END_REACH`` samples either side) turn back by
       ``STROKE_END_TURN`` (150 deg) or more and do not meet near it, no other corner lies between those arms,
       and the outline leaves the two side lines (by more than ``STROKE_END_ON_SIDE`` = 0.5 px) 1-5 px apart, on
       either side of the corner. "Near" is where the tip of a wedge of the sides' opening ``theta`` can lie
       beyond its rendering: a render cuts a tip where it narrows below a pixel, at most ``TIP_TRUNCATION /
       sin(theta / 2)`` px (``sqrt(1/2)``, half a pixel diagonal) before it, plus ``STROKE_END_SLACK`` (1 px) for
       where the departures are found; and at least ``STROKE_END_PARALLEL`` (5) end widths, a guard for sharp
       wedges whose measured sides are a few degrees off. Lines crossing farther away, or never (parallel
       sides), belong to a cut end, square or tapered. Then the corner becomes two, at the input points nearest
       those departures. An acute wedge's tip stays one corner: its sides meet just beyond it.

    0. **Scale.** Steps 1-6 run on the outline divided by ``scale`` (default 1), so every length above
       (smoothing, tolerance, flanks, arms, separation, the 3 px of step 6) counts in units of ``scale`` px:
       the detector sees a noisy outline at the coarser scale where its wiggles are as small as the
       staircase of a clean one (:func:`detection_scale` finds that scale;
       :func:`~splinecraft.capture.trace.trace` uses it on noisy bitmaps).

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
        Gaussian sigma (px) applied after resampling, in ``[0, MAX_SMOOTHING]`` = [0, 50] (0 = none).
    tolerance : float, default 0.3
        Largest distance (px) of an arm sample from the arm's line, in ``(0, MAX_TOLERANCE]`` = (0, 50].
    min_turn : float, default 25
        Smallest turn |J| (degrees) of a corner, in [0, 180).
    min_excess : float, default 25
        Smallest excess |E| (degrees) of a corner, in [0, 180).
    flank : (int, int), default (4, 10)
        Nearest and farthest flank offsets (samples) of the excess baseline,
        ``1 <= flank[0] <= flank[1] <= MAX_FLANK`` (500).
    max_arm : int, default 40
        Longest arm (samples), in ``[3, 120]`` (120 is the longest length of the arm ladder). Longer arms (60) find the same corners on the 335 shapes of
        ``bench_corners.py``'s synthetic sets (seeds 0 and 1) and the yardstick (the same true and false
        positives) and cost 1.2-2x the time on outlines with long straight sides.
    separation : int, default 2
        Half width (samples) of the non-maximum suppression, in ``[1, MAX_SEPARATION]`` (500).
    spread : float, default 0.5
        Step 5b, in [0, 1] (0 = off): drop a lone corner whose turn ``|J|`` is less than ``spread`` times the
        turn across 8 samples either side of it, the same way round. On the shapes tester's ellipses (ends of
        3.6-6.7 px radius of curvature) this removes 80 of 131 false corners; on the held-out fonts 13 of 37
        old-style and 10 of 22 CJK false corners, and one true CJK corner (``BENCHMARKS.md``, "Session 13").
        Two corners within 16 samples are not tested (a fillet split in two stays).
    fillets : bool, default False
        Step 7, the fillet test (:mod:`._fillet`, docs/capture.md §11): release every corner whose sides cross
        farther beyond the outline than the pixels of a sharp tip can lie (a rounded corner). Off by default: the
        lsq fit's pixel check (docs/capture.md §12, "Pixel consistency") now holds the released fillets within
        1 px as often as the default holds the corners, but the test still releases some sharp corners (a serif
        corner of ``tests/test_corners.py`` at some rotations) (``BENCHMARKS.md``, "Fillets", "Pixel
        consistency").
    wedge : bool, default False
        Step 7b, the wedge test (:func:`._fillet.wedge_contradictions`): release every corner of a closed crack
        outline whose two sides are digital straight segments of at least 12 px and whose pixels near the
        corner contradict the sharp wedge of those sides (paper pixel centres inside it, ink ones outside) by
        more than 0.2 px beyond the lines' own uncertainty (``BENCHMARKS.md``, "Corner F1 on old-style").
    pixel_corners : bool, default True
        Step 9 (closed crack outlines only; :mod:`splinecraft.capture._pixel_corners`, docs/capture.md §11,
        "Pixel corners"): every turn of the pixel boundary between two axis-aligned straight runs of at least
        3 cracks (neither the tread of a staircase) is a corner, at the point after the turn's vertex, in place
        of a corner found within one point of it. Such a turn is where two straight sides of the shape meet as
        far as the pixels show, also where steps 1-6 see nothing (sides of 3-5 px: the ends of a 3-px bar, a
        5 x 5 block) or put the corner on the midpoint before the vertex. The fit puts the corner's knot point
        on the vertex (docs/capture.md §12). A rendering of a smooth curve has no such turn. Not at a ``scale``
        above 1, where a pixel-sized turn is below the scale the corners are seen at (the noise).
    scale : float, default 1.0
        Step 0, in ``[1, MAX_SCALE]`` = [1, 64]: the unit (px) of every length parameter. Steps 7 and 7b work
        on the outline as given.
    stroke_ends : bool, default True
        Step 6b: a corner at the end of a stroke 1-5 px wide becomes the end's two corners. On random bars
        2-4 px wide at random angles it raises the share of bars traced within 1 px of their rectangle from 62-64 %
        to 74-83 %; it changes no corner of the benchmark sets (``BENCHMARKS.md``, "Session 19").

    Returns
    -------
    numpy.ndarray of intp
        Sorted indices into ``points``; empty when the outline is shorter than 8 px.
    """
    settings = check_tangent_jump_params(smoothing=smoothing, tolerance=tolerance, min_turn=min_turn,
                                         min_excess=min_excess, flank=flank, max_arm=max_arm, separation=separation,
                                         spread=spread, fillets=fillets, wedge=wedge, pixel_corners=pixel_corners,
                                         scale=scale, stroke_ends=stroke_ends)
    P, keep = _prepare(points, closed)
    if len(P) < 3:
        return _EMPTY.copy()
    found = _tangent_jump(P, closed, settings)
    if settings["pixel_corners"] and closed and settings["scale"] == 1.0:  # a pixel is below a coarser scale
        found = with_pixel_corners(found, P)
    return _result(found, keep)


def _tangent_jump(P, closed, settings):
    """Steps 1-8 of :func:`tangent_jump` on the distinct points ``P``: indices into ``P`` (empty when the
    outline is shorter than 8 samples)."""
    n = len(P)
    levels, starts, source = _starts(P) if closed else (None, [(0, 1)], [0])
    runs, done = [], {}
    for k, (start, direction) in enumerate(starts):   # one, or one per symmetry of a symmetric outline
        # a start whose outline is a quarter turn or reflection of one already run gives that run's corners
        found = done.get(source[k])
        if found is None:
            # the outline from ``start`` that way round, P[(start + direction * arange(n)) % n], from two slices
            outline = np.concatenate([P[start:], P[:start]] if direction > 0 else [P[start::-1], P[:start:-1]])
            found = done[k] = _detect(outline, closed, settings)
            if found is None:
                return np.zeros(0, dtype=np.intp)
        runs.append((start + direction * found) % n)
    nearest = runs[0] if len(runs) == 1 else _symmetric_union(P, runs, levels)
    if settings["fillets"] or settings["wedge"]:
        first = starts[0][0]                # steps 7 and 8 from the first start, along the outline's own way
        rolled = np.roll(P, -first, axis=0)
        _, _, arc, perimeter, _ = _resample(rolled, closed)
        found = (np.unique(nearest) - first) % n
        if settings["fillets"]:
            found = release_fillets(rolled, arc, perimeter, closed, np.unique(found))
        if settings["wedge"]:
            found = release_wedge_fillets(rolled, arc, perimeter, closed, np.unique(found))
        nearest = (np.asarray(found, dtype=np.intp) + first) % n
    return np.unique(np.asarray(nearest, dtype=np.intp))


def _relative(P, scale):
    """The points relative to the first one and, step 0, divided by ``scale`` (a division commutes with the frame's
    quarter turns and reflections)."""
    P = P - P[0]
    return P / scale if scale != 1.0 else P


def _detect(P, closed, settings):
    """Steps 1-6 on the outline as given (a closed one from its first point): the corners' indices into
    ``P``, or None when the outline is shorter than 8 samples.

    The work is done relative to the first point (``P - P[0]``): a quarter turn or reflection of the pixel
    frame then maps every intermediate value onto the turned one exactly (the outline's coordinates are
    half-integers, so the shift is exact, and every step treats x and y alike), not just to rounding. Compiled
    (session 30): the resampling (:func:`._jump_kernels.resample`) and the rest but for the few stroke ends of
    step 6b (:func:`._jump_kernels.corners_of`; a smoothing of ``COMPILED_TAPS`` taps or more is numpy's,
    :func:`_smooth`)."""
    P = _relative(P, settings["scale"])
    samples, where, arc, perimeter, step = _resample(P, closed)
    if len(samples) < 8:
        return None
    sigma = settings["smoothing"] / step
    taps = _gaussian(sigma) if sigma > 0 else _NO_TAPS
    if len(taps) >= COMPILED_TAPS:
        samples, taps = _smooth(samples, sigma, closed), _NO_TAPS
    ladder = [length for length in _ARM_LADDER if length <= settings["max_arm"] and 2 * length < len(samples)] \
        or [3]
    chosen, nearest, ends, samples, lines, _ = corners_of(P, arc, perimeter, closed, taps, samples, where, ladder,
                                                       _forward_operators, *_kernel_settings(settings))
    if settings["stroke_ends"] and chosen.size:
        nearest = _split_stroke_ends(P, arc, perimeter, samples, where, lines, chosen, nearest, ends, closed)
    if not closed:
        nearest = nearest[(nearest > 0) & (nearest < len(P) - 1)]
    return np.asarray(nearest, dtype=np.intp)


#: Largest power of two (as ``2**k``) by which the coordinates are scaled to integers for the exact order of
#: :func:`_distance_levels` (crack outlines need ``k = 1``); other coordinates use a rounded order.
_EXACT_SCALE = 16


def _distance_levels(P):
    """An integer per point whose order (and ties) are those of the squared distances from the centroid.

    For coordinates that are multiples of ``2**-k`` (``k <= 16``: pixel and crack outlines) the level is the
    exact integer ``n |q_i|^2 - 2 q_i . sum(q)`` of the scaled coordinates ``q`` (``n`` times the squared
    distance less a constant), so equal distances are equal and the order does not depend on the first point,
    a quarter turn or a reflection (a shift of the frame adds a constant): compiled
    (:func:`._jump_kernels.starts_of`) where these fit in int64, else with Python integers. Other coordinates
    fall back to the squared distances rounded to 1e-12 of the largest."""
    found = starts_of(P, None)
    return found[0] if found is not None else _wide_levels(P)


def _dyadic(P):
    """The coordinates times the smallest ``2**k`` (``k <= _EXACT_SCALE``) that makes them integers below ``2**52``,
    or ``None``."""
    for k in range(_EXACT_SCALE + 1):
        scaled = P * 2.0 ** k
        if np.all(scaled == np.round(scaled)) and np.abs(scaled).max() < 2.0 ** 52:
            return scaled
    return None


def _wide_levels(P):
    """:func:`_distance_levels` where the compiled rule does not apply: exact with Python integers, or rounded."""
    n = len(P)
    scaled = _dyadic(P)
    if scaled is not None:
        x, y = scaled[:, 0], scaled[:, 1]
        q = [(int(a), int(b)) for a, b in zip((x - x.min()).tolist(), (y - y.min()).tolist())]   # exact
        tx, ty = sum(a for a, _ in q), sum(b for _, b in q)
        exact = np.array([a * (n * a - 2 * tx) + b * (n * b - 2 * ty) for a, b in q], dtype=object)
        return np.unique(exact, return_inverse=True)[1].reshape(-1).astype(np.int64)
    squared = np.sum((P - P.mean(axis=0)) ** 2, axis=1)
    top = squared.max()
    if not np.isfinite(top) or top <= 0:
        return np.zeros(n, dtype=np.int64)
    return np.round(squared / top * 1e12).astype(np.int64)


def _starts(P, levels=None):
    """The levels of the closed outline ``P`` (:func:`_distance_levels`, unless given), its canonical starts
    (:func:`_canonical_starts`) and, for each start, the first start (its index) whose outline is the image of
    its own under a quarter turn or a reflection of the frame, exactly (itself where none before it is): steps
    1-6 find the same corners from both, :func:`_detect`. Compiled (:func:`._jump_kernels.starts_of`), the levels
    too where their exact integer rule applies (crack and pixel outlines)."""
    found = starts_of(P, levels)
    if found is None:
        found = starts_of(P, _wide_levels(P))
    return found


def _canonical_starts(levels):
    """Where and which way round the resampling of a closed outline starts: the pairs ``(point, direction)``
    (direction +1 along the outline, -1 against it) whose sequence of ``levels`` (:func:`_distance_levels`)
    read from the point that way is lexicographically the largest -- the farthest point from the centroid,
    ties going to the point and direction whose followers are farther, over the whole outline. The choice is
    a property of the shape: it moves with it under a change of the first point, a quarter turn or a
    reflection of the frame (a reflection reverses the outline's way round, and the choice with it), with no
    rounding to flip it. Several pairs tie only on an outline that a rotation or a reflection maps onto
    itself (one pair per element of its symmetry group); all of them are returned, sorted by point, along
    the outline first. Compiled (:func:`._jump_kernels.starts_of`): each candidate is compared with the largest
    so far up to their first difference."""
    levels = np.ascontiguousarray(levels, dtype=np.int64)
    return starts_of(np.zeros((len(levels), 2)), levels)[1]


def _symmetric_union(P, runs, levels, reach=3.0):
    """The corners of the runs from the tied starts of a symmetric outline, as one set that the symmetry
    maps onto itself.

    Each run is the image of the others under the symmetry, so a corner whose placement depends on where
    the resampling starts (one pixel either way) has a version in each run. Every corner of any run is kept
    unless a corner of another run lies within ``reach`` px of arc of it, no run has both, and that corner's
    comparison key is larger: the outline's ``levels`` read from the point both ways along the outline, the
    larger of the two sequences first (the same for a point and its mirror image), then the sequence along the
    outline's own way round, compared lexicographically up to their first difference. The versions of one corner
    reduce to the one the shape itself prefers, while two corners that one run reports stay two. Compiled
    (:func:`._jump_kernels.union_drops`)."""
    union = np.unique(np.concatenate(runs))
    return union[~union_drops(P, union, runs, levels, reach)]


def check_tangent_jump_params(*, smoothing, tolerance, min_turn, min_excess, flank, max_arm, separation, fillets,
                              wedge, spread=0.5, pixel_corners=True, scale=1.0, stroke_ends=True, label=_plain):
    """tangent-jump's parameters checked against their documented domains and bounds (the one rule, used by
    :func:`tangent_jump` and by :func:`~splinecraft.capture.corners.check_params`); ``label(key)`` names a
    parameter in messages. Returns the settings of :func:`_detect` (``flank`` split into ``near`` and ``far``)."""
    if isinstance(flank, (str, bytes)) or np.ndim(flank) != 1 or len(flank) != 2:
        raise TypeError(f"{label('flank')} must be a pair of integers (near, far), got {flank!r}")
    near = _check_int(flank[0], f"{label('flank')}[0]", low=1, high=MAX_FLANK)
    return {
        "smoothing": _check_real(smoothing, label("smoothing"), low=0.0, high=MAX_SMOOTHING),
        "tolerance": _check_real(tolerance, label("tolerance"), low=0.0, low_open=True, high=MAX_TOLERANCE),
        "min_turn": _check_real(min_turn, label("min_turn"), low=0.0, high=180.0, high_open=True),
        "min_excess": _check_real(min_excess, label("min_excess"), low=0.0, high=180.0, high_open=True),
        "near": near, "far": _check_int(flank[1], f"{label('flank')}[1]", low=near, high=MAX_FLANK),
        "max_arm": _check_int(max_arm, label("max_arm"), low=3, high=max(_ARM_LADDER)),
        "separation": _check_int(separation, label("separation"), low=1, high=MAX_SEPARATION),
        "spread": _check_real(spread, label("spread"), low=0.0, high=1.0),
        "fillets": _check_bool(fillets, label("fillets")),
        "wedge": _check_bool(wedge, label("wedge")),
        "pixel_corners": _check_bool(pixel_corners, label("pixel_corners")),
        "scale": _check_real(scale, label("scale"), low=1.0, high=MAX_SCALE),
        "stroke_ends": _check_bool(stroke_ends, label("stroke_ends")),
    }


#: Step 5b: the wide turn is taken between the arms ``SPREAD_REACH`` samples before and after a corner, and only
#: of a corner with no other corner within ``2 * SPREAD_REACH`` samples.
SPREAD_REACH = 8


def _kernel_settings(settings):
    """The numbers of :func:`._jump_kernels.corners_of` (``settings``, ``flank``) from :func:`_detect`'s
    settings; kept for the next call with the same settings."""
    key = tuple(settings[name] for name in ("min_turn", "min_excess", "spread", "tolerance", "separation",
                                            "stroke_ends", "near", "far"))
    found = _KERNEL_SETTINGS.get(key)
    if found is None:
        min_turn, min_excess, spread, tolerance, separation, stroke_ends, near, far = key
        numbers = np.array([min_turn, min_excess, spread, tolerance, separation, float(stroke_ends), SPREAD_REACH,
                            STROKE_END_REACH, STROKE_END_ARM, STROKE_END_TURN], dtype=np.float64)
        flank = np.concatenate([np.arange(-far, -near + 1), np.arange(near, far + 1)]).astype(np.int64)
        found = numbers, flank
        for table in found:  # read-only (kept or not: one type for the kernel)
            table.flags.writeable = False
        if len(_KERNEL_SETTINGS) < GAUSSIANS_KEPT:
            _KERNEL_SETTINGS[key] = found
    return found


_KERNEL_SETTINGS = {}
