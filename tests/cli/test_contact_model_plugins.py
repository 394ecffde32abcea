"""Contact models as plug-ins: a model declared by another package under the entry-point group
``wheelrail.contact_models`` reaches the command line, a study and the explorer with no change to wheelrail; a
broken plug-in is one warning naming it, never a crash.

The plug-in is a real package (tests/data/plugin: a pyproject.toml and a module, a linear contact spring),
installed by ``pip install --target`` into a folder of its own; the command line, the study and the explorer
run as separate processes with that folder on PYTHONPATH, as they would beside an installed plug-in.
"""

import json
import os
import shutil
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest

from wheelrail.core import models
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import MODELS, PluginWarning, model_entry, model_names

PLUGIN_SOURCE = Path(__file__).resolve().parents[1] / "data" / "plugin"
PLUGIN = "linear-spring"  # the model the test plug-in declares


def _env(*folders) -> dict:
    path = os.pathsep.join([*map(str, folders), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return {**os.environ, "PYTHONPATH": path}


def _wheelrail(env, *argv, timeout=600):
    return subprocess.run(
        [sys.executable, "-m", "wheelrail", *argv], capture_output=True, text=True, env=env, timeout=timeout
    )


@pytest.fixture(scope="module")
def plugin_env(tmp_path_factory):
    """The environment of a process that has the test plug-in installed (from its own package, offline)."""
    work = tmp_path_factory.mktemp("plugin")
    source = shutil.copytree(PLUGIN_SOURCE, work / "source")  # pip builds in the source tree: keep tests/data clean
    site = work / "site"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--no-deps",
            "--no-build-isolation",
            "--no-index",
            "--target",
            str(site),
            str(source),
        ],
        check=True,
        capture_output=True,
        timeout=300,
    )
    assert (site / "wheelrail_test_plugin").is_dir()
    return _env(site)


@pytest.mark.slow
def test_a_plugin_model_runs_from_the_command_line(plugin_env):
    help_text = _wheelrail(plugin_env, "run", "--help")
    assert help_text.returncode == 0 and PLUGIN in help_text.stdout  # offered by --model, listed by --help
    run = _wheelrail(plugin_env, "run", "--set", "corrugated-rail", "--model", PLUGIN, "--length-m", "0.3", "--json")
    assert run.returncode == 0 and run.stderr == "", run.stderr
    summary = json.loads(run.stdout)
    assert summary["model"] == PLUGIN and summary["steps"] == 300 and summary["loss_of_contact_steps"] == 0
    # the plug-in's law ran: a linear spring of the Hertz spring's stiffness at the preload gives Hertz's force
    # to within the curvature of F = C delta^1.5 over the force's swing (+-14 %, measured 0.02 % in std) ...
    from wheelrail.core.engine import simulate

    hertz = simulate("corrugated-rail", model="hertz", length=0.3)
    assert summary["force_std_n"] == pytest.approx(float(hertz.force.std()), rel=0.01)
    assert summary["force_mean_n"] == pytest.approx(float(hertz.force.mean()), rel=1e-3)
    # ... and is not Hertz: the extremes differ (the spring is stiffer below the preload, softer above)
    assert summary["force_max_n"] != pytest.approx(float(hertz.force.max()), rel=1e-6)
    # without the plug-in installed the name is refused in one line
    refused = _wheelrail(_env(), "run", "--set", "corrugated-rail", "--model", PLUGIN)
    assert refused.returncode == 2 and "invalid choice: 'linear-spring'" in refused.stderr
    assert len(refused.stderr.strip().splitlines()) == 1


@pytest.mark.slow
def test_a_plugin_model_runs_in_the_filters_study(plugin_env, tmp_path):
    # spawned pool workers find the plug-in by themselves (entry points, not a register() in this process)
    out = tmp_path / "filters"
    study = _wheelrail(
        plugin_env,
        "study",
        "filters",
        "--set",
        "sinter-wheel-1",
        "--length-m",
        "0.8",
        "--workers",
        "2",
        "--out",
        str(out),
        "--json",
    )
    assert study.returncode == 0, study.stderr
    summary = json.loads(study.stdout)
    assert summary["runs"] == 36  # 7 lines x (4 built-in one-line models + the plug-in) + 3d
    levels = out / "fig10_sinter-wheel-1_force_levels.csv"
    assert levels.read_text().splitlines()[0].split(",")[-1] == "linear_spring_db"
    filters = np.genfromtxt(out / "fig10_sinter-wheel-1_contact_filters.csv", delimiter=",", names=True)
    spring, two_d = filters["linear_spring_db"], filters["2d_db"]
    resolved = np.isfinite(spring)
    assert resolved.sum() >= 10 and np.array_equal(resolved, np.isfinite(two_d))
    # the linear spring filters nothing (its filter L - L_hertz is the linearisation error only: within
    # 0.2 dB in every band, measured at most 0.05 dB), unlike the 2D bedding (below -10 dB at 8 kHz)
    assert np.all(np.abs(spring[resolved]) < 0.2) and np.any(spring[resolved] != 0.0)
    assert two_d[-1] < -10.0


EXPLORER_PROBE = textwrap.dedent("""
    import json, threading
    from wheelrail.core.parameters import KMH
    from wheelrail.core.roughness import load_roughness
    from wheelrail.explorer.config import COMPARE_ORDER, MODEL_CHOICES, length_range, read_config
    from wheelrail.explorer.controller import RunController

    class Listener:
        def __init__(self):
            self.errors, self.outcomes, self.done = [], [], threading.Event()
        def status(self, text): pass
        def progress(self, fraction): pass
        def frame(self, state, view): pass
        def live(self, result, view): pass
        def model_done(self, entry, view): pass
        def error(self, message): self.errors.append(message)
        def finished(self, config, outcome):
            self.outcomes.append(outcome)
            self.done.set()

    rough = load_roughness("corrugated-rail")
    length = length_range(rough, 100 * KMH)[0]
    listener = Listener()
    controller = RunController(listener)
    found = {}
    for model in ("linear-spring", "hertz"):
        config = read_config(rough, "corrugated-rail", line="0", model=model, speed_kmh="100", preload_kn="65",
                             length_m=str(length))
        listener.done.clear()
        controller.start(config, rough)
        assert listener.done.wait(600)
    entry = controller.store.entries(config.case())["linear-spring"]
    filters = controller.store.contact_filters(config.case())
    print(json.dumps({"choices": list(MODEL_CHOICES), "compare": list(COMPARE_ORDER), "errors": listener.errors,
                      "outcomes": listener.outcomes, "model": entry.result.model,
                      "filter_db": [float(v) for v in filters["linear-spring"][1]]}))
""")


@pytest.mark.slow
def test_the_explorer_offers_and_runs_a_plugin_model(plugin_env):
    probe = subprocess.run(
        [sys.executable, "-c", EXPLORER_PROBE], capture_output=True, text=True, env=plugin_env, timeout=600
    )
    assert probe.returncode == 0, probe.stderr
    seen = json.loads(probe.stdout.strip().splitlines()[-1])
    assert seen["choices"] == [*MODELS, PLUGIN, "compare"]  # the menu: built-in models, the plug-in, compare
    assert PLUGIN in seen["compare"]  # compare runs it too
    assert seen["errors"] == [] and seen["outcomes"] == ["done", "done"] and seen["model"] == PLUGIN
    # its contact filter against hertz, as the page draws it: near 0 dB where resolved (a linear spring filters
    # nothing; on the corrugated rail the force swings +-14 %, where linear and Hertz springs part: measured
    # at most 0.21 dB, within 0.5 dB)
    resolved = np.isfinite(seen["filter_db"])
    assert resolved.any() and np.all(np.abs(np.asarray(seen["filter_db"])[resolved]) < 0.5)


# --- broken plug-ins ------------------------------------------------------------------------------------------

BROKEN_MODULE = textwrap.dedent("""
    from wheelrail.core.models import ModelEntry, ModelTraits

    class Spring:  # not used: none of the entries below is registered
        pass

    NOT_AN_ENTRY = {"name": "a-dict"}
    MISNAMED = ModelEntry(name="something-else", label="x", traits=ModelTraits(), implementation=Spring)
    HERTZ_AGAIN = ModelEntry(name="hertz", label="x", traits=ModelTraits(), implementation=Spring)
    FINE = ModelEntry(name="fine", label="a plug-in that loads", traits=ModelTraits(), implementation=Spring)
""")
BROKEN_ENTRY_POINTS = {  # entry-point name -> (object reference, what the warning says)
    "boom": ("wheelrail_broken_plugin_boom:ENTRY", "loading it raised RuntimeError: plug-in failed on import"),
    "ghost": ("no_such_module_anywhere:ENTRY", "loading it raised ModuleNotFoundError"),
    "a-dict": ("wheelrail_broken_plugin:NOT_AN_ENTRY", "it gives a dict, not a wheelrail.core.models.ModelEntry"),
    "misnamed": ("wheelrail_broken_plugin:MISNAMED", "the entry point's name must be the model's name"),
    "hertz": ("wheelrail_broken_plugin:HERTZ_AGAIN", "already registered"),
}


def _install_by_hand(folder: Path, entry_points: dict[str, str]) -> Path:
    """A distribution as pip leaves it (a dist-info folder with its entry points) and its modules."""
    (folder / "wheelrail_broken_plugin.py").write_text(BROKEN_MODULE)
    (folder / "wheelrail_broken_plugin_boom.py").write_text("raise RuntimeError('plug-in failed on import')\n")
    info = folder / "wheelrail_broken_plugin-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: wheelrail-broken-plugin\nVersion: 1.0\n")
    lines = [f"{name} = {target}" for name, target in entry_points.items()]
    (info / "entry_points.txt").write_text("[wheelrail.contact_models]\n" + "\n".join(lines) + "\n")
    return folder


@pytest.fixture
def fresh_registry(monkeypatch):
    """The registry as a new process has it: built-ins only, plug-ins not yet looked for (restored after)."""
    monkeypatch.setattr(models, "_REGISTRY", {name: models._REGISTRY[name] for name in MODELS})
    monkeypatch.setattr(models, "_plugins_loaded", False)


def test_each_broken_plugin_is_one_warning_naming_it_and_the_others_load(tmp_path, monkeypatch, fresh_registry):
    targets = {name: target for name, (target, _) in BROKEN_ENTRY_POINTS.items()}
    monkeypatch.syspath_prepend(str(_install_by_hand(tmp_path, {**targets, "fine": "wheelrail_broken_plugin:FINE"})))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        names = model_names()
        model_names()  # looked for once per process: no second round of warnings
    assert names == (*MODELS, "fine")  # the built-in models stay first; the good plug-in is registered
    assert model_entry("fine").label == "a plug-in that loads"
    assert all(issubclass(w.category, PluginWarning) for w in caught)
    messages = sorted(str(w.message) for w in caught)
    assert len(messages) == len(BROKEN_ENTRY_POINTS)
    for message, (name, (target, why)) in zip(messages, sorted(BROKEN_ENTRY_POINTS.items()), strict=True):
        assert message.startswith(
            f"contact-model plug-in {name!r} ({target} from wheelrail-broken-plugin 1.0) is skipped: "
        ), message
        assert why in message and "\n" not in message
    assert model_entry("hertz") is models._BUILTIN[2]  # a plug-in never replaces a built-in model
    with pytest.raises(WheelrailError, match="unknown contact model 'boom'"):
        model_entry("boom")


def test_a_broken_plugin_is_one_warning_line_on_the_command_line(tmp_path):
    env = _env(_install_by_hand(tmp_path, {"boom": BROKEN_ENTRY_POINTS["boom"][0]}))
    result = _wheelrail(env, "run", "--help", timeout=120)
    assert result.returncode == 0 and "--model {3d,2d,hertz,hertz-winkler,hertz-average}" in result.stdout
    assert result.stderr == (
        "wheelrail run: warning: contact-model plug-in 'boom' (wheelrail_broken_plugin_boom:"
        "ENTRY from wheelrail-broken-plugin 1.0) is skipped: loading it raised RuntimeError: "
        "plug-in failed on import\n"
    )


def test_model_entries_are_checked():
    with pytest.raises(WheelrailError, match="ModelEntry.name must be letters, digits"):
        models.ModelEntry(name="two words", label="x", traits=models.ModelTraits(), implementation=object)
    with pytest.raises(WheelrailError, match="ModelEntry.label must be one line"):
        models.ModelEntry(name="ok", label="two\nlines", traits=models.ModelTraits(), implementation=object)
    with pytest.raises(WheelrailError, match="ModelEntry.traits must be a ModelTraits"):
        models.ModelEntry(name="ok", label="x", traits=None, implementation=object)


def test_the_noise_study_plans_every_one_line_model_plugins_included(tmp_path, monkeypatch, fresh_registry):
    # as the filters study: the registry's one-line models, a plug-in among them, then 3d; hertz (the reference
    # of every dynamic filter) first
    from wheelrail.core.study import plan_study
    from wheelrail.core.study.noise_plan import noise_models

    monkeypatch.syspath_prepend(str(_install_by_hand(tmp_path, {"fine": "wheelrail_broken_plugin:FINE"})))
    assert noise_models() == ("hertz", "2d", "hertz-winkler", "hertz-average", "fine", "3d")
    plan = plan_study("noise", ["sinter-wheel-1"], length=2.0)
    assert {spec.model for spec in plan.specs} == set(noise_models())
