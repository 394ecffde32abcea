"""House rules of core/, cli/ and explorer/: modules of at most ~600 lines, functions of at most 80 lines
(docstrings not counted) and 10 arguments, except the numba loops named below, each with the reason in its own
docstring or comment; the explorer's app and a tab's session (the page's wiring) under 400 lines each; no module of
the explorer imports another's private name."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CORE = ROOT / "core"
EXPLORER = ROOT / "explorer"
CLI = ROOT / "cli"
# explorer/app.py (the server and its tabs' sessions) and browser_session.py (a tab's wiring of its parts: page, form,
# session, replay, downloads, tabs): nothing else
MAX_APP_LINES = 400
MAX_MODULE_LINES = 620  # "about 600"
MAX_FUNCTION_LINES = 80
MAX_ARGUMENTS = 10
EXEMPT = {
    # numba loops over time steps or Newmark steps: every array is an argument, so that the loop compiles to
    # one function that numba caches on disk (jitted functions passed as arguments defeat the cache)
    "_newmark_steps",
}


def _functions(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            yield node


def _code_lines(node) -> int:
    """Lines of a function without its docstring: the rule bounds code, and the public API's docstrings carry
    full numpydoc sections (Parameters, Returns, Raises, See Also, Examples: often longer than the code)."""
    length = node.end_lineno - node.lineno + 1
    first = node.body[0]
    if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
        length -= first.end_lineno - first.lineno + 1
    return length


def _argument_count(node) -> int:
    args = node.args
    names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
    return len(names) - (1 if names and names[0] in ("self", "cls") else 0)


def test_modules_and_functions_of_core_and_the_explorer_stay_small():
    problems = []
    for path in sorted((*CORE.rglob("*.py"), *CLI.rglob("*.py"), *EXPLORER.rglob("*.py"))):
        text = path.read_text(encoding="utf-8")
        name = path.relative_to(CORE.parent)
        if text.count("\n") > MAX_MODULE_LINES:
            problems.append(f"{name}: {text.count(chr(10))} lines")
        for node in _functions(ast.parse(text)):
            if node.name in EXEMPT:
                continue
            length = _code_lines(node)
            if length > MAX_FUNCTION_LINES or _argument_count(node) > MAX_ARGUMENTS:
                problems.append(f"{name}:{node.lineno} {node.name}: {length} lines, {_argument_count(node)} arguments")
    assert not problems, "\n".join(problems)


def test_the_explorers_app_only_wires_its_parts():
    for name in ("app.py", "browser_session.py"):
        lines = (EXPLORER / name).read_text(encoding="utf-8").count("\n")
        assert lines < MAX_APP_LINES, f"explorer/{name}: {lines} lines"


def test_no_explorer_module_imports_a_private_name():
    problems = []
    for path in sorted(EXPLORER.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("wheelrail."):
                private = [a.name for a in node.names if a.name.startswith("_")]
                problems += [f"{path.name}: {node.module}.{name}" for name in private]
    assert not problems, "\n".join(problems)
