"""One BLAS thread for the fit's dense solves (docs/capture.md §12, "Small outlines").

The small-outline path solves a dense system per chain of knots and round (:mod:`.small`; for the contours
that fall back to it from ``"lsq"``, systems of a few hundred unknowns). OpenBLAS splits such a solve over
both cores of a two-core machine, and when the other core is busy the split waits for it: the held-out
Arabic glyph qaf, whose 1652-point contour falls back, fits in 1.6 s instead of 2.5 s with one thread
(same result, BENCHMARKS.md "Speed"). The limit (threadpoolctl) holds for the duration of each fit only
(:func:`~splinecraft.capture.fitting.fit_outline` and the small-outline batches), or of all the fits of a
trace (:func:`~splinecraft.capture.trace.trace` sets it once around them; the fits inside find it set).
"""
from __future__ import annotations

import threading

from threadpoolctl import ThreadpoolController

__all__ = ["one_blas_thread"]

_CONTROLLER = []
_HELD = threading.local()


class _OneThread:
    """The limit of :func:`one_blas_thread`: set on entering unless this thread already holds it (an enclosing
    ``with``), restored on leaving the outermost one."""

    __slots__ = ("_limit",)

    def __enter__(self):
        depth = getattr(_HELD, "depth", 0)
        _HELD.depth = depth + 1
        self._limit = None
        if not depth:
            if not _CONTROLLER:
                _CONTROLLER.append(ThreadpoolController())
            try:
                self._limit = _CONTROLLER[0].limit(limits=1, user_api="blas")
                self._limit.__enter__()
            except BaseException:
                _HELD.depth = depth
                raise
        return self

    def __exit__(self, *exc_info):
        _HELD.depth -= 1
        if self._limit is not None:
            self._limit.__exit__(*exc_info)
        return False


def one_blas_thread():
    """A context manager that limits the BLAS libraries loaded in the process to one thread (about 10 µs to
    enter and leave; the libraries are looked up once per process); nested in another one of this thread it
    leaves the limit as it is (nothing to set, nothing to restore)."""
    return _OneThread()
