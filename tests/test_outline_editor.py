"""OutlineEditor, kernel side: traits, page messages, gestures, undo/redo, refusals that keep the last good outline."""
import math
import warnings

import numpy as np
import pytest

import splinecraft as sc
from splinecraft import datasets
from splinecraft.outline import as_outline
from splinecraft.widgets.outline_editor import OutlineEditor, OutlineEditorWarning


@pytest.fixture(scope="module")
def traced():
    return sc.trace(datasets.thesis_object("D"))


@pytest.fixture
def editor(traced):
    return OutlineEditor(traced)


def page(editor, **content):
    editor._handle_message(editor, content, [])


def test_opens_a_trace_with_its_bitmap_and_deviation(editor, traced):
    assert len(editor.contours) == len(traced.splines)
    # the trace's corners, and a join whose two curvatures differ in sign, which the spline form takes as a
    # corner (test_outline: test_a_trace_comes_in_exactly_with_its_corners_and_sources)
    assert [list(map(bool, c)) for c in editor.corners] == [c.corners.tolist() for c in as_outline(traced).contours]
    assert sum(sum(c) for c in editor.corners) >= traced.stats["corners"]
    assert editor.image[:8] == b"\x89PNG\r\n\x1a\n"
    assert editor.max_deviation == pytest.approx(traced.stats["hausdorff"], abs=0.15)
    entries = editor.geometry["contours"]
    for entry, spline in zip(entries, traced.splines):
        drawn = np.frombuffer(entry["bezier"], "<f4").reshape(-1, 4, 2)
        assert np.allclose(drawn, spline.bezier(), atol=1e-3)


def test_drag_gesture_moves_a_knot_and_is_one_undo_step(editor):
    start = editor.outline
    x, y = start.contours[0].points[4].tolist()
    for step, final in ((1, False), (2, False), (3, True)):
        page(editor, type="drag", contour=0, knot=4, x=x + 2 * step, y=y - step, seq=step, gesture=7, final=final)
    assert editor.contours[0][4] == [x + 6, y - 3]
    assert np.allclose(editor.outline.contours[0].bezier()[4, 0], [x + 6, y - 3])
    assert editor.geometry["seq"] == 3 and editor.can_undo
    assert editor.undo() and editor.outline is start
    assert editor.redo() and editor.contours[0][4] == [x + 6, y - 3]


def test_dragging_a_selected_knot_moves_the_whole_selection(editor):
    editor.selection = [[1, 0], [1, 1], [1, 2]]
    before = editor.outline.contours[1].points.copy()
    page(editor, type="drag", contour=1, knot=1, x=float(before[1, 0]) + 5, y=float(before[1, 1]), seq=1, gesture=1,
         final=True)
    after = editor.outline.contours[1].points
    assert np.allclose(after[:3], before[:3] + [5, 0]) and np.allclose(after[3:], before[3:])


def test_transform_gesture_of_a_selected_contour_is_exact(editor):
    editor.selection = [[1, k] for k in range(len(editor.contours[1]))]
    angle = math.radians(20)
    c, s = math.cos(angle), math.sin(angle)
    center = editor.outline.selection_center(contours=[1])
    e, f = center - np.array([[c, -s], [s, c]]) @ center
    before = editor.outline
    page(editor, type="transform", matrix=[c, s, -s, c, float(e), float(f)], seq=1, gesture=3, final=True)
    expected = before.contours[1].spline.transformed(np.array([[c, -s], [s, c]]), np.array([e, f])).bezier()
    assert np.abs(editor.outline.contours[1].bezier() - expected).max() < 1e-9
    assert editor.outline.contours[0] is before.contours[0]


def test_code_transforms_act_on_the_selection_or_the_whole_shape(editor):
    before = editor.outline
    editor.slant(12)
    shear = -math.tan(math.radians(12))
    center = before.selection_center()
    moved = editor.outline.contours[0].bezier()
    original = before.contours[0].bezier()
    assert np.allclose(moved[..., 0], original[..., 0] + shear * (original[..., 1] - center[1]))
    editor.selection = [[0, 0]]
    editor.translate(3, 4)
    assert np.allclose(editor.outline.contours[0].points[0], before.contours[0].points[0] @ [[1, 0], [shear, 1]]
                       + [-shear * center[1], 0] + [3, 4])


def test_corner_toggle_insert_and_delete_from_the_page(editor):
    editor.selection = [[0, 3]]
    was = editor.corners[0][3]
    page(editor, type="corner")
    assert editor.corners[0][3] is (not was)
    n = len(editor.contours[0])
    piece = editor.outline.contours[0].bezier()[2]
    middle = (piece[0] + 3 * piece[1] + 3 * piece[2] + piece[3]) / 8
    page(editor, type="insert", x=float(middle[0]), y=float(middle[1]), tol=2.0)
    assert len(editor.contours[0]) == n + 1 and editor.selection == [[0, 3]]
    page(editor, type="delete")
    assert len(editor.contours[0]) == n


def test_delete_below_three_knots_is_refused_and_keeps_the_outline(traced):
    editor = OutlineEditor([np.array([[0, 0], [10, 0], [5, 8]], float)])
    editor.selection = [[0, 1]]
    before = editor.outline
    page(editor, type="delete")
    assert editor.outline is before and editor.status_level == "error" and "at least 3 knots" in editor.status_message


def test_bad_values_from_code_keep_the_last_good_outline(editor):
    before = editor.outline
    bad = [list(map(list, c)) for c in editor.contours]
    bad[0][1] = [math.nan, 3.0]
    with pytest.warns(OutlineEditorWarning, match="contours"):
        editor.contours = bad
    assert editor.outline is before and editor.contours[0][1] == before.contours[0].points[1].tolist()
    with pytest.warns(OutlineEditorWarning, match="singular"):
        editor.transform([[1, 1, 0], [1, 1, 0]])
    assert editor.outline is before
    with pytest.warns(OutlineEditorWarning, match="selection"):
        editor.selection = [[0, 999]]
    assert editor.selection == []


def test_traits_from_code_edit_the_outline(editor):
    corners = [list(c) for c in editor.corners]
    corners[1][0] = not corners[1][0]
    editor.corners = corners
    assert editor.outline.contours[1].corners[0] == corners[1][0]
    tension = [list(v) for v in editor.point_tension]
    tension[0][2] = 4.0
    editor.point_tension = tension
    assert editor.outline.contours[0].point_tension[2] == 4.0
    seen = []
    editor.observe(lambda change: seen.append(change["name"]), "contours")
    editor.move_knot(0, 1, (50.0, 60.0))
    assert seen == ["contours"] and editor.contours[0][1] == [50.0, 60.0]


def test_bad_page_messages_are_answered_not_raised(editor):
    before = editor.outline
    page(editor, type="drag", contour=0, knot=10_000, x=1.0, y=2.0, seq=1, gesture=1, final=True)
    page(editor, type="drag", contour=0, knot=1, x="left", y=2.0, seq=2, gesture=2, final=True)
    page(editor, type="transform", matrix=[1, 0, 0], seq=3, gesture=3, final=True)
    page(editor, type="tension", value=1.0)  # nothing selected
    assert editor.outline is before and editor.status_level == "error"


def test_export_and_fonts(editor, tmp_path):
    editor.export_path = str(tmp_path / "d.svg")
    page(editor, type="export")
    assert (tmp_path / "d.svg").read_text().count("<path") == 1
    files = sc.font.build({"D": editor}, family="Editor Test", output_dir=tmp_path)
    assert files.otf.is_file() and files.ttf.is_file()
    assert editor.to_glyph("D").unicodes == [ord("D")]
    assert as_outline(editor) is editor.outline


def test_opens_svg_knot_lists_and_font_glyphs():
    assert len(OutlineEditor("M 0,0 L 10,0 L 10,10 L 0,10 Z").contours[0]) == 4
    glyph = sc.font.glyph_outline("DejaVu Sans", "B")
    editor = OutlineEditor(glyph)
    assert len(editor.contours) == 3 and editor.image == b"" and editor.max_deviation is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        editor.rotate(15)


def test_mirror_buttons_reflect_the_selection_about_its_box(editor):
    editor.selection = [[1, k] for k in range(len(editor.contours[1]))]
    before = editor.outline
    center = before.selection_center(contours=[1])
    page(editor, type="reflect", axis="vertical")
    mirrored = before.contours[1].bezier().copy()
    mirrored[..., 0] = 2 * center[0] - mirrored[..., 0]
    assert np.abs(editor.outline.contours[1].bezier() - mirrored).max() < 1e-9
    assert editor.outline.contours[0] is before.contours[0]
    page(editor, type="reflect", axis="diagonal")
    assert editor.status_level == "error" and "axis" in editor.status_message


def test_synced_tables_rebuild_only_changed_rows_and_equal_a_full_rebuild(traced):
    from splinecraft.widgets._outline_state import OUTLINE_TRAITS, synced_tables

    outline = as_outline(traced)
    current = synced_tables(outline, {}, None)
    assert set(current) == set(OUTLINE_TRAITS) and len(current["contours"]) == len(outline)
    moved = outline.move_knot(1, 2, (outline.contours[1].points[2] + [3.0, -2.0]).tolist())
    partial = synced_tables(moved, current, changed={1})
    full = synced_tables(moved, {}, None)
    assert set(partial) == {"contours"}  # corners, tensions and weights of contour 1 did not change
    assert partial["contours"] == full["contours"] and partial["contours"][0] is current["contours"][0]
    assert synced_tables(outline, current, changed={0, 1}) == {}


def test_page_checks_selection_pairs_matrices_and_the_fitted_view(traced):
    from splinecraft.widgets._outline_state import clean_selection, fitted_view, grouped_by_contour, page_matrix

    assert clean_selection([[0, 1], (0, 1), [1, 0]], [5, 3]) == [[0, 1], [1, 0]]
    for bad, words in (([[0, True]], "pairs of integers"), ([[0, 1, 2]], "pairs"), ([[2, 0]], "no knot 0 in contour 2"),
                       ([[0, 5]], "no knot 5")):
        with pytest.raises(ValueError, match=words):
            clean_selection(bad, [5, 3])
    assert grouped_by_contour([[1, 2], [0, 4], [1, 0]]) == {1: [2, 0], 0: [4]}
    assert page_matrix([1, 2, 3, 4, 5, 6]) == [[1, 3, 5], [2, 4, 6]]
    for bad in ([1, 2, 3], [1, 2, 3, 4, 5, "6"], [1, 2, 3, 4, 5, True], None, (1, 0, 0, 1, 0, 0)):
        with pytest.raises(ValueError, match="6 numbers"):
            page_matrix(bad)
    outline = as_outline(traced)
    x0, y0, x1, y1 = fitted_view(outline)
    low, high = outline.bounds()
    shown_low, shown_high = np.minimum(low, 0.0), np.maximum(high, [outline.width, outline.height])  # bitmap frame too
    pad = 0.05 * max(shown_high - shown_low)
    assert [x0, y0, x1, y1] == pytest.approx([*(shown_low - pad), *(shown_high + pad)])
    glyph = OutlineEditor("M 10,20 L 50,20 L 50,40 Z").outline  # no bitmap: the knots' box only
    assert fitted_view(glyph) == pytest.approx([8.0, 18.0, 52.0, 42.0])


def first_corner(outline):
    for k, contour in enumerate(outline.contours):
        corners = np.flatnonzero(contour.corners)
        if corners.size:
            return k, int(corners[0])
    raise AssertionError("the traced D has corners")


def test_handle_gesture_puts_the_corner_control_point_where_the_pointer_is(editor):
    start = editor.outline
    k, i = first_corner(start)
    n = len(start.contours[k])
    knot = start.contours[k].points[i]
    for step, final in ((1, False), (2, False), (3, True)):
        target = [float(knot[0] + 4 * step), float(knot[1] - 2 * step)]
        page(editor, type="handle", contour=k, knot=i, side="out", x=target[0], y=target[1], seq=step, gesture=5,
             final=final)
    bezier = editor.outline.contours[k].bezier()
    assert np.allclose(bezier[i, 1], target, atol=1e-9) and np.allclose(bezier[i, 0], knot)
    assert np.allclose(editor.outline.contours[k].handles_out[i], np.subtract(target, knot))
    assert np.allclose(bezier[(i - 1) % n], start.contours[k].bezier()[(i - 1) % n])  # the arriving side keeps
    assert editor.status_level == "info" and "Handle out" in editor.status_message
    assert editor.undo() and editor.outline is start  # the gesture is one undo step
    page(editor, type="handle", contour=k, knot=i, side="in", x=float(knot[0]) - 3, y=float(knot[1]) + 1, seq=4,
         gesture=6, final=True)
    assert np.allclose(editor.outline.contours[k].bezier()[(i - 1) % n, 2], [knot[0] - 3, knot[1] + 1], atol=1e-9)
    moved = editor.move_handle(k, i, "in", (float(knot[0]) - 6, float(knot[1])))
    assert np.allclose(moved.contours[k].bezier()[(i - 1) % n, 2], [knot[0] - 6, knot[1]], atol=1e-9)


def test_bad_handle_messages_are_refused_with_a_drag_ack_and_keep_the_outline(editor):
    answers = []
    editor.send = lambda message, buffers=None: answers.append(message)
    k, i = first_corner(editor.outline)
    smooth = int(np.flatnonzero(~editor.outline.contours[k].corners)[0])
    good = {"type": "handle", "contour": k, "knot": i, "side": "out", "x": 1.0, "y": 2.0, "final": True}
    before = editor.outline
    for seq, (change, words) in enumerate((({"knot": smooth}, "smooth"), ({"side": "up"}, "side"),
                                           ({"side": None}, "side"), ({"x": float("nan")}, "x"),
                                           ({"y": True}, "y"), ({"contour": 99}, "contour"),
                                           ({"x": None}, "x")), start=1):
        page(editor, **{**good, **change, "seq": seq, "gesture": seq})
        assert editor.outline is before and editor.status_level == "error", change
        assert words in editor.status_message, (change, editor.status_message)
        assert answers[-1] == {"type": "drag_ack", "seq": seq, "ok": False}
    with pytest.warns(OutlineEditorWarning, match="smooth"):
        editor.move_handle(k, smooth, "out", (1.0, 2.0))
    assert editor.outline is before


@pytest.mark.parametrize("kind", ["handle", "drag", "transform"])
def test_a_refused_move_in_a_gesture_publishes_the_last_good_one_and_ends_it_on_release(editor, kind):
    """Moves of a gesture reach the page as live pieces only; a bad move after them publishes the outline of the
    last good move (synced lists and geometry, newer than the live pieces), and a bad release ends the gesture
    as one undo step."""
    answers = []
    editor.send = lambda message, buffers=None: answers.append(message)
    start = editor.outline
    k, i = first_corner(start)
    knot = start.contours[k].points[i]
    good = {"handle": {"contour": k, "knot": i, "side": "out", "x": float(knot[0]) + 5, "y": float(knot[1])},
            "drag": {"contour": k, "knot": i, "x": float(knot[0]) + 5, "y": float(knot[1])},
            "transform": {"matrix": [1.0, 0.0, 0.0, 1.0, 5.0, 0.0]}}[kind]
    bad = {"handle": {"side": "sideways"}, "drag": {"x": float("inf")}, "transform": {"matrix": [1.0, 0.0]}}[kind]
    page(editor, type=kind, **good, seq=1, gesture=3, final=False)
    assert answers[-1]["type"] == "live" and editor.outline is not start
    moved, live_revision = editor.outline, answers[-1]["contours"][0]["revision"]
    assert editor.contours == [c.points.tolist() for c in start.contours]  # not synced during the gesture
    page(editor, type=kind, **{**good, **bad}, seq=2, gesture=3, final=False)
    assert answers[-1] == {"type": "drag_ack", "seq": 2, "ok": False} and editor.status_level == "error"
    assert editor.outline is moved and editor.contours == [c.points.tolist() for c in moved.contours]
    entry = editor.geometry["contours"][k]
    assert entry["revision"] > live_revision
    assert np.allclose(np.frombuffer(entry["bezier"], "<f4").reshape(-1, 4, 2), moved.contours[k].bezier(), atol=1e-3)
    page(editor, type=kind, **{**good, **bad}, seq=3, gesture=3, final=True)
    assert editor.outline is moved and editor._gesture is None and editor.can_undo
    assert editor.undo() and editor.outline is start


def test_a_transform_gesture_of_one_run_between_corners_maps_it_exactly(editor):
    """The page's handles scale (per axis) and shear a selection that is one run of the outer contour between
    two corners: that run's pieces become the affine image of the old ones, the selected knots land where the
    matrix sends them, the other knots and the hole stay."""
    before = editor.outline
    start = before.contours[0]
    corners = np.flatnonzero(start.corners)
    n = len(start)
    lengths = (np.roll(corners, -1) - corners) % n
    first = int(corners[np.argmax(lengths)])
    run = (first + np.arange(int(lengths.max()) + 1)) % n
    assert run.size >= 3  # the longest run of the traced D has interior smooth knots
    editor.selection = [[0, int(i)] for i in run]
    a, b, c, d, e, f = 1.3, 0.1, -0.25, 0.8, 12.0, -7.0  # x' = a x + c y + e, y' = b x + d y + f
    page(editor, type="transform", matrix=[a, b, c, d, e, f], seq=1, gesture=2, final=True)
    linear, offset = np.array([[a, c], [b, d]]), np.array([e, f])
    edited = editor.outline.contours[0]
    assert np.allclose(edited.points[run], start.points[run] @ linear.T + offset, rtol=0, atol=1e-12 * 400)
    rest = np.setdiff1d(np.arange(n), run)
    assert np.array_equal(edited.points[rest], start.points[rest])
    pieces = run[:-1]
    assert np.abs(edited.bezier()[pieces] - (start.bezier()[pieces] @ linear.T + offset)).max() < 1e-9
    assert editor.outline.contours[1] is before.contours[1]  # the hole has no selected knot
    assert editor.undo() and editor.outline is before


def test_corner_handles_are_synced_lists_that_code_can_read_set_and_observe(editor):
    """handles_out / handles_in: [dx, dy] per corner (None elsewhere); a handle drag updates them once, at the
    release; setting them from code moves the control point exactly; undo restores them."""
    start = editor.outline
    k, i = first_corner(start)
    contour = start.contours[k]
    assert all(h is None for h, corner in zip(editor.handles_out[k], contour.corners) if not corner)
    assert editor.handles_in[k][i] == contour.handles_in[i].tolist()  # a trace's corners keep its handles
    seen = []
    editor.observe(lambda change: seen.append(change["name"]), ["handles_out", "handles_in"])
    knot = contour.points[i]
    for step, final in ((1, False), (2, True)):
        page(editor, type="handle", contour=k, knot=i, side="out", x=float(knot[0]) + 3 * step, y=float(knot[1]),
             seq=step, gesture=4, final=final)
    assert seen == ["handles_out"] and editor.handles_out[k][i] == [6.0, 0.0]
    rows = [list(row) for row in editor.handles_in]
    rows[k][i] = [-2.5, 1.5]
    editor.handles_in = rows
    bezier = editor.outline.contours[k].bezier()
    assert np.allclose(bezier[i - 1, 2], knot + [-2.5, 1.5], rtol=0, atol=1e-12)
    assert np.allclose(bezier[i, 1], knot + [6.0, 0.0], rtol=0, atol=1e-12)
    assert editor.undo() and editor.handles_in[k][i] == contour.handles_in[i].tolist()
    assert editor.undo() and editor.outline is start and editor.handles_out[k][i] == contour.handles_out[i].tolist()


@pytest.mark.parametrize("entry, words", [([1.0], "two numbers"), (["a", 1.0], "two numbers"),
                                          ([True, 1.0], "two numbers"), ([float("nan"), 0.0], "finite"),
                                          ("far", "two numbers")])
def test_bad_handles_from_code_keep_the_last_good_outline(editor, entry, words):
    before = editor.outline
    k, i = first_corner(before)
    rows = [list(row) for row in editor.handles_out]
    rows[k][i] = entry
    with pytest.warns(OutlineEditorWarning, match=words):
        editor.handles_out = rows
    assert editor.outline is before and f"handles_out[{i}]" in editor.status_message
    assert editor.handles_out[k][i] != entry  # the lists are put back


def test_display_settings_are_checked_like_the_other_widgets(editor):
    import traitlets

    good = list(editor.view)
    for view in ([0, 0, math.nan, 1], [1e17, 0, 1e17 + 32, 1], [-1e308, -1e308, 1e308, 1e308], [0, 0, 1]):
        with pytest.warns(OutlineEditorWarning, match="view"):
            editor.view = view
        assert editor.view == good and editor.status_level == "error"
    editor.set_state({"view": [0, 0, 1e-12, 1]})  # from the page: refused, an error status and no warning
    assert editor.view == good and "view is too small" in editor.status_message
    editor.view = [0.0, 0.0, 50.0, 40.0]
    assert editor.view == [0.0, 0.0, 50.0, 40.0]
    for name, bad in (("width", -5), ("height", 10**9), ("width", True), ("show_fill", 1)):
        before = getattr(editor, name)
        with pytest.raises(traitlets.TraitError):
            setattr(editor, name, bad)
        assert getattr(editor, name) == before
    editor.set_state({"width": -5, "height": 300})  # a page update: the good key applies, the bad one is answered
    assert editor.width == 640 and editor.height == 300 and "width" in editor.status_message


@pytest.mark.parametrize("name", ["corners", "point_tension", "interval_weights", "handles_in", "handles_out"])
def test_a_table_must_list_every_contour_like_contours(editor, name):
    before = editor.outline
    rows = [list(row) for row in getattr(editor, name)]
    assert len(rows) >= 2
    with pytest.warns(OutlineEditorWarning, match=f"{name} must list {len(rows)} contours"):
        setattr(editor, name, rows[:1])  # one row for several contours
    assert editor.outline is before and getattr(editor, name) == [list(row) for row in rows]
    short = [row[:-1] if k == 1 else row for k, row in enumerate(rows)]
    with pytest.warns(OutlineEditorWarning, match=rf"{name}\[1\] must be a list of {len(rows[1])} entries"):
        setattr(editor, name, short)  # contour 1 one entry short
    assert editor.outline is before


def test_knots_beyond_reach_are_refused_by_name_and_keep_the_outline(editor):
    """A drag, a move or a transform to coordinates beyond ±1e9 (the page draws in float32): the status says
    so -- not that two untouched knots coincide, nor an IndexError of the deviation measure."""
    before = editor.outline
    page(editor, type="drag", contour=0, knot=1, x=1e39, y=0.0, seq=1, gesture=1, final=True)
    assert editor.outline is before and editor.status_level == "error"
    assert "x must be" in editor.status_message and "1e+09" in editor.status_message
    page(editor, type="transform", matrix=[1, 0, 0, 1, 1e12, 0], seq=2, gesture=2, final=True)
    assert editor.outline is before and "beyond ±1e+09" in editor.status_message
    # beyond float range the outline model itself refuses (Outline.transform), and the status says that
    page(editor, type="transform", matrix=[1, 0, 0, 1, 1e300, 0], seq=3, gesture=3, final=True)
    assert editor.outline is before and "beyond ±1e+150" in editor.status_message
    with pytest.warns(OutlineEditorWarning, match=r"position \(1e\+39, 0\) is beyond"):
        editor.move_knot(0, 1, (1e39, 0.0))
    with pytest.warns(OutlineEditorWarning, match="beyond"):
        editor.translate(0.0, -1e12)
    far = [list(map(list, c)) for c in editor.contours]
    far[0][1] = [1e39, 0.0]
    with pytest.warns(OutlineEditorWarning, match=r"contour 0: knot 1 at \(1e\+39, 0\) is beyond"):
        editor.contours = far
    assert editor.outline is before and editor.contours[0][1] == before.contours[0].points[1].tolist()
    editor.move_knot(0, 1, (1e5, 0.0))  # far, within reach: done (and measured quickly)
    assert editor.outline.contours[0].points[1].tolist() == [1e5, 0.0] and editor.max_deviation > 9e4


def test_a_bad_selection_from_the_page_keeps_the_last_good_one(editor):
    """The page's updates arrive with held trait notifications, where the trait holds the new value by the time
    the selection is checked: a pair naming no knot must not stay selected behind an error status."""
    sent = []
    editor.comm.send = lambda data=None, buffers=None, **_kwargs: sent.append(data)
    last = len(editor.contours[1]) - 1  # the last knot of contour 1, whatever the trace gave it
    good = [[1, last], [0, 1]]
    editor.set_state({"selection": good})
    assert editor.selection == good and editor.status_level == "info"
    sent.clear()
    editor.set_state({"selection": [[0, 1], [1, 99]]})
    assert editor.selection == good
    assert editor.status_level == "error" and editor.status_message.endswith("selection: no knot 99 in contour 1")
    resynced = [m["state"]["selection"] for m in sent if m.get("method") == "update" and "selection" in m["state"]]
    assert resynced[-1] == good
    editor.set_state({"selection": [[0, "1"]]})
    assert editor.selection == good and "pairs of integers" in editor.status_message


def test_a_refused_action_from_the_page_says_why_without_calling_the_message_bad(editor):
    """Delete, C or a double-click with nothing to act on are refusals of a well-formed message: the status says
    why ("select a knot first"), not "bad message", which is kept for malformed ones."""
    editor.selection = []
    page(editor, type="delete")
    assert editor.status_level == "error" and editor.status_message == "Kept the last good outline: select a knot first"
    page(editor, type="insert", x=-500.0, y=-500.0, tol=5.0)
    assert editor.status_message.startswith("Kept the last good outline: no curve within 5 of (-500.0, -500.0)")
    page(editor, type="insert", x=-500.0, y=-500.0)
    assert editor.status_message == "Kept the last good outline: bad message: the message has no field 'tol'"


def test_a_blank_export_path_keeps_the_last_good_one(editor, tmp_path, monkeypatch):
    """The page could set export_path to '' (an export then failed as "IsADirectoryError: '.'", logged as a
    handler bug) or ' ' (an export wrote a file called space). A blank one is refused: from the page with an error
    status and a resync, from code with a warning; the last good path is kept and exports there."""
    monkeypatch.chdir(tmp_path)
    editor.export_path = "good.svg"
    for blank in ("", " ", "\t\n"):
        editor.set_state({"export_path": blank})
        assert editor.export_path == "good.svg" and editor.status_level == "error"
        assert f"export_path is {'empty' if not blank else 'blank'}" in editor.status_message
        with pytest.warns(OutlineEditorWarning, match="export_path is"):
            editor.export_path = blank
        assert editor.export_path == "good.svg"
    page(editor, type="export")
    assert editor.status_message == "Saved good.svg." and sorted(p.name for p in tmp_path.iterdir()) == ["good.svg"]
    with pytest.raises(ValueError, match="path is blank"):
        editor.outline.save_svg(" ")


def test_a_failed_export_says_why_and_keeps_the_outline(editor, tmp_path, caplog):
    """An export to a folder that does not exist or to a folder's own path failed with a logged traceback, as if
    the handler had a bug, and 'Kept the last good outline' (nothing about the outline was wrong). Now: an error
    status naming the path and the system's reason, the outline unchanged, no traceback."""
    before = editor.outline
    for target, why in ((tmp_path / "missing" / "x.svg", "No such file or directory"),
                        (tmp_path, "Is a directory")):
        editor.export_path = str(target)
        with caplog.at_level("WARNING"):
            page(editor, type="export")
        assert editor.status_level == "error"
        assert editor.status_message == f"Not saved to {str(target)!r}: {why}"
        assert editor.outline is before and not caplog.records
    assert list(tmp_path.iterdir()) == []


def test_a_zero_interval_weight_from_the_page_is_a_bad_message(editor, caplog):
    """The page's weight 0 passed the message check (>= 0) and failed in the engine: a logged traceback, as if the
    handler had a bug, and a message about 'knots 1..2 (between two corners; ...)'. Refused as a bad value now."""
    before = editor.outline
    editor.set_state({"selection": [[0, 1]]})
    with caplog.at_level("WARNING"):
        page(editor, type="weight", value=0.0)
    assert editor.outline is before and editor.status_level == "error"
    assert "value must be > 0, got 0.0" in editor.status_message and not caplog.records
    page(editor, type="weight", value=2.0)
    assert editor.outline is not before and editor.status_level == "info"


def test_an_edit_during_a_drag_is_kept_by_the_release_and_each_is_an_undo_step(editor):
    """An edit that arrives while a drag is in progress (a key, a button, a call from code) ends the drag so far as
    its own undo step; the drag's next moves continue from the edited outline, so the release keeps the edit."""
    start = editor.outline
    x, y = start.contours[0].points[1].tolist()
    was = bool(start.contours[0].corners[2])
    editor.selection = [[0, 2]]
    page(editor, type="drag", contour=0, knot=1, x=x + 3, y=y, seq=1, gesture=4, final=False)
    page(editor, type="corner")
    toggled = editor.outline
    assert bool(toggled.contours[0].corners[2]) is (not was)
    page(editor, type="drag", contour=0, knot=1, x=x + 5, y=y, seq=2, gesture=4, final=True)
    assert bool(editor.outline.contours[0].corners[2]) is (not was) and editor.contours[0][1] == [x + 5, y]
    # three steps back: the drag after the toggle, the toggle, the drag before it
    assert editor.undo() and editor.outline is toggled
    assert editor.undo() and bool(editor.outline.contours[0].corners[2]) is was
    assert editor.contours[0][1] == [x + 3, y]
    assert editor.undo() and editor.outline is start and not editor.can_undo


def test_an_undo_during_a_drag_takes_back_the_drag_so_far(editor):
    editor.selection = [[0, 2]]
    page(editor, type="tension", value=3.0)
    tensed = editor.outline
    x, y = tensed.contours[0].points[1].tolist()
    page(editor, type="drag", contour=0, knot=1, x=x + 3, y=y, seq=1, gesture=2, final=False)
    page(editor, type="undo")
    assert editor.outline is tensed and editor.can_redo
    page(editor, type="drag", contour=0, knot=1, x=x + 5, y=y, seq=2, gesture=2, final=True)
    assert editor.contours[0][1] == [x + 5, y] and editor.outline.contours[0].point_tension[2] == 3.0
    assert editor.undo() and editor.outline is tensed  # the release's step, then the tension's
    assert editor.undo() and editor.outline.contours[0].point_tension[2] != 3.0


def test_toggling_corners_on_a_selection_is_one_undo_step(editor):
    start = editor.outline
    editor.selection = [[0, 1], [0, 2], [0, 3]]
    page(editor, type="corner")
    corners = editor.outline.contours[0].corners
    assert [bool(corners[k]) for k in (1, 2, 3)] == [not bool(start.contours[0].corners[k]) for k in (1, 2, 3)]
    assert editor.undo() and editor.outline is start and not editor.can_undo


def test_values_refused_from_code_never_reach_the_page_as_nan(editor):
    """A NaN list set from code syncs before the observer refuses it: the page gets JSON (null), not NaN."""
    import json

    sent = []
    editor.comm.kernel = True  # a live comm: state changes are sent (captured here)
    editor.comm.send = lambda data=None, metadata=None, buffers=None, **kw: sent.append(data)
    with pytest.warns(OutlineEditorWarning):
        editor.point_tension = [[float("nan")] * len(row) for row in editor.point_tension]
    assert sent and all(json.dumps(message, allow_nan=False, default=repr) for message in sent)
    assert all(math.isfinite(value) for row in editor.point_tension for value in row)


@pytest.mark.parametrize("gap", [4e-6, 1e-2])
def test_a_knot_dropped_onto_its_neighbour_is_refused_and_keeps_the_outline(editor, gap):
    """Beside a corner with fixed handles, a knot 4e-6 px from it threw a 280-px glyph's curve to 1e7 px; an edit
    whose curve lies more than MAX_SPREAD sizes beyond its knots and handles is refused."""
    from splinecraft.widgets._outline_state import MAX_SPREAD

    start = editor.outline
    corner = int(np.flatnonzero(start.contours[0].corners[1:])[0]) + 1
    x, y = (start.contours[0].points[corner] + [gap, 0]).tolist()
    page(editor, type="drag", contour=0, knot=corner - 1, x=x, y=y, seq=1, gesture=3, final=True)
    assert editor.outline is start and editor.status_level == "error" and "beyond its knots" in editor.status_message
    moved = start.move_knot(0, corner - 1, (x, y)).contours[0]
    anchors = np.concatenate([moved.points, moved.points[~np.isnan(moved.handles_in).any(axis=1)]
                              + moved.handles_in[~np.isnan(moved.handles_in).any(axis=1)]])
    size = np.ptp(anchors, axis=0).max()
    assert np.abs(moved.bezier()).max() > anchors.max() + MAX_SPREAD * size  # the refused curve: far beyond
    page(editor, type="drag", contour=0, knot=corner - 1, x=x + 3, y=y, seq=2, gesture=4, final=True)
    assert editor.outline is not start and editor.status_level == "info"  # a knot 3 px away is fine
