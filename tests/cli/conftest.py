"""Shared set-up of the command-line tests: the command run in this process (``cli``) and in a fresh Python
process (``python_probe``: what a new process imports or prints)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from wheelrail.cli import main  # the `wheelrail` command: core's commands and `explore`


@pytest.fixture
def cli(capsys):
    """``cli(*argv)`` runs ``wheelrail *argv`` in this process: (exit code, stdout, stderr)."""

    def run(*argv):
        code = main(list(argv))
        out, err = capsys.readouterr()
        return code, out, err

    return run


@pytest.fixture
def python_probe():
    """``python_probe(code)``: the standard output of ``python -c code`` in a fresh process (it must exit 0)."""

    def probe(code: str) -> str:
        return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout

    return probe
