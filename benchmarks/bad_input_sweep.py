"""Sweep of bad inputs to the command line: each case ends in one of four classes.

* ``clear``: non-zero exit and one line on stderr naming what is wrong (no traceback, no "internal error");
* ``internal``: an "internal error" line or a traceback;
* ``hang``: no exit within the timeout;
* ``silent-wrong``: exit 0 with an answer that is not physics (NaN force, period-2 chatter, no steps).

Cases that must succeed (``ok``) are checked for a sound answer too. Run it after changing input handling:

    python3 benchmarks/bad_input_sweep.py [--timeout 120]

It prints one row per case and the count per class; the exit code is 1 if any case is internal, hang or
silent-wrong, or a case meant to succeed did not.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

WHEELRAIL = [sys.executable, "-m", "wheelrail"]


def _files(folder: Path) -> dict[str, str]:
    """Bad and good input files for the cases."""
    from wheelrail.core.roughness import load_roughness, write_csv, write_npz

    rail = load_roughness("corrugated-rail")
    small = rail.with_heights(rail.heights[:, :3000], note="3 m")
    good_npz = write_npz(small, folder / "in.npz")
    write_csv(small, folder / "in.csv")
    coarse = folder / "coarse.csv"
    coarse.write_text("# kind: rail\nx_m,y_mm=0\n0,0\n1e6,1\n2e6,0\n")
    damaged = folder / "damaged.npz"
    data = bytearray(Path(good_npz).read_bytes())
    data[len(data) // 2] ^= 0xFF  # one byte of an array's data: the member's CRC no longer matches
    damaged.write_bytes(bytes(data))
    (folder / "empty.csv").write_text("")
    (folder / "handmade.npz").write_bytes(Path(good_npz).read_bytes())  # a roughness file, not a run file
    (folder / "underscore.csv").write_text("# kind: rail\nx_m,y_mm=0\n0,1\n0.001,1_0\n")
    (folder / "tinystep.csv").write_text("# kind: rail\nx_m,y_mm=0\n0,1\n1e-300,2\n")
    (folder / "wide.csv").write_text("# kind: rail\nx_m,y_mm=0,y_mm=1e300\n0,1,2\n0.001,2,1\n")
    from wheelrail.core.engine.results import RunHeader, RunResult
    from wheelrail.core.parameters import ModelParameters

    n = 500  # a 0.5 m run: too short for a force spectrum at 100 km/h (0.572 m)
    t = np.arange(n) * 3.6e-5
    RunResult(
        header=RunHeader(model="hertz", line=0, roughness_name="corrugated-rail", params=ModelParameters()),
        time=t,
        x=np.arange(n) * 1e-3,
        force=65e3 + 1e3 * np.sin(2e3 * np.pi * t),
        xi_wheel=np.zeros(n),
        xi_rail=np.zeros(n),
        roughness=np.zeros(n),
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5),
        equivalent_roughness=np.zeros(n),
    ).save_npz(folder / "short-run.npz")
    long_cell = folder / "longcell.csv"
    long_cell.write_text("# kind: rail\nx_m,y_mm=0\n" + "0," + "1" * 200_000 + "\n")
    return {
        "dir": str(folder),
        "npz": str(good_npz),
        "csv": str(folder / "in.csv"),
        "coarse": str(coarse),
        "damaged": str(damaged),
        "empty": str(folder / "empty.csv"),
        "handmade": str(folder / "handmade.npz"),
        "longcell": str(long_cell),
        "underscore": str(folder / "underscore.csv"),
        "tinystep": str(folder / "tinystep.csv"),
        "wide": str(folder / "wide.csv"),
        "short_run": str(folder / "short-run.npz"),
    }


def _cases(f: dict[str, str]) -> list[tuple[str, list[str]]]:
    """(expected class, argv after `wheelrail`): "clear" for bad input, "ok" for what must work."""
    run = ["run", "--set", "corrugated-rail", "--json"]
    return [
        ("clear", [*run, "--speed-kmh", "3", "--length-m", "0.5"]),
        ("clear", [*run, "--speed-kmh", "1e-300"]),
        ("clear", [*run, "--speed-kmh", "1e308"]),
        ("clear", [*run, "--speed-kmh", "nan"]),
        ("clear", [*run, "--speed-kmh", "-5"]),
        ("clear", [*run, "--preload-kn", "0"]),
        ("clear", [*run, "--preload-kn", "inf"]),
        ("clear", [*run, "--length-m", "1e9"]),
        ("clear", [*run, "--length-m", "-1"]),
        ("clear", [*run, "--model", "3d", "--length-m", "1e5"]),
        ("clear", [*run, "--model", "3d", "--line", "5", "--length-m", "0.1"]),
        ("clear", [*run, "--model", "bogus"]),
        ("clear", [*run, "--line", "99"]),
        ("clear", [*run, "--wheel-set", "corrugated-rail", "--length-m", "0.1"]),
        ("clear", [*run, "--wheel-transverse-radius-mm", "-300", "--length-m", "0.1"]),
        ("clear", [*run, "--length-m", "0.1", "--rrd", f"{f['dir']}/x.rrd", "--record-every", "1e20"]),
        ("clear", ["run", "--set", f["npz"], "--out", f["npz"], "--length-m", "0.1"]),
        (
            "clear",
            ["run", "--set", f["npz"], "--out", f"{f['dir']}/../{Path(f['dir']).name}/in.npz", "--length-m", "0.1"],
        ),
        ("clear", ["run", "--set", "corrugated-rail", "--out", "/proc/x.npz", "--length-m", "0.1"]),
        ("clear", ["run", "--set", f["coarse"]]),
        ("clear", ["run", "--set", f["damaged"]]),
        ("clear", ["run", "--set", f["empty"]]),
        ("clear", ["run", "--set", f["longcell"]]),
        ("clear", ["run", "--set", f"{f['dir']}/missing.csv"]),
        ("clear", ["spectra", f["handmade"]]),
        ("clear", ["track", "--df-hz", "1e-9"]),
        ("clear", ["track", "--plot", f"{f['dir']}/r.txt"]),
        ("clear", ["explore", "--port", "-1"]),
        ("clear", ["explore", "--port", "70000"]),
        ("clear", ["explore", "--host", "999.1.1.1"]),
        (
            "clear",
            [
                "study",
                "filters",
                "--set",
                "corrugated-rail",
                "--out",
                f["dir"],
                "--dask",
                "tcp://127.0.0.1:1",
                "--workers",
                "2",
            ],
        ),
        ("clear", ["study", "bogus", "--set", "corrugated-rail", "--out", f["dir"]]),
        ("clear", ["filters", "--preload-kn", "-1"]),
        # only physical inputs (core/inputs/ranges.py): each of these ran silently once
        ("clear", [*run, "--wheel-radius-mm", "0.001", "--length-m", "0.5"]),
        ("clear", [*run, "--wheel-radius-mm", "1e6", "--length-m", "0.5"]),
        ("clear", [*run, "--rail-crown-radius-mm", "0.001", "--length-m", "0.5"]),
        (
            "clear",
            [*run, "--rail-crown-radius-mm", "300", "--wheel-transverse-radius-mm", "-300.5", "--length-m", "0.5"],
        ),
        ("clear", [*run, "--preload-kn", "5000", "--length-m", "0.5"]),
        ("clear", [*run, "--preload-kn", "0.1", "--length-m", "0.5"]),
        ("clear", ["filters", "--preload-kn", "1e12"]),
        ("clear", ["track", "--speed-kmh", "401"]),
        ("clear", ["track", "--speed-kmh", "4"]),
        ("clear", [*run, "--wheel-set", "sinter-wheel-1", "--length-m", "0.5"]),
        # impossible files and outputs: each once read or ran silently
        ("clear", ["run", "--set", f["underscore"]]),
        ("clear", ["run", "--set", f["tinystep"]]),
        ("clear", ["run", "--set", f["wide"]]),
        ("clear", [*run, "--length-m", "0.1", "--out", ""]),
        ("clear", ["study", "filters", "--set", "corrugated-rail", "--out", ""]),
        ("clear", ["noise", "--run", f["short_run"]]),
        ("clear", ["noise", "--run", f["short_run"], "--train-length-m", "1e300"]),
        ("clear", ["noise", "--run", f["short_run"], "--train-axles", "40", "--train-length-m", "2.5"]),
        ("ok", [*run, "--speed-kmh", "5", "--length-m", "0.5"]),
        ("ok", [*run, "--speed-kmh", "6.85", "--length-m", "0.5"]),
        ("ok", [*run, "--speed-kmh", "400", "--length-m", "1.0"]),
        ("ok", [*run, "--model", "3d", "--line", "2", "--length-m", "0.3"]),
        ("ok", ["run", "--set", f["csv"], "--json", "--length-m", "0.5"]),
        ("ok", [*run, "--wheel-set", "sinter-wheel-1", "--wheel-radius-mm", "461.5", "--length-m", "0.5"]),
    ]


def _sound(stdout: str) -> str | None:
    """Why a successful run's JSON is not physics, or None."""
    try:
        summary = json.loads(stdout)
    except json.JSONDecodeError:
        return None  # not a run summary (e.g. a table): nothing to check
    if "force_mean_n" not in summary:
        return None
    if not summary["steps"]:
        return "no steps"
    if not all(np.isfinite([summary["force_mean_n"], summary["force_min_n"], summary["force_max_n"]])):
        return "NaN force"
    if summary["loss_of_contact_steps"] > summary["steps"] // 4:
        return f"contact lost in {summary['loss_of_contact_steps']} of {summary['steps']} steps (chatter)"
    return None


def classify(argv: list[str], timeout: float) -> tuple[str, str]:
    try:
        done = subprocess.run([*WHEELRAIL, *argv], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "hang", f"no exit within {timeout:g} s"
    err = done.stderr.strip()
    if "internal error" in err or "Traceback" in err:
        return "internal", err.splitlines()[-1] if err else ""
    if done.returncode == 0:
        why = _sound(done.stdout)
        return ("silent-wrong", why) if why else ("ok", "")
    lines = [line for line in err.splitlines() if line.strip()]
    return ("clear", lines[-1]) if lines else ("internal", f"exit {done.returncode} with nothing on stderr")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds before a case counts as a hang")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="wheelrail-sweep-"))
    try:
        cases = _cases(_files(folder))
        counts: dict[str, int] = {}
        failed = 0
        for expected, argv in cases:
            start = time.perf_counter()
            got, detail = classify(argv, args.timeout)
            counts[got] = counts.get(got, 0) + 1
            bad = got in ("internal", "hang", "silent-wrong") or got != expected
            failed += bad
            print(
                f"{'FAIL' if bad else 'ok  '} {got:12s} {time.perf_counter() - start:6.1f} s  "
                f"wheelrail {' '.join(argv)[:90]}\n{'':24s}{detail[:150]}"
            )
        print(
            "classes:",
            ", ".join(f"{name} {n}" for name, n in sorted(counts.items())),
            f"| {len(cases)} cases, {failed} not as expected",
        )
        return 1 if failed else 0
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
