"""The public level, band and spectrum functions at the edges: NaN, infinities, 1e300, zero, negative, empty,
None, text and arrays of the wrong shape either give one WheelrailError line or an answer reached without a numpy
warning (no overflow, no division by zero, no invalid value) and with no +inf in it; never a Python or numpy
exception."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import LEVEL_LIMIT_DB
from wheelrail.core.spectra import bands, force, levels, narrowband

ODD = {
    "nan": math.nan,
    "inf": math.inf,
    "-inf": -math.inf,
    "1e300": 1e300,
    "-1e300": -1e300,
    "zero": 0.0,
    "negative": -1.0,
    "empty": [],
    "2x3": np.ones((2, 3)),
    "None": None,
    "text": "1",
    "huge-in-array": np.array([1e300, 1.0]),
}
_BANDS = bands.frequency_bands(100 / 3.6)
_EDGES = (np.array([1.0]), np.array([2.0]))
CALLS = {  # each public function, one argument at a time replaced by the odd value
    "a_weighting": lambda v: levels.a_weighting(v),
    "energy_sum": lambda v: levels.energy_sum(v, [1.0]),
    "energy_sum axis": lambda v: levels.energy_sum(v, axis=0),
    "a_weighted_total": lambda v: levels.a_weighted_total(v),
    "a_weighted_total frequencies": lambda v: levels.a_weighted_total([60.0], v),
    "level": lambda v: levels.level(v, 1.0),
    "level reference": lambda v: levels.level(1.0, v),
    "power_level": lambda v: levels.power_level(v),
    "wavelength_bands": lambda v: bands.wavelength_bands(0.1, v),
    "frequency_bands speed": lambda v: bands.frequency_bands(v),
    "frequency_bands range": lambda v: bands.frequency_bands(10.0, (v, 100.0)),
    "frequency_bands range pair": lambda v: bands.frequency_bands(10.0, v),
    "Bands centres": lambda v: bands.Bands(centres=v, axis="frequency", speed=10.0).wavenumber_edges(),
    "map_levels": lambda v: bands.map_levels(v, _BANDS, _BANDS),
    "third_octave_bands": lambda v: bands.third_octave_bands(v, 100.0),
    "nominal_band_label": lambda v: bands.nominal_band_label(v),
    "band_labels": lambda v: bands.band_labels(v),
    "narrowband_spectrum signal": lambda v: narrowband.narrowband_spectrum(v, 10.0),
    "narrowband_spectrum rate": lambda v: narrowband.narrowband_spectrum(np.ones(8), v),
    "hann_window": lambda v: narrowband.hann_window(v),
    "band_power psd": lambda v: narrowband.band_power(np.arange(4.0), v, *_EDGES),
    "band_power frequencies": lambda v: narrowband.band_power(v, np.ones(4), *_EDGES),
    "band_power edges": lambda v: narrowband.band_power(np.arange(4.0), np.ones(4), v, _EDGES[1]),
    "level_db": lambda v: narrowband.level_db(v, 1.0),
    "level_db reference": lambda v: narrowband.level_db(1.0, v),
    "third_octave_levels": lambda v: narrowband.third_octave_levels(v, 10.0, *_EDGES, 1.0),
    "third_octave_levels reference": lambda v: narrowband.third_octave_levels(np.ones(16), 10.0, *_EDGES, v),
    "third_octave_spectrum rate": lambda v: narrowband.third_octave_spectrum(np.ones(64), v, (1.0, 10.0), 1.0),
    "block_spectra": lambda v: narrowband.block_spectra(v, np.ones((2, 64)), 10.0, 2),
    "block_spectra rate": lambda v: narrowband.block_spectra(np.ones(64), np.ones((2, 64)), v, 2),
    "band_coherence": lambda v: narrowband.band_coherence(np.ones(64), np.ones((2, 64)), 10.0, v, _EDGES[1], 2),
    "shortest_spectrum_run speed": lambda v: force.shortest_spectrum_run(v, 1e-3),
    "shortest_spectrum_run element": lambda v: force.shortest_spectrum_run(10.0, v),
    "check_spectrum_length": lambda v: force.check_spectrum_length(v, 10.0, 1e-3),
    "force_spectrum": lambda v: force.force_spectrum(v, 1e-4),
    "force_spectrum time_step": lambda v: force.force_spectrum(np.ones(2000), v),
    "resolved_force_bands": lambda v: force.resolved_force_bands(v, 1e-4),
    "resolved_force_bands time_step": lambda v: force.resolved_force_bands(1000, v),
    "record_of_steps skip": lambda v: force.record_of_steps(1000, 1e-4, skip=v).resolved,
    "spectrum_record": lambda v: force.spectrum_record(v, 1e-4).duration,
    "spectrum_record skip": lambda v: force.spectrum_record(np.ones(2000), 1e-4, skip=v).words(),
    "mean_level": lambda v: levels.mean_level([v]),
    "level_difference": lambda v: levels.level_difference(v, [1.0]),
    "contact_filter": lambda v: levels.contact_filter(v, [1.0]),
}


def _arrays(out):
    if isinstance(out, tuple | list):
        for item in out:
            yield from _arrays(item)
    elif isinstance(out, bands.Bands):
        yield out.centres
    elif out is not None and not isinstance(out, str):
        yield np.abs(np.asarray(out)) if np.iscomplexobj(out) else np.asarray(out, dtype=float)


@pytest.mark.parametrize("value", list(ODD.values()), ids=list(ODD))
@pytest.mark.parametrize("name", list(CALLS))
def test_a_public_function_refuses_in_one_line_or_answers_without_warnings(name, value):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a numpy RuntimeWarning (overflow, divide, invalid) fails the test
        try:
            out = CALLS[name](value)
        except WheelrailError as error:
            assert "\n" not in str(error)
            return
    for array in _arrays(out):
        assert not np.any(array == np.inf), (name, out)  # no finite input has an infinite answer here


def _a_weighting_textbook(f: float) -> float:
    """IEC 61672-1 eq. E.6 as written (finite only where f^4 does not overflow)."""
    f1, f2, f3, f4 = 20.598997, 107.65265, 737.86223, 12194.217
    f_sq = f * f
    return 20 * math.log10(
        f4**2 * f_sq**2 / ((f_sq + f1**2) * math.sqrt((f_sq + f2**2) * (f_sq + f3**2)) * (f_sq + f4**2))
    )


def test_extreme_but_valid_inputs_have_their_exact_answers():
    # the A-weighting in logarithms equals the textbook form where that is finite (1e-12 dB: round-off) ...
    for f in (10.0, 1000.0, 12345.0, 1e6, 1e30):
        assert levels.a_weighting(f) == pytest.approx(_a_weighting_textbook(f) - _a_weighting_textbook(1e3), abs=1e-9)
    # ... and far above the poles it is 40 lg(f4 / f) less the 1 kHz value (exact asymptote, 1e-9 dB)
    assert levels.a_weighting(1e300) == pytest.approx(40 * math.log10(12194.217 / 1e300) - _a_weighting_textbook(1e3))
    assert levels.a_weighting(0.0) == -math.inf  # documented: no weighting of a constant
    assert levels.level(1.0, 1e300) == -6000.0 and levels.power_level(1e300) == pytest.approx(3120.0)
    assert narrowband.level_db(0.0, 1e-300) == -math.inf
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert levels.energy_sum([-math.inf], [-math.inf]) == -math.inf  # no power twice is no power
        assert np.isnan(levels.energy_sum([math.nan], [60.0]))  # a band without an estimate stays without
    with pytest.raises(WheelrailError, match=f"beyond \\+-{LEVEL_LIMIT_DB:g} dB"):
        levels.mean_level([[1e300, 1.0]])
    assert bands.nominal_band_label(1e300) == "1e+300"


def test_one_energetic_sum_of_levels():
    """Levels are added energetically by one function, ``energy_sum``, to the bit the sum of 10^(L/10) per band
    that the combined roughness and the noise totals both take (no second function of the same sum)."""
    assert not hasattr(levels, "energetic_sum") and "energetic_sum" not in levels.__all__
    rng = np.random.default_rng(37)
    rail, wheel, third = rng.uniform(-40.0, 30.0, (3, 27))
    rail[3], wheel[3], wheel[5] = -math.inf, -math.inf, math.nan  # no power twice; a band without an estimate
    for parts in ((rail, wheel), (rail, wheel, third)):
        with np.errstate(divide="ignore"):
            expected = 10.0 * np.log10(np.sum(10.0 ** (np.vstack(parts) / 10.0), axis=0))
        np.testing.assert_array_equal(levels.energy_sum(*parts), expected)
