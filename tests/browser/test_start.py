"""The README's start commands, run as a user runs them, then looked at in Debian's chromium.

``bash scripts/start.sh [notebook|app] --no-browser --port N ...`` installs (here: finds the test venv already
installed, see ``scripts/bootstrap.sh``) and serves ``notebooks/`` in JupyterLab, Notebook 7 or Voila. Each test
waits for the server to answer, opens notebook 01, runs it, checks that its SplineEditor renders, and stops the
server as a user would (``/api/shutdown`` for Jupyter, SIGTERM for Voila): the server must exit by itself and
leave no process behind (kernels included). The repository's notebooks must come out unchanged (autosave is
off, checkpoints go to a temporary directory).
"""
from __future__ import annotations

import contextlib
import json
import os
import secrets
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from labharness import (  # noqa: E402
    _ALL_RUN_JS,
    _ERRORS_JS,
    _KERNEL_IDLE_JS,
    _free_port,
    _http_json,
)

pytestmark = [pytest.mark.browser, pytest.mark.slow]

REPO = Path(__file__).resolve().parents[2]
START = REPO / "scripts" / "start.sh"
NOTEBOOKS = REPO / "notebooks"
ARTIFACTS = REPO / "test-artifacts"
NOTEBOOK = "01_generic_cubic.ipynb"
EDITOR = "[data-testid=spline-editor][data-ready='1']"
START_TIMEOUT = 180.0   # seconds: bootstrap finds the venv installed, then the server starts (a loaded machine)
STOP_TIMEOUT = 30.0
PAGE_TIMEOUT = 180_000  # milliseconds: open, start the kernel, run every cell of the notebook


class StartedServer:
    """A server started by ``scripts/start.sh``: its URL, token, process (a session leader) and log."""

    def __init__(self, url: str, token: str, process: subprocess.Popen, log: Path):
        self.url, self.token, self.process, self.log = url, token, process, log

    def api(self, path: str, method: str = "GET"):
        return _http_json(f"{self.url}{path}", self.token, method)

    def page_status(self, path: str = "/") -> int:
        """HTTP status of a page of the server (Voila has no REST API to poll)."""
        with urllib.request.urlopen(f"{self.url}{path}?token={self.token}", timeout=10) as response:
            return response.status

    def log_tail(self) -> str:
        return self.log.read_text(errors="replace")[-4000:]


def isolated_env(base: Path) -> dict:
    """The environment of a user with empty Jupyter directories in ``base``; lab settings for a test run."""
    env = dict(os.environ)
    env.update(
        JUPYTER_CONFIG_DIR=str(base / "config"),
        JUPYTER_DATA_DIR=str(base / "data"),
        JUPYTER_RUNTIME_DIR=str(base / "runtime"),
        JUPYTER_PLATFORM_DIRS="1",
        IPYTHONDIR=str(base / "ipython"),
        PYTHONUNBUFFERED="1",
    )
    settings = base / "config" / "lab" / "user-settings" / "@jupyterlab"
    for plugin, values in {
        "docmanager-extension/plugin": {"autosave": False},
        "apputils-extension/notification": {"checkForUpdates": False, "fetchNews": "false",
                                            "doNotDisturbMode": True},
    }.items():
        path = settings / f"{plugin}.jupyterlab-settings"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(values), encoding="utf-8")
    return env


def session_processes(session_id: int) -> list[int]:
    """Process ids of every live process in the session ``session_id`` (from /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[1].split()
        if int(fields[3]) == session_id and fields[0] != "Z":
            found.append(int(entry.name))
    return found


def _kill_session(session_id: int) -> None:
    for pid in session_processes(session_id):
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)


def stop(server: StartedServer, jupyter: bool) -> list[int]:
    """Stop the server as a user does: ``POST /api/shutdown`` (Jupyter: kernels first, then the server) or
    SIGTERM (Voila shuts its kernels down on it).

    Returns the processes that were still alive afterwards (they are killed); a clean stop returns ``[]``.
    """
    process = server.process
    if process.poll() is None:
        if jupyter:
            with contextlib.suppress(urllib.error.URLError, OSError, ValueError):
                server.api("/api/shutdown", method="POST")
        else:
            process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGTERM)
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
    deadline = time.monotonic() + 10.0
    while session_processes(process.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    left = session_processes(process.pid)
    _kill_session(process.pid)
    return left


@contextlib.contextmanager
def run_start(base: Path, command: list[str], options: list[str], *, jupyter: bool = True):
    """Run ``bash scripts/start.sh COMMAND... OPTIONS...`` on a free port; yield once the server answers
    (``/api/status`` of a Jupyter server, the front page of Voila)."""
    port = _free_port()
    token = secrets.token_hex(16)
    env = isolated_env(base)
    log = base / "start.log"
    argv = ["bash", str(START), *command, "--no-browser", f"--port={port}", *options]
    argv = [arg.replace("{token}", token).replace("{base}", str(base)) for arg in argv]
    with open(log, "wb") as handle:
        process = subprocess.Popen(argv, cwd=base, env=env, stdout=handle, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL, start_new_session=True)
    server = StartedServer(f"http://127.0.0.1:{port}", token, process, log)
    try:
        deadline = time.monotonic() + START_TIMEOUT
        while True:
            if process.poll() is not None:
                raise AssertionError(f"start.sh exited with {process.returncode}:\n{server.log_tail()}")
            try:
                if jupyter:
                    server.api("/api/status")
                else:
                    server.page_status("/")
                break
            except (urllib.error.URLError, OSError, ValueError):
                if time.monotonic() > deadline:
                    raise AssertionError(f"no answer within {START_TIMEOUT} s:\n"
                                         f"{server.log_tail()}") from None
                time.sleep(0.25)
        yield server
    finally:
        left = stop(server, jupyter)
    assert not left, f"processes left after /api/shutdown: {left}\n{server.log_tail()}"
    assert process.returncode == 0, f"the server exited with {process.returncode}:\n{server.log_tail()}"


def notebooks_state() -> dict:
    """Size and modification time of every file under notebooks/ (the test must not change any)."""
    return {str(path.relative_to(NOTEBOOKS)): (path.stat().st_size, path.stat().st_mtime_ns)
            for path in sorted(NOTEBOOKS.rglob("*")) if path.is_file() and "__pycache__" not in path.parts}


try:
    from playwright.sync_api import TimeoutError as PlaywrightTimeout
except ImportError:  # the chromium fixture skips every test then
    PlaywrightTimeout = TimeoutError


@pytest.fixture
def page(chromium, request, tmp_path):
    """A fresh page in the session's browser (conftest.py; these tests start their own servers, not the
    session's JupyterLab); when the test fails, its screenshot, console and the server's log go to
    test-artifacts/ (``rep_call`` is set by the hook in conftest.py)."""
    context = chromium.new_context(viewport={"width": 1400, "height": 1000}, device_scale_factor=1)
    page = context.new_page()
    console: list[str] = []
    page.on("console", lambda message: console.append(f"{message.type}: {message.text}"))
    page.on("pageerror", lambda error: console.append(f"pageerror: {error}"))
    yield page
    if getattr(getattr(request.node, "rep_call", None), "failed", False):
        ARTIFACTS.mkdir(exist_ok=True)
        stem = request.node.name
        with contextlib.suppress(Exception):  # best effort: the test has failed already
            page.screenshot(path=str(ARTIFACTS / f"{stem}.png"), full_page=True)
        (ARTIFACTS / f"{stem}.console.txt").write_text("\n".join(console), encoding="utf-8")
        if (tmp_path / "start.log").exists():
            (ARTIFACTS / f"{stem}.server.log").write_text((tmp_path / "start.log").read_text(errors="replace"))
    context.close()


def run_all_cells(page) -> None:
    """In the open notebook (JupyterLab's or Notebook 7's app object): run every cell; fail on a cell error."""
    page.wait_for_function("() => window.jupyterapp && window.jupyterapp.shell", timeout=PAGE_TIMEOUT)
    page.wait_for_selector(".jp-NotebookPanel .jp-Notebook .jp-Cell", timeout=PAGE_TIMEOUT)
    page.wait_for_function(_KERNEL_IDLE_JS, timeout=PAGE_TIMEOUT)
    page.evaluate("() => window.jupyterapp.commands.execute('notebook:run-all-cells')")
    page.wait_for_function(_ALL_RUN_JS, timeout=PAGE_TIMEOUT)
    errors = page.evaluate(_ERRORS_JS)
    assert not errors, "a cell of notebook 01 failed:\n" + "\n".join(errors)


def assert_editor_rendered(page) -> None:
    """Notebook 01's SplineEditor is drawn: ready, with a curve path."""
    root = page.wait_for_selector(EDITOR, timeout=PAGE_TIMEOUT)
    curve = root.query_selector("[data-testid=curve]")
    assert curve is not None and len(curve.get_attribute("d") or "") > 10


COMMON_OPTIONS = [
    "--IdentityProvider.token={token}", "--ServerApp.ip=127.0.0.1", "--ServerApp.port_retries=0",
    "--FileCheckpoints.checkpoint_dir={base}/checkpoints",
]
LAB_OPTIONS = COMMON_OPTIONS + [
    "--LabApp.expose_app_in_browser=True", "--LabApp.news_url=None",
    "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate", "--LabApp.workspaces_dir={base}/workspaces",
]
NOTEBOOK_OPTIONS = COMMON_OPTIONS + ["--JupyterNotebookApp.expose_app_in_browser=True"]
VOILA_OPTIONS = ["--token={token}", "--Voila.ip=127.0.0.1", "--Voila.port_retries=0"]


def assert_tree_lists(page, url: str, name: str, attempts: int = 3) -> None:
    """Voila's front page lists ``name``. Its list is filled in by the page's script, which now and then (about
    one load in ten on a loaded machine) leaves it empty until the page is reloaded: reload, as a user would."""
    for attempt in range(attempts):
        response = page.goto(url, wait_until="domcontentloaded")
        assert response.ok, f"{url}: HTTP {response.status}"
        try:
            page.wait_for_function("(name) => document.body.innerText.includes(name)", arg=name, timeout=30_000)
            return
        except PlaywrightTimeout:
            if attempt == attempts - 1:
                raise AssertionError(f"Voila's front page never listed {name} ({attempts} loads)") from None


def code_lines(notebook: Path) -> list[str]:
    """The longer lines of the notebook's code cells (long enough not to occur in its prose by chance)."""
    cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
    return [line.strip() for cell in cells if cell["cell_type"] == "code"
            for line in "".join(cell["source"]).splitlines() if len(line.strip()) >= 25]


def assert_root_note(log: str, frontend: str) -> None:
    """As root, start.sh says that it passes --allow-root; the server never refuses to run."""
    if os.geteuid() == 0:
        assert f"Jupyter {frontend} is started with --allow-root" in log
    assert "Running as root is not recommended" not in log


def test_readme_start_command_serves_notebook_01_in_jupyterlab(tmp_path, page):
    before = notebooks_state()
    with run_start(tmp_path, [], LAB_OPTIONS) as server:
        assert server.api("/api/status")["kernels"] == 0
        page.goto(f"{server.url}/lab/tree/{NOTEBOOK}?token={server.token}&reset", wait_until="domcontentloaded")
        run_all_cells(page)
        assert_editor_rendered(page)
        kernels = server.api("/api/kernels")
        assert len(kernels) == 1 and kernels[0]["execution_state"] in {"idle", "busy"}
    assert_root_note(server.log.read_text(errors="replace"), "lab")
    assert notebooks_state() == before


def test_start_notebook_serves_notebook_01_in_notebook_7(tmp_path, page):
    before = notebooks_state()
    with run_start(tmp_path, ["notebook"], NOTEBOOK_OPTIONS) as server:
        page.goto(f"{server.url}/notebooks/{NOTEBOOK}?token={server.token}", wait_until="domcontentloaded")
        run_all_cells(page)
        assert_editor_rendered(page)
        assert page.evaluate("() => window.jupyterapp.name") == "Jupyter Notebook"
        assert len(server.api("/api/kernels")) == 1
    assert_root_note(server.log.read_text(errors="replace"), "notebook")
    assert notebooks_state() == before


def test_start_app_serves_notebook_01_in_voila_with_code_hidden(tmp_path, page):
    before = notebooks_state()
    with run_start(tmp_path, ["app"], VOILA_OPTIONS, jupyter=False) as server:
        assert_tree_lists(page, f"{server.url}/?token={server.token}", NOTEBOOK)
        page.goto(f"{server.url}/voila/render/{NOTEBOOK}?token={server.token}", wait_until="domcontentloaded")
        assert_editor_rendered(page)
        # every cell ran (the closing check cell prints its verdict) and no code is shown
        page.wait_for_function("() => document.body.innerText.includes('all checks passed')",
                               timeout=PAGE_TIMEOUT)
        text = page.evaluate("() => document.body.innerText")
        shown = [line for line in code_lines(NOTEBOOKS / NOTEBOOK) if line in text]
        assert not shown, f"Voila shows code: {shown[:3]}"
        assert page.locator(".jp-CodeMirrorEditor, .cm-editor").count() == 0
        assert "There was an error when executing cell" not in page.content()
    assert notebooks_state() == before
