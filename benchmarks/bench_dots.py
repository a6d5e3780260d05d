"""Dots and tiny blocks (issue 9; the session-20 tester's lopsided 2 x 2 dot): shapes of 1-8 px across, traced
against their exact outlines.

    .venv/bin/python benchmarks/bench_dots.py                       # this tree and potrace (if installed)
    .venv/bin/python benchmarks/bench_dots.py --compare BEFORE/src  # and another tree, same shapes

Shapes, generated here from a fixed seed, each alone in a 24 x 24 image, beside a 12 x 12 block (a larger
outline: the tester's setting, and what keeps a dot from being the only ink):

* ``blocks 1-2 px``: axis-aligned blocks 1 x 1, 1 x 2, 2 x 1 and 2 x 2 at integer positions (pixel art, the
  periods and i-dots of small bitmap text); their truth is the block itself;
* ``blocks 3-4 px``: blocks of 3-4 px sides, likewise;
* ``discs r 0.9-1.5``, ``discs r 1.5-2.5``, ``discs r 2.5-4``: discs with a random centre, rasterized by pixel
  centres (pixel (r, c) is ink when its centre (c + 0.5, r + 0.5) is inside); their truth is the circle.

Each is traced by ``sc.trace(mask, min_speck_area=0)`` (the default drops specks of 1-2 px beside a larger
outline, as potrace's ``turdsize``) and scored on the traced outline nearest the shape: the two-sided distance to
the exact outline (dense samples of both), the error of its area centroid, its area over the truth's, and its
segments. As a reference the centroid error of the ink pixels themselves (the best a tracer can read from them
without a model of the shape). potrace (Debian's CLI, ``-t 0`` so that it keeps every speck) is traced on the
same bitmaps when installed (``scripts/system-deps.sh potrace``).
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image
from scipy.spatial import cKDTree

import splinecraft as sc

SIZE = 24
GROUPS = ("blocks 1-2 px", "blocks 3-4 px", "discs r 0.9-1.5", "discs r 1.5-2.5", "discs r 2.5-4")


def shapes(count=60, seed=21):
    """``(group, mask, truth points (dense, closed), true centroid, true area)`` of every shape."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[:SIZE, :SIZE]
    out = []
    for group in GROUPS:
        for _ in range(count):
            mask = np.zeros((SIZE, SIZE), bool)
            mask[2:14, 2:14] = True  # the larger outline beside the dot
            if group.startswith("blocks"):
                sides = (1, 2) if group == "blocks 1-2 px" else (3, 4)
                height, width = rng.choice(sides, 2)
                top, left = rng.integers(16, SIZE - 5, 2)
                mask[top:top + height, left:left + width] = True
                corners = np.array([(left, top), (left + width, top), (left + width, top + height),
                                    (left, top + height)], float)
                truth = np.vstack([a + (b - a) * np.linspace(0, 1, 200, endpoint=False)[:, None]
                                   for a, b in zip(corners, np.roll(corners, -1, axis=0))])
                centre, area = corners.mean(axis=0), float(height * width)
            else:
                low, high = {"discs r 0.9-1.5": (0.9, 1.5), "discs r 1.5-2.5": (1.5, 2.5),
                             "discs r 2.5-4": (2.5, 4.0)}[group]
                radius = rng.uniform(low, high)
                centre = np.array([19.0, 19.0]) + rng.random(2)
                dot = (cols + 0.5 - centre[0]) ** 2 + (rows + 0.5 - centre[1]) ** 2 <= radius * radius
                if not dot.any():
                    continue
                mask |= dot
                angle = np.linspace(0, 2 * np.pi, 800, endpoint=False)
                truth = centre + radius * np.column_stack([np.cos(angle), np.sin(angle)])
                area = float(np.pi * radius * radius)
            out.append((group, mask, truth, centre, area))
    return out


def _cubic_samples(bezier, count=80):
    t = np.linspace(0.0, 1.0, count, endpoint=False)[:, None, None]
    b = np.asarray(bezier, float)[None]
    s = 1.0 - t
    return (s ** 3 * b[:, :, 0] + 3 * s * s * t * b[:, :, 1] + 3 * s * t * t * b[:, :, 2]
            + t ** 3 * b[:, :, 3]).transpose(1, 0, 2).reshape(-1, 2)


def score(chains, truth, centre, area):
    """(distance, centroid error, area ratio, segments) of the traced closed chain nearest ``centre``."""
    if not chains:
        return float("inf"), float("inf"), 0.0, 0
    samples = [_cubic_samples(c) for c in chains]
    nearest = int(np.argmin([np.hypot(*(s.mean(axis=0) - centre)) for s in samples]))
    points = samples[nearest]
    x, y = points[:, 0], points[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    signed = cross.sum() / 2.0
    if signed == 0:
        return float("inf"), float("inf"), 0.0, len(chains[nearest])
    centroid = np.array([((x + x1) * cross).sum(), ((y + y1) * cross).sum()]) / (6.0 * signed)
    distance = max(cKDTree(truth).query(points)[0].max(), cKDTree(points).query(truth)[0].max())
    return (float(distance), float(np.hypot(*(centroid - centre))), float(abs(signed) / area),
            int(len(chains[nearest])))


def run_splinecraft(mask):
    return [spline.bezier() for spline in sc.trace(mask, min_speck_area=0).splines]


def make_potrace(exe):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from synthetic_shapes import svg_beziers

    def run(mask):
        with tempfile.TemporaryDirectory() as tmp:
            pbm = os.path.join(tmp, "in.pbm")
            Image.fromarray(~mask).convert("1").save(pbm)
            svg = subprocess.run([exe, "-t", "0", "-b", "svg", "-o", "-", pbm], check=True,
                                 capture_output=True).stdout.decode()
        return svg_beziers(svg)
    return run


def pixel_centroid_error(mask, centre):
    """Centroid error of the ink pixels of the dot (those beyond the larger block)."""
    dot = mask.copy()
    dot[:16, :16] = False
    rows, cols = np.nonzero(dot)
    return float(np.hypot(cols.mean() + 0.5 - centre[0], rows.mean() + 0.5 - centre[1]))


def measure(runners):
    rows = []
    for group, mask, truth, centre, area in shapes():
        rows.append([group, pixel_centroid_error(mask, centre)]
                    + [score(run(mask), truth, centre, area) for run in runners])
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--compare", help="another tree's src folder, traced at its defaults")
    parser.add_argument("--json", help=argparse.SUPPRESS)  # the child's output
    args = parser.parse_args(argv)
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(measure([run_splinecraft]), handle)
        return
    names, runners = ["splinecraft"], [run_splinecraft]
    potrace = shutil.which("potrace")
    if potrace:
        names.append("potrace -t 0")
        runners.append(make_potrace(potrace))
    rows = measure(runners)
    if args.compare:
        out = os.path.join(tempfile.gettempdir(), f"bench_dots_{os.getpid()}.json")
        env = dict(os.environ, PYTHONPATH=os.path.abspath(args.compare))
        subprocess.run([sys.executable, os.path.abspath(__file__), "--json", out], env=env, check=True)
        with open(out) as handle:
            other = json.load(handle)
        os.remove(out)
        rows = [row + [tuple(o[2])] for row, o in zip(rows, other)]
        names.append(f"compare ({args.compare})")
    print("Cells: within 0.5 px / median distance px / median centroid error px / median area ratio / "
          "median segments\n")
    print("| group | n | ink pixels' centroid error | " + " | ".join(names) + " |")
    print("|---|---|---|" + "---|" * len(names))
    for group in GROUPS:
        mine = [row for row in rows if row[0] == group]
        cells = []
        for k in range(len(names)):
            distance, centroid, ratio, segments = (np.array([r[2 + k][j] for r in mine]) for j in range(4))
            cells.append(f"{(distance <= 0.5).mean():.0%} / {np.median(distance):.2f} / {np.median(centroid):.2f} / "
                         f"{np.median(ratio):.2f} / {np.median(segments):.0f}")
        pixels = np.median([row[1] for row in mine])
        print(f"| {group} | {len(mine)} | {pixels:.2f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
