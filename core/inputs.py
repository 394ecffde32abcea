"""The user-facing inputs, each declared once: key, place in ``ModelParameters``, unit, accepted range, names.

An :class:`Input` says everything a front end needs of one number a user can set: its stable ``key`` (the
``parameter`` of a :class:`~wheelrail.core.errors.WheelrailError` about it), its ``path`` in
:class:`~wheelrail.core.parameters.ModelParameters` (``"track.support.pad_stiffness"``), its SI unit and
accepted range (with the reason for it), the :class:`Unit` front ends show it in, its page label, its group
(the command-line option group and the explorer's folder) and a sentence of help. Its default is read from
the dataclass, never restated.

Everything else is derived from :data:`INPUTS`: the command line's options (``--pad-stiffness-mn-m``: the key
and the unit's token) and their help, the explorer's fields (one folder per group), the accepted ranges the
parameter classes check (:data:`wheelrail.core.accepted.ACCEPTED`), the names each front end gives an error
(:func:`cli_names`, :func:`page_names`), the case key and file names of a result, and the study's inputs.
Adding an input is one declaration here, with its range (and the dataclass field it sets).

The track's ranges hold real ballasted and slab tracks with room to spare (Thompson, *Railway Noise and
Vibration*, Elsevier 2009, section 3.6 and table 3.1: pads from about 20 MN/m, the soft baseplate
fastenings of slab track, to over 1 GN/m, stiff studded HDPE pads; half concrete sleepers of 100-160 kg,
half timber ones around 40 kg; spacings of 0.6-0.7 m; ballast of 50-200 MN/m per half sleeper). Where the
model stops holding is in :mod:`wheelrail.core.accepted`'s docstring and the documentation's limitations.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, replace

from wheelrail.core.errors import Name, WheelrailError

__all__ = [
    "GROUPS",
    "Accepted",
    "INPUTS",
    "Input",
    "MAX_SPEED_KMH",
    "MIN_SPEED_KMH",
    "ROUND_OFF",
    "Unit",
    "by_key",
    "cli_names",
    "describe",
    "describe_words",
    "inputs_of",
    "model_parameters",
    "page_names",
]

ROUND_OFF = 1e-12  # relative: a bound met after a unit conversion (km/h -> m/s) is met
# Accepted train speeds: the range over which the interaction loop is shown stable (FOH_MAX_STEP in
# parameters.py; smooth-rail speed scans in tests/physics/test_stability.py and benchmarks/speed_scan.py).
# Below MIN_SPEED_KMH steps get so long (7.2 ms at 0.5 km/h: 8 lags) that the 50 ms truncation of the
# trapezoidal weights matters and the loop chattered again at 0.5 km/h. MAX_SPEED_KMH is the reach of the
# cached track responses (``TrackNumerics.max_speed``).
MIN_SPEED_KMH = 5.0
MAX_SPEED_KMH = 400.0


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


@dataclass(frozen=True)
class Accepted:
    """One input's accepted range: ``key`` (the stable name front ends map to their own), SI ``unit``,
    ``minimum`` and ``maximum`` (SI), the ``reason`` for them; ``magnitude``: the range bounds |value| (a
    radius whose sign means concave), ``maximum`` then inf."""

    key: str
    unit: str
    minimum: float
    maximum: float
    reason: str
    magnitude: bool = False

    def check(self, value, argument: str | None = None) -> float:
        """``value`` as a float within the range, else one WheelrailError naming ``argument`` (default the key)."""
        fields = {"parameter": self.key, "value": value, "unit": self.unit, "argument": argument}
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or math.isnan(value):
            raise WheelrailError("not a number", **fields)
        number = float(value)
        size = abs(number) if self.magnitude else number
        if not self.minimum * (1 - ROUND_OFF) <= size <= self.maximum * (1 + ROUND_OFF):
            raise WheelrailError(
                None,
                minimum=self.minimum,
                maximum=None if self.magnitude else self.maximum,
                reason=self.reason,
                magnitude=self.magnitude,
                **fields,
            )
        return number

    def in_unit(self, scale: float) -> tuple[float, float]:
        """(minimum, maximum) in a front end's unit (``scale`` of it per SI unit), rounded for display."""
        return float(f"{self.minimum * scale:.6g}"), float(f"{self.maximum * scale:.6g}")


KMH = Unit("km/h", 1.0 / 3.6, "kmh")
KN = Unit("kN", 1e3, "kn")
MM = Unit("mm", 1e-3, "mm")
MN_PER_M = Unit("MN/m", 1e6, "mn-m")
KNS_PER_M = Unit("kNs/m", 1e3, "kns-m")
KG = Unit("kg", 1.0, "kg")
METRE = Unit("m", 1.0, "m")
NUMBER = Unit("", 1.0, "")

GROUPS = {"run": "Run", "geometry": "Contact geometry", "track": "Track"}
"""Input groups, in order, and their titles (the command line's option groups, the explorer's folders)."""


@dataclass(frozen=True)
class Input:
    """One user-facing input (module docstring).

    Attributes
    ----------
    key : str
        Stable name (``"pad_stiffness"``): the ``parameter`` of its errors, the key of its range.
    path : str
        Where it lives in ``ModelParameters``, dotted (``"track.support.pad_stiffness"``).
    unit : str
        Its SI unit (``"N/m"``; ``""`` for a pure number).
    shown : Unit
        The unit the command line and the explorer take it in.
    minimum, maximum : float
        Accepted range, SI (``maximum`` inf: open).
    reason : str
        Why the range is what it is (shown with a refusal).
    label : str
        The explorer's field label, without its unit ("Pad stiffness").
    group : str
        A key of :data:`GROUPS`.
    help : str
        What it is, in a few words (the option's help, the field's hint).
    magnitude : bool
        The range bounds |value| (a radius whose sign means concave).
    unset : str or None
        What an empty field or an absent option means, for inputs whose dataclass default is None or
        infinite ("the paper's R"; "a cylindrical tread"); None: the dataclass default, a number.
    stem : str
        Its short name in file names ("R", "kP"); empty: the value and unit alone ("100kmh").
    always_shown : bool
        Named in every case label and file name, even at its default (speed, preload).
    """

    key: str
    path: str
    unit: str
    shown: Unit
    minimum: float
    maximum: float
    reason: str
    label: str
    group: str
    help: str
    magnitude: bool = False
    unset: str | None = None
    stem: str = ""
    always_shown: bool = False

    @property
    def option(self) -> str:
        """The command-line option: ``--`` + the key + the unit's token (``--pad-stiffness-mn-m``)."""
        words = self.key.replace("_", "-")
        return f"--{words}-{self.shown.token}" if self.shown.token else f"--{words}"

    @property
    def dest(self) -> str:
        """The option's attribute name in argparse's namespace (``pad_stiffness_mn_m``)."""
        return self.option[2:].replace("-", "_")

    def default(self):
        """Its default, SI, read from ``ModelParameters()`` (None where the dataclass has None)."""
        from wheelrail.core.parameters import ModelParameters

        value = ModelParameters()
        for part in self.path.split("."):
            value = getattr(value, part)
        return value

    def shown_default(self) -> float | None:
        """The default in the shown unit, or None when it is not a finite number (see ``unset``)."""
        value = self.default()
        if value is None or not math.isfinite(value):
            return None
        return float(f"{value * self.shown.scale:.12g}")

    @property
    def accepted(self) -> Accepted:
        """Its accepted range as an :class:`Accepted`."""
        return Accepted(self.key, self.unit, self.minimum, self.maximum, self.reason, self.magnitude)

    def check(self, value, argument: str | None = None) -> float:
        """``value`` (SI) as a float within the range, else one WheelrailError keyed by ``key``."""
        return self.accepted.check(value, argument)

    def in_shown(self) -> tuple[float, float]:
        """(minimum, maximum) in the shown unit, rounded for display."""
        return self.accepted.in_unit(self.shown.scale)

    def accepted_text(self) -> str:
        """The range in the shown unit: "5 to 400 km/h", "at least 50 mm in magnitude"."""
        low, high = self.in_shown()
        unit = f" {self.shown.name}" if self.shown.name else ""
        if self.magnitude:
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


def _track(key, field, shown, low, high, reason, label, help_text, stem) -> Input:
    part = "rail" if field in ("loss_factor",) else "support"
    path = f"track.{part}.{field}"
    return Input(key, path, _SI[shown], shown, low, high, reason, label, "track", help_text, stem=stem)


_SI = {KMH: "m/s", KN: "N", MM: "m", MN_PER_M: "N/m", KNS_PER_M: "N s/m", KG: "kg", METRE: "m", NUMBER: ""}
_WHEEL_RADIUS = (0.1, 1.25, "a railway wheel, around the CNOSSOS-EU table's 360 to 920 mm diameters")
_PAPER_R = "the paper's R"

INPUTS: tuple[Input, ...] = (
    Input(
        "speed", "run.speed", "m/s", KMH, MIN_SPEED_KMH * KMH.si, MAX_SPEED_KMH * KMH.si,
        "where the interaction loop is shown stable and the cached track responses reach",
        "Speed", "run", "train speed", always_shown=True,
    ),
    Input(
        "preload", "contact.preload", "N", KN, 1e3, 500e3,
        "a railway wheel's static load, around the CNOSSOS-EU table's 25 to 100 kN",
        "Preload", "run", "static wheel load", always_shown=True,
    ),
    Input(
        "wheel_radius", "contact.wheel_radius", "m", MM, *_WHEEL_RADIUS,
        "Wheel radius", "geometry", "wheel rolling radius, along the rail", unset=_PAPER_R, stem="R",
    ),
    Input(
        "rail_crown_radius", "contact.rail_crown_radius", "m", MM, 0.05, 5.0,
        "a rail head, from a sharp 50 mm crown to a worn, nearly flat 5 m",
        "Rail crown radius", "geometry", "rail head (crown) radius across the rail", unset=_PAPER_R, stem="crown",
    ),
    Input(
        "wheel_transverse_radius", "contact.wheel_transverse_radius", "m", MM, 0.05, math.inf,
        "inf: a cylindrical or conical tread; negative: a concave, worn one",
        "Wheel tread radius across", "geometry", "wheel tread radius across the rail (negative: concave, worn)",
        magnitude=True, unset="a cylindrical tread", stem="tread",
    ),
    _track(
        "pad_stiffness", "pad_stiffness", MN_PER_M, 10e6, 3000e6,
        "from the softest baseplate fastenings of slab track to stiff studded pads",
        "Pad stiffness", "rail pad stiffness, per support", "kP",
    ),
    _track(
        "pad_damping", "pad_damping", KNS_PER_M, 1e3, 500e3,
        "a pad's loss factor of about 0.05 to 0.5 over the accepted stiffnesses at the rail-on-pad resonance",
        "Pad damping", "rail pad viscous damping, per support", "cP",
    ),
    _track(
        "sleeper_mass", "sleeper_mass", KG, 20.0, 300.0,
        "half a sleeper: from a light timber sleeper to a heavy concrete one",
        "Sleeper mass", "half-sleeper mass (one rail's share, as the paper)", "mS",
    ),
    _track(
        "sleeper_spacing", "sleeper_spacing", METRE, 0.5, 0.9,
        "the sleeper spacings of ballasted and slab track",
        "Sleeper spacing", "distance between supports", "LS",
    ),
    _track(
        "ballast_stiffness", "ballast_stiffness", MN_PER_M, 10e6, 3000e6,
        "per half sleeper: from soft subgrade with under-sleeper pads to a slab's rigid support",
        "Ballast stiffness", "ballast stiffness under a half sleeper", "kB",
    ),
    _track(
        "ballast_damping", "ballast_damping", KNS_PER_M, 1e3, 1000e3,
        "per half sleeper, around the paper's 165 kNs/m",
        "Ballast damping", "ballast viscous damping under a half sleeper", "cB",
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


def model_parameters(values: dict, base=None):
    """``ModelParameters`` with the inputs ``values`` (key -> SI value; None: the default) set on ``base``
    (default: the paper's). Each value is checked against its declared range first (one WheelrailError keyed
    by the input), then by the dataclasses (the rules that relate inputs: the patch, the tread)."""
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


def describe(params, *groups: str) -> dict[str, dict[str, float | None]]:
    """The inputs of ``params`` by group (all groups when none is named), SI, for every result's record:
    ``{"track": {"pad_stiffness": 1.2e8, ...}, ...}`` (an infinite tread radius as None, as JSON has it)."""
    found: dict[str, dict[str, float | None]] = {}
    for entry in inputs_of(*groups):
        value = params
        for part in entry.path.split("."):
            value = getattr(value, part)
        if entry.path.startswith("contact.") and value is None:  # an unset radius: the one in use
            value = params.contact.radius
        number = None if value is None or not math.isfinite(value) else float(value)
        found.setdefault(entry.group, {})[entry.key] = number
    return found


def describe_words(params, group: str) -> str:
    """The inputs of one group of ``params`` as a line of text: "pad stiffness 120 MN/m, pad damping 16 kNs/m, ..."
    (an unset radius as the words of its ``unset``)."""
    values = describe(params, group)[group]
    parts = []
    for key, value in values.items():
        entry = by_key(key)
        parts.append(entry.unset if value is None else entry.words(value))
    return ", ".join(parts)
