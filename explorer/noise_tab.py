"""The Noise tab: rolling noise of the case (sound power per component and band, A-weighted, per axle, of the
model shown; every model's total; CNOSSOS-EU beside it on the run's own roughness; another run overlaid), the
totals and pass-by level for a train the user sets, and the pass-by to hear and download."""

from __future__ import annotations

import numpy as np
import viser

from wheelrail.core.drawing.palette import CNOSSOS_COLOURS
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.contact_position import CONTACT_POSITION_INPUTS
from wheelrail.core.inputs.declared import choice
from wheelrail.core.noise.components import TOTAL, component
from wheelrail.core.noise.run_noise import (
    AXLE_DB,
    DEFAULT_TRAIN_AXLES,
    DEFAULT_TRAIN_LENGTH,
    ISO3095_DISTANCE,
    ISO3095_HEIGHT,
    pass_by_level,
)
from wheelrail.core.parameters import KMH
from wheelrail.core.spectra.levels import a_weighting, energy_sum
from wheelrail.explorer.config import RunConfig, page_message, read_contact_position, read_train
from wheelrail.explorer.panel import NO_RUN, ResultsTab, Shown, TabParts
from wheelrail.explorer.plots import DASHED, DOTTED, SOLID, Plot, bands_with_data, model_colour

__all__ = ["NoiseTab", "power_curves", "superstructure_words"]

NOISE_RANGE_DB = 60.0  # the sound-power plot shows the loudest band down by this (A-weighted, quieter bands
# matter little to the total)
AUDIO_HINT = (
    "The pass-by of the train set below at the ISO 3095 position, synthesised from the run's contact force "
    "(the model shown); a few seconds to make"
)
NOISE_NOTE = (
    "*Sound power* per axle (two wheels on two rails), A-weighted per band, of the model shown: its components "
    "(solid, their colours) and every model's total (model colours), from the run's contact force through "
    "the model track's transfer functions (the TWINS approach). Dotted: the CNOSSOS-EU source (Directive (EU) "
    "2015/996, Annex II 2.3) on the run's own roughness with its fixed contact filter A3: track, vehicle and the "
    "total, which also holds the small superstructure term (said under the table). Dashed: a run overlaid. "
    f"*Pass-by audio*: the model shown, at {ISO3095_DISTANCE:g} m; listen for the high bands (above about 1 kHz) "
    "that a finite "
    "patch (3d, 2d) takes out and the point contact (hertz) keeps. *Wheel model (noise)*: whose wheel sound power "
    "the tab shows (its curves, table, audio and download): the directive's L_H,veh or the modal wheel's (the run's "
    "own modal wheel if it ran with one, else the named wheel nearest its R; computed on first choice, a few "
    "seconds to a minute per wheel shape). *Contact offset* on the railhead and on the wheel tread (mm, + towards "
    "the field side; 0: centred): off the rail's centreline the vertical force twists the rail, whose lateral "
    "vibration radiates (*rail, lateral*); off the rolling circle it drives the modal wheel's axial modes (about a "
    "minute to compute a new position)."
)
WHEEL_CHOICE = choice("noise_wheel_model")  # the noise chain's wheel: one declaration (core.inputs.declared.CHOICES)


class NoiseTab(ResultsTab):
    """Rolling noise of the case: sound power per component and band (A-weighted, per axle) of the model shown,
    every model's total, CNOSSOS-EU beside it on the run's own roughness, another run overlaid; the totals and the
    pass-by level for a train the user sets; the pass-by to hear and download."""

    title, icon = "Noise", viser.Icon.VOLUME

    def __init__(self, parts: TabParts, tab) -> None:
        super().__init__(parts, tab)
        gui, page = self.gui, self.page
        self.power = Plot(gui, tab, "Sound power per axle", "band (Hz)", "dB(A) re 1 pW", bands=True)
        with tab:
            self.totals_md = gui.add_markdown("")
            self.audio_button = gui.add_button(
                "Pass-by audio", icon=viser.Icon.HEADPHONES, disabled=True, hint=AUDIO_HINT
            )
            self.audio_button.on_click(lambda event: page.guarded(self.make_pass_by, client=event.client))
            self.audio_html = gui.add_html("")
            self.axles_text = gui.add_text(
                "Train axles", str(DEFAULT_TRAIN_AXLES), hint="Axles of the train passing by (pass-by level, audio)"
            )
            self.train_length_text = gui.add_text(
                "Train length (m)", f"{DEFAULT_TRAIN_LENGTH:g}", hint="From the first axle to the last, m"
            )
            for field in (self.axles_text, self.train_length_text):
                field.on_update(lambda event: page.guarded(parts.redraw, self))
            self.overlay_dropdown = self._overlay_menu("totals dashed (the same choice as in Spectra)")
            self.wav_button = gui.add_button("Download pass-by (.wav)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.wav_button.on_click(lambda event: page.guarded(self.download_wav, event.client, client=event.client))
            self.json_button = gui.add_button("Download noise (.json)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.json_button.on_click(lambda event: page.guarded(self.download_json, event.client, client=event.client))
            wheel = WHEEL_CHOICE
            self.wheel_dropdown = gui.add_dropdown(
                wheel.label, wheel.values, initial_value=wheel.default, hint=wheel.help_text()
            )
            self.wheel_dropdown.on_update(lambda event: page.guarded(parts.redraw, self))
            self.position_texts = [
                gui.add_text(
                    f"{entry.label} ({entry.shown.name})",
                    f"{entry.shown_default():g}",
                    hint=f"{entry.help[0].upper()}{entry.help[1:]}; {entry.accepted_text()}",
                )
                for entry in CONTACT_POSITION_INPUTS
            ]
            for field in self.position_texts:
                field.on_update(lambda event: page.guarded(parts.redraw, self))
            gui.add_markdown(NOISE_NOTE)
            self._plot_export()
        self.audio_key = None  # (case, model, train, wheel model, contact position) of the pass-by in the player
        self.wav: tuple[str, bytes] | None = None  # its file name and bytes
        # (id of a run's result, wheel model, contact position) -> (the result, its RunNoise or why there is none)
        self._wheel_noises: dict = {}

    def plots(self) -> dict[str, Plot]:
        return {"sound power": self.power}

    def show(self, shown: Shown) -> None:
        self._show_overlay_menu(self.overlay_dropdown, shown)
        config = shown.config
        try:
            position = self.contact_position()
        except WheelrailError as error:  # the tab's own fields: said in place of the noise
            self.clear_audio()
            self.audio_button.disabled = self.json_button.disabled = True
            self.power.clear(page_message(error))
            self.totals_md.content = f"**Contact position:** {page_message(error)}"
            return
        noises = {} if config is None else self._noises(shown.store, config.case())
        model = shown.model if shown.model in noises else next(iter(noises), None)
        try:
            train, train_problem = self.train(), None
        except WheelrailError as error:
            train, train_problem = None, error
        if model is None or self.audio_key != (config.case(), model, train, self.wheel_dropdown.value, position):
            self.clear_audio()  # the player holds only the pass-by of what the tab shows
        self.audio_button.disabled = model is None or train is None
        self.json_button.disabled = model is None
        if config is None:
            self.power.clear("fix the settings on the left")
            self.totals_md.content = ""
            return
        label = config.title_label()
        if model is None:
            self.power.clear(NO_RUN, title=f"Sound power per axle: {label}")
            entries = shown.store.entries(config.case()).values()
            problems = [e.noise_problem or self._problem(e) for e in entries if e.noise_problem or self._problem(e)]
            self.totals_md.content = problems[0] if problems else ""
            return
        overlay = None if shown.overlay is None or shown.overlay.case() == config.case() else shown.overlay
        extra = {} if overlay is None else self._noises(shown.store, overlay.case())
        self._plot(noises, model, label, extra, overlay)
        self.totals_md.content = self._totals(noises, model, extra, overlay, train, train_problem)

    def make_pass_by(self) -> tuple[str, bytes]:
        """Pass-by audio: the pass-by of the model shown for the tab's train, in the player."""
        entry = self.parts.downloads.shown_noise()
        self.train()  # a bad train field is said before the work starts
        self.audio_html.content = "<i>Making the pass-by ...</i>"
        try:
            return self.pass_by(entry)
        except BaseException:
            self.clear_audio()
            raise

    def download_wav(self, client=None) -> tuple[str, bytes]:
        """The pass-by in the player as a WAV file."""
        if self.wav is None:
            raise WheelrailError("no pass-by made yet: press Pass-by audio first")
        return self.page.send(*self.wav, client)

    def download_json(self, client=None) -> tuple[str, bytes]:
        """The rolling noise of the model shown, with the pass-by for the tab's train, as JSON."""
        entry = self.parts.downloads.shown_noise()
        return self.parts.downloads.noise_json(self.train(), client, noise=self.noise_of(entry))

    def pass_by(self, entry) -> tuple[str, bytes]:
        """Make the pass-by of ``entry`` (an Entry with its noise) for the train of the fields: the player shows it
        with its calibration, the download button offers it; its file name and WAV bytes."""
        import base64

        axles, length = self.train()
        noise = self.noise_of(entry).with_train(axles, length)
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
        self.audio_key = (config.case(), config.model, (axles, length), self.wheel_dropdown.value,
                          self.contact_position())  # fmt: skip
        self.wav = (name, data)
        self.wav_button.disabled = False
        return name, data

    def noise_of(self, entry):
        """The rolling noise of ``entry`` (an Entry with its noise) with the wheel's sound power of the tab's choice
        and the contact at the tab's position: the run's own (the directive's L_H,veh, centred) or another,
        computed once per run (one WheelrailError if it cannot be)."""
        wheel_model = WHEEL_CHOICE.check(self.wheel_dropdown.value)
        position = self.contact_position()
        if wheel_model == entry.noise.configuration["wheel_model"] and position.centred:
            return entry.noise
        key = (id(entry.result), wheel_model, position)
        if self._wheel_noises.get(key, (None,))[0] is not entry.result:  # not yet, or another run's id
            from wheelrail.core.noise import run_noise as run_noise_module

            try:
                found = run_noise_module.run_noise(entry.result, wheel_model=wheel_model, contact_position=position)
            except WheelrailError as error:
                found = f"{entry.config.model}: no {wheel_model} wheel power: {page_message(error)}"
            self._wheel_noises[key] = (entry.result, found)
        found = self._wheel_noises[key][1]
        if isinstance(found, str):
            raise WheelrailError(found)
        return found

    def _problem(self, entry) -> str | None:
        """Why ``entry`` has no noise with the tab's wheel, if it was tried and failed."""
        try:
            position = self.contact_position()
        except WheelrailError:
            return None  # the fields' problem is said in the noise's place
        kept = self._wheel_noises.get((id(entry.result), self.wheel_dropdown.value, position))
        return kept[1] if kept is not None and kept[0] is entry.result and isinstance(kept[1], str) else None

    def _noises(self, store, case) -> dict:
        """Every model's rolling noise of ``case`` with the tab's wheel (those that have one)."""
        noises = {}
        for name, entry in store.entries(case).items():
            if entry.noise is not None:
                try:
                    noises[name] = self.noise_of(entry)
                except WheelrailError:
                    pass  # said under the plot (show: the problems)
        return noises

    def contact_position(self):
        """The contact's lateral position of the tab's fields (``ContactPosition``, m), or one WheelrailError."""
        return read_contact_position([field.value for field in self.position_texts])

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
        curves = power_curves(noises, model, extra, None if overlay is None else overlay.case_label())
        title = f"Sound power per axle, A-weighted: {label}"
        if shown_noise.configuration["wheel_model"] != WHEEL_CHOICE.default:
            title += f" (wheel: {shown_noise.configuration['wheel_model']})"
        if overlay is not None and extra:
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
        """L_WA per axle (dB(A)) by component (those driven by the force, their sum ``track``, those driven by the
        roughness) and the pass-by level as a table, and what they are."""
        wheel_model = noises[model].configuration["wheel_model"]
        parts = [name for name in noises[model].sound_power_db if name != TOTAL]
        track_parts = [name for name in parts if component(name).driven_by == "force"]
        wheel_parts = [name for name in parts if name not in track_parts]
        heads = [component(name).label for name in track_parts] + ["track"]
        heads += [f"{component(name).label} ({wheel_model})" for name in wheel_parts] + ["total", "pass-by"]
        rows = ["| L_WA, dB(A) | " + " | ".join(heads) + " |", "|---" * (len(heads) + 1) + "|"]

        def passing(level: float) -> str:
            return "-" if train is None else _db(pass_by_level(level, *train))

        runs = list(noises.items())
        runs += [] if overlay is None else [(f"{m} [{overlay.case_label()}]", n) for m, n in extra.items()]
        for name, n in runs:
            dba = {k: v + AXLE_DB for k, v in n.sound_power_dba.items()}
            cells = [dba.get(part, np.nan) for part in track_parts]
            cells.append(energy_sum(*(dba.get(part, -np.inf) for part in track_parts)))
            cells += [dba.get(part, np.nan) for part in wheel_parts] + [dba[TOTAL]]
            shown = f"**{name}**" if name == model else name
            rows.append(f"| {shown} | " + " | ".join(_db(cell) for cell in cells) + f" | {passing(dba[TOTAL])} |")
        beside = noises[model].cnossos
        cfg = beside.configuration
        vehicle = [_db(beside.vehicle_dba)] + [""] * (len(wheel_parts) - 1) if wheel_parts else []
        cells = [""] * len(track_parts) + [_db(beside.track_dba), *vehicle, _db(beside.total_dba)]
        rows.append("| CNOSSOS-EU | " + " | ".join(cells) + f" | {passing(beside.total_dba)} |")
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
            f"{cfg['track_type']}, {cfg['wheel_diameter_m'] * 1e3:g} mm wheels; {superstructure_words(beside)} "
            f"Wheel ({WHEEL_CHOICE.label.lower()}: {wheel_model}): {noises[model].configuration['wheel']}"
        )


def power_curves(noises: dict, model: str, extra: dict, overlay_label: str | None = None) -> list:
    """The sound-power plot's curves: (label, colour, line style, levels in dB(A) per band) of the ``model``'s
    components (each in its entry's colour, :mod:`wheelrail.core.noise.components`), every model's total (model
    colours), the CNOSSOS-EU source beside the shown run (dotted) and the totals of ``extra``, another case's
    noises (dashed, labelled with ``overlay_label``); sound power per axle (one wheel's + 3 dB), A-weighted."""
    shown_noise = noises[model]
    f = shown_noise.frequency_hz
    weight = a_weighting(f) + AXLE_DB
    curves = [
        (f"{model}: {name}", component(name).colour, SOLID, levels + weight)
        for name, levels in shown_noise.sound_power_db.items()
        if name != TOTAL
    ]
    curves += [(f"{m}: total", model_colour(m), SOLID, n.sound_power_db[TOTAL] + weight) for m, n in noises.items()]
    beside = shown_noise.cnossos
    cnossos = {"track": beside.track_db, "vehicle": beside.vehicle_db, "total": beside.total_db}
    curves += [
        (f"CNOSSOS-EU: {name}", CNOSSOS_COLOURS[name], DOTTED, levels + a_weighting(f))
        for name, levels in cnossos.items()
    ]
    if overlay_label is not None:
        curves += [
            (f"{m}: total [{overlay_label}]", model_colour(m), DASHED, n.sound_power_db[TOTAL] + weight)
            for m, n in extra.items()
        ]
    return curves


def superstructure_words(beside) -> str:
    """What CNOSSOS-EU's superstructure term (in its total, not in the table's columns) is, with its level."""
    below = beside.track_dba - beside.superstructure_dba
    return (
        f"its total also holds the *superstructure* term, {_db(beside.superstructure_dba)} dB(A): the third "
        "source of CNOSSOS-EU's rolling noise beside track and vehicle: the vehicle's superstructure (its body) "
        "excited by the same roughness, L_W,0,sup = L_R,TOT + L_H,veh,sup + 10 lg N_a (Directive (EU) 2015/996, "
        "Annex II eq. 2.3.10). The directive tabulates one superstructure transfer L_H,veh,sup, 0 dB in every "
        "band (Table G-3c), so this term is the total effective roughness L_R,TOT (dB re 1 µm) read as a sound "
        f"power: {_db(below)} dB below the track term here, it adds nothing audible. (Not a bridge: no bridge or "
        "impact-noise term is added.)"
    )


def _markdown_bold(text: str) -> str:
    """``**x**`` as HTML bold (the caption sits in HTML), everything else escaped."""
    import html
    import re

    return re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", html.escape(text))


def _db(value: float) -> str:
    return f"{value:.1f}" if np.isfinite(value) else "-"
