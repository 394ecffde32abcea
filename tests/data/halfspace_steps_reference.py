"""Writes ``halfspace_steps_reference.npz``: the per-step 3D contact solves of three short runs, as solved by
the solver the compiled 3D loop replaced (``HalfSpaceModel.solve`` -> ``HalfSpaceWindow.solve_coupled``, one
Python call per step), so that ``tests/physics/test_halfspace_loop.py`` pins the fast loop to it.

What is stored does not depend on the track's Green's functions: for each case, the model's inputs (the
roughness window along the track, ``start_index``, ``ramp``, geometry and preload) and, per step, the known
part of the approach and the compliance that the loop handed the model in a real run, with the model's answer
(force, contact area and length along the centre line, and the pressure map every ``PRESSURE_EVERY`` steps).
Replaying the same per-step calls on any implementation of the ``3d`` law must give the same answers.

The file was written once, at the commit before the compiled 3D loop (its ``source`` entry names it), by the
``3d`` model of that commit; the script ran that per-step solver. That solver is gone (one active-set solver,
``contact.active_set``): the script now records the dense oracle of the tests
(``tests/physics/halfspace_oracle.py``), whose answers agree with the pin to about 1e-14 of the preload, so
rerunning it would replace the previous solver's answers by the oracle's (don't, unless the physics is meant
to change). Run from the repository root:

    .venv/bin/python tests/data/halfspace_steps_reference.py
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from wheelrail.core.engine import prepare_run
from wheelrail.core.models import ModelEntry, ModelTraits, register, unregister
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.roughness import RoughnessSet

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "physics"))
from halfspace_oracle import OracleModel  # noqa: E402 - the oracle lives beside the tests that use it

OUT = Path(__file__).with_suffix(".npz")
PRESSURE_EVERY = 25


def _sine_set():
    """19 lines of a 30 um, 50 mm sine (a light wheel bounces on it: loss of contact on many steps)."""
    x = np.arange(int(0.5 / 1e-3)) * 1e-3
    heights = np.repeat((30e-6 * np.sin(2 * np.pi * x / 0.05))[None, :], 19, axis=0)
    y = (np.arange(19) - 9) * 1e-3
    return RoughnessSet(heights=heights, dx=1e-3, y=y, kind="rail", description="30 um, 50 mm sine")


CASES = {
    # name: (roughness, ContactParameters, run length m, run-in m)
    "corrugated_paper": ("corrugated-rail", ContactParameters(), 0.25, 0.08),
    "sinter_460_300": ("sinter-wheel-1", ContactParameters(wheel_radius=0.46, rail_crown_radius=0.3), 0.25, 0.08),
    "sine_light_wheel": (_sine_set(), ContactParameters(preload=5e3), 0.3, 0.05),
}


def record(roughness, contact: ContactParameters, length: float, run_in: float) -> dict[str, np.ndarray]:
    run = prepare_run(
        roughness, model=REFERENCE, params=ModelParameters(contact=contact), length=length, run_in_length=run_in
    )
    model = run.contact
    assert type(model) is OracleModel
    inputs = model._inputs
    calls = []
    solve = model.solve

    def recording_solve(s, approach_known, compliance):
        state = solve(s, approach_known, compliance)
        calls.append((s, approach_known, compliance, state))
        return state

    model.solve = recording_solve
    run.run()
    hx = inputs.half_x
    lo = int(inputs.start_index.min()) - hx
    hi = int(inputs.start_index.max()) + hx + 1
    steps = np.array([c[0] for c in calls])
    assert np.array_equal(steps, np.arange(run.loop.n_total))
    pressure_steps = steps[::PRESSURE_EVERY]
    return {
        "lines": inputs.lines[:, lo:hi].copy(),
        "centre_row": np.array(inputs.centre_row),
        "window_y": inputs.window_y,
        "half_x": np.array(hx),
        "start_index": inputs.start_index - lo,
        "ramp": inputs.ramp,
        "contact": np.array(
            [
                contact.youngs_modulus,
                contact.poisson_ratio,
                contact.radius_along,
                contact.radius_across,
                contact.preload,
            ]
        ),
        "approach_known": np.array([c[1] for c in calls]),
        "compliance": np.array([c[2] for c in calls]),
        "force": np.array([c[3].force for c in calls]),
        "contact_area": np.array([c[3].contact_area for c in calls]),
        "contact_length": np.array([c[3].contact_length for c in calls]),
        "pressure_steps": pressure_steps,
        "pressure": np.array([calls[s][3].pressure for s in pressure_steps]),
    }


REFERENCE = "3d-reference"


def main() -> None:
    register(
        ModelEntry(
            name=REFERENCE,
            label="3d, dense oracle",
            implementation=OracleModel,
            traits=ModelTraits(lateral_window=True, pressure_map=True),
        )
    )
    commit = subprocess.run(
        ["git", "rev-parse", "HEAD"], capture_output=True, text=True, cwd=Path(__file__).parent
    ).stdout.strip()
    arrays = {"source": np.array(f"tests/physics/halfspace_oracle.py per step, wheelrail commit {commit}")}
    for name, case in CASES.items():
        for key, value in record(*case).items():
            arrays[f"{name}/{key}"] = value
        force = arrays[f"{name}/force"]
        print(
            f"{name}: {force.size} steps, F {force.min() / 1e3:.1f}..{force.max() / 1e3:.1f} kN, "
            f"{np.count_nonzero(force == 0)} without contact"
        )
    unregister(REFERENCE)
    np.savez_compressed(OUT, **arrays)
    print(f"wrote {OUT} ({OUT.stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
