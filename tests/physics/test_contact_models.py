"""The contact-model interface: a sixth model added from a test, by one class and one registry entry."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wheelrail.core.engine import prepare_run, simulate
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import (
    LAW_HERTZ,
    MODELS,
    ContactModel,
    ContactState,
    ModelEntry,
    ModelInputs,
    ModelTraits,
    model_entry,
    model_names,
    register,
    unregister,
)
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.roughness import load_roughness


class LinearSpring(ContactModel):
    """A linear contact spring F = k (delta + r) on the chosen line (k: the Hertz spring's tangent at P)."""

    def prepare(self, inputs: ModelInputs) -> float:
        contact = inputs.params.contact
        self.stiffness = 1.5 * contact.hertz_constant * math.sqrt(contact.hertz_approach())
        self.inputs = inputs
        self.equivalent_line = inputs.centre_line
        return contact.preload / self.stiffness

    def solve(self, s, approach_known, compliance):
        r = self.inputs.ramp[s] * self.inputs.centre_line[self.inputs.start_index[s]]
        # delta = approach_known - c F and F = k (delta + r)  =>  F = k (approach_known + r) / (1 + k c)
        force = max(0.0, self.stiffness * (approach_known + r) / (1.0 + self.stiffness * compliance))
        return ContactState(force=force, contact_length=0.0, contact_area=math.nan)


@pytest.fixture
def linear_spring():
    entry = register(
        ModelEntry(
            name="linear-spring", label="linear spring (test)", traits=ModelTraits(), implementation=LinearSpring
        )
    )
    yield entry
    unregister(entry.name)


def test_registry_lists_the_five_paper_models_first():
    assert MODELS == ("3d", "2d", "hertz", "hertz-winkler", "hertz-average")
    assert model_names()[:5] == MODELS
    assert model_entry("3d").traits.pressure_map and model_entry("3d").traits.lateral_window
    assert model_entry("2d").traits.compiled and model_entry("hertz-average").traits.law == LAW_HERTZ
    with pytest.raises(WheelrailError, match="unknown contact model 'elastic'; choose one of 3d, 2d"):
        model_entry("elastic")


def test_registry_refuses_bad_entries():
    with pytest.raises(WheelrailError, match="already registered"):
        register(ModelEntry(name="hertz", label="x", traits=ModelTraits(), implementation=LinearSpring))
    with pytest.raises(WheelrailError, match="takes a ModelEntry"):
        register(LinearSpring)
    with pytest.raises(WheelrailError, match="cannot be removed"):
        unregister("2d")
    with pytest.raises(WheelrailError, match="pressure map needs a lateral window"):
        ModelTraits(pressure_map=True)
    with pytest.raises(WheelrailError, match="law must be a ContactLaw class"):
        ModelTraits(law=7)


def test_a_model_registered_from_a_test_runs_in_the_loop(linear_spring):
    assert "linear-spring" in model_names()
    run = prepare_run("corrugated-rail", model="linear-spring", length=0.2)
    states = list(run.steps())  # a per-step law streams step by step
    result = run.result()
    assert len(states) == result.n_steps == 200 and result.model == "linear-spring"
    assert np.all(np.isfinite(result.force)) and result.pressure is None and result.window_x is None
    # only the registered name is accepted: after unregistering, one clear error
    unregister("linear-spring")
    with pytest.raises(WheelrailError, match="unknown contact model 'linear-spring'"):
        prepare_run("corrugated-rail", model="linear-spring", length=0.2)
    register(linear_spring)


def test_linear_spring_equals_hertz_for_small_roughness(linear_spring):
    """Linear theory: for roughness small against the static approach (2 nm against 53 um here) the Hertz
    spring acts as its tangent stiffness, so both models give the same dynamic force."""
    rail = load_roughness("corrugated-rail")
    tiny = rail.with_heights(rail.heights * 1e-4, note="corrugated rail scaled by 1e-4")
    params = ModelParameters(contact=ContactParameters())
    hertz = simulate(tiny, model="hertz", params=params, length=1.0)
    linear = simulate(tiny, model="linear-spring", params=params, length=1.0)
    dynamic = hertz.force - hertz.force.mean()
    # measured: 1.2 N against a 2.7 kN range (5e-4, the Hertz law's curvature over the sleeper-passing
    # motion); at full roughness the two differ by 5e-3 of the range, so 2e-3 separates linear from not
    assert np.max(np.abs(linear.force - hertz.force)) < 2e-3 * np.ptp(dynamic)
    # smooth-surface equilibrium of the new model: mean force = preload within 0.1 %
    assert linear.force.mean() == pytest.approx(65e3, rel=1e-3)
