"""What one press of Run asks for, checked in the page's own words (no viser here).

A :class:`RunConfig` is the full configuration of a run (set, wheel set, line, model, speed, preload, length,
contact geometry); its :meth:`RunConfig.case` (everything but the model) keys every result the page shows, so
that a plot, a contact filter or a download never mixes configurations. :func:`read_config` turns the page's
fields (text as typed) into a config or one :class:`~wheelrail.core.errors.WheelrailError` a user can act on; the
choices it allows come from core (:func:`wheelrail.core.run_setup.run_lines`,
:func:`wheelrail.core.run_setup.usable_length`, the accepted ranges of :mod:`wheelrail.core.accepted`,
:func:`wheelrail.core.spectra.shortest_spectrum_run`). :func:`page_message` words any WheelrailError, core's
or the page's own, with the page's field labels and units (:data:`FIELD_NAMES`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace

from wheelrail.core.accepted import ACCEPTED, check_wheel_circumference
from wheelrail.core.errors import Name, WheelrailError
from wheelrail.core.models import REFERENCE_MODEL, model_entry, model_names
from wheelrail.core.parameters import KMH, ContactParameters, ModelParameters, RunParameters
from wheelrail.core.run_setup import run_lines, usable_length
from wheelrail.core.spectra import shortest_spectrum_run

__all__ = [
    "COMPARE",
    "COMPARE_ORDER",
    "FIELD_NAMES",
    "GEOMETRY_FIELDS",
    "MODEL_CHOICES",
    "NO_LINE_FITS",
    "NO_WHEEL_SET",
    "PRELOAD_RANGE_KN",
    "RunConfig",
    "accepted_text",
    "length_range",
    "models_of",
    "offered_lines",
    "page_message",
    "read_config",
    "read_geometry",
    "read_train",
]

COMPARE = "compare"
# the registry's models, installed plug-ins included (read once, when the explorer starts)
MODEL_CHOICES = (*model_names(), COMPARE)
# the reference first (every contact filter needs it), then the others: compiled laws before per-step ones
# (the built-in ones from the cheapest to the costliest)
COMPARE_ORDER = (
    REFERENCE_MODEL,
    *sorted(
        (m for m in reversed(MODEL_CHOICES[:-1]) if m != REFERENCE_MODEL),
        key=lambda m: not model_entry(m).traits.compiled,
    ),
)
MAX_WHEEL_RUN_M = 100.0  # wheel data repeat around the circumference: longest run offered on a wheel set
NO_WHEEL_SET = "none"  # the wheel-set picker's choice for a smooth wheel (one rough surface, the paper's case)
# What the page calls each input an error can name (WheelrailError.parameter): its field's label, the unit the
# field takes and that unit per SI unit (the labels of the fields in app.py, less their "(unit)")
FIELD_NAMES: dict[str, Name] = {
    "speed": Name("Speed", "km/h", 1.0 / KMH),
    "preload": Name("Preload", "kN", 1e-3),
    "length": Name("Run length", "m"),
    "line": Name("Line"),
    "wheel_radius": Name("Wheel radius", "mm", 1e3),
    "radius": Name("Wheel radius", "mm", 1e3),  # the paper's R: the wheel's, as the page sets it
    "rail_crown_radius": Name("Rail crown radius", "mm", 1e3),
    "wheel_transverse_radius": Name("Wheel tread radius across", "mm", 1e3),
    "rail_loss_factor": Name("Rail loss factor"),  # the track's inputs (the fields: to come)
    "pad_width": Name("Pad width", "mm", 1e3),
    "model": Name("Contact model"),
    "set": Name("Roughness set"),
    "wheel_set": Name("Wheel roughness"),
    "train_axles": Name("Train axles"),  # the Noise tab's train
    "train_length": Name("Train length", "m"),
}
NO_LINE_FITS = "no line fits"  # the Line menu when the model cannot run on any line of the set(s)
PRELOAD_RANGE_KN = ACCEPTED["preload"].in_unit(FIELD_NAMES["preload"].scale)  # core's range, in the field's kN
# ContactParameters geometry field -> what the page calls it (mm in the page, m inside; empty: the default)
GEOMETRY_FIELDS = {
    name: FIELD_NAMES[name].label for name in ("wheel_radius", "rail_crown_radius", "wheel_transverse_radius")
}


def accepted_text(key: str) -> str:
    """An input's accepted range (``core.accepted``) in its field's unit, for the field's hint: "1 to 500 kN"."""
    name = FIELD_NAMES[key]
    accepted = ACCEPTED[key]
    low, high = accepted.in_unit(name.scale)
    if accepted.magnitude:
        return f"at least {low:g} {name.unit} in magnitude"
    return f"{low:g} to {high:g} {name.unit}"


def page_message(error: WheelrailError) -> str:
    """A WheelrailError as the page says it: its input named by the field's label, values in the field's unit."""
    return error.render(FIELD_NAMES)


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
        return (
            self.set_label,
            self.wheel_set_label,
            self.line,
            round(self.speed, 9),
            round(self.preload, 6),
            round(self.length, 9),
            geometry,
        )

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
        return ", ".join(
            [
                f"{sets}, line {self.line}, {self.speed / KMH:g} km/h, {self.preload / 1e3:g} kN, {self.length:g} m",
                *self._geometry_words(),
            ]
        )

    def label(self) -> str:
        return f"{self.model} on {self.case_label()}"

    def file_stem(self) -> str:
        """A file name for downloads: 'wheelrail-3d-corrugated-rail-line0-100kmh-65kN-3m'."""
        sets = [self.set_label] if self.wheel_set_label is None else [self.set_label, self.wheel_set_label]
        short = {"wheel_radius": "R", "rail_crown_radius": "crown", "wheel_transverse_radius": "tread"}
        parts = [
            "wheelrail",
            self.model,
            *sets,
            f"line{self.line}",
            f"{self.speed / KMH:g}kmh",
            f"{self.preload / 1e3:g}kN",
            f"{self.length:g}m",
            *(f"{short[name]}{value * 1e3:g}mm" for name, value in self.geometry),
        ]
        return re.sub(r"[^A-Za-z0-9.+-]+", "_", "-".join(parts)).replace("_-", "-").strip("_")

    def as_dict(self) -> dict:
        values = {
            "model": self.model,
            "set": self.set_label,
            "line": self.line,
            "speed_kmh": self.speed / KMH,
            "preload_kn": self.preload / 1e3,
            "length_m": self.length,
        }
        if self.wheel_set_label is not None:
            values["wheel_set"] = self.wheel_set_label
        values.update((f"{name}_mm", value * 1e3) for name, value in self.geometry)
        return values


def models_of(model_choice: str) -> tuple[str, ...]:
    """The models one choice of the menu runs (``compare``: all, the reference first)."""
    return COMPARE_ORDER if model_choice == COMPARE else (model_choice,)


def offered_lines(roughness, model_choice: str, contact: ContactParameters, wheel=None) -> tuple[int, ...]:
    """Lines the page offers: the lines every model of the choice can run on for this contact (core's rule,
    :func:`wheelrail.core.run_setup.run_lines`: for ``3d``, and ``compare``, which runs it, the lines whose
    window fits the set), and with a wheel set the lines it has data at (paired by lateral position)."""
    params = ModelParameters(contact=contact)
    found = [set(run_lines(roughness, model, params, wheel)) for model in models_of(model_choice)]
    return tuple(sorted(set.intersection(*found)))


def read_geometry(**fields_mm) -> tuple[tuple[str, float], ...]:
    """The geometry fields as typed (mm; empty: the paper's default) as ``RunConfig.geometry``, or one
    WheelrailError (core's checks of ``ContactParameters``: each radius's range, a concave tread that conforms);
    keywords: the names of ``GEOMETRY_FIELDS`` with ``_mm``. The patch size depends on the preload too:
    :func:`read_config` checks it at the run's."""
    geometry = []
    for name in GEOMETRY_FIELDS:
        text = str(fields_mm.get(f"{name}_mm", "") or "").strip()
        if text:
            geometry.append((name, _number(text, name) * 1e-3))
    ContactParameters(preload=ACCEPTED["preload"].minimum, **dict(geometry))  # at the lightest load accepted
    return tuple(geometry)


def length_range(roughness, speed: float, element_size: float | None = None) -> tuple[float, float]:
    """Shortest run with a force spectrum at this speed, longest run the set allows, m."""
    dx = RunParameters().element_size if element_size is None else element_size
    shortest = shortest_spectrum_run(speed, dx)
    longest = MAX_WHEEL_RUN_M if roughness.periodic else usable_length(roughness, dx)
    return round(shortest, 6), math.floor(longest / dx + 1e-9) * dx


def _number(text, key: str) -> float:
    """A field's text as a number in the field's unit (key: its ``FIELD_NAMES`` key), or one WheelrailError."""
    try:
        value = float(str(text).strip().replace(",", "."))
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise WheelrailError("not a number", parameter=key, value=str(text))
    return value


def read_train(axles_text, length_text) -> tuple[int, float]:
    """The Noise tab's train (axles, length in m) from its fields, or one WheelrailError in the page's words."""
    from wheelrail.core.noise.run_noise import checked_train

    axles = _number(axles_text, "train_axles")
    if axles != round(axles):
        raise WheelrailError("not a whole number of at least 1", parameter="train_axles", value=str(axles_text))
    return checked_train(int(axles), _number(length_text, "train_length"))


def _span(lines: tuple[int, ...]) -> str:
    if not lines:
        return "no line"
    if lines[-1] - lines[0] == len(lines) - 1:
        return f"a line from {lines[0]} to {lines[-1]}"
    return "one of lines " + ", ".join(map(str, lines))


def read_config(
    roughness,
    set_label: str,
    *,
    line,
    model: str,
    speed_kmh,
    preload_kn,
    length_m,
    geometry: tuple = (),
    wheel=None,
    wheel_label: str | None = None,
) -> RunConfig:
    """The run the page's fields ask for, or one WheelrailError in the page's words (what to type instead).

    ``geometry`` as :func:`read_geometry` gives it; ``wheel`` (labelled ``wheel_label``) a wheel set added to
    the rail set ``roughness``, or None."""
    if model not in MODEL_CHOICES:
        raise WheelrailError(f"unknown contact model '{model}'; choose one of {', '.join(MODEL_CHOICES)}")
    speed_kmh = _number(speed_kmh, "speed")
    ACCEPTED["speed"].check(speed_kmh * KMH)
    preload_kn = _number(preload_kn, "preload")
    if wheel is not None:
        if roughness.kind != "rail":
            raise WheelrailError(
                f"A wheel roughness is added to a rail set, and {set_label} is a {roughness.kind} "
                f"set: choose a rail set, or wheel roughness '{NO_WHEEL_SET}'"
            )
        if wheel.kind != "wheel":
            raise WheelrailError(
                f"{wheel_label} is a {wheel.kind} set, not a wheel set: choose a wheel set as the wheel roughness"
            )
    contact = ContactParameters(preload=preload_kn * 1e3, **dict(geometry))
    if wheel is not None:  # core's rule: the wheel set must go round this wheel
        check_wheel_circumference(wheel.length, contact.radius_along, wheel_label)
    allowed = offered_lines(roughness, model, contact, wheel)
    sets = set_label if wheel is None else f"{set_label} + {wheel_label}"
    if not allowed:
        raise WheelrailError(
            f"The 3d contact patch at {preload_kn:g} kN is {2e3 * contact.hertz_semi_axes()[1]:.1f} "
            f"mm wide across the rail: no line of {sets} leaves room for it; choose another "
            "geometry or a one-line model"
        )
    try:
        line = int(str(line).strip())
    except ValueError:
        raise WheelrailError(f"Line must be a whole number; got '{line}'") from None
    if line not in allowed:
        if line not in roughness.line_numbers:
            raise WheelrailError(f"Line {line} is not in {sets}; choose {_span(allowed)}")
        if wheel is not None and line not in offered_lines(roughness, REFERENCE_MODEL, contact, wheel):
            raise WheelrailError(
                f"Line {line} of {set_label} lies where {wheel_label} has no data across the "
                f"rail (wheel and rail are paired by position); choose {_span(allowed)}"
            )
        raise WheelrailError(
            f"Line {line} is too near the edge of {sets} for the 3d contact patch at "
            f"{preload_kn:g} kN; choose {_span(allowed)}"
        )
    length = _number(length_m, "length")
    shortest, longest = length_range(roughness, speed_kmh * KMH)
    if not shortest - 1e-9 <= length <= longest + 1e-9:
        raise WheelrailError(
            None,
            parameter="length",
            value=length,
            minimum=shortest,
            maximum=longest,
            unit="m",
            reason=f"on {set_label} at {speed_kmh:g} km/h: long enough for a force spectrum, within the data",
        )
    return RunConfig(
        set_label=set_label,
        line=line,
        model=model,
        speed=speed_kmh * KMH,
        preload=preload_kn * 1e3,
        length=length,
        wheel_set_label=None if wheel is None else wheel_label,
        geometry=tuple(geometry),
    )
