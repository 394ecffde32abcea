"""The Roughness tab: the roughness of the configuration (spectra of the rail, the wheel set and their sum with
the ISO 3095 limit, against frequency and wavelength), the lateral coherence, the lines across the running
surface."""

from __future__ import annotations

import numpy as np
import viser

from wheelrail.core.parameters import KMH
from wheelrail.core.roughness import lateral_coherence, roughness_spectrum
from wheelrail.core.roughness.analysis import FREQUENCY_RANGE
from wheelrail.core.roughness.iso3095 import iso3095_limit
from wheelrail.core.spectra.bands import frequency_bands, map_levels
from wheelrail.core.spectra.levels import energy_sum
from wheelrail.explorer.form import RunForm
from wheelrail.explorer.panel import ResultsTab, TabParts
from wheelrail.explorer.plots import DOTTED, SOLID, Plot, bands_with_data, finite_bands

__all__ = ["EMPTY_BAND_DB", "ISO_LIMIT_COLOUR", "RoughnessTab", "line_map"]

EMPTY_BAND_DB = 120.0  # a roughness band this far below the set's highest band is empty (a numerical floor)
ISO_LIMIT_COLOUR = "#000000"


class RoughnessTab(ResultsTab):
    """The roughness of the configuration: spectra (rail, wheel set and combined, the ISO 3095 limit) against
    frequency and wavelength, the lateral coherence, the lines across the running surface."""

    title, icon = "Roughness", viser.Icon.WAVE_SINE

    def __init__(self, parts: TabParts, tab) -> None:
        super().__init__(parts, tab)
        gui = self.gui
        self._line_map_key = None  # what the line map shows
        self.spectrum = Plot(gui, tab, "Roughness spectrum", "band (Hz)", "dB re 1 µm", bands=True)
        self.coherence = Plot(gui, tab, "Lateral coherence", "band (Hz)", "γ²", bands=True, y_range=(0.0, 1.0))
        with tab:
            self.line_map = gui.add_image(
                np.full((10, 10, 3), 255, dtype=np.uint8), label="Lines across the running surface", format="png"
            )
            self.description_md = gui.add_markdown("")
            self._plot_export()

    def plots(self) -> dict[str, Plot]:
        return {"roughness spectrum": self.spectrum, "lateral coherence": self.coherence}

    def show_form(self, form: RunForm) -> None:
        """The set of the form: its description, its lines with the one chosen and the contact width across (drawn
        again only when they changed: a matplotlib figure costs far more than a frame), its spectra at the speed of
        the fields."""
        rough, name = form.roughness, form.roughness_label
        desc = rough.description.splitlines()[0] if rough.description else ""
        desc = desc if len(desc) <= 140 else desc[:137].rstrip() + "..."
        self.description_md.content = (
            f"**{name}**: {rough.kind}, {rough.n_lines} lines {rough.lateral_spacing * 1e3:.3g} mm apart, "
            f"{rough.length:.3g} m at {rough.dx * 1e3:.3g} mm. {desc}"
        )
        line, b = form.line(), form.contact().hertz_semi_axes()[1]
        if self._line_map_key != (id(rough), line, round(b * 1e6)):
            self._line_map_key = (id(rough), line, round(b * 1e6))
            self.line_map.image = line_map(rough, line, b)
        speed = form.field_value("speed")
        if speed is not None:
            wheel, wheel_label = form.wheel_or_none()
            self.show_roughness(rough, name, speed, wheel, wheel_label)

    def show_roughness(self, rough, label: str, speed: float, wheel=None, wheel_label: str | None = None) -> None:
        """Spectra of the set ``rough`` (and of the wheel set ``wheel`` with the combined roughness) at ``speed``
        (m/s), averaged over its lines ``DEFAULT_LINES`` (-3..3, the paper's), and its lateral coherence."""
        curves = []
        lines = self._lines(rough)
        rail = roughness_spectrum(rough, speed=speed, lines=lines)
        centres = rail.band_centres
        what = "rail" if rough.kind == "rail" else "wheel"
        curves.append((f"{what}: {label}, lines {lines[0]}..{lines[-1]}", "#1f77b4", rail.levels_db))
        title = f"Roughness spectrum: {label}"
        if wheel is not None:
            wheel_lines = self._lines(wheel)
            of_wheel = roughness_spectrum(wheel, speed=speed, lines=wheel_lines)
            curves.append(
                (f"wheel: {wheel_label}, lines {wheel_lines[0]}..{wheel_lines[-1]}", "#8c564b", of_wheel.levels_db)
            )
            curves.append(("combined (energetic sum)", "#d62728", energy_sum(rail.levels_db, of_wheel.levels_db)))
            title = f"Roughness spectrum: {label} + {wheel_label}"
        curves = [(name, colour, SOLID, _without_empty_bands(levels)) for name, colour, levels in curves]
        if rough.kind == "rail":
            limit_bands, limit = iso3095_limit()
            on_frequency = map_levels(limit, limit_bands, frequency_bands(speed, FREQUENCY_RANGE))
            curves.append(("ISO 3095:2013 limit (rail)", ISO_LIMIT_COLOUR, DOTTED, on_frequency))
        self.spectrum.show(
            bands_with_data(centres, [levels for *_, levels in curves]),
            tuple((name, colour, style) for name, colour, style, _ in curves),
            title=f"{title} at {speed / KMH:g} km/h",
            wavelength_speed=speed,
        )
        half = min(3, int(rough.line_numbers[-1]), -int(rough.line_numbers[0]))
        if half >= 1:
            centres, gamma2 = lateral_coherence(rough, speed, half_lines=half)
            self.coherence.show(
                finite_bands(centres, [gamma2]),
                ((f"γ², lines -{half}..{half}", "#2ca02c", SOLID),),
                title=f"Lateral coherence: {label} at {speed / KMH:g} km/h",
            )
        else:
            self.coherence.clear("one line only: no lateral coherence", title=f"Lateral coherence: {label}")

    @staticmethod
    def _lines(rough) -> list[int]:
        return [k for k in range(-3, 4) if k in rough.line_numbers] or [int(rough.line_numbers[0])]


def _without_empty_bands(levels: np.ndarray) -> np.ndarray:
    """Levels with the bands more than ``EMPTY_BAND_DB`` below the highest set to NaN: such a band holds no
    roughness, only the FFT's numerical floor (a pure sine gives -300 dB there), which would set the axis."""
    levels = np.asarray(levels, dtype=float)
    if not np.any(np.isfinite(levels)):
        return levels
    return np.where(levels >= np.nanmax(levels) - EMPTY_BAND_DB, levels, np.nan)


def line_map(rough, line: int | None, hertz_radius: float) -> np.ndarray:
    """Small map of the lines across the rail with the chosen line (None: none fits) and the nominal contact
    width across (2 ``hertz_radius``: 2b, the Hertz semi-axis across, for an elliptic patch)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    y = rough.y * 1e3
    chosen = line is not None and line in rough.line_numbers
    y_line = float(y[rough.row_of_line(line)]) if chosen else 0.0
    a = hertz_radius * 1e3
    fig = Figure(figsize=(5.2, 0.95), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.03, 0.42, 0.94, 0.4))
    ax.axvspan(y_line - a, y_line + a, color="#f0c800", alpha=0.35, lw=0)
    ax.vlines(y, 0, 1, color="#777777", lw=1)
    if chosen:
        ax.vlines([y_line], 0, 1, color="#d62728", lw=2.5)
    ax.set_yticks([])
    ax.set_xlim(min(y[0], y_line - a) - 1.5, max(y[-1], y_line + a) + 1.5)
    ax.tick_params(labelsize=7, length=2)
    what = f"line {line} red" if chosen else "no line fits"
    ax.set_xlabel(f"lateral position (mm); {what}, contact width {2 * a:.1f} mm yellow", fontsize=7, labelpad=1)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()
