"""What a SplineEditor drag sends to the page: only what changed while the point moves, everything on release.

The page is simulated from the kernel's own update messages (``_send``): it starts from the full state (as a
new view does), puts the binary buffers back at their paths (ipywidgets' ``_put_buffers``) and applies each
geometry delta to the geometry it holds, as ``js/editor_view.js`` ``updateGeometry`` does. The reference is
the engine's curve (``editor.spline.bezier()``, ``knot_points``) as float32 bytes: after every update the
simulated page must hold exactly those bytes.
"""
from __future__ import annotations

import shutil
import subprocess
from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from ipywidgets.widgets.widget import _put_buffers

from splinecraft.widgets import SplineEditor
from splinecraft.widgets import _editor_drawing as drawing
from splinecraft.widgets._assets import static_dir

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
       steps=st.lists(st.tuples(st.floats(-30, 30), st.floats(-30, 30)), min_size=1, max_size=6),
       min_bytes=st.sampled_from([0, drawing.DELTA_MIN_BYTES]))
def test_page_holds_the_engine_curve_after_every_update(form, closed, n, where, steps, min_bytes):
    """Whole or as rows (``min_bytes`` 0: even these small curves move as changed rows)."""
    with mock.patch.object(drawing, "DELTA_MIN_BYTES", min_bytes):
        editor = SplineEditor(spiral(n), form=form, closed=closed)
        page = Page(editor)
        index = min(int(where * n), n - 1)
        start = np.array(editor.points[index])
        for seq, step in enumerate(steps, start=1):
            drag(editor, index, start + np.array(step), seq=seq)
            assert ("base" in page.updates[-1]["geometry"]) == (min_bytes == 0)
            assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)
            assert page.geometry["revision"] == editor.geometry["revision"]
        drag(editor, index, start + np.array(steps[-1]), seq=len(steps) + 1, final=True)
        assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)
        np.testing.assert_array_equal(page.points(), np.asarray(editor.points))


@pytest.mark.parametrize("n", [20, 100, 101, 400])
def test_small_curves_move_whole_large_ones_as_changed_rows(n):
    """One rule decides (:data:`DELTA_MIN_BYTES`): below it a move sends the Bézier and knot buffers whole."""
    editor = SplineEditor(spiral(n))
    page = Page(editor)
    drag(editor, n // 2, np.array(editor.points[n // 2]) + [4.0, 3.0], seq=1)
    geometry = page.updates[-1]["geometry"]
    small = len(editor.geometry["bezier"]) + len(editor.geometry["knots"]) < drawing.DELTA_MIN_BYTES
    assert small == (n <= 100)
    assert ("bezier" in geometry and "base" not in geometry) == small
    assert "points" not in page.updates[-1]  # the page draws the dragged point itself either way
    assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)


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
    editor = SplineEditor(spiral(150))
    page = Page(editor)
    target = np.array(editor.points[7]) + [5.0, 5.0]
    drag(editor, 7, target, seq=1)
    drag(editor, 7, target, seq=2, final=True)  # released where the last move was: no trait changes
    assert "points" in page.updates[-2] or "points" in page.updates[-1]
    np.testing.assert_array_equal(page.points()[7], target)
    assert "bezier" in page.state["geometry"]  # the model's value is whole again (a later view can use it)


def test_a_change_after_an_unreleased_drag_sends_the_points():
    editor = SplineEditor(spiral(150))
    page = Page(editor)
    drag(editor, 3, np.array(editor.points[3]) + [8.0, 0.0], seq=1)  # no release (the page went away)
    editor.set_state({"point_tension": [1.5] * 150})
    np.testing.assert_array_equal(page.points(), np.asarray(editor.points))
    assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)


def test_whole_state_and_resend_during_a_drag():
    editor = SplineEditor(spiral(150))
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
    editor = SplineEditor(spiral(150))
    page = Page(editor)
    drag(editor, 3, np.array(editor.points[3]) + [8.0, 0.0], seq=1)
    drag(editor, 3, editor.points[4], seq=2)  # onto its neighbour: refused, the page is resynced
    assert editor.status_level == "error"
    np.testing.assert_array_equal(page.points(), np.asarray(editor.points))
    assert (page.geometry["bezier"], page.geometry["knots"]) == engine_bytes(editor)


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_marker_tiles_in_node(tmp_path):
    """The marker raster's bookkeeping (js/marker_cache.js): which markers moved, which tiles a marker's ink
    meets, and which markers each tile must repaint -- against brute force over every pixel's tile."""
    base = static_dir().as_uri()
    script = tmp_path / "check.mjs"
    script.write_text(f"""
import assert from "node:assert/strict";
import {{ TILE, MAX_MOVED, movedMarkers, tileGrid, markersByTile }} from "{base}/marker_cache.js";
const painted = [10, 10, 70, 10, NaN, NaN, 130, 140];
assert.deepEqual(movedMarkers(painted, [10, 10, 71, 10, NaN, NaN, 130, 140]), [1]);   // NaN stays NaN: not moved
assert.deepEqual(movedMarkers(painted, painted.slice()), []);
assert.equal(movedMarkers(painted, painted.slice(0, 6)), null);                      // count changed: repaint all
assert.equal(movedMarkers(null, painted), null);
const many = Array.from({{ length: 2 * (MAX_MOVED + 1) }}, (_, i) => i);
assert.equal(movedMarkers(many, many.map((v) => v + 0.5)), null);                    // too many moved
// tiles of a 300 x 200 device-px raster at ratio 2 (150 x 100 CSS px), ink reaching 4 CSS px
const ratio = 2, reach = 4, grid = tileGrid(300, 200, ratio, reach);
assert.deepEqual([grid.columns, grid.rows], [Math.ceil(300 / TILE), Math.ceil(200 / TILE)]);
const tiles = (x, y) => {{ const out = []; grid.tilesOf(x, y, (k) => out.push(k)); return out.sort((a, b) => a - b); }};
// brute force: the tiles holding a device pixel within the ink's box (1 px of anti-aliasing around it)
const brute = (x, y) => {{
  const keys = new Set();
  for (let py = 0; py < 200; py++) for (let px = 0; px < 300; px++) {{
    if (px + 1 > (x - reach) * ratio - 1 && px < (x + reach) * ratio + 1 && py + 1 > (y - reach) * ratio - 1 && py < (y + reach) * ratio + 1)
      keys.add(Math.floor(py / TILE) * grid.columns + Math.floor(px / TILE));
  }}
  return [...keys].sort((a, b) => a - b);
}};
for (const [x, y] of [[5, 5], [31.5, 10], [32.2, 33], [149, 99], [0, 0], [-3, 50], [64, 64]]) {{
  const found = tiles(x, y), needed = brute(x, y);
  assert.ok(needed.every((k) => found.includes(k)), `${{x}},${{y}}: ${{found}} misses ${{needed}}`);
  assert.ok(found.length <= needed.length + 4, `${{x}},${{y}}: ${{found}} vs ${{needed}}`);
}}
assert.deepEqual(tiles(NaN, 5), []);
assert.deepEqual(tiles(500, 500), []);                                               // off the raster
// markers by tile: each tile lists (in index order) exactly the markers whose ink meets it
const centers = [5, 5, 31, 30, 33, 34, 100, 60, NaN, NaN, 80, 20];
const all = markersByTile(grid, centers);
for (const [key, list] of all) {{
  const expected = [];
  for (let i = 0; 2 * i < centers.length; i++) if (tiles(centers[2 * i], centers[2 * i + 1]).includes(key)) expected.push(centers[2 * i], centers[2 * i + 1]);
  assert.deepEqual(list, expected);
}}
const some = markersByTile(grid, centers, new Set([tiles(31, 30)[0]]));
assert.deepEqual([...some.keys()], [tiles(31, 30)[0]]);
assert.deepEqual(some.get(tiles(31, 30)[0]), all.get(tiles(31, 30)[0]));
console.log("ok");
""", encoding="utf-8")
    run = subprocess.run(["node", str(script)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr


def test_debug_ping_answers_with_the_asked_number_of_bytes():
    editor = SplineEditor(spiral(6), debug=True)
    answers = []
    editor.send = lambda content, buffers=None: answers.append((content, buffers))
    editor._handle_message(editor, {"type": "ping", "id": 3}, [])
    editor._handle_message(editor, {"type": "ping", "id": 4, "bytes": 40_000}, [])
    assert [(content["type"], content["id"]) for content, _ in answers] == [("pong", 3), ("pong", 4)]
    assert answers[0][1] is None and [len(buffer) for buffer in answers[1][1]] == [40_000]
    for bad in (-1, True, 1.5, 1 << 23, "40"):
        answers.clear()
        editor._handle_message(editor, {"type": "ping", "id": 5, "bytes": bad}, [])
        assert answers == [] and editor.status_level == "error" and "bytes" in editor.status_message
