"""The element size in the explorer: a field of the Run folder next to the speed (core's declaration,
``--element-mm``'s), read into the run's parameters, worded when out of range, named in the case where it is not the
default and in the result's text always, and kept by a session."""

from __future__ import annotations

import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness import load_roughness
from wheelrail.explorer.config import length_range, page_message, read_config

RAIL = load_roughness("corrugated-rail")
FIELDS = {"line": "0", "model": "3d", "speed_kmh": "100", "preload_kn": "65", "length_m": "1"}


def test_the_field_sets_the_runs_element_size_and_names_it():
    config = read_config(RAIL, "corrugated-rail", **FIELDS, element_mm="0.5")
    assert config.params().run.element_size == 5e-4 and config.params().run.time_step == pytest.approx(1.8e-5)
    assert config.case_label() == "corrugated-rail, line 0, 100 km/h, 65 kN, 1 m, element size 0.5 mm"
    assert config.file_stem() == "wheelrail-3d-corrugated-rail-line0-100kmh-65kN-1m-dx0.5mm"
    assert config.as_dict()["element_mm"] == 0.5
    plain = read_config(RAIL, "corrugated-rail", **FIELDS, element_mm="1")
    assert plain.inputs == () and config.case() != plain.case()  # the default: the case and its label as before
    assert plain.case_label() == "corrugated-rail, line 0, 100 km/h, 65 kN, 1 m"
    assert plain.label(stated=True) == "3d on corrugated-rail, line 0, 100 km/h, 65 kN, 1 m, element size 1 mm"
    assert config.label(stated=True) == config.label()  # named once


@pytest.mark.parametrize(
    ("typed", "start"),
    [
        ("3", "Element size 3 mm is outside the accepted 0.5 to 2 mm ("),
        ("0.1", "Element size 0.1 mm is outside the accepted 0.5 to 2 mm ("),
        ("x", "Element size 'x': not a number"),
    ],
)
def test_an_element_size_out_of_range_is_worded_with_the_fields_label(typed, start):
    with pytest.raises(WheelrailError) as info:
        read_config(RAIL, "corrugated-rail", **FIELDS, element_mm=typed)
    message = page_message(info.value)
    assert message.startswith(start) and "--" not in message and "\n" not in message


def test_the_run_lengths_offered_are_whole_elements():
    shortest, longest = length_range(RAIL, 100 / 3.6, 2e-3)
    assert longest == pytest.approx(round(longest / 2e-3) * 2e-3, abs=1e-12) and shortest < longest
    config = read_config(RAIL, "corrugated-rail", **{**FIELDS, "length_m": f"{longest:g}"}, element_mm="2")
    assert config.length == pytest.approx(longest)


@pytest.mark.slow
def test_the_form_has_it_next_to_the_speed_runs_it_and_a_session_keeps_it(app, finish_run):
    form = app.form
    assert list(form.fields)[:3] == ["speed", "preload", "element_size"]  # the Run folder: speed, load, grid
    field = form.fields["element_size"]
    assert field.label == "Element size (mm)" and field.value == "1"
    assert field.hint.endswith("0.5 to 2 mm; default 1 mm")
    try:
        form.model_dropdown.value = "hertz"
        form.line_dropdown.value = "0"
        form.length_text.value = "0.6"
        field.value = "5"
        assert app.shown is None and "Element size 5 mm is outside the accepted 0.5 to 2 mm" in form.check_md.content
        field.value = "2"
        assert app.shown.params().run.element_size == 2e-3
        result = finish_run(app)
        assert result.element_size == 2e-3 and result.n_steps == 300
        assert "element size 2 mm" in app.page.status_md.content and app.page.status_md.content.startswith("Done:")
        name, content = app.session.download()
        assert b'"element_mm": "2"' in content and "dx2mm" in name
        saved = app.shown
        field.value = "1"
        assert app.shown != saved
        app.session.load(content)
        assert field.value == "2" and app.shown == saved
        field.value = "1"
        finish_run(app)
        assert "0.6 m, element size 1 mm." in app.page.status_md.content  # the default, stated in the result's text
        form.model_dropdown.value = "3d"  # the 3d window on the finer grid, replayed and drawn without an error
        field.value = "0.5"
        result = finish_run(app)
        assert result.element_size == 5e-4 and result.window_x[1] - result.window_x[0] == pytest.approx(5e-4)
        assert app.page.last_error is None and app.page.status_md.content.startswith("Done: 3d on")
    finally:
        field.value = "1"


@pytest.mark.slow
def test_in_the_page_the_field_sits_under_the_speed_and_preload_and_a_typed_size_runs(open_page):
    """Headless Chromium: the field is drawn right below Speed and Preload, a size typed in it reaches the run and
    the result line names it."""
    page, session, errors = open_page(1400, 1000)
    session.form.model_dropdown.value = "hertz"
    session.form.length_text.value = "0.8"
    tops = [page.get_by_text(label, exact=True).first.bounding_box()["y"]
            for label in ("Speed (km/h)", "Preload (kN)", "Element size (mm)")]  # fmt: skip
    assert tops == sorted(tops) and tops[2] - tops[1] == pytest.approx(tops[1] - tops[0], abs=4)  # one row each
    field = page.get_by_text("Element size (mm)", exact=True).first.locator("xpath=following::input[1]")
    field.fill("0.5")
    field.press("Enter")
    # the page sends the field before the click, on the one connection: the run is the typed size's
    page.get_by_role("button", name="Run", exact=True).click()
    page.get_by_text("Done: hertz on corrugated-rail, line 0, 100 km/h, 65 kN, 0.8 m, element size 0.5 mm",
                     exact=False).wait_for(timeout=300_000)  # fmt: skip
    assert session.replay.entry.result.element_size == 5e-4
    assert not errors, errors
