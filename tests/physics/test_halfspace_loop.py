"""The compiled 3D loop gives the results of the per-step solver it replaced, and those of a dense oracle.

Two checks:

* ``tests/data/halfspace_steps_reference.npz`` holds the per-step contact solves of three short runs (rough
  corrugated rail on the paper's circle, the sinter-braked wheel on a 460 mm wheel / 300 mm crown, a light
  wheel that loses contact on a sine) as the previous solver answered them (written by
  ``tests/data/halfspace_steps_reference.py``). Replaying the same calls on the ``3d`` model must give the
  same forces;
* a whole run of ``3d`` against the same equations stepped by a deliberately simple oracle (a dense NNLS solve
  per step, ``halfspace_oracle.OracleModel``) on the same track.

Both also for the compiled law's other paths: the deformed gap from the kernel instead of the window's
influence matrix (windows over ``FULL_MATRIX_ELEMENTS``) and a factor buffer too small for the set (grown, the
step repeated).

Tolerance 1e-9 on the force, relative to the preload: the active-set decisions are the same, so what is left
is round-off of reordered sums and of the reformulated solve (measured: below 3e-15 P).
"""

from pathlib import Path

import numpy as np
import pytest

from wheelrail.core.contact.halfspace_model import HalfSpaceModel
from wheelrail.core.engine import prepare_run
from wheelrail.core.models import (
    LAW_HALFSPACE,
    ModelEntry,
    ModelInputs,
    ModelTraits,
    model_entry,
    register,
    unregister,
)
from wheelrail.core.parameters import ContactParameters, ModelParameters

REFERENCE = Path(__file__).resolve().parents[1] / "data" / "halfspace_steps_reference.npz"
CASES = ("corrugated_paper", "sinter_460_300", "sine_light_wheel")
TOLERANCE = 1e-9  # of the preload: round-off of reordered sums (module docstring)


class KernelPathModel(HalfSpaceModel):
    """``3d`` reading the kernel instead of the influence matrix, from a factor buffer of 8 rows."""

    step_options = {"full_matrix": False, "capacity": 8}


IMPLEMENTATIONS = {"3d": lambda: model_entry("3d").create(), "kernel path, small buffer": KernelPathModel}


def _case(name):
    with np.load(REFERENCE) as data:
        return {key.split("/", 1)[1]: data[key] for key in data.files if key.startswith(name + "/")}


def _params(case) -> ModelParameters:
    youngs_modulus, poisson_ratio, along, across, preload = case["contact"]
    return ModelParameters(
        contact=ContactParameters(
            youngs_modulus=youngs_modulus,
            poisson_ratio=poisson_ratio,
            wheel_radius=along,
            rail_crown_radius=across,
            preload=preload,
        )
    )


def _replay(model, case):
    params = _params(case)
    inputs = ModelInputs(
        params=params,
        element_size=params.run.element_size,
        lines=case["lines"],
        centre_row=int(case["centre_row"]),
        window_y=case["window_y"],
        half_x=int(case["half_x"]),
        start_index=case["start_index"],
        ramp=case["ramp"],
        position_of=lambda s: s * params.run.element_size,
    )
    model.prepare(inputs)
    states = [
        model.solve(s, a, c) for s, (a, c) in enumerate(zip(case["approach_known"], case["compliance"], strict=True))
    ]
    return params, states


@pytest.mark.parametrize("implementation", IMPLEMENTATIONS)
@pytest.mark.parametrize("name", CASES)
def test_3d_law_reproduces_the_previous_solver(name, implementation):
    case = _case(name)
    params, states = _replay(IMPLEMENTATIONS[implementation](), case)
    force = np.array([state.force for state in states])
    reference = case["force"]
    preload = params.contact.preload
    assert np.max(np.abs(force - reference)) <= TOLERANCE * preload
    # the same contact sets (areas) and loss of contact on the same steps, F = 0 exactly there
    np.testing.assert_array_equal([state.contact_area for state in states], case["contact_area"])
    np.testing.assert_array_equal([state.contact_length for state in states], case["contact_length"])
    np.testing.assert_array_equal(force == 0.0, reference == 0.0)
    # the pressure maps: same tolerance, of the largest pressure
    pressure = np.array([states[s].pressure for s in case["pressure_steps"]])
    assert np.max(np.abs(pressure - case["pressure"])) <= TOLERANCE * case["pressure"].max()


@pytest.fixture(scope="module")
def models():
    from halfspace_oracle import OracleModel

    entries = [
        register(
            ModelEntry(
                name="3d-oracle",
                label="3d, dense NNLS oracle",
                traits=ModelTraits(lateral_window=True, pressure_map=True),
                implementation=OracleModel,
            )
        ),
        register(
            ModelEntry(
                name="3d-kernel-path",
                label="3d, kernel path, small buffer",
                traits=ModelTraits(lateral_window=True, law=LAW_HALFSPACE, pressure_map=True),
                implementation=KernelPathModel,
            )
        ),
    ]
    yield
    for entry in entries:
        unregister(entry.name)


@pytest.mark.parametrize(
    ("roughness", "geometry", "model"),
    [
        ("sinter-wheel-1", {}, "3d"),
        ("corrugated-rail", {"wheel_radius": 0.46, "rail_crown_radius": 0.3}, "3d"),
        ("corrugated-rail", {}, "3d-kernel-path"),
    ],
)
def test_3d_run_equals_the_dense_oracle(models, roughness, geometry, model):
    # a whole run: the force feeds back through the wheel and track history, so a difference would grow
    params = ModelParameters(contact=ContactParameters(**geometry))
    fast = prepare_run(roughness, model=model, params=params, length=0.04, run_in_length=0.02).run()
    slow = prepare_run(roughness, model="3d-oracle", params=params, length=0.04, run_in_length=0.02).run()
    # the oracle solves the same discrete problem exactly (NNLS to round-off); the solver's eq. 10 holds to 1e-9
    # relative, so the forces agree to 1e-9 of the preload (measured: below 6e-15 P)
    assert np.max(np.abs(fast.force - slow.force)) <= TOLERANCE * params.contact.preload
    np.testing.assert_array_equal(fast.contact_area, slow.contact_area)
    # a result keeps its pressure maps in float32: equal to within one float32 rounding of the largest
    assert np.max(np.abs(fast.pressure - slow.pressure)) <= np.finfo(np.float32).eps * slow.pressure.max()


def test_the_compiled_3d_loop_is_loaded_from_numbas_disk_cache():
    # The 3D chunk loop compiles once and later processes load it from numba's on-disk cache (no jitted
    # function passed as an argument, no dynamic global). The first process may compile it (a fresh
    # checkout); the second must not.
    import subprocess
    import sys

    script = (
        "import sys\n"
        "from wheelrail.core.contact.halfspace_model import HalfSpaceModel\n"
        "from wheelrail.core.engine import prepare_run\n"
        "from wheelrail.core.engine.laws.halfspace import run_chunk_3d\n"
        "from wheelrail.core.engine.laws.one_line import run_chunk\n"
        "from wheelrail.core.contact.halfspace_model import _python_step\n"
        "prepare_run('corrugated-rail', model='3d', length=0.01, run_in_length=0.0).run()\n"
        "prepare_run('corrugated-rail', model='hertz', length=0.01, run_in_length=0.0).run()\n"
        "run = prepare_run('corrugated-rail', model='3d', length=0.01, run_in_length=0.0)\n"
        "run.contact.solve(0, 1e-4, 1e-9)\n"
        "for f in (run_chunk_3d, run_chunk, _python_step):\n"
        "    print(sum(f.stats.cache_hits.values()), sum(f.stats.cache_misses.values()))\n"
    )
    for _ in range(2):
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    loaded = [tuple(map(int, line.split())) for line in done.stdout.split("\n") if line]
    assert loaded == [(1, 0)] * 3  # the 3D chunk loop, the one-line chunk loop, the per-step 3D law
