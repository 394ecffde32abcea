"""The ``wheelrail`` command line.

Each sub-command lives in its own module under ``wheelrail.core.commands`` that defines
``add_parser(subparsers)`` and ``run(args) -> int``; this module only dispatches. Every error ends as
one line on stderr and a non-zero exit code; set ``WHEELRAIL_DEBUG=1`` to see the
traceback of an unexpected failure.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from wheelrail.core.errors import WheelrailError

# name -> one-line help shown by `wheelrail --help`; the module wheelrail.core.commands.NAME (its
# "-" written "_") is imported only when that command runs, so that `--help` and a cached `track` start
# fast (issue 13: importing every command, scipy.signal among them, took 0.8 s before anything ran).
# tests/cli/test_cli_startup.py checks these lines against each module's own help.
COMMANDS = {
    "explore": "start the browser GUI (default http://127.0.0.1:8080)",
    "track": "track receptance peaks (sleeper-on-ballast, rail-on-pad, pinned-pinned) and Green's function cache",
    "run": "simulate the wheel rolling over a roughness set with one contact model",
    "datasets": "list the bundled roughness sets",
    "roughness": "third-octave roughness spectra and lateral coherence of a roughness set",
    "spectra": "third-octave contact-force spectrum of a saved run (.npz or .rrd)",
    "study": "run one of the paper's studies (force spectra, contact filters, model differences)",
    "filters": "reference contact filters (CNOSSOS-EU A3, analytic) by wavelength and frequency band",
    "noise": "rolling noise: CNOSSOS-EU source, the model track's transfer function, or a run's sound power and WAV",
}

class _OneLineErrors(argparse.ArgumentParser):
    """Usage errors as one line on stderr, not argparse's usage block."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser; only ``command``'s module is imported (every module when ``command`` is "*")."""
    parser = _OneLineErrors(
        prog="wheelrail",
        description=(
            "Time-domain vertical wheel/rail interaction and the dynamic contact filter "
            "(Pieringer, Kropp & Thompson, Wear 271, 2011)."
        ),
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, help_text in COMMANDS.items():
        if command in (name, "*"):
            module = importlib.import_module(f"wheelrail.core.commands.{name.replace('-', '_')}")
            command_parser = module.add_parser(sub)
            command_parser.set_defaults(_run=module.run)
        else:
            sub.add_parser(name, help=help_text, add_help=False)
    return parser


def _command_of(argv: list[str]) -> str | None:
    """The sub-command named on the command line (the first word that is not an option)."""
    return next((word for word in argv if not word.startswith("-")), None)


def _interrupted(error: BaseException) -> bool:
    """Whether ``error`` is, or was caused by, Ctrl-C: numba-compiled code that calls back into Python
    (e.g. to raise an exception) turns a KeyboardInterrupt arriving there into a ``SystemError`` "returned
    a result with an exception set" whose cause is the interrupt (issue 13)."""
    seen = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    command = _command_of(argv)
    name = command or ""
    try:
        parser = build_parser(command if command in COMMANDS else None)
        args = parser.parse_args(argv)
        return int(args._run(args) or 0)
    except WheelrailError as error:
        print(f"wheelrail {name}: error: {_cli_wording(str(error))}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into a closed reader (e.g. `| head`): not an error
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 - silence the interpreter's flush at exit
        return 0
    except KeyboardInterrupt:
        print(f"wheelrail {name}: interrupted", file=sys.stderr)
        return 130
    except OSError as error:
        print(f"wheelrail {name}: error: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # noqa: BLE001 - last resort: still one line unless debugging
        if _interrupted(error):
            print(f"wheelrail {name}: interrupted", file=sys.stderr)
            return 130
        if os.environ.get("WHEELRAIL_DEBUG"):
            raise
        print(
            f"wheelrail {name}: internal error: {type(error).__name__}: {error} "
            "(set WHEELRAIL_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        return 1


# Library messages that advise a Python caller (a window size, a keyword argument) reworded into what a
# command-line user can change (issue 13 item 9).
_CLI_ADVICE = {
    "the window is too small for the load, use a larger window":
        "the load or the roughness is too large for the contact window: lower --preload-kn or use a "
        "smoother line or set",
    "the roughness is too large, pass a larger half_window":
        "the roughness is too large for the bedding window: use a smoother line or set, or --model hertz",
    "use a longer run or a smaller skip": "use a longer run or a smaller --skip-ms",
}


def _cli_wording(message: str) -> str:
    for library, cli in _CLI_ADVICE.items():
        message = message.replace(library, cli)
    return message


if __name__ == "__main__":
    sys.exit(main())
