"""Editable outlines: the spline form of a contour, exact import of Bézier curves, edits, affine transforms."""
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import splinecraft as sc
from splinecraft import datasets
from splinecraft.outline import Contour, Outline, as_outline, from_bezier, from_knots
from splinecraft.outline.bezier import contour_from_bezier
from splinecraft.outline.contour import bezier_signed_area
from splinecraft.outline.transforms import affine_parts, reflection, rotation, scaling, shearing, translation


@pytest.fixture(scope="module")
def traced_d():
    return sc.trace(datasets.thesis_object("D"))


def _loop(n, seed, radius=50.0):
    rng = np.random.default_rng(seed)
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False) + rng.uniform(-0.25, 0.25, n) * (2 * np.pi / n)
    radii = radius * rng.uniform(0.6, 1.4, n)
    return np.c_[100 + radii * np.cos(angles), 100 + radii * np.sin(angles)]


contours = st.builds(
    lambda n, seed, corner_bits, tension, weight_seed: Contour(
        _loop(n, seed), np.array([(corner_bits >> i) & 1 for i in range(n)], bool),
        point_tension=tension, interval_weights=np.random.default_rng(weight_seed).uniform(0.5, 3.0, n)),
    st.integers(3, 9), st.integers(0, 10_000), st.integers(0, 511), st.floats(0.0, 2.0), st.integers(0, 10_000))

matrices = st.lists(st.floats(-2.0, 2.0), min_size=6, max_size=6).map(
    lambda v: np.array(v).reshape(2, 3)).filter(lambda m: abs(np.linalg.det(m[:, :2])) > 0.05)


def _gc2_residual(bezier, steps, weights, tension, i):
    """omega_i P''(t_i+) - v_i P'(t_i) - omega_{i-1} P''(t_i-) from the Bézier pieces (thesis eqs 3.13-3.14)."""
    after, before = bezier[i], bezier[i - 1]
    h, h_prev = steps[i], steps[i - 1]
    second_after = 6 * (after[0] - 2 * after[1] + after[2]) / h ** 2
    second_before = 6 * (before[1] - 2 * before[2] + before[3]) / h_prev ** 2
    first_after = 3 * (after[1] - after[0]) / h
    first_before = 3 * (before[3] - before[2]) / h_prev
    return (weights[i] * second_after - tension[i] * first_after - weights[i - 1] * second_before,
            first_after - first_before)


# ---------------------------------------------------------------------------------------------- the spline form
@settings(max_examples=40, deadline=None)
@given(contours)
def test_smooth_knots_are_gc2_joints_and_corners_keep_their_handles(contour):
    bezier = contour.bezier()
    assert np.allclose(bezier[:, 0], contour.points, atol=1e-9)  # an interpolant: passes through its knots
    scale = np.abs(bezier).max()
    for i in range(len(contour)):
        if contour.corners[i]:
            continue
        gc2, c1 = _gc2_residual(bezier, contour.steps, contour.interval_weights, contour.point_tension, i)
        assert np.abs(c1).max() < 1e-8 * scale
        assert np.abs(gc2).max() < 1e-8 * scale


def test_corners_without_handles_give_natural_ends_a_square_has_straight_sides():
    square = Contour([[0, 0], [10, 0], [10, 10], [0, 10]], [True] * 4)
    bezier = square.bezier()
    assert np.allclose(bezier[:, 1], bezier[:, 0] + (bezier[:, 3] - bezier[:, 0]) / 3)
    assert np.allclose(bezier[:, 2], bezier[:, 0] + 2 * (bezier[:, 3] - bezier[:, 0]) / 3)
    assert square.signed_area() == pytest.approx(100.0)


def test_signed_area_matches_the_closed_form_of_a_polygon():
    points = _loop(7, 3)
    polygon = Contour(points, [True] * 7)
    x, y = points.T
    shoelace = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    assert polygon.signed_area() == pytest.approx(shoelace, rel=1e-12)


@pytest.mark.parametrize("offset", [1e9, 1e12, 1e15])
def test_the_area_and_orientation_of_a_shape_far_from_the_origin_are_kept(offset):
    """A 2 x 2 square with a 1 x 1 hole, far away: the areas are exact (the cancellation of ``x dy - y dx``
    at ``x ~ 1e15`` gave areas of 1e14 and random signs)."""
    outline = from_knots([([[0, 0], [2, 0], [2, 2], [0, 2]], [True] * 4),
                          ([[0.5, 0.5], [1.5, 0.5], [1.5, 1.5], [0.5, 1.5]], [True] * 4)]).translate(offset, offset)
    assert [contour.signed_area() for contour in outline.contours] == pytest.approx([4.0, 1.0], rel=1e-9)
    assert [bezier_signed_area(b) for b in outline.oriented_bezier()] == pytest.approx([4.0, -1.0], rel=1e-9)


# ---------------------------------------------------------------------------------------------- exact import
@settings(max_examples=40, deadline=None)
@given(st.integers(3, 9), st.integers(0, 10_000), st.integers(0, 511))
def test_any_closed_bezier_curve_is_reproduced_exactly(n, seed, kink_bits):
    """G1 joints with arbitrary handle lengths become smooth knots (solved v, omega) or corners; kinks corners."""
    rng = np.random.default_rng(seed)
    points = _loop(n, seed)
    directions = np.roll(points, -1, axis=0) - np.roll(points, 1, axis=0)
    directions /= np.hypot(*directions.T)[:, None]
    out_dir = directions.copy()
    kinks = np.array([(kink_bits >> i) & 1 for i in range(n)], bool)
    turn = rng.uniform(0.3, 1.0, n)
    out_dir[kinks] = np.c_[np.cos(turn) * directions[:, 0] - np.sin(turn) * directions[:, 1],
                           np.sin(turn) * directions[:, 0] + np.cos(turn) * directions[:, 1]][kinks]
    chords = np.hypot(*(np.roll(points, -1, axis=0) - points).T)
    out_len = chords * rng.uniform(0.15, 0.45, n)
    in_len = np.roll(chords, 1) * rng.uniform(0.15, 0.45, n)
    nxt = np.roll(np.arange(n), -1)
    bezier = np.stack([points, points + out_len[:, None] * out_dir,
                       points[nxt] - in_len[nxt, None] * directions[nxt], points[nxt]], axis=1)
    contour = contour_from_bezier(bezier)
    assert np.abs(contour.bezier() - bezier).max() < 1e-6
    assert contour.corners[kinks].all()


def test_a_trace_comes_in_exactly_with_its_corners_and_sources(traced_d):
    """Every corner of the trace is a corner of the outline; a smooth join becomes one only where its two
    curvatures differ in sign (an S-bend at a join, which no positive weight ratio takes; docs/capture.md §12,
    "Merged segments"; with ``curvature_jumps=True`` D's jump knots give it one)."""
    outline = as_outline(traced_d)
    assert len(outline) == len(traced_d.splines)
    for contour, spline in zip(outline.contours, traced_d.splines):
        assert np.abs(contour.bezier() - spline.bezier()).max() < 1e-9
    for fit, spline, contour in zip(traced_d.fits, traced_d.splines, outline.contours):
        trace_corners = np.zeros(len(spline.bezier()), bool)
        if len(fit.corners_used):
            counts = [len(k) - 1 for k in fit.knot_indices]
            trace_corners[np.concatenate([[0], np.cumsum(counts)[:-1]])] = True
        assert (contour.corners >= trace_corners).all()
        extra = contour.corners & ~trace_corners
        assert (_curvature_ratio(spline.bezier())[extra] <= 0).all()
    assert sum(int(c.corners.sum()) for c in outline.contours) >= traced_d.stats["corners"]
    assert outline.bitmap.shape == traced_d.mask.shape
    assert (outline.width, outline.height) == (traced_d.width, traced_d.height)
    # the deviation from the bitmap's contour is the trace's own measure
    assert outline.max_deviation() == pytest.approx(traced_d.stats["hausdorff"], abs=0.15)


def test_the_unmerged_trace_comes_in_with_v_0_and_omega_1():
    """The C2 fit before merging (``merge_tolerance=0``) is the project's own spline form: it comes back with
    v = 0 and omega = 1 and with the trace's corners only (docs/capture.md §12, "Merged segments")."""
    traced = sc.trace(datasets.thesis_object("D"), fit_params={"merge_tolerance": 0.0})
    outline = as_outline(traced)
    assert all((c.point_tension == 0).all() and (c.interval_weights == 1).all() for c in outline.contours)
    assert sum(int(c.corners.sum()) for c in outline.contours) == traced.stats["corners"]


def _curvature_ratio(bezier):
    """Per knot the curvature at the end of the piece before it over that at the start of the piece after it."""
    def curvature(d1, d2):
        return (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
    before = np.roll(bezier, 1, axis=0)
    end = curvature(before[:, 3] - before[:, 2], before[:, 1] - 2 * before[:, 2] + before[:, 3])
    start = curvature(bezier[:, 1] - bezier[:, 0], bezier[:, 0] - 2 * bezier[:, 1] + bezier[:, 2])
    with np.errstate(divide="ignore", invalid="ignore"):
        return end / start


@pytest.mark.parametrize("name", ["ali", "apple", "D"])
def test_a_merged_trace_keeps_its_smooth_joins_smooth(name):
    """The merged joins are G1 with a curvature jump; the spline form takes a jump by a positive ratio (interval
    weights, thesis eqs 3.13-3.14), so a join whose two curvatures have one sign stays smooth, unless the
    engine refuses its tension (§2.5), then it alone becomes a corner; the trace's corners stay corners."""
    # the trace is this test's input, pinned to the corners it was written with: tangent-jump's spread turns
    # (step 5b) release two fillet corners of ali (3.5-8 px radius) whose smooth fit some joins of the spline
    # form can only take as corners (a tension outside the dominant domain, §2.5): 3 of 19 there
    traced = sc.trace(datasets.thesis_object(name), corner_params={"spread": 0.0})
    outline = as_outline(traced)
    for fit, spline, contour in zip(traced.fits, traced.splines, outline.contours):
        bezier = spline.bezier()
        assert np.abs(contour.bezier() - bezier).max() < 1e-9 * max(1.0, np.abs(bezier).max())
        trace_corners = np.zeros(len(bezier), bool)
        if len(fit.corners_used):
            counts = [len(k) - 1 for k in fit.knot_indices]
            trace_corners[np.concatenate([[0], np.cumsum(counts)[:-1]])] = True
        assert (contour.corners >= trace_corners).all()
        ratio = _curvature_ratio(bezier)
        extra = contour.corners & ~trace_corners
        same_sign = ~trace_corners & (ratio > 0)
        # before the fix every knot of ali's first contour became a corner (one refused tension)
        assert (extra & same_sign).sum() <= max(1, same_sign.sum() // 10)


def test_an_iteration_of_the_trace_can_be_opened(traced_d):
    outline = as_outline(traced_d, iteration=0)
    first = traced_d.snapshots[0]
    for contour, snapshot in zip(outline.contours, first.snapshots):
        assert np.abs(contour.bezier() - snapshot.bezier).max() < 1e-9


# ---------------------------------------------------------------------------------------------- transforms
@settings(max_examples=40, deadline=None)
@given(contours, matrices)
def test_transform_equals_the_transformed_curve(contour, matrix):
    """Affine invariance (thesis section 3.3): mapping the knots and handles maps the curve exactly."""
    outline = Outline([contour])
    moved = outline.transform(matrix)
    expected = contour.spline.transformed(matrix[:, :2], matrix[:, 2]).bezier()
    assert np.abs(moved.contours[0].bezier() - expected).max() < 1e-7 * max(1.0, np.abs(expected).max())


@settings(max_examples=25, deadline=None)
@given(contours, st.floats(-180, 180), st.floats(0.2, 3), st.floats(0.2, 3), st.floats(-1, 1))
def test_named_transforms_match_their_closed_forms(contour, degrees, sx, sy, shear):
    outline = Outline([contour])
    bezier = contour.bezier()
    center = np.array([7.0, -3.0])
    a = math.radians(degrees)
    rotated = (bezier - center) @ np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]]) + center
    assert np.allclose(outline.rotate(degrees, center=center).contours[0].bezier(), rotated, atol=1e-7)
    scaled = (bezier - center) * [sx, sy] + center
    assert np.allclose(outline.scale(sx, sy, center=center).contours[0].bezier(), scaled, atol=1e-7)
    sheared = bezier.copy()
    sheared[..., 0] += shear * (bezier[..., 1] - center[1])
    assert np.allclose(outline.shear(shear, center=center).contours[0].bezier(), sheared, atol=1e-7)
    mirrored = bezier.copy()
    mirrored[..., 0] = 2 * center[0] - bezier[..., 0]
    assert np.allclose(outline.reflect("vertical", center=center).contours[0].bezier(), mirrored, atol=1e-7)
    assert np.allclose(outline.translate(3, -4).contours[0].bezier(), bezier + [3, -4], atol=1e-9)


def test_transform_of_one_contour_leaves_the_others(traced_d):
    outline = as_outline(traced_d)
    turned = outline.rotate(30, contours=[1])
    assert turned.contours[0] is outline.contours[0]
    center = outline.selection_center(contours=[1])
    expected = outline.contours[1].spline.transformed(
        np.array([[math.cos(math.radians(30)), -math.sin(math.radians(30))],
                  [math.sin(math.radians(30)), math.cos(math.radians(30))]]),
        center - np.array([[math.cos(math.radians(30)), -math.sin(math.radians(30))],
                           [math.sin(math.radians(30)), math.cos(math.radians(30))]]) @ center).bezier()
    assert np.abs(turned.contours[1].bezier() - expected).max() < 1e-9


def _run_knots(corners):
    """Piece -> the knots of its run between consecutive corners, both corners included (a loop without corners:
    every knot)."""
    n, index = len(corners), np.flatnonzero(corners)
    if index.size == 0:
        return {p: tuple(range(n)) for p in range(n)}
    runs = {}
    for j, start in enumerate(index):
        length = (index[(j + 1) % index.size] - start) % n or n
        knots = tuple(int(k) for k in (start + np.arange(length + 1)) % n)
        runs.update({p: knots for p in knots[:-1]})
    return runs


def _with_some_handles(contour, bits):
    """The contour with the current curve's handles given to the corners picked by ``bits``."""
    b, n = contour.bezier(), len(contour)
    picked = contour.corners & np.array([(bits >> i) & 1 for i in range(n)], bool)
    return contour.replace(handles_out=np.where(picked[:, None], b[:, 1] - b[:, 0], np.nan),
                           handles_in=np.where(picked[:, None], np.roll(b[:, 2] - b[:, 3], 1, axis=0), np.nan))


PARTIAL_MOVES = {  # name -> (the Outline method on the selection, the same map as a matrix about the pivot c)
    "translate": (lambda o, pairs, a: o.translate(20 * a, -12 * a, knots=pairs), lambda a, c: translation(20 * a, -12 * a)),
    "rotate": (lambda o, pairs, a: o.rotate(170 * a, knots=pairs), lambda a, c: rotation(170 * a, c)),
    "scale": (lambda o, pairs, a: o.scale(0.3 + 2 * a, knots=pairs), lambda a, c: scaling(0.3 + 2 * a, None, c)),
    "scale per axis": (lambda o, pairs, a: o.scale(0.4 + a, 1.6 - a, knots=pairs),
                       lambda a, c: scaling(0.4 + a, 1.6 - a, c)),
    "shear": (lambda o, pairs, a: o.shear(a - 0.5, knots=pairs), lambda a, c: shearing(a - 0.5, 0.0, c)),
    "mirror": (lambda o, pairs, a: o.reflect(180 * a, knots=pairs), lambda a, c: reflection(180 * a, c)),
}


@settings(max_examples=60, deadline=None)
@given(contours, st.integers(0, 511), st.integers(0, 511), st.integers(0, 8), st.sampled_from(sorted(PARTIAL_MOVES)),
       st.floats(0.05, 0.95))
def test_a_transform_of_some_knots_is_exact_and_keeps_every_joint(contour, handle_bits, chosen_bits, piece, move,
                                                                  amount):
    """Moving, rotating, scaling, shearing or mirroring some knots of a contour (the run of one piece and some
    other knots): the selected knots (and the handles of selected corners) land exactly where the affine map
    sends them, the others stay, smooth knots stay GC2 joints and corners corners; a run between corners whose
    knots are all selected becomes exactly the affine image of the old run, a run without a selected knot is
    untouched."""
    contour = _with_some_handles(contour, handle_bits)
    n = len(contour)
    selected = np.array([(chosen_bits >> i) & 1 for i in range(n)], bool)
    run = list(_run_knots(contour.corners)[piece % n])
    selected[run] = True
    if selected.all():  # keep one knot out (outside the run, when the run is not the whole loop)
        selected[min(set(range(n)) - set(run), default=0)] = False
    pairs = [(0, int(i)) for i in np.flatnonzero(selected)]
    outline = Outline([contour])
    method, matrix = PARTIAL_MOVES[move]
    linear, offset = affine_parts(matrix(amount, outline.selection_center(knots=pairs)))
    edited = method(outline, pairs, amount).contours[0]
    scale = max(1.0, np.abs(contour.bezier()).max())
    assert np.abs(edited.points[selected] - (contour.points[selected] @ linear.T + offset)).max() <= 1e-12 * scale
    assert np.array_equal(edited.points[~selected], contour.points[~selected])
    assert np.array_equal(edited.corners, contour.corners)
    bezier, before = edited.bezier(), contour.bezier()
    for i in range(n):
        if not contour.corners[i]:
            gc2, c1 = _gc2_residual(bezier, edited.steps, edited.interval_weights, edited.point_tension, i)
            assert np.abs(c1).max() < 1e-8 * scale and np.abs(gc2).max() < 1e-8 * scale
            continue
        for side, handle in (("out", bezier[i, 1] - bezier[i, 0]), ("in", bezier[i - 1, 2] - bezier[i - 1, 3])):
            given_handle = getattr(contour, f"handles_{side}")[i]
            if not np.isnan(given_handle).any():
                expected = given_handle @ linear.T if selected[i] else given_handle
                assert np.abs(handle - expected).max() <= 1e-9 * scale
    for piece, knots in _run_knots(contour.corners).items():
        knots = list(knots)
        if selected[knots].all():
            assert np.abs(bezier[piece] - (before[piece] @ linear.T + offset)).max() <= 1e-9 * scale
        elif not selected[knots].any():
            assert np.array_equal(bezier[piece], before[piece])


@pytest.mark.parametrize("matrix, message", [
    ([[1, 2, 0], [2, 4, 0]], "singular"),
    ([[0, 0, 0], [0, 0, 0], [0, 0, 1]], "singular"),
    ([[1, 0, np.nan], [0, 1, 0]], "non-finite"),
    ([[1, 0, np.inf], [0, 1, 0]], "non-finite"),
    ([[1, 0, 0], [0, 1, 0], [0.1, 0, 1]], "last row"),
    ([[1, 0], [0, 1]], "2x3 or 3x3"),
])
def test_bad_matrices_are_refused_with_a_message(matrix, message):
    outline = Outline([Contour(_loop(5, 1))])
    with pytest.raises(ValueError, match=message):
        outline.transform(matrix)


@pytest.mark.parametrize("scale", [1e-100, 1e-30, 1e30, 1e100])
def test_extreme_scales_about_the_origin_keep_the_shape(scale):
    """A scale within float range is not singular (the test is made on A / |A|_max, not on a determinant that
    overflows or underflows): a square with a hole scaled about the origin keeps its nesting, its orientation
    and its area times scale²."""
    from splinecraft.outline import from_svg

    outline = from_svg("M0 0 H10 V10 H0 Z M2 2 V8 H8 V2 Z")
    scaled = outline.scale(scale, center=(0.0, 0.0))
    assert scaled.nesting_depths().tolist() == [0, 1]
    for before, after in zip(outline.contours, scaled.contours):
        np.testing.assert_allclose(after.bezier(), before.bezier() * scale, rtol=1e-12)
        assert bezier_signed_area(after.bezier()) == pytest.approx(bezier_signed_area(before.bezier()) * scale ** 2,
                                                                   rel=1e-9)


@pytest.mark.parametrize("change, message", [
    (lambda o: o.scale(1e200), r"coordinate of 5e\+200, beyond ±1e\+150"),
    (lambda o: o.translate(1e308, 0.0), r"coordinate of 1e\+308, beyond ±1e\+150"),
    (lambda o: o.scale(1e-200), r"extent of 0, below 1e-150"),  # about (5, 5): every point rounds to 5
    (lambda o: o.scale(1e-200, center=(0.0, 0.0)), r"extent of 1e-199, below 1e-150"),  # areas underflow to 0
    (lambda o: o.translate(10.0, 0.0, knots=[(0, 0)]), r"leaves contour 0 invalid: knots 0 and 1 coincide"),
])
def test_transforms_beyond_float_range_are_refused_for_what_they_do(change, message):
    """A scale of 1e200 was refused as singular ("determinant inf"), a translation by 1e308 as "knots 0 and 1
    coincide", and a scale of 1e-200 about the origin made areas of 0 (orientation and nesting lost) or was
    "singular"; now each names what happens, and the outline stays as it was."""
    from splinecraft.outline import from_svg

    outline = from_svg("M0 0 H10 V10 H0 Z M2 2 V8 H8 V2 Z")
    before = [c.bezier().copy() for c in outline.contours]
    with pytest.raises(ValueError, match=message):
        change(outline)
    assert all(np.array_equal(c.bezier(), b) for c, b in zip(outline.contours, before))


def test_a_matrix_of_strings_is_a_type_error():
    with pytest.raises(TypeError, match="matrix"):
        Outline([Contour(_loop(5, 1))]).transform("rotate(30)")


# ---------------------------------------------------------------------------------------------- edits
def test_moving_a_knot_moves_the_curve_through_the_new_point():
    outline = Outline([Contour(_loop(6, 2), [True, False, False, True, False, False])])
    moved = outline.move_knot(0, 2, (130.0, 140.0))
    assert np.allclose(moved.contours[0].bezier()[2, 0], [130, 140])
    assert np.allclose(moved.contours[0].bezier()[1, 3], [130, 140])
    assert outline.contours[0].points[2].tolist() != [130.0, 140.0]  # the original is unchanged


def test_a_knot_becomes_a_corner_then_smooth_again():
    contour = Contour(_loop(7, 4), point_tension=0.5)
    kept = contour.with_corner(3, keep_shape=True)
    assert kept.corners[3] and np.abs(kept.bezier() - contour.bezier()).max() < 1e-9
    bent = contour.with_corner(3)
    assert np.array_equal(bent.points, contour.points)
    out, into = bent.bezier()[3, 1] - bent.bezier()[3, 0], bent.bezier()[2, 2] - bent.bezier()[2, 3]
    sine = (out[0] * into[1] - out[1] * into[0]) / (np.hypot(*out) * np.hypot(*into))
    assert abs(sine) > 1e-3  # a real corner: the two tangents follow their own neighbours
    smooth = bent.with_corner(3, False)
    gc2, c1 = _gc2_residual(smooth.bezier(), smooth.steps, smooth.interval_weights, smooth.point_tension, 3)
    assert np.abs(c1).max() < 1e-9 and np.abs(gc2).max() < 1e-8


@settings(max_examples=60, deadline=None)
@given(st.integers(4, 8), st.integers(0, 2 ** 32 - 1))
def test_a_new_corner_that_keeps_the_shape_keeps_it_beside_corners_without_handles(size, seed):
    # a handle-less corner's end tangent is the parabola of its run's first three knots (§6.3), the chord's on a
    # run of one piece: splitting the run next to it must not fall back to the chord
    rng = np.random.default_rng(seed)
    corners = rng.random(size) < 0.4
    corners[0] = True
    contour = Contour(_loop(size, seed % 7 + 1), corners, point_tension=rng.random(size))
    for knot in np.flatnonzero(~corners):
        kept = contour.with_corner(int(knot), keep_shape=True)
        assert kept.corners[knot]
        assert np.abs(kept.bezier() - contour.bezier()).max() < 1e-9 * np.abs(contour.bezier()).max()
    outline = Outline([contour])
    for knot in np.flatnonzero(~corners):
        assert np.abs(outline.set_corner(0, int(knot), keep_shape=True).bezier()[0]
                      - outline.bezier()[0]).max() < 1e-9 * np.abs(contour.bezier()).max()


def test_inserting_a_knot_puts_it_on_the_curve_and_deleting_it_refuses_below_three():
    contour = Contour(_loop(4, 5), [True, False, False, False])
    piece = contour.bezier()[1]
    theta = 0.3
    expected = (1 - theta) ** 3 * piece[0] + 3 * (1 - theta) ** 2 * theta * piece[1] \
        + 3 * (1 - theta) * theta ** 2 * piece[2] + theta ** 3 * piece[3]
    inserted = contour.inserted(1, theta)
    assert len(inserted) == 5 and np.allclose(inserted.points[2], expected)
    assert inserted.steps[1] + inserted.steps[2] == pytest.approx(contour.steps[1])
    three = inserted.removed(2).removed(0)
    assert len(three) == 3
    with pytest.raises(ValueError, match="at least 3 knots"):
        three.removed(1)


def test_nearest_point_finds_the_piece_to_insert_on():
    outline = Outline([Contour([[0, 0], [100, 0], [100, 100], [0, 100]], [True] * 4)])
    contour, piece, theta, distance = outline.nearest_point((50, 2))
    assert (contour, piece) == (0, 0) and theta == pytest.approx(0.5, abs=0.02) and distance == pytest.approx(2)


def test_tension_and_weight_edits_are_validated_by_the_engine():
    contour = Contour(_loop(6, 6))
    tight = contour.with_point_tension([1, 2], 50.0).with_interval_weight(4, 3.0)
    assert tight.point_tension[1] == 50.0 and tight.interval_weights[4] == 3.0
    gc2, _ = _gc2_residual(tight.bezier(), tight.steps, tight.interval_weights, tight.point_tension, 1)
    assert np.abs(gc2).max() < 1e-7 * np.abs(tight.bezier()).max()
    span = 2 * (1 / contour.steps[1] + 1 / contour.steps[2])
    with pytest.raises(ValueError, match="diagonally dominant"):
        contour.with_point_tension(2, -2 * span)
    with pytest.raises(ValueError, match="interval_weights"):
        contour.with_interval_weight(0, 0.0)


def test_contour_input_errors_name_the_argument():
    with pytest.raises(ValueError, match="at least 3 knots"):
        Contour([[0, 0], [1, 1]])
    with pytest.raises(ValueError, match="points"):
        Contour([[0, 0], [1, np.nan], [2, 0]])
    with pytest.raises(ValueError, match="coincide"):
        Contour([[0, 0], [0, 0], [2, 0]])
    with pytest.raises(ValueError, match="corners"):
        Contour(_loop(4, 1), [True, False])
    with pytest.raises(ValueError, match="index 9"):
        Contour(_loop(4, 1)).moved(9, (0, 0))


def test_a_knot_moved_to_a_malformed_position_names_positions():
    """``move_knot``/``Contour.moved`` reshaped the position with numpy: a 3-number point was "cannot reshape
    array of size 3 into shape (2)", and a 6-number one silently became three points. The shape is checked and
    the message names ``positions``; a non-finite coordinate is named as a plain number (not np.float64)."""
    outline = from_knots([_loop(4, 1)])
    for bad in ((1.0, 2.0, 3.0), [[1.0], [2.0]], [[[1.0, 2.0]]], 5.0):
        with pytest.raises(ValueError, match=r"positions must be a point \(x, y\) or one per knot"):
            outline.move_knot(0, 0, bad)
    with pytest.raises(ValueError, match=r"positions must be a point"):
        outline.move_knot(0, [0, 1, 2], [1.0, 2.0, 3.0, 4.0, 5.0, 6.0])  # not three points
    with pytest.raises(TypeError, match="positions"):
        outline.move_knot(0, 0, None)
    with pytest.raises(ValueError, match=r"points\[0, 0\] is nan; it must be finite"):
        outline.move_knot(0, 0, (np.nan, 1.0))
    moved = outline.move_knot(0, [0, 1], [[0.1, 0.2], [0.9, 0.1]])
    np.testing.assert_array_equal(moved.contours[0].points[:2], [[0.1, 0.2], [0.9, 0.1]])
    np.testing.assert_array_equal(outline.move_knot(0, 0, [(0.1, 0.2)]).contours[0].points[0], [0.1, 0.2])


def test_selections_are_single_indices_checked_against_the_outline():
    """A contour or knot index that was a list took its first item (``contours=[[0, 1]]`` moved contour 0 only;
    ``knots=[(0, [1, 2])]`` moved knot 1 only; ``move_knot([0, 1], ...)`` edited contour 0), a knot of a contour
    chosen whole was never checked (``knots=[(0, 99)]``), a bare index in ``knots`` or a dict was "object of type
    'int' has no len()", and a contour out of range was reported as "a contour of 2 knots". Each is an error
    naming the argument and what it indexes."""
    outline = from_knots([_loop(4, 1), _loop(3, 2, radius=20.0) + 200])
    cases = [
        (dict(contours=[[0, 1]]), TypeError, r"contours\[0\] must be one integer index, got \[0, 1\]"),
        (dict(knots=[(0, [1, 2])]), TypeError, r"knots\[0\]\[1\] \(a knot\) must be one integer index"),
        (dict(contours=[0], knots=[(0, 99)]), ValueError, r"knots\[0\]\[1\] \(a knot\) = 99 is out of range for "
                                                         r"contour 0 of 4 knots"),
        (dict(knots=[5]), ValueError, r"\(contour, knot\) pairs, got knots\[0\] = 5"),
        (dict(knots={0: [1]}), TypeError, "knots must be a list of"),
        (dict(contours=[7]), ValueError, r"contours\[0\] = 7 is out of range for an outline of 2 contours"),
        (dict(contours=1.0), TypeError, "one integer index"),
    ]
    for selection, error, pattern in cases:
        with pytest.raises(error, match=pattern):
            outline.translate(1.0, 1.0, **selection)
    with pytest.raises(TypeError, match=r"contour must be one integer index, got \[0, 1\]"):
        outline.move_knot([0, 1], 0, (3.0, 3.0))
    with pytest.raises(ValueError, match="contour = 2 is out of range for an outline of 2 contours"):
        outline.set_corner(2, 0)
    both = outline.translate(1.0, 2.0, contours=np.array([0, 1]))
    for before, after in zip(outline.contours, both.contours):
        np.testing.assert_allclose(after.points, before.points + [1.0, 2.0])
    last = outline.translate(1.0, 2.0, knots=[(np.int64(-1), np.int32(-1))])
    np.testing.assert_allclose(last.contours[1].points[2], outline.contours[1].points[2] + [1.0, 2.0])
    np.testing.assert_array_equal(last.contours[1].points[:2], outline.contours[1].points[:2])
    np.testing.assert_array_equal(last.contours[0].points, outline.contours[0].points)


def test_an_empty_selection_is_refused_not_ignored():
    """``contours=[]`` or ``knots=[]`` selected nothing, so a transform silently returned the outline unchanged
    (and ``selection_center`` failed inside numpy); an explicit empty selection is now a ValueError, while
    neither argument still means the whole shape."""
    outline = from_knots([_loop(4, 1), _loop(3, 2, radius=20.0) + 200])
    for selection in (dict(contours=[]), dict(knots=[]), dict(contours=[], knots=[]), dict(contours=np.array([], int))):
        with pytest.raises(ValueError, match="the selection is empty"):
            outline.translate(1.0, 2.0, **selection)
        with pytest.raises(ValueError, match="the selection is empty"):
            outline.selection_center(**selection)
    whole = outline.translate(1.0, 2.0)
    for before, after in zip(outline.contours, whole.contours):
        np.testing.assert_allclose(after.points, before.points + [1.0, 2.0])
    some = outline.translate(1.0, 2.0, contours=[], knots=[(1, 0)])
    np.testing.assert_allclose(some.contours[1].points[0], outline.contours[1].points[0] + [1.0, 2.0])


def test_single_knot_edits_refuse_lists_and_non_bool_flags():
    """delete_knot, set_corner, insert_knot and move_handle took the first of a list of indices silently
    (``delete_knot(0, [0, 1])`` deleted knot 0 only), ``corner="no"`` made a corner (``bool("no")``) and
    ``theta="0.5"`` was read as a number; each is now a TypeError naming the argument."""
    outline = from_knots([_loop(5, 3)])
    cases = [
        (lambda: outline.delete_knot(0, [0, 1]), r"knot must be one integer index, got \[0, 1\]"),
        (lambda: outline.set_corner(0, [1, 2]), r"knot must be one integer index"),
        (lambda: outline.insert_knot(0, [0, 1]), r"piece must be one integer index"),
        (lambda: outline.set_corner(0, 1).move_handle(0, [1, 2], "in", (1.0, 1.0)), r"knot must be one integer"),
        (lambda: outline.set_corner(0, 1, corner="no"), r"corner must be a bool"),
        (lambda: outline.set_corner(0, 1, corner=0), r"corner must be a bool"),
        (lambda: outline.set_corner(0, 1, keep_shape="yes"), r"keep_shape must be a bool"),
        (lambda: outline.insert_knot(0, 0, "0.5"), r"theta must be a real number"),
    ]
    for edit, pattern in cases:
        with pytest.raises(TypeError, match=pattern):
            edit()
    assert len(outline.delete_knot(0, np.int64(1)).contours[0]) == 4
    assert outline.set_corner(0, 1, np.True_).contours[0].corners.tolist() == [False, True, False, False, False]
    assert len(outline.insert_knot(0, -1, np.float32(0.25)).contours[0]) == 6


def test_reversed_contour_is_the_same_curve_backwards():
    contour = Contour(_loop(6, 8), [True, False, True, False, False, False], interval_weights=[1, 2, 1, 3, 1, 1])
    backwards = contour.reversed()
    assert backwards.signed_area() == pytest.approx(-contour.signed_area())
    forward = contour.bezier()
    reverse = backwards.bezier()
    assert np.allclose(reverse[0], forward[-1][::-1])


# ---------------------------------------------------------------------------------------------- export
def test_json_round_trip_is_exact(traced_d):
    outline = as_outline(traced_d).set_corner(0, 3).set_point_tension(1, 2, 1.5)
    again = Outline.from_json(outline.to_json())
    for a, b in zip(again.contours, outline.contours):
        assert np.array_equal(a.bezier(), b.bezier())
        assert np.array_equal(a.corners, b.corners)
    assert again.max_deviation() == pytest.approx(outline.max_deviation())
    with pytest.raises(ValueError, match="JSON"):
        Outline.from_json("{not json")
    with pytest.raises(ValueError, match="splinecraft.Outline"):
        Outline.from_json('{"type": "other"}')


def test_svg_is_one_nonzero_path_of_exact_cubics(traced_d, tmp_path):
    """nonzero, not evenodd: the contours are oriented by nesting (outer positive, holes negative), so the two
    rules agree on nested contours, and nonzero also fills overlapping outer contours as their union (the
    even-odd rule would punch a hole there). A trace is already oriented so: its curves are written as they are."""
    from splinecraft.capture.svg import read_svg_paths

    outline = as_outline(traced_d)
    path = outline.save_svg(tmp_path / "d.svg", decimals=None)
    document = read_svg_paths(path.read_text())
    assert len(document["paths"]) == 1 and document["paths"][0]["fill_rule"] == "nonzero"
    for (bezier, closed), contour in zip(document["paths"][0]["subpaths"], outline.contours):
        assert closed and np.array_equal(bezier, contour.bezier())
    again = as_outline(path)
    for a, b in zip(again.contours, outline.contours):
        assert np.abs(a.bezier() - b.bezier()).max() < 1e-9


def _winding(curves, point, samples=64):
    """Winding number of closed Bézier curves about ``point`` (dense polygons; signed angle sum)."""
    total = 0.0
    theta = np.linspace(0.0, 1.0, samples, endpoint=False)
    one = 1.0 - theta
    weights = np.stack([one ** 3, 3 * one * one * theta, 3 * one * theta * theta, theta ** 3], axis=1)
    for bezier in curves:
        ring = np.einsum("sk,pkd->psd", weights, np.asarray(bezier, float)).reshape(-1, 2) - point
        angles = np.arctan2(ring[:, 1], ring[:, 0])
        total += np.sum((np.diff(np.r_[angles, angles[:1]]) + np.pi) % (2 * np.pi) - np.pi)
    return round(total / (2 * np.pi))


def test_nested_holes_and_islands_of_a_trace_keep_their_depths_and_directions():
    """A ring with a dot inside, the dot with a hole, and a bar beside: depths 0/1/2/3 by plain nesting (traced
    contours never overlap), and the trace's own orientation (outer positive, holes negative) is kept."""
    from splinecraft.outline.contour import bezier_signed_area

    yy, xx = np.mgrid[:80, :80]
    radius = np.hypot(yy - 40, xx - 40)
    bitmap = ((radius < 35) & (radius > 22)) | (radius < 12) | ((np.abs(xx - 4) < 2) & (yy > 5) & (yy < 20))
    bitmap[38:43, 38:43] = False
    outline = as_outline(sc.trace(bitmap))
    curves = outline.bezier()
    by_area = np.argsort([-abs(bezier_signed_area(c)) for c in curves])
    depths = outline.nesting_depths()[by_area]
    areas = np.array([bezier_signed_area(c) for c in curves])[by_area]
    assert sorted(depths.tolist()) == [0, 0, 1, 2, 3]
    assert ((areas > 0) == (depths % 2 == 0)).all()
    for before, after in zip(curves, outline.oriented_bezier()):
        assert np.array_equal(before, after)
    # the fill: ring ink, between ring and dot empty, dot ink, the dot's hole empty
    winding = [_winding(outline.oriented_bezier(), p) for p in ([40, 11], [40, 26], [40, 33], [40, 40])]
    assert [w != 0 for w in winding] == [True, False, True, False]


def test_overlapping_contours_are_not_nested_and_stay_outer():
    """A "+" of two bars: the vertical bar starts inside the horizontal one but is not inside it as a whole, so
    both are outer contours (depth 0) and fill as their union; a square wholly inside is a hole whichever way it
    runs."""
    horizontal = [[0, 40], [200, 40], [200, 80], [0, 80]]
    vertical = [[80, 60], [80, 0], [120, 0], [120, 200], [80, 200]]
    square = [[150, 50], [150, 70], [170, 70], [170, 50]]
    outline = from_knots([(np.array(c, float), [True] * len(c)) for c in (horizontal, vertical, square)])
    assert outline.nesting_depths().tolist() == [0, 0, 1]
    curves = outline.oriented_bezier()
    assert _winding(curves, [100, 60]) == 2 and _winding(curves, [160, 60]) == 0
    assert _winding(curves, [100, 20]) == 1 and _winding(curves, [20, 60]) == 1


def test_knot_lists_make_contours_with_holes():
    outer = np.array([[10, 10], [90, 10], [90, 90], [10, 90]], float)
    hole = np.array([[50, 30], [70, 50], [50, 70], [30, 50]], float)
    outline = from_knots([(outer, [True] * 4), hole])
    assert len(outline) == 2 and outline.contours[0].corners.all() and not outline.contours[1].corners.any()
    assert outline.width == 91 and outline.height == 91
    with pytest.raises(ValueError, match=r"contours\[1\]"):
        from_knots([outer, [[0, 0], [1, 1]]])


def test_from_bezier_refuses_open_curves():
    piece = np.array([[[0, 0], [1, 0], [2, 0], [3, 0]], [[3, 0], [3, 1], [3, 2], [3, 3]]], float)
    with pytest.raises(ValueError, match=r"curves\[0\] is not closed"):
        from_bezier([piece])


def test_as_outline_refuses_unknown_sources():
    with pytest.raises(TypeError, match="cannot make an outline"):
        as_outline(42)


@settings(max_examples=40, deadline=None)
@given(contours, st.integers(0, 8), st.floats(-20, 20), st.floats(-20, 20), st.floats(0.0, 5.0))
def test_edits_that_rebuild_only_some_runs_equal_a_full_rebuild(contour, knot, dx, dy, tension):
    """Moving a knot or changing a tension rebuilds only the runs holding it; the curve is the full rebuild's."""
    knot %= len(contour)
    try:
        edited = contour.moved(knot, contour.points[knot] + [dx, dy]).with_point_tension((knot + 2) % len(contour), tension)
    except ValueError:  # a move onto a neighbour: refused either way
        return
    fresh = Contour(**{name: value for name, value in edited.fields().items()})
    assert np.abs(edited.bezier() - fresh.bezier()).max() <= 1e-9 * max(1.0, np.abs(fresh.bezier()).max())


@given(contours, st.integers(0, 8), st.sampled_from(["in", "out"]), st.floats(-20, 20), st.floats(-20, 20))
def test_a_corner_handle_puts_its_control_point_exactly_there(contour, knot, side, dx, dy):
    """The dragged handle's control point lands on the target, the runs away from the corner keep their pieces,
    and the partial rebuild equals a full one."""
    knot %= len(contour)
    n = len(contour)
    if not contour.corners[knot]:
        with pytest.raises(ValueError, match="smooth"):
            contour.with_handle(knot, side, (0.0, 0.0))
        return
    target = contour.points[knot] + [dx, dy]
    edited = contour.with_handle(knot, side, target)
    bezier, before = edited.bezier(), contour.bezier()
    piece, node = (knot, 1) if side == "out" else ((knot - 1) % n, 2)
    assert np.allclose(bezier[piece, node], target, rtol=0, atol=1e-9 * max(1.0, np.abs(target).max()))
    runs = _run_knots(contour.corners)
    touched = {runs[knot], runs[(knot - 1) % n]} if side == "in" else {runs[knot]}
    for p in range(n):
        if runs[p] not in touched:
            assert np.array_equal(bezier[p], before[p])
    fresh = Contour(**edited.fields())
    assert np.abs(bezier - fresh.bezier()).max() <= 1e-9 * max(1.0, np.abs(fresh.bezier()).max())


def test_handle_edits_name_the_bad_argument():
    square = Contour([[0, 0], [10, 0], [10, 10], [0, 10]], [True, False, True, False])
    with pytest.raises(ValueError, match="side must be 'in' or 'out'"):
        square.with_handle(0, "up", (1, 1))
    with pytest.raises(ValueError, match="side"):
        square.with_handle(0, ["out"], (1, 1))
    with pytest.raises(ValueError, match="position.*finite"):
        square.with_handle(0, "out", (np.nan, 1))
    with pytest.raises(ValueError, match="position must have shape"):
        square.with_handle(0, "out", (1, 2, 3))
    with pytest.raises(TypeError, match="position must be numeric"):
        square.with_handle(0, "out", "far")
    with pytest.raises(ValueError, match="out of range"):
        square.with_handle(7, "out", (1, 1))
    outline = Outline([square], width=20, height=20)
    moved = outline.move_handle(0, 2, "in", (10, 5))
    assert np.allclose(moved.contours[0].bezier()[1, 2], [10, 5]) and outline.contours[0] is square


def test_curve_bounds_are_the_curves_box_inside_the_control_box():
    """A drop whose handles reach past its tip: the curve box (cubic extrema) is what dense sampling finds,
    the control box is wider."""
    drop = from_bezier([np.array([[[0, 50], [-40, 0], [100, 0], [100, 50]],
                                  [[100, 50], [100, 100], [-40, 100], [0, 50]]], float)])
    theta = np.linspace(0, 1, 20001)[:, None, None]
    pieces = drop.bezier()[0][None]
    samples = ((1 - theta) ** 3 * pieces[:, :, 0] + 3 * (1 - theta) ** 2 * theta * pieces[:, :, 1]
               + 3 * (1 - theta) * theta ** 2 * pieces[:, :, 2] + theta ** 3 * pieces[:, :, 3]).reshape(-1, 2)
    low, high = drop.curve_bounds()
    assert np.allclose(low, samples.min(axis=0), atol=1e-6) and np.allclose(high, samples.max(axis=0), atol=1e-6)
    control_low, _ = drop.bounds()
    assert control_low[0] < low[0] - 20


def test_a_hole_grazing_its_outer_curve_stays_a_hole():
    """A fitted hole may cross its outer curve by a hair at a thin wall (within the fit's tolerance): it is
    still nested (90 % of its samples inside), so it stays a hole; a bar overlapping a square by 40 % of its
    length is not nested and stays outer."""
    outer = [[0, 0], [100, 0], [100, 100], [0, 100]]
    hole = [[10, 10], [10, 90], [99, 90], [100.3, 50], [99, 10]]     # a tip 0.3 beyond the outer's side
    bar = [[60, 40], [60, 60], [160, 60], [160, 40]]
    grazing = from_knots([(np.array(c, float), [True] * len(c)) for c in (outer, hole)])
    assert grazing.nesting_depths().tolist() == [0, 1]
    overlapping = from_knots([(np.array(c, float), [True] * 4) for c in (outer, bar)])
    assert overlapping.nesting_depths().tolist() == [0, 0]


def test_deviation_of_a_knot_dragged_far_away_has_bounded_samples():
    """A knot dragged 100000 px away: the deviation samples the long pieces more coarsely (at most about
    ``MAX_DEVIATION_SAMPLES`` points) instead of one every 0.25 px, which took minutes and gigabytes for a
    drag a million pixels away; a contour of the usual size keeps the fine spacing."""
    from splinecraft.outline.model import DEVIATION_SPACING, MAX_DEVIATION_SAMPLES, _sample_pieces

    traced = sc.trace(datasets.thesis_object("D"))
    outline = as_outline(traced)
    contour = outline.contours[0]
    samples, _ = _sample_pieces(contour.bezier(), DEVIATION_SPACING)
    lengths = np.hypot(*np.diff(contour.bezier(), axis=1).transpose(2, 0, 1)).sum()
    assert len(samples) >= lengths / DEVIATION_SPACING  # the usual spacing where it fits
    far = outline.move_knot(0, 1, (1e5, 0.0)).contours[0]
    samples, piece = _sample_pieces(far.bezier(), DEVIATION_SPACING)
    assert len(samples) <= MAX_DEVIATION_SAMPLES + 3 * len(far)
    deviation = sc.outline.contour_deviation(far, outline.sources[0])
    assert np.isfinite(deviation).all() and deviation.max() > 9e4


@pytest.mark.parametrize("change, error, words", [
    ({"baseline": math.nan}, ValueError, "baseline must be a finite number"),
    ({"baseline": "12"}, TypeError, "baseline must be a real number"),
    ({"width": "abc"}, TypeError, "width must be a real number"),
    ({"width": True}, TypeError, "width must be a real number"),
    ({"name": 5}, TypeError, "name must be a string or None"),
    ({"sources": [[1.0, 2.0, 3.0]]}, ValueError, r"sources\[0\] must have shape \(M, 2\)"),
    ({"sources": [[[0.0, "a"]]]}, TypeError, r"sources\[0\] must be an \(M, 2\) array"),
    ({"version": 2}, ValueError, "version 2 is not read"),
])
def test_a_bad_outline_field_is_refused_when_read_not_at_export(change, error, words):
    """A NaN baseline in a JSON file reached font.build ("cannot convert float NaN to integer"), a name that is
    not a string to_svg, a source of the wrong shape the deviation."""
    data = json.loads(Outline([Contour(_loop(5, 1))]).to_json())
    data.update(change)
    with pytest.raises(error, match=words):
        Outline.from_json(json.dumps(data))


def test_from_trace_names_a_bad_iteration():
    """``from_trace(result, iteration=...)`` (also ``result.edit(iteration=...)``) indexed the snapshots
    unchecked: an iteration past the last was a bare ``IndexError: list index out of range``, a float a
    ``TypeError`` about list indices, and any iteration of a trace without snapshots an IndexError that did
    not say why. They are errors naming ``iteration``, the range and the way out."""
    yy, xx = np.mgrid[:40, :40] + 0.5
    mask = ((yy - 20) ** 2 / 300 + (xx - 20) ** 2 / 150 < 1) & ((yy - 20) ** 2 + (xx - 20) ** 2 > 30)
    result = sc.trace(mask, method="euclidean", seed=3)
    count = len(result.snapshots)
    assert count > 1
    first = as_outline(result, iteration=0)
    assert len(first) == len(result.splines)
    assert np.allclose(as_outline(result, iteration=-1).bezier()[0], as_outline(result, iteration=count - 1).bezier()[0])
    for bad in (count, -count - 1, 10**6):
        with pytest.raises(ValueError, match=rf"iteration={bad} is out of range: the trace has {count} snapshots"):
            as_outline(result, iteration=bad)
    for bad in (1.5, "2", True):
        with pytest.raises(TypeError, match="iteration must be an integer"):
            as_outline(result, iteration=bad)
    bare = sc.trace(mask, keep_snapshots=False)
    assert len(as_outline(bare)) == len(bare.splines)
    with pytest.raises(ValueError, match="kept no snapshots.*keep_snapshots=True"):
        as_outline(bare, iteration=0)


@pytest.mark.parametrize("value, error, words", [
    ("a", TypeError, "point_tension (v) must be a real number, got 'a' (str)"),
    (None, TypeError, "point_tension (v) must be a real number, got None (NoneType)"),  # was 'is nan'
    (True, TypeError, "point_tension (v) must be a real number, got True (bool)"),      # was taken as 1.0
    ([1, 2], TypeError, "point_tension (v) must be a real number, got [1, 2] (list)"),
    (float("inf"), ValueError, "point_tension (v) must be a finite number, got inf"),
])
def test_a_point_tension_edit_is_one_real_number(value, error, words):
    contour = Contour(_loop(6, 6))
    with pytest.raises(error) as caught:
        contour.with_point_tension(1, value)
    assert str(caught.value) == words


@pytest.mark.parametrize("value, error, words", [
    (0.0, ValueError, "interval_weights (omega) must be > 0, got 0.0"),
    (-1.0, ValueError, "interval_weights (omega) must be > 0, got -1.0"),
    (True, TypeError, "interval_weights (omega) must be a real number, got True (bool)"),
    (float("nan"), ValueError, "interval_weights (omega) must be a finite number > 0, got nan"),
])
def test_an_interval_weight_edit_is_refused_when_it_is_made(value, error, words):
    """A weight of 0 was taken, then refused by the interpolant of the knots between two corners, as 'knots 1..2
    (between two corners; indices below count from knot 1): interval_weights[0] = 0.0 must be > 0'."""
    contour = Contour(_loop(6, 6))
    with pytest.raises(error) as caught:
        contour.with_interval_weight(1, value)
    assert str(caught.value) == words


def test_forced_corners_follow_their_knots_when_a_short_curve_is_split():
    """A contour needs three knots: a curve of two pieces is split, and its corner flags stay on their knots."""
    from splinecraft.outline import from_bezier

    oval = np.array([[[0, 0], [0, -14], [40, -14], [40, 0]], [[40, 0], [40, 14], [0, 14], [0, 0]]], float)
    outline = from_bezier([oval], corners=[[True, True]])
    contour = outline.contours[0]
    flagged = {tuple(np.round(p, 9)) for p in contour.points[contour.corners]}
    assert flagged == {(0.0, 0.0), (40.0, 0.0)}
    with pytest.raises(ValueError, match="one flag per knot"):
        from_bezier([oval], corners=[[True, True, False]])


def test_contours_and_outlines_copy_and_pickle():
    """A Contour's __slots__ and immutable __setattr__ broke copy, deepcopy and pickle (of every Outline too)."""
    import copy
    import pickle

    from splinecraft.outline import as_outline

    outline = as_outline(sc.trace(datasets.thesis_object("D")))
    for again in (copy.copy(outline), copy.deepcopy(outline), pickle.loads(pickle.dumps(outline))):
        assert len(again) == len(outline) and again.width == outline.width
        for contour, copied in zip(outline.contours, again.contours):
            np.testing.assert_array_equal(copied.bezier(), contour.bezier())
            np.testing.assert_array_equal(copied.corners, contour.corners)
