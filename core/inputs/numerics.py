"""The track's numerics as a user sets them: ``--track-numerics elements_per_bay=32,positions_per_bay=128``.

:class:`~wheelrail.core.parameters.TrackNumerics` says how the track's Green's functions are computed (the FE mesh
across the bay, the excitation positions, the rows read between them, the near field stored at every node, the
integration's step and length). Its defaults are converged for the force's third-octave levels and the
sleeper-passing harmonics a run resolves (``docs/validation.md``); a user checks a result against finer numerics
by naming the fields to change, each declared once here with its unit and accepted range
(:data:`NUMERICS_FIELDS`). The command line's ``--track-numerics`` (``run``, ``track``, ``study`` and ``noise``) and
the explorer's Track numerics field read them with :func:`parse_track_numerics` and every output states the fields
that differ from the default (:func:`numerics_changes`, :func:`numerics_words`). The cache key of the track's
responses holds every field. The frequency-domain models of the track (the noise chain's, the receptances) take the
fields marked ``frequency_domain`` (:func:`frequency_domain_fields`): the elements per bay.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from wheelrail.core.errors import WheelrailError

if TYPE_CHECKING:
    from wheelrail.core.parameters import TrackNumerics

__all__ = [
    "NUMERICS_FIELDS",
    "NUMERICS_OPTION",
    "NumericsField",
    "frequency_domain_fields",
    "numerics_changes",
    "numerics_from_changes",
    "numerics_words",
    "parse_track_numerics",
]

NUMERICS_OPTION = "--track-numerics"
"""The command line's option (``run``, ``track``, ``study`` and ``noise``)."""


@dataclass(frozen=True)
class NumericsField:
    """One field of ``TrackNumerics`` a user can set: the ``name`` typed (with its unit where it has one), the
    dataclass ``field``, the unit typed and its ``si`` value (1e-6 for us), whether it is a whole number, the
    accepted range in the unit typed (the upper ends keep a precompute within minutes and memory), and whether the
    frequency-domain models of the track take it too (``frequency_domain``; the others are the time integration's)."""

    name: str
    field: str
    unit: str
    si: float
    whole: bool
    minimum: float
    maximum: float
    help: str
    frequency_domain: bool = False

    def accepted_text(self) -> str:
        kind = "a whole number" if self.whole else "a number"
        unit = f" {self.unit}" if self.unit else ""
        return f"{kind} from {self.minimum:g} to {self.maximum:g}{unit}"


NUMERICS_FIELDS: tuple[NumericsField, ...] = (
    NumericsField("elements_per_bay", "elements_per_bay", "", 1.0, True, 4, 256,
                  "elements per bay outside the refined bays, and the grid stored beyond the near field; the "
                  "frequency-domain track's elements per bay", frequency_domain=True),
    NumericsField("refined_elements_per_bay", "refined_elements_per_bay", "", 1.0, True, 4, 1024,
                  "elements per bay in the refined bays (a multiple of the two counts per bay)"),
    NumericsField("refined_bays", "refined_bays", "", 1.0, True, 1, 16, "bays meshed with the refined elements"),
    NumericsField("positions_per_bay", "positions_per_bay", "", 1.0, True, 4, 512,
                  "excitation positions per bay at which the responses are computed"),
    NumericsField("rows_per_position", "rows_per_position", "", 1.0, True, 1, 32,
                  "rows of the moving Green's functions per excitation position"),
    NumericsField("near_field_m", "near_field", "m", 1.0, False, 0.01, 2.0,
                  "length after the load stored at every node of the refined mesh"),
    NumericsField("time_step_us", "time_step", "us", 1e-6, False, 0.5, 20.0,
                  "step of the integration of the impulse responses"),
    NumericsField("duration_ms", "duration", "ms", 1e-3, False, 10.0, 150.0,
                  "length of the Green's functions (their truncation)"),
)  # fmt: skip
"""The fields of ``TrackNumerics`` ``--track-numerics`` sets, in the order outputs state them."""


def _field(name: str, label: str = NUMERICS_OPTION) -> NumericsField:
    for entry in NUMERICS_FIELDS:
        if entry.name == name:
            return entry
    names = ", ".join(entry.name for entry in NUMERICS_FIELDS)
    raise WheelrailError(f"{label}: unknown name {name!r}; the names are {names}")


def _value(entry: NumericsField, text: str, label: str) -> float | int:
    wanted = f"{label}: {entry.name} must be {entry.accepted_text()}, got {text!r}"
    try:
        number = float(text)
    except ValueError:
        raise WheelrailError(wanted) from None
    if not math.isfinite(number) or not entry.minimum <= number <= entry.maximum:
        raise WheelrailError(wanted)
    if entry.whole:
        if number != int(number):
            raise WheelrailError(wanted)
        return int(number)
    return number * entry.si


def parse_track_numerics(
    text: str | None, base: TrackNumerics | None = None, *, label: str = NUMERICS_OPTION
) -> TrackNumerics:
    """``TrackNumerics`` from comma-separated ``name=value`` pairs (:data:`NUMERICS_FIELDS`), the others ``base``'s.

    Parameters
    ----------
    text : str or None
        ``"elements_per_bay=32,positions_per_bay=128"``; None or empty: ``base`` unchanged.
    base : TrackNumerics, optional
        Default ``TrackNumerics()``.
    label : str
        How the front end names the input, first in every message (the command line's ``--track-numerics``, the
        explorer's field).

    Returns
    -------
    TrackNumerics

    Raises
    ------
    WheelrailError
        One line naming the input (``label``), the name or value and what is accepted: an unknown name, a name
        given twice, a value that is not a number in its range, or counts that do not go together (the refined mesh
        must hold every excitation position and stored grid point as a node).

    Examples
    --------
    >>> from wheelrail.core.inputs.numerics import parse_track_numerics
    >>> numerics = parse_track_numerics("elements_per_bay=32,time_step_us=2.5")
    >>> numerics.elements_per_bay, numerics.time_step
    (32, 2.5e-06)
    """
    from dataclasses import replace

    from wheelrail.core.parameters import TrackNumerics

    numerics = TrackNumerics() if base is None else base
    if text is None or not text.strip():
        return numerics
    changes: dict[str, float | int] = {}
    for item in text.split(","):
        name, equals, value = (part.strip() for part in item.partition("="))
        if not equals or not name or not value:
            raise WheelrailError(f"{label}: {item.strip()!r} is not name=value (e.g. elements_per_bay=32)")
        entry = _field(name, label)
        if entry.field in changes:
            raise WheelrailError(f"{label}: {name} is given twice")
        changes[entry.field] = _value(entry, value, label)
    refined = changes.get("refined_elements_per_bay", numerics.refined_elements_per_bay)
    for name in ("positions_per_bay", "elements_per_bay"):
        count = changes.get(name, getattr(numerics, name))
        if refined % count:
            raise WheelrailError(
                f"{label}: {name} ({count}) must divide refined_elements_per_bay ({refined}), so that "
                f"every excitation position and stored grid point is a node; set refined_elements_per_bay too"
            )
    return replace(numerics, **changes)


def numerics_from_changes(changes, *, label: str = NUMERICS_OPTION) -> TrackNumerics:
    """``TrackNumerics`` from changed fields by their typed names and units (a dict as :func:`numerics_changes` gives,
    or its items), checked as :func:`parse_track_numerics` checks ``--track-numerics``: what a run's header, a saved
    session or a noise chain read back."""
    items = changes.items() if isinstance(changes, dict) else changes
    return parse_track_numerics(",".join(f"{name}={value}" for name, value in items), label=label)


def numerics_changes(numerics: TrackNumerics | None) -> dict[str, float | int]:
    """The fields of ``numerics`` that differ from ``TrackNumerics()``, by their typed name, in their typed unit."""
    from wheelrail.core.parameters import TrackNumerics

    if numerics is None:
        return {}
    default = TrackNumerics()
    found = {}
    for entry in NUMERICS_FIELDS:
        value = getattr(numerics, entry.field)
        if value != getattr(default, entry.field):
            found[entry.name] = value if entry.whole else float(f"{value / entry.si:.12g}")
    return found


def numerics_words(changes: dict[str, float | int]) -> str:
    """Changed numerics (:func:`numerics_changes`) in words, as ``--track-numerics`` takes them
    ("elements_per_bay=32, time_step_us=2.5"), or "the default" when there are none."""
    if not changes:
        return "the default"
    return ", ".join(f"{name}={value:g}" for name, value in changes.items())


def frequency_domain_fields(numerics: TrackNumerics | None, *, only: str | None = None) -> dict[str, int | float]:
    """The fields of ``numerics`` the frequency-domain models of the track take (``NumericsField.frequency_domain``),
    by their dataclass name, SI: ``{"elements_per_bay": 16}``.

    Parameters
    ----------
    numerics : TrackNumerics or None
        None: the default.
    only : str, optional
        What takes no other fields, in words ("--method twins"): a field changed from its default that the frequency
        domain does not take is then one WheelrailError naming it and ``only``; None: the others are left aside (a
        run's numerics, whose force took them).

    Examples
    --------
    >>> from wheelrail.core.inputs.numerics import frequency_domain_fields, parse_track_numerics
    >>> frequency_domain_fields(parse_track_numerics("elements_per_bay=32,time_step_us=2.5"))
    {'elements_per_bay': 32}
    """
    from wheelrail.core.parameters import TrackNumerics

    numerics = TrackNumerics() if numerics is None else numerics
    if not isinstance(numerics, TrackNumerics):
        raise WheelrailError(f"track_numerics must be TrackNumerics or None, got {type(numerics).__name__}")
    taken = [entry for entry in NUMERICS_FIELDS if entry.frequency_domain]
    if only is not None:
        other = [name for name in numerics_changes(numerics) if not _field(name).frequency_domain]
        if other:
            names = ", ".join(entry.name for entry in taken)
            raise WheelrailError(
                f"{NUMERICS_OPTION}: {', '.join(other)} not used by {only} (the track in the frequency domain, no time "
                f"integration); it takes {names}"
            )
    return {entry.field: getattr(numerics, entry.field) for entry in taken}
