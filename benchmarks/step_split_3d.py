"""Where the microseconds of a 3D step go, in the compiled loop (``engine.laws.halfspace.run_chunk_3d``).

Run: python3 benchmarks/step_split_3d.py [--length-m 2] [--wheel-radius-mm 460 --rail-crown-radius-mm 300]

On the corrugated rail at 100 km/h, 1 mm elements, after a warm-up run (compiled code and Green's functions
loaded). Prints

* the whole step (a run of the ``3d`` model, steps/s by the wall clock and per CPU second: the machine is
  shared, and the CPU figure is what the step costs when it has a core);
* eqs. 1-2 alone (history and commit, the track convolution of ``_scatter``): the same loop with the law
  replaced by the forces the run found;
* the contact law alone (``halfspace_model.halfspace_step``: gap assembly and solve), replayed on the
  approaches the run handed it, from the warm state of a fresh run stepped to the same first recorded step;
* inside the law: how many active-set iterations, additions and drops a step takes (counted by replaying the
  law's solve, ``active_set.solve_step``, on the same approaches) and what each costs at the run's contact
  set (each kernel timed alone in a compiled loop, on the state the run ended with);
* where the law solves through ``contact.capacitance`` (windows without the influence matrix, 0.5 mm): the
  references factored and kept vectors computed per recorded step, the members at the end, and the costs of
  x_h = C_RR^-1 h_R (once a step: one product with the kept inverse, ``capacitance.prepare_gap``) alone and with
  the set's pressure from the small system (once an iteration); the
  itemised substitutions and factor updates are then those of the factor path, which the law does not take.

The sum of the itemised costs is printed against the measured law: the difference is what is not
itemised (the tension check, bookkeeping, cache misses between the pieces).

With ``--in-situ`` each piece of a step is also timed where the run has it: the law replayed again with the piece
run ``IN_SITU_TIMES`` more times after each step (on that step's state, in the cache state the step leaves),
its cost the replay's extra time divided by that (best of ``--rounds``).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from numba import njit

from wheelrail.core.contact import active_set as steps
from wheelrail.core.contact import capacitance, cholesky, halfspace_model
from wheelrail.core.engine import prepare_run
from wheelrail.core.engine.kernels import commit_force, known_approach
from wheelrail.core.parameters import ContactParameters, ModelParameters, RunParameters

SET = "corrugated-rail"
IN_SITU_TIMES = 4  # extra runs of a piece after each replayed step (--in-situ)
IN_SITU = (
    "gap assembly from the roughness lines",
    "the gap's minimum",
    "x_h = C_RR^-1 h_R (one product with the kept C_RR^-1)",
    "the set's pressure from the small system (per iteration)",
    "tension check (per iteration)",
    "a step's first deformed-gap check",
    "a later check (bounds of u kept)",
    "the window's pressure summed, the edge and centre-row count",
    "the float32 pressure map written (recorded run)",
)


@njit
def _loop_without_law(j0, j1, track, wheel, preload, xi_w0, forces, offset):
    """Eqs. 1-2 of the loop with the law replaced by known forces; returns the approaches it handed over."""
    known = np.empty(j1 - j0)
    compliance = np.empty(j1 - j0)
    for j in range(j0, j1):
        delta_known, c, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
        known[j - j0] = delta_known
        compliance[j - j0] = c
        commit_force(j, forces[j - offset], track, wheel, s_pred, preload, xi_w0, q, w0)
    return known, compliance


@njit
def _law_alone_from(first, known, compliance, law):
    total = 0.0
    for s in range(first, known.size):
        status, force, on_centre, count = halfspace_model.halfspace_step(s, known[s], compliance[s], law)
        total += force
    return total


@njit
def _repeat_forward(upper, m, rhs, reps):
    for _ in range(reps):
        for a in range(m):
            rhs[a] = 1.0
        cholesky.forward(upper, m, rhs)


@njit
def _repeat_backward(upper, m, rhs, reps):
    for _ in range(reps):
        for a in range(m):
            rhs[a] = 1.0
        cholesky.backward(upper, m, rhs)


@njit
def _repeat_penetrating(law, m, limits, reps):
    """The first check of a step: no bounds of u kept from an earlier check (``deformed_gap.displacement_kept``)."""
    grid, state, work, _, _ = law
    known, _, since = work[7]
    n = 0
    for _ in range(reps):
        known[:] = np.nan
        since[1] = 0.0
        n += steps._penetrating(grid, state[0], m, work, state[1], limits)
    return n


@njit
def _repeat_capacitance(law, reps):
    """x_h for the gap (``capacitance.prepare_gap``), then the set's pressure (``capacitance.pressure_on_set``)."""
    _, state, work, _, _ = law
    cap, upper, active = state[5], state[4], state[1]
    pressure = work[0].copy()
    for _ in range(reps):
        capacitance.prepare_gap(work[1], upper, cap)
    for _ in range(reps):
        capacitance.pressure_on_set(cap, work[1], active, pressure, (True, 0.0, 0.0))


@njit
def _repeat_prepare_gap(law, reps):
    """x_h for the gap alone (``capacitance.prepare_gap``)."""
    _, state, work, _, _ = law
    for _ in range(reps):
        capacitance.prepare_gap(work[1], state[4], state[5])


@njit
def _repeat_append_remove(law, m, reps):
    """Remove the element at the middle of the factor and append it again (z kept with it)."""
    grid, state, work, _, _ = law
    order, active, z, counts, upper = state[:5]
    for _ in range(reps):
        element = order[m // 2]
        cholesky.remove(order, m, upper, (z, work[6]), work[4], m // 2)
        cholesky.append(grid, order, m - 1, upper, (z, work[6], work[1]), work[4], element)


@njit
def _in_situ(first, known, compliance, law, piece, maps):
    """The law replayed on these approaches with piece ``piece`` (1-based in ``IN_SITU``, 0 none) run
    ``IN_SITU_TIMES`` more times after each step, on that step's state."""
    grid, state, work, track, limits = law
    base, lines, start_index, ramp, half_x, centre_row = track
    pressure, gap = work[0], work[1]
    nx = 2 * half_x + 1
    ny = base.size // nx
    order, active, _, counts, upper, cap = state
    tol, _, area, _ = limits
    total = 0.0
    for s in range(first, known.size):
        _, f, _, _ = halfspace_model.halfspace_step(s, known[s], compliance[s], law)
        m = counts[0]
        for _ in range(IN_SITU_TIMES if piece > 0 else 0):
            if piece == 1:
                begin = start_index[s] - half_x
                for row in range(ny):
                    for column in range(nx):
                        gap[row * nx + column] = base[row * nx + column] - ramp[s] * lines[row, begin + column]
            elif piece == 2:
                total += steps._lowest(gap)
            elif piece == 3:
                capacitance.prepare_gap(gap, upper, cap)
            elif piece == 4:
                total += capacitance.pressure_on_set(
                    cap, gap, active, pressure, (True, known[s], compliance[s] * area)
                )[0]
            elif piece == 5:
                pmax = 0.0
                for a in range(m):
                    pmax = max(pmax, pressure[order[a]])
                total += steps._tension_elements(pressure, order, m, pmax, tol, False, work[3])
            elif piece == 6 or piece == 7:
                known_u, listed, since = work[7]
                if piece == 6:  # as a step's start: no bounds of u kept
                    for k in range(int(since[1])):
                        known_u[listed[k]] = np.nan
                    since[0] = since[1] = 0.0
                delta = known[s] - compliance[s] * f
                scale = max(delta - steps._lowest(gap), 1e-30)
                limits_check = (delta, 1e-6 * scale, -tol * scale, False)
                total += steps._penetrating(grid, order, m, work, active, limits_check)
            elif piece == 8:
                total += steps._sum(pressure)
                rows, columns = grid[3], grid[4]
                for a in range(m):
                    i = order[a]
                    if rows[i] == 0 or rows[i] == ny - 1 or columns[i] == 0 or columns[i] == nx - 1:
                        total += 1.0
                    if rows[i] == centre_row:
                        total += 1.0
            elif piece == 9:
                flat = maps[s - first].reshape(pressure.size)
                for i in range(pressure.size):
                    flat[i] = pressure[i]
    return total


def _report_in_situ(params, args, known, compliance, first, window) -> None:
    """The pieces of a recorded step timed in situ (``_in_situ``), best of ``args.rounds``."""
    n = known.size - first
    shape = (n, *window)
    warm = _at_record(params, args.length_m).law.solver.law
    for piece in range(len(IN_SITU) + 1):  # compile every branch (no step)
        _in_situ(known.size, known, compliance, warm, piece, np.zeros((1, 1, 1), dtype=np.float32))
    best = np.full(len(IN_SITU) + 1, np.inf)
    for _ in range(args.rounds):
        for piece in range(len(IN_SITU) + 1):
            law = _at_record(params, args.length_m).law.solver.law
            maps = np.zeros(shape, dtype=np.float32)
            start = time.process_time()
            _in_situ(first, known, compliance, law, piece, maps)
            best[piece] = min(best[piece], (time.process_time() - start) / n * 1e6)
    print(
        f"  in situ (the law replayed: best {best[0]:.1f} us a step; each piece's extra time, best of {args.rounds}):"
    )
    for name, extra in zip(IN_SITU, best[1:], strict=True):
        print(f"    {name:62s} {(extra - best[0]) / IN_SITU_TIMES:6.2f} us")


def _params(args) -> ModelParameters:
    geometry = {
        name: value * 1e-3
        for name, value in (("wheel_radius", args.wheel_radius_mm), ("rail_crown_radius", args.rail_crown_radius_mm))
        if value is not None
    }
    return ModelParameters(
        contact=ContactParameters(**geometry), run=RunParameters(element_size=args.element_mm * 1e-3)
    )


def _per_call(function, *arguments, reps: int) -> float:
    function(*arguments[:-1], 1)
    start = time.process_time()
    function(*arguments[:-1], reps)
    return (time.process_time() - start) / reps * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--length-m", type=float, default=2.0)
    parser.add_argument("--wheel-radius-mm", type=float, default=None)
    parser.add_argument("--rail-crown-radius-mm", type=float, default=None)
    parser.add_argument("--element-mm", type=float, default=1.0)
    parser.add_argument("--in-situ", action="store_true", help="also time each piece of a step where the run has it")
    parser.add_argument("--rounds", type=int, default=3, help="rounds of the in-situ timings (best of)")
    args = parser.parse_args()
    params = _params(args)
    prepare_run(SET, model="3d", params=params, length=0.05).run()  # warm-up

    run = prepare_run(SET, model="3d", params=params, length=args.length_m)
    loop = run.loop
    run._advance_to(loop.n_run_in)  # the run-in (on its tabulated law) is not timed: recorded steps only
    wall, cpu = time.perf_counter(), time.process_time()
    run.run()
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    n, r = loop.n_steps, loop.n_run_in
    radii = f"{params.contact.radius_along * 1e3:g} / {params.contact.radius_across * 1e3:g} mm"
    print(
        f"{SET}, {args.length_m:g} m ({n} recorded steps timed; {r} run-in steps before), window "
        f"{run.law.solver.shape[0]} x {run.law.solver.shape[1]}, relative radii along / across {radii}"
    )
    print(
        f"whole step            {cpu / n * 1e6:6.1f} us CPU  ({n / cpu:,.0f} steps per CPU s; "
        f"{n / wall:,.0f} steps/s by the wall clock on the shared machine)"
    )

    # eqs. 1-2 alone, on a fresh run at the same point (steady start and run-in done) with the run's forces
    forces = loop.force.copy()
    j0, j1 = loop.n_hist + r, loop.n_hist + loop.n_total
    preload = params.contact.preload
    warm = _at_record(params, args.length_m)  # compiles the loop (one step), then a fresh one
    _loop_without_law(j0, j0 + 1, warm.loop.track, warm.loop.wheel, preload, warm.loop.xi_w0, forces, 0)
    f = _at_record(params, args.length_m).loop
    start = time.process_time()
    known, compliance = _loop_without_law(j0, j1, f.track, f.wheel, preload, f.xi_w0, forces, 0)
    history = (time.process_time() - start) / n * 1e6
    known = np.concatenate((np.zeros(r), known))  # indexed by step s, run-in included
    compliance = np.concatenate((np.zeros(r), compliance))
    print(f"  eqs. 1-2 (history, track convolution of {loop.weights.shape[1]} lags, commit) {history:6.1f} us")

    # the law alone on the same approaches, from the warm state the recorded steps start from
    _law_alone_from(known.size, known, compliance, warm.law.solver.law)  # compile (no step)
    law = _at_record(params, args.length_m).law.solver.law
    start = time.process_time()
    _law_alone_from(r, known, compliance, law)
    law_us = (time.process_time() - start) / n * 1e6
    print(f"  contact law (gap assembly + solve)                        {law_us:6.1f} us")
    print(f"  rest (outputs: pressure map, lengths; not itemised)       {cpu / n * 1e6 - history - law_us:6.1f} us")

    replayed = _at_record(params, args.length_m).law.solver
    before = replayed.capacitance_counts()
    decisions = _decisions(r, known, compliance, replayed.law)[r:]
    after = replayed.capacitance_counts()
    iterations, added, dropped, elements = decisions.mean(axis=0)
    m = int(round(elements))
    state_law = run.law.solver.law
    size = int(state_law[1][3][0])
    upper = state_law[1][4]
    rhs = np.empty(upper.shape[0])
    forward = _per_call(_repeat_forward, upper, size, rhs, 20000, reps=20000)
    backward = _per_call(_repeat_backward, upper, size, rhs, 20000, reps=20000)
    gap, pressure, members = state_law[2][1], state_law[2][0], state_law[1][0][:size]
    # the last step's approach: d = h - delta + C p = 0 on the set
    delta = float(np.mean(gap[members] + steps.displacement(state_law[0], pressure)[members]))
    scale = delta - gap.min()
    penetrating = _per_call(
        _repeat_penetrating, state_law, size, (delta, 1e-6 * scale, -1e-9 * scale, False), 5000, reps=5000
    )
    update = _per_call(_repeat_append_remove, state_law, size, 5000, reps=5000)
    print(
        f"  inside the law, per step: {iterations:.2f} iterations, {added:.2f} elements added, {dropped:.2f} "
        f"dropped, {m} in contact (the law's decisions, replayed)"
    )
    print(
        f"    per iteration: forward + backward substitution {forward:.1f} + {backward:.1f} us, deformed gap "
        f"outside the set {penetrating:.1f} us (a step's first check; later ones keep bounds of u)"
    )
    print(f"    per element added and dropped (new factor row + downdate at mid-set) {update:.1f} us")
    if replayed.law[1][5][0].dtype == np.int64:  # the law solves through contact.capacitance
        both = _per_call(_repeat_capacitance, state_law, 5000, reps=5000)
        xh = _per_call(_repeat_prepare_gap, state_law, 5000, reps=5000)
        print(f"    capacitance: x_h alone {xh:.1f} us (the two substitutions above: {forward + backward:.1f} us)")
        print(
            f"    capacitance: {after['references'] - before['references']} reference(s) factored, "
            f"{(after['vectors'] - before['vectors']) / n:.2f} kept vectors computed per step, "
            f"{after['members']} members at the end; x_h + the set's pressure {both:.1f} us (timed alone); "
            "the substitutions and updates above are the factor path's"
        )
    itemised = iterations * (forward + backward + penetrating) + 0.5 * (added + dropped) * update
    print(
        f"    itemised {itemised:.1f} us of the law's {law_us:.1f} us (an upper bound: a forward substitution and a "
        f"deformed gap each iteration, updates at mid-set; not itemised: gap assembly, tension check, bookkeeping)"
    )
    if args.in_situ:
        _report_in_situ(params, args, known, compliance, r, run.law.solver.shape)


def _at_record(params, length):
    """A fresh run of the same length stepped to its first recorded step (steady start and run-in done)."""
    run = prepare_run(SET, model="3d", params=params, length=length)
    run._advance_to(run.loop.n_run_in)
    return run


@njit
def _decisions(first, known, compliance, law):
    """(iterations, elements added, dropped, in contact) per step of the law replayed on these approaches."""
    _, state, work, track, _ = law
    base, lines, start_index, ramp, half_x, _ = track
    nx = 2 * half_x + 1
    ny = base.size // nx
    gap, active = work[1], state[1]
    out = np.zeros((known.size, 4))
    for s in range(first, known.size):
        before = active.copy()
        first = start_index[s] - half_x
        for row in range(ny):
            for column in range(nx):
                gap[row * nx + column] = base[row * nx + column] - ramp[s] * lines[row, first + column]
        status, force, delta, iterations = steps.solve_step(law, True, known[s], compliance[s])
        if force > 0.0:
            out[s, 0] = iterations
            out[s, 1] = (active & ~before).sum()
            out[s, 2] = (before & ~active).sum()
            out[s, 3] = state[3][0]
    return out


if __name__ == "__main__":
    main()
