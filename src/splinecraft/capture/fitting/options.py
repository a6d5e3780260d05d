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
                "hoschek_gate": 2.0, "sample_spacing": 0.5, "geometric_corners": False, "corner_pin": 0.0,
                "initial_density": 0.01, "fallback": True}
LSQ_OPTIONS = tuple(LSQ_DEFAULTS)
_LSQ_REALS = ("corner_radius", "corner_allowance", "tip_gap", "hoschek_gate", "sample_spacing", "corner_pin",
              "initial_density")
_LSQ_BOOLS = ("remove_knots", "geometric_corners", "fallback")


def check_points(points):
    """A closed contour as a contiguous float ``(n, 2)`` array: finite, ``n >= 4``, no coincident neighbours."""
    if isinstance(points, (str, bytes)):
        raise TypeError("points must be an (n, 2) array of numbers")
    try:
        array = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"points must be an (n, 2) array of numbers: {exc}") from None
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got {array.shape}")
    bad = np.flatnonzero(~np.isfinite(array).all(axis=1))
    if bad.size:
        raise ValueError(f"points[{bad[0]}] is not finite: {array[bad[0]].tolist()}")
    if array.shape[0] < 4:
        raise ValueError(f"points needs at least 4 points for a closed outline, got {array.shape[0]}")
    steps = np.hypot(*(np.roll(array, -1, axis=0) - array).T)
    extent = float(np.ptp(array, axis=0).max())
    dup = np.flatnonzero(steps <= 1e-12 * max(extent, 1.0))
    if dup.size:
        i = int(dup[0])
        raise ValueError(f"points[{i}] and points[{(i + 1) % array.shape[0]}] coincide; merge consecutive "
                         "duplicate points first (the first point must not be repeated at the end)")
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
    if isinstance(epsilon, (bool, np.bool_)) or not isinstance(epsilon, numbers.Real):
        raise TypeError(f"epsilon must be a positive number (px), got {type(epsilon).__name__}")
    value = float(epsilon)
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"epsilon must be a finite number > 0 (px), got {epsilon!r}")
    if value < MIN_EPSILON:
        raise ValueError(f"epsilon must be >= {MIN_EPSILON:g} px (a thousandth of a pixel, far below what a fit "
                         f"of a pixel outline can resolve), got {epsilon!r}")
    return value


def check_count(value, name, minimum):
    """An integer option (not a bool) ``>= minimum``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer >= {minimum}, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def check_flag(value, name):
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def check_method(method):
    if not isinstance(method, str):
        raise TypeError(f"method must be a string, got {type(method).__name__}")
    if method not in KNOT_METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {sorted(KNOT_METHODS)}")
    return method


def check_tau(tau, method):
    if tau is None:
        return DEFAULT_TAU.get(method)
    if method not in DEFAULT_TAU:
        raise ValueError(f"tau is used by the methods 'euclidean' and 'positional' only, not {method!r}")
    if isinstance(tau, bool) or not isinstance(tau, numbers.Real) or not math.isfinite(float(tau)):
        raise ValueError(f"tau must be a finite number, got {tau!r}")
    tau = float(tau)
    if method == "euclidean" and tau < 0:
        raise ValueError(f"tau (Euclidean nearness, px) must be >= 0, got {tau}")
    if method == "positional" and not 0 <= tau < 50:
        raise ValueError(f"tau (positional nearness, % of the piece's points) must be in [0, 50), got {tau}")
    return tau


def make_rng(seed):
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, numbers.Integral)):
        raise TypeError(f"seed must be an int, None or a numpy Generator, got {type(seed).__name__}")
    if seed is not None and int(seed) < 0:
        raise ValueError(f"seed must be >= 0, got {seed}")
    return np.random.default_rng(seed)


def check_small_outline(small_outline):
    if small_outline is None:
        return SMALL_OUTLINE
    if isinstance(small_outline, bool) or not isinstance(small_outline, numbers.Integral) or small_outline < 0:
        raise ValueError(f"small_outline must be an integer >= 0, got {small_outline!r}")
    return int(small_outline)


def check_options(method, options):
    """The ``**options`` of :func:`~splinecraft.capture.fitting.fit_outline` for ``method``: the full lsq
    table (defaults filled in), or ``{"engine", "tangent_stride", "fuzzy_weights"}`` for the thesis methods."""
    allowed = LSQ_OPTIONS if method == "lsq" else THESIS_OPTIONS
    for key in options:
        if key not in allowed:
            if method == "lsq" and key in THESIS_OPTIONS:
                raise ValueError(
                    f"{key!r} applies to the thesis methods {THESIS_METHODS}; method 'lsq' fits in the "
                    "v = 0, omega = 1 family of the interpolant (its least-squares problem is linear there)")
            raise TypeError(f"fit_outline() got an unexpected option {key!r} for method {method!r}; "
                            f"allowed: {sorted(allowed)}")
    return _check_lsq_options(options) if method == "lsq" else _check_thesis_options(options)


def _check_lsq_options(options):
    out = dict(LSQ_DEFAULTS)
    out.update(options)
    for key in _LSQ_REALS:
        value = out[key]
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value < 0:
            raise ValueError(f"{key} must be a finite number >= 0, got {value!r}")
    if out["initial_density"] > 1e6:
        raise ValueError(f"initial_density must be <= 1e6, got {out['initial_density']!r}")
    if out["sample_spacing"] <= 0 or out["sample_spacing"] > 2:
        raise ValueError(f"sample_spacing must be in (0, 2] px, got {out['sample_spacing']!r}")
    if isinstance(out["min_gap"], bool) or not isinstance(out["min_gap"], numbers.Integral) or out["min_gap"] < 1:
        raise ValueError(f"min_gap must be an integer >= 1, got {out['min_gap']!r}")
    for key in _LSQ_BOOLS:
        if not isinstance(out[key], (bool, np.bool_)):
            raise TypeError(f"{key} must be True or False, got {out[key]!r}")
    return out


def _check_thesis_options(options):
    out = dict(options)
    stride = out.pop("tangent_stride", 3)
    if isinstance(stride, bool) or not isinstance(stride, numbers.Integral) or stride < 1:
        raise ValueError(f"tangent_stride must be an integer >= 1, got {stride!r}")
    weights = out.pop("fuzzy_weights", (0.7, 0.3))
    try:
        w, v = (float(x) for x in weights)
    except (TypeError, ValueError):
        raise ValueError(f"fuzzy_weights must be a pair (w, v) of numbers, got {weights!r}") from None
    if not (math.isfinite(w) and math.isfinite(v) and w > v >= 0):
        raise ValueError(f"fuzzy_weights (w, v) need w > v >= 0 (thesis eq 4.21), got {weights!r}")
    return {"engine": out, "tangent_stride": int(stride), "fuzzy_weights": (w, v)}
