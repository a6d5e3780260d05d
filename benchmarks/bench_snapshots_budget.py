"""The 2000 x 2000 noise image traced at the defaults (snapshots kept), in a fresh process per tree (issue 9,
session 17): CPU and wall time of ``sc.trace``, its own ``stats["time_s"]``, peak RSS, and how many of the
per-boundary fits exist afterwards (the polygons of a spent time budget are made only when read).

    .venv/bin/python benchmarks/bench_snapshots_budget.py SRC     # SRC: a tree's src folder, e.g. src
"""
import sys, time, resource
sys.path.insert(0, sys.argv[1])
import numpy as np, splinecraft as sc
m = np.random.default_rng(1).random((2000,2000)) < 0.3
sc.trace(np.random.default_rng(2).random((60,60)) < 0.3)   # warm the kernels
c0, t0 = time.process_time(), time.perf_counter()
r = sc.trace(m)
print(sys.argv[1], f"cpu {time.process_time()-c0:.2f} s wall {time.perf_counter()-t0:.2f} s stats time_s {r.stats['time_s']:.2f} peak RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss/1024:.0f} MB snapshots {len(r.snapshots)} made {r.fits.made()} of {len(r.fits)}")
