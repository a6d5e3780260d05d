"""Curvature jumps (docs/capture.md §12, "Curvature jumps"): shapes made of lines and arcs, traced with the
option ``curvature_jumps`` off and at its default (``"smooth"``: outlines without corners) and by potrace, side by
side in one run.

Shapes (``synthetic_shapes``, exact outlines): two rounded rectangles, a stadium, a turned ellipse, a ring, a
'D', a star and a hexagon, each at 1x, 4x and 12x (about 250, 1000 and 3000 px). Per shape: segments against the
true count, the largest deviation from the exact outline (px), and the time of each trace (CPU seconds of this
process; potrace's CLI in wall seconds).

    .venv/bin/python benchmarks/bench_jumps.py [--scales 1,4,12] [--rotate DEGREES] [--no-potrace]

``--refits``: the cost control instead. The quick held-out glyph set (``heldout_shapes``, 3 per family, one
scan each) traced with ``curvature_jumps=True`` (every outline), once with ``REFIT_MARGIN`` = 0 (every outline
with a jump is refitted) and once at its value: refits run, refits kept, segments in all, CPU seconds.
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import splinecraft as sc  # noqa: E402
import synthetic_shapes as S  # noqa: E402


def stadium(name, width, height):
    """Two straight sides and two half circles (6 true segments)."""
    radius = height / 2
    right, left = (width - radius, radius), (radius, radius)
    pieces = [S._line((radius, 0), (width - radius, 0)), S._arc(right, radius, -np.pi / 2, np.pi / 2),
              S._line((width - radius, height), (radius, height)), S._arc(left, radius, np.pi / 2, 1.5 * np.pi)]
    points, corners = S._contour_from_pieces(pieces)
    return S._shape(name, [points], corners, segments=6)


def rotated(shape, degrees):
    """The shape turned by ``degrees`` about the origin of its outline, re-framed (exact outline and corners)."""
    if not degrees:
        return shape
    a = np.radians(degrees)
    turn = np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])
    contours = [np.asarray(c) @ turn for c in shape["contours"]]
    corners = [tuple(np.asarray(c) @ turn) for c in shape["corners"]]
    return S._shape(f"{shape['name']}_r{degrees:g}", contours, corners, segments=shape["segments"])


def shapes(scales, degrees=0.0):
    return [rotated(shape, degrees) for shape in _upright(scales)]


def _upright(scales):
    out = []
    for k in scales:
        out += [S.rounded_rect(f"rounded_a_{k}x", 200 * k, 120 * k, 20 * k),
                S.rounded_rect(f"rounded_b_{k}x", 240 * k, 160 * k, 50 * k),
                stadium(f"stadium_{k}x", 240 * k, 90 * k),
                S.ellipse(f"ellipse_{k}x", 110 * k, 60 * k, 0.3),
                S.ring(f"ring_{k}x", 100 * k, 60 * k),
                S.d_shape(f"D_{k}x", 200 * k),
                S.star(f"star_{k}x", 5, 110 * k, 45 * k),
                S.regular_polygon(f"hexagon_{k}x", 6, 100 * k, 0.2)]
    return out


def trace(mask, jumps):
    start = time.process_time()
    result = sc.trace(mask, fit_params=None if jumps else {"curvature_jumps": False}, time_budget=None)
    return [np.asarray(s.bezier()) for s in result.splines], time.process_time() - start


def refits():
    import heldout_shapes as H
    from splinecraft.capture.fitting import lsq

    masks = [s["mask"] if "mask" in s else H.rasterize(s) for s in H.heldout_set(per_family=3, scans=1)]
    sc.trace(masks[0])  # compiled kernels loaded before the first measurement
    print("| REFIT_MARGIN | refits | kept | segments | CPU s |")
    print("|---|---|---|---|---|")
    kept_value = lsq.REFIT_MARGIN
    for margin in (0, kept_value, None):
        lsq.REFIT_MARGIN = kept_value if margin is None else margin
        tried = kept = segments = 0
        start = time.process_time()
        for mask in masks:
            result = sc.trace(mask, fit_params={"curvature_jumps": margin is not None})
            records = [f.info["curvature_jumps"] for f in result.fits if "curvature_jumps" in f.info]
            tried += len(records)
            kept += sum(r["kept"] for r in records)
            segments += sum(len(s.bezier()) for s in result.splines)
        label = "off (`curvature_jumps=False`)" if margin is None else str(margin)
        print(f"| {label} | {tried} | {kept} | {segments} | {time.process_time() - start:.2f} |", flush=True)
    lsq.REFIT_MARGIN = kept_value


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scales", default="1,4,12")
    parser.add_argument("--no-potrace", action="store_true")
    parser.add_argument("--rotate", type=float, default=0.0, help="turn every shape by this many degrees")
    parser.add_argument("--refits", action="store_true", help="the cost control on held-out glyphs instead")
    args = parser.parse_args(argv)
    if args.refits:
        return refits()
    use_potrace = not args.no_potrace and shutil.which("potrace")
    rows = []
    trace(S.rasterize(shapes([1])[0]), True)  # compiled kernels loaded before the first measurement
    print("| shape | true | off: segments / max px / s | default: segments / max px / s "
          "| potrace: segments / max px |")
    print("|---|---|---|---|---|")
    for shape in shapes([int(k) for k in args.scales.split(",")], args.rotate):
        mask = S.rasterize(shape)
        cells = []
        for jumps in (False, True):
            beziers, seconds = trace(mask, jumps)
            score = S.score_beziers(shape, beziers)
            cells.append((score["segments"], score["max_dev"], seconds))
        if use_potrace:
            svg, _ = S.run_potrace(mask)
            score = S.score_beziers(shape, S.svg_beziers(svg))
            cells.append((score["segments"], score["max_dev"], float("nan")))
        rows.append((shape, cells))
        text = " | ".join(f"{c[0]} / {c[1]:.2f}" + ("" if np.isnan(c[2]) else f" / {c[2]:.3f}") for c in cells)
        print(f"| {shape['name']} | {shape['segments']} | {text} |", flush=True)
    ratio = lambda k: np.median([c[k][0] / s["segments"] for s, c in rows])  # noqa: E731
    print(f"\nMedian segments per true segment: off {ratio(0):.2f}, default {ratio(1):.2f}"
          + (f", potrace {ratio(2):.2f}" if use_potrace else ""))
    print(f"Largest deviation (px): off {max(c[0][1] for _, c in rows):.2f}, "
          f"default {max(c[1][1] for _, c in rows):.2f}" + (f", potrace {max(c[2][1] for _, c in rows):.2f}"
                                                           if use_potrace else ""))
    print(f"CPU time default / off, summed: {sum(c[1][2] for _, c in rows) / sum(c[0][2] for _, c in rows):.2f}")


if __name__ == "__main__":
    main()
