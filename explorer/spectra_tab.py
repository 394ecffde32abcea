"""The Spectra and filters tab: force spectra and contact filters of the case beside the reference filters,
another run overlaid, the spectra as CSV."""

from __future__ import annotations

import numpy as np
import viser

from wheelrail.core.models import REFERENCE_MODEL
from wheelrail.explorer.config import COMPARE, RunConfig
from wheelrail.explorer.panel import ResultsTab, Shown, TabParts
from wheelrail.explorer.plots import DASHED, DOTTED, SOLID, Plot, finite_bands, model_colour
from wheelrail.explorer.results import ResultStore, case_reference_filters

__all__ = ["REFERENCE_COLOURS", "SpectraTab"]

REFERENCE_COLOURS = {
    "cnossos": "#000000",
    "averaging": "#7f7f7f",
    "patch-correlated": "#bcbd22",
    "patch-incoherent": "#17becf",
}


class SpectraTab(ResultsTab):
    """Force spectra and contact filters of the case, reference filters, another run overlaid, the CSV."""

    title, icon = "Spectra and filters", viser.Icon.CHART_LINE

    def __init__(self, parts: TabParts, tab) -> None:
        super().__init__(parts, tab)
        gui, page = self.gui, self.page
        self.spectra = Plot(gui, tab, "Force spectra", "band (Hz)", "dB re 1 N", bands=True)
        self.filters = Plot(gui, tab, "Contact filters", "band (Hz)", "dB", bands=True)
        with tab:
            self.record_md = gui.add_markdown("")
            gui.add_markdown(
                f"*Contact filter*: a model's level minus `{REFERENCE_MODEL}`'s (solid; needs a "
                f"`{REFERENCE_MODEL}` run of the same configuration: use `{COMPARE}`). Dotted: "
                "reference filters at this preload, geometry and speed. Dashed: a run overlaid."
            )
            self.overlay_dropdown = self._overlay_menu("spectra and filters dashed beside these")
            self.csv_button = gui.add_button("Download spectra (.csv)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.csv_button.on_click(
                lambda event: page.guarded(parts.downloads.spectra_csv, event.client, client=event.client)
            )
            self._plot_export()

    def plots(self) -> dict[str, Plot]:
        return {"force spectra": self.spectra, "contact filters": self.filters}

    def show(self, shown: Shown) -> None:
        self._show_overlay_menu(self.overlay_dropdown, shown)
        config, store = shown.config, shown.store
        if config is None:
            for plot in (self.spectra, self.filters):
                plot.clear("fix the settings on the left")
            self.record_md.content = ""
            self.csv_button.disabled = True
            return
        self.record_md.content = _record_note(store, config)
        label = config.title_label()
        overlay = None if shown.overlay is None or shown.overlay.case() == config.case() else shown.overlay
        spectra = store.spectra(config.case())
        self.csv_button.disabled = not spectra
        if spectra:
            centres = next(iter(spectra.values()))[0]
            columns = [levels for _, levels in spectra.values()]
            series = tuple((m, model_colour(m), SOLID) for m in spectra)
            title = f"Force spectra: {label}"
            if overlay is not None:
                extra = {m: v for m, v in store.spectra(overlay.case()).items() if np.array_equal(v[0], centres)}
                columns += [levels for _, levels in extra.values()]
                series += tuple((f"{m} [{overlay.case_label()}]", model_colour(m), DASHED) for m in extra)
                if extra:  # the title names a dashed curve only when one is drawn
                    title += f" (dashed: {overlay.case_label()})"
            self.spectra.show(finite_bands(centres, columns), series, title=title)
        else:
            self.spectra.clear("no spectrum of this configuration yet", title=f"Force spectra: {label}")
        self._filters(config, store, overlay)

    def _filters(self, config: RunConfig, store: ResultStore, overlay: RunConfig | None) -> None:
        """Dynamic contact filters of the case (solid) beside the reference filters at its preload, geometry and
        speed (dotted; they need no run) and, on purpose, those of an ``overlay`` case (dashed, labelled)."""
        references = case_reference_filters(config)
        centres = next(iter(references.values()))[0]
        own = store.contact_filters(config.case())
        curves = [(f"{m} - {REFERENCE_MODEL}", model_colour(m), SOLID, v) for m, v in own.items()]
        title = f"Contact filters: {config.title_label()}"
        if overlay is not None:
            curves += [
                (f"{m} - {REFERENCE_MODEL} [{overlay.case_label()}]", model_colour(m), DASHED, v)
                for m, v in store.contact_filters(overlay.case()).items()
            ]
        curves = [c for c in curves if np.array_equal(c[3][0], centres)]
        if any(style == DASHED for _, _, style, _ in curves):  # an overlay without contact filters draws none
            title += f" (dashed: {overlay.case_label()})"
        curves += [(name, REFERENCE_COLOURS.get(name, "#555555"), DOTTED, v) for name, v in references.items()]
        columns = [levels for *_, (_, levels) in curves]
        series = tuple((label, colour, style) for label, colour, style, _ in curves)
        self.filters.show(finite_bands(centres, columns), series, title=title)


def _record_note(store: ResultStore, config: RunConfig) -> str:
    """What the case's force spectra analysed (core's ``spectrum_record``, as ``run`` and ``spectra`` print it):
    one line per distinct record among the case's runs, or nothing before a run."""
    from wheelrail.core.spectra.force import spectrum_record

    lines = {}
    for model, entry in store.entries(config.case()).items():
        if entry.spectrum is not None:
            lines.setdefault(spectrum_record(entry.result).words(), []).append(f"`{model}`")
    return "\n\n".join(f"*Force spectra* ({', '.join(models)}): {words}" for words, models in lines.items())
