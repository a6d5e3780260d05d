"""Corners of noisy boundaries (issue 9, "Scan-like input"): tangent-jump at the pixel scale against the scale of
the noise (``corners.detection_scale``, the default on boundaries that read as noisy), side by side in one run.

    .venv/bin/python benchmarks/bench_noisy_corners.py            # analytic shapes and glyphs
    .venv/bin/python benchmarks/bench_noisy_corners.py --quick    # analytic shapes only

Shapes: the analytic shapes of ``synthetic_shapes.tuning_set`` (polygons, stars, discs, ellipses, blobs, lenses,
a rounded rectangle, a ring, a hand-drawn D, an arrow) and, without ``--quick``, its glyphs at 200 px (the
DejaVu and Liberation glyphs of that set). Each is rendered clean and at four noise levels:

* ``ss blur/noise``: the scan-like recipe of ``heldout_shapes.scan_like`` (rendered at 4x, Gaussian blur of
  ``blur`` px, per-4x-pixel noise of standard deviation ``noise``, averaged to 1x, thresholded at 0.5);
  ``ss 1.5/0.25`` is the level of the yardstick's and the held-out set's scans;
* ``px blur/noise``: blurred at 1x and given per-pixel noise (noisier than any scan of the benchmark sets).

Both variants trace the same bitmap, interleaved (``sc.trace(mask)`` with ``corner_params={"scale": 1}``, the
pixel scale, and with the defaults); each traced outline is scored against the exact one by
``synthetic_shapes.score_beziers`` (the yardstick's measures: within 1 px, rms, segments, corner F1 with
corners as joins turning by more than 30 degrees matched within 3 px). Printed per level and variant: the share
within 1 px, the median rms, the median and total segments against the truth's, the pooled corner F1, the
corners found, and the CPU seconds of all traces.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy.ndimage import gaussian_filter

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import synthetic_shapes as shapes_module  # noqa: E402
from heldout_shapes import rasterize  # noqa: E402

import splinecraft as sc  # noqa: E402

LEVELS = [("clean", 0.0, 0.0), ("ss", 1.5, 0.25), ("ss", 2.0, 0.3), ("ss", 1.5, 0.6), ("px", 2.0, 0.2)]
VARIANTS = [("pixel scale", {"scale": 1}), ("noise scale (default)", {})]
MARGIN = 12


def _padded(shape):
    shape = dict(shape)
    shape["contours"] = [c + MARGIN for c in shape["contours"]]
    shape["corners"] = [tuple(np.asarray(c) + MARGIN) for c in shape["corners"]]
    shape["width"] += 2 * MARGIN
    shape["height"] += 2 * MARGIN
    return shape


def render(shape, mode, blur, noise, seed):
    """The ink mask of ``shape`` at a noise level (module docstring)."""
    if mode == "clean":
        return rasterize(shape, 1)
    rng = np.random.default_rng(seed)
    if mode == "ss":
        factor = 4
        ink = rasterize(shape, factor).astype(float)
        gray = 1.0 - gaussian_filter(ink, blur * factor) + rng.normal(0.0, noise, ink.shape)
        gray = gray.reshape(shape["height"], factor, shape["width"], factor).mean(axis=(1, 3))
    else:
        gray = 1.0 - gaussian_filter(rasterize(shape, 1).astype(float), blur) + rng.normal(0.0, noise,
                                                                                           (shape["height"],
                                                                                            shape["width"]))
    return gray < 0.5


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="analytic shapes only")
    args = parser.parse_args(argv)
    shapes = [_padded(s) for s in shapes_module.tuning_set(include_glyphs=not args.quick, sizes=(200,))]
    print(f"{len(shapes)} shapes; splinecraft {sc.__version__}")
    print("| level | variant | within 1 px | median rms px | median segments (truth) | total segments (truth) "
          "| corner F1 | corners found (true) | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for mode, blur, noise in LEVELS:
        rows = {name: [] for name, _ in VARIANTS}
        cpu = dict.fromkeys(rows, 0.0)
        tp_found_true = {name: [0, 0, 0] for name in rows}
        for index, shape in enumerate(shapes):
            mask = render(shape, mode, blur, noise, seed=100 + index)
            for name, corner_params in VARIANTS:
                started = time.process_time()
                result = sc.trace(mask, keep_snapshots=False, corner_params=corner_params)
                cpu[name] += time.process_time() - started
                score = shapes_module.score_beziers(shape, [np.asarray(b) for b in result.bezier()])
                rows[name].append((score["max_dev"] <= 1.0, score["rms_dev"], score["segments"],
                                   shape.get("segments") or 1))
                counts = tp_found_true[name]
                counts[0] += round(score["corner_p"] * score["corners"])
                counts[1] += score["corners"]
                counts[2] += score["true_corners"]
        label = "clean" if mode == "clean" else f"{mode} {blur:g}/{noise:g}"
        for name in rows:
            values = np.array(rows[name], float)
            tp, found, true = tp_found_true[name]
            precision = tp / found if found else 1.0
            recall = tp / true if true else 1.0
            f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
            print(f"| {label} | {name} | {values[:, 0].mean():.0%} | {np.median(values[:, 1]):.3f} | "
                  f"{np.median(values[:, 2]):.0f} ({np.median(values[:, 3]):.0f}) | {values[:, 2].sum():.0f} "
                  f"({values[:, 3].sum():.0f}) | {f1:.3f} | {found} ({true}) | {cpu[name]:.1f} |", flush=True)


if __name__ == "__main__":
    main()
