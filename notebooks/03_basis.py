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
# # 03 · The local-support basis form
#
# **What you should see.** The basis form writes the curve as P(t) = Σ Bⱼ(t) Pⱼ with basis functions that
# sum to one, are non-negative and live on only four intervals, so dragging one control point moves at most
# four segments; with v = 0, ω = 1 they are exactly the cubic B-splines. Point tension pulls the curve to its
# control points and interval tension straightens legs (thesis Figs 3.12–3.25), while strongly negative v
# (below −8 with uniform knots) makes the basis negative, so the curve can leave the convex hull of its
# control polygon (Figs 3.26–3.38).
#
# thesis section 3.2 (eqs 3.29–3.84); §4 (errata E9–E12).

# %%
import numpy as np
from IPython.display import display
from scipy.spatial import Delaunay

import splinecraft as sc

# %% [markdown]
# ## 1. The basis functions
#
# `sc.basis_functions(t, n)` evaluates all Bⱼ at once (uniform knots tⱼ = j), as a sparse matrix: at each t only
# four Bⱼ are non-zero (`.toarray()` gives the full table). For a closed curve with 8 control
# points, and then for point tension v = 10 and v = −10 at every point:

# %%
n_control = 8
t = np.linspace(0.0, n_control, 801)
basis = {v: sc.basis_functions(t, n_control, closed=True, point_tension=v).toarray() for v in (0.0, 10.0, -10.0)}
display(sc.plot.grid(*[sc.plot.basis_figure(t, values, title=f"closed, uniform knots, v = {v:g}", width=360,
                                            y_range=None if v < 0 else (-0.05, 1.05))
                       for v, values in basis.items()]))
sc.plot.table(["v", "min Bⱼ", "max |Σ Bⱼ − 1|"],
              [[v, float(values.min()), float(np.abs(values.sum(axis=1) - 1).max())] for v, values in basis.items()])

# %% [markdown]
# With v = 0 and ω = 1 these are the uniform cubic B-splines. Compare an open (floating-end) basis with
# `scipy.interpolate.BSpline.basis_element` on the same knots — an independent implementation:

# %%
from scipy.interpolate import BSpline

n_open = 10
t_open = np.linspace(1.0, n_open - 2.0, 700)            # the curve's domain [t_1, t_n]
open_basis = sc.basis_functions(t_open, n_open).toarray()
bspline_error = 0.0
support_violation = 0.0                                 # B_j must vanish outside (t_{j-2}, t_{j+2})
for j in range(n_open):
    element = BSpline.basis_element(np.arange(j - 2, j + 3, dtype=float), extrapolate=False)
    bspline_error = max(bspline_error, float(np.abs(open_basis[:, j] - np.nan_to_num(element(t_open))).max()))
    outside = (t_open <= j - 2) | (t_open >= j + 2)
    support_violation = max(support_violation, float(np.abs(open_basis[outside, j]).max(initial=0.0)))
print(f"max |B_j - scipy B-spline| = {bspline_error:.2e}")
print(f"largest |B_j| outside its four intervals = {support_violation:.2e}")

# %% [markdown]
# ## 2. Local control
#
# Move one control point of the 'pot' (thesis Fig 3.12) and compare the Bézier pieces before and after: only the
# four segments that Pⱼ supports change.

# %%
pot = sc.datasets.sample_points("pot")
before = sc.basis_spline(pot)
moved = pot.copy()
moved[6] += [40.0, -60.0]
after = sc.basis_spline(moved)
changed = np.flatnonzero(np.abs(after.bezier() - before.bezier()).max(axis=(1, 2)) > 1e-9)
print(f"{before.n_segments} segments; moving P6 changed segments {changed.tolist()}")
sc.plot.figure(sc.plot.polygon(pot), sc.plot.curve(before, "#90a4ae", 2, dashed=True, label="before"),
               sc.plot.polygon(moved, color=sc.plot.PALETTE[1]), sc.plot.curve(after, label="after"),
               sc.plot.points(moved[6:7], "#c62828", 60, label="P6 moved"),
               title="Moving P6 changes four segments", width=520, height=380)

# %% [markdown]
# ## 3. Point and interval tension on the Pot and the Square (Figs 3.12–3.25)
#
# Uniform knots as in the thesis (`basis_spline` default). Global point tension v pulls the curve to the control
# points (v → ∞: the curve passes through them with a cusp); a large ω on the bottom leg makes that segment a
# straight piece of the leg; point tension at chosen points (here the square's corners) sharpens only those.

# %%
square = sc.datasets.sample_points("square")       # 8 control points: corners and midpoints
corners = np.array([0, 2, 4, 6])
bottom = np.where(np.arange(8) == 0, 1.0, 0.0)     # leg P0 -> P1 lies on the bottom edge (y down)


def square_curve(v=0.0, w=1.0):
    return sc.basis_spline(square, closed=True, point_tension=v, interval_weights=w)


def gap(spline, targets):
    """Largest distance from the target points to the curve (px)."""
    _, samples = spline.sample(samples_per_segment=64)
    return float(np.linalg.norm(samples[None] - targets[:, None], axis=2).min(axis=1).max())


pot_figures = {"Fig 3.12 Pot: v = 0": sc.basis_spline(pot), "Fig 3.14: v = 10": sc.basis_spline(pot, point_tension=10.0),
               "Fig 3.15: v = 100": sc.basis_spline(pot, point_tension=100.0)}
square_figures = {"Fig 3.13 Square: v = 0": square_curve(), "Fig 3.16: v = 10": square_curve(10.0),
                  "Fig 3.17: v = 100": square_curve(100.0),
                  "Fig 3.18/3.20: ω = 10 on the bottom leg": square_curve(w=1.0 + 9.0 * bottom),
                  "Fig 3.19/3.21: ω = 100 on the bottom leg": square_curve(w=1.0 + 99.0 * bottom),
                  "Figs 3.22–3.25: v = 100 at the corners": square_curve(np.where(np.isin(np.arange(8), corners), 100.0, 0.0))}
pot_gaps = [gap(spline, pot[1:-1]) for spline in pot_figures.values()]
corner_gaps = {title: gap(spline, square[corners]) for title, spline in square_figures.items()}
display(sc.plot.grid(*[sc.plot.spline_figure(spline, data_points=pot, polygon=pot, title=title, width=300, height=280)
                       for title, spline in pot_figures.items()],
                     *[sc.plot.spline_figure(spline, data_points=square, polygon=square, title=title, width=300, height=280)
                       for title, spline in square_figures.items()]))
sc.plot.table(["figure", "corner control point to curve (px)"], list(corner_gaps.items()))

# %% [markdown]
# ## 4. Negative point tension and the convex hull (Figs 3.26–3.38)
#
# The basis is non-negative — and so every curve point is a convex combination of control points — as long as
# dᵢ = aᵢ₋₁ + aᵢ + ½aᵢ₋₁aᵢvᵢ > 0, i.e. v > −2(ωᵢ₋₁/hᵢ₋₁ + ωᵢ/hᵢ) = −4 here; numerically the uniform basis stays
# ≥ 0 down to v = −8, and is negative below (§4.5). At v = −4 exactly the closed forms are 0/0 and the
# engine refuses. Below −8 the basis has negative parts, so the convex hull no longer binds the curve: at
# v = −10 the square's curve still happens to stay inside it, from v = −11 on it leaves it (red).

# %%
hull = Delaunay(square)
negative_rows, outside, negative_curves, refused = [], {}, {}, {}
for v in (-3.0, -4.0, -5.0, -8.0, -10.0, -11.0, -20.0, -50.0):
    try:
        spline = square_curve(v)
    except ValueError as error:
        refused[v] = str(error)
        negative_rows.append([v, "refused", "—", str(error)[:70] + "…"])
        continue
    negative_curves[v] = spline
    minimum = float(sc.basis_functions(np.linspace(0, 8, 801), 8, closed=True, point_tension=v).min())
    outside[v] = int((hull.find_simplex(spline.sample(samples_per_segment=64)[1], tol=1e-9) < 0).sum())
    negative_rows.append([v, minimum, outside[v], ""])
display(sc.plot.table(["v", "min Bⱼ", "curve samples outside the hull", "note"], negative_rows))
sc.plot.grid(*[sc.plot.spline_figure(spline, polygon=square, title=f"v = {v:g}", width=260, height=250,
                                     color=sc.plot.PALETTE[0] if outside[v] == 0 else "#c62828")
               for v, spline in negative_curves.items()], columns=4)

# %% [markdown]
# ## 5. Try it yourself
#
# The editor in basis form, with the live basis-function plot: select a control point (its Bⱼ is drawn thick) and
# move its **v**; select a leg and move its **ω**. The dashed line Σ Bⱼ = 1 never moves.

# %%
editor = sc.SplineEditor(pot, form="basis", knots="uniform", tension_scale="absolute", show_control_polygon=True)
editor.panel()

# %%
editor.selected = 6
editor.point_tension = [0.0] * 6 + [50.0] + [0.0] * (len(pot) - 7)   # v = 50 at P6 only
editor_gap = gap(editor.spline, pot[6:7])
print(f"with v6 = 50 the curve passes {editor_gap:.1f} px from P6")

# %% [markdown]
# ## Check

# %%
for v, values in basis.items():
    assert np.allclose(values.sum(axis=1), 1.0, atol=1e-12)               # partition of unity
assert basis[0.0].min() > -1e-12 and basis[10.0].min() > -1e-12           # non-negative for v ≥ 0
assert basis[-10.0].min() < 0                                             # negative lobes below −8
assert bspline_error < 1e-12 and support_violation < 1e-12               # = cubic B-splines, local support
assert 0 < len(changed) <= 4 and np.all(np.diff(changed) == 1)            # local control
assert pot_gaps[2] < pot_gaps[1] < pot_gaps[0]                            # v pulls to the control points
gaps = list(corner_gaps.values())
assert gaps[2] < gaps[1] < gaps[0] and gaps[5] < gaps[0] / 3
bottom_leg = square[[0, 1]]                                               # ω straightens the bottom leg
sag = {w: float(np.abs(square_figures[title].bezier()[0][:, 1] - bottom_leg[0, 1]).max())
       for w, title in ((1, "Fig 3.13 Square: v = 0"), (100, "Fig 3.19/3.21: ω = 100 on the bottom leg"))}
assert sag[100] < sag[1] / 5
assert -4.0 in refused and len(refused) == 1                              # D_i = 0 at v = −4 only
minimum_basis = {row[0]: row[1] for row in negative_rows if row[1] != "refused"}
for v in (-3.0, -5.0, -8.0):
    assert outside[v] == 0 and minimum_basis[v] > -1e-12                  # B ≥ 0, hull kept down to −8
assert minimum_basis[-10.0] < 0 and outside[-10.0] == 0                   # −10: B < 0, the square still inside
assert all(outside[v] > 0 for v in (-11.0, -20.0, -50.0))                 # from −11 on it leaves the hull
assert editor_gap < 5.0
dashed = [mark for mark in editor.basis_figure.marks if getattr(mark, "line_style", "") == "dashed"]
assert dashed and np.allclose(np.asarray(dashed[0].y), 1.0, atol=1e-9)   # the editor's Σ Bⱼ = 1 line
print("all checks passed")
