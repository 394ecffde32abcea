"""House rules of core/: modules of at most ~600 lines, functions of at most 80 lines and 10
arguments, except the numba loops named below, each with the reason in its own docstring or comment."""

from __future__ import annotations

import ast
from pathlib import Path

CORE = Path(__file__).resolve().parents[2] / "core"
MAX_MODULE_LINES = 620  # "about 600"
MAX_FUNCTION_LINES = 80
MAX_ARGUMENTS = 10
EXEMPT = {
    # numba loops over time steps or Newmark steps: every array is an argument, so that the loop compiles to
    # one function that numba caches on disk (jitted functions passed as arguments defeat the cache)
    "_newmark_block",
}


def _functions(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            yield node


def _argument_count(node) -> int:
    args = node.args
    names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
    return len(names) - (1 if names and names[0] in ("self", "cls") else 0)


def test_modules_and_functions_of_core_stay_small():
    problems = []
    for path in sorted(CORE.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        name = path.relative_to(CORE.parent)
        if text.count("\n") > MAX_MODULE_LINES:
            problems.append(f"{name}: {text.count(chr(10))} lines")
        for node in _functions(ast.parse(text)):
            if node.name in EXEMPT:
                continue
            length = node.end_lineno - node.lineno + 1
            if length > MAX_FUNCTION_LINES or _argument_count(node) > MAX_ARGUMENTS:
                problems.append(f"{name}:{node.lineno} {node.name}: {length} lines, {_argument_count(node)} arguments")
    assert not problems, "\n".join(problems)
