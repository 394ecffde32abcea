"""`wheelrail run` with a wheel set added to the rail set and with real contact geometry."""

import json

import numpy as np
import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.engine.results import RunResult
from wheelrail.core.parameters import ContactParameters


def test_wheel_set_and_geometry_reach_the_run(tmp_path, capsys):
    out = tmp_path / "run.npz"
    argv = [
        "run",
        "--set",
        "corrugated-rail",
        "--wheel-set",
        "sinter-wheel-1",
        "--model",
        "hertz",
        "--wheel-radius-mm",
        "461.5",
        "--rail-crown-radius-mm",
        "300",
        "--wheel-transverse-radius-mm",
        "-500",
        "--length-m",
        "0.1",
        "--out",
        str(out),
        "--json",
    ]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["set"] == "corrugated-rail" and summary["wheel_set"] == "sinter-wheel-1"
    result = RunResult.load_npz(out)
    assert result.wheel_roughness_name == "sinter-wheel-1"
    contact = result.header.params.contact
    assert (contact.wheel_radius, contact.rail_crown_radius, contact.wheel_transverse_radius) == pytest.approx(
        (0.4615, 0.30, -0.50)
    )
    # the hertz law's contact length is 2a of that ellipse at each step's force
    assert np.allclose(result.contact_length, [2 * contact.hertz(f).semi_axis_along for f in result.force])


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        (["--wheel-set", "corrugated-rail"], "the wheel roughness is a rail set"),
        (["--wheel-radius-mm", "-460"], "--wheel-radius-mm -460 is outside the accepted 100 to 1250 mm"),
        (["--rail-crown-radius-mm", "nan"], "--rail-crown-radius-mm nan: not a number"),
        (
            ["--wheel-transverse-radius-mm", "0"],
            "--wheel-transverse-radius-mm 0 is outside the accepted range, a magnitude of at least 50 mm",
        ),
        (
            ["--wheel-transverse-radius-mm", "-300"],
            "--wheel-transverse-radius-mm -300: a concave tread of radius "
            "0.3 m fits the rail crown of radius 0.39 m or closer",
        ),
    ],
)
def test_bad_wheel_set_or_geometry_is_one_line(extra, fragment, capsys):
    assert main(["run", "--set", "corrugated-rail", "--length-m", "0.05", *extra]) != 0
    err = capsys.readouterr().err.strip()
    assert fragment in err and len(err.splitlines()) == 1


def _contact_line(text: str, start: str) -> str:
    return next(line.split(start, 1)[1] for line in text.splitlines() if start in line)


def test_the_unset_crown_is_one_rule_in_run_and_filters(capsys):
    """An unset rail crown is the paper's R = 0.39 m whatever the wheel (``ContactParameters.crown_radius``):
    ``filters`` and ``run`` with a 0.46 m wheel give the same ellipse (Hertz, a = 5.95 mm along the rail for
    R_x = 0.46 m, b = 5.33 mm across for R_y = 0.39 m) and state the same geometry, text and JSON."""
    wheel = ["--wheel-radius-mm", "460"]
    assert main(["filters", "--json", *wheel]) == 0
    filters = json.loads(capsys.readouterr().out)
    argv = ["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "0.1", *wheel]
    assert main([*argv, "--json"]) == 0
    run = json.loads(capsys.readouterr().out)
    expected = ContactParameters(wheel_radius=0.46).hertz_semi_axes()
    assert expected[0] > 1.05 * expected[1]  # an ellipse: the crown did not follow the wheel
    assert filters["semi_axes_m"] == pytest.approx(expected, rel=1e-12)  # one formula: equal to rounding
    assert run["hertz_semi_axes_m"] == pytest.approx(expected, rel=1e-12)
    assert filters["geometry"] == run["geometry"]
    assert run["geometry"]["rail_crown_radius"] == pytest.approx(0.39)
    assert main(["filters", *wheel]) == 0
    filters_text = capsys.readouterr().out
    assert main(argv) == 0
    run_text = capsys.readouterr().out
    words = _contact_line(run_text, "contact geometry: ")
    assert "rail crown radius 390 mm (the paper's R)" in words and "a = 5.95 mm along" in words
    assert _contact_line(filters_text, "contact geometry: ") == words
