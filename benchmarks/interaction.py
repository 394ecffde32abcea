"""Interaction loop speed: steps/s per contact model, peak memory, and the 3D step split.

Run: python3 benchmarks/interaction.py [--length-m 7.96] [--wheel-radius-mm 460 --rail-crown-radius-mm 300]
Each model runs in its own process (peak resident memory per run), on the corrugated rail at 100 km/h,
after a warm-up run so that numba's compiled code and the track's Green's functions are loaded.
Targets (2 cores): 3d >= 2 000 steps/s; 2d and hertz* >= 100 000 steps/s;
peak memory of an 8 m 3D run < 1 GB.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time

from wheelrail.core.run_setup import default_run_in_length

CHILD = r"""
import json, resource, sys, time
from wheelrail.core.interaction import prepare_run
from wheelrail.core.parameters import ContactParameters, ModelParameters
model, length = sys.argv[1], (None if sys.argv[2] == "full" else float(sys.argv[2]))
geometry = json.loads(sys.argv[3])  # ContactParameters geometry, m ({} : the paper's circle)
params = ModelParameters(contact=ContactParameters(**geometry))
prepare_run("corrugated-rail", model=model, length=0.05, params=params).run()   # warm-up: compiled code, Green's
t0 = time.perf_counter()
run = prepare_run("corrugated-rail", model=model, length=length, params=params)
t1 = time.perf_counter()
result = run.run()
t2 = time.perf_counter()
steps = run.loop.n_total  # run-in steps are computed too
out = {"model": model, "steps": steps, "prepare_s": t1 - t0, "run_s": t2 - t1, "steps_per_s": steps / (t2 - t1),
       "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}
if run.traits.pressure_map:
    out["patch_elements"] = float((result.pressure > 0).sum(axis=(1, 2)).mean())
    out["window"] = list(result.pressure.shape[1:])
if model == "3d":
    # split of a 3D step: contact solve vs everything else (history, gap assembly, bookkeeping)
    # (the model calls either solve_coupled_contact, imported into its module, or a HalfSpaceWindow's
    # solve_coupled: time both)
    import wheelrail.core.contact.halfspace_model as halfspace_model
    from wheelrail.core.contact import HalfSpaceWindow
    spent = [0.0]
    def timer(function):
        def timed(*a, **k):
            s = time.perf_counter(); r = function(*a, **k); spent[0] += time.perf_counter() - s; return r
        return timed
    if hasattr(halfspace_model, "solve_coupled_contact"):
        halfspace_model.solve_coupled_contact = timer(halfspace_model.solve_coupled_contact)
    HalfSpaceWindow.solve_coupled = timer(HalfSpaceWindow.solve_coupled)
    run = prepare_run("corrugated-rail", model=model, length=2.0, params=params)
    s = time.perf_counter(); run.run(); total = time.perf_counter() - s
    out["solve_us_per_step"] = spent[0] / run.loop.n_total * 1e6
    out["other_us_per_step"] = (total - spent[0]) / run.loop.n_total * 1e6
print(json.dumps(out))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--length-m", default="full", help="run length in m, or 'full' (the whole 8 m set)")
    parser.add_argument("--models", nargs="*", default=["hertz", "hertz-winkler", "hertz-average", "2d", "3d"])
    parser.add_argument("--wheel-radius-mm", type=float, default=None, help="default: the paper's 390")
    parser.add_argument("--rail-crown-radius-mm", type=float, default=None, help="default: the paper's 390")
    args = parser.parse_args()
    geometry = {name: value * 1e-3 for name, value in (("wheel_radius", args.wheel_radius_mm),
                                                       ("rail_crown_radius", args.rail_crown_radius_mm))
                if value is not None}
    print(f"corrugated rail, 100 km/h, length {args.length_m} (+{default_run_in_length():.3f} m run-in), "
          f"1 mm elements, geometry {geometry or 'paper'}")
    for model in args.models:
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-c", CHILD, model, str(args.length_m), json.dumps(geometry)],
                              capture_output=True, text=True)
        if done.returncode:
            print(f"  {model:14s} failed: {done.stderr.strip().splitlines()[-1]}")
            continue
        row = json.loads(done.stdout.strip().splitlines()[-1])
        line = (f"  {model:14s} {row['steps_per_s']:10.0f} steps/s  run {row['run_s']:6.2f} s  "
                f"prepare {row['prepare_s']:5.2f} s  peak RSS {row['peak_rss_mb']:6.0f} MB")
        if "patch_elements" in row:
            line += (f"\n  {'':14s} window {row['window'][0]} x {row['window'][1]}, "
                     f"patch {row['patch_elements']:.0f} elements")
        if "solve_us_per_step" in row:
            line += (f"\n  {'':14s} 3D step: contact solve {row['solve_us_per_step']:.0f} us, "
                     f"history + gap + bookkeeping {row['other_us_per_step']:.0f} us")
        print(line + f"   (wall {time.perf_counter() - start:.1f} s)")


if __name__ == "__main__":
    main()
