"""Notches between a stem and a bowl (issue 9, "Acute tips are reconstructed by extrapolating the two sides"):
how close the traced corner comes to the true notch tip.

    .venv/bin/python benchmarks/bench_notches.py                          # this tree
    .venv/bin/python benchmarks/bench_notches.py --compare BEFORE/src     # and another tree, same shapes

Shapes: a stem 40 px wide with a disc crossing one of its sides at an opening of 25-55 degrees, the disc's
radius drawn from 20-50 px ("tight bowls": its side curves by 1.4-3.5 px within 24 px of the tip) and from
50-250 px ("wide bowls"), at any rotation and sub-pixel offset (shapes whose bowl leaves the image are drawn
again), rendered by pixel centres
(``tests/test_tip_retry.py``'s ``stem_and_bowl``, the tests' own family). Each shape has two notch tips; per tip
the distance from the true tip to the nearest knot of the trace at its defaults. Cells: tips within 0.5 px /
within 1 px / median distance / largest.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
GROUPS = {"tight bowls": (20.0, 50.0), "wide bowls": (50.0, 250.0)}


def inside(radius, opening, rotation, offset, margin=10.0):
    """Whether the shape's bowl lies inside its image (``stem_and_bowl`` places the stem at a fixed point, so a
    turned shape can leave the frame): the bowl at least ``margin`` px from every edge."""
    size = int(40.0 + 2 * radius + 60)
    along = np.array([np.cos(rotation), np.sin(rotation)])
    centre = np.array([30.0 + offset[0], size / 2 + offset[1]]) + along * (40.0 + radius * np.cos(np.radians(opening)))
    return bool((centre - radius >= margin).all() and (centre + radius <= size - margin).all())


def shapes(seed, count):
    """(group, radius, opening, rotation, offset) of every shape, deterministic: ``count`` per group whose bowl
    lies inside the image (:func:`inside`)."""
    rng = np.random.default_rng(seed)
    out = []
    for group, (low, high) in GROUPS.items():
        kept = 0
        while kept < count:
            shape = (float(rng.uniform(low, high)), float(rng.uniform(25, 55)), float(rng.uniform(0, np.pi / 2)),
                     tuple(float(v) for v in rng.uniform(0, 1, 2)))
            if inside(*shape):
                out.append((group, *shape))
                kept += 1
    return out


def measure(seed, count):
    sys.path.insert(0, os.path.join(HERE, "..", "tests"))
    import splinecraft as sc  # the tree on PYTHONPATH
    from test_tip_retry import stem_and_bowl

    warnings.simplefilter("ignore")
    rows = []
    for group, radius, opening, rotation, offset in shapes(seed, count):
        mask, tips = stem_and_bowl(radius, opening, rotation, offset)
        result = sc.trace(mask)
        knots = np.concatenate([np.asarray(spline.knot_points) for spline in result.splines])
        for tip in tips:
            rows.append({"group": group, "distance": float(np.hypot(*(knots - tip).T).min())})
    return rows


def cell(rows):
    d = np.array([r["distance"] for r in rows])
    return f"{(d <= 0.5).mean():.0%} / {(d <= 1.0).mean():.0%} / {np.median(d):.2f} / {d.max():.2f}"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--count", type=int, default=30, help="shapes per group (two tips each)")
    parser.add_argument("--compare", help="another tree's src folder, traced at its defaults")
    parser.add_argument("--json", help=argparse.SUPPRESS)  # the child's output
    args = parser.parse_args(argv)
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(measure(args.seed, args.count), handle)
        return
    columns = {"this tree": measure(args.seed, args.count)}
    if args.compare:
        out = os.path.join("/tmp", f"bench_notches_{os.getpid()}.json")
        env = dict(os.environ, PYTHONPATH=os.path.abspath(args.compare))
        subprocess.run([sys.executable, os.path.abspath(__file__), "--seed", str(args.seed), "--count",
                        str(args.count), "--json", out], env=env, check=True)
        with open(out) as handle:
            columns[f"compare ({args.compare})"] = json.load(handle)
        os.remove(out)
    names = list(columns)
    print("Cells: notch tips within 0.5 px / within 1 px / median distance px / largest px (nearest knot)\n")
    print("| group | tips | " + " | ".join(names) + " |")
    print("|---|---|" + "---|" * len(names))
    for group in GROUPS:
        cells = [cell([r for r in columns[name] if r["group"] == group]) for name in names]
        print(f"| {group} | {sum(r['group'] == group for r in columns[names[0]])} | " + " | ".join(cells) + " |")
    print(f"| **all** | {len(columns[names[0]])} | " + " | ".join(cell(columns[name]) for name in names) + " |")


if __name__ == "__main__":
    main()
