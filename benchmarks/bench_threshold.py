"""Which threshold should ``threshold=None`` stand for? ``"background"``, ``"otsu"``, ``"sauvola"`` and ``"local"`` side by side.

    .venv/bin/python benchmarks/bench_threshold.py [--yardstick DIR] [--out benchmarks/out]

Three inputs:

* the yardstick's ``shapes2/scan_*`` bitmaps (already bilevel: the methods must not break them), scored by
  the yardstick's ``score_svg.py`` (skipped when absent);
* held-out scan-like gray renders (``heldout_shapes.scan_like`` before its threshold), on even paper and
  under uneven lighting (the paper's brightness falls linearly from 1.0 at the top-left to ``0.35`` at the
  bottom-right corner, the ink stays at 0), scored against the exact outline: within 1 px, median rms,
  outlines traced / true contours;
* ``skimage.data.page()`` and ``skimage.data.text()`` (no ground truth): the ink share, the number of ink
  components and the share of the ink in the largest component (one solid blob means the lighting won).
  With ``--out`` the masks are written as PNGs.
* wide dark areas whose ink (or paper) runs between two grays, with and without a small counter
  (:func:`dark_areas`): exact masks, wrong pixels counted.

Every trace runs ``sc.trace`` at its defaults except ``threshold``. Last, the time of ``load_bitmap`` per
method (median of 5 after a warm-up, in this process) on a 300-px scan-like gray glyph, ``page()`` and a
2000 x 2000 tiling of ``page()``.
"""
from __future__ import annotations

import argparse
import glob
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "src"))
sys.path.insert(0, HERE)

import splinecraft as sc  # noqa: E402
from bench_peers import make_scorer  # noqa: E402

METHODS = ("background", "otsu", "sauvola", "local")


def _lit(gray, darkest=0.35):
    height, width = gray.shape
    ramp = 1.0 - (1.0 - darkest) * (np.add.outer(np.arange(height) / height, np.arange(width) / width) / 2)
    return gray * ramp


def _score_rows(entries, scorer):
    print("| input | n | " + " | ".join(METHODS) + " |")
    print("|---|---|" + "---|" * len(METHODS))
    for label, items in entries:
        cells = []
        for method in METHODS:
            dev, rms, outlines = [], [], []
            for entry, image in items:
                result = sc.trace(image, threshold=method, keep_snapshots=False)
                score = scorer(entry, result.to_svg())
                dev.append(score["max_dev"])
                rms.append(score["rms_dev"])
                outlines.append(len(result.boundaries) / len(entry["truth"]["contours"]))
            cells.append(f"{100 * np.mean(np.array(dev) <= 1):.0f}% / {np.median(rms):.3f} / "
                         f"{np.median(outlines):.2f}")
        print(f"| {label} | {len(items)} | " + " | ".join(cells) + " |")
    print("\nCells: within 1 px / median rms px / median traced outlines per true contour.")


def _pages(out):
    from skimage import data
    from scipy import ndimage

    print("\n| image | " + " | ".join(METHODS) + " |")
    print("|---|" + "---|" * len(METHODS))
    for name in ("page", "text"):
        gray = getattr(data, name)()
        cells = []
        for method in METHODS:
            mask = sc.load_bitmap(gray, threshold=method)
            labels, count = ndimage.label(mask, structure=np.ones((3, 3)))
            largest = np.bincount(labels.ravel())[1:].max() / max(mask.sum(), 1) if count else 0.0
            cells.append(f"{100 * mask.mean():.0f}% / {count} / {100 * largest:.0f}%")
            if out:
                from PIL import Image
                Image.fromarray(~mask).save(os.path.join(out, f"threshold_{name}_{method}.png"))
        print(f"| skimage.data.{name}() | " + " | ".join(cells) + " |")
    print("\nCells: ink share / ink components / share of the ink in the largest component.")


def _times(glyph):
    import time
    from skimage import data

    images = {"300-px scan-like glyph": glyph, "skimage.data.page()": data.page(),
              "2000 x 2000 tiles of page()": np.tile(data.page(), (11, 6))[:2000, :2000]}
    print("\n| image | " + " | ".join(METHODS) + " |")
    print("|---|" + "---|" * len(METHODS))
    for label, gray in images.items():
        cells = []
        for method in METHODS:
            sc.load_bitmap(gray, threshold=method)
            runs = []
            for _ in range(5):
                start = time.perf_counter()
                sc.load_bitmap(gray, threshold=method)
                runs.append(time.perf_counter() - start)
            cells.append(f"{1000 * np.median(runs):.1f}")
        print(f"| {label} | " + " | ".join(cells) + " |")
    print("\nCells: ms per load_bitmap call (median of 5).")


def dark_areas():
    """Wide dark areas on paper (discs of 20-200 px radius; ink and paper each running left to right between
    two 8-bit grays, as uneven toner or a gradient fill), with and without a paper counter of 3-30 px at the
    centre: exact masks, so every wrong pixel counts. Yields (label, gray, true mask)."""
    for size, radius in ((64, 20), (256, 80), (512, 200), (512, 120)):
        for paper, ink in (((200, 250), (20, 40)), ((120, 250), (10, 60)), ((250, 250), (30, 30)),
                           ((250, 250), (10, 90))):
            yield "no counter", *_disc(size, radius, paper, ink, 0.0)
    for paper, ink in (((200, 250), (20, 40)), ((120, 250), (10, 60)), ((250, 250), (10, 90)),
                       ((200, 250), (10, 30)), ((150, 250), (20, 20))):
        for counter in (3.0, 6.0, 30.0):
            yield "counter", *_disc(256, 80, paper, ink, counter)


def _disc(size, radius, paper, ink, counter):
    rows, cols = np.mgrid[:size, :size] + 0.5
    distance = np.hypot(cols - size / 2, rows - size / 2)
    mask = (distance < radius) & (distance >= counter)
    ramp = np.linspace(0.0, 1.0, size)[None, :]
    gray = np.where(mask, ink[0] + (ink[1] - ink[0]) * ramp, paper[0] + (paper[1] - paper[0]) * ramp)
    return np.rint(gray).astype(np.uint8), mask


def _dark_area_rows():
    groups = {}
    for label, gray, mask in dark_areas():
        for method in METHODS:
            wrong = int((sc.load_bitmap(gray, threshold=method, min_speck_area=0) != mask).sum())
            cell = groups.setdefault(label, {}).setdefault(method, [0, 0, 0])
            cell[0] += 1
            cell[1] += wrong > 0
            cell[2] += wrong
    print("\n| dark areas | n | " + " | ".join(METHODS) + " |")
    print("|---|---|" + "---|" * len(METHODS))
    for label, cells in groups.items():
        count = next(iter(cells.values()))[0]
        print(f"| {label} | {count} | " + " | ".join(f"{cells[m][1]} / {cells[m][2]}" for m in METHODS) + " |")
    print("\nCells: cases with a wrong pixel / wrong pixels in all (a hole of paper inside the ink, mostly).")


def main(argv=None):
    import heldout_shapes as H
    from bench_peers import ensure_peers

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--yardstick", default=os.path.join(ROOT, "..", "shared", "yardstick"))
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    ensure_peers([], fonts=True)
    yardstick = os.path.abspath(args.yardstick)
    scorer, scorer_name = make_scorer(yardstick if os.path.isdir(yardstick) else None)
    print(f"scorer: {scorer_name}\n")
    if args.out:
        os.makedirs(args.out, exist_ok=True)
    entries = []
    scans = sorted(glob.glob(os.path.join(yardstick, "shapes2", "scan_*.json")))
    if scans:
        import json
        items = []
        for js in scans:
            with open(js) as handle:
                truth = json.load(handle)
            items.append(({"truth": truth}, np.where(sc.load_bitmap(js[:-5] + ".png"), 0, 255).astype(np.uint8)))
        entries.append(("shapes2 scan_* (bilevel)", items))
    even, lit = [], []
    rng = np.random.default_rng(11)
    for label, (path, chars) in H.available_families().items():
        for k, char in enumerate(chars[:2]):
            shape = H.glyph_shape(path, char, 300, 0.0, label)
            gray, _ = H.scan_like(shape, float(rng.uniform(1, 2)), float(rng.uniform(0.2, 0.3)), seed=50 + k)
            truth = {"contours": [{"dense": np.asarray(c)} for c in shape["contours"]],
                     "corners": [{"x": x, "y": y} for x, y in shape["corners"]]}
            even.append(({"truth": truth}, gray))
            lit.append(({"truth": truth}, _lit(gray)))
    entries += [("held-out scan-like gray, even paper", even), ("held-out scan-like gray, uneven lighting", lit)]
    _score_rows(entries, scorer)
    _pages(args.out)
    _dark_area_rows()
    _times(even[0][1])


if __name__ == "__main__":
    main()
