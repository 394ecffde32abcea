"""A new contact position reuses the parts of the noise chain that do not depend on it: the track's vertical
vibration (for every wheel model and position), the lateral track (another offset on the railhead only scales its
receptance) and the wheel's transfer (another offset on the railhead keeps it); the chain so assembled is the one
computed from nothing."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.inputs.contact_position import ContactPosition
from wheelrail.core.noise import twins, wheel_power
from wheelrail.core.noise.twins import NoiseNumerics, track_noise_model, with_modal_wheel
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.track import lateral

SMALL = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=2)
PARAMS = ModelParameters()
POSITIONS = (  # (railhead, tread) offsets, m: both new, the railhead's only, the tread's only
    ContactPosition(rail_offset=0.01, wheel_offset=0.01),
    ContactPosition(rail_offset=-0.015, wheel_offset=0.01),
    ContactPosition(rail_offset=-0.015, wheel_offset=-0.005),
)


@pytest.fixture(autouse=True)
def coarse_wheel():
    """The modal wheel up to 3 kHz and n = 0..4 on 8 points per band, the chain's caches emptied around."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(wheel_power, "MAX_FREQUENCY", 3000.0)
        patch.setattr(wheel_power, "MAX_HARMONIC", 4)
        patch.setattr(wheel_power, "WHEEL_POINTS_PER_BAND", 8)
        wheel_power.radiation_table.cache_clear()
        twins.clear_chain_caches()
        yield
    wheel_power.radiation_table.cache_clear()
    twins.clear_chain_caches()


def _arrays(chain) -> dict:
    """Every number of a chain, by name: its JSON's arrays, the effective roughness per force and each component's
    sound power per force."""
    numbers = {name: value for name, value in chain.to_dict().items() if isinstance(value, np.ndarray)}
    numbers["effective_roughness_per_force"] = chain.effective_roughness_per_force_db
    return numbers | {f"power {name}": power for name, power in chain.power_per_force.items()}


@pytest.mark.parametrize("wheel_model", ["directive", "modal"])
def test_a_chain_from_the_parts_kept_is_the_chain_computed_afresh(wheel_model):
    track_noise_model(PARAMS, SMALL, wheel_model=wheel_model)  # a centred contact first: its parts kept
    reused = [track_noise_model(PARAMS, SMALL, wheel_model=wheel_model, contact_position=p) for p in POSITIONS]
    for position, chain in zip(POSITIONS, reused, strict=True):
        twins.clear_chain_caches()
        fresh = _arrays(track_noise_model(PARAMS, SMALL, wheel_model=wheel_model, contact_position=position))
        kept = _arrays(chain)
        assert kept.keys() == fresh.keys()
        for name, values in fresh.items():
            np.testing.assert_allclose(kept[name], values, rtol=1e-12, atol=0, err_msg=f"{name} at {position}")
        assert (
            chain.configuration
            == track_noise_model(PARAMS, SMALL, wheel_model=wheel_model, contact_position=position).configuration
        )
    assert np.all(np.isfinite(reused[0].transfer_db["rail_lateral"]))


def _counted(monkeypatch, module, name: str) -> list:
    """Record each call of ``module.name`` (its first arguments), calling it through."""
    calls, real = [], getattr(module, name)

    def spy(*args, **kwargs):
        calls.append(kwargs.get("contact_offset", args[:1]))
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, spy)
    return calls


def test_a_new_position_does_not_recompute_the_vertical_chain(monkeypatch):
    vertical = _counted(monkeypatch, twins, "stored_track_part")  # computed, or read from the disk cache
    lateral_track = _counted(monkeypatch, lateral, "lateral_receptances")
    wheel_means = _counted(monkeypatch, wheel_power, "modal_wheel_band_means")
    centred = track_noise_model(PARAMS, SMALL, wheel_model="modal")
    for position in POSITIONS:
        track_noise_model(PARAMS, SMALL, wheel_model="modal", contact_position=position)
    # the 2-DOF wheel's chain and the modal wheel on its effective roughness (a 2-DOF run's modal noise)
    directive = track_noise_model(PARAMS, SMALL, contact_position=POSITIONS[0])
    with_modal_wheel(directive, PARAMS, numerics=SMALL, contact_position=POSITIONS[0])
    assert len(vertical) == 1  # one track, whatever the wheel and the position
    assert len(lateral_track) == 2  # the lateral track once (both excitation positions), at the first offset
    assert len(wheel_means) == 3  # the modal wheel once per offset on the tread: 0, 10 and -5 mm
    assert np.all(centred.power_per_force["rail_lateral"] == 0.0)
