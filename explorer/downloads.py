"""The page's downloads, each named after the configuration it holds: the run replayed (.rrd), the spectra and
filters (.csv), the rolling noise (.json), the pass-by (.wav) and any plot as shown (.png)."""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path

from wheelrail.core.errors import WheelrailError
from wheelrail.explorer.config import RunConfig
from wheelrail.explorer.form import RunForm
from wheelrail.explorer.page import Page
from wheelrail.explorer.replay import Replay
from wheelrail.explorer.results import Entry, ResultStore

__all__ = ["Downloads"]


class Downloads:
    """Files of what the page shows, sent to the page (its browser tab); each returns its (name, bytes)."""

    def __init__(
        self,
        page: Page,
        form: RunForm,
        store: ResultStore,
        replay: Replay,
        shown: Callable[[], RunConfig | None],
        plots: Callable[[], dict],
    ) -> None:
        """``shown()``: the configuration the page shows (None: not valid); ``plots()``: every plot by name."""
        self.page, self.form, self.store, self.replay = page, form, store, replay
        self._shown, self._plots = shown, plots

    def rrd(self, client=None) -> tuple[str, bytes]:
        """The replayed run (the model shown) as a rerun recording, named after its configuration."""
        from wheelrail.core.recording import record_result

        entry = self.replay.entry
        if entry is None:
            raise WheelrailError("no run of this configuration to save yet: press Run first")
        name = entry.config.file_stem() + ".rrd"
        with tempfile.TemporaryDirectory(prefix="wheelrail-rrd-") as folder:
            path = Path(folder) / name
            record_result(
                entry.result,
                path,
                roughness=self.form.sets.get(entry.config.set_label, self.form.roughness),
                description=f"wheelrail explorer: {entry.config.label()}",
                sound_power=entry.noise is not None,  # spectra/sound_power: the Noise tab's spectra
            )
            content = path.read_bytes()
        return self.page.send(name, content, client)

    def spectra_csv(self, client=None) -> tuple[str, bytes]:
        """Spectra, contact filters and reference filters of the shown configuration, named after it."""
        shown = self._shown()
        if shown is None:
            raise WheelrailError("the settings are not a valid configuration: fix them first")
        content = self.store.csv_text(shown).encode()
        return self.page.send(shown.for_model("spectra").file_stem() + ".csv", content, client)

    def shown_noise(self) -> Entry:
        """The entry of the model shown, with its rolling noise, or one WheelrailError."""
        entry = self.replay.entry
        if entry is None:
            raise WheelrailError("no run of this configuration yet: press Run first")
        if entry.noise is None:
            raise WheelrailError(f"{entry.config.model} has no rolling noise: {entry.noise_problem or 'stopped early'}")
        return entry

    def noise_json(self, train: tuple[int, float], client=None, noise=None) -> tuple[str, bytes]:
        """The rolling noise of the model shown (sound power, totals, pass-by for ``train``, (axles, length in m),
        CNOSSOS-EU beside it and the configuration) as JSON, named after the configuration; ``noise``: its rolling
        noise with another wheel's sound power (the Noise tab's choice), default the run's own."""
        from wheelrail.core.files.jsonready import strict_json

        entry = self.shown_noise()
        noise = (entry.noise if noise is None else noise).with_train(*train)
        summary = {"explorer": entry.config.label(), **noise.to_dict()}
        content = (strict_json(summary, indent=1) + "\n").encode()
        return self.page.send(entry.config.file_stem() + "-noise.json", content, client)

    def plot_png(self, which: str, client=None) -> tuple[str, bytes]:
        """One plot as shown (its title names the configuration), as a PNG named after the configuration."""
        plots = self._plots()
        if which not in plots:
            raise WheelrailError(f"unknown plot {which!r}; choose one of {', '.join(plots)}")
        shown = self._shown()
        stem = shown.for_model("plot").file_stem() if shown is not None else "wheelrail-plot"
        return self.page.send(f"{stem}-{which.replace(' ', '-')}.png", plots[which].png(), client)
