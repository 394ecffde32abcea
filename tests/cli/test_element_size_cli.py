"""`--element-mm`: the element size (contact grid and step along the rail) from the command line, declared once in
core (``core.inputs.declared``: 0.5 to 2 mm), stated by every output of a run and a study."""

from __future__ import annotations

import json

import numpy as np
import pytest

from wheelrail.core.inputs.declared import by_key


def test_the_element_size_is_a_declared_run_input():
    entry = by_key("element_size")
    assert entry.option == "--element-mm" and entry.dest == "element_mm" and entry.group == "run"
    assert entry.path == "run.element_size" and entry.default() == 1e-3  # RunParameters' default, SI
    assert entry.in_shown() == (0.5, 2.0) and entry.accepted.unit == "m"


@pytest.mark.parametrize(
    ("value", "wording"),
    [
        ("3", "--element-mm 3 is outside the accepted 0.5 to 2 mm ("),
        ("0.25", "--element-mm 0.25 is outside the accepted 0.5 to 2 mm ("),
        ("nan", "--element-mm nan: not a number"),
    ],
)
def test_a_bad_element_size_is_one_line_in_run_and_study(value, wording, cli, tmp_path):
    for command in (["run", "--set", "corrugated-rail"], ["study", "filters", "--set", "x", "--out", str(tmp_path)]):
        code, out, err = cli(*command, "--element-mm", value)
        assert code == 2 and out == ""
        line = err.strip()
        assert "\n" not in line and line.split("error: ", 1)[1].startswith(wording), line
        assert "Traceback" not in line and "RunParameters" not in line


def test_run_and_study_take_it_and_filters_which_makes_no_run_does_not(cli, capsys):
    from wheelrail.cli.dispatch import main

    for command in ("run", "study"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        out = " ".join(capsys.readouterr().out.split())
        assert "--element-mm ELEMENT_MM" in out and "mm (default 1 mm; accepted 0.5 to 2)" in out
    with pytest.raises(SystemExit) as info:  # the analytic filters make no run: no element size to take
        main(["filters", "--element-mm", "0.5"])
    assert info.value.code == 2 and "unrecognized arguments: --element-mm" in capsys.readouterr().err


def test_a_run_at_half_a_millimetre_steps_it_and_says_so_in_text_json_and_csv(cli, tmp_path):
    speed = 100 / 3.6
    code, out, err = cli("run", "--set", "corrugated-rail", "--length-m", "0.05", "--element-mm", "0.5", "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["element_size_m"] == 5e-4 and summary["steps"] == 100
    assert summary["time_step_s"] == pytest.approx(5e-4 / speed, rel=1e-12)  # dt = element / speed
    history = tmp_path / "h.csv"
    code, out, err = cli("run", "--set", "corrugated-rail", "--length-m", "0.05", "--element-mm", "2",
                         "--csv", str(history))  # fmt: skip
    assert code == 0, err
    assert "80 km/h" not in out and ", 65 kN, element 2 mm: 25 steps over 0.050 m" in out.splitlines()[0]
    head = history.read_text().splitlines()
    assert "element 2 mm" in head[0] and '"element_size_m": 0.002' in head[1]
    x = np.loadtxt(history, delimiter=",", comments="#", skiprows=3)[:, 1]
    assert np.allclose(np.diff(x), 2e-3)
    code, out, _ = cli("run", "--set", "corrugated-rail", "--length-m", "0.05", "--json")
    assert code == 0 and json.loads(out)["element_size_m"] == 1e-3  # the default, stated as well


def test_a_recording_states_the_element_size(cli, tmp_path):
    from wheelrail.core.recording import read_recording

    path = tmp_path / "r.rrd"
    code, _, err = cli("run", "--set", "corrugated-rail", "--length-m", "0.05", "--element-mm", "0.5",
                       "--rrd", str(path))  # fmt: skip
    assert code == 0, err
    back = read_recording(path)  # its parameters document: element_size_m and the parameters, checked to agree
    assert back.header.element_size == 5e-4 and back.n_steps == 100
    assert np.allclose(np.diff(back.x), 5e-4)


@pytest.mark.slow
def test_a_study_runs_at_the_element_size_and_states_it(cli, tmp_path):
    out = tmp_path / "o"
    argv = ["study", "filters", "--set", "corrugated-rail", "--out", str(out), "--length-m", "0.8", "--workers", "1"]
    code, text, err = cli(*argv, "--element-mm", "2")
    assert code == 0, err
    assert "100 km/h, element 2 mm:" in text.splitlines()[0]
    summary = json.loads((out / "filters_summary.json").read_text())
    assert summary["element_size_m"] == 2e-3
    assert len(summary["spectrum_records"]) == 1  # every run at 2 mm: 0.8 m in 400 steps
    assert summary["spectrum_records"][0]["steps"] == 400


def test_a_studys_runs_and_their_length_are_on_its_element_grid():
    from wheelrail.core.inputs.declared import model_parameters
    from wheelrail.core.study import plan_study

    plan = plan_study("filters", ["corrugated-rail"], params=model_parameters({"element_size": 2e-3}))
    assert {spec.params.run.element_size for spec in plan.specs} == {2e-3}
    assert plan.sets[0].length == pytest.approx(7.958)  # the set's data less the margins at 2 mm (7.959 m at 1 mm)
