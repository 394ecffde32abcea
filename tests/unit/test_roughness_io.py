"""Roughness data model and its two file formats (CSV, NPZ; docs/user_guide.md, Roughness data), every bad input."""

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness import (
    RoughnessSet,
    load_roughness,
    read_csv,
    read_npz,
    read_roughness,
    write_csv,
    write_npz,
)


def _set(kind="wheel", n_lines=5, n_samples=64, dy=2e-3, seed=1):
    rng = np.random.default_rng(seed)
    y = (np.arange(n_lines) - n_lines // 2) * dy
    return RoughnessSet(
        heights=rng.normal(scale=3e-6, size=(n_lines, n_samples)),
        dx=0.5e-3,
        y=y,
        kind=kind,
        description="test set, seed 1",
    )


# ----------------------------------------------------------------------------- data model
def test_line_numbers_follow_figure_8():
    s = _set(n_lines=7)
    assert s.line_numbers.tolist() == [-3, -2, -1, 0, 1, 2, 3]
    assert s.row_of_line(0) == 3
    assert s.row_of_line(-3) == 0
    assert s.line_of_row(6) == 3
    np.testing.assert_array_equal(s.line(2), s.heights[5])
    with pytest.raises(WheelrailError, match="line 4 is not in this set; lines run from -3 to 3"):
        s.row_of_line(4)


def test_centre_line_is_nearest_to_zero_for_asymmetric_positions():
    s = RoughnessSet(heights=np.zeros((4, 3)), dx=1e-3, y=[-3e-3, -1e-3, 1.5e-3, 4e-3], kind="rail")
    assert s.centre_row == 1
    assert s.line_numbers.tolist() == [-1, 0, 1, 2]


def test_set_is_frozen_and_read_only():
    s = _set()
    with pytest.raises(AttributeError):
        s.dx = 1.0
    with pytest.raises(ValueError):
        s.heights[0, 0] = 1.0
    assert s.length == pytest.approx(64 * 0.5e-3)  # n * dx, the circumference for a wheel


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"kind": "tram"}, "kind must be one of rail, wheel, got 'tram'"),
        ({"dx": 0.0}, "dx must be a positive finite spacing"),
        ({"dx": float("nan")}, "dx must be a positive finite spacing"),
        ({"heights": np.zeros((2, 1))}, "at least 1 line and 2 samples"),
        ({"heights": np.full((2, 4), np.nan)}, "must be finite"),
        ({"heights": np.full((2, 4), 0.02)}, "within ±10 mm"),
        ({"y": [0.0, 0.0]}, "strictly increasing without duplicates"),
        ({"y": [0.0]}, "one position per line"),
    ],
)
def test_data_model_rejects_bad_values(kwargs, message):
    base = {"heights": np.zeros((2, 4)), "dx": 1e-3, "y": [0.0, 1e-3], "kind": "rail"}
    base.update(kwargs)
    with pytest.raises(WheelrailError, match=message):
        RoughnessSet(**base)


def test_a_smooth_set_is_declared_once():
    # a rail's samples reach x = length; a wheel's are one circumference; lines centred on line 0 at y = 0
    rail = RoughnessSet.smooth(0.3, lines=41)
    assert rail.heights.shape == (41, 301) and not rail.heights.any() and rail.kind == "rail"
    np.testing.assert_array_equal(rail.y, (np.arange(41) - 20) * 1e-3)
    assert rail.centre_row == 20 and rail.description == "smooth"
    wheel = RoughnessSet.smooth(2.45, dx=0.5e-3, lines=4, line_spacing=2e-3, kind="wheel", description="flat")
    assert wheel.n_samples == 4900 and wheel.length == pytest.approx(2.45) and wheel.periodic
    assert wheel.y.tolist() == pytest.approx([-4e-3, -2e-3, 0.0, 2e-3]) and wheel.description == "flat"


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"length": 0.0}, "RoughnessSet.smooth: length must be a positive finite number of m, got 0.0"),
        ({"length": float("nan")}, "length must be a positive finite number of m, got nan"),
        ({"length": "1 m"}, "length must be a positive number of m, got '1 m'"),
        ({"dx": -1e-3}, "dx must be a positive finite number of m, got -0.001"),
        ({"line_spacing": float("inf"), "lines": 3}, "line_spacing must be a positive finite number of m, got inf"),
        ({"lines": 0}, "lines must be a positive whole number, got 0"),
        ({"lines": 2.5}, "lines must be a positive whole number, got 2.5"),
        ({"kind": "tram"}, "kind must be one of rail, wheel, got 'tram'"),
        ({"length": 1e-3, "kind": "wheel"}, "length 0.001 m holds 1 sample(s) at dx 0.001 m; at least 2 are needed"),
        ({"length": 1e6, "lines": 41}, "a smooth set would hold 4.1e+10 heights"),
        ({"length": 1e300, "dx": 1e-300}, "a smooth set would hold inf heights"),
    ],
)
def test_a_smooth_set_refuses_bad_input(kwargs, message):
    with pytest.raises(WheelrailError) as info:
        RoughnessSet.smooth(**{"length": 1.0, **kwargs})
    assert message in str(info.value) and "\n" not in str(info.value)


# ----------------------------------------------------------------------------- round trips
def test_csv_round_trip(tmp_path):
    s = _set()
    path = write_csv(s, tmp_path / "set.csv")
    text = path.read_text().splitlines()
    assert text[0] == "# kind: wheel"
    assert text[2].startswith("x_m,y_mm=-4.0,")
    back = read_csv(path)
    assert back.kind == s.kind
    assert back.description == s.description
    assert back.n_lines == s.n_lines and back.n_samples == s.n_samples
    # Heights pass through a µm <-> m conversion: equal to a few ulp, so rtol 1e-14.
    np.testing.assert_allclose(back.heights, s.heights, rtol=1e-14, atol=0)
    np.testing.assert_allclose(back.y, s.y, rtol=1e-14, atol=0)
    # dx is recovered as (x_last - x_0)/(n - 1) from repr-exact x values: a few ulp.
    assert back.dx == pytest.approx(s.dx, rel=1e-13)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_npz_round_trip(tmp_path, dtype):
    s = _set(kind="rail")
    back = read_npz(write_npz(s, tmp_path / "set.npz", dtype=dtype))
    assert (back.kind, back.description, back.dx) == (s.kind, s.description, s.dx)
    np.testing.assert_array_equal(back.y, s.y)
    if dtype is np.float64:
        np.testing.assert_array_equal(back.heights, s.heights)  # float64 storage is lossless
    else:
        # float32 keeps 24 bits: relative error <= 2**-24 = 6e-8.
        np.testing.assert_allclose(back.heights, s.heights, rtol=6e-8, atol=0)


def test_user_files_load_like_bundled_sets(tmp_path):
    s = _set()
    for suffix, writer in ((".csv", write_csv), (".npz", write_npz)):
        path = writer(s, tmp_path / f"mine{suffix}")
        loaded = load_roughness(str(path))
        np.testing.assert_allclose(loaded.heights, s.heights, rtol=1e-14)  # µm conversion, see above
        assert read_roughness(path).n_lines == 5


def test_csv_written_by_hand(tmp_path):
    path = tmp_path / "hand.csv"
    path.write_text(
        "# kind: rail\n# description: two lines by hand\n# operator: me\n"
        "x_m, y_mm=1, y_mm=-1\n0.000,1.5,-2\n0.001,2.5,-3\n0.002,0,0\n\n"
    )
    s = read_csv(path)
    assert s.kind == "rail" and s.description == "two lines by hand"
    assert s.y.tolist() == pytest.approx([-1e-3, 1e-3])  # columns sorted by lateral position
    np.testing.assert_allclose(s.heights[1], [1.5e-6, 2.5e-6, 0.0], rtol=1e-15)
    assert s.dx == pytest.approx(1e-3, rel=1e-12)


def test_csv_without_kind_assumes_rail_and_says_so(tmp_path):
    path = tmp_path / "nokind.csv"
    path.write_text("x_m,y_mm=0\n0,1\n0.001,2\n")
    s = read_csv(path)
    assert s.kind == "rail" and "rail assumed" in s.description
    assert read_csv(path, kind="wheel").kind == "wheel"


# ----------------------------------------------------------------------------- bad CSV files
GOOD_HEADER = "# kind: rail\nx_m,y_mm=0,y_mm=1\n"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("0,1,2\n0.001,1,2\n", r"line 1: header must start with 'x_m', got '0'"),
        ("# kind: rail\n", r"missing header row"),
        ("x_m\n0\n0.001\n", r"line 1: header needs at least one 'y_mm="),
        ("x_m,y=0\n0,1\n0.001,1\n", r"line 1, column 2: expected 'y_mm=<lateral position in mm>', got 'y=0'"),
        ("x_m,y_mm=abc\n0,1\n0.001,1\n", r"line 1, column 2: the lateral position y_mm must be a number"),
        ("x_m,y_mm=1,y_mm=1.0\n0,1,1\n0.001,1,1\n", r"duplicate lateral position y_mm=1 in columns 2 and 3"),
        (GOOD_HEADER + "0,1,2\n0.001,1\n", r"line 4: ragged row with 2 cells, header has 3"),
        (
            GOOD_HEADER + "0,1,2\n0.001,1,nan\n",
            r"line 4: height \(µm\) in column 3 must be finite",
        ),
        (
            GOOD_HEADER + "0,1,2\n0.001,inf,2\n",
            r"line 4: height \(µm\) in column 2 must be finite",
        ),
        (
            GOOD_HEADER + "0,1,2\n0.001,1,two\n",
            r"line 4: height \(µm\) in column 3 must be a number",
        ),
        (GOOD_HEADER + "0,1,2\n", r"needs at least 2 samples \(data rows\), got 1"),
        (GOOD_HEADER + "0,1,2\n0.001,1,2\n0.0025,1,2\n0.003,1,2\n", r"line 5: non-uniform x spacing"),
        (GOOD_HEADER + "0,1,2\n-0.001,1,2\n", r"x_m must increase"),
        (GOOD_HEADER + "0,1,2\n0.001,12000,2\n", r"line 4: height 12000 µm exceeds ±10000 µm"),
        (GOOD_HEADER + "0,1e-7,2e-7\n0.001,3e-7,-1e-7\n", r"seems to hold metres, heights must be in µm"),
        ("# kind: tram\nx_m,y_mm=0\n0,1\n0.001,1\n", r"unknown kind 'tram', allowed: rail, wheel"),
        (GOOD_HEADER + "0,1,2\n# late comment\n0.001,1,2\n", r"line 4: comment lines are allowed only"),
    ],
)
def test_bad_csv_gives_one_line_naming_file_and_line(tmp_path, content, message):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(WheelrailError, match=message) as info:
        read_csv(path)
    text = str(info.value)
    assert "\n" not in text
    assert str(path) in text  # names the file


def test_binary_file_named_csv(tmp_path):
    path = tmp_path / "bin.csv"
    path.write_bytes(b"\xff\xfe\x00\x81garbage")
    with pytest.raises(WheelrailError, match="not a text CSV file"):
        read_csv(path)


# ----------------------------------------------------------------------------- bad NPZ files
def _npz(tmp_path, **arrays):
    path = tmp_path / "bad.npz"
    np.savez(path, **arrays)
    return path


@pytest.mark.parametrize(
    ("arrays", "message"),
    [
        ({"z_m": np.zeros((2, 4)), "dx_m": 1e-3, "kind": "rail"}, r"missing array\(s\) y_m"),
        ({"z_m": np.zeros((2, 4)), "dx_m": 1e-3, "y_m": [0, 1e-3], "kind": "tram"}, r"unknown kind 'tram'"),
        ({"z_m": np.zeros(4), "dx_m": 1e-3, "y_m": [0.0], "kind": "rail"}, r"z_m must be 2-D"),
        ({"z_m": np.zeros((2, 1)), "dx_m": 1e-3, "y_m": [0, 1e-3], "kind": "rail"}, r"at least 2 samples"),
        ({"z_m": np.full((2, 4), np.inf), "dx_m": 1e-3, "y_m": [0, 1e-3], "kind": "rail"}, r"must be finite"),
        ({"z_m": np.zeros((2, 4)), "dx_m": 1e-3, "y_m": [0, 0], "kind": "rail"}, r"duplicate lateral"),
        ({"z_m": np.zeros((2, 4)), "dx_m": 1e-3, "y_m": [0.0], "kind": "rail"}, r"one lateral position per"),
        (
            {"z_m": np.zeros((2, 4)), "dx_m": [1e-3, 2e-3], "y_m": [0, 1e-3], "kind": "rail"},
            r"dx_m must be a",
        ),
        ({"z_m": np.ones((2, 4)), "dx_m": 1e-3, "y_m": [0, 1e-3], "kind": "rail"}, r"within ±10 mm"),
        (
            {"z_m": np.zeros((2, 4)), "dx_m": -1e-3, "y_m": [0, 1e-3], "kind": "rail"},
            r"dx must be a positive",
        ),
    ],
)
def test_bad_npz_gives_one_line_naming_file(tmp_path, arrays, message):
    path = _npz(tmp_path, **arrays)
    with pytest.raises(WheelrailError, match=message) as info:
        read_npz(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_corrupt_npz(tmp_path):
    path = tmp_path / "corrupt.npz"
    path.write_bytes(b"PK\x03\x04 not really a zip")
    with pytest.raises(WheelrailError, match="not a readable NPZ roughness file"):
        read_npz(path)


# ----------------------------------------------------------------------------- load_roughness
def test_unknown_name_lists_bundled_sets():
    with pytest.raises(WheelrailError, match=r"unknown roughness set 'no-such-set'; bundled sets: ") as info:
        load_roughness("no-such-set")
    for name in ("cast-iron-wheel", "corrugated-rail", "sinter-wheel-1", "sinter-wheel-2"):
        assert name in str(info.value)


def test_missing_file_and_unknown_suffix(tmp_path):
    with pytest.raises(WheelrailError, match="roughness file not found"):
        load_roughness(str(tmp_path / "absent.csv"))
    other = tmp_path / "data.txt"
    other.write_text("x")
    with pytest.raises(WheelrailError, match=r"unknown roughness file type '.txt', allowed: .csv, .npz"):
        load_roughness(str(other))
