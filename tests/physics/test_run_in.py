"""The run-in before step 0: long enough at every speed that the recorded force carries no start-up transient."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.interaction import simulate
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import load_roughness
from wheelrail.core.run_setup import DEFAULT_RUN_IN_TIME, default_run_in_length

RAIL = load_roughness("corrugated-rail")
LONG_RUN_IN = 40.0  # m: 0.48 s at 300 km/h, 1.4 s at 100 km/h; the transient decays about 10x per 55 ms


@pytest.mark.parametrize("model", ["hertz", "2d"])
@pytest.mark.parametrize("rough", [False, True], ids=["smooth", "corrugated"])
@pytest.mark.parametrize("kmh", [100.0, 300.0])
def test_recorded_force_is_that_of_a_long_run_in(kmh, rough, model):
    # The start (wheel at rest at the bay-averaged static deflection, history filled with the preload) is not
    # the moving steady state: the wheel-on-track resonance (~66 Hz, decaying about 10x per 55 ms) rings from
    # it. Against a 40 m run-in, compared at the same positions, the default run-in must leave at most 1 N
    # (issue target): a 1 m run-in left 391-399 N at 100 km/h and 396-429 N at 300 km/h here. Measured with
    # the default (0.3 s: 8.334 m, 25 m): 0.007 N (100 km/h) and 0.074 N (300 km/h), smooth or rough, hertz
    # or 2d; over 5-400 km/h in 5 km/h steps at most 0.17 N (benchmarks/run_in.py).
    rail = RAIL if rough else RAIL.with_heights(0.0 * RAIL.heights)
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    default = simulate(rail, model=model, params=params, length=0.5)
    settled = simulate(rail, model=model, params=params, length=0.5, run_in_length=LONG_RUN_IN)
    np.testing.assert_array_equal(default.x, settled.x)
    assert np.max(np.abs(default.force - settled.force)) <= 1.0


def test_the_default_run_in_is_a_time_and_every_output_states_it():
    # 0.3 s at the run's speed, whole elements: the header (npz, recordings, JSON) carries length and time
    for kmh, metres in ((5.0, 0.417), (100.0, 8.334), (300.0, 25.0)):
        params = ModelParameters(run=RunParameters(speed=kmh * KMH))
        assert default_run_in_length(params) == pytest.approx(metres)
    result = simulate(RAIL, params=ModelParameters(run=RunParameters(speed=300 * KMH)), length=0.05)
    assert result.run_in_length == pytest.approx(25.0) and result.run_in_time == pytest.approx(DEFAULT_RUN_IN_TIME)
    header = result.header.to_dict()
    assert header["run_in_length_m"] == pytest.approx(25.0) and header["run_in_time_s"] == pytest.approx(0.3)
    # an explicit run-in is kept as given
    assert simulate(RAIL, length=0.05, run_in_length=0.5).run_in_length == pytest.approx(0.5)
