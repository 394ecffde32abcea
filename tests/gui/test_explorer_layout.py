"""Explorer in a real browser: after the default Run, what a user came to see is on screen without scrolling.

Headless Chromium (Debian's /usr/bin/chromium, driven by Playwright) at 1280 x 800 and 1920 x 1080: on every
results tab the first plot lies at least 90 % inside the window and is at least 480 px wide (the Wheel tab, which
draws nothing before it is asked to: its Compute the wheel button is on screen), and on the Patch tab the pressure
colour bar is on screen; plot titles wrap inside their plot. Screenshots of every tab at
both sizes go to ``test-artifacts/``. Every wait is for a condition in the page, never a fixed time.
"""

from pathlib import Path

import pytest

from wheelrail.explorer.tabs import RESULT_TABS, HelpTab, NoiseTab, PatchTab, WheelTab

pytestmark = pytest.mark.slow  # every test here takes seconds: `pytest -m 'not slow'` skips them

ARTIFACTS = Path(__file__).resolve().parents[2] / "test-artifacts"
SIZES = ((1280, 800), (1920, 1080))
MIN_INSIDE = 0.9  # share of the first plot's area inside the window
MIN_WIDTH = 480  # px
TABS = tuple(tab.title for tab in RESULT_TABS)  # the page's tabs, in order
# the Wheel tab draws nothing until Compute the wheel is pressed: its button is what must be on screen
PLOT_TABS = tuple(tab.title for tab in RESULT_TABS if tab not in (HelpTab, WheelTab))
COLOUR_BAR = "contact pressure (MPa)"  # the colour bar's label in the Patch tab

# every uPlot chart of the page with its box on screen (zero size: in a tab not shown)
PLOT_BOXES = """() => Object.values((window.__viserTestpoints || {}).uplots || {}).map(t => {
    const r = t.chart.root.getBoundingClientRect();
    const title = t.chart.root.querySelector('.u-title');
    return {title: String((title || {}).textContent || ''), x: r.x, y: r.y, width: r.width, height: r.height,
            title_fits: !title || title.scrollWidth <= title.clientWidth + 1};
}).filter(b => b.width > 0 && b.height > 0)"""


FRAMES_RENDERED = "(window.__viserTestpoints && window.__viserTestpoints.rendererInfo.render.frame) || 0"


def inside_share(box, width, height) -> float:
    """Share of ``box``'s area inside the window (0, 0)-(width, height)."""
    w = max(0.0, min(box["x"] + box["width"], width) - max(box["x"], 0.0))
    h = max(0.0, min(box["y"] + box["height"], height) - max(box["y"], 0.0))
    return w * h / (box["width"] * box["height"])


def _first_plot(page):
    boxes = page.evaluate(PLOT_BOXES)
    return min(boxes, key=lambda b: (round(b["y"]), b["x"])) if boxes else None


def test_after_the_default_run_every_tab_shows_its_first_plot(open_page):
    ARTIFACTS.mkdir(exist_ok=True)
    page, app, errors = open_page(*SIZES[0])
    page.get_by_role("button", name="Run", exact=True).click()
    page.get_by_text("Done: 3d on corrugated-rail, line 0, 100 km/h, 65 kN, 3 m", exact=False).wait_for(timeout=300_000)
    assert app.page.last_error is None
    problems = []
    for width, height in SIZES:  # the same page (its session holds the run) at each window size
        page.set_viewport_size({"width": width, "height": height})
        page.wait_for_function(f"({FRAMES_RENDERED}) > 2", timeout=90_000)  # the 3D view has been drawn
        for close in page.locator(".mantine-Notification-closeButton").all():  # viser's software-WebGL notice
            close.click()
        for title in TABS:
            page.get_by_role("tab", name=title).click()
            if title in PLOT_TABS:
                page.wait_for_function(f"() => ({PLOT_BOXES})().length > 0", timeout=60_000)
                first = _first_plot(page)
                share = inside_share(first, width, height)
                if share < MIN_INSIDE or first["width"] < MIN_WIDTH or not first["title_fits"]:
                    problems.append(
                        f"{width}x{height} {title}: '{first['title'][:40]}' {share:.0%} inside, "
                        f"{first['width']:.0f} px wide, title {'' if first['title_fits'] else 'not '}"
                        "wrapped"
                    )
            if title == WheelTab.title:
                button = page.get_by_role("button", name="Compute the wheel", exact=True).bounding_box()
                if button is None or inside_share(button, width, height) < 0.99:
                    problems.append(f"{width}x{height}: the Compute the wheel button is not on screen ({button})")
            if title == PatchTab.title:
                bar = page.get_by_text(COLOUR_BAR, exact=True).locator("xpath=following::img[1]").bounding_box()
                if bar is None or inside_share(bar, width, height) < 0.99:
                    problems.append(f"{width}x{height}: the colour bar is not on screen ({bar})")
            page.screenshot(path=str(ARTIFACTS / f"explorer-{title.split()[0].lower()}-{width}x{height}.png"))
        assert not errors, errors
    assert not problems, problems


def test_long_plot_titles_wrap_inside_their_plot(open_page):
    """A configuration with a contact geometry has titles longer than a plot is wide: they wrap."""
    page, app, errors = open_page(*SIZES[0])
    try:
        (
            app.form.fields["wheel_radius"].value,
            app.form.fields["rail_crown_radius"].value,
            app.form.fields["wheel_transverse_radius"].value,
        ) = "460", "300", "-1000"
        page.wait_for_function(
            f"() => ({PLOT_BOXES})().some(b => b.title.includes('tread radius across -1000'))", timeout=60_000
        )
        first = _first_plot(page)
        assert "tread radius across -1000 mm" in first["title"] and first["title_fits"]
        assert first["width"] >= MIN_WIDTH
        assert not errors, errors
    finally:
        app.form.fields["wheel_radius"].value = app.form.fields["rail_crown_radius"].value = app.form.fields[
            "wheel_transverse_radius"
        ].value = ""
        page.close()


def test_the_pass_by_plays_in_the_page(open_page):
    """After a run, the Noise tab's Pass-by audio puts a player in the page whose WAV the browser decodes (its
    duration is the pass-by's: T_p of the 40-axle, 200 m train and 1 s either side), and offers the download."""
    page, app, errors = open_page(*SIZES[0])
    try:
        app.form.model_dropdown.value = "hertz"  # a short run of the page's own session first
        app.form.length_text.value = "1"
        page.get_by_role("button", name="Run", exact=True).click()
        page.get_by_text("Done: hertz on corrugated-rail", exact=False).wait_for(timeout=300_000)
        page.wait_for_function(f"({FRAMES_RENDERED}) > 2", timeout=90_000)  # the 3D view has been drawn
        for close in page.locator(".mantine-Notification-closeButton").all():  # viser's software-WebGL notice
            close.click()
        page.get_by_role("tab", name=NoiseTab.title).click()
        page.get_by_role("button", name="Pass-by audio").click()
        page.wait_for_function(
            "() => { const a = document.querySelector('audio'); return a && isFinite(a.duration) && a.duration > 0 }",
            timeout=60_000,
        )
        duration = page.evaluate("document.querySelector('audio').duration")
        assert duration == pytest.approx(200.0 / (100 / 3.6) + 2.0, abs=0.01)
        assert page.get_by_role("button", name="Download pass-by (.wav)").is_enabled()
        page.screenshot(path=str(ARTIFACTS / "explorer-noise-audio-1280x800.png"))
        assert not errors, errors
    finally:
        page.close()
