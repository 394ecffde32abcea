"""Hertz spring, Winkler bedding (eqs. 3-6, 12-13) and the roughness prefilters against theory."""

import numpy as np
import pytest

from wheelrail.core.contact import (
    average_roughness,
    hertz_approach,
    hertz_constant,
    hertz_force,
    hertz_stiffness,
    winkler_contact,
    winkler_equivalent_roughness,
)
from wheelrail.core.contact.hertz_law import _hertz_force, _hertz_force_and_stiffness
from wheelrail.core.contact.winkler import _winkler_force, bedding_stiffness, wheel_profile
from wheelrail.core.parameters import ContactParameters

CONTACT = ContactParameters()
C_H = hertz_constant()
A = CONTACT.hertz_radius()


def test_hertz_spring_matches_parameters_and_kernels():
    assert C_H == pytest.approx(CONTACT.hertz_constant, rel=1e-14)  # same formula, round-off only
    delta = CONTACT.hertz_approach()
    assert delta == pytest.approx(77.07e-6, abs=0.01e-6)  # Hertz at the paper's 65 kN, R = 0.39 m
    assert hertz_force(delta, C_H) == pytest.approx(65e3, rel=1e-12)
    assert hertz_approach(65e3, C_H) == pytest.approx(delta, rel=1e-12)
    compression = np.array([-1e-6, 0.0, 20e-6, delta])
    np.testing.assert_array_equal(hertz_force(compression, C_H)[:2], 0.0)  # no tension (eq. 12)
    # derivative vs central difference (step 1e-10 m: truncation error ~1e-10 relative)
    step = 1e-10
    numeric = (hertz_force(compression[2:] + step, C_H) - hertz_force(compression[2:] - step, C_H)) / (2 * step)
    np.testing.assert_allclose(hertz_stiffness(compression[2:], C_H), numeric, rtol=1e-6)
    for value in compression:
        force, stiffness = _hertz_force_and_stiffness(value, C_H)
        assert force == pytest.approx(float(hertz_force(value, C_H)), rel=1e-14)
        assert _hertz_force(value, C_H) == force
        assert stiffness == pytest.approx(float(hertz_stiffness(value, C_H)), rel=1e-14)


@pytest.mark.parametrize("dx, force_tolerance", [(1e-3, 0.02), (0.25e-3, 0.005)])
def test_winkler_reproduces_hertz_for_smooth_surfaces(dx, force_tolerance):
    # Ford & Thompson: with R_m = R/2 (eq. 6) and k = E / (2 (1 - nu^2)) (eq. 5) the continuous bedding
    # gives F = C_H delta^1.5 and contact length 2 sqrt(R delta) = 2a exactly.
    segment = np.zeros(2 * int(round(20e-3 / dx)) + 1)
    delta = np.linspace(40e-6, 150e-6, 400)
    result = winkler_contact(delta, segment, dx)
    # one spring per dx (midpoint rule): the springs at the contact edges make the force err by up to
    # 1.6 % at dx = 1 mm for delta >= 40 um (5.5 springs per half length), 0.4 % at dx = 0.25 mm
    np.testing.assert_allclose(result.force, C_H * delta**1.5, rtol=force_tolerance)
    # the compressed length is a whole (odd) number of springs, so it is within one dx of 2a
    np.testing.assert_array_less(np.abs(result.contact_length - 2 * np.sqrt(CONTACT.radius * delta)), dx + 1e-12)
    # at the static preload the force is within 0.5 % (measured 0.42 % at 1 mm)
    at_preload = winkler_contact(CONTACT.hertz_approach(), segment, dx)
    assert float(at_preload.force) == pytest.approx(65e3, rel=0.005)
    assert float(at_preload.contact_length) == pytest.approx(2 * A, abs=dx)
    # dF/d delta = k dx n_c: the exact slope of the piecewise-linear bedding force
    np.testing.assert_allclose(result.stiffness, bedding_stiffness() * result.contact_length, rtol=1e-12)


def test_winkler_kernel_and_roughness_sign():
    dx = 1e-3
    profile = wheel_profile(41, dx, CONTACT.radius)
    k_dx = bedding_stiffness() * dx
    smooth = np.zeros(41)
    force, stiffness, count, edge = _winkler_force(77e-6, smooth, profile, k_dx)
    assert force == pytest.approx(float(winkler_contact(77e-6, smooth, dx).force), rel=1e-14)
    assert not edge
    # eq. 3: a constant roughness c acts like an extra approach c (positive r pushes the bodies together)
    shifted, *_ = _winkler_force(77e-6 - 5e-6, smooth + 5e-6, profile, k_dx)
    assert shifted == pytest.approx(force, rel=1e-12)
    bump = smooth.copy()
    bump[20] = 10e-6
    assert _winkler_force(77e-6, bump, profile, k_dx)[0] > force


def sine_line(wavelength: float, amplitude: float, dx: float = 1e-3, length: float = 8.0) -> np.ndarray:
    x = np.arange(int(round(length / dx))) * dx
    return amplitude * np.sin(2 * np.pi * x / wavelength)


def amplitude_ratio(filtered: np.ndarray, line: np.ndarray) -> float:
    """Ratio of rms values away from the ends (the end extension does not continue the sine)."""
    inner = slice(50, -50)
    return float(np.std(filtered[inner]) / np.std(line[inner]))


def test_prefilters_pass_long_wavelengths_unchanged():
    # a 1 m wave over 8 m (whole periods, periodic line): the contact length is 0.011 of the wavelength and
    # the averaging transfer function sinc(2a / lambda) = 0.9998; allow 1e-3
    line = sine_line(1.0, 20e-6)
    for filtered in (
        winkler_equivalent_roughness(line, 1e-3, boundary="wrap"),
        average_roughness(line, 1e-3, boundary="wrap"),
    ):
        np.testing.assert_allclose(filtered, line, rtol=0, atol=1e-3 * 20e-6)
    # a constant roughness is an offset of the approach only: r_eq = r up to round-off
    constant = np.full(200, 7e-6)
    np.testing.assert_allclose(winkler_equivalent_roughness(constant, 1e-3), constant, rtol=0, atol=1e-15)


@pytest.mark.parametrize("order", [1, 2])
def test_prefilters_attenuate_the_contact_length_dips(order):
    # eq. 19: wavelengths lambda = 2a / n fit the nominal contact length and are filtered out
    wavelength = 2 * A / order
    line = sine_line(wavelength, 1e-6, length=2.0)
    averaged = average_roughness(line, 1e-3, boundary="nearest")
    winkler = winkler_equivalent_roughness(line, 1e-3, boundary="nearest")
    # the average over exactly 2a of the linear interpolant: a sampled sine at 11 mm has interpolation
    # ripple, measured ratio 5e-5 (n = 1) and 2e-4 (n = 2); allow 1 %
    assert amplitude_ratio(averaged, line) < 0.01
    # the bedding's contact length is ~2a (a whole number of springs), measured ratio 0.3 %; allow 3 %
    assert amplitude_ratio(winkler, line) < 0.03
    # whereas a 55 mm corrugation wave passes mostly (sinc(0.2) = 0.94)
    corrugation = sine_line(0.055, 1e-6, length=2.0)
    assert amplitude_ratio(average_roughness(corrugation, 1e-3), corrugation) > 0.9
    assert amplitude_ratio(winkler_equivalent_roughness(corrugation, 1e-3), corrugation) > 0.9


def test_winkler_prefilter_matches_the_bedding_it_models():
    # r_eq is defined so that a Hertz spring with r_eq carries the preload at the bedding's approach:
    # check position by position with the bedding itself on a rough line
    rng = np.random.default_rng(5)
    line = np.cumsum(rng.normal(size=400)) * 2e-7
    line -= line.mean()
    r_eq = winkler_equivalent_roughness(line, 1e-3, boundary="nearest")
    half = int(np.ceil(3 * A / 1e-3))
    padded = np.pad(line, half, mode="edge")
    profile_line = np.zeros(2 * half + 1)
    # the smooth bedding approach delta_0 at the preload, found with the public winkler_contact
    deltas = np.linspace(76e-6, 78e-6, 20001)
    smooth_approach = deltas[np.searchsorted(winkler_contact(deltas, profile_line, 1e-3).force, 65e3)]
    for i in (0, 57, 200, 399):
        delta = smooth_approach - r_eq[i]
        force = float(winkler_contact(delta, padded[i : i + 2 * half + 1], 1e-3).force)
        # bisection grid above: 0.1 nm in delta, i.e. 1.4e-6 relative in force; allow 1e-5
        assert force == pytest.approx(65e3, rel=1e-5)


def test_prefilter_runs_the_compiled_kernel_on_an_8_m_line():
    # No wall time here (benchmarks/prefilter.py prints it: ~2 ms for 8000 samples): the prefilter must go
    # through the numba kernel (compiled, or loaded from numba's cache), and the 8 m line must equal the same
    # line cut in two overlapping halves: each sample is the exact root of a piecewise-linear equation (Newton
    # from the previous sample's root ends exactly), so nothing is carried along the line.
    from numba.core.registry import CPUDispatcher

    from wheelrail.core.contact import prefilter

    line = sine_line(0.055, 5e-6) + sine_line(0.3, 20e-6)
    whole = winkler_equivalent_roughness(line, 1e-3)
    assert isinstance(prefilter._winkler_equivalent, CPUDispatcher)
    assert prefilter._winkler_equivalent.signatures  # compiled (or loaded from numba's cache), not interpreted
    half, overlap = len(line) // 2, 200  # samples: > 3 a / dx = 17 of the bedding's reach on each side
    first = winkler_equivalent_roughness(line[: half + overlap], 1e-3)
    second = winkler_equivalent_roughness(line[half - overlap :], 1e-3)
    # the same root away from the cut ends: equal to rounding (1e-15 m against heights of 25 um; Newton stops
    # at a step of 1e-13 of the ~0.1 mm approach)
    np.testing.assert_allclose(first[:half], whole[:half], rtol=0, atol=1e-15)
    np.testing.assert_allclose(second[overlap:], whole[half:], rtol=0, atol=1e-15)
    assert average_roughness(line, 1e-3).shape == line.shape
