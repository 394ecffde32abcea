"""Time of ``prepare_run`` on a cached track and speed (target: under 50 ms), optionally interleaved with another
checkout of the project (e.g. the previous commit's, as a `git worktree`), in fresh processes.

Each process times, for ``hertz`` and ``2d`` on the corrugated rail (0.5 m) at 100 and 200 km/h: the first
``prepare_run`` in the process (imports done; numba's cached kernels loaded on the way), then the median of
five more calls. A first untimed process per checkout fills the cache (the track's Green's functions: tens of
seconds once). Both checkouts share one cache folder (``WHEELRAIL_CACHE_DIR`` if set, else a folder in the
system's temporary directory); a checkout's code is imported from its own folders.

    python3 benchmarks/prepare_run.py [--base /path/to/other/checkout] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASES = [("hertz", 100.0), ("hertz", 200.0), ("2d", 100.0)]

CHILD = r"""
import json, statistics, sys, time
from dataclasses import replace
from wheelrail.core.engine import prepare_run
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import load_roughness
import wheelrail.core.engine.prepare as where

rail = load_roughness("corrugated-rail")
out = {"code": where.__file__}
for model, kmh in json.loads(sys.argv[1]):
    params = replace(ModelParameters(), run=RunParameters(speed=kmh * KMH))
    start = time.perf_counter()
    prepare_run(rail, model=model, params=params, length=0.5)
    first = time.perf_counter() - start
    again = []
    for _ in range(5):
        start = time.perf_counter()
        prepare_run(rail, model=model, params=params, length=0.5)
        again.append(time.perf_counter() - start)
    out[f"{model} {kmh:g}"] = (first, statistics.median(again))
print(json.dumps(out))
"""


def _package_view(checkout: Path, scratch: Path) -> Path:
    """A folder whose ``wheelrail`` package is ``checkout``'s code (setup.py's mapping of its folders)."""
    view = scratch / checkout.name / "wheelrail"
    view.mkdir(parents=True, exist_ok=True)
    for item in (checkout / "package").iterdir():
        if item.suffix == ".py":
            (view / item.name).symlink_to(item)
    for name, folder in (("core", "core"), ("explorer", "explorer"), ("sample_data", "sample_data")):
        (view / name).symlink_to(checkout / folder)
    return view.parent


def _session(checkout: Path, scratch: Path, cache: str) -> dict:
    env = {**os.environ, "WHEELRAIL_CACHE_DIR": cache, "PYTHONPATH": str(_package_view(checkout, scratch))}
    done = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps(CASES)], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", type=Path, help="another checkout to interleave with (e.g. a worktree of main)")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    cache = os.environ.get("WHEELRAIL_CACHE_DIR") or str(Path(tempfile.gettempdir()) / "wheelrail-bench-prepare")
    checkouts = {"this": ROOT, **({"base": args.base.resolve()} if args.base else {})}
    with tempfile.TemporaryDirectory() as folder:
        scratch = Path(folder)
        for name, checkout in checkouts.items():
            code = _session(checkout, scratch / "fill", cache)["code"]  # fills the cache; not timed
            print(f"{name}: {checkout} (imports {code})")
        print(f"cache: {cache}; {os.cpu_count()} cores")
        print(
            f"{'load':>5} {'code':>5} "
            + " ".join(f"{case[0]} {case[1]:g} km/h: first, again (ms)".rjust(34) for case in CASES)
        )
        for number in range(args.repeat):
            for name, checkout in checkouts.items():
                load = os.getloadavg()[0]
                times = _session(checkout, scratch / f"run{number}", cache)
                cells = [
                    f"{times[f'{m} {k:g}'][0] * 1e3:16.1f}, {times[f'{m} {k:g}'][1] * 1e3:15.1f}" for m, k in CASES
                ]
                print(f"{load:5.1f} {name:>5} " + " ".join(cells))


if __name__ == "__main__":
    main()
