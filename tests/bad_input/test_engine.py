"""Hostile arguments for every public function of the engine (splinecraft.spline).

Each case replaces one argument of a valid call by a hostile value (NaN, inf, huge and tiny numbers,
wrong types, bools where numbers belong, strings, nested and ragged lists, wrong shapes, coincident or
equal points, empty arrays). The call must either return a valid result -- finite numbers throughout --
or raise ``ValueError``/``TypeError`` whose message names the argument. Never another exception type,
a NaN in the result, or a hang (every input is small; hypothesis runs without a deadline, but the
whole file takes seconds).
"""
from __future__ import annotations

import math
import warnings

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy import sparse

import splinecraft as sc
from splinecraft.spline.piecewise import Spline

# derandomize: CI runs the same cases every time (fuzzed locally with 1500 random examples per test)
HOSTILE = settings(max_examples=150, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
WAVE = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 3.0], [4.0, 1.0], [6.0, 2.0], [7.0, 0.0]])
LOOP = np.array([[0.0, 0.6], [0.5, 1.0], [1.0, 0.6], [0.0, -1.0], [-1.0, 0.6], [-0.5, 1.0]])


class Opaque:
    """An object no numeric code knows."""


# ---------------------------------------------------------------------------------------------- strategies
scalars = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-320, -1e-320, 0.0, -0.0, -1.0, 1.0, 0.5,
                     -8.0, 3.0, 4.0, 1e15, -1e15, 10**400, -(10**400), 2**63, True, False, np.bool_(True),
                     np.float32(math.nan), np.int64(-3), np.uint8(7), 1j, None, "", "1", "abc", "nan", b"1",
                     Opaque()]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-10**6, 10**6),
)
containers = st.one_of(
    st.sampled_from([[], [[]], [[[]]], (), {}, set(), {"a": 1}, [1, "2"], [None], [[1, 2], [3]],
                     [[1, 2, 3], [4, 5, 6]], np.zeros((0, 2)), np.zeros((3, 0)), np.zeros((2, 2, 2)),
                     np.array(["a", "b"]), np.array([1 + 2j, 3]), np.array([True, False]), np.array(object()),
                     np.full((4, 2), np.nan), [math.inf] * 6, [[0.0, 0.0]] * 6]),
    st.lists(scalars, max_size=8),
    st.lists(st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=2, max_size=2), max_size=8),
)
hostile = st.one_of(scalars, containers)


def point_sets(min_count=2):
    """Point arrays that are valid in form but hostile in content: any scale, coincident, collinear, equal."""
    scale = st.sampled_from([1e-320, 1e-300, 1e-160, 1e-8, 1.0, 1e8, 1e150, 1e300, 1e308])
    raw = st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=min_count, max_size=8)
    shift = st.sampled_from([0.0, 1.0, -1e300, 1e16])
    return st.builds(_scaled, raw, scale, shift)


def _scaled(raw, scale, shift):
    with np.errstate(over="ignore", invalid="ignore"):
        return np.asarray(raw, dtype=float) * scale + shift


# ---------------------------------------------------------------------------------------------- the rule
def finite(result) -> bool:
    """Whether a result holds finite numbers only (curves, arrays, sparse matrices, tuples, numbers)."""
    if isinstance(result, Spline):
        return bool(np.isfinite(result.bezier()).all() and np.isfinite(result.knots).all()
                    and all(np.isfinite(value).all() for value in result.auxiliary.values()))
    if sparse.issparse(result):
        return bool(np.isfinite(result.data).all())
    if isinstance(result, (tuple, list)):
        return all(finite(item) for item in result)
    if isinstance(result, dict):
        return all(finite(item) for item in result.values())
    if isinstance(result, str) or result is None:
        return True
    if isinstance(result, np.ndarray) and result.dtype.kind in "biuf":
        return bool(np.isfinite(result).all())
    if isinstance(result, (int, float, np.integer, np.floating)):
        return bool(np.isfinite(result))
    return True


def check(call, names):
    """Run ``call()``: a finite result, or a ValueError/TypeError whose message names one of ``names``."""
    try:
        result = call()
    except (ValueError, TypeError) as exc:
        message = str(exc)
        assert any(name in message for name in names), f"{type(exc).__name__} does not name {names}: {message}"
        return None
    assert finite(result), f"non-finite result {result!r}"
    return result


# ---------------------------------------------------------------------------------------------- constructors
INTERPOLATE = ["points", "closed", "point_tension", "interval_weights", "alpha", "beta", "end_condition",
               "end_tangents", "knots", "point_tension_scale"]


@HOSTILE
@given(st.sampled_from(INTERPOLATE[1:]), hostile)
def test_interpolate_hostile_argument(name, value):
    kwargs = {name: value}
    if name == "end_tangents":
        kwargs["end_condition"] = "clamped"
    names = [name] + (["end_tangents"] if name == "end_tangents" else []) + (["end_condition"] if name == "closed" else [])
    check(lambda: sc.interpolate(WAVE, **kwargs), names)


@HOSTILE
@given(point_sets(), st.booleans(), st.sampled_from(["chord", "centripetal", "uniform"]),
       st.sampled_from(["absolute", "relative"]))
def test_interpolate_hostile_points(points, closed, knots, scale):
    check(lambda: sc.interpolate(points, closed=closed, knots=knots, point_tension_scale=scale,
                                 point_tension=1.0), ["points", "float64"])


@HOSTILE
@given(hostile)
def test_interpolate_hostile_points_type(value):
    check(lambda: sc.interpolate(value), ["points"])


BASIS = ["closed", "point_tension", "interval_weights", "alpha", "beta", "knots", "ends", "point_tension_scale"]


@HOSTILE
@given(st.sampled_from(BASIS), hostile)
def test_basis_spline_hostile_argument(name, value):
    names = [name] + (["ends"] if name == "closed" else []) + (["knot", "basis is degenerate"]
                                                               if name in ("point_tension", "interval_weights") else [])
    check(lambda: sc.basis_spline(WAVE, **{name: value}), names)


@HOSTILE
@given(point_sets(min_count=3), st.booleans(), st.sampled_from(["uniform", "chord", "centripetal"]))
def test_basis_spline_hostile_control_points(points, closed, knots):
    check(lambda: sc.basis_spline(points, closed=closed, knots=knots), ["control_points", "basis is degenerate"])


@HOSTILE
@given(st.sampled_from(["t", "knots_or_n", "point_tension", "interval_weights", "closed", "ends"]), hostile)
def test_basis_functions_hostile_argument(name, value):
    kwargs = {"t": np.linspace(1.0, 4.0, 7), "knots_or_n": 6}
    kwargs[name] = value
    names = [name, "domain"] + (["control points", "knots"] if name == "knots_or_n" else []) \
        + (["basis is degenerate"] if name in ("point_tension", "interval_weights") else []) \
        + (["ends"] if name == "closed" else [])
    check(lambda: sc.basis_functions(kwargs.pop("t"), kwargs.pop("knots_or_n"), **kwargs), names)


@HOSTILE
@given(st.sampled_from(["F0", "V", "W", "F1", "alpha", "beta", "knots"]), hostile)
def test_generic_segment_hostile_argument(name, value):
    kwargs = {"F0": [0.0, 0.0], "V": [1.0, 2.0], "W": [3.0, 2.0], "F1": [4.0, 0.0], "alpha": 3.0, "beta": 3.0}
    kwargs[name] = value
    names = [name] + (["F0, V, W, F1"] if name in ("F0", "V", "W", "F1") else [])
    check(lambda: sc.generic_segment(**kwargs), names)


TIMMER = {
    "timmer_g2": (sc.timmer_g2, ["closed", "tangents", "alpha0", "clamp"]),
    "timmer_gc1": (sc.timmer_gc1, ["closed", "alpha", "beta", "tangents", "shape_scale"]),
    "timmer_gc2": (sc.timmer_gc2, ["closed", "alpha", "beta", "end_derivatives", "joint"]),
}


@HOSTILE
@given(st.sampled_from(sorted(TIMMER)), st.data(), hostile)
def test_timmer_hostile_argument(scheme, data, value):
    build, arguments = TIMMER[scheme]
    name = data.draw(st.sampled_from(arguments))
    names = [name, "alpha", "beta"] if name in ("alpha", "beta", "shape_scale", "alpha0", "clamp") else [name]
    if name == "closed":
        names.append("end_derivatives")
    check(lambda: build(WAVE, **{name: value}), names + (["Timmer GC2 tangent system"] if scheme == "timmer_gc2" else []))


@HOSTILE
@given(st.sampled_from(sorted(TIMMER)), point_sets(min_count=3), st.booleans())
def test_timmer_hostile_points(scheme, points, closed):
    build, _ = TIMMER[scheme]
    check(lambda: build(points, closed=closed), ["points", "alpha", "Timmer GC2 tangent system", "tangents"])


@HOSTILE
@given(st.one_of(point_sets(min_count=2), hostile), st.sampled_from(["closed", "method", "reversal_tol", None]),
       hostile)
def test_estimate_tangents_hostile(points, name, value):
    kwargs = {} if name is None else {name: value}
    check(lambda: sc.estimate_tangents(points, **kwargs), ["points"] + ([name] if name else []))


@HOSTILE
@given(st.sampled_from(["bezier", "knots", "closed", "auxiliary", "info"]), hostile)
def test_spline_constructor_hostile_part(name, value):
    kwargs = {"bezier": [[[0.0, 0.0], [1.0, 1.0], [2.0, 1.0], [3.0, 0.0]]], "knots": [0.0, 1.0]}
    kwargs[name] = value
    check(lambda: Spline(**kwargs), [name] + (["pieces", "closed=True"] if name in ("bezier", "closed") else []))


@HOSTILE
@given(st.sampled_from(["type", "version", "closed", "knots", "bezier", "auxiliary", "auxiliary_shapes", "info",
                        "extra"]), hostile)
def test_from_dict_hostile_key(key, value):
    data = sc.interpolate(WAVE).to_dict()
    data[key] = value
    check(lambda: Spline.from_dict(data), [key, "from_dict", "bezier", "knots", "pieces"])


# ---------------------------------------------------------------------------------------------- methods
CURVES = {
    "interpolant": sc.interpolate(WAVE),
    "loop": sc.basis_spline(LOOP, closed=True),
    "timmer": sc.timmer_g2(LOOP, closed=True),
    "segment": sc.generic_segment([0, 0], [1, 2], [3, 2], [4, 0], 4.0, 2.0),
}
METHODS = {
    "__call__": ["t", "nu", "extrapolate", "side"],
    "curvature": ["t", "side", "extrapolate"],
    "sample": ["tolerance", "max_points", "samples_per_segment", "method"],
    "curvature_comb": ["scale", "samples_per_segment"],
    "curvature_profile": ["samples_per_piece"],
    "to_svg_path": ["precision"],
    "nearest": ["point"],
    "construction": ["t"],
    "piece_leg": ["piece"],
    "leg_pieces": ["leg"],
    "transformed": ["matrix", "offset"],
}
REQUIRED = {"__call__": {"t": 0.5}, "curvature": {"t": 0.5}, "nearest": {"point": [0.5, 0.5]},
            "construction": {"t": 0.5}, "piece_leg": {"piece": 0}, "leg_pieces": {"leg": 0},
            "transformed": {"matrix": np.eye(2)}}
MAY_HOLD_NAN = {"curvature", "curvature_profile"}  # NaN where the speed vanishes / at open ends, by contract


@HOSTILE
@given(st.sampled_from(sorted(CURVES)), st.sampled_from(sorted(METHODS)), st.data(), hostile)
def test_spline_method_hostile_argument(curve_name, method, data, value):
    curve = CURVES[curve_name]
    name = data.draw(st.sampled_from(METHODS[method]))
    kwargs = dict(REQUIRED.get(method, {}))
    kwargs[name] = value
    bound = getattr(curve, method)
    if method in MAY_HOLD_NAN:
        try:
            bound(**kwargs)
        except (ValueError, TypeError) as exc:
            assert name in str(exc) or "domain" in str(exc), str(exc)
        return
    check(lambda: bound(**kwargs), [name, "domain"])


def test_methods_without_arguments_on_extreme_curves():
    """Curves the library builds at the float64 limits: every query gives finite results (or NaN by contract)."""
    warnings.simplefilter("ignore", RuntimeWarning)  # sample() coarsens (and says so) at 1e300 with tolerance 0.25
    for scale in (1e-300, 1e300):
        for curve in (sc.interpolate(WAVE * scale), sc.basis_spline(LOOP * scale, closed=True),
                      sc.timmer_gc2(WAVE * scale), sc.timmer_gc1(WAVE, alpha=1e-300)):
            assert finite(curve.sample()) and finite(curve.sample(method="subdivide"))
            assert finite(curve.curvature_comb()) and finite(curve.to_svg_path())
            assert finite(curve.nearest(curve.knot_points[0] + scale))
            kappa = curve.joint_curvature()
            assert np.isfinite(kappa[1:-1]).all() or curve.closed
            assert finite(Spline.from_dict(curve.to_dict()))
