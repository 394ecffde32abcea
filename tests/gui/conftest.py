"""Shared set-up of the explorer's tests: a free port, an explorer per test module (``explorer``) and the session
of a tab of it opened without a browser (``app``: a :class:`~wheelrail.explorer.headless.HeadlessTab`), a run
pressed and waited for (``finish_run``), one headless Chromium for the session's page tests (Debian's
/usr/bin/chromium, driven by Playwright; never a downloaded browser) and a page of it with its session
(``open_page``)."""

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


def new_session(explorer, open_tab, timeout: float = 120.0):
    """``open_tab()`` (a page or a HeadlessTab connecting), then the session the explorer built for it."""
    known = set(explorer.sessions)
    tab = open_tab()
    assert explorer.wait_for(lambda: set(explorer.sessions) - known, timeout), "no session for the new tab"
    return tab, explorer.sessions[max(set(explorer.sessions) - known)]


@pytest.fixture(scope="module")
def explorer():
    """An explorer of the test module's own (a session's one would not do: a test expects a configuration that
    another module has run to have no run yet)."""
    from wheelrail.explorer.app import ExplorerApp

    app = ExplorerApp(port=_free_port(), max_upload_bytes=SHARED_UPLOAD_BYTES)
    yield app
    app.close()


@pytest.fixture(scope="module")
def app(explorer):
    """The session of one tab of the module's explorer, opened without a browser (its tests share it and set the
    controls they rely on)."""
    from wheelrail.explorer.headless import HeadlessTab

    tab, session = new_session(explorer, lambda: HeadlessTab(explorer.port))
    yield session
    tab.close()


@pytest.fixture
def open_page(browser, explorer):
    """``open_page(width, height)``: a page of the module's explorer in the browser, once its Run button is there,
    its session, and the list its script errors go to; closed after the test."""
    pages = []

    def open_(width: int = 1280, height: int = 800):
        errors = []
        page = browser.new_page(viewport={"width": width, "height": height})
        pages.append(page)
        page.on("pageerror", lambda error: errors.append(str(error)))

        def load():
            page.goto(f"http://127.0.0.1:{explorer.port}")
            return page

        _, session = new_session(explorer, load)
        page.get_by_role("button", name="Run", exact=True).wait_for(timeout=90_000)
        return page, session, errors

    yield open_
    for page in pages:
        if not page.is_closed():
            page.close()


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
