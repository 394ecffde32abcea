"""Time of the test suite as the README runs it, fast part (`-m "not slow"`; target: under a minute on a quiet
2-core machine) or whole (`--all`; target: under 5 minutes), and of every test over 2 s.

The README's command runs the tests in two pytest-xdist worker processes, ``pytest -n 2 --dist worksteal``
(``--workers 2``, the default: both cores of a 2-core machine; ``--workers 0``: one process, no xdist). With
worksteal each worker starts on its own half of the tests in order (a module's tests mostly stay in one worker,
which computes its module fixtures once) and takes tests from the other's queue when its own is done.

Each repeat is a fresh pytest session (collection, imports, and the Green's functions of the tracks the tests use:
read from the tests' persistent cache, ``.pytest_cache/wheelrail-cache``, see tests/conftest.py, or computed into
it). Prints its wall time, the CPU time it and its child processes used (the workers included), the load average
before and after it, the cores that other processes kept busy meanwhile (from /proc/stat: the machine's busy CPU
time less the suite's, over the wall time) and how many cache entries it found (0: a cold session, as on a fresh
clone, e.g. CI); then the tests of the last repeat that took over ``--over`` seconds (pytest's ``--durations``:
set-up, call and tear-down apart; with workers, each test's time in its worker). On a shared machine the wall time grows
with the load while the CPU time stays; with two workers a quiet machine's wall time is about half the CPU time. It
also says whether Python may write its bytecode (``PYTHONDONTWRITEBYTECODE`` set: every process compiles every
module it imports, the tests' rewritten ones too). pytest runs with the checkout's ``.venv/bin/python`` if there is
one (the README's set-up), else with the Python running this script.

    python3 benchmarks/fast_suite.py [REPEAT] [--workers N] [--cold] [--all] [--over SECONDS]

``--cold``: each repeat in an empty temporary test cache (what a fresh clone's first session costs);
``--all``: the whole suite, slow tests included (CI's command).
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# the checkout's virtual environment (the README's set-up) if there is one: `python3 benchmarks/fast_suite.py`
# then times the suite as the README runs it, not with a Python lacking the test extra
VENV_PYTHON = ROOT / ".venv" / "bin" / "python"
PYTHON = str(VENV_PYTHON) if VENV_PYTHON.is_file() else sys.executable
DURATION = re.compile(r"^(\d+\.\d+)s (setup|call|teardown)\s+(\S+)")


def cache_entries(base: Path) -> int:
    return sum(1 for _ in base.glob("*/*.npz")) if base.is_dir() else 0


def busy_cpu_s() -> float | None:
    """CPU seconds the whole machine has spent busy since boot (Linux's /proc/stat), or None elsewhere."""
    try:
        fields = [int(v) for v in Path("/proc/stat").read_text().splitlines()[0].split()[1:]]
    except (OSError, ValueError, IndexError):
        return None
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)  # idle and waiting for I/O
    return (sum(fields[:8]) - idle) / os.sysconf("SC_CLK_TCK")


def one_session(args, env) -> tuple[float, float, str, list[str]]:
    command = [PYTHON, "-m", "pytest", "-q", "-p", "no:cacheprovider", f"--durations-min={args.over}"]
    command += ["--durations=0"] + ([] if args.all else ["-m", "not slow"])
    command += ["-n", str(args.workers), "--dist", "worksteal"] if args.workers else []
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    lines = done.stdout.strip().splitlines()
    summary = lines[-1] if lines else f"exit {done.returncode}"
    for line in lines:
        if line.startswith(("FAILED ", "ERROR ")):
            print("    " + line)  # the summary's failures, so that a failed run says which
    return wall, cpu, summary, [line for line in lines if DURATION.match(line)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("repeat", type=int, nargs="?", default=2)
    parser.add_argument("--cold", action="store_true", help="an empty test cache for each repeat")
    parser.add_argument("--all", action="store_true", help="the whole suite, slow tests included")
    parser.add_argument("--over", type=float, default=2.0, help="list the tests over this many seconds")
    parser.add_argument(
        "--workers", type=int, default=2, help="pytest-xdist worker processes (-n; default 2: the README's command)"
    )
    args = parser.parse_args()
    suite = "whole suite" if args.all else 'fast suite (-m "not slow")'
    mode = f"-n {args.workers} --dist worksteal (pytest-xdist)" if args.workers else "one process (no -n)"
    bytecode = "not written (PYTHONDONTWRITEBYTECODE)" if os.environ.get("PYTHONDONTWRITEBYTECODE") else "cached"
    print(f"{suite}, {mode}, {os.cpu_count()} cores, {'cold' if args.cold else 'persistent'} test cache")
    print(f"Python bytecode {bytecode}")
    head = f"{'run':>3} {'wall s':>7} {'cpu s':>6} {'load (1 min) before, after':>27} {'others, cores':>13}"
    print(f"{head} {'cache entries':>14}  result")
    slowest: list[str] = []
    for number in range(1, args.repeat + 1):
        env = dict(os.environ)
        env.pop("WHEELRAIL_CACHE_DIR", None)
        scratch = tempfile.TemporaryDirectory(prefix="wheelrail-test-cache-") if args.cold else None
        if scratch is not None:
            env["WHEELRAIL_TEST_CACHE_DIR"] = scratch.name
        base = Path(env.get("WHEELRAIL_TEST_CACHE_DIR") or ROOT / ".pytest_cache" / "wheelrail-cache")
        entries = cache_entries(base)
        load, busy = os.getloadavg()[0], busy_cpu_s()
        wall, cpu, summary, slowest = one_session(args, env)
        after, busy_after = os.getloadavg()[0], busy_cpu_s()
        # the cores the machine's other processes kept busy meanwhile, on average (what the load hides)
        others = "" if busy is None else f"{max(0.0, busy_after - busy - cpu) / wall:13.2f}"
        print(f"{number:>3} {wall:7.1f} {cpu:6.1f} {load:20.1f} {after:6.1f} {others:>13} {entries:>14}  {summary}")
        if scratch is not None:
            scratch.cleanup()
    print(f"\nlast run: {len(slowest)} set-ups, calls and tear-downs over {args.over:g} s")
    for line in slowest:
        print("  " + line)


if __name__ == "__main__":
    main()
