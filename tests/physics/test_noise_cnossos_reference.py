"""CNOSSOS-EU rolling noise against the Commission's own published results (the CNOSSOS-EU emission test workbook).

Reference: ``tests/data/cnossos_reference_circabc2015.csv`` (its header gives the provenance): 14 cases of
``CNOSSOS_RAIL_EMISSION_TEST.xlsx`` (JRC CNOSSOS-EU source module, 2014), octave-band line power per metre at
source A, constant speed, no impact noise, computed by the Commission's reference emission library with the 2015
catalogue, together with the catalogue rows those cases use. The numbers are independent of this project's table
transcription and of its formulas: they are the reference program's output for the reference program's database.

What the test does: it hands the 2015 catalogue rows to :func:`cnossos_rolling_noise` in place of the shipped
tables (the roughness on its printed wavelength grid, so the implementation's own wavelength-to-frequency
conversion, energy sum, A3, transfer functions and axle term are exercised; the contact filter through the public
``contact_filter`` argument, converted by the implementation's :func:`roughness_to_frequency`), and adds what the
workbook carries besides rolling noise, written here from the directive's text (2015 edition, as the workbook
was computed): the squeal and bridge constants of the case, traction noise at source A, aerodynamic noise above
200 km/h (eq. 2.3.13), the vertical directivity of source A (2.3.16 as printed in 2015, with the absolute value)
and the horizontal dipole (2.3.15) applied to every source as the reference module does, the flow term
10 lg(Q / (1000 v)) of eq. 2.3.2 (v in km/h) and the sum of three one-third octaves per octave. Rolling noise is
the largest term in most bands of these cases (in the 1-8 kHz octaves of every 30 and 120 km/h case), so a wrong
rolling level shows.

A second test runs the four cases on rail roughness class E with the tables this project ships (G-1a, G-1b, G-3a,
G-3b, G-3c, which (EU) 2021/1226 left equal to the 2015 catalogue to within G-1a's 0.1 dB print) and only the
contact filter from the catalogue (G-2 was replaced in 2021).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from wheelrail.core.noise import cnossos
from wheelrail.core.noise.cnossos import cnossos_rolling_noise, roughness_to_frequency
from wheelrail.core.noise.tables import NOMINAL_FREQUENCIES_HZ, Table

DATA = Path(__file__).parent.parent / "data" / "cnossos_reference_circabc2015.csv"
OCTAVES = ("63", "125", "250", "500", "1000", "2000", "4000", "8000")
FREQ = np.asarray(NOMINAL_FREQUENCIES_HZ)
# The catalogue's wavelength grid, 1000 .. 0.8 mm, in m (the module's own 1/3-octave series).
GRID_M = (
    np.array(
        [1000, 800, 630, 500, 400, 315, 250, 200, 160, 125, 100, 80, 63, 50, 40, 31.5, 25, 20, 16, 12.5, 10, 8, 6.3, 5]
        + [4, 3.15, 2.5, 2, 1.6, 1.25, 1, 0.8]
    )
    * 1e-3
)
WHEEL_NAMES = {"3": "cast-iron", "4": "composite", "5": "disc"}
WHEEL_DIAMETERS_M = {"3": 0.92, "6": 1.2}


def _sections() -> dict[str, list[dict[str, str]]]:
    sections: dict[str, list[str]] = {}
    current = None
    for line in DATA.read_text(encoding="utf-8").splitlines():
        if line.startswith("#") or not line.strip():
            continue
        if line.startswith("["):
            current = line.strip("[]")
            sections[current] = []
        else:
            sections[current].append(line)
    return {name: list(csv.DictReader(lines)) for name, lines in sections.items()}


SECTIONS = _sections()
CASES = SECTIONS["cases"]
VEHICLES = {row["id"]: row for row in SECTIONS["vehicles"]}


def _spectra(section: str, columns) -> dict[tuple[str, str], np.ndarray]:
    return {(row["table"], row["id"]): np.array([float(row[c]) for c in columns]) for row in SECTIONS[section]}


WAVELENGTH = _spectra("wavelength_tables", [f"{w:g}" for w in GRID_M * 1e3])
FREQUENCY = _spectra("frequency_tables", [f"{f:g}" for f in FREQ])


def _catalogue_tables(case: dict, vehicle: dict) -> dict[str, Table]:
    """The case's 2015 catalogue rows as tables, each under the one column name the call below selects."""
    rows = (  # (table the implementation loads, column it selects, catalogue table, catalogue id)
        ("wheel_roughness", "cast-iron", "wheel_roughness", vehicle["wheel_roughness"]),
        ("rail_roughness", "iso3095", "rail_roughness", case["rail_roughness"]),
        ("track_transfer", "mono-block-medium", "track_transfer", case["track_transfer"]),
        ("vehicle_transfer", "920", "wheel_transfer", vehicle["wheel_transfer"]),
        ("superstructure_transfer", "eu-standard", "superstructure_transfer", case["superstructure_transfer"]),
    )
    tables = {}
    for name, column, table, row_id in rows:
        by_wavelength = (table, row_id) in WAVELENGTH
        tables[name] = Table(
            name=name,
            axis="wavelength" if by_wavelength else "frequency",
            grid=GRID_M if by_wavelength else FREQ,
            columns={column: (WAVELENGTH if by_wavelength else FREQUENCY)[table, row_id]},
            source="CNOSSOS-EU 2015 catalogue",
        )
    return tables


def _line_power_octaves(case: dict, rolling_db: np.ndarray) -> np.ndarray:
    """Octave-band L'_W,eq,line at source A from the rolling L_W,0 per vehicle (24 bands), as the workbook sums it."""
    vehicle = VEHICLES[case["vehicle"]]
    kmh = float(case["speed_kmh"])
    sources = [
        rolling_db + float(case["squeal_excess_db"]) + float(case["bridge_constant_db"]),
        FREQUENCY["traction_constant_A", vehicle["traction"]],
    ]
    if kmh > 200.0:  # eq. 2.3.13: aerodynamic noise only above 200 km/h
        v0, alpha = float(case["aero_v0_kmh"]), float(case["aero_alpha"])
        sources.append(FREQUENCY["aerodynamic_A_300kmh", vehicle["aerodynamic"]] + alpha * math.log10(kmh / v0))
    psi, phi = math.radians(float(case["psi_deg"])), math.radians(float(case["phi_deg"]))
    vertical = np.abs(40.0 / 3.0 * (2.0 / 3.0 * math.sin(2.0 * psi) - math.sin(psi)) * np.log10((FREQ + 600.0) / 200.0))
    horizontal = 10.0 * math.log10(0.01 + 0.99 * math.sin(phi) ** 2)
    directional = 10.0 * np.log10(sum(10.0 ** ((s + vertical + horizontal) / 10.0) for s in sources))
    line = directional + 10.0 * math.log10(float(case["flow_veh_per_h"]) / (1000.0 * kmh))
    return 10.0 * np.log10((10.0 ** (line / 10.0)).reshape(8, 3).sum(axis=1))


def _expected(case: dict) -> np.ndarray:
    return np.array([float(case[f"lw_{band}"]) for band in OCTAVES])


def _with_catalogue(case: dict, monkeypatch, rule: str = "proportional") -> np.ndarray:
    vehicle = VEHICLES[case["vehicle"]]
    tables = _catalogue_tables(case, vehicle)
    monkeypatch.setattr(cnossos, "load_table", tables.__getitem__)
    speed = float(case["speed_kmh"]) / 3.6
    a3 = roughness_to_frequency(WAVELENGTH["contact_filter", vehicle["contact_filter"]], GRID_M, speed, rule)
    result = cnossos_rolling_noise(
        speed,
        rail="iso3095",
        wheel="cast-iron",
        track_type="mono-block-medium",
        wheel_diameter=0.92,
        load=50e3,  # unused: the contact filter is given
        axles=int(vehicle["axles"]),
        rule=rule,
        contact_filter=("CNOSSOS-EU 2015 catalogue contact filter " + vehicle["contact_filter"], a3),
    )
    return _line_power_octaves(case, result.total_db)


def _case_id(case: dict) -> str:
    return f"case{case['case']}-veh{case['vehicle']}-{case['speed_kmh']}kmh"


def test_reference_file_is_complete_and_self_consistent():
    assert len(CASES) == 14
    assert {c["source_height"] for c in CASES} == {"A"} and {c["condition"] for c in CASES} == {"constant"}
    assert {c["speed_kmh"] for c in CASES} == {"30", "120", "260"}
    for case in CASES:  # the printed total is the energy sum of the printed bands (catches a mistyped band)
        total = 10.0 * math.log10(np.sum(10.0 ** (_expected(case) / 10.0)))
        assert total == pytest.approx(float(case["lw_total"]), abs=0.01)
        assert float(case["joint_density_per_m"]) == 0.0 and not case["impact_roughness"]


@pytest.mark.parametrize("case", CASES, ids=_case_id)
def test_workbook_reproduced_with_the_2015_catalogue(case, monkeypatch):
    computed = _with_catalogue(case, monkeypatch)
    # 0.01 dB: the workbook prints two decimals (+-0.005 dB) and is fed the very catalogue it was computed with;
    # observed worst 0.0050 dB over the 112 bands. The energy-log-frequency rule misses by up to 0.22 dB.
    np.testing.assert_allclose(computed, _expected(case), rtol=0, atol=0.01)


def test_workbook_tells_the_conversion_rules_apart(monkeypatch):
    """The Commission's reference program reads the tables linearly in wavelength (the ``proportional`` rule)."""
    worst = {}
    for rule in ("proportional", "energy-log-frequency"):
        worst[rule] = max(np.abs(_with_catalogue(case, monkeypatch, rule) - _expected(case)).max() for case in CASES)
    assert worst["proportional"] < 0.01
    assert worst["energy-log-frequency"] > 0.05


@pytest.mark.parametrize("case", [c for c in CASES if c["rail_roughness"] == "3"], ids=_case_id)
def test_workbook_reproduced_with_the_shipped_tables(case):
    vehicle = VEHICLES[case["vehicle"]]
    assert case["track_transfer"] == "7" and case["superstructure_transfer"] == "1"  # bi-block medium, 0 dB
    speed = float(case["speed_kmh"]) / 3.6
    a3 = roughness_to_frequency(WAVELENGTH["contact_filter", vehicle["contact_filter"]], GRID_M, speed)
    result = cnossos_rolling_noise(
        speed,
        rail="iso3095",
        wheel=WHEEL_NAMES[vehicle["wheel_roughness"]],
        track_type="bi-block-medium",
        wheel_diameter=WHEEL_DIAMETERS_M[vehicle["wheel_transfer"]],
        axles=int(vehicle["axles"]),
        contact_filter=("CNOSSOS-EU 2015 catalogue contact filter " + vehicle["contact_filter"], a3),
    )
    # 0.05 dB: the shipped G-1a is the Official Journal print, rounded to 0.1 dB (the catalogue has 0.01 dB) and
    # printed at 120, 12, 3.2, 1.2 mm where the catalogue has 125, 12.5, 3.15, 1.25 mm; with the catalogue's own
    # rows the same cases agree to 0.005 dB (test above), here the worst is 0.032 dB.
    np.testing.assert_allclose(_line_power_octaves(case, result.total_db), _expected(case), rtol=0, atol=0.05)
