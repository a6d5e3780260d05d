"""The start of an ``"lsq"`` fit (docs/capture.md §12, "The lsq method"): the contour seen from its first
corner, the corners kept, their truncated pixel tips (weighting radius, angle, parameter gaps, straight-line
estimates) and the first knots placed by the contour's curvature.
"""
from __future__ import annotations

import numpy as np

from .._pixel_corners import outline_pixel_corners
from . import _kernels
from .tips import MAX_TIP_REACH, tip_estimates

__all__ = ["RotatedContour", "CornerTips", "thin_corners", "curvature_knots", "crack_normals"]

#: Curvature rates below this (1/px) count as straight in :func:`curvature_knots`: what is left of the pixel
#: staircase on long straight sides.
SEED_MIN_CURVATURE = 1.0 / 150.0


class RotatedContour:
    """A closed contour rotated to start at its first corner (so that no piece wraps past index 0).

    Attributes: ``size`` points (``points``; ``closed_points`` repeats the first at the end), ``arc`` (n + 1
    cumulative arc lengths), ``perimeter``, ``corner_count``, ``corner_bounds`` (rotated corner indices, then
    ``size``: piece ``k`` runs from ``corner_bounds[k]`` to ``corner_bounds[k + 1]``; without corners one
    piece ``0 .. size``), ``piece_of_point`` (n + 1), ``corner_distance`` (arc length to the nearest corner,
    n + 1), ``nearest_corner`` and ``pixel_corners``: the contour's
    :class:`~splinecraft.capture._pixel_corners.PixelCorners` (rotated), when the caller has found them
    (``pixel_corners``, of the contour as given), else ``None`` (:func:`~.tips.tip_estimates` finds them then);
    ``pinholes``: the centres ``(m, 2)`` of the pinholes filled near the contour (trace's), or ``None``
    (:func:`~.tips.tip_estimates`: a notch reaches a pinhole beyond its contour corner; ``pinhole_tips``, the
    corners whose tip it took from one).
    """

    def __init__(self, points, corners, pixel_corners=None, pinholes=None):
        n = points.shape[0]
        self.size = n
        self.corner_count = count = corners.shape[0]
        self.rotation = int(corners[0]) if count else 0
        self.pixel_corners = None if pixel_corners is None else pixel_corners.rotated(self.rotation, n)
        self.pinholes = pinholes
        #: the corners whose tip :func:`~.tips.tip_estimates` took from a pinhole (set there)
        self.pinhole_tips = np.zeros(0, dtype=np.int64)
        # numpy.roll(points, -rotation, axis=0), and the first point again at the end
        self.closed_points = np.concatenate([points[self.rotation:], points[: self.rotation + 1]])
        self.points = self.closed_points[:-1]
        self.corner_bounds = np.append((corners - self.rotation) % n, n) if count else np.array([0, n])
        self.piece_count = self.corner_bounds.shape[0] - 1
        # the edge table (geometry.edge_table), the arc lengths, and per point its piece and nearest corner (the
        # period end is corner 0) with the arc length to it, in one compiled pass
        self.edges, self.arc, self.piece_of_point, self.corner_distance, self.nearest_corner = \
            _kernels.contour_tables(self.closed_points, self.corner_bounds, count)
        self.perimeter = float(self.arc[-1])

    def point_at_arc(self, arc):
        """Points of the contour polyline at arc lengths ``arc`` (in ``[0, perimeter]``)."""
        arc = np.asarray(arc).reshape(-1)
        out = np.empty((arc.shape[0], 2))  # numpy.column_stack of the two interpolations, without its set-up
        out[:, 0] = np.interp(arc, self.arc, self.closed_points[:, 0])
        out[:, 1] = np.interp(arc, self.arc, self.closed_points[:, 1])
        return out

    def original_index(self, index):
        """Index into the caller's contour of a rotated index."""
        return (np.asarray(index) + self.rotation) % self.size


class CornerTips:
    """Per-corner state of the tip extrapolation (docs/capture.md §12, "Corners of lsq").

    ``radius``: current weighting radius (px of arc; 0 = the pieces follow the pixels); ``zone_radius``: the
    initial radius (the zone of ``epsilon + corner_allowance`` keeps its size); ``angle``: interior angle on the
    contour; ``allowance_kept``: the zone keeps its allowance although the corner follows the pixels;
    ``gap``: the angle-based parameter gap; ``gap_before``, ``gap_after``: the gaps used on both sides;
    ``estimate``: the extrapolated tip (NaN where there is none); ``allowance``: the extra tolerance in the
    corner's zone (``corner_allowance``, or the extrapolated tip's distance from the contour if larger). An
    outline without corners has one inert entry.
    """

    def __init__(self, radius, angle, gap, allowance=0.0):
        self.radius = radius
        self.base_allowance = float(allowance)
        self.allowance = np.full(radius.shape[0], self.base_allowance)
        self.angle = angle
        self.gap = gap
        self.zone_radius = radius.copy()
        self.allowance_kept = np.zeros(radius.shape[0], bool)
        self.gap_before, self.gap_after = gap.copy(), gap.copy()
        self.estimate = np.full((radius.shape[0], 2), np.nan)

    @classmethod
    def none(cls):
        tips = cls(np.zeros(1), np.full(1, np.pi), np.zeros(1))
        tips.gap_after = tips.gap_before
        return tips

    @classmethod
    def measure(cls, contour, corner_radius, tip_gap, geometric, allowance=0.0, measured=None):
        """Tips of the corners of ``contour``: radii by :func:`corner_radii`; a gap of
        ``tip_gap (1 / sin(theta / 2) - 1)`` px on each side (the pixel tip is truncated by about
        ``0.5 / sin(theta / 2) - 0.5`` px, and the pieces need that much parameter to reach the true corner),
        at most 3 px; with ``geometric`` the gaps of :meth:`geometric_gaps` where those apply (``measured``: the
        corners measured there, default all)."""
        if not contour.corner_count:
            return cls.none()
        radius, angle = corner_radii(contour, corner_radius)
        gap = np.clip(tip_gap * (1.0 / np.maximum(np.sin(0.5 * angle), 0.1) - 1.0), 0.0, 3.0)
        tips = cls(radius, angle, gap, allowance)
        if geometric:
            tips.geometric_gaps(contour, measured)
        return tips

    def geometric_gaps(self, contour, measured=None):
        """Extrapolated tips (:func:`~.tips.tip_estimates`): the two sides fitted beside the truncated tip and
        intersected. Where that gives a tip, it is remembered (``estimate``), the parameter gaps are set so
        that the parameter is the distance along the fitted sides (the pieces reach the tip without bending)
        and the corner's allowance becomes at least the tip's distance from the contour (the true tip of a
        rendering lies outside its crack outline, by at most :func:`~.tips.tip_reach`). Other corners keep
        the angle-based gaps."""
        estimate, start, anchors, outside = tip_estimates(contour, self.angle, self.radius, measured)
        found = np.flatnonzero(np.isfinite(estimate[:, 0]))
        if not found.size:
            return
        self.estimate[found] = estimate.take(found, axis=0)
        gaps = np.hypot(*(estimate[found, None, :] - anchors[found]).transpose(2, 0, 1)) - start[found, None]
        gaps = np.clip(gaps, 0.0, MAX_TIP_REACH)
        self.gap_before[found], self.gap_after[found] = gaps[:, 0], gaps[:, 1]
        self.allowance[found] = np.maximum(self.allowance[found], outside[found])

    def release(self, corner):
        """Halve the extrapolation radius of a corner (0 below 0.75 px: the pieces then follow the pixel tip).
        Returns True if the corner was still extrapolated."""
        if self.radius[corner] <= 0:
            return False
        self.radius[corner] = 0.5 * self.radius[corner] if self.radius[corner] >= 1.5 else 0.0
        if self.radius[corner] == 0.0:  # the pieces follow the pixels: no tip beyond them any more
            self.allowance[corner] = self.base_allowance
        return True


def corner_radii(contour, corner_radius):
    """Per corner: the arc length (px) over which the pixel data near the corner is truncated, about
    ``corner_radius / tan(theta / 2)`` for the interior angle ``theta`` measured on the contour (chords to
    the points ``min(6, 0.4 piece)`` px away on both sides), clipped to ``[1, 3 corner_radius]`` and to a fifth
    of either neighbouring piece (most of a short piece still carries weight). Returns (radius, theta) (one compiled
    pass, :func:`~._kernels.corner_radii`)."""
    return _kernels.corner_radii(contour.arc, contour.closed_points, contour.corner_bounds, corner_radius)


def thin_corners(points, corners, min_gap, pixel_corners=None):
    """Drop corners fewer than ``min_gap`` contour steps after another one (a piece needs a few points to be
    fitted); of two such corners the one where the contour turns more (chords to the points 3 steps away)
    is kept. Two pixel corners stay (the ends of a stroke 1-2 px wide, docs/capture.md §11 step 9: their piece
    is pinned to its chord, :meth:`~.lsq_model.OutlineRegression._pins`); ``pixel_corners`` is the contour's
    :class:`~splinecraft.capture._pixel_corners.PixelCorners` where the caller has them (else they are found
    here, only when two corners are that close)."""
    n = points.shape[0]
    if corners.shape[0] < 2 or not np.any(np.diff(np.append(corners, corners[0] + n)) < min_gap):
        return corners
    a, b = points[corners] - points[(corners - 3) % n], points[(corners + 3) % n] - points[corners]
    cos = (a * b).sum(1) / np.maximum(np.hypot(*a.T) * np.hypot(*b.T), 1e-300)
    turn = np.arccos(np.clip(cos, -1.0, 1.0))
    if pixel_corners is None:
        pixel_corners = outline_pixel_corners(points)
    pixel = np.isin(corners, pixel_corners.index)
    keep = list(range(corners.shape[0]))
    changed = True
    while changed and len(keep) > 1:
        changed = False
        for pos in range(len(keep)):
            i, j = keep[pos], keep[(pos + 1) % len(keep)]
            if i != j and (corners[j] - corners[i]) % n < min_gap and not (pixel[i] and pixel[j]):
                keep.remove(i if turn[i] < turn[j] else j)
                changed = True
                break
    return corners[np.sort(keep)]


def _smoothed_curvature(contour):
    """Curvature rate per contour point: the turn of the chord directions (chords over +-4 contour steps)
    between +-4 steps, per arc length, averaged over +-8 steps (the staircase of a straight side turns both
    ways); rates below :data:`SEED_MIN_CURVATURE` count as straight (compiled, :func:`~._kernels.seed_knots`;
    callers have n >= 16 points)."""
    return _seed_knots(contour, 1.0, 1.0, 1, 0)


def _seed_knots(contour, density, epsilon, min_gap, stage, seeds=_kernels._NO_INTS):
    n = contour.size
    return _kernels.seed_knots(contour.points, contour.arc, contour.perimeter, contour.corner_distance[:n],
                               contour.corner_count > 0, contour.corner_bounds, seeds, density, epsilon, min_gap,
                               SEED_MIN_CURVATURE, stage)


def knot_density_integral(contour, density, epsilon):
    """The integral of :func:`curvature_knots`' knot density ``(density kappa^3 / epsilon)^(1/4)`` along the contour
    up to each point (``n + 1`` values, from 0), ``kappa`` the :func:`_smoothed_curvature`, 0 within 6 px of a
    corner."""
    return _seed_knots(contour, density, epsilon, 1, 1)


def curvature_knots(contour, simple_knots, density, epsilon, min_gap):
    """Initial simple knots from the contour's curvature, before any insertion round, or None to keep
    ``simple_knots``.

    The error of a cubic spline on a knot interval of length ``h`` is about ``c h^4 |S^(4)|``, and on an arc
    of curvature ``kappa`` (arc-length parameter) ``|S^(4)|`` is about ``kappa^3``: an interval meets the
    tolerance when ``h <= (epsilon / (c kappa^3))^(1/4)``. The knots are placed where the integral of the
    knot density ``lambda = (density kappa^3 / epsilon)^(1/4)`` along each piece crosses a multiple of its
    total over ``floor(total) + 1`` (equidistributed error, de Boor's knot placement), at most one per
    contour step; ``kappa`` is :func:`_smoothed_curvature`, and contour points within 6 px of a corner are
    left out (the corner's pieces end there). ``density = 0`` keeps the corners as the only knots (four
    equally spaced knots on an outline without corners). The knots at least ``min_gap`` steps from the ends of
    their piece and after the knot before them, with ``simple_knots`` (the seam knot 0 without corners); one
    compiled pass from the contour to the knots (:func:`~._kernels.seed_knots`)."""
    if density <= 0 or contour.size < 16:
        return None
    merged = _seed_knots(contour, density, epsilon, min_gap, 2,
                         simple_knots if contour.corner_count else np.zeros(1, dtype=np.int64))
    if contour.corner_count or merged.shape[0] >= 4:  # a periodic spline needs four knots
        return merged
    return None


def crack_normals(points):
    """Per point of a crack outline (midpoints of unit pixel edges, pixel corners on integers), the unit normal
    of its crack: ``(1, 0)`` for a vertical crack (integer x, half-integer y), ``(0, 1)`` for a horizontal one;
    the pixel centres on both sides lie half a pixel along it. None when not every point is such a midpoint (a
    polyline that is not a crack outline gets no pixel check; compiled, :func:`~._kernels.crack_normals`)."""
    return _kernels.crack_normals(points)
