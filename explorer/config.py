"""What one press of Run asks for, checked in the page's own words (no viser here).

A :class:`RunConfig` is the full configuration of a run (set, wheel set, line, model, speed, preload, length,
contact geometry); its :meth:`RunConfig.case` (everything but the model) keys every result the page shows, so
that a plot, a contact filter or a download never mixes configurations. :func:`read_config` turns the page's
fields (text as typed) into a config or one :class:`~wheelrail.core.errors.WheelrailError` a user can act on; the
choices it allows come from core (:func:`wheelrail.core.engine.track_lines.run_lines`,
:func:`wheelrail.core.engine.track_lines.usable_length`, the accepted ranges of :mod:`wheelrail.core.inputs.ranges`,
:func:`wheelrail.core.spectra.force.shortest_spectrum_run`). :func:`page_message` words any WheelrailError, core's
or the page's own, with the page's field labels and units (:data:`FIELD_NAMES`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace

from wheelrail.core.engine.track_lines import run_lines, usable_length, window_width
from wheelrail.core.errors import Blame, Name, WheelrailError
from wheelrail.core.inputs.contact_position import CONTACT_POSITION_INPUTS
from wheelrail.core.inputs.declared import (
    Input,
    by_key,
    describe_track,
    inputs_of,
    model_parameters,
    page_names,
)
from wheelrail.core.inputs.numerics import numerics_changes, numerics_from_changes, parse_track_numerics
from wheelrail.core.inputs.ranges import ACCEPTED, check_wheel_circumference
from wheelrail.core.inputs.run_records import IRREGULARITY_INPUT_VALUES
from wheelrail.core.models import REFERENCE_MODEL, model_entry, model_names
from wheelrail.core.parameters import KMH, ContactParameters, ModelParameters, RunParameters
from wheelrail.core.spectra.force import shortest_spectrum_run

__all__ = [
    "COMPARE",
    "COMPARE_ORDER",
    "FIELD_NAMES",
    "MODEL_CHOICES",
    "NEAREST_WHEEL",
    "NO_LINE_FITS",
    "NO_WHEEL_SET",
    "RunConfig",
    "accepted_text",
    "length_range",
    "models_of",
    "numerics_hint",
    "offered_lines",
    "page_message",
    "read_config",
    "field_hint",
    "field_text",
    "read_inputs",
    "read_session",
    "read_train",
    "read_wheel",
    "WHEEL_SHAPE_KEYS",
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
# field takes and that unit per SI unit. The declared inputs' come from their declaration
# (wheelrail.core.inputs.declared, the fields are built from it); the rest are the page's own controls.
FIELD_NAMES: dict[str, Name] = {
    **page_names(),
    "radius": page_names()["wheel_radius"],  # the paper's R: the wheel's, as the page sets it
    "length": Name("Run length", "m"),
    "line": Name("Line"),
    "model": Name("Contact model"),
    "set": Name("Roughness set"),
    "wheel_set": Name("Wheel roughness"),
    "train_axles": Name("Train axles"),  # the Noise tab's train
    "train_length": Name("Train length", "m"),
    # the modal wheel's shape (core.inputs.ranges' wheel_<field> ranges, in mm; "Tyre width", "Web offset", ...)
    **{
        key: Name(key.removeprefix("wheel_").replace("_", " ").capitalize(), "mm", 1e3)
        for key in ACCEPTED
        if key.startswith("wheel_") and key not in page_names()
    },
    # the Noise tab's contact position (core.inputs.contact_position: its declaration's label, mm)
    **{entry.key: Name(entry.label, entry.shown.name, entry.shown.scale) for entry in CONTACT_POSITION_INPUTS},
    "wheel_name": Name("Wheel shape"),  # the Wheel tab's named wheel
    "added_loss_factor": Name("Added loss factor"),  # the Wheel tab's damper
}
NEAREST_WHEEL = "nearest"  # the Wheel tab's choice of the named wheel nearest the run's wheel radius
WHEEL_SHAPE_KEYS = tuple(k for k in ACCEPTED if k.startswith("wheel_") and k not in page_names())
"""The modal wheel's shape inputs besides its radius (the Wheel tab's fields): ``wheel_tyre_width``, ..."""
NO_LINE_FITS = "no line fits"  # the Line menu when the model cannot run on any line of the set(s)
NUMERICS_LABEL = "Track numerics"  # the Track folder's field of core's --track-numerics (core.inputs.numerics)


def accepted_text(key: str) -> str:
    """An input's accepted range (its declaration) in its field's unit, for the field's hint: "1 to 500 kN"."""
    return by_key(key).accepted_text()


def field_hint(entry: Input) -> str:
    """A declared input's field hint: what it is, its range and its default ("Rail pad stiffness, per support,
    10 to 3000 MN/m; default 120 MN/m")."""
    return f"{entry.help[0].upper()}{entry.help[1:]}, {entry.accepted_text()}; default {entry.default_text()}"


def numerics_hint() -> str:
    """The Track numerics field's hint: what it takes (core's declaration of ``--track-numerics``), its default."""
    from wheelrail.core.inputs.numerics import NUMERICS_FIELDS

    names = ", ".join(entry.name for entry in NUMERICS_FIELDS)
    return (
        f"The track's numerics as name=value pairs, e.g. elements_per_bay=32 (names: {names}; ranges in the user "
        "guide); each change is a new one-off precompute of the track. Empty: the converged defaults."
    )


def field_text(entry: Input) -> str:
    """A declared input's field as a new page shows it: its default in the field's unit, or empty (unset)."""
    shown = entry.shown_default()
    return "" if shown is None or entry.unset else f"{shown:g}"


def page_message(error: WheelrailError) -> str:
    """A WheelrailError as the page says it: its input named by the field's label, values in the field's unit."""
    from wheelrail.explorer.irregularity import IRREGULARITY_NAMES

    return error.render({**FIELD_NAMES, **page_names(), **IRREGULARITY_NAMES})  # the declared names as now


@dataclass(frozen=True)
class RunConfig:
    """The full configuration of one run (SI inside; the page shows km/h, kN, m).

    ``inputs`` holds the declared inputs (``wheelrail.core.inputs.declared.INPUTS``) that differ from their default,
    as (key, SI value) in declaration order; every other input is its default."""

    set_label: str
    line: int
    model: str
    length: float  # m
    wheel_set_label: str | None = None  # a wheel set added to the rail set (combined roughness); None: smooth
    inputs: tuple[tuple[str, float], ...] = ()
    irregularities: tuple = ()  # core's WheelFlat, RailJoint, DippedWeld, Squat (the Irregularity folder)
    irregularity_input: str = IRREGULARITY_INPUT_VALUES[0]  # what the Hertz models are driven by over them
    track_numerics: tuple[tuple[str, float], ...] = ()  # those that differ from the default, as typed (name, value)

    def value(self, key: str):
        """A declared input's value, SI (its default where not given)."""
        return dict(self.inputs).get(key, by_key(key).default())

    @property
    def speed(self) -> float:
        """m/s."""
        return self.value("speed")

    @property
    def preload(self) -> float:
        """N."""
        return self.value("preload")

    def case(self) -> tuple:
        """Everything but the model: results of one case compare (spectra, contact filters)."""
        inputs = tuple((key, round(value, 12)) for key, value in self.inputs)
        case = (self.set_label, self.wheel_set_label, self.line, round(self.length, 9), inputs)
        case += (self.track_numerics,) if self.track_numerics else ()
        return (*case, self.irregularities, self.irregularity_input) if self._irregular() else case

    def for_model(self, model: str) -> RunConfig:
        return replace(self, model=model)

    def _irregular(self) -> bool:
        """Whether the run differs from one without irregularities (some given, or the raw input chosen)."""
        return bool(self.irregularities) or self.irregularity_input != IRREGULARITY_INPUT_VALUES[0]

    def params(self) -> ModelParameters:
        """The run's parameters: the declared inputs and, if any, the irregularities (``RunParameters``)."""
        params = model_parameters(dict(self.inputs))
        if not self._irregular():
            return params
        run = replace(params.run, irregularities=self.irregularities, irregularity_input=self.irregularity_input)
        return replace(params, run=run)

    def run_options(self) -> dict:
        """The run's keywords of ``prepare_run`` besides its parameters: ``track_numerics`` when given (else {})."""
        if not self.track_numerics:
            return {}
        return {"track_numerics": numerics_from_changes(self.track_numerics, label=NUMERICS_LABEL)}

    def numerics_words(self) -> str:
        """The track numerics given, as core words them ("track numerics elements_per_bay=32"), or ""."""
        from wheelrail.core.inputs.numerics import numerics_words

        return f"track numerics {numerics_words(dict(self.track_numerics))}" if self.track_numerics else ""

    def irregularity_words(self) -> str:
        """The irregularities in core's words ("flat 50 mm rounded at x = 0.5 m (Hertz on the trajectory)"), or
        "" for a run without."""
        if not self.irregularities:
            return ""
        from wheelrail.core.irregularities.shapes import words

        return f"{', '.join(map(words, self.irregularities))} (Hertz on the {self.irregularity_input})"

    def contact(self) -> ContactParameters:
        return self.params().contact

    def _shown(self) -> list[Input]:
        """The inputs a label names: the always-shown ones and those given, in declaration order."""
        given = dict(self.inputs)
        return [entry for entry in inputs_of() if entry.always_shown or entry.key in given]

    def case_label(self, *, stated: bool = False) -> str:
        """The case as people read it: 'corrugated-rail, line 0, 100 km/h, 65 kN, 3 m' (with a wheel set:
        'corrugated-rail + sinter-wheel-1, ...'; an input given: '..., wheel radius 460 mm'); ``stated``: the
        element size named even at its default ('..., 3 m, element size 1 mm'), as a result's text says it."""
        sets = self.set_label if self.wheel_set_label is None else f"{self.set_label} + {self.wheel_set_label}"
        shown = self._shown()
        if stated and by_key("element_size") not in shown:
            shown.append(by_key("element_size"))
        head = [entry.words(self.value(entry.key)) for entry in shown if entry.always_shown]
        rest = [entry.words(self.value(entry.key)) for entry in shown if not entry.always_shown]
        irregular = [self.irregularity_words()] if self.irregularities else []
        numerics = [self.numerics_words()] if self.track_numerics else []
        return ", ".join([sets, f"line {self.line}", *head, f"{self.length:g} m", *rest, *numerics, *irregular])

    def title_label(self) -> str:
        """The case as a plot's title names it: its case label without the track's inputs, then the track in core's
        words (``describe_track``): 'corrugated-rail, line 0, 100 km/h, 65 kN, 3 m; the paper's track'."""
        kept = replace(self, inputs=tuple((k, v) for k, v in self.inputs if by_key(k).group != "track"))
        return f"{kept.case_label()}; {describe_track(self.params())}"

    def label(self, *, stated: bool = False) -> str:
        """The model on the case (:meth:`case_label`, ``stated`` as there)."""
        return f"{self.model} on {self.case_label(stated=stated)}"

    def file_stem(self) -> str:
        """A file name for downloads: 'wheelrail-3d-corrugated-rail-line0-100kmh-65kN-3m'."""
        sets = [self.set_label] if self.wheel_set_label is None else [self.set_label, self.wheel_set_label]
        head = [entry.file_part(self.value(entry.key)) for entry in self._shown() if entry.always_shown]
        rest = [entry.file_part(self.value(entry.key)) for entry in self._shown() if not entry.always_shown]
        irregular = [f"{type(item).__name__}{item.position:g}m" for item in self.irregularities]
        numerics = [f"{name}{value:g}" for name, value in self.track_numerics]
        parts = ["wheelrail", self.model, *sets, f"line{self.line}", *head, f"{self.length:g}m", *rest, *numerics]
        parts += irregular
        return re.sub(r"[^A-Za-z0-9.+-]+", "_", "-".join(parts)).replace("_-", "-").strip("_")

    def as_dict(self) -> dict:
        """The configuration as the page's units say it (keys: the command line's ``speed_kmh``, ...)."""
        values = {"model": self.model, "set": self.set_label, "line": self.line, "length_m": self.length}
        if self.wheel_set_label is not None:
            values["wheel_set"] = self.wheel_set_label
        values.update((entry.dest, entry.to_shown(self.value(entry.key))) for entry in self._shown())
        if self.track_numerics:
            values["track_numerics"] = dict(self.track_numerics)
        if self._irregular():
            from wheelrail.core.irregularities.shapes import as_record

            values["irregularities"] = [as_record(item) for item in self.irregularities]
            values["irregularity_input"] = self.irregularity_input
        return values


def models_of(model_choice: str) -> tuple[str, ...]:
    """The models one choice of the menu runs (``compare``: all, the reference first)."""
    return COMPARE_ORDER if model_choice == COMPARE else (model_choice,)


def offered_lines(
    roughness, model_choice: str, contact: ContactParameters, wheel=None, element_size: float | None = None
) -> tuple[int, ...]:
    """Lines the page offers: the lines every model of the choice can run on for this contact and element size (m;
    default 1 mm) (core's rule, :func:`wheelrail.core.engine.track_lines.run_lines`: for ``3d``, and ``compare``,
    which runs it, the lines whose window fits the set on its grid), and with a wheel set the lines it has data at
    (paired by lateral position)."""
    run = RunParameters() if element_size is None else RunParameters(element_size=element_size)
    params = ModelParameters(contact=contact, run=run)
    found = [set(run_lines(roughness, model, params, wheel)) for model in models_of(model_choice)]
    return tuple(sorted(set.intersection(*found)))


def read_inputs(**typed) -> tuple[tuple[str, float], ...]:
    """The declared inputs' fields as typed (keyword: the input's ``dest``, e.g. ``pad_stiffness_mn_m="60"``;
    text in the field's unit; absent or empty: the default where the input has an ``unset`` meaning) as
    ``RunConfig.inputs``, or one WheelrailError in the page's words: each value against its declared range,
    then core's rules that relate them (a tread that conforms, a patch too large at the preload)."""
    unknown = set(typed) - {entry.dest for entry in inputs_of()}
    if unknown:
        raise TypeError(f"unknown input field(s) {sorted(unknown)}")
    values = {}
    for entry in inputs_of():
        text = str(typed.get(entry.dest, "") or "").strip()
        if not text and (entry.unset or entry.dest not in typed):
            continue
        value = entry.check(_number(text, entry.key) * entry.shown.si)
        default = entry.default()
        if default is None or not math.isclose(value, default, rel_tol=1e-12, abs_tol=0.0):
            values[entry.key] = value
    model_parameters(values)  # core's checks of the whole (the patch at the preload, the tread)
    return tuple(values.items())


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
        raise WheelrailError("not a number", Blame(key, str(text)))
    return value


def read_train(axles_text, length_text) -> tuple[int, float]:
    """The Noise tab's train (axles, length in m) from its fields, or one WheelrailError in the page's words."""
    from wheelrail.core.noise.run_noise import checked_train

    axles = _number(axles_text, "train_axles")
    if axles != round(axles):
        raise WheelrailError("not a whole number of at least 1", Blame("train_axles", str(axles_text)))
    return checked_train(int(axles), _number(length_text, "train_length"))


def read_contact_position(texts) -> object:
    """The Noise tab's contact position (:class:`~wheelrail.core.inputs.contact_position.ContactPosition`, m) from
    its fields' texts (mm, in ``CONTACT_POSITION_INPUTS``' order), or one WheelrailError in the page's words."""
    from wheelrail.core.inputs.contact_position import ContactPosition

    values = {}
    for entry, text in zip(CONTACT_POSITION_INPUTS, texts, strict=True):
        values[entry.field] = _number(text, entry.key) * entry.shown.si
    return ContactPosition(**values)


def read_wheel(name: str, wheel_radius: float, shape: dict[str, str], added_text) -> tuple[object, float]:
    """The Wheel tab's wheel: the named wheel ``name`` (or the nearest, :data:`NEAREST_WHEEL`) at the run's rolling
    radius (m), each shape field typed (mm; ``shape``: key -> text, empty: the named wheel's) set on it, and the
    added loss factor (empty: 0); or one WheelrailError in the page's words."""
    from wheelrail.core.modal_wheel import modal_loss_factor, wheel_profile_for

    profile = wheel_profile_for(wheel_radius, None if name == NEAREST_WHEEL else name)
    typed = {key: _number(text, key) * 1e-3 for key, text in shape.items() if str(text).strip()}
    profile = replace(profile, **{key.removeprefix("wheel_"): value for key, value in typed.items()})
    added = _number(added_text, "added_loss_factor") if str(added_text).strip() else 0.0
    modal_loss_factor(0, "axial", added)  # its range, said now
    return profile, added


def _span(lines: tuple[int, ...]) -> str:
    if not lines:
        return "no line"
    if lines[-1] - lines[0] == len(lines) - 1:
        return f"a line from {lines[0]} to {lines[-1]}"
    return "one of lines " + ", ".join(map(str, lines))


def _checked_irregular(irregular: tuple, params: ModelParameters, length: float) -> tuple:
    """``(irregularities, irregularity_input)`` checked against the wheel, the track and a run from 0 to
    ``length`` (m), or one WheelrailError (core's ``check_irregularities``)."""
    items, irregularity_input = irregular
    if items:
        from wheelrail.core.irregularities import check_irregularities

        check_irregularities(items, wheel_radius=params.contact.radius_along, run_start=0.0, run_end=length,
                             sleeper_spacing=params.track.support.sleeper_spacing)  # fmt: skip
    return tuple(items), irregularity_input


def read_config(
    roughness,
    set_label: str,
    *,
    line,
    model: str,
    length_m,
    wheel=None,
    wheel_label: str | None = None,
    irregular: tuple = ((), IRREGULARITY_INPUT_VALUES[0]),
    track_numerics: str = "",
    **typed,
) -> RunConfig:
    """The run the page's fields ask for, or one WheelrailError in the page's words (what to type instead).

    ``typed``: the declared inputs' fields as typed (see :func:`read_inputs`: ``speed_kmh="100"``,
    ``pad_stiffness_mn_m="60"``, ...); ``wheel`` (labelled ``wheel_label``) a wheel set added to the rail set
    ``roughness``, or None; ``irregular`` the irregularities and the Hertz models' input
    (``wheelrail.explorer.irregularity.read_irregularities``), checked here against the wheel, the track and a
    run from 0 to the run length (the run checks them against its exact first and last wheel positions);
    ``track_numerics`` the Track numerics field as typed (``name=value,...``, core's ``--track-numerics``)."""
    if model not in MODEL_CHOICES:
        raise WheelrailError(f"unknown contact model '{model}'; choose one of {', '.join(MODEL_CHOICES)}")
    inputs = read_inputs(**typed)
    numerics = numerics_changes(parse_track_numerics(str(track_numerics or ""), label=NUMERICS_LABEL))
    params = model_parameters(dict(inputs))
    speed_kmh, preload_kn = params.run.speed / KMH, params.contact.preload / 1e3
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
    contact = params.contact
    if wheel is not None:  # core's rule: the wheel set must go round this wheel
        check_wheel_circumference(wheel.length, contact.radius_along, wheel_label)
    allowed = offered_lines(roughness, model, contact, wheel, params.run.element_size)
    sets = set_label if wheel is None else f"{set_label} + {wheel_label}"
    if not allowed:
        width = window_width(params) * 1e3
        raise WheelrailError(
            f"The 3d contact patch at {preload_kn:g} kN is {2e3 * contact.hertz_semi_axes()[1]:.1f} "
            f"mm wide across the rail and 3d needs data {width:.3g} mm across around its line: no line of {sets} "
            "leaves room for it; choose a wider set, another geometry or a one-line model"
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
    shortest, longest = length_range(roughness, speed_kmh * KMH, params.run.element_size)
    if not shortest - 1e-9 <= length <= longest + 1e-9:
        reason = f"on {set_label} at {speed_kmh:g} km/h: long enough for a force spectrum, within the data"
        raise WheelrailError(None, Blame("length", length, unit="m", minimum=shortest, maximum=longest, reason=reason))
    items, irregularity_input = _checked_irregular(irregular, params, length)
    return RunConfig(
        set_label=set_label,
        line=line,
        model=model,
        length=length,
        wheel_set_label=None if wheel is None else wheel_label,
        inputs=inputs,
        irregularities=items,
        irregularity_input=irregularity_input,
        track_numerics=tuple(numerics.items()),
    )


SESSION_KEYS = (
    "wheelrail_session", "set", "wheel_set", "model", "line", "length_m", "inputs", "irregularity", "track_numerics"
)  # fmt: skip
"""The settings of a session document (``SessionFiles.session``), in the order it writes them."""
SESSION_OPTIONAL = ("inputs", "irregularity", "track_numerics")  # a session without them has them as a new page


def read_session(content: bytes, sets: tuple[str, ...], wheel_sets: tuple[str, ...]) -> dict:
    """A session document saved by the explorer (``SessionFiles.session``) read back and checked: its settings as
    text fields, or one WheelrailError (not a session, nested too deeply, a setting or input it does not hold, a
    set or wheel set this page does not have, a model it does not know). :func:`session_config` checks the values
    as the fields do, before any is set."""
    import json

    try:
        session = json.loads(content.decode("utf-8"))
    except RecursionError:  # e.g. 100 000 nested brackets: no session nests that deep
        raise WheelrailError("session file: nested too deeply to be a session saved by the page") from None
    except (UnicodeDecodeError, json.JSONDecodeError):
        raise WheelrailError("not a wheelrail session file (JSON saved with Save session)") from None
    if not isinstance(session, dict) or session.get("wheelrail_session") != 1:
        raise WheelrailError("not a wheelrail session file (JSON saved with Save session)")
    unknown = sorted(set(session) - set(SESSION_KEYS))
    if unknown:
        raise WheelrailError(
            f"session file: unknown setting(s) {', '.join(map(repr, unknown))}; a session holds "
            f"{', '.join(SESSION_KEYS)}"
        )
    missing = [key for key in SESSION_KEYS if key not in session and key not in SESSION_OPTIONAL]
    if missing:
        raise WheelrailError(f"session file: no {', '.join(missing)}")
    fields = {key: session[key] for key in ("set", "wheel_set", "model", "line", "length_m")}
    inputs = session.get("inputs", {})
    fields["track_numerics"] = session.get("track_numerics", "")
    if not all(isinstance(value, str) for value in fields.values()) or not isinstance(inputs, dict):
        raise WheelrailError("session file: the settings must be text as the page's fields hold them")
    if fields["set"] not in sets:
        raise WheelrailError(f"session file: the roughness set {fields['set']!r} is not loaded here; upload it first")
    if fields["wheel_set"] not in wheel_sets:
        raise WheelrailError(f"session file: the wheel roughness {fields['wheel_set']!r} is not offered here")
    if fields["model"] not in MODEL_CHOICES:
        raise WheelrailError(f"session file: unknown contact model {fields['model']!r}")
    known = {entry.dest for entry in inputs_of()}
    unknown = sorted(set(inputs) - known)
    if unknown or not all(isinstance(value, str) for value in inputs.values()):
        raise WheelrailError(f"session file: unknown inputs {', '.join(unknown) or 'or values not text'}")
    from wheelrail.explorer.irregularity import session_irregularity

    return {**fields, "inputs": inputs, "irregularity": session_irregularity(session.get("irregularity"))}


def session_config(session: dict, roughness, wheel=None, wheel_label: str | None = None) -> RunConfig:
    """The run a session (:func:`read_session`) asks for on ``roughness`` (its set) and ``wheel`` (its wheel set,
    or None), every input it does not hold at its default: one WheelrailError in the page's words otherwise (a run
    length outside what the set holds at the session's speed, a line the model cannot run on, an input outside its
    range), so that a session is loaded whole or not at all, never brought into range without a word."""
    from wheelrail.explorer.irregularity import session_read

    typed = {entry.dest: session["inputs"].get(entry.dest, field_text(entry)) for entry in inputs_of()}
    try:
        return read_config(
            roughness,
            session["set"],
            line=session["line"],
            model=session["model"],
            length_m=session["length_m"],
            wheel=wheel,
            wheel_label=wheel_label,
            irregular=session_read(session.get("irregularity", {})),
            track_numerics=session.get("track_numerics", ""),
            **typed,
        )
    except WheelrailError as error:
        raise WheelrailError(f"session file: {page_message(error)}; nothing was loaded") from None
