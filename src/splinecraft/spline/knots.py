"""Knot parameterization (§3; left open by the thesis).

``t_1 = 0``, ``t_{i+1} = t_i + h_i`` with ``h_i = |F_{i+1} - F_i|^e``: ``e = 0`` uniform, ``e = 1/2``
centripetal, ``e = 1`` chord length (the recommended default for outline capture). Closed curves add the
closing interval ``h_N = |F_1 - F_N|^e``. Every ``h_i`` must be positive, so consecutive coincident points are
rejected (:func:`remove_coincident` merges them first, for callers that want that).
"""
from __future__ import annotations

import numpy as np

from .._validation import (
    COINCIDENT_RTOL,
    as_float_array,
    check_distinct_neighbours,
    check_strictly_increasing,
    point_extent,
    relative_gaps,
)

# COINCIDENT_RTOL (re-exported): the package's one coincidence rule, see splinecraft._validation.
__all__ = ["KNOT_EXPONENTS", "COINCIDENT_RTOL", "parameterize", "leg_lengths", "check_distinct", "remove_coincident"]

#: Exponent ``e`` of ``h_i = |F_{i+1} - F_i|^e`` for each named parameterization (§3).
KNOT_EXPONENTS = {"uniform": 0.0, "centripetal": 0.5, "chord": 1.0}

def leg_lengths(points: np.ndarray, closed: bool) -> np.ndarray:
    """Euclidean lengths of the legs ``F_i F_{i+1}`` (and ``F_N F_1`` when ``closed``)."""
    legs = np.diff(points, axis=0)
    if closed:
        legs = np.concatenate([legs, points[:1] - points[-1:]], axis=0)
    return np.sqrt(np.einsum("ij,ij->i", legs, legs))


def check_distinct(points: np.ndarray, closed: bool, name: str = "points", lengths=None, extent=None) -> np.ndarray:
    """Raise ``ValueError`` naming the first pair of consecutive coincident points; return leg lengths.

    The rule is the package's one coincidence rule (:mod:`splinecraft._validation`): neighbours closer
    than ``1e-12`` times the extent of the points coincide, decided on scaled coordinates, so the
    verdict is the same at every scale. ``lengths`` (optional, the leg lengths) are returned as given;
    ``extent`` (optional) is the largest coordinate range of the points, if already known.
    """
    check_distinct_neighbours(points, name, closed=closed, extent=extent)
    if lengths is None:
        lengths = leg_lengths(points, closed)
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
    gaps = relative_gaps(points)
    keep = np.concatenate([[True], gaps > COINCIDENT_RTOL])
    index = np.flatnonzero(keep)
    if closed and index.size > 1:
        closing = relative_gaps(points[[index[-1], 0]], extent=point_extent(points))
        if not closing[0] > COINCIDENT_RTOL:
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
