"""The command line's dispatcher: the commands on core and the explorer's.

Each sub-command lives in its own module that defines ``add_parser(subparsers)`` and ``run(args) -> int``; the
commands on core are under ``wheelrail.cli.commands``, and the ``wheelrail`` console script (``wheelrail.cli``)
adds the explorer's ``explore`` command to them, so that core never imports a front end. This module only
dispatches, after one check common to all commands: the files a command's module declares (``FILES``, a
``commands._common.Files``) are checked with ``commands._common.check_files`` before it runs. Every error ends
as one line on stderr and a non-zero exit code, a :class:`WheelrailError` worded with
the command line's own names for its inputs (``commands._common.CLI_NAMES``: option, unit), a warning as one line
too; set ``WHEELRAIL_DEBUG=1`` to see the traceback of an unexpected failure.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import sys
import warnings

from wheelrail import __version__
from wheelrail.core.errors import WheelrailError

# name -> one-line help shown by `wheelrail --help`; the module wheelrail.cli.commands.NAME (its
# "-" written "_") is imported only when that command runs, so that `--help` and a cached `track` start
# fast (importing every command would import scipy.signal among others before anything runs).
# tests/cli/test_cli_reliability.py checks these lines against each module's own help.
COMMANDS = {
    "track": "track receptances, resonances, decay rate against the type-test limit, and Green's function cache",
    "run": "simulate the wheel rolling over a roughness set with one contact model",
    "datasets": "list the bundled roughness sets",
    "roughness": "third-octave roughness spectra and lateral coherence of a roughness set",
    "spectra": "third-octave contact-force spectrum of a saved run (.npz or .rrd)",
    "study": "run one of the paper's studies (force spectra, contact filters, model differences)",
    "filters": "reference contact filters (CNOSSOS-EU A3, analytic) by wavelength and frequency band",
    "noise": "rolling noise: CNOSSOS-EU source, the model track's transfer function, or a run's sound power and WAV",
    "wheel": "the modal wheel: natural frequencies by family and nodal diameters, receptances at the contact",
    "cache": "list or clear the disk cache (the Green's functions of each track computed, ~208 MB each)",
}


class _OneLineErrors(argparse.ArgumentParser):
    """Usage errors as one line on stderr, not argparse's usage block."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _commands(extra: dict[str, tuple[str, str]] | None) -> dict[str, tuple[str, str]]:
    """name -> (one-line help, module): ``extra`` (e.g. the explorer's, from ``wheelrail.cli``), then core's."""
    core = {name: (text, f"wheelrail.cli.commands.{name.replace('-', '_')}") for name, text in COMMANDS.items()}
    return {**(extra or {}), **core}


def build_parser(
    command: str | None = None, extra: dict[str, tuple[str, str]] | None = None
) -> argparse.ArgumentParser:
    """The parser; only ``command``'s module is imported (every module when ``command`` is "*"). ``extra``:
    more commands, name -> (one-line help, module)."""
    parser = _OneLineErrors(
        prog="wheelrail",
        description=(
            "Time-domain vertical wheel/rail interaction and the dynamic contact filter "
            "(Pieringer, Kropp & Thompson, Wear 271, 2011)."
        ),
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (help_text, module_name) in _commands(extra).items():
        if command in (name, "*"):
            module = importlib.import_module(module_name)
            command_parser = module.add_parser(sub)
            command_parser.set_defaults(_run=module.run, _files=getattr(module, "FILES", None))
        else:
            sub.add_parser(name, help=help_text, add_help=False)
    return parser


def _command_of(argv: list[str]) -> str | None:
    """The sub-command named on the command line (the first word that is not an option)."""
    return next((word for word in argv if not word.startswith("-")), None)


def _interrupted(error: BaseException) -> bool:
    """Whether ``error`` is, or was caused by, Ctrl-C: numba-compiled code that calls back into Python
    (e.g. to raise an exception) turns a KeyboardInterrupt arriving there into a ``SystemError`` "returned
    a result with an exception set" whose cause is the interrupt)."""
    seen = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False


def main(argv: list[str] | None = None, *, extra: dict[str, tuple[str, str]] | None = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``) with core's commands and ``extra`` ones
    (name -> (one-line help, module)); returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    command = _command_of(argv)
    name = command or ""
    try:
        with _one_line_warnings(name):
            if command in _commands(extra):  # `--help` alone stays without it
                from wheelrail.core.startup import fast_start_on_import

                fast_start_on_import()  # numba's first load made lighter, if it comes (wheelrail.core.startup)
            parser = build_parser(command if command in _commands(extra) else None, extra)
            args = parser.parse_args(argv)
            if args._files is not None:  # every command's outputs: none is an input, no two the same file
                from wheelrail.cli.commands._common import check_files

                check_files(args, args._files)
            return int(args._run(args) or 0)
    except WheelrailError as error:
        from wheelrail.cli.commands._common import cli_error_names  # not at import: `--help` loads no command

        print(f"wheelrail {name}: error: {error.render(cli_error_names())}", file=sys.stderr)
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


@contextlib.contextmanager
def _one_line_warnings(name: str):
    """Warnings (a plug-in skipped, a cache entry rebuilt) as one line each, like the errors."""
    original = warnings.formatwarning
    warnings.formatwarning = lambda message, *_args, **_kwargs: f"wheelrail {name}: warning: {message}\n"
    try:
        yield
    finally:
        warnings.formatwarning = original


if __name__ == "__main__":
    sys.exit(main())
