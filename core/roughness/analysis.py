"""Roughness analyses: third-octave roughness spectra (paper section 3.1, Figure 6) and the lateral
coherence parameter of eqs. (15)-(18) (section 3.2, Figure 9)."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.roughness.model import RoughnessSet
from wheelrail.core.spectra.bands import FORCE_BAND_RANGE, third_octave_bands
from wheelrail.core.spectra.narrowband import band_coherence, third_octave_levels

ROUGHNESS_REFERENCE = 1e-6  # m: roughness levels are in dB re 1 µm
DEFAULT_LINES = tuple(range(-3, 4))  # the paper averages the 7 lines -3..3
FREQUENCY_RANGE = FORCE_BAND_RANGE  # Hz, the band range of the paper's figures
WAVELENGTH_RANGE = (0.8, 0.00315)  # m, EN 15610 / CNOSSOS-EU wavelength bands 800 mm .. 3.15 mm


@dataclass(frozen=True, kw_only=True, eq=False)
class RoughnessSpectrum:
    """Third-octave roughness spectrum.

    Attributes
    ----------
    band_centres : numpy.ndarray
        Exact base-10 band centres: Hz (``axis == "frequency"``) or m (``axis == "wavelength"``).
    wavelengths : numpy.ndarray
        Wavelength of each band centre, m (``v / f`` for frequency bands).
    levels_db : numpy.ndarray
        Band level, dB re 1 µm, averaged energetically over ``lines``; NaN where the band is outside what
        the data resolves.
    lines : tuple of int
        Line numbers averaged (Figure 8 numbering).
    axis : str
        ``"frequency"`` or ``"wavelength"``.
    speed : float or None
        Speed used for the frequency axis, m/s.
    """

    band_centres: np.ndarray
    wavelengths: np.ndarray
    levels_db: np.ndarray
    lines: tuple
    axis: str
    speed: float | None = None


def _rows(roughness: RoughnessSet, lines, parameter: str = "lines") -> list[int]:
    """Rows of ``lines``; a line the set lacks is one WheelrailError keyed ``parameter``, with the set's lines."""
    available = roughness.line_numbers
    first, last = int(available[0]), int(available[-1])
    lines = tuple(_whole(line, parameter, first, last, "not in the roughness set") for line in lines)
    if not lines:
        raise WheelrailError("choose at least one roughness line")
    return [roughness.row_of_line(line) for line in lines]


def _whole(value, parameter: str, minimum: int, maximum: int, problem: str | None = None, reason: str | None = None):
    """``value`` as an int from ``minimum`` to ``maximum``, else one WheelrailError keyed ``parameter``
    (``problem``: what a value outside the range is, ``reason``: why the range, in words that name no input)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise WheelrailError("not a whole number", Blame(parameter, value))
    if not minimum <= value <= maximum:
        raise WheelrailError(problem, Blame(parameter, int(value), minimum=minimum, maximum=maximum, reason=reason))
    return int(value)


def _check_speed(speed: float) -> float:
    if not (isinstance(speed, int | float) and math.isfinite(speed) and speed > 0):
        raise WheelrailError(f"speed must be a positive number in m/s, got {speed!r}")
    return float(speed)


def _spatial_levels(roughness: RoughnessSet, rows, k_lower, k_upper) -> np.ndarray:
    levels = third_octave_levels(roughness.heights[rows], 1.0 / roughness.dx, k_lower, k_upper, ROUGHNESS_REFERENCE)
    # A band is only resolved when it lies between the record's fundamental and the Nyquist wavenumber.
    resolved = (k_lower >= 1.0 / roughness.length) & (k_upper <= 0.5 / roughness.dx)
    return np.where(resolved, levels, np.nan)


def roughness_spectrum(
    roughness: RoughnessSet,
    *,
    speed: float | None = None,
    lines=DEFAULT_LINES,
    frequency_range: tuple[float, float] = FREQUENCY_RANGE,
    wavelength_range: tuple[float, float] = WAVELENGTH_RANGE,
) -> RoughnessSpectrum:
    """Third-octave roughness spectrum in dB re 1 µm (paper section 3.1, Figure 6).

    A single Hann-windowed FFT of each chosen line, integrated into third-octave bands and averaged over
    the lines (:func:`wheelrail.core.spectra.narrowband.third_octave_levels`).

    Parameters
    ----------
    speed : float, optional
        Train speed, m/s. Given: bands in frequency ``f = v / λ`` over ``frequency_range`` (Hz).
        Omitted: EN 15610 / CNOSSOS-EU wavelength bands over ``wavelength_range`` (m, long to short).
    lines : iterable of int
        Line numbers to average (default -3..3, as in the paper).
    """
    rows = _rows(roughness, lines)
    if speed is not None:
        speed = _check_speed(speed)
        centres, lower, upper = third_octave_bands(*frequency_range)
        levels = _spatial_levels(roughness, rows, lower / speed, upper / speed)
        return RoughnessSpectrum(
            band_centres=centres,
            wavelengths=speed / centres,
            levels_db=levels,
            lines=tuple(int(line) for line in lines),
            axis="frequency",
            speed=speed,
        )
    long, short = max(wavelength_range), min(wavelength_range)
    centres, lower, upper = third_octave_bands(short, long)
    centres, lower, upper = centres[::-1], lower[::-1], upper[::-1]  # long wavelengths first (EN 15610)
    levels = _spatial_levels(roughness, rows, 1.0 / upper, 1.0 / lower)
    return RoughnessSpectrum(
        band_centres=centres,
        wavelengths=centres,
        levels_db=levels,
        lines=tuple(int(line) for line in lines),
        axis="wavelength",
    )


def lateral_coherence(
    roughness: RoughnessSet,
    speed: float,
    *,
    half_lines: int = 3,
    blocks: int = 20,
    frequency_range: tuple[float, float] = FREQUENCY_RANGE,
) -> tuple[np.ndarray, np.ndarray]:
    """Lateral coherence parameter γ²(f0) of eqs. (15)-(18) (paper section 3.2, Figure 9).

    Line 0 against lines m = -M..M (m != 0), each line cut into B consecutive blocks; see
    :func:`wheelrail.core.spectra.narrowband.band_coherence` for the estimator and its bias (~1/(2 M B L)).

    Parameters
    ----------
    speed : float
        Train speed, m/s; band frequency ``f = v / λ``.
    half_lines : int
        M (paper: 3, so that the lines cover the nominal contact area).
    blocks : int
        B (paper: 20).

    Returns
    -------
    band_centres : numpy.ndarray
        Hz.
    coherence : numpy.ndarray
        γ², dimensionless in [0, 1]; NaN in bands that hold no bin of the block spectra (block length
        ``length / B`` sets the resolution ``v B / length``).
    """
    speed = _check_speed(speed)
    available = roughness.line_numbers  # the lines -M..M must be in the set; each block at least 8 samples
    widest = max(1, min(-int(available[0]), int(available[-1])))
    half_lines = _whole(half_lines, "half_lines", 1, widest, reason="the lines -M..M must be in the set")
    samples = roughness.heights.shape[-1]
    blocks = _whole(blocks, "blocks", 1, max(1, samples // 8), reason=f"at least 8 of the {samples} samples a block")
    others = [m for m in range(-half_lines, half_lines + 1) if m != 0]
    centre_row = roughness.row_of_line(0)
    other_rows = _rows(roughness, others)
    centres, lower, upper = third_octave_bands(*frequency_range)
    gamma2 = band_coherence(
        roughness.heights[centre_row],
        roughness.heights[other_rows],
        1.0 / roughness.dx,
        lower / speed,
        upper / speed,
        blocks=blocks,
    )
    return centres, gamma2
