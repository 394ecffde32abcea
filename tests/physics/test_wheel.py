"""Wheel model (paper section 2.1): receptance, Green's function g_W (eq. 1), discrete form."""

import numpy as np
import pytest
from scipy.signal import StateSpace, lsim

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import WheelParameters
from wheelrail.core.wheel import (
    _wheel_state_space,
    wheel_discrete_system,
    wheel_green_function,
    wheel_receptance,
    wheel_static_compliance,
)

WHEEL = WheelParameters()


def test_green_function_is_inverse_fourier_transform_of_receptance():
    # The FFT of g_W (sampled at 5 us over 4 s, long enough for the 7 Hz suspension mode to die out to
    # < 1e-6) equals the receptance. The impulse gives m_W the velocity 1/m_W, a kink of g at t = 0:
    # the Euler-Maclaurin term dt^2/12 g'(0) is added to the sum. Tolerance 1e-3: the remaining
    # error is O((2 pi f dt)^2 / 12), 1e-4 at 2 kHz.
    dt = 5e-6
    t = np.arange(int(4.0 / dt)) * dt
    g = wheel_green_function(WHEEL, t)
    freqs = np.array([10.0, 50.0, 200.0, 322.0, 500.0, 1000.0, 2000.0])
    dft = np.array([np.sum(g * np.exp(-2j * np.pi * f * t)) * dt for f in freqs])
    dft += dt**2 / 12 / WHEEL.contact_mass
    alpha = wheel_receptance(WHEEL, freqs)
    np.testing.assert_allclose(dft, alpha, rtol=1e-3)


def test_main_antiresonance_in_few_hundred_hz():
    # Paper: k_W and c_W were chosen in relation to the main anti-resonance "at around 400 Hz"; for
    # the 2-DOF model it lies at sqrt((k_S + k_W) / M_W) / 2 pi = 320 Hz. Find the minimum of |alpha|.
    f = np.arange(50.0, 2000.0, 0.5)
    f_anti = f[np.argmin(np.abs(wheel_receptance(WHEEL, f)))]
    expected = np.sqrt((WHEEL.suspension_stiffness + WHEEL.wheel_stiffness) / WHEEL.unsprung_mass) / (2 * np.pi)
    assert 200.0 < f_anti < 500.0
    # damping shifts the minimum of |alpha| slightly; 2 % covers it
    assert f_anti == pytest.approx(expected, rel=0.02)


def test_static_limits():
    # At 0 Hz the receptance is the series compliance 1/k_S + 1/k_W (exact), and the integral of
    # g_W over time is the same (2 s covers the suspension mode to < 1e-5; 0.1 % tolerance).
    assert wheel_receptance(WHEEL, [0.0])[0].real == pytest.approx(wheel_static_compliance(WHEEL), rel=1e-12)
    t = np.linspace(0, 3.0, 600001)
    assert np.trapezoid(wheel_green_function(WHEEL, t), t) == pytest.approx(wheel_static_compliance(WHEEL), rel=1e-3)


def test_discrete_form_is_exact_for_piecewise_linear_force():
    # The first-order-hold discretisation is exact for a force linear between samples: compare with
    # scipy.signal.lsim (interp=True is the same hold). Tolerance 1e-9 relative: round-off only.
    dt = 3.6e-5
    n = 3000
    t = np.arange(n) * dt
    force = np.sin(2 * np.pi * 900 * t) * t / t[-1] + 50.0 * t
    Phi, G0, G1 = wheel_discrete_system(WHEEL, dt)
    state = np.zeros(4)
    out = [0.0]
    for k in range(n - 1):
        state = Phi @ state + G0 * force[k] + G1 * force[k + 1]
        out.append(state[1])
    A, B = _wheel_state_space(WHEEL)
    system = StateSpace(A, B[:, None], np.array([[0.0, 1.0, 0.0, 0.0]]), np.zeros((1, 1)))
    _, ref, _ = lsim(system, force, t, interp=True)
    np.testing.assert_allclose(out, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def test_bad_input():
    with pytest.raises(WheelrailError, match="time_step"):
        wheel_discrete_system(WHEEL, 0.0)
    with pytest.raises(WheelrailError, match="times"):
        wheel_green_function(WHEEL, [-1.0])
    with pytest.raises(WheelrailError, match="frequencies"):
        wheel_receptance(WHEEL, [np.nan])
