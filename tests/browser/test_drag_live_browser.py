"""Real-browser tests of the SplineEditor's drag path: the live canvas and the geometry deltas.

While a point is dragged the page paints the drawing on one canvas over the SVG (the SVG's path layers keep
the path data but are not displayed) and the kernel sends only the changed Bézier rows; the page must hold
the kernel's curve byte for byte all the same, in every view of the editor, and show the SVG again on release.
"""
from __future__ import annotations

import pytest

from test_widgets_browser import wait_layout_settled

pytestmark = [pytest.mark.browser, pytest.mark.slow]

SPIRAL_CELL = """\
import numpy as np
import splinecraft as sc
theta = np.linspace(0.0, 6.0 * np.pi, 300)
radius = 40.0 + 260.0 * np.linspace(0.0, 1.0, 300)
editor = sc.SplineEditor(np.c_[400 + radius * np.cos(theta), 320 + radius * np.sin(theta)], width=620, height=440)
editor
"""
SECOND_VIEW_CELL = "editor"
EDITORS = "[data-testid=spline-editor][data-ready='1']"
LIVE = "(el) => el.querySelector('[data-testid=live-canvas]').style.display === 'block'"
PAINTED = """(el) => {
  const canvas = el.querySelector('[data-testid=live-canvas]');
  const pixels = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
  let count = 0;
  for (let i = 3; i < pixels.length; i += 4) if (pixels[i]) count++;
  return count;
}"""


def kernel_geometry(lab):
    return lab.python_json("{'revision': editor.geometry['revision'], "
                           "'bezier': np.frombuffer(editor.geometry['bezier'], '<f4').tolist(), "
                           "'knots': np.frombuffer(editor.geometry['knots'], '<f4').tolist()}")


def assert_views_hold_kernel_geometry(lab, views, timeout: float = 20.0):
    """Once the kernel's last answer has reached every view (same revision), each holds its curve exactly."""
    import time

    deadline = time.monotonic() + timeout
    while True:
        wanted = kernel_geometry(lab)  # the kernel may still be working through the last moves: poll
        held = [view.evaluate("(el) => el.__splinecraft.geometry()") for view in views]
        if all(h["revision"] == wanted["revision"] for h in held):
            break
        assert time.monotonic() < deadline, ([h["revision"] for h in held], wanted["revision"])
        lab.page.wait_for_timeout(100)
    for h in held:
        assert h["bezier"] == wanted["bezier"] and h["knots"] == wanted["knots"]


def test_drag_paints_live_and_every_view_holds_the_kernel_curve(lab):
    page = lab.open_notebook([SPIRAL_CELL, SECOND_VIEW_CELL])
    page.evaluate("() => window.jupyterapp.shell.collapseLeft()")
    page.wait_for_function(f"() => document.querySelectorAll(\"{EDITORS}\").length === 2", timeout=60_000)
    first, second = page.query_selector_all(EDITORS)
    first.scroll_into_view_if_needed()
    wait_layout_settled(page, first)
    x, y = first.evaluate("el => el.__splinecraft.screenPoint(150)")
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 8):
        page.mouse.move(x + 3.0 * k, y - 2.0 * k)
    # live: the canvas is shown and painted, the SVG's layers are hidden, the labels sit above the canvas
    page.wait_for_function(LIVE, arg=first, timeout=20_000)
    assert first.evaluate("el => el.querySelector('[data-testid=curve]').style.display") == "none"
    assert first.evaluate(PAINTED) > 1000
    assert first.evaluate("el => el.querySelector('[data-testid=canvas] .sc-labels') === null")
    # mid-drag, the moves' deltas applied: both views hold the kernel's float32 curve and knots exactly
    assert_views_hold_kernel_geometry(lab, (first, second))
    page.mouse.up()
    page.wait_for_function(f"(el) => !({LIVE})(el) && el.querySelector('[data-testid=curve]').style.display === ''",
                           arg=first, timeout=20_000)
    assert first.evaluate("el => el.querySelector('[data-testid=canvas] .sc-labels') !== null")
    assert not second.evaluate(LIVE)  # the other view never went live
    assert_views_hold_kernel_geometry(lab, (first, second))
    # the page's points are the kernel's again (they wait for the release during a drag)
    moved = lab.python_json("editor.points[150]")
    drawn = first.evaluate("(el, p) => el.__splinecraft.screenOf(p[0], p[1])", moved)
    assert drawn == pytest.approx(first.evaluate("el => el.__splinecraft.screenPoint(150)"))
    assert second.evaluate("(el) => el.__splinecraft.pagePoint(150)") == pytest.approx(moved)


LIVE_PIXELS = """(el) => {
  const live = el.__splinecraft.live, canvas = el.querySelector('[data-testid=live-canvas]');
  const pixels = () => canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
  const updates = live.updates;
  live.cached = true;  // paint now, from the marker rasters as the drag has kept them
  const kept = pixels();
  live.cached = false;  // every layer as one whole path
  const whole = pixels();
  live.cached = true;  // rasters painted afresh, every tile
  const fresh = pixels();
  let keptVsFresh = 0, differing = 0, large = 0, inked = 0, largest = 0;
  for (let i = 0; i < whole.length; i++) {
    if (kept[i] !== fresh[i]) keptVsFresh++;
    const d = Math.abs(whole[i] - kept[i]);
    if (d) differing++;
    if (d > 96) large++;
    largest = Math.max(largest, d);
    if (i % 4 === 3 && whole[i]) inked++;
  }
  return { updates, keptVsFresh, differing, large, largest, inked };
}"""


def test_marker_rasters_repaint_only_what_moved_and_look_like_whole_paths(lab):
    """Through a drag the point and knot layers keep their rasters and repaint only the tiles where markers
    moved: the raster is then exactly a fresh one, and the canvas looks like the whole paths' canvas (edge
    pixels differ by the anti-aliasing of smaller paths, no marker is missing or left behind)."""
    page = lab.open_notebook([SPIRAL_CELL])
    root = page.wait_for_selector(EDITORS, timeout=60_000)
    root.scroll_into_view_if_needed()
    wait_layout_settled(page, root)
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(150)")
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 13):  # steps of 20 px: the point leaves its tiles (64 device px) now and then
        page.mouse.move(x + 20.0 * (k % 6), y + (5.0 if k % 2 else -5.0) + 4.0 * k)
        page.wait_for_timeout(30)
    page.wait_for_function(LIVE, arg=root, timeout=20_000)
    assert_views_hold_kernel_geometry(lab, (root,))
    page.wait_for_timeout(100)  # the last answer's frame is painted
    seen = root.evaluate(LIVE_PIXELS)
    page.mouse.up()
    print(seen)
    assert seen["updates"]["whole"] >= 2 and seen["updates"]["moved"] >= 4, seen["updates"]
    assert seen["keptVsFresh"] == 0, seen
    assert seen["inked"] > 5000
    assert seen["large"] == 0 and seen["differing"] < 0.25 * 4 * seen["inked"], seen
