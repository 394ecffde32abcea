"""Track model (paper section 2.2): FE beam, supports, receptance, moving Green's functions (eq. 2)."""

import numpy as np
import pytest
import scipy.linalg

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import (
    RailParameters,
    SupportParameters,
    TrackNumerics,
    TrackParameters,
)
from wheelrail.core.track import (
    assemble_track,
    moving_from_stationary,
    receptance_peaks,
    stationary_track_response,
    timoshenko_element_matrices,
    track_receptance,
)

TRACK = TrackParameters()
L_S = TRACK.support.sleeper_spacing
# Small numerics keep the suite fast: 30 ms, 4 excitation points per bay, speeds up to 160 km/h.
FAST = TrackNumerics(duration=0.03, positions_per_bay=4, max_speed=160 / 3.6)


@pytest.fixture(scope="module")
def model():
    return assemble_track(TRACK)


@pytest.fixture(scope="module")
def response():
    return stationary_track_response(TRACK, FAST)


def test_element_matches_rayleigh_timoshenko_theory():
    # A simply supported Rayleigh-Timoshenko beam (the paper's UIC60, 3 m, 60 elements): mode n has
    # k = n pi / l and EI k^4 - m w^2 - (rho I + EI m / kGA) k^2 w^2 + (rho I m / kGA) w^4 = 0.
    # Tolerance 0.3 %: cubic elements with >= 10 elements per half wavelength.
    rail = RailParameters()
    n_el, length = 60, 3.0
    Ke, Me = timoshenko_element_matrices(rail, length / n_el)
    n = 2 * (n_el + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    for e in range(n_el):
        s = slice(2 * e, 2 * e + 4)
        K[s, s] += Ke
        M[s, s] += Me
    free = [i for i in range(n) if i not in (0, n - 2)]  # pin w at both ends
    w2 = scipy.linalg.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)], eigvals_only=True)[:6]
    EI, kGA = rail.bending_stiffness, rail.shear_stiffness
    m, rI = rail.mass_per_length, rail.rotary_inertia_per_length
    for mode, computed in enumerate(np.sqrt(w2), start=1):
        k = mode * np.pi / length
        a, b, c = rI * m / kGA, -(m + (rI + EI * m / kGA) * k**2), EI * k**4
        exact = np.sqrt((-b - np.sqrt(b * b - 4 * a * c)) / (2 * a))
        assert computed == pytest.approx(exact, rel=3e-3), mode


def test_supports_give_the_two_bounce_frequencies_of_a_rigid_rail():
    # With a (nearly) rigid rail, the bounce of rail mass on pads and sleepers on ballast is an exact
    # 2-DOF system: masses m' l and N m_SL, springs N k_P and N k_B. The FE model must contain both
    # frequencies. Tolerance 0.2 %: the rail is 1e5 times stiffer than UIC60, not infinitely stiff.
    rail = RailParameters(bending_stiffness=6.4e11, shear_stiffness=2.5e13)
    sup = SupportParameters()
    track = TrackParameters(rail=rail, support=sup, n_bays=8)
    fe = assemble_track(track, elements_per_bay=2)
    w2 = scipy.linalg.eigh(fe.K.toarray(), fe.M.toarray(), eigvals_only=True)
    fe_freqs = np.sqrt(np.abs(w2)) / (2 * np.pi)
    n_sup = track.n_bays + 1
    Mr, Ms = rail.mass_per_length * track.length, n_sup * sup.sleeper_mass
    kp, kb = n_sup * sup.pad_stiffness, n_sup * sup.ballast_stiffness
    K2 = np.array([[kp, -kp], [-kp, kp + kb]])
    exact = np.sqrt(scipy.linalg.eigh(K2, np.diag([Mr, Ms]), eigvals_only=True)) / (2 * np.pi)
    for f in exact:
        assert np.min(np.abs(fe_freqs - f)) / f < 2e-3, f


@pytest.mark.slow
def test_pinned_pinned_and_support_resonances(model):
    # Paper: pinned-pinned resonance at 943 Hz for these parameters; the model's peak within +-3 % of it.
    peaks = receptance_peaks(model)
    assert peaks["pinned_pinned"].frequency_hz == pytest.approx(943.0, rel=0.03)
    # The support resonances of a UIC60 track on these pads and ballast: the sleeper-on-ballast mode
    # in the 80-160 Hz range and the rail-on-pad mode between it and the pinned-pinned resonance.
    assert 80 < peaks["sleeper_on_ballast"].frequency_hz < 160
    assert 1.5 * peaks["sleeper_on_ballast"].frequency_hz < peaks["rail_on_pad"].frequency_hz < 600


def test_midspan_receptance_peaks_at_pinned_pinned_while_above_sleeper_dips(model):
    # Discrete support signature: at 943 Hz the midspan receptance is several times the one above a
    # sleeper (the sleeper is a node of the pinned-pinned mode). Factor 3 is well inside what the
    # model gives (about 10).
    x_s = (TRACK.n_bays // 2) * L_S
    f = np.array([941.0])
    ratio = abs(track_receptance(model, f, x_s + L_S / 2)[0]) / abs(track_receptance(model, f, x_s)[0])
    assert ratio > 3.0


def _band_levels(values, dt, centres):
    t = np.arange(values.shape[-1]) * dt
    out = []
    for fc in centres:
        f = np.linspace(fc * 2 ** (-1 / 6), fc * 2 ** (1 / 6), 40)
        spectrum = np.exp(-2j * np.pi * np.outer(f, t)) @ values * dt
        out.append(10 * np.log10(np.mean(np.abs(spectrum) ** 2)))
    return np.array(out)


def test_slow_moving_green_function_equals_stationary_receptance(model, response):
    # At a walking pace the moving Green's function is the stationary point impulse response, whose
    # Fourier transform is the point receptance solved directly in the frequency domain. Above a
    # sleeper the 30 ms truncation costs < 0.1 dB; Newmark with 5 us steps shifts frequencies by
    # (w dt)^2/12 (0.5 % at 8 kHz). Tolerance 0.3 dB per third-octave band from 63 Hz to 5 kHz.
    g = moving_from_stationary(response, 0.05 / 3.6)
    x_e = (TRACK.n_bays // 2) * L_S
    centres = np.array([63, 125, 250, 500, 1000, 2000, 4000, 5000.0])
    ours = _band_levels(g.values[0], g.time_step, centres)
    ref = []
    for fc in centres:
        f = np.linspace(fc * 2 ** (-1 / 6), fc * 2 ** (1 / 6), 40)
        ref.append(10 * np.log10(np.mean(np.abs(track_receptance(model, f, x_e)) ** 2)))
    np.testing.assert_allclose(ours, ref, atol=0.3)


def test_moving_green_functions_show_pinned_pinned_at_midspan(response):
    # Paper Fig. 4: excitation at midspan gives extra oscillation at the pinned-pinned frequency.
    # Energy of g in 850-1050 Hz relative to 50 Hz-8 kHz is ~9 dB higher at midspan than above a
    # sleeper at 50-150 km/h (default numerics); require > 5 dB with the short test numerics.
    for kmh in (50, 100, 150):
        g = moving_from_stationary(response, kmh / 3.6)
        f = np.fft.rfftfreq(g.values.shape[1], g.time_step)
        band, ref = (f > 850) & (f < 1050), (f > 50) & (f < 8000)
        share = []
        for p in (0, len(g.excitation_positions) // 2):  # above the sleeper, midspan
            power = np.abs(np.fft.rfft(g.values[p])) ** 2
            share.append(power[band].sum() / power[ref].sum())
        assert 10 * np.log10(share[1] / share[0]) > 5.0, kmh


def test_green_functions_decay_and_truncation_error_is_small(response):
    # Above a sleeper the response decays to < 1 % of its peak within 10 ms and the static moving
    # compliance (integral of g) changes by < 0.2 % between 20 and 30 ms truncation, so the
    # truncation hardly matters for the quasi-static load (benchmarks/track_green.py shows the
    # band-level error of the default 50 ms truncation: <= 0.27 dB in the 1 kHz band at midspan).
    # The decay is asserted below 8 kHz (the force spectra's range): above 15 kHz, waves too short for the
    # 16-element bays stay trapped in the refined bays around the load (TrackNumerics.refined_elements_per_bay)
    # and ring for longer, 90 % of the late response's energy (measured; 0.64 % of the peak below 8 kHz
    # against 0.63 % with 16 elements everywhere).
    g = moving_from_stationary(response, 100 / 3.6)
    values = g.values[0]
    spectrum = np.fft.rfft(values, 2 * len(values))
    spectrum[np.fft.rfftfreq(2 * len(values), g.time_step) > 8000.0] = 0.0
    below_8k = np.fft.irfft(spectrum)[: len(values)]
    k10 = int(round(0.010 / g.time_step))
    assert np.abs(below_8k[k10:]).max() < 0.01 * np.abs(below_8k).max()
    k20 = int(round(0.020 / g.time_step))
    i20, i30 = np.trapezoid(values[: k20 + 1], dx=g.time_step), np.trapezoid(values, dx=g.time_step)
    assert abs(i20 / i30 - 1) < 2e-3


def test_weights_conserve_the_integral_and_make_the_loop_implicit(response):
    # First-order-hold weights integrate g exactly: their sum is the trapezoid integral of g (to
    # round-off), and w_0 > 0 (the current force moves the rail now).
    g = moving_from_stationary(response, 100 / 3.6)
    for dt in (3.6e-5, 1.8e-5, 7.7e-5):
        w = g.weights(dt)
        np.testing.assert_allclose(w.sum(axis=1), np.trapezoid(g.values, dx=g.time_step, axis=1), rtol=1e-9)
        assert np.all(w[:, 0] > 0)


def test_interpolation_between_excitation_positions(response):
    g = moving_from_stationary(response, 100 / 3.6)
    np.testing.assert_allclose(g.at(g.excitation_positions[1]), g.values[1])
    np.testing.assert_allclose(g.at(L_S + g.excitation_positions[1]), g.values[1])  # periodic in L_S
    mid = 0.5 * (g.excitation_positions[1] + g.excitation_positions[2])
    np.testing.assert_allclose(g.at(mid), 0.5 * (g.values[1] + g.values[2]))


def test_speed_limits(response):
    with pytest.raises(WheelrailError, match="exceeds"):
        moving_from_stationary(response, 200 / 3.6)
    from wheelrail.core.track import moving_green_functions

    for bad in (0.0, -5.0, float("nan")):
        with pytest.raises(WheelrailError, match="speed"):
            moving_green_functions(bad)


def test_track_too_short_for_the_wedge():
    with pytest.raises(WheelrailError, match="too short"):
        stationary_track_response(TrackParameters(n_bays=4), TrackNumerics(duration=0.2), use_cache=False)


def test_rows_between_positions_keep_the_sleeper_bay_harmonics():
    # g(x0, t) has kinks in x0 where the load or the moving receiver x0 + v t sits on a support, so the
    # quasi-static moving compliance s(x0) = sum_m w_m(x0) carries bay harmonics k (at k v / L_S) far beyond
    # what P positions sample. Rows read between 16 stored positions (track.bay_rows) against 64 positions
    # computed directly on the same mesh: k = 1..4 within 10 % (measured <= 2 %; <= 9.5 % on the 8-bay model
    # before it was made mirror-symmetric, 4 bays before the central one and 3 after), k = 5..6 within 20 %
    # (measured 3 %; 12 and 16 % then), k = 9..15 within a factor of 2 (measured 0.93-1.91): a band-limited
    # (trigonometric) interpolant of the 16 positions has none above k = 8.
    track = TrackParameters(n_bays=8)  # a 9-bay model (stationary.model_bays)
    base = dict(duration=0.02, max_speed=110 / 3.6, refined_elements_per_bay=64)
    direct = stationary_track_response(track, TrackNumerics(positions_per_bay=64, **base))
    coarse = stationary_track_response(track, TrackNumerics(positions_per_bay=16, **base))
    speed = 100 / 3.6
    dt = 1e-3 / speed
    w_direct = moving_from_stationary(direct, speed, 1).weights(dt)
    w_between = moving_from_stationary(coarse, speed, 4).weights(dt)
    assert w_between.shape == w_direct.shape

    def harmonics(w):
        return np.abs(np.fft.rfft(w.sum(axis=1))) / len(w) * 2

    ref, ours = harmonics(w_direct), harmonics(w_between)
    np.testing.assert_allclose(ours[1:5], ref[1:5], rtol=0.10)
    np.testing.assert_allclose(ours[5:7], ref[5:7], rtol=0.20)
    assert np.all((ours[9:16] > 0.5 * ref[9:16]) & (ours[9:16] < 2.0 * ref[9:16])), (ours[9:16], ref[9:16])
    # Two loads a spacing apart do not make the near field of one load between them: read at the same rail
    # point from the start, a mid row's w_0 came out 80 % low and s(x0) dipped between positions, a tone at
    # k = 16 (and on the default track a 200 N force at v P / L_S on a smooth rail). Read at their own offset
    # for the first 10-20 crossing times of the shear wave (track.moving.SHEAR_CROSSINGS), w_0 is within
    # 10 % (measured 2.6 %) and the k = 16 tone within a factor 3 of the direct one (1.06 against 0.42 pm/N; the
    # direct one is the short track's ends': 1.04 pm/N on the 8-bay model, 0.45 and 0.42 on 11 and 13 bays, while
    # the rows' stays at 0.98-1.09; read without the near field, the default track's force had a 200 N tone there,
    # 2.7 N with it).
    np.testing.assert_allclose(w_between[2::4, 0], w_direct[2::4, 0], rtol=0.10)
    assert ours[16] < 3.0 * ref[16]
