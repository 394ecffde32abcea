"""A run's discrete irregularities as users give them and ``RunParameters`` holds them.

:data:`IRREGULARITY_INPUTS` declares each number once (key, kind, field, unit, help), as ``declared.INPUTS`` does
the track's: the command line's options and the names its errors give derive from it
(:func:`irregularity_cli_names`, :func:`irregularities_from_values`). How ``RunParameters`` checks and records
them: ``run_records``.

The irregularities' package (``wheelrail.core.irregularities``, compiled code) is imported only for a run that has
some, so that parameters stay cheap to build.
"""

from __future__ import annotations

from dataclasses import dataclass

from wheelrail.core.errors import Blame, Name, WheelrailError
from wheelrail.core.inputs.declared import METRE, MM, OptionNamed, Unit

__all__ = [
    "FLAT_SHAPE_HELP",
    "IRREGULARITY_INPUTS",
    "IrregularityInput",
    "irregularities_from_values",
    "irregularity_cli_names",
]


@dataclass(frozen=True)
class IrregularityInput(OptionNamed):
    """One number of a discrete irregularity a user can set, declared once: its stable ``key`` (the ``parameter``
    of its errors: ``"flat_length"``), the irregularity's ``kind`` ("flat", "joint", "weld", "squat") and
    ``field`` (of ``WheelFlat``, ``RailJoint``, ``DippedWeld``, ``Squat``), the unit front ends show it in, a
    sentence of help and whether an irregularity of its kind needs it."""

    key: str
    kind: str
    field: str
    shown: Unit
    help: str
    required: bool = False


MRAD = Unit("mrad", 1e-3, "mrad")
_SI_UNITS = {"mm": "m", "m": "m", "mrad": "rad"}  # the SI unit of each shown unit of these inputs

IRREGULARITY_INPUTS: tuple[IrregularityInput, ...] = (
    IrregularityInput("flat_length", "flat", "length", MM, "wheel flat: length L along the tread", True),
    IrregularityInput(
        "flat_depth", "flat", "depth", MM,
        "wheel flat: depth D at its centre (default: a rounded flat's L^2 / (16 R), the depth of the new flat of "
        "length L / sqrt(2) that wore into it; a new flat's chord sagitta)",
    ),
    IrregularityInput(
        "flat_position", "flat", "position", METRE,
        "wheel flat: where along the run its centre first meets the rail (it comes back every 2 pi R)", True,
    ),
    IrregularityInput("joint_position", "joint", "position", METRE, "rail joint: the gap's centre along the run", True),
    IrregularityInput("joint_gap", "joint", "gap", MM, "rail joint: gap width (default 10 mm)"),
    IrregularityInput(
        "joint_step", "joint", "step", MM, "rail joint: height of the rail after the gap over the one before (+ up)"
    ),
    IrregularityInput("joint_dip_angle", "joint", "dip_angle", MRAD, "rail joint: dip angle of each rail end"),
    IrregularityInput("joint_dip_length", "joint", "dip_length", METRE, "rail joint: length of each end's dip"),
    IrregularityInput("weld_position", "weld", "position", METRE, "dipped weld: centre along the run", True),
    IrregularityInput("weld_length", "weld", "length", MM, "dipped weld: length of the cosine dip", True),
    IrregularityInput("weld_depth", "weld", "depth", MM, "dipped weld: depth at its centre", True),
    IrregularityInput("squat_position", "squat", "position", METRE, "squat: centre along the run", True),
    IrregularityInput("squat_length", "squat", "length", MM, "squat: length along the rail", True),
    IrregularityInput("squat_width", "squat", "width", MM, "squat: width across the railhead", True),
    IrregularityInput("squat_depth", "squat", "depth", MM, "squat: depth at its centre", True),
    IrregularityInput(
        "squat_lateral_position", "squat", "lateral_position", MM, "squat: centre across the railhead from the line"
    ),
)  # fmt: skip
"""Every number of a discrete irregularity a user can set, in the order front ends show them (with the choices
``flat_shape`` and ``irregularity_input``)."""

FLAT_SHAPE_HELP = "wheel flat shape: rounded (a worn flat, -D/2 (1 + cos(2 pi s / L))) or new (the chord)"


def irregularity_cli_names() -> dict[str, Name]:
    """How the command line names each irregularity input (its option and unit), for its errors."""
    names = {e.key: Name(e.option, e.shown.name, e.shown.scale, True) for e in IRREGULARITY_INPUTS}
    return {**names, "flat_shape": Name("--flat-shape")}


def irregularities_from_values(values: dict, flat_shape: str | None = None) -> tuple:
    """The irregularities of the inputs given: ``values`` maps an input's key to its value in SI (inputs not given
    left out); ``flat_shape`` the flat's shape if given. One irregularity of each kind any of whose inputs is
    given; a kind without all its required inputs is one WheelrailError naming the first missing."""
    from wheelrail.core.irregularities.shapes import DippedWeld, RailJoint, Squat, WheelFlat

    classes = {"flat": WheelFlat, "joint": RailJoint, "weld": DippedWeld, "squat": Squat}
    items = []
    for kind, cls in classes.items():
        entries = [e for e in IRREGULARITY_INPUTS if e.kind == kind]
        given = {e.field: values[e.key] for e in entries if values.get(e.key) is not None}
        if kind == "flat" and flat_shape is not None:
            given["shape"] = flat_shape
        if not given:
            continue
        missing = [e for e in entries if e.required and e.field not in given]
        if missing:  # blamed on an input the user gave (the one to complete), the missing one named in words
            first = next((e for e in entries if values.get(e.key) is not None), None)  # None: only its shape given
            blame = (
                Blame(missing[0].key, value="not given")
                if first is None
                else Blame(first.key, value=values[first.key], unit=_SI_UNITS[first.shown.name])
            )
            raise WheelrailError(f"a {kind} needs its {missing[0].field.replace('_', ' ')} as well", blame)
        items.append(cls(**given))
    return tuple(items)
