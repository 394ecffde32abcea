"""Only physical inputs on the command line: every input that once ran silently is one error line naming the
option, in the option's unit, with the accepted range of core/inputs/ranges.py; the help states the same ranges."""

from __future__ import annotations

import pytest

from wheelrail.cli.dispatch import build_parser, main
from wheelrail.core.inputs.ranges import ACCEPTED

RUN = ["run", "--set", "corrugated-rail", "--length-m", "0.05"]


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        ([*RUN, "--wheel-radius-mm", "0.001"], "--wheel-radius-mm 0.001 is outside the accepted 100 to 1250 mm ("),
        ([*RUN, "--wheel-radius-mm", "1e6"], "--wheel-radius-mm 1e+06 is outside the accepted 100 to 1250 mm ("),
        (
            [*RUN, "--rail-crown-radius-mm", "0.001"],
            "--rail-crown-radius-mm 0.001 is outside the accepted 50 to 5000 mm (",
        ),
        (
            [*RUN, "--rail-crown-radius-mm", "300", "--wheel-transverse-radius-mm", "-300.5"],
            "--wheel-transverse-radius-mm -300.5: the Hertz patch at the preload would be 0.148 m wide across the rail",
        ),
        ([*RUN, "--preload-kn", "5000"], "--preload-kn 5000 is outside the accepted 1 to 500 kN ("),
        ([*RUN, "--preload-kn", "0.1"], "--preload-kn 0.1 is outside the accepted 1 to 500 kN ("),
        (["filters", "--preload-kn", "1e12"], "--preload-kn 1e+12 is outside the accepted 1 to 500 kN ("),
        (["filters", "--wheel-radius-mm", "1e6"], "--wheel-radius-mm 1e+06 is outside the accepted 100 to 1250 mm ("),
        (["track", "--speed-kmh", "401"], "--speed-kmh 401 is outside the accepted 5 to 400 km/h ("),
        (["track", "--speed-kmh", "4"], "--speed-kmh 4 is outside the accepted 5 to 400 km/h ("),
        (
            ["roughness", "--set", "corrugated-rail", "--speed-kmh", "4"],
            "--speed-kmh 4 is outside the accepted 5 to 400",
        ),
        (
            [*RUN, "--wheel-set", "sinter-wheel-1"],
            "--wheel-radius-mm 390: the wheel set sinter-wheel-1 is 2.9 m round (a wheel of radius 0.4615 m)",
        ),
        (
            ["study", "filters", "--set", "corrugated-rail", "--wheel-set", "sinter-wheel-1", "--length-m", "1"],
            "--wheel-radius-mm 390: the wheel set sinter-wheel-1 is 2.9 m round",
        ),
        (["study", "filters", "--set", "corrugated-rail", "--speed-kmh", "401"], "--speed-kmh 401 is outside"),
    ],
)
def test_an_unphysical_input_is_one_line_in_the_options_terms(argv, line, capsys, tmp_path):
    if argv[0] == "study":
        argv = [*argv, "--out", str(tmp_path / "study")]
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert err.startswith(f"wheelrail {argv[0]}: error: {line}"), err
    assert len(err.strip().splitlines()) == 1 and out == ""
    assert "ContactParameters" not in err and "RunParameters" not in err and "m/s" not in err


@pytest.mark.slow
def test_a_combined_run_on_the_wheel_sets_own_radius_runs(capsys):
    # the bundled wheel sets are 2.900 m round: 461.5 mm is within 1 % (and so is 460)
    for radius in ("461.5", "460"):
        assert main([*RUN, "--wheel-set", "sinter-wheel-1", "--wheel-radius-mm", radius, "--json"]) == 0
        capsys.readouterr()


def test_a_run_too_short_for_a_spectrum_says_so_in_the_options_terms(capsys):
    assert main(["run", "--set", "corrugated-rail", "--length-m", "0.1"]) == 0
    out = capsys.readouterr().out
    assert (
        "no force spectrum: --length-m 0.1: too short for a force spectrum at 100 km/h, which leaves out the "
        "first 20 ms (start-up) and needs 16 steps after them; accepted at least 0.572 m"
    ) in out


def test_the_help_states_the_accepted_ranges_of_core():
    helps = {}
    for command in ("run", "filters", "study", "track", "roughness"):
        sub = build_parser(command)._subparsers._group_actions[0].choices[command]
        helps[command] = {action.dest: action.help for action in sub._actions}
        assert "accepted" in sub.format_help()  # the help formats (a bare % in it would not)
    low, high = ACCEPTED["preload"].in_unit(1e-3)
    assert (low, high) == (1.0, 500.0)
    for command in ("run", "filters"):
        assert "accepted 1 to 500" in helps[command]["preload_kn"]
        assert "accepted 100 to 1250" in helps[command]["wheel_radius_mm"]
        assert "accepted 50 to 5000" in helps[command]["rail_crown_radius_mm"]
    for command in ("run", "filters", "study", "track", "roughness"):
        assert "accepted 5 to 400" in helps[command]["speed_kmh"], command
