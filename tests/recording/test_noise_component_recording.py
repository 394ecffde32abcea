"""A noise component registered in core (wheelrail.core.noise.components) is recorded with the others: its sound
power as a bar chart of its own and a view of the blueprint showing it."""

from __future__ import annotations

import functools

import numpy as np
from rerun.chunk import RrdReader
from test_blueprint import _views, check_blueprint

from wheelrail.core.engine import simulate
from wheelrail.core.noise import run_noise as run_noise_module
from wheelrail.core.noise.components import NoiseComponent, component, register_component, unregister_component
from wheelrail.core.noise.twins import NoiseNumerics
from wheelrail.core.recording import record_result

SMALL = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=1)  # coarse: the plumbing, not the physics


def _half_of_the_sleepers(chain):
    return 0.5 * component("sleeper").radiation(chain)


def test_a_registered_component_is_recorded_and_shown(tmp_path, monkeypatch):
    result = simulate("corrugated-rail", model="hertz", line=0, length=0.6)
    monkeypatch.setattr(run_noise_module, "run_noise", functools.partial(run_noise_module.run_noise, numerics=SMALL))
    extra = NoiseComponent(
        name="sleeper_pad",
        label="sleeper pad",
        colour="#009E73",
        driven_by="force",
        response=component("sleeper").response,
        radiation=_half_of_the_sleepers,
    )
    register_component(extra)
    try:
        path = record_result(result, tmp_path / "noise.rrd", sound_power=True)
        expected = run_noise_module.run_noise(result)
    finally:
        unregister_component(extra.name)
    chunks = [c for c in RrdReader(path).stream() if c.entity_path == "/spectra/sound_power/sleeper_pad"]
    (chunk,) = chunks
    levels = np.array(chunk.to_record_batch().column("BarChart:values")[0].as_py()[0]["buffer"]).view(np.float64)
    np.testing.assert_array_equal(levels, np.nan_to_num(expected.sound_power_db["sleeper_pad"], nan=0.0))
    assert check_blueprint(path) == []  # its view shows its bar chart (a view without its entity is a problem)
    assert "spectra/sound_power/sleeper_pad" in [view["origin"] for view in _views(path)]
