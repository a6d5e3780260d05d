"""The stages of :func:`~splinecraft.capture.trace.trace` before the fit, kept for the next call.

A change of the fit's settings (``epsilon``, ``method`` among the thesis's algorithms, ``tau``, ``seed``,
``max_iterations``, ``fit_params`` other than ``small_outline``) leaves the bitmap's boundaries, their corners
and the boundary noise as they were. Passed as ``trace(..., stages=TraceStages())``, this object keeps them
(docs/capture.md §13, "Re-tracing"), each stage under a key made of exactly what it depends on:

* ``"boundaries"``: the binarized mask (its bytes, through a digest), ``connectivity`` and whether pinholes
  are filled (``min_speck_area is None``) -- the boundaries, the mask with its pinholes filled, the note;
* ``"contours"``: that key, ``contour``, the small-outline limit in force (``fit_params["small_outline"]``
  for ``"lsq"``, else 0), ``corner_method``, ``corner_params`` and ``time_budget`` -- the fitted contours,
  their corners, which take the small-outline path, and the notes; kept only when every boundary got its
  corner detection within the budget;
* ``"noise"``: that key and whether the noise rule is on (``noise_factor > 0``) -- the boundary noise and the
  corners detected again at the scale of a noisy boundary; kept only when the contours were (the noise is
  measured on their corners).

Keys compare by ``repr``, so ``7`` and ``7.0`` are different keys (a miss is always safe). Values are copied
in and out, so a result may be changed without changing the next one: a result traced with the stages of an
earlier call is the one a call without them gives, bit for bit, but for its times (``stats["time_breakdown"]``
counts the seconds of this call; ``stats["time_per_boundary_s"]`` then holds fit seconds only).
"""
from __future__ import annotations

import copy
import hashlib
import threading
from collections import OrderedDict

import numpy as np

from .._validation import check_int

__all__ = ["TraceStages", "STAGES"]

#: The stages a :class:`TraceStages` keeps, in the order :func:`~splinecraft.capture.trace.trace` runs them.
STAGES = ("boundaries", "contours", "noise")


class TraceStages:
    """The last ``size`` results of each stage of :func:`~splinecraft.capture.trace.trace` before the fit (module
    docstring); ``size=0`` keeps nothing (what ``trace`` uses without one). Safe to share between threads.

    Attributes
    ----------
    hits, misses : dict
        Per stage name (:data:`STAGES`), how many lookups found a kept result and how many computed it.
    """

    def __init__(self, size: int = 4):
        self.size = check_int(size, "size", minimum=0)
        self._entries = {stage: OrderedDict() for stage in STAGES}
        self._lock = threading.Lock()
        self.hits = dict.fromkeys(STAGES, 0)
        self.misses = dict.fromkeys(STAGES, 0)

    def __repr__(self) -> str:
        kept = {stage: len(entries) for stage, entries in self._entries.items()}
        return f"TraceStages(size={self.size}, kept={kept}, hits={self.hits})"

    def mask_key(self, mask: np.ndarray):
        """A key of a bitmap's content (shape, dtype and a digest of its bytes); ``None`` when nothing is kept."""
        if not self.size:
            return None
        mask = np.ascontiguousarray(mask)
        return (mask.shape, mask.dtype.str, hashlib.blake2b(mask.view(np.uint8).data, digest_size=16).hexdigest())

    def remember(self, stage: str, key, compute, *, keep=None):
        """The result of ``compute()`` for ``key`` in ``stage``: a copy of the kept one, else computed (and kept,
        a copy of it, unless ``keep(result)`` is false). Returns ``(result, hit)``."""
        entries = self._entries[stage]
        if self.size:
            key = repr(key)
            with self._lock:
                kept = entries.get(key)
                if kept is not None:
                    entries.move_to_end(key)
                    self.hits[stage] += 1
                    return copy.deepcopy(kept), True
        value = compute()
        with self._lock:
            self.misses[stage] += 1
            if self.size and (keep is None or keep(value)):
                entries[key] = copy.deepcopy(value)
                while len(entries) > self.size:
                    entries.popitem(last=False)
        return value, False

    def clear(self) -> None:
        """Forget every kept result."""
        with self._lock:
            for entries in self._entries.values():
                entries.clear()
