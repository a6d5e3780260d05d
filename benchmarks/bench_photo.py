"""A phone photo of a printed page: what ``load_bitmap`` (the default threshold, ``"background"``) costs on
12 and 48 megapixels (issue 9, "Real scans"; a session-12 tester found 40-60 s and 2.5 GB at 48 Mpx).

    .venv/bin/python benchmarks/bench_photo.py
    .venv/bin/python benchmarks/bench_photo.py --compare OTHER/src --rounds 2

The photo is built here: lines of DejaVu Serif text (90 px at 48 Mpx) on paper lit unevenly (the brightness
falls from 215 at the top left to 105 at the bottom right, ink at 0.2 of the paper), Gaussian noise of 3 gray
levels, saved as a JPEG (quality 85) of 8000 x 6000 px and a 2x-subsampled 4000 x 3000 one. Each tree loads each
file in a fresh process (the trees alternating, ``--rounds`` times): reported are the process CPU time of
``load_bitmap``, the process's peak RSS (``VmHWM``: ``ru_maxrss`` would keep the parent's peak across the
fork), and an MD5 of the mask, so two trees can be checked to give the same
mask bit for bit.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSerif.ttf"
WORDS = "the quick brown fox jumps over a lazy dog splines curves knots ball bezier timmer".split()

_CHILD = r"""
import hashlib, json, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np
from splinecraft.capture.image import load_bitmap
started = time.process_time()
mask = load_bitmap(sys.argv[2])
cpu = time.process_time() - started
peak = [int(line.split()[1]) for line in open("/proc/self/status") if line.startswith("VmHWM")][0] / 1024
print(json.dumps({"cpu_s": cpu, "peak_rss_mb": peak,
                  "ink": int(np.count_nonzero(mask)), "md5": hashlib.md5(np.packbits(mask).tobytes()).hexdigest()}))
"""


def make_photos(folder):
    """Write ``photo_48mpx.jpg`` and ``photo_12mpx.jpg`` into ``folder``; returns their paths."""
    import numpy as np
    from PIL import Image, ImageDraw, ImageFont

    rng = np.random.default_rng(1)
    height, width = 6000, 8000
    page = Image.new("L", (width, height), 255)
    draw = ImageDraw.Draw(page)
    font = ImageFont.truetype(FONT, 90)
    for top in range(300, height - 300, 140):
        draw.text((300, top), " ".join(rng.choice(WORDS, 14)), fill=0, font=font)
    reflectance = 0.2 + 0.8 * np.asarray(page, np.float32) / 255
    rows, cols = np.mgrid[0:height, 0:width].astype(np.float32)
    gray = (215 - 70 * cols / width - 40 * rows / height) * reflectance
    gray += rng.normal(0, 3, gray.shape).astype(np.float32)
    gray = np.clip(gray, 0, 255).astype(np.uint8)
    paths = [os.path.join(folder, "photo_48mpx.jpg"), os.path.join(folder, "photo_12mpx.jpg")]
    Image.fromarray(gray).save(paths[0], quality=85)
    Image.fromarray(gray[::2, ::2]).save(paths[1], quality=85)
    return paths


def measure(src, path):
    done = subprocess.run([sys.executable, "-c", _CHILD, src, path], capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--compare", help="another tree's src folder, run alternately with this one")
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args(argv)
    trees = {"this tree": os.path.join(ROOT, "src")}
    if args.compare:
        trees["compare"] = os.path.abspath(args.compare)
    with tempfile.TemporaryDirectory() as folder:
        paths = make_photos(folder)
        runs = {(tree, path): [] for tree in trees for path in paths}
        for _ in range(args.rounds):
            for path in paths:
                for tree, src in trees.items():
                    runs[tree, path].append(measure(src, path))
    print("| photo | tree | CPU s (median) | peak RSS MB (median) | ink px | mask MD5 |")
    print("|---|---|---|---|---|---|")
    for (tree, path), found in runs.items():
        md5s = {run["md5"] for run in found}
        print(f"| {os.path.basename(path)} | {tree} | {statistics.median(r['cpu_s'] for r in found):.2f} | "
              f"{statistics.median(r['peak_rss_mb'] for r in found):.0f} | {found[0]['ink']} | "
              f"{' '.join(sorted(md5s))[:12]} |")


if __name__ == "__main__":
    main()
