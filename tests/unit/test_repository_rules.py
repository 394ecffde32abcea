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
        "import sys\nfrom wheelrail.cli.dispatch import build_parser\nbuild_parser('*')\n"
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
    assert len(graph) > 50 and graph["wheelrail.core.engine.prepare"]  # the scan sees core's modules and imports

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


def _required_imports() -> set[str]:
    """The import names of pyproject's required dependencies ("rerun-sdk>=0.41" -> "rerun"), and wheelrail."""
    import tomllib

    with open(ROOT / "pyproject.toml", "rb") as handle:
        requirements = tomllib.load(handle)["project"]["dependencies"]
    names = {re.split(r"[<>=!~\[; ]", requirement, maxsplit=1)[0].lower() for requirement in requirements}
    return {{"rerun-sdk": "rerun"}.get(name, name).replace("-", "_") for name in names} | {"wheelrail"}


def test_no_import_guard_around_what_is_always_installed():
    """``except ImportError`` guards only what may be absent (an extra, a part of the standard library a build
    can leave out): an import of a required dependency or of wheelrail itself cannot fail, and a guard there
    hides a broken installation behind a missing feature."""
    required = _required_imports()
    assert {"rerun", "numpy", "viser"} <= required
    offenders = []
    for path in sorted((*CORE.rglob("*.py"), *(ROOT / "explorer").rglob("*.py"), *(ROOT / "package").rglob("*.py"))):
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            guarded = isinstance(node, ast.Try) and any(
                isinstance(h.type, ast.Name) and h.type.id in ("ImportError", "ModuleNotFoundError")
                for h in node.handlers
            )
            if not guarded:
                continue
            for inner in (n for statement in node.body for n in ast.walk(statement)):
                modules = [inner.module or ""] if isinstance(inner, ast.ImportFrom) and inner.level == 0 else []
                modules += [alias.name for alias in inner.names] if isinstance(inner, ast.Import) else []
                offenders += [
                    f"{path.relative_to(ROOT)}:{inner.lineno} {m}" for m in modules if m.split(".")[0] in required
                ]
    assert offenders == []


def test_the_noise_components_are_named_once():
    """The sound-power parts (rail, sleeper, wheel, total) are one registry in core (noise.components); everything
    that lists them reads it, and no other module writes two of them side by side (rail and wheel alone are also
    the kinds of a roughness set)."""
    from wheelrail.core.noise import components

    assert components.sound_power_parts() == (*components.component_names(), components.TOTAL)
    assert components.component_names() == tuple(part.name for part in components.noise_components())
    listed = re.compile(r"""["'](rail|sleeper|wheel|total)["'],\s*["'](rail|sleeper|wheel|total)["']""")
    restated = [
        f"{path.relative_to(ROOT)}:{text.count(chr(10), 0, match.start()) + 1}"
        for path in sorted((*CORE.rglob("*.py"), *(ROOT / "explorer").rglob("*.py")))
        if path != CORE / "noise" / "components.py"
        for text in [path.read_text(encoding="utf-8")]
        for match in listed.finditer(text)
        if {match.group(1), match.group(2)} != {"rail", "wheel"}  # the two kinds of roughness set, not parts
    ]
    assert restated == []


_RETYPED = ("7.5 m", "1.2 m above", "-3..3", "120 dB", "390 mm", "65 kN", "100 km/h", "0 to 1.5")


def _prose(path: Path):
    """(line, text) of every string in ``path`` a user reads (docstrings aside: they explain the code)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            yield node.lineno, node.value


def test_the_explorer_states_defaults_from_their_constants():
    """The explorer's page text reads the values core declares (ISO 3095 distance and height, the paper's lines,
    the empty-band floor, the paper's radius, preload and speed, the pressure colour range) instead of retyping
    them, so a change in core shows on the page."""
    found = [
        f"{path.relative_to(ROOT)}:{line}: {word!r}"
        for path in sorted((ROOT / "explorer").rglob("*.py"))
        for line, text in _prose(path)
        for word in _RETYPED
        if word in text
    ]
    assert found == []


def test_both_front_ends_draw_pressure_on_one_colour_range():
    from wheelrail.core.drawing import patch
    from wheelrail.core.recording import pressure
    from wheelrail.explorer import scene

    assert scene.PRESSURE_TOP is patch.PRESSURE_RANGE_P0 and pressure.PRESSURE_RANGE_P0 is patch.PRESSURE_RANGE_P0
