"""Deviation geometry of the outline fit: point-to-polyline distances, Bézier sampling and the two-sided
closest-point deviation between curve pieces and a contour (docs/capture.md §12, "Stopping rule").
"""
from __future__ import annotations

import numpy as np

from . import _kernels

__all__ = ["polyline_distance", "piece_deviation", "sample_bezier", "eval_bezier", "edge_table",
           "windowed_distance", "sorted_group_max", "group_max", "member_sorted"]


def member_sorted(values, sorted_set):
    """``numpy.isin(values, sorted_set)`` for a sorted ``sorted_set`` (a binary search per value, not a sort of
    both: the arrays here are short and ``isin``'s set-up costs more than its search)."""
    if not sorted_set.shape[0]:
        return np.zeros(values.shape[0], bool)
    at = np.minimum(np.searchsorted(sorted_set, values), sorted_set.shape[0] - 1)
    return sorted_set[at] == values


def segment_squared_distances(points, a, b):
    """Exact squared distances from ``points`` to the segments ``a -> b`` (arrays of matching shape (..., 2))."""
    ab = b - a
    ap = points - a
    denom = np.einsum("...d,...d->...", ab, ab)
    t = np.clip(np.einsum("...d,...d->...", ap, ab) / np.where(denom > 0, denom, 1.0), 0.0, 1.0)
    diff = ap - t[..., None] * ab
    return np.einsum("...d,...d->...", diff, diff)


def _segment_distances(points, a, b):
    """Exact distances from points (n, 2) to the segments a[k] -> b[k] (n, k, 2): minimum over k."""
    return np.sqrt(segment_squared_distances(points[:, None, :], a, b).min(axis=1))


def polyline_distance(points, line, *, closed=False, neighbours=6):
    """Distance from each point to the polyline ``line`` (closed: with the edge back to the start).

    Candidate edges are those adjacent to the ``neighbours`` nearest vertices (``scipy.spatial.cKDTree``),
    with exact point-to-segment distances: exact whenever the closest edge has an end among those vertices
    (always for the unit-spaced outlines here), otherwise an upper bound.
    """
    from scipy.spatial import cKDTree

    points = np.asarray(points, float)
    line = np.asarray(line, float)
    m = line.shape[0]
    if m == 1:
        return np.hypot(*(points - line[0]).T)
    k = min(neighbours, m)
    _, idx = cKDTree(line).query(points, k=k)
    idx = idx.reshape(points.shape[0], k)
    if closed:
        edges = np.concatenate([idx, (idx - 1) % m], axis=1)
        a, b = line[edges], line[(edges + 1) % m]
    else:
        edges = np.clip(np.concatenate([idx, idx - 1], axis=1), 0, m - 2)
        a, b = line[edges], line[edges + 1]
    return _segment_distances(points, a, b)


def sample_bezier(bezier, spacing):
    """Samples of Bézier pieces about ``spacing`` px apart (each piece from theta = 0 to 1 inclusive)."""
    lengths = np.hypot(*np.diff(bezier, axis=1).transpose(2, 0, 1)).sum(axis=1)
    counts = np.maximum(2, np.ceil(lengths / spacing).astype(np.int64)) + 1
    piece = np.repeat(np.arange(bezier.shape[0]), counts)
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    theta = (np.arange(piece.shape[0]) - first[piece]) / (counts[piece] - 1)
    return eval_bezier(bezier, piece, theta), piece, theta


def piece_deviation(bezier, contour, spacing=0.25):
    """Symmetric closest-point deviation (px) between Bézier pieces and an open contour polyline.

    Curve samples (``spacing`` px apart) to the polyline edges, and polyline vertices and edge midpoints to the
    chords between curve samples, both with :func:`polyline_distance`. An upper bound of the Hausdorff
    distance up to the sampling (``<= spacing / 2`` plus the chord sag of the samples, ~1e-3 px).
    """
    samples, _, _ = sample_bezier(np.asarray(bezier, float), spacing)
    contour = np.asarray(contour, float)
    d_curve = polyline_distance(samples, contour)
    probes = np.vstack([contour, 0.5 * (contour[:-1] + contour[1:])]) if contour.shape[0] > 1 else contour
    d_contour = polyline_distance(probes, samples)
    return float(max(d_curve.max(), d_contour.max()))



def sorted_group_max(groups: np.ndarray, values: np.ndarray, count: int) -> np.ndarray:
    """Per group ``g < count`` the maximum of ``values`` (``-inf`` if empty), for non-decreasing ``groups``."""
    return group_max(groups, values, count)[0]


def group_max(groups: np.ndarray, values: np.ndarray, count: int):
    """Per group ``g < count`` (``groups`` non-decreasing): the maximum of ``values`` and the first index where
    it occurs (``-inf`` and 0 for empty groups); one pass, :func:`._kernels.group_max`."""
    return _kernels.group_max(groups, values, count)


def eval_bezier(bezier: np.ndarray, piece: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Points of the Bézier pieces ``bezier[piece]`` at ``theta`` (cubic Bernstein weights, one pass,
    :func:`._kernels.eval_bezier`)."""
    return _kernels.eval_bezier(bezier, piece, theta)


def edge_table(line: np.ndarray):
    """Per edge ``line[e] -> line[e + 1]`` of a polyline: start x, start y, dx, dy and ``1 / |d|^2`` (1 for a
    zero-length edge), the rows of one ``(5, edges)`` array (one argument of the compiled deviation check), the
    input of :func:`windowed_distance` (compiled: :func:`._kernels.contour_tables`)."""
    return _kernels.contour_tables(line, None, 0, edges_only=True)


def windowed_distance(points, centre, lo, hi, edges, window, wrap=0):
    """Distance from ``points[j]`` to the polyline edges ``e = centre[j] - window .. centre[j] + window``,
    clipped to ``[lo[j], hi[j]]`` (if given), then taken modulo ``wrap`` (if > 0); ``edges`` is the
    polyline's :func:`edge_table`.

    Exact point-to-segment distances; the minimum over a subset of the edges, so never below the true
    closest-point distance to the polyline (an upper bound that is tight when the window holds the closest edge,
    which the fit's parameterization ensures; one pass per point, :func:`._kernels.windowed_distance`)."""
    return _kernels.windowed_distance(points, centre, lo, hi, edges, window, wrap)
