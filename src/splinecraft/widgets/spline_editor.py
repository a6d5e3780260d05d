"""``SplineEditor``: drag points, move sliders and watch the generic cubic spline respond (anywidget).

The kernel computes everything: each change of a synced trait (or a drag/add/delete message from the
page) makes a new state (:mod:`._editor_state`, pure functions), builds its curve with the engine and sends
the drawing back as one ``geometry`` dict of float32 byte buffers (:mod:`._editor_drawing`: exact Bézier
pieces, knots, the class polygon V, W, tangent handles, the curvature comb with both one-sided teeth at
every joint, §7). The page (``js/spline_editor.js`` and the modules it imports) only draws and forwards
input. Undo and redo keep whole states (:class:`._history.History`).

Bad values -- NaN, out-of-range numbers, a drag that would make two consecutive points coincide, a
point tension in the singular band (§2.5), a malformed message -- from the page or from code never
replace the curve: the trait reverts to the last good value, ``status_message`` says why, and the page is
resynced.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import traitlets as tl

from .._validation import check_int, check_number, file_path
from ..spline.svg import svg_document
from . import _editor_drawing as drawing
from . import _editor_state as model
from ._assets import load_css, load_esm
from ._base import (
    Bool, Float, Int, NumberList, PointList, WidgetBase, json_numbers, points_from_json, points_to_json, read_bool,
    read_int, read_number, view_problem,
)
from ._editor_state import MAX_POINTS, MODEL_TRAITS, Rejected
from ._forms import FORMS, explanation, form_options, plain_text
from ._history import History
from ._png import curves_png

__all__ = ["SplineEditor", "SplineEditorWarning", "MAX_POINTS"]

_DISPLAY_TRAITS = ("show_control_polygon", "show_knots", "show_bezier_points", "show_tangents", "show_comb",
                   "comb_scale", "selected", "selected_interval", "view", "width", "height", "t", "show_grid", "snap",
                   "large")
_PAGE_ONLY = ("view", "width", "height", "show_grid", "snap", "large")  # drawn by the page, nothing to recompute
_COMB_RESET = ("form", "closed", "preset", "alpha", "beta")
_MAX_SEQ = 2**53


class SplineEditorWarning(UserWarning):
    """A value set from code was rejected; the editor kept its last good state."""


class SplineEditor(WidgetBase):
    """Interactive editor for the generic cubic spline forms of the thesis (chapter 3).

    Parameters
    ----------
    points : array_like, shape (n, 2), optional
        Data points (interpolant, Timmer forms) or control points (basis form); for
        ``form="segment"`` exactly four points ``F0, V, W, F1``. Default: six points on a loop.
        The frame is the SVG/pixel frame (x right, y down), so ``to_svg()`` matches the screen.
    max_points : int, optional
        Most points the editor takes (default :data:`MAX_POINTS` = 5000; every edit rebuilds the whole
        curve, about 1 ms per 1000 points). Also an attribute: ``editor.max_points = 20000``.
    debug : bool, optional
        Switch on the page's benchmark hooks (drag latency records, ping); ``benchmarks/bench_drag.py``.
    **engine_params
        Initial values of the synced traits below, e.g. ``form="basis"``, ``closed=True``,
        ``point_tension=2.0`` (a scalar is broadcast), ``interval_weights=[1, 4, 1]``,
        ``preset="bezier"``, ``end_condition="clamped"``, ``knots="uniform"``,
        ``tension_scale="absolute"``, overlays such as ``show_comb=True``.

    Synced traits (read, set and ``observe`` them from code)
    --------------------------------------------------------
    points : list of [x, y]
    point_tension : list of float, one per point (``v_i``, §2.2; ``tension_scale`` says the unit)
    interval_weights : list of float, one per interval (``omega_i > 0``); setting either list to a single
        number sets every item to it
    alpha, beta : float -- class parameters; what they mean depends on ``form`` (see
        :func:`splinecraft.widgets._forms.build_spline`): for the interpolant and basis forms they only
        move the auxiliary points V, W (E1).
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
    show_grid, snap : bool -- grid lines; dragged points snap to them
    large : bool -- presentation size (larger canvas, text and controls)
    t : float or None -- the parameter slider: the point P(t) with the de Casteljau construction of its piece
        (None: off); kept inside the curve's parameter interval
    view : [xmin, ymin, xmax, ymax] -- the visible data rectangle
    width, height : int -- drawing size in pixels (120 to 4000)
    status_message, status_level : str -- the last message ("info", "warning" or "error")
    explanation_html : str -- the teaching text beside the drawing (``editor.explanation``: plain text)
    geometry : dict -- what the page draws (float32 byte buffers); read-only for users

    Examples
    --------
    >>> editor = SplineEditor([[0, 0], [100, 80], [200, 0], [300, 60]], point_tension=1.0)
    >>> editor.spline.n_segments
    3
    >>> panel = editor.panel()  # in JupyterLab, display(panel): the editor with its live basis-function plot
    """

    _esm = load_esm("spline_editor.js")
    _css = load_css()
    kept = "curve"
    warning_class = SplineEditorWarning
    panel_plot = "basis_figure"
    messages = {**WidgetBase.messages, "drag": "_on_drag", "add": "_on_add", "delete": "_on_delete",
                "select_at": "_on_select_at", "undo": "_on_undo", "redo": "_on_redo", "fit": "_on_fit",
                "resend": "_on_resend"}
    page_traits = frozenset(MODEL_TRAITS + _DISPLAY_TRAITS)

    max_points = tl.Int(MAX_POINTS, min=4)

    @tl.validate("max_points")
    def _valid_max_points(self, proposal):
        count = len(self._trait_values.get("points") or ())
        if proposal["value"] < count:
            raise tl.TraitError(f"max_points = {proposal['value']} is below the {count} points the editor holds; "
                                "delete points first (the limit was kept)")
        return proposal["value"]
    points = PointList().tag(sync=True, to_json=points_to_json, from_json=points_from_json)
    point_tension = NumberList().tag(sync=True, to_json=json_numbers)
    interval_weights = NumberList().tag(sync=True, to_json=json_numbers)
    alpha = Float(2.0, allow_none=True).tag(sync=True, to_json=json_numbers)
    beta = Float(2.0, allow_none=True).tag(sync=True, to_json=json_numbers)
    preset = tl.Unicode("ball").tag(sync=True)
    form = tl.Unicode("interpolant").tag(sync=True)
    closed = Bool(False).tag(sync=True)
    end_condition = tl.Unicode("natural").tag(sync=True)
    knots = tl.Unicode("chord").tag(sync=True)
    tension_scale = tl.Unicode("relative").tag(sync=True)

    selected = Int(-1).tag(sync=True)
    selected_interval = Int(-1).tag(sync=True)
    show_control_polygon = Bool(True).tag(sync=True)
    show_knots = Bool(True).tag(sync=True)
    show_bezier_points = Bool(False).tag(sync=True)
    show_tangents = Bool(False).tag(sync=True)
    show_comb = Bool(False).tag(sync=True)
    comb_scale = Float(1.0, allow_none=True).tag(sync=True, to_json=json_numbers)
    t = Float(None, allow_none=True).tag(sync=True, to_json=json_numbers)
    show_grid = Bool(True).tag(sync=True)
    snap = Bool(False).tag(sync=True)
    view = tl.List([0.0, 0.0, 1.0, 1.0]).tag(sync=True)
    width = Int(620, min=120, max=4000).tag(sync=True)
    height = Int(440, min=120, max=4000).tag(sync=True)

    explanation_html = tl.Unicode("").tag(sync=True)
    options = tl.Dict().tag(sync=True)
    geometry = tl.Dict().tag(sync=True)
    can_undo = Bool(False).tag(sync=True)
    can_redo = Bool(False).tag(sync=True)

    def __init__(self, points=None, *, max_points: int = MAX_POINTS, **engine_params):
        unknown = set(engine_params) - set(MODEL_TRAITS) - set(_DISPLAY_TRAITS) - {"debug"}
        if unknown:
            raise TypeError(f"SplineEditor got unexpected argument(s): {', '.join(sorted(unknown))}")
        max_points = check_int(max_points, "max_points", minimum=4)
        self._spline = None
        self._history = History()
        self._drag_gesture = None
        self._revision = 0
        self._segment_stash = None
        self._comb_unit = None
        self._sent_geometry = None  # the geometry the page was last sent whole or as a delta
        self._moving = False  # an update of a drag in progress: send only what changed (get_state)
        self._points_unsent = False
        display = {k: engine_params.pop(k) for k in list(engine_params) if k in _DISPLAY_TRAITS + ("debug",)}
        view = self._given_view(display)
        super().__init__(max_points=max_points, **display)
        state = model.initial_state(points, engine_params, max_points=max_points)
        try:
            spline = self._check(state)
        except Rejected as exc:  # bad constructor arguments: a plain ValueError naming them
            raise ValueError(str(exc)) from None
        with self._quiet(), self.hold_sync():
            for name in MODEL_TRAITS:
                setattr(self, name, state[name])
            self.options = form_options(state["tension_scale"])
            self.explanation_html = explanation(state["form"], state["preset"], state["tension_scale"])
        self._spline = spline
        with self._quiet():
            self.t = drawing.clamp_parameter(spline, self.t)
        if view is None:
            self.fit_view()
        else:
            self.view = view
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
        cloud = np.vstack([self._spline.bezier().reshape(-1, 2), np.asarray(self.points)])
        lo, hi = cloud.min(axis=0), cloud.max(axis=0)
        size = float(max(hi[0] - lo[0], hi[1] - lo[1], 1e-9))
        pad = 0.05 * size if margin is None else check_number(margin, "margin", minimum=0.0)
        box = (lo[0] - pad, lo[1] - pad, hi[0] - lo[0] + 2 * pad, hi[1] - lo[1] + 2 * pad)
        return svg_document(self._spline.to_svg_path(precision=precision), box[2], box[3], view_box=box,
                            fill="none", stroke=stroke, stroke_width=stroke_width, decimals=precision)

    def save_svg(self, path) -> Path:
        """Write :meth:`to_svg` to ``path``; returns the path (a blank ``path`` is a ``ValueError``)."""
        path = file_path(path, "curve.svg")
        path.write_text(self.to_svg(), encoding="utf-8")
        return path

    def to_png(self, width: int = 800, height: int | None = None) -> bytes:
        """PNG bytes of the current curve, ``width`` pixels wide (the page's PNG button exports what it shows)."""
        return curves_png([self._spline.bezier()], width=width, height=height)

    def undo(self) -> bool:
        """Restore the state before the last change; False when there is nothing to undo."""
        return self._travel(self._history.undo, "Undone.", "Nothing to undo.")

    def redo(self) -> bool:
        """Re-apply the last undone change; False when there is nothing to redo."""
        return self._travel(self._history.redo, "Redone.", "Nothing to redo.")

    def add_point(self, x: float, y: float, *, tolerance: float | None = None) -> int:
        """Insert a point at ``(x, y)``; returns its index (or -1 if rejected).

        Within ``tolerance`` of the curve (default: 2% of the view) the point goes into the sequence
        where it lies on the curve (between the two points of that piece's interval or leg); elsewhere an
        open curve grows at its nearer end and a closed one gets it in the nearest piece.
        """
        x, y = check_number(x, "x"), check_number(y, "y")
        if tolerance is not None:
            tolerance = check_number(tolerance, "tolerance", minimum=0.0)
        return self._add_point(x, y, tolerance)

    def delete_point(self, index: int) -> bool:
        """Remove point ``index``; False (with a message) if the form needs more points."""
        return self._delete_point(check_int(index, "index"))

    def fit_view(self) -> None:
        """Fit the view to the points and the curve (and the curvature comb, when it is shown)."""
        self.view = drawing.fitted_view(self.points, self._spline, self.comb_scale if self.show_comb else None)

    @property
    def explanation(self) -> str:
        """What the controls of the current form do, as plain text (the page shows ``explanation_html``)."""
        return plain_text(self.explanation_html)

    @property
    def basis_figure(self):
        """bqplot Figure with the live basis functions (created on first use, then kept in sync)."""
        from ._basis_plot import BasisPlot

        return self._plot("basis", BasisPlot).figure

    @property
    def curvature_figure(self):
        """bqplot Figure of κ(t) with the one-sided jumps at the joints marked (created on first use, kept in sync)."""
        from ._basis_plot import CurvaturePlot

        return self._plot("curvature", CurvaturePlot).figure

    # ------------------------------------------------------------------ state
    def _state(self) -> dict:
        return model.copy_state({name: getattr(self, name) for name in MODEL_TRAITS})

    def _check(self, state):
        return model.check_state(state, max_points=self.max_points)

    def _save_good(self):
        return self._state(), self._spline

    def _restore_good(self, saved) -> None:
        state, spline = saved
        if spline is not None and (spline is not self._spline or state != self._state()):
            self._commit(state, spline)

    def get_state(self, key=None, drop_defaults=False):
        """The synced state; an update during a drag carries only what changed.

        While a point moves (every drag message but the release) the page draws the point itself, so
        ``points`` waits for the release, and ``geometry`` goes as :func:`._editor_drawing.geometry_delta`
        against the geometry the page holds. Full states (a new view, a resync) are always whole.
        """
        state = super().get_state(key=key, drop_defaults=drop_defaults)
        moving = self._moving and key is not None
        if "geometry" in state:
            sent, self._sent_geometry = self._sent_geometry, self.geometry
            delta = drawing.geometry_delta(sent, self.geometry) if moving and sent else None
            if delta is not None:
                state["geometry"] = delta
        if "points" in state:
            self._points_unsent = moving
            if moving:
                del state["points"]
        return state

    def _commit(self, state, spline, *, seq=None, moving=False):
        self._moving = moving
        try:
            self._commit_traits(state, spline, seq=seq)
        finally:
            self._moving = False

    def _commit_traits(self, state, spline, *, seq=None):
        with self._quiet(), self.hold_sync():
            if self._points_unsent and not self._moving:
                self._states_to_send.add("points")  # the release, or any change after a drag: the page gets them
            for name in MODEL_TRAITS:
                if getattr(self, name) != state[name]:
                    setattr(self, name, state[name])
            self._spline = spline
            self.t = drawing.clamp_parameter(spline, self.t)
            if self.selected >= len(self.points):
                self.selected = -1
            if self.selected_interval >= len(self.interval_weights):
                self.selected_interval = -1
            self._publish(seq=seq)
            self.explanation_html = explanation(self.form, self.preset, self.tension_scale)
            self.options = form_options(self.tension_scale)
            self.can_undo, self.can_redo = self._history.can_undo, self._history.can_redo

    def _apply(self, previous: dict, state: dict, *, key=None, seq=None) -> bool:
        """Check ``state``; if good, record ``previous`` for undo and show it. False (with a message) if bad."""
        try:
            spline = self._check(state)
        except Rejected as exc:
            self._reject(str(exc))
            return False
        self._history.push(previous, key=key)
        self._drag_gesture = None  # a drag's next move after this edit is a step of its own
        self._commit(state, spline, seq=seq)
        return True

    def _travel(self, step, done: str, nothing: str) -> bool:
        saved = self._history.saved()
        state = step(self._state())
        if state is None:
            self._set_status(nothing, "info")
            return False
        try:  # history holds only good states, but a limit may have changed since (max_points)
            spline = self._check(state)
        except Rejected as exc:
            self._history.restore(saved)  # the step did not happen: both stacks as they were
            self._reject(f"{'undo' if step == self._history.undo else 'redo'} is not possible: {exc}")
            return False
        self._drag_gesture = None
        self._commit(state, spline)
        self._set_status(done, "info")
        return True

    # ------------------------------------------------------------------ trait changes
    @tl.observe(*MODEL_TRAITS)
    def _on_model_change(self, change):
        if self._applying:
            return
        name = change["name"]
        previous = self._state()
        previous[name] = change["old"]
        try:
            state, note, stash = model.derive(name, change["old"], self._state(), spline=self._spline,
                                              stash=self._segment_stash)
            spline = self._check(state)
        except Rejected as exc:
            self._revert(name, change["old"], str(exc))
            return
        before = self._spline
        self._segment_stash = stash
        self._history.push(previous, key=name)
        self._drag_gesture = None  # a drag's next move after this change is a step of its own
        if name in _COMB_RESET:
            self._comb_unit = None  # a different curve: rescale the comb
        self._commit(state, spline)
        if name == "form" or (name == "points" and not self._from_page):
            self.fit_view()  # another form or new points from code: fit them (this also rescales the comb)
        self._set_status(note or model.describe_change(name, state, before, spline, selected=self.selected,
                                                       selected_interval=self.selected_interval), "info")

    def _revert(self, name, old, reason):
        with self._quiet():
            setattr(self, name, old)
        self._reject(reason, resync=(name,))  # the page still shows the rejected value: send the kept one

    def _display_problem(self, name, value):
        """Why a display value is bad (or None)."""
        if name == "comb_scale" and (value is None or not 0 < value <= 1000):
            return f"comb size must be a number in (0, 1000], got {value}"
        if name == "view":
            return view_problem(value)
        if name == "t" and value is not None and value != value:
            return "t = nan is not a number; pass a parameter value, or None to hide the point"
        if name == "t" and value is not None and self._spline is not None and \
                not self._spline.knots[0] <= value <= self._spline.knots[-1]:
            return f"t = {value:g} is outside the curve's parameters [{self._spline.knots[0]:g}, {self._spline.knots[-1]:g}]"
        if name == "selected" and not -1 <= value < len(self.points):
            return f"no point {value}"
        if name == "selected_interval" and not -1 <= value < len(self.interval_weights):
            return f"no interval {value}"
        return None

    @tl.observe(*_DISPLAY_TRAITS)
    def _on_display_change(self, change):
        name = change["name"]
        if name in ("view", "show_comb", "width", "height"):
            self._comb_unit = None
        if self._applying:
            return
        problem = self._display_problem(name, change["new"])
        if problem:
            self._revert(name, change["old"], problem)
            return
        if name not in _PAGE_ONLY:
            self._publish()

    # ------------------------------------------------------------------ page messages
    def _on_drag(self, content, _buffers):
        seq = read_int(content, "seq", low=0, high=_MAX_SEQ)
        index = read_int(content, "index", low=0, high=len(self.points) - 1)
        point = (read_number(content, "x"), read_number(content, "y"))
        final = read_bool(content, "final", default=False)
        gesture = read_int(content, "gesture", low=0, high=_MAX_SEQ, default=None)
        previous = self._state()
        state = model.moved(previous, index, point)
        try:
            spline = self._check(state)
        except Rejected as exc:
            self._reject(str(exc))  # the base answers: drag_ack ok=False and a resync of the kept points
            return
        if gesture is None or gesture != self._drag_gesture:
            self._history.push(previous, key=None)
            self._drag_gesture = gesture
        if final:  # the gesture is over: another view (or a reloaded page) numbers its gestures from 1 again
            self._drag_gesture = None
        self._commit(state, spline, seq=seq, moving=not final)
        if final:
            self._set_status(f"Point {index} moved to ({point[0]:.1f}, {point[1]:.1f}).", "info")

    def _resync_after(self, content) -> None:
        if isinstance(content, dict) and content.get("type") == "drag":
            seq = content.get("seq")
            self.send({"type": "drag_ack", "seq": seq if type(seq) is int else -1, "ok": False})

    def _on_add(self, content, _buffers):
        x, y = read_number(content, "x"), read_number(content, "y")
        self._add_point(x, y, read_number(content, "tol", low=0.0, default=None))

    def _on_delete(self, content, _buffers):
        self._delete_point(read_int(content, "index", low=-2**31, high=2**31))

    def _on_select_at(self, content, _buffers):
        x, y = read_number(content, "x"), read_number(content, "y")
        read_number(content, "tol", low=0.0, default=None)
        near = self._spline.nearest((x, y))
        interval = self._spline.piece_leg(near.piece)
        with self._quiet():
            self.selected_interval = interval if interval < len(self.interval_weights) else -1
        self._publish()
        if FORMS[self.form]["tension"]:
            self._set_status(f"Interval {interval} selected: set its weight ωᵢ in the side panel.", "info")

    def _on_undo(self, _content, _buffers):
        self.undo()

    def _on_redo(self, _content, _buffers):
        self.redo()

    def _on_fit(self, _content, _buffers):
        self.fit_view()

    def _on_resend(self, _content, _buffers):
        """The page missed the geometry a drag delta builds on (a view opened during a drag): send it whole."""
        self.send_state(["geometry", "points"])

    # ------------------------------------------------------------------ add / delete
    def _add_point(self, x: float, y: float, tolerance) -> int:
        if not FORMS[self.form]["add_delete"]:
            self._reject("this mode has exactly the four points F0, V, W, F1; switch the form to add points")
            return -1
        if len(self.points) >= self.max_points:
            self._reject(f"the editor takes at most max_points = {self.max_points} points")
            return -1
        if tolerance is None:
            view = self.view
            tolerance = 0.02 * max(view[2] - view[0], view[3] - view[1])
        previous = self._state()
        index, interval = model.insertion_place(previous, self._spline, (x, y), tolerance)
        if not self._apply(previous, model.inserted(previous, index, interval, (x, y))):
            return -1
        with self._quiet():
            self.selected = index
            self.selected_interval = -1
        self._publish()
        self._set_status(f"Point {index} added.", "info")
        return index

    def _delete_point(self, index: int) -> bool:
        if not FORMS[self.form]["add_delete"]:
            self._reject("this mode has exactly the four points F0, V, W, F1")
            return False
        if not 0 <= index < len(self.points):
            self._reject(f"no point {index} to delete")
            return False
        previous = self._state()
        if not self._apply(previous, model.deleted(previous, index)):
            return False
        with self._quiet():
            self.selected = -1
            self.selected_interval = -1
        self._publish()
        self._set_status(f"Point {index} deleted.", "info")
        return True

    # ------------------------------------------------------------------ drawing data
    def _publish(self, seq=None):
        """Send the drawing of the current curve to the page (one ``geometry`` update)."""
        spline = self._spline
        if spline is None:
            return
        self._revision += 1
        display = {name: getattr(self, name) for name in
                   ("show_bezier_points", "show_tangents", "show_comb", "comb_scale", "selected_interval", "t")}
        if self.show_comb and self._comb_unit is None:
            self._comb_unit = drawing.comb_unit(spline)
        self.geometry = drawing.geometry(spline, self._state(), display, revision=self._revision,
                                         seq=-1 if seq is None else seq, unit=self._comb_unit)
        for plot in self._plots.values():
            plot.update(self, final=seq is None)
