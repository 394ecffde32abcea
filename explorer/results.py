"""Results of the session keyed by their full configuration (no viser here).

Every finished (or stopped) run is kept under ``(config.case(), model)`` with its force spectrum and rolling noise
(:func:`wheelrail.core.noise.run_noise.run_noise`) or the reason it has none. What the page shows is always one
case's entries (the case of the controls), so changing the set, wheel set, line, speed, preload, length or contact
geometry never leaves another case's curves on a plot or in a download; going back to a case shows its runs again.
Spectra from :func:`wheelrail.core.spectra.force.force_spectrum`, contact filters (model minus the reference model) from
:func:`wheelrail.core.spectra.levels.contact_filter`, reference filters from
:func:`wheelrail.core.reference_filters.reference_filters`.
"""

from __future__ import annotations

import csv
import io
import threading
from dataclasses import dataclass

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import REFERENCE_MODEL, model_names
from wheelrail.core.reference_filters import REFERENCE_FILTERS, run_reference_filters
from wheelrail.core.spectra.bands import nominal_band_label
from wheelrail.core.spectra.levels import contact_filter
from wheelrail.explorer.config import RunConfig

__all__ = ["Entry", "ResultStore", "case_reference_filters"]


@dataclass(frozen=True)
class Entry:
    """One model's run of one case: the result, its spectrum (centres, levels) or why there is none."""

    config: RunConfig
    result: object
    spectrum: tuple[np.ndarray, np.ndarray] | None
    problem: str | None = None  # stopped early, or the spectrum failed
    planned_steps: int | None = None  # steps the run was to take (more than it has when stopped)
    noise: object = None  # its rolling noise (wheelrail.core.noise.run_noise.RunNoise), with CNOSSOS-EU beside it
    noise_problem: str | None = None  # why it has none

    @property
    def done_fraction(self) -> float:
        """Share of the planned steps the run took (1 for a finished run)."""
        planned = self.planned_steps or self.result.n_steps
        return min(1.0, self.result.n_steps / planned) if planned else 0.0


def case_reference_filters(config: RunConfig) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """CNOSSOS-EU A3 and analytic contact filters for the case's preload, contact geometry and speed, on the
    force-spectrum bands: name -> (band centres Hz, levels dB)."""
    references = run_reference_filters(config.contact(), config.speed)
    centres = references.frequency_bands.centres
    return {name: (centres, np.asarray(references.by_frequency[name], dtype=float)) for name in REFERENCE_FILTERS}


class ResultStore:
    """Thread-safe store of entries by (case, model); the run thread adds, the page reads."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._entries: dict[tuple, Entry] = {}

    def add(self, entry: Entry) -> None:
        with self._lock:
            self._entries[(entry.config.case(), entry.config.model)] = entry

    def clear(self) -> None:
        """Let go of every entry (a closed tab's results)."""
        with self._lock:
            self._entries.clear()

    def entries(self, case: tuple) -> dict[str, Entry]:
        """model -> entry of one case, in registry order."""
        with self._lock:
            found = {model: e for (c, model), e in self._entries.items() if c == case}
        return {m: found[m] for m in model_names() if m in found}

    def run_list(self) -> dict[str, RunConfig]:
        """The session's cases with a force spectrum, by their label (the page's run list), in run order."""
        with self._lock:
            entries = list(self._entries.values())
        return {e.config.case_label(): e.config for e in entries if e.spectrum is not None}

    def spectra(self, case: tuple) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        return {m: e.spectrum for m, e in self.entries(case).items() if e.spectrum is not None}

    def noise(self, case: tuple) -> dict[str, object]:
        """model -> its rolling noise (RunNoise) of one case, for the runs that have it, in registry order."""
        return {m: e.noise for m, e in self.entries(case).items() if e.noise is not None}

    def contact_filters(self, case: tuple) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Contact filter of every model run on this case: its level minus the reference model's, dB."""
        spectra = self.spectra(case)
        if REFERENCE_MODEL not in spectra:
            return {}
        centres, reference = spectra[REFERENCE_MODEL]
        return {
            m: (centres, contact_filter(levels, reference))
            for m, (c, levels) in spectra.items()
            if m != REFERENCE_MODEL and np.array_equal(c, centres)
        }

    def csv_text(self, config: RunConfig) -> str:
        """Force spectra, contact filters and reference filters of one case as CSV, headed by the case."""
        spectra = self.spectra(config.case())
        if not spectra:
            raise WheelrailError(f"no force spectrum yet for {config.case_label()}: finish a run first")
        filters = self.contact_filters(config.case())
        references = case_reference_filters(config)
        centres = next(iter(spectra.values()))[0]
        columns = [(f"{m}_level_db", levels) for m, (_, levels) in spectra.items()]
        columns += [(f"{m}_contact_filter_db", levels) for m, (_, levels) in filters.items()]
        columns += [(f"reference_{name}_db", _on(centres, c, levels)) for name, (c, levels) in references.items()]
        out = io.StringIO()
        out.write(f"# wheelrail explorer: {config.case_label(stated=True)}\n")
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(["band", "centre_hz", *(name for name, _ in columns)])
        for i, f in enumerate(centres):
            values = [column[i] for _, column in columns]
            writer.writerow(
                [nominal_band_label(f), f"{f:.6g}", *("" if not np.isfinite(v) else f"{v:.3f}" for v in values)]
            )
        return out.getvalue()


def _on(centres: np.ndarray, their_centres: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """Levels given on ``their_centres`` placed on ``centres`` (NaN where a band is missing)."""
    out = np.full(centres.shape, np.nan)
    for i, f in enumerate(centres):
        match = np.nonzero(np.isclose(their_centres, f, rtol=1e-6))[0]
        if match.size:
            out[i] = levels[match[0]]
    return out
