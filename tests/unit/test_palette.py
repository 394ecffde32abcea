"""The figures' palette (``wheelrail.core.drawing.palette``): colours drawn together stay apart, under normal vision and
under simulated deuteranopia and protanopia, and every front end takes them from there."""

from __future__ import annotations

import itertools
from types import SimpleNamespace

import numpy as np
import pytest

from wheelrail.core.drawing import palette
from wheelrail.core.models import model_names
from wheelrail.core.noise.components import noise_components

# Machado, Oliveira & Fernandes (IEEE TVCG 2009), severity 1.0, on linear sRGB (the matrices colorspacious uses)
VISIONS = {
    "normal vision": np.eye(3),
    "deuteranopia": np.array(
        [[0.367322, 0.860646, -0.227968], [0.280085, 0.672501, 0.047413], [-0.011820, 0.042940, 0.968881]]
    ),
    "protanopia": np.array(
        [[0.152286, 1.052583, -0.204868], [0.114503, 0.786281, 0.099216], [-0.003882, -0.048116, 1.051998]]
    ),
}
MIN_DELTA_E = {"normal vision": 20.0, "deuteranopia": 10.0, "protanopia": 10.0}
"""CIEDE2000 distance two solid curves drawn together keep, per vision. About 1 is a just-noticeable difference
between large patches; thin lines need many times that to be named apart. The look-alikes the Noise tab once drew (its
greens, oranges and purples) were 5.8, 12.5 and 7.6 apart in normal vision and 2.2-9.2 under the simulations, so
20 and 10 refuse each of them; Okabe & Ito's set keeps 22 and 12 (vermillion and orange under deuteranopia, blue
and reddish purple under protanopia: the closest pairs an eight-colour set that also spans models and parts
keeps)."""


def _linear(colour: str) -> np.ndarray:
    srgb = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)]) / 255.0
    return np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)


def _lab(linear: np.ndarray) -> np.ndarray:
    to_xyz = np.array(
        [[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750], [0.0193339, 0.1191920, 0.9503041]]
    )
    t = to_xyz @ np.clip(linear, 0.0, 1.0) / np.array([0.95047, 1.0, 1.08883])  # D65 white
    f = np.where(t > (6 / 29) ** 3, np.cbrt(t), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def _ciede2000(first: np.ndarray, second: np.ndarray) -> float:
    """CIEDE2000 colour difference of two CIELAB colours (Sharma, Wu & Dalal, Color Res. Appl. 30, 2005, eqs 1-19)."""
    (l1, a1, b1), (l2, a2, b2) = first, second
    mean_c = (np.hypot(a1, b1) + np.hypot(a2, b2)) / 2
    g = 0.5 * (1 - np.sqrt(mean_c**7 / (mean_c**7 + 25.0**7)))
    c1, c2 = np.hypot((1 + g) * a1, b1), np.hypot((1 + g) * a2, b2)
    h1, h2 = np.degrees(np.arctan2(b1, (1 + g) * a1)) % 360, np.degrees(np.arctan2(b2, (1 + g) * a2)) % 360
    dh = 0.0 if c1 * c2 == 0 else (h2 - h1 + 180) % 360 - 180
    big_dh = 2 * np.sqrt(c1 * c2) * np.sin(np.radians(dh / 2))
    mean_l, mean_cp = (l1 + l2) / 2, (c1 + c2) / 2
    if c1 * c2 == 0:
        mean_h = h1 + h2
    elif abs(h1 - h2) <= 180:
        mean_h = (h1 + h2) / 2
    else:
        mean_h = (h1 + h2 + 360) / 2 if h1 + h2 < 360 else (h1 + h2 - 360) / 2
    t = (
        1 - 0.17 * np.cos(np.radians(mean_h - 30)) + 0.24 * np.cos(np.radians(2 * mean_h))
        + 0.32 * np.cos(np.radians(3 * mean_h + 6)) - 0.20 * np.cos(np.radians(4 * mean_h - 63))
    )  # fmt: skip
    rotation = (
        -2
        * np.sqrt(mean_cp**7 / (mean_cp**7 + 25.0**7))
        * np.sin(np.radians(60 * np.exp(-(((mean_h - 275) / 25) ** 2))))
    )
    s_l = 1 + 0.015 * (mean_l - 50) ** 2 / np.sqrt(20 + (mean_l - 50) ** 2)
    s_c, s_h = 1 + 0.045 * mean_cp, 1 + 0.015 * mean_cp * t
    terms = ((l2 - l1) / s_l, (c2 - c1) / s_c, big_dh / s_h)
    return float(np.sqrt(terms[0] ** 2 + terms[1] ** 2 + terms[2] ** 2 + rotation * terms[1] * terms[2]))


def delta_e(first: str, second: str, vision: str) -> float:
    """CIEDE2000 distance of two sRGB colours as seen with ``vision``."""
    matrix = VISIONS[vision]
    return _ciede2000(_lab(matrix @ _linear(first)), _lab(matrix @ _linear(second)))


def _too_close(colours: dict) -> list[str]:
    """The pairs of ``colours`` nearer than :data:`MIN_DELTA_E` in some vision, worded."""
    found = []
    for (a, ca), (b, cb) in itertools.combinations(colours.items(), 2):
        for vision, least in MIN_DELTA_E.items():
            distance = delta_e(ca, cb, vision)
            if distance < least:
                found.append(f"{a} {ca} and {b} {cb}: {distance:.1f} under {vision} (at least {least:g})")
    return found


def test_the_distance_is_ciede2000_and_refuses_the_old_look_alikes():
    # Sharma, Wu & Dalal's test data, pairs 1 and 7 (Table 1)
    assert _ciede2000(np.array([50, 2.6772, -79.7751]), np.array([50, 0, -82.7485])) == pytest.approx(2.0425, abs=1e-4)
    assert _ciede2000(np.array([50, 0, 0]), np.array([50, -1, 2])) == pytest.approx(2.3669, abs=1e-4)
    # the greens, oranges and purples the Noise tab once drew alike (components and model totals), each refused
    for pair in (("#31A354", "#2CA02C"), ("#E6550D", "#FF7F0E"), ("#756BB1", "#9467BD")):
        assert _too_close(dict(zip("ab", pair, strict=True)))


def _noise_tab_solid_colours() -> dict:
    """What the explorer's Noise tab draws solid after ``compare``: the shown model's components and every model's
    total."""
    from wheelrail.explorer import plots

    drawn = {f"component {part.name}": part.colour for part in noise_components()}
    drawn.update({f"model {name}": plots.model_colour(name) for name in model_names()})
    return drawn


def test_the_noise_tab_components_and_model_totals_stay_apart():
    assert not _too_close(_noise_tab_solid_colours())


def test_the_references_drawn_dotted_beside_them_stay_apart_from_each_other():
    assert not _too_close({f"CNOSSOS-EU {k}": v for k, v in palette.CNOSSOS_COLOURS.items()})


def test_the_wheel_power_total_is_apart_from_its_parts_and_drawn_on_top():
    from wheelrail.explorer.wheel_tab import WheelTab

    colours = {"total": palette.TOTAL_COLOUR, **palette.WHEEL_SURFACE_COLOURS}
    assert not _too_close(colours)
    shown = {}
    plot = SimpleNamespace(show=lambda data, series, title=None: shown.update(series=series, data=data))
    f = np.array([100.0, 125.0, 160.0])
    power = {"frequency_hz": f, "power_per_force": np.full(3, 2e-9), "axial": np.full(3, 2e-9), "radial": np.zeros(3)}
    WheelTab._draw_power(SimpleNamespace(power=plot, caption="wheel freight_920"), power)
    # a later series is drawn over an earlier one (uPlot and matplotlib alike): the total last, never hidden
    assert shown["series"][-1] == ("total", palette.TOTAL_COLOUR, "solid")


def test_every_front_end_takes_the_models_and_components_from_the_palette():
    from wheelrail.core.study import figures
    from wheelrail.explorer import noise_tab, plots

    for name in model_names():
        assert plots.model_colour(name) == palette.model_colour(name, model_names())
        column = f"{name.replace('-', '_')}_db"
        assert figures.model_style(column)["color"] == palette.MODEL_COLOURS[name]
    # each noise component's colour is its registry entry's (the explorer and the study figures read it there),
    # one of the palette's
    palette_colours = {*palette.OKABE_ITO.values(), palette.TOL_WINE, palette.TOL_INDIGO}
    assert all(part.colour in palette_colours for part in noise_components())
    assert noise_tab.CNOSSOS_COLOURS == palette.CNOSSOS_COLOURS


def test_a_plug_in_model_gets_a_colour_of_its_own():
    registered = (*palette.MODEL_COLOURS, "mine", "theirs")
    assert palette.model_colour("mine", registered) != palette.model_colour("theirs", registered)
    assert palette.model_colour("mine", registered) not in palette.MODEL_COLOURS.values()
