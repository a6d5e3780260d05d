"""How often does the tracer find as many outlines as the shape has contours? 4, 8 and "minority" side by side.

    .venv/bin/python benchmarks/bench_contours.py [--yardstick DIR] [--sizes 48,64,120,300] [--angles 0,17,45]

Held-out glyphs (``heldout_shapes.py``: every character of every family, at each size and rotation) are
rendered by the pixel-centre rule and traced by :func:`splinecraft.trace_boundaries` with each connectivity;
a render counts as wrong when the number of boundaries (outer and holes) differs from the number of the
glyph's true contours. The yardstick's ``shapes/`` and ``shapes2/`` bitmaps are counted the same way when
present. A few renders stay wrong under every rule: their bitmap itself has a pixel island or pinhole the
outline does not (a hairline or a notch thinner than the pixels), which no connectivity can undo.
"""
from __future__ import annotations

import argparse
import glob
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "src"))
sys.path.insert(0, HERE)

import splinecraft as sc  # noqa: E402

RULES = (4, 8, "minority")
#: The last column: the boundaries of ``sc.trace`` at its defaults (despeckling from the noise estimate, the
#: minority rule, pinholes filled: docs/capture.md §10, "Pinholes").
TRACE_DEFAULTS = "sc.trace defaults"


def count_outlines(mask, rule):
    """Boundaries of ``mask`` under connectivity ``rule``, or under sc.trace's defaults (despeckled first)."""
    if rule == TRACE_DEFAULTS:
        return len(sc.trace(mask, keep_snapshots=False).boundaries)
    return len(sc.trace_boundaries(mask, connectivity=rule))


def main(argv=None):
    import heldout_shapes as H
    from bench_peers import ensure_peers

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--yardstick", default=os.path.join(ROOT, "..", "shared", "yardstick"))
    parser.add_argument("--sizes", default="48,64,120,300")
    parser.add_argument("--angles", default="0,17,45")
    args = parser.parse_args(argv)
    ensure_peers([], fonts=True)
    sizes = [int(s) for s in args.sizes.split(",")]
    angles = [float(a) for a in args.angles.split(",")]
    columns = RULES + (TRACE_DEFAULTS,)
    wrong = {rule: 0 for rule in columns}
    total = 0
    for label, (path, chars) in H.available_families().items():
        for char in chars:
            for size in sizes:
                for angle in angles:
                    shape = H.glyph_shape(path, char, size, angle, label)
                    if shape is None:
                        continue
                    mask = H.rasterize(shape)
                    total += 1
                    for rule in columns:
                        wrong[rule] += count_outlines(mask, rule) != len(shape["contours"])
    print("| input | renders | " + " | ".join(f"wrong count, connectivity={rule!r}" for rule in RULES)
          + f" | wrong count, {TRACE_DEFAULTS} |")
    print("|---|---|" + "---|" * len(columns))
    print(f"| held-out glyphs, sizes {sizes}, rotations {angles} | {total} | "
          + " | ".join(str(wrong[rule]) for rule in columns) + " |")
    files = sorted(glob.glob(os.path.join(os.path.abspath(args.yardstick), "shapes*", "*.json")))
    if files:
        wrong = {rule: 0 for rule in columns}
        for js in files:
            with open(js) as handle:
                truth = len(json.load(handle)["contours"])
            mask = sc.load_bitmap(js[:-5] + ".png")
            for rule in columns:
                wrong[rule] += count_outlines(mask, rule) != truth
        print(f"| yardstick shapes/ + shapes2/ | {len(files)} | " + " | ".join(str(wrong[rule]) for rule in columns)
              + " |")


if __name__ == "__main__":
    main()
