"""Kernel-side logic of the widgets, without a browser.

The page is simulated the way ipywidgets delivers it: trait updates through ``set_state`` (what a slider or
dropdown sends) and custom messages through the widget's message handler (drags, double-clicks,
right-clicks, buttons). Reference values come from independent engine calls, closed forms (spec E1, E2) and
the geometry the widget must reproduce -- never from the widget's own earlier output.
"""
from __future__ import annotations

import math
import re
import shutil
import subprocess
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import splinecraft as sc
from splinecraft.widgets import SplineEditor, SplineEditorWarning
from splinecraft.widgets._assets import load_css, load_esm, static_dir
from splinecraft.widgets._forms import FORMS

SETTINGS = settings(max_examples=50, deadline=None)
POINTS = [[60.0, 300.0], [160.0, 120.0], [300.0, 80.0], [440.0, 160.0], [540.0, 320.0]]


def buffer(value, shape=(-1, 2)):
    return np.frombuffer(value, dtype="<f4").reshape(shape) if value else np.zeros((0, 2), dtype="<f4")


def page_message(widget, content, buffers=None):
    """Deliver a custom message as if it came from the page."""
    widget._handle_message(widget, content, buffers or [])


def drag(editor, index, xy, *, seq, gesture, final=False):
    page_message(editor, {"type": "drag", "index": index, "x": float(xy[0]), "y": float(xy[1]), "seq": seq,
                          "gesture": gesture, "final": final})


def sent_messages(widget):
    """Capture the custom messages the kernel sends to the page."""
    messages = []
    widget.send = lambda content, buffers=None: messages.append(content)
    return messages


# ---------------------------------------------------------------------------------------------- assets
def test_esm_inlines_the_shared_module_once():
    for name in ("spline_editor.js", "trace_explorer.js"):
        source = load_esm(name)
        assert "./common.js" not in source and 'from "./' not in source
        assert source.count("function bezierPath(") == 1
        assert "export default { render }" in source
        assert re.findall(r"^export\b.*$", source, re.MULTILINE) == ["export default { render };"]
    assert ".sc-widget" in load_css()
    assert (static_dir() / "common.js").is_file()


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_inlined_modules_are_valid_javascript(tmp_path):
    for name in ("spline_editor.js", "trace_explorer.js"):
        target = tmp_path / name.replace(".js", ".mjs")
        target.write_text(load_esm(name), encoding="utf-8")
        run = subprocess.run(["node", "--check", str(target)], capture_output=True, text=True, timeout=60)
        assert run.returncode == 0, run.stderr


# ---------------------------------------------------------------------------------------------- curve buffers
def test_geometry_buffers_are_the_engine_curve():
    editor = SplineEditor(POINTS)
    reference = sc.interpolate(np.array(POINTS), knots="chord", end_condition="natural")
    geometry = editor.geometry
    np.testing.assert_allclose(buffer(geometry["bezier"], (-1, 4, 2)), reference.bezier(), rtol=1e-6, atol=1e-4)
    np.testing.assert_allclose(buffer(geometry["knots"]), reference.knot_points, atol=1e-4)
    assert geometry["closed"] is False
    np.testing.assert_allclose(editor.spline.bezier(), reference.bezier(), atol=1e-12)


@pytest.mark.parametrize("form", list(FORMS))
def test_every_form_builds_and_draws(form):
    editor = SplineEditor(form=form)
    assert editor.status_level == "info"
    drawn = buffer(editor.geometry["bezier"], (-1, 4, 2))
    np.testing.assert_allclose(drawn, editor.spline.bezier(), atol=1e-3)
    assert editor.explanation_html.startswith("<p>")
    assert "<" not in editor.explanation and editor.explanation.strip() and "&gt;" not in editor.explanation


def test_setting_points_from_code_recomputes_and_refits_the_view():
    editor = SplineEditor(POINTS)
    revision = editor.geometry["revision"]
    new = (np.array(POINTS) * 2.0 + 1000.0).tolist()
    editor.points = new
    assert editor.geometry["revision"] > revision
    reference = sc.interpolate(np.array(new), knots="chord")
    np.testing.assert_allclose(buffer(editor.geometry["bezier"], (-1, 4, 2)), reference.bezier(), atol=1e-2)
    x0, y0, x1, y1 = editor.view
    assert x0 < 1120 and x1 > 2080 and y0 < 1160 and y1 > 1640


def test_numpy_points_are_accepted_and_lists_resize():
    editor = SplineEditor(np.array(POINTS), point_tension=2.0)
    assert editor.point_tension == [2.0] * 5 and len(editor.interval_weights) == 4
    editor.points = np.array(POINTS + [[600.0, 200.0]])
    assert editor.point_tension == [2.0] * 6 and len(editor.interval_weights) == 5
    editor.closed = True
    assert len(editor.interval_weights) == 6 and editor.spline.closed


def test_interval_weight_changes_curve_and_comb_shows_the_jump():
    """E2: kappa(t_i^+) / kappa(t_i^-) = omega_{i-1} / omega_i at joint i (§2.2)."""
    editor = SplineEditor(POINTS, show_comb=True)
    assert editor.geometry["labels"] == []  # equal weights: G2, no jump labels
    editor.interval_weights = [1.0, 4.0, 1.0, 1.0]
    ratios = {round(label["x"], 6): label["text"] for label in editor.geometry["labels"] if label["kind"] == "joint"}
    assert ratios[round(POINTS[1][0], 6)] == "κ⁺/κ⁻ = 0.25"  # joint 1: omega_0 / omega_1 = 1/4
    assert ratios[round(POINTS[2][0], 6)] == "κ⁺/κ⁻ = 4.00"  # joint 2: omega_1 / omega_2 = 4
    teeth = buffer(editor.geometry["comb_teeth"], (-1, 2, 2))
    m = editor.spline.n_segments
    assert len(teeth) % m == 0 and len(teeth) // m >= 6  # every piece sampled with both end points
    samples = len(teeth) // m
    # both one-sided teeth at joint 1: end of piece 0 and start of piece 1 share the base, differ in length
    end_of_0, start_of_1 = teeth[samples - 1], teeth[samples]
    np.testing.assert_allclose(end_of_0[0], start_of_1[0], atol=1e-3)
    length = lambda tooth: float(np.hypot(*(tooth[1] - tooth[0])))  # noqa: E731
    assert length(start_of_1) / length(end_of_0) == pytest.approx(0.25, rel=1e-3)


def test_class_preset_moves_v_w_but_not_the_interpolant():
    """E1: alpha, beta cancel in the interpolant; only V, W change (V_i = F_i + h_i M_i / alpha_i)."""
    editor = SplineEditor(POINTS, show_bezier_points=True)
    before = editor.spline.bezier()
    vw_ball = buffer(editor.geometry["vw"], (-1, 2, 2))
    editor.preset = "timmer"
    assert (editor.alpha, editor.beta) == (4.0, 4.0)
    np.testing.assert_array_equal(editor.spline.bezier(), before)
    vw_timmer = buffer(editor.geometry["vw"], (-1, 2, 2))
    F = before[:, 0]
    # V - F scales with 1/alpha: (V_timmer - F) = (2/4) (V_ball - F)
    np.testing.assert_allclose(vw_timmer[:, 0] - F, 0.5 * (vw_ball[:, 0] - F), atol=2e-3)
    assert "did not move" in editor.status_message and "E1" in editor.status_message
    editor.alpha = 2.5
    assert editor.preset == "free"


def test_segment_mode_alpha_reshapes_the_curve():
    """§1: with V, W fixed, b1 = F0 + alpha/3 (V - F0), b2 = F1 + beta/3 (W - F1)."""
    editor = SplineEditor(form="segment")
    F0, V, W, F1 = np.array(editor.points)
    editor.alpha, editor.beta = 1.5, 4.5
    b = editor.spline.bezier()[0]
    np.testing.assert_allclose(b[1], F0 + 0.5 * (V - F0), atol=1e-9)
    np.testing.assert_allclose(b[2], F1 + 1.5 * (W - F1), atol=1e-9)
    assert [label["text"] for label in editor.geometry["labels"]] == ["F₀", "V", "W", "F₁"]


def test_switching_to_segment_mode_takes_the_first_piece_and_back_restores():
    editor = SplineEditor(POINTS)
    first_piece = editor.spline.bezier()[0]
    editor.form = "segment"
    # same class (Ball), so the segment is exactly the interpolant's first piece
    np.testing.assert_allclose(editor.spline.bezier()[0], first_piece, atol=1e-9)
    editor.form = "interpolant"
    assert editor.points == POINTS


def test_basis_form_relative_tension_scale():
    """nu_j = -2 is the edge of the safe domain: v_j = nu_j (c_{j-1} + c_j) with c_i = omega_i / h_i (§2.5, §4.5).

    Floating ends extend the legs (h_{-1} = h_0, h_n = h_{n-1}, E12), so the end points count their leg twice.
    """
    editor = SplineEditor(POINTS, form="basis", knots="chord")
    legs = np.hypot(*np.diff(np.array(POINTS), axis=0).T)
    c = np.concatenate([[1.0 / legs[0]], 1.0 / legs, [1.0 / legs[-1]]])
    spans = c[:-1] + c[1:]
    reference = sc.basis_spline(np.array(POINTS), knots="chord", point_tension=spans * 3.0)
    editor.point_tension = [3.0] * 5
    np.testing.assert_allclose(editor.spline.bezier(), reference.bezier(), atol=1e-9)
    with pytest.warns(SplineEditorWarning, match="must be > -2"):
        editor.point_tension = [3.0, -2.5, 3.0, 3.0, 3.0]
    assert editor.point_tension == [3.0] * 5
    editor.point_tension = 4.0            # a single number is broadcast, as in the constructor
    assert editor.point_tension == [4.0] * 5
    with pytest.warns(SplineEditorWarning, match="must be > -2.*kept the last good curve"):
        editor.point_tension = -2.5       # and a bad one is refused like a bad list
    assert editor.point_tension == [4.0] * 5
    editor.interval_weights = np.float64(2.0)
    assert editor.interval_weights == [2.0] * 4


# ---------------------------------------------------------------------------------------------- bad values
@pytest.mark.parametrize(
    "name, value, reason",
    [
        ("points", [[60, 300], [float("nan"), 1], [300, 80], [440, 160], [540, 320]], "not a finite number"),
        ("points", [[60, 300], [60, 300], [300, 80], [440, 160], [540, 320]], "coincide"),
        ("interval_weights", [1.0, -1.0, 1.0, 1.0], "must be > 0"),
        ("interval_weights", [1.0, float("inf"), 1.0, 1.0], "must be finite"),
        ("interval_weights", [1.0, 1e7, 1.0, 1.0], "out of range"),
        ("interval_weights", [1.0, 1.0, 1.0], "4 values are needed"),
        ("alpha", float("nan"), "alpha must be a finite number"),
        ("alpha", 0.0, "out of range"),
        ("point_tension", [0.0, float("nan"), 0.0, 0.0, 0.0], "must be finite"),
        ("end_condition", "bogus", "does not apply"),
        ("form", "spiral", "unknown form"),
        ("comb_scale", -1.0, "comb size"),
        ("selected", 99, "no point 99"),
    ],
)
def test_bad_values_from_code_revert_with_message(name, value, reason):
    editor = SplineEditor(POINTS)
    before = editor.spline.bezier()
    old = getattr(editor, name)
    with pytest.warns(SplineEditorWarning, match=re.escape(reason)):
        setattr(editor, name, value)
    assert getattr(editor, name) == old
    assert editor.status_level == "error" and reason in editor.status_message
    np.testing.assert_array_equal(editor.spline.bezier(), before)


def test_singular_point_tension_is_rejected():
    """§2.5: with h = omega = 1 and v = -8 the diagonal vanishes (singular); keep the last curve."""
    points = [[float(i), float((-1) ** i)] for i in range(9)]
    editor = SplineEditor(points, knots="uniform", tension_scale="absolute", end_condition="clamped")
    before = editor.spline.bezier()
    with pytest.warns(SplineEditorWarning):
        editor.point_tension = [-8.0] * 9
    assert editor.point_tension == [0.0] * 9
    np.testing.assert_array_equal(editor.spline.bezier(), before)
    editor.point_tension = [-15.0] * 9  # the reversed range below -6 (c_{k-1} + c_k) is valid (Figs 3.8-3.11)
    assert editor.status_level == "info"


def test_bad_values_from_the_page_revert_without_warning():
    editor = SplineEditor(POINTS)
    before = editor.spline.bezier()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        editor.set_state({"interval_weights": [1.0, 0.0, 1.0, 1.0]})
        editor.set_state({"alpha": None})  # what the page sends for NaN
    assert editor.interval_weights == [1.0] * 4 and editor.alpha == 2.0
    assert editor.status_level == "error"
    np.testing.assert_array_equal(editor.spline.bezier(), before)
    editor.set_state({"interval_weights": [1.0, 2.0, 1.0, 1.0]})
    assert editor.interval_weights == [1.0, 2.0, 1.0, 1.0] and editor.status_level == "info"


def test_bad_constructor_arguments_raise():
    with pytest.raises(ValueError, match="2 coordinates per point"):
        SplineEditor([[1, 2, 3]])
    with pytest.raises(ValueError, match=r"points\[1, 0\] is nan"):
        SplineEditor([[1, 2], [float("nan"), 3], [4, 5]])
    with pytest.raises(ValueError, match="form"):
        SplineEditor(form="nope")
    with pytest.raises(TypeError, match="unexpected"):
        SplineEditor(POINTS, colour="red")
    with pytest.raises(ValueError, match="coincide"):
        SplineEditor([[0, 0], [0, 0], [1, 1]])


# ---------------------------------------------------------------------------------------------- drags
def test_drag_moves_point_echoes_seq_and_is_one_undo_step():
    editor = SplineEditor(POINTS)
    for k in range(1, 6):
        drag(editor, 2, (300 + 5 * k, 80 + 4 * k), seq=k, gesture=7, final=(k == 5))
        assert editor.geometry["seq"] == k
    assert editor.points[2] == [325.0, 100.0]
    reference = sc.interpolate(np.array(editor.points), knots="chord")
    np.testing.assert_allclose(buffer(editor.geometry["bezier"], (-1, 4, 2)), reference.bezier(), atol=1e-3)
    assert len(editor._history) == 1
    editor.undo()
    assert editor.points == POINTS
    editor.redo()
    assert editor.points[2] == [325.0, 100.0]


def test_a_drag_from_another_view_with_the_same_gesture_number_is_its_own_undo_step():
    """Each view numbers its gestures from 1 (js/drag_controller.js): a finished gesture's number is forgotten, so
    a later drag from another view (or a reloaded page) is not merged into an earlier step."""
    editor = SplineEditor(POINTS)
    drag(editor, 0, (90, 300), seq=1, gesture=1)
    drag(editor, 0, (100, 300), seq=2, gesture=1, final=True)
    page_message(editor, {"type": "undo"})
    page_message(editor, {"type": "redo"})
    editor.alpha = 3.0
    drag(editor, 3, (400, 160), seq=1, gesture=1, final=True)
    assert len(editor._history) == 3
    assert editor.undo() and editor.points[3] == POINTS[3] and editor.alpha == 3.0
    assert editor.undo() and editor.alpha == 2.0 and editor.points[0] == [100.0, 300.0]
    # an edit in the middle of a drag: the drag's next moves are a step of their own
    drag(editor, 1, (170, 120), seq=3, gesture=5)
    editor.alpha = 2.5
    drag(editor, 1, (180, 120), seq=4, gesture=5, final=True)
    assert editor.undo() and editor.points[1] == [170.0, 120.0] and editor.alpha == 2.5


def test_a_lower_max_points_than_the_points_held_is_refused_and_undo_keeps_history():
    editor = SplineEditor(POINTS)
    editor.add_point(600.0, 400.0)
    editor.add_point(640.0, 420.0)
    with pytest.raises(Exception, match="below the 7 points"):
        editor.max_points = 6
    assert editor.max_points > 7 - 1 and len(editor.points) == 7
    editor.max_points = 7  # a limit at the count is fine; an undo that would exceed a later limit is refused
    assert editor.undo() and len(editor.points) == 6
    editor.max_points = 6
    steps, redo = len(editor._history), list(editor._history._redo)
    with pytest.warns(SplineEditorWarning, match="redo is not possible"):
        assert not editor.redo()
    assert len(editor._history) == steps and editor._history._redo == redo and len(editor.points) == 6
    assert editor.undo() and len(editor.points) == 5 and editor.redo() and len(editor.points) == 6


@pytest.mark.parametrize("form", ["timmer_g2", "timmer_gc1", "interpolant", "basis"])
def test_a_tiny_class_parameter_that_stretches_the_drawing_beyond_reach_is_refused(form):
    """alpha > 0 is in range, but the handles (Timmer) or the class points V, W (the Bézier view) grow as
    1 / alpha: beyond the page's reach (float32) the value is refused and the last good curve kept."""
    editor = SplineEditor(POINTS, form=form, show_bezier_points=True)
    before = editor.spline.bezier()
    with pytest.warns(SplineEditorWarning, match="beyond"):
        editor.alpha = 1e-40
    assert editor.alpha != 1e-40 and "Kept the last good curve" in editor.status_message
    np.testing.assert_array_equal(editor.spline.bezier(), before)
    for name in ("bezier", "vw"):
        if name in editor.geometry:
            assert np.isfinite(buffer(editor.geometry[name])).all()
            assert np.abs(buffer(editor.geometry[name])).max() < 1e9


def test_a_cleared_number_box_is_echoed_to_the_page_as_null_not_nan():
    import json

    editor = SplineEditor(POINTS)
    sent = []
    editor.comm.kernel = True
    editor.comm.send = lambda data=None, metadata=None, buffers=None, **kw: sent.append(data)
    editor._handle_msg({"content": {"data": {"method": "update", "state": {"point_tension": [None] * 5}}},
                        "buffers": []})
    assert sent and all(json.dumps(message, allow_nan=False, default=repr) for message in sent)
    assert editor.point_tension == [0.0] * 5


def test_drag_onto_neighbour_is_rejected_and_acknowledged():
    editor = SplineEditor(POINTS)
    messages = sent_messages(editor)
    before = editor.spline.bezier()
    drag(editor, 2, POINTS[1], seq=3, gesture=1, final=True)
    assert messages[-1] == {"type": "drag_ack", "seq": 3, "ok": False}
    assert editor.points == POINTS and "coincide" in editor.status_message
    np.testing.assert_array_equal(editor.spline.bezier(), before)
    page_message(editor, {"type": "drag", "index": 2, "x": None, "y": 5.0, "seq": 4, "gesture": 1})
    assert messages[-1]["ok"] is False and editor.points == POINTS


# ---------------------------------------------------------------------------------------------- add / delete
def test_double_click_on_curve_inserts_in_sequence():
    editor = SplineEditor(POINTS)
    t_mid = 0.5 * (editor.spline.knots[2] + editor.spline.knots[3])
    x, y = editor.spline(t_mid)
    page_message(editor, {"type": "add", "x": float(x), "y": float(y), "tol": 5.0})
    assert len(editor.points) == 6 and editor.points[3] == pytest.approx([x, y])
    assert editor.selected == 3 and len(editor.point_tension) == 6 and len(editor.interval_weights) == 5
    np.testing.assert_allclose(editor.spline(editor.spline.knots[3]), [x, y], atol=1e-9)


def test_double_click_off_an_open_curve_extends_the_nearer_end():
    editor = SplineEditor(POINTS)
    assert editor.add_point(700.0, 360.0, tolerance=5.0) == 5
    assert editor.points[-1] == [700.0, 360.0]
    assert editor.add_point(-50.0, 350.0, tolerance=5.0) == 0
    assert editor.points[0] == [-50.0, 350.0]


def test_add_in_basis_form_goes_into_the_leg_of_that_piece():
    """§4.3: the inner Bézier points of a basis piece lie on its control leg P_i P_{i+1}."""
    points = [[0, 0], [100, 0], [200, 100], [300, 100], [400, 0], [500, 0]]
    editor = SplineEditor(points, form="basis")
    bezier = editor.spline.bezier()
    for piece in range(editor.spline.n_segments):
        leg = editor.spline.piece_leg(piece)
        a, b = np.array(points[leg]), np.array(points[leg + 1])
        for inner in bezier[piece, 1:3]:
            u, w = b - a, inner - a
            assert abs(u[0] * w[1] - u[1] * w[0]) / np.linalg.norm(u) < 1e-9
    mid = editor.spline(0.5 * (editor.spline.knots[1] + editor.spline.knots[2]))
    expected = editor.spline.piece_leg(1) + 1  # floating ends: piece 1 is thesis segment 2, on leg P_2 P_3
    assert expected == 3
    index = editor.add_point(*mid, tolerance=2.0)
    assert index == expected
    assert editor.points[index] == pytest.approx(list(mid))


def test_delete_point_and_minimum_count():
    editor = SplineEditor(POINTS)
    editor.selected = 2
    page_message(editor, {"type": "delete", "index": 2})
    assert editor.points == [p for i, p in enumerate(POINTS) if i != 2]
    assert len(editor.interval_weights) == 3 and editor.selected == -1
    editor.delete_point(0)
    editor.delete_point(0)
    assert len(editor.points) == 2
    with pytest.warns(SplineEditorWarning, match="at least 2"):
        assert editor.delete_point(0) is False
    assert len(editor.points) == 2
    for _ in range(3):
        editor.undo()
    assert editor.points == POINTS


def test_segment_mode_refuses_add_and_delete():
    editor = SplineEditor(form="segment")
    with pytest.warns(SplineEditorWarning, match="four points"):
        assert editor.add_point(10.0, 10.0) == -1
    assert len(editor.points) == 4


# ---------------------------------------------------------------------------------------------- history
def test_undo_redo_and_slider_coalescing():
    editor = SplineEditor(POINTS)
    editor._history.coalesce_seconds = 60.0
    for value in (1.0, 2.0, 3.0):  # one slider gesture: consecutive changes of one trait
        editor.set_state({"point_tension": [value] * 5})
    editor.set_state({"interval_weights": [2.0] * 4})
    assert len(editor._history) == 2
    assert editor.undo() and editor.interval_weights == [1.0] * 4 and editor.point_tension == [3.0] * 5
    assert editor.undo() and editor.point_tension == [0.0] * 5
    assert not editor.undo() and not editor.can_undo and editor.can_redo
    assert editor.redo() and editor.point_tension == [3.0] * 5
    editor._history.coalesce_seconds = 0.0
    editor.point_tension = [5.0] * 5  # a new change clears the redo stack
    assert not editor.can_redo and not editor.redo()


@SETTINGS
@given(st.lists(st.tuples(st.integers(0, 4), st.floats(-200, 800), st.floats(-200, 600)), min_size=1, max_size=12))
def test_random_drag_sequences_keep_a_valid_curve_and_undo_all(moves):
    editor = SplineEditor(POINTS)
    for k, (index, x, y) in enumerate(moves):
        drag(editor, index, (x, y), seq=k + 1, gesture=k, final=True)
        # whatever happened, the drawing is the engine's curve through the kernel's points
        reference = sc.interpolate(np.array(editor.points), knots="chord")
        np.testing.assert_allclose(editor.spline.bezier(), reference.bezier(), atol=1e-9)
    while editor.undo():
        pass
    assert editor.points == POINTS


# ---------------------------------------------------------------------------------------------- selection, view, svg
def test_click_on_curve_selects_interval_and_highlights_it():
    editor = SplineEditor(POINTS)
    x, y = editor.spline(0.5 * (editor.spline.knots[1] + editor.spline.knots[2]))
    page_message(editor, {"type": "select_at", "x": float(x), "y": float(y), "tol": 4.0})
    assert editor.selected_interval == 1
    np.testing.assert_allclose(buffer(editor.geometry["highlight"], (-1, 4, 2))[0], editor.spline.bezier()[1], atol=1e-3)


def test_fit_view_and_svg_export(tmp_path):
    editor = SplineEditor(POINTS)
    editor.view = [0.0, 0.0, 10.0, 10.0]
    page_message(editor, {"type": "fit"})
    x0, y0, x1, y1 = editor.view
    assert x0 < 60 and x1 > 540 and y0 < 80 and y1 > 300
    svg = editor.to_svg()
    assert svg.startswith("<?xml") and "<svg" in svg and editor.spline.to_svg_path(precision=3) in svg
    path = editor.save_svg(tmp_path / "curve.svg")
    assert path.read_text() == svg


# ---------------------------------------------------------------------------------------------- basis figure
def test_basis_figure_is_the_engine_basis_and_stays_in_sync():
    pytest.importorskip("bqplot")
    editor = SplineEditor(POINTS + [[640.0, 200.0]], form="basis", knots="uniform", tension_scale="absolute")
    figure = editor.basis_figure
    plot = editor._plots["basis"]
    t = np.asarray(plot.lines.x)
    reference = sc.basis_functions(t, 6).toarray()
    np.testing.assert_allclose(np.asarray(plot.lines.y), reference.T, atol=1e-12)
    np.testing.assert_allclose(np.asarray(plot.sum_line.y), 1.0, atol=1e-12)  # partition of unity
    editor.point_tension = [0.0, 0.0, 5.0, 0.0, 0.0, 0.0]
    editor.selected = 2
    t = np.asarray(plot.lines.x)
    reference = sc.basis_functions(t, 6, point_tension=[0.0, 0.0, 5.0, 0.0, 0.0, 0.0]).toarray()
    np.testing.assert_allclose(np.asarray(plot.highlight.y), reference[:, 2], atol=1e-12)
    # local support: B_2 vanishes outside (t_0, t_4)
    outside = (t <= 0.0) | (t >= 4.0)
    assert np.all(np.abs(np.asarray(plot.highlight.y)[outside]) < 1e-12)
    assert "Σ B_j = 1" in figure.title
    editor.form = "segment"
    assert np.asarray(plot.lines.y).shape == (4, len(plot.lines.x))
    panel = editor.panel()
    assert panel.children == (editor, figure)


@pytest.mark.parametrize("view", [[1e17, 0.0, 1e17 + 32, 1.0], [-1e308, -1e308, 1e308, 1e308], [0.0, 0.0, 1e-12, 1.0]])
def test_a_view_the_page_cannot_draw_keeps_the_last_view(view):
    editor = SplineEditor(POINTS)
    good, curve = list(editor.view), editor.spline
    with pytest.warns(SplineEditorWarning, match="view is too"):
        editor.view = view
    assert editor.view == good and editor.spline is curve and editor.status_level == "error"
    editor.set_state({"view": view})  # from the page: an error status, no warning
    assert editor.view == good and "view is too" in editor.status_message


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_js_geometry_helpers_in_node(tmp_path):
    """The page's pure helpers: the data -> screen map keeps the aspect ratio, paths are exact Béziers."""
    script = tmp_path / "check.mjs"
    script.write_text(f"""
import assert from "node:assert/strict";
import {{ Viewport, bezierPath, polylinePath, segmentsPath, floats }} from "{(static_dir() / 'common.js').as_uri()}";
const vp = new Viewport(400, 200, [0, 0, 10, 10]);          // square view in a 2:1 canvas
assert.equal(vp.k, 20);                                       // limited by the height
assert.deepEqual([vp.sx(0), vp.sy(0), vp.sx(10), vp.sy(10)], [100, 0, 300, 200]);
assert.deepEqual([vp.dx(vp.sx(3.25)), vp.dy(vp.sy(7.5))], [3.25, 7.5]);
assert.deepEqual(vp.visible(), [-5, 0, 15, 10]);
const z = vp.zoomed(2, 200, 100);                             // zoom in about the centre
assert.deepEqual(z, [0, 2.5, 10, 7.5]);
const unit = new Viewport(100, 100, [0, 0, 100, 100]);
const bez = new Float32Array([0, 0, 10, 0, 20, 10, 30, 10, 30, 10, 40, 10, 50, 0, 60, 0]);
assert.equal(bezierPath(unit, bez, false), "M0,0C10,0 20,10 30,10C40,10 50,0 60,0");
assert.equal(bezierPath(unit, bez, true).endsWith("Z"), true);
assert.equal(polylinePath(unit, [0, 0, 1, 1, NaN, NaN, 2, 2, 3, 3]), "M0,0L1,1M2,2L3,3");
assert.equal(segmentsPath(unit, [0, 0, 1, 1, 5, 5, 6, 6]), "M0,0L1,1M5,5L6,6");
const bytes = new Float32Array([1.5, -2.25]).buffer;
assert.deepEqual(Array.from(floats(new DataView(bytes))), [1.5, -2.25]);
const shifted = new Uint8Array(9); shifted.set(new Uint8Array(bytes), 1);  // unaligned view: copied
assert.deepEqual(Array.from(floats(new DataView(shifted.buffer, 1, 8))), [1.5, -2.25]);
console.log("ok");
""", encoding="utf-8")
    run = subprocess.run(["node", str(script)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_editor_modules_in_node(tmp_path):
    """The editor's ES modules import each other like any ES modules; their pure parts, checked in node."""
    base = static_dir().as_uri()
    script = tmp_path / "check.mjs"
    script.write_text(f"""
import assert from "node:assert/strict";
import {{ Viewport }} from "{base}/common.js";
import {{ gridStep, tangentTips, decodeGeometry }} from "{base}/editor_view.js";
import {{ typical, allEqual }} from "{base}/editor_controls.js";
import {{ hitPoint }} from "{base}/editor_input.js";
assert.equal(gridStep(120), 10);                                  // about 12 lines across, 1-2-5 steps
assert.equal(gridStep(100), 10);
assert.equal(gridStep(24), 2); assert.equal(gridStep(25), 5);
assert.deepEqual(Array.from(tangentTips([0, 0, 1, 2, 5, 5, 7, 8])), [1, 2, 7, 8]);
const g = decodeGeometry({{ bezier: new Float32Array([1, 2, 3, 4, 5, 6, 7, 8]).buffer, seq: 3 }});
assert.equal(g.seq, 3); assert.equal(g.bezier.length, 8); assert.equal(g.comb_teeth.length, 0);
assert.equal(typical([3, 1, 2]), 2); assert.equal(typical([4, 4]), 4); assert.ok(allEqual([]));
const vp = new Viewport(100, 100, [0, 0, 100, 100]);
assert.equal(hitPoint(vp, [10, 10, 50, 50, 52, 52], 50.5, 50.5), 1);  // nearest within the radius
assert.equal(hitPoint(vp, [10, 10], 40, 40), -1);
console.log("ok");
""", encoding="utf-8")
    run = subprocess.run(["node", str(script)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_zoom_stops_above_the_kernels_precision_and_the_grid_is_bounded_in_node(tmp_path):
    """Ctrl+wheel zoom in a loop (a long trackpad pinch) used to reach views a few ulps wide, where the grid loop
    ``x += step`` never ended; every view the page reaches now passes the kernel's view_problem."""
    base = static_dir().as_uri()
    script = tmp_path / "check.mjs"
    script.write_text(f"""
import assert from "node:assert/strict";
import {{ Viewport, drawableView, smallestSpan, MAX_SPAN, ZOOM_MARGIN }} from "{base}/common.js";
import {{ gridStep, gridLines, MAX_GRID_LINES }} from "{base}/editor_view.js";
const views = [];
for (const start of [[0, 0, 620, 440], [1e17, 0, 1e17 + 1e10, 1e10], [-3e5, 7e5, -2e5, 8e5]]) {{
  const vp = new Viewport(620, 440, start);
  for (let notch = 0; notch < 600; notch++) {{                // in: far beyond where the page used to hang
    vp.setView(vp.zoomed(Math.exp(100 * 0.002), 311.3, 207.9));
    const [x0, y0, x1, y1] = vp.visible();
    assert.ok(Math.min(x1 - x0, y1 - y0) >= 0.99 * ZOOM_MARGIN * smallestSpan(x0, y0, x1, y1), `${{vp.visible()}}`);
    const step = gridStep(Math.max(x1 - x0, y1 - y0));
    assert.ok(gridLines(x0, x1, step).length >= 2 && gridLines(y0, y1, step).length >= 2);
  }}
  views.push(vp.visible());
  for (let notch = 0; notch < 3000; notch++) vp.setView(vp.zoomed(Math.exp(-100 * 0.002), 10, 10));  // out
  const [x0, y0, x1, y1] = vp.visible();
  assert.ok(Math.max(x1 - x0, y1 - y0) <= 1.01 * MAX_SPAN && Number.isFinite(vp.k) && vp.k > 0);
  views.push(vp.visible());
}}
// the kernel's precision and overflow limits, as drawableView widens or narrows what it cannot draw
assert.deepEqual(drawableView([1, 2, NaN, 4]), [0, 0, 1, 1]);
assert.deepEqual(drawableView([0, 0, 0, 0]), [-0.5, -0.5, 0.5, 0.5]);
const far = drawableView([1e17, 0, 1e17 + 32, 1]);
assert.ok(far[2] - far[0] >= 1e8 && far[3] - far[1] >= 1e8);
const huge = drawableView([-1e308, -1e308, 1e308, 1e308]);
assert.ok(huge[2] - huge[0] === MAX_SPAN && huge[3] - huge[1] === MAX_SPAN);
// the grid never has more than MAX_GRID_LINES lines, whatever it is given
assert.deepEqual(gridLines(0, 10, 2.5), [0, 2.5, 5, 7.5, 10]);
assert.deepEqual(gridLines(1e17, 1e17 + 32, 1e-3), []);          // x + step == x: the old loop never ended
assert.deepEqual(gridLines(0, 1, 0), []); assert.deepEqual(gridLines(0, Infinity, 1), []);
assert.deepEqual(gridLines(NaN, 1, 1), []);
assert.equal(gridLines(0, MAX_GRID_LINES - 1, 1).length, MAX_GRID_LINES);
console.log(JSON.stringify(views));
""", encoding="utf-8")
    run = subprocess.run(["node", str(script)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    import json

    from splinecraft.widgets._base import view_problem

    for view in json.loads(run.stdout):  # every view the page reached, zoomed in and out: the kernel takes it
        assert view_problem(view) is None, view


def test_module_linker_orders_dependencies_and_refuses_cycles(tmp_path):
    from splinecraft.widgets._assets import module_order

    assert module_order("spline_editor.js")[-1] == "spline_editor.js"
    order = module_order("spline_editor.js")
    assert order.index("common.js") < order.index("editor_view.js") < order.index("editor_controls.js")
    (tmp_path / "a.js").write_text('import { b } from "./b.js";\nexport const a = 1;\n')
    (tmp_path / "b.js").write_text('import { a } from "./a.js";\nexport const b = 2;\n')
    with pytest.raises(RuntimeError, match="import cycle"):
        module_order("a.js", tmp_path)


def test_points_travel_as_float64_bytes_both_ways():
    editor = SplineEditor(POINTS)
    state = editor.get_state("points")
    raw = np.frombuffer(state["points"], dtype="<f8").reshape(-1, 2)
    np.testing.assert_array_equal(raw, np.array(POINTS))
    moved = np.array(POINTS)
    moved[1] += [5.0, -7.0]
    editor.set_state({"points": memoryview(moved.astype("<f8").tobytes())})  # what a page would send
    assert editor.points == moved.tolist()


def test_nodelay_server_extension_sets_tcp_nodelay_on_open():
    from splinecraft import jupyter_nodelay

    calls = []

    class FakeHandler:
        def set_nodelay(self, value):
            calls.append(("nodelay", value))

        async def open(self, kernel_id):
            calls.append(("open", kernel_id))

    assert jupyter_nodelay.enable_nodelay(FakeHandler) is True
    assert jupyter_nodelay.enable_nodelay(FakeHandler) is False  # idempotent
    # Drive the coroutine by hand: it never suspends, and the test must not need (or collide with) an event
    # loop -- Playwright's sync API keeps one running in this thread during the browser tests.
    opening = FakeHandler().open("k1")
    with pytest.raises(StopIteration):
        opening.send(None)
    assert calls == [("nodelay", True), ("open", "k1")]
    assert jupyter_nodelay._jupyter_server_extension_points() == [{"module": "splinecraft.jupyter_nodelay"}]


# ---------------------------------------------------------------------------------------------- TraceExplorer
def small_bitmap(size=48):
    """An L-shaped block with an oval hole: sharp corners, a curved hole, two boundaries. The hole (4 x 6.4 px
    half-axes) needs knots inserted, so that there are iterations to step through: a round one of radius 4 is
    within tolerance with the four knots its loop starts with."""
    yy, xx = np.mgrid[0:size, 0:size] + 0.5
    block = ((xx > 6) & (xx < 42) & (yy > 6) & (yy < 24)) | ((xx > 6) & (xx < 22) & (yy > 6) & (yy < 42))
    hole = (xx - 14.0) ** 2 + ((yy - 15.0) / 1.6) ** 2 < 16.0
    return block & ~hole


@pytest.fixture(scope="module")
def explorer_factory():
    pytest.importorskip("splinecraft.capture.fitting", exc_type=ImportError)
    from splinecraft.widgets import TraceExplorer

    return lambda image=None, **params: TraceExplorer(small_bitmap() if image is None else image,
                                                       **{"epsilon": 1.0, **params})


@pytest.mark.parametrize("method, words", [("lsq", "curvature"), ("fuzzy", "corners as the only knots")])
def test_explorer_explains_what_iteration_zero_holds(explorer_factory, method, words):
    explorer = explorer_factory(method=method)
    explorer.go_to(0)
    assert words in explorer.iteration_info["note"]


def test_explorer_draws_the_last_snapshot_and_steps(explorer_factory):
    explorer = explorer_factory()
    result = explorer.result
    assert explorer.n_snapshots == len(result.snapshots) >= 2
    assert explorer.snapshot_index == explorer.n_snapshots - 1
    np.testing.assert_allclose(buffer(explorer.snapshot_geometry["bezier"], (-1, 4, 2)), result.snapshots[-1].bezier,
                               atol=1e-4)
    assert explorer.image_size == [48, 48] and explorer.image_png.startswith(b"\x89PNG")
    assert explorer.go_to(0) == 0
    first = result.snapshots[0]
    np.testing.assert_allclose(buffer(explorer.snapshot_geometry["bezier"], (-1, 4, 2)), first.bezier, atol=1e-4)
    assert explorer.iteration_info["knots"] == first.knots and explorer.iteration_info["iteration"] == first.iteration
    assert explorer.iteration_info["max_error"] == pytest.approx(first.max_error)
    assert explorer.step(1) == 1 and explorer.iteration_info["iteration"] == result.snapshots[1].iteration
    assert explorer.step(-5) == 0 and explorer.step(10_000) == explorer.n_snapshots - 1
    corners = sum(len(c) for c in result.corners)
    assert len(buffer(explorer.base_geometry["corners"])) == corners


def test_explorer_candidates_are_split_by_acceptance(explorer_factory):
    explorer = explorer_factory()
    for index, merged in enumerate(explorer.result.snapshots):
        explorer.go_to(index)
        candidates = [c for s in merged.snapshots for c in (s.candidates or []) if c.get("point") is not None]
        inserts = [c for c in candidates if c.get("action", "insert") == "insert"]
        accepted = np.array([c["point"] for c in inserts if c["accepted"]], dtype=float).reshape(-1, 2)
        rejected = np.array([c["point"] for c in inserts if not c["accepted"]], dtype=float).reshape(-1, 2)
        removed = np.array([c["point"] for c in candidates if c.get("action") == "remove" and c["accepted"]],
                           dtype=float).reshape(-1, 2)
        np.testing.assert_allclose(buffer(explorer.snapshot_geometry["accepted"]), accepted, atol=1e-4)
        np.testing.assert_allclose(buffer(explorer.snapshot_geometry["rejected"]), rejected, atol=1e-4)
        np.testing.assert_allclose(buffer(explorer.snapshot_geometry["removed"]), removed, atol=1e-4)
        assert explorer.iteration_info["accepted"] == len(accepted)
        assert explorer.iteration_info["removed"] == len(removed)


def test_explorer_bad_values_keep_the_last_result(explorer_factory):
    from splinecraft.widgets import TraceExplorerWarning

    explorer = explorer_factory()
    result = explorer.result
    with pytest.warns(TraceExplorerWarning, match=r"epsilon \(px\) must be >= 0.001"):
        explorer.epsilon = -1.0
    assert explorer.epsilon == 1.0 and explorer.result is result and explorer.status_level == "error"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        explorer.set_state({"epsilon": None})  # NaN typed into the page's number box
        explorer.set_state({"snapshot_index": 999})
    assert explorer.epsilon == 1.0 and explorer.result is result
    assert explorer.snapshot_index == explorer.n_snapshots - 1
    page_message(explorer, {"type": "upload", "name": "junk.png"}, [b"not an image at all"])
    assert explorer.result is result and "not an image file" in explorer.status_message


def test_explorer_refuses_a_view_it_cannot_draw(explorer_factory):
    from splinecraft.widgets import TraceExplorerWarning

    explorer = explorer_factory()
    good, result = list(explorer.view), explorer.result
    with pytest.warns(TraceExplorerWarning, match="view is too large"):
        explorer.view = [-1e308, -1e308, 1e308, 1e308]
    with pytest.warns(TraceExplorerWarning, match="view is too small"):
        explorer.view = [1e17, 0.0, 1e17 + 32, 1.0]
    assert explorer.view == good and explorer.result is result and explorer.status_level == "error"


def test_explorer_time_budget_is_seconds_above_zero_or_none(explorer_factory):
    import traitlets

    explorer = explorer_factory()
    for bad in (math.nan, -1.0, 0.0, math.inf, True, "60"):
        with pytest.raises(traitlets.TraitError, match="time_budget_s"):
            explorer.time_budget_s = bad
        assert explorer.time_budget_s == 60.0
    explorer.time_budget_s = None  # no limit
    explorer.epsilon = 1.5
    assert explorer.result.params["epsilon"] == 1.5 and explorer.status_level == "info"
    explorer.time_budget_s = 5
    assert explorer.time_budget_s == 5.0


def test_explorer_retraces_on_settings_and_upload(explorer_factory, tmp_path):
    from PIL import Image

    explorer = explorer_factory()
    explorer.epsilon = 3.0
    assert explorer.result.params["epsilon"] == 3.0 and explorer.status_level == "info"
    methods = list(sc.KNOT_METHODS)
    other = next(name for name in methods if name != explorer.method)
    explorer.set_state({"method": other})
    assert explorer.result.params["method"] == other
    html_table = explorer.stats_html
    for column in ("Total number of points on contour", "Number of corner points", "Number of knots inserted",
                   "Total number of iterations", "Execution time", "Threshold value"):
        assert column in html_table
    assert f"<td>{explorer.result.stats['contour_points']:,}</td>" in html_table
    # an uploaded PNG replaces the bitmap
    square = np.zeros((32, 40), dtype=np.uint8) + 255
    square[8:24, 10:30] = 0
    path = tmp_path / "square.png"
    Image.fromarray(square).save(path)
    page_message(explorer, {"type": "upload", "name": "square.png"}, [path.read_bytes()])
    assert explorer.image_size == [40, 32] and explorer.mask.sum() == 16 * 20
    assert explorer.load(path) and explorer.status_level == "info"


def test_explorer_corner_parameters(explorer_factory):
    from splinecraft.widgets.trace_explorer import corner_param_specs

    specs = {spec["name"]: spec for spec in corner_param_specs("srm05")}
    assert {"zct", "dt", "ta"} <= set(specs) and specs["ta"]["min"] >= 90
    explorer = explorer_factory(corner_method="srm05", corner_params={"zct": 5})
    before = sum(len(c) for c in explorer.result.corners)
    explorer.corner_params = {"zct": 5, "ta": 100}
    assert explorer.result.params["corner_params"] == {"zct": 5, "ta": 100}
    assert sum(len(c) for c in explorer.result.corners) <= before  # a smaller TA keeps fewer corners
    other = next(name for name in sc.CORNER_METHODS if name != "srm05")
    explorer.corner_method = other
    allowed = {spec["name"] for spec in corner_param_specs(other)}
    assert set(explorer.corner_params) <= allowed


def test_explorer_convergence_figure(explorer_factory):
    pytest.importorskip("bqplot")
    explorer = explorer_factory()
    figure = explorer.convergence_figure
    plot = explorer._plots["convergence"]
    snapshots = explorer.result.snapshots
    np.testing.assert_array_equal(np.asarray(plot.knots.y), [s.knots for s in snapshots])
    np.testing.assert_allclose(np.asarray(plot.error.y), [s.max_error for s in snapshots])
    assert list(plot.threshold.y) == [1.0, 1.0]
    explorer.go_to(1)
    assert list(plot.current.x) == [float(snapshots[1].iteration)] * 2
    assert explorer.panel().children == (explorer, figure)


def test_closed_curve_insert_and_delete_keep_one_weight_per_interval():
    square = [[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0]]
    editor = SplineEditor(square, closed=True, interval_weights=[1.0, 2.0, 3.0, 4.0])
    assert editor.spline.closed and editor.spline.n_segments == 4
    # far outside, next to the closing side (points 3 -> 0): a closed curve takes it into the nearest piece
    index = editor.add_point(-60.0, 50.0, tolerance=1.0)
    assert index == 4 and editor.points[4] == [-60.0, 50.0]
    assert editor.interval_weights == [1.0, 2.0, 3.0, 4.0, 4.0]  # the split interval's weight on both halves
    assert editor.spline.n_segments == 5
    editor.delete_point(1)
    assert editor.interval_weights == [1.0, 3.0, 4.0, 4.0] and len(editor.points) == 4
    with pytest.warns(SplineEditorWarning, match="at least 3"):
        editor.delete_point(0)
        editor.delete_point(0)
    assert len(editor.points) == 3


def test_explorer_highlights_the_worst_corner_piece(explorer_factory):
    """piece_max_error is per piece between corners; the highlight is that piece's Bézier segments + contour."""
    explorer = explorer_factory(method="random", seed=3, epsilon=0.5)
    for index, merged in enumerate(explorer.result.snapshots[:6]):
        explorer.go_to(index)
        pieces = [(float(err), b, k) for b, s in enumerate(merged.snapshots)
                  for k, err in enumerate(np.asarray(s.piece_max_error, dtype=float))]
        # the first of equal maxima, as the explorer picks it (pieces of an exact fit can tie)
        error, boundary, k = max(pieces, key=lambda piece: (piece[0], -piece[1], -piece[2]))
        knot_indices = merged.snapshots[boundary].knot_indices[k]
        worst = buffer(explorer.snapshot_geometry["worst"], (-1, 4, 2))
        assert len(worst) == len(knot_indices) - 1
        np.testing.assert_allclose(worst[1:, 0], worst[:-1, 3], atol=1e-3)  # consecutive segments
        contour = buffer(explorer.snapshot_geometry["worst_contour"])
        points = explorer.result.points[boundary]
        np.testing.assert_allclose(contour[0], points[knot_indices[0]], atol=1e-4)
        np.testing.assert_allclose(contour[-1], points[knot_indices[-1] % len(points)], atol=1e-4)
        assert error == pytest.approx(explorer.iteration_info["max_error"])


def test_installed_layout_uses_the_packaged_static_dir(tmp_path):
    """A wheel carries js/ as splinecraft/widgets/static (pyproject force-include); _assets finds it there."""
    import importlib.util

    from splinecraft.widgets import _assets

    package = tmp_path / "site-packages" / "splinecraft" / "widgets"
    (package / "static").mkdir(parents=True)
    shutil.copy(_assets.__file__, package / "_assets.py")
    for source in static_dir().iterdir():
        if source.suffix in (".js", ".css"):
            shutil.copy(source, package / "static" / source.name)
    spec = importlib.util.spec_from_file_location("installed_assets", package / "_assets.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.static_dir() == package / "static"
    assert module.load_esm("trace_explorer.js") == load_esm("trace_explorer.js")


def test_alpha_beta_reset_when_their_meaning_changes():
    """Class parameters (§1) vs relative tangent scales (Alg 3.1/3.2) vs tangent scales (Alg 3.3)."""
    editor = SplineEditor(POINTS, preset="bezier")
    editor.form = "timmer_gc1"
    assert (editor.preset, editor.alpha, editor.beta) == ("free", 1.0, 1.0)
    chords = np.hypot(*np.diff(np.array(POINTS), axis=0).T)
    reference = sc.timmer_gc1(np.array(POINTS), alpha=4.0 / chords, beta=4.0 / chords)
    np.testing.assert_allclose(editor.spline.bezier(), reference.bezier(), atol=1e-9)
    editor.form = "timmer_gc2"
    assert (editor.preset, editor.alpha, editor.beta) == ("timmer", 4.0, 4.0)
    editor.form = "interpolant"
    assert (editor.preset, editor.alpha, editor.beta) == ("ball", 2.0, 2.0)
    editor.preset = "bezier"
    editor.form = "basis"  # same meaning (class parameters): kept
    assert (editor.preset, editor.alpha) == ("bezier", 3.0)


@pytest.mark.parametrize("path", ["", " ", "\t"])
def test_explorer_save_svg_refuses_a_blank_path(explorer_factory, tmp_path, monkeypatch, path):
    """save_svg('') wrote nowhere ('IsADirectoryError: .'), save_svg(' ') a file called space."""
    monkeypatch.chdir(tmp_path)
    explorer = explorer_factory()
    with pytest.raises(ValueError, match=r"^path is (empty|blank \(.*: only white space\)): give a file name"):
        explorer.save_svg(path)
    assert list(tmp_path.iterdir()) == []
    assert explorer.save_svg("trace.svg").read_text().startswith("<?xml")


@pytest.mark.parametrize("path", ["", " "])
def test_editor_save_svg_refuses_a_blank_path(tmp_path, monkeypatch, path):
    monkeypatch.chdir(tmp_path)
    editor = SplineEditor(POINTS)
    with pytest.raises(ValueError, match=r"^path is (empty|blank \(' ': only white space\)): give a file name"):
        editor.save_svg(path)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("text, value", [("NaN", math.nan), ("Infinity", math.inf), ("-Infinity", -math.inf)])
def test_the_page_texts_for_non_finite_numbers_are_read_as_numbers_and_refused(text, value):
    """A number box sends "NaN" or "Infinity" for a value that is no finite number (JSON would make it null, which
    t reads as "off"); the traits read the float and the editor refuses it with a message, keeping t."""
    from splinecraft.widgets._base import NONFINITE_TEXT

    assert NONFINITE_TEXT[text] == value or (math.isnan(value) and math.isnan(NONFINITE_TEXT[text]))
    editor = SplineEditor(POINTS, t=1.0)
    editor._handle_msg({"content": {"data": {"method": "update", "state": {"t": text}}}, "buffers": []})
    assert editor.t == 1.0 and editor.status_level == "error" and "t = " in editor.status_message
    editor._handle_msg({"content": {"data": {"method": "update", "state": {"point_tension": [text] * 5}}},
                        "buffers": []})
    assert editor.point_tension == [0.0] * 5 and editor.status_level == "error"


def test_a_refusal_keeps_the_engines_advice_in_the_status_line():
    editor = SplineEditor(POINTS)
    with pytest.warns(SplineEditorWarning):
        editor.point_tension = [-4.0] * 5  # relative: in the band [-6, -2] of every interior row
    assert "singular" in editor.status_message and editor.status_message.rstrip(".").endswith("the curve loops)")
