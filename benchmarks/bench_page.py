"""A page of text at print resolution: what ``sc.trace`` does with thousands of glyph outlines (issue 9, "Real
scans").

    .venv/bin/python benchmarks/bench_page.py
    .venv/bin/python benchmarks/bench_page.py --lines 20 --compare OTHER/src

The page is ``--lines`` lines of DejaVu Serif at ``--size`` px (42 px: 10-pt type at 300 dpi), rendered by PIL
into an 8-bit gray image ``--width`` px wide (anti-aliased, even paper), as a scanner would give a clean page.
It is traced at the defaults (the time budget of 5 s) and with ``time_budget=None``, each in a fresh process
per tree (this tree, and ``--compare SRC`` alternating with it), after a first trace of a small part of the page
(the kernels' warm-up is not counted). Reported per run: the process CPU time of ``sc.trace``, its stages
(``stats["time_breakdown"]``), the outlines, how many the budget left as polygons, the boundary-noise estimate
and the tolerance the fit used.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSerif.ttf"
TEXT = "The quick brown fox jumps over the lazy dog. Pack my box with five dozen liquor jugs! 0123456789"

_CHILD = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np
from PIL import Image, ImageDraw, ImageFont
import splinecraft as sc

lines, size, width, budget = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
font = ImageFont.truetype(sys.argv[6], size)
text = sys.argv[7]
pitch = int(round(1.35 * size))
page = Image.new("L", (width, 2 * size + lines * pitch), 255)
draw = ImageDraw.Draw(page)
for row in range(lines):
    draw.text((2 * size, size + row * pitch), text[row % 7:] + text[:row % 7], font=font, fill=0)
gray = np.asarray(page)
sc.trace(gray[: 2 * pitch + size, : width // 4], keep_snapshots=False)     # the kernels' warm-up
started = time.process_time()
result = sc.trace(gray, keep_snapshots=False, time_budget=None if budget == "none" else float(budget))
cpu = time.process_time() - started
per = result.stats["per_boundary"]
print(json.dumps({"cpu_s": cpu, "breakdown": result.stats["time_breakdown"], "outlines": len(per),
                  "polygons": sum(entry["budget"] == "polygon" for entry in per),
                  "stopped": sum(entry["budget"] == "stopped" for entry in per),
                  "noise": result.stats["boundary_noise"], "tolerance": result.stats["tolerance"],
                  "segments": result.stats["segments"], "shape": list(gray.shape)}))
"""


def run(src, args, budget):
    command = [sys.executable, "-c", _CHILD, src, str(args.lines), str(args.size), str(args.width), budget, FONT,
               TEXT]
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lines", type=int, default=20)
    parser.add_argument("--size", type=int, default=42)
    parser.add_argument("--width", type=int, default=2480)
    parser.add_argument("--compare", default=None, help="the src folder of another checkout")
    args = parser.parse_args(argv)
    if not os.path.exists(FONT):
        sys.exit(f"{FONT} is missing (Debian: fonts-dejavu-core)")
    trees = [("this tree", os.path.join(ROOT, "src"))]
    if args.compare:
        trees.append(("compare", os.path.abspath(args.compare)))
    print(f"load average before: {os.getloadavg()[0]:.1f}")
    print("\n| tree | time_budget | page (px) | sc.trace CPU s | corners / noise / fit s | outlines | polygons "
          "(budget) | stopped | noise px | tolerance px | segments |\n|---|---|---|---|---|---|---|---|---|---|---|")
    for budget in ("5", "none"):
        for name, src in trees:
            row = run(src, args, budget)
            stages = row["breakdown"]
            print(f"| {name} | {budget} | {row['shape'][1]} x {row['shape'][0]} | {row['cpu_s']:.1f} | "
                  f"{stages['corners_s']:.1f} / {stages['noise_s']:.1f} / {stages['fit_s']:.1f} | {row['outlines']} | "
                  f"{row['polygons']} | {row['stopped']} | {row['noise']:.2f} | {row['tolerance']:.2f} | "
                  f"{row['segments']} |", flush=True)
    print(f"\nload average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
