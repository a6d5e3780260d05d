"""Batch tracing throughput: ``splinecraft.trace_many`` on generated glyph bitmaps, scheduler by scheduler.

Renders ``--count`` glyph bitmaps (letters and digits of the DejaVu fonts, or PIL's default font where they
are missing, 40-96 px high), then traces all of them with every configuration, round-robin for
``--repeats`` rounds in one process (same machine state), each run into a fresh output directory:

* serial            -- ``trace_many(paths, out)``: one file after the other in this process;
* jobs 2            -- ``trace_many(paths, out, jobs=2)``: splinecraft's own worker processes, what
  ``splinecraft trace --jobs 2`` runs (worker start-up included);
* dask threads      -- ``scheduler="threads", jobs=2``;
* dask processes    -- ``scheduler="processes", jobs=2`` (worker start-up included);
* LocalCluster      -- a ``dask.distributed.LocalCluster`` of 2 single-threaded worker processes on
  127.0.0.1, started once before the rounds (its start-up is reported separately).

Reported per configuration: the median wall time, throughput (images/s), the speed-up against serial, the
wall overhead per image ``(wall x workers - serial wall) / images`` (worker time spent on anything but the
tracing itself: start-up, pickling, scheduling, waiting), and the CPU time per image of the whole process tree
(this process, its workers, the cluster's processes; from /proc) with its overhead against serial. On a shared
machine the wall figures depend on the other load (the load average is printed); the CPU figures much less.
Then dask's own per-task overhead, timed with empty tasks, and the storage per image, for the cost model in
BENCHMARKS.md.

    python benchmarks/bench_batch.py                      # 1000 images, 3 rounds
    python benchmarks/bench_batch.py --count 200 --repeats 1
"""
from __future__ import annotations

import argparse
import logging
import os
import platform
import shutil
import statistics
import sys
import tempfile
import time

import numpy as np
from PIL import Image, ImageDraw, ImageFont

import splinecraft as sc
from splinecraft.batch import MANIFEST_NAME, trace_many

FONT_DIR = "/usr/share/fonts/truetype/dejavu"
FONTS = ("DejaVuSans.ttf", "DejaVuSerif.ttf", "DejaVuSans-Bold.ttf", "DejaVuSansMono.ttf")
CHARACTERS = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789&@"
HEIGHTS = (40, 56, 72, 96)


def _font(name, height):
    path = os.path.join(FONT_DIR, name)
    if os.path.exists(path):
        return ImageFont.truetype(path, height)
    return ImageFont.load_default(size=height)


def glyph_bitmap(index):
    """Glyph ``index``: character, font and height cycle independently; ink black on white, 4 px margin."""
    char = CHARACTERS[index % len(CHARACTERS)]
    font = _font(FONTS[(index // len(CHARACTERS)) % len(FONTS)], HEIGHTS[(index // 7) % len(HEIGHTS)])
    left, top, right, bottom = font.getbbox(char)
    image = Image.new("L", (right - left + 8, bottom - top + 8), 255)
    ImageDraw.Draw(image).text((4 - left, 4 - top), char, font=font, fill=0)
    return image


def write_glyphs(directory, count):
    paths = []
    for index in range(count):
        path = os.path.join(directory, f"glyph{index:05d}.png")
        glyph_bitmap(index).save(path)
        paths.append(path)
    return paths


def _stat_fields(pid):
    with open(f"/proc/{pid}/stat") as handle:
        return handle.read().rsplit(")", 1)[1].split()


def tree_cpu_seconds():
    """CPU seconds (user + system) of this process, its live descendants and the children they reaped."""
    children = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                children.setdefault(int(_stat_fields(entry)[1]), []).append(int(entry))
            except (OSError, IndexError):
                pass
    ticks, todo = 0, [os.getpid()]
    while todo:
        pid = todo.pop()
        try:
            fields = _stat_fields(pid)
        except OSError:
            continue
        ticks += sum(int(value) for value in fields[11:15])  # utime, stime, cutime, cstime
        todo.extend(children.get(pid, []))
    return ticks / os.sysconf("SC_CLK_TCK")


def _noop(value):
    return value


def task_overhead(client, tasks=2000):
    """Seconds per empty task: dask threads, dask processes, and the LocalCluster."""
    import dask

    result = {}
    for name in ("threads", "processes"):
        started = time.perf_counter()
        dask.compute(*[dask.delayed(_noop, pure=False)(k) for k in range(tasks)], scheduler=name, num_workers=2)
        result[name] = (time.perf_counter() - started) / tasks
    client.gather(client.map(_noop, range(200), pure=False))  # warm the workers
    started = time.perf_counter()
    client.gather(client.map(_noop, range(tasks), pure=False))
    result["distributed"] = (time.perf_counter() - started) / tasks
    return result


def run(paths, client, repeats, root):
    configurations = {
        "serial": {},
        "jobs 2 (own worker processes)": {"jobs": 2},
        "dask threads, 2": {"scheduler": "threads", "jobs": 2},
        "dask processes, 2": {"scheduler": "processes", "jobs": 2},
        "LocalCluster, 2 workers": {"scheduler": client},
    }
    trace_many(paths[:16], os.path.join(root, "warm-up"), progress=False)  # first-call imports, not timed
    times = {name: [] for name in configurations}
    cpu = {name: [] for name in configurations}
    reference = None
    for round_number in range(repeats):
        for name, options in configurations.items():
            out = os.path.join(root, f"out-{round_number}-{len(times[name])}-{name.split()[0]}")
            cpu_before, started = tree_cpu_seconds(), time.perf_counter()
            result = trace_many(paths, out, resume=False, progress=False, **options)
            times[name].append(time.perf_counter() - started)
            cpu[name].append(tree_cpu_seconds() - cpu_before)
            assert result.counts == {"ok": len(paths)}, (name, result.failed[:3])
            digests = [record.output_sha256 for record in result]
            reference = reference or digests
            assert digests == reference, f"{name} wrote other bytes than serial"
            if round_number or name != "serial":
                shutil.rmtree(out)
    return ({name: statistics.median(values) for name, values in times.items()},
            {name: statistics.median(values) for name, values in cpu.items()})


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    from distributed import Client, LocalCluster

    root = tempfile.mkdtemp(prefix="bench-batch-")
    try:
        paths = write_glyphs(root, args.count)
        started = time.perf_counter()
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)
        client = Client(cluster, set_as_default=False)
        cluster_start = time.perf_counter() - started
        load_before = os.getloadavg()[0]
        try:
            medians, cpu = run(paths, client, args.repeats, root)
            overhead = task_overhead(client)
        finally:
            client.close()
            cluster.close()
        serial_dir = next(os.path.join(root, d) for d in os.listdir(root) if d.endswith("-serial"))
        report(args, paths, medians, cpu, overhead, cluster_start, serial_dir, (load_before, os.getloadavg()[0]))
    finally:
        shutil.rmtree(root, ignore_errors=True)


def report(args, paths, medians, cpu, overhead, cluster_start, serial_dir, load):
    import dask

    count = len(paths)
    serial, serial_cpu = medians["serial"], cpu["serial"]
    print(f"splinecraft {sc.__version__}, dask {dask.__version__}, Python {platform.python_version()}, "
          f"{os.cpu_count()} CPUs, load average {load[0]:.1f} before / {load[1]:.1f} after; {count} glyph "
          f"bitmaps, median of {args.repeats} rounds")
    print()
    print("| configuration | wall s | images/s | speed-up vs serial | wall overhead per image (ms) "
          "| CPU per image (ms) | CPU overhead per image (ms) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, wall in medians.items():
        workers = 1 if name == "serial" else 2
        per_image = (wall * workers - serial) / count * 1e3
        cpu_image = cpu[name] / count * 1e3
        dash = name == "serial"
        print(f"| {name} | {wall:.2f} | {count / wall:.1f} | {serial / wall:.2f}x | "
              f"{'-' if dash else f'{per_image:.2f}'} | {cpu_image:.2f} | "
              f"{'-' if dash else f'{cpu_image - serial_cpu / count * 1e3:.2f}'} |")
    print()
    print(f"serial time per image: {serial / count * 1e3:.2f} ms; LocalCluster start-up {cluster_start:.1f} s "
          "(not in the table)")
    print("dask per-task overhead (empty tasks, 2 workers): "
          + ", ".join(f"{name} {seconds * 1e3:.2f} ms" for name, seconds in overhead.items()))
    sizes_in = [os.path.getsize(p) for p in paths]
    outputs = [os.path.join(serial_dir, n) for n in os.listdir(serial_dir) if n.endswith(".svg")]
    sizes_out = [os.path.getsize(p) for p in outputs]
    manifest = os.path.getsize(os.path.join(serial_dir, MANIFEST_NAME))
    print(f"storage per image: input PNG {np.mean(sizes_in):.0f} B, output SVG {np.mean(sizes_out):.0f} B, "
          f"manifest line {manifest / count:.0f} B")


if __name__ == "__main__":
    sys.exit(main())
