"""The discrete irregularities as data: frozen keyword-only dataclasses in SI units, each validated on construction.

A wheel flat (:class:`WheelFlat`), a rail joint (:class:`RailJoint`), a dipped weld (:class:`DippedWeld`) and a
squat or local defect (:class:`Squat`). Each checks its own numbers in ``__post_init__`` (finite, positive where a
size must be, a known shape); what depends on the run (the wheel's radius, the run's extent, the sleeper bay) is
checked by :func:`check_irregularities`. Every refusal is one :class:`WheelrailError` keyed by the input
(``"flat_length"``, ``"joint_gap"``, ...).

Heights follow the combined roughness of the paper's eq. (14), r = r_W - r_R with z pointing down into the rail:
positive where material pushes wheel and rail together (a bump on either), negative for a flat or a dip.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.checks import keyed_real

__all__ = [
    "FLAT_SHAPES",
    "RAILHEAD_HALF_WIDTH",
    "DippedWeld",
    "Irregularity",
    "RailJoint",
    "Squat",
    "WheelFlat",
    "as_record",
    "check_irregularities",
    "checked_items",
    "contact_reach",
    "extent",
    "flat_depth",
    "flat_meetings",
    "from_record",
    "words",
]

FLAT_SHAPES = ("rounded", "new")  # a wheel flat's shapes, the default (WheelFlat.shape) first
# Half the head width of a UIC60 rail (72 mm): a squat's centre must lie on the railhead
RAILHEAD_HALF_WIDTH = 0.036
# A new flat's depth given apart from its length must match the chord's sagitta to this relative tolerance
_CHORD_TOLERANCE = 0.01


def _number(owner, name: str, key: str, unit: str, *, sign: str = "positive") -> None:
    """One field: a finite real number of the given sign ("positive", "nonnegative", "any"), else one error keyed
    ``key`` (:func:`wheelrail.core.inputs.checks.keyed_real`)."""
    keyed_real(key, getattr(owner, name), unit, argument=f"{type(owner).__name__}.{name}", sign=sign)


@dataclass(frozen=True, kw_only=True)
class WheelFlat:
    """A wheel flat: a piece of the tread worn flat, met by the rail once per revolution.

    Across the whole running band (every line y).

    Attributes
    ----------
    length : float
        L, the flat's length along the tread, m.
    depth : float or None
        D, its depth at the centre, m. None: for a rounded flat D = L^2 / (16 R), the depth of the new flat of
        length L / sqrt(2) that wore into it (Wu & Thompson, JSV 251 (2002)); for a new flat the sagitta of the
        chord, R - sqrt(R^2 - L^2 / 4) (about L^2 / (8 R)). R is the run's wheel radius (:func:`flat_depth`).
    shape : str
        "rounded": radius deviation -D/2 (1 + cos(2 pi s / L)) for ``|s| < L/2`` (s along the tread from the flat's
        centre); "new": the chord (a straight cut; its depth is the sagitta, a given depth must match it to 1 %).
    position : float
        x_F, where along the run the flat's centre first meets the rail, m; it meets it again every 2 pi R
        (:func:`flat_meetings`).

    Raises
    ------
    WheelrailError
        Keyed by the input ("flat_length", "flat_depth", "flat_shape", "flat_position") for a value that is not
        a finite number of its sign or an unknown shape.
    """

    length: float
    depth: float | None = None
    shape: str = FLAT_SHAPES[0]
    position: float = 0.0

    def __post_init__(self) -> None:
        _number(self, "length", "flat_length", "m")
        if self.depth is not None:
            _number(self, "depth", "flat_depth", "m")
        if self.shape not in FLAT_SHAPES:
            raise WheelrailError(
                f"is not a flat shape; accepted {' or '.join(FLAT_SHAPES)}",
                Blame("flat_shape", value=str(self.shape), argument="WheelFlat.shape"),
            )
        _number(self, "position", "flat_position", "m", sign="any")


@dataclass(frozen=True, kw_only=True)
class RailJoint:
    """A rail joint: a gap between two rail ends, a height step across it and the ends dipped towards it.

    Attributes
    ----------
    position : float
        x_J, the gap's centre along the run, m.
    gap : float
        g, the gap's width, m (> 0). The wheel bridges it: the rail's top in the gap lies deeper than the wheel
        can reach (:mod:`wheelrail.core.irregularities.surface`).
    step : float
        h, the height of the rail after the joint (in the running direction) above the rail before it, m: > 0 a
        step up, < 0 a step down, 0 none. It holds for the rest of the run (the rails are misaligned).
    dip_angle : float
        alpha, the angle each rail end slopes down towards the gap, rad (0: a plain joint).
    dip_length : float
        How far from the gap each end's slope runs, m: the ends lie alpha * dip_length below the rail there.

    Raises
    ------
    WheelrailError
        Keyed by the input ("joint_gap", "joint_step", ...) for a value that is not a finite number of its sign,
        or a dip angle of 0.1 rad or more.
    """

    position: float
    gap: float = 0.01
    step: float = 0.0
    dip_angle: float = 0.0
    dip_length: float = 0.5

    def __post_init__(self) -> None:
        _number(self, "position", "joint_position", "m", sign="any")
        _number(self, "gap", "joint_gap", "m")
        _number(self, "step", "joint_step", "m", sign="any")
        _number(self, "dip_angle", "joint_dip_angle", "rad", sign="nonnegative")
        _number(self, "dip_length", "joint_dip_length", "m")
        if self.dip_angle >= 0.1:
            raise WheelrailError(
                None,
                Blame(
                    "joint_dip_angle",
                    value=self.dip_angle,
                    unit="rad",
                    minimum=0.0,
                    maximum=0.1,
                    argument="RailJoint.dip_angle",
                    reason="a dip of a few milliradians is a badly dipped joint",
                ),
            )


@dataclass(frozen=True, kw_only=True)
class DippedWeld:
    """A dipped weld: a cosine dip -D/2 (1 + cos(2 pi (x - x_W) / L)) for ``|x - x_W| < L/2``, across the railhead.

    Attributes
    ----------
    position : float
        x_W, the dip's centre along the run, m.
    length : float
        L, the dip's length, m.
    depth : float
        D, its depth at the centre, m.

    Raises
    ------
    WheelrailError
        Keyed by the input ("weld_position", "weld_length", "weld_depth") for a value that is not a finite
        number of its sign.
    """

    position: float
    length: float
    depth: float

    def __post_init__(self) -> None:
        _number(self, "position", "weld_position", "m", sign="any")
        _number(self, "length", "weld_length", "m")
        _number(self, "depth", "weld_depth", "m")


@dataclass(frozen=True, kw_only=True)
class Squat:
    """A squat or local defect: a dip of finite width on the railhead, D c(x - x_S, L) c(y - y_S, W) deep, with
    c(s, L) = (1 + cos(2 pi s / L)) / 2 for ``|s| < L/2`` (else 0): narrower than the contact patch, only the 3D
    model sees its width.

    Attributes
    ----------
    position : float
        x_S, its centre along the run, m.
    length : float
        L, its length along the rail, m.
    width : float
        W, its width across the railhead, m.
    depth : float
        D, its depth at the centre, m.
    lateral_position : float
        y_S, its centre across the railhead from the running line (y = 0), m; at most
        ``RAILHEAD_HALF_WIDTH`` (36 mm, a UIC60 head) either side.

    Raises
    ------
    WheelrailError
        Keyed by the input ("squat_length", "squat_width", ...) for a value that is not a finite number of its
        sign, or a centre off the railhead.
    """

    position: float
    length: float
    width: float
    depth: float
    lateral_position: float = 0.0

    def __post_init__(self) -> None:
        _number(self, "position", "squat_position", "m", sign="any")
        _number(self, "length", "squat_length", "m")
        _number(self, "width", "squat_width", "m")
        _number(self, "depth", "squat_depth", "m")
        _number(self, "lateral_position", "squat_lateral_position", "m", sign="any")
        if abs(self.lateral_position) > RAILHEAD_HALF_WIDTH:
            raise WheelrailError(
                None,
                Blame(
                    "squat_lateral_position",
                    value=self.lateral_position,
                    unit="m",
                    minimum=-RAILHEAD_HALF_WIDTH,
                    maximum=RAILHEAD_HALF_WIDTH,
                    argument="Squat.lateral_position",
                    reason="on the railhead",
                ),
            )


Irregularity = WheelFlat | RailJoint | DippedWeld | Squat


_KINDS = {"flat": WheelFlat, "joint": RailJoint, "weld": DippedWeld, "squat": Squat}


def checked_items(irregularities, argument: str = "irregularities") -> tuple[Irregularity, ...]:
    """The irregularities as a tuple, each one of the four kinds, else one WheelrailError (``argument``: how the
    caller names them)."""
    if not isinstance(irregularities, tuple | list):
        raise WheelrailError(
            f"{argument} must be a tuple of WheelFlat, RailJoint, DippedWeld or Squat, got "
            f"{type(irregularities).__name__}"
        )
    items = tuple(irregularities)
    for item in items:
        if not isinstance(item, WheelFlat | RailJoint | DippedWeld | Squat):
            raise WheelrailError(
                f"an irregularity must be a WheelFlat, RailJoint, DippedWeld or Squat, got {type(item).__name__}"
            )
    return items


def as_record(item: Irregularity) -> dict:
    """A plain dict of an irregularity, SI, with its ``kind`` ("flat", "joint", "weld", "squat"): what a run's
    header and cache keys hold (:func:`from_record` reads it back)."""
    kind = next(name for name, cls in _KINDS.items() if isinstance(item, cls))
    return {"kind": kind, **{name: getattr(item, name) for name in item.__dataclass_fields__}}


def from_record(values) -> Irregularity:
    """The irregularity of :func:`as_record`'s dict; a damaged one is one WheelrailError."""
    if not isinstance(values, dict) or values.get("kind") not in _KINDS:
        raise WheelrailError(f"an irregularity's record needs a kind ({', '.join(_KINDS)}), got {values!r:.80}")
    cls = _KINDS[values["kind"]]
    fields = {name: value for name, value in values.items() if name != "kind"}
    unknown = sorted(set(fields) - set(cls.__dataclass_fields__))
    if unknown:
        raise WheelrailError(f"an irregularity's record ({values['kind']}) has unknown field(s) {', '.join(unknown)}")
    return cls(**fields)


def words(item: Irregularity) -> str:
    """One irregularity in words, mm and m: "flat 50 mm rounded at x = 0.9 m" (a result's description)."""
    if isinstance(item, WheelFlat):
        depth = "" if item.depth is None else f" {item.depth * 1e3:g} mm deep"
        return f"flat {item.length * 1e3:g} mm {item.shape}{depth} at x = {item.position:g} m"
    if isinstance(item, RailJoint):
        return (
            f"joint gap {item.gap * 1e3:g} mm, step {item.step * 1e3:g} mm, dip {item.dip_angle * 1e3:g} mrad at "
            f"x = {item.position:g} m"
        )
    if isinstance(item, DippedWeld):
        return f"weld {item.length * 1e3:g} mm, {item.depth * 1e3:g} mm deep at x = {item.position:g} m"
    return (
        f"squat {item.length * 1e3:g} x {item.width * 1e3:g} mm, {item.depth * 1e3:g} mm deep at x = "
        f"{item.position:g} m, y = {item.lateral_position * 1e3:g} mm"
    )


def contact_reach(item: Irregularity, wheel_radius: float) -> float:
    """How far from the wheel's centre along the rail the irregularity can move the contact, m: R times its
    steepest slope (the wheel touches a slope r' at R r' from its centre), at most its half-length; a new flat's
    edges (L/2), a joint's gap edges (g/2), its dip (R alpha) and its step climbed from sqrt(2 R |h|) ahead."""
    if isinstance(item, RailJoint):
        return max(0.5 * item.gap, wheel_radius * item.dip_angle, math.sqrt(2.0 * wheel_radius * abs(item.step)))
    if isinstance(item, WheelFlat) and item.shape == "new":
        return 0.5 * item.length
    depth = flat_depth(item, wheel_radius) if isinstance(item, WheelFlat) else item.depth
    return min(0.5 * item.length, wheel_radius * math.pi * depth / item.length)


def flat_depth(flat: WheelFlat, wheel_radius: float) -> float:
    """The flat's depth D on a wheel of radius R (m): as given, or its default (:class:`WheelFlat`)."""
    if flat.shape == "new":
        return wheel_radius - math.sqrt(wheel_radius**2 - 0.25 * flat.length**2)
    return flat.length**2 / (16.0 * wheel_radius) if flat.depth is None else float(flat.depth)


def flat_meetings(flat: WheelFlat, wheel_radius: float, run_end: float) -> list[float]:
    """Where the flat's centre meets the rail up to ``run_end`` (m): x_F + k 2 pi R for k = 0, 1, ..."""
    circumference = 2.0 * math.pi * wheel_radius
    count = max(0, math.floor((run_end + 0.5 * flat.length - flat.position) / circumference) + 1)
    return [flat.position + k * circumference for k in range(count)]


def extent(item: Irregularity) -> tuple[float, float]:
    """The stretch of rail (m) the irregularity changes, for a flat its first meeting; a joint's step holds on
    after it (the stretch is the gap and the dipped ends)."""
    if isinstance(item, RailJoint):
        half = 0.5 * item.gap + (item.dip_length if item.dip_angle > 0.0 else 0.0)
        return item.position - half, item.position + half
    return item.position - 0.5 * item.length, item.position + 0.5 * item.length


def _check_flat(flat: WheelFlat, wheel_radius: float) -> None:
    if flat.length >= 2.0 * wheel_radius:
        raise WheelrailError(
            "a flat this long does not fit on the wheel",
            Blame(
                "flat_length",
                value=flat.length,
                unit="m",
                maximum=2.0 * wheel_radius,
                argument="WheelFlat.length",
                reason="a chord of the wheel, shorter than its diameter",
            ),
        )
    if flat.depth is None:
        return
    if flat.shape == "new":
        chord = flat_depth(flat, wheel_radius)
        if abs(flat.depth - chord) > _CHORD_TOLERANCE * chord:
            raise WheelrailError(
                f"a new flat this long is a chord {chord:.6g} m deep; give that depth or none",
                Blame("flat_depth", value=flat.depth, unit="m", argument="WheelFlat.depth"),
            )
    elif flat.depth >= 0.5 * flat.length:
        raise WheelrailError(
            "a flat deeper than half its length is not a flat",
            Blame("flat_depth", value=flat.depth, unit="m", maximum=0.5 * flat.length, argument="WheelFlat.depth"),
        )


def check_irregularities(
    irregularities, *, wheel_radius: float, run_start: float, run_end: float, sleeper_spacing: float
) -> tuple[Irregularity, ...]:
    """Check a set of irregularities against the run they are to be used in.

    Parameters
    ----------
    irregularities : iterable of WheelFlat, RailJoint, DippedWeld or Squat
    wheel_radius : float
        R, the wheel's rolling radius, m.
    run_start, run_end : float
        The run [x0, x1] along the rail, m.
    sleeper_spacing : float
        The sleeper bay, m: a joint's gap must be narrower.

    Returns
    -------
    tuple
        The irregularities, in the order given.

    Raises
    ------
    WheelrailError
        One line for the first one refused: a flat longer than the wheel can hold (a chord: L < 2R), a new flat's
        depth other than its chord's, a joint's gap as wide as a sleeper bay, an irregularity (a flat's first
        meeting) not wholly inside [x0, x1], or an item that is none of the four.
    """
    items = checked_items(irregularities)
    for item in items:
        kind = type(item).__name__
        key = {"WheelFlat": "flat", "RailJoint": "joint", "DippedWeld": "weld", "Squat": "squat"}[kind]
        if isinstance(item, WheelFlat):
            _check_flat(item, wheel_radius)
        if isinstance(item, RailJoint) and item.gap >= sleeper_spacing:
            raise WheelrailError(
                None,
                Blame(
                    "joint_gap",
                    value=item.gap,
                    unit="m",
                    maximum=sleeper_spacing,
                    argument="RailJoint.gap",
                    reason="narrower than a sleeper bay",
                ),
            )
        start, end = extent(item)
        if start < run_start or end > run_end:
            raise WheelrailError(
                f"reaches from {start:.6g} to {end:.6g} m, outside the run",
                Blame(
                    f"{key}_position",
                    value=item.position,
                    unit="m",
                    minimum=run_start + (item.position - start),
                    maximum=run_end - (end - item.position),
                    argument=f"{kind}.position",
                ),
            )
    return items
