"""C1 joints of ``"lsq"`` (``joint_continuity=1``; docs/capture.md §12, "Joints of lsq"): smooth blobs and
discs rendered here at several sizes, fitted without corners, checked against their pixels and exact
outlines; a disc keeps four segments where C2 joints need more; the joints of the inserted knots are C1 or C2
(the default) as asked.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.fitting import fit_outline
from test_fitting import hausdorff as deviation  # the independent symmetric check of test_fitting


def blob_radius(angle, harmonics):
    """Radius factor ``1 + sum a_k cos(k angle + phase_k)`` of a star-shaped smooth blob."""
    factor = np.ones_like(angle)
    for k, (amplitude, phase) in enumerate(harmonics, start=2):
        factor += amplitude * np.cos(k * angle + phase)
    return factor


def render_blob(radius, harmonics, offset=(0.37, 0.21)):
    """Contour (crack outline) and dense exact outline of a blob of mean radius ``radius`` px: a pixel is ink
    when its centre lies inside (polar test, exact)."""
    size = int(np.ceil(2 * radius * (1 + sum(abs(a) for a, _ in harmonics)))) + 8
    centre = np.array([size / 2 + offset[0], size / 2 + offset[1]])
    yy, xx = np.mgrid[0:size, 0:size]
    dx, dy = xx + 0.5 - centre[0], yy + 0.5 - centre[1]
    mask = np.hypot(dx, dy) < radius * blob_radius(np.arctan2(dy, dx), harmonics)
    a = np.linspace(0, 2 * np.pi, int(40 * radius), endpoint=False)
    r = radius * blob_radius(a, harmonics)
    dense = centre + np.column_stack([r * np.cos(a), r * np.sin(a)])
    return trace_boundaries(mask)[0].outline, dense


harmonic = st.tuples(st.floats(-0.12, 0.12), st.floats(0.0, 2 * np.pi))


@settings(max_examples=6, deadline=None)
@given(st.lists(harmonic, min_size=1, max_size=3), st.floats(24.0, 40.0), st.sampled_from([1, 2, 4]))
def test_c1_fits_of_blobs_stay_within_epsilon_at_any_size(harmonics, radius, scale):
    """With C1 joints a smooth blob, drawn at 1x, 2x or 4x, is fitted within its epsilon of the pixels (the
    guarantee of docs/capture.md §12 holds for either continuity), re-measured here."""
    outline, _ = render_blob(radius * scale, harmonics)
    fit = fit_outline(outline, np.zeros(0, int), epsilon=0.8, joint_continuity=1)
    assert fit.converged
    assert deviation(fit.spline.bezier(), outline) <= 0.8 + 0.05


@pytest.mark.parametrize("radius", [40.0, 160.0])
def test_a_disc_takes_four_c1_segments_at_any_size(radius):
    """Four cubic pieces with C1 joints are within 0.03 % of a circle's radius (2.7e-4 r, the quarter-circle
    Bézier), far inside 0.8 px at r = 160 px: the C1 fit of a disc keeps its four segments. With C2 joints
    (the default) four pieces are 3 % off, so the C2 fit of a large disc needs more."""
    outline, dense = render_blob(radius, [])
    fit = fit_outline(outline, np.zeros(0, int), epsilon=0.8, joint_continuity=1)
    assert fit.converged and fit.spline.bezier().shape[0] == 4
    c2 = fit_outline(outline, np.zeros(0, int), epsilon=0.8, merge_tolerance=0.0)
    assert c2.converged and c2.spline.bezier().shape[0] > 4
    # within epsilon of the pixels and within about a pixel of the true circle
    assert deviation(fit.spline.bezier(), outline) <= 0.8 + 0.05
    assert deviation(fit.spline.bezier(), dense) <= 1.0


@pytest.mark.parametrize("continuity", [1, 2])
def test_inserted_knots_join_with_the_requested_continuity(continuity):
    """At every inserted knot the pieces share the point and the first derivative (in the knot parameter);
    with ``joint_continuity=2`` the second derivative too, with 1 it jumps somewhere. Of the fit before merging
    (``merge_tolerance=0``); the merged joints are G1 only (test_merge.assert_g1)."""
    outline, _ = render_blob(60.0, [(0.1, 0.3), (0.08, 1.9), (0.05, 4.0)])
    fit = fit_outline(outline, np.zeros(0, int), epsilon=0.5, joint_continuity=continuity, merge_tolerance=0.0)
    bez, knots = fit.spline.bezier(), fit.spline.knots
    h = np.diff(knots)
    nxt = np.roll(np.arange(bez.shape[0]), -1)
    scale = np.abs(bez).max()
    np.testing.assert_allclose(bez[:, 3], bez[nxt, 0], atol=1e-9 * scale)
    d_end = 3 * (bez[:, 3] - bez[:, 2]) / h[:, None]
    d_start = 3 * (bez[nxt, 1] - bez[nxt, 0]) / h[nxt, None]
    np.testing.assert_allclose(d_end, d_start, atol=1e-7 * scale)
    dd_end = 6 * (bez[:, 3] - 2 * bez[:, 2] + bez[:, 1]) / h[:, None] ** 2
    dd_start = 6 * (bez[nxt, 2] - 2 * bez[nxt, 1] + bez[nxt, 0]) / h[nxt, None] ** 2
    jump = np.hypot(*(dd_end - dd_start).T) / np.hypot(*dd_end.T).max()
    if continuity == 2:
        assert jump.max() < 1e-6
    else:
        assert jump.max() > 1e-3


def test_joint_continuity_is_checked():
    outline, _ = render_blob(20.0, [])
    for bad in (0, 3):
        with pytest.raises(ValueError, match="joint_continuity"):
            fit_outline(outline, np.zeros(0, int), joint_continuity=bad)
    with pytest.raises(TypeError, match="joint_continuity"):
        fit_outline(outline, np.zeros(0, int), joint_continuity=1.5)
