"""The run's start: from the moving load's steady state (``core/engine/steady_start.py``), so that the recorded force
carries no start-up transient, at every speed, after a run-in of a few steps."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wheelrail.core.engine import prepare_run, simulate
from wheelrail.core.engine.history import DEFAULT_RUN_IN_TIME, PRELOAD_RUN_IN_TIME, default_run_in_length, starts_steady
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters, TrackParameters
from wheelrail.core.roughness import load_roughness
from wheelrail.core.wheel import wheel_static_compliance

RAIL = load_roughness("corrugated-rail")
SMOOTH = RAIL.with_heights(0.0 * RAIL.heights)
LONG_RUN_IN = 40.0  # m: 0.48 s at 300 km/h, 1.4 s at 100 km/h; the transient decays about 10x per 55 ms
BAY = 650  # steps per sleeper bay at the defaults (0.65 m, 1 mm elements)


@pytest.mark.parametrize("model", ["hertz", "2d"])
@pytest.mark.parametrize("rough", [False, True], ids=["smooth", "corrugated"])
@pytest.mark.parametrize("kmh", [100.0, 300.0])
def test_recorded_force_is_that_of_a_long_run_in(kmh, rough, model):
    # The default start (the steady state on the gap of step 0, then DEFAULT_RUN_IN_TIME) against a 40 m run-in
    # from the preload at rest (history filled with P, roughness faded in: the start every run had before, whose
    # wheel-on-track resonance rings and decays about 10x per 55 ms), compared at the same positions: at most 1 N
    # (0.002 % of the 65 kN preload; a 1 m run-in from the preload left 391-429 N here). Measured: 0.0000 N at
    # 100 km/h and 0.0005 N at 300 km/h, smooth or rough, hertz or 2d (what the 40 m run-in has left of its own
    # transient; validation/run_in.py: the same from 0 to 5 ms of run-in from the steady state).
    rail = RAIL if rough else SMOOTH
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    default = simulate(rail, model=model, params=params, length=0.5)
    settled = simulate(rail, model=model, params=params, length=0.5, run_in_length=LONG_RUN_IN)
    np.testing.assert_array_equal(default.x, settled.x)
    assert np.max(np.abs(default.force - settled.force)) <= 1.0


@pytest.mark.parametrize("model", ["hertz", "2d", "3d"])
def test_a_run_started_from_the_steady_state_stays_on_it(model):
    # The steady state solves the loop's own equations (eqs. 1-2 folded over the bay, the model's law on the gap
    # of step 0), so on a smooth rail the loop, stepping from it, must reproduce it: the recorded force is periodic
    # in the bay (n = 650 steps) and equals the steady force at each step's phase. Tolerance 1e-5 N: the solve
    # stops within 1e-11 P (6.5e-7 N) of the law, and the loop's convolution of 4 168 lags rounds to ~1e-7 N
    # (measured 2-5e-7 N for hertz, 2d and 3d at 300 km/h; a run from the preload is off by 100s of N here).
    params = ModelParameters(run=RunParameters(speed=300 * KMH))
    run = prepare_run(SMOOTH, model=model, params=params, length=0.7, keep_pressure=False)
    force = run.run().force
    steady = run.steady.force
    assert steady.size == BAY and run.loop.bay == BAY
    phase = (run.loop.n_run_in + np.arange(force.size)) % BAY
    assert np.max(np.abs(force - steady[phase])) <= 1e-5
    assert np.max(np.abs(force[BAY:] - force[: force.size - BAY])) <= 1e-5
    assert np.ptp(steady) > 1e3  # not trivially constant: the sleeper-passing force, 4.8 kN peak to peak


def test_the_steady_force_is_held_by_the_preload_and_the_suspension():
    # Static equilibrium of the wheel over a bay: its mass averages no acceleration, so the mean contact force
    # is the preload plus the suspension's (and the contact spring's) mean deflection from the rest position
    # xi_W0: mean F - P = (xi_W0 - mean xi_W) / (1/k_S + 1/k_W). Checked to 1e-9 relative to P (round-off of a
    # sum over the bay; the discrete wheel's gain at 0 Hz is the static compliance exactly, first-order hold).
    # And the mean is the preload within 1 N: the bogie is held where the bay-averaged static deflection puts
    # it; the moving load deflects the rail a little differently on average, which k_S = 1.12 MN/m turns into a
    # fraction of a newton (measured +0.21 N at 300 km/h, -0.09 N at 100 km/h on a smooth rail).
    for kmh in (100.0, 300.0):
        params = ModelParameters(run=RunParameters(speed=kmh * KMH))
        run = prepare_run(SMOOTH, model="hertz", params=params, length=0.65, keep_pressure=False)
        result = run.run()
        preload = params.contact.preload
        mean_force = float(np.mean(result.force))
        held = (run.loop.xi_w0 - float(np.mean(result.xi_wheel))) / wheel_static_compliance(params.wheel)
        assert mean_force - preload == pytest.approx(held, abs=1e-9 * preload)
        assert abs(mean_force - preload) <= 1.0


def test_the_default_run_in_is_a_time_and_every_output_states_it():
    # DEFAULT_RUN_IN_TIME (0.5 ms) at the run's speed, whole elements, after the steady start; 0.3 s from the
    # preload where no steady start is taken. The header (npz, recordings, JSON) carries length and time.
    for kmh, metres in ((5.0, 0.001), (100.0, 0.014), (300.0, 0.042)):
        params = ModelParameters(run=RunParameters(speed=kmh * KMH))
        assert default_run_in_length(params) == pytest.approx(metres)
    params = ModelParameters(run=RunParameters(speed=300 * KMH))
    result = simulate(RAIL, params=params, length=0.05)
    assert result.run_in_length == pytest.approx(0.042) and result.run_in_time == pytest.approx(0.042 / (300 * KMH))
    header = result.header.to_dict()
    assert header["run_in_length_m"] == pytest.approx(0.042) and header["run_in_time_s"] >= DEFAULT_RUN_IN_TIME
    # an explicit run-in is kept as given (and starts from the preload at rest, as before the steady start)
    run = prepare_run(RAIL, length=0.05, run_in_length=0.5)
    assert run.run_in_length == pytest.approx(0.5) and not run.loop.steady and run.loop.ramp[0] == 0.0


def test_a_bay_of_no_whole_number_of_steps_starts_from_the_preload():
    # The steady state is periodic in whole steps (the loop's positions in the bay repeat every n steps); a sleeper
    # spacing of 650.5 elements has none, so the run starts from the preload with the 0.3 s run-in.
    track = TrackParameters()
    params = ModelParameters(track=replace(track, support=replace(track.support, sleeper_spacing=0.6505)))
    assert not starts_steady(params) and starts_steady(ModelParameters())
    assert default_run_in_length(params) == pytest.approx(PRELOAD_RUN_IN_TIME * 100 * KMH, abs=1e-3)


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
    # From the preload at rest (an explicit run-in: its 0.3 s) the 3d model's run-in runs on its law
    # tabulated (contact.run_in_law.run_in_table: T_1 exact on the first recorded step's gap, T_0 smooth, blended
    # while the roughness fades in) at ~1 us a step instead
    # of ~13 us, and hands over to the 3D solver at step 0 from the warm state of the last approach. The record
    # must be that of the run-in stepped with the 3D solver within 1 N (as the run-in above); the law is exact near
    # the preload, so it is far closer: measured 0.0001 N at 100 km/h and 0.0010 N at 300 km/h over 1 m of
    # the corrugated rail (the fade's blend, decayed) (4-7 s on a quiet machine).
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    preload = PRELOAD_RUN_IN_TIME * params.run.speed
    forces = []
    for tabulated in (True, False):
        run = prepare_run(RAIL, model="3d", params=params, length=1.0, run_in_length=preload, keep_pressure=False)
        run.law.tabulated_run_in = tabulated
        forces.append(run.run().force)
    assert np.max(np.abs(forces[0] - forces[1])) <= 0.1


def test_a_short_3d_run_in_is_stepped_with_the_3d_solver():
    # Below laws.halfspace.TABULATED_RUN_IN_TIME (0.1 s) the tabulated law's fade-in would not have decayed by the
    # record (0.2-2.4 N after 1-36 ms of run-in, measured): such a run-in is stepped with the 3D solver, so the
    # result is that of tabulated_run_in = False to the bit.
    forces = []
    for tabulated in (True, False):
        run = prepare_run(RAIL, model="3d", length=0.05, run_in_length=0.5, keep_pressure=False)
        run.law.tabulated_run_in = tabulated
        forces.append(run.run().force)
        assert run.law.table is None
    np.testing.assert_array_equal(forces[0], forces[1])


@pytest.mark.parametrize("kmh", [100.0, 300.0])
def test_3d_recorded_force_is_that_of_a_long_run_in(kmh):
    # As for the one-line models above, the 3d model's default start (its law tabulated exactly near the preload on
    # the gap of step 0 for the steady state: run_in_law.step_law; then 3D steps) against a 40 m run-in from the
    # preload stepped with the 3D solver: within 1 N; measured 5e-8 N at 100 km/h and 0.0006 N at 300 km/h
    # (validation/run_in.py --3d) (40 000 3D steps: 1.1-1.4 s).
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    default = prepare_run(RAIL, model="3d", params=params, length=0.3, keep_pressure=False).run().force
    run = prepare_run(RAIL, model="3d", params=params, length=0.3, run_in_length=LONG_RUN_IN, keep_pressure=False)
    run.law.tabulated_run_in = False
    assert np.max(np.abs(default - run.run().force)) <= 1.0


@pytest.mark.slow
def test_a_stiff_track_starts_steady_where_the_anderson_mixing_stalls():
    # Pads of 3000 MN/m under 300 kg sleepers (both accepted) vary the support across the bay so much that the
    # chord iterations' Anderson mixing of 5 differences took 112 iterations here (100 allowed; it stalled at 1e-6
    # to 1e-3 P on the corrugated rail) and the run asked for an explicit run-in that no front end offers; 20
    # differences converge (45). The run starts steady and stays on it (the tolerance of the test above).
    base = ModelParameters()
    support = replace(base.track.support, pad_stiffness=3000e6, sleeper_mass=300.0)
    params = replace(base, track=replace(base.track, support=support))
    run = prepare_run(SMOOTH, model="3d", params=params, length=0.03, keep_pressure=False)
    force = run.run().force
    steady = run.steady.force
    phase = (run.loop.n_run_in + np.arange(force.size)) % run.loop.bay
    assert np.max(np.abs(force - steady[phase])) <= 1e-5


@pytest.mark.slow
@pytest.mark.parametrize("rough", [False, True], ids=["smooth", "corrugated"])
def test_a_light_3d_wheel_starts_steady(rough):
    # At the lightest accepted preload (1 kN) the 3d law's table from 0.8 of the static approach held no steady
    # state: the Anderson mixing's normal equations were singular (LinAlgError), and with least squares the
    # iterations stalled and the run asked for an explicit run-in. Tabulated over 0.05-2 P from first contact it
    # converges (the steady force within 0.98-1.02 P on the corrugated rail); on the smooth rail the loop stays
    # on it (the tolerance of test_a_run_started_from_the_steady_state_stays_on_it, scaled to the preload).
    params = ModelParameters(contact=replace(ModelParameters().contact, preload=1e3))
    run = prepare_run(RAIL if rough else SMOOTH, model="3d", params=params, length=0.03, keep_pressure=False)
    force = run.run().force
    assert run.steady is not None and np.all(np.isfinite(force))
    if not rough:
        phase = (run.loop.n_run_in + np.arange(force.size)) % run.loop.bay
        assert np.max(np.abs(force - run.steady.force[phase])) <= 1e-5
