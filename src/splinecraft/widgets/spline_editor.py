"""``SplineEditor``: drag points, move sliders and watch the generic cubic spline respond (anywidget).

The kernel computes everything: each change of a synced trait (or a drag/add/delete message from the
page) rebuilds the curve with the engine (:mod:`splinecraft.widgets._forms`) and sends the drawing back
as one ``geometry`` dict of float32 byte buffers (exact Bézier pieces, knots, the class polygon V, W,
tangent handles, the curvature comb with both one-sided teeth at every joint, §7). The page
(``js/spline_editor.js``) only draws and forwards input.

Bad values -- NaN, out-of-range numbers, a drag that would make two consecutive points coincide, a
point tension in the singular band (§2.5) -- from the page or from code never replace the curve:
the trait reverts to the last good value and ``status_message`` says why.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import traitlets as t

from ._assets import load_css, load_esm
from ._base import WidgetBase, f32
from ._forms import (
    ALPHA_MEANING, FORMS, KNOT_CHOICES, PRESETS, SEGMENT_LABELS, build_spline, default_end_condition, end_choices,
    explanation, form_options,
)

__all__ = ["SplineEditor", "SplineEditorWarning"]

#: Traits that define the curve (undo/redo restores exactly these).
MODEL_TRAITS = (
    "points", "point_tension", "interval_weights", "alpha", "beta", "preset", "form", "closed",
    "end_condition", "knots", "tension_scale",
)
_DISPLAY_TRAITS = ("show_control_polygon", "show_knots", "show_bezier_points", "show_tangents", "show_comb",
                   "comb_scale", "selected", "selected_interval", "view", "width", "height")
_MAX_HISTORY = 200
_MAX_COMB_TEETH = 1500
_COINCIDENT_RTOL = 1e-9
_MAX_COORDINATE = 1e9


class _ArrayList(t.List):
    """A List trait that also takes numpy arrays (converted to nested lists)."""

    def validate(self, obj, value):
        if isinstance(value, np.ndarray):
            value = value.tolist()
        return super().validate(obj, value)


class SplineEditorWarning(UserWarning):
    """A value set from code was rejected; the editor kept its last good state."""


class _Rejected(ValueError):
    """A proposed state is bad; the message is shown in the widget."""


def _default_points() -> list:
    angles = np.linspace(0.15, 2.0 * np.pi - 0.35, 6)
    radius = np.array([150.0, 110.0, 160.0, 100.0, 150.0, 120.0])
    return (np.c_[300.0 + radius * np.cos(angles), 220.0 - radius * np.sin(angles)]).round(1).tolist()


def _copy_value(value):
    """Copy of a trait value: lists are copied one level deep (their [x, y] items are never mutated in place,
    only replaced, so sharing them between states is safe and keeps drags fast)."""
    return list(value) if isinstance(value, list) else value


def _points_to_json(value, _widget):
    """``points`` travel to the page as little-endian float64 bytes (x0, y0, x1, y1, ...), not JSON lists."""
    return np.asarray(value, dtype="<f8").reshape(-1).tobytes()


def _points_from_json(value, _widget):
    if isinstance(value, (bytes, bytearray, memoryview)):
        return np.frombuffer(bytes(value), dtype="<f8").reshape(-1, 2).tolist()
    return value


def _copy_state(state: dict) -> dict:
    return {name: _copy_value(value) for name, value in state.items()}


class SplineEditor(WidgetBase):
    """Interactive editor for the generic cubic spline forms of the thesis (chapter 3).

    Parameters
    ----------
    points : array_like, shape (n, 2), optional
        Data points (interpolant, Timmer forms) or control points (basis form); for
        ``form="segment"`` exactly four points ``F0, V, W, F1``. Default: six points on a loop.
        The frame is the SVG/pixel frame (x right, y down), so ``to_svg()`` matches the screen.
    **engine_params
        Initial values of the synced traits below, e.g. ``form="basis"``, ``closed=True``,
        ``point_tension=2.0`` (a scalar is broadcast), ``interval_weights=[1, 4, 1]``,
        ``preset="bezier"``, ``end_condition="clamped"``, ``knots="uniform"``,
        ``tension_scale="absolute"``, overlays such as ``show_comb=True``.

    Synced traits (read, set and ``observe`` them from code)
    --------------------------------------------------------
    points : list of [x, y]
    point_tension : list of float, one per point (``v_i``, §2.2; ``tension_scale`` says the unit)
    interval_weights : list of float, one per interval (``omega_i > 0``)
    alpha, beta : float -- class parameters; what they mean depends on ``form`` (see
        :func:`splinecraft.widgets._forms.build_spline`): for the interpolant and basis forms they only
        move the auxiliary points V, W (spec E1).
    preset : {"ball", "bezier", "timmer", "free"} -- sets alpha = beta = 2, 3, 4 (or leaves them free)
    form : {"interpolant", "basis", "timmer_g2", "timmer_gc1", "timmer_gc2", "segment"}
    closed : bool
    end_condition : str -- interpolant: natural / natural_v / clamped; basis: floating / clamped;
        timmer_gc2: the joint, thesis / g2
    knots : {"chord", "centripetal", "uniform"}
    tension_scale : {"relative", "absolute"} -- point tension as the scale-free nu of §2.5
        (default) or the thesis's raw v
    selected, selected_interval : int (-1 for none)
    show_control_polygon, show_knots, show_bezier_points, show_tangents, show_comb : bool
    comb_scale : float -- relative length of the comb teeth
    view : [xmin, ymin, xmax, ymax] -- the visible data rectangle
    width, height : int -- drawing size in pixels
    status_message, status_level : str -- the last message ("info", "warning" or "error")
    geometry : dict -- what the page draws (float32 byte buffers); read-only for users

    Examples
    --------
    >>> editor = SplineEditor([[0, 0], [100, 80], [200, 0], [300, 60]], point_tension=1.0)
    >>> editor.spline.n_segments
    3
    >>> editor.panel()          # in JupyterLab: the editor with its live basis-function plot
    """

    _esm = load_esm("spline_editor.js")
    _css = load_css()
    kept = "curve"
    warning_class = SplineEditorWarning
    panel_plot = "basis_figure"
    messages = {**WidgetBase.messages, "drag": "_on_drag", "add": "_on_add", "delete": "_on_delete",
                "select_at": "_on_select_at", "undo": "_on_undo", "redo": "_on_redo", "fit": "_on_fit"}
    page_traits = frozenset(MODEL_TRAITS + _DISPLAY_TRAITS)

    points = _ArrayList().tag(sync=True, to_json=_points_to_json, from_json=_points_from_json)
    point_tension = _ArrayList().tag(sync=True)
    interval_weights = _ArrayList().tag(sync=True)
    alpha = t.Float(2.0, allow_none=True).tag(sync=True)
    beta = t.Float(2.0, allow_none=True).tag(sync=True)
    preset = t.Unicode("ball").tag(sync=True)
    form = t.Unicode("interpolant").tag(sync=True)
    closed = t.Bool(False).tag(sync=True)
    end_condition = t.Unicode("natural").tag(sync=True)
    knots = t.Unicode("chord").tag(sync=True)
    tension_scale = t.Unicode("relative").tag(sync=True)

    selected = t.Int(-1).tag(sync=True)
    selected_interval = t.Int(-1).tag(sync=True)
    show_control_polygon = t.Bool(True).tag(sync=True)
    show_knots = t.Bool(True).tag(sync=True)
    show_bezier_points = t.Bool(False).tag(sync=True)
    show_tangents = t.Bool(False).tag(sync=True)
    show_comb = t.Bool(False).tag(sync=True)
    comb_scale = t.Float(1.0, allow_none=True).tag(sync=True)
    view = t.List([0.0, 0.0, 1.0, 1.0]).tag(sync=True)
    width = t.Int(620).tag(sync=True)
    height = t.Int(440).tag(sync=True)

    explanation = t.Unicode("").tag(sync=True)
    options = t.Dict().tag(sync=True)
    geometry = t.Dict().tag(sync=True)
    can_undo = t.Bool(False).tag(sync=True)
    can_redo = t.Bool(False).tag(sync=True)

    def __init__(self, points=None, **engine_params):
        unknown = set(engine_params) - set(MODEL_TRAITS) - set(_DISPLAY_TRAITS) - {"debug"}
        if unknown:
            raise TypeError(f"SplineEditor got unexpected argument(s): {', '.join(sorted(unknown))}")
        self._spline = None
        self._undo: list[dict] = []
        self._redo: list[dict] = []
        self._last_push = (None, 0.0)
        self._coalesce_seconds = 1.0
        self._drag_gesture = None
        self._revision = 0
        self._segment_stash = None
        self._comb_unit = None
        display = {k: engine_params.pop(k) for k in list(engine_params) if k in _DISPLAY_TRAITS + ("debug",)}
        super().__init__(**display)

        state = self._initial_state(points, engine_params)
        spline = self._check(state)  # raises ValueError/TypeError for bad constructor arguments
        with self._quiet(), self.hold_sync():
            for name in MODEL_TRAITS:
                setattr(self, name, state[name])
            self.options = form_options(state["tension_scale"])
            self.explanation = explanation(state["form"], state["preset"], state["tension_scale"])
        self._spline = spline
        self.view = self._fitted_view()
        self._publish()
        if state["form"] == "segment":
            self._set_status("Drag F₀, V, W, F₁; move α and β to reshape the segment.", "info")
        else:
            self._set_status(f"{len(self.points)} points. Drag a point; double-click to add one; right-click or "
                             "Delete removes the selected point.", "info")

    # ------------------------------------------------------------------ public API
    @property
    def spline(self):
        """The current curve (:class:`splinecraft.Spline`, exact Bézier pieces)."""
        return self._spline

    def to_svg(self, *, stroke="#1565c0", stroke_width=2.0, precision=3, margin=None) -> str:
        """A standalone SVG document of the current curve (exact cubic Béziers, the editor's frame)."""
        bezier = self._spline.bezier()
        lo = np.minimum(bezier.reshape(-1, 2).min(axis=0), np.asarray(self.points).min(axis=0))
        hi = np.maximum(bezier.reshape(-1, 2).max(axis=0), np.asarray(self.points).max(axis=0))
        size = float(max(hi[0] - lo[0], hi[1] - lo[1], 1e-9))
        pad = 0.05 * size if margin is None else float(margin)
        x0, y0, w, h = lo[0] - pad, lo[1] - pad, hi[0] - lo[0] + 2 * pad, hi[1] - lo[1] + 2 * pad
        fmt = lambda v: f"{v:.{precision}f}".rstrip("0").rstrip(".")  # noqa: E731
        path = self._spline.to_svg_path(precision=precision)
        return (
            f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{fmt(x0)} {fmt(y0)} {fmt(w)} {fmt(h)}" '
            f'width="{fmt(w)}" height="{fmt(h)}">\n'
            f'  <path d="{path}" fill="none" stroke="{stroke}" stroke-width="{stroke_width}" '
            f'stroke-linejoin="round"/>\n</svg>\n'
        )

    def save_svg(self, path) -> Path:
        """Write :meth:`to_svg` to ``path``; returns the path."""
        path = Path(path)
        path.write_text(self.to_svg(), encoding="utf-8")
        return path

    def undo(self) -> bool:
        """Restore the state before the last change; False when there is nothing to undo."""
        if not self._undo:
            self._set_status("Nothing to undo.", "info")
            return False
        state = self._undo.pop()
        self._redo.append(self._state())
        self._restore(state, "Undone.")
        return True

    def redo(self) -> bool:
        """Re-apply the last undone change; False when there is nothing to redo."""
        if not self._redo:
            self._set_status("Nothing to redo.", "info")
            return False
        state = self._redo.pop()
        self._undo.append(self._state())
        self._restore(state, "Redone.")
        return True

    def add_point(self, x: float, y: float, *, tolerance: float | None = None) -> int:
        """Insert a point at ``(x, y)``; returns its index (or -1 if rejected).

        Within ``tolerance`` of the curve (default: 2% of the view) the point goes into the sequence
        where it lies on the curve (between the two points of that piece's interval or leg); elsewhere an
        open curve grows at its nearer end and a closed one gets it in the nearest piece.
        """
        return self._add_point(float(x), float(y), tolerance)

    def delete_point(self, index: int) -> bool:
        """Remove point ``index``; False (with a message) if the form needs more points."""
        return self._delete_point(int(index))

    def fit_view(self) -> None:
        """Fit the view to the points and the curve."""
        self.view = self._fitted_view()

    @property
    def basis_figure(self):
        """bqplot Figure with the live basis functions (created on first use, then kept in sync)."""
        from ._basis_plot import BasisPlot

        return self._plot("basis", BasisPlot).figure

    # ------------------------------------------------------------------ state
    def _state(self) -> dict:
        return _copy_state({name: getattr(self, name) for name in MODEL_TRAITS})

    def _initial_state(self, points, params) -> dict:
        form = params.get("form", "interpolant")
        if form not in FORMS:
            raise ValueError(f"form must be one of {', '.join(FORMS)}, got {form!r}")
        if points is None:
            points = _default_points() if form != "segment" else [[60, 320], [160, 80], [420, 80], [520, 320]]
            params.setdefault("closed", False)
        state = {
            "form": form, "closed": bool(params.get("closed", False)),
            "preset": params.get("preset", ALPHA_MEANING[form][1][0] if "alpha" not in params and "beta" not in params
                                 else "free"),
            "knots": params.get("knots", "chord"), "tension_scale": params.get("tension_scale", "relative"),
        }
        if not isinstance(state["knots"], str) or state["knots"] not in dict(KNOT_CHOICES):
            raise ValueError(f"knots must be one of {', '.join(dict(KNOT_CHOICES))}, got {state['knots']!r}")
        if state["tension_scale"] not in ("relative", "absolute"):
            raise ValueError(f"tension_scale must be 'relative' or 'absolute', got {state['tension_scale']!r}")
        if state["preset"] not in PRESETS:
            raise ValueError(f"preset must be one of {', '.join(PRESETS)}, got {state['preset']!r}")
        state["points"] = self._as_point_list(points, "points")
        n = len(state["points"])
        values = PRESETS[state["preset"]][1] or ALPHA_MEANING[form][1][1:]
        alpha = params.get("alpha", values[0])
        state["alpha"] = float(alpha)
        state["beta"] = float(params.get("beta", values[1] if values else alpha))
        state["end_condition"] = params.get("end_condition", default_end_condition(form))
        state["point_tension"] = self._broadcast(params.get("point_tension", 0.0), n, "point_tension")
        state["interval_weights"] = self._broadcast(
            params.get("interval_weights", 1.0), self._interval_count(n, state["closed"], form), "interval_weights")
        return state

    @staticmethod
    def _as_point_list(points, name) -> list:
        try:
            array = np.array(points, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"{name} must be an (n, 2) array of numbers: {exc}") from None
        if array.ndim != 2 or array.shape[1] != 2:
            raise ValueError(f"{name} must have shape (n, 2), got {array.shape}")
        return array.tolist()

    @staticmethod
    def _broadcast(value, count, name) -> list:
        array = np.array(value, dtype=float)
        if array.ndim == 0:
            return [float(array)] * count
        if array.shape != (count,):
            raise ValueError(f"{name} must be a scalar or have {count} values, got shape {array.shape}")
        return array.tolist()

    @staticmethod
    def _interval_count(n, closed, form) -> int:
        return n if closed and FORMS[form]["closed"] else max(n - 1, 0)

    # ------------------------------------------------------------------ validation
    def _check(self, state) -> object:
        """Validate a complete state and build its curve; raises :class:`_Rejected` with a short reason."""
        form = state["form"]
        if form not in FORMS:
            raise _Rejected(f"unknown form {form!r}")
        spec = FORMS[form]
        if state["preset"] not in PRESETS:
            raise _Rejected(f"unknown class preset {state['preset']!r}")
        if state["knots"] not in dict(KNOT_CHOICES):
            raise _Rejected(f"unknown knots {state['knots']!r}")
        if state["tension_scale"] not in ("relative", "absolute"):
            raise _Rejected(f"tension_scale must be 'relative' or 'absolute', not {state['tension_scale']!r}")
        if state["end_condition"] not in end_choices(form):
            raise _Rejected(f"{spec['ends'][0] if spec['ends'] else 'end condition'} {state['end_condition']!r} "
                            f"does not apply to this form ({', '.join(end_choices(form))})")
        points = np.array(state["points"], dtype=float)
        if points.ndim != 2 or points.shape[1] != 2:
            raise _Rejected(f"points must have shape (n, 2), got {points.shape}")
        bad = ~np.isfinite(points).all(axis=1)
        if bad.any():
            raise _Rejected(f"point {int(np.flatnonzero(bad)[0])} is not a finite number")
        if (np.abs(points) > _MAX_COORDINATE).any():
            raise _Rejected("a coordinate is beyond ±1e9")
        closed = state["closed"] and spec["closed"]
        need = spec["min_points"][1 if closed else 0]
        if len(points) < need:
            raise _Rejected(f"this form needs at least {need} points, got {len(points)}")
        if form == "segment" and len(points) != 4:
            raise _Rejected("the single-segment mode takes exactly 4 points F0, V, W, F1")
        if form != "segment":
            legs = np.diff(np.vstack([points, points[:1]]) if closed else points, axis=0)
            extent = float(np.ptp(points, axis=0).max()) or 1.0
            close = np.hypot(legs[:, 0], legs[:, 1]) <= _COINCIDENT_RTOL * extent
            if close.any():
                i = int(np.flatnonzero(close)[0])
                raise _Rejected(f"points {i} and {(i + 1) % len(points)} would coincide")
        n = len(points)
        for name, count in (("point_tension", n), ("interval_weights", self._interval_count(n, closed, form))):
            values = np.array(state[name], dtype=float)
            if values.shape != (count,):
                raise _Rejected(f"{name} needs {count} values, got {values.size}")
            if not np.isfinite(values).all():
                raise _Rejected(f"{name}[{int(np.flatnonzero(~np.isfinite(values))[0])}] is not a finite number")
        weights = np.array(state["interval_weights"], dtype=float)
        if (weights <= 0).any():
            i = int(np.flatnonzero(weights <= 0)[0])
            raise _Rejected(f"interval weight ω[{i}] = {weights[i]:g} must be > 0")
        if (weights > 1e6).any():
            raise _Rejected("interval weights above 1e6 are out of range")
        for name in ("alpha", "beta"):
            value = state[name]
            if value is None or not math.isfinite(value):
                raise _Rejected(f"{name} must be a finite number")
            # alpha = 0 drops V from a single segment (§1); elsewhere V, W divide by alpha, beta (§2.1)
            low_ok = value >= 0 if form == "segment" else value > 0
            if not low_ok or value > 100:
                raise _Rejected(f"{name} = {value:g} is out of range ({'≥ 0' if form == 'segment' else '> 0'} and ≤ 100)")
        try:
            return build_spline(state)
        except (ValueError, TypeError, ZeroDivisionError, FloatingPointError, np.linalg.LinAlgError) as exc:
            raise _Rejected(str(exc)) from None

    # ------------------------------------------------------------------ trait changes
    @t.validate("points")
    def _validate_points(self, proposal):
        value = proposal["value"]
        if self._applying:
            return value  # already checked by _check()
        try:
            array = np.array(value, dtype=float)  # None (NaN from the page) becomes nan
        except (TypeError, ValueError) as exc:
            raise t.TraitError(f"points must be an (n, 2) array of numbers: {exc}") from None
        if array.size == 0:
            array = array.reshape(0, 2)
        if array.ndim != 2 or array.shape[1] != 2:
            raise t.TraitError(f"points must have shape (n, 2), got {array.shape}")
        return array.tolist()

    @t.validate("point_tension", "interval_weights")
    def _validate_lists(self, proposal):
        value = proposal["value"]
        try:
            if isinstance(value, (list, tuple)):
                value = [math.nan if v is None else v for v in value]
            array = np.array(value, dtype=float).reshape(-1)
        except (TypeError, ValueError) as exc:
            raise t.TraitError(f"{proposal['trait'].name} must be a list of numbers: {exc}") from None
        return array.tolist()

    @t.observe(*MODEL_TRAITS)
    def _on_model_change(self, change):
        if self._applying:
            return
        name = change["name"]
        state = self._state()
        state[name] = change["old"]
        previous = _copy_state(state)
        state[name] = _copy_value(change["new"])
        try:
            state, note = self._derive(name, change["old"], state)
            spline = self._check(state)
        except _Rejected as exc:
            self._revert(name, change["old"], str(exc))
            return
        before = self._spline
        self._push_history(previous, key=name)
        if name in ("form", "closed", "preset", "alpha", "beta"):
            self._comb_unit = None  # a different curve: rescale the comb
        self._commit(state, spline)
        if name == "points" and not self._from_page:
            self.view = self._fitted_view()  # new points from code: fit them (this also rescales the comb)
        self._set_status(note or self._describe_change(name, before, spline), "info")

    def _derive(self, name, old, state):
        """Adjust the traits that depend on the one that changed; returns (state, note)."""
        note = None
        form = state["form"]
        if form not in FORMS:
            raise _Rejected(f"unknown form {form!r}; choose one of {', '.join(FORMS)}")
        if name == "preset":
            values = PRESETS.get(state["preset"], (None, None))[1]
            if values is not None:
                state["alpha"], state["beta"] = float(values[0]), float(values[1])
        if name in ("alpha", "beta") and state["preset"] != "free":
            values = PRESETS[state["preset"]][1]
            if (state["alpha"], state["beta"]) != tuple(values):
                state["preset"] = "free"
        if name == "form":
            if state["end_condition"] not in end_choices(form):
                state["end_condition"] = default_end_condition(form)
            if old in ALPHA_MEANING and ALPHA_MEANING[old][0] != ALPHA_MEANING[form][0]:
                # alpha, beta mean something else in this form: start from its default
                state["preset"], state["alpha"], state["beta"] = ALPHA_MEANING[form][1]
            if form == "segment" and old != "segment":
                self._segment_stash = _copy_state({k: state[k] for k in ("points", "point_tension", "interval_weights", "closed")})
                state["points"] = self._segment_points(state)
                state["closed"] = False
                note = ("Single-segment mode: F₀, V, W, F₁ taken from the first piece. Drag V, W and move α, β — "
                        "here they reshape the curve.")
            elif old == "segment" and form != "segment" and self._segment_stash is not None:
                state.update(_copy_state(self._segment_stash))
                self._segment_stash = None
        if name in ("points", "closed", "form"):
            n = len(state["points"])
            state["point_tension"] = self._resized(state["point_tension"], n)
            state["interval_weights"] = self._resized(
                state["interval_weights"], self._interval_count(n, state["closed"], form), fill=1.0)
        return state, note

    @staticmethod
    def _resized(values, count, fill=None):
        values = list(values)
        if len(values) == count:
            return values
        if len(values) > count:
            return values[:count]
        pad = values[-1] if values and fill is None else (fill if fill is not None else 0.0)
        if values and all(v == values[0] for v in values):
            pad = values[0]
        return values + [pad] * (count - len(values))

    def _segment_points(self, state) -> list:
        """F0, V, W, F1 of the current curve's first piece (with the current class), for design mode."""
        spline = self._spline
        bezier = spline.bezier()[0]
        alpha = state["alpha"] if state["alpha"] else 3.0
        beta = state["beta"] if state["beta"] else 3.0
        # invert b1 = F0 + alpha/3 (V - F0), b2 = F1 + beta/3 (W - F1) (§1)
        V = bezier[0] + 3.0 / alpha * (bezier[1] - bezier[0])
        W = bezier[3] + 3.0 / beta * (bezier[2] - bezier[3])
        return np.vstack([bezier[0], V, W, bezier[3]]).tolist()

    def _revert(self, name, old, reason):
        with self._quiet():
            setattr(self, name, old)
        self._reject(reason, resync=(name,))  # the page still shows the rejected value: send the kept one

    def _commit(self, state, spline, *, seq=None):
        with self._quiet(), self.hold_sync():
            for name in MODEL_TRAITS:
                if getattr(self, name) != state[name]:
                    setattr(self, name, state[name])
            self._spline = spline
            self._clamp_selection()
            self._publish(seq=seq)
            self.explanation = explanation(self.form, self.preset, self.tension_scale)
            self.options = form_options(self.tension_scale)

    def _clamp_selection(self):
        n = len(self.points)
        if self.selected >= n:
            self.selected = -1
        if self.selected_interval >= len(self.interval_weights):
            self.selected_interval = -1

    def _describe_change(self, name, before, after) -> str:
        form = self.form
        if name in ("preset", "alpha", "beta") and form in ("interpolant", "basis") and before is not None:
            moved = self._max_change(before, after)
            label = (f"{PRESETS[self.preset][0].split(' (')[0]} (α = β = {self.alpha:g})" if self.preset != "free"
                     else f"α = {self.alpha:g}, β = {self.beta:g}")
            return (f"Class {label}: V, W redrawn; the curve did not move (max change {moved:.2g}) — "
                    "α, β cancel in this form (spec E1).")
        if name in ("preset", "alpha", "beta") and form == "segment":
            return f"α = {self.alpha:g}, β = {self.beta:g}: with V, W fixed the segment changes shape (§1)."
        if name == "form":
            return f"Form: {FORMS[form]['label']}."
        if name == "interval_weights" and self.selected_interval >= 0:
            i = self.selected_interval
            return f"ω[{i}] = {self.interval_weights[i]:g}. Unequal neighbouring ω make curvature jump (E2)."
        if name == "point_tension" and self.selected >= 0:
            return f"v[{self.selected}] = {self.point_tension[self.selected]:g}."
        return f"{name.replace('_', ' ')} updated."

    @staticmethod
    def _max_change(before, after) -> float:
        a, b = before.bezier(), after.bezier()
        if a.shape != b.shape:
            return float("nan")
        return float(np.max(np.abs(a - b)))

    @t.observe(*_DISPLAY_TRAITS)
    def _on_display_change(self, change):
        if change["name"] in ("view", "show_comb", "width", "height"):
            self._comb_unit = None
        if self._applying:
            return
        name = change["name"]
        if name == "comb_scale":
            value = change["new"]
            if value is None or not math.isfinite(value) or not 0 < value <= 1000:
                self._revert(name, change["old"], f"comb size must be a number in (0, 1000], got {value}")
                return
        if name == "view":
            view = change["new"]
            ok = (isinstance(view, (list, tuple)) and len(view) == 4
                  and all(isinstance(v, (int, float)) and math.isfinite(v) for v in view)
                  and view[2] > view[0] and view[3] > view[1])
            if not ok:
                self._revert(name, change["old"], "view must be [xmin, ymin, xmax, ymax] with xmax > xmin, ymax > ymin")
                return
            return
        if name in ("width", "height"):
            if not 120 <= change["new"] <= 4000:
                self._revert(name, change["old"], f"{name} must be between 120 and 4000 pixels")
            return
        if name == "selected":
            if not -1 <= change["new"] < len(self.points):
                self._revert(name, change["old"], f"no point {change['new']}")
                return
        if name == "selected_interval":
            if not -1 <= change["new"] < len(self.interval_weights):
                self._revert(name, change["old"], f"no interval {change['new']}")
                return
        self._publish()

    # ------------------------------------------------------------------ history
    def _push_history(self, state, *, key):
        now = time.monotonic()
        last_key, last_time = self._last_push
        self._last_push = (key, now)
        if key is not None and key == last_key and now - last_time < self._coalesce_seconds and self._undo:
            return  # one slider gesture = one undo step
        self._undo.append(state)
        del self._undo[:-_MAX_HISTORY]
        self._redo.clear()
        self._sync_history_flags()

    def _sync_history_flags(self):
        with self._quiet():
            self.can_undo = bool(self._undo)
            self.can_redo = bool(self._redo)

    def _restore(self, state, message):
        try:
            spline = self._check(state)
        except _Rejected as exc:  # pragma: no cover - history holds only good states
            self._reject(str(exc))
            return
        self._last_push = (None, 0.0)
        self._commit(state, spline)
        self._sync_history_flags()
        self._set_status(message, "info")

    # ------------------------------------------------------------------ page messages
    def _on_add(self, content, _buffers):
        self._add_point(content.get("x"), content.get("y"), content.get("tol"))

    def _on_delete(self, content, _buffers):
        self._delete_point(content.get("index"))

    def _on_select_at(self, content, _buffers):
        self._select_at(content.get("x"), content.get("y"), content.get("tol"))

    def _on_undo(self, _content, _buffers):
        self.undo()

    def _on_redo(self, _content, _buffers):
        self.redo()

    def _on_fit(self, _content, _buffers):
        self.fit_view()

    def _on_drag(self, content, _buffers):
        self._drag(content)

    def _drag(self, content):
        seq = int(content.get("seq", 0))
        index = content.get("index")
        x, y = content.get("x"), content.get("y")
        final = bool(content.get("final", False))
        n = len(self.points)
        ok = False
        if not isinstance(index, int) or not 0 <= index < n:
            self._reject(f"no point {index}")
        else:
            state = self._state()
            point = [math.nan if x is None else float(x), math.nan if y is None else float(y)]
            old_point = state["points"][index]
            state["points"][index] = point
            try:
                spline = self._check(state)
            except _Rejected as exc:
                self._reject(str(exc))
            else:
                gesture = content.get("gesture")
                if gesture is None or gesture != self._drag_gesture:
                    previous = _copy_state(state)
                    previous["points"][index] = old_point
                    self._push_history(previous, key=None)
                    self._drag_gesture = gesture
                self._last_push = (("drag", gesture), time.monotonic())
                self._commit(state, spline, seq=seq)
                ok = True
                if final:
                    self._set_status(f"Point {index} moved to ({point[0]:.1f}, {point[1]:.1f}).", "info")
        if not ok:
            self.send({"type": "drag_ack", "seq": seq, "ok": False})
            if final:
                # the page shows the rejected position; make it redraw the last good points
                self.send_state("points")

    def _nearest_on_curve(self, x, y):
        """(piece index, distance) of the curve point nearest to (x, y), from a fine display polyline."""
        spline = self._spline
        extent = float(np.ptp(np.asarray(self.points), axis=0).max()) or 1.0
        params, samples = spline.sample(tolerance=extent * 1e-3)
        start, end = samples[:-1], samples[1:]
        along = end - start
        length2 = np.einsum("ij,ij->i", along, along)
        target = np.array([x, y], dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.where(length2 > 0, np.einsum("ij,ij->i", target - start, along) / length2, 0.0)
        s = np.clip(s, 0.0, 1.0)
        nearest = start + s[:, None] * along
        distances = np.hypot(nearest[:, 0] - x, nearest[:, 1] - y)
        k = int(np.argmin(distances))
        t_near = params[k] + s[k] * (params[k + 1] - params[k])
        piece = int(np.clip(np.searchsorted(spline.knots, t_near, side="right") - 1, 0, spline.n_segments - 1))
        return piece, float(distances[k])

    def _piece_leg(self, piece: int) -> int:
        """The control-polygon leg (points i, i+1) that piece ``piece`` belongs to."""
        if self.form != "basis":
            return piece
        bezier = self._spline.bezier()[piece]
        points = np.asarray(self.points)
        legs_a = points if self.closed else points[:-1]
        legs_b = np.roll(points, -1, axis=0) if self.closed else points[1:]
        mid = 0.5 * (bezier[1] + bezier[2])  # the inner Bézier points lie on the leg (§4.3)
        d = legs_b - legs_a
        length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        s = np.clip(np.einsum("ij,ij->i", mid - legs_a, d) / length2, 0.0, 1.0)
        dist = np.hypot(*(legs_a + s[:, None] * d - mid).T)
        return int(np.argmin(dist))

    def _leg_pieces(self, leg: int) -> list:
        if self.form != "basis":
            return [leg] if 0 <= leg < self._spline.n_segments else []
        return [p for p in range(self._spline.n_segments) if self._piece_leg(p) == leg]

    def _add_point(self, x, y, tolerance=None) -> int:
        if not FORMS[self.form]["add_delete"]:
            self._reject("this mode has exactly the four points F0, V, W, F1; switch the form to add points")
            return -1
        try:
            x, y = float(x), float(y)
        except (TypeError, ValueError):
            self._reject("the new point is not a number")
            return -1
        if not (math.isfinite(x) and math.isfinite(y)):
            self._reject("the new point is not a finite number")
            return -1
        view = self.view
        if tolerance is None or not math.isfinite(float(tolerance)):
            tolerance = 0.02 * max(view[2] - view[0], view[3] - view[1])
        piece, distance = self._nearest_on_curve(x, y)
        points = [list(p) for p in self.points]
        n = len(points)
        if distance <= 3.0 * float(tolerance) or self.closed:
            leg = self._piece_leg(piece)
            index = leg + 1
            interval = leg
        else:
            first, last = np.hypot(*(np.subtract(points[0], (x, y)))), np.hypot(*(np.subtract(points[-1], (x, y))))
            index = 0 if first < last else n
            interval = 0 if index == 0 else n - 2
        state = self._state()
        previous = _copy_state(state)
        points.insert(index, [x, y])
        tension = list(state["point_tension"])
        tension.insert(index, tension[min(index, n - 1)] if tension else 0.0)
        weights = list(state["interval_weights"])
        if weights:
            weights.insert(min(interval, len(weights)), weights[min(interval, len(weights) - 1)])
        state.update(points=points, point_tension=tension, interval_weights=weights)
        try:
            spline = self._check(state)
        except _Rejected as exc:
            self._reject(str(exc))
            return -1
        self._push_history(previous, key=None)
        self._commit(state, spline)
        with self._quiet():
            self.selected = index
            self.selected_interval = -1
        self._publish()
        self._set_status(f"Point {index} added.", "info")
        return index

    def _delete_point(self, index) -> bool:
        if not FORMS[self.form]["add_delete"]:
            self._reject("this mode has exactly the four points F0, V, W, F1")
            return False
        n = len(self.points)
        if not isinstance(index, int) or not 0 <= index < n:
            self._reject(f"no point {index} to delete")
            return False
        state = self._state()
        previous = _copy_state(state)
        del state["points"][index]
        del state["point_tension"][index]
        weights = state["interval_weights"]
        if weights:
            del weights[min(index, len(weights) - 1) if not state["closed"] else index % len(weights)]
        try:
            spline = self._check(state)
        except _Rejected as exc:
            self._reject(str(exc))
            return False
        self._push_history(previous, key=None)
        self._commit(state, spline)
        with self._quiet():
            self.selected = -1
            self.selected_interval = -1
        self._publish()
        self._set_status(f"Point {index} deleted.", "info")
        return True

    def _select_at(self, x, y, tolerance):
        try:
            x, y = float(x), float(y)
        except (TypeError, ValueError):
            return
        piece, _distance = self._nearest_on_curve(x, y)
        interval = self._piece_leg(piece)
        with self._quiet():
            self.selected_interval = interval if interval < len(self.interval_weights) else -1
        self._publish()
        if FORMS[self.form]["tension"]:
            self._set_status(f"Interval {interval} selected: set its weight ωᵢ in the side panel.", "info")

    # ------------------------------------------------------------------ drawing data
    def _fitted_view(self) -> list:
        points = np.asarray(self.points, dtype=float)
        cloud = np.vstack([points, self._spline.bezier().reshape(-1, 2)]) if self._spline is not None else points
        lo, hi = cloud.min(axis=0), cloud.max(axis=0)
        size = np.maximum(hi - lo, 1e-6 * max(1.0, float(np.abs(cloud).max())))
        pad = 0.08 * size.max()
        return [float(lo[0] - pad), float(lo[1] - pad), float(lo[0] + size[0] + pad), float(lo[1] + size[1] + pad)]

    def _publish(self, seq=None):
        """Send the drawing of the current curve to the page (one ``geometry`` update)."""
        spline = self._spline
        if spline is None:
            return
        self._revision += 1
        bezier = spline.bezier()
        m = bezier.shape[0]
        closed = spline.closed
        knots = spline.knot_points[:-1] if closed else spline.knot_points
        aux = spline.auxiliary
        geometry = {
            "revision": self._revision,
            "seq": -1 if seq is None else int(seq),
            "closed": bool(closed),
            "bezier": f32(bezier),
            "knots": f32(knots),
        }
        # class polygon: V, W (generic cubic) or Q1, Q2 (Timmer) per piece
        V = aux.get("V", aux.get("Q1"))
        W = aux.get("W", aux.get("Q2"))
        if self.show_bezier_points and V is not None and W is not None and self.form != "segment":
            nan = np.full((m, 1, 2), np.nan)
            polygon = np.concatenate([bezier[:, :1], V[:, None], W[:, None], bezier[:, 3:], nan], axis=1)
            geometry["class_polygon"] = f32(polygon)
            geometry["vw"] = f32(np.stack([V, W], axis=1))
        if self.show_tangents:
            handles = np.stack([bezier[:, 0], bezier[:, 1], bezier[:, 3], bezier[:, 2]], axis=1)
            geometry["tangents"] = f32(handles)
        labels = []
        if self.show_comb:
            teeth, envelope, joint_labels = self._comb(spline)
            geometry["comb_teeth"] = f32(teeth)
            geometry["comb_envelope"] = f32(envelope)
            labels.extend(joint_labels)
        if self.form == "segment":
            labels.extend({"x": float(p[0]), "y": float(p[1]), "text": label, "kind": "point"}
                          for p, label in zip(self.points, SEGMENT_LABELS))
        geometry["labels"] = labels
        interval = self.selected_interval
        if 0 <= interval < len(self.interval_weights):
            pieces = self._leg_pieces(interval)
            if pieces:
                geometry["highlight"] = f32(np.concatenate([bezier[p].reshape(1, 4, 2) for p in pieces]))
            if self.form == "basis":
                points = np.asarray(self.points)
                geometry["highlight_leg"] = f32(np.vstack([points[interval], points[(interval + 1) % len(points)]]))
        self.geometry = geometry
        if "basis" in self._plots:
            self._plots["basis"].update(self, final=seq is None)

    def _comb(self, spline):
        """Curvature comb teeth (segments), tip envelope and joint labels (§7, E2)."""
        m = spline.n_segments
        samples = int(np.clip(4000 // max(m, 1), 6, 33))
        bases, tips = spline.curvature_comb(scale=1.0, samples_per_segment=samples)
        lengths = np.hypot(*(tips - bases).T)  # = |kappa|
        finite = lengths[np.isfinite(lengths)]
        if self._comb_unit is None:
            # teeth length per unit curvature: the 95th-percentile tooth is 12% of the view diagonal. Fixed
            # until the view, the form or the comb size changes, so during a drag the comb shows real
            # changes of curvature instead of being renormalised every move.
            view = self.view
            diag = math.hypot(view[2] - view[0], view[3] - view[1])
            reference = float(np.percentile(finite, 95)) if finite.size else 0.0
            self._comb_unit = 0.12 * diag / reference if reference > 0 else None
        scale = self.comb_scale * (self._comb_unit or 0.0)
        tips = bases + scale * (tips - bases)
        teeth = np.stack([bases, tips], axis=1)
        if len(teeth) > _MAX_COMB_TEETH:  # long curves: every k-th tooth (the envelope keeps every sample)
            teeth = teeth[:: math.ceil(len(teeth) / _MAX_COMB_TEETH)]
        envelope = tips
        if spline.closed and len(tips):
            envelope = np.vstack([tips, tips[:1]])
        labels = []
        joints = spline.joint_curvature()
        points = spline.knot_points
        if m <= 60:
            for i in (range(1, m) if not spline.closed else range(m)):
                minus, plus = joints[i]
                if not (math.isfinite(minus) and math.isfinite(plus)):
                    continue
                big = max(abs(minus), abs(plus))
                if big <= 1e-12:
                    continue
                if abs(plus - minus) > 1e-3 * big:
                    ratio = plus / minus if abs(minus) > 1e-12 * big else math.inf
                    text = f"κ⁺/κ⁻ = {ratio:.2f}" if math.isfinite(ratio) else "κ jumps"
                    labels.append({"x": float(points[i][0]), "y": float(points[i][1]), "text": text, "kind": "joint"})
        return teeth, envelope, labels


