"""Fixtures for the real-browser tests: one JupyterLab server and one Debian chromium per session.

* ``lab_server``: ``jupyter lab`` on 127.0.0.1 in a temporary root (see :mod:`labharness`).
* ``chromium``: Playwright (sync API) driving ``/usr/bin/chromium`` -- browsers are never downloaded. One
  Playwright per session: its sync API cannot start a second instance while one runs, so every test that needs
  a browser (``test_start.py`` included, which starts its own servers) takes this fixture, in any order.
* ``lab``: a fresh browser page per test with helpers to write a notebook, open it, run all cells, and run
  code in its kernel (to read the Python-side state of a widget).
* Screenshots (plus the page console and the server log) of failed tests go to ``test-artifacts/`` at the
  repository root.
"""
from __future__ import annotations

import re
import shutil
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from labharness import CHROMIUM, Lab, launch_chromium, start_lab  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
ARTIFACTS = REPO / "test-artifacts"


def _require_chromium() -> None:
    if not Path(CHROMIUM).exists():
        pytest.skip(f"chromium not found at {CHROMIUM} (bash scripts/system-deps.sh chromium)")
    pytest.importorskip("playwright.sync_api")


@pytest.fixture(scope="session")
def lab_server(tmp_path_factory):
    _require_chromium()
    with start_lab(tmp_path_factory.mktemp("lab")) as server:
        yield server


@pytest.fixture(scope="session")
def chromium():
    _require_chromium()
    with launch_chromium() as browser:
        yield browser


@pytest.hookimpl(tryfirst=True, hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    setattr(item, f"rep_{report.when}", report)


@pytest.fixture
def lab(lab_server, chromium, request):
    context = chromium.new_context(viewport={"width": 1400, "height": 1000}, device_scale_factor=1)
    page = context.new_page()
    console: list[str] = []
    page.on("console", lambda message: console.append(f"{message.type}: {message.text}"))
    page.on("pageerror", lambda error: console.append(f"pageerror: {error}"))
    helper = Lab(lab_server, page)
    helper.console = console
    yield helper
    failed = any(getattr(getattr(request.node, f"rep_{when}", None), "failed", False) for when in ("setup", "call"))
    if failed:
        ARTIFACTS.mkdir(exist_ok=True)
        stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", request.node.nodeid)[-120:]
        try:
            page.screenshot(path=str(ARTIFACTS / f"{stem}.png"), full_page=True)
            (ARTIFACTS / f"{stem}.console.txt").write_text("\n".join(console), encoding="utf-8")
            shutil.copy(lab_server.log, ARTIFACTS / f"{stem}.server.log")
        except Exception:  # noqa: BLE001 - artifacts are best effort; the test already failed
            pass
    context.close()
    lab_server.shutdown_kernels()
