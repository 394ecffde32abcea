"""A modal-wheel run's noise from its own force (wheelrail.core.noise.run_noise): the modal wheel
is driven by the contact force through its own W / F^2, as the rail is, not by an effective roughness of another
wheel's receptance; a 2-DOF run keeps the modal wheel on its effective roughness (with_modal_wheel)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from wheelrail.core.engine import simulate
from wheelrail.core.noise import twins, wheel_power
from wheelrail.core.noise.components import component
from wheelrail.core.noise.run_noise import AXLE_DB, run_noise, sound_power_from_force
from wheelrail.core.noise.twins import NoiseNumerics, band_frequencies, track_noise_model
from wheelrail.core.noise.wheel_power import modal_wheel_band_means, modal_wheel_profile, modal_wheel_response
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.spectra.bands import noise_bands

pytestmark = pytest.mark.slow  # the modal wheel's modes (cached) and a 0.6 m run: seconds

SMALL = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=2)  # coarse: the plumbing, not the physics
WHEEL_POINTS = 8  # the wheel's own frequencies per band here (1 000 in the chain's default)
PARAMS = ModelParameters()


@pytest.fixture(scope="module", autouse=True)
def coarse_wheel():
    """The noise chain's modal wheel up to 3 kHz and n = 0..4 on 8 points per band, its caches emptied around."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(wheel_power, "MAX_FREQUENCY", 3000.0)
        patch.setattr(wheel_power, "MAX_HARMONIC", 4)
        patch.setattr(wheel_power, "WHEEL_POINTS_PER_BAND", WHEEL_POINTS)
        wheel_power.radiation_table.cache_clear()
        twins.clear_chain_caches()
        yield
    wheel_power.radiation_table.cache_clear()
    twins.clear_chain_caches()


@pytest.fixture(scope="module")
def profile():
    return modal_wheel_profile(PARAMS.contact.radius_along)  # the paper's R = 390 mm: the 840 mm wheel's shape


@pytest.fixture(scope="module")
def wheel_power_per_force(profile):
    """The chain's modal wheel: its sound power per unit mean-square force in each band, W/N^2."""
    return track_noise_model(PARAMS, SMALL, "modal", profile).power_per_force["wheel"]


@pytest.fixture(scope="module")
def modal_run(profile):
    """A 0.6 m hertz run whose header says it ran with the modal wheel ``profile`` (the force is a 2-DOF run's:
    the noise reads the wheel from the header; the physics of the force is not what is tested)."""
    result = simulate("corrugated-rail", model="hertz", line=0, length=0.6, params=PARAMS)
    header = dataclasses.replace(result.header, wheel_model="modal", wheel_profile=profile.describe())
    return dataclasses.replace(result, header=header)


def test_a_force_spectrum_through_the_wheels_own_receptance_by_hand(profile):
    """A force spectrum of our choosing (60 dB re 1 N at 50 Hz, 3 dB less per band) on the modal wheel coupled to a
    track and contact of 1e-9 m/N: by hand, per band on the wheel's own frequencies f_j, its W / F^2 T_j and
    receptance alpha_j (modal_wheel_response), |F / r|_j^2 = 1 / |alpha_j + 1e-9|^2 (the force's shape within the
    band), and the sound power L_F + 10 lg(sum_j T_j |F / r|_j^2 / sum_j |F / r|_j^2 / 1 pW). The plain band mean
    of T is held by the resonances, at which the coupled force vanishes: more than 3 dB higher in some band."""
    mass = PARAMS.wheel.unsprung_mass
    freqs = band_frequencies(WHEEL_POINTS)
    force_db = 60.0 - 3.0 * np.arange(24)
    expected, plain = np.empty(24), np.empty(24)
    for b, f in enumerate(freqs):
        response = modal_wheel_response(profile, f, mass)
        force_sq = 1.0 / np.abs(response["receptance"] + 1e-9) ** 2
        weighted = np.sum(response["power_per_force"] * force_sq) / np.sum(force_sq)
        expected[b] = force_db[b] + 10 * np.log10(weighted / 1e-12)
        plain[b] = force_db[b] + 10 * np.log10(np.mean(response["power_per_force"]) / 1e-12)
    means = modal_wheel_band_means(profile, mass, lambda f: np.full((len(f), 1), 1e-9 + 0j), freqs)
    np.testing.assert_allclose(force_db + 10 * np.log10(means["power_per_force_weighted"] / 1e-12), expected, atol=1e-9)
    assert np.max(plain - expected) > 3.0


def test_the_modal_wheel_is_driven_by_the_force(profile, wheel_power_per_force):
    """The modal chain's wheel is an entry driven by the force: L_W = L_F + 10 lg(T / 1 pW) per band, T its sound
    power per unit mean-square force, whatever the effective roughness; the rail's as in the directive's chain."""
    track = track_noise_model(PARAMS, SMALL, "modal", profile)
    assert component("wheel").driven_by == "roughness"  # the registered (directive) wheel stays as it is
    assert track.track_parts == ("rail", "rail_lateral", "sleeper")
    assert set(track.power_per_force) == {"rail", "rail_lateral", "sleeper", "wheel"}
    directive = track_noise_model(PARAMS, SMALL)
    np.testing.assert_allclose(track.power_per_force["rail"], directive.power_per_force["rail"], rtol=1e-12)
    force_db = 60.0 - 3.0 * np.arange(24)
    power = sound_power_from_force(force_db, track)
    np.testing.assert_allclose(power["db"]["wheel"], force_db + 10 * np.log10(wheel_power_per_force / 1e-12), atol=1e-9)
    rail = force_db + 10 * np.log10(directive.power_per_force["rail"] / 1e-12)
    np.testing.assert_allclose(power["db"]["rail"], rail, atol=1e-9)
    # L_H,tr is the track's parts alone; the modal wheel's transfer per roughness is its own chain's
    track_only = 10 * np.log10(10 ** (track.transfer_db["rail"] / 10) + 10 ** (track.transfer_db["sleeper"] / 10))
    np.testing.assert_allclose(track.track_transfer_db, track_only, atol=1e-9)


def test_a_modal_wheel_run_radiates_its_own_force(modal_run, wheel_power_per_force):
    """run_noise on a run with the modal wheel: the wheel's power per band is the run's force level plus
    10 lg(<W / F^2> / 1 pW), and the effective roughness is the modal wheel's (one wheel throughout)."""
    noise = run_noise(modal_run, wheel_model="modal", numerics=SMALL)
    resolved = np.isfinite(noise.force_db)
    assert resolved.sum() >= 5  # 0.6 m resolves the bands from 3.15 kHz up
    expected = noise.force_db + 10 * np.log10(wheel_power_per_force / 1e-12)
    np.testing.assert_allclose(noise.sound_power_db["wheel"][resolved], expected[resolved], atol=1e-9)
    assert "effective roughness" not in noise.configuration["wheel"]
    assert noise.configuration["wheel"].startswith("modal wheel (wheel_840's shape, 2R = 780 mm)")
    modal = track_noise_model(PARAMS, SMALL, "modal", modal_wheel_profile(PARAMS.contact.radius_along))
    np.testing.assert_allclose(
        noise.effective_roughness_db[resolved],
        noise.force_db[resolved] + modal.effective_roughness_per_force_db[resolved],
        atol=1e-9,
    )


def test_a_2dof_run_keeps_the_modal_wheel_on_its_effective_roughness(modal_run):
    """The same force from a 2-DOF run: the modal wheel's L_H,veh-equivalent on the 2-DOF effective roughness."""
    two_dof = dataclasses.replace(modal_run, header=dataclasses.replace(modal_run.header, wheel_model="2dof",
                                                                        wheel_profile=None))  # fmt: skip
    noise = run_noise(two_dof, wheel_model="modal", numerics=SMALL)
    modal = track_noise_model(PARAMS, SMALL, "modal", modal_wheel_profile(PARAMS.contact.radius_along))
    resolved = np.isfinite(noise.force_db)
    expected = noise.effective_roughness_db + modal.transfer_db["wheel"] - AXLE_DB
    np.testing.assert_allclose(noise.sound_power_db["wheel"][resolved], expected[resolved], atol=1e-9)
    assert "effective roughness of the 2-DOF wheel's force" in noise.configuration["wheel"]
    assert noise.frequency_hz.shape == noise_bands().shape
