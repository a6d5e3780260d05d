"""The regression spline of one closed outline, the state of the ``"lsq"`` method (docs/capture.md §12,
"The lsq method").

The whole closed outline is one periodic cubic spline ``S(u)`` in the contour's arc-length parameter ``u``:
every corner is a knot of multiplicity 3 (the curve is ``C^0`` there: the two pieces share the corner point
and nothing else) and every inserted knot is simple (``C^2``). Between two corners this is exactly the
family of the thesis's GC² interpolant with ``v = 0`` and ``omega = 1`` (§2.2-2.4, Type 1 clamped ends):
a ``C^2`` cubic on given knots is fixed by its knot points ``F_i`` and its two end tangents, and every choice
of those is such a spline (§4.5, cross-check). The interpolant is *linear* in ``(F_1..F_n, M_1, M_n)``, so
choosing them to minimise the squared distance to all contour points of the piece is a linear least-squares
problem (a regression spline in the generic model), solved in the B-spline basis of the same space for the
whole outline at once (:mod:`.bspline`), with the corner points as shared unknowns: corners move to where both
neighbouring pieces want them (for acute corners beyond the truncated pixel tip).
"""
from __future__ import annotations

import numpy as np

from ._kernels import (_NO_FLOATS, _NO_INTS, curve_points, deviation_measures, fit_step, hook_tests, interval_samples,
                       anchor_bounds, corner_tables, corner_weights, interval_worst, knot_vector, normal_work,
                       removal_scores, zone_window)
from .bspline import _FROM_SAMPLES, _THETA4, bezier_of_intervals, fit_coefficients
from .geometry import group_max, member_sorted, piece_deviation
from .jumps import locate_on_contour
from .lsq_setup import CornerTips, RotatedContour, crack_normals, curvature_knots
from .options import DEFAULT_EPSILON, extrapolates_tips

__all__ = ["OutlineRegression"]


def _unique(values):
    """``numpy.unique`` of a 1-d array without NaN (sorted, each value once) by a sort and a mask: the knot lists
    here are short and ``unique``'s set-up costs more than the work."""
    values = np.sort(values)
    if values.shape[0] < 2:
        return values
    keep = np.empty(values.shape[0], bool)
    keep[0] = True
    np.not_equal(values[1:], values[:-1], out=keep[1:])
    return values[keep]

#: Smallest curvature (1/px) of the fitted curve at which the pixel check applies (:meth:`pixel_excess`):
#: bends of radius up to 50 px, where a cut-short fillet or rounded corner lies.
PIXEL_MIN_CURVATURE = 1.0 / 50.0
#: Largest spacing (px of parameter) of the curve samples of :meth:`OutlineRegression.zone_hooks`: a curve that
#: crosses a crack's segment has a sample within half of it, below ``pixel_slack`` (0.1 px).
ZONE_SPACING = 0.1
#: Contour points on each side of a corner whose chords decide whether it is convex or a notch, the side on which
#: its zone's allowance holds (:meth:`OutlineRegression._allowance_sides`).
TURN_REACH = 3


class _Deviations:
    """The deviations of a model's current fit (:meth:`OutlineRegression.deviations`), computed on the first
    look-up: tests that need them only now and then share one computation."""

    def __init__(self, model):
        self._model, self._values = model, None

    def __getitem__(self, key):
        if self._values is None:
            self._values = self._model.deviations()
        return self._values[key]


class OutlineRegression:
    """Least-squares fit state of one closed outline; the knot insertion that drives it is
    :class:`~splinecraft.capture.fitting.lsq.LsqKnotInsertion`.

    Parameters
    ----------
    points : (n, 2) closed contour polyline (first point not repeated).
    corners : sorted unique corner indices into ``points`` (may be empty).
    epsilon : tolerance (px) of the stopping rule.
    options : the ``"lsq"`` options (:data:`~splinecraft.capture.fitting.options.LSQ_DEFAULTS`, checked).
    pixel_corners : the contour's :class:`~splinecraft.capture._pixel_corners.PixelCorners`, or ``None``: found
        where the corner tips need them (:class:`~.lsq_setup.RotatedContour`).
    pinholes : centres ``(m, 2)`` of the pinholes trace filled near the contour, or ``None`` (the corner tips of
        notches that reach them, :func:`~.tips.tip_estimates`).

    Main attributes: ``contour`` (:class:`~.lsq_setup.RotatedContour`), ``tips``
    (:class:`~.lsq_setup.CornerTips`), ``simple_knots`` (rotated contour indices of the simple knots),
    ``base_parameter`` (n + 1 values: arc length plus the corner gaps), ``parameter`` (the current, projected
    parameter of every contour point), ``period``.
    """

    def __init__(self, points, corners, epsilon, options, pixel_corners=None, pinholes=None):
        contour = self.contour = RotatedContour(np.asarray(points, float), corners, pixel_corners, pinholes)
        n = contour.size
        self.epsilon = float(epsilon)
        self.corner_allowance = float(options["corner_allowance"])
        self.min_gap = int(options["min_gap"])
        self.sample_spacing = float(options["sample_spacing"])
        self.hoschek_gate = float(options["hoschek_gate"])
        self.corner_pin = float(options["corner_pin"])
        #: multiplicity of every inserted knot: 1 (the spline is C2 there) or 2 (C1, as a font's segments join)
        self.knot_multiplicity = 3 - int(options["joint_continuity"])
        #: simple knots of multiplicity 2 at the curvature jumps of an earlier fit (:mod:`.jumps`): sorted rotated
        #: contour indices, never removed (:meth:`seed_jumps`)
        self.jump_knots = np.zeros(0, dtype=np.int64)
        if contour.corner_count:
            self.simple_knots = np.zeros(0, dtype=np.int64)
        else:  # four equally spaced knots, the seam knot 0 among them
            self.simple_knots = np.unique(np.round(np.arange(4) * n / 4).astype(np.int64))
        self.fixed = np.zeros(n + 1, bool)  # points whose parameter never moves: the corners (or the seam)
        self.fixed[contour.corner_bounds if contour.corner_count else 0] = True
        #: points whose parameter went back to its base value for good (:meth:`reset_parameters`)
        self.held = np.zeros(n + 1, bool)
        geometric = extrapolates_tips(options["geometric_corners"])
        self.tips = CornerTips.measure(contour, float(options["corner_radius"]), float(options["tip_gap"]),
                                       geometric, self.corner_allowance)
        self.base_parameter = self._base_parameter()
        self.period = float(self.base_parameter[-1])
        self._corner_par = self.base_parameter[contour.corner_bounds]  # of every corner, and the period (or seam)
        #: the corners' base parameters (sorted; none without corners)
        self._corner_values = self.base_parameter[contour.corner_bounds[:-1]] if contour.corner_count else np.zeros(0)
        bounds, piece = contour.corner_bounds, contour.piece_of_point
        self.parameter_low = self.base_parameter[bounds[piece]]
        self.parameter_high = self.base_parameter[bounds[piece + 1]]
        self.parameter = self.base_parameter.copy()
        self._step_bounds = self._parameter_bounds()  # (low, high, fixed, base) of the Hoschek steps
        self._piece_of_points = contour.piece_of_point[:n]
        self._normal_work = None  # the work arrays of the normal equations (_kernels.normal_work)
        self._zone_cache = None  # (tip state, {dense: zones}) of _zones
        self._knot_cache = self._weight_cache = None  # (simple knots, knot vector) and (radii, weights) of fit
        self._knot_index_cache = None  # (simple knots, knot_indices)
        self._knot_list_cache = None  # (knot_indices, their original indices, each piece's first and last) of knot_lists
        self._hook_limit = None  # (tips, the displacement limit) of hooked_corners
        self._zone_window_cache = None  # (radii and exclusions, set-up) of zone_hooks (_zone_window)
        # the most curve parameters of a zone window so far (_kernels.zone_window; a first guess: a row of some 250)
        self._zone_bound = 256 * contour.corner_count
        # the pixel check (docs/capture.md §12, "Pixel consistency"): on a crack outline
        # (C2 joints only: the freer C1 fit, joint_continuity=1, keeps a disc's four pieces 0.1-0.2 px beside them)
        # (nor with merge_tolerance > 0: merging rebuilds the segments under its own tolerance)
        pixel_check = options["pixel_check"] and self.knot_multiplicity == 1 and \
            not float(options.get("merge_tolerance", 0.0)) > 0
        # the crack normals of a crack outline (None: not one), found once where the corner zones' sides
        # (_allowance_sides), zone_hooks or the pixel check need them
        cracks = crack_normals(contour.points) if contour.corner_count or pixel_check else None
        # (the crack normals of the contour, or None,) of zone_hooks; (None,) where tips are not extrapolated (a
        # noisy boundary, trace's estimate above CLEAN_NOISE: its pixels are no render's)
        self._cracks = (cracks,) if geometric else (None,)
        self._dense_probes = None  # the contour points and edge midpoints of the dense check (_probes)
        # the pixel check's crack normals, or None
        self.crack_normal = cracks if pixel_check else None
        self._side_tables = self._allowance_sides(cracks)
        self.pixel_slack = float(options["pixel_slack"]) + max(0.0, self.epsilon - DEFAULT_EPSILON)
        self.pixel_waived = np.zeros(n, bool)
        self.pixel_exempt = self._pixel_exempt() if self.crack_normal is not None else None
        #: intervals whose pixel check failed but could not be split in the last :meth:`insert` (then waived)
        self.last_waived = []

    def seed_knots(self, density):
        """First simple knots placed by the contour's curvature (:func:`~.lsq_setup.curvature_knots`)."""
        seeded = curvature_knots(self.contour, self.simple_knots, density, self.epsilon, self.min_gap)
        if seeded is not None:
            self.simple_knots = seeded

    def seed_jumps(self, values, scales):
        """``C^1`` knots at the curvature jumps ``values`` (parameters of an earlier fit of this contour, found
        at window half-widths ``scales``; :func:`~.jumps.curvature_jumps`): each becomes a simple knot of
        multiplicity 2 at the contour point whose base parameter is nearest, and the first knots within half
        its scale (at least ``min_gap`` steps) go (the jump knot takes the step they were placed for), except
        the seam knot 0 of an outline without corners, which a jump closer than ``min_gap`` moves onto. The
        jump knots are never removed."""
        contour = self.contour
        n = contour.size
        base = self.base_parameter[:n]
        values = np.asarray(values, float).reshape(-1)
        j = np.clip(np.searchsorted(base, values), 1, n - 1)
        j = np.where(np.abs(base[j - 1] - values) <= np.abs(base[j] - values), j - 1, j)
        inside = ~member_sorted(j, contour.corner_bounds) if contour.corner_count else np.ones(j.shape[0], bool)
        j, reach = j[inside], np.asarray(scales, float)[inside]
        if not j.size:
            return
        bounds = contour.corner_bounds
        piece = contour.piece_of_point[j]
        j = locate_on_contour(contour.points, j, reach.astype(np.int64), np.column_stack([bounds[piece],
                              bounds[piece + 1]]), not contour.corner_count)
        knots = self.simple_knots
        clearance = np.maximum(0.5 * reach, self.min_gap)
        if not contour.corner_count:
            # the seam knot 0 stays (the knot intervals start there): a jump closer to it than min_gap moves onto it
            seam_gap = np.minimum(base[j], self.period - base[j])
            j = np.where(seam_gap < self.min_gap, 0, j)
        gap = np.abs(base[knots][:, None] - base[j][None, :])
        gap = np.minimum(gap, self.period - gap)  # around the seam of an outline without corners
        clear = (gap < clearance[None, :]).any(axis=1)
        if not contour.corner_count:
            clear &= knots != 0
        self.jump_knots = _unique(j.astype(np.int64))
        self.simple_knots = _unique(np.concatenate([knots[~clear], self.jump_knots]))

    def _base_parameter(self):
        """Base parameter of every contour point (n + 1 values): arc length, plus the gaps on both sides of
        each corner (the corner's own point sits in the middle of its gap)."""
        contour = self.contour
        if not contour.corner_count:
            return contour.arc.copy()
        after, before = self.tips.gap_after, self.tips.gap_before
        lengths = np.diff(contour.arc[contour.corner_bounds])
        # piece k: corner k, gap_after[k], the piece's arc length, gap_before[k + 1], corner k + 1
        corner_par = np.concatenate([[0.0], np.cumsum(after + lengths + np.concatenate([before[1:], before[:1]]))])
        k = contour.piece_of_point
        base = corner_par[k] + after[k] + contour.arc - contour.arc[contour.corner_bounds[k]]
        base[contour.corner_bounds] = corner_par
        return base

    # ---------------------------------------------------------------- knots, weights, zones
    def knot_values(self):
        """The knots of one period: corners three times, the inserted knots ``inserted_multiplicity`` times, sorted."""
        return self._knot_vector()[0]

    def _knot_vector(self):
        """:meth:`knot_values`, the full knot vector and the knot intervals' starts and ends
        (:func:`~._kernels.knot_vector`)."""
        return knot_vector(self._corner_values, self.base_parameter[self.simple_knots], self.inserted_multiplicity(),
                           self.period)

    def inserted_multiplicity(self):
        """Multiplicity of every simple knot: ``knot_multiplicity`` (2 for the jump knots), but 1 (C2) for the
        first and the last inserted knot of each piece between corners: the end pieces reach a truncated tip by
        extrapolation, which a C1 knot beside the corner would let bend into the rounded pixels (docs/capture.md
        §12, "Joints of lsq"; a jump knot there is a simple knot while it is first or last)."""
        knots = self.simple_knots
        multiplicity = np.full(knots.shape[0], self.knot_multiplicity, dtype=np.int64)
        if self.jump_knots.size and knots.size:
            multiplicity[member_sorted(knots, self.jump_knots)] = 2
        if not self.contour.corner_count or not knots.size or (multiplicity == 1).all():
            return multiplicity
        piece = self.contour.piece_of_point[knots]
        first = np.diff(piece, prepend=-1) != 0
        last = np.diff(piece, append=piece.max() + 1) != 0
        multiplicity[first | last] = 1
        return multiplicity

    def knot_indices(self):
        """Sorted rotated indices of all knots (corners once, simple knots) and the closing index n (kept while
        the simple knots are unchanged; do not modify)."""
        key = self.simple_knots.tobytes()
        if self._knot_index_cache is None or self._knot_index_cache[0] != key:
            self._knot_index_cache = (key, _unique(np.concatenate([self.contour.corner_bounds, self.simple_knots])))
        return self._knot_index_cache[1]

    def knot_lists(self):
        """Per piece, the caller's contour indices of its knots (corners at both ends; without corners the
        seam knot at both ends)."""
        contour = self.contour
        if not contour.corner_count:
            return [contour.original_index(np.append(self.simple_knots, contour.size))]
        knots = self.knot_indices()
        cached = self._knot_list_cache
        if cached is None or cached[0] is not knots:  # kept with the knot indices (the snapshots and the result)
            bounds = contour.corner_bounds
            # the knots from corner a to corner b, both included: one slice of the sorted knots per piece
            cached = self._knot_list_cache = (knots, contour.original_index(knots),
                                              np.searchsorted(knots, bounds[:-1]).tolist(),
                                              np.searchsorted(knots, bounds[1:], "right").tolist())
        _, original, first, last = cached
        return [original[lo:hi].copy() for lo, hi in zip(first, last)]

    def zone(self):
        """Boolean per point (n + 1): within ``2 r + 1`` px (arc length) of a corner whose tip is still
        extrapolated, ``r`` its initial weighting radius; the tolerance there is ``epsilon + corner_allowance``."""
        contour, tips = self.contour, self.tips
        if not contour.corner_count:
            return np.zeros(contour.size + 1, bool)
        return self._corner_tables(False)[0] > 0

    def allowance(self):
        """Extra tolerance of every point (n + 1) in the zone of an extrapolated corner (that corner's
        ``allowance``: ``corner_allowance``, or its extrapolated tip's distance from the contour), 0 elsewhere."""
        if not self.contour.corner_count:
            return np.zeros(self.contour.size + 1)
        return self._corner_tables(False)[1]

    def _corner_tables(self, dense):
        """:meth:`zone` (as floats), :meth:`allowance` and both of every probe (``dense``: the edge midpoints between
        the contour points too) in one compiled pass (:func:`~._kernels.corner_tables`)."""
        contour, tips = self.contour, self.tips
        return corner_tables(tips.zone_radius, tips.radius, tips.allowance_kept, tips.allowance,
                             contour.nearest_corner, contour.corner_distance, dense)

    def weights(self):
        """Weight of every contour point: ``min(1, (distance / r)^2)`` within the radius ``r`` of an extrapolated
        corner (the corner point itself 0), else 1; at least 1e-3."""
        contour = self.contour
        if not contour.corner_count:
            return np.ones(contour.size)
        n = contour.size
        return corner_weights(self.tips.radius, contour.nearest_corner[:n], contour.corner_distance[:n],
                              self.fixed[:n])

    def _pins(self):
        """Virtual data points (weight ``corner_pin``), or None: at the straight-line corner estimates, and at a
        third and two thirds of every piece of fewer than ``min_gap`` contour steps between two estimated corners
        (the end of a stroke one or two pixels wide between its two pixel corners, which
        :func:`~.lsq_setup.thin_corners` keeps), on the chord between the estimates: that piece's one or two contour
        points leave its cubic underdetermined, and its cracks lie on the chord."""
        tips, contour = self.tips, self.contour
        if not contour.corner_count or self.corner_pin <= 0:
            return None
        ok = np.isfinite(tips.estimate[:, 0]) & (tips.radius > 0)
        if not ok.any():
            return None
        idx = np.flatnonzero(ok)
        parameters, targets = [self.base_parameter[contour.corner_bounds[idx]]], [tips.estimate.take(idx, axis=0)]
        bounds = contour.corner_bounds
        nxt = (np.arange(contour.corner_count) + 1) % contour.corner_count
        short = np.flatnonzero((np.diff(bounds) < self.min_gap) & ok & ok[nxt])
        if short.size:
            third = np.array([1.0, 2.0]) / 3.0
            low, high = self.base_parameter[bounds[short]], self.base_parameter[bounds[short + 1]]
            parameters.append((low[:, None] + third * (high - low)[:, None]).ravel())
            start, end = tips.estimate[short], tips.estimate[nxt[short]]
            targets.append((start[:, None, :] + third[None, :, None] * (end - start)[:, None, :]).reshape(-1, 2))
        parameters, targets = np.concatenate(parameters), np.concatenate(targets)
        return parameters, targets, np.full(parameters.shape[0], self.corner_pin)

    # ---------------------------------------------------------------- fitting
    def fit(self, hoschek_steps=1):
        """Solve the weighted least-squares problem, then ``hoschek_steps`` times correct the parameters
        (one Newton step of the foot-point equation, with ``S, S', S''`` from the power form of each knot
        interval's Bézier piece, only in pieces whose residuals are below ``hoschek_gate``: projecting onto a bad
        curve scrambles the parameters) and solve again. A correction that moves no parameter (every piece above
        the gate) ends the steps: each solve and step after it would repeat the last bit for bit. The step is
        clipped between the fixed (or held) points around each point, those stay at their base parameter, and
        the parameters are kept non-decreasing (:func:`~._kernels.fit_step`)."""
        count, knot_vector, starts, ends, values = self._knot_setup()
        pin_u, targets, all_weights = self._weight_setup()
        contour = self.contour
        n = contour.size
        u = self.parameter[:n]
        work = self._normal_work
        if work is None or work[0].shape[1] != count:
            work = self._normal_work = normal_work(count)
        bounds = self._step_bounds
        for step in range(hoschek_steps + 1):
            coefficients = fit_coefficients(knot_vector, u, all_weights, targets, count, extra=pin_u, work=work)
            bezier = None
            if step == hoschek_steps:
                break
            bezier, stepped, same = fit_step(coefficients, knot_vector, count, starts, ends, _THETA4, _FROM_SAMPLES, u,
                                             contour.points, self._piece_of_points, contour.piece_count,
                                             self.hoschek_gate, bounds, values)
            if same:  # the same parameters, bit for bit (signed zeros included)
                break
            u = stepped
        self.parameter[:n] = u
        self.coefficients, self.knot_vector, self.coefficient_count = coefficients, knot_vector, count
        self._starts, self._ends = starts, ends
        self._bezier = bezier_of_intervals(coefficients, knot_vector, count, starts, ends) if bezier is None else bezier
        return coefficients

    def _knot_setup(self):
        """The knots' part of :meth:`fit` (kept while the simple knots are unchanged): the coefficient count,
        the full periodic knot vector, the knot intervals (multiple knots once) and a work array of the spline's
        values on them."""
        key = self.simple_knots.tobytes()
        if self._knot_cache is None or self._knot_cache[0] != key:
            knots, full, starts, ends = self._knot_vector()
            self._knot_cache = (key, (knots.shape[0], full, starts, ends,
                                      np.empty((starts.shape[0], _THETA4.shape[0], 2))))
        return self._knot_cache[1]

    def _weight_setup(self):
        """The data part of :meth:`fit` (kept while the corners' radii and tips are unchanged): the parameters of
        the corner pins (:meth:`_pins`; none: empty), the targets (contour points, then the pins) and their weights
        (:meth:`weights`)."""
        key = self.tips.radius.tobytes() + self.tips.estimate.tobytes()
        if self._weight_cache is None or self._weight_cache[0] != key:
            weights, pins = self.weights(), self._pins()
            targets = self.contour.points if pins is None else np.vstack([self.contour.points, pins[1]])
            all_weights = weights if pins is None else np.concatenate([weights, pins[2]])
            self._weight_cache = (key, (np.zeros(0) if pins is None else pins[0], targets, all_weights))
        return self._weight_cache[1]

    def _parameter_bounds(self):
        """Per contour point, the base parameters of the nearest fixed or held points at or before and at or
        after it (the closing index ``n`` counts as fixed), which points are fixed or held, and the points' base
        parameters: the range of its Hoschek steps (:meth:`fit`). Without held points these are the piece's
        corners (the seam)."""
        n = self.contour.size
        anchor = self.fixed[:n] | self.held[:n]
        low, high = anchor_bounds(anchor, self.base_parameter)
        return low, high, anchor, self.base_parameter[:n]

    def reset_parameters(self, dev, stuck, reach=2):
        """Give the points around the stuck knot intervals ``stuck`` (from ``reach`` knots before each one to
        ``reach`` knots after it, within its piece) their base parameter (arc length) back, and hold them there
        for the rest of the fit (no more Hoschek steps). Projected onto a curve that misses the contour there,
        their parameters can have bunched up and left knot intervals next to them with few data points or
        none; the least-squares spline is then free to loop there, and no knot can be inserted between knots
        fewer than ``2 min_gap`` steps apart (docs/capture.md §12, "The lsq method"). Returns the intervals
        whose points had moved from there."""
        contour = self.contour
        n = contour.size
        knots = self.knot_indices()
        knot_values = self.base_parameter[knots]
        reset = []
        for f in stuck:
            first = min(int(np.searchsorted(knot_values, dev["starts"][f] - 1e-9)), knots.shape[0] - 1)
            piece = contour.piece_of_point[knots[first]]
            lo = max(int(knots[max(first - reach, 0)]), int(contour.corner_bounds[piece]))
            hi = min(int(knots[min(first + 1 + reach, knots.shape[0] - 1)]), int(contour.corner_bounds[piece + 1]))
            if hi <= lo or self.held[lo:hi + 1].all():
                continue
            self.held[lo:hi + 1] = True
            if np.any(self.parameter[lo:hi + 1] != self.base_parameter[lo:hi + 1]):
                reset.append(int(f))
        self.held[n] = False  # the closing index is the seam, not a contour point
        base, u = self.base_parameter, self.parameter
        u[self.held] = base[self.held]
        self._step_bounds = low, high, _, _ = self._parameter_bounds()
        u[:n] = np.minimum(np.maximum(u[:n], low), high)  # in order with the held points
        return reset

    # ---------------------------------------------------------------- geometry of the current fit
    def intervals(self):
        """Starts and ends of the knot intervals of the current fit (multiple knots once)."""
        return self._starts, self._ends

    def bezier(self):
        """Bézier control points (k, 4, 2) of the current fit on its knot intervals."""
        return self._bezier

    def curve_at(self, u):
        """Points ``S(u)`` of the current fit (``u`` in ``[0, period]``)."""
        starts, ends = self.intervals()
        return curve_points(self._bezier, starts, ends, u)

    def point(self, index):
        """Contour point of a rotated index (modulo n)."""
        return self.contour.points[index % self.contour.size]

    def point_before(self, value):
        """The rotated index of the first contour point whose parameter is not below ``value``."""
        return int(np.clip(np.searchsorted(self.parameter, value), 0, self.contour.size - 1))

    def hooked_corners(self, dev=None):
        """Corners (still extrapolated) whose fitted point lies farther from the contour corner point than
        the tip of a pixel shape can be truncated: ``0.5 / sin(theta / 2)`` for the interior angle ``theta``,
        at least 0.75 px, at most ``epsilon + corner_allowance``. Such a corner is a misfit of the pieces'
        extensions (a hook), not a truncated tip. A corner with a kept tip estimate counts only where both
        pieces beside it fit (``dev``: the current fit's :meth:`deviations`, computed here when needed): on a
        coarse fit a piece that misses its pixels by several pixels moves its corner point as far."""
        if not self.contour.corner_count:
            return np.zeros(0, dtype=np.int64)
        return self._hooked(self._hook_tests(None)[0], dev)

    def _hook_limit_setup(self):
        """The displacement test's set-up of :meth:`hooked_corners` (kept while the tips' angles and estimates are
        unchanged): the corners' base parameters, their contour points and displacement limits (beyond a kept
        tip estimate, its distance from the corner point and 0.25 px more)."""
        contour, tips = self.contour, self.tips
        key = tips.angle.tobytes() + tips.estimate.tobytes()
        if self._hook_limit is None or self._hook_limit[0] != key:
            corners = contour.corner_bounds[:-1]
            limit = np.clip(0.5 / np.maximum(np.sin(0.5 * tips.angle), 1e-3), 0.75,
                            self.epsilon + self.corner_allowance)
            reach = np.hypot(*(tips.estimate - contour.points.take(corners % contour.size, axis=0)).T)
            self._hook_limit = (key, self.base_parameter[corners], contour.points.take(corners % contour.size, axis=0),
                                np.where(np.isfinite(reach), np.maximum(limit, reach + 0.25), limit))
        return self._hook_limit[1:]

    def _hook_tests(self, window):
        """Both tests after a fit in one compiled pass (:func:`~._kernels.hook_tests`): per corner whether its
        fitted point moved beyond the limit of :meth:`hooked_corners`, and per corner whether a point of the
        zone ``window`` (:meth:`_zone_window`, or None: no zone test) passes beside its pixels
        (:meth:`zone_hooks`)."""
        at, points, limit = self._hook_limit_setup()
        starts, ends = self.intervals()
        if window is None:
            hooked, _ = hook_tests(self._bezier, starts, ends, at, points, limit, self.tips.radius, _NO_FLOATS, 0,
                                   _NO_INTS, _NO_INTS, _NO_FLOATS, _NO_FLOATS, self.pixel_slack)
            return hooked, None
        u, rows, row, axis, along_start, across_start, owner = window
        hooked, beside = hook_tests(self._bezier, starts, ends, at, points, limit, self.tips.radius, u, rows, row,
                                    axis, along_start, across_start, self.pixel_slack)
        failing = np.zeros(self.contour.corner_count, bool)
        failing[owner[beside]] = True
        return hooked, failing

    def _hooked(self, moved, dev):
        """:meth:`hooked_corners` of the displacement test's answer ``moved`` (per corner)."""
        found = np.flatnonzero(moved)
        tipped = np.isfinite(self.tips.estimate[found, 0])
        if not tipped.any():
            return found
        return found[~tipped | self._pieces_fit(found, dev)]

    def _zone_failing(self, failing, dev):
        """:meth:`zone_hooks` of the zone test's answer ``failing`` (per corner)."""
        found = np.flatnonzero(failing)
        if not found.size:
            return np.zeros(0, dtype=np.int64)
        return found[self._pieces_fit(found, dev)]

    def hooks(self, dev=None):
        """The corners to release after a fit: :meth:`hooked_corners` and :meth:`zone_hooks` (``dev``: the
        current fit's :meth:`deviations`, if at hand)."""
        hooked, zone = self.hook_releases(dev)
        return np.union1d(hooked, zone).astype(np.int64) if zone.size else hooked

    def zone_hooks(self, dev=None, exclude=()):
        """Corners (still extrapolated, not in ``exclude``) whose fitted curve leaves the two pixel centres of a
        crack on one side by more than ``pixel_slack`` within the corner's weighting radius (at least 1 px of
        arc from the corner point), where both pieces beside the corner fit (their deviation within the
        tolerance; ``dev``: the current fit's :meth:`deviations`, computed here when needed). On a crack
        outline every crack separates an ink and a paper pixel centre 1 px apart, and the true outline crosses
        the segment between them, at a truncated tip as anywhere else: pieces that pass beside it there bend
        away from the pixels where the corner's weights let them (a hook), not towards a tip the pixels allow.
        Judged only where the pieces beside the corner fit: on the coarse first fits a piece that misses its
        pixels everywhere misses them near its corners too. Only crack outlines are checked (else none), and
        only where tips are extrapolated (option ``geometric_corners``: not on a noisy boundary, whose pixels are
        no render of an outline). Nor a notch tip that a pinhole placed (``contour.pinhole_tips``,
        :func:`~.tips.tip_estimates`): its notch narrows below a pixel before the tip, so the pieces that reach
        the pinhole pass the ink centres between it and the rendered notch within less than the fit's own error.

        The crack normal is (1, 0) or (0, 1): the pixel centres' segment runs from ``along_start`` over [0, 1]
        along the normal's axis, so the distance of a sample from it is that of (along - clip(along, 0, 1),
        across) -- the operations of the projection onto a unit axis vector, without its zero products. A corner
        fails where one of its points has every sample farther than the slack (its least distance above it;
        compiled, :func:`~._kernels.hook_tests`: each point's scan stops at its first sample within it); a corner
        with a NaN sample does not (the least distance of each of its points is NaN then)."""
        window = self._zone_window(self._zone_exclusion(exclude))
        if window is None:
            return np.zeros(0, dtype=np.int64)
        return self._zone_failing(self._hook_tests(window)[1], dev)

    def _zone_exclusion(self, exclude):
        """The corners :meth:`zone_hooks` leaves out: ``exclude`` and the pinhole tips."""
        pinhole_tips = self.contour.pinhole_tips
        return np.union1d(exclude, pinhole_tips) if pinhole_tips.size else exclude

    def _zone_window(self, exclude=()):
        """The set-up of :meth:`zone_hooks` (kept while the corners' radii and ``exclude`` are unchanged), or None
        where there is nothing to test: the parameters of the tested corners' curve samples (per corner,
        at most ``ZONE_SPACING`` apart over the corner's parameter window: its reach and gaps on both sides, and
        2 px more; a curve that crosses a segment has a sample within half a spacing), one row of them per tested
        corner, and the number of rows; per contour point within a corner's reach (``max(r, 1)`` px of arc) its
        corner's row, the axis of its crack normal (0: x, 1: y; the coordinate along it), the coordinates of the
        pixel centre at the segment's start (along; the other centre lies 1 px further) and of the crack (across),
        and its corner."""
        contour, tips = self.contour, self.tips
        if not contour.corner_count:
            return None
        cracks = self._cracks[0]
        if cracks is None:
            return None
        exclude = np.asarray(exclude, dtype=np.int64)
        key = tips.radius.tobytes() + exclude.tobytes()
        if self._zone_window_cache is not None and self._zone_window_cache[0] == key:
            return self._zone_window_cache[1]
        excluded = np.zeros(contour.corner_count, bool)
        excluded[exclude] = True
        n = contour.size
        window = zone_window(tips.radius, excluded, contour.nearest_corner[:n], contour.corner_distance[:n],
                             self.base_parameter[contour.corner_bounds[:-1]], tips.gap_before, tips.gap_after,
                             cracks[:, 1], contour.points, self.period, ZONE_SPACING, self._zone_bound)
        if window is not None:
            self._zone_bound = max(self._zone_bound, window[0].shape[0])
        self._zone_window_cache = (key, window)
        return window

    def _pieces_fit(self, corners, dev=None):
        """Per corner of ``corners``: whether both pieces beside it fit, their deviation within the tolerance
        (``dev``: the current fit's :meth:`deviations`, computed here when ``None``)."""
        if dev is None:
            dev = self.deviations()
        fits = dev["piece_excess"] <= 0
        pieces = self.contour.piece_count
        return fits[(corners - 1) % pieces] & fits[corners % pieces]

    def hook_releases(self, dev=None):
        """The corners to release after a fit, by reason: ``(hooked, zone)``, :meth:`hooked_corners` and
        :meth:`zone_hooks`; the fit's :meth:`deviations` (``dev``, if at hand) are computed at most once, and only
        where either test needs them. Both tests run in one compiled pass (:meth:`_hook_tests`); where a corner is
        hooked, the zone test runs again without it (its window, and so its samples, change)."""
        none = np.zeros(0, dtype=np.int64)
        if not self.contour.corner_count:
            return none, none
        deviations = _Deviations(self) if dev is None else dev
        window = self._zone_window(self._zone_exclusion(none))
        moved, failing = self._hook_tests(window)
        hooked = self._hooked(moved, deviations)
        if hooked.size:
            return hooked, self.zone_hooks(deviations, exclude=hooked)
        return hooked, none if window is None else self._zone_failing(failing, deviations)

    # ---------------------------------------------------------------- pixel consistency
    def _pixel_exempt(self):
        """Contour points the pixel check leaves out: within ``2 r + 1`` px (arc length, at least 2 px) of a
        corner, ``r`` its initial weighting radius, where the pieces reach past the truncated pixel tip."""
        contour = self.contour
        n = contour.size
        if not contour.corner_count:
            return np.zeros(n, bool)
        reach = np.maximum(2.0 * self.tips.zone_radius[contour.nearest_corner[:n]] + 1.0, 2.0)
        return contour.corner_distance[:n] < reach

    def pixel_excess(self):
        """Per contour point of a crack outline: how far (px) the fitted curve passes beside the segment
        between the two pixel centres its crack separates, on the inner side of a bend of the curve (the
        point lies on the curve's convex side, and the curve turns by at least :data:`PIXEL_MIN_CURVATURE`),
        less ``pixel_slack``; ``-inf`` elsewhere, near corners and where waived. The true boundary of a
        point-sampled render crosses every such segment (an inside and an outside pixel centre, 1 px apart),
        and very nearly so for area-sampled renders; a curve that passes inside a bend beside it cuts the
        bend (a fillet, a rounded corner) short. Beyond a bend is where extrapolated tips go and is not
        checked. The curve is taken locally as its tangent line at the point's foot point (two Gauss-Newton
        steps of the foot-point equation from the point's parameter)."""
        n = self.contour.size
        out = np.full(n, -np.inf)
        idx = np.flatnonzero(~(self.pixel_exempt | self.pixel_waived))
        if not idx.size:
            return out
        m = self.contour.points[idx]
        u = self.parameter[idx].copy()
        lo, hi = self.parameter_low[idx], self.parameter_high[idx]
        h = 0.1
        for step in range(3):
            a, b = np.maximum(u - h, lo), np.minimum(u + h, hi)
            before, point, after = self.curve_at(a), self.curve_at(u), self.curve_at(b)
            derivative = (after - before) / np.maximum(b - a, 1e-12)[:, None]
            if step == 2:
                break
            speed = np.maximum(np.einsum("kd,kd->k", derivative, derivative), 1e-12)
            du = np.clip(np.einsum("kd,kd->k", m - point, derivative) / speed, -2.0, 2.0)
            u = np.clip(u + du, lo, hi)
        length = np.maximum(np.hypot(*derivative.T), 1e-12)
        normal = np.column_stack([-derivative[:, 1], derivative[:, 0]]) / length[:, None]
        # the bend: second difference of the three samples, along the normal, per squared arc length
        wide = np.maximum(np.minimum(u - a, b - u), 1e-12)
        second = ((after - point) / np.maximum(b - u, 1e-12)[:, None] - (point - before)
                  / np.maximum(u - a, 1e-12)[:, None]) / (0.5 * (b - a))[:, None]
        bend = np.einsum("kd,kd->k", second, normal) / length**2
        bend = np.where(wide > 0.25 * h, bend, 0.0)
        crack = self.crack_normal[idx]
        side = np.einsum("kd,kd->k", m - point, normal)           # the crack midpoint's side of the curve
        reach = 0.5 * np.abs(np.einsum("kd,kd->k", crack, normal))  # the centres lie side +- reach
        beside = np.abs(side) - reach
        inner = (np.abs(bend) >= PIXEL_MIN_CURVATURE) & (side * bend < 0)  # the pixels on the convex side
        out[idx] = np.where(inner, np.maximum(beside, 0.0) - self.pixel_slack, -np.inf)
        return out

    # ---------------------------------------------------------------- deviations
    def deviations(self, dense=False):
        """Closest-point deviations of the current fit, both directions (upper bounds, docs/capture.md §12).

        * curve -> contour: curve samples (``sample_spacing`` px apart; ``dense``: 0.25 px) to the contour
          edges in a window around the sample's corresponding contour position (the piece's own edges and
          three more across each corner);
        * contour -> curve: every contour point (``dense``: and every edge midpoint) to its corresponding curve
          point ``S(u_j)``; where that is more than ``epsilon`` (``dense``: ``epsilon / 2``), to the nearest
          chord of the curve samples within 3 px of parameter instead.

        Returns a dict: per knot interval the worst excess over the tolerance (``epsilon``, plus the corner's
        allowance in the zone of an extrapolated corner, on a crack outline only on the side of its tip:
        :meth:`_allowance_sides`, docs/capture.md §12 "Guarantee"), per piece the max deviation, the thesis
        error (contour point to its corresponding curve point) and the worst excess, and the per-probe arrays
        that :meth:`insert` needs."""
        contour = self.contour
        n = contour.size
        starts, ends = self.intervals()
        bez = self.bezier()
        spacing = min(self.sample_spacing, 0.25) if dense else self.sample_spacing
        # the samples' parameters with the period after them (the closed parameters of the check)
        samples, closed_params, iv = interval_samples(bez, starts, ends, spacing, self.period)
        probes, probe_u, probe_piece, is_point = self._probes(dense)
        zone, allowance, probe_zone, probe_allowance = self._zones(dense)
        dev = deviation_measures(bez, starts, ends, samples, closed_params, iv, self._corner_par, contour.corner_bounds,
                                 contour.corner_count > 0, self.parameter, self.base_parameter, contour.edges, probes,
                                 probe_u, probe_piece, is_point, zone, allowance, probe_allowance, self.epsilon,
                                 0.5 * self.epsilon if dense else self.epsilon, int(np.ceil(3.0 / spacing)),
                                 *self._side_tables[dense])
        dev.update(starts=starts, ends=ends, probe_zone=probe_zone, curve_iv=iv, curve_params=closed_params[:-1],
                   bezier=bez, dense=dense, tol_excess=dev["excess"], pixel=None, pixel_iv=None)
        if self.crack_normal is not None:
            k = starts.shape[0]
            pixel = self.pixel_excess()
            pixel_iv = np.clip(np.searchsorted(ends, self.parameter[:n]), 0, k - 1)
            if contour.corner_count:  # not in a piece's end intervals: they reach the corner's tip, or its pixels
                tip = self.base_parameter[contour.corner_bounds[:-1]]
                end = np.isin(starts, tip) | np.isin(ends, tip) | np.isin(ends, tip + self.period)
                pixel = np.where(end[pixel_iv], -np.inf, pixel)
            dev.update(excess=np.maximum(dev["excess"], group_max(pixel_iv, pixel, k)[0]), pixel=pixel,
                       pixel_iv=pixel_iv)
        return dev

    def tighten(self, dev):
        """Where a piece's windowed deviation (:meth:`deviations`) exceeds ``epsilon``, the smaller of it and the
        piece's closest-point deviation over all its edges (:func:`~.geometry.piece_deviation`, with the three
        edges across each corner that the window reaches too), in ``dev["piece_dev"]`` (both bound the true
        distance from above). The window follows the parameterization: where that has gone wrong (a curve that
        loops through knot intervals without data, on a fit that did not converge) it can miss the nearest
        edges and report several times the true distance."""
        contour = self.contour
        n, bounds = contour.size, contour.corner_bounds
        starts = dev["starts"]
        piece_dev = dev["piece_dev"].copy()
        corner_par = self.base_parameter[bounds]
        for p in np.flatnonzero(piece_dev > self.epsilon):
            lo, hi = np.searchsorted(starts, corner_par[p] - 1e-9), np.searchsorted(starts, corner_par[p + 1] - 1e-9)
            if hi <= lo:
                continue
            if contour.corner_count:
                idx = np.arange(bounds[p] - 3, bounds[p + 1] + 4) % n
            else:
                idx = np.arange(n + 1) % n
            exact = piece_deviation(dev["bezier"][lo:hi], contour.points[idx])
            piece_dev[p] = min(piece_dev[p], exact)
        dev["piece_dev"] = piece_dev
        return dev

    def _allowance_sides(self, cracks):
        """The side of the contour on which the corner zones' allowance holds (the side of the corner's tip beyond
        the pixels: the paper at a convex corner, the ink at a notch; the contour's turn over :data:`TURN_REACH`
        points each way decides), per contour point (n + 1) and per probe of both checks, as
        ``{dense: (point_side, probe_side)}``: +1 where the allowance is for the paper side, -1 for the ink side, in
        the deviation kernel's sign (the ink left of the contour's direction, ``x`` right and ``y`` down: the
        tracer's crack outlines, docs/capture.md §10; ``cracks``: their crack normals, None for other contours,
        whose allowance holds on both sides: empty arrays)."""
        contour = self.contour
        none = (_NO_FLOATS, _NO_FLOATS)
        if not contour.corner_count or cracks is None:
            return {False: none, True: none}
        n = contour.size
        closed = contour.closed_points
        bounds = contour.corner_bounds[:-1]
        before = closed[(bounds - TURN_REACH) % n] - closed[bounds]
        after = closed[(bounds + TURN_REACH) % n] - closed[bounds]
        turn = before[:, 1] * after[:, 0] - before[:, 0] * after[:, 1]  # cross(incoming, outgoing): > 0 convex
        corner_side = np.sign(turn)
        point_side = corner_side[contour.nearest_corner]
        probe_dense = np.repeat(point_side[:n], 2)
        return {False: (np.ascontiguousarray(point_side, float), np.ascontiguousarray(point_side[:n], float)),
                True: (np.ascontiguousarray(point_side, float), np.ascontiguousarray(probe_dense, float))}

    def _zones(self, dense):
        """The corner zones (:meth:`zone`, as floats) and :meth:`allowance` of every contour point and of every
        probe (``dense``: the edge midpoints between, in a zone where either end is, with the larger allowance);
        kept while the corners' tip state is unchanged (both forms: the rounds alternate between them)."""
        tips = self.tips
        key = (tips.radius.tobytes(), tips.allowance_kept.tobytes(), tips.allowance.tobytes())
        cached = self._zone_cache
        if cached is None or cached[0] != key:
            cached = self._zone_cache = (key, {})
        if dense in cached[1]:
            return cached[1][dense]
        value = cached[1][dense] = self._corner_tables(dense)
        return value

    def _probes(self, dense):
        """Contour points (``dense``: and edge midpoints), in parameter order: points, parameters (``dense``: None,
        the deviation check's kernel takes the points' and the midpoints' means of theirs,
        :func:`~._kernels.deviation_measures`), pieces and which of them are contour points."""
        contour = self.contour
        n = contour.size
        if not dense:
            return contour.points, self.parameter[:n], contour.piece_of_point[:n], np.ones(n, bool)
        if self._dense_probes is None:  # the contour's points and edge midpoints never change
            probes = np.empty((2 * n, 2))
            probes[0::2], probes[1::2] = contour.points, 0.5 * (contour.closed_points[:-1] + contour.closed_points[1:])
            self._dense_probes = (probes, None, np.repeat(contour.piece_of_point[:n], 2), np.tile([True, False], n))
        return self._dense_probes

    # ---------------------------------------------------------------- knot insertion
    def insert(self, dev, tight=False):
        """Insert one knot into every failing knot interval, at its worst point outside the corner zones,
        kept in the middle half of the interval. Where an interval fails only inside the zone of an
        extrapolated corner, knots cannot help (the fit ignores the truncated tip), so that corner stops being
        extrapolated instead.

        Returns (new knots as (rotated index, interval, excess), intervals that could not be split because
        their knots are fewer than ``2 min_gap`` steps apart, released corners). ``tight``: the last resort of a
        round in which nothing else helped, knots down to one contour step apart, and no pixel-check intervals."""
        n = self.contour.size
        excess = dev["excess"]
        failing = np.flatnonzero(excess > 0)
        if failing.size == 0:
            return [], [], []
        k = excess.shape[0]
        u_data, u_curve = dev["probe_u"], dev["curve_params"]
        # worst excess per interval outside / inside the corner zones, with its parameter (one compiled pass; as
        # lists: the loop below reads single values)
        best, at = interval_worst(dev["data_iv"], dev["probe_zone"], dev["d_data"], dev["tol_data"], dev["curve_iv"],
                                  dev["curve_zone"], dev["d_curve"], dev["tol_curve"], k)
        (out_d, out_c, in_d, in_c), (out_d_at, out_c_at, in_d_at, in_c_at) = best.tolist(), at.tolist()
        knots = self.knot_indices()
        knot_values = self.base_parameter[knots]
        new, stuck, released = [], [], []
        self.last_waived = []
        if dev["pixel"] is not None:
            pixel_worst, pixel_at = group_max(dev["pixel_iv"], dev["pixel"], k)
        gap = 1 if tight else self.min_gap
        # the knots at (or first after) the ends of every failing interval, one search for all of them
        last_knot = knots.shape[0] - 1
        lefts = knots[np.minimum(np.searchsorted(knot_values, dev["starts"][failing] - 1e-9), last_knot)].tolist()
        rights = knots[np.minimum(np.searchsorted(knot_values, dev["ends"][failing] - 1e-9), last_knot)].tolist()
        for f, left, right in zip(failing, lefts, rights):
            a, b = dev["starts"][f], dev["ends"][f]
            pixel_only = dev["tol_excess"][f] <= 0
            if pixel_only and tight:
                continue
            if pixel_only:  # within the tolerance, but not consistent with the pixels: a knot at the worst point
                best, where = pixel_worst[f], self.parameter[pixel_at[f]]
            elif max(out_d[f], out_c[f]) <= 0:
                in_data = in_d[f] >= in_c[f]
                best = in_d[f] if in_data else in_c[f]
                where = u_data[in_d_at[f]] if in_data else u_curve[in_c_at[f]]
                c = int(self.contour.nearest_corner[min(max(int(np.searchsorted(self.parameter, where)), 0), n)])
                if self.tips.release(c):
                    released.append(c)
                    continue
                # the corner already follows the pixels: a knot may still help
            elif out_d[f] >= out_c[f]:
                best, where = out_d[f], u_data[out_d_at[f]]
            else:
                best, where = out_c[f], u_curve[out_c_at[f]]
            quarter = 0.25 * (b - a)
            where = min(max(where, a + quarter), b - quarter)
            if right - left < 2 * gap:
                if pixel_only:  # no knot fits: the check gives way there for the rest of the fit
                    self.pixel_waived[dev["pixel_iv"] == f] = True
                    self.last_waived.append(int(f))
                else:
                    stuck.append(int(f))
                continue
            j = min(max(int(np.searchsorted(self.parameter[:n], where)), left + gap), right - gap)
            new.append((j, int(f), float(best)))
        if new:
            self.simple_knots = _unique(np.concatenate([self.simple_knots, [j for j, _, _ in new]]).astype(np.int64))
        return new, stuck, released

    def release_corners(self, dev, stuck):
        """Reduce the extrapolation of the corners near a stuck interval (knots too close to split it); a corner
        that already follows the pixels keeps the corner allowance in its zone instead (a ragged, truncated tip
        that a C² piece cannot follow within epsilon). Returns the corner numbers."""
        contour, tips = self.contour, self.tips
        released = []
        if not contour.corner_count:
            return released
        r = tips.zone_radius[contour.nearest_corner]
        zone = (r > 0) & (contour.corner_distance < 2.0 * r + 1.0)
        for f in stuck:
            j0 = np.searchsorted(self.base_parameter, dev["starts"][f])
            j1 = np.searchsorted(self.base_parameter, dev["ends"][f])
            inside = np.flatnonzero(zone[j0: j1 + 1]) + j0
            for c in np.unique(contour.nearest_corner[inside]):
                if tips.release(int(c)):
                    released.append(int(c))
                elif not tips.allowance_kept[c]:
                    tips.allowance_kept[c] = True
                    released.append(int(c))
        return released

    # ---------------------------------------------------------------- knot removal
    def removal_scores(self, bezier):
        """For every simple knot: score = |jump of S'''| * h^3 / 48, about the deviation that removing the knot
        causes (the size of the cubic's departure from one polynomial), plus |jump of S''| * h^2 / 16 where
        S'' jumps (knots of multiplicity 2, ``joint_continuity=1``); one compiled pass
        (:func:`~._kernels.removal_scores`)."""
        starts, ends = self.intervals()
        return removal_scores(bezier, starts, ends, self.base_parameter[self.simple_knots], self.knot_multiplicity != 1)

    def removable_mask(self):
        """Which simple knots may be removed (not the seam knot 0 of an outline without corners, nor a jump
        knot)."""
        mask = (self.simple_knots != 0) | (self.contour.corner_count > 0)
        if self.jump_knots.size:
            mask &= ~member_sorted(self.simple_knots, self.jump_knots)
        return mask

    def removable_knots(self):
        """Simple knots that may be removed (:meth:`removable_mask`)."""
        return self.simple_knots[self.removable_mask()]

    def remove(self, indices):
        """Remove simple knots (never the seam knot at index 0 of an outline without corners, where the
        knot intervals start)."""
        knots = self.simple_knots
        indices = np.asarray(indices, dtype=np.int64).reshape(-1)
        at = np.minimum(np.searchsorted(knots, indices), max(knots.shape[0] - 1, 0))
        keep = np.ones(knots.shape[0], bool)
        if knots.shape[0]:  # the simple knots are sorted and unique: a membership test by position
            keep[at[knots[at] == indices]] = False
        self.simple_knots = knots[keep | (knots == 0)]

    def restore(self, indices):
        self.simple_knots = _unique(np.concatenate([self.simple_knots, np.asarray(indices, dtype=np.int64)]))

    _FIT_STATE = ("simple_knots", "parameter", "coefficients", "knot_vector", "coefficient_count", "_starts",
                  "_ends", "_bezier")

    def save(self):
        """The knots and the current fit (to go back to without refitting)."""
        return {name: getattr(self, name) for name in self._FIT_STATE} | {"parameter": self.parameter.copy()}

    def load(self, saved):
        for name, value in saved.items():
            setattr(self, name, value)
        self.parameter = self.parameter.copy()
