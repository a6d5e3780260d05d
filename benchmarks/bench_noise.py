"""A bitmap of uniform noise end to end: wall time and peak memory of ``sc.trace`` (issue 9, "Speed": a 2000 x 2000
noise image in <= 10 s and <= 1 GB).

    .venv/bin/python benchmarks/bench_noise.py --size 2000
    .venv/bin/python benchmarks/bench_noise.py --size 2000 --compare OTHER/src --rounds 2

The image is ``np.random.default_rng(seed).random((size, size)) < ink`` (``--ink``, default 0.3: 30 % ink), traced with
``sc.trace(image, keep_snapshots=False)`` at the other defaults (``time_budget=5`` s, docs/capture.md §12,
"Time budget"). Each run is a fresh process under ``/usr/bin/time -f "rss_kb=%M elapsed=%e"`` (wall time of the
whole process, imports included, and its peak resident memory); the process also reports the in-process time
of the call, its CPU time and ``stats["time_breakdown"]``. A second fresh process times ``trace_boundaries``
alone on the same image (the contour tracer, after a first call on a tiny mask). With ``--compare SRC`` this tree and the ``src``
folder of another checkout alternate A B A B (``--rounds``); the load average is printed before and after, since
the seconds of a shared machine are only comparable within one run.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

_CHILD = """
import json, sys, time
import numpy as np
import splinecraft as sc
size, seed, ink = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
image = np.random.default_rng(seed).random((size, size)) < ink
wall, cpu = time.perf_counter(), time.process_time()
result = sc.trace(image, keep_snapshots=False)
wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
states = [entry["budget"] for entry in result.stats["per_boundary"]]
print(json.dumps({"trace_s": wall, "cpu_s": cpu, "breakdown": result.stats["time_breakdown"],
                  "boundaries": result.stats["boundaries"], "polygons": states.count("polygon"),
                  "segments": result.stats["segments"]}))
"""
# the contour tracer alone, in a process of its own (its first call loads the compiled kernels: not timed)
_TRACER_CHILD = """
import json, sys, time
import numpy as np
from splinecraft.capture.contour import trace_boundaries
size, seed, ink = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
image = np.random.default_rng(seed).random((size, size)) < ink
trace_boundaries(image[:8, :8] | np.eye(8, dtype=bool))
wall = time.perf_counter()
boundaries = trace_boundaries(image, connectivity="minority")
print(json.dumps({"tracer_s": time.perf_counter() - wall, "tracer_boundaries": len(boundaries)}))
"""


def run_once(src, size, seed, ink=0.3):
    """One fresh process on the tree whose package is under ``src``: its report plus wall time and peak RSS."""
    env = dict(os.environ, PYTHONPATH=src)
    done = subprocess.run(["/usr/bin/time", "-f", "rss_kb=%M elapsed=%e", sys.executable, "-c", _CHILD, str(size),
                           str(seed), str(ink)], capture_output=True, text=True, env=env, check=True)
    report = json.loads(done.stdout.strip().splitlines()[-1])
    timing = re.search(r"rss_kb=(\d+) elapsed=([\d.]+)", done.stderr)
    report["rss_mb"] = int(timing.group(1)) / 1024.0
    report["wall_s"] = float(timing.group(2))
    tracer = subprocess.run([sys.executable, "-c", _TRACER_CHILD, str(size), str(seed), str(ink)], capture_output=True,
                            text=True, env=env, check=True)
    report.update(json.loads(tracer.stdout.strip().splitlines()[-1]))
    return report


def _load() -> str:
    return " / ".join(f"{value:.1f}" for value in os.getloadavg())


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--ink", type=float, default=0.3, help="fraction of ink pixels (0.5: one boundary percolates "
                        "through the image, 262 000 points at --size 1000)")
    parser.add_argument("--compare", help="the src folder of another checkout (run alternately with this tree)")
    args = parser.parse_args(argv)
    trees = {"this tree": os.path.join(ROOT, "src")}
    if args.compare:
        trees["compare"] = os.path.abspath(args.compare)
    print(f"load average (1/5/15 min) before: {_load()}")
    runs = {name: [] for name in trees}
    for _ in range(args.rounds):
        for name, src in trees.items():
            runs[name].append(run_once(src, args.size, args.seed, args.ink))
            print(f"  {name}: {json.dumps(runs[name][-1])}", flush=True)
    print(f"load average (1/5/15 min) after: {_load()}")
    print(f"\n{args.size} x {args.size} noise ({100 * args.ink:g} % ink, seed {args.seed}), median of {args.rounds} "
          "fresh process(es)\n")
    print("| tree | wall (process) | sc.trace | CPU of sc.trace | peak RSS | trace_boundaries alone | boundaries "
          "(polygons) |")
    print("|---|---|---|---|---|---|---|")
    for name, reports in runs.items():
        med = {key: statistics.median(r[key] for r in reports) for key in ("wall_s", "trace_s", "cpu_s", "rss_mb",
                                                                           "tracer_s")}
        print(f"| {name} | {med['wall_s']:.1f} s | {med['trace_s']:.1f} s | {med['cpu_s']:.1f} s | "
              f"{med['rss_mb']:.0f} MB | {med['tracer_s']:.2f} s | {reports[-1]['boundaries']} "
              f"({reports[-1]['polygons']}) |")
    if args.compare:
        this, other = (statistics.median(r["wall_s"] for r in runs[name]) for name in trees)
        print(f"\nwall time ratio this / compare: {this / other:.2f}")


if __name__ == "__main__":
    main()
