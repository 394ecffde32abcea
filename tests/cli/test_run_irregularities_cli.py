"""`wheelrail run` with a discrete irregularity: the options (declared once in core.inputs.irregular), the impact
summary printed and in --json, the irregularities the output states, and bad geometry refused in one line."""

import json

import pytest

from wheelrail.cli.dispatch import main

FLAT = ["--flat-length-mm", "50", "--flat-position-m", "0.5"]
RUN = ["run", "--set", "corrugated-rail", "--length-m", "1"]


def test_a_flat_run_prints_its_impact_and_states_the_flat(capsys, tmp_path):
    csv = tmp_path / "run.csv"
    assert main([*RUN, *FLAT, "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "irregularities (Hertz on the trajectory): flat 50 mm rounded at x = 0.5 m" in out
    assert "1 impact(s)" in out and "at x = 0.5" in out and "without contact" in out
    assert "flat 50 mm rounded" in csv.read_text().splitlines()[0]  # the CSV's header states it


def test_the_json_summary_has_the_irregularities_and_the_impacts(capsys):
    assert main([*RUN, *FLAT, "--flat-shape", "new", "--irregularity-input", "raw", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["irregularities"] == [
        {"kind": "flat", "length": 0.05, "depth": None, "shape": "new", "position": 0.5}
    ]
    assert summary["irregularity_input"] == "raw"
    impacts = summary["impacts"]
    assert impacts["peak_force_n"] == summary["force_max_n"] and impacts["time_without_contact_s"] > 0
    # the flat's impact first (the corrugation then rings above 1.2 P once more on the raw new flat's landing)
    assert abs(impacts["impacts"][0]["position_m"] - 0.5) < 0.03 and impacts["impacts"][0]["min_force_n"] == 0.0


def test_a_run_without_irregularities_has_no_impact(capsys):
    assert main([*RUN, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert "irregularities" not in summary and summary["impacts"]["impacts"] == []


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--flat-length-mm", "1000", "--flat-position-m", "0.5"], "--flat-length-mm 1000: a flat this long"),
        (["--flat-length-mm", "50"], "--flat-length-mm 50: a flat needs its position as well"),
        (["--flat-length-mm", "50", "--flat-position-m", "5"], "--flat-position-m 5: reaches from"),
        (["--flat-length-mm", "-5", "--flat-position-m", "0.5"], "--flat-length-mm -5: must be positive"),
        (["--joint-position-m", "0.5", "--joint-gap-mm", "700"], "--joint-gap-mm 700"),
        (
            ["--weld-position-m", "0.5", "--weld-length-mm", "300"],
            "--weld-position-m 0.5: a weld needs its depth as well",
        ),
    ],
)
def test_bad_geometry_is_one_line_and_exit_2(argv, words, capsys):
    assert main([*RUN, *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1 and "Traceback" not in err and "Error:" not in err


@pytest.mark.slow
def test_the_noise_of_an_impact_run_states_its_irregularities(capsys, tmp_path):
    out = tmp_path / "flat.npz"
    assert main([*RUN, *FLAT, "--out", str(out), "--json"]) == 0
    capsys.readouterr()
    assert main(["noise", "--run", str(out)]) == 0
    text = capsys.readouterr().out
    assert "irregularities (Hertz on the trajectory): flat 50 mm rounded at x = 0.5 m" in text
    assert "pass-by" in text
