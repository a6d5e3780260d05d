"""Timmer class (§5, thesis section 3.3): blending functions, one piece, Algorithms 3.1, 3.2 and 3.3."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.interpolate import BPoly, CubicSpline

from splinecraft.spline.piecewise import Spline
from splinecraft.spline.tangents import estimate_tangents
from splinecraft.spline.timmer import (
    timmer_bezier,
    timmer_blending_functions,
    timmer_end_curvatures,
    timmer_g2,
    timmer_gc1,
    timmer_gc2,
)

SETTINGS = settings(max_examples=50, deadline=None)
GOLDEN = (3.0 + np.sqrt(5.0)) / 2.0


def cross(u, w):
    return u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def jumps(spline):
    kappa = spline.joint_curvature()
    return kappa[:, 1] - kappa[:, 0], np.maximum(np.abs(kappa[:, 0]), np.abs(kappa[:, 1]))


# ---------------------------------------------------------------------------------------------- test data
@st.composite
def ellipse_samples(draw, closed=False, min_count=5, max_count=24):
    """Points on an ellipse at random, well separated angles (an arc when open)."""
    count = draw(st.integers(min_count, max_count))
    a, b = draw(st.floats(0.5, 5.0)), draw(st.floats(0.5, 5.0))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    span = 2 * np.pi if closed else draw(st.floats(0.5, 1.8)) * np.pi
    gaps = rng.uniform(0.5, 1.5, count if closed else count - 1)
    angles = np.concatenate([[0.0], np.cumsum(gaps)]) / gaps.sum() * span
    angles = angles[:-1] if closed else angles
    angles = angles + rng.uniform(0, 2 * np.pi)
    center = rng.normal(size=2) * 3
    return center + np.c_[a * np.cos(angles), b * np.sin(angles)]


@st.composite
def smooth_curves(draw, min_count=5, max_count=20):
    """Samples of a random smooth closed curve r(phi) = 1 + sum of small harmonics (star-shaped)."""
    count = draw(st.integers(min_count, max_count))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    phi = np.sort(rng.uniform(0, 2 * np.pi, count))
    assume(np.min(np.diff(np.concatenate([phi, [phi[0] + 2 * np.pi]]))) > 0.3 / count)
    radius = 1.0 + sum(rng.uniform(-0.15, 0.15) * np.cos(k * phi + rng.uniform(0, 6)) for k in range(1, 4))
    return np.c_[radius * np.cos(phi), radius * np.sin(phi)] * draw(st.floats(0.1, 100.0))


@st.composite
def random_polylines(draw, min_count=3, max_count=10, closed=False):
    count = draw(st.integers(min_count, max_count))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    steps = rng.normal(size=(count, 2))
    steps[:, 0] += 1.5                             # a forward drift keeps the polyline tame
    points = np.cumsum(steps, axis=0)
    if closed:
        angle = np.sort(rng.uniform(0, 2 * np.pi, count))
        points = np.c_[np.cos(angle), np.sin(angle)] * rng.uniform(1, 3, (count, 1))
    chords = np.linalg.norm(np.diff(np.vstack([points, points[:1]]) if closed else points, axis=0), axis=1)
    assume(chords.min() > 0.05 * chords.max())
    return points


# ---------------------------------------------------------------------------------------------- §5.1
def test_blending_functions_values_and_minima():
    f = timmer_blending_functions([0.0, 0.5, 1.0])
    np.testing.assert_allclose(f, [[1, 0, 0, 0], [0, 0.5, 0.5, 0], [0, 0, 0, 1]], atol=1e-15)   # E15
    theta = np.linspace(0, 1, 30001)
    values = timmer_blending_functions(theta)
    assert values[:, 0].min() == pytest.approx(-1 / 27, abs=1e-9)
    assert theta[np.argmin(values[:, 0])] == pytest.approx(2 / 3, abs=1e-4)
    assert values[:, 3].min() == pytest.approx(-1 / 27, abs=1e-9)
    assert theta[np.argmin(values[:, 3])] == pytest.approx(1 / 3, abs=1e-4)
    assert values[:, 1:3].min() >= 0.0


@SETTINGS
@given(st.lists(st.floats(-0.5, 1.5), min_size=1, max_size=20))
def test_blending_functions_partition_symmetry_and_bernstein_form(theta):
    theta = np.array(theta)
    f = timmer_blending_functions(theta)
    np.testing.assert_allclose(f.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(timmer_blending_functions(1 - theta), f[:, ::-1], atol=1e-12)
    # independent reference: f0 = B0 - B1/3, f1 = 4/3 B1, f2 = 4/3 B2, f3 = B3 - B2/3 (scipy BPoly)
    bernstein = np.array([[1, -1 / 3, 0, 0], [0, 4 / 3, 0, 0], [0, 0, 4 / 3, 0], [0, 0, -1 / 3, 1]])
    for k in range(4):
        reference = BPoly(bernstein[k][:, None], [0.0, 1.0], extrapolate=True)(theta)
        np.testing.assert_allclose(f[:, k], reference, atol=1e-12)


@st.composite
def timmer_pieces(draw):
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    points = rng.normal(size=(2, 2)) * 3
    assume(np.linalg.norm(points[1] - points[0]) > 0.1)
    tangents = rng.normal(size=(2, 2))
    assume(np.linalg.norm(tangents, axis=1).min() > 0.1)
    alpha, beta = draw(st.floats(0.2, 10.0)), draw(st.floats(0.2, 10.0))
    return points, tangents, alpha, beta


@SETTINGS
@given(timmer_pieces(), st.lists(st.floats(0.0, 1.0), min_size=1, max_size=10))
def test_f_form_equals_bezier_form(piece, theta):
    """H = f0 P_i + f1 Q1 + f2 Q2 + f3 P_{i+1} (3.89 with E14) equals the Bézier form b1, b2 of §5.1."""
    points, tangents, alpha, beta = piece
    bezier, q1, q2 = timmer_bezier(points, tangents, alpha, beta)
    np.testing.assert_allclose(q1[0], points[0] + tangents[0] / alpha)
    np.testing.assert_allclose(q2[0], points[1] - tangents[1] / beta)        # E14: minus sign
    theta = np.array(theta)
    f = timmer_blending_functions(theta)
    f_form = f @ np.array([points[0], q1[0], q2[0], points[1]])
    spline = Spline(bezier, [0.0, 1.0])
    np.testing.assert_allclose(spline(theta), f_form, atol=1e-12 * (1 + np.abs(f_form).max()))
    np.testing.assert_allclose(BPoly(bezier[0][:, None, :], [0.0, 1.0])(theta), f_form, atol=1e-10)


@SETTINGS
@given(timmer_pieces(), st.floats(0.05, 0.95))
def test_derivatives_match_spec_5_2(piece, theta):
    """H', H'' of §5.2 (general theta and the end values; E19) vs the Bézier derivatives and finite
    differences."""
    points, tangents, alpha, beta = piece
    bezier, _, _ = timmer_bezier(points, tangents, alpha, beta)
    spline = Spline(bezier, [0.0, 1.0])
    chord = points[1] - points[0]
    t_i, t_j = tangents

    def first(t):
        return 6 * t * (1 - t) * chord + 4 / alpha * (1 - 4 * t + 3 * t**2) * t_i + 4 / beta * (3 * t**2 - 2 * t) * t_j

    def second(t):
        return 6 * (1 - 2 * t) * chord + 8 / alpha * (3 * t - 2) * t_i + 8 / beta * (3 * t - 1) * t_j

    scale = 1 + np.abs(bezier).max() * 10
    np.testing.assert_allclose(spline.derivative(theta, 1), first(theta), atol=1e-10 * scale)
    np.testing.assert_allclose(spline.derivative(theta, 2), second(theta), atol=1e-10 * scale)
    np.testing.assert_allclose(first(0.0), 4 * t_i / alpha, atol=1e-12 * scale)
    np.testing.assert_allclose(first(1.0), 4 * t_j / beta, atol=1e-12 * scale)
    np.testing.assert_allclose(spline.derivative(0.0, 2), 6 * chord - 16 * t_i / alpha - 8 * t_j / beta,
                               atol=1e-10 * scale)
    np.testing.assert_allclose(spline.derivative(1.0, 2), -6 * chord + 8 * t_i / alpha + 16 * t_j / beta,
                               atol=1e-10 * scale)
    step = 1e-4
    values = spline(np.array([theta - step, theta, theta + step]))
    np.testing.assert_allclose((values[2] - values[0]) / (2 * step), first(theta), atol=1e-6 * scale)
    np.testing.assert_allclose((values[2] - 2 * values[1] + values[0]) / step**2, second(theta),
                               atol=1e-4 * scale)


@SETTINGS
@given(timmer_pieces())
def test_end_curvatures_match_spec_5_3(piece):
    """kappa(0), kappa(1) of §5.3 (unit tangents, alpha != beta) vs the Bézier curvature and a finite
    difference curvature."""
    points, tangents, alpha, beta = piece
    start, end = timmer_end_curvatures(points, tangents, alpha, beta)
    bezier, _, _ = timmer_bezier(points, unit(tangents), alpha, beta)
    spline = Spline(bezier, [0.0, 1.0])
    kappa = spline.joint_curvature()
    scale = 1 + abs(kappa[0, 1]) + abs(kappa[1, 0])
    assert start[0] == pytest.approx(kappa[0, 1], abs=1e-10 * scale)
    assert end[0] == pytest.approx(kappa[1, 0], abs=1e-10 * scale)
    # finite differences on the polynomial extended past the end (extrapolate)
    step = 1e-4
    for t, expected in ((0.0, start[0]), (1.0, end[0])):
        values = spline(np.array([t - step, t, t + step]), extrapolate=True)
        d1 = (values[2] - values[0]) / (2 * step)
        d2 = (values[2] - 2 * values[1] + values[0]) / step**2
        finite = cross(d1, d2) / np.linalg.norm(d1) ** 3
        assert finite == pytest.approx(expected, abs=1e-4 * scale)
    # beta == alpha: thesis eqs 3.117 / 3.118 written with M, N components
    (m_i, n_i), (m_j, n_j) = unit(tangents)
    (x_i, y_i), (x_j, y_j) = points
    start, end = timmer_end_curvatures(points, tangents, alpha, alpha)
    eq_3_117 = alpha / 8 * (4 * m_j * n_i - 4 * m_i * n_j + 3 * (n_i * (x_i - x_j) + m_i * (y_j - y_i)) * alpha)
    eq_3_118 = alpha / 8 * (n_j * (3 * alpha * (x_j - x_i) - 4 * m_i) + m_j * (4 * n_i + 3 * (y_i - y_j) * alpha))
    assert start[0] == pytest.approx(eq_3_117, abs=1e-12 * (1 + abs(eq_3_117)))
    assert end[0] == pytest.approx(eq_3_118, abs=1e-12 * (1 + abs(eq_3_118)))


# ---------------------------------------------------------------------------------------------- Alg 3.1
def _check_g2_result(spline, points, closed):
    """Common checks of an Algorithm 3.1 result: per-knot report, G2 at root joints, honest jumps,
    fallback joints have no positive root and use the vertex / alpha_ref."""
    info = spline.info
    m = spline.n_segments
    assert m == (len(points) if closed else len(points) - 1)
    np.testing.assert_array_equal(spline.knots, np.arange(m + 1))
    assert len(info["joint_status"]) == len(info["curvature_jump"]) == m + 1
    jump, size = jumps(spline)
    chords = np.linalg.norm(np.diff(np.vstack([points, points[:1]]) if closed else points, axis=0), axis=1)
    curvature_scale = np.maximum(size, 1 / chords.mean())
    tangents = spline.auxiliary["tangents"]
    np.testing.assert_allclose(np.linalg.norm(tangents, axis=1), 1.0)
    alpha = np.array(info["alpha"])
    np.testing.assert_allclose(alpha, info["beta"])
    kappa = spline.joint_curvature()
    count = len(points)
    for k, status in enumerate(info["joint_status"]):
        if not closed and k in (0, m):
            assert status == "end" and info["curvature_jump"][k] is None
            continue
        assert info["curvature_jump"][k] == pytest.approx(jump[k], abs=1e-12 * curvature_scale[k])
        if status == "g2":
            # kappa_i(0) = 3/8 alpha^2 S - alpha/2 C: rounding is relative to the size of these terms,
            # which can cancel when the root alpha is large
            i = k % m
            chord = points[(i + 1) % count] - points[i]
            terms = (3 / 8 * alpha[i] ** 2 * abs(cross(tangents[i], chord))
                     + alpha[i] / 2 * abs(cross(tangents[i], tangents[(i + 1) % count])))
            assert abs(jump[k]) <= 1e-9 * max(curvature_scale[k], terms)
        elif status == "g1_no_root":
            i = k % m
            chord = points[(i + 1) % count] - points[i]
            s_term, c_term = cross(tangents[i], chord), cross(tangents[i], tangents[(i + 1) % count])
            target = kappa[k, 0]
            disc = c_term**2 + 6 * s_term * target
            if abs(disc) > 1e-8 * (c_term**2 + abs(6 * s_term * target)):
                roots = np.roots([3 / 8 * s_term, -c_term / 2, -target])
                real = roots[np.abs(roots.imag) <= 1e-12 * np.abs(roots)].real
                assert not np.any(real > 0), (k, roots)
            vertex = 2 * c_term / (3 * s_term) if s_term != 0 else -1
            reference = 4 / np.linalg.norm(chord)
            expected = np.clip(vertex if vertex > 0 else reference, reference / 16, reference * 16)
            assert alpha[i] == pytest.approx(expected, rel=1e-12)
        else:
            assert status in ("g1_degenerate", "g1_closing")


@SETTINGS
@given(ellipse_samples())
def test_alg_3_1_open_ellipse_arcs(points):
    spline = timmer_g2(points)
    _check_g2_result(spline, points, closed=False)
    assert spline.info["alpha0"] == pytest.approx(4 / np.linalg.norm(points[1] - points[0]))


@SETTINGS
@given(st.one_of(ellipse_samples(closed=True), smooth_curves()))
def test_alg_3_1_closed_curves(points):
    spline = timmer_g2(points, closed=True)
    assert spline.closed
    _check_g2_result(spline, points, closed=True)
    status = spline.info["joint_status"]
    assert status[0] == status[-1]
    assert (status[0] == "g2") == spline.info["closing_converged"]


@SETTINGS
@given(random_polylines(min_count=4))
def test_alg_3_1_random_polylines_with_given_alpha0(points):
    spline = timmer_g2(points, alpha0=2.5)
    _check_g2_result(spline, points, closed=False)
    assert spline.info["alpha"][0] == 2.5


@pytest.mark.parametrize("count", [3, 7, 16])
def test_alg_3_1_uniform_circle_closes_g2(count):
    """Uniform circle samples: by symmetry one alpha fits every joint, the closing one included."""
    angle = 2 * np.pi * np.arange(count) / count
    points = 2.0 * np.c_[np.cos(angle), np.sin(angle)]
    spline = timmer_g2(points, closed=True)
    assert spline.info["closing_converged"]
    assert set(spline.info["joint_status"]) == {"g2"}
    jump, _ = jumps(spline)
    assert np.abs(jump).max() < 1e-9
    np.testing.assert_allclose(spline.info["alpha"], spline.info["alpha"][0], rtol=1e-9)
    # the curve hugs the circle (radius 2) between the samples; 3 points is a very coarse triangle
    radius = np.linalg.norm(spline(np.linspace(0, count, 400, endpoint=False)), axis=1)
    assert np.abs(radius - 2).max() < (0.6 if count == 3 else 0.02)


@pytest.mark.parametrize("seed", [0, 2, 5])
def test_alg_3_1_closed_search_closes_uneven_ellipse_samples(seed):
    """Uneven samples (no symmetry): the alpha_0 search finds a value that makes the closing joint G2."""
    rng = np.random.default_rng(seed)
    angle = np.cumsum(rng.uniform(0.5, 1.5, 12))
    angle = angle / angle[-1] * 2 * np.pi
    points = np.c_[3 * np.cos(angle), np.sin(angle)]
    spline = timmer_g2(points, closed=True)
    assert spline.info["closing_converged"]
    assert spline.info["joint_status"][0] == spline.info["joint_status"][-1] == "g2"
    jump, size = jumps(spline)
    assert abs(jump[0]) <= 1e-11 * max(size[0], 1.0)
    # the default alpha_ref,0 would not close it
    default = timmer_g2(points, closed=True, alpha0=4 / np.linalg.norm(points[1] - points[0]))
    assert default.info["joint_status"][0] == "g1_closing"
    assert abs(default.info["curvature_jump"][0]) > 1e-3


def test_alg_3_1_batched_and_scalar_sweeps_agree():
    """The closed search runs the recurrence for many alpha_0 at once; it must match the scalar path."""
    from splinecraft.spline import timmer as module

    rng = np.random.default_rng(11)
    for _ in range(20):
        points = np.cumsum(rng.normal(size=(9, 2)) + [1.0, 0.0], axis=0)
        tangents = unit(rng.normal(size=(9, 2)) + [2.0, 0.0])
        chords = np.linalg.norm(np.diff(points, axis=0), axis=1)
        s_term = cross(tangents[:-1], np.diff(points, axis=0))
        u_term = cross(tangents[1:], np.diff(points, axis=0))
        c_term = cross(tangents[:-1], tangents[1:])
        starts = 4 / chords[0] * np.geomspace(0.1, 10, 17)
        batch_alpha, batch_code = module._g2_sweep(starts, s_term, u_term, c_term, 4 / chords, chords, 16.0)
        for row, start in enumerate(starts):
            alpha, code = module._g2_sweep([start], s_term, u_term, c_term, 4 / chords, chords, 16.0)
            np.testing.assert_array_equal(code[0], batch_code[row])
            np.testing.assert_allclose(alpha[0], batch_alpha[row], rtol=1e-9)


def test_alg_3_1_printed_e18_discriminant_fails_where_corrected_passes():
    """E18: 3.122 prints sqrt(C^2 - 6 S K*). The corrected roots 2[C ± sqrt(C^2 + 6 S K*)]/(3S) give a
    piece whose measured start curvature is K*; the printed ones do not."""
    rng = np.random.default_rng(7)
    corrected_ok = printed_ok = trials = 0
    for _ in range(1500):
        points = rng.normal(size=(2, 2)) * rng.uniform(0.1, 10)
        tangents = unit(rng.normal(size=(2, 2)))
        target = rng.normal() / np.linalg.norm(points[1] - points[0])
        s_term = cross(tangents[0], points[1] - points[0])
        c_term = cross(tangents[0], tangents[1])
        good, bad = c_term**2 + 6 * s_term * target, c_term**2 - 6 * s_term * target
        if good < 0 or bad < 0 or abs(s_term * target) < 1e-3:
            continue
        trials += 1
        for disc, counter in ((good, "corrected"), (bad, "printed")):
            roots = [2 * (c_term + sign * np.sqrt(disc)) / (3 * s_term) for sign in (1, -1)]
            matched = []
            for alpha in roots:
                if alpha <= 0:
                    continue
                bezier, _, _ = timmer_bezier(points, tangents, alpha, alpha)
                measured = Spline(bezier, [0.0, 1.0]).joint_curvature()[0, 1]
                matched.append(abs(measured - target) <= 1e-8 * (1 + abs(target)))
            if matched and all(matched):
                if counter == "corrected":
                    corrected_ok += 1
                else:
                    printed_ok += 1
            elif counter == "corrected":
                assert not matched, "a corrected positive root failed to match the target curvature"
    assert trials > 100
    assert printed_ok == 0
    assert corrected_ok > 0.3 * trials


def test_alg_3_1_linear_and_degenerate_cases():
    # S_1 = 0 (T_1 along the chord P1P2) but C_1 != 0: linear equation alpha = -2 K* / C
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 1.0]])
    tangents = np.array([[1.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    spline = timmer_g2(points, tangents=tangents, alpha0=4.0)
    t = unit(tangents)
    target = -3 / 8 * 16 * cross(t[1], points[1] - points[0]) - 4 / 2 * cross(t[0], t[1])
    expected = -2 * target / cross(t[1], t[2])
    assert expected > 0
    assert spline.info["joint_status"][1] == "g2"
    assert spline.info["alpha"][1] == pytest.approx(expected)
    assert abs(jumps(spline)[0][1]) < 1e-12
    # S_1 = C_1 = 0 (straight second piece, aligned tangents) after a curved piece: kappa_1(0) = 0
    # for every alpha, the target is not 0 -> G1 with the full jump
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    tangents = np.array([[0.0, 1.0], [1.0, 0.0], [1.0, 0.0]])
    spline = timmer_g2(points, tangents=tangents)
    assert spline.info["joint_status"][1] == "g1_degenerate"
    kappa = spline.joint_curvature()
    assert kappa[1, 1] == 0.0 and kappa[1, 0] != 0.0
    assert spline.info["alpha"][1] == pytest.approx(4.0)
    # all collinear: every joint trivially G2 with alpha_ref, the curve is the straight line
    points = np.c_[np.array([0.0, 1.0, 3.0, 4.0]), np.zeros(4)]
    spline = timmer_g2(points)
    assert spline.info["joint_status"] == ["end", "g2", "g2", "end"]
    np.testing.assert_allclose(spline.info["alpha"], 4 / np.diff(points[:, 0]))
    np.testing.assert_allclose(spline(np.linspace(0, 3, 50))[:, 1], 0.0)


def test_alg_3_1_root_choice_closest_to_reference():
    """Two positive roots: the one nearer alpha_ref in |log| is used, and it is G2."""
    rng = np.random.default_rng(3)
    seen_two = 0
    for _ in range(1000):
        points = np.cumsum(rng.normal(size=(3, 2)) + [1.5, 0], axis=0)
        spline = timmer_g2(points, alpha0=rng.uniform(1, 8))
        if spline.info["joint_status"][1] != "g2":
            continue
        t = spline.auxiliary["tangents"]
        chord = points[2] - points[1]
        s_term, c_term = cross(t[1], chord), cross(t[1], t[2])
        a0 = spline.info["alpha"][0]
        target = -3 / 8 * a0**2 * cross(t[1], points[1] - points[0]) - a0 / 2 * cross(t[0], t[1])
        roots = np.roots([3 / 8 * s_term, -c_term / 2, -target])
        positive = roots[(np.abs(roots.imag) < 1e-12) & (roots.real > 0)].real
        if len(positive) == 2:
            seen_two += 1
            reference = 4 / np.linalg.norm(chord)
            best = positive[np.argmin(np.abs(np.log(positive / reference)))]
            assert spline.info["alpha"][1] == pytest.approx(best, rel=1e-9)
    assert seen_two >= 10


@SETTINGS
@given(random_polylines(min_count=4), st.floats(0.1, 10.0), st.floats(-np.pi, np.pi))
def test_alg_3_1_similarity_invariant(points, scale, angle):
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    offset = np.array([3.0, -2.0])
    moved = timmer_g2(scale * points @ rotation.T + offset)
    expected = timmer_g2(points).transformed(scale * rotation, offset)
    np.testing.assert_allclose(moved.bezier(), expected.bezier(), atol=1e-8 * scale * (1 + np.abs(points).max()))
    assert moved.info["joint_status"] == expected.info["joint_status"]


@pytest.mark.parametrize("closed", [False, True])
@pytest.mark.parametrize("clamp", [16.0, 4.0, None])
def test_alg_3_1_wild_scales_reported(closed, clamp):
    """Roots are not clamped, so on noisy samples a chain of G2 joints can drive alpha far from alpha_ref;
    info["wild"] flags exactly the pieces whose handles (from the Bezier points, not from info) are more than R
    times shorter or longer than a third of their chord, and reversal keeps the flags with their pieces."""
    rng = np.random.default_rng(4)
    angle = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    points = 10 * np.c_[np.cos(angle), np.sin(angle)] + rng.normal(scale=0.3, size=(40, 2))
    spline = timmer_g2(points, closed=closed, clamp=clamp)
    bezier = spline.bezier()
    chord = np.linalg.norm(bezier[:, 3] - bezier[:, 0], axis=1)
    handles = np.linalg.norm(bezier[:, 1] - bezier[:, 0], axis=1)
    band = 16.0 if clamp is None else clamp
    ratio = chord / (3 * handles)
    np.testing.assert_allclose(spline.info["alpha_ratio"], ratio, rtol=1e-9)
    assert spline.info["wild"] == ((ratio > band) | (ratio < 1 / band)).tolist()
    wild = np.flatnonzero(spline.info["wild"])
    assert wild.size > 0 and max(ratio) > 100  # the case that went unreported: hundreds of times alpha_ref
    # ... reached through joints that are G2 (a root, not a clamped fallback)
    assert any(spline.info["joint_status"][i] == "g2" for i in wild if i > 0)
    backwards = spline.reversed()
    assert backwards.info["wild"] == spline.info["wild"][::-1]
    # clean samples of an ellipse stay in the band
    clean = timmer_g2(np.c_[3 * np.cos(angle), np.sin(angle)], closed=closed, clamp=clamp)
    assert not any(clean.info["wild"]) and max(clean.info["alpha_ratio"]) < 2


def test_alg_3_1_clamp_none_and_validation():
    points = np.array([[0.0, 0.0], [1.0, 0.2], [2.0, -0.5], [3.0, 1.0], [4.0, 0.0]])
    spline = timmer_g2(points, clamp=None)
    assert len(spline.info["alpha"]) == 4
    with pytest.raises(ValueError, match="clamp"):
        timmer_g2(points, clamp=0.5)
    with pytest.raises(ValueError, match="alpha0"):
        timmer_g2(points, alpha0=-1.0)
    with pytest.raises(ValueError, match="planar"):
        timmer_g2(np.c_[points, points[:, :1]])
    with pytest.raises(ValueError, match=r"tangents\[2\] is the zero vector"):
        timmer_g2(points, tangents=np.array([[1.0, 0], [1, 0], [0, 0], [1, 0], [1, 0]]))
    with pytest.raises(ValueError, match="tangents must have shape"):
        timmer_g2(points, tangents=np.ones((4, 2)))


# ---------------------------------------------------------------------------------------------- Alg 3.2
@SETTINGS
@given(random_polylines(), st.data())
def test_alg_3_2_g1_and_c1_iff_matching_scales(points, data):
    m = len(points) - 1
    alpha = np.array(data.draw(st.lists(st.floats(0.2, 8.0), min_size=m, max_size=m)))
    beta = np.array(data.draw(st.lists(st.floats(0.2, 8.0), min_size=m, max_size=m)))
    matched = np.array(data.draw(st.lists(st.booleans(), min_size=m, max_size=m)))
    for i in range(1, m):
        if matched[i]:
            beta[i - 1] = alpha[i]
        elif abs(beta[i - 1] - alpha[i]) <= 1e-6 * alpha[i]:
            beta[i - 1] = 1.25 * alpha[i]
    spline = timmer_gc1(points, alpha=alpha, beta=beta)
    expected_tangents = unit(estimate_tangents(points))
    for k in range(1, m):
        left = spline.derivative(float(k), 1, side="left")
        right = spline.derivative(float(k), 1, side="right")
        np.testing.assert_allclose(unit(left), unit(right), atol=1e-12)         # G1
        np.testing.assert_allclose(unit(right), expected_tangents[k], atol=1e-12)
        is_c1 = np.linalg.norm(left - right) <= 1e-10 * np.linalg.norm(right)
        assert is_c1 == bool(matched[k])
        assert spline.info["joint_status"][k] == ("c1" if is_c1 else "g1")
    np.testing.assert_allclose(spline.derivative(0.0, 1), 4 * expected_tangents[0] / alpha[0])
    np.testing.assert_allclose(spline.derivative(float(m), 1), 4 * expected_tangents[-1] / beta[-1])


@SETTINGS
@given(random_polylines(closed=True, min_count=3), st.floats(0.1, 2.0))
def test_alg_3_2_shape_scale_and_closed(points, scale):
    """alpha_i = 4 / (s |P_{i+1} - P_i|): the end speed is s times the chord; closed outlines are G1
    at every joint including the closing one."""
    spline = timmer_gc1(points, closed=True, shape_scale=scale)
    chords = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
    m = len(points)
    np.testing.assert_allclose(np.linalg.norm(spline.derivative(np.arange(m) * 1.0, 1), axis=1), scale * chords)
    np.testing.assert_allclose(spline.info["alpha"], 4 / (scale * chords))
    for k in range(m + 1):
        left = spline.derivative(float(k), 1, side="left")
        right = spline.derivative(float(k), 1, side="right")
        np.testing.assert_allclose(unit(left), unit(right), atol=1e-12)
    np.testing.assert_allclose(spline.auxiliary["tangents"], unit(estimate_tangents(points, closed=True)))
    default = timmer_gc1(points, closed=True)
    np.testing.assert_allclose(default.info["shape_scale"], 1.0)


def test_alg_3_2_validation():
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [3.0, 1.0]])
    with pytest.raises(ValueError, match=r"alpha\[1\] must be > 0"):
        timmer_gc1(points, alpha=[1.0, 0.0, 1.0])
    with pytest.raises(ValueError, match=r"beta\[2\] must be > 0"):
        timmer_gc1(points, alpha=1.0, beta=[1.0, 1.0, -2.0])
    with pytest.raises(ValueError, match="alpha must be > 0"):
        timmer_gc1(points, alpha=-1.0)
    with pytest.raises(ValueError, match=r"shape \(3,\)"):
        timmer_gc1(points, alpha=[1.0, 1.0])
    with pytest.raises(ValueError, match="not both"):
        timmer_gc1(points, alpha=1.0, shape_scale=1.0)
    with pytest.raises(ValueError, match=r"alpha\[0\]"):
        timmer_gc1(points, alpha=[np.nan, 1.0, 1.0])
    with pytest.raises(ValueError, match=r"points\[4, 0\]"):
        timmer_gc1(np.vstack([points, [[np.inf, 0.0]]]))


# ---------------------------------------------------------------------------------------------- Alg 3.3
def _joint_second_derivatives(spline):
    m = spline.n_segments
    knots = np.arange(1, m) * 1.0 if not spline.closed else np.arange(m + 1) * 1.0
    return knots, spline.derivative(knots, 2, side="left"), spline.derivative(knots, 2, side="right")


@SETTINGS
@given(random_polylines(min_count=3, max_count=12), st.data())
def test_alg_3_3_thesis_rows_and_e20_ratio(points, data):
    """'thesis' joint: H''_{i-1}(1) = H''_i(0) (eq 3.123), and kappa+ = (alpha_i / beta_{i-1})^2 kappa- (E20)."""
    m = len(points) - 1
    alpha = np.array(data.draw(st.lists(st.floats(1.0, 6.0), min_size=m, max_size=m)))
    beta = np.array(data.draw(st.lists(st.floats(1.0, 6.0), min_size=m, max_size=m)))
    spline = timmer_gc2(points, alpha=alpha, beta=beta, joint="thesis")
    _, left, right = _joint_second_derivatives(spline)
    scale = 1 + np.abs(left).max()
    np.testing.assert_allclose(left, right, atol=1e-9 * scale)
    kappa = spline.joint_curvature()
    for k in range(1, m):
        ratio = (alpha[k] / beta[k - 1]) ** 2
        assert kappa[k, 1] == pytest.approx(ratio * kappa[k, 0], abs=1e-8 * (1 + abs(kappa[k, 1])))
    # the end rows: H_1'(0) = D_1, H_{n-1}'(1) = D_n with the raw 2.1 / 2.2 estimates
    raw = estimate_tangents(points)
    np.testing.assert_allclose(spline.derivative(0.0, 1), raw[0], atol=1e-10 * scale)
    np.testing.assert_allclose(spline.derivative(float(m), 1), raw[-1], atol=1e-10 * scale)


@SETTINGS
@given(st.one_of(random_polylines(min_count=3, max_count=12), ellipse_samples()), st.data())
def test_alg_3_3_g2_joint_has_no_curvature_jump(points, data):
    m = len(points) - 1
    alpha = np.array(data.draw(st.lists(st.floats(0.5, 8.0), min_size=m, max_size=m)))
    beta = np.array(data.draw(st.lists(st.floats(0.5, 8.0), min_size=m, max_size=m)))
    try:
        spline = timmer_gc2(points, alpha=alpha, beta=beta, joint="g2")
    except ValueError as error:             # only an ill-conditioned system may be refused
        assert "ill-conditioned" in str(error) or "singular" in str(error)
        return
    knots, left, right = _joint_second_derivatives(spline)
    big_b, small_a = beta[:-1], alpha[1:]
    np.testing.assert_allclose(right, ((big_b / small_a) ** 2)[:, None] * left,
                               atol=1e-8 * (1 + np.abs(left).max()))
    jump, size = jumps(spline)
    assert np.all(np.abs(jump[1:-1]) <= 1e-8 * np.maximum(size[1:-1], 1))
    assert set(spline.info["joint_status"][1:-1]) <= {"g2"}


@SETTINGS
@given(st.one_of(random_polylines(min_count=2, max_count=12), ellipse_samples()), st.floats(0.3, 20.0))
def test_alg_3_3_constant_scales_equal_scipy_clamped_cubic_spline(points, scale):
    """With alpha = beta = a the thesis joint is the uniform-knot C2 cubic spline with end slopes
    4 T / a = D (§5.6; reference: scipy CubicSpline, clamped)."""
    spline = timmer_gc2(points, alpha=scale)
    raw = estimate_tangents(points)
    knots = np.arange(len(points), dtype=float)
    reference = CubicSpline(knots, points, bc_type=((1, raw[0]), (1, raw[-1])))
    t = np.linspace(0, knots[-1], 7 * len(points))
    size = 1 + np.abs(points).max()
    np.testing.assert_allclose(spline(t), reference(t), atol=1e-10 * size)
    np.testing.assert_allclose(4 * spline.auxiliary["tangents"] / scale, reference(knots, 1), atol=1e-10 * size)
    assert spline.info["diagonally_dominant"] is True
    assert set(spline.info["joint_status"][1:-1]) <= {"c2"}
    # explicit end derivatives
    ends = (np.array([1.0, -2.0]), np.array([0.5, 3.0]))
    explicit = timmer_gc2(points, alpha=scale, end_derivatives=ends)
    reference = CubicSpline(knots, points, bc_type=((1, ends[0]), (1, ends[1])))
    np.testing.assert_allclose(explicit(t), reference(t), atol=1e-10 * size)


@SETTINGS
@given(st.one_of(random_polylines(closed=True, min_count=3), ellipse_samples(closed=True, min_count=3)),
       st.floats(0.3, 20.0))
def test_alg_3_3_closed_constant_scales_equal_scipy_periodic_spline(points, scale):
    spline = timmer_gc2(points, closed=True, alpha=scale)
    count = len(points)
    knots = np.arange(count + 1, dtype=float)
    reference = CubicSpline(knots, np.vstack([points, points[:1]]), bc_type="periodic")
    t = np.linspace(0, count, 9 * count)
    size = 1 + np.abs(points).max()
    np.testing.assert_allclose(spline(t), reference(t), atol=1e-10 * size)
    jump, _ = jumps(spline)
    assert np.abs(jump).max() <= 1e-8 * (1 + np.abs(spline.joint_curvature()).max())


@SETTINGS
@given(st.one_of(random_polylines(closed=True, min_count=3), smooth_curves()), st.data())
def test_alg_3_3_closed_g2_and_thesis_rows(points, data):
    count = len(points)
    alpha = np.array(data.draw(st.lists(st.floats(1.0, 4.0), min_size=count, max_size=count)))
    beta = np.array(data.draw(st.lists(st.floats(1.0, 4.0), min_size=count, max_size=count)))
    for joint in ("thesis", "g2"):
        try:
            spline = timmer_gc2(points, closed=True, alpha=alpha, beta=beta, joint=joint)
        except ValueError as error:
            assert "ill-conditioned" in str(error) or "singular" in str(error)
            continue
        _, left, right = _joint_second_derivatives(spline)
        big_b, small_a = np.roll(beta, 1), alpha            # joint k: piece k-1 before, k after
        big_b, small_a = np.append(big_b, big_b[0]), np.append(small_a, small_a[0])
        factor = np.ones_like(big_b) if joint == "thesis" else (big_b / small_a) ** 2
        np.testing.assert_allclose(right, factor[:, None] * left, atol=1e-8 * (1 + np.abs(left).max()))
        if joint == "g2":
            jump, size = jumps(spline)
            assert np.all(np.abs(jump) <= 1e-8 * np.maximum(size, 1))


def test_alg_3_3_non_dominant_system_is_solved_and_checked():
    """alpha = 1, beta = 4 with the g2 joint: rows are not diagonally dominant, the system is still
    regular; rcond is reported and the joint rows hold."""
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.5], [3.0, 2.0], [4.0, 0.0], [5.0, 1.0]])
    spline = timmer_gc2(points, alpha=1.0, beta=4.0, joint="g2")
    assert spline.info["diagonally_dominant"] is False
    assert 0 < spline.info["rcond"] < 1
    _, left, right = _joint_second_derivatives(spline)
    np.testing.assert_allclose(right, 16 * left, atol=1e-9 * np.abs(left).max())
    closed = timmer_gc2(points, closed=True, alpha=1.0, beta=4.0, joint="g2")
    assert closed.info["diagonally_dominant"] is False
    jump, size = jumps(closed)
    assert np.all(np.abs(jump) <= 1e-8 * np.maximum(size, 1))


@pytest.mark.parametrize("count", [4, 6, 10])
def test_alg_3_3_singular_system_raises(count):
    """Closed, even N, alpha = 1, beta = (3+sqrt5)/2, g2 joint: the normalised circulant rows
    [l, 1, u] have l + u = 1, so the eigenvalue 1 - l - u at the alternating mode vanishes."""
    angle = 2 * np.pi * np.arange(count) / count
    points = np.c_[np.cos(angle), np.sin(angle)]
    lower, upper = GOLDEN**2 / (2 * (1 + GOLDEN)), 1 / (2 * GOLDEN * (1 + GOLDEN))
    assert lower + upper == pytest.approx(1.0)
    # §5.6's dominance test 2/B + 2/a > 1/A + 1/b is for the thesis rows only: it holds here
    # (A = a = 1, B = b = GOLDEN), yet the g2 rows are singular; their test is 2(a+B) > B^2/A + a^2/b
    big_a = small_a = 1.0
    big_b = small_b = GOLDEN
    assert 2 / big_b + 2 / small_a > 1 / big_a + 1 / small_b
    assert 2 * (small_a + big_b) == pytest.approx(big_b**2 / big_a + small_a**2 / small_b)
    thesis = timmer_gc2(points, closed=True, alpha=1.0, beta=GOLDEN, joint="thesis")
    assert thesis.info["diagonally_dominant"] is True
    with pytest.raises(ValueError, match="singular|ill-conditioned"):
        timmer_gc2(points, closed=True, alpha=1.0, beta=GOLDEN, joint="g2")


def test_alg_3_3_validation():
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [3.0, 1.0]])
    with pytest.raises(ValueError, match=r"beta\[1\] must be > 0"):
        timmer_gc2(points, beta=[1.0, -1.0, 1.0])
    with pytest.raises(ValueError, match="joint"):
        timmer_gc2(points, joint="c2")
    with pytest.raises(ValueError, match="open curves only"):
        timmer_gc2(points, closed=True, end_derivatives=([1.0, 0.0], [1.0, 0.0]))
    with pytest.raises(ValueError, match=r"end_derivatives\[1\] must have shape"):
        timmer_gc2(points, end_derivatives=([1.0, 0.0], [1.0, 0.0, 2.0]))
    with pytest.raises(ValueError, match=r"points\[1\] and points\[2\] coincide"):
        timmer_gc2(np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [3.0, 1.0]]))
    with pytest.raises(ValueError, match="at least 3 points"):
        timmer_gc2(points[:2], closed=True)
    with pytest.raises(ValueError, match="at least 2 points"):
        timmer_g2(points[:1])
    with pytest.raises(TypeError, match="closed"):
        timmer_gc2(points, closed=1)


# ---------------------------------------------------------------------------------------------- all schemes
@pytest.mark.parametrize("build", [timmer_g2, timmer_gc1, timmer_gc2])
@pytest.mark.parametrize("closed", [False, True])
def test_common_output(build, closed):
    angle = np.linspace(0, 2 * np.pi, 9)[:-1]
    points = np.c_[3 * np.cos(angle), np.sin(angle)] + [10.0, 5.0]
    spline = build(points, closed=closed)
    m = len(points) if closed else len(points) - 1
    assert spline.info["form"] == build.__name__
    assert spline.n_segments == m and spline.closed == closed
    aux = spline.auxiliary
    assert aux["Q1"].shape == aux["Q2"].shape == (m, 2)
    assert aux["tangents"].shape == points.shape
    np.testing.assert_allclose(spline.knot_points[:len(points)], points)
    # Q1, Q2 are the Timmer polygon points: H(1/2) is their midpoint (thesis section 3.3.2 extra interpolation)
    np.testing.assert_allclose(spline(np.arange(m) + 0.5), 0.5 * (aux["Q1"] + aux["Q2"]), atol=1e-12)
    # JSON round trip keeps the report
    again = Spline.from_dict(spline.to_dict())
    assert again.info == spline.info


@pytest.mark.parametrize("count", [2, 3, 4, 6])
def test_reversed_gc2_spline_has_the_end_derivatives_of_the_curve_built_backwards(count):
    from splinecraft.spline.timmer import timmer_gc2

    points = np.array([[0, 0], [1, 2], [3, 3], [4, 1], [6, 2], [8, 0.5]])[:count]
    back = timmer_gc2(points).reversed()
    built = timmer_gc2(points[::-1])
    np.testing.assert_allclose(back.bezier(), built.bezier(), atol=1e-12)
    np.testing.assert_allclose(back.info["end_derivatives"], built.info["end_derivatives"], atol=1e-12)


def test_reversed_timmer_spline_keeps_its_polygon_and_joint_metadata():
    """Reversal maps Q1 <-> Q2, reverses per-piece alpha/beta and per-knot joint lists (piecewise.reversed)."""
    from splinecraft.spline.timmer import timmer_gc1

    theta = np.linspace(0.0, 2.5, 7)
    points = np.column_stack([40 * np.cos(theta), 25 * np.sin(theta)])
    alpha = np.linspace(0.05, 0.2, 6)
    beta = np.linspace(0.3, 0.1, 6)
    curve = timmer_gc1(points, alpha=alpha, beta=beta)
    back = curve.reversed()
    np.testing.assert_allclose(back.auxiliary["Q1"], curve.auxiliary["Q2"][::-1])
    np.testing.assert_allclose(back.auxiliary["Q2"], curve.auxiliary["Q1"][::-1])
    # Piece i of the reversed curve is piece m-1-i traversed backwards: its alpha is the old beta.
    np.testing.assert_allclose(back.bezier(), curve.bezier()[::-1, ::-1])
    if isinstance(curve.info.get("alpha"), list):
        assert back.info["alpha"] == curve.info["beta"][::-1]
    for key in ("joint_status", "curvature_jump"):
        if isinstance(curve.info.get(key), list):
            assert back.info[key] == curve.info[key][::-1]
