"""CSV exports engineers expect: a run's time history and a run's sound power per band, each headed by the
configuration that produced it."""

from __future__ import annotations

import json

import numpy as np
import pytest

from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.noise.run_noise import RunNoise
from wheelrail.core.parameters import ContactParameters, ModelParameters


def _result(n: int = 300) -> RunResult:
    t = np.arange(n) * 3.6e-5
    rng = np.random.default_rng(2)
    return RunResult(
        header=RunHeader(
            model="2d",
            line=1,
            roughness_name="corrugated-rail",
            params=ModelParameters(contact=ContactParameters(preload=80e3)),
            wheel_roughness_name="sinter-wheel-1",
        ),
        time=t,
        x=np.arange(n) * 1e-3,
        force=80e3 + rng.normal(0, 500, n),
        xi_wheel=rng.normal(0, 1e-6, n),
        xi_rail=rng.normal(0, 1e-6, n),
        roughness=rng.normal(0, 1e-6, n),
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5),
        equivalent_roughness=rng.normal(0, 1e-6, n),
    )


def test_time_history_csv_holds_the_arrays_and_names_the_configuration(tmp_path):
    result = _result()
    path = result.save_csv(tmp_path / "history.csv")
    lines = path.read_text().splitlines()
    assert lines[0].startswith("# wheelrail run time history: corrugated-rail + wheel set sinter-wheel-1 line 1, ")
    for fact in ("model 2d", "100 km/h", "preload 80 kN", "element 1 mm", "wheel radius 390 mm", "track 70 bays"):
        assert fact in lines[0], fact
    configuration = json.loads(lines[1].split(":", 1)[1], parse_constant=lambda name: pytest.fail(name))
    assert configuration["parameters"]["contact"]["preload"] == 80e3
    assert lines[2] == "time_s,x_m,force_N,xi_wheel_m,xi_rail_m,roughness_m,equivalent_roughness_m"
    table = np.loadtxt(path, delimiter=",", comments="#", skiprows=3)
    assert table.shape == (300, 7)
    expected = [result.time, result.x, result.force, result.xi_wheel, result.xi_rail, result.roughness]
    for column, values in enumerate([*expected, result.equivalent_roughness]):
        assert np.allclose(table[:, column], values, rtol=1e-9, atol=0), column  # 10 significant digits


def test_sound_power_csv_has_band_names_exact_centres_and_empty_unresolved_bands():
    from wheelrail.core.spectra.bands import noise_bands

    f = noise_bands()
    level = np.linspace(80.0, 100.0, 24)
    level[-2:] = np.nan  # above the run's Nyquist frequency
    powers = {name: level - k for k, name in enumerate(("rail", "sleeper", "wheel", "total"))}
    noise = RunNoise(
        frequency_hz=f,
        force_db=level,
        effective_roughness_db=level,
        sound_power_db=powers,
        sound_power_dba={name: 101.0 for name in powers},
        axle_dba=104.0,
        pass_by_laeq_dba=88.8,
        configuration={"train_axles": 16, "train_length_m": 80.0},
    )
    lines = noise.csv_text("# wheelrail rolling noise of r.npz: a run\n").splitlines()
    assert lines[0] == "# wheelrail rolling noise of r.npz: a run"
    assert "pass-by L_pAeq,Tp 88.80 dB(A)" in lines[1] and "16 axles in 80 m" in lines[1]
    assert lines[2] == "band,centre_hz,force_dB_re_1N,rail_dB,sleeper_dB,wheel_dB,total_dB"
    assert lines[3].startswith("50,50.1187,80.000,80.000,79.000,78.000,77.000")
    assert lines[-1] == "10000,10000,,,,,"
    assert len(lines) == 3 + 24
