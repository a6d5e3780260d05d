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
cells the search visits (a band a few pixels wide around the boundaries) instead of the whole image.
numba, compiled on first use and cached on disk (``cache=True``); the compiled loops write into arrays their
wrappers allocate.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import JIT_OPTIONS

__all__ = ["gaussian_weights", "iso_line_distance", "warm_up"]

_JIT = JIT_OPTIONS

#: Per marching-squares case (bits: upper left, upper right, lower left, lower right above the level) the
#: (from, to) ends of its one or two segments; ends 0 top, 1 bottom, 2 left, 3 right, -1 none. At the saddles
#: 6 and 9 the low values connect.
_CASE_ENDS = np.array([
    [-1, -1, -1, -1], [0, 2, -1, -1], [3, 0, -1, -1], [3, 2, -1, -1], [2, 1, -1, -1], [0, 1, -1, -1],
    [3, 0, 2, 1], [3, 1, -1, -1], [1, 3, -1, -1], [0, 2, 1, 3], [1, 0, -1, -1], [1, 2, -1, -1],
    [2, 3, -1, -1], [0, 3, -1, -1], [2, 0, -1, -1], [-1, -1, -1, -1]], dtype=np.int64)

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


@njit(**_JIT)
def _smooth_into(mask, pad, weights, r, c, smooth, known, row_memo, row_known):
    """``smooth[r, c] = gaussian_filter(np.pad(mask, pad), sigma)[r, c]`` in scipy's arithmetic: the
    correlation along columns (axis 1) of the correlation along rows (axis 0, kept in ``row_memo``), each
    ``correlate1d``'s symmetric sum, the centre term first, then the pairs from the farthest in
    (``(x[-j] + x[j]) w[-j]``). The padded bitmap is 1.0 on ink, 0.0 elsewhere and in the ``pad`` border;
    outside the padded image the row pass is 0 (``pad >= radius``: scipy's reflection reads the border)."""
    radius, rows, cols = weights.shape[0] // 2, mask.shape[0], mask.shape[1]
    for cc in range(max(c - radius, 0), min(c + radius + 1, smooth.shape[1])):
        if row_known[r, cc]:
            continue
        column = cc - pad
        inside = 0 <= column < cols
        total = (1.0 if inside and 0 <= r - pad < rows and mask[r - pad, column] else 0.0) * weights[radius]
        for j in range(-radius, 0):
            up, down = r - pad + j, r - pad - j
            above = 1.0 if inside and 0 <= up < rows and mask[up, column] else 0.0
            below = 1.0 if inside and 0 <= down < rows and mask[down, column] else 0.0
            total += (above + below) * weights[radius + j]
        row_memo[r, cc], row_known[r, cc] = total, 1
    total = row_memo[r, c] * weights[radius]
    for j in range(-radius, 0):
        left = row_memo[r, c + j] if c + j >= 0 else 0.0
        right = row_memo[r, c - j] if c - j < smooth.shape[1] else 0.0
        total += (left + right) * weights[radius + j]
    smooth[r, c], known[r, c] = total, 1


@njit(**_JIT)
def _nearest_into(points, mask, pad, weights, level, table, smooth, known, row_memo, row_known, ends, out):
    """Ring search per point (see :func:`iso_line_distance`), computing the smoothed values of each visited
    cell's corners when first needed; stops after a point that finds no segment in the whole grid (then no
    point can: returns False).

    The 0-2 marching-squares segments of a cell end on its sides (0 top, 1 bottom, 2 left, 3 right), where
    the level crosses between the side's two corners, ``from + (level - v_from) / (v_to - v_from)`` (0 when
    they are equal), as ``find_contours`` interpolates; their ends go to ``ends`` in the output frame
    (``x = column - pad + 0.5``), and the distance to a segment is exact (foot point clipped to it)."""
    grid_rows, grid_cols = smooth.shape[0] - 1, smooth.shape[1] - 1
    reach = max(grid_rows, grid_cols)
    for j in range(points.shape[0]):
        px, py = points[j, 0], points[j, 1]
        row = min(max(int(np.floor(py - 0.5 + pad)), 0), grid_rows - 1)
        col = min(max(int(np.floor(px - 0.5 + pad)), 0), grid_cols - 1)
        best = np.inf
        for ring in range(reach + 1):
            for r0 in range(max(row - ring, 0), min(row + ring, grid_rows - 1) + 1):
                step = 1 if abs(r0 - row) == ring else 2 * ring
                for c0 in range(col - ring, col + ring + 1, step):
                    if c0 < 0 or c0 >= grid_cols:
                        continue
                    for rr in (r0, r0 + 1):
                        for cc in (c0, c0 + 1):
                            if not known[rr, cc]:
                                _smooth_into(mask, pad, weights, rr, cc, smooth, known, row_memo, row_known)
                    upper_left, upper_right = smooth[r0, c0], smooth[r0, c0 + 1]
                    lower_left, lower_right = smooth[r0 + 1, c0], smooth[r0 + 1, c0 + 1]
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
                        t = min(max((apx * abx + apy * aby) / (denom if denom > 0 else 1.0), 0.0), 1.0)
                        dx, dy = apx - t * abx, apy - t * aby
                        best = min(best, np.sqrt(dx * dx + dy * dy))
            if best <= ring:
                break
        out[j] = best
        if best == np.inf:
            return False
    return True


def iso_line_distance(points, mask, sigma, pad, level=0.5):
    """Distance from every point (output frame: ``x = column + 0.5``, ``y = row + 0.5`` of ``mask``) to the
    nearest segment of the ``level`` iso-line of ``gaussian_filter(np.pad(mask, pad), sigma)`` (values
    ``> level`` are high; at a saddle the low values connect); ``None`` when that iso-line is empty.
    Segments lie in their unit cell, so after the cells within Chebyshev ring ``R`` of the point's cell every
    unvisited segment is at least ``R`` away."""
    mask = np.ascontiguousarray(mask, dtype=np.bool_)
    weights = gaussian_weights(sigma)
    pad = int(pad)
    if pad < weights.shape[0] // 2:
        raise ValueError(f"pad: must be at least the Gaussian's radius {weights.shape[0] // 2}, got {pad}")
    points = np.ascontiguousarray(points, dtype=np.float64)
    out = np.full(points.shape[0], np.inf)
    rows, cols = mask.shape[0] + 2 * pad, mask.shape[1] + 2 * pad
    if not points.shape[0] or rows < 2 or cols < 2:
        return out
    smooth, row_memo = np.empty((rows, cols)), np.empty((rows, cols))
    known, row_known = np.zeros((rows, cols), np.uint8), np.zeros((rows, cols), np.uint8)
    if not _nearest_into(points, mask, pad, weights, float(level), _CASE_ENDS, smooth, known, row_memo, row_known,
                         np.empty(4), out):
        return None
    return out


_WARM = []


def warm_up():
    """Compile or load the kernels once per process (see :func:`._kernels.warm_up`)."""
    if _WARM:
        return
    mask = np.zeros((3, 3), bool)
    mask[1, 1:] = True
    iso_line_distance(np.ones((1, 2)), mask, 1.0, 4)
    _WARM.append(True)
