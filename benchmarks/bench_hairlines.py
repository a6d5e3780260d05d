"""Hairlines and the boundary-noise estimate (issue 9): clean thin strokes and real scans, before and after.

    .venv/bin/python benchmarks/bench_hairlines.py
    .venv/bin/python benchmarks/bench_hairlines.py --compare OTHER/src
    .venv/bin/python benchmarks/bench_hairlines.py --small --compare OTHER/src

Clean strokes of width 1.2-3 px along a sine wave and a spiral, and rings of those widths, are rendered with
the pixel-centre rule (``heldout_shapes.rasterize``) from their exact outlines (the centre line offset by half
the width on both sides) and traced with ``sc.trace`` at its defaults. Per shape the table gives the boundary
noise estimate (``stats["boundary_noise"]``), the fit's tolerance, the largest and rms distance between the
traced and the exact outline (both ways, ``synthetic_shapes.score_beziers``) and the segment count. The real
scans of ``skimage.data`` (``page``, ``text``, ``camera``, ``coins``, default threshold) have no exact outline:
noise, tolerance, outlines and segments only. With ``--compare SRC`` the same shapes are traced by the
``src`` folder of another checkout in a second process, and both columns are printed side by side.
With ``--small`` the shapes are clean renders of the held-out families' glyphs at 24-48 px instead (small
text, whose serifs, arms and spurs are a few pixels): per size, how many had their tolerance raised by the
noise rule, the share within 1 px of the exact outline, and the median and largest distance.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
WIDTHS = (1.2, 1.5, 2.0, 3.0)


def _stroke(centre_line, width, size):
    """The exact outline of a stroke of ``width`` around an open centre line, as one closed polyline."""
    tangent = np.gradient(centre_line, axis=0)
    tangent /= np.hypot(*tangent.T)[:, None]
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    outline = np.vstack([centre_line + normal * width / 2, (centre_line - normal * width / 2)[::-1]])
    return {"contours": [outline], "height": size, "width": size, "corners": []}


def _ring(radius, width, size, centre=(150.3, 150.7)):
    angle = np.linspace(0.0, 2 * np.pi, 4000, endpoint=False)
    circle = np.column_stack([np.cos(angle), np.sin(angle)])
    return {"contours": [centre + (radius + width) * circle, centre + radius * circle[::-1]], "height": size,
            "width": size, "corners": []}


def shapes():
    s = np.linspace(0.0, 1.0, 4000)
    turn = np.linspace(0.5, 6 * np.pi, 6000)
    out = []
    for width in WIDTHS:
        out.append((f"sine, {width} px", _stroke(np.column_stack([20 + 260 * s, 150 + 60 * np.sin(6 * np.pi * s)]),
                                                 width, 300)))
        out.append((f"spiral, {width} px", _stroke(np.column_stack([150 + (4 + 7 * turn) * np.cos(turn),
                                                                    150 + (4 + 7 * turn) * np.sin(turn)]), width, 300)))
        out.append((f"ring r 80, {width} px", _ring(80.0, width, 300)))
    return out


SMALL_SIZES = (24, 32, 40, 48)


def small_glyphs(per_family=8):
    """Clean renders (pixel-centre rule) of the held-out families' first ``per_family`` glyphs at the sizes of
    small text, where serifs, arms and spurs are a few pixels wide."""
    import heldout_shapes

    out = []
    for label, (path, chars) in heldout_shapes.available_families().items():
        for size in SMALL_SIZES:
            for char in chars[:per_family]:
                shape = heldout_shapes.glyph_shape(path, char, size, 0.0, label)
                if shape is not None:
                    out.append((f"{label} {char} {size} px", shape))
    return out


def _traced(src, shapes_of):
    """``(name, shape, result, score)`` per shape of ``shapes_of()``, traced at the defaults by the tree whose
    ``src`` folder is ``src`` (run in a process of its own) and scored against the exact outline."""
    sys.path.insert(0, src)
    sys.path.insert(0, HERE)
    import warnings

    import heldout_shapes
    import splinecraft as sc
    import synthetic_shapes

    warnings.simplefilter("ignore")
    for name, shape in shapes_of():
        result = sc.trace(heldout_shapes.rasterize(shape), keep_snapshots=False)
        yield name, shape, result, synthetic_shapes.score_beziers(shape, synthetic_shapes.svg_beziers(result.to_svg()))


def measure_small(src):
    """Per small glyph: noise, tolerance and the largest distance to the exact outline."""
    return [{"name": name, "size": shape["size"], "noise": result.stats["boundary_noise"],
             "tolerance": result.stats["tolerance"], "max": score["max_dev"], "epsilon": result.params["epsilon"]}
            for name, shape, result, score in _traced(src, small_glyphs)]


def _small_table(before, after):
    columns = [("before", before), ("after", after)] if before else [("this tree", after)]
    print("Cells: tolerance raised by the noise rule / within 1 px of the exact outline / median and largest "
          "distance px\n")
    print("| size | n | " + " | ".join(label for label, _ in columns) + " |")
    print("|---|---|" + "---|" * len(columns))
    for size in SMALL_SIZES + (None,):
        cells = []
        for _, rows in columns:
            picked = [row for row in rows if size is None or row["size"] == size]
            raised = sum(row["tolerance"] > row["epsilon"] for row in picked)
            within = sum(row["max"] <= 1.0 for row in picked)
            distances = np.array([row["max"] for row in picked])
            cells.append(f"{raised} / {100 * within / len(picked):.0f}% / {np.median(distances):.2f}, "
                         f"{distances.max():.2f}")
        print(f"| {size or 'all'} | {len(picked)} | " + " | ".join(cells) + " |")


def measure(src):
    """Rows for the tree whose ``src`` folder is ``src`` (run in a process of its own)."""
    import skimage.data

    rows = [{"name": name, "noise": result.stats["boundary_noise"], "tolerance": result.stats["tolerance"],
             "max": score["max_dev"], "rms": score["rms_dev"], "segments": score["segments"],
             "outlines": len(result.boundaries)} for name, _, result, score in _traced(src, shapes)]
    import splinecraft as sc

    for name in ("page", "text", "camera", "coins"):
        result = sc.trace(getattr(skimage.data, name)(), keep_snapshots=False)
        segments = sum(spline.n_segments for spline in result.splines if spline is not None)
        rows.append({"name": f"skimage.data.{name}()", "noise": result.stats["boundary_noise"],
                     "tolerance": result.stats["tolerance"], "max": None, "rms": None, "segments": segments,
                     "outlines": len(result.boundaries)})
    return rows


def _cell(row):
    quality = "" if row["max"] is None else f"{row['max']:.2f} / {row['rms']:.2f} / "
    return f"{row['noise']:.2f} / {row['tolerance']:.2f} / {quality}{row['segments']} ({row['outlines']} outlines)"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--compare", help="the src folder of another checkout (the 'before')")
    parser.add_argument("--small", action="store_true",
                        help="clean glyphs of small text (24-48 px) instead: the noise rule's false alarms")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        print(json.dumps(measure_small(args.child) if args.small else measure(args.child)))
        return

    def run(src):
        command = [sys.executable, __file__, "--child", src] + (["--small"] if args.small else [])
        done = subprocess.run(command, capture_output=True, text=True, check=True)
        return json.loads(done.stdout.strip().splitlines()[-1])

    after = run(os.path.join(ROOT, "src"))
    before = run(os.path.abspath(args.compare)) if args.compare else None
    if args.small:
        _small_table(before, after)
        return
    print("Cells: noise px / tolerance px / max / rms px to the exact outline / segments (outlines)\n")
    if before:
        print("| shape | before | after |\n|---|---|---|")
        for old, new in zip(before, after):
            print(f"| {new['name']} | {_cell(old)} | {_cell(new)} |")
    else:
        print("| shape | this tree |\n|---|---|")
        for new in after:
            print(f"| {new['name']} | {_cell(new)} |")


if __name__ == "__main__":
    main()
