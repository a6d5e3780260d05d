"""Extrapolated corner tips (docs/capture.md §12, "Corners of lsq"): the two sides that meet at a corner,
fitted by least squares beside the truncated pixel tip and extended to their intersection.

A rendering cuts an acute tip off: where a wedge of opening ``theta`` is narrower than about a pixel no pixel
centre is inside it, so the crack outline stops up to ``sqrt(1/2) / sin(theta / 2)`` px short of the true tip
(the point where the two sides, moved inwards by the half-diagonal of a pixel, meet). The sides themselves are
well measured away from the tip: a least-squares line through a few dozen pixels of staircase has an offset
error of a few hundredths of a pixel (except for sides within a few degrees of an axis, whose offset no
binary rendering resolves better than half a pixel). :func:`side_fit` fits each side, :func:`tip_estimates`
intersects them.
"""
from __future__ import annotations

import numpy as np

from .geometry import polyline_distance

__all__ = ["tip_reach", "side_fit", "tip_estimates", "SideFit"]

#: Residual (px) up to which a window of the contour counts as one line (or one parabola): the staircase of a
#: straight side stays within half a pixel diagonal of its line.
STRAIGHT_RESIDUAL = 0.8
#: Longest side window (px of arc) and the shortest that still gives a direction.
LONGEST_SIDE = 48.0
SHORTEST_SIDE = 4.0
#: A sharp tip of interior angle ``theta`` lies at most ``SHARP_TRUNCATION / sin(theta / 2)`` px outside the
#: crack outline of its rendering (half a pixel diagonal, where the sides moved inwards by it meet); the sides
#: of a corner rounded by a fillet of radius ``rho`` cross ``rho (1 / sin(theta / 2) - 1)`` px outside it, so
#: the rule keeps the tips of fillets below ``SHARP_TRUNCATION / (1 - sin(theta / 2))`` px (2.4 px at 90
#: degrees: there the crossing is within 1 px of the fillet) and drops the rest.
SHARP_TRUNCATION = np.sqrt(0.5)
#: Only corners sharper than this (radians) are extrapolated: at 90 degrees and more a sharp tip lies at most
#: ``sqrt(1/2) / sin(45 deg)`` = 1 px outside its pixels, within the tolerance of a fit that follows them
#: (``epsilon + corner_allowance``), while their sides are often axis-aligned or flattened, where the crossing
#: is least certain.
MAX_EXTRAPOLATED_ANGLE = np.radians(90.0)
#: Farthest an extrapolated tip may lie from its contour corner (px): the bound that keeps nearly parallel
#: sides (or misread ones) from shooting the corner off.
MAX_TIP_REACH = 5.0
#: An extrapolated tip lies at most this fraction of the shorter side window from its contour corner (short
#: sides, as on ragged or noisy outlines, do not carry a tip far).
REACH_PER_SIDE = 0.25
#: How far (px) an extrapolated tip may lie behind its contour corner (towards the pieces): the crack outline
#: goes round whole pixels, so it can pass a tip by up to half a pixel diagonal.
BEHIND = 1.0
#: Sides that meet at less than this angle (radians, between their directions) give no reliable intersection.
MIN_CROSSING = np.radians(8.0)


def tip_reach(angle):
    """How far (px) the true tip of an interior angle ``angle`` (radians) can lie beyond the crack outline of a
    rendering: ``sqrt(1/2) / sin(angle / 2)`` plus half a pixel for where the detector put the contour corner,
    at most :data:`MAX_TIP_REACH`."""
    return np.minimum(np.sqrt(0.5) / np.maximum(np.sin(0.5 * np.asarray(angle, float)), 1e-6) + 0.5,
                      MAX_TIP_REACH)


class SideFit:
    """A side beside a corner: total-least-squares line (``centre``, unit ``direction``, ``normal``) and, on a
    curved side, a parabola ``y = c0 + c1 t + c2 t^2`` in that line's frame (``coefficients``; zeros on a
    straight side); ``length``: the window's arc length (px)."""

    def __init__(self, centre, direction, coefficients, length):
        self.centre, self.direction, self.length = centre, direction, length
        self.normal = np.array([-direction[1], direction[0]])
        self.coefficients = coefficients

    def point(self, t):
        c0, c1, c2 = self.coefficients
        return self.centre + t * self.direction + (c0 + t * (c1 + t * c2)) * self.normal

    def tangent(self, t):
        return self.direction + (self.coefficients[1] + 2.0 * self.coefficients[2] * t) * self.normal

    def local(self, point):
        return float((point - self.centre) @ self.direction)


def _window_fit(points, length):
    """Line, then parabola, through ``points`` (``length`` px of arc); the first whose residuals stay within
    :data:`STRAIGHT_RESIDUAL`, or None."""
    centre = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - centre, full_matrices=False)
    direction = vt[0]
    normal = np.array([-direction[1], direction[0]])
    t, y = (points - centre) @ direction, (points - centre) @ normal
    if np.abs(y).max() <= STRAIGHT_RESIDUAL:
        return SideFit(centre, direction, np.zeros(3), length)
    design = np.column_stack([np.ones_like(t), t, t * t])
    coefficients = np.linalg.lstsq(design, y, rcond=None)[0]
    if np.abs(y - design @ coefficients).max() <= STRAIGHT_RESIDUAL:
        return SideFit(centre, direction, coefficients, length)
    return None


def side_fit(contour, corner_arc, sign, start, stop):
    """The side of a corner at arc length ``corner_arc`` towards ``sign`` (+1 forwards, -1 backwards): the
    contour polyline sampled every 0.5 px from ``start`` to ``stop`` px of arc away, fitted by
    :func:`_window_fit`; where neither a line nor a parabola fits, the window shrinks from its far end (by a
    quarter at a time) down to :data:`SHORTEST_SIDE`. Returns a :class:`SideFit` or None."""
    while stop - start >= SHORTEST_SIDE:
        offsets = np.arange(start, stop + 1e-9, 0.5)
        fit = _window_fit(contour.point_at_arc((corner_arc + sign * offsets) % contour.perimeter), stop - start)
        if fit is not None:
            return fit
        stop = start + 0.75 * (stop - start)
    return None


def _crossing(first, second):
    """Intersection of two :class:`SideFit`: the lines' crossing, refined by Newton steps on the parabolas.
    None for sides meeting at less than :data:`MIN_CROSSING`."""
    d1, d2 = first.direction, second.direction
    cross = d1[0] * d2[1] - d1[1] * d2[0]
    if abs(cross) < np.sin(MIN_CROSSING):
        return None
    delta = second.centre - first.centre
    point = first.centre + (delta[0] * d2[1] - delta[1] * d2[0]) / cross * d1
    if not (first.coefficients.any() or second.coefficients.any()):
        return point
    t = np.array([first.local(point), second.local(point)])
    for _ in range(8):
        jacobian = np.column_stack([first.tangent(t[0]), -second.tangent(t[1])])
        if abs(np.linalg.det(jacobian)) < 1e-9:
            return None
        step = np.linalg.solve(jacobian, second.point(t[1]) - first.point(t[0]))
        t += step
        if np.abs(step).max() < 1e-9:
            break
    return first.point(t[0])


def tip_estimates(contour, angle, radius):
    """Per corner of ``contour`` (a :class:`~.lsq_setup.RotatedContour` with corners), the extrapolated tip:
    both sides fitted by :func:`side_fit` from ``max(radius, min(6, 1 / tan(angle / 2)))`` px of arc (where
    a wedge of that opening is about two pixels wide) to 0.8 of the side (at most :data:`LONGEST_SIDE` px
    further), intersected by :func:`_crossing`. Kept when the intersection lies within :func:`tip_reach` of
    the contour corner (and within :data:`REACH_PER_SIDE` of the shorter window), no farther outside the
    contour than a sharp tip can be (:data:`SHARP_TRUNCATION`) and not more than :data:`BEHIND` behind it
    (along the bisector of the sides).

    Returns ``(estimate, start, anchors)``: estimate (k, 2), NaN where there is none; the window start per
    corner; the contour points at the window starts (k, 2, 2: before, after)."""
    arc, perimeter = contour.arc, contour.perimeter
    lengths = np.diff(arc[contour.corner_bounds])
    before_len, after_len = np.roll(lengths, 1), lengths
    count = contour.corner_count
    start = np.maximum(radius, np.clip(1.0 / np.maximum(np.tan(0.5 * angle), 1e-6), 1.0, 6.0))
    reach = tip_reach(angle)
    estimate = np.full((count, 2), np.nan)
    anchors = np.full((count, 2, 2), np.nan)
    for c in range(count):
        corner_arc = arc[contour.corner_bounds[c]]
        sides = []
        for sign, side_len in ((-1, before_len[c]), (1, after_len[c])):
            stop = min(start[c] + LONGEST_SIDE, 0.8 * side_len)
            sides.append(side_fit(contour, corner_arc, sign, start[c], stop))
        if sides[0] is None or sides[1] is None:
            continue
        windows = [side.length for side in sides]
        point = _crossing(*sides)
        corner_point = contour.points[contour.corner_bounds[c] % contour.size]
        ends = contour.point_at_arc((corner_arc + np.array([-start[c], start[c]])) % perimeter)
        if point is None or not np.isfinite(point).all() or \
                np.hypot(*(point - corner_point)) > min(reach[c], REACH_PER_SIDE * min(windows)):
            continue
        outward = corner_point - 0.5 * (ends[0] + ends[1])  # along the bisector, away from the pieces
        if outward @ (point - corner_point) < -BEHIND * np.hypot(*outward):
            continue
        estimate[c], anchors[c] = point, ends
    # a sharp tip lies at most sqrt(1/2) / sin(theta / 2) outside the pixels; one farther out is the crossing of
    # the sides of a rounded (or flattened) corner, which the pixels follow better than the crossing does
    estimate[angle >= MAX_EXTRAPOLATED_ANGLE] = np.nan
    found = np.flatnonzero(np.isfinite(estimate[:, 0]))
    if found.size:
        outside = polyline_distance(estimate[found], contour.points, closed=True)
        rounded = found[outside * np.sin(0.5 * angle[found]) > SHARP_TRUNCATION]
        estimate[rounded], anchors[rounded] = np.nan, np.nan
    return estimate, start, anchors
