"""Algebra of levels in dB over bands: the mean over lines, differences, energetic sums and the contact filter
(paper section 4, eq. 22). Re-exported by :mod:`wheelrail.core.spectra`, where the spectra these act on are made.
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.checks import level_arrays

__all__ = ["contact_filter", "energetic_sum", "level_difference", "mean_level"]


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
    >>> from wheelrail.core.spectrum_levels import mean_level
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


def energetic_sum(*levels) -> np.ndarray:
    """Band levels of uncorrelated signals added: 10 lg(sum 10^(L/10)) per band, dB (NaN where any is NaN).

    The level of a sum of independent signals, such as the rail and the wheel roughness of one contact: the
    total roughness of CNOSSOS-EU (Commission Directive (EU) 2015/996, Annex II, 2.3.2) is this sum of the
    rail and the wheel roughness levels.
    """
    stack = np.vstack(level_arrays("energetic_sum: levels", levels))
    with np.errstate(divide="ignore"):  # every level -inf (no power): the sum is -inf too
        return 10.0 * np.log10(np.sum(10.0 ** (stack / 10.0), axis=0))


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
    >>> from wheelrail.core.spectrum_levels import contact_filter
    >>> contact_filter(np.array([60.0, 50.0]), np.array([60.0, 55.0])).tolist()   # dB: no filter, then -5 dB
    [0.0, -5.0]
    """
    return level_difference(levels_model, levels_hertz)
