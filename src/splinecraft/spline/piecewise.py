"""The common curve type of the engine: a piecewise cubic stored as exact Bézier pieces (§0).

Every construction in :mod:`splinecraft.spline` (interpolant §2, local-support basis form §4, generic
segment §1, Timmer schemes §5) ends in a :class:`Spline`. Evaluation, differentiation, curvature (§7),
display sampling, SVG export, JSON round trip and the conversion to scipy all work from the Bézier
control points, so they are exact for every construction.
"""
from __future__ import annotations

import numbers
import warnings

import numpy as np

from .._json import to_jsonable
from .._validation import (
    as_float_array,
    check_bool,
    check_choice,
    check_int,
    check_positive_number,
    check_strictly_increasing,
    format_index,
)

__all__ = ["Spline"]

#: Auxiliary keys that hold free vectors (derivatives), not points: an affine map applies only its
#: linear part to them and reversal flips their sign.
VECTOR_AUXILIARY_KEYS = frozenset({"tangents"})

#: Auxiliary keys holding one entry per knot (``m + 1`` open, ``m`` closed).
_PER_KNOT_KEYS = frozenset({"tangents", "F"})

# Relative tolerance for the continuity of consecutive pieces and the closure of closed curves.
_JOIN_RTOL = 1e-9
# Relative tolerance for parameters just outside [t0, tm] of an open curve (rounding).
_DOMAIN_RTOL = 1e-12


#: Auxiliary arrays that trade roles when a curve is traversed backwards.
_REVERSED_ROLES = {"V": "W", "W": "V", "Q1": "Q2", "Q2": "Q1"}


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
        bezier = as_float_array(bezier, "bezier", copy=True)
        if bezier.ndim != 3 or bezier.shape[1] != 4 or bezier.shape[0] < 1 or bezier.shape[2] < 1:
            raise ValueError(f"bezier must have shape (m, 4, d) with m >= 1, d >= 1; got {bezier.shape}")
        m = bezier.shape[0]
        knots = as_float_array(knots, "knots", ndim=1, copy=True)
        if knots.shape[0] != m + 1:
            raise ValueError(f"knots must have m + 1 = {m + 1} values for {m} pieces, got {knots.shape[0]}")
        check_strictly_increasing(knots, "knots")
        closed = check_bool(closed, "closed")

        scale = float(np.max(np.abs(bezier))) or 1.0
        tol = _JOIN_RTOL * scale
        if m > 1:
            gaps = np.linalg.norm(bezier[1:, 0] - bezier[:-1, 3], axis=-1)
            if (gaps > tol).any():
                bad = int(np.flatnonzero(gaps > tol)[0])
                raise ValueError(
                    f"pieces {bad} and {bad + 1} do not join: bezier[{bad}, 3] and bezier[{bad + 1}, 0] "
                    f"are {gaps[bad]:.3g} apart"
                )
            bezier[1:, 0] = bezier[:-1, 3]
        if closed:
            gap = float(np.linalg.norm(bezier[-1, 3] - bezier[0, 0]))
            if gap > tol:
                raise ValueError(
                    f"closed=True but the last piece ends {gap:.3g} away from the first point "
                    f"(bezier[{m - 1}, 3] != bezier[0, 0])"
                )
            bezier[-1, 3] = bezier[0, 0]
        knots.flags.writeable = False

        aux = {}
        if auxiliary is not None:
            if not isinstance(auxiliary, dict):
                raise TypeError(f"auxiliary must be a dict of arrays, got {type(auxiliary).__name__}")
            for key, value in auxiliary.items():
                if not isinstance(key, str):
                    raise TypeError(f"auxiliary keys must be strings, got {key!r}")
                array = as_float_array(value, f"auxiliary[{key!r}]", copy=True)
                array.flags.writeable = False
                aux[key] = array
        if info is None:
            info = {}
        if not isinstance(info, dict):
            raise TypeError(f"info must be a dict, got {type(info).__name__}")

        self._set_planar(np.ascontiguousarray(bezier.transpose(1, 2, 0)))
        self._knots = knots
        self._closed = closed
        self._auxiliary = aux
        self._info = to_jsonable(info, "info")

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
                    f"domain [{t0!r}, {tm!r}]; pass extrapolate=True to extend the end pieces"
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
        return value / h**nu

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
    @staticmethod
    def _curvature_from(first, second):
        """Signed (d = 2) or unsigned (d >= 3) curvature ``|P' x P''| / |P'|^3`` (§7).

        Planar arguments: ``first``, ``second`` have shape ``(d, k)``.
        """
        speed2 = np.einsum("dk,dk->k", first, first)
        if first.shape[0] == 2:
            cross = first[0] * second[1] - first[1] * second[0]
        else:
            dot = np.einsum("dk,dk->k", first, second)
            cross = np.sqrt(np.maximum(speed2 * np.einsum("dk,dk->k", second, second) - dot**2, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            kappa = cross / (speed2 * np.sqrt(speed2))
        return np.where(speed2 > 0, kappa, np.nan)

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
        self._require_curvature_dim()
        b0, b1, b2, b3 = self._planar
        start = self._curvature_from(3.0 * (b1 - b0), 6.0 * (b0 - 2.0 * b1 + b2))
        end = self._curvature_from(3.0 * (b3 - b2), 6.0 * (b1 - 2.0 * b2 + b3))
        m = self.n_segments
        out = np.full((m + 1, 2), np.nan)
        out[1:, 0] = end
        out[:-1, 1] = start
        if self._closed:
            out[0, 0] = end[-1]
            out[m, 1] = start[0]
        return out

    def curvature_comb(self, scale=1.0, samples_per_segment=16):
        """Curvature comb (§7): tooth base points and tips, each shape ``(k, 2)``.

        Each piece is sampled uniformly in ``theta`` with both endpoints, so every joint gets both
        one-sided teeth. A tooth runs from ``P`` to ``P - scale * kappa * N`` with ``N = (-T_y, T_x)``
        (drawn outside, the CAD convention; a negative ``scale`` draws towards the centre of
        curvature). Samples with (near) zero speed are skipped. Planar curves only.
        """
        if self.dim != 2:
            raise ValueError(f"curvature_comb needs a planar curve (d = 2), this curve has d = {self.dim}")
        if isinstance(scale, (bool, np.bool_)) or not isinstance(scale, numbers.Real) or not np.isfinite(scale):
            raise TypeError(f"scale must be a finite real number, got {scale!r}")
        samples = check_int(samples_per_segment, "samples_per_segment", minimum=2)
        theta = np.linspace(0.0, 1.0, samples)
        points = self._uniform_planar(_bernstein(theta))  # (d, m * k), piece-major
        d1 = self._uniform_planar(_bernstein_d1(theta))
        d2 = self._uniform_planar(_bernstein_d2(theta))
        speed = np.sqrt(np.einsum("dk,dk->k", d1, d1))
        scale_ref = float(np.max(np.abs(self._planar))) or 1.0
        keep = speed > 1e-12 * scale_ref
        points, d1, d2, speed = points[:, keep], d1[:, keep], d2[:, keep], speed[keep]
        kappa = self._curvature_from(d1, d2)
        factor = float(scale) * kappa / speed  # tooth = -scale * kappa * N, N = (-T_y, T_x), T = P'/|P'|
        tips = np.stack([points[0] + factor * d1[1], points[1] - factor * d1[0]], axis=1)
        return np.ascontiguousarray(points.T), tips

    # ------------------------------------------------------------------ queries (spline/queries.py)
    def nearest(self, point):
        """The curve point nearest to ``point``: ``Nearest(parameter, distance, piece, point)``.

        Exact up to rounding: pieces whose control-point box (convex hull property, §0) cannot hold
        the nearest point are skipped, every local minimum of the squared distance sampled on the
        others is refined by a safeguarded Newton iteration on ``(P - q) . P' = 0`` inside its
        bracket, and both ends of every piece are compared too. Works in coordinates relative to the
        query point and scaled to the curve's size, so any float64 scale works. ``point`` is a finite
        ``(d,)`` array; ``parameter`` is the knot parameter ``t``, ``piece`` the piece index, ``point``
        the curve point ``P(t)``.
        """
        from .queries import nearest

        return nearest(self, point)

    def construction(self, t):
        """The de Casteljau construction at ``t`` (§0): ``Construction(parameter, piece, theta, levels,
        point, tangent, class_polygon)``.

        ``piece`` is the piece that ``t`` falls on (the right one at a knot; a loop wraps ``t``),
        ``theta = (t - t_i) / h_i`` its local parameter, and ``levels`` the four de Casteljau levels:
        the Bézier points ``b_0..b_3`` (4, d), then ``(1 - theta) b_j + theta b_{j+1}`` (3, d), again
        (2, d), and the curve point (1, d). The last level's two points span the tangent:
        ``tangent = P'(t) = 3 (levels[2][1] - levels[2][0]) / h_i``. ``class_polygon`` is the polygon the
        piece was designed from, ``F_i, V_i, W_i, F_{i+1}`` (generic cubic, §1-§2.1: ``b_1`` lies on
        ``F_i V_i`` at ``alpha / 3``, ``b_2`` on ``F_{i+1} W_i`` at ``beta / 3``) or the Timmer points
        ``P_i, Q_i1, Q_i2, P_{i+1}`` (§5.1: at ``4 / 3``), or None when the curve has no such auxiliary.
        """
        from .queries import construction

        return construction(self, t)

    def curvature_profile(self, samples_per_piece=32):
        """``kappa(t)`` for a plot (§7): ``CurvatureProfile(parameters, curvature, piece, knots,
        joint_curvature, jumps)``.

        Every piece is sampled at ``samples_per_piece`` (>= 2) parameters from ``t_i`` to ``t_{i+1}``
        inclusive, so each knot appears twice, with the left value ``kappa(t_i^-)`` and then the right
        one ``kappa(t_i^+)``: drawn as one line, a jump at a joint (unequal interval weights, §2.2 and
        E2; Timmer joints, §5) is a vertical step. ``joint_curvature`` is :meth:`joint_curvature`
        and ``jumps`` its difference ``kappa^+ - kappa^-`` per knot (NaN at the ends of an open curve).
        """
        from .queries import curvature_profile

        return curvature_profile(self, samples_per_piece)

    def piece_leg(self, piece) -> int:
        """The leg of the input polygon that piece ``piece`` belongs to.

        A leg ``j`` joins input point ``j`` and ``j + 1`` (``n - 1`` with ``0`` for the closing leg of a
        loop). The constructors record ``info['leg_offset']``: piece ``i`` lies over leg
        ``i + leg_offset``. It is 0 for the interpolant (§2, piece ``i`` runs from ``F_i`` to
        ``F_{i+1}``) and the Timmer schemes (§5), and for the basis form (§4.3) 1 when open (segment ``i``
        has its inner Bézier points on the leg ``P_{i+1} P_{i+2}``) and 0 when closed. Curves without it
        (e.g. built directly) count pieces as legs.
        """
        from .queries import piece_leg

        return piece_leg(self, piece)

    def leg_pieces(self, leg):
        """The pieces over leg ``leg`` of the input polygon (an int array, empty for a leg that carries
        no piece, e.g. the end legs of an open basis curve); the inverse of :meth:`piece_leg`."""
        from .queries import leg_pieces

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
            Upper bound on the number of points. If the tolerance would need more, the sampling is coarsened
            to fit and a ``RuntimeWarning`` is issued.
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
        planar = self._planar
        _, d, m = planar.shape
        knots = self._knots
        method = check_choice(method, "method", ("wang", "subdivide"))
        if samples_per_segment is not None:
            k = check_int(samples_per_segment, "samples_per_segment", minimum=1)
            theta = np.arange(k) / k
            weights = _bernstein(theta)  # (k, 4)
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
        if method == "wang":
            return self._sample_wang(check_positive_number(tolerance, "tolerance"),
                                     check_int(max_points, "max_points", minimum=m + 1))

        tolerance = check_positive_number(tolerance, "tolerance")
        max_points = check_int(max_points, "max_points", minimum=m + 1)
        tol2 = tolerance * tolerance
        active = planar
        piece = None  # None: the pieces themselves, in order (level 0)
        lo = None
        width = 1.0
        done_points, done_piece, done_lo = [], [], []
        count = m + 1
        for _level in range(60):
            flat = _flatness_sq(active) <= tol2
            n_split = active.shape[2] - int(np.count_nonzero(flat))
            if n_split > max_points - count:
                warnings.warn(
                    f"sample(): tolerance {tolerance} needs more than max_points={max_points} points; "
                    f"returning a coarser sampling",
                    RuntimeWarning,
                    stacklevel=2,
                )
                flat[:] = True
                n_split = 0
            if piece is None:
                piece_all, lo_all = np.arange(m), np.zeros(m)
            else:
                piece_all, lo_all = piece, lo
            if n_split == 0:
                done_points.append(active[0])
                done_piece.append(piece_all)
                done_lo.append(lo_all)
                break
            done_points.append(active[0][:, flat])
            done_piece.append(piece_all[flat])
            done_lo.append(lo_all[flat])
            split = ~flat
            left, right = _split_half(active[:, :, split])
            count += n_split
            active = np.concatenate([left, right], axis=2)
            width *= 0.5
            piece = np.concatenate([piece_all[split], piece_all[split]])
            lo = np.concatenate([lo_all[split], lo_all[split] + width])
        if len(done_points) == 1:
            points_planar, piece, lo = done_points[0], done_piece[0], done_lo[0]
        else:
            points_planar = np.concatenate(done_points, axis=1)
            piece = np.concatenate(done_piece)
            lo = np.concatenate(done_lo)
            order = np.lexsort((lo, piece))  # curve order
            piece, lo, points_planar = piece[order], lo[order], points_planar[:, order]
        k = piece.shape[0]
        points = np.empty((k + 1, d))
        points[:-1] = points_planar.T
        points[-1] = planar[3, :, -1]
        params = np.empty(k + 1)
        params[:-1] = knots[piece] + lo * (knots[piece + 1] - knots[piece])
        params[-1] = knots[-1]
        return params, points

    def _sample_wang(self, tolerance, max_points):
        planar = self._planar
        _, d, m = planar.shape
        knots = self._knots
        b0, b1, b2, b3 = planar
        first = b1 - b2  # reuse: b0 - 2 b1 + b2 = (b0 - b1) - (b1 - b2), b1 - 2 b2 + b3 = (b1 - b2) - (b2 - b3)
        second_a = (b0 - b1) - first
        second_b = first - (b2 - b3)
        size2 = np.maximum(np.einsum("dk,dk->k", second_a, second_a), np.einsum("dk,dk->k", second_b, second_b))
        counts = np.ceil(np.sqrt(np.sqrt(size2) * (0.75 / tolerance)))
        np.maximum(counts, 1.0, out=counts)
        total = float(counts.sum())
        if total + 1 > max_points:
            warnings.warn(
                f"sample(): tolerance {tolerance} needs {int(total) + 1} points, more than max_points={max_points}; "
                f"returning a coarser sampling",
                RuntimeWarning,
                stacklevel=3,
            )
            budget = max_points - 1 - m  # one point per piece is the minimum
            extra = counts - 1.0
            counts = 1.0 + np.floor(extra * (budget / max(float(extra.sum()), 1.0)))
        counts = counts.astype(np.intp)
        total = int(counts.sum())
        piece = np.repeat(np.arange(m), counts)
        starts = np.cumsum(counts) - counts
        theta = (np.arange(total) - np.repeat(starts, counts)) / np.repeat(counts, counts).astype(float)
        index = piece
        h = knots[1:] - knots[:-1]
        params = np.empty(total + 1)
        params[:-1] = knots[index] + theta * h[index]
        params[-1] = knots[-1]
        points = np.empty((total + 1, d))
        points[:-1] = self._evaluate(index, theta, None, 0).T
        points[-1] = planar[3, :, -1]
        return params, points

    # ------------------------------------------------------------------ export
    def to_svg_path(self, precision=3) -> str:
        """SVG path data ``"M x,y C x1,y1 x2,y2 x3,y3 ... Z"`` of the exact cubic Béziers (§0).

        ``precision`` is the number of decimals (an integer in ``[0, 64]``, trailing zeros dropped);
        ``None`` writes the shortest exact representation of every float (lossless round trip). Closed
        curves end with ``Z`` (the last ``C`` already returns to the start point). Planar curves only.
        Written by :func:`splinecraft.spline.svg.path_data`, the package's one SVG writer.
        """
        from .svg import path_data

        if self.dim != 2:
            raise ValueError(f"to_svg_path needs a planar curve (d = 2), this curve has d = {self.dim}")
        if precision is not None:
            precision = check_int(precision, "precision", minimum=0, maximum=64)
        return path_data([self._bezier], decimals=precision, closed=self._closed)

    def to_dict(self) -> dict:
        """JSON-able representation (plain lists of floats); exact round trip via :meth:`from_dict`."""
        return {
            "type": "splinecraft.Spline",
            "version": 1,
            "closed": self._closed,
            "knots": self._knots.tolist(),
            "bezier": self._bezier.tolist(),
            "auxiliary": {key: value.tolist() for key, value in self._auxiliary.items()},
            "auxiliary_shapes": {key: list(value.shape) for key, value in self._auxiliary.items()},
            "info": to_jsonable(self._info, "info"),
        }

    @classmethod
    def from_dict(cls, data: dict) -> "Spline":
        """Rebuild a spline from :meth:`to_dict` output (also after a JSON round trip)."""
        if not isinstance(data, dict):
            raise TypeError(f"from_dict expects a dict, got {type(data).__name__}")
        if data.get("type", "splinecraft.Spline") != "splinecraft.Spline":
            raise ValueError(f"not a splinecraft.Spline dict: type={data.get('type')!r}")
        for key in ("bezier", "knots"):
            if key not in data:
                raise ValueError(f"from_dict: missing key {key!r}")
        shapes = data.get("auxiliary_shapes", {})
        auxiliary = {}
        for key, value in (data.get("auxiliary") or {}).items():
            array = np.asarray(value, dtype=float)
            if key in shapes:
                array = array.reshape(shapes[key])
            auxiliary[key] = array
        bezier = np.asarray(data["bezier"], dtype=float)
        return cls(bezier, data["knots"], closed=bool(data.get("closed", False)),
                   auxiliary=auxiliary, info=data.get("info") or {})

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
        planar = np.ascontiguousarray(self._planar[::-1, :, ::-1])
        knots = (self._knots[0] + self._knots[-1]) - self._knots[::-1]
        m = self.n_segments
        aux = {}
        for key, value in self._auxiliary.items():
            target = _REVERSED_ROLES.get(key, key)
            flipped = value[::-1]
            if self._closed and key in _PER_KNOT_KEYS and value.shape[0] == m:
                flipped = np.roll(flipped, 1, axis=0)
            if key in VECTOR_AUXILIARY_KEYS:
                flipped = -flipped
            aux[target] = flipped
        info = dict(self._info)
        if "alpha" in info or "beta" in info:
            info["alpha"], info["beta"] = self._info.get("beta"), self._info.get("alpha")
        for key, value in info.items():
            # Per-piece (m) and per-knot (m + 1) metadata lists follow the pieces backwards.
            if isinstance(value, list) and len(value) in (m, m + 1):
                info[key] = value[::-1]
        knots = np.ascontiguousarray(knots)
        aux = {key: np.array(value) for key, value in aux.items()}
        return Spline._from_trusted(planar, knots, closed=self._closed, auxiliary=aux, info=to_jsonable(info, "info"))

    def transformed(self, matrix, offset=None) -> "Spline":
        """Affine image ``x -> matrix @ x + offset`` (exact: Bézier pieces map to Bézier pieces).

        Point-like auxiliary arrays are mapped the same way; vector-valued ones (``'tangents'``) get
        only ``matrix``. Knots and info are unchanged.
        """
        d = self.dim
        matrix = as_float_array(matrix, "matrix")
        if matrix.shape != (d, d):
            raise ValueError(f"matrix must have shape ({d}, {d}), got {matrix.shape}")
        offset = np.zeros(d) if offset is None else as_float_array(offset, "offset")
        if offset.shape != (d,):
            raise ValueError(f"offset must have shape ({d},), got {offset.shape}")
        planar = np.matmul(matrix, self._planar) + offset[:, None]
        aux = {}
        for key, value in self._auxiliary.items():
            if value.ndim >= 1 and value.shape[-1] == d:
                value = value @ matrix.T
                if key not in VECTOR_AUXILIARY_KEYS:
                    value = value + offset
            aux[key] = value
        result = Spline(planar.transpose(2, 0, 1), self._knots, closed=self._closed, auxiliary=aux, info=dict(self._info))
        return result


# ---------------------------------------------------------------------- Bernstein helpers
def _bernstein(theta):
    s = 1.0 - theta
    return np.stack([s**3, 3.0 * theta * s**2, 3.0 * theta**2 * s, theta**3], axis=-1)


def _bernstein_d1(theta):
    s = 1.0 - theta
    return np.stack([-3.0 * s**2, 3.0 * s**2 - 6.0 * theta * s, 6.0 * theta * s - 3.0 * theta**2, 3.0 * theta**2], axis=-1)


def _bernstein_d2(theta):
    return np.stack([6.0 * (1.0 - theta), 6.0 * (3.0 * theta - 2.0), 6.0 * (1.0 - 3.0 * theta), 6.0 * theta], axis=-1)


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
