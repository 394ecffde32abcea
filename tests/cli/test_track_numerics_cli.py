"""`--track-numerics` on `wheelrail run`, `track`, `study` and `noise`: parsed from one declaration, bad input one
line, and every output stating the numerics that differ from the default."""

import json

import numpy as np
import pytest

from wheelrail.core.engine.results import RunHeader
from wheelrail.core.inputs.numerics import numerics_changes, parse_track_numerics
from wheelrail.core.parameters import TrackNumerics

# small numerics: a precompute of well under a second (the tests' own cache keeps it)
SMALL = "elements_per_bay=8,refined_elements_per_bay=16,positions_per_bay=8,duration_ms=10,time_step_us=20"
SMALL_CHANGES = {
    "elements_per_bay": 8,
    "refined_elements_per_bay": 16,
    "positions_per_bay": 8,
    "time_step_us": 20.0,
    "duration_ms": 10.0,
}


def test_the_names_set_their_fields_in_their_units():
    numerics = parse_track_numerics("elements_per_bay=32, near_field_m=0.2,time_step_us=2.5,duration_ms=60")
    assert (numerics.elements_per_bay, numerics.near_field) == (32, 0.2)
    assert numerics.time_step == pytest.approx(2.5e-6) and numerics.duration == pytest.approx(0.06)
    assert numerics_changes(numerics) == {
        "elements_per_bay": 32,
        "near_field_m": 0.2,
        "time_step_us": 2.5,
        "duration_ms": 60.0,
    }
    assert parse_track_numerics(None) == parse_track_numerics("") == TrackNumerics()
    assert numerics_changes(TrackNumerics()) == {}


def test_a_header_keeps_the_numerics_through_its_dictionary():
    header = RunHeader(model="hertz", line=0, roughness_name="corrugated-rail", track_numerics=SMALL_CHANGES)
    again = RunHeader.from_dict(json.loads(json.dumps(header.to_dict())))
    assert again.track_numerics == SMALL_CHANGES
    assert "track numerics elements_per_bay=8" in again.description()
    default = RunHeader(model="hertz", line=0, roughness_name="corrugated-rail")
    assert "track_numerics" not in default.to_dict() and "numerics" not in default.description()


COMMANDS = {
    "run": ["run", "--set", "corrugated-rail"],
    "track": ["track"],
    "study": ["study", "filters", "--set", "corrugated-rail", "--out", "OUT"],
    "noise": ["noise", "--method", "twins"],
}


@pytest.mark.parametrize("command", COMMANDS.values(), ids=COMMANDS)
@pytest.mark.parametrize(
    "value, fragment",
    [
        ("foo=1", "unknown name 'foo'; the names are elements_per_bay"),
        ("elements_per_bay=x", "elements_per_bay must be a whole number from 4 to 256, got 'x'"),
        ("elements_per_bay=32.5", "must be a whole number"),
        ("time_step_us=0.1", "time_step_us must be a number from 0.5 to 20 us"),
        ("near_field_m=nan", "near_field_m must be a number"),
        ("positions_per_bay=48", "positions_per_bay (48) must divide refined_elements_per_bay (64)"),
        ("elements_per_bay=32,elements_per_bay=16", "elements_per_bay is given twice"),
        ("elements_per_bay", "'elements_per_bay' is not name=value"),
    ],
)
def test_bad_numerics_are_one_line(command, value, fragment, cli, tmp_path):
    command = [str(tmp_path / "study") if word == "OUT" else word for word in command]
    code, out, err = cli(*command, "--track-numerics", value)
    assert not (tmp_path / "study").exists()  # refused before any work
    assert code != 0 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "--track-numerics" in lines[0] and fragment in lines[0], err
    assert "Traceback" not in err and "Error:" not in err.split("error:", 1)[-1]


def test_a_run_states_its_numerics_in_every_output(tmp_path, cli):
    out_csv, out_npz = tmp_path / "run.csv", tmp_path / "run.npz"
    argv = ["run", "--set", "corrugated-rail", "--length-m", "0.2", "--track-numerics", SMALL]
    code, out, err = cli(*argv, "--json", "--csv", str(out_csv), "--out", str(out_npz))
    assert code == 0, err
    summary = json.loads(out)
    assert summary["track_numerics"] == SMALL_CHANGES
    assert "track numerics elements_per_bay=8" in out_csv.read_text().splitlines()[0]
    from wheelrail.core.engine.results import RunResult

    assert RunResult.load_npz(out_npz).header.track_numerics == SMALL_CHANGES
    code, out, err = cli(*argv)
    assert code == 0, err
    assert "  track numerics: elements_per_bay=8, refined_elements_per_bay=16, positions_per_bay=8" in out


def test_the_track_command_uses_and_states_its_numerics(cli):
    code, out, err = cli("track", "--track-numerics", SMALL, "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["track_numerics"] == SMALL_CHANGES
    green = summary["green_functions"]
    assert green["excitation_positions_per_bay"] == 8 and green["rows_per_bay"] == 8 * 4
    assert green["duration_s"] == pytest.approx(0.01, abs=2e-5)
    assert np.isfinite(summary["static_moving_compliance_m_per_n"]["midspan"])
    code, out, err = cli("track", "--track-numerics", SMALL)
    assert code == 0, err
    assert "  track numerics: elements_per_bay=8" in out


def test_the_noise_chain_takes_the_elements_per_bay_and_states_them(cli):
    code, out, err = cli("noise", "--method", "twins", "--track-numerics", "elements_per_bay=8", "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["track_numerics"] == {"elements_per_bay": 8}
    assert summary["twins"]["configuration"]["elements_per_bay"] == 8
    code, out, err = cli("noise", "--method", "twins", "--track-numerics", "elements_per_bay=8")
    assert code == 0, err
    assert "  track numerics: elements_per_bay=8 (240 bays, 8 elements per bay, 20 frequencies per band)" in out
    code, out, err = cli("noise", "--method", "twins", "--json")
    assert code == 0, err
    assert json.loads(out)["track_numerics"] == {}


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["--method", "twins", "--track-numerics", "time_step_us=2.5,elements_per_bay=8"],
         "--track-numerics: time_step_us not used by --method twins (the track in the frequency domain, no time "
         "integration); it takes elements_per_bay"),
        (["--method", "cnossos", "--track-numerics", "elements_per_bay=8"], "--track-numerics: not used by --method"),
        (["--run", "run.npz", "--track-numerics", "elements_per_bay=8"], "--track-numerics: not used by --run"),
    ],
)  # fmt: skip
def test_the_noise_refuses_numerics_it_does_not_use_in_one_line(argv, fragment, cli):
    code, out, err = cli("noise", *argv)
    lines = err.strip().splitlines()
    assert code != 0 and out == "" and len(lines) == 1 and fragment in lines[0], err


def test_a_runs_noise_takes_and_states_the_runs_numerics(tmp_path, cli):
    out_npz = tmp_path / "run.npz"
    argv = ["run", "--set", "corrugated-rail", "--length-m", "0.6", "--track-numerics", SMALL, "--out", str(out_npz)]
    code, out, err = cli(*argv)
    assert code == 0, err
    code, out, err = cli("noise", "--run", str(out_npz), "--json")
    assert code == 0, err
    configuration = json.loads(out)["configuration"]
    assert configuration["run"]["track_numerics"] == SMALL_CHANGES
    assert configuration["track"]["elements_per_bay"] == 8  # one track: the run's elements per bay
    code, out, err = cli("noise", "--run", str(out_npz))
    assert code == 0, err
    assert "  track numerics: elements_per_bay=8, refined_elements_per_bay=16" in out
    assert "(the run's; the noise chain's track 240 bays, 8 elements per bay)" in out


def test_a_studys_runs_carry_the_numerics_into_their_keys_and_their_runs(monkeypatch):
    from wheelrail.core import engine
    from wheelrail.core.study import plan_study
    from wheelrail.core.study.specs import compute_run

    numerics = parse_track_numerics(SMALL)
    default = plan_study("speeds", ["corrugated-rail"], length=1.2)
    plan = plan_study("speeds", ["corrugated-rail"], length=1.2, track_numerics=numerics)
    assert plan.track_numerics == numerics and all(spec.track_numerics == numerics for spec in plan.specs)
    assert not {spec.key for spec in plan.specs} & {spec.key for spec in default.specs}  # other runs
    same = plan_study("speeds", ["corrugated-rail"], length=1.2, track_numerics=TrackNumerics())
    assert [spec.key for spec in same.specs] == [spec.key for spec in default.specs]  # the default: the keys of old
    given = {}

    def simulate(*args, **kwargs):
        given.update(kwargs)
        raise KeyboardInterrupt  # enough: what the run was given

    monkeypatch.setattr(engine, "simulate", simulate)
    with pytest.raises(KeyboardInterrupt):
        compute_run(plan.specs[0])
    assert given["track_numerics"] == numerics


@pytest.mark.slow
def test_a_study_runs_on_and_states_its_numerics(tmp_path, cli):
    argv = ["study", "speeds", "--set", "corrugated-rail", "--out", str(tmp_path / "s"), "--length-m", "1.2"]
    code, out, err = cli(*argv, "--track-numerics", SMALL, "--workers", "1", "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["track_numerics"] == SMALL_CHANGES
    assert json.loads((tmp_path / "s" / "speeds_summary.json").read_text())["track_numerics"] == SMALL_CHANGES
    code, out, err = cli(*argv, "--track-numerics", SMALL, "--workers", "1")
    assert code == 0, err
    assert "runs (0 computed, 5 from" in out  # the runs on these numerics, kept
    assert "  track numerics: elements_per_bay=8, refined_elements_per_bay=16, positions_per_bay=8" in out


def test_a_track_studys_cost_looks_for_the_tracks_on_its_numerics(monkeypatch, tmp_path):
    from wheelrail.core import track
    from wheelrail.core.parameters import TrackParameters
    from wheelrail.core.study.track_plan import track_study_cost

    asked = []
    monkeypatch.setattr(track, "track_cache_path", lambda t, numerics: asked.append(numerics) or tmp_path / "no")
    numerics = parse_track_numerics(SMALL)
    assert track_study_cost([TrackParameters()], numerics=numerics)["new_tracks"] == 1
    assert track_study_cost([TrackParameters()])["new_tracks"] == 1
    assert asked == [numerics, TrackNumerics()]
