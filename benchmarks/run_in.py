"""The default run-in against a long one: what is left of the start-up transient in the recorded force.

Run: python3 benchmarks/run_in.py [--models hertz 2d] [--step-kmh 5] [--3d]

For every speed from 5 to 400 km/h (``--step-kmh`` apart) the first 0.5 m of the corrugated rail (line 0) is
run with the default run-in (``run_setup.DEFAULT_RUN_IN_TIME`` at the speed) and with a 40 m one (at least
0.36 s), and the largest difference of the recorded force at the same positions is printed (target: 1 N).
Also the same for shorter and longer run-in times, so the choice of the default can be seen, and for the
old 1 m run-in. ``--3d`` adds the 3d model at 100 and 300 km/h (slow: 40 m of 3d steps each).
"""

from __future__ import annotations

import argparse

import numpy as np

from wheelrail.core.interaction import simulate
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import load_roughness
from wheelrail.core.run_setup import DEFAULT_RUN_IN_TIME

LENGTH = 0.5  # m recorded
TIMES = (0.1, 0.15, 0.2, 0.25, DEFAULT_RUN_IN_TIME, 0.4)  # s of run-in compared


def residual(rail, model: str, kmh: float, run_in_length: float | None, reference: np.ndarray) -> float:
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    force = simulate(
        rail, model=model, params=params, length=LENGTH, run_in_length=run_in_length, keep_pressure=False
    ).force
    return float(np.max(np.abs(force - reference)))


def long_run_in(rail, model: str, kmh: float) -> np.ndarray:
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    return simulate(
        rail, model=model, params=params, length=LENGTH, keep_pressure=False, run_in_length=max(40.0, 0.36 * kmh * KMH)
    ).force


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--models", nargs="*", default=["hertz", "2d"])
    parser.add_argument("--step-kmh", type=float, default=5.0)
    parser.add_argument("--3d", dest="three_d", action="store_true")
    args = parser.parse_args()
    rail = load_roughness("corrugated-rail")
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
            print(
                f"  3d     {kmh:5.0f} km/h: default {residual(rail, '3d', kmh, None, reference):.3f} N, "
                f"1 m run-in {residual(rail, '3d', kmh, 1.0, reference):.1f} N"
            )


if __name__ == "__main__":
    main()
