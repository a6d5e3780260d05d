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
# # 01 · The generic cubic and its special classes
#
# **What you should see.** A single generic cubic segment, drawn from four points F₀, V, W, F₁ and two
# shape parameters α, β, bends further towards V and W as α and β grow — Ball (α = β = 2), Bézier (3) and
# Timmer (4) are three stops on the same slider. In the interpolating spline through given points, however,
# α and β cancel exactly (erratum **E1**): choosing Ball, Bézier or Timmer moves only the auxiliary points
# Vᵢ, Wᵢ, never the curve.
#
# thesis section 3 (eqs 3.5–3.12, Figs 3.1–3.3); §1, §2.1 of `docs/math.md`. Run the cells from the top;
# the last cell checks every claim made here. Figures come from `sc.plot`, the widgets from `sc`.

# %%
import numpy as np
from IPython.display import display

import splinecraft as sc

# %% [markdown]
# ## 1. Blending functions (thesis eq 3.5, §1)
#
# $$P(\theta)=(1-\theta)^2\{1+(2-\alpha)\theta\}F_0+\alpha\theta(1-\theta)^2V+\beta\theta^2(1-\theta)W+\theta^2\{1+(2-\beta)(1-\theta)\}F_1$$
#
# The four coefficient functions always sum to 1 (so the curve is affine invariant). α = β = 3 gives the
# Bernstein polynomials (V, W are then the Bézier inner points), 2 Ball's basis and 4 Timmer's.

# %%
from splinecraft.spline.segment import blending_functions

theta = np.linspace(0.0, 1.0, 201)
names = {"ball": "Ball (α = β = 2)", "bezier": "Bézier (α = β = 3)", "timmer": "Timmer (α = β = 4)"}
blending = {key: blending_functions(theta, alpha, beta) for key, (alpha, beta) in sc.CLASS_PRESETS.items()}
display(sc.plot.grid(*[sc.plot.basis_figure(theta, values, labels=["F₀", "V", "W", "F₁"], title=names[key],
                                            xlabel="θ", y_range=(-0.1, 1.05), width=360)
                       for key, values in blending.items()]))
sc.plot.table(["class", "min of the F₀ weight", "max |Σ − 1|"],
              [[names[key], float(values[:, 0].min()), float(np.abs(values.sum(axis=1) - 1).max())]
               for key, values in blending.items()])

# %% [markdown]
# Timmer's end weights dip **below zero** (minimum −1/27 at θ = 2/3, thesis Fig 3.1): a Timmer segment is not a
# convex combination of its four points, so it may leave their convex hull (Fig 3.2).
#
# ## 2. One segment, several classes (eqs 3.5–3.11)
#
# Hold F₀, V, W, F₁ fixed and change α = β. The exact Bézier points are b₁ = F₀ + α/3 (V − F₀) and
# b₂ = F₁ + β/3 (W − F₁), and the end derivatives are P′(0) = α (V − F₀), P′(1) = β (F₁ − W) (eqs 3.10, 3.11).

# %%
F0, V, W, F1 = np.array([60.0, 320.0]), np.array([160.0, 80.0]), np.array([420.0, 80.0]), np.array([520.0, 320.0])
classes = [("α = β = 1", 1.0), ("Ball 2", 2.0), ("Bézier 3", 3.0), ("Timmer 4", 4.0), ("α = β = 6", 6.0)]
segments = {label: sc.generic_segment(F0, V, W, F1, value, value) for label, value in classes}
frame = np.array([F0, V, W, F1])
display(sc.plot.figure(sc.plot.polygon(frame), sc.plot.points(frame, size=40),
                       [sc.plot.curve(segments[label], color, label=label)
                        for (label, _), color in zip(classes, sc.plot.PALETTE)],
                       title="One segment, F₀ V W F₁ fixed", width=620, height=340))

rows = []
for label, value in classes:
    segment = segments[label]
    rows.append([label, str(np.round(segment(0.0, nu=1), 3)), str(np.round(value * (V - F0), 3)),
                 float(np.linalg.norm(segment(0.5) - (F0 + F1) / 2))])
sc.plot.table(["class", "P′(0) from the curve", "α (V − F₀), eq 3.10", "height of P(½) above the chord"], rows)

# %% [markdown]
# The larger α and β, the more the segment is pulled towards V and W (the height of the midpoint grows);
# with α = β = 6 the Bézier inner points lie *beyond* V and W.
#
# ### Timmer leaves the convex hull (thesis Fig 3.2)
# Because f₀ and f₃ are negative on parts of [0, 1], a Timmer segment can leave the convex hull of F₀, V, W, F₁.
# Here V and W sit close together above the chord, the hull is almost a triangle, and the Timmer curve pokes out
# of it on both sides:

# %%
from scipy.spatial import Delaunay

hull_points = np.array([[0.0, 0.0], [140.0, -100.0], [160.0, -100.0], [300.0, 0.0]])
hull = Delaunay(hull_points)
hull_classes = {"Bézier 3": 3.0, "Timmer 4": 4.0}
hull_segments = {label: sc.generic_segment(*hull_points, value, value) for label, value in hull_classes.items()}
outside_share = {label: float((hull.find_simplex(segment.sample(samples_per_segment=400)[1], tol=1e-9) < 0).mean())
                 for label, segment in hull_segments.items()}
display(sc.plot.table(["class", "share of the curve samples outside the hull of F₀ V W F₁"],
                      list(outside_share.items())))
sc.plot.figure(sc.plot.polygon(hull_points, closed=True, label="convex hull"),
               sc.plot.curve(hull_segments["Bézier 3"], sc.plot.PALETTE[1], label="Bézier 3"),
               sc.plot.curve(hull_segments["Timmer 4"], sc.plot.PALETTE[2], label="Timmer 4"),
               title="Convex hull (grey) and the two classes", width=620, height=260)

# %% [markdown]
# ## 3. The interpolating spline: the class does not change the curve (E1)
#
# For a spline through data points Fᵢ with tangents Mᵢ, the thesis sets Vᵢ = Fᵢ + hᵢMᵢ/αᵢ and Wᵢ = Fᵢ₊₁ − hᵢMᵢ₊₁/βᵢ
# (eqs 3.10–3.12). Substituting into b₁ = Fᵢ + αᵢ/3 (Vᵢ − Fᵢ) gives b₁ = Fᵢ + hᵢMᵢ/3: **αᵢ cancels** (§2.1).
# The thesis's figures that claim different Ball/Bézier/Timmer interpolants cannot be reproduced; what does change
# is the auxiliary polygon Fᵢ Vᵢ Wᵢ Fᵢ₊₁, which the engine keeps in `spline.auxiliary` for drawing.

# %%
points = sc.datasets.sample_points("hand")
interpolants = {name: sc.interpolate(points, alpha=a, beta=b) for name, (a, b) in sc.CLASS_PRESETS.items()}
reference = interpolants["ball"]
curve_difference = {name: float(np.abs(s.bezier() - reference.bezier()).max()) for name, s in interpolants.items()}
polygon_difference = {name: float(np.abs(s.auxiliary["V"] - reference.auxiliary["V"]).max())
                      for name, s in interpolants.items()}
display(sc.plot.table(["class", "max |Bézier points − Ball's|", "max |Vᵢ − Ball's Vᵢ|"],
                      [[name, curve_difference[name], polygon_difference[name]] for name in interpolants]))
sc.plot.figure([sc.plot.auxiliary_polygons(spline, color, 1.6, label=f"{name} polygon")
                for (name, spline), color in zip(interpolants.items(), sc.plot.PALETTE[1:])],
               sc.plot.curve(interpolants["bezier"], width=3.0, label="interpolant (all three)"),
               sc.plot.points(points, size=36),
               title="Same curve, three class polygons", width=720, height=380)

# %% [markdown]
# ## 4. Try it yourself
#
# **Single-segment design mode.** Drag F₀, V, W, F₁ and move the α, β sliders (preset *free α, β*): the curve
# reshapes, and the plot underneath shows the four blending functions of the current α, β.

# %%
segment_editor = sc.SplineEditor([F0.tolist(), V.tolist(), W.tolist(), F1.tolist()], form="segment",
                                 preset="free", alpha=3.0, beta=3.0, show_bezier_points=True)
segment_editor.panel()

# %% [markdown]
# The same from code: every control of the widget is a synced trait, and `editor.spline` is the curve.

# %%
before = segment_editor.spline.bezier()
segment_editor.alpha = 5.0                 # what the α slider does
segment_change = float(np.abs(segment_editor.spline.bezier() - before).max())
print(f"α 3 → 5 moved the segment's Bézier points by up to {segment_change:.1f} px")

# %% [markdown]
# **Interpolant mode.** Switch the class preset between Ball, Bézier and Timmer with *class points V, W* on: the
# dashed polygon moves, the curve stays exactly where it is (the widget says so too).

# %%
editor = sc.SplineEditor(points, form="interpolant", preset="ball", show_bezier_points=True)
editor.panel()

# %%
ball_curve, ball_V = editor.spline.bezier(), editor.spline.auxiliary["V"]
editor.preset = "timmer"                   # what the preset dropdown does
timmer_curve, timmer_V = editor.spline.bezier(), editor.spline.auxiliary["V"]
print("curve moved by", float(np.abs(timmer_curve - ball_curve).max()),
      "| auxiliary V moved by", round(float(np.abs(timmer_V - ball_V).max()), 2))

# %% [markdown]
# ## Check
# The claims of this notebook, asserted (the tests execute every notebook).

# %%
for key, values in blending.items():                          # partition of unity, every class
    assert np.allclose(values.sum(axis=1), 1.0, atol=1e-12), key
timmer_f0 = blending["timmer"][:, 0]
assert abs(timmer_f0.min() + 1 / 27) < 1e-4                   # Timmer's negative dip, −1/27 at θ = 2/3
assert abs(theta[timmer_f0.argmin()] - 2 / 3) < 0.01
assert min(blending["bezier"][:, 0]) >= 0 and min(blending["ball"][:, 0]) >= 0
heights = [float(np.linalg.norm(segments[label](0.5) - (F0 + F1) / 2)) for label, _ in classes]
assert all(np.diff(heights) > 0)                              # larger α, β pull towards V, W
for label, value in classes:                                  # eq 3.10 and 3.11
    assert np.allclose(segments[label](0.0, nu=1), value * (V - F0))
    assert np.allclose(segments[label](1.0, nu=1), value * (F1 - W))
bezier_six = segments["α = β = 6"].bezier()[0]               # α = 6: inner Bézier points beyond V and W
assert np.linalg.norm(bezier_six[1] - F0) > np.linalg.norm(V - F0)
assert outside_share["Bézier 3"] == 0 and outside_share["Timmer 4"] > 0   # convex hull (Fig 3.2)
assert max(curve_difference.values()) < 1e-9                  # E1: α, β do not change the interpolant
assert polygon_difference["timmer"] > 1.0                      # ... only the auxiliary V, W
assert segment_change > 1.0                                    # in design mode they do change the segment
assert np.abs(timmer_curve - ball_curve).max() < 1e-9 and np.abs(timmer_V - ball_V).max() > 1.0
assert "did not move" in editor.status_message                # ... and the widget says so
print("all checks passed")
