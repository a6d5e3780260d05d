"""Tests of the chain-code boundary tracer (capture/contour.py).

Independent references: a plain Moore-neighbour tracer written here (pixel chains), skimage's
marching squares (``find_contours``) for the crack outline, scipy.ndimage.label for components and
pixel counts for areas (exact).
"""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays
from scipy import ndimage
from skimage.measure import find_contours

from splinecraft.capture.contour import FREEMAN_STEPS, Boundary, chain_to_pixels, trace_boundaries

EIGHT = np.ones((3, 3), bool)
FOUR = ndimage.generate_binary_structure(2, 1)


# ------------------------------------------------------------------------------------------ helpers
def moore_trace(component_mask):
    """Reference Moore-neighbour tracing (8-connected outer boundary, transition stopping criterion).

    Returns the list of pixel centres (x, y) starting at the first ink pixel in raster order and going
    clockwise on screen (ink on the right).
    """
    padded = np.pad(component_mask, 1)
    clockwise = [(0, -1), (-1, -1), (-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1)]  # W NW N NE E SE S SW
    rows, cols = np.nonzero(padded)
    start = (int(rows[0]), int(cols[0]))
    chain, current, back, first_move = [start], start, (start[0], start[1] - 1), None
    while True:
        k = clockwise.index((back[0] - current[0], back[1] - current[1]))
        for s in range(1, 9):
            dr, dc = clockwise[(k + s) % 8]
            candidate = (current[0] + dr, current[1] + dc)
            if padded[candidate]:
                pr, pc = clockwise[(k + s - 1) % 8]
                back = (current[0] + pr, current[1] + pc)
                break
        else:
            break  # isolated pixel
        move = (current, candidate)
        if first_move is None:
            first_move = move
        elif move == first_move:
            chain.pop()
            break
        chain.append(candidate)
        current = candidate
    return [(c - 1 + 0.5, r - 1 + 0.5) for r, c in chain]


def shoelace(points):
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def contours_of(mask, connectivity):
    """find_contours at level 0.5 on the zero-padded mask, in the pixel frame, last point dropped."""
    padded = np.pad(mask.astype(float), 1)
    contours = find_contours(padded, 0.5, fully_connected="high" if connectivity == 8 else "low")
    return [np.column_stack([c[:-1, 1] - 0.5, c[:-1, 0] - 0.5]) for c in contours]


def polyline_distance(points, polygon):
    """Distance from each point to the closed polyline ``polygon`` (exact, vectorized)."""
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    ab = b - a
    ap = points[:, None, :] - a[None, :, :]
    denom = np.maximum((ab * ab).sum(-1), 1e-300)
    t = np.clip((ap * ab[None]).sum(-1) / denom, 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    return np.sqrt(((points[:, None, :] - closest) ** 2).sum(-1)).min(axis=1)


def densify(polygon, step=0.02):
    if len(polygon) == 1:
        return polygon
    a, b = polygon, np.roll(polygon, -1, axis=0)
    pieces = []
    for p, q in zip(a, b):
        k = max(1, int(np.ceil(np.linalg.norm(q - p) / step)))
        pieces.append(p + np.linspace(0, 1, k, endpoint=False)[:, None] * (q - p))
    return np.vstack(pieces)


def hausdorff(p, q):
    return max(polyline_distance(densify(p), q).max(), polyline_distance(densify(q), p).max())


def boundary_pixel_set(mask, connectivity):
    """Ink pixels with a background neighbour (4-neighbour for 8-connected ink, 8-neighbour for 4)."""
    structure = FOUR if connectivity == 8 else EIGHT
    interior = ndimage.binary_erosion(np.pad(mask, 1), structure=structure, border_value=0)[1:-1, 1:-1]
    rows, cols = np.nonzero(mask & ~interior)
    return {(c + 0.5, r + 0.5) for r, c in zip(rows, cols)}


def check_invariants(mask, connectivity):
    """Everything that must hold for any mask; returns the boundaries."""
    boundaries = trace_boundaries(mask, connectivity=connectivity)
    structure = EIGHT if connectivity == 8 else FOUR
    labels, n_components = ndimage.label(mask, structure=structure)
    holes = [b for b in boundaries if b.is_hole]
    outers = [b for b in boundaries if not b.is_hole]
    assert len(outers) == n_components
    total_area = 0
    midpoint_area = 0.0
    pixel_union = set()
    for index, b in enumerate(boundaries):
        assert isinstance(b, Boundary) and b.connectivity == connectivity
        n = len(b.pixels)
        # chain code reproduces the pixel chain and closes it
        assert b.chain_code.dtype == np.int8
        assert len(b.chain_code) == (n if n > 1 else 0)
        np.testing.assert_array_equal(chain_to_pixels(b.pixels[0], b.chain_code), b.pixels)
        if n > 1:
            np.testing.assert_array_equal(b.pixels[-1] + FREEMAN_STEPS[b.chain_code[-1]], b.pixels[0])
            steps = np.diff(np.vstack([b.pixels, b.pixels[:1]]), axis=0)
            assert np.abs(steps).max() == 1 and (np.abs(steps).sum(1) > 0).all()
        if connectivity == 4:
            assert (b.chain_code % 2 == 0).all()
        # every chain pixel is ink of this boundary's component
        cols = (b.pixels[:, 0] - 0.5).astype(int)
        rows = (b.pixels[:, 1] - 0.5).astype(int)
        assert mask[rows, cols].all()
        assert (labels[rows, cols] - 1 == b.component).all()
        pixel_union |= set(map(tuple, b.pixels.tolist()))
        # crack outline: unit cracks, midpoints, exact area with the right sign
        vertices = b.crack_vertices
        assert len(vertices) == len(b.outline) >= 4
        np.testing.assert_array_equal(vertices, np.round(vertices))
        cracks = np.roll(vertices, -1, axis=0) - vertices
        np.testing.assert_array_equal(np.abs(cracks).sum(1), 1)
        np.testing.assert_array_equal(b.outline, vertices + cracks / 2)
        area = shoelace(vertices)
        assert area == b.area and (area < 0) == b.is_hole
        total_area += area
        midpoint_area += shoelace(b.outline)
        if b.is_hole:
            assert boundaries[b.parent].component == b.component and not boundaries[b.parent].is_hole
            assert b.parent < index
        else:
            assert b.parent is None
    # exact: cracks enclose exactly the ink; midpoints cut 1/8 per net corner (4 per boundary)
    assert total_area == int(mask.sum())
    assert midpoint_area == mask.sum() - 0.5 * (len(outers) - len(holes))
    assert pixel_union == boundary_pixel_set(mask, connectivity)
    return boundaries


def check_against_find_contours(mask, connectivity):
    """Marching squares at level 0.5 passes exactly through the crack midpoints: same contours, same
    points; the pixel-centre chain stays close to them; orientations agree up to one global sign
    (outer and holes alike)."""
    boundaries = trace_boundaries(mask, connectivity=connectivity)
    reference = contours_of(mask, connectivity)
    assert len(reference) == len(boundaries)
    ours = {frozenset(map(tuple, b.outline.tolist())): b for b in boundaries}
    relative_signs = set()
    for contour in reference:
        key = frozenset(map(tuple, contour.tolist()))
        assert key in ours, "a find_contours contour has no identical crack outline"
        boundary = ours[key]
        assert len(contour) == len(boundary.outline)
        # 8-chains cut concave corners diagonally (<= sqrt(0.5)); 4-chains go round them through the
        # corner pixel, whose centre is 1.5 / sqrt(2) px from the cut between the corner's crack midpoints.
        bound = np.sqrt(0.5) if connectivity == 8 else 1.5 / np.sqrt(2)
        assert hausdorff(boundary.pixels, contour) <= bound + 0.02
        relative_signs.add(np.sign(shoelace(contour)) * np.sign(shoelace(boundary.outline)))
    assert len(relative_signs) <= 1


def disc(size, radius, centre=None):
    yy, xx = np.mgrid[:size, :size] + 0.5
    cx, cy = centre if centre is not None else (size / 2, size / 2)
    return (xx - cx) ** 2 + (yy - cy) ** 2 <= radius**2


# ------------------------------------------------------------------------------------------ tests
def test_rectangle_chain_and_outline():
    mask = np.zeros((6, 7), bool)
    mask[1:4, 2:6] = True  # rows 1..3, cols 2..5
    (b,) = trace_boundaries(mask)
    assert not b.is_hole and b.parent is None and b.component == 0
    assert b.start == (2.5, 1.5)
    assert b.chain_string == "0006644422"  # 3 x 4 block: 3 E, 2 S, 3 W, 2 N
    assert b.area == 12
    np.testing.assert_array_equal(b.crack_vertices[0], [2, 1])
    np.testing.assert_array_equal(b.outline[:2], [[2.5, 1.0], [3.5, 1.0]])
    assert len(b.outline) == 2 * (3 + 4)


def test_single_pixel_is_a_tiny_square():
    mask = np.zeros((3, 3), bool)
    mask[1, 1] = True
    for connectivity in (4, 8):
        (b,) = trace_boundaries(mask, connectivity=connectivity)
        np.testing.assert_array_equal(b.pixels, [[1.5, 1.5]])
        assert b.chain_code.size == 0 and b.area == 1
        np.testing.assert_array_equal(b.crack_vertices, [[1, 1], [2, 1], [2, 2], [1, 2]])
        np.testing.assert_array_equal(b.outline, [[1.5, 1], [2, 1.5], [1.5, 2], [1, 1.5]])


def test_pixel_in_the_corner_of_the_frame_and_full_frame():
    mask = np.zeros((4, 5), bool)
    mask[0, 0] = True
    (b,) = trace_boundaries(mask)
    np.testing.assert_array_equal(b.crack_vertices, [[0, 0], [1, 0], [1, 1], [0, 1]])
    (full,) = trace_boundaries(np.ones((4, 5), bool))
    assert full.area == 20 and len(full.outline) == 18
    assert full.crack_vertices.min(0).tolist() == [0, 0] and full.crack_vertices.max(0).tolist() == [5, 4]


def test_no_ink_gives_no_boundaries():
    assert trace_boundaries(np.zeros((5, 5), bool)) == []


def test_ring_has_outer_and_hole_with_opposite_orientation():
    yy, xx = np.mgrid[:40, :40] + 0.5
    r2 = (xx - 20) ** 2 + (yy - 20) ** 2
    mask = (r2 <= 15**2) & (r2 > 8**2)
    outer, hole = check_invariants(mask, 8)
    assert not outer.is_hole and hole.is_hole and hole.parent == 0
    assert outer.area > 0 > hole.area
    assert shoelace(outer.pixels) > 0 > shoelace(hole.pixels)
    assert outer.area + hole.area == mask.sum()
    assert -hole.area == int(((r2 <= 8**2)).sum())
    check_against_find_contours(mask, 8)


def test_hole_chain_starts_heading_south():
    mask = np.ones((5, 5), bool)
    mask[2, 2] = False
    outer, hole = trace_boundaries(mask)
    np.testing.assert_array_equal(hole.crack_vertices[:2], [[2, 2], [2, 3]])
    assert hole.chain_string == "7135"  # the 4 ink pixels around the hole, 8-connected
    outer4, hole4 = trace_boundaries(mask, connectivity=4)
    assert hole4.chain_string == "60022446"  # 4-connected: the corner pixels are included


def test_several_components_and_nesting():
    mask = np.zeros((60, 80), bool)
    mask[5:55, 5:55] = True
    mask[10:50, 10:50] = False  # big hole
    mask[20:40, 20:40] = True  # island inside the hole
    mask[27:33, 27:33] = False  # hole in the island
    mask[5:15, 60:75] = True  # separate block with two holes
    mask[7:9, 62:64] = False
    mask[10:12, 70:72] = False
    boundaries = check_invariants(mask, 8)
    kinds = [(b.component, b.is_hole) for b in boundaries]
    assert kinds == [(0, False), (0, True), (1, False), (1, True), (1, True), (2, False), (2, True)]
    assert [b.parent for b in boundaries] == [None, 0, None, 2, 2, None, 5]
    check_against_find_contours(mask, 8)


@pytest.mark.parametrize("connectivity, n_boundaries", [(8, 1), (4, 2)])
def test_touching_diagonals(connectivity, n_boundaries):
    mask = np.array([[1, 0], [0, 1]], bool)
    boundaries = check_invariants(mask, connectivity)
    assert len(boundaries) == n_boundaries
    check_against_find_contours(mask, connectivity)


def test_checkerboard_connectivity():
    mask = (np.add.outer(np.arange(7), np.arange(7)) % 2 == 0)
    eight = check_invariants(mask, 8)
    four = check_invariants(mask, 4)
    assert sum(not b.is_hole for b in eight) == 1
    assert sum(b.is_hole for b in eight) == 12  # interior odd pixels (5x5 inner block: 12 odd), 4-conn bg
    assert len(four) == mask.sum() and not any(b.is_hole for b in four)
    for connectivity in (4, 8):
        check_against_find_contours(mask, connectivity)


@pytest.mark.parametrize("connectivity", [4, 8])
def test_one_pixel_wide_lines(connectivity):
    mask = np.zeros((30, 30), bool)
    mask[3, 2:25] = True  # horizontal
    mask[6:28, 27] = True  # vertical
    idx = np.arange(8, 24)
    mask[idx, idx - 4] = True  # diagonal: 8-connected, 4-disconnected
    boundaries = check_invariants(mask, connectivity)
    horizontal = boundaries[0]
    assert len(horizontal.pixels) == 2 * 23 - 2  # there and back, ends not repeated
    assert horizontal.chain_string == "0" * 22 + "4" * 22
    assert shoelace(horizontal.pixels) == 0
    if connectivity == 8:
        assert len(boundaries) == 3
        diagonal = boundaries[2]
        assert diagonal.chain_string == "7" * 15 + "3" * 15
    else:
        assert len(boundaries) == 2 + len(idx)
    check_against_find_contours(mask, connectivity)


def test_disc_matches_find_contours_and_moore():
    mask = disc(64, 25.3)
    (b,) = check_invariants(mask, 8)
    check_against_find_contours(mask, 8)
    np.testing.assert_array_equal(b.pixels, moore_trace(mask))


def test_moore_reference_on_each_component():
    rng = np.random.default_rng(5)
    mask = ndimage.binary_opening(rng.random((50, 50)) < 0.55)
    labels, n = ndimage.label(mask, structure=EIGHT)
    outers = [b for b in trace_boundaries(mask) if not b.is_hole]
    assert len(outers) == n and n > 3
    for b in outers:
        np.testing.assert_array_equal(b.pixels, moore_trace(labels == b.component + 1))


@settings(max_examples=60, deadline=None)
@given(
    shape=st.tuples(st.integers(1, 14), st.integers(1, 14)),
    density=st.floats(0.05, 0.95),
    seed=st.integers(0, 2**32 - 1),
    connectivity=st.sampled_from([4, 8]),
)
def test_random_masks(shape, density, seed, connectivity):
    mask = np.random.default_rng(seed).random(shape) < density
    boundaries = check_invariants(mask, connectivity)
    if mask.any():
        check_against_find_contours(mask, connectivity)
    else:
        assert boundaries == []
    if connectivity == 8:
        labels, _ = ndimage.label(mask, structure=EIGHT)
        for b in boundaries:
            if not b.is_hole:
                np.testing.assert_array_equal(b.pixels, moore_trace(labels == b.component + 1))


def test_integer_mask_and_validation():
    mask = np.zeros((4, 4), np.uint8)
    mask[1:3, 1:3] = 1
    (b,) = trace_boundaries(mask)
    assert b.area == 4
    with pytest.raises(ValueError, match="connectivity"):
        trace_boundaries(mask, connectivity=6)
    with pytest.raises(ValueError, match="2-D"):
        trace_boundaries(np.zeros((2, 2, 2), bool))
    with pytest.raises(ValueError, match="empty"):
        trace_boundaries(np.zeros((0, 3), bool))
    with pytest.raises(ValueError, match="0 and 1"):
        trace_boundaries(np.full((3, 3), 2))
    with pytest.raises(TypeError, match="bool"):
        trace_boundaries(np.array([["a"]]))


def test_chain_to_pixels_validation():
    np.testing.assert_array_equal(chain_to_pixels((0.5, 0.5), [0, 6]), [[0.5, 0.5], [1.5, 0.5]])
    with pytest.raises(ValueError, match="0..7"):
        chain_to_pixels((0, 0), [8])


def test_large_disc_8000():
    """8000 x 8000 image: finishes (memory stays O(H W) bytes) and the crack area is still exact."""
    size = 8000
    mask = np.zeros((size, size), bool)
    y = np.arange(size) + 0.5 - size / 2
    half = np.sqrt(np.maximum(3900.0**2 - y**2, 0))
    lo = np.ceil(size / 2 - half - 0.5).astype(int)
    hi = np.floor(size / 2 + half - 0.5).astype(int)
    for row in np.flatnonzero(half > 0):  # one slice per row, no float (H, W) temporaries
        mask[row, lo[row]:hi[row] + 1] = True
    (b,) = trace_boundaries(mask)
    assert b.area == int(mask.sum())
    radius = np.hypot(b.outline[:, 0] - size / 2, b.outline[:, 1] - size / 2)
    assert np.abs(radius - 3900).max() < 1.0


# ------------------------------------------------------------------------------ the minority rule
def thin_diagonal(size=40, width=0.8):
    """A stroke along the diagonal, narrower than a pixel: its pixels touch only at their corners."""
    yy, xx = np.mgrid[:size, :size] + 0.5
    return np.abs(yy - xx) <= width / 2


def test_minority_keeps_a_thin_diagonal_stroke_whole():
    mask = thin_diagonal()
    assert len(trace_boundaries(mask, connectivity=4)) > 1
    (stroke,) = trace_boundaries(mask, connectivity="minority")
    assert stroke.area == mask.sum() and stroke.connectivity == "minority"


def test_minority_joins_the_rarer_paper_across_a_corner():
    # two paper pixels touching at a corner inside a block of ink: one gap of paper, not two pinholes
    mask = np.ones((12, 12), bool)
    mask[5, 5] = mask[6, 6] = False
    assert [b.area for b in trace_boundaries(mask, connectivity=8)] == [144, -1, -1]
    assert [b.area for b in trace_boundaries(mask, connectivity="minority")] == [144, -2]
    # and ink stays apart where ink is the rarer colour: two ink pixels touching at a corner on paper
    assert len(trace_boundaries(~mask, connectivity="minority")) == 1
    assert len(trace_boundaries(~mask, connectivity=4)) == 2


@settings(max_examples=40, deadline=None)
@given(arrays(bool, st.tuples(st.integers(1, 14), st.integers(1, 14))))
def test_minority_cycles_are_consistent(mask):
    """Every crack lies on exactly one boundary and the signed areas add up to the ink count."""
    boundaries = trace_boundaries(mask, connectivity="minority")
    assert sum(b.area for b in boundaries) == int(mask.sum())
    cracks = sum(len(b.outline) for b in boundaries)
    horizontal = np.count_nonzero(np.diff(np.pad(mask, 1).astype(np.int8), axis=0))
    vertical = np.count_nonzero(np.diff(np.pad(mask, 1).astype(np.int8), axis=1))
    assert cracks == horizontal + vertical
    for b in boundaries:
        assert np.abs(np.diff(np.vstack([b.crack_vertices, b.crack_vertices[:1]]), axis=0)).sum(axis=1).max() == 1


def test_connectivity_is_checked():
    for bad in (6, np.int64(6), "eight", "4"):  # an int or a name, but not one of the choices
        with pytest.raises(ValueError, match="connectivity"):
            trace_boundaries(np.ones((2, 2), bool), connectivity=bad)
    for bad in (True, None, [8], 4.0, np.float64(8.0)):  # 4.0 was accepted (4.0 in (4, 8)); now of the wrong type
        with pytest.raises(TypeError, match="connectivity"):
            trace_boundaries(np.ones((2, 2), bool), connectivity=bad)


@pytest.mark.parametrize("bad", [None, True, 8.0, np.float64(4.0), [8], (4,), b"minority"])
def test_a_connectivity_of_the_wrong_type_is_a_type_error_everywhere(bad):
    """``connectivity=None`` was a ValueError ("must be one of [4, 8, 'minority'], got None") where its neighbours
    of the same kind, ``contour=None`` say, are a TypeError, and ``sc.trace(connectivity=8.0)`` passed trace's
    check and failed in the loader. One rule now, ``check_connectivity``, for ``trace``, ``load_bitmap`` and
    ``trace_boundaries``: a value of the wrong type (None, a bool, a float, a sequence) is a TypeError naming the
    argument, the value and its type, an int or a name that is not a choice a ValueError; None is no default
    here (the defaults differ: "minority" for ``trace``, 8 for the lower layers)."""
    import splinecraft as sc

    mask = np.zeros((12, 12), bool)
    mask[3:9, 3:9] = True
    for call in (lambda: sc.trace(mask, connectivity=bad), lambda: sc.load_bitmap(mask, connectivity=bad),
                 lambda: trace_boundaries(mask, connectivity=bad)):
        with pytest.raises(TypeError, match=r"^connectivity must be 4, 8 or 'minority', got .* \(\w+\)$"):
            call()
    with pytest.raises(TypeError, match=r"contour must be one of \['outline', 'pixels'\], got None \(NoneType\)"):
        sc.trace(mask, contour=None)  # the neighbour it now agrees with
    with pytest.raises(ValueError, match=r"^connectivity must be 4, 8 or 'minority', got 6$"):
        sc.trace(mask, connectivity=6)
    assert sc.trace(mask, connectivity=np.int64(4)).params["connectivity"] == 4
