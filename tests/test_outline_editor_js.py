"""OutlineEditor front end in node: the linked module is valid JavaScript, and its pure parts (contour cache,
selection box, hit tests, handle matrices, gesture flow control) compute what they say."""
from __future__ import annotations

import shutil
import subprocess

import pytest

from splinecraft.widgets._assets import load_esm, module_order, static_dir

pytestmark = pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")


def run_node(tmp_path, body: str) -> None:
    base = static_dir().as_uri()
    script = tmp_path / "check.mjs"
    script.write_text(f"""
import assert from "node:assert/strict";
import {{ Viewport }} from "{base}/common.js";
import {{ ContourCache, selectionBox, handles, cornerHandles }} from "{base}/outline_view.js";
import {{ hitKnot, hitCurve, hitCornerHandle, knotsInRect, insideBox, transformMatrix, gestureMessage }}
  from "{base}/outline_input.js";
import {{ selectedValues }} from "{base}/outline_controls.js";
import {{ createDragFlow }} from "{base}/drag_controller.js";
const apply = (m, [x, y]) => [m[0] * x + m[2] * y + m[4], m[1] * x + m[3] * y + m[5]];
const close = (a, b, tol = 1e-9) => assert.ok(Math.hypot(a[0] - b[0], a[1] - b[1]) < tol, `${{a}} != ${{b}}`);
// two closed contours: a square 0..10 (4 line pieces) and a triangle
const line = (a, b) => [a[0], a[1], a[0] + (b[0] - a[0]) / 3, a[1] + (b[1] - a[1]) / 3,
  a[0] + 2 * (b[0] - a[0]) / 3, a[1] + 2 * (b[1] - a[1]) / 3, b[0], b[1]];
const loop = (pts) => new Float32Array(pts.flatMap((p, i) => line(p, pts[(i + 1) % pts.length])));
const square = loop([[0, 0], [10, 0], [10, 10], [0, 10]]), triangle = loop([[20, 0], [30, 0], [25, 8]]);
const cache = new ContourCache();
cache.update([{{ revision: 1, bezier: square.buffer, deviation: null }}, {{ revision: 1, bezier: triangle.buffer, deviation: null }}]);
const vp = new Viewport(100, 100, [0, 0, 100, 100]);  // one data unit per pixel
{body}
console.log("ok");
""", encoding="utf-8")
    run = subprocess.run(["node", str(script)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr


def test_linked_module_is_valid_javascript_with_one_default_export(tmp_path):
    order = module_order("outline_editor.js")
    assert order[-1] == "outline_editor.js" and "drag_controller.js" in order and "common.js" == order[0]
    target = tmp_path / "outline_editor.mjs"
    target.write_text(load_esm("outline_editor.js"), encoding="utf-8")
    run = subprocess.run(["node", "--check", str(target)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert target.read_text().count("export default") == 1


def test_contour_cache_knots_selection_box_and_hit_tests(tmp_path):
    run_node(tmp_path, """
assert.equal(cache.length, 2); assert.equal(cache.count(0), 4); assert.equal(cache.count(1), 3);
const { xy, owners } = cache.knots();
assert.deepEqual(Array.from(xy.slice(0, 8)), [0, 0, 10, 0, 10, 10, 0, 10]);
assert.deepEqual(owners[4], [1, 0]); assert.equal(owners.length, 7);
assert.deepEqual(hitKnot(vp, cache, 10.5, 9.6), [0, 2]);        // nearest knot within 8 px
assert.equal(hitKnot(vp, cache, 50, 50), null);
assert.equal(hitCurve(vp, cache, 5, 0.5), 0);                    // on the square's bottom edge
assert.equal(hitCurve(vp, cache, 50, 30), -1);                   // more than 8 px from every curve
assert.equal(hitCurve(vp, cache, 25, 14), 1);                    // 6 px above the triangle's apex
assert.deepEqual(knotsInRect(vp, cache, [31, -1], [19, 9]), [[1, 0], [1, 1], [1, 2]]);
const box = selectionBox(cache, [[0, 0], [0, 2], [1, 2]]);
assert.deepEqual(box, { x0: 0, y0: 0, x1: 25, y1: 10 });
assert.equal(selectionBox(cache, [[0, 1]]), null);               // one knot: no box
assert.equal(selectionBox(cache, [[0, 1], [0, 1]]), null);       // no extent
assert.ok(insideBox(vp, box, 12, 5) && !insideBox(vp, box, 26, 5) && !insideBox(vp, null, 1, 1));
const spots = handles(vp, box);
assert.deepEqual(spots["scale-se"], [25, 10]); assert.deepEqual(spots.rotate, [12.5, -24]);
// a live answer replaces the pieces of one contour and the knots follow
cache.replace(1, 2, loop([[40, 0], [50, 0], [45, 8]]).buffer);
assert.deepEqual(cache.knot(1, 2), [45, 8]); assert.deepEqual(Array.from(cache.knots().xy.slice(8, 10)), [40, 0]);
cache.update([{ revision: 1, bezier: square.buffer, deviation: null }]);  // one contour left
assert.equal(cache.length, 1); assert.equal(cache.knots().owners.length, 4);
assert.deepEqual(selectedValues([[1, 2, 2], [5]], [[0, 1], [0, 2]]), [2]);
assert.deepEqual(selectedValues([[1, 2, 2], [5]], [[0, 0], [1, 0]]), [1, 5]);
""")


def test_handle_matrices_rotate_scale_and_shear_about_the_right_points(tmp_path):
    run_node(tmp_path, """
const box = { x0: 0, y0: 0, x1: 20, y1: 10 }, c = [10, 5];
// rotate: grabbed above the centre, the pointer turned by 30 degrees about it
const a = Math.PI / 6, grab = [10, -15], r = 20;
const at = [c[0] + r * Math.sin(a), c[1] - r * Math.cos(a)];
const rot = transformMatrix({ handle: "rotate", box, x0: grab[0], y0: grab[1] }, ...at);
close(apply(rot, c), c);
close(apply(rot, [20, 5]), [c[0] + 10 * Math.cos(a), c[1] + 10 * Math.sin(a)]);
// uniform scale from the south-east corner keeps the north-west corner; Shift scales each axis
const uni = transformMatrix({ handle: "scale-se", box, x0: 20, y0: 10, shift: false }, 30, 15);
close(apply(uni, [0, 0]), [0, 0]); close(apply(uni, [20, 10]), [30, 15]);
const axes = transformMatrix({ handle: "scale-se", box, x0: 20, y0: 10, shift: true }, 40, 12);
close(apply(axes, [20, 10]), [40, 12]); close(apply(axes, [0, 0]), [0, 0]);
const nw = transformMatrix({ handle: "scale-nw", box, x0: 0, y0: 0, shift: true }, -20, -10);
close(apply(nw, [20, 10]), [20, 10]); close(apply(nw, [0, 0]), [-20, -10]);
// shear: the top edge moves with the pointer, the bottom edge stays; shear-right keeps the left edge
const top = transformMatrix({ handle: "shear-top", box, x0: 10, y0: 0 }, 14, 0);
close(apply(top, [0, 0]), [4, 0]); close(apply(top, [0, 10]), [0, 10]);
const right = transformMatrix({ handle: "shear-right", box, x0: 20, y0: 5 }, 20, 8);
close(apply(right, [20, 0]), [20, 3]); close(apply(right, [0, 7]), [0, 7]);
const move = transformMatrix({ handle: "move", box, x0: 3, y0: 4 }, 5, 1);
assert.deepEqual(move, [1, 0, 0, 1, 2, -3]);
assert.deepEqual(gestureMessage({ kind: "drag", contour: 1, knot: 2, x: 3, y: 4, ox: 9 }),
  { type: "drag", contour: 1, knot: 2, x: 3, y: 4 });
assert.deepEqual(gestureMessage({ kind: "transform", matrix: move }), { type: "transform", matrix: move });
""")


def test_gesture_flow_sends_the_latest_fields_and_always_the_release(tmp_path):
    run_node(tmp_path, """
globalThis.requestAnimationFrame = (fn) => setTimeout(fn, 0);
globalThis.cancelAnimationFrame = (id) => clearTimeout(id);
const sent = [], model = { get: () => false, send: (m) => sent.push(m) };
let idle = 0;
const flow = createDragFlow(model, { message: gestureMessage, onIdle: () => { idle += 1; } });
flow.begin({ kind: "drag", contour: 0, knot: 3, x: 1, y: 1 }, 7);
flow.update({ x: 2, y: 2 });
await new Promise((done) => setTimeout(done, 20));
assert.deepEqual(sent.map((m) => [m.x, m.final]), [[2, false]]);  // one frame, one message
flow.update({ x: 3, y: 3 }); flow.update({ x: 4, y: 5 });           // in flight: coalesced, not sent
await new Promise((done) => setTimeout(done, 20));
assert.equal(sent.length, 1);
assert.equal(flow.live().x, 4);
flow.end();                                                       // the release always goes, with the last fields
assert.deepEqual(sent[1], { type: "drag", contour: 0, knot: 3, x: 4, y: 5, seq: 2, gesture: 1, final: true });
assert.equal(flow.live().x, 4);                                   // shown until the kernel answers the release
flow.acknowledge(1); assert.ok(flow.live() && idle === 0);
flow.acknowledge(2); assert.equal(flow.live(), null); assert.equal(idle, 1);
flow.once({ type: "transform", matrix: [1, 0, 0, 1, 1, 0] });   // an arrow key: a gesture of its own
assert.deepEqual([sent[2].seq, sent[2].gesture, sent[2].final], [3, 2, true]);
const unmoved = createDragFlow(model, { message: gestureMessage });
unmoved.begin({ kind: "transform", matrix: [1, 0, 0, 1, 0, 0] }, 1);
unmoved.end();                                                    // a press without a move sends nothing
assert.equal(sent.length, 3);
""")


def test_corner_handles_are_the_control_points_next_to_the_selected_corners(tmp_path):
    run_node(tmp_path, """
// square knot 1 = (10, 0): its out handle is b1 of piece 1, its in handle b2 of piece 0
const corners = [[true, true, false, false], [false, false, false]];
const grips = cornerHandles(cache, corners, [[0, 1], [0, 2], [1, 0], [7, 0]]);  // smooth, other contour, unknown
assert.equal(grips.length, 2);
const out = grips.find((g) => g.side === "out"), into = grips.find((g) => g.side === "in");
close([out.x, out.y], [10, 10 / 3], 1e-5); close([into.x, into.y], [20 / 3, 0], 1e-5);
assert.deepEqual([out.contour, out.knot, out.kx, out.ky], [0, 1, 10, 0]);
const knot0 = cornerHandles(cache, corners, [[0, 0]]).find((g) => g.side === "in");
close([knot0.x, knot0.y], [0, 10 / 3], 1e-5);                       // knot 0 arrives from the last piece
assert.equal(hitCornerHandle(vp, grips, 10.5, 3.5).side, "out");
assert.equal(hitCornerHandle(vp, grips, 10, 20), null);
assert.deepEqual(gestureMessage({ kind: "handle", contour: 0, knot: 1, side: "in", x: 3, y: 4, ox: 1 }),
  { type: "handle", contour: 0, knot: 1, side: "in", x: 3, y: 4 });
""")
