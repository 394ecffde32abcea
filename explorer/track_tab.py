"""The Track tab: the track of the configuration shown, its point receptance and its vertical and lateral decay rates
against the EN ISO 3095:2013 limits, beside the track of the run overlaid."""

from __future__ import annotations

import numpy as np
import viser

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import describe_track, describe_words
from wheelrail.core.noise.decay import decay_verdict
from wheelrail.explorer.config import page_message
from wheelrail.explorer.panel import ResultsTab, Shown, TabParts
from wheelrail.explorer.plots import DASHED, DOTTED, SOLID, Plot, bands_with_data
from wheelrail.explorer.roughness_tab import ISO_LIMIT_COLOUR

__all__ = ["TrackTab"]


class TrackTab(ResultsTab):
    """The track of the configuration shown: its point receptance above a sleeper and at midspan and its vertical
    and lateral decay rates against EN ISO 3095:2013's lower limits (core's ``noise.decay``), and those of the track
    of the run overlaid (Spectra and Noise tabs) when it is another. A new track's curves are computed once in the
    background (a few seconds of FE solves, then kept on disk) and drawn when they are ready."""

    title, icon = "Track", viser.Icon.TRAIN

    def __init__(self, parts: TabParts, tab) -> None:
        super().__init__(parts, tab)
        gui = self.gui
        self.receptance = Plot(gui, tab, "Point receptance", "band (Hz)", "dB re 1 m/N", bands=True)
        self.decay = Plot(gui, tab, "Vertical decay rate", "band (Hz)", "dB/m", bands=True)
        self.lateral = Plot(gui, tab, "Lateral decay rate", "band (Hz)", "dB/m", bands=True)
        with tab:
            self.track_md = gui.add_markdown("")
            self.resonances_md = gui.add_markdown("")
            gui.add_markdown(
                "Solid: the track of the settings on the left (its *Track* folder). Dotted: EN ISO 3095:2013's lower "
                "limits of the vertical and the lateral decay rate (Figure 3, curves A and B), which a test track must "
                "meet; the lateral one is the railhead's, of the rail's lateral bending and torsion on the pads' "
                "lateral and roll stiffness. Dashed: the track of the run overlaid in the Spectra or Noise tab, when "
                "it is another."
            )
            self._plot_export()
        self._curves: dict = {}  # track -> (bands, decay, resonances, lateral decay) or the error's words
        self._computing: set = set()
        self._last: Shown | None = None
        self.followers: list = []  # other tabs that draw these curves (the Wheel tab), redrawn with this one

    def plots(self) -> dict[str, Plot]:
        return {"point receptance": self.receptance, "decay rate": self.decay, "lateral decay rate": self.lateral}

    def curves(self, track):
        """The track's (bands, decay, resonances, lateral decay) once computed (None: not yet; it is being computed in
        the background)."""
        found = self._curves.get(track)
        if found is None and track not in self._computing:
            self._computing.add(track)
            if self.parts.workers.start(self._compute, track, name="wheelrail-track-tab") is None:
                self._computing.discard(track)  # the page is closed: nothing more is computed
        return found

    def _compute(self, track) -> None:
        from wheelrail.core.noise.decay import band_receptances, track_decay, track_lateral_decay
        from wheelrail.core.track.resonances import track_resonances

        try:
            computed = (band_receptances(track), track_decay(track), track_resonances(track))
            self._curves[track] = (*computed, track_lateral_decay(track))
        except WheelrailError as error:
            self._curves[track] = page_message(error)
        finally:
            self._computing.discard(track)
        if self._last is not None:  # redraw what is shown now, if it still wants this track
            for tab in (self, *self.followers):
                self.parts.redraw(tab)

    def show(self, shown: Shown) -> None:
        self._last = shown
        config = shown.config
        if config is None:
            for plot in (self.receptance, self.decay, self.lateral):
                plot.clear("fix the settings on the left")
            self.track_md.content = self.resonances_md.content = ""
            return
        track = config.params().track
        self.track_md.content = f"**Track:** {describe_words(config.params(), 'track')}."
        own = self.curves(track)
        self.resonances_md.content = _resonance_words(own[2]) if isinstance(own, tuple) else ""
        if own is None or isinstance(own, str):
            why = "computing the track's receptance and decay rates (once per track) ..." if own is None else own
            for plot in (self.receptance, self.decay, self.lateral):
                plot.clear(why, title=f"{plot.title} of {describe_track(config.params())}")
            return
        overlay = shown.overlay.params().track if shown.overlay is not None else None
        other = self.curves(overlay) if overlay is not None and overlay != track else None
        other = other if isinstance(other, tuple) else None
        self._draw(own, other, shown.overlay.case_label() if other is not None else "", describe_track(config.params()))

    def _draw(self, own: tuple, other: tuple | None, other_label: str, track_words: str) -> None:
        """The curves of the track named by ``track_words`` (core's ``describe_track``), and ``other``'s dashed."""
        bands, f = own[0], own[0]["frequency_hz"]
        curves = _receptance_curves(bands, SOLID, "")
        if other is not None:
            curves += _receptance_curves(other[0], DASHED, f" [{other_label}]")
        self.receptance.show(
            bands_with_data(f, [c[3] for c in curves]),
            tuple(c[:3] for c in curves),
            title=f"Point receptance of {track_words}" + (f" (dashed: {other_label})" if other is not None else ""),
        )
        for plot, index, name, colour in (
            (self.decay, 1, "Vertical", "#2ca02c"),
            (self.lateral, 3, "Lateral", "#9467bd"),
        ):
            theirs = None if other is None else other[index]
            self._draw_decay(plot, f, own[index], theirs, other_label, (name, colour, track_words))

    @staticmethod
    def _draw_decay(plot: Plot, f, decay: dict, other: dict | None, other_label: str, how: tuple) -> None:
        """One direction's decay rate (``decay_against_limit``'s layout) and its limit on the bands ``f``, and
        ``other``'s dashed; ``how``: the direction's name, its colour and the track's words."""
        name, colour, track_words = how
        on_bands = {float(x): i for i, x in enumerate(decay["frequency_hz"])}
        rows = [on_bands.get(float(x)) for x in f]

        def per_band(values) -> np.ndarray:
            values = [np.nan if v is None else v for v in values]
            return np.array([np.nan if i is None else values[i] for i in rows], dtype=float)

        lines = [
            ("decay rate", colour, SOLID, per_band(decay["decay_rate_dB_per_m"])),
            ("EN ISO 3095:2013 limit", ISO_LIMIT_COLOUR, DOTTED, per_band(decay["limit_dB_per_m"])),
        ]
        if other is not None:
            lines.append((f"decay rate [{other_label}]", colour, DASHED, per_band(other["decay_rate_dB_per_m"])))
        plot.show(
            bands_with_data(f, [c[3] for c in lines]),
            tuple(c[:3] for c in lines),
            title=f"{name} decay rate of {track_words} {decay_verdict(decay)}",
        )


def _resonance_words(resonances: dict) -> str:
    """The track's resonances (core's ``track.resonances``): each one's receptance peak, or why it has none."""
    return "**Resonances** (peaks of the point receptance): " + "; ".join(
        f"{peak.label} {peak.in_words()}" for peak in resonances.values()
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
