"""Spline fitting per piece and knot insertion (thesis sections 4.2.1-4.4), every iteration kept as a snapshot.

A closed contour (the crack outline of :mod:`~splinecraft.capture.contour`, or any closed polyline) is cut at
its corners into *pieces*; each piece gets a GC² interpolant (§2, thesis section 4.2.1, eqs 4.1-4.9) and knots
are inserted until the fit is within ``epsilon``. The method, the definitions where the thesis is silent, the
stopping rule and its guarantee are in docs/capture.md §12.

Layout (each module imports only those above it in this list):

* :mod:`.options` -- defaults (:data:`DEFAULT_EPSILON`, :data:`KNOT_METHODS`, ...), option tables, checks;
* :mod:`.results` -- :class:`FitResult`, :class:`Snapshot`;
* :mod:`.budget` -- time budgets, and the polygons of the boundaries they leave unfitted;
* :mod:`.geometry` -- deviation geometry (:func:`piece_deviation`, :func:`polyline_distance`);
* :mod:`.thesis` -- the thesis's Algorithms 4.1-4.6;
* :mod:`.bspline`, :mod:`.tips`, :mod:`.lsq_setup`, :mod:`.jumps`, :mod:`.merge`, :mod:`.lsq_model`,
  :mod:`.lsq` -- the default ``"lsq"`` (:mod:`.tips`: corner tips extrapolated from the two sides that meet
  there; :mod:`.jumps`: curvature jumps; :mod:`.merge`: segment merging after the fit, ``merge_tolerance``, on
  by default);
* :mod:`.small` -- the small-outline path of ``"lsq"``;
* this module -- the public entries :func:`fit_outline` and :func:`fit_small_outlines`, and the one place
  that routes a contour to a family.
"""
from __future__ import annotations

import numpy as np

from ._threads import one_blas_thread
from .budget import FALLBACK_BUDGET_REASON
from .geometry import piece_deviation, polyline_distance
from .lsq import fit_lsq
from .options import (DEFAULT_EPSILON, DEFAULT_METHOD, FALLBACK_PIECE, KNOT_METHODS, MIN_EPSILON, SMALL_OUTLINE,
                      THESIS_METHODS, check_corners, check_count, check_epsilon, check_flag, check_method,
                      check_options, check_points, check_small_outline, check_tau, make_rng)
from .results import FitResult, Snapshot
from .small import check_outlines, fit_small_trusted, keeps_area
from .thesis import fit_thesis

__all__ = ["fit_outline", "fit_small_outlines", "FitResult", "Snapshot", "KNOT_METHODS", "THESIS_METHODS",
           "DEFAULT_METHOD", "DEFAULT_EPSILON", "MIN_EPSILON", "SMALL_OUTLINE", "FALLBACK_PIECE",
           "piece_deviation", "polyline_distance"]


def fit_small_outlines(outlines, corner_lists=None, *, epsilon=DEFAULT_EPSILON, max_iterations=200,
                       keep_snapshots=True) -> list:
    """Fit many small closed contours at once: the direct path of ``"lsq"`` for contours of fewer than
    :data:`SMALL_OUTLINE` points (:func:`fit_outline` and :func:`~splinecraft.capture.trace.trace` use it).

    The thesis's interpolant with ``v = 0``, ``omega = 1`` (§2, thesis eqs 4.1-4.9) through knot points
    that are contour points (arc-length parameter; one periodic loop without corners, natural ends at
    corners), with knots inserted at the farthest contour point of every interval whose two-sided deviation
    exceeds ``epsilon``; all outlines refine side by side, stacked dense solves per round (docs/capture.md
    §12, "Small outlines"). Corners are interpolated, except an acute corner whose tip is extrapolated and a
    corner beside a pixel corner (a turn of a crack outline between two axis-aligned straight runs), whose knot
    point is that vertex. ``converged=True`` means ``hausdorff <= epsilon`` everywhere but in the zones of those
    corners, where it is ``info["tolerance_near_corners"]``; otherwise ``FitResult.info["reason"]`` says why.

    Parameters
    ----------
    outlines : sequence of array_like (n, 2)
        Closed contours as in :func:`fit_outline` (``n >= 4``, no consecutive duplicates).
    corner_lists : sequence of array_like of int, optional
        Corner indices per contour (default: none, periodic loops).
    epsilon, max_iterations, keep_snapshots
        As in :func:`fit_outline`.

    Returns
    -------
    list of FitResult
        One per outline, ``method="lsq"``, ``info["small_outline"] = True``. These are the small path's own
        fits: :func:`fit_outline` and ``trace`` fit an outline by the regression spline instead when its fit
        here encloses less than half its area (``small.keeps_area``: a thin stroke collapsed onto one chord).
    """
    epsilon = check_epsilon(epsilon)
    max_iterations = check_count(max_iterations, "max_iterations", 1)
    keep_snapshots = check_flag(keep_snapshots, "keep_snapshots")
    outlines, corners = check_outlines(outlines, corner_lists)
    return fit_small_trusted(outlines, corners, epsilon, max_iterations, keep_snapshots)


def fit_outline(points, corner_indices, *, closed=True, epsilon=DEFAULT_EPSILON, method=DEFAULT_METHOD, tau=None,
                seed=0, max_iterations=200, keep_snapshots=True, small_outline=None, **options) -> FitResult:
    """Fit a closed contour with one spline piece per pair of consecutive corners, inserting knots until
    every piece is within ``epsilon`` (thesis sections 4.2.1-4.3; stopping rule and guarantee:
    docs/capture.md §12).

    Parameters
    ----------
    points : array_like (n, 2)
        Closed contour, first point not repeated, ``n >= 4``, no consecutive duplicates, roughly unit spaced
        (the crack outline ``Boundary.outline``; ``Boundary.pixels`` works too).
    corner_indices : array_like of int
        Corner indices into ``points`` (any order; duplicates are merged). Empty: one periodic closed curve.
    closed : bool
        Must be True (outlines are closed; open polylines are not supported).
    epsilon : float
        Tolerance in px, at least :data:`MIN_EPSILON` (0.001); default :data:`DEFAULT_EPSILON` = 0.8
        (docs/capture.md §12, "Default epsilon").
    method : str
        A key of :data:`KNOT_METHODS`; default ``"lsq"``.
    tau : float, optional
        Nearness threshold of ``"euclidean"`` (px, default 5) and ``"positional"`` (% of the piece's points,
        in [0, 50), default 5). Other methods reject it.
    seed : int, None or numpy.random.Generator
        Seed of the thesis methods' random candidates (reproducible; ``"lsq"`` is deterministic).
    max_iterations : int
        Bound on the iterations (>= 1); ``converged=False`` when reached first.
    keep_snapshots : bool
        Keep every iteration in :attr:`FitResult.snapshots`.
    small_outline : int >= 0, optional
        ``"lsq"`` fits contours of fewer points than this (``None``: :data:`SMALL_OUTLINE` = 64) with
        :func:`fit_small_outlines` (the ``"lsq"`` options do not apply there; acute corners of outlines that
        pass a pre-test get the tips of the ``"lsq"`` defaults, docs/capture.md §12, "Small outlines"). ``0``
        fits every contour with the regression spline.
    **options
        Thesis methods: ``point_tension``, ``interval_weights``, ``alpha``, ``beta`` (one number each),
        ``point_tension_scale`` (passed to :func:`~splinecraft.spline.interpolate`, per piece), ``tangent_stride``
        (default 3), and for ``"fuzzy"`` only ``fuzzy_weights=(w, v)`` (default (0.7, 0.3), ``w > v``). ``"lsq"``: the keys of
        :data:`~.options.LSQ_DEFAULTS`, explained in docs/capture.md §12, "Options of lsq". A regression
        spline that gets stuck above ``epsilon`` runs once more with the parameters around its stuck knot
        intervals reset to arc length (``info["retry_from"]`` records the first run when the second is kept,
        docs/capture.md §12, "The lsq method"); with ``fallback`` (default True) a contour on which it still
        cannot reach ``epsilon``, and whose longest piece has at most :data:`FALLBACK_PIECE` steps, is refitted
        by :func:`fit_small_outlines` (``info["fallback_from"]`` records the lsq attempt).

    Returns
    -------
    FitResult

    Raises
    ------
    TypeError
        Non-numeric points, non-integer corner indices, unknown options, arguments of the wrong type.
    ValueError
        Bad shapes, NaN/inf, fewer than 4 points, coincident consecutive points, corner indices out of range,
        ``epsilon`` below :data:`MIN_EPSILON`, unknown method, ``tau`` out of range or given to a method
        without it, ``max_iterations < 1``, ``closed=False``.
    """
    if not check_flag(closed, "closed"):
        raise ValueError("fit_outline fits closed outlines only (closed=False is not supported)")
    points = check_points(points)
    corners = check_corners(corner_indices, points.shape[0])
    epsilon = check_epsilon(epsilon)
    method = check_method(method)
    tau = check_tau(tau, method)
    rng = make_rng(seed)
    max_iterations = check_count(max_iterations, "max_iterations", 1)
    keep_snapshots = check_flag(keep_snapshots, "keep_snapshots")
    small_outline = check_small_outline(small_outline, method=method)
    opts = check_options(method, options)
    return fit_trusted(points, corners, epsilon, method, tau, rng, max_iterations, keep_snapshots, small_outline,
                       opts)


def routes_to_small(method, point_count, small_outline):
    """Whether a contour of ``point_count`` points takes the small-outline path (the one routing rule)."""
    return method == "lsq" and point_count < small_outline


def fit_trusted(points, corners, epsilon, method, tau, rng, max_iterations, keep_snapshots, small_outline, opts,
                deadline=None, pixel_corners=None, pinholes=None):
    """:func:`fit_outline` on checked arguments: route the contour to its family (``deadline``, a
    :class:`~.budget.Deadline`, stops the knot rounds of every method); BLAS on one thread (:mod:`._threads`).
    ``pixel_corners``: the contour's :class:`~splinecraft.capture._pixel_corners.PixelCorners` where the caller
    has found them (trace's corner stage), for the corner tips of ``"lsq"`` and the small-outline path; ``None``:
    found where needed. ``pinholes``: the centres of the pinholes trace filled near the contour, for the notch
    tips of ``"lsq"`` (:func:`~.tips.tip_estimates`)."""
    with one_blas_thread():
        return _fit_routed(points, corners, epsilon, method, tau, rng, max_iterations, keep_snapshots, small_outline,
                           opts, deadline, pixel_corners, pinholes)


def _fit_routed(points, corners, epsilon, method, tau, rng, max_iterations, keep_snapshots, small_outline, opts,
                deadline, pixel_corners, pinholes=None):
    pixel_list = None if pixel_corners is None else [pixel_corners]
    if routes_to_small(method, points.shape[0], small_outline):
        result = fit_small_trusted([points], [corners], epsilon, max_iterations, keep_snapshots,
                                   pixel_corners=pixel_list)[0]
        if keeps_area(points, result.spline.bezier()):
            if not (result.info["stuck"] and opts["fallback"]):
                return result
            return unstuck(result, points, corners, epsilon, max_iterations, keep_snapshots, opts, deadline,
                            pixel_corners, pinholes)
        # collapsed on a thin stroke (small.keeps_area): the regression spline of "lsq" below follows the cracks
    if method != "lsq":
        return fit_thesis(points, corners, epsilon, method, tau, rng, max_iterations, keep_snapshots, opts, deadline)
    result = fit_lsq(points, corners, epsilon, max_iterations, keep_snapshots, opts, deadline, pixel_corners,
                     pinholes)
    if not result.converged and not result.info["reason"] and opts["joint_continuity"] == 1:
        # C1 knots got stuck (docs/capture.md §12, "Joints of lsq"): the C2 fit next, then the fallback below
        result = fit_lsq(points, corners, epsilon, max_iterations, keep_snapshots, dict(opts, joint_continuity=2),
                         deadline, pixel_corners, pinholes)
    if (result.converged or result.info["reason"] or not opts["fallback"]
            or _longest_piece(points.shape[0], corners) > FALLBACK_PIECE):
        return result
    # the regression spline got stuck (typically short pieces between many corners of a noisy outline, where
    # no knot fits min_gap steps from the others): the interpolant path through contour points always gets
    # there, since with every contour point a knot the curve interpolates them all
    if deadline is not None and deadline.passed():  # no time left for a second fit
        result.info["reason"] = FALLBACK_BUDGET_REASON.format(budget=deadline.budget)
        return result
    fallback = fit_small_trusted([points], [corners], epsilon, max_iterations, keep_snapshots, deadline,
                                 pixel_list)[0]
    if fallback.converged or fallback.hausdorff < result.hausdorff:
        fallback.info["fallback_from"] = {"method": "lsq", "hausdorff": result.hausdorff,
                                          "iterations": result.iterations, "knots_inserted": result.knots_inserted}
        return fallback
    return result


def unstuck(result, points, corners, epsilon, max_iterations, keep_snapshots, opts, deadline=None,
            pixel_corners=None, pinholes=None):
    """A small outline whose fit got stuck (``info["stuck"]``: the interpolant through every contour point of a
    stretch overshoots it, as beside a corner, where its natural ends overshoot the staircase) fitted by the
    regression spline of ``"lsq"``, whose corner zones keep their allowance where a piece cannot follow the
    pixels; that fit is kept where it converges (``info["fallback_from"]`` records the small one), else
    ``result`` (which says why it stopped)."""
    if deadline is not None and deadline.passed():
        return result
    with one_blas_thread():
        retry = fit_lsq(points, corners, epsilon, max_iterations, keep_snapshots, opts, deadline, pixel_corners,
                        pinholes)
    if retry.converged:
        retry.info["fallback_from"] = {"method": "small-outline", "hausdorff": result.hausdorff,
                                       "iterations": result.iterations, "knots_inserted": result.knots_inserted}
        return retry
    return result


def _longest_piece(n, corners):
    if corners.size == 0:
        return n
    return int(np.diff(np.append(corners, corners[0] + n)).max())
