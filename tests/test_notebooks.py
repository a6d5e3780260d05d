"""The classroom notebooks in notebooks/ (marker: notebook).

Each notebook has one source, ``notebooks/NN_name.py`` in jupytext's percent format, paired with
``NN_name.ipynb`` (what JupyterLab opens; stored without outputs). A new notebook is picked up by its
file name alone. The tests check that

* the notebooks are numbered 01, 02, ... without gaps, and every .py has its .ipynb and vice versa;
* each .ipynb holds exactly the cells of its .py (``jupytext --sync notebooks/NN_name.py`` rewrites it);
* each opens with prose ("What you should see" and at least two sentences), then a short first code cell
  (under 15 lines) that imports ``splinecraft as sc``, and ends with a check cell;
* each runs top to bottom on a fresh kernel without an error, displays a widget, and its check cell prints
  "all checks passed".

The kernel is this interpreter's own ipykernel (a temporary "python3" kernelspec put first on JUPYTER_PATH),
so the notebooks run against the installed package of this venv whatever other kernels the machine has.
"""
import json
import os
import sys
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
jupytext = pytest.importorskip("jupytext")
pytest.importorskip("ipykernel")

pytestmark = pytest.mark.notebook

NOTEBOOK_DIR = Path(__file__).resolve().parent.parent / "notebooks"
SOURCES = sorted(NOTEBOOK_DIR.glob("[0-9][0-9]_*.py"))
KERNELSPEC = {"name": "python3", "display_name": "Python 3", "language": "python"}
CELL_TIMEOUT = 240  # seconds per cell; every notebook finishes well inside a minute on 2 cores
FIRST_CODE_CELL_LINES = 15
SYNC_COMMAND = ".venv/bin/jupytext --sync notebooks/{name}.py"


def _ids(paths):
    return [path.stem for path in paths]


@pytest.fixture(scope="session")
def venv_kernel(tmp_path_factory):
    """A 'python3' kernelspec that launches ipykernel with this very interpreter, first on JUPYTER_PATH."""
    root = tmp_path_factory.mktemp("jupyter")
    spec_dir = root / "kernels" / "python3"
    spec_dir.mkdir(parents=True)
    spec = {"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
            "display_name": "Python 3", "language": "python", "metadata": {"debugger": False}}
    (spec_dir / "kernel.json").write_text(json.dumps(spec), encoding="utf-8")
    saved = os.environ.get("JUPYTER_PATH")
    os.environ["JUPYTER_PATH"] = os.pathsep.join([str(root)] + ([saved] if saved else []))
    yield "python3"
    if saved is None:
        os.environ.pop("JUPYTER_PATH", None)
    else:
        os.environ["JUPYTER_PATH"] = saved


def _cells(notebook):
    return [(cell.cell_type, cell.source.strip()) for cell in notebook.cells]


def test_notebooks_are_numbered_and_paired():
    numbers = sorted(int(path.name[:2]) for path in SOURCES)
    assert numbers[:7] == list(range(1, 8)), numbers          # the seven chapters of the thesis, at least
    assert numbers == list(range(1, len(numbers) + 1)), f"gaps or repeats in the numbering: {numbers}"
    paired = {path.with_suffix(".ipynb").name for path in SOURCES}
    stored = {path.name for path in NOTEBOOK_DIR.glob("[0-9][0-9]_*.ipynb")}
    assert stored - paired == set(), f"notebooks without a .py source: {sorted(stored - paired)}"
    missing = sorted(paired - stored)
    assert not missing, "create the .ipynb of each source: " + "; ".join(
        SYNC_COMMAND.format(name=Path(name).stem) for name in missing)


@pytest.mark.parametrize("source", SOURCES, ids=_ids(SOURCES))
def test_ipynb_is_in_sync_with_its_source(source):
    """The .ipynb holds exactly the cells and kernelspec of its jupytext source, and says they are paired."""
    stored = source.with_suffix(".ipynb")
    if not stored.exists():
        pytest.fail(f"{stored.name} is missing: {SYNC_COMMAND.format(name=source.stem)}")
    text = jupytext.read(source)
    notebook = nbformat.read(stored, as_version=4)
    assert _cells(notebook) == _cells(text), f"{stored.name} differs from {source.name}: " \
                                             f"{SYNC_COMMAND.format(name=source.stem)}"
    assert text.metadata.get("kernelspec") == KERNELSPEC
    assert notebook.metadata.get("kernelspec") == KERNELSPEC
    assert notebook.metadata.get("jupytext", {}).get("formats") == "ipynb,py:percent"


@pytest.mark.parametrize("source", SOURCES, ids=_ids(SOURCES))
def test_notebook_is_committed_clean(source):
    """Stored without outputs, opening with what a student should see, a short setup, a final check."""
    stored = source.with_suffix(".ipynb")
    if not stored.exists():
        pytest.fail(f"{stored.name} is missing: {SYNC_COMMAND.format(name=source.stem)}")
    notebook = nbformat.read(stored, as_version=4)
    nbformat.validate(notebook)
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    assert code and all(not cell.outputs and cell.execution_count is None for cell in code)
    first = notebook.cells[0]
    assert first.cell_type == "markdown" and "What you should see" in first.source
    intro = first.source.split("What you should see", 1)[1]            # at least two sentences of intent
    assert intro.count(". ") + intro.count(".\n") + intro.rstrip().endswith(".") >= 2
    setup = code[0].source.strip().splitlines()
    assert "import splinecraft as sc" in setup, "the first code cell imports splinecraft as sc"
    assert len(setup) < FIRST_CODE_CELL_LINES, f"the first code cell has {len(setup)} lines"
    assert "all checks passed" in code[-1].source                       # a final check cell
    assert "assert " in code[-1].source


@pytest.mark.parametrize("source", SOURCES, ids=_ids(SOURCES))
def test_notebook_executes(source, venv_kernel):
    notebook = jupytext.read(source)
    client = nbclient.NotebookClient(
        notebook, timeout=CELL_TIMEOUT, kernel_name=venv_kernel, allow_errors=False,
        resources={"metadata": {"path": str(NOTEBOOK_DIR)}},
    )
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as error:
        pytest.fail(f"{source.name} failed:\n{str(error)[-4000:]}")
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    errors = [out for cell in code for out in cell.outputs if out.output_type == "error"]
    assert not errors
    widget_views = [out for cell in code for out in cell.outputs
                    if out.output_type in ("display_data", "execute_result")
                    and "application/vnd.jupyter.widget-view+json" in out.get("data", {})]
    assert widget_views, "no widget was displayed"
    final_text = "".join(out.get("text", "") for out in code[-1].outputs if out.output_type == "stream")
    assert "all checks passed" in final_text
