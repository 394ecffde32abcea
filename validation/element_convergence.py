"""Convergence of the force spectra in the element size: third-octave force levels per band at 2, 1 and 0.5 mm.

Run: python3 validation/element_convergence.py [--length-m 3] [--speed-kmh 100] [--sets ...] [--models ...]
     [--save levels.json]
Runs every model on line 0 of every bundled roughness set (``wheelrail datasets``) at each element size (the
front ends' ``--element-mm``; ``core.inputs.ranges.ACCEPTED["element_size"]``), the same run length and speed, and
prints per set and model the levels (dB re 1 N) with their differences from the 0.5 mm run, then per model the
largest difference over the sets in each band and the bands where 1 mm and 2 mm differ from 0.5 mm by more than
``THRESHOLD_DB``. A band a run does not resolve (below 1 / analysed duration wide, or above its Nyquist frequency:
v / (2 dx), 6.9 kHz at 2 mm and 100 km/h) is ``n/a``. ``--save`` keeps the levels as JSON and skips the runs it
already holds (a long scan resumes).
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.models import model_names
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import bundled_names
from wheelrail.core.spectra.bands import band_labels
from wheelrail.core.spectra.force import force_spectrum

SIZES_MM = (2.0, 1.0, 0.5)  # the accepted range's ends and the default; the finest is the reference
THRESHOLD_DB = 1.0  # a band "changes" when a coarser grid differs from 0.5 mm by more than this


def levels_of(set_name: str, model: str, size_mm: float, speed: float, length: float) -> dict:
    """One run's force levels per band (dB re 1 N; None where not resolved) and its CPU time."""
    params = replace(ModelParameters(), run=RunParameters(speed=speed, element_size=size_mm * 1e-3))
    start = time.process_time()
    result = simulate(set_name, model=model, line=0, params=params, length=length)
    centres, levels = force_spectrum(result)
    return {
        "centres_hz": [float(c) for c in centres],
        "levels_db": [float(v) if np.isfinite(v) else None for v in levels],
        "steps": int(result.n_steps),
        "cpu_s": time.process_time() - start,
    }


def _cell(value) -> str:
    return "   n/a" if value is None else f"{value:6.1f}"


def _difference(a, b):
    return None if a is None or b is None else a - b


def print_case(set_name: str, model: str, runs: dict) -> None:
    """The levels at each size and their differences from the finest, one line per band."""
    finest = runs[SIZES_MM[-1]]
    labels = band_labels(np.array(finest["centres_hz"]))
    sizes = " ".join(f"{s:>5g}mm" for s in SIZES_MM)
    deltas = " ".join(f"{s:g}-{SIZES_MM[-1]:g}".rjust(7) for s in SIZES_MM[:-1])
    steps = ", ".join(f"{runs[s]['steps']} steps" for s in SIZES_MM)
    print(f"\n{set_name}, {model}: levels dB re 1 N ({steps})")
    print(f"  {'band Hz':>8} {sizes} | {deltas}")
    for k, label in enumerate(labels):
        row = [runs[s]["levels_db"][k] for s in SIZES_MM]
        diffs = [_difference(value, row[-1]) for value in row[:-1]]
        print(
            f"  {label:>8} "
            + " ".join(f"{_cell(v):>7}" for v in row)
            + " | "
            + " ".join(f"{'   n/a' if d is None else f'{d:+6.1f}':>7}" for d in diffs)
        )


def print_summary(results: dict, sets: list[str], models: list[str]) -> None:
    """Per model: the largest |difference| from 0.5 mm over the sets in each band, and the bands beyond the
    threshold."""
    print(f"\nLargest |L(dx) - L(0.5 mm)| over the sets {', '.join(sets)}, dB (n/a: not resolved at both sizes)")
    first = results[f"{sets[0]}|{models[0]}|{SIZES_MM[-1]:g}"]
    labels = band_labels(np.array(first["centres_hz"]))
    print(f"  {'band Hz':>8} " + " ".join(f"{m:>17}" for m in models))
    print(f"  {'':>8} " + " ".join(f"{'2 mm':>8} {'1 mm':>8}" for _ in models))
    changed = {(m, s): [] for m in models for s in SIZES_MM[:-1]}
    for k, label in enumerate(labels):
        cells = []
        for model in models:
            for size in SIZES_MM[:-1]:
                worst = None
                for set_name in sets:
                    fine = results[f"{set_name}|{model}|{SIZES_MM[-1]:g}"]["levels_db"][k]
                    coarse = results[f"{set_name}|{model}|{size:g}"]["levels_db"][k]
                    d = _difference(coarse, fine)
                    if d is not None and (worst is None or abs(d) > abs(worst)):
                        worst = d
                cells.append("     n/a" if worst is None else f"{worst:+8.1f}")
                if worst is not None and abs(worst) > THRESHOLD_DB:
                    changed[model, size].append(label)
        print(f"  {label:>8} " + " ".join(cells))
    print(f"\nBands where a coarser grid differs from 0.5 mm by more than {THRESHOLD_DB:g} dB on some set:")
    for model in models:
        for size in SIZES_MM[:-1]:
            bands = changed[model, size]
            print(f"  {model:>14} at {size:g} mm: {', '.join(bands) + ' Hz' if bands else 'none'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--length-m", type=float, default=3.0, help="run length, m (default 3)")
    parser.add_argument("--speed-kmh", type=float, default=100.0, help="train speed, km/h (default 100)")
    parser.add_argument("--sets", nargs="+", default=None, help="roughness sets (default: every bundled set)")
    parser.add_argument("--models", nargs="+", default=None, help="contact models (default: every built-in)")
    parser.add_argument("--save", type=Path, default=None, help="keep the levels in this JSON file (and resume)")
    args = parser.parse_args()
    sets = args.sets or list(bundled_names())
    models = args.models or list(model_names())
    results = json.loads(args.save.read_text()) if args.save is not None and args.save.is_file() else {}
    print(f"element convergence: {args.length_m:g} m at {args.speed_kmh:g} km/h on line 0, sizes {SIZES_MM} mm")
    started = time.perf_counter()
    for set_name in sets:
        for model in models:
            for size in SIZES_MM:
                key = f"{set_name}|{model}|{size:g}"
                if key not in results:
                    results[key] = levels_of(set_name, model, size, args.speed_kmh * KMH, args.length_m)
                    if args.save is not None:
                        args.save.write_text(json.dumps(results))
            print_case(set_name, model, {s: results[f"{set_name}|{model}|{s:g}"] for s in SIZES_MM})
    print_summary(results, sets, models)
    cpu = sum(results[f"{s}|{m}|{z:g}"]["cpu_s"] for s in sets for m in models for z in SIZES_MM)
    runs = len(sets) * len(models) * len(SIZES_MM)
    print(f"\n{runs} runs, {cpu:.0f} s CPU (this call {time.perf_counter() - started:.0f} s wall)")


if __name__ == "__main__":
    main()
