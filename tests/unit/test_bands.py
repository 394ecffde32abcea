"""Wavelength and frequency bands and the level mapping between them (core/spectra/bands.py)."""

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.spectra.bands import Bands, frequency_bands, map_levels, wavelength_bands


def test_cnossos_wavelength_bands():
    bands = wavelength_bands()
    assert bands.centres.size == 35 and bands.labels()[0] == "2000" and bands.labels()[-1] == "0.8"
    assert np.all(np.diff(bands.centres) < 0)  # long first, as EN 15610 and CNOSSOS list them
    k_lo, k_hi = bands.wavenumber_edges()
    np.testing.assert_allclose(k_hi / k_lo, 10**0.1)  # one tenth of a decade each
    assert wavelength_bands(0.8, 0.00315).centres.size == 25  # the EN 15610 range of wheelrail roughness


def test_aligned_bands_map_unchanged_both_ways():
    # at v = 10 m/s a wavelength band of centre 10^(-n/10) m is exactly the frequency band 10^((10-n)/10) Hz
    lam = wavelength_bands(0.2, 0.002)
    freq = frequency_bands(10.0, (50.0, 5000.0))
    levels = np.linspace(3.0, -20.0, lam.centres.size)
    np.testing.assert_allclose(map_levels(levels, lam, freq), levels, atol=1e-9)  # long wavelength = low f
    np.testing.assert_allclose(map_levels(map_levels(levels, lam, freq), freq, lam), levels, atol=1e-9)


def test_straddling_bands_share_energy_proportionally():
    lam = wavelength_bands(0.2, 0.002)
    freq = frequency_bands(10.0 * 10**0.03, (63.0, 4000.0))  # shifted by 0.3 of a band
    levels = np.zeros(lam.centres.size)
    levels[10] = 10.0  # one band 10 dB up
    mapped = map_levels(levels, lam, freq)
    power = 10 ** (mapped / 10) - 1.0
    assert np.count_nonzero(power > 1e-9) == 2  # it lands in the two frequency bands it overlaps
    np.testing.assert_allclose(sorted(power[power > 1e-9]), [0.3 * 9, 0.7 * 9], rtol=1e-9)
    # white (flat) spectra and 0 dB filters stay flat; energy is conserved
    np.testing.assert_allclose(map_levels(np.full(lam.centres.size, -3.0), lam, freq), -3.0, atol=1e-9)


def test_uncovered_and_nan_bands_are_nan():
    lam = wavelength_bands(0.1, 0.01)
    freq = frequency_bands(27.0, (50.0, 8000.0))
    mapped = map_levels(np.zeros(lam.centres.size), lam, freq)
    k_lo, k_hi = freq.wavenumber_edges()
    inside = (k_lo >= 1 / (0.1 * 10**0.05)) & (k_hi <= 1 / (0.01 / 10**0.05))
    assert np.all(np.isfinite(mapped[inside])) and np.all(np.isnan(mapped[~inside]))
    levels = np.zeros(lam.centres.size)
    levels[4] = np.nan
    assert np.isnan(map_levels(levels, lam, freq)).sum() > np.isnan(mapped).sum()


def test_bad_bands():
    with pytest.raises(WheelrailError, match="speed"):
        frequency_bands(None).wavenumber_edges()
    with pytest.raises(WheelrailError, match="axis"):
        Bands(centres=np.ones(2), axis="time")
    with pytest.raises(WheelrailError, match="levels"):
        map_levels([1.0, 2.0], wavelength_bands(), frequency_bands(10.0))
    with pytest.raises(WheelrailError, match="wavelength range"):
        wavelength_bands(0.001, 0.1)
