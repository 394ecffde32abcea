"""Input checks, one family for all of core: each returns the value converted, or raises one WheelrailError
line that names the value (``label``: "where: name" or "Class.name"), its unit and what it got.

Used by the parameter classes, the contact modules and the run set-up, so that every bad number reads the
same way wherever it enters.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import WheelrailError

__all__ = ["finite_array", "integer", "poisson_ratio", "positive", "real"]

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


def finite_array(label: str, value, unit: str) -> np.ndarray:
    """``value`` as a float array with no NaN or infinity."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError(f"{label} must be numbers in {unit}") from None
    if not np.all(np.isfinite(array)):
        raise WheelrailError(f"{label} must be finite ({unit}), got a NaN or infinity")
    return array
