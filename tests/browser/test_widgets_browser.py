"""Real-browser tests: JupyterLab + Debian chromium drive the SplineEditor and TraceExplorer widgets.

Each test writes a fresh notebook into the server's temporary root, opens it, runs all cells, then acts
like a user (mouse drags, double-clicks, right-clicks, keys, sliders, buttons) and checks both sides: the
kernel's state (read through the notebook's own kernel) and what the page drew (SVG attributes).
"""
from __future__ import annotations

import math

import pytest

pytestmark = [pytest.mark.browser, pytest.mark.slow]

EDITOR_CELL = """\
import splinecraft as sc
editor = sc.SplineEditor([[60, 300], [160, 120], [300, 80], [440, 160], [540, 320]], width=620, height=420)
editor
"""

EDITOR = "[data-testid=spline-editor][data-ready='1']"


def open_editor(lab, cell=EDITOR_CELL):
    page = lab.open_notebook([cell])
    page.evaluate("() => window.jupyterapp.shell.collapseLeft()")
    root = page.wait_for_selector(EDITOR, timeout=60_000)
    wait_layout_settled(page, root)
    return page, root


def wait_layout_settled(page, root, frames: int = 6):
    """Wait until the canvas keeps its size for a few animation frames (it fills the cell, which the
    collapsing side bar resizes), so that screen positions read now stay valid."""
    page.wait_for_function(
        """([el, frames]) => new Promise((resolve) => {
            const canvas = el.querySelector('[data-testid=canvas]');
            let last = canvas.getAttribute('width'), same = 0;
            const tick = () => {
              const now = canvas.getAttribute('width');
              same = now === last ? same + 1 : 0;
              last = now;
              if (same >= frames) resolve(true); else requestAnimationFrame(tick);
            };
            requestAnimationFrame(tick);
          })""", arg=[root, frames], timeout=20_000)


def curve_d(root) -> str:
    return root.query_selector("[data-testid=curve]").get_attribute("d")


def wait_curve_change(page, old_d: str):
    page.wait_for_function(
        "(old) => { const p = document.querySelector(\"[data-testid=spline-editor] [data-testid=curve]\");"
        " return p && p.getAttribute('d') !== old; }",
        arg=old_d, timeout=20_000)


def wait_python(lab, expression: str, predicate, timeout: float = 20.0):
    """Poll the kernel until ``predicate(value)`` holds for the JSON value of ``expression``."""
    import time

    deadline = time.monotonic() + timeout
    while True:
        value = lab.python_json(expression)
        if predicate(value):
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"{expression} = {value!r} did not reach the expected state")
        lab.page.wait_for_timeout(100)


def wait_drag_released(lab, index: int):
    """The kernel's points once it has applied the release of a drag of point ``index``: only that message
    sets the status "Point i moved to ..." (the answers to the moves before it may be read earlier)."""
    wait_python(lab, "editor.status_message", lambda text: text.startswith(f"Point {index} moved to"))
    return lab.python_json("editor.points")


def test_drag_point_updates_python_and_curve(lab):
    page, root = open_editor(lab)
    before = lab.python_json("editor.points")
    old_d = curve_d(root)
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(2)")
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 11):  # several pointermove events, throttled to animation frames by the page
        page.mouse.move(x + 4.0 * k, y + 5.0 * k)
    page.mouse.up()
    target = root.evaluate("(el, xy) => el.__splinecraft.dataOf(xy[0], xy[1])", [x + 40.0, y + 50.0])
    after = wait_drag_released(lab, 2)
    # the final position is never lost: the kernel has exactly where the pointer was released
    assert math.dist(after[2], target) < 1e-6 * max(1.0, abs(target[0]) + abs(target[1]))
    assert [p for i, p in enumerate(after) if i != 2] == [p for i, p in enumerate(before) if i != 2]
    wait_curve_change(page, old_d)
    # the drawn curve is the kernel's curve: it passes through the moved point (an interpolant)
    assert lab.python_json("editor.spline(editor.spline.knots[2]).tolist()") == pytest.approx(after[2])
    assert lab.python_json("len(editor._history)") >= 1


def test_slider_moves_tension_and_redraws(lab):
    page, root = open_editor(lab)
    old_d = curve_d(root)
    slider = root.query_selector("[data-testid=point_tension-range]")
    box = slider.bounding_box()
    page.mouse.click(box["x"] + 0.85 * box["width"], box["y"] + box["height"] / 2)  # a real click on the track
    tension = wait_python(lab, "editor.point_tension", lambda v: v[0] > 1.0)
    assert len(set(tension)) == 1 and len(tension) == 5
    wait_curve_change(page, old_d)
    shown = float(root.query_selector("[data-testid=point_tension-number]").input_value())
    assert shown == pytest.approx(tension[0], rel=1e-3)


def test_add_and_delete_points(lab):
    page, root = open_editor(lab)
    # double-click on the curve between points 1 and 2: the new point goes between them
    mid = lab.python_json("editor.spline(0.5 * (editor.spline.knots[1] + editor.spline.knots[2])).tolist()")
    x, y = root.evaluate("(el, p) => el.__splinecraft.screenOf(p[0], p[1])", mid)
    old_d = curve_d(root)
    page.mouse.dblclick(x, y)
    page.wait_for_selector("[data-testid=spline-editor][data-npoints='6']", timeout=20_000)
    points = wait_python(lab, "editor.points", lambda pts: len(pts) == 6)
    assert math.dist(points[2], mid) < 3.0  # within a few pixels of where we clicked
    assert len(lab.python_json("editor.interval_weights")) == 5
    wait_curve_change(page, old_d)
    # right-click the new point: removed
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(2)")
    page.mouse.click(x, y, button="right")
    page.wait_for_selector("[data-testid=spline-editor][data-npoints='5']", timeout=20_000)
    assert len(lab.python_json("editor.points")) == 5
    # select point 3 and press Delete
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(3)")
    page.mouse.click(x, y)
    wait_python(lab, "editor.selected", lambda i: i == 3)
    page.keyboard.press("Delete")
    page.wait_for_selector("[data-testid=spline-editor][data-npoints='4']", timeout=20_000)
    assert len(lab.python_json("editor.points")) == 4
    # undo twice restores the two deleted points: once with the keyboard, once with the button
    page.keyboard.press("Control+z")
    page.wait_for_selector("[data-testid=spline-editor][data-npoints='5']", timeout=20_000)
    root.query_selector("[data-testid=undo]").click()
    page.wait_for_selector("[data-testid=spline-editor][data-npoints='6']", timeout=20_000)
    page.keyboard.press("Control+Shift+z")  # redo: the right-click deletion again
    page.wait_for_selector("[data-testid=spline-editor][data-npoints='5']", timeout=20_000)
    assert len(lab.python_json("editor.points")) == 5


def test_bad_value_from_page_keeps_last_good_curve(lab):
    page, root = open_editor(lab)
    old_d = curve_d(root)
    box = root.query_selector("[data-testid=interval_weights-number]")
    box.fill("-3")
    box.press("Enter")
    page.wait_for_selector("[data-testid=spline-editor][data-status-level='error']", timeout=20_000)
    assert "must be > 0" in root.query_selector("[data-testid=status]").inner_text()
    assert lab.python_json("editor.interval_weights") == [1.0, 1.0, 1.0, 1.0]
    assert curve_d(root) == old_d
    page.wait_for_function(
        "() => document.querySelector('[data-testid=interval_weights-number]').value === '1'", timeout=20_000)


def test_deep_ctrl_wheel_zoom_stops_and_the_page_keeps_responding(lab):
    """A long pinch (Ctrl+wheel) used to zoom to a view a few ulps wide, where drawing the grid never ended.
    The zoom now stops at 1e-8 x max(1, |coordinate|); the grid is drawn and the kernel takes the view."""
    page, root = open_editor(lab)
    x, y = (round(v) for v in root.evaluate("el => el.__splinecraft.screenOf(300.3, 80.7)"))
    target = root.evaluate("(el, xy) => el.__splinecraft.dataOf(xy[0], xy[1])", [x, y])  # stays under the pointer
    page.evaluate("""([x, y]) => setTimeout(() => {
        const svg = document.querySelector('[data-testid=spline-editor] [data-testid=canvas]');
        for (let i = 0; i < 600; i++) svg.dispatchEvent(new WheelEvent('wheel',
          { deltaY: -100, ctrlKey: true, clientX: x, clientY: y, bubbles: true, cancelable: true }));
        window.__zoomed = true;
      }, 0)""", [x, y])
    page.wait_for_function("() => window.__zoomed === true", timeout=30_000)
    corners = root.evaluate("""el => { const r = el.querySelector('[data-testid=canvas]').getBoundingClientRect();
        return [el.__splinecraft.dataOf(r.left, r.top), el.__splinecraft.dataOf(r.right, r.bottom)]; }""")
    (x0, y0), (x1, y1) = corners
    least = 1e-8 * max(1.0, abs(x0), abs(y0), abs(x1), abs(y1))
    assert least * 0.99 <= min(x1 - x0, y1 - y0) < 1e-5  # zoomed in about 1e7 times, and no further
    assert root.evaluate("el => el.querySelector('[data-testid=grid]').getAttribute('d').length") > 0
    view = wait_python(lab, "editor.view", lambda v: v[2] - v[0] < 1e-5)  # the page sent it after the last notch
    assert view[0] <= target[0] <= view[2] and view[1] <= target[1] <= view[3]
    assert lab.python_json("editor.status_level") != "error"
    root.query_selector("[data-testid=fit]").click()  # the page still answers: Fit brings the whole curve back
    wait_python(lab, "editor.view", lambda v: v[2] - v[0] > 400)


def test_touch_drag_moves_a_point(lab):
    """Touch input: Chromium turns CDP touch events into pointer events (pointerType "touch")."""
    page, root = open_editor(lab)
    before = lab.python_json("editor.points")
    old_d = curve_d(root)
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(1)")
    cdp = page.context.new_cdp_session(page)

    def touch(kind, px, py):
        points = [] if kind == "touchEnd" else [{"x": px, "y": py, "radiusX": 2, "radiusY": 2, "force": 1}]
        cdp.send("Input.dispatchTouchEvent", {"type": kind, "touchPoints": points})

    touch("touchStart", x, y)
    for k in range(1, 9):
        touch("touchMove", x - 3.0 * k, y + 4.0 * k)
    touch("touchEnd", x - 24.0, y + 32.0)
    target = root.evaluate("(el, xy) => el.__splinecraft.dataOf(xy[0], xy[1])", [x - 24.0, y + 32.0])
    after = wait_drag_released(lab, 1)
    assert math.dist(after[1], target) < 0.5 and math.dist(after[1], before[1]) > 1.0
    wait_curve_change(page, old_d)


EXPLORER_CELL = """\
import numpy as np
import splinecraft as sc
yy, xx = np.mgrid[0:48, 0:48] + 0.5
block = ((xx > 6) & (xx < 42) & (yy > 6) & (yy < 24)) | ((xx > 6) & (xx < 22) & (yy > 6) & (yy < 42))
mask = block & ~((xx - 14.0) ** 2 + (yy - 15.0) ** 2 < 16.0)
explorer = sc.TraceExplorer(mask, epsilon=0.5, method="random", seed=1, width=480, height=400, play_interval_ms=100)
explorer
"""
EXPLORER = "[data-testid=trace-explorer][data-ready='1']"


def test_trace_explorer_steps_back_and_forward(lab):
    pytest.importorskip("splinecraft.capture.fitting", exc_type=ImportError)
    page = lab.open_notebook([EXPLORER_CELL])
    root = page.wait_for_selector(EXPLORER, timeout=60_000)
    n = lab.python_json("explorer.n_snapshots")
    assert n >= 3 and root.get_attribute("data-n-snapshots") == str(n)
    assert root.get_attribute("data-snapshot-index") == str(n - 1)
    last_d = root.query_selector("[data-testid=snapshot-curve]").get_attribute("d")
    root.query_selector("[data-testid=step-back]").click()
    page.wait_for_selector(f"{EXPLORER}[data-snapshot-index='{n - 2}']", timeout=20_000)
    assert wait_python(lab, "explorer.snapshot_index", lambda i: i == n - 2) == n - 2
    root.query_selector("[data-testid=first]").click()
    page.wait_for_selector(f"{EXPLORER}[data-snapshot-index='0']", timeout=20_000)
    page.wait_for_function(
        "(old) => document.querySelector('[data-testid=trace-explorer] [data-testid=snapshot-curve]')"
        ".getAttribute('d') !== old", arg=last_d, timeout=20_000)
    # the page draws the cached snapshot at once; the kernel's iteration_info follows its snapshot_index
    assert wait_python(lab, "explorer.snapshot_index", lambda i: i == 0) == 0
    knots0 = lab.python_json("explorer.result.snapshots[0].knots")
    assert wait_python(lab, "explorer.iteration_info['knots']", lambda k: k == knots0) == knots0
    root.query_selector("[data-testid=step-forward]").click()
    page.wait_for_selector(f"{EXPLORER}[data-snapshot-index='1']", timeout=20_000)
    assert "iteration 1 /" in root.query_selector("[data-testid=iteration]").inner_text()
    # keyboard: End jumps to the final fit, whose drawing is the result again
    root.focus()
    page.keyboard.press("End")
    page.wait_for_selector(f"{EXPLORER}[data-snapshot-index='{n - 1}']", timeout=20_000)
    page.wait_for_function(
        "(d) => document.querySelector('[data-testid=trace-explorer] [data-testid=snapshot-curve]')"
        ".getAttribute('d') === d", arg=last_d, timeout=20_000)
    # play from the start runs to the end and stops
    root.query_selector("[data-testid=first]").click()
    page.wait_for_selector(f"{EXPLORER}[data-snapshot-index='0']", timeout=20_000)
    root.query_selector("[data-testid=play]").click()
    page.wait_for_selector(f"{EXPLORER}[data-snapshot-index='{n - 1}'][data-playing='0']", timeout=60_000)
    assert "Total number of points on contour" in root.query_selector("[data-testid=stats]").inner_text()
    # another knot-insertion algorithm from the dropdown: the kernel re-traces
    root.query_selector("[data-testid=knot-method]").select_option("fuzzy")
    assert wait_python(lab, "explorer.result.params['method']", lambda m: m == "fuzzy") == "fuzzy"
    n_fuzzy = lab.python_json("explorer.n_snapshots")
    page.wait_for_selector(f"{EXPLORER}[data-n-snapshots='{n_fuzzy}'][data-snapshot-index='{n_fuzzy - 1}']",
                           timeout=20_000)


def test_trace_explorer_traces_an_image_uploaded_from_the_page(lab):
    """The page's file input sends the file's bytes as the message's buffer (anywidget's send(content,
    callbacks, buffers)): a PNG is traced at its size, and a file that is no image is refused by its name."""
    import io

    import numpy as np
    from PIL import Image

    pixels = np.full((60, 80), 255, np.uint8)
    pixels[10:50, 10:40] = 0
    encoded = io.BytesIO()
    Image.fromarray(pixels).save(encoded, format="PNG")
    page = lab.open_notebook([EXPLORER_CELL])
    root = page.wait_for_selector(EXPLORER, timeout=60_000)
    root.query_selector("[data-testid=upload]").set_input_files(
        files=[{"name": "block.png", "mimeType": "image/png", "buffer": encoded.getvalue()}])
    assert wait_python(lab, "explorer.image_size", lambda size: size == [80, 60]) == [80, 60]
    curve = lab.python_json("(lambda s: s(np.linspace(*s.domain, 400)).tolist())(explorer.result.splines[0])")
    assert np.allclose(np.min(curve, axis=0), [10, 10], atol=1.0) and np.allclose(np.max(curve, axis=0), [40, 50], atol=1.0)
    root.query_selector("[data-testid=upload]").set_input_files(
        files=[{"name": "notes.txt", "mimeType": "text/plain", "buffer": b"not an image"}])
    level, message = wait_python(lab, "[explorer.status_level, explorer.status_message]",
                                 lambda status: "notes.txt" in status[1])
    assert level == "error" and lab.python_json("explorer.image_size") == [80, 60]


def test_editing_keys_wait_while_a_point_is_dragged(lab):
    """Delete during a drag would hand the drag's next moves (which name the point by index) to the next point."""
    page, root = open_editor(lab)
    before = lab.python_json("editor.points")
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(2)")
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 6):
        page.mouse.move(x + 5 * k, y + 5 * k)
        page.wait_for_timeout(30)
    page.keyboard.press("Delete")
    for k in range(6, 12):
        page.mouse.move(x + 5 * k, y + 5 * k)
        page.wait_for_timeout(30)
    target = root.evaluate("(el, xy) => el.__splinecraft.dataOf(xy[0], xy[1])", [x + 55, y + 55])
    page.mouse.up()
    after = wait_drag_released(lab, 2)
    assert len(after) == len(before) and math.dist(after[2], target) < 0.5
    assert after[:2] == before[:2] and after[3:] == before[3:]


def test_a_number_box_refuses_a_value_that_is_no_finite_number(lab):
    """1e999 (which the number box reads as no number) and an empty box used to arrive as null, which t reads as
    "slider off": they are refused with a message and t keeps its value."""
    page, root = open_editor(lab)
    root.query_selector("[data-testid=t-on]").check()
    t = wait_python(lab, "editor.t", lambda value: value is not None)
    box = root.query_selector("[data-testid=t-number]")
    for typed, words in (("1e999", "is not a number"), ("-1e999", "is not a number"), ("", "is not a number")):
        box.fill(typed)
        box.press("Enter")
        status = wait_python(lab, "[editor.status_level, editor.status_message]", lambda s: words in s[1])
        assert status[0] == "error" and lab.python_json("editor.t") == t
        assert root.query_selector("[data-testid=t-on]").is_checked()


def test_a_released_point_is_grabbed_where_it_is_drawn_before_the_kernel_answers(lab):
    page, root = open_editor(lab)
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(2)")
    view = lab.python_json("editor.view")
    page.evaluate("() => window.jupyterapp.shell.currentWidget.sessionContext.session.kernel"
                  ".requestExecute({code: 'import time; time.sleep(2)'})")  # the kernel is busy for 2 s
    page.wait_for_timeout(200)
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 11):
        page.mouse.move(x + 6 * k, y)
        page.wait_for_timeout(15)
    page.mouse.up()
    page.wait_for_timeout(100)
    page.mouse.move(x + 60, y)  # where the page draws the point now, before the kernel has answered
    page.mouse.down()
    for k in range(1, 11):
        page.mouse.move(x + 60, y + 5 * k)
        page.wait_for_timeout(15)
    target = root.evaluate("(el, xy) => el.__splinecraft.dataOf(xy[0], xy[1])", [x + 60, y + 50])
    page.mouse.up()
    point = wait_python(lab, "editor.points[2]", lambda p: math.dist(p, target) < 0.5, timeout=30)
    assert math.dist(point, target) < 0.5 and lab.python_json("editor.view") == view  # grabbed, not panned


@pytest.mark.parametrize("cell, selector, window", [(EDITOR_CELL, EDITOR, 560), (EXPLORER_CELL, EXPLORER, 640)])
def test_every_control_stays_reachable_in_a_narrow_cell(lab, cell, selector, window):
    """A canvas wider than the cell used to clip the side panel (overflow hidden): the panel now wraps below
    the canvas and a canvas wider than the cell scrolls."""
    lab.page.set_viewport_size({"width": window, "height": 1000})
    page = lab.open_notebook([cell])
    page.evaluate("() => window.jupyterapp.shell.collapseLeft()")
    root = page.wait_for_selector(selector, timeout=60_000)
    page.wait_for_timeout(1500)
    # each control: in the widget's width without scrolling it sideways, and the element at its centre once the
    # notebook has scrolled it into view vertically
    unreachable = root.evaluate("""(root) => {
        const out = [];
        for (const el of root.querySelectorAll('input, select, button')) {
          const r = el.getBoundingClientRect();
          if (!r.width || !r.height) continue;
          el.scrollIntoView({block: 'center', inline: 'nearest'});
          root.scrollLeft = 0;
          const box = root.getBoundingClientRect(), b = el.getBoundingClientRect();
          const cx = b.left + b.width / 2, cy = b.top + b.height / 2, hit = document.elementFromPoint(cx, cy);
          if (cx < box.left || cx > box.right || !(hit && (hit === el || el.contains(hit) || hit.contains(el))))
            out.push(el.dataset.testid || el.tagName);
        }
        return out;
      }""")
    assert unreachable == []
