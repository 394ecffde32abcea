"""The wheel's radiation efficiency per mode family (wheelrail.core.modal_wheel.radiation) against closed forms."""

import math

import numpy as np
import pytest
import scipy.special as sps

from wheelrail.core.errors import WheelrailError
from wheelrail.core.modal_wheel.radiation import (
    band_radiation_efficiency,
    disc_radiation_efficiency,
    radiated_power,
    wheel_radiation_efficiency,
)
from wheelrail.core.noise.radiation import AIR_DENSITY, SOUND_SPEED, piston_radiation_efficiency

RADIUS = 0.46  # m: a 920 mm wheel


def test_axial_n0_is_the_baffled_piston():
    """Eq. (2) with n = 0 on a full disc is the baffled piston, 1 - J1(2ka)/(ka), 20 Hz-12 kHz; 1e-9: the two are
    the same integral, one by 400-point Gauss quadrature (converged to 1e-12 when doubled)."""
    f = np.geomspace(20, 12000, 25)
    sigma = disc_radiation_efficiency(f, RADIUS, 0)
    assert np.allclose(sigma, piston_radiation_efficiency(f, math.pi * RADIUS**2), rtol=1e-9, atol=0)


@pytest.mark.parametrize("n", [0, 1, 2, 4, 8])
def test_axial_low_frequency_asymptote(n):
    """At k a = 0.05, sigma = 2 (ka)^(2n+2) / ((n+2)^2 (2n+1)!) (the first term of J_n in eq. 2) within 0.1 %:
    the next term is smaller by about (ka)^2 = 0.25 %, times a coefficient below 1/4."""
    ka = 0.05
    f = ka * SOUND_SPEED / (2 * np.pi * RADIUS)
    expected = 2 * ka ** (2 * n + 2) / ((n + 2) ** 2 * math.factorial(2 * n + 1))
    assert disc_radiation_efficiency(f, RADIUS, n) == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize("n", [0, 2, 6])
def test_high_frequency_limit_is_one(n):
    """Far above coincidence every family radiates as a plane wave: sigma within 5 % of 1 where k a >= 8 (n + 1)
    (the disc's edge ripple decays as k a grows; measured 0.4-3.5 % here) and, for the 135 mm band, also
    k b >= 12 (its ends' ripple, measured 0.1-2.6 % at 5-16 kHz)."""
    f = 8 * (n + 1) * SOUND_SPEED / (2 * np.pi * RADIUS) * np.array([1.0, 1.5])
    assert np.allclose(disc_radiation_efficiency(f, RADIUS, n, inner_radius=0.1), 1.0, atol=0.05)
    f_band = np.array([5000.0, 8000.0, 16000.0])
    assert np.allclose(band_radiation_efficiency(f_band, RADIUS, 0.135, n), 1.0, atol=0.05)


def test_axial_critical_frequency_grows_with_n():
    """The frequency where sigma first reaches 0.5 rises with n in step with the coincidence k a ~ n + 1 (the
    circumferential wavelength 2 pi a / n meeting the acoustic one): within 0.6 to 1.6 times (n + 1) c / (2 pi a)
    for n = 1..10, found by bisection from below (sigma rises monotonically up to it)."""
    from scipy.optimize import brentq

    previous = 0.0
    for n in range(1, 11):
        coincidence = (n + 1) * SOUND_SPEED / (2 * np.pi * RADIUS)
        excess = lambda f, n=n: disc_radiation_efficiency(f, RADIUS, n) - 0.5  # noqa: E731
        f_half = brentq(excess, 0.3 * coincidence, 1.6 * coincidence, xtol=1.0)
        assert 0.6 < f_half / coincidence < 1.6
        assert f_half > previous
        previous = f_half


@pytest.mark.parametrize("n", [0, 1, 2, 5])
def test_radial_long_band_is_the_infinite_cylinder(n):
    """Eq. (3) for a band 4 m wide tends to the infinite cylinder's 2 / (pi ka |H_n'(ka)|^2): within 0.6 % at
    1-3 kHz (k b = 73-220; the band's ends add a share of order 1/(k b), measured 0.05-0.5 %)."""
    f = np.array([1000.0, 2000.0, 3000.0])
    k = 2 * np.pi * f / SOUND_SPEED
    exact = 2 / (np.pi * k * RADIUS * np.abs(sps.h1vp(n, k * RADIUS)) ** 2)
    assert np.allclose(band_radiation_efficiency(f, RADIUS, 4.0, n), exact, rtol=6e-3)


def test_wheel_families_and_power():
    """The wheel's families dispatch to eqs. (2)/(3), and W = rho c S sigma <v^2> exactly."""
    f = np.array([500.0, 2000.0])
    axial = wheel_radiation_efficiency(f, 3, "axial", radius=RADIUS, tyre_width=0.135, hub_radius=0.1)
    radial = wheel_radiation_efficiency(f, 3, "radial", radius=RADIUS, tyre_width=0.135)
    assert np.array_equal(axial, disc_radiation_efficiency(f, RADIUS, 3, inner_radius=0.1))
    assert np.array_equal(radial, band_radiation_efficiency(f, RADIUS, 0.135, 3))
    power = radiated_power(np.array([1e-6, 4e-6]), 0.5, axial)
    assert np.allclose(power, AIR_DENSITY * SOUND_SPEED * 0.5 * axial * np.array([1e-6, 4e-6]), rtol=1e-15)


def test_radiation_summary_of_a_named_wheel():
    from wheelrail.core.modal_wheel import named_profile
    from wheelrail.core.modal_wheel.radiation import radiation_summary

    summary = radiation_summary(named_profile("freight_920"), [500.0, 2000.0])
    assert len(summary["axial"]) == 11 and len(summary["radial"]) == 11
    assert np.array_equal(
        summary["axial"][3], disc_radiation_efficiency([500.0, 2000.0], RADIUS, 3, inner_radius=0.095)
    )


@pytest.mark.parametrize(
    "call",
    [
        lambda: disc_radiation_efficiency(-1.0, RADIUS, 0),
        lambda: disc_radiation_efficiency(100.0, RADIUS, 1.5),
        lambda: disc_radiation_efficiency(100.0, RADIUS, 0, inner_radius=RADIUS),
        lambda: band_radiation_efficiency(100.0, float("nan"), 0.1, 0),
        lambda: wheel_radiation_efficiency(100.0, 0, "lateral", radius=RADIUS, tyre_width=0.1),
        lambda: radiated_power(1.0, 0.0, 1.0),
    ],
)
def test_bad_input_is_one_error(call):
    with pytest.raises(WheelrailError):
        call()
