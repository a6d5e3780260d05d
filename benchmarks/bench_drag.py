"""SplineEditor drag round trip in a real browser (issue 4): pointer move -> new curve drawn.

A real JupyterLab server and Debian's chromium (Playwright) open a notebook with a ``SplineEditor`` of n
points (interpolant, chord knots, control polygon and knots shown). The benchmark presses the mouse on a
point in the middle and moves it 200 times by a few pixels. For every move the page records, with
``performance.now()`` (``window.__splinecraft.dragLatencies``, written by ``js/spline_editor.js``):

* ``dom``   -- from the ``pointermove`` event to the moment the redrawn curve path for that move is in the
  DOM: the page throttles to the next animation frame, sends the position to the kernel, the kernel
  validates it, rebuilds the spline with the engine and sends back the Bézier pieces and overlays as
  float32 buffers, and the page rewrites the SVG path;
* ``frame`` -- ``dom`` plus the wait for the next animation frame (when that path is painted);
* ``frames`` -- the same, frame-aligned: from the start of the animation frame the move came in
  (``document.timeline.currentTime``) to the start of the frame whose callbacks see the new path (its
  ``requestAnimationFrame`` timestamp), a whole number of frame intervals. The table gives its median in
  frames and the share of moves painted in the very next frame: ``frame`` above has a floor of one
  interval plus the callback's own delay after the frame start, this one does not.

Each move waits until its own round trip is drawn before the next one, so latencies do not queue.
The first 10 moves warm up and are dropped. The kernel-side handling time of one drag message is
measured separately in this process (no browser, no network) for comparison.

    .venv/bin/python benchmarks/bench_drag.py                    # n = 10, 100, 1000; 200 moves each
    .venv/bin/python benchmarks/bench_drag.py --sizes 100 --moves 50
    .venv/bin/python benchmarks/bench_drag.py --compare /tmp/old   # this tree vs a checkout of another commit

``--trace`` records a Chrome trace of each row's moves and adds the page's CPU (thread time) per move: its
main thread (scripts, style, layout, paint records) and the raster workers (the tiles of what was painted).
CPU time is what a change of the page's work changes; unlike the latencies it hardly depends on the load.

``--transport`` measures instead what the size of a kernel -> page message costs (to decide when a drag
sends its geometry whole rather than as changed rows): debug pings whose answers carry 0, 4, 40 and 400 kB,
``--moves`` of each per row, with the CPU per message of the kernel and of the server (``/proc``, Linux) and
of the page (Chrome trace), and the round trip.

``--compare DIR`` measures this tree and the checkout ``DIR`` (e.g. ``git worktree add /tmp/old <commit>``)
side by side on one TCP_NODELAY server: the notebook of each row puts ``DIR/src`` first on the kernel's
``sys.path`` (its ES modules come from ``DIR/js``), the rows alternate per size and ``--rounds`` repeats them
with the order swapped, and the kernel handler is timed in a subprocess per tree. The editor is created with
``debug=True`` (the page's latency records and ping are off without it; older trees record them always).
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "browser"))
sys.path.insert(0, str(REPO / "benchmarks"))

import drag_breakdown  # noqa: E402

WARMUP = 10


def spiral_points(n: int) -> np.ndarray:
    theta = np.linspace(0.0, 6.0 * np.pi, n)
    radius = 40.0 + 260.0 * np.linspace(0.0, 1.0, n)
    if n > 12:
        return np.c_[400.0 + radius * np.cos(theta), 320.0 + radius * np.sin(theta)].round(3)
    return np.c_[np.linspace(40.0, 760.0, n), 320.0 + 180.0 * np.sin(np.linspace(0.0, 3.0, n))].round(3)


def points_cell(n: int, src: str | None = None) -> str:
    prefix = f"import sys\nsys.path.insert(0, {src!r})\n" if src else ""
    return f"""\
{prefix}import numpy as np
import splinecraft as sc
points = np.array({spiral_points(n).tolist()!r})
debug = {{"debug": True}} if "debug" in sc.SplineEditor.class_trait_names() else {{}}
editor = sc.SplineEditor(points, width=620, height=440, **debug)
editor
"""


def percentile(values, q):
    return float(np.percentile(np.asarray(values, dtype=float), q))


def drag_and_record(page, root, x: float, y: float, moves: int, trace: bool = False):
    """Press at (x, y) and move ``moves + WARMUP`` times, each move waiting for its own drawn answer.

    Returns the page's latency records of the measured moves (not the warm-up, not the release) and 50
    empty-message round trips through the same widget (the transport floor).
    """
    page.evaluate("() => { window.__splinecraft = window.__splinecraft ?? {}; window.__splinecraft.dragLatencies = []; }")
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(moves + WARMUP):
        offset = 3.0 + (k % 7)  # a small zig-zag: every move changes the point
        page.mouse.move(x + offset, y + (offset if k % 2 else -offset))
        page.wait_for_function("(count) => (window.__splinecraft.dragLatencies || []).length > count", arg=k,
                               timeout=30_000)
    page.mouse.up()
    if trace:  # the page's CPU is for the drag's moves, not for the pings
        page.context.browser.stop_tracing()
    records = page.evaluate("() => window.__splinecraft.dragLatencies")[WARMUP:WARMUP + moves]
    pings = root.evaluate("async (el) => { const out = []; for (let i = 0; i < 60; i++) out.push(await el.__splinecraft.ping()); return out.slice(10); }")
    return records, pings


#: Trace events that are whole tasks of a thread (not nested in one another): their thread time is its CPU.
_TASKS = {"RunTask": "main", "TaskGraphRunner::RunTask": "raster"}


def renderer_cpu(trace_path: Path, moves: int) -> dict:
    """Thread (CPU) time per move from a Chrome trace: the page's main thread and the raster workers (ms)."""
    events = json.loads(trace_path.read_text())
    events = events["traceEvents"] if isinstance(events, dict) else events
    names = {(e["pid"], e["tid"]): e["args"]["name"] for e in events
             if e.get("ph") == "M" and e.get("name") == "thread_name"}
    cpu = {"main": 0.0, "raster": 0.0}
    for e in events:
        kind = _TASKS.get(e.get("name"))
        if e.get("ph") != "X" or kind is None or "tdur" not in e:
            continue
        thread = names.get((e["pid"], e["tid"]), "")
        if (kind == "main" and thread == "CrRendererMain") or kind == "raster":
            cpu[kind] += e["tdur"] / 1e3
    return {key: value / moves for key, value in cpu.items()}


#: One animation frame at 60 Hz (ms): headless chromium's frame interval.
FRAME_MS = 1000.0 / 60.0

#: Trace categories: the page's tasks (CPU per move); with the V8 CPU profile for ``--breakdown``.
TRACE_CATEGORIES = ["toplevel", "disabled-by-default-devtools.timeline"]
PROFILE_CATEGORIES = TRACE_CATEGORIES + ["disabled-by-default-v8.cpu_profiler"]


def browser_round_trips(lab, n: int, moves: int, src: str | None = None, trace: bool = False,
                        breakdown: bool = False) -> dict:
    page = lab.open_notebook([points_cell(n, src)], name=f"bench_drag_{n}.ipynb")
    root = page.wait_for_selector("[data-testid=spline-editor][data-ready='1']", timeout=60_000)
    root.scroll_into_view_if_needed()
    index = n // 2
    x, y = root.evaluate("(el, i) => el.__splinecraft.screenPoint(i)", index)
    browser = page.context.browser
    if trace:
        trace_path = Path(tempfile.mkdtemp(prefix="bench-drag-")) / "trace.json"
        browser.start_tracing(page=page, path=str(trace_path),
                              categories=PROFILE_CATEGORIES if breakdown else TRACE_CATEGORIES)
    records, pings = drag_and_record(page, root, x, y, moves, trace=trace)
    cpu = {"main": float("nan"), "raster": float("nan")}
    extra = {}
    if trace:
        cpu = renderer_cpu(trace_path, moves + WARMUP)
        if breakdown:
            extra["split"] = drag_breakdown.main_thread_split(trace_path, moves + WARMUP)
            extra["no_browser_ping"] = drag_breakdown.server_round_trip(lab.server, lab.python_json("editor.comm.comm_id"))
        shutil.rmtree(trace_path.parent, ignore_errors=True)
    kernel_points = lab.python_json("len(editor.points)")
    assert kernel_points == n, kernel_points
    parts = {key: statistics.median(r[key] for r in records) for key in ("wait", "kernel", "draw")}
    dom = [r["dom"] for r in records]
    frame = [r["frame"] for r in records]
    # frame-aligned latency in frame intervals (1 = painted in the frame after the move's); older trees lack it
    frames = [r["frames"] / FRAME_MS for r in records if "frames" in r]
    return {
        "n": n, "moves": len(records), "ping_median": statistics.median(p["total"] for p in pings),
        "ping_up": statistics.median(p["up"] for p in pings), "ping_down": statistics.median(p["down"] for p in pings),
        "dom_median": statistics.median(dom), "dom_p95": percentile(dom, 95),
        "frame_median": statistics.median(frame), "frame_p95": percentile(frame, 95),
        "frames_median": statistics.median(frames) if frames else float("nan"),
        "next_frame": float(np.mean(np.round(frames) <= 1)) if frames else float("nan"),
        "wait_median": parts["wait"], "kernel_median_rt": parts["kernel"], "draw_median": parts["draw"],
        "cpu_main": cpu["main"], "cpu_raster": cpu["raster"], **extra,
    }


def kernel_handling(n: int, repeats: int = 200) -> float:
    """Median time (ms) of the kernel's drag handler alone: validate, rebuild, pack the geometry."""
    import splinecraft as sc

    editor = sc.SplineEditor(spiral_points(n))
    base = np.array(editor.points[n // 2])
    return handler_median(editor, lambda x, y: {"index": n // 2, "x": x, "y": y}, base, repeats)


def handler_median(editor, fields, base, repeats: int = 200) -> float:
    """Median time (ms) of ``editor``'s drag handler for ``repeats`` zig-zag moves around ``base``, without a
    comm (the computation only); ``fields(x, y)`` gives the message's fields naming what is dragged."""
    editor.send = lambda *args, **kwargs: None
    editor._send = lambda *args, **kwargs: None
    times = []
    for k in range(repeats):
        offset = 3.0 + (k % 7)
        message = {"type": "drag", "seq": k + 1, "gesture": 1, "final": False,
                   **fields(float(base[0] + offset), float(base[1] - offset))}
        started = time.perf_counter()
        editor._handle_message(editor, message, [])
        times.append(1e3 * (time.perf_counter() - started))
    return statistics.median(times)


def kernel_handling_of(src: str | None, sizes) -> dict:
    """:func:`kernel_handling` per size for the tree whose ``src`` is given (a subprocess: a clean import)."""
    path = [src] if src else []
    code = (f"import sys, json; sys.path[:0] = {path!r}; sys.path.insert(0, {str(REPO / 'benchmarks')!r}); "
            f"import bench_drag; print(json.dumps({{n: bench_drag.kernel_handling(n) for n in {list(sizes)!r}}}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    return {int(n): ms for n, ms in json.loads(out.strip().splitlines()[-1]).items()}


def compare(args) -> list:
    """This tree vs ``args.compare`` on one TCP_NODELAY server, alternating per size, order swapped per round."""
    from labharness import Lab, launch_chromium, start_lab

    trees = [("this tree", None), (Path(args.compare).name, str(Path(args.compare).resolve() / "src"))]
    kernel = {label: kernel_handling_of(src, args.sizes) for label, src in trees}
    rows = []
    with start_lab(nodelay=True) as server, launch_chromium() as browser:
        for round_index in range(args.rounds):
            for n in args.sizes:
                for label, src in (trees if round_index % 2 == 0 else trees[::-1]):
                    context = browser.new_context(viewport={"width": 1400, "height": 1000})
                    row = browser_round_trips(Lab(server, context.new_page()), n, args.moves, src, args.trace,
                                              args.breakdown)
                    context.close()
                    server.shutdown_kernels()
                    row.update(server=label, kernel_median=kernel[label][n], round=round_index)
                    rows.append(row)
                    print(f"round {round_index} n={n} {label}: done", file=sys.stderr, flush=True)
    return rows


#: Sizes (bytes) of the pong buffer in ``--transport``.
PAYLOADS = (0, 4_000, 40_000, 400_000)


def process_cpu_ms(pid: int) -> float:
    """User + system CPU time (ms) that process ``pid`` has used so far (Linux ``/proc``)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) * 1e3 / os.sysconf("SC_CLK_TCK")


def transport(args) -> list:
    """CPU per kernel -> page message (kernel, server, page) and round trip, by the message's size."""
    from labharness import Lab, launch_chromium, start_lab

    rows = []
    with start_lab(nodelay=True) as server, launch_chromium() as browser:
        context = browser.new_context(viewport={"width": 1400, "height": 1000})
        lab = Lab(server, context.new_page())
        page = lab.open_notebook([points_cell(10)], name="bench_transport.ipynb")
        root = page.wait_for_selector("[data-testid=spline-editor][data-ready='1']", timeout=60_000)
        kernel_pid, server_pid = lab.python_json("[__import__('os').getpid(), __import__('os').getppid()]")
        for round_index in range(args.rounds):
            for size in PAYLOADS if round_index % 2 == 0 else PAYLOADS[::-1]:
                trace_path = Path(tempfile.mkdtemp(prefix="bench-transport-")) / "trace.json"
                browser.start_tracing(page=page, path=str(trace_path),
                                      categories=["toplevel", "disabled-by-default-devtools.timeline"])
                before = process_cpu_ms(kernel_pid), process_cpu_ms(server_pid)
                trips = root.evaluate("async (el, [count, bytes]) => { const out = [];"
                                      " for (let i = 0; i < count; i++) out.push((await el.__splinecraft.ping(bytes)).total);"
                                      " return out; }", [args.moves, size])
                after = process_cpu_ms(kernel_pid), process_cpu_ms(server_pid)
                browser.stop_tracing()
                cpu = renderer_cpu(trace_path, args.moves)
                shutil.rmtree(trace_path.parent, ignore_errors=True)
                rows.append({"bytes": size, "messages": len(trips), "round_trip": statistics.median(trips),
                             "kernel": (after[0] - before[0]) / len(trips), "server": (after[1] - before[1]) / len(trips),
                             "page_main": cpu["main"], "page_raster": cpu["raster"]})
                print(f"round {round_index} {size} bytes: done", file=sys.stderr, flush=True)
    return rows


def delta_costs(sizes=(10, 30, 100, 300, 1000)) -> list:
    """Per size: the time (us, best of 5 x 200) of the row comparison of one drag move
    (:func:`splinecraft.widgets._editor_drawing.geometry_delta`, size rule off) and the Bézier + knot bytes
    sent whole and as changed rows."""
    import timeit
    from unittest import mock

    import splinecraft as sc
    from splinecraft.widgets import _editor_drawing as drawing

    rows = []
    for n in sizes:
        editor = sc.SplineEditor(spiral_points(n))
        sent = editor.geometry
        x, y = editor.points[n // 2]
        editor._handle_message(editor, {"type": "drag", "seq": 1, "gesture": 1, "final": False, "index": n // 2,
                                        "x": x + 3.0, "y": y - 3.0}, [])
        current = editor.geometry
        with mock.patch.object(drawing, "DELTA_MIN_BYTES", 0):
            delta = drawing.geometry_delta(sent, current)
            seconds = min(timeit.repeat(lambda: drawing.geometry_delta(sent, current), number=200, repeat=5)) / 200
        whole = sum(len(current[key]) for key in drawing.DELTA_ROWS)
        rows.append({"n": n, "us": 1e6 * seconds, "whole": whole,
                     "delta": sum(len(delta[f"{key}_{part}"]) for key in drawing.DELTA_ROWS for part in ("rows", "data"))})
    return rows


def print_transport(rows) -> None:
    print("| payload (kB) | messages | round trip, median (ms) | CPU per message: kernel / server / page main / page raster (ms) |")
    print("|---:|---:|---:|---|")
    for r in rows:
        print(f"| {r['bytes'] / 1e3:g} | {r['messages']} | {r['round_trip']:.1f} | "
              f"{r['kernel']:.2f} / {r['server']:.2f} / {r['page_main']:.2f} / {r['page_raster']:.2f} |")
    parts = ("kernel", "server", "page_main")
    mean = {size: {part: statistics.fmean(r[part] for r in rows if r["bytes"] == size) for part in parts} for size in PAYLOADS}
    for size in PAYLOADS[1:]:
        extra = {part: (mean[size][part] - mean[0][part]) / (size / 1e3) for part in parts}
        print(f"\n{size / 1e3:g} kB against the empty message, CPU per kB (us): kernel {1e3 * extra['kernel']:.1f}, "
              f"server {1e3 * extra['server']:.1f}, page main {1e3 * extra['page_main']:.1f}, "
              f"all three {1e3 * sum(extra.values()):.1f}")
    per_kb = {part: (mean[PAYLOADS[-1]][part] - mean[0][part]) / (PAYLOADS[-1] / 1e3) for part in parts}
    senders = 1e3 * (per_kb["kernel"] + per_kb["server"])  # us per kB, from the largest payload
    print("\nA drag move's geometry, whole or as changed rows (the row comparison timed in this process; the saved "
          f"bytes priced at the {PAYLOADS[-1] / 1e3:g} kB rate: kernel + server {senders:.1f} us/kB, "
          f"with the page {senders + 1e3 * per_kb['page_main']:.1f} us/kB):\n")
    print("| points | comparison (us) | whole (bytes) | changed rows (bytes) | saved: kernel + server (us) | saved: with the page (us) |")
    print("|---:|---:|---:|---:|---:|---:|")
    for r in delta_costs():
        saved_kb = (r["whole"] - r["delta"]) / 1e3
        print(f"| {r['n']} | {r['us']:.1f} | {r['whole']} | {r['delta']} | {senders * saved_kb:.1f} | "
              f"{(senders + 1e3 * per_kb['page_main']) * saved_kb:.1f} |")


def servers(args) -> list:
    """The stock server vs the TCP_NODELAY server, side by side per size."""
    from labharness import Lab, launch_chromium, start_lab

    rows = []
    with start_lab(nodelay=False) as stock, start_lab(nodelay=True) as nodelay, launch_chromium() as browser:
        for n in args.sizes:
            kernel = kernel_handling(n)
            for label, server in (("stock", stock), ("TCP_NODELAY", nodelay)):  # side by side, same n
                context = browser.new_context(viewport={"width": 1400, "height": 1000})
                row = browser_round_trips(Lab(server, context.new_page()), n, args.moves, trace=args.trace,
                                              breakdown=args.breakdown)
                context.close()
                server.shutdown_kernels()
                row.update(server=label, kernel_median=kernel)
                rows.append(row)
                print(f"n={n} {label}: done", file=sys.stderr, flush=True)
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 100, 1000])
    parser.add_argument("--moves", type=int, default=200)
    parser.add_argument("--compare", metavar="DIR", help="a checkout of another commit, measured side by side")
    parser.add_argument("--rounds", type=int, default=2, help="with --compare: rounds, the order swapped each")
    parser.add_argument("--trace", action="store_true",
                        help="record a Chrome trace of each row's moves: the page's CPU per move (main thread, raster workers)")
    parser.add_argument("--breakdown", action="store_true",
                        help="with the trace, the page's main thread per move by who runs (widget, JupyterLab's kernel "
                             "status handling, message handling, browser) and the ping round trip without a browser")
    parser.add_argument("--transport", action="store_true",
                        help="CPU and round trip of a kernel -> page message by its size (0, 4, 40, 400 kB)")
    args = parser.parse_args(argv)
    args.trace = args.trace or args.breakdown
    if args.transport:
        rows = transport(args)
        print(f"python {platform.python_version()}, {platform.machine()}, chromium via Playwright, "
              f"{args.moves} messages per row, {args.rounds} rounds\n")
        print_transport(rows)
        return
    rows = compare(args) if args.compare else servers(args)

    print(f"python {platform.python_version()}, {platform.machine()}, chromium via Playwright, "
          f"{args.moves} moves per row (after {WARMUP} warm-up moves)\n")
    print("| points | server | moves | pointer→path in DOM, median (ms) | p95 (ms) | →painted frame, median (ms) | p95 (ms) "
          "| of which: frame wait / send→answer / draw (ms) | kernel handler alone (ms) | empty message round trip: total (up / down) (ms) "
          "| page CPU per move: main / raster (ms) | frames to the paint: median (in the next frame) |")
    print("|---:|---|---:|---:|---:|---:|---:|---|---:|---:|---|---|")
    for r in rows:
        print(f"| {r['n']} | {r['server']} | {r['moves']} | {r['dom_median']:.1f} | {r['dom_p95']:.1f} | {r['frame_median']:.1f} | "
              f"{r['frame_p95']:.1f} | {r['wait_median']:.1f} / {r['kernel_median_rt']:.1f} / {r['draw_median']:.1f} | "
              f"{r['kernel_median']:.2f} | {r['ping_median']:.1f} ({r['ping_up']:.1f} / {r['ping_down']:.1f}) | {r['cpu_main']:.1f} / {r['cpu_raster']:.1f} | "
              f"{r['frames_median']:.0f} ({100 * r['next_frame']:.0f}%) |")
    if args.breakdown:
        print_breakdown(rows)


def print_breakdown(rows) -> None:
    """The page's main thread per move by who runs it, and the ping without a browser (``--breakdown``)."""
    print("\nThe page's main thread per move (V8 CPU profile samples, ms) and the empty message's round trip "
          "with and without the browser (ms):\n")
    print("| points | server | " + " | ".join(drag_breakdown.PARTS) + " | ping: page | ping: no browser |")
    print("|---:|---|" + "---:|" * (len(drag_breakdown.PARTS) + 2))
    for r in rows:
        split = " | ".join(f"{r['split'][part]:.1f}" for part in drag_breakdown.PARTS)
        print(f"| {r['n']} | {r['server']} | {split} | {r['ping_median']:.1f} | {r['no_browser_ping']:.1f} |")


if __name__ == "__main__":
    main()
