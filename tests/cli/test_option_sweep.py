"""Every numeric option of every command at the values a user can mistype: 0, -1, NaN, +-inf, +-1e308, 1e-308,
1e9 and 1e-9 (999999999 for counts), its declared limits and just past them, and text.

Each case is accepted (the command goes on to its work) or refused with exit code 2 and one line on stderr that
names the option and no Python exception. The options are found the way a user finds them, from each command's
``--help``; which take a number, from argparse's refusal of text; their ranges from core's declarations
(:data:`wheelrail.core.inputs.ranges.ACCEPTED`, keyed by the command line's name for each key,
``cli_error_names``). A command whose work takes seconds or more (a run, a track's Green's functions, a wheel's
modes, a study, the model track's noise) stops where that work starts: the test checks everything the command
checks before it (``stop_at_work``); the work itself on accepted values near the limits is in the slow tests
below and in the commands' own tests.
"""

from __future__ import annotations

import math
import re
import warnings

import pytest

from wheelrail.cli import main
from wheelrail.cli.commands._common import cli_error_names
from wheelrail.core.inputs.ranges import ACCEPTED

COMMON = ("0", "-1", "nan", "inf", "-inf", "1e308", "-1e308", "1e-308", "abc", "")
FLOATS = ("1e9", "1e-9")
COUNTS = ("999999999", "-999999999")
PYTHON_NAMES = re.compile(r"Traceback|\b[A-Z][A-Za-z]*(Error|Exception|Warning)\b|internal error")


class WorkStarted(BaseException):
    """Raised where a command's long work starts: everything before it (the checks) has passed."""


# (module, attribute) where each long-running command starts its work (looked up when the command runs)
WORK = (
    ("wheelrail.core.engine.prepare", "prepare_run"),
    ("wheelrail.core.track", "assemble_track"),
    ("wheelrail.core.track.fe", "assemble_track"),
    ("wheelrail.core.modal_wheel", "wheel_modes"),
    ("wheelrail.core.noise.twins", "track_noise_model"),
    ("wheelrail.core.study", "run_study"),
)


@pytest.fixture
def stop_at_work(monkeypatch):
    """The long work of run, track, wheel, study and noise --method twins replaced by raising WorkStarted."""
    import importlib

    def started(*args, **kwargs):
        raise WorkStarted

    for module, name in WORK:
        monkeypatch.setattr(importlib.import_module(module), name, started)


@pytest.fixture(scope="module")
def saved_run(tmp_path_factory):
    """A short hertz run saved with --out (for spectra and noise --run)."""
    path = tmp_path_factory.mktemp("sweep") / "run.npz"
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        code = main(["run", "--set", "corrugated-rail", "--length-m", "0.7", "--out", str(path)])
    assert code == 0
    return path


def command_help(capsys, command: str) -> str:
    with pytest.raises(SystemExit):
        main([command, "--help"])
    return capsys.readouterr().out


def numeric_options(capsys, command: str, base: list[str]) -> list[tuple[str, str]]:
    """(option, "float" or "int") of every option in ``command --help`` that argparse refuses text for."""
    options = sorted(set(re.findall(r"(--[a-z][a-z0-9-]*) [A-Z]", command_help(capsys, command))))
    found = []
    for option in options:
        _, err = run_case(capsys, [command, *base, option, "abc"])
        for kind in ("float", "int"):
            if f"invalid {kind} value" in err:
                found.append((option, kind))
    return found


def declared_ranges() -> dict[str, tuple[float, float, bool]]:
    """option -> (minimum, maximum, magnitude) in the option's unit, for every option with a declared range."""
    ranges = {}
    for key, name in cli_error_names().items():
        if key in ACCEPTED:
            low, high = ACCEPTED[key].in_unit(name.scale)
            ranges[name.label] = (low, high, ACCEPTED[key].magnitude)
    return ranges


def sweep_values(kind: str, declared: tuple[float, float, bool] | None) -> list[str]:
    """The values tried on one option: the common ones, then its declared limits and just past them."""
    values = [*COMMON, *(COUNTS if kind == "int" else FLOATS)]
    if declared is not None:
        low, high, magnitude = declared
        span = high - low if math.isfinite(high) else max(abs(low), 1.0)
        limits = [low, low - 0.01 * span]
        if math.isfinite(high):
            limits += [high, high + 0.01 * span]
        if magnitude:  # the range bounds |value|: its negative limits too
            limits += [-low, -low + 0.01 * span]
        values += [str(round(v)) if kind == "int" else repr(float(v)) for v in limits]
    return values


# (command, arguments before the option); "{run}" is the saved run's path
COMMANDS = (
    ("filters", []),
    ("roughness", ["--set", "corrugated-rail"]),
    ("spectra", ["{run}"]),
    ("noise", ["--method", "cnossos"]),
    ("noise", ["--method", "twins"]),
    ("noise", ["--run", "{run}"]),
    ("track", []),
    ("run", ["--set", "corrugated-rail", "--length-m", "0.1"]),
    ("wheel", []),
    ("study", ["track", "--set", "corrugated-rail", "--out", "{out}"]),
)


def inside(value: str, declared: tuple[float, float, bool] | None) -> bool:
    """Whether ``value`` is a number within the declared range."""
    if declared is None:
        return False
    try:
        number = float(value)
    except ValueError:
        return False
    low, high, magnitude = declared
    return low <= (abs(number) if magnitude else number) <= high


def verdict(code, err: str, option: str, others: tuple[str, ...] = ()) -> str | None:
    """None if the case is sound (accepted, or one clean line naming the option with exit code 2), else why not.
    ``others``: options the line may name instead (a value within its range that a rule between two inputs
    refuses, such as a wheel's hub against its rim, may blame the other input)."""
    if code in ("work", 0):
        return "a warning leaked" if PYTHON_NAMES.search(err) else None
    lines = [line for line in err.splitlines() if line.strip()]
    if code != 2:
        return f"exit code {code}"
    if len(lines) != 1:
        return f"{len(lines)} lines on stderr"
    if PYTHON_NAMES.search(err):
        return "a Python name in the message"
    if not any(name in err for name in (option, *others)):
        return "the option is not named"
    return None


def run_case(capsys, argv: list[str]):
    """(exit code or "work", stderr) of ``wheelrail *argv`` in this process, RuntimeWarnings as errors."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            code = main(argv)
        except WorkStarted:
            code = "work"
        except SystemExit as exit_:  # argparse's refusals
            code = exit_.code
    return code, capsys.readouterr().err


@pytest.mark.parametrize("command, base", COMMANDS, ids=[f"{c} {' '.join(b[:2])}".strip() for c, b in COMMANDS])
def test_every_numeric_option_accepts_or_refuses_in_one_line(command, base, capsys, stop_at_work, saved_run, tmp_path):
    base = [word.format(run=saved_run, out=tmp_path / "study") for word in base]
    options = numeric_options(capsys, command, base)
    assert options, f"no numeric option found in wheelrail {command} --help"
    ranges = declared_ranges()
    failures, count = [], 0
    for option, kind in options:
        for value in sweep_values(kind, ranges.get(option)):
            argv = [command, *base, f"{option}={value}"]
            code, err = run_case(capsys, argv)
            count += 1
            why = verdict(code, err, option, tuple(o for o, _ in options) if inside(value, ranges.get(option)) else ())
            if why is not None:
                failures.append(f"{' '.join(argv)}: {why}: {err.strip()[:200]!r}")
    assert not failures, f"{len(failures)} of {count} cases:\n" + "\n".join(failures)


def limit_cases(groups: tuple[str, ...]) -> list[tuple[str, str]]:
    """(option, value) at each end of the declared range of every input of ``groups``, in the option's unit."""
    from wheelrail.core.inputs.declared import inputs_of

    cases = []
    for entry in inputs_of(*groups):
        low, high = entry.in_shown()
        ends = (low, -low) if entry.accepted.magnitude else (low, high)
        cases += [(entry.option, repr(float(end))) for end in ends]
    return cases


@pytest.mark.slow
@pytest.mark.parametrize(
    "command, base, groups",
    [
        ("run", ["--set", "corrugated-rail", "--length-m", "0.05"], ("run", "geometry")),
        ("run", ["--set", "corrugated-rail", "--length-m", "0.01", "--model", "2d"], ("run", "geometry")),
        ("run", ["--set", "corrugated-rail", "--length-m", "0.01", "--model", "3d"], ("run", "geometry")),
        ("filters", [], ("run", "geometry")),
        ("noise", ["--method", "cnossos"], ("geometry",)),
        ("noise", ["--run", "{run}"], ()),
    ],
    ids=["run hertz", "run 2d", "run 3d", "filters", "noise cnossos", "noise run"],
)
def test_accepted_values_at_the_limits_work_without_numpy_warnings(command, base, groups, capsys, saved_run):
    """Each declared input at each end of its range does the command's whole work (a short run), RuntimeWarnings
    as errors; a refusal by a rule between inputs (the patch against the radii) is one clean line. (``run --model
    3d --preload-kn 1`` ended in an internal LinAlgError in the steady start.)"""
    base = [word.format(run=saved_run) for word in base]
    extra = {"noise": [("--speed-kmh", "5"), ("--speed-kmh", "400"), ("--preload-kn", "1"), ("--preload-kn", "500")]}
    trains = [("--train-axles", "1"), ("--train-axles", "2000"), ("--train-length-m", "5000"), ("--axles", "1")]
    cases = limit_cases(groups) + extra.get(command, []) + (trains if "--run" in base else [])
    failures = []
    for option, value in cases:
        argv = [command, *base, option, value]
        code, err = run_case(capsys, argv)
        # a rule between inputs may blame another one, or the roughness line that cannot hold a wider patch
        why = verdict(code, err, option, (*(o for o, _ in cases), "--line", "--set"))
        if why is not None:
            failures.append(f"{' '.join(argv)}: {why}: {err.strip()[:200]!r}")
    assert not failures, "\n".join(failures)
