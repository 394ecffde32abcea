"""The record a band spectrum analyses and the one rule that says which bands it resolves.

A spectrum of a record of duration T (the part left after any start-up skip) has FFT bins 1/T apart: its
frequency resolution. A band is resolved when it is at least that wide (``upper - lower >= 1 / T``) and lies
below the Nyquist frequency; every other band has no estimate (NaN: ``n/a`` in text, null in JSON). Third-octave
bands widen with their centre, so the resolved bands are one contiguous range, from the lowest resolved band up
to the last band below the Nyquist frequency: a short record loses its lowest bands, never a band in between.
:func:`wheelrail.core.spectra.narrowband.band_power` applies the rule,
:func:`wheelrail.core.spectra.force.spectrum_record` builds the :class:`SpectrumRecord` of a force spectrum, which
every front end prints.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SpectrumRecord", "resolved_bands"]

_WIDTH_TOLERANCE = 1e-9  # relative: a band exactly 1/T wide is resolved whatever the round-off


def resolved_bands(lower, upper, resolution: float, nyquist: float = np.inf) -> np.ndarray:
    """Which bands a spectrum of frequency resolution ``resolution`` resolves (module docstring's rule).

    Parameters
    ----------
    lower, upper : array_like
        Band edges, in the unit of ``resolution`` (Hz, or cycles/m for a spatial record).
    resolution : float
        Spacing of the spectrum's bins, 1 / (the analysed record's duration or length).
    nyquist : float
        Half the sampling rate; bands reaching above it are not resolved (default: no limit).

    Returns
    -------
    numpy.ndarray of bool
        True where the band is at least ``resolution`` wide and its upper edge at most ``nyquist``.

    Examples
    --------
    >>> from wheelrail.core.spectra.record import resolved_bands
    >>> resolved_bands([44.7, 56.2, 70.8], [56.2, 70.8, 89.1], resolution=15.0).tolist()   # widths 11.5, 14.6, 18.3 Hz
    [False, False, True]
    """
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    return (upper - lower >= resolution * (1.0 - _WIDTH_TOLERANCE)) & (upper <= nyquist)


@dataclass(frozen=True, kw_only=True, eq=False)
class SpectrumRecord:
    """What a band spectrum of a sampled record analysed, and which of its bands that resolves.

    Attributes
    ----------
    n_steps : int
        Samples of the whole record.
    time_step : float
        Sampling interval, s.
    skipped_steps : int
        Samples left out at the start (the start-up skip in whole steps).
    band_centres : numpy.ndarray
        Exact band centres, Hz.
    band_labels : list of str
        Their nominal names ("50", "63", ...).
    resolved : numpy.ndarray of bool
        True where a band has an estimate (:func:`resolved_bands`).
    """

    n_steps: int
    time_step: float
    skipped_steps: int
    band_centres: np.ndarray
    band_labels: list
    resolved: np.ndarray

    @property
    def skip(self) -> float:
        """The start left out, s (whole steps)."""
        return self.skipped_steps * self.time_step

    @property
    def analysed_steps(self) -> int:
        """Samples the spectrum analyses."""
        return self.n_steps - self.skipped_steps

    @property
    def duration(self) -> float:
        """Duration T of the analysed record, s."""
        return self.analysed_steps * self.time_step

    @property
    def resolution(self) -> float:
        """Frequency resolution 1 / T, Hz: the narrowest band the spectrum resolves (inf for no record)."""
        return 1.0 / self.duration if self.analysed_steps > 0 else float("inf")

    @property
    def nyquist(self) -> float:
        """Half the sampling rate, Hz: no band above it is resolved."""
        return 0.5 / self.time_step

    def lowest_resolved(self) -> int | None:
        """Index of the lowest resolved band (None when none is)."""
        found = np.flatnonzero(self.resolved)
        return int(found[0]) if found.size else None

    def highest_resolved(self) -> int | None:
        """Index of the highest resolved band (None when none is)."""
        found = np.flatnonzero(self.resolved)
        return int(found[-1]) if found.size else None

    def to_dict(self) -> dict:
        """Plain, JSON-ready view: the skip, the analysed record and the resolved range (keys with their unit)."""
        low, high = self.lowest_resolved(), self.highest_resolved()
        return {
            "skip_s": self.skip,
            "analysed_steps": self.analysed_steps,
            "analysed_duration_s": self.duration,
            "frequency_resolution_hz": self.resolution,
            "nyquist_hz": self.nyquist,
            "lowest_resolved_band_hz": None if low is None else float(self.band_centres[low]),
            "lowest_resolved_band_label": None if low is None else self.band_labels[low],
            "highest_resolved_band_hz": None if high is None else float(self.band_centres[high]),
            "highest_resolved_band_label": None if high is None else self.band_labels[high],
            "rule": "a band is resolved when it is at least 1 / analysed_duration_s wide and below nyquist_hz",
        }

    def words(self) -> str:
        """One line for people: what was left out, what was analysed and which bands that resolves."""
        low, high = self.lowest_resolved(), self.highest_resolved()
        head = (
            f"spectrum of {self.duration * 1e3:.4g} ms ({self.analysed_steps} steps) after the first "
            f"{self.skip * 1e3:.4g} ms (start-up, left out)"
        )
        if low is None:
            return f"{head}: no band resolved"
        return (
            f"{head}: bands {self.band_labels[low]}-{self.band_labels[high]} Hz resolved; n/a: a band narrower "
            f"than 1 / {self.duration * 1e3:.4g} ms = {self.resolution:.4g} Hz or above {self.nyquist:.0f} Hz (Nyquist)"
        )
