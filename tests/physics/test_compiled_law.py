"""The run engine's contact laws: each model's law is one object the loop steps without asking which it is, and a
new compiled law is one module and one registry entry (``spring_law``: a linear spring in numba) that the loop,
the command line, a study and the explorer's model menu take as they take the built-in ones."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from spring_law import SPRING, SpringLaw, SpringModel
from test_contact_models import LinearSpring

from wheelrail.core.engine import prepare_run, simulate
from wheelrail.core.engine.laws.base import PerStepLaw, law_class
from wheelrail.core.engine.laws.halfspace import HalfSpaceLaw
from wheelrail.core.engine.laws.one_line import BeddingLaw, HertzLaw
from wheelrail.core.models import MODELS, ModelEntry, ModelTraits, model_entry, register, unregister

HERE = Path(__file__).resolve().parent


@pytest.fixture
def spring():
    """The compiled spring registered for the test (removed after)."""
    entry = register(SPRING)
    yield entry
    unregister(entry.name)


def test_each_model_names_its_law_and_the_registry_resolves_it():
    laws = {name: law_class(model_entry(name).traits) for name in MODELS}
    assert laws == {
        "3d": HalfSpaceLaw,
        "2d": BeddingLaw,
        "hertz": HertzLaw,
        "hertz-winkler": HertzLaw,
        "hertz-average": HertzLaw,
    }
    assert law_class(ModelTraits()) is PerStepLaw and law_class(SPRING.traits) is SpringLaw


@pytest.mark.parametrize("model", MODELS)
def test_surface_input_is_what_each_law_reads_of_the_surface(model):
    # the hook a surface added to the track goes through: each law's own treatment of the lines on the model grid
    # (hertz*: the model's equivalent roughness under the wheel; 2d: the bedding's window; 3d: the window's rows)
    run = prepare_run("corrugated-rail", model=model, length=0.05)
    law = run.law
    read = law.solver.track[1] if model == "3d" else law.law_inputs[0]
    np.testing.assert_array_equal(law.surface_input(law.inputs.lines), read)


class _MeanSpring(SpringModel):
    """The spring on the chosen line's roughness less its mean over 5 elements: a model whose treatment of the
    surface is its own (a pre-filter in ``prepare``) on the plain ``SpringLaw``."""

    def prepare(self, inputs):
        approach = super().prepare(inputs)
        line = np.convolve(inputs.centre_line, np.ones(5) / 5, mode="same")
        roughness = np.ascontiguousarray((line[inputs.start_index] * inputs.ramp)[:, None])
        self._law = replace(self._law, roughness=roughness)
        return approach


@pytest.mark.parametrize("model", [*MODELS, "mean-spring"])
def test_surface_input_on_other_lines_is_what_the_model_prepared_on_them_reads(model):
    # the hook reads any surface through the model's own treatment (its prepare), a compiled law's of a plug-in
    # with a pre-filter of its own too: the law's inputs of a run prepared on those lines
    entry = register(ModelEntry(name="mean-spring", label="x", traits=SPRING.traits, implementation=_MeanSpring))
    try:
        law = prepare_run("corrugated-rail", model=model, length=0.05).law
        other = prepare_run("sinter-wheel-1", model=model, length=0.05).law
        read = other.solver.track[1] if model == "3d" else other.law_inputs[0]
        np.testing.assert_array_equal(law.surface_input(other.inputs.lines), read)
    finally:
        unregister(entry.name)


def test_a_compiled_law_from_one_module_and_one_entry_runs_in_the_loop(spring):
    # the compiled spring against the same spring solved per step from Python (test_contact_models.LinearSpring):
    # the same equations, so the same forces to round-off, from the steady start and from the preload at rest
    per_step = register(
        ModelEntry(name="spring-per-step", label="x", traits=ModelTraits(), implementation=LinearSpring)
    )
    runs = {}
    try:
        for run_in in (None, 0.02):
            compiled = simulate("corrugated-rail", model="spring", length=0.3, run_in_length=run_in)
            reference = simulate("corrugated-rail", model="spring-per-step", length=0.3, run_in_length=run_in)
            assert compiled.model == "spring" and compiled.force.size == 300
            assert np.max(np.abs(compiled.force - reference.force)) <= 1e-9 * reference.force.max()
            runs[run_in] = compiled
    finally:
        unregister(per_step.name)
    # it is not the Hertz spring: the same mean, other extremes
    hertz, compiled = simulate("corrugated-rail", model="hertz", length=0.3), runs[None]
    assert compiled.force.mean() == pytest.approx(hertz.force.mean(), rel=1e-3)
    assert compiled.force.max() != pytest.approx(hertz.force.max(), rel=1e-6)


def test_a_compiled_law_runs_from_the_command_line(spring, capsys):
    from wheelrail.cli import main

    code = main(["run", "--set", "corrugated-rail", "--model", "spring", "--length-m", "0.2", "--json"])
    out, err = capsys.readouterr()
    assert code == 0 and err == "", err
    summary = json.loads(out)
    assert summary["model"] == "spring" and summary["steps"] == 200 and summary["loss_of_contact_steps"] == 0


@pytest.mark.slow
def test_a_compiled_law_runs_in_a_study(spring, tmp_path):
    # the filters study runs every one-line model of the registry (the spring among them), in this process
    from wheelrail.core.study.runner import run_study

    run_study("filters", ["sinter-wheel-1"], tmp_path, length=0.8, workers=1, progress=False, figures=False)
    levels = tmp_path / "fig10_sinter-wheel-1_force_levels.csv"
    assert levels.read_text().splitlines()[0].split(",")[-1] == "spring_db"
    filters = np.genfromtxt(tmp_path / "fig10_sinter-wheel-1_contact_filters.csv", delimiter=",", names=True)
    resolved = np.isfinite(filters["spring_db"])
    # a linear spring filters nothing: its filter against hertz is the linearisation error alone
    assert resolved.any() and np.all(np.abs(filters["spring_db"][resolved]) < 0.5)


def test_the_explorer_offers_a_compiled_law():
    # the explorer's model menu is read from the registry when its configuration is imported: a fresh process that
    # registers the spring first
    probe = (
        "from spring_law import SPRING\n"
        "from wheelrail.core.models import register\n"
        "register(SPRING)\n"
        "from wheelrail.explorer.config import MODEL_CHOICES\n"
        "print(list(MODEL_CHOICES))\n"
    )
    path = os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    done = subprocess.run(
        [sys.executable, "-c", probe],
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, "PYTHONPATH": path},
    )
    assert json.loads(done.stdout.replace("'", '"')) == [*MODELS, "spring", "compare"]


def test_the_built_in_one_line_laws_step_on_compiled_laws_own_loop():
    """``hertz`` and the bedding give their compiled chunk loop and curve; the stepping and the steady law are
    ``CompiledLaw``'s, written once for them and a plug-in alike."""
    from wheelrail.core.engine.laws.base import CompiledLaw
    from wheelrail.core.engine.laws.one_line import BeddingLaw, HertzLaw

    for law in (HertzLaw, BeddingLaw):
        assert law.advance is CompiledLaw.advance and law.steady_law is CompiledLaw.steady_law
