"""Outline capture quality: ``sc.trace`` at its defaults vs Debian's potrace, scored by the yardstick.

    .venv/bin/python benchmarks/bench_yardstick.py                       # yardstick (if present) + synthetic set
    .venv/bin/python benchmarks/bench_yardstick.py --yardstick DIR --repeat 5 --out benchmarks/out
    .venv/bin/python benchmarks/bench_yardstick.py --no-synthetic        # yardstick only
    .venv/bin/python benchmarks/bench_yardstick.py --no-yardstick        # synthetic set only (no external data)

A third part compares all knot methods (``KNOT_METHODS``) on six synthetic shapes at the default epsilon:
knots, iterations, convergence, deviation and time, relative to the default ``"lsq"``.

Yardstick (``--yardstick``, default ``../shared/yardstick`` next to the repository; skipped with a message when
absent): every ``shapes/*.png`` is traced by :func:`splinecraft.trace` with all defaults, written to
``benchmarks/out/NAME.svg`` and scored with the yardstick's own ``score_svg.py`` (imported by path): symmetric
Hausdorff ``max_dev`` and pooled ``rms_dev`` to the true outline, segment count, corners = joins turning by more
than 30 deg, matched within 3 px. The same bitmap goes to ``potrace -b svg`` at its defaults (PBM input made with
PIL; potrace writes a transform into the pixel frame, which the scorer applies), written to
``benchmarks/out/NAME.potrace.svg``. Time: ours is the in-process ``sc.trace`` call (median of ``--repeat``
runs, the bitmap already loaded), potrace's is the CLI process (median of ``--repeat`` runs, process start
included), side by side in the same run. Nothing is tuned here: the defaults were chosen on the synthetic set.

Synthetic set (``benchmarks/synthetic_shapes.py``, the set the fit was tuned on; no external data): the same
comparison with this project's own scorer (same metrics, independent code).
"""
from __future__ import annotations

import argparse
import glob
import importlib.util
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "src"))
sys.path.insert(0, HERE)

import splinecraft as sc  # noqa: E402


def _load_scorer(yardstick):
    sys.path.insert(0, yardstick)
    spec = importlib.util.spec_from_file_location("yardstick_score_svg", os.path.join(yardstick, "score_svg.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _ensure_potrace():
    exe = shutil.which("potrace")
    if exe is None:
        subprocess.run(["bash", os.path.join(ROOT, "scripts", "system-deps.sh"), "potrace"], check=False)
        exe = shutil.which("potrace")
    return exe


def _potrace(exe, mask, repeat):
    with tempfile.TemporaryDirectory() as tmp:
        pbm = os.path.join(tmp, "in.pbm")
        Image.fromarray(~mask).convert("1").save(pbm)
        times, svg = [], None
        for _ in range(repeat):
            t0 = time.perf_counter()
            svg = subprocess.run([exe, "-b", "svg", "-o", "-", pbm], check=True, capture_output=True).stdout
            times.append(time.perf_counter() - t0)
        return svg.decode(), statistics.median(times)


def _ours(mask, repeat):
    times, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = sc.trace(mask)
        times.append(time.perf_counter() - t0)
    return result, statistics.median(times)


def _f1(rows, key):
    values = [r[key] for r in rows if r.get(key) is not None]
    return values


def _summary(rows, prefix):
    seg = [r[prefix + "segments"] for r in rows]
    md = np.array([r[prefix + "max_dev"] for r in rows])
    rms = [r[prefix + "rms_dev"] for r in rows]
    f1 = [r[prefix + "corner_f1"] for r in rows if r.get(prefix + "corner_f1") is not None]
    tp = sum(r.get(prefix + "corner_tp") or 0 for r in rows)
    found = sum(r.get(prefix + "corners") or 0 for r in rows)
    truth = sum(r.get(prefix + "true_corners") or 0 for r in rows)
    pooled = 2 * tp / (found + truth) if found + truth else float("nan")
    return {
        "segments": statistics.median(seg), "max_dev": float(np.median(md)), "max_dev_mean": float(md.mean()),
        "within_1px": float(np.mean(md <= 1.0)), "rms": float(np.median(rms)),
        "f1_median": float(np.median(f1)) if f1 else float("nan"), "f1_mean": float(np.mean(f1)) if f1 else float("nan"),
        "f1_pooled": pooled, "time": statistics.median(r[prefix + "time"] for r in rows),
    }


def _print_table(rows, title, ours_label="splinecraft", glyph_times=None):
    print(f"\n### {title}\n")
    print(f"| shape | segments (ours / potrace) | max_dev px | rms px | corner F1 | time ms (ours in-process / "
          f"potrace CLI) |")
    print("|---|---|---|---|---|---|")

    def f(value, digits=2):
        return "-" if value is None else f"{value:.{digits}f}"

    for r in rows:
        print(f"| {r['name']} | {r['o_segments']} / {r['p_segments']} | {f(r['o_max_dev'])} / {f(r['p_max_dev'])} | "
              f"{f(r['o_rms_dev'], 3)} / {f(r['p_rms_dev'], 3)} | {f(r.get('o_corner_f1'))} / "
              f"{f(r.get('p_corner_f1'))} | {1e3 * r['o_time']:.1f} / {1e3 * r['p_time']:.1f} |")
    o, p = _summary(rows, "o_"), _summary(rows, "p_")
    print(f"| **median** | **{o['segments']:g} / {p['segments']:g}** | **{o['max_dev']:.2f} / {p['max_dev']:.2f}** "
          f"| **{o['rms']:.3f} / {p['rms']:.3f}** | **{o['f1_median']:.2f} / {p['f1_median']:.2f}** | "
          f"**{1e3 * o['time']:.1f} / {1e3 * p['time']:.1f}** |")
    print()
    print(f"| summary ({len(rows)} shapes) | {ours_label} | potrace |")
    print("|---|---|---|")
    print(f"| shapes with max_dev <= 1 px | {100 * o['within_1px']:.0f}% | {100 * p['within_1px']:.0f}% |")
    print(f"| median / mean max_dev px | {o['max_dev']:.2f} / {o['max_dev_mean']:.2f} | "
          f"{p['max_dev']:.2f} / {p['max_dev_mean']:.2f} |")
    print(f"| median rms px | {o['rms']:.3f} | {p['rms']:.3f} |")
    print(f"| median segments | {o['segments']:g} | {p['segments']:g} |")
    print(f"| corner F1: median / mean / pooled | {o['f1_median']:.3f} / {o['f1_mean']:.3f} / {o['f1_pooled']:.3f} "
          f"| {p['f1_median']:.3f} / {p['f1_mean']:.3f} / {p['f1_pooled']:.3f} |")
    print(f"| median time ms (ours in-process, potrace CLI) | {1e3 * o['time']:.1f} | {1e3 * p['time']:.1f} |")
    if glyph_times:
        ours_g, pot_g = glyph_times
        print(f"| median time ms, glyphs only | {1e3 * statistics.median(ours_g):.1f} | "
              f"{1e3 * statistics.median(pot_g):.1f} |")
    print(f"| time ratio ours / potrace (medians) | {o['time'] / p['time']:.2f} | 1 |")
    return o, p


def run_yardstick(yardstick, out_dir, repeat, potrace):
    shapes = sorted(glob.glob(os.path.join(yardstick, "shapes", "*.png")))
    if not shapes:
        print(f"yardstick: no shapes/*.png under {yardstick}; skipped")
        return None
    scorer = _load_scorer(yardstick)
    rows, glyph_ours, glyph_pot = [], [], []
    breakdown = []
    for png in shapes:
        name = os.path.splitext(os.path.basename(png))[0]
        truth = os.path.join(yardstick, "shapes", name + ".json")
        mask = sc.load_bitmap(png)
        result, t_ours = _ours(mask, repeat)
        svg = result.to_svg()
        with open(os.path.join(out_dir, name + ".svg"), "w") as fh:
            fh.write(svg)
        ours = scorer.score(truth, svg)
        p_svg, t_pot = _potrace(potrace, mask, repeat)
        with open(os.path.join(out_dir, name + ".potrace.svg"), "w") as fh:
            fh.write(p_svg)
        pot = scorer.score(truth, p_svg)
        row = {"name": name, "o_time": t_ours, "p_time": t_pot}
        row.update({"o_" + k: v for k, v in ours.items()})
        row.update({"p_" + k: v for k, v in pot.items()})
        rows.append(row)
        breakdown.append(result.stats.get("time_breakdown", {}))
        if len(name) == 1:
            glyph_ours.append(t_ours)
            glyph_pot.append(t_pot)
    o, p = _print_table(rows, f"Yardstick ({yardstick}): sc.trace defaults vs potrace 1.16 defaults",
                        glyph_times=(glyph_ours, glyph_pot))
    if breakdown and all(breakdown):
        keys = breakdown[0].keys()
        print("\nIn-process time split, median over shapes (ms): "
              + ", ".join(f"{k} {1e3 * statistics.median(b[k] for b in breakdown):.1f}" for k in keys))
    return rows


def run_synthetic(repeat, potrace):
    import synthetic_shapes as S

    rows, glyph_ours, glyph_pot = [], [], []
    for shape in S.tuning_set():
        mask = S.rasterize(shape)
        result, t_ours = _ours(mask, repeat)
        ours = S.score_beziers(shape, [np.asarray(s.bezier()) for s in result.splines])
        p_svg, t_pot = _potrace(potrace, mask, repeat)
        pot = S.score_beziers(shape, S.svg_beziers(p_svg))
        row = {"name": shape["name"], "o_time": t_ours, "p_time": t_pot}
        row.update({"o_" + k: v for k, v in ours.items()})
        row.update({"p_" + k: v for k, v in pot.items()})
        row["o_corner_tp"] = round(ours["corner_r"] * ours["true_corners"])
        row["p_corner_tp"] = round(pot["corner_r"] * pot["true_corners"])
        rows.append(row)
        if "_300" in shape["name"]:
            glyph_ours.append(t_ours)
            glyph_pot.append(t_pot)
    _print_table(rows, "Synthetic tuning set (benchmarks/synthetic_shapes.py): sc.trace defaults vs potrace",
                 glyph_times=(glyph_ours, glyph_pot))
    return rows


def run_methods(epsilon=None, seeds=3, max_iterations=500):
    """All knot methods on a few synthetic shapes at the default epsilon: knots, iterations, time, deviation."""
    import synthetic_shapes as S
    from splinecraft.capture.fitting import DEFAULT_EPSILON, KNOT_METHODS, fit_outline

    names = ("disc40", "star5", "blob1", "roundrect", "Sans-Bold_D_300", "Serif_S_300")
    shapes = [s for s in S.tuning_set() if s["name"] in names]
    contours = []
    for shape in shapes:
        mask = S.rasterize(shape)
        for b in sc.trace_boundaries(mask):
            contours.append((shape["name"], b.outline, sc.corners(b.outline, method="tangent-jump")))
    epsilon = DEFAULT_EPSILON if epsilon is None else epsilon
    print(f"\n### Knot methods on {len(shapes)} synthetic shapes ({len(contours)} contours), epsilon = "
          f"{epsilon}, corners by tangent-jump, max_iterations = {max_iterations}, {seeds} seeds for "
          f"the random methods\n")
    print("| method | knots (corners + inserted), sum | iterations, max over contours (mean over seeds) | "
          "converged | max deviation px (max) | time ms (sum) | knots / lsq | time / lsq |")
    print("|---|---|---|---|---|---|---|---|")
    base = None
    for method in KNOT_METHODS:
        knots, iters, conv, dev, times = [], [], [], [], []
        for seed in (range(seeds) if method != "lsq" else [0]):
            k = it = 0
            ok, worst, elapsed = True, 0.0, 0.0
            for _, outline, corners in contours:
                t0 = time.perf_counter()
                fit = fit_outline(outline, corners, epsilon=epsilon, method=method, seed=seed,
                                  max_iterations=max_iterations, keep_snapshots=False)
                elapsed += time.perf_counter() - t0
                k += len(fit.corners_used) + fit.knots_inserted
                it = max(it, fit.iterations)
                ok &= fit.converged
                worst = max(worst, fit.hausdorff)
            knots.append(k)
            iters.append(it)
            conv.append(ok)
            dev.append(worst)
            times.append(elapsed)
        row = (np.mean(knots), np.mean(iters), np.mean(conv), max(dev), 1e3 * np.mean(times))
        if base is None:
            base = row
        print(f"| {method} | {row[0]:.0f} | {row[1]:.1f} | {100 * row[2]:.0f}% | {row[3]:.2f} | {row[4]:.0f} | "
              f"{row[0] / base[0]:.2f} | {row[4] / base[4]:.1f} |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--yardstick", default=os.path.join(ROOT, "..", "shared", "yardstick"))
    parser.add_argument("--out", default=os.path.join(HERE, "out"))
    parser.add_argument("--repeat", type=int, default=5, help="timing runs per shape (median)")
    parser.add_argument("--no-yardstick", action="store_true")
    parser.add_argument("--no-synthetic", action="store_true")
    parser.add_argument("--no-methods", action="store_true", help="skip the comparison of the knot methods")
    args = parser.parse_args(argv)
    potrace = _ensure_potrace()
    if potrace is None:
        sys.exit("potrace is not installed and scripts/system-deps.sh potrace failed")
    version = subprocess.run([potrace, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    print(f"splinecraft trace defaults: epsilon={sc.capture.fitting.DEFAULT_EPSILON} "
          f"method={sc.capture.fitting.DEFAULT_METHOD!r}; peer: {version} (-b svg, defaults); "
          f"timing: median of {args.repeat} runs")
    os.makedirs(args.out, exist_ok=True)
    if not args.no_yardstick:
        yardstick = os.path.abspath(args.yardstick)
        if os.path.isdir(yardstick):
            run_yardstick(yardstick, args.out, args.repeat, potrace)
        else:
            print(f"\nyardstick not found at {yardstick}: skipped (pass --yardstick DIR)")
    if not args.no_synthetic:
        run_synthetic(args.repeat, potrace)
    if not args.no_methods:
        run_methods()
        run_methods(2.0)


if __name__ == "__main__":
    main()
