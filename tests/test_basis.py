"""Tests of the local-support basis form ``basis_spline`` / ``basis_functions`` (§4, thesis section 3.2).

Independent references: scipy's BSpline (v = 0, omega = 1; uniform, non-uniform and clamped knots), the
joint constraint evaluated from the Bézier pieces, and the interpolant of §2 through the knot points.
"""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st
from scipy.interpolate import BSpline

from splinecraft.spline.basis import basis_functions, basis_spline
from splinecraft.spline.interpolant import interpolate

SETTINGS = settings(max_examples=50, deadline=None)


@st.composite
def basis_problems(draw, closed=None, ends=None, tension=True, weights=True, knots=None):
    closed = draw(st.booleans()) if closed is None else closed
    ends = "floating" if closed else (draw(st.sampled_from(["floating", "clamped"])) if ends is None else ends)
    n_control = draw(st.integers(3 if closed else 4, 12))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    points = rng.uniform(-100, 100, size=(n_control, 2))
    legs = n_control if closed else n_control - 1
    knot_choice = draw(st.sampled_from(["uniform", "chord", "centripetal", "explicit"])) if knots is None else knots
    if knot_choice == "explicit":
        count = n_control + 1 if closed else (n_control - 2 if ends == "clamped" else n_control)
        knot_choice = np.cumsum(rng.uniform(0.3, 3, count)) - 2.0
    kwargs = dict(closed=closed, ends=ends, knots=knot_choice)
    if tension:
        kwargs["point_tension"] = rng.uniform(0, 4, n_control) * draw(st.sampled_from([0.0, 0.05, 1.0]))
    if weights:
        kwargs["interval_weights"] = rng.uniform(0.3, 4, legs)
    return points, kwargs


def _extended_knots(spline, kwargs, n_control):
    """Full scipy knot vector t_{-2}..t_{n+3} for the floating / clamped cases (§4.4)."""
    k = spline.knots
    if kwargs["ends"] == "clamped":
        return np.concatenate([[k[0]] * 3, k, [k[-1]] * 3])
    values = spline.knots  # t_1..t_n
    if isinstance(kwargs["knots"], np.ndarray):
        full = kwargs["knots"]  # t_0..t_{n+1}
    else:
        full = None
    if full is None:
        raise AssertionError("use explicit knots")
    h0, hn = full[1] - full[0], full[-1] - full[-2]
    assert np.allclose(values, full[1:-1])
    return np.concatenate([[full[0] - 2 * h0, full[0] - h0], full, [full[-1] + hn, full[-1] + 2 * hn]])


# ---------------------------------------------------------------- B-spline references
@SETTINGS
@given(st.integers(4, 14), st.integers(0, 2**32 - 1), st.booleans())
def test_uniform_cubic_bspline_recovered(n_control, seed, uniform):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n_control, 2)) * 50
    knots = np.arange(n_control, dtype=float) if uniform else np.cumsum(rng.uniform(0.2, 3, n_control))
    spline = basis_spline(points, knots="uniform" if uniform else knots)
    if uniform:
        expected = (points[:-2] + 4 * points[1:-1] + points[2:]) / 6
        np.testing.assert_allclose(spline.knot_points, expected, atol=1e-12 * 50)
    h0, hn = knots[1] - knots[0], knots[-1] - knots[-2]
    full = np.concatenate([[knots[0] - 2 * h0, knots[0] - h0], knots, [knots[-1] + hn, knots[-1] + 2 * hn]])
    reference = BSpline(full, points, 3)
    t = np.linspace(knots[1], knots[-2], 301)
    np.testing.assert_allclose(spline(t), reference(t), atol=1e-11 * 50)


@SETTINGS
@given(st.integers(4, 14), st.integers(0, 2**32 - 1), st.booleans())
def test_clamped_matches_scipy_clamped_bspline(n_control, seed, uniform):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n_control, 2)) * 50
    knots = "uniform" if uniform else np.cumsum(rng.uniform(0.2, 3, n_control - 2))
    spline = basis_spline(points, knots=knots, ends="clamped")
    k = spline.knots
    reference = BSpline(np.concatenate([[k[0]] * 3, k, [k[-1]] * 3]), points, 3)
    t = np.linspace(k[0], k[-1], 301)
    np.testing.assert_allclose(spline(t), reference(t), atol=1e-11 * 50)
    np.testing.assert_allclose(spline.knot_points[[0, -1]], points[[0, -1]], atol=1e-12)
    h1, hl = k[1] - k[0], k[-1] - k[-2]
    np.testing.assert_allclose(spline(k[0], 1), 3 * (points[1] - points[0]) / h1, rtol=1e-12)
    np.testing.assert_allclose(spline(k[-1], 1, side="left"), 3 * (points[-1] - points[-2]) / hl, rtol=1e-12)


@SETTINGS
@given(st.integers(5, 12), st.integers(0, 2**32 - 1), st.booleans())
def test_basis_functions_equal_scipy_basis_elements(n_control, seed, uniform):
    rng = np.random.default_rng(seed)
    knots = np.arange(n_control, dtype=float) if uniform else np.cumsum(rng.uniform(0.2, 3, n_control))
    h0, hn = knots[1] - knots[0], knots[-1] - knots[-2]
    full = np.concatenate([[knots[0] - 2 * h0, knots[0] - h0], knots, [knots[-1] + hn, knots[-1] + 2 * hn]])
    t = np.linspace(knots[1], knots[-2], 401)
    values = basis_functions(t, n_control if uniform else knots).toarray()
    assert values.shape == (t.size, n_control)
    for j in range(n_control):
        element = BSpline.basis_element(full[j : j + 5], extrapolate=False)  # t_{j-2}..t_{j+2}
        expected = np.nan_to_num(element(t))
        np.testing.assert_allclose(values[:, j], expected, atol=1e-12)


# ---------------------------------------------------------------- basis properties
@SETTINGS
@given(basis_problems())
def test_partition_of_unity_and_non_negativity(problem):
    points, kwargs = problem
    n_control = points.shape[0]
    spline = basis_spline(points, **kwargs)
    knots = kwargs["knots"] if not isinstance(kwargs["knots"], str) else _uniform_or_named(spline, kwargs, points)
    t = np.linspace(spline.knots[0], spline.knots[-1], 257)
    values = basis_spline(np.eye(n_control), **dict(kwargs, knots=knots))(t)
    np.testing.assert_allclose(values.sum(axis=1), 1.0, atol=1e-12)
    assert values.min() >= -1e-12  # v >= 0, omega > 0 (§4.5)
    # the curve is the basis combination of the control points
    np.testing.assert_allclose(values @ points, spline(t), atol=1e-9 * 100)


def _uniform_or_named(spline, kwargs, points):
    """Explicit knot values equivalent to a named choice, so the identity-matrix basis uses the same knots."""
    if kwargs["knots"] == "uniform":
        return "uniform"
    closed, ends = kwargs["closed"], kwargs["ends"]
    if closed:
        return spline.knots
    if ends == "clamped":
        return spline.knots
    exponent = {"chord": 1.0, "centripetal": 0.5}[kwargs["knots"]]
    legs = np.linalg.norm(np.diff(points, axis=0), axis=1) ** exponent
    return np.concatenate([[0.0], np.cumsum(legs)])


@SETTINGS
@given(basis_problems(knots="uniform"), st.data())
def test_local_support(problem, data):
    """Moving P_j changes only the (at most 4) segments j-2..j+1 it supports (§4.1)."""
    points, kwargs = problem
    n_control = points.shape[0]
    j = data.draw(st.integers(0, n_control - 1))
    moved = points.copy()
    moved[j] += [17.0, -5.0]
    before = basis_spline(points, **kwargs).bezier()
    after = basis_spline(moved, **kwargs).bezier()
    changed = np.flatnonzero(np.abs(after - before).max(axis=(1, 2)) > 0)
    m = before.shape[0]
    if kwargs["closed"]:
        allowed = {(j + k) % n_control for k in (-2, -1, 0, 1)}
    else:
        allowed = {s - 1 for s in range(j - 2, j + 2) if 1 <= s <= n_control - 3}  # thesis segments 1..n-1
    assert set(changed.tolist()) <= allowed
    assert len(changed) <= 4 and m >= 1


@SETTINGS
@given(st.sampled_from(["chord", "centripetal"]), st.booleans(), st.integers(0, 2 ** 32 - 1))
def test_local_support_with_knots_from_the_legs(knots, closed, seed):
    """With chord or centripetal knots P_j also moves the knots of its two legs: at most six segments,
    j-3..j+2, change (the basis_spline docstring)."""
    rng = np.random.default_rng(seed)
    n_control = int(rng.integers(7, 12))
    points = rng.normal(size=(n_control, 2)) * 10
    j = int(rng.integers(0, n_control))
    moved = points.copy()
    moved[j] += [17.0, -5.0]
    before = basis_spline(points, knots=knots, closed=closed).bezier()
    after = basis_spline(moved, knots=knots, closed=closed).bezier()
    changed = set(np.flatnonzero(np.abs(after - before).max(axis=(1, 2)) > 0).tolist())
    if closed:
        allowed = {(j + k) % n_control for k in range(-3, 3)}
    else:
        allowed = {s - 1 for s in range(j - 3, j + 3) if 1 <= s <= n_control - 3}
    assert changed <= allowed and len(changed) <= 6


@SETTINGS
@given(basis_problems())
def test_joint_constraint_at_every_knot(problem):
    """omega_i P''(t_i^+) = v_i P'(t_i) + omega_{i-1} P''(t_i^-) (§2.2, §4.5; checks errata E9, E10)."""
    points, kwargs = problem
    spline = basis_spline(points, **kwargs)
    n_control = points.shape[0]
    v = np.broadcast_to(kwargs.get("point_tension", 0.0), (n_control,))
    legs = n_control if kwargs["closed"] else n_control - 1
    omega = np.broadcast_to(kwargs.get("interval_weights", 1.0), (legs,))
    knots = spline.knots
    left, right = spline(knots, 2, side="left"), spline(knots, 2)
    velocity = spline(knots, 1)
    np.testing.assert_allclose(spline(knots, 1, side="left"), velocity, atol=1e-8 * np.abs(velocity).max())
    if kwargs["closed"]:
        joints = np.arange(n_control)  # knot i <-> control point i, leg i
        v_j, w_prev, w_next = v, np.roll(omega, 1), omega
    else:
        joints = np.arange(1, len(knots) - 1)  # interior knots t_2..t_{n-1} <-> control points 2..n-1
        v_j, w_prev, w_next = v[joints + 1], omega[joints], omega[joints + 1]
    lhs = w_next[:, None] * right[joints]
    rhs = v_j[:, None] * velocity[joints] + w_prev[:, None] * left[joints]
    scale = np.abs(lhs).max(initial=0) + np.abs(rhs).max(initial=0) + 1e-300
    np.testing.assert_allclose(lhs, rhs, atol=1e-8 * scale)


@SETTINGS
@given(basis_problems())
def test_interpolating_the_knot_points_reproduces_the_curve(problem):
    """Cross-check (§4.5): interpolate() through F_i with the basis curve's M_1, M_n gives the same curve."""
    points, kwargs = problem
    spline = basis_spline(points, **kwargs)
    n_control = points.shape[0]
    v = np.broadcast_to(kwargs.get("point_tension", 0.0), (n_control,))
    legs = n_control if kwargs["closed"] else n_control - 1
    omega = np.broadcast_to(kwargs.get("interval_weights", 1.0), (legs,))
    F = spline.auxiliary["F"]
    assume(np.linalg.norm(np.diff(F, axis=0), axis=1).min() > 1e-6)
    if kwargs["closed"]:
        assume(np.linalg.norm(F[0] - F[-1]) > 1e-6)
        again = interpolate(F, closed=True, knots=spline.knots, point_tension=v, interval_weights=omega)
    else:
        M = spline.auxiliary["tangents"]
        again = interpolate(F, knots=spline.knots, point_tension=v[1:-1], interval_weights=omega[1:-1],
                            end_condition="clamped", end_tangents=(M[0], M[-1]))
    np.testing.assert_allclose(again.bezier(), spline.bezier(), atol=1e-7 * np.abs(points).max())


@SETTINGS
@given(basis_problems(tension=False, weights=False))
def test_curvature_jump_ratio(problem):
    points, kwargs = problem
    n_control = points.shape[0]
    rng = np.random.default_rng(n_control)
    legs = n_control if kwargs["closed"] else n_control - 1
    omega = rng.uniform(0.3, 3, legs)
    spline = basis_spline(points, interval_weights=omega, point_tension=0.5, **kwargs)
    joints = spline.joint_curvature()
    if kwargs["closed"]:
        index, ratio = np.arange(n_control), np.roll(omega, 1) / omega
    else:
        index = np.arange(1, spline.n_segments)
        ratio = omega[index] / omega[index + 1]
    minus, plus = joints[index, 0], joints[index, 1]
    keep = np.abs(minus) > 1e-9 * np.abs(minus).max(initial=0)
    np.testing.assert_allclose(plus[keep], ratio[keep] * minus[keep], rtol=1e-7)


@SETTINGS
@given(basis_problems(), st.integers(0, 2**32 - 1))
def test_affine_invariance(problem, seed):
    points, kwargs = problem
    reference = basis_spline(points, **kwargs)
    rng = np.random.default_rng(seed)
    matrix = rng.normal(size=(2, 2))
    assume(abs(np.linalg.det(matrix)) > 0.1)
    offset = rng.normal(size=2) * 100
    explicit = dict(kwargs)
    if isinstance(kwargs["knots"], str) and kwargs["knots"] != "uniform":
        explicit["knots"] = _uniform_or_named(reference, kwargs, points)
    image = basis_spline(points @ matrix.T + offset, **explicit)
    expected = reference.transformed(matrix, offset)
    np.testing.assert_allclose(image.bezier(), expected.bezier(), atol=1e-8 * np.abs(expected.bezier()).max())


@SETTINGS
@given(basis_problems(), st.integers(-1000, 1000))
def test_weights_and_tensions_scaled_together_leave_the_curve_unchanged(problem, power):
    """The joint condition of §2.2 is homogeneous in (omega, v) (v has the units of omega / h, §2.5 Units):
    multiplying every weight and every absolute tension by one 2^k, at any k float64 holds, gives the same
    curve. Before the fix a constant weight beyond about 1e155 (or below 1e-155) failed, as an overflow or as
    a 'degenerate' D_i blamed on point tensions that were zero."""
    points, kwargs = problem
    legs = points.shape[0] if kwargs["closed"] else points.shape[0] - 1
    weights = np.broadcast_to(kwargs.get("interval_weights", 1.0), (legs,))
    tension = np.broadcast_to(kwargs.get("point_tension", 0.0), (points.shape[0],))
    reference = basis_spline(points, **kwargs)
    scaled = basis_spline(points, **dict(kwargs, interval_weights=np.ldexp(weights, power),
                                         point_tension=np.ldexp(tension, power)))
    np.testing.assert_allclose(scaled.bezier(), reference.bezier(), rtol=0,
                               atol=1e-12 * np.abs(reference.bezier()).max())
    np.testing.assert_allclose(scaled.auxiliary["tangents"], reference.auxiliary["tangents"], rtol=0,
                               atol=1e-12 * np.abs(reference.auxiliary["tangents"]).max())


def test_constant_extreme_weight_gives_the_weight_one_curve():
    points = np.array([[0, 0], [1, 2], [3, 1], [4, 3], [6, 0], [7, 2.0]])
    reference = basis_spline(points, knots="chord")
    for weight in (1e160, 1e200, 1e300, 1e-160, 1e-300):
        curve = basis_spline(points, knots="chord", interval_weights=weight)
        np.testing.assert_allclose(curve.bezier(), reference.bezier(), rtol=0, atol=1e-13)


@SETTINGS
@given(basis_problems(knots="uniform"))
def test_reversal_symmetry(problem):
    points, kwargs = problem
    n_control = points.shape[0]
    spline = basis_spline(points, **kwargs)
    v = np.broadcast_to(kwargs.get("point_tension", 0.0), (n_control,))
    legs = n_control if kwargs["closed"] else n_control - 1
    omega = np.broadcast_to(kwargs.get("interval_weights", 1.0), (legs,))
    order = np.roll(np.arange(n_control)[::-1], 1) if kwargs["closed"] else np.arange(n_control)[::-1]
    back = basis_spline(points[order], **dict(kwargs, point_tension=v[order], interval_weights=omega[::-1]))
    expected = spline.reversed()
    np.testing.assert_allclose(back.knots, expected.knots, atol=1e-12)
    np.testing.assert_allclose(back.bezier(), expected.bezier(), atol=1e-9 * 100)
    # the reversed curve's auxiliary arrays are those of the curve built backwards (a loop's control points
    # rotated too, so that piece i still lies over the leg P_i P_{i+1})
    for key in ("control_points", "F", "tangents", "V", "W"):
        np.testing.assert_allclose(back.auxiliary[key], expected.auxiliary[key], atol=1e-9 * 100, err_msg=key)


def test_inner_bezier_points_lie_on_the_legs():
    rng = np.random.default_rng(2)
    points = rng.normal(size=(9, 2)) * 10
    spline = basis_spline(points, point_tension=rng.uniform(0, 3, 9), interval_weights=rng.uniform(0.5, 2, 8),
                          knots="chord")
    b = spline.bezier()
    leg_start, leg_end = points[1:-2], points[2:-1]
    for inner in (b[:, 1], b[:, 2]):
        cross = (leg_end - leg_start)[:, 0] * (inner - leg_start)[:, 1] - (leg_end - leg_start)[:, 1] * (inner - leg_start)[:, 0]
        np.testing.assert_allclose(cross, 0.0, atol=1e-9 * 100)
    # F_i = (h_i b2^(i-1) + h_{i-1} b1^(i)) / (h_{i-1} + h_i)  (§4.3)
    h = np.diff(spline.knots)
    F = (h[1:, None] * b[:-1, 2] + h[:-1, None] * b[1:, 1]) / (h[:-1] + h[1:])[:, None]
    np.testing.assert_allclose(F, spline.knot_points[1:-1], atol=1e-9 * 10)


def test_class_parameters_cancel():
    rng = np.random.default_rng(4)
    points = rng.normal(size=(7, 2))
    reference = basis_spline(points)
    for alpha, beta in ((2.0, 2.0), (4.0, 4.0), (1.5, 7.0)):
        spline = basis_spline(points, alpha=alpha, beta=beta)
        np.testing.assert_array_equal(spline.bezier(), reference.bezier())
        h = np.diff(spline.knots)[:, None]
        M = spline.auxiliary["tangents"]
        np.testing.assert_allclose(spline.auxiliary["V"], spline.knot_points[:-1] + h * M[:-1] / alpha)
        np.testing.assert_allclose(spline.auxiliary["W"], spline.knot_points[1:] - h * M[1:] / beta)


# ---------------------------------------------------------------- limits and the spec's parameter domain
def test_limits_of_tension_and_weight():
    rng = np.random.default_rng(8)
    points = rng.normal(size=(8, 2)) * 10
    v = np.zeros(8)
    v[4] = 1e10
    spline = basis_spline(points, point_tension=v)
    F, M = spline.auxiliary["F"], spline.auxiliary["tangents"]
    np.testing.assert_allclose(F[3], points[4], atol=1e-6)  # joint index 3 <-> thesis i = 4
    assert np.linalg.norm(M[3]) < 1e-6
    omega = np.ones(7)
    omega[3] = 1e10
    straight = basis_spline(points, interval_weights=omega)
    b = straight.bezier()[2]  # thesis segment 3 on leg P_3 P_4
    leg = points[4] - points[3]
    cross = leg[0] * (b - points[3])[:, 1] - leg[1] * (b - points[3])[:, 0]
    np.testing.assert_allclose(cross, 0.0, atol=1e-6)


def test_spec_nonnegativity_domain_for_constant_tension():
    """§4.5: with h = omega = 1 and constant v, B >= 0 for v > -8 (v = -4 removable), min B = -1 at v = -10."""
    t = np.linspace(1, 10, 3001)
    for v in (-3.0, -6.0, -7.9):
        assert basis_functions(t, 12, point_tension=v).min() >= -1e-12
    assert basis_functions(t, 12, point_tension=-8.2).min() < -1e-3
    np.testing.assert_allclose(basis_functions(t, 12, point_tension=-10.0).min(), -1.0, atol=1e-9)
    with pytest.raises(ValueError, match=r"degenerate at knot 1: D_1"):
        basis_functions(t, 12, point_tension=-4.0)


def test_huge_positive_tension_reports_an_overflow_not_a_vanishing_d():
    """Two neighbouring tensions beyond about 2.7e154 overflow D_i (~ v**2 / 4): the message says so instead of
    calling D_i vanishing and advising v > -2(...), which such a v already satisfies."""
    points = np.array([[0, 0], [1, 2], [3, 1], [4, 4], [6, 0], [7, 3.0]])
    curve = basis_spline(points, point_tension=1e150)  # still finite: the cusp limit F_j -> P_j (§4.5)
    np.testing.assert_allclose(curve.auxiliary["F"], points[1:-1], atol=1e-12)
    for tension in (1e155, 1e300):
        with pytest.raises(ValueError, match="overflows float64") as caught:
            basis_spline(points, point_tension=tension)
        assert "vanishes" not in str(caught.value)
    single = np.zeros(len(points))
    single[2] = 1e300
    assert np.isfinite(basis_spline(points, point_tension=single).bezier()).all()


def test_closed_three_points_and_basis_functions_variants():
    points = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 2.0]])
    loop = basis_spline(points, closed=True, point_tension=[0.5, 0.0, 2.0], interval_weights=[1.0, 2.0, 0.5])
    assert loop.n_segments == 3 and loop.closed
    values = basis_functions(np.linspace(0, 3, 31), 3, closed=True).toarray()
    np.testing.assert_allclose(values.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(values[0], [4 / 6, 1 / 6, 1 / 6])
    clamped = basis_functions(np.linspace(0, 5, 21), np.arange(6.0), ends="clamped").toarray()
    assert clamped.shape == (21, 8)
    np.testing.assert_allclose(clamped[0], np.eye(8)[0])
    np.testing.assert_allclose(clamped[-1], np.eye(8)[-1])
    one_piece = basis_spline(np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]]), ends="clamped")
    np.testing.assert_allclose(one_piece.bezier()[0], [[0, 0], [1, 2], [3, 2], [4, 0]])


def test_coincident_control_points_allowed_with_uniform_knots():
    points = np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [1.0, 1.0], [2.0, 0.0], [3.0, 1.0]])
    spline = basis_spline(points)  # a triple control point: the curve passes through it
    np.testing.assert_allclose(spline.knot_points[1], [1.0, 1.0])
    with pytest.raises(ValueError, match=r"control_points\[1\] and control_points\[2\] coincide"):
        basis_spline(points, knots="chord")


@pytest.mark.parametrize(
    "kwargs, error, pattern",
    [
        (dict(control_points=np.zeros((3, 2)) + np.arange(3)[:, None]), ValueError, "at least 4 points"),
        (dict(control_points=np.arange(4.0)[:, None] * [1, 0], closed=True, ends="clamped"), ValueError, "open curves only"),
        (dict(control_points=[[0, 0], [1, 0], [2, np.nan], [3, 0]]), ValueError, r"control_points\[2, 1\] is nan"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), interval_weights=[1, 1, 0, 1]), ValueError, r"interval_weights\[2\] = 0.0"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), interval_weights=[1, 1, 1]), ValueError, "interval_weights has length 3 but 4"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), point_tension=[1, 1]), ValueError, "point_tension has length 2 but 5"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), knots=[0, 1, 2, 2, 3]), ValueError, r"knots\[3\] = 2.0 <= knots\[2\]"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), knots=[0, 1, 2]), ValueError, "knots has length 3 but needs one per control point"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), ends="clamped", knots=[0, 1, 2, 3, 4]), ValueError, "n_control - 2 = 3"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), alpha=[1.0, 0.0]), ValueError, r"alpha\[1\] = 0"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), ends="loose"), ValueError, "ends must be one of"),
        (dict(control_points=np.arange(10.0).reshape(5, 2), knots="arc"), ValueError, "knots must be one of"),
        (dict(control_points="points"), TypeError, "control_points must be numeric"),
    ],
)
def test_bad_input(kwargs, error, pattern):
    kwargs = dict(kwargs)
    points = kwargs.pop("control_points")
    with pytest.raises(error, match=pattern):
        basis_spline(points, **kwargs)


def test_basis_functions_bad_input():
    with pytest.raises(ValueError, match="at least 4 control points"):
        basis_functions([1.0], 3)
    with pytest.raises(ValueError, match="outside"):
        basis_functions([0.0], 6)  # the floating curve runs over [t_1, t_n] = [1, 4]


def test_basis_functions_outside_the_domain_advises_no_missing_argument():
    """The message named ``extrapolate=True``, an argument of ``Spline.__call__`` that basis_functions does not
    take (passing it is a TypeError): it names ``t`` and the domain only."""
    with pytest.raises(ValueError, match=r"t\[1\] = 9\.0 is outside the curve's domain \[1\.0, 4\.0\]") as info:
        basis_functions([2.0, 9.0], 6)
    assert "extrapolate" not in str(info.value)
    with pytest.raises(TypeError):
        basis_functions([2.0, 9.0], 6, extrapolate=True)


def test_clamped_end_tensions_have_no_effect():
    """§4.4: with clamped ends only v_2..v_{n-1} act; v_0, v_1, v_n, v_{n+1} have no effect."""
    rng = np.random.default_rng(12)
    points = rng.normal(size=(8, 2)) * 20
    v = rng.uniform(0, 3, 8)
    omega = rng.uniform(0.5, 2, 7)
    reference = basis_spline(points, ends="clamped", point_tension=v, interval_weights=omega)
    changed = v.copy()
    changed[[0, 1, 6, 7]] = rng.uniform(5, 50, 4)
    other_weights = omega.copy()
    other_weights[[0, 6]] = [9.0, 0.1]  # the end legs carry no interval
    again = basis_spline(points, ends="clamped", point_tension=changed, interval_weights=other_weights)
    np.testing.assert_allclose(again.bezier(), reference.bezier(), rtol=1e-12, atol=1e-12)
    inner = v.copy()
    inner[3] += 1.0
    assert np.abs(basis_spline(points, ends="clamped", point_tension=inner, interval_weights=omega).bezier()
                  - reference.bezier()).max() > 1e-3


@settings(max_examples=30, deadline=None)
@given(st.integers(3, 11), st.sampled_from(["floating", "clamped", "closed"]), st.integers(0, 2**32 - 1))
def test_sparse_basis_functions_equal_the_identity_curve(n_control, ends, seed):
    """Four non-zero entries per row, equal to the dense evaluation of the curve with identity control points."""
    rng = np.random.default_rng(seed)
    closed = ends == "closed"
    if not closed and n_control < 4:
        n_control = 4
    tension = rng.uniform(0.0, 5.0, n_control)
    weights = rng.uniform(0.5, 2.0, n_control if closed else n_control - 1)
    ends = "floating" if closed else ends
    dense_curve = basis_spline(np.eye(n_control), closed=closed, ends=ends, point_tension=tension,
                               interval_weights=weights)
    t0, t1 = dense_curve.domain
    t = np.linspace(t0, t1, 97)
    sparse = basis_functions(t, n_control, closed=closed, ends=ends, point_tension=tension,
                             interval_weights=weights)
    assert sparse.shape == (97, n_control) and sparse.nnz <= 4 * 97
    np.testing.assert_allclose(sparse.toarray(), dense_curve(t), atol=1e-13)
    np.testing.assert_allclose(np.asarray(sparse.sum(axis=1)).ravel(), 1.0, atol=1e-12)


def test_basis_functions_of_many_control_points_stay_small():
    t = np.linspace(1.0, 9_998.0, 5_000)
    values = basis_functions(t, 10_000)
    assert values.shape == (5_000, 10_000) and values.nnz <= 4 * 5_000
    assert values.data.nbytes + values.indices.nbytes + values.indptr.nbytes < 1_000_000
