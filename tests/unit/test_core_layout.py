"""Core's folders say what they hold: the developer docs' table of core's packages (docs/user_guide.md, Code
layout) names every module of each package it lists, and each of those modules exists."""

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ROW = re.compile(r"^\| `(core/[\w/]+)/` \| (.*) \|$")


def _table() -> dict[str, set[str]]:
    """Package folder -> the names in backticks of its row."""
    text = (ROOT / "docs" / "user_guide.md").read_text(encoding="utf-8")
    return {match[1]: set(re.findall(r"`(\w+)`", match[2])) for match in map(ROW.match, text.splitlines()) if match}


def test_the_layout_table_names_every_module_of_each_package():
    table = _table()
    assert {"core/spectra", "core/inputs", "core/files", "core/drawing"} <= set(table)  # the table is read
    unnamed = [
        f"{folder}/{path.name}"
        for folder, names in table.items()
        for path in sorted((ROOT / folder).glob("*.py"))
        if path.stem != "__init__" and path.stem not in names
    ]
    assert unnamed == []


def test_each_module_the_table_names_exists():
    missing = [
        f"{folder}/{name}.py"
        for folder, names in _table().items()
        for name in names
        if re.fullmatch(r"[a-z_0-9]+", name) and not (ROOT / folder / f"{name}.py").is_file()
    ]
    assert missing == []


# Files that name an old path on purpose: the changelog's history, the recording fixtures' provenance, and the
# two benchmarks that import the run from a ``--base`` checkout of a commit before the engine package.
HISTORY = {
    "CHANGELOG.md",
    "tests/recording/test_compatibility.py",
    "benchmarks/engine_identity.py",
    "benchmarks/interaction.py",
}
FILE_PATH = re.compile(r"(?<![\w/.])((?:core|cli|explorer)/[\w/]+\.py)\b")
DOTTED = re.compile(r"(?<![\w.])(wheelrail\.(?:core|cli|explorer)(?:\.\w+)+|core(?:\.\w+)+)")


def _dotted_exists(name: str) -> bool:
    """Whether ``name`` (``wheelrail.core.spectra.force.force_spectrum``, ``core.engine``) starts with a module
    that exists, or with a package and a module of it or a name its ``__init__`` holds."""
    parts = [part for part in name.removeprefix("wheelrail.").split(".") if part != "py"]
    if {"NAME", "M"} & set(parts):  # a placeholder (``wheelrail.cli.commands.NAME``)
        return True
    for k in range(len(parts), 0, -1):  # the longest module or package the name starts with
        base = ROOT.joinpath(*parts[:k])
        if base.with_suffix(".py").is_file():
            return True
        if base.is_dir():
            return k == len(parts) or parts[k] in _package_names(base / "__init__.py")
    return False


def _package_names(init: Path) -> set[str]:
    """The names a package's ``__init__`` defines, imports or lists (its strings but the docstring)."""
    if not init.is_file():
        return set()
    tree = ast.parse(init.read_text(encoding="utf-8"))
    docstring = ast.get_docstring(tree, clean=False)
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.alias):
            names.add((node.asname or node.name).split(".")[0])
        elif isinstance(node, ast.Name | ast.FunctionDef | ast.ClassDef):
            names.add(node.id if isinstance(node, ast.Name) else node.name)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value != docstring:
            names.add(node.value)
    return names


def test_every_module_path_the_sources_and_docs_name_exists():
    """A path (``core/spectra/force.py``) or a dotted name (``wheelrail.core.spectra.force``, ``core.engine``)
    in the sources, tests, docs, benchmarks and validation names a module that exists: none names a module
    moved away."""
    import subprocess

    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    stale = []
    for name in tracked.split():
        if name in HISTORY or not name.endswith((".py", ".md", ".toml", ".cfg", ".txt", ".rst")):
            continue
        for number, line in enumerate((ROOT / name).read_text(encoding="utf-8").splitlines(), 1):
            stale += [f"{name}:{number} {path}" for path in FILE_PATH.findall(line) if not (ROOT / path).is_file()]
            stale += [f"{name}:{number} {dotted}" for dotted in DOTTED.findall(line) if not _dotted_exists(dotted)]
    assert stale == [], "\n".join(stale)
