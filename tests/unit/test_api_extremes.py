"""The Python API's entry points at the values the command-line sweep tries (tests/cli/test_option_sweep.py): 0,
+-inf, +-1e308, 1e-308, a huge count, a wrong kind. Each is accepted with finite results or refused with one
WheelrailError, never a Python or numpy error (numpy's RuntimeWarnings count as errors here)."""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.ranges import WHEEL_SYSTEM
from wheelrail.core.parameters import (
    ContactParameters,
    ModelParameters,
    RailParameters,
    SupportParameters,
    TrackParameters,
    WheelParameters,
)

EXTREMES = (0, 0.0, math.inf, -math.inf, 1e308, -1e308, 1e-308, 10**6, True, "abc", None)


def accepted_or_refused(call):
    """``call()`` returns or raises WheelrailError; RuntimeWarnings are errors."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            return call()
        except WheelrailError:
            return None


@pytest.mark.parametrize("value", EXTREMES, ids=repr)
def test_contact_material_at_extremes_is_accepted_or_one_wheelrail_error(value):
    # 1e308 Pa: ZeroDivisionError; 1e-308 Pa: refused blaming the preload, "accepted at most 0 N"
    contact = accepted_or_refused(lambda: ContactParameters(youngs_modulus=value))
    if contact is not None:
        assert all(0 < axis < 0.1 * 0.39 for axis in contact.hertz_semi_axes())
    if isinstance(value, float) and math.isfinite(value) and value > 0:
        with pytest.raises(WheelrailError) as refused:
            ContactParameters(youngs_modulus=value)
        assert refused.value.parameter == "youngs_modulus" and refused.value.maximum is not None


def test_a_soft_or_stiff_solid_is_accepted():
    for modulus in (1e9, 100e9, 210e9, 1200e9):
        assert ContactParameters(youngs_modulus=modulus).youngs_modulus == modulus


@pytest.mark.parametrize(
    "build",
    [
        lambda value: ModelParameters(wheel=value),
        lambda value: ModelParameters(track=value),
        lambda value: ModelParameters(contact=value),
        lambda value: ModelParameters(run=value),
        lambda value: TrackParameters(rail=value),
        lambda value: TrackParameters(support=value),
    ],
    ids=["wheel", "track", "contact", "run", "rail", "support"],
)
def test_a_part_of_the_wrong_kind_is_refused_where_it_is_given(build):
    # ModelParameters(track=0) was accepted and failed deep inside a run with AttributeError
    for value in (0, "abc", None, 1e308, ModelParameters):
        with pytest.raises(WheelrailError, match="must be a"):
            build(value)


@pytest.mark.parametrize(
    "value", [*EXTREMES, (1, 2, 3), ([[1.0]], [1.0], [1.0]), (np.eye(4), np.zeros(4), [np.nan] * 4)]
)
def test_prepare_run_refuses_a_wheel_system_that_is_not_one(value):
    from wheelrail.core.engine import prepare_run

    if value is None:
        return  # the documented default: the paper's wheel
    with pytest.raises(WheelrailError, match="wheel_system"):
        prepare_run("corrugated-rail", length=0.05, wheel_system=value)


@pytest.mark.parametrize("ka", [1e-308, 1e-200, 1e-3, 1.0, 1e3, 1e200, 1e308])
def test_cylinder_radiation_efficiency_is_finite_at_every_positive_ka(ka):
    from wheelrail.core.noise.radiation import cylinder_radiation_efficiency

    sigma = accepted_or_refused(lambda: cylinder_radiation_efficiency(ka))
    assert sigma is not None and np.all(np.isfinite(sigma)) and np.all((sigma >= 0) & (sigma <= 1.5))
    if ka >= 1e3:
        assert sigma == pytest.approx(1.0, abs=1e-3)  # far above coincidence: radiates as a plane piston


@pytest.mark.parametrize("frequency", [1e-308, 1e-3, 1e5, 1e308])
def test_rail_radiation_efficiency_is_finite_at_every_positive_frequency(frequency):
    from wheelrail.core.noise.radiation import rail_radiation_efficiency

    sigma = accepted_or_refused(lambda: rail_radiation_efficiency(frequency))
    assert sigma is not None and np.all(np.isfinite(sigma))


def test_rail_parts_of_the_right_kind_pass():
    track = TrackParameters(rail=RailParameters(), support=SupportParameters())
    assert ModelParameters(track=track).track is track


@pytest.mark.parametrize("name", [f.name for f in dataclasses.fields(WheelParameters)])
def test_the_wheel_at_extremes_is_refused_naming_the_field(name):
    # a contact mass of 1e-308 kg overflowed the wheel's discrete-time system (RuntimeWarning, then NaN), a wheel
    # stiffness of 1e-308 N/m divided 0 by 0; both were accepted
    tiny = (1e-308,) if WHEEL_SYSTEM[name].minimum > 0 else ()  # a damping of 1e-308 is none: accepted
    for value in (*tiny, 1e308, -1.0, math.nan, "abc"):
        with pytest.raises(WheelrailError) as refused:
            WheelParameters(**{name: value})
        assert refused.value.parameter == name and f"WheelParameters.{name}" in str(refused.value)


@pytest.mark.slow
def test_the_wheel_at_its_declared_limits_runs_without_numpy_warnings():
    from wheelrail.core.engine import simulate

    for name, entry in WHEEL_SYSTEM.items():
        for value in (entry.minimum, entry.maximum):
            params = ModelParameters(wheel=WheelParameters(**{name: value}))
            result = accepted_or_refused(lambda p=params: simulate("corrugated-rail", params=p, length=0.05))
            assert result is not None and np.all(np.isfinite(result.force)), (name, value)
