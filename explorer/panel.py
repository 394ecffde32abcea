"""The results panel's tab, in general: what it is handed (:class:`TabParts`), what it shows (:class:`Shown`) and
what every tab does (:class:`ResultsTab`: build its elements, redraw, name its plots for the PNG export).

A tab's controls get their callbacks where they are built (viser's pattern), through the parts it is handed:
the :class:`~wheelrail.explorer.page.Page` guards them, the :class:`~wheelrail.explorer.replay.Replay` and
:class:`~wheelrail.explorer.downloads.Downloads` do their work, and ``choose_overlay``/``choose_model`` tell the
page a user's choice. The tabs themselves are in ``patch_tab``, ``spectra_tab``, ``noise_tab``, ``track_tab``,
``wheel_tab``, ``roughness_tab`` and ``help_tab``; :data:`wheelrail.explorer.tabs.RESULT_TABS` lists them in page order.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import viser

from wheelrail.explorer.config import RunConfig
from wheelrail.explorer.downloads import Downloads
from wheelrail.explorer.form import RunForm
from wheelrail.explorer.page import Page
from wheelrail.explorer.plots import Plot
from wheelrail.explorer.replay import Replay
from wheelrail.explorer.results import ResultStore
from wheelrail.explorer.workers import Workers

__all__ = ["NO_OVERLAY", "NO_RUN", "PLOT_HINT", "ResultsTab", "Shown", "TabParts"]

PLOT_HINT = (
    "*Plots*: drag across one to zoom, double-click to zoom back; hover for values; the ⤢ corner "
    "button (on hover) opens it large."
)
NO_RUN = "no run of this configuration yet"
NO_OVERLAY = "none"  # the overlay menus' choice of no run overlaid


@dataclass(frozen=True)
class TabParts:
    """What a tab is handed: the page, the run form, the replay, the downloads, and what a user's choice of the
    run overlaid or of the model shown does, how a tab asks to be redrawn (curves computed later), how it
    finds another tab (``find_tab(TrackTab)``: the Wheel tab draws the Track tab's receptance) and where it starts
    its background threads (``workers``: joined when the page closes)."""

    page: Page
    form: RunForm
    replay: Replay
    downloads: Downloads
    choose_overlay: Callable[[str], None]
    choose_model: Callable[[str], None]
    redraw: Callable[[object], None]
    find_tab: Callable[[type], object]
    workers: Workers


@dataclass(frozen=True)
class Shown:
    """What the page shows: the configuration the controls describe (None: not valid), the session's
    results, the model the Patch tab shows (replay, displacement, .rrd) among the models with a run, another
    configuration overlaid and the overlay menus' choices."""

    config: RunConfig | None
    store: ResultStore
    model: str | None = None
    models: tuple[str, ...] = ()
    overlay: RunConfig | None = None
    overlay_choice: str = NO_OVERLAY
    overlay_options: tuple[str, ...] = (NO_OVERLAY,)


class ResultsTab:
    """One tab of the results panel (subclasses set ``title`` and ``icon`` and build in ``__init__``)."""

    title = ""
    icon = None

    def __init__(self, parts: TabParts, tab) -> None:
        self.parts, self.page, self.tab = parts, parts.page, tab
        self.gui = parts.page.gui

    def plots(self) -> dict[str, Plot]:
        """The tab's plots by the names its PNG menu shows."""
        return {}

    def show(self, shown: Shown) -> None:
        """Redraw for the configuration shown."""

    def show_form(self, form: RunForm) -> None:
        """Redraw what follows the run form's fields alone, valid or not (after any of them changed)."""

    def live(self, result, config: RunConfig) -> None:
        """A running model's results so far."""

    def _overlay_menu(self, what: str):
        """The menu of the session's other runs, to overlay one (the page keeps its options and choice)."""
        menu = self.gui.add_dropdown(
            "Overlay a run",
            (NO_OVERLAY,),
            initial_value=NO_OVERLAY,
            hint=f"Runs of this session: draw another configuration's {what}",
        )
        choose = self.parts.choose_overlay
        menu.on_update(lambda event: None if self.page.is_quiet() else self.page.guarded(choose, event.target.value))
        return menu

    def _show_overlay_menu(self, menu, shown: Shown) -> None:
        """The overlay menu with the session's runs and the choice (the page's own update, not a user's)."""
        with self.page.quietly():
            if tuple(menu.options) != shown.overlay_options:
                menu.options = shown.overlay_options
            if menu.value != shown.overlay_choice:
                menu.value = shown.overlay_choice

    def _plot_export(self) -> None:
        """The hint on zooming and, for the tab's plots, a PNG download (titled with the configuration)."""
        gui, plots = self.gui, self.plots()
        gui.add_markdown(PLOT_HINT)
        names = tuple(plots)
        self.png_choice = gui.add_dropdown("Plot", names, initial_value=names[0])
        self.png_button = gui.add_button("Download plot (.png)", icon=viser.Icon.PHOTO)
        png = self.parts.downloads.plot_png
        self.png_button.on_click(
            lambda event: self.page.guarded(png, self.png_choice.value, event.client, client=event.client)
        )
