"""The rail's lateral vibration in the noise chain (``rail_lateral``): its sound power from a given cross receptance,
decay rate and radiation efficiency by hand, the section's lateral radiation against the exact cylinder, the
chain's band means and a run's power from them, and the centred contact's chain unchanged."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from wheelrail.core.inputs.contact_position import ContactPosition
from wheelrail.core.noise import rail_lateral, twins
from wheelrail.core.noise.radiation import (
    SOUND_SPEED,
    UIC60_POLYGON,
    circle,
    cylinder_radiation_efficiency,
    discretise,
    rail_section,
    section_radiation_efficiency,
)
from wheelrail.core.noise.run_noise import sound_power_from_force
from wheelrail.core.noise.twins import NoiseNumerics, band_frequencies, track_noise_model
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.spectra.levels import energy_sum

SMALL = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=2)
PARAMS = ModelParameters()


def test_the_lateral_power_of_given_numbers_by_hand(monkeypatch):
    # the section by hand: its 12 sides' lengths and the lateral component of their normals (the vertical and
    # horizontal sides 1 and 0; the foot's two sloping tops (dx, dy) = (66.75, 20) mm: n_x^2 = dy^2 / L^2)
    sides = np.diff(np.vstack([UIC60_POLYGON, UIC60_POLYGON[:1]]), axis=0)
    lengths = np.hypot(sides[:, 0], sides[:, 1])
    perimeter = lengths.sum()
    nx2 = np.sum(sides[:, 1] ** 2 / lengths) / perimeter
    assert rail_section()["perimeter_m"] == pytest.approx(perimeter, rel=1e-12)
    assert rail_section()["mean_normal_x_squared"] == pytest.approx(nx2, rel=1e-3)  # 2 mm elements on the sides
    # alpha_vl = 2e-11 m/N at 1 kHz (|v_0| = 2 pi 1000 2e-11 = 1.2566e-7 m/s per N), 0.8 dB/m, sigma = 0.7:
    # int |v|^2 dx = |v_0|^2 2 (10 lg e) / 0.8 = 1.5791e-14 x 10.857 = 1.7145e-13 (m/s)^2 m / N^2
    # W / F^2 = 1.21 x 343 x P <n_x^2> x 0.7 x that
    monkeypatch.setattr(rail_lateral, "lateral_rail_radiation_efficiency", lambda f: np.full(np.shape(f), 0.7))
    integral = (2 * math.pi * 1000 * 2e-11) ** 2 * 2 * 10 * math.log10(math.e) / 0.8
    assert integral == pytest.approx(1.7145e-13, rel=1e-4)
    hand = 1.21 * 343.0 * perimeter * rail_section()["mean_normal_x_squared"] * 0.7 * integral
    assert float(rail_lateral.lateral_power_per_force(1000.0, 2e-11j, 0.8)) == pytest.approx(hand, rel=1e-12)
    # the decay: twice the rate, half the power; the receptance: its square
    assert float(rail_lateral.lateral_power_per_force(1000.0, 4e-11, 1.6)) == pytest.approx(2 * hand, rel=1e-12)


@pytest.mark.slow
def test_the_bem_in_lateral_motion_reproduces_the_oscillating_cylinder():
    # a circle is the same sideways as up and down: sigma = 2 / (pi ka |H1'(ka)|^2), 64 elements within 0.025 dB
    # as the vertical motion's test (tests/physics/test_noise_radiation.py)
    a = 0.05
    f = np.array([100.0, 1000.0, 8000.0])
    exact = cylinder_radiation_efficiency(2 * np.pi * f / SOUND_SPEED * a)
    got = section_radiation_efficiency(discretise(circle(a, 64), 1.0), f, "lateral", [(0.01, 0.005), (-0.02, 0.01)])
    np.testing.assert_array_less(np.abs(10 * np.log10(got / exact)), 0.025)


def _fake_lateral(calls):
    """A lateral track of known receptance and decay: alpha_vl = -d 1e-8 (1 + 0.1 i) / f (m/N for the offset d in
    m) above a sleeper, twice that at midspan; Delta = 0.5 + f_band / 1 kHz dB/m."""

    def receptances(track, frequency, *, contact_offset, excitation, numerics):
        calls.append((contact_offset, excitation, numerics.track_bays, numerics.points_per_band))
        f = np.asarray(frequency, dtype=float)
        return SimpleNamespace(vertical_to_lateral=-contact_offset * 1e-8 / f * (1 + excitation * 2) * (1 + 0.1j))

    def decay(track, frequency, *, numerics):
        return 0.5 + np.asarray(frequency) / 1000.0

    return receptances, decay


@pytest.fixture
def fake_lateral(monkeypatch):
    from wheelrail.core.track import lateral

    calls = []
    receptances, decay = _fake_lateral(calls)
    monkeypatch.setattr(lateral, "lateral_receptances", receptances)
    monkeypatch.setattr(lateral, "lateral_decay_rate", decay)
    twins.clear_chain_caches()
    yield calls
    twins.clear_chain_caches()


def test_the_chains_band_means_and_a_runs_power_come_from_the_lateral_track(fake_lateral):
    position = ContactPosition(rail_offset=0.01)
    track = track_noise_model(PARAMS, SMALL, contact_position=position)
    # called with the chain's numerics, both excitation positions, the contact's offset
    assert sorted(c[:2] for c in fake_lateral) == [(0.01, 0.0), (0.01, 0.5)]
    assert {c[2:] for c in fake_lateral} == {(SMALL.track_bays, SMALL.points_per_band)}
    # by hand: the band mean over its points and the two positions of rho c P <n_x^2> sigma |w alpha|^2 2 (10 lg e)
    # / Delta_band
    f = band_frequencies(SMALL.points_per_band)
    centres = np.exp(np.mean(np.log(f), axis=1))
    section = rail_section()
    rho_c_p = 1.21 * 343.0 * section["perimeter_m"] * section["mean_normal_x_squared"]
    sigma = rail_lateral.lateral_rail_radiation_efficiency(f.ravel()).reshape(f.shape)
    by_position = [
        rho_c_p * sigma * np.abs(2 * np.pi * f * 0.01e-8 / f * (1 + 2 * e) * (1 + 0.1j)) ** 2
        * 2 * 10 * math.log10(math.e) / (0.5 + centres[:, None] / 1000.0)
        for e in (0.0, 0.5)
    ]  # fmt: skip
    hand = np.mean(np.stack(by_position, axis=-1), axis=(1, 2))
    np.testing.assert_allclose(track.power_per_force["rail_lateral"], hand, rtol=1e-10)
    # a part of L_H,tr
    assert "rail_lateral" in track.track_parts
    parts = energy_sum(*(track.transfer_db[name] for name in track.track_parts))
    np.testing.assert_allclose(track.track_transfer_db, parts, atol=1e-9)
    # a run's force level L_F gives L_W = L_F + 10 lg(T / 1 pW)
    force_db = 70.0 - 2.0 * np.arange(24)
    power = sound_power_from_force(force_db, track)
    np.testing.assert_allclose(power["db"]["rail_lateral"], force_db + 10 * np.log10(hand / 1e-12), atol=1e-9)


def test_a_centred_contact_leaves_todays_chain_as_it_was_and_an_offset_adds_the_lateral_rail(fake_lateral):
    centred = track_noise_model(PARAMS, SMALL)
    assert fake_lateral == []  # nothing of the lateral track is computed for a centred contact
    assert np.all(centred.transfer_db["rail_lateral"] == -np.inf)
    assert np.all(centred.power_per_force["rail_lateral"] == 0.0)
    same = track_noise_model(PARAMS, SMALL, contact_position=ContactPosition())
    off = track_noise_model(PARAMS, SMALL, contact_position=ContactPosition(rail_offset=-0.02))
    for name in ("rail", "sleeper", "wheel"):
        np.testing.assert_array_equal(same.transfer_db[name], centred.transfer_db[name])
        np.testing.assert_array_equal(off.transfer_db[name], centred.transfer_db[name])  # the vertical chain's own
    np.testing.assert_allclose(centred.track_transfer_db, energy_sum(centred.transfer_db["rail"],
                               centred.transfer_db["sleeper"]), atol=1e-9)  # fmt: skip
    assert np.all(np.isfinite(off.transfer_db["rail_lateral"]))
    assert off.configuration["contact_position"] == {"rail_offset_m": -0.02, "wheel_offset_m": 0.0}


def test_the_lateral_track_itself_gives_a_power_that_goes_as_the_offset_squared():
    # the lateral track of core.track.lateral on a short track (40 bays, 4 elements per bay; its absorbing ends a
    # quarter of it), one frequency per band: twice the offset, four times the power in every band and position
    # (alpha_vl is the torque's, F d: exactly linear in d); either side of the centreline alike (a symmetric rail)
    from wheelrail.core.noise.components import NoiseChain

    numerics = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=1)
    f = band_frequencies(1)[8:16]  # 250 Hz-1.25 kHz

    def power(offset):
        chain = NoiseChain(params=PARAMS, numerics=numerics, frequencies=f, wheel={},
                           contact_position=ContactPosition(rail_offset=offset))  # fmt: skip
        return rail_lateral.lateral_rail_power(chain)

    ten, twenty, other = power(0.01), power(0.02), power(-0.01)
    assert ten.shape == (8, 1, 2) and np.all(ten > 0)
    np.testing.assert_allclose(twenty, 4 * ten, rtol=1e-9)
    np.testing.assert_allclose(other, ten, rtol=1e-9)
