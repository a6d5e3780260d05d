"""The editors' teaching aids, kernel side: comb scale, t slider with its construction, κ(t) figure, export,
labels and status texts (issue 12). Reference values from the engine's own queries and closed forms."""
from __future__ import annotations

import io
import warnings

import numpy as np
import pytest

import splinecraft as sc
from splinecraft.widgets import SplineEditor, SplineEditorWarning
from splinecraft.widgets._editor_drawing import COMB_REFERENCE

POINTS = [[60.0, 300.0], [160.0, 120.0], [300.0, 80.0], [440.0, 160.0], [540.0, 320.0]]


def buffer(value, shape=(-1, 2)):
    return np.frombuffer(value, dtype="<f4").reshape(shape) if value else np.zeros((0, 2), dtype="<f4")


def test_comb_is_scaled_like_the_static_figures_and_capped():
    """90th-percentile tooth = 12% of the curve's size; no tooth longer than COMB_CAP times that (§7)."""
    from splinecraft.plot._layers import COMB_CAP

    heart = sc.datasets.sample_points("heart") * 100.0
    editor = SplineEditor(heart, closed=True, show_comb=True)
    teeth = buffer(editor.geometry["comb_teeth"], (-1, 2, 2))
    lengths = np.hypot(*(teeth[:, 1] - teeth[:, 0]).T)
    bases, _tips = editor.spline.curvature_comb(scale=1.0, samples_per_segment=33)
    size = float(np.ptp(bases, axis=0).max())
    assert lengths.max() <= COMB_CAP * COMB_REFERENCE * size * (1 + 1e-4)
    assert np.percentile(lengths, 90) == pytest.approx(COMB_REFERENCE * size, rel=0.05)
    editor.comb_scale = 2.0  # the user's comb size scales every tooth, the cap too
    doubled = buffer(editor.geometry["comb_teeth"], (-1, 2, 2))
    np.testing.assert_allclose(np.hypot(*(doubled[:, 1] - doubled[:, 0]).T), 2 * lengths, rtol=1e-3, atol=1e-3)
    editor.fit_view()
    x0, y0, x1, y1 = editor.view  # the fitted view holds the longest tooth
    tips = doubled[:, 1]
    assert (tips[:, 0] >= x0).all() and (tips[:, 0] <= x1).all() and (tips[:, 1] >= y0).all() and (tips[:, 1] <= y1).all()


def test_t_slider_draws_the_de_casteljau_construction_of_its_piece():
    editor = SplineEditor(POINTS, form="basis", show_bezier_points=True)
    assert editor.t is None and "construction" not in editor.geometry
    t0, t1 = editor.geometry["domain"]
    assert (t0, t1) == (editor.spline.knots[0], editor.spline.knots[-1])
    editor.t = t0 + 0.6 * (t1 - t0)
    built = editor.spline.construction(editor.t)
    np.testing.assert_allclose(buffer(editor.geometry["t_point"])[0], editor.spline(editor.t), atol=1e-3)
    levels = buffer(editor.geometry["construction"])
    np.testing.assert_allclose(levels[:4], built.levels[0], atol=1e-3)  # the Bézier polygon of that piece
    assert np.isnan(levels[4]).all()
    # each inner level interpolates the one before at theta (de Casteljau)
    theta = editor.geometry["t_info"]["theta"]
    np.testing.assert_allclose(levels[5:8], (1 - theta) * built.levels[0][:-1] + theta * built.levels[0][1:], atol=1e-3)
    np.testing.assert_allclose(buffer(editor.geometry["construction_class"]), built.class_polygon, atol=1e-3)
    with pytest.warns(SplineEditorWarning, match="outside the curve's parameters"):
        editor.t = t1 + 1e6
    kept = editor.t
    with pytest.warns(SplineEditorWarning, match="t = nan is not a number"):
        editor.t = float("nan")
    assert editor.t == kept
    editor.points = [[0.0, 0.0], [10.0, 0.0], [20.0, 5.0], [30.0, 0.0]]  # a shorter curve: t moves into it
    assert editor.spline.knots[0] <= editor.t <= editor.spline.knots[-1]
    editor.t = None
    assert "t_point" not in editor.geometry


def test_curvature_figure_shows_the_jumps_live():
    """E2: unequal neighbouring interval weights make kappa jump at the joint."""
    pytest.importorskip("bqplot")
    editor = SplineEditor(POINTS)
    figure = editor.curvature_figure
    assert "jump" not in figure.title or "0 of" in figure.title
    editor.interval_weights = [1.0, 4.0, 1.0, 1.0]
    assert "2 of 3 joints jump" in figure.title


def test_to_png_draws_the_curve():
    from PIL import Image

    editor = SplineEditor(POINTS)
    image = Image.open(io.BytesIO(editor.to_png(width=300))).convert("RGB")
    assert image.width == 300
    pixels = np.asarray(image).astype(int)
    blue = (pixels[..., 2] > 150) & (pixels[..., 0] < 120)
    assert blue.sum() > 300  # a line of some hundred pixels
    # the curve passes through its data points: the pixel of the middle point is on it
    x0, y0 = np.min(editor.spline.bezier().reshape(-1, 2), axis=0)
    x1, y1 = np.max(editor.spline.bezier().reshape(-1, 2), axis=0)
    pad = 0.05 * max(x1 - x0, y1 - y0)
    scale = min(300 / (x1 - x0 + 2 * pad), image.height / (y1 - y0 + 2 * pad))
    px = (300 - scale * (x1 - x0 + 2 * pad)) / 2 + scale * (POINTS[2][0] - x0 + pad)
    py = (image.height - scale * (y1 - y0 + 2 * pad)) / 2 + scale * (POINTS[2][1] - y0 + pad)
    window = blue[int(py) - 3:int(py) + 4, int(px) - 3:int(px) + 4]
    assert window.any()


def test_explanation_is_plain_text_and_status_names_the_global_value():
    editor = SplineEditor(POINTS)
    assert "<" not in editor.explanation and "&gt;" not in editor.explanation and "E1" in editor.explanation
    assert "ν > −2" in editor.explanation  # entities and tags become plain characters
    editor.selected = 3
    editor.point_tension = [2.0] * 5  # the global v slider
    assert editor.status_message == "v = 2 at every point."
    editor.selected_interval = 1
    editor.interval_weights = [1.0, 3.0, 1.0, 1.0]  # one interval's slider
    assert editor.status_message.startswith("ω[1] = 3.")


def test_segment_form_refits_the_view():
    editor = SplineEditor([[0.0, 0.0], [1000.0, 0.0], [2000.0, 800.0], [3000.0, 0.0], [4000.0, 500.0]])
    editor.form = "segment"
    x0, y0, x1, y1 = editor.view
    first = editor.spline.bezier().reshape(-1, 2)
    assert x0 <= first[:, 0].min() and x1 >= first[:, 0].max()
    assert (x1 - x0) < 0.8 * 4000  # fitted to the one segment, not the old five points


def test_timmer_labels_have_no_raw_underscores_or_unused_beta():
    options = SplineEditor(form="timmer_g2").options["uses"]
    assert options["timmer_g2"]["beta_label"] is None
    for form, uses in options.items():
        for key in ("alpha_label", "beta_label"):
            assert uses[key] is None or ("_" not in uses[key] and len(uses[key]) <= 9), (form, uses[key])


def test_explorer_png_and_display_switches():
    from PIL import Image

    from splinecraft.widgets import TraceExplorer

    explorer = TraceExplorer(epsilon=2.0, show_knots=False, large=True)
    assert explorer.show_knots is False and explorer.large is True
    image = Image.open(io.BytesIO(explorer.to_png(width=200)))
    assert image.size == (200, 200)
    grey = np.asarray(image.convert("L"))
    assert (grey < 240).mean() > 0.2  # the bitmap is drawn under the outline


def test_explorer_image_controls_threshold_invert_despeckle():
    from splinecraft.capture import load_bitmap
    from splinecraft.widgets import TraceExplorer

    gray = np.full((60, 60), 230, dtype=np.uint8)
    gray[:, 30:] = 150  # uneven paper: the right half is darker
    gray[15:45, 10:25] = 20  # a dark block
    gray[20:40, 38:52] = 60  # a block on the darker half
    gray[5, 5] = gray[55, 50] = 0  # two specks
    explorer = TraceExplorer(gray, epsilon=2.0, min_speck_area=0)
    np.testing.assert_array_equal(explorer.mask, load_bitmap(gray, threshold="otsu", min_speck_area=0))
    with_specks = len(explorer.result.boundaries)
    explorer.set_state({"despeckle": 4})
    assert len(explorer.result.boundaries) == with_specks - 2 and explorer.status_level == "info"
    explorer.set_state({"threshold": "local"})
    np.testing.assert_array_equal(explorer.mask, load_bitmap(gray, threshold="local", min_speck_area=4))
    before = explorer.mask.copy()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the bitmap's warning goes to the status line, not to a lost thread
        explorer.set_state({"invert": True})
    np.testing.assert_array_equal(explorer.mask, load_bitmap(gray, threshold="local", invert=True, min_speck_area=4))
    assert not np.array_equal(explorer.mask, before)
    # inverted, the paper is ink and touches every border: the status says so
    assert explorer.status_level == "warning" and "may be the traced shape" in explorer.status_message
    assert explorer.status_message.startswith("Bitmap made again (invert); Traced")
    result = explorer.result
    explorer.set_state({"threshold": "bogus"})
    assert explorer.threshold == "local" and explorer.result is result and explorer.status_level == "error"
    # "fixed" is the level given to the constructor; this explorer got none (the page does not offer it)
    explorer.set_state({"threshold": "fixed"})
    assert explorer.threshold == "local" and explorer.result is result and explorer.status_level == "error"
    assert "needs a level" in explorer.status_message
    fixed = TraceExplorer(gray, epsilon=2.0, min_speck_area=0, threshold=0.4)
    assert fixed.threshold == "fixed" and "fixed" in dict(map(tuple, fixed.options["thresholds"]))
    np.testing.assert_array_equal(fixed.mask, load_bitmap(gray, threshold=0.4, min_speck_area=0))
    fixed.set_state({"threshold": "otsu"})
    fixed.set_state({"threshold": "fixed"})
    assert fixed.status_level == "info"
    np.testing.assert_array_equal(fixed.mask, load_bitmap(gray, threshold=0.4, min_speck_area=0))
    assert explorer.options["image_is_mask"] is False
    assert TraceExplorer().options["image_is_mask"] is True  # the demo is a bool mask: no threshold control
    explorer.set_state({"invert": False})
    assert explorer.status_level == "info"


def test_explorer_shows_the_bitmaps_warning_and_passes_it_on():
    """A bitmap whose True pixels fill the border (ink may be inverted): the constructor warns its caller and
    the status line shows it; a clean bitmap gives an info status."""
    from splinecraft.widgets import TraceExplorer

    framed = ~np.pad(np.ones((10, 10), bool), 10)  # True everywhere but a square: the paper looks like ink
    with pytest.warns(UserWarning, match="background may be the traced shape: toggle invert"):
        explorer = TraceExplorer(framed)
    assert explorer.status_level == "warning" and "toggle invert" in explorer.status_message
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert explorer.load(~framed)
    assert explorer.status_level == "info" and "Warning" not in explorer.status_message
