"""What a SplineEditor drag sends to the page: only what changed while the point moves, everything on release.

The page is simulated from the kernel's own update messages (``_send``): it starts from the full state (as a
new view does), puts the binary buffers back at their paths (ipywidgets' ``_put_buffers``) and applies each
geometry delta to the geometry it holds, as ``js/editor_view.js`` ``updateGeometry`` does. The reference is
the engine's curve (``editor.spline.bezier()``, ``knot_points``) as float32 bytes: after every update the
simulated page must hold exactly those bytes.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from ipywidgets.widgets.widget import _put_buffers

from splinecraft.widgets import SplineEditor

SETTINGS = settings(max_examples=25, deadline=None)


def spiral(n: int) -> np.ndarray:
    theta = np.linspace(0.0, 6.0 * np.pi, n)
    radius = 40.0 + 260.0 * np.linspace(0.0, 1.0, n)
    return np.c_[400.0 + radius * np.cos(theta), 320.0 + radius * np.sin(theta)]


class Page:
    """The page's copy of the synced state, built from the update messages the kernel sends."""

    def __init__(self, editor):
        self.state = dict(editor.get_state())  # what a new view gets: the whole state
        self.geometry = self.apply(None, self.state["geometry"])
        self.updates = []
        views = editor.__dict__.setdefault("_test_views", [])  # every view hears every update
        views.append(self)
        editor._send = lambda msg, buffers=None: [view.receive(msg, buffers) for view in views]

    @staticmethod
    def apply(previous, geometry):
        if "base" not in geometry:
            return {key: bytes(value) if isinstance(value, (bytes, memoryview)) else value
                    for key, value in geometry.items()}
        assert previous is not None and previous["revision"] == geometry["base"]
        out = dict(geometry)
        for key, width in (("bezier", 8), ("knots", 2)):
            rows = np.frombuffer(geometry[f"{key}_rows"], dtype="<i4")
            data = np.frombuffer(geometry[f"{key}_data"], dtype="<f4").reshape(-1, width)
            held = np.frombuffer(previous[key], dtype="<f4").reshape(-1, width).copy()
            held[rows] = data
            out[key] = held.tobytes()
        return out

    def receive(self, msg, buffers=None):
        if msg.get("method") != "update":
            return
        state = msg["state"]
        _put_buffers(state, msg["buffer_paths"], list(buffers or []))
        self.updates.append(state)
        self.state.update(state)
        if "geometry" in state:
            self.geometry = self.apply(self.geometry, state["geometry"])

    def points(self):
        return np.frombuffer(bytes(self.state["points"]), dtype="<f8").reshape(-1, 2)


def engine_bytes(editor):
    spline = editor.spline
    knots = spline.knot_points[:-1] if spline.closed else spline.knot_points
    return np.asarray(spline.bezier(), dtype="<f4").tobytes(), np.asarray(knots, dtype="<f4").tobytes()


def drag(editor, index, xy, *, seq, final=False):
    editor._handle_message(editor, {"type": "drag", "index": index, "x": float(xy[0]), "y": float(xy[1]),
                                    "seq": seq, "gesture": 1, "final": final}, [])


@SETTINGS
@given(form=st.sampled_from(["interpolant", "basis", "timmer_g2", "timmer_gc2"]), closed=st.booleans(),
       n=st.integers(5, 60), where=st.floats(0.0, 1.0),
       steps=st.lists(st.tuples(st.floats(-30, 30), st.floats(-30, 30)), min_size=1, max_size=6))
def test_page_holds_the_engine_curve_after_every_update(form, closed, n, where, steps):
    editor = SplineEditor(spiral(n), form=form, closed=closed)
    page = Page(editor)
    index = min(int(where * n), n - 1)
    start = np.array(editor.points[index])
    for seq, step in enumerate(steps, start=1):
        drag(editor, index, start + np.array(step), seq=seq)
        assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)
        assert page.geometry["revision"] == editor.geometry["revision"]
    drag(editor, index, start + np.array(steps[-1]), seq=len(steps) + 1, final=True)
    assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)
    np.testing.assert_array_equal(page.points(), np.asarray(editor.points))


@pytest.mark.parametrize("form", ["interpolant", "basis"])
def test_moves_send_changed_rows_and_no_points(form):
    editor = SplineEditor(spiral(1000), form=form)
    page = Page(editor)
    full_bytes = len(editor.geometry["bezier"]) + len(editor.geometry["knots"])
    before_bezier, before_knots = engine_bytes(editor)
    drag(editor, 500, np.array(editor.points[500]) + [6.0, -4.0], seq=1)
    after_bezier, after_knots = engine_bytes(editor)
    update = page.updates[-1]
    assert "points" not in update and "bezier" not in update["geometry"]
    # the rows sent are exactly the pieces (knots) whose float32 bytes changed
    for key, before, after, width in (("bezier", before_bezier, after_bezier, 32), ("knots", before_knots, after_knots, 8)):
        changed = np.flatnonzero((np.frombuffer(before, np.uint8).reshape(-1, width)
                                  != np.frombuffer(after, np.uint8).reshape(-1, width)).any(axis=1))
        np.testing.assert_array_equal(np.frombuffer(update["geometry"][f"{key}_rows"], dtype="<i4"), changed)
    sent = sum(len(value) for value in update["geometry"].values() if isinstance(value, (bytes, memoryview)))
    assert sent < 0.1 * full_bytes


def test_release_sends_everything_even_where_the_last_move_was():
    editor = SplineEditor(spiral(40))
    page = Page(editor)
    target = np.array(editor.points[7]) + [5.0, 5.0]
    drag(editor, 7, target, seq=1)
    drag(editor, 7, target, seq=2, final=True)  # released where the last move was: no trait changes
    assert "points" in page.updates[-2] or "points" in page.updates[-1]
    np.testing.assert_array_equal(page.points()[7], target)
    assert "bezier" in page.state["geometry"]  # the model's value is whole again (a later view can use it)


def test_a_change_after_an_unreleased_drag_sends_the_points():
    editor = SplineEditor(spiral(30))
    page = Page(editor)
    drag(editor, 3, np.array(editor.points[3]) + [8.0, 0.0], seq=1)  # no release (the page went away)
    editor.set_state({"point_tension": [1.5] * 30})
    np.testing.assert_array_equal(page.points(), np.asarray(editor.points))
    assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)


def test_whole_state_and_resend_during_a_drag():
    editor = SplineEditor(spiral(30))
    page = Page(editor)
    drag(editor, 3, np.array(editor.points[3]) + [8.0, 0.0], seq=1)
    whole = editor.get_state()
    assert "bezier" in whole["geometry"] and "points" in whole
    late = Page(editor)  # a view opened during the drag
    drag(editor, 3, np.array(editor.points[3]) + [3.0, 0.0], seq=2)
    editor._handle_message(editor, {"type": "resend"}, [])
    assert "bezier" in late.updates[-1]["geometry"] and "points" in late.updates[-1]
    for view in (page, late):
        assert (view.geometry["bezier"], view.geometry["knots"]) == engine_bytes(editor)
    np.testing.assert_array_equal(late.points(), np.asarray(editor.points))


def test_rejected_move_resyncs_whole_points():
    editor = SplineEditor(spiral(30))
    page = Page(editor)
    drag(editor, 3, np.array(editor.points[3]) + [8.0, 0.0], seq=1)
    drag(editor, 3, editor.points[4], seq=2)  # onto its neighbour: refused, the page is resynced
    assert editor.status_level == "error"
    np.testing.assert_array_equal(page.points(), np.asarray(editor.points))
    assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)
