"""One browser tab of the explorer: its own form, runs, results and downloads on its own client's GUI and 3D view.

A :class:`BrowserSession` is what :class:`~wheelrail.explorer.app.ExplorerApp` builds for each client that connects
(viser's per-client GUI: ``client.gui``, ``client.scene``) and closes when it disconnects. It wires the parts like a
viser example: :mod:`.page` (the status line, notices, guarded callbacks, the camera, files sent and received),
:mod:`.form` (the run form), :mod:`.session` (save and load the form), :mod:`.replay` (a run in the 3D view, the Step
slider and Play), :mod:`.downloads`, :mod:`.tabs` (the results panel's tabs, one module each), :mod:`.controller`
(the background run: stop, replace, compare; no viser), :mod:`.results` (results keyed by configuration),
:mod:`.scene` (the 3D view of the contact patch), :mod:`.plots` (uPlot charts and their PNGs), :mod:`.config` (what
Run asks for, checked in the page's words); each part builds its controls and attaches their callbacks where it
builds them; the session keeps what the page shows and listens to its runs. Everything computed comes from core.

The page: the run form docked on the left, the results panel (tabs Patch, Spectra and filters, Noise, Track, Wheel,
Roughness, Help) docked on the right at a width that keeps its plots at least 480 px wide, and the 3D view between
them, so that after Run the open tab's plots and the colour bar are on screen from 1280 x 800 up.

One truth on screen: the page always shows the configuration its controls describe (set, wheel set, line,
speed, preload, length, contact geometry; every model of it). Change one and the plots, the 3D view, its
readout, the Step slider and the progress bar show that configuration's run (its last step), or are cleared
with "no run of this configuration yet". After ``compare``, *Model shown* chooses the model replayed,
plotted as displacement and downloaded.
"""

from __future__ import annotations

import logging
import threading

import viser

from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import model_names
from wheelrail.core.parameters import KMH
from wheelrail.explorer.config import RunConfig, page_message
from wheelrail.explorer.controller import Preparation, RunController, RunView
from wheelrail.explorer.downloads import Downloads
from wheelrail.explorer.form import DEFAULT_LENGTH, DEFAULT_SET, RunForm
from wheelrail.explorer.page import Page
from wheelrail.explorer.panel import NO_OVERLAY, Shown, TabParts
from wheelrail.explorer.replay import Replay
from wheelrail.explorer.results import Entry, ResultStore
from wheelrail.explorer.scene import PatchScene
from wheelrail.explorer.session import SessionFiles
from wheelrail.explorer.tabs import RESULT_TABS
from wheelrail.explorer.uploads import MAX_UPLOAD_BYTES
from wheelrail.explorer.workers import Workers

__all__ = ["FIX_FIRST", "READY", "BrowserSession"]

LOG = logging.getLogger("wheelrail.explorer")
CONTROL_PANEL_WIDTH = 340  # px: the run form, docked left
RESULTS_PANEL_WIDTH = 560  # px: the results panel, docked right; its plots are about 520 px wide
READY = "Ready: choose a set, a line and a model, then press **Run**."
FIX_FIRST = "The settings are not a run yet: the line above **Run** says what to fix."
# The browser tab's title (React hoists a <title> rendered from markdown into the document's head), and viser's
# own "File uploaded successfully" notice (a green check) hidden, since it only means that the bytes arrived:
# the page says itself whether the file was loaded. If viser's markup changes, its notice shows again.
PAGE_HEAD = (
    "<title>wheelrail explorer</title><style>.mantine-Notification-root:has(.tabler-icon-check){display:none}</style>"
)


class BrowserSession:
    """One browser tab's explorer on its own client of the server: its parts, what its page shows, and its run
    controller's listener."""

    def __init__(
        self,
        server: viser.ViserServer,
        client: viser.ClientHandle,
        *,
        roughness: str = DEFAULT_SET,
        length: float = DEFAULT_LENGTH,
        max_upload_bytes: int = MAX_UPLOAD_BYTES,
        preparation: Preparation | None = None,
    ) -> None:
        """``preparation``: what the runs of every tab share (the tracks prepared, one first preparation)."""
        self.server, self.client = server, client
        self.port = server.get_port()
        self.store = ResultStore()  # this tab's runs: its overlays, downloads and replays
        self.workers = Workers()  # every background thread of the page, joined by close()
        self.controller = RunController(self, self.store, workers=self.workers, preparation=preparation)
        self.shown: RunConfig | None = None  # the configuration the controls describe (None: not valid)
        self.running: RunConfig | None = None  # the configuration being run, if any
        self._model_choice: str | None = None  # the user's choice in Model shown, for the configuration shown
        self._overlay_choice = NO_OVERLAY  # the run overlaid (Spectra and Noise tabs)
        self._done: tuple[RunConfig, str] | None = None  # the last run finished and its status line
        self._done_elsewhere: str | None = None  # the status line put in its place while another config is shown
        self._lock = threading.RLock()
        self.page = Page(server, client, max_upload_bytes)
        self.scene = PatchScene(client.scene)
        self._build(roughness, length)
        self.form.select_set(self.form.set_dropdown.value)
        self.status(READY)

    def warming_up(self, config: RunConfig) -> None:
        """The explorer prepares ``config``'s track and solver in the background: the status line says so."""
        self.status(
            f"{READY} Meanwhile the track for {config.speed / KMH:g} km/h and the {config.model} "
            "solver are prepared in the background (once; a first Run waits for it)."
        )

    def warmed_up(self, seconds: float) -> None:
        if self.page.status_md.content.startswith(f"{READY} Meanwhile"):
            self.status(f"{READY} (The track and solver were prepared in {seconds:.0f} s.)")

    def _build(self, roughness: str, length: float) -> None:
        """The run form docked left (with its Session folder), the results panel docked right."""
        gui = self.page.gui
        gui.configure_theme(control_width="medium", show_share_button=False)
        gui.main_panel.dock_left()
        gui.main_panel.set_width(CONTROL_PANEL_WIDTH)
        gui.add_markdown(PAGE_HEAD)
        gui.add_markdown(
            "Vertical wheel/rail interaction in the time domain (Pieringer, Kropp & Thompson, Wear 271, 2011)"
        )
        self.form = RunForm(
            self.page,
            changed=self.show_config,
            run=lambda client: self.start_run(client=client),
            stop=self.controller.stop,
            roughness=roughness,
            length=length,
        )
        with self.form.folder:
            self.session = SessionFiles(self.page, self.form, lambda: self.shown)
        self.replay = Replay(self.page, self.scene, self.form, self._running_shown, self.workers)
        self.downloads = Downloads(self.page, self.form, self.store, self.replay, lambda: self.shown, self.plots)
        parts = TabParts(
            page=self.page,
            form=self.form,
            replay=self.replay,
            downloads=self.downloads,
            choose_overlay=self.choose_overlay,
            choose_model=self.choose_model,
            redraw=self.redraw_tab,
            find_tab=self.tab,
            workers=self.workers,
        )
        panel = gui.add_panel()
        self.tabs = tuple(tab_class(parts, panel.add_tab(tab_class.title, tab_class.icon)) for tab_class in RESULT_TABS)
        panel.dock_right()
        panel.set_width(RESULTS_PANEL_WIDTH)

    def tab(self, kind: type):
        """The results panel's tab of class ``kind``."""
        return next(t for t in self.tabs if isinstance(t, kind))

    def plots(self) -> dict:
        """Every plot of the page by the name its tab's PNG menu shows."""
        return {name: plot for tab in self.tabs for name, plot in tab.plots().items()}

    # ------------------------------------------------------------------ what the page shows
    def show_config(self, config: RunConfig | None) -> None:
        """After any control of the form changed: the configuration it describes (None: not valid) is shown."""
        with self._lock:
            if self.page.last_error is not None and (config is None or config != self.shown):
                self.page.last_error = None  # the settings it was about have changed: it no longer applies
                self.status(READY if config is not None else FIX_FIRST)
            changed = config is None or self.shown is None or config != self.shown
            self.shown = config
            if changed:
                self._model_choice = None
                self.show_case()
                self._status_for_shown()
            self.scene.set_contact(self.form.contact())
            for tab in self.tabs:
                tab.show_form(self.form)

    def _status_for_shown(self) -> None:
        """A status line about a finished run (Done) follows the configuration shown: Done again for the run's
        own settings, else that the settings describe another configuration (its run or none)."""
        if self._done is None or self.page.status_md.content not in (self._done[1], self._done_elsewhere):
            return  # the status line says something else (a run under way, an error, a note): left as it is
        config = self.shown
        if config is None:
            text = FIX_FIRST
        elif config.case() == self._done[0].case():
            text = self._done[1]
        elif self.store.entries(config.case()):
            text = f"Shown: the run of {config.label()} made before; **Run** runs it again."
        else:
            text = f"The settings changed: no run of {config.label()} yet; press **Run**."
        self._done_elsewhere = text
        self.status(text)

    def choose_overlay(self, label: str) -> None:
        """The run overlaid (either tab's menu): both menus show it."""
        self._overlay_choice = label
        self.show_case()

    def choose_model(self, model: str) -> None:
        """Model shown (after compare): the model replayed, plotted as displacement and downloaded."""
        if self.shown is None or model not in self.store.entries(self.shown.case()):
            return
        self._model_choice = model
        self.show_case()

    def show_case(self) -> None:
        """Everything of the configuration shown: every tab, and the 3D view, readout, slider and progress (its
        run's last step, or cleared)."""
        if self.workers.closed.is_set():
            return
        with self._lock:
            shown, entries = self._shown_now()
            with self.page.atomic():
                for tab in self.tabs:
                    tab.show(shown)
                self.replay.show(entries.get(shown.model) if shown.model else None)

    def redraw_tab(self, tab) -> None:
        """Redraw one tab for what the page shows now (a tab whose curves were computed in the background)."""
        if self.workers.closed.is_set():
            return
        with self._lock:
            shown, _ = self._shown_now()
            with self.page.atomic():
                tab.show(shown)

    def _shown_now(self) -> tuple[Shown, dict]:
        """What the page shows now (the configuration of the controls, its model shown, the overlay) and the
        configuration's results by model."""
        config = self.shown
        entries = self.store.entries(config.case()) if config else {}
        models = tuple(m for m in model_names() if m in entries)
        if self._model_choice in models:  # the user's choice, else the model of the controls, else the first
            model = self._model_choice
        elif config is not None and config.model in models:
            model = config.model
        else:
            model = models[0] if models else None
        runs = {  # the other configurations of this session with a spectrum, to overlay one
            label: c for label, c in self.store.run_list().items() if config is None or c.case() != config.case()
        }
        if self._overlay_choice not in runs:
            self._overlay_choice = NO_OVERLAY
        shown = Shown(
            config=config,
            store=self.store,
            model=model,
            models=models,
            overlay=runs.get(self._overlay_choice),
            overlay_choice=self._overlay_choice,
            overlay_options=(NO_OVERLAY, *runs),
        )
        return shown, entries

    def _shows_the_run(self, config: RunConfig) -> bool:
        """Whether the page shows the configuration ``config`` (a run's, of any model)."""
        return self.shown is not None and config.case() == self.shown.case()

    def _running_shown(self) -> RunConfig | None:
        """The configuration being run when the page shows it (its live frames own the 3D view)."""
        running = self.running
        return running if running is not None and self._shows_the_run(running) else None

    # ------------------------------------------------------------------ runs (RunListener)
    def start_run(self, client=None) -> bool:
        """What the Run button does: check the controls, replace any run, start in the background."""
        form = self.form
        try:
            config = form.read_config()
        except WheelrailError as error:
            self.page.report_error(page_message(error), client)
            return False
        with self._lock:
            self.replay.playing = False
            self.page.last_error = None
            self.scene.frames_drawn = 0
            self.running = config
            form.show_running(True)
            self.replay.patch.time_slider.disabled = True
            wheel = None if config.wheel_set_label is None else form.sets[config.wheel_set_label]
            self.controller.start(config, form.roughness, wheel)
        return True

    def status(self, text: str) -> None:
        if not self.workers.closed.is_set():
            self.page.status(text)

    def progress(self, fraction: float) -> None:
        if self._running_shown() is not None and not self.workers.closed.is_set():
            self.form.show_progress(fraction)

    def frame(self, state, view: RunView) -> None:
        """A run's step: drawn only while the page shows that run's configuration."""
        with self._lock:
            if self._shows_the_run(view.config) and not self.workers.closed.is_set():
                self.replay.draw(state, view)

    def live(self, result, view: RunView) -> None:
        with self._lock:
            if self._shows_the_run(view.config) and not self.workers.closed.is_set():
                for tab in self.tabs:
                    tab.live(result, view.config)

    def model_done(self, entry: Entry, view: RunView) -> None:
        if self._shows_the_run(entry.config):
            self.show_case()

    def error(self, message: str) -> None:
        if not self.workers.closed.is_set():
            self.page.report_error(message)

    def finished(self, config: RunConfig, outcome: str) -> None:
        if self.workers.closed.is_set():
            return
        with self._lock:
            self.running = None
            self.form.show_running(False)
            if self._shows_the_run(config):
                self.show_case()
        if outcome == "done":
            self._done = (config, f"Done: {config.label(stated=True)}. Scrub with the Step slider or press Play.")
            self._done_elsewhere = None
            self.status(self._done[1])

    def close(self) -> None:
        """The tab closed (or the explorer stops): cancel its run, stop and join every background thread (a run
        or a track still being prepared ends once prepared; nothing is drawn meanwhile) and let go of its
        results."""
        self.replay.playing = False
        self.controller.close()  # marks the workers closed, supersedes the run and joins every thread
        self.store.clear()
        self.replay.entry = None
