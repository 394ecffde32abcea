"""Writes ``halfspace_fine_reference.npz``: the forces and contact areas of two short ``3d`` runs (the corrugated
rail at 100 km/h, 0.05 m from the steady start, the paper's wheel) on 1 mm and 0.5 mm elements, as computed by
the solver before its 0.5 mm speed-ups, so that ``tests/physics/test_halfspace_fine_reference.py`` pins the faster
solver to it.

The file was written at commit 33de9ac (its ``source`` entry names it) by running this script with that commit's
checkout (``WHEELRAIL_CHECKOUT=/path/to/33de9ac``; the numbers are its solver's); rerunning it would replace them
by the current solver's (don't, unless the physics is meant to change). Run from the repository root:

    .venv/bin/python tests/data/halfspace_fine_reference.py
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np

from wheelrail.core.engine import prepare_run
from wheelrail.core.parameters import ModelParameters, RunParameters

OUT = Path(__file__).with_suffix(".npz")
LENGTH = 0.05  # m, from the steady start
ELEMENTS_MM = (1.0, 0.5)


def main() -> None:
    arrays = {}
    for element_mm in ELEMENTS_MM:
        params = ModelParameters(run=RunParameters(element_size=element_mm * 1e-3))
        result = prepare_run("corrugated-rail", model="3d", params=params, length=LENGTH).run()
        key = f"{element_mm:g}".replace(".", "_")
        arrays[f"force_{key}"] = np.asarray(result.force, dtype=np.float64)
        arrays[f"area_{key}"] = np.asarray(result.contact_area, dtype=np.float64)
    import wheelrail

    root = Path(wheelrail.__file__).resolve().parent
    source = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True)
    np.savez_compressed(OUT, source=np.array(source.stdout.strip()), length=LENGTH, **arrays)
    print(f"wrote {OUT} ({source.stdout.strip()})")


if __name__ == "__main__":
    main()
