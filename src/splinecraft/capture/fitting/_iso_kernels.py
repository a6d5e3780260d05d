"""Compiled distance from points to the iso-line of a smoothed bitmap, for the boundary noise estimate
(docs/capture.md §12, "Noisy boundaries"; :func:`~.noise.boundary_noise`).

The smoothed bitmap is ``scipy.ndimage.gaussian_filter(np.pad(mask, pad), sigma)`` and the iso-line is the
marching-squares polyline of ``skimage.measure.find_contours`` on it (same segments, same vertex
interpolation, same choice at saddle cells: low values fully connected), but neither is computed for the
whole image: the distance of each point is the exact distance to the nearest segment, found by searching
rings of grid cells outwards from the point's cell until no closer segment can remain, and a cell's
segments come from the smoothed values at its four corners, each computed when first needed and kept.
A smoothed value is scipy's separable correlation (``correlate1d`` along rows, then along columns, with its
symmetric-kernel summation order), so it is bit for bit ``gaussian_filter``'s, and the work is that of the
cells the search visits (a band a few pixels wide around the boundaries) instead of the whole image, kept in
small direct-mapped caches (:data:`CACHE_SIDE`) instead of arrays of the image's size, whose memory (written
once, a fresh allocation each call) cost more than the values.
numba, compiled on first use and cached on disk (``cache=True``); the compiled loops write into arrays their
wrappers allocate.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import HELPER_OPTIONS, JIT_OPTIONS, pyclip, pymax, pymin, union_join, union_root as _root

__all__ = ["gaussian_weights", "iso_line_distance", "large_pieces", "warm_up"]

_JIT = JIT_OPTIONS

#: Per marching-squares case (bits: upper left, upper right, lower left, lower right above the level) the
#: (from, to) ends of its one or two segments; ends 0 top, 1 bottom, 2 left, 3 right, -1 none. At the saddles
#: 6 and 9 the low values connect.
_CASE_ENDS = np.array([
    [-1, -1, -1, -1], [0, 2, -1, -1], [3, 0, -1, -1], [3, 2, -1, -1], [2, 1, -1, -1], [0, 1, -1, -1],
    [3, 0, 2, 1], [3, 1, -1, -1], [1, 3, -1, -1], [0, 2, 1, 3], [1, 0, -1, -1], [1, 2, -1, -1],
    [2, 3, -1, -1], [0, 3, -1, -1], [2, 0, -1, -1], [-1, -1, -1, -1]], dtype=np.int64)

#: Margin (px) by which a cell must lie farther from a point than the nearest segment found so far to be skipped
#: (:func:`_nearest_into`): far above the rounding of the distances (some 1e-12 px at 10^4 px), so a skipped cell's
#: segments are never nearer as computed either, and the result is that of the search of every cell.
_SLACK = 1e-6

_WEIGHTS = {}


def gaussian_weights(sigma):
    """The weights of ``scipy.ndimage.gaussian_filter1d(..., sigma)`` (offsets ``-radius..radius``), read off
    its response to a unit impulse (exact: the other terms of each sum are zeros)."""
    sigma = float(sigma)
    if sigma not in _WEIGHTS:
        from scipy.ndimage import gaussian_filter1d

        radius = int(4.0 * sigma + 0.5)  # scipy's default truncate=4.0
        impulse = np.zeros(4 * radius + 3)
        impulse[2 * radius + 1] = 1.0
        response = gaussian_filter1d(impulse, sigma, mode="constant")
        _WEIGHTS[sigma] = np.ascontiguousarray(response[radius + 1: 3 * radius + 2])
    return _WEIGHTS[sigma]


@njit(**dict(HELPER_OPTIONS, forceinline=False))  # inlined where LLVM sees fit (forced: 2.5x the code)
def _smoothed(ink, weights, r, c, cols, smooth, smooth_tag, row_memo, row_tag):
    """``gaussian_filter(np.pad(mask, pad), sigma)[r, c]`` (a grid of ``cols`` columns) in scipy's arithmetic:
    the correlation along columns (axis 1) of the correlation along rows (axis 0), each ``correlate1d``'s
    symmetric sum, the centre term first, then the pairs from the farthest in (``(x[-j] + x[j]) w[-j]``).
    ``ink`` is the padded bitmap (1 on ink, 0 elsewhere and in the ``pad`` border) with ``radius`` more rows of 0
    above and below; outside the padded image the row pass is 0 (``pad >= radius``: scipy's reflection reads the
    border).

    Both passes are kept in direct-mapped caches: the value of grid point ``(r, c)`` in slot
    ``(r mod side, c mod side)`` of ``smooth`` (the row pass: ``row_memo``), tagged ``r * cols + c`` in
    ``smooth_tag`` (``row_tag``; -1 empty). A value another grid point displaced is computed again, the same.
    ``side`` (the caches' shape, a power of two) exceeds ``2 radius + 1``: the row-pass values one smoothed value
    reads share no slot."""
    radius, side = weights.shape[0] // 2, smooth.shape[0]
    low = side - 1
    slot_r = r & low
    tag = r * cols + c
    if smooth_tag[slot_r, c & low] == tag:
        return smooth[slot_r, c & low]
    for cc in range(pymax(c - radius, 0), pymin(c + radius + 1, cols)):
        if row_tag[slot_r, cc & low] == r * cols + cc:
            continue
        total = ink[r + radius, cc] * weights[radius]
        for j in range(-radius, 0):
            total += (ink[r + radius + j, cc] + ink[r + radius - j, cc]) * weights[radius + j]
        row_memo[slot_r, cc & low], row_tag[slot_r, cc & low] = total, r * cols + cc
    total = row_memo[slot_r, c & low] * weights[radius]
    for j in range(-radius, 0):
        left = row_memo[slot_r, (c + j) & low] if c + j >= 0 else 0.0
        right = row_memo[slot_r, (c - j) & low] if c - j < cols else 0.0
        total += (left + right) * weights[radius + j]
    smooth[slot_r, c & low], smooth_tag[slot_r, c & low] = total, tag
    return total


@njit(**_JIT)
def _nearest_into(points, ink, pad, weights, level, table, smooth, smooth_tag, row_memo, row_tag, ends, out):
    """Ring search per point (see :func:`iso_line_distance`), reading the smoothed values of each visited cell's
    corners from :func:`_smoothed`'s caches (computed when missing); stops after a point that finds no segment in
    the whole grid (then no point can: returns False).

    The 0-2 marching-squares segments of a cell end on its sides (0 top, 1 bottom, 2 left, 3 right), where
    the level crosses between the side's two corners, ``from + (level - v_from) / (v_to - v_from)`` (0 when
    they are equal), as ``find_contours`` interpolates; their ends go to ``ends`` in the output frame
    (``x = column - pad + 0.5``), and the distance to a segment is exact (foot point clipped to it)."""
    cols = ink.shape[1]
    grid_rows, grid_cols = ink.shape[0] - weights.shape[0], cols - 1
    reach, low = pymax(grid_rows, grid_cols), smooth.shape[0] - 1
    for j in range(points.shape[0]):
        px, py = points[j, 0], points[j, 1]
        row = pyclip(np.int64(np.floor(py - 0.5 + pad)), 0, grid_rows - 1)
        col = pyclip(np.int64(np.floor(px - 0.5 + pad)), 0, grid_cols - 1)
        grid_y, grid_x = py - 0.5 + pad, px - 0.5 + pad  # the point in the grid's frame (cell r0: rows r0..r0 + 1)
        best = np.inf
        for ring in range(reach + 1):
            for r0 in range(pymax(row - ring, 0), pymin(row + ring, grid_rows - 1) + 1):
                step = 1 if abs(r0 - row) == ring else 2 * ring
                gap_y = pymax(pymax(r0 - grid_y, grid_y - (r0 + 1)), 0.0)
                for c0 in range(col - ring, col + ring + 1, step):
                    if c0 < 0 or c0 >= grid_cols:
                        continue
                    # a cell no nearer than the nearest segment so far holds no nearer segment: skipped
                    gap_x = pymax(pymax(c0 - grid_x, grid_x - (c0 + 1)), 0.0)
                    within = best + _SLACK
                    if gap_y * gap_y + gap_x * gap_x >= within * within:
                        continue
                    for rr in (r0, r0 + 1):  # the corners' values (cached in four distinct slots)
                        for cc in (c0, c0 + 1):
                            if smooth_tag[rr & low, cc & low] != rr * cols + cc:
                                _smoothed(ink, weights, rr, cc, cols, smooth, smooth_tag, row_memo, row_tag)
                    upper_left, upper_right = smooth[r0 & low, c0 & low], smooth[r0 & low, (c0 + 1) & low]
                    lower_left, lower_right = smooth[(r0 + 1) & low, c0 & low], smooth[(r0 + 1) & low, (c0 + 1) & low]
                    code = ((upper_left > level) * 1 + (upper_right > level) * 2 + (lower_left > level) * 4
                            + (lower_right > level) * 8)
                    for q in (0, 2):
                        if table[code, q] < 0:
                            break
                        for e in range(2):
                            which = table[code, q + e]
                            if which == 0:
                                start, stop = upper_left, upper_right
                            elif which == 1:
                                start, stop = lower_left, lower_right
                            elif which == 2:
                                start, stop = upper_left, lower_left
                            else:
                                start, stop = upper_right, lower_right
                            fraction = 0.0 if stop == start else (level - start) / (stop - start)
                            if which < 2:  # along a row: (row, column + fraction)
                                y, x = float(r0 + which), c0 + fraction
                            else:          # along a column: (row + fraction, column)
                                y, x = r0 + fraction, float(c0 + which - 2)
                            ends[2 * e], ends[2 * e + 1] = x - pad + 0.5, y - pad + 0.5
                        abx, aby = ends[2] - ends[0], ends[3] - ends[1]
                        apx, apy = px - ends[0], py - ends[1]
                        denom = abx * abx + aby * aby
                        t = pyclip((apx * abx + apy * aby) / (denom if denom > 0 else 1.0), 0.0, 1.0)
                        dx, dy = apx - t * abx, apy - t * aby
                        best = pymin(best, np.sqrt(dx * dx + dy * dy))
            if best <= ring:
                break
        out[j] = best
        if best == np.inf:
            return False
    return True


#: Side (cells, a power of two) of the direct-mapped caches of smoothed and row-pass values (:func:`_smoothed`):
#: 64 x 64 of each, 128 kB in all whatever the image's size. The ring searches of points that follow each other
#: along a boundary read nearby grid points, so few are displaced before they are read again.
CACHE_SIDE = 64


def iso_line_distance(points, mask, sigma, pad, level=0.5, cache_side=CACHE_SIDE):
    """Distance from every point (output frame: ``x = column + 0.5``, ``y = row + 0.5`` of ``mask``) to the
    nearest segment of the ``level`` iso-line of ``gaussian_filter(np.pad(mask, pad), sigma)`` (values
    ``> level`` are high; at a saddle the low values connect); ``None`` when that iso-line is empty.
    Segments lie in their unit cell, so after the cells within Chebyshev ring ``R`` of the point's cell every
    unvisited segment is at least ``R`` away; within a ring, a cell no nearer to the point than the nearest segment
    found so far (by more than :data:`_SLACK`) is skipped, its smoothed values unread (a crack midpoint lies on a
    grid line: the two cells beside it, not the nine of rings 0 and 1, unless its distance exceeds 0.5 px).
    ``cache_side``: of the caches of smoothed values (the results
    do not depend on it)."""
    return _distances(points, mask, gaussian_weights(sigma), pad, level, cache_side)


def _distances(points, mask, weights, pad, level, cache_side):
    """:func:`iso_line_distance` with the Gaussian's ``weights`` given (:func:`warm_up` compiles the kernel with
    weights of its own: :func:`gaussian_weights` imports scipy.ndimage, 0.17 s of a helper process's start;
    docs/capture.md, "Cold kernels compile in parallel")."""
    mask = np.ascontiguousarray(mask, dtype=np.bool_)
    pad = int(pad)
    if pad < weights.shape[0] // 2:
        raise ValueError(f"pad: must be at least the Gaussian's radius {weights.shape[0] // 2}, got {pad}")
    side = int(cache_side)
    if side & (side - 1) or side <= weights.shape[0]:
        raise ValueError(f"cache_side: must be a power of two above {weights.shape[0]}, got {cache_side}")
    points = np.ascontiguousarray(points, dtype=np.float64)
    out = np.full(points.shape[0], np.inf)
    rows, cols = mask.shape[0] + 2 * pad, mask.shape[1] + 2 * pad
    if not points.shape[0] or rows < 2 or cols < 2:
        return out
    radius = weights.shape[0] // 2
    ink = np.zeros((rows + 2 * radius, cols), np.uint8)   # the padded bitmap, ``radius`` more rows of 0 above, below
    ink[pad + radius: pad + radius + mask.shape[0], pad: pad + mask.shape[1]] = mask
    smooth, row_memo = np.empty((side, side)), np.empty((side, side))
    smooth_tag, row_tag = np.full((side, side), -1, np.int64), np.full((side, side), -1, np.int64)
    if not _nearest_into(points, ink, pad, weights, float(level), _CASE_ENDS, smooth, smooth_tag, row_memo,
                         row_tag, np.empty(4), out):
        return None
    return out


@njit(**_JIT)
def _large_pieces_into(flat, width, min_area, parent, size, keep):
    """Whether each pixel at the sorted flat indices ``flat`` of a bool image ``width`` pixels wide (its first and last
    columns empty: no piece wraps from one row to the next) lies in an 8-connected piece of at least ``min_area`` of
    them, into ``keep``: union-find over each pixel's neighbours ahead (the next in its row, the three below it, found
    by a pointer that walks ``flat`` once), then the pieces' sizes counted at their roots. ``parent``, ``size``:
    work."""
    count = flat.shape[0]
    for k in range(count):
        parent[k] = k
        size[k] = 0
    below = 0
    for k in range(count):
        here = flat[k]
        if k + 1 < count and flat[k + 1] == here + 1:
            union_join(parent, k, k + 1)
        while below < count and flat[below] < here + width - 1:
            below += 1
        q = below
        while q < count and flat[q] <= here + width + 1:
            union_join(parent, k, q)
            q += 1
    for k in range(count):
        size[_root(parent, k)] += 1
    for k in range(count):
        keep[k] = size[_root(parent, k)] >= min_area


def large_pieces(flat, width, min_area):
    """Which of the pixels at the sorted flat indices ``flat`` of a bool image ``width`` pixels wide, whose first and
    last columns are empty, lie in 8-connected pieces of at least ``min_area`` of them (``scipy.ndimage.label`` with
    the 3 x 3 square, then the pieces' sizes: the same pieces, in time linear in the pixels given instead of the
    image's size)."""
    flat = np.ascontiguousarray(flat, dtype=np.int64)
    count = flat.shape[0]
    keep = np.empty(count, np.bool_)
    _large_pieces_into(flat, int(width), int(min_area), np.empty(count, np.int64), np.empty(count, np.int64), keep)
    return keep


_WARM = []


def warm_up():
    """Compile or load the kernels once per process (see :func:`._kernels.warm_up`)."""
    if _WARM:
        return
    mask = np.zeros((3, 3), bool)
    mask[1, 1:] = True
    large_pieces(np.array([1, 2, 6]), 5, 2)  # before the distances: their kernel tells whether the task is warm
    _distances(np.ones((1, 2)), mask, np.array([0.25, 0.5, 0.25]), 4, 0.5, CACHE_SIDE)
    _WARM.append(True)
