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

