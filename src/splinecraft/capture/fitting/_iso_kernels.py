"""Compiled distance from points to the iso-line of a smoothed bitmap, for the boundary noise estimate
(docs/capture.md §12, "Noisy boundaries"; :func:`~.noise.boundary_noise`).

The iso-line is the marching-squares polyline of ``skimage.measure.find_contours`` (same segments, same
vertex interpolation, same choice at saddle cells: low values fully connected), but it is never assembled
into polylines: the segments are bucketed by the grid cell they cross, and the distance of each point is
the exact distance to the nearest segment, found by searching rings of cells outwards until no closer
segment can remain. numba, compiled on first use and cached on disk (``cache=True``).
"""
from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["iso_segments", "nearest_segment_distance"]


@njit(cache=True, nogil=True)
def _fraction(from_value, to_value, level):
    if to_value == from_value:
        return 0.0
    return (level - from_value) / (to_value - from_value)


@njit(cache=True, nogil=True)
def iso_segments(image, level, pad):
    """Marching-squares segments of ``image`` at ``level`` (cells with a value ``> level`` are high; at a
    saddle the low values connect), in the output frame ``x = column - pad + 0.5``, ``y = row - pad + 0.5``:
    an array (s, 4) of ``x0, y0, x1, y1`` and the row-major index of the cell of each segment."""
    rows, cols = image.shape
    capacity = 64
    segments = np.empty((capacity, 4))
    cells = np.empty(capacity, np.int64)
    count = 0
    ends = np.empty((4, 2))  # top, bottom, left, right as (row, column)
    for r0 in range(rows - 1):
        for c0 in range(cols - 1):
            ul, ur = image[r0, c0], image[r0, c0 + 1]
            ll, lr = image[r0 + 1, c0], image[r0 + 1, c0 + 1]
            case = (ul > level) * 1 + (ur > level) * 2 + (ll > level) * 4 + (lr > level) * 8
            if case == 0 or case == 15:
                continue
            ends[0, 0], ends[0, 1] = r0, c0 + _fraction(ul, ur, level)
            ends[1, 0], ends[1, 1] = r0 + 1, c0 + _fraction(ll, lr, level)
            ends[2, 0], ends[2, 1] = r0 + _fraction(ul, ll, level), c0
            ends[3, 0], ends[3, 1] = r0 + _fraction(ur, lr, level), c0 + 1
            # (from, to) ends of the one or two segments of each case; 0 top, 1 bottom, 2 left, 3 right
            if case == 1:
                pairs = ((0, 2), (-1, -1))
            elif case == 2:
                pairs = ((3, 0), (-1, -1))
            elif case == 3:
                pairs = ((3, 2), (-1, -1))
            elif case == 4:
                pairs = ((2, 1), (-1, -1))
            elif case == 5:
                pairs = ((0, 1), (-1, -1))
            elif case == 6:
                pairs = ((3, 0), (2, 1))
            elif case == 7:
                pairs = ((3, 1), (-1, -1))
            elif case == 8:
                pairs = ((1, 3), (-1, -1))
            elif case == 9:
                pairs = ((0, 2), (1, 3))
            elif case == 10:
                pairs = ((1, 0), (-1, -1))
            elif case == 11:
                pairs = ((1, 2), (-1, -1))
            elif case == 12:
                pairs = ((2, 3), (-1, -1))
            elif case == 13:
                pairs = ((0, 3), (-1, -1))
            else:
                pairs = ((2, 0), (-1, -1))
            for a, b in pairs:
                if a < 0:
                    continue
                if count == capacity:
                    capacity *= 2
                    grown = np.empty((capacity, 4))
                    grown[:count] = segments[:count]
                    segments = grown
                    grown_cells = np.empty(capacity, np.int64)
                    grown_cells[:count] = cells[:count]
                    cells = grown_cells
                segments[count, 0] = ends[a, 1] - pad + 0.5
                segments[count, 1] = ends[a, 0] - pad + 0.5
                segments[count, 2] = ends[b, 1] - pad + 0.5
                segments[count, 3] = ends[b, 0] - pad + 0.5
                cells[count] = r0 * (cols - 1) + c0
                count += 1
    return segments[:count], cells[:count]


@njit(cache=True, nogil=True)
def _segment_distance(px, py, segment):
    """Exact distance from ``(px, py)`` to the segment ``x0, y0 -> x1, y1``."""
    abx, aby = segment[2] - segment[0], segment[3] - segment[1]
    apx, apy = px - segment[0], py - segment[1]
    denom = abx * abx + aby * aby
    t = (apx * abx + apy * aby) / (denom if denom > 0 else 1.0)
    t = min(max(t, 0.0), 1.0)
    dx, dy = apx - t * abx, apy - t * aby
    return np.sqrt(dx * dx + dy * dy)


@njit(cache=True, nogil=True)
def nearest_segment_distance(points, segments, cells, rows, cols, pad):
    """Distance from every point (output frame) to the nearest segment of :func:`iso_segments` of an image
    of ``rows`` x ``cols`` values (``inf`` when there is none). Segments lie in their unit cell, so after the
    cells within Chebyshev ring ``R`` of the point's cell every unvisited segment is at least ``R`` away."""
    grid_rows, grid_cols = rows - 1, cols - 1
    order = np.argsort(cells, kind="mergesort")
    first = np.zeros(grid_rows * grid_cols + 1, np.int64)
    for s in range(cells.shape[0]):
        first[cells[s] + 1] += 1
    for g in range(grid_rows * grid_cols):
        first[g + 1] += first[g]
    out = np.full(points.shape[0], np.inf)
    if cells.shape[0] == 0:
        return out
    reach = max(grid_rows, grid_cols)
    for j in range(points.shape[0]):
        px, py = points[j, 0], points[j, 1]
        row = min(max(int(np.floor(py - 0.5 + pad)), 0), grid_rows - 1)
        col = min(max(int(np.floor(px - 0.5 + pad)), 0), grid_cols - 1)
        best = np.inf
        for ring in range(reach + 1):
            for r in range(row - ring, row + ring + 1):
                if r < 0 or r >= grid_rows:
                    continue
                step = 1 if abs(r - row) == ring else 2 * ring
                for c in range(col - ring, col + ring + 1, max(step, 1)):
                    if c < 0 or c >= grid_cols:
                        continue
                    g = r * grid_cols + c
                    for q in range(first[g], first[g + 1]):
                        d = _segment_distance(px, py, segments[order[q]])
                        if d < best:
                            best = d
            if best <= ring:
                break
        out[j] = best
    return out
