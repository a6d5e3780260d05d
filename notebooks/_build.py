"""Generate the classroom notebooks in notebooks/ from one source, so they stay consistent.

Run from the repository root after editing:  .venv/bin/python notebooks/_build.py [NAME ...]
The notebooks are written without outputs (tests/test_notebooks.py executes them). The cells live in
``notebooks/_lessons.py``: a shared setup cell (imports, the small bqplot helper ``Plot``), then the
lesson, then a final "Check" cell that asserts what the lesson claimed, so an executed notebook is
also a test.
"""
from __future__ import annotations

import sys
from pathlib import Path

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from _lessons import NOTEBOOKS  # noqa: E402

KERNELSPEC = {"name": "python3", "display_name": "Python 3", "language": "python"}


def build(name, cells):
    notebook = new_notebook()
    notebook.metadata["kernelspec"] = dict(KERNELSPEC)
    notebook.metadata["language_info"] = {"name": "python"}
    for index, (kind, source) in enumerate(cells):
        source = source.strip("\n")
        cell = new_markdown_cell(source) if kind == "md" else new_code_cell(source)
        cell["id"] = f"{name[:2]}-{index:02d}"  # stable ids: regenerating gives no diff noise
        notebook.cells.append(cell)
    nbformat.validate(notebook)
    path = HERE / f"{name}.ipynb"
    path.write_text(nbformat.writes(notebook) + "\n", encoding="utf-8")
    return path


def main(argv=None):
    names = set(argv or [])
    for name, cells in NOTEBOOKS.items():
        if names and name not in names:
            continue
        print("wrote", build(name, cells).relative_to(HERE.parent))


if __name__ == "__main__":
    main(sys.argv[1:])
