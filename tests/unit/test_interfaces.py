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

