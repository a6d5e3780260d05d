"""The kernels' warm-up (``capture._jit.warm_up``): cold warm-up tasks are split between this process and helper
processes that compile into the shared numba cache; the result of a trace does not depend on where its kernels
were compiled."""
import json
import os
import subprocess
import sys

import numba
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import splinecraft as sc
from splinecraft.capture import _jit

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(_jit.__file__))))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from(sorted(_jit.WARM_UP_TASKS)), unique=True), st.integers(1, 5))
def test_plan_gives_every_cold_task_to_one_process(cold, processes):
    shares = _jit.plan(cold, processes)
    assert len(shares) == processes
    assert sorted(name for share in shares for name in share) == sorted(cold)
    weight = {name: task[3] for name, task in _jit.WARM_UP_TASKS.items()}
    finish = [sum(weight[name] for name in share) + (index > 0) * _jit.HELPER_START
              for index, share in enumerate(shares)]
    # longest first to the earliest finisher: no process ends later than the best one by more than one task
    if cold:
        assert max(finish) - min(finish) <= max(weight[name] for name in cold) + _jit.HELPER_START + 1e-9


def test_plan_balances_the_trace_tasks_between_two_processes():
    """The default trace's six tasks on two processes: each gets about half of the compile (the helper's
    start included), far less than all of it."""
    tasks = _jit.TRACE_TASKS + ("merge", "corners")
    mine, theirs = _jit.plan(tasks, 2)
    weight = {name: task[3] for name, task in _jit.WARM_UP_TASKS.items()}
    total = sum(weight[name] for name in tasks)
    assert mine and theirs
    assert sum(weight[name] for name in mine) < 0.6 * total
    assert sum(weight[name] for name in theirs) + _jit.HELPER_START < 0.6 * total


@pytest.mark.parametrize("setting, expected", [("1", 1), ("3", 3), (" 2 ", 2)])
def test_workers_follows_the_environment(monkeypatch, setting, expected):
    monkeypatch.setenv("SPLINECRAFT_JIT_WORKERS", setting)
    assert _jit.workers() == expected


@pytest.mark.parametrize("setting", ["0", "-2", "two", "1.5", ""])
def test_workers_ignores_settings_that_are_not_a_positive_count(monkeypatch, setting):
    monkeypatch.setenv("SPLINECRAFT_JIT_WORKERS", setting)
    monkeypatch.setattr(_jit.os, "sched_getaffinity", lambda pid: {0, 1, 2}, raising=False)
    assert _jit.workers() == 3


def test_unknown_task_is_refused():
    with pytest.raises(ValueError, match="unknown warm-up tasks"):
        _jit.warm_up(("fit solves", "no such task"))


def test_is_cached_reads_numba_s_index():
    """After a warm-up every task's kernel is in the on-disk cache; a kernel without a cache is not."""
    _jit.warm_up_all()
    assert all(_jit.is_cached(_jit._sentinel(name)) for name in _jit.WARM_UP_TASKS)

    @numba.njit(cache=False)
    def uncached(values):
        return values[0]

    uncached(np.ones(1))
    assert not _jit.is_cached(uncached)
    assert not _jit.is_cached(object())


def test_a_failing_helper_costs_only_time(monkeypatch):
    """A helper that exits with an error leaves its tasks to this process, which then runs them itself."""
    monkeypatch.setattr(_jit, "_DONE", set())
    monkeypatch.setattr(_jit, "is_cached", lambda dispatcher: False)  # every task looks cold
    monkeypatch.setattr(_jit, "workers", lambda: 2)
    started = []

    def failing_helper(names):
        started.append(list(names))
        return subprocess.Popen([sys.executable, "-c", "raise SystemExit(3)"])

    monkeypatch.setattr(_jit, "_start_helper", failing_helper)
    _jit.warm_up(("noise", "corners", "merge"))
    assert started and _jit.LAST_WARM_UP["helpers"] == started
    assert _jit.LAST_WARM_UP["failed"] == started
    assert _jit._DONE == {"noise", "corners", "merge"}
    _jit.warm_up(("noise", "corners", "merge"))  # done once per process: no second helper
    assert len(started) == 1


def test_a_helper_that_cannot_start_costs_only_time(monkeypatch):
    monkeypatch.setattr(_jit, "_DONE", set())
    monkeypatch.setattr(_jit, "is_cached", lambda dispatcher: False)
    monkeypatch.setattr(_jit, "workers", lambda: 3)
    monkeypatch.setattr(_jit.sys, "executable", "/nonexistent/python")
    _jit.warm_up(("noise", "corners", "merge"))
    assert _jit.LAST_WARM_UP["helpers"] and _jit.LAST_WARM_UP["failed"] == _jit.LAST_WARM_UP["helpers"]
    assert _jit._DONE == {"noise", "corners", "merge"}


_COLD_TRACE = """
import json, sys
import numpy as np
import splinecraft as sc
from splinecraft.capture import _jit
mask = np.zeros((40, 60), bool)
mask[8:32, 10:50] = True
mask[14:26, 20:30] = False
svg = sc.trace(mask).to_svg()
print(json.dumps({"svg": svg, "last": _jit.LAST_WARM_UP, "cached": {name: _jit.is_cached(_jit._sentinel(name))
                  for name in _jit.WARM_UP_TASKS}}))
"""


def test_cold_first_trace_compiles_in_two_processes_with_the_same_result(tmp_path):
    """A fresh process on an empty cache: a helper compiles part of the cold kernels, the trace is the one this
    (warm) process makes, and the cache then holds every kernel the trace needed."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), SPLINECRAFT_JIT_WORKERS="2",
               PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH", "")])))
    done = subprocess.run([sys.executable, "-c", _COLD_TRACE], capture_output=True, text=True, env=env,
                          timeout=600, check=True)
    child = json.loads(done.stdout.strip().splitlines()[-1])
    mask = np.zeros((40, 60), bool)
    mask[8:32, 10:50] = True
    mask[14:26, 20:30] = False
    assert child["svg"] == sc.trace(mask).to_svg()
    needed = set(_jit.TRACE_TASKS) | {"merge", "corners"}
    assert set(child["last"]["cold"]) == needed
    assert len(child["last"]["helpers"]) == 1 and child["last"]["helpers"][0]
    assert not child["last"]["failed"]
    assert all(child["cached"][name] for name in needed)
    assert not child["cached"]["polygons"]  # compiled only where a spent budget needs it
