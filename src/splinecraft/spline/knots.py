"""Knot parameterization (§3; left open by the thesis).

``t_1 = 0``, ``t_{i+1} = t_i + h_i`` with ``h_i = |F_{i+1} - F_i|^e``: ``e = 0`` uniform, ``e = 1/2``
centripetal, ``e = 1`` chord length (the recommended default for outline capture). Closed curves add the
closing interval ``h_N = |F_1 - F_N|^e``. Every ``h_i`` must be positive, so consecutive coincident points are
rejected (:func:`remove_coincident` merges them first, for callers that want that).
"""
from __future__ import annotations

import numpy as np

from ._validation import as_float_array, check_strictly_increasing

__all__ = ["KNOT_EXPONENTS", "parameterize", "leg_lengths", "check_distinct", "remove_coincident"]

#: Exponent ``e`` of ``h_i = |F_{i+1} - F_i|^e`` for each named parameterization (§3).
KNOT_EXPONENTS = {"uniform": 0.0, "centripetal": 0.5, "chord": 1.0}

# Consecutive points closer than this (relative to the size of the point set) count as coincident.
COINCIDENT_RTOL = 1e-12


def leg_lengths(points: np.ndarray, closed: bool) -> np.ndarray:
    """Euclidean lengths of the legs ``F_i F_{i+1}`` (and ``F_N F_1`` when ``closed``)."""
    legs = np.diff(points, axis=0)
    if closed:
        legs = np.concatenate([legs, points[:1] - points[-1:]], axis=0)
    return np.sqrt(np.einsum("ij,ij->i", legs, legs))


def _coincidence_tolerance(points: np.ndarray) -> float:
    extent = float(np.max(np.ptp(points, axis=0))) if points.shape[0] > 1 else 0.0
    return COINCIDENT_RTOL * max(extent, np.finfo(float).tiny)


def check_distinct(points: np.ndarray, closed: bool, name: str = "points", lengths=None, extent=None) -> np.ndarray:
    """Raise ``ValueError`` naming the first pair of consecutive coincident points; return leg lengths.

    ``extent`` (optional) is the largest coordinate range of the points, if already known.
    """
    if lengths is None:
        lengths = leg_lengths(points, closed)
    if extent is None:
        tol = _coincidence_tolerance(points)
    else:
        tol = COINCIDENT_RTOL * max(extent, np.finfo(float).tiny)
    if not (lengths > tol).all():
        i = int(np.flatnonzero(~(lengths > tol))[0])
        n = points.shape[0]
        if closed and i == n - 1:
            raise ValueError(
                f"{name}[{n - 1}] and {name}[0] coincide: a closed curve takes N distinct points, "
                f"do not repeat the first point at the end"
            )
        raise ValueError(
            f"{name}[{i}] and {name}[{i + 1}] coincide; consecutive points must be distinct "
            f"(merge them first, e.g. with splinecraft.spline.knots.remove_coincident)"
        )
    return lengths


def remove_coincident(points, *, closed=False):
    """Merge runs of consecutive coincident points (§3).

    Returns
    -------
    kept_points : ndarray
        The points with each run of coincident points replaced by its first point (for a closed
        curve a final point equal to the first is dropped as well).
    kept_index : ndarray of int
        Indices into ``points`` of the kept points, so that callers can report what was merged.
    """
    points = as_float_array(points, "points")
    if points.ndim != 2:
        raise ValueError(f"points must be an (n, d) array, got shape {points.shape}")
    if points.shape[0] == 0:
        return points.copy(), np.zeros(0, dtype=int)
    tol = _coincidence_tolerance(points)
    step = np.sqrt(np.einsum("ij,ij->i", np.diff(points, axis=0), np.diff(points, axis=0)))
    keep = np.concatenate([[True], step > tol])
    index = np.flatnonzero(keep)
    if closed and index.size > 1 and np.linalg.norm(points[index[-1]] - points[0]) <= tol:
        index = index[:-1]
    return points[index], index


def parameterize(points, knots="chord", *, closed=False, lengths=None, name="knots") -> np.ndarray:
    """Knot values for ``points`` (§3).

    Parameters
    ----------
    points : ndarray, shape (n, d)
        Already validated points (finite, consecutive points distinct for named methods).
    knots : {"chord", "centripetal", "uniform"} or array_like
        A named parameterization, or explicit strictly increasing values: ``n`` of them for an open
        curve, ``N + 1`` for a closed one (the last closes the loop).
    closed : bool
        Closed curves get ``N + 1`` knots.
    lengths : ndarray, optional
        Precomputed leg lengths (:func:`leg_lengths`).

    Returns
    -------
    ndarray, shape (n,) open or (N + 1,) closed, starting at 0 for named methods.
    """
    n = points.shape[0]
    count = n + 1 if closed else n
    if isinstance(knots, str):
        if knots not in KNOT_EXPONENTS:
            raise ValueError(f"{name} must be one of {sorted(KNOT_EXPONENTS)} or an increasing array, got {knots!r}")
        exponent = KNOT_EXPONENTS[knots]
        if exponent == 0.0:
            return np.arange(count, dtype=float)
        if lengths is None:
            lengths = leg_lengths(points, closed)
        steps = lengths if exponent == 1.0 else np.sqrt(lengths)
        values = np.empty(count)
        values[0] = 0.0
        np.cumsum(steps, out=values[1:])
        return values
    values = as_float_array(knots, name, ndim=1)
    if values.shape[0] != count:
        what = f"N + 1 = {count} for a closed curve of N = {n} points" if closed else f"one per point ({n})"
        raise ValueError(f"{name} has length {values.shape[0]} but needs {what}")
    check_strictly_increasing(values, name)
    return values
