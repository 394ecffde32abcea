"""The pass-by WAV: a standard sample rate, and its own L_pAeq over T_p is the stated pass-by level, whatever
the seed of the random stretches of the record each wheel gets."""

from __future__ import annotations

import io

import numpy as np
import pytest
from scipy.io import wavfile

from wheelrail.core.noise.levels import noise_bands
from wheelrail.core.noise.run_noise import WAV_RATE, RunNoise, laeq_of_pressure

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
