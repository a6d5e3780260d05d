"""JupyterLab + chromium harness shared by the browser tests (``conftest.py``) and ``benchmarks/bench_drag.py``.

* :func:`start_lab` runs ``jupyter lab`` on 127.0.0.1 (free port, random token, ``--no-browser``, a temporary
  root directory, isolated Jupyter config/data/runtime dirs so nothing from the user's home leaks in) and
  waits for ``/api/status``. The venv's ipykernel is first registered as the ``python3`` kernel of the venv
  (``python -m ipykernel install --sys-prefix``), so notebooks run with this interpreter.
* :func:`launch_chromium` starts Debian's ``/usr/bin/chromium`` through Playwright (browsers are never
  downloaded).
* :class:`Lab` drives one page: write a notebook, open it, run all cells, run code in its kernel.
"""
from __future__ import annotations

import contextlib
import json
import os
import secrets
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
import uuid
from pathlib import Path

CHROMIUM = os.environ.get("SPLINECRAFT_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
SERVER_START_TIMEOUT = 90.0


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _http_json(url: str, token: str, method: str = "GET"):
    request = urllib.request.Request(url, method=method, headers={"Authorization": f"token {token}"})
    with urllib.request.urlopen(request, timeout=10) as response:
        body = response.read()
        return json.loads(body) if body else None


class LabServer:
    """A running ``jupyter lab``: its URL, token, root directory and log."""

    def __init__(self, url: str, token: str, root: Path, process: subprocess.Popen, log: Path):
        self.url, self.token, self.root, self.process, self.log = url, token, root, process, log

    def api(self, path: str, method: str = "GET"):
        return _http_json(f"{self.url}{path}", self.token, method)

    def shutdown_kernels(self) -> None:
        with contextlib.suppress(urllib.error.URLError, OSError, ValueError):
            for kernel in self.api("/api/kernels") or []:
                self.api(f"/api/kernels/{kernel['id']}", method="DELETE")


@contextlib.contextmanager
def start_lab(base: Path | None = None, *, nodelay: bool = True):
    """Context manager: a JupyterLab server in ``base`` (a new temporary directory by default).

    ``nodelay`` enables the ``splinecraft.jupyter_nodelay`` server extension (``TCP_NODELAY`` on the
    kernel websockets); ``benchmarks/bench_drag.py`` compares both settings.
    """
    cleanup = None
    if base is None:
        cleanup = tempfile.TemporaryDirectory(prefix="splinecraft-lab-")
        base = Path(cleanup.name)
    root = base / "notebooks"
    root.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ)
    env.update(
        JUPYTER_CONFIG_DIR=str(base / "config"),
        JUPYTER_DATA_DIR=str(base / "data"),
        JUPYTER_RUNTIME_DIR=str(base / "runtime"),
        JUPYTER_PLATFORM_DIRS="1",
        IPYTHONDIR=str(base / "ipython"),
        PYTHONUNBUFFERED="1",
    )
    subprocess.run(
        [sys.executable, "-m", "ipykernel", "install", "--sys-prefix", "--name", "python3",
         "--display-name", "Python 3 (splinecraft)"],
        check=True, env=env, capture_output=True,
    )
    config = base / "config"
    config.mkdir(parents=True, exist_ok=True)
    # Explicit either way: installing splinecraft enables the extension environment-wide (jupyter-config/).
    extensions = {"splinecraft.jupyter_nodelay": bool(nodelay)}
    (config / "jupyter_server_config.json").write_text(json.dumps({"ServerApp": {"jpserver_extensions": extensions}}))
    settings = base / "settings"
    notification = settings / "@jupyterlab" / "apputils-extension"
    notification.mkdir(parents=True, exist_ok=True)
    (notification / "notification.jupyterlab-settings").write_text(
        json.dumps({"checkForUpdates": False, "fetchNews": "false", "doNotDisturbMode": True}))
    port = _free_port()
    token = secrets.token_hex(16)
    log = base / "server.log"
    command = [
        sys.executable, "-m", "jupyterlab", "--no-browser",
        "--ServerApp.ip=127.0.0.1", f"--ServerApp.port={port}", "--ServerApp.port_retries=0",
        f"--IdentityProvider.token={token}", f"--ServerApp.root_dir={root}",
        "--ServerApp.disable_check_xsrf=True", "--LabApp.expose_app_in_browser=True",
        f"--LabApp.user_settings_dir={settings}", f"--LabApp.workspaces_dir={base / 'workspaces'}",
        "--LabApp.news_url=None", "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
        "--LabApp.extension_manager=readonly", "--ServerApp.terminals_enabled=False",
    ]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        command.append("--allow-root")
    with open(log, "wb") as handle:
        process = subprocess.Popen(command, cwd=root, env=env, stdout=handle, stderr=subprocess.STDOUT)
        server = LabServer(f"http://127.0.0.1:{port}", token, root, process, log)
        try:
            deadline = time.monotonic() + SERVER_START_TIMEOUT
            while True:
                if process.poll() is not None:
                    raise RuntimeError(f"jupyter lab exited with {process.returncode}:\n{log.read_text()[-3000:]}")
                try:
                    server.api("/api/status")
                    break
                except (urllib.error.URLError, OSError, ValueError):
                    if time.monotonic() > deadline:
                        raise RuntimeError(f"jupyter lab did not answer within {SERVER_START_TIMEOUT} s:\n"
                                           f"{log.read_text()[-3000:]}") from None
                    time.sleep(0.25)
            yield server
        finally:
            server.shutdown_kernels()
            process.terminate()
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
            if cleanup is not None:
                cleanup.cleanup()


@contextlib.contextmanager
def launch_chromium():
    """Context manager: a Playwright (sync API) chromium browser, Debian's binary."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            yield browser
        finally:
            browser.close()


def notebook_json(cells: list[str]) -> dict:
    """A minimal nbformat-4 notebook whose kernel is this venv's python3."""
    return {
        "cells": [
            {"cell_type": "code", "execution_count": None, "id": uuid.uuid4().hex[:8], "metadata": {},
             "outputs": [], "source": source}
            for source in cells
        ],
        "metadata": {
            "kernelspec": {"display_name": "Python 3 (splinecraft)", "language": "python", "name": "python3"},
            "language_info": {"name": "python"},
        },
        "nbformat": 4,
        "nbformat_minor": 5,
    }


_EXECUTE_JS = """
async (code) => {
  const panel = window.jupyterapp.shell.currentWidget;
  const kernel = panel.sessionContext.session.kernel;
  const future = kernel.requestExecute({ code, store_history: false, silent: false });
  let out = "";
  future.onIOPub = (msg) => {
    const type = msg.header.msg_type;
    if (type === "stream") out += msg.content.text;
    else if (type === "error") out += `\\n${msg.content.ename}: ${msg.content.evalue}\\n`;
  };
  await future.done;
  return out;
}
"""

_KERNEL_IDLE_JS = """() => {
  const w = window.jupyterapp.shell.currentWidget;
  const k = w && w.sessionContext && w.sessionContext.session && w.sessionContext.session.kernel;
  return k && k.connectionStatus === 'connected' && k.status === 'idle';
}"""

_ALL_RUN_JS = """() => {
  const w = window.jupyterapp.shell.currentWidget;
  const k = w.sessionContext.session.kernel;
  return k.status === 'idle' && w.content.widgets.every(c => c.model.type !== 'code' || c.model.executionCount);
}"""

_ERRORS_JS = """() => window.jupyterapp.shell.currentWidget.content.widgets
  .filter(c => c.model.type === 'code')
  .flatMap(c => c.model.outputs.toJSON())
  .filter(o => o.output_type === 'error')
  .map(o => `${o.ename}: ${o.evalue}`)"""


class Lab:
    """One browser page on a JupyterLab server."""

    def __init__(self, server: LabServer, page):
        self.server = server
        self.page = page

    def open_notebook(self, cells: list[str], name: str | None = None, *, timeout: float = 90_000):
        """Write a fresh notebook into the server root, open it, run all cells; fail on any cell error."""
        name = name or f"test_{uuid.uuid4().hex[:10]}.ipynb"
        (self.server.root / name).write_text(json.dumps(notebook_json(cells)), encoding="utf-8")
        page = self.page
        page.goto(f"{self.server.url}/lab/tree/{name}?token={self.server.token}&reset", wait_until="domcontentloaded")
        page.wait_for_function("() => window.jupyterapp && window.jupyterapp.shell", timeout=timeout)
        page.wait_for_selector(".jp-NotebookPanel .jp-Notebook .jp-Cell", timeout=timeout)
        page.wait_for_function(_KERNEL_IDLE_JS, timeout=timeout)
        page.evaluate("() => window.jupyterapp.shell.collapseLeft()")
        page.evaluate("() => window.jupyterapp.commands.execute('notebook:run-all-cells')")
        page.wait_for_function(_ALL_RUN_JS, timeout=timeout)
        errors = page.evaluate(_ERRORS_JS)
        if errors:
            raise AssertionError("a notebook cell failed:\n" + "\n".join(errors))
        return page

    def execute(self, code: str) -> str:
        """Run ``code`` in the notebook's kernel (not as a cell) and return its stdout (+ errors)."""
        out = self.page.evaluate(_EXECUTE_JS, code)
        if "Error:" in out or "Traceback" in out:
            raise AssertionError(out)
        return out

    def python_json(self, expression: str):
        """Evaluate ``expression`` in the kernel and return it decoded from JSON."""
        out = self.execute(f"import json as _json\nprint(_json.dumps({expression}))")
        return json.loads(out.strip().splitlines()[-1])
