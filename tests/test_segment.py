"""Tests of the generic cubic segment (§1, thesis 3.5-3.22) and its blending functions."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from splinecraft.spline.segment import CLASS_PRESETS, blending_functions, generic_segment, hermite_bezier

SETTINGS = settings(max_examples=60, deadline=None)
THETA = np.linspace(0, 1, 101)


def test_presets():
    assert CLASS_PRESETS == {"ball": (2, 2), "bezier": (3, 3), "timmer": (4, 4)}


def test_ball_blending_functions():
    s = 1 - THETA
    expected = np.stack([s**2, 2 * THETA * s**2, 2 * THETA**2 * s, THETA**2], axis=1)
    np.testing.assert_allclose(blending_functions(THETA, *CLASS_PRESETS["ball"]), expected, atol=1e-15)


def test_bezier_blending_functions_are_bernstein():
    s = 1 - THETA
    expected = np.stack([s**3, 3 * THETA * s**2, 3 * THETA**2 * s, THETA**3], axis=1)
    np.testing.assert_allclose(blending_functions(THETA, *CLASS_PRESETS["bezier"]), expected, atol=1e-15)


def test_timmer_blending_functions():
    s = 1 - THETA
    expected = np.stack([(1 - 2 * THETA) * s**2, 4 * THETA * s**2, 4 * THETA**2 * s, (2 * THETA - 1) * THETA**2], axis=1)
    values = blending_functions(THETA, *CLASS_PRESETS["timmer"])
    np.testing.assert_allclose(values, expected, atol=1e-15)
    # §5.1: f(1/2) = (0, 1/2, 1/2, 0); f_0 has minimum -1/27 at 2/3, f_3 at 1/3
    np.testing.assert_allclose(blending_functions(0.5, 4, 4), [0, 0.5, 0.5, 0], atol=1e-15)
    np.testing.assert_allclose(blending_functions(2 / 3, 4, 4)[0], -1 / 27, atol=1e-15)
    np.testing.assert_allclose(blending_functions(1 / 3, 4, 4)[3], -1 / 27, atol=1e-15)
    assert values[:, 0].min() >= -1 / 27 - 1e-15


@SETTINGS
@given(st.floats(-10, 10), st.floats(-10, 10))
def test_blending_functions_sum_to_one_and_mirror(alpha, beta):
    values = blending_functions(THETA, alpha, beta)
    np.testing.assert_allclose(values.sum(axis=1), 1.0, atol=1e-12)
    mirrored = blending_functions(1 - THETA, beta, alpha)[:, ::-1]
    np.testing.assert_allclose(values, mirrored, atol=1e-12)
    np.testing.assert_allclose(values[0], [1, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(values[-1], [0, 0, 0, 1], atol=1e-15)


@st.composite
def segment_data(draw):
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    F0, V, W, F1 = rng.uniform(-50, 50, size=(4, 2))
    alpha = draw(st.floats(0.2, 8))
    beta = draw(st.floats(0.2, 8))
    t0 = draw(st.floats(-5, 5))
    h = draw(st.floats(0.1, 10))
    return F0, V, W, F1, alpha, beta, t0, h


@SETTINGS
@given(segment_data())
def test_generic_segment_equals_its_definition(data):
    F0, V, W, F1, alpha, beta, t0, h = data
    segment = generic_segment(F0, V, W, F1, alpha, beta, knots=(t0, t0 + h))
    weights = blending_functions(THETA, alpha, beta)
    expected = weights @ np.stack([F0, V, W, F1])
    np.testing.assert_allclose(segment(t0 + h * THETA), expected, atol=1e-10 * 50)
    # end derivatives, eqs 3.10, 3.11, 3.18, 3.21 (§1)
    np.testing.assert_allclose(segment(t0, 1), alpha / h * (V - F0), rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(segment(t0 + h, 1, side="left"), beta / h * (F1 - W), rtol=1e-10, atol=1e-10)
    second_start = (2 * (2 * alpha - 3) * F0 - 4 * alpha * V + 2 * beta * W + 2 * (3 - beta) * F1) / h**2
    second_end = (2 * (3 - alpha) * F0 + 2 * alpha * V - 4 * beta * W + 2 * (2 * beta - 3) * F1) / h**2
    np.testing.assert_allclose(segment(t0, 2), second_start, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(segment(t0 + h, 2, side="left"), second_end, rtol=1e-9, atol=1e-9)
    assert segment.n_segments == 1 and segment.info["alpha"] == alpha
    np.testing.assert_array_equal(segment.auxiliary["V"], [V])


def test_class_parameters_change_a_designed_segment():
    F0, V, W, F1 = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]])
    shapes = {name: generic_segment(F0, V, W, F1, *ab)(0.5) for name, ab in CLASS_PRESETS.items()}
    assert shapes["ball"][1] < shapes["bezier"][1] < shapes["timmer"][1]
    np.testing.assert_allclose(shapes["timmer"], (V + W) / 2)  # f(1/2) = (0, 1/2, 1/2, 0)
    np.testing.assert_allclose(shapes["bezier"][1], 0.75 * 2)  # Bernstein: 3/8 (V_y + W_y)


def test_hermite_bezier_has_the_given_tangents():
    rng = np.random.default_rng(1)
    points = rng.normal(size=(5, 2))
    tangents = rng.normal(size=(5, 2))
    steps = rng.uniform(0.5, 2, 4)
    b = hermite_bezier(points, tangents, steps, closed=False)
    np.testing.assert_allclose(3 * (b[:, 1] - b[:, 0]) / steps[:, None], tangents[:-1])
    np.testing.assert_allclose(3 * (b[:, 3] - b[:, 2]) / steps[:, None], tangents[1:])
    loop = hermite_bezier(points, tangents, rng.uniform(0.5, 2, 5), closed=True)
    np.testing.assert_allclose(loop[-1, 3], points[0])


def test_generic_segment_bad_input():
    with pytest.raises(ValueError, match="same dimension"):
        generic_segment([0, 0], [1, 1], [2, 2, 2], [3, 3])
    with pytest.raises(ValueError, match=r"V\[1\] is nan"):
        generic_segment([0, 0], [1, np.nan], [2, 2], [3, 3])
    with pytest.raises(ValueError, match=r"knots\[1\]"):
        generic_segment([0, 0], [1, 1], [2, 2], [3, 3], knots=(1.0, 1.0))
    with pytest.raises(ValueError, match="alpha"):
        generic_segment([0, 0], [1, 1], [2, 2], [3, 3], alpha=[1.0, 2.0])
    with pytest.raises(TypeError, match="alpha"):
        generic_segment([0, 0], [1, 1], [2, 2], [3, 3], alpha="ball")


@pytest.mark.parametrize("scale", [1.0, 1e-300, 1e300, 1e308])
def test_generic_segment_near_the_float64_limit(scale):
    """b1 = F0 + alpha/3 (V - F0) is representable whenever the points are (for alpha in [0, 3] it lies between
    F0 and V), but V - F0 of points near the float64 limit used to overflow: 'bezier[0, 1, 0] is -inf'."""
    F0, V, W, F1 = (np.array(p) * scale for p in ([1.0, 0.0], [-1.0, 0.5], [0.0, -1.0], [1e-9, 0.25]))
    for alpha, beta in CLASS_PRESETS.values():
        b = generic_segment(F0, V, W, F1, alpha, beta).bezier()[0]
        np.testing.assert_array_equal(b[0], F0)
        np.testing.assert_array_equal(b[3], F1)
        expected = segment_reference(F0 / scale, V / scale, W / scale, F1 / scale, alpha, beta)
        np.testing.assert_allclose(b / scale, expected, rtol=1e-15, atol=1e-15)
    np.testing.assert_array_equal(generic_segment(F0, V, W, F1).bezier()[0, 1:3], [V, W])  # Bézier: b1 = V
    if scale >= 1e300:  # b1 truly beyond 1.8e308: refused by name, not as an internal 'bezier[0, 1, 0] is -inf'
        with pytest.raises(ValueError, match=r"b1 = F0 \+ alpha/3 \(V - F0\).*alpha = 3000000000000.0"):
            generic_segment(F0, V, W, F1, alpha=3e12)


def segment_reference(F0, V, W, F1, alpha, beta):
    return np.array([F0, F0 + alpha / 3 * (V - F0), F1 + beta / 3 * (W - F1), F1])
