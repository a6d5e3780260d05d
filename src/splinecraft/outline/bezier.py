"""Closed cubic Bézier curves -> contours in the project's spline form, exactly.

A closed run of cubic Bézier pieces (an SVG subpath, a font glyph's contour, a traced outline) becomes a
:class:`~splinecraft.outline.contour.Contour` that reproduces it exactly:

* a knot where the incoming and outgoing handles are not collinear and pointing the same way (no G¹ joint),
  or where one is zero, is a **corner** with those handles (clamped ends, §2.4 Type 1);
* at a G¹ knot the parameter steps are chosen so the joint is C¹ (``h_i / h_{i-1} = |b1 - b0|_i /
  |b3 - b2|_{i-1}``, since ``P'(t_i) = 3 (b1 - b0) / h_i``), and the GC² constraint of thesis eqs 3.13-3.14,
  ``omega_i P''(t_i^+) = v_i P'(t_i) + omega_{i-1} P''(t_i^-)``, is two linear equations for the interval
  weight ``omega_i`` (given ``omega_{i-1}``) and the point tension ``v_i``. When they have a solution with
  ``omega_i > 0`` the knot is **smooth** with that ``v_i``, else it becomes a corner. A loop without corners
  must also close up (steps and weights back to their start values), else knot 0 becomes a corner.

The result is then rebuilt by the engine and compared with the input: a knot whose negative tension the engine
refuses (§2.5, outside the dominant domain) becomes a corner, and pieces that do not match (rounding) get corners
at their ends, so the conversion is always exact to rounding.
The project's own curves (``v = 0``, ``omega = 1``) come back with those values.

Rounded input. Curves read from text with a few decimals (an SVG written with ``decimals=4``) are the
exact curves moved by up to ``rounding`` per coordinate, which bends every G¹ joint a little. Given that
``rounding``, a knot is tested for G¹ with the sine tolerance the rounding can cause,
``2 sqrt(2) rounding (1 / |out| + 1 / |in|)`` (each handle is the difference of two rounded points; capped at
``MAX_ROUNDING_SINE``: handles too short to show a direction stay corners); a loop's steps and weights
spread their closing error evenly instead of demanding exact closure, and the final comparison accepts
pieces within ``MATCH_ROUNDING * rounding`` of the input (at least the ``MATCH_TOLERANCE`` of exact
input). So a smooth knot comes back smooth when a smooth contour reproduces the rounded numbers to a few
roundings, and a real corner (a kink larger than the rounding explains, or one no smooth curve matches)
stays a corner.
"""
from __future__ import annotations

import numpy as np

from .contour import Contour

__all__ = ["contour_from_bezier", "drop_degenerate_pieces", "curve_bounds"]

#: Relative tolerance of the G¹ test (sine of the angle between the handles) and of the exactness check.
SMOOTH_TOLERANCE = 1e-9
MATCH_TOLERANCE = 1e-7
#: Rounded input: the largest sine tolerance the rounding may give a knot, and the accepted distance of the
#: rebuilt control points from the input, in units of the rounding.
MAX_ROUNDING_SINE = 0.02
MATCH_ROUNDING = 8.0


def drop_degenerate_pieces(bezier) -> np.ndarray:
    """Pieces of zero length (all four control points equal) removed."""
    bezier = np.asarray(bezier, float)
    spread = np.abs(bezier - bezier[:, :1]).max(axis=(1, 2))
    scale = max(float(np.abs(bezier).max(initial=0.0)), 1.0)
    return bezier[spread > 1e-12 * scale]


def curve_bounds(curves):
    """``(low, high)`` corners of the bounding box of the cubic Bézier curves ``curves`` (a list of
    ``(m, 4, 2)`` arrays): each coordinate's extremes are at the piece ends or where its derivative
    ``3 (a t^2 + b t + c)`` vanishes in ``(0, 1)``, with ``a = d0 - 2 d1 + d2``, ``b = 2 (d1 - d0)``, ``c = d0``
    and ``d_k = b_{k+1} - b_k`` (the control points' box contains it)."""
    pieces = np.concatenate([np.asarray(c, float).reshape(-1, 4, 2) for c in curves])
    d = np.diff(pieces, axis=1)  # (P, 3, 2)
    a, b, c = d[:, 0] - 2 * d[:, 1] + d[:, 2], 2 * (d[:, 1] - d[:, 0]), d[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(b * b - 4 * a * c)  # NaN: no real root
        q = -0.5 * (b + np.where(b < 0, -root, root))  # the stable pair of roots q / a and c / q
        theta = np.stack([q / a, c / q])  # (2, P, 2); where a = 0 the first is infinite, the second -c/b
    theta = np.where(np.isfinite(theta) & (theta > 0) & (theta < 1), theta, 0.0)
    one = 1.0 - theta
    values = (one ** 3 * pieces[:, 0] + 3 * one * one * theta * pieces[:, 1]
              + 3 * one * theta * theta * pieces[:, 2] + theta ** 3 * pieces[:, 3])
    ends = pieces[:, [0, 3]].reshape(-1, 2)
    every = np.concatenate([values.reshape(-1, 2), ends])
    return every.min(axis=0), every.max(axis=0)


def _handles(bezier):
    out = bezier[:, 1] - bezier[:, 0]
    into = np.roll(bezier[:, 2] - bezier[:, 3], 1, axis=0)  # arriving at knot i: piece i - 1
    return out, into


def _g1_joints(bezier, rounding=0.0):
    """Knots whose two handles are non-zero, collinear and opposite (a G¹ joint), within the sine tolerance
    that a ``rounding`` of the coordinates can cause (module docstring)."""
    out, into = _handles(bezier)
    length_out, length_in = np.hypot(*out.T), np.hypot(*into.T)
    scale = max(float(np.ptp(bezier.reshape(-1, 2), axis=0).max()), 1e-300)
    nonzero = (length_out > 1e-12 * scale) & (length_in > 1e-12 * scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        sine = (out[:, 0] * into[:, 1] - out[:, 1] * into[:, 0]) / (length_out * length_in)
        opposite = (out * into).sum(axis=1) < 0
        rounded = np.minimum(2 * np.sqrt(2) * rounding * (1 / length_out + 1 / length_in), MAX_ROUNDING_SINE)
    return nonzero & opposite & (np.abs(sine) <= SMOOTH_TOLERANCE + np.nan_to_num(rounded))


def _runs(corners):
    """Runs of intervals between consecutive corners: lists of knot indices (first corner .. next corner)."""
    n = corners.size
    index = np.flatnonzero(corners)
    if index.size == 0:
        return [np.r_[np.arange(n), 0]]
    runs = []
    for j, start in enumerate(index):
        end = index[(j + 1) % index.size]
        length = (end - start) % n or n
        runs.append((start + np.arange(length + 1)) % n)
    return runs


def _second_derivatives(bezier, steps):
    """``P''`` at the start and at the end of every piece for the given steps."""
    start = 6.0 * (bezier[:, 0] - 2 * bezier[:, 1] + bezier[:, 2]) / steps[:, None] ** 2
    end = 6.0 * (bezier[:, 1] - 2 * bezier[:, 2] + bezier[:, 3]) / steps[:, None] ** 2
    return start, end


def _solve_run(bezier, run, steps, weights, tension, closing, exact=True):
    """Steps, weights and tensions along one run; returns the first interior knot that cannot be smooth.
    ``exact=False`` (rounded input): a loop's steps and weights need not come back to their start values
    exactly; the rebuilt curve is compared with the input instead."""
    out, into = _handles(bezier)
    chords = np.hypot(*(bezier[:, 3] - bezier[:, 0]).T)
    intervals = run[:-1]
    steps[intervals[0]] = 1.0
    for previous, i in zip(intervals[:-1], intervals[1:]):
        steps[i] = steps[previous] * np.hypot(*out[i]) / np.hypot(*into[i])
    if closing:  # a loop without corners: the step at knot 0 must come back to itself
        back = steps[intervals[-1]] * np.hypot(*out[run[0]]) / np.hypot(*into[run[0]])
        if exact and not np.isclose(back, steps[run[0]], rtol=1e-9, atol=0.0):
            return int(run[0])
        if not exact:  # rounded input: spread the closing error evenly, every step ratio by the same factor
            steps[intervals] *= (back / steps[run[0]]) ** (-np.arange(intervals.size) / intervals.size)
    steps[intervals] *= chords[intervals].sum() / steps[intervals].sum()
    start, end = _second_derivatives(bezier, steps)
    weights[intervals[0]] = 1.0
    interior = list(zip(intervals[:-1], intervals[1:]))
    if closing:
        interior.append((intervals[-1], intervals[0]))
    for previous, i in interior:
        tangent = 3.0 * out[i] / steps[i]
        system = np.column_stack([start[i], -tangent])
        rhs = weights[previous] * end[previous]
        solution, *_ = np.linalg.lstsq(system, rhs, rcond=None)
        weight, v = solution
        tolerance = 1e-9 * max(np.abs(rhs).max(), np.abs(system).max(), 1e-300)
        if not np.allclose(system @ solution, rhs, rtol=0, atol=tolerance):
            # parallel columns (straight or symmetric pieces): keep the weight, take v along the tangent
            weight = weights[previous]
            residual = weight * start[i] - rhs
            v = float(residual @ tangent / (tangent @ tangent))
            if not np.allclose(weight * start[i] - v * tangent, rhs, rtol=0,
                               atol=1e-9 * max(np.abs(rhs).max(), np.abs(start[i]).max(), 1e-300)):
                return int(i)
        if not weight > 0:
            return int(i)
        if closing and i == intervals[0]:
            if exact and not np.isclose(weight, weights[i], rtol=1e-9):
                return int(i)
            if not exact:  # rounded input: spread the closing error of the weights evenly, as for the steps
                tension[i] = v
                factors = (weight / weights[i]) ** (-np.arange(intervals.size) / intervals.size)
                tension[intervals[1:]] *= factors[:-1]  # v_k scales with omega_{k-1}
                tension[i] *= factors[-1]
                weights[intervals] *= factors
                return None
        else:
            weights[i] = weight
        tension[i] = v
    return None


def _attempt(bezier, corners, exact=True):
    n = bezier.shape[0]
    while True:
        steps, weights, tension = np.ones(n), np.ones(n), np.zeros(n)
        failed = None
        for run in _runs(corners):
            failed = _solve_run(bezier, run, steps, weights, tension, closing=not corners.any(), exact=exact)
            if failed is not None:
                break
        if failed is None:
            return steps, weights, tension
        if corners[failed]:
            raise AssertionError(f"knot {failed} is a corner already")
        corners[failed] = True


def contour_from_bezier(bezier, corners=None, *, rounding=0.0) -> Contour:
    """The contour reproducing the closed Bézier curve ``bezier`` ``(N, 4, 2)`` (module docstring).

    ``corners`` (optional, N booleans) forces corners at those knots (e.g. a trace's corners).
    ``rounding`` (optional): how far each coordinate may be from the exact curve (half a unit of the last
    decimal place written); smooth knots bent by that rounding stay smooth, and the result is within
    ``MATCH_ROUNDING * rounding`` of ``bezier`` instead of exact.
    """
    rounding = float(rounding)
    if not (np.isfinite(rounding) and rounding >= 0):
        raise ValueError(f"rounding must be a finite number >= 0, got {rounding!r}")
    bezier = np.asarray(bezier, float)
    if bezier.ndim != 3 or bezier.shape[1:] != (4, 2):
        raise ValueError(f"bezier must have shape (N, 4, 2), got {bezier.shape}")
    bezier, corners = _split_loops(bezier, corners)
    n = bezier.shape[0]
    if n < 3:  # split pieces so that the contour has 3 knots (exact de Casteljau halves)
        bezier, corners = _split_to_three(bezier, corners)
        n = bezier.shape[0]
    forced = np.zeros(n, bool) if corners is None else np.asarray(corners, bool).copy()
    scale = max(float(np.ptp(bezier.reshape(-1, 2), axis=0).max()), 1.0)
    exact = rounding <= 1e-12 * scale  # exact input (or floats written in full): the loop checks apply
    corner_mask = forced | ~_g1_joints(bezier, rounding)
    tolerance = max(MATCH_TOLERANCE * scale, MATCH_ROUNDING * rounding)
    for _ in range(n + 1):
        steps, weights, tension = _attempt(bezier, corner_mask, exact)
        out, into = _handles(bezier)
        try:
            contour = Contour(bezier[:, 0], corner_mask, handles_in=into, handles_out=out, steps=steps,
                              point_tension=_snap(tension, 0.0), interval_weights=_snap(weights, 1.0))
        except ValueError:
            # a negative tension outside the domain where the tangent system is dominant (§2.5; the engine
            # refuses it): that knot becomes a corner, the most negative first (a positive tension never
            # breaks dominance); other refusals: every knot
            negative = np.flatnonzero(~corner_mask & (tension < 0))
            if negative.size:
                corner_mask = corner_mask.copy()
                corner_mask[negative[np.argmin(tension[negative])]] = True
                continue
            contour = None
            bad = np.ones(n, bool)
        else:
            bad = np.abs(contour.bezier() - bezier).max(axis=(1, 2)) > tolerance
            if not bad.any():
                return contour
        worse = corner_mask | bad | np.roll(bad, 1)
        if (worse == corner_mask).all():
            worse[:] = True
        corner_mask = worse
    raise AssertionError("unreachable: a contour of corners reproduces every Bézier piece")


def _snap(values, target):
    """Values within rounding of ``target`` (the project's defaults v = 0, omega = 1) set to it."""
    values = np.array(values, float)
    values[np.abs(values - target) <= 1e-9 * max(1.0, abs(target))] = target
    return values


def _halves(p):
    """The two exact de Casteljau halves of the cubic piece ``p`` (4, 2)."""
    a = (p[:-1] + p[1:]) / 2
    b = (a[:-1] + a[1:]) / 2
    c = (b[0] + b[1]) / 2
    return [np.array([p[0], a[0], b[0], c]), np.array([c, b[1], a[2], p[3]])]


def _split_to_three(bezier, corners=None):
    """At least three pieces: the widest piece halved (exact de Casteljau) until there are; ``corners`` (per knot,
    or None) follow their knots, and a knot made by a split is not forced."""
    pieces = list(bezier)
    flags = [False] * len(pieces) if corners is None else [bool(c) for c in corners]
    while len(pieces) < 3:
        widest = int(np.argmax([np.ptp(p, axis=0).max() for p in pieces]))
        pieces[widest:widest + 1] = _halves(pieces[widest])
        flags[widest:widest + 1] = [flags[widest], False]
    return np.array(pieces), (None if corners is None else np.array(flags))


def _split_loops(bezier, corners):
    """Pieces that end where they start (a loop of one cubic, e.g. a teardrop's tip between two lines) split
    into their exact de Casteljau halves, so that consecutive knots are distinct (a contour's knots must be);
    the new knot in the middle of such a piece is not forced to be a corner."""
    loops = (bezier[:, 3] == bezier[:, 0]).all(axis=1)
    if not loops.any() or bezier.shape[0] == 1:  # a single piece is split by _split_to_three
        return bezier, corners
    pieces, forced = [], []
    flags = np.zeros(bezier.shape[0], bool) if corners is None else np.asarray(corners, bool)
    for piece, loop, flag in zip(bezier, loops, flags):
        pieces.extend(_halves(piece) if loop else [piece])
        forced.extend([flag, False] if loop else [flag])
    return np.array(pieces), None if corners is None else np.array(forced)
