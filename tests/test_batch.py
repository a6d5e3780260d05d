"""Tests of splinecraft.trace_many (splinecraft.batch): same bytes on every scheduler, resume, manifest,
faults and bad input. Dask clusters run on loopback only (127.0.0.1)."""
import hashlib
import json
import logging
import os
import signal
import socket
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageDraw

import splinecraft as sc
from splinecraft.batch import MANIFEST_NAME, BatchResult, trace_many
from splinecraft.batch._plan import auto_batch_size
from splinecraft.batch._work import PART_SUFFIX

EPSILON = 1.0


# ---------------------------------------------------------------------------------------------------
# generated glyph-like bitmaps
# ---------------------------------------------------------------------------------------------------
def glyph_image(seed, size=48):
    """A glyph-like bitmap (ring, bar letter, polygon or blob with a hole), ink dark on white."""
    rng = np.random.default_rng(seed)
    image = Image.new("L", (size, size), 255)
    draw = ImageDraw.Draw(image)
    low, high = size * 0.15, size * 0.85
    kind = seed % 4
    if kind == 0:  # an 'o'
        a, b = rng.uniform(0.3, 0.42, 2) * size
        centre = size / 2 + rng.uniform(-2, 2, 2)
        draw.ellipse([centre[0] - a, centre[1] - b, centre[0] + a, centre[1] + b], fill=0)
        draw.ellipse([centre[0] - a / 2, centre[1] - b / 2, centre[0] + a / 2, centre[1] + b / 2], fill=255)
    elif kind == 1:  # an 'L', 'T' or 'H' of thick bars
        width = rng.uniform(0.12, 0.2) * size
        draw.rectangle([low, low, low + width, high], fill=0)
        draw.rectangle([low, high - width, high, high], fill=0)
        if seed % 8 == 5:
            draw.rectangle([high - width, low, high, high], fill=0)
    elif kind == 2:  # a star-like polygon
        count = int(rng.integers(5, 8))
        angles = np.sort(rng.uniform(0, 2 * np.pi, count))
        radii = rng.uniform(0.2, 0.42, count) * size
        draw.polygon([(size / 2 + r * np.cos(t), size / 2 + r * np.sin(t)) for r, t in zip(radii, angles)], fill=0)
    else:  # a blob with a rectangular hole
        draw.ellipse([low, low, high, high], fill=0)
        inset = rng.uniform(0.35, 0.42) * size
        draw.rectangle([inset, inset, size - inset, size - inset], fill=255)
    return image


def write_glyphs(directory, count, size=48, start=0):
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for seed in range(start, start + count):
        path = directory / f"glyph{seed:03d}.png"
        glyph_image(seed, size).save(path)
        paths.append(path)
    return paths


def reference_bytes(path, fmt="svg", **params):
    """What ``sc.trace`` gives for one file: the bytes every scheduler must write."""
    result = sc.trace(path, epsilon=params.pop("epsilon", EPSILON), **params)
    if fmt == "svg":
        return result.to_svg(title=os.path.basename(path)).encode()
    document = result.to_dict()
    for name in ("time_s", "time_breakdown", "time_per_boundary_s"):
        del document["stats"][name]
    return json.dumps(document, allow_nan=False).encode()


def manifest_lines(directory):
    return [json.loads(line) for line in (directory / MANIFEST_NAME).read_text().splitlines()]


def assert_outputs_whole(out, paths, fmt="svg", **params):
    for path in paths:
        assert (out / f"{path.stem}.{fmt}").read_bytes() == reference_bytes(path, fmt, **params), path.name
    assert not [p.name for p in out.iterdir() if p.name.endswith(PART_SUFFIX)]


@pytest.fixture(scope="module")
def glyphs(tmp_path_factory):
    directory = tmp_path_factory.mktemp("glyphs")
    return write_glyphs(directory, 40)


# ---------------------------------------------------------------------------------------------------
# same bytes everywhere
# ---------------------------------------------------------------------------------------------------
def test_local_schedulers_write_the_bytes_of_trace(glyphs, tmp_path):
    paths = glyphs[:12]
    # no time budget here: on a loaded machine a budget can end one run's fit and not another's, which says
    # nothing about the schedulers
    expected = {path.stem: reference_bytes(path, time_budget=None) for path in paths}
    for name, options in [("serial", {}), ("jobs", {"jobs": 2}), ("threads", {"scheduler": "threads", "jobs": 2}),
                          ("processes", {"scheduler": "processes", "jobs": 2}),
                          ("synchronous", {"scheduler": "synchronous"})]:
        out = tmp_path / name
        result = trace_many(paths, out, epsilon=EPSILON, progress=False, time_budget=None, **options)
        assert isinstance(result, BatchResult) and result.counts == {"ok": 12}, (name, result.failed)
        assert [record.input for record in result] == [str(p) for p in paths]  # input order
        for path in paths:
            assert (out / f"{path.stem}.svg").read_bytes() == expected[path.stem], (name, path.name)
        assert sorted(p.name for p in out.iterdir()) == sorted([f"{p.stem}.svg" for p in paths] + [MANIFEST_NAME])


def test_json_outputs_are_reproducible(glyphs, tmp_path):
    paths = glyphs[:6]
    first = trace_many(paths, tmp_path / "a", format="json", epsilon=EPSILON, progress=False, time_budget=None)
    second = trace_many(paths, tmp_path / "b", format="json", epsilon=EPSILON, scheduler="threads", jobs=2,
                        batch_size=2, progress=False, time_budget=None)
    assert first.counts == second.counts == {"ok": 6}
    for path in paths:
        data = (tmp_path / "a" / f"{path.stem}.json").read_bytes()
        assert data == (tmp_path / "b" / f"{path.stem}.json").read_bytes() == reference_bytes(path, "json",
                                                                                   time_budget=None)
        assert "time_s" not in json.loads(data)["stats"]


def test_arrays_in_memory_and_dataframe():
    images = [np.asarray(glyph_image(seed)) for seed in range(3)]
    result = trace_many(images, progress=False, epsilon=EPSILON, keep_snapshots=True)
    assert result.counts == {"ok": 3}
    for image, record in zip(images, result):
        expected = sc.trace(image, epsilon=EPSILON)
        assert record.output is None and record.input.startswith("<image ")
        assert record.result.to_svg() == expected.to_svg()
        assert record.result.snapshots  # keep_snapshots reaches trace
        assert record.stats["segments"] == expected.stats["segments"]
    frame = result.to_dataframe()
    assert list(frame["status"]) == ["ok"] * 3 and "stats.hausdorff" in frame.columns
    assert "result" not in frame.columns


def test_arrays_to_a_directory(tmp_path):
    images = [np.asarray(glyph_image(seed)) for seed in range(2)]
    result = trace_many(images, tmp_path, progress=False, epsilon=EPSILON)
    assert [os.path.basename(record.output) for record in result] == ["image-00000.svg", "image-00001.svg"]
    assert trace_many(images, tmp_path, progress=False, epsilon=EPSILON).counts == {"skipped": 2}
    images[1] = images[1].copy()
    images[1][:4, :4] = 0  # a changed array is traced again
    assert trace_many(images, tmp_path, progress=False, epsilon=EPSILON).counts == {"skipped": 1, "ok": 1}


def test_encoded_image_bytes_are_traced_as_trace_reads_them(glyphs, tmp_path):
    """``trace(bytes)`` reads the bytes as an encoded image file, but ``trace_many`` refused them (``TypeError``
    "must be a path, a glob pattern or an image array"). Bytes, bytearray and memoryview are traced as ``trace``
    reads them, written as ``image-NNNNN`` like arrays, hashed as the file they are (so a rerun skips them);
    bytes that are no image fail alone, named by their position."""
    data = [path.read_bytes() for path in glyphs[:3]]
    inputs = [data[0], bytearray(data[1]), memoryview(data[2]), b"not an image", glyphs[3]]
    result = trace_many(inputs, tmp_path, progress=False, epsilon=EPSILON, jobs=2, batch_size=1)
    assert [record.status for record in result] == ["ok"] * 3 + ["failed", "ok"]
    assert [os.path.basename(record.output) for record in result] == [
        "image-00000.svg", "image-00001.svg", "image-00002.svg", "image-00003.svg", "glyph003.svg"]
    for record, encoded, path in zip(result, data, glyphs):
        expected = sc.trace(encoded, epsilon=EPSILON).to_svg().encode()
        assert (tmp_path / os.path.basename(record.output)).read_bytes() == expected
        assert record.input_sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
    assert "bytes 3" in result[3].input and "not an image" in result[3].error
    assert trace_many(inputs[:3], tmp_path, progress=False, epsilon=EPSILON).counts == {"skipped": 3}
    (single,) = trace_many(data[0], progress=False, epsilon=EPSILON)  # one image's bytes, not 3000 inputs
    assert single.status == "ok" and single.result.to_svg() == sc.trace(data[0], epsilon=EPSILON).to_svg()


# ---------------------------------------------------------------------------------------------------
# resume and manifest
# ---------------------------------------------------------------------------------------------------
def test_resume_skips_finished_files_and_retraces_changed_ones(glyphs, tmp_path):
    paths = glyphs[:8]
    out = tmp_path / "out"
    assert trace_many(paths, out, epsilon=EPSILON, progress=False).counts == {"ok": 8}
    seen = []
    again = trace_many(paths, out, epsilon=EPSILON, progress=False, on_record=seen.append)
    assert again.counts == {"skipped": 8} and len(seen) == 8
    assert trace_many(paths, out, epsilon=EPSILON, progress=False, resume=False).counts == {"ok": 8}
    # a spelled-out default is the same setting
    assert trace_many(paths, out, epsilon=EPSILON, max_iterations=200, progress=False).counts == {"skipped": 8}

    (out / f"{paths[0].stem}.svg").write_text("<svg/>")               # output damaged
    (out / f"{paths[1].stem}.svg").unlink()                           # output gone
    glyph_image(99).save(paths[2])                                    # input changed
    result = trace_many(paths, out, epsilon=EPSILON, progress=False)
    assert [record.status for record in result[:4]] == ["ok", "ok", "ok", "skipped"]
    assert result.counts == {"ok": 3, "skipped": 5}
    assert_outputs_whole(out, paths)

    lines = manifest_lines(out)
    assert sorted(line["output"] for line in lines) == sorted(f"{p.stem}.svg" for p in paths)  # one per file
    for line in lines:
        assert line["status"] == "ok" and line["error"] is None
        assert line["output_sha256"] == sc.batch._work.file_sha256(out / line["output"])
        assert line["input_sha256"] == sc.batch._work.file_sha256(line["input"])

    changed = trace_many(paths, out, epsilon=EPSILON * 1.5, progress=False)
    assert changed.counts == {"ok": 8}  # a new epsilon re-traces everything
    assert_outputs_whole(out, paths, epsilon=EPSILON * 1.5)


def test_manifest_survives_a_torn_line_and_an_explicit_path(glyphs, tmp_path):
    paths = glyphs[:3]
    manifest = tmp_path / "records" / "run.jsonl"
    trace_many(paths, tmp_path / "out", manifest=manifest, epsilon=EPSILON, progress=False)
    assert not (tmp_path / "out" / MANIFEST_NAME).exists()
    text = manifest.read_text()
    manifest.write_text(text + text.splitlines()[0][:40])  # a run killed while appending
    assert trace_many(paths, tmp_path / "out", manifest=manifest, epsilon=EPSILON,
                      progress=False).counts == {"skipped": 3}
    assert len(manifest.read_text().splitlines()) == 3  # compacted: one line per file


def test_trace_many_is_exported():
    assert sc.trace_many is trace_many and "trace_many" in sc.__all__ and "trace_many" in dir(sc)


def test_auto_batch_size():
    assert auto_batch_size(0.02, 1000, 2) == 5          # 5 x 20 ms = 100 ms per task
    assert auto_batch_size(0.5, 1000, 2) == 1           # slow files: one per task
    assert auto_batch_size(0.001, 40, 2) == 5           # small runs: at least 4 tasks per worker
    assert auto_batch_size(0.0, 10 ** 6, 64) == 1000    # no timing: the floor of 0.1 ms per file


# ---------------------------------------------------------------------------------------------------
# bad files and bad arguments
# ---------------------------------------------------------------------------------------------------
def test_bad_files_do_not_stop_the_batch(glyphs, tmp_path):
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "notes.png").write_text("not an image")
    Image.new("L", (20, 20), 255).save(bad / "blank.png")
    data = glyphs[0].read_bytes()
    (bad / "cut.png").write_bytes(data[: len(data) // 2])
    inputs = [glyphs[0], bad / "notes.png", glyphs[1], bad / "blank.png", bad / "cut.png", bad / "missing.png"]
    out = tmp_path / "out"
    for options in ({}, {"jobs": 2, "batch_size": 2}):
        result = trace_many(inputs, out, epsilon=EPSILON, progress=False, resume=False, **options)
        assert [record.status for record in result] == ["ok", "failed", "ok", "failed", "failed", "failed"]
        reasons = [record.error for record in result.failed]
        for reason, expected in zip(reasons, ["not an image", "no shape found", "truncated", "not found"]):
            assert expected in reason
        assert sorted(p.name for p in out.iterdir()) == sorted(
            [f"{glyphs[0].stem}.svg", f"{glyphs[1].stem}.svg", MANIFEST_NAME])
        failed_lines = [line for line in manifest_lines(out) if line["status"] == "failed"]
        assert len(failed_lines) == 4 and all(line["error"] for line in failed_lines)


def test_bad_arguments_fail_before_any_file(glyphs, tmp_path):
    out = tmp_path / "out"
    cases = [
        (dict(epsilon=-1), ValueError, "epsilon"),
        (dict(epsilon="x"), TypeError, "epsilon"),
        (dict(method="nope"), ValueError, "method"),
        (dict(nonsense=1), TypeError, "nonsense"),
        (dict(format="png"), ValueError, "format"),
        (dict(batch_size=0), ValueError, "batch_size"),
        (dict(batch_size=2.5), TypeError, "batch_size"),
        (dict(decimals=-1), ValueError, "decimals"),
        (dict(resume="yes"), TypeError, "resume"),
        (dict(on_record=3), TypeError, "on_record"),
        (dict(jobs=-1), ValueError, "jobs"),  # (jobs=0 is one worker per CPU, as --jobs 0)
        (dict(scheduler="cluster"), ValueError, "scheduler"),
        (dict(scheduler=3), TypeError, "scheduler"),
        (dict(scheduler="tcp://127.0.0.1:1", jobs=2), ValueError, "jobs"),
    ]
    for options, error, word in cases:
        with pytest.raises(error, match=word):
            trace_many(glyphs[:2], out, progress=False, **options)
    with pytest.raises(ValueError, match="matches no file"):
        trace_many(str(tmp_path / "*.tif"), out)
    with pytest.raises(TypeError, match=r"inputs\[1\]"):
        trace_many([glyphs[0], 3.5], out)
    with pytest.raises(ValueError, match="inputs is empty"):
        trace_many([], out)
    (tmp_path / "sub").mkdir()
    glyph_image(0).save(tmp_path / "sub" / glyphs[0].name)
    with pytest.raises(ValueError, match="would both be written"):
        trace_many([glyphs[0], tmp_path / "sub" / glyphs[0].name], out)
    assert not out.exists()  # nothing was created


def test_an_output_that_is_also_an_input_is_refused(glyphs, tmp_path):
    source = tmp_path / "a.svg"
    source.write_bytes(glyphs[0].read_bytes())  # a PNG named .svg
    with pytest.raises(ValueError, match="also an input"):
        trace_many([source], tmp_path)
    with pytest.raises(ValueError, match="manifest .* also an input"):
        trace_many([glyphs[0]], tmp_path / "o", manifest=glyphs[0])
    assert source.read_bytes() == glyphs[0].read_bytes()


def test_unusable_output_directory(glyphs, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(ValueError, match="not a directory"):
        trace_many(glyphs[:1], blocker, progress=False)
    with pytest.raises(OSError, match="not writable"):
        trace_many(glyphs[:1], blocker / "sub", progress=False)


def test_a_failed_write_leaves_no_partial_file(glyphs, tmp_path, monkeypatch):
    from splinecraft.batch import _work

    def full_disk(fd, mode):
        stream = open(fd, mode)
        stream.write = lambda data: (_ for _ in ()).throw(OSError(28, "No space left on device"))
        return stream

    monkeypatch.setattr(_work.os, "fdopen", full_disk)
    result = trace_many(glyphs[:2], tmp_path, epsilon=EPSILON, progress=False)
    assert result.counts == {"failed": 2}
    for record in result:
        assert record.error == f"cannot write {record.output}: No space left on device"
    assert sorted(p.name for p in tmp_path.iterdir()) == [MANIFEST_NAME]


def test_leftover_partial_files_are_removed(glyphs, tmp_path):
    (tmp_path / f".{glyphs[0].stem}.svg.abc123{PART_SUFFIX}").write_text("<svg")
    (tmp_path / f".unrelated.svg.abc{PART_SUFFIX}").write_text("kept")  # not an output of this batch
    trace_many(glyphs[:1], tmp_path, epsilon=EPSILON, progress=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [f"{glyphs[0].stem}.svg", MANIFEST_NAME, f".unrelated.svg.abc{PART_SUFFIX}"])


def test_a_killed_local_worker_costs_a_pool_restart_not_files(glyphs, tmp_path):
    import multiprocessing

    killed = []

    def kill_a_worker(record):
        workers = [child for child in multiprocessing.active_children() if child.is_alive()]
        if not killed and workers:
            os.kill(workers[0].pid, signal.SIGKILL)
            killed.append(workers[0].pid)

    result = trace_many(glyphs[:16], tmp_path, jobs=2, batch_size=1, epsilon=EPSILON, progress=False,
                        on_record=kill_a_worker)
    assert killed and result.counts == {"ok": 16}, result.failed
    assert_outputs_whole(tmp_path, glyphs[:16])
    assert len(manifest_lines(tmp_path)) == 16


def test_jobs_are_capped_at_the_cpu_count(glyphs, tmp_path):
    with pytest.warns(RuntimeWarning, match="CPUs"):
        result = trace_many(glyphs[:3], tmp_path, jobs=1000, epsilon=EPSILON, progress=False)
    assert result.counts == {"ok": 3}


def test_jobs_zero_means_one_worker_per_cpu_as_on_the_command_line(glyphs, tmp_path, monkeypatch):
    """``trace_many(jobs=0)`` raised while ``--jobs 0`` meant one worker per CPU; both mean that now."""
    from splinecraft import batch
    from splinecraft.batch import _schedulers
    from splinecraft.cli import _job_count

    for module in (batch, _schedulers):  # a machine of 3 CPUs, for the library and for the command line
        monkeypatch.setattr(module, "cpu_count", lambda: 3)
    runner = _schedulers.make_runner(None, 0, files=10)
    try:
        assert runner.workers == 3 == _job_count(0, None)
    finally:
        runner.close()
    assert _schedulers.make_runner(None, 0, files=2).workers == 2  # never more workers than files
    monkeypatch.undo()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # one per CPU is no cap: no warning
        result = trace_many(glyphs[:3], tmp_path, jobs=0, epsilon=EPSILON, progress=False)
    assert result.counts == {"ok": 3}
    assert_outputs_whole(tmp_path, glyphs[:3])


def test_without_dask_the_error_says_how_to_install_it(glyphs, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "dask", None)
    monkeypatch.setitem(sys.modules, "distributed", None)
    for scheduler in ("threads", "tcp://127.0.0.1:8786"):
        with pytest.raises(ImportError, match=r"pip install 'splinecraft\[dask\]'"):
            trace_many(glyphs[:1], tmp_path, scheduler=scheduler)
    assert trace_many(glyphs[:1], tmp_path, epsilon=EPSILON, progress=False).counts == {"ok": 1}


def test_unreachable_scheduler_address_fails_fast(glyphs, tmp_path):
    with socket.socket() as probe:  # a port nobody listens on
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    started = time.monotonic()
    with pytest.raises(ConnectionError, match=f"scheduler '{address}': no dask scheduler answered"):
        trace_many(glyphs[:2], tmp_path / "out", scheduler=address, progress=False)
    assert time.monotonic() - started < 10
    assert not list((tmp_path / "out").glob("*.svg"))


# ---------------------------------------------------------------------------------------------------
# dask.distributed on loopback
# ---------------------------------------------------------------------------------------------------
def _local_cluster():
    distributed = pytest.importorskip("distributed")
    return distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                    dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)


def test_local_cluster_traces_like_trace_and_resumes(glyphs, tmp_path):
    from distributed import Client

    out = tmp_path / "out"
    with _local_cluster() as cluster, Client(cluster, set_as_default=False) as client:
        result = trace_many(glyphs, out, scheduler=client, epsilon=EPSILON, progress=False)
        assert result.counts == {"ok": 40}, result.failed
        assert_outputs_whole(out, glyphs)
        assert trace_many(glyphs, out, scheduler=client, epsilon=EPSILON, progress=False).counts == {"skipped": 40}
        changed = trace_many(glyphs, out, scheduler=cluster.scheduler_address, epsilon=EPSILON * 2,
                             progress=False)
        assert changed.counts == {"ok": 40}
        assert_outputs_whole(out, glyphs, epsilon=EPSILON * 2)
    assert len(manifest_lines(out)) == 40


def test_a_killed_worker_does_not_lose_files(glyphs, tmp_path):
    from distributed import Client

    out = tmp_path / "out"
    killed = []
    with _local_cluster() as cluster, Client(cluster, set_as_default=False) as client:
        def kill_a_busy_worker(record):
            if killed:
                return
            busy = [address for address, keys in client.processing().items() if keys]
            if busy:
                pid = client.run(os.getpid, workers=[busy[0]])[busy[0]]
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # distributed reports the lost worker
            result = trace_many(glyphs, out, scheduler=client, batch_size=1, epsilon=EPSILON, progress=False,
                                on_record=kill_a_busy_worker)
    assert killed, "no worker was busy when the first file finished"
    assert result.counts == {"ok": 40}, result.failed
    assert_outputs_whole(out, glyphs)
    lines = manifest_lines(out)
    assert sorted(line["output"] for line in lines) == sorted(f"{p.stem}.svg" for p in glyphs)


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="pipes as paths (/proc/self/fd)")
def test_a_pipe_input_is_read_once_and_resumes_by_its_content(tmp_path):
    """An input path that is a pipe (``splinecraft trace <(curl ...) -o out/``, which the shell passes as
    ``/dev/fd/N``) can be read once. The resume check hashed it before the trace, so the trace read an empty
    pipe ("not an image file") whenever the manifest had a line for its output, and the first run recorded the
    hash of nothing. The pipe is read once, in the calling process: the file is traced, the manifest holds the
    hash of what came through it, and a run with the same content skips while one with other content traces
    it. (An anonymous pipe, as the shell's: read past its end, it gives nothing instead of waiting.)"""
    import threading

    images = {}
    for seed in (0, 1):
        path = tmp_path / f"glyph{seed}.png"
        glyph_image(seed).save(path)
        images[seed] = path
    out = tmp_path / "out"

    def run(seed):
        read_end, write_end = os.pipe()

        def write():
            with os.fdopen(write_end, "wb") as stream:
                stream.write(images[seed].read_bytes())

        writer = threading.Thread(target=write)
        writer.start()
        try:
            (record,) = trace_many([f"/proc/self/fd/{read_end}"], out, epsilon=EPSILON)
        finally:
            writer.join(timeout=10)
            os.close(read_end)
        return record

    first = run(0)
    assert first.status == "ok", first.error
    assert first.input_sha256 == hashlib.sha256(images[0].read_bytes()).hexdigest()
    name = Path(first.output).name
    expected = sc.trace(images[0], epsilon=EPSILON).to_svg(title=Path(name).stem).encode()
    assert (out / name).read_bytes() == expected
    again = run(0)
    assert again.status == "skipped"
    other = run(1)
    assert other.status == "ok", other.error
    assert (out / name).read_bytes() == sc.trace(images[1], epsilon=EPSILON).to_svg(title=Path(name).stem).encode()


def test_a_manifest_that_is_a_directory_is_refused_by_name(tmp_path):
    """``manifest=`` (the command line's ``--manifest``) naming a directory was a bare "[Errno 21] Is a
    directory" from deep in the run; it is refused up front, naming the manifest, and nothing is traced."""
    path = tmp_path / "glyph.png"
    glyph_image(0).save(path)
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(ValueError, match="manifest .* is a directory"):
        trace_many([path], out, manifest=out, epsilon=EPSILON)
    assert list(out.iterdir()) == []


def test_an_all_ink_input_has_a_warning_in_its_record():
    """trace_many kept the 'every pixel is ink' note of an all-black input nowhere but in the TraceResult (none
    with an output directory, and no warning): its record now carries it among the file's warnings."""
    records = sc.trace_many([np.zeros((12, 12), np.uint8), np.ones((12, 12), bool), np.eye(12, dtype=bool)])
    assert [record.status for record in records] == ["ok"] * 3
    for record in records[:2]:
        assert len(record.warnings) == 1 and record.warnings[0].startswith("InkPolarityWarning: every pixel is ink")
        assert "see threshold/invert" in record.warnings[0]
    assert records[2].warnings == []


def test_the_notes_that_qualify_an_output_are_warnings_of_its_record():
    """trace_many kept a file's Python warnings and its all-ink note, but not its other notes that say the output
    is not what was asked for: boundaries that did not converge, a spent time budget. Now they are warning
    lines of its record (and manifest line), in the library's spelling; a converged file has none."""
    ring = np.full((64, 64), 255, np.uint8)
    yy, xx = np.mgrid[:64, :64] + 0.5
    r2 = (xx - 32) ** 2 + (yy - 32) ** 2
    ring[(r2 <= 25 ** 2) & (r2 > 10 ** 2)] = 0
    (short,) = trace_many([ring], method="random", max_iterations=1, progress=False)
    library = sc.trace(ring, method="random", max_iterations=1)
    reasons = [entry["reason"] for entry in library.stats["per_boundary"]]
    assert short.status == "ok" and all(reasons)
    (line,) = short.warnings
    assert line == (f"NotConverged: 2 of 2 boundaries did not converge: boundary 0 "
                    f"({library.stats['per_boundary'][0]['contour_points']} points): {reasons[0]}; "
                    "stats['per_boundary'][k]['reason'] says why for each")
    (spent,) = trace_many([ring], time_budget=1e-9, progress=False)
    assert spent.warnings == [f"TimeBudget: {note}" for note in sc.trace(ring, time_budget=1e-9).notes
                              if note.startswith("time budget of")]
    assert len(spent.warnings) == 1 and "time_budget=None" in spent.warnings[0]
    (fitted,) = trace_many([ring], progress=False)
    assert fitted.warnings == []


def test_a_mapping_of_inputs_names_them_by_its_keys(tmp_path):
    """``trace_many(dict)`` iterated the dict's keys and traced the names as paths ("image file not found").
    A mapping ``{name: image}`` is now a set of named inputs: each value one image (a path, taken literally, an
    array, a PIL image, encoded bytes), each key its name: the record's input, the output ``NAME.svg`` and the
    SVG's title, in the mapping's order; resume works by name as by path."""
    path = tmp_path / "scan.png"
    glyph_image(0).save(path)
    encoded = tmp_path / "other.png"
    glyph_image(1).save(encoded)
    array = np.asarray(glyph_image(2))
    named = {"zeta": array, "alpha": path, "raw": encoded.read_bytes(), "pil": glyph_image(3)}
    out = tmp_path / "out"
    records = trace_many(named, out, epsilon=EPSILON, progress=False)
    assert [record.input for record in records] == list(named) and records.counts == {"ok": 4}
    assert sorted(p.name for p in out.iterdir()) == sorted([f"{name}.svg" for name in named] + [MANIFEST_NAME])
    for name, image in named.items():
        expected = sc.trace(image, epsilon=EPSILON, keep_snapshots=False).to_svg(title=name)
        assert (out / f"{name}.svg").read_text() == expected, name
    assert trace_many(named, out, epsilon=EPSILON, progress=False).counts == {"skipped": 4}
    (kept,) = trace_many({"only": array}, epsilon=EPSILON, progress=False)
    assert kept.input == "only" and kept.result.to_svg() == sc.trace(array, epsilon=EPSILON).to_svg()


@pytest.mark.parametrize("inputs, error, words", [
    ({}, ValueError, "inputs is empty"),
    ({3: np.zeros((4, 4))}, TypeError, "inputs keys must be names (str), got 3 (int)"),
    ({"": np.zeros((4, 4))}, ValueError, "inputs key '' is not a name"),
    ({"a/b": np.zeros((4, 4))}, ValueError, "inputs key 'a/b' is not a name"),
    ({"..": np.zeros((4, 4))}, ValueError, "inputs key '..' is not a name"),
    ({"  ": np.zeros((4, 4))}, ValueError, "inputs key '  ' is not a name"),  # only white space: output '  .svg'
    ({"\t": np.zeros((4, 4))}, ValueError, "inputs key '\\t' is not a name (U+0009 at index 0)"),
    ({"a\nb": np.zeros((4, 4))}, ValueError, "inputs key 'a\\nb' is not a name (U+000A at index 1)"),
    ({"a": 5}, TypeError, "inputs['a'] must be a path, an image array, a PIL image or encoded image bytes, got int"),
    ({"a": [np.zeros((4, 4))]}, TypeError, "inputs['a'] must be a path"),
])
def test_a_bad_mapping_of_inputs_is_refused_by_name(tmp_path, inputs, error, words):
    with pytest.raises(error) as caught:
        trace_many(inputs, tmp_path / "out", progress=False)
    assert words in str(caught.value)
    assert not (tmp_path / "out").exists()


def test_a_manifest_that_is_also_an_output_is_refused(glyphs, tmp_path):
    """``manifest=`` naming one of the outputs: the SVG was written, then the manifest's JSON line appended to it
    (an SVG with a line of JSON after ``</svg>``), and the next run read that file as the manifest. Refused up
    front, as an output that is an input is, naming both."""
    out = tmp_path / "out"
    target = out / f"{glyphs[0].stem}.svg"
    for manifest in (target, out / "sub" / ".." / target.name):
        with pytest.raises(ValueError) as caught:
            trace_many(glyphs[:2], out, manifest=manifest, epsilon=EPSILON, progress=False)
        assert f"manifest {target} is also the output of {glyphs[0]}" in str(caught.value)
    assert not out.exists()  # nothing was created
    with pytest.raises(ValueError, match=r"manifest .*a\.json is also the output of a;"):
        trace_many({"a": np.asarray(glyph_image(0))}, out, manifest=out / "a.json", format="json", progress=False)
    assert not out.exists()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are a POSIX matter")
def test_an_output_or_manifest_that_is_a_special_file_is_refused(glyphs, tmp_path):
    """An output that exists and is a named pipe or a device (``-o /dev/null``, ``-o /dev/stdout``) was replaced:
    outputs are written to a temporary file renamed over theirs, so the pipe (or, run as root, the device node)
    became a regular file holding the SVG, exit code 0. A manifest that is one hung: the resume check opened it
    for reading. Both are refused up front, saying what the file is."""
    out = tmp_path / "out"
    out.mkdir()
    pipe = out / f"{glyphs[0].stem}.svg"
    os.mkfifo(pipe)
    with pytest.raises(ValueError) as caught:
        trace_many(glyphs[:2], out, epsilon=EPSILON, progress=False)
    assert f"output {pipe} is a named pipe (FIFO), not a regular file" in str(caught.value)
    assert pipe.is_fifo() and sorted(p.name for p in out.iterdir()) == [pipe.name]
    code = ("import sys; from splinecraft import trace_many\n"
            "try:\n"
            f"    trace_many([{str(glyphs[1])!r}], {str(tmp_path / 'other')!r}, manifest={str(pipe)!r},\n"
            "               progress=False)\n"
            "except ValueError as exc:\n"
            "    print(exc)\n")
    import subprocess
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert f"manifest {pipe} is a named pipe (FIFO), not a regular file" in done.stdout, done.stderr
    assert pipe.is_fifo() and not (tmp_path / "other").exists()


def test_an_empty_output_dir_or_manifest_is_refused(glyphs, tmp_path, monkeypatch):
    """``output_dir=""`` wrote every output and the manifest into the current directory (``os.path.join("", name)``),
    and ``manifest=""`` was refused as "manifest '<current directory>' is a directory": an empty name (an unset
    variable, say) is now refused as empty, as ``-o ''`` is on the command line, before anything is written."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match="output_dir is empty: give a directory"):
        trace_many(glyphs[:1], "", epsilon=EPSILON, progress=False)
    with pytest.raises(ValueError, match="manifest is empty: give a file name"):
        trace_many(glyphs[:1], tmp_path / "out", manifest="", epsilon=EPSILON, progress=False)
    assert list(tmp_path.iterdir()) == []


def test_a_blank_output_dir_or_manifest_is_refused(glyphs, tmp_path, monkeypatch):
    """``output_dir=" "`` wrote the outputs into a folder called space (and ``manifest=" "`` failed as a directory
    or wrote a file called space): a name of only white space is never meant, refused as an empty one is."""
    monkeypatch.chdir(tmp_path)
    for blank in (" ", "\t", " \n "):
        with pytest.raises(ValueError) as caught:
            trace_many(glyphs[:1], blank, epsilon=EPSILON, progress=False)
        assert str(caught.value).startswith(f"output_dir is blank ({blank!r}: only white space): give a directory")
        with pytest.raises(ValueError) as caught:
            trace_many(glyphs[:1], tmp_path / "out", manifest=blank, epsilon=EPSILON, progress=False)
        assert str(caught.value).startswith(f"manifest is blank ({blank!r}: only white space): give a file name")
    assert list(tmp_path.iterdir()) == []


def test_a_manifest_without_outputs_is_refused(glyphs, tmp_path):
    """``output_dir=None`` writes nothing (the records keep the results), so a ``manifest=`` given with it was
    ignored without a word: no file, and a second run traced everything again. Refused, as ``-o -`` refuses
    ``--manifest`` on the command line."""
    manifest = tmp_path / "runs.jsonl"
    with pytest.raises(ValueError, match=r"manifest .*runs\.jsonl is given, but output_dir is None"):
        trace_many(glyphs[:1], None, manifest=manifest, epsilon=EPSILON, progress=False)
    assert not manifest.exists()


def test_one_multi_frame_pil_image_for_several_inputs_is_refused(tmp_path):
    """A PIL image is traced at the frame it is at (the way to trace frame k of a GIF is ``img.seek(k)`` and pass
    ``img``), but only when its turn comes: the frames of one image object seeked in a loop,
    ``{f"frame{k}": img}``, were all traced at the last frame, three identical outputs and no word. One
    multi-frame image object given for several inputs is refused, naming them and the way out (``img.copy()``);
    copies trace each frame."""
    masks = [np.asarray(glyph_image(seed)) for seed in range(3)]
    path = tmp_path / "anim.gif"
    frames = [Image.fromarray(mask) for mask in masks]
    frames[0].save(path, save_all=True, append_images=frames[1:])
    out = tmp_path / "out"
    with Image.open(path) as img:
        shared, copies = {}, {}
        for k in range(3):
            img.seek(k)
            shared[f"frame{k}"], copies[f"frame{k}"] = img, img.copy()
        with pytest.raises(ValueError) as caught:
            trace_many(shared, out, epsilon=EPSILON, progress=False)
        assert ("inputs frame0 and frame1 are the same PIL image object, a file of 3 frames now at frame 2"
                in str(caught.value)) and "img.copy()" in str(caught.value)
        with pytest.raises(ValueError, match="inputs <image 0> and <image 1> are the same PIL image object"):
            trace_many(list(shared.values()), out, epsilon=EPSILON, progress=False)
        assert not out.exists()
        records = trace_many(copies, out, epsilon=EPSILON, progress=False)
    assert records.counts == {"ok": 3}
    drawings = set()
    for name, image in copies.items():
        result = sc.trace(image, epsilon=EPSILON, keep_snapshots=False)
        assert (out / f"{name}.svg").read_text() == result.to_svg(title=name)
        drawings.add(result.to_svg())
    assert len(drawings) == 3  # three frames, three different outlines
    single = np.asarray(glyph_image(5))
    assert trace_many({"a": Image.fromarray(single), "b": Image.fromarray(single)}, progress=False).counts == {"ok": 2}


@pytest.mark.parametrize("options", [{"jobs": 2, "batch_size": 3},
                                     {"scheduler": "processes", "jobs": 2, "batch_size": 3}])
def test_a_pil_image_whose_pixels_cannot_be_read_fails_alone_in_worker_processes(tmp_path, options):
    """A PIL image opened in a ``with Image.open(path)`` block reads its pixels from a file that is closed. Sent
    to a worker process it cannot be pickled (PIL loads it to pickle it): with ``jobs=2`` its task failed whole,
    the good images beside it too, each with the record 'AssertionError: ', and with dask's processes the run
    ended in a bare AssertionError. PIL images are decoded in the calling process (as pipes are read there),
    and one that cannot be fails alone, saying why, as in one process."""
    path = tmp_path / "glyph.png"
    glyph_image(4).save(path)
    with Image.open(path) as lazy:
        pass
    good = np.asarray(glyph_image(1))
    inputs = {"a": good, "b": good, "c": good, "d": good, "lazy": lazy, "e": Image.fromarray(good), "f": good}
    result = trace_many(inputs, tmp_path / "out", epsilon=EPSILON, progress=False, **options)
    assert [record.status for record in result] == ["ok"] * 4 + ["failed"] + ["ok"] * 2, [r.error for r in result]
    assert result[4].error.startswith("PIL image: its pixels were never loaded and its file is closed")


def test_a_pil_image_over_max_pixels_is_not_decoded_by_the_batch(tmp_path):
    """PIL images are decoded in the calling process before the run (previous test), but not one over
    ``max_pixels``: the cap is read from its header, before any pixel is decoded (a decompression bomb costs
    nothing), and its file fails on its size."""
    path = tmp_path / "big.png"
    Image.fromarray(np.asarray(glyph_image(2, size=64))).save(path)
    with Image.open(path) as lazy:
        (record,) = trace_many({"big": lazy}, max_pixels=100, progress=False)
        assert record.status == "failed" and "is more than max_pixels=100" in record.error
        assert lazy.tile  # PIL empties its tile list once the pixels are decoded


def test_numpy_string_keys_name_inputs_as_plain_text(tmp_path):
    """A mapping's keys taken from numpy (``dict(zip(np.array(["a", "b"]), images))``) are ``np.str_``: the record
    kept them, ``FileRecord(input=np.str_('a'), ...)`` and the same in the data frame. Names are plain ``str``."""
    image = np.asarray(glyph_image(0))
    records = trace_many(dict(zip(np.array(["a", "b"]), [image, image])), tmp_path, epsilon=EPSILON, progress=False)
    assert [type(record.input) for record in records] == [str, str]
    assert repr(records[0]).startswith("FileRecord(input='a', ")
    with pytest.raises(ValueError, match=r"^inputs key 'a/b' is not a name"):
        trace_many({np.str_("a/b"): image}, tmp_path, progress=False)


def _tells_case_apart(directory):
    probe = directory / "Case-Probe"
    probe.write_text("")
    try:
        return not (directory / "cASE-pROBE").exists()
    finally:
        probe.unlink()


def test_outputs_that_differ_only_in_case_are_refused_where_the_directory_ignores_case(tmp_path, monkeypatch):
    """Inputs named ``A`` and ``a`` (or ``scans/A.png`` and ``old/a.png``) are written to ``A.svg`` and ``a.svg``:
    two files on Linux, one on the usual file systems of macOS and Windows, which ignore case; the second
    output replaced the first, both records said "ok", and every rerun traced both again (the first output's
    hash never matched). An output directory that ignores case (found by the write check every output
    directory gets) refuses such names up front, naming both inputs; one that tells case apart keeps both."""
    from splinecraft.batch import _plan

    image = np.asarray(glyph_image(0))
    inputs = {"Logo": image, "page": image, "logo": image}
    monkeypatch.setattr(_plan, "directory_ignores_case", lambda directory, name: True)
    with pytest.raises(ValueError) as caught:
        trace_many(inputs, tmp_path / "out", epsilon=EPSILON, progress=False)
    assert ("inputs Logo and logo would both be written to Logo.svg and logo.svg, one file in output directory "
            f"{tmp_path / 'out'}, which ignores case") in str(caught.value)
    assert list((tmp_path / "out").iterdir()) == []
    monkeypatch.undo()
    if _tells_case_apart(tmp_path):
        assert trace_many(inputs, tmp_path / "out", epsilon=EPSILON, progress=False).counts == {"ok": 3}


@pytest.mark.parametrize("text", ["my notes\nsecond line\n", "<svg xmlns='http://www.w3.org/2000/svg'/>\n",
                                  '{"name": "settings", "epsilon": 1}\n', "[1, 2]\n"])
def test_a_manifest_file_that_is_no_manifest_is_refused_not_overwritten(glyphs, tmp_path, text):
    """``manifest=`` (``--manifest``) naming an existing file that is no manifest (a typo for another file, notes,
    an SVG, another program's JSON lines): its lines were ignored as torn ones and, at the end of the run, the file
    was rewritten with the manifest's lines, its content lost. It is refused before anything is traced, naming
    the first line that is no manifest line; a torn last line of a real manifest is still ignored (the test
    above)."""
    notes = tmp_path / "notes.txt"
    notes.write_text(text)
    with pytest.raises(ValueError) as caught:
        trace_many(glyphs[:1], tmp_path / "out", manifest=notes, epsilon=EPSILON, progress=False)
    assert str(caught.value).startswith(f"manifest {notes} is not a splinecraft manifest (line 1: ")
    assert notes.read_text() == text and not (tmp_path / "out").exists()
    torn = tmp_path / "torn.jsonl"
    torn.write_text('{"error": null, "finished": "2026-')  # a first run killed while writing its first line
    assert trace_many(glyphs[:1], tmp_path / "out", manifest=torn, epsilon=EPSILON,
                      progress=False).counts == {"ok": 1}


@pytest.mark.parametrize("dtype", [str, object])
def test_a_numpy_array_of_paths_is_refused_with_the_way_out(glyphs, dtype):
    """An array of file names (``np.array(paths)``, ``frame["file"].to_numpy()``) was taken for one image array:
    one record ``<image 0>`` failed with "image array must have a bool, integer or float dtype, got <U..", and the
    batch returned. A string or object array is no image: refused up front, saying to pass a list."""
    names = np.array([str(path) for path in glyphs[:2]], dtype=dtype)
    with pytest.raises(TypeError) as caught:
        trace_many(names, progress=False)
    message = str(caught.value)
    assert message.startswith(f"inputs is a numpy array of dtype {names.dtype}") and ".tolist()" in message
    assert trace_many(names.tolist(), epsilon=EPSILON, progress=False).counts == {"ok": 2}
