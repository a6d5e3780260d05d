"""Tangent estimates (§6, thesis eqs 2.1-2.5): estimate_tangents, end_derivatives, interior_angle."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from splinecraft.spline.tangents import end_derivatives, estimate_tangents, interior_angle, unit_tangents

SETTINGS = settings(max_examples=60, deadline=None)

coefficient = st.floats(-10.0, 10.0, allow_nan=False)
vector = st.tuples(coefficient, coefficient).map(np.array)


def _well_spaced(points, rtol=1e-3):
    """Consecutive points clearly distinct (relative to the extent)."""
    extent = np.max(np.ptp(points, axis=0))
    return extent > 0 and np.min(np.linalg.norm(np.diff(points, axis=0), axis=1)) > rtol * extent


@st.composite
def polygons(draw, min_size=3, max_size=12):
    count = draw(st.integers(min_size, max_size))
    seed = draw(st.integers(0, 2**32 - 1))
    points = np.random.default_rng(seed).normal(size=(count, 2)) * draw(st.floats(0.01, 100.0))
    assume(_well_spaced(points))
    return points


# ---------------------------------------------------------------------------------------------- eqs 2.1/2.2
@SETTINGS
@given(vector, vector, vector, st.integers(3, 10))
def test_end_formulas_are_exact_for_quadratics(a, b, c, count):
    """2.1 and 2.2 are the one-sided second-order differences: exact derivative of a quadratic at t=0, n."""
    t = np.arange(count, dtype=float)
    points = a + np.outer(t, b) + np.outer(t**2, c)
    assume(_well_spaced(points))
    n = count - 1
    scale = 1.0 + np.abs(points).max()
    # a zero derivative at an end triggers the documented chord fallback instead
    assume(min(np.linalg.norm(b), np.linalg.norm(b + 2.0 * n * c)) > 1e-6 * scale)
    tangents = estimate_tangents(points)
    np.testing.assert_allclose(tangents[0], b, atol=1e-11 * scale)
    np.testing.assert_allclose(tangents[-1], b + 2.0 * n * c, atol=1e-11 * scale)


def test_end_formula_points_forward_along_travel():
    """§6.1: T_n points along the direction of travel (no sign error)."""
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]])
    tangents = estimate_tangents(points)
    np.testing.assert_allclose(tangents[[0, -1]], [[1.0, 0.0], [1.0, 0.0]])


# ---------------------------------------------------------------------------------------------- eqs 2.3/2.4
@SETTINGS
@given(polygons())
def test_interior_is_thesis_formula_and_bisector(points):
    """2.3 with a_i of 2.4 equals d-d+/(d-+d+) (u- + u+): it bisects the two unit chords (§6.2)."""
    tangents = estimate_tangents(points)
    before, here, after = points[:-2], points[1:-1], points[2:]
    d_minus = np.linalg.norm(here - before, axis=1)
    d_plus = np.linalg.norm(after - here, axis=1)
    a = d_plus / (d_plus + d_minus)                                      # eq 2.4
    printed = a[:, None] * (here - before) + (1 - a)[:, None] * (after - here)   # eq 2.3
    u_minus = (here - before) / d_minus[:, None]
    u_plus = (after - here) / d_plus[:, None]
    reversal = np.linalg.norm(u_minus + u_plus, axis=1) < 1e-6
    scale = np.abs(points).max()
    np.testing.assert_allclose(tangents[1:-1][~reversal], printed[~reversal], atol=1e-12 * scale)
    # bisector: same angle to both unit chords
    unit = tangents[1:-1][~reversal]
    unit = unit / np.linalg.norm(unit, axis=1)[:, None]
    np.testing.assert_allclose(np.sum(unit * u_minus[~reversal], axis=1),
                               np.sum(unit * u_plus[~reversal], axis=1), atol=1e-9)


@SETTINGS
@given(polygons(), st.integers(0, 20))
def test_closed_uses_the_interior_formula_cyclically(points, shift):
    """Closed: every point gets 2.3 with cyclic neighbours; rolling the input rolls the output."""
    assume(np.linalg.norm(points[0] - points[-1]) > 1e-3 * np.ptp(points, axis=0).max())
    tangents = estimate_tangents(points, closed=True)
    padded = np.vstack([points[-1:], points, points[:1]])
    open_interior = estimate_tangents(padded)[1:-1]
    np.testing.assert_allclose(tangents, open_interior, atol=1e-12 * np.abs(points).max())
    shift %= len(points)
    rolled = estimate_tangents(np.roll(points, -shift, axis=0), closed=True)
    np.testing.assert_allclose(rolled, np.roll(tangents, -shift, axis=0), atol=1e-12 * np.abs(points).max())


def test_reversal_falls_back_to_outgoing_chord():
    """u- + u+ = 0 (the path turns back): the estimate is along u+ (§6.2)."""
    points = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 3.0]])
    tangents = estimate_tangents(points)
    direction = tangents[1] / np.linalg.norm(tangents[1])
    np.testing.assert_allclose(direction, [-1.0, 0.0])
    assert np.linalg.norm(tangents[1]) > 0


def test_two_points_and_zero_end_estimate_use_the_chord():
    two = np.array([[0.0, 0.0], [3.0, 4.0]])
    np.testing.assert_allclose(estimate_tangents(two), [[3.0, 4.0], [3.0, 4.0]])
    # P2 = 4 P1 - 3 P0 makes 2.1 vanish; the estimate falls back to the first chord
    zero_end = np.array([[0.0, 0.0], [1.0, 0.0], [4.0, 0.0], [5.0, 1.0]])
    assert np.allclose(0.5 * (-3 * zero_end[0] + 4 * zero_end[1] - zero_end[2]), 0.0)
    np.testing.assert_allclose(estimate_tangents(zero_end)[0], [1.0, 0.0])


@SETTINGS
@given(polygons(), st.floats(0.1, 10.0), st.floats(-np.pi, np.pi), vector)
def test_tangents_are_similarity_equivariant(points, scale, angle, offset):
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    moved = scale * points @ rotation.T + offset
    for closed in (False, True):
        if closed:
            assume(np.linalg.norm(points[0] - points[-1]) > 1e-3 * np.ptp(points, axis=0).max())
        expected = scale * estimate_tangents(points, closed=closed) @ rotation.T
        np.testing.assert_allclose(estimate_tangents(moved, closed=closed), expected,
                                   atol=1e-9 * scale * (1 + np.abs(points).max()))


# ---------------------------------------------------------------------------------------------- chord parabola
@SETTINGS
@given(polygons(min_size=4, max_size=8))
def test_chord_parabola_is_the_derivative_of_the_chord_knot_parabola(points):
    """Interior: derivative at the middle point of the parabola through 3 points at chord-length knots,
    compared with numpy.polyfit; ends: §6.3 with chord knots."""
    tangents = estimate_tangents(points, method="chord_parabola")
    knots = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    for i in range(1, len(points) - 1):
        local = knots[i - 1:i + 2] - knots[i]
        for axis in range(2):
            coefficients = np.polyfit(local, points[i - 1:i + 2, axis], 2)
            assert tangents[i, axis] == pytest.approx(coefficients[1], abs=1e-7 * (1 + abs(coefficients[1])))
    first, last = end_derivatives(points, knots)
    np.testing.assert_allclose(tangents[0], first, atol=1e-12 * (1 + np.abs(first).max()))
    np.testing.assert_allclose(tangents[-1], last, atol=1e-12 * (1 + np.abs(last).max()))


def test_chord_parabola_is_exact_on_a_line_with_uneven_spacing():
    points = np.outer([0.0, 0.3, 1.0, 4.0, 4.5], [0.6, 0.8])
    np.testing.assert_allclose(estimate_tangents(points, method="chord_parabola"), np.tile([0.6, 0.8], (5, 1)))


# ---------------------------------------------------------------------------------------------- §6.3
@SETTINGS
@given(vector, vector, vector, st.lists(st.floats(0.05, 5.0), min_size=1, max_size=8))
def test_end_derivatives_exact_for_quadratics_with_uneven_knots(a, b, c, steps):
    knots = np.concatenate([[0.7], 0.7 + np.cumsum(steps)])
    points = a + np.outer(knots, b) + np.outer(knots**2, c)
    assume(_well_spaced(points))
    first, last = end_derivatives(points, knots)
    scale = 1.0 + np.abs(b).max() + np.abs(c).max() * knots[-1]
    if len(knots) == 2:  # two points: the chord slope
        np.testing.assert_allclose(first, (points[1] - points[0]) / steps[0], atol=1e-12 * scale)
        np.testing.assert_allclose(last, first)
    else:
        np.testing.assert_allclose(first, b + 2 * c * knots[0], atol=1e-9 * scale)
        np.testing.assert_allclose(last, b + 2 * c * knots[-1], atol=1e-9 * scale)


@SETTINGS
@given(polygons())
def test_end_derivatives_with_unit_knots_reduce_to_eqs_2_1_2_2(points):
    first, last = end_derivatives(points, np.arange(len(points)) * 1.0)
    tangents = estimate_tangents(points)
    scale = np.abs(points).max()
    for mine, thesis in ((first, tangents[0]), (last, tangents[-1])):
        if np.linalg.norm(thesis) > 1e-9 * scale:       # away from the zero-estimate fallback
            np.testing.assert_allclose(mine, thesis, atol=1e-12 * scale)


def test_end_derivatives_validate_knots():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]])
    with pytest.raises(ValueError, match=r"knots\[1\]"):
        end_derivatives(points, [0.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="shape"):
        end_derivatives(points, [0.0, 1.0])
    with pytest.raises(ValueError, match=r"knots\[2\]"):
        end_derivatives(points, [0.0, 1.0, np.nan])


# ---------------------------------------------------------------------------------------------- E21
def test_interior_angle_known_values():
    right = np.array([[1.0, 0.0], [0.0, 0.0], [0.0, 1.0]])
    straight = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    reversal = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 0.0]])
    assert interior_angle(right)[0] == pytest.approx(90.0)
    assert interior_angle(straight)[0] == pytest.approx(180.0)
    assert interior_angle(reversal)[0] == pytest.approx(0.0, abs=1e-12)
    assert interior_angle(right, degrees=False)[0] == pytest.approx(np.pi / 2)


@SETTINGS
@given(polygons())
def test_interior_angle_is_180_minus_the_printed_angle(points):
    """E21: the printed eq 2.5 angle between a = P_{i+1}-P_i and b = P_{i+2}-P_{i+1} is 180° minus the
    interior angle; straight-on travel gives interior 180° (collinear ⇔ angle > TA)."""
    a = points[1:-1] - points[:-2]
    b = points[2:] - points[1:-1]
    cosine = np.sum(a * b, axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    printed = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
    np.testing.assert_allclose(interior_angle(points), 180.0 - printed, atol=1e-5)
    closed = interior_angle(points, closed=True)
    assert closed.shape == (len(points),)
    np.testing.assert_allclose(closed[1:-1], interior_angle(points), atol=1e-9)


# ---------------------------------------------------------------------------------------------- validation
def test_bad_inputs_raise_with_the_index():
    good = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0], [3.0, 3.0]])
    nan = good.copy()
    nan[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"points\[2, 1\]"):
        estimate_tangents(nan)
    duplicate = np.vstack([good[:2], good[1:]])
    with pytest.raises(ValueError, match=r"points\[1\] and points\[2\] coincide"):
        estimate_tangents(duplicate)
    with pytest.raises(ValueError, match=r"points\[1\] and points\[2\]"):
        interior_angle(duplicate)
    with pytest.raises(ValueError, match="repeats points\\[0\\]"):
        estimate_tangents(np.vstack([good, good[:1]]), closed=True)
    with pytest.raises(ValueError, match="at least 2 points"):
        estimate_tangents(good[:1])
    with pytest.raises(ValueError, match="at least 3 points"):
        estimate_tangents(good[:2], closed=True)
    with pytest.raises(ValueError, match="at least 3 points"):
        interior_angle(good[:2])
    with pytest.raises(ValueError, match="method"):
        estimate_tangents(good, method="spline")
    with pytest.raises(ValueError, match="shape"):
        estimate_tangents(good[0])
    with pytest.raises(TypeError):
        estimate_tangents("points")
    with pytest.raises(TypeError, match="closed"):
        estimate_tangents(good, closed="yes")
    with pytest.raises(ValueError, match=r"tangents\[1\] is the zero vector"):
        unit_tangents([[1.0, 0.0], [0.0, 0.0]])
