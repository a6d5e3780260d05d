"""Stages kept between traces (capture/trace_stages.py) and the TraceExplorer's re-trace after a slider change:
a result traced with the kept stages of earlier calls is, bit for bit, the one a fresh ``sc.trace`` gives."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from splinecraft.capture import KNOT_METHODS, trace
from splinecraft.capture import TraceStages
from splinecraft.capture.trace_stages import STAGES
from splinecraft.widgets.trace_explorer import TAU_METHODS, TraceExplorer, demo_bitmap

TIMES = ("time_s", "time_breakdown", "time_per_boundary_s")


def block_with_hole(size=48, hole_radius=4.0):
    """An L-shaped block with a round hole (two boundaries, sharp corners and a curve); ``hole_radius`` 0: none."""
    yy, xx = np.mgrid[0:size, 0:size] + 0.5
    s = size / 48.0
    block = (((xx > 6 * s) & (xx < 42 * s) & (yy > 6 * s) & (yy < 24 * s))
             | ((xx > 6 * s) & (xx < 22 * s) & (yy > 6 * s) & (yy < 42 * s)))
    return block & ~((xx - 14.0 * s) ** 2 + (yy - 15.0 * s) ** 2 < (hole_radius * s) ** 2)


def scan_like(size=64, seed=3):
    """A disc with a ragged (noisy) edge and a few specks: the noise rule and the small-outline path."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:size, 0:size] + 0.5
    radius = np.hypot(xx - size / 2, yy - size / 2)
    mask = radius + rng.normal(0.0, 1.2, (size, size)) < size / 3
    mask[2:4, 2:4] = True
    mask[size - 6, size - 8] = True
    return mask


SHAPES = {"block": block_with_hole(), "demo": demo_bitmap(48), "scan": scan_like()}


def comparable(result) -> dict:
    """Everything a result holds but its times, in plain values (floats exact)."""
    document = result.to_dict(include_points=True, include_snapshots=True)
    document["stats"] = {key: value for key, value in document["stats"].items() if key not in TIMES}
    document["boundary_arrays"] = [
        [np.asarray(getattr(b, name)).tolist() for name in ("pixels", "chain_code", "outline", "crack_vertices")]
        for b in result.boundaries]
    document["corner_arrays"] = [(np.asarray(c).dtype.str, np.asarray(c).tolist()) for c in result.corners]
    document["merged"] = [(s.iteration, s.finished.tolist(), s.bezier.tolist()) for s in result.snapshots]
    document["mask"] = (result.mask.shape, np.packbits(result.mask).tobytes())
    return document


def outcome(image, **params):
    """The comparable result of ``trace(image, **params)``, or the error it raised (type and message)."""
    try:
        return comparable(trace(image, **params))
    except (ValueError, TypeError) as exc:
        return type(exc).__name__, str(exc)


# the settings a slider or a control of the explorer changes, and a few more of trace's (epsilon >= 1: the
# thesis's algorithms take a few hundred ms on these shapes below)
epsilons = st.sampled_from([1.0, 1.5, 2.0, 3.0])
other_settings = {
    "method": st.sampled_from(sorted(KNOT_METHODS)),
    "corner_method": st.sampled_from(["tangent-jump", "srm05", "ipan99", "rj73"]),
    "seed": st.integers(0, 3),
    "max_iterations": st.sampled_from([1, 3, 200]),
    "tau": st.sampled_from([None, 2.0]),
    "noise_factor": st.sampled_from([0.0, 2.0]),
    "contour": st.sampled_from(["outline", "pixels"]),
    "connectivity": st.sampled_from(["minority", 4, 8]),
    "fit_params": st.sampled_from([{"small_outline": 0}, {"small_outline": 64}]),
}
first_settings = st.fixed_dictionaries({"epsilon": epsilons}, optional=other_settings)
changes = st.fixed_dictionaries({}, optional={"epsilon": epsilons, **other_settings}).filter(
    lambda change: 1 <= len(change) <= 2)


def _valid(params):
    if params.get("tau") is not None and params.get("method") not in TAU_METHODS:
        params = {k: v for k, v in params.items() if k != "tau"}
    return params


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shape=st.sampled_from(sorted(SHAPES)), first=first_settings, change=changes)
def test_a_trace_with_kept_stages_is_the_fresh_trace(shape, first, change):
    """A change of one or two settings (a slider, a control) after a trace with others."""
    image = SHAPES[shape]
    first, second = _valid(first), _valid({**first, **change})
    stages = TraceStages()
    outcome(image, stages=stages, **first)
    kept = outcome(image, stages=stages, **second)
    assert kept == outcome(image, **second)
    # and once more from the stages both calls left
    assert outcome(image, stages=stages, **second) == kept


@pytest.mark.parametrize("base, change, recomputed", [
    ({}, {"epsilon": 1.5}, ()),
    ({}, {"seed": 5, "method": "random"}, ("contours", "noise")),  # "lsq" alone has a small-outline path
    ({"method": "positional"}, {"method": "euclidean", "tau": 3.0}, ()),  # thesis algorithms both
    ({}, {"max_iterations": 4, "fit_params": {"remove_knots": False}}, ()),
    ({}, {"corner_method": "srm05"}, ("contours", "noise")),
    ({}, {"corner_params": {"min_turn": 30.0}}, ("contours", "noise")),
    ({}, {"contour": "pixels"}, ("contours", "noise")),
    ({}, {"noise_factor": 0.0}, ("noise",)),
    ({}, {"connectivity": 4}, STAGES),
    ({}, {"min_speck_area": 0}, STAGES),
])
def test_only_the_stages_a_change_touches_run_again(base, change, recomputed):
    base = {"epsilon": 1.0, **base}
    image = block_with_hole()
    stages = TraceStages()
    trace(image, stages=stages, **base)
    assert stages.misses == dict.fromkeys(STAGES, 1) and stages.hits == dict.fromkeys(STAGES, 0)
    params = {**base, **change}
    result = trace(image, stages=stages, **params)
    for stage in STAGES:
        assert (stages.misses[stage], stages.hits[stage]) == ((2, 0) if stage in recomputed else (1, 1)), stage
    assert comparable(result) == comparable(trace(image, **params))


def test_an_epsilon_change_runs_no_corner_detection(monkeypatch):
    import importlib

    trace_module = importlib.import_module("splinecraft.capture.trace")

    calls = []
    detect = trace_module.detect_corners
    monkeypatch.setattr(trace_module, "detect_corners", lambda *a, **k: calls.append(1) or detect(*a, **k))
    stages = TraceStages()
    trace(demo_bitmap(64), epsilon=2.0, stages=stages)
    detected = len(calls)
    assert detected >= 2  # outer boundary and hole
    trace(demo_bitmap(64), epsilon=1.5, stages=stages)
    assert len(calls) == detected
    assert stages.misses["contours"] == 1 and stages.hits["contours"] == 1


def test_changing_a_result_leaves_the_next_one_as_it_was():
    image = block_with_hole()
    stages = TraceStages()
    first = trace(image, epsilon=1.0, stages=stages)
    expected = comparable(trace(image, epsilon=1.0))
    first.mask[:] = False
    first.points[0][:] = 0.0
    first.corners[0][:] = 0
    first.boundaries[0].outline[:] = -1.0
    first.notes.append("changed")
    again = trace(image, epsilon=1.0, stages=stages)
    assert stages.hits["contours"] == 1
    assert comparable(again) == expected
    again.points[0][:] = 7.0
    assert comparable(trace(image, epsilon=1.0, stages=stages)) == expected


def test_a_different_bitmap_is_a_different_key_and_old_ones_age_out():
    stages = TraceStages(size=1)
    big_hole, small_hole = block_with_hole(hole_radius=6.0), block_with_hole(hole_radius=4.0)
    for image in (big_hole, small_hole, big_hole):
        result = trace(image, epsilon=1.0, stages=stages)
        assert comparable(result) == comparable(trace(image, epsilon=1.0))
    assert stages.misses == dict.fromkeys(STAGES, 3) and stages.hits == dict.fromkeys(STAGES, 0)
    trace(big_hole, epsilon=2.0, stages=stages)
    assert stages.hits == dict.fromkeys(STAGES, 1)
    stages.clear()
    trace(big_hole, epsilon=2.0, stages=stages)
    assert stages.misses == dict.fromkeys(STAGES, 4)


def test_corners_the_budget_left_undetected_and_their_noise_are_not_kept():
    image = block_with_hole()
    stages = TraceStages()
    for _ in range(2):
        result = trace(image, epsilon=1.0, time_budget=1e-9, stages=stages)
        assert set(entry["budget"] for entry in result.stats["per_boundary"]) == {"polygon"}
    assert stages.misses["contours"] == 2 and stages.hits["contours"] == 0
    assert stages.misses["noise"] == 2 and stages.hits["noise"] == 0  # measured on those corners
    trace(image, epsilon=1.0, stages=stages)  # a budget of its own: another key
    assert stages.misses["contours"] == 3


def test_bad_stages_arguments_are_refused_by_name():
    with pytest.raises(TypeError, match="stages"):
        trace(block_with_hole(), stages={})
    with pytest.raises(ValueError, match="size"):
        TraceStages(size=-1)
    with pytest.raises(TypeError, match="size"):
        TraceStages(size="4")
    assert "size=0" in repr(TraceStages(0))


# ------------------------------------------------------------------------------------- TraceExplorer sliders
def fresh_trace_of(explorer):
    """``sc.trace`` with the explorer's settings, without kept stages."""
    method = explorer.method or None
    return trace(explorer.mask, epsilon=explorer.epsilon, method=method, corner_method=explorer.corner_method or None,
                 corner_params=explorer.corner_params, seed=explorer.seed, max_iterations=explorer.max_iterations,
                 tau=explorer.tau if method in TAU_METHODS else None)


@pytest.mark.parametrize("name, values", [
    ("epsilon", [1.5, 1.0, 2.5]),
    ("method", ["fuzzy", "euclidean", "lsq"]),
    ("seed", [3, 1]),
    ("max_iterations", [2, 200]),
    ("corner_method", ["srm05", "tangent-jump"]),
    ("corner_params", [{"min_turn": 25.0}, {"min_turn": 40.0, "tolerance": 0.5}]),
])
def test_the_explorer_after_a_slider_change_shows_the_fresh_trace(name, values):
    explorer = TraceExplorer(block_with_hole(), epsilon=2.0)
    for value in values:
        setattr(explorer, name, value)
        assert explorer.status_level == "info", explorer.status_message
        assert comparable(explorer.result) == comparable(fresh_trace_of(explorer))
    if name in ("epsilon", "seed", "max_iterations"):  # the fit's settings: corners found once
        assert explorer._stages.misses["contours"] == 1
        assert explorer._stages.hits["contours"] == len(values)


def test_the_explorer_on_a_new_image_traces_its_own_stages():
    explorer = TraceExplorer(block_with_hole(), epsilon=2.0)
    assert explorer.load(demo_bitmap(64))
    assert comparable(explorer.result) == comparable(fresh_trace_of(explorer))
    explorer.epsilon = 1.0
    assert comparable(explorer.result) == comparable(fresh_trace_of(explorer))
    assert explorer._stages.misses["contours"] == 2 and explorer._stages.hits["contours"] == 1
