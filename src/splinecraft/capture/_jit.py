"""Options of the compiled kernels (:mod:`.fitting._kernels`, :mod:`.fitting._iso_kernels`,
:mod:`.corners._jump_kernels`, the tracer's :mod:`._cracks` and the polygons of :mod:`.fitting.budget`) and where
numba caches them.

numba compiles each kernel on its first call and keeps the machine code on disk (``cache=True``): in the
``__pycache__`` folder next to the module, else in the user's cache folder (``~/.cache/numba``), else under
``NUMBA_CACHE_DIR`` when that is set. Where none of them can be written (a read-only install run by a user
without a home folder) numba refuses ``cache=True`` when the module is imported ("no locator available").
:func:`ensure_cache_dir` then points numba's cache at a per-user folder of the temporary directory, so the
kernels still compile once per machine boot instead of failing.
"""
from __future__ import annotations

import os
import tempfile

import numba

__all__ = ["JIT_OPTIONS", "ensure_cache_dir", "warm_up_all", "KERNEL_MODULES"]

#: ``numba.njit`` options of every kernel: cached on disk, GIL released, no bounds checks, numpy's
#: floating-point error model (no ``fastmath``: results are bit for bit those of the numpy expressions), and
#: no reference counting (``_nrt=False``): the kernels only read and write arrays their wrappers allocate, so
#: numba's runtime has nothing to count; without it less code is compiled (about 5-10 % of the cold compile)
#: and an allocation inside a kernel fails to compile instead of costing compile time.
JIT_OPTIONS = dict(cache=True, nogil=True, boundscheck=False, error_model="numpy", _nrt=False)


def _writable(folder) -> bool:
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return False
    return os.access(folder, os.W_OK | os.X_OK)


def ensure_cache_dir() -> str | None:
    """Set ``numba.config.CACHE_DIR`` to a folder of the temporary directory when numba would find no writable
    place for its cache (module docstring); returns the folder numba's own rule does not cover, or ``None``."""
    if numba.config.CACHE_DIR:
        return None
    if _writable(os.path.join(os.path.dirname(os.path.abspath(__file__)), "__pycache__")):
        return None
    from numba.misc.appdirs import AppDirs

    if _writable(AppDirs(appname="numba", appauthor=False).user_cache_dir):
        return None
    user = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    folder = os.path.join(tempfile.gettempdir(), f"splinecraft-numba-{user}")
    numba.config.CACHE_DIR = folder
    return folder


ensure_cache_dir()

#: The modules with compiled kernels, each with a ``warm_up()`` (relative to :mod:`splinecraft.capture`).
KERNEL_MODULES = ("fitting._kernels", "fitting._iso_kernels", "corners._jump_kernels", "_cracks", "fitting.budget",
                  "fitting._merge_kernels")


def warm_up_all():
    """Compile (empty cache) or load every kernel; ``scripts/bootstrap.sh`` runs this after an install so
    that the first trace of a session finds the cache filled."""
    import importlib

    for name in KERNEL_MODULES:
        importlib.import_module("splinecraft.capture." + name).warm_up()
