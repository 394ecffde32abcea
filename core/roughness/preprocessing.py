"""Preprocessing of measured roughness (paper section 3.1; EN 15610): detrend, spike removal, high-pass.

Each step takes a :class:`~wheelrail.core.roughness.model.RoughnessSet` and returns a new one; wheel data
(one circumference) is treated as periodic throughout.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness.model import RoughnessSet

_SEAM_FIT_SAMPLES = 2  # samples on each side of a wheel's seam used to estimate the closure jump


def detrend_linear(roughness: RoughnessSet) -> RoughnessSet:
    """Remove a linear trend from every line (paper 3.1, step 1: trend of the measurement equipment).

    Rail (open) data: least-squares straight line removed (``scipy.signal.detrend``).
    Wheel (periodic) data: a drift of the equipment shows as a jump where the circumference closes, and a
    least-squares line would also take away part of the true periodic roughness (a harmonic of amplitude A
    and order n tilts the fit by ~2A/n over the circumference). The slope is therefore estimated from the
    closure jump: the last two and the first two samples are extrapolated linearly to the seam (half a
    sample beyond each end); their difference ``J`` is the drift over one circumference, ``s = J / (n dx)``,
    and ``s x`` is removed. For drift-free data the error of ``J`` is of the size of one ordinary
    sample-to-sample step (the curvature across the seam): the seam then stays as smooth as the rest of
    the profile. Longer fits were tried on the bundled wheels and err more (short-wavelength roughness).
    """
    z = roughness.heights
    if roughness.periodic:
        n = roughness.n_samples
        w = max(1, min(_SEAM_FIT_SAMPLES, n // 4))
        index = np.arange(w, dtype=float)
        if w >= 2:
            end_fit = np.polyfit(index, z[:, -w:].T, 1)  # (2, lines): slope, intercept per line
            start_fit = np.polyfit(index, z[:, :w].T, 1)
            end_value = end_fit[0] * (w - 0.5) + end_fit[1]  # at index n - 0.5
            start_value = start_fit[0] * (-0.5) + start_fit[1]  # at index -0.5
        else:
            end_value, start_value = z[:, -1], z[:, 0]
        slope = (end_value - start_value) / (n * roughness.dx)
        out = z - slope[:, np.newaxis] * roughness.x[np.newaxis, :]
    else:
        import scipy.signal  # imported where used: a second at import, which most commands never need

        out = scipy.signal.detrend(z, axis=1, type="linear")
    return roughness.with_heights(out)


def remove_mean(roughness: RoughnessSet) -> RoughnessSet:
    """Subtract the mean of every line (paper 3.1, step 3)."""
    z = roughness.heights
    return roughness.with_heights(z - z.mean(axis=1, keepdims=True))


def curvature(heights: np.ndarray, dx: float, *, periodic: bool) -> np.ndarray:
    """Curvature estimate of each line, the central second difference ``(z[i-1] - 2 z[i] + z[i+1]) / dx²``.

    Units 1/m. End samples of open lines get the curvature of their neighbour.
    """
    z = np.atleast_2d(heights)
    if periodic:
        return (np.roll(z, 1, axis=1) - 2 * z + np.roll(z, -1, axis=1)) / dx**2
    c = np.empty_like(z)
    c[:, 1:-1] = (z[:, :-2] - 2 * z[:, 1:-1] + z[:, 2:]) / dx**2
    c[:, 0] = c[:, 1]
    c[:, -1] = c[:, -2]
    return c


def default_curvature_limit(heights: np.ndarray, dx: float, *, periodic: bool) -> float:
    """Default spike threshold on |curvature|, 1/m: 10 robust standard deviations of the curvature.

    The robust standard deviation is 1.4826 x the median absolute curvature (Gaussian-consistent MAD), so
    genuine roughness (Gaussian-like) practically never exceeds it, while a spike one sample wide and
    a few µm high has a curvature of order height / dx², far above.
    """
    c = curvature(heights, dx, periodic=periodic)
    sigma = 1.4826 * float(np.median(np.abs(c - np.median(c))))
    return 10.0 * sigma if sigma > 0 else math.inf


def remove_spikes(
    roughness: RoughnessSet, *, curvature_limit: float | None = None, max_passes: int = 10
) -> RoughnessSet:
    """Remove spikes by the EN 15610 curvature criterion (paper 3.1, step 2).

    EN 15610 removes spikes (foreign material, dust, measurement dropouts) from raw roughness data with a
    curvature criterion: where the curvature of the measured profile is larger than a profile that can
    have, the sample is a spike. The standard's text could not be consulted while writing this; this
    implementation follows that principle as documented here:

    1. curvature ``c_i = (z[i-1] - 2 z[i] + z[i+1]) / dx²`` (1/m) on each line (periodic for wheels);
    2. samples with ``|c_i| > curvature_limit`` are flagged together with their two neighbours (a
       one-sample spike of height h gives -2h/dx² at its peak and +h/dx² beside it);
    3. the flagged samples are replaced by linear interpolation between the nearest unflagged samples
       (around the circumference for wheels);
    4. repeat until nothing is flagged (at most ``max_passes`` passes).

    Parameters
    ----------
    curvature_limit : float, optional
        Threshold on |curvature|, 1/m. Default: :func:`default_curvature_limit` per line, i.e. 10 robust
        standard deviations of that line's curvature.
    """
    z = np.array(roughness.heights)
    x = roughness.x
    removed = 0
    for row in range(roughness.n_lines):
        line = z[row]
        limit = (
            default_curvature_limit(line, roughness.dx, periodic=roughness.periodic)
            if curvature_limit is None
            else float(curvature_limit)
        )
        if not limit > 0:
            raise WheelrailError(f"remove_spikes: curvature_limit must be positive (1/m), got {curvature_limit}")
        for _ in range(max_passes):
            c = curvature(line, roughness.dx, periodic=roughness.periodic)[0]
            flagged = np.abs(c) > limit
            if not flagged.any():
                break
            grown = flagged.copy()
            grown[1:] |= flagged[:-1]
            grown[:-1] |= flagged[1:]
            if roughness.periodic:
                grown[0] |= flagged[-1]
                grown[-1] |= flagged[0]
            flagged = grown
            good = ~flagged
            if good.sum() < 2:
                raise WheelrailError(
                    f"remove_spikes: line {roughness.line_of_row(row)} is all spikes at curvature limit {limit:g} 1/m"
                )
            removed += int(flagged.sum())
            if roughness.periodic:
                line[flagged] = np.interp(x[flagged], x[good], line[good], period=roughness.length)
            else:
                line[flagged] = np.interp(x[flagged], x[good], line[good])
    note = f"spikes removed ({removed} samples)" if removed else None
    return roughness.with_heights(z, note=note)


def _butterworth_cutoff_for_zero_phase(cutoff: float, order: int) -> float:
    # Forward-backward filtering squares |H|; shift the Butterworth corner so that |H|^2 is -3 dB at the
    # requested cut-off: 1 + (fc/f3)^(2n) = sqrt(2)  =>  fc = f3 (sqrt(2) - 1)^(1/(2n)).
    return cutoff * (math.sqrt(2.0) - 1.0) ** (1.0 / (2 * order))


def highpass_gain(wavenumber: np.ndarray, cutoff_wavelength: float, order: int = 4) -> np.ndarray:
    """Amplitude gain of :func:`highpass` at ``wavenumber`` (cycles/m); exactly 1/sqrt(2) at the cut-off."""
    kc = _butterworth_cutoff_for_zero_phase(1.0 / cutoff_wavelength, order)
    k = np.abs(np.asarray(wavenumber, dtype=float))
    with np.errstate(divide="ignore"):
        return np.where(k > 0, 1.0 / (1.0 + (kc / np.where(k > 0, k, 1.0)) ** (2 * order)), 0.0)


def highpass(roughness: RoughnessSet, cutoff_wavelength: float, *, order: int = 4) -> RoughnessSet:
    """Zero-phase high-pass filter at a cut-off wavelength (paper 3.1: CAT data high-passed at 14 cm).

    The filter is a Butterworth filter of ``order`` applied forwards and backwards (zero phase), with its
    corner shifted so that the overall amplitude gain is exactly -3 dB (1/sqrt(2)) at
    ``cutoff_wavelength``; the gain is ``1 / (1 + (k_c / k)^(2 order))`` (:func:`highpass_gain`).
    Rail data: ``scipy.signal.sosfiltfilt`` (edges padded by odd extension). Wheel data: the same gain
    applied to the DFT of the circumference, which is exactly periodic and zero-phase.

    Parameters
    ----------
    cutoff_wavelength : float
        Wavelength at -3 dB, m. Must be longer than two sample spacings.
    order : int
        Butterworth order of the one-way filter (default 4: 48 dB/octave after forward-backward).
    """
    if not (math.isfinite(cutoff_wavelength) and cutoff_wavelength > 2 * roughness.dx):
        raise WheelrailError(
            f"high-pass cut-off wavelength must exceed 2 dx = {2 * roughness.dx:g} m, got {cutoff_wavelength!r}"
        )
    if cutoff_wavelength > roughness.length:
        raise WheelrailError(
            f"high-pass cut-off wavelength {cutoff_wavelength:g} m exceeds the data length {roughness.length:g} m"
        )
    z = roughness.heights
    if roughness.periodic:
        k = np.fft.rfftfreq(roughness.n_samples, d=roughness.dx)
        out = np.fft.irfft(np.fft.rfft(z, axis=1) * highpass_gain(k, cutoff_wavelength, order), n=z.shape[1], axis=1)
    else:
        kc = _butterworth_cutoff_for_zero_phase(1.0 / cutoff_wavelength, order)
        import scipy.signal

        sos = scipy.signal.butter(order, kc, btype="highpass", fs=1.0 / roughness.dx, output="sos")
        out = scipy.signal.sosfiltfilt(sos, z, axis=1)
    return roughness.with_heights(out, note=f"high-passed at {cutoff_wavelength:g} m")


def preprocess(
    roughness: RoughnessSet,
    *,
    detrend: bool = True,
    despike: bool = True,
    demean: bool = True,
    highpass_wavelength: float | None = None,
    curvature_limit: float | None = None,
) -> RoughnessSet:
    """Preprocess raw roughness as in the paper (section 3.1) and EN 15610.

    Steps, in order: (1) linear detrend (:func:`detrend_linear`), (2) spike removal by the curvature
    criterion (:func:`remove_spikes`), (3) optional zero-phase high-pass at ``highpass_wavelength`` m
    (:func:`highpass`), (4) mean removal (:func:`remove_mean`), last so that the result has exactly zero
    mean (the padded forward-backward filter of open rail data leaves a small mean). Wheel data is
    treated as periodic.
    """
    out = roughness
    if detrend:
        out = detrend_linear(out)
    if despike:
        out = remove_spikes(out, curvature_limit=curvature_limit)
    if highpass_wavelength is not None:
        out = highpass(out, highpass_wavelength)
    if demean:
        out = remove_mean(out)
    return out
