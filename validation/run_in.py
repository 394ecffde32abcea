"""The default run-in against a long one: what is left of the start-up transient in the recorded force.

Run: python3 validation/run_in.py [--models hertz 2d] [--step-kmh 5] [--3d] [--timing]

For every speed from 5 to 400 km/h (``--step-kmh`` apart) the first 0.5 m of the corrugated rail (line 0) is
run with the default run-in (``run_setup.DEFAULT_RUN_IN_TIME`` at the speed) and with a 40 m one (at least
0.36 s), and the largest difference of the recorded force at the same positions is printed (target: 1 N).
Also the same for shorter and longer run-in times, so the choice of the default can be seen, and for the
old 1 m run-in. ``--3d`` adds the 3d model at 100 and 300 km/h: its default run-in (the tabulated 3D law,
``contact.run_in_law``) and the run-in stepped with the 3D solver, both against a 40 m run-in stepped
with the 3D solver (slow: 40 m of 3d steps each).

``--timing``: a 3 m ``3d`` run on the corrugated rail (line 0, no pressure maps kept) at 100 and 300 km/h, the
run-in with the tabulated law and with the 3D solver (interleaved, best of ``--repeats``): the time of the
run-in (table included) and of the record's steps, and the whole run's steps over the record's (target 1.2),
with the machine's load (``uptime``) before and after.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from wheelrail.core.interaction import prepare_run
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import load_roughness
from wheelrail.core.run_setup import DEFAULT_RUN_IN_TIME

LENGTH = 0.5  # m recorded
TIMES = (0.1, 0.15, 0.2, 0.25, DEFAULT_RUN_IN_TIME, 0.4)  # s of run-in compared


def recorded(rail, model: str, kmh: float, run_in_length: float | None, tabulated: bool = True) -> np.ndarray:
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    run = prepare_run(rail, model=model, params=params, length=LENGTH, run_in_length=run_in_length, keep_pressure=False)
    run.tabulated_run_in = tabulated
    return run.run().force


def residual(rail, model: str, kmh: float, run_in_length: float | None, reference: np.ndarray, **kw) -> float:
    return float(np.max(np.abs(recorded(rail, model, kmh, run_in_length, **kw) - reference)))


def long_run_in(rail, model: str, kmh: float) -> np.ndarray:
    """The recorded force after a 40 m run-in (3d: stepped with the 3D solver)."""
    return recorded(rail, model, kmh, max(40.0, 0.36 * kmh * KMH), tabulated=False)


def timing(rail, repeats: int) -> None:
    print(f"3 m 3d run, corrugated rail line 0; load before: {os.getloadavg()[0]:.2f} (1 min), best of {repeats}")
    for kmh in (100.0, 300.0):
        params = ModelParameters(run=RunParameters(speed=kmh * KMH))
        best = {True: [np.inf, np.inf], False: [np.inf, np.inf]}
        for _ in range(repeats):
            for tabulated in (True, False):
                run = prepare_run(rail, model="3d", params=params, length=3.0, keep_pressure=False)
                run.tabulated_run_in = tabulated
                t0 = time.perf_counter()
                run._advance_to(run.loop.n_run_in)
                t1 = time.perf_counter()
                run._advance_to(run.loop.n_total)
                t2 = time.perf_counter()
                best[tabulated] = [min(best[tabulated][0], t1 - t0), min(best[tabulated][1], t2 - t1)]
        record = min(best[True][1], best[False][1])
        for tabulated, label in ((False, "3D solver"), (True, "tabulated")):
            run_in = best[tabulated][0]
            print(
                f"  {kmh:5.0f} km/h, run-in ({run.loop.n_run_in} steps) {label:9s}: run-in {run_in * 1e3:7.1f} ms, "
                f"record ({run.n_steps} steps) {best[tabulated][1] * 1e3:6.1f} ms; "
                f"run / record {(run_in + record) / record:.2f}"
            )
    print(f"load after: {os.getloadavg()[0]:.2f} (1 min)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--models", nargs="*", default=["hertz", "2d"])
    parser.add_argument("--step-kmh", type=float, default=5.0)
    parser.add_argument("--3d", dest="three_d", action="store_true")
    parser.add_argument("--timing", action="store_true", help="only the 3 m 3d run's timing")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    rail = load_roughness("corrugated-rail")
    if args.timing:
        timing(rail, args.repeats)
        return
    speeds = np.arange(5.0, 400.0 + 1e-9, args.step_kmh)
    print(
        f"corrugated rail line 0, {LENGTH} m recorded: max |F - F(40 m run-in)|, N "
        f"(default run-in {DEFAULT_RUN_IN_TIME} s at the speed)"
    )
    for model in args.models:
        worst = {t: (0.0, 0.0) for t in (*TIMES, "1 m")}
        for kmh in speeds:
            reference = long_run_in(rail, model, kmh)
            for t in TIMES:
                value = residual(rail, model, kmh, t * kmh * KMH if t != DEFAULT_RUN_IN_TIME else None, reference)
                worst[t] = max(worst[t], (value, kmh))
            worst["1 m"] = max(worst["1 m"], (residual(rail, model, kmh, 1.0, reference), kmh))
            if kmh in (100.0, 300.0):
                print(
                    f"  {model:6s} {kmh:5.0f} km/h: default {residual(rail, model, kmh, None, reference):.3f} N, "
                    f"1 m run-in {residual(rail, model, kmh, 1.0, reference):.1f} N"
                )
        for t, (value, kmh) in worst.items():
            label = f"{t:g} s" if t != "1 m" else t
            mark = " (default)" if t == DEFAULT_RUN_IN_TIME else ""
            print(
                f"  {model:6s} run-in {label:7s}{mark:10s} worst over {speeds[0]:g}-{speeds[-1]:g} km/h: "
                f"{value:9.3f} N at {kmh:g} km/h"
            )
    if args.three_d:
        for kmh in (100.0, 300.0):
            reference = long_run_in(rail, "3d", kmh)
            solver = recorded(rail, "3d", kmh, None, tabulated=False)
            tabulated = recorded(rail, "3d", kmh, None)
            print(
                f"  3d     {kmh:5.0f} km/h: default (tabulated) {np.max(np.abs(tabulated - reference)):.3f} N, "
                f"default stepped with the 3D solver {np.max(np.abs(solver - reference)):.3f} N, "
                f"1 m run-in {residual(rail, '3d', kmh, 1.0, reference, tabulated=False):.1f} N; "
                f"tabulated vs 3D solver run-in {np.max(np.abs(tabulated - solver)):.4f} N"
            )


if __name__ == "__main__":
    main()
