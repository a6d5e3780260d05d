"""tangent-jump's fillet test (capture/corners/_fillet.py, docs/capture.md §11): a corner is kept only where
the pixels support a tangent discontinuity. Shapes are made here: polygons whose corners are sharp or rounded
by circular fillets of known radius, rasterized at random rotations."""
from __future__ import annotations

import importlib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from skimage.draw import polygon as fill_polygon

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.corners import corners, tangent_jump

fillet = importlib.import_module("splinecraft.capture.corners._fillet")
jump = importlib.import_module("splinecraft.capture.corners._jump")

SETTINGS = settings(max_examples=25, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow])


def filleted_polygon(vertices, radii, step=0.05):
    """Dense closed outline of a polygon whose vertex ``i`` is rounded by a circular fillet of radius
    ``radii[i]`` (0 = sharp): the fillet is tangent to both sides (tangent length ``r tan(turn / 2)``)."""
    v = np.asarray(vertices, float)
    count = len(v)
    points = []
    for i in range(count):
        before, after = v[i] - v[i - 1], v[(i + 1) % count] - v[i]
        u1, u2 = before / np.hypot(*before), after / np.hypot(*after)
        turn = np.arccos(np.clip(u1 @ u2, -1.0, 1.0))
        left = np.sign(u1[0] * u2[1] - u1[1] * u2[0])
        if radii[i] > 0:
            start = v[i] - radii[i] * np.tan(turn / 2) * u1
            centre = start + left * radii[i] * np.array([-u1[1], u1[0]])
            a0 = np.arctan2(*(start - centre)[::-1])
            angles = a0 + left * np.linspace(0.0, turn, max(2, int(np.ceil(radii[i] * turn / step))))
            points.append(centre + radii[i] * np.column_stack([np.cos(angles), np.sin(angles)]))
        else:
            points.append(v[i][None, :])
    return np.vstack(points)


def mask_of(dense, margin=6):
    """Ink where the pixel centre is inside the closed dense outline, and the outline shifted into the mask's
    frame."""
    shift = margin - np.floor(dense.min(axis=0))
    placed = dense + shift
    height, width = (np.ceil(placed.max(axis=0)).astype(int) + margin)[::-1]
    mask = np.zeros((height, width), bool)
    rows, cols = fill_polygon(placed[:, 1] - 0.5, placed[:, 0] - 0.5, mask.shape)
    mask[rows, cols] = True
    return mask, placed


def outline_of(dense, margin=6):
    """Rasterize a closed dense outline (pixel ink where its centre is inside) and trace its crack outline;
    returns the outline and the shift applied to the coordinates."""
    shift = margin - np.floor(dense.min(axis=0))
    mask, _ = mask_of(dense, margin)
    outer = [b for b in trace_boundaries(mask) if not b.is_hole]
    assert len(outer) == 1
    return outer[0].outline, shift


def rotated_square(side, angle):
    corners_ = np.array([[0, 0], [side, 0], [side, side], [0, side]], float) - side / 2
    c, s = np.cos(angle), np.sin(angle)
    return corners_ @ np.array([[c, -s], [s, c]]).T


@SETTINGS
@given(radius=st.floats(8.0, 12.0), angle=st.floats(0, np.pi / 2), side=st.floats(50.0, 90.0))
def test_a_fillet_seen_as_one_corner_is_released_and_the_sharp_corners_stay(radius, angle, side):
    # a fillet of radius 8-12 px at a right angle lies 3.3-5 px inside the crossing of its sides, a sharp tip's
    # pixels at most 1 px (sqrt(1/2) / sin 45). Limits (docs/capture.md §11): a fillet on which the arms see two
    # turns of about 45 degrees keeps them (each turn alone is too gentle to show its rounding), and so may a
    # smaller one whose corner the arms put off its middle (the windows of one side then start on the arc)
    vertices = rotated_square(side, angle)
    outline, shift = outline_of(filleted_polygon(vertices, [radius, 0.0, radius, 0.0]))
    before, after = outline[tangent_jump(outline, fillets=False)], outline[tangent_jump(outline, fillets=True)]
    for point in vertices[[1, 3]] + shift:                      # the sharp corners
        assert np.hypot(*(after - point).T).min() <= 2.5
    for point in vertices[[0, 2]] + shift:                      # the fillets (tangent length = radius)
        if np.sum(np.hypot(*(before - point).T) <= radius) == 1:
            assert np.hypot(*(after - point).T).min() > radius


@pytest.mark.parametrize("radius, angle", [(6.0, 0.0), (6.0, 5 * np.pi / 22), (7.0, 2 * np.pi / 22), (7.0, 3 * np.pi / 22),
                                           (8.0, 5 * np.pi / 22), (9.0, 6 * np.pi / 22)])
def test_without_the_fillet_test_these_fillets_count_as_corners(radius, angle):
    # the reason for the test: tangent-jump's arms alone (without step 5b, spread turns, which releases some of
    # them too) see these right-angle fillets as corners; larger fillets spread their turn beyond the arms' flanks
    vertices = rotated_square(60.0, angle)
    outline, shift = outline_of(filleted_polygon(vertices, [radius, 0.0, radius, 0.0]))
    found = outline[tangent_jump(outline, fillets=False, spread=0.0)]
    for vertex in vertices[[0, 2]] + shift:
        assert np.hypot(*(found - vertex).T).min() <= radius      # on the fillet (tangent length = radius)
    assert len(found) == 4 and len(tangent_jump(outline, fillets=True, spread=0.0)) == 2
    # spread turns only release corners: the square's two sharp corners stay, fillet corners may go
    spread = set(tangent_jump(outline, fillets=False).tolist())
    assert spread <= set(tangent_jump(outline, fillets=False, spread=0.0).tolist()) and len(spread) >= 2
    both = tangent_jump(outline, fillets=True).tolist()
    assert both == tangent_jump(outline, fillets=True, spread=0.0).tolist() and len(both) == 2


@pytest.mark.parametrize("options", [{}, {"wedge": True}], ids=["fillet-test", "wedge-test"])
@SETTINGS
@given(count=st.integers(3, 8), angle=st.floats(0, 2 * np.pi), radius=st.floats(30.0, 80.0),
       dx=st.floats(0, 1), dy=st.floats(0, 1))
def test_the_sharp_corners_of_regular_polygons_are_all_kept(options, count, angle, radius, dx, dy):
    # neither the fillet test (on by default) nor the wedge test releases a sharp corner
    turns = angle + 2 * np.pi * np.arange(count) / count
    vertices = np.column_stack([np.cos(turns), np.sin(turns)]) * radius + [dx, dy]
    outline, shift = outline_of(vertices)
    with_test, without = tangent_jump(outline, **options), tangent_jump(outline, fillets=False)
    assert np.array_equal(with_test, without)
    assert len(with_test) == count


@SETTINGS
@given(radius=st.floats(0.0, 12.0), angle=st.floats(0, 2 * np.pi), side=st.floats(40.0, 90.0))
def test_the_fillet_test_only_releases_corners(radius, angle, side):
    outline, _ = outline_of(filleted_polygon(rotated_square(side, angle), [radius, radius, 0.0, radius]))
    assert set(tangent_jump(outline)) <= set(tangent_jump(outline, fillets=False))


@pytest.mark.parametrize("turn_deg, radius", [(60.0, 0.0), (90.0, 0.0), (120.0, 0.0), (45.0, 3.0), (90.0, 3.0),
                                               (120.0, 2.0), (60.0, 6.0), (90.0, 6.0)])
def test_rounding_depth_of_an_exact_fillet_is_the_closed_form(turn_deg, radius):
    # exact (unrasterized) sides: the crossing of the sides lies r (1 / sin(theta / 2) - 1) beyond the fillet,
    # theta = 180 - turn the interior angle, and the depth is that times sin(theta / 2); the windows of the last
    # starts lie beyond the fillet's tangent points (r tan(turn / 2) <= 6 px here)
    turn = np.radians(turn_deg)
    vertices = np.array([[0.0, 0.0], [80.0, 0.0], [80.0 + 80.0 * np.cos(turn), 80.0 * np.sin(turn)]])
    dense = filleted_polygon(vertices, [0.0, radius, 0.0], step=0.05)
    points = np.vstack([np.linspace(dense[k], dense[(k + 1) % len(dense)], 200, endpoint=False)
                        for k in range(len(dense))])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))])
    perimeter = arc[-1] + np.hypot(*(points[0] - points[-1]))
    middle = np.argmin(np.hypot(*(points - vertices[1]).T))       # on the bisector: the fillet's middle
    depth, = fillet.rounding_depths(points, arc, perimeter, True, [arc[middle]], [40.0], [40.0], tilt=0.0)
    assert depth == pytest.approx(radius * (1 - np.sin((np.pi - turn) / 2)), abs=0.05)


def test_fillets_must_be_a_bool():
    outline, _ = outline_of(rotated_square(40.0, 0.3))
    with pytest.raises((TypeError, ValueError), match="fillets"):
        tangent_jump(outline, fillets="yes")
    assert np.array_equal(corners(outline, "tangent-jump", fillets=True), tangent_jump(outline))


# ---- the wedge test (wedge=True, _fillet.wedge_contradictions): paper pixel centres inside the sharp wedge of
# a corner's digital straight sides


@SETTINGS
@given(radius=st.floats(0.0, 12.0), angle=st.floats(0, 2 * np.pi), side=st.floats(40.0, 90.0))
def test_the_wedge_test_only_releases_corners_and_keeps_the_sharp_ones(radius, angle, side):
    vertices = rotated_square(side, angle)
    outline, shift = outline_of(filleted_polygon(vertices, [radius, radius, 0.0, radius]))
    found = tangent_jump(outline, wedge=True)
    assert set(found) <= set(tangent_jump(outline))
    assert np.hypot(*(outline[found] - (vertices[2] + shift)).T).min() <= 2.5      # the sharp corner


@pytest.mark.parametrize("radius", [3.2, 3.5, 3.8])
@pytest.mark.parametrize("angle", [0.25, 0.5, 0.75, 1.0, 1.5])
def test_the_wedge_test_releases_right_angle_fillets_of_3_to_4_px(radius, angle):
    # a fillet of r = 3-4 px at a right angle lies 1.2-1.7 px inside its sides' crossing, within what the depth
    # test must allow a sharp tip at some rotations; the rounding leaves about 0.2 r^2 px^2 between arc and
    # wedge, and a paper centre there. Limit: sides within a few degrees of an axis are resolved only to half a
    # pixel (their preimage is a pixel wide), so the fillets of an axis-aligned square (and at 1.25 rad,
    # 18 degrees off an axis) stay corners
    vertices = rotated_square(70.0, angle)
    outline, shift = outline_of(filleted_polygon(vertices, [radius, 0.0, radius, 0.0]))
    before, after = outline[tangent_jump(outline)], outline[tangent_jump(outline, wedge=True)]
    for point in vertices[[1, 3]] + shift:                      # the sharp corners stay
        assert np.hypot(*(after - point).T).min() <= 2.5
    for point in vertices[[0, 2]] + shift:                      # the fillets, corners without the test, go
        assert np.hypot(*(before - point).T).min() <= radius
        assert np.hypot(*(after - point).T).min() > radius


def test_wedge_must_be_a_bool():
    with pytest.raises(TypeError, match="wedge"):
        tangent_jump(np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float), wedge=1)
