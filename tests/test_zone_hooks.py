"""Hooks of lsq's corners inside their weighting radius (docs/capture.md §12, "Corners of lsq").

On a crack outline every crack separates an ink and a paper pixel centre 1 px apart, and the true outline
crosses the segment between them, near a truncated corner tip as anywhere else. A corner that is still
extrapolated after the fit (weighting radius > 0) must therefore have pieces that cross the segment of every
crack within that radius (to ``pixel_slack``, 0.1 px): pieces that pass beside it bend away from the pixels
where the corner's weights let them, a hook (``OutlineRegression.zone_hooks``). Shapes: thick ring sectors
whose ends are cut obliquely (obtuse corners between a straight cut and a curved side, as the terminals of an
S or a C), rendered by pixel centres at random sizes, positions and rotations, traced without segment merging
(merging moves the curve by up to ``merge_tolerance`` after the fit).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.corners import tangent_jump
from splinecraft.capture.fitting.lsq_model import ZONE_SPACING, OutlineRegression
from splinecraft.capture.fitting.lsq_setup import crack_normals
from splinecraft.capture.fitting.options import LSQ_DEFAULTS
from splinecraft.capture.trace import trace
from test_tips import render  # pixel-centre rendering of a polygon, the tips' tests' own

SIZE = 120
PIXEL_SLACK = 0.1


def cut_ring_sector(rng):
    """A ring sector (mid radius 30-45 px, 10-18 px wide, spanning 1.5-2.5 rad) whose two ends are cut
    obliquely (each end's one side moved along the ring by 0.3-0.6 of the width)."""
    radius, width = rng.uniform(30, 45), rng.uniform(10, 18)
    centre = np.full(2, SIZE / 2) + rng.uniform(-0.5, 0.5, 2)
    start, span = rng.uniform(0, 2 * math.pi), rng.uniform(1.5, 2.5)
    t = np.linspace(start, start + span, 80)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    outer, inner = centre + (radius + width / 2) * ring, centre + (radius - width / 2) * ring
    skew = rng.uniform(0.3, 0.6) * width
    outer[0] -= skew * np.array([-math.sin(start), math.cos(start)])
    inner[-1] += skew * np.array([-math.sin(start + span), math.cos(start + span)])
    return np.vstack([outer, inner[::-1]])


def _shapes(count=12, seed=1):
    rng = np.random.default_rng(seed)
    return [cut_ring_sector(rng) for _ in range(count)]


SHAPES = _shapes()


def zone_gaps(result):
    """Per extrapolated corner of every converged fit: the largest distance from the fitted curve to the
    ink-paper segment of a crack within the corner's weighting radius (at least 1 px of arc)."""
    gaps = []
    for fit, boundary in zip(result.fits, result.boundaries):
        if not fit.converged or not len(fit.corners_used):
            continue
        points = np.asarray(boundary.outline, float)
        n = points.shape[0]
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(np.vstack([points, points[:1]]), axis=0).T))])
        bezier = np.asarray(fit.spline.bezier())
        u = np.linspace(0.0, 1.0, 600)[:, None, None]
        curve = ((1 - u) ** 3 * bezier[:, 0] + 3 * (1 - u) ** 2 * u * bezier[:, 1]
                 + 3 * (1 - u) * u ** 2 * bezier[:, 2] + u ** 3 * bezier[:, 3]).reshape(-1, 2)
        for corner, radius in zip(fit.corners_used, fit.info["corner_radii"]):
            if radius <= 0:
                continue
            distance = np.abs(arc[:n] - arc[corner])
            distance = np.minimum(distance, arc[-1] - distance)
            worst = 0.0
            for j in np.flatnonzero(distance < max(radius, 1.0)):
                point = points[j]
                vertical = abs(point[0] - round(point[0])) < 1e-9  # a vertical crack: integer x
                normal = np.array([1.0, 0.0]) if vertical else np.array([0.0, 1.0])
                d = curve - (point - 0.5 * normal)
                t = np.clip(d @ normal, 0.0, 1.0)
                worst = max(worst, float(np.hypot(*(d - t[:, None] * normal).T).min()))
            gaps.append(worst)
    return gaps


@pytest.mark.parametrize("index", range(len(SHAPES)))
def test_an_extrapolated_corner_crosses_every_crack_within_its_radius(index):
    mask = render(SHAPES[index], SIZE)
    result = trace(mask, fit_params={"merge_tolerance": 0.0})
    gaps = zone_gaps(result)
    # the pieces beside these corners fit (converged), so a corner whose pieces pass beside a crack was released
    assert max(gaps, default=0.0) <= PIXEL_SLACK + 1e-6, gaps


def reference_corner_gaps(model, exclude=()):
    """Per corner, the largest over the contour points within its reach (``max(r, 1)`` px of arc, corners still
    extrapolated and not in ``exclude``) of the least distance from the curve samples of its window to the
    segment between the point's two pixel centres, by the general projection onto the crack normal
    (``-inf`` where no point is tested): the formulation ``zone_hooks`` computes without the normal's zero
    products."""
    contour, tips = model.contour, model.tips
    worst = np.full(contour.corner_count, -np.inf)
    cracks = crack_normals(contour.points)
    active = tips.radius > 0
    active[np.asarray(exclude, dtype=np.int64)] = False
    n = contour.size
    reach = np.maximum(tips.radius, 1.0)
    nearest = contour.nearest_corner[:n]
    points = np.flatnonzero(active[nearest] & (contour.corner_distance[:n] < reach[nearest]))
    if not points.size:
        return worst
    corners = np.unique(nearest[points])
    row = np.full(contour.corner_count, -1)
    row[corners] = np.arange(corners.shape[0])
    at = model.base_parameter[contour.corner_bounds[corners]]
    half = reach[corners] + np.maximum(tips.gap_before[corners], tips.gap_after[corners]) + 2.0
    count = int(np.ceil(2.0 * half.max() / ZONE_SPACING)) + 1
    u = np.mod(at[:, None] + half[:, None] * np.linspace(-1.0, 1.0, count)[None, :], model.period)
    samples = model.curve_at(u.ravel()).reshape(corners.shape[0], count, 2)
    normal = cracks[points]
    d = samples[row[nearest[points]]] - (contour.points[points] - 0.5 * normal)[:, None, :]
    t = np.clip(np.einsum("pkd,pd->pk", d, normal), 0.0, 1.0)
    gap = np.hypot(*(d - t[:, :, None] * normal[:, None, :]).transpose(2, 0, 1)).min(axis=1)
    np.maximum.at(worst, nearest[points], gap)
    return worst


def fitted_model(index):
    """The first fit of the largest boundary of shape ``index`` (seed knots, default options) and deviations in
    which both pieces beside every corner fit."""
    mask = render(SHAPES[index], SIZE)
    boundary = max(trace_boundaries(mask), key=lambda b: len(b.outline))
    points = np.asarray(boundary.outline, float)
    model = OutlineRegression(points, np.asarray(tangent_jump(points), np.int64), 0.8, dict(LSQ_DEFAULTS))
    model.seed_knots(LSQ_DEFAULTS["initial_density"])
    model.fit()
    return model, {"piece_excess": -np.ones(model.contour.piece_count)}


@pytest.mark.parametrize("index", range(4))
def test_zone_hooks_measure_the_gaps_of_the_general_projection_bit_for_bit(index):
    """``zone_hooks`` projects onto the axis of each crack normal directly ((1, 0) or (0, 1): no zero products):
    a corner is found exactly where the general projection's largest gap exceeds ``pixel_slack`` -- at a slack
    equal to that gap it is not, one ulp below it it is -- on fitted curves moved off their pixels in several
    directions (both pieces beside every corner taken to fit), with and without excluded corners."""
    model, fitting = fitted_model(index)
    fitted, checked = model._bezier.copy(), 0
    for shift in ([0.0, 0.0], [0.3, -0.2], [-0.45, 0.15], [0.05, 0.6]):
        model._bezier = fitted + np.array(shift)
        for exclude in ((), np.array([0])):
            worst = reference_corner_gaps(model, exclude)
            for corner in np.flatnonzero(np.isfinite(worst)):
                model.pixel_slack = worst[corner]
                assert corner not in model.zone_hooks(fitting, exclude)
                model.pixel_slack = np.nextafter(worst[corner], -np.inf)
                assert corner in model.zone_hooks(fitting, exclude)
                checked += 1
    assert checked >= 8


@pytest.mark.parametrize("index", range(2))
def test_zone_hooks_pass_a_corner_whose_window_has_a_nan_sample(index):
    """The compiled zone test stops each point at its first sample within the slack; a corner whose window holds
    a NaN sample (a fit gone wrong) is not found, as the least-gap formulation leaves it (its gaps' minimum is
    NaN, and NaN does not exceed the slack), while the other corners are found as before."""
    model, fitting = fitted_model(index)
    model.pixel_slack = -1.0  # every tested corner's gaps exceed it
    tested = np.flatnonzero(np.isfinite(reference_corner_gaps(model)))
    assert tested.size >= 2
    np.testing.assert_array_equal(model.zone_hooks(fitting), tested)
    corner = int(tested[0])
    starts, _ = model.intervals()
    at = model.base_parameter[model.contour.corner_bounds[corner]]
    model._bezier = model._bezier.copy()
    model._bezier[int(np.searchsorted(starts, at, side="right")) - 1, 1] = np.nan  # the piece after the corner
    with np.errstate(invalid="ignore"):  # the reference's maximum of a NaN gap
        worst = reference_corner_gaps(model)
    assert np.isnan(worst[corner])
    np.testing.assert_array_equal(model.zone_hooks(fitting), np.flatnonzero(worst > model.pixel_slack))
    assert corner not in model.zone_hooks(fitting)
