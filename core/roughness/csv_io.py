"""The CSV roughness format, the one a user writes by hand or exports from a spreadsheet.

Optional leading ``# key: value`` comment lines (``# kind: rail``, ``# description: ...``); a header row
``x_m,y_mm=-6,y_mm=-4,...``; then one row per sample: x in m (uniform spacing), heights in µm. Only this
format uses µm for heights and mm for lateral positions; everything inside is in m.

A CSV whose largest height is below 1e-3 µm (1 nm) is taken to hold metres instead of µm and is refused;
one above 10 000 µm is refused by the data model (``MAX_HEIGHT``). The reader streams the file: a line may
hold at most :data:`MAX_LINE_CHARS` characters, and the data at most
:data:`~wheelrail.core.roughness.model.MAX_VALUES` heights, so that a damaged or huge file is refused
before it fills the memory.
"""

from __future__ import annotations

import csv
import math
import os
import re
from array import array
from pathlib import Path

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.atomic import atomic_write
from wheelrail.core.roughness.model import KINDS, MAX_HEIGHT, RoughnessSet, check_file_geometry, check_value_count

MAX_LINE_CHARS = 1_000_000  # characters in one CSV line (a row of 1 000 lines takes about 25 000)
_MIN_CSV_PEAK_UM = 1e-3  # µm; a set whose largest |height| is below 1 nm was written in metres
_UM = 1e-6  # m per µm
_MM = 1e-3  # m per mm
_SPACING_RTOL = 1e-3  # relative tolerance on uniform x spacing (CSV files round x to a few digits)
# One column in metres among µm columns: its rms is ~1e6 times below the others'. Real lines across one rail
# head or wheel tread differ by at most a few times in rms (1.02 to 1.6 in the bundled sets); a nonzero
# column 1e4 times (80 dB) below the median column is two orders from each case. An all-zero column (a
# deliberately smooth line) is left alone.
_METRES_COLUMN_RATIO = 1e-4
# A decimal number as people and spreadsheets write it: Python's float() also reads "1_0" as 10 and
# non-ASCII digits; inf and nan are matched here to be refused as not finite, with their own message
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|[+-]?(?:inf|infinity|nan)", re.IGNORECASE)


def write_csv(roughness: RoughnessSet, path: str | os.PathLike) -> Path:
    """Write a set in the CSV format (x in m, heights in µm, lateral positions in mm).

    Numbers are written with ``repr`` (shortest exact float), so reading back gives the same heights up
    to the rounding of the µm <-> m conversion (a few ulp).
    """
    path = Path(path)

    def write(stream) -> None:
        stream.write(f"# kind: {roughness.kind}\n")
        description = " ".join(roughness.description.split())
        if description:
            stream.write(f"# description: {description}\n")
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow(["x_m"] + [f"y_mm={repr(float(y / _MM))}" for y in roughness.y])
        heights_um = roughness.heights / _UM
        for i in range(roughness.n_samples):
            writer.writerow([repr(float(i * roughness.dx))] + [repr(float(v)) for v in heights_um[:, i]])

    atomic_write(path, write, "w", newline="", encoding="utf-8")
    return path


def _parse_float(text: str, where: str, what: str) -> float:
    if not _NUMBER.fullmatch(text.strip()):
        raise WheelrailError(f"{where}: {what} must be a number, got {text.strip()!r}")
    return float(text)


def _lines(stream, name: str):
    """(line number, stripped text) of every line, refusing a line longer than MAX_LINE_CHARS."""
    number = 0
    while raw := stream.readline(MAX_LINE_CHARS + 1):
        number += 1
        if len(raw) > MAX_LINE_CHARS and raw[-1] not in "\r\n":
            raise WheelrailError(f"{name}, line {number}: longer than {MAX_LINE_CHARS:,} characters")
        yield number, raw.strip()


def _cells(text: str, where: str) -> list[str]:
    try:
        return next(csv.reader([text]))
    except csv.Error as error:  # e.g. a cell over csv.field_size_limit() (131 072) characters
        raise WheelrailError(f"{where}: not a CSV row ({error})") from None


def _read_head(lines, name: str) -> tuple[dict[str, str], list[str], int]:
    """Metadata of the leading ``# key: value`` lines, the header cells and the header's line number."""
    metadata: dict[str, str] = {}
    for number, text in lines:
        if not text:
            continue
        if text.startswith("#"):
            key, sep, value = text[1:].partition(":")
            if sep:
                metadata[key.strip().lower()] = value.strip()
            continue
        return metadata, [cell.strip() for cell in _cells(text, f"{name}, line {number}")], number
    raise WheelrailError(f"{name}: missing header row 'x_m,y_mm=<mm>,...' (file has no data)")


def _lateral_positions_mm(header: list[str], where: str) -> list[float]:
    """The lateral positions (mm) of the header ``x_m,y_mm=<mm>,...``, checked."""
    if header[0] != "x_m":
        raise WheelrailError(f"{where}: header must start with 'x_m', got {header[0]!r}")
    if len(header) < 2:
        raise WheelrailError(f"{where}: header needs at least one 'y_mm=<lateral position in mm>' column")
    y_mm: list[float] = []
    seen: dict[float, int] = {}
    for column, cell in enumerate(header[1:], start=2):
        key, sep, value = cell.partition("=")
        if key.strip() != "y_mm" or not sep:
            raise WheelrailError(f"{where}, column {column}: expected 'y_mm=<lateral position in mm>', got {cell!r}")
        position = _parse_float(value, f"{where}, column {column}", "the lateral position y_mm")
        if not math.isfinite(position):
            raise WheelrailError(f"{where}, column {column}: lateral position must be finite, got {value!r}")
        if position in seen:
            raise WheelrailError(
                f"{where}: duplicate lateral position y_mm={position:g} in columns {seen[position]} and {column}"
            )
        seen[position] = column
        y_mm.append(position)
    return y_mm


def _read_rows(lines, name: str, n_cols: int) -> tuple[np.ndarray, list[int]]:
    """The data rows as a (rows, columns) array and the file line number of each row."""
    values = array("d")
    numbers: list[int] = []
    for number, text in lines:
        if not text:
            continue
        where = f"{name}, line {number}"
        if text.startswith("#"):
            raise WheelrailError(f"{where}: comment lines are allowed only before the header")
        cells = _cells(text, where)
        if len(cells) != n_cols:
            raise WheelrailError(f"{where}: ragged row with {len(cells)} cells, header has {n_cols}")
        check_value_count((len(numbers) + 1) * (n_cols - 1), f"{name} up to line {number}")
        for column, cell in enumerate(cells):
            what = "x_m" if column == 0 else f"height (µm) in column {column + 1}"
            value = _parse_float(cell, where, what)
            if not math.isfinite(value):
                raise WheelrailError(f"{where}: {what} must be finite, got {cell.strip()!r}")
            values.append(value)
        numbers.append(number)
    if len(numbers) < 2:
        raise WheelrailError(f"{name}: needs at least 2 samples (data rows), got {len(numbers)}")
    return np.frombuffer(values, dtype=float).reshape(len(numbers), n_cols), numbers


def _spacing(x: np.ndarray, numbers: list[int], name: str) -> float:
    """The uniform spacing of the x column, m."""
    with np.errstate(over="ignore", invalid="ignore"):
        dx = (x[-1] - x[0]) / (len(x) - 1)
        steps = np.diff(x)
    if not dx > 0:
        raise WheelrailError(f"{name}: x_m must increase down the file, got {x[0]:g} m then {x[-1]:g} m")
    if not math.isfinite(dx) or not np.all(np.isfinite(steps)):
        raise WheelrailError(f"{name}: x_m from {x[0]:g} m to {x[-1]:g} m spans more than a float can hold")
    bad = np.flatnonzero(np.abs(steps - dx) > _SPACING_RTOL * dx)
    if bad.size:
        i = int(bad[0])
        raise WheelrailError(
            f"{name}, line {numbers[i + 1]}: non-uniform x spacing, step {steps[i]:g} m where the mean "
            f"spacing is {dx:g} m (allowed deviation {_SPACING_RTOL:g} relative)"
        )
    return float(dx)


def _check_heights_um(heights_um: np.ndarray, numbers: list[int], name: str) -> None:
    peak_um = float(np.max(np.abs(heights_um)))
    if peak_um > MAX_HEIGHT / _UM:
        i, j = np.unravel_index(int(np.argmax(np.abs(heights_um))), heights_um.shape)
        raise WheelrailError(
            f"{name}, line {numbers[j]}: height {heights_um[i, j]:g} µm exceeds ±{MAX_HEIGHT / _UM:g} µm "
            "(10 mm); heights must be in µm"
        )
    if 0 < peak_um < _MIN_CSV_PEAK_UM:
        raise WheelrailError(
            f"{name}: largest height is {peak_um:g} µm (below 1 nm): the file seems to hold metres, "
            "heights must be in µm"
        )


def _check_columns_um(heights_um: np.ndarray, y_mm: list[float], name: str) -> None:
    """Refuse a column whose rms is far below the others' (``_METRES_COLUMN_RATIO``): written in metres."""
    rms = np.sqrt(np.mean(heights_um**2, axis=1))
    nonzero = rms[rms > 0]
    if nonzero.size < 2:
        return
    typical = float(np.median(nonzero))
    for column, value in enumerate(rms.tolist(), start=2):
        if 0 < value < _METRES_COLUMN_RATIO * typical:
            raise WheelrailError(
                f"{name}, column {column} (y_mm={y_mm[column - 2]:g}): rms height {value:.3g} µm, "
                f"{typical / value:.2g} times below the columns' median {typical:.3g} µm: the column seems to "
                "hold metres, heights must be in µm"
            )


def _read_text(path: Path, name: str):
    """Metadata, lateral positions (mm), data rows and their line numbers of a CSV file."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as stream:
            lines = _lines(stream, name)
            metadata, header, header_line = _read_head(lines, name)
            y_mm = _lateral_positions_mm(header, f"{name}, line {header_line}")
            values, numbers = _read_rows(lines, name, len(header))
    except UnicodeDecodeError:
        raise WheelrailError(f"{name}: not a text CSV file (cannot decode as UTF-8)") from None
    except FileNotFoundError:
        raise WheelrailError(f"{name}: roughness file not found") from None
    except OSError as error:
        raise WheelrailError(f"{name}: cannot read the file ({error.strerror or error})") from None
    return metadata, y_mm, values, numbers


def read_csv(path: str | os.PathLike, *, kind: str | None = None, label: str | None = None) -> RoughnessSet:
    """Read a CSV roughness file (format in the module docstring).

    Parameters
    ----------
    path : path-like
        The file. Metadata comes from leading ``# key: value`` lines (``kind``, ``description``).
    kind : {"rail", "wheel"}, optional
        Used when the file has no ``# kind:`` line; without either, ``rail`` (non-periodic) is assumed and
        the description says so.
    label : str, optional
        What messages call the file (default its path).

    Raises
    ------
    WheelrailError
        One line naming the file, the line number and the problem for a missing or malformed header,
        ragged rows, non-numeric/NaN/inf cells, fewer than 2 samples, non-uniform x spacing, duplicate
        lateral positions, heights that cannot be µm, an unknown kind, a line over MAX_LINE_CHARS
        characters or more than MAX_VALUES heights.
    """
    path = Path(path)
    name = str(path) if label is None else label
    metadata, y_mm, values, numbers = _read_text(path, name)
    dx = _spacing(values[:, 0], numbers, name)
    heights_um = values[:, 1:].T
    try:
        check_file_geometry(dx, np.asarray(y_mm) * _MM, [f"column {i + 2} (y_mm={y:g})" for i, y in enumerate(y_mm)])
    except WheelrailError as error:
        raise WheelrailError(f"{name}: {error}") from None
    _check_heights_um(heights_um, numbers, name)
    _check_columns_um(heights_um, y_mm, name)
    file_kind = metadata.get("kind")
    description = metadata.get("description", "")
    if file_kind is None:
        file_kind = kind if kind is not None else "rail"
        if kind is None:
            description = f"{description}; kind not given in file, rail assumed".lstrip("; ")
    if file_kind not in KINDS:
        raise WheelrailError(f"{name}: unknown kind {file_kind!r}, allowed: {', '.join(KINDS)}")
    order = np.argsort(y_mm)
    try:
        return RoughnessSet(
            heights=heights_um[order] * _UM,
            dx=dx,
            y=np.asarray(y_mm)[order] * _MM,
            kind=file_kind,
            description=description or f"read from {path.name}",
        )
    except WheelrailError as error:
        raise WheelrailError(f"{name}: {error}") from None
