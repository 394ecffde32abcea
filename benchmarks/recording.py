"""Cost of rerun recordings: time per step and file size, synthetic 3D-like states and the real 3D run.

    python3 benchmarks/recording.py [--steps N] [--length-m L] [--repeat R] [--skip-real]

Part 1 streams N synthetic 3D-like states (a Hertz pressure map on the 25 x 25 window of 1 mm elements,
scaled with a sine force, as the 3D model produces) through a RecordingSink into a .rrd file, with every
pressure map recorded and with every 10th; and writes the same run in one go with record_result. It prints
the time per step against passing the states to a no-op callback, and the file size per 1 000 steps.

Part 2 runs the real 3D model on the corrugated rail (line 0, 100 km/h, paper defaults) over L m, without
recording, with a no-op per-step callback, and recording every step to a .rrd file. Each case prints its wall
time and its CPU time (the process's, so rerun's own encoding threads count), steps per second of each, and the
recording's added CPU per step: the target is 27 778 steps/s (real time at 100 km/h, 1 mm steps) with the
recording on, i.e. on a free core at least 27 778 steps per CPU second. The machine's load is printed first: on
a shared machine the wall clock follows the load, the CPU time much less. Green's functions come from the disk
cache (the first run ever precomputes them).
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.recording import RecordingOptions, RecordingSink, read_recording, record_result
from wheelrail.core.recording.sink import SURFACE_EVERY
from wheelrail.core.roughness import load_roughness

DT = 1e-3 / (100 / 3.6)  # s: 1 mm at 100 km/h


def synthetic_run(n: int) -> RunResult:
    """n steps of a 3D-like run: 65 kN + a 500 Hz force, Hertz pressure maps (float32, Pa) scaled with it."""
    contact = ContactParameters()
    t = np.arange(n) * DT
    force = contact.preload + 8e3 * np.sin(2 * np.pi * 500 * t)
    window = np.arange(-12, 13) * 1e-3
    r2 = window[None, :] ** 2 + window[:, None] ** 2
    radius = contact.hertz_radius(force)[:, None, None]
    peak = contact.hertz_peak_pressure(force)[:, None, None]
    pressure = (peak * np.sqrt(np.clip(1 - r2 / radius**2, 0, None))).astype(np.float32)
    small = 1e-6 * np.sin(2 * np.pi * 300 * t)
    return RunResult(
        header=RunHeader(model="3d", line=0, roughness_name="corrugated-rail", params=ModelParameters()),
        time=t,
        x=0.016 + np.arange(n) * 1e-3,
        force=force,
        xi_wheel=8e-5 + small,
        xi_rail=3e-5 + small,
        roughness=small,
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5),
        equivalent_roughness=small,
        pressure=pressure,
        window_x=window,
        window_y=window,
    )


def stream(result: RunResult, path: Path | None, record_every: int = 1) -> tuple[float, float]:
    """Seconds (wall, CPU of the process) to pass every step's StepState to a sink (or to a no-op callback when
    path is None).

    The sink records roughness/lines of the run's set, as ``wheelrail run`` does (the set is loaded before
    the clock starts, as the command has it before the run).
    """
    states = [result.state(k) for k in range(result.n_steps)]  # made beforehand: the loop makes them anyway
    roughness = load_roughness(result.roughness_name)
    start, cpu = time.perf_counter(), time.process_time()
    if path is None:
        sink = lambda state: None  # noqa: E731 - the baseline: a callback that does nothing
        for state in states:
            sink(state)
    else:
        sink = RecordingSink(rrd=path, options=RecordingOptions(record_every=record_every))
        sink.start(result, roughness=roughness)
        for state in states:
            sink(state)
        sink.finish(result)
    return time.perf_counter() - start, time.process_time() - cpu


def part_synthetic(n: int, folder: Path) -> None:
    result = synthetic_run(n)
    RecordingSink(rrd=folder / "warm.rrd").finish()  # import rerun and start its threads once
    stream(result, folder / "warm.rrd")  # and build the columns' templates, the spectrum's imports
    base, _ = stream(result, None)
    print(f"synthetic 3D-like states, {n} steps, 25 x 25 pressure maps (float32); wall and CPU per step")
    print(f"  no-op callback                     {base / n * 1e6:8.2f} us/step")
    for every in (1, 10):
        path = folder / f"stream{every}.rrd"
        seconds, cpu = stream(result, path, every)
        size = path.stat().st_size
        print(
            f"  RecordingSink, pressure every {every:<3d}   {seconds / n * 1e6:8.2f} us/step wall "
            f"{cpu / n * 1e6:8.2f} us/step CPU   {size / n * 1e3 / 1e6:6.2f} MB per 1 000 steps"
        )
    roughness = load_roughness(result.roughness_name)
    start = time.perf_counter()
    path = record_result(result, folder / "whole.rrd", roughness=roughness)
    seconds = time.perf_counter() - start
    print(
        f"  record_result (whole run at once)  {seconds / n * 1e6:8.2f} us/step   "
        f"{path.stat().st_size / n * 1e3 / 1e6:6.2f} MB per 1 000 steps"
    )
    start = time.perf_counter()
    back = read_recording(path)
    print(
        f"  read_recording                     {(time.perf_counter() - start) / n * 1e6:8.2f} us/step "
        f"(force identical: {np.array_equal(back.force, result.force)})"
    )
    raw = result.pressure.nbytes + 9 * 8 * n
    print(f"  (raw arrays: {raw / n * 1e3 / 1e6:.2f} MB per 1 000 steps; surface mesh every 4th map)")


def part_real(length: float, folder: Path, repeat: int, surface_every: int) -> None:
    from wheelrail.core.engine import prepare_run

    roughness = load_roughness("corrugated-rail")

    def timed(callback_kind: str) -> tuple[float, float, int]:
        run = prepare_run("corrugated-rail", model="3d", length=length)
        sink = None
        if callback_kind == "record":
            sink = RecordingSink(
                rrd=folder / "real.rrd",
                options=RecordingOptions(description="3d corrugated-rail (benchmark)", surface_every=surface_every),
            )
        start, cpu = time.perf_counter(), time.process_time()
        if sink is not None:
            sink.start(run, roughness=roughness)
            result = run.run(sink)
            sink.finish(result)
        elif callback_kind == "noop":
            result = run.run(lambda state: None)
        else:
            result = run.run()
        return time.perf_counter() - start, time.process_time() - cpu, result.n_steps

    timed("none")  # compile / load the kernels and the Green's functions once
    timed("record")  # and the recording's imports, threads and templates
    print(
        f"real 3D run, corrugated rail, line 0, 100 km/h, {length:g} m, surface every {surface_every} maps "
        f"(best of {repeat}; wall, CPU of the process)"
    )
    best = {kind: [math.inf, math.inf] for kind in ("none", "noop", "record")}
    for _ in range(repeat):  # round robin, so that a busy spell of the machine hits every case alike
        for kind, figures in best.items():
            seconds, cpu, n = timed(kind)
            figures[0], figures[1] = min(figures[0], seconds), min(figures[1], cpu)
    labels = {"none": "without recording", "noop": "per-step no-op callback", "record": "recording every step"}
    for kind, (seconds, cpu) in best.items():
        print(
            f"  {labels[kind]:26s} {seconds:6.2f} s {n / seconds:8.0f} steps/s wall   "
            f"{cpu:6.2f} s CPU {n / cpu:8.0f} steps per CPU second   {cpu / n * 1e6:6.1f} us/step"
        )
    (plain, plain_cpu), (recorded, recorded_cpu) = best["none"], best["record"]
    print(
        f"  the recording adds {(recorded_cpu - plain_cpu) / n * 1e6:.1f} us of CPU a step: CPU ratio "
        f"{recorded_cpu / plain_cpu:.2f}, wall ratio {recorded / plain:.2f}; target >= 27 778 steps per CPU second "
        f"recording ({n / recorded_cpu:.0f})"
    )
    size = (folder / "real.rrd").stat().st_size
    print(f"  file {size / n * 1e3 / 1e6:.2f} MB per 1 000 steps, {size / 1e6:.1f} MB in all")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KiB on Linux
    print(f"  peak memory of this process {peak:7.0f} MB (target < 1 GB)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=8000, help="synthetic steps (default 8000 = 8 m)")
    parser.add_argument("--length-m", type=float, default=7.9, help="real 3D run length, m (default 7.9)")
    parser.add_argument("--repeat", type=int, default=3, help="real runs per case, the fastest counts (default 3)")
    parser.add_argument("--skip-real", action="store_true", help="only the synthetic part")
    parser.add_argument(
        "--surface-every", type=int, default=SURFACE_EVERY, help=f"a surface every M maps ({SURFACE_EVERY})"
    )
    args = parser.parse_args()
    load = ", ".join(f"{value:.1f}" for value in os.getloadavg())
    print(f"{os.cpu_count()} CPUs, load average {load} (1, 5, 15 min), Python {sys.version.split()[0]}")
    with tempfile.TemporaryDirectory() as folder:
        part_synthetic(args.steps, Path(folder))
        if not args.skip_real:
            part_real(args.length_m, Path(folder), args.repeat, args.surface_every)
    return 0


if __name__ == "__main__":
    sys.exit(main())
