"""Execute every classroom notebook in notebooks/ on a fresh kernel (marker: notebook).

Each notebook ends with a "Check" cell that asserts what the lesson claims and prints
"all checks passed"; a notebook passes when every cell runs without an error output and that line is
printed. The kernel is this interpreter's own ipykernel (a temporary "python3" kernelspec put first on
JUPYTER_PATH), so the notebooks run against the installed package of this venv whatever other kernels
the machine has.
"""
import json
import os
import sys
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

pytestmark = pytest.mark.notebook

NOTEBOOK_DIR = Path(__file__).resolve().parent.parent / "notebooks"
NOTEBOOKS = sorted(NOTEBOOK_DIR.glob("[0-9][0-9]_*.ipynb"))
KERNELSPEC = {"name": "python3", "display_name": "Python 3", "language": "python"}
CELL_TIMEOUT = 240  # seconds per cell; every notebook finishes well inside a minute on 2 cores


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


def test_there_are_seven_notebooks():
    names = [path.stem for path in NOTEBOOKS]
    prefixes = sorted(name[:2] for name in names)
    assert prefixes == ["01", "02", "03", "04", "05", "06", "07"], names


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_is_committed_clean(path):
    """Stored without outputs, with the python3 kernelspec, opening with what a student should see."""
    notebook = nbformat.read(path, as_version=4)
    nbformat.validate(notebook)
    assert notebook.metadata.get("kernelspec") == KERNELSPEC
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    assert code and all(not cell.outputs and cell.execution_count is None for cell in code)
    first = notebook.cells[0]
    assert first.cell_type == "markdown" and "What you should see" in first.source
    # at least two sentences of intent after the marker
    intro = first.source.split("What you should see", 1)[1]
    assert intro.count(". ") + intro.count(".\n") + intro.rstrip().endswith(".") >= 2
    source = "\n".join(cell.source for cell in code)
    assert "SplineEditor(" in source or "TraceExplorer(" in source      # a widget
    assert "Plot(" in source or "bq." in source                          # and static bqplot figures
    assert "all checks passed" in code[-1].source                         # a final check cell


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_executes(path, venv_kernel):
    notebook = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        notebook, timeout=CELL_TIMEOUT, kernel_name=venv_kernel, allow_errors=False,
        resources={"metadata": {"path": str(NOTEBOOK_DIR)}},
    )
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as error:
        pytest.fail(f"{path.name} failed:\n{str(error)[-4000:]}")
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    errors = [out for cell in code for out in cell.outputs if out.output_type == "error"]
    assert not errors
    widget_views = [out for cell in code for out in cell.outputs
                    if out.output_type == "display_data" and "application/vnd.jupyter.widget-view+json" in out.data]
    assert widget_views, "no widget was displayed"
    final_text = "".join(out.get("text", "") for out in code[-1].outputs if out.output_type == "stream")
    assert "all checks passed" in final_text
