"""Input checks, one family for all of core: each returns the value converted, or raises one WheelrailError
line that names the value (``label``: "where: name" or "Class.name"), its unit and what it got.

Used by the parameter classes, the contact modules and the run set-up, so that every bad number reads the
same way wherever it enters.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import WheelrailError

__all__ = ["finite_array", "integer", "level_arrays", "poisson_ratio", "positive", "real"]

_SIGNS = {
    "positive": ("positive and finite", lambda v: v > 0.0),
    "nonnegative": ("zero or positive and finite", lambda v: v >= 0.0),
    "any": ("finite", lambda v: True),
}


def real(label: str, value, unit: str, *, sign: str = "positive") -> float:
    """``value`` as a finite float of the given sign ("positive", "nonnegative" or "any")."""
    if isinstance(value, bool):
        raise WheelrailError(f"{label} must be a number in {unit}, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise WheelrailError(f"{label} must be a number in {unit}, got {value!r}") from None
    words, accept = _SIGNS[sign]
    if not (math.isfinite(number) and accept(number)):
        raise WheelrailError(f"{label} must be {words} ({unit}), got {value!r}")
    return number


def positive(where: str, name: str, value, unit: str) -> float:
    """``real(f"{where}: {name}", value, unit)``: a positive, finite float."""
    return real(f"{where}: {name}", value, unit)


def integer(label: str, value, minimum: int) -> int:
    """``value`` as an int >= ``minimum`` (bools and floats refused)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise WheelrailError(f"{label} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def poisson_ratio(where: str, value) -> float:
    """Poisson's ratio nu in [0, 0.5) (0.5 would make E* infinite); ``where`` names the caller."""
    label = f"{where}: poisson_ratio"
    nu = real(label, value, "-", sign="any")
    if not 0.0 <= nu < 0.5:
        raise WheelrailError(f"{label} must be in [0, 0.5), got {value!r}")
    return nu


def level_arrays(label: str, levels, *, at_least: int = 1) -> list[np.ndarray]:
    """``levels`` (a sequence of band-level arrays, dB) as float arrays of one shape, at least ``at_least`` of
    them. NaN passes (a band a record cannot resolve); +inf does not (no finite power has it)."""
    if isinstance(levels, str | bytes) or not hasattr(levels, "__len__"):
        raise WheelrailError(f"{label} must be a sequence of band-level arrays (dB), got {type(levels).__name__}")
    if len(levels) < at_least:
        raise WheelrailError(f"{label} must hold at least {at_least} band-level array(s) (dB), got {len(levels)}")
    arrays = []
    for level in levels:
        try:
            arrays.append(np.asarray(level, dtype=float))
        except (TypeError, ValueError):
            raise WheelrailError(f"{label} must be numbers (dB), got {level!r:.60}") from None
    shapes = sorted({array.shape for array in arrays})
    if len(shapes) > 1:
        raise WheelrailError(f"{label}: band-level arrays of different shapes {', '.join(map(str, shapes))}")
    if any(np.any(array == np.inf) for array in arrays):
        raise WheelrailError(f"{label}: a level of +inf dB (no finite power has one)")
    return arrays


def finite_array(label: str, value, unit: str) -> np.ndarray:
    """``value`` as a float array with no NaN or infinity."""
    if value is None:
        raise WheelrailError(f"{label} must be numbers in {unit}, got None")
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError(f"{label} must be numbers in {unit}") from None
    if not np.all(np.isfinite(array)):
        raise WheelrailError(f"{label} must be finite ({unit}), got a NaN or infinity")
    return array
