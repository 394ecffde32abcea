"""The run's start against a long run-in: what is left of the start-up transient in the recorded force.

Run: python3 validation/run_in.py [--models hertz 2d] [--step-kmh 5 | --speeds-kmh 100 300] [--3d]
     python3 validation/run_in.py --timing [--repeats 5] [--base DIR]

A run starts from the moving load's steady state on the gap of step 0 (``core/engine/steady_start.py``) and runs in for
``history.DEFAULT_RUN_IN_TIME``. For every speed from 5 to 400 km/h (``--step-kmh`` apart) the first 0.5 m of the
corrugated rail (line 0) is run so and compared with a 40 m run-in (at least 0.36 s) from the preload at rest
(the start every run had before: history filled with the preload, roughness faded in): the largest difference of
the recorded force at the same positions is printed (target: 1 N), also for other run-ins from the steady state
(0 to 5 ms) so the choice of the default can be seen, and for the old start's 0.3 s run-in. ``--3d`` adds the 3d
model at 100 and 300 km/h (its 40 m reference stepped with the 3D solver: slow).

``--timing``: a 3 m ``3d`` run on the corrugated rail (line 0, no pressure maps kept) at 100 and 300 km/h, best
of ``--repeats``: the start (the steady state: the law's table, the solve, the history; and the run-in's steps)
and the record's steps, and the whole run over the record (target 1.2), with the load average before and after.
``--base DIR``: the same printed by ``DIR``'s own ``validation/run_in.py --timing`` (its ``.venv``), interleaved.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from wheelrail.core.engine import history, prepare_run
from wheelrail.core.engine.history import DEFAULT_RUN_IN_TIME, PRELOAD_RUN_IN_TIME
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import load_roughness

LENGTH = 0.5  # m recorded
STEADY_TIMES = (0.0, 0.0005, 0.001, DEFAULT_RUN_IN_TIME, 0.005)  # s of run-in from the steady state compared
ONE_LINE_MODELS = ("hertz", "2d", "hertz-winkler", "hertz-average")


def recorded(rail, model: str, kmh: float, run_in_length=None, tabulated=True, steady_time=None) -> np.ndarray:
    """The recorded force: ``run_in_length`` None starts from the steady state (with ``steady_time`` s of run-in
    instead of the default, if given), a length from the preload at rest (``prepare_run``)."""
    params = ModelParameters(run=RunParameters(speed=kmh * KMH))
    default = history.DEFAULT_RUN_IN_TIME
    if steady_time is not None:  # the default run-in's time, for this run only (default_run_in_length reads it)
        history.DEFAULT_RUN_IN_TIME = steady_time
    try:
        run = prepare_run(
            rail, model=model, params=params, length=LENGTH, run_in_length=run_in_length, keep_pressure=False
        )
    finally:
        history.DEFAULT_RUN_IN_TIME = default
    run.law.tabulated_run_in = tabulated
    return run.run().force


def long_run_in(rail, model: str, kmh: float) -> np.ndarray:
    """The recorded force after a 40 m run-in from the preload at rest (3d: stepped with the 3D solver)."""
    return recorded(rail, model, kmh, max(40.0, 0.36 * kmh * KMH), tabulated=False)


def differences(rail, model: str, kmh: float) -> dict:
    """max |F - F(40 m run-in)| (N) of the default, of each run-in time from the steady state, of the old start."""
    reference = long_run_in(rail, model, kmh)
    out = {"default": np.max(np.abs(recorded(rail, model, kmh) - reference))}
    for t in STEADY_TIMES:
        out[t] = np.max(np.abs(recorded(rail, model, kmh, steady_time=t) - reference))
    old = recorded(rail, model, kmh, PRELOAD_RUN_IN_TIME * kmh * KMH)
    out["preload 0.3 s"] = np.max(np.abs(old - reference))
    return out


def scan(rail, models, speeds) -> None:
    print(
        f"corrugated rail line 0, {LENGTH} m recorded: max |F - F(40 m run-in from the preload)|, N "
        f"(default: {DEFAULT_RUN_IN_TIME * 1e3:g} ms of run-in from the steady state)"
    )
    for model in models:
        worst = {}
        for kmh in speeds:
            values = differences(rail, model, kmh)
            for key, value in values.items():
                worst[key] = max(worst.get(key, (0.0, 0.0)), (float(value), float(kmh)))
            if kmh in (100.0, 300.0):
                listed = ", ".join(f"{_label(k)} {v:.4f}" for k, v in values.items())
                print(f"  {model:13s} {kmh:5.0f} km/h: {listed}")
        for key, (value, kmh) in worst.items():
            print(
                f"  {model:13s} {_label(key):14s} worst over {speeds[0]:g}-{speeds[-1]:g} km/h: "
                f"{value:9.4f} N at {kmh:g} km/h"
            )


def _label(key) -> str:
    return key if isinstance(key, str) else f"steady+{key * 1e3:g} ms"


def three_d(rail) -> None:
    for kmh in (100.0, 300.0):
        reference = long_run_in(rail, "3d", kmh)
        default = recorded(rail, "3d", kmh)
        old = recorded(rail, "3d", kmh, PRELOAD_RUN_IN_TIME * kmh * KMH)
        print(
            f"  3d            {kmh:5.0f} km/h: default {np.max(np.abs(default - reference)):.4f} N, "
            f"preload 0.3 s (tabulated) {np.max(np.abs(old - reference)):.4f} N"
        )


def _timed_run(rail, params) -> tuple[float, float, int, int]:
    run = prepare_run(rail, model="3d", params=params, length=3.0, keep_pressure=False)
    t0 = time.perf_counter()
    run._advance_to(run.loop.n_run_in)  # the steady start (found on first use) and the run-in's steps
    t1 = time.perf_counter()
    run._advance_to(run.loop.n_total)
    t2 = time.perf_counter()
    return t1 - t0, t2 - t1, run.loop.n_run_in, run.n_steps


def timing(rail, repeats: int, base: str | None) -> None:
    print(f"3 m 3d run, corrugated rail line 0; load average before: {os.getloadavg()}, best of {repeats}")
    for kmh in (100.0, 300.0):
        params = ModelParameters(run=RunParameters(speed=kmh * KMH))
        start, record = np.inf, np.inf
        base_lines = []
        for _ in range(repeats):
            a, b, n_run_in, n_steps = _timed_run(rail, params)
            start, record = min(start, a), min(record, b)
            if base:
                base_lines.append(_base_timing(base, kmh))
        print(
            f"  {kmh:5.0f} km/h: start (steady state + {n_run_in} run-in steps) {start * 1e3:6.1f} ms, record "
            f"({n_steps} steps) {record * 1e3:6.1f} ms; run / record {(start + record) / record:.3f}"
        )
        for line in base_lines:
            print(f"        base: {line}")
    print(f"load average after: {os.getloadavg()}")


def _base_timing(base: str, kmh: float) -> str:
    """The base's own timing line of the tabulated run-in at this speed (its script, its .venv, 2 repeats)."""
    python = Path(base) / ".venv" / "bin" / "python"
    script = Path(base) / "validation" / "run_in.py"
    out = subprocess.run(
        [str(python), str(script), "--timing", "--repeats", "2"], capture_output=True, text=True, check=True
    ).stdout
    lines = [line.strip() for line in out.splitlines() if f"{kmh:5.0f} km/h" in line and "tabulated" in line]
    return lines[0] if lines else out.strip().replace("\n", " | ")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--models", nargs="*", default=list(ONE_LINE_MODELS))
    parser.add_argument("--step-kmh", type=float, default=5.0)
    parser.add_argument("--speeds-kmh", type=float, nargs="*", help="these speeds instead of the 5 km/h scan")
    parser.add_argument("--3d", dest="three_d", action="store_true")
    parser.add_argument("--timing", action="store_true", help="only the 3 m 3d run's timing")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--base", help="a checkout of the previous code (with its .venv) timed interleaved")
    args = parser.parse_args()
    rail = load_roughness("corrugated-rail")
    if args.timing:
        timing(rail, args.repeats, args.base)
        return
    speeds = np.array(args.speeds_kmh) if args.speeds_kmh else np.arange(5.0, 400.0 + 1e-9, args.step_kmh)
    scan(rail, args.models, speeds)
    if args.three_d:
        three_d(rail)
    sys.stdout.flush()


if __name__ == "__main__":
    main()
