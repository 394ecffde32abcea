"""The equation -> code -> test table of docs/physics.md names public code that exists and tests that exist.

In the code column a backticked name starting with ``wheelrail.`` is a module (the names after it are looked
up in it) or a full dotted name (whose module the names after it are then looked up in); every other backticked
name is an attribute path in the current module. In the test column ``file.py::test`` names a test of
``tests/physics/file.py`` and ``::test`` one of the last file named.
"""

import ast
import importlib
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TABLE_HEADER = "| Paper | What | Implemented in | Validated by (`tests/physics/...`) |"


def _rows() -> list[list[str]]:
    lines = (ROOT / "docs" / "physics.md").read_text().splitlines()
    start = lines.index(TABLE_HEADER) + 2  # after the header and its |---| line
    rows = []
    for line in lines[start:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip("|").split(" | ")])
    return rows


def _resolve(dotted: str):
    """The object a full dotted name ``wheelrail....`` names and the module it was found in."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            module = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        value = module
        for name in parts[cut:]:
            value = getattr(value, name)
        return value, module
    raise ImportError(dotted)


def test_the_table_names_public_code_that_exists():
    rows = _rows()
    assert len(rows) >= 11  # the table is found and read whole
    checked = 0
    for row in rows:
        module = None
        for token in re.findall(r"`([^`]+)`", row[2]):
            assert not any(part.startswith("_") for part in token.split(".")), f"{row[0]}: private name {token}"
            if token.startswith("wheelrail."):
                value, module = _resolve(token)
            else:
                assert module is not None, f"{row[0]}: {token} before any module"
                value = module
                for name in token.split("."):
                    value = getattr(value, name)
            checked += 1
    assert checked >= 40


def test_the_table_cites_tests_that_exist():
    defined: dict[str, set[str]] = {}
    checked = 0
    for row in _rows():
        current = None
        for token in re.findall(r"`([^`]*::[^`]+)`", row[3]):
            file, name = token.split("::")
            current = file or current
            if current not in defined:
                tree = ast.parse((ROOT / "tests" / "physics" / current).read_text())
                defined[current] = {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}
            assert name in defined[current], f"{row[0]}: {current}::{name} not found"
            checked += 1
    assert checked >= 30
