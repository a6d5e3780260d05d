"""Curvature jumps (option ``curvature_jumps``; docs/capture.md §12, "Curvature jumps"): where a line runs into
an arc the fit of ``"lsq"`` gets a ``C^1`` knot. The detector is checked on exact Bézier chains built here (lines
and quarter circles, a circle, an ellipse), invariant under rigid motions; the fit on rounded rectangles and
stadiums rendered here, against their exact outlines and against the fit without the option.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from splinecraft.capture.contour import trace_boundaries
from splinecraft.capture.fitting import fit_outline
from splinecraft.capture.fitting.jumps import curvature_jumps
from splinecraft.capture.fitting.lsq_model import OutlineRegression
from splinecraft.capture.fitting.options import LSQ_DEFAULTS
from test_fitting import hausdorff

KAPPA = 4.0 * (np.sqrt(2.0) - 1.0) / 3.0  # handle length of the quarter-circle cubic, per unit radius


def _line(p, q):
    p, q = np.asarray(p, float), np.asarray(q, float)
    return np.array([p, p + (q - p) / 3.0, p + 2.0 * (q - p) / 3.0, q])


def _quarter(centre, radius, a0, a1):
    """The cubic of a quarter circle from angle ``a0`` to ``a1 = a0 +- pi/2`` (tangent handles of length
    ``KAPPA radius``)."""
    centre = np.asarray(centre, float)
    sign = np.sign(a1 - a0)
    p0 = centre + radius * np.array([np.cos(a0), np.sin(a0)])
    p3 = centre + radius * np.array([np.cos(a1), np.sin(a1)])
    t0 = sign * np.array([-np.sin(a0), np.cos(a0)])
    t3 = sign * np.array([-np.sin(a1), np.cos(a1)])
    return np.array([p0, p0 + KAPPA * radius * t0, p3 - KAPPA * radius * t3, p3])


def _chain(segments):
    """Bézier segments (k, 4, 2) and their parameter intervals: arc length (chord length for a line, the
    quarter arc's length for an arc)."""
    bezier = np.asarray(segments, float)
    lengths = np.array([np.hypot(*(b[3] - b[0])) if np.allclose(b[1], b[0] + (b[3] - b[0]) / 3.0)
                        else 0.5 * np.pi * np.hypot(*(b[1] - b[0])) / KAPPA for b in bezier])
    ends = np.cumsum(lengths)
    return bezier, ends - lengths, ends


def rounded_rectangle_chain(width, height, radius):
    w, h, r = width, height, radius
    segments = [_line((r, 0), (w - r, 0)), _quarter((w - r, r), r, -np.pi / 2, 0),
                _line((w, r), (w, h - r)), _quarter((w - r, h - r), r, 0, np.pi / 2),
                _line((w - r, h), (r, h)), _quarter((r, h - r), r, np.pi / 2, np.pi),
                _line((0, h - r), (0, r)), _quarter((r, r), r, np.pi, 1.5 * np.pi)]
    return _chain(segments)


def circle_chain(radius, pieces=8):
    angles = np.linspace(0.0, 2.0 * np.pi, pieces + 1)
    segments = []
    for a0, a1 in zip(angles[:-1], angles[1:]):  # arcs of 2 pi / pieces: handles 4/3 tan(theta / 4) r
        p0, p3 = radius * np.array([np.cos(a0), np.sin(a0)]), radius * np.array([np.cos(a1), np.sin(a1)])
        handle = 4.0 / 3.0 * np.tan((a1 - a0) / 4.0) * radius
        segments.append([p0, p0 + handle * np.array([-np.sin(a0), np.cos(a0)]),
                         p3 - handle * np.array([-np.sin(a1), np.cos(a1)]), p3])
    bezier = np.asarray(segments)
    lengths = np.full(pieces, 2.0 * np.pi * radius / pieces)
    ends = np.cumsum(lengths)
    return bezier, ends - lengths, ends


def _periodic_gap(a, b, period):
    gap = np.abs(a - b) % period
    return np.minimum(gap, period - gap)


# ------------------------------------------------------------------------------------------------ the detector

@pytest.mark.parametrize("width, height, radius", [(200, 120, 30), (600, 360, 60), (2400, 1500, 400)])
def test_line_arc_joins_are_found_and_nothing_else(width, height, radius):
    bezier, starts, ends = rounded_rectangle_chain(width, height, radius)
    values, scales = curvature_jumps(bezier, starts, ends, (), 0.8)
    joins = np.sort(np.concatenate([starts, [ends[-1]]])[:-1])  # every join is a line-arc join here
    period = ends[-1]
    assert values.shape[0] == joins.shape[0] == 8
    for v in values:
        assert _periodic_gap(joins, v, period).min() <= 2.0
    assert (scales >= 8).all()


@pytest.mark.parametrize("radius", [30.0, 150.0, 900.0])
def test_a_circle_has_no_jumps(radius):
    bezier, starts, ends = circle_chain(radius)
    values, _ = curvature_jumps(bezier, starts, ends, (), 0.8)
    assert values.shape[0] == 0


def test_an_ellipse_has_no_jumps():
    """Smoothly varying curvature (an ellipse, the affine image of the circle chain): a ramp, not a step."""
    bezier, starts, ends = circle_chain(100.0, pieces=16)
    bezier = bezier * np.array([2.2, 1.0])
    lengths = np.array([np.hypot(*np.diff(np.array([
        ((1 - t) ** 3) * b[0] + 3 * t * (1 - t) ** 2 * b[1] + 3 * t * t * (1 - t) * b[2] + t ** 3 * b[3]
        for t in np.linspace(0, 1, 200)]), axis=0).T).sum() for b in bezier])
    ends = np.cumsum(lengths)
    values, _ = curvature_jumps(bezier, ends - lengths, ends, (), 0.8)
    assert values.shape[0] == 0


@settings(max_examples=20, deadline=None)
@given(angle=st.floats(0.0, 2.0 * np.pi), shift=st.tuples(st.floats(-500, 500), st.floats(-500, 500)),
       mirror=st.booleans())
def test_jumps_are_invariant_under_rigid_motions(angle, shift, mirror):
    """The detector reads curvature against arc length only: a rotation, translation or reflection of the chain
    finds the same jumps at the same parameters."""
    bezier, starts, ends = rounded_rectangle_chain(400, 250, 50)
    reference, _ = curvature_jumps(bezier, starts, ends, (), 0.8)
    c, s = np.cos(angle), np.sin(angle)
    moved = bezier @ np.array([[c, s], [-s, c]]) + np.asarray(shift)
    if mirror:
        moved = moved * np.array([-1.0, 1.0])
    values, _ = curvature_jumps(moved, starts, ends, (), 0.8)
    assert values.shape == reference.shape
    np.testing.assert_allclose(values, reference, atol=1.0)


def test_windows_stay_inside_pieces():
    """With corners the windows never reach across one: a jump one window from a corner is not taken for one
    at the corner, and the corners themselves are not jumps."""
    bezier, starts, ends = rounded_rectangle_chain(600, 360, 60)
    corner_values = np.array([starts[0], starts[4]])  # two corners: the starts of the two long lines
    values, scales = curvature_jumps(bezier, starts, ends, corner_values, 0.8)
    assert values.shape[0] == 6  # the two joins at the corners are piece ends now
    assert _periodic_gap(corner_values[:, None], values[None, :], ends[-1]).min() > 8.0


def test_a_chain_too_short_has_no_jumps():
    bezier, starts, ends = rounded_rectangle_chain(12, 8, 3)
    values, scales = curvature_jumps(bezier, starts, ends, (), 0.8)
    assert values.shape == scales.shape == (0,)


# ------------------------------------------------------------------------------------------------- the fit

def render_rounded_rectangle(width, height, radius, offset=(0.31, 0.23)):
    """Crack outline of a rounded rectangle rendered at pixel centres (exact inside test) and its exact outline
    as dense points."""
    w, h, r = width, height, radius
    size = (int(np.ceil(h)) + 8, int(np.ceil(w)) + 8)
    origin = np.array([4.0 + offset[0], 4.0 + offset[1]])
    yy, xx = np.mgrid[0:size[0], 0:size[1]]
    x, y = xx + 0.5 - origin[0], yy + 0.5 - origin[1]
    qx, qy = np.clip(x, r, w - r), np.clip(y, r, h - r)
    mask = ((x - qx) ** 2 + (y - qy) ** 2 < r * r) & (x > 0) & (x < w) & (y > 0) & (y < h)
    bezier, starts, ends = rounded_rectangle_chain(w, h, r)
    t = np.linspace(0.0, 1.0, 400)[:, None]
    dense = np.concatenate([((1 - t) ** 3) * b[0] + 3 * t * (1 - t) ** 2 * b[1] + 3 * t * t * (1 - t) * b[2]
                            + t ** 3 * b[3] for b in bezier])
    return trace_boundaries(mask)[0].outline, dense + origin


def _deviation(bezier, dense):
    return hausdorff(bezier, dense)


@pytest.mark.parametrize("width, height, radius", [(300, 180, 40), (900, 560, 120)])
def test_a_rounded_rectangle_takes_a_jump_knot_at_each_line_arc_join(width, height, radius):
    outline, exact = render_rounded_rectangle(width, height, radius)
    plain = fit_outline(outline, [], keep_snapshots=False, curvature_jumps=False)
    fit = fit_outline(outline, [], keep_snapshots=False)
    record = fit.info["curvature_jumps"]
    assert record["kept"] and record["jumps"] >= 6
    assert fit.converged
    segments, plain_segments = fit.spline.bezier().shape[0], plain.spline.bezier().shape[0]
    assert segments == record["segments"] and plain_segments == record["segments_without"]
    assert segments < plain_segments
    assert segments <= 12  # 8 true segments (four lines, four quarter circles)
    assert _deviation(fit.spline.bezier(), exact) <= 1.0
    assert hausdorff(fit.spline.bezier(), outline) <= fit.epsilon + 1e-6


def test_a_stadium_needs_half_the_segments():
    """Two lines and two half circles (6 true segments) at 720 x 270 px: the C2 fit alone takes 20 segments,
    with C1 knots at the four jumps half as many (the half circles still take two or three cubics each)."""
    w, h = 720.0, 270.0
    r = h / 2
    size = (int(h) + 8, int(w) + 8)
    yy, xx = np.mgrid[0:size[0], 0:size[1]]
    x, y = xx + 0.5 - 4.37, yy + 0.5 - 4.21
    qx = np.clip(x, r, w - r)
    mask = (x - qx) ** 2 + (y - r) ** 2 < r * r
    outline = trace_boundaries(mask)[0].outline
    plain = fit_outline(outline, [], keep_snapshots=False, curvature_jumps=False)
    fit = fit_outline(outline, [], keep_snapshots=False)
    assert fit.converged
    assert 2 * fit.spline.bezier().shape[0] <= plain.spline.bezier().shape[0]
    assert fit.spline.bezier().shape[0] <= 12


def test_the_refit_is_kept_only_when_it_is_better():
    """A disc: curvature is constant, no jump is found, the fit is the one without the option."""
    size = 260
    yy, xx = np.mgrid[0:size, 0:size]
    mask = (xx + 0.5 - 130.3) ** 2 + (yy + 0.5 - 129.8) ** 2 < 110.0 ** 2
    outline = trace_boundaries(mask)[0].outline
    fit = fit_outline(outline, [], keep_snapshots=False)
    plain = fit_outline(outline, [], keep_snapshots=False, curvature_jumps=False)
    record = fit.info.get("curvature_jumps")
    if record is None:
        np.testing.assert_array_equal(fit.spline.bezier(), plain.spline.bezier())
    else:  # found something: kept only with fewer segments, or as many and closer
        assert (record["segments"], record["hausdorff"]) < (record["segments_without"], record["hausdorff_without"]) \
            or not record["kept"]
        assert fit.spline.bezier().shape[0] <= plain.spline.bezier().shape[0]


def _model(outline):
    options = dict(LSQ_DEFAULTS)
    model = OutlineRegression(outline, np.zeros(0, np.int64), 0.8, options)
    model.seed_knots(options["initial_density"])
    return model


def test_jump_knots_are_double_never_removed_and_clear_their_neighbours():
    outline, _ = render_rounded_rectangle(300, 180, 40)
    model = _model(outline)
    n = model.contour.size
    base = model.base_parameter
    model.seed_jumps([base[n // 3]], [16])
    assert model.jump_knots.shape == (1,) and abs(int(model.jump_knots[0]) - n // 3) <= 8
    multiplicity = model.inserted_multiplicity()
    jump = np.isin(model.simple_knots, model.jump_knots)
    assert (multiplicity[jump] == 2).all() and (multiplicity[~jump] == 1).all()
    assert model.knot_values().shape[0] == model.simple_knots.shape[0] + 1
    assert not model.removable_mask()[jump].any()
    others = model.simple_knots[~jump]  # the first knots within half the scale of the jump went
    gap = np.abs(base[others] - base[model.jump_knots[0]])
    assert (np.minimum(gap, model.period - gap) >= 8.0 - 1e-9).all()


def test_a_jump_beside_the_seam_moves_onto_it():
    """The seam knot 0 of an outline without corners starts the knot intervals and stays; a jump closer than
    min_gap to it becomes that knot (window half-width 2: the refinement on the contour moves it by one step at
    most)."""
    outline, _ = render_rounded_rectangle(300, 180, 40)
    model = _model(outline)
    n = model.contour.size
    model.seed_jumps([model.base_parameter[n - 1]], [2])
    assert model.jump_knots.tolist() == [0]
    assert model.inserted_multiplicity()[model.simple_knots == 0].tolist() == [2]


def test_without_merging_the_fit_stays_the_thesis_c2_fit():
    """``merge_tolerance=0`` gives the thesis's own C2 fit (docs/capture.md §12): no jump is looked for."""
    outline, _ = render_rounded_rectangle(900, 560, 120)
    unmerged = fit_outline(outline, [], keep_snapshots=False, merge_tolerance=0.0)
    plain = fit_outline(outline, [], keep_snapshots=False, merge_tolerance=0.0, curvature_jumps=False)
    assert "curvature_jumps" not in unmerged.info
    np.testing.assert_array_equal(unmerged.spline.bezier(), plain.spline.bezier())


def test_the_option_is_checked():
    outline, _ = render_rounded_rectangle(120, 80, 20)
    with pytest.raises(ValueError, match="curvature_jumps"):
        fit_outline(outline, [], curvature_jumps="yes")
    with pytest.raises(ValueError, match="curvature_jumps"):
        fit_outline(outline, [], curvature_jumps=1)
    with pytest.raises(TypeError, match="curvature_jumps"):
        fit_outline(outline, [], curvature_jumps=["smooth"])


def test_by_default_only_outlines_without_corners_are_refitted():
    """``"smooth"`` (the default) leaves an outline with corners as the C2 fit and merging make it; ``True``
    refits it too: the rounded rectangle with two of its straight sides' ends made corners."""
    outline, _ = render_rounded_rectangle(900, 560, 120)
    n = outline.shape[0]
    corners = [0, n // 2]
    default = fit_outline(outline, corners, keep_snapshots=False)
    everywhere = fit_outline(outline, corners, keep_snapshots=False, curvature_jumps=True)
    plain = fit_outline(outline, corners, keep_snapshots=False, curvature_jumps=False)
    assert "curvature_jumps" not in default.info
    np.testing.assert_array_equal(default.spline.bezier(), plain.spline.bezier())
    record = everywhere.info["curvature_jumps"]
    assert record["jumps"] >= 4 and record["segments_without"] == plain.spline.bezier().shape[0]
    assert everywhere.spline.bezier().shape[0] <= plain.spline.bezier().shape[0]


def test_the_refit_counts_the_segments_of_the_pieces_with_jumps_only():
    """``REFIT_MARGIN`` is measured in the pieces between corners that hold a jump: segments elsewhere (a
    glyph's serifs) cannot be saved by a C1 knot there."""
    from types import SimpleNamespace

    from splinecraft.capture.fitting.lsq import _segments_beside

    outline, _ = render_rounded_rectangle(300, 180, 40)
    n = outline.shape[0]
    corners = np.array([0, n // 4, n // 2])
    model = OutlineRegression(outline, corners, 0.8, dict(LSQ_DEFAULTS))
    bounds = model.contour.corner_bounds
    # pieces of 5, 2 and 7 segments
    knots = [np.linspace(bounds[k], bounds[k + 1], count + 1).astype(int) for k, count in enumerate((5, 2, 7))]
    result = SimpleNamespace(knot_indices=knots)
    middle = lambda k: 0.5 * (model.base_parameter[bounds[k]] + model.base_parameter[bounds[k + 1]])  # noqa: E731
    assert _segments_beside(model, result, np.array([middle(1)])) == 2
    assert _segments_beside(model, result, np.array([middle(0), middle(2)])) == 12
    assert _segments_beside(model, result, np.array([middle(0), middle(0) + 1.0])) == 5
    cornerless = OutlineRegression(outline, np.zeros(0, np.int64), 0.8, dict(LSQ_DEFAULTS))
    assert _segments_beside(cornerless, SimpleNamespace(knot_indices=[np.arange(10)]), np.array([3.0])) == 9


def test_jumps_are_measured_only_where_a_refit_can_follow(monkeypatch):
    """A refit needs ``REFIT_MARGIN`` segments more than jumps, so a converged fit of at most ``REFIT_MARGIN``
    segments (a disc's four) is never measured for jumps, and its result is the same as without the option; the
    stadium (20 segments before its refit) is measured once."""
    from splinecraft.capture.fitting import lsq
    from splinecraft.capture.fitting.jumps import REFIT_MARGIN

    calls = []
    measure = lsq.curvature_jumps
    monkeypatch.setattr(lsq, "curvature_jumps", lambda *args, **kw: calls.append(args) or measure(*args, **kw))
    yy, xx = np.mgrid[0:120, 0:120]
    disc = trace_boundaries((xx + 0.5 - 60.3) ** 2 + (yy + 0.5 - 59.8) ** 2 < 45.0 ** 2)[0].outline
    fit = fit_outline(disc, [], keep_snapshots=False)
    assert fit.converged and fit.spline.bezier().shape[0] <= REFIT_MARGIN
    assert calls == [] and "curvature_jumps" not in fit.info
    np.testing.assert_array_equal(fit.spline.bezier(),
                                  fit_outline(disc, [], keep_snapshots=False, curvature_jumps=False).spline.bezier())
    outline, _ = render_rounded_rectangle(300, 180, 40)
    fit = fit_outline(outline, [], keep_snapshots=False)
    assert len(calls) == 1 and fit.info["curvature_jumps"]["jumps"] >= 1
