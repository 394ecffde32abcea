"""The colours of the figures: one palette for the contact models and the noise components, drawn together.

Every front end (the explorer's plots and their PNGs, ``wheelrail track/wheel --plot``, the study figures) takes
its model colours from here, and each noise component's entry (:mod:`wheelrail.core.noise.components`: the rail
orange, its lateral vibration Tol's indigo, the sleeper sky blue, the wheel Tol's wine) takes its colour from
here, so a model is the same colour everywhere and no component shares a near colour with a model it is drawn
beside (the Noise tab draws the shown model's components with every model's total).

Source: the eight colours of Okabe & Ito, *Color Universal Design* (J*FLY, 2008), as printed by B. Wong, "Points
of view: Color blindness", Nature Methods 8, 441 (2011), chosen to stay apart under the common colour-vision
deficiencies. Their yellow (#F0E442) has a contrast of 1.3:1 on the white plot background, too faint for a thin
line; the wheel takes Paul Tol's "wine" (#882255) of his colour-blind safe "muted" scheme instead (P. Tol,
*Colour Schemes*, SRON/EPS/TN/09-002, 2021). The pairwise distances in CIELAB under normal vision and under
simulated deuteranopia and protanopia (Machado, Oliveira & Fernandes, IEEE TVCG 15(6), 2009, severity 1) are
checked in ``tests/unit/test_palette.py``.

Curves of another kind drawn with them keep their own line style (``DOTTED`` references: CNOSSOS-EU, the
analytic filters, the ISO limits; ``DASHED``: another configuration overlaid), so a reference may share a colour's
neighbourhood with a solid curve.
"""

from __future__ import annotations

__all__ = [
    "CNOSSOS_COLOURS",
    "MODEL_COLOURS",
    "OKABE_ITO",
    "TOL_INDIGO",
    "TOL_WINE",
    "TOTAL_COLOUR",
    "WHEEL_SURFACE_COLOURS",
    "model_colour",
]

OKABE_ITO = {
    "black": "#000000",
    "orange": "#E69F00",
    "sky blue": "#56B4E9",
    "bluish green": "#009E73",
    "yellow": "#F0E442",
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "reddish purple": "#CC79A7",
}
"""Okabe & Ito's colour-universal set, sRGB hex (module docstring)."""

TOL_WINE = "#882255"
"""Paul Tol's "wine" of the muted scheme (module docstring)."""

TOL_INDIGO = "#332288"
"""Paul Tol's "indigo" of the muted scheme: the rail's lateral vibration (apart from every component and model)."""

MODEL_COLOURS = {
    "3d": OKABE_ITO["blue"],
    "2d": OKABE_ITO["black"],  # the paper's Fig. 10 draws the 2D model black
    "hertz": OKABE_ITO["vermillion"],
    "hertz-winkler": OKABE_ITO["reddish purple"],
    "hertz-average": OKABE_ITO["bluish green"],
}
"""One colour per built-in contact model (its total in the noise figures, its spectrum and force elsewhere)."""

PLUG_IN_COLOURS = ("#777777", "#AA7700", "#4477AA", "#BB5566")
"""Colours of models registered by plug-ins, in registry order after the built-in ones (greys and muted tones:
the built-in models keep the distinct colours; a plug-in's curve is told by its legend)."""

TOTAL_COLOUR = OKABE_ITO["black"]
"""The total of parts drawn with its parts (the Wheel tab's sound power: total, axial and radial surfaces); drawn
last, so on top of them."""

WHEEL_SURFACE_COLOURS = {"axial surfaces": OKABE_ITO["blue"], "radial surfaces": OKABE_ITO["vermillion"]}
"""The wheel's sound power by radiating surface (axially facing: web, rim sides, hub; radially facing: tread)."""

CNOSSOS_COLOURS = {"track": "#7F7F7F", "vehicle": "#8C6D31", "total": OKABE_ITO["black"]}
"""CNOSSOS-EU's source terms beside a run's noise, drawn dotted (grey, brown, black: apart from each other)."""


def model_colour(model: str, registered: tuple[str, ...] = ()) -> str:
    """The colour of a contact model: its own for a built-in one, else a plug-in colour by its place among the
    ``registered`` models that are not built in (the last plug-in colour for a model not registered)."""
    if model in MODEL_COLOURS:
        return MODEL_COLOURS[model]
    others = [name for name in registered if name not in MODEL_COLOURS]
    index = others.index(model) if model in others else len(PLUG_IN_COLOURS) - 1
    return PLUG_IN_COLOURS[index % len(PLUG_IN_COLOURS)]
