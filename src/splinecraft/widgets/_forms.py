"""What each curve form of the SplineEditor takes, and how to build it with the engine.

One table (:data:`FORMS`) says, per form, which controls apply (tension, knots, class parameters,
end condition, open/closed), their slider ranges and the teaching text; :func:`build_spline` turns an
editor state into a :class:`~splinecraft.spline.piecewise.Spline` by calling the engine. Nothing here
imports a widget library, so the kernel-side logic is testable without Jupyter.
"""
from __future__ import annotations

import html
import re

import numpy as np

from ..spline import CLASS_PRESETS, basis_spline, generic_segment, interpolate, timmer_g2, timmer_gc1, timmer_gc2

__all__ = ["FORMS", "PRESETS", "KNOT_CHOICES", "build_spline", "form_options", "explanation", "plain_text"]

#: Class presets of the generic cubic (§1): name -> (label, (alpha, beta) or None for free).
PRESETS = {
    "ball": ("Ball (2)", CLASS_PRESETS["ball"]),
    "bezier": ("Bézier (3)", CLASS_PRESETS["bezier"]),
    "timmer": ("Timmer (4)", CLASS_PRESETS["timmer"]),
    "free": ("free α, β", None),
}

#: Knot parameterizations (§3).
KNOT_CHOICES = (("chord", "chord"), ("centripetal", "centripetal"), ("uniform", "uniform"))

_TENSION_RANGES = {
    # dimensionless nu_k with v_k = nu_k (c_{k-1} + c_k) (§2.5 Units): safe iff nu > -2
    "relative": (-12.0, 30.0, 0.1),
    # the thesis's raw v (its figures use uniform knots, h = omega = 1)
    "absolute": (-60.0, 60.0, 0.5),
}

FORMS = {
    "interpolant": {
        "label": "Interpolant (§2)",
        "tension": True, "knots": True, "closed": True, "vw": True, "alpha": True,
        "alpha_label": "α", "beta_label": "β",
        "alpha_range": (0.25, 6.0, 0.05),
        "ends": ("ends", (("natural", "natural"), ("natural_v", "free end, v (3.3)"),
                          ("clamped", "clamped"))),
        "min_points": (2, 3),
        "add_delete": True,
    },
    "basis": {
        "label": "Basis form (§4)",
        "tension": True, "knots": True, "closed": True, "vw": True, "alpha": True,
        "alpha_label": "α", "beta_label": "β",
        "alpha_range": (0.25, 6.0, 0.05),
        "ends": ("ends", (("floating", "floating"), ("clamped", "clamped"))),
        "min_points": (4, 3),
        "add_delete": True,
    },
    "timmer_g2": {
        "label": "Timmer G² (Alg 3.1)",
        "tension": False, "knots": False, "closed": True, "vw": True, "alpha": True,
        "alpha_label": "α₀ scale", "beta_label": None,
        "alpha_title": "α₀ relative to α_ref = 4/|P₁ − P₀| (1: handles a third of the first chord)",
        "alpha_range": (0.1, 5.0, 0.01),
        "ends": None,
        "min_points": (2, 3),
        "add_delete": True,
    },
    "timmer_gc1": {
        "label": "Timmer GC¹ (Alg 3.2)",
        "tension": False, "knots": False, "closed": True, "vw": True, "alpha": True,
        "alpha_label": "α scale", "beta_label": "β scale",
        "alpha_title": "αᵢ relative to 4/|Pᵢ₊₁ − Pᵢ| (1: handles a third of the chord)",
        "alpha_range": (0.1, 5.0, 0.01),
        "ends": None,
        "min_points": (2, 3),
        "add_delete": True,
    },
    "timmer_gc2": {
        "label": "Timmer GC² (Alg 3.3)",
        "tension": False, "knots": False, "closed": True, "vw": True, "alpha": True,
        "alpha_label": "α", "beta_label": "β",
        "alpha_range": (0.5, 16.0, 0.05),
        "ends": ("joint", (("thesis", "thesis (3.123)"), ("g2", "true G²"))),
        "min_points": (2, 3),
        "add_delete": True,
    },
    "segment": {
        "label": "One segment F, V, W (§1)",
        "tension": False, "knots": False, "closed": False, "vw": False, "alpha": True,
        "alpha_label": "α", "beta_label": "β",
        "alpha_range": (0.0, 6.0, 0.05),
        "ends": None,
        "min_points": (4, 4),
        "add_delete": False,
    },
}

SEGMENT_LABELS = ("F₀", "V", "W", "F₁")

#: What alpha, beta mean per form (§1 class parameters, §5.4/5.5 relative tangent scales, §5.6 tangent
#: scales), and the (preset, alpha, beta) a form starts from when the meaning changes.
ALPHA_MEANING = {
    "interpolant": ("class", ("ball", 2.0, 2.0)),
    "basis": ("class", ("ball", 2.0, 2.0)),
    "segment": ("class", ("ball", 2.0, 2.0)),
    "timmer_g2": ("relative", ("free", 1.0, 1.0)),
    "timmer_gc1": ("relative", ("free", 1.0, 1.0)),
    "timmer_gc2": ("tangent_scale", ("timmer", 4.0, 4.0)),
}


def default_end_condition(form: str) -> str:
    ends = FORMS[form]["ends"]
    return ends[1][0][0] if ends else "natural"


def end_choices(form: str) -> tuple:
    ends = FORMS[form]["ends"]
    return tuple(value for value, _label in ends[1]) if ends else ("natural",)


def form_options(tension_scale: str) -> dict:
    """The static description of the controls sent to the page (``SplineEditor.options``)."""
    tension_range = _TENSION_RANGES[tension_scale]
    return {
        "forms": [[name, spec["label"]] for name, spec in FORMS.items()],
        "presets": [[name, label] for name, (label, _values) in PRESETS.items()],
        "knots": [list(choice) for choice in KNOT_CHOICES],
        "end_conditions": {
            name: ([list(choice) for choice in spec["ends"][1]] if spec["ends"] else [])
            for name, spec in FORMS.items()
        },
        "end_labels": {name: (spec["ends"][0] if spec["ends"] else "") for name, spec in FORMS.items()},
        "uses": {
            name: {
                "tension": spec["tension"], "knots": spec["knots"], "closed": spec["closed"], "vw": spec["vw"],
                "alpha": spec["alpha"], "alpha_label": spec["alpha_label"], "beta_label": spec["beta_label"],
                "alpha_title": spec.get("alpha_title", "Class parameter α (§1)"),
                "add_delete": spec["add_delete"], "alpha_range": list(spec["alpha_range"]),
                "vw_label": "Timmer points Q₁, Q₂" if name.startswith("timmer") else "class points V, W",
                # Ball/Bézier/Timmer presets are class parameters (§1); in Alg 3.1/3.2 the sliders are relative
                # tangent scales, so the presets would mean nothing there
                "preset": name not in ("timmer_g2", "timmer_gc1"),
            }
            for name, spec in FORMS.items()
        },
        "ranges": {
            "point_tension": list(tension_range),
            "interval_weights": [0.05, 20.0, 0.01],
            "alpha": [0.25, 6.0, 0.05],
            "beta": [0.25, 6.0, 0.05],
            "comb_scale": [0.1, 10.0, 0.01],
        },
    }


def build_spline(state: dict):
    """Build the curve of an editor ``state`` with the engine; raises ``ValueError``/``TypeError`` when bad.

    ``state`` keys: ``form, points, closed, point_tension, interval_weights, alpha, beta, end_condition,
    knots, tension_scale``. The class parameters ``alpha``/``beta`` mean (per form):
    interpolant/basis: the class of the auxiliary polygon V, W only (the curve does not depend on them,
    spec E1); timmer_g2: alpha_0 / alpha_ref,0; timmer_gc1: the tangent scales relative to 4/chord
    (§5.5: alpha_i = a * 4 / |P_{i+1} - P_i|); timmer_gc2: the tangent scales themselves (§5.6);
    segment: the class parameters of the one generic segment F0, V, W, F1 (§1), which do reshape it.
    """
    form = state["form"]
    points = np.asarray(state["points"], dtype=float)
    closed = bool(state["closed"]) and FORMS[form]["closed"]
    alpha, beta = float(state["alpha"]), float(state["beta"])
    if form == "interpolant":
        return interpolate(
            points, closed=closed, point_tension=state["point_tension"], interval_weights=state["interval_weights"],
            alpha=alpha, beta=beta, end_condition="periodic" if closed else state["end_condition"],
            knots=state["knots"], point_tension_scale=state["tension_scale"],
        )
    if form == "basis":
        return basis_spline(
            points, closed=closed, point_tension=state["point_tension"], interval_weights=state["interval_weights"],
            alpha=alpha, beta=beta, knots=state["knots"], ends=state["end_condition"],
            point_tension_scale=state["tension_scale"],
        )
    if form == "timmer_g2":
        first = points[1] - points[0]
        alpha_ref = 4.0 / float(np.hypot(*first)) if np.hypot(*first) > 0 else None
        return timmer_g2(points, closed=closed, alpha0=None if alpha_ref is None else alpha * alpha_ref)
    if form == "timmer_gc1":
        chords = np.linalg.norm(np.diff(np.vstack([points, points[:1]]) if closed else points, axis=0), axis=1)
        if not (chords > 0).all():
            i = int(np.flatnonzero(~(chords > 0))[0])
            raise ValueError(f"points[{i}] and points[{(i + 1) % len(points)}] coincide")
        return timmer_gc1(points, closed=closed, alpha=alpha * 4.0 / chords, beta=beta * 4.0 / chords)
    if form == "timmer_gc2":
        return timmer_gc2(points, closed=closed, alpha=alpha, beta=beta, joint=state["end_condition"])
    if form == "segment":
        if points.shape != (4, 2):
            raise ValueError(f"the single-segment mode takes exactly 4 points F0, V, W, F1, got {len(points)}")
        return generic_segment(points[0], points[1], points[2], points[3], alpha, beta)
    raise ValueError(f"unknown form {form!r}; choose one of {', '.join(FORMS)}")


def plain_text(markup: str) -> str:
    """The text of the small HTML of :func:`explanation`: paragraphs on their own lines, sub/superscripts inline."""
    text = re.sub(r"</p>\s*", "\n\n", markup)
    text = re.sub(r"<[^>]+>", "", text)
    return html.unescape(text).strip()


def explanation(form: str, preset: str, tension_scale: str) -> str:
    """Teaching text (HTML) shown beside the drawing: what the controls of this form really do."""
    values = PRESETS.get(preset, (preset, None))[1]
    preset_label = (f"{PRESETS[preset][0].split(' (')[0]}, α = β = {values[0]:g}" if values
                    else "free α, β")
    tension_unit = (
        "dimensionless ν with v<sub>k</sub> = ν(c<sub>k−1</sub>+c<sub>k</sub>), safe for ν &gt; −2 (§2.5)"
        if tension_scale == "relative" else "the thesis's raw v (its figures use uniform knots, h = ω = 1)"
    )
    if form == "interpolant":
        return (
            "<p><b>Interpolant</b>: the C¹ weighted ν-spline through the points (§2). "
            f"Tension v is {tension_unit}: v &gt; 0 pulls the curve towards the polygon (E22); "
            "strongly negative v reverses the tangents and makes loops (thesis Figs 3.8–3.11). "
            "A larger interval weight ω stiffens that interval.</p>"
            f"<p><b>The class ({preset_label}) does not change this curve</b> (E1): α, β cancel; "
            "they only place the auxiliary points V, W. Switch the class and watch V, W move while the curve stays.</p>"
            "<p>Joints are G² only where neighbouring ω are equal: κ⁺/κ⁻ = ω<sub>i−1</sub>/ω<sub>i</sub> (E2). "
            "Select an interval, change its ω and switch on the comb to see the jump.</p>"
        )
    if form == "basis":
        return (
            "<p><b>Local-support basis form</b> (§4): the curve is Σ B<sub>j</sub>(t) P<sub>j</sub>; each B<sub>j</sub> "
            "lives on four intervals and they sum to 1 (see the basis plot). Moving one control point changes "
            "only the nearby pieces.</p>"
            f"<p>Tension v is {tension_unit}; v → ∞ pulls the curve onto P<sub>i</sub> (a cusp), ω → ∞ "
            "straightens an interval along its leg.</p>"
            f"<p><b>The class ({preset_label}) does not change this curve</b> either (E1): only V, W move. "
            "Unequal neighbouring ω make curvature jump at the joint (E2, the comb shows it).</p>"
        )
    if form == "timmer_g2":
        return (
            "<p><b>Timmer G², Algorithm 3.1</b> (§5.4): unit tangents from eqs 3.106–3.109; one tangent scale "
            "α<sub>i</sub> = β<sub>i</sub> per piece is solved joint by joint so the curvature is continuous. "
            "Where the joint quadratic has no positive root the joint is only G¹ (labelled on the comb).</p>"
            "<p>The slider sets α₀ relative to α<sub>ref</sub> = 4/|P₁ − P₀|; every later α follows from it.</p>"
        )
    if form == "timmer_gc1":
        return (
            "<p><b>Timmer GC¹, Algorithm 3.2</b> (§5.5): unit tangents and your tangent scales. The sliders set "
            "α<sub>i</sub>, β<sub>i</sub> relative to 4/|P<sub>i+1</sub> − P<sub>i</sub>| (1: handles a third of "
            "the chord). The curve is G¹; curvature jumps at the joints (comb).</p>"
            "<p>Here α, β <b>do</b> change the curve: in thesis section 3.3 they are tangent scales, not the class parameter of §1.</p>"
        )
    if form == "timmer_gc2":
        return (
            "<p><b>Timmer “GC²”, Algorithm 3.3</b> (§5.6): the tangents solve one tridiagonal system. With the "
            "thesis joint the curve is C² only where α<sub>i</sub> = β<sub>i−1</sub>; otherwise "
            "κ⁺/κ⁻ = (α<sub>i</sub>/β<sub>i−1</sub>)² (E20). Set α ≠ β and the comb shows the jumps; "
            "the “true G²” joint removes them.</p>"
        )
    if form == "segment":
        return (
            "<p><b>One generic segment</b> (§1, eq 3.5): drag F₀, V, W, F₁. Here V and W are held fixed, so "
            "α and β <b>really reshape the curve</b>: b₁ = F₀ + α/3 (V − F₀), b₂ = F₁ + β/3 (W − F₁). "
            f"Class now: {preset_label}.</p>"
            "<p>Compare the interpolant, where V, W are derived from the curve and α, β cancel (E1).</p>"
        )
    return ""
