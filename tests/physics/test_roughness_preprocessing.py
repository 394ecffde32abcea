"""Preprocessing of roughness data (paper section 3.1, EN 15610): detrend, spikes, mean, high-pass, grids."""

import math

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness import (
    RoughnessSet,
    detrend_linear,
    highpass,
    line_along_track,
    lines_along_track,
    preprocess,
    remove_spikes,
    resample_lateral,
    resample_longitudinal,
    to_model_grid,
)

DX = 1e-3


def _line(kind, z, dx=DX):
    return RoughnessSet(heights=np.atleast_2d(z), dx=dx, y=[0.0], kind=kind)


def _sinusoid(n, wavelength, amplitude=5e-6, dx=DX, phase=0.3):
    x = np.arange(n) * dx
    return amplitude * np.sin(2 * np.pi * x / wavelength + phase)


@pytest.mark.parametrize("kind", ["rail", "wheel"])
def test_ramp_is_removed(kind):
    n = 4000
    # 50 whole cycles so that the wheel data is periodic without the ramp.
    signal = _sinusoid(n, n * DX / 50)
    ramp = 2e-6 + 40e-6 * np.arange(n) / n  # 40 µm drift over the line
    out = detrend_linear(_line(kind, signal + ramp)).heights[0]
    residual = out - signal
    # What is left of the ramp is at most a constant plus a small line: least squares (rail) projects a
    # little of the sinusoid onto the ramp (~ amplitude/(pi*cycles) = 0.03 µm); the seam estimate (wheel)
    # errs by the sinusoid's change across the seam window. 0.3 µm is 1 % of the 40 µm drift.
    slope = np.polyfit(np.arange(n) * DX, residual, 1)[0] * n * DX
    assert abs(slope) < 0.3e-6


def test_spike_is_removed_and_clean_data_untouched():
    rng = np.random.default_rng(3)
    n = 3000
    base = _sinusoid(n, 0.055, 10e-6) + rng.normal(scale=0.05e-6, size=n)
    clean = _line("rail", base)
    # Clean data (a 55 mm corrugation and a little noise) has no spike: nothing may change.
    np.testing.assert_array_equal(remove_spikes(clean).heights, clean.heights)
    spiked = base.copy()
    spiked[1234] += 30e-6  # a 30 µm grain of dirt, one sample wide
    spiked[2000:2002] -= 20e-6  # a two-sample dropout
    out = remove_spikes(_line("rail", spiked)).heights[0]
    # After removal the profile is within 0.5 µm of the clean one: the replaced samples are linear
    # interpolation across 3-4 mm of a 10 µm, 55 mm corrugation (curvature error <= A k^2 d^2/8 ~ 0.3 µm).
    assert np.max(np.abs(out - base)) < 0.5e-6
    assert "spikes removed" in remove_spikes(_line("rail", spiked)).description


def test_spike_on_wheel_seam_is_removed_periodically():
    n = 2000
    base = _sinusoid(n, n * DX / 20, 5e-6)
    spiked = base.copy()
    spiked[0] += 25e-6
    out = remove_spikes(_line("wheel", spiked)).heights[0]
    assert np.max(np.abs(out - base)) < 0.2e-6  # interpolation across the seam of a 100 mm sinusoid


@pytest.mark.parametrize("kind", ["rail", "wheel"])
def test_highpass_is_minus_3db_at_cutoff(kind):
    n = 8400  # 8.4 m: a whole number of cycles of the test wavelengths
    cutoff = 0.14
    for wavelength, expected_db in ((0.14, -3.0103), (0.42, None), (0.035, 0.0)):
        z = _sinusoid(n, wavelength)
        out = highpass(_line(kind, z), cutoff).heights[0]
        middle = slice(n // 4, 3 * n // 4)  # away from the filtfilt edge transients (rail)
        gain_db = 20 * math.log10(np.std(out[middle]) / np.std(z[middle]))
        if expected_db is None:
            # three times the cut-off wavelength: 4th order forward-backward, -43 dB nominal.
            assert gain_db < -35
        else:
            # 0.05 dB: the gain formula is exact for the DFT (wheel); sosfiltfilt matches |H|^2 exactly on
            # a long steady-state sinusoid.
            assert gain_db == pytest.approx(expected_db, abs=0.05)


def test_highpass_rejects_bad_cutoff():
    with pytest.raises(WheelrailError, match="cut-off wavelength must exceed 2 dx"):
        highpass(_line("rail", np.zeros(100)), 1e-3)


def test_preprocess_chain_gives_zero_mean():
    rng = np.random.default_rng(0)
    z = rng.normal(scale=1e-6, size=(3, 1000)) + 5e-6
    s = RoughnessSet(heights=z, dx=DX, y=[-1e-3, 0, 1e-3], kind="rail")
    out = preprocess(s, highpass_wavelength=0.14)
    assert np.max(np.abs(out.heights.mean(axis=1))) < 1e-18  # mean removal is the last step: rounding only


def test_longitudinal_interpolation_wheel_keeps_circumference():
    n = 5800  # 2.9 m at 0.5 mm
    z = _sinusoid(n, 2.9 / 29, dx=0.5e-3)
    s = _line("wheel", z, dx=0.5e-3)
    out = resample_longitudinal(s, 1e-3)
    assert out.n_samples == 2900 and out.dx == pytest.approx(1e-3, rel=1e-12)
    # sample i of the new grid is sample 2i of the old one: linear interpolation is exact there.
    np.testing.assert_allclose(out.heights[0], z[::2], atol=1e-18)


@pytest.mark.parametrize("kind", ["rail", "wheel"])
def test_a_tone_above_the_grids_nyquist_does_not_appear_at_its_alias(kind):
    # 0.5 mm data on a 1 mm grid (a bundled wheel set at the default element): a 1.25 mm tone lies above the
    # grid's Nyquist wavenumber 1 / (2 mm) and, sample-picked, would read as a tone of its full amplitude at
    # 1 / (1 / 1 mm - 1 / 1.25 mm) = 5 mm; low-passed first it is gone, and a 20 mm tone is kept to 1e-4 (2 m: whole
    # periods of both, for the wheel's wrap; the rail's ends, reflected, left out)
    x = np.arange(4000) * 0.5e-3
    short, long = np.sin(2 * np.pi * x / 1.25e-3), np.sin(2 * np.pi * x / 20e-3)
    s = RoughnessSet(heights=5e-6 * np.stack([short, long]), dx=0.5e-3, y=[0.0, 1e-3], kind=kind)
    out = resample_longitudinal(s, 1e-3)
    inner = slice(100, -100)
    assert out.n_samples == 2000
    assert np.max(np.abs(out.heights[0, inner])) < 1e-3 * 5e-6  # at most -60 dB of the tone at its alias
    np.testing.assert_allclose(out.heights[1, inner], 5e-6 * long[::2][inner], rtol=0, atol=1e-4 * 5e-6)
    assert "low-passed" in out.description
    # onto a finer grid nothing is filtered: linear interpolation, the set's own samples kept
    finer = resample_longitudinal(s, 0.25e-3)
    np.testing.assert_array_equal(finer.heights[:, ::2][:, : s.n_samples], s.heights)
    assert "low-passed" not in finer.description


def test_lateral_interpolation_two_to_one_mm():
    y = np.arange(-6, 7, 2) * 1e-3
    z = np.outer(y, np.ones(10)) * 1e-3  # heights linear in y: reproduced exactly by linear interpolation
    s = RoughnessSet(heights=z, dx=DX, y=y, kind="wheel")
    out = resample_lateral(s, 1e-3)
    assert out.n_lines == 13
    np.testing.assert_allclose(out.y, np.arange(-6, 7) * 1e-3, atol=1e-15)
    np.testing.assert_allclose(out.heights[:, 0], out.y * 1e-3, atol=1e-15)
    grid = to_model_grid(s, 1e-3, 1e-3)
    assert grid.n_lines == 13 and grid.dx == pytest.approx(1e-3)


def test_wheel_line_repeats_around_circumference():
    n = 1000
    z = _sinusoid(n, n * DX / 7)
    s = RoughnessSet(heights=np.stack([z, 2 * z]), dx=DX, y=[0.0, 2e-3], kind="wheel")
    long = line_along_track(s, 0, 3.5, DX)  # 3.5 circumferences
    assert long.shape == (3501,)
    np.testing.assert_allclose(long[1000:2000], z, atol=1e-18)  # exactly periodic
    both = lines_along_track(s, [0, 1], 2.0)
    np.testing.assert_allclose(both[1], 2 * both[0], atol=1e-18)


def test_rail_run_longer_than_data_is_an_error():
    s = _line("rail", np.zeros(1001))
    assert line_along_track(s, 0, 1.0).shape == (1001,)
    with pytest.raises(WheelrailError, match="exceeds the rail roughness data"):
        line_along_track(s, 0, 1.5)


@pytest.mark.parametrize("name", ["corrugated-rail", "cast-iron-wheel", "sinter-wheel-1", "sinter-wheel-2"])
def test_preprocessing_leaves_clean_bundled_data_nearly_unchanged(name):
    from wheelrail.core.roughness import load_roughness

    s = load_roughness(name)  # synthetic: no drift, no spikes, zero mean
    np.testing.assert_array_equal(remove_spikes(s).heights, s.heights)  # no false spike detections
    out = preprocess(s)
    step = np.std(np.diff(s.heights, axis=1))
    # Detrending drift-free data may only tilt a line by about one sample-to-sample step (wheels: seam
    # extrapolation error; rail: least-squares projection of the long waves); 4 steps is the bound.
    assert np.max(np.abs(out.heights - s.heights)) < 4 * step
