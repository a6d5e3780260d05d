"""``OutlineEditor``: edit a captured outline in JupyterLab -- knots, corners, tensions, transforms, export.

The kernel holds an :class:`~splinecraft.outline.Outline` (several closed contours in the project's spline
form, thesis sections 3.1 and 5.1) and rebuilds the edited contours with the engine on every change; the page
(``js/outline_editor.js``) draws what the kernel sends (per contour, the Bézier pieces as float32 buffers, and
the deviation of each piece from the bitmap's contour) and turns pointer and keyboard input into messages.

Code and page share the synced traits ``contours`` (knots per contour), ``corners`` (flags per knot),
``point_tension`` / ``interval_weights`` (per knot / per piece), ``handles_in`` / ``handles_out`` (the corners'
Bézier offsets, ``None`` where there is no handle) and ``selection`` (``[contour, knot]`` pairs).
A bad value from either side keeps the last good outline and says why in ``status_message`` (from code also
as an :class:`OutlineEditorWarning`).
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import traitlets as t

from .._validation import blank_text
from ..outline import Outline, as_outline
from ..outline.transforms import reflection, rotation, scaling, shearing, translation
from ._assets import load_css, load_esm
from ._base import Bool, Int, WidgetBase, f32, json_numbers, read_number, read_str, short_reason
from ._outline_gestures import HISTORY, OutlineGestures
from ._outline_state import (OUTLINE_TRAITS, MAX_COORDINATE, DeviationCache, check_outline_reach, clean_selection,
                             fitted_view, grouped_by_contour, outline_from_lists, png_of_mask, synced_tables)

__all__ = ["OutlineEditor", "OutlineEditorWarning"]

_OUTLINE_TRAITS = tuple(OUTLINE_TRAITS)
_DISPLAY = ("width", "height", "view", "show_image", "show_deviation", "show_fill", "export_path")


def _within_reach(position):
    """``position`` (x, y) when it lies within ±:data:`MAX_COORDINATE`, so that a far one is named as such (farther out the
    outline would only see coinciding knots); anything else goes to the outline, which names it."""
    try:
        point = np.asarray(position, dtype=float)
    except (TypeError, ValueError):
        return position
    if point.shape == (2,) and np.isfinite(point).all() and (np.abs(point) > MAX_COORDINATE).any():
        raise ValueError(f"position ({point[0]:g}, {point[1]:g}) is beyond ±{MAX_COORDINATE:g}")
    return position


class OutlineEditorWarning(UserWarning):
    """A value set from code was rejected; the editor kept its last good outline."""


class OutlineEditor(OutlineGestures, WidgetBase):
    """Edit the contours of an outline: drag knots, corners, insert and delete, tensions, transforms, export.

    Parameters
    ----------
    source : TraceResult, Outline, SVG (file, document or path data), list of contours, font glyph outline
        Anything :func:`splinecraft.outline.as_outline` accepts; ``iteration=`` picks an iteration of a trace.
    **params
        ``width``, ``height`` (canvas px, 120 to 4000), ``show_image``, ``show_deviation``, ``show_fill``, ``export_path``,
        ``debug``.

    Page
    ----
    Drag a knot (or the selected knots); click a knot to select it (Shift adds), click the curve to select its
    contour, drag on the background for a box selection; a selected corner shows its two handles (the Bézier
    control points next to it), and dragging one puts that control point under the pointer; double-click the
    curve to insert a knot; ``C`` or the button toggles corner / smooth; Delete removes the selected knots;
    arrow keys move the selection (Shift: 10 px); the handles of the selection's box translate, rotate (round
    handle), scale (corners, Shift: per axis) and shear (edge handles); the mirror buttons reflect the selection
    (or the whole shape) about its box's vertical or horizontal centre line; Ctrl+Z / Ctrl+Y undo and redo; the
    wheel zooms, the middle button pans, Fit resets the view.

    Synced traits
    -------------
    contours : list of list of [x, y] -- the knots of every contour
    corners : list of list of bool -- corner flags
    point_tension, interval_weights : list of list of float -- per knot, per piece
    handles_in, handles_out : list of list of [dx, dy] or None -- per knot, the Bézier offsets ``b2 - b3`` arriving
        at and ``b1 - b0`` leaving a corner (``None``: no handle, the tangent follows the neighbours)
    selection : list of [contour, knot]
    max_deviation : float or None -- largest deviation (px) of a piece from the source contour
    can_undo, can_redo, status_message, status_level
    """

    _esm = load_esm("outline_editor.js")
    _css = load_css()
    kept = "outline"
    warning_class = OutlineEditorWarning
    messages = {**WidgetBase.messages, "drag": "_on_drag", "transform": "_on_transform", "corner": "_on_corner",
                "insert": "_on_insert", "delete": "_on_delete", "undo": "_on_undo", "redo": "_on_redo",
                "tension": "_on_tension", "weight": "_on_weight", "export": "_on_export", "fit": "_on_fit",
                "reflect": "_on_reflect", "handle": "_on_handle"}
    page_traits = frozenset(("selection",) + _DISPLAY)

    contours = t.List().tag(sync=True, to_json=json_numbers)
    corners = t.List().tag(sync=True)
    point_tension = t.List().tag(sync=True, to_json=json_numbers)
    interval_weights = t.List().tag(sync=True, to_json=json_numbers)
    handles_in = t.List().tag(sync=True, to_json=json_numbers)
    handles_out = t.List().tag(sync=True, to_json=json_numbers)
    selection = t.List().tag(sync=True)
    geometry = t.Dict().tag(sync=True)
    image = t.Bytes(b"").tag(sync=True)
    frame = t.List([1.0, 1.0]).tag(sync=True, to_json=json_numbers)
    view = t.List([]).tag(sync=True, to_json=json_numbers)
    width = Int(640, min=120, max=4000).tag(sync=True)
    height = Int(480, min=120, max=4000).tag(sync=True)
    show_image = Bool(True).tag(sync=True)
    show_deviation = Bool(False).tag(sync=True)
    show_fill = Bool(True).tag(sync=True)
    max_deviation = t.Float(None, allow_none=True).tag(sync=True)
    can_undo = t.Bool(False).tag(sync=True)
    can_redo = t.Bool(False).tag(sync=True)
    export_path = t.Unicode("outline.svg").tag(sync=True)

    def __init__(self, source, *, iteration=None, **params):
        options = {} if iteration is None else {"iteration": iteration}
        outline = as_outline(source, **options)
        view = self._given_view(params)
        super().__init__(**params)
        self._outline = outline
        self._undo, self._redo = [], []
        self._gesture = None  # (kind, id, outline at the start of the gesture)
        self._revisions = [0] * len(outline)
        self._live_changed = set()
        self._deviations = DeviationCache()
        with self._quiet(), self.hold_sync():
            self.frame = [outline.width, outline.height]
            self.image = png_of_mask(outline.bitmap)
            self.view = fitted_view(outline) if view is None else view
            self._sync_traits()
        self._publish(changed=range(len(outline)))
        self._set_status(f"{len(outline)} contours, {sum(len(c) for c in outline.contours)} knots.")

    # ------------------------------------------------------------------ public API
    @property
    def outline(self) -> Outline:
        """The current outline (immutable; edits make new ones)."""
        return self._outline

    def _target(self, contours, knots):
        if contours is None and knots is None and self.selection:
            return None, [tuple(pair) for pair in self.selection]
        return contours, knots

    def transform(self, matrix, *, contours=None, knots=None) -> Outline:
        """Affine map (2x3 or 3x3 matrix) of the selection -- or, with nothing selected, the whole shape --
        acting on the knots and handles (thesis section 3.3). ``contours=`` / ``knots=`` choose explicitly."""
        contours, knots = self._target(contours, knots)
        return self._apply(lambda o: o.transform(matrix, contours=contours, knots=knots), "Transformed")

    def _pivot(self, center, contours, knots):
        contours, knots = self._target(contours, knots)
        return (self._outline.selection_center(contours, knots) if center is None else center), contours, knots

    def translate(self, dx, dy, **where):
        return self.transform(translation(dx, dy), **where)

    def rotate(self, degrees, *, center=None, **where):
        center, contours, knots = self._pivot(center, where.get("contours"), where.get("knots"))
        return self.transform(rotation(degrees, center), contours=contours, knots=knots)

    def scale(self, sx, sy=None, *, center=None, **where):
        center, contours, knots = self._pivot(center, where.get("contours"), where.get("knots"))
        return self.transform(scaling(sx, sy, center), contours=contours, knots=knots)

    def shear(self, kx, ky=0.0, *, center=None, **where):
        center, contours, knots = self._pivot(center, where.get("contours"), where.get("knots"))
        return self.transform(shearing(kx, ky, center), contours=contours, knots=knots)

    def slant(self, degrees, *, center=None, **where):
        """Italic slant: the top leans right by ``degrees``."""
        return self.shear(-math.tan(math.radians(degrees)), 0.0, center=center, **where)

    def reflect(self, axis="vertical", *, center=None, **where):
        center, contours, knots = self._pivot(center, where.get("contours"), where.get("knots"))
        return self.transform(reflection(axis, center), contours=contours, knots=knots)

    def move_knot(self, contour, knot, position) -> Outline:
        return self._apply(lambda o: o.move_knot(contour, knot, _within_reach(position)),
                           f"Knot {knot} of contour {contour} moved")

    def move_handle(self, contour, knot, side, position) -> Outline:
        """The ``side`` handle ("in" or "out") of corner ``knot`` ends at ``position``: the curve's control point
        next to the knot goes there (:meth:`~splinecraft.outline.Contour.with_handle`)."""
        return self._apply(lambda o: o.move_handle(contour, knot, side, _within_reach(position)),
                           f"Handle {side} of corner {knot} (contour {contour}) moved")

    def set_corner(self, contour, knot, corner=True) -> Outline:
        word = "a corner" if corner else "smooth"
        return self._apply(lambda o: o.set_corner(contour, knot, corner), f"Knot {knot} of contour {contour} is {word}")

    def insert_knot(self, contour, piece, theta=0.5) -> Outline:
        return self._apply(lambda o: o.insert_knot(contour, piece, theta), f"Knot inserted on piece {piece}")

    def delete_knot(self, contour, knot) -> Outline:
        return self._apply(lambda o: o.delete_knot(contour, knot), f"Knot {knot} of contour {contour} deleted")

    def set_point_tension(self, contour, knots, value) -> Outline:
        return self._apply(lambda o: o.set_point_tension(contour, knots, value), "Point tension set")

    def set_interval_weight(self, contour, pieces, value) -> Outline:
        return self._apply(lambda o: o.set_interval_weight(contour, pieces, value), "Interval weight set")

    def undo(self) -> bool:
        self._close_gesture()
        if not self._undo:
            return False
        self._redo.append(self._outline)
        self._commit(self._undo.pop(), "Undone", history=False)
        return True

    def redo(self) -> bool:
        self._close_gesture()
        if not self._redo:
            return False
        self._undo.append(self._outline)
        self._commit(self._redo.pop(), "Redone", history=False)
        return True

    def deviation(self) -> list:
        return self._outline.deviation()

    def to_svg(self, **options) -> str:
        return self._outline.to_svg(**options)

    def save_svg(self, path=None, **options) -> Path:
        return self._outline.save_svg(self.export_path if path is None else path, **options)

    def to_json(self, **options) -> str:
        return self._outline.to_json(**options)

    def to_glyph(self, name=None, **options):
        """A ufoLib2 glyph of the edited outline (:func:`splinecraft.font.to_glyph`)."""
        from .. import font

        return font.to_glyph(self._outline, name, **options)

    def bezier(self) -> list:
        return self._outline.bezier()

    # ------------------------------------------------------------------ state
    def _apply(self, edit, message, *, history=True) -> Outline:
        """Run ``edit(outline)``; a refusal (or a result beyond the editor's reach, :func:`check_outline_reach`)
        keeps the last good outline and says why."""
        try:
            new = check_outline_reach(edit(self._outline), self._outline)
        except (TypeError, ValueError) as exc:
            self._reject(exc)
            return self._outline
        self._commit(new, message, history=history)
        return new

    def _commit(self, new, message=None, *, history=True, seq=None, measure=True, live=False):
        """Make ``new`` the outline and send it to the page.

        ``live`` (the moves of a gesture while the deviation is hidden): only the Bézier pieces of the changed
        contours go to the page, in one small message; the synced lists, ``geometry`` and the deviation follow
        with the gesture's last message.
        """
        if history:
            self._close_gesture()
        old = self._outline
        if history:
            self._undo.append(old)
            del self._undo[:-HISTORY]
            self._redo.clear()
        self._outline = new
        if len(new) != len(old):
            changed = set(range(len(new)))
            self._revisions = [r + 1 for r in (self._revisions + [0] * len(new))[:len(new)]]
        else:
            changed = {k for k in range(len(new)) if new.contours[k] is not old.contours[k]}
        if live:
            self._live_changed |= changed
            self._send_live(sorted(changed), seq)
            return
        changed |= {k for k in self._live_changed if k < len(new)}
        self._live_changed = set()
        with self._quiet(), self.hold_sync():
            self._clamp_selection()
            self._sync_traits(changed)
            self._publish(changed=changed, seq=seq, measure=measure)
            self.can_undo, self.can_redo = bool(self._undo), bool(self._redo)
        if message:
            self._set_status(message + self._deviation_note())

    def _send_live(self, changed, seq):
        entries, buffers = [], []
        for k in changed:
            self._revisions[k] += 1
            entries.append({"index": k, "revision": self._revisions[k]})
            buffers.append(f32(self._outline.contours[k].bezier()))
        self.send({"type": "live", "seq": -1 if seq is None else int(seq), "contours": entries}, buffers)

    def _deviation_note(self):
        if self.max_deviation is None:
            return "."
        return f"; max deviation from the bitmap {self.max_deviation:.2f} px."

    def _sync_traits(self, changed=None):
        """The synced lists from the outline: all of them, or only the rows of the ``changed`` contours."""
        current = {name: getattr(self, name) for name in _OUTLINE_TRAITS}
        for name, table in synced_tables(self._outline, current, changed).items():
            setattr(self, name, table)

    def _clamp_selection(self):
        sizes = [len(c) for c in self._outline.contours]
        kept = [pair for pair in self.selection if pair[0] < len(sizes) and pair[1] < sizes[pair[0]]]
        if kept != self.selection:
            self.selection = kept

    def _publish(self, changed=(), seq=None, measure=True):
        """Send the drawing: per contour its Bézier pieces (and deviations), re-encoded only where changed.

        ``measure=False`` (the moves of a gesture while the deviation is not shown) leaves the deviation of the
        changed contours, and ``max_deviation``, to the gesture's last message.
        """
        outline = self._outline
        previous = self.geometry.get("contours", []) if self.geometry else []
        entries = list(previous[:len(outline)]) + [None] * max(0, len(outline) - len(previous))
        changed = set(changed)
        deviations, stale = [], False
        self._revisions = (self._revisions + [0] * len(outline))[:len(outline)]
        for k, contour in enumerate(outline.contours):
            deviation = self._deviations.get(outline, k, measure)
            if deviation is not None:
                deviations.append(float(deviation.max()))
            stale = stale or (deviation is None and outline.sources[k] is not None)
            if k in changed or entries[k] is None:
                self._revisions[k] += 1
                entries[k] = {"bezier": f32(contour.bezier()), "revision": self._revisions[k],
                              "deviation": None if deviation is None else f32(deviation)}
            elif deviation is not None and entries[k].get("deviation") is None:
                entries[k] = {**entries[k], "deviation": f32(deviation)}
        if not stale:
            self.max_deviation = max(deviations) if deviations else None
        self.geometry = {"contours": entries, "seq": -1 if seq is None else int(seq),
                         "revision": int(self.geometry.get("revision", 0)) + 1 if self.geometry else 1}

    # ------------------------------------------------------------------ traits from code
    @t.observe(*_OUTLINE_TRAITS)
    def _on_outline_traits(self, change):
        if self._applying:
            return
        try:
            new = self._outline_from_traits(change["name"])
        except (TypeError, ValueError, IndexError) as exc:
            with self._quiet(), self.hold_sync():
                self._sync_traits()
            self._reject(f"{change['name']}: {exc}", resync=_OUTLINE_TRAITS)
            return
        self._commit(new, f"{change['name']} set")

    def _outline_from_traits(self, changed=None) -> Outline:
        return check_outline_reach(outline_from_lists(self._outline, self.contours, self.corners, self.point_tension,
                                                      self.interval_weights, self.handles_in, self.handles_out,
                                                      changed=changed), self._outline)

    @t.validate("export_path")
    def _valid_export_path(self, proposal):
        """An ``export_path`` that is blank ('', only white space: ``Path('')`` is the current folder, ``' '`` a file
        called space) keeps the last good one (from the page: a status and a resync; from code: a warning)."""
        path = proposal["value"]
        blank = blank_text(path)
        if not blank:
            return path
        reason = f"export_path is {blank}: give a file name such as outline.svg"
        if self._cross_validation_lock:
            raise t.TraitError(reason)
        self._reject(reason, resync=("export_path",))
        return self.export_path

    @t.validate("selection")
    def _valid_selection(self, proposal):
        """A bad selection keeps the last good one. Inside held notifications (every update from the page) the
        trait already holds the bad value here: a ``TraitError`` makes traitlets roll it back (and ``set_state``
        says why and resyncs the page); from code, a warning."""
        sizes = [len(c) for c in self._outline.contours] if hasattr(self, "_outline") else []
        try:
            return clean_selection(proposal["value"], sizes)
        except ValueError as exc:
            if self._cross_validation_lock:
                raise t.TraitError(str(exc)) from None
            self._reject(exc, resync=("selection",))
            return self.selection

    @t.observe("view")
    def _on_view(self, change):
        self._keep_good_view(change)

    @t.observe("show_deviation")
    def _on_show_deviation(self, change):
        if change["new"]:
            with self.hold_sync():
                self._publish()
            self._set_status("Deviation shown" + self._deviation_note())

    # ------------------------------------------------------------------ page messages
    def _selected_or_refuse(self):
        if not self.selection:
            raise ValueError("select a knot first")
        return [tuple(p) for p in self.selection]

    def _on_corner(self, content, _buffers):
        """Toggle the selected knots between corner and smooth: one undo step."""
        selected = self._selected_or_refuse()

        def toggled(outline):
            for contour, knot in selected:
                outline = outline.set_corner(contour, knot, not bool(outline.contours[contour].corners[knot]))
            return outline

        if len(selected) == 1:
            contour, knot = selected[0]
            self.set_corner(contour, knot, not bool(self._outline.contours[contour].corners[knot]))
            return
        self._apply(toggled, f"Toggled {len(selected)} knots between corner and smooth")

    def _on_insert(self, content, _buffers):
        x, y = read_number(content, "x"), read_number(content, "y")
        tolerance = read_number(content, "tol", low=0.0)
        contour, piece, theta, distance = self._outline.nearest_point((x, y))
        if distance > tolerance:
            raise ValueError(f"no curve within {tolerance:.3g} of ({x:.1f}, {y:.1f}); double-click on the curve")
        theta = min(max(theta, 0.02), 0.98)
        new = self.insert_knot(contour, piece, theta)
        with self._quiet():
            self.selection = [[contour, (piece + 1) % len(new.contours[contour])]]

    def _on_delete(self, _content, _buffers):
        pairs = sorted(self._selected_or_refuse(), key=lambda p: (p[0], -p[1]))
        outline = self._outline
        try:
            for contour, knot in pairs:
                outline = outline.delete_knot(contour, knot)
            check_outline_reach(outline, self._outline)
        except ValueError as exc:
            self._reject(exc)
            return
        with self._quiet():
            self.selection = []
        self._commit(outline, f"Deleted {len(pairs)} knot{'s' if len(pairs) > 1 else ''}")

    def _grouped_selection(self):
        return grouped_by_contour(self._selected_or_refuse())

    def _on_tension(self, content, _buffers):
        value = read_number(content, "value")
        outline = self._outline
        for contour, knots in self._grouped_selection().items():
            outline = outline.set_point_tension(contour, knots, value)
        self._commit(check_outline_reach(outline, self._outline), f"Point tension {value:g} at the selected knots")

    def _on_weight(self, content, _buffers):
        value = read_number(content, "value", low=0.0, inclusive=(False, True))  # omega > 0 (thesis §2.2)
        outline = self._outline
        for contour, knots in self._grouped_selection().items():
            outline = outline.set_interval_weight(contour, knots, value)
        self._commit(check_outline_reach(outline, self._outline),
                     f"Interval weight {value:g} on the pieces after the selected knots")

    def _on_reflect(self, content, _buffers):
        axis = read_str(content, "axis", choices=("vertical", "horizontal"))
        self.reflect(axis)

    def _on_undo(self, _content, _buffers):
        if not self.undo():
            self._set_status("Nothing to undo.")

    def _on_redo(self, _content, _buffers):
        if not self.redo():
            self._set_status("Nothing to redo.")

    def _on_export(self, _content, _buffers):
        """Save to ``export_path``. A write that fails (a folder that is missing or not writable, a path that is a
        folder) is not a bad input to the outline, which is kept as it is: an error status says what failed."""
        try:
            path = self.save_svg()
        except OSError as exc:
            self._set_status(f"Not saved to {self.export_path!r}: {exc.strerror or short_reason(exc)}", "error")
            return
        self._set_status(f"Saved {os.fspath(path)}.")

    def _on_fit(self, _content, _buffers):
        with self._quiet():
            self.view = fitted_view(self._outline)

    def _save_good(self):
        return self._outline

    def _restore_good(self, saved):
        self._settle()
        if saved is not self._outline:
            self._commit(saved, None, history=False)
        with self._quiet(), self.hold_sync():
            self._sync_traits()
