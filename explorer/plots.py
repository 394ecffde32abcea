"""uPlot charts of the explorer, each titled with the configuration it shows.

:class:`Plot` wraps one ``viser`` uPlot handle: new data with the same series updates it in place; other
series re-create it at the same place in its tab. :class:`CasePlots` draws one case's results (force
history of every model overlaid, force spectra, contact filters with the CNOSSOS-EU A3 and analytic
reference filters dashed) from a :class:`~wheelrail.explorer.results.ResultStore`; nothing of another case.
"""

from __future__ import annotations

import threading

import numpy as np

from wheelrail.core.models import REFERENCE_MODEL, model_names
from wheelrail.explorer.config import RunConfig
from wheelrail.explorer.results import ResultStore, case_reference_filters

__all__ = ["REFERENCE_STYLE", "CasePlots", "Plot", "finite_bands", "model_colour"]

_PALETTE = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")
REFERENCE_STYLE = {"cnossos": "#000000", "averaging": "#7f7f7f", "patch-correlated": "#bcbd22",
                   "patch-incoherent": "#17becf"}
MAX_POINTS = 4000  # points per line sent to the page
_CONTAINER_LOCK = threading.Lock()  # a viser container is entered by one thread at a time (run and callbacks)


def model_colour(model: str) -> str:
    """One colour per registered model, in registry order."""
    names = model_names()
    return _PALETTE[names.index(model) % len(_PALETTE)] if model in names else _PALETTE[-1]


def finite_bands(centres: np.ndarray, columns: list[np.ndarray]) -> tuple[np.ndarray, ...]:
    """Keep the bands where every column is finite (uPlot draws numbers only)."""
    keep = np.ones(centres.shape, dtype=bool)
    for column in columns:
        keep &= np.isfinite(column)
    return (centres[keep], *(np.asarray(column)[keep] for column in columns))


class Plot:
    """One uPlot chart in a GUI container; ``series``: (label, colour, dashed) after the x label."""

    def __init__(self, gui, container, title: str, x_label: str, y_label: str, *, log_x: bool = False) -> None:
        self._gui, self._container = gui, container
        self.title, self.x_label, self.y_label, self.log_x = title, x_label, y_label, log_x
        self.series: tuple = ()
        self.data: tuple = ()
        self.handle = None
        self.show((np.zeros(0), np.zeros(0)), (("no run yet", "#999999", False),))

    def show(self, data: tuple, series: tuple, title: str | None = None) -> None:
        data = tuple(np.asarray(d, dtype=np.float64) for d in data)
        title = self.title if title is None else title
        self.data = data
        if self.handle is not None and series == self.series and title == self.handle.title:
            self.handle.data = data
            return
        specs = [{"label": self.x_label}]
        specs += [{"label": label, "stroke": colour, "width": 1.5, **({"dash": (6.0, 4.0)} if dashed else {})}
                  for label, colour, dashed in series]
        scales = {"x": {"time": False, **({"distr": 3} if self.log_x else {})}}
        axes = ({"label": self.x_label}, {"label": self.y_label})
        with _CONTAINER_LOCK:
            order = None
            if self.handle is not None:
                order = self.handle.order
                self.handle.remove()
            with self._container:
                self.handle = self._gui.add_uplot(data, tuple(specs), title=title, scales=scales, axes=axes,
                                                  aspect=1.5, order=order)
            self.series = series

    def png(self) -> bytes:
        """The chart as shown (title, series, dashes, axes) drawn with matplotlib, as PNG bytes."""
        import io

        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        figure = Figure(figsize=(7.0, 4.2), layout="constrained")
        FigureCanvasAgg(figure)
        ax = figure.subplots()
        x = self.data[0] if self.data else np.zeros(0)
        for (label, colour, dashed), y in zip(self.series, self.data[1:], strict=False):
            ax.plot(x, y, color=colour, linestyle="--" if dashed else "-", linewidth=1.3, label=label)
        if self.log_x and x.size and np.all(x > 0):
            ax.set_xscale("log")
        ax.set(xlabel=self.x_label, ylabel=self.y_label)
        ax.set_title(self.handle.title if self.handle is not None else self.title, fontsize=9)
        ax.grid(True, alpha=0.3)
        if self.series:
            ax.legend(fontsize=7)
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", dpi=110)
        return buffer.getvalue()

    def clear(self, why: str, title: str | None = None) -> None:
        self.show((np.zeros(0), np.zeros(0)), ((why, "#999999", False),), title=title)


class CasePlots:
    """Force history, displacement, force spectra and contact filters of one case."""

    def __init__(self, gui, patch_tab, spectra_tab) -> None:
        self.force = Plot(gui, patch_tab, "Contact force", "position (m)", "force (kN)")
        self.displacement = Plot(gui, patch_tab, "Wheel and rail displacement (downwards)", "position (m)",
                                 "displacement (um)")
        self.spectra = Plot(gui, spectra_tab, "Force spectra", "band (Hz)", "dB re 1 N", log_x=True)
        self.filters = Plot(gui, spectra_tab, "Contact filters", "band (Hz)", "dB", log_x=True)

    def by_name(self) -> dict[str, Plot]:
        """The plots by the names the export menu shows."""
        return {"contact force": self.force, "displacement": self.displacement, "force spectra": self.spectra,
                "contact filters": self.filters}

    def live(self, result, config: RunConfig) -> None:
        """A running model's force and displacement so far."""
        step = max(1, result.n_steps // MAX_POINTS)
        x = result.x[::step]
        self.force.show((x, result.force[::step] / 1e3), ((f"{result.model} (running)", model_colour(result.model),
                                                          False),), title=f"Contact force: {config.case_label()}")
        self.displacement.show((x, result.xi_wheel[::step] * 1e6, result.xi_rail[::step] * 1e6),
                               (("wheel", "#1f77b4", False), ("rail", "#d62728", False)),
                               title=f"Displacement, {result.model}: {config.case_label()}")

    def show_case(self, config: RunConfig | None, store: ResultStore, overlay: RunConfig | None = None) -> None:
        """Everything of ``config``'s case (None: the controls are not a valid configuration); ``overlay``: another
        case whose spectra and contact filters are drawn dashed beside them on purpose, labelled with it."""
        if config is None:
            for plot in (self.force, self.displacement, self.spectra, self.filters):
                plot.clear("fix the settings above")
            return
        label = config.case_label()
        entries = store.entries(config.case())
        finished = {m: e for m, e in entries.items() if e.result.n_steps}
        if finished:
            n = min(e.result.n_steps for e in finished.values())
            step = max(1, n // MAX_POINTS)
            first = next(iter(finished.values())).result
            self.force.show((first.x[:n:step], *(e.result.force[:n:step] / 1e3 for e in finished.values())),
                            tuple((m, model_colour(m), False) for m in finished), title=f"Contact force: {label}")
            last = finished[config.model].result if config.model in finished else first
            self.displacement.show((last.x[::step], last.xi_wheel[::step] * 1e6, last.xi_rail[::step] * 1e6),
                                   (("wheel", "#1f77b4", False), ("rail", "#d62728", False)),
                                   title=f"Displacement, {last.model}: {label}")
        else:
            self.force.clear("no run of this configuration yet", title=f"Contact force: {label}")
            self.displacement.clear("no run of this configuration yet", title=f"Displacement: {label}")
        overlay = None if overlay is None or overlay.case() == config.case() else overlay
        spectra = store.spectra(config.case())
        if spectra:
            centres = next(iter(spectra.values()))[0]
            columns = [levels for _, levels in spectra.values()]
            series = tuple((m, model_colour(m), False) for m in spectra)
            title = f"Force spectra: {label}"
            if overlay is not None:
                extra = {m: v for m, v in store.spectra(overlay.case()).items() if np.array_equal(v[0], centres)}
                columns += [levels for _, levels in extra.values()]
                series += tuple((f"{m} [{overlay.case_label()}]", model_colour(m), True) for m in extra)
                title += f" (dashed: {overlay.case_label()})"
            self.spectra.show(finite_bands(centres, columns), series, title=title)
        else:
            self.spectra.clear("no spectrum of this configuration yet", title=f"Force spectra: {label}")
        self._filters(config, store, overlay)

    def _filters(self, config: RunConfig, store: ResultStore, overlay: RunConfig | None = None) -> None:
        """Dynamic contact filters of the case (solid) beside the reference filters at its preload and speed
        (dashed; they need no run) and, on purpose, those of an ``overlay`` case (dashed, labelled with it)."""
        references = case_reference_filters(config)
        centres = next(iter(references.values()))[0]
        own = store.contact_filters(config.case())
        curves = [(f"{m} - {REFERENCE_MODEL}", model_colour(m), False, v) for m, v in own.items()]
        title = f"Contact filters: {config.case_label()}"
        if overlay is not None:
            curves += [(f"{m} - {REFERENCE_MODEL} [{overlay.case_label()}]", model_colour(m), True, v)
                       for m, v in store.contact_filters(overlay.case()).items()]
            title += f" (dashed in model colours: {overlay.case_label()})"
        curves = [c for c in curves if np.array_equal(c[3][0], centres)]
        curves += [(name, REFERENCE_STYLE.get(name, "#555555"), True, v) for name, v in references.items()]
        columns = [levels for *_, (_, levels) in curves]
        series = tuple((label, colour, dashed) for label, colour, dashed, _ in curves)
        self.filters.show(finite_bands(centres, columns), series, title=title)
