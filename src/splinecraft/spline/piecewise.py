"""The common curve type of the engine: a piecewise cubic stored as exact Bézier pieces (§0).

Every construction in :mod:`splinecraft.spline` (interpolant §2, local-support basis form §4, generic
segment §1, Timmer schemes §5) ends in a :class:`Spline`. Evaluation, differentiation, curvature (§7),
display sampling, SVG export, JSON round trip and the conversion to scipy all work from the Bézier
control points, so they are exact for every construction.
"""
from __future__ import annotations

import copy

import numpy as np

from .._validation import (
    as_float_array,
    check_bool,
    check_choice,
    check_int,
    check_positive_number,
    format_index,
)
from .curvature import curvature_comb, curvature_from, joint_curvature
from .queries import construction, curvature_profile, leg_pieces, nearest, piece_leg
from .sampling import sample_subdivide, sample_uniform, sample_wang
from .serialize import checked_parts, spline_from_dict, spline_to_dict
from .svg import path_data
from .transform import VECTOR_AUXILIARY_KEYS, reversed_spline, transformed_spline

__all__ = ["Spline", "VECTOR_AUXILIARY_KEYS", "MAX_SAMPLES"]

#: Most points :meth:`Spline.sample` returns (``max_points`` and ``samples_per_segment`` are bounded by it;
#: 24 bytes per planar point with its parameter).
MAX_SAMPLES = 10_000_000

# Relative tolerance for parameters just outside [t0, tm] of an open curve (rounding).
_DOMAIN_RTOL = 1e-12


class Spline:
    """Piecewise cubic curve stored as exact Bézier pieces (§0).

    Piece ``i`` covers ``[t_i, t_{i+1}]`` and is the cubic Bézier ``[b0, b1, b2, b3]`` in the local
    parameter ``theta = (t - t_i) / h_i``. Derivatives are taken with respect to the knot parameter
    ``t`` (``d/dt = h_i^-1 d/dtheta``), as in the thesis.

    Parameters
    ----------
    bezier : array_like, shape (m, 4, d)
        Control points of the ``m >= 1`` pieces, all finite. Consecutive pieces must join
        (``bezier[i, 3] == bezier[i + 1, 0]`` to a relative ``1e-9``; the start point of the later
        piece is then set exactly to the end of the earlier one).
    knots : array_like, shape (m + 1,)
        Strictly increasing finite knot values ``t_0 < ... < t_m``.
    closed : bool, optional
        The curve is a loop: the last piece must end at the first point (same tolerance, then made
        exact), and parameters wrap with period ``t_m - t_0``.
    auxiliary : dict of str -> array_like, optional
        Drawable extra geometry, for example the class polygon points ``'V'``, ``'W'`` (§2.1),
        ``'control_points'`` (§4), ``'F'`` (knot points) or ``'tangents'`` (``M_i = P'(t_i)``).
        Stored as finite float arrays. ``'tangents'`` is treated as vectors by :meth:`transformed`
        and :meth:`reversed`, everything else as points.
    info : dict, optional
        JSON-able metadata (``form``, ``alpha``, ``beta``, ``end_condition``, ...). numpy values are
        converted to plain Python types.

    Raises
    ------
    TypeError, ValueError
        For wrong types, shapes, non-finite values, non-increasing knots, pieces that do not join or
        an open loop, naming the offending index.
    """

    # Internal storage is "planar": _planar[j, k, i] is coordinate k of control point b_j of piece i,
    # shape (4, d, m), so that vectorised work runs over long contiguous rows (pieces) rather than over
    # the short coordinate axis. _bezier is the (m, 4, d) view of the same memory.
    __slots__ = ("_planar", "_bezier", "_knots", "_closed", "_auxiliary", "_info", "_power")

    def __init__(self, bezier, knots, *, closed=False, auxiliary=None, info=None):
        bezier, knots, closed, aux, info = checked_parts(bezier, knots, closed, auxiliary, info)
        self._set_planar(np.ascontiguousarray(bezier.transpose(1, 2, 0)))
        self._knots = knots
        self._closed = closed
        self._auxiliary = aux
        self._info = info

    def _set_planar(self, planar):
        planar.flags.writeable = False
        self._planar = planar
        self._bezier = planar.transpose(2, 0, 1)
        self._power = None

    @classmethod
    def _from_trusted(cls, planar, knots, *, closed=False, auxiliary=None, info=None):
        """Internal fast path for constructions that guarantee valid input (no checks, no copies).

        ``planar`` is the C-contiguous ``(4, d, m)`` array with ``planar[j, :, i]`` = control point ``b_j``
        of piece ``i``. The caller hands over ownership of the arrays: finite float64, strictly increasing
        ``(m + 1,)`` knots, exactly joined pieces, JSON-normalised ``info``.
        """
        self = cls.__new__(cls)
        self._set_planar(planar)
        knots.flags.writeable = False
        aux = auxiliary or {}
        for value in aux.values():
            value.flags.writeable = False
        self._knots = knots
        self._closed = bool(closed)
        self._auxiliary = aux
        self._info = info or {}
        return self

    def __reduce__(self):
        """Copies and pickles rebuild the spline through :meth:`_from_trusted` from copies of its parts, so that
        its arrays stay read-only (and ``bezier()`` a view of its storage) in the copy too."""
        auxiliary = {key: np.array(value) for key, value in self._auxiliary.items()}
        return (_rebuilt, (type(self), np.array(self._planar), np.array(self._knots), self._closed, auxiliary,
                           copy.deepcopy(self._info)))

    # ------------------------------------------------------------------ properties
    @property
    def knots(self) -> np.ndarray:
        """Knot values ``t_0 < ... < t_m`` (read-only array, shape ``(m + 1,)``)."""
        return self._knots

    @property
    def closed(self) -> bool:
        """True for a loop (periodic parameter)."""
        return self._closed

    @property
    def n_segments(self) -> int:
        """Number of pieces ``m``."""
        return self._planar.shape[2]

    @property
    def dim(self) -> int:
        """Dimension ``d`` of the points."""
        return self._planar.shape[1]

    @property
    def auxiliary(self) -> dict:
        """Drawable extra geometry (dict of read-only arrays; a shallow copy)."""
        return dict(self._auxiliary)

    @property
    def info(self) -> dict:
        """JSON-able metadata (the stored dict; treat as read-only)."""
        return self._info

    @property
    def knot_points(self) -> np.ndarray:
        """Curve points at the knots, shape ``(m + 1, d)`` (for a loop the last equals the first)."""
        return np.concatenate([self._planar[0], self._planar[3][:, -1:]], axis=1).T.copy()

    @property
    def domain(self) -> tuple:
        """``(t_0, t_m)``."""
        return float(self._knots[0]), float(self._knots[-1])

    def bezier(self) -> np.ndarray:
        """A copy of the Bézier control points, shape ``(m, 4, d)``."""
        return np.array(self._bezier, order="C")

    def __repr__(self) -> str:
        form = self._info.get("form")
        extra = f", form={form!r}" if form is not None else ""
        t0, tm = self.domain
        return (
            f"Spline(n_segments={self.n_segments}, dim={self.dim}, closed={self._closed}, "
            f"t=[{t0:.6g}, {tm:.6g}]{extra})"
        )

    # ------------------------------------------------------------------ evaluation
    def _power_coefficients(self) -> np.ndarray:
        """Planar coefficients ``c_k`` of ``P(theta) = sum_k c_k theta^k``, shape (4, d, m)."""
        if self._power is None:
            b0, b1, b2, b3 = self._planar
            power = np.stack([b0, 3.0 * (b1 - b0), 3.0 * (b0 - 2.0 * b1 + b2), b3 - b0 + 3.0 * (b1 - b2)])
            power.flags.writeable = False
            self._power = power
        return self._power

    def _locate(self, t, *, side: str = "right", extrapolate: bool = False):
        """Map parameters to (piece index, theta). ``side='left'`` takes the left piece at knots."""
        knots = self._knots
        t0, tm = knots[0], knots[-1]
        span = tm - t0
        if self._closed:
            # wrap only what lies outside one period, so that knot values stay bit-exact
            if side == "right":
                outside = (t < t0) | (t >= tm)
                if outside.any():
                    t = np.where(outside, t0 + np.mod(t - t0, span), t)
            else:
                outside = (t <= t0) | (t > tm)
                if outside.any():
                    t = np.where(outside, tm - np.mod(tm - t, span), t)
        elif not extrapolate:
            slack = _DOMAIN_RTOL * max(span, abs(t0), abs(tm))
            outside = (t < t0 - slack) | (t > tm + slack)
            if outside.any():
                bad = int(np.flatnonzero(outside.reshape(-1))[0])
                raise ValueError(
                    f"t{format_index(bad, t.shape)} = {float(t.reshape(-1)[bad])!r} is outside the curve's "
                    f"domain [{float(t0)!r}, {float(tm)!r}]; pass extrapolate=True to extend the end pieces"
                )
            t = np.clip(t, t0, tm)
        index = np.searchsorted(knots, t, side=side) - 1
        np.clip(index, 0, self.n_segments - 1, out=index)
        h = knots[index + 1] - knots[index]
        theta = (t - knots[index]) / h
        return index, theta, h

    @staticmethod
    def _check_parameters(t):
        array = as_float_array(t, "t")
        if array.ndim > 1:
            raise ValueError(f"t must be a scalar or a 1-d array, got shape {array.shape}")
        return array

    def _evaluate(self, index, theta, h, nu):
        """Planar values ``(d, k)`` of ``d^nu P / dt^nu`` on pieces ``index`` at local ``theta``."""
        if nu == 0:
            # Bernstein form: exact end points (theta = 0 gives b0, theta = 1 gives b3 bit for bit)
            b = np.take(self._planar, index, axis=2)  # (4, d, k)
            s = 1.0 - theta
            return (s * s * s) * b[0] + (3.0 * s * s * theta) * b[1] + (3.0 * s * theta * theta) * b[2] + (theta * theta * theta) * b[3]
        if nu > 3:
            return np.zeros((self.dim, theta.shape[0]))
        coef = np.take(self._power_coefficients(), index, axis=2)  # (4, d, k)
        if nu == 1:
            value = coef[1] + theta * (2.0 * coef[2] + 3.0 * theta * coef[3])
        elif nu == 2:
            value = 2.0 * coef[2] + 6.0 * theta * coef[3]
        else:
            value = 6.0 * coef[3] + 0.0 * theta
        for _ in range(nu):  # one division per order: h**nu over- or underflows at extreme scales
            value = value / h
        return value

    def __call__(self, t, nu=0, *, extrapolate=False, side="right"):
        """Evaluate the curve or its ``nu``-th derivative ``d^nu P / dt^nu``.

        Parameters
        ----------
        t : float or array_like, shape (k,)
            Parameters. Closed curves wrap periodically. Open curves raise ``ValueError`` outside
            ``[t_0, t_m]`` (up to rounding) unless ``extrapolate=True``, which extends the end pieces.
        nu : int, optional
            Derivative order ``>= 0`` (orders above 3 are zero).
        side : {"right", "left"}, optional
            Which piece to use at a knot (matters for ``nu >= 2``, where the curve is only ``C^1``).

        Returns
        -------
        ndarray, shape (k, d), or (d,) for scalar ``t``.
        """
        nu = check_int(nu, "nu", minimum=0)
        side = check_choice(side, "side", ("right", "left"))
        extrapolate = check_bool(extrapolate, "extrapolate")
        array = self._check_parameters(t)
        flat = array.reshape(-1)
        index, theta, h = self._locate(flat, side=side, extrapolate=extrapolate)
        values = self._evaluate(index, theta, h, nu)
        return values[:, 0].copy() if array.ndim == 0 else np.ascontiguousarray(values.T)

    def derivative(self, t, order=1, **kwargs):
        """``d^order P / dt^order`` at ``t`` (see :meth:`__call__`)."""
        return self(t, nu=order, **kwargs)

    # ------------------------------------------------------------------ curvature
    _curvature_from = staticmethod(curvature_from)

    def _require_curvature_dim(self):
        if self.dim < 2:
            raise ValueError(f"curvature needs points with d >= 2 coordinates, this curve has d = {self.dim}")

    def curvature(self, t, side="right", *, extrapolate=False):
        """Curvature ``kappa = P' x P'' / |P'|^3`` at ``t`` (§7, thesis eq 3.116).

        For planar curves (d = 2) it is signed, ``kappa > 0`` turning left (counter-clockwise); for
        d >= 3 it is the unsigned magnitude. The curve is only ``C^1`` at the knots and its curvature
        jumps there unless neighbouring interval weights are equal (§2.2, E2): ``side`` chooses
        the one-sided value at a knot (``"right"``: ``kappa(t_i^+)``, ``"left"``: ``kappa(t_i^-)``).
        Where the speed ``|P'|`` is zero (a cusp) the curvature is NaN.
        """
        self._require_curvature_dim()
        side = check_choice(side, "side", ("right", "left"))
        array = self._check_parameters(t)
        flat = array.reshape(-1)
        index, theta, h = self._locate(flat, side=side, extrapolate=check_bool(extrapolate, "extrapolate"))
        kappa = self._curvature_from(self._evaluate(index, theta, h, 1), self._evaluate(index, theta, h, 2))
        return kappa[0] if array.ndim == 0 else kappa

    def joint_curvature(self) -> np.ndarray:
        """One-sided curvature at every knot, shape ``(m + 1, 2)``: columns ``kappa(t_i^-)``, ``kappa(t_i^+)``.

        Computed from the Bézier end formulas of §7,
        ``kappa(0) = 2/3 (b1-b0) x (b2-b1) / |b1-b0|^3`` and ``kappa(1) = 2/3 (b2-b1) x (b3-b2) / |b3-b2|^3``
        (in ``theta``; curvature does not depend on the parametrisation). For an open curve the
        missing sides (``[0, 0]`` and ``[m, 1]``) are NaN; for a loop row ``m`` repeats row ``0``.
        Where neighbouring interval weights differ, ``kappa^+ / kappa^- = omega_{i-1} / omega_i``
        (§2.2, E2): the jump is shown, not hidden. Zero end speed gives NaN.
        """
        return joint_curvature(self)

    def curvature_comb(self, scale=1.0, samples_per_segment=16):
        """Curvature comb (§7): tooth base points and tips, each shape ``(k, 2)``.

        Each piece is sampled uniformly in ``theta`` with both endpoints, so every joint gets both
        one-sided teeth. A tooth runs from ``P`` to ``P - scale * kappa * N`` with ``N = (-T_y, T_x)``
        (drawn outside, the CAD convention; a negative ``scale`` draws towards the centre of
        curvature). Samples with (near) zero speed are skipped. Planar curves only.
        """
        return curvature_comb(self, scale, samples_per_segment)

    # ------------------------------------------------------------------ queries (spline/queries.py)
    def nearest(self, point):
        """The curve point nearest to ``point`` (finite, shape ``(d,)``), exact up to rounding.

        Returns ``Nearest(parameter, distance, piece, point)``: the knot parameter ``t``, the distance,
        the piece and ``P(t)``. Pieces whose control-point box cannot hold the nearest point are
        skipped (convex hull, §0); on the others every sampled local minimum of the squared distance is
        refined by a safeguarded Newton iteration on ``(P - q) . P' = 0``, and the piece ends compete
        too. Computed relative to ``point`` and scaled to the curve's size: any float64 scale works.
        """
        return nearest(self, point)

    def construction(self, t):
        """The de Casteljau construction at ``t`` (§0), for teaching: ``Construction(parameter, piece,
        theta, levels, point, tangent, class_polygon)``.

        ``piece`` holds ``t`` (the right piece at a knot; a loop wraps ``t``), ``theta = (t - t_i) / h_i``.
        ``levels``: the Bézier points ``b_0..b_3`` (4, d), then ``(1 - theta) b_j + theta b_{j+1}`` (3, d),
        (2, d) and the curve point (1, d); ``tangent = P'(t) = 3 (levels[2][1] - levels[2][0]) / h_i``.
        ``class_polygon`` (4, d) is the polygon the piece is designed from: ``F_i, V_i, W_i, F_{i+1}``
        (generic cubic, §1, §2.1: ``b_1 = F_i + alpha/3 (V_i - F_i)``, ``b_2 = F_{i+1} + beta/3 (W_i - F_{i+1})``),
        the Timmer points ``P_i, Q_i1, Q_i2, P_{i+1}`` (§5.1: ``b_1 = P_i + 4/3 (Q_i1 - P_i)``), or None.
        """
        return construction(self, t)

    def curvature_profile(self, samples_per_piece=32):
        """``kappa(t)`` for a plot (§7): ``CurvatureProfile(parameters, curvature, piece, knots,
        joint_curvature, jumps)``.

        Each piece is sampled at ``samples_per_piece`` (>= 2) parameters from ``t_i`` to ``t_{i+1}``
        inclusive, so every knot appears twice, first with ``kappa(t_i^-)``, then with ``kappa(t_i^+)``:
        drawn as one line, a jump at a joint (§2.2, E2; Timmer joints, §5) is a vertical step.
        ``joint_curvature`` is :meth:`joint_curvature`, ``jumps`` is ``kappa^+ - kappa^-`` per knot.
        """
        return curvature_profile(self, samples_per_piece)

    def piece_leg(self, piece) -> int:
        """The leg of the input polygon (from input point ``j`` to ``j + 1``, cyclically on a loop) that
        piece ``piece`` belongs to: ``piece + info['leg_offset']``.

        The constructors record ``leg_offset``: 0 for the interpolant (§2) and the Timmer schemes (§5);
        for the basis form (§4.3) 1 when open (the inner Bézier points of segment ``i`` lie on the leg
        ``P_{i+1} P_{i+2}``) and 0 when closed. Curves without it count pieces as legs.
        """
        return piece_leg(self, piece)

    def leg_pieces(self, leg):
        """The pieces over leg ``leg`` (int array; empty for a leg without a piece, such as the end legs
        of an open basis curve): the inverse of :meth:`piece_leg`."""
        return leg_pieces(self, leg)

    # ------------------------------------------------------------------ sampling
    def _uniform_planar(self, weights):
        """``sum_j weights[k, j] b_j`` for every piece: planar ``(d, m * k)`` in curve order (one GEMM)."""
        planar = self._planar
        _, d, m = planar.shape
        k = weights.shape[0]
        # numpy's own loop, not BLAS: a multithreaded GEMM this thin is slower, badly so on a busy machine
        values = np.einsum("kj,jn->kn", weights, planar.reshape(4, d * m))  # (k, d * m)
        return values.reshape(k, d, m).transpose(1, 2, 0).reshape(d, m * k)

    def sample(self, tolerance=0.25, max_points=1_000_000, *, samples_per_segment=None, method="wang"):
        """Display sampling: parameters ``(k,)`` and points ``(k, d)``, in order along the curve.

        The returned polyline stays within ``tolerance`` of the curve (same units as the points, e.g.
        pixels). Knots and both endpoints are always included; for a loop the last point repeats the first.
        Fully vectorised over pieces; no Python loop over samples.

        Parameters
        ----------
        tolerance : float
            Maximum distance between the curve and the polyline (> 0).
        max_points : int
            Upper bound on the number of points (at most :data:`MAX_SAMPLES`, 10 million). If the tolerance
            would need more, the sampling is coarsened to fit and a ``RuntimeWarning`` is issued.
        samples_per_segment : int, optional
            Ignore ``tolerance`` and sample every piece uniformly: ``theta = 0, 1/k, .., (k-1)/k`` per piece,
            plus the final endpoint.
        method : {"wang", "subdivide"}
            ``"wang"`` (default, fastest): piece ``i`` gets ``k_i = ceil(sqrt(3/4 * L_i / tolerance))`` uniform
            samples in ``theta``, with ``L_i = max(|b0 - 2 b1 + b2|, |b1 - 2 b2 + b3|)`` (Wang's bound: the chord
            error of a step ``1/k`` is at most ``|P''|_max / (8 k^2)`` and ``|P''(theta)| <= 6 L_i``).
            ``"subdivide"``: split at ``theta = 1/2`` (de Casteljau, vectorised per level) until each
            sub-piece's inner control points lie within ``tolerance`` of its chord (convex-hull bound); it
            adapts inside a piece and usually returns fewer points, at a higher cost.
        """
        method = check_choice(method, "method", ("wang", "subdivide"))
        m = self.n_segments
        if samples_per_segment is not None:
            k = check_int(samples_per_segment, "samples_per_segment", minimum=1,
                          maximum=max(1, MAX_SAMPLES // m))
            return sample_uniform(self._planar, self._knots, k)
        tolerance = check_positive_number(tolerance, "tolerance")
        max_points = check_int(max_points, "max_points", minimum=m + 1, maximum=max(m + 1, MAX_SAMPLES))
        if method == "wang":
            return sample_wang(self._planar, self._knots, tolerance, max_points,
                               lambda index, theta: self._evaluate(index, theta, None, 0))
        return sample_subdivide(self._planar, self._knots, tolerance, max_points)

    # ------------------------------------------------------------------ export
    def to_svg_path(self, precision=3) -> str:
        """SVG path data ``"M x,y C x1,y1 x2,y2 x3,y3 ... Z"`` of the exact cubic Béziers (§0).

        ``precision`` is the number of decimals (an integer in ``[0, 64]``, trailing zeros dropped);
        ``None`` writes the shortest exact representation of every float (lossless round trip). Closed
        curves end with ``Z`` (the last ``C`` already returns to the start point). Planar curves only.
        Written by :func:`splinecraft.spline.svg.path_data`, the package's one SVG writer.
        """
        if self.dim != 2:
            raise ValueError(f"to_svg_path needs a planar curve (d = 2), this curve has d = {self.dim}")
        if precision is not None:
            precision = check_int(precision, "precision", minimum=0, maximum=64)
        return path_data([self._bezier], decimals=precision, closed=self._closed)

    def to_dict(self) -> dict:
        """JSON-able representation (plain lists of floats); exact round trip via :meth:`from_dict`."""
        return spline_to_dict(self)

    @classmethod
    def from_dict(cls, data: dict) -> "Spline":
        """Rebuild a spline from :meth:`to_dict` output (also after a JSON round trip).

        The dict is checked against a strict schema first (:mod:`splinecraft.spline.serialize`): known
        keys only, exact types (``closed`` must be a bool), shapes, finiteness and nesting depth;
        errors name the key.
        """
        return spline_from_dict(cls, data)

    def to_bpoly(self):
        """``scipy.interpolate.BPoly`` with coefficients of shape ``(4, m, d)`` (vector valued).

        A loop gets ``extrapolate='periodic'``.
        """
        from scipy.interpolate import BPoly

        coefficients = np.ascontiguousarray(self._planar.transpose(0, 2, 1))
        return BPoly(coefficients, np.array(self._knots), extrapolate="periodic" if self._closed else True)

    def to_ppoly(self):
        """``scipy.interpolate.PPoly`` (power basis, via ``PPoly.from_bernstein_basis``)."""
        from scipy.interpolate import PPoly

        bpoly = self.to_bpoly()
        return PPoly.from_bernstein_basis(bpoly, extrapolate=bpoly.extrapolate)

    # ------------------------------------------------------------------ geometry
    def reversed(self) -> "Spline":
        """The same curve traversed backwards, with knots ``t'_j = t_0 + t_m - t_{m-j}``.

        Auxiliary geometry is carried over so that it still belongs to the right pieces: per-piece
        arrays and polylines are flipped, ``'V'`` and ``'W'`` swap roles, ``'tangents'`` change sign,
        and for a loop per-knot arrays (``'F'``, ``'tangents'``) keep index 0 at the start point.
        ``'Q1'``/``'Q2'`` (Timmer polygon) likewise. ``info['alpha']`` and ``info['beta']`` are swapped
        (they swap roles in reverse, §1), and per-piece or per-knot ``info`` lists are reversed.
        """
        return reversed_spline(self)

    def transformed(self, matrix, offset=None) -> "Spline":
        """Affine image ``x -> matrix @ x + offset`` (exact: Bézier pieces map to Bézier pieces).

        Point-like auxiliary arrays are mapped the same way; vector-valued ones (``'tangents'``) get
        only ``matrix``. Knots and info are unchanged.
        """
        return transformed_spline(self, matrix, offset)


def _rebuilt(cls, planar, knots, closed, auxiliary, info):
    """A :class:`Spline` (or subclass ``cls``) from the parts :meth:`Spline.__reduce__` copied."""
    return cls._from_trusted(np.ascontiguousarray(planar), knots, closed=closed, auxiliary=auxiliary, info=info)
