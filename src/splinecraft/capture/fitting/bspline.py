"""Periodic cubic B-spline numerics of the ``"lsq"`` fit (docs/capture.md §12, "The lsq method").

Knot vectors of a periodic cubic spline with multiple knots, the four non-zero basis functions at many
parameters at once (Cox-de Boor, compiled: :mod:`._kernels`), the banded cyclic normal equations of a weighted least-squares
fit (O(m) for any outline length) and the exact Bézier pieces of the spline on its knot intervals.
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import LinAlgError
from scipy.linalg.lapack import dpbsv

from . import _kernels
from ._linalg import solve

__all__ = ["periodic_knot_vector", "interval_index", "cubic_basis", "fit_coefficients", "bezier_of_intervals"]


# Bézier control points from the values at theta = 0, 1/3, 2/3, 1 (inverse cubic Bernstein matrix).
_THETA4 = np.array([0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0])
_FROM_SAMPLES = np.linalg.inv(
    np.stack([(1 - _THETA4) ** 3, 3 * _THETA4 * (1 - _THETA4) ** 2, 3 * _THETA4**2 * (1 - _THETA4), _THETA4**3],
             axis=1)
)


def periodic_knot_vector(knots: np.ndarray, period: float) -> np.ndarray:
    """Full knot vector ``tau_{-3} .. tau_{M+3}`` (length ``M + 7``) of a periodic cubic spline whose knots in
    one period are ``knots = tau_0 .. tau_{M-1}`` in ``[0, period)``, sorted (a repeated value is a multiple knot):
    ``knots[idx % M] + period * floor_divide(idx, M)`` (:func:`._kernels.knot_vector`)."""
    knots = np.asarray(knots, dtype=np.float64)
    return _kernels.knot_vector(_kernels._NO_FLOATS, knots, np.ones(knots.shape[0], np.int64), period)[1]


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
                     regularization: float = 1e-8, extra: np.ndarray = _kernels._NO_FLOATS, work=None) -> np.ndarray:
    """Weighted least squares ``min sum_j w_j |sum_k N_k(u_j) c_k - Q_j|^2`` for the ``m`` periodic
    coefficients of the spline on the full knot vector ``full`` (two right-hand sides, x and y), the points at
    the parameters ``u`` and then ``extra`` (rows of ``weights`` and ``targets`` in that order).

    The normal matrix is cyclic with band 3 (assembled in one pass over the points,
    :func:`._kernels.normal_equations`, into the arrays ``work`` where given: :func:`._kernels.normal_work`). A
    tiny second-difference penalty keeps it positive definite when a coefficient is barely constrained. Up to
    :data:`._kernels.DENSE_LIMIT` coefficients solved as a dense matrix (LAPACK ``gesv``), above that as a
    symmetric banded system (LAPACK ``pbsv``) after cutting the cyclic coupling with a Schur complement on the
    last three coefficients, so the cost is O(m) for any outline length.
    """
    # + pen * D^T D (D the cyclic second difference), and up to DENSE_LIMIT coefficients the dense cyclic matrix
    band, rhs, normal = _kernels.normal_equations(full, u, weights, targets, m, regularization, extra, work)
    if normal is not None:
        return solve(normal, rhs)
    return _solve_cyclic_band(band, rhs)


def _cyclic_coupling(m):
    """Where the band entries of the cyclic coupling go (:func:`_solve_cyclic_band`), for ``m`` unknowns split
    as ``[y (m - 3), z (3)]``: per contribution its band row and column and its place in one flat buffer, ``[D
    (3 x 3) | C ((m - 3) x 3)]``, in the order of the loop over rows ``k`` then columns ``a`` (repeated places
    are added in that order by ``numpy.add.at``). Depends on ``m`` only: kept per ``m``."""
    if m not in _COUPLING:
        w, nb = 3, m - 3
        rows, columns, places = [], [], []
        for k in range(4):
            for a in range(nb - 3, m):
                b = (a + k) % m
                if k == 0:
                    if a >= nb:  # D's diagonal
                        rows.append(k), columns.append(a), places.append((a - nb) * w + (a - nb))
                    continue
                if a < nb and b < nb:
                    continue  # inside B (already stored when b = a + k without wrap)
                if a >= nb and b >= nb:
                    rows += [k, k]
                    columns += [a, a]
                    places += [(a - nb) * w + (b - nb), (b - nb) * w + (a - nb)]
                elif a < nb:
                    rows.append(k), columns.append(a), places.append(w * w + a * w + (b - nb))
                else:
                    rows.append(k), columns.append(a), places.append(w * w + b * w + (a - nb))
        _COUPLING[m] = (np.array(rows, dtype=np.intp), np.array(columns, dtype=np.intp),
                        np.array(places, dtype=np.intp))
    return _COUPLING[m]


_COUPLING = {}


def _solve_cyclic_band(band, rhs):
    """Solve the symmetric cyclic matrix with upper band ``band[k, a] = A[a, (a + k) % m]`` (k <= 3)."""
    m = band.shape[1]
    w = 3
    # split unknowns: x = [y (m - w), z (w)]; A = [[B, C], [C^T, D]] with B banded (non-cyclic part)
    nb = m - w
    ab = np.zeros((4, nb))  # upper form for pbsv (scipy's solveh_banded): ab[3 - k, j] = B[j - k, j]
    for k in range(4):
        ab[3 - k, k:] = band[k, : nb - k]
    # the entries of B that wrapped are none (B is the leading block without wrap); band entries with a < nb,
    # b = a + k < nb are in ab; those with a + k >= m wrap to b < a (:func:`_cyclic_coupling`). Each lands
    # in D or C by one in-order addition onto zeros (a zero entry adds nothing)
    rows, columns, places = _cyclic_coupling(m)
    coupling = np.zeros(w * w + nb * w)
    np.add.at(coupling, places, band[rows, columns])
    Dm, C = coupling[: w * w].reshape(w, w), coupling[w * w:].reshape(nb, w)
    rhs_y, rhs_z = rhs[:nb], rhs[nb:]
    # scipy.linalg.solveh_banded(ab, ..., check_finite=False) is this LAPACK call (pbsv of float64), less its set-up
    _, sol, info = dpbsv(ab, np.hstack([rhs_y, C]), lower=0, overwrite_ab=0, overwrite_b=0)
    if info > 0:
        raise LinAlgError(f"{info}th leading minor not positive definite")
    if info < 0:
        raise ValueError(f"illegal value in {-info}th argument of internal pbsv")
    By, BC = sol[:, : rhs.shape[1]], sol[:, rhs.shape[1]:]
    schur = Dm - C.T @ BC
    z = np.linalg.solve(schur, rhs_z - C.T @ By)
    y = By - BC @ z
    return np.vstack([y, z])


def bezier_of_intervals(coef: np.ndarray, full: np.ndarray, m: int, starts: np.ndarray, ends: np.ndarray):
    """Exact Bézier control points (k, 4, 2) of the spline on its knot intervals ``[starts, ends]`` (from its
    values at theta = 0, 1/3, 2/3, 1 times the inverse Bernstein matrix, :func:`._kernels.spline_values`)."""
    return _kernels.spline_values(coef, full, m, starts, ends, _THETA4, _FROM_SAMPLES)
