"""Geometric queries on a :class:`~splinecraft.spline.piecewise.Spline` (§0, §7).

* :func:`nearest` -- the curve point nearest to a given point (exact up to rounding: every local
  minimum of the squared distance is refined by a safeguarded Newton iteration).
* :func:`construction` -- the de Casteljau construction of the piece at a parameter ``t`` (the three
  levels of linear interpolation between the Bézier points), and the class polygon it comes from.
* :func:`curvature_profile` -- ``kappa(t)`` sampled piece by piece with both one-sided values at every
  joint, so a plot shows the jumps of §2.2 (erratum E2) as vertical steps.
* :func:`piece_leg`, :func:`leg_pieces` -- which leg of the input polygon each piece belongs to.

:class:`Spline` exposes these as methods; this module holds the arithmetic.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._validation import as_float_array, check_int, check_number

__all__ = ["Nearest", "Construction", "CurvatureProfile", "nearest", "construction", "curvature_profile",
           "piece_leg", "leg_pieces"]

# Samples per piece that start the Newton refinement of nearest(): a cubic's squared distance to a point
# has at most three local minima per piece, which are separated far more than 1/16 of the piece unless
# they are nearly equal in value.
_NEAREST_SAMPLES = 17
#: Most samples of one curvature profile (memory bound).
MAX_PROFILE_SAMPLES = 10_000_000
_NEWTON_STEPS = 60


class Nearest(NamedTuple):
    """Result of :meth:`Spline.nearest`."""

    parameter: float  #: the knot parameter ``t`` of the nearest curve point
    distance: float   #: its Euclidean distance to the query point
    piece: int        #: the piece it lies on (at a knot: either neighbour, ``parameter`` is the same)
    point: np.ndarray  #: the nearest curve point, shape (d,)


class Construction(NamedTuple):
    """Result of :meth:`Spline.construction`: the de Casteljau construction at one parameter."""

    parameter: float     #: the knot parameter ``t`` (wrapped into ``[t_0, t_m)`` on a loop)
    piece: int           #: the piece that ``t`` falls on
    theta: float         #: the local parameter ``(t - t_i) / h_i`` in [0, 1]
    levels: tuple        #: arrays (4, d), (3, d), (2, d), (1, d): Bézier points, then each interpolation level
    point: np.ndarray    #: the curve point ``P(t)`` (= ``levels[3][0]``), shape (d,)
    tangent: np.ndarray  #: ``dP/dt`` at ``t`` (= 3 (levels[2][1] - levels[2][0]) / h_i), shape (d,)
    class_polygon: np.ndarray | None  #: (4, d): ``F_i, V_i, W_i, F_{i+1}`` or ``P_i, Q_i1, Q_i2, P_{i+1}``, or None


class CurvatureProfile(NamedTuple):
    """Result of :meth:`Spline.curvature_profile`."""

    parameters: np.ndarray       #: (m * k,): per piece ``k`` parameters from ``t_i`` to ``t_{i+1}`` inclusive
    curvature: np.ndarray        #: (m * k,): ``kappa`` there (signed for d = 2; NaN at zero speed)
    piece: np.ndarray            #: (m * k,): the piece of every sample
    knots: np.ndarray            #: (m + 1,): the knot values
    joint_curvature: np.ndarray  #: (m + 1, 2): ``kappa(t_i^-)``, ``kappa(t_i^+)`` (:meth:`Spline.joint_curvature`)
    jumps: np.ndarray            #: (m + 1,): ``kappa(t_i^+) - kappa(t_i^-)`` (NaN at the ends of an open curve)


# ---------------------------------------------------------------------------------------------- nearest
def nearest(spline, point) -> Nearest:
    """The point of ``spline`` nearest to ``point`` (see :meth:`Spline.nearest`)."""
    target = as_float_array(point, "point", ndim=1)
    if target.shape[0] != spline.dim:
        raise ValueError(f"point must have {spline.dim} coordinates, got {target.shape[0]}")
    planar = spline._planar  # (4, d, m)
    # work relative to the query point and in units of the curve's size: no overflow, no underflow
    offsets = planar - target[None, :, None]
    scale = float(np.max(np.abs(offsets)))
    if scale == 0.0:
        return Nearest(float(spline.knots[0]), 0.0, 0, spline._planar[0, :, 0].copy())
    offsets = offsets / scale
    candidates = _candidate_pieces(offsets)
    local = offsets[:, :, candidates]
    theta, dist2, pieces = _refine(local)
    best = int(np.argmin(dist2))
    piece = int(candidates[pieces[best]])
    t_local = float(theta[best])
    knots = spline.knots
    parameter = float(knots[piece] + t_local * (knots[piece + 1] - knots[piece]))
    if t_local == 1.0:
        parameter = float(knots[piece + 1])
    point_on_curve = spline._evaluate(np.array([piece]), np.array([t_local]), None, 0)[:, 0]
    distance = float(np.sqrt(dist2[best])) * scale
    return Nearest(parameter, distance, piece, point_on_curve)


def _candidate_pieces(offsets):
    """Pieces whose control-point box (a bound by the convex hull property) may hold the nearest point."""
    ends = np.concatenate([offsets[0], offsets[3]], axis=1)  # (d, 2m)
    upper = float(np.min(np.einsum("dk,dk->k", ends, ends)))
    low = offsets.min(axis=0)  # (d, m)
    high = offsets.max(axis=0)
    gap = np.maximum(low, 0.0) + np.maximum(-high, 0.0)  # distance of the origin from each box, per axis
    lower = np.einsum("dk,dk->k", gap, gap)
    return np.flatnonzero(lower <= upper * (1.0 + 1e-9))


def _refine(offsets):
    """Local minima of ``|B(theta)|^2`` over theta in [0, 1] for planar Bézier pieces (4, d, k).

    Samples every piece at ``_NEAREST_SAMPLES`` values, starts at each sampled local minimum and runs a
    Newton iteration on ``g = B . B'`` kept inside the bracket of the neighbouring samples (bisection when
    Newton leaves it). Returns ``theta``, the squared distance and the piece (index into ``offsets``) of
    every candidate; both ends of every piece are candidates too.
    """
    k = _NEAREST_SAMPLES
    grid = np.linspace(0.0, 1.0, k)
    values = _bezier_at(offsets, grid)  # (d, k_pieces, k)
    dist2 = np.einsum("dps,dps->ps", values, values)
    padded = np.pad(dist2, ((0, 0), (1, 1)), constant_values=np.inf)
    is_min = (dist2 <= padded[:, :-2]) & (dist2 <= padded[:, 2:])
    pieces, index = np.nonzero(is_min)
    low = grid[np.maximum(index - 1, 0)]
    high = grid[np.minimum(index + 1, k - 1)]
    theta = grid[index].copy()
    ctrl = offsets[:, :, pieces]  # (4, d, c)
    for _ in range(_NEWTON_STEPS):
        position, first, second = _bezier_derivatives(ctrl, theta)
        g = np.einsum("dc,dc->c", position, first)
        dg = np.einsum("dc,dc->c", first, first) + np.einsum("dc,dc->c", position, second)
        low = np.where(g < 0, theta, low)
        high = np.where(g > 0, theta, high)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = theta - g / dg
        inside = (dg > 0) & (step > low) & (step < high)
        new = np.where(inside, step, 0.5 * (low + high))
        new = np.where(g == 0, theta, new)
        done = np.abs(new - theta) <= 1e-15
        theta = new
        if done.all():
            break
    # the ends are candidates too (a minimum there has g != 0)
    theta = np.concatenate([theta, np.zeros(offsets.shape[2]), np.ones(offsets.shape[2])])
    pieces = np.concatenate([pieces, np.arange(offsets.shape[2]), np.arange(offsets.shape[2])])
    position = _bezier_derivatives(offsets[:, :, pieces], theta)[0]
    return theta, np.einsum("dc,dc->c", position, position), pieces


def _bezier_at(ctrl, grid):
    """Planar ``(d, pieces, samples)`` values of Bézier pieces ``ctrl`` (4, d, p) at ``grid``."""
    s = 1.0 - grid
    weights = np.stack([s**3, 3.0 * grid * s**2, 3.0 * grid**2 * s, grid**3])  # (4, samples)
    return np.einsum("js,jdp->dps", weights, ctrl)


def _bezier_derivatives(ctrl, theta):
    """Point, first and second theta-derivatives of pieces ``ctrl`` (4, d, c), one theta per piece."""
    b0, b1, b2, b3 = ctrl
    s = 1.0 - theta
    position = s**3 * b0 + 3.0 * s * s * theta * b1 + 3.0 * s * theta * theta * b2 + theta**3 * b3
    first = 3.0 * (s * s * (b1 - b0) + 2.0 * s * theta * (b2 - b1) + theta * theta * (b3 - b2))
    second = 6.0 * (s * (b2 - 2.0 * b1 + b0) + theta * (b3 - 2.0 * b2 + b1))
    return position, first, second


# ---------------------------------------------------------------------------------------------- construction
def de_casteljau_levels(bezier, theta):
    """The de Casteljau levels of one Bézier piece ``bezier`` (4, d) at ``theta``: (4, d), (3, d), (2, d), (1, d)."""
    levels = [np.array(bezier, dtype=float)]
    for _ in range(3):
        previous = levels[-1]
        levels.append((1.0 - theta) * previous[:-1] + theta * previous[1:])
    return tuple(levels)


def construction(spline, t) -> Construction:
    """The de Casteljau construction of ``spline`` at ``t`` (see :meth:`Spline.construction`)."""
    value = check_number(t, "t")
    index, theta, h = spline._locate(np.array([value]))
    piece, local = int(index[0]), float(theta[0])
    levels = de_casteljau_levels(spline._bezier[piece], local)
    tangent = 3.0 * (levels[2][1] - levels[2][0]) / float(h[0])
    parameter = float(spline.knots[piece] + local * float(h[0]))
    return Construction(parameter, piece, local, levels, levels[3][0].copy(), tangent,
                        _class_polygon(spline, piece))


def _class_polygon(spline, piece):
    aux = spline._auxiliary
    inner = ("V", "W") if "V" in aux and "W" in aux else (("Q1", "Q2") if "Q1" in aux and "Q2" in aux else None)
    if inner is None or aux[inner[0]].shape[0] != spline.n_segments:
        return None
    bezier = spline._bezier[piece]
    return np.stack([bezier[0], aux[inner[0]][piece], aux[inner[1]][piece], bezier[3]])


# ---------------------------------------------------------------------------------------------- curvature
def curvature_profile(spline, samples_per_piece=32) -> CurvatureProfile:
    """``kappa(t)`` along ``spline`` with both one-sided values at the joints (see :meth:`Spline.curvature_profile`)."""
    spline._require_curvature_dim()
    m = spline.n_segments
    k = check_int(samples_per_piece, "samples_per_piece", minimum=2, maximum=max(2, MAX_PROFILE_SAMPLES // m))
    theta = np.linspace(0.0, 1.0, k)
    index = np.repeat(np.arange(m), k)
    local = np.tile(theta, m)
    knots = spline.knots
    h = np.diff(knots)[index]
    parameters = knots[index] + local * h
    parameters[k - 1::k] = knots[1:]  # piece ends exactly on the knots
    first = spline._evaluate(index, local, h, 1)
    second = spline._evaluate(index, local, h, 2)
    kappa = spline._curvature_from(first, second)
    joints = spline.joint_curvature()
    return CurvatureProfile(parameters, kappa, index, np.array(knots), joints, joints[:, 1] - joints[:, 0])


# ---------------------------------------------------------------------------------------------- legs
def _leg_offset(spline):
    offset = spline._info.get("leg_offset", 0)
    return int(offset) if isinstance(offset, int) and not isinstance(offset, bool) else 0


def piece_leg(spline, piece) -> int:
    """The input-polygon leg that piece ``piece`` belongs to (see :meth:`Spline.piece_leg`)."""
    piece = check_int(piece, "piece", minimum=0, maximum=spline.n_segments - 1)
    return piece + _leg_offset(spline)


def leg_pieces(spline, leg) -> np.ndarray:
    """The pieces over leg ``leg`` (see :meth:`Spline.leg_pieces`)."""
    leg = check_int(leg, "leg")
    piece = leg - _leg_offset(spline)
    if 0 <= piece < spline.n_segments:
        return np.array([piece], dtype=np.intp)
    return np.zeros(0, dtype=np.intp)
