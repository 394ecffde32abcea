"""The ``wheelrail`` command line.

Each sub-command lives in its own module under ``wheelrail.core.commands`` that defines
``add_parser(subparsers)`` and ``run(args) -> int``; this module only dispatches. Every error ends as
one line on stderr and a non-zero exit code (SPEC.md §5, §7); set ``WHEELRAIL_DEBUG=1`` to see the
traceback of an unexpected failure.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from wheelrail.core.errors import WheelrailError

# name -> module under wheelrail.core.commands; add one line per command.
COMMANDS = {
    "explore": "explore",
    "track": "track",
    "run": "run",
    "datasets": "datasets",
    "roughness": "roughness",
    "spectra": "spectra",
    "study": "study",
    "filters": "filters",
}


class _OneLineErrors(argparse.ArgumentParser):
    """Usage errors as one line on stderr (SPEC.md §5), not argparse's usage block."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _OneLineErrors(
        prog="wheelrail",
        description=(
            "Time-domain vertical wheel/rail interaction and the dynamic contact filter "
            "(Pieringer, Kropp & Thompson, Wear 271, 2011)."
        ),
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module_name in COMMANDS.values():
        module = importlib.import_module(f"wheelrail.core.commands.{module_name}")
        command_parser = module.add_parser(sub)
        command_parser.set_defaults(_run=module.run)
    return parser



def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args._run(args) or 0)
    except WheelrailError as error:
        print(f"wheelrail {args.command}: error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into a closed reader (e.g. `| head`): not an error
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 - silence the interpreter's flush at exit
        return 0
    except KeyboardInterrupt:
        print(f"wheelrail {args.command}: interrupted", file=sys.stderr)
        return 130
    except OSError as error:
        print(f"wheelrail {args.command}: error: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # noqa: BLE001 - last resort: still one line unless debugging
        if os.environ.get("WHEELRAIL_DEBUG"):
            raise
        print(
            f"wheelrail {args.command}: internal error: {type(error).__name__}: {error} "
            "(set WHEELRAIL_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        return 1


if __name__ == "__main__":
    sys.exit(main())
