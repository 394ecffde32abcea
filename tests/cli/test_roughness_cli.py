"""``wheelrail datasets`` and ``wheelrail roughness``."""

import json
import subprocess
import sys

import numpy as np
import pytest

from wheelrail.core.roughness import RoughnessSet, write_csv


def test_datasets_json(cli):
    code, out, err = cli("datasets", "--json")
    assert code == 0 and err == ""
    sets = {s["name"]: s for s in json.loads(out)["datasets"]}
    assert set(sets) == {"corrugated-rail", "cast-iron-wheel", "sinter-wheel-1", "sinter-wheel-2"}
    rail = sets["corrugated-rail"]
    assert (rail["kind"], rail["lines"], rail["line_numbers"]) == ("rail", 19, [-9, 9])
    assert rail["length_m"] == pytest.approx(8.0) and rail["dx_m"] == pytest.approx(1e-3)
    wheel = sets["cast-iron-wheel"]
    assert wheel["lateral_spacing_m"] == pytest.approx(2e-3) and wheel["length_m"] == pytest.approx(2.9)


def test_datasets_table(cli):
    code, out, _ = cli("datasets")
    assert code == 0 and "corrugated-rail" in out and "synthetic" in out


def test_roughness_json_for_bundled_set(cli):
    code, out, err = cli("roughness", "--set", "corrugated-rail", "--json")
    assert code == 0 and err == ""
    result = json.loads(out)  # strict JSON: unresolved bands are null, never NaN
    centres = np.array(result["band_centres_hz"])
    levels = np.array([np.nan if v is None else v for v in result["levels_db"]])
    assert len(centres) == len(levels) == len(result["coherence"]) == len(result["wavelengths_m"]) == 23
    assert result["band_labels"][int(np.nanargmax(levels))] == "500"  # the corrugation band
    np.testing.assert_allclose(result["wavelengths_m"], result["speed_m_s"] / centres, rtol=1e-12)
    assert result["speed_m_s"] == pytest.approx(100 / 3.6)
    assert result["lines_averaged"] == [-3, -2, -1, 0, 1, 2, 3]
    assert len(result["wavelength_bands"]["levels_db"]) == 25  # 800 mm .. 3.15 mm


def test_roughness_user_csv_and_options(cli, tmp_path):
    rng = np.random.default_rng(2)
    x = np.arange(4000) * 1e-3
    common = 5e-6 * np.sin(2 * np.pi * x / 0.04)  # 40 mm wavelength, the same on every line
    heights = common + rng.normal(scale=0.2e-6, size=(5, x.size))
    path = write_csv(
        RoughnessSet(heights=heights, dx=1e-3, y=np.arange(-2, 3) * 1e-3, kind="rail", description="mine"),
        tmp_path / "mine.csv",
    )
    code, out, err = cli(
        "roughness",
        "--set",
        str(path),
        "--speed-kmh",
        "90",
        "--lines",
        "-1",
        "0",
        "1",
        "--m",
        "2",
        "--blocks",
        "10",
        "--json",
    )
    assert code == 0, err
    result = json.loads(out)
    assert result["lines_averaged"] == [-1, 0, 1] and result["coherence_m"] == 2
    levels = np.array([np.nan if v is None else v for v in result["levels_db"]])
    # 25 m/s / 0.04 m = 625 Hz -> the 630 Hz band
    assert result["band_labels"][int(np.nanargmax(levels))] == "630"
    labels = result["band_labels"]
    assert result["coherence"][labels.index("630")] > 0.95  # the common sinusoid dominates there


@pytest.mark.slow
def test_roughness_plot(cli, tmp_path):
    target = tmp_path / "r.png"
    code, out, err = cli("roughness", "--set", "sinter-wheel-1", "--plot", str(target))
    assert code == 0, err
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "figure written" in out and "EN 15610 wavelength bands" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["roughness", "--set", "no-such-set"],
            "unknown roughness set 'no-such-set'; bundled sets: cast-iron",
        ),
        (["roughness", "--set", "corrugated-rail", "--speed-kmh", "-5"], "--speed-kmh -5 is outside the accepted"),
        (["roughness", "--set", "corrugated-rail", "--lines", "12"], "--lines 12: not in the roughness set"),
        (["roughness", "--set", "corrugated-rail", "--plot", "x.pdf"], "--plot x.pdf: the file name must end in .png"),
        (["roughness", "--set", "cast-iron-wheel", "--blocks", "1000"], "--blocks 1000 is outside the accepted 1 to"),
    ],
)
def test_bad_input_one_line_nonzero(cli, argv, message):
    code, out, err = cli(*argv)
    assert code != 0 and out == ""
    assert err.count("\n") == 1 and message in err


def test_malformed_user_file(cli, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("# kind: rail\nx_m,y_mm=0,y_mm=1\n0,1,2\n0.001,3\n")
    code, out, err = cli("roughness", "--set", str(bad))
    assert code != 0 and out == ""
    assert err.count("\n") == 1 and f"{bad}, line 4: ragged row" in err


@pytest.mark.slow
def test_module_entry_point_reports_one_line(tmp_path):
    # the real console path: a subprocess, stderr one line, non-zero exit
    missing = tmp_path / "absent.npz"
    proc = subprocess.run(
        [sys.executable, "-m", "wheelrail", "roughness", "--set", str(missing)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode != 0 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "roughness file not found" in proc.stderr


@pytest.mark.parametrize("model", ["hertz", "3d"])
def test_run_refuses_roughness_whose_model_grid_would_need_gigabytes(cli, tmp_path, model):
    # Two samples 1e6 m apart: the 1 mm model grid needs 1e9 heights (8 GB) a line; this was a MemoryError
    # after trying to allocate them. Now one line with the figure, before allocating.
    coarse = tmp_path / "coarse.csv"
    coarse.write_text("x_m,y_mm=-1,y_mm=0,y_mm=1\n0,1,2,3\n1000000,2,3,4\n")
    code, out, err = cli("run", "--set", str(coarse), "--model", model)
    assert code != 0 and out == ""
    # refused by the reader's accepted spacing (1 µm to 10 mm) before any grid is sized; sets made in memory
    # meet the grid's own height count (tests/unit/test_roughness_damaged.py)
    assert err.count("\n") == 1 and "sample spacing 1e+06 m is outside the accepted" in err
