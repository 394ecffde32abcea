"""CPU per step and peak memory of a ``3d`` run against the run's length, pressure maps kept or not.

    python3 benchmarks/run_length_3d.py [--lengths-m 1 10 80]

The corrugated rail (8 m) mirrored end to end (continuous at the joins) to the length asked, 100 km/h, the
paper's defaults. Each case runs in its own process (after a warm-up run there, so numba's cache and the
Green's functions are loaded) and prints the CPU time per recorded step of the record (the run-in's steps on
its tabulated law are timed apart) and the process's peak resident memory. ``keep_pressure=True`` (the API's
default) keeps every pressure map (steps x 19 x 25 float32); ``False`` keeps none (a recording streams them).
"""

from __future__ import annotations

import argparse
import subprocess
import sys

CASE = r"""
import resource, sys, time
import numpy as np
from wheelrail.core.engine import prepare_run
from wheelrail.core.roughness import RoughnessSet, load_roughness

length, keep = float(sys.argv[1]), sys.argv[2] == "keep"
base = load_roughness("corrugated-rail")
copies = int(np.ceil((length + 1.0) / (base.heights.shape[1] * base.dx)))
heights = np.concatenate([base.heights if k % 2 == 0 else base.heights[:, ::-1] for k in range(copies)], axis=1)
rough = RoughnessSet(heights=heights, dx=base.dx, y=base.y, kind=base.kind, description="mirrored corrugated rail")
prepare_run(rough, model="3d", length=0.05).run()
run = prepare_run(rough, model="3d", length=length, keep_pressure=keep)
n_run_in = run.loop.n_run_in
cpu = time.process_time()
run._advance_to(n_run_in)
run_in = time.process_time() - cpu
cpu = time.process_time()
result = run.run()
cpu = time.process_time() - cpu
n = result.force.size
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3
maps = "kept" if keep else "not kept"
print(f"{length:5g} m  maps {maps:8s}  {cpu / n * 1e6:6.1f} us CPU per recorded step ({n} steps; run-in "
      f"{run_in:.2f} s CPU for {n_run_in} steps)  peak RSS {peak:5.0f} MB", flush=True)
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lengths-m", type=float, nargs="+", default=[1.0, 10.0, 80.0])
    args = parser.parse_args()
    print("3d on the corrugated rail (mirrored), 100 km/h; CPU time per step and peak memory per process")
    for length in args.lengths_m:
        for keep in ("keep", "drop"):
            subprocess.run([sys.executable, "-c", CASE, str(length), keep], check=True)


if __name__ == "__main__":
    main()
