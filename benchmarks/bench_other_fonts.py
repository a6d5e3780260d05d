"""Glyphs of the fonts no other benchmark uses (issue 9): a second held-out set, traced against exact outlines.

    .venv/bin/python benchmarks/bench_other_fonts.py                          # this tree, seeds 11-15
    .venv/bin/python benchmarks/bench_other_fonts.py --compare BEFORE/src     # and another tree, same glyphs
    .venv/bin/python benchmarks/bench_other_fonts.py --seeds 11 --list        # every glyph's row

The held-out set of ``heldout_shapes.py`` draws on six families; this one on ten fonts of the same Debian
packages that neither it, the yardstick nor the synthetic tuning set use (FreeSans, FreeMono, Liberation Sans,
Mono and Serif Bold, EB Garamond Italic and Bold, Amiri Bold, FreeSerif Italic, IPA P Mincho), so that a change
tuned, even unknowingly, on the other sets shows here. Per seed and font six glyphs, each at a size drawn from
48, 64, 120, 300 (twice as likely), 600 and 1200 px and, for half of them, turned by a uniform angle of 0-90
degrees; rendered by pixel centres (``heldout_shapes.rasterize``) and traced by ``sc.trace`` at its defaults.
Scored by the yardstick's ``score_svg`` when ``--yardstick`` has it, else by ``synthetic_shapes``.

Cells: within 1 px / median rms px / median segments per true segment / pooled corner F1 / traced outlines
equal to true contours. Nothing is tuned here; the project's tests do not use it.
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

#: label -> font file (none of them used by another benchmark set)
FONTS = {"freesans": "FreeSans.ttf", "freemono": "FreeMono.ttf", "libsans": "LiberationSans-Regular.ttf",
         "libmono": "LiberationMono-Regular.ttf", "libserifbold": "LiberationSerif-Bold.ttf",
         "garamond-it": "EBGaramond12-Italic.otf", "garamond-bold": "EBGaramond12-Bold.otf",
         "amiri-bold": "Amiri-Bold.ttf", "freeserif-it": "FreeSerifItalic.ttf", "ipamp": "ipamp.ttf"}
LATIN = "ABCDEFGHJKMNPQRSWXYZabdefghkmnpqrsty2345&@%"
#: characters of the non-Latin fonts
CHARACTERS = {"amiri-bold": "\u0628\u062c\u0633\u0639\u0642\u0643\u0647\u0645\u0635\u0637\u0641\u0636",
              "ipamp": "\u6c38\u6c34\u66f8\u56fd\u611b\u9053\u5c71\u8a9e\u5b57\u6f22"}
SIZES = (48, 64, 120, 300, 300, 600, 1200)


def glyphs(seed):
    """(label, shape) of one seed's glyphs (``heldout_shapes.glyph_shape``), deterministic."""
    import heldout_shapes as H

    rng = np.random.default_rng(seed)
    out = []
    for label, file_name in FONTS.items():
        path = H.find_font(file_name)
        if path is None:
            print(f"# {file_name} is not installed: skipped (`scripts/system-deps.sh fonts` installs them)",
                  file=sys.stderr)
            continue
        for char in rng.choice(list(CHARACTERS.get(label, LATIN)), size=6, replace=False):
            size = int(rng.choice(SIZES))
            angle = float(rng.uniform(0, 90)) if rng.random() < 0.5 else 0.0
            shape = H.glyph_shape(path, char, size, angle, label)
            if shape is not None:
                out.append((label, shape))
    return out


def measure(seeds, yardstick):
    sys.path.insert(0, HERE)
    import splinecraft as sc  # noqa: F401  (the tree on PYTHONPATH, before bench_peers puts this one's src first)
    import bench_peers
    import heldout_shapes as H

    scorer, _ = bench_peers.make_scorer(yardstick)
    rows = []
    warnings.simplefilter("ignore")
    for seed in seeds:
        for label, shape in glyphs(seed):
            mask = H.rasterize(shape)
            entry = {"truth": {"contours": [{"dense": np.asarray(c)} for c in shape["contours"]],
                               "corners": [{"x": x, "y": y} for x, y in shape["corners"]]}}
            result = sc.trace(mask)
            score = scorer(entry, result.to_svg())
            rows.append({"seed": seed, "font": label, "name": shape["name"], "max_dev": score["max_dev"],
                         "rms_dev": score["rms_dev"], "segments": score["segments"],
                         "true_segments": shape["segments"], "corners": score["corners"],
                         "true_corners": score["true_corners"], "corner_tp": score["corner_tp"],
                         "outlines": len(result.splines), "contours": len(shape["contours"])})
    return rows


def cell(rows):
    dev = np.array([r["max_dev"] for r in rows])
    ratio = np.median([r["segments"] / r["true_segments"] for r in rows])
    tp = sum(r["corner_tp"] for r in rows)
    found, truth = sum(r["corners"] for r in rows), sum(r["true_corners"] for r in rows)
    f1 = 2 * tp / (found + truth) if found + truth else float("nan")
    outlines = np.mean([r["outlines"] == r["contours"] for r in rows])
    return (f"{(dev <= 1.0).mean():.0%} ({int((dev <= 1.0).sum())}) / {np.median([r['rms_dev'] for r in rows]):.3f} / "
            f"{ratio:.2f} / {f1:.3f} / {outlines:.0%}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="11,12,13,14,15")
    parser.add_argument("--yardstick", default=os.path.join(HERE, "..", "..", "shared", "yardstick"))
    parser.add_argument("--compare", help="another tree's src folder, traced at its defaults")
    parser.add_argument("--list", action="store_true", help="every glyph's row")
    parser.add_argument("--json", help=argparse.SUPPRESS)  # the child's output
    args = parser.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",")]
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(measure(seeds, args.yardstick), handle)
        return
    columns = {"this tree": measure(seeds, args.yardstick)}
    if args.compare:
        out = os.path.join("/tmp", f"bench_other_fonts_{os.getpid()}.json")
        env = dict(os.environ, PYTHONPATH=os.path.abspath(args.compare))
        subprocess.run([sys.executable, os.path.abspath(__file__), "--seeds", args.seeds, "--yardstick",
                        args.yardstick, "--json", out], env=env, check=True)
        with open(out) as handle:
            columns[f"compare ({args.compare})"] = json.load(handle)
        os.remove(out)
    names = list(columns)
    print("Cells: within 1 px (count) / median rms px / median segments per true segment / pooled corner F1 / "
          "traced outlines = true contours\n")
    print("| font | n | " + " | ".join(names) + " |")
    print("|---|---|" + "---|" * len(names))
    first = columns[names[0]]
    for font in dict.fromkeys(r["font"] for r in first):
        cells = [cell([r for r in columns[name] if r["font"] == font]) for name in names]
        print(f"| {font} | {sum(r['font'] == font for r in first)} | " + " | ".join(cells) + " |")
    print(f"| **all** | {len(first)} | " + " | ".join(cell(columns[name]) for name in names) + " |")
    if args.list:
        print("\n| glyph | " + " | ".join(f"{name}: max dev / segments / corners (tp/true)" for name in names) + " |")
        print("|---|" + "---|" * len(names))
        for k, row in enumerate(first):
            cells = [f"{c[k]['max_dev']:.2f} / {c[k]['segments']} / {c[k]['corner_tp']}/{c[k]['true_corners']}"
                     for c in (columns[name] for name in names)]
            print(f"| {row['name']} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
