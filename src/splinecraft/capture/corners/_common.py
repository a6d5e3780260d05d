"""Shared parts of the corner detectors: argument checks, input preparation and window geometry
(conventions in :mod:`splinecraft.capture.corners`)."""
from __future__ import annotations

import numpy as np

from ... import _validation


_EMPTY = np.zeros(0, dtype=np.intp)
#: Largest coordinate magnitude (px) of an outline: beyond 2**53 a double has no fractional pixels left, and the
#: squared lengths of the detectors' windows overflow long before 1e300.
MAX_COORDINATE = 1e15


# ----------------------------------------------------------------------------------------------------------
# validation
# ----------------------------------------------------------------------------------------------------------
def _plain(key):
    """The name of parameter ``key`` in messages of a detector called directly: the key itself. The parameter
    checks take such a ``label`` (``check_params`` passes one that gives ``corner_params['key']``)."""
    return key


def _check_bool(value, name):
    return _validation.check_bool(value, name)


def _check_real(value, name, *, low=None, high=None, low_open=False, high_open=False):
    """A finite real number inside [low, high] (ends open when asked): the shared kit's check."""
    return _validation.check_number(value, name, minimum=low, maximum=high,
                                    inclusive=(not low_open, not high_open))


def _check_int(value, name, *, low=None, high=None):
    """An integer (Python or numpy, not bool; a float with an integer value too) inside [low, high]."""
    return _validation.check_int(value, name, minimum=low, maximum=high, integral_floats=True)


def _prepare(points, closed):
    """Validate ``points``; merge consecutive duplicates.

    Returns ``(P, keep)``: the distinct points as a float ``(m, 2)`` array and, for each of them, its
    index in the input (the first point of a run of duplicates).
    """
    closed = _check_bool(closed, "closed")
    if isinstance(points, (str, bytes)):
        raise TypeError(f"points must be an (n, 2) array of numbers, got {type(points).__name__}")
    if np.iscomplexobj(points):
        raise TypeError("points must be real, got complex values")
    try:
        array = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"points must be an (n, 2) array of numbers: {exc}") from None
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got shape {array.shape}")
    if len(array) == 0:
        return array, _EMPTY
    if not (np.isfinite(array).all() and np.abs(array).max() <= MAX_COORDINATE):  # the whole array at once; the
        finite = np.isfinite(array).all(axis=1)                                    # first bad point named
        if not finite.all():
            bad = int(np.flatnonzero(~finite)[0])
            raise ValueError(f"points[{bad}] is not finite: {array[bad].tolist()}")
        bad = int(np.flatnonzero(np.abs(array).max(axis=1) > MAX_COORDINATE)[0])
        raise ValueError(f"points[{bad}] = {array[bad].tolist()} is beyond {MAX_COORDINATE:g} px: corner detection "
                         f"works in pixel units (scale the outline down)")
    keep = np.ones(len(array), dtype=bool)
    keep[1:] = (array[1:, 0] != array[:-1, 0]) | (array[1:, 1] != array[:-1, 1])
    index = np.flatnonzero(keep)
    if closed and len(index) > 1 and np.array_equal(array[index[-1]], array[0]):
        index = index[:-1]
    return array.take(index, axis=0), index  # (take: numpy 2.4's row indexing is 5-15x slower)


def _result(found, keep):
    """Map indices into the merged points back to the input; sorted, unique, intp."""
    found = np.asarray(found, dtype=np.intp).reshape(-1)
    if found.size == 0:
        return _EMPTY.copy()
    return np.unique(keep[found]).astype(np.intp)


# ----------------------------------------------------------------------------------------------------------
# shared geometry
# ----------------------------------------------------------------------------------------------------------
def _offset_points(P, offsets, closed):
    """``P[i + k]`` for every point ``i`` and offset ``k``: array (n, len(offsets), 2).

    Closed outlines wrap around; for open ones positions beyond an end are NaN.
    """
    n = len(P)
    offsets = np.asarray(offsets, dtype=np.intp)
    idx = np.arange(n)[:, None] + offsets[None, :]
    if closed:
        return P[idx % n]
    inside = (idx >= 0) & (idx < n)
    out = P[np.clip(idx, 0, n - 1)]
    out[~inside] = np.nan
    return out


def _k_cosines(P, kmax, closed):
    """k-cosines ``c[i, k-1] = cos angle(P[i-k] - P[i], P[i+k] - P[i])`` for k = 1..kmax (RJ73 eq. 1).

    -1 on a straight line, +1 at a spike; NaN where a vector leaves an open polyline or is zero.
    """
    ks = np.arange(1, kmax + 1)
    a = _offset_points(P, -ks, closed) - P[:, None, :]
    b = _offset_points(P, ks, closed) - P[:, None, :]
    na, nb = np.hypot(a[..., 0], a[..., 1]), np.hypot(b[..., 0], b[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.sum(a * b, axis=-1) / (na * nb)
    cos[(na == 0) | (nb == 0)] = np.nan
    return np.clip(cos, -1.0, 1.0)


def _circular_max_filter(values, half_width, closed, fill=-np.inf):
    """Maximum of ``values`` over ``[i - half_width, i + half_width]`` (cyclic when closed; ``fill`` beyond the
    ends of an open curve): one padded copy, then ``numpy.maximum`` of its shifted views (NaN wins)."""
    if half_width <= 0:
        return values.copy()
    n = len(values)
    if closed:
        padded = values[np.arange(-half_width, n + half_width) % n]
    else:
        padded = np.concatenate([np.full(half_width, fill), values, np.full(half_width, fill)])
    out = padded[half_width: half_width + n].copy()
    for offset in range(1, half_width + 1):
        np.maximum(out, padded[half_width - offset: half_width - offset + n], out=out)
        np.maximum(out, padded[half_width + offset: half_width + offset + n], out=out)
    return out


def _thin_by_strength(candidates, strength, P, min_distance):
    """Greedy non-maximum suppression: strongest first, drop candidates within ``min_distance`` (Euclidean)
    of an already kept one. Ties go to the smaller x, then y (not to the index, so that the result does
    not depend on where a closed outline starts). Returns the kept candidate indices (sorted)."""
    candidates = np.asarray(candidates, dtype=np.intp)
    if candidates.size <= 1 or min_distance <= 0:
        return np.sort(candidates)
    order = candidates[np.lexsort((P[candidates, 1], P[candidates, 0], -strength[candidates]))]
    kept = []
    for c in order:
        if not kept or np.min(np.hypot(*(P[kept] - P[c]).T)) > min_distance:
            kept.append(int(c))
    return np.sort(np.asarray(kept, dtype=np.intp))


def _variable_window_maxima(strength, half_widths, closed):
    """``strength[i] >= strength[j]`` for all ``j`` with ``|i - j| <= half_widths[i]`` (NaN never wins)."""
    n = len(strength)
    hmax = int(np.max(half_widths)) if n else 0
    if hmax <= 0:
        return np.isfinite(strength)
    offsets = np.arange(-hmax, hmax + 1)
    idx = np.arange(n)[:, None] + offsets[None, :]
    if closed:
        neighbour = strength[idx % n]
    else:
        neighbour = np.where((idx >= 0) & (idx < n), strength[np.clip(idx, 0, n - 1)], -np.inf)
    neighbour = np.where(np.abs(offsets)[None, :] <= half_widths[:, None], neighbour, -np.inf)
    neighbour = np.nan_to_num(neighbour, nan=-np.inf)
    return np.isfinite(strength) & (strength >= neighbour.max(axis=1))
