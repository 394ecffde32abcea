"""Explorer in a real browser: headless Chromium (Debian's /usr/bin/chromium) driven by Playwright.

The test loads the page, changes the model and the speed in the page, clicks Run, waits for the run to
finish (polling the app's state), then checks in the page that the force plot and the 3D contact patch
hold the run's data, and saves screenshots to ``test-artifacts/``. Software WebGL in headless Chromium is
slow to draw its first frames, hence the generous timeouts.
"""

import socket
import time
from pathlib import Path

import numpy as np
import pytest

CHROMIUM = Path("/usr/bin/chromium")
ARTIFACTS = Path(__file__).resolve().parents[2] / "test-artifacts"
LAUNCH_ARGS = ["--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-sandbox",
               "--disable-gpu"]

if not CHROMIUM.exists():
    pytest.skip("Debian's chromium is not installed at /usr/bin/chromium (apt-get install chromium); "
                "CI installs it", allow_module_level=True)
from playwright import sync_api as playwright_api  # noqa: E402  (the test extra installs it)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_for(condition, timeout: float, what: str) -> None:
    start = time.monotonic()
    deadline = start + timeout
    while time.monotonic() < deadline:
        if condition():
            print(f"{what}: {time.monotonic() - start:.1f} s")
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")


@pytest.fixture(scope="module")
def app():
    from wheelrail.explorer.app import ExplorerApp

    explorer = ExplorerApp(port=_free_port())
    explorer.model_dropdown.value = "hertz"  # the page changes it to 3d
    explorer.length_number.value = 1.0
    yield explorer
    explorer.close()


@pytest.fixture(scope="module")
def browser():
    with playwright_api.sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=str(CHROMIUM), args=LAUNCH_ARGS)
        yield chromium
        chromium.close()


PATCH_IN_PAGE = """() => {
    const node = window.__viserSceneTree.getState()['/contact/patch'];
    return node ? {vertices: Array.from(node.message.props.vertices), visible: node.visibility} : null;
}"""

FORCE_PLOT_IN_PAGE = """() => {
    const plots = Object.values((window.__viserTestpoints || {}).uplots || {});
    const force = plots.find(t => t.chart.series.some(s => String(s.label).endsWith('force (kN)')));
    return force ? {label: force.chart.series[1].label, x: Array.from(force.chart.data[0]),
                    y: Array.from(force.chart.data[1])} : null;
}"""

FRAMES_RENDERED = "() => (window.__viserTestpoints && window.__viserTestpoints.rendererInfo.render.frame) || 0"


def test_run_from_the_page(app, browser):
    ARTIFACTS.mkdir(exist_ok=True)
    errors = []
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(f"http://127.0.0.1:{app.port}")
    run_button = page.get_by_role("button", name="Run", exact=True)
    run_button.wait_for(timeout=90_000)

    # change the model and the speed in the page
    page.get_by_label("Contact model").click()
    page.get_by_role("option", name="3d", exact=True).click()
    speed = page.get_by_label("Speed (km/h)")
    speed.fill("80")
    speed.press("Enter")
    _wait_for(lambda: app.model_dropdown.value == "3d" and app.speed_number.value == 80.0, 30,
              "the page's model and speed to reach the server")

    finished = app.runs_finished
    run_button.click()
    _wait_for(lambda: app.runs_finished > finished and not app.running, 120, "the run to finish")
    assert app.last_error is None
    result = app.last_result
    assert result.model == "3d" and result.speed == pytest.approx(80 / 3.6) and result.n_steps == 1000
    assert app.frames_drawn > 0

    # the force plot in the page holds this run
    _wait_for(lambda: (page.evaluate(FORCE_PLOT_IN_PAGE) or {}).get("label") == "3d force (kN)" and
              len(page.evaluate(FORCE_PLOT_IN_PAGE)["x"]) == result.n_steps, 60, "the force plot to update")
    plot = page.evaluate(FORCE_PLOT_IN_PAGE)
    assert np.allclose(plot["x"], result.x) and np.allclose(plot["y"], result.force / 1e3)

    # the 3D patch in the page is the last step's pressure (raised 3 mm per GPa, 1 unit = 10 mm)
    patch = page.evaluate(PATCH_IN_PAGE)
    assert patch is not None and patch["visible"]
    vertices = np.array(patch["vertices"]).reshape(-1, 3)
    ny, nx = result.pressure.shape[1:]
    assert vertices.shape == (ny * nx, 3)
    assert np.allclose(vertices[:, 2] / 0.1, result.pressure[-1].reshape(-1) / 1e9 * 3.0, atol=1e-3)
    assert vertices[:, 2].max() > 0.1  # a raised patch: about 1 GPa at the centre

    # WebGL has drawn frames; then a screenshot for a person to look at
    _wait_for(lambda: page.evaluate(FRAMES_RENDERED) > 2, 90, "WebGL frames")
    time.sleep(2.0)
    page.screenshot(path=str(ARTIFACTS / "explorer-3d-run.png"))

    # a second tab sees the same state (the finished run's status) without errors
    second = browser.new_page(viewport={"width": 1400, "height": 1000})
    second.on("pageerror", lambda error: errors.append(str(error)))
    second.goto(f"http://127.0.0.1:{app.port}")
    second.get_by_text("Done: 3d on line 0, 80 km/h").wait_for(timeout=90_000)
    # scrolling the control panel shows the plots
    second.evaluate("() => document.querySelector('.u-title').scrollIntoView()")
    time.sleep(2.0)
    second.screenshot(path=str(ARTIFACTS / "explorer-plots.png"))
    second.close()
    page.close()
    assert not errors, errors


def test_bad_uploads_in_the_page(app, browser):
    """A malformed CSV and a file over the size limit, uploaded through the page: a message, no harm done."""
    errors = []
    page = browser.new_page(viewport={"width": 1200, "height": 900})
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(f"http://127.0.0.1:{app.port}")
    page.get_by_role("button", name="Run", exact=True).wait_for(timeout=90_000)
    before = app.last_result
    upload = page.locator("input[type=file]")
    upload.set_input_files(files=[{"name": "broken.csv", "mimeType": "text/csv", "buffer": b"x_m,heights\n0,abc\n"}])
    _wait_for(lambda: (app.last_error or "").startswith("upload 'broken.csv'"), 60, "the malformed-CSV message")
    page.get_by_text("Error: upload 'broken.csv'", exact=False).first.wait_for(timeout=60_000)

    limit = app.max_upload_bytes
    app.max_upload_bytes = 100_000  # keep the test's upload small
    try:
        upload.set_input_files(files=[{"name": "huge.csv", "mimeType": "text/csv", "buffer": b"0" * 150_000}])
        _wait_for(lambda: "huge.csv" in (app.last_error or ""), 60, "the over-limit message")
        # refused when announced, before its bytes were buffered
        assert app.last_error == "upload 'huge.csv' (146 kB) is over the 98 kB limit; refused before sending"
        page.get_by_text("Error: upload 'huge.csv'", exact=False).first.wait_for(timeout=60_000)
    finally:
        app.max_upload_bytes = limit
    page.screenshot(path=str(ARTIFACTS / "explorer-bad-upload.png"))
    assert app.roughness_label == "corrugated-rail" and app.last_result is before
    assert not errors, errors
    page.close()
