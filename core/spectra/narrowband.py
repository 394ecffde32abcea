"""Spectra of uniformly sampled signals: the Hann-windowed narrowband spectrum, band powers and levels, block
spectra and the band coherence (paper sections 3.1-3.2).

The functions work on any uniformly sampled signal; the "frequency" axis is in cycles per unit of the sampling
axis (Hz for time signals, cycles/m for spatial ones), and the bands are those of
:func:`wheelrail.core.spectra.bands.third_octave_bands`. Used for roughness (Figs 6 and 9) and, through
:mod:`wheelrail.core.spectra.force`, for contact-force spectra (Figs 10-17).
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import finite_array, integer, mean_squares, real, samples
from wheelrail.core.spectra.bands import band_centre_range, third_octave_bands
from wheelrail.core.spectra.record import resolved_bands


def narrowband_spectrum(signal: np.ndarray, sample_rate: float) -> tuple[np.ndarray, np.ndarray]:
    """One-sided power spectral density from a single Hann-windowed FFT of each row (paper section 3.1).

    The estimate of ``scipy.signal.periodogram(window="hann", scaling="density", detrend=False)``, computed
    with ``numpy.fft`` (so that the command line, which reads spectra, does not import ``scipy.signal``): the periodic
    Hann window, the squared FFT divided by ``sample_rate * sum(w^2)`` (the window's power, i.e. the Hann
    window's mean square 3/8 times the number of samples) and doubled for positive frequencies (not the
    Nyquist bin of an even length). The same operations in the same order; only the FFTs differ (numpy's
    and scipy's pocketfft), by round-off: PSDs within 5e-15 of the largest, levels within 1e-12 dB. This is
    the power-conserving window correction: summing the PSD times the bin width gives the mean square of the
    windowed-and-corrected signal, equal on average to the mean square of the signal. A stationary random
    signal's band power is therefore unbiased; a pure tone's power is spread over about 3 bins (Hann main
    lobe), which band integration gathers again.

    Parameters
    ----------
    signal : numpy.ndarray
        Samples, shape (n,) or (rows, n), in any unit U.
    sample_rate : float
        Samples per unit of the sampling axis (1/dx for a spatial signal, 1/dt for a time signal).

    Returns
    -------
    frequencies : numpy.ndarray
        Bin frequencies, cycles per unit of the sampling axis.
    psd : numpy.ndarray
        One-sided PSD, U² per (cycle per unit), same leading shape as ``signal``.
    """
    signal = samples("spectrum: signal", signal, "any unit")
    sample_rate = real("spectrum: sample_rate", sample_rate, "samples per unit of the sampling axis")
    n = signal.shape[-1]
    window = hann_window(n)
    spectrum = np.fft.rfft(window * signal, n=n, axis=-1)
    psd = np.conjugate(spectrum) * spectrum
    psd *= 1.0 / (sample_rate * (window * window).sum())
    if n % 2:
        psd[..., 1:] *= 2
    else:
        psd[..., 1:-1] *= 2
    return np.fft.rfftfreq(n, 1.0 / sample_rate), psd.real


def hann_window(n: int) -> np.ndarray:
    """The periodic Hann window of n samples, 0.5 + 0.5 cos(phi) on n + 1 points from -pi to pi less the last:
    ``scipy.signal.get_window("hann", n)`` to the bit (the same expression)."""
    n = integer("hann_window: n", n, 1)
    phase = np.linspace(-np.pi, np.pi, n + 1)[:-1]
    window = np.zeros(n)
    window += 0.5 * np.cos(0.0 * phase)
    window += 0.5 * np.cos(phase)
    return window


def band_power(frequencies: np.ndarray, psd: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Integrate a narrowband PSD into bands: sum of ``psd * df`` over bins with ``lower <= f < upper``.

    Returns the band mean squares (U²), shape ``psd.shape[:-1] + (bands,)``. A band narrower than the bin
    spacing (the frequency resolution 1 / the record's duration) gives NaN: there is no estimate there
    (:func:`wheelrail.core.spectra.record.resolved_bands`, the one rule), so the bands with an estimate are
    contiguous.
    """
    frequencies = samples("band_power: frequencies", frequencies, "cycles per unit", rows=False)
    df = frequencies[1] - frequencies[0]
    if not np.all(np.diff(frequencies) > 0):
        raise WheelrailError("band_power: frequencies must increase (the bins of a spectrum)")
    psd = mean_squares("band_power: psd", psd, "the signal's unit squared per cycle")
    if psd.ndim == 0 or psd.shape[-1] != frequencies.size:
        raise WheelrailError(f"band_power: psd of shape {psd.shape} for {frequencies.size} frequencies")
    lower, upper = _band_edges("band_power", lower, upper)
    out = np.full(psd.shape[:-1] + (len(lower),), np.nan)
    resolved = resolved_bands(lower, upper, df)
    for band, (lo, hi) in enumerate(zip(lower, upper, strict=True)):
        if resolved[band]:
            inside = (frequencies >= lo) & (frequencies < hi)
            out[..., band] = psd[..., inside].sum(axis=-1) * df
    return out


def _band_edges(where: str, lower, upper) -> tuple[np.ndarray, np.ndarray]:
    """Band edges: two 1-D arrays of one length, positive and finite, each lower edge below its upper one."""
    lower = finite_array(f"{where}: lower", lower, "cycles per unit")
    upper = finite_array(f"{where}: upper", upper, "cycles per unit")
    if lower.ndim != 1 or lower.shape != upper.shape or np.any(lower <= 0) or np.any(upper <= lower):
        raise WheelrailError(f"{where}: band edges must be two 1-D arrays of one length with 0 < lower < upper")
    return lower, upper


def level_db(mean_square: np.ndarray, reference: float) -> np.ndarray:
    """Level ``10 log10(mean_square / reference²)`` in dB re ``reference`` (NaN stays NaN, 0 -> -inf), computed
    as ``10 lg(mean_square) - 20 lg(reference)`` (no overflow for any finite inputs)."""
    reference = real("level_db: reference", reference, "the mean square's unit, square-rooted")
    mean_square = mean_squares("level_db: mean_square", mean_square, "the reference's unit squared")
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(mean_square) - 20.0 * math.log10(reference)


def third_octave_levels(
    signals: np.ndarray,
    sample_rate: float,
    lower: np.ndarray,
    upper: np.ndarray,
    reference: float,
) -> np.ndarray:
    """Third-octave band levels of one or several signals, averaged energetically over the rows.

    A single Hann-windowed FFT per row (:func:`narrowband_spectrum`) is integrated into the bands
    (:func:`band_power`); the band mean squares of all rows are averaged (the paper averages 7 roughness
    lines, section 3.1) and expressed in dB re ``reference`` (:func:`level_db`).

    Parameters
    ----------
    signals : numpy.ndarray
        One signal (n,) or several as rows (rows, n), uniformly sampled.
    sample_rate : float
        Samples per unit of the sampling axis (per s: Hz; per m: cycles/m).
    lower, upper : numpy.ndarray
        Band edges, in the unit of ``sample_rate`` (:func:`third_octave_bands`).
    reference : float
        Reference value of the levels, in the signals' unit (1 N for forces).

    Returns
    -------
    levels : numpy.ndarray
        dB re ``reference``, one per band (NaN where a band is narrower than the bin spacing).

    See Also
    --------
    force_spectrum : the contact force's levels, start-up left out and mean removed.
    """
    frequencies, psd = narrowband_spectrum(np.atleast_2d(signals), sample_rate)
    return level_db(band_power(frequencies, psd, lower, upper).mean(axis=0), reference)


def third_octave_spectrum(
    signals: np.ndarray,
    sample_rate: float,
    band_range: tuple[float, float],
    reference: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Bands and levels in one call: :func:`third_octave_bands` then :func:`third_octave_levels`.

    E.g. a contact-force time signal ``force`` (N) sampled every ``dt`` s:
    ``third_octave_spectrum(force, 1 / dt, (50, 8000), 1.0)`` gives the band centres (Hz) and the
    levels in dB re 1 N.

    Returns
    -------
    centres : numpy.ndarray
        Exact base-10 band centres, unit of ``sample_rate``.
    levels : numpy.ndarray
        dB re ``reference``, averaged energetically over rows; NaN where a band is narrower than the bin
        spacing or above the Nyquist frequency.
    """
    sample_rate = real("third_octave_spectrum: sample_rate", sample_rate, "samples per unit of the sampling axis")
    centres, lower, upper = third_octave_bands(*band_centre_range(band_range))
    levels = third_octave_levels(signals, sample_rate, lower, upper, reference)
    nyquist = 0.5 * sample_rate
    return centres, np.where(upper <= nyquist, levels, np.nan)


def block_spectra(
    centre: np.ndarray, others: np.ndarray, sample_rate: float, blocks: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Block-averaged auto- and cross-spectra of a centre signal and other signals (paper section 3.2).

    Each signal is divided into ``blocks`` consecutive, non-overlapping blocks of ``n // blocks`` samples
    (the remainder at the end is dropped); each block is Hann-windowed and the spectra are averaged over
    blocks (``scipy.signal.csd``/``welch`` with ``noverlap=0``, mean per block removed).

    Returns
    -------
    frequencies : numpy.ndarray
        Bin frequencies, cycles per unit of the sampling axis.
    s00 : numpy.ndarray
        Auto-spectrum of the centre signal, shape (bins,).
    smm : numpy.ndarray
        Auto-spectra of the other signals, shape (others, bins).
    s0m : numpy.ndarray
        Cross-spectra centre x other (complex), shape (others, bins).
    """
    centre = samples("block_spectra: centre", centre, "any unit", rows=False)
    others = np.atleast_2d(samples("block_spectra: others", others, "any unit"))
    if others.shape[-1] != centre.size:
        raise WheelrailError(f"block_spectra: others of {others.shape[-1]} samples beside a centre of {centre.size}")
    sample_rate = real("block_spectra: sample_rate", sample_rate, "samples per unit of the sampling axis")
    if isinstance(blocks, bool) or int(blocks) != blocks or blocks < 1:
        raise WheelrailError(f"number of blocks B must be a positive integer, got {blocks!r}")
    segment = centre.shape[-1] // int(blocks)
    if segment < 8:
        raise WheelrailError(
            f"B = {blocks} blocks leave {segment} samples per block (at least 8 needed) for {centre.shape[-1]} samples"
        )
    import scipy.signal  # heavy to import: only the coherence needs it

    options = dict(fs=sample_rate, window="hann", nperseg=segment, noverlap=0, detrend="constant")
    frequencies, s00 = scipy.signal.welch(centre, **options)
    _, smm = scipy.signal.welch(others, axis=-1, **options)
    _, s0m = scipy.signal.csd(centre[np.newaxis, :], others, axis=-1, **options)
    return frequencies, s00, smm, s0m


def band_coherence(
    centre: np.ndarray,
    others: np.ndarray,
    sample_rate: float,
    lower: np.ndarray,
    upper: np.ndarray,
    blocks: int = 20,
) -> np.ndarray:
    """Lateral coherence parameter γ²(f0) of eqs. (15)-(18) in each band.

    ``S_xx(f0)`` is the block-averaged auto-spectrum of the centre line averaged over the L bins of the
    band (eq. 16); ``S_yy(f0)`` the auto-spectra of the 2M other lines averaged over lines and bins
    (eq. 17); ``S_xy(f0)`` the cross-spectra centre x line m averaged likewise (eq. 18, complex average);
    ``γ² = |S_xy|² / (S_xx S_yy)`` (eq. 15).

    Estimation bias: for independent lines the expected value is not 0 but about
    ``1 / (B x 2M x L_eff)`` (the averaged cross-spectrum keeps a random residue), with ``L_eff`` the
    number of statistically independent bins in the band (roughly L/1.5 for Hann); at most ~1/B.

    Parameters
    ----------
    centre : numpy.ndarray
        Line 0, shape (n,).
    others : numpy.ndarray
        Lines m = -M..M, m != 0, shape (2M, n).
    sample_rate : float
        Samples per unit of the sampling axis.
    lower, upper : numpy.ndarray
        Band edges in the unit of ``sample_rate``.
    blocks : int
        B, the number of consecutive blocks per line (paper: 20).

    Returns
    -------
    numpy.ndarray
        γ² per band, in [0, 1]; NaN where the band holds no bin of the block spectra.

    See Also
    --------
    third_octave_bands : the band edges.
    """
    frequencies, s00, smm, s0m = block_spectra(centre, others, sample_rate, blocks)
    lower, upper = _band_edges("band_coherence", lower, upper)
    out = np.full(len(lower), np.nan)
    for band, (lo, hi) in enumerate(zip(lower, upper, strict=True)):
        inside = (frequencies >= lo) & (frequencies < hi)
        if not inside.any():
            continue
        sxx = s00[inside].mean()  # eq. (16)
        syy = smm[:, inside].mean()  # eq. (17)
        sxy = s0m[:, inside].mean()  # eq. (18)
        if sxx > 0 and syy > 0:
            out[band] = abs(sxy) ** 2 / (sxx * syy)  # eq. (15)
    return out
