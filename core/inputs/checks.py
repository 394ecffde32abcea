"""Input checks, one family for all of core: each returns the value converted, or raises one WheelrailError
line that names the value (``label``: "where: name" or "Class.name"), its unit and what it got.

Used by the parameter classes, the contact modules and the run set-up, so that every bad number reads the
same way wherever it enters.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError

__all__ = [
    "LEVEL_LIMIT_DB",
    "check_positive",
    "finite_array",
    "integer",
    "keyed_real",
    "level_arrays",
    "mean_squares",
    "parts",
    "poisson_ratio",
    "positive",
    "real",
    "samples",
]

LEVEL_LIMIT_DB = 1000.0
"""The largest magnitude a level may have, dB: 10^100 times its reference, beyond any physical quantity (sound in
air ends near 194 dB re 20 uPa, a force of 1e10 N is 200 dB re 1 N), and far enough inside float64 (10^308) that
energetic sums of levels, 10^(L/10), never overflow. -inf (no power) and NaN (no estimate) pass."""

_SIGNS = {  # sign: (its words in a label's message, the problem a keyed error states, the test)
    "positive": ("positive and finite", "must be positive", lambda v: v > 0.0),
    "nonnegative": ("zero or positive and finite", "must not be negative", lambda v: v >= 0.0),
    "any": ("finite", "must be finite", lambda v: True),
}


def _shown(value) -> str:
    """``repr(value)`` on one line, at most 60 characters (an array's repr spans lines)."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 60 else text[:57] + "..."


def _reading(value, sign: str, *, text: bool) -> tuple[float, str | None]:
    """``value`` as a float and what is wrong with it: None (a finite number of the sign), "number" (not a number:
    a bool, an array, or what ``float`` cannot read; with ``text`` False anything but a real number), "finite"
    (NaN or infinite, an integer beyond float64 included) or "sign". Its sign is :data:`_SIGNS`' key."""
    if isinstance(value, bool) or (isinstance(value, np.ndarray) and value.ndim > 0):
        return math.nan, "number"
    if not (text or isinstance(value, numbers.Real)):
        return math.nan, "number"
    try:
        number = float(value)
    except OverflowError:  # an integer beyond float64
        return (math.inf if value > 0 else -math.inf), "finite"
    except (TypeError, ValueError):
        return math.nan, "number"
    if not math.isfinite(number):
        return number, "finite"
    return number, None if _SIGNS[sign][2](number) else "sign"


def real(label: str, value, unit: str, *, sign: str = "positive") -> float:
    """``value`` as a finite float of the given sign ("positive", "nonnegative" or "any")."""
    number, fault = _reading(value, sign, text=True)
    if fault == "number":
        raise WheelrailError(f"{label} must be a number in {unit}, got {_shown(value)}")
    if fault is not None:
        raise WheelrailError(f"{label} must be {_SIGNS[sign][0]} ({unit}), got {_shown(value)}")
    return number


def keyed_real(key: str, value, unit: str, *, argument: str, sign: str = "positive") -> float:
    """``value`` as a finite float of the given sign (as :func:`real`; text refused), else one WheelrailError that
    blames the input ``key`` (:class:`~wheelrail.core.errors.Blame`, the Python API's name ``argument``), so that
    each front end names it in its own terms: "must be a number in m", "must be finite", "must be positive",
    "must not be negative"."""
    number, fault = _reading(value, sign, text=False)
    if fault == "number":
        raise WheelrailError(f"must be a number in {unit}", Blame(key, value=str(value), argument=argument))
    if fault is not None:
        problem = _SIGNS["any" if fault == "finite" else sign][1]
        raise WheelrailError(problem, Blame(key, value=number, unit=unit, argument=argument))
    return number


def parts(owner, *names: str) -> None:
    """Each named field of the dataclass ``owner`` holds an instance of its annotated class (a number or text
    given for a part is refused where it is given, not deep inside a run)."""
    import typing

    hints = typing.get_type_hints(type(owner))
    for name in names:
        value, kind = getattr(owner, name), hints[name]
        if not isinstance(value, kind):
            raise WheelrailError(f"{type(owner).__name__}.{name} must be a {kind.__name__}, got {_shown(value)}")


def positive(where: str, name: str, value, unit: str) -> float:
    """``real(f"{where}: {name}", value, unit)``: a positive, finite float."""
    return real(f"{where}: {name}", value, unit)


def integer(label: str, value, minimum: int, maximum: int | None = None) -> int:
    """``value`` as an int >= ``minimum`` and, when given, <= ``maximum`` (bools and floats refused)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise WheelrailError(f"{label} must be an integer >= {minimum}, got {_shown(value)}")
    if maximum is not None and value > maximum:
        raise WheelrailError(f"{label} must be an integer from {minimum} to {maximum}, got {_shown(value)}")
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
        if level is None or isinstance(level, str | bytes):  # numpy reads None as NaN and digits in a string
            raise WheelrailError(f"{label} must be numbers (dB), got {_shown(level)}")
        try:
            arrays.append(np.asarray(level, dtype=float))
        except (TypeError, ValueError):
            raise WheelrailError(f"{label} must be numbers (dB), got {_shown(level)}") from None
    shapes = sorted({array.shape for array in arrays})
    if len(shapes) > 1:
        raise WheelrailError(f"{label}: band-level arrays of different shapes {', '.join(map(str, shapes))}")
    if any(np.any(array == np.inf) for array in arrays):
        raise WheelrailError(f"{label}: a level of +inf dB (no finite power has one)")
    if any(np.any(np.isfinite(array) & (np.abs(array) > LEVEL_LIMIT_DB)) for array in arrays):
        raise WheelrailError(f"{label}: a level beyond +-{LEVEL_LIMIT_DB:g} dB (10^100 times its reference)")
    return arrays


def _numbers(label: str, value, unit: str) -> np.ndarray:
    """``value`` as a float array; None, text or what numpy cannot read as numbers is one WheelrailError."""
    if value is None or isinstance(value, str | bytes):  # numpy reads None as NaN and digits in a string
        raise WheelrailError(f"{label} must be numbers in {unit}, got {_shown(value)}")
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError(f"{label} must be numbers in {unit}") from None


def mean_squares(label: str, value, unit: str) -> np.ndarray:
    """``value`` as a float array of mean squares or powers (``unit``): zero or positive and finite; NaN passes
    (a band with no estimate)."""
    array = _numbers(label, value, unit)
    if np.any(np.isinf(array)) or np.any(array < 0):
        raise WheelrailError(f"{label} must be zero or positive and finite ({unit}), got a negative or infinite value")
    return array


def samples(label: str, value, unit: str, *, rows: bool = True, at_least: int = 2) -> np.ndarray:
    """``value`` as finite samples: one signal (1-D) or, with ``rows``, one per row (2-D), each of at least
    ``at_least`` samples."""
    array = finite_array(label, value, unit)
    shapes = "a 1-D array of samples" + (" (or 2-D, one signal per row)" if rows else "")
    if array.ndim not in ((1, 2) if rows else (1,)):
        raise WheelrailError(f"{label} must be {shapes}, got shape {array.shape}")
    if array.shape[-1] < at_least:
        raise WheelrailError(f"{label} needs at least {at_least} samples, got {array.shape[-1]}")
    return array


def finite_array(label: str, value, unit: str) -> np.ndarray:
    """``value`` as a float array with no NaN or infinity."""
    array = _numbers(label, value, unit)
    if not np.all(np.isfinite(array)):
        raise WheelrailError(f"{label} must be finite ({unit}), got a NaN or infinity")
    return array


def check_positive(value, key: str, unit: str, argument: str | None = None) -> float:
    """``value`` as a float if finite and > 0, else one WheelrailError keyed ``key`` (SI ``unit``; ``argument``:
    the API's name of the input, default the key)."""
    blame = Blame(key, value, unit, argument=argument)
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise WheelrailError("not a number", blame) from None
    if not (math.isfinite(number) and number > 0):
        raise WheelrailError("not a positive number", blame)
    return number
