"""Display sampling of Bézier pieces (§0): uniform, Wang's bound, and adaptive subdivision.

All three work on the planar storage of :class:`~splinecraft.spline.piecewise.Spline` (``(4, d, m)``:
control point ``j``, coordinate, piece) and are vectorised over pieces. Curves of any float64 scale are
sampled in coordinates scaled by a power of two (exact), so squared lengths never overflow or underflow.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

__all__ = ["bernstein", "bernstein_d1", "bernstein_d2", "sample_uniform", "sample_wang", "sample_subdivide"]

# Scales outside [2^-SAFE_EXPONENT, 2^SAFE_EXPONENT] are normalised before any squared length is formed.
SAFE_EXPONENT = 120
# Subdivision depth bound (a piece is halved at most this many times).
MAX_LEVELS = 60


def bernstein(theta):
    """Cubic Bernstein weights ``(..., 4)`` at ``theta``."""
    s = 1.0 - theta
    return np.stack([s**3, 3.0 * theta * s**2, 3.0 * theta**2 * s, theta**3], axis=-1)


def bernstein_d1(theta):
    """First ``theta``-derivatives of the cubic Bernstein weights."""
    s = 1.0 - theta
    return np.stack([-3.0 * s**2, 3.0 * s**2 - 6.0 * theta * s, 6.0 * theta * s - 3.0 * theta**2, 3.0 * theta**2],
                    axis=-1)


def bernstein_d2(theta):
    """Second ``theta``-derivatives of the cubic Bernstein weights."""
    return np.stack([6.0 * (1.0 - theta), 6.0 * (3.0 * theta - 2.0), 6.0 * (1.0 - 3.0 * theta), 6.0 * theta], axis=-1)


def normalised(planar, tolerance):
    """``(planar / 2^e, tolerance / 2^e, 2^e)`` with ``2^e`` near the largest coordinate (exact scaling).

    Returns the inputs unchanged (and 1.0) when the coordinates are of moderate size.
    """
    size = float(np.max(np.abs(planar)))
    if size == 0.0:
        return planar, tolerance, 1.0
    exponent = math.frexp(size)[1] - 1  # 2^exponent <= size < 2^(exponent + 1)
    if -SAFE_EXPONENT <= exponent <= SAFE_EXPONENT:
        return planar, tolerance, 1.0
    factor = math.ldexp(1.0, exponent)
    # a tolerance far below the curve's size may underflow: the smallest normal float is as good; one far
    # above it (a tiny curve, or subnormal coordinates) may overflow: the largest float is as good
    info = np.finfo(float)
    try:
        scaled_tolerance = min(max(math.ldexp(tolerance, -exponent), float(info.tiny)), float(info.max))
    except OverflowError:
        scaled_tolerance = float(info.max)
    return np.ldexp(planar, -exponent), scaled_tolerance, factor


def sample_uniform(planar, knots, k):
    """``theta = 0, 1/k, .., (k-1)/k`` on every piece plus the final end point: ``(params, points)``."""
    _, d, m = planar.shape
    theta = np.arange(k) / k
    weights = bernstein(theta)  # (k, 4)
    points = np.empty((m * k + 1, d))
    grid = points[:-1].reshape(m, k, d)
    for axis in range(d):  # numpy's own loop (no BLAS: a thin multithreaded GEMM is slow on a busy machine)
        grid[:, :, axis] = np.einsum("kj,jm->km", weights, planar[:, axis, :]).T
    points[-1] = planar[3, :, -1]
    params = np.empty(m * k + 1)
    steps = params[:-1].reshape(m, k)
    np.multiply(np.diff(knots)[:, None], theta, out=steps)
    steps += knots[:-1, None]
    params[-1] = knots[-1]
    return params, points


def _norm(vectors):
    """Euclidean norms of planar ``(d, k)`` vectors of moderate size."""
    return np.sqrt(np.einsum("dk,dk->k", vectors, vectors))


def sample_wang(planar, knots, tolerance, max_points, evaluate):
    """Uniform ``theta`` steps per piece from Wang's bound (see :meth:`Spline.sample`).

    ``evaluate(index, theta)`` returns the planar curve points; it is the spline's own Bernstein
    evaluation, so end points are exact.
    """
    _, d, m = planar.shape
    scaled, tol, _factor = normalised(planar, tolerance)
    b0, b1, b2, b3 = scaled
    first = b1 - b2  # b0 - 2 b1 + b2 = (b0 - b1) - (b1 - b2), b1 - 2 b2 + b3 = (b1 - b2) - (b2 - b3)
    size = np.maximum(_norm((b0 - b1) - first), _norm(first - (b2 - b3)))
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        counts = np.ceil(np.sqrt(size * (0.75 / tol)))
    counts[np.isnan(counts)] = 1.0  # a straight piece (size 0) with a tolerance that underflowed
    np.clip(counts, 1.0, float(max_points), out=counts)  # finite even for tolerance near 0
    total = float(counts.sum())
    if total + 1 > max_points:
        warnings.warn(
            f"sample(): tolerance {tolerance} needs {int(total) + 1} points, more than max_points={max_points}; "
            f"returning a coarser sampling",
            RuntimeWarning,
            stacklevel=4,
        )
        budget = max_points - 1 - m  # one point per piece is the minimum
        extra = counts - 1.0
        counts = 1.0 + np.floor(extra * (budget / max(float(extra.sum()), 1.0)))
    counts = counts.astype(np.intp)
    total = int(counts.sum())
    piece = np.repeat(np.arange(m), counts)
    starts = np.cumsum(counts) - counts
    theta = (np.arange(total) - np.repeat(starts, counts)) / np.repeat(counts, counts).astype(float)
    h = knots[1:] - knots[:-1]
    params = np.empty(total + 1)
    params[:-1] = knots[piece] + theta * h[piece]
    params[-1] = knots[-1]
    points = np.empty((total + 1, d))
    points[:-1] = evaluate(piece, theta).T
    points[-1] = planar[3, :, -1]
    return params, points


def sample_subdivide(planar, knots, tolerance, max_points):
    """Halve pieces (de Casteljau) until their inner control points lie within ``tolerance`` of the chord."""
    _, d, m = planar.shape
    scaled, tol, factor = normalised(planar, tolerance)
    points_planar, piece, lo = _subdivide(scaled, tol * tol, max_points, tolerance)
    k = piece.shape[0]
    points = np.empty((k + 1, d))
    points[:-1] = points_planar.T
    if factor != 1.0:
        points[:-1] *= factor  # a power of two: exact, so the piece starts are the knot points bit for bit
    points[-1] = planar[3, :, -1]
    params = np.empty(k + 1)
    params[:-1] = knots[piece] + lo * (knots[piece + 1] - knots[piece])
    params[-1] = knots[-1]
    return params, points


def _subdivide(planar, tol2, max_points, tolerance):
    """Start points ``(d, k)``, piece index and local start of every flat enough sub-piece, in curve order."""
    m = planar.shape[2]
    active, piece, lo = planar, np.arange(m), np.zeros(m)
    width = 1.0
    done_points, done_piece, done_lo = [], [], []
    count = m + 1
    for _level in range(MAX_LEVELS):
        flat = _flatness_sq(active) <= tol2
        n_split = active.shape[2] - int(np.count_nonzero(flat))
        if n_split > max_points - count:
            warnings.warn(
                f"sample(): tolerance {tolerance} needs more than max_points={max_points} points; "
                f"returning a coarser sampling",
                RuntimeWarning,
                stacklevel=5,
            )
            flat[:] = True
            n_split = 0
        done_points.append(active[0][:, flat])
        done_piece.append(piece[flat])
        done_lo.append(lo[flat])
        if n_split == 0:
            break
        split = ~flat
        left, right = _split_half(active[:, :, split])
        count += n_split
        active = np.concatenate([left, right], axis=2)
        width *= 0.5
        piece = np.concatenate([piece[split], piece[split]])
        lo = np.concatenate([lo[split], lo[split] + width])
    else:  # depth bound reached: keep the remaining sub-pieces as they are
        done_points.append(active[0])
        done_piece.append(piece)
        done_lo.append(lo)
    if len(done_points) == 1:
        return done_points[0], done_piece[0], done_lo[0]
    points_planar = np.concatenate(done_points, axis=1)
    piece = np.concatenate(done_piece)
    lo = np.concatenate(done_lo)
    order = np.lexsort((lo, piece))  # curve order
    return points_planar[:, order], piece[order], lo[order]


def _flatness_sq(ctrl):
    """Squared max distance of ``b1``, ``b2`` from the segment ``b0 b3``; planar ``ctrl`` (4, d, k)."""
    a = ctrl[0]
    chord = ctrl[3] - a
    length2 = np.einsum("dk,dk->k", chord, chord)
    safe = np.where(length2 > 0, length2, 1.0)
    worst = None
    for j in (1, 2):
        rel = ctrl[j] - a
        s = np.einsum("dk,dk->k", rel, chord) / safe
        np.clip(s, 0.0, 1.0, out=s)
        rel -= s * chord
        dist = np.einsum("dk,dk->k", rel, rel)
        worst = dist if worst is None else np.maximum(worst, dist, out=worst)
    return worst


def _split_half(ctrl):
    """de Casteljau split of every planar piece (4, d, k) at ``theta = 1/2``: (left, right)."""
    b0, b1, b2, b3 = ctrl
    p01 = 0.5 * (b0 + b1)
    p12 = 0.5 * (b1 + b2)
    p23 = 0.5 * (b2 + b3)
    p012 = 0.5 * (p01 + p12)
    p123 = 0.5 * (p12 + p23)
    mid = 0.5 * (p012 + p123)
    return np.stack([b0, p01, p012, mid]), np.stack([mid, p123, p23, b3])
