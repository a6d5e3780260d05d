"""Tangent and end-derivative estimates for point sequences (§6, thesis eqs 2.1-2.5, 3.106-3.109).

Three estimates live here:

* :func:`estimate_tangents` -- the thesis's tangent vectors :math:`\\tilde T_i` (eqs 2.1-2.4 = 3.106-3.109):
  second-order one-sided differences at the two ends of an open sequence, and the bisector of the two unit
  chords, scaled by :math:`d_-d_+/(d_-+d_+)`, at every other point (§6.1, §6.2).
* :func:`end_derivatives` -- the 3-point parabola derivatives :math:`\\hat M_1,\\hat M_n` for the clamped
  (Type 1) end condition of the interpolant; they match the knot scale (§6.3).
* :func:`interior_angle` -- the interior angle at a point, used by the corner detector's
  tolerance-angle test (thesis eq 2.5 with erratum **E21**).

All functions work for points in any dimension :math:`\\mathbb R^d` (``d >= 2`` in practice) and validate
their input strictly: NaN/inf coordinates, consecutive duplicate points and too few points raise
``ValueError`` naming the offending index.
"""
from __future__ import annotations

import numpy as np

from .._validation import COINCIDENT_RTOL, as_float_array, check_bool, check_choice, check_distinct_neighbours, check_number
from .interpolant import end_derivative_estimates
from .scaling import even_exponent

__all__ = ["estimate_tangents", "end_derivatives", "interior_angle", "unit_tangents", "TANGENT_METHODS"]

#: Methods accepted by :func:`estimate_tangents`.
TANGENT_METHODS = ("thesis", "chord_parabola")

#: Relative size below which two consecutive points count as duplicates (times the extent of the data):
#: the package's one coincidence rule (:mod:`splinecraft._validation`).
DUPLICATE_RTOL = COINCIDENT_RTOL


# ----------------------------------------------------------------------------------------------------------
# validation helpers (shared with timmer.py)
# ----------------------------------------------------------------------------------------------------------
def _validate_points(points, *, closed: bool, name: str = "points", min_open: int = 2,
                     min_closed: int = 3) -> np.ndarray:
    """Return ``points`` as a float ``(n, d)`` array after strict validation.

    Raises ``TypeError`` for non-numeric input and ``ValueError`` for a wrong shape, non-finite
    coordinates (naming the first bad index), too few points, consecutive duplicates (naming the pair),
    and, for closed sequences, a repeated first point at the end.
    """
    check_bool(closed, "closed")
    array = as_float_array(points, name)
    if array.ndim != 2 or array.shape[1] < 1:
        raise ValueError(f"{name} must have shape (n, d), got shape {array.shape}")
    count = array.shape[0]
    needed = min_closed if closed else min_open
    if count < needed:
        kind = "a closed" if closed else "an open"
        raise ValueError(f"{name} needs at least {needed} points for {kind} curve, got {count}")
    check_distinct_neighbours(array, name, closed=closed)
    return array


def _chords(points: np.ndarray, closed: bool) -> np.ndarray:
    """Chord vectors ``P_{i+1} - P_i`` (``n-1`` of them, or ``n`` with the closing chord)."""
    if closed:
        return np.roll(points, -1, axis=0) - points
    return np.diff(points, axis=0)


# ----------------------------------------------------------------------------------------------------------
# tangent estimates
# ----------------------------------------------------------------------------------------------------------
def estimate_tangents(points, *, closed: bool = False, method: str = "thesis",
                      reversal_tol: float = 1e-9) -> np.ndarray:
    """Tangent vector estimates :math:`\\tilde T_i` at every point (§6.1-§6.2, thesis eqs 2.1-2.4).

    ``method="thesis"`` (default, the thesis's estimate, also eqs 3.106-3.109):

    * ends of an open sequence, eqs 2.1 and 2.2 (correct as printed, §6.1)
      :math:`\\tilde T_0=\\tfrac12(-3P_0+4P_1-P_2)`, :math:`\\tilde T_n=\\tfrac12(3P_n-4P_{n-1}+P_{n-2})`:
      second-order one-sided differences for a unit parameter step, exact for quadratics sampled at
      uniform parameters. :math:`\\tilde T_n` points along the direction of travel.
    * every other point, eqs 2.3/2.4 (§6.2):
      :math:`\\tilde T_i=a_i(P_i-P_{i-1})+(1-a_i)(P_{i+1}-P_i)=\\frac{d_-d_+}{d_-+d_+}(u_-+u_+)`, the bisector
      of the two unit chords. At a reversal (:math:`\\|u_-+u_+\\|<` ``reversal_tol``) the estimate falls back
      to :math:`u_+` scaled by :math:`2d_-d_+/(d_-+d_+)` (the length the formula has for collinear chords).
    * closed sequences use the interior formula cyclically at every point (§5.5, §6.2).

    ``method="chord_parabola"``: the derivative of the parabola through three consecutive points with
    chord-length knots, :math:`(d_+^2(P_i-P_{i-1})+d_-^2(P_{i+1}-P_i))/(d_-d_+(d_-+d_+))` at interior points
    (§6.2 note), and the §6.3 parabola end derivatives with chord-length knots at open ends. These
    are derivatives per unit chord length (roughly unit vectors). This is not the thesis's estimate;
    it is offered for comparison.

    Parameters
    ----------
    points : array_like, shape (n, d)
        The points. Open: ``n >= 2`` (with ``n == 2`` both estimates equal the chord
        :math:`P_1-P_0`, the degree-1 limit of 2.1/2.2). Closed: ``n >= 3`` distinct points, the first one
        not repeated at the end.
    closed : bool
        Treat the sequence as a closed outline.
    method : {"thesis", "chord_parabola"}
        See above.
    reversal_tol : float
        Threshold on :math:`\\|u_-+u_+\\|` (which lies in [0, 2]) below which a point is a reversal.

    Returns
    -------
    numpy.ndarray, shape (n, d)
        The (non-unit) tangent estimates, per unit parameter step. An open end where 2.1/2.2 gives the
        zero vector (points collinear with :math:`P_2=4P_1-3P_0`) falls back to the first (last) chord so
        that every estimate can be normalised.

    Raises
    ------
    ValueError
        Non-finite coordinates, consecutive duplicate points, too few points, unknown ``method``.
    """
    method = check_choice(method, "method", TANGENT_METHODS)
    reversal_tol = check_number(reversal_tol, "reversal_tol", minimum=0.0, maximum=2.0, inclusive=(True, False))
    pts = _validate_points(points, closed=closed)
    exponent = even_exponent(pts)  # estimate on points scaled by 2^-k (exact): any float64 scale works
    if exponent:
        with np.errstate(over="ignore"):
            tangents = np.ldexp(_estimate(np.ldexp(pts, -exponent), closed, method, reversal_tol), exponent)
        if not np.isfinite(tangents).all():
            raise ValueError("points: the tangent estimates of points this large exceed the float64 range")
        return tangents
    return _estimate(pts, closed, method, reversal_tol)


def _estimate(pts, closed, method, reversal_tol):
    """:func:`estimate_tangents` on validated points of moderate size."""
    count = pts.shape[0]
    chords = _chords(pts, closed)                     # chord i runs from P_i to P_{i+1}
    lengths = np.linalg.norm(chords, axis=1)
    if not closed and count == 2:
        return np.vstack([chords[0], chords[0]])

    # Incoming chord (P_i - P_{i-1}) and outgoing chord (P_{i+1} - P_i) at each point that has both.
    if closed:
        incoming, outgoing = np.roll(chords, 1, axis=0), chords
        d_in, d_out = np.roll(lengths, 1), lengths
    else:
        incoming, outgoing = chords[:-1], chords[1:]
        d_in, d_out = lengths[:-1], lengths[1:]

    if method == "thesis":
        unit_sum = incoming / d_in[:, None] + outgoing / d_out[:, None]
        scale = d_in * d_out / (d_in + d_out)
        inner = scale[:, None] * unit_sum
        reversal = np.linalg.norm(unit_sum, axis=1) < reversal_tol
        if np.any(reversal):
            inner[reversal] = (2.0 * scale[reversal] / d_out[reversal])[:, None] * outgoing[reversal]
    else:
        inner = ((d_out ** 2)[:, None] * incoming + (d_in ** 2)[:, None] * outgoing) / \
                (d_in * d_out * (d_in + d_out))[:, None]

    if closed:
        return inner

    tangents = np.empty_like(pts)
    tangents[1:-1] = inner
    if method == "thesis":
        tangents[0] = 0.5 * (-3.0 * pts[0] + 4.0 * pts[1] - pts[2])          # eq 2.1
        tangents[-1] = 0.5 * (3.0 * pts[-1] - 4.0 * pts[-2] + pts[-3])       # eq 2.2
    else:
        knots = np.concatenate([[0.0], np.cumsum(lengths)])
        tangents[0], tangents[-1] = end_derivatives(pts, knots)
    extent = float(np.max(np.ptp(pts, axis=0)))
    for end, chord in ((0, chords[0]), (-1, chords[-1])):
        if np.linalg.norm(tangents[end]) <= 1e-12 * extent:
            tangents[end] = chord
    return tangents


def unit_tangents(tangents, *, name: str = "tangents") -> np.ndarray:
    """Normalise tangent vectors row by row (thesis eq 3.110 with erratum E16: all :math:`i=0..n`).

    Raises ``ValueError`` naming the first zero or non-finite row.
    """
    array = np.asarray(tangents, dtype=float)
    if array.ndim != 2:
        raise ValueError(f"{name} must have shape (n, d), got shape {array.shape}")
    bad_rows = np.flatnonzero(~np.isfinite(array).all(axis=1))
    if bad_rows.size:
        raise ValueError(f"{name}[{bad_rows[0]}] is not finite: {array[bad_rows[0]].tolist()}")
    norms = np.linalg.norm(array, axis=1)
    zero_rows = np.flatnonzero(norms == 0.0)
    if zero_rows.size:
        raise ValueError(f"{name}[{zero_rows[0]}] is the zero vector; a unit tangent needs a direction")
    return array / norms[:, None]


# ----------------------------------------------------------------------------------------------------------
# end derivatives for Type 1 (clamped) end conditions
# ----------------------------------------------------------------------------------------------------------
def end_derivatives(points, knots) -> tuple[np.ndarray, np.ndarray]:
    """Clamped-end derivatives :math:`(\\hat M_1,\\hat M_n)` from 3-point parabolas (§6.3).

    .. math::
        \\hat M_1=\\frac{(2h_1+h_2)\\Delta_1-h_1\\Delta_2}{h_1+h_2},\\qquad
        \\hat M_n=\\frac{(2h_{n-1}+h_{n-2})\\Delta_{n-1}-h_{n-1}\\Delta_{n-2}}{h_{n-2}+h_{n-1}},

    with :math:`\\Delta_i=(F_{i+1}-F_i)/h_i`. These are :math:`dP/dt` in the units of ``knots`` and are exact
    when the points lie on a quadratic polynomial evaluated at the knots, for any spacing. For
    :math:`h\\equiv1` they reduce to thesis eqs 2.1 and 2.2. With two points both equal :math:`\\Delta_1`.

    Parameters
    ----------
    points : array_like, shape (n, d), n >= 2
    knots : array_like, shape (n,), strictly increasing

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        :math:`\\hat M_1` and :math:`\\hat M_n`, each of shape (d,).
    """
    pts = _validate_points(points, closed=False)
    try:
        knot_values = np.asarray(knots, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"knots must be an array-like of numbers: {exc}") from None
    if knot_values.shape != (pts.shape[0],):
        raise ValueError(f"knots must have shape ({pts.shape[0]},) to match points, got {knot_values.shape}")
    bad = np.flatnonzero(~np.isfinite(knot_values))
    if bad.size:
        raise ValueError(f"knots[{bad[0]}] is not finite: {float(knot_values[bad[0]])!r}")
    steps = np.diff(knot_values)
    not_increasing = np.flatnonzero(steps <= 0.0)
    if not_increasing.size:
        k = int(not_increasing[0])
        raise ValueError(f"knots must be strictly increasing: knots[{k}]={float(knot_values[k])!r} >= "
                         f"knots[{k + 1}]={float(knot_values[k + 1])!r}")
    return end_derivative_estimates(pts, steps)


# ----------------------------------------------------------------------------------------------------------
# interior angle (corner tolerance-angle test)
# ----------------------------------------------------------------------------------------------------------
def interior_angle(points, closed: bool = False, *, degrees: bool = True) -> np.ndarray:
    """Interior angle at each point between its two neighbours (thesis eq 2.5, erratum E21).

    For the triple :math:`P_i,P_{i+1},P_{i+2}` the angle at :math:`P_{i+1}` is
    :math:`\\angle(P_i-P_{i+1},\\,P_{i+2}-P_{i+1})`: 180° for collinear points travelled straight on, 0° for
    a full reversal. The thesis's printed angle between :math:`a=P_{i+1}-P_i` and :math:`b=P_{i+2}-P_{i+1}`
    is 180° minus this one (E21); the tolerance-angle test "angle > TA (152°) means collinear" needs
    the interior angle. Computed as :math:`2\\operatorname{atan2}(\\|\\hat a-\\hat b\\|,\\|\\hat a+\\hat b\\|)`
    with unit vectors, which is accurate near 0° and 180° (unlike ``arccos`` of a dot product).

    Parameters
    ----------
    points : array_like, shape (n, d)
        Open: ``n >= 3``; closed: ``n >= 3`` distinct points without repeating the first.
    closed : bool
        Closed outline: angles at every point, neighbours taken cyclically.
    degrees : bool
        Return degrees (default) or radians.

    Returns
    -------
    numpy.ndarray
        Open: shape (n-2,), the angle at ``points[1:-1]`` (entry ``k`` is the angle at point ``k+1``).
        Closed: shape (n,), entry ``k`` is the angle at point ``k``.
    """
    pts = _validate_points(points, closed=closed, min_open=3)
    chords = _chords(pts, closed)
    unit = chords / np.linalg.norm(chords, axis=1)[:, None]
    if closed:
        backward, forward = -np.roll(unit, 1, axis=0), unit
    else:
        backward, forward = -unit[:-1], unit[1:]
    angle = 2.0 * np.arctan2(np.linalg.norm(backward - forward, axis=1),
                             np.linalg.norm(backward + forward, axis=1))
    return np.degrees(angle) if degrees else angle
