"""Real-browser test of the OutlineEditor: a TraceResult opened in JupyterLab and edited with the mouse.

Drag a knot, toggle a corner, box-select a contour and rotate it with its handle, undo, export; after each
step the kernel's state (read through the notebook's kernel) and the drawn SVG path are checked.
"""
from __future__ import annotations

import math

import pytest
from test_widgets_browser import wait_python

pytestmark = [pytest.mark.browser, pytest.mark.slow]

CELL = """\
import splinecraft as sc
from splinecraft import datasets
result = sc.trace(datasets.thesis_object("D"))
editor = result.edit(width=600, height=520)
editor.export_path = "exported_d.svg"
editor
"""

ROOT = "[data-testid=outline-editor][data-ready='1']"


def path_d(root, k):
    return root.query_selector(f"[data-testid=contour-{k}]").get_attribute("d")


def wait_path_change(page, k, old):
    page.wait_for_function(
        "([k, old]) => { const p = document.querySelector(`[data-testid=outline-editor] [data-testid=contour-${k}]`);"
        " return p && p.getAttribute('d') !== old; }", arg=[k, old], timeout=20_000)


def wait_drawn_matches_kernel(lab, page, root, k):
    """Wait until the drawn path of contour k starts at the kernel's first knot (screen -> data through the
    page's map): the page draws the kernel's last answer a moment after the kernel has it."""
    knot = lab.python_json(f"editor.contours[{k}][0]")
    page.wait_for_function(
        """([el, k, knot]) => {
          const d = el.querySelector(`[data-testid=contour-${k}]`).getAttribute('d');
          const [x, y] = d.slice(1, d.indexOf('C')).split(',').map(Number);
          const r = el.querySelector('[data-testid=canvas]').getBoundingClientRect();
          const [dx, dy] = el.__splinecraft.dataOf(r.left + x, r.top + y);
          return Math.hypot(dx - knot[0], dy - knot[1]) < 0.5;
        }""", arg=[root, k, knot], timeout=20_000)


def open_outline_editor(lab, cell=CELL):
    """Open the notebook and wait until the editor's canvas holds still on the screen for a few animation
    frames (the notebook settles its layout after the side bar collapses), so screen positions stay valid."""
    page = lab.open_notebook([cell])
    root = page.wait_for_selector(ROOT, timeout=60_000)
    root.scroll_into_view_if_needed()
    page.wait_for_function(
        """(el) => new Promise((resolve) => {
            const canvas = el.querySelector('[data-testid=canvas]');
            const spot = () => { const r = canvas.getBoundingClientRect(); return `${r.left},${r.top},${r.width}`; };
            let last = spot(), same = 0;
            const tick = () => {
              const now = spot();
              same = now === last ? same + 1 : 0;
              last = now;
              if (same >= 6) resolve(true); else requestAnimationFrame(tick);
            };
            requestAnimationFrame(tick);
          })""", arg=root, timeout=20_000)
    return page, root


def test_edit_a_traced_outline_in_the_browser(lab):
    page, root = open_outline_editor(lab)
    assert lab.python_json("len(editor.contours)") == 2
    wait_drawn_matches_kernel(lab, page, root, 0)
    wait_drawn_matches_kernel(lab, page, root, 1)

    # 1. drag knot 3 of the outer contour by (+25, +15) screen px
    before = lab.python_json("editor.contours[0][3]")
    old = path_d(root, 0)
    x, y = root.evaluate("el => el.__splinecraft.screenKnot(0, 3)")
    page.mouse.move(x, y)
    page.mouse.down()
    for step in range(1, 6):
        page.mouse.move(x + 5 * step, y + 3 * step)
        page.wait_for_timeout(30)
    page.mouse.up()
    target = root.evaluate("(el, p) => el.__splinecraft.dataOf(p[0], p[1])", [x + 25, y + 15])
    moved = wait_python(lab, "editor.contours[0][3]", lambda p: math.dist(p, target) < 0.5)
    assert math.dist(moved, before) > 5
    wait_path_change(page, 0, old)
    assert lab.python_json("editor.selection") == [[0, 3]]

    # 2. toggle that knot's corner flag with the button
    was = lab.python_json("editor.corners[0][3]")
    old = path_d(root, 0)
    root.query_selector("[data-testid=toggle-corner]").click()
    wait_python(lab, "editor.corners[0][3]", lambda v: v is (not was))
    if not was:  # a new corner changes the curve
        wait_path_change(page, 0, old)

    # 3. box-select the hole (contour 1) and rotate it with the rotate handle
    hole = lab.python_json("editor.contours[1]")
    corners = [root.evaluate("(el, p) => el.__splinecraft.screenOf(p[0], p[1])", p) for p in hole]
    xs, ys = [c[0] for c in corners], [c[1] for c in corners]
    page.mouse.move(min(xs) - 6, min(ys) - 6)
    page.mouse.down()
    page.mouse.move((min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, steps=3)
    page.mouse.move(max(xs) + 6, max(ys) + 6, steps=3)
    page.mouse.up()
    wait_python(lab, "sorted(map(tuple, editor.selection))", lambda v: v == [[1, i] for i in range(len(hole))])
    handle = root.evaluate("el => el.__splinecraft.screenHandle('rotate')")
    assert handle is not None
    center = ((min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2)
    radius = math.dist(handle, center)
    old_hole, old_outer = path_d(root, 1), path_d(root, 0)
    page.mouse.move(*handle)
    page.mouse.down()
    start = math.atan2(handle[1] - center[1], handle[0] - center[0])
    for step in range(1, 7):  # 30 degrees clockwise on screen
        angle = start + math.radians(5 * step)
        page.mouse.move(center[0] + radius * math.cos(angle), center[1] + radius * math.sin(angle))
        page.wait_for_timeout(30)
    page.mouse.up()
    wait_path_change(page, 1, old_hole)
    pivot = [(min(p[0] for p in hole) + max(p[0] for p in hole)) / 2,
             (min(p[1] for p in hole) + max(p[1] for p in hole)) / 2]  # the box centre before the gesture

    def turns(knots):
        return [math.degrees(math.atan2(b[1] - pivot[1], b[0] - pivot[0]) - math.atan2(a[1] - pivot[1], a[0] - pivot[0]))
                % 360 for a, b in zip(hole, knots)]

    # the release's message carries the final angle; intermediate answers may be read first
    rotated = wait_python(lab, "editor.contours[1]", lambda v: all(abs(turn - 30) < 1 for turn in turns(v)))
    assert path_d(root, 0) == old_outer  # only the selected contour moved
    lengths = [math.dist(rotated[i], rotated[i + 1]) - math.dist(hole[i], hole[i + 1]) for i in range(len(hole) - 1)]
    assert max(map(abs, lengths)) < 1e-6  # a rotation: knot spacing unchanged
    wait_drawn_matches_kernel(lab, page, root, 1)

    # 4. undo the rotation (Ctrl+Z on the widget)
    root.focus()
    page.keyboard.press("Control+z")
    wait_python(lab, "editor.contours[1]", lambda v: all(math.dist(a, b) < 1e-9 for a, b in zip(v, hole)))
    page.wait_for_function("(old) => document.querySelector('[data-testid=outline-editor] [data-testid=contour-1]')"
                           ".getAttribute('d') === old", arg=old_hole, timeout=20_000)

    # 5. export
    root.query_selector("[data-testid=export]").click()
    wait_python(lab, "__import__('os').path.isfile('exported_d.svg')", lambda v: v is True)
    assert (lab.server.root / "exported_d.svg").read_text().count("<path") == 1
    assert "Saved" in lab.python_json("editor.status_message")


def test_deviation_toggle_colours_pieces_and_shows_the_max(lab):
    page, root = open_outline_editor(lab)
    assert "max deviation" in root.query_selector("[data-testid=max-deviation]").inner_text()
    root.query_selector("[data-testid=show_deviation]").check()
    page.wait_for_selector("[data-testid=outline-editor] [data-testid=deviation-0]", timeout=20_000)
    drawn = sum(len(root.query_selector(f"[data-testid=deviation-{b}]").get_attribute("d").split("M")) - 1
                for b in range(4))
    assert drawn == lab.python_json("sum(len(c) for c in editor.contours)")
    assert lab.python_json("editor.show_deviation") is True
    before = lab.python_json("editor.contours[0]")
    old = path_d(root, 0)
    root.query_selector("[data-testid=mirror-vertical]").click()  # nothing selected: the whole shape
    mirrored = wait_python(lab, "editor.contours[0]", lambda v: v != before)
    xs = [p[0] for p in before]
    middle = (min(xs) + max(xs)) / 2  # the box of all knots: contour 0 holds the extreme ones
    assert all(abs((a[0] + b[0]) / 2 - middle) < 1e-6 and abs(a[1] - b[1]) < 1e-9 for a, b in zip(before, mirrored))
    wait_path_change(page, 0, old)


def test_trace_explorer_opens_the_shown_iteration_in_an_editor(lab):
    cell = ("import splinecraft as sc\nfrom splinecraft import datasets\n"
            "explorer = sc.TraceExplorer(datasets.thesis_object('D'))\nexplorer")
    page = lab.open_notebook([cell])
    root = page.wait_for_selector("[data-testid=trace-explorer][data-ready='1']", timeout=60_000)
    root.query_selector("[data-testid=first]").click()
    wait_python(lab, "explorer.snapshot_index", lambda v: v == 0)
    root.query_selector("[data-testid=edit-outline]").click()
    page.wait_for_selector("[data-testid=editor-slot] [data-testid=outline-editor][data-ready='1']", timeout=30_000)
    first = lab.python_json("[len(c) for c in explorer.editor.contours]")
    expected = lab.python_json("[len(s.bezier) for s in explorer.result.snapshots[0].snapshots]")
    assert first == expected
    drawn = page.query_selector("[data-testid=editor-slot] [data-testid=contour-0]").get_attribute("d")
    assert drawn.count("C") == first[0]


def test_wheel_zoom_and_resize_change_the_view(lab):
    page, root = open_outline_editor(lab)
    view = lab.python_json("editor.view")
    old = path_d(root, 0)
    x, y = root.evaluate("el => el.__splinecraft.screenKnot(0, 0)")
    far = root.evaluate("el => el.__splinecraft.screenKnot(0, 5)")
    page.mouse.move(x, y)
    page.mouse.wheel(0, -100)
    wait_python(lab, "editor.view", lambda v: v != view)
    after = root.evaluate("el => el.__splinecraft.screenKnot(0, 0)")
    assert math.dist(after, (x, y)) < 2.0  # around the pointer
    spread = math.dist(after, root.evaluate("el => el.__splinecraft.screenKnot(0, 5)")) / math.dist((x, y), far)
    assert spread == pytest.approx(1.15, rel=0.02)  # one wheel step zooms in by 1.15
    assert path_d(root, 0) != old
    lab.execute("editor.width = 400")
    page.wait_for_function("() => document.querySelector('[data-testid=outline-editor] [data-testid=canvas]')"
                           ".getAttribute('width') === '400'", timeout=20_000)


def test_a_view_given_to_the_constructor_is_the_view_drawn(lab):
    """``result.edit(view=...)``: the page draws that rectangle (centred, the limiting axis filling the canvas),
    not the view fitted to the outline."""
    cell = CELL.replace("result.edit(width=600, height=520)", "result.edit(width=600, height=520, view=[10, 20, 110, 120])")
    page, root = open_outline_editor(lab, cell)
    assert lab.python_json("editor.view") == [10.0, 20.0, 110.0, 120.0]
    top, centre, bottom = root.evaluate(
        """el => { const r = el.querySelector('[data-testid=canvas]').getBoundingClientRect();
                   const s = el.__splinecraft;
                   return [s.dataOf(r.left + r.width / 2, r.top), s.dataOf(r.left + r.width / 2, r.top + r.height / 2),
                           s.dataOf(r.left + r.width / 2, r.top + r.height)]; }""")
    assert centre == pytest.approx([60.0, 70.0], abs=0.3)
    assert top[1] == pytest.approx(20.0, abs=0.3) and bottom[1] == pytest.approx(120.0, abs=0.3)  # 520 < 600: height limits
