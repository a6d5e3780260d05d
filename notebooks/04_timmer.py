# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#       jupytext_version: 1.19.7
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 04 · Timmer curves: G² by iteration, GC¹ and GC² with shape control
#
# **What you should see.** Algorithm 3.1 chooses one α per piece so that the curvature is continuous — but at
# some joints the quadratic for α has no positive root, and those joints stay G¹ (the engine flags them and
# reports the jump); Algorithm 3.2 keeps unit tangents and lets α, β shape each piece (Figs 3.39–3.45: small α
# loops, large α hugs the polygon). Algorithm 3.3 solves one banded system and is C² only where αᵢ = βᵢ₋₁
# (erratum **E20**: elsewhere κ jumps by (αᵢ/βᵢ₋₁)²), while the corrected true-G² joint keeps the curvature
# continuous for any α, β.
#
# thesis section 3.3 (eqs 3.85–3.133, Algorithms 3.1–3.3); §5, §6 (errata E13–E20).

# %%
import numpy as np
from IPython.display import display

import splinecraft as sc
from splinecraft.capture.fitting import polyline_distance

# %% [markdown]
# ## 1. Timmer's blending functions (Figs 3.1–3.3)
#
# f₀ = (1−2θ)(1−θ)², f₁ = 4θ(1−θ)², f₂ = 4θ²(1−θ), f₃ = (2θ−1)θ² (eqs 3.85–3.88; E13: the last is f₃). They sum to 1,
# but f₀ and f₃ are negative on part of [0, 1]: no convex-hull property.

# %%
from splinecraft.spline.timmer import timmer_blending_functions

theta = np.linspace(0.0, 1.0, 301)
f = timmer_blending_functions(theta)
display(sc.plot.basis_figure(theta, f, labels=["f₀", "f₁", "f₂", "f₃"], title="Timmer blending functions",
                             xlabel="θ", y_range=(-0.1, 1.05), width=460))
print(f"min f0 = {f[:, 0].min():.5f} at θ = {theta[f[:, 0].argmin()]:.3f}   (−1/27 = {-1/27:.5f} at 2/3)")

# %% [markdown]
# ## 2. Algorithm 3.1: G² joint by joint
#
# Unit tangents from eqs 3.106–3.109, α₀ = 4/‖P₁ − P₀‖, then at each joint the α of the next piece solves
# ⅜Sα² − ½Cα − K* = 0 so that its start curvature matches the previous piece's end curvature (E18 fixes the sign
# under the root). When there is **no positive root** the engine takes the best α (the vertex of the parabola),
# marks the joint `g1_no_root` and reports the curvature jump — the thesis does not mention this case, which is
# common. On 14 points of an ellipse (closed: the last joint, back at P₀, depends on α₀ alone; the engine
# searches α₀ for it and reports `g1_closing` when no α₀ closes it G²):

# %%
angles = np.linspace(0.0, 2 * np.pi, 14, endpoint=False) + 0.1
ellipse = np.c_[310 + 230 * np.cos(angles), 220 + 120 * np.sin(angles)]
g2 = sc.timmer_g2(ellipse, closed=True)
status = g2.info["joint_status"][: len(ellipse)]
jumps = np.array([np.nan if j is None else j for j in g2.info["curvature_jump"][: len(ellipse)]], float)
kappa = g2.joint_curvature()[: len(ellipse)]
no_root = [i for i, s in enumerate(status) if s != "g2"]
display(sc.plot.table(["joint", "status", "κ⁻", "κ⁺", "jump"],
                      [[i, status[i], kappa[i, 0], kappa[i, 1], jumps[i]] for i in range(len(ellipse))]))
display(sc.plot.figure(sc.plot.comb(g2), sc.plot.curve(g2), sc.plot.points(ellipse, label="G² joint"),
                       sc.plot.points(ellipse[no_root], "#c62828", 60, label="only G¹"),
                       title=f"Alg 3.1 on an ellipse: {len(no_root)} of {len(ellipse)} joints only G¹",
                       width=620, height=360))
g2_profile = sc.plot.curvature_profile(g2)
sc.plot.curvature_figure(g2, width=760)

# %% [markdown]
# The κ(t) plot marks the same joints in red: a bar from κ(tᵢ⁻) to κ(tᵢ⁺) wherever no root was found (the closing
# joint, back at P₀, is the last knot). Here the jumps are tiny (the table above: 10⁻⁵ to 10⁻⁴), so the bars
# are dots at t = 3, 10 and 14; on noisier points they grow.
#
# ## 3. Algorithm 3.2: GC¹ with shape control (Figs 3.39–3.45)
#
# Unit tangents, and per piece the tangent scales α, β: the Timmer polygon points are Q₁ = Pᵢ + Tᵢ/αᵢ and
# Q₂ = Pᵢ₊₁ − Tᵢ₊₁/βᵢ, so the end speed is 4/α. The thesis's values α = 1 … 20 refer to coordinates of a few units;
# we scale the heart to that size. Fig 3.44 raises α = β to 15 on the base pieces only. Below α = 1 the
# pieces overshoot and the curve loops (it crosses itself).

# %%
heart = sc.datasets.sample_points("heart") / 40.0             # a few units across, like the thesis
base = [5, 6]                                                # the two pieces around the heart's tip


def deviation(spline):
    """Largest distance of the curve from the closed heart polygon."""
    _, samples = spline.sample(samples_per_segment=48)
    return float(polyline_distance(samples, heart, closed=True, neighbours=len(heart)).max())


def crossings(spline):
    """How often the sampled curve crosses itself (pairs of polyline edges that intersect)."""
    xy = spline.sample(samples_per_segment=48)[1]
    start, step = xy[:-1], np.diff(xy, axis=0)
    cross = lambda u, v: u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]      # noqa: E731
    offset = start[None] - start[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        along, other = cross(offset, step[None]) / cross(step[:, None], step[None]), \
            cross(offset, step[:, None]) / cross(step[:, None], step[None])
    return int(np.triu((along > 0) & (along < 1) & (other > 0) & (other < 1), 2).sum())


gc1_figures = {f"α = β = {a:g}": sc.timmer_gc1(heart, closed=True, alpha=a) for a in (0.5, 1.0, 2.0, 4.0, 20.0)}
local_alpha = np.where(np.isin(np.arange(len(heart)), base), 15.0, 1.0)
gc1_figures["Fig 3.44: α = β = 15 on the base"] = sc.timmer_gc1(heart, closed=True, alpha=local_alpha)
display(sc.plot.grid(*[sc.plot.spline_figure(spline, data_points=heart, polygon=heart, title=title, width=300,
                                             height=280) for title, spline in gc1_figures.items()]))
sc.plot.table(["figure", "max distance from the polygon", "self-crossings", "joint statuses"],
              [[title, deviation(s), crossings(s), ", ".join(sorted(set(s.info["joint_status"])))]
               for title, s in gc1_figures.items()])

# %% [markdown]
# With α = β everywhere the joints are C¹ (`c1`); where the scales differ (Fig 3.44) the tangent *direction* is
# still continuous but the speed is not (`g1`). **Negative α (Fig 3.45, α = β = −10).** The engine requires α, β > 0
# (§5.5). A negative α is the same as a positive one with reversed tangents, Q₁ = Pᵢ + (−Tᵢ)/|α|, which is what
# the thesis's loops show (Fig 3.45 with α = −10: small loops at every point; at α = −2 they are large):

# %%
try:
    sc.timmer_gc1(heart, closed=True, alpha=-10.0)
    negative_refused = False
except ValueError as error:
    negative_refused = True
    print("ValueError:", error)
unit = sc.estimate_tangents(heart, closed=True)
unit /= np.linalg.norm(unit, axis=1, keepdims=True)
reversed_curves = {a: sc.timmer_gc1(heart, closed=True, alpha=a, tangents=-unit) for a in (10.0, 2.0)}
loop_size = {a: deviation(s) for a, s in reversed_curves.items()}
print("largest distance from the polygon (size of the loops):", {f"α = −{a:g}": round(d, 3) for a, d in loop_size.items()})
sc.plot.grid(*[sc.plot.spline_figure(s, data_points=heart, polygon=heart, width=400, height=340,
                                     title=f"α = β = −{a:g} ≡ α = {a:g}, tangents reversed")
               for a, s in reversed_curves.items()], columns=2)

# %% [markdown]
# ## 4. Algorithm 3.3: one banded system — "GC²" and the true G² joint
#
# The tangents Tᵢ now solve one tridiagonal system (eqs 3.126–3.130). With all α = β equal the result is the
# uniform-knot C² cubic spline (compare with `scipy.interpolate.CubicSpline`). With different α, β the thesis joint
# H″ᵢ₋₁(1) = H″ᵢ(0) is not G²: the curvature jumps by (αᵢ/βᵢ₋₁)² (E20). The corrected joint
# H″ᵢ(0) = (βᵢ₋₁/αᵢ)² H″ᵢ₋₁(1) is G² for any α, β (`joint="g2"`).

# %%
from scipy.interpolate import CubicSpline

zigzag = sc.datasets.sample_points("zigzag")
constant = sc.timmer_gc2(zigzag, alpha=4.0)
ends = sc.estimate_tangents(zigzag)                       # raw end derivatives, eqs 2.1/2.2
reference = CubicSpline(np.arange(len(zigzag)), zigzag, bc_type=((1, ends[0]), (1, ends[-1])))
u = np.linspace(0, len(zigzag) - 1, 400)
cubic_spline_error = float(np.abs(constant(u) - reference(u)).max())
print(f"α = β = 4: max |Timmer GC² − scipy CubicSpline| = {cubic_spline_error:.2e} px")

alpha = np.array([2.0, 6.0, 2.0, 6.0, 2.0, 6.0])
thesis_joint = sc.timmer_gc2(zigzag, alpha=alpha, joint="thesis")
g2_joint = sc.timmer_gc2(zigzag, alpha=alpha, joint="g2")
k_thesis, k_g2 = thesis_joint.joint_curvature(), g2_joint.joint_curvature()
rows = [[i, k_thesis[i, 1] / k_thesis[i, 0], (alpha[i] / alpha[i - 1]) ** 2, k_g2[i, 1] / k_g2[i, 0]]
        for i in range(1, len(zigzag) - 1)]
display(sc.plot.table(["joint", "thesis joint κ⁺/κ⁻", "(αᵢ/βᵢ₋₁)²", "G² joint κ⁺/κ⁻"], rows))
display(sc.plot.grid(
    sc.plot.spline_figure(thesis_joint, data_points=zigzag, show_comb=True, width=460, height=300,
                          title="Alg 3.3, thesis joint: curvature steps"),
    sc.plot.spline_figure(g2_joint, data_points=zigzag, show_comb=True, width=460, height=300,
                          title="Alg 3.3, true G² joint: no steps"), columns=2))
sc.plot.grid(sc.plot.curvature_figure(thesis_joint, width=460), sc.plot.curvature_figure(g2_joint, width=460),
             columns=2)

# %% [markdown]
# ## 5. Try it yourself
#
# The editor in Timmer G² form on the ellipse, with the curvature comb: the joints where Algorithm 3.1 finds
# no positive root are labelled on the comb (κ⁺/κ⁻). Drag a point and watch them change. Switch the form to GC¹
# or GC² and move α, β; for GC² switch the joint to *true G²*.

# %%
editor = sc.SplineEditor(ellipse, closed=True, form="timmer_g2", show_comb=True)
editor.panel()

# %% [markdown]
# The same from code, on a second editor (the one above stays in G² form): GC² with α = 3, β = 6 and the true G²
# joint.

# %%
editor_g2_status = list(editor.spline.info["joint_status"])
print("G² form, joint statuses:", editor_g2_status)
gc2_editor = sc.SplineEditor(ellipse, closed=True, form="timmer_g2", show_comb=True)
gc2_editor.form = "timmer_gc2"
gc2_editor.end_condition = "g2"          # the joint dropdown
gc2_editor.alpha, gc2_editor.beta = 3.0, 6.0
gc2_editor.fit_view()                    # the "Fit" button
editor_jumps = [j for j in gc2_editor.spline.info["curvature_jump"] if j is not None]
print("GC² form, true G² joint, α = 3, β = 6: largest curvature jump", max(abs(j) for j in editor_jumps))
gc2_editor

# %% [markdown]
# ## Check

# %%
assert np.allclose(f.sum(axis=1), 1.0) and abs(f[:, 0].min() + 1 / 27) < 1e-5
assert f[:, 0].min() < 0 and f[:, 3].min() < 0                               # no convex-hull property
for i, s in enumerate(status):
    if s == "g2":
        assert abs(kappa[i, 1] - kappa[i, 0]) <= 1e-9 * np.abs(kappa).max()   # root found: G²
    else:
        assert s in ("g1_no_root", "g1_closing") and abs(jumps[i]) > 0         # flagged, jump reported
assert "g1_no_root" in status                                                  # the thesis's silent case
jumping = {int(j) % len(ellipse) for j in g2_profile["joints"][g2_profile["jumps"]]}
assert jumping == set(no_root)                                                 # κ(t) marks the same joints
distances = [deviation(s) for title, s in gc1_figures.items() if title.startswith("α")]
assert all(np.diff(distances) < 0)                                             # large α hugs the polygon
assert crossings(gc1_figures["α = β = 0.5"]) > 0                               # small α loops
assert all(crossings(gc1_figures[f"α = β = {a:g}"]) == 0 for a in (1.0, 2.0, 4.0, 20.0))
assert set(gc1_figures["α = β = 1"].info["joint_status"]) == {"c1"}
assert "g1" in gc1_figures["Fig 3.44: α = β = 15 on the base"].info["joint_status"]
assert negative_refused and loop_size[2.0] > loop_size[10.0] > 0             # α = −2: larger loops
assert crossings(reversed_curves[10.0]) >= len(heart)                         # α = −10: a loop at every point
assert cubic_spline_error < 1e-9                               # constant α: the uniform C² cubic spline
for i, ratio_thesis, expected, ratio_g2 in rows:
    assert np.isclose(ratio_thesis, expected, rtol=1e-8)       # E20
    assert np.isclose(ratio_g2, 1.0, rtol=1e-8)                # true G²
assert not sc.plot.curvature_profile(g2_joint)["jumps"].any()
assert sc.plot.curvature_profile(thesis_joint)["jumps"].all()
assert "g1_no_root" in editor_g2_status                        # the editor's ellipse has joints without a root
assert max(abs(j) for j in editor_jumps) < 1e-9
print("all checks passed")
