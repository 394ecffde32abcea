"""Each user-facing input is declared once (core/inputs/declared.py); the command line's options, the explorer's
fields, the error wording of each front end and the study's parameters all derive from that declaration."""

from __future__ import annotations

import dataclasses
import math

import pytest

from wheelrail.cli.commands._common import params_from_args
from wheelrail.cli.dispatch import build_parser, main
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs import declared
from wheelrail.core.inputs.declared import GROUPS, INPUTS, Input, Unit, by_key, describe, inputs_of, model_parameters
from wheelrail.core.inputs.ranges import ACCEPTED, Accepted
from wheelrail.core.parameters import ModelParameters, SupportParameters

TRACK_OPTIONS = (
    "--pad-stiffness-mn-m",
    "--pad-damping-kns-m",
    "--sleeper-mass-kg",
    "--sleeper-spacing-m",
    "--ballast-stiffness-mn-m",
    "--ballast-damping-kns-m",
    "--rail-loss-factor",
    "--pad-width-mm",
    "--pad-lateral-stiffness-mn-m",
    "--pad-rotational-stiffness-knm-rad",
    "--pad-lateral-loss-factor",
)


def test_every_declared_input_has_a_default_within_its_range_and_a_group():
    for entry in INPUTS:
        assert entry.group in GROUPS, entry.key
        assert ACCEPTED[entry.key] == entry.accepted  # the parameter classes check the declared range
        default = entry.default()  # read from ModelParameters(), never restated
        if default is not None and math.isfinite(default):
            assert entry.check(default) == default
            assert entry.shown_default() * entry.shown.si == pytest.approx(default, rel=1e-12)
        else:
            assert entry.unset, entry.key  # an unset default says what it means
    assert [e.option for e in inputs_of("track")] == list(TRACK_OPTIONS)
    assert by_key("pad_stiffness").path == "track.support.pad_stiffness"
    assert by_key("pad_stiffness").default() == SupportParameters().pad_stiffness == 120e6


@pytest.mark.parametrize(
    ("argv", "wording"),
    [
        (["--pad-stiffness-mn-m", "0"], "--pad-stiffness-mn-m 0 is outside the accepted 10 to 3000 MN/m ("),
        (["--sleeper-spacing-m", "nan"], "--sleeper-spacing-m 'nan': not a number"),
        (["--rail-loss-factor", "-0.01"], "--rail-loss-factor -0.01 is outside the accepted 0 to 0.1 ("),
        (["--ballast-damping-kns-m", "-1"], "--ballast-damping-kns-m -1 is outside the accepted 20 to 1000 kNs/m ("),
    ],
)
def test_a_track_input_out_of_range_is_one_line_in_each_front_ends_words(argv, wording, capsys):
    for command in (["run", "--set", "corrugated-rail"], ["track"], ["study", "filters", "--set", "x", "--out", "o"]):
        assert main([*command, *argv]) == 2
        err = capsys.readouterr().err.strip()
        assert "\n" not in err and err.split("error: ", 1)[1].startswith(wording.replace("'nan'", "nan")), err
        assert "SupportParameters" not in err
    from wheelrail.explorer.config import page_message, read_inputs

    entry = next(e for e in INPUTS if e.option == argv[0])
    with pytest.raises(WheelrailError) as info:
        read_inputs(**{entry.dest: argv[1]})
    label = f"{entry.label} "
    assert page_message(info.value).startswith(label) and "--" not in page_message(info.value)
    with pytest.raises(WheelrailError) as info:  # the API: the argument's own name, SI
        model_parameters({entry.key: float(argv[1]) * entry.shown.si})
    assert str(info.value).startswith(entry.key)


def test_the_track_options_set_the_track_and_defaults_keep_the_parameters_to_the_bit():
    parser = build_parser("run")
    default = params_from_args(parser.parse_args(["run", "--set", "s"]), "run", "geometry", "track")
    assert default == ModelParameters()
    args = parser.parse_args(["run", "--set", "s", "--pad-stiffness-mn-m", "60", "--sleeper-mass-kg", "40"])
    params = params_from_args(args, "run", "geometry", "track")
    assert params.track.support.pad_stiffness == 60e6 and params.track.support.sleeper_mass == 40.0
    assert params.track.support.ballast_stiffness == 140e6  # the rest: the paper's
    assert describe(params, "track")["track"]["pad_stiffness"] == 60e6


def test_the_study_takes_the_parameters_as_prepare_run_does():
    from wheelrail.core.study import plan_study

    soft = model_parameters({"pad_stiffness": 60e6})
    plan = plan_study("speeds", ["corrugated-rail"], params=soft, length=1.2)
    assert {spec.params.track for spec in plan.specs} == {soft.track}  # every run on the soft track
    plain = plan_study("speeds", ["corrugated-rail"], length=1.2)
    assert {s.key for s in plan.specs}.isdisjoint(s.key for s in plain.specs)  # the track is in every run's key


def test_adding_an_input_is_one_declaration(monkeypatch, capsys):
    # the rail's mass per length, declared here as a new input would be (its declaration and its range): it
    # appears in the command line's help, sets the parameters, is refused in each front end's words and gets a
    # field in the explorer's Track folder
    rail_mass = Input(
        "rail_mass", "track.rail.mass_per_length", Unit("kg/m", 1.0, "kg-m"), "Rail mass", "track", "mass"
    )
    monkeypatch.setattr(declared, "INPUTS", (*INPUTS, rail_mass))
    monkeypatch.setitem(ACCEPTED, "rail_mass", Accepted("rail_mass", "kg/m", 30.0, 80.0, "rails from 30 to 80 kg/m"))
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    assert "--rail-mass-kg-m" in capsys.readouterr().out
    args = build_parser("run").parse_args(["run", "--set", "s", "--rail-mass-kg-m", "54.77"])
    assert params_from_args(args, "track").track.rail.mass_per_length == 54.77
    assert main(["track", "--rail-mass-kg-m", "5"]) == 2
    assert (
        capsys.readouterr()
        .err.strip()
        .endswith("error: --rail-mass-kg-m 5 is outside the accepted 30 to 80 kg/m (rails from 30 to 80 kg/m)")
    )
    from wheelrail.explorer.config import page_message, read_inputs

    assert dict(read_inputs(rail_mass_kg_m="54.77")) == {"rail_mass": 54.77}
    with pytest.raises(WheelrailError) as info:
        read_inputs(rail_mass_kg_m="5")
    assert (
        page_message(info.value) == "Rail mass 5 kg/m is outside the accepted 30 to 80 kg/m (rails from 30 to 80 kg/m)"
    )
    from wheelrail.explorer.app import ExplorerApp
    from wheelrail.explorer.headless import HeadlessTab

    app = ExplorerApp(port=0)  # any free port; one tab connects, without a browser
    try:
        tab = HeadlessTab(app.port)
        assert app.wait_for(lambda: app.sessions, 60)
        form = next(iter(app.sessions.values())).form
        assert form.fields["rail_mass"].label == "Rail mass (kg/m)" and form.fields["rail_mass"].value == "60"
        tab.close()
    finally:
        app.close()


def test_a_config_names_its_track_in_labels_and_file_names():
    from wheelrail.explorer.config import RunConfig

    config = RunConfig(set_label="corrugated-rail", line=0, model="3d", length=3.0, inputs=(("pad_stiffness", 60e6),))
    assert config.case_label() == "corrugated-rail, line 0, 100 km/h, 65 kN, 3 m, pad stiffness 60 MN/m"
    assert config.file_stem() == "wheelrail-3d-corrugated-rail-line0-100kmh-65kN-3m-kP60MNm"
    assert config.params().track.support.pad_stiffness == 60e6
    assert config.case() != dataclasses.replace(config, inputs=()).case()
    assert config.as_dict()["pad_stiffness_mn_m"] == 60


def test_the_user_guides_track_table_states_the_declared_defaults_and_ranges():
    from pathlib import Path

    text = (Path(__file__).parents[2] / "docs" / "user_guide.md").read_text(encoding="utf-8")
    for entry in inputs_of("track"):
        row = next(line for line in text.splitlines() if line.startswith(f"| `{entry.option}` |"))
        cells = [cell.strip() for cell in row.strip("|").split("|")]
        low, high = entry.in_shown()
        assert cells[3] == f"{entry.shown_default():g}" and cells[4] == f"{low:g} to {high:g}", row
        assert cells[2].startswith(f"`{entry.path}`"), row


def test_an_unstable_step_is_refused_not_run(monkeypatch):
    # the guard of the coupled step's period-two mode (history.check_step_stability): an undamped track's
    # alternating compliance larger than the contact's is refused in one line (the accepted tracks keep a
    # margin of 0.34-0.85; a stand-in rail compliance of -2/k_H here)
    import numpy as np

    from wheelrail.core.engine.history import check_step_stability
    from wheelrail.core.wheel import wheel_discrete_system

    params = ModelParameters()
    stiffness = 1.5 * params.contact.preload / params.contact.hertz_approach()
    system = wheel_discrete_system(params.wheel, params.run.time_step)
    calm = np.zeros((4, 8))
    assert 0.9 < check_step_stability(params, calm, system) <= 1.0  # the wheel alone barely moves it
    ringing = np.tile((-1.0) ** np.arange(8) * (-2.0 / stiffness / 8), (4, 1))
    with pytest.raises(WheelrailError, match="time stepping would be unstable"):
        check_step_stability(params, ringing, system)


def test_a_run_states_its_track_and_contact_geometry(capsys):
    import json

    argv = ["run", "--set", "corrugated-rail", "--length-m", "0.6", "--pad-stiffness-mn-m", "120"]
    assert main([*argv, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["track"]["pad_stiffness"] == 120e6 and summary["track"]["rail_loss_factor"] == 0.0
    assert summary["geometry"]["wheel_radius"] == 0.39 and summary["geometry"]["wheel_transverse_radius"] is None
    assert summary["hertz_semi_axes_m"] == pytest.approx([5.482e-3, 5.482e-3], rel=1e-3)  # the paper's a
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "  track: pad stiffness 120 MN/m, pad damping 16 kNs/m, sleeper mass 125 kg" in text
    assert "a = 5.48 mm along, b = 5.48 mm across" in text


def test_the_wheel_model_is_a_declared_choice():
    """--wheel-model is declared once (core.inputs.declared.CHOICES): its values, default, option and error key."""
    from wheelrail.cli.commands._common import CLI_NAMES
    from wheelrail.core.errors import WheelrailError
    from wheelrail.core.inputs.declared import choice
    from wheelrail.core.noise.wheel_power import DEFAULT_WHEEL_MODEL, WHEEL_MODELS

    entry = choice("noise_wheel_model")
    assert entry.values == WHEEL_MODELS == ("directive", "modal") and entry.default == DEFAULT_WHEEL_MODEL
    assert entry.option == "--wheel-model" and CLI_NAMES["noise_wheel_model"].label == "--wheel-model"
    assert "directive: CNOSSOS-EU" in entry.help_text() and "default directive" in entry.help_text()
    try:
        entry.check("fem")
    except WheelrailError as error:
        assert error.parameter == "noise_wheel_model"
    else:
        raise AssertionError("an unknown wheel model was accepted")
