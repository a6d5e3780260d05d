"""The compiled kernels run by the Python interpreter: the first trace on a machine whose kernel cache is cold.

Every kernel is a numba dispatcher whose Python source (``dispatcher.py_func``) is the one implementation: numba
compiles it, and the interpreter can run it as it stands. Compiling the kernels of a trace takes 10-20 s of CPU on a
cold cache (docs/capture.md, "Compiled kernels"), while the interpreter runs a 300-px glyph's kernels in about 0.6-3
s (BENCHMARKS.md, "Session 32-33"). So the first trace of a machine runs them interpreted while a background process
compiles them into the cache (:func:`._jit.warm_up` with ``interpret=True``), and the traces after it load the
compiled kernels as soon as that process is done.

:func:`interpret` puts, into every ``splinecraft`` module that holds a kernel, a *clone* of it in its place: a plain
Python function with the kernel's code whose globals are its module's with every kernel replaced by its clone and
every intrinsic of the kernels (:func:`._jit.pymin`, :func:`._jit.pymax`, :func:`._jit.pyclip`,
:func:`._jit.compact`, the tips' fused multiply-add) by its stand-in (:func:`stand_in`): Python code that gives the
same value. :func:`restore` puts the kernels back. The interpreter's arithmetic is the kernels': IEEE double
precision, no ``fastmath``, numpy's scalars where the kernels read arrays (the hot loops turn them into Python
floats, the same doubles, whose arithmetic the interpreter runs about 3x faster), so a trace comes out bit for bit
the same either way (``tests/test_interpreted.py`` traces shapes both ways). The elementary functions too: compiled,
``np.arctan2``, ``np.arccos``, ``np.exp`` ... call the C library, as Python's ``math`` does, while numpy on a CPU
with AVX-512 computes them with its own vectorized routines, which differ in the last bit for about 1 % of
arguments; so the clones see numpy as :data:`LIBM_NUMPY`, whose elementary functions are ``math``'s. A kernel whose
Python semantics differ from numba's (a Python float divided by zero raises where numba gives ``inf``) raises
instead of giving another value; :func:`splinecraft.trace` then runs the compiled kernels.
"""
from __future__ import annotations

import math
import sys
import threading
import types
from fractions import Fraction

import numpy as np
from numba.core.dispatcher import Dispatcher

__all__ = ["stand_in", "interpret", "restore", "active", "compiled", "raised_in_kernel", "fused_multiply_add",
           "LIBM_NUMPY"]

#: intrinsic -> the Python function that runs in its place in interpreted kernels (:func:`stand_in`).
_STAND_INS = {}
#: kernel (dispatcher) -> its clone, and back, built once per process (:func:`_clones`).
_CLONES = {}
_KERNELS = {}
#: Whether the clones are in place (:func:`interpret`); the clones' globals; the kernels put back one by one
#: (:func:`restore_ready`).
_ACTIVE = False
_NAMESPACES = []
_BACK = set()
_LOCK = threading.RLock()


def stand_in(intrinsic, function):
    """Register ``function`` as what runs in place of ``intrinsic`` (a ``numba.extending.intrinsic``) when the
    kernels are interpreted: it must return the value the intrinsic's machine code computes. Returns
    ``intrinsic``."""
    _STAND_INS[intrinsic] = function
    return intrinsic


def fused_multiply_add(a, b, c):
    """``a * b + c`` rounded once, as LLVM's ``llvm.fma.f64``: ``math.fma`` (Python 3.13+), else the exact
    rational value rounded to the nearest double (``Fraction`` to ``float`` rounds correctly); infinities and
    NaNs as the plain expression gives them."""
    a, b, c = float(a), float(b), float(c)
    if _FMA is not None:
        return _FMA(a, b, c)
    if not (math.isfinite(a) and math.isfinite(b) and math.isfinite(c)):
        return a * b + c
    exact = Fraction(a) * Fraction(b) + Fraction(c)
    if exact == 0:  # the sign of a zero: that of the rounded product and sum
        return a * b + c
    return float(exact)


_FMA = getattr(math, "fma", None)


#: numpy's elementary functions (of float64 scalars) -> the C library's, through Python's ``math``.
_LIBM_FUNCTIONS = {"arctan2": math.atan2, "arccos": math.acos, "arcsin": math.asin, "arctan": math.atan,
                   "sin": math.sin, "cos": math.cos, "tan": math.tan, "sinh": math.sinh, "cosh": math.cosh,
                   "tanh": math.tanh, "exp": math.exp, "expm1": math.expm1, "log": math.log, "log2": math.log2,
                   "log10": math.log10, "log1p": math.log1p}


def _libm(numpy_function, libm_function):
    """``numpy_function`` with the C library's values: ``libm_function`` of float64 scalars (a numpy float64, as numpy
    gives), element by element for arrays; numpy's own value where ``math`` refuses (a domain error or an overflow:
    NaN and infinities, the C library's too)."""
    def scalar(*args):
        try:
            return np.float64(libm_function(*map(float, args)))
        except (ValueError, OverflowError):
            return numpy_function(*args)

    elementwise = np.frompyfunc(scalar, numpy_function.nin, 1)

    def function(*args):
        if all(isinstance(arg, (float, int, np.floating, np.integer)) for arg in args):
            return scalar(*args)
        return elementwise(*args).astype(np.float64)

    function.__name__ = function.__qualname__ = numpy_function.__name__
    function.__doc__ = f"``numpy.{numpy_function.__name__}`` with the C library's values (:func:`_libm`)."
    return function


class _LibmNumpy(types.ModuleType):
    """numpy as the interpreted kernels see it: its elementary functions of :data:`_LIBM_FUNCTIONS` give the C
    library's values (:func:`_libm`), everything else is numpy's."""

    def __init__(self):
        super().__init__("numpy", "numpy, with the C library's elementary functions")
        for name, value in vars(np).items():  # as fast to look up as numpy's own (the interpreted loops' names)
            if not name.startswith("__"):
                setattr(self, name, value)
        for name, libm_function in _LIBM_FUNCTIONS.items():
            setattr(self, name, _libm(getattr(np, name), libm_function))

    def __getattr__(self, name):
        return getattr(np, name)


#: numpy as the clones' globals hold it (module docstring).
LIBM_NUMPY = _LibmNumpy()


def _modules():
    return [module for name, module in list(sys.modules.items())
            if isinstance(module, types.ModuleType) and (name == "splinecraft" or name.startswith("splinecraft."))]


def _clones():
    """Every kernel of the imported ``splinecraft`` modules with its clone (module docstring). Kernels of a
    module imported later are cloned when :func:`interpret` next runs."""
    modules = _modules()
    found = {}
    for module in modules:
        for value in vars(module).values():
            if isinstance(value, Dispatcher) and value not in _CLONES:
                found[value] = module
    if not found:
        return
    namespaces = {}
    for kernel in found:
        source = kernel.py_func
        namespace = namespaces.get(id(source.__globals__))
        if namespace is None:
            namespace = namespaces[id(source.__globals__)] = ({}, source.__globals__)
        clone = types.FunctionType(source.__code__, namespace[0], source.__name__, source.__defaults__,
                                   source.__closure__)
        clone.__kwdefaults__ = source.__kwdefaults__
        clone.__qualname__, clone.__doc__, clone.__module__ = source.__qualname__, source.__doc__, source.__module__
        clone.__wrapped_kernel__ = kernel
        _CLONES[kernel], _KERNELS[clone] = clone, kernel
    for namespace, original in namespaces.values():
        _NAMESPACES.append(namespace)
        namespace.update(original)
        for name, value in original.items():
            namespace[name] = _replacement(value, namespace[name])


def _replacement(value, default):
    if value is np:
        return LIBM_NUMPY
    try:
        if value in _STAND_INS:
            return _STAND_INS[value]
        if value in _CLONES:
            return _CLONES[value]
    except TypeError:  # unhashable
        pass
    return default


def _replace(mapping, kind, modules=True):
    """Every value of type ``kind`` that is a key of ``mapping`` replaced by its value: in the ``splinecraft``
    modules (unless ``modules`` is false) and in the clones' globals."""
    places = [vars(module) for module in _modules()] if modules else []
    for namespace in places + _NAMESPACES:
        for name, value in list(namespace.items()):
            if isinstance(value, kind) and value in mapping:
                namespace[name] = mapping[value]


def interpret():
    """Put every kernel's clone in its place (module docstring); the kernels' modules are imported first. The
    clones' globals point at clones again (after :func:`restore`)."""
    global _ACTIVE
    with _LOCK:
        _clones()
        _replace(_CLONES, Dispatcher)
        _ACTIVE = True


def restore_ready(is_ready):
    """Put back, where its clone is in place, every kernel for which ``is_ready(kernel)`` (its compiled code is in the
    cache: :func:`._jit.is_cached`), in the modules and in the clones' globals (a clone goes on calling the compiled
    kernel); the others stay interpreted. Kernels that only kernels call (no Python wrapper) stay as they are:
    Python cannot call their compiled code, and they have no cache entry of their own. Returns how many came back."""
    with _LOCK:
        if not _ACTIVE:
            return 0
        ready = {clone: kernel for kernel, clone in _CLONES.items()
                 if kernel not in _BACK and not kernel.targetoptions.get("no_cpython_wrapper") and is_ready(kernel)}
        if ready:
            _replace(ready, types.FunctionType)
            _BACK.update(ready.values())
        return len(ready)


def restore():
    """Put every kernel back where :func:`interpret` put its clone (also where a module imported a clone
    meanwhile, and in the clones' globals: a clone still running in another thread calls the compiled kernels)."""
    global _ACTIVE
    with _LOCK:
        _replace(_KERNELS, types.FunctionType)
        _ACTIVE = False
        _BACK.clear()


def active() -> bool:
    """Whether the kernels are interpreted now (:func:`interpret` without :func:`restore` since)."""
    return _ACTIVE


def raised_in_kernel(error) -> bool:
    """Whether ``error`` was raised inside an interpreted kernel (a frame of a clone's code in its traceback)."""
    codes = {kernel.py_func.__code__ for kernel in _CLONES}
    trace = error.__traceback__
    while trace is not None:
        if trace.tb_frame.f_code in codes:
            return True
        trace = trace.tb_next
    return False


def compiled(value):
    """The kernel of ``value`` when it is a clone, else ``value``."""
    try:
        return _KERNELS.get(value, value)
    except TypeError:
        return value
