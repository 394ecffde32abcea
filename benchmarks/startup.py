"""Start-up time of the command line, side by side with the bare import of numpy and numba.

Each command runs as a fresh process (what a user waits for), after one warm-up run of each that fills the
Green's-function, wheel and numba caches and Python's bytecode cache; then REPEAT rounds, each running every
command once in turn (so that a busy moment of a shared machine hits all of them alike). Prints the median
and the fastest wall time and, for the fastest, the ratio to ``python -c "import numpy, numba"``.

The commands run with Python's bytecode cache on (``PYTHONDONTWRITEBYTECODE`` removed from their
environment), as in an installed package: with it off, every start compiles wheelrail's modules from source
again (about 0.15 s more), while numpy and numba come with their bytecode compiled at installation.

Targets: a cached ``wheelrail run`` of a one-line model (7.5 m) and ``wheelrail spectra`` on its output each
within 2x the bare import; ``wheelrail --help`` under 0.3 s; a cached ``wheelrail track`` under 1 s.

    python3 benchmarks/startup.py [REPEAT]
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPEAT = int(sys.argv[1]) if len(sys.argv) > 1 else 7
BASELINE = "python -c 'import numpy, numba'"


def commands(folder: Path) -> dict[str, list[str]]:
    cli = [sys.executable, "-m", "wheelrail"]  # the console script's command
    out = str(folder / "hertz.npz")
    return {
        "python -c pass (interpreter alone)": [sys.executable, "-c", "pass"],
        BASELINE: [sys.executable, "-c", "import numpy, numba"],
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


def main() -> None:
    environment = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
    with tempfile.TemporaryDirectory() as folder:
        argvs = commands(Path(folder))
        for argv in argvs.values():  # warm-up: caches filled (and the run's output written for spectra)
            subprocess.run(argv, check=True, capture_output=True, env=environment)
        times: dict[str, list[float]] = {name: [] for name in argvs}
        for _ in range(REPEAT):
            for name, argv in argvs.items():
                start = time.perf_counter()
                subprocess.run(argv, check=True, capture_output=True, env=environment)
                times[name].append(time.perf_counter() - start)
    base = min(times[BASELINE])
    print(f"{'command':<38} {'median s':>9} {'fastest s':>10} {'fastest / bare import':>22}   ({REPEAT} rounds)")
    for name, values in times.items():
        print(f"{name:<38} {statistics.median(values):9.3f} {min(values):10.3f} {min(values) / base:21.2f}x")


if __name__ == "__main__":
    main()
