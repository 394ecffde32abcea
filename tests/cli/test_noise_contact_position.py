"""The contact's lateral position, declared once (``core.inputs.contact_position``): SI inside, mm on the command
line, its range and one-line errors; ``wheelrail noise`` takes it for ``--method twins`` and ``--run`` only."""

from __future__ import annotations

import math

import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.contact_position import CONTACT_POSITION_INPUTS, ContactPosition
from wheelrail.core.inputs.ranges import ACCEPTED


def test_declared_once_si_inside_mm_at_the_edge():
    assert [(e.key, e.option, e.field) for e in CONTACT_POSITION_INPUTS] == [
        ("contact_offset_rail", "--contact-offset-rail-mm", "rail_offset"),
        ("contact_offset_wheel", "--contact-offset-wheel-mm", "wheel_offset"),
    ]
    assert ContactPosition() == ContactPosition(0.0, 0.0) and ContactPosition().centred
    assert [e.shown_default() for e in CONTACT_POSITION_INPUTS] == [0.0, 0.0]
    assert [e.accepted_text() for e in CONTACT_POSITION_INPUTS] == ["-30 to 30 mm", "-40 to 40 mm"]
    assert ACCEPTED["contact_offset_rail"].unit == "m"
    assert ContactPosition(rail_offset=0.01).to_dict() == {"rail_offset_m": 0.01, "wheel_offset_m": 0.0}


@pytest.mark.parametrize(
    ("values", "key"),
    [({"rail_offset": 0.031}, "contact_offset_rail"), ({"wheel_offset": -0.05}, "contact_offset_wheel"),
     ({"rail_offset": math.nan}, "contact_offset_rail"), ({"wheel_offset": "5"}, "contact_offset_wheel")],
)  # fmt: skip
def test_a_position_outside_its_range_is_one_error_keyed_by_its_input(values, key):
    with pytest.raises(WheelrailError) as caught:
        ContactPosition(**values)
    assert caught.value.parameter == key and "\n" not in str(caught.value)


@pytest.mark.parametrize(
    ("argv", "wording"),
    [
        (["--method", "twins", "--contact-offset-rail-mm", "31"],
         "--contact-offset-rail-mm 31 is outside the accepted -30 to 30 mm (on the railhead's crown"),
        (["--method", "twins", "--contact-offset-wheel-mm", "nan"], "--contact-offset-wheel-mm nan: not a number"),
        (["--method", "cnossos", "--contact-offset-rail-mm", "5"], "--contact-offset-rail-mm: not used by --method"),
    ],
)  # fmt: skip
def test_the_command_line_names_the_option_in_one_line(argv, wording, capsys):
    assert main(["noise", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith(f"wheelrail noise: error: {wording}"), err
    assert "Traceback" not in err and "WheelrailError" not in err


def test_the_help_says_the_position_its_default_and_range(capsys):
    with pytest.raises(SystemExit):
        main(["noise", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--contact-offset-rail-mm" in text and "--contact-offset-wheel-mm" in text
    assert "(default 0; accepted -30 to 30 mm)" in text and "(default 0; accepted -40 to 40 mm)" in text
