"""Start-up time of the command line, side by side with the bare import of numpy and numba.

Each command runs as a fresh process (what a user waits for), after one warm-up run of each that fills the
Green's-function, wheel and numba caches and Python's bytecode cache; then REPEAT rounds, each running every
command once in turn (so that a busy moment of a shared machine hits all of them alike). Prints the median
and the fastest wall time and, for the fastest, the ratio to ``python -c "import numpy, numba"``; and the
least CPU time (user + system) of each and its ratio, which a busy machine disturbs less than the wall time.

The commands run with Python's bytecode cache on (``PYTHONDONTWRITEBYTECODE`` removed from their
environment), as in an installed package: with it off, every start compiles wheelrail's modules from source
again (about 0.15 s more), while numpy and numba come with their bytecode compiled at installation.

Targets: a cached ``wheelrail run`` of a one-line model (7.5 m) and ``wheelrail spectra`` on its output each
within 2x the bare import; ``wheelrail --help`` under 0.3 s; a cached ``wheelrail track`` under 1 s.

``--base DIR`` runs another checkout's commands (with its ``DIR/.venv/bin/python``) in the same rounds,
each command of both checkouts in turn, so that the two see the same moments of a shared machine; the load
average is printed with each table (1-minute, before and after the rounds).

    python3 benchmarks/startup.py [--repeat N] [--base /path/to/other/checkout]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BASELINE = "python -c 'import numpy, numba'"


def commands(folder: Path, python: str) -> dict[str, list[str]]:
    cli = [python, "-m", "wheelrail"]  # the console script's command
    out = str(folder / "hertz.npz")
    return {
        "python -c pass (interpreter alone)": [python, "-c", "pass"],
        BASELINE: [python, "-c", "import numpy, numba"],
        "wheelrail --help": [*cli, "--help"],
        "wheelrail run hertz 7.5 m (cached)": [
            *cli,
            "run",
            "--set",
            "corrugated-rail",
            "--model",
            "hertz",
            "--length-m",
            "7.5",
            "--out",
            out,
        ],
        "wheelrail spectra (that run's .npz)": [*cli, "spectra", out],
        "wheelrail track (cached)": [*cli, "track"],
    }


def _children_cpu() -> float:
    """CPU seconds (user + system) of this process's finished children: on a shared machine, less disturbed
    by the other processes than the wall time."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="rounds (default 7)")
    parser.add_argument("--base", type=Path, help="another checkout, run with its .venv, interleaved")
    args = parser.parse_args()
    checkouts = {"this": sys.executable}
    if args.base is not None:
        checkouts["base"] = str(args.base.resolve() / ".venv" / "bin" / "python")
    environment = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
    with tempfile.TemporaryDirectory() as folder:
        argvs = {
            label: commands(Path(folder) / label, python) for label, python in checkouts.items()
        }  # each checkout its own run output
        for label in argvs:
            (Path(folder) / label).mkdir()
            for argv in argvs[label].values():  # warm-up: caches filled (and the run's output written for spectra)
                subprocess.run(argv, check=True, capture_output=True, env=environment, cwd=folder)
        times = {label: {name: [] for name in argvs[label]} for label in argvs}
        cpu = {label: {name: [] for name in argvs[label]} for label in argvs}
        load_before = os.getloadavg()[0]
        for _ in range(args.repeat):
            for name in argvs["this"]:
                for label in argvs:
                    start, cpu_start = time.perf_counter(), _children_cpu()
                    subprocess.run(argvs[label][name], check=True, capture_output=True, env=environment, cwd=folder)
                    times[label][name].append(time.perf_counter() - start)
                    cpu[label][name].append(_children_cpu() - cpu_start)
        load_after = os.getloadavg()[0]
    for label, python in checkouts.items():
        base, base_cpu = min(times[label][BASELINE]), min(cpu[label][BASELINE])
        print(f"{label} ({python}); load {load_before:.1f} before, {load_after:.1f} after; {args.repeat} rounds")
        print(
            f"{'command':<38} {'median s':>9} {'fastest s':>10} {'/ bare import':>14} {'least CPU s':>12} {'/ bare':>7}"
        )
        for name, values in times[label].items():
            least = min(cpu[label][name])
            print(
                f"{name:<38} {statistics.median(values):9.3f} {min(values):10.3f} {min(values) / base:13.2f}x "
                f"{least:12.3f} {least / base_cpu:6.2f}x"
            )
        print()


if __name__ == "__main__":
    main()
