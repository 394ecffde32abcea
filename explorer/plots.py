"""uPlot charts of the explorer and their PNG twins, each titled with the configuration it shows.

:class:`Plot` wraps one ``viser`` uPlot handle: new data with the same series and axes updates it in place;
anything else re-creates it at the same place in its tab. Curves have one of three styles: solid (this
configuration's results), dashed (another configuration overlaid on purpose) and dotted (reference curves:
the analytic and CNOSSOS-EU contact filters, the ISO 3095 limit). Band axes are ticked at the octave bands
with their nominal names (``wheelrail.core.spectra.bands.nominal_band_label``: 63, 125, ... 8000 Hz); a roughness
plot adds a wavelength axis on top (lambda = v / f at the speed shown). :meth:`Plot.png` draws the same
data, styles and axes with matplotlib, its title wrapped to the figure's width.
"""

from __future__ import annotations

import math
import textwrap
import threading

import numpy as np

from wheelrail.core.drawing import palette
from wheelrail.core.models import model_names
from wheelrail.core.parameters import KMH
from wheelrail.core.spectra.bands import nominal_band_label

__all__ = [
    "DASHED",
    "DOTTED",
    "PLOT_ASPECT",
    "POINTS",
    "SOLID",
    "Plot",
    "band_ticks",
    "bands_with_data",
    "finite_bands",
    "model_colour",
    "wavelength_ticks",
]

SOLID, DASHED, DOTTED, POINTS = "solid", "dashed", "dotted", "points"  # POINTS: markers alone (NaN elsewhere)
STYLES = (SOLID, DASHED, DOTTED, POINTS)
_DASH = {DASHED: (6.0, 4.0), DOTTED: (1.5, 3.0)}  # uPlot dash patterns, px
_MPL_LINESTYLE = {SOLID: "-", DASHED: "--", DOTTED: ":", POINTS: "none"}
MARKER_SIZE = 10.0  # px: a POINTS series' markers
PLOT_ASPECT = 1.7  # width / height of the page's plots (about 310 px high at the results panel's width)
PLOT_PADDING = (12, 24, 0, 0)  # px: top, right, bottom, left (room for the highest tick label)
MAX_POINTS = 4000  # points per line sent to the page
PNG_SIZE = (7.0, 4.6)  # inches; at PNG_DPI: 770 x 506 px
PNG_DPI = 110
PNG_TITLE_CHARACTERS = 95  # a title line at 9 pt fits the PNG's width (about 7.5 px a character)
# wavelengths (mm) marked on a roughness plot's top axis where they fall inside its frequency range
WAVELENGTH_TICKS_MM = (2000, 1000, 500, 200, 100, 50, 20, 10, 5, 2, 1)
_CONTAINER_LOCK = threading.Lock()  # a viser container is entered by one thread at a time (run and callbacks)


def model_colour(model: str) -> str:
    """The model's colour of core's palette (``wheelrail.core.drawing.palette``), the same in every figure."""
    return palette.model_colour(model, model_names())


def finite_bands(centres: np.ndarray, columns: list[np.ndarray]) -> tuple[np.ndarray, ...]:
    """Keep the bands where every column is finite (curves that all cover the same bands)."""
    keep = np.ones(centres.shape, dtype=bool)
    for column in columns:
        keep &= np.isfinite(column)
    return (centres[keep], *(np.asarray(column)[keep] for column in columns))


def bands_with_data(centres: np.ndarray, columns: list[np.ndarray]) -> tuple[np.ndarray, ...]:
    """Keep the bands where any column is finite; the others stay NaN there (a curve over part of the range,
    such as a limit defined on fewer bands, next to full ones)."""
    keep = np.zeros(centres.shape, dtype=bool)
    for column in columns:
        keep |= np.isfinite(column)
    return (centres[keep], *(np.asarray(column, dtype=float)[keep] for column in columns))


def band_ticks(lowest: float, highest: float) -> tuple[list[float], list[str]]:
    """The octave bands (exact base-10 centres 10^(3n/10) Hz) within [lowest, highest] and their nominal
    names ('63', '125', ... '8000')."""
    if not (math.isfinite(lowest) and math.isfinite(highest) and 0 < lowest <= highest):
        return [], []
    first, last = math.ceil(10 * math.log10(lowest) / 3 - 1e-9), math.floor(10 * math.log10(highest) / 3 + 1e-9)
    centres = [10.0 ** (3 * n / 10) for n in range(first, last + 1)]
    return centres, [nominal_band_label(c) for c in centres]


def wavelength_ticks(speed: float, lowest: float, highest: float) -> tuple[list[float], list[str]]:
    """Frequencies (Hz) within [lowest, highest] of round wavelengths at ``speed`` (m/s): f = v / lambda, and
    their wavelengths in mm as labels."""
    ticks = [(speed / (mm * 1e-3), f"{mm:g}") for mm in WAVELENGTH_TICKS_MM]
    ticks = [(f, label) for f, label in ticks if lowest <= f <= highest]
    return [f for f, _ in ticks], [label for _, label in ticks]


def _series_spec(label: str, colour: str, style: str) -> dict:
    """A curve as uPlot draws it: a line (dashed or dotted as ``style`` says) or, for :data:`POINTS`, markers
    alone at its finite values."""
    if style == POINTS:
        return {"label": label, "stroke": colour, "width": 0, "points": {"show": True, "size": MARKER_SIZE,
                "fill": colour, "space": 0}}  # fmt: skip
    return {"label": label, "stroke": colour, "width": 1.5, **({"dash": _DASH[style]} if style in _DASH else {})}


def _range_around_gaps(columns: tuple) -> tuple[float, float] | None:
    """A fixed y range (rounded out to 5) for curves with gaps (NaN: a band a curve does not cover), which uPlot
    cannot range itself; None when there is no gap."""
    values = np.concatenate([np.ravel(c) for c in columns]) if columns else np.zeros(0)
    if values.size == 0 or np.all(np.isfinite(values)):
        return None
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        return None
    return 5.0 * math.floor(finite.min() / 5.0 - 0.2), 5.0 * math.ceil(finite.max() / 5.0 + 0.2)


class Plot:
    """One uPlot chart in a GUI container, and its PNG.

    ``series``: (label, colour, style) per curve after the x values, style one of ``STYLES``. ``bands``: the
    x axis is third-octave bands (log scale, octave ticks with nominal names); ``y_range``: a fixed y range.
    """

    def __init__(
        self,
        gui,
        container,
        title: str,
        x_label: str,
        y_label: str,
        *,
        bands: bool = False,
        y_range: tuple[float, float] | None = None,
    ) -> None:
        self._gui, self._container = gui, container
        self.title, self.x_label, self.y_label = title, x_label, y_label
        self.bands, self.y_range = bands, y_range
        self.series: tuple = ()
        self.data: tuple = ()
        self.wavelength_speed: float | None = None
        self.handle = None
        self._visible = True
        self._axes_key = None
        self.show((np.zeros(0), np.zeros(0)), (("no run yet", "#999999", SOLID),))

    def show(
        self, data: tuple, series: tuple, title: str | None = None, *, wavelength_speed: float | None = None
    ) -> None:
        """New data; ``wavelength_speed`` (m/s): add a wavelength axis on top (a roughness plot)."""
        for _, _, style in series:
            if style not in STYLES:
                raise ValueError(f"unknown line style {style!r}; one of {', '.join(STYLES)}")
        data = tuple(np.asarray(d, dtype=np.float64) for d in data)
        title = self.title if title is None else title
        self.data, self.wavelength_speed = data, wavelength_speed
        scales, axes = self._uplot_axes(data, wavelength_speed)
        axes_key = repr((scales, axes))
        if (
            self.handle is not None
            and series == self.series
            and title == self.handle.title
            and axes_key == self._axes_key
        ):
            self.handle.data = data
            return
        specs = [{"label": self.x_label}]
        specs += [_series_spec(label, colour, style) for label, colour, style in series]
        with _CONTAINER_LOCK:
            order = None
            if self.handle is not None:
                order = self.handle.order
                self.handle.remove()
            with self._container:
                self.handle = self._gui.add_uplot(
                    data,
                    tuple(specs),
                    title=title,
                    scales=scales,
                    axes=axes,
                    aspect=PLOT_ASPECT,
                    padding=PLOT_PADDING,
                    order=order,
                    visible=self._visible,
                )
            self.series, self._axes_key = series, axes_key

    @property
    def visible(self) -> bool:
        """Whether the chart is on the page (a hidden chart keeps its data and comes back as it was)."""
        return self._visible

    @visible.setter
    def visible(self, visible: bool) -> None:
        self._visible = bool(visible)
        if self.handle is not None and self.handle.visible != self._visible:
            self.handle.visible = self._visible

    def _uplot_axes(self, data: tuple, wavelength_speed: float | None) -> tuple[dict, tuple]:
        x = data[0]
        scales: dict = {"x": {"time": False, **({"distr": 3} if self.bands else {})}}
        y_range = self.y_range if self.y_range is not None else _range_around_gaps(data[1:])
        if y_range is not None:
            scales["y"] = {"range": list(y_range)}
        bottom: dict = {"label": self.x_label}
        axes = [bottom, {"label": self.y_label}]
        if self.bands and x.size:
            bottom["splits"], bottom["values"] = band_ticks(float(x.min()), float(x.max()))
            if wavelength_speed is not None:
                splits, values = wavelength_ticks(wavelength_speed, float(x.min()), float(x.max()))
                axes.append(
                    {
                        "side": 0,
                        "scale": "x",
                        "label": self._wavelength_label(wavelength_speed),
                        "splits": splits,
                        "values": values,
                        "grid": {"show": False},
                    }
                )
        return scales, tuple(axes)

    @staticmethod
    def _wavelength_label(speed: float) -> str:
        return f"wavelength (mm) at {speed / KMH:g} km/h"

    def figure(self):
        """The chart as shown (title wrapped, series and styles, axes) as a matplotlib Figure."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        figure = Figure(figsize=PNG_SIZE, dpi=PNG_DPI, layout="constrained")
        FigureCanvasAgg(figure)
        ax = figure.subplots()
        x = self.data[0] if self.data else np.zeros(0)
        for (label, colour, style), y in zip(self.series, self.data[1:], strict=False):
            marker = {"marker": "o", "markersize": 6} if style == POINTS else {}
            ax.plot(x, y, color=colour, linestyle=_MPL_LINESTYLE[style], linewidth=1.3, label=label, **marker)
        if self.bands and x.size and np.all(x > 0):
            ax.set_xscale("log")
            ax.minorticks_off()
            ticks, labels = band_ticks(float(x.min()), float(x.max()))
            ax.set_xticks(ticks, labels)
            speed = self.wavelength_speed
            if speed is not None:  # as on the page: ticks at f = v / lambda, labelled with lambda
                top = ax.twiny()
                top.set_xscale("log")
                top.set_xlim(ax.get_xlim())
                top.minorticks_off()
                top.set_xticks(*wavelength_ticks(speed, float(x.min()), float(x.max())))
                top.set_xlabel(self._wavelength_label(speed))
        if self.y_range is not None:
            ax.set_ylim(*self.y_range)
        ax.set(xlabel=self.x_label, ylabel=self.y_label)
        title = self.handle.title if self.handle is not None else self.title
        ax.set_title("\n".join(textwrap.wrap(title, PNG_TITLE_CHARACTERS)), fontsize=9)
        ax.grid(True, alpha=0.3)
        if self.series:
            ax.legend(fontsize=7)
        return figure

    def png(self) -> bytes:
        """The chart as shown, drawn with matplotlib, as PNG bytes."""
        import io

        buffer = io.BytesIO()
        self.figure().savefig(buffer, format="png", dpi=PNG_DPI)
        return buffer.getvalue()

    def clear(self, why: str, title: str | None = None) -> None:
        self.show((np.zeros(0), np.zeros(0)), ((why, "#999999", SOLID),), title=title)
