"""What the roughness's anti-alias filter changes where a set is read on a coarser model grid, per force band.

A run reads a roughness set on its element size (``roughness.grid.to_model_grid``). Where the set's spacing is
finer than the element (the bundled wheel sets, 0.5 mm, at 1 and 2 mm; the rail set, 1 mm, at 2 mm) the lines are
low-passed first (``roughness.grid.anti_alias``); picking every q-th sample instead (linear interpolation alone,
as the paper and this project did before) folds the roughness at wavelengths below two elements back onto longer
ones, where no contact filter removes it.

This script runs each one-line model on line 0 of each bundled set at each element size coarser than the set's
spacing three times: on the set as a run reads it (low-passed), on its every q-th sample (no filter) and, the
reference, at the set's own spacing (nothing resampled; a finer grid, so the model's own discretisation error is
in the comparison too). It prints the third-octave force levels (dB re 1 N) of the first and each one's
difference from the reference per band, then per model and size the largest |difference| over the sets.

Run: python3 validation/roughness_aliasing.py [--length-m 3] [--speed-kmh 100] [--sets ...] [--models ...]
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import bundled_names, load_roughness
from wheelrail.core.spectra.bands import band_labels
from wheelrail.core.spectra.force import force_spectrum

SIZES_MM = (1.0, 2.0)
MODELS = ("hertz", "hertz-winkler", "hertz-average", "2d")


def sample_picked(rough, size: float):
    """Every q-th sample of ``rough`` at spacing ``size`` (m, q >= 2 times its own: no filter), or None where the
    run's grid is not coarser than the set's."""
    q = int(round(size / rough.dx))
    if q < 2 or abs(q * rough.dx - size) > 1e-9 * size:
        return None
    return rough.with_heights(rough.heights[:, ::q], dx=size, note=f"every {q}th sample")


def levels(rough, model: str, size: float, speed: float, length: float) -> tuple[np.ndarray, np.ndarray]:
    params = replace(ModelParameters(), run=RunParameters(speed=speed, element_size=size))
    return force_spectrum(simulate(rough, model=model, line=0, params=params, length=length))


def _row(values, signed: bool = True) -> str:
    return " ".join(("   n/a" if not np.isfinite(v) else f"{v:+6.2f}" if signed else f"{v:6.1f}") for v in values)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--length-m", type=float, default=3.0, help="run length, m (default 3)")
    parser.add_argument("--speed-kmh", type=float, default=100.0, help="train speed, km/h (default 100)")
    parser.add_argument("--sets", nargs="+", default=None, help="roughness sets (default: every bundled set)")
    parser.add_argument("--models", nargs="+", default=list(MODELS), help="contact models (default: one-line)")
    args = parser.parse_args()
    speed = args.speed_kmh * KMH
    print(f"roughness aliasing: {args.length_m:g} m at {args.speed_kmh:g} km/h on line 0")
    worst: dict = {}
    labels = None
    for set_name in args.sets or bundled_names():
        rough = load_roughness(set_name)
        for size_mm in SIZES_MM:
            picked = sample_picked(rough, size_mm * 1e-3)
            if picked is None:
                continue
            for model in args.models:
                centres, run = levels(rough, model, size_mm * 1e-3, speed, args.length_m)
                _, plain = levels(picked, model, size_mm * 1e-3, speed, args.length_m)
                _, own = levels(rough, model, rough.dx, speed, args.length_m)
                labels = band_labels(centres)
                print(f"\n{set_name} ({rough.dx * 1e3:g} mm) at {size_mm:g} mm, {model}: level, differences, dB")
                print("  " + " ".join(f"{label:>6}" for label in labels))
                print("  " + _row(run, signed=False) + "  low-passed (as a run reads it)")
                for row, what in ((plain - own, "no filter - own spacing"), (run - own, "low-passed - own spacing")):
                    print("  " + _row(row) + f"  {what}")
                    key = (model, size_mm, what)
                    worst[key] = np.fmax(worst.get(key, np.full(row.shape, np.nan)), np.abs(row))
    print("\nLargest |difference from the set's own spacing| over the sets, dB, per band")
    print(f"  {'':>40} " + " ".join(f"{label:>6}" for label in labels))
    for (model, size_mm, what), row in worst.items():
        cells = " ".join(f"{v:6.2f}" if np.isfinite(v) else "   n/a" for v in row)
        name = f"{model} {size_mm:g} mm, {what.split(' - ')[0]}"
        print(f"  {name:>40} {cells}   max {np.nanmax(row):.2f}")


if __name__ == "__main__":
    main()
