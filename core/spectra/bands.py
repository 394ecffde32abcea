"""Third-octave bands: the exact base-10 bands, their names, the outputs' band ranges, wavelength bands
(EN 15610 / CNOSSOS-EU) and frequency bands at a speed.

Third-octave bands are the exact base-10 bands of IEC 61260: centres ``10^(n/10)`` (n integer) in any unit,
edges ``centre x 10^(±1/20)``. So 1000 Hz, 501.19 Hz (nominal 500), 10^-1.25 m = 56.2 mm (nominal 56 mm
wavelength band) are all centres. The force spectra use the bands 50 Hz .. 8 kHz (:data:`FORCE_BAND_RANGE`), the
noise outputs the 24 bands 50 Hz .. 10 kHz (:data:`NOISE_BAND_RANGE`, :func:`noise_bands`).

Railway roughness and contact filters are tabulated by wavelength (EN 15610; CNOSSOS-EU, Commission
Directive (EU) 2015/996 Appendix G as replaced by Delegated Directive (EU) 2021/1226, uses the 35 bands
2000 mm .. 0.8 mm), force and sound spectra by frequency. A band of wavelengths [l_lo, l_hi] is the band
of spatial frequencies (wavenumbers, cycles/m) [1/l_hi, 1/l_lo]; at train speed v a frequency band
[f_lo, f_hi] is the wavenumber band [f_lo / v, f_hi / v] (f = v / lambda). Both kinds are the exact
base-10 bands of :func:`third_octave_bands`, so every band is one tenth of a decade
wide in wavenumber and a band of one kind generally straddles two of the other.

:func:`map_levels` moves band levels from one set of bands to another by the rule CNOSSOS-EU prescribes
for its roughness (Directive 2015/996 Annex II, 2.3.2: the two corresponding wavelength bands "averaged
energetically and proportionally"): each source band's mean square is spread uniformly over its width in
log wavenumber and every target band collects the part that falls inside it. For equal (third-octave)
widths this is both energy-conserving for spectra (band powers) and a weighted energetic mean for
transfer functions (filters), so roughness spectra and contact filters use the same function.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import finite_array, level_arrays, real

BAND_HALF_WIDTH = 10.0 ** (1.0 / 20.0)  # upper edge / centre of a third-octave band (base 10)
FORCE_BAND_RANGE = (50.0, 8000.0)  # Hz, band centres of the paper's force spectra (Figs 10-17)
NOISE_BAND_RANGE = (50.0, 10000.0)  # Hz: the 24 bands of CNOSSOS-EU Appendix G and of the noise outputs


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
    >>> from wheelrail.core.spectra.bands import nominal_band_label, third_octave_bands
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


def band_centre_range(band_range) -> tuple[float, float]:
    """``band_range`` as (lowest, highest) band centre; the values are checked by :func:`third_octave_bands`."""
    if isinstance(band_range, str | bytes) or not hasattr(band_range, "__len__") or len(band_range) != 2:
        raise WheelrailError(f"band_range must be (lowest, highest) band centres, got {type(band_range).__name__}")
    return band_range[0], band_range[1]


def noise_bands() -> np.ndarray:
    """Exact centres (Hz) of the 24 one-third octave bands 50 Hz .. 10 kHz."""
    return third_octave_bands(*NOISE_BAND_RANGE)[0]


CNOSSOS_WAVELENGTH_RANGE = (2.0, 0.0008)  # m: the 35 bands 2000 mm .. 0.8 mm of CNOSSOS-EU Tables G-1, G-2
AXES = ("wavelength", "frequency")


@dataclass(frozen=True, kw_only=True, eq=False)
class Bands:
    """A set of exact base-10 third-octave bands on a wavelength or a frequency axis.

    Attributes
    ----------
    centres : numpy.ndarray
        Band centres: m (``axis == "wavelength"``, long to short, as EN 15610 lists them) or Hz
        (``axis == "frequency"``, low to high).
    axis : str
        ``"wavelength"`` or ``"frequency"``.
    speed : float or None
        Train speed v, m/s, that ties a frequency band to wavenumbers (f = v k). None for wavelength
        bands, and for frequency bands that are never mapped.
    """

    centres: np.ndarray
    axis: str
    speed: float | None = None

    def __post_init__(self) -> None:
        from wheelrail.core.inputs.checks import finite_array, real

        if self.axis not in AXES:
            raise WheelrailError(f"band axis must be one of {', '.join(AXES)}, got {self.axis!r}")
        unit = "m" if self.axis == "wavelength" else "Hz"
        centres = finite_array("Bands.centres", self.centres, unit)
        if centres.ndim != 1 or centres.size == 0 or np.any(centres <= 0):
            raise WheelrailError(f"Bands.centres must be a 1-D array of positive band centres ({unit})")
        object.__setattr__(self, "centres", centres)
        if self.speed is not None:
            real("band speed", self.speed, "m/s")

    @property
    def lower(self) -> np.ndarray:
        """Lower band edges in the unit of the centres."""
        return np.asarray(self.centres) / BAND_HALF_WIDTH

    @property
    def upper(self) -> np.ndarray:
        """Upper band edges in the unit of the centres."""
        return np.asarray(self.centres) * BAND_HALF_WIDTH

    def wavenumber_edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper edge of every band as a spatial frequency k = 1 / lambda, cycles/m."""
        if self.axis == "wavelength":
            return 1.0 / self.upper, 1.0 / self.lower
        if self.speed is None:
            raise WheelrailError("frequency bands need a train speed (m/s) to be expressed in wavenumber")
        return self.lower / self.speed, self.upper / self.speed

    def labels(self) -> list[str]:
        """Nominal band names: mm for wavelength bands (``'31.5'``), Hz for frequency bands (``'500'``)."""
        scale = 1e3 if self.axis == "wavelength" else 1.0
        return [nominal_band_label(c * scale) for c in np.asarray(self.centres)]


def wavelength_bands(
    longest: float = CNOSSOS_WAVELENGTH_RANGE[0], shortest: float = CNOSSOS_WAVELENGTH_RANGE[1]
) -> Bands:
    """Wavelength bands from ``longest`` to ``shortest`` (m), long first; default the 35 CNOSSOS-EU bands.

    The EN 15610 roughness range 800 .. 3.15 mm is ``wavelength_bands(0.8, 0.00315)`` (24 bands).
    """
    from wheelrail.core.inputs.checks import real

    longest = real("wavelength_bands: longest", longest, "m")
    shortest = real("wavelength_bands: shortest", shortest, "m")
    if not shortest <= longest:
        raise WheelrailError(
            f"wavelength range must satisfy 0 < shortest <= longest (m), got {longest!r} .. {shortest!r}"
        )
    centres, _, _ = third_octave_bands(shortest, longest)
    return Bands(centres=centres[::-1].copy(), axis="wavelength")


def frequency_bands(speed: float | None, band_range: tuple[float, float] = FORCE_BAND_RANGE) -> Bands:
    """Frequency bands (Hz) with centres in ``band_range`` (default 50 Hz .. 8 kHz) at train speed ``speed`` (m/s)."""
    if isinstance(band_range, str | bytes) or not hasattr(band_range, "__len__") or len(band_range) != 2:
        raise WheelrailError(
            f"frequency_bands: band_range must be (lowest, highest) in Hz, got {type(band_range).__name__}"
        )
    centres, _, _ = third_octave_bands(*band_range)
    return Bands(centres=centres, axis="frequency", speed=speed)


def map_levels(levels_db, source: Bands, target: Bands) -> np.ndarray:
    """Band levels on ``source`` bands expressed on ``target`` bands (wavelength <-> frequency at a speed).

    Each source band's mean square ``10^(L/10)`` is spread uniformly over its width in log wavenumber;
    a target band takes the share of every source band that overlaps it (the CNOSSOS-EU "energetically
    and proportionally" rule, see the module docstring). A target band that the source bands do not cover
    completely, or that overlaps a source band whose level is NaN, is NaN. Mapping a band onto bands that
    coincide with it returns its level unchanged.

    Parameters
    ----------
    levels_db : array_like
        One level per source band, dB (any reference: spectra in dB re 1 um, filters in dB).
    source, target : Bands
        The bands of ``levels_db`` and the bands wanted; a frequency side needs its ``speed``.

    Returns
    -------
    numpy.ndarray
        One level per target band, dB, same reference as ``levels_db``.
    """
    (levels,) = level_arrays("map_levels: levels_db", [levels_db])
    if levels.shape != np.shape(source.centres):
        raise WheelrailError(f"map_levels: {levels.size} levels for {np.size(source.centres)} source bands")
    s_lo, s_hi = (np.log10(edge) for edge in source.wavenumber_edges())
    t_lo, t_hi = (np.log10(edge) for edge in target.wavenumber_edges())
    overlap = np.clip(np.minimum(s_hi[:, None], t_hi[None, :]) - np.maximum(s_lo[:, None], t_lo[None, :]), 0.0, None)
    share = overlap / (s_hi - s_lo)[:, None]  # fraction of each source band inside each target band
    covered = overlap.sum(axis=0) / (t_hi - t_lo)
    used = overlap > 1e-12
    power = np.where(np.isfinite(levels), 10.0 ** (levels / 10.0), 0.0)
    with np.errstate(divide="ignore"):
        out = 10.0 * np.log10(share.T @ power)
    bad = (covered < 1.0 - 1e-9) | (used & ~np.isfinite(levels)[:, None]).any(axis=0)
    return np.where(bad, np.nan, out)
