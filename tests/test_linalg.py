"""``fitting._linalg``: numpy's LAPACK solve and singular value decomposition without their wrappers, pinned bit
for bit to ``numpy.linalg.solve`` and ``numpy.linalg.svd`` (and to their errors)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from splinecraft.capture.fitting._linalg import solve, svd_direction, svd_directions

_FINITE = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 12).flatmap(lambda m: st.tuples(arrays(np.float64, (m, m), elements=_FINITE),
                                                      arrays(np.float64, (m, 2), elements=_FINITE))))
def test_solve_is_numpys(system):
    a, b = system
    a = a + np.diag(np.abs(a).sum(axis=1) + 1.0)  # diagonally dominant: regular
    assert solve(a, b).tobytes() == np.linalg.solve(a, b).tobytes()


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 6).flatmap(lambda r: st.tuples(arrays(np.float64, (r, 3, 3), elements=_FINITE),
                                                     arrays(np.float64, (r, 3, 1), elements=_FINITE))))
def test_stacked_solve_is_numpys(system):
    a, b = system
    a = a + 10.0 * np.eye(3) * (np.abs(a).sum(axis=2, keepdims=True) + 1.0)
    assert solve(a, b).tobytes() == np.linalg.solve(a, b).tobytes()


def test_singular_solve_raises_as_numpy():
    a, b = np.ones((3, 3)), np.ones((3, 2))
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.solve(a, b)
    with pytest.raises(np.linalg.LinAlgError):
        solve(a, b)


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 60).flatmap(lambda n: arrays(np.float64, (n, 2), elements=_FINITE)))
def test_svd_direction_is_numpys(points):
    local = points - points.mean(axis=0)
    assert svd_direction(local).tobytes() == np.linalg.svd(local, full_matrices=False)[2][0].tobytes()


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 5).flatmap(lambda k: st.integers(1, 100).flatmap(
    lambda n: arrays(np.float64, (k, n, 2), elements=_FINITE))))
def test_stacked_svd_directions_are_each_matrixs(stack):
    """One call for a stack of windows of one length: each direction that of its matrix alone, bit for bit."""
    local = stack - stack.mean(axis=1, keepdims=True)
    got = svd_directions(local)
    assert got.shape == (stack.shape[0], 2)
    for window, direction in zip(local, got):
        assert direction.tobytes() == svd_direction(np.ascontiguousarray(window)).tobytes()


def test_svd_of_nan_raises_as_numpy():
    local = np.array([[np.nan, 1.0], [2.0, 3.0]])
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.svd(local, full_matrices=False)
    with pytest.raises(np.linalg.LinAlgError):
        svd_direction(local)


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 6).flatmap(lambda m: st.tuples(arrays(np.float64, (m, m), elements=_FINITE),
                                                     arrays(np.float64, (m,), elements=_FINITE))))
def test_solve_of_one_vector_is_numpys(system):
    a, b = system
    a = a + np.diag(np.abs(a).sum(axis=1) + 1.0)
    assert solve(a, b).shape == (a.shape[0],)
    assert solve(a, b).tobytes() == np.linalg.solve(a, b).tobytes()
