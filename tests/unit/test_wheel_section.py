"""What a wheel is (``core/modal_wheel/section.py``): one set of rules for the shape options and an outline, each
stated in its message as it is tested; a mode near 0 Hz is refused or named for what it is."""

from __future__ import annotations

import json
import warnings
from dataclasses import fields

import numpy as np
import pytest

from wheelrail.cli import main
from wheelrail.core.errors import WheelrailError
from wheelrail.core.modal_wheel import (
    NAMED_WHEELS,
    WheelProfile,
    outline_profile,
    profile_from_description,
    read_outline,
    wheel_modes,
)
from wheelrail.core.modal_wheel.modes import MIN_MODE_FREQUENCY, _check_strain_free
from wheelrail.core.modal_wheel.section import MIN_AREA, MIN_THICKNESS, thinnest_part

FAST = {"max_frequency": 2e3, "max_harmonic": 2, "element_size": 0.02, "use_cache": False}


def _rectangle(r0, r1, z0, z1):
    return [[r0, z0], [r1, z0], [r1, z1], [r0, z1]]


def _web_wheel(web):
    """A hub, a web ``web`` m thick and a rim (m), counter-clockwise."""
    h = web / 2
    return [[0.08, -0.04], [0.11, -0.04], [0.11, -h], [0.28, -h], [0.28, -0.06], [0.32, -0.06], [0.32, 0.06],
            [0.28, 0.06], [0.28, h], [0.11, h], [0.11, 0.04], [0.08, 0.04]]  # fmt: skip


def _refusal(make) -> str | None:
    try:
        make()
    except WheelrailError as error:
        assert "\n" not in str(error)
        return str(error)
    return None


def test_a_10_by_9_mm_ring_is_refused_by_the_area_its_message_states():
    message = _refusal(lambda: outline_profile(_rectangle(0.40, 0.41, 0.0, 0.009), contact_z=0.004))
    assert message is not None and "0.9 cm^2" in message and f"at least {MIN_AREA * 1e4:g} cm^2" in message
    # the limit tested is the limit stated: just above it the area rule passes (a 40 mm thick plate of 10.2 cm^2)
    side = MIN_AREA * 1.02 / 0.04
    assert _refusal(lambda: outline_profile(_rectangle(0.1, 0.1 + side, -0.02, 0.02), contact_z=0.0)) is None
    below = MIN_AREA * 0.98 / 0.04
    assert "area" in _refusal(lambda: outline_profile(_rectangle(0.1, 0.1 + below, -0.02, 0.02), contact_z=0.0))


@pytest.mark.parametrize("web_mm", [0.2, 1.0, 5.0, 9.5])
def test_a_web_thinner_than_10_mm_is_refused_naming_its_thickness(web_mm):
    message = _refusal(lambda: outline_profile(_web_wheel(web_mm * 1e-3), contact_z=0.0))
    assert message is not None and f"is {web_mm:g} mm thick" in message and "at least 10 mm" in message


@pytest.mark.parametrize("thickness_mm", [1.0, 2.0, 5.0])
def test_thin_discs_are_refused_and_a_10_mm_disc_is_a_wheel(thickness_mm):
    disc = _rectangle(0.1, 0.46, -thickness_mm / 2e3, thickness_mm / 2e3)
    assert _refusal(lambda: outline_profile(disc, contact_z=0.0)) is not None
    assert _refusal(lambda: outline_profile(_rectangle(0.1, 0.46, -0.005, 0.005), contact_z=0.0)) is None


def test_the_thinnest_part_is_measured_across_the_material_not_along_a_corner():
    thickness, (r, z) = thinnest_part(np.array(_web_wheel(0.02)))
    assert thickness == pytest.approx(0.02, rel=1e-3) and 0.11 < r < 0.28 and z == pytest.approx(0.0, abs=1e-3)
    # a compact block has no thin part; a notch of air is not a thickness
    assert thinnest_part(np.array(_rectangle(0.1, 0.14, 0.0, 0.04)))[0] == np.inf
    notch = [[0.1, 0], [0.3, 0], [0.3, 0.1], [0.2, 0.1], [0.2, 0.05], [0.199, 0.05], [0.199, 0.1], [0.1, 0.1]]
    assert 0.045 < thinnest_part(np.array(notch))[0] < 0.06  # under the 1 mm notch (50 mm), not across it


def _unchecked(**changes) -> WheelProfile:
    """A WheelProfile built without its checks, for its outline."""
    profile = object.__new__(WheelProfile)
    values = {**{f.name: getattr(NAMED_WHEELS["freight_920"], f.name) for f in fields(WheelProfile)}, **changes}
    for name, value in values.items():
        object.__setattr__(profile, name, value)
    return profile


@pytest.mark.parametrize(
    ("changes", "blamed"),
    [
        ({}, None),
        ({"flange_thickness": 0.005}, "wheel_flange_thickness"),  # a 5 mm fin: the shape options took it
        ({"hub_outer_radius": 0.1}, "wheel_hub_outer_radius"),  # 5 mm of hub around the bore
        ({"web_thickness": 0.01, "web_offset": 0.15}, "wheel_web_thickness"),  # a steep 10 mm web: 8 mm across
        ({"wheel_radius": 1.25, "flange_height": 0.05}, None),  # the outline refused its flange above 1.25 m
        ({"wheel_radius": 1.25, "hub_inner_radius": 0.2, "hub_outer_radius": 0.3}, None),
    ],
)
def test_the_shape_options_and_the_outline_accept_the_same_wheels(changes, blamed):
    arguments = {f.name: getattr(_unchecked(**changes), f.name) for f in fields(WheelProfile)}
    by_shape = _refusal(lambda: WheelProfile(**arguments))
    by_outline = _refusal(lambda: outline_profile(_unchecked(**changes).outline(), contact_z=0.0))
    assert (by_shape is None) == (by_outline is None), (by_shape, by_outline)
    if blamed is not None:
        with pytest.raises(WheelrailError) as caught:
            WheelProfile(**arguments)
        assert caught.value.parameter == blamed and "mm thick" in str(caught.value)


def test_the_command_line_names_the_shape_option_of_a_thin_part(capsys):
    assert main(["wheel", "--flange-thickness-mm", "5", "--max-harmonic", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("wheelrail wheel: error: --flange-thickness-mm 5: the cross-section is 5 mm thick")
    assert err.count("\n") == 1


def test_a_clockwise_outline_is_the_same_wheel():
    ccw = outline_profile(_web_wheel(0.025), contact_z=0.0)
    cw = outline_profile(_web_wheel(0.025)[::-1], contact_z=0.0)
    assert set(cw.points) == set(ccw.points) and cw.contact == ccw.contact
    np.testing.assert_allclose(wheel_modes(cw, **FAST).frequency, wheel_modes(ccw, **FAST).frequency, rtol=1e-9)


def test_repeated_points_next_to_each_other_are_dropped_elsewhere_refused():
    points = _web_wheel(0.025)
    repeated = [points[0], *points[:5], points[4], *points[5:], points[0]]  # the first at the end too
    assert outline_profile(repeated, contact_z=0.0).points == outline_profile(points, contact_z=0.0).points
    touching = [*points[:6], points[2], *points[6:]]  # back to an earlier corner: the outline touches itself
    assert "touches itself" in _refusal(lambda: outline_profile(touching, contact_z=0.0))


@pytest.mark.parametrize(
    "points",
    [
        [[0.1, 0.0], [0.4, 0.04], [0.4, 0.0], [0.1, 0.04]],  # a figure of eight
        [[0.1, 0.0], [0.4, 0.0], [0.4, 0.04], [0.25, 0.04], [0.25, 0.0], [0.1, 0.04]],  # a vertex on an edge
        [[0.1, 0.0], [0.4, 0.0], [0.4, 0.04], [0.3, 0.04], [0.35, 0.04], [0.1, 0.04]],  # doubling back on itself
    ],
)
def test_an_outline_that_crosses_or_touches_itself_is_refused(points):
    assert "crosses or touches itself" in _refusal(lambda: outline_profile(points, contact_z=0.0))


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (
            "0.08,-0.04\n0.32,-0.04\n0.32,0.04\n0.08,0.04\n",
            "the largest r is 0.32 mm, below the smallest tread's 100 mm; "
            "the outline is read in mm (were its values metres, inches or cm?)",
        ),
        ("3.1,-1.6\n18.1,-1.6\n18.1,1.6\n3.1,1.6\n", "the largest r is 18.1 mm, below"),  # inches
        ("80,-40\n320,-40\n320,1e300\n80,40\n", "is 1e+300 mm from the axle's axis"),
        ("80,nan\n320,-40\n320,40\n80,40\n", "two finite numbers"),
        ("80,-40\n320,-40\n320,1e400\n80,40\n", "two finite numbers"),
        ("80,-40\n320,-40\n320,20\n380,20\n380,40\n80,40\n", "reaches 60 mm above the tread"),
        ("10,-40\n320,-40\n320,40\n10,40\n", "the bore (the smallest r) is at 10 mm; accepted 30 to 200 mm"),
    ],
)
def test_outlines_in_the_wrong_unit_or_shape_are_one_line_saying_what(tmp_path, text, words):
    path = tmp_path / "outline.csv"
    path.write_text(text, encoding="utf-8")
    assert words in _refusal(lambda: read_outline(path, contact_z_mm=0.0))


def test_a_near_zero_mode_is_a_mechanism_unless_a_free_hubs_rigid_body_motion():
    below = MIN_MODE_FREQUENCY / 2
    with pytest.raises(WheelrailError, match="moves without strain"):
        _check_strain_free(np.array([below, 250.0]), 3, clamped=True)
    _check_strain_free(np.array([0.0, below, 300.0]), 0, clamped=False)  # along and about the axle
    with pytest.raises(WheelrailError, match="where a free wheel has 2"):
        _check_strain_free(np.array([0.0, 0.0, below]), 1, clamped=False)
    with pytest.raises(WheelrailError):
        _check_strain_free(np.array([below]), 2, clamped=False)


def test_a_free_hubs_rigid_body_motions_are_not_printed_as_natural_frequencies(capsys):
    argv = ["wheel", "--wheel", "wheel_640", "--free-hub", "--max-harmonic", "3", "--max-frequency-hz", "2000",
            "--element-size-mm", "20"]  # fmt: skip
    assert main([*argv, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    table = summary["natural_frequencies_hz"]
    assert [row["rigid_body"] for row in table] == [2, 2, 0, 0] and summary["modes"]["rigid_body"] == 4
    frequencies = [f for row in table for key in ("axial", "radial", "circumferential") for f in row[key]]
    assert len(frequencies) == summary["modes"]["count"] and min(frequencies) > 100.0
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "4 rigid-body motions" in text and " 0;" not in text and "axial 0 " not in text


def test_a_minimum_thickness_wheel_is_accepted_and_has_no_mode_near_0_hz():
    profile = outline_profile(_web_wheel(MIN_THICKNESS), contact_z=0.0)
    modes = wheel_modes(profile, **FAST)
    assert modes.frequency.min() > 20.0 and not modes.rigid_body.any()


def test_no_mode_in_range_is_said_not_left_as_empty_rows(capsys):
    argv = ["wheel", "--wheel", "wheel_640", "--max-frequency-hz", "100", "--max-harmonic", "1", "--element-size-mm",
            "30"]  # fmt: skip
    assert main(argv) == 0
    assert "no natural frequency up to 100 Hz: raise --max-frequency-hz to see some" in capsys.readouterr().out


@pytest.mark.parametrize("scale", [1e300, 1e-300])
def test_extreme_coordinates_are_one_line_without_numpy_warnings(scale):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _refusal(lambda: outline_profile(np.array(_web_wheel(0.02)) * scale, contact_z=0.0)) is not None


@pytest.mark.parametrize(
    ("description", "words"),
    [
        ({"kind": "outline", "points": [[0.1, 0.0]]}, "damaged (a field missing"),
        ({"kind": "outline", "points": "x", "contact": [0.4, 0.0]}, "damaged (a field missing"),
        (
            {"kind": "parametric", "wheel_radius": 0.46, "flange_height": 0.03, "flange_thickness": 0.005},
            "not a wheel: WheelProfile.flange_thickness 0.005 m: the cross-section is 5 mm thick",
        ),
    ],
)
def test_a_recorded_profile_is_checked_as_any_and_refused_without_python_names(description, words):
    message = _refusal(lambda: profile_from_description(description))
    assert words in message and "Error" not in message


@pytest.mark.parametrize("name", list(NAMED_WHEELS))
def test_every_accepted_rolling_radius_that_fits_a_named_wheels_parts_is_a_wheel(name):
    # the rules of section.py refuse nothing the named wheels' parts allow, to the last float of the range
    from wheelrail.core.modal_wheel import wheel_profile_for

    made = 0
    for radius in np.arange(0.1, 1.2501, 0.025):
        try:
            wheel_profile_for(float(radius), name)
            made += 1
        except WheelrailError as error:
            assert "the web must span at least twice its thickness" in str(error), (radius, str(error))
    assert made >= 40
