"""Hostile pages: what a buggy or malicious front end can send the widgets' kernel side.

Every message and trait update goes through the real entry points (``_handle_message`` and ``set_state``,
which ipywidgets calls for the page). What the kernel sends back is recorded at the comm. After each one:

* the widget's state is either the last good one (rejected) or a new good one (accepted): the curve is
  always the engine's curve of the kept state, every kept value passes the widget's own checks;
* a rejected input got an error status sent to the page and a resync of what the page shows.
"""
from __future__ import annotations

import io
import math
import struct
import zlib

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from splinecraft.widgets import SplineEditor, SplineEditorWarning
from splinecraft.widgets import _editor_state as model

POINTS = [[60.0, 300.0], [160.0, 120.0], [300.0, 80.0], [440.0, 160.0], [540.0, 320.0]]
FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


class Page:
    """Records what the kernel sends to the page of ``widget`` (trait updates and custom messages)."""

    def __init__(self, widget):
        self.sent = []
        widget.comm.send = lambda data=None, buffers=None, **_kwargs: self.sent.append(data)

    def clear(self):
        self.sent.clear()

    def updated(self) -> set:
        """Names of the traits sent (JSON state and binary buffers)."""
        keys = set()
        for message in self.sent:
            if message.get("method") == "update":
                keys.update(message["state"])
                keys.update(path[0] for path in message.get("buffer_paths", []))
        return keys

    def custom(self) -> list:
        return [message["content"] for message in self.sent if message.get("method") == "custom"]

    def got_error_status(self) -> bool:
        for message in self.sent:
            state = message.get("state", {}) if message.get("method") == "update" else {}
            if state.get("status_level") == "error":
                return True
        return False


# ---------------------------------------------------------------------------------------------- strategies
hostile = st.one_of(
    st.none(), st.booleans(), st.integers(-2**70, 2**70), st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=6), st.lists(st.floats(allow_nan=True), max_size=3), st.dictionaries(st.text(max_size=3),
                                                                                          st.integers(), max_size=2),
)
coordinate = st.one_of(st.floats(-100, 700), hostile)
index = st.one_of(st.integers(-2, 7), hostile)
editor_messages = st.one_of(
    st.fixed_dictionaries({"type": st.just("drag"), "index": index, "x": coordinate, "y": coordinate,
                           "seq": st.one_of(st.integers(0, 10), hostile)},
                          optional={"final": st.one_of(st.booleans(), hostile), "gesture": index}),
    st.fixed_dictionaries({"type": st.just("add"), "x": coordinate, "y": coordinate},
                          optional={"tol": st.one_of(st.floats(0, 20), hostile)}),
    st.fixed_dictionaries({"type": st.just("delete"), "index": index}),
    st.fixed_dictionaries({"type": st.just("select_at"), "x": coordinate, "y": coordinate},
                          optional={"tol": st.one_of(st.floats(0, 20), hostile)}),
    st.fixed_dictionaries({"type": st.sampled_from(["undo", "redo", "fit", "ping", "pong", "", "DRAG"])}),
    st.fixed_dictionaries({"type": hostile}),
    hostile,
)
editor_updates = st.dictionaries(
    st.sampled_from(["points", "point_tension", "interval_weights", "alpha", "beta", "preset", "form", "closed",
                     "end_condition", "knots", "tension_scale", "selected", "selected_interval", "show_comb",
                     "comb_scale", "view", "width", "height", "geometry", "can_undo", "status_message", "options"]),
    st.one_of(hostile, st.floats(0.1, 5.0), st.lists(st.floats(-5, 5), min_size=5, max_size=5),
              st.sampled_from(["basis", "segment", "bezier", "natural", "uniform", "relative"])),
    min_size=1, max_size=3,
)


def kept_state_is_good(editor):
    """The editor's curve is the engine's curve of its state, and the state passes the editor's checks."""
    reference = model.check_state(editor._state(), max_points=editor.max_points)
    np.testing.assert_array_equal(editor.spline.bezier(), reference.bezier())
    assert -1 <= editor.selected < len(editor.points)
    assert -1 <= editor.selected_interval < len(editor.interval_weights)
    assert 120 <= editor.width <= 4000 and 120 <= editor.height <= 4000


# ---------------------------------------------------------------------------------------------- editor
@FUZZ
@given(st.lists(editor_messages, min_size=1, max_size=6))
def test_editor_survives_any_message(messages):
    editor = SplineEditor(POINTS)
    page = Page(editor)
    for message in messages:
        before = editor._state()
        page.clear()
        editor._set_status("", "info")
        editor._handle_message(editor, message, [])
        kept_state_is_good(editor)
        if editor.status_level == "error":
            assert editor._state() == before, message  # rejected: the last good state
            assert page.got_error_status(), message
            drag_answered = any(c.get("type") == "drag_ack" and c.get("ok") is False for c in page.custom())
            assert drag_answered or page.updated() - {"status_message", "status_level"}, message  # resynced


@FUZZ
@given(st.lists(editor_updates, min_size=1, max_size=4))
@example([{"end_condition": None, "closed": True, "can_undo": True}])  # closing the curve is an undo step
def test_editor_survives_any_trait_update(updates):
    editor = SplineEditor(POINTS)
    twin = SplineEditor(POINTS)  # gets only the page traits of each update
    page = Page(editor)
    for update in updates:
        page.clear()
        editor._set_status("", "info")
        editor.set_state(update)
        twin.set_state({name: value for name, value in update.items() if name in editor.page_traits})
        kept_state_is_good(editor)
        for name in update:
            if name not in editor.page_traits and name not in ("status_message", "status_level"):
                # kernel-only traits never take the page's value: they hold what the kernel computed, as in
                # the twin (a page change of `closed` may well make `can_undo` True)
                assert _same(getattr(editor, name), getattr(twin, name)), name
        if editor.status_level == "error":
            assert page.got_error_status(), update


def _same(first, second) -> bool:
    if isinstance(first, dict) and isinstance(second, dict):
        return first.keys() == second.keys() and all(_same(first[k], second[k]) for k in first)
    if isinstance(first, (np.ndarray, list, tuple)) or isinstance(second, (np.ndarray, list, tuple)):
        return np.array_equal(np.asarray(first, dtype=object), np.asarray(second, dtype=object))
    return first == second


@pytest.mark.parametrize("message, field", [
    ({"type": "drag", "index": True, "x": 1.0, "y": 2.0, "seq": 1}, "index"),
    ({"type": "drag", "index": 1, "x": "abc", "y": 2.0, "seq": 1}, "x"),
    ({"type": "drag", "index": 1, "x": 1.0, "y": 2.0, "seq": None}, "seq"),
    ({"type": "drag", "index": 1, "x": 1.0, "y": 2.0, "seq": 1, "final": "no"}, "final"),
    ({"type": "delete", "index": False}, "index"),
    ({"type": "select_at", "x": math.nan, "y": 1.0}, "x"),
    ({"type": "add", "x": 1e308 * 10, "y": 1.0}, "x"),
])
def test_editor_names_the_bad_field_and_keeps_the_state(message, field):
    editor = SplineEditor(POINTS)
    editor.selected_interval = -1
    page = Page(editor)
    before = editor._state()
    editor._handle_message(editor, message, [])
    assert editor._state() == before and editor.selected_interval == -1
    assert editor.status_level == "error" and field in editor.status_message
    assert page.got_error_status() and "points" in page.updated()  # the page is resynced to the kept state
    if message["type"] == "drag":
        assert {"type": "drag_ack", "seq": message["seq"] if type(message["seq"]) is int else -1,
                "ok": False} in page.custom()


@pytest.mark.parametrize("message, words", [
    ({"type": "drag", "index": 1, "x": 1e308, "y": 2.0, "seq": 1, "final": True},
     "point 1 at (1e+308, 2) is beyond ±1e+09"),
    ({"type": "drag", "index": 3, "x": 5.0, "y": -2e9, "seq": 2, "final": True},
     "point 3 at (5, -2e+09) is beyond ±1e+09"),
    ({"type": "add", "x": 1e300, "y": 1.0}, "at (1e+300, 1) is beyond ±1e+09"),
])
def test_editor_names_the_point_dragged_too_far(message, words):
    """A drag or an add far off the canvas was refused as 'a coordinate is beyond ±1e+09': which point, and where,
    went unsaid (the outline editor names both). Now the point and its position are named."""
    editor = SplineEditor(POINTS)
    page = Page(editor)
    before = editor._state()
    editor._handle_message(editor, message, [])
    assert editor._state() == before and editor.status_level == "error"
    assert words in editor.status_message and page.got_error_status() and "points" in page.updated()


def test_editor_batched_update_keeps_the_good_values():
    editor = SplineEditor(POINTS)
    page = Page(editor)
    editor.set_state({"alpha": 2.5, "closed": "no", "width": -100, "show_comb": True})
    assert editor.alpha == 2.5 and editor.show_comb is True  # the good values are applied
    assert editor.closed is False and editor.width == 620  # the bad ones are refused and resynced
    assert {"closed", "width"} <= page.updated()


def test_editor_exact_bools_and_capped_points():
    with pytest.raises(TypeError, match="closed"):
        SplineEditor(POINTS, closed="no")
    with pytest.raises(ValueError, match="max_points"):
        SplineEditor(np.c_[np.arange(50.0), np.sin(np.arange(50.0))], max_points=20)
    editor = SplineEditor(POINTS, max_points=6)
    page = Page(editor)
    many = np.c_[np.arange(7.0) * 50, np.cos(np.arange(7.0)) * 40].astype("<f8").tobytes()
    editor.set_state({"points": memoryview(many)})
    assert editor.points == POINTS and "max_points" in editor.status_message and "points" in page.updated()
    editor.set_state({"points": memoryview(many[:-8])})  # not whole (x, y) pairs
    assert editor.points == POINTS and "whole number" in editor.status_message
    assert editor.add_point(700.0, 300.0) == 5
    with pytest.warns(SplineEditorWarning, match="max_points"):
        assert editor.add_point(800.0, 300.0) == -1
    editor.max_points = 10
    assert editor.add_point(800.0, 300.0) == 6


def test_editor_failure_inside_a_handler_restores_the_state(monkeypatch):
    editor = SplineEditor(POINTS)
    before = editor._state()
    page = Page(editor)
    from splinecraft.widgets import _editor_drawing

    def out_of_memory(*_args, **_kwargs):
        raise MemoryError("no memory for the drawing")

    monkeypatch.setattr(_editor_drawing, "geometry", out_of_memory)
    editor._handle_message(editor, {"type": "drag", "index": 2, "x": 310.0, "y": 90.0, "seq": 1}, [])
    monkeypatch.undo()
    assert editor.status_level == "error" and "MemoryError" in editor.status_message
    assert page.got_error_status()
    editor._handle_message(editor, {"type": "fit"}, [])
    assert editor._state()["points"] == before["points"]
    kept_state_is_good(editor)


# ---------------------------------------------------------------------------------------------- TraceExplorer
def small_bitmap(size=40):
    yy, xx = np.mgrid[0:size, 0:size] + 0.5
    return ((xx > 6) & (xx < 34) & (yy > 6) & (yy < 20)) | ((xx > 6) & (xx < 18) & (yy > 6) & (yy < 34))


@pytest.fixture(scope="module")
def explorer():
    from splinecraft.widgets import TraceExplorer

    return TraceExplorer(small_bitmap(), epsilon=1.0)


def settings_of(explorer):
    return {name: getattr(explorer, name) for name in
            ("corner_method", "corner_params", "method", "epsilon", "tau", "seed", "max_iterations")}


def bomb_png(width=60_000, height=60_000) -> bytes:
    """A valid 1 x 1 PNG whose header claims ``width x height`` pixels (a decompression bomb's header)."""
    from PIL import Image

    buffer = io.BytesIO()
    Image.new("L", (1, 1), 255).save(buffer, format="PNG")
    data = bytearray(buffer.getvalue())
    ihdr = data[12:29]  # b"IHDR" + 13 bytes
    ihdr[4:12] = struct.pack(">II", width, height)
    data[12:29] = ihdr
    data[29:33] = struct.pack(">I", zlib.crc32(bytes(ihdr)) & 0xFFFFFFFF)
    return bytes(data)


def test_explorer_any_retrace_failure_restores_settings_and_result(explorer, monkeypatch):
    import splinecraft.widgets.trace_explorer as module

    good, result = settings_of(explorer), explorer.result

    def exhausted(*_args, **_kwargs):
        raise MemoryError("Unable to allocate 44.7 GiB")

    monkeypatch.setattr(module, "trace", exhausted)
    page = Page(explorer)
    explorer.set_state({"corner_params": {"smoothing": 3.0}})
    assert settings_of(explorer) == good and explorer.result is result
    assert explorer.busy is False and "MemoryError" in explorer.status_message and page.got_error_status()
    assert "corner_params" in page.updated()
    monkeypatch.undo()
    explorer.epsilon = 2.0  # later re-traces work
    assert explorer.result is not result and explorer.result.params["epsilon"] == 2.0
    assert explorer.status_level == "info"
    explorer.epsilon = 1.0


def test_explorer_time_budget_keeps_the_last_result(explorer, monkeypatch):
    import time

    import splinecraft.widgets.trace_explorer as module

    result = explorer.result
    real_trace = module.trace

    def slow_trace(*args, **kwargs):
        time.sleep(0.3)
        return real_trace(*args, **kwargs)

    monkeypatch.setattr(module, "trace", slow_trace)
    monkeypatch.setattr(explorer, "time_budget_s", 0.05)
    with pytest.warns(UserWarning, match="time budget of 0.05 s"):
        explorer.seed = 5
    assert explorer.seed == 0 and explorer.result is result and explorer.busy is False


def test_explorer_refuses_a_decompression_bomb_from_its_header(explorer):
    result = explorer.result
    page = Page(explorer)
    explorer._handle_message(explorer, {"type": "upload", "name": "bomb.png"}, [bomb_png()])
    assert explorer.result is result and "3600000000 pixels" in explorer.status_message
    assert page.got_error_status()


@FUZZ
@given(st.dictionaries(
    st.sampled_from(["epsilon", "tau", "seed", "max_iterations", "corner_params", "method", "corner_method",
                     "snapshot_index", "n_snapshots", "width", "play_interval_ms", "view", "show_final", "busy"]),
    st.one_of(hostile, st.floats(0.5, 4.0), st.sampled_from(["fuzzy", "lsq", "srm05", "bogus"])),
    min_size=1, max_size=3))
def test_explorer_survives_any_trait_update(explorer, update):
    page = Page(explorer)
    result = explorer.result
    explorer._set_status("", "info")
    explorer.set_state(update)
    assert explorer.busy is False
    assert 0 <= explorer.snapshot_index < explorer.n_snapshots == max(len(explorer.result.snapshots), 1)
    assert 120 <= explorer.width <= 4000
    if explorer.status_level == "error":
        assert page.got_error_status()
        if explorer.result is result:
            assert explorer.result.params["epsilon"] == explorer.epsilon  # the settings of the kept result
    explorer.set_state({"epsilon": 1.0, "method": "lsq", "seed": 0})


@FUZZ
@given(st.one_of(hostile, st.binary(max_size=64), st.fixed_dictionaries({"type": st.just("upload"),
                                                                          "name": hostile})))
def test_explorer_survives_any_message(explorer, message):
    page = Page(explorer)
    result = explorer.result
    explorer._set_status("", "info")
    explorer._handle_message(explorer, message, [b"\x89PNG not really"])
    assert explorer.result is result and explorer.busy is False
    assert explorer.status_level == "error" and page.got_error_status()


@pytest.mark.parametrize("tau", [float("inf"), float("nan"), -2.0])
def test_explorer_refuses_a_tau_no_method_takes_while_its_method_takes_none(explorer, tau):
    """With method 'lsq' (no tau), the page's tau=inf, NaN or -2 was accepted as the good state ('Traced ...'),
    and the next switch to 'euclidean' was refused for a tau the user had set long before. Such a tau fits no
    method: refused when it is set, naming tau; the last good tau is kept and the switch works."""
    explorer.set_state({"method": "lsq"})  # the shared explorer: the fuzz tests may have left another method
    page = Page(explorer)
    assert explorer.method == "lsq"
    good, result = settings_of(explorer), explorer.result
    explorer.set_state({"tau": tau})
    assert settings_of(explorer) == good and explorer.result is result
    assert explorer.status_level == "error" and "status_message" in page.updated()
    assert "tau (nearness of the methods euclidean, positional)" in explorer.status_message
    assert "tau" in page.updated()  # the page is resynced to the kept tau
    explorer.set_state({"method": "euclidean"})
    assert explorer.method == "euclidean" and explorer.status_level == "info"
    assert explorer.result.params["method"] == "euclidean"
    explorer.set_state({"method": "lsq"})


def _png(pixels) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(pixels).save(buffer, format="PNG")
    return buffer.getvalue()


@pytest.mark.parametrize("name, data, words", [
    ("text.png", b"hello world", "text.png: not an image file (PIL cannot identify its format)"),
    ("empty.png", b"", "empty.png: the file is empty (0 bytes), not an image"),
    ("cut.png", _png(np.zeros((30, 30), np.uint8))[:50], "cut.png: truncated or corrupt image file"),
])
def test_explorer_names_the_uploaded_file_it_cannot_read(explorer, name, data, words):
    """An upload that is no image was refused as 'image bytes (11 bytes): not an image file', the page's file name
    unsaid (and an empty one as 'image bytes are empty; pass the bytes of an encoded image file')."""
    result = explorer.result
    page = Page(explorer)
    explorer._handle_message(explorer, {"type": "upload", "name": name}, [data])
    assert explorer.result is result and explorer.status_level == "error" and "status_message" in page.updated()
    assert f"Kept the last good result: {words}" in explorer.status_message


def test_explorer_warns_of_an_upload_whose_every_pixel_is_ink(explorer):
    """An all-black upload was traced with an 'info' status ('Traced 1 boundary: 4 pieces'): its outline is the
    image's frame, which the command line and trace_many warn of (the note of trace). The status warns too now,
    and an image with a shape after it is back to 'info'."""
    explorer._handle_message(explorer, {"type": "upload", "name": "black.png"},
                             [_png(np.zeros((30, 40), np.uint8))])
    assert explorer.result.stats["boundaries"] == 1 and explorer.status_level == "warning"
    assert explorer.status_message.startswith("black.png: Traced 1 boundary")
    assert "Warning: every pixel is ink: the outline is the image's frame" in explorer.status_message
    shape = np.full((30, 40), 255, np.uint8)
    shape[8:20, 10:30] = 0
    explorer._handle_message(explorer, {"type": "upload", "name": "shape.png"}, [_png(shape)])
    assert explorer.status_level == "info" and explorer.status_message.startswith("shape.png: Traced")
    explorer.load(small_bitmap())  # the shared explorer's bitmap back
