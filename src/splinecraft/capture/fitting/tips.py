"""Extrapolated corner tips (docs/capture.md §12, "Corners of lsq"; ``geometric_corners``, by default on clean
boundaries, :func:`~.options.extrapolates_tips`): the
two sides that meet at a corner, measured beside the truncated pixel tip and extended to their intersection.

A rendering cuts an acute tip off: where a wedge of opening ``theta`` is narrower than about a pixel no pixel
centre is inside it, so the crack outline stops up to ``sqrt(1/2) / sin(theta / 2)`` px short of the true tip
(the point where the two sides, moved inwards by the half-diagonal of a pixel, meet). The sides themselves are
well measured away from the tip. Every crack of the outline separates an ink pixel centre from a paper pixel
centre (:func:`pixel_pairs`); a straight side is the line that separates the window's ink centres from its
paper centres with the largest margin, the centre of the digital straight segment's preimage (the set of
lines whose rendering gives exactly those pixels), and a least-squares line only where no line separates
them; a curved side is a least-squares parabola (:func:`side_fit`). A side too short for a window of its own
(the face of a stroke end or a serif on a small glyph) is one separating line over the whole side, shared by
its two corners, without the pixel centres that the neighbouring sides explain (:func:`short_side`). Sides
within a few degrees of an axis are resolved only to half a pixel by any method. :func:`tip_estimates`
intersects the sides, bounds the crossing (reach and how far outside the pixels a sharp tip can lie, from the
opening of the fitted sides at the crossing) and drops a crossing whose wedge the pixels contradict: an ink
centre near the tip outside it or a paper centre inside it by more than ``CONTRADICTION`` px
(:func:`tip_contradiction`), or a centre of the other kind anywhere between the crossing and the contour
(:func:`wedge_contradiction`); such a crossing is sought again on shorter straight windows.
"""
from __future__ import annotations

import numpy as np

from .._pixel_corners import corner_vertices
from ._kernels import closed_polyline_distance
from ._linalg import solve, svd_direction
from ._tip_kernels import (SIDE_FIELDS, arange_count, frame_offsets, inkward_of, ray_parities, separating_line,
                           side_window, tip_checks, tip_contradiction_of, wedge_contradiction_of, window_local,
                           window_sides, line_tip_checks, curved_side)

__all__ = ["tip_reach", "side_fit", "side_fits", "short_side", "tip_estimates", "tip_contradiction",
           "wedge_contradiction", "is_convex", "ray_parity", "horizontal_cracks", "pixel_pairs", "SideFit"]

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
#: Corners from :data:`MAX_EXTRAPOLATED_ANGLE` up to this interior angle (radians, measured on the contour) are
#: extrapolated too where both sides are straight runs that the pixels pin down: a separating line on each side
#: (:func:`_separating_line`) over a window of at least :data:`OBTUSE_SIDE` px, with the same bounds and
#: consistency tests. Such a corner's crossing is as certain as its lines (``1 / sin(theta / 2) <= 1.41``
#: times their offsets), while the pixels cut the tip of a sharp obtuse corner by up to 1 px and the pieces
#: without it round the corner off by as much (Liberation Serif Bold P at 1200 px, turned: 0.92 px, 0.38 with
#: it; BENCHMARKS.md, "Session 25: obtuse corners").
#:
#: The same limit holds for a corner with one short side (:func:`short_side`: the cut face of a stroke end or
#: a serif's face, too short for a window of its own), on the opening of its fitted sides, where both sides are
#: separating lines and the short side's direction is pinned by its pixels (``SideFit.pinned``: at least two
#: distinct ink and two distinct paper centres left beside it; with a single paper centre the line turns about
#: it up to the slope search's bound, :data:`SLOPE_SEARCH`, and the tip slides along the other side, as on the
#: left end of a 2-px bar at 30 degrees). Without its tip the corner's knot stays on the pixels' chamfer, up to
#: ``sqrt(1/2) / sin(theta / 2)`` (0.8-1 px) inside the corner, and the short face's piece takes the rest of
#: the turn: the join turns by 11-23 degrees where the corner turns by 60-90 (a *fit hook*, the corner lost
#: from the output; BENCHMARKS.md, "Session 35"). Below :data:`MAX_EXTRAPOLATED_ANGLE` a short side's tip is
#: kept without that condition, as before.
MAX_OBTUSE_ANGLE = np.radians(120.0)
#: Shortest window (px of arc) of each side of an obtuse corner that is extrapolated (:data:`MAX_OBTUSE_ANGLE`).
#: The rendering of a curve of radius ``R`` is a digital straight segment over 12 px only where its sagitta
#: ``12^2 / (8 R)`` stays below a pixel, ``R`` above about 18 px; on smaller curves (a small blob) two short
#: straight stretches of the staircase meet at a false corner whose sharp tip lies beyond the curve
#: (``BENCHMARKS.md``, "Small outlines: obtuse tips": without this bound every limit of 100-150 degrees lost
#: shapes).
OBTUSE_SIDE = 12.0
#: A pinhole (a paper pixel centre enclosed by ink, which trace fills) beyond a notch's contour corner, within this
#: distance (px) of the bisector of its sides, marks where the notch still is (:func:`_with_pinholes`); its tip goes
#: :data:`PINHOLE_BEYOND` px beyond that centre: half a pixel, to the far edge of the pixel the centre stands for.
PINHOLE_LATERAL = 1.0
PINHOLE_BEYOND = 0.5
#: Farthest an extrapolated tip may lie from its contour corner (px): the bound that keeps nearly parallel
#: sides (or misread ones) from shooting the corner off.
MAX_TIP_REACH = 5.0
#: An extrapolated tip lies at most this fraction of the shorter side window from its contour corner (short
#: sides, as on ragged or noisy outlines, do not carry a tip far).
REACH_PER_SIDE = 0.25
#: How far (px) an extrapolated tip may lie behind its contour corner (towards the pieces): the crack outline
#: goes round whole pixels, so it can pass a tip by up to half a pixel diagonal.
BEHIND = 1.0
#: Arc (px) beyond the side windows' start whose pixels the extrapolated tip must agree with, and how far (px)
#: a pixel centre may lie on the wrong side of the extrapolated wedge before the tip counts as contradicted
#: (:func:`tip_contradiction`).
TIP_ZONE = 1.0
CONTRADICTION = 0.1
#: Where a corner's crossing fails the bounds or the consistency tests, its sides are fitted again on windows
#: shrunk to this fraction (from the window start), as long as both are separating lines, until one passes or
#: a window is shorter than :data:`SHORTEST_SIDE`; 0: no retry. A retried crossing is kept only where the
#: sides' margins pin it down to :data:`RETRY_UNCERTAINTY` px along the bisector.
RETRY_SHRINK = 0.5
RETRY_UNCERTAINTY = 0.5
#: Range of slopes (in the frame of the least-squares line) searched for the separating line of a side.
SLOPE_SEARCH = 0.25
#: Sides that meet at less than this angle (radians, between their directions) give no reliable intersection.
MIN_CROSSING = np.radians(8.0)
#: On a short side (:func:`short_side`), a pixel centre within this distance (px) of a neighbouring side's line
#: may lie on either side of the true line (a side is resolved to about half a pixel), so the neighbour does
#: not explain it and it does not constrain the short side either.
NEIGHBOUR_BAND = 0.5


def tip_reach(angle):
    """How far (px) the true tip of an interior angle ``angle`` (radians) can lie beyond the crack outline of a
    rendering: ``sqrt(1/2) / sin(angle / 2)`` plus half a pixel for where the detector put the contour corner,
    at most :data:`MAX_TIP_REACH`."""
    return np.minimum(np.sqrt(0.5) / np.maximum(np.sin(0.5 * np.asarray(angle, float)), 1e-6) + 0.5,
                      MAX_TIP_REACH)


class SideFit:
    """A side beside a corner: total-least-squares line (``centre``, unit ``direction``, ``normal``) and, on a
    curved side, a parabola ``y = c0 + c1 t + c2 t^2`` in that line's frame (``coefficients``; zeros on a
    straight side); ``length``: the window's arc length (px); ``ink``: +1 or -1, the side of the normal the
    ink pixels lie on (0 where the contour is not a crack outline); ``margin``: the smallest distance (px,
    across the frame) of the window's pixel centres from the side, when the side separates them (else 0).
    All of them are views of one row of :data:`~._tip_kernels.SIDE_FIELDS` floats (``row``), what the compiled
    kernels read."""

    #: A short side's (:func:`short_side`): whether its pixels pin its direction (two distinct ink and two distinct
    #: paper centres or more); every other side: False.
    pinned = False

    def __init__(self, centre, direction, coefficients, length, ink=0.0, margin=0.0):
        row = np.empty(SIDE_FIELDS)
        row[0:2], row[2:4], row[4], row[5] = centre, direction, -direction[1], direction[0]
        row[6:9], row[9], row[10], row[11] = coefficients, length, ink, margin
        self._take(row)

    @classmethod
    def of_row(cls, row):
        """The side of a kernel's row (:data:`~._tip_kernels.SIDE_FIELDS` floats), not copied."""
        side = cls.__new__(cls)
        side._take(row)
        return side

    def _take(self, row):
        self.row = row
        self.centre, self.direction, self.normal, self.coefficients = row[0:2], row[2:4], row[4:6], row[6:9]

    length = property(lambda self: self.row[9], lambda self, value: self.row.__setitem__(9, value))
    ink = property(lambda self: self.row[10], lambda self, value: self.row.__setitem__(10, value))
    margin = property(lambda self: self.row[11], lambda self, value: self.row.__setitem__(11, value))

    def inkward(self, points):
        """Signed offset (px, across the frame) of ``points`` (k, 2) from the side, positive on its ink side:
        ``ink * y`` on a straight side, ``ink * (y - (c0 + t (c1 + t c2)))`` on a curved one, ``t, y`` the points
        in the side's frame (:func:`~._tip_kernels.inkward_of`)."""
        return inkward_of(self.row, points)

    def point(self, t):
        c0, c1, c2 = self.coefficients
        return self.centre + t * self.direction + (c0 + t * (c1 + t * c2)) * self.normal

    def tangent(self, t):
        return self.direction + (self.coefficients[1] + 2.0 * self.coefficients[2] * t) * self.normal

    def local(self, point):
        return float((point - self.centre) @ self.direction)


def _window_fit(points, length):
    """Line, then parabola, through ``points`` (``length`` px of arc); the first whose residuals stay within
    :data:`STRAIGHT_RESIDUAL`, or None. The line through the points' centre along their first right singular
    vector (numpy's, LAPACK), its frame's offsets in one compiled pass (:func:`~._tip_kernels.frame_offsets`)."""
    local, centre = window_local(points, points.shape[0])
    direction = svd_direction(local)
    t, y, straight = frame_offsets(local, direction)
    if straight:
        return SideFit(centre, direction, np.zeros(3), length)
    coefficients = _parabola(t, y)
    return None if coefficients is None else SideFit(centre, direction, coefficients, length)


def _parabola(t, y):
    """The least-squares parabola ``y = c0 + c1 t + c2 t^2`` (numpy's ``lstsq``, LAPACK) where its residuals stay
    within :data:`STRAIGHT_RESIDUAL`, else None."""
    design = np.empty((t.shape[0], 3))
    design[:, 0], design[:, 1], design[:, 2] = 1.0, t, t * t
    coefficients = np.linalg.lstsq(design, y, rcond=None)[0]
    return coefficients if np.abs(y - design @ coefficients).max() <= STRAIGHT_RESIDUAL else None


def pixel_pairs(points):
    """The two pixel centres beside every point of a crack outline (``points``: unit-crack midpoints in the
    tracer's order, ink on the left of the direction of travel, docs/capture.md §10): ``(ink, paper)``, each
    (n, 2); None if ``points`` are not crack midpoints (another contour form)."""
    points = np.asarray(points, float)
    n = points.shape[0]
    if n < 4:
        return None
    frac = np.abs(points - np.round(points))
    whole, half = frac < 1e-6, np.abs(frac - 0.5) < 1e-6  # per coordinate: an integer, a half-integer
    horizontal = whole[:, 1] & half[:, 0]
    if not (horizontal | (whole[:, 0] & half[:, 1])).all():
        return None
    travel = np.empty_like(points)  # the next point less the previous one, cyclically
    np.subtract(points[2:], points[:-2], out=travel[1:-1])
    travel[0], travel[-1] = points[1] - points[-1], points[0] - points[-2]
    # the unit step (sign of the travel along the crack, 0 across it) turned a quarter to the left, halved
    sign = np.sign(travel, out=travel)
    left = np.empty_like(points)
    np.multiply(-np.where(horizontal, 0.0, sign[:, 1]), 0.5, out=left[:, 0])
    np.multiply(np.where(horizontal, sign[:, 0], 0.0), 0.5, out=left[:, 1])
    return points + left, points - left


_FIRST_SLOPES = np.linspace(-SLOPE_SEARCH, SLOPE_SEARCH, 17)
_NO_POINTS = np.empty((0, 2))
_SIN_MIN_CROSSING = float(np.sin(MIN_CROSSING))
#: The bounds of :func:`~._tip_kernels.tip_checks`.
_TIP_LIMITS = np.array([REACH_PER_SIDE, BEHIND, CONTRADICTION, TIP_ZONE, MAX_TIP_REACH])


def _separating_line(fit, ink, paper):
    """The line that separates the pixel centres ``ink`` from ``paper`` with the largest margin (measured across
    the frame of ``fit``): the centre of the set of lines whose digitization gives these pixels (the preimage
    of a digital straight segment), or None when no line separates them (a ragged or curved window).

    In the frame of ``fit`` the line is ``y = c0 + c1 t``; for a slope ``c1`` the best offset and margin are in
    closed form (half the gap between the lowest ink and the highest paper offset ``y - c1 t``), and the margin
    is a concave function of ``c1``, maximised on grids of slopes, each zoomed around the best of the last
    (to about 1e-5)."""
    row = separating_line(ink, paper, fit.row, _FIRST_SLOPES, SLOPE_SEARCH / 8, 5)
    return None if row is None else SideFit.of_row(row)


def side_fit(contour, corner_arc, sign, start, stop, pairs=None):
    """The side of a corner at arc length ``corner_arc`` towards ``sign`` (+1 forwards, -1 backwards): the
    contour polyline sampled every 0.5 px from ``start`` to ``stop`` px of arc away, fitted by
    :func:`_window_fit`; where neither a line nor a parabola fits, the window shrinks from its far end (by a
    quarter at a time) down to :data:`SHORTEST_SIDE`. With ``pairs`` (:func:`pixel_pairs` of the contour) a
    straight side is replaced by the line that separates the window's ink and paper pixel centres with the
    largest margin (:func:`_separating_line`), where there is one. Returns a :class:`SideFit` or None
    (:func:`side_fits` of one side)."""
    return side_fits(contour, [(corner_arc, sign, start, stop)], pairs)[0]


def side_fits(contour, requests, pairs=None):
    """:func:`side_fit` of each ``(corner_arc, sign, start, stop)`` of ``requests``: a list of :class:`SideFit` or
    None. The first window of every side runs in one batch (:func:`~._tip_kernels.window_sides`, the same
    operations and bits as one side at a time); a window that is not straight gets its parabola from the frame
    offsets the batch found, and where that fails it shrinks from its far end, a window at a time (a shrunk
    window's samples are the first ones of the longest window's: sampled once)."""
    out = [None] * len(requests)
    todo = [r for r, (_, _, start, stop) in enumerate(requests) if stop - start >= SHORTEST_SIDE]
    if not todo:
        return out
    ink, paper = (_NO_POINTS, _NO_POINTS) if pairs is None else pairs
    corner_arcs, signs, starts, stops = zip(*(requests[r] for r in todo))
    step = SLOPE_SEARCH / 8
    first = window_sides(contour, corner_arcs, signs, starts, stops, ink, paper, _FIRST_SLOPES, step, 5)
    offsets = first["offsets"]
    for at, r in enumerate(todo):
        if first["status"][at] != 2:
            out[r] = SideFit.of_row(first["rows"][at])
            continue
        corner_arc, sign, start, stop = requests[r]
        window = slice(offsets[at], offsets[at + 1])
        row = curved_side(contour, corner_arc, sign, start, stop, first["local"][window], first["centres"][at],
                          first["directions"][at], first["t"][window], first["y"][window], ink, paper, _parabola,
                          _FIRST_SLOPES, step, 5)
        samples = first["samples"][window]
        while row is None:
            stop = start + 0.75 * (stop - start)
            if stop - start < SHORTEST_SIDE:
                break
            row = side_window(contour, corner_arc, sign, start, stop, samples, arange_count(start, stop + 1e-9, 0.5),
                              None, None, ink, paper, _parabola, _FIRST_SLOPES, step, 5)
        out[r] = None if row is None else SideFit.of_row(row)
    return out


def short_side(contour, piece, pairs, neighbours):
    """The whole side ``piece`` (between corners ``piece`` and ``piece + 1`` of ``contour``) as one line shared by
    both corners: the separating line (:func:`_separating_line`) of the ink and paper pixel centres beside the
    contour points of the piece, in the frame of the piece's least-squares line. Near a corner some of these
    centres belong to the neighbouring side (``neighbours``: the :class:`SideFit` beyond the piece's first and
    last corner, each fitted on its own window): beside a convex corner a paper centre outside the neighbour's
    line is paper because of the neighbour, beside a notch an ink centre inside it is ink because of the
    neighbour; such centres, and those within :data:`NEIGHBOUR_BAND` of the neighbour's line, are left out.
    Returns a :class:`SideFit` (``length``: the piece's arc length; ``pinned``: at least two distinct ink and
    two distinct paper centres were left, so that the pixels, not the slope search's bound, set the line's
    direction) or None: a neighbour without a fit (the centres near that corner cannot be sorted), a curved or
    ragged piece, too few centres left or no line that separates them."""
    if any(side is None or not side.ink for side in neighbours):
        return None
    n = contour.size
    lo, hi = int(contour.corner_bounds[piece]), int(contour.corner_bounds[piece + 1])  # (no piece wraps round)
    length = float(contour.arc[hi] - contour.arc[lo])
    offsets = np.arange(0.0, length + 1e-9, 0.5)
    fit = _window_fit(contour.point_at_arc((contour.arc[lo] + offsets) % contour.perimeter), length)
    if fit is None or fit.coefficients.any():
        return None
    index = np.arange(lo, hi + 1) % n
    ink, paper = pairs[0][index], pairs[1][index]
    keep_ink, keep_paper = np.ones(index.size, bool), np.ones(index.size, bool)
    for side, far in zip(neighbours, (contour.points[hi % n], contour.points[lo % n])):
        if side.inkward(far[None])[0] > 0:  # convex corner: the piece lies on the neighbour's ink side
            keep_paper &= side.inkward(paper) >= NEIGHBOUR_BAND
        else:
            keep_ink &= side.inkward(ink) <= -NEIGHBOUR_BAND
    ink, paper = ink[keep_ink], paper[keep_paper]
    if ink.shape[0] < 2 or paper.shape[0] < 2:
        return None
    side = _separating_line(fit, ink, paper)
    if side is not None:  # neighbouring contour points often share a centre: count the distinct ones
        side.pinned = min(np.unique(ink, axis=0).shape[0], np.unique(paper, axis=0).shape[0]) >= 2
    return side


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
        step = solve(jacobian, second.point(t[1]) - first.point(t[0]))
        t += step
        if np.abs(step).max() < 1e-9:
            break
    return first.point(t[0])


def tip_contradiction(contour, corner_arc, zone, sides, pairs, convex=None):
    """How far (px) the wedge of two :class:`SideFit` (crossing at the tip) contradicts the pixels of the
    truncated tip: the pixel centres beside the contour within ``zone`` px of arc of the corner, ink ones
    that fall outside the wedge's ink and paper ones inside it; the largest such offset (<= 0: consistent).
    The ink of a convex corner is where both sides have ink, that of a concave one (a notch) where either
    has (``convex``: :func:`is_convex` of ``sides``, found here when None)."""
    if convex is None:
        convex = is_convex(sides)
    return tip_contradiction_of(contour, corner_arc, zone, sides[0].row, sides[1].row, pairs[0], pairs[1], convex)


def is_convex(sides):
    """Whether the wedge of two :class:`SideFit` is a convex corner: the second side's centre on the ink side
    of the first (else a notch)."""
    return sides[0].inkward(sides[1].centre[None])[0] > 0


def ray_parity(cracks, queries):
    """Per point of ``queries``, the parity (0 or 1) of the horizontal cracks (``cracks``, :func:`horizontal_cracks`)
    that a vertical ray from it upwards crosses: those of its own column above it (a ray only meets cracks of its
    own column; they are a run of the x-sorted cracks)."""
    return ray_parities(cracks, queries)


def horizontal_cracks(points):
    """The horizontal cracks of a crack outline ``points`` (the points with an integer y), sorted by x (stable):
    what :func:`wedge_contradiction` counts its rays' crossings on, found once per outline."""
    cracks = points.compress(np.abs(points[:, 1] - np.round(points[:, 1])) < 1e-9, axis=0)
    return cracks.take(np.argsort(cracks[:, 0], kind="stable"), axis=0)


def wedge_contradiction(cracks, pairs, tip, ends, sides, convex=None, ink_parity=None):
    """How far (px) the wedge of two :class:`SideFit` crossing at ``tip`` contradicts the pixel centres between
    the tip and the contour: every centre inside the triangle of ``tip`` and the contour points ``ends`` at the
    side windows' start, not only those beside the contour (:func:`tip_contradiction`): the deepest paper centre
    inside the ink wedge of a convex corner, or ink centre inside the paper wedge of a notch (<= 0 or
    ``-inf``: none), with each side moved inwards by its margin (:class:`SideFit`: every line within it
    separates the side's window as well, so only a centre deeper than that contradicts the side as measured). A
    rendering makes every pixel centre inside the true wedge ink (outside it paper), so an extrapolated tip whose
    wedge holds paper centres beyond the contour (a spike past a stroke end, say) is not the tip.

    Whether a centre is ink follows from the crack outline alone: a vertical ray from the centre crosses the
    outline at its horizontal cracks (``cracks``, :func:`horizontal_cracks` of the outline: points with integer y;
    those on the centre's column), and the parity of the crossings above it is that of a centre known to be ink
    (``pairs[0][0]``, beside the first crack) exactly when it is ink (:func:`ray_parity`; ``ink_parity``: that
    centre's, the same for every corner of the outline, found here when None). ``convex``: :func:`is_convex` of
    ``sides``, found here when None."""
    if convex is None:
        convex = is_convex(sides)
    return wedge_contradiction_of(cracks, ink_parity, pairs[0], tip, ends, sides[0].row, sides[1].row, convex)


def tip_estimates(contour, angle, radius, measured=None):
    """Per corner of ``contour`` (a :class:`~.lsq_setup.RotatedContour` with corners), the extrapolated tip:
    both sides fitted by :func:`side_fit` from ``max(radius, min(6, 1 / tan(angle / 2)))`` px of arc (where
    a wedge of that opening is about two pixels wide) to 0.8 of the side (at most :data:`LONGEST_SIDE` px
    further), intersected by :func:`_crossing`. Kept when the intersection lies within :func:`tip_reach` of
    the contour corner (and within :data:`REACH_PER_SIDE` of the shorter window), no farther outside the
    contour than a sharp tip can be (:data:`SHARP_TRUNCATION`) and not more than :data:`BEHIND` behind it
    (along the bisector of the sides), and neither :func:`tip_contradiction` nor :func:`wedge_contradiction`
    finds pixels that contradict its wedge. A crossing that fails is sought again on windows shrunk by
    :data:`RETRY_SHRINK` (a side that is no separating line there gets its parabola, as on the long window), and
    where both shrunk sides are separating lines it is kept only where their margins pin it down to
    :data:`RETRY_UNCERTAINTY`. Only corners sharper than :data:`MAX_OBTUSE_ANGLE` are measured (the others get
    no estimate, and their sides are not fitted), and those from :data:`MAX_EXTRAPOLATED_ANGLE` on keep their
    estimate only between two separating lines of :data:`OBTUSE_SIDE` px or more.

    A side whose window would be shorter than :data:`SHORTEST_SIDE` is a short side: the whole side between
    its two corners is one line shared by both (:func:`short_side`, its neighbours the sides beyond its
    corners). A corner with one short side is measured whatever its angle on the contour (measured on chords
    that reach past the short side, it is blunter than the corner), and keeps its tip only where the other
    side is a separating line too and the fitted sides meet at less than :data:`MAX_EXTRAPOLATED_ANGLE`, or at
    less than :data:`MAX_OBTUSE_ANGLE` (the limit of obtuse corners between long straight sides) where the short
    side's direction is pinned by its pixels (``SideFit.pinned`` of :func:`short_side`); the
    reach is bounded by the other side's window only (the tip lies at the end of the shared side). A corner
    between two short sides gets no estimate.

    A corner beside a pixel corner of a crack outline (one of the two contour points beside a turn of the
    pixel boundary between two axis-aligned straight runs, :mod:`splinecraft.capture._pixel_corners`) has that
    vertex as its tip whatever its angle: each run's separating line is the crack line itself, so their
    crossing is exact (as far as the pixels go) and lies on the pixel boundary, 0.35 px outside the contour's
    chamfer; its sides are not fitted. The pixel corners are ``contour.pixel_corners`` where the caller found
    them (trace's corner stage), else found here.

    ``measured`` (boolean per corner, optional): only these corners are measured (the small-outline path
    measures the corners its pre-test passes, docs/capture.md §12, "Small outlines").

    Returns ``(estimate, start, anchors, outside)``: estimate (k, 2), NaN where there is none; the window start
    per corner; the contour points at the window starts (k, 2, 2: before, after); the estimate's distance from
    the contour (px; NaN where there is none)."""
    arc, perimeter = contour.arc, contour.perimeter
    lengths = np.diff(arc[contour.corner_bounds])
    before_len, after_len = np.concatenate([lengths[-1:], lengths[:-1]]), lengths  # numpy.roll(lengths, 1)
    count = contour.corner_count
    start = np.maximum(radius, np.clip(1.0 / np.maximum(np.tan(0.5 * angle), 1e-6), 1.0, 6.0))
    estimate = np.full((count, 2), np.nan)
    anchors = np.full((count, 2, 2), np.nan)
    opening = np.array(angle, float)
    pinned = np.zeros(count, bool)  # beside a short side: that side's direction pinned by its pixels
    straight = np.zeros(count, bool)  # both sides separating lines (digital straight segments) of OBTUSE_SIDE px
    # the side windows (before, after): a side shorter than SHORTEST_SIDE from the window start to 0.8 of the
    # side is a short side, the whole side one line shared by its two corners (short_side)
    stops = np.minimum(start[:, None] + LONGEST_SIDE, 0.8 * np.column_stack([before_len, after_len]))
    short = stops - start[:, None] < SHORTEST_SIDE
    one_short = short.sum(axis=1) == 1
    # a corner at max(MAX_EXTRAPOLATED_ANGLE, MAX_OBTUSE_ANGLE) or blunter is not extrapolated: its sides are
    # not fitted; a corner with one short side is measured whatever its angle on the contour (the angle
    # measured on chords that reach past the short side is blunter than the corner) and kept only if its sides
    # meet at less than MAX_EXTRAPOLATED_ANGLE
    acute = ~(opening >= max(MAX_EXTRAPOLATED_ANGLE, MAX_OBTUSE_ANGLE))
    # pixel corners: the vertex, no sides fitted
    vertex = corner_vertices(contour.points, [contour.size], np.zeros(count, dtype=np.int64),
                             contour.corner_bounds[:-1],
                             None if contour.pixel_corners is None else [contour.pixel_corners])
    pixel = np.isfinite(vertex[:, 0]) if measured is None else np.isfinite(vertex[:, 0]) & measured
    wanted = (acute | one_short) if measured is None else (acute | one_short) & measured
    wanted &= ~pixel
    if not wanted.any():
        return _with_pinholes(contour, angle, pixel, *_with_pixel_corners(
            contour, pixel, vertex, start, estimate, anchors, np.full(count, np.nan),
            _outside(contour, vertex.compress(pixel, axis=0))))
    pairs = pixel_pairs(contour.points)
    if pairs is None:
        one_short[:] = False
    cracks = None if pairs is None else horizontal_cracks(contour.points)
    candidates = np.flatnonzero(wanted)
    regular, shared = {}, {}
    # every side the loop below may fit on its own window, in one batch (side_fits); the shared sides' neighbours
    # and the retries' shorter windows as they come
    needed = [(int(c), k) for c in candidates for k in (0, 1)]
    regular.update(zip(needed, side_fits(contour, [(arc[contour.corner_bounds[c]], 2 * k - 1, start[c], stops[c, k])
                                                   for c, k in needed], pairs)))

    def side_of(c, k):
        """Side ``k`` (0: before, 1: after) of corner ``c``: its own window, or None where that is short."""
        if (c, k) not in regular:
            regular[c, k] = side_fit(contour, arc[contour.corner_bounds[c]], 2 * k - 1, start[c], stops[c, k], pairs)
        return regular[c, k]

    def shared_side(piece):
        """The short side ``piece`` (from corner ``piece`` to the next): one line for both its corners."""
        if piece not in shared:
            shared[piece] = short_side(contour, piece, pairs, (side_of(piece, 0), side_of((piece + 1) % count, 1)))
        return shared[piece]

    measured_sides = []  # (corner, its sides, which of them are shared)
    for c in candidates:
        sides, measured = [None, None], True
        for k in (1, 0) if one_short[c] and short[c, 0] else (0, 1):  # beside a short side, the other one first
            sides[k] = shared_side((c - 1 + k) % count) if short[c, k] and one_short[c] else side_of(c, k)
            # no crossing without both sides; beside a short side, none where the other side is curved (its
            # parabola, fitted far along the side, misses the tip by up to a pixel)
            if sides[k] is None or (one_short[c] and not sides[k].margin > 0):
                measured = False
                break
        if measured:
            measured_sides.append((c, sides, [bool(short[c, k] and one_short[c]) for k in (0, 1)]))
    for (c, sides, is_shared), found in zip(measured_sides, _tips(contour, measured_sides, start, pairs, cracks)):
        corner_arc = arc[contour.corner_bounds[c]]
        reach = stops[c].copy()
        while found is None and RETRY_SHRINK and not any(is_shared):
            reach = start[c] + RETRY_SHRINK * (reach - start[c])
            if (reach - start[c]).min() < SHORTEST_SIDE:
                break
            sides = side_fits(contour, [(corner_arc, 2 * k - 1, start[c], reach[k]) for k in (0, 1)], pairs)
            if any(side is None for side in sides):
                break
            found = _tip(contour, c, sides, is_shared, corner_arc, start[c], pairs, cracks)
            if found is not None and sides[0].margin > 0 and sides[1].margin > 0 and \
                    (sides[0].margin + sides[1].margin) / (2.0 * np.sin(0.5 * found[1])) > RETRY_UNCERTAINTY:
                found = None
                break
        if found is None:
            continue
        estimate[c], opening[c], anchors[c] = found
        pinned[c] = any(is_shared) and all(side.pinned for side, shared in zip(sides, is_shared) if shared)
        straight[c] = sides[0].margin > 0 and sides[1].margin > 0 and \
            min(sides[0].length, sides[1].length) >= OBTUSE_SIDE
    # a sharp tip lies at most sqrt(1/2) / sin(theta / 2) outside the pixels; one farther out is the crossing of
    # the sides of a rounded (or flattened) corner, which the pixels follow better than the crossing does
    # (an obtuse corner below MAX_OBTUSE_ANGLE only between two straight sides, or beside a short side whose
    # direction its pixels pin, both sides separating lines where it was measured); where one side is short, the
    # angle is the opening of the fitted sides
    gate = np.where(one_short, opening, angle)
    estimate[(gate >= MAX_EXTRAPOLATED_ANGLE) & ~((straight | pinned) & (gate < MAX_OBTUSE_ANGLE))] = np.nan
    found = np.flatnonzero(np.isfinite(estimate[:, 0]))  # none of them a pixel corner (not measured)
    outside = _outside(contour, np.concatenate([estimate[found], vertex[pixel]]))
    distance = np.full(count, np.nan)
    if found.size:
        distance[found] = outside[:found.size]
        rounded = found[outside[:found.size] * np.sin(0.5 * opening[found]) > SHARP_TRUNCATION]
        estimate[rounded], anchors[rounded], distance[rounded] = np.nan, np.nan, np.nan
    return _with_pinholes(contour, angle, pixel, *_with_pixel_corners(contour, pixel, vertex, start, estimate,
                                                                      anchors, distance, outside[found.size:]))


def _outside(contour, points):
    """Distance (px) of ``points`` (a few tips) from the closed contour polyline, exact: the least over the edges
    with an end within the nearest vertex's distance plus half the longest edge (no other edge comes nearer),
    each by the arithmetic of :func:`~.geometry.segment_squared_distances`, in one compiled pass
    (:func:`~._kernels.closed_polyline_distance`; :func:`~.geometry.polyline_distance`'s search tree of the whole
    contour cost more than these few points, and so did their grid against every vertex)."""
    if not points.shape[0]:
        return np.zeros(0)
    return closed_polyline_distance(points, contour.points, 0.5 * np.diff(contour.arc).max())


def _tip(contour, c, sides, is_shared, corner_arc, start, pairs, cracks, parity=None):
    """The crossing of the two :class:`SideFit` ``sides`` of corner ``c`` as its tip (:func:`tip_estimates`'
    bounds and consistency tests), with the opening of the fitted sides at the crossing and the contour points
    at the window starts; None where it fails them. ``cracks``: :func:`horizontal_cracks` of the contour (with
    ``pairs``); ``parity``: the :func:`ray_parity` of its ink centre ``pairs[0][0]`` (the same for every corner
    of the outline; found in the tests' compiled pass when None)."""
    # a shared short side spans its whole side, so the tip lies at its end, not beyond its pixels: only the
    # other side's window bounds the reach
    windows = np.array([side.length for side, shared in zip(sides, is_shared) if not shared])
    crossing = None
    if sides[0].coefficients.any() or sides[1].coefficients.any():  # a parabola: Newton steps in numpy
        crossing = _crossing(*sides)
        if crossing is None:
            return None
    ink, paper = (_NO_POINTS, _NO_POINTS) if pairs is None else pairs
    return tip_checks(contour, contour.corner_bounds[c] % contour.size, corner_arc, start, sides[0].row,
                      sides[1].row, windows, crossing, ink, paper, _NO_POINTS if cracks is None else cracks,
                      -1 if parity is None else parity, _SIN_MIN_CROSSING, _TIP_LIMITS)


def _tips(contour, measured_sides, start, pairs, cracks):
    """:func:`_tip` of each ``(corner, sides, is_shared)`` of ``measured_sides`` (window start ``start[corner]``):
    the corners between two lines in one compiled pass (:func:`~._tip_kernels.line_tip_checks`), the others one
    by one."""
    found = [None] * len(measured_sides)
    lines = []
    for at, (c, sides, is_shared) in enumerate(measured_sides):
        if sides[0].coefficients.any() or sides[1].coefficients.any():
            found[at] = _tip(contour, c, sides, is_shared, contour.arc[contour.corner_bounds[c]], start[c], pairs,
                             cracks)
        else:
            lines.append(at)
    if lines:
        ink, paper = (_NO_POINTS, _NO_POINTS) if pairs is None else pairs
        corners = [measured_sides[at][0] for at in lines]
        checked = line_tip_checks(
            contour, [contour.corner_bounds[c] % contour.size for c in corners],
            [contour.arc[contour.corner_bounds[c]] for c in corners], [start[c] for c in corners],
            [measured_sides[at][1][0].row for at in lines], [measured_sides[at][1][1].row for at in lines],
            [[side.length for side, shared in zip(measured_sides[at][1], measured_sides[at][2]) if not shared]
             for at in lines], ink, paper, _NO_POINTS if cracks is None else cracks, _SIN_MIN_CROSSING, _TIP_LIMITS)
        for at, result in zip(lines, checked):
            found[at] = result
    return found


def _with_pinholes(contour, angle, pixel, estimate, start, anchors, distance):
    """:func:`tip_estimates`' results with the notches that a pinhole shows reaching farther: a paper pixel centre
    enclosed by ink (``contour.pinholes``, the centres of the pinholes trace filled) beyond the contour corner, at
    most :data:`MAX_TIP_REACH` px along the outward bisector of the window starts and within
    :data:`PINHOLE_LATERAL` px of it, lies inside the true notch: the notch narrows below a pixel before its tip,
    its rendering breaks off, and the pixel centre that still falls inside the sliver is all that is left of it.
    The tip goes :data:`PINHOLE_BEYOND` px beyond the farthest such centre, unless the estimate already lies
    farther out, and no farther from the contour than the tip of a sharp wedge of the corner's angle (``angle``,
    measured on the contour) can lie beyond its rendering (:func:`tip_reach`), at corners sharper than
    :data:`MAX_EXTRAPOLATED_ANGLE` (a blunter notch is no sliver). A convex corner has paper beyond it, never a
    pinhole; pixel corners keep their vertex. The corners so placed are ``contour.pinhole_tips``
    (:meth:`~.lsq_model.OutlineRegression.zone_hooks` leaves them be). Memory is linear in the corners and the
    pinholes (a long noisy boundary can have tens of thousands of both)."""
    pinholes = contour.pinholes
    if pinholes is None or not pinholes.shape[0] or not contour.corner_count:
        return estimate, start, anchors, distance
    pinholes = pinholes[np.argsort(pinholes[:, 0], kind="stable")]
    placed = []
    corners = contour.points[contour.corner_bounds[:-1] % contour.size]
    # the pinholes within MAX_TIP_REACH in x of each corner: a run of the x-sorted centres
    low = np.searchsorted(pinholes[:, 0], corners[:, 0] - MAX_TIP_REACH, side="left")
    high = np.searchsorted(pinholes[:, 0], corners[:, 0] + MAX_TIP_REACH, side="right")
    for c in np.flatnonzero((high > low) & ~pixel & (np.asarray(angle) < MAX_EXTRAPOLATED_ANGLE)):
        candidates = pinholes[low[c]:high[c]]
        candidates = candidates[np.abs(candidates[:, 1] - corners[c, 1]) <= MAX_TIP_REACH]
        if not candidates.shape[0]:
            continue
        corner_arc = contour.arc[contour.corner_bounds[c]]
        ends = contour.point_at_arc((corner_arc + np.array([-start[c], start[c]])) % contour.perimeter)
        outward = corners[c] - 0.5 * (ends[0] + ends[1])
        length = np.hypot(*outward)
        if length == 0.0:
            continue
        outward /= length
        offset = candidates - corners[c]
        along, across = offset @ outward, offset @ np.array([-outward[1], outward[0]])
        inside = (along > 0.0) & (along <= MAX_TIP_REACH) & (np.abs(across) <= PINHOLE_LATERAL)
        if not inside.any():
            continue
        tip = candidates[inside][np.argmax(along[inside])] + PINHOLE_BEYOND * outward
        if np.isfinite(estimate[c, 0]) and (estimate[c] - corners[c]) @ outward >= (tip - corners[c]) @ outward:
            continue
        outside = _outside(contour, tip[None])[0]
        if outside > tip_reach(angle[c]):
            continue
        estimate[c], anchors[c], distance[c] = tip, ends, outside
        placed.append(c)
    contour.pinhole_tips = np.array(placed, dtype=np.int64)
    return estimate, start, anchors, distance


def _with_pixel_corners(contour, pixel, vertex, start, estimate, anchors, distance, vertex_distance):
    """:func:`tip_estimates`' results with the pixel corners ``pixel`` (boolean per corner) at their vertex
    (``vertex``, per corner; ``vertex_distance``: the distance of each of those vertices from the contour, in
    corner order): the estimate, the contour points at the window starts and the distance from the contour."""
    if not pixel.any():
        return estimate, start, anchors, distance
    found = np.flatnonzero(pixel)
    corner_arc = contour.arc[contour.corner_bounds[found]]
    estimate[found] = vertex.take(found, axis=0)
    reach = start[found]
    # the points before and after every corner, in one look-up: (before, after) per corner
    arcs = np.column_stack([(corner_arc - reach) % contour.perimeter, (corner_arc + reach) % contour.perimeter])
    anchors[found] = contour.point_at_arc(arcs).reshape(-1, 2, 2)
    distance[found] = vertex_distance
    return estimate, start, anchors, distance
