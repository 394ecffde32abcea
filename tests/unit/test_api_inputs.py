"""Public functions check their inputs: bad input is one WheelrailError, never a Python or numpy error, and
never a silently wrong number."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import math

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters, RunParameters
from wheelrail.core.spectra.levels import contact_filter, energy_sum, level_difference, mean_level

MODULES = (
    "wheelrail.core.spectra.bands",
    "wheelrail.core.spectra.narrowband",
    "wheelrail.core.spectra.force",
    "wheelrail.core.spectra.levels",
    "wheelrail.core.parameters",
    "wheelrail.core.noise.cnossos",
    "wheelrail.core.noise.run_noise",
    "wheelrail.core.noise.cnossos_run",
    "wheelrail.core.noise.radiation",
    "wheelrail.core.noise.twins",
    "wheelrail.core.noise.tables",
)
BAD = (None, [], "x", math.nan, -1.0)


def _single_argument_functions():
    """(name, callable, argument) of every public function (and dataclass) with one required argument, and of
    every optional argument of those with none."""
    out = []
    for module_name in MODULES:
        module = importlib.import_module(module_name)
        for name, obj in list(vars(module).items()):
            if name.startswith("_") or getattr(obj, "__module__", None) != module_name or not callable(obj):
                continue
            if inspect.isclass(obj) and not dataclasses.is_dataclass(obj):
                continue
            params = [
                p
                for p in inspect.signature(obj).parameters.values()
                if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
            ]
            required = [p for p in params if p.default is p.empty]
            candidates = required if len(required) == 1 else params if not required else []
            label = f"{module_name.rsplit('.', 1)[1]}.{name}"
            out += [pytest.param(label, obj, p, id=f"{label}({p.name})") for p in candidates]
    return out


# ids name the function and the argument (never a repr with a memory address: pytest-xdist's workers must collect
# the same ids)
@pytest.mark.parametrize("label, function, argument", _single_argument_functions())
def test_bad_values_are_one_wheelrail_error_or_a_finite_answer(label, function, argument):
    """The class: None, an empty list, text, NaN or -1 in any argument of a public function."""
    for bad in BAD:
        if bad is argument.default or (argument.default is None and bad is None):
            continue  # the documented default
        if isinstance(argument.default, float) and bad == -1.0 and "transverse" in argument.name:
            continue  # a negative tread radius is a concave tread (in range or refused by the range's check)
        try:
            answer = function(**{argument.name: bad})
        except WheelrailError:
            continue
        except Exception as error:  # noqa: BLE001 - what the test looks for
            pytest.fail(f"{label}({argument.name}={bad!r}) raised {type(error).__name__}: {error}")
        try:
            values = np.asarray(answer, dtype=float)
        except (TypeError, ValueError):
            continue  # not numbers (a dataclass, a table): constructed from a checked value
        # NaN in, NaN out is a band without a value passing through (documented where it applies); else finite
        passed_through = isinstance(bad, float) and math.isnan(bad) and np.all(np.isnan(values))
        assert passed_through or np.all(np.isfinite(values)), f"{label}({argument.name}={bad!r}) returned {values}"


@pytest.mark.parametrize(
    "call",
    [
        lambda: ContactParameters(preload=None),
        lambda: ContactParameters(radius=None),
        lambda: mean_level([]),
        lambda: mean_level(None),
        lambda: mean_level([[60.0, 50.0], [60.0]]),
        lambda: contact_filter(np.array([60.0, 50.0]), np.array([60.0, 55.0, 40.0])),
        lambda: level_difference([1.0], "x"),
        lambda: energy_sum([1.0, 2.0], [1.0]),
    ],
    ids=["preload None", "radius None", "mean of none", "mean of None", "ragged", "filter shapes", "text", "sum"],
)
def test_named_cases_raise_wheelrail_error(call):
    with pytest.raises(WheelrailError):
        call()


def test_run_noise_of_none_is_one_line():
    from wheelrail.core.noise.run_noise import run_noise

    with pytest.raises(WheelrailError, match="RunResult"):
        run_noise(None)


def test_cnossos_refuses_an_impossible_speed_and_an_all_nan_roughness():
    from wheelrail.core.noise.cnossos import cnossos_rolling_noise

    with pytest.raises(WheelrailError) as error:
        cnossos_rolling_noise(speed=1e300)
    assert error.value.parameter == "speed"
    with pytest.raises(WheelrailError, match="no band"):
        cnossos_rolling_noise(speed=30.0, roughness=("measured", np.full(24, np.nan)))
    # a partly undefined roughness stays allowed: NaN there, a finite total from the other bands
    partial = np.r_[np.full(12, np.nan), np.zeros(12)]
    assert math.isfinite(cnossos_rolling_noise(speed=30.0, roughness=("measured", partial)).total_dba)


def test_an_element_size_that_leaves_no_run_is_not_given_a_negative_range():
    """RunParameters(element_size=1.0) once ran into "accepted at most -1 m": the window margins alone were
    longer than the roughness data, and the longest run offered was negative."""
    from wheelrail.core.engine import simulate
    from wheelrail.core.parameters import ModelParameters
    from wheelrail.core.roughness import load_roughness

    params = ModelParameters(run=RunParameters(element_size=1.0))
    with pytest.raises(WheelrailError) as error:
        simulate(load_roughness("corrugated-rail"), params=params, length=1.0)
    assert error.value.parameter == "element_size" and error.value.maximum is None, str(error.value)
    assert "-" not in str(error.value).split("accepted")[-1], str(error.value)
