"""The roughness readers refuse data no rail or wheel can give, in one line naming the file, row or column."""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness import read_csv, read_npz

HEADER = "# kind: rail\nx_m,y_mm=-5,y_mm=0,y_mm=5\n"


def _rows(dx: float, n: int = 50, scale=(1.0, 1.0, 1.0)) -> str:
    rng = np.random.default_rng(1)
    lines = []
    for i in range(n):
        heights = rng.normal(0.0, 3.0, 3) * np.asarray(scale)  # µm
        lines.append(",".join([repr(i * dx), *map(repr, heights.tolist())]))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (HEADER + _rows(1e-300), r"spacing 1e-300 m is outside"),
        (HEADER + _rows(1e300), r"spacing 1e\+300 m is outside"),
        (
            "# kind: rail\nx_m,y_mm=-1e300,y_mm=0\n0,1,2\n0.001,2,1\n",
            r"column 2 \(y_mm=-1e\+300\): lateral position .* outside",
        ),
        (
            "# kind: rail\nx_m,y_mm=0,y_mm=1e300\n0,1,2\n0.001,2,1\n",
            r"column 3 \(y_mm=1e\+300\): lateral position .* outside",
        ),
        # one column in metres among µm columns: 3 µm rms against 3e-6 "µm"
        (HEADER + _rows(1e-3, scale=(1.0, 1e-6, 1.0)), r"column 3 \(y_mm=0\).*metres"),
        (HEADER + "0,1,2,3\n0.001,1_0,2,3\n", r"line 4: height \(µm\) in column 2 must be a number, got '1_0'"),
        (HEADER + "0,1,2,3\n0.00_1,1,2,3\n", r"line 4: x_m must be a number, got '0.00_1'"),
        ("# kind: rail\nx_m,y_mm=1_0\n0,1\n0.001,1\n", r"the lateral position y_mm must be a number, got '1_0'"),
        (HEADER + "0,1,2,3\n0.001,１,2,3\n", r"must be a number"),  # a full-width digit: float() reads it
    ],
    ids=["dx 1e-300", "dx 1e300", "y -1e300 mm", "y 1e300 mm", "metres column", "1_0", "x 0.00_1", "y 1_0", "wide"],
)
def test_impossible_csv_is_refused_naming_the_file(tmp_path, content, message):
    path = tmp_path / "odd.csv"
    path.write_text(content, encoding="utf-8")
    with pytest.raises(WheelrailError, match=message) as info:
        read_csv(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_columns_of_different_but_real_roughness_are_read():
    """The metres rule leaves real data alone: lines 30 times apart in rms (a polished band beside a rough
    one) and a line of zeros (a deliberately smooth line) are roughness."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "ok.csv"
        rows = _rows(1e-3, scale=(1.0, 1 / 30, 0.0))
        path.write_text(HEADER + rows)
        rough = read_csv(path)
    assert rough.n_lines == 3 and np.all(rough.heights[2] == 0.0)


def _npz(path, **arrays):
    base = {"z_m": np.zeros((2, 4)), "dx_m": 1e-3, "y_m": [0.0, 1e-3], "kind": "rail"}
    np.savez(path, **{**base, **arrays})
    return path


@pytest.mark.parametrize(
    ("arrays", "message"),
    [
        ({"dx_m": 1e-300}, r"spacing 1e-300 m is outside"),
        ({"dx_m": 1e300}, r"spacing 1e\+300 m is outside"),
        ({"y_m": [-1e300, 0.0]}, r"row 0: lateral position -1e\+300 m is outside"),
        ({"y_m": [0.0, 1e300]}, r"row 1: lateral position 1e\+300 m is outside"),
    ],
)
def test_impossible_npz_is_refused_naming_the_file(tmp_path, arrays, message):
    path = _npz(tmp_path / "odd.npz", **arrays)
    with pytest.raises(WheelrailError, match=message) as info:
        read_npz(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_duplicate_npz_members_are_refused(tmp_path):
    """numpy.load (and a reader taking the last) would use whichever z_m.npy comes last in the archive."""
    path = _npz(tmp_path / "twice.npz")
    np.savez(tmp_path / "other.npz", z_m=np.full((2, 4), 5e-6))
    with zipfile.ZipFile(tmp_path / "other.npz") as source, zipfile.ZipFile(path, "a") as target:
        with pytest.warns(UserWarning, match="Duplicate name"):
            target.writestr("z_m.npy", source.read("z_m.npy"))
    with pytest.raises(WheelrailError, match=r"twice.npz: .*z_m.npy.*twice"):
        read_npz(path)
    # an archive holding both z_m and z_m.npy is as ambiguous
    path = _npz(tmp_path / "both.npz")
    with zipfile.ZipFile(tmp_path / "other.npz") as source, zipfile.ZipFile(path, "a") as target:
        target.writestr("z_m", source.read("z_m.npy"))
    with pytest.raises(WheelrailError, match=r"both.npz: .*z_m"):
        read_npz(path)
