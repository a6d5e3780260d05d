"""Warm ``sc.trace`` CPU time per glyph of two source trees, side by side in one run (issue 9's speed work).

    .venv/bin/python benchmarks/bench_ab.py BEFORE/src src --yardstick ../shared/yardstick --set shapes \
        [--only A,W,M] [--rounds 8] [--passes 10] [--wrap splinecraft.capture.fitting.tips:tip_estimates ...]

Each tree runs in a long-lived process of its own (``PYTHONPATH`` its ``src``, one BLAS thread), which loads the
set's bitmaps (``sc.load_bitmap``: the yardstick's own reading) and traces each once to load the kernels. Then,
round by round and in alternating order (A B, B A, ...), each process traces the whole set ``--passes`` times and
reports the mean CPU milliseconds per glyph in ``sc.trace`` and in each ``--wrap``-ped function (``module:name``,
``name`` may be ``Class.method``; where a module imported the function by name, that reference is timed too). The
per-round ratios B/A and their median are printed: two processes that alternate see the same machine, so their
ratio is steadier on a shared machine than either time.

Not the issue's target figure (``bench_peers.py`` compares with potrace); this one says whether a change made the
tracer faster. The project's tests do not use it.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))

_CHILD = r"""
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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("a", help="the first tree's src folder")
    parser.add_argument("b", help="the second tree's src folder")
    parser.add_argument("--yardstick", default=os.path.join(HERE, "..", "..", "shared", "yardstick"))
    parser.add_argument("--set", default="shapes", help="a folder of the yardstick (shapes, shapes2)")
    parser.add_argument("--only", default="", help="comma-separated glyph names of the set (default: all)")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--passes", type=int, default=5, help="passes over the set per round and tree")
    parser.add_argument("--wrap", nargs="*", default=[], help="functions to time too, module:name")
    args = parser.parse_args(argv)
    folder = os.path.join(args.yardstick, args.set)
    if not os.path.isdir(folder):
        parser.error(f"no folder {folder}")
    processes = []
    for src in (args.a, args.b):
        env = dict(os.environ, PYTHONPATH=os.path.abspath(src), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
        processes.append(subprocess.Popen([sys.executable, "-c", _CHILD, folder, args.only, json.dumps(args.wrap)],
                                          stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env,
                                          cwd=HERE))
    counts = [int(process.stdout.readline()) for process in processes]
    print(f"{counts[0]} glyphs of {folder}; A = {args.a}, B = {args.b}; ms of CPU per glyph")
    rows = ([], [])
    for round_ in range(args.rounds):
        for index in ((0, 1) if round_ % 2 == 0 else (1, 0)):
            processes[index].stdin.write(f"{args.passes}\n")
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


if __name__ == "__main__":
    main()
