"""Implicit planar shapes ``f(x, y) <= 0`` and their exact outlines, for the deterministic bitmaps of
:mod:`splinecraft.datasets`.

Every primitive maps x, y (1-D float arrays, design units, y down) to f(x, y): negative inside, positive
outside. Discs, polygons and strokes return the exact signed distance; ellipses a smooth function with the
exact zero set. Boolean operations (min / max) keep the zero set exact, so the bitmap and the true outline are
those of the composed shape. :func:`project` and :func:`refine_closed` put dense polylines on the zero set.
"""
from __future__ import annotations

import functools

import numpy as np

_CHUNK = 1 << 22  # max elements of one (points x segments) temporary
_GROUP = 16  # segments per bounding-box group in segment_distance
#: Points farther than this (design units) beyond a group's reach get a lower bound instead of the
#: exact distance. It exceeds every fillet size used below, so min/max/smooth-min compositions are
#: exact wherever their result is within this margin of zero: the zero set is unchanged.
_EXACT_MARGIN = 12.0


def segment_distance(x, y, starts, ends, radius_start, radius_end):
    """min over segments of ``distance(point, segment) - radius(u)``, radius linear along the segment.

    This is a stroke of varying width around a polyline (round caps and joins). Vectorised over
    points and segments, in chunks of at most ``_CHUNK`` elements. Segments are taken in groups of
    ``_GROUP`` with a bounding box: points farther than ``_EXACT_MARGIN`` from a group's reach get the
    lower bound ``box distance - max radius`` from that group (same sign, never above the exact value),
    which keeps the zero set and every value within the margin exact.
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    out = np.full(x.shape[0], np.inf)
    for lo in range(0, starts.shape[0], _GROUP):
        a, b = starts[lo:lo + _GROUP], ends[lo:lo + _GROUP]
        ra, rb = radius_start[lo:lo + _GROUP], radius_end[lo:lo + _GROUP]
        box_lo = np.minimum(a.min(axis=0), b.min(axis=0))
        box_hi = np.maximum(a.max(axis=0), b.max(axis=0))
        reach = float(max(ra.max(), rb.max()))
        gap_x = np.maximum(np.maximum(box_lo[0] - x, x - box_hi[0]), 0.0)
        gap_y = np.maximum(np.maximum(box_lo[1] - y, y - box_hi[1]), 0.0)
        bound = np.hypot(gap_x, gap_y) - reach
        near = np.flatnonzero(bound <= _EXACT_MARGIN)
        far = bound > _EXACT_MARGIN
        out[far] = np.minimum(out[far], bound[far])
        if near.size == 0:
            continue
        ax, ay = a[:, 0], a[:, 1]
        dx, dy = b[:, 0] - ax, b[:, 1] - ay
        length_sq = np.maximum(dx * dx + dy * dy, 1e-300)
        step = max(1, _CHUNK // max(1, a.shape[0]))
        for start in range(0, near.size, step):
            index = near[start:start + step]
            px = x[index, None] - ax
            py = y[index, None] - ay
            u = np.clip((px * dx + py * dy) / length_sq, 0.0, 1.0)
            dist = np.hypot(px - u * dx, py - u * dy) - (ra + u * (rb - ra))
            out[index] = np.minimum(out[index], dist.min(axis=1))
    return out


def disc(cx, cy, radius):
    def f(x, y):
        return np.hypot(x - cx, y - cy) - radius
    return f


def ellipse(cx, cy, semi_x, semi_y, angle_deg=0.0):
    """Ellipse; f = (rho - 1) * min(semi axes) with rho the ellipse 'radius' (exact zero set)."""
    cos_a, sin_a = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    scale = min(semi_x, semi_y)

    def f(x, y):
        u = (x - cx) * cos_a + (y - cy) * sin_a
        v = -(x - cx) * sin_a + (y - cy) * cos_a
        return (np.hypot(u / semi_x, v / semi_y) - 1.0) * scale
    return f


def polygon(vertices):
    """Exact signed distance to a simple polygon (even-odd inside test)."""
    vertices = np.asarray(vertices, float)
    starts = vertices
    ends = np.roll(vertices, -1, axis=0)
    zeros = np.zeros(len(vertices))

    def f(x, y):
        dist = segment_distance(x, y, starts, ends, zeros, zeros)
        inside = np.zeros(x.shape[0], bool)
        for (ax, ay), (bx, by) in zip(starts, ends):  # loop over the few polygon edges only
            crosses = (ay > y) != (by > y)
            with np.errstate(divide="ignore", invalid="ignore"):
                x_cross = ax + (bx - ax) * (y - ay) / (by - ay)
            inside ^= crosses & (x < x_cross)
        return np.where(inside, -dist, dist)
    return f


def catmull_rom(points, samples_per_span=12):
    """Centripetal Catmull-Rom curve through ``points`` (no loops or cusps), as a dense polyline."""
    points = np.asarray(points, float)
    padded = np.vstack([2 * points[0] - points[1], points, 2 * points[-1] - points[-2]])
    out = [points[:1]]
    theta = np.linspace(0.0, 1.0, samples_per_span + 1)[1:, None]
    for k in range(1, len(padded) - 2):
        p0, p1, p2, p3 = padded[k - 1:k + 3]
        t0 = 0.0
        t1 = t0 + np.linalg.norm(p1 - p0) ** 0.5
        t2 = t1 + np.linalg.norm(p2 - p1) ** 0.5
        t3 = t2 + np.linalg.norm(p3 - p2) ** 0.5
        t = t1 + theta * (t2 - t1)
        a1 = (t1 - t) / (t1 - t0) * p0 + (t - t0) / (t1 - t0) * p1
        a2 = (t2 - t) / (t2 - t1) * p1 + (t - t1) / (t2 - t1) * p2
        a3 = (t3 - t) / (t3 - t2) * p2 + (t - t2) / (t3 - t2) * p3
        b1 = (t2 - t) / (t2 - t0) * a1 + (t - t0) / (t2 - t0) * a2
        b2 = (t3 - t) / (t3 - t1) * a2 + (t - t1) / (t3 - t1) * a3
        out.append((t2 - t) / (t2 - t1) * b1 + (t - t1) / (t2 - t1) * b2)
    return np.vstack(out)


def stroke(points, radii, samples_per_span=12):
    """A pen stroke along the smooth curve through ``points``, half-width interpolated from ``radii``.

    ``radii`` holds one half-width per control point (linearly interpolated along the curve). Ends
    are round.
    """
    points = np.asarray(points, float)
    spine = catmull_rom(points, samples_per_span) if len(points) > 2 else points
    radii = np.asarray(radii, float)
    # radius at each spine vertex: linear in the control-point index along the spine
    position = np.linspace(0.0, len(points) - 1.0, len(spine))
    spine_radius = np.interp(position, np.arange(len(points)), radii)

    def f(x, y):
        return segment_distance(x, y, spine[:-1], spine[1:], spine_radius[:-1], spine_radius[1:])
    return f


def union(*shapes):
    def f(x, y):
        return functools.reduce(np.minimum, (s(x, y) for s in shapes))
    return f


def intersection(*shapes):
    def f(x, y):
        return functools.reduce(np.maximum, (s(x, y) for s in shapes))
    return f


def difference(shape_a, *removed):
    def f(x, y):
        return functools.reduce(np.maximum, (-s(x, y) for s in removed), shape_a(x, y))
    return f


def smooth_union(shape_a, shape_b, blend):
    """Union with a fillet of size ``blend`` (polynomial smooth minimum); the zero set is smooth."""
    def f(x, y):
        a, b = shape_a(x, y), shape_b(x, y)
        h = np.clip(0.5 + 0.5 * (b - a) / blend, 0.0, 1.0)
        return b + (a - b) * h - blend * h * (1.0 - h)
    return f


def half_plane(point, normal_out):
    """Half-plane ``(p - point) . normal_out <= 0`` (``normal_out`` points outside)."""
    nx, ny = np.asarray(normal_out, float) / np.hypot(*normal_out)

    def f(x, y):
        return (x - point[0]) * nx + (y - point[1]) * ny
    return f


def vesica(tip_a, tip_b, half_width):
    """Leaf shape: intersection of two discs through the tips ``tip_a``, ``tip_b`` (pointed ends)."""
    tip_a, tip_b = np.asarray(tip_a, float), np.asarray(tip_b, float)
    chord = tip_b - tip_a
    half_chord = np.linalg.norm(chord) / 2
    radius = (half_chord ** 2 + half_width ** 2) / (2 * half_width)
    normal = np.array([-chord[1], chord[0]]) / (2 * half_chord)
    middle = (tip_a + tip_b) / 2
    offset = radius - half_width
    c1, c2 = middle + offset * normal, middle - offset * normal
    return intersection(disc(c1[0], c1[1], radius), disc(c2[0], c2[1], radius))


def central_gradient(f, points, step=1e-6):
    """Central-difference gradient of ``f`` at ``points`` (k, 2), and the values there."""
    x, y = points[:, 0], points[:, 1]
    values = f(np.concatenate([x, x + step, x - step, x, x]),
               np.concatenate([y, y, y, y + step, y - step]))
    value, x_plus, x_minus, y_plus, y_minus = values.reshape(5, -1)
    return value, np.c_[(x_plus - x_minus) / (2 * step), (y_plus - y_minus) / (2 * step)]


def project(f, points, tolerance=1e-10, max_iterations=40):
    """Newton-project points onto the zero set of ``f`` (central-difference gradient), design units.

    Only points not yet within ``tolerance`` are iterated. The gradient norm is floored at 0.5 so
    that a point on a medial axis (where the gradient of a distance is undefined) moves at most
    ``2 |f|``; on exact signed distances one step suffices, elsewhere a few.
    """
    points = np.array(points, float)
    active = np.arange(points.shape[0])
    for _ in range(max_iterations):
        if active.size == 0:
            break
        value, gradient = central_gradient(f, points[active])
        norm_sq = np.maximum((gradient**2).sum(axis=1), 0.25)
        moving = np.abs(value) > tolerance
        points[active] -= gradient * (value * moving / norm_sq)[:, None]
        active = active[moving]
    return points


def refine_closed(f, points, spacing):
    """Subdivide a closed polyline on the zero set until no edge exceeds ``spacing`` (design units).

    Every inserted point is projected onto the zero set. An edge that stays long after a round of
    projection spans a sharp corner: there the intersection of the tangent lines at its two ends
    (exactly the corner of a polygon, close to it for a pointed arc) is inserted instead.
    """
    for round_ in range(40):
        nxt = np.roll(points, -1, axis=0)
        edge = np.linalg.norm(nxt - points, axis=1)
        long = np.flatnonzero(edge > spacing * (1 + 1e-9))
        if long.size == 0:
            break
        pieces = np.ones(len(points), int)
        pieces[long] = np.ceil(edge[long] / spacing).astype(int)
        extra = {}
        if round_ >= 2:  # projection alone has converged on smooth parts: what is left are corners
            # tangent lines at both ends, from the (short) neighbouring edges
            _, _, det, along, corner = _edge_crossings(points, nxt, long)
            middle = (points[long] + nxt[long]) / 2
            usable = ((np.abs(det) > 0.17) & (along > 1e-3 * spacing)
                      & (np.linalg.norm(corner - nxt[long], axis=1) > 1e-3 * spacing)
                      # an acute corner lies up to edge / (2 sin(theta / 2)) from its chord: the crossing of lines
                      # that turn by 180 - theta (|det| = sin theta) is accepted up to edge / |det| from the
                      # middle (edge alone cut the tips of a star's 36-degree points by 0.13 px)
                      & (np.linalg.norm(corner - middle, axis=1) <= edge[long] / np.abs(det)))
            for index, point in zip(long[usable], corner[usable]):
                extra[int(index)] = point
                pieces[index] = 2
        start = np.repeat(points, pieces, axis=0)
        delta = np.repeat(nxt - points, pieces, axis=0)
        fraction = np.concatenate([np.arange(k) / k for k in pieces])
        dense = start + fraction[:, None] * delta
        if extra:
            offsets = np.cumsum(pieces) - pieces
            for index, point in extra.items():
                dense[offsets[index] + 1] = point
        fresh = fraction > 0
        dense[fresh] = project(f, dense[fresh])
        points = dense
    return _with_short_corners(f, points)


def _edge_crossings(points, nxt, rows):
    """For the edges ``rows`` of the closed polyline ``points`` (``nxt``: each point's successor): the unit
    directions of the edges before and after each, the cross product of the two, and the crossing of their lines
    (``along``: its distance from the edge's start along the edge before; NaN or inf where they are parallel)."""
    before = points[rows] - np.roll(points, 1, axis=0)[rows]
    after = np.roll(points, -2, axis=0)[rows] - nxt[rows]
    before /= np.maximum(np.linalg.norm(before, axis=1), 1e-300)[:, None]
    after /= np.maximum(np.linalg.norm(after, axis=1), 1e-300)[:, None]
    det = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
    gap = nxt[rows] - points[rows]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        along = (gap[:, 0] * after[:, 1] - gap[:, 1] * after[:, 0]) / det
        corner = points[rows] + along[:, None] * before
    return before, after, det, along, corner


def _with_short_corners(f, points):
    """``points`` with the corners that a short edge cuts: where the edges before and after an edge turn by more
    than 30 degrees, the crossing of their lines is the corner (a reflex corner of a polygon sampled finely
    enough that no edge stays long: a star's inner vertices at 600 px were 0.028 px off); inserted where it lies
    on the zero set (to 1e-3 of the edge) and between the edge's ends."""
    nxt = np.roll(points, -1, axis=0)
    before, after, det, along, corner = _edge_crossings(points, nxt, np.arange(len(points)))
    turns = np.einsum("ij,ij->i", before, after) < np.cos(np.radians(30.0))
    edge = np.linalg.norm(nxt - points, axis=1)
    inside = (np.linalg.norm(corner - points, axis=1) < edge) & (np.linalg.norm(corner - nxt, axis=1) < edge)
    candidates = np.flatnonzero(turns & np.isfinite(along) & (along > 0) & inside
                                & (np.linalg.norm(corner - points, axis=1) > 1e-9 * edge)
                                & (np.linalg.norm(corner - nxt, axis=1) > 1e-9 * edge))
    if candidates.size == 0:
        return points
    on_set = np.abs(project(f, corner[candidates]) - corner[candidates]).max(axis=1) <= 1e-3 * edge[candidates]
    chosen = candidates[on_set]
    if chosen.size == 0:
        return points
    return np.insert(points, chosen + 1, corner[chosen], axis=0)
