"""The modules ask each other through public interfaces: no front end reads argparse's private attributes, ..."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FRONT_ENDS = ("core", "cli", "explorer")
ARGPARSE_PRIVATE = {"_actions", "_option_string_actions", "_group_actions", "_action_groups", "_defaults"}


def _trees(*folders: str):
    for folder in folders:
        for path in sorted((ROOT / folder).rglob("*.py")):
            yield path.relative_to(ROOT), ast.parse(path.read_text(encoding="utf-8"))


def test_no_module_reads_argparses_private_attributes():
    found = [
        f"{path}:{node.lineno} .{node.attr}"
        for path, tree in _trees(*FRONT_ENDS)
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute) and node.attr in ARGPARSE_PRIVATE
    ]
    assert not found, "\n".join(found)


def _dotted(node: ast.AST) -> str:
    if isinstance(node, ast.Attribute):
        return f"{_dotted(node.value)}.{node.attr}"
    return node.id if isinstance(node, ast.Name) else "?"


def _targets(node: ast.AST):
    targets = node.targets if isinstance(node, ast.Assign) else [node.target]
    for target in targets:
        yield from target.elts if isinstance(target, ast.Tuple) else (target,)


def test_only_the_run_form_sets_its_widgets():
    """The explorer asks the form (``form.show_progress(f)``, ``form.show_running(b)``, ``form.show_session(s)``)
    and never writes a widget of it (``form.progress_bar.value = ...``)."""
    found = []
    for path, tree in _trees("explorer"):
        if path.name == "form.py":
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign | ast.AugAssign | ast.AnnAssign):
                for target in _targets(node):
                    parts = _dotted(target).split(".")
                    if "form" in parts[:-2]:  # form.<widget>.<attribute> (or deeper)
                        found.append(f"{path}:{node.lineno} {_dotted(target)}")
    assert not found, "\n".join(found)


MODEL_USERS = ("core/recording/sink.py", "core/study/noise_plan.py", "core/study/plans.py", "explorer/patch_tab.py")


def test_the_models_are_named_by_the_registry_alone():
    """The studies, the recording and the explorer's tabs name a model through the registry
    (``wheelrail.core.models``: its role constants, or a trait), never as a literal."""
    from wheelrail.core.models import MODELS

    found = []
    for name in (*MODEL_USERS, "explorer/form.py"):
        tree = ast.parse((ROOT / name).read_text(encoding="utf-8"))
        found += [
            f"{name}:{node.lineno} {node.value!r}"
            for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and node.value in MODELS
        ]
    assert not found, "\n".join(found)


def test_the_paper_roles_are_registered_models():
    from wheelrail.core import models

    roles = ("REFERENCE_MODEL", "HALFSPACE_MODEL", "BEDDING_MODEL", "WINKLER_FILTER_MODEL", "AVERAGE_FILTER_MODEL")
    assert {getattr(models, role) for role in roles} <= set(models.MODELS)
    assert models.model_entry(models.HALFSPACE_MODEL).traits.pressure_map


MAX_INIT_PARAMETERS = 6  # a class given more takes its settings as one object (a NamedTuple, a dataclass)


def test_no_class_of_core_takes_more_than_a_few_parameters():
    found = []
    for path, tree in _trees("core"):
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name == "__init__":
                args = node.args
                count = len(args.posonlyargs) + len(args.args) + len(args.kwonlyargs) - 1  # not self
                if count > MAX_INIT_PARAMETERS:
                    found.append(f"{path}:{node.lineno} __init__ takes {count}")
    assert not found, "\n".join(found)


def test_an_errors_init_takes_its_problem_the_input_to_blame_and_advice():
    import inspect

    from wheelrail.core.errors import WheelrailError

    assert len(inspect.signature(WheelrailError.__init__).parameters) - 1 <= 5


def test_an_error_crosses_processes_with_every_field():
    import pickle

    from wheelrail.core.errors import Blame, WheelrailError

    blame = Blame("radius", -0.1, "m", minimum=0.2, argument="Wheel.radius", reason="a wheel's", magnitude=True)
    error = WheelrailError("too small", blame, advice="use a larger wheel")
    back = pickle.loads(pickle.dumps(error))
    assert (back.problem, back.blame, back.advice, str(back)) == (error.problem, blame, error.advice, str(error))
    assert (back.parameter, back.argument, back.magnitude) == ("radius", "Wheel.radius", True)


MAX_RECORDING_CLASS_LINES = 300  # a recording's parts (buffer, streams, options, end spectra) are classes of their own


def test_the_recordings_classes_each_do_one_thing():
    found = [
        f"{path}:{node.lineno} {node.name}: {node.end_lineno - node.lineno + 1} lines"
        for path, tree in _trees("core/recording")
        for node in tree.body
        if isinstance(node, ast.ClassDef) and node.end_lineno - node.lineno + 1 > MAX_RECORDING_CLASS_LINES
    ]
    assert not found, "\n".join(found)
