"""The ``wheelrail`` command line: the commands on core (``wheelrail.cli.commands``, dispatched by
``wheelrail.cli.dispatch``) and the explorer's ``explore``.

The command line lives here, beside the explorer and above core, so that ``wheelrail.core`` is the library and
never imports a front end: the dispatcher is given the explorer's command by name and imports its module only
when ``wheelrail explore`` runs.
"""

from __future__ import annotations

import sys

from wheelrail.cli import dispatch as _dispatch

# name -> (one-line help shown by `wheelrail --help`, module defining add_parser(subparsers) and run(args))
EXPLORER_COMMANDS = {
    "explore": ("start the browser GUI (default http://127.0.0.1:8080)", "wheelrail.explorer.command"),
}


def main(argv: list[str] | None = None) -> int:
    """Run ``wheelrail`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code."""
    return _dispatch.main(argv, extra=EXPLORER_COMMANDS)


if __name__ == "__main__":
    sys.exit(main())
