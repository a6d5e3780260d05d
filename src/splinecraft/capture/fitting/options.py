"""Defaults, option tables and argument checks of the outline fit (docs/capture.md §12).

The bottom of the fitting package: it imports nothing of the package. The public entries
(:func:`~splinecraft.capture.fitting.fit_outline`, :func:`~splinecraft.capture.fitting.fit_small_outlines`,
:func:`~splinecraft.capture.trace.trace`) check their arguments here once; the fitting families below them
trust what they get.
"""
from __future__ import annotations

import math
import numbers

import numpy as np

from ... import _validation

#: Knot insertion methods: name -> one-line description (thesis section 4.3, and the deterministic default).
KNOT_METHODS = {
    "lsq": "least-squares regression spline with worst-point knot insertion, Hoschek re-parameterization, "
           "corner tip extrapolation and knot removal (deterministic; the default)",
    "random": "Alg 4.1: single unconstrained random point per piece (eq 4.10)",
    "euclidean": "Alg 4.2: single random point with a Euclidean nearness constraint tau in px (eqs 4.13-4.15)",
    "positional": "Alg 4.3: single random point with a positional nearness constraint tau in % of the piece's "
                  "points (eq 4.16)",
    "random3": "Alg 4.4: three unconstrained random points per piece",
    "equal3": "Alg 4.5: one random point in each of three equal sub-segments of the piece",
    "fuzzy": "Alg 4.6: fuzzy random knot selection (three candidates, fuzzy Euclidean and positional distance, "
             "weights w > v, product aggregation, eqs 4.17-4.21)",
}
THESIS_METHODS = ("random", "euclidean", "positional", "random3", "equal3", "fuzzy")
DEFAULT_METHOD = "lsq"
#: Default tolerance (px); why 0.8: docs/capture.md §12, "Default epsilon".
DEFAULT_EPSILON = 0.8
#: Smallest accepted tolerance (px). Crack outlines are on a half-pixel grid and the deviation checks sample
#: the curve every 0.25 px, so a thousandth of a pixel is already far below what a fit can resolve; smaller
#: values would only ask for more knots than the contour has points.
MIN_EPSILON = 1e-3
DEFAULT_TAU = {"euclidean": 5.0, "positional": 5.0}
#: Iterations without an accepted candidate after which an unfinished piece takes its next candidate anyway.
STALL_ITERATIONS = 10
#: Contours with fewer points than this are fitted by the small-outline path of ``"lsq"``
#: (:func:`~splinecraft.capture.fitting.fit_small_outlines`); ``fit_outline(..., small_outline=0)`` turns it off.
SMALL_OUTLINE = 64
#: A contour whose ``"lsq"`` fit gets stuck above ``epsilon`` is refitted by the interpolant path (option
#: ``fallback``) when its longest piece (contour steps between consecutive corners; the whole contour without
#: corners) has at most this many steps: that path solves each piece as one dense system.
FALLBACK_PIECE = 2048

# options accepted through **options, per method family
ENGINE_OPTIONS = ("point_tension", "interval_weights", "alpha", "beta", "point_tension_scale")
THESIS_OPTIONS = ENGINE_OPTIONS + ("tangent_stride", "fuzzy_weights")
#: Options of ``"lsq"`` and their defaults (the meaning of each: docs/capture.md §12, "Options of lsq").
LSQ_DEFAULTS = {"corner_radius": 2.0, "corner_allowance": 0.5, "tip_gap": 0.5, "min_gap": 3, "remove_knots": True,
                "hoschek_gate": 2.0, "sample_spacing": 0.5, "geometric_corners": "clean", "corner_pin": 1000.0,
                "initial_density": 0.01, "fallback": True, "joint_continuity": 2, "merge_tolerance": 0.5,
                "pixel_check": False, "pixel_slack": 0.1, "curvature_jumps": "smooth"}
LSQ_OPTIONS = tuple(LSQ_DEFAULTS)
#: Real options of lsq checked as finite numbers >= 0 (``sample_spacing`` and ``initial_density`` are checked
#: against their own ranges, so that every bad value gets that range in its message).
_LSQ_REALS = ("corner_radius", "corner_allowance", "tip_gap", "hoschek_gate", "corner_pin", "merge_tolerance",
              "pixel_slack")
_LSQ_BOOLS = ("remove_knots", "fallback", "pixel_check")
#: Smallest ``sample_spacing`` (px) of the deviation check: 25 samples per pixel beside the final check's 4. The
#: samples (and the chords searched around each) grow as 1 / spacing: 1e-5 px took 20 s on a 160-px disc,
#: 1e-6 px exhausted the memory and 1e-12 px asked numpy for 1.4 PiB.
MIN_SAMPLE_SPACING = 0.01


def check_points(points):
    """A closed contour as a contiguous float ``(n, 2)`` array: finite, ``n >= 4``, no two neighbours coincide
    (the coincidence rule of :mod:`splinecraft._validation`, the last point and the first are neighbours)."""
    array = _validation.as_float_array(points, "points")
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got {array.shape}")
    array = _validation.check_points(array, "points", min_count=4, dim=2, distinct=True, closed=True)
    return np.ascontiguousarray(array)


def check_corners(corner_indices, n):
    """Sorted unique corner indices (int64) into a contour of ``n`` points."""
    if corner_indices is None:
        return np.zeros(0, dtype=np.int64)
    if isinstance(corner_indices, (str, bytes)):
        raise TypeError("corner_indices must be a 1-d array of integer indices")
    array = np.asarray(corner_indices)
    if array.size == 0:
        return np.zeros(0, dtype=np.int64)
    if array.ndim != 1:
        raise ValueError(f"corner_indices must be 1-d, got shape {array.shape}")
    if array.dtype.kind not in "iu":
        if array.dtype.kind == "f" and np.all(np.isfinite(array)) and np.all(array == np.round(array)):
            array = array.astype(np.int64)
        else:
            raise TypeError(f"corner_indices must be integers, got dtype {array.dtype}")
    bad = np.flatnonzero((array < 0) | (array >= n))
    if bad.size:
        raise ValueError(f"corner_indices[{bad[0]}] = {int(array[bad[0]])} is outside 0..{n - 1}")
    return np.unique(array.astype(np.int64))


def check_epsilon(epsilon):
    """The tolerance as a float in ``[MIN_EPSILON, inf)`` px."""
    return _validation.check_number(epsilon, "epsilon (px)", minimum=MIN_EPSILON)


def check_count(value, name, minimum):
    """An integer option (not a bool) ``>= minimum``."""
    return _validation.check_int(value, name, minimum=minimum)


def check_flag(value, name):
    """``True``, ``False`` or ``np.bool_``."""
    return _validation.check_bool(value, name)


def check_method(method):
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__}")
    if method not in KNOT_METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {sorted(KNOT_METHODS)}")
    return method


def check_tau(tau, method):
    """The nearness threshold of Algs 4.2 and 4.3 (their default when ``None``)."""
    if tau is None:
        return DEFAULT_TAU.get(method)
    if method not in DEFAULT_TAU:
        raise ValueError(f"tau is used by the methods 'euclidean' and 'positional' only, not {method!r}")
    if method == "euclidean":
        return _validation.check_number(tau, "tau (Euclidean nearness, px)", minimum=0.0)
    return _validation.check_number(tau, "tau (positional nearness, % of the piece's points)", minimum=0.0,
                                    maximum=50.0, inclusive=(True, False))


def make_rng(seed):
    """A :class:`numpy.random.Generator` from ``seed`` (an int >= 0, None or a Generator)."""
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is not None:
        seed = _validation.check_int(seed, "seed", minimum=0)
    return np.random.default_rng(seed)


def check_small_outline(small_outline, name="small_outline", method="lsq"):
    """The small-outline threshold (``None``: :data:`SMALL_OUTLINE`); given for another ``method`` than ``"lsq"``
    (which has no small-outline path) a ``ValueError``, as the other options a method does not take."""
    if small_outline is None:
        return SMALL_OUTLINE
    if method != "lsq":
        raise ValueError(f"{name} is used by the method 'lsq' only (its small-outline path), not {method!r}")
    return _validation.check_int(small_outline, name, minimum=0)


def check_options(method, options, source=None):
    """The ``**options`` of :func:`~splinecraft.capture.fitting.fit_outline` for ``method``: the full lsq
    table (defaults filled in), or ``{"engine", "tangent_stride", "fuzzy_weights"}`` for the thesis methods.

    ``source`` names the mapping the options came from in messages: ``None`` (keyword arguments of
    ``fit_outline``) names an option bare (``merge_tolerance must be >= 0``); ``"fit_params"`` (of
    :func:`~splinecraft.capture.trace.trace`, ``trace_many``, the trace explorer) names it as the key the caller
    wrote (``fit_params['merge_tolerance'] must be >= 0``)."""
    def label(key):
        return key if source is None else f"{source}[{key!r}]"

    allowed = LSQ_OPTIONS if method == "lsq" else THESIS_OPTIONS
    for key in options:
        if key not in allowed:
            if method == "lsq" and key in THESIS_OPTIONS:
                raise ValueError(
                    f"{label(key) if source else repr(key)} applies to the thesis methods {THESIS_METHODS}; method "
                    "'lsq' fits in the v = 0, omega = 1 family of the interpolant (its least-squares problem is "
                    "linear there)")
            where = "fit_outline() got an unexpected option" if source is None else f"{source} has an unknown key"
            raise TypeError(f"{where} {key!r} for method {method!r}; allowed: {sorted(allowed)}")
    if "fuzzy_weights" in options and method != "fuzzy":  # as tau for the methods without a nearness rule
        raise ValueError(f"{label('fuzzy_weights')} is used by the method 'fuzzy' (Alg 4.6) only, not {method!r}")
    return _check_lsq_options(options, label) if method == "lsq" else _check_thesis_options(options, label)


def _check_lsq_options(options, label):
    out = dict(LSQ_DEFAULTS)
    out.update(options)
    for key in _LSQ_REALS:
        out[key] = _validation.check_number(out[key], label(key), minimum=0.0)
    out["initial_density"] = _validation.check_number(out["initial_density"], label("initial_density"), minimum=0.0,
                                                      maximum=1e6)
    out["sample_spacing"] = _validation.check_number(out["sample_spacing"], f"{label('sample_spacing')} (px)",
                                                     minimum=MIN_SAMPLE_SPACING, maximum=2.0)
    out["min_gap"] = _validation.check_int(out["min_gap"], label("min_gap"), minimum=1)
    out["joint_continuity"] = _validation.check_int(out["joint_continuity"],
                                                    f"{label('joint_continuity')} (1 = C1, 2 = C2)", minimum=1,
                                                    maximum=2)
    for key in _LSQ_BOOLS:
        out[key] = _validation.check_bool(out[key], label(key))
    # "clean": extrapolated unless trace() measured a noisy boundary; True: always; False: never (docs/capture.md
    # §12, "Corners of lsq"); resolved by :func:`extrapolates_tips`
    out["geometric_corners"] = _validation.check_choice(out["geometric_corners"], label("geometric_corners"),
                                                        (False, True, "clean"))
    # "smooth": outlines without corners; True: every outline; False: none (docs/capture.md §12, "Curvature jumps")
    out["curvature_jumps"] = _validation.check_choice(out["curvature_jumps"], label("curvature_jumps"),
                                                      (False, True, "smooth"))
    return out


def extrapolates_tips(geometric_corners, noisy=False):
    """Whether the ``"lsq"`` fit extrapolates corner tips (option ``geometric_corners``, docs/capture.md §12,
    "Corners of lsq"): ``True`` and ``False`` say so; ``"clean"`` (the default) extrapolates unless the boundary
    is ``noisy``, i.e. :func:`~splinecraft.capture.trace.trace`'s boundary-noise estimate exceeds
    ``fitting.noise.CLEAN_NOISE``. The extrapolation reads each side as a digital straight segment (a line that
    separates the side's ink pixel centres from its paper ones, checked against the tip's pixels to 0.1 px);
    on a boundary ragged by noise no such line exists and the test against the tip's pixels measures the noise,
    so the tips would cost the fit's setup and change nothing (BENCHMARKS.md, "Session 15"). A contour fitted
    by itself (``fit_outline``) has no noise estimate: ``"clean"`` extrapolates there."""
    if geometric_corners == "clean":
        return not noisy
    return bool(geometric_corners)


def _check_engine_options(options, label=str):
    """The interpolant's options of the thesis methods (:data:`ENGINE_OPTIONS`), checked before any fit. Each piece
    is interpolated through its current knot points, whose count changes with every insertion, so an option is
    one number for all of them: an array (per point or per interval in
    :func:`~splinecraft.spline.interpolant.interpolate`) was taken where its length happened to match the
    first knots (silently, on an outline that converged at once) and refused on the next with a count of
    knots the caller never saw. ``point_tension``'s sign rule depends on the chords: the interpolant checks it."""
    out = dict(options)
    if "point_tension_scale" in out:
        out["point_tension_scale"] = _validation.check_choice(out["point_tension_scale"],
                                                              label("point_tension_scale"), ("absolute", "relative"))
    for key in ("point_tension", "interval_weights", "alpha", "beta"):
        if key not in out:
            continue
        value = out[key]
        if not isinstance(value, (numbers.Real, np.bool_)):  # bools: check_number names them
            raise TypeError(f"{label(key)} must be one number for every piece of a thesis method's fit (its knots "
                            f"change with every insertion), got {_validation._describe(value)} "
                            f"({type(value).__name__})")
        number = _validation.check_number(value, label(key))
        if key == "interval_weights" and not number > 0:
            raise ValueError(f"{label(key)} must be > 0, got {number!r}")
        if key in ("alpha", "beta") and number == 0:
            raise ValueError(f"{label(key)} must be non-zero (the class polygon divides by it), got 0.0")
        out[key] = number
    return out


def _check_thesis_options(options, label):
    out = _check_engine_options({key: value for key, value in options.items() if key in ENGINE_OPTIONS}, label)
    out.update({key: value for key, value in options.items() if key not in ENGINE_OPTIONS})
    stride = _validation.check_int(out.pop("tangent_stride", 3), label("tangent_stride"), minimum=1)
    weights = out.pop("fuzzy_weights", (0.7, 0.3))
    if isinstance(weights, (str, bytes)) or not hasattr(weights, "__len__") or len(weights) != 2:
        raise TypeError(f"{label('fuzzy_weights')} must be a pair (w, v) of numbers, got "
                        f"{_validation._describe(weights)}")
    w = _validation.check_number(weights[0], f"{label('fuzzy_weights')}[0] (w)")
    v = _validation.check_number(weights[1], f"{label('fuzzy_weights')}[1] (v)", minimum=0.0)
    if not w > v:
        raise ValueError(f"{label('fuzzy_weights')} (w, v) need w > v >= 0 (thesis eq 4.21), got "
                         f"{_validation._describe(weights)}")
    return {"engine": out, "tangent_stride": stride, "fuzzy_weights": (w, v)}
