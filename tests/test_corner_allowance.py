"""The corner zones' extra tolerance on a crack outline holds on one side only (docs/capture.md §12,
"Guarantee"): the side where the corner's true tip lies beyond the pixels, the paper beside a convex corner and
the ink beside a notch. A piece that cuts into the ink beside a convex corner gets ``epsilon`` there."""
from __future__ import annotations

import numpy as np
import pytest

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.fitting.lsq_model import OutlineRegression
from splinecraft.capture.fitting.options import LSQ_DEFAULTS

EPSILON = 0.5
ALLOWANCE = 1.0


def _crack_outline(mask):
    return max(trace_boundaries(mask), key=lambda b: b.outline.shape[0]).outline


def _corner_indices(points, corners):
    return np.sort([int(np.argmin(np.hypot(*(points - c).T))) for c in corners]).astype(np.int64)


def _rectangle_model():
    """The crack outline of a 30 x 20 block, its four corners, a converged fit (four straight pieces), every
    zone as wide as the outline and allowing ``ALLOWANCE``."""
    mask = np.zeros((40, 50), bool)
    mask[10:30, 10:40] = True
    points = _crack_outline(mask)
    corners = _corner_indices(points, [(10, 10), (40, 10), (40, 30), (10, 30)])
    model = OutlineRegression(points, corners, EPSILON, dict(LSQ_DEFAULTS))
    model.fit(hoschek_steps=2)
    tips = model.tips
    tips.zone_radius[:] = 100.0
    tips.allowance_kept[:] = True
    tips.allowance[:] = ALLOWANCE
    return model


def _top_side(bezier):
    """The index of the segment along the top side (y = 10) of the block."""
    return int(np.argmin(np.abs(bezier[:, :, 1] - 10.0).max(axis=1)))


def test_the_unbent_fit_passes():
    model = _rectangle_model()
    assert not (model.deviations(dense=True)["excess"] > 0).any()


@pytest.mark.parametrize("dense", [False, True])
@pytest.mark.parametrize("bend, fails", [(+1.2, True), (-1.2, False), (+0.5, False)])
def test_a_side_bent_into_the_ink_beside_a_convex_corner_gets_epsilon(bend, fails, dense):
    """The top side's inner control points moved by ``bend`` px (y down: + is into the ink below it): the side
    bulges by 3/4 of it, 0.9 px, between ``epsilon`` and ``epsilon + allowance``. Into the ink it fails the check,
    out into the paper it passes, as does a bulge of 0.375 px into the ink (within ``epsilon``)."""
    model = _rectangle_model()
    bezier = model.bezier().copy()
    top = _top_side(bezier)
    bezier[top, 1:3, 1] += bend
    model.bezier = lambda: bezier
    dev = model.deviations(dense=dense)
    assert bool((dev["excess"] > 0).any()) == fails
    starts, ends = dev["starts"], dev["ends"]
    assert (dev["excess"] > 0).sum() == (1 if fails else 0)
    if fails:
        assert np.flatnonzero(dev["excess"] > 0)[0] == top
        assert starts[top] < ends[top]


def test_a_polyline_that_is_no_crack_outline_keeps_the_allowance_on_both_sides():
    """The same block as a polygon of points on its pixel corners (no crack outline: the ink side is not known):
    the side bent into the ink stays within ``epsilon + allowance``."""
    mask = np.zeros((40, 50), bool)
    mask[10:30, 10:40] = True
    points = _crack_outline(mask) + 0.25  # no longer unit-crack midpoints
    corners = _corner_indices(points, [(10, 10), (40, 10), (40, 30), (10, 30)])
    model = OutlineRegression(points, corners, EPSILON, dict(LSQ_DEFAULTS))
    model.fit(hoschek_steps=2)
    model.tips.zone_radius[:] = 100.0
    model.tips.allowance_kept[:] = True
    model.tips.allowance[:] = ALLOWANCE
    bezier = model.bezier().copy()
    bezier[_top_side(bezier - 0.25), 1:3, 1] += 1.2
    model.bezier = lambda: bezier
    assert not (model.deviations(dense=True)["excess"] > 0).any()


def test_notch_corners_allow_the_ink_side_and_convex_corners_the_paper_side():
    """An L-shaped block: five convex corners and one notch. Per contour point the side of its nearest corner:
    +1 (paper) for the convex ones, -1 (ink) at the notch, the same for the probes of both checks."""
    mask = np.zeros((50, 50), bool)
    mask[10:40, 10:20] = True
    mask[30:40, 10:40] = True
    points = _crack_outline(mask)
    vertices = [(10, 10), (20, 10), (20, 30), (40, 30), (40, 40), (10, 40)]
    corners = _corner_indices(points, vertices)
    model = OutlineRegression(points, corners, EPSILON, dict(LSQ_DEFAULTS))
    contour = model.contour
    sides = model._side_tables
    point_side, probe_side = sides[False]
    at = contour.corner_bounds[:-1]
    found = {tuple(np.round(contour.closed_points[b]).astype(int)): point_side[b] for b in at}
    assert found == {(10, 10): 1.0, (20, 10): 1.0, (20, 30): -1.0, (40, 30): 1.0, (40, 40): 1.0, (10, 40): 1.0}
    np.testing.assert_array_equal(probe_side, point_side[:-1])
    np.testing.assert_array_equal(sides[True][1], np.repeat(point_side[:-1], 2))
