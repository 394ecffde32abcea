"""Levels in dB: references, A-weighting, energetic sums, the mean over lines, differences and the contact filter.

Band levels are ``10 lg`` of a mean square over the square of a reference (:data:`SOUND_POWER_REFERENCE`,
:data:`PRESSURE_REFERENCE`, :data:`ROUGHNESS_REFERENCE`); the contact filter is a level difference (paper
section 4, eq. 22). A-weighting is the closed form of IEC 61672-1:2013 (eqs. E.1-E.6, A(f) = 20 lg(f4^2 f^4 /
((f^2 + f1^2) sqrt(f^2 + f2^2) sqrt(f^2 + f3^2) (f^2 + f4^2))) - A1000) evaluated at the exact base-10 band
centres 10^(n/10) Hz; rounded to 0.1 dB it gives the standard's tabulated values (checked in
``tests/physics/test_noise_cnossos.py``).
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import finite_array, level_arrays, mean_squares, real
from wheelrail.core.spectra.bands import noise_bands

__all__ = [
    "PRESSURE_REFERENCE",
    "ROUGHNESS_REFERENCE",
    "SOUND_POWER_REFERENCE",
    "a_weighted_energy",
    "a_weighted_total",
    "a_weighting",
    "contact_filter",
    "energy_sum",
    "level",
    "level_difference",
    "mean_level",
    "power_level",
]

SOUND_POWER_REFERENCE = 1e-12  # W: sound power levels in dB re 1 pW
PRESSURE_REFERENCE = 20e-6  # Pa: sound pressure levels in dB re 20 uPa
ROUGHNESS_REFERENCE = 1e-6  # m: roughness levels in dB re 1 um

# IEC 61672-1:2013 Annex E: pole frequencies (Hz) of the A-weighting closed form
_F1, _F2, _F3, _F4 = 20.598997, 107.65265, 737.86223, 12194.217


def _lg_sum_of_squares(f: np.ndarray, pole: float) -> np.ndarray:
    """lg(f^2 + pole^2), without squaring f (no overflow for any finite f)."""
    big, small = np.maximum(f, pole), np.minimum(f, pole)
    return 2.0 * np.log10(big) + np.log1p((small / big) ** 2) / math.log(10.0)


def _a_weighting_raw(f: np.ndarray) -> np.ndarray:
    """20 lg(f4^2 f^4 / ((f^2 + f1^2) sqrt(f^2 + f2^2) sqrt(f^2 + f3^2) (f^2 + f4^2))), in logarithms."""
    with np.errstate(divide="ignore"):  # lg 0 = -inf: the weighting at 0 Hz
        lg_f = np.log10(f)
    return 20.0 * (
        2.0 * math.log10(_F4)
        + 4.0 * lg_f
        - _lg_sum_of_squares(f, _F1)
        - 0.5 * (_lg_sum_of_squares(f, _F2) + _lg_sum_of_squares(f, _F3))
        - _lg_sum_of_squares(f, _F4)
    )


def a_weighting(frequency) -> np.ndarray:
    """A-weighting in dB at ``frequency`` (Hz, >= 0), IEC 61672-1 closed form (0 dB at 1 kHz; -inf at 0 Hz).

    Computed in logarithms, so any finite frequency has its value (-40 lg f + 94.9 dB far above 12 kHz) without
    overflow; a NaN, an infinity or a negative frequency is one WheelrailError."""
    f = finite_array("a_weighting: frequency", frequency, "Hz")
    if np.any(f < 0):
        raise WheelrailError("a_weighting: frequency must be zero or positive (Hz)")
    return _a_weighting_raw(f) - _a_weighting_raw(np.array(1000.0))


def a_weighted_energy(pressure: np.ndarray, rate: float) -> float:
    """Sum of the squared A-weighted pressure (Pa^2), A-weighting applied in the frequency domain."""
    spectrum = np.fft.rfft(pressure)
    f = np.fft.rfftfreq(len(pressure), 1.0 / rate)
    weight = np.zeros_like(f)
    weight[1:] = 10 ** (a_weighting(f[1:]) / 20)
    weighted = np.fft.irfft(spectrum * weight, len(pressure))
    return float(np.sum(weighted**2))


def energy_sum(*levels_db, axis=None) -> np.ndarray:
    """10 lg of the sum of 10^(L/10): levels added energetically (element-wise, or along ``axis`` of one array).

    The level of a sum of uncorrelated signals, such as the rail and the wheel roughness of one contact (the total
    roughness of CNOSSOS-EU, Commission Directive (EU) 2015/996, Annex II, 2.3.2) or the noise of a run's
    components. ``-inf`` levels contribute nothing (all ``-inf``: ``-inf``); NaN propagates.
    """
    if axis is not None:
        if len(levels_db) != 1:
            raise WheelrailError(f"energy_sum: one array of levels with axis={axis!r}, got {len(levels_db)}")
        (levels,) = level_arrays("energy_sum: levels_db", levels_db)
        with np.errstate(divide="ignore"):
            return 10.0 * np.log10(np.sum(10.0 ** (np.asarray(levels, dtype=float) / 10.0), axis=axis))
    total = sum(10.0 ** (level / 10.0) for level in level_arrays("energy_sum: levels_db", levels_db))
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(total)


def a_weighted_total(levels_db, frequencies=None) -> float:
    """The A-weighted total (dB(A)) of band levels on the 24 bands (or on ``frequencies``, Hz)."""
    (levels,) = level_arrays("a_weighted_total: levels_db", [levels_db])
    f = noise_bands() if frequencies is None else finite_array("a_weighted_total: frequencies", frequencies, "Hz")
    if levels.shape != f.shape:
        raise WheelrailError(f"A-weighted total: {levels.size} levels for {f.size} bands")
    return float(energy_sum(levels + a_weighting(f), axis=0))


def level(mean_square, reference: float) -> np.ndarray:
    """10 lg(mean_square / reference^2) for amplitudes (0 gives -inf; NaN, a band without a value, stays NaN).

    Computed as 10 lg(mean_square) - 20 lg(reference): no overflow for any finite inputs."""
    reference = real("level: reference", reference, "the mean square's unit, square-rooted")
    mean_square = mean_squares("level: mean_square", mean_square, "the reference's unit squared")
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(mean_square) - 20.0 * math.log10(reference)


def power_level(power_w) -> np.ndarray:
    """Sound power level, dB re 1 pW, of a power in W (0 W gives -inf; NaN, a band without a value, stays NaN)."""
    power = mean_squares("power_level: power_w", power_w, "W")
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(power) - 10.0 * math.log10(SOUND_POWER_REFERENCE)


def mean_level(levels) -> np.ndarray:
    """Arithmetic mean of band levels in dB over runs (the paper's averaged spectra of Fig. 10), dB.

    A choice: the mean is taken of the levels in dB, not of the band powers (an energetic mean). Section
    3.3 says only "an average of the seven spectra" for the force levels and "the average of the filter
    curves" for the contact filters, which are level differences in dB; averaging in dB keeps the two
    consistent (the mean filter equals the difference of the mean levels).

    Parameters
    ----------
    levels : sequence of array_like
        Band levels of each run, dB, all on the same bands.

    Returns
    -------
    numpy.ndarray
        The mean level per band, dB.

    Raises
    ------
    WheelrailError
        If the runs' levels are not numbers on the same bands.

    Examples
    --------
    >>> from wheelrail.core.spectra.levels import mean_level
    >>> mean_level([[60.0, 50.0], [62.0, 54.0]]).tolist()    # two runs, two bands, dB
    [61.0, 52.0]
    """
    stack = np.vstack(level_arrays("mean_level: levels", levels))
    return stack.mean(axis=0)


def level_difference(levels_a: np.ndarray, levels_b: np.ndarray) -> np.ndarray:
    """Level difference L_a - L_b per band (paper Figs 12-14, 16, 17).

    Parameters
    ----------
    levels_a, levels_b : numpy.ndarray
        Band levels, dB, on the same bands (one shape).

    Returns
    -------
    numpy.ndarray
        L_a - L_b per band, dB.

    Raises
    ------
    WheelrailError
        If the levels are not numbers of one shape.
    """
    levels_a, levels_b = level_arrays("level_difference: levels_a and levels_b", (levels_a, levels_b))
    return levels_a - levels_b


def contact_filter(levels_model: np.ndarray, levels_hertz: np.ndarray) -> np.ndarray:
    """Contact filter of a model: its level minus that of ``hertz`` (r_eq = r) on the same line, dB.

    Section 3.3: the Hertz spring without roughness pre-filtering has no contact filtering, so the level
    difference characterises the filtering of the other models (Fig. 10, right column).

    Parameters
    ----------
    levels_model : numpy.ndarray
        The model's force levels per band, dB re 1 N (:func:`force_spectrum`).
    levels_hertz : numpy.ndarray
        The ``hertz`` model's on the same line and bands, dB re 1 N.

    Returns
    -------
    numpy.ndarray
        The contact filter per band, dB (negative where the model filters the roughness).

    Raises
    ------
    WheelrailError
        If the levels are not numbers of one shape.

    See Also
    --------
    wheelrail.core.reference_filters.reference_filters : analytic and CNOSSOS-EU filters to compare with.

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.spectra.levels import contact_filter
    >>> contact_filter(np.array([60.0, 50.0]), np.array([60.0, 55.0])).tolist()   # dB: no filter, then -5 dB
    [0.0, -5.0]
    """
    return level_difference(levels_model, levels_hertz)
