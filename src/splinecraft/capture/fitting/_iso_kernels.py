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
def _ink(mask, pad, r, c):
    """The padded bitmap (ink 1.0, the ``pad`` border and beyond 0.0) at row ``r``, column ``c``."""
    r, c = r - pad, c - pad
    if r < 0 or c < 0 or r >= mask.shape[0] or c >= mask.shape[1]:
        return 0.0
    return 1.0 if mask[r, c] else 0.0


@njit(**_JIT)
def _row_pass(mask, pad, weights, r, c):
    """The correlation along rows (axis 0) at ``(r, c)``: ``correlate1d``'s symmetric sum, the centre term
    first, then the pairs from the farthest in (``(x[-j] + x[j]) w[-j]``)."""
    radius = weights.shape[0] // 2
    total = _ink(mask, pad, r, c) * weights[radius]
    for j in range(-radius, 0):
        total += (_ink(mask, pad, r + j, c) + _ink(mask, pad, r - j, c)) * weights[radius + j]
    return total


@njit(**_JIT)
def _smooth_into(mask, pad, weights, r, c, smooth, known, row_memo, row_known):
    """``smooth[r, c] = gaussian_filter(np.pad(mask, pad), sigma)[r, c]``: the correlation along columns
    (axis 1) of the row pass (kept in ``row_memo``); outside the padded image the row pass is 0
    (``pad >= radius``: scipy's reflection there reads the zeros of the border)."""
    radius, cols = weights.shape[0] // 2, smooth.shape[1]
    for cc in range(max(c - radius, 0), min(c + radius + 1, cols)):
        if not row_known[r, cc]:
            row_memo[r, cc], row_known[r, cc] = _row_pass(mask, pad, weights, r, cc), 1
    total = row_memo[r, c] * weights[radius]
    for j in range(-radius, 0):
        left = row_memo[r, c + j] if c + j >= 0 else 0.0
        right = row_memo[r, c - j] if c - j < cols else 0.0
        total += (left + right) * weights[radius + j]
    smooth[r, c], known[r, c] = total, 1


@njit(**_JIT)
def _fraction(from_value, to_value, level):
    if to_value == from_value:
        return 0.0
    return (level - from_value) / (to_value - from_value)


@njit(**_JIT)
def _end(corners, level, r0, c0, which):
    """(row, column) of end ``which`` (0 top, 1 bottom, 2 left, 3 right) of the cell at ``r0, c0`` whose
    corner values are ``corners`` = (upper left, upper right, lower left, lower right)."""
    if which == 0:
        return float(r0), c0 + _fraction(corners[0], corners[1], level)
    if which == 1:
        return float(r0 + 1), c0 + _fraction(corners[2], corners[3], level)
    if which == 2:
        return r0 + _fraction(corners[0], corners[2], level), float(c0)
    return r0 + _fraction(corners[1], corners[3], level), float(c0 + 1)


@njit(**_JIT)
def _segment_distance(px, py, x0, y0, x1, y1):
    """Exact distance from ``(px, py)`` to the segment ``x0, y0 -> x1, y1``."""
    abx, aby = x1 - x0, y1 - y0
    apx, apy = px - x0, py - y0
    denom = abx * abx + aby * aby
    t = (apx * abx + apy * aby) / (denom if denom > 0 else 1.0)
    t = min(max(t, 0.0), 1.0)
    dx, dy = apx - t * abx, apy - t * aby
    return np.sqrt(dx * dx + dy * dy)


@njit(**_JIT)
def _cell_distance(px, py, r0, c0, pad, level, table, smooth, corners):
    """Distance from ``(px, py)`` (output frame ``x = column - pad + 0.5``) to the nearest of the 0-2
    marching-squares segments of cell ``r0, c0`` (``inf`` when it has none); its corner values are known."""
    corners[0], corners[1] = smooth[r0, c0], smooth[r0, c0 + 1]
    corners[2], corners[3] = smooth[r0 + 1, c0], smooth[r0 + 1, c0 + 1]
    code = (corners[0] > level) * 1 + (corners[1] > level) * 2 + (corners[2] > level) * 4 + (corners[3] > level) * 8
    best = np.inf
    for q in (0, 2):
        a, b = table[code, q], table[code, q + 1]
        if a < 0:
            break
        ra, ca = _end(corners, level, r0, c0, a)
        rb, cb = _end(corners, level, r0, c0, b)
        d = _segment_distance(px, py, ca - pad + 0.5, ra - pad + 0.5, cb - pad + 0.5, rb - pad + 0.5)
        if d < best:
            best = d
    return best


@njit(**_JIT)
def _nearest_into(points, mask, pad, weights, level, table, smooth, known, row_memo, row_known, corners, out):
    """Ring search per point (see :func:`iso_line_distance`), computing the smoothed values of each visited
    cell's corners when first needed; stops after a point that finds no segment in the whole grid (then no
    point can: returns False)."""
    grid_rows, grid_cols = smooth.shape[0] - 1, smooth.shape[1] - 1
    reach = max(grid_rows, grid_cols)
    for j in range(points.shape[0]):
        px, py = points[j, 0], points[j, 1]
        row = min(max(int(np.floor(py - 0.5 + pad)), 0), grid_rows - 1)
        col = min(max(int(np.floor(px - 0.5 + pad)), 0), grid_cols - 1)
        best = np.inf
        for ring in range(reach + 1):
            for r in range(max(row - ring, 0), min(row + ring, grid_rows - 1) + 1):
                step = 1 if abs(r - row) == ring else 2 * ring
                for c in range(col - ring, col + ring + 1, step):
                    if c < 0 or c >= grid_cols:
                        continue
                    for rr in (r, r + 1):
                        for cc in (c, c + 1):
                            if not known[rr, cc]:
                                _smooth_into(mask, pad, weights, rr, cc, smooth, known, row_memo, row_known)
                    d = _cell_distance(px, py, r, c, pad, level, table, smooth, corners)
                    if d < best:
                        best = d
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
