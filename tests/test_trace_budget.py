"""Time budget of trace (docs/capture.md §12, "Time budget"): documented, reported per boundary, never a hang."""
from __future__ import annotations

import sys

import numpy as np
import pytest

from splinecraft.capture.fitting import fit_outline
from splinecraft.capture.fitting.budget import BUDGET_REASON, Deadline, polygon_fits
from splinecraft.capture.fitting.lsq import fit_lsq
from splinecraft.capture.fitting.options import check_options
from splinecraft.capture.trace import trace


def bezier_samples(bezier, per_piece=16):
    t = np.linspace(0.0, 1.0, per_piece)[:, None]
    basis = np.hstack([(1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t**2 * (1 - t), t**3])
    return np.einsum("kj,mjd->mkd", basis, np.asarray(bezier)).reshape(-1, 2)


def distance_to_closed_polyline(points, vertices):
    a = np.asarray(vertices, float)
    ab = np.roll(a, -1, axis=0) - a
    ap = points[:, None, :] - a[None]
    t = np.clip((ap * ab).sum(-1) / (ab * ab).sum(-1), 0, 1)
    return np.linalg.norm(ap - t[..., None] * ab, axis=-1).min(axis=1)


def noise_image(size, seed):
    return np.random.default_rng(seed).random((size, size)) < 0.3


def test_spent_budget_gives_every_boundary_its_contour_polygon():
    result = trace(noise_image(48, 1), time_budget=1e-9)
    assert all(entry["budget"] == "polygon" for entry in result.stats["per_boundary"])
    assert result.stats["converged"]
    assert any("time budget" in note for note in result.notes)
    for spline, contour in zip(result.splines, result.points):
        curve = bezier_samples(spline.bezier())
        # the polygon is the contour: every curve point on the contour and every contour point on the curve
        assert distance_to_closed_polyline(curve, contour).max() < 1e-9
        assert distance_to_closed_polyline(contour, np.asarray(spline.bezier())[:, 0]).max() < 1e-9
        knots = np.asarray(spline.knots)
        assert np.all(np.diff(knots) > 0)


def test_polygon_keeps_only_turning_points():
    square = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [2, 2], [1, 2], [0, 2], [0, 1]], float)
    (fit,) = polygon_fits([square], 0.8, True)
    assert fit.spline.n_segments == 4
    assert sorted(fit.corners_used.tolist()) == [0, 2, 4, 6]
    assert fit.hausdorff == 0.0 and fit.converged and len(fit.snapshots) == 1


def test_default_budget_is_reported_and_not_reached_on_a_clean_shape():
    yy, xx = np.mgrid[:64, :64] + 0.5
    disc = (xx - 32) ** 2 + (yy - 30) ** 2 <= 20**2
    result = trace(disc)
    (entry,) = result.stats["per_boundary"]
    assert entry["budget"] is None
    (seconds,) = result.stats["time_per_boundary_s"]
    assert 0 < seconds <= result.stats["time_s"]
    assert result.params["time_budget"] == 5.0
    assert trace(disc, time_budget=None).params["time_budget"] is None


@pytest.mark.parametrize("bad, error", [(0, ValueError), (-1.0, ValueError), (float("nan"), ValueError),
                                        ("1", TypeError), (True, TypeError)])
def test_bad_time_budget_names_the_argument(bad, error):
    with pytest.raises(error, match="time_budget"):
        trace(noise_image(16, 0), time_budget=bad)


def test_lsq_rounds_stop_at_a_passed_deadline():
    angle = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    radius = 40 + 3 * np.sin(23 * angle)  # many wiggles: the first fit does not meet a tight epsilon
    points = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    options = check_options("lsq", {})
    deadline = Deadline(1e-9)
    stopped = fit_lsq(points, np.zeros(0, np.int64), 0.05, 200, False, options, deadline)
    assert not stopped.converged and stopped.iterations == 0
    assert stopped.info["reason"] == BUDGET_REASON.format(budget=1e-9)
    free = fit_outline(points, [], epsilon=0.05, keep_snapshots=False)
    assert free.iterations > 0 and free.info["reason"] is None


class _DeadlineAfterOneCheck(Deadline):
    """A deadline that passes after it has been asked once (the corner loop detects one boundary, then stops)."""

    def __init__(self, budget):
        super().__init__(budget)
        self.checks = 0

    def passed(self) -> bool:
        self.checks += 1
        return self.end is not None and self.checks > 1


def test_noise_estimate_leaves_out_boundaries_the_budget_left_without_corners(monkeypatch):
    # three clean 40-px squares: corners excluded, their crack outlines lie within 0.4 px of the blurred
    # bitmap's iso-line; counted, the corners (which the iso-line cuts) read as noise
    mask = np.zeros((60, 170), bool)
    for left in (8, 64, 120):
        mask[10:50, left:left + 40] = True
    full = trace(mask, time_budget=None)
    assert full.stats["boundary_noise"] <= 0.4
    # the module (its name is shadowed by the function in the package)
    monkeypatch.setattr(sys.modules["splinecraft.capture.trace"], "Deadline", _DeadlineAfterOneCheck)
    cut = trace(mask, time_budget=5.0)
    polygons = [entry["budget"] == "polygon" for entry in cut.stats["per_boundary"]]
    assert any(polygons) and not all(polygons)  # the budget really cut corner detection short
    assert cut.stats["boundary_noise"] <= 0.4
    assert cut.stats["tolerance"] == full.stats["tolerance"] == full.params["epsilon"]


class _DeadlinePassingAfter(Deadline):
    """A deadline that passes after it has been asked ``checks`` times."""

    def __init__(self, checks):
        super().__init__(1.0)
        self.checks, self.asked = checks, 0

    def passed(self) -> bool:
        self.asked += 1
        return self.asked > self.checks


def _stuck_speckle_outline():
    """A speckle outline on which the regression spline gets stuck (the fallback test of test_fitting)."""
    from splinecraft.capture.contour import trace_boundaries
    from splinecraft.capture.corners import corners as detect_corners

    mask = np.random.default_rng(0).random((60, 60)) < 0.3
    for boundary in trace_boundaries(mask):
        outline = np.asarray(boundary.outline, float)
        if len(outline) < 64:
            continue
        corners = np.unique(detect_corners(outline, method="tangent-jump")).astype(np.int64)
        if not fit_outline(outline, corners, fallback=False).converged:
            return outline, corners
    raise AssertionError("no stuck outline in the speckle mask")


def test_fallback_fit_is_not_started_once_the_budget_has_run_out():
    from splinecraft.capture.fitting import fit_trusted
    from splinecraft.capture.fitting.budget import FALLBACK_BUDGET_REASON

    outline, corners = _stuck_speckle_outline()
    options = check_options("lsq", {})
    rescued = fit_trusted(outline, corners, 0.8, "lsq", None, None, 200, False, 0, options, Deadline(None))
    assert rescued.converged and "fallback_from" in rescued.info  # with time, the fallback rescues it
    # the deadline holds through the knot rounds (which stop stuck, not out of time) and has passed after them
    rounds = _DeadlinePassingAfter(10**6)
    fit_trusted(outline, corners, 0.8, "lsq", None, None, 200, False, 0, dict(options, fallback=False), rounds)
    late = _DeadlinePassingAfter(rounds.asked)
    stopped = fit_trusted(outline, corners, 0.8, "lsq", None, None, 200, False, 0, options, late)
    assert not stopped.converged and "fallback_from" not in stopped.info
    assert stopped.info["reason"] == FALLBACK_BUDGET_REASON.format(budget=1.0)


def test_small_outline_rounds_stop_at_a_passed_deadline():
    from splinecraft.capture.fitting.small import fit_small_trusted

    outline, corners = _stuck_speckle_outline()  # a long outline: many insertion rounds through its points
    full = fit_small_trusted([outline], [corners], 0.3, 200, True)[0]
    assert full.converged and full.iterations > 2
    (cut,) = fit_small_trusted([outline], [corners], 0.3, 200, True, _DeadlinePassingAfter(1))
    assert not cut.converged and cut.iterations < full.iterations
    assert cut.info["reason"] == BUDGET_REASON.format(budget=1.0)
    assert cut.snapshots[-1].phase == "insert"  # no removal rounds after the deadline


def test_noise_estimate_is_not_charged_to_the_budget(monkeypatch):
    """The budget covers corner detection and fitting (docs/capture.md §12, "Time budget"); a noise estimate
    that takes long (a large image) leaves the fits their time."""
    import time as clock

    module = sys.modules["splinecraft.capture.trace"]
    real = module.boundary_noise

    def slow_noise(*args):
        clock.sleep(1.5)  # three budgets' worth
        return real(*args)

    monkeypatch.setattr(module, "boundary_noise", slow_noise)
    yy, xx = np.mgrid[:64, :64] + 0.5
    disc = (xx - 32) ** 2 + (yy - 30) ** 2 <= 20**2
    result = trace(disc, time_budget=0.5)
    (entry,) = result.stats["per_boundary"]
    assert entry["budget"] is None and result.stats["converged"]
    assert result.stats["time_breakdown"]["noise_s"] >= 1.5


def test_a_fit_the_budget_stopped_far_from_its_contour_gets_the_polygon(monkeypatch):
    """The first knot rounds of the regression spline on a long noisy boundary can be far off it (here 100+ px
    on a 100-px image): without a budget the fallback fit replaces such a fit, but a budget that ran out during
    them kept it, and the traced outline spiked across the picture (2500 px on a 300-px image of noise). A fit
    stopped more than STOPPED_FIT_LIMIT times its tolerance from its contour now gets the contour's polygon."""
    from splinecraft.capture.fitting import fit_trusted, lsq
    from splinecraft.capture.fitting.budget import STOPPED_FIT_LIMIT

    mask = np.random.default_rng(0).random((100, 100)) < 0.5
    spent = []  # the budget runs out once a boundary of 1000+ points has had one knot round
    insert_round = lsq.LsqKnotInsertion.insert_round

    def round_then_spent(self, dev):
        out = insert_round(self, dev)
        if self.model.contour.size >= 1000:
            spent.append(self.model.contour.size)
        return out

    class SpentAfterTheRound(Deadline):
        def passed(self) -> bool:
            return self.end is not None and bool(spent)

    monkeypatch.setattr(lsq.LsqKnotInsertion, "insert_round", round_then_spent)
    monkeypatch.setattr(sys.modules["splinecraft.capture.trace"], "Deadline", SpentAfterTheRound)
    result = trace(mask, min_speck_area=0)  # the raw boundaries: no pinhole or speck removal
    (k,) = [k for k, points in enumerate(result.points) if len(points) == spent[0]]
    entry = result.stats["per_boundary"][k]
    assert entry["budget"] == "polygon"
    curve = bezier_samples(result.splines[k].bezier(), per_piece=3)
    assert distance_to_closed_polyline(curve, result.points[k]).max() < 1e-9  # the contour itself
    assert any(f"the knot rounds of boundary {k} stopped more than {STOPPED_FIT_LIMIT:g} times the tolerance" in note
               for note in result.notes)
    for fit, points, entry in zip(result.fits, result.points, result.stats["per_boundary"]):
        if entry["budget"] == "stopped":
            assert fit.hausdorff <= STOPPED_FIT_LIMIT * entry["tolerance"]
    # what was replaced: that boundary's fit, stopped after one round, is far off it
    spent.clear()
    monkeypatch.undo()
    options = dict(check_options("lsq", {}), geometric_corners=False)
    outline = np.asarray(result.points[k], float)
    corners = np.asarray(result.corners[k], np.int64)
    tolerance = result.stats["per_boundary"][k]["tolerance"]
    stopped = fit_trusted(outline, np.unique(corners), tolerance, "lsq", None, None, 200, False, 0, options,
                          _DeadlinePassingAfter(1))
    assert stopped.info["reason"] == BUDGET_REASON.format(budget=1.0)
    assert stopped.hausdorff > STOPPED_FIT_LIMIT * tolerance


def test_a_passed_deadline_stops_the_corner_releases_and_skips_tightening(monkeypatch):
    """On a long noisy boundary one fit of the whole outline costs as much as a round: once the budget has passed,
    ``settle`` releases no more hooked corners (each release is another fit) and the stopped fit keeps its windowed
    deviation bound (an upper one) instead of tightening it piece by piece (docs/capture.md §12, "Time budget")."""
    from splinecraft.capture.fitting import lsq, lsq_model

    calls = {"fit": 0, "tighten": 0}
    fit, tighten = lsq_model.OutlineRegression.fit, lsq_model.OutlineRegression.tighten

    def counted_fit(self, *args, **kwargs):
        calls["fit"] += 1
        return fit(self, *args, **kwargs)

    def counted_tighten(self, *args, **kwargs):
        calls["tighten"] += 1
        return tighten(self, *args, **kwargs)

    monkeypatch.setattr(lsq_model.OutlineRegression, "fit", counted_fit)
    monkeypatch.setattr(lsq_model.OutlineRegression, "tighten", counted_tighten)
    outline, corners = _stuck_speckle_outline()
    options = dict(check_options("lsq", {}), fallback=False)
    free = lsq.fit_lsq(outline, corners, 0.8, 200, False, options, None)
    assert not free.converged and calls["fit"] > 2 and calls["tighten"] > 0  # releases and tightening, in time
    calls.update(fit=0, tighten=0)
    stopped = lsq.fit_lsq(outline, corners, 0.8, 200, False, options, Deadline(1e-9))
    assert not stopped.converged and stopped.info["reason"] == BUDGET_REASON.format(budget=1e-9)
    assert calls == {"fit": 1, "tighten": 0}
    assert np.isfinite(stopped.hausdorff) and stopped.hausdorff > 0.8  # the bound is reported, above the tolerance


@pytest.mark.parametrize("corners", [[], [0, 100, 200, 300]])
@pytest.mark.parametrize("method", ["random", "fuzzy"])
def test_thesis_rounds_stop_at_a_passed_deadline(method, corners):
    """The thesis methods' insertion rounds stop at the deadline too (they ran their max_iterations for tens of
    seconds under time_budget=0.3), with the same reason as lsq's; without one they run."""
    from splinecraft.capture.fitting.thesis import fit_thesis

    angle = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    radius = 40 + 3 * np.sin(23 * angle)
    points = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    options = check_options(method, {})
    corner_array = np.array(corners, np.int64)
    stopped = fit_thesis(points, corner_array, 0.05, method, None, np.random.default_rng(0), 200, True, options,
                         Deadline(1e-9))
    assert not stopped.converged and stopped.iterations == 0 and len(stopped.snapshots) == 1
    assert stopped.info["reason"] == BUDGET_REASON.format(budget=1e-9)
    free = fit_outline(points, corners, method=method, epsilon=0.05, max_iterations=3, keep_snapshots=False, seed=0)
    assert free.iterations == 3 and free.info["reason"] is None


def test_a_trace_with_a_thesis_method_keeps_its_time_budget():
    yy, xx = np.mgrid[0:400, 0:400] + 0.5
    disc = (xx - 200) ** 2 + (yy - 200) ** 2 <= 190 ** 2
    result = trace(disc, method="random", epsilon=0.3, max_iterations=1500, time_budget=0.3, keep_snapshots=False,
                   seed=0)
    assert result.stats["per_boundary"][0]["budget"] in ("stopped", "polygon")
    assert any("time budget of 0.3 s" in note for note in result.notes)
