"""The kernels run by the interpreter (``capture._interpreted``): the first trace on a cold kernel cache runs their
Python source while a background process compiles them; the results are those of the compiled kernels."""
import contextlib
import importlib
import math
import sys
import types
import warnings
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from numba import njit
from numba.core.dispatcher import Dispatcher

import splinecraft as sc
from splinecraft.capture import _interpreted, _jit
from splinecraft.capture.fitting import _tip_kernels

from cold_process import HOLED_RECTANGLE, holed_rectangle, run_cold

trace_module = importlib.import_module("splinecraft.capture.trace")


@pytest.fixture
def interpreted():
    """Every kernel of the imported modules replaced by its clone for the test, and put back after it (the trace's
    compiled kernels loaded first: a trace's warm-up finds them done)."""
    _jit.warm_up(_jit.TRACE_TASKS + ("merge", "corners", "pixel corners"))
    _interpreted.interpret()
    try:
        yield
    finally:
        _interpreted.restore()


def _kernels_in_place():
    return [(module.__name__, name) for module in _interpreted._modules() for name, value in vars(module).items()
            if isinstance(value, Dispatcher)]


def test_interpret_replaces_every_kernel_and_restore_puts_each_back():
    kernels = _kernels_in_place()
    assert len(kernels) > 30
    _interpreted.interpret()
    try:
        assert _interpreted.active() and _jit.interpreting()
        assert _kernels_in_place() == []
        module = sys.modules["splinecraft.capture.fitting._kernels"]
        clone = module._deviation_into
        assert not isinstance(clone, Dispatcher) and clone.__code__ is _interpreted.compiled(clone).py_func.__code__
        # the clone's globals: kernels are clones, intrinsics their stand-ins
        assert clone.__globals__["_walk_right"] is _interpreted._CLONES[_interpreted.compiled(module._walk_right)]
        assert clone.__globals__["pyclip"] is _jit._clip and clone.__globals__["pymin"] is min
    finally:
        _interpreted.restore()
    assert not _interpreted.active()
    assert _kernels_in_place() == kernels


@contextlib.contextmanager
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


def _masks():
    rng = np.random.default_rng(11)
    masks = [sc.datasets.shape(name, 64) for name in ("star", "square", "blob")]
    masks.append(sc.datasets.thesis_object("ali", 90))
    noisy = sc.datasets.shape("blob", 80).copy()
    noisy ^= rng.random(noisy.shape) < 0.03  # ragged boundaries, specks and pinholes
    masks.append(noisy)
    return masks


def test_interpreted_traces_are_the_compiled_ones_bit_for_bit(interpreted):
    """Every stage of a trace (tracer, corners, noise estimate, tips, fit, merge) through the kernels' Python source:
    the same SVG, the same corners, the same fits as the compiled kernels."""
    masks = _masks()
    with _quiet():
        slow = [sc.trace(mask) for mask in masks]
    _interpreted.restore()
    with _quiet():
        fast = [sc.trace(mask) for mask in masks]
    for a, b in zip(slow, fast):
        assert a.to_svg() == b.to_svg()
        assert all(np.array_equal(x, y) for x, y in zip(a.corners, b.corners))
        assert len(a.bezier()) == len(b.bezier())
        assert all(np.array_equal(x, y) for x, y in zip(a.bezier(), b.bezier()))  # every bit, not 4 decimals


#: Compiled ``np.<name>`` of every elementary function of ``LIBM_NUMPY`` against the interpreted kernels' (scalars and
#: arrays, and arguments where ``math`` refuses), and numpy's own, in a process with numpy's SIMD dispatch as it is.
_LIBM_PROGRAM = """
import json
import numpy as np
from numba import njit
from splinecraft.capture import _interpreted

rng = np.random.default_rng(5)
special = np.array([np.nan, np.inf, -np.inf, 0.0, -0.0, 2.0, -2.0, 1e3, -1e3, 1e308])
mismatches, numpy_own = {}, {}
for name, libm_function in _interpreted._LIBM_FUNCTIONS.items():
    two = getattr(np, name).nin == 2
    namespace = {"np": np, "njit": njit}
    exec(f"@njit\\ndef kernel(x, y, out):\\n    for i in range(x.shape[0]):\\n"
         f"        out[i] = np.{name}(x[i]{', y[i]' if two else ''})", namespace)
    low, high = {"arccos": (-1, 1), "arcsin": (-1, 1), "log": (1e-6, 1e3), "log2": (1e-6, 1e3), "log10": (1e-6, 1e3),
                 "log1p": (-0.99, 1e3), "exp": (-700, 700), "expm1": (-700, 700), "sinh": (-700, 700),
                 "cosh": (-700, 700)}.get(name, (-50, 50))
    x = np.concatenate([rng.uniform(low, high, 20000), special])
    y = np.concatenate([rng.uniform(-50, 50, 20000), special[::-1]])
    compiled = np.empty(x.shape[0])
    with np.errstate(all="ignore"):
        namespace["kernel"](x, y, compiled)
        function = getattr(_interpreted.LIBM_NUMPY, name)
        scalars = np.array([function(a, b) if two else function(a) for a, b in zip(x.tolist(), y.tolist())])
        arrays = function(x, y) if two else function(x)
        own = getattr(np, name)(x, y) if two else getattr(np, name)(x)
    same = lambda values: int(np.count_nonzero(~((values == compiled) | (np.isnan(values) & np.isnan(compiled)))))
    mismatches[name] = same(scalars) + same(arrays)
    numpy_own[name] = same(own)
print(json.dumps({"mismatches": mismatches, "numpy": numpy_own}))
"""


def test_interpreted_elementary_functions_are_the_compiled_ones_whatever_numpy_s_simd(tmp_path):
    """The interpreted kernels' ``np.arctan2``, ``np.arccos``, ``np.exp`` ... give the compiled kernels' values (the C
    library's), bit for bit, also where numpy's own differ: in a process with numpy's SIMD dispatch as the CPU has it
    (on an AVX-512 CPU numpy's vectorized routines differ in the last bit for about 1 % of arguments; the test
    session turns them off, ``conftest.py``)."""
    result = run_cold(_LIBM_PROGRAM, tmp_path, NPY_DISABLE_CPU_FEATURES=None, OPENBLAS_CORETYPE=None)
    assert result["mismatches"] == {name: 0 for name in _interpreted._LIBM_FUNCTIONS}
    assert set(result["numpy"]) == set(_interpreted._LIBM_FUNCTIONS)


def _exact_fma(a, b, c):
    return float(Fraction(a) * Fraction(b) + Fraction(c))


finite = st.floats(allow_nan=False, allow_infinity=False, width=64, min_value=-1e150, max_value=1e150)


@njit(cache=False)
def _compiled_fma(a, b, c):
    return _tip_kernels._fma(a, b, c)


@settings(max_examples=300, deadline=None)
@given(finite, finite, finite)
def test_the_fused_multiply_add_stand_in_rounds_once(a, b, c):
    """The tips' ``_fma`` stand-in: the exact a * b + c rounded once (Fraction), which the compiled intrinsic
    (the processor's FMA or libm's fma) also gives, bit for bit."""
    value = _interpreted.fused_multiply_add(a, b, c)
    expected = _exact_fma(a, b, c) if _exact_fma(a, b, c) != 0 else a * b + c
    assert value == expected and math.copysign(1, value) == math.copysign(1, expected)
    compiled = _compiled_fma(a, b, c)
    assert compiled == value and math.copysign(1, compiled) == math.copysign(1, value)


def test_the_fused_multiply_add_stand_in_differs_from_two_roundings():
    """A case where a * b + c rounded twice differs from the fused value: the stand-in gives the fused one."""
    a = 1.0 + 2.0 ** -30
    b = 1.0 - 2.0 ** -30
    c = -1.0
    assert a * b + c == 0.0  # the product 1 - 2**-60 rounds to 1
    assert _interpreted.fused_multiply_add(a, b, c) == -(2.0 ** -60) == _compiled_fma(a, b, c)


@pytest.mark.parametrize("values", [(3, 2.5), (2.5, 3), (1, 1.0), (np.float64(2), 7), (-0.0, 0.0), (0.0, -0.0)])
def test_the_min_max_stand_ins_are_the_intrinsics(values):
    @njit(cache=False)
    def both(a, b):
        return _jit.pymin(a, b), _jit.pymax(a, b), _jit.pyclip(a, 0.5, b)

    low, high, clipped = both(*values)
    a, b = values
    for stand_in, compiled in ((min(a, b), low), (max(a, b), high), (_jit._clip(a, 0.5, b), clipped)):
        assert stand_in == compiled and math.copysign(1, stand_in) == math.copysign(1, compiled)


def _fake_warm_up(calls):
    """``_jit.warm_up`` as on a cold cache with a small bitmap: the first call interprets, later ones compile."""
    def warm_up(tasks=_jit.TRACE_TASKS, interpret=False):
        interpret = interpret() if callable(interpret) else interpret
        calls.append(interpret)
        if len(calls) == 1 and interpret:
            for name in _jit.WARM_UP_TASKS:
                _jit._sentinel(name)
            _interpreted.interpret()
            return True
        _interpreted.restore()
        return False
    return warm_up


def test_a_kernel_error_while_interpreted_falls_back_to_the_compiled_kernels(monkeypatch):
    """A kernel whose Python semantics differ (here: a stand-in that raises inside the deviation check) costs the
    compile, not the trace: the same result as the compiled kernels, reported as compiled."""
    mask = sc.datasets.shape("star", 64)
    expected = sc.trace(mask)
    calls = []
    monkeypatch.setattr(_jit, "warm_up", _fake_warm_up(calls))
    _interpreted._clones()
    kernels = sys.modules["splinecraft.capture.fitting._kernels"]
    clone = _interpreted._CLONES[kernels._deviation_into]

    def divided_by_zero(*args):
        return 1.0 / 0.0

    monkeypatch.setitem(clone.__globals__, "pyclip", divided_by_zero)
    try:
        result = sc.trace(mask)
    finally:
        _interpreted.restore()
    assert calls == [True, False]
    assert result.stats["kernels"] == "compiled"
    assert result.to_svg() == expected.to_svg()


def test_an_error_outside_the_kernels_is_raised_at_once(monkeypatch):
    """An error of the trace itself (no ink left after the specks are dropped) is not retried with compiled
    kernels: it is raised from the interpreted run."""
    calls = []
    monkeypatch.setattr(_jit, "warm_up", _fake_warm_up(calls))
    monkeypatch.setattr(trace_module, "_boundaries", lambda *args: (_ for _ in ()).throw(ValueError("no shape found")))
    try:
        with pytest.raises(ValueError, match="no shape found"):
            sc.trace(sc.datasets.shape("disc", 32))
    finally:
        _interpreted.restore()
    assert calls == [True]


@pytest.mark.parametrize("shape", [(1, 1), (5, 7), (40, 33)])
def test_cracks_of_counts_the_pixel_edges_between_ink_and_paper(shape):
    rng = np.random.default_rng(sum(shape))
    mask = rng.random(shape) < 0.5
    padded = np.pad(mask, 1)
    expected = sum(int(padded[i, j] != padded[i, j + 1]) for i in range(padded.shape[0])
                   for j in range(padded.shape[1] - 1))
    expected += sum(int(padded[i, j] != padded[i + 1, j]) for i in range(padded.shape[0] - 1)
                    for j in range(padded.shape[1]))
    assert trace_module._cracks_of(mask) == expected


def test_a_rectangle_s_cracks_are_its_perimeter():
    mask = np.zeros((30, 50), bool)
    mask[5:25, 10:40] = True
    assert trace_module._cracks_of(mask) == 2 * (20 + 30)
    mask[:, :] = True
    assert trace_module._cracks_of(mask) == 2 * (30 + 50)


def test_only_small_bitmaps_are_interpreted(monkeypatch):
    calls = []
    monkeypatch.setattr(_jit, "warm_up", lambda tasks=(), interpret=False: calls.append(interpret()) or False)
    sc.trace(sc.datasets.shape("disc", 64))
    large = np.zeros((420, 420), bool)  # a 1200-px glyph has 6000-8300 cracks, an ideograph 16 000-17 000
    large[10:410, 10:410] = True
    for k in range(20, 400, 20):
        large[k:k + 10, 20:400] = False  # about 2 * 19 * 380 cracks
    assert 8000 < trace_module._cracks_of(large) <= trace_module.INTERPRET_CRACKS
    sc.trace(large)
    big = np.zeros((700, 700), bool)
    big[50:650, 50:650] = True
    for k in range(60, 640, 20):
        big[k:k + 10, 60:640] = False  # stripes: about 2 * 29 * 580 cracks
    assert trace_module._cracks_of(big) > trace_module.INTERPRET_CRACKS
    sc.trace(big)
    assert calls == [True, True, False]


_COLD_INTERPRETED = """
import json, os, sys, time
import numpy as np
import splinecraft as sc
from splinecraft.capture import _jit
""" + HOLED_RECTANGLE + """
first = sc.trace(mask)
last = dict(_jit.LAST_WARM_UP)
helper = _jit._BACKGROUND
interpreting = _jit.interpreting()
second = sc.trace(mask)
after_second = _jit.interpreting()
helper.wait(timeout=600)
time.sleep(0.5)  # the thread that puts the compiled kernels back
print(json.dumps({"svg": [first.to_svg(), second.to_svg()], "kernels": [first.stats["kernels"], second.stats["kernels"]],
                  "last": last, "interpreting": [interpreting, after_second, _jit.interpreting()],
                  "background": helper.returncode,
                  "cached": {name: _jit.is_cached(_jit._sentinel(name)) for name in _jit.WARM_UP_TASKS}}))
"""


def test_a_cold_first_trace_is_interpreted_while_every_kernel_compiles_in_the_background(tmp_path):
    """A fresh process on an empty cache: its first trace runs the kernels interpreted (the same SVG as this warm
    process's), a background process compiles every warm-up task into the cache, and the second trace runs the
    compiled kernels."""
    child = run_cold(_COLD_INTERPRETED, tmp_path, SPLINECRAFT_JIT_WORKERS="2", SPLINECRAFT_JIT_INTERPRET=None)
    assert child["svg"] == [sc.trace(holed_rectangle()).to_svg()] * 2
    assert child["kernels"] == ["interpreted", "compiled"]
    assert child["interpreting"] == [True, False, False]
    assert child["last"]["interpreted"] is True
    assert set(child["last"]["helpers"][0]) == set(_jit.WARM_UP_TASKS)
    assert child["background"] == 0
    assert all(child["cached"].values())


def test_interpreting_is_off_with_the_environment(monkeypatch):
    monkeypatch.setenv("SPLINECRAFT_JIT_INTERPRET", "0")
    assert not _jit.may_interpret()
    monkeypatch.setenv("SPLINECRAFT_JIT_INTERPRET", "1")
    assert _jit.may_interpret()


@pytest.mark.parametrize("task", sorted(_jit.WARM_UP_TASKS))
def test_every_warm_up_runs_interpreted_in_bounds(interpreted, task):
    """The warm-ups call the kernels with tiny inputs only to compile them; compiled, a kernel reads out of bounds
    silently (``boundscheck=False``), interpreted it raises: each warm-up's inputs are valid ones (until session 31
    the fit step's was not: a 2-row mix read rows 2 and 3 of its pieces). Warnings are errors here."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _jit._function(task)()


def test_restore_ready_puts_back_only_the_kernels_found_ready(interpreted):
    """A background compile caches kernels one by one: each that is ready comes back in the modules and in the
    clones' globals while the others stay interpreted, and a trace then mixes both with the same result."""
    kernels = sys.modules["splinecraft.capture.fitting._kernels"]
    clone = kernels._deviation_into
    deviation = _interpreted.compiled(clone)
    walk = _interpreted.compiled(clone.__globals__["_walk_right"])
    assert _interpreted.restore_ready(lambda kernel: kernel is deviation) == 1
    assert kernels._deviation_into is deviation
    assert isinstance(kernels._normal_into, types.FunctionType)  # still interpreted
    assert clone.__globals__["_walk_right"] is _interpreted._CLONES[walk]  # a helper of kernels only: stays
    assert _interpreted.restore_ready(lambda kernel: kernel is deviation) == 0  # already back
    assert _interpreted.restore_ready(lambda kernel: kernel is walk) == 0  # no Python wrapper: never alone
    mask = sc.datasets.shape("star", 64)
    with _quiet():
        mixed = sc.trace(mask)
    _interpreted.restore()
    with _quiet():
        assert mixed.to_svg() == sc.trace(mask).to_svg()
    _interpreted.interpret()  # again: the clones' globals point at clones again
    assert isinstance(kernels._deviation_into, types.FunctionType)


def test_background_order_names_every_task_once():
    assert sorted(_jit.BACKGROUND_ORDER) == sorted(_jit.WARM_UP_TASKS)


def test_the_background_s_first_steps_are_part_of_a_task(monkeypatch):
    """Each step a background compile runs before its tasks is a function its task's warm-up calls too (so the
    task's cache entry check covers it, and a step that failed is compiled with its task)."""
    called = []
    for module, function in _jit.BACKGROUND_FIRST:
        owner = importlib.import_module("splinecraft.capture." + module)
        monkeypatch.setattr(owner, function, lambda name=function: called.append(name))
    for name in _jit.WARM_UP_TASKS:
        _jit._function(name)()
    assert called == [function for _, function in _jit.BACKGROUND_FIRST]


@pytest.mark.parametrize("options", [
    {"method": "fuzzy", "seed": 3},
    {"method": "euclidean", "seed": 1, "corner_method": "srm05"},
    {"corner_method": "tc89"},
    {"fit_params": {"merge_tolerance": 0}},
    {"contour": "pixels", "epsilon": 0.6},
])
def test_interpreted_traces_match_with_other_options(interpreted, options):
    """The thesis's knot insertion, other corner detectors, no merging, pixel contours: interpreted as compiled."""
    mask = sc.datasets.thesis_object("ali", 80)
    with _quiet():
        slow = sc.trace(mask, **options)
    _interpreted.restore()
    with _quiet():
        fast = sc.trace(mask, **options)
    assert slow.to_svg() == fast.to_svg()
    assert [len(fit.snapshots) for fit in slow.fits] == [len(fit.snapshots) for fit in fast.fits]


def test_a_warm_cache_never_asks_whether_to_interpret():
    """``trace`` passes the bitmap's size test as a function: on a warm cache (every task done or cached) it is
    not called, so a warm trace does not count the bitmap's cracks."""
    asked = []
    tasks = _jit.TRACE_TASKS + ("merge", "corners", "pixel corners")
    _jit.warm_up(tasks)
    assert _jit.warm_up(tasks, interpret=lambda: asked.append(1) or True) is False
    assert asked == []
