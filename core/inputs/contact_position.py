"""The contact's lateral position, an input of the noise chain: where the contact sits across the railhead and on
the wheel's tread.

The interaction is vertical (the contact carries no lateral force) and does not depend on it; the noise chain does:
a vertical force off the rail's centreline twists the rail and so moves the railhead laterally
(:mod:`wheelrail.core.noise.components`, the ``rail_lateral`` component), and a radial force off the wheel's
nominal rolling circle drives the wheel's axial modes through their radial displacement there
(:func:`wheelrail.core.modal_wheel.receptance.tread_shapes`). :data:`CONTACT_POSITION_INPUTS` declares each number
once (key, field, unit, label, help): the command line's options and the names its errors give derive from it. Both
are 0 by default, the chain of a centred contact.

Signs: positive towards the field side (away from the track's centre) for both: across the railhead from its
centreline, along the wheel's axis from the nominal rolling circle (the modal wheel's z, the flange on the other
side).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from wheelrail.core.errors import Name
from wheelrail.core.inputs.declared import MM, OptionNamed, Unit
from wheelrail.core.inputs.ranges import ACCEPTED

__all__ = ["CONTACT_POSITION_INPUTS", "ContactPosition", "PositionInput", "contact_position_cli_names"]


@dataclass(frozen=True)
class ContactPosition:
    """The contact's lateral position (module docstring), m, SI.

    Attributes
    ----------
    rail_offset : float
        Across the railhead from its centreline, m (``contact_offset_rail``: -30 to 30 mm).
    wheel_offset : float
        Along the wheel's axis from the nominal rolling circle, m (``contact_offset_wheel``: -40 to 40 mm; the modal
        wheel's own profile may hold it nearer: on its tread, 5 mm from its edges and the flange).

    Raises
    ------
    WheelrailError
        Keyed by the input, for a value that is not a number within its range.

    Examples
    --------
    >>> from wheelrail.core.inputs.contact_position import ContactPosition
    >>> ContactPosition(rail_offset=0.01).wheel_offset
    0.0
    """

    rail_offset: float = 0.0
    wheel_offset: float = 0.0

    def __post_init__(self) -> None:
        for entry in CONTACT_POSITION_INPUTS:
            value = ACCEPTED[entry.key].check(getattr(self, entry.field), f"ContactPosition.{entry.field}")
            object.__setattr__(self, entry.field, value)

    @property
    def centred(self) -> bool:
        """Whether both offsets are 0 (the chain of a centred contact)."""
        return self.rail_offset == 0.0 and self.wheel_offset == 0.0

    def to_dict(self) -> dict:
        """The record results keep: ``{"rail_offset_m": ..., "wheel_offset_m": ...}``."""
        return {f"{item.name}_m": getattr(self, item.name) for item in fields(self)}

    def words(self) -> str:
        """In words: "contact 10 mm off the rail's centreline, -5 mm off the wheel's rolling circle"."""
        return (
            f"contact {self.rail_offset * 1e3:g} mm off the rail's centreline, "
            f"{self.wheel_offset * 1e3:g} mm off the wheel's rolling circle"
        )


@dataclass(frozen=True)
class PositionInput(OptionNamed):
    """One number of the contact's position a user can set, declared once: its stable ``key`` (the ``parameter``
    of its errors and of its range in ``ACCEPTED``), the :class:`ContactPosition` ``field``, the unit front ends
    show it in, a page ``label`` and a sentence of help."""

    key: str
    field: str
    shown: Unit
    label: str
    help: str

    def shown_default(self) -> float:
        """The default (:class:`ContactPosition`'s) in the shown unit."""
        return getattr(ContactPosition(), self.field) * self.shown.scale

    def accepted_text(self) -> str:
        """The range in the shown unit: "-30 to 30 mm"."""
        low, high = ACCEPTED[self.key].in_unit(self.shown.scale)
        return f"{low:g} to {high:g} {self.shown.name}"


CONTACT_POSITION_INPUTS: tuple[PositionInput, ...] = (
    PositionInput(
        "contact_offset_rail",
        "rail_offset",
        MM,
        "Contact offset on the railhead",
        "the contact's lateral position across the railhead from its centreline (+ towards the field side): a "
        "vertical force off the centreline twists the rail, whose lateral vibration then radiates",
    ),
    PositionInput(
        "contact_offset_wheel",
        "wheel_offset",
        MM,
        "Contact offset on the wheel tread",
        "the contact's axial position on the wheel's tread from the nominal rolling circle (+ towards the field "
        "side): the modal wheel's radial force there drives its axial modes",
    ),
)
"""The contact position's inputs, in the order front ends show them."""


def contact_position_cli_names() -> dict[str, Name]:
    """How the command line names each of these inputs in an error (its option, mm, values bare after it)."""
    return {e.key: Name(e.option, e.shown.name, e.shown.scale, True) for e in CONTACT_POSITION_INPUTS}
