# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#       jupytext_version: 1.19.6
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 02 · Point tension and interval tension
#
# **What you should see.** Raising the point tension v pulls the interpolating spline towards its data
# polygon (the thesis says positive v has no effect — erratum **E22**), large interval weights ω straighten
# their intervals, and negative v first bulges the curve and then, below −6(c₍ₖ₋₁₎ + cₖ), reverses the
# tangents so the curve loops (thesis Figs 3.4–3.11), with a band in between where the system is singular
# (**E8**). With curvature combs and the κ(t) plot you will also see that a joint is only G² where the
# neighbouring interval weights are equal (**E2**): the curvature jumps by the ratio ω₍ᵢ₋₁₎/ωᵢ.
#
# thesis sections 3.1, 3.4 (eqs 3.1–3.4, 3.13–3.14); §2.2–2.5, §7.

# %%
import warnings

import numpy as np
from IPython.display import display

import splinecraft as sc
from splinecraft.capture.fitting import polyline_distance

# %% [markdown]
# ## 1. The joint condition and the tangent system
#
# At every interior knot the interpolant is C¹ and satisfies **ωᵢ P″(tᵢ⁺) = vᵢ P′(tᵢ) + ωᵢ₋₁ P″(tᵢ⁻)**
# (eq 3.13). This is the stationarity condition of the energy
# E = Σ ωᵢ ∫ ‖P″‖² dt + Σ vᵢ ‖Mᵢ‖²: **vᵢ penalises the speed at the point, ωᵢ the bending of interval i**.
# The tangents Mₖ solve one tridiagonal system (§2.3; E3 corrects a factor 2 in eq 3.25):
#
# $$c_{k-1}M_{k-1}+\big(\tfrac12v_k+2c_{k-1}+2c_k\big)M_k+c_kM_{k+1}=3(c_{k-1}\Delta_{k-1}+c_k\Delta_k),\qquad c_i=\omega_i/h_i.$$
#
# The thesis's figures use uniform knots, h = ω = 1, so cₖ₋₁ + cₖ = 2: row k is safe for v > −4, singular
# somewhere in [−12, −4], and *reversed* below −12. We use the same setting (`knots="uniform"`) on a closed
# heart.

# %%
heart = sc.datasets.sample_points("heart")
chord_average = np.roll(heart, -1, axis=0) - np.roll(heart, 1, axis=0)   # F_{k+1} - F_{k-1}


def heart_curve(v=0.0, w=1.0, **options):
    return sc.interpolate(heart, closed=True, knots="uniform", point_tension=v, interval_weights=w, **options)


def deviation(spline, polygon=heart, closed=True):
    """Largest distance of the curve from the data polygon (px)."""
    _, samples = spline.sample(samples_per_segment=48)
    return float(polyline_distance(samples, polygon, closed=closed, neighbours=len(polygon)).max())


def reversed_tangents(spline):
    """Indices k whose tangent M_k points against the chord average F_{k+1} - F_{k-1}."""
    tangents = spline.auxiliary["tangents"][: len(heart)]
    return np.flatnonzero((tangents * chord_average).sum(axis=1) < 0)


figures = [("Fig 3.4: ω = 1, v = 0", 0.0, 1.0), ("Fig 3.5: v = 10", 10.0, 1.0), ("Fig 3.6: v = 50", 50.0, 1.0),
           ("Fig 3.7: ω = 100, v = 0", 0.0, 100.0), ("Fig 3.8: v = −3", -3.0, 1.0),
           ("Fig 3.9: v = −15", -15.0, 1.0), ("Fig 3.10: v = −25", -25.0, 1.0), ("Fig 3.11: v = −50", -50.0, 1.0)]
curves = {title: heart_curve(v, w) for title, v, w in figures}
display(sc.plot.grid(*[sc.plot.spline_figure(spline, data_points=heart, polygon=heart, title=title, width=290,
                                             height=260) for title, spline in curves.items()], columns=4))
sc.plot.table(["figure", "max distance from the polygon (px)", "reversed tangents (of 12)"],
              [[title, deviation(spline), len(reversed_tangents(spline))] for title, spline in curves.items()])

# %% [markdown]
# What the table says:
#
# * **Positive v tightens (E22).** v = 10 and v = 50 bring the curve much closer to the polygon; as v → ∞ the
#   tangents go to zero and the curve *becomes* the polygon (with cusps at the points). The thesis's remark
#   that "positive increase … does not produce any effect" is wrong; its Figs 3.5–3.6 just used a scale where
#   the effect was small.
# * **A global ω changes nothing when v = 0 (Fig 3.7).** Multiplying every ωᵢ by 100 multiplies every row of
#   the system by 100: the tangents and the curve are identical to Fig 3.4. Only *relative* weights act.
# * **Negative v.** v = −3 is in the safe range (the solution is still the unique energy minimiser) and makes
#   the curve rounder and bulgier; at the heart's two sharp points (top notch and tip), where the chords
#   nearly cancel, the bulge already turns the tangent against them. v = −15, −25, −50 are below −12: the
#   system is uniquely solvable but every tangent is reversed against the chords, so the curve loops at each
#   point; as v → −∞ the loops shrink and the curve tends back to the polygon — exactly the sequence of thesis
#   Figs 3.8–3.11, which the thesis misreads as "bulging inside".
#
# ### The singular band (E8)
# Between −12 and −4 (here) the rows lose diagonal dominance and the system can be singular; the thesis claims
# the matrix is always diagonally dominant. The engine refuses such values with a clear message:

# %%
band_errors = {}
for v in (-4.5, -8.0, -11.0):
    try:
        heart_curve(v)
        band_errors[v] = None
    except ValueError as error:
        band_errors[v] = str(error)
        print(f"v = {v}: ValueError: {error}")

# %% [markdown]
# ## 2. How much does v tighten? A sweep, and the scale-free ν
#
# The raw v has the units of c = ω/h. The *relative* tension ν with vₖ = νₖ (cₖ₋₁ + cₖ) acts the same at every
# scale and knot spacing (§2.5, `point_tension_scale="relative"`; the widget's default). With chord-length
# knots (the default for drawing):

# %%
def relative(nu):
    return sc.interpolate(heart, closed=True, point_tension=nu, point_tension_scale="relative")


nus = [0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 50.0]
sweep = [deviation(relative(nu)) for nu in nus]
display(sc.plot.table(["ν (relative point tension)"] + [f"{nu:g}" for nu in nus],
                      [["max distance from polygon (px)"] + sweep]))
sc.plot.figure(sc.plot.polygon(heart, closed=True),
               [sc.plot.curve(relative(nu), color, label=f"ν = {nu:g}")
                for nu, color in zip((0.0, 2.0, 10.0, 50.0), sc.plot.PALETTE)],
               title="Chord knots, ν = 0, 2, 10, 50", width=480, height=360)

# %% [markdown]
# ## 3. Interval tension on one interval, and the curvature jump (E2)
#
# Give one interval a large weight ω: it straightens towards its chord, its neighbours adjust. The joint
# condition then says κ(tᵢ⁺) = (ωᵢ₋₁/ωᵢ) κ(tᵢ⁻): **the curvature jumps** at both ends of the heavy interval.
# The thesis calls these joints GC² unconditionally; they are G² only where ωᵢ₋₁ = ωᵢ. The curvature comb
# (teeth ∝ κ, drawn outside) shows the jump as a step, the κ(t) plot below as a red bar.

# %%
heavy = 2                                              # interval F_2 -> F_3
weights = {w: np.where(np.arange(len(heart)) == heavy, w, 1.0) for w in (1.0, 10.0, 100.0)}
local = {w: heart_curve(0.0, weights[w]) for w in weights}
rows = []
for w, spline in local.items():
    piece = sc.Spline(spline.bezier()[heavy:heavy + 1], spline.knots[heavy:heavy + 2])
    kappa = spline.joint_curvature()                   # columns: κ(tᵢ⁻), κ(tᵢ⁺)
    rows.append([f"ω₂ = {w:g}", deviation(piece, heart[[heavy, heavy + 1]], closed=False),
                 kappa[heavy, 1] / kappa[heavy, 0], 1.0 / w, kappa[heavy + 1, 1] / kappa[heavy + 1, 0], w])
display(sc.plot.grid(*[sc.plot.figure(sc.plot.polygon(heart, closed=True), sc.plot.comb(spline),
                                      sc.plot.curve(spline), sc.plot.points(heart[[heavy, heavy + 1]], "#c62828", 40),
                                      title=f"ω₂ = {w:g} on interval 2 (red ends)") for w, spline in local.items()]))
display(sc.plot.table(["weights", "sag of interval 2 from its chord", "κ⁺/κ⁻ at F₂", "ω₁/ω₂", "κ⁺/κ⁻ at F₃",
                       "ω₂/ω₃"], rows))
profile = sc.plot.curvature_profile(local[10.0])
sc.plot.curvature_figure(local[10.0], width=760)

# %% [markdown]
# In the κ(t) plot of the ω₂ = 10 heart, exactly two joints jump: F₂ and F₃, the two ends of the heavy
# interval. Everywhere else the one-sided values agree (grey dots).
#
# ## 4. Try it yourself
#
# The editor below starts in the thesis's setting (uniform knots, raw v) with the curvature comb on. Select a
# point and move its **v** slider, or an interval and its **ω** slider; watch the comb step at the joints of an
# interval whose ω differs from its neighbours'.

# %%
editor = sc.SplineEditor(heart, closed=True, knots="uniform", tension_scale="absolute", show_comb=True)
editor.panel()

# %%
loose = deviation(editor.spline)
editor.point_tension = [10.0] * len(heart)          # what moving the global v slider to 10 does
tight = deviation(editor.spline)
print(f"v = 0: {loose:.1f} px from the polygon;  v = 10: {tight:.1f} px")

# %% [markdown]
# Values in the singular band are refused: the editor keeps the last good curve and says why in its status
# line, in red. Here is a second editor of its own, given v = −8 at every point from code (the editor above
# stays as you left it):

# %%
refusing = sc.SplineEditor(heart, closed=True, knots="uniform", tension_scale="absolute")
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    refusing.point_tension = [-8.0] * len(heart)    # in the singular band: refused
print("the editor says:", refusing.status_message)
refusing

# %% [markdown]
# ## Check

# %%
dev = {title: deviation(spline) for title, spline in curves.items()}
assert dev["Fig 3.5: v = 10"] < dev["Fig 3.4: ω = 1, v = 0"] / 2            # E22: v > 0 tightens
assert dev["Fig 3.6: v = 50"] < dev["Fig 3.5: v = 10"]
assert np.allclose(curves["Fig 3.7: ω = 100, v = 0"].bezier(), curves["Fig 3.4: ω = 1, v = 0"].bezier())
assert len(reversed_tangents(curves["Fig 3.4: ω = 1, v = 0"])) == 0
sharp_points = set(np.argsort(np.linalg.norm(chord_average, axis=1))[:2].tolist())   # notch and tip
assert set(reversed_tangents(curves["Fig 3.8: v = −3"]).tolist()) == sharp_points     # only there, at v = −3
assert dev["Fig 3.8: v = −3"] > dev["Fig 3.4: ω = 1, v = 0"]             # ... and it bulges
for title in ("Fig 3.9: v = −15", "Fig 3.10: v = −25", "Fig 3.11: v = −50"):
    assert len(reversed_tangents(curves[title])) == len(heart), title       # all tangents reversed
assert dev["Fig 3.11: v = −50"] < dev["Fig 3.10: v = −25"] < dev["Fig 3.9: v = −15"]   # v → −∞: the polygon
assert all(message is not None for message in band_errors.values())       # E8: singular band refused
assert all(np.diff(sweep) < 0)                                            # monotone tightening in ν
assert sweep[-1] < sweep[0] / 10
sags = [row[1] for row in rows]
assert sags[2] < sags[1] < sags[0]                                        # heavy interval straightens
for _, _, ratio_in, expected_in, ratio_out, expected_out in rows:          # E2: κ⁺/κ⁻ = ω_{i−1}/ω_i
    assert np.isclose(ratio_in, expected_in, rtol=1e-6) and np.isclose(ratio_out, expected_out, rtol=1e-6)
assert profile["joints"][profile["jumps"]].tolist() == [heavy, heavy + 1]  # κ(t): jumps only at F₂, F₃
assert tight < loose / 2
assert editor.status_level != "error" and editor.point_tension == [10.0] * len(heart)   # main editor: fine
assert refusing.status_level == "error" and "singular" in refusing.status_message      # bad value refused,
assert refusing.point_tension == [0.0] * len(heart) and caught                       # last good state kept
print("all checks passed")
