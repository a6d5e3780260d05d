"""The SplineEditor's model as plain data: a state dict and pure functions from one state to the next.

A *state* is a dict with the keys :data:`MODEL_TRAITS` (``points`` a list of ``[x, y]``, the other values
plain Python scalars, strings and lists). Every function here takes a state and returns a new one (or
raises :class:`Rejected` with a short reason); none touches a widget, so the editor's rules are
testable without Jupyter. :func:`check_state` is the one gate: it applies the editor's own limits
(choices, :data:`MAX_POINTS`, coordinate and weight ranges) and builds the curve with the engine, whose
errors name the argument and index.
"""
from __future__ import annotations

import math

import numpy as np

from .._validation import as_points, check_bool, check_choice, check_distinct_neighbours, check_number, per_item
from ._forms import ALPHA_MEANING, FORMS, KNOT_CHOICES, PRESETS, build_spline, default_end_condition, end_choices

__all__ = ["MODEL_TRAITS", "MAX_POINTS", "MAX_COORDINATE", "check_reach", "Rejected", "copy_state", "interval_count", "initial_state",
           "check_state", "derive", "moved", "inserted", "deleted", "insertion_place", "segment_points",
           "describe_change"]

#: Traits that define the curve (undo/redo restores exactly these).
MODEL_TRAITS = ("points", "point_tension", "interval_weights", "alpha", "beta", "preset", "form", "closed",
                "end_condition", "knots", "tension_scale")
#: Default cap on the number of points (``SplineEditor(max_points=...)`` changes it): every edit rebuilds
#: the whole curve, about 1 ms per 1000 points, so 5000 points keep a drag interactive.
MAX_POINTS = 5000
#: Coordinates beyond this are refused, by the SplineEditor and the OutlineEditor alike: the page draws in float32,
#: and farther out an outline's own checks only see coinciding knots (every other knot is that near, relatively).
MAX_COORDINATE = 1e9
#: Interval weights above this are refused.
MAX_WEIGHT = 1e6


def check_reach(points, what: str = "knot") -> None:
    """``ValueError`` naming the first of ``points`` (n, 2) with a coordinate beyond ±:data:`MAX_COORDINATE`
    (NaN and inf too): ``what`` names them ("point", "knot", "control point ..."); both editors' messages."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    with np.errstate(invalid="ignore"):
        beyond = ~(np.abs(points) <= MAX_COORDINATE).all(axis=1)
    if beyond.any():
        i = int(np.flatnonzero(beyond)[0])
        raise ValueError(f"{what} {i} at ({points[i, 0]:g}, {points[i, 1]:g}) is beyond ±{MAX_COORDINATE:g}")
#: Class parameters above this are refused.
MAX_CLASS_PARAMETER = 100.0
TENSION_SCALES = ("relative", "absolute")


class Rejected(ValueError):
    """A proposed state is bad; the message says why (shown in the widget)."""


def copy_state(state: dict) -> dict:
    """Copy of a state: lists one level deep (``[x, y]`` items are replaced, never mutated, so sharing them is safe)."""
    return {name: list(value) if isinstance(value, list) else value for name, value in state.items()}


def interval_count(n: int, closed: bool, form: str) -> int:
    """Number of intervals (interval weights) of ``n`` points."""
    return n if closed and FORMS[form]["closed"] else max(n - 1, 0)


def _point_list(points, max_points) -> list:
    array = as_points(points, "points", min_count=0, dim=2)
    if array.shape[0] > max_points:
        raise ValueError(f"points has {array.shape[0]} points; the editor takes at most max_points = {max_points}")
    return array.tolist()


def _default_points(form: str) -> list:
    if form == "segment":
        return [[60.0, 320.0], [160.0, 80.0], [420.0, 80.0], [520.0, 320.0]]
    angles = np.linspace(0.15, 2.0 * np.pi - 0.35, 6)
    radius = np.array([150.0, 110.0, 160.0, 100.0, 150.0, 120.0])
    return (np.c_[300.0 + radius * np.cos(angles), 220.0 - radius * np.sin(angles)]).round(1).tolist()


def initial_state(points, params: dict, *, max_points: int = MAX_POINTS) -> dict:
    """The state of ``SplineEditor(points, **params)``; ``TypeError``/``ValueError`` naming a bad argument."""
    form = check_choice(params.get("form", "interpolant"), "form", tuple(FORMS))
    explicit_class = "alpha" in params or "beta" in params
    state = {
        "form": form,
        "closed": check_bool(params.get("closed", False), "closed"),
        "preset": check_choice(params.get("preset", "free" if explicit_class else ALPHA_MEANING[form][1][0]),
                               "preset", tuple(PRESETS)),
        "knots": check_choice(params.get("knots", "chord"), "knots", tuple(dict(KNOT_CHOICES))),
        "tension_scale": check_choice(params.get("tension_scale", "relative"), "tension_scale", TENSION_SCALES),
        "points": _point_list(_default_points(form) if points is None else points, max_points),
    }
    n = len(state["points"])
    values = PRESETS[state["preset"]][1] or ALPHA_MEANING[form][1][1:]
    state["alpha"] = check_number(params.get("alpha", values[0]), "alpha")
    state["beta"] = check_number(params.get("beta", values[1]), "beta")
    state["end_condition"] = check_choice(params.get("end_condition", default_end_condition(form)), "end_condition",
                                          end_choices(form))
    state["point_tension"] = per_item(params.get("point_tension", 0.0), n, "point_tension",
                                      what="one per point").tolist()
    count = interval_count(n, state["closed"], form)
    state["interval_weights"] = per_item(params.get("interval_weights", 1.0), count, "interval_weights",
                                         what="one per interval").tolist()
    return state


def _check_choices(state) -> None:
    form = state["form"]
    if form not in FORMS:
        raise Rejected(f"unknown form {form!r}; choose one of {', '.join(FORMS)}")
    if state["preset"] not in PRESETS:
        raise Rejected(f"unknown class preset {state['preset']!r}")
    if state["knots"] not in dict(KNOT_CHOICES):
        raise Rejected(f"unknown knots {state['knots']!r}")
    if state["tension_scale"] not in TENSION_SCALES:
        raise Rejected(f"tension_scale must be 'relative' or 'absolute', not {state['tension_scale']!r}")
    if state["end_condition"] not in end_choices(form):
        ends = FORMS[form]["ends"]
        raise Rejected(f"{ends[0] if ends else 'end condition'} {state['end_condition']!r} does not apply to this "
                       f"form ({', '.join(end_choices(form))})")
    if type(state["closed"]) is not bool:
        raise Rejected(f"closed must be true or false, got {state['closed']!r}")


def _check_numbers(state, max_points) -> None:
    form = state["form"]
    points = np.array(state["points"], dtype=float).reshape(-1, 2)
    if len(points) > max_points:
        raise Rejected(f"{len(points)} points; the editor takes at most max_points = {max_points}")
    finite = np.isfinite(points).all(axis=1)
    if not finite.all():
        raise Rejected(f"point {int(np.flatnonzero(~finite)[0])} is not a finite number")
    try:
        check_reach(points, "point")
    except ValueError as exc:
        raise Rejected(str(exc)) from None
    closed = state["closed"] and FORMS[form]["closed"]
    need = FORMS[form]["min_points"][1 if closed else 0]
    if len(points) < need or (form == "segment" and len(points) != 4):
        exactly = "exactly" if form == "segment" else "at least"
        raise Rejected(f"this form needs {exactly} {need} points, got {len(points)}")
    if form == "basis":  # the other forms' constructors apply the coincidence rule themselves
        try:
            check_distinct_neighbours(points, "points", closed=closed)
        except ValueError as exc:
            raise Rejected(str(exc).split(";")[0]) from None
    weights = np.asarray(state["interval_weights"], dtype=float)
    if (weights[np.isfinite(weights)] > MAX_WEIGHT).any():  # NaN and inf: the engine names them
        raise Rejected(f"interval weights above {MAX_WEIGHT:g} are out of range")
    for name in ("alpha", "beta"):
        value = state[name]
        if type(value) not in (int, float) or not math.isfinite(value):
            raise Rejected(f"{name} must be a finite number")
        # alpha = 0 drops V from a single segment (§1); elsewhere V, W divide by alpha, beta (§2.1)
        low_ok = value >= 0 if form == "segment" else value > 0
        if not low_ok or value > MAX_CLASS_PARAMETER:
            low = "≥ 0" if form == "segment" else "> 0"
            raise Rejected(f"{name} = {value:g} is out of range ({low} and ≤ {MAX_CLASS_PARAMETER:g})")


def check_state(state: dict, *, max_points: int = MAX_POINTS):
    """Validate a complete state and build its curve (a :class:`~splinecraft.Spline`); :class:`Rejected` if bad."""
    _check_choices(state)
    _check_numbers(state, max_points)
    try:
        spline = build_spline(state)
    except (ValueError, TypeError, ZeroDivisionError, FloatingPointError, np.linalg.LinAlgError) as exc:
        raise Rejected(str(exc)) from None
    # what the page draws, within its reach too: a tiny alpha or beta is a number in range, but its handles (or
    # the class points V, W, Q1, Q2 of the Bézier view, at 3 / alpha times the handle) can reach 1e300
    auxiliary = spline.auxiliary
    try:
        check_reach(spline.bezier().reshape(-1, 2), "Bézier control point")
        for key in ("V", "W", "Q1", "Q2"):
            if key in auxiliary:
                check_reach(np.asarray(auxiliary[key], dtype=float).reshape(-1, 2), f"class point {key}")
    except ValueError as exc:
        raise Rejected(f"{exc}: alpha = {state['alpha']:g}, beta = {state['beta']:g} stretch the curve beyond what "
                       "the page draws") from None
    return spline


# ---------------------------------------------------------------------------------------------- transitions
def resized(values: list, count: int, fill=None) -> list:
    """``values`` cut or padded to ``count`` (padding repeats a common value, else the last one, else ``fill``)."""
    values = list(values)
    if len(values) >= count:
        return values[:count]
    pad = values[-1] if values and fill is None else (fill if fill is not None else 0.0)
    if values and all(v == values[0] for v in values):
        pad = values[0]
    return values + [pad] * (count - len(values))


def segment_points(spline, alpha: float, beta: float) -> list:
    """``F0, V, W, F1`` of the first piece of ``spline`` for class ``alpha, beta`` (the inverse of eq 3.5, §1).

    ``b1 = F0 + alpha/3 (V - F0)`` and ``b2 = F1 + beta/3 (W - F1)``, solved for ``V`` and ``W``.
    """
    bezier = spline.bezier()[0]
    alpha = alpha or 3.0
    beta = beta or 3.0
    V = bezier[0] + 3.0 / alpha * (bezier[1] - bezier[0])
    W = bezier[3] + 3.0 / beta * (bezier[2] - bezier[3])
    return np.vstack([bezier[0], V, W, bezier[3]]).tolist()


def derive(name: str, old, state: dict, *, spline, stash):
    """Adjust the traits that depend on the one that changed (``name``, previously ``old``).

    Returns ``(state, note, stash)``: ``note`` is a status text or None; ``stash`` keeps the points of the
    other forms while the single-segment form is shown (they come back when it is left).
    """
    note = None
    form = state["form"]
    if form not in FORMS:
        raise Rejected(f"unknown form {form!r}; choose one of {', '.join(FORMS)}")
    if name == "preset":
        values = PRESETS.get(state["preset"], (None, None))[1]
        if values is not None:
            state["alpha"], state["beta"] = float(values[0]), float(values[1])
    if name in ("alpha", "beta") and state["preset"] != "free":
        if (state["alpha"], state["beta"]) != tuple(PRESETS[state["preset"]][1]):
            state["preset"] = "free"
    if name == "form":
        if state["end_condition"] not in end_choices(form):
            state["end_condition"] = default_end_condition(form)
        if old in ALPHA_MEANING and ALPHA_MEANING[old][0] != ALPHA_MEANING[form][0]:
            # alpha, beta mean something else in this form: start from its default
            state["preset"], state["alpha"], state["beta"] = ALPHA_MEANING[form][1]
        if form == "segment" and old != "segment":
            stash = copy_state({k: state[k] for k in ("points", "point_tension", "interval_weights", "closed")})
            state["points"] = segment_points(spline, state["alpha"], state["beta"])
            state["closed"] = False
            note = ("Single-segment mode: F₀, V, W, F₁ taken from the first piece. Drag V, W and move α, β — "
                    "here they reshape the curve.")
        elif old == "segment" and form != "segment" and stash is not None:
            state.update(copy_state(stash))
            stash = None
    if name in ("points", "closed", "form"):
        n = len(state["points"])
        state["point_tension"] = resized(state["point_tension"], n)
        state["interval_weights"] = resized(state["interval_weights"], interval_count(n, state["closed"], form),
                                            fill=1.0)
    return state, note, stash


def moved(state: dict, index: int, point) -> dict:
    """``state`` with point ``index`` at ``point``."""
    new = copy_state(state)
    new["points"][index] = [float(point[0]), float(point[1])]
    return new


def inserted(state: dict, index: int, interval: int, point) -> dict:
    """``state`` with ``point`` inserted before ``index``; interval ``interval`` is split (both halves keep its weight)."""
    new = copy_state(state)
    n = len(new["points"])
    new["points"].insert(index, [float(point[0]), float(point[1])])
    tension = new["point_tension"]
    tension.insert(index, tension[min(index, n - 1)] if tension else 0.0)
    weights = new["interval_weights"]
    if weights:
        weights.insert(min(interval, len(weights)), weights[min(interval, len(weights) - 1)])
    return new


def deleted(state: dict, index: int) -> dict:
    """``state`` without point ``index`` (and without one interval weight next to it)."""
    new = copy_state(state)
    del new["points"][index]
    del new["point_tension"][index]
    weights = new["interval_weights"]
    if weights:
        del weights[min(index, len(weights) - 1) if not new["closed"] else index % len(weights)]
    return new


def insertion_place(state: dict, spline, point, tolerance: float):
    """Where a new point goes: ``(index, interval)``.

    Within ``3 tolerance`` of the curve (and always on a closed curve) it goes into the leg of the nearest
    piece (:meth:`~splinecraft.Spline.nearest`, :meth:`~splinecraft.Spline.piece_leg`); elsewhere an open
    curve grows at its nearer end.
    """
    near = spline.nearest(point)
    points = np.asarray(state["points"], dtype=float)
    n = len(points)
    if near.distance <= 3.0 * tolerance or state["closed"]:
        leg = spline.piece_leg(near.piece)
        return leg + 1, leg
    to_first = math.dist(points[0], point)
    to_last = math.dist(points[-1], point)
    return (0, 0) if to_first < to_last else (n, n - 2)


def describe_change(name: str, state: dict, before, after, *, selected: int, selected_interval: int) -> str:
    """Status text after trait ``name`` changed the curve from ``before`` to ``after``."""
    form = state["form"]
    if name in ("preset", "alpha", "beta") and form in ("interpolant", "basis") and before is not None:
        a, b = before.bezier(), after.bezier()
        moved_by = float(np.max(np.abs(a - b))) if a.shape == b.shape else float("nan")
        label = (f"{PRESETS[state['preset']][0].split(' (')[0]} (α = β = {state['alpha']:g})"
                 if state["preset"] != "free" else f"α = {state['alpha']:g}, β = {state['beta']:g}")
        return (f"Class {label}: V, W redrawn; the curve did not move (max change {moved_by:.2g}) — "
                "α, β cancel in this form (E1).")
    if name in ("preset", "alpha", "beta") and form == "segment":
        return f"α = {state['alpha']:g}, β = {state['beta']:g}: with V, W fixed the segment changes shape (§1)."
    if name == "form":
        return f"Form: {FORMS[form]['label']}."
    values = state.get(name)
    if name in ("interval_weights", "point_tension") and values:
        symbol, where, index = (("ω", "interval", selected_interval) if name == "interval_weights"
                                else ("v", "point", selected))
        if len(values) > 1 and all(value == values[0] for value in values):
            text = f"{symbol} = {values[0]:g} at every {where}."
        elif 0 <= index < len(values):
            text = f"{symbol}[{index}] = {values[index]:g}."
        else:
            text = f"{symbol} updated ({len(values)} values)."
        return text + (" Unequal neighbouring ω make curvature jump (E2)." if name == "interval_weights" else "")
    return f"{name.replace('_', ' ')} updated."
