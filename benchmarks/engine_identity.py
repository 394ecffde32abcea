"""The run engine's results against saved ones: every model, steady start and run-in from the preload.

Run: python3 benchmarks/engine_identity.py save DIR     (writes one .npz per case into DIR)
     python3 benchmarks/engine_identity.py compare DIR  (prints the largest relative difference per case and array)

Each case is a short run on the bundled corrugated rail: every built-in model from the steady start (the default)
and from the preload at rest (an explicit run-in), and for ``3d`` a run-in long enough for its tabulated law, a
run that keeps no pressure maps (recorded by chunks) and a run on 0.5 mm elements. The arrays compared are the
force, the wheel and rail displacements, the contact length and area, and the pressure maps where the model has
them. Save on one checkout, compare on another: ``compare`` exits 1 where a difference exceeds 1e-12 of the
array's largest magnitude.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from wheelrail.core.models import MODELS
from wheelrail.core.parameters import ModelParameters, RunParameters

ARRAYS = ("force", "xi_wheel", "xi_rail", "contact_length", "contact_area", "pressure")
TOLERANCE = 1e-12


def _prepare_run():
    try:
        from wheelrail.core.engine import prepare_run
    except ImportError:  # a checkout from before the engine package
        from wheelrail.core.interaction import prepare_run
    return prepare_run


def cases():
    """(name, prepare_run keywords, recorded by chunks) of every case."""
    out = []
    for model in MODELS:
        out.append((f"{model}-steady", {"model": model, "length": 0.06}, False))
        out.append((f"{model}-preload", {"model": model, "length": 0.06, "run_in_length": 0.03}, False))
    out.append(("3d-tabulated", {"model": "3d", "length": 0.04, "run_in_length": 2.8}, False))
    out.append(("3d-chunks", {"model": "3d", "length": 0.3, "keep_pressure": False}, True))
    fine = ModelParameters(run=RunParameters(element_size=0.5e-3))  # the window without C: contact.capacitance
    out.append(("3d-0.5mm", {"model": "3d", "length": 0.1, "params": fine}, False))
    return out


def run_case(keywords: dict, chunked: bool) -> dict[str, np.ndarray]:
    """The arrays of one case's result."""
    run = _prepare_run()("corrugated-rail", line=0, **keywords)
    if not chunked:
        result = run.run()
        return {name: np.asarray(getattr(result, name)) for name in ARRAYS if getattr(result, name) is not None}
    blocks = list(run.blocks())
    out = {name: np.concatenate([getattr(b, name) for _, b in blocks]) for name in ARRAYS[:-1]}
    out["pressure"] = np.concatenate([b.pressure for _, b in blocks])
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("action", choices=("save", "compare"))
    parser.add_argument("folder", type=Path)
    args = parser.parse_args(argv)
    args.folder.mkdir(parents=True, exist_ok=True)
    worst = 0.0
    for name, keywords, chunked in cases():
        arrays = run_case(keywords, chunked)
        path = args.folder / f"{name}.npz"
        if args.action == "save":
            np.savez(path, **arrays)
            print(f"{name}: saved {', '.join(arrays)}")
            continue
        saved = np.load(path)
        parts = []
        for key in saved.files:
            a, b = np.asarray(saved[key], dtype=float), np.asarray(arrays[key], dtype=float)
            if a.shape != b.shape:
                print(f"{name}: {key} has shape {b.shape}, saved {a.shape}")
                return 1
            if not np.array_equal(np.isnan(a), np.isnan(b)):
                difference = np.inf  # NaN (an area a model has not) where the other has a number
            else:
                a, b = a[~np.isnan(a)], b[~np.isnan(b)]
                scale = max(float(np.max(np.abs(a))), 1e-300) if a.size else 1.0
                difference = float(np.max(np.abs(a - b))) / scale if a.size else 0.0
            worst = max(worst, difference)
            parts.append(f"{key} {difference:.3g}")
        print(f"{name}: " + ", ".join(parts))
    if args.action == "compare":
        print(f"largest relative difference: {worst:.3g} (tolerance {TOLERANCE:g})")
    return int(worst > TOLERANCE)


if __name__ == "__main__":
    sys.exit(main())
