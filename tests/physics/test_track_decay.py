"""Decay rates of the noise model's FE track against an exact infinite periodic track, for tracks held out of
the model's tuning; the decay rate against EN ISO 3095:2013's lower limit."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from wheelrail.core.noise.decay import decay_against_limit, vertical_decay_limit
from wheelrail.core.noise.twins import NoiseNumerics, band_frequencies, track_decay_rates
from wheelrail.core.parameters import RailParameters, SupportParameters, TrackParameters


def _beam_matrix(rail, w):
    """d/dx (w, theta, M, Q) = A (w, theta, M, Q) of the Rayleigh-Timoshenko beam at angular frequency w:
    w' = theta + Q / kGA, theta' = M / EI, M' = -Q - rho I w^2 theta, Q' = -m' w^2 w (the rail's loss factor on
    EI and kGA, hysteretic)."""
    damped = 1 + 1j * rail.loss_factor
    ei, kga = rail.bending_stiffness * damped, rail.shear_stiffness * damped
    return np.array(
        [
            [0, 1, 0, 1 / kga],
            [0, 0, 1 / ei, 0],
            [0, -rail.rotary_inertia_per_length * w**2, 0, -1],
            [-rail.mass_per_length * w**2, 0, 0, 0],
        ],
        dtype=complex,
    )


def exact_periodic_transfer(track: TrackParameters, frequency: float, offsets: np.ndarray) -> np.ndarray:
    """Rail displacement of the infinite periodic track per unit force at midspan (x = L/2), at x = L/2 + offsets
    (offsets >= 0, m), by Floquet waves: the transfer matrix of one bay (beam, then the support's force
    Q += K_S(w) w), its two waves decaying to the right and two to the left, matched across the loaded bay (the
    force makes Q jump by -F). K_S = k_P (k_B - m_S w^2) / (k_P + k_B - m_S w^2) with k = stiffness + i w damping.
    Independent of the FE model: no elements, no finite length. Point supports only."""
    sup, rail = track.support, track.rail
    w = 2 * np.pi * frequency
    L = sup.sleeper_spacing
    kp = sup.pad_stiffness + 1j * w * sup.pad_damping
    kb = sup.ballast_stiffness + 1j * w * sup.ballast_damping - sup.sleeper_mass * w**2
    support = np.eye(4, dtype=complex)
    support[3, 0] = kp * kb / (kp + kb)
    A = _beam_matrix(rail, w)
    half = expm(A * L / 2)
    cell = support @ half @ half
    values, vectors = np.linalg.eig(cell)
    order = np.argsort(np.abs(values))
    right, left = vectors[:, order[:2]], vectors[:, order[2:]]
    force = np.array([0, 0, 0, -1.0], dtype=complex)
    # unknowns a (right waves at the bay's end, just past its support) and b (left waves at its start)
    system = np.hstack([right, -support @ half @ half @ left])
    a_b = np.linalg.solve(system, support @ half @ force)
    a, b = a_b[:2], a_b[2:]
    start = left @ b
    after_load = half @ start + force  # the state just past the force at L/2
    lam = values[order[:2]]
    offsets = np.asarray(offsets, dtype=float)
    beyond = offsets >= L / 2 - 1e-9 * L
    bay = np.where(beyond, np.floor((offsets - L / 2) / L + 1e-9), 0).astype(int)  # whole bays past the loaded one
    # the state just past the support starting each bay: after the force within the loaded bay, then the waves
    states = np.where(beyond, right @ (a[:, None] * lam[:, None] ** bay), after_load[:, None])
    within = np.where(beyond, offsets - L / 2 - bay * L, offsets)
    out = np.empty(len(offsets), dtype=complex)
    for dist in np.unique(np.round(within, 12)):
        here = np.abs(within - dist) < 1e-9
        out[here] = (expm(A * dist) @ states[:, here])[0]
    return out


def exact_decay_rates(track: TrackParameters, numerics: NoiseNumerics) -> np.ndarray:
    """EN 15461's formula on the exact periodic track, with the noise model's grid and band sampling."""
    dx = track.support.sleeper_spacing / numerics.elements_per_bay
    offsets = np.arange(0, numerics.decay_length - 1e-9, dx)
    freqs = band_frequencies(numerics.points_per_band)
    power = np.zeros((freqs.shape[0], len(offsets)))
    for (b, _), f in np.ndenumerate(freqs):
        power[b] += np.abs(exact_periodic_transfer(track, f, offsets)) ** 2
    ratio = power / power[:, :1]
    return 4.343 / (dx * (ratio.sum(axis=1) - 0.5 * (ratio[:, 0] + ratio[:, -1])))


def test_exact_periodic_model_matches_the_fe_receptance_of_a_long_track():
    # The exact model against the FE track (240 bays, 16 elements per bay) along the rail, 200 Hz: within 0.1 %
    # (measured 0.03 %: both are the same beam; the FE's error grows as the wavelength shrinks).
    from wheelrail.core.track import assemble_track, track_receptance

    track = TrackParameters(n_bays=240)
    spacing = track.support.sleeper_spacing
    model = assemble_track(track, 16)
    offsets = np.array([0.0, 0.1, 0.3, spacing, 1.0, 3.3, 10.0])
    fe = track_receptance(model, [200.0], 120.5 * spacing, 120.5 * spacing + offsets)[0]
    np.testing.assert_allclose(fe, exact_periodic_transfer(track, 200.0, offsets), rtol=1e-3)


HELD_OUT = {
    # soft pads on a damped rail, and stiff pads (a low decay above the pinned-pinned frequency, high around
    # the pad resonance): neither was used to set the noise model's numerics (240 bays, 16 elements per bay)
    "soft pads 60 MN/m, rail loss factor 0.02": TrackParameters(
        rail=RailParameters(loss_factor=0.02), support=SupportParameters(pad_stiffness=60e6)
    ),
    "stiff pads 1000 MN/m": TrackParameters(support=SupportParameters(pad_stiffness=1000e6)),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(HELD_OUT))
def test_noise_track_decay_rates_match_the_exact_periodic_track(name):
    # Known answer: EN 15461's decay rate of the infinite periodic track (Floquet waves, no elements, no finite
    # length), with the same grid and band sampling as the noise model. Per band 100 Hz-5 kHz within
    # max(0.15 dB/m, 12 %): measured 0.034 dB/m (soft pads, damped rail) and 0.165 dB/m = 9.7 % (stiff pads,
    # the 1 kHz band, where the undamped rail's pinned-pinned stop band makes the decay steep in frequency).
    track = HELD_OUT[name]
    numerics = NoiseNumerics()
    f, model, _ = track_decay_rates(track, numerics)
    exact = exact_decay_rates(track, numerics)
    bands = (f > 90) & (f < 5100)
    tolerance = np.maximum(0.15, 0.12 * exact[bands])
    assert np.all(np.abs(model[bands] - exact[bands]) <= tolerance), (model[bands], exact[bands])


@pytest.mark.slow
def test_paper_track_decay_rates_match_the_exact_periodic_track_closely():
    # The paper's track: within 0.05 dB/m per band 100 Hz-5 kHz (measured 0.037 dB/m, the 1 kHz band).
    numerics = NoiseNumerics()
    f, model, _ = track_decay_rates(TrackParameters(), numerics)
    exact = exact_decay_rates(TrackParameters(), numerics)
    bands = (f > 90) & (f < 5100)
    assert np.max(np.abs(model[bands] - exact[bands])) <= 0.05


def test_decay_limit_file_and_comparison():
    # The data file: EN ISO 3095:2013 Figure 3 curve A, 14 bands 250 Hz-5 kHz, named in its header.
    limit = vertical_decay_limit()
    assert list(limit.frequency_hz) == [250, 315, 400, 500, 630, 800, 1000, 1250, 1600, 2000, 2500, 3150, 4000, 5000]
    assert list(limit.limit_db_per_m[:6]) == [2.0, 2.0, 6.0, 6.0, 6.0, 2.19] and set(limit.limit_db_per_m[6:]) == {0.8}
    assert "ISO 3095:2013" in limit.source and "Figure 3" in limit.source
    # exact band centres find their nominal band; bands outside 250 Hz-5 kHz have no limit
    f = np.array([200.0, 251.19, 398.1, 794.3, 5011.9, 6309.6])
    rates = np.array([0.1, 2.5, 5.0, 2.5, 0.5, 0.1])
    result = decay_against_limit(f, rates)
    assert result["limit_dB_per_m"] == [None, 2.0, 6.0, 2.19, 0.8, None]
    assert result["below_limit_hz"] == [398.1, 5011.9] and result["meets_limit"] is False
    assert decay_against_limit(f[1:2], rates[1:2])["meets_limit"] is True
