"""Start-up time of the command line: `wheelrail --help` and a cached `wheelrail track`.

Each command runs as a fresh process (what a user waits for), REPEAT times after one warm-up run that fills
the Green's-function and receptance-peak caches and the numba cache; prints the median and the fastest
wall time. Targets: `--help` under 0.3 s, cached `track` under 1 s. The machine's load shows in the
spread: the fastest run is the best estimate of the cost itself.

    python3 benchmarks/startup.py [REPEAT]
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time

REPEAT = int(sys.argv[1]) if len(sys.argv) > 1 else 7
COMMANDS = {
    "python -c pass (interpreter alone)": [sys.executable, "-c", "pass"],
    "wheelrail --help": [sys.executable, "-m", "wheelrail", "--help"],
    "wheelrail track (cached)": [sys.executable, "-m", "wheelrail", "track"],
}


def wall_times(argv: list[str]) -> list[float]:
    subprocess.run(argv, check=True, capture_output=True)  # warm-up: caches filled
    times = []
    for _ in range(REPEAT):
        start = time.perf_counter()
        subprocess.run(argv, check=True, capture_output=True)
        times.append(time.perf_counter() - start)
    return times


def main() -> None:
    print(f"{'command':<38} {'median s':>9} {'fastest s':>10}   ({REPEAT} runs each)")
    for name, argv in COMMANDS.items():
        times = wall_times(argv)
        print(f"{name:<38} {statistics.median(times):9.3f} {min(times):10.3f}")


if __name__ == "__main__":
    main()
