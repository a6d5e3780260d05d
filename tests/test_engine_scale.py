"""The engine at every float64 scale: solvers, sampling and curvature."""

import numpy as np
import pytest

import splinecraft as sc

HEART = np.array([[0.0, 0.6], [0.5, 1.0], [1.0, 0.6], [0.0, -1.0], [-1.0, 0.6], [-0.5, 1.0]])
WAVE = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 3.0], [4.0, 1.0], [6.0, 2.0], [7.0, 0.0]])


def scale_family():
    """(name, builder(points)) of constructions whose shape does not depend on the coordinate scale."""
    return [
        ("interpolant", lambda p: sc.interpolate(p)),
        ("interpolant_closed", lambda p: sc.interpolate(p, closed=True, interval_weights=np.linspace(1, 2, len(p)))),
        ("basis", lambda p: sc.basis_spline(p, knots="chord")),
        ("basis_closed", lambda p: sc.basis_spline(p, closed=True)),
        ("timmer_g2", lambda p: sc.timmer_g2(p)),
        ("timmer_gc1", lambda p: sc.timmer_gc1(p)),
        ("timmer_gc2", lambda p: sc.timmer_gc2(p)),
    ]


@pytest.mark.parametrize("scale", [1e-300, 1e-160, 1e-20, 1e20, 1e153, 1e300])
@pytest.mark.parametrize("name, build", scale_family(), ids=[name for name, _ in scale_family()])
def test_sample_and_curvature_at_extreme_scales(name, build, scale):
    """sample() and the curvature of scaled curves are the unit-scale results, scaled."""
    points = WAVE if "closed" not in name else HEART
    if name.startswith("timmer") or name.startswith("interpolant"):
        try:
            reference, curve = build(points), build(points * scale)
        except ValueError as exc:  # allowed only with a plain reason that names the scale
            pytest.fail(f"{name} at scale {scale:g} refused: {exc}")
    else:
        reference, curve = build(points), build(points * scale)
    np.testing.assert_allclose(curve.bezier() / scale, reference.bezier(), rtol=1e-9, atol=1e-9)
    params, samples = curve.sample(tolerance=1e-3 * scale)
    ref_params, ref_samples = reference.sample(tolerance=1e-3)
    assert np.isfinite(samples).all() and abs(len(samples) - len(ref_samples)) <= curve.n_segments
    np.testing.assert_allclose(samples / scale, curve(params) / scale, rtol=1e-12, atol=1e-12)
    params, samples = curve.sample(tolerance=1e-3 * scale, method="subdivide")
    assert np.isfinite(samples).all()
    kappa = curve.joint_curvature()
    ref_kappa = reference.joint_curvature()
    np.testing.assert_allclose(kappa * scale, ref_kappa, rtol=1e-7, atol=1e-9)
    profile, ref_profile = curve.curvature_profile(8), reference.curvature_profile(8)
    np.testing.assert_allclose(profile.curvature * scale, ref_profile.curvature, rtol=1e-7, atol=1e-9)
    if 1e-150 < scale < 1e150:  # a tooth of length scale * kappa: compare at the reference's size
        bases, tips = curve.curvature_comb(scale=scale * scale)
        ref_bases, ref_tips = reference.curvature_comb()
        np.testing.assert_allclose(tips / scale, ref_tips, rtol=1e-7, atol=1e-7)


@pytest.mark.parametrize("scale, tolerance", [(1e-300, 1e10), (1e-200, 1e200), (1e-40, 1e280), (1e-310, 1.0)])
@pytest.mark.parametrize("method", ["wang", "subdivide"])
def test_sample_with_a_tolerance_far_above_the_curve(scale, tolerance, method):
    """A tolerance larger than the whole curve is met by the knot points alone (one sample per piece); the
    power-of-two rescaling of a tiny curve used to overflow it (``OverflowError: math range error``)."""
    curve = sc.interpolate(WAVE * scale)
    params, samples = curve.sample(tolerance=tolerance, method=method)
    np.testing.assert_array_equal(params, curve.knots)
    np.testing.assert_array_equal(samples, curve.knot_points)




@pytest.mark.parametrize("radius, offset", [(1.0, 1e13), (1e-3, 1e7), (1e-3, 1e9), (1e5, -1e15)])
def test_curvature_comb_is_translation_invariant(radius, offset):
    """Moving a curve away from the origin keeps every comb tooth (the cusp test measures the curve's extent,
    not its distance from the origin): same count, and the same teeth up to the coordinates' rounding."""
    angle = np.linspace(0.0, 2.0 * np.pi, 8, endpoint=False)
    circle = radius * np.c_[np.cos(angle), np.sin(angle)]
    reference = sc.interpolate(circle, closed=True).curvature_comb(scale=radius * radius)
    moved = sc.interpolate(circle + offset, closed=True).curvature_comb(scale=radius * radius)
    assert len(moved[0]) == len(reference[0]) == 8 * 16
    rounding = 1e4 * np.finfo(float).eps * abs(offset)
    np.testing.assert_allclose(moved[0] - offset, reference[0], atol=rounding)
    np.testing.assert_allclose(moved[1] - offset, reference[1], atol=rounding + 1e-6 * radius)


# ---------------------------------------------------------------------------------------------- messages at the limits
@pytest.mark.parametrize("scale", [1e-300, 1e-160, 1e150, 1e300])
def test_interpolant_at_extreme_scales_keeps_its_meaning(scale):
    """Relative tension, explicit knots, clamped ends and natural_v at any scale: no misleading messages."""
    points = WAVE * scale
    nu = np.full(len(WAVE), 1.5)
    relative = sc.interpolate(points, point_tension=nu, point_tension_scale="relative")
    reference = sc.interpolate(WAVE, point_tension=nu, point_tension_scale="relative")
    np.testing.assert_allclose(relative.bezier() / scale, reference.bezier(), rtol=1e-9, atol=1e-12)
    absolute = sc.interpolate(points, point_tension=2.0 / scale, end_condition="natural_v")  # v has units 1/h
    np.testing.assert_allclose(absolute.bezier() / scale,
                               sc.interpolate(WAVE, point_tension=2.0, end_condition="natural_v").bezier(),
                               rtol=1e-9, atol=1e-12)
    clamped = sc.interpolate(points, end_condition="clamped", end_tangents=([1.0, 0.0], None))
    np.testing.assert_allclose(clamped.auxiliary["tangents"][0], [1.0, 0.0], rtol=1e-12)
    explicit = sc.interpolate(points, knots=np.arange(len(WAVE)) * 2.0)
    np.testing.assert_array_equal(explicit.knots, np.arange(len(WAVE)) * 2.0)
    with pytest.raises(ValueError, match=r"point_tension\[2\] = -3 \(relative\) makes row 2"):
        sc.interpolate(points, point_tension=np.where(np.arange(6) == 2, -3.0, 0.0), point_tension_scale="relative")


def test_huge_positive_tension_is_accepted():
    """v -> +inf gives zero tangents at those points (§2.5, E22): allowed, not 'move away from the band'."""
    for tension in (1e15, 1e100, 1e300, [0.0, 1e300, 0.0, 1e200, 0.0, 0.0]):
        curve = sc.interpolate(WAVE, point_tension=tension)
        tangents = curve.auxiliary["tangents"]
        assert np.isfinite(curve.bezier()).all()
        tight = np.broadcast_to(tension, 6) > 1e10
        tight[[0, -1]] = False  # the end tensions act only with end_condition="natural_v"
        assert np.linalg.norm(tangents[tight], axis=1).max() < 1e-9
    curve = sc.interpolate(HEART, closed=True, point_tension=1e300)
    np.testing.assert_allclose(curve.bezier()[:, 1], HEART, atol=1e-12)  # the polygon, with cusps


def test_tiny_class_parameters_are_refused_by_name():
    with pytest.raises(ValueError, match=r"the class point V_0 = F \+ h M / alpha \(§2\.1\) lies beyond the float64 range, with alpha = 1e-320"):
        sc.interpolate(WAVE, alpha=1e-320)
    with pytest.raises(ValueError, match=r"with beta\[1\] = 1e-320"):
        sc.basis_spline(WAVE, beta=[1.0, 1e-320, 1.0])
    curve = sc.interpolate(WAVE, alpha=1e-300)  # still representable: accepted
    assert np.isfinite(curve.auxiliary["V"]).all()


@pytest.mark.parametrize("build", [sc.interpolate, sc.basis_spline], ids=["interpolant", "basis"])
def test_tangents_beyond_float64_are_refused_not_stored(build):
    # the curve of points near the float64 limit over close knots fits, its tangents (points / knot step) do
    # not: an error naming them, never a spline whose auxiliary holds inf (it could not be serialized)
    points = WAVE * 1e307 / 7.0
    with pytest.raises(ValueError, match="tangents .* overflow float64"):
        build(points, knots=np.arange(6) * 0.01)
    curve = build(points, knots=np.arange(6) * 10.0)  # larger steps: the same points are fine
    assert np.isfinite(curve.auxiliary["tangents"]).all()
    assert sc.Spline.from_dict(curve.to_dict()).bezier().tolist() == curve.bezier().tolist()


@pytest.mark.parametrize("power", [-1000, -530, -300, 300, 530, 1000])
@pytest.mark.parametrize("closed", [False, True])
def test_explicit_knots_at_any_scale_give_the_curve_of_moderate_knots(power, closed):
    # the curve depends on the knot steps only through c = omega / h and v in the units of omega / h (§2.5
    # Units): knots times 2^power with the point tension over 2^power is the same curve, its tangents over
    # 2^power, its knots the caller's (on explicit knots of extreme size c once under- or overflowed)
    scale = 2.0 ** power
    count = len(WAVE) + (1 if closed else 0)
    knots = np.array([0.0, 1.0, 2.5, 3.0, 4.5, 5.0, 6.5])[:count]
    tension = np.array([0.5, 1.0, 0.0, 2.0, 0.3, 0.7])
    options = {"closed": closed} if closed else {"end_condition": "clamped", "end_tangents": ([1.0, 2.0], [0.5, -1.0])}
    reference = sc.interpolate(WAVE, knots=knots, point_tension=tension, **options)
    if not closed:
        options["end_tangents"] = tuple(np.array(m) / scale for m in options["end_tangents"])
    curve = sc.interpolate(WAVE, knots=knots * scale, point_tension=tension / scale, **options)
    np.testing.assert_allclose(curve.bezier(), reference.bezier(), rtol=0, atol=1e-12)
    np.testing.assert_allclose(curve.auxiliary["tangents"] * scale, reference.auxiliary["tangents"], rtol=1e-12)
    assert np.array_equal(curve.knots, knots * scale)
    basis_knots = np.array([0.0, 1.0, 2.5, 3.0, 4.5, 5.0, 6.5])[: count if closed else len(WAVE)]
    reference = sc.basis_spline(WAVE, knots=basis_knots, point_tension=tension, closed=closed)
    curve = sc.basis_spline(WAVE, knots=basis_knots * scale, point_tension=tension / scale, closed=closed)
    np.testing.assert_allclose(curve.bezier(), reference.bezier(), rtol=0, atol=1e-12)
    assert np.array_equal(curve.knots * 1.0, reference.knots * scale)
