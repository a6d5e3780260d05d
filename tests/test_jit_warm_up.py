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

from cold_process import HOLED_RECTANGLE, holed_rectangle, run_cold

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
    # longest first to the earliest finisher: no process ends later than the best one by more than one task and
    # the processes' difference in start (a helper may start earlier than this process: a negative HELPER_START)
    if cold:
        assert max(finish) - min(finish) <= max(weight[name] for name in cold) + abs(_jit.HELPER_START) + 1e-9


def _finishes(shares):
    return [sum(_jit.WARM_UP_TASKS[name][3] for name in share) + (index > 0) * _jit.HELPER_START
            for index, share in enumerate(shares)]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from(sorted(_jit.WARM_UP_TASKS)), unique=True), st.integers(1, 3))
def test_plan_finishes_as_early_as_any_split(cold, processes):
    """Where every split is tried (up to 7 tasks on 3 processes), no split of the tasks finishes earlier."""
    import itertools

    best = min(max(_finishes([[name for name, at in zip(cold, places) if at == index] for index in range(processes)]))
               for places in itertools.product(range(processes), repeat=len(cold)))
    assert max(_finishes(_jit.plan(cold, processes))) == pytest.approx(best)


def test_plan_of_the_trace_tasks_beats_longest_first():
    """The default trace's seven tasks on two processes: the planned split finishes no later than longest first
    (each task to the process that would finish it earliest), and within the smallest task of each other."""
    tasks = _jit.TRACE_TASKS + ("merge", "corners", "pixel corners")
    loads, greedy = [0.0, _jit.HELPER_START], [[], []]
    for name in sorted(tasks, key=lambda task: -_jit.WARM_UP_TASKS[task][3]):
        at = 0 if loads[0] <= loads[1] else 1
        loads[at] += _jit.WARM_UP_TASKS[name][3]
        greedy[at].append(name)
    finishes = _finishes(_jit.plan(tasks, 2))
    assert max(finishes) <= max(_finishes(greedy)) + 1e-9
    assert max(finishes) - min(finishes) <= min(_jit.WARM_UP_TASKS[name][3] for name in tasks) + 1e-9


@pytest.mark.parametrize("task, kernels", [("corners", "splinecraft.capture.corners._jump_kernels"),
                                           ("noise", "splinecraft.capture.fitting._iso_kernels"),
                                           ("pixel corners", "splinecraft.capture._pixel_corners")])
def test_the_helper_imports_only_its_kernel_modules(tmp_path, task, kernels):
    """The helper's program registers bare parent packages: compiling the corner kernels imports neither the
    trace, the fit nor the corner detectors, nor scipy's image modules (the noise estimate's warm-up compiles
    its kernel with weights of its own, not scipy.ndimage's Gaussian)."""
    code = _jit._HELPER_CODE.replace(
        "os._exit(0)", "import json; print(json.dumps(sorted(m for m in sys.modules if m.startswith(('splinecraft', "
        "'scipy.ndimage', 'scipy.spatial'))))); sys.stdout.flush(); os._exit(0)")
    assert code != _jit._HELPER_CODE
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), SPLINECRAFT_JIT_WORKERS="1",
               PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH", "")])))
    done = subprocess.run([sys.executable, "-c", code, str(os.getpid()), task], cwd=SRC, env=env,
                          capture_output=True, text=True, timeout=300, check=True)
    modules = json.loads(done.stdout.strip().splitlines()[-1])
    assert kernels in modules
    assert not {"splinecraft.capture.trace", "splinecraft.capture.fitting.lsq", "splinecraft.capture.corners._jump",
                "splinecraft.spline", "scipy.ndimage", "scipy.spatial"} & set(modules)


def test_the_helper_passes_numba_s_blas_check_without_scipy_linalg(tmp_path):
    """numba's set-up checks for BLAS by importing scipy.linalg (0.15-0.2 s): the helper passes the check with
    a stand-in, so BLAS counts as present as in this process (np.dot would compile the same code in both), and
    the stand-ins are gone once the check is done."""
    import numba.np.arraymath

    code = _jit._HELPER_CODE.replace(
        "os._exit(0)", "import json, numba.np.arraymath as arraymath; print(json.dumps({'blas': arraymath._HAVE_BLAS, "
        "'linalg': sorted(m for m in sys.modules if m.startswith('scipy.linalg')), 'left': [sys.modules.get(m) is "
        "not None for m in ('scipy.linalg.cython_blas', 'scipy.__config__')]})); sys.stdout.flush(); os._exit(0)")
    assert code != _jit._HELPER_CODE
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), SPLINECRAFT_JIT_WORKERS="1",
               PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH", "")])))
    done = subprocess.run([sys.executable, "-c", code, str(os.getpid()), "corners"], cwd=SRC, env=env,
                          capture_output=True, text=True, timeout=300, check=True)
    helper = json.loads(done.stdout.strip().splitlines()[-1])
    assert helper["blas"] == numba.np.arraymath._HAVE_BLAS
    assert helper["linalg"] == []
    assert helper["left"] == [False, False]


def test_plan_balances_the_trace_tasks_between_two_processes():
    """The default trace's seven tasks on two processes: each gets about half of the compile (the helper's
    start included), far less than all of it."""
    tasks = _jit.TRACE_TASKS + ("merge", "corners", "pixel corners")
    mine, theirs = _jit.plan(tasks, 2)
    weight = {name: task[3] for name, task in _jit.WARM_UP_TASKS.items()}
    total = sum(weight[name] for name in tasks)
    assert mine and theirs
    assert sum(weight[name] for name in mine) < 0.6 * total
    assert sum(weight[name] for name in theirs) + _jit.HELPER_START < 0.6 * total


@pytest.mark.parametrize("setting, expected", [("1", 1), ("3", 3), (" 2 ", 2), ("9", 4), ("", 4)])
def test_workers_follows_the_environment_up_to_the_cpus(monkeypatch, recwarn, setting, expected):
    monkeypatch.setenv("SPLINECRAFT_JIT_WORKERS", setting)
    monkeypatch.setattr(_jit, "_cpus", lambda: 4)
    assert _jit.workers() == expected
    assert not recwarn.list


@pytest.mark.parametrize("setting", ["0", "-2", "two", "1.5", "+2", "\u00b2", "\u0663"])
def test_workers_ignores_other_settings_with_a_warning(monkeypatch, setting):
    """Not a whole number from 1 (zero, signs, decimals, non-ASCII digits that ``int`` refuses or reads):
    a warning names the value, and the CPUs are used."""
    monkeypatch.setenv("SPLINECRAFT_JIT_WORKERS", setting)
    monkeypatch.setattr(_jit, "_cpus", lambda: 3)
    with pytest.warns(RuntimeWarning, match="SPLINECRAFT_JIT_WORKERS"):
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


@pytest.mark.parametrize("executable", ["/nonexistent/python", None, ""])
def test_a_helper_that_cannot_start_costs_only_time(monkeypatch, executable):
    """No interpreter to start (a bad path, or an embedded Python whose ``sys.executable`` is None or empty) and
    no fork (``SPLINECRAFT_JIT_FORK=0``; elsewhere than Linux, or other threads running); where this process may
    fork, its helpers need no interpreter and do not fail."""
    monkeypatch.setattr(_jit, "_DONE", set())
    monkeypatch.setattr(_jit, "is_cached", lambda dispatcher: False)
    monkeypatch.setattr(_jit, "workers", lambda: 3)
    monkeypatch.setattr(_jit.sys, "executable", executable)
    monkeypatch.setenv("SPLINECRAFT_JIT_FORK", "0")
    _jit.warm_up(("noise", "corners", "merge"))
    assert _jit.LAST_WARM_UP["helpers"] and _jit.LAST_WARM_UP["failed"] == _jit.LAST_WARM_UP["helpers"]
    assert _jit._DONE == {"noise", "corners", "merge"}
    if sys.platform.startswith("linux"):
        monkeypatch.delenv("SPLINECRAFT_JIT_FORK")
        monkeypatch.setattr(_jit, "_can_fork", lambda: True)  # whatever threads earlier tests left running
        monkeypatch.setattr(_jit, "_DONE", set())
        _jit.warm_up(("noise", "corners", "merge"))
        assert _jit.LAST_WARM_UP["helpers"] and not _jit.LAST_WARM_UP["failed"]
        assert all(_jit.LAST_WARM_UP["forked"])
        assert _jit._DONE == {"noise", "corners", "merge"}


def test_an_interrupted_warm_up_stops_its_helpers(monkeypatch):
    """KeyboardInterrupt (Jupyter's "interrupt kernel") while this process compiles: the helper is stopped, not
    left compiling for nobody."""
    monkeypatch.setattr(_jit, "_DONE", set())
    monkeypatch.setattr(_jit, "is_cached", lambda dispatcher: False)
    monkeypatch.setattr(_jit, "workers", lambda: 2)
    started = []

    def slow_helper(names):
        started.append(subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"]))
        return started[-1]

    def interrupted(name):
        def run():
            raise KeyboardInterrupt
        return run

    monkeypatch.setattr(_jit, "_start_helper", slow_helper)
    monkeypatch.setattr(_jit, "_function", interrupted)
    with pytest.raises(KeyboardInterrupt):
        _jit.warm_up(("noise", "corners", "merge"))
    assert started and started[0].poll() is not None


def test_the_helper_uses_this_process_s_package_whatever_the_working_folder(monkeypatch, tmp_path):
    """``python -c`` puts the working folder first on the import path: a folder holding another splinecraft
    must not be the one the helper compiles."""
    shadow = tmp_path / "splinecraft"
    shadow.mkdir()
    (shadow / "__init__.py").write_text("raise ImportError('the shadow copy was imported')\n")
    monkeypatch.chdir(tmp_path)
    helper = _jit._spawn_helper(["noise"])  # a warm cache here: it only loads
    assert helper is not None and helper.wait(timeout=120) == 0


_CAN_FORK = """
import json, os, threading
from splinecraft.capture import _jit
seen = {"alone": _jit._can_fork()}
release = threading.Event()
other = threading.Thread(target=release.wait)
other.start()
seen["another thread"] = _jit._can_fork()
release.set()
other.join()
seen["alone again"] = _jit._can_fork()
worker = threading.Thread(target=lambda: seen.__setitem__("from a worker thread", _jit._can_fork()))
worker.start()
worker.join()
os.environ["SPLINECRAFT_JIT_FORK"] = "0"
seen["SPLINECRAFT_JIT_FORK=0"] = _jit._can_fork()
print(json.dumps(seen))
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="forks only on Linux")
def test_a_helper_is_forked_only_where_no_other_python_thread_runs(tmp_path):
    """A fork copies only the forking thread: a lock another thread holds (Jupyter's kernel threads, a worker
    thread tracing) would stay held in the child. In a fresh process with one thread the helper is forked; with
    two, or from a thread other than the main one, or with ``SPLINECRAFT_JIT_FORK=0``, it is a fresh
    interpreter."""
    env = {key: value for key, value in os.environ.items() if key != "SPLINECRAFT_JIT_FORK"}
    env.update(NUMBA_CACHE_DIR=str(tmp_path),
               PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH", "")])))
    done = subprocess.run([sys.executable, "-c", _CAN_FORK], env=env, capture_output=True, text=True, timeout=300,
                          check=True)
    assert json.loads(done.stdout.strip().splitlines()[-1]) == {
        "alone": True, "another thread": False, "alone again": True, "from a worker thread": False,
        "SPLINECRAFT_JIT_FORK=0": False}


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="forks only on Linux")
def test_a_forked_helper_is_waited_for_like_a_process():
    """Its exit status (0: its tasks are in the cache; a warm cache here: it only loads)."""
    helper = _jit._fork_helper(["noise"])
    assert isinstance(helper, _jit._Forked)
    assert helper.wait(timeout=120) == 0 and helper.poll() == 0 and helper.returncode == 0


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="forks only on Linux")
def test_a_stuck_forked_helper_costs_only_time(monkeypatch):
    """A forked helper that uses no CPU (blocked for good on a lock some thread held at the fork) is stopped
    after ``FORK_STALL`` seconds, and this process compiles its tasks, instead of waiting ``HELPER_TIMEOUT``."""
    import time

    monkeypatch.setattr(_jit, "_DONE", set())
    monkeypatch.setattr(_jit, "is_cached", lambda dispatcher: False)
    monkeypatch.setattr(_jit, "workers", lambda: 2)
    monkeypatch.setattr(_jit, "FORK_STALL", 0.5)
    monkeypatch.setattr(_jit, "_can_fork", lambda: True)  # whatever threads earlier tests left running
    here, real = os.getpid(), _jit._function

    def stuck_in_the_child(name):
        if os.getpid() != here:
            time.sleep(120)  # no CPU, as on a lock
        return real(name)

    monkeypatch.setattr(_jit, "_function", stuck_in_the_child)
    start = time.monotonic()
    _jit.warm_up(("noise", "corners", "merge"))
    assert time.monotonic() - start < 60
    assert _jit.LAST_WARM_UP["forked"] == [True]
    assert _jit.LAST_WARM_UP["failed"] == _jit.LAST_WARM_UP["helpers"] and _jit.LAST_WARM_UP["helpers"][0]
    assert _jit._DONE == {"noise", "corners", "merge"}


_ORPHAN = """
import sys, time
from splinecraft.capture import _jit
helper = getattr(_jit, sys.argv[1])(list(_jit.WARM_UP_TASKS))  # about 7 s of compiling
print(helper.pid, flush=True)
time.sleep(600)
"""


def _alive(pid):
    try:
        with open(f"/proc/{pid}/status") as status:
            return not any(line.startswith("State:") and "Z" in line.split()[1] for line in status)
    except FileNotFoundError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("start", ["_spawn_helper", "_fork_helper"])
def test_a_helper_exits_when_its_parent_is_killed(tmp_path, start):
    """A helper (a fresh interpreter or a fork) compiling on an empty cache whose parent dies (killed, or the
    kernel restarted) stops within a second instead of compiling for nobody."""
    import time

    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path),
               PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH", "")])))
    parent = subprocess.Popen([sys.executable, "-c", _ORPHAN, start], env=env, stdout=subprocess.PIPE, text=True)
    try:
        pid = int(parent.stdout.readline())
        time.sleep(0.5)
        assert _alive(pid)
    finally:
        parent.kill()
        parent.wait()
    deadline = time.monotonic() + 2.0  # far less than its compile: it stopped, not finished
    while _alive(pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _alive(pid)


_COLD_TRACE = """
import json, sys
import numpy as np
import splinecraft as sc
from splinecraft.capture import _jit
""" + HOLED_RECTANGLE + """
svg = sc.trace(mask).to_svg()
print(json.dumps({"svg": svg, "last": _jit.LAST_WARM_UP, "cached": {name: _jit.is_cached(_jit._sentinel(name))
                  for name in _jit.WARM_UP_TASKS}}))
"""


@pytest.mark.parametrize("fork", ["1", "0"])
def test_cold_first_trace_compiles_in_two_processes_with_the_same_result(tmp_path, fork):
    """A fresh process on an empty cache that does not interpret its first trace (``SPLINECRAFT_JIT_INTERPRET=0``,
    as a bitmap too large to interpret): a helper (forked, or with ``SPLINECRAFT_JIT_FORK=0`` a fresh
    interpreter) compiles part of the cold kernels, the trace is the one this (warm) process makes, and the
    cache then holds every kernel the trace needed."""
    child = run_cold(_COLD_TRACE, tmp_path, timeout=600, SPLINECRAFT_JIT_WORKERS="2", SPLINECRAFT_JIT_FORK=fork,
                     SPLINECRAFT_JIT_INTERPRET="0")
    assert child["svg"] == sc.trace(holed_rectangle()).to_svg()
    needed = set(_jit.TRACE_TASKS) | {"merge", "corners", "pixel corners"}
    assert set(child["last"]["cold"]) == needed
    assert len(child["last"]["helpers"]) == 1 and child["last"]["helpers"][0]
    assert not child["last"]["failed"]
    assert child["last"]["forked"] == [fork == "1" and sys.platform.startswith("linux")]
    assert all(child["cached"][name] for name in needed)
    assert not child["cached"]["polygons"]  # compiled only where a spent budget needs it


_COMPILES_NOTHING = r'''
import json, sys, warnings
import numpy as np
from numba.core.registry import CPUDispatcher
import splinecraft as sc
from splinecraft.capture import _jit

def signatures():
    return {f"{module.__name__}.{name}": len(value.signatures) for module in list(sys.modules.values())
            if module is not None and module.__name__.startswith("splinecraft")
            for name, value in list(vars(module).items()) if isinstance(value, CPUDispatcher)}

_jit.warm_up(_jit.TRACE_TASKS + ("merge", "corners", "pixel corners"))
before = signatures()
rng = np.random.default_rng(5)
images = [sc.datasets.thesis_object(name, 160) for name in sc.datasets.THESIS_OBJECTS]
images += [sc.datasets.shape(name, 96) for name in sc.datasets.SHAPES]
images += [sc.datasets.shape("star", 40), sc.datasets.shape("disc", 16)]
noisy = sc.datasets.thesis_object("D", 200).copy()
noisy ^= rng.random(noisy.shape) < 0.04  # ragged boundaries, specks and pinholes: the noise rule and the small fits
images.append(noisy)
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    for image in images:
        sc.trace(image)
after = signatures()
print(json.dumps({name: count - before.get(name, 0) for name, count in after.items() if count > before.get(name, 0)}))
'''


def test_a_default_trace_compiles_nothing_its_warm_up_left_out():
    """Every compiled kernel a default trace calls is compiled (cold cache) or loaded (warm) by the warm-up tasks
    ``trace`` runs before its time budget starts: a kernel compiled inside the budget would spend it on compiling
    and the trace would depend on where its kernels were compiled. A fresh interpreter runs the warm-up, then
    traces the thesis's objects, the teaching shapes, small outlines and a noisy bitmap; no kernel may gain a
    signature meanwhile."""
    env = dict(os.environ, SPLINECRAFT_JIT_WORKERS="1",
               PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH", "")])))
    done = subprocess.run([sys.executable, "-c", _COMPILES_NOTHING], cwd=SRC, env=env, capture_output=True,
                          text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-3000:]
    compiled = json.loads(done.stdout.strip().splitlines()[-1])
    assert compiled == {}, f"compiled during the traces, not by the warm-up: {compiled}"
