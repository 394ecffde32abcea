"""The wheelrail explorer: a viser browser GUI over ``wheelrail.core``.

Parts: :mod:`.config` (what Run asks for, checked in the page's words), :mod:`.controller` (the background
run: stop, replace, compare; no viser), :mod:`.results` (results keyed by configuration), :mod:`.scene` (the
contact patch), :mod:`.plots` (uPlot charts), :mod:`.uploads` (roughness files from the browser). This module
wires them to the controls, like a viser example: :func:`serve` creates the app and waits; the app declares
its controls in a folder and four tabs and attaches small callbacks. Everything computed comes from core.

The page always shows the results of the configuration its controls describe (set, wheel set, line, speed,
preload, length, contact geometry; every model of it): change one and the plots show that configuration's
runs, or none yet.
"""

from __future__ import annotations

import logging
import threading
import time
from pathlib import Path

import numpy as np
import viser

from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import REFERENCE_MODEL, model_entry
from wheelrail.core.parameters import KMH, MAX_SPEED_KMH, MIN_SPEED_KMH, ContactParameters
from wheelrail.core.roughness import bundled_names, lateral_coherence, load_roughness, roughness_spectrum
from wheelrail.explorer.config import (
    COMPARE,
    MODEL_CHOICES,
    NO_WHEEL_SET,
    PRELOAD_RANGE_KN,
    RunConfig,
    accepted_text,
    length_range,
    offered_lines,
    page_message,
    read_config,
    read_geometry,
)
from wheelrail.explorer.controller import RunController, RunView
from wheelrail.explorer.plots import CasePlots, Plot, finite_bands
from wheelrail.explorer.results import Entry, ResultStore
from wheelrail.explorer.scene import PRESSURE_TOP, PatchScene, colour_bar_image
from wheelrail.explorer.uploads import MAX_UPLOAD_BYTES, read_upload, refuse_large_uploads_early, size_text

__all__ = ["ExplorerApp", "main", "serve"]

NO_OVERLAY = "none"
PNG_PLOTS = ("contact force", "displacement", "force spectra", "contact filters", "roughness spectrum",
             "lateral coherence")

LOG = logging.getLogger("wheelrail.explorer")
DEFAULT_SET = "corrugated-rail"
DEFAULT_LENGTH = 3.0  # m
REPLAY_SPEEDS = {"0.01x": 0.01, "0.02x": 0.02, "0.05x": 0.05, "0.1x": 0.1}  # of real time
REPLAY_FPS = 20.0


def _help_text() -> str:
    models = "\n".join(f"- **{m}**: {model_entry(m).label}" for m in MODEL_CHOICES[:-1])
    return (
        "**Contact models** (Pieringer, Kropp & Thompson, Wear 271, 2011):\n\n" + models +
        f"\n- **{COMPARE}**: every model one after another on the same configuration, {REFERENCE_MODEL} first.\n\n"
        "**Contact filter**: a contact patch is several millimetres long and wide, so roughness of shorter "
        "wavelengths is partly averaged out before it excites the wheel and rail. The *contact filter* of a "
        f"model is its force level minus that of `{REFERENCE_MODEL}` (a point contact, no filtering), per "
        "third-octave band: 0 dB means no filtering, negative values show how much the patch attenuates. "
        "Dashed: reference filters for the same load and speed (CNOSSOS-EU A3 of noise mapping, and the "
        "analytic averaging and circular-patch filters).\n\n"
        "**Contact geometry**: wheel radius (rolling, along the rail), rail crown radius (across) and wheel "
        "tread radius across (empty: a cylindrical tread; negative: a concave, worn tread, which must stay "
        "flatter than the crown), in mm; empty fields keep the paper's crossed cylinders of 390 mm (a circular "
        "patch). Otherwise the patch is an ellipse, drawn with its Hertz semi-axes.\n\n"
        "**Wheel roughness**: a bundled wheel set added to a rail set (r = r_rail + r_wheel, the wheel's lines "
        "repeating with its circumference); `none`: a smooth wheel, as in the paper.\n\n"
        "**Run length**: at least long enough for a force spectrum at the chosen speed, at most what the "
        "roughness set holds; the page shows the range.")


class ExplorerApp:
    """The explorer around one :class:`viser.ViserServer`; also the run controller's listener."""

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, *, roughness: str = DEFAULT_SET,
                 length: float = DEFAULT_LENGTH, max_upload_bytes: int = MAX_UPLOAD_BYTES,
                 verbose: bool = False) -> None:
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
        self.replay: Entry | None = None  # the run the Step slider and Play show
        self.last_error: str | None = None
        self.last_download: tuple[str, int] | None = None
        self._setting_overlay = False
        self._playing = False
        try:
            self.scene = PatchScene(self.server)
            self._build_controls(roughness, length)
            self._build_tabs()
            refuse_large_uploads_early(self.server, lambda: self.max_upload_bytes, self.report_error)
            self.select_set(self.set_dropdown.value)
        except BaseException:
            self.server.stop()
            raise
        self.status("Ready: choose a set, a line and a model, then press **Run**.")

    # ------------------------------------------------------------------ controls
    def _build_controls(self, roughness: str, length: float) -> None:
        gui = self.server.gui
        gui.configure_theme(control_width="large", show_share_button=False)
        gui.add_markdown("**wheelrail explorer**: vertical wheel/rail interaction")
        self.status_md = gui.add_markdown("")
        with gui.add_folder("Run"):
            names = bundled_names()
            self.set_dropdown = gui.add_dropdown("Roughness set", names,
                                                 initial_value=roughness if roughness in names else names[0])
            self.wheel_set_dropdown = gui.add_dropdown(
                "Wheel roughness", (NO_WHEEL_SET, *self._wheel_set_names()), initial_value=NO_WHEEL_SET,
                hint="A wheel set added to the rail set (combined roughness); none: a smooth wheel.")
            self.upload_button = gui.add_upload_button(
                f"Upload CSV/NPZ (<= {size_text(self.max_upload_bytes)})", icon=viser.Icon.UPLOAD,
                hint="A roughness file in the CSV or NPZ format of the user guide (Roughness data); read in memory.")
            self.model_dropdown = gui.add_dropdown("Contact model", MODEL_CHOICES, initial_value="3d",
                                                   hint=f"{COMPARE}: every model one after another")
            self.line_dropdown = gui.add_dropdown("Line", ("0",), initial_value="0",
                                                  hint="Only the lines this model can run on are offered.")
            self.speed_text = gui.add_text("Speed (km/h)", "100", hint=accepted_text("speed"))
            self.preload_text = gui.add_text("Preload (kN)", "65", hint=accepted_text("preload"))
            self.length_text = gui.add_text("Run length (m)", f"{length:g}")
            radius_mm = f"{ContactParameters().radius * 1e3:g}"
            self.wheel_radius_text = gui.add_text(
                "Wheel radius (mm)", "", hint=f"Rolling radius, along the rail, {accepted_text('wheel_radius')}; "
                                             f"empty: {radius_mm} mm")
            self.crown_radius_text = gui.add_text(
                "Rail crown radius (mm)", "", hint=f"Rail head, across the rail, {accepted_text('rail_crown_radius')}; "
                                                  f"empty: {radius_mm} mm")
            self.tread_radius_text = gui.add_text(
                "Wheel tread radius across (mm)", "",
                hint=f"{accepted_text('wheel_transverse_radius')}; empty: cylindrical; negative: concave (worn)")
            self.check_md = gui.add_markdown("")
            self.run_button = gui.add_button("Run", icon=viser.Icon.PLAYER_PLAY, color="green")
            self.stop_button = gui.add_button("Stop", icon=viser.Icon.PLAYER_STOP, color="red", disabled=True)
            self.progress_bar = gui.add_progress_bar(0.0, animated=False)
        self.set_dropdown.on_update(lambda event: self._guarded(self.select_set, self.set_dropdown.value,
                                                                client=event.client))
        for handle in (self.model_dropdown, self.line_dropdown, self.speed_text, self.preload_text,
                       self.length_text, self.wheel_radius_text, self.crown_radius_text, self.tread_radius_text):
            handle.on_update(lambda event: self._guarded(self.refresh))
        self.wheel_set_dropdown.on_update(lambda event: self._guarded(self.select_wheel_set, client=event.client))
        self.upload_button.on_upload(self._on_upload)
        self.run_button.on_click(lambda event: self.start_run(client=event.client))
        self.stop_button.on_click(lambda event: self.controller.stop())

    def _build_tabs(self) -> None:
        gui = self.server.gui
        tabs = gui.add_tab_group()
        patch, spectra, rough, helps = (tabs.add_tab("Patch", viser.Icon.CIRCLE),
                                        tabs.add_tab("Spectra and filters", viser.Icon.CHART_LINE),
                                        tabs.add_tab("Roughness", viser.Icon.WAVE_SINE),
                                        tabs.add_tab("Help", viser.Icon.HELP))
        with patch:
            self.colour_bar = gui.add_image(colour_bar_image(1000.0), label="pressure", format="png")
            self.readout_md = gui.add_markdown("")
            self.surfaces_box = gui.add_checkbox("Rail and wheel surfaces", False,
                                                 hint="Roughness drawn 200 times its size, 1.5 mm off the patch")
            self.raised_box = gui.add_checkbox("Raised pressure surface", False, hint="3 mm per GPa")
            self.time_slider = gui.add_slider("Step", min=0, max=1, step=1, initial_value=0, disabled=True)
            self.play_button = gui.add_button("Play", icon=viser.Icon.PLAYER_PLAY, disabled=True)
            self.replay_speed = gui.add_dropdown("Replay speed", tuple(REPLAY_SPEEDS), initial_value="0.02x")
            self.rrd_button = gui.add_button("Download run (.rrd)", icon=viser.Icon.DOWNLOAD, disabled=True)
        self.plots = CasePlots(gui, patch, spectra)
        with spectra:
            self.csv_button = gui.add_button("Download spectra (.csv)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.overlay_dropdown = gui.add_dropdown(
                "Overlay a run", (NO_OVERLAY,), initial_value=NO_OVERLAY,
                hint="Runs of this session: draw another configuration's spectra and filters dashed beside these")
            self.png_choice = gui.add_dropdown("Plot as PNG", PNG_PLOTS, initial_value=PNG_PLOTS[3])
            self.png_button = gui.add_button("Download plot (.png)", icon=viser.Icon.PHOTO)
            gui.add_markdown("Contact filter: model level minus `hertz` (solid, needs a `hertz` run of the same "
                             "configuration: use `compare`); dashed: reference filters at this preload and speed.")
        with rough:
            self.line_map = gui.add_image(np.full((10, 10, 3), 255, dtype=np.uint8),
                                          label="Lines across the running surface", format="png")
            self.roughness_md = gui.add_markdown("")
        self.roughness_plot = Plot(gui, rough, "Roughness spectrum", "band (Hz)", "dB re 1 um", log_x=True)
        self.coherence_plot = Plot(gui, rough, "Lateral coherence", "band (Hz)", "gamma^2", log_x=True)
        with helps:
            gui.add_markdown(_help_text())
        self.surfaces_box.on_update(lambda event: self._guarded(self._on_surfaces))
        self.raised_box.on_update(lambda event: self._guarded(self._on_raised))
        self.time_slider.on_update(lambda event: self._guarded(self.scrub, self.time_slider.value))
        self.play_button.on_click(lambda event: self._guarded(self.toggle_play))
        self.rrd_button.on_click(lambda event: self._guarded(self.download_rrd, event.client, client=event.client))
        self.csv_button.on_click(lambda event: self._guarded(self.download_spectra_csv, event.client,
                                                             client=event.client))
        self.overlay_dropdown.on_update(lambda event: None if self._setting_overlay else self._guarded(self._show_case))
        self.png_button.on_click(lambda event: self._guarded(self.download_plot_png, self.png_choice.value,
                                                             event.client, client=event.client))

    # ------------------------------------------------------------------ set, line, configuration
    def select_set(self, name: str) -> None:
        """Make ``name`` (a bundled set or an uploaded file's label) the current roughness set."""
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
        self.roughness_md.content = (f"{rough.kind}, {rough.n_lines} lines {rough.lateral_spacing * 1e3:.3g} mm "
                                     f"apart, {rough.length:.3g} m at {rough.dx * 1e3:.3g} mm. {desc}")
        self.refresh()

    def _preload_or_default(self) -> float:
        try:
            kn = float(self.preload_text.value)
        except ValueError:
            kn = 0.0
        lo, hi = PRELOAD_RANGE_KN
        return kn * 1e3 if lo <= kn <= hi else ContactParameters().preload

    def _geometry(self) -> tuple:
        """The geometry fields read (one WheelrailError in the page's words if one is bad)."""
        return read_geometry(wheel_radius_mm=self.wheel_radius_text.value,
                             rail_crown_radius_mm=self.crown_radius_text.value,
                             wheel_transverse_radius_mm=self.tread_radius_text.value)

    def _contact_or_default(self) -> ContactParameters:
        """The contact the fields describe; a field not valid yet counts as its default (the check line says)."""
        try:
            return ContactParameters(preload=self._preload_or_default(), **dict(self._geometry()))
        except WheelrailError:  # a geometry refused (at this preload, e.g. a patch too wide): the default's
            return ContactParameters(preload=self._preload_or_default())

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

    def _offer_lines(self) -> None:
        """The Line menu: the lines the model can run on (core's rule); a line no longer offered moves to the
        nearest one offered, and the page says so."""
        try:
            wheel = self._wheel()[0] if self.roughness.kind == "rail" else None
        except WheelrailError:
            wheel = None
        lines = offered_lines(self.roughness, self.model_dropdown.value, self._contact_or_default(), wheel)
        if not lines:
            lines = tuple(int(n) for n in self.roughness.line_numbers)
        options = tuple(str(n) for n in lines)
        current = self.line_dropdown.value
        if tuple(self.line_dropdown.options) != options:
            self.line_dropdown.options = options
        try:
            wanted = int(current)
        except ValueError:
            wanted = 0
        if str(wanted) not in options:
            nearest = min(lines, key=lambda n: (abs(n - wanted), n))
            self.line_dropdown.value = str(nearest)
            if current in ("", "0") or wanted == 0:
                return
            self.status(f"Line {wanted} is not offered for {self.model_dropdown.value} on "
                             f"{self.roughness_label}; line {nearest} is chosen.")
        elif self.line_dropdown.value != str(wanted):
            self.line_dropdown.value = str(wanted)

    def read_config(self) -> RunConfig:
        """The configuration the controls describe, or one WheelrailError in the page's words."""
        wheel, wheel_label = self._wheel()
        return read_config(self.roughness, self.roughness_label, line=self.line_dropdown.value,
                           model=self.model_dropdown.value, speed_kmh=self.speed_text.value,
                           preload_kn=self.preload_text.value, length_m=self.length_text.value,
                           geometry=self._geometry(), wheel=wheel, wheel_label=wheel_label)

    def refresh(self) -> None:
        """After any control changed: offered lines, the check line, and the plots of that configuration."""
        with self._lock:
            self._offer_lines()
            try:
                speed = float(self.speed_text.value) * KMH
            except ValueError:
                speed = 100 * KMH
            shortest, longest = length_range(self.roughness, max(speed, MIN_SPEED_KMH * KMH))
            try:
                config = self.read_config()
            except WheelrailError as error:
                config = None
                self.check_md.content = f"**Cannot run:** {page_message(error)}"
            else:
                self.check_md.content = (f"Run length {shortest:g} to {longest:g} m on this set at "
                                         f"{config.speed / KMH:g} km/h.")
            changed = config is None or self.shown is None or config != self.shown
            self.shown = config
            if changed:
                self._show_case()
            self._update_preload_views()
            self._update_roughness_views()

    def _overlay(self) -> RunConfig | None:
        """The run list: other configurations of this session with a spectrum; the one chosen to overlay."""
        runs = {label: c for label, c in self.store.run_list().items()
                if self.shown is None or c.case() != self.shown.case()}
        options = (NO_OVERLAY, *runs)
        if tuple(self.overlay_dropdown.options) != options:
            chosen = self.overlay_dropdown.value
            self._setting_overlay = True  # the menu's own update is not a user's choice
            try:
                self.overlay_dropdown.options = options
                self.overlay_dropdown.value = chosen if chosen in options else NO_OVERLAY
            finally:
                self._setting_overlay = False
        return runs.get(self.overlay_dropdown.value)

    def _show_case(self) -> None:
        config = self.shown
        overlay = self._overlay()
        with self.server.atomic():
            self.plots.show_case(config, self.store, overlay)
            entries = self.store.entries(config.case()) if config else {}
            self.csv_button.disabled = not any(e.spectrum is not None for e in entries.values())
            entry = entries.get(config.model) if config else None
            if entry is None and entries:
                entry = list(entries.values())[-1]
            self._set_replay(entry)

    def _set_replay(self, entry: Entry | None) -> None:
        self.replay = entry if entry is not None and entry.result.n_steps else None
        self.rrd_button.disabled = self.play_button.disabled = self.replay is None
        self.time_slider.disabled = self.replay is None or self.controller.running
        if self.replay is not None:
            self.time_slider.max = max(1, self.replay.result.n_steps - 1)

    # ------------------------------------------------------------------ runs (RunListener)
    def start_run(self, client=None) -> bool:
        """What the Run button does: check the controls, replace any run, start in the background."""
        try:
            config = self.read_config()
        except WheelrailError as error:
            self.report_error(page_message(error), client)
            return False
        self._playing = False
        self.last_error = None
        self.scene.frames_drawn = 0
        self.progress_bar.value, self.progress_bar.animated = 0.0, True
        self.stop_button.disabled = False
        self.time_slider.disabled = True
        wheel = None if config.wheel_set_label is None else self._sets[config.wheel_set_label]
        self.controller.start(config, self.roughness, wheel)
        return True

    def status(self, text: str) -> None:
        self.status_md.content = text

    def progress(self, fraction: float) -> None:
        self.progress_bar.value = round(100.0 * min(max(fraction, 0.0), 1.0), 1)

    def frame(self, state, view: RunView) -> None:
        with self.server.atomic():
            self.scene.draw(state, view)
            self._readout(state, view.config)

    def _readout(self, state, config: RunConfig) -> None:
        self.readout_md.content = (f"**{config.model}** step {state.step}: x = {state.position:.4f} m, "
                                   f"F = {state.force / 1e3:.2f} kN, contact length "
                                   f"{state.contact_length * 1e3:.1f} mm")

    def live(self, result, view: RunView) -> None:
        if self.shown is not None and view.config.case() == self.shown.case():
            self.plots.live(result, view.config)

    def model_done(self, entry: Entry, view: RunView) -> None:
        if self.shown is not None and entry.config.case() == self.shown.case():
            overlay = self._overlay()
            with self.server.atomic():
                self.plots.show_case(self.shown, self.store, overlay)
                self.csv_button.disabled = not self.store.spectra(self.shown.case())
                self._set_replay(entry)

    def error(self, message: str) -> None:
        self.report_error(message)

    def finished(self, config: RunConfig, outcome: str) -> None:
        self.progress_bar.animated = False
        self.stop_button.disabled = True
        if self.replay is not None:
            self.time_slider.disabled = False
            self.time_slider.value = self.time_slider.max
        if outcome == "done":
            self.progress(1.0)
            self.status(f"Done: {config.label()}. Scrub with the Step slider or press Play.")

    # ------------------------------------------------------------------ replay
    def scrub(self, step: int) -> None:
        """Show step ``step`` of the replayed run (the Step slider)."""
        entry = self.replay
        if entry is None or self.controller.running:
            return
        result = entry.result
        step = int(min(max(step, 0), result.n_steps - 1))
        wheel = entry.config.wheel_set_label
        view = RunView(config=entry.config, roughness=self._sets.get(entry.config.set_label, self.roughness),
                       window_x=result.window_x, window_y=result.window_y,
                       wheel_roughness=None if wheel is None else self._sets[wheel])
        self.frame(result.state(step), view)

    def toggle_play(self) -> None:
        """Play/pause the replayed run at the chosen fraction of real time (as viser's record3d example)."""
        if self._playing:
            self._playing = False
            return
        if self.replay is None or self.controller.running:
            return
        self._playing = True
        self.play_button.label = "Pause"
        threading.Thread(target=self._play, daemon=True, name="wheelrail-explorer-replay").start()

    def _play(self) -> None:
        result = self.replay.result
        steps_per_frame = max(1, round(REPLAY_SPEEDS[self.replay_speed.value] / REPLAY_FPS / result.time_step))
        step = int(self.time_slider.value)
        if step >= result.n_steps - 1:
            step = 0
        while self._playing and step < result.n_steps:
            self.time_slider.value = step  # its callback draws the step
            step += steps_per_frame
            time.sleep(1.0 / REPLAY_FPS)
        self._playing = False
        self.play_button.label = "Play"

    # ------------------------------------------------------------------ scene options, roughness views
    def _on_surfaces(self) -> None:
        self.scene.show_surfaces = bool(self.surfaces_box.value)
        try:
            wheel = self._wheel()[0] if self.roughness.kind == "rail" else None
        except WheelrailError:
            wheel = None
        self.scene.draw_surfaces(self.roughness, None, int(self.line_dropdown.value), self._contact_or_default(),
                                 wheel)

    def _on_raised(self) -> None:
        self.scene.show_raised = bool(self.raised_box.value)
        self.scene.surface.visible = self.scene.show_raised and self.scene.heatmap.visible

    def _update_preload_views(self) -> None:
        contact = self._contact_or_default()
        self.scene.set_contact(contact)
        top = PRESSURE_TOP * contact.hertz_peak_pressure() / 1e6
        self.colour_bar.image = colour_bar_image(round(top))
        self.line_map.image = _line_map(self.roughness, int(self.line_dropdown.value), contact.hertz_semi_axes()[1])

    def _update_roughness_views(self) -> None:
        rough = self.roughness
        try:
            speed = float(self.speed_text.value) * KMH
        except ValueError:
            return
        if not MIN_SPEED_KMH * KMH <= speed <= MAX_SPEED_KMH * KMH:
            return
        lines = [k for k in range(-3, 4) if k in rough.line_numbers] or [int(rough.line_numbers[0])]
        spectrum = roughness_spectrum(rough, speed=speed, lines=lines)
        self.roughness_plot.show(finite_bands(spectrum.band_centres, [spectrum.levels_db]),
                                 ((f"lines {lines[0]}..{lines[-1]}", "#1f77b4", False),),
                                 title=f"Roughness spectrum: {self.roughness_label} at {speed / KMH:g} km/h")
        half = min(3, int(rough.line_numbers[-1]), -int(rough.line_numbers[0]))
        if half >= 1:
            centres, gamma2 = lateral_coherence(rough, speed, half_lines=half)
            self.coherence_plot.show(finite_bands(centres, [gamma2]), ((f"gamma^2, M = {half}", "#2ca02c", False),),
                                     title=f"Lateral coherence: {self.roughness_label}")
        else:
            self.coherence_plot.clear("one line only")

    # ------------------------------------------------------------------ uploads and downloads
    def _on_upload(self, event) -> None:
        uploaded = event.target.value
        try:
            self.load_upload(uploaded.name, uploaded.content, event.client)
        except WheelrailError as error:
            # viser's own notice "File uploaded successfully" only means the bytes arrived: say plainly
            # beside it that the file was not loaded, and why
            self.report_error(str(error), event.client, title="File received but not loaded")

    def load_upload(self, name: str, content: bytes, client=None) -> str:
        label, rough = read_upload(name, content, self.max_upload_bytes)
        self._sets[label] = rough
        options = tuple(self.set_dropdown.options)
        if label not in options:
            self.set_dropdown.options = (*options, label)
        self.set_dropdown.value = label  # its callback selects it
        if self.roughness_label != label:
            self.select_set(label)
        self.status(f"Loaded {label}: {rough.kind}, {rough.n_lines} lines, {rough.length:.3g} m.")
        LOG.info("uploaded %s", label)
        return label

    def download_rrd(self, client=None) -> tuple[str, bytes]:
        """The replayed run as a rerun recording, named after its configuration."""
        import tempfile

        from wheelrail.core.recording import record_result

        entry = self.replay
        if entry is None:
            raise WheelrailError("no run of this configuration to save yet: press Run first")
        name = entry.config.file_stem() + ".rrd"
        with tempfile.TemporaryDirectory(prefix="wheelrail-rrd-") as folder:
            path = Path(folder) / name
            record_result(entry.result, path, roughness=self._sets.get(entry.config.set_label, self.roughness),
                          description=f"wheelrail explorer: {entry.config.label()}")
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

    def download_plot_png(self, which: str, client=None) -> tuple[str, bytes]:
        """One plot as shown (its title names the configuration), as a PNG named after the configuration."""
        plots = {**self.plots.by_name(), "roughness spectrum": self.roughness_plot,
                 "lateral coherence": self.coherence_plot}
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

    def report_error(self, message: str, client=None, title: str = "wheelrail") -> None:
        self.last_error = message
        LOG.warning("error shown in the page: %s", message)
        self.status(f"**Error:** {message}")
        for target in [client] if client is not None else list(self.server.get_clients().values()):
            try:
                target.add_notification(title, message, color="red", auto_close_seconds=None)
            except Exception:  # a tab that closed meanwhile
                pass

    def close(self) -> None:
        """Cancel any run and stop the server."""
        self._playing = False
        self.controller.cancel_current()
        self.server.stop()


def _line_map(rough, line: int, hertz_radius: float) -> np.ndarray:
    """Small map of the lines across the rail with the chosen line and the nominal contact width across
    (2 ``hertz_radius``: 2b, the Hertz semi-axis across, for an elliptic patch)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    y = rough.y * 1e3
    y_line = float(y[rough.row_of_line(line)]) if line in rough.line_numbers else 0.0
    a = hertz_radius * 1e3
    fig = Figure(figsize=(3.6, 0.95), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.04, 0.42, 0.92, 0.4))
    ax.axvspan(y_line - a, y_line + a, color="#f0c800", alpha=0.35, lw=0)
    ax.vlines(y, 0, 1, color="#777777", lw=1)
    ax.vlines([y_line], 0, 1, color="#d62728", lw=2.5)
    ax.set_yticks([])
    ax.set_xlim(y[0] - 1.5, y[-1] + 1.5)
    ax.tick_params(labelsize=7, length=2)
    ax.set_xlabel(f"lateral position (mm); line {line} red, width {2 * a:.1f} mm yellow", fontsize=7, labelpad=1)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


def serve(host: str = "127.0.0.1", port: int = 8080, *, roughness: str = DEFAULT_SET,
          length: float = DEFAULT_LENGTH) -> int:
    """Start the explorer and serve until interrupted (Ctrl-C); runs and errors are logged to the terminal."""
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s", datefmt="%H:%M:%S")
    app = ExplorerApp(host, port, roughness=roughness, length=length, verbose=False)
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
