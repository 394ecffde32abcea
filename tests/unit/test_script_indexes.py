"""benchmarks/ (timing) and validation/ (physics figures) each list every script of theirs in their README.md, one
list item per script, and list no script that is not there."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _listed(readme: Path) -> list[str]:
    """The scripts a README lists: the file name that opens each list item (``- `name.py`: what it prints``)."""
    return re.findall(r"^- `([\w.]+\.py)`: \S", readme.read_text(encoding="utf-8"), flags=re.MULTILINE)


@pytest.mark.parametrize("folder", ["benchmarks", "validation"])
def test_readme_lists_every_script_of_its_folder_once(folder):
    listed = _listed(ROOT / folder / "README.md")
    present = sorted(path.name for path in (ROOT / folder).glob("*.py"))
    assert len(present) >= 10  # both folders hold their scripts (a wrong folder name finds none)
    assert sorted(listed) == present
    assert len(set(listed)) == len(listed)


def test_timing_and_physics_scripts_are_apart_and_cited_where_they_are():
    # no script in both folders, and every citation of one (docs, README, code and test comments) finds it
    assert not {path.name for path in (ROOT / "benchmarks").glob("*.py")} & {
        path.name for path in (ROOT / "validation").glob("*.py")
    }
    citing = [ROOT / "README.md", *(ROOT / "docs").glob("*.md")]
    for folder in ("core", "explorer", "package", "tests", "benchmarks", "validation"):
        citing += (ROOT / folder).rglob("*.py")
    cited = set()
    for page in citing:
        for script in re.findall(r"\b(?:benchmarks|validation)/\w+\.py", page.read_text(encoding="utf-8")):
            assert (ROOT / script).is_file(), f"{page.relative_to(ROOT)} cites {script}, which is not there"
            cited.add(script)
    assert "validation/run_in.py" in cited and "benchmarks/interaction.py" in cited  # the scan reads the citations
