"""Roughness data: the data model, import/export, preprocessing, the model grid and roughness analyses.

A roughness set holds the heights of several parallel longitudinal lines of a rail or a wheel running
surface (Pieringer, Kropp & Thompson 2011, section 3.1 and Figure 8). Everything is SI inside: heights and
positions in m. The package is split by the stage of the data's journey:

* :mod:`.model`: :class:`RoughnessSet` and the limits every set obeys (``MAX_HEIGHT``, ``MAX_VALUES``);
* :mod:`.csv_io`, :mod:`.npz_io`: the two file formats (CSV with heights in µm; NPZ with ``z_m``, ``dx_m``,
  ``y_m``, ``kind``, ``description``); :mod:`.io`: bundled sets and files by name or path;
* :mod:`.preprocessing`: detrend, spike removal, high-pass (paper section 3.1, EN 15610);
* :mod:`.grid`: interpolation to the model grid and the lines along the track;
* :mod:`.analysis`: third-octave roughness spectra and the lateral coherence (sections 3.1-3.2);
* :mod:`.synthesis`: the seeded synthetic sets bundled in ``sample_data``;
* :mod:`.iso3095`: the ISO 3095:2013 rail roughness limit spectrum and a rail's margin to it.

Everything a caller needs is importable from ``wheelrail.core.roughness`` itself.
"""

from wheelrail.core.roughness.analysis import (
    DEFAULT_LINES,
    FREQUENCY_RANGE,
    ROUGHNESS_REFERENCE,
    WAVELENGTH_RANGE,
    RoughnessSpectrum,
    lateral_coherence,
    roughness_spectrum,
)
from wheelrail.core.roughness.csv_io import MAX_LINE_CHARS, read_csv, write_csv
from wheelrail.core.roughness.grid import (
    LATERAL_TOLERANCE,
    at_lateral_positions,
    covers,
    lateral_extent_mm,
    line_along_track,
    lines_along_track,
    resample_lateral,
    resample_longitudinal,
    to_model_grid,
)
from wheelrail.core.roughness.io import SAMPLE_DATA_PACKAGE, bundled_names, load_roughness, read_roughness
from wheelrail.core.roughness.model import (
    KINDS,
    MAX_HEIGHT,
    MAX_LATERAL,
    MAX_VALUES,
    SPACING_RANGE,
    RoughnessLike,
    RoughnessSet,
    check_value_count,
)
from wheelrail.core.roughness.npz_io import MAX_HEADER_BYTES, MAX_TEXT_CHARS, read_npz, write_npz
from wheelrail.core.roughness.preprocessing import (
    curvature,
    default_curvature_limit,
    detrend_linear,
    highpass,
    highpass_gain,
    preprocess,
    remove_mean,
    remove_spikes,
)

__all__ = [
    "DEFAULT_LINES",
    "FREQUENCY_RANGE",
    "KINDS",
    "LATERAL_TOLERANCE",
    "MAX_HEADER_BYTES",
    "MAX_HEIGHT",
    "MAX_LATERAL",
    "MAX_LINE_CHARS",
    "MAX_TEXT_CHARS",
    "MAX_VALUES",
    "SPACING_RANGE",
    "ROUGHNESS_REFERENCE",
    "SAMPLE_DATA_PACKAGE",
    "WAVELENGTH_RANGE",
    "RoughnessLike",
    "RoughnessSet",
    "RoughnessSpectrum",
    "at_lateral_positions",
    "bundled_names",
    "check_value_count",
    "covers",
    "curvature",
    "default_curvature_limit",
    "detrend_linear",
    "highpass",
    "highpass_gain",
    "lateral_coherence",
    "lateral_extent_mm",
    "line_along_track",
    "lines_along_track",
    "load_roughness",
    "preprocess",
    "read_csv",
    "read_npz",
    "read_roughness",
    "remove_mean",
    "remove_spikes",
    "resample_lateral",
    "resample_longitudinal",
    "roughness_spectrum",
    "to_model_grid",
    "write_csv",
    "write_npz",
]
