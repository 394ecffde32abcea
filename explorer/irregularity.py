"""The run form's Irregularity folder and what its fields ask for (no viser in :func:`read_irregularities`).

Its fields are the discrete irregularities' inputs as :mod:`wheelrail.core.inputs.irregular` declares them (one
text field each, labelled with the key in words and the declared unit, hinted with the declared help), the flat's
shape and the choice ``irregularity_input`` of :data:`wheelrail.core.inputs.declared.CHOICES`. An empty field is
not given; an irregularity is one whose inputs are given (core's rule, ``irregularities_from_values``).
"""

from __future__ import annotations

from wheelrail.core.errors import Blame, Name, WheelrailError
from wheelrail.core.inputs.declared import choice
from wheelrail.core.inputs.irregular import FLAT_SHAPE_HELP, IRREGULARITY_INPUTS, irregularities_from_values
from wheelrail.core.irregularities.shapes import FLAT_SHAPES

__all__ = [
    "IRREGULARITY_NAMES",
    "IrregularityFolder",
    "irregularity_label",
    "read_irregularities",
    "session_irregularity",
]


def irregularity_label(key: str) -> str:
    """A declared irregularity input's field label without its unit: its key in words ("Flat length")."""
    return key.replace("_", " ").capitalize()


IRREGULARITY_NAMES: dict[str, Name] = {
    **{e.key: Name(irregularity_label(e.key), e.shown.name, e.shown.scale) for e in IRREGULARITY_INPUTS},
    "flat_shape": Name("Flat shape"),
    "irregularity_input": Name(choice("irregularity_input").label),
}
"""What the page calls each irregularity input an error can name: its field's label and unit."""


def _number(text: str, key: str) -> float:
    try:
        value = float(text.replace(",", "."))
    except ValueError:
        value = float("nan")
    if value != value or value in (float("inf"), float("-inf")):
        raise WheelrailError("not a number", Blame(key, text))
    return value


def read_irregularities(
    typed: dict[str, str], flat_shape: str = FLAT_SHAPES[0], irregularity_input: str | None = None
) -> tuple[tuple, str]:
    """The irregularities the folder's fields ask for and the Hertz models' input, or one WheelrailError.

    Parameters
    ----------
    typed : dict
        A declared irregularity input's key (``"flat_length"``) -> its field's text in the field's unit; empty or
        absent: not given.
    flat_shape : str
        One of ``wheelrail.core.irregularities.shapes.FLAT_SHAPES``.
    irregularity_input : str, optional
        One of the choice ``irregularity_input``'s values; default its default.

    Returns
    -------
    tuple
        ``(irregularities, irregularity_input)``: core's ``WheelFlat``, ``RailJoint``, ``DippedWeld``, ``Squat``
        (SI), checked alone (a run checks them against itself), and the choice.
    """
    entry = choice("irregularity_input")
    chosen = entry.check(entry.default if irregularity_input is None else irregularity_input)
    if flat_shape not in FLAT_SHAPES:
        raise WheelrailError(f"must be one of {', '.join(FLAT_SHAPES)}", Blame("flat_shape", flat_shape))
    values = {}
    for item in IRREGULARITY_INPUTS:
        text = str(typed.get(item.key, "") or "").strip()
        if text:
            values[item.key] = _number(text, item.key) * item.shown.si
    flat_given = any(values.get(e.key) is not None for e in IRREGULARITY_INPUTS if e.kind == "flat")
    items = irregularities_from_values(values, flat_shape if flat_given else None)
    if items:
        from wheelrail.core.irregularities.shapes import checked_items

        items = checked_items(items)
    return items, chosen


SESSION_CHOICES = ("flat_shape", "irregularity_input")  # a session's irregularity besides the inputs' keys


def session_irregularity(value) -> dict[str, str]:
    """A session document's ``irregularity`` (the folder as typed: input key -> text, ``flat_shape``,
    ``irregularity_input``) checked for its keys and text, or one WheelrailError; absent (None): empty."""
    if value is None:
        return {}
    known = {e.key for e in IRREGULARITY_INPUTS} | set(SESSION_CHOICES)
    if not isinstance(value, dict) or not all(isinstance(text, str) for text in value.values()):
        raise WheelrailError("session file: the irregularity must be text as the page's fields hold it")
    unknown = sorted(set(value) - known)
    if unknown:
        raise WheelrailError(f"session file: unknown irregularity input(s) {', '.join(unknown)}")
    return dict(value)


def session_read(folder: dict[str, str]) -> tuple[tuple, str]:
    """The irregularities and input a session's checked ``irregularity`` (:func:`session_irregularity`) asks for."""
    chosen = folder.get("irregularity_input", choice("irregularity_input").default)
    return read_irregularities(folder, folder.get("flat_shape", FLAT_SHAPES[0]), chosen)


class IrregularityFolder:
    """The Irregularity folder of the run form (folded): a text field per declared irregularity input, the flat's
    shape and the Hertz models' irregularity input. ``handles`` are every control (the form refreshes on each)."""

    def __init__(self, gui) -> None:
        with gui.add_folder("Irregularity", expand_by_default=False):
            self.fields = {}
            for entry in IRREGULARITY_INPUTS:
                unit = f" ({entry.shown.name})" if entry.shown.name else ""
                needed = "; needed for one" if entry.required else ""
                self.fields[entry.key] = gui.add_text(
                    f"{irregularity_label(entry.key)}{unit}", "", hint=f"{entry.help[0].upper()}{entry.help[1:]}"
                    f"{needed}; empty: none"
                )  # fmt: skip
            self.shape = gui.add_dropdown(
                "Flat shape", FLAT_SHAPES, initial_value=FLAT_SHAPES[0], hint=f"{FLAT_SHAPE_HELP[0].upper()}"
                f"{FLAT_SHAPE_HELP[1:]}"
            )  # fmt: skip
            entry = choice("irregularity_input")
            self.input = gui.add_dropdown(
                entry.label, entry.values, initial_value=entry.default, hint=entry.help_text()
            )

    @property
    def handles(self) -> tuple:
        """Every control of the folder."""
        return (*self.fields.values(), self.shape, self.input)

    def typed(self) -> dict[str, str]:
        """The fields as typed, by key, for :func:`read_irregularities`."""
        return {key: handle.value for key, handle in self.fields.items()}

    def session(self) -> dict[str, str] | None:
        """The folder as a session saves it (fields given, the choices), or None when it is as a new page has it."""
        typed = {key: text for key, text in self.typed().items() if str(text).strip()}
        entry = choice("irregularity_input")
        if not typed and self.shape.value == FLAT_SHAPES[0] and self.input.value == entry.default:
            return None
        return {**typed, "flat_shape": self.shape.value, "irregularity_input": self.input.value}

    def show_session(self, folder: dict[str, str]) -> None:
        """Set the folder from a session's checked ``irregularity`` (:func:`session_irregularity`)."""
        for key, handle in self.fields.items():
            handle.value = folder.get(key, "")
        self.shape.value = folder.get("flat_shape", FLAT_SHAPES[0])
        self.input.value = folder.get("irregularity_input", choice("irregularity_input").default)

    def read(self) -> tuple[tuple, str]:
        """The irregularities and input the folder asks for (:func:`read_irregularities`)."""
        return read_irregularities(self.typed(), self.shape.value, self.input.value)
