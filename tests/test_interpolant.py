"""Tests of the interpolant form ``interpolate`` (§2-3, thesis section 3.1).

Independent references: scipy's CubicSpline (v = 0, constant omega), the joint constraint and end
conditions evaluated from the Bézier pieces, the energy of §2.2 computed in closed form, and dense
linear algebra for the spec's singular example.
"""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st
from scipy.interpolate import CubicSpline

from splinecraft.spline.interpolant import end_derivative_estimates, interpolate
from splinecraft.spline.segment import CLASS_PRESETS

SETTINGS = settings(max_examples=60, deadline=None)
KNOT_METHODS = ["chord", "centripetal", "uniform"]


def random_points(rng, n, scale=100.0):
    """Random walk with legs of length >= scale/20 (no near-coincident points)."""
    angles = rng.uniform(0, 2 * np.pi, n)
    lengths = rng.uniform(scale / 20, scale, n)
    steps = np.stack([np.cos(angles), np.sin(angles)], axis=1) * lengths[:, None]
    return np.cumsum(steps, axis=0)


@st.composite
def problems(draw, closed=None, end_conditions=("natural", "natural_v", "clamped"), tension=True, weights=True):
    closed = draw(st.booleans()) if closed is None else closed
    n = draw(st.integers(3 if closed else 2, 12))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    points = random_points(rng, n)
    m = n if closed else n - 1
    knots = draw(st.sampled_from(KNOT_METHODS))
    kwargs = dict(closed=closed, knots=knots)
    if not closed:
        kwargs["end_condition"] = draw(st.sampled_from(end_conditions))
    if tension:
        kwargs["point_tension"] = rng.uniform(0, 5, n) * draw(st.sampled_from([0.0, 0.01, 1.0]))
    if weights:
        kwargs["interval_weights"] = rng.uniform(0.2, 5, m)
    return points, kwargs


def one_sided_second(spline):
    """P''(t_i^-) and P''(t_i^+) at every knot from the Bézier pieces (§0)."""
    left = spline(spline.knots, 2, side="left")
    right = spline(spline.knots, 2, side="right")
    return left, right


# ---------------------------------------------------------------- core properties
@SETTINGS
@given(problems())
def test_interpolates_the_points(problem):
    points, kwargs = problem
    spline = interpolate(points, **kwargs)
    expected = np.vstack([points, points[:1]]) if spline.closed else points
    np.testing.assert_allclose(spline(spline.knots, side="left"), expected, atol=1e-9 * np.abs(points).max())
    np.testing.assert_array_equal(spline.knot_points, expected)
    assert spline.n_segments == (len(points) if spline.closed else len(points) - 1)


@SETTINGS
@given(problems())
def test_joint_constraint_holds_at_every_joint(problem):
    """omega_i P''(t_i^+) = v_i P'(t_i) + omega_{i-1} P''(t_i^-) (§2.2, thesis 3.13-3.14)."""
    points, kwargs = problem
    spline = interpolate(points, **kwargs)
    v = np.broadcast_to(kwargs.get("point_tension", 0.0), (len(points),))
    omega = np.broadcast_to(kwargs.get("interval_weights", 1.0), (spline.n_segments,))
    left, right = one_sided_second(spline)
    velocity_left = spline(spline.knots, 1, side="left")
    velocity_right = spline(spline.knots, 1, side="right")
    np.testing.assert_allclose(velocity_left, velocity_right, rtol=1e-9, atol=1e-9 * np.abs(velocity_right).max())
    if spline.closed:
        joints = np.arange(len(points))  # every point, including the seam t_0 = t_N
        omega_prev, omega_next = np.roll(omega, 1), omega
    else:
        joints = np.arange(1, len(points) - 1)
        omega_prev, omega_next = omega[:-1], omega[1:]
    lhs = omega_next[:, None] * right[joints]
    rhs = v[joints, None] * velocity_right[joints] + omega_prev[:, None] * left[joints]
    scale = np.abs(omega_next[:, None] * right[joints]).max(initial=0) + np.abs(rhs).max(initial=0) + 1e-300
    np.testing.assert_allclose(lhs, rhs, atol=1e-8 * scale)


@SETTINGS
@given(problems(closed=True))
def test_periodic_closure(problem):
    points, kwargs = problem
    spline = interpolate(points, **kwargs)
    t0, tm = spline.domain
    for nu in (0, 1):
        scale = np.abs(spline(t0, nu)).max() + 1e-300
        np.testing.assert_allclose(spline(tm, nu, side="left"), spline(t0, nu), atol=1e-9 * scale)
    assert spline.to_svg_path().endswith("Z")


@SETTINGS
@given(problems(tension=False, weights=False))
def test_one_sided_curvature_ratio_is_weight_ratio(problem):
    """kappa(t_i^+) / kappa(t_i^-) = omega_{i-1} / omega_i, for any v (§2.2, E2)."""
    points, kwargs = problem
    rng = np.random.default_rng(len(points))
    m = len(points) if kwargs["closed"] else len(points) - 1
    omega = rng.uniform(0.3, 4, m)
    v = rng.uniform(0, 2, len(points)) * 0.01
    spline = interpolate(points, interval_weights=omega, point_tension=v, **kwargs)
    joints = spline.joint_curvature()
    if spline.closed:
        index, ratio = np.arange(m), np.roll(omega, 1) / omega
    else:
        index, ratio = np.arange(1, m), omega[:-1] / omega[1:]
    minus, plus = joints[index, 0], joints[index, 1]
    keep = np.abs(minus) > 1e-9 * np.abs(minus).max(initial=0)
    np.testing.assert_allclose(plus[keep], ratio[keep] * minus[keep], rtol=1e-7)


@SETTINGS
@given(problems(), st.sampled_from(sorted(CLASS_PRESETS)), st.floats(0.5, 6))
def test_class_parameters_cancel_and_only_move_class_polygon(problem, preset, free):
    """E1: alpha, beta do not change the curve; V_i = F_i + h_i M_i / alpha_i, W_i = F_{i+1} - h_i M_{i+1} / beta_i."""
    points, kwargs = problem
    reference = interpolate(points, **kwargs)
    alpha, beta = CLASS_PRESETS[preset]
    spline = interpolate(points, alpha=alpha, beta=free * beta, **kwargs)
    np.testing.assert_array_equal(spline.bezier(), reference.bezier())
    h = np.diff(spline.knots)[:, None]
    M = spline.auxiliary["tangents"]
    F = spline.knot_points
    M_next = np.roll(M, -1, 0) if spline.closed else M[1:]
    np.testing.assert_allclose(spline.auxiliary["V"], F[:-1] + h * M[: len(h)] / alpha, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(spline.auxiliary["W"], F[1:] - h * M_next[: len(h)] / (free * beta), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(M, spline(spline.knots[: len(M)], 1), rtol=1e-9, atol=1e-9)


# ---------------------------------------------------------------- scipy reference
@SETTINGS
@given(st.integers(2, 15), st.integers(0, 2**32 - 1), st.sampled_from(KNOT_METHODS), st.floats(0.1, 10))
def test_matches_scipy_natural_and_clamped(n, seed, knots, omega):
    rng = np.random.default_rng(seed)
    points = random_points(rng, n)
    for end_condition in ("natural", "natural_v"):  # identical for v = 0
        spline = interpolate(points, knots=knots, interval_weights=omega, end_condition=end_condition)
        reference = CubicSpline(spline.knots, points, bc_type="natural")
        _compare_with_scipy(spline, reference)
    end = rng.normal(size=(2, 2)) * 10
    spline = interpolate(points, knots=knots, interval_weights=omega, end_condition="clamped", end_tangents=end)
    reference = CubicSpline(spline.knots, points, bc_type=((1, end[0]), (1, end[1])))
    _compare_with_scipy(spline, reference)


@SETTINGS
@given(st.integers(3, 15), st.integers(0, 2**32 - 1), st.sampled_from(KNOT_METHODS), st.floats(0.1, 10))
def test_matches_scipy_periodic(n, seed, knots, omega):
    rng = np.random.default_rng(seed)
    points = random_points(rng, n)
    spline = interpolate(points, closed=True, knots=knots, interval_weights=omega)
    reference = CubicSpline(spline.knots, np.vstack([points, points[:1]]), bc_type="periodic")
    _compare_with_scipy(spline, reference)
    periodic = interpolate(points, end_condition="periodic", knots=knots, interval_weights=omega)
    np.testing.assert_array_equal(periodic.bezier(), spline.bezier())


def _compare_with_scipy(spline, reference):
    knots = spline.knots
    M = spline.auxiliary["tangents"]
    scale = np.abs(reference(knots, 1)).max()
    np.testing.assert_allclose(M, reference(knots[: len(M)], 1), atol=1e-9 * scale)
    t = np.linspace(knots[0], knots[-1], 257)
    np.testing.assert_allclose(spline(t), reference(t), atol=1e-9 * np.abs(reference(t)).max())


def test_default_clamped_tangents_are_exact_for_quadratics():
    """§6.3: the 3-point parabola end derivatives are exact for quadratic data, for any h."""
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(0.2, 3, 9))
    coefficients = rng.normal(size=(3, 2))
    points = coefficients[0] + t[:, None] * coefficients[1] + t[:, None] ** 2 * coefficients[2]
    spline = interpolate(points, knots=t, end_condition="clamped")
    exact = coefficients[1] + 2 * t[:, None] * coefficients[2]
    # a clamped cubic spline with exact end slopes reproduces every quadratic (v = 0, omega const)
    np.testing.assert_allclose(spline.auxiliary["tangents"], exact, rtol=1e-10, atol=1e-10)
    s = np.linspace(t[0], t[-1], 50)
    quadratic = coefficients[0] + s[:, None] * coefficients[1] + s[:, None] ** 2 * coefficients[2]
    np.testing.assert_allclose(spline(s), quadratic, atol=1e-9 * np.abs(quadratic).max())
    first, last = end_derivative_estimates(points[:2], np.diff(t[:2]))
    np.testing.assert_allclose(first, (points[1] - points[0]) / (t[1] - t[0]))
    np.testing.assert_allclose(last, first)
    partial = interpolate(points, knots=t, end_condition="clamped", end_tangents=(None, [1.0, 2.0]))
    np.testing.assert_allclose(partial.auxiliary["tangents"][[0, -1]], [exact[0], [1.0, 2.0]], rtol=1e-12)


# ---------------------------------------------------------------- end conditions
@SETTINGS
@given(problems(closed=False, end_conditions=("natural", "natural_v")))
def test_end_conditions(problem):
    points, kwargs = problem
    spline = interpolate(points, **kwargs)
    second = spline(spline.knots[[0, -1]], 2, side="right"), spline(spline.knots[-1], 2, side="left")
    start, end = second[0][0], second[1]
    velocity = spline(spline.knots[[0, -1]], 1, side="left")
    scale = np.abs(spline(spline.knots, 2)).max() + np.abs(velocity).max() + 1e-300
    if kwargs["end_condition"] == "natural":
        np.testing.assert_allclose([start, end], 0.0, atol=1e-9 * scale)
    else:
        v = np.broadcast_to(kwargs["point_tension"], (len(points),))
        omega = np.broadcast_to(kwargs["interval_weights"], (len(points) - 1,))
        np.testing.assert_allclose(start, v[0] * velocity[0] / omega[0], atol=1e-9 * scale)
        np.testing.assert_allclose(end, -v[-1] * velocity[1] / omega[-1], atol=1e-9 * scale)


def _energy(spline, omega, v):
    """E = sum_i omega_i int ||P''||^2 dt + sum_i v_i ||M_i||^2 (§2.2), exact for linear P''."""
    b = spline.bezier()
    h = np.diff(spline.knots)
    A = 6 * (b[:, 0] - 2 * b[:, 1] + b[:, 2]) / h[:, None] ** 2
    B = 6 * (b[:, 1] - 2 * b[:, 2] + b[:, 3]) / h[:, None] ** 2
    bending = h / 3 * ((A * A).sum(1) + (A * B).sum(1) + (B * B).sum(1))
    M = spline.auxiliary["tangents"]
    return float((omega * bending).sum() + (v * (M * M).sum(1)).sum())


@SETTINGS
@given(problems(end_conditions=("natural_v", "clamped")), st.integers(0, 2**32 - 1))
def test_solution_minimises_the_energy(problem, seed):
    """Types 1, 2v and 3 minimise E (§2.2, §2.5 safe domain); perturbing the tangents raises E."""
    from splinecraft.spline.piecewise import Spline
    from splinecraft.spline.segment import hermite_bezier

    points, kwargs = problem
    spline = interpolate(points, **kwargs)
    v = np.broadcast_to(kwargs.get("point_tension", 0.0), (len(points),)).astype(float)
    omega = np.broadcast_to(kwargs.get("interval_weights", 1.0), (spline.n_segments,))
    best = _energy(spline, omega, v)
    rng = np.random.default_rng(seed)
    M = spline.auxiliary["tangents"]
    h = np.diff(spline.knots)
    for _ in range(5):
        delta = rng.normal(size=M.shape) * 1e-3 * (np.abs(M).max() + 1)
        if kwargs.get("end_condition") == "clamped":
            delta[[0, -1]] = 0.0  # the clamped ends are constraints, not free
        other = Spline(hermite_bezier(points, M + delta, h, spline.closed), spline.knots, closed=spline.closed,
                       auxiliary={"tangents": M + delta})
        assert _energy(other, omega, v) >= best * (1 - 1e-12)


# ---------------------------------------------------------------- invariance and symmetry
@SETTINGS
@given(problems(), st.integers(0, 2**32 - 1))
def test_affine_invariance_with_explicit_knots(problem, seed):
    points, kwargs = problem
    reference = interpolate(points, **kwargs)
    rng = np.random.default_rng(seed)
    matrix = rng.normal(size=(2, 2))
    assume(abs(np.linalg.det(matrix)) > 0.1)
    offset = rng.normal(size=2) * 100
    kwargs = dict(kwargs, knots=reference.knots)
    if kwargs.get("end_condition") == "clamped":
        kwargs["end_tangents"] = tuple(reference.auxiliary["tangents"][[0, -1]] @ matrix.T)
    image = interpolate(points @ matrix.T + offset, **kwargs)
    expected = reference.transformed(matrix, offset)
    np.testing.assert_allclose(image.bezier(), expected.bezier(), atol=1e-8 * np.abs(expected.bezier()).max())


@SETTINGS
@given(problems(tension=False), st.floats(0.01, 100), st.floats(0, 2 * np.pi))
def test_similarity_invariance_with_relative_tension(problem, scale, angle):
    """Chord/centripetal knots: rigid motions always; scaling only with v = 0 or relative tension (§3)."""
    points, kwargs = problem
    rng = np.random.default_rng(len(points))
    nu = rng.uniform(0, 3, len(points))
    kwargs = dict(kwargs, point_tension=nu, point_tension_scale="relative")
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    reference = interpolate(points, **kwargs)
    image = interpolate(scale * points @ rotation.T, **kwargs)
    # knots scale by scale**e; the curve geometry scales with the points
    expected = reference.transformed(scale * rotation)
    np.testing.assert_allclose(image.bezier(), expected.bezier(), atol=1e-8 * np.abs(expected.bezier()).max())


def test_absolute_tension_is_not_scale_invariant_with_chord_knots():
    points = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 3.0], [4.0, 1.0], [6.0, 0.0]])
    small = interpolate(points, point_tension=1.0)
    large = interpolate(100 * points, point_tension=1.0)
    difference = np.abs(large.bezier() - 100 * small.bezier()).max()
    assert difference > 1.0  # §3: a fixed v changes weight relative to c = omega / h


@SETTINGS
@given(problems())
def test_reversal_symmetry(problem):
    points, kwargs = problem
    spline = interpolate(points, **kwargs)
    n = len(points)
    v = np.broadcast_to(kwargs.get("point_tension", 0.0), (n,))
    omega = np.broadcast_to(kwargs.get("interval_weights", 1.0), (spline.n_segments,))
    if spline.closed:
        order = np.roll(np.arange(n)[::-1], 1)  # start at the same point, run backwards
        back_kwargs = dict(kwargs, point_tension=v[order], interval_weights=omega[::-1])
    else:
        order = np.arange(n)[::-1]
        back_kwargs = dict(kwargs, point_tension=v[order], interval_weights=omega[::-1])
        if kwargs.get("end_condition") == "clamped":
            M = spline.auxiliary["tangents"]
            back_kwargs["end_tangents"] = (-M[-1], -M[0])
    back = interpolate(points[order], **back_kwargs)
    expected = spline.reversed()
    np.testing.assert_allclose(back.knots, expected.knots, atol=1e-9 * expected.knots[-1])
    np.testing.assert_allclose(back.bezier(), expected.bezier(), atol=1e-8 * np.abs(points).max())


# ---------------------------------------------------------------- point tension (§2.5)
def _deviation_from_polygon(spline, points):
    _, samples = spline.sample(samples_per_segment=64)
    a, b = points[:-1], points[1:]
    rel = samples[:, None] - a[None]
    chord = b - a
    u = np.clip((rel * chord).sum(-1) / (chord * chord).sum(-1), 0, 1)
    return np.linalg.norm(rel - u[..., None] * chord, axis=-1).min(axis=1).max()


def test_positive_tension_tightens_towards_the_polygon():
    """E22: increasing v pulls the curve to the polygon (thesis Figs 3.5-3.6 claim no effect)."""
    zigzag = np.stack([np.arange(8.0), np.arange(8) % 2], axis=1)
    for points in (zigzag, 100 * zigzag):
        deviations = [_deviation_from_polygon(interpolate(points, point_tension=v), points)
                      for v in (0.0, 1.0, 3.0, 10.0, 100.0, 1e4)]
        assert all(a > b for a, b in zip(deviations, deviations[1:]))
        assert deviations[-1] < 1e-3 * deviations[0]
    # The size of the effect of a given v depends on the scale (v has the units of c = omega / h):
    # the spec's "v: 0 -> 10 reduces the deviation 40-fold" is a property of one data scale only.
    unit = [_deviation_from_polygon(interpolate(zigzag, point_tension=v), zigzag) for v in (0.0, 10.0)]
    pixels = [_deviation_from_polygon(interpolate(100 * zigzag, point_tension=v), 100 * zigzag) for v in (0.0, 10.0)]
    assert unit[0] / unit[1] < 5 and pixels[0] / pixels[1] > 100


def test_huge_tension_gives_zero_tangents():
    points = random_points(np.random.default_rng(3), 7)
    spline = interpolate(points, point_tension=1e12, end_condition="natural_v")
    assert np.abs(spline.auxiliary["tangents"]).max() < 1e-6


def test_reversed_range_reverses_the_tangent():
    """v_k < -6 (c_{k-1} + c_k): unique solution, tangent antiparallel to the weighted chord average."""
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 1.5], [3.0, 1.0], [4.0, 0.0]])
    t = np.arange(5.0)
    c = np.ones(4)
    k = 2
    average = c[k - 1] * (points[k] - points[k - 1]) + c[k] * (points[k + 1] - points[k])
    for factor in (-7.0, -50.0, -1e4):
        v = np.zeros(5)
        v[k] = factor * (c[k - 1] + c[k])
        spline = interpolate(points, knots=t, point_tension=v)
        M = spline.auxiliary["tangents"][k]
        cosine = M @ average / np.linalg.norm(M) / np.linalg.norm(average)
        assert cosine < 0
    assert cosine < -0.999
    # the joint constraint still holds in the reversed range
    left = spline(t[k], 2, side="left")
    right = spline(t[k], 2)
    np.testing.assert_allclose(right, v[k] * M + left, rtol=1e-9, atol=1e-9 * np.abs(v[k] * M).max())


def test_closed_curve_in_reversed_range():
    theta = np.linspace(0, 2 * np.pi, 7)[:-1]
    points = np.stack([np.cos(theta), np.sin(theta)], axis=1) * 50
    spline = interpolate(points, closed=True, knots="uniform", point_tension=-20.0)  # < -6 * 2
    left, right = spline(spline.knots[:-1], 2, side="left"), spline(spline.knots[:-1], 2)
    M = spline.auxiliary["tangents"]
    np.testing.assert_allclose(right, -20.0 * M + left, atol=1e-9 * np.abs(left).max())


def test_spec_singular_example_is_singular_and_rejected():
    """§2.5: h = omega = 1, v = -8, n = 9, Type 1 gives a zero diagonal and a singular matrix."""
    n = 9
    matrix = np.zeros((n, n))
    matrix[0, 0] = matrix[-1, -1] = 1.0  # clamped rows
    for k in range(1, n - 1):
        matrix[k, k - 1 : k + 2] = [1.0, 0.5 * -8 + 2 + 2, 1.0]
    assert np.linalg.matrix_rank(matrix) < n  # independent check of the spec's claim
    points = np.stack([np.arange(n, dtype=float), np.sin(np.arange(n))], axis=1)
    with pytest.raises(ValueError, match=r"point_tension\[1\] = -8 .*\[-12, -4\]"):
        interpolate(points, knots="uniform", point_tension=-8.0, end_condition="clamped")


def test_relative_tension_equals_absolute_tension_times_span():
    rng = np.random.default_rng(11)
    points = random_points(rng, 8)
    nu = rng.uniform(-1.5, 4, 8)
    omega = rng.uniform(0.5, 2, 7)
    relative = interpolate(points, point_tension=nu, interval_weights=omega, point_tension_scale="relative",
                           end_condition="natural_v")
    c = omega / np.diff(relative.knots)
    span = np.concatenate([[c[0]], c[:-1] + c[1:], [c[-1]]])
    absolute = interpolate(points, point_tension=nu * span, interval_weights=omega, end_condition="natural_v")
    np.testing.assert_allclose(relative.bezier(), absolute.bezier(), rtol=1e-12, atol=1e-9)
    with pytest.raises(ValueError, match=r"point_tension\[3\] = -3 \(relative\)"):
        interpolate(points, point_tension=np.where(np.arange(8) == 3, -3.0, 0.0), point_tension_scale="relative")


def test_natural_v_end_row_dominance():
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]])
    with pytest.raises(ValueError, match=r"point_tension\[0\].*\[-6, -2\] \* c_1"):
        interpolate(points, knots="uniform", point_tension=[-3.0, 0, 0], end_condition="natural_v")
    interpolate(points, knots="uniform", point_tension=[-3.0, 0, 0], end_condition="natural")  # unused there


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kwargs, error, pattern",
    [
        (dict(points=[[0.0, 0.0]]), ValueError, "at least 2 points"),
        (dict(points=[[0.0, 0.0], [1.0, 0.0]], closed=True), ValueError, "at least 3 points"),
        (dict(points=[[0.0, 0.0], [1.0, np.nan], [2.0, 0.0]]), ValueError, r"points\[1, 1\] is nan"),
        (dict(points=[[0.0, 0.0], [1.0, np.inf], [2.0, 0.0]]), ValueError, r"points\[1, 1\] is inf"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [2.0, 0.0]]), ValueError, r"points\[1\] and points\[2\] coincide"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [0.0, 0.0]], closed=True), ValueError, r"points\[3\] and points\[0\].*do not repeat"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], interval_weights=[1.0, 0.0]), ValueError, r"interval_weights\[1\] = 0.0 must be > 0"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], interval_weights=[1.0, -2.0]), ValueError, r"interval_weights\[1\]"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], interval_weights=[1.0, 1.0, 1.0]), ValueError, r"interval_weights has length 3 but 2"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], point_tension=[1.0, 1.0]), ValueError, r"point_tension has length 2 but 3"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], alpha=[1.0]), ValueError, r"alpha has length 1 but 2"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], beta=[1.0, 0.0]), ValueError, r"beta\[1\] = 0"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], knots=[0.0, 2.0, 2.0]), ValueError, r"knots\[2\] = 2.0 <= knots\[1\]"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], knots=[0.0, 1.0]), ValueError, "knots has length 2"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], closed=True, knots=[0.0, 1.0, 2.0]), ValueError, r"N \+ 1 = 4"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], knots="arc"), ValueError, "knots must be one of"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], end_condition="free"), ValueError, "end_condition must be one of"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], closed=True, end_condition="clamped"), ValueError, "periodic"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], end_tangents=([1, 0], [1, 0])), ValueError, "only used with end_condition='clamped'"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], end_condition="clamped", end_tangents=([1, 0, 0], None)), ValueError, "M_1 must be a vector of length 2"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], point_tension=[0.0, np.nan, 0.0]), ValueError, r"point_tension\[1\] is nan"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], closed="yes"), TypeError, "closed must be a bool"),
        (dict(points="abc"), TypeError, "points must be numeric"),
        (dict(points=[0.0, 1.0, 2.0]), ValueError, r"\(n, d\)"),
        (dict(points=[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], point_tension_scale="pixels"), ValueError, "point_tension_scale"),
    ],
)
def test_bad_input_raises_with_a_clear_message(kwargs, error, pattern):
    kwargs = dict(kwargs)
    points = kwargs.pop("points")
    with pytest.raises(error, match=pattern):
        interpolate(points, **kwargs)


def test_ill_conditioned_system_is_rejected():
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [3.0, 1.0]])
    # just outside the band: dominant, but the margin is tiny -> condition bound > 1e12
    v = -2 * 2 * (1 - 1e-14)
    with pytest.raises(ValueError, match="ill-conditioned"):
        interpolate(points, knots="uniform", point_tension=[0.0, v, 0.0, 0.0])


@pytest.mark.parametrize("scale", [1.0, 1e300])
def test_weights_too_far_apart_are_reported_in_the_callers_units(scale):
    """Weights 1e300 and 1e-300 in one curve cannot share a tangent system (the power-of-two rescaling of
    §2.5 Units flushes the small one to 0). The message names the weight and h_i the caller passed, not
    the rescaled 'interval_weights[2] = 0.0'."""
    points = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [4.0, 3.0], [6.0, 0.0]]) * scale
    with pytest.raises(ValueError, match=r"interval_weights\[2\] = 1e-300") as caught:
        interpolate(points, interval_weights=[1.0, 1e300, 1e-300, 1.0])
    assert f"h_2 = {np.hypot(1.0, 2.0) * scale:.3g}" in str(caught.value)


def test_one_dimensional_and_three_dimensional_data():
    rng = np.random.default_rng(5)
    t = np.cumsum(rng.uniform(0.5, 2, 10))
    values = rng.normal(size=(10, 1))
    spline = interpolate(values, knots=t)
    np.testing.assert_allclose(spline(t[:, None].ravel()), values, atol=1e-12)
    reference = CubicSpline(t, values, bc_type="natural")
    s = np.linspace(t[0], t[-1], 40)
    np.testing.assert_allclose(spline(s), reference(s), atol=1e-12)
    space = interpolate(random_points(rng, 6).repeat(2, axis=1)[:, :3], closed=True)
    assert space.dim == 3 and space.closed


# ---------------------------------------------------------------- knot parameterization (§3)
def test_parameterize_and_remove_coincident():
    from splinecraft.spline.knots import parameterize, remove_coincident

    points = np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 4.0], [3.0, 4.0], [6.0, 8.0], [0.0, 0.0]])
    kept, index = remove_coincident(points)
    np.testing.assert_array_equal(index, [0, 1, 4, 5])
    kept_closed, index_closed = remove_coincident(points, closed=True)
    np.testing.assert_array_equal(index_closed, [0, 1, 4])  # the final repeat of the first point goes too
    np.testing.assert_allclose(parameterize(kept, "chord"), [0, 5, 10, 20])
    np.testing.assert_allclose(parameterize(kept, "centripetal"), np.concatenate([[0], np.cumsum(np.sqrt([5, 5, 10]))]))
    np.testing.assert_allclose(parameterize(kept, "uniform"), [0, 1, 2, 3])
    np.testing.assert_allclose(parameterize(kept_closed, "chord", closed=True), [0, 5, 10, 20])
    spline = interpolate(kept_closed, closed=True, knots="centripetal")
    np.testing.assert_allclose(np.diff(spline.knots), np.sqrt([5.0, 5.0, 10.0]))


def test_caller_arrays_are_not_modified_or_frozen():
    rng = np.random.default_rng(21)
    points = random_points(rng, 6)
    knots = np.cumsum(rng.uniform(0.5, 2, 6))
    weights = rng.uniform(0.5, 2, 5)
    before = points.copy(), knots.copy(), weights.copy()
    spline = interpolate(points, knots=knots, interval_weights=weights, point_tension=np.ones(6))
    for array, copy in zip((points, knots, weights), before):
        assert array.flags.writeable
        np.testing.assert_array_equal(array, copy)
    points[0] += 1.0  # the spline keeps its own data
    np.testing.assert_array_equal(spline.knot_points[0], before[0][0])
    with pytest.raises(ValueError):
        spline.knots[0] = 5.0  # the spline's arrays are read-only
