"""One closed contour of an editable outline, in the project's own spline form (thesis sections 3.1, 4.2.1; §2).

A contour is ``N >= 3`` knots ``F_0 .. F_{N-1}`` on a closed loop, interval ``i`` running from knot ``i`` to
knot ``i + 1`` (the last back to knot 0). Its curve is the engine's interpolant
(:func:`~splinecraft.spline.interpolate`): GC² joints (the weighted nu-spline constraint of thesis eqs 3.13,
3.14) at *smooth* knots, with a point tension ``v_i`` per knot and an interval weight ``omega_i`` per interval.
A knot flagged as a *corner* cuts the loop: between two consecutive corners the curve is one open interpolant
whose end tangents are the corner's *handles* (the Bézier offsets ``b1 - b0`` leaving the knot and ``b2 - b3``
arriving at it; clamped ends, §2.4 Type 1); where a corner has no handle the end tangent is the 3-point
parabola estimate of §6.3 (the engine's default clamped end), so the tangent follows the neighbouring knots.
Without corners the loop is one periodic interpolant (§2.4 Type 3).

The parameter steps ``h_i`` (the knot spacing of §3) are stored per interval, so that an affine map of the
knots and handles maps the curve exactly (the tangent system depends on ``h``, ``v``, ``omega`` only and is
linear in the points; thesis section 3.3, "transform only the control points"). Edits that move some knots
rescale the steps of the changed intervals with their chord lengths (chord-length knots, §3), except that an
affine map of all the knots of a run between two corners keeps that run's steps, so the run maps exactly.

A :class:`Contour` is immutable and always valid: every constructor and edit rebuilds the curve with the
engine and raises ``ValueError`` (leaving the original untouched) when the engine refuses it.
"""
from __future__ import annotations

import numbers

import numpy as np

from .._validation import check_bool, check_number
from ..spline import Spline, interpolate
from ..spline.segment import bezier_signed_area
from .transforms import check_reach

__all__ = ["Contour", "MIN_KNOTS", "bezier_signed_area"]

#: A contour needs at least this many knots (a closed interpolant takes three distinct points, §2.4).
MIN_KNOTS = 3


def _array(value, name, shape, *, fill=None):
    """A finite float array of ``shape`` (a scalar broadcasts); ``None`` -> ``fill``."""
    if value is None:
        return np.full(shape, fill, dtype=float)
    if isinstance(value, (str, bytes)) or isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be numeric, got {type(value).__name__}")
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be numeric, got {type(value).__name__}") from None
    if array.ndim == 0:
        array = np.full(shape, float(array))
    if array.shape != shape:
        raise ValueError(f"{name} must have shape {shape} (one per knot or interval), got {array.shape}")
    return array


def _finite(array, name):
    bad = ~np.isfinite(array)
    if bad.any():
        index = np.unravel_index(int(np.flatnonzero(bad)[0]), array.shape)
        raise ValueError(f"{name}[{', '.join(str(int(i)) for i in index)}] is {float(array[index])!r}; it must be "
                         "finite")


def _chords(points):
    return np.hypot(*(np.roll(points, -1, axis=0) - points).T)


class Contour:
    """A closed contour: knots, corner flags, corner handles, parameter steps, point tension, interval weights.

    Parameters
    ----------
    points : array_like (N, 2)
        The knots, in order around the loop (do not repeat the first one); consecutive knots distinct.
    corners : array_like of bool (N,), optional
        Corner flags (default: all smooth).
    handles_in, handles_out : array_like (N, 2), optional
        Bézier offsets at corners: ``handles_out[i] = b1 - b0`` of the piece leaving knot ``i``,
        ``handles_in[i] = b2 - b3`` of the piece arriving at it. NaN (the default) = no handle: the end tangent
        is the 3-point parabola estimate (§6.3). Ignored
        (stored as NaN) at smooth knots.
    steps : array_like (N,), optional
        Parameter steps ``h_i > 0`` of the intervals (default: the chord lengths, §3).
    point_tension : float or array_like (N,)
        ``v_i`` per knot (default 0; §2.5 for the admissible values).
    interval_weights : float or array_like (N,)
        ``omega_i > 0`` per interval (default 1).

    Raises
    ------
    ValueError, TypeError
        Naming the argument (and index): fewer than 3 knots, non-finite values, coincident neighbours,
        non-positive steps or weights, a point tension in the engine's singular band.
    """

    __slots__ = ("points", "corners", "handles_in", "handles_out", "steps", "point_tension", "interval_weights",
                 "spline")
    # an edit that changes only some knots rebuilds only the runs between corners that hold them (_build)
    _reuse = None

    def __init__(self, points, corners=None, *, handles_in=None, handles_out=None, steps=None, point_tension=0.0,
                 interval_weights=1.0):
        points = _array(points, "points", np.shape(points) if np.ndim(points) == 2 else (-1, 2))
        if points.ndim != 2 or points.shape[1] != 2:
            raise ValueError(f"points must have shape (N, 2), got {points.shape}")
        _finite(points, "points")
        check_reach(points, "the contour", given=True)  # areas and lengths in range (the transforms' limits)
        n = points.shape[0]
        if n < MIN_KNOTS:
            raise ValueError(f"a contour needs at least {MIN_KNOTS} knots, got {n}")
        if corners is None:
            corners = np.zeros(n, dtype=bool)
        corners = np.asarray(corners)
        if corners.shape != (n,) or corners.dtype.kind not in "biu":
            raise ValueError(f"corners must be {n} booleans (one per knot), got shape {corners.shape}")
        corners = corners.astype(bool)
        handles_in = _array(handles_in, "handles_in", (n, 2), fill=np.nan)
        handles_out = _array(handles_out, "handles_out", (n, 2), fill=np.nan)
        handles_in[~corners] = np.nan
        handles_out[~corners] = np.nan
        for name, handles in (("handles_in", handles_in), ("handles_out", handles_out)):
            if np.isinf(handles).any():
                raise ValueError(f"{name} must be finite or NaN (no handle)")
        chords = _chords(points)
        if not (chords > 0).all():
            i = int(np.flatnonzero(~(chords > 0))[0])
            raise ValueError(f"knots {i} and {(i + 1) % n} coincide; consecutive knots must be distinct")
        steps = chords if steps is None else _array(steps, "steps", (n,))
        _finite(steps, "steps")
        if not (steps > 0).all():
            i = int(np.flatnonzero(~(steps > 0))[0])
            raise ValueError(f"steps[{i}] = {float(steps[i])!r} must be > 0")
        point_tension = _array(point_tension, "point_tension", (n,))
        _finite(point_tension, "point_tension")
        interval_weights = _array(interval_weights, "interval_weights", (n,))
        _finite(interval_weights, "interval_weights")
        for name, value in (("points", points), ("corners", corners), ("handles_in", handles_in),
                            ("handles_out", handles_out), ("steps", steps), ("point_tension", point_tension),
                            ("interval_weights", interval_weights)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        object.__setattr__(self, "spline", _build(self, Contour._reuse))

    def __setattr__(self, name, value):
        raise AttributeError("a Contour is immutable; its edit methods return a new one")

    def __reduce__(self):
        """Copies and pickles rebuild the contour from :meth:`fields` (its ``__slots__`` and the immutable
        ``__setattr__`` leave the default protocol nothing to restore them with)."""
        return (_contour_of, (self.fields(),))

    def __repr__(self):
        return (f"Contour({len(self)} knots, {int(self.corners.sum())} corners, "
                f"area={self.signed_area():.4g})")

    def __len__(self):
        return int(self.points.shape[0])

    # ------------------------------------------------------------------ data
    def fields(self) -> dict:
        """The constructor's arguments (copies), e.g. to build a modified contour."""
        return {name: np.array(getattr(self, name)) for name in
                ("points", "corners", "handles_in", "handles_out", "steps", "point_tension", "interval_weights")}

    def replace(self, *, changed_knots=None, **changes) -> "Contour":
        """A new contour with some fields replaced (validated and rebuilt by the engine).

        ``changed_knots`` (optional): the only knots whose point, handles or tension, or whose neighbouring
        intervals' step or weight, changed; the runs between corners without them are copied, not rebuilt.
        """
        data = self.fields()
        unknown = set(changes) - set(data)
        if unknown:
            raise TypeError(f"unknown contour field(s) {sorted(unknown)}")
        data.update(changes)
        points = data.pop("points")
        corners = data.pop("corners")
        reuse = None
        if changed_knots is not None and np.shape(points) == self.points.shape and np.array_equal(corners, self.corners):
            reuse = (self.bezier(), _knot_mask(changed_knots, len(self)))
        Contour._reuse = reuse
        try:
            return Contour(points, corners, **data)
        finally:
            Contour._reuse = None

    def bezier(self) -> np.ndarray:
        """The exact cubic Bézier pieces, shape ``(N, 4, 2)``; piece ``i`` runs from knot ``i`` to ``i + 1``."""
        return self.spline.bezier()

    def signed_area(self) -> float:
        """Exact signed area enclosed by the curve (Green's theorem on the Bézier pieces); > 0 when the loop
        turns counter-clockwise in an x-right, y-up frame (clockwise on screen, y down)."""
        return float(bezier_signed_area(self.bezier()))

    # ------------------------------------------------------------------ edits (each returns a new contour)
    def transformed(self, linear, offset, knots=None) -> "Contour":
        """Affine image ``x -> linear @ x + offset`` of the knots ``knots`` (default: all) and their handles.

        The selected knots go exactly where the map sends them, the others stay, and every knot keeps its
        class (smooth knots stay GC² joints, corners stay corners). The curve of a run between two corners
        whose knots are all selected (the whole contour, when it is all selected) keeps its steps and is
        therefore exactly the affine image of the old one: its tangent system depends on ``h``, ``v`` and
        ``omega`` only and is linear in the points and handles (thesis section 3.3). Elsewhere the steps of
        intervals whose chord changed follow the chord (§3).
        """
        linear = np.asarray(linear, float)
        offset = np.asarray(offset, float)
        data = self.fields()
        selected = _knot_mask(knots, len(self))
        data["points"][selected] = data["points"][selected] @ linear.T + offset
        for name in ("handles_in", "handles_out"):
            data[name][selected] = data[name][selected] @ linear.T
        if selected.all():
            return self.replace(**data)
        steps = _rescaled_steps(self.points, data["points"], self.steps)
        mapped = _selected_runs(self.corners, selected)
        steps[mapped] = self.steps[mapped]
        return self.replace(changed_knots=np.flatnonzero(selected), steps=steps,
                            **{name: data[name] for name in ("points", "handles_in", "handles_out")})

    def moved(self, knots, positions) -> "Contour":
        """Knots ``knots`` moved to ``positions`` (their handles move with them)."""
        index = _indices(knots, len(self))
        if positions is None:
            raise TypeError("positions must be a point (x, y) or one per knot, got None")
        positions = _array(positions, "positions", np.shape(positions))
        if positions.ndim == 0 or positions.shape[-1] != 2 or positions.ndim > 2:
            raise ValueError(f"positions must be a point (x, y) or one per knot, shape (n, 2); got shape "
                             f"{positions.shape}")
        positions = positions.reshape(-1, 2)
        if positions.shape[0] not in (1, index.size):
            raise ValueError(f"positions must give one point per knot ({index.size}), got {positions.shape[0]}")
        points = np.array(self.points)
        points[index] = positions
        return self.replace(points=points, steps=_rescaled_steps(self.points, points, self.steps),
                            changed_knots=index)

    def with_corner(self, knot, corner=True, *, keep_shape=False) -> "Contour":
        """Knot ``knot`` flagged as a corner or made smooth (a GC² joint; its handles are dropped).

        A new corner has no handles (its two tangents follow the neighbouring knots, §6.3), so the curve
        kinks there; with ``keep_shape=True`` it gets the current curve's handles instead and the shape is
        unchanged (the two tangents are then fixed until the handles are edited). The run through the knot
        splits there: a handle-less corner at either end of it whose new run is a single piece would lose its
        three-point end tangent (§6.3) for the chord's, so with ``keep_shape=True`` it gets its current handle
        on that side too.
        """
        i = _single_index(knot, len(self), "knot")
        corner = check_bool(corner, "corner")
        keep_shape = check_bool(keep_shape, "keep_shape")
        data = self.fields()
        data["corners"][i] = corner
        if corner and keep_shape and not self.corners[i]:
            b = self.bezier()
            n = len(self)
            data["handles_out"][i] = b[i, 1] - b[i, 0]
            data["handles_in"][i] = b[i - 1, 2] - b[i - 1, 3]
            # the run through knot i splits there; a handle-less end of it whose new run is a single piece loses
            # its three-point end tangent (§6.3) for the chord's, so it keeps the current one as a handle
            before = [k for k in range(1, n) if self.corners[(i - k) % n]]
            if before:
                first, last = (i - before[0]) % n, (i + min(k for k in range(1, n) if self.corners[(i + k) % n])) % n
                if before[0] == 1 and np.isnan(data["handles_out"][first]).any():
                    data["handles_out"][first] = b[first, 1] - b[first, 0]
                if (last - i) % n == 1 and np.isnan(data["handles_in"][last]).any():
                    data["handles_in"][last] = b[last - 1, 2] - b[last - 1, 3]
        return self.replace(**data)

    def with_handle(self, knot, side, position) -> "Contour":
        """Corner ``knot`` with its ``side`` handle ("out": leaving the knot, "in": arriving) ending at the point
        ``position``: the Bézier control point next to the knot (``b1`` of the piece leaving it, ``b2`` of the
        piece arriving) moves exactly there, since the run's clamped end tangent is ``3 (b1 - b0) / h`` (§2.4
        Type 1). Smooth knots have no handles (``ValueError``: make the knot a corner first)."""
        i = _single_index(knot, len(self), "knot")
        if not isinstance(side, str) or side not in ("in", "out"):
            raise ValueError(f"side must be 'in' or 'out', got {side!r:.20}")
        if not self.corners[i]:
            raise ValueError(f"knot {i} is smooth: only corners have handles (make it a corner first)")
        point = _array(position, "position", (2,))
        _finite(point, "position")
        handles = np.array(getattr(self, f"handles_{side}"))
        handles[i] = point - self.points[i]
        return self.replace(changed_knots=[i], **{f"handles_{side}": handles})

    def inserted(self, piece, theta=0.5) -> "Contour":
        """A knot inserted on piece ``piece`` at its local parameter ``theta`` in (0, 1) (a point of the curve).

        The step splits as ``theta h``, ``(1 - theta) h``; the new knot is smooth, with the mean point tension
        of its neighbours and the interval weight of the split interval. Handles of a corner at either end
        are shortened as by de Casteljau subdivision, so the curve stays close to the old one.
        """
        n = len(self)
        i = _single_index(piece, n, "piece")
        theta = check_number(theta, "theta")
        if not 0.0 < theta < 1.0:
            raise ValueError(f"theta must lie strictly between 0 and 1, got {theta!r}")
        b = self.bezier()[i]
        one = 1.0 - theta
        point = one ** 3 * b[0] + 3 * one * one * theta * b[1] + 3 * one * theta * theta * b[2] + theta ** 3 * b[3]
        data = self.fields()
        data["handles_out"][i] *= theta
        data["handles_in"][(i + 1) % n] *= one
        at = i + 1
        data["points"] = np.insert(data["points"], at, point, axis=0)
        data["corners"] = np.insert(data["corners"], at, False)
        data["handles_in"] = np.insert(data["handles_in"], at, np.nan, axis=0)
        data["handles_out"] = np.insert(data["handles_out"], at, np.nan, axis=0)
        step = self.steps[i]
        data["steps"] = np.insert(data["steps"], at, one * step)
        data["steps"][i] = theta * step
        tension = 0.5 * (self.point_tension[i] + self.point_tension[(i + 1) % n])
        data["point_tension"] = np.insert(data["point_tension"], at, tension)
        data["interval_weights"] = np.insert(data["interval_weights"], at, self.interval_weights[i])
        return self.replace(**data)

    def removed(self, knot) -> "Contour":
        """Knot ``knot`` deleted (refused when fewer than 3 knots would remain); its two intervals merge."""
        n = len(self)
        i = _single_index(knot, n, "knot")
        if n - 1 < MIN_KNOTS:
            raise ValueError(f"cannot delete knot {i}: a contour needs at least {MIN_KNOTS} knots and this one has {n}")
        data = self.fields()
        steps = data["steps"]
        steps[i - 1] += steps[i]
        for name in data:
            data[name] = np.delete(data[name], i, axis=0)
        return self.replace(**data)

    def with_point_tension(self, knots, value) -> "Contour":
        """Point tension ``v`` of ``knots`` set to ``value``: one finite real number (``None`` read as NaN, ``True`` as 1,
        text as a numpy conversion error before), whose sign rule the engine checks (§2.5)."""
        value = check_number(value, "point_tension (v)")
        tension = np.array(self.point_tension)
        index = _indices(knots, len(self))
        tension[index] = value
        return self.replace(point_tension=tension, changed_knots=index)

    def with_interval_weight(self, pieces, value) -> "Contour":
        """Interval weight ``omega`` of ``pieces`` set to ``value`` (a finite number > 0, thesis §2.2: refused here, not
        later by the interpolant of the knots between two corners, whose message counted from their first knot)."""
        value = check_number(value, "interval_weights (omega)", minimum=0.0, inclusive=False)
        weights = np.array(self.interval_weights)
        index = _indices(pieces, len(self))
        weights[index] = value
        return self.replace(interval_weights=weights, changed_knots=np.r_[index, (index + 1) % len(self)])

    def reversed(self) -> "Contour":
        """The same curve traversed the other way (knot order, handles and steps follow)."""
        order = np.r_[0, np.arange(len(self) - 1, 0, -1)]
        intervals = np.roll(order, -1)
        return Contour(self.points[order], self.corners[order], handles_in=self.handles_out[order],
                       handles_out=self.handles_in[order], steps=self.steps[intervals],
                       point_tension=self.point_tension[order], interval_weights=self.interval_weights[intervals])

    # ------------------------------------------------------------------ JSON
    def to_dict(self) -> dict:
        """Plain lists (handles: ``None`` where there is none); exact round trip with :meth:`from_dict`."""
        def handles(values):
            return [None if np.isnan(h).any() else [float(h[0]), float(h[1])] for h in values]

        return {"points": self.points.tolist(), "corners": self.corners.tolist(),
                "handles_in": handles(self.handles_in), "handles_out": handles(self.handles_out),
                "steps": self.steps.tolist(), "point_tension": self.point_tension.tolist(),
                "interval_weights": self.interval_weights.tolist()}

    @classmethod
    def from_dict(cls, data) -> "Contour":
        if not isinstance(data, dict) or "points" not in data:
            raise ValueError("a contour dict needs at least 'points'")
        unknown = set(data) - {"points", "corners", "handles_in", "handles_out", "steps", "point_tension",
                               "interval_weights"}
        if unknown:
            raise ValueError(f"unknown contour key(s) {sorted(unknown)}")

        def handles(values):
            if values is None:
                return None
            return [[np.nan, np.nan] if h is None else h for h in values]

        return cls(data["points"], data.get("corners"), handles_in=handles(data.get("handles_in")),
                   handles_out=handles(data.get("handles_out")), steps=data.get("steps"),
                   point_tension=data.get("point_tension", 0.0), interval_weights=data.get("interval_weights", 1.0))


def _indices(values, n) -> np.ndarray:
    """Knot or interval indices (negative ones count from the end), checked against ``n``."""
    array = np.atleast_1d(np.asarray(values))
    if array.dtype.kind not in "iu" or isinstance(values, (bool, np.bool_)):
        if not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in array.tolist()):
            raise TypeError(f"knot or piece indices must be integers, got {values!r}")
    array = array.astype(np.intp)
    if ((array < -n) | (array >= n)).any():
        bad = int(array[(array < -n) | (array >= n)][0])
        raise ValueError(f"index {bad} is out of range for a contour of {n} knots")
    return array % n


def _single_index(value, n, name, of="a contour of {n} knots") -> int:
    """One index into ``n`` items (negative ones count from the end): an integer, not a bool, a float or a
    list (never its first item); ``of`` says what is indexed (``{n}`` is filled in)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        shown = value.tolist() if isinstance(value, np.ndarray) else value
        raise TypeError(f"{name} must be one integer index, got {shown!r:.40}")
    index = int(value)
    if not -n <= index < n:
        raise ValueError(f"{name} = {index} is out of range for {of.format(n=n)}")
    return index % n


def _knot_mask(knots, n) -> np.ndarray:
    mask = np.zeros(n, dtype=bool)
    if knots is None:
        mask[:] = True
    else:
        mask[_indices(knots, n)] = True
    return mask


def _selected_runs(corners, selected) -> np.ndarray:
    """Mask of the intervals whose run between consecutive corners has all its knots (both corners too)
    selected; without corners the one run is the whole loop."""
    count = int(corners.sum())
    if count == 0:
        return np.full(corners.size, bool(selected.all()))
    run = (np.cumsum(corners) - 1) % count  # interval i lies in the run of the last corner <= i (cyclically)
    whole = np.ones(count, dtype=bool)
    np.logical_and.at(whole, run, selected & np.roll(selected, -1))
    return whole[run]


def _rescaled_steps(old_points, new_points, steps):
    """Steps of intervals whose chord changed scale with the chord (the others are kept)."""
    old, new = _chords(old_points), _chords(new_points)
    changed = ~np.isclose(old, new, rtol=1e-12, atol=0.0)
    result = np.array(steps, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(old > 0, new / old, 1.0)
    result[changed] *= ratio[changed]
    # a vanished chord is refused by the engine (coincident knots); keep the step positive meanwhile
    result[~(result > 0)] = np.asarray(steps, float)[~(result > 0)]
    return result


def _build(contour: Contour, reuse=None) -> Spline:
    """The contour's curve: one periodic interpolant, or one open interpolant per run between corners.

    ``reuse = (bezier, changed)``: the pieces of runs without a changed knot are copied from ``bezier``.
    """
    points, n = contour.points, len(contour)
    knots = np.concatenate([[0.0], np.cumsum(contour.steps)])
    corner_index = np.flatnonzero(contour.corners)
    if corner_index.size == 0:
        spline = interpolate(points, closed=True, knots=knots, point_tension=contour.point_tension,
                             interval_weights=contour.interval_weights)
        return Spline(spline.bezier(), knots, closed=True, info={"form": "outline_contour"})
    bezier = np.empty((n, 4, 2))
    for j, start in enumerate(corner_index):
        end = corner_index[(j + 1) % corner_index.size]
        length = (end - start) % n or n
        index = (start + np.arange(length + 1)) % n
        intervals = index[:-1]
        if reuse is not None and not reuse[1][index].any():
            bezier[intervals] = reuse[0][intervals]
            continue
        run_knots = np.concatenate([[0.0], np.cumsum(contour.steps[intervals])])
        out_handle, in_handle = contour.handles_out[start], contour.handles_in[end]
        first = None if np.isnan(out_handle).any() else 3.0 * out_handle / contour.steps[start]
        last = None if np.isnan(in_handle).any() else -3.0 * in_handle / contour.steps[intervals[-1]]
        try:
            run = interpolate(points[index], knots=run_knots, point_tension=contour.point_tension[index],
                              interval_weights=contour.interval_weights[intervals], end_condition="clamped",
                              end_tangents=(first, last))
        except ValueError as exc:
            raise ValueError(f"knots {int(start)}..{int(end)} (between two corners; indices below count from "
                             f"knot {int(start)}): {exc}") from None
        bezier[intervals] = run.bezier()
    return Spline(bezier, knots, closed=True, info={"form": "outline_contour"})


def _contour_of(fields):
    """The :class:`Contour` of the constructor's arguments ``fields`` (:meth:`Contour.__reduce__`)."""
    return Contour(**fields)
