"""The cells of the classroom notebooks (read by notebooks/_build.py).

Each notebook is a list of ("md" | "code", source) pairs. Every notebook starts with two sentences of
what a student should see, then the shared SETUP cell, and ends with a "Check" cell whose asserts make
the executed notebook a test of what the lesson claims.
"""

SETUP = r'''
import warnings

import numpy as np
import bqplot as bq
import ipywidgets as ipw
from IPython.display import Markdown, display

import splinecraft as sc

PALETTE = ["#1565c0", "#ef6c00", "#2e7d32", "#8e24aa", "#c62828", "#00838f", "#6d4c41", "#5e35b1"]


class Plot:
    """A small bqplot figure. Equal axis scales and y pointing down by default: the frame of the
    SplineEditor and of bitmaps (x right, y down), so what you see here matches the widgets."""

    def __init__(self, title="", width=330, height=290, *, y_down=True, equal=True, xlabel="", ylabel="",
                 x_range=None, y_range=None, bounds=None, log_y=False):
        self.x = bq.LinearScale()
        self.y = bq.LogScale(reverse=y_down) if log_y else bq.LinearScale(reverse=y_down)
        self.bounds = bounds
        if x_range is not None:
            self.x.min, self.x.max = map(float, x_range)
        if y_range is not None:
            self.y.min, self.y.max = map(float, y_range)
        self.size, self.equal, self.marks = (width, height), equal, []
        self.title, self.xlabel, self.ylabel = title, xlabel, ylabel
        self.low, self.high = np.full(2, np.inf), np.full(2, -np.inf)

    def _grow(self, xy):
        xy = np.asarray(xy, float).reshape(-1, 2)
        xy = xy[np.isfinite(xy).all(axis=1)]
        if len(xy):
            self.low, self.high = np.minimum(self.low, xy.min(0)), np.maximum(self.high, xy.max(0))

    def _scales(self):
        return {"x": self.x, "y": self.y}

    def line(self, xy, color=PALETTE[0], width=2.0, *, dashed=False, label=None, closed=False, opacity=1.0):
        xy = np.asarray(xy, float)
        if closed:
            xy = np.vstack([xy, xy[:1]])
        self._grow(xy)
        self.marks.append(bq.Lines(x=xy[:, 0], y=xy[:, 1], scales=self._scales(), colors=[color],
                                   stroke_width=width, line_style="dashed" if dashed else "solid",
                                   opacities=[opacity], labels=[label] if label else [],
                                   display_legend=bool(label)))
        return self

    def polylines(self, paths, color=PALETTE[0], width=1.0, *, dashed=False, opacity=1.0):
        """Many polylines of the same length in one mark, paths: array (k, m, 2)."""
        paths = np.asarray(paths, float)
        if paths.size == 0:
            return self
        self._grow(paths)
        self.marks.append(bq.Lines(x=paths[..., 0], y=paths[..., 1], scales=self._scales(),
                                   colors=[color] * len(paths), stroke_width=width, opacities=[opacity] * len(paths),
                                   line_style="dashed" if dashed else "solid"))
        return self

    def dots(self, xy, color=PALETTE[0], size=28, *, marker="circle", label=None):
        xy = np.asarray(xy, float).reshape(-1, 2)
        self._grow(xy)
        self.marks.append(bq.Scatter(x=xy[:, 0], y=xy[:, 1], scales=self._scales(), colors=[color],
                                     default_size=size, marker=marker, stroke="white",
                                     labels=[label] if label else [], display_legend=bool(label)))
        return self

    def curve(self, spline, color=PALETTE[0], width=2.5, *, label=None, samples=32, dashed=False):
        _, xy = spline.sample(samples_per_segment=samples)
        return self.line(xy, color, width, label=label, dashed=dashed)

    def comb(self, spline, relative_length=0.12, color="#8e24aa", samples=20):
        """Curvature comb (§7): teeth ∝ κ, drawn outside, both one-sided teeth at every joint.

        Scaled so the 90th-percentile tooth is ``relative_length`` of the curve's size; the few teeth
        of sharp turns that would be longer than 2.5 times that are clipped (drawn dashed-free, capped)."""
        base, tips = spline.curvature_comb(scale=1.0, samples_per_segment=samples)
        teeth = tips - base                                    # length |κ|
        lengths = np.linalg.norm(teeth, axis=1)
        size = float(np.ptp(base, axis=0).max())
        target = relative_length * size
        scale = target / max(float(np.percentile(lengths, 90)), 1e-300)
        factor = np.minimum(scale, 2.5 * target / np.maximum(lengths, 1e-300))
        self.polylines(np.stack([base, base + teeth * factor[:, None]], axis=1), color, 1.0, opacity=0.7)
        return self

    @property
    def figure(self):
        width, height = self.size
        margin = {"top": 36, "bottom": 34, "left": 52, "right": 12}
        if self.bounds is not None:                       # a fixed window (x0, y0, x1, y1): zoom
            self.low, self.high = np.array(self.bounds[:2], float), np.array(self.bounds[2:], float)
        if self.equal and np.isfinite(self.low).all():
            area = np.array([width - margin["left"] - margin["right"], height - margin["top"] - margin["bottom"]])
            span = np.maximum(self.high - self.low, 1e-9) * 1.08
            half = (span / area).max() * area / 2
            middle = (self.low + self.high) / 2
            self.x.min, self.x.max = float(middle[0] - half[0]), float(middle[0] + half[0])
            self.y.min, self.y.max = float(middle[1] - half[1]), float(middle[1] + half[1])
        for mark in self.marks:
            mark.apply_clip = True
        axes = [bq.Axis(scale=self.x, label=self.xlabel, num_ticks=5, grid_lines="none"),
                bq.Axis(scale=self.y, orientation="vertical", label=self.ylabel, num_ticks=5, grid_lines="none")]
        return bq.Figure(marks=self.marks, axes=axes, title=self.title, fig_margin=margin,
                         layout=ipw.Layout(width=f"{width}px", height=f"{height}px"),
                         title_style={"font-size": "13px"}, legend_location="top-right",
                         legend_style={"fill": "white", "stroke": "#d0d7de", "font-size": "11px"},
                         animation_duration=0)


def show(*plots, columns=3):
    """Display plots (Plot or any widget) in rows of ``columns``."""
    items = [p.figure if isinstance(p, Plot) else p for p in plots]
    display(ipw.VBox([ipw.HBox(items[i:i + columns]) for i in range(0, len(items), columns)]))


def table(header, rows, digits=4):
    """Display a small markdown table (numbers rounded to ``digits`` significant digits)."""
    def cell(value):
        if isinstance(value, (float, np.floating)):
            return f"{value:.{digits}g}"
        return str(value).replace("|", "\\|")
    lines = ["| " + " | ".join(cell(h) for h in header) + " |", "|" + " --- |" * len(header)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    display(Markdown("\n".join(lines)))


def distance_to_polyline(points, polyline, closed=False):
    """Distance from each point to a polyline (vectorised over points and segments)."""
    points, polyline = np.asarray(points, float), np.asarray(polyline, float)
    if closed:
        polyline = np.vstack([polyline, polyline[:1]])
    a, b = polyline[:-1], polyline[1:]
    d = b - a
    rel = points[:, None, :] - a[None]
    u = np.clip((rel * d).sum(-1) / np.maximum((d * d).sum(-1), 1e-300), 0.0, 1.0)
    return np.linalg.norm(rel - u[..., None] * d, axis=-1).min(axis=1)
'''


def _intro(title, two_sentences, sections=""):
    text = f"# {title}\n\n{two_sentences}"
    if sections:
        text += f"\n\n{sections}"
    return ("md", text)


# ----------------------------------------------------------------------------------------------------
# 01 the generic cubic
# ----------------------------------------------------------------------------------------------------
NB01 = [
    _intro(
        "01 · The generic cubic and its special classes",
        "**What you should see.** A single generic cubic segment, drawn from four points F₀, V, W, F₁ and two "
        "shape parameters α, β, bends further towards V and W as α and β grow — Ball (α = β = 2), Bézier (3) "
        "and Timmer (4) are three stops on the same slider. In the interpolating spline through given points, "
        "however, α and β cancel exactly (erratum **E1** of the spec): choosing Ball, Bézier or Timmer moves "
        "only the auxiliary points Vᵢ, Wᵢ, never the curve.",
        "thesis section 3 (eqs 3.5–3.12, Figs 3.1–3.3); §1, §2.1. Run the cells from the top; the last cell "
        "checks every claim made here.",
    ),
    ("code", SETUP),
    ("md", r"""
## 1. Blending functions (thesis eq 3.5, §1)

$$P(\theta)=(1-\theta)^2\{1+(2-\alpha)\theta\}F_0+\alpha\theta(1-\theta)^2V+\beta\theta^2(1-\theta)W+\theta^2\{1+(2-\beta)(1-\theta)\}F_1$$

The four coefficient functions always sum to 1 (so the curve is affine invariant). α = β = 3 gives the
Bernstein polynomials (V, W are then the Bézier inner points), 2 Ball's basis and 4 Timmer's."""),
    ("code", r'''
from splinecraft.spline.segment import blending_functions

theta = np.linspace(0.0, 1.0, 201)
names = {"ball": "Ball (α = β = 2)", "bezier": "Bézier (α = β = 3)", "timmer": "Timmer (α = β = 4)"}
plots, blending_sums = [], {}
for key, (alpha, beta) in sc.CLASS_PRESETS.items():
    values = blending_functions(theta, alpha, beta)              # shape (201, 4)
    blending_sums[key] = values.sum(axis=1)
    plot = Plot(names[key], y_down=False, equal=False, xlabel="θ", x_range=(0, 1), y_range=(-0.1, 1.05))
    for j, label in enumerate(["F₀", "V", "W", "F₁"]):
        plot.line(np.c_[theta, values[:, j]], PALETTE[j], label=label)
    plot.line(np.c_[theta, values.sum(axis=1)], "#263238", 1.5, dashed=True)
    plots.append(plot)
show(*plots)
table(["class", "min of the F₀ weight", "max |Σ − 1|"],
      [[names[k], float(blending_functions(theta, *sc.CLASS_PRESETS[k])[:, 0].min()),
        float(np.abs(blending_sums[k] - 1).max())] for k in sc.CLASS_PRESETS])
'''),
    ("md", r"""
Timmer's end weights dip **below zero** (minimum −1/27 at θ = 2/3, thesis Fig 3.1): a Timmer segment is not a
convex combination of its four points, so it may leave their convex hull (Fig 3.2).

## 2. One segment, several classes (eqs 3.5–3.11)

Hold F₀, V, W, F₁ fixed and change α = β. The exact Bézier points are b₁ = F₀ + α/3 (V − F₀) and
b₂ = F₁ + β/3 (W − F₁), and the end derivatives are P′(0) = α (V − F₀), P′(1) = β (F₁ − W) (eqs 3.10, 3.11)."""),
    ("code", r'''
F0, V, W, F1 = np.array([60.0, 320.0]), np.array([160.0, 80.0]), np.array([420.0, 80.0]), np.array([520.0, 320.0])
classes = [("α = β = 1", 1.0), ("Ball 2", 2.0), ("Bézier 3", 3.0), ("Timmer 4", 4.0), ("α = β = 6", 6.0)]
segments = {label: sc.generic_segment(F0, V, W, F1, value, value) for label, value in classes}

plot = Plot("One segment, F₀ V W F₁ fixed", width=520, height=340)
plot.line(np.array([F0, V, W, F1]), "#90a4ae", 1.5, dashed=True)
plot.dots(np.array([F0, V, W, F1]), "#455a64", 40)
for (label, value), color in zip(classes, PALETTE):
    plot.curve(segments[label], color, label=label)
show(plot)

rows = []
for label, value in classes:
    segment = segments[label]
    start_derivative = segment(0.0, nu=1)
    rows.append([label, str(np.round(start_derivative, 3)), str(np.round(value * (V - F0), 3)),
                 float(np.linalg.norm(segment(0.5) - (F0 + F1) / 2))])
table(["class", "P′(0) from the curve", "α (V − F₀), eq 3.10", "height of P(½) above the chord"], rows)
'''),
    ("md", r"""
The larger α and β, the more the segment is pulled towards V and W (the height of the midpoint grows);
with α = β = 6 the Bézier inner points lie *beyond* V and W.

### Timmer leaves the convex hull (thesis Fig 3.2)
Because f₀ and f₃ are negative on parts of [0, 1], a Timmer segment can leave the convex hull of F₀, V, W, F₁.
Here V and W sit close together above the chord, the hull is almost a triangle, and the Timmer curve pokes out
of it on both sides:"""),
    ("code", r'''
from scipy.spatial import Delaunay

hull_points = np.array([[0.0, 0.0], [140.0, -100.0], [160.0, -100.0], [300.0, 0.0]])
hull = Delaunay(hull_points)
rows, outside_count = [], {}
for label, value in [("Bézier 3", 3.0), ("Timmer 4", 4.0)]:
    segment = sc.generic_segment(*hull_points, value, value)
    _, samples = segment.sample(samples_per_segment=400)
    outside = hull.find_simplex(samples, tol=1e-9) < 0
    outside_count[label] = int(outside.sum())
    rows.append([label, int(outside.sum()), len(samples)])
table(["class", "samples outside the hull of F₀ V W F₁", "samples"], rows)

plot = Plot("Convex hull (grey) and the two classes", width=520, height=260)
plot.line(hull_points[[0, 1, 2, 3, 0]], "#90a4ae", 1.5, dashed=True)
plot.curve(sc.generic_segment(*hull_points, 3.0, 3.0), PALETTE[1], label="Bézier 3")
plot.curve(sc.generic_segment(*hull_points, 4.0, 4.0), PALETTE[2], label="Timmer 4")
show(plot)
'''),
    ("md", r"""
## 3. The interpolating spline: the class does not change the curve (E1)

For a spline through data points Fᵢ with tangents Mᵢ, the thesis sets Vᵢ = Fᵢ + hᵢMᵢ/αᵢ and Wᵢ = Fᵢ₊₁ − hᵢMᵢ₊₁/βᵢ
(eqs 3.10–3.12). Substituting into b₁ = Fᵢ + αᵢ/3 (Vᵢ − Fᵢ) gives b₁ = Fᵢ + hᵢMᵢ/3: **αᵢ cancels** (§2.1).
The thesis's figures that claim different Ball/Bézier/Timmer interpolants cannot be reproduced; what does change
is the auxiliary polygon Fᵢ Vᵢ Wᵢ Fᵢ₊₁, which the engine keeps in `spline.auxiliary` for drawing."""),
    ("code", r'''
points = sc.datasets.sample_points("hand")
interpolants = {name: sc.interpolate(points, alpha=a, beta=b) for name, (a, b) in sc.CLASS_PRESETS.items()}
reference = interpolants["ball"].bezier()
curve_difference = {name: float(np.abs(s.bezier() - reference).max()) for name, s in interpolants.items()}
polygon_difference = {name: float(np.abs(s.auxiliary["V"] - interpolants["ball"].auxiliary["V"]).max())
                      for name, s in interpolants.items()}
table(["class", "max |Bézier points − Ball's|", "max |Vᵢ − Ball's Vᵢ|"],
      [[name, curve_difference[name], polygon_difference[name]] for name in interpolants])

plot = Plot("Same curve, three class polygons (Ball, Bézier, Timmer)", width=620, height=380)
for (name, spline), color in zip(interpolants.items(), PALETTE[1:]):
    aux = spline.auxiliary
    F = aux["F"]
    polygons = np.stack([F[:-1], aux["V"], aux["W"], F[1:]], axis=1)     # (segments, 4, 2)
    plot.polylines(polygons, color, 1.2, dashed=True)
plot.curve(interpolants["bezier"], PALETTE[0], 3.0, label="interpolant (all three)")
plot.dots(points, "#263238", 36)
show(plot)
'''),
    ("md", r"""
## 4. Try it yourself

**Single-segment design mode.** Drag F₀, V, W, F₁ and move the α, β sliders (preset *free α, β*): the curve
reshapes, and the plot underneath shows the four blending functions of the current α, β."""),
    ("code", r'''
segment_editor = sc.SplineEditor([F0.tolist(), V.tolist(), W.tolist(), F1.tolist()], form="segment",
                                 preset="free", alpha=3.0, beta=3.0, show_bezier_points=True)
display(segment_editor.panel())
'''),
    ("md", "The same from code: every control of the widget is a synced trait, and `editor.spline` is the curve."),
    ("code", r'''
before = segment_editor.spline.bezier()
segment_editor.alpha = 5.0                 # what the α slider does
after = segment_editor.spline.bezier()
segment_change = float(np.abs(after - before).max())
print(f"α 3 → 5 moved the segment's Bézier points by up to {segment_change:.1f} px")
'''),
    ("md", r"""
**Interpolant mode.** Switch the class preset between Ball, Bézier and Timmer with *Bézier points* on: the
dashed polygon moves, the curve stays exactly where it is (the widget says so too)."""),
    ("code", r'''
editor = sc.SplineEditor(points, form="interpolant", preset="ball", show_bezier_points=True)
display(editor.panel())
'''),
    ("code", r'''
ball_curve, ball_V = editor.spline.bezier(), editor.spline.auxiliary["V"]
editor.preset = "timmer"                   # what the preset dropdown does
timmer_curve, timmer_V = editor.spline.bezier(), editor.spline.auxiliary["V"]
print("curve moved by", float(np.abs(timmer_curve - ball_curve).max()),
      "| auxiliary V moved by", round(float(np.abs(timmer_V - ball_V).max()), 2))
print(editor.explanation)
'''),
    ("md", "## Check\nThe claims of this notebook, asserted (the tests execute every notebook)."),
    ("code", r'''
for key, sums in blending_sums.items():                       # partition of unity, every class
    assert np.allclose(sums, 1.0, atol=1e-12), key
timmer_f0 = blending_functions(theta, 4.0, 4.0)[:, 0]
assert abs(timmer_f0.min() + 1 / 27) < 1e-4                   # Timmer's negative dip, −1/27 at θ = 2/3
heights = [float(np.linalg.norm(segments[label](0.5) - (F0 + F1) / 2)) for label, _ in classes]
assert all(np.diff(heights) > 0)                              # larger α, β pull towards V, W
for label, value in classes:                                  # eq 3.10 and 3.11
    assert np.allclose(segments[label](0.0, nu=1), value * (V - F0))
    assert np.allclose(segments[label](1.0, nu=1), value * (F1 - W))
assert outside_count["Bézier 3"] == 0 and outside_count["Timmer 4"] > 0   # convex hull (Fig 3.2)
assert max(curve_difference.values()) < 1e-9                  # E1: α, β do not change the interpolant
assert polygon_difference["timmer"] > 1.0                      # ... only the auxiliary V, W
assert segment_change > 1.0                                    # in design mode they do change the segment
assert np.abs(timmer_curve - ball_curve).max() < 1e-9 and np.abs(timmer_V - ball_V).max() > 1.0
print("all checks passed")
'''),
]


# ----------------------------------------------------------------------------------------------------
# 02 point and interval tension
# ----------------------------------------------------------------------------------------------------
NB02 = [
    _intro(
        "02 · Point tension and interval tension",
        "**What you should see.** Raising the point tension v pulls the interpolating spline towards its data "
        "polygon (the thesis says positive v has no effect — erratum **E22**), large interval weights ω "
        "straighten their intervals, and negative v first bulges the curve and then, below −6(c₍ₖ₋₁₎ + cₖ), "
        "reverses the tangents so the curve loops (thesis Figs 3.4–3.11), with a band in between where the "
        "system is singular (**E8**). With curvature combs you will also see that a joint is only G² where "
        "the neighbouring interval weights are equal (**E2**): the curvature jumps by the ratio ω₍ᵢ₋₁₎/ωᵢ.",
        "thesis sections 3.1, 3.4 (eqs 3.1–3.4, 3.13–3.14); §2.2–2.5, §7.",
    ),
    ("code", SETUP),
    ("md", r"""
## 1. The joint condition and the tangent system

At every interior knot the interpolant is C¹ and satisfies **ωᵢ P″(tᵢ⁺) = vᵢ P′(tᵢ) + ωᵢ₋₁ P″(tᵢ⁻)**
(eq 3.13). This is the stationarity condition of the energy
E = Σ ωᵢ ∫ ‖P″‖² dt + Σ vᵢ ‖Mᵢ‖²: **vᵢ penalises the speed at the point, ωᵢ the bending of interval i**.
The tangents Mₖ solve one tridiagonal system (§2.3; E3 corrects a factor 2 in eq 3.25):

$$c_{k-1}M_{k-1}+\big(\tfrac12v_k+2c_{k-1}+2c_k\big)M_k+c_kM_{k+1}=3(c_{k-1}\Delta_{k-1}+c_k\Delta_k),\qquad c_i=\omega_i/h_i.$$

The thesis's figures use uniform knots, h = ω = 1, so cₖ₋₁ + cₖ = 2: row k is safe for v > −4, singular
somewhere in [−12, −4], and *reversed* below −12. We use the same setting (`knots="uniform"`) on a closed
heart."""),
    ("code", r'''
heart = sc.datasets.sample_points("heart")
def heart_curve(v=0.0, w=1.0, **kw):
    return sc.interpolate(heart, closed=True, knots="uniform", point_tension=v, interval_weights=w, **kw)

def deviation(spline, polygon=heart):
    """Largest distance of the curve from the closed data polygon (px)."""
    _, samples = spline.sample(samples_per_segment=48)
    return float(distance_to_polyline(samples, polygon, closed=True).max())

def reversed_tangents(spline, polygon=heart):
    """How many tangents M_k point against the chord average F_{k+1} - F_{k-1} (uniform knots)."""
    M = spline.auxiliary["tangents"][: len(polygon)]
    chord_average = np.roll(polygon, -1, axis=0) - np.roll(polygon, 1, axis=0)
    return int(((M * chord_average).sum(axis=1) < 0).sum())

figures = [("Fig 3.4: ω = 1, v = 0", 0.0, 1.0), ("Fig 3.5: v = 10", 10.0, 1.0), ("Fig 3.6: v = 50", 50.0, 1.0),
           ("Fig 3.7: ω = 100, v = 0", 0.0, 100.0), ("Fig 3.8: v = −3", -3.0, 1.0),
           ("Fig 3.9: v = −15", -15.0, 1.0), ("Fig 3.10: v = −25", -25.0, 1.0), ("Fig 3.11: v = −50", -50.0, 1.0)]
curves, plots, rows = {}, [], []
for title, v, w in figures:
    curves[title] = spline = heart_curve(v, w)
    plots.append(Plot(title, width=270, height=250).line(heart, "#90a4ae", 1.2, dashed=True, closed=True)
                 .curve(spline, PALETTE[0]).dots(heart, "#263238", 22))
    rows.append([title, deviation(spline), reversed_tangents(spline)])
show(*plots, columns=4)
table(["figure", "max distance from the polygon (px)", "reversed tangents (of 12)"], rows)
'''),
    ("md", r"""
What the table says:

* **Positive v tightens (E22).** v = 10 and v = 50 bring the curve much closer to the polygon; as v → ∞ the
  tangents go to zero and the curve *becomes* the polygon (with cusps at the points). The thesis's remark
  that "positive increase … does not produce any effect" is wrong; its Figs 3.5–3.6 just used a scale where
  the effect was small.
* **A global ω changes nothing when v = 0 (Fig 3.7).** Multiplying every ωᵢ by 100 multiplies every row of
  the system by 100: the tangents and the curve are identical to Fig 3.4. Only *relative* weights act.
* **Negative v.** v = −3 is in the safe range (the solution is still the unique energy minimiser) and makes
  the curve rounder and bulgier; at the heart's two sharp points (top notch and tip), where the chords
  nearly cancel, the bulge already turns the tangent against them. v = −15, −25, −50 are below −12: the system is uniquely solvable but every tangent is reversed against the chords, so the
  curve loops at each point; as v → −∞ the loops shrink and the curve tends back to the polygon — exactly
  the sequence of thesis Figs 3.8–3.11, which the thesis misreads as "bulging inside".

### The singular band (E8)
Between −12 and −4 (here) the rows lose diagonal dominance and the system can be singular; the thesis claims
the matrix is always diagonally dominant. The engine refuses such values with a clear message:"""),
    ("code", r'''
band_errors = {}
for v in (-4.5, -8.0, -11.0):
    try:
        heart_curve(v)
        band_errors[v] = None
    except ValueError as error:
        band_errors[v] = str(error)
        print(f"v = {v}: ValueError: {error}")
'''),
    ("md", r"""
## 2. How much does v tighten? A sweep, and the scale-free ν

The raw v has the units of c = ω/h. The *relative* tension ν with vₖ = νₖ (cₖ₋₁ + cₖ) acts the same at every
scale and knot spacing (§2.5, `point_tension_scale="relative"`; the widget's default). With chord-length
knots (the default for drawing):"""),
    ("code", r'''
nus = [0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 50.0]
sweep = [deviation(sc.interpolate(heart, closed=True, point_tension=nu, point_tension_scale="relative"))
         for nu in nus]
table(["ν (relative point tension)"] + [f"{nu:g}" for nu in nus],
      [["max distance from polygon (px)"] + sweep])
plot = Plot("Chord knots, ν = 0, 2, 10, 50", width=420, height=340)
plot.line(heart, "#90a4ae", 1.2, dashed=True, closed=True)
for nu, color in zip((0.0, 2.0, 10.0, 50.0), PALETTE):
    plot.curve(sc.interpolate(heart, closed=True, point_tension=nu, point_tension_scale="relative"), color,
               label=f"ν = {nu:g}")
show(plot)
'''),
    ("md", r"""
## 3. Interval tension on one interval, and the curvature jump (E2)

Give one interval a large weight ω: it straightens towards its chord, its neighbours adjust. The joint
condition then says κ(tᵢ⁺) = (ωᵢ₋₁/ωᵢ) κ(tᵢ⁻): **the curvature jumps** at both ends of the heavy interval.
The thesis calls these joints GC² unconditionally; they are G² only where ωᵢ₋₁ = ωᵢ. The curvature comb
(teeth ∝ κ, drawn outside) shows the jump as a step."""),
    ("code", r'''
heavy = 2                                              # interval F_2 -> F_3
weights = {w: np.where(np.arange(len(heart)) == heavy, w, 1.0) for w in (1.0, 10.0, 100.0)}
local = {w: heart_curve(0.0, weights[w]) for w in weights}
plots, rows = [], []
for w, spline in local.items():
    chord = heart[[heavy, heavy + 1]]
    piece = sc.Spline(spline.bezier()[heavy:heavy + 1], spline.knots[heavy:heavy + 2])
    sag = deviation(piece, chord)
    kappa = spline.joint_curvature()                   # columns: κ(tᵢ⁻), κ(tᵢ⁺)
    ratio_in = kappa[heavy, 1] / kappa[heavy, 0]       # joint where the heavy interval starts
    ratio_out = kappa[heavy + 1, 1] / kappa[heavy + 1, 0]
    rows.append([f"ω₂ = {w:g}", sag, ratio_in, 1.0 / w, ratio_out, w])
    plots.append(Plot(f"ω₂ = {w:g} (Figs 3.7 idea, one interval)", width=330, height=300)
                 .line(heart, "#90a4ae", 1.2, dashed=True, closed=True)
                 .comb(spline).curve(spline, PALETTE[0]).dots(heart[[heavy, heavy + 1]], PALETTE[4], 40))
show(*plots)
table(["weights", "sag of interval 2 from its chord", "κ⁺/κ⁻ at F₂", "ω₁/ω₂", "κ⁺/κ⁻ at F₃", "ω₂/ω₃"], rows)
'''),
    ("md", r"""
## 4. Try it yourself

The editor below starts in the thesis's setting (uniform knots, raw v) with the curvature comb on. Select a
point and move its **v** slider, or an interval and its **ω** slider; watch the comb step at the joints of an
interval whose ω differs from its neighbours'. Values in the singular band are refused with a message and the
last good curve stays."""),
    ("code", r'''
editor = sc.SplineEditor(heart, closed=True, knots="uniform", tension_scale="absolute", show_comb=True)
display(editor.panel())
'''),
    ("code", r'''
loose = deviation(editor.spline)
editor.point_tension = [10.0] * len(heart)          # what moving the global v slider to 10 does
tight = deviation(editor.spline)
print(f"v = 0: {loose:.1f} px from the polygon;  v = 10: {tight:.1f} px")

with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    editor.point_tension = [-8.0] * len(heart)      # in the singular band: refused
print("editor says:", editor.status_message)
kept_tension = list(editor.point_tension)
'''),
    ("md", "## Check"),
    ("code", r'''
dev = {title: deviation(curves[title]) for title, _, _ in figures}
assert dev["Fig 3.5: v = 10"] < dev["Fig 3.4: ω = 1, v = 0"] / 2            # E22: v > 0 tightens
assert dev["Fig 3.6: v = 50"] < dev["Fig 3.5: v = 10"]
assert np.allclose(curves["Fig 3.7: ω = 100, v = 0"].bezier(), curves["Fig 3.4: ω = 1, v = 0"].bezier())
assert reversed_tangents(curves["Fig 3.4: ω = 1, v = 0"]) == 0
assert reversed_tangents(curves["Fig 3.8: v = −3"]) < len(heart) // 2     # safe range: only at sharp points
assert dev["Fig 3.8: v = −3"] > dev["Fig 3.4: ω = 1, v = 0"]             # ... and it bulges
for title in ("Fig 3.9: v = −15", "Fig 3.10: v = −25", "Fig 3.11: v = −50"):
    assert reversed_tangents(curves[title]) == len(heart), title             # all tangents reversed
assert dev["Fig 3.11: v = −50"] < dev["Fig 3.9: v = −15"]                  # v → −∞ tends to the polygon
assert all(message is not None for message in band_errors.values())       # E8: singular band refused
assert all(np.diff(sweep) < 0)                                            # monotone tightening in ν
assert sweep[-1] < sweep[0] / 10
sags = [row[1] for row in rows]
assert sags[2] < sags[1] < sags[0]                                        # heavy interval straightens
for _, _, ratio_in, expected_in, ratio_out, expected_out in rows:          # E2: κ⁺/κ⁻ = ω_{i−1}/ω_i
    assert np.isclose(ratio_in, expected_in, rtol=1e-6) and np.isclose(ratio_out, expected_out, rtol=1e-6)
assert tight < loose / 2
assert kept_tension == [10.0] * len(heart) and editor.status_message        # bad value refused, state kept
print("all checks passed")
'''),
]


# ----------------------------------------------------------------------------------------------------
# 03 the local-support basis
# ----------------------------------------------------------------------------------------------------
NB03 = [
    _intro(
        "03 · The local-support basis form",
        "**What you should see.** The basis form writes the curve as P(t) = Σ Bⱼ(t) Pⱼ with basis functions that "
        "sum to one, are non-negative and live on only four intervals, so dragging one control point moves at "
        "most four segments; with v = 0, ω = 1 they are exactly the cubic B-splines. Point tension pulls the "
        "curve to its control points and interval tension straightens legs (thesis Figs 3.12–3.25), while "
        "strongly negative v (below −8 with uniform knots) makes the basis negative, so the curve leaves the "
        "convex hull of its control polygon (Figs 3.26–3.38).",
        "thesis section 3.2 (eqs 3.29–3.84); §4 (errata E9–E12).",
    ),
    ("code", SETUP),
    ("md", r"""
## 1. The basis functions

`sc.basis_functions(t, n)` evaluates all Bⱼ at once (uniform knots tⱼ = j). For a closed curve with 8 control
points, and then for point tension v = 10 and v = −10 at every point:"""),
    ("code", r'''
n_control = 8
t = np.linspace(0.0, n_control, 801)
basis = {v: sc.basis_functions(t, n_control, closed=True, point_tension=v) for v in (0.0, 10.0, -10.0)}
plots = []
for v, values in basis.items():
    plot = Plot(f"closed, uniform knots, v = {v:g}", width=330, height=250, y_down=False, equal=False,
                xlabel="t", x_range=(0, n_control), y_range=(-1.1, 1.1) if v < 0 else (-0.05, 1.05))
    for j in range(n_control):
        plot.line(np.c_[t, values[:, j]], PALETTE[j % len(PALETTE)], 1.6)
    plot.line(np.c_[t, values.sum(axis=1)], "#263238", 1.5, dashed=True)
    plots.append(plot)
show(*plots)
table(["v", "min Bⱼ", "max |Σ Bⱼ − 1|"],
      [[v, float(values.min()), float(np.abs(values.sum(axis=1) - 1).max())] for v, values in basis.items()])
'''),
    ("md", r"""
With v = 0 and ω = 1 these are the uniform cubic B-splines. Compare an open (floating-end) basis with
`scipy.interpolate.BSpline.basis_element` on the same knots — an independent implementation:"""),
    ("code", r'''
from scipy.interpolate import BSpline

n_open = 10
t_open = np.linspace(1.0, n_open - 2.0, 700)            # the curve's domain [t_1, t_n]
open_basis = sc.basis_functions(t_open, n_open)
bspline_error = 0.0
for j in range(n_open):
    element = BSpline.basis_element(np.arange(j - 2, j + 3, dtype=float), extrapolate=False)
    reference = np.nan_to_num(element(t_open))
    bspline_error = max(bspline_error, float(np.abs(open_basis[:, j] - reference).max()))
print(f"max |B_j - scipy B-spline| = {bspline_error:.2e}")

# local support: B_j vanishes outside (t_{j-2}, t_{j+2})
support_violation = 0.0
for j in range(n_open):
    outside = (t_open <= j - 2) | (t_open >= j + 2)
    support_violation = max(support_violation, float(np.abs(open_basis[outside, j]).max(initial=0.0)))
print(f"largest |B_j| outside its four intervals = {support_violation:.2e}")
'''),
    ("md", r"""
## 2. Local control

Move one control point of the 'pot' (thesis Fig 3.12) and compare the Bézier pieces before and after: only the
four segments that Pⱼ supports change."""),
    ("code", r'''
pot = sc.datasets.sample_points("pot")
before = sc.basis_spline(pot)
moved = pot.copy()
moved[6] += [40.0, -60.0]
after = sc.basis_spline(moved)
changed = np.flatnonzero(np.abs(after.bezier() - before.bezier()).max(axis=(1, 2)) > 1e-9)
print(f"{before.n_segments} segments; moving P6 changed segments {changed.tolist()}")
plot = Plot("Moving P6 changes four segments", width=420, height=360)
plot.line(pot, "#90a4ae", 1.0, dashed=True).curve(before, "#90a4ae", 2)
plot.line(moved, PALETTE[1], 1.0, dashed=True).curve(after, PALETTE[0], 2.5).dots(moved[6:7], PALETTE[4], 60)
show(plot)
'''),
    ("md", r"""
## 3. Point and interval tension on the Pot and the Square (Figs 3.12–3.25)

Uniform knots as in the thesis (`basis_spline` default). Global point tension v pulls the curve to the control
points (v → ∞: the curve passes through them with a cusp); a large ω on the bottom leg makes that segment a
straight piece of the leg; point tension at chosen points (here the square's corners) sharpens only those."""),
    ("code", r'''
square = sc.datasets.sample_points("square")       # 8 control points: corners and midpoints
corners = np.array([0, 2, 4, 6])
bottom = 0                                         # leg P0 -> P1 lies on the bottom edge (y down)
def square_curve(v=0.0, w=1.0):
    return sc.basis_spline(square, closed=True, point_tension=v, interval_weights=w)
def corner_gap(spline):
    """Distance from the square's corner control points to the curve."""
    _, samples = spline.sample(samples_per_segment=64)
    return float(np.linalg.norm(samples[None] - square[corners][:, None], axis=2).min(axis=1).max())

pot_figures = [("Fig 3.12 Pot: v = 0", {}), ("Fig 3.14: v = 10", {"point_tension": 10.0}),
               ("Fig 3.15: v = 100", {"point_tension": 100.0})]
square_figures = [("Fig 3.13 Square: v = 0", square_curve()), ("Fig 3.16: v = 10", square_curve(10.0)),
                  ("Fig 3.17: v = 100", square_curve(100.0)),
                  ("Fig 3.18/3.20: ω = 10 on the bottom leg", square_curve(w=np.where(np.arange(8) == bottom, 10.0, 1.0))),
                  ("Fig 3.19/3.21: ω = 100 on the bottom leg", square_curve(w=np.where(np.arange(8) == bottom, 100.0, 1.0))),
                  ("Figs 3.22–3.25: v = 100 at the corners", square_curve(np.where(np.isin(np.arange(8), corners), 100.0, 0.0)))]
plots, pot_gaps = [], []
for title, params in pot_figures:
    spline = sc.basis_spline(pot, **params)
    _, samples = spline.sample(samples_per_segment=64)
    pot_gaps.append(float(np.linalg.norm(samples[None] - pot[1:-1, None], axis=2).min(axis=1).max()))
    plots.append(Plot(title, width=280, height=280).line(pot, "#90a4ae", 1.0, dashed=True).curve(spline).dots(pot, "#263238", 20))
for title, spline in square_figures:
    plots.append(Plot(title, width=280, height=280).line(square, "#90a4ae", 1.0, dashed=True, closed=True)
                 .curve(spline).dots(square, "#263238", 20))
show(*plots, columns=3)
table(["figure", "corner control point to curve (px)"], [[title, corner_gap(s)] for title, s in square_figures])
'''),
    ("md", r"""
## 4. Negative point tension and the convex hull (Figs 3.26–3.38)

The basis is non-negative — and so every curve point is a convex combination of control points — as long as
dᵢ = aᵢ₋₁ + aᵢ + ½aᵢ₋₁aᵢvᵢ > 0, i.e. v > −2(ωᵢ₋₁/hᵢ₋₁ + ωᵢ/hᵢ) = −4 here; numerically the uniform basis stays
≥ 0 down to v = −8, and is negative below (§4.5). At v = −4 exactly the closed forms are 0/0 and the
engine refuses. Below −8 the square's curve leaves the convex hull of its control polygon."""),
    ("code", r'''
from scipy.spatial import Delaunay

hull = Delaunay(square)
negative_rows, outside, negative_curves = [], {}, {}
for v in (-3.0, -4.0, -5.0, -8.0, -10.0, -20.0, -25.0, -50.0):
    try:
        spline = square_curve(v)
    except ValueError as error:
        negative_rows.append([v, "refused", "—", str(error)[:70] + "…"])
        continue
    negative_curves[v] = spline
    minimum = float(sc.basis_functions(np.linspace(0, 8, 801), 8, closed=True, point_tension=v).min())
    _, samples = spline.sample(samples_per_segment=64)
    outside[v] = int((hull.find_simplex(samples, tol=1e-9) < 0).sum())
    negative_rows.append([v, minimum, outside[v], ""])
table(["v", "min Bⱼ", "curve samples outside the hull", "note"], negative_rows)
show(*[Plot(f"v = {v:g}", width=250, height=250).line(square, "#90a4ae", 1.0, dashed=True, closed=True)
        .curve(s, PALETTE[0] if outside[v] == 0 else PALETTE[4]) for v, s in negative_curves.items()], columns=4)
'''),
    ("md", r"""
## 5. Try it yourself

The editor in basis form, with the live basis-function plot: select a control point (its Bⱼ is drawn thick) and
move its **v**; select a leg and move its **ω**. The dashed line Σ Bⱼ = 1 never moves."""),
    ("code", r'''
editor = sc.SplineEditor(pot, form="basis", knots="uniform", tension_scale="absolute", show_control_polygon=True)
display(editor.panel())
'''),
    ("code", r'''
editor.selected = 6
editor.point_tension = [0.0] * 6 + [50.0] + [0.0] * (len(pot) - 7)   # v = 50 at P6 only
_, samples = editor.spline.sample(samples_per_segment=64)
editor_gap = float(np.linalg.norm(samples - pot[6], axis=1).min())
print(f"with v6 = 50 the curve passes {editor_gap:.1f} px from P6")
'''),
    ("md", "## Check"),
    ("code", r'''
for v, values in basis.items():
    assert np.allclose(values.sum(axis=1), 1.0, atol=1e-12)               # partition of unity
assert basis[0.0].min() > -1e-12 and basis[10.0].min() > -1e-12           # non-negative for v ≥ 0
assert basis[-10.0].min() < -0.5                                          # negative lobes below −8
assert bspline_error < 1e-12 and support_violation < 1e-12               # = cubic B-splines, local support
assert 0 < len(changed) <= 4 and np.all(np.diff(changed) == 1)            # local control
assert pot_gaps[2] < pot_gaps[1] < pot_gaps[0]                            # v pulls to the control points
gaps = [corner_gap(s) for _, s in square_figures]
assert gaps[2] < gaps[1] < gaps[0] and gaps[5] < gaps[0] / 3
assert any(row[1] == "refused" for row in negative_rows if row[0] == -4.0)  # D_i = 0 at v = −4
for v in (-3.0, -5.0):
    assert outside[v] == 0                                                # convex hull kept
assert any(outside[v] > 0 for v in (-10.0, -20.0, -25.0, -50.0))          # and lost below −8
assert editor_gap < 5.0
print("all checks passed")
'''),
]


# ----------------------------------------------------------------------------------------------------
# 04 Timmer curves
# ----------------------------------------------------------------------------------------------------
NB04 = [
    _intro(
        "04 · Timmer curves: G² by iteration, GC¹ and GC² with shape control",
        "**What you should see.** Algorithm 3.1 chooses one α per piece so that the curvature is continuous — "
        "but at some joints the quadratic for α has no positive root, and those joints stay G¹ (the engine flags "
        "them and reports the jump); Algorithm 3.2 keeps unit tangents and lets α, β shape each piece "
        "(Figs 3.39–3.45: small α loops, large α hugs the polygon). Algorithm 3.3 solves one banded system and is "
        "C² only where αᵢ = βᵢ₋₁ (erratum **E20**: elsewhere κ jumps by (αᵢ/βᵢ₋₁)²), while the corrected "
        "true-G² joint keeps the curvature continuous for any α, β.",
        "thesis section 3.3 (eqs 3.85–3.133, Algorithms 3.1–3.3); §5, §6 (errata E13–E20).",
    ),
    ("code", SETUP),
    ("md", r"""
## 1. Timmer's blending functions (Figs 3.1–3.3)

f₀ = (1−2θ)(1−θ)², f₁ = 4θ(1−θ)², f₂ = 4θ²(1−θ), f₃ = (2θ−1)θ² (eqs 3.85–3.88; E13: the last is f₃). They sum to 1,
but f₀ and f₃ are negative on part of [0, 1]: no convex-hull property."""),
    ("code", r'''
from splinecraft.spline.timmer import timmer_blending_functions

theta = np.linspace(0.0, 1.0, 301)
f = timmer_blending_functions(theta)
plot = Plot("Timmer blending functions", width=420, height=260, y_down=False, equal=False, xlabel="θ",
            x_range=(0, 1), y_range=(-0.1, 1.05))
for j in range(4):
    plot.line(np.c_[theta, f[:, j]], PALETTE[j], label=f"f{j}")
plot.line(np.c_[theta, f.sum(axis=1)], "#263238", 1.5, dashed=True)
show(plot)
print(f"min f0 = {f[:, 0].min():.5f} at θ = {theta[f[:, 0].argmin()]:.3f}   (−1/27 = {-1/27:.5f} at 2/3)")
'''),
    ("md", r"""
## 2. Algorithm 3.1: G² joint by joint

Unit tangents from eqs 3.106–3.109, α₀ = 4/‖P₁ − P₀‖, then at each joint the α of the next piece solves
⅜Sα² − ½Cα − K* = 0 so that its start curvature matches the previous piece's end curvature (E18 fixes the sign
under the root). When there is **no positive root** the engine takes the best α (the vertex of the parabola),
marks the joint `g1_no_root` and reports the curvature jump — the thesis does not mention this case, which is
common. On 14 points of an ellipse (closed: the last joint, back at P₀, depends on α₀ alone; the engine
searches α₀ for it and reports `g1_closing` when no α₀ closes it G²):"""),
    ("code", r'''
angles = np.linspace(0.0, 2 * np.pi, 14, endpoint=False) + 0.1
ellipse = np.c_[310 + 230 * np.cos(angles), 220 + 120 * np.sin(angles)]
g2 = sc.timmer_g2(ellipse, closed=True)
status = g2.info["joint_status"][: len(ellipse)]
jumps = np.array([np.nan if j is None else j for j in g2.info["curvature_jump"][: len(ellipse)]], float)
kappa = g2.joint_curvature()[: len(ellipse)]
table(["joint", "status", "κ⁻", "κ⁺", "jump"],
      [[i, status[i], kappa[i, 0], kappa[i, 1], jumps[i]] for i in range(len(ellipse))])
no_root = [i for i, s in enumerate(status) if s != "g2"]
plot = Plot(f"Alg 3.1 on an ellipse: {len(no_root)} of {len(ellipse)} joints only G¹ (red)", width=520, height=340)
plot.comb(g2).curve(g2).dots(ellipse, "#263238", 24).dots(ellipse[no_root], PALETTE[4], 60)
show(plot)
'''),
    ("md", r"""
## 3. Algorithm 3.2: GC¹ with shape control (Figs 3.39–3.45)

Unit tangents, and per piece the tangent scales α, β: the Timmer polygon points are Q₁ = Pᵢ + Tᵢ/αᵢ and
Q₂ = Pᵢ₊₁ − Tᵢ₊₁/βᵢ, so the end speed is 4/α. The thesis's values α = 1 … 20 refer to coordinates of a few units;
we scale the heart to that size. Fig 3.44 raises α = β to 15 on the base pieces only."""),
    ("code", r'''
heart = sc.datasets.sample_points("heart") / 40.0             # a few units across, like the thesis
base = [5, 6]                                                # the two pieces around the heart's tip
gc1_figures = [(f"Fig 3.{39 + k}: α = β = {a:g}", sc.timmer_gc1(heart, closed=True, alpha=a))
               for k, a in enumerate((1.0, 2.0, 3.0, 4.0, 20.0))]
local_alpha = np.where(np.isin(np.arange(len(heart)), base), 15.0, 1.0)
gc1_figures.append(("Fig 3.44: α = β = 15 on the base, 1 elsewhere", sc.timmer_gc1(heart, closed=True, alpha=local_alpha)))
plots, gc1_rows = [], []
for title, spline in gc1_figures:
    plots.append(Plot(title, width=280, height=270).line(heart, "#90a4ae", 1.0, dashed=True, closed=True)
                 .curve(spline).dots(heart, "#263238", 18))
    _, samples = spline.sample(samples_per_segment=48)
    gc1_rows.append([title, float(distance_to_polyline(samples, heart, closed=True).max()),
                     ", ".join(sorted(set(spline.info["joint_status"])))])
show(*plots, columns=3)
table(["figure", "max distance from the polygon", "joint statuses"], gc1_rows)
'''),
    ("md", r"""
With α = β everywhere the joints are C¹ (`c1`); where the scales differ (Fig 3.44) the tangent *direction* is
still continuous but the speed is not (`g1`). **Negative α (Fig 3.45, α = β = −10).** The engine requires α, β > 0
(§5.5). A negative α is the same as a positive one with reversed tangents, Q₁ = Pᵢ + (−Tᵢ)/|α|, which is what
the thesis's loops show (Fig 3.45 with α = −10: small loops at every point; at α = −2 they are large):"""),
    ("code", r'''
try:
    sc.timmer_gc1(heart, closed=True, alpha=-10.0)
    negative_refused = False
except ValueError as error:
    negative_refused = True
    print("ValueError:", error)
unit = sc.estimate_tangents(heart, closed=True)
unit /= np.linalg.norm(unit, axis=1, keepdims=True)
reversed_curves = {a: sc.timmer_gc1(heart, closed=True, alpha=a, tangents=-unit) for a in (10.0, 2.0)}
show(*[Plot(f"α = β = −{a:g} ≡ α = {a:g}, tangents reversed", width=380, height=340)
       .line(heart, "#90a4ae", 1.0, dashed=True, closed=True).curve(s).dots(heart, "#263238", 18)
       for a, s in reversed_curves.items()], columns=2)
loop_size = {a: deviation_from_polygon for a, deviation_from_polygon in
             ((a, float(distance_to_polyline(s.sample(samples_per_segment=48)[1], heart, closed=True).max()))
              for a, s in reversed_curves.items())}
print("largest distance from the polygon (size of the loops):", {f"α = −{a:g}": round(d, 3) for a, d in loop_size.items()})
'''),
    ("md", r"""
## 4. Algorithm 3.3: one banded system — "GC²" and the true G² joint

The tangents Tᵢ now solve one tridiagonal system (eqs 3.126–3.130). With all α = β equal the result is the
uniform-knot C² cubic spline (compare with `scipy.interpolate.CubicSpline`). With different α, β the thesis joint
H″ᵢ₋₁(1) = H″ᵢ(0) is not G²: the curvature jumps by (αᵢ/βᵢ₋₁)² (E20). The corrected joint
H″ᵢ(0) = (βᵢ₋₁/αᵢ)² H″ᵢ₋₁(1) is G² for any α, β (`joint="g2"`)."""),
    ("code", r'''
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
rows = []
for i in range(1, len(zigzag) - 1):
    rows.append([i, k_thesis[i, 1] / k_thesis[i, 0], (alpha[i] / alpha[i - 1]) ** 2, k_g2[i, 1] / k_g2[i, 0]])
table(["joint", "thesis joint κ⁺/κ⁻", "(αᵢ/βᵢ₋₁)²", "G² joint κ⁺/κ⁻"], rows)
show(Plot("Alg 3.3, thesis joint: curvature steps", width=420, height=300).comb(thesis_joint)
     .curve(thesis_joint).dots(zigzag, "#263238", 22),
     Plot("Alg 3.3, true G² joint: no steps", width=420, height=300).comb(g2_joint)
     .curve(g2_joint).dots(zigzag, "#263238", 22), columns=2)
'''),
    ("md", r"""
## 5. Try it yourself

The editor in Timmer G² form with the curvature comb: drag a point and watch which joints lose their root (the
status line lists them). Switch the form to GC¹ or GC² and move α, β; for GC² switch the joint to *true G²*."""),
    ("code", r'''
editor = sc.SplineEditor(sc.datasets.sample_points("zigzag"), form="timmer_g2", show_comb=True)
display(editor.panel())
'''),
    ("code", r'''
print("G² form, joint statuses:", editor.spline.info["joint_status"])
editor.form = "timmer_gc2"
editor.end_condition = "g2"          # the joint dropdown
editor.alpha, editor.beta = 3.0, 6.0
editor.fit_view()                    # the "Fit" button
editor_jumps = [j for j in editor.spline.info["curvature_jump"] if j is not None]
print("GC² form, true G² joint, α = 3, β = 6: largest curvature jump", max(abs(j) for j in editor_jumps))
'''),
    ("md", "## Check"),
    ("code", r'''
assert np.allclose(f.sum(axis=1), 1.0) and abs(f[:, 0].min() + 1 / 27) < 1e-5
for i, s in enumerate(status):
    if s == "g2":
        assert abs(kappa[i, 1] - kappa[i, 0]) <= 1e-9 * np.abs(kappa).max()   # root found: G²
    else:
        assert s in ("g1_no_root", "g1_closing") and abs(jumps[i]) > 0         # flagged, jump reported
assert "g1_no_root" in status                                                  # the thesis's silent case
distances = [row[1] for row in gc1_rows[:5]]
assert distances[-1] < distances[0]                            # large α hugs the polygon
assert set(gc1_figures[0][1].info["joint_status"]) == {"c1"}
assert "g1" in gc1_figures[5][1].info["joint_status"]
assert negative_refused and loop_size[2.0] > loop_size[10.0] > 0
assert cubic_spline_error < 1e-9                               # constant α: the uniform C² cubic spline
for i, ratio_thesis, expected, ratio_g2 in rows:
    assert np.isclose(ratio_thesis, expected, rtol=1e-8)       # E20
    assert np.isclose(ratio_g2, 1.0, rtol=1e-8)                # true G²
assert max(abs(j) for j in editor_jumps) < 1e-9
print("all checks passed")
'''),
]


NOTEBOOKS = {
    "01_generic_cubic": NB01,
    "02_tension": NB02,
    "03_basis": NB03,
    "04_timmer": NB04,
}


# ----------------------------------------------------------------------------------------------------
# 05 corner detectors
# ----------------------------------------------------------------------------------------------------
NB05 = [
    _intro(
        "05 · Corner detectors compared (thesis chapter 2)",
        "**What you should see.** Outline capture cuts every contour at its corners and fits each piece "
        "separately, so a missed corner gets rounded off and a false corner puts a kink into a smooth arc. "
        "You should see how the thesis's three-phase slope detector SRM05 (ZCT = 7, DT = 5, TA = 152°) and "
        "the classic detectors it is compared with — Rosenfeld–Johnston, Rosenfeld–Weszka, Freeman–Davis, "
        "Beus–Tiu, IPAN99, Teh–Chin — score on shapes whose corners are known exactly, what they find on the "
        "five thesis-like objects, and how ZCT, DT and TA trade missed corners against false ones.",
        "thesis sections 2.1–2.4, 4.1.2 (eqs 2.1–2.5); §6 (E21 fixes the angle of the TA test).",
    ),
    ("code", SETUP),
    ("md", r"""
## 1. Contours and ground truth

`sc.trace_boundaries(mask)` follows the crack (pixel-edge) outline of every component and hole; the corner
detectors work on `Boundary.outline` (edge midpoints). `sc.datasets.shape_corners` gives the exact corners of
the teaching shapes and of the letter 'D' (its serifs and stem): a square (4), a star (10: 5 tips, 5 reflex),
three smooth shapes (none) and the D (8)."""),
    ("code", r'''
import inspect
import time

SIZE = 160
truth_shapes = ["square", "star", "disc", "ellipse", "blob", "D"]
masks = {name: (sc.datasets.thesis_object(name, SIZE) if name == "D" else sc.datasets.shape(name, SIZE))
         for name in truth_shapes}
outlines = {name: [b.outline for b in sc.trace_boundaries(mask)] for name, mask in masks.items()}
truth = {name: sc.datasets.shape_corners(name, SIZE) for name in truth_shapes}
methods = list(sc.CORNER_METHODS)
print("detectors:", ", ".join(methods))
print("contour points:", {name: sum(len(o) for o in outs) for name, outs in outlines.items()})

def detect(method, contours, **params):
    """Corner points (x, y) found by ``method`` on a list of closed contours, and the time taken."""
    start = time.perf_counter()
    found = [contour[sc.corners(contour, method=method, **params)] for contour in contours]
    return np.vstack(found) if found else np.zeros((0, 2)), time.perf_counter() - start

def match(found, expected, tolerance=2.0):
    """True positives: one-to-one matches within ``tolerance`` px (closest pairs first)."""
    if len(found) == 0 or len(expected) == 0:
        return 0
    distance = np.linalg.norm(found[:, None] - expected[None], axis=2)
    pairs = sorted(zip(*np.nonzero(distance <= tolerance)), key=lambda ij: distance[ij])
    used_found, used_expected = set(), set()
    for i, j in pairs:
        if i not in used_found and j not in used_expected:
            used_found.add(i)
            used_expected.add(j)
    return len(used_found)
'''),
    ("md", r"""
## 2. Precision, recall and F1 against the exact corners

A detected corner counts as correct when it lies within 2 px of a true corner (each true corner matched once).
Watch the smooth shapes: a digitized circle is a staircase whose step pattern changes at regular places, and
detectors that look at the chain code too locally report corners there."""),
    ("code", r'''
scores, rows = {}, []
for method in methods:
    found_total = expected_total = correct = 0
    seconds = 0.0
    counts = []
    for name in truth_shapes:
        found, elapsed = detect(method, outlines[name])
        seconds += elapsed
        tp = match(found, truth[name])
        found_total, expected_total, correct = found_total + len(found), expected_total + len(truth[name]), correct + tp
        counts.append(f"{len(found)}")
    precision = correct / found_total if found_total else 1.0
    recall = correct / expected_total
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    scores[method] = {"precision": precision, "recall": recall, "f1": f1}
    rows.append([method] + counts + [precision, recall, f1, 1000 * seconds])
expected_counts = [str(len(truth[name])) for name in truth_shapes]
table(["detector"] + [f"{n} ({c})" for n, c in zip(truth_shapes, expected_counts)]
      + ["precision", "recall", "F1", "time (ms)"], rows, digits=3)
'''),
    ("md", r"""
## 3. The five thesis-like objects

The thesis reports 33 corners on its scan of 'Ali' and 41 on the multi-part plane. Our objects are drawn, not
scanned, so the numbers differ; what matters is *where* the corners land. Grey: the crack outline; dots: the
corners of SRM05 (orange) and of the detector `sc.trace` uses by default (blue)."""),
    ("code", r'''
# the detector sc.trace uses when none is given (resolved by a tiny trace)
capture_default = sc.trace(sc.datasets.shape("square", 48), keep_snapshots=False).params["corner_method"]
print("sc.trace's default corner detector:", capture_default)
objects = {name: sc.datasets.thesis_object(name) for name in sc.datasets.THESIS_OBJECTS}
object_contours = {name: [b.outline for b in sc.trace_boundaries(mask)] for name, mask in objects.items()}
count_rows, plots = [], []
for name, contours in object_contours.items():
    row = [sc.datasets.THESIS_TITLES[name], sum(len(c) for c in contours)]
    for method in methods:
        row.append(len(detect(method, contours)[0]))
    count_rows.append(row)
    plot = Plot(f"{name}: SRM05 (orange), {capture_default} (blue)", width=380, height=330)
    for contour in contours:
        plot.line(contour, "#9e9e9e", 1.0, closed=True)
    plot.dots(detect("srm05", contours)[0], PALETTE[1], 36)
    plot.dots(detect(capture_default, contours)[0], PALETTE[0], 16)
    plots.append(plot)
table(["object", "contour points"] + methods, count_rows)
show(*plots, columns=3)
'''),
    ("md", r"""
## 4. Tuning SRM05: ZCT, DT and TA

* **ZCT** (zero-crossing threshold): how many equal slope states in a row count as a straight run — small
  values see corners in every pixel step, large values merge nearby corners.
* **DT** (distance threshold): corners closer than DT are merged into one.
* **TA** (angle threshold, 152° in the thesis): a candidate whose interior angle is above TA is too flat to be a
  corner (E21: the printed formula measures the supplementary angle).

Each sweep varies one parameter with the others at the thesis's defaults, scored on the shapes of section 2."""),
    ("code", r'''
srm05_defaults = {name: p.default for name, p in inspect.signature(sc.CORNER_METHODS["srm05"]).parameters.items()
                  if name in ("zct", "dt", "ta")}
print("SRM05 defaults:", srm05_defaults)
sweeps = {"zct": [2, 3, 5, 7, 9, 12, 15], "dt": [1, 2, 3, 5, 8, 12], "ta": [120, 135, 145, 152, 160, 170]}

def f1_score(**params):
    found_total = expected_total = correct = 0
    for name in truth_shapes:
        found, _ = detect("srm05", outlines[name], **params)
        found_total += len(found)
        expected_total += len(truth[name])
        correct += match(found, truth[name])
    precision = correct / found_total if found_total else 1.0
    recall = correct / expected_total
    return (2 * precision * recall / (precision + recall) if precision + recall else 0.0), found_total

sweep_results, plots = {}, []
for parameter, values in sweeps.items():
    results = [f1_score(**{parameter: value}) for value in values]
    sweep_results[parameter] = results
    plot = Plot(f"SRM05: F1 vs {parameter.upper()}", width=300, height=240, y_down=False, equal=False,
                xlabel=parameter.upper(), y_range=(0, 1.05))
    plot.line(np.c_[values, [r[0] for r in results]], PALETTE[0]).dots(np.c_[values, [r[0] for r in results]], PALETTE[0])
    plots.append(plot)
show(*plots)
table(["parameter", "values", "F1", "corners found (of 26 true)"],
      [[p, str(sweeps[p]), ", ".join(f"{r[0]:.2f}" for r in sweep_results[p]),
        ", ".join(str(r[1]) for r in sweep_results[p])] for p in sweeps])
'''),
    ("md", r"""
## 5. Try it yourself

The TraceExplorer shows the bitmap, its boundaries and the corners; pick a detector in the dropdown and move its
sliders (for SRM05: ZCT, DT, TA) — the corners and the fitted outline update."""),
    ("code", r'''
explorer = sc.TraceExplorer(sc.datasets.thesis_object("D"), corner_method="srm05", epsilon=1.0)
display(explorer.panel())
'''),
    ("code", r'''
corners_default = sum(len(c) for c in explorer.result.corners)
explorer.corner_params = {"zct": 3, "dt": 5, "ta": 152}      # what the ZCT slider does
corners_small_zct = sum(len(c) for c in explorer.result.corners)
print(f"SRM05 on the D: {corners_default} corners with ZCT = 7, {corners_small_zct} with ZCT = 3")
'''),
    ("md", "## Check"),
    ("code", r'''
assert set(scores) == set(sc.CORNER_METHODS)
for method in methods:                                     # every detector returns valid, sorted indices
    for contour in outlines["star"]:
        found = sc.corners(contour, method=method)
        assert np.all(np.diff(found) > 0) and (len(found) == 0 or (found.min() >= 0 and found.max() < len(contour)))
for method in ("srm05", capture_default):
    assert scores[method]["recall"] >= 0.9, (method, scores[method])   # the tips and serif corners are found
assert scores[capture_default]["f1"] >= 0.9, scores[capture_default]
false_on_smooth = sum(len(detect(capture_default, outlines[name])[0]) for name in ("disc", "ellipse", "blob"))
assert false_on_smooth <= 1                                         # smooth arcs: (almost) no corners
assert sum(len(detect("srm05", outlines[name])[0]) for name in ("disc", "ellipse", "blob")) > false_on_smooth
assert corners_default > 0 and corners_small_zct >= corners_default
print("all checks passed")
'''),
]


# ----------------------------------------------------------------------------------------------------
# 06 outline capture
# ----------------------------------------------------------------------------------------------------
NB06 = [
    _intro(
        "06 · Outline capture: stepping through knot insertion (thesis chapter 4)",
        "**What you should see.** `sc.trace` turns a bitmap into a few smooth closed splines: it follows the "
        "crack outline of every component and hole, cuts it at the corners, fits one spline piece per "
        "corner-to-corner stretch and inserts knots until every piece is within ε of the contour. Stepping "
        "through the iterations with the TraceExplorer you should see how each algorithm of thesis section 4.3 picks its "
        "candidate knots (accepted or rejected, and why), that the randomized algorithms need many more knots "
        "and iterations than the team's deterministic default for the same ε, and the thesis's tables "
        "(contour points, corners, knots inserted, iterations, time, % data reduction) recomputed.",
        "thesis section 4.1–4.4, Algorithms 4.1–4.6, Figs 4.1–4.89, Tables 4.1–4.61.",
    ),
    ("code", SETUP),
    ("md", r"""
## 1. The five objects

Like the thesis's scans — the Arabic word 'Ali' (علي), an apple, a plane, the letter 'D' and a plane made of
several parts — but drawn by `sc.datasets` from exact shapes, so their true outline is known too."""),
    ("code", r'''
import io
from PIL import Image

def png(mask, height=150):
    image = Image.fromarray(np.where(mask, 30, 255).astype(np.uint8))
    image = image.resize((max(1, round(mask.shape[1] * height / mask.shape[0])), height), Image.NEAREST)
    buffer = io.BytesIO()
    image.save(buffer, format="PNG")
    return ipw.Image(value=buffer.getvalue(), format="png")

objects = {name: sc.datasets.thesis_object(name) for name in sc.datasets.THESIS_OBJECTS}
display(ipw.HBox([ipw.VBox([png(mask), ipw.Label(sc.datasets.THESIS_TITLES[name])]) for name, mask in objects.items()]))
'''),
    ("md", r"""
## 2. The pipeline on 'Ali', step by step

Boundaries (outer contours and holes, Freeman chain codes), corners, the initial fit (corners only) and the
final fit. `result.snapshots` keeps every iteration; `result.stats` has the columns of the thesis's tables."""),
    ("code", r'''
default_method = sc.trace(sc.datasets.shape("disc", 48), keep_snapshots=False).params["method"]
for name, text in sc.KNOT_METHODS.items():
    print(f"{name:11s} {text}")
print("default:", default_method)

ali = sc.trace(objects["ali"], epsilon=2.0, method="random", seed=0)
print(f"{len(ali.boundaries)} boundaries ({ali.stats['holes']} holes), chain codes of the first:",
      "".join(map(str, ali.boundaries[0].chain_code[:40])), "...")
columns = ["contour_points", "corners", "knots_inserted", "iterations", "time_s", "segments",
           "data_reduction_pct_thesis", "max_error", "hausdorff", "converged"]
table(columns, [[ali.stats[key] for key in columns]])

def outline_plot(result, snapshot, title, width=420, height=290):
    plot = Plot(title, width=width, height=height)
    for contour in result.points:
        plot.line(contour, "#bdbdbd", 1.0, closed=True)
    for points, corner_index in zip(result.points, result.corners):
        plot.dots(points[corner_index], PALETTE[1], 22)
    bezier = snapshot.bezier
    theta = np.linspace(0, 1, 12)[:, None]
    weights = np.hstack([(1 - theta) ** 3, 3 * (1 - theta) ** 2 * theta, 3 * (1 - theta) * theta ** 2, theta ** 3])
    plot.polylines(np.einsum("kj,mjd->mkd", weights, bezier), PALETTE[0], 1.8)
    plot.dots(bezier[:, 0], "#263238", 10)
    return plot

last = len(ali.snapshots) - 1
picks = [0, 1, min(10, last), min(20, last), last]
show(*[outline_plot(ali, ali.snapshots[i], f"Alg 4.1, ε = 2: iteration {i} ({ali.snapshots[i].knots} knots)",
                    width=380, height=270) for i in dict.fromkeys(picks)], columns=3)
'''),
    ("md", r"""
These are the thesis's Figs 4.12–4.14 for our 'Ali': at iteration 0 the pieces join corner to corner and cut
across the letters; every iteration inserts knots where pieces are still farther than ε from the contour.

## 3. Step through it yourself

The TraceExplorer below starts with Alg 4.6 (fuzzy) on 'Ali'. Use ◀ ▶ (or play) to step through the
iterations: accepted candidates are drawn green, rejected ones red, with the reason in the side panel; the plot
under it shows knots and maximum error per iteration. Change the algorithm, ε, τ or the seed and compare."""),
    ("code", r'''
explorer = sc.TraceExplorer(objects["ali"], method="fuzzy", epsilon=2.0, seed=0)
display(explorer.panel())
'''),
    ("code", r'''
explorer.go_to(0)
start_info = dict(explorer.iteration_info)
explorer.step(1)
explorer.step(1)
print("iteration 2:", {k: explorer.iteration_info[k] for k in list(explorer.iteration_info)[:8]})
explorer.go_to(explorer.n_snapshots - 1)
final_info = dict(explorer.iteration_info)
explorer.method = default_method             # what the algorithm dropdown does
print(f"{default_method}: {explorer.n_snapshots - 1} iterations, "
      f"{explorer.result.stats['knots_inserted']} knots inserted (fuzzy: see the table below)")
'''),
    ("md", r"""
## 4. The thesis's tables, recomputed (one object)

All algorithms at ε = 1, 2, 3 on the apple (seed 0; the randomized ones vary with the seed — the benchmark
`benchmarks/thesis_tables.py` averages seeds over all five objects, see `BENCHMARKS.md`). % reduction is
the thesis's definition, 100 (1 − knots inserted / contour points) (Table 4.61)."""),
    ("code", r'''
apple = objects["apple"]
THESIS_METHODS = ("random", "euclidean", "positional", "random3", "equal3", "fuzzy")
methods = [m for m in THESIS_METHODS if m in sc.KNOT_METHODS]
methods += [m for m in sc.KNOT_METHODS if m not in methods]
runs, rows = {}, []
for method in methods:
    for epsilon in (1.0, 2.0, 3.0):
        result = sc.trace(apple, epsilon=epsilon, method=method, seed=0, keep_snapshots=True)
        runs[(method, epsilon)] = result
        s = result.stats
        rows.append([method, epsilon, s["contour_points"], s["corners"], s["knots_inserted"], s["iterations"],
                     round(1000 * s["time_s"], 1), s["segments"], round(s["hausdorff"], 2),
                     round(s["data_reduction_pct_thesis"], 2)])
table(["algorithm", "ε", "contour points", "corners", "knots inserted", "iterations", "time (ms)",
       "segments", "max dev. (px)", "% reduction"], rows)

plots = []
for key, label in (("knots", "knots"), ("error", "max error (px)")):
    plot = Plot(f"apple, ε = 2: {label} per iteration", width=430, height=260, y_down=False, equal=False,
                xlabel="iteration", log_y=(key == "error"))
    for method, color in zip(methods, PALETTE):
        snapshots = runs[(method, 2.0)].snapshots
        values = [s.knots if key == "knots" else s.max_error for s in snapshots]
        plot.line(np.c_[np.arange(len(values)), values], color, 1.8, label=method)
    plots.append(plot)
show(*plots, columns=2)
unconverged = [key for key, result in runs.items() if not result.stats["converged"]]
print("runs that hit the 200-iteration cap before reaching ε:", unconverged or "none")
'''),
    ("md", r"""
What to read from the table:

* The randomized algorithms pick candidate knots blindly. With the thesis's own stopping rule (stop as soon as
  the random candidates happen to lie within ε) they stop early but guarantee nothing; with an honest rule
  (every piece within ε of its contour, which `sc.trace` enforces) they need many iterations at ε = 1 and may
  hit the iteration cap: the last bad spots are rarely drawn.
* The team's default (`lsq`, deterministic) fits all contour points of a piece by least squares, starts with
  knots where the contour's curvature calls for them, inserts a knot where the fit is worst and, once within ε,
  removes knots that are not needed (so its knot count can drop in the last snapshots, phase "remove"): fewer
  knots, far fewer iterations, the same ε.
* The thesis's "% reduction" counts only inserted knots against contour points, so it is high for every
  algorithm; the number of Bézier segments is the honest size of the result (see also notebook 07)."""),
    ("md", "## Check"),
    ("code", r'''
for (method, epsilon), result in runs.items():
    knots = [s.knots for s in result.snapshots]
    if method in THESIS_METHODS:
        assert all(np.diff(knots) >= 0), (method, epsilon)                  # thesis: knots only grow
    final = result.snapshots[-1]
    assert np.allclose(final.bezier, np.concatenate([s.bezier() for s in result.splines]))  # last = result
    if result.stats["converged"]:
        assert result.stats["hausdorff"] <= epsilon + 0.5 + 1e-9, (method, epsilon)       # issue's rule
    else:
        assert result.stats["iterations"] == 200 and method != default_method   # only the cap stops it
for epsilon in (1.0, 2.0, 3.0):                                           # the default beats Alg 4.6
    if "fuzzy" in sc.KNOT_METHODS:
        assert runs[(default_method, epsilon)].stats["knots_inserted"] < runs[("fuzzy", epsilon)].stats["knots_inserted"]
assert start_info != final_info and explorer.n_snapshots >= 1
print("all checks passed")
'''),
]


# ----------------------------------------------------------------------------------------------------
# 07 potrace
# ----------------------------------------------------------------------------------------------------
NB07 = [
    _intro(
        "07 · Side by side with potrace",
        "**What you should see.** potrace is the standard open-source bitmap tracer; here it and splinecraft "
        "trace the same five bitmaps, and you should see how many Bézier segments each needs, how far each "
        "result strays from the true outline of the shape (known exactly for these drawn objects), and how long "
        "each takes. If potrace is not installed, this notebook tells you how to install it "
        "(`bash scripts/system-deps.sh potrace`) and skips the comparison.",
        "The full comparison with timings over repeated runs is `benchmarks/thesis_tables.py` (see "
        "`BENCHMARKS.md`).",
    ),
    ("code", SETUP),
    ("code", r'''
import shutil
import subprocess
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from PIL import Image
from scipy.spatial import cKDTree
from splinecraft.capture.svg import parse_path_data

POTRACE = shutil.which("potrace")
if POTRACE is None:
    display(Markdown("**potrace is not installed**, so the comparison below is skipped. Install Debian's "
                     "package with `bash scripts/system-deps.sh potrace` (it runs `apt-get install potrace`), "
                     "then restart the kernel and run the notebook again."))
else:
    print(subprocess.run([POTRACE, "--version"], capture_output=True, text=True).stdout.splitlines()[0])
'''),
    ("md", r"""
## 1. Measuring both the same way

potrace writes an SVG whose path is in units of 0.1 px with y pointing up; we undo its transform so both
results live in the bitmap's pixel frame. Both are then sampled densely on their exact cubic pieces and compared
with the object's exact outline (`sc.datasets.true_outline`): the deviation is the symmetric Hausdorff
distance, the largest distance from either curve to the other."""),
    ("code", r'''
def potrace_beziers(mask):
    """Trace a bool mask with the potrace CLI at its defaults: list of (m, 4, 2) Bézier arrays, seconds."""
    with tempfile.TemporaryDirectory() as folder:
        source, target = Path(folder) / "in.pbm", Path(folder) / "out.svg"
        Image.fromarray(~mask).convert("1").save(source)            # PBM: black = ink
        start = time.perf_counter()
        subprocess.run([POTRACE, "-s", "-o", str(target), str(source)], check=True, capture_output=True)
        seconds = time.perf_counter() - start
        root = ET.fromstring(target.read_text())
    pieces = []
    for group in root.iter("{http://www.w3.org/2000/svg}g"):
        numbers = [float(v) for v in group.get("transform").replace("translate(", " ").replace("scale(", " ")
                   .replace(")", " ").replace(",", " ").split()]
        offset, scale = np.array(numbers[:2]), np.array(numbers[2:4])
        for path in group.iter("{http://www.w3.org/2000/svg}path"):
            pieces += [bezier * scale + offset for bezier, _ in parse_path_data(path.get("d"))]
    return pieces, seconds

def dense(bezier, spacing=0.05):
    theta = np.linspace(0, 1, int(np.ceil(np.linalg.norm(np.diff(bezier, axis=1), axis=2).sum(1).max() / spacing)) + 2)[:, None]
    weights = np.hstack([(1 - theta) ** 3, 3 * (1 - theta) ** 2 * theta, 3 * (1 - theta) * theta ** 2, theta ** 3])
    return np.einsum("kj,mjd->mkd", weights, bezier).reshape(-1, 2)

def reference_points(name, spacing=0.05):
    points = []
    for outline in sc.datasets.true_outline(name):
        ring = np.vstack([outline, outline[:1]])
        steps = np.maximum(1, np.ceil(np.linalg.norm(np.diff(ring, axis=0), axis=1) / spacing).astype(int))
        for a, b, k in zip(ring[:-1], ring[1:], steps):
            points.append(a + np.arange(k)[:, None] / k * (b - a))
    return np.vstack(points)

def hausdorff(a, b):
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))
'''),
    ("md", "## 2. The comparison"),
    ("code", r'''
EPSILON = 1.0
comparison = {}
if POTRACE is not None:
    rows = []
    for name in sc.datasets.THESIS_OBJECTS:
        mask = sc.datasets.thesis_object(name)
        reference = reference_points(name)
        pieces, potrace_seconds = potrace_beziers(mask)
        start = time.perf_counter()
        ours = sc.trace(mask, epsilon=EPSILON, keep_snapshots=False)
        our_seconds = time.perf_counter() - start
        potrace_dev = hausdorff(np.vstack([dense(p) for p in pieces]), reference)
        our_dev = hausdorff(np.vstack([dense(s.bezier()) for s in ours.splines]), reference)
        comparison[name] = {"potrace": (sum(len(p) for p in pieces), potrace_dev, potrace_seconds, pieces),
                            "ours": (ours.stats["segments"], our_dev, our_seconds, ours)}
        rows.append([name, sum(len(p) for p in pieces), ours.stats["segments"], round(potrace_dev, 2),
                     round(our_dev, 2), round(1000 * potrace_seconds, 1), round(1000 * our_seconds, 1)])
    table(["object", "potrace segments", f"ours (ε = {EPSILON:g}) segments", "potrace max dev. (px)",
           "ours max dev. (px)", "potrace ms (CLI)", "ours ms (in-process)"], rows)
else:
    print("skipped: potrace is not installed")
'''),
    ("md", r"""
One run each, on a shared machine: the times are indicative only (potrace's includes starting a process).

## 3. A close look

The 'Ali' outline: grey (wide) is the exact outline, orange potrace, blue ours; the dots are where segments
join. The zoom shows the ayn's head and the tail cut: where each tracer rounds a corner or flattens an arc."""),
    ("code", r'''
if POTRACE is not None:
    segments_potrace, _, _, pieces = comparison["ali"]["potrace"]
    result = comparison["ali"]["ours"][3]
    def bezier_plot(title, beziers, color, bounds=None, width=560, height=380):
        plot = Plot(title, width=width, height=height, bounds=bounds)
        for outline in sc.datasets.true_outline("ali"):
            plot.line(outline, "#bdbdbd", 3.0, closed=True)
        theta = np.linspace(0, 1, 16)[:, None]
        weights = np.hstack([(1 - theta) ** 3, 3 * (1 - theta) ** 2 * theta, 3 * (1 - theta) * theta ** 2, theta ** 3])
        for bezier in beziers:
            plot.polylines(np.einsum("kj,mjd->mkd", weights, bezier), color, 1.4)
            plot.dots(bezier[:, 0], color, 12)
        return plot
    ours_pieces = [s.bezier() for s in result.splines]
    zoom = (280, 60, 370, 150)                   # the ayn's head and the lam's foot, px
    show(bezier_plot(f"potrace: {segments_potrace} segments", pieces, PALETTE[1]),
         bezier_plot(f"splinecraft ε = {EPSILON:g}: {result.stats['segments']} segments", ours_pieces, PALETTE[0]),
         bezier_plot("potrace, zoomed", pieces, PALETTE[1], zoom, 420, 420),
         bezier_plot("splinecraft, zoomed", ours_pieces, PALETTE[0], zoom, 420, 420), columns=2)
'''),
    ("md", "## 4. Explore our side interactively"),
    ("code", r'''
explorer = sc.TraceExplorer(sc.datasets.thesis_object("planes"), epsilon=EPSILON)
display(explorer.panel())
'''),
    ("md", "## Check"),
    ("code", r'''
if POTRACE is None:
    assert comparison == {}                                      # skipped gracefully
else:
    for name, sides in comparison.items():
        segments, deviation, seconds, _ = sides["ours"]
        assert segments > 0 and np.isfinite(deviation) and deviation < 3.0, name
        assert sides["potrace"][0] > 0 and np.isfinite(sides["potrace"][1]), name
assert explorer.result.stats["converged"]
print("all checks passed")
'''),
]

NOTEBOOKS.update({
    "05_corners": NB05,
    "06_outline_capture": NB06,
    "07_potrace": NB07,
})
