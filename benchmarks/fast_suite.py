"""Time of the fast test suite, `pytest -m "not slow"` (the README's figure; target: under a minute).

Each repeat is a fresh pytest process (collection, imports, and the session's private Green's-function cache
filled at the speeds the fast tests use, as in CI); prints its wall time and the CPU time it and its child
processes used. On a shared machine the wall time grows with the load while the CPU time stays: both are
printed, with the load average before each run.

    python3 benchmarks/fast_suite.py [REPEAT]
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import time
from pathlib import Path

REPEAT = int(sys.argv[1]) if len(sys.argv) > 1 else 2
ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    print(f"{'run':>3} {'wall s':>7} {'cpu s':>6} {'load (1 min) before':>20}  result")
    for number in range(1, REPEAT + 1):
        load = os.getloadavg()[0]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-m", "pytest", "-q", "-m", "not slow", "-p", "no:cacheprovider"],
            cwd=ROOT,
            capture_output=True,
            text=True,
        )
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        summary = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else f"exit {done.returncode}"
        print(f"{number:>3} {wall:7.1f} {cpu:6.1f} {load:20.1f}  {summary}")


if __name__ == "__main__":
    main()
