"""Damaged and oversized roughness files and grids: one WheelrailError line naming the file, nothing else,
and no allocation of what a file merely claims."""

import io
import tracemalloc
import zipfile

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.cache import wait_for_writes
from wheelrail.core.roughness import (
    MAX_LINE_CHARS,
    MAX_VALUES,
    RoughnessSet,
    lines_along_track,
    read_csv,
    read_npz,
    resample_lateral,
    to_model_grid,
)


def _npy(array) -> bytes:
    stream = io.BytesIO()
    np.save(stream, np.asarray(array))
    return stream.getvalue()


def _raw_npy(header: str, data: bytes = b"", version: int = 1) -> bytes:
    """A .npy member with a hand-written header (padded as numpy pads it) and raw data."""
    text = header.encode("latin1")
    length_size = 2 if version == 1 else 4
    text += b" " * (64 - (8 + length_size + len(text) + 1) % 64) + b"\n"
    return b"\x93NUMPY" + bytes([version, 0]) + len(text).to_bytes(length_size, "little") + text + data


GOOD_MEMBERS = {
    "z_m": _npy(np.zeros((2, 4))),
    "dx_m": _npy(np.float64(1e-3)),
    "y_m": _npy([0.0, 1e-3]),
    "kind": _npy(np.str_("rail")),
}


def _zip(path, members, method=zipfile.ZIP_STORED):
    """An NPZ whose members have correct CRCs, so that only the damage we put in is seen."""
    with zipfile.ZipFile(path, "w", method) as archive:
        for key, data in {**GOOD_MEMBERS, **members}.items():
            archive.writestr(f"{key}.npy", data)
    return path


def _refused(path, reader, match):
    with pytest.raises(WheelrailError, match=match) as info:
        reader(path)
    text = str(info.value)
    assert str(path) in text and "\n" not in text
    return text


# ----------------------------------------------------------------------------- CSV
def test_csv_cell_over_the_csv_field_limit(tmp_path):
    # A cell over csv.field_size_limit() (131 072 characters) escaped as _csv.Error.
    path = tmp_path / "long-cell.csv"
    path.write_text("x_m,y_mm=0\n0,1\n0.001," + "1" * 140_000 + "\n")
    _refused(path, read_csv, r"line 3: not a CSV row \(field larger than field limit")


def test_csv_line_over_the_line_limit_is_refused_before_it_is_read_whole(tmp_path):
    path = tmp_path / "long-line.csv"
    path.write_text("x_m,y_mm=0\n0,1\n0.001," + "1," * (MAX_LINE_CHARS // 2) + "1\n")
    _refused(path, read_csv, rf"line 3: longer than {MAX_LINE_CHARS:,} characters")


def test_csv_x_span_beyond_float_range(tmp_path):
    path = tmp_path / "span.csv"
    path.write_text("x_m,y_mm=0\n-1e308,1\n1e308,2\n")
    _refused(path, read_csv, "spans more than a float can hold")


def test_csv_folder_named_csv(tmp_path):
    folder = tmp_path / "folder.csv"
    folder.mkdir()
    _refused(folder, read_csv, "cannot read the file")


# ----------------------------------------------------------------------------- NPZ: container damage
def test_npy_file_named_npz(tmp_path):
    # numpy.load returned a bare array, which then failed as a context manager (TypeError).
    path = tmp_path / "array.npz"
    path.write_bytes(_npy(np.zeros(3)))
    _refused(path, read_npz, "not a readable NPZ roughness file")


def _patch_headers(path, local_offset, central_offset, value, mode):
    data = bytearray(path.read_bytes())
    for signature, offset in ((b"PK\x03\x04", local_offset), (b"PK\x01\x02", central_offset)):
        index = data.find(signature) + offset
        data[index] = value if mode == "set" else data[index] | value
    path.write_bytes(bytes(data))
    return path


def test_member_with_unsupported_compression_method(tmp_path):
    # The method field of the first member set to 99: NotImplementedError escaped.
    path = _patch_headers(_zip(tmp_path / "method.npz", {}), 8, 10, 99, "set")
    _refused(path, read_npz, "compression method is not supported")


def test_member_flagged_encrypted(tmp_path):
    # The encryption bit of the first member's flags: RuntimeError escaped.
    path = _patch_headers(_zip(tmp_path / "encrypted.npz", {}), 6, 8, 1, "or")
    _refused(path, read_npz, "encrypted")


def test_damaged_deflate_stream(tmp_path):
    # Eight bytes of the first member's compressed data inverted: zlib.error escaped.
    path = _zip(tmp_path / "deflate.npz", {}, zipfile.ZIP_DEFLATED)
    data = bytearray(path.read_bytes())
    start = 30 + int.from_bytes(data[26:28], "little") + int.from_bytes(data[28:30], "little")
    for index in range(start, start + 8):
        data[index] ^= 0xFF
    path.write_bytes(bytes(data))
    _refused(path, read_npz, "not a readable NPZ roughness file")


# ----------------------------------------------------------------------------- NPZ: .npy header damage
@pytest.mark.parametrize(
    "header",
    [
        "{[]: 1}",  # TypeError (unhashable) escaped from the header parser
        "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 4), }}",  # tokenize.TokenError escaped
        "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 4), } '''",  # tokenize.TokenError escaped
        "{'descr': '|O', 'fortran_order': False, 'shape': (2, 4), }",  # pickled objects
        "{'descr': [('a', '<f8')], 'fortran_order': False, 'shape': (2, 4), }",  # a structured dtype
        "{'descr': '<f8', 'fortran_order': False, 'shape': (-2, 4), }",
    ],
)
def test_damaged_npy_header(tmp_path, header):
    path = _zip(tmp_path / "header.npz", {"z_m": _raw_npy(header, bytes(64))})
    _refused(path, read_npz, "not a readable NPZ|dtype|negative shape")


def test_one_element_dx_array_is_read_as_the_spacing(tmp_path):
    # dx_m stored as a one-element array: float() of it raised TypeError under numpy 2.
    path = _zip(tmp_path / "dx.npz", {"dx_m": _npy([2e-3])})
    assert read_npz(path).dx == 2e-3


def test_header_claiming_a_huge_shape_is_refused_with_the_limit(tmp_path):
    # numpy.load tried to allocate 2.9 TiB and raised MemoryError.
    header = "{'descr': '<f8', 'fortran_order': False, 'shape': (100000000000, 4), }"
    path = _zip(tmp_path / "huge.npz", {"z_m": _raw_npy(header)})
    text = _refused(path, read_npz, "member z_m of shape")
    assert "3.2e+03 GB" in text and f"{MAX_VALUES:,}" in text  # 4e11 heights x 8 bytes


def test_header_claiming_a_huge_header_is_refused_before_reading_it(tmp_path):
    # A version-2 header declares its length in 4 bytes; numpy reads all of it before checking the size.
    data = b"\x93NUMPY\x02\x00" + (4_000_000_000).to_bytes(4, "little") + b"{"
    path = _zip(tmp_path / "long-header.npz", {"z_m": data})
    _refused(path, read_npz, r"declares a 4000000000-byte .npy header \(at most 10000 read\)")


def test_declared_size_over_the_limit_allocates_nothing(tmp_path):
    # The old reader allocated the declared array (here 160 MB) before finding the data missing; a
    # 1.56 MB archive of zeros declaring 200 M heights made it peak at 6.4 GB. Python's allocation tracer
    # also sees numpy's data buffers; 10 MB is far above the reader's own few kB and far below 160 MB.
    header = f"{{'descr': '<f8', 'fortran_order': False, 'shape': (1, {MAX_VALUES + 1}), }}"
    path = _zip(tmp_path / "bomb.npz", {"z_m": _raw_npy(header, bytes(1024))}, zipfile.ZIP_DEFLATED)
    wait_for_writes()  # another test's cache write (a thread of its own) would be traced too
    tracemalloc.start()
    try:
        with pytest.raises(WheelrailError, match="more than the limit"):
            read_npz(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 10e6


def test_member_shorter_or_longer_than_its_header(tmp_path):
    short = _zip(tmp_path / "short.npz", {"z_m": _npy(np.zeros((2, 4)))[:-8]})
    _refused(short, read_npz, "holds 56 of the 64 data bytes its header declares")
    long = _zip(tmp_path / "long.npz", {"z_m": _npy(np.zeros((2, 4))) + b"\0"})
    _refused(long, read_npz, "more data than its header declares")


# ----------------------------------------------------------------------------- model grid size
def _coarse_set(dx, n_lines=1, kind="rail"):
    y = np.arange(n_lines) * 2e-3
    return RoughnessSet(heights=np.full((n_lines, 2), 1e-6), dx=dx, y=y, kind=kind)


def test_csv_with_a_1e6_m_step_is_refused_before_resampling_to_1_mm(tmp_path):
    # Resampling 1e6 m of data to the 1 mm grid tried to allocate 8 GB for the one line. The reader now refuses
    # the 1e6 m spacing itself; a set made in memory still meets the grid's own limit.
    path = tmp_path / "coarse.csv"
    path.write_text("x_m,y_mm=0\n0,1\n1000000,2\n")
    with pytest.raises(WheelrailError, match=r"coarse.csv: sample spacing 1e\+06 m is outside"):
        read_csv(path)
    coarse = _coarse_set(1e6, n_lines=1)
    with pytest.raises(WheelrailError, match=r"would hold 1e\+09 heights \(8 GB as float64\)"):
        to_model_grid(coarse, 1e-3)


@pytest.mark.parametrize("kind", ["rail", "wheel"])
def test_resampling_refuses_grids_over_the_limit(kind):
    with pytest.raises(WheelrailError, match="more than the limit of 20,000,000"):
        to_model_grid(_coarse_set(100.0, kind=kind), 1e-6)
    with pytest.raises(WheelrailError, match="roughness width at lines"):
        resample_lateral(_coarse_set(1e-3, n_lines=2), 1e-12)


def test_lines_along_a_very_long_run_are_refused_with_the_figure():
    wheel = _coarse_set(1e-3, kind="wheel")
    with pytest.raises(WheelrailError, match=r"along a run of 1e\+09 m at dx 0.001 m would hold 1e\+12 heights"):
        lines_along_track(wheel, [0], 1e9, 1e-3)
    with pytest.raises(WheelrailError, match="would hold"):
        lines_along_track(wheel, [0], 1e300, 1e-300)  # length / dx overflows to inf: still one clear line
