"""The NPZ roughness format: ``z_m`` (lines x samples, m), ``dx_m`` (scalar, m), ``y_m`` (lateral positions,
m), ``kind`` and ``description`` (text).

The reader does not hand the file to ``numpy.load``: a damaged or hostile archive could then raise any of
a dozen exception types (zlib, zipfile, the ``.npy`` header parser) or make numpy allocate whatever shape a
header claims (a 1.56 MB archive of zeros decompresses to gigabytes). Instead it opens the ZIP itself and,
for each member it needs, reads the ``.npy`` header (``numpy.lib.format.read_array_header_1_0/2_0``) from
at most :data:`MAX_HEADER_BYTES` bytes, checks the dtype and the declared size against the limits
(:data:`~wheelrail.core.roughness.model.MAX_VALUES` numbers, :data:`MAX_TEXT_CHARS` characters of text), and
only then reads exactly the declared number of bytes. Every failure becomes one ``WheelrailError`` line
naming the file.
"""

from __future__ import annotations

import io
import math
import os
import struct
import tokenize
import zipfile
import zlib
from pathlib import Path

import numpy as np
import numpy.lib.format as npy_format

from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.atomic import atomic_write
from wheelrail.core.roughness.model import KINDS, RoughnessSet, check_file_geometry, check_value_count

try:  # zipfile reads LZMA members when the interpreter has lzma; its errors are then LZMAError
    from lzma import LZMAError
except ImportError:  # pragma: no cover - Python built without lzma
    LZMAError = OSError

MAX_HEADER_BYTES = 10_000  # bytes of one .npy header (numpy's own default limit for untrusted files)
MAX_TEXT_CHARS = 100_000  # characters of the kind and description members
_TEXT_BYTES = 4 * MAX_TEXT_CHARS  # numpy stores text as UCS-4
_REQUIRED = ("z_m", "dx_m", "y_m", "kind")
_NUMERIC_KINDS = "fiu"  # float, signed and unsigned integer dtypes
_TEXT_KINDS = "biufUS"  # the description was always read with str(); keep accepting what that accepted
_HEADER_LENGTH_FORMAT = {(1, 0): "<H", (2, 0): "<I"}
_HEADER_READERS = {(1, 0): npy_format.read_array_header_1_0, (2, 0): npy_format.read_array_header_2_0}
# Everything that reading a damaged ZIP/.npy member can raise (found by fuzzing, tests/unit/test_roughness_fuzz.py)
_DAMAGED = (
    OSError,
    EOFError,
    ValueError,
    TypeError,
    KeyError,
    OverflowError,
    SyntaxError,
    RuntimeError,  # zipfile: "File ... is encrypted, password required"
    NotImplementedError,  # zipfile: an unsupported compression method
    RecursionError,
    tokenize.TokenError,
    zipfile.BadZipFile,
    zipfile.LargeZipFile,
    zlib.error,
    LZMAError,
    struct.error,
)


def write_npz(roughness: RoughnessSet, path: str | os.PathLike, *, dtype=np.float64) -> Path:
    """Write a set in the NPZ format (``z_m``, ``dx_m``, ``y_m``, ``kind``, ``description``).

    ``dtype=numpy.float32`` halves the file size (relative precision 6e-8, far below any measurement).
    """
    path = Path(path)

    def write(stream) -> None:
        np.savez_compressed(
            stream,
            z_m=roughness.heights.astype(dtype),
            dx_m=np.float64(roughness.dx),
            y_m=roughness.y.astype(np.float64),
            kind=np.str_(roughness.kind),
            description=np.str_(roughness.description),
        )

    atomic_write(path, write)
    return path


def _one_line(error: BaseException) -> str:
    text = " ".join(str(error).split()) or type(error).__name__
    return text if len(text) <= 200 else text[:197] + "..."


def _read_header(stream, key: str):
    """Shape, Fortran order and dtype of one ``.npy`` member, reading at most MAX_HEADER_BYTES of header."""
    version = npy_format.read_magic(stream)
    if version not in _HEADER_READERS:
        raise WheelrailError(f"member {key} has .npy format version {version}; versions 1.0 and 2.0 are read")
    length_format = _HEADER_LENGTH_FORMAT[version]
    length_bytes = stream.read(struct.calcsize(length_format))
    (length,) = struct.unpack(length_format, length_bytes)
    if length > MAX_HEADER_BYTES:
        raise WheelrailError(f"member {key} declares a {length}-byte .npy header (at most {MAX_HEADER_BYTES} read)")
    header = stream.read(length)
    if len(header) != length:
        raise WheelrailError(f"member {key} ends inside its .npy header")
    reader = _HEADER_READERS[version]
    return reader(io.BytesIO(length_bytes + header), max_header_size=MAX_HEADER_BYTES)


def _read_member(archive: zipfile.ZipFile, key: str, *, text: bool = False) -> np.ndarray:
    """The array of member ``key``, refused before reading its data if its header breaks a limit.

    Numeric members may hold at most MAX_VALUES numbers, text members at most MAX_TEXT_CHARS characters.
    """
    kinds = _TEXT_KINDS if text else _NUMERIC_KINDS
    names = archive.namelist()
    member = key if key in names else f"{key}.npy"  # the names numpy.load accepts, in its order
    with archive.open(member) as stream:
        shape, fortran_order, dtype = _read_header(stream, key)
        if dtype.hasobject or dtype.fields is not None or dtype.subdtype is not None or dtype.kind not in kinds:
            raise WheelrailError(f"member {key} has dtype {dtype.str!r}, which a roughness file does not use")
        if any(size < 0 for size in shape):
            raise WheelrailError(f"member {key} declares a negative shape {shape}")
        count = math.prod(shape)
        size = count * dtype.itemsize
        if text and size > _TEXT_BYTES:
            raise WheelrailError(f"member {key} declares {size:.4g} bytes of text, more than {_TEXT_BYTES:,}")
        if not text:
            check_value_count(count, f"member {key} of shape {shape}")
        data = stream.read(size)
        if len(data) != size:
            raise WheelrailError(f"member {key} holds {len(data)} of the {size} data bytes its header declares")
        if stream.read(1):  # also reaches the member's end, where zipfile checks its CRC
            raise WheelrailError(f"member {key} holds more data than its header declares")
    if count == 0:
        return np.empty(shape, dtype=dtype)
    return np.frombuffer(data, dtype=dtype).reshape(shape, order="F" if fortran_order else "C")


def _read_members(path: Path) -> dict[str, np.ndarray]:
    with zipfile.ZipFile(path) as archive:
        names = [name.removesuffix(".npy") for name in archive.namelist()]
        twice = sorted({name for name in names if names.count(name) > 1})
        if twice:  # numpy.load takes whichever comes last: the file means two things
            raise WheelrailError(
                f"the archive holds member(s) {', '.join(f'{name}.npy' for name in twice)} twice (as written, "
                "or as both 'name' and 'name.npy'): which one is meant is not known"
            )
        present = set(names)
        missing = [key for key in _REQUIRED if key not in present]
        if missing:
            raise WheelrailError(
                f"missing array(s) {', '.join(missing)}; an NPZ roughness file needs z_m, dx_m, "
                "y_m, kind (and description)"
            )
        arrays = {
            "z_m": _read_member(archive, "z_m"),
            "dx_m": _read_member(archive, "dx_m"),
            "y_m": _read_member(archive, "y_m"),
            "kind": _read_member(archive, "kind", text=True),
        }
        if "description" in present:
            arrays["description"] = _read_member(archive, "description", text=True)
    return arrays


def _text(array: np.ndarray, key: str) -> str:
    text = str(array)
    if len(text) > MAX_TEXT_CHARS:
        raise WheelrailError(f"{key} holds {len(text):,} characters, more than {MAX_TEXT_CHARS:,}")
    return text


def _to_set(arrays: dict[str, np.ndarray]) -> RoughnessSet:
    """Check the member arrays and build the set (errors without the file name; the caller adds it)."""
    z, dx, y = arrays["z_m"], arrays["dx_m"], arrays["y_m"]
    kind = _text(arrays["kind"], "kind")
    description = _text(arrays["description"], "description") if "description" in arrays else ""
    if dx.size != 1:
        raise WheelrailError(f"dx_m must be a scalar spacing in m, got shape {dx.shape}")
    if z.ndim != 2:
        raise WheelrailError(f"z_m must be 2-D (lines x samples, m), got shape {z.shape}")
    if kind not in KINDS:
        raise WheelrailError(f"unknown kind {kind!r}, allowed: {', '.join(KINDS)}")
    if y.ndim != 1 or y.shape[0] != z.shape[0]:
        raise WheelrailError(f"y_m must hold one lateral position per line ({z.shape[0]}), got {y.shape}")
    if z.shape[1] < 2:
        raise WheelrailError(f"needs at least 2 samples per line, got {z.shape[1]}")
    finite = np.isfinite(z)
    if not finite.all():
        row, col = np.argwhere(~finite)[0]
        raise WheelrailError(f"z_m must be finite, got {z[row, col]} at line row {row}, sample {col}")
    if y.shape[0] > 1 and np.unique(y).size != y.size:
        raise WheelrailError(f"duplicate lateral positions in y_m: {y.tolist()}")
    try:
        dx_value = float(dx.reshape(-1)[0])
    except (TypeError, ValueError):
        raise WheelrailError(f"dx_m must be a spacing in m, got {dx!r}") from None
    if math.isfinite(dx_value) and dx_value > 0:  # else the data model's own message
        check_file_geometry(dx_value, y, [f"y_m row {row}" for row in range(y.shape[0])])
    order = np.argsort(y, kind="stable")
    if np.any(order != np.arange(order.size)):
        z, y = z[order], y[order]
    return RoughnessSet(heights=z, dx=float(dx.reshape(-1)[0]), y=y, kind=kind, description=description)


def read_npz(path: str | os.PathLike, *, label: str | None = None) -> RoughnessSet:
    """Read an NPZ roughness file (``z_m``, ``dx_m``, ``y_m``, ``kind``, ``description``).

    Raises
    ------
    WheelrailError
        One line naming the file for a missing file, anything that is not a readable ZIP of ``.npy``
        members, a missing member, a member whose header declares more than the limits of this module, and
        any value the data model refuses.
    """
    path = Path(path)
    name = str(path) if label is None else label  # what messages call the file
    try:
        arrays = _read_members(path)
        return _to_set(arrays)
    except FileNotFoundError:
        raise WheelrailError(f"{name}: roughness file not found") from None
    except WheelrailError as error:
        raise WheelrailError(f"{name}: {error}") from None
    except _DAMAGED as error:
        raise WheelrailError(f"{name}: not a readable NPZ roughness file ({_one_line(error)})") from None
