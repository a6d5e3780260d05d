"""Spline queries: nearest point, de Casteljau construction, curvature profile, legs; the relative
basis tension; the one SVG writer; the JSON helper."""
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

import splinecraft as sc
from splinecraft import _json
from splinecraft.spline import svg
from splinecraft.spline.basis import tension_spans
from splinecraft.spline.piecewise import Spline

FAST = settings(max_examples=40, deadline=None)


def walk(seed, count, closed=False):
    rng = np.random.default_rng(seed)
    steps = rng.normal(size=(count, 2))
    steps /= np.linalg.norm(steps, axis=1)[:, None]
    points = np.cumsum(steps * rng.uniform(0.3, 2.0, size=(count, 1)), axis=0)
    return points


def curves(seed):
    points = walk(seed, 7)
    yield sc.interpolate(points)
    yield sc.interpolate(points, closed=True, interval_weights=np.linspace(0.5, 2.0, 7))
    yield sc.basis_spline(points, knots="chord")
    yield sc.timmer_gc1(points)
    yield sc.generic_segment(points[0], points[1], points[2], points[3], 4.0, 2.0)


def brute_force_nearest(spline, target):
    """Dense sampling, then a bounded scalar minimisation per piece around the best sample."""
    best = (math.inf, None)
    knots = spline.knots
    for i in range(spline.n_segments):
        ts = np.linspace(knots[i], knots[i + 1], 2001)
        distances = np.linalg.norm(spline(ts) - target, axis=1)
        k = int(np.argmin(distances))
        lo, hi = ts[max(k - 1, 0)], ts[min(k + 1, len(ts) - 1)]
        result = minimize_scalar(lambda t: float(np.linalg.norm(spline(t) - target)), bounds=(lo, hi),
                                 method="bounded", options={"xatol": 1e-13})
        value = min(float(result.fun), float(distances[k]))
        if value < best[0]:
            best = (value, i)
    return best


@FAST
@given(st.integers(0, 10_000), st.floats(-3, 3), st.floats(-3, 3))
def test_nearest_matches_brute_force(seed, dx, dy):
    for spline in curves(seed % 50):
        target = spline.knot_points.mean(axis=0) + np.array([dx, dy])
        found = spline.nearest(target)
        reference, _ = brute_force_nearest(spline, target)
        assert found.distance <= reference + 1e-9
        assert found.distance >= reference - 1e-7 * max(1.0, reference)
        np.testing.assert_allclose(spline(found.parameter), found.point, atol=1e-9)
        assert abs(np.linalg.norm(found.point - target) - found.distance) <= 1e-9
        lo, hi = spline.knots[found.piece], spline.knots[found.piece + 1]
        assert lo <= found.parameter <= hi


@pytest.mark.parametrize("scale", [1e-250, 1e-6, 1.0, 1e8, 1e250])
def test_nearest_at_any_scale(scale):
    unit = sc.interpolate(walk(3, 6))
    target = np.array([0.3, 0.7])
    reference = unit.nearest(target)
    scaled = unit.transformed(np.eye(2) * scale)
    found = scaled.nearest(target * scale)
    assert found.piece == reference.piece
    assert found.parameter == pytest.approx(reference.parameter, rel=1e-9)
    assert found.distance == pytest.approx(reference.distance * scale, rel=1e-9)


def test_nearest_on_the_curve_and_bad_points():
    spline = sc.interpolate(walk(1, 5), closed=True)
    for t in np.linspace(*spline.domain, 13)[:-1]:
        found = spline.nearest(spline(t))
        assert found.distance <= 1e-12 * 10
    with pytest.raises(ValueError, match="point must have 2 coordinates"):
        spline.nearest([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"point\[1\] is nan"):
        spline.nearest([1.0, math.nan])
    with pytest.raises(TypeError, match="point must be numeric"):
        spline.nearest("1,2")


def test_construction_levels():
    for spline in curves(4):
        t0, tm = spline.domain
        for t in np.linspace(t0, tm, 9):
            c = spline.construction(t)
            assert [level.shape[0] for level in c.levels] == [4, 3, 2, 1]
            np.testing.assert_allclose(c.point, spline(min(c.parameter, tm)), atol=1e-12)
            np.testing.assert_allclose(c.tangent, spline(min(c.parameter, tm), nu=1), atol=1e-9)
            np.testing.assert_array_equal(c.levels[0], spline.bezier()[c.piece])
            for upper, lower in zip(c.levels[:-1], c.levels[1:]):  # each level interpolates the one before
                np.testing.assert_allclose(lower, (1 - c.theta) * upper[:-1] + c.theta * upper[1:], atol=1e-14)


def test_construction_class_polygon_relations():
    points = walk(5, 6)
    interpolant = sc.interpolate(points, alpha=2.0, beta=4.0)
    c = interpolant.construction(1.0)
    F0, V, W, F1 = c.class_polygon
    b = c.levels[0]
    np.testing.assert_allclose(b[1], F0 + 2.0 / 3.0 * (V - F0), atol=1e-12)  # alpha / 3
    np.testing.assert_allclose(b[2], F1 + 4.0 / 3.0 * (W - F1), atol=1e-12)  # beta / 3
    segment = sc.generic_segment([0, 0], [1, 2], [3, 2], [4, 0], 4.0, 2.0)
    c = segment.construction(0.25)
    np.testing.assert_array_equal(c.class_polygon, [[0, 0], [1, 2], [3, 2], [4, 0]])
    np.testing.assert_allclose(c.point, segment(0.25))
    timmer = sc.timmer_gc1(points)
    c = timmer.construction(0.5)
    P0, Q1, Q2, P1 = c.class_polygon
    np.testing.assert_allclose(c.levels[0][1], P0 + 4.0 / 3.0 * (Q1 - P0), atol=1e-12)
    assert Spline([[[0, 0], [1, 1], [2, 1], [3, 0]]], [0, 1]).construction(0.5).class_polygon is None
    with pytest.raises(ValueError, match="outside the curve's domain"):
        interpolant.construction(-1.0)
    with pytest.raises(TypeError, match="t must be a real number"):
        interpolant.construction("0.5")


def test_curvature_profile_has_both_sides_at_joints():
    points = walk(6, 6)
    spline = sc.interpolate(points, interval_weights=[1.0, 3.0, 1.0, 0.5, 2.0])
    profile = spline.curvature_profile(samples_per_piece=9)
    m = spline.n_segments
    assert profile.parameters.shape == profile.curvature.shape == profile.piece.shape == (9 * m,)
    np.testing.assert_array_equal(profile.parameters[8::9], spline.knots[1:])
    np.testing.assert_array_equal(profile.parameters[0::9], spline.knots[:-1])
    kappa_left = spline.curvature(spline.knots[1:-1], side="left")
    kappa_right = spline.curvature(spline.knots[1:-1], side="right")
    np.testing.assert_allclose(profile.curvature[8:-1:9], kappa_left, rtol=1e-9)
    np.testing.assert_allclose(profile.curvature[9::9], kappa_right, rtol=1e-9)
    np.testing.assert_allclose(profile.jumps[1:-1], kappa_right - kappa_left, rtol=1e-7, atol=1e-12)
    assert np.isnan(profile.jumps[[0, -1]]).all()
    inner = np.setdiff1d(np.arange(9 * m), np.r_[0:9 * m:9, 8:9 * m:9])
    np.testing.assert_allclose(profile.curvature[inner], spline.curvature(profile.parameters[inner]), rtol=1e-9)
    with pytest.raises(ValueError, match="samples_per_piece must be >= 2"):
        spline.curvature_profile(samples_per_piece=1)
    with pytest.raises(TypeError, match="samples_per_piece must be an integer"):
        spline.curvature_profile(samples_per_piece=True)


def test_legs_recorded_by_the_constructors():
    points = walk(7, 7)
    open_basis = sc.basis_spline(points)
    for piece in range(open_basis.n_segments):
        leg = open_basis.piece_leg(piece)
        b = open_basis.bezier()[piece]
        start, end = points[leg], points[leg + 1]
        for inner in b[1:3]:  # the inner Bézier points lie on the leg (§4.3)
            cross = (end - start)[0] * (inner - start)[1] - (end - start)[1] * (inner - start)[0]
            assert abs(cross) <= 1e-9
        np.testing.assert_array_equal(open_basis.leg_pieces(leg), [piece])
    assert open_basis.leg_pieces(0).size == 0 and open_basis.leg_pieces(6).size == 0
    closed_basis = sc.basis_spline(points, closed=True)
    assert [closed_basis.piece_leg(i) for i in range(7)] == list(range(7))
    for spline in (sc.interpolate(points), sc.timmer_g2(points), sc.timmer_gc2(points, closed=True)):
        assert spline.info["leg_offset"] == 0
        assert spline.piece_leg(2) == 2
    with pytest.raises(ValueError, match="piece must be <= 3"):
        open_basis.piece_leg(4)


# ---------------------------------------------------------------------------------------------- relative basis tension
def test_relative_basis_tension_matches_the_absolute_conversion():
    points = walk(8, 8)
    nu = np.linspace(-1.5, 4.0, 8)
    for closed, ends in ((False, "floating"), (False, "clamped"), (True, "floating")):
        reference = sc.basis_spline(points, closed=closed, ends=ends, knots="chord")
        steps = np.diff(reference.knots)
        if not closed:
            legs = np.linalg.norm(np.diff(points, axis=0), axis=1)
            steps = legs if ends == "floating" else legs[1:-1]
        weights = np.linspace(0.5, 2.0, 8 if closed else 7)
        spans, _acts = tension_spans(steps, weights, closed, ends)
        absolute = sc.basis_spline(points, closed=closed, ends=ends, knots="chord", interval_weights=weights,
                                   point_tension=nu * spans)
        relative = sc.basis_spline(points, closed=closed, ends=ends, knots="chord", interval_weights=weights,
                                   point_tension=nu, point_tension_scale="relative")
        np.testing.assert_allclose(relative.bezier(), absolute.bezier(), atol=1e-12)
        assert relative.info["point_tension_scale"] == "relative"


@FAST
@given(st.floats(-1.999, 50.0), st.integers(0, 100))
def test_relative_basis_tension_above_minus_two_is_convex(nu, seed):
    """nu > -2 everywhere gives d_j > 0 and a non-negative basis (§4.5), at any scale."""
    points = walk(seed, 7) * 10.0 ** (seed % 7 - 3)
    spline = sc.basis_spline(np.eye(7), knots=np.cumsum(np.r_[0, np.linalg.norm(np.diff(points, axis=0), axis=1)]),
                             point_tension=nu, point_tension_scale="relative")
    assert spline.bezier().min() >= -1e-9


@pytest.mark.parametrize("nu", [-2.0, -3.0, -8.0, -100.0])
def test_relative_basis_tension_in_the_unsafe_domain_is_refused(nu):
    tension = np.zeros(6)
    tension[3] = nu
    with pytest.raises(ValueError, match=r"point_tension\[3\] = .* \(relative\) must be > -2"):
        sc.basis_spline(walk(2, 6), point_tension=tension, point_tension_scale="relative")
    # with clamped ends the first two tensions have no effect, so they are not checked
    tension = np.zeros(6)
    tension[0] = nu
    sc.basis_spline(walk(2, 6), ends="clamped", point_tension=tension, point_tension_scale="relative")
    with pytest.raises(ValueError, match="point_tension_scale must be one of"):
        sc.basis_spline(walk(2, 6), point_tension_scale="pixels")


# ---------------------------------------------------------------------------------------------- svg and json
def test_one_svg_writer():
    from splinecraft.capture import svg as capture_svg

    assert capture_svg.path_data is svg.path_data and capture_svg.format_number is svg.format_number
    spline = sc.interpolate(walk(9, 5), closed=True)
    assert spline.to_svg_path(precision=2) == svg.path_data([spline.bezier()], decimals=2, closed=True)
    open_curve = sc.interpolate(walk(9, 5))
    assert not open_curve.to_svg_path().endswith("Z")
    parsed = capture_svg.parse_path_data(open_curve.to_svg_path(precision=None))
    np.testing.assert_array_equal(parsed[0][0], open_curve.bezier())
    for bad in (-1, 1.5, True, "3", 65):
        with pytest.raises((TypeError, ValueError), match="precision"):
            spline.to_svg_path(precision=bad)
        with pytest.raises((TypeError, ValueError), match="decimals"):
            svg.path_data([spline.bezier()], decimals=bad)
        with pytest.raises((TypeError, ValueError), match="decimals"):
            svg.format_number(1.0, bad)
    with pytest.raises(ValueError, match="closed has 1 flags for 2 curves"):
        svg.path_data([spline.bezier()] * 2, closed=[True])


def test_svg_document_frames():
    default = svg.svg_document("M 0,0 Z", 3, 4)
    assert 'width="3" height="4" viewBox="0 0 3 4"' in default and 'fill-rule="evenodd" stroke="none"' in default
    line = svg.svg_document("M 0,0 C 1,1 2,1 3,0", 10.5, 4, fill="none", stroke="#1565c0", stroke_width=2,
                            view_box=(-0.25, -1, 10.5, 4))
    assert 'viewBox="-0.25 -1 10.5 4"' in line and 'stroke="#1565c0" stroke-width="2"' in line
    with pytest.raises(ValueError, match="width must be >= 0"):
        svg.svg_document("M 0,0 Z", -100, 4)
    with pytest.raises(ValueError, match=r"view_box\[0\] must be a finite number"):
        svg.svg_document("M 0,0 Z", 1, 4, view_box=(math.nan, 0, 1, 1))


def test_json_helper():
    data = {"a": np.float32(1.5), "b": [np.int64(2), (np.bool_(True), None)], "c": np.arange(3.0), "d": math.nan}
    plain = _json.to_jsonable(data)
    assert plain["a"] == 1.5 and plain["b"] == [2, [True, None]] and plain["c"] == [0.0, 1.0, 2.0]
    assert math.isnan(plain["d"])
    assert json.loads(json.dumps(_json.to_jsonable(data, non_finite="none"), allow_nan=False))["d"] is None
    with pytest.raises(ValueError, match=r"info\['d'\] is nan"):
        _json.to_jsonable(data, "info", non_finite="error")
    with pytest.raises(TypeError, match=r"info\['x'\] must be JSON-able, got object"):
        _json.to_jsonable({"x": object()}, "info")
    with pytest.raises(TypeError, match="info keys must be strings"):
        _json.to_jsonable({1: 2}, "info")
    assert _json.to_jsonable({1: object()}, coerce=True)["1"].startswith("<object")
    loop = []
    loop.append(loop)
    with pytest.raises(ValueError, match="nested too deeply"):
        _json.to_jsonable(loop)
