"""Tests of the command line (splinecraft.cli), run as a real process: ``python -m splinecraft.cli``."""
import io
import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from splinecraft import __version__
from splinecraft.cli import _plan_outputs, main

SVG = "{http://www.w3.org/2000/svg}"


def run_cli(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "splinecraft.cli", *map(str, args)],
        capture_output=True, text=True, cwd=cwd, timeout=300,
    )


def write_shape(path, kind="disc", size=64):
    yy, xx = np.mgrid[:size, :size] + 0.5
    if kind == "disc":
        mask = (xx - size / 2) ** 2 + (yy - size / 2) ** 2 <= (size / 3) ** 2
    elif kind == "ring":
        r2 = (xx - size / 2) ** 2 + (yy - size / 2) ** 2
        mask = (r2 <= (size / 2.5) ** 2) & (r2 > (size / 6) ** 2)
    elif kind == "square":
        mask = np.zeros((size, size), bool)
        mask[size // 4: 3 * size // 4, size // 5: 4 * size // 5] = True
    else:  # blank page
        mask = np.zeros((size, size), bool)
    Image.fromarray(np.where(mask, 0, 255).astype(np.uint8)).save(path)
    return mask


def subpath_count(svg_text):
    root = ET.fromstring(svg_text)
    (path,) = root.findall(f"{SVG}path")
    return path.get("d").count("M"), root


def test_version():
    result = run_cli("--version")
    assert result.returncode == 0
    assert result.stdout.strip() == f"splinecraft {__version__}"


def test_python_m_splinecraft_runs_the_console_script(tmp_path):
    import importlib
    import tomllib

    pyproject = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())
    module, _, name = pyproject["project"]["scripts"]["splinecraft"].partition(":")
    assert importlib.import_module("splinecraft.__main__").main is getattr(importlib.import_module(module), name)
    version = subprocess.run([sys.executable, "-m", "splinecraft", "--version"], capture_output=True, text=True,
                             timeout=300)
    assert version.returncode == 0 and version.stdout.strip() == f"splinecraft {__version__}"
    source = tmp_path / "disc.png"
    write_shape(source, "disc")
    traced = subprocess.run([sys.executable, "-m", "splinecraft", "trace", str(source), "-o", str(tmp_path / "d.svg")],
                            capture_output=True, text=True, timeout=300)
    assert traced.returncode == 0, traced.stderr
    assert subpath_count((tmp_path / "d.svg").read_text())[0] == 1
    wrong = subprocess.run([sys.executable, "-m", "splinecraft", "frobnicate"], capture_output=True, text=True,
                           timeout=300)
    assert wrong.returncode == 2 and "usage: splinecraft" in wrong.stderr


def test_single_file_svg_and_json(tmp_path):
    source = tmp_path / "ring.png"
    write_shape(source, "ring")
    result = run_cli("trace", source, "-o", tmp_path / "ring.svg", "--epsilon", "1.5")
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""  # not a terminal: no progress bar
    count, root = subpath_count((tmp_path / "ring.svg").read_text())
    assert count == 2  # outer boundary and hole
    assert (root.get("width"), root.get("height"), root.get("viewBox")) == ("64", "64", "0 0 64 64")
    assert root.find(f"{SVG}path").get("fill-rule") == "evenodd"

    result = run_cli("trace", source, "-o", tmp_path / "out" / "ring.json", "--method", "random", "--seed", "3", "-v")
    assert result.returncode == 0, result.stderr
    data = json.loads((tmp_path / "out" / "ring.json").read_text())
    assert data["width"] == 64 and data["stats"]["holes"] == 1 and data["params"]["seed"] == 3
    assert "2 boundaries (1 holes)" in result.stderr  # --verbose stats line


def test_many_files_with_bad_ones_in_parallel(tmp_path):
    inputs = []
    for name, kind in [("a", "disc"), ("b", "square"), ("c", "ring")]:
        write_shape(tmp_path / f"{name}.png", kind)
        inputs.append(tmp_path / f"{name}.png")
    (tmp_path / "notes.png").write_text("not an image")
    write_shape(tmp_path / "blank.png", "blank")
    data = (tmp_path / "a.png").read_bytes()
    (tmp_path / "cut.png").write_bytes(data[: len(data) // 2])
    bad = [tmp_path / "notes.png", tmp_path / "blank.png", tmp_path / "cut.png", tmp_path / "missing.png"]
    out = tmp_path / "traced"
    result = run_cli("trace", *inputs[:2], *bad, inputs[2], "-o", out, "--jobs", "2", "--format", "json")
    assert result.returncode == 1
    lines = result.stderr.strip().splitlines()
    assert len(lines) == len(bad) + 1  # one line per failed file + the summary
    for path, reason in zip(bad, ["not an image", "no shape found", "truncated", "not found"]):
        (line,) = [line for line in lines if f"{path}:" in line]
        assert line.startswith("splinecraft: ") and reason in line
    assert lines[-1] == f"splinecraft: {len(bad)} of {len(bad) + 3} files failed"
    assert sorted(p.name for p in out.iterdir()) == ["a.json", "b.json", "c.json", "splinecraft-manifest.jsonl"]
    for name in ("a", "b", "c"):
        assert json.loads((out / f"{name}.json").read_text())["type"] == "splinecraft.TraceResult"
    lines = [json.loads(line) for line in (out / "splinecraft-manifest.jsonl").read_text().splitlines()]
    assert sorted((line["output"], line["status"]) for line in lines) == sorted(
        [(f"{name}.json", "ok") for name in "abc"] + [(f"{p.stem}.json", "failed") for p in bad])


def test_stdout_and_quiet(tmp_path):
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    result = run_cli("trace", source, "-o", "-", "--epsilon", "1", "--decimals", "2", "-q")
    assert result.returncode == 0 and result.stderr == ""
    count, _ = subpath_count(result.stdout)
    assert count == 1


def test_usage_errors_exit_2(tmp_path):
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    assert run_cli("trace", source, "-o", tmp_path / "x.svg", "--epsilon", "0").returncode == 2
    assert run_cli("trace", source, "-o", tmp_path / "x.svg", "--method", "nope").returncode == 2
    assert run_cli("trace", source).returncode == 2  # -o is required
    (tmp_path / "sub").mkdir()
    write_shape(tmp_path / "sub" / "sq.png", "disc")
    result = run_cli("trace", source, tmp_path / "sub" / "sq.png", "-o", tmp_path / "dir")
    assert result.returncode == 2 and "would both be written" in result.stderr


def test_in_process_main_and_one_file_into_a_directory(tmp_path, capsys):
    source = tmp_path / "disc.png"
    write_shape(source, "disc")
    (tmp_path / "out").mkdir()
    assert main(["trace", str(source), "-o", str(tmp_path / "out"), "--epsilon", "2"]) == 0
    assert (tmp_path / "out" / "disc.svg").exists()
    assert main(["trace", str(tmp_path / "nothing.png"), "-o", str(tmp_path / "n.svg")]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "nothing.png" in err and "not found" in err


def test_a_quoted_glob_pattern_traces_every_match(tmp_path, capsys):
    """A pattern the shell did not expand (quoted, or too many files for a command line) is expanded as
    trace_many expands it; one that matches nothing is a usage error naming it. Before, it was 'image file not
    found: scans/*.png'."""
    (tmp_path / "scans" / "more").mkdir(parents=True)
    for name in ("scans/a.png", "scans/b.png", "scans/more/c.png"):
        write_shape(tmp_path / name, "disc")
    out = tmp_path / "out"
    assert main(["trace", str(tmp_path / "scans" / "*.png"), "-o", str(out) + os.sep, "-q"]) == 0
    assert sorted(p.name for p in out.glob("*.svg")) == ["a.svg", "b.svg"]
    deep = tmp_path / "deep"
    assert main(["trace", str(tmp_path / "scans" / "**" / "*.png"), "-o", str(deep) + os.sep, "-q"]) == 0
    assert sorted(p.name for p in deep.glob("*.svg")) == ["a.svg", "b.svg", "c.svg"]
    capsys.readouterr()
    assert main(["trace", str(tmp_path / "scans" / "*.jpg"), "-o", str(tmp_path / "x.svg")]) == 2
    err = capsys.readouterr().err
    assert "*.jpg" in err and "matches no file" in err and not (tmp_path / "x.svg").exists()


def test_plan_outputs():
    assert _plan_outputs(["a.png"], "x.json", None) == ([("a.png", "x.json")], "json")
    assert _plan_outputs(["a.png"], "x.out", None) == ([("a.png", "x.out")], "svg")
    pairs, fmt = _plan_outputs(["p/a.png", "q/b.gif"], "dir", "json")
    assert fmt == "json" and [p[1] for p in pairs] == ["dir/a.json", "dir/b.json"]
    with pytest.raises(ValueError, match="exactly one"):
        _plan_outputs(["a.png", "b.png"], "-", None)


class _FakeTerminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_draws_on_a_terminal_only(tmp_path, monkeypatch):
    for name, kind in [("a", "disc"), ("b", "square")]:
        write_shape(tmp_path / f"{name}.png", kind)
    (tmp_path / "c.png").write_text("not an image")
    inputs = [str(tmp_path / f"{name}.png") for name in "abc"]
    terminal = _FakeTerminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["trace", *inputs, "-o", str(tmp_path / "out")]) == 1
    text = terminal.getvalue()
    assert "\r" in text and "3/3" in text  # tqdm redraws its line and ends at 3 of 3 files
    assert f"splinecraft: {inputs[2]}: not an image" in text
    quiet = _FakeTerminal()
    monkeypatch.setattr(sys, "stderr", quiet)
    assert main(["trace", *inputs, "-o", str(tmp_path / "quiet"), "-q"]) == 1
    assert quiet.getvalue() == f"splinecraft: {inputs[2]}: not an image file (PIL cannot identify its format)\n"


# ---------------------------------------------------------------------------------------------------
# nothing is lost: output = input, failed writes, signals, job cap
# ---------------------------------------------------------------------------------------------------
def test_an_output_that_is_also_an_input_is_refused(tmp_path):
    source = tmp_path / "a.png"
    write_shape(source, "disc")
    before = source.read_bytes()
    result = run_cli("trace", source, "-o", source)
    assert result.returncode == 2 and "also an input" in result.stderr
    assert source.read_bytes() == before
    result = run_cli("trace", source, "-o", tmp_path / "x", "--manifest", source)
    assert result.returncode == 2 and "manifest" in result.stderr and source.read_bytes() == before


def _file_size_limit(limit):
    import resource

    def apply():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
    return apply


def test_a_failed_write_leaves_no_partial_file(tmp_path):
    inputs = [tmp_path / f"{name}.png" for name in "ab"]
    for path in inputs:
        write_shape(path, "ring")
    out = tmp_path / "out"
    out.mkdir()
    result = subprocess.run([sys.executable, "-m", "splinecraft.cli", "trace", *map(str, inputs), "-o", str(out)],
                            capture_output=True, text=True, timeout=300, preexec_fn=_file_size_limit(0))
    assert result.returncode == 1
    for path in inputs:
        assert f"splinecraft: {path}: cannot write {out / path.stem}.svg: File too large" in result.stderr
    assert "cannot write manifest" in result.stderr
    assert [p.name for p in out.iterdir() if p.suffix != ".jsonl"] == []  # no output, no partial file


def test_unwritable_output_directory_is_a_usage_error(tmp_path):
    source, other = tmp_path / "a.png", tmp_path / "b.png"
    write_shape(source, "disc")
    write_shape(other, "ring")
    (tmp_path / "file").write_text("x")
    result = run_cli("trace", source, other, "-o", tmp_path / "file" / "out")
    assert result.returncode == 2 and "not writable" in result.stderr
    result = run_cli("trace", source, "-o", tmp_path / "file" / "a.svg")
    assert result.returncode == 2 and "error:" in result.stderr


def test_jobs_are_capped_at_the_cpu_count(tmp_path):
    from splinecraft.batch import cpu_count

    for name in "ab":
        write_shape(tmp_path / f"{name}.png", "square")
    result = run_cli("trace", tmp_path / "a.png", tmp_path / "b.png", "-o", tmp_path / "out", "--jobs", "1000")
    assert result.returncode == 0, result.stderr
    assert f"--jobs 1000 is more than the {cpu_count()} CPUs of this machine; using {cpu_count()}" in result.stderr


def test_resume_and_scheduler_flags(tmp_path):
    for name in "ab":
        write_shape(tmp_path / f"{name}.png", "ring")
    inputs = [tmp_path / "a.png", tmp_path / "b.png"]
    out = tmp_path / "out"
    assert run_cli("trace", *inputs, "-o", out).returncode == 0
    again = run_cli("trace", *inputs, "-o", out)
    assert again.returncode == 0 and "2 of 2 files already traced (manifest), skipped" in again.stderr
    assert "skipped" not in run_cli("trace", *inputs, "-o", out, "--no-resume").stderr
    threads = run_cli("trace", *inputs, "-o", tmp_path / "threads", "--scheduler", "threads", "--jobs", "2")
    assert threads.returncode == 0, threads.stderr
    for path in inputs:
        assert (tmp_path / "threads" / f"{path.stem}.svg").read_bytes() == (out / f"{path.stem}.svg").read_bytes()
    manifest = tmp_path / "single.jsonl"
    assert run_cli("trace", inputs[0], "-o", tmp_path / "one.svg", "--manifest", manifest).returncode == 0
    assert "skipped" in run_cli("trace", inputs[0], "-o", tmp_path / "one.svg", "--manifest", manifest).stderr
    bad = run_cli("trace", *inputs, "-o", out, "--scheduler", "nowhere")
    assert bad.returncode == 2 and "scheduler must be" in bad.stderr


def test_unreachable_scheduler_is_a_clear_usage_error(tmp_path):
    import socket

    source = tmp_path / "a.png"
    write_shape(source, "disc")
    with socket.socket() as probe:  # a loopback port nobody listens on
        probe.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{probe.getsockname()[1]}"
    started = time.monotonic()
    result = run_cli("trace", source, "-o", tmp_path / "out", "--scheduler", address)
    assert time.monotonic() - started < 30  # 5 s of connection attempts plus two interpreter start-ups
    assert result.returncode == 2
    assert f"splinecraft: error: scheduler '{address}': no dask scheduler answered within 5 s" in result.stderr


def _processes_by_parent():
    children = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    return children


def _descendants(pid):
    children, found, todo = _processes_by_parent(), [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found


def _alive(pid):
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state not in ("Z", "X")  # a zombie has exited


def _poll(condition, timeout, what):
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"timed out after {timeout} s waiting for {what}"
        time.sleep(0.02)


def _start_batch(tmp_path, count=40, size=128):
    from test_batch import glyph_image

    sources = tmp_path / "in"
    sources.mkdir()
    paths = []
    for seed in range(count):
        paths.append(sources / f"g{seed:03d}.png")
        glyph_image(seed, size).save(paths[-1])
    out = tmp_path / "out"
    process = subprocess.Popen([sys.executable, "-m", "splinecraft.cli", "trace", *map(str, paths), "-o", str(out),
                                "--jobs", "2", "--epsilon", "1"],
                               stderr=subprocess.PIPE, text=True, start_new_session=True)
    return process, paths, out


def _assert_nothing_partial(out, paths):
    from test_batch import reference_bytes

    assert not [p.name for p in out.iterdir() if p.name.endswith(".splinecraft-part")]
    for path in paths:
        output = out / f"{path.stem}.svg"
        if output.exists():
            assert output.read_bytes() == reference_bytes(path), output.name
    lines = [json.loads(line) for line in (out / "splinecraft-manifest.jsonl").read_text().splitlines()]
    assert len({line["output"] for line in lines}) == len(lines)
    return lines


@pytest.mark.parametrize("how, code", [("SIGINT", 130), ("SIGTERM", 143), ("group SIGINT", 130)])
def test_a_signal_stops_the_batch_at_once_and_loses_nothing(tmp_path, how, code):
    process, paths, out = _start_batch(tmp_path)
    try:
        manifest = out / "splinecraft-manifest.jsonl"
        _poll(lambda: manifest.exists() and manifest.read_text().endswith("\n"), 120, "the first finished file")
        workers = _descendants(process.pid)
        assert len(workers) >= 2
        number = getattr(signal, how.split()[-1])
        sent = time.monotonic()
        if how.startswith("group"):
            os.killpg(process.pid, number)  # Ctrl-C in a terminal reaches the whole process group
        else:
            process.send_signal(number)
        _, stderr = process.communicate(timeout=60)
        elapsed = time.monotonic() - sent
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    assert process.returncode == code, stderr
    assert elapsed < 2.0, f"exit took {elapsed:.2f} s after {how}"
    assert f"interrupted by {how.split()[-1]}" in stderr
    _poll(lambda: not any(_alive(pid) for pid in workers), 10, "the workers to exit")
    lines = _assert_nothing_partial(out, paths)
    assert 0 < len(lines) < len(paths)  # stopped half-way, and what finished is in the manifest

    again = run_cli("trace", *paths, "-o", out, "--jobs", "2", "--epsilon", "1")
    assert again.returncode == 0, again.stderr
    assert f"{len(lines)} of {len(paths)} files already traced" in again.stderr
    assert len(_assert_nothing_partial(out, paths)) == len(paths)


def test_workers_die_with_a_killed_parent(tmp_path):
    process, paths, out = _start_batch(tmp_path)
    try:
        _poll(lambda: len(_descendants(process.pid)) >= 2, 120, "the worker processes")
        workers = _descendants(process.pid)
        process.kill()
        process.wait(timeout=60)
        _poll(lambda: not any(_alive(pid) for pid in workers), 10, "the orphaned workers to exit")
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
        process.communicate()


# ---------------------------------------------------------------------------------------------------
# the CLI's defaults and choices are the library's (connectivity, threshold, speck area)
# ---------------------------------------------------------------------------------------------------
def write_noisy_scan(path, noise=0.15, size=64, seed=0):
    """A gray square with a one-pixel diagonal crack of paper through it, plus Gaussian noise: the default
    connectivity ("minority" keeps the crack one hole, 8 breaks it into one hole per pixel) and the default
    speck area (from the noise estimate, against 0) both change the result."""
    ink = np.zeros((size, size), bool)
    ink[12:52, 12:52] = True
    diagonal = np.arange(14, 50)
    ink[diagonal, diagonal] = False
    gray = np.where(ink, 0.1, 0.9) + np.random.default_rng(seed).normal(0.0, noise, ink.shape)
    Image.fromarray((np.clip(gray, 0, 1) * 255).round().astype(np.uint8)).save(path)


def library_document(source, **options):
    """What ``splinecraft trace SOURCE -o X.json`` should write: sc.trace's JSON without the wall times."""
    import splinecraft as sc
    from splinecraft.batch._work import TIMING_STATS

    document = json.loads(sc.trace(str(source), **options).to_json())
    for name in TIMING_STATS:
        document["stats"].pop(name, None)
    return document


def cli_document(source, out, *options):
    assert main(["trace", str(source), "-o", str(out), "-q", *map(str, options)]) == 0
    return json.loads(out.read_text())


def test_cli_defaults_trace_like_the_library(tmp_path):
    import inspect

    import splinecraft as sc

    source = tmp_path / "scan.png"
    write_noisy_scan(source)
    defaults = {name: parameter.default for name, parameter in inspect.signature(sc.trace).parameters.items()}
    by_cli = cli_document(source, tmp_path / "default.json")
    assert by_cli == library_document(source)
    assert by_cli["params"]["connectivity"] == defaults["connectivity"] == "minority"
    assert by_cli["params"]["threshold"] == defaults["threshold"]
    assert by_cli["params"]["min_speck_area"] == defaults["min_speck_area"]
    # the CLI's former defaults (8-connected ink, no speck removal) trace this scan differently
    former = library_document(source, connectivity=8, min_speck_area=0)
    assert former["stats"]["boundaries"] > by_cli["stats"]["boundaries"]
    assert cli_document(source, tmp_path / "former.json", "--connectivity", 8, "--min-speck-area", 0) == former


@pytest.mark.parametrize("name, value, noise", [
    *(("connectivity", connectivity, 0.0) for connectivity in ("minority", 4, 8)),
    *(("threshold", threshold, 0.05) for threshold in ("background", "otsu", "sauvola", "local", 0.5)),
])
def test_cli_connectivity_and_threshold_take_the_library_values(tmp_path, name, value, noise):
    source = tmp_path / "scan.png"
    write_noisy_scan(source, noise=noise)
    by_cli = cli_document(source, tmp_path / "out.json", "--" + name, value)
    assert by_cli == library_document(source, **{name: value})
    assert by_cli["params"][name] == value


@pytest.mark.parametrize("option, value, message", [
    ("--connectivity", "6", "expected one of minority, 4, 8"),
    ("--connectivity", "Minority", "expected one of minority, 4, 8"),
    ("--threshold", "otsu2", "expected one of background, otsu, sauvola, local, alpha or a number in [0, 1]"),
    ("--threshold", "1.5", "must be in [0, 1]"),
    ("--threshold", "nan", "must be in [0, 1]"),
    ("--time-budget", "0", "must be a finite number > 0"),
    ("--time-budget", "-1", "must be a finite number > 0"),
    ("--time-budget", "inf", "must be a finite number > 0"),
    ("--time-budget", "nan", "must be a finite number > 0"),
    ("--time-budget", "soon", "not a number"),
    ("--noise-factor", "-2", "must be a finite number >= 0"),
    ("--noise-factor", "x", "not a number"),
])
def test_bad_option_value_is_a_usage_error(tmp_path, capsys, option, value, message):
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    with pytest.raises(SystemExit) as stop:
        main(["trace", str(source), "-o", str(tmp_path / "x.svg"), option, value])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert option in err and message in err
    assert not (tmp_path / "x.svg").exists()


@pytest.mark.parametrize("option, value, expected", [
    ("--time-budget", "none", None), ("--time-budget", "None", None), ("--time-budget", "30", 30.0),
    ("--noise-factor", "0", 0.0), ("--noise-factor", "3.5", 3.5),
])
def test_cli_time_budget_and_noise_factor_take_the_library_values(tmp_path, option, value, expected):
    source = tmp_path / "scan.png"
    write_noisy_scan(source)
    name = option[2:].replace("-", "_")
    by_cli = cli_document(source, tmp_path / "out.json", option, value)
    assert by_cli["params"][name] == expected
    assert by_cli == library_document(source, **{name: expected})


def test_cli_noise_factor_zero_keeps_epsilon_on_a_noisy_scan(tmp_path):
    source = tmp_path / "scan.png"
    write_noisy_scan(source, noise=0.3)
    raised = cli_document(source, tmp_path / "default.json")
    assert raised["stats"]["tolerance"] > raised["params"]["epsilon"]  # the scan is ragged enough to raise it
    kept = cli_document(source, tmp_path / "zero.json", "--noise-factor", 0)
    assert kept["stats"]["tolerance"] == kept["params"]["epsilon"]




def test_help_names_the_library_choices():
    result = run_cli("trace", "--help")
    assert result.returncode == 0
    text = " ".join(result.stdout.split())
    assert "--connectivity {minority,4,8}" in text and "default minority" in text
    assert "--threshold {background,otsu,sauvola,local,alpha}|NUMBER" in text and "default background" in text


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")   # the dropped exception
def test_a_signal_whose_exception_a_destructor_drops_still_stops_the_run():
    # Python runs a signal handler between two bytecodes of the main thread, also inside a __del__, where the
    # exception it raises is printed and dropped (a zip file's clean-up once swallowed a SIGTERM this way and
    # the batch ran on to exit 0); the run's check after every file raises it again
    from splinecraft import cli

    class SignalsInItsDestructor:
        def __del__(self):
            os.kill(os.getpid(), signal.SIGTERM)

    went_on, before = [], signal.getsignal(signal.SIGTERM)
    with pytest.raises(cli.Interrupted) as stopped:
        with cli._signals_raise() as stop_if_signalled:
            SignalsInItsDestructor()              # the handler's exception is dropped inside __del__
            went_on.append(True)
            stop_if_signalled()
    assert went_on == [True]
    assert stopped.value.signum == signal.SIGTERM
    assert signal.getsignal(signal.SIGTERM) == before         # the old handler is back


@pytest.mark.skipif(sys.platform != "linux", reason="file names of arbitrary bytes are a POSIX matter")
@pytest.mark.parametrize("raw_name, shown", [(b"caf\xe9.png", "caf\ufffd.png"), (b"scan\x01.png", "scan\ufffd.png"),
                                             (b"a & <b>.png", "a & <b>.png")])
def test_a_file_name_xml_cannot_hold_still_gives_a_well_formed_svg(tmp_path, raw_name, shown):
    # a Latin-1 name from an old archive decodes to surrogates (os.fsdecode), a control character is legal in
    # a POSIX name: neither may reach the SVG's <title> as it is (the file failed, or the SVG was not XML)
    write_shape(tmp_path / "ok.png", "disc")
    source = os.path.join(os.fsencode(tmp_path), raw_name)
    os.rename(tmp_path / "ok.png", source)
    out = tmp_path / "out.svg"
    assert main(["trace", os.fsdecode(source), "-o", str(out), "-q"]) == 0
    root = ET.fromstring(out.read_bytes())
    assert root.find(f"{SVG}title").text == shown
    assert subpath_count(out.read_text(encoding="utf-8"))[0] == 1


def test_help_examples_of_corner_params_run(tmp_path):
    """The --corner-param examples of --help run as written (a thesis detector's parameter once named for the
    default detector was refused)."""
    import re

    shown = subprocess.run([sys.executable, "-m", "splinecraft.cli", "trace", "--help"], capture_output=True,
                           text=True, timeout=300, env={**os.environ, "COLUMNS": "1000"})  # no wrapped options
    text = " ".join(shown.stdout.split())
    examples = re.findall(r"e\.g\. (--corner-param \S+) for the default \S+, (--corner-method \S+ --corner-param \S+) for the thesis",
                          text)
    assert examples, text
    write_shape(tmp_path / "disc.png", "disc")
    for example in examples[0]:
        assert main(["trace", str(tmp_path / "disc.png"), "-o", str(tmp_path / "out.svg"), "-q", *example.split()]) == 0


def test_a_files_warnings_are_printed_with_its_name_even_when_quiet(tmp_path):
    """A warning of one file's trace (here the ink polarity of light shapes on a dark background) is printed
    as 'splinecraft: FILE: warning: ...' and kept in the manifest, not as a Python warning of the package's
    own source line; the other file has none."""
    negative = tmp_path / "negative.png"
    mask = write_shape(tmp_path / "positive.png", "disc")
    Image.fromarray(np.where(mask, 230, 20).astype(np.uint8)).save(negative)
    result = run_cli("trace", negative, tmp_path / "positive.png", "-o", tmp_path / "out", "-q", "--no-resume")
    assert result.returncode == 0
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith(f"splinecraft: {negative}: warning: InkPolarityWarning: ")
    assert "--invert" in lines[0] and "invert=True" not in lines[0] and ".py:" not in result.stderr
    entries = {os.path.basename(json.loads(line)["input"]): json.loads(line)
               for line in (tmp_path / "out" / "splinecraft-manifest.jsonl").read_text().splitlines()}
    assert entries["negative.png"]["warnings"] == [lines[0].split("warning: ", 1)[1]]
    assert entries["positive.png"]["warnings"] == []


@pytest.mark.parametrize("option", [("--epsilon", "1e-300"), ("--corner-param", "nonsense=3"), ("--decimals", "100")])
def test_bad_options_with_stdout_output_are_one_line_usage_errors(tmp_path, option):
    """``-o -`` answers a bad option as a file output does: one line, exit 2, no traceback (it printed a
    traceback and exited 1)."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    result = run_cli("trace", source, "-o", "-", *option)
    assert result.returncode == 2 and "Traceback" not in result.stderr and result.stdout == ""
    assert "error" in result.stderr


def test_decimals_beyond_the_limit_are_refused_before_any_trace(tmp_path):
    """``--decimals 100`` / ``trace_many(decimals=100)`` were accepted and every file failed after its trace."""
    from splinecraft.batch import trace_many

    source = tmp_path / "sq.png"
    write_shape(source, "square")
    result = run_cli("trace", source, "-o", tmp_path / "x.svg", "--decimals", "65")
    assert result.returncode == 2 and "must be <= 64" in result.stderr and not (tmp_path / "x.svg").exists()
    with pytest.raises(ValueError, match="decimals must be <= 64"):
        trace_many([str(source)], decimals=100)


@pytest.mark.parametrize("output,how", [("", "empty"), (" ", "blank (' ': only white space)")])
def test_an_empty_or_blank_output_is_refused_before_any_trace(tmp_path, output, how):
    """``-o ''`` was accepted and failed only after the trace (the output path was the current directory); ``-o ' '``
    (an unset variable in quotes beside a space) wrote a file called space."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    result = run_cli("trace", source, "-o", output, cwd=tmp_path)
    lines = result.stderr.splitlines()
    assert result.returncode == 2 and len(lines) == 1, result.stderr
    assert lines[0] == f"splinecraft: error: -o/--output is {how}: give an output file, a directory, or - for stdout"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sq.png"]  # nothing written, no manifest


@pytest.mark.parametrize("name", ["out.svg", "OUT.JSON"])
def test_a_file_output_for_several_inputs_is_refused(tmp_path, name):
    """``-o out.svg`` with two inputs created a directory named out.svg; a name with an output suffix is
    refused (exit 2, one line) unless it is an existing directory or ends with a separator."""
    for stem, kind in [("a", "disc"), ("b", "square")]:
        write_shape(tmp_path / f"{stem}.png", kind)
    inputs = [tmp_path / "a.png", tmp_path / "b.png"]
    result = run_cli("trace", *inputs, "-o", tmp_path / name)
    lines = result.stderr.splitlines()
    assert result.returncode == 2 and len(lines) == 1, result.stderr
    assert lines[0].startswith("splinecraft: error: ") and name in lines[0] and "2 inputs" in lines[0]
    assert not (tmp_path / name).exists()
    assert run_cli("trace", *inputs, "-o", f"{tmp_path / name}{os.sep}", "-q").returncode == 0  # asked for a directory
    assert sorted(p.name for p in (tmp_path / name).iterdir()) == ["a.svg", "b.svg", "splinecraft-manifest.jsonl"]
    assert run_cli("trace", *inputs, "-o", tmp_path / name, "-q", "--no-resume").returncode == 0  # it exists now


def test_the_polarity_warning_names_the_option_of_its_interface(tmp_path):
    """The dark-background warning said ``pass invert=True`` on the command line too: there it names
    ``--invert`` (also with ``-o -``), while ``sc.trace`` keeps the Python spelling."""
    import splinecraft as sc
    from splinecraft.capture.image import InkPolarityWarning

    negative = tmp_path / "negative.png"
    mask = write_shape(tmp_path / "positive.png", "disc")
    Image.fromarray(np.where(mask, 230, 20).astype(np.uint8)).save(negative)
    with pytest.warns(InkPolarityWarning, match=r"pass invert=True"):
        sc.trace(negative)
    for output in (tmp_path / "n.svg", "-"):
        result = run_cli("trace", negative, "-o", output, "-q")
        (line,) = result.stderr.splitlines()
        assert result.returncode == 0 and "InkPolarityWarning" in line
        assert line.endswith("pass --invert") and "invert=True" not in line


def write_two_squares(path, big=10, small=6):
    """Two ink squares of big**2 and small**2 pixels on white; returns their pixel counts."""
    image = np.full((40, 40), 255, np.uint8)
    image[5:5 + big, 5:5 + big] = 0
    image[25:25 + small, 25:25 + small] = 0
    Image.fromarray(image).save(path)
    return big * big, small * small


def test_speck_removal_that_removes_all_ink_says_so(tmp_path):
    """``--min-speck-area`` above every ink component said "no ink pixels after thresholding"; the error says
    that speck removal removed all N ink pixels, how large the largest component was and what keeps it, in
    the library's spelling for ``sc.trace`` and ``trace_many`` and the option's on the command line."""
    import splinecraft as sc

    source = tmp_path / "squares.png"
    big, small = write_two_squares(source)
    with pytest.raises(ValueError) as caught:
        sc.trace(source, min_speck_area=big + 1)
    message = str(caught.value)
    assert f"speck removal removed all {big + small} ink pixels" in message
    assert f"min_speck_area={big + 1}" in message and f"largest ink component has {big} pixels" in message
    assert f"lower min_speck_area to {big} or less" in message and "after thresholding" not in message
    assert sc.trace(source, min_speck_area=big).stats["boundaries"] == 1  # the advice keeps it
    (record,) = sc.trace_many([str(source)], progress=False, min_speck_area=big + 1)
    assert record.status == "failed" and f"removed all {big + small} ink pixels" in record.error

    result = run_cli("trace", source, "-o", tmp_path / "out.svg", "--min-speck-area", big + 1)
    (line,) = result.stderr.splitlines()
    assert result.returncode == 1 and line.startswith(f"splinecraft: {source}: ")
    assert f"removed all {big + small} ink pixels" in line and f"--min-speck-area {big + 1}" in line
    assert f"lower --min-speck-area to {big} or less" in line and "min_speck_area" not in line


def test_blank_pages_still_have_no_ink_after_thresholding(tmp_path):
    """Without ink to remove, the message stays the thresholding one (nothing was removed)."""
    import splinecraft as sc

    source = tmp_path / "blank.png"
    write_shape(source, "blank")
    for area in (None, 0, 50):
        with pytest.raises(ValueError, match="no ink pixels after thresholding"):
            sc.trace(source, min_speck_area=area)


def test_a_spent_time_budget_is_reported_per_file(tmp_path):
    """Boundaries the time budget left as polygons were reported nowhere on the command line, and ``-v`` gave
    them a deviation of 0 px like fits. Now: one warning line per file (not with ``-q``), a ``-v`` line that
    counts them apart from the fitted boundaries, and ``stats["polygons"]`` plus a note in Python."""
    import splinecraft as sc

    source = tmp_path / "ring.png"
    write_shape(source, "ring")
    budget = "1e-9"  # spent before the first boundary: every boundary gets its polygon
    library = sc.trace(source, time_budget=float(budget))
    total = library.stats["boundaries"]
    polygons = sum(entry["budget"] == "polygon" for entry in library.stats["per_boundary"])
    assert total > 1 and library.stats["polygons"] == polygons == total
    assert any(f"{polygons} of {total} boundaries got the polygon" in note for note in library.notes)
    assert sc.trace(source).stats["polygons"] == 0

    expected = (f"splinecraft: {source}: time budget {float(budget):g} s reached: {polygons} of {total} boundaries "
                "kept as polygons (use --time-budget none or a larger value)")
    for output in (tmp_path / "ring.svg", "-"):
        result = run_cli("trace", source, "-o", output, "--time-budget", budget)
        assert result.returncode == 0 and result.stderr.splitlines() == [expected], result.stderr
    quiet = run_cli("trace", source, "-o", tmp_path / "ring.svg", "--time-budget", budget, "-q")
    assert quiet.returncode == 0 and quiet.stderr == ""
    verbose = run_cli("trace", source, "-o", tmp_path / "ring.svg", "--time-budget", budget, "-v")
    (summary,) = [line for line in verbose.stderr.splitlines() if not line.startswith("splinecraft:")]
    assert f"{total} boundaries" in summary and f"0 fitted, {polygons} kept as polygons" in summary
    assert "max deviation" not in summary and "converged" not in summary
    fitted = run_cli("trace", source, "-o", tmp_path / "ring.svg", "-v")
    (summary,) = fitted.stderr.splitlines()
    assert "polygons" not in summary and "max deviation" in summary and "converged" in summary


def test_max_pixels_caps_the_decoded_image_size(tmp_path, capsys):
    """``load_bitmap(max_pixels=)`` (the decompression-bomb cap) had no option: ``--max-pixels N`` and
    ``sc.trace(max_pixels=N)`` pass it on; it is checked up front, named in ``--help``, and changes no output
    (a rerun with another cap skips the finished file)."""
    import splinecraft as sc
    from splinecraft.capture.image import MAX_PIXELS

    source = tmp_path / "disc.png"
    write_shape(source, "disc")
    pixels = Image.open(source).width * Image.open(source).height
    with pytest.raises(ValueError, match=f"more than max_pixels={pixels - 1}"):
        sc.trace(source, max_pixels=pixels - 1)
    assert sc.trace(source, max_pixels=pixels).to_svg() == sc.trace(source).to_svg()
    with pytest.raises(ValueError, match="max_pixels"):
        sc.trace_many([str(source)], progress=False, max_pixels=0)

    (tmp_path / "out").mkdir()  # a directory: a manifest, so that a rerun can skip
    refused = run_cli("trace", source, "-o", tmp_path / "out", "--max-pixels", pixels - 1)
    (line,) = refused.stderr.splitlines()
    reason = line.removeprefix(f"splinecraft: {source}: ")  # (the test's directory is named max_pixels too)
    assert refused.returncode == 1 and f"more than --max-pixels {pixels - 1}" in reason and "max_pixels" not in reason
    assert run_cli("trace", source, "-o", tmp_path / "out", "--max-pixels", pixels, "-q").returncode == 0
    again = run_cli("trace", source, "-o", tmp_path / "out", "--max-pixels", 10 * pixels)
    assert again.returncode == 0 and "1 of 1 files already traced" in again.stderr
    for bad in ("0", "-5", "many"):
        result = run_cli("trace", source, "-o", tmp_path / "x.svg", "--max-pixels", bad)
        assert result.returncode == 2 and "--max-pixels" in result.stderr
    with pytest.raises(SystemExit):
        main(["trace", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    assert "--max-pixels N" in help_text and f"default {MAX_PIXELS}" in help_text


def test_an_all_black_image_says_so_on_the_command_line(tmp_path, capsys):
    """An all-black file traced to its frame rectangle (the documented outline of an all-ink image) with exit
    code 0 and not a word: the library says so in TraceResult.notes only, which an SVG output drops. Now a
    warning line names the file, as the polarity warning of a dark background does, also with -q and for
    stdout; a file with ink and paper gets none."""
    black = tmp_path / "black.png"
    Image.fromarray(np.zeros((20, 30), np.uint8)).save(black)
    write_shape(tmp_path / "disc.png", "disc")
    for output in (tmp_path / "black.svg", "-"):
        assert main(["trace", str(black), "-o", str(output), "-q"]) == 0
        err = capsys.readouterr().err
        assert f"splinecraft: {black}: warning: InkPolarityWarning: every pixel is ink" in err
        assert "see --threshold/--invert" in err
    assert main(["trace", str(tmp_path / "disc.png"), "-o", str(tmp_path / "disc.svg"), "-q"]) == 0
    assert capsys.readouterr().err == ""


def test_a_corner_param_pair_can_be_given(tmp_path, capsys):
    """tangent-jump's flank is a pair (near, far): --corner-param flank=4,10 was the text '4,10' and refused as
    'must be a pair of integers (near, far)', which no value of the option could meet. A value with commas is
    a tuple now; the output is the library's with corner_params={'flank': (4, 10)}."""
    import splinecraft as sc
    from splinecraft.cli import _key_value

    assert _key_value("flank=4,10") == ("flank", (4, 10))
    assert _key_value("ta=150") == ("ta", 150) and _key_value("wedge=true") == ("wedge", True)
    mask = write_shape(tmp_path / "square.png", "square")
    out = tmp_path / "out.svg"
    assert main(["trace", str(tmp_path / "square.png"), "-o", str(out), "-q", "--corner-param", "flank=3,12"]) == 0
    expected = sc.trace(mask, corner_params={"flank": (3, 12)}).to_svg(title="square.png")
    assert out.read_text() == expected
    assert main(["trace", str(tmp_path / "square.png"), "-o", str(out), "-q", "--corner-param", "flank=4,10,2"]) == 2
    assert "--corner-param flank must be a pair of integers" in capsys.readouterr().err


def test_every_warning_of_a_trace_reaches_stderr_and_the_manifest(tmp_path):
    """The command line printed a file's Python warnings and its all-ink note but dropped its other notes that say
    the output is not what was asked for: boundaries that did not converge (``--max-iterations`` too low) were
    reported only by ``-v``, and a spent time budget was in no manifest line. Now each is a warning line of its file
    (``Category: message``, in the command's spelling) in its record and manifest line, and on stderr: the budget
    in the command's own line, not with ``-q`` (as before); the others with its name, also with ``-q``."""
    from splinecraft.batch import MANIFEST_NAME

    ring = tmp_path / "ring.png"
    write_shape(ring, "ring")
    anim = tmp_path / "anim.gif"
    frames = [Image.fromarray(np.where(m, 0, 255).astype(np.uint8)) for m in (write_shape(tmp_path / "d.png", "disc"),
                                                                             write_shape(tmp_path / "s.png", "square"))]
    frames[0].save(anim, save_all=True, append_images=frames[1:])
    out = tmp_path / "out"
    result = run_cli("trace", ring, anim, "-o", out, "--method", "random", "--max-iterations", 1, "-q")
    assert result.returncode == 0, result.stderr
    lines = result.stderr.splitlines()
    entries = {os.path.basename(json.loads(line)["input"]): json.loads(line)["warnings"]
               for line in (out / MANIFEST_NAME).read_text().splitlines()}
    for source in (ring, anim):
        mine = [line.split(": warning: ", 1)[1] for line in lines if line.startswith(f"splinecraft: {source}: warning: ")]
        assert mine == entries[source.name], (mine, entries)
    (converge,) = [line for line in entries["ring.png"] if line.startswith("NotConverged: ")]
    assert converge.startswith("NotConverged: 2 of 2 boundaries did not converge") and "--max-iterations 1 reached" in converge
    assert "max_iterations" not in converge
    assert any(line.startswith("MultiFrameWarning: ") and "2 frames" in line for line in entries["anim.gif"])
    assert len(lines) == sum(map(len, entries.values()))

    budget = run_cli("trace", ring, "-o", f"{tmp_path / 'budget'}{os.sep}", "--time-budget", "1e-9", "-q")
    assert budget.returncode == 0 and budget.stderr == ""
    (entry,) = [json.loads(line) for line in (tmp_path / "budget" / MANIFEST_NAME).read_text().splitlines()]
    (line,) = entry["warnings"]
    assert line.startswith("TimeBudget: time budget of 1e-09 s spent: 2 of 2 boundaries got the polygon")
    assert "--time-budget none fits them all" in line and "time_budget=None" not in line


def test_knot_rounds_stopped_by_the_time_budget_get_their_line():
    """Knot rounds that a spent time budget stopped (a note in Python) said nothing on the command line; they get
    a line of the budget's kind, not with -q, and the record's TimeBudget warning line is not printed twice."""
    from splinecraft.batch import FileRecord
    from splinecraft.cli import _file_messages

    record = FileRecord(input="page.png", output="page.svg", status="ok",
                        stats={"boundaries": 5, "polygons": 0, "budget_stopped": 2},
                        warnings=["TimeBudget: time budget of 5 s: the knot rounds of 2 boundaries stopped before "
                                  "convergence", "NotConverged: 1 of 5 boundaries did not converge: boundary 3 (90 "
                                  "points): --max-iterations 4 reached with a deviation of 1.2 px"])
    assert _file_messages(record, False, 5.0) == [
        "splinecraft: page.png: warning: " + record.warnings[1],
        "splinecraft: page.png: time budget 5 s reached: the knot rounds of 2 of 5 boundaries stopped before "
        "convergence (use --time-budget none or a larger value)"]
    assert _file_messages(record, True, 5.0) == ["splinecraft: page.png: warning: " + record.warnings[1]]


@pytest.mark.parametrize("options, named", [
    (["--manifest", "m.jsonl"], "--manifest"), (["--jobs", "2"], "--jobs"), (["-j", "1"], "--jobs"),
    (["--scheduler", "threads"], "--scheduler"), (["--batch-size", "3"], "--batch-size"),
    (["--manifest", "m.jsonl", "--jobs", "2"], "--manifest, --jobs"),
])
def test_stdout_output_refuses_the_options_of_file_outputs(tmp_path, options, named):
    """``-o -`` ignored ``--manifest``, ``--jobs``, ``--scheduler`` and ``--batch-size`` without a word (no manifest
    was written, nothing ran in parallel). They are refused before anything is traced: a usage error naming them,
    exit code 2, nothing on stdout and no manifest."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    result = run_cli("trace", source, "-o", "-", *options, cwd=tmp_path)
    assert result.returncode == 2 and result.stdout == "", result.stderr
    last = result.stderr.splitlines()[-1]
    assert last.startswith("splinecraft trace: error: ") and f"-o - (stdout) does not take {named}" in last
    assert result.stderr.startswith("usage: splinecraft trace")
    assert sorted(path.name for path in tmp_path.iterdir()) == ["sq.png"]
    assert run_cli("trace", source, "-o", "-", "--batch-size", "auto", "-q").returncode == 0  # the default, spelt out


def test_verbose_stats_reach_stderr_with_stdout_output(tmp_path):
    """``-v`` prints each file's stats on stderr; with ``-o -`` it printed nothing (the stdout path never looked at
    it). The SVG goes to stdout, the stats line to stderr, as with a file output."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    to_file = run_cli("trace", source, "-o", tmp_path / "sq.svg", "-v")
    to_stdout = run_cli("trace", source, "-o", "-", "-v")
    assert to_stdout.returncode == 0 and subpath_count(to_stdout.stdout)[0] == 1
    (line,) = to_stdout.stderr.splitlines()
    assert line.startswith(f"{source}: 1 boundaries (0 holes), ") and " iterations, max deviation " in line
    assert line.rsplit(", ", 1)[0] == to_file.stderr.strip().rsplit(", ", 1)[0]  # the same line but its time


@pytest.mark.parametrize("output, options", [("x.json", []), ("-", ["--format", "json"]),
                                             ("dir/", ["--format", "json"])])
def test_decimals_with_json_output_is_refused(tmp_path, output, options):
    """``--decimals`` sets the decimal places of SVG coordinates; a JSON output keeps full precision, so with
    ``--format json`` (or ``-o x.json``) it was ignored without a word. A usage error naming both, before anything
    is traced; with SVG it still applies."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    result = run_cli("trace", source, "-o", output, "--decimals", "2", *options, cwd=tmp_path)
    assert result.returncode == 2 and result.stdout == "", result.stderr
    assert "--decimals applies to SVG output only" in result.stderr.splitlines()[-1]
    assert sorted(path.name for path in tmp_path.iterdir()) == ["sq.png"]
    svg = run_cli("trace", source, "-o", "-", "--decimals", "2")
    assert svg.returncode == 0 and subpath_count(svg.stdout)[0] == 1


@pytest.mark.parametrize("method", [None, "lsq"])
def test_a_seed_for_a_method_without_random_numbers_is_refused(tmp_path, capsys, method):
    """``--seed`` with ``lsq`` (deterministic) would be ignored: refused naming the method, as the library refuses
    ``tau`` and ``fuzzy_weights`` for the methods that do not use them."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    with pytest.raises(SystemExit) as stop:
        main(["trace", str(source), "-o", str(tmp_path / "x.svg"), "--seed", "5"]
             + (["--method", method] if method else []))
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "--seed" in err and "'lsq'" not in err and "--method lsq" in err and "random" in err
    assert not (tmp_path / "x.svg").exists()


def test_a_seed_reaches_a_random_method(tmp_path):
    source = tmp_path / "disc.png"
    write_shape(source, "disc")
    outputs = {}
    for seed in ("1", "2", None):
        output = tmp_path / f"{seed}.json"
        assert main(["trace", str(source), "-o", str(output), "--method", "random", "-q"]
                    + (["--seed", seed] if seed else [])) == 0
        outputs[seed] = json.loads(output.read_text())
    assert outputs["1"]["params"]["seed"] == 1 and outputs["2"]["params"]["seed"] == 2
    assert outputs[None]["params"]["seed"] == 0  # the library's default


def test_fit_params_can_be_given_and_trace_like_the_library(tmp_path):
    """--fit-param NAME=VALUE is the library's fit_params (there was no way to reach them from the command line:
    the thesis's C2 fit, merge_tolerance=0, for one)."""
    import splinecraft as sc

    source = tmp_path / "ring.png"
    write_shape(source, "ring")
    output = tmp_path / "ring.svg"
    assert main(["trace", str(source), "-o", str(output), "-q", "--fit-param", "merge_tolerance=0",
                 "--fit-param", "remove_knots=false"]) == 0
    expected = sc.trace(str(source), fit_params={"merge_tolerance": 0, "remove_knots": False})
    assert output.read_text() == expected.to_svg(title="ring.png", decimals=4)
    assert output.read_text() != sc.trace(str(source)).to_svg(title="ring.png", decimals=4)


@pytest.mark.parametrize("options, message", [
    (["--fit-param", "merge_tolerance=-1"], "--fit-param merge_tolerance must be >= 0, got -1.0"),
    (["--fit-param", "merge_tolerance=nan"], "--fit-param merge_tolerance must be a finite number >= 0, got nan"),
    (["--fit-param", "no_such=1"], "--fit-param has an unknown name 'no_such' for method 'lsq'; allowed: ["),
    (["--fit-param", "fuzzy_weights=0.1,0.2", "--method", "fuzzy"],
     "--fit-param fuzzy_weights (w, v) need w > v >= 0 (thesis eq 4.21), got (0.1, 0.2)"),
    (["--corner-param", "min_turn=-1"], "--corner-param min_turn must be >= 0 and < 180, got -1.0"),
    (["--corner-param", "no_such=1"], "--corner-param has an unexpected name 'no_such' for the 'tangent-jump'"),
])
@pytest.mark.parametrize("output", ["x.svg", "-"])
def test_a_bad_fit_or_corner_param_is_named_as_its_option(tmp_path, capsys, options, message, output):
    """The library names a bad value by the key of its mapping (fit_params['merge_tolerance']); the command line
    says which option it came from (--fit-param merge_tolerance), before anything is traced."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    destination = output if output == "-" else str(tmp_path / output)
    assert main(["trace", str(source), "-o", destination, *options]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"splinecraft: error: {message}"), err
    assert len(err.splitlines()) == 1 and "fit_params" not in err and "corner_params" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sq.png"]


@pytest.mark.parametrize("options, message", [
    (["--tau", "3"], "--tau is used by the methods 'euclidean' and 'positional' only, not 'lsq'"),
    (["--tau", "nan", "--method", "euclidean"], "--tau (Euclidean nearness, px) must be a finite number >= 0, got nan"),
    (["--tau", "50", "--method", "positional"], "--tau (positional nearness, % of the piece's points) must be >= 0"),
])
def test_a_bad_tau_is_named_as_its_option(tmp_path, capsys, options, message):
    """--tau is passed to the library as given; its message named the library's 'tau'."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    assert main(["trace", str(source), "-o", str(tmp_path / "x.svg"), *options]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"splinecraft: error: {message}"), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sq.png"]


@pytest.mark.parametrize("output, options, message", [
    ("out.png", [], "-o out.png names an image file, but the output is SVG text: name it out.svg"),
    ("OUT.JPG", ["--format", "json"], "-o OUT.JPG names an image file, but the output is JSON text: name it OUT.json"),
    ("t.svg", ["--format", "json"], "-o t.svg names an SVG file, but --format json asks for JSON: leave --format out, "
                                    "or name the output t.json"),
    ("t.json", ["--format", "svg"], "-o t.json names a JSON file, but --format svg asks for SVG"),
])
def test_an_output_named_for_another_format_is_refused(tmp_path, output, options, message):
    """-o out.png wrote SVG text into out.png (and -o other.png overwrote another image with it); -o t.svg with
    --format json wrote JSON into t.svg. Usage errors before anything is traced; an existing image is kept."""
    source = tmp_path / "sq.png"
    write_shape(source, "square")
    other = tmp_path / "other.png"
    write_shape(other, "disc")
    kept = other.read_bytes()
    for target in (output, "other.png"):
        result = run_cli("trace", source, "-o", target, *options, cwd=tmp_path)
        assert result.returncode == 2, result.stderr
        assert len(result.stderr.splitlines()) == 1
        if target == output:
            assert result.stderr.startswith(f"splinecraft: error: {message}"), result.stderr
    assert other.read_bytes() == kept
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.png", "sq.png"]
