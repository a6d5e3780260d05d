"""The compiled kernels of the fit (capture/fitting/_kernels.py) against independent references.

Two references per kernel: scipy's B-spline basis (``BSpline.basis_element``) or a brute-force loop for the
values themselves, and the vectorized numpy formulation written out here, which the kernel must match bit
for bit (it performs the same floating-point operations in the same order, so the fit's results do not
depend on which of the two ran).
"""
from __future__ import annotations

import os

import numba
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.interpolate import BSpline

from splinecraft.capture.fitting import _kernels, bspline, geometry


def _knots(m, seed, multiple=False):
    """A random periodic knot vector of ``m`` knots in [0, 100) (optionally with triple knots), sorted
    parameters in the period, weights and targets."""
    rng = np.random.default_rng(seed)
    period = 100.0
    tau = np.sort(rng.uniform(0, period, m))
    tau[0] = 0.0
    if np.diff(tau).min() < 1e-3:
        tau = np.linspace(0, period, m, endpoint=False)
    if multiple and m >= 7:
        tau[1:3] = tau[0]  # a corner: knot 0 three times
        tau = np.sort(tau)
    full = bspline.periodic_knot_vector(tau, period)
    u = np.sort(rng.uniform(0, period, 10 * m))
    return rng, period, full, u


def _numpy_basis(full, i, u):
    """Cox-de Boor, vectorized over the points (the formulation the kernel replaced)."""
    n = u.shape[0]
    left, right = np.empty((n, 4)), np.empty((n, 4))
    for j in range(1, 4):
        left[:, j] = u - full[i + 1 - j]
        right[:, j] = full[i + j] - u
    basis = np.ones((n, 1))
    for j in range(1, 4):
        new = np.zeros((n, j + 1))
        saved = np.zeros(n)
        for r in range(j):
            denom = right[:, r + 1] + left[:, j - r]
            temp = basis[:, r] / np.where(denom > 0, denom, 1.0)
            new[:, r] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        new[:, j] = saved
        basis = new
    return basis


def _collocation(full, m, u):
    """Periodic collocation matrix from scipy's basis elements (coefficient of full index k + 3 is k mod m)."""
    matrix = np.zeros((u.shape[0], m))
    for k in range(full.shape[0] - 4):
        if full[k + 4] > full[k]:
            matrix[:, (k - 3) % m] += np.nan_to_num(BSpline.basis_element(full[k:k + 5], extrapolate=False)(u))
    return matrix


@settings(max_examples=30, deadline=None)
@given(st.integers(4, 40), st.integers(0, 10_000), st.booleans())
def test_basis_matches_scipy_and_the_vectorized_recurrence(m, seed, multiple):
    _, _, full, u = _knots(m, seed, multiple)
    i = bspline.interval_index(full, u)
    got = bspline.cubic_basis(full, i, u)
    np.testing.assert_array_equal(got, _numpy_basis(full, i, u))
    dense = np.zeros((u.shape[0], m))
    np.add.at(dense, (np.arange(u.shape[0])[:, None], (i[:, None] - 6 + np.arange(4)) % m), got)
    np.testing.assert_allclose(dense, _collocation(full, m, u), atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(st.integers(4, 40), st.integers(0, 10_000), st.booleans())
def test_normal_equations_match_the_dense_collocation_and_the_bincount_sums(m, seed, multiple):
    rng, _, full, u = _knots(m, seed, multiple)
    weights = rng.uniform(0.1, 1.0, u.shape[0])
    targets = rng.normal(size=(u.shape[0], 2))
    band, rhs, normal = _kernels.normal_equations(full, u, weights, targets, m)
    assert normal is None
    # reference 1: the dense normal matrix A^T W A and A^T W Q from scipy's basis
    matrix = _collocation(full, m, u)
    normal = matrix.T @ (weights[:, None] * matrix)
    np.testing.assert_allclose(rhs, matrix.T @ (weights[:, None] * targets), atol=1e-9)
    rebuilt = np.zeros((m, m))
    idx = np.arange(m)
    rebuilt[idx, idx] += band[0]
    for k in (1, 2, 3):
        rebuilt[idx, (idx + k) % m] += band[k]
        rebuilt[(idx + k) % m, idx] += band[k]
    np.testing.assert_allclose(rebuilt, normal, atol=1e-9)
    # reference 2: bincount sums of the vectorized basis, bit for bit
    i = bspline.interval_index(full, u)
    basis = _numpy_basis(full, i, u)
    cols = (i[:, None] - 6 + np.arange(4)[None, :]) % m
    wb = basis * weights[:, None]
    expected_rhs = np.column_stack([np.bincount(cols.reshape(-1), weights=(wb * targets[:, d, None]).reshape(-1),
                                                minlength=m) for d in range(2)])
    expected_band = np.zeros((4, m))
    for r in range(4):
        for s in range(r, 4):
            expected_band[s - r] += np.bincount(cols[:, r], weights=wb[:, r] * basis[:, s], minlength=m)
    np.testing.assert_array_equal(rhs, expected_rhs)
    np.testing.assert_array_equal(band, expected_band)


@settings(max_examples=40, deadline=None)
@given(st.integers(4, 120), st.integers(0, 10_000))
def test_lsq_normal_equations_match_a_dense_least_squares_reference(m, seed):
    """The banded cyclic normal-equation solve (dense below 65 coefficients, Schur-complement band solve
    above) equals numpy's least squares on the explicit collocation matrix (scipy's BSpline basis)."""
    rng, _, full, u = _knots(m, seed)
    weights = rng.uniform(0.1, 1.0, u.shape[0])
    targets = rng.normal(size=(u.shape[0], 2))
    regularization = 1e-8
    solved = bspline.fit_coefficients(full, u, weights, targets, m, regularization)
    collocation = _collocation(full, m, u)
    np.testing.assert_allclose(collocation.sum(axis=1), 1.0, atol=1e-12)
    normal = collocation.T @ (weights[:, None] * collocation)
    second_difference = np.zeros((m, m))
    idx = np.arange(m)
    second_difference[idx, idx] = 1.0
    second_difference[idx, (idx + 1) % m] += -2.0
    second_difference[idx, (idx + 2) % m] += 1.0
    normal += regularization * np.diag(normal).max() * second_difference.T @ second_difference
    reference = np.linalg.solve(normal, collocation.T @ (weights[:, None] * targets))
    np.testing.assert_allclose(solved, reference, rtol=1e-6, atol=1e-6 * np.abs(reference).max())


@settings(max_examples=30, deadline=None)
@given(st.integers(4, 40), st.integers(0, 10_000), st.booleans())
def test_spline_values_and_bezier_pieces_match_scipy(m, seed, multiple):
    rng, period, full, _ = _knots(m, seed, multiple)
    coef = rng.normal(size=(m, 2))
    distinct = np.unique(np.append(full[3:-4], period))
    starts, ends = distinct[:-1], distinct[1:]
    theta = np.array([0.0, 0.25, 0.5, 1.0])
    values = _kernels.spline_values(coef, full, m, starts, ends, theta)
    params = starts[:, None] + (ends - starts)[:, None] * theta[None, :]
    # inside each interval, scipy's basis at the interval's own parameters (ends taken from the left)
    inner = np.clip(params, starts[:, None] + 1e-12 * period, ends[:, None] - 1e-12 * period)
    reference = (_collocation(full, m, inner.reshape(-1)) @ coef).reshape(values.shape)
    np.testing.assert_allclose(values, reference, atol=1e-8)
    bez = bspline.bezier_of_intervals(coef, full, m, starts, ends)
    # the Bezier points mixed in the kernel are einsum's, bit for bit (the formulation the mix replaced)
    samples = _kernels.spline_values(coef, full, m, starts, ends, bspline._THETA4)
    np.testing.assert_array_equal(bez, np.einsum("ij,kjd->kid", bspline._FROM_SAMPLES, samples))
    t = 0.3
    point = ((1 - t) ** 3 * bez[:, 0] + 3 * t * (1 - t) ** 2 * bez[:, 1] + 3 * t * t * (1 - t) * bez[:, 2]
             + t ** 3 * bez[:, 3])
    middle = starts + t * (ends - starts)
    np.testing.assert_allclose(point, _collocation(full, m, middle) @ coef, atol=1e-8)


def _penalized_reference(band, regularization):
    """The penalty and the dense cyclic matrix as numpy's fancy-index additions build them (the formulation the
    kernel replaced): ``(band + pen * D^T D, dense matrix)``."""
    m = band.shape[1]
    expected = band.copy()
    pen = regularization * (float(expected[0].max()) or 1.0)
    expected[0] += 6 * pen
    expected[1] += -4 * pen
    expected[2] += 1 * pen
    dense = np.zeros((m, m))
    idx = np.arange(m)
    dense[idx, idx] = expected[0]
    for k in (1, 2, 3):
        dense[idx, (idx + k) % m] += expected[k]
        dense[(idx + k) % m, idx] += expected[k]
    return expected, dense


@settings(max_examples=40, deadline=None)
@given(st.integers(4, 70), st.integers(0, 10_000), st.booleans(), st.integers(0, 5))
def test_penalized_normal_matches_the_fancy_index_assembly(m, seed, multiple, pins):
    """The penalty and the dense cyclic matrix, bit for bit as numpy's fancy-index additions build them
    (wrapped entries of m < 7 added up in the same order), on the band of the same points; the extra points (the
    corner pins) are the points appended, and work arrays holding an earlier system give the same answer."""
    rng, period, full, u = _knots(m, seed, multiple)
    extra = rng.uniform(0, period, pins)
    weights = rng.uniform(0.1, 1.0, u.shape[0] + pins)
    targets = rng.normal(size=(u.shape[0] + pins, 2))
    band, rhs, _ = _kernels.normal_equations(full, np.concatenate([u, extra]), weights, targets, m)
    expected, dense = _penalized_reference(band, 1e-8)
    work = tuple(rng.normal(size=a.shape) for a in _kernels.normal_work(m))  # dirty work arrays
    for given_work in (None, work):
        got_band, got_rhs, got = _kernels.normal_equations(full, u, weights, targets, m, 1e-8, extra, given_work)
        np.testing.assert_array_equal(got_rhs, rhs)
        np.testing.assert_array_equal(got_band, expected)
        if m <= _kernels.DENSE_LIMIT:
            np.testing.assert_array_equal(got, dense)
        else:
            assert got is None


def test_penalized_normal_of_an_empty_diagonal_takes_scale_one():
    full = bspline.periodic_knot_vector(np.arange(7.0), 7.0)
    band, _, normal = _kernels.normal_equations(full, np.zeros(0), np.zeros(0), np.zeros((0, 2)), 7, 1e-8)
    expected, dense = _penalized_reference(np.zeros((4, 7)), 1e-8)
    np.testing.assert_array_equal(band, expected)
    np.testing.assert_array_equal(normal, dense)


def _numpy_hoschek(u, points, bez, starts, ends, piece_of, piece_count, gate):
    """The vectorized Newton step of the foot-point equation (the formulation the kernel replaced)."""
    seg = np.clip(np.searchsorted(starts, u, side="right") - 1, 0, starts.shape[0] - 1)
    h = (ends - starts)[seg]
    theta = (u - starts[seg]) / h
    b0, b1, b2, b3 = (bez[seg, j] for j in range(4))
    c1, c2, c3 = 3.0 * (b1 - b0), 3.0 * (b0 - 2.0 * b1 + b2), b3 - b0 + 3.0 * (b1 - b2)
    th = theta[:, None]
    r = b0 + th * (c1 + th * (c2 + th * c3)) - points
    d1 = (c1 + th * (2.0 * c2 + 3.0 * th * c3)) / h[:, None]
    d2 = (2.0 * c2 + 6.0 * th * c3) / (h * h)[:, None]
    speed2 = d1[:, 0] ** 2 + d1[:, 1] ** 2
    den = speed2 + r[:, 0] * d2[:, 0] + r[:, 1] * d2[:, 1]
    den = np.where(den > 0.1 * speed2, den, speed2)
    du = -(r[:, 0] * d1[:, 0] + r[:, 1] * d1[:, 1]) / np.maximum(den, 1e-300)
    np.clip(du, -2.0, 2.0, out=du)
    res = np.hypot(r[:, 0], r[:, 1])
    worst = np.full(piece_count, -np.inf)
    np.maximum.at(worst, piece_of, res)
    du[worst[piece_of] > gate] = 0.0
    return du


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 12), st.integers(0, 10_000), st.floats(0.2, 5.0))
def test_hoschek_step_matches_the_vectorized_formulation(count, seed, gate):
    rng = np.random.default_rng(seed)
    bounds = np.concatenate([[0.0], np.cumsum(rng.uniform(1.0, 10.0, count))])
    starts, ends = bounds[:-1], bounds[1:]
    bez = np.cumsum(rng.normal(size=(count, 4, 2)), axis=1)
    u = np.sort(rng.uniform(0, bounds[-1], 60))
    points = rng.normal(size=(60, 2)) * 2
    piece_of = np.sort(rng.integers(0, 3, 60))
    got = _kernels.hoschek_update(u, points, bez, starts, ends, piece_of, 3, gate)
    np.testing.assert_array_equal(got, _numpy_hoschek(u, points, bez, starts, ends, piece_of, 3, gate))
    # the stepped parameters: clipped (signed zeros and crossed bounds too), fixed points, non-decreasing
    low, high = u - rng.uniform(0.0, 1.5, 60), u + rng.uniform(-0.2, 1.5, 60)
    low[:3], high[:3] = np.array([0.0, -0.0, 0.0]), np.array([-0.0, 0.0, 0.0])
    fixed, base = rng.random(60) < 0.2, rng.uniform(0, bounds[-1], 60)
    moved = _kernels.hoschek_update(u, points, bez, starts, ends, piece_of, 3, gate, (low, high, fixed, base))
    expected = np.clip(u + got, low, high)
    expected[fixed] = base[fixed]
    expected = np.maximum.accumulate(expected)
    np.testing.assert_array_equal(moved, expected)
    np.testing.assert_array_equal(np.signbit(moved), np.signbit(expected))


@settings(max_examples=30, deadline=None)
@given(st.integers(4, 40), st.integers(0, 10_000), st.booleans(), st.floats(0.2, 5.0))
def test_fit_step_is_the_bezier_pieces_then_the_hoschek_step(m, seed, multiple, gate):
    """The fit's fused step: the Bézier pieces of the spline (einsum of its values, bit for bit) and the Newton
    step on them (the vectorized formulation), with and without the bounds."""
    rng, period, full, u = _knots(m, seed, multiple)
    coef = rng.normal(size=(m, 2)) * 10
    distinct = np.unique(np.append(full[3:-4], period))
    starts, ends = distinct[:-1], distinct[1:]
    points = rng.normal(size=(u.shape[0], 2)) * 10
    piece_of = np.sort(rng.integers(0, 3, u.shape[0]))
    bez = np.einsum("ij,kjd->kid", bspline._FROM_SAMPLES,
                    _kernels.spline_values(coef, full, m, starts, ends, bspline._THETA4))
    got_bez, du, same = _kernels.fit_step(coef, full, m, starts, ends, bspline._THETA4, bspline._FROM_SAMPLES, u,
                                          points, piece_of, 3, gate)
    assert not same
    np.testing.assert_array_equal(got_bez, bez)
    np.testing.assert_array_equal(du, _numpy_hoschek(u, points, bez, starts, ends, piece_of, 3, gate))
    low, high = u - rng.uniform(0.0, 1.5, u.shape[0]), u + rng.uniform(-0.2, 1.5, u.shape[0])
    fixed, base = rng.random(u.shape[0]) < 0.2, rng.uniform(0, period, u.shape[0])
    work = rng.normal(size=(starts.shape[0], 4, 2))
    got_bez, moved, same = _kernels.fit_step(coef, full, m, starts, ends, bspline._THETA4, bspline._FROM_SAMPLES, u,
                                             points, piece_of, 3, gate, (low, high, fixed, base), work)
    expected = np.maximum.accumulate(np.where(fixed, base, np.clip(u + du, low, high)))
    np.testing.assert_array_equal(got_bez, bez)
    np.testing.assert_array_equal(moved, expected)
    assert same == (moved.tobytes() == u.tobytes())
    # a step that moves nothing (every piece above the gate, the bounds the parameters themselves): the same bits,
    # and a signed zero in place of a zero is not the same
    still = np.maximum.accumulate(u)
    _, moved, same = _kernels.fit_step(coef, full, m, starts, ends, bspline._THETA4, bspline._FROM_SAMPLES, still,
                                       points, piece_of, 3, -1.0, (still, still, np.zeros(u.shape[0], bool), base))
    assert same and moved.tobytes() == still.tobytes()
    signed = still.copy()
    signed[0] = -0.0
    low = still.copy()
    low[0] = 0.0
    _, moved, same = _kernels.fit_step(coef, full, m, starts, ends, bspline._THETA4, bspline._FROM_SAMPLES, signed,
                                       points, piece_of, 3, -1.0, (low, low, np.zeros(u.shape[0], bool), base))
    assert not same and moved[0] == 0.0 and not np.signbit(moved[0])


def test_hoschek_step_lands_on_the_foot_point_of_a_straight_piece():
    """On a straight, uniformly parameterized piece the Newton step is exact: S(u + du) is the foot point."""
    bez = np.array([[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]])
    u = np.array([0.5, 1.0, 2.2])
    points = np.array([[1.1, 0.3], [0.4, -0.2], [2.9, 0.1]])
    du = _kernels.hoschek_update(u, points, bez, np.array([0.0]), np.array([3.0]), np.zeros(3, np.int64), 1, 10.0)
    np.testing.assert_allclose(u + du, points[:, 0], atol=1e-12)


def _numpy_windowed(points, centre, lo, hi, edges, window, wrap, sides=False):
    """Windowed point-to-segment distances, vectorized (the formulation the kernel replaced); ``sides``: and the
    cross product of the nearest edge's direction with the vector from its start to the point (the first nearest
    edge of the window)."""
    e = centre[:, None] + np.arange(-window, window + 1)[None, :]
    if lo is not None:
        np.clip(e, lo[:, None], hi[:, None], out=e)
    if wrap:
        e %= wrap
    ax, ay, dx, dy, inverse = edges
    px, py = points[:, 0, None] - ax[e], points[:, 1, None] - ay[e]
    cross = dx[e] * py - dy[e] * px
    t = np.clip((px * dx[e] + py * dy[e]) * inverse[e], 0.0, 1.0)
    px, py = px - t * dx[e], py - t * dy[e]
    squared = px * px + py * py
    distance = np.sqrt(squared.min(axis=1))
    if not sides:
        return distance
    return distance, np.take_along_axis(cross, squared.argmin(axis=1)[:, None], axis=1)[:, 0]


@settings(max_examples=30, deadline=None)
@given(st.integers(5, 60), st.integers(0, 6), st.integers(0, 10_000), st.booleans())
def test_windowed_distance_matches_the_vectorized_formulation(count, window, seed, clipped):
    rng = np.random.default_rng(seed)
    line = np.cumsum(rng.normal(size=(count, 2)), axis=0)
    line[3] = line[2]  # a zero-length edge
    closed = np.vstack([line, line[:1]])
    points = rng.normal(size=(50, 2)) * 3 + line[rng.integers(0, count, 50)]
    centre = rng.integers(0, count, 50)
    lo = hi = None
    if clipped:
        lo = centre - rng.integers(0, 3, 50)
        hi = centre + rng.integers(0, 3, 50)
    edges = geometry.edge_table(closed)
    got = geometry.windowed_distance(points, centre, lo, hi, edges, window, count)
    np.testing.assert_array_equal(got, _numpy_windowed(points, centre, lo, hi, edges, window, count))


def _numpy_segment_grid(px, py, ax, ay, dx, dy):
    """Distances (I, P, E) from points (I, P) to segments ``a -> a + d`` (I, E) as one dense grid (the
    small-outline fit's formulation the kernel replaced)."""
    den = dx * dx + dy * dy
    inverse = 1.0 / np.where(den > 0, den, 1.0)
    rx = px[..., :, None] - ax[..., None, :]
    ry = py[..., :, None] - ay[..., None, :]
    t = np.clip((rx * dx[..., None, :] + ry * dy[..., None, :]) * inverse[..., None, :], 0.0, 1.0)
    rx -= t * dx[..., None, :]
    ry -= t * dy[..., None, :]
    return np.sqrt(rx * rx + ry * ry)


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 7), st.integers(1, 40), st.integers(1, 20), st.integers(0, 10_000))
def test_nearest_segment_distance_matches_the_dense_grid(rows, points, edges, seed):
    """Bit for bit the minimum over the dense (row, point, edge) grid, zero-length segments included, on views
    that are not contiguous (as the small-outline fit passes them); and the exact distance where it is known: a
    point on a segment is 0 from it, a point beyond a segment's end is its distance to that end."""
    rng = np.random.default_rng(seed)
    vertices = np.cumsum(rng.normal(size=(rows, edges + 1, 2)), axis=1)
    vertices[:, edges // 2 + 1] = vertices[:, edges // 2]  # a zero-length segment per row (when edges >= 2)
    vx, vy = vertices[..., 0], vertices[..., 1]
    px, py = (rng.normal(size=(rows, points)) * 2 for _ in range(2))
    ex, ey = np.diff(vx, axis=1), np.diff(vy, axis=1)
    got = _kernels.nearest_segment_distance(px, py, vx[:, :-1], vy[:, :-1], ex, ey)
    np.testing.assert_array_equal(got, _numpy_segment_grid(px, py, vx[:, :-1], vy[:, :-1], ex, ey).min(axis=2))
    on = vertices[:, :1] + 0.25 * (vertices[:, 1:2] - vertices[:, :1])  # a quarter along each row's first edge
    assert np.all(_kernels.nearest_segment_distance(on[..., 0], on[..., 1], vx[:, :1], vy[:, :1], ex[:, :1],
                                                    ey[:, :1]) <= 1e-12)
    beyond = vertices[:, :1] - (vertices[:, 1:2] - vertices[:, :1])  # as far before the first edge's start
    np.testing.assert_allclose(
        _kernels.nearest_segment_distance(beyond[..., 0], beyond[..., 1], vx[:, :1], vy[:, :1], ex[:, :1], ey[:, :1]),
        np.hypot(ex[:, :1], ey[:, :1]), rtol=1e-12)


def _numpy_separating_slope(t_ink, y_ink, t_paper, y_paper, slopes, step, rounds):
    """The slope search of ``tips._separating_line`` in numpy (the formulation the kernel replaced): offset grids,
    argmax of the gaps, then ``numpy.linspace`` grids around the best."""
    count = t_ink.shape[0]
    t_all, y_all = np.concatenate([t_ink, t_paper]), np.concatenate([y_ink, y_paper])
    for _ in range(rounds):
        offsets = y_all[None, :] - slopes[:, None] * t_all[None, :]
        above, below = offsets[:, :count].min(axis=1), offsets[:, count:].max(axis=1)
        slope = slopes[int(np.argmax(above - below))]
        slopes, step = np.linspace(slope - step, slope + step, slopes.shape[0]), step / 8
    return float(slope)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 40), st.integers(1, 40), st.integers(0, 10_000), st.floats(-0.2, 0.2), st.booleans())
def test_separating_slope_matches_the_numpy_search(inks, papers, seed, true_slope, separable):
    """Bit for bit the numpy search (``numpy.linspace`` grids; ties to the first slope as ``argmax``) on pixel
    centres either side of a line (separable) or mixed; on separable centres from a line of slope within the
    first grid the search finds a margin at least that of the true line (up to the last grid's resolution)."""
    from splinecraft.capture.fitting.tips import _FIRST_SLOPES, SLOPE_SEARCH

    rng = np.random.default_rng(seed)
    t_ink, t_paper = rng.uniform(-8, 8, inks), rng.uniform(-8, 8, papers)
    gap = 0.3 if separable else -0.3
    y_ink = true_slope * t_ink + gap / 2 + rng.uniform(0, 1, inks)
    y_paper = true_slope * t_paper - gap / 2 - rng.uniform(0, 1, papers)
    got = _kernels.separating_slope(t_ink, y_ink, t_paper, y_paper, _FIRST_SLOPES, SLOPE_SEARCH / 8, 5)
    assert got == _numpy_separating_slope(t_ink, y_ink, t_paper, y_paper, _FIRST_SLOPES, SLOPE_SEARCH / 8, 5)
    if separable:
        margin = (y_ink - got * t_ink).min() - (y_paper - got * t_paper).max()
        # the margin is concave in the slope: the zoomed grids reach its maximum on the first grid within ~1e-5
        assert margin >= (y_ink - true_slope * t_ink).min() - (y_paper - true_slope * t_paper).max() - 1e-4


def _numpy_eval_bezier(bezier, piece, theta):
    """Cubic Bernstein weights contracted with einsum (the formulation the kernel replaced)."""
    s = 1.0 - theta
    t2, s2 = theta * theta, s * s
    weights = np.column_stack([s2 * s, 3.0 * theta * s2, 3.0 * t2 * s, t2 * theta])
    return np.einsum("nj,njd->nd", weights, bezier[piece])


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 12), st.integers(0, 10_000), st.floats(0.1, 3.0))
def test_bezier_points_and_interval_samples_match_the_vectorized_formulation(count, seed, spacing):
    rng = np.random.default_rng(seed)
    bez = np.cumsum(rng.normal(size=(count, 4, 2)) * rng.uniform(0.1, 20.0), axis=1)
    piece = rng.integers(0, count, 80)
    theta = rng.uniform(0.0, 1.0, 80)
    np.testing.assert_array_equal(geometry.eval_bezier(bez, piece, theta), _numpy_eval_bezier(bez, piece, theta))
    # de Casteljau at theta = 0.5, independently
    half = 0.5 * (bez[:, :-1] + bez[:, 1:])
    half = 0.5 * (half[:, :-1] + half[:, 1:])
    np.testing.assert_allclose(geometry.eval_bezier(bez, np.arange(count), np.full(count, 0.5)),
                               0.5 * (half[:, 0] + half[:, 1]), atol=1e-9)
    starts = np.concatenate([[0.0], np.cumsum(rng.uniform(0.5, 5.0, count - 1))])
    ends = np.append(starts[1:], starts[-1] + 2.0)
    points, params, interval = _kernels.interval_samples(bez, starts, ends, spacing)
    lengths = np.hypot(*np.diff(bez, axis=1).transpose(2, 0, 1)).sum(axis=1)
    counts = np.maximum(3, np.ceil(lengths / spacing).astype(np.int64))
    iv = np.repeat(np.arange(count), counts)
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    fraction = (np.arange(iv.shape[0]) - first[iv]) / counts[iv]
    np.testing.assert_array_equal(interval, iv)
    np.testing.assert_array_equal(params, starts[iv] + fraction * (ends - starts)[iv])
    np.testing.assert_array_equal(points, _numpy_eval_bezier(bez, iv, fraction))


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 8), st.integers(0, 10_000), st.booleans())
def test_group_max_matches_reduceat(count, seed, with_nan):
    """Per group maximum and its first index, against ``numpy.maximum.reduceat`` and a plain search."""
    rng = np.random.default_rng(seed)
    groups = np.sort(rng.integers(0, count, 50))
    values = rng.integers(-3, 4, 50).astype(float)  # ties
    values[rng.random(50) < 0.2] = -np.inf
    if with_nan:
        values[rng.integers(0, 50)] = np.nan
    best, at = geometry.group_max(groups, values, count)
    expected = np.full(count, -np.inf)
    starts = np.flatnonzero(np.concatenate([[True], groups[1:] != groups[:-1]]))
    expected[groups[starts]] = np.maximum.reduceat(values, starts)
    np.testing.assert_array_equal(best, expected)
    for g in range(count):
        hits = np.flatnonzero((groups == g) & (values == expected[g]))
        assert at[g] == (hits[0] if hits.size else 0)


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 10), st.integers(0, 10_000))
def test_curve_points_pick_the_piece_of_each_parameter(count, seed):
    """Against the searchsorted-and-evaluate formulation, bit for bit, and the piece ends (closed form)."""
    rng = np.random.default_rng(seed)
    bez = np.cumsum(rng.normal(size=(count, 4, 2)), axis=1)
    starts = np.concatenate([[0.0], np.cumsum(rng.uniform(0.5, 3.0, count - 1))])
    ends = np.append(starts[1:], starts[-1] + 1.0)
    u = np.concatenate([rng.uniform(-0.5, ends[-1] + 0.5, 40), starts, ends])
    seg = np.clip(np.searchsorted(starts, u, side="right") - 1, 0, count - 1)
    expected = _numpy_eval_bezier(bez, seg, (u - starts[seg]) / (ends - starts)[seg])
    got = _kernels.curve_points(bez, starts, ends, u)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_allclose(got[40:40 + count], bez[:, 0], atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 60), st.integers(0, 200), st.integers(0, 10_000), st.booleans(), st.booleans())
def test_search_sorted_is_numpys_searchsorted(size, count, seed, sorted_keys, right):
    """Same positions as ``numpy.searchsorted`` for sorted values with repeats, keys sorted or not, on and
    between the values and beyond both ends, NaN keys last."""
    rng = np.random.default_rng(seed)
    values = np.sort(rng.integers(0, 20, size) * 0.5)
    keys = rng.integers(-4, 46, count) * 0.25
    keys[rng.uniform(size=count) < 0.05] = np.nan
    if sorted_keys:
        keys = np.sort(keys)
    side = "right" if right else "left"
    np.testing.assert_array_equal(_kernels.search_sorted(values, keys, side), np.searchsorted(values, keys, side))


def test_kernels_are_compiled_with_an_on_disk_cache():
    """Every compiled loop is a numba dispatcher with ``cache=True`` (compiled once per machine, not per
    process), and every public kernel is a thin wrapper around one of them; the helpers that only compiled loops
    call (no Python wrapper) have no cache entry of their own: their callers' entries hold their code."""
    from numba.core.registry import CPUDispatcher

    from splinecraft.capture import _pixel_corners
    from splinecraft.capture.corners import _jump_kernels
    from splinecraft.capture.fitting import _iso_kernels

    expected = {_kernels: {"_normal_into", "_step_into", "_windowed_into", "_search_into", "_group_max_into"},
                _iso_kernels: {"_smoothed", "_nearest_into"},
                _jump_kernels: {"_window_fit", "_prefix_moments", "_moment_verdict", "_arm_lines_into", "_resample_into",
                                "_corners_into", "_peaks", "_starts_into", "_congruent", "_union_into", "_pairwise_sum"},
                _pixel_corners: {"_pixel_corners_into"}}
    for module, names in expected.items():
        loops = {name: value for name, value in vars(module).items() if isinstance(value, CPUDispatcher)}
        assert names <= set(loops), (module.__name__, sorted(loops))
        for loop in loops.values():
            assert loop.targetoptions.get("nogil") is True
            helper = loop.targetoptions.get("no_cpython_wrapper") is True
            assert loop._cache.__class__.__name__ == ("NullCache" if helper else "FunctionCache"), loop


@pytest.mark.parametrize("size", [1, 3])
def test_normal_equations_of_a_single_point_are_its_basis_products(size):
    """One point: band[k, a] = N_a N_(a+k) w and rhs = N w Q (closed form)."""
    full = bspline.periodic_knot_vector(np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]), 7.0)
    u = np.full(size, 3.5)
    band, rhs, _ = _kernels.normal_equations(full, u, np.full(size, 2.0), np.tile([[1.0, -1.0]], (size, 1)), 7)
    i = bspline.interval_index(full, u[:1])
    basis = bspline.cubic_basis(full, i, u[:1])[0]
    cols = (i[0] - 6 + np.arange(4)) % 7
    np.testing.assert_allclose(basis, [1 / 48, 23 / 48, 23 / 48, 1 / 48])  # uniform cubic B-spline at 1/2
    np.testing.assert_allclose(rhs[cols, 0], size * 2.0 * basis)
    np.testing.assert_allclose(band[1, cols[:3]], size * 2.0 * basis[:3] * basis[1:])


# ------------------------------------------------------------------------------ iso-line distance (noise)
def _random_mask(seed, shape):
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(seed)
    return gaussian_filter(rng.random(shape), 2.0) > 0.5


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 30), st.integers(1, 30), st.sampled_from([16, 64]))
def test_smoothed_values_are_those_of_gaussian_filter(seed, rows, cols, side):
    """Each lazily smoothed value is ``gaussian_filter(np.pad(mask, 4), 1.0)`` at that pixel, bit for bit
    (scipy's summation order; the reflection at the border reads the pad's zeros), read in a random order twice
    over, from caches small enough (side 16) that values displace each other and are computed again."""
    from scipy.ndimage import gaussian_filter

    from splinecraft.capture.fitting import _iso_kernels

    mask = _random_mask(seed, (rows, cols))
    expected = gaussian_filter(np.pad(mask.astype(float), 4), 1.0)
    weights = _iso_kernels.gaussian_weights(1.0)
    smooth, row_memo = np.empty((side, side)), np.empty((side, side))
    smooth_tag, row_tag = np.full((side, side), -1, np.int64), np.full((side, side), -1, np.int64)
    ink = np.zeros((expected.shape[0] + 8, expected.shape[1]), np.uint8)  # 4 more rows of 0 above and below
    ink[8:8 + rows, 4:4 + cols] = mask
    cells = list(np.ndindex(*expected.shape)) * 2
    smoothed = numba.njit(lambda *args: _iso_kernels._smoothed(*args))  # a helper: no Python wrapper of its own
    got = np.full(expected.shape, np.nan)
    for k in np.random.default_rng(seed).permutation(len(cells)):
        r, c = cells[k]
        value = smoothed(ink, weights, r, c, expected.shape[1], smooth, smooth_tag, row_memo, row_tag)
        assert np.isnan(got[r, c]) or value == got[r, c]
        got[r, c] = value
    np.testing.assert_array_equal(got, expected)


def _segment_distances(points, segments):
    """Brute force: every point to every segment ``x0, y0, x1, y1`` (the kernel's formula, vectorized)."""
    a, ab = segments[None, :, :2], segments[None, :, 2:] - segments[None, :, :2]
    ap = points[:, None, :] - a
    denom = ab[..., 0] * ab[..., 0] + ab[..., 1] * ab[..., 1]
    t = np.clip((ap[..., 0] * ab[..., 0] + ap[..., 1] * ab[..., 1]) / np.where(denom > 0, denom, 1.0), 0.0, 1.0)
    dx, dy = ap[..., 0] - t * ab[..., 0], ap[..., 1] - t * ab[..., 1]
    return np.sqrt(dx * dx + dy * dy).min(axis=1)


def _assert_nearest_edges_of_find_contours(got, points, mask):
    """``got`` is the distance from each point to the nearest segment of ``skimage.measure.find_contours`` at 0.5
    on ``gaussian_filter(np.pad(mask, 4), 1.0)`` (its polylines cut into edges, in the pixel frame
    ``x = column - 4 + 0.5``), bit for bit; ``None`` exactly when find_contours finds nothing."""
    from scipy.ndimage import gaussian_filter
    from skimage.measure import find_contours

    lines = find_contours(gaussian_filter(np.pad(mask.astype(float), 4), 1.0), 0.5)
    if not lines:
        assert got is None
        return
    segments = np.concatenate([np.column_stack([line[:-1, 1] - 4 + 0.5, line[:-1, 0] - 4 + 0.5,
                                                line[1:, 1] - 4 + 0.5, line[1:, 0] - 4 + 0.5]) for line in lines])
    np.testing.assert_array_equal(got, _segment_distances(points, segments))


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 40), st.integers(2, 40), st.sampled_from([16, 64]))
def test_iso_line_distance_is_the_nearest_edge_of_find_contours(seed, rows, cols, side):
    """The distance to the nearest segment of ``skimage.measure.find_contours`` on the smoothed, padded
    bitmap (its polylines cut into edges, in the pixel frame ``x = column - 4 + 0.5``), bit for bit, for points
    on and far off the boundaries, whatever the side of the kernel's caches (16: smaller than the padded image);
    ``None`` exactly when find_contours finds nothing."""
    from splinecraft.capture.fitting import _iso_kernels

    mask = _random_mask(seed, (rows, cols))
    rng = np.random.default_rng(seed + 1)
    points = rng.uniform(-6, max(rows, cols) + 6, size=(60, 2))
    got = _iso_kernels.iso_line_distance(points, mask, 1.0, 4, cache_side=side)
    _assert_nearest_edges_of_find_contours(got, points, mask)


def _crack_midpoints(mask):
    """The midpoints of every crack between an ink and a paper pixel of ``mask`` (outside is paper), in the
    pixel frame (``x = column + 0.5``): one integer and one half-integer coordinate."""
    padded = np.pad(mask, 1)
    rows, cols = np.nonzero(padded[1:, :] != padded[:-1, :])  # between padded rows r and r + 1: y = r
    across = np.nonzero(padded[:, 1:] != padded[:, :-1])  # between padded columns c and c + 1: x = c
    return np.concatenate([np.column_stack([cols - 1 + 0.5, rows.astype(float)]),
                           np.column_stack([across[1].astype(float), across[0] - 1 + 0.5])])


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 40), st.integers(2, 40))
def test_iso_line_distance_of_crack_midpoints_and_grid_points_is_the_nearest_edge(seed, rows, cols):
    """Crack midpoints (the trace's points: on a grid line of the smoothed values, where the ring search skips
    the cells no nearer than the nearest segment so far), pixel corners and pixel centres (exactly as far from
    several cells): the distance to the nearest segment of ``find_contours``, bit for bit."""
    from splinecraft.capture.fitting import _iso_kernels

    mask = _random_mask(seed, (rows, cols))
    grid = np.stack(np.meshgrid(np.arange(-2.0, cols + 3.0, 0.5), np.arange(-2.0, rows + 3.0, 0.5)), -1)
    points = np.concatenate([_crack_midpoints(mask), grid.reshape(-1, 2)])
    got = _iso_kernels.iso_line_distance(points, mask, 1.0, 4)
    _assert_nearest_edges_of_find_contours(got, points, mask)


def test_iso_line_distance_of_a_hairline_is_none_and_of_a_square_its_closed_form():
    """A 1-px line smoothed by a 1-px Gaussian never reaches 0.5 (no iso-line: ``None``); the iso-line of a
    large square passes through the middle of its edges, so a point on the crack outline there is at ~0."""
    from splinecraft.capture.fitting import _iso_kernels

    line = np.zeros((9, 40), bool)
    line[4, 2:38] = True
    assert _iso_kernels.iso_line_distance(np.array([[10.0, 4.5]]), line, 1.0, 4) is None
    square = np.zeros((40, 40), bool)
    square[10:30, 10:30] = True
    got = _iso_kernels.iso_line_distance(np.array([[20.0, 10.0], [20.0, 5.0]]), square, 1.0, 4)
    np.testing.assert_allclose(got, [0.0, 5.0], atol=1e-9)
    with pytest.raises(ValueError, match="pad"):
        _iso_kernels.iso_line_distance(np.array([[20.0, 10.0]]), square, 1.0, 3)
    for side in (8, 48):  # not above the 9 weights, not a power of two
        with pytest.raises(ValueError, match="cache_side"):
            _iso_kernels.iso_line_distance(np.array([[20.0, 10.0]]), square, 1.0, 4, cache_side=side)


# ------------------------------------------------------------------------------ tangent-jump's arm search
def _numpy_arm_fit(padded, starts, length, centred, slope_weights, tolerance):
    """The vectorized line fit of the windows of ``length`` samples at ``starts`` (the formulation the kernel
    replaced): sample-major block, running sums, squared-distance test with the ``hypot`` fallback."""
    arm = np.take(padded, np.arange(length)[:, None] + starts[None, :], axis=0)
    mean = arm.sum(axis=0) / length
    slope = np.einsum("l,lad->ad", slope_weights, arm)
    if tolerance is None:
        return mean, slope, None
    arm -= mean
    arm -= centred[:, None, None] * slope
    squared = np.square(arm)
    worst = (squared[..., 0] + squared[..., 1]).max(axis=0)
    limit = tolerance * tolerance
    with np.errstate(invalid="ignore"):
        straight = worst < limit * (1.0 - 1e-12)
        unsure = ~straight & ~(worst > limit * (1.0 + 1e-12))
        if unsure.any():
            straight[unsure] = np.hypot(arm[..., 0][:, unsure], arm[..., 1][:, unsure]).max(axis=0) <= tolerance
    return mean, slope, straight


def _numpy_arm_lines(padded, reach, ladder, operators, tolerance):
    """An arm whose longest window is straight is that window; the others grown rung by rung over all alive
    samples at once (each needed window fitted once per length)."""
    m = padded.shape[0] - 2 * reach
    alive = [np.arange(m), np.arange(m)]
    out = np.full((2, m, 4), np.nan)
    if len(ladder) > 1 and tolerance > 0:
        length = ladder[-1]
        centred, slope_weights = operators(length)
        for side in range(2):
            starts = alive[side] + (reach if side == 1 else reach - length + 1)
            mean, slope, straight = _numpy_arm_fit(padded, starts, length, centred, slope_weights, tolerance)
            out[side, alive[side][straight], :2], out[side, alive[side][straight], 2:] = mean[straight], slope[straight]
            alive[side] = alive[side][~straight]
    for rung, length in enumerate(ladder):
        centred, slope_weights = operators(length)
        first = [alive[0] + (reach - length + 1), alive[1] + reach]
        needed = np.zeros(len(padded) - length + 1, dtype=bool)
        for side in range(2):
            needed[first[side]] = True
        row_of_start = np.cumsum(needed) - 1
        mean, slope, straight = _numpy_arm_fit(padded, np.flatnonzero(needed), length, centred, slope_weights,
                                               tolerance if rung > 0 else None)
        for side in range(2):
            row = row_of_start[first[side]]
            if rung > 0:
                alive[side], row = alive[side][straight[row]], row[straight[row]]
            out[side, alive[side], :2], out[side, alive[side], 2:] = mean[row], slope[row]
    return out


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(8, 300), st.booleans(), st.sampled_from([0.05, 0.3, 1.0]))
def test_arm_lines_match_the_vectorized_formulation(seed, m, closed, tolerance):
    """Mean points and slopes of every sample's last straight arm on both sides, bit for bit those of the
    numpy formulation (NaN where an arm of an open curve runs off an end)."""
    rng = np.random.default_rng(seed)
    heading = np.cumsum(np.where(rng.uniform(size=m) < 0.1, rng.normal(0, 0.8, m), 0.0))
    curve = np.cumsum(np.column_stack([np.cos(heading), np.sin(heading)]), axis=0) + rng.normal(0, 0.1, (m, 2))
    _assert_arm_lines_match(curve, closed, tolerance)


def _assert_arm_lines_match(curve, closed, tolerance):
    """The kernel's arm lines of ``curve`` (its ladder up to 40 samples) equal the numpy formulation's."""
    from splinecraft.capture.corners import _jump, _jump_kernels

    m = len(curve)
    ladder = [length for length in _jump._ARM_LADDER if length <= 40 and 2 * length < m] or [3]
    reach = max(ladder)
    if closed:
        padded = curve[np.arange(-reach, m + reach) % m]
    else:
        padded = np.vstack([np.full((reach, 2), np.nan), curve, np.full((reach, 2), np.nan)])

    def operators(length):
        return _jump._arm_operators(length, 1)[1:]
    got = _jump_kernels.arm_lines(padded, reach, ladder, operators, tolerance)
    np.testing.assert_array_equal(got, _numpy_arm_lines(padded, reach, ladder, operators, tolerance))


def _near_tolerance_curve(seed, m, offset):
    """A random curve of ``m`` samples (runs of gently bent straight steps, 0.1 px noise, or 0.001 px noise and
    one sample 0.2-2 px off: nearly all of a window's squared distances in one sample) shifted by ``offset``, and
    a tolerance at the edge of one of its windows: the largest distance of a sample of a random window of a
    random ladder length from its least-squares line (scaled by ``1 +- 1e-13`` or so), or the root of the sum of
    the window's squared distances, where the moments' bound for straight windows sits."""
    rng = np.random.default_rng(seed)
    heading = np.cumsum(np.where(rng.uniform(size=m) < 0.1, rng.normal(0, 0.3, m), 0.0))
    spike = rng.uniform() < 0.5
    curve = np.cumsum(np.column_stack([np.cos(heading), np.sin(heading)]), axis=0) + \
        rng.normal(0, 0.001 if spike else 0.1, (m, 2))
    length = int(rng.choice([4, 8, 15, 24, 38]))
    start = int(rng.integers(0, m - length))
    if spike:
        curve[start + int(rng.integers(0, length))] += rng.uniform(0.2, 2.0) * rng.choice([-1.0, 1.0], 2)
    curve += offset
    window = curve[start:start + length]
    centred = np.arange(length) - (length - 1) / 2
    slope = centred @ (window - window.mean(axis=0)) / np.sum(centred ** 2)
    squared = np.sum((window - window.mean(axis=0) - centred[:, None] * slope) ** 2, axis=1)
    edge = np.sqrt(squared.max()) if rng.uniform() < 0.5 else np.sqrt(squared.sum())
    return curve, edge * (1.0 + rng.choice([-3e-13, -1e-15, 0.0, 1e-15, 3e-13, 1e-9]))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.integers(80, 240), st.booleans(), st.sampled_from([0.0, 1e3, -3e5, 2e7]))
def test_arm_lines_match_the_vectorized_formulation_at_the_tolerance(seed, m, closed, offset):
    """The arms' lines bit for bit those of the numpy formulation when the tolerance is at the edge of a window
    (its farthest sample's distance, or the root of its sum of squares, where the kernel's moment bounds give
    way to the scan) and on coordinates far from the origin (wider rounding margins)."""
    curve, tolerance = _near_tolerance_curve(seed, m, offset)
    _assert_arm_lines_match(curve, closed, tolerance)


_VERDICTS = []


def _verdicts():
    """A compiled loop over windows calling the arm search's moment bound and its scan (helpers without a
    Python entry of their own): per window, the bound's verdict (0 undecided, 1 straight, 2 not) and the scan's."""
    if not _VERDICTS:
        from splinecraft.capture.corners import _jump_kernels

        @numba.njit
        def verdicts(padded, starts, length, centred, weights, tolerance, amplitude):
            sums, nans = np.empty((padded.shape[0] + 1, 12)), np.empty(padded.shape[0] + 1, np.int64)
            spread = _jump_kernels._prefix_moments(padded, sums, nans)
            bounds, line, out = np.zeros(5), np.empty(4), np.empty((starts.shape[0], 2), np.int64)
            for k in range(starts.shape[0]):
                out[k, 0] = _jump_kernels._moment_verdict(sums, nans, starts[k], length, tolerance, amplitude,
                                                          spread, bounds)
                out[k, 1] = 1 if _jump_kernels._window_fit(padded, starts[k], length, centred, weights,
                                                           tolerance, line) else 2
            return out
        _VERDICTS.append(verdicts)
    return _VERDICTS[0]


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([0.0, 1e3, -3e5, 2e7, 1e12]))
def test_the_moment_bound_agrees_with_the_scan(seed, offset):
    """Where the second moments decide a window (straight or not) the full scan decides the same, on every window
    of a random curve at a tolerance at the edge of one of them, near the origin and far from it (up to 1e12,
    where a coordinate's rounding is 1e-4 px)."""
    from splinecraft.capture.corners import _jump

    curve, tolerance = _near_tolerance_curve(seed, 200, offset)
    length = int(np.random.default_rng(seed).choice([4, 8, 15, 24, 38]))
    centred, weights = _jump._arm_operators(length, 1)[1:]
    starts = np.arange(200 - length + 1)
    amplitude = float(np.abs(curve).max())
    got = _verdicts()(curve, starts, length, centred, weights, tolerance, amplitude)
    decided = got[:, 0] != 0
    np.testing.assert_array_equal(got[decided, 0], got[decided, 1])


def test_the_moment_bound_decides_clear_windows():
    """The bound is not vacuous: it finds every window of a nearly straight run straight and every window of a
    tight circle bent, without scanning them."""
    from splinecraft.capture.corners import _jump

    rng = np.random.default_rng(1)
    line = np.column_stack([np.arange(120.0), 0.5 * np.arange(120.0)]) + rng.normal(0, 0.01, (120, 2))
    angle = np.arange(120.0) / 3.0
    circle = 3.0 * np.column_stack([np.cos(angle), np.sin(angle)])
    for curve, verdict in ((line, 1), (circle, 2)):
        for length in (8, 15, 38):
            centred, weights = _jump._arm_operators(length, 1)[1:]
            got = _verdicts()(curve, np.arange(120 - length + 1), length, centred, weights, 0.3,
                              float(np.abs(curve).max()))
            assert (got == verdict).all()


def test_arm_ladder_tables_are_kept_per_ladder_and_function_up_to_a_bound(monkeypatch):
    """The offsets and weights of a ladder are formed once per ladder and operators function (read-only, the
    lines the same as with fresh tables), and no more than ``LADDER_TABLES_KEPT`` of them are kept."""
    from splinecraft.capture.corners import _jump, _jump_kernels

    monkeypatch.setattr(_jump_kernels, "_LADDER_TABLES", {})
    curve = np.column_stack([np.arange(40.0), 0.1 * np.sin(np.arange(40.0))])
    padded = curve[np.arange(-8, 48) % 40]
    first = _jump_kernels.arm_lines(padded, 8, [3, 4, 5, 6, 8], _jump._forward_operators, 0.3)
    assert len(_jump_kernels._LADDER_TABLES) == 1
    tables = _jump_kernels._LADDER_TABLES[((3, 4, 5, 6, 8), _jump._forward_operators)]
    assert not any(table.flags.writeable for table in tables)
    np.testing.assert_array_equal(_jump_kernels.arm_lines(padded, 8, [3, 4, 5, 6, 8], _jump._forward_operators,
                                                          0.3), first)
    for _ in range(_jump_kernels.LADDER_TABLES_KEPT + 5):   # a new function each time
        lines = _jump_kernels.arm_lines(padded, 8, [3, 4, 5, 6, 8], lambda length: _jump._forward_operators(length),
                                        0.3)
        np.testing.assert_array_equal(lines, first)
    assert len(_jump_kernels._LADDER_TABLES) == _jump_kernels.LADDER_TABLES_KEPT


def test_arm_lines_of_a_corner_are_its_two_sides():
    """An exact right angle (closed form): away from the corner the arms have grown to the longest length
    and point along the sides; at the corner the backward arm runs along +x and the forward arm along +y."""
    from splinecraft.capture.corners import _jump, _jump_kernels

    side = np.arange(60.0)
    curve = np.vstack([np.column_stack([side, np.zeros(60)]), np.column_stack([np.full(60, 60.0), side])])
    padded = np.vstack([np.full((38, 2), np.nan), curve, np.full((38, 2), np.nan)])
    ladder = [length for length in _jump._ARM_LADDER if length <= 38]
    lines = _jump_kernels.arm_lines(padded, 38, ladder, lambda length: _jump._arm_operators(length, 1)[1:], 0.3)
    np.testing.assert_allclose(lines[0, 60, 2:], [1.0, 0.0], atol=1e-12)   # arriving at (60, 0) along +x
    np.testing.assert_allclose(lines[1, 60, 2:], [0.0, 1.0], atol=1e-12)   # leaving it along +y
    np.testing.assert_allclose(lines[1, 10, :2], [10 + 18.5, 0.0], atol=1e-12)  # a 38-sample forward arm


def test_the_cache_goes_to_the_temporary_directory_when_nothing_else_is_writable(monkeypatch, tmp_path):
    """numba refuses ``cache=True`` at import when neither the package's ``__pycache__`` nor the user's cache
    folder can be written; ``_jit.ensure_cache_dir`` then gives it a folder of the temporary directory, and
    leaves numba's own rule alone otherwise."""
    import numba

    from splinecraft.capture import _jit

    monkeypatch.setattr(numba.config, "CACHE_DIR", "")
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    monkeypatch.setattr(_jit, "_writable", lambda folder: False)
    folder = _jit.ensure_cache_dir()
    assert folder is not None and folder.startswith(str(tmp_path)) and numba.config.CACHE_DIR == folder
    monkeypatch.setattr(numba.config, "CACHE_DIR", "")
    monkeypatch.setattr(_jit, "_writable", lambda folder: True)
    assert _jit.ensure_cache_dir() is None and numba.config.CACHE_DIR == ""
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path / "own"))
    assert _jit.ensure_cache_dir() is None and numba.config.CACHE_DIR == str(tmp_path / "own")
    assert _jit._writable(str(tmp_path / "new" / "folder")) or os.geteuid() != 0


def _numpy_group_max(groups, values, count):
    """Per group maximum, ``-inf`` when empty, NaN wins (``numpy.maximum.at``)."""
    best = np.full(count, -np.inf)
    np.maximum.at(best, groups, values)
    return best


def _numpy_deviations(model, dense, crack_outline=False):
    """The deviation check of an ``lsq`` fit state, vectorized with numpy's own searches, ``numpy.interp`` and
    the windowed distances above (the formulation :func:`_kernels.deviation_measures` replaced); ``crack_outline``:
    the contour is a tracer's crack outline, whose corner zones allow their extra tolerance on one side only."""
    contour = model.contour
    n, pieces = contour.size, contour.piece_count
    starts, ends = model.intervals()
    bez = model.bezier()
    k = starts.shape[0]
    spacing = min(model.sample_spacing, 0.25) if dense else model.sample_spacing
    samples, params, iv = _kernels.interval_samples(bez, starts, ends, spacing)
    corner_par = model.base_parameter[contour.corner_bounds]
    spiece = np.clip(np.searchsorted(corner_par, params, "right") - 1, 0, pieces - 1)
    centre = np.clip(np.searchsorted(model.parameter, params) - 1, 0, n - 1)
    bounds = contour.corner_bounds
    if contour.corner_count:
        d_curve, curve_side = _numpy_windowed(samples, centre, bounds[spiece] - 3, bounds[spiece + 1] + 2,
                                              contour.edges, 1, n, sides=True)
    else:
        d_curve, curve_side = _numpy_windowed(samples, centre, None, None, contour.edges, 1, n, sides=True)
    if dense:
        probes = np.empty((2 * n, 2))
        probes[0::2], probes[1::2] = contour.points, 0.5 * (contour.closed_points[:-1] + contour.closed_points[1:])
        probe_u = np.empty(2 * n)
        probe_u[0::2], probe_u[1::2] = model.parameter[:n], 0.5 * (model.parameter[:-1] + model.parameter[1:])
        probe_piece, is_point = np.repeat(contour.piece_of_point[:n], 2), np.tile([True, False], n)
    else:
        probes, probe_u, probe_piece, is_point = contour.points, model.parameter[:n], contour.piece_of_point[:n], \
            np.ones(n, bool)
    seg = np.clip(np.searchsorted(starts, probe_u, "right") - 1, 0, k - 1)
    theta = (probe_u - starts[seg]) / (ends - starts)[seg]
    curve = _numpy_eval_bezier(bez, seg, theta)
    # the curve's direction there (its derivative over 3), and the probe's side of it
    s1 = 1.0 - theta
    handles = np.diff(bez[seg], axis=1)
    tangent = np.einsum("nj,njd->nd", np.column_stack([s1 * s1, 2.0 * theta * s1, theta * theta]), handles)
    probe_side = tangent[:, 0] * (probes[:, 1] - curve[:, 1]) - tangent[:, 1] * (probes[:, 0] - curve[:, 0])
    d_data = np.hypot(*(curve - probes).T)
    loose = np.flatnonzero(d_data > (0.5 * model.epsilon if dense else model.epsilon))
    if loose.size:
        closed_samples = np.vstack([samples, bez[-1:, 3]])
        closed_params = np.append(params, model.period)
        lo = np.searchsorted(closed_params, corner_par[probe_piece[loose]])
        hi = np.maximum(np.searchsorted(closed_params, corner_par[probe_piece[loose] + 1], "right") - 2, lo)
        near_centre = np.clip(np.searchsorted(closed_params, probe_u[loose]), lo, hi)
        reach = int(np.ceil(3.0 / spacing))
        window = (lo - reach, hi + reach) if contour.corner_count else (None, None)
        near = _numpy_windowed(probes[loose], near_centre, *window, geometry.edge_table(closed_samples), reach,
                               closed_samples.shape[0] - 1)
        d_data[loose] = np.minimum(d_data[loose], near)
    zone, allowance = model.zone(), model.allowance()
    if dense:
        probe_allowance = np.empty(2 * n)
        probe_allowance[0::2], probe_allowance[1::2] = allowance[:n], np.maximum(allowance[:n], allowance[1:])
    else:
        probe_allowance = allowance[:n]
    curve_zone = np.interp(params, model.base_parameter, zone.astype(float)) > 0
    nearest = np.clip(np.searchsorted(model.base_parameter, params), 0, n)
    curve_allowance = np.maximum(allowance[nearest], allowance[np.maximum(nearest - 1, 0)])
    if crack_outline and contour.corner_count:
        # the allowance holds on the side of the corner's tip only: the paper beside a convex corner (a left turn
        # of the contour, whose ink is on its left), the ink beside a notch
        closed, corner_at = contour.closed_points, contour.corner_bounds[:-1]
        incoming = closed[corner_at] - closed[(corner_at - 3) % n]
        outgoing = closed[(corner_at + 3) % n] - closed[corner_at]
        convex = np.sign(incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0])
        point_side = convex[contour.nearest_corner]
        curve_allowance = np.where(curve_side * point_side[nearest] > 0, 0.0, curve_allowance)
        probe_sign = np.repeat(point_side[:n], 2) if dense else point_side[:n]
        probe_allowance = np.where(probe_side * probe_sign < 0, 0.0, probe_allowance)
    tol_data = model.epsilon + probe_allowance
    tol_curve = model.epsilon + np.where(curve_zone, curve_allowance, 0.0)
    data_iv = np.clip(np.searchsorted(ends, probe_u), 0, k - 1)
    ex_curve, ex_data = d_curve - tol_curve, d_data - tol_data
    gm = _numpy_group_max
    return {
        "excess": np.maximum(gm(iv, ex_curve, k), gm(data_iv, ex_data, k)),
        "piece_dev": np.maximum(np.maximum(gm(spiece, d_curve, pieces), gm(probe_piece, d_data, pieces)), 0.0),
        "piece_err": np.maximum(gm(probe_piece[is_point], d_data[is_point], pieces), 0.0),
        "piece_excess": np.maximum(gm(spiece, ex_curve, pieces), gm(probe_piece, ex_data, pieces)),
        "d_data": d_data, "tol_data": tol_data, "data_iv": data_iv, "d_curve": d_curve, "tol_curve": tol_curve,
        "curve_zone": curve_zone, "probe_u": probe_u, "curve_params": params, "curve_iv": iv,
    }


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.integers(0, 5), st.booleans(), st.floats(0.3, 2.0))
def test_deviation_measures_match_the_vectorized_formulation(seed, corners, dense, epsilon):
    """The one-pass deviation check of an ``lsq`` fit state (random staircase-noisy outlines with 0-5 corners,
    fitted, some corners released, a coarse fit so some probes are refined) equals the numpy formulation bit
    for bit."""
    from splinecraft.capture.fitting.lsq_model import OutlineRegression
    from splinecraft.capture.fitting.options import LSQ_DEFAULTS

    rng = np.random.default_rng(seed)
    n = int(rng.integers(60, 240))
    angle = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    radius = 30.0 * (1.0 + 0.3 * np.sin(3 * angle + rng.uniform(0, 6)))
    points = np.round(np.column_stack([radius * np.cos(angle), radius * np.sin(angle)]) * 2.0) / 2.0
    points = points[np.any(np.diff(points, axis=0, append=points[:1]) != 0, axis=1)]
    chosen = np.sort(rng.choice(points.shape[0], size=corners, replace=False)) if corners else np.zeros(0, int)
    chosen = chosen[np.diff(chosen, prepend=-100) > 8] if corners else chosen
    model = OutlineRegression(points, chosen.astype(np.int64), epsilon, dict(LSQ_DEFAULTS))
    model.seed_knots(float(rng.choice([0.0, LSQ_DEFAULTS["initial_density"]])))
    model.fit(hoschek_steps=int(rng.integers(0, 3)))
    if model.contour.corner_count and rng.random() < 0.5:
        model.tips.release(0)
        model.tips.allowance_kept[-1] = True
    got = model.deviations(dense=dense)
    expected = _numpy_deviations(model, dense)
    for key, value in expected.items():
        np.testing.assert_array_equal(got[key], value, err_msg=key)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 6), st.booleans(), st.floats(0.3, 2.0))
def test_deviation_measures_of_a_crack_outline_match_the_vectorized_formulation(seed, corners, dense, epsilon):
    """On a tracer's crack outline (a random polygon's render, corners at the polygon's vertices, a coarse fit)
    the corner zones' allowance holds only on the side of the corner's tip, and the one-pass check still equals
    the numpy formulation bit for bit."""
    from skimage.draw import polygon

    from splinecraft.capture.contour import trace_boundaries
    from splinecraft.capture.fitting.lsq_model import OutlineRegression
    from splinecraft.capture.fitting.options import LSQ_DEFAULTS

    rng = np.random.default_rng(seed)
    angle = np.sort(rng.uniform(0.0, 2 * np.pi, 7))
    radius = rng.uniform(12.0, 30.0, 7)
    vertices = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)]) + 40.0
    mask = np.zeros((80, 80), bool)
    mask[polygon(vertices[:, 1], vertices[:, 0], mask.shape)] = True
    points = max(trace_boundaries(mask), key=lambda b: b.outline.shape[0]).outline
    nearest = np.unique([np.argmin(np.hypot(*(points - v).T)) for v in vertices])
    chosen = np.sort(rng.choice(nearest, size=min(corners, nearest.size), replace=False))
    chosen = chosen[np.diff(chosen, prepend=-100) > 8]
    model = OutlineRegression(points, chosen.astype(np.int64), epsilon, dict(LSQ_DEFAULTS))
    model.seed_knots(float(rng.choice([0.0, LSQ_DEFAULTS["initial_density"]])))
    model.fit(hoschek_steps=int(rng.integers(0, 3)))
    if model.contour.corner_count and rng.random() < 0.5:
        model.tips.allowance_kept[-1] = True
    got = model.deviations(dense=dense)
    expected = _numpy_deviations(model, dense, crack_outline=True)
    for key, value in expected.items():
        np.testing.assert_array_equal(got[key], value, err_msg=key)


@pytest.mark.parametrize("m", [1, 2, 3, 7, 40])
def test_index_wraps_are_pythons_remainder(m):
    """The remainders of the deviation and normal-equation loops, by steps instead of an integer division
    (``_wrapped``, ``_next_index``: helpers without a Python wrapper, called through a kernel here), are Python's
    ``%`` on every index within three periods of ``[0, m)``."""
    wrapped = numba.njit(lambda e, count: _kernels._wrapped(e, count))
    following = numba.njit(lambda k, count: _kernels._next_index(k, count))
    for e in range(-3 * m, 4 * m):
        assert wrapped(e, m) == e % m
    for k in range(m):
        assert following(k, m) == (k + 1) % m


@pytest.mark.parametrize("seed", range(6))
def test_zone_points_beside_is_the_least_gap_above_the_slack(seed):
    """``zone_points_beside`` (the compiled zone test: each point stops at its first sample within the slack) says
    for every point whether ``numpy.min`` of the gaps ``hypot(along - clip(along, 0, 1), across)`` of its row's
    samples exceeds the slack, also at a slack equal to a point's least gap and one ulp below it."""
    rng = np.random.default_rng(seed)
    rows, count, points = int(rng.integers(1, 4)), int(rng.integers(1, 60)), int(rng.integers(1, 30))
    samples = rng.normal(0.0, 2.0, (rows, count, 2))
    row, axis = rng.integers(0, rows, points), rng.integers(0, 2, points)
    along_start, across_start = rng.normal(0.0, 1.0, points), rng.normal(0.0, 1.0, points)
    pick = np.arange(points)
    along = samples[row][pick, :, axis] - along_start[:, None]
    across = samples[row][pick, :, 1 - axis] - across_start[:, None]
    least = np.hypot(along - np.clip(along, 0.0, 1.0), across).min(axis=1)
    for slack in (0.05, 0.5, 2.0, float(least[0]), float(np.nextafter(least[0], -np.inf))):
        got = _kernels.zone_points_beside(samples, row, axis, along_start, across_start, slack)
        np.testing.assert_array_equal(got, least > slack)


@pytest.mark.parametrize("pairs", [_kernels.POLYLINE_PAIRS, 0])
@pytest.mark.parametrize("seed", range(8))
def test_closed_polyline_distance_matches_the_grid_formulation(seed, pairs, monkeypatch):
    """``closed_polyline_distance`` (the corner tips' distance from the contour in one pass) equals the grid it
    replaced bit for bit: squared distances to every vertex, the edges at the vertices within the nearest one's
    distance plus half the longest edge, their ``geometry.segment_squared_distances``, the least, its square root;
    on crack-like and random polylines (repeated points among them), for points near and far, on vertices and on
    edges. ``pairs`` 0: every point through the k-d tree's balls (used above ``POLYLINE_PAIRS``)."""
    monkeypatch.setattr(_kernels, "POLYLINE_PAIRS", pairs)
    rng = np.random.default_rng(seed)
    m = int(rng.integers(3, 200))
    if seed % 2:
        line = np.cumsum(rng.choice([-0.5, 0.0, 0.5], (m, 2)), axis=0)
    else:
        line = rng.normal(0.0, 10.0, (m, 2))
    points = np.vstack([rng.normal(0.0, 12.0, (5, 2)), line[rng.integers(0, m, 2)],
                        0.5 * (line[:2] + line[1:3])])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(np.vstack([line, line[:1]]), axis=0).T))])
    half = 0.5 * np.diff(arc).max()
    squared = (line[None, :, 0] - points[:, None, 0]) ** 2 + (line[None, :, 1] - points[:, None, 1]) ** 2
    reach = np.sqrt(squared.min(axis=1)) + half + 1e-6
    rows, near = np.nonzero(squared <= (reach * reach)[:, None])
    rows, edges = np.concatenate([rows, rows]), np.concatenate([near, (near - 1) % m])
    least = np.full(points.shape[0], np.inf)
    np.minimum.at(least, rows, geometry.segment_squared_distances(points[rows], line[edges], line[(edges + 1) % m]))
    np.testing.assert_array_equal(_kernels.closed_polyline_distance(points, line, half), np.sqrt(least))


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 8), st.integers(0, 10_000), st.booleans())
def test_hook_tests_are_the_curve_points_then_the_two_tests(count, seed, nan):
    """``hook_tests`` (both corner tests after a fit in one pass) against the formulation it replaced: the fitted
    corner points by ``curve_points``, ``hypot`` of their offsets against the limits where the radius is positive;
    the zone samples by ``curve_points``, the least gap of each point's row above the slack, a row with a NaN
    sample passing all its points."""
    rng = np.random.default_rng(seed)
    bounds = np.concatenate([[0.0], np.cumsum(rng.uniform(1.0, 10.0, count))])
    starts, ends = bounds[:-1], bounds[1:]
    bez = np.cumsum(rng.normal(size=(count, 4, 2)), axis=1)
    if nan:
        bez[rng.integers(0, count)] = np.nan
    corners = int(rng.integers(1, 5))
    at = rng.uniform(0, bounds[-1], corners)
    corner_points, limit = rng.normal(size=(corners, 2)), rng.uniform(0.0, 3.0, corners)
    radius = rng.uniform(-1.0, 2.0, corners) * (rng.random(corners) < 0.7)
    rows, per_row, points = int(rng.integers(1, 4)), int(rng.integers(1, 40)), int(rng.integers(1, 20))
    u = rng.uniform(0, bounds[-1], rows * per_row)
    row, axis = rng.integers(0, rows, points), rng.integers(0, 2, points)
    along_start, across_start = rng.normal(0.0, 1.0, points), rng.normal(0.0, 1.0, points)
    hooked, beside = _kernels.hook_tests(bez, starts, ends, at, corner_points, limit, radius, u, rows, row, axis,
                                         along_start, across_start, 0.5)
    disp = np.hypot(*(_kernels.curve_points(bez, starts, ends, at) - corner_points).T)
    np.testing.assert_array_equal(hooked, (disp > limit) & (radius > 0))
    samples = _kernels.curve_points(bez, starts, ends, u).reshape(rows, per_row, 2)
    pick = np.arange(points)
    along = samples[row][pick, :, axis] - along_start[:, None]
    across = samples[row][pick, :, 1 - axis] - across_start[:, None]
    least = np.hypot(along - np.clip(along, 0.0, 1.0), across).min(axis=1)
    np.testing.assert_array_equal(beside, (least > 0.5) & np.isfinite(samples).all(axis=(1, 2))[row])


def _numpy_zone_window(radius, exclude, nearest, corner_distance, corner_par, gap_before, gap_after, cracks, points,
                       period, spacing):
    """The zone window as numpy built it (the formulation ``zone_window`` replaced)."""
    active = radius > 0
    active[exclude] = False
    if not active.any():
        return None
    reach = np.maximum(radius, 1.0)
    chosen = np.flatnonzero(active[nearest] & (corner_distance < reach[nearest]))
    if not chosen.size:
        return None
    owner = nearest[chosen]
    tested = np.zeros(radius.shape[0], bool)
    tested[owner] = True
    corners = np.flatnonzero(tested)
    row = np.full(radius.shape[0], -1)
    row[corners] = np.arange(corners.shape[0])
    half = reach[corners] + np.maximum(gap_before[corners], gap_after[corners]) + 2.0
    count = int(np.ceil(2.0 * half.max() / spacing)) + 1
    steps = np.linspace(-1.0, 1.0, count)
    u = np.mod(corner_par[corners][:, None] + half[:, None] * steps[None, :], period).ravel()
    axis = (cracks[chosen, 1] == 1.0).astype(np.int64)
    own = points.take(chosen, axis=0)
    pick = np.arange(chosen.shape[0])
    return u, corners.shape[0], row[owner], axis, own[pick, axis] - 0.5, own[pick, 1 - axis], owner


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 6), st.integers(0, 10_000), st.sampled_from([0.1, 0.25, 0.37]), st.integers(0, 50))
def test_zone_window_matches_the_numpy_formulation(corners, seed, spacing, bound):
    """``zone_window`` (the zone test's set-up in one pass) bit for bit against the numpy formulation it replaced:
    the tested points, their rows, axes and pixel-centre coordinates, and the rows of curve parameters (numpy's
    ``linspace`` and ``mod`` arithmetic, around the period's end too), from any first guess of their count."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 80))
    period = float(n) + rng.uniform(0.0, 5.0)
    radius = rng.uniform(-0.5, 6.0, corners) * (rng.random(corners) < 0.8)
    exclude = np.flatnonzero(rng.random(corners) < 0.2)
    nearest = rng.integers(0, corners, n)
    corner_distance = rng.uniform(0.0, 8.0, n)
    corner_par = rng.uniform(0.0, period, corners)
    gap_before, gap_after = rng.uniform(0.0, 3.0, corners), rng.uniform(0.0, 3.0, corners)
    cracks = np.where((rng.random(n) < 0.5)[:, None], np.array([1.0, 0.0]), np.array([0.0, 1.0]))
    points = rng.integers(0, 40, (n, 2)) + 0.5 * rng.integers(0, 2, (n, 2))
    excluded = np.zeros(corners, bool)
    excluded[exclude] = True
    got = _kernels.zone_window(radius, excluded, nearest, corner_distance, corner_par, gap_before, gap_after,
                               cracks[:, 1], points, period, spacing, bound)
    expected = _numpy_zone_window(radius, exclude, nearest, corner_distance, corner_par, gap_before, gap_after,
                                  cracks, points, period, spacing)
    if expected is None:
        assert got is None
        return
    assert got[1] == expected[1]
    for a, b in zip(got[:1] + got[2:], expected[:1] + expected[2:]):
        np.testing.assert_array_equal(a, b)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 6), st.integers(0, 12), st.integers(0, 10_000), st.booleans())
def test_knot_vector_matches_the_numpy_formulation(corners, simple, seed, repeats):
    """``knot_vector`` (the fit's knots, full knot vector and intervals in one pass) against numpy: the sorted repeats
    of the corners (three times) and the simple knots (their multiplicities), ``knots[idx % m] + period *
    floor_divide(idx, m)`` and ``numpy.unique`` of the knots and the period."""
    rng = np.random.default_rng(seed)
    period = 100.0
    if corners + simple == 0:
        simple = 4
    grid = np.sort(rng.choice(np.arange(0.0, period, 0.5), corners + simple, replace=False))
    if repeats and simple > 1:  # a simple knot on a corner's value (both lists keep their order)
        grid[-1] = grid[0]
        grid = np.sort(grid)
    pick = rng.permutation(corners + simple)
    corner_values, values = np.sort(grid[pick[:corners]]), np.sort(grid[pick[corners:]])
    multiplicity = rng.integers(1, 3, values.shape[0])
    knots, full, starts, ends = _kernels.knot_vector(corner_values, values, multiplicity, period)
    expected = np.sort(np.concatenate([np.repeat(corner_values, 3), np.repeat(values, multiplicity)]))
    np.testing.assert_array_equal(knots, expected)
    m = expected.shape[0]
    idx = np.arange(-3, m + 4)
    np.testing.assert_array_equal(full, expected[idx % m] + period * np.floor_divide(idx, m))
    np.testing.assert_array_equal(bspline.periodic_knot_vector(expected, period), full)
    distinct = np.unique(np.append(expected, period))
    np.testing.assert_array_equal(starts, distinct[:-1])
    np.testing.assert_array_equal(ends, distinct[1:])


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 60), st.integers(0, 6), st.integers(0, 10_000))
def test_contour_tables_match_the_numpy_formulation(n, corners, seed):
    """``contour_tables`` (``RotatedContour``'s tables in one pass) bit for bit against the numpy formulation it
    replaced: the edge table, the arc lengths, each point's piece, nearest corner and distance to it (ties to
    the earlier corner; repeated points make zero-length edges)."""
    rng = np.random.default_rng(seed)
    points = rng.integers(0, 6, (n, 2)) * 0.5
    closed = np.vstack([points, points[:1]])
    chosen = np.unique(rng.integers(0, n, corners)).astype(np.int64)
    count = chosen.shape[0]
    bounds = np.append(chosen, n) if count else np.array([0, n])
    if count:
        bounds = np.append(chosen - chosen[0], n)
    edges, arc, piece_of, distance, nearest = _kernels.contour_tables(closed, bounds, count)
    dx, dy = np.diff(closed[:, 0]), np.diff(closed[:, 1])
    den = dx * dx + dy * dy
    np.testing.assert_array_equal(edges, np.stack([closed[:-1, 0], closed[:-1, 1], dx, dy,
                                                   1.0 / np.where(den > 0, den, 1.0)]))
    np.testing.assert_array_equal(geometry.edge_table(closed), edges)
    expected_arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    np.testing.assert_array_equal(arc, expected_arc)
    np.testing.assert_array_equal(piece_of, np.clip(np.searchsorted(bounds, np.arange(n + 1), side="right") - 1, 0,
                                                    bounds.shape[0] - 2))
    if count:
        corner_arc = expected_arc[bounds]
        k = np.clip(np.searchsorted(corner_arc, expected_arc), 1, corner_arc.shape[0] - 1)
        left, right = expected_arc - corner_arc[k - 1], corner_arc[k] - expected_arc
        np.testing.assert_array_equal(distance, np.minimum(left, right))
        np.testing.assert_array_equal(nearest, np.where(left <= right, k - 1, k) % count)
    else:
        assert np.isinf(distance).all() and not nearest.any()


def _numpy_corner_radii(contour, corner_radius):
    """``corner_radii`` as numpy computed it (the formulation the kernel replaced)."""
    arc, perimeter, bounds = contour.arc, contour.perimeter, contour.corner_bounds

    def point_at_arc(values):
        return np.column_stack([np.interp(values, arc, contour.closed_points[:, 0]),
                                np.interp(values, arc, contour.closed_points[:, 1])])
    corner_arc = arc[bounds[:-1]]
    piece_len = np.diff(arc[bounds])
    before = np.concatenate([piece_len[-1:], piece_len[:-1]])
    q_back = point_at_arc((corner_arc - np.minimum(6.0, 0.4 * before)) % perimeter)
    q_fwd = point_at_arc((corner_arc + np.minimum(6.0, 0.4 * piece_len)) % perimeter)
    corner = contour.points.take(bounds[:-1] % contour.size, axis=0)
    a, b = q_back - corner, q_fwd - corner
    cos = np.einsum("kd,kd->k", a, b) / np.maximum(np.hypot(*a.T) * np.hypot(*b.T), 1e-300)
    theta = np.arccos(np.clip(cos, -1.0, 1.0))
    radius = corner_radius / np.maximum(np.tan(0.5 * theta), 1e-6)
    radius = np.clip(radius, 1.0, 3.0 * corner_radius) if corner_radius > 0 else np.zeros(contour.corner_count)
    return np.minimum(radius, 0.2 * np.minimum(before, piece_len)), theta


@settings(max_examples=60, deadline=None)
@given(st.integers(6, 80), st.integers(1, 6), st.integers(0, 10_000), st.sampled_from([0.0, 0.7, 2.0]), st.booleans())
def test_corner_kernels_match_the_numpy_formulations(n, corners, seed, corner_radius, dense):
    """The per-corner and per-point tables of the model (``corner_radii``, ``corner_tables``, ``corner_weights``,
    ``anchor_bounds``, ``crack_normals``) bit for bit against the numpy formulations they replaced, on crack
    outlines with repeated points (zero-length edges) and random tip states."""
    from splinecraft.capture.fitting.lsq_setup import RotatedContour

    rng = np.random.default_rng(seed)
    steps = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [0.0, 0.0]])
    points = np.cumsum(steps[rng.integers(0, 5, n)], axis=0) + np.array([0.0, 0.5])
    chosen = np.unique(rng.integers(0, n, corners)).astype(np.int64)
    contour = RotatedContour(points, chosen)
    count = contour.corner_count
    radius, theta = _kernels.corner_radii(contour.arc, contour.closed_points, contour.corner_bounds, corner_radius)
    expected_radius, expected_theta = _numpy_corner_radii(contour, corner_radius)
    np.testing.assert_array_equal(theta, expected_theta)
    np.testing.assert_array_equal(radius, expected_radius)
    zone_radius = rng.uniform(0.0, 4.0, count) * (rng.random(count) < 0.8)
    tip_radius = zone_radius * (rng.random(count) < 0.6)
    kept, tip_allowance = rng.random(count) < 0.3, rng.uniform(0.0, 1.0, count)
    nearest, distance = contour.nearest_corner, contour.corner_distance
    r = zone_radius[nearest]
    zone = (r > 0) & ((tip_radius > 0) | kept)[nearest] & (distance < 2.0 * r + 1.0)
    allowance = np.where(zone, tip_allowance[nearest], 0.0)
    got = _kernels.corner_tables(zone_radius, tip_radius, kept, tip_allowance, nearest, distance, dense)
    np.testing.assert_array_equal(got[0], zone.astype(float))
    np.testing.assert_array_equal(got[1], allowance)
    if dense:
        probe_zone, probe_allowance = np.empty(2 * n, bool), np.empty(2 * n)
        probe_zone[0::2], probe_zone[1::2] = zone[:n], zone[:n] | zone[1:]
        probe_allowance[0::2], probe_allowance[1::2] = allowance[:n], np.maximum(allowance[:n], allowance[1:])
    else:
        probe_zone, probe_allowance = zone[:n], allowance[:n]
    np.testing.assert_array_equal(got[2], probe_zone)
    np.testing.assert_array_equal(got[3], probe_allowance)
    fixed = rng.random(n + 1) < 0.2
    r = tip_radius[nearest]
    x = distance / np.where(r > 0, r, 1.0)
    w = np.where(r > 0, np.minimum(1.0, x ** 2), 1.0)
    w[fixed & (r > 0)] = 0.0
    np.testing.assert_array_equal(_kernels.corner_weights(tip_radius, nearest[:n], distance[:n], fixed[:n]),
                                  np.maximum(w[:n], 1e-3))
    anchor = np.append(fixed[:n], True)
    base = np.sort(rng.uniform(0.0, 50.0, n + 1))
    index = np.arange(n + 1)
    before = np.maximum.accumulate(np.where(anchor, index, 0))
    after = np.minimum.accumulate(np.where(anchor, index, n)[::-1])[::-1]
    low, high = _kernels.anchor_bounds(fixed[:n], base)
    np.testing.assert_array_equal(low, base[before[:n]])
    np.testing.assert_array_equal(high, base[after[:n]])
    frac = points - np.floor(points)
    whole, half = (frac < 1e-9) | (frac > 1.0 - 1e-9), np.abs(frac - 0.5) < 1e-9
    vertical, horizontal = whole[:, 0] & half[:, 1], half[:, 0] & whole[:, 1]
    normals = _kernels.crack_normals(points)
    if not (vertical | horizontal).all():
        assert normals is None
    else:
        np.testing.assert_array_equal(normals, np.where(vertical[:, None], [1.0, 0.0], [0.0, 1.0]))
    moved = points.copy()
    moved[:, 1] -= 0.5  # pixel corners, not crack midpoints
    assert _kernels.crack_normals(moved) is None


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 6), st.integers(0, 10_000))
def test_interval_worst_is_group_max_of_the_masked_excesses(count, seed):
    """``interval_worst`` (the four per-interval maxima of knot insertion in one pass) against ``group_max`` of the
    excesses masked by the corner zones (``numpy.where``), NaN excesses and empty intervals included."""
    rng = np.random.default_rng(seed)
    data_iv, curve_iv = np.sort(rng.integers(0, count, 30)), np.sort(rng.integers(0, count, 50))
    data_zone, curve_zone = rng.random(30) < 0.3, rng.random(50) < 0.3
    d_data, tol_data = rng.uniform(0.0, 2.0, 30), rng.uniform(0.5, 1.0, 30)
    d_curve, tol_curve = rng.uniform(0.0, 2.0, 50), rng.uniform(0.5, 1.0, 50)
    d_data[rng.random(30) < 0.05] = np.nan
    best, at = _kernels.interval_worst(data_iv, data_zone, d_data, tol_data, curve_iv, curve_zone, d_curve, tol_curve,
                                       count)
    data_ex, curve_ex = d_data - tol_data, d_curve - tol_curve
    expected = [geometry.group_max(data_iv, np.where(data_zone, -np.inf, data_ex), count),
                geometry.group_max(curve_iv, np.where(curve_zone, -np.inf, curve_ex), count),
                geometry.group_max(data_iv, np.where(data_zone, data_ex, -np.inf), count),
                geometry.group_max(curve_iv, np.where(curve_zone, curve_ex, -np.inf), count)]
    for row, (value, index) in enumerate(expected):
        np.testing.assert_array_equal(best[row], value)
        np.testing.assert_array_equal(at[row], index)
        np.testing.assert_array_equal(value, _numpy_group_max([data_iv, curve_iv][row % 2],
                                                              np.where([data_zone, curve_zone][row % 2] == (row < 2),
                                                                       -np.inf, [data_ex, curve_ex][row % 2]), count))


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 12), st.integers(0, 10_000), st.booleans())
def test_removal_scores_match_the_numpy_formulation(count, seed, bend):
    """``removal_scores`` (knot removal's scores in one pass) bit for bit against the numpy formulation it
    replaced, with and without the second derivative's jump (C1 knots)."""
    rng = np.random.default_rng(seed)
    bounds = np.concatenate([[0.0], np.cumsum(rng.uniform(0.5, 10.0, count))])
    starts, ends = bounds[:-1], bounds[1:]
    bezier = np.cumsum(rng.normal(size=(count, 4, 2)), axis=1)
    values = starts[np.sort(rng.choice(count, int(rng.integers(1, count + 1)), replace=False))]
    h = ends - starts
    third = 6.0 * (bezier[:, 3] - 3 * bezier[:, 2] + 3 * bezier[:, 1] - bezier[:, 0]) / (h[:, None] ** 3)
    right = np.clip(np.searchsorted(starts, values), 0, starts.shape[0] - 1)
    left = (right - 1) % starts.shape[0]
    jump = np.hypot(*(third.take(right, axis=0) - third.take(left, axis=0)).T)
    span = 0.5 * (h[left] + h[right])
    expected = jump * span**3 / 48.0
    if bend:
        second_start = 6.0 * (bezier[:, 2] - 2 * bezier[:, 1] + bezier[:, 0]) / (h[:, None] ** 2)
        second_end = 6.0 * (bezier[:, 3] - 2 * bezier[:, 2] + bezier[:, 1]) / (h[:, None] ** 2)
        expected = np.hypot(*(second_start[right] - second_end[left]).T) * span**2 / 16.0 + expected
    np.testing.assert_array_equal(_kernels.removal_scores(bezier, starts, ends, values, bend), expected)
