"""One way to word an error: core raises it as data; the API, the command line and the explorer page each name
the input in their own terms (argument, option, field label) and units. Nothing rewrites a finished message."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from wheelrail.cli.commands._common import CLI_NAMES
from wheelrail.core.errors import Blame, Name, WheelrailError
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.parameters import KMH, ContactParameters, RunParameters
from wheelrail.explorer.config import FIELD_NAMES, page_message

ROOT = Path(__file__).resolve().parents[2]
REASON = ACCEPTED["preload"].reason


def _error(call, *args, **kwargs) -> WheelrailError:
    with pytest.raises(WheelrailError) as info:
        call(*args, **kwargs)
    return info.value


def test_a_preload_out_of_range_in_three_front_ends():
    error = _error(ContactParameters, preload=5e6)
    assert str(error) == f"ContactParameters.preload 5e+06 N is outside the accepted 1000 to 500000 N ({REASON})"
    assert error.render(CLI_NAMES) == f"--preload-kn 5000 is outside the accepted 1 to 500 kN ({REASON})"
    assert page_message(error) == f"Preload 5000 kN is outside the accepted 1 to 500 kN ({REASON})"


def test_a_speed_out_of_range_in_three_front_ends():
    error = _error(RunParameters, speed=401 * KMH)
    assert str(error).startswith("RunParameters.speed 111.389 m/s is outside the accepted 1.38889 to 111.111 m/s (")
    assert error.render(CLI_NAMES).startswith("--speed-kmh 401 is outside the accepted 5 to 400 km/h (")
    assert page_message(error).startswith("Speed 401 km/h is outside the accepted 5 to 400 km/h (")


def test_a_run_longer_than_its_data_in_three_front_ends():
    # core's own error of the run set-up (it once said "use --length-m <= ..." to every front end)
    from wheelrail.core.engine import prepare_run

    error = _error(prepare_run, "corrugated-rail", length=100.0)
    problem = "with the 20 mm window margins at each end the run needs more than the 7.999 m of rail roughness data"
    assert str(error) == f"length 100 m: {problem}; accepted at most 7.959 m"
    assert error.render(CLI_NAMES) == f"--length-m 100: {problem}; accepted at most 7.959 m"
    assert page_message(error) == f"Run length 100 m: {problem}; accepted at most 7.959 m"


def test_a_wheel_set_of_another_wheel_in_three_front_ends():
    from wheelrail.core.engine import prepare_run

    error = _error(prepare_run, "corrugated-rail", wheel_roughness="sinter-wheel-1", length=0.05)
    assert str(error).startswith("ContactParameters.wheel_radius 0.39 m: the wheel set sinter-wheel-1 is 2.9 m round")
    assert "; accepted 0.45698 to 0.466211 m (" in str(error)
    assert error.render(CLI_NAMES).startswith("--wheel-radius-mm 390: the wheel set sinter-wheel-1 is 2.9 m round")
    assert "; accepted 456.98 to 466.211 mm (" in error.render(CLI_NAMES)
    assert page_message(error).startswith("Wheel radius 390 mm: the wheel set sinter-wheel-1")


def test_advice_is_given_where_the_remedy_is_known_and_names_no_option():
    # the spectrum's skip: an argument of force_spectrum and an option of `wheelrail spectra` (ms)
    import numpy as np

    from wheelrail.core.spectra.force import force_spectrum

    error = _error(force_spectrum, np.zeros(100), 1e-3, skip=0.09)
    assert str(error) == (
        "skip 0.09 s: the record of 100 steps (0.1 s) leaves 10 steps after the skip, and a "
        "spectrum needs 16; accepted at most 0.084 s; or use a longer run"
    )
    assert error.render(CLI_NAMES).startswith("--skip-ms 90: the record of 100 steps")
    assert "; accepted at most 84 ms; or use a longer run" in error.render(CLI_NAMES)


def test_a_message_without_an_input_reads_the_same_everywhere():
    error = WheelrailError("file x.npz is damaged")
    assert str(error) == error.render(CLI_NAMES) == page_message(error) == "file x.npz is damaged"
    # an input a front end has no name for keeps the API's name
    other = WheelrailError("too coarse", Blame("element_size", 0.01, unit="m"))
    assert other.render(CLI_NAMES) == page_message(other) == str(other) == "element_size 0.01 m: too coarse"


def test_every_physical_input_has_a_name_on_the_command_line_and_in_the_page():
    for key in (*ACCEPTED, "length"):
        assert isinstance(CLI_NAMES[key], Name) and CLI_NAMES[key].label.startswith("--")
        assert isinstance(FIELD_NAMES[key], Name) and not FIELD_NAMES[key].label.startswith("-")
    for key, name in CLI_NAMES.items():  # an option in mm carries mm values: its scale is that of its unit
        scale = {
            "km/h": 3.6,
            "kN": 1e-3,
            "mm": 1e3,
            "m": 1.0,
            "ms": 1e3,
            "MN/m": 1e-6,
            "kNs/m": 1e-3,
            "kNm/rad": 1e-3,
            "kg": 1.0,
            "Hz": 1.0,
        }
        assert name.scale == pytest.approx({**scale, "": 1.0}[name.unit]), key
        unit = name.unit.replace("/", "-").lower().replace("km-h", "kmh")  # --pad-stiffness-mn-m, --speed-kmh
        assert name.unit_in_label and (not name.unit or name.label.endswith(unit)), key


_CLI_MODULES = ("cli/dispatch.py", "cli/commands/", "core/recording/cli.py")


def _core_error_texts():
    """The string parts of every WheelrailError(...) raised in core outside the command-line modules."""
    for path in sorted((ROOT / "core").rglob("*.py")):
        relative = path.relative_to(ROOT).as_posix()
        if relative.startswith(_CLI_MODULES):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "WheelrailError":
                for part in ast.walk(node):
                    if isinstance(part, ast.Constant) and isinstance(part.value, str):
                        yield relative, node.lineno, part.value


def test_core_messages_name_no_command_line_option():
    found = [
        f"{path}:{line}: {text!r}" for path, line, text in _core_error_texts() if re.search(r"(^|[\s(])--[a-z]", text)
    ]
    assert not found, "\n".join(found)
    assert len(list(_core_error_texts())) > 200  # the scan sees core's messages


def test_no_front_end_rewrites_a_message():
    # the tables that once reworded core's sentences by substring or regex are gone, and nothing took their place
    sources = {
        path.relative_to(ROOT).as_posix(): path.read_text(encoding="utf-8")
        for folder in ("core", "explorer")
        for path in (ROOT / folder).rglob("*.py")
    }
    pattern = re.compile(
        r"str\((error|err|exc|e)\)\s*\.replace|\.sub\([^)]*str\((error|err|exc|e)\)|in_page_words|"
        r"_cli_wording|_CLI_ADVICE|_CLI_HINTS|\{(error|err|exc|e)\}[^\n]*\"\s*\)?\.replace\("
    )
    found = [f"{name}: {match.group(0)}" for name, text in sources.items() for match in pattern.finditer(text)]
    assert not found, found
