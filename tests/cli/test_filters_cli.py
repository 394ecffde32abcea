"""``wheelrail filters`` and the ISO 3095 limit of ``wheelrail roughness``."""

import csv
import json

import numpy as np
import pytest

from wheelrail.core.parameters import ContactParameters
from wheelrail.core.reference_filters import CNOSSOS_A3, reference_filters


def test_filters_json_layout(cli):
    code, out, err = cli("filters", "--json", "--preload-kn", "50", "--wheel-radius-mm", "460")
    assert code == 0 and err == ""
    result = json.loads(out)  # strict JSON: undefined levels are null
    assert len(result["wavelength_mm"]) == 35
    assert result["wavelength_mm"][0] == pytest.approx(1995.26, rel=1e-5)  # nominal 2000 mm, exact base-10 centre
    assert (
        set(result["by_wavelength"])
        == set(result["by_frequency"])
        == {"cnossos", "averaging", "patch-correlated", "patch-incoherent"}
    )
    # a tabulated case (50 kN, 920 mm) prints its CNOSSOS column exactly
    assert result["by_wavelength"]["cnossos"] == pytest.approx(list(CNOSSOS_A3[(50e3, 0.92)]))
    assert len(result["band_centres_hz"]) == 23 == len(result["by_frequency"]["averaging"])
    a, b = result["semi_axes_m"]  # an unset crown is the paper's R = 0.39 m: an ellipse under a 0.46 m wheel
    assert [a, b] == pytest.approx(ContactParameters(preload=50e3, wheel_radius=0.46).hertz_semi_axes(), rel=1e-12)
    assert a > b and result["geometry"]["rail_crown_radius"] == pytest.approx(0.39)
    assert result["speed_m_s"] == pytest.approx(100 / 3.6)


def test_filters_on_an_elliptic_patch(cli):
    """A 0.46 m wheel on a 0.30 m crown: Hertz's ellipse, a = 6.20 mm along the rail and b = 4.67 mm
    across (Johnson 4.2); the analytic filters follow a, the CNOSSOS column stays the table's for D = 920 mm."""
    code, out, err = cli("filters", "--json", "--wheel-radius-mm", "460", "--rail-crown-radius-mm", "300")
    assert code == 0 and err == ""
    result = json.loads(out)
    a, b = result["semi_axes_m"]
    assert a == pytest.approx(6.20e-3, abs=0.01e-3) and b == pytest.approx(4.67e-3, abs=0.01e-3)
    assert result["geometry"]["rail_crown_radius"] == pytest.approx(0.30)
    circle = reference_filters(65e3, 0.46, 100 / 3.6)
    expected = [None if not np.isfinite(v) else pytest.approx(v) for v in circle.by_wavelength["cnossos"]]
    assert result["by_wavelength"]["cnossos"] == expected
    assert result["by_wavelength"]["averaging"] != pytest.approx(list(circle.by_wavelength["averaging"]))
    code, _, err = cli("filters", "--wheel-transverse-radius-mm", "-300")
    assert code != 0 and "the surfaces conform" in err and len(err.strip().splitlines()) == 1


def test_filters_null_where_undefined(cli):
    code, out, _ = cli("filters", "--json")  # the paper's 65 kN, R = 390 mm: interpolated CNOSSOS
    assert code == 0
    cnossos = json.loads(out)["by_wavelength"]["cnossos"]
    assert cnossos[-1] is None and all(v is not None for v in cnossos[:-1])


@pytest.mark.slow
def test_filters_table_csv_and_plot(cli, tmp_path, monkeypatch):
    from wheelrail.cli.commands import filters

    made, original = [], filters.filters_figure
    monkeypatch.setattr(filters, "filters_figure", lambda result: made.append(original(result)) or made[-1])
    table, figure = tmp_path / "f.csv", tmp_path / "f.png"
    code, out, err = cli("filters", "--speed-kmh", "140", "--csv", str(table), "--plot", str(figure))
    assert code == 0 and err == "" and "at 140 km/h" in out and "patch-incoherent" in out
    with open(table, newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["axis"] for r in rows].count("wavelength") == 35 and [r["axis"] for r in rows].count("frequency") == 23
    assert rows[-1]["cnossos_db"] != "" and rows[34]["cnossos_db"] == ""  # 0.8 mm undefined after scaling
    assert figure.stat().st_size > 10_000
    assert not list(tmp_path.glob(".*"))  # atomic writes leave no temporary file
    # the figure names its configuration in core's words (the radii in use and the Hertz patch at the preload)
    title = made[0].axes[0].get_title().replace("\n", " ")
    assert title.startswith("Reference contact filters at 140 km/h: wheel radius 390 mm (the paper's R)")
    assert title.endswith("Hertz patch at 65 kN a = 5.48 mm along, b = 5.48 mm across")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--preload-kn", "0"], "--preload-kn 0 is outside the accepted 1 to 500 kN"),
        (["--wheel-radius-mm", "nan"], "--wheel-radius-mm nan: not a number"),
        (["--speed-kmh", "-5"], "--speed-kmh -5 is outside the accepted 5 to 400 km/h"),
        (["--csv", "out.txt"], "must end in .csv"),
        (["--plot", "/no/such/folder/f.png"], "does not exist"),
    ],
)
def test_filters_bad_input_is_one_line(cli, argv, message):
    code, out, err = cli("filters", *argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1


@pytest.mark.slow
def test_roughness_iso3095_margin_for_rail_sets(cli, tmp_path):
    code, out, _ = cli("roughness", "--set", "corrugated-rail", "--json", "--plot", str(tmp_path / "r.png"))
    assert code == 0
    bands = json.loads(out)["wavelength_bands"]
    labels, limit, margin = bands["band_labels_mm"], bands["iso3095_limit_db"], bands["iso3095_margin_db"]
    assert labels[3] == "400" and limit[3] == pytest.approx(17.1) and limit[-1] == pytest.approx(-11.0)
    assert limit[:3] == [None, None, None]  # 800 .. 500 mm: outside the standard's 400 .. 3.15 mm
    levels = np.array([np.nan if v is None else v for v in bands["levels_db"]])
    expected = np.array(limit[3:], dtype=float) - levels[3:]
    np.testing.assert_allclose(np.array(margin[3:], dtype=float), expected, atol=1e-9)
    code, out, _ = cli("roughness", "--set", "cast-iron-wheel", "--json")
    assert code == 0 and "iso3095_margin_db" not in json.loads(out)["wavelength_bands"]  # a rail limit only
