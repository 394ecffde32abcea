"""The ``wheelrail`` console script: core's commands (``wheelrail.core.cli``) and the explorer's ``explore``.

The command line lives here, above both, so that the physics package never imports the GUI: core's dispatcher
is given the explorer's command by name and imports its module only when ``wheelrail explore`` runs.
"""

from __future__ import annotations

import sys

from wheelrail.core import cli as _core_cli

# name -> (one-line help shown by `wheelrail --help`, module defining add_parser(subparsers) and run(args))
EXPLORER_COMMANDS = {
    "explore": ("start the browser GUI (default http://127.0.0.1:8080)", "wheelrail.explorer.command"),
}


def main(argv: list[str] | None = None) -> int:
    """Run ``wheelrail`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code."""
    return _core_cli.main(argv, extra=EXPLORER_COMMANDS)


if __name__ == "__main__":
    sys.exit(main())
