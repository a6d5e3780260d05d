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
# # 07 · Side by side with potrace
#
# **What you should see.** potrace is the standard open-source bitmap tracer; here it and splinecraft trace
# the same five bitmaps, and you should see how many Bézier segments each needs, how far each result strays
# from the true outline of the shape (known exactly for these drawn objects), and how long each takes. If
# potrace is not installed, this notebook tells you how to install it (`bash scripts/system-deps.sh potrace`)
# and skips the comparison.
#
# The full comparison with timings over repeated runs is `benchmarks/thesis_tables.py` (see `BENCHMARKS.md`).

# %%
import numpy as np
from IPython.display import Markdown, display

import splinecraft as sc

# %%
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

# %% [markdown]
# ## 1. Measuring both the same way
#
# potrace writes an SVG whose path is in units of 0.1 px with y pointing up; we undo its transform so both
# results live in the bitmap's pixel frame. Both are then sampled densely on their exact cubic pieces and compared
# with the object's exact outline (`sc.datasets.true_outline`): the deviation is the symmetric Hausdorff
# distance, the largest distance from either curve to the other.

# %%
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
    """Points along Bézier pieces (m, 4, 2), about ``spacing`` px apart."""
    longest = np.linalg.norm(np.diff(bezier, axis=1), axis=2).sum(1).max()
    theta = np.linspace(0, 1, int(np.ceil(longest / spacing)) + 2)[:, None]
    weights = np.hstack([(1 - theta) ** 3, 3 * (1 - theta) ** 2 * theta, 3 * (1 - theta) * theta ** 2, theta ** 3])
    return np.einsum("kj,mjd->mkd", weights, bezier).reshape(-1, 2)


def reference_points(name, spacing=0.05):
    """Points along the exact outline of a thesis object, about ``spacing`` px apart."""
    points = []
    for outline in sc.datasets.true_outline(name):
        ring = np.vstack([outline, outline[:1]])
        steps = np.maximum(1, np.ceil(np.linalg.norm(np.diff(ring, axis=0), axis=1) / spacing).astype(int))
        for a, b, k in zip(ring[:-1], ring[1:], steps):
            points.append(a + np.arange(k)[:, None] / k * (b - a))
    return np.vstack(points)


def hausdorff(a, b):
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))

# %% [markdown]
# ## 2. The comparison

# %%
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
    display(sc.plot.table(["object", "potrace segments", f"ours (ε = {EPSILON:g}) segments", "potrace max dev. (px)",
                           "ours max dev. (px)", "potrace ms (CLI)", "ours ms (in-process)"], rows))
else:
    print("skipped: potrace is not installed")

# %% [markdown]
# One run each, on a shared machine: the times are indicative only (potrace's includes starting a process).
#
# ## 3. A close look
#
# The 'Ali' outline: grey (wide) is the exact outline, orange potrace, blue ours; the dots are where segments
# join. The zoom shows the ayn's head and the tail's cut end: where each tracer rounds a corner or flattens an arc.

# %%
def bezier_plot(title, beziers, color, bounds=None, width=600, height=400):
    exact = [sc.plot.line(outline, "#bdbdbd", 3.0, closed=True) for outline in sc.datasets.true_outline("ali")]
    return sc.plot.figure(exact, [sc.plot.bezier_pieces(bezier, color, 1.4) for bezier in beziers],
                          title=title, width=width, height=height, bounds=bounds)


if POTRACE is not None:
    segments_potrace, _, _, potrace_pieces = comparison["ali"]["potrace"]
    result = comparison["ali"]["ours"][3]
    ours_pieces = [s.bezier() for s in result.splines]
    zoom = (280, 60, 400, 170)                   # the ayn's head and the tail's cut end, px
    display(sc.plot.grid(
        bezier_plot(f"potrace: {segments_potrace} segments", potrace_pieces, sc.plot.PALETTE[1]),
        bezier_plot(f"splinecraft ε = {EPSILON:g}: {result.stats['segments']} segments", ours_pieces,
                    sc.plot.PALETTE[0]),
        bezier_plot("potrace, zoomed", potrace_pieces, sc.plot.PALETTE[1], zoom, 440, 440),
        bezier_plot("splinecraft, zoomed", ours_pieces, sc.plot.PALETTE[0], zoom, 440, 440), columns=2))

# %% [markdown]
# ## 4. Explore our side interactively

# %%
explorer = sc.TraceExplorer(sc.datasets.thesis_object("planes"), epsilon=EPSILON)
explorer.panel()

# %% [markdown]
# ## Check

# %%
if POTRACE is None:
    assert comparison == {}                                      # skipped gracefully
else:
    for name, sides in comparison.items():
        segments, deviation, seconds, _ = sides["ours"]
        assert segments > 0 and np.isfinite(deviation) and deviation < 3.0, name
        assert sides["potrace"][0] > 0 and np.isfinite(sides["potrace"][1]), name
assert explorer.result.stats["converged"]
print("all checks passed")
