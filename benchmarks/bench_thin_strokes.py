"""Thin strokes (issue 9): bars, rounded bars and wedges 1-6 px wide, traced against their exact outlines.

    .venv/bin/python benchmarks/bench_thin_strokes.py                       # this tree, its variants
    .venv/bin/python benchmarks/bench_thin_strokes.py --compare BEFORE/src  # and another tree, same shapes

Shapes, generated here from a fixed seed and rasterized by pixel centres (pixel (r, c) is ink when its centre
(c + 0.5, r + 0.5) is inside) in a 100 x 100 image with a sub-pixel offset:

* ``upright bars``: rectangles 1-2.5 px wide and 15-60 px long along an axis (their ends are runs of 1-2 cracks);
* ``turned bars``: rectangles 1.5-4 px wide, 15-60 px long, at any angle;
* ``rounded bars``: stadiums (a rectangle with semicircular ends) 2-6 px wide, at any angle (no corners);
* ``wedges``: triangles with an acute tip of 8-45 degrees, 25-60 px long, at any angle;
* ``tapered ends``: strokes narrowing from 6-10 px to 2-4.5 px over 25-60 px, cut square at both ends, at any
  angle (session 20; drawn after the other groups, which stay as they were);
* ``blunt tapers`` (180): strokes whose sides converge at 12-30 degrees, cut square where they are 1.0-2.2 px
  wide, 18-30 px long, at any angle: the crossing of the converging sides lies 2-5 px beyond the blunt end
  (session 22; drawn last). The cell adds the share traced beyond 2 px of the outline.

Each is traced by ``sc.trace(mask, corner_params=...)`` per variant, interleaved shape by shape, and scored
against its exact outline: the two-sided distance (dense samples of both; the share within 1 px and the median),
the segments, and for the bars and wedges the share whose every true corner has a join of the fit within 1 px.
With ``--compare SRC`` the same shapes are traced by the tree ``SRC`` at its defaults in a child process, as the
column ``compare``.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

import numpy as np
from scipy.spatial import cKDTree
from skimage.draw import polygon as fill_polygon

import splinecraft as sc

SIZE = 100


def turned(points, degrees, centre):
    angle = np.radians(degrees)
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return np.asarray(points, float) @ rotation.T + np.asarray(centre, float)


def bar(width, length, degrees, centre):
    half_length, half_width = length / 2.0, width / 2.0
    return turned([(-half_length, -half_width), (half_length, -half_width), (half_length, half_width),
                   (-half_length, half_width)], degrees, centre)


def stadium(width, length, degrees, centre, count=64):
    radius, t = width / 2.0, np.linspace(-np.pi / 2, np.pi / 2, count)
    right = np.c_[length / 2 + radius * np.cos(t), radius * np.sin(t)]
    return turned(np.vstack([right, -right]), degrees, centre)


def wedge(opening, length, degrees, centre):
    half = length * np.tan(np.radians(opening) / 2.0)
    return turned([(-length / 2.0, 0.0), (length / 2.0, -half), (length / 2.0, half)], degrees, centre)


def taper(base, end, length, degrees, centre):
    """A stroke narrowing from ``base`` to ``end`` px wide, cut square at both ends (the narrow end is the
    second and third vertex)."""
    half = length / 2.0
    return turned([(-half, -base / 2.0), (half, -end / 2.0), (half, end / 2.0), (-half, base / 2.0)], degrees, centre)


def shapes(seed=19, count=60):
    """``(group, vertices, corners)`` of every shape (``corners``: the true corners, none for rounded bars)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        centre = (SIZE / 2 + rng.uniform(0, 1), SIZE / 2 + rng.uniform(0, 1))
        vertices = bar(rng.uniform(1.0, 2.5), rng.uniform(15, 60), 90.0 * rng.integers(0, 2), centre)
        out.append(("upright bars", vertices, vertices))
    for _ in range(count):
        centre = (SIZE / 2 + rng.uniform(0, 1), SIZE / 2 + rng.uniform(0, 1))
        vertices = bar(rng.uniform(1.5, 4.0), rng.uniform(15, 60), rng.uniform(0, 180), centre)
        out.append(("turned bars", vertices, vertices))
    for _ in range(count):
        centre = (SIZE / 2 + rng.uniform(0, 1), SIZE / 2 + rng.uniform(0, 1))
        out.append(("rounded bars", stadium(rng.uniform(2.0, 6.0), rng.uniform(15, 50), rng.uniform(0, 180), centre),
                    np.zeros((0, 2))))
    for _ in range(count):
        centre = (SIZE / 2 + rng.uniform(0, 1), SIZE / 2 + rng.uniform(0, 1))
        vertices = wedge(rng.uniform(8, 45), rng.uniform(25, 60), rng.uniform(0, 360), centre)
        out.append(("wedges", vertices, vertices[:1]))
    for _ in range(count):  # drawn after the others: their shapes stay as they were
        centre = (SIZE / 2 + rng.uniform(0, 1), SIZE / 2 + rng.uniform(0, 1))
        vertices = taper(rng.uniform(6.0, 10.0), rng.uniform(2.0, 4.5), rng.uniform(25, 60), rng.uniform(0, 360), centre)
        out.append(("tapered ends", vertices, vertices))
    for _ in range(3 * count):  # session 22, drawn after the others
        centre = (SIZE / 2 + rng.uniform(0, 1), SIZE / 2 + rng.uniform(0, 1))
        opening, end, length = np.radians(rng.uniform(12, 30)), rng.uniform(1.0, 2.2), rng.uniform(18, 30)
        vertices = taper(end + 2 * length * np.tan(opening / 2), end, length, rng.uniform(0, 360), centre)
        out.append(("blunt tapers", vertices, vertices))
    return out


def render(vertices):
    mask = np.zeros((SIZE, SIZE), bool)
    rows, cols = fill_polygon(vertices[:, 1] - 0.5, vertices[:, 0] - 0.5, mask.shape)
    mask[rows, cols] = True
    return mask


def dense(points, step=0.05):
    points = np.asarray(points, float)
    out = [a + (b - a) * np.linspace(0.0, 1.0, max(2, int(np.hypot(*(b - a)) / step)), endpoint=False)[:, None]
           for a, b in zip(points, np.roll(points, -1, axis=0))]
    return np.vstack(out)


def score(result, vertices, corners):
    """(distance, segments, corners hit) of one trace: the two-sided distance to the exact outline, the segment
    count, and whether every true corner has a join within 1 px."""
    if not result.splines:
        return float("inf"), 0, False
    traced = np.vstack([dense(spline.sample(0.02)[1]) for spline in result.splines])
    truth = dense(vertices)
    distance = max(cKDTree(truth).query(traced)[0].max(), cKDTree(traced).query(truth)[0].max())
    joins = np.vstack([spline.bezier()[:, 0] for spline in result.splines])
    hit = all(np.hypot(*(joins - c).T).min() <= 1.0 for c in corners)
    return float(distance), int(sum(len(spline.bezier()) for spline in result.splines)), bool(hit)


def measure(variants):
    rows = []
    for group, vertices, corners in shapes():
        mask = render(vertices)
        rows.append([group] + [score(sc.trace(mask, corner_params=v), vertices, corners) for v in variants])
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--variants", default='[{"stroke_ends": false}, {}]',
                        help="JSON list of corner_params, one column each")
    parser.add_argument("--compare", help="another tree's src folder, traced at its defaults")
    parser.add_argument("--json", help=argparse.SUPPRESS)  # the child's output
    args = parser.parse_args(argv)
    variants = json.loads(args.variants)
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(measure(variants), handle)
        return
    names = [json.dumps(v) for v in variants]
    rows = measure(variants)
    if args.compare:
        out = os.path.join("/tmp", f"bench_thin_strokes_{os.getpid()}.json")
        env = dict(os.environ, PYTHONPATH=os.path.abspath(args.compare))
        subprocess.run([sys.executable, os.path.abspath(__file__), "--variants", "[{}]", "--json", out], env=env,
                       check=True)
        with open(out) as handle:
            other = json.load(handle)
        os.remove(out)
        rows = [row + [tuple(o[1])] for row, o in zip(rows, other)]
        names.append(f"compare ({args.compare})")
    print("Cells: within 1 px / median distance px / median segments / every true corner joined within 1 px\n")
    print("| group | n | " + " | ".join(names) + " |")
    print("|---|---|" + "---|" * len(names))
    for group in dict.fromkeys(row[0] for row in rows):
        mine = [row[1:] for row in rows if row[0] == group]
        cells = []
        for k in range(len(names)):
            distance = np.array([r[k][0] for r in mine])
            segments = np.array([r[k][1] for r in mine])
            hits = np.array([r[k][2] for r in mine])
            corner_cell = "-" if group == "rounded bars" else f"{hits.mean():.0%}"
            beyond = f" / beyond 2 px {(distance > 2.0).mean():.0%}" if group == "blunt tapers" else ""
            cells.append(f"{(distance <= 1.0).mean():.0%} / {np.median(distance):.2f} / {np.median(segments):.0f} / "
                         f"{corner_cell}{beyond}")
        print(f"| {group} | {len(mine)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
