"""Writes ``halfspace_fine_reference.npz``: the ``3d`` law's answers on two short runs (the corrugated rail at
100 km/h, 0.05 m from the steady start, the paper's wheel) on 1 mm and 0.5 mm elements, as computed by the solver
before its 0.5 mm speed-ups, so that ``tests/physics/test_halfspace_fine_reference.py`` pins the faster solver to
it.

Per recorded step it stores what the loop handed the law (the known part of the approach, m, and the compliance,
m/N) and the law's answer (force, N; contact area, m^2). What is stored does not depend on the track's Green's
functions beyond the approaches themselves: replaying them on any implementation of the ``3d`` law must give the
same answers. The file was written at commit 33de9ac (its ``source`` entry names it) by running this script with
that commit's checkout; rerunning it would replace the numbers by the current solver's (don't, unless the physics
is meant to change). Run from the repository root:

    .venv/bin/python tests/data/halfspace_fine_reference.py
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
from numba import njit

from wheelrail.core.contact.halfspace_model import halfspace_step
from wheelrail.core.engine import prepare_run
from wheelrail.core.engine.kernels import commit_force, known_approach
from wheelrail.core.parameters import ModelParameters, RunParameters

OUT = Path(__file__).with_suffix(".npz")
LENGTH = 0.05  # m, from the steady start
ELEMENTS_MM = (1.0, 0.5)


@njit
def _record(j0, j1, track, wheel, constants, law, out):
    """The run's recorded steps as its compiled chunk steps them, keeping each step's inputs and answer."""
    preload, xi_w0, offset, dx = constants
    known, compliance, force, area = out
    for j in range(j0, j1):
        delta_known, c, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
        status, f, _, count = halfspace_step(j - offset, delta_known, c, law)
        k = j - j0
        known[k], compliance[k], force[k], area[k] = delta_known, c, f, count * dx * dx
        commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0)
        if status != 0:
            return j
    return -1


def main() -> None:
    arrays = {}
    for element_mm in ELEMENTS_MM:
        params = ModelParameters(run=RunParameters(element_size=element_mm * 1e-3))
        run = prepare_run("corrugated-rail", model="3d", params=params, length=LENGTH)
        run._advance_to(run.loop.n_run_in)  # the steady start and the run-in
        loop = run.loop
        out = tuple(np.zeros(loop.n_steps) for _ in range(4))
        j0 = loop.n_hist + loop.n_run_in
        constants = (params.contact.preload, loop.xi_w0, loop.n_hist, params.run.element_size)
        failed = _record(j0, j0 + loop.n_steps, loop.track, loop.wheel, constants, run.law.solver.law, out)
        assert failed < 0, failed
        key = f"{element_mm:g}".replace(".", "_")
        for name, values in zip(("known", "compliance", "force", "area"), out, strict=True):
            arrays[f"{name}_{key}"] = values
        arrays[f"first_{key}"] = np.array(loop.n_run_in)
    import wheelrail

    root = Path(wheelrail.__file__).resolve().parent
    source = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True)
    np.savez_compressed(OUT, source=np.array(source.stdout.strip()), length=LENGTH, **arrays)
    print(f"wrote {OUT} ({source.stdout.strip()})")


if __name__ == "__main__":
    main()
