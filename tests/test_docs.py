"""The project's own documentation resolves: every section and erratum reference has a heading in docs/.

A bare section sign with a number (such as the one of the tangent system, 2.3) in a docstring, a notebook,
a test or the README names a heading of ``docs/math.md`` (sections 0-8, errata E1-E22 under section 8) or
``docs/capture.md`` (sections 9-13). Ranges ("2.2-2.4", "E16-E18") resolve both ends. The README must
not name files or folders of the repository that do not exist.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
DOCS = REPO / "docs"
SECTION_SIGN = "\u00a7"

HEADING = re.compile(rf"^#{{1,6}}\s+(?:{SECTION_SIGN}(?P<section>\d+(?:\.\d+)*)|(?P<erratum>E\d+))(?=\s|$)")
NUMBER = r"\d+(?:\.\d+)*"
SECTION_REF = re.compile(rf"{SECTION_SIGN}\s?(?P<first>{NUMBER})(?:\s?[-\u2013]\s?{SECTION_SIGN}?(?P<last>{NUMBER}))?")
ERRATUM_REF = re.compile(r"\bE(?P<first>\d{1,2})\b(?:\s?[-\u2013]\s?E(?P<last>\d{1,2})\b)?")

# Sections numbered as the verified write-up of the thesis's formulas (math) and the capture pipeline.
EXPECTED_SECTIONS = (
    [str(k) for k in range(14)]
    + [f"2.{k}" for k in range(1, 6)] + [f"4.{k}" for k in range(1, 6)]
    + [f"5.{k}" for k in range(1, 7)] + [f"6.{k}" for k in range(1, 4)]
)
EXPECTED_ERRATA = [f"E{k}" for k in range(1, 23)]

# Where references are written: sources, widgets' JS, notebooks (and their sources), tests, benchmarks, docs.
SCANNED = ["src", "js", "notebooks", "tests", "benchmarks", "docs", "README.md", "BENCHMARKS.md"]
SUFFIXES = {".py", ".js", ".mjs", ".css", ".ipynb", ".md", ".txt"}


def doc_headings() -> dict:
    """``{"2.5": "math.md:123", "E21": "math.md:456", ...}`` from the headings of docs/*.md."""
    found = {}
    for page in sorted(DOCS.glob("*.md")):
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            match = HEADING.match(line)
            if match:
                key = match["section"] or match["erratum"]
                assert key not in found, f"{page.name}:{number}: heading {key} also at {found[key]}"
                found[key] = f"{page.name}:{number}"
    return found


def scanned_files() -> list[Path]:
    files = []
    for name in SCANNED:
        path = REPO / name
        if path.is_file():
            files.append(path)
        elif path.is_dir():
            files.extend(p for p in sorted(path.rglob("*"))
                         if p.is_file() and p.suffix in SUFFIXES and "__pycache__" not in p.parts)
    return [p for p in files if p.resolve() != Path(__file__).resolve()]


def references(text: str):
    """``(line, key)`` for every section and erratum reference in ``text``."""
    for number, line in enumerate(text.splitlines(), 1):
        for match in SECTION_REF.finditer(line):
            for key in (match["first"], match["last"]):
                if key:
                    yield number, key
        for match in ERRATUM_REF.finditer(line):
            for key in (match["first"], match["last"]):
                if key:
                    yield number, f"E{key}"


def test_docs_have_every_numbered_heading():
    headings = doc_headings()
    missing = [key for key in EXPECTED_SECTIONS + EXPECTED_ERRATA if key not in headings]
    assert not missing, f"docs/ lacks the headings {missing}"
    assert all(headings[key].startswith("math.md") for key in EXPECTED_ERRATA + [str(k) for k in range(9)])
    assert all(headings[str(k)].startswith("capture.md") for k in range(9, 14))


def test_errata_are_under_section_8():
    lines = (DOCS / "math.md").read_text(encoding="utf-8").splitlines()
    eight = next(i for i, line in enumerate(lines) if HEADING.match(line) and HEADING.match(line)["section"] == "8")
    for key in EXPECTED_ERRATA:
        index = next(i for i, line in enumerate(lines) if HEADING.match(line) and HEADING.match(line)["erratum"] == key)
        assert index > eight, f"{key} is above section 8"


def test_reference_parser_reads_ranges_and_lists():
    text = f"see {SECTION_SIGN}2.2-2.4 and {SECTION_SIGN}6.1-{SECTION_SIGN}6.2,\nerrata E16-E18, E21; 1E12 is a number"
    assert list(references(text)) == [(1, "2.2"), (1, "2.4"), (1, "6.1"), (1, "6.2"),
                                      (2, "E16"), (2, "E18"), (2, "E21")]


def test_every_reference_resolves():
    headings = doc_headings()
    unresolved = []
    count = 0
    for path in scanned_files():
        text = path.read_text(encoding="utf-8", errors="replace")
        for line, key in references(text):
            count += 1
            if key not in headings:
                unresolved.append(f"{path.relative_to(REPO)}:{line}: {SECTION_SIGN if key[0] != 'E' else ''}{key}")
    assert count > 100, "the scan found almost no references: is the pattern still right?"
    assert not unresolved, "references without a heading in docs/:\n" + "\n".join(unresolved)


# Repository paths a README or docs page may name: top-level folders, root files, and modules of the package
# (``capture/trace.py`` is read inside src/splinecraft/).
PACKAGE = REPO / "src" / "splinecraft"
_SUBPACKAGES = "|".join(sorted(p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()))
_PREFIXES = r"(?:\.ci|src|js|notebooks|tests|benchmarks|scripts|docs|jupyter-config)"
README_PATH = re.compile(
    rf"(?<![\w./-])(?:{_PREFIXES}(?:/[\w.*-]+)*/?|(?:{_SUBPACKAGES})/(?:[\w.*-]+/?)*"
    rf"|[A-Z][\w-]*\.(?:md|toml|txt)|pyproject\.toml)(?![\w-])")
README_LINK = re.compile(r"\]\((?!https?:|#|mailto:)(?P<target>[^)\s#]+)")


def readme_paths(text: str) -> list[tuple[int, str]]:
    found = []
    for number, line in enumerate(text.splitlines(), 1):
        found += [(number, m.group(0).rstrip(".,:;")) for m in README_PATH.finditer(line)]
        found += [(number, m["target"]) for m in README_LINK.finditer(line)]
    return found


def _exists(relative: str, beside: Path) -> bool:
    """``relative`` names something in the repository, beside the page, or inside the package."""
    relative = relative.rstrip("/")
    for base in (REPO, beside, PACKAGE):
        if any(ch in relative for ch in "*?["):
            if any(base.glob(relative)):
                return True
        elif (base / relative).exists():
            return True
    return False


def test_readme_path_parser():
    text = "run `bash scripts/start.sh`, see [BENCHMARKS.md](BENCHMARKS.md) and `tests/bad_input/test_*.py`;\n" \
           "`splinecraft trace a.png -o out/` writes letter.svg; docstrings of capture/trace.py trace an outline"
    assert set(readme_paths(text)) == {(1, "scripts/start.sh"), (1, "BENCHMARKS.md"), (1, "tests/bad_input/test_*.py"),
                                       (2, "capture/trace.py")}


@pytest.mark.parametrize("page", ["README.md", "docs/README.md", "docs/math.md", "docs/capture.md"])
def test_readme_names_only_existing_files(page):
    text = (REPO / page).read_text(encoding="utf-8")
    paths = readme_paths(text)
    if page == "README.md":
        assert paths, "the README names no file at all: is the pattern still right?"
    missing = [f"{page}:{line}: {relative}" for line, relative in paths
               if not _exists(relative, (REPO / page).parent)]
    assert not missing, "named but not in the repository:\n" + "\n".join(missing)
