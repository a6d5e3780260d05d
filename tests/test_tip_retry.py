"""Extrapolated tips of notches between a straight side and a curved one, and when lsq releases them (docs/capture.md
§12, "Corners of lsq").

Where the crossing of a corner's long side windows fails the bounds or the pixel tests (a side that curves within
its 48 px window), both sides are fitted again on windows halved from the start; a side that is no digital
straight segment there is fitted by its parabola, as on the long window, and the crossing is kept if it passes the
same tests. A corner whose tip is kept is released as a hook (its fitted point too far from the contour corner)
only on a fit where both pieces beside it fit: on the coarse first fits, with the seed knots, a piece that misses
its pixels by several pixels moves its corner point as far, and that says nothing about the tip.

Shapes: a band (a stem) with a disc (a bowl) crossing one of its sides, rendered by pixel centres in the test.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.corners import tangent_jump
from splinecraft.capture.fitting.lsq_model import OutlineRegression
from splinecraft.capture.fitting.options import LSQ_DEFAULTS
from splinecraft.capture.trace import trace

STEM = 40.0


def stem_and_bowl(radius, opening, rotation, offset):
    """A stem ``STEM`` px wide along ``rotation`` with a disc of ``radius`` crossing its side at ``opening``
    degrees (the notches between the side and the circle): the mask (pixel centres inside) and the two notch
    tips."""
    theta = math.radians(opening)
    size = int(STEM + 2 * radius + 60)
    origin = np.array([30.0 + offset[0], size / 2 + offset[1]])
    along = np.array([math.cos(rotation), math.sin(rotation)])
    across = np.array([-along[1], along[0]])
    rows, cols = np.mgrid[:size, :size]
    p = np.stack([cols + 0.5, rows + 0.5], axis=-1) - origin
    s, t = p @ along, p @ across
    stem = (s >= 0) & (s <= STEM) & (np.abs(t) <= size / 2 - 12)
    bowl = (s - STEM - radius * math.cos(theta)) ** 2 + t ** 2 <= radius * radius
    rise = radius * math.sin(theta)
    tips = np.array([origin + along * STEM + across * rise, origin + along * STEM - across * rise])
    return stem | bowl, tips


# (radius, opening, rotation, offset, which tip): notches whose long windows' crossing fails; before the halved
# windows took parabolas, these tips were clipped at the pixels, 0.89-1.24 px off
CURVED_NOTCHES = [(22.569, 32.104, 1.2586, (0.5822, 0.0941), 1), (37.555, 39.139, 1.2147, (0.0303, 0.707), 1),
                  (31.079, 27.547, 0.304, (0.2139, 0.8586), 1), (31.696, 46.2, 0.1384, (0.169, 0.5126), 1)]


@pytest.mark.parametrize("radius, opening, rotation, offset, which", CURVED_NOTCHES)
def test_a_notch_between_a_stem_and_a_bowl_is_extrapolated_on_halved_windows(radius, opening, rotation, offset,
                                                                             which):
    mask, tips = stem_and_bowl(radius, opening, rotation, offset)
    result = trace(mask)
    knots = np.concatenate([np.asarray(spline.knot_points) for spline in result.splines])
    assert np.hypot(*(knots - tips[which]).T).min() <= 0.5


def test_a_kept_tip_is_released_as_a_hook_only_where_the_pieces_beside_it_fit():
    """The displacement test of ``hooked_corners``: with every fitted point moved 3 px off (the curve shifted), a
    corner without a tip is released whatever its pieces do; a corner with a kept tip only where the deviations
    say both pieces beside it fit."""
    mask, _ = stem_and_bowl(*CURVED_NOTCHES[1][:4])
    boundary = max(trace_boundaries(mask), key=lambda b: len(b.outline))
    points = np.asarray(boundary.outline, float)
    model = OutlineRegression(points, np.asarray(tangent_jump(points), np.int64), 0.8, dict(LSQ_DEFAULTS))
    model.seed_knots(LSQ_DEFAULTS["initial_density"])
    model.fit()
    tipped = np.isfinite(model.tips.estimate[:, 0]) & (model.tips.radius > 0)
    untipped = ~np.isfinite(model.tips.estimate[:, 0]) & (model.tips.radius > 0)
    assert tipped.any() and untipped.any()
    model._bezier = model._bezier + np.array([3.0, 0.0])  # every fitted point 3 px off: all hooked
    model._hook_limit = None
    dev = model.deviations()
    pieces = model.contour.piece_count
    failing = dict(dev, piece_excess=np.ones(pieces))
    fitting = dict(dev, piece_excess=-np.ones(pieces))
    np.testing.assert_array_equal(model.hooked_corners(failing), np.flatnonzero(untipped))
    np.testing.assert_array_equal(model.hooked_corners(fitting), np.flatnonzero(tipped | untipped))
