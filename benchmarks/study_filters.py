"""The `filters` study (paper Fig. 10): wall time per set and for all four bundled sets, 1 vs 2 workers.

Run: python3 benchmarks/study_filters.py [--base /path/to/other/checkout] [--rounds N]
Target: the `filters` study on all four bundled sets < 60 s on 2 cores, and 2 workers faster than 1.

Each set: 7 lines (-3..3) x 4 one-line models + one 3D run, all over the whole set (rail 7.96 m, wheels
one 2.9 m turn) at 100 km/h; 116 runs for the four sets. Every measurement writes into a fresh folder,
so no run comes from the study's run cache. The track's Green's functions (disk cache) and numba's
compiled kernels are warmed first: the figures are the study, not the one-off precompute.

Rows:
* ``cold pool``: what one ``wheelrail study`` command costs: the 2 worker processes are started (spawned,
  imports and numba cache loads) inside the timing.
* ``warm pool``: a later study in the same process (the GUI, a script running several studies) reuses the
  workers.
* ``in-process``: ``--workers 1``, the serial reference of the speed-up.

Each row also gives the CPU seconds spent (this process, and the workers once the pool is stopped) and the
load average before it: on a shared machine the wall time follows the other jobs, the CPU time much less.
``--base DIR`` runs the same script with another checkout's ``DIR/.venv/bin/python`` in turn with this one,
``--rounds`` times (each in a fresh process), so that the two see the same moments of the machine.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from wheelrail.core.roughness import bundled_names
from wheelrail.core.study import run_study, shutdown_pools

SETS = ["corrugated-rail", "cast-iron-wheel", "sinter-wheel-1", "sinter-wheel-2"]


def cpu_seconds() -> float:
    """CPU seconds of this process and of its finished children (the workers of a stopped pool)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def timed(sets, workers):
    """Run the study into a fresh folder; returns (wall time s, result, worker time of the 3D runs s)."""
    out = tempfile.mkdtemp(prefix="wheelrail-bench-study-")
    start = time.perf_counter()
    result = run_study("filters", sets, out, workers=workers, progress=False)
    wall = time.perf_counter() - start
    three_d = sum(s.run_time for key, s in result.report.summaries.items() if key in _KEYS_3D)
    return wall, result, three_d


def load() -> str:
    return f"load {os.getloadavg()[0]:.1f}"


_KEYS_3D: set[str] = set()


def main() -> None:
    assert sorted(SETS) == sorted(bundled_names()), bundled_names()
    from wheelrail.core.study import plan_study

    for name in SETS:
        _KEYS_3D.update(spec.key for spec in plan_study("filters", [name]).specs if spec.model == "3d")
    # warm the Green's function cache and numba's kernels (one short run of each kind, in this process)
    run_study("filters", ["cast-iron-wheel"], tempfile.mkdtemp(), length=0.8, workers=1, progress=False, figures=False)
    print(
        f"filters study (paper Fig. 10), 100 km/h, whole sets; {os.cpu_count()} CPUs; python {sys.version.split()[0]}"
    )
    print()

    shutdown_pools()
    before, cpu = load(), cpu_seconds()
    wall, result, three_d = timed(SETS, 2)
    cold_two = wall
    print(
        f"all four sets, 2 workers, cold pool: {wall:6.1f} s  ({result.report.computed} runs; "
        f"3D runs {three_d:.1f} s of worker time; target < 60 s; {before})"
    )
    before = load()
    wall, result, three_d = timed(SETS, 2)
    warm_two = wall
    shutdown_pools()  # the workers' CPU time is counted once they have ended
    two_cpu = cpu_seconds() - cpu
    print(f"all four sets, 2 workers, warm pool: {wall:6.1f} s  ({before}; CPU of both studies {two_cpu:.1f} s)")
    before, cpu = load(), cpu_seconds()
    wall, result, three_d = timed(SETS, 1)
    one = wall
    print(
        f"all four sets, 1 worker (in-process): {wall:6.1f} s  (3D runs {three_d:.1f} s; CPU "
        f"{cpu_seconds() - cpu:.1f} s; {before})"
    )
    print(f"speed-up 1 -> 2 workers: {one / cold_two:.2f}x cold pool, {one / warm_two:.2f}x warm pool")
    print()
    print("per set, 2 workers, warm pool:")
    for name in SETS:
        wall, result, three_d = timed([name], 2)
        runs = list(result.report.summaries.values())
        steps = sum(s.n_steps for s in runs)
        print(f"  {name:16s} {wall:6.1f} s  {len(runs)} runs, {steps / 1e3:.0f}k steps, 3D run {three_d:.1f} s")
    shutdown_pools()


def interleaved() -> None:
    """With ``--base DIR``: this checkout's run and the other's in turn, each in a fresh process."""
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", type=Path, required=True)
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args()
    pythons = {"this": sys.executable, "base": str(args.base.resolve() / ".venv" / "bin" / "python")}
    for _ in range(args.rounds):
        for label, python in pythons.items():
            print(f"--- {label} ({python})", flush=True)
            subprocess.run([python, str(Path(__file__).resolve())], check=True)


if __name__ == "__main__":
    if len(sys.argv) > 1:
        interleaved()
    else:
        main()
