"""numpy's LAPACK solve and singular value decomposition for the fit's small float64 systems, without the
wrappers' per-call conversions (docs/capture.md §12, "The lsq method").

:func:`numpy.linalg.solve` and :func:`numpy.linalg.svd` check and convert their arguments (``_makearray``, the
common type, ``astype`` and ``wrap`` of every result, a named tuple) around one call of a generalized ufunc of
``numpy.linalg._umath_linalg``. The fit calls them some 25 times a 300-px glyph on arrays that are float64
already (the dense normal equations of every fit, the frame of every corner side's window, the merge's
parabolas), where that work was 7-10 us of the 12-19 us of a call. :func:`solve` and :func:`svd_direction`
call the same ufunc under the same floating-point error state (a singular matrix or an SVD that does not
converge raises ``LinAlgError`` as numpy's does): the same LAPACK call, so the same bits. Where this numpy has
no such ufunc (a private module), they are numpy's own functions.
"""
from __future__ import annotations

import numpy as np

__all__ = ["solve", "svd_direction", "svd_directions"]

try:
    from numpy.linalg import _umath_linalg
    try:
        from numpy.linalg._linalg import _raise_linalgerror_singular, _raise_linalgerror_svd_nonconvergence
    except ImportError:  # numpy < 2
        from numpy.linalg.linalg import _raise_linalgerror_singular, _raise_linalgerror_svd_nonconvergence
    _SOLVE, _SOLVE1, _SVD = _umath_linalg.solve, _umath_linalg.solve1, _umath_linalg.svd_s
except (ImportError, AttributeError):  # pragma: no cover - another numpy's layout: its own functions
    _SOLVE = _SOLVE1 = _SVD = None


def solve(a, b):
    """``numpy.linalg.solve(a, b)`` of float64 matrices ``a`` (..., m, m) and float64 right-hand sides ``b``
    (..., m, k), or of one matrix ``a`` (m, m) and one right-hand side ``b`` (m,): LAPACK ``gesv`` through numpy's
    ufunc, bit for bit; ``LinAlgError`` on a singular ``a``."""
    if _SOLVE is None:  # pragma: no cover
        return np.linalg.solve(a, b)
    with np.errstate(call=_raise_linalgerror_singular, invalid="call", over="ignore", divide="ignore",
                     under="ignore"):
        return (_SOLVE1 if b.ndim == 1 else _SOLVE)(a, b, signature="dd->d")


def svd_direction(a):
    """``numpy.linalg.svd(a, full_matrices=False)[2][0]`` of a float64 matrix ``a`` (n, 2), n >= 1: its first
    right singular vector (LAPACK ``gesdd`` through numpy's ufunc, bit for bit); ``LinAlgError`` where the
    decomposition does not converge."""
    if _SVD is None:  # pragma: no cover
        return np.linalg.svd(a, full_matrices=False)[2][0]
    with np.errstate(call=_raise_linalgerror_svd_nonconvergence, invalid="call", over="ignore", divide="ignore",
                     under="ignore"):
        return _SVD(a, signature="d->ddd")[2][0]


def svd_directions(stack):
    """:func:`svd_direction` of each matrix of a float64 stack (k, n, 2), n >= 1, in one call of numpy's ufunc (its
    loop runs LAPACK ``gesdd`` on each matrix as one call would: the same bits); (k, 2)."""
    if _SVD is None:  # pragma: no cover
        return np.linalg.svd(stack, full_matrices=False)[2][:, 0]
    with np.errstate(call=_raise_linalgerror_svd_nonconvergence, invalid="call", over="ignore", divide="ignore",
                     under="ignore"):
        return _SVD(stack, signature="d->ddd")[2][:, 0]
