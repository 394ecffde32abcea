"""What one press of Run asks for, checked in the page's own words (no viser here).

A :class:`RunConfig` is the full configuration of a run (set, wheel set, line, model, speed, preload, length,
contact geometry); its :meth:`RunConfig.case` (everything but the model) keys every result the page shows, so
that a plot, a contact filter or a download never mixes configurations. :func:`read_config` turns the page's
fields (text as typed) into a config or one :class:`~wheelrail.core.errors.WheelrailError` line a user can act on; the
choices it allows come from core (:func:`wheelrail.core.run_setup.window_lines`,
:func:`wheelrail.core.run_setup.usable_length`, ``MIN_SPEED_KMH``/``MAX_SPEED_KMH``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace

from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import MODELS, REFERENCE_MODEL, model_entry
from wheelrail.core.parameters import (
    KMH,
    MAX_SPEED_KMH,
    MIN_SPEED_KMH,
    ContactParameters,
    ModelParameters,
    RunParameters,
)
from wheelrail.core.run_setup import usable_length, window_lines
from wheelrail.core.spectra import FORCE_MIN_STEPS, FORCE_SKIP

__all__ = [
    "COMPARE", "COMPARE_ORDER", "GEOMETRY_FIELDS", "MODEL_CHOICES", "NO_LINE_FITS", "NO_WHEEL_SET", "PRELOAD_RANGE_KN",
    "RunConfig",
    "in_page_words", "length_range", "models_of", "offered_lines", "read_config", "read_geometry",
]

COMPARE = "compare"
# the reference first (every contact filter needs it), then the others from the cheapest to the costliest
COMPARE_ORDER = (REFERENCE_MODEL, *(m for m in reversed(MODELS) if m != REFERENCE_MODEL))
MODEL_CHOICES = (*MODELS, COMPARE)
PRELOAD_RANGE_KN = (1.0, 500.0)  # wheel loads the page accepts (paper: 65 kN)
MAX_WHEEL_RUN_M = 100.0  # wheel data repeat around the circumference: longest run offered on a wheel set
NO_WHEEL_SET = "none"  # the wheel-set picker's choice for a smooth wheel (one rough surface, the paper's case)
NO_LINE_FITS = "no line fits"  # the Line menu when the model cannot run on any line of the set(s)
# ContactParameters geometry field -> what the page calls it (mm in the page, m inside; empty: the default)
GEOMETRY_FIELDS = {"wheel_radius": "Wheel radius", "rail_crown_radius": "Rail crown radius",
                   "wheel_transverse_radius": "Wheel tread radius across"}


@dataclass(frozen=True)
class RunConfig:
    """The full configuration of one run (SI inside; the page shows km/h, kN, m)."""

    set_label: str
    line: int
    model: str
    speed: float  # m/s
    preload: float  # N
    length: float  # m
    wheel_set_label: str | None = None  # a wheel set added to the rail set (combined roughness); None: smooth
    geometry: tuple[tuple[str, float], ...] = ()  # (ContactParameters field, m) given; the rest: the defaults

    def case(self) -> tuple:
        """Everything but the model: results of one case compare (spectra, contact filters)."""
        geometry = tuple((name, round(value, 12)) for name, value in self.geometry)
        return (self.set_label, self.wheel_set_label, self.line, round(self.speed, 9), round(self.preload, 6),
                round(self.length, 9), geometry)

    def for_model(self, model: str) -> RunConfig:
        return replace(self, model=model)

    def contact(self) -> ContactParameters:
        return ContactParameters(preload=self.preload, **dict(self.geometry))

    def params(self) -> ModelParameters:
        return ModelParameters(contact=self.contact(), run=RunParameters(speed=self.speed))

    def _geometry_words(self) -> list[str]:
        return [f"{GEOMETRY_FIELDS[name].lower()} {value * 1e3:g} mm" for name, value in self.geometry]

    def case_label(self) -> str:
        """The case as people read it: 'corrugated-rail, line 0, 100 km/h, 65 kN, 3 m' (with a wheel set:
        'corrugated-rail + sinter-wheel-1, ...'; a geometry given: '..., wheel radius 460 mm')."""
        sets = self.set_label if self.wheel_set_label is None else f"{self.set_label} + {self.wheel_set_label}"
        return ", ".join([f"{sets}, line {self.line}, {self.speed / KMH:g} km/h, {self.preload / 1e3:g} kN, "
                          f"{self.length:g} m", *self._geometry_words()])

    def label(self) -> str:
        return f"{self.model} on {self.case_label()}"

    def file_stem(self) -> str:
        """A file name for downloads: 'wheelrail-3d-corrugated-rail-line0-100kmh-65kN-3m'."""
        sets = [self.set_label] if self.wheel_set_label is None else [self.set_label, self.wheel_set_label]
        short = {"wheel_radius": "R", "rail_crown_radius": "crown", "wheel_transverse_radius": "tread"}
        parts = ["wheelrail", self.model, *sets, f"line{self.line}", f"{self.speed / KMH:g}kmh",
                 f"{self.preload / 1e3:g}kN", f"{self.length:g}m",
                 *(f"{short[name]}{value * 1e3:g}mm" for name, value in self.geometry)]
        return re.sub(r"[^A-Za-z0-9.+-]+", "_", "-".join(parts)).replace("_-", "-").strip("_")

    def as_dict(self) -> dict:
        values = {"model": self.model, "set": self.set_label, "line": self.line, "speed_kmh": self.speed / KMH,
                  "preload_kn": self.preload / 1e3, "length_m": self.length}
        if self.wheel_set_label is not None:
            values["wheel_set"] = self.wheel_set_label
        values.update((f"{name}_mm", value * 1e3) for name, value in self.geometry)
        return values


def models_of(model_choice: str) -> tuple[str, ...]:
    """The models one choice of the menu runs (``compare``: all, the reference first)."""
    return COMPARE_ORDER if model_choice == COMPARE else (model_choice,)


def offered_lines(roughness, model_choice: str, contact: ContactParameters, wheel=None) -> tuple[int, ...]:
    """Lines the page offers: every line of the set (and of the wheel set, when one is added), or for a model
    with a lateral window (``3d``, and ``compare``, which runs it) the lines whose window fits the set(s) for
    this contact (preload and geometry: core's rule)."""
    sets = (roughness,) if wheel is None else (roughness, wheel)
    if any(model_entry(m).traits.lateral_window for m in models_of(model_choice)):
        found = [set(window_lines(rough, ModelParameters(contact=contact))) for rough in sets]
    else:
        found = [{int(n) for n in rough.line_numbers} for rough in sets]
    return tuple(sorted(set.intersection(*found)))


def read_geometry(**fields_mm) -> tuple[tuple[str, float], ...]:
    """The geometry fields as typed (mm; empty: the paper's default) as ``RunConfig.geometry``, or one
    WheelrailError in the page's words. Keywords: the names of ``GEOMETRY_FIELDS`` with ``_mm``."""
    geometry = []
    for name, words in GEOMETRY_FIELDS.items():
        text = str(fields_mm.get(f"{name}_mm", "") or "").strip()
        if not text:
            continue
        value = _number(text, words, "mm")
        if name == "wheel_transverse_radius":
            if value == 0:
                raise WheelrailError(f"{words} must not be 0 mm; leave it empty for a cylindrical tread, negative "
                                     "for a concave (worn) tread")
        elif value <= 0:
            raise WheelrailError(f"{words} must be a positive number of mm (empty: the paper's "
                                 f"{ContactParameters().radius * 1e3:g} mm); got {value:g} mm")
        geometry.append((name, value * 1e-3))
    values = dict(geometry)
    try:
        ContactParameters(**values)  # core's check of the geometry (a concave tread must not conform)
    except WheelrailError:
        tread = values.get("wheel_transverse_radius", math.inf)
        crown = values.get("rail_crown_radius", ContactParameters().radius)
        raise WheelrailError(f"A concave wheel tread of {-tread * 1e3:g} mm across fits the rail crown of "
                             f"{crown * 1e3:g} mm or closer (the surfaces conform): make the wheel tread radius across "
                             f"more negative than -{crown * 1e3:g} mm, or leave it empty") from None
    return tuple(geometry)


def length_range(roughness, speed: float, element_size: float | None = None) -> tuple[float, float]:
    """Shortest run with a force spectrum at this speed, longest run the set allows, m."""
    dx = RunParameters().element_size if element_size is None else element_size
    shortest = math.ceil((FORCE_SKIP * speed + FORCE_MIN_STEPS * dx) / dx) * dx
    longest = MAX_WHEEL_RUN_M if roughness.periodic else usable_length(roughness, dx)
    return round(shortest, 6), math.floor(longest / dx + 1e-9) * dx


def _number(text, what: str, unit: str) -> float:
    try:
        value = float(str(text).strip().replace(",", "."))
    except ValueError:
        raise WheelrailError(f"{what} must be a number in {unit}; got '{text}'") from None
    if not math.isfinite(value):
        raise WheelrailError(f"{what} must be a number in {unit}; got '{text}'")
    return value


def _span(lines: tuple[int, ...]) -> str:
    if not lines:
        return "no line"
    if lines[-1] - lines[0] == len(lines) - 1:
        return f"a line from {lines[0]} to {lines[-1]}"
    return "one of lines " + ", ".join(map(str, lines))


def read_config(roughness, set_label: str, *, line, model: str, speed_kmh, preload_kn, length_m,
                geometry: tuple = (), wheel=None, wheel_label: str | None = None) -> RunConfig:
    """The run the page's fields ask for, or one WheelrailError in the page's words (what to type instead).

    ``geometry`` as :func:`read_geometry` gives it; ``wheel`` (labelled ``wheel_label``) a wheel set added to
    the rail set ``roughness``, or None."""
    if model not in MODEL_CHOICES:
        raise WheelrailError(f"unknown contact model '{model}'; choose one of {', '.join(MODEL_CHOICES)}")
    speed_kmh = _number(speed_kmh, "Speed", "km/h")
    if not MIN_SPEED_KMH <= speed_kmh <= MAX_SPEED_KMH:
        raise WheelrailError(f"Speed must be between {MIN_SPEED_KMH:g} and {MAX_SPEED_KMH:g} km/h; "
                             f"got {speed_kmh:g} km/h")
    preload_kn = _number(preload_kn, "Preload", "kN")
    lo, hi = PRELOAD_RANGE_KN
    if not lo <= preload_kn <= hi:
        raise WheelrailError(f"Preload must be between {lo:g} and {hi:g} kN; got {preload_kn:g} kN")
    if wheel is not None:
        if roughness.kind != "rail":
            raise WheelrailError(f"A wheel roughness is added to a rail set, and {set_label} is a {roughness.kind} "
                                 f"set: choose a rail set, or wheel roughness '{NO_WHEEL_SET}'")
        if wheel.kind != "wheel":
            raise WheelrailError(f"{wheel_label} is a {wheel.kind} set, not a wheel set: choose a wheel set as "
                                 "the wheel roughness")
    contact = ContactParameters(preload=preload_kn * 1e3, **dict(geometry))
    allowed = offered_lines(roughness, model, contact, wheel)
    sets = set_label if wheel is None else f"{set_label} + {wheel_label}"
    if not allowed:
        raise WheelrailError(f"The 3d contact patch at {preload_kn:g} kN is {2e3 * contact.hertz_semi_axes()[1]:.1f} "
                             f"mm wide across the rail: no line of {sets} leaves room for it; choose another "
                             "geometry or a one-line model")
    try:
        line = int(str(line).strip())
    except ValueError:
        raise WheelrailError(f"Line must be a whole number; got '{line}'") from None
    if line not in allowed:
        if line in roughness.line_numbers and (wheel is None or line in wheel.line_numbers):
            raise WheelrailError(f"Line {line} is too near the edge of {sets} for the 3d contact patch at "
                                 f"{preload_kn:g} kN; choose {_span(allowed)}")
        raise WheelrailError(f"Line {line} is not in {sets}; choose {_span(allowed)}")
    length = _number(length_m, "Run length", "m")
    shortest, longest = length_range(roughness, speed_kmh * KMH)
    if not shortest - 1e-9 <= length <= longest + 1e-9:
        raise WheelrailError(f"Run length must be between {shortest:g} and {longest:g} m on {set_label} at "
                             f"{speed_kmh:g} km/h; got {length:g} m")
    return RunConfig(set_label=set_label, line=line, model=model, speed=speed_kmh * KMH, preload=preload_kn * 1e3,
                     length=length, wheel_set_label=None if wheel is None else wheel_label, geometry=tuple(geometry))


_CLI_HINTS = (
    (re.compile(r"use --length-m <= ([0-9.]+)"), r"choose a run length of at most \1 m"),
    (re.compile(r"use --speed-kmh[^;,.]*"), "choose another speed"),
    (re.compile(r"use --line[^;,.]*"), "choose another line"),
    (re.compile(r"--([a-z]+)-[a-z]+"), r"\1"),
)


def in_page_words(message: str) -> str:
    """A core message as the page says it: command-line options replaced by what to do in the page."""
    for pattern, words in _CLI_HINTS:
        message = pattern.sub(words, message)
    return message
