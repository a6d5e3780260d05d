"""One BLAS thread for the fit's dense solves (docs/capture.md §12, "Small outlines").

The small-outline path solves a dense system per chain of knots and round (:mod:`.small`; for the contours
that fall back to it from ``"lsq"``, systems of a few hundred unknowns). OpenBLAS splits such a solve over
both cores of a two-core machine, and when the other core is busy the split waits for it: the held-out
Arabic glyph qaf, whose 1652-point contour falls back, fits in 1.6 s instead of 2.5 s with one thread
(same result, BENCHMARKS.md "Speed"). The limit (threadpoolctl) holds for the duration of each fit only
(:func:`~splinecraft.capture.fitting.fit_outline` and the small-outline batches).
"""
from __future__ import annotations

from threadpoolctl import ThreadpoolController

__all__ = ["one_blas_thread"]

_CONTROLLER = []


def one_blas_thread():
    """A context manager that limits the BLAS libraries loaded in the process to one thread (about 10 µs to
    enter and leave; the libraries are looked up once per process)."""
    if not _CONTROLLER:
        _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0].limit(limits=1, user_api="blas")
