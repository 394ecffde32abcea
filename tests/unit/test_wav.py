"""The pass-by WAV: a standard sample rate, and its own L_pAeq over T_p is the stated pass-by level, whatever
the seed of the random stretches of the record each wheel gets."""

from __future__ import annotations

import dataclasses
import io

import numpy as np
import pytest
from scipy.io import wavfile

from wheelrail.core.noise.run_noise import WAV_RATE, RunNoise, laeq_of_pressure
from wheelrail.core.spectra.bands import noise_bands

SPEED = 100 / 3.6  # m/s
DT = 1e-3 / SPEED  # s: the run's 27 778 Hz


def _noise(level_dba: float = 84.0) -> RunNoise:
    """A run's noise with a 2 m force record (a random force of 1 kN rms) and a pressure-per-force gain that
    rises 3 dB per band to 1 kHz; the stated pass-by level is ``level_dba``."""
    rng = np.random.default_rng(7)
    bands = noise_bands()
    gain_db = np.where(bands < 1000, -95 + 3 * np.log2(bands / 1000) * 3, -95.0)
    nan = np.full(24, np.nan)
    return RunNoise(
        frequency_hz=bands,
        force_db=nan,
        effective_roughness_db=nan,
        sound_power_db={},
        sound_power_dba={},
        axle_dba=np.nan,
        pass_by_laeq_dba=level_dba,
        configuration={"run": {"speed_m_s": SPEED}, "train_axles": 8, "train_length_m": 40.0},
        _force=65e3 + rng.normal(0.0, 1e3, 2000),
        _time_step=DT,
        _pressure_per_force_sq=10 ** (gain_db / 10),
    )


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4])
def test_wav_is_at_48_khz_and_at_the_stated_level_for_every_seed(seed):
    noise = _noise()
    data, full_scale = noise.wav_bytes(lead=0.3, seed=seed)
    rate, samples = wavfile.read(io.BytesIO(data))
    assert rate == WAV_RATE == 48_000 and samples.dtype == np.int16
    _, _, (first, last), correction = noise.calibrated_pass_by(lead=0.3, seed=seed)
    level = laeq_of_pressure(samples[first:last] / 32767 * full_scale, rate)
    # 0.05 dB: 16-bit quantisation of a signal peaking at half scale is ~80 dB down; the rest is the
    # resampled T_p's edges (a sample either way)
    assert level == pytest.approx(noise.pass_by_laeq_dba, abs=0.05)
    # T_p: the train's 40 m at 100 km/h, 1.44 s, at 48 kHz
    assert (last - first) / rate == pytest.approx(40.0 / SPEED, abs=2 / rate)


def test_the_seeds_differ_before_calibration():
    """What the calibration removes: the random stretches alone move the level by tenths of a dB."""
    noise = _noise()
    corrections = [noise.calibrated_pass_by(lead=0.3, seed=seed)[3] for seed in range(5)]
    assert np.ptp(corrections) > 0.05


def _slow_noise(train_length: float) -> RunNoise:
    """A 5 km/h run (its own rate 1 389 Hz, a 48 kHz WAV 35 times as many samples) past a train of
    ``train_length`` m."""
    noise = _noise()
    speed = 5 / 3.6
    configuration = {"run": {"speed_m_s": speed}, "train_axles": 8, "train_length_m": train_length}
    force = 65e3 + np.random.default_rng(3).normal(0.0, 1e3, 4000)
    return dataclasses.replace(noise, configuration=configuration, _force=force, _time_step=1e-3 / speed)


def test_the_wav_written_in_blocks_is_the_wav_computed_whole(monkeypatch):
    from wheelrail.core.noise import wav

    noise = _slow_noise(20.0)  # 14.4 s + 2 x 0.3 s: 720 000 samples
    monkeypatch.setattr(wav, "BLOCK_SAMPLES", 50_000)  # 15 blocks, T_p weighted in 14
    data, full_scale = noise.wav_bytes(lead=0.3)
    rate, samples = wavfile.read(io.BytesIO(data))
    pressure, _, (first, last), correction = noise.calibrated_pass_by(lead=0.3)  # the whole record at once
    assert rate == WAV_RATE and len(samples) == len(pressure)
    assert full_scale == pytest.approx(2 * np.max(np.abs(pressure)), rel=1e-3)
    whole = np.round(pressure / (2 * np.max(np.abs(pressure))) * 32767)
    assert np.max(np.abs(samples - whole)) <= 33  # the blocks join seamlessly: within 0.1 % of full scale
    level = laeq_of_pressure(samples[first:last] / 32767 * full_scale, rate)
    assert level == pytest.approx(noise.pass_by_laeq_dba, abs=0.05)


def test_writing_a_long_wav_holds_a_block_not_the_pass_by(monkeypatch, tmp_path):
    import tracemalloc

    from wheelrail.core.files.cache import wait_for_writes
    from wheelrail.core.noise import wav

    noise = _slow_noise(40.0)  # 29 s: 1.4 million samples, 11 MB as float64 and 55 MB computed whole
    monkeypatch.setattr(wav, "BLOCK_SAMPLES", 1 << 16)
    wait_for_writes()  # another test's cache write (a thread of its own) would be traced too
    tracemalloc.start()
    try:
        with open(tmp_path / "p.wav", "wb") as handle:
            noise.write_wav(handle, lead=0.3)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    samples = ((tmp_path / "p.wav").stat().st_size - 44) / 2
    assert samples == pytest.approx((40.0 / (5 / 3.6) + 0.6) * WAV_RATE, abs=0.01 * WAV_RATE)  # within 10 ms
    assert peak < 8e6


def test_a_pass_by_longer_than_a_wav_holds_is_refused_before_any_work():
    from wheelrail.core.errors import WheelrailError

    noise = _slow_noise(5000.0)  # an hour at 5 km/h
    with pytest.raises(WheelrailError) as caught:
        noise.wav_bytes()
    assert str(caught.value) == (
        "train_length 5000 m: a WAV of this pass-by would last 3602 s (5000 m at 5 km/h and 1 s before and after; "
        "346 MB): at most 600 s are written; give a train of at most 830 m at this speed for the WAV (the pass-by "
        "level itself needs no WAV)"
    )


def test_a_pass_by_of_too_many_wheels_to_sum_is_refused_before_any_work():
    from wheelrail.core.errors import WheelrailError

    noise = dataclasses.replace(
        _noise(),
        configuration={"run": {"speed_m_s": SPEED}, "train_axles": 2000, "train_length_m": 5000.0},
    )  # 182 s within the WAV's limit, but 4 000 wheels over 5 million samples each
    with pytest.raises(WheelrailError) as caught:
        noise.wav_bytes()
    assert str(caught.value) == (
        "train_axles 2000: a WAV of this pass-by sums 4000 wheels' records of 5.1 million samples each (2e+10 "
        "samples, about 22 min): at most 2e+09 are summed; give at most 197 axles or a shorter train for the WAV "
        "(the pass-by level itself needs no WAV)"
    )
