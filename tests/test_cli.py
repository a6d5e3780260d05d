"""Tests of the command line (splinecraft.cli), run as a real process: ``python -m splinecraft.cli``."""
import io
import json
import subprocess
import sys
import xml.etree.ElementTree as ET

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

    result = run_cli("trace", source, "-o", tmp_path / "out" / "ring.json", "--seed", "3", "-v")
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
