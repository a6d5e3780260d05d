"""Curvature jumps: where an outline's curvature steps (a straight side running into an arc, a stem into a bowl),
found on the converged ``C^2`` fit of ``"lsq"``, become ``C^1`` knots of a second fit (option
``curvature_jumps``; docs/capture.md §12, "Curvature jumps").

A designed outline is a chain of lines and arcs or cubics joined ``G^1``: the tangent turns smoothly but the
curvature jumps at the joins. A ``C^2`` spline cannot jump in curvature, so around each such join the regression
spline of ``"lsq"`` takes several knots and its straight sides bow (a 1000 x 600 px rounded rectangle: 44 segments
against 8, 0.57 px off the true outline). One knot of multiplicity 2 at the join (``S''`` may jump there, as
:mod:`.lsq_model` allows for ``joint_continuity=1``) takes the step exactly.

Where the jumps are is decided on the converged ``C^2`` fit ``S`` rather than on the pixels: the chord-turn
curvature of a staircase fluctuates by as much as the jumps of a large shape (a 600 px arc's curvature is
0.0017 / px), while the fit is smooth and within ``epsilon`` of the contour. On ``S`` the rule, per piece
between corners (the whole outline, periodic, without corners):

1. ``kappa(s)``, the signed curvature of ``S`` on a 1-px grid of its arc length ``s``;
2. per scale ``L`` in :data:`SCALES` (while a piece holds ``4 L``): ``D_L(s)``, the mean of ``kappa`` over
   ``(s, s + L]`` minus its mean over ``[s - L, s)`` (both windows inside the piece);
3. a jump at ``s`` when ``|D_L(s)|`` is the largest within ``s +- L`` (one per step), **significant**: the
   deviation ``|D_L| L^2 / 8`` that a step of that size makes from one smooth arc over the window is at least
   :data:`SIGNIFICANCE` ``* epsilon`` (``epsilon`` itself), and **isolated**: ``|D_L(s +- L)| <= ISOLATION
   |D_L(s)|`` (a step; a smoothly varying curvature, as on an ellipse, keeps ``D_L`` near ``kappa' L`` over
   long stretches);
4. the detections of all scales, the largest scale first: one within ``max(L, L')`` of a larger one's is the
   same jump.

:func:`curvature_jumps` returns the parameter values of the jumps on ``S``; ``"lsq"`` refits with a ``C^1`` knot
at each (and without the first knots within ``L / 2`` of it) and keeps the refit when it converges with fewer
segments (:func:`~.lsq.fit_lsq`).
"""
from __future__ import annotations

import numpy as np
from scipy.ndimage import maximum_filter1d

from ...spline.curvature import curvature_from

__all__ = ["curvature_jumps", "locate_on_contour", "SCALES", "SIGNIFICANCE", "ISOLATION", "REFIT_MARGIN"]

#: Window half-widths ``L`` (px of arc) at which a step of the curvature is looked for.
SCALES = (8, 16, 32, 64, 128)
#: A step counts when ``|D_L| L^2 / 8``, the deviation it makes from one arc over the window, is at least this
#: share of ``epsilon``: a smaller step the ``C^2`` fit follows within the tolerance without extra knots.
SIGNIFICANCE = 1.0
#: A step, not a ramp: ``|D_L|`` one window away on either side is at most this share of its peak.
ISOLATION = 0.5
#: The refit runs where the merged first fit has, in the pieces between corners that hold a jump, at least this
#: many segments more than jumps. Each jump knot is a join of the refit, so pieces with about a segment per jump
#: have nothing to save; a ``C^2`` fit spends several knots around each jump, which merging does not always take
#: back. On the quick held-out glyphs (79 outlines, ``bench_jumps.py --refits``) this runs 28 refits instead of
#: 47 (every outline with a jump) and keeps 50 of the 54 segments they save (BENCHMARKS.md, "Session 14").
REFIT_MARGIN = 4


def _samples(bezier, starts, ends):
    """Signed curvature, parameter and arc-length step of ``S`` at about one sample per parameter unit: the
    midpoints of ``ceil(h)`` equal parameter steps of every segment (``h`` its parameter length)."""
    h = ends - starts
    count = np.maximum(np.ceil(h).astype(np.int64), 2)
    seg = np.repeat(np.arange(bezier.shape[0]), count)
    first = np.cumsum(count) - count
    t = ((np.arange(seg.shape[0]) - first[seg]) + 0.5) / count[seg]
    c = bezier.take(seg, axis=0)
    s, tt = (1.0 - t)[:, None], t[:, None]
    d1 = 3.0 * (s * s * (c[:, 1] - c[:, 0]) + 2.0 * s * tt * (c[:, 2] - c[:, 1]) + tt * tt * (c[:, 3] - c[:, 2]))
    d2 = 6.0 * (s * (c[:, 2] - 2.0 * c[:, 1] + c[:, 0]) + tt * (c[:, 3] - 2.0 * c[:, 2] + c[:, 1]))
    kappa = np.nan_to_num(curvature_from(d1.T, d2.T))  # the one formula of §7 (NaN where S' = 0: none here)
    return kappa, starts[seg] + t * h[seg], np.hypot(d1[:, 0], d1[:, 1]) / count[seg]


def curvature_jumps(bezier, starts, ends, corner_values, epsilon, scales=SCALES, significance=SIGNIFICANCE,
                    isolation=ISOLATION):
    """The curvature jumps of a fitted outline (module docstring): ``bezier`` (k, 4, 2) its segments on the
    parameter intervals ``[starts, ends]``, ``corner_values`` the sorted parameters of its corners (empty: a
    periodic outline without corners), ``epsilon`` the fit's tolerance. Returns ``(values, scales)``: the
    parameter of each jump on the fit and the window half-width ``L`` it was found at, sorted by parameter."""
    bezier, starts, ends = (np.asarray(a, float) for a in (bezier, starts, ends))
    corner_values = np.asarray(corner_values, float).reshape(-1)
    empty = (np.zeros(0), np.zeros(0, np.int64))
    if bezier.shape[0] < 2:
        return empty
    kappa, value, step = _samples(bezier, starts, ends)
    arc = np.cumsum(step) - 0.5 * step  # arc length at each sample
    grid = np.arange(0.0, arc[-1], 1.0)
    n = grid.shape[0]
    periodic = corner_values.shape[0] == 0
    if n < 32:
        return empty
    curvature = np.interp(grid, arc, kappa)
    at = np.interp(grid, arc, value)
    piece = np.zeros(n, np.int64) if periodic else np.searchsorted(corner_values, at, side="right")
    index = np.arange(n)
    # prefix sums over two periods (periodic) or one, for the window means
    total = np.concatenate([[0.0], np.cumsum(np.concatenate([curvature, curvature]) if periodic else curvature)])
    found_value, found_scale = [], []
    for width in scales:
        if 4 * width > n:
            break
        if periodic:
            ahead = total[index + width + 1] - total[index + 1]
            behind = np.where(index >= width, total[index] - total[np.maximum(index - width, 0)],
                              total[index + n] - total[index + n - width])
            valid = np.ones(n, bool)
        else:
            hi, lo = np.minimum(index + width, n - 1), np.maximum(index - width, 0)
            ahead = total[hi + 1] - total[np.minimum(index + 1, n)]
            behind = total[index] - total[lo]
            valid = (index >= width) & (index + width < n) & (piece[lo] == piece) & (piece[hi] == piece)
        step_size = np.abs(ahead - behind) / width
        beside = np.maximum(np.roll(step_size, width), np.roll(step_size, -width))
        peak = step_size >= maximum_filter1d(step_size, size=2 * width + 1, mode="wrap" if periodic else "nearest")
        keep = valid & peak & (step_size * width * width / 8.0 >= significance * epsilon) & \
            (beside <= isolation * step_size)
        for j in np.flatnonzero(keep).tolist():
            found_value.append(float(at[j]))
            found_scale.append(width)
    if not found_value:
        return empty
    # one jump per step: the largest scale first, smaller ones within max(L, L') of a kept one are the same jump
    period = float(ends[-1] - starts[0])
    order = np.argsort(-np.asarray(found_scale), kind="stable")
    kept_value, kept_scale = [], []
    for i in order.tolist():
        v, w = found_value[i], found_scale[i]
        near = False
        for kv, kw in zip(kept_value, kept_scale):
            gap = abs(v - kv)
            if periodic:
                gap = min(gap, period - gap)
            if gap <= max(w, kw):
                near = True
                break
        if not near:
            kept_value.append(v)
            kept_scale.append(w)
    order = np.argsort(kept_value)
    return np.asarray(kept_value)[order], np.asarray(kept_scale, np.int64)[order]


def locate_on_contour(points, indices, scales, piece_bounds, periodic):
    """Refine jumps on the contour itself: for each jump near contour index ``indices[i]`` (found at window
    half-width ``scales[i]`` px, about as many contour steps), the index ``c`` within half a window of it that
    best splits the contour points ``c - L .. c + L`` into two parabolas sharing their value and slope at ``c``:
    in the frame of the window's chord, ``y = a + b x + q_- x^2`` for ``x < 0`` and ``a + b x + q_+ x^2`` for
    ``x >= 0``, least squares. A step of the curvature is a step of ``q``; the ``C^2`` fit that found the jump
    spreads it over a knot interval, the contour does not. ``piece_bounds`` (``lo, hi`` per jump) keep the
    windows inside the jump's piece (``periodic``: indices wrap around the contour). Returns the refined
    indices."""
    points = np.asarray(points, float)
    n = points.shape[0]
    indices = np.asarray(indices, np.int64)
    out = indices.copy()
    for i, (centre, width) in enumerate(zip(indices.tolist(), np.asarray(scales, np.int64).tolist())):
        lo, hi = (centre - 2 * width, centre + 2 * width) if periodic else piece_bounds[i]
        first, last = max(centre - width // 2, lo + width), min(centre + width // 2, hi - width)
        if last <= first:
            continue
        # coarse to fine: every stride-th candidate, then every one within a stride of the best
        stride = max(1, width // 8)
        best = _best_split(points, np.arange(first, last + 1, stride), width)
        out[i] = _best_split(points, np.arange(max(first, best - stride + 1), min(last, best + stride - 1) + 1),
                             width) % n
    return out


def _best_split(points, candidates, width):
    """The candidate index whose window ``c - width .. c + width`` the two parabolas of
    :func:`locate_on_contour` fit best (smallest sum of squared residuals)."""
    n = points.shape[0]
    offsets = np.arange(-width, width + 1)
    window = (candidates[:, None] + offsets[None, :]) % n  # (C, 2 width + 1)
    origin = points.take(candidates % n, axis=0)
    chord = points.take((candidates + width) % n, axis=0) - points.take((candidates - width) % n, axis=0)
    chord /= np.maximum(np.hypot(chord[:, 0], chord[:, 1]), 1e-12)[:, None]
    rel = points.take(window, axis=0) - origin[:, None, :]
    x = (rel[:, :, 0] * chord[:, None, 0] + rel[:, :, 1] * chord[:, None, 1]) / float(width)
    y = rel[:, :, 1] * chord[:, None, 0] - rel[:, :, 0] * chord[:, None, 1]
    square = x * x
    design = np.stack([np.ones_like(x), x, np.where(x < 0, square, 0.0), np.where(x >= 0, square, 0.0)], axis=2)
    normal = np.einsum("cmi,cmj->cij", design, design) + 1e-9 * np.eye(4)
    rhs = np.einsum("cmi,cm->ci", design, y)
    coef = np.linalg.solve(normal, rhs[..., None])[..., 0]
    residual = np.einsum("cmi,ci->cm", design, coef) - y
    return int(candidates[int(np.argmin((residual * residual).sum(axis=1)))])
