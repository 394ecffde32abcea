"""The rail's radiation in the wavenumber domain for a decaying field: against the closed-form
spectrum of an exponentially decaying field, and its effect on the chain against the independent review's figures."""

import numpy as np
import pytest
from scipy.integrate import quad

from wheelrail.core.noise.radiation import SOUND_SPEED, decaying_rail_radiation, rail_radiation_efficiency
from wheelrail.core.noise.twins import NoiseNumerics, track_noise_model
from wheelrail.core.parameters import ModelParameters

DX = 0.0375  # m: the FE track's node spacing (16 elements per 0.6 m bay)
X = np.arange(-2000, 2001) * DX  # 150 m: the field has decayed by > 100 dB at the ends


@pytest.mark.parametrize(("frequency", "beta"), [(50.0, 1.27), (100.0, 1.27), (250.0, 0.6), (1000.0, 0.1)])
def test_exponential_field_against_its_closed_form_spectrum(frequency, beta):
    """v = exp(-beta |x|) has V(k_x) = 2 beta / (beta^2 + k_x^2): the wavenumber integral by quadrature of the
    closed form within 0.1 % (the FFT's k_x step, pi / 300 rad/m; measured <= 0.05 %)."""
    k = 2 * np.pi * frequency / SOUND_SPEED

    def integrand(kx):
        kr = np.sqrt(k * k - kx * kx)
        return (2 * beta / (beta**2 + kx**2)) ** 2 * k / kr * rail_radiation_efficiency(SOUND_SPEED * kr / (2 * np.pi))

    edge = k * (1 - 1e-12)
    exact = quad(integrand, -edge, edge, limit=400)[0] / (2 * np.pi)
    got = decaying_rail_radiation(np.exp(-beta * np.abs(X)), DX, frequency)
    assert got == pytest.approx(exact, rel=1e-3)


def test_slowly_decaying_field_is_the_2d_ratio():
    """A field decaying over many wavelengths (beta = 0.05 /m at 3 kHz, k = 55 rad/m) radiates as the 2D ratio
    on its whole length (Parseval): within 0.01 dB."""
    v = np.exp(-0.05 * np.abs(X))
    two_d = rail_radiation_efficiency(3000.0) * np.sum(np.abs(v) ** 2) * DX
    assert 10 * np.log10(decaying_rail_radiation(v, DX, 3000.0) / two_d) == pytest.approx(0.0, abs=0.01)


def test_chain_correction_matches_the_independent_review():
    """The paper's track: the 2D ratio on the whole field overstated the rail's power by 4.3 dB at 50 Hz, 1.7 at
    100 Hz, 0.4 at 250 Hz (an independent review of the chain); the wavenumber-domain radiation takes
    it off: within 0.3 dB of those figures (measured 0.03 dB on this small track), and within 0.6 dB of the 2D
    ratio from 800 Hz up (the supersonic share's k / k_r; measured 0.46 dB at most)."""
    model = track_noise_model(ModelParameters(), NoiseNumerics(track_bays=60, elements_per_bay=8, points_per_band=2))
    correction = model.rail_decay_correction_db
    np.testing.assert_allclose(correction[[0, 3, 7]], [-4.3, -1.7, -0.4], atol=0.3)
    assert np.all(np.abs(correction[12:]) < 0.6)
