"""Each study's wall and CPU time on 1 and 2 workers: the filters, track and impact studies.

Run: python3 benchmarks/study_workers.py [--quick] [--studies filters track impact] [--rounds N]
                                         [--backend auto|fork|threads|processes] [--pin] [--precompute]
Target: two workers at least 1.7x faster than one on each study, on a quiet 2-core machine.

A study's ``workers`` are the cores it may use (a new track's precompute in the study's process integrates in at
most that many threads). Each line gives the study's wall and CPU time, the load average before it and the wall time
of its figures (drawn after the last run, on two processes with two workers where the study forks); each study's
speed-up line gives the best wall times' ratio, and that ratio without the figures. ``--pin`` pins each
measurement's process (and the worker processes it starts) to as many CPUs as it has workers: 1 core against 2.

Each measurement is a fresh process that runs one study by the API, as one ``wheelrail study`` command does (its
start-up as the command line's, ``core.startup``, unless ``STUDY_WORKERS_API_START=1``; numba's compiled code
loaded, matplotlib imported and any worker process started inside the timing), into a fresh
output folder, so that no run comes from the study's run cache. The 1- and 2-worker measurements of a round run one
after the other, so that they see the same moments of a shared machine; each line gives the load average before it.
CPU time is that of the process and of its worker processes (ended before it is read).

Studies (full size; ``--quick``: about a minute in all on a quiet machine):

* ``filters``: paper Fig. 10 on the four bundled sets, whole sets at 100 km/h (116 runs; quick: the same).
* ``track``: the track study on the corrugated rail with the pad stiffness swept over 10 values (quick: 2, 1 m runs),
  each a new track: every measurement gets a disk cache of its own with the user's entries but no track (removed
  afterwards), so each track is a precompute of its Green's functions, spread over the workers.
* ``impact``: a rounded wheel flat of 20, 30 and 50 mm at 1 m on the corrugated rail, every model at 30-140 km/h,
  3 m runs (60 runs; quick: 20 and 50 mm at 60 and 140 km/h, 2 m: 20 runs).

``--precompute`` also times two new tracks' precomputes one after the other in one process with two threads each
(``NUMBA_NUM_THREADS=2``) against two processes side by side with one thread each (what the study's process pool
does with two or more new tracks).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SETS = ["corrugated-rail", "cast-iron-wheel", "sinter-wheel-1", "sinter-wheel-2"]
PAD_STIFFNESS_MN_M = (60, 80, 100, 150, 200, 300, 400, 600, 800, 1000)  # 10 tracks, none the paper's 120 MN/m


def cpu_seconds() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def study_arguments(name: str, quick: bool) -> tuple[list, dict]:
    """The sets and keywords of ``run_study`` for a study at the chosen size."""
    from wheelrail.core.inputs.declared import model_parameters
    from wheelrail.core.irregularities.shapes import WheelFlat
    from wheelrail.core.parameters import KMH, ModelParameters
    from wheelrail.core.study.impact_plan import ImpactSweep

    if name == "filters":
        return SETS, {}
    if name == "track":
        values = PAD_STIFFNESS_MN_M[:2] if quick else PAD_STIFFNESS_MN_M
        params = [model_parameters({"pad_stiffness": v * 1e6}) for v in values]
        return ["corrugated-rail"], {"params": params, "length": 1.0 if quick else None}
    flats = (0.02, 0.05) if quick else (0.02, 0.03, 0.05)  # a 100 mm flat leaves 3d's window
    speeds = (60.0, 140.0) if quick else (30.0, 60.0, 100.0, 140.0)
    sweep = ImpactSweep(
        ModelParameters(),
        cases=tuple((WheelFlat(length=v, position=1.0),) for v in flats),
        speeds=tuple(v * KMH for v in speeds),
    )
    return ["corrugated-rail"], {"params": sweep, "length": 2.0 if quick else 3.0}


_PHASES: list = []  # the file phase stamps go to (``--phases``), in every process of the study


def stamp(label: str) -> None:
    """One phase stamp: this process's pid, the label, ``perf_counter`` (one clock for all processes on Linux) and
    this process's CPU time, appended to the phases file (one write: lines of several processes do not mix)."""
    if _PHASES:
        line = f"{os.getpid()} {label} {time.perf_counter():.6f} {time.process_time():.6f}\n"
        handle = os.open(_PHASES[0], os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            os.write(handle, line.encode())
        finally:
            os.close(handle)


def _stamped(module, attribute: str, label: str, each: bool = True) -> None:
    """Wrap ``module.attribute`` so that its calls are stamped ``label+`` and ``label-`` (``each`` False: its first
    call's start and its last call's end only matter; every call is still stamped)."""
    function = getattr(module, attribute)

    def wrapper(*args, **kwargs):
        stamp(f"{label}+")
        try:
            return function(*args, **kwargs)
        finally:
            stamp(f"{label}-")

    setattr(module, attribute, wrapper)


def install_phase_stamps(path: str) -> None:
    """Stamp each phase of a study in every process (wrappers round the study's functions, inherited by a fork)."""
    from wheelrail.core.study import execution, figure_workers, figures, forked, plans, runner, specs, threads

    _PHASES.append(path)
    _stamped(runner, "plan_study", "plan")
    _stamped(execution, "_dispatch", "dispatch")  # begins once the run keys and the run cache are looked at
    _stamped(forked, "execute_forked", "forked")
    _stamped(forked, "_work", "work")
    _stamped(forked, "_child", "child")
    _stamped(forked, "_call_child", "figure-child")
    _stamped(threads, "read_once", "read-sets")
    _stamped(execution, "read_once", "read-sets")
    _stamped(execution, "compute_run", "run")
    _stamped(specs, "compute_run", "run")
    _stamped(runner, "_load_matplotlib", "matplotlib")
    _stamped(plans, "_noise_chain", "noise-chain")
    _stamped(figures, "study_figures", "figure-build")
    _stamped(figure_workers, "_cut", "figure-layout")
    _stamped(figure_workers, "_drawn", "figure-draw")
    _stamped(figure_workers, "_png", "figure-png")
    _stamped(figure_workers, "_encoded", "figure-stitch")
    plan_study = runner.plan_study

    def plan_with_tables(*args, **kwargs):
        import dataclasses

        plan = plan_study(*args, **kwargs)
        tabulate = plan.tabulate

        def tables(summaries):
            stamp("tables+")
            try:
                return tabulate(summaries)
            finally:
                stamp("tables-")

        return dataclasses.replace(plan, tabulate=tables)

    runner.plan_study = plan_with_tables


def child_study(name: str, workers: int, quick: bool, backend: str, pin: bool = False) -> None:
    """One study in this (fresh) process; prints its figures as one JSON line (wall and CPU time, s; the load; the
    wall time of its figures, s)."""
    import functools

    if os.environ.get("STUDY_WORKERS_API_START") != "1":  # 1: start as a library user's process does
        from wheelrail.core.startup import fast_start_on_import

        fast_start_on_import()  # as the command line starts (numba's first load without scipy.linalg's package)
    from wheelrail.core.study import execute, run_study, runner, shutdown_pools

    if os.environ.get("STUDY_WORKERS_PHASES"):
        install_phase_stamps(os.environ["STUDY_WORKERS_PHASES"])
    if pin:  # this process and the workers it starts on the first `workers` CPUs
        os.sched_setaffinity(0, sorted(os.sched_getaffinity(0))[:workers])
    runner.execute = functools.partial(execute, backend=backend)  # run_study's choice of local workers
    plotted = [0.0]
    plot_study = runner.plot_study

    def timed_plot(*args, **kwargs):
        start = time.perf_counter()
        try:
            return plot_study(*args, **kwargs)
        finally:
            plotted[0] += time.perf_counter() - start

    runner.plot_study = timed_plot
    sets, keywords = study_arguments(name, quick)
    out = tempfile.mkdtemp(prefix="wheelrail-bench-workers-")
    load = os.getloadavg()[0]
    cpu, start = cpu_seconds(), time.perf_counter()
    stamp("study+")
    result = run_study(name, sets, out, workers=workers, progress=False, **keywords)
    stamp("study-")
    wall = time.perf_counter() - start
    shutdown_pools()  # the workers' CPU time is counted once they have ended
    shutil.rmtree(out, ignore_errors=True)
    report = result.report
    figures = {"wall": wall, "cpu": cpu_seconds() - cpu, "load": load, "backend": report.backend, "figure": plotted[0]}
    print(json.dumps({**figures, "runs": report.computed}))


def child_precompute(values: list[float]) -> None:
    """Each track's precompute (pad stiffness ``values``, MN/m) in turn in this process; prints wall and CPU."""
    from wheelrail.core.inputs.declared import model_parameters
    from wheelrail.core.track import moving_weights

    cpu, start = cpu_seconds(), time.perf_counter()
    for value in values:
        params = model_parameters({"pad_stiffness": value * 1e6})
        moving_weights(params.run.speed, params.run.time_step, params.track)
    print(json.dumps({"wall": time.perf_counter() - start, "cpu": cpu_seconds() - cpu}))


def phase_table(path: str) -> list[str]:
    """The phases file's stamps as lines: each process (the study's first, then the workers in the order they
    started), each phase's first start and last end (s from the study's start) and its CPU time (s: the process's
    CPU time across each call, summed; in the study's process a phase beside another counts both's CPU)."""
    stamps = []
    with open(path) as handle:
        for line in handle:
            pid, label, wall, cpu = line.split()
            stamps.append((int(pid), label, float(wall), float(cpu)))
    origin = next(wall for _, label, wall, _ in stamps if label == "study+")
    order: list[int] = []
    for pid, *_ in sorted(stamps, key=lambda item: item[2]):
        if pid not in order:
            order.append(pid)
    lines = []
    for number, pid in enumerate(order):
        own = [item for item in stamps if item[0] == pid]
        phases: dict[str, list] = {}  # label: [first start, last end, CPU, calls, open starts]
        for _, label, wall, cpu in own:
            name, edge = label[:-1], label[-1]
            entry = phases.setdefault(name, [wall, wall, 0.0, 0, []])
            if edge == "+":
                entry[0] = min(entry[0], wall)
                entry[4].append(cpu)
            elif entry[4]:
                entry[1], entry[2], entry[3] = wall, entry[2] + cpu - entry[4].pop(), entry[3] + 1
        who = "study's process" if number == 0 else f"worker process {number}"
        lines.append(
            f"  {who} (pid {pid}), CPU {own[-1][3] - (own[0][3] if number == 0 else 0.0):.2f} s to its last stamp:"
        )
        for name, (first, last, cpu, calls, _) in sorted(phases.items(), key=lambda item: item[1][0]):
            times = f" x{calls}" if calls > 1 else ""
            lines.append(f"    {name:14s}{times:6s} {first - origin:6.2f} -> {last - origin:6.2f} s, CPU {cpu:5.2f} s")
    return [*lines, critical_path(stamps, order)]


def critical_path(stamps: list[tuple], order: list[int]) -> str:
    """The study's longest path in CPU seconds (what its wall time would be with a core for each process): the
    study's process before its runs' dispatch, the longer of its CPU in the dispatch and the run workers' CPU, its CPU
    after the dispatch but for its half of the figure's drawing, the longer of the two halves' drawing."""
    main = order[0]

    def cpu_at(label: str, pid: int = main, last: bool = False) -> float:
        found = [item[3] for item in stamps if item[0] == pid and item[1] == label]
        return found[-1] if last else found[0]

    def total(pid: int) -> float:
        return max(item[3] for item in stamps if item[0] == pid)

    def drawing(pid: int) -> float:
        starts = [item[3] for item in stamps if item[0] == pid and item[1] == "figure-draw+"]
        ends = [item[3] for item in stamps if item[0] == pid and item[1] == "figure-draw-"]
        return sum(end - start for start, end in zip(starts, ends, strict=False))

    labels = {pid: {item[1] for item in stamps if item[0] == pid} for pid in order}
    runners = [pid for pid in order[1:] if "child+" in labels[pid]]
    drawers = [pid for pid in order[1:] if "figure-child+" in labels[pid]]
    before = cpu_at("dispatch+") - cpu_at("study+")
    shares = [cpu_at("dispatch-", last=True) - cpu_at("dispatch+"), *(total(pid) for pid in runners)]
    runs = max(shares)
    own_drawing = drawing(main)
    after = cpu_at("study-") - cpu_at("dispatch-", last=True) - own_drawing
    draw = max([own_drawing, *(drawing(pid) for pid in drawers)])
    each = " / ".join(f"{value:.2f}" for value in shares)
    return (
        f"  CPU critical path: {before:.2f} before the runs + {runs:.2f} runs (of {each})"
        f" + {after:.2f} after them + {draw:.2f} "
        f"drawing = {before + runs + after + draw:.2f} s"
    )


def _spawn(arguments: list[str], environment: dict | None = None) -> subprocess.Popen:
    env = {**os.environ, **(environment or {})}
    command = [sys.executable, str(Path(__file__).resolve()), *arguments]
    return subprocess.Popen(command, env=env, stdout=subprocess.PIPE, text=True)


def _result(process: subprocess.Popen) -> dict:
    out, _ = process.communicate()
    if process.returncode != 0:
        raise SystemExit(f"a measurement failed (exit {process.returncode})")
    return json.loads(out.strip().splitlines()[-1])


def cache_without_tracks() -> str:
    """A disk cache of its own holding the user's entries but the tracks' (the wheel's modes, the rail's radiation:
    what every track shares), linked, not copied: every track a new one."""
    from wheelrail.core.files.cache import cache_dir

    folder = tempfile.mkdtemp(prefix="wheelrail-bench-cache-")
    for entry in cache_dir().glob("*.npz"):
        if not entry.name.startswith("track-"):
            try:
                os.link(entry, Path(folder) / entry.name)
            except OSError:
                shutil.copy2(entry, Path(folder) / entry.name)
    return folder


def measure(name: str, workers: int, quick: bool, backend: str, pin: bool = False, phases: bool = False) -> dict:
    """The study in a fresh process (the track study with a disk cache of its own without tracks); ``phases``: each
    process's phases stamped, printed after the measurement's line (``"phases"``: the lines)."""
    cache = cache_without_tracks() if name == "track" else None
    stamps = tempfile.mkstemp(prefix="wheelrail-bench-phases-")[1] if phases else None
    try:
        arguments = ["--child", name, "--workers", str(workers), "--backend", backend, *(["--quick"] * quick)]
        arguments += ["--pin"] * pin
        environment = {
            **({"WHEELRAIL_CACHE_DIR": cache} if cache else {}),
            **({"STUDY_WORKERS_PHASES": stamps} if stamps else {}),
        }
        found = _result(_spawn(arguments, environment))
        return {**found, "phases": phase_table(stamps) if stamps else []}
    finally:
        if cache:
            shutil.rmtree(cache, ignore_errors=True)
        if stamps:
            os.unlink(stamps)


def precompute_comparison() -> None:
    """Two new tracks: one process, two threads, one after the other; against two processes side by side, one
    thread each."""
    values = PAD_STIFFNESS_MN_M[:2]
    cache = cache_without_tracks()
    try:
        load, start = os.getloadavg()[0], time.perf_counter()
        serial = _result(_spawn(["--precompute-child", *map(str, values)], {"WHEELRAIL_CACHE_DIR": cache}))
        print(
            f"  2 new tracks, 1 process x 2 threads, one after the other: {time.perf_counter() - start:6.1f} s wall, "
            f"{serial['cpu']:6.1f} s CPU (load {load:.1f})"
        )
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    caches = [cache_without_tracks() for _ in values]
    try:
        load, start = os.getloadavg()[0], time.perf_counter()
        processes = [
            _spawn(["--precompute-child", str(v)], {"WHEELRAIL_CACHE_DIR": c, "NUMBA_NUM_THREADS": "1"})
            for v, c in zip(values, caches, strict=True)
        ]
        found = [_result(process) for process in processes]
        print(
            f"  2 new tracks, 2 processes x 1 thread, side by side:      {time.perf_counter() - start:6.1f} s wall, "
            f"{sum(f['cpu'] for f in found):6.1f} s CPU (load {load:.1f})"
        )
    finally:
        for cache in caches:
            shutil.rmtree(cache, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller studies: about a minute in all")
    parser.add_argument("--studies", nargs="+", default=["filters", "track", "impact"])
    parser.add_argument("--workers", nargs="+", type=int, default=[1, 2])
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--backend", default="auto", choices=("auto", "fork", "threads", "processes"))
    parser.add_argument("--pin", action="store_true", help="pin each study to as many CPUs as it has workers")
    parser.add_argument("--phases", action="store_true", help="each process's phases (start, end, CPU) printed")
    parser.add_argument("--precompute", action="store_true", help="also 2 tracks x 1 thread against 1 x 2")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--precompute-child", nargs="+", type=float, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child_study(args.child, args.workers[0], args.quick, args.backend, args.pin)
        return
    if args.precompute_child:
        child_precompute(args.precompute_child)
        return
    size = "quick sizes" if args.quick else "full sizes"
    pinned = ", each pinned to as many CPUs as workers" if args.pin else ""
    print(
        f"studies on 1 and 2 workers ({size}, backend {args.backend}{pinned}); {os.cpu_count()} CPUs; python "
        f"{sys.version.split()[0]}; each a fresh process, its wall time from run_study's call to its return"
    )
    for name in args.studies:
        walls: dict[int, list[float]] = {}
        rest: dict[int, list[float]] = {}  # the wall time but the figures'
        for _ in range(args.rounds):
            for workers in args.workers:
                found = measure(name, workers, args.quick, args.backend, args.pin, args.phases)
                walls.setdefault(workers, []).append(found["wall"])
                rest.setdefault(workers, []).append(found["wall"] - found["figure"])
                plural = "s" * (workers > 1)
                print(
                    f"  {name:8s} {workers} worker{plural}: {found['wall']:6.1f} s wall, {found['cpu']:6.1f} s CPU, "
                    f"figures {found['figure']:4.1f} s wall, {found['runs']} runs on {found['backend']} "
                    f"(load {found['load']:.1f})",
                    flush=True,
                )
                if found["phases"]:
                    print("\n".join(found["phases"]), flush=True)
        if 1 in walls and 2 in walls:
            print(
                f"  {name:8s} speed-up 1 -> 2 workers (best wall times): {min(walls[1]) / min(walls[2]):.2f}x; "
                f"without the figures {min(rest[1]) / min(rest[2]):.2f}x"
            )
    if args.precompute:
        precompute_comparison()


if __name__ == "__main__":
    main()
