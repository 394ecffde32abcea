"""The Wheel tab: the modal wheel (``wheelrail.core.modal_wheel``) at the run's wheel radius, its shape, its natural
frequencies by family and nodal diameters n, its point and cross receptances at the contact beside the track's
point receptance (the Track tab's curves, on the same frequency axis) and its sound power per band for a unit
radial force (``wheelrail.core.noise.wheel_power``, the noise chain's modal wheel)."""

from __future__ import annotations

import logging
import threading
import time

import numpy as np
import viser

from wheelrail.core.drawing.palette import TOTAL_COLOUR, WHEEL_SURFACE_COLOURS
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import describe_track
from wheelrail.core.modal_wheel import describe_wheel
from wheelrail.core.noise.wheel_power import MAX_FREQUENCY, MAX_HARMONIC, WHEEL_POINTS_PER_BAND
from wheelrail.explorer.config import (
    FIELD_NAMES,
    NEAREST_WHEEL,
    WHEEL_SHAPE_KEYS,
    page_message,
    read_wheel,
)
from wheelrail.explorer.panel import ResultsTab, Shown, TabParts
from wheelrail.explorer.plots import SOLID, Plot, bands_with_data
from wheelrail.explorer.track_tab import TrackTab

__all__ = ["MODE_SETTINGS", "WheelTab", "frequency_rows", "wheel_band_power", "wheel_words"]

LOG = logging.getLogger("wheelrail.explorer")
# the noise chain's modes (wheel_power: n = 0..10 up to 12.5 kHz): one computation serves the plots and the power
MODE_SETTINGS = {"max_frequency": MAX_FREQUENCY, "max_harmonic": MAX_HARMONIC}
RECEPTANCE_RANGE_HZ = (50.0 / 2 ** (1 / 6), 5000.0 * 2 ** (1 / 6))  # the Track tab's bands 50 Hz-5 kHz, edge to edge
GRID_POINTS = 3000  # log-spaced frequencies of the wheel's curves, every natural frequency in range added
KEPT_WHEELS = 8  # the shapes whose modes and power the tab keeps in memory (the disk cache keeps the modes)
MAX_ORDERS = 3  # the plot joins the 1st, 2nd and 3rd mode of a family by frequency across n; the table has all
FAMILY_COLOURS = {
    "axial": ("#1f77b4", "#6baed6", "#9ecae1"),
    "radial": ("#d62728", "#fb6a4a", "#fcae91"),
    "circumferential": ("#2ca02c", "#74c476", "#a1d99b"),
}
RECEPTANCE_COLOURS = {
    "wheel radial": "#d62728",
    "wheel axial": "#1f77b4",
    "wheel cross": "#9467bd",
    "track above a sleeper": "#636363",
    "track midspan": "#bdbdbd",
}
POWER_COLOURS = {**WHEEL_SURFACE_COLOURS, "total": TOTAL_COLOUR}  # core's palette; the total drawn last, on top
WHEEL_NOTE = (
    "The modal wheel: axisymmetric finite elements of the wheel's cross-section with n nodal diameters "
    "(`wheelrail wheel`; the bore clamped on the axle, steel), at the rolling radius of the settings on the left "
    "(*Contact geometry*). Its shape is the named wheel chosen here, each dimension typed below replacing that "
    "wheel's (empty: the named wheel's). *Receptance*: displacement per force at the contact, radial (along the "
    "track's vertical), axial (along the axle) and cross (radial per axial force: the contact's offset from the "
    "web couples them), beside the track's vertical point receptance (the Track tab's, between its band centres); "
    "the wheel's curves pass through each natural frequency, so the peaks are at their full height (loss factors "
    "1e-3 for n = 0, 1 and 1e-4 from n = 2, plus a damper's added loss factor). *Sound power*: one wheel's, "
    "per third-octave band, for a radial force of 1 N RMS at the contact in each band (the band mean of W / F^2 "
    f"over {WHEEL_POINTS_PER_BAND} frequencies, as the noise chain's `--wheel-model modal` computes it: each "
    "family's radiation efficiency by n times its surfaces' mean-square velocity), split into the axially "
    "facing surfaces (web, rim sides, hub) and the radially facing ones (tread); without the added loss factor, "
    "as the chain."
)


class WheelTab(ResultsTab):
    """The modal wheel of the configuration shown (module docstring). Its modes, then its sound power, are computed
    once per shape in the background by one worker (seconds for the modes, then kept on disk; the radiation table
    a minute or more the first time for a radius, tyre width and bore), the latest shape asked for first;
    ``mode_settings`` are those of :func:`wheelrail.core.modal_wheel.wheel_modes` and ``points_per_band`` the
    power's band means' (tests set fewer)."""

    title, icon = "Wheel", viser.Icon.DISC

    def __init__(self, parts: TabParts, tab) -> None:
        super().__init__(parts, tab)
        gui, page = self.gui, self.page
        self.mode_settings = dict(MODE_SETTINGS)
        self.frequencies = Plot(gui, tab, "Natural frequencies", "nodal diameters n", "frequency (Hz)")
        self.receptance = Plot(gui, tab, "Receptance at the contact", "frequency (Hz)", "dB re 1 m/N", bands=True)
        self.power = Plot(gui, tab, "Sound power for 1 N", "band (Hz)", "dB re 1 pW", bands=True)
        with tab:
            self.wheel_md = gui.add_markdown("")
            self.table_md = gui.add_markdown("")
            with gui.add_folder("Wheel shape", expand_by_default=False):
                self.name_dropdown = gui.add_dropdown(
                    "Named wheel",
                    (NEAREST_WHEEL, *_named_wheels()),
                    initial_value=NEAREST_WHEEL,
                    hint="Its rim, web and hub, at the run's wheel radius; nearest: the one nearest in radius",
                )
                self.shape_fields = {key: _shape_field(gui, key) for key in WHEEL_SHAPE_KEYS}
                self.added_text = gui.add_text(
                    "Added loss factor", "", hint="A damper's loss factor added to every mode, 0 to 1; empty: 0"
                )
            self.compute_button = gui.add_button(
                "Compute the wheel",
                icon=viser.Icon.PLAYER_PLAY,
                hint="Its modes (seconds) and sound power (a minute or more the first time for a radius, rim and "
                "bore); asked for here, so a first Run does not share the machine with it. Later shapes follow.",
            )
            self.compute_button.on_click(lambda _: page.guarded(self.ask))
            self.power_bar = gui.add_progress_bar(0.0, visible=False)  # the sound power's progress, while computed
            for handle in (self.name_dropdown, *self.shape_fields.values(), self.added_text):
                handle.on_update(lambda event: None if page.is_quiet() else page.guarded(parts.redraw, self))
            gui.add_markdown(WHEEL_NOTE)
            self._plot_export()
        self.points_per_band = WHEEL_POINTS_PER_BAND  # the sound power's band means
        self._modes: dict = {}  # (profile, settings) -> WheelModes, or the error's words
        self._power: dict = {}  # (profile, points per band) -> wheel_band_power's, or the error's words
        self.asked = False  # the user pressed Compute the wheel: shapes are then computed as they are shown
        self._wanted = None  # the key the worker computes next
        self._working = False
        self._lock = threading.Lock()
        self._last: Shown | None = None
        self._progress: tuple | None = None  # (power key, words) of the sound power being computed
        self._following = False
        self.caption = self.track_caption = ""  # the wheel and the track shown, in words (show)

    def plots(self) -> dict[str, Plot]:
        return {
            "wheel natural frequencies": self.frequencies,
            "wheel receptance": self.receptance,
            "wheel sound power": self.power,
        }

    # ------------------------------------------------------------------ modes and power, in the background
    def want(self, profile) -> tuple:
        """The wheel's (modes, band power) once computed (None: not yet, being computed; a str: why they cannot be);
        the worker computes what is missing, modes first."""
        key = (profile, tuple(sorted(self.mode_settings.items())))
        found = self._modes.get(key), self._power.get(self._power_key(key))
        if self.asked and (found[0] is None or found[1] is None):
            with self._lock:
                self._wanted = key
                if not self._working:
                    self._working = self.parts.workers.start(self._work, name="wheelrail-wheel-tab") is not None
        return found

    def ask(self) -> None:
        """Compute the wheel shown, and from now on every shape shown (the button's callback)."""
        self.asked = True
        self.parts.redraw(self)

    def _power_key(self, key) -> tuple:
        return key[0], self.points_per_band

    def _work(self) -> None:
        """Compute what the shape asked for last lacks, until it has all (shapes typed meanwhile are skipped)."""
        while True:
            with self._lock:
                key = self._wanted
                job = None
                if self.parts.workers.closed.is_set():  # the page is closed: nothing more is computed
                    pass
                elif key is not None and key not in self._modes:
                    job = self.compute
                elif key is not None and self._power_key(key) not in self._power:
                    job = self.compute_power
                if job is None:
                    self._working = False
                    return
            job(key)

    def compute(self, key) -> None:
        """The modes of ``key`` = (profile, settings), then a redraw (what the worker thread does)."""
        from wheelrail.core.modal_wheel import wheel_modes

        profile, settings = key
        _keep(self._modes, key, _or_words(lambda: wheel_modes(profile, **dict(settings))))
        if self._last is not None:
            self.parts.redraw(self)

    def compute_power(self, key) -> None:
        """The sound power per band of ``key``'s wheel, then a redraw (what the worker thread does next)."""
        from wheelrail.core.noise.wheel_power import radiation_progress

        modes = self._modes.get(key)
        with radiation_progress(self._power_progress(key)):
            power = (
                modes if isinstance(modes, str) else _or_words(lambda: wheel_band_power(key[0], self.points_per_band))
            )
        self._progress = None
        self.power_bar.visible = False
        _keep(self._power, self._power_key(key), power)
        if self._last is not None:
            self.parts.redraw(self)

    def _power_progress(self, key):
        """The sound power's ``progress(phase, done, total)``: the phase, the tab's bar and, once a part is done,
        the time left from the pace so far, in the power plot's line while ``key``'s wheel is the one shown."""
        began = {}

        def progress(phase: str, done: int, total: int) -> None:
            began.setdefault(phase, time.perf_counter())
            words = f"computing the wheel's sound power: {phase} ({done} of {total})"
            if 0 < done < total:
                words += f", about {(time.perf_counter() - began[phase]) * (total - done) / done:.0f} s left"
            self._progress = (self._power_key(key), words)
            if self._wanted == key and not self.parts.workers.closed.is_set():
                self.power.clear(f"{words} ...")
                self.power_bar.value = round(100.0 * done / total, 1)
                self.power_bar.visible = True

        return progress

    # ------------------------------------------------------------------ drawing
    def read(self, config):
        """(profile, added loss factor) of the tab's fields at the run's wheel radius, or one WheelrailError."""
        shape = {key: field.value for key, field in self.shape_fields.items()}
        radius = config.params().contact.radius_along
        return read_wheel(self.name_dropdown.value, radius, shape, self.added_text.value)

    def show(self, shown: Shown) -> None:
        self._last = shown
        config = shown.config
        if config is None:
            self._clear("Fix the settings on the left for this run's wheel.")
            return
        try:
            profile, added = self.read(config)
        except WheelrailError as error:
            self._clear(f"**Cannot make this wheel:** {page_message(error)}")
            return
        modes, power = self.want(profile)
        words = wheel_words(profile, self.name_dropdown.value, added)
        # each plot's title names the wheel, the receptance's the track too (core's words)
        self.caption, self.track_caption = describe_wheel(profile), describe_track(config.params())
        if modes is None or isinstance(modes, str):
            if modes is not None:
                why = f"**No modes for this wheel:** {modes}"
            elif self.asked:
                why = "Computing the wheel's modes (a few seconds, once per shape) ..."
            else:
                why = (
                    "Press **Compute the wheel** (below, under the *Wheel shape* folder) for this wheel's modes "
                    "and sound power."
                )
            self._clear(f"{words}\n\n{why}")
            return
        self.wheel_md.content = (
            f"{words} {len(modes.frequency)} modes up to {modes.max_frequency:g} Hz, n = 0..{modes.max_harmonic}."
        )
        self.table_md.content = _frequency_table(modes)
        for plot in self.plots().values():
            plot.visible = True
        self._draw_frequencies(modes)
        self._draw_receptance(modes, added, self._track_curves(config))
        if power is None or isinstance(power, str):
            if power is not None:
                why = power
            elif self._progress is not None and self._progress[0] == (profile, self.points_per_band):
                why = f"{self._progress[1]} ..."
            elif self.asked:
                why = "computing the wheel's sound power (seconds; a minute or more for a new radius or rim) ..."
            else:
                why = "press Compute the wheel for its sound power"
            self.power.clear(why)
        else:
            self._draw_power(power)

    def _clear(self, words: str) -> None:
        """No modes to draw: the plots hidden (nothing empty above the tab's fields and button), ``words`` (markdown)
        say why."""
        for plot in self.plots().values():
            plot.visible = False
        self.wheel_md.content, self.table_md.content = words, ""

    def _track_curves(self, config) -> dict | str:
        """The Track tab's band receptances of the configuration's track, or why there are none (being computed:
        this tab is redrawn when they are; or the track's error)."""
        track_tab = self.parts.find_tab(TrackTab)
        if not self._following:
            track_tab.followers.append(self)
            self._following = True
        curves = track_tab.curves(config.params().track)
        if curves is None:
            return "being computed ..."
        return curves[0] if isinstance(curves, tuple) else curves

    def _draw_frequencies(self, modes) -> None:
        n = np.arange(modes.max_harmonic + 1, dtype=float)
        series, columns = [], []
        for family, orders in frequency_rows(modes).items():
            for order, values in enumerate(orders[:MAX_ORDERS]):
                series.append((f"{family} {_ordinal(order + 1)}", FAMILY_COLOURS[family][order], SOLID))
                columns.append(values)
        if not series:
            self.frequencies.clear(f"no mode below {modes.max_frequency:g} Hz")
            return
        title = f"Natural frequencies by family and n: {self.caption}"
        self.frequencies.show((n, *columns), tuple(series), title=title)

    def _draw_receptance(self, modes, added: float, track: dict | str) -> None:
        from wheelrail.core.modal_wheel import contact_receptance

        low, high = RECEPTANCE_RANGE_HZ
        natural = modes.frequency[(modes.frequency > low) & (modes.frequency < high)]
        centres = track["frequency_hz"] if isinstance(track, dict) else np.zeros(0)
        f = np.unique(np.concatenate([np.geomspace(low, high, GRID_POINTS), natural, centres]))
        wheel = contact_receptance(modes, f, added_loss_factor=added)
        curves = {
            "wheel radial": wheel.radial,
            "wheel axial": wheel.axial,
            "wheel cross": wheel.cross,
        }
        columns = {name: 20 * np.log10(np.maximum(np.abs(values), 1e-30)) for name, values in curves.items()}
        if isinstance(track, dict):
            bands = track["frequency_hz"]
            inside = (f >= bands[0]) & (f <= bands[-1])
            for name, key in (("track above a sleeper", "above_sleeper_m_per_n"), ("track midspan", "midspan_m_per_n")):
                level = np.interp(np.log10(f), np.log10(bands), 20 * np.log10(track[key]))
                columns[name] = np.where(inside, level, np.nan)
        series = tuple((name, RECEPTANCE_COLOURS[name], SOLID) for name in columns)
        title = f"Receptance at the contact: {self.caption}; " + (
            self.track_caption if isinstance(track, dict) else f"the track's: {track}"
        )
        self.receptance.show(bands_with_data(f, list(columns.values())), series, title=title)

    def _draw_power(self, power: dict) -> None:
        parts = {name: 10 * np.log10(np.maximum(power[key], 1e-30) / 1e-12) for name, key in _POWER_PARTS}
        series = tuple((name, POWER_COLOURS[name], SOLID) for name in parts)
        self.power.show(
            bands_with_data(power["frequency_hz"], list(parts.values())),
            series,
            title=f"Sound power of one wheel for 1 N radial force at the contact: {self.caption}",
        )


# the total last: a later curve is drawn over an earlier one, so the total is never hidden under a part equal to it
_POWER_PARTS = (("axial surfaces", "axial"), ("radial surfaces", "radial"), ("total", "power_per_force"))


def wheel_band_power(profile, points_per_band: int = WHEEL_POINTS_PER_BAND) -> dict:
    """One wheel's sound power per unit mean-square radial contact force, W/N^2, per band of the noise chain
    (``frequency_hz``: 50 Hz-10 kHz): ``power_per_force`` and its ``axial`` and ``radial`` surfaces' parts, each
    the mean over ``points_per_band`` frequencies spread evenly in lg f across the band
    (:func:`wheelrail.core.noise.wheel_power.modal_wheel_response`, as ``modal_wheel_band_means``)."""
    from wheelrail.core.noise.twins import band_frequencies
    from wheelrail.core.noise.wheel_power import modal_wheel_response
    from wheelrail.core.parameters import ModelParameters
    from wheelrail.core.spectra.bands import noise_bands

    mass = ModelParameters().wheel.unsprung_mass  # enters only the receptance, not the power per force
    means: dict = {key: [] for _, key in _POWER_PARTS}
    for f in band_frequencies(points_per_band):  # a band at a time: the modal sums hold (points, modes, surfaces)
        response = modal_wheel_response(profile, f, mass)
        for key in means:
            means[key].append(float(np.mean(response[key])))
    return {"frequency_hz": noise_bands(), **{key: np.array(values) for key, values in means.items()}}


def _keep(found: dict, key, value) -> None:
    """``found[key] = value``, the oldest entries dropped beyond :data:`KEPT_WHEELS` (a wheel's modes hold MB)."""
    found[key] = value
    while len(found) > KEPT_WHEELS:
        del found[next(iter(found))]


def _or_words(compute):
    """``compute()``, or the words of its error (a WheelrailError in the page's words; anything else logged)."""
    try:
        return compute()
    except WheelrailError as error:
        return page_message(error)
    except Exception as error:  # keep the tab usable; the log has the traceback
        LOG.exception("the Wheel tab's computation failed")
        return f"unexpected error: {type(error).__name__}: {error}"


def _named_wheels() -> tuple[str, ...]:
    from wheelrail.core.modal_wheel import NAMED_WHEELS

    return tuple(NAMED_WHEELS)


def _shape_field(gui, key: str):
    """A shape dimension's field, mm, empty (the named wheel's), hinted with its accepted range and reason."""
    from wheelrail.core.inputs.ranges import ACCEPTED

    accepted, name = ACCEPTED[key], FIELD_NAMES[key]
    low, high = accepted.in_unit(name.scale)
    hint = (
        f"{accepted.reason[0].upper()}{accepted.reason[1:]}; {low:g} to {high:g} {name.unit}; empty: the named wheel's"
    )
    return gui.add_text(f"{name.label} ({name.unit})", "", hint=hint)


def _ordinal(k: int) -> str:
    return {1: "1st", 2: "2nd", 3: "3rd"}.get(k, f"{k}th")


def frequency_rows(modes) -> dict[str, list[np.ndarray]]:
    """Per family, its k-th natural frequency (Hz, by frequency) at each n = 0..N (NaN where it has fewer modes)."""
    from wheelrail.core.modal_wheel import FAMILIES

    rows: dict[str, list[np.ndarray]] = {}
    for family in FAMILIES:
        per_n = [
            np.sort(modes.frequency[(modes.harmonic == n) & (modes.family == family)])
            for n in range(modes.max_harmonic + 1)
        ]
        count = max((len(values) for values in per_n), default=0)
        rows[family] = [np.array([values[k] if k < len(values) else np.nan for values in per_n]) for k in range(count)]
    return rows


def _frequency_table(modes) -> str:
    """The natural frequencies (Hz) by n and family as a markdown table."""
    from wheelrail.core.modal_wheel import FAMILIES

    lines = ["| n | " + " | ".join(FAMILIES) + " |", "|---|" + "---|" * len(FAMILIES)]
    for n in range(modes.max_harmonic + 1):
        cells = []
        for family in FAMILIES:
            values = np.sort(modes.frequency[(modes.harmonic == n) & (modes.family == family)])
            cells.append(", ".join(f"{value:.0f}" for value in values) or "-")
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    return "**Natural frequencies (Hz)** by nodal diameters n and family:\n\n" + "\n".join(lines)


def wheel_words(profile, choice: str, added: float) -> str:
    """The wheel's name and dimensions in words (mm)."""
    from wheelrail.core.modal_wheel import NAMED_WHEELS

    def nearest() -> str:
        return min(NAMED_WHEELS, key=lambda key: abs(NAMED_WHEELS[key].wheel_radius - profile.wheel_radius))

    name = choice if choice != NEAREST_WHEEL else nearest()
    named = NAMED_WHEELS[name]
    mm = {key.removeprefix("wheel_"): 1e3 * getattr(profile, key.removeprefix("wheel_")) for key in WHEEL_SHAPE_KEYS}
    changed = [
        FIELD_NAMES[key].label.lower()
        for key in WHEEL_SHAPE_KEYS
        if getattr(profile, key.removeprefix("wheel_")) != getattr(named, key.removeprefix("wheel_"))
    ]
    words = [f"**Wheel:** {name}'s shape" + (f" (changed: {', '.join(changed)})" if changed else "")]
    words.append(f" at the run's rolling radius, diameter {2e3 * profile.wheel_radius:g} mm")
    if profile.wheel_radius != named.wheel_radius:
        words.append(f" ({name}: {2e3 * named.wheel_radius:g} mm)")
    words.append(f"; rim {mm['tyre_width']:g} mm wide, {mm['tyre_depth']:g} mm deep")
    words.append(f"; web {mm['web_thickness']:g} mm thick, dished {mm['web_offset']:g} mm")
    words.append(f", bulging {mm['web_curvature']:g} mm; hub {mm['hub_inner_radius']:g} to {mm['hub_outer_radius']:g}")
    words.append(f" mm radius, {mm['hub_width']:g} mm wide; ")
    has_flange = profile.flange_height > 0 and profile.flange_thickness > 0
    words.append(
        f"flange {mm['flange_height']:g} mm high, {mm['flange_thickness']:g} mm thick" if has_flange else "no flange"
    )
    words.append(f"; contact {mm['contact_offset']:g} mm from the web; added loss factor {added:g}.")
    return "".join(words)
