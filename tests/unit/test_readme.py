"""The README is a front door: at most 120 lines, its command table lists exactly the commands ``wheelrail`` has,
and its test command is the one CI runs (its Python example is run by ``test_doctests.py``)."""

import re
from pathlib import Path

from wheelrail.cli import EXPLORER_COMMANDS
from wheelrail.cli.dispatch import COMMANDS, build_parser

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
MAX_LINES = 120


def _cli_commands() -> set[str]:
    """The sub-commands of ``wheelrail``: core's and the explorer's, as the dispatcher is given them."""
    return set(COMMANDS) | set(EXPLORER_COMMANDS)


def _table_commands() -> list[str]:
    """The commands named in the first column of the README's command table (``| `run` |``, ``| `a`, `b` |``)."""
    rows = re.findall(r"^\| ((?:`[^`]+`(?:, )?)+) \|", README, flags=re.MULTILINE)
    return [name.split()[0] for row in rows for name in re.findall(r"`([^`]+)`", row)]


def test_readme_is_at_most_120_lines():
    assert len(README.splitlines()) <= MAX_LINES


def test_readme_command_table_lists_every_command_once():
    listed = _table_commands()
    assert len(listed) == len(set(listed))
    assert set(listed) == _cli_commands()
    assert {"run", "explore", "wheel"} <= set(listed)  # the scan reads the table
    parser = build_parser(None, extra=EXPLORER_COMMANDS)  # each is a command of the parser (modules not imported)
    for name in listed:
        assert parser.parse_known_args([name])[0].command == name


def test_readme_test_command_is_what_ci_runs():
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    (marker,) = [number for number, line in enumerate(ci) if line.startswith("# The README's test command")]
    command = ci[marker + 1]
    assert "pytest -q -n 2 --dist worksteal" in command
    assert f"```bash\n{command}\n```" in README
