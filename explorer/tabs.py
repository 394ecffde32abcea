"""The results panel's tabs: each a class that builds its elements in its tab and redraws them.

A tab is a :class:`ResultsTab`: ``title`` and ``icon`` name it, ``__init__`` builds its elements (plots first,
so that they open on screen), :meth:`ResultsTab.show` redraws it for the configuration shown (a
:class:`Shown`), :meth:`ResultsTab.plots` names its plots for the PNG export below them. :data:`RESULT_TABS`
lists them in page order: another tab is one more class and one more entry. Everything
drawn comes from the :class:`~wheelrail.explorer.results.ResultStore` and from core.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np
import viser

from wheelrail.core.bands import frequency_bands, map_levels
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs import describe_words
from wheelrail.core.models import REFERENCE_MODEL, model_entry
from wheelrail.core.noise.levels import a_weighting, energy_sum
from wheelrail.core.noise.run_noise import (
    AXLE_DB,
    COMPONENTS,
    DEFAULT_TRAIN_AXLES,
    DEFAULT_TRAIN_LENGTH,
    ISO3095_DISTANCE,
    ISO3095_HEIGHT,
    pass_by_level,
)
from wheelrail.core.parameters import KMH, ContactParameters
from wheelrail.core.roughness import lateral_coherence, roughness_spectrum
from wheelrail.core.roughness.analysis import DEFAULT_LINES, FREQUENCY_RANGE
from wheelrail.core.roughness_limits import iso3095_limit
from wheelrail.core.spectra import energetic_sum
from wheelrail.explorer.config import COMPARE, MODEL_CHOICES, RunConfig, page_message, read_train
from wheelrail.explorer.plots import (
    DASHED,
    DOTTED,
    MAX_POINTS,
    SOLID,
    Plot,
    bands_with_data,
    finite_bands,
    model_colour,
)
from wheelrail.explorer.results import ResultStore, case_reference_filters

__all__ = ["RESULT_TABS", "HelpTab", "NoiseTab", "PatchTab", "ResultsTab", "RoughnessTab", "Shown", "SpectraTab"]

REFERENCE_COLOURS = {
    "cnossos": "#000000",
    "averaging": "#7f7f7f",
    "patch-correlated": "#bcbd22",
    "patch-incoherent": "#17becf",
}
ISO_LIMIT_COLOUR = "#000000"
PLOT_HINT = (
    "*Plots*: drag across one to zoom, double-click to zoom back; hover for values; the ⤢ corner "
    "button (on hover) opens it large."
)
EMPTY_BAND_DB = 120.0  # a roughness band this far below the set's highest band is empty (a numerical floor)
NO_RUN = "no run of this configuration yet"
NOISE_RANGE_DB = 60.0  # the sound-power plot shows the loudest band down by this (A-weighted, quieter bands
# matter little to the total)
COMPONENT_COLOURS = dict(zip(COMPONENTS, ("#e6550d", "#31a354", "#756bb1"), strict=True))  # rail, sleeper, wheel
CNOSSOS_COLOURS = {"track": "#636363", "vehicle": "#8c6d31", "total": "#000000"}
AUDIO_HINT = (
    "The pass-by of the train set below at the ISO 3095 position, synthesised from the run's contact force "
    "(the model shown); a few seconds to make"
)
NOISE_NOTE = (
    "*Sound power* per axle (two wheels on two rails), A-weighted per band, of the model shown: rail, sleeper and "
    "wheel (solid, their colours) and every model's total (model colours), from the run's contact force through "
    "the model track's transfer functions (the TWINS approach). Dotted: the CNOSSOS-EU source (Directive (EU) "
    "2015/996, Annex II 2.3) on the run's own roughness with its fixed contact filter A3. Dashed: a run overlaid. "
    f"*Pass-by audio*: the model shown, at {ISO3095_DISTANCE:g} m; listen for the high bands (above about 1 kHz) "
    "that a finite "
    "patch (3d, 2d) takes out and the point contact (hertz) keeps."
)


@dataclass(frozen=True)
class Shown:
    """What the page shows: the configuration the controls describe (None: not valid), the session's
    results, the model the Patch tab shows (replay, displacement, .rrd), another configuration overlaid."""

    config: RunConfig | None
    store: ResultStore
    model: str | None = None
    overlay: RunConfig | None = None


class ResultsTab:
    """One tab of the results panel (subclasses set ``title`` and ``icon`` and build in ``__init__``)."""

    title = ""
    icon = None

    def __init__(self, app, tab) -> None:
        self.app, self.gui, self.tab = app, app.server.gui, tab

    def plots(self) -> dict[str, Plot]:
        """The tab's plots by the names its PNG menu shows."""
        return {}

    def show(self, shown: Shown) -> None:
        """Redraw for the configuration shown."""

    def _overlay_menu(self, what: str):
        """The menu of the session's other runs, to overlay one (the app keeps its options and choice)."""
        return self.gui.add_dropdown(
            "Overlay a run",
            (self.app.no_overlay,),
            initial_value=self.app.no_overlay,
            hint=f"Runs of this session: draw another configuration's {what}",
        )

    def _plot_export(self) -> None:
        """The hint on zooming and, for the tab's plots, a PNG download (titled with the configuration)."""
        gui, plots = self.gui, self.plots()
        gui.add_markdown(PLOT_HINT)
        names = tuple(plots)
        self.png_choice = gui.add_dropdown("Plot", names, initial_value=names[0])
        self.png_button = gui.add_button("Download plot (.png)", icon=viser.Icon.PHOTO)
        self.png_button.on_click(
            lambda event: self.app._guarded(
                self.app.download_plot_png, self.png_choice.value, event.client, client=event.client
            )
        )


class PatchTab(ResultsTab):
    """The patch shown in the 3D view: colour bar, readout, Step slider and replay, the model shown, force and
    displacement histories, the run's download and the view's options."""

    title, icon = "Patch", viser.Icon.CIRCLE

    def __init__(self, app, tab) -> None:
        super().__init__(app, tab)
        gui = self.gui
        with tab:
            self.colour_bar = gui.add_image(
                np.full((10, 10, 3), 255, np.uint8), label="contact pressure (MPa)", format="png"
            )
            self.readout_md = gui.add_markdown("")
            self.time_slider = gui.add_slider("Step", min=0, max=1, step=1, initial_value=0, disabled=True)
            self.play_button = gui.add_button("Play", icon=viser.Icon.PLAYER_PLAY, disabled=True)
            self.model_shown = gui.add_dropdown(
                "Model shown",
                ("3d",),
                initial_value="3d",
                disabled=True,
                hint="After compare: the model replayed, plotted as displacement and downloaded",
            )
        self.force = Plot(gui, tab, "Contact force", "position (m)", "force (kN)")
        self.displacement = Plot(
            gui, tab, "Wheel and rail displacement (downwards)", "position (m)", "displacement (µm)"
        )
        with tab:
            self.rrd_button = gui.add_button("Download run (.rrd)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.replay_speed = gui.add_dropdown("Replay speed", tuple(app.replay_speeds), initial_value="0.02x")
            self.view_buttons = gui.add_button_group("3D view", ("Top view", "Oblique view"))
            self.surfaces_box = gui.add_checkbox(
                "Rail and wheel surfaces",
                False,
                hint="Roughness drawn 200 times its size: the rail below the patch, the wheel as lines above it",
            )
            self.raised_box = gui.add_checkbox("Raised pressure surface", False, hint="3 mm per GPa")
            self._plot_export()

    def plots(self) -> dict[str, Plot]:
        return {"contact force": self.force, "displacement": self.displacement}

    def show(self, shown: Shown) -> None:
        """Force history of every model of the case overlaid; displacement of the model shown."""
        config = shown.config
        if config is None:
            for plot in (self.force, self.displacement):
                plot.clear("fix the settings on the left")
            return
        label = config.case_label()
        finished = {m: e for m, e in shown.store.entries(config.case()).items() if e.result.n_steps}
        if not finished:
            self.force.clear(NO_RUN, title=f"Contact force: {label}")
            self.displacement.clear(NO_RUN, title=f"Displacement: {label}")
            return
        n = min(e.result.n_steps for e in finished.values())
        step = max(1, n // MAX_POINTS)
        first = next(iter(finished.values())).result
        self.force.show(
            (first.x[:n:step], *(e.result.force[:n:step] / 1e3 for e in finished.values())),
            tuple((m, model_colour(m), SOLID) for m in finished),
            title=f"Contact force: {label}",
        )
        shown_result = finished[shown.model].result if shown.model in finished else first
        self._displacement(shown_result, label)

    def _displacement(self, result, label: str, running: bool = False) -> None:
        step = max(1, result.n_steps // MAX_POINTS)
        self.displacement.show(
            (result.x[::step], result.xi_wheel[::step] * 1e6, result.xi_rail[::step] * 1e6),
            (("wheel", "#1f77b4", SOLID), ("rail", "#d62728", SOLID)),
            title=f"Displacement, {result.model}{' (running)' if running else ''}: {label}",
        )

    def live(self, result, config: RunConfig) -> None:
        """A running model's force and displacement so far."""
        step = max(1, result.n_steps // MAX_POINTS)
        self.force.show(
            (result.x[::step], result.force[::step] / 1e3),
            ((f"{result.model} (running)", model_colour(result.model), SOLID),),
            title=f"Contact force: {config.case_label()}",
        )
        self._displacement(result, config.case_label(), running=True)


class SpectraTab(ResultsTab):
    """Force spectra and contact filters of the case, reference filters, another run overlaid, the CSV."""

    title, icon = "Spectra and filters", viser.Icon.CHART_LINE

    def __init__(self, app, tab) -> None:
        super().__init__(app, tab)
        gui = self.gui
        self.spectra = Plot(gui, tab, "Force spectra", "band (Hz)", "dB re 1 N", bands=True)
        self.filters = Plot(gui, tab, "Contact filters", "band (Hz)", "dB", bands=True)
        with tab:
            gui.add_markdown(
                f"*Contact filter*: a model's level minus `{REFERENCE_MODEL}`'s (solid; needs a "
                f"`{REFERENCE_MODEL}` run of the same configuration: use `{COMPARE}`). Dotted: "
                "reference filters at this preload, geometry and speed. Dashed: a run overlaid."
            )
            self.overlay_dropdown = self._overlay_menu("spectra and filters dashed beside these")
            self.csv_button = gui.add_button("Download spectra (.csv)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self._plot_export()

    def plots(self) -> dict[str, Plot]:
        return {"force spectra": self.spectra, "contact filters": self.filters}

    def show(self, shown: Shown) -> None:
        config, store = shown.config, shown.store
        if config is None:
            for plot in (self.spectra, self.filters):
                plot.clear("fix the settings on the left")
            self.csv_button.disabled = True
            return
        label = config.case_label()
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
        title = f"Contact filters: {config.case_label()}"
        if overlay is not None:
            curves += [
                (f"{m} - {REFERENCE_MODEL} [{overlay.case_label()}]", model_colour(m), DASHED, v)
                for m, v in store.contact_filters(overlay.case()).items()
            ]
            title += f" (dashed: {overlay.case_label()})"
        curves = [c for c in curves if np.array_equal(c[3][0], centres)]
        curves += [(name, REFERENCE_COLOURS.get(name, "#555555"), DOTTED, v) for name, v in references.items()]
        columns = [levels for *_, (_, levels) in curves]
        series = tuple((label, colour, style) for label, colour, style, _ in curves)
        self.filters.show(finite_bands(centres, columns), series, title=title)


class NoiseTab(ResultsTab):
    """Rolling noise of the case: sound power per component and band (A-weighted, per axle) of the model shown,
    every model's total, CNOSSOS-EU beside it on the run's own roughness, another run overlaid; the totals and the
    pass-by level for a train the user sets; the pass-by to hear and download."""

    title, icon = "Noise", viser.Icon.VOLUME

    def __init__(self, app, tab) -> None:
        super().__init__(app, tab)
        gui = self.gui
        self.power = Plot(gui, tab, "Sound power per axle", "band (Hz)", "dB(A) re 1 pW", bands=True)
        with tab:
            self.totals_md = gui.add_markdown("")
            self.audio_button = gui.add_button(
                "Pass-by audio", icon=viser.Icon.HEADPHONES, disabled=True, hint=AUDIO_HINT
            )
            self.audio_html = gui.add_html("")
            self.axles_text = gui.add_text(
                "Train axles", str(DEFAULT_TRAIN_AXLES), hint="Axles of the train passing by (pass-by level, audio)"
            )
            self.train_length_text = gui.add_text(
                "Train length (m)", f"{DEFAULT_TRAIN_LENGTH:g}", hint="From the first axle to the last, m"
            )
            self.overlay_dropdown = self._overlay_menu("totals dashed (the same choice as in Spectra)")
            self.wav_button = gui.add_button("Download pass-by (.wav)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.json_button = gui.add_button("Download noise (.json)", icon=viser.Icon.DOWNLOAD, disabled=True)
            gui.add_markdown(NOISE_NOTE)
            self._plot_export()
        self.audio_key = None  # (case, model, train) of the pass-by in the player
        self.wav: tuple[str, bytes] | None = None  # its file name and bytes

    def plots(self) -> dict[str, Plot]:
        return {"sound power": self.power}

    def show(self, shown: Shown) -> None:
        config = shown.config
        noises = {} if config is None else shown.store.noise(config.case())
        model = shown.model if shown.model in noises else next(iter(noises), None)
        try:
            train, train_problem = self.train(), None
        except WheelrailError as error:
            train, train_problem = None, error
        if model is None or self.audio_key != (config.case(), model, train):
            self.clear_audio()  # the player holds only the pass-by of what the tab shows
        self.audio_button.disabled = model is None or train is None
        self.json_button.disabled = model is None
        if config is None:
            self.power.clear("fix the settings on the left")
            self.totals_md.content = ""
            return
        label = config.case_label()
        if model is None:
            self.power.clear(NO_RUN, title=f"Sound power per axle: {label}")
            problems = [e.noise_problem for e in shown.store.entries(config.case()).values() if e.noise_problem]
            self.totals_md.content = problems[0] if problems else ""
            return
        overlay = None if shown.overlay is None or shown.overlay.case() == config.case() else shown.overlay
        extra = {} if overlay is None else shown.store.noise(overlay.case())
        self._plot(noises, model, label, extra, overlay)
        self.totals_md.content = self._totals(noises, model, extra, overlay, train, train_problem)

    def pass_by(self, entry) -> tuple[str, bytes]:
        """Make the pass-by of ``entry`` (an Entry with its noise) for the train of the fields: the player shows it
        with its calibration, the download button offers it; its file name and WAV bytes."""
        import base64

        axles, length = self.train()
        noise = entry.noise.with_train(axles, length)
        data, full_scale = noise.wav_bytes()
        config = entry.config
        from wheelrail.core.noise.run_noise import WAV_RATE

        rate = WAV_RATE
        name = f"{config.file_stem()}-pass-by-{axles}axles-{length:g}m.wav"
        caption = (
            f"Pass-by of **{config.model}** on {config.case_label()}: {axles} axles in {length:g} m, "
            f"L_pAeq,Tp {noise.pass_by_laeq_dba:.1f} dB(A) at {ISO3095_DISTANCE:g} m. WAV {rate} Hz, 16 bit; "
            "a sample of 1.0 "
            f"is {full_scale:.3g} Pa."
        )
        self.audio_html.content = (
            f'<audio controls preload="auto" style="width:100%" src="data:audio/wav;base64,'
            f'{base64.b64encode(data).decode()}"></audio>'
            f'<div style="font-size:0.8em">{_markdown_bold(caption)}</div>'
        )
        self.audio_key = (config.case(), config.model, (axles, length))
        self.wav = (name, data)
        self.wav_button.disabled = False
        return name, data

    def train(self) -> tuple[int, float]:
        """(axles, length in m) of the train fields, or one WheelrailError."""
        return read_train(self.axles_text.value, self.train_length_text.value)

    def clear_audio(self) -> None:
        self.audio_key, self.wav = None, None
        if self.audio_html.content:
            self.audio_html.content = ""
        self.wav_button.disabled = True

    def _plot(self, noises: dict, model: str, label: str, extra: dict, overlay: RunConfig | None) -> None:
        shown_noise = noises[model]
        f = shown_noise.frequency_hz
        weight = a_weighting(f) + AXLE_DB
        curves = [
            (f"{model}: {name}", COMPONENT_COLOURS[name], SOLID, shown_noise.sound_power_db[name] + weight)
            for name in COMPONENTS
        ]
        curves += [
            (f"{m}: total", model_colour(m), SOLID, n.sound_power_db["total"] + weight) for m, n in noises.items()
        ]
        beside = shown_noise.cnossos
        cnossos = {"track": beside.track_db, "vehicle": beside.vehicle_db, "total": beside.total_db}
        curves += [
            (f"CNOSSOS-EU: {name}", CNOSSOS_COLOURS[name], DOTTED, levels + a_weighting(f))
            for name, levels in cnossos.items()
        ]
        title = f"Sound power per axle, A-weighted: {label}"
        if overlay is not None and extra:
            curves += [
                (f"{m}: total [{overlay.case_label()}]", model_colour(m), DASHED, n.sound_power_db["total"] + weight)
                for m, n in extra.items()
            ]
            title += f" (dashed: {overlay.case_label()})"
        columns = [np.where(np.isfinite(levels), levels, np.nan) for *_, levels in curves]
        loudest = max(float(np.nanmax(c)) for c in columns if np.any(np.isfinite(c)))
        self.power.y_range = (
            float(10 * np.floor((loudest - NOISE_RANGE_DB) / 10)),
            float(10 * np.ceil(loudest / 10 + 0.05)),
        )
        self.power.show(
            bands_with_data(f, columns), tuple((name, colour, style) for name, colour, style, _ in curves), title=title
        )

    def _totals(self, noises, model, extra, overlay, train, train_problem) -> str:
        """L_WA per axle (dB(A)) by component and the pass-by level as a table, and what they are."""
        rail, sleeper, wheel = COMPONENTS
        rows = [
            f"| L_WA, dB(A) | {rail} | {sleeper} | track | {wheel} | total | pass-by |",
            "|---|---|---|---|---|---|---|",
        ]

        def passing(level: float) -> str:
            return "-" if train is None else _db(pass_by_level(level, *train))

        runs = list(noises.items())
        runs += [] if overlay is None else [(f"{m} [{overlay.case_label()}]", n) for m, n in extra.items()]
        for name, n in runs:
            dba = {k: v + AXLE_DB for k, v in n.sound_power_dba.items()}
            track = energy_sum(dba[rail], dba[sleeper])
            shown = f"**{name}**" if name == model else name
            rows.append(
                f"| {shown} | {_db(dba[rail])} | {_db(dba[sleeper])} | {_db(track)} | {_db(dba[wheel])} | "
                f"{_db(dba['total'])} | {passing(dba['total'])} |"
            )
        beside = noises[model].cnossos
        cfg = beside.configuration
        rows.append(
            f"| CNOSSOS-EU | | | {_db(beside.track_dba)} | {_db(beside.vehicle_dba)} | {_db(beside.total_dba)} | "
            f"{passing(beside.total_dba)} |"
        )
        if train is None:
            where = f"**Train:** {page_message(train_problem)}"
        else:
            where = (
                f"Pass-by: L_pAeq,Tp (dB(A)) at {ISO3095_DISTANCE:g} m from the track, {ISO3095_HEIGHT:g} m above the "
                f"rail, {train[0]} axles in "
                f"{train[1]:g} m at {noises[model].configuration['run']['speed_m_s'] / KMH:g} km/h"
            )
        return (
            "\n".join(rows) + f"\n\nL_WA per axle, re 1 pW. {where}. CNOSSOS-EU: the run's roughness, A3, "
            f"{cfg['track_type']}, {cfg['wheel_diameter_m'] * 1e3:g} mm wheels (superstructure "
            f"{_db(beside.superstructure_dba)} dB(A) in its total). Wheel: {noises[model].configuration['wheel']}"
        )


def _markdown_bold(text: str) -> str:
    """``**x**`` as HTML bold (the caption sits in HTML), everything else escaped."""
    import html
    import re

    return re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", html.escape(text))


def _db(value: float) -> str:
    return f"{value:.1f}" if np.isfinite(value) else "-"


class RoughnessTab(ResultsTab):
    """The roughness of the configuration: spectra (rail, wheel set and combined, the ISO 3095 limit) against
    frequency and wavelength, the lateral coherence, the lines across the running surface."""

    title, icon = "Roughness", viser.Icon.WAVE_SINE

    def __init__(self, app, tab) -> None:
        super().__init__(app, tab)
        gui = self.gui
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
            curves.append(("combined (energetic sum)", "#d62728", energetic_sum(rail.levels_db, of_wheel.levels_db)))
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


class TrackTab(ResultsTab):
    """The track of the configuration shown: its point receptance above a sleeper and at midspan and its vertical
    decay rate against EN ISO 3095:2013's lower limit (core's ``noise.decay``), and those of the track of the run
    overlaid (Spectra and Noise tabs) when it is another. A new track's curves are computed once in the
    background (a few seconds of FE solves, then kept on disk) and drawn when they are ready."""

    title, icon = "Track", viser.Icon.TRAIN

    def __init__(self, app, tab) -> None:
        super().__init__(app, tab)
        gui = self.gui
        self.receptance = Plot(gui, tab, "Point receptance", "band (Hz)", "dB re 1 m/N", bands=True)
        self.decay = Plot(gui, tab, "Vertical decay rate", "band (Hz)", "dB/m", bands=True)
        with tab:
            self.track_md = gui.add_markdown("")
            gui.add_markdown(
                "Solid: the track of the settings on the left (its *Track* folder). Dotted: EN ISO 3095:2013's lower "
                "limit of the vertical decay rate (Figure 3, curve A), which a test track must meet. Dashed: the "
                "track of the run overlaid in the Spectra or Noise tab, when it is another."
            )
            self._plot_export()
        self._curves: dict = {}  # track -> (bands, decay) or the error's words, once computed
        self._computing: set = set()
        self._last: Shown | None = None

    def plots(self) -> dict[str, Plot]:
        return {"point receptance": self.receptance, "decay rate": self.decay}

    def curves(self, track):
        """The track's (bands, decay) once computed (None: not yet; it is being computed in the background)."""
        found = self._curves.get(track)
        if found is None and track not in self._computing:
            self._computing.add(track)
            threading.Thread(target=self._compute, args=(track,), daemon=True, name="wheelrail-track-tab").start()
        return found

    def _compute(self, track) -> None:
        from wheelrail.core.noise.decay import band_receptances, track_decay

        try:
            self._curves[track] = (band_receptances(track), track_decay(track))
        except WheelrailError as error:
            self._curves[track] = page_message(error)
        finally:
            self._computing.discard(track)
        if self._last is not None:  # redraw what is shown now, if it still wants this track
            self.app.redraw_tab(self)

    def show(self, shown: Shown) -> None:
        self._last = shown
        config = shown.config
        if config is None:
            for plot in (self.receptance, self.decay):
                plot.clear("fix the settings on the left")
            self.track_md.content = ""
            return
        track = config.params().track
        self.track_md.content = f"**Track:** {describe_words(config.params(), 'track')}."
        own = self.curves(track)
        if own is None or isinstance(own, str):
            why = "computing the track's receptance and decay rate (once per track) ..." if own is None else own
            for plot in (self.receptance, self.decay):
                plot.clear(why, title=f"Track: {config.case_label()}")
            return
        overlay = shown.overlay.params().track if shown.overlay is not None else None
        other = self.curves(overlay) if overlay is not None and overlay != track else None
        other = other if isinstance(other, tuple) else None
        self._draw(own, other, shown.overlay.case_label() if other is not None else "")

    def _draw(self, own: tuple, other: tuple | None, other_label: str) -> None:
        (bands, decay), f = own, own[0]["frequency_hz"]
        curves = [
            ("above a sleeper", "#1f77b4", SOLID, 20 * np.log10(bands["above_sleeper_m_per_n"])),
            ("midspan", "#d62728", SOLID, 20 * np.log10(bands["midspan_m_per_n"])),
        ]
        if other is not None:
            curves += [
                (
                    f"above a sleeper [{other_label}]",
                    "#1f77b4",
                    DASHED,
                    20 * np.log10(other[0]["above_sleeper_m_per_n"]),
                ),
                (f"midspan [{other_label}]", "#d62728", DASHED, 20 * np.log10(other[0]["midspan_m_per_n"])),
            ]
        self.receptance.show(
            bands_with_data(f, [c[3] for c in curves]), tuple(c[:3] for c in curves), title="Point receptance"
        )
        on_bands = {float(x): i for i, x in enumerate(decay["frequency_hz"])}
        rows = [on_bands.get(float(x)) for x in f]

        def per_band(values) -> np.ndarray:
            values = [np.nan if v is None else v for v in values]
            return np.array([np.nan if i is None else values[i] for i in rows], dtype=float)

        lines = [
            ("decay rate", "#2ca02c", SOLID, per_band(decay["decay_rate_dB_per_m"])),
            ("EN ISO 3095:2013 limit", ISO_LIMIT_COLOUR, DOTTED, per_band(decay["limit_dB_per_m"])),
        ]
        if other is not None:
            lines.append((f"decay rate [{other_label}]", "#2ca02c", DASHED, per_band(other[1]["decay_rate_dB_per_m"])))
        verdict = "meets" if decay["meets_limit"] else "is below"
        self.decay.show(
            bands_with_data(f, [c[3] for c in lines]),
            tuple(c[:3] for c in lines),
            title=f"Vertical decay rate: {verdict} the EN ISO 3095 limit",
        )


def _receptance_curves(bands: dict, style: str, suffix: str) -> list:
    """The point receptances above a sleeper and at midspan as curves in dB re 1 m/N."""
    return [
        (f"{where}{suffix}", colour, style, 20 * np.log10(bands[key]))
        for where, colour, key in (
            ("above a sleeper", "#1f77b4", "above_sleeper_m_per_n"),
            ("midspan", "#d62728", "midspan_m_per_n"),
        )
    ]


class HelpTab(ResultsTab):
    """The models, the contact filter, the geometry and the inputs in words."""

    title, icon = "Help", viser.Icon.HELP

    def __init__(self, app, tab) -> None:
        super().__init__(app, tab)
        with tab:
            self.gui.add_markdown(help_text())


def help_text() -> str:
    models = "\n".join(f"- **{m}**: {model_entry(m).label}" for m in MODEL_CHOICES[:-1])
    return (
        "**Contact models** (Pieringer, Kropp & Thompson, Wear 271, 2011):\n\n"
        + models
        + f"\n- **{COMPARE}**: every model one after another on the same configuration, {REFERENCE_MODEL} first; "
        "*Model shown* (Patch tab) chooses the one replayed and downloaded.\n\n"
        "**Contact filter**: a contact patch is several millimetres long and wide, so roughness of shorter "
        "wavelengths is partly averaged out before it excites the wheel and rail. The *contact filter* of a "
        f"model is its force level minus that of `{REFERENCE_MODEL}` (a point contact, no filtering), per "
        "third-octave band: 0 dB means no filtering, negative values show how much the patch attenuates. "
        "Dotted: reference filters for the same load, geometry and speed (CNOSSOS-EU A3 of noise mapping, and "
        "the analytic averaging and circular-patch filters). Dashed: another run overlaid on purpose.\n\n"
        "**3D view**: seen from above, x (the rolling direction) to the right, y across the rail up; grid of "
        "1 mm, bold every 5 mm. The red ellipse is the Hertz patch at the preload with its semi-axes a (along) "
        "and b (across); the colour bar marks its peak pressure p0. *Top view* / *Oblique view* set the camera.\n\n"
        "**Contact geometry**: wheel radius (rolling, along the rail), rail crown radius (across) and wheel "
        "tread radius across (empty: a cylindrical tread; negative: a concave, worn tread, which must stay "
        f"flatter than the crown), in mm; empty fields keep the paper's crossed cylinders of "
        f"{ContactParameters().radius * 1e3:g} mm (a circular "
        "patch). Otherwise the patch is an ellipse, drawn with its Hertz semi-axes.\n\n"
        "**Wheel roughness**: a bundled wheel set added to a rail set (r = r_rail + r_wheel, the wheel's lines "
        "repeating with its circumference); `none`: a smooth wheel, as in the paper. The Roughness tab then "
        "shows the rail, the wheel and their energetic sum.\n\n"
        "**Roughness spectrum**: dB re 1 µm against frequency at the speed and wavelength (top axis), averaged "
        f"over lines {DEFAULT_LINES[0]}..{DEFAULT_LINES[-1]}; dotted, for rail sets: the ISO 3095:2013 limit, put on "
        f"these bands by the CNOSSOS-EU rule. Bands more than {EMPTY_BAND_DB:g} dB below the highest hold no "
        "roughness and are not drawn.\n\n"
        "**Noise**: the run's contact force through the model track's transfer functions (rail and sleeper sound "
        "power) and, for the wheel, the effective roughness through CNOSSOS-EU's L_H,veh (the 2-DOF wheel has no "
        "radiating modes); per axle, A-weighted per band, beside the CNOSSOS-EU source on the run's own roughness "
        f"with A3. The table: L_WA per axle and the pass-by L_pAeq,Tp at {ISO3095_DISTANCE:g} m for the train set "
        "below it. "
        "*Pass-by audio* makes the pass-by of the model shown to hear and download (its calibration under the "
        "player).\n\n"
        "**Track**: the *Track* folder sets the pads, sleepers, ballast, the rail's loss factor and the pads' "
        "width (empty fields are not allowed: each shows the paper's value). A new track computes its Green's "
        "functions once (13-60 s, kept on disk); the Track tab shows its receptance and decay rate against the "
        "EN ISO 3095 limit.\n\n"
        "**Run length**: at least long enough for a force spectrum at the chosen speed, at most what the "
        "roughness set holds; the page shows the range.\n\n"
        "**One shared session**: every browser tab open on this explorer shows the same form and the same "
        "results (a change in one is seen in all); *Session* saves the settings to a file and loads them back."
    )


RESULT_TABS = (PatchTab, SpectraTab, NoiseTab, TrackTab, RoughnessTab, HelpTab)
