"""Segment merging after the ``"lsq"`` fit (option ``merge_tolerance``, 0.5 px by default, 0 = off): runs of
consecutive Bézier segments between two corners become one G1 cubic where one cubic stays within the fit's
tolerance of the contour (docs/capture.md §12, "Merged segments").

The ``C^2`` regression spline needs about twice a font's segments on large renders (its curvature is
continuous at every knot, a font's jumps at every join; §12, "Joints of lsq"). This stage keeps that fit and
gives ``G^1`` segment counts, in the manner of potrace's curve optimisation (``opticurve``):

1. the fitted segments are cut (exactly, de Casteljau) where their tangent is horizontal or vertical, the
   points where a font puts its nodes (:func:`._merge_kernels.prepare`);
2. every join inside a piece gets a second tangent direction besides the fitted curve's, from a parabola fitted
   to the contour around it (:func:`._merge_kernels.prepare`; the fitted curve's direction follows the pixel staircase
   on large renders);
3. every run of 1 to :data:`MAX_RUN` consecutive segments of one piece (turning by at most :data:`MAX_TURN`) is
   fitted by one cubic with the run's end points and a direction at each end, its two handle lengths fitted to
   the contour points the run covers (:mod:`._merge_kernels`: least squares, then normal distances at the
   points' feet). A run qualifies when the cubic stays within the fit's tolerance of those points (``epsilon``,
   plus the allowance near an extrapolated corner) and within ``merge_tolerance`` of the fitted curve there;
4. dynamic programming over the chain (each join in one of its two direction states, so that both sides of
   every join share one tangent direction) picks the fewest segments, ties to the smallest squared distance
   from the fitted curve; the fitted segments as they were are always among the choices, so merging never
   adds segments;
5. the merged outline is measured by the fit's own dense check
   (:meth:`~.lsq_model.OutlineRegression.deviations`), a merged segment that fails it is not chosen again and
   the programme runs once more (at most four times, else the fit stays as it was): the guarantee of §12 holds
   unchanged.

Steps 1 to 4 run compiled (:mod:`._merge_kernels`: the cuts, tangents, turns and joins in one pass, the
candidates, fitted and grown a length at a time, in a second, the dynamic programme in a third; only the 3 x 3
solves of the joins' parabolas run in numpy between the first two), step 5 in the fit's model.
"""
from __future__ import annotations

import numpy as np

from . import _merge_kernels
from ._kernels import curve_points
from ._linalg import solve
from .geometry import member_sorted

__all__ = ["merge_segments", "MAX_RUN", "MAX_TURN"]

#: Longest run of segments tried as one cubic.
MAX_RUN = 12
#: Largest total turn (radians) of the tangent along a run tried as one cubic (a cubic with both handles
#: positive turns by less than pi; a quarter circle turns by pi / 2).
MAX_TURN = 0.8 * np.pi
#: A run keeps growing after this many consecutive lengths that did not qualify (a pair can fail where a triple
#: fits, the joins of a C2 fit being where they are).
MISSES = 2
#: Half-width of the window of the parabola that gives a join's tangent direction, in units of the longer
#: neighbouring segment's parameter length (clipped to the piece).
WINDOW = 0.5
#: Contour points a candidate cubic is fitted to (evenly spread over the run; all of them are checked).
FIT_POINTS = 32
#: Fewest parameter units (about px of arc) between a cut at an extremum and either end of its segment.
MIN_SPLIT = 2.0
#: Solves of a candidate cubic's handle lengths after the first, each after two foot-point corrections of
#: its points' parameters.
NEWTON_STEPS = 4
#: Margin (px) below the tolerance that a candidate must keep on the contour points (the dense check also
#: measures edge midpoints and curve samples; a merged segment that fails it is not chosen again). A disc's
#: staircase is up to 0.7 px from the circle, so at epsilon = 0.8 a margin leaves no room.
MARGIN = 0.0


def merge_segments(model, dev, tolerance):
    """Merge runs of segments of the converged fit of ``model`` (an :class:`~.lsq_model.OutlineRegression`
    whose dense deviations are ``dev``; module docstring); ``tolerance`` (px) bounds the distance of a merged
    cubic from the fitted curve it replaces. When anything merges, the model's fit state (Bézier segments,
    intervals, parameters) becomes the merged one and its simple knots the joins (the contour point nearest
    each). Returns the dense deviations of the result (``dev`` when nothing merged) and the simple knots that
    are no longer joins."""
    fit_bez = dev["bezier"]
    contour = model.contour
    # a run stays within its piece between corners, so every piece keeps a cubic at least: a fit with one segment
    # per piece (a polygon's sides, an image's frame) has nothing to merge
    if fit_bez.shape[0] < 2 or fit_bez.shape[0] <= contour.corner_count:
        return dev, []
    prepared, cand = candidate_runs(model, dev, tolerance)
    if not (cand["length"] > 1).any():
        return dev, []
    k, starts, ends, points = prepared["k"], prepared["starts"], prepared["ends"], contour.points
    cornered = contour.corner_count > 0
    saved = model.save()
    allowed = np.ones(cand["first"].shape[0], bool)
    for _ in range(4):
        chosen = _merge_kernels.choose(k, cand, allowed, not cornered)
        if chosen.shape[0] >= fit_bez.shape[0]:
            break
        _put_state(model, saved, starts, ends, points, cand, chosen)
        new_dev = model.deviations(dense=True)
        failing = np.flatnonzero(new_dev["excess"] > 0)
        joins = _join_indices(model, new_dev["starts"], cornered)
        if not failing.size and joins is not None:
            gone = saved["simple_knots"][~member_sorted(saved["simple_knots"], joins)]
            model.simple_knots = joins
            return new_dev, gone
        if joins is None:  # two joins at one contour point: no knot list for them
            break
        # a run that fails the dense check is not taken again (the fit's own segments never fail it)
        allowed[chosen[failing]] = False
        allowed[~cand["refit"]] = True
    model.load(saved)
    return dev, []


def candidate_runs(model, dev, tolerance):
    """Steps 1 to 3 of :func:`merge_segments` (module docstring): the pieces of the fit between extrema and
    their joins (:func:`._merge_kernels.prepare`, the joins' parabolas solved here), and the candidate runs
    (:func:`._merge_kernels.candidates`)."""
    contour = model.contour
    n = contour.size
    u = model.parameter[:n]
    points = contour.points
    # the pieces between extrema and the joins inside a piece (the seam of an outline without corners is one too:
    # the window of its parabola reaches around it)
    prepared = _merge_kernels.prepare(dev["bezier"], dev["starts"], dev["ends"], MIN_SPLIT,
                                      model.base_parameter[contour.corner_bounds], contour.piece_count,
                                      contour.corner_count > 0, points, u, model.period, WINDOW)
    good = prepared["good"]
    if good.any():  # the parabolas' b (the join's direction is (1, b) in its tangent's frame)
        prepared["slope"][good] = solve(prepared["m"][good], prepared["rhs"][good])[:, 1, 0]
    tol = np.ascontiguousarray(dev["tol_data"][0::2] if dev["dense"] else dev["tol_data"])  # one copy per merge
    fitted = curve_points(dev["bezier"], dev["starts"], dev["ends"], u)
    return prepared, _merge_kernels.candidates(prepared, dev["bezier"], points, u, tol, fitted, tolerance, MAX_RUN,
                                               MAX_TURN, MISSES, NEWTON_STEPS, FIT_POINTS, MARGIN)


def _join_indices(model, join_values, cornered):
    """The rotated contour indices of the joins (the simple knots of the merged outline): per join inside a piece
    the contour point whose parameter is nearest; None when two joins would share one."""
    contour = model.contour
    n = contour.size
    corner_values = model.base_parameter[contour.corner_bounds]
    inner = join_values[~member_sorted(join_values, corner_values)] if cornered else join_values
    parameter = model.parameter[: n + 1]
    j = np.clip(np.searchsorted(parameter, inner), 1, n)
    j = np.where(np.abs(parameter[j - 1] - inner) <= np.abs(parameter[j] - inner), j - 1, j)
    if not cornered:
        j[np.isclose(inner, 0.0)] = 0
    j = np.sort(j % n).astype(np.int64)
    if (j[1:] == j[:-1]).any() or (cornered and member_sorted(j, contour.corner_bounds).any()):
        return None
    return j


def _put_state(model, saved, starts, ends, points, cand, chosen):
    """Put the chosen runs (in chain order) into ``model``: one cubic per run on the run's parameter interval,
    the contour points of refitted runs re-parameterized on them (a segment kept as it was keeps its
    parameters)."""
    model.load(saved)
    f, length = cand["first"][chosen], cand["length"][chosen]
    last = f + length - 1
    refit = cand["refit"][chosen]
    parameter = model.parameter.copy()
    if refit.any():
        # the parameters the candidate's fit gave its points (:func:`_candidates`, on the same parameters)
        fr, lr, c = f[refit], length[refit], chosen[refit]
        count = cand["t_count"][c]
        lo = np.searchsorted(model.parameter[:points.shape[0]], starts[fr], side="left")
        run = np.repeat(np.arange(fr.shape[0]), count)
        within = np.arange(run.shape[0]) - np.repeat(np.cumsum(count) - count, count)
        idx = lo[run] + within
        s, e = starts[fr[run]], ends[fr[run] + lr[run] - 1]
        parameter[idx] = s + cand["t"][cand["t_start"][c][run] + within] * (e - s)
    parameter[model.fixed] = model.base_parameter[model.fixed]
    model.parameter = np.maximum.accumulate(parameter)
    model._bezier, model._starts, model._ends = cand["cubic"].take(chosen, axis=0), starts[f], ends[last]
