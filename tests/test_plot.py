"""splinecraft.plot: round ticks, equal-aspect geometry figures, legends outside the data, the curvature
profile κ(t) with its one-sided jumps, the comb, and the live basis / convergence plots."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import splinecraft as sc

bq = pytest.importorskip("bqplot")
plot = sc.plot

HEART = sc.datasets.sample_points("heart")


def _is_round_step(step):
    """1, 2 or 5 times a power of ten."""
    mantissa = step / 10.0 ** math.floor(math.log10(step) + 1e-12)
    return any(abs(mantissa - m) < 1e-6 for m in (1.0, 2.0, 5.0, 10.0))   # float spacing at 1e6: ~1e-10


# ---------------------------------------------------------------------------------------------------- ticks
@settings(max_examples=300, deadline=None)
@given(low=st.floats(-1e6, 1e6), span=st.floats(1e-6, 1e6), count=st.integers(2, 10))
def test_nice_ticks_are_round_and_inside(low, span, count):
    assume(span > 1e-7 * abs(low))                 # an axis range well above float resolution
    high = low + span
    ticks = plot.nice_ticks(low, high, count)
    assert len(ticks) >= 2
    assert ticks[0] >= low - 1e-9 * span and ticks[-1] <= high + 1e-9 * span
    steps = np.diff(ticks)
    assert np.allclose(steps, steps[0], rtol=1e-6)
    assert _is_round_step(steps[0])
    assert np.allclose(ticks / steps[0], np.round(ticks / steps[0]), atol=1e-6)   # multiples of the step
    assert len(ticks) <= 3 * count + 1


def test_nice_ticks_fix_the_unround_axes_of_the_old_figures():
    assert plot.nice_ticks(-0.0038, 0.97, 5).tolist() == [0.0, 0.2, 0.4, 0.6, 0.8]
    assert plot.nice_ticks(27, 218, 3).tolist() == [50.0, 100.0, 150.0, 200.0]
    assert all(np.signbit(plot.nice_ticks(-0.3, 0.3)) == (plot.nice_ticks(-0.3, 0.3) < 0))   # no "-0"


@settings(max_examples=200, deadline=None)
@given(exponent=st.floats(-8, 6), decades=st.floats(0.05, 8))
def test_log_ticks_are_powers_of_ten_or_their_2_5_multiples(exponent, decades):
    low, high = 10.0 ** exponent, 10.0 ** (exponent + decades)
    ticks = plot.log_ticks(low, high)
    assert len(ticks) >= 2 and np.all(np.diff(ticks) > 0)
    assert ticks[0] >= low * (1 - 1e-9) and ticks[-1] <= high * (1 + 1e-9)
    mantissas = ticks / 10.0 ** np.floor(np.log10(ticks) + 1e-12)
    multiples = np.all(np.isclose(mantissas[:, None], np.arange(1, 10)).any(axis=1))
    assert multiples or (decades < 1.0 and _is_round_step(float(np.diff(ticks)[0])))   # short: linear steps
    if decades >= 3.0:
        assert np.allclose(mantissas, 1.0)                         # several decades: 1, 10, 100 only
    assert len(ticks) <= max(7, decades + 2)


def test_log_ticks_and_formats():
    assert plot.log_ticks(0.3, 2000).tolist() == [1.0, 10.0, 100.0, 1000.0]
    assert plot.log_ticks(0.5, 3.0).tolist() == [0.5, 1.0, 2.0]
    assert plot.tick_format([1.0, 10.0, 100.0], log=True) == "~g"
    assert plot.tick_format([1e-6, 1e-3, 1.0], log=True) == ".0e"
    assert plot.tick_format([0.0, 0.2, 0.4]) == ".1f"
    assert plot.tick_format([0.0, 0.05, 0.1]) == ".2f"
    assert plot.tick_format([0.0, 500.0, 1000.0]) == ".0f"
    with pytest.raises(ValueError, match="log axis"):
        plot.log_ticks(0.0, 1.0)
    with pytest.raises(ValueError, match="finite"):
        plot.nice_ticks(0.0, float("nan"))


def test_nice_limits_enclose_the_data_on_round_values():
    low, high = plot.nice_limits(0.013, 0.87, 5)
    assert low <= 0.013 and high >= 0.87 and (low, high) == (0.0, 1.0)
    assert plot.nice_limits(3.0, 3.0)[0] < 3.0 < plot.nice_limits(3.0, 3.0)[1]


# ---------------------------------------------------------------------------------------------------- figures
def _plot_area(fig):
    width, height = (float(fig.layout.width[:-2]), float(fig.layout.height[:-2]))
    margin = fig.fig_margin
    return width - margin["left"] - margin["right"], height - margin["top"] - margin["bottom"]


def _legend_labels(fig):
    return [mark for mark in fig.marks if isinstance(mark, bq.Label)]


def test_figure_has_equal_scales_round_ticks_and_y_down():
    spline = sc.interpolate(HEART, closed=True)
    fig = plot.figure(plot.polygon(HEART, closed=True), plot.comb(spline), plot.curve(spline), plot.points(HEART),
                      title="heart", width=400, height=300)
    assert isinstance(fig, bq.Figure) and fig.title == "heart"
    x_axis, y_axis = fig.axes
    x_scale, y_scale = x_axis.scale, y_axis.scale
    area_w, area_h = _plot_area(fig)
    assert np.isclose((x_scale.max - x_scale.min) / area_w, (y_scale.max - y_scale.min) / area_h)   # equal aspect
    assert y_scale.reverse                                      # y down, as in the widgets and bitmaps
    assert x_scale.min <= HEART[:, 0].min() and x_scale.max >= HEART[:, 0].max()
    for axis in fig.axes:
        ticks = np.asarray(axis.tick_values)
        assert len(ticks) >= 2 and _is_round_step(float(np.diff(ticks)[0]))
        assert axis.scale.min <= ticks.min() and ticks.max() <= axis.scale.max
    data_marks = [mark for mark in fig.marks if not isinstance(mark, bq.Label)]
    assert len(data_marks) == 4 and all(mark.apply_clip for mark in data_marks)
    assert not _legend_labels(fig)                              # nothing labelled: no legend, slim margin


def test_legend_stands_in_the_right_margin_outside_the_data():
    spline = sc.interpolate(HEART, closed=True)
    fig = plot.figure(plot.curve(spline, label="curve"), plot.polygon(HEART, closed=True, label="data polygon"),
                      plot.points(HEART, label="points"), width=480, height=300)
    swatches, texts = _legend_labels(fig)
    assert list(texts.text) == ["curve", "data polygon", "points"]
    assert list(swatches.colors) == [plot.PALETTE[0], "#90a4ae", "#263238"]
    assert len(set(swatches.text)) == 3                          # solid, dashed and dot swatches differ
    for label in (swatches, texts):
        assert not label.apply_clip and label.scales["x"].min == 0.0 and label.scales["x"].max == 1.0
        assert np.all(np.asarray(label.x) == 1.0) and label.x_offset > 0   # right of the plot area's edge
    longest = max(len(text) for text in texts.text)
    assert fig.fig_margin["right"] >= texts.x_offset + 6 * longest       # the margin holds the labels


def test_figure_bounds_zoom_and_bad_input():
    fig = plot.figure(plot.line(HEART, closed=True), bounds=(100, 50, 300, 250), width=300, height=300)
    x_scale, y_scale = fig.axes[0].scale, fig.axes[1].scale
    assert x_scale.min <= 100 and x_scale.max >= 300 and y_scale.min <= 50 and y_scale.max >= 250
    assert (x_scale.max - x_scale.min) < 1.2 * 200
    with pytest.raises(TypeError, match="Layer"):
        plot.figure(HEART)
    with pytest.raises(ValueError, match="width"):
        plot.figure(plot.points(HEART), width=10)
    with pytest.raises(ValueError, match="shape"):
        plot.line(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="kind"):
        plot.Layer("bars", np.zeros((2, 2)))
    with pytest.raises(ValueError, match="columns"):
        plot.grid(fig, columns=0)
    with pytest.raises(TypeError, match="Spline"):
        plot.curve(HEART)


def test_chart_log_axis_reads_in_decades_and_drops_non_positive_values():
    iterations = np.arange(30)
    error = 300 * 0.7 ** iterations
    error[5] = 0.0
    fig = plot.chart(plot.line(np.c_[iterations, error], label="max error"), log_y=True, xlabel="iteration")
    y_axis = fig.axes[1]
    assert isinstance(y_axis.scale, bq.LogScale)
    ticks = np.asarray(y_axis.tick_values)
    assert np.allclose(np.log10(ticks), np.round(np.log10(ticks)))          # 0.01, 0.1, 1, 10, 100 ...
    assert y_axis.scale.min <= error[error > 0].min() and y_axis.scale.max >= error.max()
    line = next(mark for mark in fig.marks if isinstance(mark, bq.Lines))
    assert np.all(np.asarray(line.y) > 0) and len(line.y) == 29
    assert fig.axes[0].tick_format == ".0f"


def test_basis_figure_and_table():
    t = np.linspace(0, 8, 401)
    values = sc.basis_functions(t, 8, closed=True).toarray()
    fig = plot.basis_figure(t, values, labels=[f"B{j}" for j in range(8)])
    lines = [mark for mark in fig.marks if isinstance(mark, bq.Lines)]
    assert len(lines) == 9 and lines[-1].line_style == "dashed"
    np.testing.assert_allclose(np.asarray(lines[-1].y), 1.0, atol=1e-12)   # the sum line
    assert fig.axes[0].scale.min == 0.0 and fig.axes[0].scale.max == 8.0
    with pytest.raises(ValueError, match="labels"):
        plot.basis_figure(t, values, labels=["B0"])
    markdown = plot.table(["a", "b|c"], [[1.23456789, "x"], [2, 3]], digits=3)
    assert markdown.data.splitlines() == ["| a | b\\|c |", "| --- | --- |", "| 1.23 | x |", "| 2 | 3 |"]
    with pytest.raises(ValueError, match="row"):
        plot.table(["a"], [[1, 2]])


# ---------------------------------------------------------------------------------------------------- comb
def test_comb_teeth_follow_the_engine_comb_and_are_capped():
    spline = sc.interpolate(HEART, closed=True)
    teeth = plot.comb_teeth(spline, relative_length=0.1, samples_per_segment=12)
    base, tips = spline.curvature_comb(scale=1.0, samples_per_segment=12)
    np.testing.assert_allclose(teeth[:, 0], base)
    drawn, engine = teeth[:, 1] - teeth[:, 0], tips - base
    cross = drawn[:, 0] * engine[:, 1] - drawn[:, 1] * engine[:, 0]
    assert np.allclose(cross, 0.0, atol=1e-9 * np.abs(engine).max() * np.abs(drawn).max())   # same direction
    assert np.all((drawn * engine).sum(axis=1) >= 0)
    ratio = np.linalg.norm(drawn, axis=1) / np.maximum(np.linalg.norm(engine, axis=1), 1e-300)
    size = np.ptp(base, axis=0).max()
    cap = plot._layers.COMB_CAP
    capped = np.linalg.norm(drawn, axis=1) >= cap * 0.1 * size * (1 - 1e-9)
    assert np.allclose(ratio[~capped], ratio[~capped][0])         # one scale for every uncapped tooth
    assert np.linalg.norm(drawn, axis=1).max() <= cap * 0.1 * size * (1 + 1e-9)
    assert np.isclose(np.percentile(np.linalg.norm(drawn, axis=1), 90), 0.1 * size, rtol=0.05)


# ---------------------------------------------------------------------------------------------------- κ(t)
def _reference_curvature(spline, t):
    """κ from scipy's piecewise polynomial of the same curve (an independent evaluation)."""
    ppoly = spline.to_ppoly()
    first, second = ppoly.derivative(1)(t), ppoly.derivative(2)(t)
    return (first[..., 0] * second[..., 1] - first[..., 1] * second[..., 0]) / np.hypot(*np.moveaxis(first, -1, 0)) ** 3


@settings(max_examples=25, deadline=None)
@given(weights=st.lists(st.sampled_from([1.0, 1.0, 1.0, 2.0, 5.0]), min_size=12, max_size=12))
def test_curvature_profile_jumps_exactly_where_interval_weights_change(weights):
    """E2: κ(tᵢ⁺)/κ(tᵢ⁻) = ωᵢ₋₁/ωᵢ, so the joints that jump are those between unequal weights."""
    spline = sc.interpolate(HEART, closed=True, interval_weights=weights)
    profile = plot.curvature_profile(spline, samples_per_piece=16)
    m = spline.n_segments
    assert profile["joints"].tolist() == list(range(1, m + 1))                 # a loop: the closing joint too
    expected = [weights[(i - 1) % m] != weights[i % m] for i in profile["joints"]]
    assert profile["jumps"].tolist() == expected
    ratio = profile["right"] / profile["left"]
    omega = np.asarray(weights)
    np.testing.assert_allclose(ratio, omega[(profile["joints"] - 1) % m] / omega[profile["joints"] % m], rtol=1e-6)


def test_curvature_profile_matches_scipy_and_the_one_sided_limits():
    spline = sc.interpolate(HEART[:7], interval_weights=[1, 3, 1, 1, 2, 1])
    profile = plot.curvature_profile(spline, samples_per_piece=10)
    t, kappa = profile["t"], profile["kappa"]
    assert t.shape == kappa.shape == (spline.n_segments, 10)
    np.testing.assert_allclose(kappa[:, 1:-1], _reference_curvature(spline, t[:, 1:-1]), rtol=1e-7, atol=1e-12)
    assert profile["joints"].tolist() == list(range(1, spline.n_segments))     # open: interior knots only
    joint = spline.joint_curvature()
    np.testing.assert_allclose(profile["left"], joint[1:-1, 0])
    np.testing.assert_allclose(profile["right"], joint[1:-1, 1])
    np.testing.assert_allclose(kappa[:-1, -1], joint[1:-1, 0], rtol=1e-9)   # a piece ends in its left limit
    np.testing.assert_allclose(kappa[1:, 0], joint[1:-1, 1], rtol=1e-9)     # and starts in its right limit
    assert profile["jumps"].tolist() == [True, True, False, True, True]


def test_curvature_figure_marks_the_jumps():
    spline = sc.interpolate(HEART, closed=True, interval_weights=np.r_[1, 1, 5, np.ones(9)])
    fig = plot.curvature_figure(spline, width=600)
    assert isinstance(fig, bq.Figure) and "2 of 12 joints jump" in fig.title
    live = plot.CurvaturePlot().show(spline)
    bars = np.asarray(live.jump_bars.y) / live.display_scale
    profile = live.profile
    np.testing.assert_allclose(bars, np.c_[profile["left"], profile["right"]][profile["jumps"]])
    assert live.display_scale >= 1 and np.log10(live.display_scale) == int(np.log10(live.display_scale))
    y_ticks = np.asarray(live.y_axis.tick_values)
    assert _is_round_step(float(np.diff(y_ticks)[0]))
    colors = np.asarray(live.joint_dots.colors)
    assert (colors == "#d32f2f").sum() == 4                     # both one-sided dots of the two jumping joints
    smooth = plot.CurvaturePlot().show(sc.interpolate(HEART, closed=True))
    assert "G² at all 12 joints" in smooth.figure.title and not smooth.jump_bars.visible


def test_curvature_axis_cuts_near_cusp_peaks_but_keeps_the_jumps():
    """Uniform knots on the heart: κ ≈ -160/px at the notch would flatten the rest of the profile."""
    spline = sc.interpolate(HEART, closed=True, knots="uniform", interval_weights=np.r_[1, 1, 10, np.ones(9)])
    live = plot.CurvaturePlot().show(spline)
    profile = live.profile
    low, high = live.y_scale.min / live.display_scale, live.y_scale.max / live.display_scale
    assert live.clipped and "off the axis" in live.figure.title
    assert np.abs(profile["kappa"]).max() > 3 * (high - low)
    assert np.mean((profile["kappa"] >= low) & (profile["kappa"] <= high)) > 0.9
    jumping = np.r_[profile["left"][profile["jumps"]], profile["right"][profile["jumps"]]]
    assert np.all((jumping >= low) & (jumping <= high)) and low <= 0 <= high


def test_curvature_profile_bad_input():
    with pytest.raises(TypeError, match="Spline"):
        plot.curvature_profile(HEART)
    space = sc.Spline(np.random.default_rng(0).random((1, 4, 3)), [0.0, 1.0])
    with pytest.raises(ValueError, match="planar"):
        plot.curvature_profile(space)
    with pytest.raises(ValueError, match="samples_per_piece"):
        plot.curvature_profile(sc.interpolate(HEART, closed=True), samples_per_piece=1)


# ---------------------------------------------------------------------------------------------------- traces
@pytest.fixture(scope="module")
def small_trace():
    return sc.trace(sc.datasets.shape("blob", 64), epsilon=1.0, method="random", seed=1)


def test_outline_layers_and_figure(small_trace):
    layers = plot.outline(small_trace, 0)
    contours = [layer for layer in layers if layer.kind == "line"]
    assert len(contours) == len(small_trace.points)
    pieces = next(layer for layer in layers if layer.kind == "lines")
    assert pieces.xy.shape[0] == len(small_trace.snapshots[0].bezier)
    np.testing.assert_allclose(pieces.xy[:, 0], small_trace.snapshots[0].bezier[:, 0])   # pieces start on F_i
    fig = plot.outline_figure(small_trace)
    assert f"{small_trace.snapshots[-1].knots} knots" in fig.title
    with pytest.raises(TypeError, match="TraceResult"):
        plot.outline(HEART)
    image = plot.bitmap(sc.datasets.shape("blob", 64), height=80)
    assert image.format == "png" and image.value[:4] == b"\x89PNG"


def test_convergence_plot_has_round_axes_and_the_legend_beside_the_error_axis(small_trace):
    live = plot.ConvergencePlot()
    live.show(small_trace, 1.0, current=2)
    iterations = np.asarray(live.x_axis.tick_values)
    assert np.all(iterations == np.round(iterations)) and len(iterations) >= 2
    error_ticks = np.asarray(live.error_axis.tick_values)
    mantissas = error_ticks / 10.0 ** np.floor(np.log10(error_ticks) + 1e-12)
    assert np.all(np.isclose(mantissas[:, None], [1.0, 2.0, 5.0]).any(axis=1))
    assert live.error_scale.min <= error_ticks.min() and error_ticks.max() <= live.error_scale.max
    knot_ticks = np.asarray(live.knot_axis.tick_values)
    assert np.all(knot_ticks == np.round(knot_ticks)) and live.knot_scale.max >= max(s.knots for s in small_trace.snapshots)
    assert list(live.current.x) == [float(small_trace.snapshots[2].iteration)] * 2
    swatches, texts = _legend_labels(live.figure)
    assert texts.x_offset > live.figure.fig_margin["left"] // 2          # clear of the right axis's labels
    assert live.figure.fig_margin["right"] > texts.x_offset


def test_basis_plot_without_an_editor():
    live = plot.BasisPlot()
    live.show("basis", HEART, point_tension=0.0, interval_weights=1.0, alpha=2.0, beta=2.0, closed=True,
              knots="uniform", end_condition="floating", selected=3)
    t = np.asarray(live.lines.x)
    np.testing.assert_allclose(np.asarray(live.lines.y), sc.basis_functions(t, len(HEART), closed=True).toarray().T,
                               atol=1e-12)
    ticks = np.asarray(live.x_axis.tick_values)
    assert _is_round_step(float(np.diff(ticks)[0])) and live.highlight.visible
    live.show("basis", HEART[:2], point_tension=0.0, interval_weights=1.0, alpha=2.0, beta=2.0, closed=False,
              knots="uniform", end_condition="floating")
    assert live.error and "at least 4" in live.figure.title


@pytest.mark.parametrize("knots", ["uniform", "chord", "centripetal"])
@pytest.mark.parametrize("closed, ends", [(False, "clamped"), (False, "floating"), (True, None)])
def test_the_basis_plot_runs_over_the_curves_own_domain(knots, closed, ends):
    """Uniform clamped knots run over [1, n - 2], as basis_spline's curve does (the plot took [0, n - 3] and
    refused every such state); and the plotted basis times the control points is that curve."""
    from splinecraft.plot.basis import basis_knot_values

    points = sc.datasets.sample_points("pot")
    curve = sc.basis_spline(points, knots=knots, closed=True) if closed else \
        sc.basis_spline(points, knots=knots, ends=ends)
    assert np.allclose(basis_knot_values(points, knots, closed, ends or "clamped")[1], curve.domain)
    data = sc.plot.basis_plot_data("basis", points, point_tension=0.0, interval_weights=1.0, alpha=3.0, beta=3.0,
                                   closed=closed, knots=knots, end_condition=ends)
    assert np.allclose(data["values"].sum(axis=0), 1.0)
    assert data["t"][0] == pytest.approx(curve.domain[0]) and data["t"][-1] == pytest.approx(curve.domain[1])


@pytest.mark.parametrize("make", [lambda p: sc.interpolate(p, closed=True), lambda p: sc.basis_spline(p, closed=True),
                                  lambda p: sc.interpolate(p)])
def test_auxiliary_polygons_of_closed_and_open_curves(make):
    """A closed curve keeps one F per piece (not repeated): the polygons wrap round to F_0."""
    points = sc.datasets.sample_points("pot")
    spline = make(points)
    layer = sc.plot.auxiliary_polygons(spline)
    polygons = np.asarray(layer.xy)
    F = np.asarray(spline.auxiliary["F"])
    assert polygons.shape == (spline.n_segments, 4, 2)
    np.testing.assert_allclose(polygons[:, 0], F[:spline.n_segments])
    np.testing.assert_allclose(polygons[:, 3], np.roll(F, -1, axis=0)[:spline.n_segments] if spline.closed else F[1:])


@pytest.mark.parametrize("low, span", [(1e6, 500.0), (1e9, 500.0), (-3e7, 60.0), (0.0, 3e6), (0.0, 5e-25)])
def test_tick_formats_tell_large_or_tiny_ticks_apart(low, span):
    """At 1e6 and beyond the SI format had two significant digits whatever the step: a 500-unit shape at 1e6
    had every tick labelled "1M". The format's precision (significant digits for ~s and ~e, d3 rounds to them)
    now keeps every tick distinct, and fixed decimals stay within d3's cap of 20."""
    import re

    ticks = plot.nice_ticks(low, low + span, 6)
    spec = plot.tick_format(ticks)
    kind, precision = re.fullmatch(r"\.(\d+)(~s|~e|f)", spec).group(2), int(re.fullmatch(r"\.(\d+).*", spec).group(1))
    if kind == "f":
        assert precision <= 20
        shown = {f"{value:.{precision}f}" for value in ticks}
    else:
        shown = {f"{value:.{precision if kind == '~s' else precision + 1}g}" for value in ticks}
    assert len(shown) == len(ticks)


@pytest.mark.parametrize("scale", [1e5, 1e7, 1e9])
def test_the_comb_of_a_scaled_curve_is_the_scaled_comb(scale):
    """Teeth of scale 1 (about 1 / size) vanished in the rounding of bases at large coordinates (65 % off at
    1e6, NaN from 1e7)."""
    points = sc.datasets.sample_points("pot")
    unit = sc.interpolate(points / np.ptp(points, axis=0).max(), closed=True)
    far = sc.interpolate(points / np.ptp(points, axis=0).max() * scale + scale, closed=True)
    near_teeth, far_teeth = plot.comb_teeth(unit), plot.comb_teeth(far)
    assert np.isfinite(far_teeth).all()
    np.testing.assert_allclose((far_teeth[:, 1] - far_teeth[:, 0]) / scale, near_teeth[:, 1] - near_teeth[:, 0],
                               atol=1e-9 * np.abs(near_teeth[:, 1] - near_teeth[:, 0]).max())


def test_a_legend_too_wide_for_the_figure_is_named():
    """A long label's legend took the plot's width: spline_figure blamed width and height, chart drew a plot of
    negative width."""
    spline = sc.interpolate(sc.datasets.sample_points("pot"))
    label = "a label much longer than the figure holds beside its plot"
    with pytest.raises(ValueError, match="the legend takes .* shorten the labels or widen the figure"):
        plot.spline_figure(spline, label=label)
    with pytest.raises(ValueError, match="the legend takes"):
        plot.chart(plot.line(np.c_[np.arange(5.0), np.arange(5.0)], label=label), width=330, height=260)
    with pytest.raises(ValueError, match="width and height leave no room"):
        plot.chart(plot.line(np.c_[np.arange(5.0), np.arange(5.0)]), width=330, height=80)
    assert plot.chart(plot.line(np.c_[np.arange(5.0), np.arange(5.0)], label=label), width=900, height=260)


@pytest.mark.parametrize("low, high", [(-1e308, 1e308), (0.0, 5e-324), (1e-300, 2e-300), (0.1, 0.1 + 3e-17),
                                       (-3.0, 7.0)])
def test_nice_ticks_on_extreme_finite_ranges(low, high):
    """The span of -1e308 .. 1e308 overflowed (2e308 ticks asked for), a subnormal one took log10 of 0, a span
    below the numbers' resolution gave repeated ticks: finite, strictly increasing, inside, at least two."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow on the way either
        ticks = plot.nice_ticks(low, high, 5)
    assert np.isfinite(ticks).all() and len(ticks) >= 2 and (np.diff(ticks) > 0).all()
    assert ticks[0] >= low and ticks[-1] <= high


@pytest.mark.parametrize("scale", [1.0, 1e-9, 1e-15, 1e9])
def test_figure_frames_a_curve_at_any_scale(scale):
    """plot.figure fits every layer: its span had an absolute floor of 1e-9, so a curve 1e-15 across was a speck;
    a single point still gets a frame around it."""
    spline = sc.interpolate(sc.datasets.sample_points("pot") * scale)
    fig = plot.figure(plot.curve(spline))
    xs = fig.marks[0].x
    x_scale = fig.axes[0].scale
    filled = (np.max(xs) - np.min(xs)) / (x_scale.max - x_scale.min)
    assert filled > 0.5
    point = plot.figure(plot.points([[3.0 * scale, 4.0 * scale]]))
    assert point.axes[0].scale.max > point.axes[0].scale.min
