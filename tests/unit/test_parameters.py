import math

import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import (
    ContactParameters,
    RunParameters,
    SupportParameters,
    TrackNumerics,
    WheelParameters,
)


def test_hertz_values_of_spec():
    # SPEC.md §2 geometry check: a = 5.482 mm, p0 = 1032.6 MPa, approach 77.07 um at 65 kN.
    # Tolerance 0.05 %: these are closed-form expressions, the spec rounds to 4 digits.
    c = ContactParameters()
    assert c.hertz_radius() == pytest.approx(5.482e-3, rel=5e-4)
    assert c.hertz_peak_pressure() == pytest.approx(1032.6e6, rel=5e-4)
    assert c.hertz_approach() == pytest.approx(77.07e-6, rel=5e-4)
    # eq. (12)-(13): C_H delta^1.5 = P, exactly
    assert c.hertz_constant * c.hertz_approach() ** 1.5 == pytest.approx(c.preload, rel=1e-12)


def test_time_step_is_element_over_speed():
    run = RunParameters(speed=100 / 3.6, element_size=1e-3)
    assert run.time_step == pytest.approx(3.6e-5)


@pytest.mark.parametrize(
    ("cls", "name", "value", "unit"),
    [
        (WheelParameters, "unsprung_mass", -1.0, "kg"),
        (WheelParameters, "wheel_stiffness", 0.0, "N/m"),
        (SupportParameters, "pad_stiffness", math.nan, "N/m"),
        (SupportParameters, "sleeper_mass", 0.0, "kg"),
        (RunParameters, "speed", -10.0, "m/s"),
        (RunParameters, "element_size", 0.0, "m"),
        (ContactParameters, "preload", -65e3, "N"),
        (TrackNumerics, "time_step", math.inf, "s"),
    ],
)
def test_bad_parameter_names_itself_and_unit(cls, name, value, unit):
    with pytest.raises(WheelrailError) as info:
        cls(**{name: value})
    message = str(info.value)
    assert name in message and unit in message and "\n" not in message


def test_poisson_ratio_range():
    with pytest.raises(WheelrailError, match="poisson_ratio"):
        ContactParameters(poisson_ratio=0.5)


def test_parameters_are_frozen():
    with pytest.raises(AttributeError):
        WheelParameters().unsprung_mass = 1.0  # type: ignore[misc]
