"""Property-based tests of the two roughness readers: whatever the bytes, ``read_csv`` and ``read_npz``
return a RoughnessSet or raise one WheelrailError line naming the file, never another exception
(a sweep of 105 000 fuzzed files once found eight other exception types).

The inputs are arbitrary bytes, and valid files mutated byte by byte; for NPZ also archives whose members
are mutated before zipping, so that the CRC is right and the damage reaches the ``.npy`` header parser.
200 examples per property keep each test near 2-4 s; ``derandomize`` makes every CI run the same.
"""

import io
import tempfile
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness import RoughnessSet, read_csv, read_npz

pytestmark = pytest.mark.slow  # every test here takes seconds: `pytest -m 'not slow'` skips them

FUZZ = settings(
    max_examples=200,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)

VALID_CSV = (
    b"# kind: rail\n# description: fuzz seed\nx_m,y_mm=-2,y_mm=0,y_mm=2\n"
    b"0.000,1.5,-2,0.25\n0.001,2.5,-3,1\n0.002,0,0,-1\n0.003,4,1e1,2\n"
)


def _npy(array) -> bytes:
    stream = io.BytesIO()
    np.save(stream, np.asarray(array))
    return stream.getvalue()


VALID_MEMBERS = {
    "z_m.npy": _npy(np.arange(12.0).reshape(3, 4) * 1e-6),
    "dx_m.npy": _npy(np.float64(1e-3)),
    "y_m.npy": _npy([-2e-3, 0.0, 2e-3]),
    "kind.npy": _npy(np.str_("wheel")),
    "description.npy": _npy(np.str_("fuzz seed")),
}


def _zip(members: dict[str, bytes], method: int) -> bytes:
    stream = io.BytesIO()
    with zipfile.ZipFile(stream, "w", method) as archive:
        for name, data in members.items():
            archive.writestr(name, data)
    return stream.getvalue()


VALID_NPZ = {method: _zip(VALID_MEMBERS, method) for method in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED)}


# Bytes that matter to the parsers: CSV separators and quotes, the .npy header's Python-literal syntax.
SYNTAX = st.sampled_from(list(b"\x00\n\r,#:=\"'()[]{}-.e0123456789LU<>|"))


@st.composite
def mutated(draw, original: bytes, focus: int | None = None) -> bytes:
    """``original`` with 1-4 bytes replaced, inserted or deleted, a run of one digit inserted (up to 140 000,
    beyond the csv module's 131 072-character field limit) or the end cut off. ``focus``: mutate mostly
    within the first ``focus`` bytes (the .npy header)."""
    data = bytearray(original)
    # Positions from a seeded generator: hypothesis's integers favour small values, and the damage must
    # reach every part of a file (compressed data, the ZIP's central directory at the end).
    spot = draw(st.randoms(use_true_random=False))
    for _ in range(draw(st.integers(1, 4))):
        end = len(data) if focus is None or draw(st.booleans()) else min(focus, len(data))
        position = spot.randrange(max(1, end))
        action = draw(st.sampled_from(["replace"] * 4 + ["insert", "delete", "run", "truncate"]))
        byte = draw(st.one_of(SYNTAX, st.integers(0, 255)))
        if action == "replace" and data:
            data[position] = byte
        elif action == "insert":
            data[position:position] = bytes([byte])
        elif action == "delete" and data:
            del data[position]
        elif action == "run":
            digit = draw(st.sampled_from(list(b"0123456789")))  # a long number, the likely long cell
            data[position:position] = bytes([digit]) * draw(st.sampled_from([2, 1000, 140_000]))
        elif action == "truncate":
            del data[position:]
    return bytes(data)


def _check(reader, suffix: str, data: bytes) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"fuzzed{suffix}"
        path.write_bytes(data)
        try:
            result = reader(path)
        except WheelrailError as error:
            text = str(error)
            assert str(path) in text and "\n" not in text, text
        else:
            assert isinstance(result, RoughnessSet)


@FUZZ
@given(st.one_of(st.binary(max_size=400), mutated(VALID_CSV)))
def test_csv_reader_returns_a_set_or_one_error_line(data):
    _check(read_csv, ".csv", data)


@FUZZ
@given(st.one_of(st.binary(max_size=400), mutated(VALID_NPZ[zipfile.ZIP_STORED]), mutated(VALID_NPZ[8])))
def test_npz_reader_returns_a_set_or_one_error_line_for_damaged_archives(data):
    _check(read_npz, ".npz", data)


@st.composite
def archive_with_a_mutated_member(draw) -> bytes:
    name = draw(st.sampled_from(sorted(VALID_MEMBERS)))
    members = dict(VALID_MEMBERS)
    members[name] = draw(mutated(members[name], focus=128))
    return _zip(members, draw(st.sampled_from([zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED])))


@FUZZ
@given(archive_with_a_mutated_member())
def test_npz_reader_returns_a_set_or_one_error_line_for_damaged_members(data):
    _check(read_npz, ".npz", data)


def test_the_seeds_are_valid_files():
    # The mutations start from files the readers accept, so that they explore near-valid input.
    for reader, suffix, data in ((read_csv, ".csv", VALID_CSV), (read_npz, ".npz", VALID_NPZ[8])):
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / f"seed{suffix}"
            path.write_bytes(data)
            assert reader(path).n_lines == 3
