"""Outline capture against its peers, side by side in one run: ``sc.trace`` at its defaults, potrace (Debian
CLI), vtracer and autotrace (Python packages), on the yardstick's ``shapes/`` and ``shapes2/`` and on a
held-out set of other font families and scripts (``heldout_shapes.py``; nothing is tuned on it).

    .venv/bin/python benchmarks/bench_peers.py                        # all sets, all tools, 3 timing runs
    .venv/bin/python benchmarks/bench_peers.py --sets shapes2 --tools splinecraft,potrace --repeat 1
    .venv/bin/python benchmarks/bench_peers.py --json out.json        # also every row as JSON
    .venv/bin/python benchmarks/bench_peers.py --tools splinecraft,pixels  # against the raw pixel staircase

``pixels`` (not among the default tools) is the bitmap's own crack outline, each boundary's polygon of pixel
corners: the raw staircase a tracer must stay closer to the truth than (on scans, its rms).

The peers are set up by the script itself, not as user dependencies: ``scripts/system-deps.sh potrace`` and
the held-out fonts (``heldout_shapes.FONT_PACKAGES``), and ``pip install vtracer pyautotrace fonttools`` into
the running interpreter's environment when they are missing.

Per shape and tool: the traced SVG (pixel frame) is scored against the exact outline by the yardstick's
``score_svg.py`` when the yardstick is present (``--yardstick``), else by ``synthetic_shapes.score_beziers``
(same metrics, independent code). Reported per group, per tool:

* **within 1 px**: share of shapes whose symmetric Hausdorff distance to the true outline is <= 1 px;
* **rms**: median over shapes of the pooled RMS distance (px);
* **seg / truth**: median over shapes of the segment count divided by the true outline's;
* **corner F1**: pooled over the group's shapes (``2 tp / (found + true)``, joins turning > 30 deg matched
  one-to-one within 3 px);
* **time / potrace**: median over shapes of the tool's time divided by potrace's on the same bitmap, both
  medians of ``--repeat`` runs (``--stat min``: the fastest), the tools interleaved shape by shape: ``sc.trace``,
  vtracer and autotrace in process (the bitmap already
  in memory; vtracer's PNG encoding excluded), potrace as a CLI process (start and file I/O included).
  Elapsed time by default; ``--clock cpu`` takes CPU time instead (this process's, plus the CLI process's
  user and system time), which a loaded machine inflates far less than the elapsed time of short calls.

Groups come from the shapes' JSON ``source``: ``scan`` (scan-like), ``rotated``, ``small`` (cap height <=
64 px), ``large`` (>= 600 px), ``oblique``, ``serif``, ``sans`` (DejaVu Sans at 300 px) and ``analytic``;
held-out shapes are grouped by family (upright 300 px) or by the same kinds.
"""
from __future__ import annotations

import argparse
import glob
import importlib
import importlib.util
import io
import json
import os
import re
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

TOOLS = ("splinecraft", "potrace", "vtracer", "autotrace")
GROUP_ORDER = ("sans", "analytic", "serif", "oblique", "small", "large", "rotated", "scan",
               "oldstyle", "italic", "boldsans", "freeserif", "arabic", "cjk")


# ------------------------------------------------------------------------------------------- set-up
def _pip_install(*packages):
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", *packages], check=False)
    importlib.invalidate_caches()


def ensure_peers(tools, fonts=True):
    """Install what the chosen tools need (Debian packages through scripts/system-deps.sh, pip packages into
    this interpreter's environment); returns the potrace executable or None."""
    debs = []
    if "potrace" in tools and shutil.which("potrace") is None:
        debs.append("potrace")
    if fonts:
        import heldout_shapes  # noqa: F401  (only the package list)
        if not heldout_shapes.available_families():
            debs.extend(heldout_shapes.FONT_PACKAGES)
    if debs:
        subprocess.run(["bash", os.path.join(ROOT, "scripts", "system-deps.sh"), *debs], check=False)
    wanted = {"vtracer": "vtracer", "autotrace": "pyautotrace"}
    missing = [pkg for tool, pkg in wanted.items() if tool in tools and importlib.util.find_spec(tool) is None]
    if fonts and importlib.util.find_spec("fontTools") is None:
        missing.append("fonttools")
    if missing:
        _pip_install(*missing)
    return shutil.which("potrace")


# ------------------------------------------------------------------------------------------- the tools
#: ``--clock``: "wall" (elapsed time) or "cpu" (this process's CPU time plus that of the child processes it
#: waited for: on a loaded machine elapsed time is mostly waiting for a core, for both tools)
CLOCK = "wall"


def _cpu_seconds():
    import resource

    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


#: ``--stat``: how the ``--repeat`` timings of one shape and tool make its time: "median", or "min" (the fastest run:
#: on a shared machine the other processes only ever add to a run's time)
STAT = "median"


def _timed(run, repeat):
    clock = _cpu_seconds if CLOCK == "cpu" else time.perf_counter
    times, out = [], None
    for _ in range(repeat):
        start = clock()
        out = run()
        times.append(clock() - start)
    return out, min(times) if STAT == "min" else statistics.median(times)


#: ``fit_params`` and ``corner_params`` of ``sc.trace`` (``--fit-params``, ``--corner-params``; empty = the
#: defaults).
FIT_PARAMS = {}
CORNER_PARAMS = {}


def run_splinecraft(mask, repeat):
    result, seconds = _timed(lambda: sc.trace(mask, fit_params=FIT_PARAMS or None,
                                              corner_params=CORNER_PARAMS or None), repeat)
    return result.to_svg(), seconds


def make_variant(params):
    """A runner of ``sc.trace`` with this variant's ``fit_params`` and ``corner_params`` (``--variants``)."""
    fit, corner = params.get("fit_params") or None, params.get("corner_params") or None

    def run(mask, repeat):
        result, seconds = _timed(lambda: sc.trace(mask, fit_params=fit, corner_params=corner), repeat)
        return result.to_svg(), seconds
    return run


def run_pixels(mask, repeat):
    """The raw pixel staircase: each boundary's crack polygon (pixel corners), the reference a fit must beat
    on scans (issue 9: "rms to the true outline below that of the raw pixel staircase")."""
    from splinecraft.capture.contour import trace_boundaries

    def once():
        paths = []
        for boundary in trace_boundaries(mask, connectivity="minority"):
            vertices = boundary.crack_vertices
            paths.append("M " + " L ".join(f"{x:g} {y:g}" for x, y in vertices) + " Z")
        height, width = mask.shape
        return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}">'
                f'<path fill-rule="evenodd" d="{" ".join(paths)}"/></svg>')
    return _timed(once, repeat)


def make_potrace(exe):
    def run(mask, repeat):
        with tempfile.TemporaryDirectory() as tmp:
            pbm = os.path.join(tmp, "in.pbm")
            Image.fromarray(~mask).convert("1").save(pbm)
            out, seconds = _timed(lambda: subprocess.run([exe, "-b", "svg", "-o", "-", pbm], check=True,
                                                         capture_output=True).stdout, repeat)
        return out.decode(), seconds
    return run


def run_vtracer(mask, repeat):
    import vtracer

    buffer = io.BytesIO()
    Image.fromarray(np.where(mask, 0, 255).astype(np.uint8)).convert("RGB").save(buffer, "png")
    data = buffer.getvalue()
    return _timed(lambda: vtracer.convert_raw_image_to_svg(data, img_format="png", colormode="binary"), repeat)


def run_autotrace(mask, repeat):
    import autotrace

    rgb = np.repeat(np.where(mask, 0, 255).astype(np.uint8)[..., None], 3, axis=2)

    def once():
        vector = autotrace.Bitmap(rgb).trace(background_color=(255, 255, 255))
        return vector.encode(autotrace.VectorFormat.SVG).decode()
    return _timed(once, repeat)


# ------------------------------------------------------------------------------------------- shapes
def _group_of_source(source):
    """Group of a yardstick shape from its JSON ``source`` (precedence: scan, rotated, small, large, oblique,
    serif, sans, analytic)."""
    if source == "analytic":
        return "analytic"
    if "scan-like" in source:
        return "scan"
    if "rotated" in source:
        return "rotated"
    cap = re.search(r"cap (\d+) px", source)
    if cap and int(cap.group(1)) <= 64:
        return "small"
    if cap and int(cap.group(1)) >= 600:
        return "large"
    if "Oblique" in source:
        return "oblique"
    if "Serif" in source:
        return "serif"
    return "sans"


def yardstick_shapes(yardstick, subset):
    shapes = []
    for js in sorted(glob.glob(os.path.join(yardstick, subset, "*.json"))):
        with open(js) as handle:
            truth = json.load(handle)
        png = js[:-5] + ".png"
        shapes.append({"name": truth["name"], "set": subset, "group": _group_of_source(truth["source"]),
                       "mask": sc.load_bitmap(png), "truth": truth,
                       "segments": sum(len(c["segments"]) for c in truth["contours"])})
    return shapes


def heldout(quick=False):
    import heldout_shapes as H

    kwargs = dict(per_family=3, scans=1) if quick else {}
    shapes = []
    for shape in H.heldout_set(**kwargs):
        mask = shape["mask"] if "mask" in shape else H.rasterize(shape)
        truth = {"contours": [{"dense": np.asarray(c)} for c in shape["contours"]],
                 "corners": [{"x": x, "y": y} for x, y in shape["corners"]]}
        shapes.append({"name": shape["name"], "set": "heldout", "group": shape["group"], "mask": mask,
                       "truth": truth, "shape": shape, "segments": shape["segments"]})
    return shapes


# ------------------------------------------------------------------------------------------- scoring
def make_scorer(yardstick):
    path = os.path.join(yardstick, "score_svg.py") if yardstick else ""
    if os.path.isfile(path):
        sys.path.insert(0, yardstick)
        spec = importlib.util.spec_from_file_location("yardstick_score_svg", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return (lambda entry, svg: module.score_subpaths(entry["truth"], module.read_svg(svg))), "yardstick"
    import synthetic_shapes as S

    def project(entry, svg):
        truth = entry["truth"]
        shape = {"contours": [np.asarray(c["dense"]) for c in truth["contours"]],
                 "corners": [(c["x"], c["y"]) for c in truth["corners"] or []]}
        res = S.score_beziers(shape, S.svg_beziers(svg))
        res["corner_tp"] = round((res["corner_r"] or 0) * res["true_corners"])
        return res
    return project, "project (synthetic_shapes.score_beziers)"


def measure(shapes, tools, runners, scorer, repeat, out_dir=None):
    rows = []
    for entry in shapes:
        for tool in tools:
            try:
                svg, seconds = runners[tool](entry["mask"], repeat)
                score = scorer(entry, svg)
            except Exception as exc:  # a peer failing on a shape is a result, not a crash of the benchmark
                print(f"# {tool} failed on {entry['name']}: {type(exc).__name__}: {exc}", file=sys.stderr)
                score, seconds, svg = {"max_dev": float("inf"), "rms_dev": float("inf"), "segments": 0}, float("nan"), ""
            if out_dir:
                with open(os.path.join(out_dir, f"{entry['set']}_{entry['name']}.{tool}.svg"), "w") as handle:
                    handle.write(svg)
            rows.append({"set": entry["set"], "name": entry["name"], "group": entry["group"], "tool": tool,
                         "true_segments": entry["segments"], "time": seconds,
                         **{k: score.get(k) for k in ("segments", "max_dev", "rms_dev", "corners", "true_corners",
                                                       "corner_tp", "corner_f1")}})
    return rows


def summarize(rows, tool):
    """Figures of one tool over a list of rows (one set or group)."""
    mine = [r for r in rows if r["tool"] == tool]
    pot = {(r["set"], r["name"]): r["time"] for r in rows if r["tool"] == "potrace"}
    dev = np.array([r["max_dev"] for r in mine], float)
    ratio = [r["segments"] / r["true_segments"] for r in mine if r["true_segments"]]
    tp = sum(r["corner_tp"] or 0 for r in mine if r["true_corners"] is not None)
    found = sum(r["corners"] or 0 for r in mine if r["true_corners"] is not None)
    truth = sum(r["true_corners"] or 0 for r in mine if r["true_corners"] is not None)
    times = [r["time"] / pot[(r["set"], r["name"])] for r in mine if pot.get((r["set"], r["name"]))]
    return {"n": len(mine), "within_1px": float(np.mean(dev <= 1.0)) if len(dev) else float("nan"),
            "rms": float(np.median([r["rms_dev"] for r in mine])) if mine else float("nan"),
            "seg_ratio": float(np.median(ratio)) if ratio else float("nan"),
            "f1": 2 * tp / (found + truth) if found + truth else float("nan"),
            "time_ratio": float(np.median(times)) if times else float("nan"),
            "time_ms": 1e3 * float(np.median([r["time"] for r in mine])) if mine else float("nan")}


def print_tables(rows, tools, title):
    print(f"\n### {title}\n")
    print("| group | n | " + " | ".join(tools) + " |")
    print("|---|---|" + "---|" * len(tools))
    groups = sorted({r["group"] for r in rows}, key=lambda g: GROUP_ORDER.index(g) if g in GROUP_ORDER else 99)
    for label, subset in [(g, [r for r in rows if r["group"] == g]) for g in groups] + [("**all**", rows)]:
        cells = []
        for tool in tools:
            s = summarize(subset, tool)
            cells.append(f"{100 * s['within_1px']:.0f}% / {s['rms']:.3f} / {s['seg_ratio']:.2f} / {s['f1']:.2f} / "
                         f"{s['time_ratio']:.2f}")
        print(f"| {label} | {summarize(subset, tools[0])['n']} | " + " | ".join(cells) + " |")
    print("\nCells: within 1 px / median rms px / median segments per true segment / pooled corner F1 / "
          "median time ratio to potrace's CLI.")
    print_glyph_times(rows, tools, "Median time per 300-px upright glyph")


#: The groups of upright 300-px glyphs (yardstick sans, serif and oblique; the held-out families).
GLYPH_GROUPS = ("sans", "serif", "oblique", "oldstyle", "italic", "boldsans", "freeserif", "arabic", "cjk")


def print_glyph_times(rows, tools, label):
    """The median time of the upright 300-px glyphs among ``rows``, per tool, and its median ratio to potrace's
    (the target of issue 9: a 300-px glyph within 2.5x potrace's CLI time)."""
    glyphs = [r for r in rows if r["group"] in GLYPH_GROUPS]
    if glyphs and "potrace" in tools:
        print(f"\n{label} (ms): " + ", ".join(
            f"{tool} {summarize(glyphs, tool)['time_ms']:.1f}" for tool in tools)
            + "; ratio to potrace: " + ", ".join(f"{tool} {summarize(glyphs, tool)['time_ratio']:.2f}" for tool in tools))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--yardstick", default=os.path.join(ROOT, "..", "shared", "yardstick"))
    parser.add_argument("--sets", default="shapes,shapes2,heldout")
    parser.add_argument("--tools", default=",".join(TOOLS))
    parser.add_argument("--repeat", type=int, default=3, help="timing runs per shape and tool (median)")
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                        help="wall: elapsed time; cpu: CPU time of this process and of the CLI processes it runs "
                             "(for a loaded machine, where elapsed time is mostly waiting for a core)")
    parser.add_argument("--stat", choices=("median", "min"), default="median",
                        help="a shape's time from its --repeat runs: their median, or the fastest (a shared machine's "
                             "other processes only add time)")
    parser.add_argument("--quick", action="store_true", help="a smaller held-out set")
    parser.add_argument("--out", default=None, help="folder for the traced SVGs")
    parser.add_argument("--json", default=None, help="write every row to this JSON file")
    parser.add_argument("--fit-params", default="{}", help="JSON dict of sc.trace's fit_params (default: none)")
    parser.add_argument("--corner-params", default="{}",
                        help="JSON dict of sc.trace's corner_params (default: none)")
    parser.add_argument("--variants", default="[]",
                        help="JSON list of {\"fit_params\": {...}, \"corner_params\": {...}}: sc.trace once per "
                        "variant, interleaved shape by shape, as the tools splinecraft[0], splinecraft[1], ...")
    args = parser.parse_args(argv)
    global CLOCK, STAT
    CLOCK, STAT = args.clock, args.stat
    variants = json.loads(args.variants)
    FIT_PARAMS.update(json.loads(args.fit_params))
    CORNER_PARAMS.update(json.loads(args.corner_params))
    tools = [t for t in args.tools.split(",") if t]
    if variants:
        tools = [f"splinecraft[{k}]" for k in range(len(variants))] + [t for t in tools if t != "splinecraft"]
    sets = [s for s in args.sets.split(",") if s]
    if "potrace" not in tools:
        tools.append("potrace")                       # the time ratios need it
    potrace = ensure_peers(tools, fonts="heldout" in sets)
    if potrace is None:
        sys.exit("potrace is not installed and scripts/system-deps.sh potrace failed")
    runners = {"splinecraft": run_splinecraft, "potrace": make_potrace(potrace), "vtracer": run_vtracer,
               "autotrace": run_autotrace, "pixels": run_pixels}
    runners.update({f"splinecraft[{k}]": make_variant(v) for k, v in enumerate(variants)})
    for k, v in enumerate(variants):
        print(f"splinecraft[{k}]: {json.dumps(v)}")
    yardstick = os.path.abspath(args.yardstick)
    scorer, scorer_name = make_scorer(yardstick if os.path.isdir(yardstick) else None)
    version = subprocess.run([potrace, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    print(f"splinecraft {getattr(sc, '__version__', '')} sc.trace defaults; {version}; scorer: {scorer_name}; "
          f"timing: {args.stat} of {args.repeat} runs ({args.clock} clock)")
    if args.out:
        os.makedirs(args.out, exist_ok=True)
    all_rows = []
    for name in sets:
        if name == "heldout":
            shapes = heldout(args.quick)
        elif os.path.isdir(os.path.join(yardstick, name)):
            shapes = yardstick_shapes(yardstick, name)
        else:
            print(f"\n{name}: not found under {yardstick}; skipped")
            continue
        rows = measure(shapes, tools, runners, scorer, args.repeat, args.out)
        all_rows.extend(rows)
        print_tables(rows, tools, f"{name} ({len(shapes)} shapes)")
    if not all_rows:  # every set skipped: say so, not an empty report (a tree outside the repository's folder)
        sys.exit(f"no set measured: none of {sets} found under {yardstick} (--yardstick names the folder)")
    if len({r["set"] for r in all_rows if r["group"] in GLYPH_GROUPS}) > 1:
        print_glyph_times(all_rows, tools, f"All sets: median time per 300-px upright glyph "
                          f"({len({(r['set'], r['name']) for r in all_rows if r['group'] in GLYPH_GROUPS})} glyphs)")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(all_rows, handle, indent=1, default=float)


if __name__ == "__main__":
    main()
