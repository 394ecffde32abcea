"""Only physical inputs through the Python API: one table of accepted ranges (core/inputs/ranges.py), each input
outside it one WheelrailError that carries the input's key, the value and the range."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.ranges import (
    ACCEPTED,
    CIRCUMFERENCE_TOLERANCE,
    MAX_SPEED_KMH,
    MIN_SPEED_KMH,
    PATCH_FRACTION,
    check_wheel_circumference,
)
from wheelrail.core.parameters import KMH, ContactParameters, ModelParameters, RunParameters
from wheelrail.core.reference_filters import reference_filters
from wheelrail.core.roughness import load_roughness


def _refused(call, **kwargs) -> WheelrailError:
    with pytest.raises(WheelrailError) as info:
        call(**kwargs)
    error = info.value
    assert "\n" not in str(error)
    return error


@pytest.mark.parametrize(
    ("kwargs", "key", "value"),
    [
        # the inputs that once ran silently (wheel radius 1 um and 1 km, a 1 um crown, 5 MN and 0.1 kN)
        ({"wheel_radius": 1e-6}, "wheel_radius", 1e-6),
        ({"wheel_radius": 1e3}, "wheel_radius", 1e3),
        ({"rail_crown_radius": 1e-6}, "rail_crown_radius", 1e-6),
        ({"preload": 5e6}, "preload", 5e6),
        ({"preload": 100.0}, "preload", 100.0),
        ({"radius": 0.0}, "radius", 0.0),
        ({"wheel_transverse_radius": 0.01}, "wheel_transverse_radius", 0.01),
        ({"wheel_transverse_radius": -0.01}, "wheel_transverse_radius", -0.01),
        ({"preload": math.nan}, "preload", None),
        ({"preload": "65e3"}, "preload", "65e3"),
    ],
)
def test_contact_inputs_outside_their_range_are_refused_with_the_data(kwargs, key, value):
    error = _refused(ContactParameters, **kwargs)
    assert error.parameter == key and error.argument == f"ContactParameters.{key}"
    if value is not None:
        assert error.value == value
    assert str(error).startswith(f"ContactParameters.{key} ")


@pytest.mark.parametrize("key", ["speed", "preload", "radius", "wheel_radius", "rail_crown_radius"])
def test_every_range_holds_its_ends_and_refuses_beyond_them(key):
    accepted = ACCEPTED[key]
    assert accepted.check(accepted.minimum) == accepted.minimum and accepted.check(accepted.maximum) == accepted.maximum
    for outside in (accepted.minimum * (1 - 1e-6), accepted.maximum * (1 + 1e-6), math.inf, -accepted.minimum):
        error = _refused(accepted.check, value=outside)
        assert (error.parameter, error.minimum, error.maximum, error.unit) == (
            key,
            accepted.minimum,
            accepted.maximum,
            accepted.unit,
        )
        assert error.reason == accepted.reason and "is outside the accepted" in str(error)


def test_the_ranges_hold_the_paper_and_the_cnossos_table_and_catch_a_unit_slip():
    # the paper's wheel (R = 0.39 m, 65 kN, 100 km/h) and the CNOSSOS-EU columns (25-100 kN, 360-920 mm) lie
    # inside; a radius typed in mm as m (390) or in m as mm (0.39e-3) lies outside
    for key, values in (
        ("wheel_radius", (0.39, 0.18, 0.46)),
        ("rail_crown_radius", (0.39, 0.30)),
        ("preload", (65e3, 25e3, 100e3)),
        ("speed", (100 * KMH,)),
    ):
        for v in values:
            ACCEPTED[key].check(v)
    for key in ("wheel_radius", "rail_crown_radius"):
        for slip in (390.0, 0.39e-3):
            _refused(ACCEPTED[key].check, value=slip)
    assert (MIN_SPEED_KMH, MAX_SPEED_KMH) == (5.0, 400.0)


def test_speed_outside_5_to_400_kmh_is_refused_by_run_parameters_and_the_filters():
    for kmh in (4.0, 401.0):
        error = _refused(RunParameters, speed=kmh * KMH)
        assert error.parameter == "speed" and error.maximum == pytest.approx(400 * KMH)
        _refused(reference_filters, load=65e3, wheel_radius=0.39, speed=kmh * KMH)
    RunParameters(speed=5 * KMH)
    RunParameters(speed=400 * KMH)


def test_reference_filters_refuse_an_absurd_load_and_radius_by_their_own_argument_names():
    error = _refused(reference_filters, load=1e15, wheel_radius=0.39)
    assert (error.parameter, error.argument) == ("preload", "load")
    assert str(error).startswith("load 1e+15 N is outside the accepted 1000 to 500000 N")
    assert _refused(reference_filters, load=65e3, wheel_radius=1e-6).parameter == "wheel_radius"


def test_a_concave_tread_close_to_the_crown_is_refused_with_the_largest_radius_that_fits():
    # -300.5 mm on a 300 mm crown under the 390 mm wheel at 65 kN: R_y = 180 m, a patch 0.15 m across
    error = _refused(ContactParameters, rail_crown_radius=0.3, wheel_transverse_radius=-0.3005)
    assert error.parameter == "wheel_transverse_radius" and "0.148 m wide across the rail" in str(error)
    limit = error.maximum
    assert -0.31 < limit < -0.3005
    # at the limit the semi-axis across is PATCH_FRACTION of the crown's radius (the rule's boundary)
    edge = ContactParameters(rail_crown_radius=0.3, wheel_transverse_radius=limit * (1 + 1e-9))
    assert edge.hertz_semi_axes()[1] == pytest.approx(PATCH_FRACTION * 0.3, rel=1e-6)
    _refused(ContactParameters, rail_crown_radius=0.3, wheel_transverse_radius=limit * (1 - 1e-4))
    # a concave tread that conforms (or overlaps) is refused with the same limit
    assert _refused(ContactParameters, rail_crown_radius=0.3, wheel_transverse_radius=-0.2).maximum == limit
    # a lighter wheel has a smaller patch: the same tread fits
    ContactParameters(rail_crown_radius=0.3, wheel_transverse_radius=limit * (1 - 1e-4), preload=30e3)


def test_a_patch_too_large_for_the_radii_blames_the_preload_with_the_largest_load():
    # within the radii's ranges only a soft material makes a convex contact's patch that large (0.1 GPa: a = 70 mm
    # at 65 kN on the paper's circle, 18 % of R); the semi-axes grow as P^(1/3), so the largest load is exact
    error = _refused(ContactParameters, youngs_modulus=0.1e9)
    assert error.parameter == "preload" and error.value == 65e3 and error.maximum < 65e3
    a, _ = ContactParameters(youngs_modulus=0.1e9, preload=error.maximum).hertz_semi_axes()
    assert a / 0.39 == pytest.approx(PATCH_FRACTION, rel=1e-9)


def test_the_paper_and_the_readme_geometries_are_accepted():
    for contact in (
        ContactParameters(),
        ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30),
        ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=-0.5),
        ContactParameters(wheel_radius=0.2, rail_crown_radius=0.8),
    ):
        a, b = contact.hertz_semi_axes()
        assert a / contact.radius_along < PATCH_FRACTION and b / contact.radius_across < PATCH_FRACTION


def test_a_wheel_set_must_go_round_the_wheel_of_a_combined_run():
    from wheelrail.core.engine import prepare_run

    wheel = load_roughness("sinter-wheel-1")
    implied = wheel.length / (2 * np.pi)
    assert wheel.length == pytest.approx(2.9) and implied == pytest.approx(0.46155, abs=1e-5)
    error = _refused(prepare_run, roughness="corrugated-rail", wheel_roughness="sinter-wheel-1", length=0.05)
    assert (error.parameter, error.value) == ("wheel_radius", 0.39)
    assert error.minimum == pytest.approx(implied / (1 + CIRCUMFERENCE_TOLERANCE))
    assert error.maximum == pytest.approx(implied / (1 - CIRCUMFERENCE_TOLERANCE))
    assert "0.4615 m" in str(error) and "sinter-wheel-1 is 2.9 m round" in str(error)
    # within 1 % it runs; the wheel set alone stays the paper's idealisation (a roughness record, as given)
    for radius in (implied * 0.991, implied * 1.009):
        check_wheel_circumference(wheel.length, radius, "sinter-wheel-1")
        _refused(check_wheel_circumference, circumference=wheel.length, wheel_radius=radius * 1.03, label="w")
    prepare_run(
        "corrugated-rail",
        wheel_roughness="sinter-wheel-1",
        length=0.05,
        params=ModelParameters(contact=ContactParameters(wheel_radius=implied)),
    )
    prepare_run("sinter-wheel-1", length=0.05)


def test_a_study_with_a_wheel_set_is_checked_before_any_run():
    from wheelrail.core.study import plan_study

    error = _refused(plan_study, name="speeds", sets=["corrugated-rail"], length=1.2, wheel_set="sinter-wheel-1")
    assert error.parameter == "wheel_radius"
    plan_study(
        "speeds",
        ["corrugated-rail"],
        length=1.2,
        wheel_set="sinter-wheel-1",
        params=ModelParameters(contact=ContactParameters(wheel_radius=0.4615)),
    )
    # the speed is the parameters' (RunParameters refuses 500 km/h: test above); params must be parameters
    assert "ModelParameters" in str(_refused(plan_study, name="speeds", sets=["corrugated-rail"], params=500 * KMH))


def test_errors_cross_processes_with_their_data():
    # study workers raise in another process: the error arrives whole, to be worded by the front end there
    error = _refused(ContactParameters, preload=5e6)
    back = pickle.loads(pickle.dumps(error))
    assert isinstance(back, WheelrailError) and str(back) == str(error)
    assert (back.parameter, back.value, back.minimum, back.maximum) == ("preload", 5e6, 1e3, 500e3)
