"""Studies (paper sections 3.3-3.5, Figs 10-17 and 11): the paper's findings reproduced through the study API.

Runs are kept short (2 m of the 1-line models or 3D, 6 m for the speed study where the sleeper-passing
bands need frequency resolution) so that the whole file runs in well under a minute on 2 cores.
"""

import numpy as np
import pytest

from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.reference_filters import reference_filters
from wheelrail.core.roughness import RoughnessSet
from wheelrail.core.spectra.bands import BAND_HALF_WIDTH
from wheelrail.core.study import (
    HALF_WHEEL_MASS,
    PAPER_SPEEDS_KMH,
    RunSpec,
    contact_filter,
    execute,
    mean_level,
    plan_study,
    roughness_digest,
    run_study,
)

P = ModelParameters()
L_S = P.track.support.sleeper_spacing  # 0.65 m
A = P.contact.hertz_radius()  # 5.48 mm


def _band_of(centres, frequency):
    """Index of the third-octave band whose edges contain ``frequency`` (Hz)."""
    inside = np.nonzero((centres / BAND_HALF_WIDTH <= frequency) & (frequency < centres * BAND_HALF_WIDTH))[0]
    assert inside.size == 1, frequency
    return int(inside[0])


def _dip_depth(levels, band):
    """How far band ``band`` lies below the mean of its two neighbours, dB (> 0: a dip)."""
    return 0.5 * (levels[band - 1] + levels[band + 1]) - levels[band]


# ------------------------------------------------------------------------------------------------
# Fig. 11: sleeper passing moves with v / L_S, not with the wheel mass
# ------------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_speeds_move_the_sleeper_passing_peak_as_v_over_ls(tmp_path):
    result = run_study("speeds", ["corrugated-rail"], tmp_path, length=6.0, progress=False, figures=False)
    (table,) = result.tables
    centres = table.band_centres
    assert result.report.computed == len(PAPER_SPEEDS_KMH) + 1
    for speed_kmh in PAPER_SPEEDS_KMH:
        levels = table.columns[f"{speed_kmh:g}_kmh_db"]
        band = _band_of(centres, 2 * speed_kmh * KMH / L_S)
        # the band holding twice the sleeper-passing frequency stands out of both neighbours by > 3 dB:
        # the parametric excitation line sits on the broadband roughness response (measured 6-30 dB)
        assert band > 0
        assert levels[band] > levels[band - 1] + 3.0 and levels[band] > levels[band + 1] + 3.0, (speed_kmh, levels)
    # the paper's statement: at 100 km/h 2 v / L_S = 85.5 Hz falls in the 80 Hz band
    assert round(centres[_band_of(centres, 2 * 100 * KMH / L_S)]) == 79
    # half the wheel mass changes levels but not where the sleeper-passing peak is (Fig. 11)
    half = table.columns["100_kmh_half_mass_db"]
    full = table.columns["100_kmh_db"]
    band = _band_of(centres, 2 * 100 * KMH / L_S)
    assert half[band] > half[band - 1] + 3.0 and half[band] > half[band + 1] + 3.0
    assert not np.allclose(half, full, atol=0.1)  # the mass did change the run (not the same cached result)


# ------------------------------------------------------------------------------------------------
# Eq. (19): dips of the one-line filters at f_n = n v / (2a); shallower in 3D
# ------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def white_set():
    """Roughness with a flat spectrum along and across the track: independent Gaussian heights on 25 lines
    1 mm apart, 0.3 µm rms (small: the contact stays linear and closed), seeded."""
    rng = np.random.default_rng(7)
    heights = 0.3e-6 * rng.standard_normal((25, 2600))
    return RoughnessSet(
        heights=heights, dx=1e-3, y=(np.arange(25) - 12) * 1e-3, kind="rail", description="white test roughness"
    )


@pytest.mark.slow
def test_2d_filter_dips_at_eq19_and_3d_dips_are_shallower(white_set, tmp_path):
    result = run_study("filters", [white_set], tmp_path, length=2.0, progress=False, figures=False)
    filters = next(t for t in result.tables if t.name.endswith("contact_filters"))
    centres = filters.band_centres
    f1 = P.run.speed / (2 * A)  # eq. (19), n = 1: 2.53 kHz at 100 km/h
    assert f1 == pytest.approx(2534, abs=5)
    for n in (1, 2):
        band = _band_of(centres, n * f1)
        two_d = filters.columns["2d_db"]
        three_d = filters.columns["3d_db"]
        # a local minimum of the 2D filter (mean of lines -3..3) at least 4 dB deep (measured 7 and 8 dB;
        # a flat input spectrum leaves only the filter's own shape)
        assert _dip_depth(two_d, band) > 4.0, (n, two_d)
        # the Winkler pre-filter on one line has the same dips (section 3.4)
        assert _dip_depth(filters.columns["hertz_winkler_db"], band) > 4.0
        # in 3D the dip is at least 3 dB shallower (measured: none at f_1, 3 dB at f_2), since the contact
        # length varies across the patch (section 3.4)
        assert _dip_depth(three_d, band) < _dip_depth(two_d, band) - 3.0, (n, three_d)
    # below 500 Hz no along-track filter acts: the wavelengths exceed 5 cm (> 4 x 2a), within 0.5 dB
    low = centres < 450
    for column in ("2d_db", "hertz_winkler_db", "hertz_average_db"):
        assert np.nanmax(np.abs(filters.columns[column][low])) < 0.5, column
    # The 3D patch also averages the laterally uncorrelated lines of this roughness, at any wavelength. Below
    # 350 Hz the sleeper-passing harmonics (the same in every model) outweigh this 0.3 um roughness and the
    # 3D filter reads 0 within 0.5 dB (measured < 0.1 dB); in the 400 Hz band the roughness response leads
    # and the 3D force is lower (measured -3.1 dB). Before the bay refinement this was hidden: linear
    # interpolation between the excitation positions put spurious sleeper-passing tones of 26-29 dB re 1 N
    # into the 400-630 Hz bands of every model (15 to -17 dB once refined).
    three_d = filters.columns["3d_db"]
    assert np.nanmax(np.abs(three_d[centres < 350])) < 0.5
    assert np.nanmax(three_d[low]) < 0.5
    # the reference filters for the runs' load and wheel sit beside the dynamic ones, the same
    # values as wheelrail.core.reference_filters gives for 65 kN, R = 0.39 m, 100 km/h
    refs = reference_filters(P.contact.preload, P.contact.radius, P.run.speed)
    for name, values in refs.by_frequency.items():
        np.testing.assert_array_equal(filters.columns[f"ref_{name.replace('-', '_')}_db"], values)


@pytest.mark.slow
def test_eq19_dips_move_with_speed(white_set, tmp_path):
    # the same 2D-minus-Hertz filter at 80 km/h: the dip moves to f_1 = 80 km/h / (2a) = 2.03 kHz. Built
    # from the public API: RunSpecs -> execute -> contact_filter -> mean_level
    speed = 80 * KMH
    params = ModelParameters(run=RunParameters(speed=speed))
    digest = roughness_digest(white_set)
    specs = {
        (model, line): RunSpec(
            source=white_set, set_label="white", set_digest=digest, model=model, line=line, params=params, length=2.0
        )
        for model in ("2d", "hertz")
        for line in range(-3, 4)
    }
    report = execute(list(specs.values()), cache=tmp_path, workers=2, progress=False)
    assert report.computed == 14 and report.cached == 0
    levels = {k: report.summaries[spec.key].levels for k, spec in specs.items()}
    two_d = mean_level([contact_filter(levels["2d", line], levels["hertz", line]) for line in range(-3, 4)])
    centres = report.summaries[specs["2d", 0].key].band_centres
    band = _band_of(centres, speed / (2 * A))
    assert round(centres[band]) == 1995
    assert _dip_depth(two_d, band) > 4.0, two_d  # as at 100 km/h, one band lower
    assert _dip_depth(two_d, band + 1) < 0  # and the 2.5 kHz band, the dip at 100 km/h, is no dip here


# ------------------------------------------------------------------------------------------------
# Sections 3.4-3.5 on the bundled sets: 3D vs 2D, the averaged input
# ------------------------------------------------------------------------------------------------

SETS = ["corrugated-rail", "sinter-wheel-1"]


@pytest.fixture(scope="module")
def bundled_studies(tmp_path_factory):
    """line-spread and averaged-input on two sets, 2 m runs; the second study reuses the 3D runs."""
    out = tmp_path_factory.mktemp("bundled-studies")
    spread = run_study("line-spread", SETS, out, length=2.0, progress=False, figures=False)
    averaged = run_study("averaged-input", SETS, out, length=2.0, progress=False, figures=False)
    return spread, averaged


def _table(result, name):
    return next(t for t in result.tables if t.name == name)


@pytest.mark.slow
def test_3d_lower_than_2d_at_high_frequencies_more_for_sinter_wheel(bundled_studies):
    spread, _ = bundled_studies
    high = {}
    for name in SETS:
        table = _table(spread, f"fig12_{name}_3d_minus_2d")
        band = (table.band_centres > 560) & (table.band_centres < 9000)
        high[name] = float(np.mean(table.columns["mean_db"][band]))
        # section 3.4: the 3D model filters more than the 2D one: mean L_3D - L_2D over 630 Hz-8 kHz below
        # -1 dB (measured -1.9 dB rail, -3.4 dB sinter wheel), despite the 2D dips of eq. (19)
        assert high[name] < -1.0, (name, table.columns["mean_db"])
        # and the mean difference stays within the paper's range (Fig. 12: up to 7 dB mean, 9.5 dB one line)
        assert np.nanmax(np.abs(table.columns["mean_db"])) < 12.0
    # more so for the laterally uncorrelated sinter-wheel roughness than for the correlated corrugation
    # (sections 3.2, 3.4): by more than 1 dB (measured 1.5 dB)
    assert high["sinter-wheel-1"] < high["corrugated-rail"] - 1.0, high


@pytest.mark.slow
def test_2d_and_winkler_prefilter_agree_up_to_2khz(bundled_studies):
    spread, _ = bundled_studies
    for name in SETS:
        table = _table(spread, f"fig13_{name}_2d_minus_hertz_winkler")
        band = table.band_centres < 2100
        # section 3.4: "very similar" below 2 kHz: mean difference within 1 dB (measured < 0.5 dB)
        assert np.nanmax(np.abs(table.columns["mean_db"][band])) < 1.0, (name, table.columns["mean_db"])


@pytest.mark.slow
def test_averaged_input_brings_2d_closer_to_3d_up_to_1_to_2_khz(bundled_studies):
    spread, averaged = bundled_studies
    (table,) = averaged.tables
    for name, top in (("corrugated-rail", 1100), ("sinter-wheel-1", 2100)):
        per_line = _table(spread, f"fig12_{name}_3d_minus_2d")
        band = (per_line.band_centres > 180) & (per_line.band_centres < top)
        lines = [v for k, v in per_line.columns.items() if k.startswith("line_")]
        one_line_error = float(np.mean(np.abs(np.vstack(lines))[:, band]))
        averaged_error = float(np.mean(np.abs(table.columns[f"{name}_db"][band])))
        # Fig. 16 vs Fig. 12: |L_3D - L_2D,av| is smaller than the typical |L_3D - L_2D,line| up to 1 kHz
        # (rail) and 2 kHz (sinter wheel); for the sinter wheel by half at least (measured 1.2 vs 4.5 dB)
        assert averaged_error < one_line_error, (name, averaged_error, one_line_error)
        if name == "sinter-wheel-1":
            assert averaged_error < 0.5 * one_line_error, (averaged_error, one_line_error)


def test_plan_sizes_follow_the_paper():
    # Fig. 10: 4 one-line models x 7 lines + one 3D run; Fig. 17: original + 2 reduced resolutions
    assert len(plan_study("filters", ["cast-iron-wheel"]).specs) == 29
    assert len(plan_study("line-spread", ["cast-iron-wheel"]).specs) == 22
    assert len(plan_study("lateral-resolution", ["cast-iron-wheel"]).specs) == 3
    speeds = plan_study("speeds", ["cast-iron-wheel"]).specs
    assert sorted(round(s.speed_kmh) for s in speeds) == [75, 100, 100, 140, 200]
    assert sorted(s.params.wheel.unsprung_mass for s in speeds)[0] == HALF_WHEEL_MASS


@pytest.mark.slow
def test_lateral_resolution_4mm_is_closer_to_the_original_than_8mm(tmp_path):
    # Fig. 17: the 3D model on the lines 4 mm apart errs much less than on lines 8 mm apart; measured on
    # 2 m runs, mean |L_3D - L_3D,low| over the bands: sinter wheel 0.9 dB (4 mm) vs 2.3 dB (8 mm), cast-iron
    # wheel 0.3 vs 0.8 dB. Required: 4 mm below 8 mm by a third at least, and 4 mm within 1.5 dB on average
    # (the paper: "negligible errors up to 1 kHz and maximum errors of about 3 dB")
    result = run_study(
        "lateral-resolution", ["sinter-wheel-1", "cast-iron-wheel"], tmp_path, length=2.0, progress=False, figures=False
    )
    four, eight = (next(t for t in result.tables if t.name.endswith(f"_{mm}mm")) for mm in (4, 8))
    for name in ("sinter-wheel-1", "cast-iron-wheel"):
        error4 = float(np.nanmean(np.abs(four.columns[f"{name}_db"])))
        error8 = float(np.nanmean(np.abs(eight.columns[f"{name}_db"])))
        assert error4 < 1.5 and error4 < 0.67 * error8, (name, error4, error8)
