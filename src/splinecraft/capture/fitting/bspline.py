"""Periodic cubic B-spline numerics of the ``"lsq"`` fit (docs/capture.md §12, "The lsq method").

Knot vectors of a periodic cubic spline with multiple knots, the four non-zero basis functions at many
parameters at once (Cox-de Boor, compiled: :mod:`._kernels`), the banded cyclic normal equations of a weighted least-squares
fit (O(m) for any outline length) and the exact Bézier pieces of the spline on its knot intervals.
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import solveh_banded

from . import _kernels

__all__ = ["periodic_knot_vector", "interval_index", "cubic_basis", "fit_coefficients", "bezier_of_intervals"]


# Bézier control points from the values at theta = 0, 1/3, 2/3, 1 (inverse cubic Bernstein matrix).
_THETA4 = np.array([0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0])
_FROM_SAMPLES = np.linalg.inv(
    np.stack([(1 - _THETA4) ** 3, 3 * _THETA4 * (1 - _THETA4) ** 2, 3 * _THETA4**2 * (1 - _THETA4), _THETA4**3],
             axis=1)
)


def periodic_knot_vector(knots: np.ndarray, period: float) -> np.ndarray:
    """Full knot vector ``tau_{-3} .. tau_{M+3}`` (length ``M + 7``) of a periodic cubic spline whose knots in
    one period are ``knots = tau_0 .. tau_{M-1}`` in ``[0, period)`` (a repeated value is a multiple knot)."""
    m = knots.shape[0]
    idx = np.arange(-3, m + 4)
    return knots[idx % m] + period * np.floor_divide(idx, m)


def interval_index(full: np.ndarray, u: np.ndarray, side: str = "right") -> np.ndarray:
    """Index ``i`` into ``full`` with ``full[i] <= u < full[i + 1]`` and ``full[i] < full[i + 1]``
    (``side="left"``: ``full[i] < u <= full[i + 1]``, the interval ending at ``u``). Restricted to the
    period ``[full[3], full[-4]]``."""
    i = np.searchsorted(full, u, side=side) - 1
    return np.clip(i, 3, full.shape[0] - 5)


def cubic_basis(full: np.ndarray, i: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The four non-zero cubic B-splines ``N_{i-3} .. N_i`` at ``u`` (in interval ``i`` of ``full``), an
    ``(n, 4)`` array (Cox-de Boor, :func:`._kernels.basis_matrix`)."""
    return _kernels.basis_matrix(full, i, u)


def fit_coefficients(full: np.ndarray, u: np.ndarray, weights: np.ndarray, targets: np.ndarray, m: int,
                     regularization: float = 1e-8) -> np.ndarray:
    """Weighted least squares ``min sum_j w_j |sum_k N_k(u_j) c_k - Q_j|^2`` for the ``m`` periodic
    coefficients of the spline on the full knot vector ``full`` (two right-hand sides, x and y).

    The normal matrix is cyclic with band 3 (assembled in one pass over the points,
    :func:`._kernels.normal_equations`). A tiny second-difference penalty keeps it positive definite
    when a coefficient is barely constrained. Solved as a symmetric banded system (LAPACK ``pbsv``) after
    cutting the cyclic coupling with a Schur complement on the last three coefficients, so the cost is
    O(m) for any outline length.
    """
    band, rhs = _kernels.normal_equations(full, u, weights, targets, m)
    # + pen * D^T D (D the cyclic second difference), and below 65 coefficients the dense cyclic matrix
    normal = _kernels.penalized_normal(band, regularization, m <= 64)
    if normal is not None:
        return np.linalg.solve(normal, rhs)
    return _solve_cyclic_band(band, rhs)


def _solve_cyclic_band(band, rhs):
    """Solve the symmetric cyclic matrix with upper band ``band[k, a] = A[a, (a + k) % m]`` (k <= 3)."""
    m = band.shape[1]
    w = 3
    # split unknowns: x = [y (m - w), z (w)]; A = [[B, C], [C^T, D]] with B banded (non-cyclic part)
    nb = m - w
    ab = np.zeros((4, nb))  # upper form for solveh_banded: ab[3 - k, j] = B[j - k, j]
    for k in range(4):
        ab[3 - k, k:] = band[k, : nb - k]
    C = np.zeros((nb, w))
    Dm = np.zeros((w, w))
    for k in range(4):
        for a in range(nb - 3, m):
            b = (a + k) % m
            if k == 0 and a >= nb:
                Dm[a - nb, a - nb] += band[0, a]
                continue
            val = band[k, a]
            if val == 0.0 or k == 0:
                continue
            ia, ib = a, b
            if ia < nb and ib < nb:
                continue  # inside B (already stored when b = a + k without wrap)
            if ia >= nb and ib >= nb:
                Dm[ia - nb, ib - nb] += val
                Dm[ib - nb, ia - nb] += val
            elif ia < nb:
                C[ia, ib - nb] += val
            else:
                C[ib, ia - nb] += val
    # B entries that wrapped are none (B is the leading block without wrap); band entries with a < nb,
    # b = a + k < nb are in ab; those with a + k >= m wrap to b < a: handled above (ib < nb, ia >= nb or not)
    rhs_y, rhs_z = rhs[:nb], rhs[nb:]
    sol = solveh_banded(ab, np.hstack([rhs_y, C]), check_finite=False)
    By, BC = sol[:, : rhs.shape[1]], sol[:, rhs.shape[1]:]
    schur = Dm - C.T @ BC
    z = np.linalg.solve(schur, rhs_z - C.T @ By)
    y = By - BC @ z
    return np.vstack([y, z])


def bezier_of_intervals(coef: np.ndarray, full: np.ndarray, m: int, starts: np.ndarray, ends: np.ndarray):
    """Exact Bézier control points (k, 4, 2) of the spline on its knot intervals ``[starts, ends]`` (from its
    values at theta = 0, 1/3, 2/3, 1 times the inverse Bernstein matrix, :func:`._kernels.spline_values`)."""
    return _kernels.spline_values(coef, full, m, starts, ends, _THETA4, _FROM_SAMPLES)
