"""``wheelrail spectra FILE``: force spectrum of a saved run, .npz and .rrd agree."""

from __future__ import annotations

import json

import numpy as np
import pytest

from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.recording import record_result

DT = 1e-3 / (100 / 3.6)  # s


def _result(n: int = 2000) -> RunResult:
    t = np.arange(n) * DT
    rng = np.random.default_rng(3)
    force = 65e3 + 2e3 * np.sin(2 * np.pi * 501.187 * t) + rng.normal(0, 30, n)  # 500 Hz tone + noise
    zeros = np.zeros(n)
    return RunResult(
        header=RunHeader(model="hertz", line=0, roughness_name="corrugated-rail", params=ModelParameters()),
        time=t,
        x=np.arange(n) * 1e-3,
        force=force,
        xi_wheel=zeros,
        xi_rail=zeros,
        roughness=zeros,
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5),
        equivalent_roughness=zeros,
    )


def test_npz_and_rrd_give_the_same_spectrum(tmp_path, cli):
    result = _result()
    npz = result.save_npz(tmp_path / "run.npz")
    rrd = record_result(result, tmp_path / "run.rrd")
    code_npz, out_npz, err_npz = cli("spectra", str(npz), "--json")
    code_rrd, out_rrd, err_rrd = cli("spectra", str(rrd), "--json")
    assert code_npz == code_rrd == 0 and err_npz == err_rrd == ""
    from_npz, from_rrd = json.loads(out_npz), json.loads(out_rrd)
    # exact: both files hold the force as float64 and the same time step
    assert from_npz["levels_db"] == from_rrd["levels_db"]
    assert from_npz["band_centres_hz"] == from_rrd["band_centres_hz"]
    levels = np.array(from_npz["levels_db"], dtype=float)
    band = int(np.nanargmax(levels))  # NaN: low bands narrower than the 19 Hz bin spacing of 52 ms
    # the 2 kN tone: 20 log10(2000 / sqrt 2) = 63.0 dB in the 500 Hz band (0.3 dB: Hann leakage and
    # the noise's ~30 dB-lower share of the band)
    assert from_npz["band_labels"][band] == "500"
    assert levels[band] == pytest.approx(20 * np.log10(2000 / np.sqrt(2)), abs=0.3)
    assert from_npz["model"] == "hertz" and from_npz["steps"] == 2000 and from_npz["skip_s"] == pytest.approx(0.02)


def test_table_output_and_skip(tmp_path, cli):
    npz = _result().save_npz(tmp_path / "run.npz")
    code, out, err = cli("spectra", str(npz), "--skip-ms", "5")
    assert code == 0 and err == ""
    assert "first 5 ms skipped" in out and "dB re 1 N" in out
    assert len([line for line in out.splitlines() if line.strip().split()[0] in ("500", "8000")]) == 2


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("missing.npz", None, "does not exist"),
        ("corrupt.npz", b"PK\x03\x04 truncated zip", "cannot read run file"),
        ("text.npz", b"hello", "not a NumPy .npz"),
        ("corrupt.rrd", b"RRF2 garbage", "cannot read recording"),
        ("run.csv", b"x_m,y_mm=0\n0,1\n", "must be a .npz"),
    ],
)
def test_bad_files_are_one_clear_line(tmp_path, cli, name, content, message):
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    code, out, err = cli("spectra", str(path))
    assert code != 0 and out == ""
    assert len(err.strip().splitlines()) == 1 and message in err and err.startswith("wheelrail spectra: error:")


def test_npz_without_force_and_too_short_run(tmp_path, cli):
    np.savez(tmp_path / "other.npz", z_m=np.zeros((3, 10)))
    code, _, err = cli("spectra", str(tmp_path / "other.npz"))
    assert code != 0 and "no 'force' array" in err
    short = _result(n=100).save_npz(tmp_path / "short.npz")  # 3.6 ms < the 20 ms start-up skip
    code, _, err = cli("spectra", str(short))
    assert code != 0 and len(err.strip().splitlines()) == 1
    assert (
        err.startswith(
            "wheelrail spectra: error: --skip-ms 20: the record of 100 steps (0.0036 s) leaves 0 steps after the skip"
        )
        and "accepted at most 3.024 ms; or use a longer run" in err
    )


def test_a_short_record_states_its_skip_duration_and_resolved_range(tmp_path, cli):
    npz = _result(n=1000).save_npz(tmp_path / "run.npz")  # 1 m at 100 km/h: 16 ms left after the 20 ms
    code, out, err = cli("spectra", str(npz), "--json")
    assert code == 0 and err == ""
    summary = json.loads(out)
    record = summary["spectrum_record"]
    assert record["skip_s"] == pytest.approx(556 * DT) and record["analysed_duration_s"] == pytest.approx(444 * DT)
    assert record["lowest_resolved_band_label"] == "315"
    resolved = np.flatnonzero([level is not None for level in summary["levels_db"]])
    assert summary["band_labels"][resolved[0]] == "315" and np.all(np.diff(resolved) == 1)
    code, out, err = cli("spectra", str(npz))
    assert code == 0 and "after the first 20.02 ms (start-up, left out): bands 315-8000 Hz resolved" in out
    table = {row.split()[0]: row.split()[1] for row in out.splitlines()[3:]}
    assert table["250"] == "n/a" and table["315"] != "n/a"


@pytest.mark.parametrize("skip_ms", ["1e308", "1e300", "72"])
def test_a_skip_past_the_record_is_one_line(tmp_path, cli, skip_ms):
    npz = _result(n=2000).save_npz(tmp_path / "run.npz")
    code, out, err = cli("spectra", str(npz), "--skip-ms", skip_ms)
    assert code != 0 and out == "" and len(err.strip().splitlines()) == 1
    assert err.startswith(f"wheelrail spectra: error: --skip-ms {float(skip_ms):g}") and "Error" not in err
