"""Time of the fast test suite, `pytest -m "not slow"` (the README's figure; target: under a minute), and of
every test over 2 s.

Each repeat is a fresh pytest process (collection, imports, and the Green's functions of the tracks the
tests use: read from the tests' persistent cache, ``.pytest_cache/wheelrail-cache``, see tests/conftest.py,
or computed into it). Prints its wall time, the CPU time it and its child processes used, the load average
before it and how many cache entries it found (0: a cold session, as on a fresh clone, e.g. CI); then the
tests of the last repeat that took over ``--over`` seconds (pytest's ``--durations``: set-up, call and
tear-down apart). On a shared machine the wall time grows with the load while the CPU time stays.

    python3 benchmarks/fast_suite.py [REPEAT] [--cold] [--all] [--over SECONDS]

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
DURATION = re.compile(r"^(\d+\.\d+)s (setup|call|teardown)\s+(\S+)")


def cache_entries(base: Path) -> int:
    return sum(1 for _ in base.glob("*/*.npz")) if base.is_dir() else 0


def one_session(args, env) -> tuple[float, float, str, list[str]]:
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", f"--durations-min={args.over}"]
    command += ["--durations=0"] + ([] if args.all else ["-m", "not slow"])
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    lines = done.stdout.strip().splitlines()
    summary = lines[-1] if lines else f"exit {done.returncode}"
    return wall, cpu, summary, [line for line in lines if DURATION.match(line)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("repeat", type=int, nargs="?", default=2)
    parser.add_argument("--cold", action="store_true", help="an empty test cache for each repeat")
    parser.add_argument("--all", action="store_true", help="the whole suite, slow tests included")
    parser.add_argument("--over", type=float, default=2.0, help="list the tests over this many seconds")
    args = parser.parse_args()
    suite = "whole suite" if args.all else 'fast suite (-m "not slow")'
    print(f"{suite}, {os.cpu_count()} cores, {'cold' if args.cold else 'persistent'} test cache")
    print(f"{'run':>3} {'wall s':>7} {'cpu s':>6} {'load (1 min) before':>20} {'cache entries':>14}  result")
    slowest: list[str] = []
    for number in range(1, args.repeat + 1):
        env = dict(os.environ)
        env.pop("WHEELRAIL_CACHE_DIR", None)
        scratch = tempfile.TemporaryDirectory(prefix="wheelrail-test-cache-") if args.cold else None
        if scratch is not None:
            env["WHEELRAIL_TEST_CACHE_DIR"] = scratch.name
        base = Path(env.get("WHEELRAIL_TEST_CACHE_DIR") or ROOT / ".pytest_cache" / "wheelrail-cache")
        entries = cache_entries(base)
        load = os.getloadavg()[0]
        wall, cpu, summary, slowest = one_session(args, env)
        print(f"{number:>3} {wall:7.1f} {cpu:6.1f} {load:20.1f} {entries:>14}  {summary}")
        if scratch is not None:
            scratch.cleanup()
    print(f"\nlast run: {len(slowest)} set-ups, calls and tear-downs over {args.over:g} s")
    for line in slowest:
        print("  " + line)


if __name__ == "__main__":
    main()
