"""Speed of outline capture, stage by stage, and before/after a change in one run (issue 9, "Speed").

    .venv/bin/python benchmarks/bench_speed.py stages --yardstick ../shared/yardstick
    .venv/bin/python benchmarks/bench_speed.py stages --yardstick ../shared/yardstick --compare OTHER/src
    .venv/bin/python benchmarks/bench_speed.py explorer [--compare OTHER/src]
    .venv/bin/python benchmarks/bench_speed.py jit [--compare OTHER/src --rounds 3]
    .venv/bin/python benchmarks/bench_speed.py first-call --yardstick ../shared/yardstick [--shapes A,B,G,heart --rounds 1]
    .venv/bin/python benchmarks/bench_speed.py blas
    .venv/bin/python benchmarks/bench_speed.py ab --compare BEFORE/src --yardstick ../shared/yardstick [--set shapes \
        --only A,W,M --rounds 8 --passes 10 --wrap splinecraft.capture.fitting.tips:tip_estimates ...]

* ``stages``: the in-process time of ``sc.trace`` at its defaults per shape (median of ``--repeat`` runs after
  one warm-up), split by ``stats["time_breakdown"]`` (binarize, contour, corners, noise estimate, fit), median
  over the 300-px upright glyphs of the yardstick's ``shapes/`` and over the scan-like glyphs of ``shapes2/``
  (without the yardstick: the thesis's five objects of :mod:`splinecraft.datasets`), and the process CPU time
  of the call (less inflated than wall time when other work shares the cores). With ``--compare SRC``
  the same measurement runs in two fresh processes per round, this tree and the ``src`` folder of another
  checkout, alternating A B A B (``--rounds``), and the table shows both and their ratio.
* ``explorer``: TraceExplorer on each thesis object, the time from a slider change to the re-traced,
  re-drawn state (median of ``--repeat`` changes, each to a value not set before, so that nothing kept from
  an earlier trace answers it), for a slider of the fit (epsilon 1.5, 1.55, 1.6 ...) and one of the corner
  detector (tangent-jump's ``min_turn``, 24, 24.25, 24.5 ... degrees); wall time and the process CPU time
  of the change (all threads: the re-trace runs in a worker thread).
* ``jit``: the first-call cost of the compiled kernels in a fresh process with an empty kernel cache (cold)
  and again with the cache it left (warm): the time of the kernels' warm-up that ``sc.trace`` runs once per
  process (after the imports, which are not counted), wall and CPU, per kernel module (the fit, the noise
  estimate, tangent-jump's arm search, the tracer, the polygons, segment merging), the cold compile time of each
  compiled function, and the first ``sc.trace`` of a fresh process (the thesis's "ali"), cold on an empty cache
  and warm on the cache it left, imports not counted: at defaults (cold: the kernels interpreted while a background
  process compiles them; also when the compiled kernels were in place, and the next trace then) and compiling
  first (``SPLINECRAFT_JIT_INTERPRET=0``) in two processes and in one.
* ``first-call``: the first ``sc.trace`` of each of ``--shapes`` (the yardstick's ``shapes/`` glyphs, or bitmaps by
  path, e.g. ``../shared/yardstick/shapes2/dvs_S.png``; without the yardstick, the thesis's objects) in a fresh
  process on an empty kernel cache, imports not counted, at defaults
  (the kernels interpreted while a background process compiles them) and compiling first
  (``SPLINECRAFT_JIT_INTERPRET=0``), alternating; with the time until every compiled kernel is in place.
* ``blas``: the fit's small solves with the BLAS threads pinned to 1 (threadpoolctl) against the library's
  default, with the other core kept busy by a spinning process, alternating.
* ``ab``: the warm CPU time per glyph of ``--compare`` (A) and this tree (B), side by side: each tree in a
  long-lived process of its own (one BLAS thread) that loads a yardstick folder's bitmaps (``--set``, ``--only``
  some of them; ``sc.load_bitmap``) and traces each once; then, round by round in alternating order, each traces the
  set ``--passes`` times and reports the mean CPU ms per glyph in ``sc.trace`` and in each ``--wrap``-ped function
  (``module:name``, ``name`` may be ``Class.method``; a module that imported the function by name is timed too).
  Prints the per-round ratios B/A and their median: two processes that alternate see the same machine, so their
  ratio is steadier than either time (``stages --compare`` starts fresh processes and splits by stage instead).
"""
from __future__ import annotations

import argparse
import glob
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
STAGES = ("load_s", "boundaries_s", "corners_s", "noise_s", "fit_s")
LABELS = {"load_s": "binarize", "boundaries_s": "contour", "corners_s": "corners", "noise_s": "noise estimate",
          "corners_noise_s": "corners + noise estimate", "fit_s": "fit", "time_s": "sc.trace total (wall)",
          "cpu_s": "sc.trace total (process CPU time)"}
ROWS = ("load_s", "boundaries_s", "corners_s", "noise_s", "corners_noise_s", "fit_s", "time_s", "cpu_s")


def _import(src):
    sys.path.insert(0, src)
    import splinecraft  # noqa: F401

    return sys.modules["splinecraft"]


def shape_sets(yardstick, sc):
    """{group: [(name, mask)]}: 300-px upright glyphs and analytic shapes of shapes/, the scans of shapes2/."""
    sets = {}
    if yardstick and os.path.isdir(yardstick):
        for subset, group, wanted in (("shapes", "300 px (shapes/)", lambda s: True),
                                      ("shapes2", "scan-like (shapes2/)", lambda s: "scan-like" in s)):
            for path in sorted(glob.glob(os.path.join(yardstick, subset, "*.json"))):
                with open(path) as handle:
                    source = json.load(handle)["source"]
                if wanted(source):
                    sets.setdefault(group, []).append((os.path.basename(path)[:-5], sc.load_bitmap(path[:-5] + ".png")))
    else:
        from splinecraft.datasets import THESIS_OBJECTS, thesis_object

        sets["thesis objects"] = [(name, thesis_object(name)) for name in THESIS_OBJECTS]
    return sets


def measure_stages(src, yardstick, repeat):
    """Per group and stage the median over shapes of the per-shape median (seconds); run in a fresh process."""
    sc = _import(src)
    out = {}
    for group, shapes in shape_sets(yardstick, sc).items():
        per_shape = {key: [] for key in STAGES + ("time_s",)}
        per_shape["cpu_s"] = []
        for _, mask in shapes:
            sc.trace(mask)
            runs, cpu = [], []
            for _ in range(repeat):
                started = time.process_time()
                runs.append(sc.trace(mask).stats)
                cpu.append(time.process_time() - started)
            for key in STAGES + ("time_s",):
                per_shape[key].append(statistics.median(
                    r["time_s"] if key == "time_s" else r["time_breakdown"].get(key, 0.0) for r in runs))
            per_shape["cpu_s"].append(statistics.median(cpu))
        per_shape["corners_noise_s"] = [a + b for a, b in zip(per_shape["corners_s"], per_shape["noise_s"])]
        out[group] = {key: statistics.median(values) for key, values in per_shape.items()}
    return out


def _child(mode, src, args):
    command = [sys.executable, os.path.abspath(__file__), mode, "--child", src, "--repeat", str(args.repeat)]
    if getattr(args, "yardstick", None):
        command += ["--yardstick", args.yardstick]
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def compare(mode, args):
    """Alternate fresh processes of this tree (A) and ``--compare`` (B); median over rounds per figure."""
    trees = {"this tree": os.path.join(ROOT, "src"), "other": os.path.abspath(args.compare)}
    rounds = {name: [] for name in trees}
    for _ in range(args.rounds):
        for name, src in trees.items():
            rounds[name].append(_child(mode, src, args))
    return {name: _median_tree(results) for name, results in rounds.items()}


def _median_tree(results):
    if isinstance(results[0], dict):
        return {key: _median_tree([r[key] for r in results if key in r]) for key in results[0]}
    if isinstance(results[0], (list, tuple)):
        return [_median_tree(list(column)) for column in zip(*results)]
    return statistics.median(results)


def print_stages(table, other=None):
    for group, figures in table.items():
        print(f"\n#### {group}\n")
        if other is None:
            print("| stage | ms |\n|---|---|")
            for key in ROWS:
                print(f"| {LABELS[key]} | {1e3 * figures[key]:.1f} |")
            continue
        print("| stage | before (other) ms | after (this tree) ms | after / before |\n|---|---|---|---|")
        for key in ROWS:
            before, after = other[group][key], figures[key]
            ratio = f"{after / before:.2f}" if before > 0 else "-"
            print(f"| {LABELS[key]} | {1e3 * before:.1f} | {1e3 * after:.1f} | {ratio} |")


#: The explorer's sliders measured: trait name and its value at the ``k``-th change.
EXPLORER_SLIDERS = {
    "epsilon": ("epsilon", lambda k: 1.5 + 0.05 * k),
    "corner min_turn": ("corner_params", lambda k: {"min_turn": 24.0 + 0.25 * k}),
}


def measure_explorer(src, repeat):
    """Median seconds (wall and process CPU) from a slider change to the re-drawn TraceExplorer, per thesis
    object and slider."""
    _import(src)
    from splinecraft.datasets import THESIS_OBJECTS, thesis_object
    from splinecraft.widgets.trace_explorer import TraceExplorer

    out = {}
    for name in THESIS_OBJECTS:
        explorer = TraceExplorer(thesis_object(name), corner_method="tangent-jump")
        out[name] = {}
        for slider, (trait, value) in EXPLORER_SLIDERS.items():
            times = []
            for k in range(repeat + 1):
                started, cpu = time.perf_counter(), time.process_time()
                setattr(explorer, trait, value(k))
                times.append((time.perf_counter() - started, time.process_time() - cpu))
            out[name][slider] = {"wall": statistics.median(wall for wall, _ in times[1:]),
                                 "cpu": statistics.median(cpu for _, cpu in times[1:])}
    return out


def print_explorer(after, before=None):
    if before is None:
        print("| object | slider | wall ms | CPU ms |\n|---|---|---|---|")
    else:
        print("| object | slider | wall before ms | wall after ms | after / before | CPU before ms | CPU after ms "
              "| after / before |\n|---|---|---|---|---|---|---|---|")
    for name, sliders in after.items():
        for slider, figures in sliders.items():
            cells = []
            for kind in ("wall", "cpu"):
                if before is None:
                    cells.append(f"{1e3 * figures[kind]:.1f}")
                    continue
                old = before[name][slider][kind]
                cells += [f"{1e3 * old:.1f}", f"{1e3 * figures[kind]:.1f}", f"{figures[kind] / old:.2f}"]
            print(f"| {name} | {slider} | " + " | ".join(cells) + " |")


_JIT_CHILD = """
import json, time, splinecraft as sc
import scipy.ndimage, scipy.spatial, skimage.measure  # imports are not the kernels' cost
import importlib
from numba.core import event
recorder = event.RecordingListener()
event.register("numba:compile", recorder)
modules = {}
for name, module in (("fit", "fitting._kernels"), ("noise estimate", "fitting._iso_kernels"),
                     ("corners", "corners._jump_kernels"), ("tracer", "_cracks"), ("polygons", "fitting.budget"),
                     ("merge", "fitting._merge_kernels"), ("pixel corners", "_pixel_corners")):
    try:
        modules[name] = importlib.import_module("splinecraft.capture." + module)
    except ImportError:  # a tree without that kernel module
        pass
    if name in modules and not hasattr(modules[name], "warm_up"):  # a tree whose module has no kernels yet
        del modules[name]
out = {"modules": {}}
w, c = time.perf_counter(), time.process_time()
for name, module in modules.items():
    w1, c1 = time.perf_counter(), time.process_time()
    module.warm_up()
    out["modules"][name] = (time.perf_counter() - w1, time.process_time() - c1)
out["total"] = (time.perf_counter() - w, time.process_time() - c)
own, stack = {}, []  # wall seconds of each compiled function itself (its callees' compiles subtracted)
for stamp, record in recorder.buffer:
    data = record.data or {}
    key = data["dispatcher"].py_func.__qualname__ if "dispatcher" in data else "?"
    if record.is_start:
        stack.append([key, stamp, 0.0])
        continue
    key, begun, inner = stack.pop()
    own[key] = own.get(key, 0.0) + (stamp - begun) - inner
    if stack:
        stack[-1][2] += stamp - begun
out["functions"] = own
print(json.dumps(out))
"""


_TRACE_CHILD = """
import json, resource, sys, time, splinecraft as sc
import scipy.ndimage, scipy.spatial, skimage.measure  # imports are not the kernels' cost
from splinecraft.datasets import thesis_object
image = thesis_object("ali")
def cpu():  # this process and the helpers that compiled kernels for it (_jit.warm_up)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime
w, c = time.perf_counter(), cpu()
result = sc.trace(image, **json.loads(sys.argv[1]))
out = {"total": (time.perf_counter() - w, cpu() - c), "kernels": result.stats.get("kernels", "compiled")}
from splinecraft.capture import _jit
background = getattr(_jit, "_BACKGROUND", None)  # the first trace ran interpreted: the kernels compile meanwhile
if background is not None:
    background.wait()
    out["compiled"] = (time.perf_counter() - w, cpu() - c)  # from the first trace's start to the cache filled
    w2 = time.perf_counter()
    sc.trace(image, **json.loads(sys.argv[1]))
    out["second"] = time.perf_counter() - w2
print(json.dumps(out))
"""

#: The first ``sc.trace`` calls timed by the ``jit`` mode: label -> (keyword arguments, environment): at
#: defaults (since session 31 a cold first trace of a small bitmap runs the kernels interpreted while a background
#: process compiles them, ``capture._jit.warm_up``), and compiling first (``SPLINECRAFT_JIT_INTERPRET=0``, as for a
#: large bitmap: cold kernels compiled in parallel processes) in two processes and in one.
_TRACE_CALLS = {"sc.trace (defaults)": ({}, {}),
                "sc.trace (SPLINECRAFT_JIT_INTERPRET=0)": ({}, {"SPLINECRAFT_JIT_INTERPRET": "0"}),
                "sc.trace (SPLINECRAFT_JIT_INTERPRET=0, SPLINECRAFT_JIT_WORKERS=1)": (
                    {}, {"SPLINECRAFT_JIT_INTERPRET": "0", "SPLINECRAFT_JIT_WORKERS": "1"})}


def measure_jit(src):
    """Cold and warm first-call cost of the kernels of the tree ``src``: fresh processes on an empty, then a
    used, cache; per module (wall, CPU seconds) and, cold, the compile wall time of each compiled function
    itself."""
    out = {}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=src)
        for name in ("cold", "warm", "warm again"):
            done = subprocess.run([sys.executable, "-c", _JIT_CHILD], capture_output=True, text=True, env=env,
                                  check=True)
            out[name] = json.loads(done.stdout.strip().splitlines()[-1])
    for label, (kwargs, extra) in _TRACE_CALLS.items():  # the first sc.trace of a process, on an empty cache
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=src, **extra)
            for name in ("cold", "warm"):
                done = subprocess.run([sys.executable, "-c", _TRACE_CHILD, json.dumps(kwargs)], capture_output=True,
                                      text=True, env=env, check=True)
                child = json.loads(done.stdout.strip().splitlines()[-1])
                runs = out.setdefault("first trace", {}).setdefault(label, {})
                runs[name] = child["total"]
                if name == "cold":
                    runs["interpreted"] = float(child["kernels"] == "interpreted")
                    runs["compiled"] = child.get("compiled", child["total"])
                    runs["second"] = child.get("second", 0.0)
    return out


def compare_jit(args):
    """With ``--compare``: the cold and warm runs of both trees, alternating this tree and the other for
    ``--rounds`` rounds (median per figure)."""
    trees = {"this tree": os.path.join(ROOT, "src")}
    if args.compare:
        trees["other"] = os.path.abspath(args.compare)
    rounds = {name: [] for name in trees}
    for _ in range(args.rounds if args.compare else 1):
        for name, src in trees.items():
            rounds[name].append(measure_jit(src))
    return {name: _median_tree(results) for name, results in rounds.items()}


def print_jit(figures):
    print("| first call in a fresh process | cold (empty cache) wall / CPU s (helpers included) | kernels | cold: "
          "compiled kernels in place after, wall / CPU s | then the next call, s | warm (cached) wall / CPU s |\n"
          "|---|---|---|---|---|---|")
    for label, runs in figures.get("first trace", {}).items():
        kernels = "interpreted" if runs.get("interpreted", 0) >= 0.5 else "compiled"
        compiled = runs.get("compiled", runs["cold"])
        print(f"| {label} | {runs['cold'][0]:.2f} / {runs['cold'][1]:.2f} | {kernels} | {compiled[0]:.2f} / "
              f"{compiled[1]:.2f} | {runs.get('second', 0.0):.3f} | {runs['warm'][0]:.2f} / {runs['warm'][1]:.2f} |")
    print()
    print("| cache | " + " | ".join(f"{name} wall / CPU s" for name in figures["cold"]["modules"])
          + " | total wall / CPU s |")
    print("|---|" + "---|" * (len(figures["cold"]["modules"]) + 1))
    for name, run in figures.items():
        if name == "first trace":
            continue
        cells = [f"{wall:.2f} / {cpu:.2f}" for wall, cpu in run["modules"].values()]
        print(f"| {name} | " + " | ".join(cells) + f" | {run['total'][0]:.2f} / {run['total'][1]:.2f} |")
    functions = sorted(figures["cold"]["functions"].items(), key=lambda item: -item[1])
    print("\ncold compile, wall seconds per compiled function (its callees' compiles subtracted): "
          + ", ".join(f"{name} {seconds:.2f}" for name, seconds in functions if seconds >= 0.01))


_FIRST_CALL_CHILD = """
import json, sys, time, warnings
warnings.simplefilter("ignore")
import splinecraft as sc
from splinecraft.capture import _jit
image = sc.load_bitmap(sys.argv[1]) if sys.argv[1].endswith(".png") else sc.datasets.thesis_object(sys.argv[1])
w = time.perf_counter()
result = sc.trace(image)
out = {"first": time.perf_counter() - w, "kernels": result.stats.get("kernels", "compiled")}
background = getattr(_jit, "_BACKGROUND", None)
if background is not None:  # every kernel compiled and in place: the next process starts warm
    background.wait()
    out["compiled"] = time.perf_counter() - w
print(json.dumps(out))
"""


def measure_first_call(src, shapes, rounds):
    """The first ``sc.trace`` of each shape in a fresh process on an empty kernel cache, imports not counted: at
    defaults (a small bitmap's kernels interpreted while a background process compiles them) and compiling first
    (``SPLINECRAFT_JIT_INTERPRET=0``), alternating, ``rounds`` times; each run waits for its background compile,
    so runs do not overlap. Returns shape -> mode -> list of (first call s, compiled kernels in place after s)."""
    out = {}
    for _ in range(rounds):
        for shape in shapes:
            for mode, extra in (("interpreted", {}), ("compiling first", {"SPLINECRAFT_JIT_INTERPRET": "0"})):
                with tempfile.TemporaryDirectory() as cache:
                    env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=src, **extra)
                    done = subprocess.run([sys.executable, "-c", _FIRST_CALL_CHILD, shape], capture_output=True,
                                          text=True, env=env, check=True)
                child = json.loads(done.stdout.strip().splitlines()[-1])
                out.setdefault(os.path.basename(shape), {}).setdefault(mode, []).append(
                    (child["first"], child.get("compiled", child["first"]), child["kernels"]))
    return out


def print_first_call(table):
    print("| shape | first call at defaults, s | kernels | compiled kernels in place after, s | first call compiling "
          "first, s | ratio |\n|---|---|---|---|---|---|")
    for shape, modes in table.items():
        fast = statistics.median(run[0] for run in modes["interpreted"])
        ready = statistics.median(run[1] for run in modes["interpreted"])
        slow = statistics.median(run[0] for run in modes["compiling first"])
        kernels = "/".join(sorted({run[2] for run in modes["interpreted"]}))
        print(f"| {shape} | {fast:.2f} | {kernels} | {ready:.1f} | {slow:.2f} | {fast / slow:.2f} |")


def measure_blas(rounds):
    """Median seconds of the fit's dense small solves (m = 20..64) with BLAS pinned to one thread and with the
    default, while a spinning process keeps the other core busy; alternating."""
    import numpy as np
    from threadpoolctl import threadpool_limits

    rng = np.random.default_rng(0)
    systems = []
    for m in range(20, 65, 4):
        a = rng.normal(size=(m, m))
        systems.append((a @ a.T + m * np.eye(m), rng.normal(size=(m, 2))))

    def solve_all():
        started = time.perf_counter()
        for _ in range(50):
            for matrix, rhs in systems:
                np.linalg.solve(matrix, rhs)
        return time.perf_counter() - started

    spinner = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        times = {"default threads": [], "1 thread": []}
        for _ in range(rounds):
            times["default threads"].append(solve_all())
            with threadpool_limits(limits=1, user_api="blas"):
                times["1 thread"].append(solve_all())
    finally:
        spinner.kill()
        spinner.wait()
    return {key: statistics.median(values) for key, values in times.items()}


_AB_CHILD = r"""
import glob, importlib, json, os, sys, time, warnings
warnings.simplefilter("ignore")
import splinecraft as sc
folder, only, wraps = sys.argv[1], [n for n in sys.argv[2].split(",") if n], json.loads(sys.argv[3])
paths = sorted(glob.glob(os.path.join(folder, "*.png")))
paths = [p for p in paths if not only or os.path.basename(p)[:-4] in only]
images = [sc.load_bitmap(p) for p in paths]
spent = dict.fromkeys(wraps, 0.0)

def timed(original, key):
    def wrapper(*args, **kwargs):
        start = time.process_time()
        try:
            return original(*args, **kwargs)
        finally:
            spent[key] += time.process_time() - start
    return wrapper

for key in wraps:
    module_name, name = key.split(":")
    owner = importlib.import_module(module_name)
    *path, last = name.split(".")
    for part in path:
        owner = getattr(owner, part)
    original = getattr(owner, last)
    setattr(owner, last, timed(original, key))
    if not path:  # the modules that imported it by name
        for module in list(sys.modules.values()):
            if module is not None and module.__name__.startswith("splinecraft") \
                    and getattr(module, last, None) is original:
                setattr(module, last, getattr(owner, last))
for image in images:
    sc.trace(image)
print(len(images), flush=True)
for line in sys.stdin:
    passes = int(line)
    spent.update(dict.fromkeys(spent, 0.0))
    start = time.process_time()
    for _ in range(passes):
        for image in images:
            sc.trace(image)
    count = passes * len(images)
    out = {"trace": (time.process_time() - start) / count * 1e3}
    out.update({key: value / count * 1e3 for key, value in spent.items()})
    print(json.dumps(out), flush=True)
"""


def measure_ab(before, after, folder, only, rounds, passes, wraps):
    """``ab``: per round and tree the CPU ms per glyph of ``sc.trace`` and of each of ``wraps``; prints them and the
    ratios."""
    processes = []
    for src in (before, after):
        env = dict(os.environ, PYTHONPATH=os.path.abspath(src), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
        processes.append(subprocess.Popen([sys.executable, "-c", _AB_CHILD, folder, only, json.dumps(wraps)],
                                          stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env,
                                          cwd=HERE))
    counts = [int(process.stdout.readline()) for process in processes]
    print(f"{counts[0]} glyphs of {folder}; A = {before}, B = {after}; ms of CPU per glyph")
    rows = ([], [])
    for round_ in range(rounds):
        for index in ((0, 1) if round_ % 2 == 0 else (1, 0)):
            processes[index].stdin.write(f"{passes}\n")
            processes[index].stdin.flush()
            rows[index].append(json.loads(processes[index].stdout.readline()))
        a, b = rows[0][-1], rows[1][-1]
        print(f"round {round_}: " + "  ".join(f"{key} {a[key]:.3f} -> {b[key]:.3f}" for key in a), flush=True)
    for process in processes:
        process.stdin.close()
        process.wait()
    for key in rows[0][0]:
        ratios = [b[key] / a[key] for a, b in zip(*rows) if a[key] > 0]
        a_median = statistics.median(row[key] for row in rows[0])
        b_median = statistics.median(row[key] for row in rows[1])
        spread = f"{statistics.median(ratios):.3f} ({min(ratios):.3f}-{max(ratios):.3f})" if ratios else "-"
        print(f"{key}: A {a_median:.3f} ms, B {b_median:.3f} ms, B/A per round: median {spread}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mode", choices=("stages", "explorer", "jit", "first-call", "blas", "ab"))
    parser.add_argument("--shapes", default="A,B,G,heart",
                        help="first-call: yardstick shapes/ names or bitmap paths (else the thesis's objects by name)")
    parser.add_argument("--yardstick", default=os.path.join(ROOT, "..", "shared", "yardstick"))
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds of --compare (or blas)")
    parser.add_argument("--compare", default=None, help="src folder of another checkout (the 'before')")
    parser.add_argument("--set", default="shapes", help="ab: a folder of the yardstick (shapes, shapes2)")
    parser.add_argument("--only", default="", help="ab: comma-separated glyph names of the set (default: all)")
    parser.add_argument("--passes", type=int, default=5, help="ab: passes over the set per round and tree")
    parser.add_argument("--wrap", nargs="*", default=[], help="ab: functions to time too, module:name")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    args.yardstick = os.path.abspath(args.yardstick) if os.path.isdir(args.yardstick) else None
    if args.child:
        result = measure_stages(args.child, args.yardstick, args.repeat) if args.mode == "stages" \
            else measure_explorer(args.child, args.repeat)
        print(json.dumps(result))
        return
    if args.mode in ("stages", "explorer"):
        if args.compare:
            both = compare(args.mode, args)
            after, before = both["this tree"], both["other"]
        else:
            after, before = _child(args.mode, os.path.join(ROOT, "src"), args), None
        if args.mode == "stages":
            print_stages(after, before)
        else:
            print_explorer(after, before)
    elif args.mode == "first-call":
        names = [name for name in args.shapes.split(",") if name]
        # a name with a folder is a bitmap's path as it stands (a shapes2/ glyph, say); else a yardstick shapes/
        # glyph's name, or without the yardstick a thesis object's
        paths = [name for name in names if os.sep in name]
        if args.yardstick:
            shapes = [name if name in paths else os.path.join(args.yardstick, "shapes", f"{name}.png")
                      for name in names]
        else:
            from splinecraft.datasets import THESIS_OBJECTS
            shapes = [name for name in names if name in THESIS_OBJECTS or name in paths] or ["ali"]
        print_first_call(measure_first_call(os.path.join(ROOT, "src"), shapes, args.rounds))
    elif args.mode == "ab":
        if not (args.compare and args.yardstick and os.path.isdir(os.path.join(args.yardstick, args.set))):
            parser.error("ab needs --compare and a --yardstick with the folder --set")
        measure_ab(args.compare, os.path.join(ROOT, "src"), os.path.join(args.yardstick, args.set), args.only,
                   args.rounds, args.passes, args.wrap)
    elif args.mode == "jit":
        for name, figures in compare_jit(args).items():
            if args.compare:
                print(f"\n#### {name}\n")
            print_jit(figures)
    else:
        for name, seconds in measure_blas(max(args.rounds, 5)).items():
            print(f"{name}: {1e3 * seconds:.1f} ms for 600 solves (m = 20..64), other core busy")
    print(f"# load average {' '.join(f'{x:.1f}' for x in os.getloadavg())}; {re.sub(chr(10), ' ', sys.version)}")


if __name__ == "__main__":
    main()
