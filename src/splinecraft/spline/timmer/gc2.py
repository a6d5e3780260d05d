"""Algorithm 3.3: the "GC2" piecewise Timmer curve with shape control (§5.6, errata E19, E20)."""
from __future__ import annotations

import numpy as np
from scipy.linalg import lapack, solve_banded

from ..._validation import as_float_array, check_bool, check_choice
from ..piecewise import Spline
from ..tangents import estimate_tangents
from .pieces import _RCOND_MIN, _make_spline, _matching_labels, _segment_values, scaled_points

# ----------------------------------------------------------------------------------------------------------
# Algorithm 3.3: "GC2" with shape control
# ----------------------------------------------------------------------------------------------------------
def _interleave(count: int) -> np.ndarray:
    """Order ``0, n-1, 1, n-2, 2, ...``: makes a cyclic tridiagonal matrix pentadiagonal (bandwidth 2)."""
    order = np.empty(count, dtype=int)
    order[0::2] = np.arange((count + 1) // 2)
    order[1::2] = count - 1 - np.arange(count // 2)
    return order


def _band_rcond(band: np.ndarray, lower: int, upper: int) -> float:
    """Reciprocal 1-norm condition number of a banded matrix (LAPACK dgbtrf + dgbcon)."""
    count = band.shape[1]
    storage = np.zeros((2 * lower + upper + 1, count))
    storage[lower:] = band
    lu, pivots, info = lapack.dgbtrf(storage, lower, upper)
    if info > 0:
        return 0.0
    # 1-norm of the matrix: the largest column sum of the band
    anorm = float(np.max(np.abs(band).sum(axis=0)))
    rcond, info = lapack.dgbcon(lower, upper, lu, pivots, anorm)
    return float(rcond)


def _solve_tridiagonal(lower, diag, upper, rhs, cyclic: bool):
    """Solve ``lower[k] x[k-1] + diag[k] x[k] + upper[k] x[k+1] = rhs[k]`` (indices mod n when cyclic).

    One ``scipy.linalg.solve_banded`` call with all right-hand-side columns: bandwidth (1, 1) for an open
    chain; a cyclic system is reordered by :func:`_interleave` into bandwidth (2, 2). Returns the solution
    and ``rcond`` (``None`` when every row is strictly diagonally dominant with a margin that bounds the
    condition number below 1e12; then no estimate is needed). Raises ``ValueError`` if singular or
    ill-conditioned.
    """
    count = diag.shape[0]
    off = np.abs(lower) + np.abs(upper)
    margin = np.abs(diag) - off
    dominant = bool(np.all(margin > 0.0))
    if dominant:
        # ||A||_inf * ||A^-1||_inf <= max row sum / min margin
        bound = float(np.max(np.abs(diag) + off) / np.min(margin))
        dominant = bound < 1.0 / _RCOND_MIN
    if cyclic:
        order = _interleave(count)
        position = np.empty(count, dtype=int)
        position[order] = np.arange(count)
        lower_bw = upper_bw = 2
        rows = position[np.arange(count)]
        band = np.zeros((5, count))
        for offset, values in ((-1, lower), (0, diag), (1, upper)):
            cols = position[(np.arange(count) + offset) % count]
            np.add.at(band, (upper_bw + rows - cols, cols), values)
        rhs_perm = rhs[order]
    else:
        lower_bw = upper_bw = 1
        band = np.zeros((3, count))
        band[0, 1:] = upper[:-1]
        band[1] = diag
        band[2, :-1] = lower[1:]
        rhs_perm = rhs
    rcond = None
    if not dominant:
        rcond = _band_rcond(band, lower_bw, upper_bw)
        if not rcond > _RCOND_MIN:
            raise ValueError(f"the Timmer GC2 tangent system is singular or ill-conditioned "
                             f"(rcond = {rcond:.3g})")
    try:
        solution = solve_banded((lower_bw, upper_bw), band, rhs_perm, check_finite=False)
    except np.linalg.LinAlgError as exc:
        raise ValueError(f"the Timmer GC2 tangent system is singular: {exc}") from None
    if not np.all(np.isfinite(solution)):
        raise ValueError("the Timmer GC2 tangent system gave non-finite tangents (singular system)")
    if cyclic:
        unpermuted = np.empty_like(solution)
        unpermuted[order] = solution
        solution = unpermuted
    return solution, rcond, bool(np.all(margin > 0.0))


def timmer_gc2(points, *, closed: bool = False, alpha=4.0, beta=None, end_derivatives=None,
               joint: str = "thesis") -> Spline:
    """Piecewise Timmer curve whose tangents solve a tridiagonal system (Algorithm 3.3; §5.6).

    Unknowns: non-unit tangents :math:`T_1..T_n` (thesis 1-based; array index ``k = i - 1``). With
    :math:`A=\\alpha_{i-1}, B=\\beta_{i-1}, a=\\alpha_i, b=\\beta_i` the joint rows at :math:`i=2..n-1` are

    * ``joint="thesis"``: :math:`H_{i-1}''(1)=H_i''(0)` (eq 3.123), i.e. eqs 3.126-3.130
      :math:`4abB\\,T_{i-1}+8Ab(a+B)\\,T_i+4AaB\\,T_{i+1}=3ABab\\,(P_{i+1}-P_{i-1})` (correct as printed; the
      derivatives 3.124/3.125 they come from have sign errors, E19). This joint is :math:`C^2` (status
      ``"c2"``) only where :math:`\\alpha_i=\\beta_{i-1}`; elsewhere
      :math:`\\kappa_i(0)=(\\alpha_i/\\beta_{i-1})^2\\kappa_{i-1}(1)` (E20, status ``"g1"``).
    * ``joint="g2"``: :math:`H_i''(0)=(B/a)^2H_{i-1}''(1)`, true :math:`G^2` for any :math:`\\alpha,\\beta` (§5.6):
      :math:`4bB^2\\,T_{i-1}+8Ab(a+B)\\,T_i+4Aa^2\\,T_{i+1}=3Ab\\,[a^2(P_{i+1}-P_i)+B^2(P_i-P_{i-1})]`.

    End rows (eq 3.131, open curves): :math:`T_1=\\alpha_1\\hat D_1/4` and :math:`T_n=\\beta_{n-1}\\hat D_n/4`, so
    that :math:`H_1'(0)=\\hat D_1` and :math:`H_{n-1}'(1)=\\hat D_n`; by default :math:`\\hat D` are the raw
    estimates 2.1/2.2 (per unit piece parameter). Closed curves use the joint row at every point,
    cyclically. The matrix is the same for x and y: one ``solve_banded`` call with two right-hand-side
    columns (a cyclic system is reordered to bandwidth 2 rather than split by Sherman-Morrison). Rows
    are diagonally dominant for the thesis joint iff :math:`2/B+2/a>1/A+1/b` (e.g. all scales equal),
    for the ``"g2"`` joint iff :math:`2(a+B)>B^2/A+a^2/b` (a different condition: the thesis joint's test does
    not carry over; :math:`A=a=1`, :math:`B=b=(3+\\sqrt5)/2` passes it but makes a closed ``"g2"`` system
    with an even number of points singular); otherwise the system is still solved, with partial pivoting, after an O(n) LAPACK condition
    estimate; a singular or ill-conditioned system (rcond < 1e-12) raises ``ValueError``. With constant
    :math:`\\alpha=\\beta` the thesis joint gives the uniform-knot :math:`C^2` cubic spline with end slopes
    :math:`\\hat D` (the scales only matter through their ratios). Rendered with §5.1 (eq 3.89; E20:
    the thesis's Step 3 cites 3.130).

    Parameters
    ----------
    points : array_like, shape (n, 2)
        Open: ``n >= 2``; closed: ``n >= 3`` distinct points.
    closed : bool
    alpha : float or array_like, shape (m,)
        Tangent scales :math:`\\alpha_i>0` per piece (default 4, Timmer's own value).
    beta : float or array_like, shape (m,), optional
        :math:`\\beta_i>0`; defaults to ``alpha``.
    end_derivatives : pair of array_like (2,), optional
        :math:`(\\hat D_1,\\hat D_n)` per unit piece parameter (open curves only).
    joint : {"thesis", "g2"}

    Returns
    -------
    Spline
        ``info``: ``form="timmer_gc2"``, ``joint``, ``alpha``, ``beta``, ``joint_status``, ``curvature_jump``,
        ``diagonally_dominant``, ``rcond`` (``None`` if not needed), ``end_derivatives``.
        ``auxiliary``: ``Q1``, ``Q2``, ``tangents`` (the solved non-unit :math:`T_i`).
    """
    closed = check_bool(closed, "closed")
    joint = check_choice(joint, "joint", ("thesis", "g2"))
    pts, exponent = scaled_points(points, closed)  # T are lengths here, alpha and beta dimensionless
    count = pts.shape[0]
    m = count if closed else count - 1
    alpha_values = _segment_values(alpha, m, "alpha")
    beta_values = alpha_values.copy() if beta is None else _segment_values(beta, m, "beta")
    if closed and end_derivatives is not None:
        raise ValueError("end_derivatives apply to open curves only (closed curves have no ends)")
    lower_j, upper_j, rhs_j = _joint_rows(pts, alpha_values, beta_values, closed, joint)
    extra = {"joint": joint}
    if closed:
        lower, diag, upper, rhs = lower_j, np.ones(count), upper_j, rhs_j
        extra["end_derivatives"] = None
    else:
        first, last = _end_derivatives(end_derivatives, pts, exponent)
        lower = np.concatenate([[0.0], lower_j, [0.0]])
        upper = np.concatenate([[0.0], upper_j, [0.0]])
        diag = np.ones(count)
        rhs = np.vstack([alpha_values[0] * first / 4.0, rhs_j, beta_values[-1] * last / 4.0])
        extra["end_derivatives"] = [np.ldexp(first, exponent).tolist(), np.ldexp(last, exponent).tolist()]

    tangents, rcond, dominant = _solve_tridiagonal(lower, diag, upper, rhs, closed)
    extra["diagonally_dominant"] = dominant
    extra["rcond"] = rcond
    if joint == "g2":
        labels = ["g2"] * m
    else:
        labels = _matching_labels(np.roll(beta_values, 1), alpha_values, "c2", "g1")
    return _make_spline("timmer_gc2", pts, tangents, alpha_values, beta_values, closed, labels, extra,
                        exponent=exponent, unit_tangents=False)


def _joint_rows(pts, alpha_values, beta_values, closed, joint):
    """Joint rows of Algorithm 3.3 divided by their diagonal ``8 A b (a + B)`` (§5.6), in closed form.

    ``A, B`` are the scales of the piece before the joint, ``a, b`` of the piece after. Dividing
    symbolically (not after the products) keeps the rows finite for any scales float64 holds.
    """
    count = pts.shape[0]
    m = alpha_values.shape[0]
    joints = np.arange(count) if closed else np.arange(1, count - 1)
    big_a, big_b = alpha_values[joints - 1], beta_values[joints - 1]
    small_a, small_b = alpha_values[joints % m], beta_values[joints % m]
    previous, current, following = pts[joints - 1], pts[joints], pts[(joints + 1) % count]
    total = small_a + big_b
    if joint == "thesis":
        # (4abB, 4AaB, 3ABab (P_{i+1} - P_{i-1})) / (8Ab(a + B))
        share = small_a * (big_b / total)
        lower = share / (2.0 * big_a)
        upper = share / (2.0 * small_b)
        rhs = (0.375 * share)[:, None] * (following - previous)
    else:
        # (4bB^2, 4Aa^2, 3Ab [a^2 (P_{i+1} - P_i) + B^2 (P_i - P_{i-1})]) / (8Ab(a + B))
        after, before = small_a / total, big_b / total
        lower = before * (big_b / (2.0 * big_a))
        upper = after * (small_a / (2.0 * small_b))
        rhs = 0.375 * ((small_a * after)[:, None] * (following - current)
                       + (big_b * before)[:, None] * (current - previous))
    return lower, upper, rhs


def _end_derivatives(end_derivatives, pts, exponent):
    """``(D_1, D_n)`` of the scaled problem: the §6 estimates, or the given pair times ``2^-exponent``."""
    if end_derivatives is None:
        raw = estimate_tangents(pts, closed=False)
        return raw[0], raw[-1]
    if not isinstance(end_derivatives, (tuple, list)) and np.ndim(end_derivatives) != 2:
        raise TypeError("end_derivatives must be a pair (D_1, D_n) of 2-vectors")
    if len(end_derivatives) != 2:
        raise ValueError(f"end_derivatives must be a pair (D_1, D_n), got {len(end_derivatives)} items")
    first = as_float_array(end_derivatives[0], "end_derivatives[0]")
    last = as_float_array(end_derivatives[1], "end_derivatives[1]")
    for name, value in (("end_derivatives[0]", first), ("end_derivatives[1]", last)):
        if value.shape != (2,):
            raise ValueError(f"{name} must have shape (2,), got {value.shape}")
    return np.ldexp(first, -exponent), np.ldexp(last, -exponent)
