"""Real-browser checks of the teaching aids (issue 12): export downloads, the t slider and its construction,
the coordinate readout, snap to grid, the presentation size and the canvas filling the cell."""
from __future__ import annotations

import math

import pytest

from test_widgets_browser import EXPLORER, EXPLORER_CELL, curve_d, open_editor, wait_python

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def test_editor_exports_t_slider_readout_and_large(lab, tmp_path):
    page, root = open_editor(lab)
    # the canvas fills the cell: wider than the 620 px asked for, in a 1400 px window
    assert float(root.query_selector("[data-testid=canvas]").get_attribute("width")) > 700
    assert root.query_selector("[data-testid=summary]").inner_text() == "5 points · 4 pieces"
    for button, suffix, magic in (("export-svg", ".svg", b"<?xml"), ("export-png", ".png", b"\x89PNG")):
        with page.expect_download() as download:
            root.query_selector(f"[data-testid={button}]").click()
        path = tmp_path / download.value.suggested_filename
        download.value.save_as(path)
        assert path.suffix == suffix and path.read_bytes().startswith(magic) and path.stat().st_size > 500
    assert "<path" in (tmp_path / "spline.svg").read_text()
    # the t slider: switching it on sets editor.t and draws P(t) with the construction of its piece
    root.query_selector("[data-testid=t-on]").check()
    t = wait_python(lab, "editor.t", lambda value: value is not None)
    page.wait_for_function("() => (document.querySelector('[data-testid=spline-editor] [data-testid=construction]')"
                           ".getAttribute('d') || '').length > 20", timeout=20_000)
    x, y = root.evaluate("(el, p) => el.__splinecraft.screenOf(p[0], p[1])", lab.python_json(f"editor.spline({t}).tolist()"))
    drawn = root.query_selector("[data-testid=t-point]").bounding_box()
    assert abs(drawn["x"] + drawn["width"] / 2 - x) < 2.0 and abs(drawn["y"] + drawn["height"] / 2 - y) < 2.0
    # the coordinate readout follows the pointer, in data units
    canvas = root.query_selector("[data-testid=canvas]").bounding_box()
    page.mouse.move(canvas["x"] + 100, canvas["y"] + 120)
    expected = root.evaluate("(el, xy) => el.__splinecraft.dataOf(xy[0], xy[1])", [canvas["x"] + 100, canvas["y"] + 120])
    assert root.query_selector("[data-testid=readout]").inner_text() == f"x {expected[0]:.1f} y {expected[1]:.1f}"
    # presentation size: a taller canvas
    height = float(root.query_selector("[data-testid=canvas]").get_attribute("height"))
    root.query_selector("[data-testid=large]").check()
    wait_python(lab, "editor.large", lambda value: value is True)
    page.wait_for_function(f"() => Number(document.querySelector('[data-testid=spline-editor] [data-testid=canvas]')"
                           f".getAttribute('height')) > {height * 1.2}", timeout=20_000)


def test_snap_to_grid_puts_dragged_points_on_grid_lines(lab):
    page, root = open_editor(lab)
    root.query_selector("[data-testid=snap]").check()
    wait_python(lab, "editor.snap", lambda value: value is True)
    step = root.evaluate("el => el.__splinecraft.gridStep()")
    x, y = root.evaluate("el => el.__splinecraft.screenPoint(2)")
    old_d = curve_d(root)
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 8):
        page.mouse.move(x + 5.3 * k, y + 3.1 * k)
    page.mouse.up()
    moved = wait_python(lab, "editor.points[2]", lambda p: p != [300.0, 80.0])
    assert all(abs(v / step - round(v / step)) < 1e-9 for v in moved), (moved, step)
    page.wait_for_function("(old) => document.querySelector('[data-testid=spline-editor] [data-testid=curve]')"
                           ".getAttribute('d') !== old", arg=old_d, timeout=20_000)


def test_explorer_exports_and_hides_knots(lab, tmp_path):
    pytest.importorskip("splinecraft.capture.fitting", exc_type=ImportError)
    page = lab.open_notebook([EXPLORER_CELL])
    root = page.wait_for_selector(EXPLORER, timeout=60_000)
    with page.expect_download() as download:
        root.query_selector("[data-testid=export-png]").click()
    path = tmp_path / download.value.suggested_filename
    download.value.save_as(path)
    assert path.name == "trace.png" and path.read_bytes().startswith(b"\x89PNG")
    assert root.query_selector("[data-testid=knots]").get_attribute("d")
    root.query_selector("[data-testid=show_knots]").uncheck()
    wait_python(lab, "explorer.show_knots", lambda value: value is False)
    page.wait_for_function("() => !document.querySelector('[data-testid=trace-explorer] [data-testid=knots]')"
                           ".getAttribute('d')", timeout=20_000)
    assert math.isfinite(lab.python_json("explorer.result.stats['max_error']"))


GRAY_CELL = """\
import numpy as np
import splinecraft as sc
gray = np.full((60, 60), 230, dtype=np.uint8)
gray[15:45, 10:25] = 20
gray[20:40, 38:52] = 60
explorer = sc.TraceExplorer(gray, epsilon=2.0, width=420, height=360)
explorer
"""


def test_explorer_image_controls(lab):
    pytest.importorskip("splinecraft.capture.fitting", exc_type=ImportError)
    page = lab.open_notebook([GRAY_CELL])
    root = page.wait_for_selector(EXPLORER, timeout=60_000)
    image = root.query_selector("[data-testid=bitmap]").get_attribute("href")
    root.query_selector("[data-testid=invert]").check()
    assert wait_python(lab, "explorer.invert", lambda value: value is True) is True
    page.wait_for_function("(old) => document.querySelector('[data-testid=trace-explorer] [data-testid=bitmap]')"
                           ".getAttribute('href') !== old", arg=image, timeout=20_000)
    root.query_selector("[data-testid=threshold]").select_option("local")
    assert wait_python(lab, "explorer.threshold", lambda value: value == "local") == "local"
    # inverted, the paper is the ink and touches every border: the page says the ink may be inverted
    assert lab.python_json("explorer.status_level") == "warning"
    page.wait_for_selector("[data-testid=trace-explorer] [data-testid=status].sc-status-warning", timeout=20_000)
    assert "may be the traced shape" in root.query_selector("[data-testid=status]").inner_text()
