"""Compiled distance from points to the iso-line of a smoothed bitmap, for the boundary noise estimate
(docs/capture.md §12, "Noisy boundaries"; :func:`~.noise.boundary_noise`).

The iso-line is the marching-squares polyline of ``skimage.measure.find_contours`` (same segments, same
direction, same vertex interpolation, same choice at saddle cells: low values fully connected), but it is
never assembled into polylines: the segments are filed by the grid cell they cross (raster order), and the
distance of each point is the exact distance to the nearest segment, found by searching rings of cells
outwards until no closer segment can remain. numba, compiled on first use and cached on disk
(``cache=True``); the compiled loops write into arrays their wrappers allocate.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ._jit import JIT_OPTIONS

__all__ = ["iso_segments", "nearest_segment_distance", "warm_up"]

_JIT = JIT_OPTIONS

#: Per marching-squares case (bits: upper left, upper right, lower left, lower right above the level) the
#: (from, to) ends of its one or two segments; ends 0 top, 1 bottom, 2 left, 3 right, -1 none. At the saddles
#: 6 and 9 the low values connect.
_CASE_ENDS = np.array([
    [-1, -1, -1, -1], [0, 2, -1, -1], [3, 0, -1, -1], [3, 2, -1, -1], [2, 1, -1, -1], [0, 1, -1, -1],
    [3, 0, 2, 1], [3, 1, -1, -1], [1, 3, -1, -1], [0, 2, 1, 3], [1, 0, -1, -1], [1, 2, -1, -1],
    [2, 3, -1, -1], [0, 3, -1, -1], [2, 0, -1, -1], [-1, -1, -1, -1]], dtype=np.int64)


@njit(**_JIT)
def _fraction(from_value, to_value, level):
    if to_value == from_value:
        return 0.0
    return (level - from_value) / (to_value - from_value)


@njit(**_JIT)
def _end(image, level, r0, c0, which):
    """(row, column) of end ``which`` (0 top, 1 bottom, 2 left, 3 right) of the cell at ``r0, c0``."""
    if which == 0:
        return float(r0), c0 + _fraction(image[r0, c0], image[r0, c0 + 1], level)
    if which == 1:
        return float(r0 + 1), c0 + _fraction(image[r0 + 1, c0], image[r0 + 1, c0 + 1], level)
    if which == 2:
        return r0 + _fraction(image[r0, c0], image[r0 + 1, c0], level), float(c0)
    return r0 + _fraction(image[r0, c0 + 1], image[r0 + 1, c0 + 1], level), float(c0 + 1)


@njit(**_JIT)
def _cases_into(image, level, table, case):
    """The marching-squares case of every cell into ``case``; returns the number of segments."""
    count = 0
    for r0 in range(image.shape[0] - 1):
        for c0 in range(image.shape[1] - 1):
            code = ((image[r0, c0] > level) * 1 + (image[r0, c0 + 1] > level) * 2
                    + (image[r0 + 1, c0] > level) * 4 + (image[r0 + 1, c0 + 1] > level) * 8)
            case[r0, c0] = code
            count += (table[code, 0] >= 0) + (table[code, 2] >= 0)
    return count


@njit(**_JIT)
def _segments_into(image, level, pad, case, table, segments, cells):
    cols = image.shape[1]
    row = 0
    for r0 in range(image.shape[0] - 1):
        for c0 in range(cols - 1):
            code = case[r0, c0]
            for q in (0, 2):
                a, b = table[code, q], table[code, q + 1]
                if a < 0:
                    break
                ra, ca = _end(image, level, r0, c0, a)
                rb, cb = _end(image, level, r0, c0, b)
                segments[row, 0], segments[row, 1] = ca - pad + 0.5, ra - pad + 0.5
                segments[row, 2], segments[row, 3] = cb - pad + 0.5, rb - pad + 0.5
                cells[row] = r0 * (cols - 1) + c0
                row += 1


def iso_segments(image, level, pad):
    """Marching-squares segments of ``image`` at ``level`` (values ``> level`` are high; at a saddle the low
    values connect), in the output frame ``x = column - pad + 0.5``, ``y = row - pad + 0.5``: an array (s, 4)
    of ``x0, y0, x1, y1`` and the row-major index of the cell of each segment, in raster order."""
    image = np.ascontiguousarray(image, dtype=np.float64)
    case = np.empty((image.shape[0] - 1, image.shape[1] - 1), np.int64)
    count = _cases_into(image, float(level), _CASE_ENDS, case)
    segments, cells = np.empty((count, 4)), np.empty(count, np.int64)
    _segments_into(image, float(level), float(pad), case, _CASE_ENDS, segments, cells)
    return segments, cells


@njit(**_JIT)
def _segment_distance(px, py, segments, s):
    """Exact distance from ``(px, py)`` to the segment ``segments[s]`` = ``x0, y0 -> x1, y1``."""
    abx, aby = segments[s, 2] - segments[s, 0], segments[s, 3] - segments[s, 1]
    apx, apy = px - segments[s, 0], py - segments[s, 1]
    denom = abx * abx + aby * aby
    t = (apx * abx + apy * aby) / (denom if denom > 0 else 1.0)
    t = min(max(t, 0.0), 1.0)
    dx, dy = apx - t * abx, apy - t * aby
    return np.sqrt(dx * dx + dy * dy)


@njit(**_JIT)
def _nearest_into(points, segments, first, grid_rows, grid_cols, pad, out):
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
                    g = r * grid_cols + c
                    for s in range(first[g], first[g + 1]):
                        d = _segment_distance(px, py, segments, s)
                        if d < best:
                            best = d
            if best <= ring:
                break
        out[j] = best


def nearest_segment_distance(points, segments, cells, rows, cols, pad):
    """Distance from every point (output frame) to the nearest segment of :func:`iso_segments` of an image
    of ``rows`` x ``cols`` values (``inf`` when there is none). Segments lie in their unit cell, so after the
    cells within Chebyshev ring ``R`` of the point's cell every unvisited segment is at least ``R`` away."""
    points = np.ascontiguousarray(points, dtype=np.float64)
    out = np.full(points.shape[0], np.inf)
    if not segments.shape[0]:
        return out
    grid_rows, grid_cols = rows - 1, cols - 1
    first = np.searchsorted(cells, np.arange(grid_rows * grid_cols + 1)).astype(np.int64)  # cells are sorted
    _nearest_into(points, np.ascontiguousarray(segments, dtype=np.float64), first, grid_rows, grid_cols, float(pad),
                  out)
    return out


_WARM = []


def warm_up():
    """Compile or load the kernels once per process (see :func:`._kernels.warm_up`)."""
    if _WARM:
        return
    image = np.zeros((4, 4))
    image[1:3, 1:3] = 1.0
    segments, cells = iso_segments(image, 0.5, 1)
    nearest_segment_distance(np.ones((1, 2)), segments, cells, 4, 4, 1)
    _WARM.append(True)
