"""The initial knots of ``"lsq"`` (``fitting.lsq_setup.curvature_knots``, compiled: ``_kernels.seed_knots``) are
those of the loop over the pieces that the vectorized form replaced, index for index, the knot density's integral
(``knot_density_integral``) is numpy's, and the curvature they follow (``_smoothed_curvature``) is the one read
through rolled indices, bit for bit (all kept here as the reference)."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecraft.capture.fitting import lsq_setup
from splinecraft.capture.fitting.lsq_setup import RotatedContour, _smoothed_curvature, curvature_knots, \
    knot_density_integral


def reference_smoothed_curvature(contour):
    n, points, arc, perimeter = contour.size, contour.points, contour.arc, contour.perimeter
    a = 4
    idx = np.arange(n)
    ahead_idx, behind_idx = np.roll(idx, -a), np.roll(idx, a)
    chord = points[ahead_idx] - points[behind_idx]
    phi = np.arctan2(chord[:, 1], chord[:, 0])
    turn = phi[ahead_idx] - phi[behind_idx]
    turn = (turn + np.pi) % (2.0 * np.pi) - np.pi
    ahead = np.where(idx + a < n, arc[np.minimum(idx + a, n)], perimeter + arc[ahead_idx])
    behind = np.where(idx - a >= 0, arc[np.maximum(idx - a, 0)], arc[behind_idx] - perimeter)
    kappa = turn / np.maximum(ahead - behind, 1e-9)
    width = 8
    padded = np.concatenate([kappa[-width:], kappa, kappa[:width]])
    box = np.concatenate([[0.0], np.cumsum(padded)])
    kappa = np.abs(box[2 * width + 1:] - box[: -2 * width - 1]) / (2 * width + 1)
    kappa[kappa < lsq_setup.SEED_MIN_CURVATURE] = 0.0
    return kappa


def reference_knot_density_integral(contour, density, epsilon):
    n = contour.size
    kappa = reference_smoothed_curvature(contour)
    bent = kappa != 0.0
    if contour.corner_count:
        bent &= ~(contour.corner_distance[:n] < 6.0)
    lam = np.zeros(n)
    lam[bent] = (density * kappa[bent] ** 3 / epsilon) ** 0.25
    return np.concatenate([[0.0], np.cumsum(lam * np.diff(contour.arc))])


def reference_curvature_knots(contour, simple_knots, density, epsilon, min_gap):
    if density <= 0 or contour.size < 16:
        return None
    cum = reference_knot_density_integral(contour, density, epsilon)
    new = [simple_knots if contour.corner_count else np.zeros(1, dtype=np.int64)]
    bounds = contour.corner_bounds
    for first, last in zip(bounds[:-1], bounds[1:]):
        total = cum[last] - cum[first]
        count = min(int(np.floor(total)), int(last - first))
        if count < 1:
            continue
        targets = cum[first] + total * np.arange(1, count + 1) / (count + 1)
        j = np.searchsorted(cum[first:last + 1], targets) + first
        new.append(j[(j - first >= min_gap) & (last - j >= min_gap)])
    merged = np.unique(np.concatenate(new)).astype(np.int64)
    merged = merged[np.diff(merged, prepend=-min_gap) >= min_gap]
    if contour.corner_count or merged.shape[0] >= 4:
        return merged
    return None


def _outline(rng, n):
    """A closed outline of about ``n`` points: a wobbly ellipse with straight runs (curvature 0) in it."""
    angle = np.sort(rng.random(n)) * 2.0 * np.pi
    radius = 40.0 + 6.0 * np.sin(rng.integers(2, 6) * angle) * (rng.random(n) < 0.7)
    return np.round(np.column_stack([radius * np.cos(angle), 0.6 * radius * np.sin(angle)]) * 2.0) / 2.0


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(16, 400), corners=st.integers(0, 9),
       density=st.sampled_from([0.0, 0.05, 1.0, 40.0]), epsilon=st.sampled_from([0.3, 0.8, 2.0]),
       min_gap=st.integers(1, 6))
def test_curvature_knots_are_the_loop_over_the_pieces(seed, n, corners, density, epsilon, min_gap):
    rng = np.random.default_rng(seed)
    points = _outline(rng, n)
    points = points[np.concatenate([[True], np.any(points[1:] != points[:-1], axis=1)])]
    if points.shape[0] < 4:
        return
    chosen = np.unique(rng.integers(0, points.shape[0], corners)).astype(np.int64)
    contour = RotatedContour(points, chosen)
    simple = np.zeros(0, dtype=np.int64)
    got = curvature_knots(contour, simple, density, epsilon, min_gap)
    expected = reference_curvature_knots(contour, simple, density, epsilon, min_gap)
    if points.shape[0] >= 16:
        assert _smoothed_curvature(contour).tobytes() == reference_smoothed_curvature(contour).tobytes()
        assert knot_density_integral(contour, density, epsilon).tobytes() == \
            reference_knot_density_integral(contour, density, epsilon).tobytes()
    assert (got is None) == (expected is None)
    if got is not None:
        assert np.array_equal(got, expected)
