"""The 2000 x 2000 noise image traced at the defaults (snapshots kept), in a fresh process per tree (issue 9,
session 17): CPU and wall time of ``sc.trace``, its own ``stats["time_s"]``, peak RSS, and how many of the
per-boundary fits exist afterwards (the polygons of a spent time budget are made only when read).

    for t in BEFORE/src src BEFORE/src src; do .venv/bin/python benchmarks/bench_snapshots_budget.py $t; done
"""
import resource
import sys
import time


def main(src):
    sys.path.insert(0, src)
    import numpy as np
    import splinecraft as sc

    noise = np.random.default_rng(1).random((2000, 2000)) < 0.3
    sc.trace(np.random.default_rng(2).random((60, 60)) < 0.3)   # compiles or loads the kernels, not timed
    cpu_start, wall_start = time.process_time(), time.perf_counter()
    result = sc.trace(noise)
    cpu, wall = time.process_time() - cpu_start, time.perf_counter() - wall_start
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"{src}: cpu {cpu:.2f} s, wall {wall:.2f} s, stats time_s {result.stats['time_s']:.2f}, "
          f"peak RSS {peak_mb:.0f} MB, snapshots {len(result.snapshots)}, "
          f"fits made {result.fits.made()} of {len(result.fits)}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "src")
