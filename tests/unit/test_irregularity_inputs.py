"""Bad irregularity geometry is refused in one line, keyed by the input, through WheelrailError."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs import checks
from wheelrail.core.irregularities import (
    DippedWeld,
    RailJoint,
    Squat,
    WheelFlat,
    check_irregularities,
    surface_deviation,
    wheel_centre_trajectory,
)

RUN = {"wheel_radius": 0.46, "run_start": 0.0, "run_end": 10.0, "sleeper_spacing": 0.65}


def _refused(call, *args, **kwargs) -> WheelrailError:
    with pytest.raises(WheelrailError) as info:
        call(*args, **kwargs)
    message = str(info.value)
    assert "\n" not in message and "Error" not in message and "Traceback" not in message
    return info.value


@pytest.mark.parametrize(
    ("build", "key", "words"),
    [
        (lambda: WheelFlat(length=-0.05), "flat_length", "WheelFlat.length -0.05 m: must be positive"),
        (lambda: WheelFlat(length=0.0), "flat_length", "WheelFlat.length 0 m: must be positive"),
        (lambda: WheelFlat(length=0.05, depth=-1e-4), "flat_depth", "WheelFlat.depth -0.0001 m: must be positive"),
        (lambda: WheelFlat(length=0.05, shape="square"), "flat_shape", "accepted rounded or new"),
        (lambda: WheelFlat(length=float("nan")), "flat_length", "must be finite"),
        (lambda: WheelFlat(length="long"), "flat_length", "must be a number in m"),
        (lambda: RailJoint(position=1.0, gap=0.0), "joint_gap", "RailJoint.gap 0 m: must be positive"),
        (lambda: RailJoint(position=1.0, dip_angle=-1e-3), "joint_dip_angle", "must not be negative"),
        (lambda: RailJoint(position=1.0, dip_angle=0.2), "joint_dip_angle", "outside the accepted 0 to 0.1 rad"),
        (lambda: DippedWeld(position=1.0, length=0.5, depth=0.0), "weld_depth", "must be positive"),
        (lambda: DippedWeld(position=1.0, length=-0.5, depth=1e-4), "weld_length", "must be positive"),
        (lambda: Squat(position=1.0, length=0.03, width=0.0, depth=1e-4), "squat_width", "must be positive"),
        (
            lambda: Squat(position=1.0, length=0.03, width=0.01, depth=1e-4, lateral_position=0.05),
            "squat_lateral_position",
            "outside the accepted -0.036 to 0.036 m (on the railhead)",
        ),
    ],
)
def test_each_dataclass_refuses_bad_numbers_in_one_line(build, key, words):
    error = _refused(build)
    assert error.parameter == key
    assert words in str(error)


def test_an_integer_beyond_float64_is_refused_in_one_line():
    error = _refused(WheelFlat, length=10**400)
    assert error.parameter == "flat_length" and "must be finite" in str(error)


@pytest.mark.parametrize(
    "value",
    [0.05, 3, np.float64(0.2), -0.1, 0.0, float("nan"), float("inf"), -math.inf, 10**400, True, np.ones(2)],
    ids=lambda value: repr(value)[:12],
)
@pytest.mark.parametrize("sign", ["positive", "nonnegative", "any"])
def test_a_shapes_number_is_the_checks_modules_real(value, sign):
    """The dataclasses' fields go through the one check of core.inputs.checks: what ``real`` accepts (a number),
    ``keyed_real`` accepts as the same float, and what it refuses, ``keyed_real`` refuses keyed by the input."""
    try:
        expected = checks.real("x", value, "m", sign=sign)
    except WheelrailError:
        expected = None
    try:
        got = checks.keyed_real("flat_length", value, "m", argument="WheelFlat.length", sign=sign)
    except WheelrailError as error:
        assert expected is None and error.parameter == "flat_length" and "\n" not in str(error)
    else:
        assert got == expected


def test_a_flat_longer_than_the_wheel_can_hold_is_refused():
    error = _refused(check_irregularities, [WheelFlat(length=1.0, position=2.0)], **RUN)
    assert str(error) == (
        "WheelFlat.length 1 m: a flat this long does not fit on the wheel; accepted at most 0.92 m "
        "(a chord of the wheel, shorter than its diameter)"
    )


def test_a_new_flat_with_a_depth_other_than_its_chords_is_refused():
    error = _refused(check_irregularities, [WheelFlat(length=0.05, depth=1e-3, shape="new", position=2.0)], **RUN)
    assert error.parameter == "flat_depth" and "a chord 0.000679" in str(error)
    check_irregularities([WheelFlat(length=0.05, depth=0.68e-3, shape="new", position=2.0)], **RUN)  # within 1 %


def test_a_gap_as_wide_as_a_sleeper_bay_is_refused():
    error = _refused(check_irregularities, [RailJoint(position=2.0, gap=0.7)], **RUN)
    assert str(error) == "RailJoint.gap 0.7 m is outside the accepted at most 0.65 m (narrower than a sleeper bay)"


@pytest.mark.parametrize(
    "item",
    [
        WheelFlat(length=0.05, position=0.01),
        RailJoint(position=9.9, dip_angle=1e-3, dip_length=0.5),
        DippedWeld(position=-1.0, length=0.3, depth=1e-4),
        Squat(position=10.5, length=0.03, width=0.01, depth=1e-4),
    ],
)
def test_an_irregularity_outside_the_run_is_refused(item):
    error = _refused(check_irregularities, [item], **RUN)
    assert error.parameter.endswith("_position") and "outside the run; accepted" in str(error)


def test_a_good_set_passes_in_order_and_a_stranger_does_not():
    items = [
        WheelFlat(length=0.05, position=1.0),
        RailJoint(position=3.0, step=-1e-4),
        DippedWeld(position=5.0, length=0.3, depth=1e-4),
    ]
    assert check_irregularities(items, **RUN) == tuple(items)
    assert "got str" in str(_refused(check_irregularities, ["flat"], **RUN))
    assert "got str" in str(_refused(surface_deviation, ["flat"], np.zeros(3), wheel_radius=0.46))


@pytest.mark.parametrize(
    ("profile", "spacing", "radius", "words"),
    [
        ([0.0], 1e-4, 0.46, "at least 2 finite heights"),
        ([0.0, float("nan")], 1e-4, 0.46, "at least 2 finite heights"),
        ([[0.0, 0.0]], 1e-4, 0.46, "1-D array"),
        ([0.0, 0.0], 0.0, 0.46, "spacing 0 m: must be a positive number"),
        ([0.0, 0.0], 1e-4, -0.46, "wheel_radius -0.46 m: must be a positive number"),
    ],
)
def test_the_trajectory_refuses_bad_arrays_in_one_line(profile, spacing, radius, words):
    assert words in str(_refused(wheel_centre_trajectory, profile, spacing, radius))
