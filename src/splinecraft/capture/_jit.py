"""Options of the compiled kernels (:mod:`.fitting._kernels`, :mod:`.fitting._iso_kernels`,
:mod:`.corners._jump_kernels`, the tracer's :mod:`._cracks`, the pixel corners of :mod:`._pixel_corners` and the
polygons of :mod:`.fitting.budget`) and where numba caches them.

numba compiles each kernel on its first call and keeps the machine code on disk (``cache=True``): in the
``__pycache__`` folder next to the module, else in the user's cache folder (``~/.cache/numba``), else under
``NUMBA_CACHE_DIR`` when that is set. Where none of them can be written (a read-only install run by a user
without a home folder) numba refuses ``cache=True`` when the module is imported ("no locator available").
:func:`ensure_cache_dir` then points numba's cache at a per-user folder of the temporary directory, so the
kernels still compile once per machine boot instead of failing.

A cold cache costs seconds of compiling on the first trace of a process (docs/capture.md, "Compiled kernels").
:func:`warm_up` spreads that over the machine's CPUs: the cold warm-up tasks (:data:`WARM_UP_TASKS`) are split
longest first between this process and helper processes that only compile them into the shared cache, and this
process then loads the helpers' kernels from it. A warm cache starts no helper; a helper that fails or cannot
start costs nothing but the time: this process compiles what it left. A helper is a fork of this process where
that is safe (:func:`_can_fork`: on Linux, no other Python thread; a forked helper that stops using CPU is
stopped, :class:`_Forked`), else a fresh interpreter that imports only the kernel modules of its tasks
(:data:`_HELPER_CODE`), and the split (:func:`plan`) weighs each task by its measured compile and the helper by
its late start (:data:`FORKED_HELPER_START`, :data:`HELPER_START`): docs/capture.md, "Cold kernels compile in
parallel".

A cold first trace of a small bitmap compiles nothing in this process: ``warm_up(..., interpret=True)`` starts one
background process that compiles every cold task (:func:`_start_background`) and runs the kernels interpreted
meanwhile (:mod:`._interpreted`: their Python source, the same results); docs/capture.md, "A cold first trace runs the
kernels interpreted".
"""
from __future__ import annotations

import gc
import hashlib
import importlib
import inspect
import itertools
import operator
import os
import select
import signal
import subprocess
import sys
import tempfile
import threading
import time
import warnings

import numba
from numba.core import postproc, types, typing
from numba.core.compiler import CompilerBase, DefaultPassBuilder
from numba.core.compiler_lock import global_compiler_lock
from numba.core.compiler_machinery import AnalysisPass, register_pass
from numba.core.ir_utils import enforce_no_dels, enforce_no_phis
from numba.core.typed_passes import IRLegalization, NopythonRewrites, PreLowerStripPhis
from numba.core.types.functions import BaseFunction
from numba.core.untyped_passes import InlineClosureLikes, ReconstructSSA
from numba.extending import intrinsic

from . import _interpreted

__all__ = ["JIT_OPTIONS", "HELPER_OPTIONS", "compact", "pymin", "pymax", "pyclip", "insertion_sort", "union_root",
           "union_join", "ensure_cache_dir", "warm_up",
           "warm_up_all", "WARM_UP_TASKS", "TRACE_TASKS", "LAST_WARM_UP"]


@register_pass(mutates_CFG=True, analysis_only=False)
class _LegalizeWithoutDels(AnalysisPass):
    """numba's ``IRLegalization`` (the checks before lowering, and the IR's post-processing: the canonical CFG,
    the variables' lifetimes) without the ``del`` statement it inserts after each variable's last use: a ``del``
    only lowers to the release of a reference-counted value (and the zeroing of its stack slot), and a kernel
    has none (``_nrt=False``). In the trace's kernels half the statements were ``del`` statements."""
    _name = "ir_legalization_without_dels"

    def __init__(self):
        AnalysisPass.__init__(self)

    def run_pass(self, state):
        enforce_no_phis(state.func_ir)
        enforce_no_dels(state.func_ir)
        postproc.PostProcessor(state.func_ir).run(emit_dels=False)
        return True


def _lean_pipeline_supported():
    """Whether this numba's post-processing of the IR can leave out the ``del`` statements
    (``PostProcessor.run(emit_dels=False)``, numba 0.60-0.68 at least), which :class:`_LegalizeWithoutDels`
    needs. Elsewhere the kernels compile through numba's own nopython pipeline: the same kernels, only slower
    to compile. (The passes :class:`_KernelCompiler` leaves out are matched by class: one that a numba does not
    have is not left out.)"""
    try:
        return "emit_dels" in inspect.signature(postproc.PostProcessor.run).parameters
    except (TypeError, ValueError):
        return False


#: Whether the kernels compile through the lean pipeline (:func:`_lean_pipeline_supported`).
_LEAN_PIPELINE = _lean_pipeline_supported()

#: (function type, typing context, argument types) -> (signature, implementation key) of every call typed while
#: a kernel compiles (:func:`_call_type`).
_CALL_TYPES = {}
_PLAIN_CALL_TYPE = BaseFunction.get_call_type


def _call_type(function, context, args, kws):
    """``BaseFunction.get_call_type`` remembered per argument types while a kernel compiles
    (:meth:`_KernelCompiler._compile_core`). numba types a call of a builtin function or operator (``a * b``,
    ``x[i]``, ``np.int64(n)``, ``range(n)``) by trying its templates one by one, sorted anew at each call,
    and does so at every call site in every round of type inference and once again when lowering each
    operator, index and item assignment (to register the implementation key of its signature): 5874 times
    in a trace's kernels for 288 distinct calls. The templates of a function answer the same argument types
    with the same signature (the function type itself is made of its templates: a new template makes a new
    type), so the first answer is kept with the implementation key it registered, which a remembered answer
    registers again. Failures are not kept (numba tries again, as before); nor are calls with keywords."""
    if kws or not isinstance(getattr(function, "_impl_keys", None), dict):
        # keywords, or a numba whose functions keep their implementation keys elsewhere: numba's own typing
        return _PLAIN_CALL_TYPE(function, context, args, kws)
    key = (function, context, args)
    known = _CALL_TYPES.get(key)
    if known is None:
        signature = _PLAIN_CALL_TYPE(function, context, args, kws)
        _CALL_TYPES[key] = signature, function._impl_keys[signature.args]
        return signature
    signature, implementation = known
    function._impl_keys[signature.args] = implementation
    return signature


class _KernelCompiler(CompilerBase):
    """numba's nopython pipeline (``numba.core.compiler.Compiler``) without passes that find nothing to do in
    the kernels or that the kernels do not need, with the typing of builtin calls remembered
    (:func:`_call_type`):

    * the rewrites of the typed IR (``NopythonRewrites``: array expressions fused into loops, static indices
      of string literals; the kernels allocate nothing and index no strings) and the inlining of closures
      (``InlineClosureLikes``: functions defined inside a kernel, comprehensions; the kernels have none: one
      that gained some would need the pass back): the cold compile 0.955x and 0.97x of that again, the same
      machine code (BENCHMARKS.md, "Session 27: cold first call"). The rewrites before type inference stay:
      without them (numba's ``no_rewrites``) a constant index of a tuple (``shape[0]``, ``k[8]``) is typed as
      a call of ``getitem``, which numba compiles per tuple type and index (the compile 1.05x);
    * the SSA form (``ReconstructSSA``, ``PreLowerStripPhis``): each assignment of a variable a version of its
      own, typed on its own and joined again before lowering. Without it numba types a variable once for all
      its assignments (their unified type): in the kernels the same types but for four integer variables of
      ``_boundaries_into`` assigned an ``int32`` and an ``int64`` (now ``int64`` throughout: the same values)
      and two flags assigned the literal ``True`` and a ``bool``. A kernel must not assign one name an integer
      in one place and a float in another (it would become a float everywhere): use two names;
    * the ``del`` statements before lowering (:class:`_LegalizeWithoutDels`).

    The cold compile of a trace's kernels: 0.74x in all (BENCHMARKS.md, "Session 28: cold first call"). The
    machine code is that of numba's own pipeline but for the stack slots and the order of some instructions
    in ``_deviation_into`` and the merge's run fit (then ``_fit_runs_into``; no SSA form, no ``del`` statements);
    results are bit for bit."""

    def define_pipelines(self):
        pipeline = DefaultPassBuilder.define_nopython_pipeline(self.state)
        if not _LEAN_PIPELINE:
            return [pipeline]
        left_out = (NopythonRewrites, InlineClosureLikes, ReconstructSSA, PreLowerStripPhis)
        pipeline.passes = [(_LegalizeWithoutDels if step is IRLegalization else step, name)
                           for step, name in pipeline.passes if step not in left_out]
        pipeline.finalize()
        return [pipeline]

    def _compile_core(self):
        # under numba's compiler lock (no other compile, no other typing, runs meanwhile); a helper compiled
        # while a kernel is typed comes here again, and the outer compile puts numba's method back
        with global_compiler_lock:
            outer = BaseFunction.get_call_type
            BaseFunction.get_call_type = _call_type
            try:
                return super()._compile_core()
            finally:
                BaseFunction.get_call_type = outer


#: ``numba.njit`` options of every kernel: cached on disk, GIL released, no bounds checks, numpy's
#: floating-point error model (no ``fastmath``: results are bit for bit those of the numpy expressions), and
#: no reference counting (``_nrt=False``): the kernels only read and write arrays their wrappers allocate, so
#: numba's runtime has nothing to count; without it less code is compiled (about 5-10 % of the cold compile)
#: and an allocation inside a kernel fails to compile instead of costing compile time. No C-callable wrapper
#: (``no_cfunc_wrapper``): nothing takes a kernel's address (``cfunc``, first-class functions), and each
#: wrapper was compiled and optimized for nothing (about 8 ms a kernel). numba's pipeline without the passes
#: the kernels do not need and with each builtin call typed once per argument types (:class:`_KernelCompiler`:
#: the cold compile 0.93x in session 27, 0.74x of that in session 28).
JIT_OPTIONS = dict(cache=True, nogil=True, boundscheck=False, error_model="numpy", _nrt=False, no_cfunc_wrapper=True,
                   pipeline_class=_KernelCompiler)
#: The options of helpers that only kernels call (``_basis``, ``_walk_right``, ``_ink``, ``_smoothed`` ...): also
#: no Python wrapper (``no_cpython_wrapper``: the argument unboxing and boxing of a call from Python, compiled for
#: each helper but never run) and no cache entry of their own (``cache=False``): their code is linked into the
#: calling kernels, whose cache entries hold it, so a warm process never loads a helper, and writing its entry
#: cost 3-4 ms a helper. Always inlined (``forceinline``): in a kernel optimized for size (:func:`compact`) LLVM
#: kept calls to the Bezier point and ran ``_samples_into`` 2x slower; the one large helper, ``_smoothed``, opts
#: out, and so does the arm search's ``_prefix_moments``, called once a call. A helper's own code is optimized before
#: its callers inline it: one that only compact kernels call begins with :func:`compact` too (``_bezier_point``,
#: the arm search's three; session 29). (Tests call ``_smoothed``,
#: ``_window_fit``, ``_prefix_moments`` and ``_moment_verdict`` through kernels of their own.)
HELPER_OPTIONS = dict(JIT_OPTIONS, no_cpython_wrapper=True, cache=False, forceinline=True)


@intrinsic
def compact(typingctx):
    """``compact()`` as the first statement of a kernel: LLVM optimizes the kernel's machine code for size (the
    ``optsize`` attribute of its function; the helpers it calls are inlined under the same rule). The
    optimizations are those of ``-O3`` but for the ones that grow the code for speed: no loops unrolled,
    vectorized with run-time overlap checks or duplicated per value of a flag (unswitched), and smaller functions
    inlined. Results are bit for bit the same (no optimization of either kind reorders floating-point
    operations); the compiled code is a third to a tenth of its ``-O3`` size, which LLVM optimizes and emits in
    that much less time (the cold compile of a trace's kernels: BENCHMARKS.md, "Session 24"). Only in kernels
    whose run time in a trace is negligible or no slower so (the fit's hot loops -- ``_deviation_into``,
    the merge's run fit (``_fit_runs_into`` until session 30, now ``_candidates_into``), ``_normal_into``, the
    Hoschek step (``_hoschek_into``, now in ``_step_into``), the noise estimate's ``_nearest_into`` -- ran 5-15 %
    slower and keep ``-O3``)."""
    def codegen(context, builder, signature, args):
        builder.function.attributes.add("optsize")
        return context.get_dummy_value()
    return types.none(), codegen


# The builtins min and max of two numbers, and min(max(x, lo), hi), for kernels: the instructions numba's builtins
# emit (numba.cpython.builtins.do_minmax: both cast to their unified type, then the second where it compares
# strictly smaller (min) or larger (max), else the first -- a NaN first stays, a NaN second is passed over), so
# results are bit for bit those of min and max. numba implements the builtins as overloads: each signature of
# each is a function of its own, compiled (with the literal-argument variants, 6-7 of them, 12-15 ms each, in
# every process and warm-up task that uses them) and typed again at each call; these intrinsics are written
# into the calling kernel at each call.
def _pick(context, builder, first_type, first, second_type, second, compare):
    unified = context.typing_context.unify_types(first_type, second_type)
    first = context.cast(builder, first, first_type, unified)
    second = context.cast(builder, second, second_type, unified)
    takes_second = context.get_function(compare, typing.signature(types.boolean, unified, unified))
    return unified, builder.select(takes_second(builder, (second, first)), second, first)


def _unified(typingctx, *values):
    values = [types.unliteral(value) for value in values]
    if not all(isinstance(value, types.Number) for value in values):
        return None, values
    unified = values[0]
    for value in values[1:]:
        unified = typingctx.unify_types(unified, value)
    return unified, values


def _min_or_max(name, compare, doc):
    """The intrinsic ``name(a, b)`` of two numbers: ``b`` where ``compare(b, a)``, else ``a`` (see above)."""
    def typer(typingctx, a, b):
        unified, args = _unified(typingctx, a, b)
        if unified is None:
            return None

        def codegen(context, builder, signature, values):
            return _pick(context, builder, signature.args[0], values[0], signature.args[1], values[1], compare)[1]
        return unified(*args), codegen
    typer.__name__ = typer.__qualname__ = name
    typer.__doc__ = doc
    return intrinsic(typer)


pymin = _min_or_max("pymin", operator.lt, "``min(a, b)`` of two numbers in a kernel: ``b`` where ``b < a``, else ``a``")
pymax = _min_or_max("pymax", operator.gt, "``max(a, b)`` of two numbers in a kernel: ``b`` where ``b > a``, else ``a``")


@intrinsic
def pyclip(typingctx, x, lo, hi):
    """``min(max(x, lo), hi)`` of three numbers in a kernel, one call (see above)."""
    unified, args = _unified(typingctx, x, lo, hi)
    if unified is None:
        return None

    def codegen(context, builder, signature, values):
        low_type, low = _pick(context, builder, signature.args[0], values[0], signature.args[1], values[1],
                              operator.gt)
        return _pick(context, builder, low_type, low, signature.args[2], values[2], operator.lt)[1]
    return unified(*args), codegen


def _clip(x, lo, hi):
    """``min(max(x, lo), hi)`` in one call, as :func:`pyclip` picks: ``lo`` where ``lo > x``, then ``hi`` where
    ``hi`` is smaller."""
    low = lo if lo > x else x
    return hi if hi < low else low


def _nothing():
    return None


# what runs in their place when the kernels are interpreted (_interpreted): the builtins whose instructions they emit
_interpreted.stand_in(pymin, min)
_interpreted.stand_in(pymax, max)
_interpreted.stand_in(pyclip, _clip)
_interpreted.stand_in(compact, _nothing)


@numba.njit(**HELPER_OPTIONS)
def union_root(parent, node):
    """The root of ``node``'s tree in the union-find forest ``parent`` (``parent[root] == root``), for kernels; halves
    the path on the way (the tracer's components of cycles, the noise estimate's pieces of thin pixels)."""
    while parent[node] != node:
        parent[node] = parent[parent[node]]
        node = parent[node]
    return node


@numba.njit(**HELPER_OPTIONS)
def union_join(parent, a, b):
    """The union of ``a``'s and ``b``'s trees in the union-find forest ``parent``, the larger root under the smaller
    (the forest does not depend on the order of the unions' arguments)."""
    a, b = union_root(parent, a), union_root(parent, b)
    if a < b:
        parent[b] = a
    elif b < a:
        parent[a] = b


@numba.njit(**HELPER_OPTIONS)
def insertion_sort(values, count):
    """Sort ``values[:count]`` in place, ascending, for kernels (an insertion sort: the few dozen values of a
    flank, knots that come nearly sorted); equal values keep their order."""
    compact()  # optimized for size, as its callers are (compact)
    for i in range(1, count):
        value = values[i]
        j = i - 1
        while j >= 0 and values[j] > value:
            values[j + 1] = values[j]
            j -= 1
        values[j + 1] = value


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

#: The warm-up tasks: name -> (module relative to :mod:`splinecraft.capture`, its function that compiles (empty
#: cache) or loads the task's kernels, the kernel whose cache entry tells whether the task is cold, the task's
#: cold compile in seconds). The seconds are CPU seconds of the task alone in a fresh process on an empty cache,
#: numba's set-up of a process's first compile left out (a trivial kernel compiled first), the mean of two
#: medians of two runs each, measured in session 30 on its machine (about 2.2x the compile time of session 29's,
#: whose figures these replaced) with the session's new kernels: the corner tips' (a task of their own since
#: then), tangent-jump's steps, merging's passes and the lsq rounds' (BENCHMARKS.md, "Session 30 at its end");
#: they balance the processes of :func:`warm_up` with the helpers' starts below (which are in session 29's
#: seconds: a tenth of a second here or there does not change the split of tasks this large).
WARM_UP_TASKS = {
    "fit solves": ("fitting._kernels", "warm_up_solves", "_normal_into", 5.0),
    "fit checks": ("fitting._kernels", "warm_up_checks", "_nearest_segments_into", 3.2),
    "tips": ("fitting._tip_kernels", "warm_up", "_tip_into", 2.9),
    "tracer": ("_cracks", "warm_up", "_follow_into", 1.35),
    "merge": ("fitting._merge_kernels", "warm_up", "_choose_into", 3.4),
    "noise": ("fitting._iso_kernels", "warm_up", "_nearest_into", 0.85),
    "corners": ("corners._jump_kernels", "warm_up", "_corners_into", 5.3),
    "polygons": ("fitting.budget", "warm_up", "_polygons_into", 0.55),
    "pixel corners": ("_pixel_corners", "warm_up", "_pixel_corners_into", 0.57),
}
#: The tasks every trace needs (segment merging adds ``"merge"``, tangent-jump ``"corners"`` and ``"pixel corners"``
#: (session 29: 0.29 s, BENCHMARKS.md, "Session 29: pixel corners and noise estimate speed"); the polygons of a spent
#: time budget compile where they are used).
TRACE_TASKS = ("fit solves", "fit checks", "tips", "tracer", "noise")
#: Seconds by which a helper process finishes later than this process with the same share, in the units of
#: :data:`WARM_UP_TASKS`: the helper's start to the end of numba's set-up of its first compile (Python, numpy,
#: numba and its kernel modules imported, 0.37 s CPU since session 25: no scipy.linalg for numba's BLAS check,
#: no scipy.ndimage for the noise estimate's warm-up), less this process's own set-up of its first compile
#: (0.15-0.2 s), the collection of its compiles' garbage after them (0.15-0.2 s: some 290 000 objects Python's
#: collector walks, whether this process collects them while it waits for a helper or the first automatic
#: collection does, which fires inside :func:`warm_up` as soon as the collector is back on), the loading of
#: the helper's kernels (0.02-0.03 s) and the first trace's own run (0.06 s) (BENCHMARKS.md, "Session 25: cold
#: first call"). 0.1 until session 27, where this process still finished 0.3-0.4 s CPU after the helper; at
#: -0.05 the two shares swap and both finish together ("Session 27: cold first call").
HELPER_START = -0.05
#: :data:`HELPER_START` of a forked helper (:func:`_fork_helper`): it starts at once and sets numba up as this
#: process does, so it finishes earlier than this process with the same share by what only this process does:
#: the collection of its compiles' garbage (0.15-0.2 s CPU), the loading of the helper's kernels (0.02 s) and
#: the first trace's own run (0.06 s) (CPU timelines of the first trace: BENCHMARKS.md, "Session 27: cold first
#: call"). -0.25 until session 28, where this process then finished 0.2 s CPU after the helper; at -0.45 both
#: finish together ("Session 28: cold first call"). -0.25 again since session 29: with the session's new tasks the
#: split of -0.45 left the helper 0.2 s CPU behind this process, and -0.25 (the fit's two tasks and tangent-jump's
#: arm search in the helper) gave the cold first trace 0.93x the wall ("Session 29: cold first call").
FORKED_HELPER_START = -0.25
#: The most splits :func:`plan` tries one by one (``processes ** len(cold)``); more are split longest first. 8192
#: since session 29: all eight tasks on three processes, 6561 splits, 4 ms (the nine of session 30 on two: 512).
EXACT_PLAN_SPLITS = 8192
#: Seconds this process waits for a helper before it stops it and compiles the helper's tasks itself.
HELPER_TIMEOUT = 600.0
#: What the last :func:`warm_up` of this process did: the tasks found cold, the tasks of each helper, the
#: helpers that failed (their tasks compiled here), and which helpers were forked (:func:`_fork_helper`).
LAST_WARM_UP = {"cold": [], "helpers": [], "failed": [], "forked": [], "interpreted": False}

_DONE = set()
_LOCK = threading.Lock()


def _cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def workers() -> int:
    """Processes a cold warm-up may use: the CPUs this process may run on, or fewer when
    ``SPLINECRAFT_JIT_WORKERS`` is set to a whole number from 1 (``1``: no helper processes). Any other value
    is ignored with a warning."""
    setting = os.environ.get("SPLINECRAFT_JIT_WORKERS", "").strip()
    cpus = _cpus()
    if not setting:
        return cpus
    if setting.isascii() and setting.isdigit() and int(setting) >= 1:
        return min(int(setting), cpus)
    warnings.warn(f"SPLINECRAFT_JIT_WORKERS={setting!r} is not a whole number from 1 (1: no helper processes); "
                  f"ignored: up to {cpus} processes compile the kernels", RuntimeWarning, stacklevel=2)
    return cpus


def is_cached(dispatcher) -> bool:
    """Whether numba's on-disk cache holds an entry of ``dispatcher`` for this machine that numba would load
    (the index of its source file's current version; numba's own check)."""
    try:
        magic = dispatcher.targetctx.codegen().magic_tuple()
        return any(key[1] == magic for key in dispatcher._cache._cache_file._load_index())
    except Exception:  # no cache, or numba's internals moved: counted as cold (costs at most a helper)
        return False


def plan(cold, processes, late=None):
    """Split the ``cold`` task names between this process (first list) and ``processes - 1`` helpers (each of
    which starts ``late`` seconds late, by default :data:`HELPER_START`): the split whose finish times, largest
    first, are the least (so the earliest last finish, and no process idle while another has a task it could
    have taken). Every
    split is tried when there are at most :data:`EXACT_PLAN_SPLITS` (a trace's eight tasks on two processes: 256);
    beyond, longest first, each to the process that would finish it earliest. Longest first alone splits the
    trace's tasks 3.25 : 3.0 s on two processes where 3.1 : 3.15 exists."""
    processes = max(1, processes)
    names = sorted(cold, key=lambda task: (-WARM_UP_TASKS[task][3], task))
    start = [0.0] + [HELPER_START if late is None else late] * (processes - 1)
    if processes ** len(names) <= EXACT_PLAN_SPLITS:
        best = None
        for places in itertools.product(range(processes), repeat=len(names)):
            loads = list(start)
            for name, at in zip(names, places):
                loads[at] += WARM_UP_TASKS[name][3]
            key = sorted(loads, reverse=True)
            if best is None or key < best[0]:
                best = (key, places)
        shares = [[] for _ in start]
        for name, at in zip(names, best[1]):
            shares[at].append(name)
        return shares
    loads, shares = list(start), [[] for _ in start]
    for name in names:
        at = min(range(len(loads)), key=lambda index: (loads[index], index))
        loads[at] += WARM_UP_TASKS[name][3]
        shares[at].append(name)
    return shares


def _function(name):
    module, function, _, _ = WARM_UP_TASKS[name]
    return getattr(importlib.import_module("splinecraft.capture." + module), function)


def _sentinel(name):
    module, _, kernel, _ = WARM_UP_TASKS[name]
    return _interpreted.compiled(getattr(importlib.import_module("splinecraft.capture." + module), kernel))


#: The helper's program: it exits when this process is gone (a watcher thread compares its parent's pid, so an
#: interrupted or killed trace leaves no compiler behind; not so a background compile, :func:`_start_background`,
#: which finishes the cache for the next process), then runs its tasks, without Python's cyclic garbage
#: collector (:func:`warm_up`) and without the interpreter's teardown. It imports the kernel modules of its
#: tasks and what they import, not the packages around them: ``splinecraft``, ``capture``, ``fitting`` and
#: ``corners`` are registered as bare packages (their folder, no ``__init__``), which halves the helper's start
#: (0.6 -> 0.3 s: no spline, image, contour, corner-detector or fit modules, no scipy of theirs). The kernels'
#: module names, source files and so their cache entries are those of this process.
_HELPER_CODE = """
import gc, os, sys, threading, time
gc.disable()  # the helper imports, compiles and exits: its garbage is never worth collecting
parent = int(sys.argv[1])
background = os.environ.pop("SPLINECRAFT_JIT_BACKGROUND", "")
def watch():
    while os.getppid() == parent:
        time.sleep(0.2)
    os._exit(3)
if background:  # a background compile (_start_background): it outlives its parent, at a lower priority, one at a time
    try:
        os.nice(10)
    except (AttributeError, OSError):
        pass
    try:
        import fcntl
        lock = open(background, "a")
        fcntl.flock(lock, fcntl.LOCK_EX)  # held until the process ends; another process's compile goes first
    except (ImportError, OSError):
        pass
else:
    threading.Thread(target=watch, daemon=True).start()
import types
for package in ("splinecraft", "splinecraft.capture", "splinecraft.capture.fitting", "splinecraft.capture.corners"):
    bare = types.ModuleType(package)  # the package without its __init__: the kernel modules' imports only
    bare.__path__ = [os.path.join(os.getcwd(), *package.split("."))]
    sys.modules[package] = bare
import numba
# numba's set-up (numba.np.arraymath, imported at the first compile) checks for BLAS by importing
# scipy.linalg.cython_blas and scipy.__config__: scipy.linalg cost the helper 0.1 s CPU of its 0.48. A stand-in module
# passes the check (BLAS counted as present, as in the tracing process, so np.dot would compile as there), the
# ABI check reads no scipy.__config__ (numba then assumes the LP64 scipy of its default build), and both are
# removed at once: a kernel that did call BLAS would import the real module when it is compiled. Where the check
# refuses (a numba built for ILP64 BLAS), the module is left to the first compile, which checks with scipy.
sys.modules["scipy.linalg.cython_blas"] = types.ModuleType("scipy.linalg.cython_blas")
sys.modules["scipy.__config__"] = None
try:
    import numba.np.arraymath
except Exception:
    pass
finally:
    del sys.modules["scipy.linalg.cython_blas"], sys.modules["scipy.__config__"]
from splinecraft.capture._jit import _background_first, warm_up
if background:
    _background_first()
warm_up(sys.argv[2:])
os._exit(0)  # the kernels are in the cache: no interpreter teardown (0.15-0.25 s) before this process goes on
"""


#: The folder that holds the ``splinecraft`` package (where helpers start, and part of the lock file's name).
_PACKAGE_FOLDER = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _start_helper(names):
    """A helper process that runs the warm-up tasks ``names`` with this process's package (helpers start no
    helpers of their own): forked from this process where that is safe (:func:`_can_fork`), else a fresh
    interpreter; None when neither can start."""
    helper = _fork_helper(names) if _can_fork() else None
    return helper if helper is not None else _spawn_helper(names)


def _spawn_helper(names, background=None):
    """A fresh interpreter that runs the warm-up tasks ``names`` (:data:`_HELPER_CODE`); None when it cannot
    start. ``background``: the lock file of a background compile (:func:`_start_background`), which runs in a
    session of its own and does not stop with this process."""
    here = _PACKAGE_FOLDER
    env = dict(os.environ, SPLINECRAFT_JIT_WORKERS="1")
    if background:
        env["SPLINECRAFT_JIT_BACKGROUND"] = background
    else:
        env.pop("SPLINECRAFT_JIT_BACKGROUND", None)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [here, os.environ.get("PYTHONPATH", "")]))
    if numba.config.CACHE_DIR:
        env["NUMBA_CACHE_DIR"] = numba.config.CACHE_DIR
    # run from the package's folder: ``-c`` puts the working folder first on the import path, which must not
    # hold another splinecraft (or numpy, numba ...) than this process's
    try:
        return subprocess.Popen([sys.executable, "-c", _HELPER_CODE, str(os.getpid()), *names], cwd=here, env=env,
                                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                start_new_session=bool(background))
    except (OSError, TypeError, ValueError):  # no interpreter to start (an embedded Python), a bad path
        return None


#: Seconds a forked helper may go without using any CPU before this process counts it as stuck (:class:`_Forked`).
FORK_STALL = 3.0


def _can_fork() -> bool:
    """Whether a helper may be forked from this process: on Linux (its ``/proc`` tells a stuck helper), from the
    main thread of a process that runs no other Python thread. A child of ``fork`` has only the forking thread:
    a lock another thread held at that moment (Jupyter's kernel threads, a worker thread tracing, a thread
    compiling with numba) stays held in the child forever. Threads outside Python (the BLAS libraries' pools,
    which shut down around a fork) are not seen here: what they might hold is the stall watch's business
    (:class:`_Forked`). ``SPLINECRAFT_JIT_FORK=0`` turns forking off."""
    return (sys.platform.startswith("linux") and hasattr(os, "fork") and os.environ.get("SPLINECRAFT_JIT_FORK") != "0"
            and threading.current_thread() is threading.main_thread() and threading.active_count() == 1)


def _watch_parent(parent):
    while os.getppid() == parent:
        time.sleep(0.2)
    os._exit(3)


def _fork_helper(names):
    """A copy of this process (``os.fork``) that runs the warm-up tasks ``names`` and exits: no interpreter to
    start, nothing to import, numba already set up (the fresh interpreter's 0.37 s CPU); None when the fork
    fails. It exits when this process is gone, like :data:`_HELPER_CODE`, its output goes nowhere, and it
    leaves without Python's teardown (``os._exit``), so nothing this process registered (``atexit``, buffered
    output) runs twice. Forked under numba's compiler lock: no other compile is half done in the copy."""
    from numba.core.compiler_lock import global_compiler_lock

    parent = os.getpid()
    try:
        done_read, done_write = os.pipe()  # the child holds the writing end: it closes when the child exits
    except OSError:
        return None
    try:
        with global_compiler_lock, warnings.catch_warnings():
            # Python 3.12+ warns of any thread at a fork (the BLAS pools too); a stuck child is watched for
            warnings.simplefilter("ignore", DeprecationWarning)
            pid = os.fork()
    except OSError:
        os.close(done_read)
        os.close(done_write)
        return None
    if pid == 0:  # the helper: compile, and leave
        status = 1
        try:
            os.close(done_read)
            nowhere = os.open(os.devnull, os.O_RDWR)
            for stream in (0, 1, 2):
                os.dup2(nowhere, stream)
            threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()
            gc.disable()  # it compiles and exits: its garbage is never worth collecting
            for name in names:
                _function(name)()
            status = 0
        finally:
            os._exit(status)
    os.close(done_write)
    return _Forked(pid, done_read)


class _Forked:
    """A forked helper, waited for like a :class:`subprocess.Popen` (``pid``, ``poll``, ``wait``, ``kill``).
    ``wait`` counts it as stuck (:class:`subprocess.TimeoutExpired`, so :func:`_finished` stops it and this
    process compiles its tasks) when it has used no CPU for :data:`FORK_STALL` seconds: a compiling process
    always does, while a child blocked on a lock that a thread of the parent held at the fork never will."""

    def __init__(self, pid, done):
        self.pid, self.returncode, self._done = pid, None, done
        self._cpu, self._since = self._cpu_ticks(), time.monotonic()

    def _cpu_ticks(self):
        try:
            with open(f"/proc/{self.pid}/stat", "rb") as stat:
                fields = stat.read().rsplit(b")", 1)[1].split()
            return int(fields[11]) + int(fields[12])  # utime, stime
        except (OSError, IndexError, ValueError):
            return None

    def _reap(self, block):
        if self.returncode is None:
            try:
                pid, status = os.waitpid(self.pid, 0 if block else os.WNOHANG)
            except ChildProcessError:
                pid, status = self.pid, 1 << 8
            if pid:
                self.returncode = os.waitstatus_to_exitcode(status)
                os.close(self._done)
        return self.returncode

    def poll(self):
        return self._reap(block=False)

    def wait(self, timeout=None):
        end = None if timeout is None else time.monotonic() + timeout
        while self.returncode is None:
            left = None if end is None else end - time.monotonic()
            if left is not None and left <= 0:
                raise subprocess.TimeoutExpired(f"forked helper {self.pid}", timeout)
            if select.select([self._done], [], [], 0.25 if left is None else min(0.25, left))[0]:
                return self._reap(block=True)
            cpu, now = self._cpu_ticks(), time.monotonic()
            if cpu != self._cpu:
                self._cpu, self._since = cpu, now
            elif now - self._since > FORK_STALL and timeout is not None:
                raise subprocess.TimeoutExpired(f"forked helper {self.pid} (no CPU for {FORK_STALL} s)", timeout)
        return self.returncode

    def kill(self):
        if self.returncode is None:
            try:
                os.kill(self.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


def _finished(helper) -> bool:
    try:
        return helper.wait(timeout=HELPER_TIMEOUT) == 0
    except subprocess.TimeoutExpired:
        _stop(helper)
        return False


def _stop(helper):
    if helper is not None and helper.poll() is None:
        helper.kill()
        helper.wait()


#: The background compile while the kernels are interpreted (:func:`warm_up` with ``interpret=True``): its
#: process, or None. ``_BACKGROUND_FAILED``: one ended without filling the cache, so this process compiles instead.
_BACKGROUND = None
_BACKGROUND_FAILED = False
_BACKGROUND_TASKS = []


def _help_background(todo):
    """Compile or load the warm-up tasks ``todo`` while the background compile goes on: in the reverse of its order,
    so the two processes work from the two ends of the list (numba loads what the other has cached: a task the
    background has compiled is loaded, and the background loads what this process compiles). At most the task both
    reach at the same time is compiled twice. The background then finishes the tasks of no trace of this process
    for the next ones."""
    order = {name: index for index, name in enumerate(_BACKGROUND_TASKS)}
    collecting = gc.isenabled()
    gc.disable()
    try:
        for name in sorted(todo, key=lambda task: -order.get(task, len(order))):
            _function(name)()
            _DONE.add(name)
    finally:
        if collecting:
            gc.enable()


def may_interpret() -> bool:
    """Whether :func:`warm_up` may run cold kernels interpreted while a background process compiles them: not when
    ``SPLINECRAFT_JIT_INTERPRET=0`` (then the first trace waits for the compile, as before session 31), nor under
    ``NUMBA_DISABLE_JIT`` (nothing compiles)."""
    return os.environ.get("SPLINECRAFT_JIT_INTERPRET", "").strip() != "0" and not numba.config.DISABLE_JIT


def interpreting() -> bool:
    """Whether the kernels run interpreted now (:mod:`._interpreted`), while a background process compiles them."""
    return _interpreted.active()


def _lock_file() -> str:
    """The file whose lock a background compile holds (:data:`_HELPER_CODE`): one per user, package folder and
    numba cache folder, so two processes that start on a cold cache compile one after the other, the second only
    loading what the first compiled."""
    key = hashlib.sha1(f"{_PACKAGE_FOLDER}\0{numba.config.CACHE_DIR or ''}".encode()).hexdigest()[:16]
    user = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    return os.path.join(tempfile.gettempdir(), f"splinecraft-jit-{user}-{key}.lock")


#: The order in which a background compile (:func:`_start_background`) takes the cold tasks: most interpreted time
#: saved per second of compile first, among the stages a first trace reaches late enough to gain from them (merging,
#: the fit's solves, the fit's checks, after the deviation check alone, :data:`BACKGROUND_FIRST`; the corners run
#: first). Interpreted time of the kernels over five yardstick glyphs (cProfile, session 31): the fit's checks 37 %
#: (the deviation check 32 %), merging 22 %, the fit's solves 17 %, tangent-jump 14 %, the noise estimate 4 %, the
#: rest 6 %; their compiles :data:`WARM_UP_TASKS`.
BACKGROUND_ORDER = ("merge", "fit solves", "fit checks", "noise", "corners", "tips", "tracer", "pixel corners",
                    "polygons")
#: What a background compile runs before its tasks: (module, function) of :mod:`splinecraft.capture`; the deviation
#: check, 32 % of the interpreted time alone (a glyph's first trace at load 2.4-2.7: in place 4.5 s after the trace's
#: start, where the whole fit checks task first put it at 5.4 s; BENCHMARKS.md, "Session 31: the first call
#: interpreted").
BACKGROUND_FIRST = (("fitting._kernels", "warm_up_deviation"),)


def _background_first():
    """Run :data:`BACKGROUND_FIRST` (in a background compile, before its tasks); a step that fails is left to its
    task."""
    for module, function in BACKGROUND_FIRST:
        try:
            getattr(importlib.import_module("splinecraft.capture." + module), function)()
        except Exception:  # noqa: BLE001 -- its task compiles it again, and reports
            pass


#: Seconds between the looks of this process at the kernels a background compile has cached (:func:`_await_background`).
BACKGROUND_POLL = 0.25


def _start_background(names):
    """A fresh interpreter that compiles the warm-up tasks ``names`` into the cache in the background
    (:func:`_spawn_helper` with a lock file): in a session of its own, at a lower priority (``nice`` 10), and it
    finishes even when this process ends first (a one-trace command line fills the cache for the next). A
    thread of this process puts the compiled kernels back in place as soon as it ends (:func:`_back_to_compiled`).
    None when it cannot start."""
    helper = _spawn_helper(names, background=_lock_file())
    if helper is not None:
        threading.Thread(target=_await_background, args=(helper,), daemon=True,
                         name="splinecraft-kernel-compile").start()
    return helper


def _await_background(helper):
    """Until the background compile ``helper`` ends: every :data:`BACKGROUND_POLL` seconds, each interpreted kernel
    that it has cached meanwhile back in place (:func:`._interpreted.restore_ready`: a trace that is running
    interpreted goes on with it compiled, the same results); then every kernel (:func:`_back_to_compiled`)."""
    while True:
        try:
            helper.wait(timeout=BACKGROUND_POLL)
            break
        except subprocess.TimeoutExpired:
            if _interpreted.active():
                _interpreted.restore_ready(is_cached)
    _back_to_compiled(helper)


def _back_to_compiled(helper):
    """The compiled kernels back in place of the interpreted ones once ``helper`` (the background compile) has
    ended; they load from the cache at their first call (or compile there, if the helper failed)."""
    global _BACKGROUND, _BACKGROUND_FAILED
    with _interpreted._LOCK:
        if _BACKGROUND is helper:
            _BACKGROUND = None
            _BACKGROUND_FAILED = helper.returncode != 0
            _interpreted.restore()


def warm_up(tasks=TRACE_TASKS, interpret=False):
    """Compile (empty cache) or load the kernels of the warm-up ``tasks`` (names of :data:`WARM_UP_TASKS`),
    each once per process. When two or more of them are cold and :func:`workers` allows, helper processes
    compile part of them at the same time (:func:`plan`); this process waits for them and loads their kernels
    from the cache. :data:`LAST_WARM_UP` tells what happened.

    Python's cyclic garbage collector is off meanwhile (and on again after, if it was on): numba's compiler
    makes some 10^5 short-lived cyclic objects per task, and the collections they trigger (full ones among
    them, which walk every object of the process) cost about 10 % of a cold compile. Their garbage is
    collected while this process waits for a helper that is still compiling, else by the next automatic
    collection.

    ``interpret=True`` (a trace of a small bitmap, :func:`splinecraft.trace`; or a function that tells, called only
    when some task is cold): when some of the ``tasks`` are cold,
    this process does not compile: a background process (:func:`_start_background`) compiles every cold task, the
    ``tasks`` first, while this process runs the kernels interpreted (:mod:`._interpreted`: their Python source, the
    same results) until it ends; a later call with ``interpret=False`` waits for it. Returns whether the kernels
    are interpreted now."""
    global _BACKGROUND
    unknown = [name for name in tasks if name not in WARM_UP_TASKS]
    if unknown:
        raise ValueError(f"unknown warm-up tasks {unknown}; known: {sorted(WARM_UP_TASKS)}")
    with _LOCK:
        todo = [name for name in dict.fromkeys(tasks) if name not in _DONE]
        helper = _BACKGROUND
        if helper is not None:  # a trace of this process ran interpreted, and the background compile goes on
            _interpreted.restore()  # this call runs the compiled kernels
            if todo:
                _help_background(todo)
            return False
        if not todo:
            return False
        cold = [name for name in todo if not is_cached(_sentinel(name))]
        if cold and may_interpret() and not _BACKGROUND_FAILED and (interpret() if callable(interpret) else interpret):
            others = [name for name in WARM_UP_TASKS if name not in cold and name not in _DONE
                      and not is_cached(_sentinel(name))]
            rank = {name: index for index, name in enumerate(BACKGROUND_ORDER)}
            everything = sorted(cold, key=lambda name: rank.get(name, len(rank))) + others
            for name in WARM_UP_TASKS:  # every kernel module imported: all of them are interpreted
                _sentinel(name)
            helper = _start_background(everything)
            if helper is not None:
                _BACKGROUND, _BACKGROUND_TASKS[:] = helper, everything
                _interpreted.interpret()
                LAST_WARM_UP.update(cold=cold, helpers=[everything], failed=[], forked=[False], interpreted=True)
                return True
        processes = 1 if numba.config.DISABLE_JIT else min(workers(), len(cold))
        late = FORKED_HELPER_START if _can_fork() else HELPER_START
        shares = plan(cold, processes, late) if processes > 1 else [cold]
        helpers = [(share, _start_helper(share)) for share in shares[1:] if share]
        LAST_WARM_UP.update(cold=cold, helpers=[share for share, _ in helpers], failed=[],
                            forked=[isinstance(helper, _Forked) for _, helper in helpers], interpreted=False)
        theirs = {name for share, _ in helpers for name in share}
        collecting = gc.isenabled()
        gc.disable()
        try:
            for name in todo:
                if name not in theirs:
                    _function(name)()
                    _DONE.add(name)
            if collecting and any(helper is not None and helper.poll() is None for _, helper in helpers):
                gc.collect()  # the garbage of this process's compiles, while it waits for the helpers anyway
            for share, helper in helpers:
                if helper is None or not _finished(helper):
                    LAST_WARM_UP["failed"].append(share)
                for name in share:  # loaded from the cache the helper filled, or compiled here if it failed
                    _function(name)()
                    _DONE.add(name)
        finally:  # interrupted (KeyboardInterrupt, an error): no helper keeps compiling for nobody
            if collecting:
                gc.enable()
            for _, helper in helpers:
                _stop(helper)


def warm_up_all():
    """Compile (empty cache) or load every kernel (:func:`warm_up` of every task); ``scripts/bootstrap.sh``
    runs this after an install so that the first trace of a session finds the cache filled."""
    warm_up(tuple(WARM_UP_TASKS))
