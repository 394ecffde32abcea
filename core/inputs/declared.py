"""The user-facing inputs, each declared once: key, place in ``ModelParameters``, units, label, group.

An :class:`Input` says what a front end needs of one number a user can set: its stable ``key`` (the
``parameter`` of a :class:`~wheelrail.core.errors.WheelrailError` about it, and the key of its accepted range in
:data:`wheelrail.core.inputs.ranges.ACCEPTED`, SI, with the reason for it), its ``path`` in
:class:`~wheelrail.core.parameters.ModelParameters` (``"track.support.pad_stiffness"``), the :class:`Unit` front
ends show it in, its page label, its group (the command-line option group and the explorer's folder) and a
sentence of help. Its default is read from the dataclass, never restated.

Everything else is derived from :data:`INPUTS`: the command line's options (``--pad-stiffness-mn-m``: the key
and the unit's token) and their help, the explorer's fields (one folder per group), the names each front end
gives an error (:func:`cli_names`, :func:`page_names`), the case key and file names of a result, and the
study's inputs. Adding an input is one declaration here, its range in ``ACCEPTED`` (which the parameter classes
check) and a test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from wheelrail.core.errors import Blame, Name, WheelrailError
from wheelrail.core.inputs.ranges import ACCEPTED, Accepted
from wheelrail.core.inputs.run_records import IRREGULARITY_INPUT_VALUES

if TYPE_CHECKING:  # parameters is imported on first use: the command line's start stays cheap
    from wheelrail.core.parameters import ModelParameters

__all__ = [
    "CHOICES",
    "GROUPS",
    "Choice",
    "INPUTS",
    "Input",
    "Unit",
    "by_key",
    "choice",
    "cli_names",
    "describe",
    "caption",
    "describe_changes",
    "describe_contact",
    "describe_track",
    "describe_words",
    "inputs_of",
    "model_parameters",
    "page_names",
]


@dataclass(frozen=True)
class Unit:
    """A unit front ends show values in: its ``name`` ("MN/m"), ``si`` (SI units per one of it: 1e6) and the
    ``token`` that ends an option's name ("mn-m": ``--pad-stiffness-mn-m``; "" for a pure number)."""

    name: str
    si: float
    token: str

    @property
    def scale(self) -> float:
        """This unit per SI unit (1e-6 for MN/m), as :class:`~wheelrail.core.errors.Name` takes it."""
        return 1.0 / self.si


KMH = Unit("km/h", 1.0 / 3.6, "kmh")
KN = Unit("kN", 1e3, "kn")
MM = Unit("mm", 1e-3, "mm")
MN_PER_M = Unit("MN/m", 1e6, "mn-m")
KNS_PER_M = Unit("kNs/m", 1e3, "kns-m")
KNM_PER_RAD = Unit("kNm/rad", 1e3, "knm-rad")
KG = Unit("kg", 1.0, "kg")
METRE = Unit("m", 1.0, "m")
NUMBER = Unit("", 1.0, "")


class OptionNamed:
    """The command-line name of a declared input (its ``key``, its ``shown`` unit if it has one, and its ``cli``
    name if it has one): ``cli``, else ``--`` + the key + the unit's token (``--pad-stiffness-mn-m``,
    ``--flat-length-mm``); ``dest`` is argparse's attribute name for it (``pad_stiffness_mn_m``)."""

    @property
    def option(self) -> str:
        """The command-line option (``--pad-stiffness-mn-m``)."""
        cli = getattr(self, "cli", "")
        if cli:
            return cli
        words = self.key.replace("_", "-")
        shown = getattr(self, "shown", None)
        return f"--{words}-{shown.token}" if shown is not None and shown.token else f"--{words}"

    @property
    def dest(self) -> str:
        """The option's attribute name in argparse's namespace (``pad_stiffness_mn_m``)."""
        return self.option[2:].replace("-", "_")


GROUPS = {"run": "Run", "geometry": "Contact geometry", "track": "Track"}
"""Input groups, in order, and their titles (the command line's option groups, the explorer's folders)."""


@dataclass(frozen=True)
class Input(OptionNamed):
    """One user-facing input, declared once (module docstring): its key, place, units, label and group.

    Attributes
    ----------
    key : str
        Stable name (``"pad_stiffness"``): the ``parameter`` of its errors, the key of its range.
    path : str
        Where it lives in ``ModelParameters``, dotted (``"track.support.pad_stiffness"``).
    shown : Unit
        The unit the command line and the explorer take it in.
    label : str
        The explorer's field label, without its unit ("Pad stiffness").
    group : str
        A key of :data:`GROUPS`.
    help : str
        What it is, in a few words (the option's help, the field's hint).
    unset : str or None
        What an empty field or an absent option means, for inputs whose dataclass default is None or
        infinite ("the paper's R"; "a cylindrical tread"); None: the dataclass default, a number.
    stem : str
        Its short name in file names ("R", "kP"); empty: the value and unit alone ("100kmh").
    always_shown : bool
        Named in every case label and file name, even at its default (speed, preload).
    cli : str
        The command-line option where it is not ``--`` + the key + the unit's token (``--element-mm`` for
        ``element_size``: ``wheelrail wheel --element-size-mm`` is the wheel's own mesh); empty: derived.

    See Also
    --------
    model_parameters : sets inputs on a ``ModelParameters``.
    wheelrail.core.inputs.ranges.ACCEPTED : the accepted range of each input, by key.

    Examples
    --------
    >>> from wheelrail.core.inputs.declared import by_key
    >>> pads = by_key("pad_stiffness")
    >>> pads.option, pads.dest, pads.default(), pads.shown.name
    ('--pad-stiffness-mn-m', 'pad_stiffness_mn_m', 120000000.0, 'MN/m')
    """

    key: str
    path: str
    shown: Unit
    label: str
    group: str
    help: str
    unset: str | None = None
    stem: str = ""
    always_shown: bool = False
    cli: str = ""

    def default(self) -> float | None:
        """Its default, read from ``ModelParameters()``.

        Returns
        -------
        float or None
            The default in SI units; None where the dataclass has None (a radius that defaults to another).
        """
        from wheelrail.core.parameters import ModelParameters

        return self.value_in(ModelParameters())

    def value_in(self, params):
        """Its value in ``params`` (a ``ModelParameters``), SI, as the dataclass holds it (None, inf included)."""
        value = params
        for part in self.path.split("."):
            value = getattr(value, part)
        return value

    def to_shown(self, value: float) -> float:
        """A value (SI) in the shown unit, rounded to 12 significant digits (80 km/h, not 79.99999999999999)."""
        return float(f"{value * self.shown.scale:.12g}")

    def shown_default(self) -> float | None:
        """The default in the shown unit, or None when it is not a finite number (see ``unset``)."""
        value = self.default()
        if value is None or not math.isfinite(value):
            return None
        return self.to_shown(value)

    @property
    def accepted(self) -> Accepted:
        """Its accepted range, SI, and the reason for it: ``wheelrail.core.inputs.ranges.ACCEPTED[key]``."""
        return ACCEPTED[self.key]

    @property
    def unit(self) -> str:
        """Its SI unit ("N/m"; "" for a pure number)."""
        return self.accepted.unit

    def check(self, value, argument: str | None = None) -> float:
        """Check a value against the input's accepted range.

        Parameters
        ----------
        value : float
            The value, SI units.
        argument : str, optional
            How the Python API names it in the error (``"SupportParameters.pad_stiffness"``).

        Returns
        -------
        float
            ``value`` as a float.

        Raises
        ------
        WheelrailError
            Keyed by ``key``, if the value is not a finite number within the range.
        """
        return self.accepted.check(value, argument)

    def in_shown(self) -> tuple[float, float]:
        """(minimum, maximum) in the shown unit, rounded for display."""
        return self.accepted.in_unit(self.shown.scale)

    def accepted_text(self) -> str:
        """The range in the shown unit: "5 to 400 km/h", "at least 50 mm in magnitude"."""
        low, high = self.in_shown()
        unit = f" {self.shown.name}" if self.shown.name else ""
        if self.accepted.magnitude:
            return f"at least {low:g}{unit} in magnitude"
        return f"{low:g} to {high:g}{unit}"

    def default_text(self) -> str:
        """The default as a front end states it: "120 MN/m", or the words of ``unset``."""
        shown = self.shown_default()
        if shown is None:
            return self.unset or "unset"
        unit = f" {self.shown.name}" if self.shown.name else ""
        text = f"{shown:g}{unit}"
        return f"{text}, {self.unset}" if self.unset else text

    def words(self, value: float) -> str:
        """A value as case labels say it: "pad stiffness 60 MN/m" ("100 km/h" for ``always_shown`` ones)."""
        unit = f" {self.shown.name}" if self.shown.name else ""
        number = f"{value * self.shown.scale:.6g}{unit}"
        return number if self.always_shown else f"{self.label.lower()} {number}"

    def file_part(self, value: float) -> str:
        """A value as file names say it: "100kmh", "R460mm", "kP60MNm"."""
        unit = "".join(c for c in self.shown.name if c.isalnum())
        return f"{self.stem}{value * self.shown.scale:.6g}{unit}"


def _track(key: str, field: str, shown: Unit, label: str, help_text: str, stem: str) -> Input:
    part = "rail" if field == "loss_factor" else "support"  # the rail's own input; the others the support's
    return Input(key, f"track.{part}.{field}", shown, label, "track", help_text, stem=stem)


_PAPER_R = "the paper's R"

INPUTS: tuple[Input, ...] = (
    Input("speed", "run.speed", KMH, "Speed", "run", "train speed", always_shown=True),
    Input("preload", "contact.preload", KN, "Preload", "run", "static wheel load", always_shown=True),
    Input(
        "element_size", "run.element_size", MM, "Element size", "run",
        "contact element length and step along the rail (the time step is element / speed)", stem="dx",
        cli="--element-mm",
    ),
    Input(
        "wheel_radius", "contact.wheel_radius", MM, "Wheel radius", "geometry", "wheel rolling radius, along the rail",
        unset=_PAPER_R, stem="R",
    ),
    Input(
        "rail_crown_radius", "contact.rail_crown_radius", MM, "Rail crown radius", "geometry",
        "rail head (crown) radius across the rail", unset=_PAPER_R, stem="crown",
    ),
    Input(
        "wheel_transverse_radius", "contact.wheel_transverse_radius", MM, "Wheel tread radius across", "geometry",
        "wheel tread radius across the rail (negative: concave, worn)", unset="a cylindrical tread", stem="tread",
    ),
    _track("pad_stiffness", "pad_stiffness", MN_PER_M, "Pad stiffness", "rail pad stiffness, per support", "kP"),
    _track("pad_damping", "pad_damping", KNS_PER_M, "Pad damping", "rail pad viscous damping, per support", "cP"),
    _track(
        "sleeper_mass", "sleeper_mass", KG, "Sleeper mass", "half-sleeper mass (one rail's share, as the paper)", "mS"
    ),
    _track("sleeper_spacing", "sleeper_spacing", METRE, "Sleeper spacing", "distance between supports", "LS"),
    _track(
        "ballast_stiffness", "ballast_stiffness", MN_PER_M, "Ballast stiffness",
        "ballast stiffness under a half sleeper", "kB",
    ),
    _track(
        "ballast_damping", "ballast_damping", KNS_PER_M, "Ballast damping",
        "ballast viscous damping under a half sleeper", "cB",
    ),
    _track(
        "rail_loss_factor", "loss_factor", NUMBER, "Rail loss factor",
        "loss factor of the rail's bending and shear stiffness (0: the paper's undamped rail; measured rails "
        "0.01-0.02)", "eta",
    ),
    _track(
        "pad_width", "pad_width", MM, "Pad width",
        "width of the rail pad along the rail (0: the paper's point support; a wide pad costs a 5x longer "
        "precompute)", "pad",
    ),
    Input(
        "pad_lateral_stiffness", "track.lateral.pad_lateral_stiffness", MN_PER_M, "Pad lateral stiffness", "track",
        "rail pad lateral (shear) stiffness, per support: the lateral track's (its decay rate)", stem="kPy",
    ),
    Input(
        "pad_rotational_stiffness", "track.lateral.pad_rotational_stiffness", KNM_PER_RAD, "Pad roll stiffness",
        "track", "rail pad stiffness against the rail's roll, per support: the lateral track's", stem="kPr",
    ),
    Input(
        "pad_lateral_loss_factor", "track.lateral.pad_lateral_loss_factor", NUMBER, "Pad lateral loss factor", "track",
        "loss factor of the rail pad's lateral and roll stiffness: the lateral track's", stem="etaPy",
    ),
)  # fmt: skip
"""Every user-facing input, in the order front ends show them."""


def by_key(key: str) -> Input:
    """The input declared with ``key`` (KeyError if none is)."""
    for entry in INPUTS:  # read at each call: what derives from the declaration never keeps a copy of it
        if entry.key == key:
            return entry
    raise KeyError(key)


def inputs_of(*groups: str) -> tuple[Input, ...]:
    """The inputs of these groups (all when none is named), in declaration order."""
    unknown = set(groups) - set(GROUPS)
    if unknown:
        raise ValueError(f"unknown input group(s) {sorted(unknown)}; groups are {list(GROUPS)}")
    return tuple(entry for entry in INPUTS if not groups or entry.group in groups)


def cli_names() -> dict[str, Name]:
    """How the command line names each input (its option, unit per SI unit, values bare after the option)."""
    return {e.key: Name(e.option, e.shown.name, e.shown.scale, True) for e in INPUTS}


def page_names() -> dict[str, Name]:
    """How the explorer names each input (its field's label and unit)."""
    return {e.key: Name(e.label, e.shown.name, e.shown.scale) for e in INPUTS}


def model_parameters(values: dict[str, float | None], base: ModelParameters | None = None) -> ModelParameters:
    """Model parameters with some inputs set, each checked against its declared range.

    Parameters
    ----------
    values : dict
        Input key (``"pad_stiffness"``, see :data:`INPUTS`) -> value in SI units; None keeps the default.
    base : ModelParameters, optional
        The parameters the values are set on; default: the paper's.

    Returns
    -------
    ModelParameters
        ``base`` with the values set.

    Raises
    ------
    WheelrailError
        For an unknown key; keyed by the input for a value outside its range; from the dataclasses for values
        that do not go together (a Hertz patch too large for the radii, a tread that conforms with the crown).

    See Also
    --------
    describe : the inputs of a ``ModelParameters``, by group.

    Examples
    --------
    >>> from wheelrail.core.inputs.declared import model_parameters
    >>> params = model_parameters({"speed": 50.0, "pad_stiffness": 600e6})   # SI: m/s, N/m
    >>> params.run.speed, params.track.support.pad_stiffness
    (50.0, 600000000.0)
    """
    from wheelrail.core.parameters import ModelParameters

    params = ModelParameters() if base is None else base
    known = {entry.key: entry for entry in INPUTS}
    for key, value in values.items():
        if key not in known:
            raise WheelrailError(f"unknown input {key!r}; inputs are {', '.join(known)}")
        if value is None:
            continue
        entry = known[key]
        entry.check(value)
        params = _replaced(params, entry.path.split("."), float(value))
    return params


def _replaced(owner, path: list[str], value):
    if len(path) == 1:
        return replace(owner, **{path[0]: value})
    return replace(owner, **{path[0]: _replaced(getattr(owner, path[0]), path[1:], value)})


_IN_USE = {"wheel_radius": "radius_along", "rail_crown_radius": "crown_radius"}
"""An unset radius is the one ``ContactParameters`` uses, read from it: the one rule, declared there (unset, the
wheel's and the rail crown's radius are its ``radius``, the paper's R = 0.39 m, each whatever the other is)."""


def describe(params: ModelParameters, *groups: str) -> dict[str, dict[str, float | None]]:
    """The inputs of some parameters by group, SI, as every result records them.

    Parameters
    ----------
    params : ModelParameters
        The parameters to describe.
    *groups : str
        Keys of :data:`GROUPS` (``"run"``, ``"geometry"``, ``"track"``); none: all of them.

    Returns
    -------
    dict
        Group -> input key -> value in SI units (``{"track": {"pad_stiffness": 1.2e8, ...}, ...}``); an unset
        radius as the radius in use (``_IN_USE``), an infinite tread radius as None (as JSON has it).

    See Also
    --------
    model_parameters : the inverse: parameters from input values.

    Examples
    --------
    >>> from wheelrail.core.inputs.declared import describe
    >>> from wheelrail.core.parameters import ModelParameters
    >>> describe(ModelParameters(), "run")
    {'run': {'speed': 27.77777777777778, 'preload': 65000.0, 'element_size': 0.001}}
    """
    found: dict[str, dict[str, float | None]] = {}
    for entry in inputs_of(*groups):
        value = entry.value_in(params)
        if value is None and entry.key in _IN_USE:
            value = getattr(params.contact, _IN_USE[entry.key])
        number = None if value is None or not math.isfinite(value) else float(value)
        found.setdefault(entry.group, {})[entry.key] = number
    return found


def describe_words(params, group: str) -> str:
    """The inputs of one group of ``params`` as a line of text: "pad stiffness 120 MN/m, pad damping 16 kNs/m, ..."
    (an unset radius as the one in use followed by its ``unset`` words, "rail crown radius 390 mm (the paper's
    R)"; an infinite tread as its ``unset`` words)."""
    values = describe(params, group)[group]
    parts = []
    for key, value in values.items():
        entry = by_key(key)
        if value is None:
            parts.append(entry.unset)
        elif entry.unset and entry.value_in(params) is None:
            parts.append(f"{entry.words(value)} ({entry.unset})")
        else:
            parts.append(entry.words(value))
    return ", ".join(parts)


PAPER_TRACK = "the paper's track"
"""How a caption names the track of ``TrackParameters()`` (paper section 2.2)."""


def describe_changes(params, group: str, *, leave_out: tuple[str, ...] = ()) -> list[str]:
    """The inputs of one group of ``params`` that differ from their defaults, each in words ("pad stiffness 60
    MN/m"), in declaration order; the keys in ``leave_out`` are not looked at (a study's swept inputs)."""
    return [
        entry.words(entry.value_in(params))
        for entry in inputs_of(group)
        if entry.key not in leave_out and entry.value_in(params) != entry.default()
    ]


def describe_track(params, *, leave_out: tuple[str, ...] = ()) -> str:
    """The track of ``params`` as figures name it: :data:`PAPER_TRACK`, or the inputs that differ from it ("the
    track with pad stiffness 60 MN/m (else the paper's)"); with ``leave_out``, what the tracks of a sweep share
    ("every track the paper's but for its pad stiffness")."""
    changes = describe_changes(params, "track", leave_out=leave_out)
    if leave_out:
        swept = " and ".join(by_key(key).label.lower() for key in leave_out)
        if not changes:
            return f"every track the paper's but for its {swept}"
        return f"every track with {', '.join(changes)}, else the paper's but for its {swept}"
    return PAPER_TRACK if not changes else f"the track with {', '.join(changes)} (else the paper's)"


def caption(
    params,
    *,
    model: str | None = None,
    run: bool = True,
    geometry: bool = True,
    track: bool = True,
    wheel: str | None = None,
    leave_out: tuple[str, ...] = (),
) -> str:
    """The configuration a figure shows, as its title names it: one source for every figure of every front end.

    Parameters
    ----------
    params : ModelParameters
        The configuration.
    model : str, optional
        The contact model, named first when given.
    run, geometry, track : bool
        Name the speed and preload (and the element size where it is not the default 1 mm); the contact
        geometry's inputs that differ from the paper's; the track (:func:`describe_track`).
    wheel : str, optional
        The wheel in words (:func:`wheelrail.core.modal_wheel.describe_wheel`), named last when given.
    leave_out : tuple of str
        Inputs a figure shows on an axis (a study's speeds, its swept track inputs): left out of the words.

    Returns
    -------
    str
        The parts joined by "; ", e.g. "hertz; 100 km/h, 65 kN; the paper's track".

    Examples
    --------
    >>> from wheelrail.core.inputs.declared import caption, model_parameters
    >>> caption(model_parameters({"pad_stiffness": 60e6}), run=False)
    "the track with pad stiffness 60 MN/m (else the paper's)"
    """
    parts = [] if model is None else [model]
    if run:
        named = tuple(e.key for e in inputs_of("run") if e.always_shown)  # the speed and preload, always named
        shown = [by_key(key).words(by_key(key).value_in(params)) for key in named if key not in leave_out]
        changed = describe_changes(params, "run", leave_out=(*leave_out, *named))  # the element size, if not 1 mm
        parts.append(", ".join([*shown, *changed]))
    if geometry:
        parts += describe_changes(params, "geometry", leave_out=leave_out)
    if track:
        swept = tuple(entry.key for entry in inputs_of("track") if entry.key in leave_out)
        parts.append(describe_track(params, leave_out=swept))
    if wheel is not None:
        parts.append(wheel)
    return "; ".join(parts)


def describe_contact(params) -> str:
    """The contact geometry of ``params`` and its Hertz patch as a line of text, as ``run``, ``filters`` and
    ``study`` print it: the radii (:func:`describe_words`) and the semi-axes a along and b across the rail."""
    contact = params.contact
    a, b = contact.hertz_semi_axes()
    return (
        f"{describe_words(params, 'geometry')}; Hertz patch at {contact.preload / 1e3:g} kN "
        f"a = {a * 1e3:.2f} mm along, b = {b * 1e3:.2f} mm across"
    )


@dataclass(frozen=True)
class Choice(OptionNamed):
    """One user-facing choice among named values (not a number): its stable ``key`` (the ``parameter`` of its
    errors), the ``values`` in the order front ends offer them, the ``default``, a page ``label``, a ``help``
    sentence and ``words``: what each value means, for help texts and hints."""

    key: str
    values: tuple[str, ...]
    default: str
    label: str
    help: str
    words: tuple[str, ...]
    cli: str = ""

    def check(self, value) -> str:
        """``value`` if it is one of ``values``, else one WheelrailError keyed by ``key``."""
        if not isinstance(value, str) or value not in self.values:
            raise WheelrailError(f"must be one of {', '.join(self.values)}", Blame(self.key, value))
        return value

    def help_text(self) -> str:
        """The help: the sentence, then each value with its meaning and the default."""
        meanings = "; ".join(f"{v}: {w}" for v, w in zip(self.values, self.words, strict=True))
        return f"{self.help} ({meanings}; default {self.default})"


CHOICES: tuple[Choice, ...] = (
    Choice(
        "noise_wheel_model",
        ("directive", "modal"),
        "directive",
        "Wheel model (noise)",
        "the wheel's sound power in the TWINS-like chain",
        (
            "CNOSSOS-EU's L_H,veh, Table G-3b, for the tabulated diameter nearest 2R",
            "the axisymmetric FE wheel of radius R radiating from its own modes",
        ),
        cli="--wheel-model",  # `wheelrail noise --wheel-model`; `run --wheel-model` (2dof|modal) is the interaction's
    ),
    Choice(
        "irregularity_input",
        IRREGULARITY_INPUT_VALUES,
        IRREGULARITY_INPUT_VALUES[0],
        "Irregularity input (Hertz)",
        "what the Hertz models are driven by over a discrete irregularity (2d and 3d see the surface itself)",
        (
            "the wheel-centre trajectory of a rigid wheel, superposed on the model's own equivalent roughness",
            "the irregularity's raw profile on the running line (no bridging: large errors, for comparison)",
        ),
    ),
)
"""Every user-facing choice among named values (front ends offer ``values``; ``wheelrail.core.noise.wheel_power``
uses ``noise_wheel_model``'s)."""


def choice(key: str) -> Choice:
    """The choice declared with ``key`` (KeyError if none is)."""
    for entry in CHOICES:
        if entry.key == key:
            return entry
    raise KeyError(key)
