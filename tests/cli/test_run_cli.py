"""`wheelrail run`: every model on a bundled set and a user CSV, --out arrays, --json, bad input."""

import json

import numpy as np
import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.roughness import load_roughness, write_csv


@pytest.mark.parametrize("model", ["3d", "2d", "hertz", "hertz-winkler", "hertz-average"])
@pytest.mark.slow
def test_run_every_model_writes_npz(model, tmp_path, capsys, step_arrays):
    out = tmp_path / "run.npz"
    argv = [
        "run",
        "--set",
        "cast-iron-wheel",
        "--line",
        "1",
        "--model",
        model,
        "--speed-kmh",
        "80",
        "--length-m",
        "0.05",
        "--out",
        str(out),
        "--json",
    ]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["steps"] == 50 and summary["model"] == model
    # the default run-in from the steady state, 0.5 ms at 80 km/h in whole elements (12 mm)
    assert summary["run_in_time_s"] == pytest.approx(0.012 / (80 / 3.6), rel=1e-4)
    assert summary["run_in_length_m"] == pytest.approx(0.012)
    assert summary["speed_m_per_s"] == pytest.approx(80 / 3.6)
    data = np.load(out)
    for name in step_arrays:
        assert data[name].shape == (50,)
    assert np.allclose(np.diff(data["time"]), 1e-3 / (80 / 3.6))
    assert np.all(data["force"] > 0)
    if model == "3d":
        assert data["pressure"].shape == (50, 25, 25)
        # the pressure integrates to the force (eq. 9, 1 mm elements)
        assert np.allclose(data["pressure"].sum(axis=(1, 2)) * 1e-6, data["force"], rtol=1e-5)
    else:
        assert "pressure" not in data


def test_run_on_a_user_csv(tmp_path, capsys):
    # a user's own data works like a bundled set: export three lines of the rail set to CSV and run
    rail = load_roughness("corrugated-rail")
    path = tmp_path / "mine.csv"
    write_csv(rail, path)
    assert main(["run", "--set", str(path), "--model", "2d", "--length-m", "0.2", "--json"]) == 0
    mine = json.loads(capsys.readouterr().out)
    assert main(["run", "--set", "corrugated-rail", "--model", "2d", "--length-m", "0.2", "--json"]) == 0
    bundled = json.loads(capsys.readouterr().out)
    # the CSV stores heights in um with 6+ significant digits: same forces to 1e-6 relative
    assert mine["force_std_n"] == pytest.approx(bundled["force_std_n"], rel=1e-4)


@pytest.mark.slow
def test_run_records_to_rrd_and_spectra_reads_it(tmp_path, capsys):
    rrd = tmp_path / "run.rrd"
    argv = ["run", "--set", "corrugated-rail", "--model", "3d", "--length-m", "0.06", "--rrd", str(rrd), "--json"]
    assert main(argv) == 0
    capsys.readouterr()
    from wheelrail.core.recording import read_recording

    back = read_recording(rrd)
    assert back.n_steps == 60
    assert np.all(back.force > 0)


def test_human_output(capsys):
    assert main(["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "1.0"]) == 0
    out = capsys.readouterr().out
    assert "contact force: mean" in out and "dB re 1 N" in out
    assert "run-in before the record (discarded): 0.014 m, 0.5 ms" in out  # 0.5 ms from the steady state, 100 km/h
    assert main(["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "0.1"]) == 0
    assert "no force spectrum" in capsys.readouterr().out


def test_a_short_run_says_its_skip_and_resolution_and_has_no_gaps(capsys):
    # 1 m at 100 km/h: 20 ms left out, 16 ms analysed; a band is resolved by its width against 1 / 16 ms
    argv = ["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "1.0"]
    assert main([*argv, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    record = summary["spectrum_record"]
    assert record["skip_s"] == pytest.approx(0.02, abs=4e-5) and record["analysed_duration_s"] == pytest.approx(
        0.016, abs=4e-5
    )
    assert record["lowest_resolved_band_label"] == "315"
    levels = np.array([np.nan if v is None else v for v in summary["levels_db"]])
    resolved = np.flatnonzero(np.isfinite(levels))
    assert summary["band_labels"][resolved[0]] == "315" and np.all(np.diff(resolved) == 1)  # no n/a in between
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "after the first 20.02 ms (start-up, left out)" in out and "bands 315-8000 Hz resolved" in out
    rows = [line.split() for line in out.splitlines() if line.strip().endswith(("n/a",)) or "Hz" in line]
    names = [row[0] for row in rows if len(row) == 3 and row[1] == "Hz"]
    shown = [row[2] for row in rows if len(row) == 3 and row[1] == "Hz"]
    assert names[:3] == ["50", "63", "80"] and shown[: names.index("315")] == ["n/a"] * names.index("315")
    assert "n/a" not in shown[names.index("315") :]


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["run", "--set", "no-such-set"], "unknown roughness set"),
        (["run", "--set", "corrugated-rail", "--line", "30"], "--line 30: not in the roughness set; accepted -9 to 9"),
        (["run", "--set", "corrugated-rail", "--model", "4d"], "invalid choice: '4d'"),
        (["run", "--set", "corrugated-rail", "--speed-kmh", "0"], "--speed-kmh 0 is outside the accepted 5 to 400"),
        (["run", "--set", "corrugated-rail", "--preload-kn", "-5"], "--preload-kn -5 is outside the accepted 1 to 500"),
        (["run", "--set", "corrugated-rail", "--length-m", "20"], "--length-m 20: with the 20 mm window margins"),
        (["run", "--set", "corrugated-rail", "--out", "/no/such/dir/r.npz"], "does not exist"),
        (["run", "--set", "corrugated-rail", "--out", "result.txt"], "must end in .npz"),
    ],
)
def test_bad_input_is_one_line(argv, fragment, capsys):
    with pytest.raises(SystemExit) if "4d" in argv else _no_raise() as info:
        code = main(argv)
    if info is not None and hasattr(info, "value"):
        code = info.value.code
    assert code == 2
    err = capsys.readouterr().err
    assert fragment in err and err.count("\n") == 1


class _no_raise:
    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False


def test_3d_on_a_one_line_set_says_how_wide_a_set_must_be(tmp_path, capsys):
    from wheelrail.cli.dispatch import main

    path = tmp_path / "one.csv"
    path.write_text(
        "# kind: rail\nx_m,y_mm=0\n" + "".join(f"{i * 1e-3:.3f},{(i % 7) * 0.1:.1f}\n" for i in range(3000))
    )
    assert main(["run", "--set", str(path), "--model", "3d"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("wheelrail run: error: --line 0: a set of one line has no width") and "14 mm" in err


def test_band_labels_are_the_nominal_names_everywhere(capsys):
    """One convention: nominal band names in text and in ``band_labels``, exact centres in ``band_centres_hz``
    (the text once printed 79, 126, 158, 251 Hz where ``spectra`` printed 80, 125, 160, 250)."""
    from wheelrail.core.spectra.bands import nominal_band_label

    argv = ["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "1.0"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    for name in ("80", "125", "160", "250", "1000", "8000"):
        assert f" {name} Hz" in text, name
    for exact in ("79", "126", "158", "251", "1585", "7943"):
        assert f" {exact} Hz" not in text, exact
    assert main([*argv, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["band_labels"] == [nominal_band_label(c) for c in summary["band_centres_hz"]]
    assert summary["band_labels"][:4] == ["50", "63", "80", "100"]
    assert summary["band_centres_hz"][0] == pytest.approx(50.1187, abs=1e-4)  # exact: 10^(17/10)


def test_run_writes_its_time_history_as_csv(tmp_path, capsys):
    path = tmp_path / "history.csv"
    argv = ["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "0.1", "--csv", str(path)]
    assert main(argv) == 0
    assert f"time history written to {path}" in capsys.readouterr().out
    lines = path.read_text().splitlines()
    assert lines[0].startswith("# wheelrail run time history: corrugated-rail line 0, model hertz, 100 km/h")
    table = np.loadtxt(path, delimiter=",", comments="#", skiprows=3)
    assert table.shape == (100, 7) and np.all(table[:, 2] > 0)  # 100 steps of 1 mm, a positive force
    # refused before the run: a CSV name that is not one, or the input itself
    assert main(["run", "--set", "corrugated-rail", "--csv", str(tmp_path / "h.txt")]) != 0
    assert "--csv" in capsys.readouterr().err


def test_sound_power_asked_for_on_a_short_run_is_said_not_dropped(tmp_path, capsys):
    """--sound-power on a run too short for a force spectrum: one warning line in the command's words, and the
    recording's sound-power document says why it holds no spectra."""
    from rerun.chunk import RrdReader

    rrd = tmp_path / "short.rrd"
    argv = ["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "0.05", "--rrd", str(rrd)]
    with pytest.warns(UserWarning) as caught:  # the command prints each as "wheelrail run: warning: <message>"
        assert main([*argv, "--sound-power"]) == 0
    messages = [str(w.message) for w in caught if "sound power" in str(w.message)]
    assert len(messages) == 1 and "\n" not in messages[0], messages
    assert messages[0].startswith(
        "--sound-power: no sound power recorded: the run is 0.05 m long (50 steps): too short"
    )
    documents = [
        c.to_record_batch().column("TextDocument:text").to_pylist()[-1][0]
        for c in RrdReader(rrd).stream()
        if c.entity_path == "/spectra/sound_power/summary"
    ]
    assert len(documents) == 1 and "not computed" in documents[0] and "0.05 m long (50 steps)" in documents[0]
