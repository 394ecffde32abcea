"""`wheelrail wheel`: natural frequencies by family and n, receptances, --json (strict), --csv, --plot, bad input
as one line naming the option."""

import csv
import json

import numpy as np
import pytest

from wheelrail.cli import main

SMALL = ["--wheel", "wheel_640", "--max-frequency-hz", "3000", "--max-harmonic", "4", "--element-size-mm", "20"]


def test_wheel_json_states_frequencies_by_family_and_receptances(capsys):
    assert main(["wheel", *SMALL, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    table = summary["natural_frequencies_hz"]
    assert [row["n"] for row in table] == [0, 1, 2, 3, 4]
    frequencies = [f for row in table for family in ("axial", "radial", "circumferential") for f in row[family]]
    assert len(frequencies) == summary["modes"]["count"] and max(frequencies) <= 3000
    # a plate-like wheel: the lowest axial mode of each n >= 2 rises with n
    lowest = [row["axial"][0] for row in table[2:]]
    assert lowest == sorted(lowest)
    bands = summary["receptance_at_bands"]
    assert bands["frequency_hz"][0] == pytest.approx(100.0) and len(bands["radial_m_per_n"]) == len(
        bands["frequency_hz"]
    )
    assert summary["wheel"]["kind"] == "parametric" and summary["wheel"]["wheel_radius"] == 0.32
    assert summary["loss_factor"]["added"] == 0.0


def test_wheel_csv_and_plot(tmp_path, capsys):
    out = tmp_path / "w.csv"
    plot = tmp_path / "w.png"
    assert main(["wheel", *SMALL, "--csv", str(out), "--plot", str(plot), "--df-hz", "50"]) == 0
    text = capsys.readouterr().out
    assert "n =  2: axial" in text and "written to" in text
    rows = list(csv.reader(out.open()))
    assert rows[0][:3] == ["frequency_hz", "radial_abs_m_per_n", "radial_phase_rad"]
    data = np.array(rows[1:], dtype=float)
    assert data[0, 0] == 50 and data[-1, 0] == 3000
    modes = list(csv.reader((tmp_path / "w_modes.csv").open()))
    assert modes[0] == ["n", "family", "frequency_hz", "loss_factor"]
    assert {row[1] for row in modes[1:]} <= {"axial", "radial", "circumferential"}
    assert plot.stat().st_size > 10_000


def test_a_shape_option_changes_the_named_wheel(capsys):
    assert main(["wheel", *SMALL, "--web-thickness-mm", "30", "--json"]) == 0
    thick = json.loads(capsys.readouterr().out)
    assert thick["wheel"]["web_thickness"] == pytest.approx(0.03)
    assert main(["wheel", *SMALL, "--json"]) == 0
    base = json.loads(capsys.readouterr().out)
    # a thicker web is a stiffer plate: the n = 2 axial mode rises
    assert thick["natural_frequencies_hz"][2]["axial"][0] > base["natural_frequencies_hz"][2]["axial"][0]


def test_an_outline_file_is_a_wheel(tmp_path, capsys):
    path = tmp_path / "disc.csv"
    path.write_text("r_mm,z_mm\n80,-40\n110,-40\n110,-10\n280,-10\n280,-60\n320,-60\n320,60\n280,60\n280,10\n"
                    "110,10\n110,40\n80,40\n", encoding="utf-8")  # fmt: skip
    assert main(["wheel", "--outline", str(path), "--contact-z-mm", "0", *SMALL[2:], "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["wheel"]["kind"] == "outline" and summary["wheel"]["contact"] == [0.32, 0.0]
    assert summary["modes"]["count"] > 5


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--tyre-width-mm", "300"], "--tyre-width-mm 300 is outside the accepted 80 to 200 mm"),
        (["--wheel", "tram"], "--wheel: unknown wheel 'tram'"),
        (["--element-size-mm", "0.1"], "--element-size-mm 0.1 is outside the accepted 2 to 50 mm"),
        (["--max-harmonic", "99"], "--max-harmonic 99 is outside the accepted 0 to 40"),
        (["--contact-offset-mm", "70"], "--contact-offset-mm 70: the contact must be on the tread"),
        (["--outline", "x.csv", "--web-offset-mm", "10"], "--outline and --web-offset-mm cannot be given together"),
        (["--added-loss-factor", "2"], "--added-loss-factor 2 is outside the accepted 0 to 1"),
        (["--plot", "w.pdf"], "must end in .png"),
    ],
)
def test_bad_wheel_input_is_one_line_naming_the_option(argv, words, capsys):
    assert main(["wheel", *argv]) != 0
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1


def test_a_radius_too_small_for_the_hub_says_what_fits(capsys):
    # --wheel-radius-mm 180 (accepted 100 to 1250) was refused as "--hub-outer-radius-mm 130: the web must span at
    # least twice its thickness between the hub and the rim", an option the user never typed and no number to aim
    # for: the line gives the parts' sizes and the smallest radius they fit
    assert main(["wheel", "--wheel-radius-mm", "180"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    for words in ("hub outer radius 130 mm", "rim inner radius 130 mm", "web 25 mm", "at least 230 mm"):
        assert words in err, err


def test_a_run_with_the_modal_wheel_states_it_and_differs_from_the_2dof(capsys):
    # the interaction with the modal wheel (the 840 mm wheel at the paper's R = 0.39 m): the mean force is the
    # preload (0.5 %, as the 2-DOF's smooth-run test) and the force levels differ from the 2-DOF wheel's in the
    # bands where their receptances differ (above a few hundred Hz: tests/physics/test_modal_wheel_interaction.py)
    argv = ["run", "--set", "corrugated-rail", "--length-m", "1.5", "--json"]
    assert main([*argv, "--wheel-model", "modal"]) == 0
    modal = json.loads(capsys.readouterr().out)
    assert main(argv) == 0
    paper = json.loads(capsys.readouterr().out)
    assert modal["wheel_model"] == "modal" and paper["wheel_model"] == "2dof"
    assert modal["modal_wheel"]["wheel_radius"] == pytest.approx(0.39)
    assert modal["force_mean_n"] == pytest.approx(65e3, rel=5e-3)
    levels = [np.array([np.nan if v is None else v for v in run["levels_db"]]) for run in (modal, paper)]
    assert np.nanmax(np.abs(levels[0] - levels[1])) > 1.0  # bands without a level are null in the JSON
