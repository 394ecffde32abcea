"""The noise of an impact: the force exposure of a hand-made half-sine pulse against its Fourier transform
integrated by hand, the exposure level through a flat transfer, the repetition rate and the pass-by formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from wheelrail.core.irregularities.shapes import RailJoint, WheelFlat
from wheelrail.core.noise.impact_noise import force_band_exposure, impact_events, single_event_level
from wheelrail.core.noise.run_noise import pass_by_level
from wheelrail.core.spectra.bands import BAND_HALF_WIDTH, noise_bands
from wheelrail.core.spectra.levels import a_weighting

AMPLITUDE = 20e3  # N: a half-sine pulse of 20 kN
DURATION = 2e-3  # s


def _half_sine_density(f: float) -> float:
    """One-sided energy density 2 |X(f)|^2 (N^2 s / Hz) of A sin(pi t / tau) on 0 < t < tau, by hand:
    |X(f)| = (2 A tau / pi) |cos(pi f tau) / (1 - (2 f tau)^2)| (the limit A tau / 2 at f tau = 1 / 2)."""
    u = 2 * f * DURATION
    if abs(u - 1) < 1e-9:
        magnitude = AMPLITUDE * DURATION / 2
    else:
        magnitude = 2 * AMPLITUDE * DURATION / math.pi * abs(math.cos(math.pi * f * DURATION) / (1 - u**2))
    return 2 * magnitude**2


def _hand_band_exposure() -> np.ndarray:
    return np.array(
        [quad(_half_sine_density, c / BAND_HALF_WIDTH, c * BAND_HALF_WIDTH, limit=200)[0] for c in noise_bands()]
    )


def _pulse(dt: float) -> np.ndarray:
    t = np.arange(-0.05, 0.05, dt)
    return np.where((t > 0) & (t < DURATION), AMPLITUDE * np.sin(np.pi * t / DURATION), 0.0)


def test_half_sine_force_exposure_matches_the_hand_computation():
    hand = _hand_band_exposure()
    computed = force_band_exposure(_pulse(4e-6), 4e-6)
    # every band within 1.5 % (the sampled pulse's own error grows as (f dt)^2: 1 % at 10 kHz)
    np.testing.assert_allclose(computed, hand, rtol=0.015)
    # all bands together: at most the pulse's whole energy A^2 tau / 2 (Parseval), most of it
    assert 0.85 * AMPLITUDE**2 * DURATION / 2 < computed.sum() < AMPLITUDE**2 * DURATION / 2


def test_half_sine_exposure_level_through_a_flat_transfer():
    transfer = 1e-6  # W / N^2 in every band
    hand = _hand_band_exposure() * transfer  # J per band
    l_wae_hand = 10 * math.log10(np.sum(hand * 10 ** (a_weighting(noise_bands()) / 10)) / 1e-12)
    computed = force_band_exposure(_pulse(2e-5), 2e-5) * transfer
    l_wae = 10 * math.log10(np.sum(computed * 10 ** (a_weighting(noise_bands()) / 10)) / 1e-12)
    assert l_wae == pytest.approx(l_wae_hand, abs=0.05)
    d = math.hypot(7.5, 1.2)  # the ISO 3095 microphone: L_AE = L_WAE + 10 lg(rho c 1 pJ / (2 pi d^2 p0^2 1 s))
    assert single_event_level(d) == pytest.approx(10 * math.log10(1.21 * 343.0 * 1e-12 / (2 * math.pi * d**2 * 4e-10)))


def test_impact_events_count_flat_meetings_and_rail_irregularities():
    radius = 0.46
    flat = WheelFlat(length=0.05, position=0.5)
    joint = RailJoint(position=1.0)
    # a flat at 0.5 m comes back every 2 pi R = 2.89 m: meetings at 0.5, 3.39, 6.28 within 0.2 .. 7 m
    assert impact_events([flat, joint], radius, 0.2, 7.0) == {"flat": 3, "rail": 1}
    assert impact_events([flat, joint], radius, 1.5, 3.0) == {"flat": 0, "rail": 0}


def test_flat_pass_by_from_exposure_and_rate_is_the_mean_power():
    # E per impact n times a second is a mean power E n: the pass-by of L_WAE + 10 lg n + 3 dB per axle
    l_wae, rate = 80.0, 100 / 3.6 / (2 * math.pi * 0.46)
    direct = pass_by_level(10 * math.log10(2 * 10 ** (l_wae / 10) * rate), 40, 200.0)
    assert pass_by_level(l_wae + 10 * math.log10(rate) + 10 * math.log10(2), 40, 200.0) == pytest.approx(direct)


BAY = 0.6


@pytest.fixture(scope="module")
def flat_noise():
    """A 50 mm rounded flat met once at a midspan, Hertz on the trajectory at 100 km/h on a smooth rail, and its
    noise on a small track."""
    from wheelrail.core.engine import simulate
    from wheelrail.core.noise.run_noise import run_noise
    from wheelrail.core.noise.twins import NoiseNumerics
    from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
    from wheelrail.core.roughness import RoughnessSet

    bay = ModelParameters().track.support.sleeper_spacing
    smooth = RoughnessSet.smooth(3 * bay + 0.1, lines=5)
    flat = WheelFlat(length=0.05, position=1.5 * bay)
    params = ModelParameters(run=RunParameters(speed=100 * KMH, element_size=1e-3, irregularities=(flat,)))
    result = simulate(smooth, model="hertz", params=params, length=round(2 * bay / 1e-3) * 1e-3)
    numerics = NoiseNumerics(track_bays=60, elements_per_bay=8, points_per_band=2)
    return result, run_noise(result, numerics=numerics)


def test_noise_of_a_flat_run_states_the_irregularities_the_exposure_and_the_rate(flat_noise):
    result, noise = flat_noise
    summary = noise.to_dict()
    (record,) = summary["configuration"]["run"]["irregularities"]
    assert record["kind"] == "flat" and record["length"] == pytest.approx(0.05)
    assert summary["configuration"]["run"]["irregularity_input"] == "trajectory"
    impact = summary["impact"]
    assert impact["events_in_record"] == {"flat": 1, "rail": 0}
    radius = result.header.params.contact.radius_along
    assert impact["flat_rate_per_s"] == pytest.approx(result.speed / (2 * math.pi * radius))
    # the record holds one impact: its exposure is the record's energy, so E n is the mean power of a record
    # stretched to one revolution. The run's own (stationary) level comes from one Hann-windowed spectrum of the
    # record, which weights an impact at its centre by 1 / 0.375 (+4.26 dB): the impact's pass-by is the run's,
    # less that, less 10 lg(revolution / record)
    revolution = 2 * math.pi * radius / result.speed
    from wheelrail.core.spectra.force import FORCE_SKIP

    record_s = (result.n_steps - round(FORCE_SKIP / result.time_step)) * result.time_step
    expected = noise.pass_by_laeq_dba + 10 * math.log10(record_s / revolution) - 10 * math.log10(1 / 0.375)
    assert impact["pass_by_LpAeq_dBA"]["flat"] == pytest.approx(expected, abs=0.5)
    assert "exposure level L_WAE" in noise.csv_text()
    longer = noise.with_train(80, 400.0)
    shift = pass_by_level(0.0, 80, 400.0) - pass_by_level(0.0, 40, 200.0)  # the train's end effect only
    assert longer.impact.pass_by_laeq_dba["flat"] == pytest.approx(impact["pass_by_LpAeq_dBA"]["flat"] + shift)


def test_a_wheel_record_is_one_revolution_or_whole_revolutions():
    from wheelrail.core.noise.run_noise import wheel_record

    short, long = np.arange(1.0, 101.0), np.arange(1.0, 351.0)
    assert np.array_equal(wheel_record(short, 0), short)  # no flat: as it is
    padded = wheel_record(short, 160)  # shorter than a revolution: no dynamic force for the rest of it
    assert len(padded) == 160 and np.array_equal(padded[:100], short) and not np.any(padded[100:])
    assert np.array_equal(wheel_record(long, 160), long[:320])  # longer: cut to whole revolutions


def test_the_wav_of_a_flat_run_shorter_than_a_revolution_has_the_flat_once_per_revolution():
    from wheelrail.core.noise.run_noise import RunNoise

    speed, dx = 100 / 3.6, 1e-3
    dt, revolution = dx / speed, int(round(2 * math.pi * 0.46 / dx))  # 2 890 steps, 0.104 s
    force = np.full(2000, 65e3)  # 2 m: 556 steps of start-up, then 1.4 m with one impact
    force[1200:1240] += AMPLITUDE * np.sin(np.pi * np.arange(40) / 40)
    nan = np.full(24, np.nan)
    noise = RunNoise(
        frequency_hz=noise_bands(),
        force_db=nan,
        effective_roughness_db=nan,
        sound_power_db={},
        sound_power_dba={},
        axle_dba=np.nan,
        pass_by_laeq_dba=80.0,
        configuration={"run": {"speed_m_s": speed}, "train_axles": 1, "train_length_m": 2.0},
        _force=force,
        _time_step=dt,
        _pressure_per_force_sq=np.full(24, 1e-10),
        _revolution_steps=revolution,
    )
    pressure, rate, _ = noise.pass_by_pressure(lead=1.0, seed=3)
    loud = np.flatnonzero(np.abs(pressure) > 0.2 * np.abs(pressure).max())
    bursts = 1 + np.count_nonzero(np.diff(loud) > 0.005 * rate)  # bursts at least 5 ms apart
    # two wheels, each its flat once per revolution over 2.07 s: 2 x 19.9; the 1.4 m record repeated as it is
    # would give a burst every 0.05 s, twice as many
    expected = 2 * len(pressure) / revolution
    assert abs(bursts - expected) <= 3


def test_noise_run_on_a_flat_run_lists_the_irregularities_and_the_impact(flat_noise, tmp_path, capsys, monkeypatch):
    import json

    from wheelrail.cli.dispatch import main
    from wheelrail.core.noise import run_noise as module
    from wheelrail.core.noise.twins import NoiseNumerics

    result, _ = flat_noise
    path = result.save_npz(tmp_path / "flat.npz")
    small, original = NoiseNumerics(track_bays=60, elements_per_bay=8, points_per_band=2), module.run_noise
    monkeypatch.setattr(module, "run_noise", lambda *a, **k: original(*a, **k, numerics=small))
    wav = tmp_path / "p.wav"
    assert main(["noise", "--run", str(path), "--json", "--train-length-m", "20", "--train-axles", "4",
                 "--wav", str(wav)]) == 0  # fmt: skip
    summary = json.loads(capsys.readouterr().out)
    assert summary["configuration"]["run"]["irregularities"][0]["kind"] == "flat"
    assert summary["impact"]["events_in_record"]["flat"] == 1 and summary["impact"]["flat_rate_per_s"] > 0
    assert "once per revolution" in summary["wav"]["fill"]
    assert summary["wav"]["level_dBA"] == pytest.approx(summary["impact"]["pass_by_LpAeq_dBA"]["flat"])
    assert main(["noise", "--run", str(path)]) == 0
    text = capsys.readouterr().out
    assert "irregularities (Hertz on the trajectory): flat 50 mm" in text
    assert "exposure level L_WAE" in text and "once per revolution" in text


@pytest.mark.slow
def test_the_impact_noise_of_a_flat_grows_about_20_lg_v():
    """Wu & Thompson (2002): impact noise about 20 lg v (6 dB per doubling); validation/impact_noise.py gives +5.5
    dB per doubling per impact on the default numerics (docs/validation.md), +5.3 on these coarse ones."""
    import importlib.util
    from pathlib import Path

    from wheelrail.core.noise.twins import NoiseNumerics

    spec = importlib.util.spec_from_file_location(
        "impact_noise_script", Path(__file__).parents[2] / "validation" / "impact_noise.py"
    )
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    small = NoiseNumerics(track_bays=60, elements_per_bay=8, points_per_band=2)
    slow, fast = script.flat_noise(50.0, numerics=small), script.flat_noise(100.0, numerics=small)
    per_doubling = fast.exposure_dba - slow.exposure_dba
    assert 4.5 < per_doubling < 7.0
    # the rate doubles too: the time-averaged level gains 10 lg 2 more
    assert fast.pass_by_laeq_dba["flat"] - slow.pass_by_laeq_dba["flat"] == pytest.approx(per_doubling + 3.01, abs=0.01)


def test_rail_irregularity_pass_by_by_hand():
    from wheelrail.core.noise.impact_noise import ImpactNoise

    impact = ImpactNoise(
        events={"flat": 0, "rail": 1},
        force_exposure_db=np.zeros(24),
        energy_db={},
        exposure_dba=100.0,
        sel_dba=np.nan,
        flat_rate_hz=None,
        flats=0,
        speed=100 / 3.6,
        train=(40, 200.0),
    )
    # 80 wheel passings within T_p = 200 m / 27.78 m/s = 7.2 s: 100 + 10 lg(80 / 7.2) - 25.43 dB
    assert impact.pass_by_laeq_dba == {"rail": pytest.approx(100 + 10.4576 - 25.4326, abs=1e-3)}
