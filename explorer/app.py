"""The wheelrail explorer: a viser browser GUI over ``wheelrail.core``.

Parts: :mod:`.config` (what Run asks for, checked in the page's words), :mod:`.controller` (the background
run: stop, replace, compare; no viser), :mod:`.results` (results keyed by configuration), :mod:`.scene` (the
3D view of the contact patch), :mod:`.tabs` (the results panel's tabs), :mod:`.plots` (uPlot charts and
their PNGs), :mod:`.uploads` (roughness files from the browser). This module wires them like a viser example:
:func:`serve` creates the app and waits; the app lays out the page, declares its controls and attaches
small callbacks. Everything computed comes from core.

The page: the run form docked on the left, the results panel (tabs Patch, Spectra and filters, Noise, Roughness,
Help) docked on the right at a width that keeps its plots at least 480 px wide, and the 3D view between
them, so that after Run the open tab's plots and the colour bar are on screen from 1280 x 800 up.

One truth on screen: the page always shows the configuration its controls describe (set, wheel set, line,
speed, preload, length, contact geometry; every model of it). Change one and the plots, the 3D view, its
readout, the Step slider and the progress bar show that configuration's run (its last step), or are cleared
with "no run of this configuration yet". After ``compare``, *Model shown* chooses the model replayed,
plotted as displacement and downloaded.
"""

from __future__ import annotations

import contextlib
import logging
import math
import threading
import time
from pathlib import Path

import numpy as np
import viser

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs import GROUPS, by_key, inputs_of, model_parameters
from wheelrail.core.models import model_names
from wheelrail.core.parameters import KMH, ContactParameters
from wheelrail.core.roughness import bundled_names, load_roughness
from wheelrail.explorer.config import (
    COMPARE,
    MODEL_CHOICES,
    NO_LINE_FITS,
    NO_WHEEL_SET,
    RunConfig,
    field_hint,
    field_text,
    length_range,
    offered_lines,
    page_message,
    read_config,
    read_inputs,
    read_session,
)
from wheelrail.explorer.controller import RunController, RunView
from wheelrail.explorer.results import Entry, ResultStore
from wheelrail.explorer.scene import PRESSURE_TOP, PatchScene, colour_bar_image, oblique_view, top_view
from wheelrail.explorer.tabs import RESULT_TABS, NoiseTab, PatchTab, RoughnessTab, Shown, SpectraTab
from wheelrail.explorer.uploads import MAX_UPLOAD_BYTES, read_upload, refuse_large_uploads_early, size_text

__all__ = ["ExplorerApp", "main", "serve"]

LOG = logging.getLogger("wheelrail.explorer")
DEFAULT_SET = "corrugated-rail"
DEFAULT_LENGTH = 3.0  # m
SESSION_VERSION = 1  # of the session document (Session: Save/Load)
REPLAY_SPEEDS = {"0.01x": 0.01, "0.02x": 0.02, "0.05x": 0.05, "0.1x": 0.1}  # of real time
REPLAY_FPS = 20.0
CONTROL_PANEL_WIDTH = 340  # px: the run form, docked left
RESULTS_PANEL_WIDTH = 560  # px: the results panel, docked right; its plots are about 520 px wide
ASPECT_CHANGE = 0.02  # the 3D view is fitted again when its width / height changes by more than this share
NOTICE_SECONDS = 10.0  # a notice (error toast) closes by itself after this; a new one replaces it
NO_RUN_READOUT = "No run of this configuration yet: press **Run**."
READY = "Ready: choose a set, a line and a model, then press **Run**."
# The browser tab's title (React hoists a <title> rendered from markdown into the document's head), and viser's
# own "File uploaded successfully" notice (a green check) hidden, since it only means that the bytes arrived:
# the page says itself whether the file was loaded. If viser's markup changes, its notice shows again.
PAGE_HEAD = (
    "<title>wheelrail explorer</title><style>.mantine-Notification-root:has(.tabler-icon-check){display:none}</style>"
)


class ExplorerApp:
    """The explorer around one :class:`viser.ViserServer`; also the run controller's listener."""

    replay_speeds = REPLAY_SPEEDS
    no_overlay = "none"

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        *,
        roughness: str = DEFAULT_SET,
        length: float = DEFAULT_LENGTH,
        max_upload_bytes: int = MAX_UPLOAD_BYTES,
        verbose: bool = False,
        warm_up: bool = False,
    ) -> None:
        self.server = viser.ViserServer(host=host, port=port, label="wheelrail explorer", verbose=verbose)
        self.port = self.server.get_port()
        self.max_upload_bytes = int(max_upload_bytes)
        self.store = ResultStore()
        self.controller = RunController(self, self.store)
        self._sets: dict[str, object] = {}
        self._lock = threading.RLock()
        self.roughness = None
        self.roughness_label = ""
        self.shown: RunConfig | None = None  # the configuration the controls describe (None: not valid)
        self.replay: Entry | None = None  # the run the 3D view, Step slider and Play show
        self.running: RunConfig | None = None  # the configuration being run, if any
        self.last_error: str | None = None
        self.last_download: tuple[str, int] | None = None
        self.length_note = ""  # what the last change of set did to the run length, if anything
        self._colour_bar_key = self._line_map_key = None  # what the two images show
        self._model_choice: str | None = None  # the user's choice in Model shown, for the configuration shown
        self._overlay_choice = self.no_overlay  # the run overlaid (Spectra and Noise tabs)
        self._local = threading.local()  # .quiet: this thread is setting a control (its callback is not a user's)
        self._playing = False
        self._notices: dict[int, object] = {}  # client id -> its notice on screen
        self.notice_seconds = NOTICE_SECONDS
        try:
            self.scene = PatchScene(self.server)
            self._build_controls(roughness, length)
            self._build_results()
            refuse_large_uploads_early(self.server, lambda: self.max_upload_bytes, self.report_error)
            self.server.on_client_connect(self._on_connect)
            self.select_set(self.set_dropdown.value)
        except BaseException:
            self.server.stop()
            raise
        self.status(READY)
        if warm_up and self.shown is not None:
            self.status(
                f"{READY} Meanwhile the track for {self.shown.speed / KMH:g} km/h and the {self.shown.model} "
                "solver are prepared in the background (once; a first Run waits for it)."
            )
            self.controller.warm_up(self.shown, self.roughness, done=self._warmed_up)

    def _warmed_up(self, seconds: float) -> None:
        if self.status_md.content.startswith(f"{READY} Meanwhile"):
            self.status(f"{READY} (The track and solver were prepared in {seconds:.0f} s.)")

    # ------------------------------------------------------------------ page
    def _build_controls(self, roughness: str, length: float) -> None:
        gui = self.server.gui
        gui.configure_theme(control_width="medium", show_share_button=False)
        gui.main_panel.dock_left()
        gui.main_panel.set_width(CONTROL_PANEL_WIDTH)
        gui.add_markdown(PAGE_HEAD)
        gui.add_markdown(
            "Vertical wheel/rail interaction in the time domain (Pieringer, Kropp & Thompson, Wear 271, 2011)"
        )
        with gui.add_folder("Run"):
            names = bundled_names()
            self.set_dropdown = gui.add_dropdown(
                "Roughness set", names, initial_value=roughness if roughness in names else names[0]
            )
            self.wheel_set_dropdown = gui.add_dropdown(
                "Wheel roughness",
                (NO_WHEEL_SET, *self._wheel_set_names()),
                initial_value=NO_WHEEL_SET,
                hint="A wheel set added to the rail set (combined roughness); none: a smooth wheel.",
            )
            self.upload_button = gui.add_upload_button(
                f"Upload CSV/NPZ (<= {size_text(self.max_upload_bytes)})",
                icon=viser.Icon.UPLOAD,
                hint="A roughness file in the CSV or NPZ format of the user guide (Roughness data); read in memory.",
            )
            self.model_dropdown = gui.add_dropdown(
                "Contact model", MODEL_CHOICES, initial_value="3d", hint=f"{COMPARE}: every model one after another"
            )
            self.line_dropdown = gui.add_dropdown(
                "Line", ("0",), initial_value="0", hint="Only the lines this model can run on are offered."
            )
            self.fields = self._input_fields("run")
            self.length_text = gui.add_text("Run length (m)", f"{length:g}")
            for group in GROUPS:
                if group != "run":
                    with gui.add_folder(GROUPS[group], expand_by_default=False):
                        self.fields.update(self._input_fields(group))
            self.check_md = gui.add_markdown("")
            self.run_button = gui.add_button("Run", icon=viser.Icon.PLAYER_PLAY, color="green")
            self.stop_button = gui.add_button("Stop", icon=viser.Icon.PLAYER_STOP, color="red", disabled=True)
            self.progress_bar = gui.add_progress_bar(0.0, animated=False)
            self.status_md = gui.add_markdown("")
            with gui.add_folder("Session", expand_by_default=False):
                self.session_save_button = gui.add_button("Save session (.json)", icon=viser.Icon.DOWNLOAD)
                self.session_load_button = gui.add_upload_button(
                    "Load session (.json)",
                    icon=viser.Icon.UPLOAD,
                    hint="A session saved here: its set, wheel set, model, line, run length and every input.",
                )
        self.set_dropdown.on_update(
            lambda event: self._guarded(self.select_set, self.set_dropdown.value, client=event.client)
        )
        for handle in (self.model_dropdown, self.line_dropdown, self.length_text, *self.fields.values()):
            handle.on_update(lambda event: self._guarded(self.refresh))
        self.wheel_set_dropdown.on_update(lambda event: self._guarded(self.select_wheel_set, client=event.client))
        self.upload_button.on_upload(self._on_upload)
        self.session_save_button.on_click(
            lambda event: self._guarded(self.download_session, event.client, client=event.client)
        )
        self.session_load_button.on_upload(
            lambda event: self._guarded(self.load_session, event.target.value.content, client=event.client)
        )
        self.run_button.on_click(lambda event: self.start_run(client=event.client))
        self.stop_button.on_click(lambda event: self.controller.stop())

    def _input_fields(self, group: str) -> dict:
        """The fields of the declared inputs of ``group`` (wheelrail.core.inputs), by key: labelled with their
        unit, hinted with their range and default, showing the default (empty where unset means one)."""
        gui = self.server.gui
        fields = {}
        for entry in inputs_of(group):
            unit = f" ({entry.shown.name})" if entry.shown.name else ""
            fields[entry.key] = gui.add_text(f"{entry.label}{unit}", field_text(entry), hint=field_hint(entry))
        return fields

    def _build_results(self) -> None:
        """The results panel: one tab per entry of RESULT_TABS, docked right."""
        panel = self.server.gui.add_panel()
        self.tabs = tuple(tab_class(self, panel.add_tab(tab_class.title, tab_class.icon)) for tab_class in RESULT_TABS)
        panel.dock_right()
        panel.set_width(RESULTS_PANEL_WIDTH)
        self.results_panel = panel
        self.patch = next(t for t in self.tabs if isinstance(t, PatchTab))
        self.spectra = next(t for t in self.tabs if isinstance(t, SpectraTab))
        self.roughness_tab = next(t for t in self.tabs if isinstance(t, RoughnessTab))
        self.noise_tab = next(t for t in self.tabs if isinstance(t, NoiseTab))
        patch = self.patch
        patch.surfaces_box.on_update(lambda event: self._guarded(self._on_surfaces))
        patch.raised_box.on_update(lambda event: self._guarded(self._on_raised))
        patch.time_slider.on_update(lambda event: self._guarded(self.scrub, patch.time_slider.value))
        patch.play_button.on_click(lambda event: self._guarded(self.toggle_play))
        patch.model_shown.on_update(
            lambda event: None if self._is_quiet() else self._guarded(self.choose_model, patch.model_shown.value)
        )
        patch.view_buttons.on_click(lambda event: self._guarded(self.set_view, event.target.value, event.client))
        patch.rrd_button.on_click(lambda event: self._guarded(self.download_rrd, event.client, client=event.client))
        spectra = self.spectra
        spectra.csv_button.on_click(
            lambda event: self._guarded(self.download_spectra_csv, event.client, client=event.client)
        )
        noise = self.noise_tab
        for menu in (spectra.overlay_dropdown, noise.overlay_dropdown):  # one choice, two menus
            menu.on_update(
                lambda event: None if self._is_quiet() else self._guarded(self._choose_overlay, event.target.value)
            )
        for field in (noise.axles_text, noise.train_length_text):
            field.on_update(lambda event: self._guarded(self._show_case))
        noise.audio_button.on_click(lambda event: self._guarded(self.make_pass_by, client=event.client))
        noise.wav_button.on_click(
            lambda event: self._guarded(self.download_pass_by_wav, event.client, client=event.client)
        )
        noise.json_button.on_click(
            lambda event: self._guarded(self.download_noise_json, event.client, client=event.client)
        )

    @contextlib.contextmanager
    def _quietly(self):
        """A block in which this thread sets controls without their callbacks acting (not a user's choice)."""
        before = self._is_quiet()
        self._local.quiet = True
        try:
            yield
        finally:
            self._local.quiet = before

    def _is_quiet(self) -> bool:
        return getattr(self._local, "quiet", False)

    # handles the tests and the benchmark read
    @property
    def readout_md(self):
        return self.patch.readout_md

    @property
    def time_slider(self):
        return self.patch.time_slider

    @property
    def rrd_button(self):
        return self.patch.rrd_button

    @property
    def play_button(self):
        return self.patch.play_button

    @property
    def shown_model(self):
        return self.patch.model_shown

    @property
    def raised_box(self):
        return self.patch.raised_box

    @property
    def surfaces_box(self):
        return self.patch.surfaces_box

    # ------------------------------------------------------------------ set, line, configuration
    def select_set(self, name: str) -> None:
        """Make ``name`` (a bundled set or an uploaded file's label) the current roughness set; a run length
        outside what it holds is brought into range, saying so."""
        if name in self._sets:
            rough = self._sets[name]
        elif name in bundled_names():  # only names: a value sent by a browser is never opened as a path
            rough = self._sets[name] = load_roughness(name)
        else:
            self.set_dropdown.value = self.roughness_label
            raise WheelrailError(f"unknown roughness set {name!r}; choose a bundled set or upload a file")
        self.roughness, self.roughness_label = rough, name
        desc = rough.description.splitlines()[0] if rough.description else ""
        desc = desc if len(desc) <= 140 else desc[:137].rstrip() + "..."
        self.roughness_tab.description_md.content = (
            f"**{name}**: {rough.kind}, {rough.n_lines} lines {rough.lateral_spacing * 1e3:.3g} mm apart, "
            f"{rough.length:.3g} m at {rough.dx * 1e3:.3g} mm. {desc}"
        )
        self._bound_length()
        self.refresh()

    def _bound_length(self) -> None:
        """A run length the new set cannot hold (or too short for a spectrum) moves to the nearest allowed."""
        speed = self._field_value("speed")
        try:
            length = float(self.length_text.value)
        except ValueError:
            return
        if speed is None or not math.isfinite(length):
            return
        shortest, longest = length_range(self.roughness, speed)
        bounded = min(max(length, shortest), longest)
        self.length_note = ""
        if abs(bounded - length) > 1e-9:
            with self._quietly():
                self.length_text.value = f"{bounded:g}"
            self.length_note = (
                f"Run length {length:g} m is not possible on {self.roughness_label} at "
                f"{speed / KMH:g} km/h ({shortest:g} to {longest:g} m): {bounded:g} m is set."
            )
            self.status(self.length_note)

    def _typed(self) -> dict[str, str]:
        """The declared inputs' fields as typed, by their ``dest`` (``speed_kmh``: "100"), for read_config."""
        return {entry.dest: self.fields[entry.key].value for entry in inputs_of()}

    def _field_value(self, key: str) -> float | None:
        """One declared input's field, SI, when it holds a number within its range (else None: the check line
        says what is wrong)."""
        entry = by_key(key)
        try:
            given = dict(read_inputs(**{entry.dest: self.fields[key].value}))
        except WheelrailError:
            return None
        return given.get(key, entry.default())

    def _contact_or_default(self) -> ContactParameters:
        """The contact the fields describe; a field not valid yet counts as its default (the check line says)."""
        try:
            return model_parameters(dict(read_inputs(**self._typed()))).contact
        except WheelrailError:  # an input refused (e.g. a patch too wide at this preload): the preload's alone
            preload = self._field_value("preload")
            return ContactParameters() if preload is None else ContactParameters(preload=preload)

    def _wheel_set_names(self) -> tuple[str, ...]:
        """The bundled wheel sets (the wheel-set picker's choices besides none)."""
        names = []
        for name in bundled_names():
            if name not in self._sets:
                self._sets[name] = load_roughness(name)
            if self._sets[name].kind == "wheel":
                names.append(name)
        return tuple(names)

    def select_wheel_set(self) -> None:
        """After the wheel-set picker changed: a name that is no bundled wheel set is refused (back to none)."""
        try:
            self._wheel()
        finally:
            self.refresh()

    def _wheel(self) -> tuple[object, str | None]:
        """The chosen wheel set and its name, or (None, None); only a bundled wheel set is ever opened."""
        name = self.wheel_set_dropdown.value
        if name == NO_WHEEL_SET:
            return None, None
        if name not in self._wheel_set_names():
            self.wheel_set_dropdown.value = NO_WHEEL_SET
            raise WheelrailError(f"unknown wheel set {name!r}; choose a bundled wheel set or {NO_WHEEL_SET}")
        return self._sets[name], name

    def _wheel_or_none(self) -> tuple[object, str | None]:
        """The wheel set that applies to the set shown (a rail set), or (None, None)."""
        try:
            return self._wheel() if self.roughness.kind == "rail" else (None, None)
        except WheelrailError:
            return None, None

    def _offer_lines(self) -> None:
        """The Line menu: the lines the model can run on with the sets loaded (core's rule), or 'no line
        fits'; a line no longer offered moves to the nearest one offered, and the page says so."""
        lines = offered_lines(
            self.roughness, self.model_dropdown.value, self._contact_or_default(), self._wheel_or_none()[0]
        )
        options = tuple(str(n) for n in lines) or (NO_LINE_FITS,)
        current = self.line_dropdown.value
        if tuple(self.line_dropdown.options) != options:
            self.line_dropdown.options = options
        if not lines:
            if self.line_dropdown.value != NO_LINE_FITS:
                self.line_dropdown.value = NO_LINE_FITS
            return
        try:
            wanted = int(current)
        except ValueError:
            wanted = 0
        if str(wanted) not in options:
            nearest = min(lines, key=lambda n: (abs(n - wanted), n))
            self.line_dropdown.value = str(nearest)
            if current in ("", "0", NO_LINE_FITS) or wanted == 0:
                return
            self.status(
                f"Line {wanted} is not offered for {self.model_dropdown.value} on "
                f"{self.roughness_label}; line {nearest} is chosen."
            )
        elif self.line_dropdown.value != str(wanted):
            self.line_dropdown.value = str(wanted)

    def read_config(self) -> RunConfig:
        """The configuration the controls describe, or one WheelrailError in the page's words."""
        wheel, wheel_label = self._wheel()
        return read_config(
            self.roughness,
            self.roughness_label,
            line=self.line_dropdown.value,
            model=self.model_dropdown.value,
            length_m=self.length_text.value,
            **self._typed(),
            wheel=wheel,
            wheel_label=wheel_label,
        )

    def refresh(self) -> None:
        """After any control changed: offered lines, the check line, and everything of that configuration."""
        if self._is_quiet():
            return
        with self._lock:
            self._offer_lines()
            speed = self._field_value("speed") or by_key("speed").default()
            shortest, longest = length_range(self.roughness, speed)
            try:
                config = self.read_config()
            except WheelrailError as error:
                config = None
                self.check_md.content = f"**Cannot run:** {page_message(error)}"
            else:
                self.check_md.content = (
                    f"Run length {shortest:g} to {longest:g} m on this set at {config.speed / KMH:g} km/h."
                )
                if self.last_error is not None and (self.shown is None or config != self.shown):
                    self.last_error = None  # the configuration it was about has changed: it no longer applies
                    self.status(READY)
            changed = config is None or self.shown is None or config != self.shown
            self.shown = config
            if changed:
                self._model_choice = None
                self._show_case()
            self._update_preload_views()
            self._update_roughness_views()

    def _choose_overlay(self, label: str) -> None:
        """The run overlaid (either tab's menu): both menus show it."""
        self._overlay_choice = label
        self._show_case()

    def _overlay(self) -> RunConfig | None:
        """The run list: other configurations of this session with a spectrum; the one chosen to overlay (the
        Spectra and Noise tabs' menus show the same list and choice)."""
        runs = {
            label: c
            for label, c in self.store.run_list().items()
            if self.shown is None or c.case() != self.shown.case()
        }
        options = (self.no_overlay, *runs)
        if self._overlay_choice not in options:
            self._overlay_choice = self.no_overlay
        for menu in (self.spectra.overlay_dropdown, self.noise_tab.overlay_dropdown):
            with self._quietly():  # the menus' own updates are not a user's choice
                if tuple(menu.options) != options:
                    menu.options = options
                if menu.value != self._overlay_choice:
                    menu.value = self._overlay_choice
        return runs.get(self._overlay_choice)

    def _model_to_show(self, entries: dict[str, Entry]) -> str | None:
        """The model the Patch tab shows: the user's choice, else the model of the controls, else (compare) the
        first with a run in registry order; the Model shown menu lists the models with a run."""
        config = self.shown
        menu = self.patch.model_shown
        with_run = tuple(m for m in model_names() if m in entries)
        if self._model_choice in with_run:
            model = self._model_choice
        elif config is not None and config.model in with_run:
            model = config.model
        else:
            model = with_run[0] if with_run else None
        options = with_run or ((config.model if config is not None and config.model != COMPARE else "3d"),)
        with self._quietly():
            if tuple(menu.options) != options:
                menu.options = options
            if menu.value != (model or options[0]):
                menu.value = model or options[0]
        menu.disabled = len(with_run) < 2
        return model

    def _show_case(self) -> None:
        """Everything of the configuration shown: every tab, and the 3D view, readout, slider and progress (its
        run's last step, or cleared)."""
        with self._lock:
            shown, entries = self._shown_now()
            with self.server.atomic():
                for tab in self.tabs:
                    tab.show(shown)
                self._set_replay(entries.get(shown.model) if shown.model else None)

    def _shown_now(self) -> tuple[Shown, dict]:
        """What the page shows now (the configuration of the controls, its model shown, the overlay) and the
        configuration's results by model."""
        config = self.shown
        entries = self.store.entries(config.case()) if config else {}
        return Shown(
            config=config, store=self.store, model=self._model_to_show(entries), overlay=self._overlay()
        ), entries

    def redraw_tab(self, tab) -> None:
        """Redraw one tab for what the page shows now (a tab whose curves were computed in the background)."""
        with self._lock:
            shown, _ = self._shown_now()
            with self.server.atomic():
                tab.show(shown)

    def _shows_the_run(self, config: RunConfig) -> bool:
        """Whether the page shows the configuration ``config`` (a run's, of any model)."""
        return self.shown is not None and config.case() == self.shown.case()

    def _set_replay(self, entry: Entry | None) -> None:
        """Make ``entry`` the run the 3D view, readout, slider and progress show (its last step), or clear them;
        while this configuration is being run, its live frames own the view."""
        patch = self.patch
        self.replay = entry if entry is not None and entry.result.n_steps else None
        patch.rrd_button.disabled = patch.play_button.disabled = self.replay is None
        if self.running is not None and self._shows_the_run(self.running):
            if self.replay is None or self.replay.config.model != self.running.model:
                self.scene.clear()  # until the run's next frame: nothing of another run
                patch.readout_md.content = f"Running {self.running.label()} ..."
            patch.time_slider.disabled = True
            return
        if self.replay is None:
            self._playing = False
            self.scene.clear()
            patch.readout_md.content = NO_RUN_READOUT
            patch.time_slider.disabled = True
            self._set_slider(0, 1)
            self.progress_bar.value = 0.0
            self._on_surfaces()
            return
        last = self.replay.result.n_steps - 1
        self._set_slider(last, max(1, last))
        patch.time_slider.disabled = False
        self.progress_bar.value = round(100.0 * self.replay.done_fraction, 1)
        self.scrub(last)

    def _set_slider(self, value: int, maximum: int) -> None:
        """Set the Step slider without its callback drawing (the caller draws)."""
        slider = self.patch.time_slider
        with self._quietly():
            if slider.max != maximum:
                slider.max = maximum
            if slider.value != value:
                slider.value = value

    def choose_model(self, model: str) -> None:
        """Model shown (after compare): the model replayed, plotted as displacement and downloaded."""
        if self.shown is None or model not in self.store.entries(self.shown.case()):
            return
        self._model_choice = model
        self._show_case()

    # ------------------------------------------------------------------ runs (RunListener)
    def start_run(self, client=None) -> bool:
        """What the Run button does: check the controls, replace any run, start in the background."""
        try:
            config = self.read_config()
        except WheelrailError as error:
            self.report_error(page_message(error), client)
            return False
        with self._lock:
            self._playing = False
            self.last_error = None
            self.scene.frames_drawn = 0
            self.running = config
            self.progress_bar.value, self.progress_bar.animated = 0.0, True
            self.stop_button.disabled = False
            self.patch.time_slider.disabled = True
            wheel = None if config.wheel_set_label is None else self._sets[config.wheel_set_label]
            self.controller.start(config, self.roughness, wheel)
        return True

    def status(self, text: str) -> None:
        self.status_md.content = text

    def progress(self, fraction: float) -> None:
        running = self.running
        if running is not None and self._shows_the_run(running):
            self.progress_bar.value = round(100.0 * min(max(fraction, 0.0), 1.0), 1)

    def frame(self, state, view: RunView) -> None:
        """A run's step: drawn only while the page shows that run's configuration."""
        with self._lock:
            if not self._shows_the_run(view.config):
                return
            with self.server.atomic():
                self.scene.draw(state, view)
                self._readout(state, view.config)

    def _readout(self, state, config: RunConfig) -> None:
        contact = config.contact()
        a, b = (v * 1e3 for v in contact.hertz_semi_axes())
        self.patch.readout_md.content = (
            f"**{config.model}** step {state.step}: x = {state.position:.4f} m, F = {state.force / 1e3:.2f} kN, "
            f"contact length {state.contact_length * 1e3:.1f} mm  \n"
            f"Hertz at {config.preload / 1e3:g} kN: a = {a:.2f} mm along, b = {b:.2f} mm across, "
            f"p0 = {contact.hertz_peak_pressure() / 1e6:.0f} MPa"
        )

    def live(self, result, view: RunView) -> None:
        with self._lock:
            if self._shows_the_run(view.config):
                self.patch.live(result, view.config)

    def model_done(self, entry: Entry, view: RunView) -> None:
        if self._shows_the_run(entry.config):
            self._show_case()

    def error(self, message: str) -> None:
        self.report_error(message)

    def finished(self, config: RunConfig, outcome: str) -> None:
        with self._lock:
            self.running = None
            self.progress_bar.animated = False
            self.stop_button.disabled = True
            if self._shows_the_run(config):
                self._show_case()
        if outcome == "done":
            self.status(f"Done: {config.label()}. Scrub with the Step slider or press Play.")

    # ------------------------------------------------------------------ replay
    def scrub(self, step: int) -> None:
        """Show step ``step`` of the replayed run (the Step slider)."""
        entry = self.replay
        if self._is_quiet() or entry is None or (self.running is not None and self._shows_the_run(self.running)):
            return
        result = entry.result
        step = int(min(max(step, 0), result.n_steps - 1))
        self.frame(result.state(step), self._view_of(entry))

    def _view_of(self, entry: Entry) -> RunView:
        wheel = entry.config.wheel_set_label
        result = entry.result
        return RunView(
            config=entry.config,
            roughness=self._sets.get(entry.config.set_label, self.roughness),
            window_x=result.window_x,
            window_y=result.window_y,
            wheel_roughness=None if wheel is None else self._sets[wheel],
        )

    def toggle_play(self) -> None:
        """Play/pause the replayed run at the chosen fraction of real time (as viser's record3d example)."""
        if self._playing:
            self._playing = False
            return
        if self.replay is None or self.controller.running:
            return
        self._playing = True
        self.patch.play_button.label = "Pause"
        threading.Thread(target=self._play, daemon=True, name="wheelrail-explorer-replay").start()

    def _play(self) -> None:
        entry = self.replay
        result = entry.result
        slider = self.patch.time_slider
        steps_per_frame = max(1, round(REPLAY_SPEEDS[self.patch.replay_speed.value] / REPLAY_FPS / result.time_step))
        step = int(slider.value)
        if step >= result.n_steps - 1:
            step = 0
        while self._playing and self.replay is entry and step < result.n_steps:
            slider.value = step  # its callback draws the step
            step += steps_per_frame
            time.sleep(1.0 / REPLAY_FPS)
        self._playing = False
        self.patch.play_button.label = "Play"

    # ------------------------------------------------------------------ scene options, roughness views
    def set_view(self, which: str, client=None) -> None:
        """Top view (the default) or an oblique view, for one page or every page, fitted to its 3D view."""
        clients = [client] if client is not None else list(self.server.get_clients().values())
        for target in clients:
            camera = target.camera
            aspect = camera.image_width / camera.image_height if camera.image_height > 0 else None
            view = (top_view if which == "Top view" else oblique_view)(*(() if aspect is None else (aspect,)))
            with target.atomic():
                camera.up_direction = view["up"]
                camera.position, camera.look_at = view["position"], view["look_at"]

    def _on_connect(self, client) -> None:
        """A new page: once it reports the size of its 3D view, the top view is fitted to it, and fitted again
        while the view changes size (the panels dock after the first report, so a first fit may be for the whole
        window) until the user moves the camera."""
        lock = threading.Lock()
        fit = {"aspect": None, "ours": []}  # the aspect fitted and the camera positions the page was given

        def report(camera) -> None:
            if camera.image_height <= 0:
                return
            aspect = camera.image_width / camera.image_height
            position = np.asarray(camera.position, dtype=float)
            with lock:
                if fit["aspect"] is not None:
                    if fit["ours"] is None:  # the user's camera now
                        return
                    if not any(np.allclose(position, p, rtol=1e-3, atol=1e-3) for p in fit["ours"]):
                        fit["ours"] = None  # moved by the user: never fitted again
                        return
                    if abs(aspect / fit["aspect"] - 1.0) < ASPECT_CHANGE:
                        return
                else:
                    fit["ours"].append(position)  # the page's own start
                fit["aspect"] = aspect
                self._guarded(self.set_view, "Top view", client)
                fit["ours"].append(np.asarray(client.camera.position, dtype=float))

        client.camera.on_update(report)

    def _on_surfaces(self) -> None:
        """Rail and wheel surfaces of the configuration shown, at the step shown (its start without a run)."""
        scene = self.scene
        scene.show_surfaces = bool(self.patch.surfaces_box.value)
        entry = self.replay
        position = None
        if entry is not None:
            step = int(min(max(self.patch.time_slider.value, 0), entry.result.n_steps - 1))
            position = float(entry.result.x[step])
        try:
            line = int(self.line_dropdown.value)
        except ValueError:
            line = int(self.roughness.line_numbers[len(self.roughness.line_numbers) // 2])
        scene.draw_surfaces(self.roughness, position, line, self._contact_or_default(), self._wheel_or_none()[0])

    def _on_raised(self) -> None:
        self.scene.set_raised(bool(self.patch.raised_box.value))

    def _update_preload_views(self) -> None:
        """Hertz ellipse, colour bar and line map of the contact the fields describe (drawn again only when
        what they show changed: matplotlib takes some 0.1 s for the two images)."""
        contact = self._contact_or_default()
        self.scene.set_contact(contact)
        p0 = contact.hertz_peak_pressure() / 1e6
        try:
            line = int(self.line_dropdown.value)
        except ValueError:
            line = None
        b = contact.hertz_semi_axes()[1]
        if self._colour_bar_key != round(p0, 1):
            self._colour_bar_key = round(p0, 1)
            self.patch.colour_bar.image = colour_bar_image(round(PRESSURE_TOP * p0), p0)
        if self._line_map_key != (id(self.roughness), line, round(b * 1e6)):
            self._line_map_key = (id(self.roughness), line, round(b * 1e6))
            self.roughness_tab.line_map.image = _line_map(self.roughness, line, b)

    def _update_roughness_views(self) -> None:
        speed = self._field_value("speed")
        if speed is None:
            return
        wheel, wheel_label = self._wheel_or_none()
        self.roughness_tab.show_roughness(self.roughness, self.roughness_label, speed, wheel, wheel_label)

    # ------------------------------------------------------------------ uploads and downloads
    def _on_upload(self, event) -> None:
        uploaded = event.target.value
        try:
            self.load_upload(uploaded.name, uploaded.content, event.client)
        except WheelrailError as error:
            self.report_error(str(error), event.client, title="File not loaded")

    def load_upload(self, name: str, content: bytes, client=None) -> str:
        label, rough = read_upload(name, content, self.max_upload_bytes)
        slowest = by_key("speed").accepted.minimum  # the shortest run with a force spectrum is the slowest's
        shortest, longest = length_range(rough, slowest)  # a set too short for any run: a one-line error
        if longest < shortest:
            raise WheelrailError(
                f"{label}: {rough.length:.3g} m of data, too short for a force spectrum at any accepted speed "
                f"(a run of at least {shortest:g} m at {slowest / KMH:g} km/h); the set is not loaded"
            )
        self._sets[label] = rough
        options = tuple(self.set_dropdown.options)
        if label not in options:
            self.set_dropdown.options = (*options, label)
        self.set_dropdown.value = label  # its callback selects it (a new name)
        if self.roughness_label != label or self.roughness is not rough:  # the same name again: the new content
            self.select_set(label)
        message = f"Loaded {label}: {rough.kind}, {rough.n_lines} lines, {rough.length:.3g} m. {self.length_note}"
        self.status(message.strip())
        self._notify("File loaded", message, client, colour="green")
        LOG.info("uploaded %s", label)
        return label

    def session(self) -> dict:
        """The page's settings as a session document (JSON-able): set, wheel set, model, line, run length and
        every declared input's field as typed (by its option's name: ``speed_kmh``, ``pad_stiffness_mn_m``)."""
        return {
            "wheelrail_session": SESSION_VERSION,
            "set": self.roughness_label,
            "wheel_set": self.wheel_set_dropdown.value,
            "model": self.model_dropdown.value,
            "line": self.line_dropdown.value,
            "length_m": self.length_text.value,
            "inputs": self._typed(),
        }

    def download_session(self, client=None) -> tuple[str, bytes]:
        """The session (:meth:`session`) as a .json download, named after the configuration when it is valid."""
        from wheelrail.core.jsonready import strict_json

        stem = self.shown.for_model(self.shown.model).file_stem() if self.shown is not None else "wheelrail"
        name = f"{stem}-session.json"
        content = strict_json(self.session(), indent=2).encode()
        self._send(name, content, client)
        return name, content

    def load_session(self, content: bytes) -> None:
        """Set the page from a session document (:meth:`session`); one WheelrailError, and nothing changed, if it
        is not one or names a set this page does not have (upload the set first)."""
        session = read_session(content, tuple(self.set_dropdown.options), tuple(self.wheel_set_dropdown.options))
        with self._quietly():
            self.set_dropdown.value = session["set"]
            self.wheel_set_dropdown.value = session["wheel_set"]
            self.model_dropdown.value = session["model"]
            self.length_text.value = session["length_m"]
            for entry in inputs_of():
                self.fields[entry.key].value = session["inputs"].get(entry.dest, field_text(entry))
        self.select_set(session["set"])
        with self._quietly():
            if session["line"] in self.line_dropdown.options:
                self.line_dropdown.value = session["line"]
        self.refresh()
        self.status(f"Session loaded: {self.shown.label() if self.shown is not None else 'not a valid run yet'}.")

    def download_rrd(self, client=None) -> tuple[str, bytes]:
        """The replayed run (the model shown) as a rerun recording, named after its configuration."""
        import tempfile

        from wheelrail.core.recording import record_result

        entry = self.replay
        if entry is None:
            raise WheelrailError("no run of this configuration to save yet: press Run first")
        name = entry.config.file_stem() + ".rrd"
        with tempfile.TemporaryDirectory(prefix="wheelrail-rrd-") as folder:
            path = Path(folder) / name
            record_result(
                entry.result,
                path,
                roughness=self._sets.get(entry.config.set_label, self.roughness),
                description=f"wheelrail explorer: {entry.config.label()}",
                sound_power=entry.noise is not None,  # spectra/sound_power: the Noise tab's spectra
            )
            content = path.read_bytes()
        self._send(name, content, client)
        return name, content

    def download_spectra_csv(self, client=None) -> tuple[str, bytes]:
        """Spectra, contact filters and reference filters of the shown configuration, named after it."""
        if self.shown is None:
            raise WheelrailError("the settings are not a valid configuration: fix them first")
        content = self.store.csv_text(self.shown).encode()
        name = self.shown.for_model("spectra").file_stem() + ".csv"
        self._send(name, content, client)
        return name, content

    def _shown_noise(self) -> Entry:
        """The entry of the model shown, with its rolling noise, or one WheelrailError."""
        entry = self.replay
        if entry is None:
            raise WheelrailError("no run of this configuration yet: press Run first")
        if entry.noise is None:
            raise WheelrailError(f"{entry.config.model} has no rolling noise: {entry.noise_problem or 'stopped early'}")
        return entry

    def make_pass_by(self) -> tuple[str, bytes]:
        """The Noise tab's Pass-by audio: the pass-by of the model shown for the tab's train, in the player."""
        entry = self._shown_noise()
        tab = self.noise_tab
        tab.train()  # a bad train field is said before the work starts
        tab.audio_html.content = "<i>Making the pass-by ...</i>"
        try:
            return tab.pass_by(entry)
        except BaseException:
            tab.clear_audio()
            raise

    def download_pass_by_wav(self, client=None) -> tuple[str, bytes]:
        """The pass-by in the player as a WAV file."""
        if self.noise_tab.wav is None:
            raise WheelrailError("no pass-by made yet: press Pass-by audio first")
        name, content = self.noise_tab.wav
        self._send(name, content, client)
        return name, content

    def download_noise_json(self, client=None) -> tuple[str, bytes]:
        """The rolling noise of the model shown (sound power, totals, pass-by for the tab's train, CNOSSOS-EU beside
        it and the configuration) as JSON, named after the configuration."""

        from wheelrail.core.jsonready import strict_json

        entry = self._shown_noise()
        noise = entry.noise.with_train(*self.noise_tab.train())
        summary = {"explorer": entry.config.label(), **noise.to_dict()}
        content = (strict_json(summary, indent=1) + "\n").encode()
        name = entry.config.file_stem() + "-noise.json"
        self._send(name, content, client)
        return name, content

    def plots(self) -> dict:
        """Every plot of the page by the name its tab's PNG menu shows."""
        return {name: plot for tab in self.tabs for name, plot in tab.plots().items()}

    def download_plot_png(self, which: str, client=None) -> tuple[str, bytes]:
        """One plot as shown (its title names the configuration), as a PNG named after the configuration."""
        plots = self.plots()
        if which not in plots:
            raise WheelrailError(f"unknown plot {which!r}; choose one of {', '.join(plots)}")
        stem = self.shown.for_model("plot").file_stem() if self.shown is not None else "wheelrail-plot"
        name = f"{stem}-{which.replace(' ', '-')}.png"
        content = plots[which].png()
        self._send(name, content, client)
        return name, content

    def _send(self, name: str, content: bytes, client) -> None:
        self.last_download = (name, len(content))
        target = client if client is not None else self.server
        target.send_file_download(name, content, save_immediately=True)

    # ------------------------------------------------------------------ messages
    def _guarded(self, function, *args, client=None):
        """Run a callback's work; a WheelrailError (bad input) becomes a message in the page."""
        try:
            return function(*args)
        except WheelrailError as error:
            self.report_error(page_message(error), client)
        except Exception as error:  # keep serving after anything
            LOG.exception("callback failed")
            self.report_error(f"unexpected error: {type(error).__name__}: {error}", client)
        return None

    def report_error(self, message: str, client=None, title: str = "Cannot do that") -> None:
        self.last_error = message
        LOG.warning("error shown in the page: %s", message)
        self.status(f"**Error:** {message}")
        self._notify(title, message, client, colour="red")

    def _notify(self, title: str, message: str, client=None, *, colour: str) -> None:
        """One notice per page, replacing the one before; it closes by itself after ``notice_seconds``."""
        for target in [client] if client is not None else list(self.server.get_clients().values()):
            try:
                old = self._notices.pop(target.client_id, None)
                if old is not None:
                    old.remove()
                self._notices[target.client_id] = target.add_notification(
                    title, message, color=colour, auto_close_seconds=self.notice_seconds
                )
            except Exception:  # a tab that closed meanwhile
                pass

    def close(self) -> None:
        """Cancel any run and stop the server."""
        self._playing = False
        self.controller.cancel_current()
        self.server.stop()


def _line_map(rough, line: int | None, hertz_radius: float) -> np.ndarray:
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


def serve(
    host: str = "127.0.0.1", port: int = 8080, *, roughness: str = DEFAULT_SET, length: float = DEFAULT_LENGTH
) -> int:
    """Start the explorer and serve until interrupted (Ctrl-C); runs and errors are logged to the terminal."""
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s", datefmt="%H:%M:%S")
    app = ExplorerApp(host, port, roughness=roughness, length=length, verbose=False, warm_up=True)
    shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
    print(f"wheelrail explorer: http://{shown}:{app.port}  (Ctrl-C to stop)", flush=True)
    try:
        threading.Event().wait()
    except KeyboardInterrupt:
        pass
    finally:
        app.close()
    return 0


main = serve
