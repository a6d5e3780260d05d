"""Axis-aligned blocks of pixels keep their corners and sides (docs/capture.md §11, "Pixel corners"; §12, "Small
outlines"): the crack outline's points are crack midpoints, so a block's true corners are not contour points;
its pixel corners (turns between two axis-aligned straight runs of at least 3 cracks) are corners at their
vertices, in both fit paths (the small-outline interpolant below 64 contour points, the regression spline
above). Everything is generated here.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

import splinecraft as sc
from splinecraft.capture._pixel_corners import (MIN_RUN, MIN_TREAD, corner_vertices, merge_pixel_corners,
                                                outline_pixel_corners, pixel_corners, pixel_corners_of_outlines)
from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.corners import check_params, tangent_jump
from splinecraft.spline.segment import bezier_signed_area


def block(height, width, top=5, left=5, margin=5, hole=None):
    """A mask with one ``height`` x ``width`` block of ink at (``top``, ``left``), and ``hole`` (top, left, height,
    width, relative to the block) cut out of it."""
    mask = np.zeros((top + height + margin, left + width + margin), bool)
    mask[top:top + height, left:left + width] = True
    if hole is not None:
        t, l, h, w = hole
        mask[top + t:top + t + h, left + l:left + l + w] = False
    return mask


def rectangle_vertices(top, left, height, width):
    return np.array([(left, top), (left + width, top), (left + width, top + height), (left, top + height)], float)


def dense(bezier, step=0.05):
    out = []
    for piece in np.asarray(bezier, float):
        length = np.hypot(*np.diff(piece, axis=0).T).sum()
        t = np.linspace(0.0, 1.0, max(4, int(np.ceil(length / step)) + 1))[:, None]
        out.append((1 - t) ** 3 * piece[0] + 3 * t * (1 - t) ** 2 * piece[1] + 3 * t**2 * (1 - t) * piece[2]
                   + t**3 * piece[3])
    return np.concatenate(out)


def rectangle_distance(samples, vertices):
    """Distance of every sample from the boundary of the axis-aligned rectangle ``vertices``."""
    (x0, y0), (x1, y1) = vertices.min(axis=0), vertices.max(axis=0)
    x, y = samples[:, 0], samples[:, 1]
    outside = np.hypot(np.maximum(np.maximum(x0 - x, x - x1), 0.0), np.maximum(np.maximum(y0 - y, y - y1), 0.0))
    inside = np.minimum(np.minimum(x - x0, x1 - x), np.minimum(y - y0, y1 - y))
    return np.where(outside > 0, outside, np.abs(inside))


def check_rectangle(bezier, vertices, corner_tolerance=0.15, side_tolerance=0.15, area_share=0.02):
    """The closed Bézier chain ``bezier`` traces the rectangle ``vertices``: a join within ``corner_tolerance`` of
    every corner, every point within ``side_tolerance`` of the rectangle's sides and the four corners within that
    of the curve, its area within ``area_share`` of the rectangle's."""
    bezier = np.asarray(bezier, float)
    joins = bezier[:, 0]
    misses = [float(np.hypot(*(joins - v).T).min()) for v in vertices]
    assert max(misses) <= corner_tolerance, (np.round(misses, 3), np.round(joins, 3).tolist())
    samples = dense(bezier)
    assert rectangle_distance(samples, vertices).max() <= side_tolerance
    area = abs(np.prod(vertices.max(axis=0) - vertices.min(axis=0)))
    assert abs(abs(bezier_signed_area(bezier)) / area - 1.0) <= area_share


# ------------------------------------------------------------------------------------------- traced blocks

@pytest.mark.parametrize("height,width", [(8, 10), (5, 5), (4, 4), (6, 9), (12, 20), (3, 7), (3, 3), (3, 30),
                                          (4, 30), (20, 20), (30, 30), (1, 5), (2, 6), (1, 12), (2, 12), (12, 2),
                                          (1, 40), (2, 40), (40, 2), (2, 70), (70, 1), (1, 1), (2, 2), (1, 2), (2, 1)])
def test_a_block_traces_to_its_rectangle(height, width):
    """The blocks of the pinwheel report (8 x 10 came back with every corner half a pixel along a side, an area of
    70 for 80; 5 x 5 as a turned square) and others across both fit paths and the 20-point limit of corner
    detection: four joins at the pixel corners, the sides on the pixel edges. Strokes 1-2 px wide too (a 2 x 40
    bar came back as a wavy lens of 8 segments): their ends are pieces of one or two cracks between two pixel
    corners."""
    result = sc.trace(block(height, width))
    assert len(result.splines) == 1 and result.stats["converged"]
    bezier = result.splines[0].bezier()
    # exact up to the weight of the regression spline's corner pins (about 1e-6 px)
    check_rectangle(bezier, rectangle_vertices(5, 5, height, width), corner_tolerance=1e-5, side_tolerance=0.01,
                    area_share=1e-4)
    assert len(bezier) == 4


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 30), st.integers(1, 30), st.integers(0, 12), st.integers(0, 12), st.integers(1, 9),
       st.booleans(), st.booleans())
def test_random_blocks_keep_their_corners_and_area(height, width, top, left, margin, with_hole, upright):
    """Blocks of 1-30 by 1-30 px anywhere in the image, either way up (and a block with a rectangular hole, whose
    outline turns the other way round): every corner within 0.15 px of a join of the fit, the sides within 0.15 px
    of the pixel edges, the area within 2 %."""
    if upright:
        height, width = width, height
    hole = None
    if with_hole and height >= 9 and width >= 9:
        hole = (3, 3, height - 6, width - 6)
    mask = block(height, width, top, left, margin, hole)
    result = sc.trace(mask)
    assert result.stats["converged"]
    outer = rectangle_vertices(top, left, height, width)
    expected = [outer] if hole is None else [outer, rectangle_vertices(top + 3, left + 3, height - 6, width - 6)]
    assert len(result.splines) == len(expected)
    for vertices in expected:  # the spline whose joins span about that rectangle
        spline = min(result.splines, key=lambda s: np.abs(np.concatenate([
            s.bezier()[:, 0].min(axis=0) - vertices.min(axis=0), s.bezier()[:, 0].max(axis=0) - vertices.max(axis=0)])).sum())
        check_rectangle(spline.bezier(), vertices)


def test_an_l_shaped_outline_has_its_six_pixel_corners():
    """Convex and concave pixel corners alike (an L of two bars 5 px wide): six joins at the vertices."""
    mask = np.zeros((30, 30), bool)
    mask[5:20, 5:10] = True
    mask[15:20, 5:20] = True
    result = sc.trace(mask)
    vertices = np.array([(5, 5), (10, 5), (10, 15), (20, 15), (20, 20), (5, 20)], float)
    joins = result.splines[0].bezier()[:, 0]
    assert max(np.hypot(*(joins - v).T).min() for v in vertices) <= 1e-5
    assert abs(bezier_signed_area(result.splines[0].bezier())) == pytest.approx(mask.sum(), rel=1e-5)


@pytest.mark.parametrize("height,width", [(1, 1), (1, 2), (2, 1), (2, 2)])
def test_specks_and_dominos_are_blocks_with_four_pixel_corners(height, width):
    """Blocks whose every side is a run of 1 or 2 cracks (specks, dominos) are blocks too: their four vertices are
    pixel corners (a tester's 2 x 2 dot beside a larger outline came back as a lopsided blob of 3.05 px² with its
    centroid 0.15 px off, a 1 x 1 dot spanned x 4.0-4.8), and they trace to their rectangle, alone and beside a
    larger outline (``min_speck_area=0`` keeps them)."""
    mask = block(height, width)
    (boundary,) = trace_boundaries(mask)
    index, vertices = outline_pixel_corners(np.asarray(boundary.outline, float))
    expected = rectangle_vertices(5, 5, height, width)
    assert index.size == 4
    assert sorted(map(tuple, vertices.tolist())) == sorted(map(tuple, expected.tolist()))
    beside = np.zeros((40, 40), bool)
    beside[:mask.shape[0], :mask.shape[1]] = mask
    beside[15:35, 15:35] = True
    for image in (mask, beside):
        result = sc.trace(image, min_speck_area=0)
        assert result.stats["converged"]
        spline = min(result.splines, key=lambda s: np.abs(s.bezier()[:, 0].mean(axis=0) - expected.mean(axis=0)).sum())
        check_rectangle(spline.bezier(), expected, corner_tolerance=1e-5, side_tolerance=0.01, area_share=1e-4)


@pytest.mark.parametrize("height,width", [(1, 3), (2, 3), (1, 12), (2, 12), (3, 1), (12, 2)])
def test_the_ends_of_strokes_one_or_two_pixels_wide_are_pixel_corners(height, width):
    """A run of 1 or 2 cracks between two runs of at least 3 that go the opposite ways (a U-turn: the end of a stroke
    1-2 px wide) has a pixel corner at both of its vertices; a staircase never turns back."""
    (boundary,) = trace_boundaries(block(height, width))
    index, vertex = outline_pixel_corners(np.asarray(boundary.outline, float))
    expected = rectangle_vertices(5, 5, height, width)
    assert index.size == 4
    assert sorted(map(tuple, vertex.tolist())) == sorted(map(tuple, expected.tolist()))


def test_a_stroke_end_beside_a_staircase_is_not_a_pixel_corner():
    """The U-turn rule keeps the staircase rule of its long runs: a 2-px stroke whose sides are staircases (a slope
    of 1/3) has no pixel corner at its ends."""
    mask = np.zeros((20, 40), bool)
    for column in range(5, 35):
        row = 5 + (column - 5) // 3
        mask[row:row + 2, column] = True
    (boundary,) = trace_boundaries(mask)
    points = np.asarray(boundary.outline, float)
    index, vertex = outline_pixel_corners(points)
    ends = np.array([(5.0, 5.0), (5.0, 7.0), (35.0, 14.0), (35.0, 16.0)])
    nearest = [np.hypot(*(vertex - end).T).min() if index.size else np.inf for end in ends]
    assert min(nearest) >= 0.5, nearest


def test_pixel_corners_can_be_turned_off():
    """``corner_params={"pixel_corners": False}`` traces as before: the detector's corners only (none on a 5 x 5
    block), so its outline is one periodic curve."""
    check_params("tangent-jump", {"pixel_corners": False})
    with pytest.raises(TypeError):
        check_params("tangent-jump", {"pixel_corners": "yes"})
    mask = block(5, 5)
    assert sc.trace(mask).corners[0].size == 4
    assert sc.trace(mask, corner_params={"pixel_corners": False}).corners[0].size == 0


# ------------------------------------------------------------------------------------------- the rule itself

def outline_of(mask):
    return [np.asarray(b.outline, float) for b in trace_boundaries(mask)]


def test_pixel_corners_of_a_block_are_its_four_corners():
    (points,) = outline_of(block(3, 7))
    index, vertices = outline_pixel_corners(points)
    assert sorted(map(tuple, vertices.tolist())) == sorted(map(tuple, rectangle_vertices(5, 5, 3, 7).tolist()))
    # the point after each vertex: half a pixel from it, and the point before as well
    n = len(points)
    assert np.allclose(np.hypot(*(points[index] - vertices).T), 0.5)
    assert np.allclose(np.hypot(*(points[(index - 1) % n] - vertices).T), 0.5)
    # a corner at either point beside a vertex names it; a corner elsewhere (the middle of a long side) names none
    middle = int(np.argmax(np.min(np.abs(np.arange(n)[:, None] - index[None, :]) % n, axis=1)
                           * np.min((index[None, :] - np.arange(n)[:, None]) % n, axis=1)))
    assert min(np.abs(middle - index).min(), n - np.abs(middle - index).max()) >= 2
    got = corner_vertices(points, [n], np.zeros(3, int), np.array([index[0], (index[1] - 1) % n, middle]))
    np.testing.assert_array_equal(got[:2], vertices[:2])
    assert np.isnan(got[2]).all()


@pytest.mark.parametrize("slope", [1 / 12, 1 / 5, 1 / 3, 2 / 5, 1.0])
def test_a_staircase_has_no_pixel_corners(slope):
    """A thick bar turned off the axes: its sides are staircases of runs a few cracks long, whose turns are not
    pixel corners (the runs continue beyond each step as treads)."""
    rows, cols = np.mgrid[:80, :80]
    # a band between two parallel lines of the given slope, cut by two lines across it far apart
    along = (cols + slope * rows) / np.hypot(1.0, slope)
    across = (rows - slope * cols) / np.hypot(1.0, slope)
    mask = (np.abs(across - across[40, 40] - 0.3) < 6.0) & (np.abs(along - along[40, 40]) < 30.0)
    for points in outline_of(mask):
        index, vertices = outline_pixel_corners(points)
        # only the band's four ends can be corners at all; none of them lies inside the straight sides
        middle = np.abs((vertices[:, 0] + slope * vertices[:, 1]) / np.hypot(1.0, slope) - along[40, 40]) < 24.0
        assert not middle.any(), vertices[middle]


@settings(max_examples=60, deadline=None)
@given(st.floats(3.15, 20.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_a_disc_has_no_pixel_corners(radius, dx, dy):
    """A rendered disc of radius above 3.1 px never turns between two straight runs of 3 cracks (a scan of
    radii 3.05-8 in steps of 0.01-0.05 px over 65 x 65 offsets found such turns up to 3.09 px, and at 3.1 px
    exactly where pixel centres lie on the circle). Smaller ones can:
    a 3 x 3, 4 x 4 or 5 x 5 block (with a nub at radius 3) is a disc of radius 1.4-2, 2.1-2.5 or 2.8-3.05 px as
    well, and there the block reading wins."""
    rows, cols = np.mgrid[:48, :48]
    mask = (cols + 0.5 - 24 - dx) ** 2 + (rows + 0.5 - 24 - dy) ** 2 <= radius * radius
    for points in outline_of(mask):
        assert outline_pixel_corners(points)[0].size == 0


@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, 0.999), st.floats(0.0, 0.999), st.floats(24.0, 60.0), st.integers(12, 30))
@example(0.3125, 0.3125, 24.0, 12)  # the treads beside the bottom flat: 2, 3 (the first a crack short)
@example(0.0, 0.40625, 24.0, 12)  # ... 2, 2, 2
def test_a_flat_side_that_bends_away_keeps_its_pixel_corner(dx, dy, radius, flat):
    """A "D": a vertical side, and at its two ends flat sides ``flat`` px long that run on into a half circle.
    Beyond each flat run the outline steps down by one crack and goes on the same way, as a staircase's tread
    would; yet the flat run is longer by more than one crack than the whole treads beyond it, which no digital
    straight segment allows, so it is a side of its own and the two turns of the vertical side are pixel corners,
    within half a pixel (per axis) of the true corners. (Before, any run that went on as a tread was taken for
    an off-axis side: freemono's q at 1200 px lost its corner and was traced 1.16 px off.)"""
    left, top = 8.0 + dx, 8.0 + dy
    rows, cols = np.mgrid[: int(2 * radius) + 20, : int(flat + radius) + 20]
    x, y = cols + 0.5, rows + 0.5
    inside = (x >= left) & (y >= top) & (y <= top + 2 * radius)
    mask = inside & ((x <= left + flat) | ((x - left - flat) ** 2 + (y - top - radius) ** 2 <= radius ** 2))
    (points,) = outline_of(mask)
    _, vertices = outline_pixel_corners(points)
    true_corners = np.array([[left, top], [left, top + 2 * radius]])
    assert len(vertices) == 2, vertices
    gap = np.abs(vertices[:, None, :] - true_corners[None, :, :]).max(axis=2).min(axis=1)
    assert (gap <= 0.5 + 1e-9).all(), (vertices, true_corners)


def test_only_crack_outlines_have_pixel_corners():
    """Pixel chains, shifted or scaled outlines are not crack outlines: no pixel corners."""
    mask = block(6, 8)
    (points,) = outline_of(mask)
    (boundary,) = trace_boundaries(mask)
    assert outline_pixel_corners(points)[0].size == 4
    for other in (np.asarray(boundary.pixels, float), points + 0.25, points * 2.0):
        assert outline_pixel_corners(other)[0].size == 0


def random_blocks(seed, size, count, largest):
    """A ``size`` x ``size`` mask with ``count`` random blocks of 1 to ``largest`` px sides (overlaps merge)."""
    rng = np.random.default_rng(seed)
    mask = np.zeros((size, size), bool)
    for _ in range(count):
        top, left = rng.integers(0, size - 6, 2)
        height, width = rng.integers(1, largest + 1, 2)
        mask[top:top + height, left:left + width] = True
    return mask


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000))
def test_pixel_corners_of_a_batch_are_those_of_each_outline(seed):
    """The vectorized batch gives every outline the pixel corners it has alone; every pixel corner is a turn
    between two runs of at least MIN_RUN cracks, or a vertex of a shorter run between two such runs that go the
    opposite ways (the end of a stroke 1-2 px wide), or a vertex of an outline of four runs (a block), as a plain
    loop over the runs reads them."""
    outlines = outline_of(random_blocks(seed, size=40, count=6, largest=7))
    at, vertices = pixel_corners(np.concatenate(outlines), [len(o) for o in outlines])
    start = 0
    for points in outlines:
        index, own = outline_pixel_corners(points)
        np.testing.assert_array_equal(np.flatnonzero(at[start:start + len(points)]), index)
        np.testing.assert_array_equal(vertices[start + index], own)
        runs = crack_runs(points)
        for i in index:
            before, after = run_at(runs, i - 1), run_at(runs, i)
            assert after == (before + 1) % len(runs)

            def long(k):
                return runs[k % len(runs)][1] >= MIN_RUN

            def u_turn(k):  # run k is short, between two long runs the opposite ways
                return not long(k) and long(k - 1) and long(k + 1) and \
                    (runs[(k - 1) % len(runs)][2] + 2) % 4 == runs[(k + 1) % len(runs)][2]

            block_outline = len(runs) == 4  # a block of any size: its four vertices
            assert (long(before) and long(after)) or u_turn(before) or u_turn(after) or block_outline
        start += len(points)


UNIT_STEPS = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])  # direction codes 0..3 -> unit step
REACH = 7  # the rules look at most this many runs either way from a run


def numpy_pixel_corners(points, lengths):
    """:func:`~splinecraft.capture._pixel_corners.pixel_corners` as the vectorized numpy formulation that the
    kernel replaced (session 29) states it, verbatim but for the names of its constants."""
    points = np.asarray(points, float).reshape(-1, 2)
    lengths = np.asarray(lengths, dtype=np.int64).reshape(-1)
    total = points.shape[0]
    at = np.zeros(total, bool)
    vertex = np.full((total, 2), np.nan)
    if total == 0:
        return at, vertex
    offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    outline = np.repeat(np.arange(lengths.shape[0]), lengths)
    local = np.arange(total) - offsets[outline]
    n = lengths[outline]
    prev = offsets[outline] + (local - 1) % n
    nxt = offsets[outline] + (local + 1) % n
    # a crack midpoint has one integer and one half-integer coordinate; its direction of travel points from
    # the point before it towards the point after it along its own axis
    frac = np.abs(points - np.floor(points))
    horizontal = (frac[:, 1] == 0.0) & (frac[:, 0] == 0.5)
    vertical = (frac[:, 0] == 0.0) & (frac[:, 1] == 0.5)
    travel = points.take(nxt, axis=0) - points.take(prev, axis=0)  # (take: numpy 2.4's row indexing is 5-15x slower)
    code = np.where(horizontal, np.where(travel[:, 0] > 0, 0, 2), np.where(travel[:, 1] > 0, 1, 3))
    unit = UNIT_STEPS.take(code, axis=0)
    # a closed chain of unit cracks: each crack starts where the one before it ends
    chained = (horizontal | vertical) & np.all((points + 0.5 * unit).take(prev, axis=0) == points - 0.5 * unit, axis=1)
    good = np.bincount(outline[~chained], minlength=lengths.shape[0]) == 0
    good &= lengths >= 4
    if not good.any():
        return at, vertex
    # runs of cracks of one direction: run starts, and per outline its runs in order (cyclically)
    start = good[outline] & (code != code[prev])
    first = np.flatnonzero(start)  # global index of every run's first crack, sorted (by outline, then index)
    run_outline = outline[first]
    count = np.bincount(run_outline, minlength=lengths.shape[0])
    run_offset = np.concatenate([[0], np.cumsum(count)[:-1]])
    j = np.arange(first.shape[0]) - run_offset[run_outline]  # a run's rank in its outline
    k = count[run_outline]
    # the runs REACH places before each run to REACH places after it, within its outline (column REACH + m: the
    # run m places after, negative m before), and their lengths and directions
    around = run_offset[run_outline][:, None] + (j[:, None] + np.arange(-REACH, REACH + 1)[None, :]) % k[:, None]
    following = first[around[:, REACH + 1]]
    length = (following - first) % lengths[run_outline]
    length = np.where(length == 0, lengths[run_outline], length)
    direction = code[first]
    lengths_at, directions_at = length[around], direction[around]

    def length_of(m):
        return lengths_at[:, REACH + m]

    def direction_of(m):
        return directions_at[:, REACH + m]

    def tread(m, way):  # run m continues at its far end (way +1: after it, -1: before) as a staircase's tread
        continues = (length_of(m + way) == 1) & (direction_of(m + 2 * way) == direction_of(m))
        # ... unless it is longer by more than one crack than a whole tread of that staircase (``beyond`` or the
        # one after it, with a step at both ends) of MIN_TREAD cracks or more: the runs of a digital straight
        # segment differ by at most one and its end runs can only be shorter, so the run is then no tread of an
        # off-axis side but a straight side of its own, from which the outline bends away gently (a flat side
        # running into a curve; a round end of a few pixels turns through treads of single cracks)
        whole = (length_of(m + 3 * way) == 1) & (direction_of(m + 4 * way) == direction_of(m))
        # the longer of the first two whole treads (the first can be a crack or two short with the phase of
        # the pixels: 2, 3 beside a bowl of radius 24)
        second = whole & (length_of(m + 5 * way) == 1) & (direction_of(m + 6 * way) == direction_of(m))
        tread_length = np.maximum(length_of(m + 2 * way), np.where(second, length_of(m + 4 * way), 0))
        flat = whole & (tread_length >= MIN_TREAD) & (length_of(m) > tread_length + 1)
        return continues & ~flat

    # the vertex before run j is a pixel corner: runs j - 1 and j long enough, neither a staircase's tread
    before_tread = tread(-1, -1)  # (used twice)
    corner = (length_of(-1) >= MIN_RUN) & (length >= MIN_RUN)
    corner &= ~before_tread & ~tread(0, 1)
    # the end of a stroke one or two pixels wide: a run shorter than MIN_RUN between two long runs the opposite
    # ways round (a U-turn), each of them not a staircase's tread at its far end; both of its vertices
    end = (length < MIN_RUN) & (length_of(-1) >= MIN_RUN) & (length_of(1) >= MIN_RUN)
    end &= direction_of(-1) == (direction_of(1) + 2) % 4
    end &= ~before_tread & ~tread(1, 1)
    end &= k >= 4
    corner |= end
    corner[around[:, REACH + 1][end]] = True
    # a block (four runs: the crack outline is a rectangle) of any size: its four vertices. Below 3 x 3 pixels
    # the runs are too short for the rules above, yet no other shape renders as a rectangle that small
    corner |= k == 4
    corner &= k >= 4
    index = first[corner]
    at[index] = True
    vertex[index] = points.take(index, axis=0) - 0.5 * unit.take(index, axis=0)
    return at, vertex


def random_crack_outlines(seed, count):
    """Closed crack outlines of random bitmaps of ``count`` kinds (specks, blocks and strokes of every width, noisy
    blobs, staircases), each read from a random point, some of them reversed or broken (a point moved off its
    crack, a crack left out, a point not on a crack: no pixel corners), stacked with outlines of 0-3 points."""
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(seed)
    outlines = []
    for _ in range(count):
        size = int(rng.integers(3, 40))
        kind = rng.integers(0, 3)
        if kind == 0:
            mask = random_blocks(int(rng.integers(0, 10 ** 6)), size=size + 6, count=int(rng.integers(1, 6)),
                                 largest=int(rng.integers(1, 9)))
        elif kind == 1:
            mask = gaussian_filter(rng.random((size, size)), rng.uniform(0.0, 3.0)) > rng.uniform(0.3, 0.7)
        else:  # a staircase or a thin slanted stroke
            y, x = np.mgrid[0:size, 0:size]
            mask = np.abs(y - rng.uniform(-1, 1) * x - size / 4) <= rng.uniform(0.5, size / 3)
        for points in outline_of(mask):
            points = np.roll(points, -int(rng.integers(0, len(points))), axis=0)
            if rng.random() < 0.2:
                points = points[::-1]
            change = rng.random()
            if change < 0.05:
                points = np.delete(points, int(rng.integers(0, len(points))), axis=0)
            elif change < 0.1:
                points = points.copy()
                points[int(rng.integers(0, len(points)))] += rng.choice([0.25, 1.0, 0.5])
            outlines.append(np.ascontiguousarray(points, float))
    for short in range(4):
        outlines.insert(int(rng.integers(0, len(outlines) + 1)), np.array([[0.5, 0.0], [1.0, 0.5], [0.5, 1.0]])[:short])
    return outlines


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10 ** 6), st.integers(1, 8))
def test_pixel_corners_are_those_of_the_numpy_formulation(seed, count):
    """The compiled pass gives the pixel corners and vertices of the vectorized numpy formulation it replaced, bit
    for bit, on random crack outlines stacked (blocks, strokes, blobs, staircases; reversed, rotated, broken),
    through every entry point: :func:`pixel_corners`, :func:`outline_pixel_corners` and
    :func:`pixel_corners_of_outlines`."""
    outlines = random_crack_outlines(seed, count)
    points, lengths = np.concatenate(outlines), [len(o) for o in outlines]
    expected_at, expected_vertex = numpy_pixel_corners(points, lengths)
    at, vertex = pixel_corners(points, lengths)
    np.testing.assert_array_equal(at, expected_at)
    np.testing.assert_array_equal(vertex, expected_vertex)
    starts = np.cumsum(lengths) - lengths
    for own, found, start in zip(outlines, pixel_corners_of_outlines(outlines), starts):
        index = np.flatnonzero(expected_at[start:start + len(own)])
        np.testing.assert_array_equal(found.index, index)
        np.testing.assert_array_equal(found.vertex, expected_vertex[start + index])
        alone = outline_pixel_corners(own)
        np.testing.assert_array_equal(alone.index, index)
        np.testing.assert_array_equal(alone.vertex, expected_vertex[start + index])


def test_pixel_corners_refuse_lengths_that_do_not_add_up():
    """The lengths must cover the points exactly (the compiled pass reads the outlines by them)."""
    (points,) = outline_of(block(3, 4))
    for lengths in ([len(points) - 1], [len(points) + 1], [len(points) + 2, -2]):
        with pytest.raises(ValueError, match="lengths"):
            pixel_corners(points, lengths)


def crack_runs(points):
    """The runs of a closed crack outline, by a plain loop: ``(first point, length, direction code)`` in order, the
    direction codes of :mod:`splinecraft.capture._pixel_corners` (0 +x, 1 +y, 2 -x, 3 -y)."""
    n = len(points)
    codes = []
    for i in range(n):
        step = points[(i + 1) % n] - points[i - 1]
        horizontal = points[i][1] == np.floor(points[i][1])
        codes.append((0 if step[0] > 0 else 2) if horizontal else (1 if step[1] > 0 else 3))
    first = next(i for i in range(n) if codes[i] != codes[i - 1])
    runs = []
    for k in range(n):
        i = (first + k) % n
        if k == 0 or codes[i] != codes[i - 1]:
            runs.append([i, 0, codes[i]])
        runs[-1][1] += 1
    return runs


def run_at(runs, point):
    """The index of the run holding ``point``."""
    for k, (first, length, _) in enumerate(runs):
        if (point - first) % sum(r[1] for r in runs) < length:
            return k
    raise AssertionError(point)


def test_detected_corners_beside_a_pixel_corner_give_way_to_it():
    """tangent-jump's step 9: a detected corner within one point of a pixel corner is replaced by it, the others
    stay; off, the detector's own corners."""
    (points,) = outline_of(block(4, 12))
    index, _ = outline_pixel_corners(points)
    n = len(points)
    far = (index[0] + 6) % n  # the middle of a long side
    assert np.min(np.minimum(np.abs(far - index), n - np.abs(far - index))) >= 2
    merged = merge_pixel_corners(np.array([(index[0] - 1) % n, (index[1] + 1) % n, far]), index, n)
    np.testing.assert_array_equal(merged, np.unique(np.append(index, far)))
    np.testing.assert_array_equal(tangent_jump(points), np.sort(index))
    assert tangent_jump(points, pixel_corners=False).size <= 4


@pytest.mark.parametrize("chunk", [1, 16, 40, 1 << 18])
def test_pixel_corners_of_outlines_in_chunks_are_those_of_each_outline(chunk, monkeypatch):
    """trace's call: chunks of whole outlines (bounded temporaries on noise images of millions of points) give
    every outline its own pixel corners and vertices, whatever the chunk size."""
    import splinecraft.capture._pixel_corners as module

    outlines = outline_of(random_blocks(7, size=60, count=12, largest=8))
    monkeypatch.setattr(module, "CHUNK_POINTS", chunk)
    found = module.pixel_corners_of_outlines(outlines)
    assert len(found) == len(outlines) and sum(len(f.index) for f in found) > 0
    for points, (index, vertex) in zip(outlines, found):
        own = outline_pixel_corners(points)
        np.testing.assert_array_equal(index, own.index)
        np.testing.assert_array_equal(vertex, own.vertex)
    assert module.pixel_corners_of_outlines([]) == []


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(0, 1000))
def test_pixel_corners_found_once_give_the_vertices_found_again(seed, turn):
    """The pixel corners the corner stage finds (``pixel_corners_of_outlines``) and hands to the fit name the
    same vertex beside every point as :func:`corner_vertices` finding them itself, also on a contour rotated to
    start elsewhere (``RotatedContour``, as the fit sees it)."""
    from splinecraft.capture.fitting.lsq_setup import RotatedContour

    mask = np.pad(random_blocks(seed, size=40, count=6, largest=7), ((0, 0), (0, 20)))
    mask[5:12, 45:53] = True  # a block apart from the random ones: an outline with four pixel corners
    outlines = outline_of(mask)
    lengths = [len(o) for o in outlines]
    found = pixel_corners_of_outlines(outlines)
    outline = np.repeat(np.arange(len(outlines)), lengths)
    every = np.concatenate([np.arange(n) for n in lengths])
    stacked = np.concatenate(outlines)
    again = corner_vertices(stacked, lengths, outline, every)
    np.testing.assert_array_equal(corner_vertices(stacked, lengths, outline, every, found), again)
    assert np.isfinite(again[:, 0]).sum() >= 8  # both points beside each of the block's corners
    for points, own in zip(outlines, found):
        n = len(points)
        corners = np.unique(np.array([turn % n, (turn * 7 + 3) % n]))
        handed = RotatedContour(points, corners, own)
        alone = outline_pixel_corners(handed.points)
        np.testing.assert_array_equal(handed.pixel_corners.index, alone.index)
        np.testing.assert_array_equal(handed.pixel_corners.vertex, alone.vertex)
        assert RotatedContour(points, corners).pixel_corners is None
    with pytest.raises(ValueError, match="pixel corners of"):
        corner_vertices(stacked, lengths, outline, every, found[:-1])


def _blocks_and_wedge():
    """Blocks of pixels (small outlines, some with pixel corners), a large rectangle (pixel corners of a regression
    spline) and a clean acute wedge (an extrapolated tip): both fit paths measure corner tips."""
    mask = random_blocks(3, size=120, count=10, largest=7)
    mask[60:100, 10:50] = True
    rows, cols = np.mgrid[:120, :120] + 0.5
    mask |= (cols > 60) & (cols < 115) & (np.abs(rows - 80.0) < 0.35 * (cols - 60))
    return mask


def test_trace_finds_the_pixel_corners_once_and_the_fit_uses_them(monkeypatch):
    """``trace`` finds the pixel corners once, in its corner stage (one chunk here), and the fit's corner tips
    (``tips.tip_estimates``, the small-outline path's pre-test) take those: every lookup gets them handed down,
    and they name the vertices a lookup of its own finds. A direct call of the fit finds them itself."""
    import splinecraft.capture._pixel_corners as module
    from splinecraft.capture.fitting import small, tips

    original_corners, original_vertices = module._corners, module.corner_vertices  # (every lookup's compiled pass)
    found_calls, lookups = [], []

    def counting(points, lengths):
        found_calls.append(len(points))
        return original_corners(points, lengths)

    def checking(points, lengths, outline, corners, found=None):
        got = original_vertices(points, lengths, outline, corners, found)
        lookups.append((found is not None, np.isfinite(got[:, 0]).sum()))
        np.testing.assert_array_equal(got, original_vertices(points, lengths, outline, corners))
        return got

    monkeypatch.setattr(module, "_corners", counting)
    monkeypatch.setattr(tips, "corner_vertices", checking)
    monkeypatch.setattr(small, "corner_vertices", checking)
    result = sc.trace(_blocks_and_wedge(), time_budget=None)
    assert result.stats["extrapolated_tips"] is True
    small_count = sum(entry["small_outline"] for entry in result.stats["per_boundary"])
    assert small_count >= 3 and small_count < len(result.points)
    total = sum(len(points) for points in result.points)
    # the corner stage's one call, then only the checks' own lookups (which pass no pixel corners)
    assert found_calls[0] == total
    assert len(found_calls) == 1 + sum(1 for handed, _ in lookups if handed)
    assert lookups and all(handed for handed, _ in lookups)
    assert sum(hits for _, hits in lookups) >= 8  # the rectangle's four corners, the blocks' corners
    found_calls.clear(), lookups.clear()
    from splinecraft.capture.fitting import fit_outline

    points, corners = result.points[0], result.corners[0]
    fit_outline(points, corners, small_outline=0)
    assert lookups and not any(handed for handed, _ in lookups) and len(found_calls) >= 1
