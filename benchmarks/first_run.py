"""A fresh install's first Run in the explorer, headless: each phase the page names, its time, the progress
bar and the estimates it was shown.

The Run goes through the explorer's own run path, ``wheelrail.explorer.controller.RunController`` (what the
Run button starts), with a listener in place of the page that records every status line, progress value and
frame; no browser and no viser server. The run is the page's default (``3d``, 3 m of the corrugated rail at
100 km/h, line 0), pressed at once (no background warm-up), in a fresh process with an empty Green's-function
cache folder (``WHEELRAIL_CACHE_DIR``) and an empty numba cache folder (``NUMBA_CACHE_DIR``): the track's
precompute and every compilation are counted, as on a fresh install.

Phases are the status lines with the seconds ticker (`` ... 12 s``), the counters (``(3 of 8)``) and the
estimates (``about 9 s left``) taken off. ``--base DIR`` runs the same in another checkout (with its
``DIR/.venv/bin/python``) right after, for a side-by-side figure; the load average is printed with each.
Target: under 60 s on a quiet 2-core machine, every phase named, a real progress bar and estimate.

    python3 benchmarks/first_run.py [--base /path/to/other/checkout]
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

_TICKER = re.compile(r" \.\.\.( \d+ s)?$")
_DETAILS = re.compile(r", about \d+ s left| \(\d+ of \d+\)$")  # the estimate, then a counter at the end


class _Recorder:
    """A RunListener that keeps what the page would show, with the time it was shown."""

    def __init__(self) -> None:
        self.start = time.perf_counter()
        self.lines: list[tuple[float, str]] = []
        self.progress_values: list[tuple[float, float]] = []
        self.first_frame: float | None = None
        self.outcome: str | None = None
        self.errors: list[str] = []
        self.done = threading.Event()

    def _now(self) -> float:
        return time.perf_counter() - self.start

    def status(self, text: str) -> None:
        self.lines.append((self._now(), text))

    def progress(self, fraction: float) -> None:
        self.progress_values.append((self._now(), float(fraction)))

    def frame(self, state, view) -> None:
        if self.first_frame is None:
            self.first_frame = self._now()

    def live(self, result, view) -> None:
        pass

    def model_done(self, entry, view) -> None:
        pass

    def error(self, message: str) -> None:
        self.errors.append(message)

    def finished(self, config, outcome: str) -> None:
        self.outcome = outcome
        self.done.set()


def _phase(text: str) -> str:
    """A status line without its ticker, estimate and counter: the phase it names."""
    text = _TICKER.sub("", text)
    while _DETAILS.search(text):
        text = _DETAILS.sub("", text)
    return text


def first_run_here() -> None:
    """In this process (its caches empty): the page's default Run through the controller; prints the phases."""
    from wheelrail.core.roughness import load_roughness
    from wheelrail.explorer.config import RunConfig
    from wheelrail.explorer.controller import RunController

    recorder = _Recorder()
    set_label = "corrugated-rail"
    controller = RunController(recorder)
    config = RunConfig(set_label=set_label, line=0, model="3d", length=3.0)
    controller.start(config, load_roughness(set_label))
    recorder.done.wait()
    total = recorder._now()
    phases: list[list] = []  # [name, first shown, last line's time, lines, estimates seen]
    for when, text in recorder.lines:
        name = _phase(text)
        if not phases or phases[-1][0] != name:
            phases.append([name, when, when, 0, []])
        phases[-1][2] = when
        phases[-1][3] += 1
        estimate = re.search(r"about (\d+) s", text)
        if estimate:
            phases[-1][4].append(int(estimate.group(1)))
    print(f"first Run, fresh install (empty track and numba caches), {config.label()}: {recorder.outcome}")
    for index, (name, began, _last, count, estimates) in enumerate(phases):
        ended = phases[index + 1][1] if index + 1 < len(phases) else total
        shown = f"; estimates shown {estimates[0]} .. {estimates[-1]} s" if estimates else ""
        print(f"  {began:6.1f} s  {ended - began:6.1f} s  {name}  ({count} status lines{shown})")
    values = [value for _, value in recorder.progress_values]
    rising = sum(1 for a, b in zip(values, values[1:], strict=False) if b > a)
    print(
        f"progress bar: {len(values)} updates, {rising} rises, last {values[-1] if values else float('nan'):.2f}; "
        f"first frame after {recorder.first_frame if recorder.first_frame is not None else float('nan'):.1f} s; "
        f"done after {total:.1f} s (target < 60 s); errors: {recorder.errors or 'none'}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", type=Path, help="another checkout, run right after with its .venv")
    parser.add_argument("--here", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.here:
        first_run_here()
        return
    pythons = {"this": sys.executable}
    if args.base is not None:
        pythons["base"] = str(args.base.resolve() / ".venv" / "bin" / "python")
    for label, python in pythons.items():
        with tempfile.TemporaryDirectory(prefix="wheelrail-first-run-") as folder:
            env = {
                **os.environ,
                "WHEELRAIL_CACHE_DIR": str(Path(folder) / "track"),
                "NUMBA_CACHE_DIR": str(Path(folder) / "numba"),
            }
            print(f"{label} ({python}), load {os.getloadavg()[0]:.1f} before", flush=True)
            subprocess.run([python, str(Path(__file__).resolve()), "--here"], env=env, check=True)
            print(f"  load {os.getloadavg()[0]:.1f} after", flush=True)


if __name__ == "__main__":
    main()
