"""The square end of a stroke 1-5 px wide is two corners (docs/capture.md §11, tangent-jump step 6b "Stroke ends",
and step 9 for the axis-aligned ends of 1-2 px): the detector's one merged corner in the middle of such an end
becomes the end's two corners, and the fit reaches them. A wedge's tip stays one corner. Everything is generated
here: bars and wedges rasterized by pixel centres."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st
from skimage.draw import polygon as fill_polygon

import splinecraft as sc
from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.corners import check_params, tangent_jump


def turned(points, degrees, centre):
    angle = np.radians(degrees)
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return np.asarray(points, float) @ rotation.T + np.asarray(centre, float)


def bar(width, length, degrees, centre=(40.3, 40.1)):
    """The four corners of a ``length`` x ``width`` rectangle turned by ``degrees`` about ``centre``."""
    half_length, half_width = length / 2.0, width / 2.0
    return turned([(-half_length, -half_width), (half_length, -half_width), (half_length, half_width),
                   (-half_length, half_width)], degrees, centre)


def wedge(opening, length, degrees, centre):
    """A triangle whose tip (its first vertex) has the interior angle ``opening`` (degrees)."""
    half = length * np.tan(np.radians(opening) / 2.0)
    return turned([(-length / 2.0, 0.0), (length / 2.0, -half), (length / 2.0, half)], degrees, centre)


def render(vertices, size):
    """Pixel (r, c) is ink when its centre (c + 0.5, r + 0.5) is inside the polygon."""
    mask = np.zeros((size, size), bool)
    rows, cols = fill_polygon(vertices[:, 1] - 0.5, vertices[:, 0] - 0.5, mask.shape)
    mask[rows, cols] = True
    return mask


def dense_polyline(points, step=0.05, closed=True):
    points = np.asarray(points, float)
    ends = np.roll(points, -1, axis=0) if closed else points[1:]
    starts = points if closed else points[:-1]
    out = [a + (b - a) * np.linspace(0.0, 1.0, max(2, int(np.hypot(*(b - a)) / step)), endpoint=False)[:, None]
           for a, b in zip(starts, ends)]
    return np.vstack(out)


def hausdorff_to_polygon(result, vertices):
    """Two-sided distance between the traced curves and the polygon ``vertices`` (dense samples of both)."""
    traced = np.vstack([dense_polyline(spline.sample(0.02)[1]) for spline in result.splines])
    truth = dense_polyline(vertices)
    from scipy.spatial import cKDTree
    return max(cKDTree(truth).query(traced)[0].max(), cKDTree(traced).query(truth)[0].max())


@pytest.mark.parametrize("width,degrees", [(3.0, 45.0), (3.0, 30.0), (2.5, 60.0), (2.0, 30.0)])
def test_a_thin_bar_off_the_axes_keeps_the_four_corners_of_its_ends(width, degrees):
    """A 3-px bar at 45 degrees had one corner per end and came back 1.4 px off its rectangle; now each end has its
    two corners: four joins, each within 0.7 px of a corner of the bar, the outline within 0.7 px of it."""
    vertices = bar(width, 40.0, degrees)
    mask = render(vertices, 80)
    result = sc.trace(mask)
    assert len(result.corners[0]) == 4
    joins = np.vstack([spline.bezier()[:, 0] for spline in result.splines])
    assert max(np.hypot(*(joins - v).T).min() for v in vertices) <= 0.7
    assert hausdorff_to_polygon(result, vertices) <= 0.7
    assert len(sc.trace(mask, corner_params={"stroke_ends": False}).corners[0]) < 4  # what the option adds


def test_stroke_ends_bring_more_thin_bars_within_one_pixel():
    """Forty bars 2-4 px wide and 20-60 px long at random angles and sub-pixel offsets: with the stroke ends at
    least 70 % within 1 px of their rectangle and at least 8 points more than without (62-64 % without)."""
    rng = np.random.default_rng(20261204)
    within = {True: 0, False: 0}
    for _ in range(40):
        vertices = bar(rng.uniform(2.0, 4.0), rng.uniform(20.0, 60.0), rng.uniform(0.0, 180.0),
                       (50.0 + rng.uniform(0.0, 1.0), 50.0 + rng.uniform(0.0, 1.0)))
        mask = render(vertices, 100)
        for stroke_ends in within:
            result = sc.trace(mask, corner_params={"stroke_ends": stroke_ends})
            within[stroke_ends] += hausdorff_to_polygon(result, vertices) <= 1.0
    assert within[True] >= 28 and within[True] >= within[False] + 3, within


@settings(max_examples=40, deadline=None)
@given(st.floats(8.0, 45.0), st.floats(25.0, 60.0), st.floats(0.0, 360.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
@example(11.0, 25.0, 0.5, 0.0, 0.0)
@example(12.0, 33.0, 180.0, 0.0, 0.0)
@example(11.0, 29.0, 89.5, 0.0, 0.0)
def test_a_wedge_tip_stays_one_corner(opening, length, degrees, dx, dy):
    """The sides of an acute wedge meet just beyond its tip: its corners near the tip are those found without the
    stroke-end step (one, whose tip the fit extrapolates). The examples: thin wedges along a pixel axis, whose
    sides measured on the first arms of 7 samples beside the 1-px sliver of the tip came out 3 degrees apart (11
    in truth) and were taken for a cut stroke end; the sides' directions now come from their longest arms
    (hypothesis found the first one)."""
    vertices = wedge(opening, length, degrees, (50.0 + dx, 50.0 + dy))
    boundaries = trace_boundaries(render(vertices, 100))   # a thin tip may render as a separate speck too
    points = np.asarray(max(boundaries, key=lambda boundary: len(boundary.outline)).outline, float)
    near = [int((np.hypot(*(points[found] - vertices[0]).T) < 5.0).sum())
            for found in (tangent_jump(points), tangent_jump(points, stroke_ends=False))]
    assert near[0] == near[1]


def test_stroke_ends_is_a_checked_option():
    check_params("tangent-jump", {"stroke_ends": False})
    with pytest.raises(TypeError, match="stroke_ends"):
        check_params("tangent-jump", {"stroke_ends": "yes"})
    with pytest.raises(TypeError, match="stroke_ends"):
        tangent_jump(np.zeros((10, 2)), stroke_ends=1.5)


def taper(base, end, length, degrees, centre):
    """A stroke ``length`` px long narrowing from ``base`` to ``end`` px, cut square at its narrow end: its
    vertices, the two corners of the cut end second and third."""
    half = length / 2.0
    return turned([(-half, -base / 2.0), (half, -end / 2.0), (half, end / 2.0), (-half, base / 2.0)], degrees, centre)


def test_a_tapered_stroke_keeps_the_two_corners_of_its_cut_end():
    """The cut end of a stroke that narrows towards it (a brush stroke, a serif's arm): its sides cross 25-40 px
    beyond the end, far more than a pixel-truncated tip of that opening can lie (about 5 px), so the end is two
    corners. 21 strokes 8 px wide narrowing to 2.5-4 px at seven angles: both corners of the end within 1 px of a
    join on at least 17 (7 when the sides had to cross 50 end widths away), and at least 8 more than without the
    stroke-end step."""
    found = {True: 0, False: 0}
    for end in (2.5, 3.0, 4.0):
        for degrees in (20.0, 33.0, 45.0, 61.0, 75.0, 110.0, 160.0):
            vertices = taper(8.0, end, 40.0, degrees, (50.3, 50.1))
            mask = render(vertices, 100)
            for stroke_ends in found:
                result = sc.trace(mask, corner_params={"stroke_ends": stroke_ends})
                joins = np.vstack([spline.bezier()[:, 0] for spline in result.splines])
                found[stroke_ends] += max(np.hypot(*(joins - v).T).min() for v in vertices[1:3]) <= 1.0
    assert found[True] >= 17 and found[True] >= found[False] + 8, found
