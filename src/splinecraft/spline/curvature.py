"""Curvature of Bézier pieces (§7): the one formula, the joint values and the comb.

``kappa = P' x P'' / |P'|^3``, signed for planar curves (``> 0`` turning left) and unsigned for d >= 3.
Every function divides the derivatives by their size first, so no square overflows or underflows at any
float64 scale (``kappa`` scales as one over the size).
"""
from __future__ import annotations

import numpy as np

from .._validation import check_int, check_number
from .sampling import bernstein, bernstein_d1, bernstein_d2, normalised

__all__ = ["curvature_from", "joint_curvature", "curvature_comb", "MAX_COMB_SAMPLES"]

#: Most comb teeth computed at once (memory bound).
MAX_COMB_SAMPLES = 10_000_000


def curvature_from(first, second):
    """Signed (d = 2) or unsigned (d >= 3) curvature ``|P' x P''| / |P'|^3`` (§7).

    Planar arguments: ``first``, ``second`` have shape ``(d, k)``. Both are divided by the largest
    component of ``P'`` first (``kappa`` scales as ``1 / size``), so no square overflows or underflows
    at any float64 scale. NaN where ``P' = 0``.
    """
    size = np.max(np.abs(first), axis=0)
    safe = np.where(size > 0, size, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):
        first = first / safe
        second = second / safe
        speed2 = np.einsum("dk,dk->k", first, first)
        if first.shape[0] == 2:
            cross = first[0] * second[1] - first[1] * second[0]
        else:
            dot = np.einsum("dk,dk->k", first, second)
            cross = np.sqrt(np.maximum(speed2 * np.einsum("dk,dk->k", second, second) - dot**2, 0.0))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        kappa = cross / (speed2 * np.sqrt(speed2)) / safe
    return np.where(size > 0, kappa, np.nan)


def joint_curvature(spline):
    """One-sided curvature at every knot, ``(m + 1, 2)`` (see :meth:`Spline.joint_curvature`)."""
    spline._require_curvature_dim()
    scaled, _tolerance, factor = normalised(spline._planar, 1.0)  # exact power-of-two scaling, any scale
    b0, b1, b2, b3 = scaled
    start = curvature_from(3.0 * (b1 - b0), 6.0 * (b0 - 2.0 * b1 + b2)) / factor
    end = curvature_from(3.0 * (b3 - b2), 6.0 * (b1 - 2.0 * b2 + b3)) / factor
    m = spline.n_segments
    out = np.full((m + 1, 2), np.nan)
    out[1:, 0] = end
    out[:-1, 1] = start
    if spline._closed:
        out[0, 0] = end[-1]
        out[m, 1] = start[0]
    return out


def curvature_comb(spline, scale=1.0, samples_per_segment=16):
    """Curvature comb tooth bases and tips (see :meth:`Spline.curvature_comb`)."""
    if spline.dim != 2:
        raise ValueError(f"curvature_comb needs a planar curve (d = 2), this curve has d = {spline.dim}")
    scale = check_number(scale, "scale")
    samples = check_int(samples_per_segment, "samples_per_segment", minimum=2,
                        maximum=max(2, MAX_COMB_SAMPLES // spline.n_segments))
    theta = np.linspace(0.0, 1.0, samples)
    points = spline._uniform_planar(bernstein(theta))  # (d, m * k), piece-major
    d1 = spline._uniform_planar(bernstein_d1(theta))
    d2 = spline._uniform_planar(bernstein_d2(theta))
    size = np.max(np.abs(d1), axis=0)
    unit = d1 / np.where(size > 0, size, 1.0)
    length = np.sqrt(np.einsum("dk,dk->k", unit, unit))
    # A sample is a cusp (no tangent, no tooth) where the speed is below what the control points resolve:
    # 1e-12 of the curve's extent, or the rounding of coordinates far from the origin (64 ulp of the largest),
    # whichever is larger. Measured against the extent, not the coordinates, so moving a curve keeps its comb.
    planar = spline._planar.transpose(1, 0, 2).reshape(spline.dim, -1)
    extent = float(np.max(np.ptp(planar, axis=1)))
    resolution = max(1e-12 * extent, 64.0 * np.finfo(float).eps * float(np.max(np.abs(planar))))
    keep = size * length > (resolution or np.finfo(float).tiny)
    points, d1, d2, unit, length = points[:, keep], d1[:, keep], d2[:, keep], unit[:, keep], length[keep]
    kappa = curvature_from(d1, d2)
    with np.errstate(over="ignore", invalid="ignore"):
        factor = scale * kappa / length  # tooth = -scale * kappa * N, N = (-T_y, T_x), T = P'/|P'|
        tips = np.stack([points[0] + factor * unit[1], points[1] - factor * unit[0]], axis=1)
    if not np.isfinite(tips).all():
        raise ValueError(f"scale = {scale!r} puts the comb's tooth tips beyond the float64 range for this curve")
    return np.ascontiguousarray(points.T), tips
