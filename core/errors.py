"""The one error type users see: one line, carried as data so that every front end words it in its own terms.

A :class:`WheelrailError` holds what went wrong (``problem``, in words that name no input) and, when an input
is to blame, which one (a :class:`Blame`): ``parameter``, a stable key such as ``"preload"`` (the keys of
:data:`wheelrail.core.inputs.ranges.ACCEPTED` and a few more: ``length``, ``line``, ``skip``, ...), the value given
and the accepted range, all in SI units. ``str(error)`` is the Python API's wording (the argument's name,
SI units). :meth:`WheelrailError.render` words the same error for another front end from a mapping of keys
to :class:`Name`: the command line's (``wheelrail.cli.commands._common.CLI_NAMES``: ``--preload-kn 5000``,
kN) and the explorer's (``wheelrail.explorer.config.FIELD_NAMES``: ``Preload 5000 kN``). No front end
rewrites a finished sentence.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from typing import NamedTuple

__all__ = ["Blame", "Name", "WheelrailError"]


class Name(NamedTuple):
    """How one front end names an input: its ``label`` ("--preload-kn", "Preload"), the ``unit`` it shows values
    in ("kN"; "" for counts and text), ``scale`` (that unit per SI unit: 1e-3 for kN) and whether the label
    already carries the unit (a command-line option: values are shown bare after it)."""

    label: str
    unit: str = ""
    scale: float = 1.0
    unit_in_label: bool = False


class Blame(NamedTuple):
    """The input to blame for a :class:`WheelrailError`: its key, the value given and what it accepts, SI.

    Attributes
    ----------
    parameter : str or None
        Stable key of the input (``"preload"``, ``"speed"``, ``"wheel_radius"``, ``"length"``, ...); None: no input
        is to blame.
    value : optional
        The value given, SI (a number, or text as given).
    unit : str
        SI unit of ``value``, ``minimum`` and ``maximum`` ("" for counts and text).
    minimum, maximum : float, optional
        The accepted range, SI (either end may be open).
    argument : str, optional
        The Python API's name of the input (``"ContactParameters.preload"``); default ``parameter``.
    reason : str, optional
        Why the range is what it is (shown in brackets after it).
    magnitude : bool
        The range bounds the value's magnitude (a radius that may be negative).
    """

    parameter: str | None
    value: object = None
    unit: str = ""
    minimum: float | None = None
    maximum: float | None = None
    argument: str | None = None
    reason: str | None = None
    magnitude: bool = False


_NOBODY = Blame(None)


class WheelrailError(ValueError):
    """Bad input or a reported numerical failure, as data (module docstring).

    Parameters
    ----------
    problem : str, optional
        What went wrong, in words that name no input (the front ends name it). None with a range: the value
        is outside it.
    blame : Blame, optional
        The input to blame, its value and accepted range; its fields are also this error's attributes
        (``error.parameter``, ``error.value``, ``error.minimum``, ...).
    advice : str, optional
        What else can be done, in words that name no input.

    A message with no input to blame (``WheelrailError("file x.npz is damaged")``) reads the same everywhere.

    Raises
    ------
    TypeError
        If neither ``problem`` nor an input to blame is given.

    See Also
    --------
    render : the message worded for a front end.

    Examples
    --------
    >>> from wheelrail.core.errors import Blame, Name, WheelrailError
    >>> error = WheelrailError(None, Blame("preload", 5e6, "N", minimum=1e3, maximum=5e5))
    >>> str(error)
    'preload 5e+06 N is outside the accepted 1000 to 500000 N'
    >>> error.render({"preload": Name("--preload-kn", "kN", 1e-3, True)})
    '--preload-kn 5000 is outside the accepted 1 to 500 kN'
    """

    def __init__(self, problem: str | None = None, blame: Blame = _NOBODY, *, advice: str | None = None) -> None:
        if problem is None and blame.parameter is None:
            raise TypeError("WheelrailError needs a problem or an input to blame")
        self.problem, self.blame, self.advice = problem, blame, advice
        (
            self.parameter,
            self.value,
            self.unit,
            self.minimum,
            self.maximum,
            self.argument,
            self.reason,
            self.magnitude,
        ) = blame
        super().__init__(self.render())

    def __reduce__(self):  # pickled across processes (study workers) with its data, not only its text
        return (_rebuild, (self.problem, tuple(self.blame), self.advice))

    def name_in(self, names: Mapping[str, Name] | None = None) -> Name:
        """The front end's :class:`Name` of this error's input (the API's when ``names`` has none)."""
        own = names.get(self.parameter) if names is not None and self.parameter is not None else None
        return own if own is not None else Name(self.argument or self.parameter or "", self.unit)

    def render(self, names: Mapping[str, Name] | None = None) -> str:
        """The one-line message, with the input named as a front end names it.

        Parameters
        ----------
        names : mapping of str to Name, optional
            Input key -> how the front end names it and the unit it shows (the command line's
            ``CLI_NAMES``, the explorer's ``FIELD_NAMES``); None: the Python API's names, SI units.

        Returns
        -------
        str
            One line: the input, its value and the accepted range in the front end's units, or the problem.
        """
        if self.parameter is None:
            text = self.problem
        else:
            name = self.name_in(names)
            head = name.label if self.value is None else f"{name.label} {_shown(self.value, name)}"
            span = self._span(name)
            if self.problem is None:
                text = (
                    f"{head} is outside the accepted range, {span}"
                    if self.magnitude
                    else f"{head} is outside the accepted {span}"
                    if span
                    else f"{head} is not accepted"
                )
            else:
                text = f"{head}: {self.problem}" + (f"; accepted {span}" if span else "")
            if self.reason:
                text += f" ({self.reason})"
        return f"{text}; {self.advice}" if self.advice else text

    def _span(self, name: Name) -> str:
        unit = f" {name.unit}" if name.unit else ""
        low = None if self.minimum is None else _number(self.minimum * name.scale)
        high = None if self.maximum is None else _number(self.maximum * name.scale)
        if self.magnitude and low is not None:
            return f"a magnitude of at least {low}{unit}"
        if low is not None and high is not None:
            return f"{low} to {high}{unit}"
        if low is not None:
            return f"at least {low}{unit}"
        if high is not None:
            return f"at most {high}{unit}"
        return ""


def _rebuild(problem, blame, advice) -> WheelrailError:
    return WheelrailError(problem, Blame(*blame), advice=advice)


def _number(value: float) -> str:
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return f"{value:.6g}"


def _shown(value, name: Name) -> str:
    """A value as the front end shows it: a number in its unit, text quoted (bare after a command-line option)."""
    if isinstance(value, str) and name.unit_in_label:  # a command-line option: the word as typed
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return repr(value)
    if isinstance(value, numbers.Integral) and abs(int(value)) >= 10**16:  # beyond float64's exact integers
        value = float(value) if abs(int(value)) < 10**308 else (math.inf if value > 0 else -math.inf)
    number = (
        _number(float(value) * name.scale)
        if name.scale != 1.0 or not isinstance(value, numbers.Integral)
        else str(int(value))
    )
    return number if name.unit_in_label or not name.unit else f"{number} {name.unit}"
