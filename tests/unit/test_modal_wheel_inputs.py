"""The modal wheel's inputs: the parametric profile's ranges and rules, the named wheels, the CSV outline's
checks (one WheelrailError line each), the modes' cache."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.modal_wheel import (
    NAMED_WHEELS,
    WheelProfile,
    mean_square_velocity,
    named_profile,
    outline_profile,
    read_outline,
    section_mass,
    wheel_modes,
    wheel_profile_for,
)


def test_every_profile_field_has_an_accepted_range_and_the_named_wheels_lie_within():
    for name, profile in NAMED_WHEELS.items():
        for field, value in profile.describe().items():
            if field != "kind":
                key = field if field == "wheel_radius" else f"wheel_{field}"
                assert ACCEPTED[key].check(value) == value, (name, field)
    assert 2 * NAMED_WHEELS["freight_920"].wheel_radius == pytest.approx(0.92)
    assert 2 * NAMED_WHEELS["wheel_840"].wheel_radius == pytest.approx(0.84)
    assert 2 * NAMED_WHEELS["wheel_640"].wheel_radius == pytest.approx(0.64)


@pytest.mark.parametrize(
    ("change", "parameter"),
    [
        ({"web_thickness": 0.2}, "wheel_web_thickness"),  # outside its range
        ({"tyre_width": 0.08, "web_thickness": 0.09}, "wheel_web_thickness"),
        ({"wheel_radius": 0.2}, "wheel_hub_outer_radius"),  # no room for the web
        ({"contact_offset": 0.066}, "wheel_contact_offset"),  # off the tread
        ({"wheel_radius": 460.0}, "wheel_radius"),  # mm given as m
    ],
)
def test_a_profile_that_cannot_be_a_wheel_is_one_error_naming_its_input(change, parameter):
    fields = {**NAMED_WHEELS["freight_920"].describe(), **change}
    del fields["kind"]
    with pytest.raises(WheelrailError) as caught:
        WheelProfile(**fields)
    assert caught.value.parameter == parameter
    assert "\n" not in str(caught.value)


def test_an_unknown_named_wheel_lists_the_names():
    with pytest.raises(WheelrailError, match="freight_920, wheel_840, wheel_640"):
        named_profile("tram")


def test_a_csv_outline_is_read_in_mm_and_its_contact_becomes_a_vertex(tmp_path):
    path = tmp_path / "disc.csv"
    path.write_text("r_mm,z_mm\n100,-20\n400,-20\n400,20\n100,20\n", encoding="utf-8")
    profile = read_outline(path, contact_z_mm=5.0)
    assert profile.contact_point() == pytest.approx((0.4, 0.005))
    assert (0.4, 0.005) in [tuple(np.round(p, 12)) for p in profile.points]
    assert profile.bore_radius == pytest.approx(0.1) and profile.wheel_radius == pytest.approx(0.4)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("100,0\n400,0\n", "at least 3 distinct"),
        ("100,0\n400,0\nx,y\n100,20\n", "line 3"),
        ("100,0\n400,0,1\n400,20\n100,20\n", "3 values"),
        ("0,0\n400,0\n400,20\n0,20\n", "r > 0"),
        ("100,0\n400,20\n400,0\n100,20\n", "crosses or touches itself"),
        ("100,0\n2000,0\n2000,20\n100,20\n", "the tread (the contact's r) is at 2000 mm"),
        ("100,0\n4000,0\n4000,20\n100,20\n", "a point of the outline is 4000 mm from the axle's axis"),
    ],
)
def test_a_bad_csv_outline_is_one_line(tmp_path, text, words):
    path = tmp_path / "bad.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(WheelrailError) as caught:
        read_outline(path, contact_z_mm=10.0)
    assert words in str(caught.value) and "\n" not in str(caught.value)


def test_a_contact_outside_the_outline_and_a_missing_file_are_refused(tmp_path):
    with pytest.raises(WheelrailError, match="within the outline"):
        outline_profile([[0.1, 0.0], [0.4, 0.0], [0.4, 0.02], [0.1, 0.02]], contact_z=0.5)
    with pytest.raises(WheelrailError, match="cannot read"):
        read_outline(tmp_path / "absent.csv", 0.0)


def test_an_outline_wheel_has_modes_like_the_same_parametric_one():
    # the parametric profile's own outline, given as points, is the same cross-section: the same frequencies
    profile = WheelProfile(wheel_radius=0.32, tyre_width=0.12, tyre_depth=0.04, hub_inner_radius=0.08,
                           hub_outer_radius=0.11, hub_width=0.12)  # fmt: skip
    outline = outline_profile(profile.outline(), contact_z=0.0)
    settings = {"max_frequency": 3e3, "max_harmonic": 3, "element_size": 0.02, "use_cache": False}
    np.testing.assert_allclose(wheel_modes(outline, **settings).frequency, wheel_modes(profile, **settings).frequency)


def test_modes_are_cached_on_disk_and_read_back_the_same(monkeypatch, tmp_path):
    from wheelrail.core.modal_wheel import modes as modes_module

    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(modes_module, "_MEMORY", {})
    settings = {"max_frequency": 2e3, "max_harmonic": 2, "element_size": 0.02}
    first = wheel_modes(named_profile("wheel_640"), **settings)
    assert first.cache_path and (tmp_path / first.cache_path.split("/")[-1]).exists()
    monkeypatch.setattr(modes_module, "_MEMORY", {})
    again = wheel_modes(named_profile("wheel_640"), **settings)
    np.testing.assert_array_equal(again.shapes, first.shapes)
    assert again.family.tolist() == first.family.tolist()
    velocity = mean_square_velocity(again, [300.0, 900.0])
    np.testing.assert_array_equal(velocity.axial, mean_square_velocity(first, [300.0, 900.0]).axial)


@pytest.mark.parametrize(
    ("call", "parameter"),
    [
        (lambda p: wheel_modes(p, max_harmonic=-1), "max_harmonic"),
        (lambda p: wheel_modes(p, max_frequency=1e6), "max_frequency"),
    ],
)
def test_bad_settings_are_refused(call, parameter):
    with pytest.raises(WheelrailError) as caught:
        call(named_profile("wheel_640"))
    assert caught.value.parameter == parameter


def test_a_wheel_for_a_rolling_radius_is_the_nearest_named_one_at_that_radius():
    # the paper's 780 mm wheel (R = 0.39 m): nearest is the 840 mm wheel, its rim, web and hub kept
    profile = wheel_profile_for(0.39)
    assert profile.wheel_radius == 0.39 and profile.tyre_depth == NAMED_WHEELS["wheel_840"].tyre_depth
    assert wheel_profile_for(0.46, "wheel_640").hub_width == NAMED_WHEELS["wheel_640"].hub_width
    with pytest.raises(WheelrailError) as caught:
        wheel_profile_for(0.18, "freight_920")  # no room for the 920 mm wheel's hub and rim
    assert caught.value.parameter == "wheel_hub_outer_radius"


def test_the_section_mass_of_a_rectangle_is_its_ring():
    # a rectangular section r = 0.1-0.4 m, 40 mm wide: a ring of pi (0.4^2 - 0.1^2) 0.04 m^3 of steel
    profile = outline_profile([[0.1, -0.02], [0.4, -0.02], [0.4, 0.02], [0.1, 0.02]], contact_z=0.0)
    assert section_mass(profile) == pytest.approx(7850 * np.pi * (0.4**2 - 0.1**2) * 0.04, rel=1e-12)
