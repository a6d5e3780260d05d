"""Tests of the common curve type :class:`splinecraft.spline.piecewise.Spline` (§0, §7).

References are independent of the implementation: scipy's BPoly/PPoly, finite differences, closed-form
curvature of a parabola, and re-parsing of the SVG text.
"""
import json
import re
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.interpolate import BPoly

from splinecraft.spline.piecewise import Spline

SETTINGS = settings(max_examples=60, deadline=None)


@st.composite
def splines(draw, closed=None, dim=2, max_segments=6):
    m = draw(st.integers(1, max_segments))
    closed = draw(st.booleans()) if closed is None else closed
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    bezier = rng.uniform(-100, 100, size=(m, 4, dim))
    bezier[1:, 0] = bezier[:-1, 3]
    if closed:
        bezier[-1, 3] = bezier[0, 0]
    knots = np.concatenate([[rng.uniform(-5, 5)], rng.uniform(0.1, 10, size=m)]).cumsum()
    return Spline(bezier, knots, closed=closed)


def _dense_params(spline, per_piece=9):
    knots = spline.knots
    theta = np.linspace(0, 1, per_piece)
    return (knots[:-1, None] + theta * np.diff(knots)[:, None]).ravel()


# ---------------------------------------------------------------- evaluation
@SETTINGS
@given(splines())
def test_values_at_knots_are_bezier_end_points(spline):
    b = spline.bezier()
    np.testing.assert_allclose(spline(spline.knots[:-1]), b[:, 0], atol=1e-9)
    np.testing.assert_allclose(spline(spline.knots[1:], side="left"), b[:, 3], atol=1e-9)


@SETTINGS
@given(splines())
def test_bpoly_and_ppoly_agree_with_call(spline):
    t = _dense_params(spline)
    if spline.closed:  # t_m wraps to t_0, where the right-sided derivatives belong to piece 0
        t = t[:-1]
    # An independent reference: scipy's Bernstein polynomial built directly from the control points.
    reference = BPoly(np.transpose(spline.bezier(), (1, 0, 2)), spline.knots)
    bpoly, ppoly = spline.to_bpoly(), spline.to_ppoly()
    # scipy's periodic extrapolation wraps every parameter (x0 + (x - x0) % period), which can move a
    # knot value by one ulp to the other piece; compare the converted loops inside the pieces only.
    inside = t if not spline.closed else _dense_params(spline, 11).reshape(-1, 11)[:, 1:-1].ravel()
    for nu in range(4):
        expected = reference(t, nu)
        scale = max(1.0, np.abs(expected).max())
        np.testing.assert_allclose(spline(t, nu), expected, atol=1e-9 * scale)
        expected = reference(inside, nu)
        np.testing.assert_allclose(bpoly(inside, nu), expected, atol=1e-9 * scale)
        np.testing.assert_allclose(ppoly(inside, nu), expected, atol=1e-8 * scale)
    assert bpoly.c.shape == (4, spline.n_segments, 2)


@SETTINGS
@given(splines())
def test_derivatives_match_finite_differences(spline):
    knots = spline.knots
    # interior points of each piece, away from the knots (the curve is only C^1 there)
    theta = np.array([0.2, 0.5, 0.8])
    t = (knots[:-1, None] + theta * np.diff(knots)[:, None]).ravel()
    step = 1e-5 * np.diff(knots).min()
    for nu in (1, 2, 3):
        numeric = (spline(t + step, nu - 1) - spline(t - step, nu - 1)) / (2 * step)
        exact = spline.derivative(t, order=nu)
        scale = max(1.0, np.abs(exact).max())
        np.testing.assert_allclose(exact, numeric, atol=1e-4 * scale)
    np.testing.assert_array_equal(spline(t, 4), 0.0)


def test_scalar_parameter_gives_single_point():
    spline = Spline(np.arange(8.0).reshape(1, 4, 2), [0.0, 2.0])
    assert spline(1.0).shape == (2,)
    assert spline([1.0]).shape == (1, 2)
    np.testing.assert_allclose(spline(1.0), spline.bezier()[0].mean(axis=0))  # collinear equally spaced


def test_open_domain_raises_and_extrapolates():
    rng = np.random.default_rng(1)
    b = rng.normal(size=(2, 4, 2))
    b[1, 0] = b[0, 3]
    spline = Spline(b, [0.0, 1.0, 3.0])
    with pytest.raises(ValueError, match=r"t\[1\].*outside"):
        spline([0.5, 3.5])
    with pytest.raises(ValueError, match="outside") as caught:
        spline(-0.1)
    assert r"domain [0.0, 3.0];" in str(caught.value)  # plain numbers, not np.float64(0.0) (numpy 2 reprs)
    with pytest.raises(TypeError, match="t must be numeric, got None"):  # not 't[0] is nan'
        spline(None)
    reference = BPoly(np.transpose(b, (1, 0, 2)), [0.0, 1.0, 3.0], extrapolate=True)
    t = np.array([-0.5, 3.5])
    np.testing.assert_allclose(spline(t, extrapolate=True), reference(t), atol=1e-12)
    spline(3.0 * (1 + 1e-15))  # rounding just past the end is tolerated


@SETTINGS
@given(splines(closed=True))
def test_closed_curves_wrap_periodically(spline):
    t0, tm = spline.domain
    period = tm - t0
    t = np.linspace(t0, tm, 23)
    scale = np.abs(spline.bezier()).max()
    np.testing.assert_allclose(spline(t + 3 * period), spline(t), atol=1e-9 * scale)
    np.testing.assert_allclose(spline(t - period), spline(t), atol=1e-9 * scale)
    np.testing.assert_allclose(spline(tm), spline(t0), atol=1e-12 * scale)
    np.testing.assert_allclose(spline.to_bpoly()(t + period), spline(t), atol=1e-9 * scale)


# ---------------------------------------------------------------- curvature
def test_curvature_of_parabola_matches_closed_form():
    # y = x^2 on [-1, 2] as one cubic Bezier with x(theta) linear: control points from the
    # polynomial (x = -1 + 3 theta). Curvature of y = x^2: 2 / (1 + 4 x^2)^(3/2).
    x = np.array([-1.0, 0.0, 1.0, 2.0])
    # Bezier ordinates of x^2 with x = -1 + 3 theta from its polar form (blossom):
    # blossom of x^2 at (x_a, x_b, x_c) is (x_a x_b + x_b x_c + x_a x_c) / 3 with Bezier nodes
    nodes = [(-1, -1, -1), (-1, -1, 2), (-1, 2, 2), (2, 2, 2)]
    y = np.array([(a * b + b * c + a * c) / 3.0 for a, b, c in nodes])
    spline = Spline(np.stack([x, y], axis=1)[None], [0.0, 3.0])
    t = np.linspace(0, 3, 31)
    xs = spline(t)[:, 0]
    np.testing.assert_allclose(spline(t)[:, 1], xs**2, atol=1e-12)
    np.testing.assert_allclose(spline.curvature(t), 2.0 / (1 + 4 * xs**2) ** 1.5, rtol=1e-12)
    # mirrored parabola turns clockwise: negative curvature
    mirrored = spline.transformed(np.diag([1.0, -1.0]))
    np.testing.assert_allclose(mirrored.curvature(t), -2.0 / (1 + 4 * xs**2) ** 1.5, rtol=1e-12)


@SETTINGS
@given(splines())
def test_joint_curvature_matches_one_sided_evaluation(spline):
    joints = spline.joint_curvature()
    m = spline.n_segments
    assert joints.shape == (m + 1, 2)
    knots = spline.knots
    left = spline.curvature(knots[1:], side="left")
    right = spline.curvature(knots[:-1], side="right")
    np.testing.assert_allclose(joints[1:, 0], left, rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(joints[:-1, 1], right, rtol=1e-7, atol=1e-12)
    if spline.closed:
        np.testing.assert_allclose(joints[0], joints[m], rtol=1e-12)
        np.testing.assert_allclose(spline.curvature(knots[0], side="left"), joints[0, 0], rtol=1e-7)
    else:
        assert np.isnan(joints[0, 0]) and np.isnan(joints[m, 1])


@SETTINGS
@given(splines(), st.floats(-5, 5).filter(lambda s: abs(s) > 1e-3))
def test_curvature_comb_teeth(spline, scale):
    per = 7
    base, tips = spline.curvature_comb(scale=scale, samples_per_segment=per)
    knots = spline.knots
    t = np.concatenate([np.linspace(a, b, per) for a, b in zip(knots[:-1], knots[1:])])
    at_end = np.tile(np.arange(per) == per - 1, spline.n_segments)  # theta = 1: left-sided values
    point = np.where(at_end[:, None], spline(t, side="left"), spline(t))
    velocity = np.where(at_end[:, None], spline(t, 1, side="left"), spline(t, 1))
    kappa = np.where(at_end, spline.curvature(t, side="left"), spline.curvature(t))
    keep = np.linalg.norm(velocity, axis=1) > 1e-12 * np.abs(spline.bezier()).max()
    assert base.shape == tips.shape == (keep.sum(), 2)
    scale_ref = np.abs(spline.bezier()).max()
    np.testing.assert_allclose(base, point[keep], atol=1e-9 * scale_ref)
    unit = velocity[keep] / np.linalg.norm(velocity[keep], axis=1)[:, None]
    normal = np.stack([-unit[:, 1], unit[:, 0]], axis=1)
    np.testing.assert_allclose(tips - base, -scale * kappa[keep][:, None] * normal, rtol=1e-7, atol=1e-9)


# ---------------------------------------------------------------- sampling
def _max_deviation_from_polyline(spline, params, points, per_interval=24):
    """Distance of densely evaluated curve points to the chord of the sample interval they lie in."""
    worst = 0.0
    s = np.linspace(0, 1, per_interval)
    t = params[:-1, None] + s * np.diff(params)[:, None]  # (k-1, per)
    curve = spline(t.ravel(), side="left").reshape(t.shape + (spline.dim,))
    a, b = points[:-1, None], points[1:, None]
    chord = b - a
    length2 = np.einsum("kpd,kpd->kp", chord, chord)
    rel = curve - a
    proj = np.clip(np.einsum("kpd,kpd->kp", rel, chord) / np.where(length2 > 0, length2, 1), 0, 1)
    dist = np.linalg.norm(rel - proj[..., None] * chord, axis=-1)
    worst = max(worst, float(dist.max()))
    return worst


@SETTINGS
@given(splines(), st.sampled_from([0.05, 0.25, 1.0, 5.0]), st.sampled_from(["wang", "subdivide"]))
def test_adaptive_sampling_is_flat_and_includes_knots(spline, tolerance, method):
    params, points = spline.sample(tolerance=tolerance, method=method)
    assert params.shape[0] == points.shape[0]
    assert (np.diff(params) > 0).all()
    assert np.isin(spline.knots, params).all()
    scale = np.abs(points).max()
    np.testing.assert_allclose(points, spline(params, side="left"), atol=1e-9 * scale)
    np.testing.assert_allclose(points[[0, -1]], spline.knot_points[[0, -1]], atol=0)
    assert _max_deviation_from_polyline(spline, params, points) <= tolerance * (1 + 1e-9) + 1e-12 * scale


def test_sampling_adapts_to_tolerance_and_respects_max_points():
    theta = np.linspace(0, 2 * np.pi, 9)
    pts = np.stack([np.cos(theta), np.sin(theta)], axis=1) * 500
    b = np.stack([pts[:-1], pts[:-1] + 100 * np.roll(pts, -1, 0)[:-1] / 500 * 0,
                  pts[1:] - 0 * pts[1:], pts[1:]], axis=1)
    b[:, 1] = pts[:-1] + np.stack([-pts[:-1, 1], pts[:-1, 0]], axis=1) * 0.3
    b[:, 2] = pts[1:] - np.stack([-pts[1:, 1], pts[1:, 0]], axis=1) * 0.3
    spline = Spline(b, np.arange(9.0), closed=True)
    for method in ("wang", "subdivide"):
        coarse, _ = spline.sample(tolerance=2.0, method=method)
        fine, _ = spline.sample(tolerance=0.02, method=method)
        assert fine.size > 4 * coarse.size
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            capped, capped_points = spline.sample(tolerance=1e-6, max_points=50, method=method)
        assert 9 <= capped.size <= 50 and any(issubclass(w.category, RuntimeWarning) for w in caught)
        assert (np.diff(capped) > 0).all()
        np.testing.assert_allclose(capped_points[-1], capped_points[0])
    # a straight piece needs no interior samples
    line = Spline(np.array([[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]]]), [0.0, 1.0])
    assert line.sample(0.01)[0].size == 2 and line.sample(0.01, method="subdivide")[0].size == 2


@SETTINGS
@given(splines(), st.integers(1, 12))
def test_uniform_sampling(spline, per_segment):
    params, points = spline.sample(samples_per_segment=per_segment)
    assert params.shape == (spline.n_segments * per_segment + 1,)
    np.testing.assert_allclose(points, spline(params, side="left"), atol=1e-9 * np.abs(points).max())
    assert np.isin(spline.knots, params).all()


# ---------------------------------------------------------------- export
_NUMBER = r"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"


def _parse_svg(path):
    tokens = re.findall(r"[MCZ]|" + _NUMBER, path)
    assert tokens[0] == "M"
    closed = tokens[-1] == "Z"
    body = tokens[:-1] if closed else tokens
    start = np.array([float(v) for v in body[1:3]])
    pieces = []
    i = 3
    current = start
    while i < len(body):
        assert body[i] == "C"
        coords = np.array([float(v) for v in body[i + 1 : i + 7]]).reshape(3, 2)
        pieces.append(np.vstack([current, coords]))
        current = coords[-1]
        i += 7
    return np.array(pieces), closed


@SETTINGS
@given(splines())
def test_svg_path_reparses_to_bezier(spline):
    exact, closed = _parse_svg(spline.to_svg_path(precision=None))
    assert closed == spline.closed
    np.testing.assert_array_equal(exact, spline.bezier())
    rounded, _ = _parse_svg(spline.to_svg_path(precision=3))
    np.testing.assert_allclose(rounded, spline.bezier(), atol=5.0001e-4)


def test_svg_path_format():
    b = np.array([[[0.0, 0.0], [1.0, 2.5], [3.25, -1.0], [4.0, 0.0]]])
    assert Spline(b, [0.0, 1.0]).to_svg_path(precision=2) == "M 0,0 C 1,2.5 3.25,-1 4,0"
    loop = np.array([[[0.0, 0.0], [1.0, 1.0], [2.0, 1.0], [3.0, 0.0]], [[3.0, 0.0], [2.0, -1.0], [1.0, -1.0], [0.0, 0.0]]])
    assert Spline(loop, [0.0, 1.0, 2.0], closed=True).to_svg_path().endswith("0,0 Z")
    assert Spline(np.array([[[-1e-9, 0.0], [1, 1], [2, 1], [3, 0]]]), [0, 1]).to_svg_path(2).startswith("M 0,0 ")


@SETTINGS
@given(splines())
def test_dict_round_trip_is_exact_through_json(spline):
    rng = np.random.default_rng(0)
    m = spline.n_segments
    decorated = Spline(spline.bezier(), spline.knots, closed=spline.closed,
                       auxiliary={"V": rng.normal(size=(m, 2)), "empty": np.zeros((0, 2))},
                       info={"form": "test", "alpha": np.float64(3.0), "weights": np.arange(3)})
    text = json.dumps(decorated.to_dict(), allow_nan=False)
    again = Spline.from_dict(json.loads(text))
    np.testing.assert_array_equal(again.bezier(), decorated.bezier())
    np.testing.assert_array_equal(again.knots, decorated.knots)
    assert again.closed == decorated.closed
    assert again.info == {"form": "test", "alpha": 3.0, "weights": [0, 1, 2]}
    assert set(again.auxiliary) == {"V", "empty"}
    np.testing.assert_array_equal(again.auxiliary["V"], decorated.auxiliary["V"])
    assert again.auxiliary["empty"].shape == (0, 2)


# ---------------------------------------------------------------- geometry
@SETTINGS
@given(splines())
def test_reversed_traverses_backwards(spline):
    back = spline.reversed()
    t0, tm = spline.domain
    t = np.linspace(t0, tm, 41)
    scale = np.abs(spline.bezier()).max()
    np.testing.assert_allclose(back(t0 + tm - t, side="left"), spline(t), atol=1e-9 * scale)
    np.testing.assert_allclose(back(t0 + tm - t, 1, side="left"), -spline(t, 1), atol=1e-8 * scale)
    np.testing.assert_allclose(back.joint_curvature()[::-1, ::-1], -spline.joint_curvature(), rtol=1e-7, atol=1e-12)
    np.testing.assert_array_equal(back.reversed().bezier(), spline.bezier())


def test_reversed_carries_auxiliary_geometry():
    theta = np.linspace(0, 2 * np.pi, 5)[:-1]
    points = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    tangents = np.stack([-np.sin(theta), np.cos(theta)], axis=1)
    b = np.stack([points, points + tangents / 3, np.roll(points - tangents / 3, -1, 0), np.roll(points, -1, 0)], axis=1)
    loop = Spline(b, np.arange(5.0), closed=True,
                  auxiliary={"F": points, "tangents": tangents, "V": b[:, 1], "W": b[:, 2]},
                  info={"alpha": [1.0, 2.0], "beta": [3.0, 4.0]})
    back = loop.reversed()
    knot_points = back.knot_points[:-1]
    np.testing.assert_allclose(back.auxiliary["F"], knot_points, atol=1e-15)
    np.testing.assert_allclose(back.auxiliary["tangents"], back(back.knots[:-1], 1) * 3 / 3, atol=1e-15)
    np.testing.assert_allclose(back.auxiliary["V"], back.bezier()[:, 1])
    np.testing.assert_allclose(back.auxiliary["W"], back.bezier()[:, 2])
    assert back.info["alpha"] == [3.0, 4.0] and back.info["beta"] == [1.0, 2.0]


@SETTINGS
@given(splines(), st.integers(0, 2**32 - 1))
def test_transformed_is_the_affine_image(spline, seed):
    rng = np.random.default_rng(seed)
    matrix = rng.normal(size=(2, 2))
    offset = rng.normal(size=2) * 10
    t = _dense_params(spline)
    decorated = Spline(spline.bezier(), spline.knots, closed=spline.closed,
                       auxiliary={"tangents": spline(spline.knots, 1), "F": spline.knot_points})
    image = decorated.transformed(matrix, offset)
    scale = max(1.0, np.abs(image.bezier()).max())
    np.testing.assert_allclose(image(t), spline(t) @ matrix.T + offset, atol=1e-9 * scale)
    np.testing.assert_allclose(image(t, 2), spline(t, 2) @ matrix.T, atol=1e-9 * scale)
    np.testing.assert_allclose(image.auxiliary["tangents"], image(image.knots, 1), atol=1e-9 * scale)
    np.testing.assert_allclose(image.auxiliary["F"], image.knot_points, atol=1e-9 * scale)


def test_three_dimensional_curve_and_repr():
    rng = np.random.default_rng(3)
    b = rng.normal(size=(2, 4, 3))
    b[1, 0] = b[0, 3]
    spline = Spline(b, [0.0, 1.0, 2.0], info={"form": "demo"})
    assert spline.dim == 3 and spline.n_segments == 2
    assert (spline.curvature(np.linspace(0, 2, 5)) >= 0).all()
    assert "n_segments=2" in repr(spline) and "demo" in repr(spline)
    with pytest.raises(ValueError, match="planar"):
        spline.to_svg_path()


# ---------------------------------------------------------------- validation
def test_bad_input_is_rejected_with_index():
    good = np.zeros((2, 4, 2))
    good[:, :, 0] = [[0, 1, 2, 3], [3, 4, 5, 6]]
    Spline(good, [0, 1, 2])
    with pytest.raises(ValueError, match=r"shape \(m, 4, d\)"):
        Spline(np.zeros((2, 3, 2)), [0, 1, 2])
    with pytest.raises(ValueError, match="m \\+ 1 = 3"):
        Spline(good, [0, 1])
    with pytest.raises(ValueError, match=r"knots\[2\].*<= knots\[1\]"):
        Spline(good, [0, 1, 1])
    bad = good.copy()
    bad[1, 2, 1] = np.nan
    with pytest.raises(ValueError, match=r"bezier\[1, 2, 1\] is nan"):
        Spline(bad, [0, 1, 2])
    with pytest.raises(ValueError, match=r"knots\[1\] is inf"):
        Spline(good, [0, np.inf, 2])
    gap = good.copy()
    gap[1, 0, 0] = 3.5
    with pytest.raises(ValueError, match="pieces 0 and 1 do not join"):
        Spline(gap, [0, 1, 2])
    for offset in (0.0, 1e9, -1e12):  # the verdict does not depend on where the pieces sit
        with pytest.raises(ValueError, match="pieces 0 and 1 do not join"):
            Spline(gap + offset, [0, 1, 2])
        near = good + offset
        near[1, 0] += 8 * np.spacing(np.abs(near).max())  # a rounding's worth at that offset: joined exactly
        joined = Spline(near, [0, 1, 2]).bezier()
        assert np.array_equal(joined[1, 0], joined[0, 3])
    with pytest.raises(ValueError, match="closed=True"):
        Spline(good, [0, 1, 2], closed=True)
    with pytest.raises(TypeError, match="closed"):
        Spline(good, [0, 1, 2], closed="yes")
    with pytest.raises(TypeError, match="info"):
        Spline(good, [0, 1, 2], info={"bad": object()})
    with pytest.raises(TypeError, match="bezier"):
        Spline("abc", [0, 1])
    spline = Spline(good, [0, 1, 2])
    with pytest.raises(ValueError, match="nu"):
        spline(0.5, nu=-1)
    with pytest.raises(ValueError, match="tolerance"):
        spline.sample(tolerance=0)
    with pytest.raises(ValueError, match="method"):
        spline.sample(method="fast")
    with pytest.raises(ValueError, match=r"matrix must have shape \(2, 2\)"):
        spline.transformed(np.eye(3))


def test_tiny_gaps_are_closed_exactly():
    b = np.zeros((2, 4, 2))
    b[:, :, 0] = [[0, 1, 2, 3], [3 + 1e-13, 4, 5, 6]]
    spline = Spline(b, [0, 1, 2])
    assert spline.bezier()[1, 0, 0] == 3.0
    assert not spline.bezier().flags.writeable or spline.bezier() is not spline.bezier()


def test_copies_and_pickles_of_a_spline_keep_its_arrays_read_only():
    """copy, deepcopy and pickle rebuild the spline through its trusted constructor: equal, and its knots,
    auxiliary arrays and storage read-only as in the original (a writable copy's knots could break the
    increasing-knots rule behind its evaluation)."""
    import copy
    import pickle

    import splinecraft as sc

    spline = sc.timmer_g2(np.random.default_rng(0).normal(size=(8, 2)) * 10)
    for again in (copy.copy(spline), copy.deepcopy(spline), pickle.loads(pickle.dumps(spline))):
        np.testing.assert_array_equal(again.bezier(), spline.bezier())
        np.testing.assert_array_equal(again.knots, spline.knots)
        assert again.info == spline.info and again.closed == spline.closed and type(again) is type(spline)
        assert not again.knots.flags.writeable and not again._planar.flags.writeable
        assert all(not value.flags.writeable for value in again.auxiliary.values())
        with pytest.raises(ValueError, match="read-only"):
            again.knots[1] = 1e6
