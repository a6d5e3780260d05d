"""The default knot method ``"lsq"``: regression spline, worst-point knot insertion, corner tip extrapolation
and knot removal (docs/capture.md §12, "The lsq method").

:class:`LsqKnotInsertion` runs the rounds on an :class:`~.lsq_model.OutlineRegression` and records them as
snapshots; :func:`fit_lsq` is its entry for a checked contour.
"""
from __future__ import annotations

import numpy as np

from ...spline import Spline
from ...spline.serialize import snap_joins
from .lsq_model import OutlineRegression
from .budget import BUDGET_REASON
from .jumps import REFIT_MARGIN, curvature_jumps
from .lsq_setup import thin_corners
from .merge import merge_segments
from .options import LSQ_OPTIONS
from .results import FitResult, Snapshot

__all__ = ["fit_lsq", "LsqKnotInsertion"]

_HOOK_REASON = "the fitted corner moved farther than a truncated pixel tip can be"
_ZONE_REASON = ("the pieces beside the corner fit, but near it the curve passes beside the two pixel centres of a "
                "crack")
#: Knot-removal rounds after convergence (each tries the cheapest half of the simple knots); with C1 joints
#: (``joint_continuity=1``) failed rounds are retried with fewer picks, and count too.
REMOVAL_ROUNDS = 4
REMOVAL_ROUNDS_C1 = 8


def fit_lsq(points, corners, epsilon, max_iterations, keep_snapshots, options, deadline=None, pixel_corners=None,
            pinholes=None):
    """``"lsq"`` on a checked contour (corners sorted and unique; ``options`` from ``check_options``); the
    knot rounds stop once ``deadline`` (a :class:`~.budget.Deadline`) has passed. ``pixel_corners``: the
    contour's :class:`~splinecraft.capture._pixel_corners.PixelCorners` where the caller has found them (else
    the corner tips find them, :class:`~.lsq_setup.RotatedContour`); ``pinholes``: the centres of the pinholes
    trace filled near the contour (notch tips, :func:`~.tips.tip_estimates`).

    A fit that gets stuck above the tolerance (not stopped by the deadline) is run once more with
    ``reset_stuck``: where knot intervals fail and cannot be split, the parameters around them go back to arc
    length before knots closer than ``min_gap`` are tried (:meth:`OutlineRegression.reset_parameters`). The
    second run is kept when it converges or deviates less (``info["retry_from"]`` records the first).

    With ``curvature_jumps`` (``"smooth"``, the default: outlines without corners; ``True``: every outline) and
    merging on (``merge_tolerance > 0``: the result is a ``G^1`` chain then, not the thesis's ``C^2`` fit), a
    converged fit whose ``C^2`` curve shows curvature jumps
    (:func:`~.jumps.curvature_jumps`) is fitted once more with a ``C^1`` knot at each jump
    (:meth:`OutlineRegression.seed_jumps`), where the pieces that hold the jumps have at least ``REFIT_MARGIN``
    segments more than jumps (a leaner fit has little to gain: :mod:`.jumps`); the refit is kept when it
    converges with fewer segments, or as many and a smaller Hausdorff deviation (``info["curvature_jumps"]``
    records both; docs/capture.md §12, "Curvature jumps")."""
    insertion = LsqKnotInsertion(points, corners, epsilon, max_iterations, keep_snapshots, options, deadline,
                                 pixel_corners=pixel_corners, pinholes=pinholes)
    result = insertion.run()
    if not result.converged and not result.info["reason"] and not (deadline is not None and deadline.passed()):
        retry_insertion = LsqKnotInsertion(points, corners, epsilon, max_iterations, keep_snapshots, options,
                                           deadline, reset_stuck=True, pixel_corners=pixel_corners,
                                           pinholes=pinholes)
        retry = retry_insertion.run()
        if retry.converged or retry.hausdorff < result.hausdorff:
            retry.info["retry_from"] = {"hausdorff": result.hausdorff, "iterations": result.iterations,
                                        "knots_inserted": result.knots_inserted}
            result, insertion = retry, retry_insertion
    # a refit needs REFIT_MARGIN segments more than jumps beside them, so at least REFIT_MARGIN + 1 in all: a
    # converged fit with fewer (most of them) is not measured for jumps at all
    if not result.converged or _segment_count(result) < REFIT_MARGIN + 1:
        return result
    values, scales = insertion.jumps
    if (not values.size or _segments_beside(insertion.model, result, values) < values.size + REFIT_MARGIN
            or (deadline is not None and deadline.passed())):
        return result
    segments = _segment_count(result)
    refit = LsqKnotInsertion(points, corners, epsilon, max_iterations, keep_snapshots, options, deadline,
                             jumps=(values, scales), pixel_corners=pixel_corners, pinholes=pinholes).run()
    refit_segments = _segment_count(refit)
    record = {"jumps": int(values.size), "segments": refit_segments, "segments_without": segments,
              "hausdorff": refit.hausdorff, "hausdorff_without": result.hausdorff}
    if refit.converged and (refit_segments, refit.hausdorff) < (segments, result.hausdorff):
        refit.info.update({k: v for k, v in result.info.items() if k == "retry_from"})
        refit.info["curvature_jumps"] = dict(record, kept=True)
        return refit
    result.info["curvature_jumps"] = dict(record, kept=False)
    return result


def outline_spline(bezier, knots, info):
    """``Spline(bezier, knots, closed=True, auxiliary={"F": bezier[:, 0]}, info=info)`` of a fit's Bézier pieces
    (m, 4, 2) and strictly increasing knots (m + 1,), without the constructor's checks and copies of what a fit
    guarantees (finite float64 pieces, knots from its intervals, JSON-plain ``info``): the joins snapped exactly
    as the constructor snaps them (:func:`~splinecraft.spline.serialize.snap_joins`; the fit's joins agree to
    rounding)."""
    planar = np.array(np.transpose(bezier, (1, 2, 0)), dtype=np.float64, order="C")  # a copy: (4, 2, m)
    snap_joins(planar.transpose(2, 0, 1), closed=True)
    return Spline._from_trusted(planar, np.array(knots, dtype=np.float64), closed=True,
                                auxiliary={"F": np.array(bezier[:, 0], dtype=np.float64)}, info=info)


def _segment_count(result):
    return int(result.spline.bezier().shape[0])


def _segments_beside(model, result, values):
    """Segments of ``result`` in the pieces between corners that hold a jump at one of ``values``."""
    contour = model.contour
    per_piece = np.array([len(k) - 1 for k in result.knot_indices])
    if not contour.corner_count or per_piece.shape[0] != contour.piece_count:
        return int(per_piece.sum())
    corner_values = model.base_parameter[contour.corner_bounds]
    pieces = np.unique(np.clip(np.searchsorted(corner_values, values, side="right") - 1, 0, contour.piece_count - 1))
    return int(per_piece[pieces].sum())


class LsqKnotInsertion:
    """Knot insertion and removal rounds of ``"lsq"`` on one outline, with their snapshots.

    Each round: measure the deviation (:meth:`OutlineRegression.deviations`), insert a knot into every failing
    interval (or release the tip extrapolation of a corner whose zone fails), refit and settle the corners
    (:meth:`settle`). Once everything is within the tolerance, knot removal (:meth:`remove_knots`), then the
    dense check of the guarantee before stopping (with merging on, that of the merged outline where something
    merges: :meth:`merge_unverified`).
    """

    def __init__(self, points, corners, epsilon, max_iterations, keep_snapshots, options, deadline=None,
                 reset_stuck=False, jumps=None, pixel_corners=None, pinholes=None):
        self.model = OutlineRegression(points, thin_corners(points, corners, options["min_gap"], pixel_corners),
                                       epsilon, options, pixel_corners, pinholes)
        self.model.seed_knots(options["initial_density"])
        if jumps is not None:  # C1 knots at the curvature jumps of a first fit (fit_lsq)
            self.model.seed_jumps(*jumps)
        #: the arguments of :func:`curvature_jumps` for the converged C2 fit, kept before merging on a fit without
        #: jump knots where the option ``curvature_jumps`` asks for it and merging is on (:attr:`jumps` measures
        #: them when asked: most fits end with too few segments for a refit, and are never asked)
        self._jump_fit = None
        self.epsilon = epsilon
        self.max_iterations = max_iterations
        self.keep = keep_snapshots
        self.options = options
        self.snapshots = []
        self.iteration = 0
        self.deadline = deadline
        self.out_of_time = False
        #: where no knot fits into a failing interval, its parameters go back to arc length before knots closer
        #: than min_gap are tried (the second run of :func:`fit_lsq`)
        self.reset_stuck = bool(reset_stuck)

    # ---------------------------------------------------------------- records
    def candidate(self, piece, index, accepted, reason, action):
        """A snapshot candidate record for the rotated contour ``index``."""
        contour, index = self.model.contour, int(index)  # the contour's original_index and point, on one int
        return {"piece": int(piece), "index": (index + contour.rotation) % contour.size,
                "point": tuple(contour.points[index % contour.size].tolist()), "accepted": bool(accepted),
                "reason": reason, "membership": None, "action": action}

    def corner_candidate(self, corner, reason):
        contour = self.model.contour
        return self.candidate(corner % contour.piece_count, int(contour.corner_bounds[corner]), True,
                              f"corner tip extrapolation reduced to radius {self.model.tips.radius[corner]:.2f} px "
                              f"({reason})", "release")

    def snapshot(self, dev, candidates, phase):
        if self.keep:
            self.snapshots.append(Snapshot(
                iteration=self.iteration, knot_indices=self.model.knot_lists(), bezier=dev["bezier"],
                piece_max_error=dev["piece_err"].copy(), piece_hausdorff=dev["piece_dev"].copy(),
                candidates=candidates, phase=phase, thesis_stop=False, finished=dev["piece_excess"] <= 0,
                knots=np.append(dev["starts"], dev["ends"][-1]), closed=True))

    # ---------------------------------------------------------------- rounds
    def settle(self, hoschek_steps):
        """Fit, then release the corners whose fitted point hooks away
        (:meth:`OutlineRegression.hooked_corners`) or whose pieces pass beside the pixels within the corner's
        weighting radius while the pieces beside it fit (:meth:`OutlineRegression.zone_hooks`), and refit until
        none does (each release halves a corner's extrapolation radius, so this ends), or until the time budget
        has passed (a long noisy boundary can go through dozens of releases, each a fit of the whole outline).
        Returns the release records."""
        model = self.model
        model.fit(hoschek_steps=hoschek_steps)
        released = []
        for _ in range(64):
            if self.deadline is not None and self.deadline.passed():  # the rounds stop too (run)
                break
            hooked, zone = model.hook_releases()
            if not hooked.size and not zone.size:
                break
            for c in hooked:
                model.tips.release(int(c))
                released.append(self.corner_candidate(int(c), _HOOK_REASON))
            for c in zone:
                model.tips.release(int(c))
                released.append(self.corner_candidate(int(c), _ZONE_REASON))
            model.fit(hoschek_steps=1)
        return released

    def run(self):
        model = self.model
        candidates = self.settle(2)
        dev = model.deviations(dense=True)  # many outlines already pass here: then this is the final check too
        self.snapshot(dev, candidates, "initial")
        removal_done = not self.options["remove_knots"]
        converged = merge_done = False
        while True:
            if not (dev["excess"] > 0).any():
                if not removal_done:
                    removal_done = True
                    dev = self.remove_knots(dev)
                    if model.hooks(dev).size and self.iteration < self.max_iterations:
                        self.iteration += 1
                        candidates = self.settle(1)
                        dev = model.deviations()
                        self.snapshot(dev, candidates, "insert")
                    continue
                merge_done = False
                if not dev["dense"]:  # verify with the dense check before stopping (the guarantee)
                    merged = self.merge_unverified(dev)
                    if merged is not None and merged is not dev:  # the merged outline passed its own dense check
                        dev, converged, merge_done = merged, True, True
                        break
                    merge_done = merged is dev  # nothing merged: the same fit is not merged again
                    dev = model.deviations(dense=True)
                if not (dev["excess"] > 0).any():
                    converged = True
                    break
                merge_done, self._jump_fit = False, None  # a fit that failed
            if self.iteration >= self.max_iterations:
                break
            if self.deadline is not None and self.deadline.passed():
                self.out_of_time = True
                break
            self.iteration += 1
            dev, progressed = self.insert_round(dev)
            if not progressed:
                break
        if not dev["dense"]:
            dev = model.deviations(dense=True)
            converged = converged and not (dev["excess"] > 0).any()
        if not converged and dev["pixel"] is not None and not self.out_of_time:
            # the pixel check only asks for knots: within the tolerance is converged
            converged = not (dev["tol_excess"] > 0).any()
        if converged and not merge_done:
            self.measure_jumps(dev)
            if self.options["merge_tolerance"] > 0:
                dev = self.merge(dev)
        if not converged and not self.out_of_time:
            # the deviation reported: the windowed bound can be loose on a fit that went wrong (a fit the time
            # budget stopped keeps that bound, an upper one: tightening costs as much as a round on a long noisy
            # boundary, and a stopped fit that far off gets its polygon, trace's STOPPED_FIT_LIMIT)
            dev = model.tighten(dev)
        return self.result(dev, converged)

    def measure_jumps(self, dev):
        """Keep the converged ``C^2`` fit for its curvature jumps (:attr:`jumps`) where the option
        ``curvature_jumps`` asks for them and merging is on."""
        model, jumps = self.model, self.options["curvature_jumps"]
        if jumps and (jumps is True or not model.contour.corner_count) and self.options["merge_tolerance"] > 0 \
                and not model.jump_knots.size:
            # the merged outline is G1; unmerged, the thesis's C2 fit stays ("smooth": outlines without corners)
            corner_values = model.base_parameter[model.contour.corner_bounds] if model.contour.corner_count else ()
            self._jump_fit = (dev["bezier"].copy(), dev["starts"].copy(), dev["ends"].copy(), corner_values)

    @property
    def jumps(self):
        """The curvature jumps of the converged ``C^2`` fit kept by :meth:`measure_jumps` (parameters, window
        half-widths; :func:`~.jumps.curvature_jumps`), measured on first access; none where no fit was kept."""
        if self._jump_fit is None:
            return np.zeros(0), np.zeros(0, np.int64)
        if len(self._jump_fit) == 4:
            self._jump_fit = curvature_jumps(*self._jump_fit, self.epsilon)
        return self._jump_fit

    def merge_unverified(self, dev):
        """Merging (:meth:`merge`) on a fit that passed the sparse check only: where something merges, the merged
        outline has passed the dense check (:func:`~.merge.merge_segments`), the guarantee of the result, and the
        unmerged fit's own dense check is not needed. Returns the deviations of the merged outline, ``dev`` itself
        where nothing merged (the model as it was: the unmerged fit is verified as before), None where merging is
        off. The curvature jumps (:meth:`measure_jumps`) are those of this fit."""
        if self.options["merge_tolerance"] <= 0:
            return None
        self.measure_jumps(dev)
        return self.merge(dev)

    def merge(self, dev):
        """Segment merging (:mod:`.merge`, docs/capture.md §12, "Merged segments") on the converged fit; a
        snapshot of phase ``"remove"`` records the joins that went away."""
        dev, removed = merge_segments(self.model, dev, self.options["merge_tolerance"])
        if len(removed):
            self.iteration += 1
            piece_of = self.model.contour.piece_of_point
            self.snapshot(dev, [self.candidate(piece_of[k], k, True, "merged: one cubic spans the joins beside "
                                               "it within the tolerance", "remove") for k in removed], "remove")
        return dev

    def insert_round(self, dev):
        """One insertion round; returns the new deviations and whether anything changed."""
        model = self.model
        piece_of = model.contour.piece_of_point
        new, stuck, released = model.insert(dev)
        candidates = [self.candidate(piece_of[j], j, True, f"worst point of interval {f}: deviation exceeds the "
                                     f"tolerance (or the pixel check's slack) by {excess:.2f} px", "insert")
                      for j, f, excess in new]
        for f in stuck:
            j = model.point_before(dev["starts"][f])
            candidates.append(self.candidate(piece_of[j], j, False, f"interval {f} fails but its knots are < "
                                             f"{2 * model.min_gap} steps apart", "insert"))
        for f in model.last_waived:
            j = model.point_before(dev["starts"][f])
            candidates.append(self.candidate(piece_of[j], j, False, f"interval {f} passes beside the pixels but its "
                                             f"knots are < {2 * model.min_gap} steps apart: pixel check waived there",
                                             "insert"))
        if not new and not released and stuck:
            released = model.release_corners(dev, stuck)
        if not new and not released and stuck and self.reset_stuck:
            # the parameters around the stuck intervals back to arc length (a projection onto a curve that
            # misses the contour there bunches them up and leaves knot intervals without data), then refit
            reset = model.reset_parameters(dev, stuck)
            if reset:
                for f in reset:
                    j = model.point_before(dev["starts"][f])
                    candidates.append(self.candidate(piece_of[j], j, False, f"interval {f} fails but its knots are "
                                                     f"< {2 * model.min_gap} steps apart: the parameters around it "
                                                     "go back to arc length", "insert"))
                candidates += self.settle(1)
                dev = model.deviations()
                self.snapshot(dev, candidates, "insert")
                return dev, True
        if not new and not released and stuck:
            # last resort before giving up (and the small-outline fallback): knots closer than min_gap
            waived = model.last_waived
            tight, _, released = model.insert(dev, tight=True)
            new, model.last_waived = tight, waived
            candidates += [self.candidate(piece_of[j], j, True, f"worst point of interval {f}: its knots are < "
                                          f"{2 * model.min_gap} steps apart, a knot closer than min_gap", "insert")
                           for j, f, _ in tight]
        candidates += [self.corner_candidate(c, "its zone exceeded eps + corner_allowance") for c in released]
        if model.last_waived and not new and not released:  # only waivers: measure again without them
            dev = model.deviations()
            self.snapshot(dev, candidates, "insert")
            return dev, True
        if not new and not released:
            self.snapshot(dev, candidates, "insert")
            return dev, False
        candidates += self.settle(1)
        dev = model.deviations()
        self.snapshot(dev, candidates, "insert")
        return dev, True

    def remove_knots(self, dev):
        """Knot removal: drop the cheapest half of the simple knots (no two neighbours), refit, put back the
        ones whose intervals then fail, and repeat while removals stick (at most :data:`REMOVAL_ROUNDS`). A
        round whose put-back fit still fails goes back to the fit before it; that ends the removal, except with
        C1 joints (``joint_continuity=1``: fewer, freer knots whose removals interact more), where the round is
        tried again with the cheaper half of its picks, down to one knot (:data:`REMOVAL_ROUNDS_C1` rounds)."""
        model = self.model
        share = 1.0
        retry = model.knot_multiplicity > 1
        for _ in range(REMOVAL_ROUNDS_C1 if retry else REMOVAL_ROUNDS):
            if self.iteration >= self.max_iterations:
                break
            picked = self._removal_picks(dev, share)
            if not picked:
                break
            saved, saved_dev = model.save(), dev
            dev, removed, restored = self._removal_round(dev, picked)
            if dev is None:  # back to the fit before this round (it met the tolerance)
                model.load(saved)
                dev = saved_dev
                if len(picked) == 1 or not retry:
                    break
                share *= 0.5
                continue
            if self.keep:
                piece_of = model.contour.piece_of_point
                self.snapshot(dev, [self.candidate(piece_of[k], k, True, "removed: the fit stays within the "
                                                   "tolerance", "remove") for k in removed]
                              + [self.candidate(piece_of[k], k, False, "restored: its removal broke the tolerance",
                                                "restore") for k in restored], "remove")
            if len(removed) <= max(1, len(picked) // 10):  # diminishing returns
                break
        return dev

    def _removal_round(self, dev, picked):
        """Remove ``picked``, refit, put back the picks inside failing intervals and refit. Returns the new
        deviations (None when the fit still fails), the removed and the restored knots."""
        model = self.model
        model.remove(picked)
        model.fit(hoschek_steps=1)
        dev = model.deviations()
        self.iteration += 1
        failing = np.flatnonzero(dev["excess"] > 0)
        restored = []
        if failing.size:
            lo, hi = dev["starts"][failing], dev["ends"][failing]
            values = model.base_parameter[np.asarray(picked)]
            back = (values[:, None] >= lo[None, :] - 1e-9) & (values[:, None] <= hi[None, :] + 1e-9)
            restored = [k for k, hit in zip(picked, back.any(axis=1)) if hit]
            model.restore(restored)
            model.fit(hoschek_steps=1)
            dev = model.deviations()
            if (dev["excess"] > 0).any():
                return None, [], restored
        return dev, [k for k in picked if k not in restored], restored

    def _removal_picks(self, dev, share=1.0):
        """The cheapest half of the removable knots by :meth:`OutlineRegression.removal_scores` (times
        ``share``, at least one), no two neighbours."""
        model = self.model
        removable = model.removable_knots()
        if removable.size == 0:
            return []
        scores = model.removal_scores(dev["bezier"])
        scores = scores[model.removable_mask()]  # the simple knots are unique: those in removable
        order = np.argsort(scores, kind="stable")[: max(1, int(share * (removable.size // 2)))]
        position = {int(k): i for i, k in enumerate(model.knot_indices())}
        taken, picked = set(), []
        for o in order:
            knot = int(removable[o])
            pos = position[knot]
            if pos - 1 in taken or pos + 1 in taken:
                continue
            taken.add(pos)
            picked.append(knot)
        return picked

    # ---------------------------------------------------------------- result
    def result(self, dev, converged):
        """The :class:`FitResult`; the last snapshot is made to equal it."""
        model, epsilon = self.model, self.epsilon
        contour = model.contour
        bezier = dev["bezier"]
        knots = np.append(dev["starts"], dev["ends"][-1])
        # between two corners the regression spline is the thesis's interpolant through its knot points with
        # v = 0, omega = 1 and clamped ends: interpolate(F, knots, end_condition="clamped", end_tangents=...)
        # rebuilds every piece (tests/test_fitting.py checks this piece by piece)
        spline = outline_spline(bezier, knots, {"form": "outline_fit", "method": "lsq", "epsilon": float(epsilon),
                                                "pieces": int(contour.piece_count)})
        if self.keep and self.snapshots:
            last = self.snapshots[-1]
            if np.array_equal(last.bezier, bezier) and last.iteration == self.iteration:  # same state, dense check
                last.piece_max_error = dev["piece_err"].copy()
                last.piece_hausdorff = dev["piece_dev"].copy()
                last.finished = dev["piece_excess"] <= 0
            else:
                self.snapshot(dev, [], last.phase if last.phase != "initial" else "insert")
        cornered = contour.corner_count > 0
        original = contour.original_index(contour.corner_bounds)  # the corners' indices, corner 0 again at the end
        ends = original.tolist()
        return FitResult(
            spline=spline,
            pieces=list(zip(ends[:-1], ends[1:])) if cornered else [(contour.rotation, contour.rotation)],
            knot_indices=model.knot_lists(), snapshots=self.snapshots, iterations=self.iteration,
            max_error=float(dev["piece_err"].max()), hausdorff=float(dev["piece_dev"].max()),
            converged=bool(converged), knots_inserted=int(model.simple_knots.shape[0]), method="lsq",
            epsilon=epsilon, thesis_stop_iteration=None,
            corners_used=np.sort(original[:-1]) if cornered else np.zeros(0, dtype=np.int64),
            info={"options": {k: self.options[k] for k in LSQ_OPTIONS},
                  "corner_radii": model.tips.radius.tolist() if cornered else [],
                  "tip_gaps": model.tips.gap.tolist() if cornered else [],
                  "tolerance_near_corners": epsilon + (float(model.tips.allowance.max()) if cornered
                                                       else self.options["corner_allowance"]),
                  "tips": model.tips.estimate.tolist() if cornered else [],
                  "reason": BUDGET_REASON.format(budget=self.deadline.budget)
                  if self.out_of_time and not converged else None},
        )
