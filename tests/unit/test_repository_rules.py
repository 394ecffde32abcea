"""Rules of the repository's shape: core never imports the explorer or the command line above it, core's
modules import each other without cycles (imports inside functions included), and nothing cites the
tracker's issues, which are not part of the repository: no issue number, and a target written out, never
named as an issue's."""

import ast
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CORE = ROOT / "core"


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts  # ("core", "contact", "hertz")
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(("wheelrail", *parts))


def _imports(path: Path) -> set[str]:
    """Every wheelrail module ``path`` imports, anywhere in the file (inside functions too)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").startswith("wheelrail"):
            found.add(node.module)
            found.update(f"{node.module}.{alias.name}" for alias in node.names)  # `from package import module`
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names if alias.name.startswith("wheelrail"))
    return found


def test_core_never_imports_the_explorer_or_the_command_above_it():
    offenders = {
        _module_name(path): sorted(
            name for name in _imports(path) if name.startswith(("wheelrail.explorer", "wheelrail.cli"))
        )
        for path in CORE.rglob("*.py")
    }
    assert {module: names for module, names in offenders.items() if names} == {}


@pytest.mark.slow
def test_core_commands_load_no_explorer_module():
    # at run time too (an import by name is no import statement): every core command's module loaded, and no
    # explorer module (nor viser) comes with them
    probe = (
        "import sys\nfrom wheelrail.core.cli import build_parser\nbuild_parser('*')\n"
        "print(sorted(m for m in sys.modules if m.startswith(('wheelrail.explorer', 'viser'))))"
    )
    loaded = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    assert loaded.strip() == "[]"


def test_core_modules_import_each_other_without_cycles():
    modules = {_module_name(path): path for path in CORE.rglob("*.py")}
    graph = {
        name: {other for other in _imports(path) if other in modules and other != name}
        for name, path in modules.items()
    }
    assert len(graph) > 50 and graph["wheelrail.core.interaction"]  # the scan sees core's modules and imports

    def cycle_from(start: str, path: tuple[str, ...], done: set[str]):
        for other in sorted(graph[start]):
            if other in path:
                return (*path[path.index(other) :], other)
            if other not in done:
                found = cycle_from(other, (*path, other), done)
                if found:
                    return found
        done.add(start)
        return None

    done: set[str] = set()
    for name in sorted(graph):
        if name not in done:
            cycle = cycle_from(name, (name,), done)
            assert cycle is None, " -> ".join(cycle)


def test_nothing_cites_the_issue_tracker():
    # an issue's number, or the words that name its target instead of writing it ([ ] and [:]: this line is none)
    pattern = re.compile(r"\bissues? #?\d+|\bissue[ ]target|\bthe[ ]issue\b|\(issue[:]", re.IGNORECASE)
    skip = {".venv", ".git", "build", "dist", "test-artifacts", "__pycache__", ".pytest_cache", ".ruff_cache"}
    offenders = []
    for folder, subfolders, files in os.walk(ROOT):
        subfolders[:] = [name for name in subfolders if name not in skip and not name.endswith(".egg-info")]
        for path in (Path(folder) / name for name in files):
            if path.suffix in {".py", ".md", ".toml", ".txt"} or path.name == "run":
                for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                    if pattern.search(line):
                        offenders.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert offenders == []
