"""Peak memory and time for the largest inputs the engine accepts (issue 13: bounds, not timed tests).

Each row runs in a fresh child process (``multiprocessing`` with the spawn start method), so its peak
resident set size (``ru_maxrss`` of the child) belongs to that row alone; the baseline row imports
splinecraft and does nothing else. Rows:

* ``interpolate`` / ``basis_spline`` / ``timmer_gc2`` on 10^6 points (one banded solve or closed forms);
* ``sample`` of that interpolant: the default tolerance, and ``max_points`` at its bound;
* ``basis_functions`` with 10^4 and 10^6 control points (sparse: 4 values per parameter);
* ``sample``, ``curvature_profile`` and ``curvature_comb`` at their bounds (10^7 samples) on a 1000-piece
  curve;
* ``nearest`` on the 10^6-piece interpolant;
* ``from_dict`` of a 10^5-piece curve after a JSON round trip.

Other layers may add rows to ``ROWS`` (name, function): the function runs in the child and returns a
short note for the table.

    python benchmarks/bench_limits.py              # every row
    python benchmarks/bench_limits.py --rows interpolate_1e6 basis_functions_1e6
"""
from __future__ import annotations

import argparse
import json
import multiprocessing
import platform
import resource
import sys
import time


def _walk(n, seed=0):
    import numpy as np

    rng = np.random.default_rng(seed)
    heading = np.cumsum(rng.normal(0.0, 0.3, n))
    return np.cumsum(8.0 * np.stack([np.cos(heading), np.sin(heading)], axis=1), axis=0)


def row_baseline():
    import splinecraft  # noqa: F401 (the import alone)

    return "import only"


def row_interpolate():
    import splinecraft as sc

    curve = sc.interpolate(_walk(1_000_000))
    return f"{curve.n_segments} pieces"


def row_basis_spline():
    import splinecraft as sc

    curve = sc.basis_spline(_walk(1_000_000), knots="chord")
    return f"{curve.n_segments} pieces"


def row_timmer_gc2():
    import splinecraft as sc

    curve = sc.timmer_gc2(_walk(1_000_000))
    return f"{curve.n_segments} pieces"


def row_sample_default():
    import splinecraft as sc

    params, points = sc.interpolate(_walk(1_000_000)).sample()
    return f"{len(points)} points"


def row_sample_max_points():
    import warnings

    import splinecraft as sc
    from splinecraft.spline.piecewise import MAX_SAMPLES

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        params, points = sc.interpolate(_walk(1_000)).sample(tolerance=1e-12, max_points=MAX_SAMPLES)
    return f"{len(points)} points (max_points = {MAX_SAMPLES})"


def row_basis_functions_1e4():
    import numpy as np

    import splinecraft as sc

    values = sc.basis_functions(np.linspace(1.0, 9_998.0, 100_000), 10_000)
    return f"{values.shape}, {values.nnz} stored"


def row_basis_functions_1e6():
    import numpy as np

    import splinecraft as sc

    values = sc.basis_functions(np.linspace(1.0, 999_998.0, 1_000_000), 1_000_000)
    return f"{values.shape}, {values.nnz} stored"


def row_curvature_profile():
    import splinecraft as sc
    from splinecraft.spline.piecewise import MAX_SAMPLES

    curve = sc.interpolate(_walk(1_001))
    profile = curve.curvature_profile(samples_per_piece=MAX_SAMPLES // curve.n_segments)
    return f"{len(profile.parameters)} samples"


def row_curvature_comb():
    import splinecraft as sc
    from splinecraft.spline.curvature import MAX_COMB_SAMPLES

    curve = sc.interpolate(_walk(1_001))
    bases, tips = curve.curvature_comb(samples_per_segment=MAX_COMB_SAMPLES // curve.n_segments)
    return f"{len(bases)} teeth"


def row_nearest():
    import splinecraft as sc

    curve = sc.interpolate(_walk(1_000_000))
    start = time.perf_counter()
    found = curve.nearest([100.0, 100.0])
    return f"the query alone {1e3 * (time.perf_counter() - start):.0f} ms (row: + build)"


def row_from_dict():
    import splinecraft as sc
    from splinecraft.spline.piecewise import Spline

    data = json.loads(json.dumps(sc.interpolate(_walk(100_000)).to_dict()))
    start = time.perf_counter()
    curve = Spline.from_dict(data)
    return f"{curve.n_segments} pieces; from_dict alone {time.perf_counter() - start:.2f} s (row: + build, JSON)"


ROWS = {
    "baseline": row_baseline,
    "interpolate_1e6": row_interpolate,
    "basis_spline_1e6": row_basis_spline,
    "timmer_gc2_1e6": row_timmer_gc2,
    "sample_1e6_default": row_sample_default,
    "sample_max_points": row_sample_max_points,
    "basis_functions_1e4": row_basis_functions_1e4,
    "basis_functions_1e6": row_basis_functions_1e6,
    "curvature_profile_max": row_curvature_profile,
    "curvature_comb_max": row_curvature_comb,
    "nearest_1e6": row_nearest,
    "from_dict_1e5": row_from_dict,
}


def _child(name, queue):
    start = time.perf_counter()
    note = ROWS[name]()
    elapsed = time.perf_counter() - start
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB on Linux
    queue.put((elapsed, peak_kib / 1024.0, note))


def run(name):
    context = multiprocessing.get_context("spawn")
    queue = context.Queue()
    process = context.Process(target=_child, args=(name, queue))
    process.start()
    process.join()
    if process.exitcode != 0:
        return None
    return queue.get()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rows", nargs="*", default=list(ROWS), choices=list(ROWS))
    args = parser.parse_args(argv)
    import numpy
    import scipy

    print(f"python {platform.python_version()}, numpy {numpy.__version__}, scipy {scipy.__version__}, "
          f"{platform.machine()}")
    print("| row | time | peak RSS | result |")
    print("|---|---:|---:|---|")
    for name in args.rows:
        result = run(name)
        if result is None:
            print(f"| {name} | failed | | |")
            continue
        elapsed, peak_mib, note = result
        print(f"| {name} | {elapsed:.2f} s | {peak_mib:.0f} MiB | {note} |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
