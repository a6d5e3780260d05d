"""Real-browser test of the OutlineEditor's corner handles: select a corner, drag its handle with the mouse, and
the Bézier control point next to the corner goes where the pointer put it (kernel state and drawn path); undo and
redo with the keys; bad handle messages from the page are refused with a status and the page keeps showing the
kernel's outline. And a part of a contour (one run between corners) scaled per axis with the selection box's
handle maps exactly.
"""
from __future__ import annotations

import math

import pytest
from test_widgets_browser import wait_python
from test_widgets_outline_editor import open_outline_editor, path_d

pytestmark = [pytest.mark.browser, pytest.mark.slow]

CONTROL = "[round(float(v), 9) for v in editor.outline.contours[{k}].bezier()[{piece}, {node}]]"

# the corner of the traced D whose out handle (b1 - b0) is longest, and its knot count
PICK = """
import numpy as _np
_best = max(((float(_np.hypot(*(c.bezier()[i, 1] - c.bezier()[i, 0]))), k, int(i))
             for k, c in enumerate(editor.outline.contours) for i in _np.flatnonzero(c.corners)))
_smooth = int(_np.flatnonzero(~editor.outline.contours[_best[1]].corners)[0])
"""


def drawn_control(root, k, piece, node):
    """Control point ``node`` (1 or 2) of piece ``piece`` of the drawn path of contour ``k``, in data units."""
    return root.evaluate(
        """(el, [k, piece, node]) => {
          const d = el.querySelector(`[data-testid=contour-${k}]`).getAttribute('d');
          const curve = d.split('C')[piece + 1].trim().split(/\\s+/)[node - 1].split(',').map(Number);
          const r = el.querySelector('[data-testid=canvas]').getBoundingClientRect();
          return el.__splinecraft.dataOf(r.left + curve[0], r.top + curve[1]);
        }""", [k, piece, node])


def test_drag_a_corner_handle_then_undo_redo_and_refuse_bad_handles(lab):
    page, root = open_outline_editor(lab)
    lab.execute(PICK)
    _, k, i = lab.python_json("_best")
    smooth = lab.python_json("_smooth")
    count = lab.python_json(f"len(editor.contours[{k}])")
    before = lab.python_json(CONTROL.format(k=k, piece=i, node=1))
    arriving = lab.python_json(CONTROL.format(k=k, piece=(i - 1) % count, node=2))

    # 1. click the corner: its two handles appear
    knot = root.evaluate(f"el => el.__splinecraft.screenKnot({k}, {i})")
    page.mouse.click(*knot)
    wait_python(lab, "editor.selection", lambda v: v == [[k, i]])
    page.wait_for_function(f"(el) => el.__splinecraft.screenCornerHandle({k}, {i}, 'out') !== null", arg=root,
                           timeout=20_000)
    grip = root.evaluate(f"el => el.__splinecraft.screenCornerHandle({k}, {i}, 'out')")
    assert math.dist(root.evaluate("(el, p) => el.__splinecraft.dataOf(p[0], p[1])", grip), before) < 1e-3

    # 2. drag the out handle by (+18, -14) screen px: the control point follows the pointer exactly
    old = path_d(root, k)
    page.mouse.move(*grip)
    page.mouse.down()
    for step in range(1, 7):
        page.mouse.move(grip[0] + 3 * step, grip[1] - 14 * step / 6)
        page.wait_for_timeout(30)
    page.mouse.up()
    shift = [a - b for a, b in zip(root.evaluate("(el, p) => el.__splinecraft.dataOf(p[0], p[1])",
                                                 [grip[0] + 18, grip[1] - 14]),
                                   root.evaluate("(el, p) => el.__splinecraft.dataOf(p[0], p[1])", grip))]
    target = [before[0] + shift[0], before[1] + shift[1]]
    moved = wait_python(lab, CONTROL.format(k=k, piece=i, node=1), lambda p: math.dist(p, target) < 1e-3)
    # the live messages of the drag move the point; the gesture's last message (mouse up) records it: the status
    # and the undo step come with that one, which a loaded machine can deliver after the point has arrived
    wait_python(lab, "[editor.status_message, editor.can_undo]", lambda v: "Handle out" in v[0] and v[1])
    assert lab.python_json(CONTROL.format(k=k, piece=i, node=1)) == moved
    assert lab.python_json(CONTROL.format(k=k, piece=(i - 1) % count, node=2)) == arriving  # the other side kept
    assert lab.python_json(f"editor.contours[{k}][{i}]") == lab.python_json(f"editor.outline.contours[{k}]"
                                                                            f".points[{i}].tolist()")
    page.wait_for_function("([el, k, old]) => el.querySelector(`[data-testid=contour-${k}]`).getAttribute('d') "
                           "!== old", arg=[root, k, old], timeout=20_000)
    page.wait_for_function(
        "([el, k, i, p]) => { const s = el.__splinecraft.screenCornerHandle(k, i, 'out');"
        " const d = s && el.__splinecraft.dataOf(s[0], s[1]); return d && Math.hypot(d[0] - p[0], d[1] - p[1]) < 1e-3; }",
        arg=[root, k, i, moved], timeout=20_000)
    assert math.dist(drawn_control(root, k, i, 1), moved) < 0.02  # the drawn path: float32, 2 decimals

    # 3. undo and redo with the keys
    root.focus()
    page.keyboard.press("Control+z")
    wait_python(lab, CONTROL.format(k=k, piece=i, node=1), lambda p: p == before)
    page.wait_for_function("([el, k, old]) => el.querySelector(`[data-testid=contour-${k}]`).getAttribute('d') "
                           "=== old", arg=[root, k, old], timeout=20_000)
    page.keyboard.press("Control+Shift+z")
    wait_python(lab, CONTROL.format(k=k, piece=i, node=1), lambda p: p == moved)
    page.wait_for_function("([el, k, old]) => el.querySelector(`[data-testid=contour-${k}]`).getAttribute('d') "
                           "!== old", arg=[root, k, old], timeout=20_000)

    # 4. bad handle messages from the page: a status naming the problem, the outline and the drawing kept
    drawn, history = path_d(root, k), lab.python_json("len(editor._undo)")
    good = {"type": "handle", "contour": k, "knot": i, "side": "out", "x": target[0], "y": target[1],
            "gesture": 900, "final": True}
    bad = [({"side": "up"}, "side"), ({"x": None}, "x"), ({"knot": count + 3}, "knot"),
           ({"knot": smooth}, "smooth"), ({"contour": 99}, "contour")]
    for seq, (change, word) in enumerate(bad, start=900):
        lab.execute("editor.status_message = ''")
        root.evaluate("(el, m) => el.__splinecraft.send(m)", {**good, **change, "seq": seq, "gesture": seq})
        status = wait_python(lab, "[editor.status_level, editor.status_message]", lambda v: v[0] == "error" and v[1])
        assert "Kept the last good outline" in status[1] and word in status[1], (change, status)
        page.wait_for_function("(el) => el.querySelector('[data-testid=status]').textContent.includes('Kept')",
                               arg=root, timeout=20_000)
        assert lab.python_json(CONTROL.format(k=k, piece=i, node=1)) == moved
        assert path_d(root, k) == drawn
    assert lab.python_json("len(editor._undo)") == history  # refusals add no undo step
    assert lab.python_json("editor.undo() and editor.outline.contours[{}].bezier()[{}, 1].round(9).tolist()"
                           .format(k, i)) == before


# the run between two corners of contour 0 whose knots span the plane best (the largest least singular value of
# its centred knots, among runs of three knots or more): the check below fits the affine map to the run's knots,
# and on nearly collinear knots (a flat side) that fit is ill-conditioned, its residual rounding, not the map
RUN = """
import numpy as _np
_c = editor.outline.contours[0]
_corners = _np.flatnonzero(_c.corners)
_lengths = (_np.roll(_corners, -1) - _corners) % len(_c)
_runs = [[int(k) for k in (start + _np.arange(int(length) + 1)) % len(_c)]
         for start, length in zip(_corners, _lengths) if length >= 2]
_spread = [_np.linalg.svd(_c.points[r] - _c.points[r].mean(axis=0), compute_uv=False)[-1] for r in _runs]
_run = _runs[int(_np.argmax(_spread))]
_before = editor.outline
editor.selection = [[0, k] for k in _run]
"""

# the affine map that took the selected knots where they are (least squares: exact when it is affine), and how
# far the run's pieces and the other knots are from what that map and "stay" predict
CHECK = """
def _check():
    new, old = editor.outline.contours[0], _before.contours[0]
    a = _np.c_[old.points[_run], _np.ones(len(_run))]
    affine, *_ = _np.linalg.lstsq(a, new.points[_run], rcond=None)
    rest = _np.setdiff1d(_np.arange(len(old)), _run)
    expected = old.bezier()[_run[:-1]] @ affine[:2] + affine[2]
    return [float(_np.abs(a @ affine - new.points[_run]).max()),
            float(_np.abs(new.bezier()[_run[:-1]] - expected).max()),
            bool(_np.array_equal(new.points[rest], old.points[rest])), float(abs(_np.linalg.det(affine[:2]) - 1)),
            editor.outline.contours[1] is _before.contours[1]]
"""


def test_scale_one_run_between_corners_per_axis_with_the_box_handle(lab):
    """Part of a contour (one run between two corners) scaled per axis with Shift on the box's corner handle:
    the selected knots move by one affine map, the run's pieces are exactly that map's image of the old ones,
    the other knots and the hole stay."""
    page, root = open_outline_editor(lab)
    lab.execute(RUN + CHECK)
    run = lab.python_json("_run")
    page.wait_for_function("(el) => el.__splinecraft.screenHandle('scale-se') !== null", arg=root, timeout=20_000)
    old = path_d(root, 0)
    x, y = root.evaluate("el => el.__splinecraft.screenHandle('scale-se')")
    page.mouse.move(x, y)
    page.keyboard.down("Shift")
    page.mouse.down()
    for step in range(1, 6):
        page.mouse.move(x + 8 * step, y + 2 * step)
        page.wait_for_timeout(30)
    page.mouse.up()
    page.keyboard.up("Shift")
    wait_python(lab, "editor.can_undo", lambda v: v is True)
    fit, pieces, rest_kept, stretch, hole_kept = wait_python(lab, "_check()", lambda v: v[3] > 0.05)
    assert len(run) >= 3 and fit < 1e-9 and pieces < 1e-9 and rest_kept and hole_kept
    page.wait_for_function("([el, old]) => el.querySelector('[data-testid=contour-0]').getAttribute('d') !== old",
                           arg=[root, old], timeout=20_000)
