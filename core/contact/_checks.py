"""Input checks shared by the contact modules: one-line WheelrailError messages naming the value."""

from __future__ import annotations

import math

from wheelrail.core.errors import WheelrailError


def positive(where: str, name: str, value, unit: str) -> float:
    """``value`` as a positive, finite float, or a WheelrailError naming ``where``, ``name`` and ``unit``."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: {name} must be a number in {unit}, got {value!r}") from None
    if not math.isfinite(number) or number <= 0.0:
        raise WheelrailError(f"{where}: {name} must be positive and finite ({unit}), got {value!r}")
    return number


def poisson_ratio(where: str, value) -> float:
    """Poisson's ratio in [0, 0.5), or a WheelrailError."""
    try:
        nu = float(value)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: poisson_ratio must be a number, got {value!r}") from None
    if not (math.isfinite(nu) and 0.0 <= nu < 0.5):
        raise WheelrailError(f"{where}: poisson_ratio must be in [0, 0.5), got {value!r}")
    return nu
