"""The OutlineEditor's pointer gestures from the page: knot drags, corner-handle drags and transforms.

A gesture is a run of messages ``{type, ..., seq, gesture, final}`` (``js/drag_controller.js``: at most one in
flight, the final position always sent on release). Every move is applied to the outline the gesture started
from, so the latest message wins and nothing accumulates; the moves reach the page as "live" pieces and the
release publishes the synced lists and the deviation and makes the whole gesture one undo step. A refused
move answers ``drag_ack`` with ``ok: false``, keeps (and publishes) the outline of the last good move and says
why in the status line.
"""
from __future__ import annotations

from ..outline.transforms import affine_parts
from ._base import read_bool, read_int, read_number, read_str
from ._outline_state import MAX_COORDINATE, check_outline_reach, page_matrix

#: Undo steps kept.
HISTORY = 200


class OutlineGestures:
    """Mixin of :class:`~splinecraft.widgets.OutlineEditor`: the handlers of its "drag", "handle" and
    "transform" messages (it provides ``_outline``, ``_commit``, ``_reject``, the undo lists and ``_gesture``)."""
    def _gesture_start(self, kind, gesture):
        if self._gesture is None or self._gesture[:2] != (kind, gesture):
            self._gesture = (kind, gesture, self._outline)
        return self._gesture[2]

    def _finish(self, new, seq, final, message):
        self._commit(new, message if final else None, history=False, seq=seq,
                     measure=final or self.show_deviation, live=not final and not self.show_deviation)
        if final:
            self._end_gesture()

    def _close_gesture(self):
        """An edit from outside the gesture (a key, a button, undo, a call from Python) arrives while a gesture
        is in progress: the gesture so far becomes its own undo step, and its next moves start a new gesture
        from the edited outline (each move is applied to the outline its gesture started from, so without this
        the release would drop the edit)."""
        if self._gesture is not None:
            self._settle()
            self._end_gesture()

    def _end_gesture(self):
        """The gesture is over: its start becomes one undo step (if it changed the outline)."""
        start, self._gesture = self._gesture[2], None
        if start is not self._outline:
            self._undo.append(start)
            del self._undo[:-HISTORY]
            self._redo.clear()
            with self._quiet():
                self.can_undo, self.can_redo = True, False

    def _settle(self):
        """Publish the moves that reached the page only as live pieces (the synced lists and ``geometry``
        follow), so that after a refusal the page and the kernel show the same outline."""
        if self._live_changed:
            self._commit(self._outline, None, history=False)

    def _refuse_gesture(self, exc, seq, final):
        """A refused move of a gesture: a negative ``drag_ack``, the outline of the last good move kept and
        published, and the gesture ended by a refused release."""
        self.send({"type": "drag_ack", "seq": seq, "ok": False})
        self._settle()
        if final and self._gesture is not None:
            self._end_gesture()
        self._reject(exc, resync=("contours",))

    def _point_gesture(self, content, kind, edit, describe):
        """A drag of a knot or of a corner's handle to (x, y): ``edit(start, contour, knot, (x, y))`` on the outline
        the gesture started from; a refusal answers the page (``drag_ack``) and keeps the last good outline."""
        seq = read_int(content, "seq", low=0, high=2**53)
        try:
            contour = read_int(content, "contour", low=0, high=len(self._outline) - 1)
            knot = read_int(content, "knot", low=0, high=len(self._outline.contours[contour]) - 1)
            x = read_number(content, "x", low=-MAX_COORDINATE, high=MAX_COORDINATE)
            y = read_number(content, "y", low=-MAX_COORDINATE, high=MAX_COORDINATE)
            final = read_bool(content, "final")
            start = self._gesture_start(kind, read_int(content, "gesture", low=0, high=2**53))
            new = check_outline_reach(edit(start, contour, knot, (x, y)), start)
        except (TypeError, ValueError) as exc:
            self._refuse_gesture(exc, seq, content.get("final") is True)
            return
        self._finish(new, seq, final, describe(contour, knot, x, y))

    def _on_drag(self, content, _buffers):
        def dragged(start, contour, knot, point):
            selected = [tuple(p) for p in self.selection]
            if (contour, knot) in selected and len(selected) > 1:
                origin = start.contours[contour].points[knot]
                return start.translate(point[0] - origin[0], point[1] - origin[1], knots=selected)
            return start.move_knot(contour, knot, point)

        self._point_gesture(content, "drag", dragged,
                            lambda contour, knot, x, y: f"Knot {knot} of contour {contour} moved to ({x:.1f}, {y:.1f})")

    def _on_handle(self, content, _buffers):
        def moved(start, contour, knot, point):
            return start.move_handle(contour, knot, read_str(content, "side", choices=("in", "out")), point)

        self._point_gesture(content, "handle", moved, lambda contour, knot, x, y: (
            f"Handle {content['side']} of corner {knot} (contour {contour}) moved to ({x:.1f}, {y:.1f})"))

    def _on_transform(self, content, _buffers):
        seq = read_int(content, "seq", low=0, high=2**53)
        knots = [tuple(p) for p in self.selection] or None
        try:
            matrix = page_matrix(content.get("matrix"))
            final = read_bool(content, "final")
            start = self._gesture_start("transform", read_int(content, "gesture", low=0, high=2**53))
            affine_parts(matrix)
            new = check_outline_reach(start.transform(matrix, knots=knots), start)
        except (TypeError, ValueError) as exc:
            self._refuse_gesture(exc, seq, content.get("final") is True)
            return
        self._finish(new, seq, final, "Transformed the " + ("selection" if knots else "whole shape"))
