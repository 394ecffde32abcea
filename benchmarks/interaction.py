"""Interaction loop speed: steps/s per contact model, peak memory.

Run: python3 benchmarks/interaction.py [--length-m 7.96] [--repeats 3]
                                       [--wheel-radius-mm 460 --rail-crown-radius-mm 300]
                                       [--element-mm 1 0.5] [--base /path/to/other/checkout]
Each model runs in its own process (peak resident memory per run), on the corrugated rail at 100 km/h,
after a warm-up run so that numba's compiled code and the track's Green's functions are loaded; then
``--repeats`` timed runs, of which the best and the range are printed: by the wall clock, and per second of
CPU time of the process (on a shared machine the wall clock also counts the time other processes had the
core; the CPU figure is what a step costs when it has one). Where a 3D step's microseconds go:
benchmarks/step_split_3d.py.
With ``--element-mm`` each model runs at each element size (the step length and the 3D window's elements, m
-> ``RunParameters.element_size``), and for ``3d`` the recorded steps alone are timed as well (after the run-in,
which runs on its tabulated law): "record". With ``--base DIR`` every child runs a second time with DIR's own
``.venv`` (another checkout, e.g. the main branch), interleaved, each line with the load average when it started.
Targets (2 cores): 3d >= 27 778 steps/s (real time at 100 km/h on 1 mm elements), for the paper's circle and
for a 460 mm wheel on a 300 mm crown; 2d and hertz* >= 1 000 000 steps/s; peak memory of an 8 m 3D run < 1 GB.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from wheelrail.core.engine.history import default_run_in_length

CHILD = r"""
import json, resource, sys, time
try:
    from wheelrail.core.engine import prepare_run
except ImportError:  # a --base checkout from before the engine package
    from wheelrail.core.interaction import prepare_run
from wheelrail.core.parameters import ContactParameters, ModelParameters, RunParameters
model, length, repeats = sys.argv[1], (None if sys.argv[2] == "full" else float(sys.argv[2])), int(sys.argv[4])
geometry = json.loads(sys.argv[3])  # ContactParameters geometry, m ({} : the paper's circle)
element = float(sys.argv[5]) * 1e-3
params = ModelParameters(contact=ContactParameters(**geometry), run=RunParameters(element_size=element))
prepare_run("corrugated-rail", model=model, length=0.05, params=params).run()   # warm-up: compiled code, Green's
walls, cpus = [], []
for _ in range(repeats):
    t0 = time.perf_counter()
    run = prepare_run("corrugated-rail", model=model, length=length, params=params)
    t1, c1 = time.perf_counter(), time.process_time()
    result = run.run()
    t2, c2 = time.perf_counter(), time.process_time()
    walls.append(t2 - t1)
    cpus.append(c2 - c1)
steps = run.loop.n_total  # run-in steps are computed too
out = {"model": model, "steps": steps, "prepare_s": t1 - t0, "run_s": min(walls),
       "steps_per_s": [steps / max(walls), steps / min(walls)],
       "steps_per_cpu_s": [steps / max(cpus), steps / min(cpus)],
       "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}
if model == "3d":  # the recorded steps alone (the run-in runs on its tabulated law)
    best = 0.0
    for _ in range(repeats):
        again = prepare_run("corrugated-rail", model=model, length=length, params=params)
        again._advance_to(again.loop.n_run_in)
        c1 = time.process_time()
        again.run()
        best = max(best, again.loop.n_steps / (time.process_time() - c1))
    out["record_steps_per_cpu_s"] = best
if run.traits.pressure_map:
    out["patch_elements"] = float((result.pressure > 0).sum(axis=(1, 2)).mean())
    out["window"] = list(result.pressure.shape[1:])
print(json.dumps(out))
"""


def _child(python: str, model: str, args, geometry: dict, element_mm: float) -> dict | str:
    """One model's figures from a fresh process of this ``python``, or the error's last line."""
    done = subprocess.run(
        [python, "-c", CHILD, model, str(args.length_m), json.dumps(geometry), str(args.repeats), str(element_mm)],
        capture_output=True,
        text=True,
    )
    if done.returncode:
        return done.stderr.strip().splitlines()[-1]
    return json.loads(done.stdout.strip().splitlines()[-1])


def _line(label: str, row: dict) -> str:
    (wall_lo, wall_hi), (cpu_lo, cpu_hi) = row["steps_per_s"], row["steps_per_cpu_s"]
    line = (
        f"  {label:20s} {wall_hi:10.0f} steps/s ({wall_lo:.0f}-{wall_hi:.0f}), per CPU s {cpu_hi:10.0f} "
        f"({cpu_lo:.0f}-{cpu_hi:.0f})  run {row['run_s']:6.3f} s  prepare {row['prepare_s']:5.2f} s  "
        f"peak RSS {row['peak_rss_mb']:6.0f} MB"
    )
    if "record_steps_per_cpu_s" in row:
        line += f"\n  {'':20s} record (steps after the run-in) {row['record_steps_per_cpu_s']:10.0f} steps per CPU s"
    if "patch_elements" in row:
        line += (
            f"\n  {'':20s} window {row['window'][0]} x {row['window'][1]}, patch {row['patch_elements']:.0f} elements"
        )
    return line


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--length-m", default="full", help="run length in m, or 'full' (the whole 8 m set)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per model (best and range printed)")
    parser.add_argument("--models", nargs="*", default=["hertz", "hertz-winkler", "hertz-average", "2d", "3d"])
    parser.add_argument("--wheel-radius-mm", type=float, default=None, help="default: the paper's 390")
    parser.add_argument("--rail-crown-radius-mm", type=float, default=None, help="default: the paper's 390")
    parser.add_argument("--element-mm", type=float, nargs="*", default=[1.0], help="element sizes, mm (default 1)")
    parser.add_argument("--base", type=Path, help="another checkout with its own .venv, interleaved")
    args = parser.parse_args()
    geometry = {
        name: value * 1e-3
        for name, value in (("wheel_radius", args.wheel_radius_mm), ("rail_crown_radius", args.rail_crown_radius_mm))
        if value is not None
    }
    pythons = {"this": sys.executable}
    if args.base is not None:
        pythons["base"] = str(args.base.resolve() / ".venv" / "bin" / "python")
    print(
        f"corrugated rail, 100 km/h, length {args.length_m} (+{default_run_in_length():.3f} m run-in), "
        f"elements {', '.join(f'{e:g}' for e in args.element_mm)} mm, geometry {geometry or 'paper'}; best of "
        f"{args.repeats} runs (range); {os.cpu_count()} cores; " + ", ".join(f"{k}: {v}" for k, v in pythons.items())
    )
    for element_mm in args.element_mm:
        for model in args.models:
            for name, python in pythons.items():
                load = os.getloadavg()[0]
                start = time.perf_counter()
                row = _child(python, model, args, geometry, element_mm)
                label = f"{model} {element_mm:g} mm" + (f" {name}" if len(pythons) > 1 else "")
                if isinstance(row, str):
                    print(f"  {label:20s} failed: {row}")
                    continue
                print(_line(label, row) + f"   (load {load:.1f}, wall {time.perf_counter() - start:.1f} s)")


if __name__ == "__main__":
    main()
