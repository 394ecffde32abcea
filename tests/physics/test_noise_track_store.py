"""The noise chain's track part kept on disk (core/noise/track_part_store.py): a new process reads it instead of
computing it again, equal to the bit; another track, contact or numerics is computed afresh; a plug-in's track part
is kept in memory only."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wheelrail.core.files import cache
from wheelrail.core.noise import twins
from wheelrail.core.noise.components import NoiseComponent, component, register_component, unregister_component
from wheelrail.core.noise.track_part_store import KIND
from wheelrail.core.noise.twins import NoiseNumerics, track_noise_model
from wheelrail.core.parameters import ModelParameters

SMALL = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=2)
PARAMS = ModelParameters()


@pytest.fixture
def computed(monkeypatch, tmp_path) -> list:
    """A disk cache of this test's own, the chain's memory emptied around, and each computation of the track part
    recorded."""
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    calls, real = [], twins.track_vibration

    def spy(*args, **kwargs):
        calls.append(args[0].track)
        return real(*args, **kwargs)

    monkeypatch.setattr(twins, "track_vibration", spy)
    twins.clear_chain_caches()
    yield calls
    twins.clear_chain_caches()


def _stored() -> list:
    return [entry for entry in cache.entries() if entry.kind == KIND]


def _numbers(chain) -> dict:
    numbers = {name: value for name, value in chain.to_dict().items() if isinstance(value, np.ndarray)}
    numbers["effective_roughness_per_force"] = chain.effective_roughness_per_force_db
    return numbers | {f"power {name}": power for name, power in chain.power_per_force.items()}


def test_a_new_process_reads_the_track_part_from_disk_to_the_bit(computed):
    first = track_noise_model(PARAMS, SMALL)
    assert len(computed) == 1 and len(_stored()) == 1
    twins.clear_chain_caches()  # what a new process starts with: nothing in memory
    again = track_noise_model(PARAMS, SMALL)
    assert len(computed) == 1  # read, not computed
    kept, read = _numbers(first), _numbers(again)
    assert kept.keys() == read.keys()
    for name, values in kept.items():
        np.testing.assert_array_equal(read[name], values, err_msg=name)
    assert again.configuration == first.configuration


def test_another_track_contact_or_numerics_is_computed_afresh(computed):
    stiffer = replace(
        PARAMS.track, support=replace(PARAMS.track.support, pad_stiffness=2 * PARAMS.track.support.pad_stiffness)
    )
    heavier = replace(PARAMS.contact, preload=1.2 * PARAMS.contact.preload)  # another contact stiffness
    cases = [
        (PARAMS, SMALL),
        (replace(PARAMS, track=stiffer), SMALL),
        (replace(PARAMS, contact=heavier), SMALL),
        (PARAMS, replace(SMALL, points_per_band=3)),
    ]
    for params, numerics in cases:
        twins.clear_chain_caches()
        track_noise_model(params, numerics)
    assert len(computed) == len(_stored()) == 4


def test_a_plug_in_track_part_is_kept_in_memory_only(computed):
    # its response's code (a lambda here, or a plug-in's module) is not in the entry's key: never read from disk
    rail = component("rail")
    plug_in = NoiseComponent(
        name="rail_twice", label="rail, twice", colour=rail.colour, driven_by="force",
        response=lambda state: 2.0 * rail.response(state), radiation=rail.radiation,
    )  # fmt: skip
    register_component(plug_in)
    try:
        track_noise_model(PARAMS, SMALL)
        twins.clear_chain_caches()
        track_noise_model(PARAMS, SMALL)
    finally:
        unregister_component(plug_in.name)
    assert len(computed) == 2 and _stored() == []


def test_other_frequencies_are_another_entry(computed, monkeypatch):
    # the bands' frequencies come from code outside the entry's code digest (spectra.bands): they are in its key
    track_noise_model(PARAMS, SMALL)
    twins.clear_chain_caches()
    real = twins.band_frequencies
    monkeypatch.setattr(twins, "band_frequencies", lambda points: real(points) * (1 + 1e-6))
    track_noise_model(PARAMS, SMALL)
    assert len(computed) == len(_stored()) == 2
