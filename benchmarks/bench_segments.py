"""Segments against the true outline's, by size: the synthetic set at 48-1200 px, fit variants side by side.

The tuning set of ``synthetic_shapes`` (300-px glyphs and analytic shapes) and its ``size_set`` (glyphs at
48, 64, 600 and 1200 px, every other one turned; analytic shapes four times larger) are traced by
``sc.trace`` once per variant (``--variants``: a JSON list of ``fit_params`` dicts, ``{}`` = the defaults; a
key ``"corner_params"`` in a dict is that variant's ``corner_params``, a key ``"tip_angles"`` sets angle
constants of ``capture.fitting.tips`` in degrees for that variant, e.g. ``{"MAX_OBTUSE_ANGLE": 110}``, and a
key ``"tip_constants"`` its other constants as they are, e.g. ``{"CONTRADICTION": 0.05}``),
shape by shape with the variants interleaved, and scored by ``synthetic_shapes.score_beziers``. Per group:
share within 1 px (symmetric Hausdorff) / median rms px / median segments per true segment / pooled corner
F1, and the median time of each variant relative to the first.

    .venv/bin/python benchmarks/bench_segments.py --variants '[{}, {"initial_density": 0}]'

The small synthetic shapes (``synthetic_shapes.small_set``: glyphs at 40-64 px, random small polygons and
blobs, turned) are measured only when asked for: ``--groups small-glyph,small-polygon,small-blob``.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import splinecraft as sc  # noqa: E402
import synthetic_shapes as S  # noqa: E402
from splinecraft.capture.fitting import tips  # noqa: E402

GROUP_ORDER = ("small", "medium", "glyph300", "large", "analytic", "analytic-large", "small-glyph", "small-polygon",
               "small-blob")
SMALL_GROUPS = ("small-glyph", "small-polygon", "small-blob")
TIP_ANGLES = {name: getattr(tips, name) for name in ("MAX_EXTRAPOLATED_ANGLE", "MAX_OBTUSE_ANGLE")}
#: The other constants a variant may set (``"tip_constants"``), restored to these defaults before every variant.
TIP_CONSTANTS = {name: getattr(tips, name) for name in ("CONTRADICTION", "TIP_ZONE", "MAX_TIP_REACH", "REACH_PER_SIDE",
                                                        "BEHIND", "SHARP_TRUNCATION", "MIN_CROSSING",
                                                        "RETRY_SHRINK", "RETRY_UNCERTAINTY")}


def shapes(groups):
    out = []
    for shape in S.tuning_set():
        shape["group"] = "glyph300" if shape["name"].endswith("_300") else "analytic"
        out.append(shape)
    out += S.size_set()
    if any(g in SMALL_GROUPS for g in groups):  # synthetic_shapes.small_set only when asked for
        out += S.small_set()
    return [s for s in out if not groups or s["group"] in groups]


def measure(shape_list, variants):
    rows = []
    for shape in shape_list:
        mask = S.rasterize(shape)
        for v, params in enumerate(variants):
            params = dict(params)
            corner_params = params.pop("corner_params", None)
            angles = {**TIP_ANGLES, **{k: np.radians(v) for k, v in params.pop("tip_angles", {}).items()}}
            angles.update({**TIP_CONSTANTS, **params.pop("tip_constants", {})})
            for constant, value in angles.items():  # the defaults, then this variant's
                setattr(tips, constant, value)
            start = time.perf_counter()
            result = sc.trace(mask, fit_params=params or None, corner_params=corner_params)
            seconds = time.perf_counter() - start
            score = S.score_beziers(shape, [np.asarray(s.bezier()) for s in result.splines])
            rows.append({"name": shape["name"], "group": shape["group"], "variant": v, "time": seconds,
                         "true_segments": shape.get("segments"), **score,
                         "corner_tp": round(score["corner_r"] * score["true_corners"])})
        print(shape["name"], " ".join(f"{r['segments']}/{r['true_segments']} {r['max_dev']:.2f}"
                                      for r in rows[-len(variants):]), file=sys.stderr, flush=True)
    return rows


def summarize(rows):
    dev = np.array([r["max_dev"] for r in rows])
    ratio = [r["segments"] / r["true_segments"] for r in rows if r["true_segments"]]
    tp = sum(r["corner_tp"] for r in rows)
    found = sum(r["corners"] for r in rows)
    truth = sum(r["true_corners"] for r in rows)
    return (f"{100 * np.mean(dev <= 1.0):.0f}% / {np.median([r['rms_dev'] for r in rows]):.3f} / "
            f"{np.median(ratio) if ratio else float('nan'):.2f} / {2 * tp / (found + truth) if found + truth else 1:.2f}")


def print_table(rows, variants):
    print("| group | n | " + " | ".join(json.dumps(v) for v in variants) + " |")
    print("|---|---|" + "---|" * len(variants))
    groups = [g for g in GROUP_ORDER if any(r["group"] == g for r in rows)]
    for label, subset in [(g, [r for r in rows if r["group"] == g]) for g in groups] + [("all", rows)]:
        cells = [summarize([r for r in subset if r["variant"] == v]) for v in range(len(variants))]
        print(f"| {label} | {len(subset) // len(variants)} | " + " | ".join(cells) + " |")
    base = {r["name"]: r["time"] for r in rows if r["variant"] == 0}
    ratios = [np.median([r["time"] / base[r["name"]] for r in rows if r["variant"] == v])
              for v in range(len(variants))]
    print("\nCells: within 1 px / median rms px / median segments per true segment / pooled corner F1. "
          "Median time per shape relative to the first variant: " + ", ".join(f"{t:.2f}" for t in ratios))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--variants", default="[{}]", help="JSON list of fit_params dicts ({} = defaults; a key "
                        "\"corner_params\" holds that variant's corner_params)")
    parser.add_argument("--groups", default="", help="comma-separated groups (default: all)")
    parser.add_argument("--json", default=None, help="write every row to this JSON file")
    args = parser.parse_args(argv)
    variants = json.loads(args.variants)
    rows = measure(shapes([g for g in args.groups.split(",") if g]), variants)
    print_table(rows, variants)
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(rows, handle, indent=1, default=float)


if __name__ == "__main__":
    main()
