"""Core's folders say what they hold: the developer docs' table of core's packages (docs/user_guide.md, Code
layout) names every module of each package it lists, and each of those modules exists."""

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
