"""Roughness spectra and lateral coherence (paper section 3.1 Fig. 6, section 3.2 eqs. 15-18 Fig. 9)."""

import math

import numpy as np
import pytest
from scipy.signal import get_window

from wheelrail.core.roughness import (
    RoughnessSet,
    bundled_names,
    lateral_coherence,
    load_roughness,
    roughness_spectrum,
)
from wheelrail.core.roughness.synthesis import (
    BUNDLED_RECIPES,
    LateralCorrelation,
    Peak,
    PowerLaw,
    SpectrumTarget,
    expected_coherence,
    synthesize,
)
from wheelrail.core.spectra.bands import nominal_band_label, third_octave_bands
from wheelrail.core.spectra.narrowband import band_coherence, band_power, narrowband_spectrum, third_octave_spectrum

V = 100 / 3.6  # m/s, the paper's speed


# ----------------------------------------------------------------------------- bands and levels
def test_third_octave_bands_are_exact_base_10():
    centres, lower, upper = third_octave_bands(50.0, 8000.0)
    assert len(centres) == 23
    assert centres[0] == pytest.approx(10**1.7, rel=1e-12)  # nominal 50 Hz
    assert 1000.0 in centres.round(9)
    np.testing.assert_allclose(upper / lower, 10**0.1, rtol=1e-12)  # a third of a decade
    np.testing.assert_allclose(np.sqrt(upper * lower), centres, rtol=1e-12)  # geometric centres
    np.testing.assert_allclose(upper[:-1], lower[1:], rtol=1e-12)  # contiguous
    labels = [nominal_band_label(c) for c in centres]
    assert labels[:4] == ["50", "63", "80", "100"] and labels[-2:] == ["6300", "8000"]
    wavelengths, _, _ = third_octave_bands(0.00315, 0.8)
    assert nominal_band_label(wavelengths[0]) == "0.00315" and nominal_band_label(wavelengths[-1]) == "0.8"


def test_hann_spectrum_conserves_power():
    rng = np.random.default_rng(5)
    x = rng.normal(size=4096)
    f, psd = narrowband_spectrum(x, 1000.0)
    window = get_window("hann", x.size)  # scipy's (periodic) Hann, as narrowband_spectrum uses
    # Sum of PSD * df equals the windowed mean square corrected by the window power (exact identity).
    total = psd.sum() * (f[1] - f[0])
    expected = np.sum((window * x) ** 2) / np.sum(window**2)
    # scipy's periodogram halves DC and Nyquist correctly, so the identity is exact to rounding.
    assert total == pytest.approx(expected, rel=1e-12)


def test_sinusoid_gives_expected_band_and_level():
    n, dx = 8000, 1e-3  # 8 m as the corrugated rail
    wavelength = 8.0 / 144  # 55.6 mm, whole number of cycles: 500 Hz at 100 km/h
    amplitude = 10e-6
    z = amplitude * np.sin(2 * np.pi * np.arange(n) * dx / wavelength + 0.4)
    s = RoughnessSet(heights=z, dx=dx, y=[0.0], kind="rail")
    spectrum = roughness_spectrum(s, speed=V, lines=[0])
    peak = int(np.nanargmax(spectrum.levels_db))
    assert nominal_band_label(spectrum.band_centres[peak]) == "500"
    expected = 20 * math.log10(amplitude / math.sqrt(2) / 1e-6)  # rms in dB re 1 µm: 16.99 dB
    # 0.05 dB: the Hann main lobe (3 bins) lies well inside the band (~33 bins); side lobes are < -31 dB.
    assert spectrum.levels_db[peak] == pytest.approx(expected, abs=0.05)
    others = np.delete(spectrum.levels_db, peak)
    assert np.nanmax(others) < expected - 40  # Hann leakage to other bands is far below
    by_wavelength = roughness_spectrum(s, lines=[0])  # EN 15610 wavelength bands, long to short
    assert by_wavelength.band_centres[0] > by_wavelength.band_centres[-1]
    i = int(np.nanargmax(by_wavelength.levels_db))
    assert by_wavelength.band_centres[i] / BAND_RATIO <= wavelength <= by_wavelength.band_centres[i] * BAND_RATIO
    assert by_wavelength.levels_db[i] == pytest.approx(expected, abs=0.05)  # same reason as above


BAND_RATIO = 10**0.05


def test_band_power_is_nan_without_bins():
    f = np.arange(10.0)
    out = band_power(f, np.ones(10), np.array([2.2, 3.0]), np.array([2.8, 5.0]))
    assert math.isnan(out[0]) and out[1] == pytest.approx(2.0)  # bins 3 and 4, df = 1


# ----------------------------------------------------------------------------- coherence
def test_coherence_of_identical_lines_is_one():
    rng = np.random.default_rng(11)
    line = rng.normal(size=20000)
    _, lower, upper = third_octave_bands(20.0, 400.0)
    gamma2 = band_coherence(line, np.stack([line] * 6), 1000.0, lower, upper, blocks=20)
    finite = gamma2[np.isfinite(gamma2)]
    assert finite.size > 5
    np.testing.assert_allclose(finite, 1.0, rtol=1e-12)  # exact: S_xy = S_xx = S_yy


def test_coherence_of_independent_lines_is_the_estimator_bias():
    rng = np.random.default_rng(12)
    lines = rng.normal(size=(7, 20000))
    blocks, half = 20, 3
    _, lower, upper = third_octave_bands(20.0, 400.0)
    gamma2 = band_coherence(lines[3], np.delete(lines, 3, axis=0), 1000.0, lower, upper, blocks=blocks)
    finite = gamma2[np.isfinite(gamma2)]
    # Independent lines: E[γ²] ~ 1/(B 2M L_eff) <= 1/B (docstring of band_coherence). Every band stays
    # below 3/B (a generous chi-square tail for the 1-bin bands); the median is below the 1/B bound.
    assert np.all(finite < 3 / blocks)
    assert np.median(finite) < 1 / blocks
    # and it is not identically zero: it is an estimate with the expected small positive bias
    assert np.median(finite) > 1 / (blocks * 2 * half * 100)


# ----------------------------------------------------------------------------- generator recovered
TARGET = SpectrumTarget(
    components=(
        PowerLaw(level_db=0.0, wavelength=0.1, slope_db_per_decade=10.0),
        Peak(level_db=10.0, wavelength=0.03, width_decades=0.12),
    )
)
CORRELATION = LateralCorrelation(length=3e-3, wavelength=0.02, exponent=3.0)


@pytest.fixture(scope="module")
def synthetic():
    return synthesize(
        kind="rail",
        n_lines=7,
        lateral_spacing=1e-3,
        dx=1e-3,
        n_samples=40000,
        spectrum=TARGET,
        correlation=CORRELATION,
        seed=7,
    )


def test_generator_spectrum_is_recovered(synthetic):
    spectrum = roughness_spectrum(synthetic, speed=V, frequency_range=(400.0, 8000.0))
    _, lower, upper = third_octave_bands(400.0, 8000.0)
    expected = TARGET.band_levels(lower / V, upper / V)
    # 1.5 dB: from 400 Hz up a band holds >= 130 bins of the 40 m record; the 7 lines are partly
    # correlated, so the level's scatter is ~4.3/sqrt(bins/1.5) < 0.5 dB; 3 sigma ~ 1.5 dB.
    np.testing.assert_allclose(spectrum.levels_db, expected, atol=1.5)


def test_generator_coherence_is_recovered(synthetic):
    centres, gamma2 = lateral_coherence(synthetic, V, half_lines=3, blocks=20, frequency_range=(400.0, 8000.0))
    _, lower, upper = third_octave_bands(400.0, 8000.0)
    expected = expected_coherence(TARGET, CORRELATION, 1e-3, lower / V, upper / V, half_lines=3)
    assert expected.max() > 0.9 and expected.min() < 0.05  # the target spans high to low coherence
    # 0.1 absolute: each band averages B x L >= 20 x 6 block spectra over 6 lines; the estimator's
    # scatter and its positive bias (~1/(2 M B L)) stay well below 0.1.
    np.testing.assert_allclose(gamma2, expected, atol=0.1)
    assert np.all(np.isfinite(gamma2))


def test_generator_is_seeded():
    kwargs = dict(
        kind="wheel",
        n_lines=3,
        lateral_spacing=2e-3,
        dx=1e-3,
        n_samples=256,
        spectrum=TARGET,
        correlation=CORRELATION,
    )
    a = synthesize(seed=1, **kwargs)
    np.testing.assert_array_equal(a.heights, synthesize(seed=1, **kwargs).heights)
    assert not np.array_equal(a.heights, synthesize(seed=2, **kwargs).heights)


# ----------------------------------------------------------------------------- the bundled sets
def _band(spectrum, label):
    labels = [nominal_band_label(c) for c in spectrum.band_centres]
    return spectrum.levels_db[labels.index(label)]


@pytest.fixture(scope="module")
def bundled():
    return {name: load_roughness(name) for name in bundled_names()}


def test_bundled_sets_have_the_paper_grids(bundled):
    assert sorted(bundled) == ["cast-iron-wheel", "corrugated-rail", "sinter-wheel-1", "sinter-wheel-2"]
    rail = bundled["corrugated-rail"]
    assert (rail.kind, rail.n_lines, rail.dx, rail.length) == ("rail", 19, 1e-3, pytest.approx(8.0))
    assert rail.lateral_spacing == pytest.approx(1e-3)
    for name in ("cast-iron-wheel", "sinter-wheel-1", "sinter-wheel-2"):
        wheel = bundled[name]
        assert (wheel.kind, wheel.n_lines, wheel.dx) == ("wheel", 25, 0.5e-3)
        assert wheel.length == pytest.approx(2.9) and wheel.lateral_spacing == pytest.approx(2e-3)
        assert "SYNTHETIC" in wheel.description
    # the recipes re-make the files (float32 storage: relative 6e-8 of the largest height)
    for recipe in BUNDLED_RECIPES[:1]:
        made = recipe.make()
        np.testing.assert_allclose(bundled[recipe.name].heights, made.heights, atol=1e-7 * 1e-4)


def test_corrugated_rail_traits(bundled):
    rail = bundled["corrugated-rail"]
    spectrum = roughness_spectrum(rail, speed=V)
    peak = nominal_band_label(spectrum.band_centres[np.nanargmax(spectrum.levels_db)])
    assert peak == "500"  # paper Fig. 6: distinct peak in the 500 Hz band (55 mm corrugation)
    assert 15 <= _band(spectrum, "500") <= 20  # dB re 1 µm, as Fig. 6
    assert _band(spectrum, "500") - _band(spectrum, "1000") > 20  # distinct, and low at high frequency
    assert _band(spectrum, "100") < _band(spectrum, "500") - 30  # high-passed at 14 cm (200 Hz)
    peak_to_peak = np.ptp(rail.line(0))
    assert 20e-6 < peak_to_peak < 100e-6  # tens of µm peak-to-peak (Fig. 7)
    centres, gamma2 = lateral_coherence(rail, V)
    by_band = dict(zip([nominal_band_label(c) for c in centres], gamma2, strict=True))
    assert min(by_band[b] for b in ("200", "315", "500", "630")) > 0.95  # highly coherent below 1 kHz
    assert by_band["1000"] > 0.7
    assert max(by_band[b] for b in ("2500", "3150", "4000", "5000")) < 0.1  # low above 2 kHz


def test_cast_iron_wheel_traits(bundled):
    wheel = bundled["cast-iron-wheel"]
    by_wavelength = roughness_spectrum(wheel)
    labels = [nominal_band_label(c) for c in by_wavelength.band_centres]
    level = dict(zip(labels, by_wavelength.levels_db, strict=True))
    broad_peak = np.mean([level[b] for b in ("0.063", "0.08", "0.1", "0.125")])  # around 90 mm
    assert 5 < broad_peak < 12  # dB re 1 µm, as Fig. 6 near 300 Hz
    assert broad_peak - max(level[b] for b in ("0.016", "0.0125", "0.01")) > 12  # a peak, not a slope
    assert broad_peak > np.mean([level[b] for b in ("0.5", "0.63")])  # falls again at long λ
    # the 0.8 m band (0.29 cycles/m wide) is narrower than 1 / 2.9 m, the bin spacing of one revolution: n/a
    assert np.isnan(level["0.8"])
    spectrum = roughness_spectrum(wheel, speed=V)
    assert 5 <= _band(spectrum, "315") <= 12
    centres, gamma2 = lateral_coherence(wheel, V)
    by_band = dict(zip([nominal_band_label(c) for c in centres], gamma2, strict=True))
    assert min(by_band[b] for b in ("400", "630", "800", "1000")) > 0.7  # fairly coherent below 1 kHz
    assert max(by_band[b] for b in ("2500", "3150", "4000", "5000")) < 0.1  # low above 2 kHz


@pytest.mark.parametrize("name", ["sinter-wheel-1", "sinter-wheel-2"])
def test_sinter_wheel_traits(bundled, name):
    sinter = roughness_spectrum(bundled[name], speed=V)
    cast_iron = roughness_spectrum(bundled["cast-iron-wheel"], speed=V)
    for band in ("250", "315", "400"):
        assert _band(cast_iron, band) - _band(sinter, band) > 10  # much lower near the cast-iron peak
        assert -13 < _band(sinter, band) < -4  # about -10..-5 dB re 1 µm
    for band in ("5000", "6300", "8000"):
        assert _band(sinter, band) > _band(cast_iron, band) + 3  # but rougher at very short wavelengths
    _, gamma2 = lateral_coherence(bundled[name], V)
    assert np.nanmax(gamma2) < 0.25  # low coherence in the whole frequency range (Fig. 9)


def test_sinter_wheels_differ(bundled):
    a, b = bundled["sinter-wheel-1"], bundled["sinter-wheel-2"]
    assert abs(np.corrcoef(a.line(0), b.line(0))[0, 1]) < 0.1  # different seeds: unrelated profiles


def test_time_signal_spectrum_for_forces():
    # Generic use (later: contact-force spectra in dB re 1 N): a 1 kHz tone of 100 N amplitude sampled
    # at 27.78 kHz (dt = 1 mm / 100 km/h) for 0.5 s.
    fs = 100 / 3.6 / 1e-3
    t = np.arange(int(0.5 * fs)) / fs
    force = 100.0 * np.cos(2 * np.pi * 1000.0 * t)
    centres, levels = third_octave_spectrum(force, fs, (50.0, 8000.0), 1.0)
    assert nominal_band_label(centres[int(np.nanargmax(levels))]) == "1000"
    # 0.05 dB: Hann main lobe (3 bins of 2 Hz) well inside the 230 Hz wide band
    assert np.nanmax(levels) == pytest.approx(20 * math.log10(100 / math.sqrt(2)), abs=0.05)
