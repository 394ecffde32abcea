"""Shared set-up of the explorer's tests: a free port, an explorer per test module (``app``), a run pressed and
waited for (``finish_run``), and one headless Chromium for the session's page tests (Debian's /usr/bin/chromium,
driven by Playwright; never a downloaded browser)."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

CHROMIUM = Path("/usr/bin/chromium")
LAUNCH_ARGS = [
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-sandbox",
    "--disable-gpu",
]
SHARED_UPLOAD_BYTES = 1_000_000  # the explorers' upload limit: the tests send a file over it


def _free_port() -> int:
    """A TCP port of 127.0.0.1 free at the moment (viser moves to the next one if it is taken meanwhile)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def free_port() -> int:
    """A free port for a server started in another process (``wheelrail explore --port``)."""
    return _free_port()


@pytest.fixture(scope="module")
def app():
    """An explorer of the test module's own (its tests share it and set the controls they rely on; a session's one
    would not do: a test expects a configuration that another module has run to have no run yet)."""
    from wheelrail.explorer.app import ExplorerApp

    explorer = ExplorerApp(port=_free_port(), max_upload_bytes=SHARED_UPLOAD_BYTES)
    yield explorer
    explorer.close()


@pytest.fixture
def finish_run():
    """``finish_run(app)``: press Run, wait for the run's end, return the result replayed."""

    def run(app, timeout: float = 300.0):
        assert app.start_run(), app.page.last_error
        assert app.controller.wait(timeout), "run did not finish"
        return app.replay.entry.result

    return run


@pytest.fixture(scope="session")
def browser():
    """One headless Chromium for the session's page tests (skipped where Debian's chromium is not installed)."""
    if not CHROMIUM.exists():
        pytest.skip(
            "Debian's chromium is not installed at /usr/bin/chromium (apt-get install chromium); CI installs it"
        )
    from playwright import sync_api  # the test extra installs it

    with sync_api.sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=str(CHROMIUM), args=LAUNCH_ARGS)
        yield chromium
        chromium.close()
