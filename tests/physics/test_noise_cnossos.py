"""CNOSSOS-EU rolling-noise source against the directive's tables and formulas, computed independently.

The tables in ``core/noise/data`` are one print (phonometry's transcription of the Official Journal);
``tests/data/cnossos_second_print.csv`` is another (NoiseModelling's numbers) and
``tests/data/cnossos_2021_rail.csv`` the A3 columns. The expected sound powers below are computed from the
second print with this file's own plain-Python reading of the directive's formulas (eqs. 2.3.7-2.3.10 and
the two conversion rules), not with the implementation's functions.
Tolerance 0.05 dB per band: the two prints differ by rounding to 0.1 dB at most
(NoiseModelling keeps the unrounded wheel roughness), i.e. by <= 0.05 dB, and both rules interpolate with
convex weights, so a correct implementation stays within 0.05 dB of the second print.
"""

from __future__ import annotations

import bisect
import csv
import itertools
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wheelrail.cli.commands._common import CLI_NAMES
from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise.cnossos import (
    INTERPOLATION_RULES,
    RAIL_ROUGHNESS,
    TRACK_TYPES,
    WHEEL_DIAMETERS_MM,
    WHEEL_ROUGHNESS,
    cnossos_rolling_noise,
    interpolation_difference,
    roughness_to_frequency,
)
from wheelrail.core.noise.tables import load_table
from wheelrail.core.reference_filters import cnossos_filter
from wheelrail.core.spectra.bands import noise_bands
from wheelrail.core.spectra.levels import a_weighting

DATA = Path(__file__).parent.parent / "data"
TOL = 0.05  # dB, see the module docstring
FREQ = [
    50,
    63,
    80,
    100,
    125,
    160,
    200,
    250,
    315,
    400,
    500,
    630,
    800,
    1000,
    1250,
    1600,
    2000,
    2500,
    3150,
    4000,
    5000,
    6300,
    8000,
    10000,
]
A3_MM = [
    2000,
    1600,
    1250,
    1000,
    800,
    630,
    500,
    400,
    315,
    250,
    200,
    160,
    125,
    100,
    80,
    63,
    50,
    40,
    31.5,
    25,
    20,
    16,
    12.5,
    10,
    8,
    6.3,
    5,
    4,
    3.15,
    2.5,
    2,
    1.6,
    1.25,
    1,
    0.8,
]
WHEEL_GRID_MM = [
    1000,
    800,
    630,
    500,
    400,
    315,
    250,
    200,
    160,
    120,
    100,
    80,
    63,
    50,
    40,
    31.5,
    25,
    20,
    16,
    12,
    10,
    8,
    6.3,
    5,
    4,
    3.2,
    2.5,
    2,
    1.6,
    1.2,
    1,
    0.8,
]  # Table G-1a's own grid, as printed


def _second_print() -> dict:
    sections, name = {}, None
    for line in (DATA / "cnossos_second_print.csv").read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        if line.startswith("["):
            name = line.strip("[]")
            sections[name] = []
            continue
        sections[name].append(line.split(","))
    out = {}
    for name, (header, *rows) in sections.items():
        out[name] = {key: [float(r[i]) for r in rows] for i, key in enumerate(header)}
    return out


SECOND = _second_print()


def _a3_columns() -> dict:
    with (DATA / "cnossos_2021_rail.csv").open() as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    return {
        (50e3, 0.36): [float(r["50kN_360mm"]) for r in rows],
        (50e3, 0.68): [float(r["50kN_680mm"]) for r in rows],
        (25e3, 0.92): [float(r["25kN_920mm"]) for r in rows],
        (50e3, 0.92): [float(r["50kN_920mm"]) for r in rows],
        (100e3, 0.92): [float(r["100kN_920mm"]) for r in rows],
    }


A3 = _a3_columns()


# ---------------------------------------------------------------------------------------------------------------
# The transcription
# ---------------------------------------------------------------------------------------------------------------
def test_tables_match_the_second_print_cell_by_cell():
    wheel = load_table("wheel_roughness")
    assert list(np.round(wheel.grid * 1e3, 4)) == WHEEL_GRID_MM  # 32 bands, printed as the directive prints them
    for name in ("cast-iron", "composite", "disc"):
        np.testing.assert_allclose(wheel.column(name), SECOND["wheel_roughness"][name], atol=TOL + 1e-9, err_msg=name)
    rail = load_table("rail_roughness")
    assert list(np.round(rail.grid * 1e3, 4)) == A3_MM  # 35 bands to 2000 mm since (EU) 2021/1226
    for name in RAIL_ROUGHNESS:
        np.testing.assert_allclose(rail.column(name), SECOND["rail_roughness"][name], atol=1e-9, err_msg=name)
    track = load_table("track_transfer")
    assert list(track.grid) == FREQ
    for name in TRACK_TYPES:
        np.testing.assert_allclose(track.column(name), SECOND["track_transfer"][name], atol=1e-9, err_msg=name)
    vehicle = load_table("vehicle_transfer")
    for d in WHEEL_DIAMETERS_MM:
        np.testing.assert_allclose(vehicle.column(str(d)), SECOND["vehicle_transfer"][str(d)], atol=1e-9)
    np.testing.assert_array_equal(load_table("superstructure_transfer").column("eu-standard"), 0.0)
    for table in map(load_table, ("wheel_roughness", "rail_roughness", "track_transfer", "vehicle_transfer")):
        assert "2015/996" in table.source and "Table G-" in table.source  # every file names its source


def test_a_weighting_matches_the_iec_61672_table():
    # IEC 61672-1:2013 Table 3, A-weighting at the nominal one-third octave frequencies, 0.1 dB
    table = [
        -30.2,
        -26.2,
        -22.5,
        -19.1,
        -16.1,
        -13.4,
        -10.9,
        -8.6,
        -6.6,
        -4.8,
        -3.2,
        -1.9,
        -0.8,
        0.0,
        0.6,
        1.0,
        1.2,
        1.3,
        1.2,
        1.0,
        0.5,
        -0.1,
        -1.1,
        -2.5,
    ]
    np.testing.assert_allclose(a_weighting(noise_bands()), table, atol=0.05 + 1e-9)  # printed values are rounded


# ---------------------------------------------------------------------------------------------------------------
# The formulas, computed here in plain Python
# ---------------------------------------------------------------------------------------------------------------
def _read_at(levels, wavelengths_mm, speed, f, rule):
    """One band level, by this file's reading of the two rules (levels on printed wavelengths)."""
    pairs = sorted(zip(wavelengths_mm, levels, strict=True))
    lam = [p[0] * 1e-3 for p in pairs]
    lev = [p[1] for p in pairs]
    if rule == "proportional":
        x = speed / f
        if x <= lam[0]:
            return lev[0]
        if x >= lam[-1]:
            return lev[-1]
        j = bisect.bisect_right(lam, x)
        w = (x - lam[j - 1]) / (lam[j] - lam[j - 1])
        return lev[j - 1] + w * (lev[j] - lev[j - 1])
    # energy-log-frequency
    fb = [speed / x for x in lam][::-1]  # rising
    en = [10 ** (v / 10) for v in lev][::-1]
    x = math.log10(f)
    logs = [math.log10(v) for v in fb]
    if x <= logs[0]:
        e = en[0]
    elif x >= logs[-1]:
        e = en[-1]
    else:
        j = bisect.bisect_right(logs, x)
        w = (x - logs[j - 1]) / (logs[j] - logs[j - 1])
        e = en[j - 1] + w * (en[j] - en[j - 1])
    return 10 * math.log10(e)


def _expected(speed, rail, wheel, track, diameter_mm, load, axles, rule):
    a3_column = A3.get((load, diameter_mm / 1e3))
    if a3_column is None:  # not a table column: the filters rule, validated in test_reference_filters.py
        a3_column = list(cnossos_filter(load, diameter_mm / 1e3))
    out = {"track": [], "vehicle": [], "superstructure": []}
    for i, f in enumerate(FREQ):
        lr = _read_at(SECOND["rail_roughness"][rail], A3_MM, speed, f, rule)
        e = 10 ** (lr / 10)
        if wheel != "none":
            e += 10 ** (_read_at(SECOND["wheel_roughness"][wheel], WHEEL_GRID_MM, speed, f, rule) / 10)
        total = 10 * math.log10(e) + _read_at(a3_column, A3_MM, speed, f, rule)
        n = 10 * math.log10(axles)
        out["track"].append(total + SECOND["track_transfer"][track][i] + n)
        out["vehicle"].append(total + SECOND["vehicle_transfer"][str(diameter_mm)][i] + n)
        out["superstructure"].append(total + 0.0 + n)
    return out


def test_hand_worked_band():
    # 100 km/h, 1 kHz band: lambda = 27.78 mm between the printed 31.5 mm (-5.0 dB) and 25 mm (-5.6 dB) of
    # Table G-1b class E: -5.6 + (27.78 - 25) / (31.5 - 25) * 0.6 = -5.344 dB re 1 um (proportional rule)
    rail = load_table("rail_roughness")
    value = roughness_to_frequency(rail.column("iso3095"), rail.grid, 100 / 3.6, "proportional", [1000.0])[0]
    assert value == pytest.approx(-5.6 + (100 / 3.6 / 1000 - 0.025) / 0.0065 * 0.6, abs=1e-12)
    assert value == pytest.approx(-5.344, abs=5e-4)


@pytest.mark.parametrize("rule", INTERPOLATION_RULES)
def test_every_table_combination_matches_the_independent_computation(rule):
    worst = 0.0
    for speed_kmh, load in ((50, 50e3), (100, 65e3), (160, 50e3), (300, 100e3)):
        speed = speed_kmh / 3.6
        for rail, wheel, track, diameter in itertools.product(
            RAIL_ROUGHNESS, WHEEL_ROUGHNESS, TRACK_TYPES, WHEEL_DIAMETERS_MM
        ):
            got = cnossos_rolling_noise(
                speed,
                rail=rail,
                wheel=wheel,
                track_type=track,
                wheel_diameter=diameter / 1e3,
                load=load,
                axles=4,
                rule=rule,
            )
            want = _expected(speed, rail, wheel, track, diameter, load, 4, rule)
            for key, levels in (
                ("track", got.track_db),
                ("vehicle", got.vehicle_db),
                ("superstructure", got.superstructure_db),
            ):
                diff = np.abs(np.asarray(levels) - want[key])
                worst = max(worst, float(np.nanmax(diff)))
                np.testing.assert_allclose(
                    levels,
                    want[key],
                    atol=TOL + 1e-9,
                    err_msg=f"{rule} {speed_kmh} km/h {rail} {wheel} {track} {diameter} {key}",
                )
            total = 10 * np.log10(sum(10 ** (np.asarray(want[k]) / 10) for k in want))
            np.testing.assert_allclose(got.total_db, total, atol=TOL + 1e-9)
            want_dba = 10 * math.log10(
                sum(10 ** ((t + a) / 10) for t, a in zip(total, a_weighting(noise_bands()), strict=True))
            )
            assert got.total_dba == pytest.approx(want_dba, abs=TOL)
    assert worst <= TOL


def test_axles_and_the_filter_in_place_of_a3():
    base = cnossos_rolling_noise(100 / 3.6, axles=1)
    eight = cnossos_rolling_noise(100 / 3.6, axles=8)
    np.testing.assert_allclose(eight.total_db - base.total_db, 10 * math.log10(8), atol=1e-12)
    flat = cnossos_rolling_noise(100 / 3.6, contact_filter=("none", np.zeros(24)))
    np.testing.assert_allclose(flat.total_roughness_db - base.total_roughness_db, -base.contact_filter_db, atol=1e-12)
    assert flat.configuration["contact_filter"] == "none"


def test_the_two_rules_differ_by_up_to_about_one_db():
    # expected up to ~1 dB per band, ~0.3 dB(A) in total; measured 0.93 dB and 0.32 dB(A) at 100 km/h
    per_band, total = interpolation_difference(100 / 3.6, rail="network-average", wheel="cast-iron")
    assert 0.5 < np.max(np.abs(per_band)) < 1.2
    assert 0.1 < abs(total) < 0.5


def test_bad_input_is_one_clear_error():
    with pytest.raises(WheelrailError, match="track type"):
        cnossos_rolling_noise(30.0, track_type="concrete")
    with pytest.raises(WheelrailError, match="680, 840, 920, 1200") as diameter:
        cnossos_rolling_noise(30.0, wheel_diameter=0.9)
    # errors are data: the API names its argument (m), the command line its option (mm)
    table = "not one of the wheel diameters 680, 840, 920, 1200 mm (the columns of CNOSSOS-EU Table G-3b)"
    assert str(diameter.value) == f"wheel_diameter 0.9 m: {table}"
    assert diameter.value.render(CLI_NAMES) == f"--wheel-diameter-mm 900: {table}"
    with pytest.raises(WheelrailError, match="axles") as axles:
        cnossos_rolling_noise(30.0, axles=0)
    assert axles.value.render(CLI_NAMES) == "--axles 0: not a whole number of at least 1"
    with pytest.raises(WheelrailError) as load:
        cnossos_rolling_noise(30.0, load=-5.0)
    assert str(load.value) == "load -5 N: not a positive number"
    with pytest.raises(WheelrailError, match="speed"):
        cnossos_rolling_noise(float("nan"))
    with pytest.raises(WheelrailError, match="roughness interpolation"):
        cnossos_rolling_noise(30.0, rule="cubic")


def _cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "wheelrail", "noise", *args], capture_output=True, text=True, timeout=120
    )


@pytest.mark.slow
def test_cli_json_layout_and_errors():
    done = _cli(
        "--method",
        "cnossos",
        "--speed-kmh",
        "120",
        "--rail-roughness",
        "network-average",
        "--wheel-roughness",
        "none",
        "--track-type",
        "wooden",
        "--wheel-diameter-mm",
        "680",
        "--preload-kn",
        "50",
        "--axles",
        "2",
        "--roughness-interpolation",
        "energy-log-frequency",
        "--json",
    )
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    assert len(out["frequency_hz"]) == 24
    for key in ("total_roughness_dB", "track_dB", "vehicle_dB", "superstructure_dB"):
        assert len(out["cnossos"][key]) == 24
    want = cnossos_rolling_noise(
        120 / 3.6,
        rail="network-average",
        wheel="none",
        track_type="wooden",
        wheel_diameter=0.68,
        load=50e3,
        axles=2,
        rule="energy-log-frequency",
    )
    np.testing.assert_allclose(out["cnossos"]["track_dB"], want.track_db, atol=1e-9)
    assert out["cnossos"]["total_dBA"] == pytest.approx(want.total_dba)
    bad = _cli("--method", "cnossos", "--wheel-diameter-mm", "900")
    assert bad.returncode == 2 and bad.stderr.startswith("wheelrail noise: error: --wheel-diameter-mm 900: not one ")
    assert len(bad.stderr.strip().splitlines()) == 1 and "Table G-3b" in bad.stderr
    bad = _cli("--method", "cnossos", "--speed-kmh", "-3")  # core's accepted range, in the option's unit
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
    assert bad.stderr.startswith("wheelrail noise: error: --speed-kmh -3 is outside the accepted 5 to 400 km/h (")
    bad = _cli("--method", "cnossos", "--preload-kn", "5000")
    assert bad.returncode == 2 and "--preload-kn 5000 is outside the accepted 1 to 500 kN" in bad.stderr
