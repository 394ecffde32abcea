"""The run-in before step 0: long enough at every speed that the recorded force carries no start-up transient."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.interaction import prepare_run, simulate
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
    # (0.002 % of the 65 kN preload): a 1 m run-in left 391-399 N at 100 km/h and 396-429 N at 300 km/h here.
    # Measured with the default (0.3 s: 8.334 m, 25 m): 0.007 N (100 km/h) and 0.074 N (300 km/h), smooth or rough,
    # hertz or 2d; over 5-400 km/h in 5 km/h steps at most 0.17 N (validation/run_in.py).
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


def test_the_3d_laws_table_is_the_law_itself():
    # The discretised 3D law on a fixed window is piecewise linear in the approach (linear on each contact set,
    # eqs. 8-11), so the run-in's table (run_in_law.tabulate_law: solves with their slopes, a kink where
    # the lines of neighbouring solves meet, solved again there where the sets differ by more than one
    # element) is the law itself in its band. Against direct solves at 200 approaches across the band on the
    # first recorded step's gap (corrugated rail, 65 kN): within 1e-6 N, round-off of the solver's 1e-9
    # (measured 1.2e-10 N; the solves alone, every 0.5 % of the static approach, without the kinks: 90 N).
    from wheelrail.core.contact.run_in_law import RUN_IN_TABLE_BAND, _solve_at, tabulate_law

    run = prepare_run(RAIL, model="3d", length=0.05, keep_pressure=False)
    steps, s, preload = run.contact.law_inputs(), run.loop.n_run_in, run.params.contact.preload
    static = run.loop.xi_w0 - preload * float(np.mean(run.loop.weights.sum(axis=1)))
    band = (RUN_IN_TABLE_BAND[0] * preload, RUN_IN_TABLE_BAND[1] * preload)
    delta, force = tabulate_law(steps, s, (0.08 * static, 0.04 * static), band, 1.3 * preload)
    lo, hi = np.interp(band, force, delta)
    probe = np.random.default_rng(1).uniform(lo, hi, 200)
    probe.sort()
    direct = _solve_at(steps, s, probe)[1]
    assert np.max(np.abs(np.interp(probe, delta, force) - direct)) <= 1e-6


@pytest.mark.slow
@pytest.mark.parametrize("kmh", [100.0, 300.0])
def test_3d_run_in_with_the_tabulated_law_records_the_force_of_the_3d_solver(kmh):
    # The 3d model's run-in runs on its law tabulated (contact.run_in_law.run_in_table: T_1 exact on
    # the first recorded step's gap, T_0 smooth, blended while the roughness fades in) at ~1 us a step instead
    # of ~13 us, and hands over to the 3D solver at step 0 from the warm state of the last approach. The record
    # must be that of the run-in stepped with the 3D solver within 1 N (as the run-in above); the law is exact near
    # the preload, so it is far closer: measured 0.0001 N at 100 km/h and 0.0010 N at 300 km/h over 1 m of
    # the corrugated rail (the fade's blend, decayed) (4-7 s on a quiet machine).
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    forces = []
    for tabulated in (True, False):
        run = prepare_run(RAIL, model="3d", params=params, length=1.0, keep_pressure=False)
        run.tabulated_run_in = tabulated
        forces.append(run.run().force)
    assert np.max(np.abs(forces[0] - forces[1])) <= 0.1


def test_a_short_3d_run_in_is_stepped_with_the_3d_solver():
    # Below interaction.TABULATED_RUN_IN_TIME (0.1 s) the tabulated law's fade-in would not have decayed by the
    # record (0.2-2.4 N after 1-36 ms of run-in, measured): such a run-in is stepped with the 3D solver, so the
    # result is that of tabulated_run_in = False to the bit.
    forces = []
    for tabulated in (True, False):
        run = prepare_run(RAIL, model="3d", length=0.05, run_in_length=0.5, keep_pressure=False)
        run.tabulated_run_in = tabulated
        forces.append(run.run().force)
        assert run._table is None
    np.testing.assert_array_equal(forces[0], forces[1])
