"""The explorer's Irregularity folder (explorer/irregularity.py): its fields reach ``RunParameters.irregularities``
as the command line's options do, bad geometry is one line in the page's words, and a run over a flat shows its
peak and impacts."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from wheelrail.core.engine.impacts import impact_summary
from wheelrail.core.errors import WheelrailError
from wheelrail.core.irregularities import RailJoint, WheelFlat
from wheelrail.core.roughness import load_roughness
from wheelrail.explorer.config import page_message, read_config
from wheelrail.explorer.irregularity import read_irregularities
from wheelrail.explorer.patch_tab import PatchTab, impact_markers

RAIL = load_roughness("corrugated-rail")
FIELDS = {"line": "0", "model": "hertz", "speed_kmh": "100", "preload_kn": "65", "length_m": "1"}


def _config(typed: dict, shape: str = "rounded", irregularity_input: str | None = None):
    irregular = read_irregularities(typed, shape, irregularity_input)
    return read_config(RAIL, "corrugated-rail", **FIELDS, irregular=irregular)


def test_the_fields_reach_the_runs_irregularities():
    config = _config({"flat_length": "50", "flat_position": "0.5"}, irregularity_input="raw")
    run = config.params().run
    assert run.irregularities == (WheelFlat(length=0.05, position=0.5),)
    assert run.irregularity_input == "raw"
    assert "flat 50 mm rounded at x = 0.5 m (Hertz on the raw)" in config.case_label()
    assert config.case() != _config({}).case()  # a flat run never shares a smooth run's results


def test_several_kinds_and_a_new_flat():
    config = _config(
        {"flat_length": "40", "flat_position": "0.3", "joint_position": "0.7", "joint_step": "-0.5"}, shape="new"
    )
    flat, joint = config.params().run.irregularities
    assert flat.shape == "new" and flat.length == pytest.approx(0.04)
    assert joint == RailJoint(position=0.7, step=-0.5e-3)


def test_empty_fields_are_a_run_without_irregularities():
    config = _config({key: "" for key in ("flat_length", "flat_depth", "weld_position")})
    assert config.params().run.irregularities == ()
    assert config.case() == read_config(RAIL, "corrugated-rail", **FIELDS).case()


@pytest.mark.parametrize(
    ("typed", "start"),
    [
        ({"flat_length": "abc", "flat_position": "0.5"}, "Flat length 'abc': not a number"),
        ({"flat_length": "50"}, "Flat length 50 mm: a flat needs its position as well"),
        (
            {"flat_length": "50", "flat_position": "3"},
            "Flat position 3 m: reaches from 2.975 to 3.025 m, outside the run",
        ),
        (
            {"flat_length": "5000", "flat_position": "0.5"},
            "Flat length 5000 mm: a flat this long does not fit on the wheel",
        ),
        ({"flat_length": "50", "flat_depth": "-1", "flat_position": "0.5"}, "Flat depth -1 mm: must be positive"),
        ({"joint_position": "0.5", "joint_gap": "700"}, "Joint gap 700 mm"),
    ],
)
def test_bad_geometry_is_one_line_in_the_pages_words(typed, start):
    with pytest.raises(WheelrailError) as info:
        _config(typed)
    message = page_message(info.value)
    assert message.startswith(start), message
    assert "\n" not in message and "--" not in message and "WheelFlat" not in message and "Error" not in message


def test_the_form_hands_the_folder_to_the_run(app):
    """The headless tab's form: the folder's fields typed, the configuration the Run button would start."""
    form = app.form
    folder = form.irregularity
    try:
        folder.fields["flat_length"].value = "50"
        folder.fields["flat_position"].value = "0.4"
        folder.input.value = "raw"
        form.model_dropdown.value = "hertz"
        form.length_text.value = "1"
        config = form.read_config()
        assert config.params().run.irregularities == (WheelFlat(length=0.05, position=0.4),)
        assert config.params().run.irregularity_input == "raw"
        folder.fields["flat_position"].value = "9"
        form.refresh()
        assert form.check_md.content.startswith("**Cannot run:** Flat position 9 m"), form.check_md.content
    finally:
        for handle in folder.fields.values():
            handle.value = ""
        folder.input.value = "trajectory"


def test_an_empty_contact_set_draws_an_empty_patch(app):
    """The wheel in the air: a 3d step with no pressure anywhere and a one-line step with F = 0 draw without
    errors (an all-background heat map; a strip and ellipse of no size)."""
    config = _config({"flat_length": "50", "flat_position": "0.4"}).for_model("3d")
    window = np.linspace(-5e-3, 5e-3, 11)
    view = SimpleNamespace(config=config, window_x=window, window_y=window, roughness=RAIL, wheel_roughness=None)
    drawn = app.scene.frames_drawn
    app.scene.draw(SimpleNamespace(pressure=np.zeros((11, 11)), force=0.0, contact_length=0.0, position=0.4), view)
    assert app.scene.heatmap.visible and not app.scene.strip.visible
    app.scene.draw(SimpleNamespace(pressure=None, force=0.0, contact_length=0.0, position=0.4), view)
    assert app.scene.strip.visible and not app.scene.heatmap.visible
    assert app.scene.frames_drawn == drawn + 2


def test_impact_markers_sit_at_each_impacts_peak():
    summary = SimpleNamespace(impacts=(SimpleNamespace(position=0.42, peak=150e3),))
    markers = impact_markers(np.linspace(0.0, 1.0, 11), summary)
    assert np.count_nonzero(np.isfinite(markers)) == 1 and markers[4] == 150.0


@pytest.mark.slow
def test_a_run_over_a_flat_marks_its_peak_and_says_its_impacts(app, finish_run):
    """A short hertz run over a 50 mm flat from the form: the run's parameters hold the flat, the force plot
    has the impact markers at the peak, the text below it the impact as ``wheelrail run`` prints it."""
    form, patch = app.form, app.tab(PatchTab)
    folder = form.irregularity
    try:
        form.model_dropdown.value = "hertz"
        form.length_text.value = "0.8"
        folder.fields["flat_length"].value = "50"
        folder.fields["flat_position"].value = "0.4"
        result = finish_run(app)
        assert result.header.params.run.irregularities == (WheelFlat(length=0.05, position=0.4),)
        summary = impact_summary(result)
        assert summary.impacts and summary.peak > 1.2 * 65e3
        labels = [label for label, _, _ in patch.force.series]
        assert labels == ["hertz", "hertz impacts"]
        markers = patch.force.data[2]
        assert np.nanmax(markers) == pytest.approx(summary.peak / 1e3)
        assert patch.force.png().startswith(b"\x89PNG")  # the markers drawn by matplotlib too
        assert patch.impacts_md.visible
        assert f"peak {summary.peak / 1e3:.2f} kN" in patch.impacts_md.content
        assert "flat 50 mm rounded at x = 0.4 m" in patch.impacts_md.content
    finally:
        for handle in folder.fields.values():
            handle.value = ""


PLOTS_IN_PAGE = """() => Object.values((window.__viserTestpoints || {}).uplots || {}).map(t => ({
    title: String((t.chart.root.querySelector('.u-title') || {}).textContent || ''),
    labels: t.chart.series.slice(1).map(s => String(s.label))}))"""


def _text_field(page, label):
    """viser's text inputs carry no label element: the input nearest the label's text."""
    return page.get_by_text(label, exact=True).first.locator("xpath=following::input[1]")


def _page_has_plot(page, title_part: str, label: str | None = None, timeout: float = 60_000) -> None:
    """Wait (on the page's own updates) for a plot whose title holds ``title_part`` (and a curve ``label``)."""
    page.wait_for_function(
        f"""([part, label]) => ({PLOTS_IN_PAGE})().some(p => p.title.includes(part)
            && (label === null || p.labels.includes(label)))""",
        arg=[title_part, label],
        timeout=timeout,
    )


@pytest.mark.slow
def test_a_flat_set_in_the_page_runs_and_shows_its_impact(open_page):
    """In Chromium: the Irregularity folder opened, a 50 mm flat typed, Run; the force plot's title states the
    flat, the plot has the impact markers and the page says the impact; a bad position is one line on the page."""
    page, session, errors = open_page(1400, 1000)
    session.form.model_dropdown.value = "hertz"
    session.form.length_text.value = "0.8"
    page.get_by_text("Irregularity", exact=True).click()
    for label, value in (("Flat length (mm)", "50"), ("Flat position (m)", "0.4")):
        field = _text_field(page, label)
        field.fill(value)
        field.press("Enter")
    _page_has_plot(page, "flat 50 mm rounded at x = 0.4 m (Hertz on the trajectory)")
    page.get_by_role("button", name="Run", exact=True).click()
    page.get_by_text("Done: hertz on corrugated-rail", exact=False).first.wait_for(timeout=300_000)
    _page_has_plot(page, "Contact force", "hertz impacts")
    page.get_by_text("Impacts", exact=True).first.wait_for(timeout=60_000)
    page.get_by_text("at x = 0.4", exact=False).first.wait_for(timeout=60_000)
    position = _text_field(page, "Flat position (m)")
    position.fill("9")
    position.press("Enter")
    page.get_by_text("Flat position 9 m: reaches from", exact=False).first.wait_for(timeout=60_000)
    assert session.page.last_error is None
    assert not errors, errors


def test_a_session_keeps_the_irregularity_folder(app):
    """Save session holds the folder as typed, Load session sets it back; a bad one is one line, nothing set."""
    form, folder = app.form, app.form.irregularity
    try:
        form.model_dropdown.value = "hertz"
        form.length_text.value = "0.8"
        folder.fields["flat_length"].value = "50"
        folder.fields["flat_position"].value = "0.4"
        folder.input.value = "raw"
        form.refresh()
        saved = app.shown
        name, content = app.session.download()
        assert b'"irregularity"' in content and "WheelFlat0.4m" in name
        for handle in folder.fields.values():
            handle.value = ""
        folder.input.value = "trajectory"
        form.refresh()
        assert app.shown != saved
        app.session.load(content)
        assert app.shown == saved and folder.fields["flat_length"].value == "50" and folder.input.value == "raw"
        bad = content.replace(b'"flat_position": "0.4"', b'"flat_position": "9"')
        with pytest.raises(WheelrailError) as info:
            app.session.load(bad)
        assert page_message(info.value).startswith("session file: Flat position 9 m: reaches from")
        unknown = content.replace(b'"flat_position"', b'"flat_colour"')
        with pytest.raises(WheelrailError, match="unknown irregularity input"):
            app.session.load(unknown)
        assert app.shown == saved  # a refused session changes nothing
    finally:
        for handle in folder.fields.values():
            handle.value = ""
        folder.input.value = "trajectory"
        form.refresh()


@pytest.mark.slow
def test_a_3d_run_over_a_flat_replays_the_wheel_in_the_air(app, finish_run):
    """3d over a 50 mm flat at 100 km/h: the wheel leaves the rail (steps with F = 0 and no pressure), the
    replay draws such a step's empty patch without error, and the impacts are said."""
    form, patch = app.form, app.tab(PatchTab)
    folder = form.irregularity
    try:
        form.model_dropdown.value = "3d"
        form.length_text.value = "0.8"
        folder.fields["flat_length"].value = "50"
        folder.fields["flat_position"].value = "0.4"
        result = finish_run(app)
        lost = np.flatnonzero(result.force <= 0.0)
        assert lost.size and not np.any(result.pressure[lost[0]])
        app.replay.scrub(int(lost[0]))
        assert app.page.last_error is None and app.scene.heatmap.visible
        assert "**3d**: impacts: peak" in patch.impacts_md.content
    finally:
        for handle in folder.fields.values():
            handle.value = ""
