"""The track's numerics in the explorer: a field of the Track folder (core's ``--track-numerics``, one declaration),
read into the run's ``prepare_run`` keywords, worded with the field's label when refused, named in the case and the
result's text, handed to the run and the track's precompute, and kept by a session."""

from __future__ import annotations

import json

import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.numerics import parse_track_numerics
from wheelrail.core.roughness import load_roughness
from wheelrail.explorer.config import page_message, read_config, read_session, session_config
from wheelrail.explorer.controller import RunController

RAIL = load_roughness("corrugated-rail")
FIELDS = {"line": "0", "model": "hertz", "speed_kmh": "100", "preload_kn": "65", "length_m": "1"}
SMALL = "elements_per_bay=8,refined_elements_per_bay=16,positions_per_bay=8,duration_ms=10,time_step_us=20"


def test_the_field_sets_the_runs_numerics_and_names_them():
    config = read_config(RAIL, "corrugated-rail", **FIELDS, track_numerics=" elements_per_bay=32 ")
    assert config.run_options() == {"track_numerics": parse_track_numerics("elements_per_bay=32")}
    assert config.case_label() == "corrugated-rail, line 0, 100 km/h, 65 kN, 1 m, track numerics elements_per_bay=32"
    assert "track numerics elements_per_bay=32" in config.label(stated=True)
    assert config.file_stem() == "wheelrail-hertz-corrugated-rail-line0-100kmh-65kN-1m-elements_per_bay32"
    assert config.as_dict()["track_numerics"] == {"elements_per_bay": 32}
    plain = read_config(RAIL, "corrugated-rail", **FIELDS)
    assert plain.run_options() == {} and plain.case() != config.case()
    assert plain.case_label() == "corrugated-rail, line 0, 100 km/h, 65 kN, 1 m"  # the default: as before
    default = read_config(RAIL, "corrugated-rail", **FIELDS, track_numerics="elements_per_bay=16")
    assert default.case() == plain.case() and default.run_options() == {}  # the default typed: the default


@pytest.mark.parametrize(
    ("typed", "start"),
    [
        ("foo=1", "Track numerics: unknown name 'foo'; the names are elements_per_bay"),
        ("time_step_us=0.1", "Track numerics: time_step_us must be a number from 0.5 to 20 us"),
        ("positions_per_bay=48", "Track numerics: positions_per_bay (48) must divide refined_elements_per_bay (64)"),
        ("elements_per_bay", "Track numerics: 'elements_per_bay' is not name=value"),
    ],
)
def test_bad_numerics_are_worded_with_the_fields_label(typed, start):
    with pytest.raises(WheelrailError) as info:
        read_config(RAIL, "corrugated-rail", **FIELDS, track_numerics=typed)
    message = page_message(info.value)
    assert message.startswith(start) and "--" not in message and "\n" not in message


def _session(**extra) -> bytes:
    document = {"wheelrail_session": 1, "set": "corrugated-rail", "wheel_set": "none", "model": "hertz"}
    return json.dumps({**document, "line": "0", "length_m": "1", **extra}).encode()


def test_a_session_keeps_the_numerics_and_refuses_what_is_not_text():
    sets, wheels = ("corrugated-rail",), ("none",)
    session = read_session(_session(track_numerics="elements_per_bay=32"), sets, wheels)
    assert session["track_numerics"] == "elements_per_bay=32"
    assert session_config(session, RAIL).track_numerics == (("elements_per_bay", 32),)
    assert read_session(_session(), sets, wheels)["track_numerics"] == ""  # a session saved before: the default
    with pytest.raises(WheelrailError, match="text as the page's fields hold them"):
        read_session(_session(track_numerics=32), sets, wheels)
    with pytest.raises(WheelrailError, match=r"^session file: Track numerics: unknown name 'x'"):
        session_config(read_session(_session(track_numerics="x=1"), sets, wheels), RAIL)


def test_the_run_and_the_tracks_precompute_are_given_the_numerics():
    """prepare_run gets ``track_numerics=`` (only when given: a run at the default is prepared as before), and the
    track's precompute the same numerics, so that the Green's functions the page waits for are the run's."""
    from tests.gui.test_explorer_controller import FakeRun, Recorder  # the controller tests' fakes

    calls, computed = [], []

    def prepare(roughness, *, model, line, params, length, **options):
        calls.append(options)
        return FakeRun(model, 3000)

    listener = Recorder()
    controller = RunController(listener, prepare=prepare, precompute=lambda p, **o: computed.append(o))
    numbered = read_config(RAIL, "corrugated-rail", **FIELDS, track_numerics=SMALL)
    for config in (read_config(RAIL, "corrugated-rail", **FIELDS), numbered):
        listener.ended.clear()
        controller.start(config, "rail")
        assert listener.ended.wait(60.0)
    assert calls == [{}, {"track_numerics": parse_track_numerics(SMALL)}]
    assert computed == [{}, {"track_numerics": parse_track_numerics(SMALL)}]  # a new track case: prepared again


@pytest.mark.slow
def test_the_track_folder_has_the_field_and_a_session_keeps_it(app, finish_run):
    form = app.form
    field = form.numerics_text
    assert field.label == "Track numerics" and field.value == "" and "elements_per_bay=32" in field.hint
    try:
        form.model_dropdown.value = "hertz"
        form.line_dropdown.value = "0"
        form.length_text.value = "1"
        field.value = "foo=1"
        assert app.shown is None and "Track numerics: unknown name 'foo'" in form.check_md.content
        field.value = "elements_per_bay=32"
        assert app.shown.run_options() == {"track_numerics": parse_track_numerics("elements_per_bay=32")}
        saved = app.shown
        name, content = app.session.download()
        assert json.loads(content)["track_numerics"] == "elements_per_bay=32" and "elements_per_bay32" in name
        field.value = ""
        assert app.shown != saved and app.shown.run_options() == {}
        app.session.load(content)
        assert field.value == "elements_per_bay=32" and app.shown == saved
        field.value = SMALL  # a run on them: its header and the result line state them
        form.length_text.value = "0.6"
        result = finish_run(app)
        assert result.header.track_numerics == dict(app.shown.track_numerics) != {}
        assert "track numerics elements_per_bay=8" in app.page.status_md.content
    finally:
        field.value = ""
