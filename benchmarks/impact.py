"""An impact's cost: steps per CPU second of a run with a wheel flat against the same run without it.

Run: python3 benchmarks/impact.py [--models 3d hertz 2d] [--length-m 2] [--repeats 3]
On the corrugated rail at 100 km/h, each model runs once to warm up (numba's compiled code, the track's Green's
functions), then ``--repeats`` times without irregularities (the rough run) and with one 50 mm rounded flat
meeting the rail every 2 pi R (the flat run), interleaved; the best steps per CPU second of the process is
printed for each (CPU, not the wall clock: the machine is shared). The target: a flat run as fast as a rough run
(a 3D step without contact, or with a small patch, costs less than one with the full patch).
"""

from __future__ import annotations

import argparse
import time

from wheelrail.core.engine import prepare_run
from wheelrail.core.irregularities import WheelFlat
from wheelrail.core.parameters import ModelParameters, RunParameters


def _steps_per_cpu_second(model: str, length: float, irregularities: tuple) -> float:
    params = ModelParameters(run=RunParameters(irregularities=irregularities))
    run = prepare_run("corrugated-rail", model=model, params=params, length=length, keep_pressure=False)
    start = time.process_time()
    run.run()
    return run.n_steps / max(time.process_time() - start, 1e-9)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="+", default=["3d", "hertz", "2d"])
    parser.add_argument("--length-m", type=float, default=2.0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    flat = (WheelFlat(length=0.05, position=0.3),)
    for model in args.models:
        _steps_per_cpu_second(model, 0.4, flat)  # warm-up
        rough, flats = [], []
        for _ in range(args.repeats):
            rough.append(_steps_per_cpu_second(model, args.length_m, ()))
            flats.append(_steps_per_cpu_second(model, args.length_m, flat))
        print(
            f"{model:6s} rough {max(rough):12.0f} steps/CPU s, with a 50 mm flat {max(flats):12.0f} steps/CPU s "
            f"({max(flats) / max(rough):.2f} x)"
        )


if __name__ == "__main__":
    main()
