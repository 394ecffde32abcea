"""Generic spectral analysis: third-octave bands, band-integrated narrowband spectra, levels, coherence.

Used for roughness (paper section 3.1-3.2, Figs 6 and 9) and later for contact-force spectra (Figs 10-17).
The functions work on any uniformly sampled signal; the "frequency" axis is in cycles per unit of the
sampling axis (Hz for time signals, cycles/m for spatial ones). Third-octave bands are the exact base-10
bands of IEC 61260: centres ``10^(n/10)`` (n integer) in the same unit, edges ``centre x 10^(±1/20)``.
So 1000 Hz, 501.19 Hz (nominal 500), 10^-1.25 m = 56.2 mm (nominal 56 mm wavelength band) are all
centres; a band of wavelengths [l_lo, l_hi] is the band of spatial frequencies [1/l_hi, 1/l_lo].
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.checks import finite_array, integer, mean_squares, real, samples
from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.spectrum_record import SpectrumRecord, resolved_bands

BAND_HALF_WIDTH = 10.0 ** (1.0 / 20.0)  # upper edge / centre of a third-octave band (base 10)


def third_octave_bands(lowest: float, highest: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact base-10 third-octave bands whose centres lie in ``[lowest, highest]``.

    Parameters
    ----------
    lowest, highest : float
        Range of band centres, any positive unit (Hz, cycles/m, m). A centre within 1 % of a limit
        counts as inside, so nominal values (50 Hz, 8000 Hz, 0.8 m, 3.15 mm) select their own band.

    Returns
    -------
    centres, lower, upper : numpy.ndarray
        Band centres ``10^(n/10)`` in increasing order and their edges ``centre x 10^(∓1/20)``.

    Raises
    ------
    WheelrailError
        Unless 0 < lowest <= highest, both finite.

    See Also
    --------
    third_octave_levels : band levels of signals in these bands.

    Examples
    --------
    >>> from wheelrail.core.spectra import nominal_band_label, third_octave_bands
    >>> centres, lower, upper = third_octave_bands(50.0, 8000.0)   # the paper's force bands, Hz
    >>> centres.size, [nominal_band_label(c) for c in centres[:4]]
    (23, ['50', '63', '80', '100'])
    """
    lowest = real("third_octave_bands: lowest", lowest, "the unit of the centres")
    highest = real("third_octave_bands: highest", highest, "the unit of the centres")
    if not lowest <= highest:
        raise WheelrailError(f"third-octave range must satisfy 0 < lowest <= highest, got {lowest!r} .. {highest!r}")
    first = math.ceil(10 * math.log10(lowest) - 0.05)
    last = math.floor(10 * math.log10(highest) + 0.05)
    centres = 10.0 ** (np.arange(first, last + 1) / 10.0)
    return centres, centres / BAND_HALF_WIDTH, centres * BAND_HALF_WIDTH


def nominal_band_label(centre: float) -> str:
    """The usual rounded name of an exact base-10 band centre (e.g. 501.19 -> '500', 0.0631 -> '0.063')."""
    centre = real("nominal_band_label: centre", centre, "Hz")
    exponent = math.floor(math.log10(centre))
    mantissa = centre / 10.0**exponent
    nominal = [1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0, 10.0]
    best = min(nominal, key=lambda m: abs(math.log10(m / mantissa)))
    value = best * 10.0**exponent
    return f"{value:.0f}" if 1e4 <= value < 1e16 else f"{value:.4g}"  # 10000, not .4g's 1e+04


def band_labels(centres) -> list[str]:
    """:func:`nominal_band_label` of every exact centre: the one naming of bands in text, JSON (``band_labels``
    beside the exact ``band_centres_hz``) and CSV (a ``band`` column beside ``centre_hz``)."""
    values = finite_array("band_labels: centres", centres, "Hz").reshape(-1)
    return [nominal_band_label(float(centre)) for centre in values]


def narrowband_spectrum(signal: np.ndarray, sample_rate: float) -> tuple[np.ndarray, np.ndarray]:
    """One-sided power spectral density from a single Hann-windowed FFT of each row (paper section 3.1).

    The estimate of ``scipy.signal.periodogram(window="hann", scaling="density", detrend=False)``, computed
    with ``numpy.fft`` (importing ``scipy.signal`` costs a command-line run more than a second): the periodic
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
    (:func:`wheelrail.core.spectrum_record.resolved_bands`, the one rule), so the bands with an estimate are
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


def _band_range(band_range) -> tuple[float, float]:
    """``band_range`` as (lowest, highest) band centre; the values are checked by :func:`third_octave_bands`."""
    if isinstance(band_range, str | bytes) or not hasattr(band_range, "__len__") or len(band_range) != 2:
        raise WheelrailError(f"band_range must be (lowest, highest) band centres, got {type(band_range).__name__}")
    return band_range[0], band_range[1]


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
    centres, lower, upper = third_octave_bands(*_band_range(band_range))
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
    import scipy.signal  # heavy (a second at import): only the coherence needs it

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


FORCE_REFERENCE = 1.0  # N: contact-force levels are in dB re 1 N
FORCE_BAND_RANGE = (50.0, 8000.0)  # Hz, band centres of the paper's force spectra (Figs 10-17)
FORCE_SKIP = 0.02  # s, start of a run left out of force spectra (see force_spectrum)
FORCE_MIN_STEPS = 16  # steps a force spectrum needs after FORCE_SKIP


def shortest_spectrum_run(speed: float, element_size: float, skip: float = FORCE_SKIP) -> float:
    """The shortest run that has a force spectrum: ``skip`` left out and ``FORCE_MIN_STEPS`` steps after it.

    Parameters
    ----------
    speed : float
        Train speed, m/s.
    element_size : float
        Step length along the rail, m.
    skip : float
        Start of the run left out, s (whole steps, as :func:`force_spectrum` counts them).

    Returns
    -------
    float
        Run length, m.

    Raises
    ------
    WheelrailError
        A speed, element size or skip that is not a finite number of its sign, or a skip of more steps than a
        float counts exactly.

    Examples
    --------
    >>> from wheelrail.core.spectra import shortest_spectrum_run
    >>> round(shortest_spectrum_run(100 / 3.6, 1e-3), 3)    # m at 100 km/h, 1 mm steps: 556 skipped + 16
    0.572
    """
    speed = real("shortest_spectrum_run: speed", speed, "m/s")
    element_size = real("shortest_spectrum_run: element_size", element_size, "m")
    skip = real("shortest_spectrum_run: skip", skip, "s", sign="nonnegative")
    steps = skip * speed / element_size
    if steps > 1e15:  # more steps than a float counts exactly, and than any run has
        raise WheelrailError(f"shortest_spectrum_run: a skip of {steps:.3g} steps (speed x skip / element_size)")
    return (math.ceil(steps - 1e-9) + FORCE_MIN_STEPS) * element_size


def check_spectrum_length(length: float, speed: float, element_size: float) -> None:
    """A run of ``length`` m at ``speed`` m/s has a force spectrum; else one WheelrailError blaming the length
    (key ``length``) with the shortest that has one (:func:`shortest_spectrum_run`)."""
    if isinstance(length, bool) or not isinstance(length, int | float):
        raise WheelrailError(f"check_spectrum_length: length must be a number in m, got {type(length).__name__}")
    if not (math.isfinite(length) and length > 0):
        raise WheelrailError("not a positive length", Blame("length", length, unit="m"))
    shortest = shortest_spectrum_run(speed, element_size)
    if length < shortest - 1e-9 * element_size:
        raise WheelrailError(
            f"too short for a force spectrum at {speed * 3.6:.4g} km/h, which leaves out the first "
            f"{FORCE_SKIP * 1e3:g} ms (start-up) and needs {FORCE_MIN_STEPS} steps after them",
            Blame("length", length, unit="m", minimum=shortest),
        )


def _force_record(result_or_force, time_step, skip) -> tuple[np.ndarray, float, float]:
    """The force (N), time step (s) and skip (s) of :func:`force_spectrum`, checked (one WheelrailError each)."""
    if hasattr(result_or_force, "force") and hasattr(result_or_force, "time_step"):
        own_step = float(result_or_force.time_step)
        if time_step is not None and not math.isclose(float(time_step), own_step, rel_tol=1e-9):
            raise WheelrailError(f"force_spectrum: time_step {time_step!r} s differs from the run's {own_step!r} s")
        force, time_step = result_or_force.force, own_step
    else:
        force = result_or_force
        if time_step is None:
            raise WheelrailError("force_spectrum: time_step (s) is required when a force array is given")
    try:
        time_step = float(time_step)
        skip = float(skip)
        force = np.asarray(force, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError("force_spectrum: force must be numbers in N, time_step and skip numbers in s") from None
    if not (math.isfinite(time_step) and time_step > 0):
        raise WheelrailError(f"force_spectrum: time_step must be a positive number of seconds, got {time_step!r}")
    if not (math.isfinite(skip) and skip >= 0):
        raise WheelrailError(f"force_spectrum: skip must be zero or a positive number of seconds, got {skip!r}")
    if force.ndim != 1:
        raise WheelrailError(f"force_spectrum: force must be one value per step, got shape {force.shape}")
    if not np.all(np.isfinite(force)):
        raise WheelrailError("force_spectrum: force contains NaN or infinity")
    return force, time_step, skip


def force_spectrum(
    result_or_force,
    time_step: float | None = None,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> tuple[np.ndarray, np.ndarray]:
    """Third-octave band levels of the dynamic contact force, dB re 1 N (paper Figs 10-17).

    Steps: (1) the first ``skip`` seconds are dropped (start-up); (2) the mean of the rest is removed, so
    only the dynamic part around the (pre)load is analysed; (3) one Hann-windowed FFT of the whole
    remaining record with the power-conserving window correction (:func:`narrowband_spectrum`, as for the
    roughness spectra of section 3.1); (4) the PSD is integrated into exact base-10 third-octave bands
    (:func:`band_power`) and expressed as ``10 log10(F_band² / (1 N)²)``. A tone of amplitude F̂ in a band
    therefore reads ``20 log10(F̂ / sqrt(2))`` dB. A band is resolved when it is at least as wide as the
    frequency resolution 1 / T of the record analysed (T: the duration left after ``skip``) and lies below the
    Nyquist frequency; every other band is NaN. The resolved bands are contiguous (third-octave bands widen with
    their centre): a short record loses its lowest bands. :func:`spectrum_record` says what was left out, what
    was analysed and which bands that resolves, as every front end prints it.

    Why skip the start: at step 0 the roughness starts acting on a system in its steady state on the gap of
    step 0 (the loop's start and run-in), and the response to that onset is a transient, not a property of the
    roughness. It decays within a few periods of the lowest, well-damped wheel-on-track resonances
    (~60-110 Hz); the default 20 ms is one period of the lowest band (50 Hz) and about 0.56 m at 100 km/h,
    7 % of the paper's 8 m run.

    Parameters
    ----------
    result_or_force : RunResult or array_like
        A run result (its ``force`` in N and ``time_step`` in s are used) or the contact force F_n(t), N,
        sampled every ``time_step`` s.
    time_step : float, optional
        Sampling interval dt, s. Required with an array; with a RunResult it must be omitted or equal to
        the result's.
    skip : float
        Duration excluded at the start of the record, s (default ``FORCE_SKIP`` = 0.02 s). 0 keeps all.
    band_range : (float, float)
        Lowest and highest band centre, Hz (default 50 Hz .. 8 kHz).

    Returns
    -------
    centres : numpy.ndarray
        Exact base-10 band centres, Hz.
    levels : numpy.ndarray
        Band levels of the dynamic contact force, dB re 1 N (NaN where a band is not resolved).

    Raises
    ------
    WheelrailError
        For a force that is not one finite number per step, a missing or inconsistent time step, or a record
        with fewer than ``FORCE_MIN_STEPS`` steps after ``skip``.

    See Also
    --------
    contact_filter : the difference of two models' levels.
    shortest_spectrum_run : the shortest run that has a spectrum.
    spectrum_record : the skip, the analysed duration and the resolved bands of the same call.

    Examples
    --------
    A tone of 100 N amplitude at 1 kHz on the 65 kN preload reads 20 log10(100 / sqrt(2)) = 37.0 dB in its band:

    >>> import numpy as np
    >>> from wheelrail.core.spectra import force_spectrum
    >>> time = np.arange(4096) * 1e-4                                   # s
    >>> force = 65e3 + 100.0 * np.sin(2 * np.pi * 1000.0 * time)        # N
    >>> centres, levels = force_spectrum(force, 1e-4)
    >>> loudest = int(np.nanargmax(levels))
    >>> round(float(centres[loudest])), round(float(levels[loudest]), 1)
    (1000, 37.0)
    """
    force, time_step, skip = _force_record(result_or_force, time_step, skip)
    first = _skipped_steps(force.size, time_step, skip)
    kept = force.size - first
    if kept < FORCE_MIN_STEPS:
        record = f"the record of {force.size} steps ({force.size * time_step:.4g} s)"
        if force.size < FORCE_MIN_STEPS:
            raise WheelrailError(
                f"force_spectrum: {record} is shorter than the {FORCE_MIN_STEPS} steps a "
                "spectrum needs; use a longer run"
            )
        raise WheelrailError(
            f"{record} leaves {max(kept, 0)} steps after the skip, and a spectrum needs {FORCE_MIN_STEPS}",
            Blame("skip", skip, unit="s", maximum=(force.size - FORCE_MIN_STEPS) * time_step),
            advice="or use a longer run",
        )
    dynamic = force[first:] - force[first:].mean()
    return third_octave_spectrum(dynamic, 1.0 / time_step, band_range, FORCE_REFERENCE)


def _skipped_steps(n_steps: int, time_step: float, skip: float) -> int:
    """Whole steps in the first ``skip`` seconds (at most ``n_steps``; no overflow for any finite skip)."""
    steps = skip / time_step
    return n_steps if steps >= n_steps else min(int(math.ceil(steps - 1e-9)), n_steps)


def spectrum_record(
    result_or_force,
    time_step: float | None = None,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> SpectrumRecord:
    """What :func:`force_spectrum` analyses with the same arguments: the start left out, the duration T of the
    record analysed, its frequency resolution 1 / T and the bands resolved (at least 1 / T wide, below the
    Nyquist frequency; contiguous).

    Parameters
    ----------
    result_or_force, time_step, skip, band_range
        As for :func:`force_spectrum`.

    Returns
    -------
    SpectrumRecord
        ``skip`` (s, whole steps), ``duration`` (s), ``resolution`` (Hz), ``resolved`` per band,
        ``to_dict()`` for JSON and ``words()`` for a line of text.

    Raises
    ------
    WheelrailError
        As :func:`force_spectrum`, for a force that is not one finite number per step or a bad time step or skip.

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.spectra import spectrum_record
    >>> record = spectrum_record(np.full(1000, 65e3), 1e-3 / (100 / 3.6))   # 1 m at 100 km/h, 1 mm steps
    >>> round(record.skip * 1e3, 2), round(record.duration * 1e3, 2), record.band_labels[record.lowest_resolved()]
    (20.02, 15.98, '315')
    """
    force, time_step, skip = _force_record(result_or_force, time_step, skip)
    return record_of_steps(force.size, time_step, skip=skip, band_range=band_range)


def record_of_steps(
    n_steps: int,
    time_step: float,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> SpectrumRecord:
    """:func:`spectrum_record` from the record's size alone: ``n_steps`` samples every ``time_step`` s."""
    n_steps = min(integer("record_of_steps: n_steps", n_steps, 0), 2**40)
    time_step = real("record_of_steps: time_step", time_step, "s")
    skip = real("record_of_steps: skip", skip, "s", sign="nonnegative")
    centres, lower, upper = third_octave_bands(*_band_range(band_range))
    first = _skipped_steps(n_steps, time_step, skip)
    kept = n_steps - first
    resolved = (
        resolved_bands(lower, upper, 1.0 / (kept * time_step), 0.5 / time_step)
        if kept >= 2
        else np.zeros(centres.shape, dtype=bool)
    )
    return SpectrumRecord(
        n_steps=n_steps,
        time_step=time_step,
        skipped_steps=first,
        band_centres=centres,
        band_labels=band_labels(centres),
        resolved=resolved,
    )


def resolved_force_bands(
    n_steps: int,
    time_step: float,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> tuple[np.ndarray, np.ndarray]:
    """Band centres (Hz) and which bands :func:`force_spectrum` resolves (bool) for a record of ``n_steps``
    samples every ``time_step`` s (:func:`record_of_steps`); the other bands are NaN. Checks stored spectra."""
    record = record_of_steps(n_steps, time_step, skip=skip, band_range=band_range)
    return record.band_centres, record.resolved
