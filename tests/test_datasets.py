"""Tests for splinecraft.datasets: deterministic bitmaps, their exact outlines and the demo point sets.

Reference values are independent of the module: closed-form areas and radii, skimage's connected
component labelling, and skimage's point-in-polygon test of the pixel centres against the outlines.
"""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import cKDTree
from skimage import measure

from splinecraft import datasets

ALL_NAMES = datasets.THESIS_OBJECTS + datasets.SHAPES


def _components_and_holes(mask):
    components = measure.label(mask, connectivity=2).max()
    background = measure.label(~np.pad(mask, 1), connectivity=1).max()
    return components, background - 1


def _shoelace(points):
    x, y = points[:, 0], points[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


@pytest.mark.parametrize("name", datasets.THESIS_OBJECTS)
def test_thesis_object_is_a_deterministic_bool_mask(name):
    first = datasets.thesis_object(name, size=160)
    second = datasets.thesis_object(name, size=160)
    assert first.dtype == bool and first.ndim == 2
    assert max(first.shape) == 160
    np.testing.assert_array_equal(first, second)
    first[:] = False  # a fresh array each call: mutating it does not change the next one
    assert datasets.thesis_object(name, size=160).any()
    # some ink, mostly background, and a clean margin (no boundary touches the image edge)
    fraction = second.mean()
    assert 0.05 < fraction < 0.6
    assert not second[0].any() and not second[-1].any()
    assert not second[:, 0].any() and not second[:, -1].any()


def test_default_sizes_and_contour_scale():
    for name in datasets.THESIS_OBJECTS:
        mask = datasets.thesis_object(name)
        assert max(mask.shape) == datasets.THESIS_DEFAULT_SIZE[name]
        # crack-edge count of the order of the thesis's contours (1005-1644 points)
        edges = (mask[1:, :] != mask[:-1, :]).sum() + (mask[:, 1:] != mask[:, :-1]).sum()
        assert 700 < edges < 3000, (name, edges)


@pytest.mark.parametrize(
    "name, components, holes",
    [("ali", 3, 0), ("apple", 1, 0), ("plane", 1, 0), ("D", 1, 1), ("planes", 7, 4)],
)
def test_thesis_object_topology(name, components, holes):
    mask = datasets.thesis_object(name)
    assert _components_and_holes(mask) == (components, holes)


def test_planes_has_several_parts():
    components, holes = _components_and_holes(datasets.thesis_object("planes", size=200))
    assert components >= 2 and holes >= 1


@pytest.mark.parametrize("call", [datasets.thesis_object, datasets.shape, datasets.true_outline,
                                  datasets.sample_points, datasets.sample_closed])
def test_unknown_name_lists_valid_names(call):
    with pytest.raises(ValueError) as info:
        call("teapot")
    message = str(info.value)
    assert "teapot" in message and "valid names" in message
    valid = {datasets.thesis_object: datasets.THESIS_OBJECTS, datasets.shape: datasets.SHAPES,
             datasets.true_outline: ALL_NAMES}.get(call, tuple(datasets.SAMPLE_POINTS))
    for name in valid:
        assert repr(name) in message
    with pytest.raises(TypeError, match="name"):
        call(3)


@pytest.mark.parametrize("size, error", [(8, ValueError), (10_000, ValueError), (100.0, TypeError),
                                         (True, TypeError), ("64", TypeError)])
def test_bad_sizes(size, error):
    with pytest.raises(error, match="size"):
        datasets.thesis_object("D", size=size)
    with pytest.raises(error, match="size"):
        datasets.shape("disc", size=size)


def test_bad_spacing():
    for spacing in (0.0, 5.0, float("nan"), "0.1"):
        with pytest.raises(ValueError, match="spacing"):
            datasets.true_outline("disc", spacing=spacing)


def test_square_mask_is_the_exact_pixel_sampling():
    mask = datasets.shape("square", size=100)
    expected = np.zeros((100, 100), bool)
    expected[20:80, 20:80] = True  # pixel centres c + 0.5 in [20, 80]
    np.testing.assert_array_equal(mask, expected)


@settings(max_examples=40, deadline=None)
@given(size=st.integers(16, 300))
def test_disc_area_and_size(size):
    mask = datasets.shape("disc", size=size)
    assert mask.shape == (size, size)
    radius = 0.38 * size
    # pixel-centre sampling: the area error is bounded by the pixels the circle passes through
    assert abs(mask.sum() - np.pi * radius**2) <= 2 * np.pi * radius * 0.75 + 4


@pytest.mark.parametrize("name", ALL_NAMES)
def test_true_outline_reproduces_the_bitmap(name):
    """Pixel centres inside the outline polygons (even-odd) are exactly the ink pixels.

    Only centres within 0.02 px of the outline may differ (the polyline's chords there).
    """
    size = 96
    mask = (datasets.thesis_object(name, size) if name in datasets.THESIS_OBJECTS
            else datasets.shape(name, size))
    outlines = datasets.true_outline(name, size, spacing=0.05)
    rows, cols = mask.shape
    centres = np.c_[np.tile(np.arange(cols) + 0.5, rows), np.repeat(np.arange(rows) + 0.5, cols)]
    inside = np.zeros(len(centres), bool)
    for outline in outlines:
        inside ^= measure.points_in_poly(centres, outline)
    nearest = cKDTree(np.vstack(outlines)).query(centres)[0]  # <= distance to the polyline + 0.025
    differ = inside != mask.ravel()
    assert (nearest[differ] < 0.06).all(), (name, differ.sum())
    # orientation convention of Boundary: outers positive, holes negative; as many outlines as
    # components plus holes
    components, holes = _components_and_holes(mask)
    areas = np.array([_shoelace(o) for o in outlines])
    assert (areas > 0).sum() == components and (areas < 0).sum() == holes


@pytest.mark.parametrize("spacing", [0.05, 0.1, 0.5])
def test_true_outline_of_disc_and_ellipse_matches_closed_forms(spacing):
    size = 200
    scale = size / 100
    (circle,) = datasets.true_outline("disc", size, spacing=spacing)
    radius = np.hypot(circle[:, 0] - 50 * scale, circle[:, 1] - 50 * scale)
    np.testing.assert_allclose(radius, 38 * scale, atol=1e-8)
    edges = np.linalg.norm(np.diff(np.vstack([circle, circle[:1]]), axis=0), axis=1)
    assert edges.max() <= spacing + 1e-9
    assert abs(_shoelace(circle) - np.pi * (38 * scale) ** 2) < 2 * np.pi * 38 * scale * spacing**2

    (oval,) = datasets.true_outline("ellipse", size, spacing=spacing)
    angle = np.radians(25)
    u = (oval[:, 0] - 50 * scale) * np.cos(angle) + (oval[:, 1] - 50 * scale) * np.sin(angle)
    v = -(oval[:, 0] - 50 * scale) * np.sin(angle) + (oval[:, 1] - 50 * scale) * np.cos(angle)
    np.testing.assert_allclose((u / (42 * scale)) ** 2 + (v / (24 * scale)) ** 2, 1.0, atol=1e-8)


def test_true_outline_reaches_the_corners():
    size = 128
    scale = size / 100
    (square,) = datasets.true_outline("square", size, spacing=0.1)
    corners = np.array([[20, 20], [80, 20], [80, 80], [20, 80]]) * scale
    np.testing.assert_allclose(datasets.shape_corners("square", size), corners)
    gap = np.linalg.norm(square[None] - corners[:, None], axis=2).min(axis=1)
    assert gap.max() < 0.05
    assert abs(_shoelace(square) - (60 * scale) ** 2) < 0.5
    # the star: 5 tips at radius 42 and 5 inner vertices at radius 18 (design units)
    (star,) = datasets.true_outline("star", size, spacing=0.1)
    angles = np.radians(-90 + 36 * np.arange(10))
    radii = np.where(np.arange(10) % 2 == 0, 42.0, 18.0)
    vertices = np.c_[50 + radii * np.cos(angles), 52 + radii * np.sin(angles)] * scale
    np.testing.assert_allclose(datasets.shape_corners("star", size), vertices)
    gap = np.linalg.norm(star[None] - vertices[:, None], axis=2).min(axis=1)
    assert gap.max() < 0.2
    x, y = vertices[:, 0], vertices[:, 1]
    exact_area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    assert abs(_shoelace(star) - exact_area) < 0.5


@pytest.mark.parametrize("name, count", [("square", 4), ("star", 10), ("disc", 0), ("ellipse", 0),
                                         ("blob", 0), ("D", 8)])
def test_shape_corners_lie_on_the_outline(name, count):
    size = 150
    corners = datasets.shape_corners(name, size)
    assert corners.shape == (count, 2)
    for corner in corners:
        # the corner lies on one of the outlines, and the outline turns sharply there: the chords to
        # the outline points 2 px of arc before and after differ in direction by more than 30°
        ring = min(datasets.true_outline(name, size, spacing=0.05),
                   key=lambda o: np.linalg.norm(o - corner, axis=1).min())
        index = int(np.argmin(np.linalg.norm(ring - corner, axis=1)))
        assert np.linalg.norm(ring[index] - corner) < 0.1
        steps = np.linalg.norm(np.diff(np.vstack([ring, ring[:1]]), axis=0), axis=1)
        arc = np.concatenate([[0.0], np.cumsum(steps)])[:-1]
        total = steps.sum()
        ahead = (arc - arc[index]) % total
        after = ring[np.argmin(np.abs(ahead - 2.0))]
        before = ring[np.argmin(np.abs(ahead - (total - 2.0)))]
        incoming, outgoing = corner - before, after - corner
        cosine = incoming @ outgoing / (np.linalg.norm(incoming) * np.linalg.norm(outgoing))
        assert cosine < np.cos(np.radians(30)), (name, corner, cosine)


def test_shape_corners_rejects_objects_without_known_corners():
    with pytest.raises(ValueError, match="valid names"):
        datasets.shape_corners("apple")


def test_true_outline_is_fresh_and_cached_consistently():
    first = datasets.true_outline("D", 120)
    first[0][:] = 0.0
    second = datasets.true_outline("D", 120)
    assert not np.allclose(second[0], 0.0)
    assert [o.shape for o in second] == [o.shape for o in datasets.true_outline("D", 120)]
    # defaults follow the bitmap defaults so that outline and bitmap overlay
    default = datasets.true_outline("apple")
    mask = datasets.thesis_object("apple")
    assert default[0][:, 0].max() < mask.shape[1] and default[0][:, 1].max() < mask.shape[0]


@pytest.mark.parametrize("name", tuple(datasets.SAMPLE_POINTS))
def test_sample_points(name):
    points = datasets.sample_points(name)
    assert points.dtype == float and points.ndim == 2 and points.shape[1] == 2
    assert len(points) >= 4 and np.isfinite(points).all()
    closed = datasets.sample_closed(name)
    assert isinstance(closed, bool)
    ring = np.vstack([points, points[:1]]) if closed else points
    assert (np.linalg.norm(np.diff(ring, axis=0), axis=1) > 1e-6).all()
    points[:] = 0.0
    assert not np.allclose(datasets.sample_points(name), 0.0)
    assert isinstance(datasets.SAMPLE_POINTS[name], str)


def test_sample_points_are_upright_in_the_editor_frame():
    for name in datasets.SAMPLE_POINTS:
        points = datasets.sample_points(name)
        assert points[:, 0].min() >= 60 - 1e-9 and points[:, 0].max() <= 560 + 1e-9
        assert points[:, 1].min() >= 60 - 1e-9 and points[:, 1].max() <= 380 + 1e-9
    heart = datasets.sample_points("heart")
    tip = heart[np.argmax(heart[:, 1])]  # y down: the tip is the lowest point on screen
    assert abs(tip[0] - heart[:, 0].mean()) < 1e-6 * np.ptp(heart[:, 0]) + 1e-9
    pot = datasets.sample_points("pot")
    assert pot[0, 1] > pot[:, 1].mean()  # the pot stands on its base (bottom of the screen)


def test_sample_flags():
    assert datasets.sample_closed("heart") and datasets.sample_closed("square")
    assert not datasets.sample_closed("hand") and not datasets.sample_closed("pot")


@pytest.mark.parametrize("name", ["square", "star", "D"])
@pytest.mark.parametrize("size", [48, 150, 600])
def test_sharp_corners_are_vertices_of_the_true_outline(name, size):
    """The docstrings: sharp corners are vertices (on the zero set to 1e-3 px). The star's 36-degree tips were
    cut by 0.13 px (the crossing of their sides lay farther from the chord than the refinement accepted)."""
    outlines = datasets.true_outline(name, size)
    for corner in datasets.shape_corners(name, size):
        nearest = min(float(np.linalg.norm(outline - corner, axis=1).min()) for outline in outlines)
        assert nearest < 1e-3, (name, size, corner, nearest)
