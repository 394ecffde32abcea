"""The ISO 3095:2013 rail roughness limit spectrum and the margin of a measured rail to it.

ISO 3095:2013 (*Acoustics - Railway applications - Measurement of noise emitted by railbound vehicles*),
6.2.5 and Figure 2: the default upper limit of the one-third octave band rail roughness of a reference
track, 22 levels from 400 mm to 3.15 mm, dB re 1 um. The levels are reprinted widely; two public
transcriptions agree in every band: jmrplens/phonometry (its ISO 3095 reference data, "the roughness
limit of Figure 2 as a label on every point", checked there against the same limit listed in EN 15610:2009
Annex B.9.2) and Universite-Gustave-Eiffel/NoiseModelling, ``noisemodelling-emission/src/main/resources/
org/noise_planet/noisemodelling/emission/railway/RailwayCnossosEU_2020.json`` (``RailRoughness`` "EN ISO
3095 2013", the CNOSSOS-EU Table G-1b class E, equal to the limit from 400 mm to 3.15 mm). CNOSSOS-EU
extends the curve to 2000 mm and 0.8 mm; those extensions are not part of ISO 3095 and are not used here.
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.spectra.bands import Bands, wavelength_bands

ISO3095_RANGE = (0.4, 0.00315)  # m: longest and shortest band of the limit
# dB re 1 um, on wavelength_bands(*ISO3095_RANGE): 400, 315, 250, ... 4, 3.15 mm
ISO3095_LIMIT_DB = (
    17.1, 15.0, 13.0, 11.0, 9.0, 7.0, 4.9, 2.9, 0.9, -1.1, -3.2,
    -5.0, -5.6, -6.2, -6.8, -7.4, -8.0, -8.6, -9.2, -9.8, -10.4, -11.0,
)  # fmt: skip


def iso3095_limit(bands: Bands | None = None) -> tuple[Bands, np.ndarray]:
    """The ISO 3095:2013 rail roughness limit on wavelength bands, dB re 1 um.

    Parameters
    ----------
    bands : Bands, optional
        Wavelength bands to express it on (e.g. the EN 15610 bands 800 .. 3.15 mm of ``wheelrail
        roughness``); default its own 22 bands 400 .. 3.15 mm. Bands outside 400 .. 3.15 mm are NaN.

    Returns
    -------
    bands : Bands
    limit_db : numpy.ndarray
        Limit level per band, dB re 1 um (NaN outside the standard's range).
    """
    own = wavelength_bands(*ISO3095_RANGE)
    if bands is not None and bands.axis != "wavelength":
        raise WheelrailError("the ISO 3095 limit is defined on wavelength bands, not frequency bands")
    if bands is None:
        return own, np.asarray(ISO3095_LIMIT_DB, dtype=float)
    own_index = np.round(10.0 * np.log10(own.centres)).astype(int)
    limit = dict(zip(own_index.tolist(), ISO3095_LIMIT_DB, strict=True))
    index = np.round(10.0 * np.log10(np.asarray(bands.centres))).astype(int)
    return bands, np.array([limit.get(i, np.nan) for i in index.tolist()], dtype=float)


def iso3095_margin(levels_db, bands: Bands) -> np.ndarray:
    """Margin of rail roughness levels to the ISO 3095:2013 limit per band: limit - level, dB.

    Positive: the rail is below (smoother than) the limit in that band; negative: it exceeds it. NaN where
    the level is not resolved or the band lies outside the limit's 400 .. 3.15 mm.
    """
    _, limit = iso3095_limit(bands)
    return limit - np.asarray(levels_db, dtype=float)
