"""Explorer in a real browser: headless Chromium (Debian's /usr/bin/chromium) driven by Playwright.

The tests load the page, choose in it, click Run and read the page's plots and menus: a compare's contact
filters go when the speed changes, the Line menu for 3d lists only core's window_lines,
bad uploads give a message; screenshots go to ``test-artifacts/``. Software WebGL in headless Chromium is
slow to draw its first frames, hence the generous timeouts.
"""

import time
from pathlib import Path

import pytest

from wheelrail.explorer.tabs import SpectraTab

ARTIFACTS = Path(__file__).resolve().parents[2] / "test-artifacts"


pytestmark = pytest.mark.slow  # every test here takes seconds: `pytest -m 'not slow'` skips them


def _wait_for(condition, timeout: float, what: str) -> None:
    start = time.monotonic()
    deadline = start + timeout
    while time.monotonic() < deadline:
        if condition():
            print(f"{what}: {time.monotonic() - start:.1f} s")
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")


def _two_frames(page) -> None:
    """Let the page draw twice more before a screenshot: driven by its own animation frames, not by a sleep."""
    page.evaluate("() => new Promise(done => requestAnimationFrame(() => requestAnimationFrame(done)))")


def _open(open_page, width, height):
    """A page in the browser and its own session (conftest's ``open_page``), set to hertz, 0.8 m (the page
    changes the model where it needs another)."""
    page, session, errors = open_page(width, height)
    session.form.model_dropdown.value = "hertz"
    session.form.length_text.value = "0.8"
    return page, session, errors


PLOTS_IN_PAGE = """() => Object.values((window.__viserTestpoints || {}).uplots || {}).map(t => ({
    title: String((t.chart.root.querySelector('.u-title') || {}).textContent || ''),
    labels: t.chart.series.slice(1).map(s => String(s.label)),
    n: t.chart.data[0].length}))"""

FRAMES_RENDERED = "() => (window.__viserTestpoints && window.__viserTestpoints.rendererInfo.render.frame) || 0"


def _plot(page, title_start):
    return next((p for p in page.evaluate(PLOTS_IN_PAGE) if p["title"].startswith(title_start)), None)


def _choose(page, label, option):
    page.get_by_label(label, exact=True).click()
    page.get_by_role("option", name=option, exact=True).click()


def _text_field(page, label):
    """viser 1.1's text inputs carry no label element: the input nearest the label's text."""
    return page.get_by_text(label, exact=True).first.locator("xpath=following::input[1]")


def _options(page, label):
    page.get_by_label(label, exact=True).click()
    names = page.get_by_role("option").all_inner_texts()  # one read: the list re-renders meanwhile
    page.keyboard.press("Escape")
    return names


def test_compare_in_the_page_then_change_speed_the_old_filters_go(open_page):
    """In the page: the contact filters of a compare disappear when the speed changes."""
    ARTIFACTS.mkdir(exist_ok=True)
    page, app, errors = _open(open_page, 1400, 1000)
    run_button = page.get_by_role("button", name="Run", exact=True)
    _choose(page, "Contact model", "compare")
    _wait_for(lambda: app.form.model_dropdown.value == "compare", 30, "the page's model to reach the server")
    run_button.click()
    page.get_by_text("Done: compare on corrugated-rail, line 0, 100 km/h", exact=False).wait_for(timeout=300_000)
    assert app.page.last_error is None
    page.get_by_role("tab", name=SpectraTab.title).click()
    _wait_for(
        lambda: "3d - hertz" in (_plot(page, "Contact filters") or {}).get("labels", []),
        60,
        "the contact filters in the page",
    )
    filters = _plot(page, "Contact filters")
    assert filters["title"] == "Contact filters: corrugated-rail, line 0, 100 km/h, 65 kN, 0.8 m; the paper's track"
    assert filters["labels"] == [
        "3d - hertz",
        "2d - hertz",
        "hertz-winkler - hertz",
        "hertz-average - hertz",
        "cnossos",
        "averaging",
        "patch-correlated",
        "patch-incoherent",
    ]
    _two_frames(page)
    page.screenshot(path=str(ARTIFACTS / "explorer-filters.png"))

    speed = _text_field(page, "Speed (km/h)")
    speed.fill("80")
    speed.press("Enter")
    _wait_for(
        lambda: (
            (_plot(page, "Contact filters") or {}).get("title", "").endswith("80 km/h, 65 kN, 0.8 m; the paper's track")
        ),
        60,
        "the contact-filter plot of the new configuration",
    )
    filters = _plot(page, "Contact filters")
    assert filters["labels"] == ["cnossos", "averaging", "patch-correlated", "patch-incoherent"]
    assert _plot(page, "Force spectra")["labels"] == ["no spectrum of this configuration yet"]
    assert not errors, errors
    page.close()


def test_3d_offers_only_the_lines_its_window_fits(open_page):
    """In the page: the Line menu for 3d lists core's window_lines (-2..2 on the corrugated rail)."""
    from wheelrail.core.engine.track_lines import window_lines
    from wheelrail.core.roughness import load_roughness

    page, app, errors = _open(open_page, 1400, 1000)
    _choose(page, "Contact model", "hertz")
    _wait_for(lambda: len(app.form.line_dropdown.options) == 19, 30, "every line for hertz")
    _wait_for(lambda: _options(page, "Line") == [str(n) for n in range(-9, 10)], 30, "every line in the page")
    _choose(page, "Line", "7")
    _choose(page, "Contact model", "3d")
    _wait_for(lambda: app.form.model_dropdown.value == "3d", 30, "3d to reach the server")
    expected = [str(n) for n in window_lines(load_roughness("corrugated-rail"))]
    assert expected == ["-2", "-1", "0", "1", "2"]
    _wait_for(lambda: _options(page, "Line") == expected, 30, "the 3d lines in the page")
    page.get_by_text("Line 7 is not offered for 3d on corrugated-rail; line 2 is chosen").wait_for(timeout=30_000)
    # a 3d run on an offered line runs and draws its heat map in the page
    speed = _text_field(page, "Speed (km/h)")
    speed.fill("100")
    speed.press("Enter")
    page.get_by_role("button", name="Run", exact=True).click()
    page.get_by_text("Done: 3d on corrugated-rail, line 2", exact=False).wait_for(timeout=300_000)
    _wait_for(lambda: page.evaluate(FRAMES_RENDERED) > 2, 90, "WebGL frames")
    _two_frames(page)
    page.screenshot(path=str(ARTIFACTS / "explorer-3d-run.png"))
    assert not errors, errors
    page.close()


def test_bad_uploads_in_the_page(open_page):
    """A malformed CSV and a file over the size limit, uploaded through the page: a message, no harm done."""
    page, app, errors = _open(open_page, 1200, 900)
    before = app.replay.entry
    upload = page.locator("input[type=file]").first  # the Run folder's upload; the Session folder's comes after
    upload.set_input_files(files=[{"name": "broken.csv", "mimeType": "text/csv", "buffer": b"x_m,heights\n0,abc\n"}])
    _wait_for(lambda: (app.page.last_error or "").startswith("upload 'broken.csv'"), 60, "the malformed-CSV message")
    page.get_by_text("Error: upload 'broken.csv'", exact=False).first.wait_for(timeout=60_000)

    limit = app.page.max_upload_bytes
    app.page.max_upload_bytes = 100_000  # keep the test's upload small
    try:
        upload.set_input_files(files=[{"name": "huge.csv", "mimeType": "text/csv", "buffer": b"0" * 150_000}])
        _wait_for(lambda: "huge.csv" in (app.page.last_error or ""), 60, "the over-limit message")
        # refused when announced, before its bytes were buffered
        assert app.page.last_error == "upload 'huge.csv' (146 kB) is over the 98 kB limit; refused before sending"
        page.get_by_text("Error: upload 'huge.csv'", exact=False).first.wait_for(timeout=60_000)
    finally:
        app.page.max_upload_bytes = limit
    page.screenshot(path=str(ARTIFACTS / "explorer-bad-upload.png"))
    assert app.form.roughness_label == "corrugated-rail" and app.replay.entry is before
    # viser's own notice that the bytes arrived is not shown beside the refusal (it is in the page, hidden)
    arrived = page.get_by_text("File uploaded successfully")
    assert all(not arrived.nth(i).is_visible() for i in range(arrived.count()))
    assert not errors, errors
    page.close()


NOTICES = """() => Array.from(document.querySelectorAll('.mantine-Notification-root'))
    .filter(e => getComputedStyle(e).display !== 'none').map(e => e.innerText)"""


def test_the_page_is_titled_and_keeps_one_notice(open_page):
    """The browser tab says what it is; refused presses of Run replace their notice instead of piling up."""
    from wheelrail.explorer.page import NOTICE_SECONDS

    page, app, errors = _open(open_page, 1280, 800)
    run_button = page.get_by_role("button", name="Run", exact=True)
    assert page.title() == "wheelrail explorer"
    speed = _text_field(page, "Speed (km/h)")
    old = app.form.fields["speed"].value
    app.page.notice_seconds = 600.0  # none closes by itself meanwhile: only a replacement takes one away
    try:
        for typo in ("1OO", "abc", "-5"):
            speed.fill(typo)
            speed.press("Enter")
            _wait_for(
                lambda typo=typo: app.form.fields["speed"].value == typo, 30, f"the speed {typo!r} to reach the server"
            )
            run_button.click()
            _wait_for(lambda typo=typo: typo in (app.page.last_error or ""), 30, f"the message about {typo!r}")
        # once the page has shown the last notice and taken the others away (they fade out): one notice
        assert app.page.last_error.startswith("Speed -5 km/h is outside the accepted 5 to 400 km/h")
        last = f"Cannot do that\n{app.page.last_error}"
        page.wait_for_function(
            f"() => JSON.stringify(({NOTICES})().filter(t => t.startsWith('Cannot do that')))"
            f" === JSON.stringify([{last!r}])",
            timeout=30_000,
        )
        app.page.notice_seconds = NOTICE_SECONDS
        run_button.click()  # and a notice closes by itself
        _wait_for(
            lambda: app.page.notices and next(iter(app.page.notices.values())).auto_close_seconds == NOTICE_SECONDS,
            30,
            "a notice that closes by itself",
        )
    finally:
        app.page.notice_seconds = NOTICE_SECONDS
        app.form.fields["speed"].value = old
    assert not errors, errors
    page.close()
