"""Roughness data: the data model, import/export, preprocessing and roughness-specific analyses.

A roughness set holds the heights of several parallel longitudinal lines of a rail or a wheel running
surface (Pieringer, Kropp & Thompson 2011, section 3.1 and Figure 8; SPEC.md §3). Everything is SI inside:
heights and positions in m. Only the CSV file format uses µm for heights and mm for lateral positions.

File formats (SPEC.md §3), exactly these two:

* CSV: optional leading ``# key: value`` comment lines (``# kind: rail``, ``# description: ...``); a header
  row ``x_m,y_mm=-6,y_mm=-4,...``; then one row per sample: x in m (uniform spacing), heights in µm.
* NPZ: ``z_m`` (lines x samples, m), ``dx_m`` (scalar, m), ``y_m`` (lateral positions, m), ``kind``,
  ``description``.

Heights must lie within ``MAX_HEIGHT`` = 10 mm of zero. Wheel/rail roughness is at most some hundred µm
(corrugation tens of µm, paper section 1: "from below 1 up to 50 µm"), so a CSV value above 10 000 "µm" is a
unit mistake (mm or m read as µm), not roughness. Conversely a CSV whose largest height is below 1e-3 µm
(1 nm) is taken to hold metres instead of µm and is rejected too.
"""

from __future__ import annotations

import csv
import math
import os
import zipfile
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

import numpy as np
import scipy.signal

from wheelrail.core.atomic import atomic_write
from wheelrail.core.errors import WheelrailError
from wheelrail.core.spectra import band_coherence, third_octave_bands, third_octave_levels

KINDS = ("rail", "wheel")
MAX_HEIGHT = 10e-3  # m; see the module docstring for why larger heights are refused
_MIN_CSV_PEAK_UM = 1e-3  # µm; a set whose largest |height| is below 1 nm was written in metres
_UM = 1e-6  # m per µm
_MM = 1e-3  # m per mm
_SPACING_RTOL = 1e-3  # relative tolerance on uniform x spacing (CSV files round x to a few digits)
SAMPLE_DATA_PACKAGE = "wheelrail.sample_data"


# --------------------------------------------------------------------------------------------------
# Data model
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True, eq=False)
class RoughnessSet:
    """Roughness heights on parallel longitudinal lines (paper section 3.1, Figure 8).

    Attributes
    ----------
    heights : numpy.ndarray
        z[row, sample], roughness heights in m, shape (lines, samples); read-only float64 copy.
        Row 0 is the line with the most negative lateral position.
    dx : float
        Longitudinal sample spacing, m (uniform).
    y : numpy.ndarray
        Lateral position of each line (row), m, strictly increasing; the centre line is at (or nearest
        to) y = 0.
    kind : str
        ``"rail"`` or ``"wheel"``. Wheel data is one circumference and is treated as periodic.
    description : str
        Free text: what the data is and where it comes from (provenance).

    Notes
    -----
    Lines are numbered -M..M as in the paper's Figure 8: number 0 is the row whose lateral position is
    closest to y = 0, and number n is row ``centre_row + n`` (see :meth:`row_of_line`).
    """

    heights: np.ndarray
    dx: float
    y: np.ndarray
    kind: str
    description: str = ""

    def __post_init__(self) -> None:
        where = "RoughnessSet"
        if self.kind not in KINDS:
            raise WheelrailError(f"{where}.kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        try:
            dx = float(self.dx)
        except (TypeError, ValueError):
            raise WheelrailError(f"{where}.dx must be a spacing in m, got {self.dx!r}") from None
        if not math.isfinite(dx) or dx <= 0:
            raise WheelrailError(f"{where}.dx must be a positive finite spacing in m, got {self.dx!r}")
        try:
            heights = np.array(self.heights, dtype=float)
            y = np.array(self.y, dtype=float).reshape(-1)
        except (TypeError, ValueError) as error:
            raise WheelrailError(f"{where}: heights and y must be numeric arrays ({error})") from None
        if heights.ndim == 1:
            heights = heights[np.newaxis, :]
        if heights.ndim != 2:
            raise WheelrailError(f"{where}.heights must be 2-D (lines x samples), got shape {heights.shape}")
        n_lines, n_samples = heights.shape
        if n_lines < 1 or n_samples < 2:
            raise WheelrailError(f"{where}.heights needs at least 1 line and 2 samples, got shape {heights.shape}")
        if not np.all(np.isfinite(heights)):
            row, col = np.argwhere(~np.isfinite(heights))[0]
            raise WheelrailError(f"{where}.heights must be finite, got {heights[row, col]} at row {row}, sample {col}")
        peak = float(np.max(np.abs(heights)))
        if peak > MAX_HEIGHT:
            raise WheelrailError(
                f"{where}.heights must be within ±{MAX_HEIGHT * 1e3:g} mm (roughness, in m), got {peak:g} m"
            )
        if y.shape != (n_lines,):
            raise WheelrailError(f"{where}.y must hold one position per line ({n_lines}), got {y.shape[0]}")
        if not np.all(np.isfinite(y)):
            raise WheelrailError(f"{where}.y must be finite lateral positions in m, got {y.tolist()}")
        if n_lines > 1 and not np.all(np.diff(y) > 0):
            raise WheelrailError(f"{where}.y must be strictly increasing without duplicates (m), got {y.tolist()}")
        heights.setflags(write=False)
        y.setflags(write=False)
        object.__setattr__(self, "heights", heights)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "dx", dx)
        object.__setattr__(self, "description", str(self.description))

    # -- shape and positions ------------------------------------------------------------------------
    @property
    def n_lines(self) -> int:
        """Number of lines (rows)."""
        return self.heights.shape[0]

    @property
    def n_samples(self) -> int:
        """Number of samples per line."""
        return self.heights.shape[1]

    @property
    def length(self) -> float:
        """Length covered by the data, ``n_samples * dx``, m (the circumference for a wheel)."""
        return self.n_samples * self.dx

    @property
    def x(self) -> np.ndarray:
        """Longitudinal sample positions ``i * dx``, m."""
        return np.arange(self.n_samples) * self.dx

    @property
    def periodic(self) -> bool:
        """True for wheel data (one circumference, wraps around)."""
        return self.kind == "wheel"

    @property
    def centre_row(self) -> int:
        """Row of line 0: the line whose lateral position is closest to y = 0."""
        return int(np.argmin(np.abs(self.y)))

    @property
    def line_numbers(self) -> np.ndarray:
        """Line number (paper's Figure 8: -M..M) of every row."""
        return np.arange(self.n_lines) - self.centre_row

    @property
    def lateral_spacing(self) -> float:
        """Mean lateral spacing of the lines, m (0 for a single line)."""
        return float(np.mean(np.diff(self.y))) if self.n_lines > 1 else 0.0

    def row_of_line(self, line: int) -> int:
        """Row index of line number ``line`` (0 = centre line, paper's Figure 8)."""
        if isinstance(line, bool) or int(line) != line:
            raise WheelrailError(f"line number must be an integer, got {line!r}")
        row = self.centre_row + int(line)
        if not 0 <= row < self.n_lines:
            numbers = self.line_numbers
            raise WheelrailError(f"line {line} is not in this set; lines run from {numbers[0]} to {numbers[-1]}")
        return row

    def line_of_row(self, row: int) -> int:
        """Line number (paper's Figure 8) of row index ``row``."""
        if not 0 <= int(row) < self.n_lines:
            raise WheelrailError(f"row {row} is not in this set; rows run from 0 to {self.n_lines - 1}")
        return int(row) - self.centre_row

    def line(self, line: int) -> np.ndarray:
        """Heights of line number ``line``, m (read-only view)."""
        return self.heights[self.row_of_line(line)]

    def with_heights(
        self, heights: np.ndarray, *, dx: float | None = None, y=None, note: str | None = None
    ) -> RoughnessSet:
        """A new set with other heights (and optionally grid), appending ``note`` to the description."""
        description = self.description if not note else f"{self.description}; {note}".lstrip("; ")
        return replace(
            self,
            heights=heights,
            dx=self.dx if dx is None else dx,
            y=self.y if y is None else y,
            description=description,
        )


# --------------------------------------------------------------------------------------------------
# Import / export
# --------------------------------------------------------------------------------------------------
def write_csv(roughness: RoughnessSet, path: str | os.PathLike) -> Path:
    """Write a set in the CSV format of SPEC.md §3 (x in m, heights in µm, lateral positions in mm).

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


def write_npz(roughness: RoughnessSet, path: str | os.PathLike, *, dtype=np.float64) -> Path:
    """Write a set in the NPZ format of SPEC.md §3 (``z_m``, ``dx_m``, ``y_m``, ``kind``, ``description``).

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


def _parse_float(text: str, where: str, what: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise WheelrailError(f"{where}: {what} must be a number, got {text.strip()!r}") from None


def read_csv(path: str | os.PathLike, *, kind: str | None = None) -> RoughnessSet:
    """Read a CSV roughness file (SPEC.md §3).

    Parameters
    ----------
    path : path-like
        The file. Metadata comes from leading ``# key: value`` lines (``kind``, ``description``).
    kind : {"rail", "wheel"}, optional
        Used when the file has no ``# kind:`` line; without either, ``rail`` (non-periodic) is assumed and
        the description says so.

    Raises
    ------
    WheelrailError
        One line naming the file, the line number and the problem for a missing or malformed header,
        ragged rows, non-numeric/NaN/inf cells, fewer than 2 samples, non-uniform x spacing, duplicate
        lateral positions, heights that cannot be µm, or an unknown kind.
    """
    path = Path(path)
    name = str(path)
    metadata: dict[str, str] = {}
    header: list[str] | None = None
    rows: list[tuple[int, list[str]]] = []
    try:
        with open(path, newline="", encoding="utf-8-sig") as stream:
            for number, raw in enumerate(stream, start=1):
                text = raw.strip()
                if header is None:
                    if not text:
                        continue
                    if text.startswith("#"):
                        key, sep, value = text[1:].partition(":")
                        if sep:
                            metadata[key.strip().lower()] = value.strip()
                        continue
                    header = next(csv.reader([text]))
                    header_line = number
                    continue
                if not text:
                    continue
                if text.startswith("#"):
                    raise WheelrailError(f"{name}, line {number}: comment lines are allowed only before the header")
                rows.append((number, next(csv.reader([text]))))
    except UnicodeDecodeError:
        raise WheelrailError(f"{name}: not a text CSV file (cannot decode as UTF-8)") from None
    except FileNotFoundError:
        raise WheelrailError(f"{name}: roughness file not found") from None

    if header is None:
        raise WheelrailError(f"{name}: missing header row 'x_m,y_mm=<mm>,...' (file has no data)")
    header = [cell.strip() for cell in header]
    where = f"{name}, line {header_line}"
    if header[0] != "x_m":
        raise WheelrailError(f"{where}: header must start with 'x_m', got {header[0]!r}")
    if len(header) < 2:
        raise WheelrailError(f"{where}: header needs at least one 'y_mm=<lateral position in mm>' column")
    y_mm = []
    for column, cell in enumerate(header[1:], start=2):
        key, sep, value = cell.partition("=")
        if key.strip() != "y_mm" or not sep:
            raise WheelrailError(f"{where}, column {column}: expected 'y_mm=<lateral position in mm>', got {cell!r}")
        position = _parse_float(value, f"{where}, column {column}", "the lateral position y_mm")
        if not math.isfinite(position):
            raise WheelrailError(f"{where}, column {column}: lateral position must be finite, got {value!r}")
        y_mm.append(position)
    seen: dict[float, int] = {}
    for column, position in enumerate(y_mm, start=2):
        if position in seen:
            raise WheelrailError(
                f"{where}: duplicate lateral position y_mm={position:g} in columns {seen[position]} and {column}"
            )
        seen[position] = column

    if len(rows) < 2:
        raise WheelrailError(f"{name}: needs at least 2 samples (data rows), got {len(rows)}")
    n_cols = len(header)
    values = np.empty((len(rows), n_cols))
    for index, (number, cells) in enumerate(rows):
        if len(cells) != n_cols:
            raise WheelrailError(f"{name}, line {number}: ragged row with {len(cells)} cells, header has {n_cols}")
        for column, cell in enumerate(cells):
            what = "x_m" if column == 0 else f"height (µm) in column {column + 1}"
            value = _parse_float(cell, f"{name}, line {number}", what)
            if not math.isfinite(value):
                raise WheelrailError(f"{name}, line {number}: {what} must be finite, got {cell.strip()!r}")
            values[index, column] = value

    x = values[:, 0]
    steps = np.diff(x)
    dx = (x[-1] - x[0]) / (len(x) - 1)
    if not dx > 0:
        raise WheelrailError(f"{name}: x_m must increase down the file, got {x[0]:g} m then {x[-1]:g} m")
    bad = np.flatnonzero(np.abs(steps - dx) > _SPACING_RTOL * dx)
    if bad.size:
        i = int(bad[0])
        raise WheelrailError(
            f"{name}, line {rows[i + 1][0]}: non-uniform x spacing, step {steps[i]:g} m where the mean "
            f"spacing is {dx:g} m (allowed deviation {_SPACING_RTOL:g} relative)"
        )
    heights_um = values[:, 1:].T
    peak_um = float(np.max(np.abs(heights_um)))
    if peak_um > MAX_HEIGHT / _UM:
        i, j = np.unravel_index(int(np.argmax(np.abs(heights_um))), heights_um.shape)
        raise WheelrailError(
            f"{name}, line {rows[j][0]}: height {heights_um[i, j]:g} µm exceeds ±{MAX_HEIGHT / _UM:g} µm "
            "(10 mm); heights must be in µm"
        )
    if 0 < peak_um < _MIN_CSV_PEAK_UM:
        raise WheelrailError(
            f"{name}: largest height is {peak_um:g} µm (below 1 nm): the file seems to hold metres, "
            "heights must be in µm"
        )

    file_kind = metadata.get("kind")
    description = metadata.get("description", "")
    if file_kind is None:
        file_kind = kind if kind is not None else "rail"
        if kind is None:
            description = f"{description}; kind not given in file, rail assumed".lstrip("; ")
    if file_kind not in KINDS:
        raise WheelrailError(f"{name}: unknown kind {file_kind!r}, allowed: {', '.join(KINDS)}")
    order = np.argsort(y_mm)
    return RoughnessSet(
        heights=heights_um[order] * _UM,
        dx=float(dx),
        y=np.asarray(y_mm)[order] * _MM,
        kind=file_kind,
        description=description or f"read from {path.name}",
    )


def read_npz(path: str | os.PathLike) -> RoughnessSet:
    """Read an NPZ roughness file (SPEC.md §3: ``z_m``, ``dx_m``, ``y_m``, ``kind``, ``description``)."""
    path = Path(path)
    name = str(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [key for key in ("z_m", "dx_m", "y_m", "kind") if key not in data.files]
            if missing:
                raise WheelrailError(
                    f"{name}: missing array(s) {', '.join(missing)}; an NPZ roughness file needs z_m, dx_m, "
                    "y_m, kind (and description)"
                )
            z = np.asarray(data["z_m"])
            dx = np.asarray(data["dx_m"])
            y = np.asarray(data["y_m"])
            kind = str(data["kind"])
            description = str(data["description"]) if "description" in data.files else ""
    except FileNotFoundError:
        raise WheelrailError(f"{name}: roughness file not found") from None
    except (zipfile.BadZipFile, ValueError, OSError, EOFError) as error:
        if isinstance(error, WheelrailError):
            raise
        raise WheelrailError(f"{name}: not a readable NPZ roughness file ({error})") from None
    if z.dtype.kind not in "fiu" or y.dtype.kind not in "fiu" or dx.dtype.kind not in "fiu":
        raise WheelrailError(f"{name}: z_m, dx_m and y_m must be numeric arrays")
    if dx.size != 1:
        raise WheelrailError(f"{name}: dx_m must be a scalar spacing in m, got shape {dx.shape}")
    if z.ndim != 2:
        raise WheelrailError(f"{name}: z_m must be 2-D (lines x samples, m), got shape {z.shape}")
    if kind not in KINDS:
        raise WheelrailError(f"{name}: unknown kind {kind!r}, allowed: {', '.join(KINDS)}")
    if y.ndim != 1 or y.shape[0] != z.shape[0]:
        raise WheelrailError(f"{name}: y_m must hold one lateral position per line ({z.shape[0]}), got {y.shape}")
    if z.shape[1] < 2:
        raise WheelrailError(f"{name}: needs at least 2 samples per line, got {z.shape[1]}")
    if not np.all(np.isfinite(z)):
        row, col = np.argwhere(~np.isfinite(z))[0]
        raise WheelrailError(f"{name}: z_m must be finite, got {z[row, col]} at line row {row}, sample {col}")
    if y.shape[0] > 1 and np.unique(y).size != y.size:
        raise WheelrailError(f"{name}: duplicate lateral positions in y_m: {y.tolist()}")
    order = np.argsort(y)
    try:
        return RoughnessSet(heights=z[order], dx=float(dx), y=y[order], kind=kind, description=description)
    except WheelrailError as error:
        raise WheelrailError(f"{name}: {error}") from None


def read_roughness(path: str | os.PathLike, *, kind: str | None = None) -> RoughnessSet:
    """Read a ``.csv`` or ``.npz`` roughness file, chosen by its suffix."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return read_csv(path, kind=kind)
    if suffix == ".npz":
        return read_npz(path)
    raise WheelrailError(f"{path}: unknown roughness file type {path.suffix!r}, allowed: .csv, .npz")


def bundled_names() -> list[str]:
    """Names of the bundled roughness sets (the ``.npz`` files of ``wheelrail.sample_data``)."""
    folder = resources.files(SAMPLE_DATA_PACKAGE)
    return sorted(entry.name[:-4] for entry in folder.iterdir() if entry.name.endswith(".npz"))


def load_roughness(name_or_path: str | os.PathLike) -> RoughnessSet:
    """A bundled set by name (see :func:`bundled_names`) or a user's ``.csv``/``.npz`` file by path.

    A user file works everywhere a bundled set does (SPEC.md §5).
    """
    text = str(name_or_path)
    names = bundled_names()
    if text in names:
        resource = resources.files(SAMPLE_DATA_PACKAGE).joinpath(f"{text}.npz")
        with resources.as_file(resource) as path:
            return read_npz(path)
    path = Path(text)
    if path.suffix.lower() in (".csv", ".npz") or path.exists():
        if not path.is_file():
            problem = "is a folder, not a roughness file" if path.is_dir() else "roughness file not found"
            raise WheelrailError(f"{text}: {problem} (bundled sets: {', '.join(names)})")
        return read_roughness(path)
    raise WheelrailError(
        f"unknown roughness set {text!r}; bundled sets: {', '.join(names) or 'none'}; "
        "or give the path of a .csv or .npz file"
    )


# --------------------------------------------------------------------------------------------------
# Preprocessing (paper section 3.1; EN 15610)
# --------------------------------------------------------------------------------------------------
_SEAM_FIT_SAMPLES = 2  # samples on each side of a wheel's seam used to estimate the closure jump


def detrend_linear(roughness: RoughnessSet) -> RoughnessSet:
    """Remove a linear trend from every line (paper 3.1, step 1: trend of the measurement equipment).

    Rail (open) data: least-squares straight line removed (``scipy.signal.detrend``).
    Wheel (periodic) data: a drift of the equipment shows as a jump where the circumference closes, and a
    least-squares line would also take away part of the true periodic roughness (a harmonic of amplitude A
    and order n tilts the fit by ~2A/n over the circumference). The slope is therefore estimated from the
    closure jump: the last two and the first two samples are extrapolated linearly to the seam (half a
    sample beyond each end); their difference ``J`` is the drift over one circumference, ``s = J / (n dx)``,
    and ``s x`` is removed. For drift-free data the error of ``J`` is of the size of one ordinary
    sample-to-sample step (the curvature across the seam): the seam then stays as smooth as the rest of
    the profile. Longer fits were tried on the bundled wheels and err more (short-wavelength roughness).
    """
    z = roughness.heights
    if roughness.periodic:
        n = roughness.n_samples
        w = max(1, min(_SEAM_FIT_SAMPLES, n // 4))
        index = np.arange(w, dtype=float)
        if w >= 2:
            end_fit = np.polyfit(index, z[:, -w:].T, 1)  # (2, lines): slope, intercept per line
            start_fit = np.polyfit(index, z[:, :w].T, 1)
            end_value = end_fit[0] * (w - 0.5) + end_fit[1]  # at index n - 0.5
            start_value = start_fit[0] * (-0.5) + start_fit[1]  # at index -0.5
        else:
            end_value, start_value = z[:, -1], z[:, 0]
        slope = (end_value - start_value) / (n * roughness.dx)
        out = z - slope[:, np.newaxis] * roughness.x[np.newaxis, :]
    else:
        out = scipy.signal.detrend(z, axis=1, type="linear")
    return roughness.with_heights(out)


def remove_mean(roughness: RoughnessSet) -> RoughnessSet:
    """Subtract the mean of every line (paper 3.1, step 3)."""
    z = roughness.heights
    return roughness.with_heights(z - z.mean(axis=1, keepdims=True))


def curvature(heights: np.ndarray, dx: float, *, periodic: bool) -> np.ndarray:
    """Curvature estimate of each line, the central second difference ``(z[i-1] - 2 z[i] + z[i+1]) / dx²``.

    Units 1/m. End samples of open lines get the curvature of their neighbour.
    """
    z = np.atleast_2d(heights)
    if periodic:
        return (np.roll(z, 1, axis=1) - 2 * z + np.roll(z, -1, axis=1)) / dx**2
    c = np.empty_like(z)
    c[:, 1:-1] = (z[:, :-2] - 2 * z[:, 1:-1] + z[:, 2:]) / dx**2
    c[:, 0] = c[:, 1]
    c[:, -1] = c[:, -2]
    return c


def default_curvature_limit(heights: np.ndarray, dx: float, *, periodic: bool) -> float:
    """Default spike threshold on |curvature|, 1/m: 10 robust standard deviations of the curvature.

    The robust standard deviation is 1.4826 x the median absolute curvature (Gaussian-consistent MAD), so
    genuine roughness (Gaussian-like) practically never exceeds it, while a spike one sample wide and
    a few µm high has a curvature of order height / dx², far above.
    """
    c = curvature(heights, dx, periodic=periodic)
    sigma = 1.4826 * float(np.median(np.abs(c - np.median(c))))
    return 10.0 * sigma if sigma > 0 else math.inf


def remove_spikes(
    roughness: RoughnessSet, *, curvature_limit: float | None = None, max_passes: int = 10
) -> RoughnessSet:
    """Remove spikes by the EN 15610 curvature criterion (paper 3.1, step 2).

    EN 15610 removes spikes (foreign material, dust, measurement dropouts) from raw roughness data with a
    curvature criterion: where the curvature of the measured profile is larger than a profile that can
    have, the sample is a spike. The standard's text could not be consulted while writing this; this
    implementation follows that principle as documented here:

    1. curvature ``c_i = (z[i-1] - 2 z[i] + z[i+1]) / dx²`` (1/m) on each line (periodic for wheels);
    2. samples with ``|c_i| > curvature_limit`` are flagged together with their two neighbours (a
       one-sample spike of height h gives -2h/dx² at its peak and +h/dx² beside it);
    3. the flagged samples are replaced by linear interpolation between the nearest unflagged samples
       (around the circumference for wheels);
    4. repeat until nothing is flagged (at most ``max_passes`` passes).

    Parameters
    ----------
    curvature_limit : float, optional
        Threshold on |curvature|, 1/m. Default: :func:`default_curvature_limit` per line, i.e. 10 robust
        standard deviations of that line's curvature.
    """
    z = np.array(roughness.heights)
    x = roughness.x
    removed = 0
    for row in range(roughness.n_lines):
        line = z[row]
        limit = (
            default_curvature_limit(line, roughness.dx, periodic=roughness.periodic)
            if curvature_limit is None
            else float(curvature_limit)
        )
        if not limit > 0:
            raise WheelrailError(f"remove_spikes: curvature_limit must be positive (1/m), got {curvature_limit}")
        for _ in range(max_passes):
            c = curvature(line, roughness.dx, periodic=roughness.periodic)[0]
            flagged = np.abs(c) > limit
            if not flagged.any():
                break
            grown = flagged.copy()
            grown[1:] |= flagged[:-1]
            grown[:-1] |= flagged[1:]
            if roughness.periodic:
                grown[0] |= flagged[-1]
                grown[-1] |= flagged[0]
            flagged = grown
            good = ~flagged
            if good.sum() < 2:
                raise WheelrailError(
                    f"remove_spikes: line {roughness.line_of_row(row)} is all spikes at curvature limit {limit:g} 1/m"
                )
            removed += int(flagged.sum())
            if roughness.periodic:
                line[flagged] = np.interp(x[flagged], x[good], line[good], period=roughness.length)
            else:
                line[flagged] = np.interp(x[flagged], x[good], line[good])
    note = f"spikes removed ({removed} samples)" if removed else None
    return roughness.with_heights(z, note=note)


def _butterworth_cutoff_for_zero_phase(cutoff: float, order: int) -> float:
    # Forward-backward filtering squares |H|; shift the Butterworth corner so that |H|^2 is -3 dB at the
    # requested cut-off: 1 + (fc/f3)^(2n) = sqrt(2)  =>  fc = f3 (sqrt(2) - 1)^(1/(2n)).
    return cutoff * (math.sqrt(2.0) - 1.0) ** (1.0 / (2 * order))


def highpass_gain(wavenumber: np.ndarray, cutoff_wavelength: float, order: int = 4) -> np.ndarray:
    """Amplitude gain of :func:`highpass` at ``wavenumber`` (cycles/m); exactly 1/sqrt(2) at the cut-off."""
    kc = _butterworth_cutoff_for_zero_phase(1.0 / cutoff_wavelength, order)
    k = np.abs(np.asarray(wavenumber, dtype=float))
    with np.errstate(divide="ignore"):
        return np.where(k > 0, 1.0 / (1.0 + (kc / np.where(k > 0, k, 1.0)) ** (2 * order)), 0.0)


def highpass(roughness: RoughnessSet, cutoff_wavelength: float, *, order: int = 4) -> RoughnessSet:
    """Zero-phase high-pass filter at a cut-off wavelength (paper 3.1: CAT data high-passed at 14 cm).

    The filter is a Butterworth filter of ``order`` applied forwards and backwards (zero phase), with its
    corner shifted so that the overall amplitude gain is exactly -3 dB (1/sqrt(2)) at
    ``cutoff_wavelength``; the gain is ``1 / (1 + (k_c / k)^(2 order))`` (:func:`highpass_gain`).
    Rail data: ``scipy.signal.sosfiltfilt`` (edges padded by odd extension). Wheel data: the same gain
    applied to the DFT of the circumference, which is exactly periodic and zero-phase.

    Parameters
    ----------
    cutoff_wavelength : float
        Wavelength at -3 dB, m. Must be longer than two sample spacings.
    order : int
        Butterworth order of the one-way filter (default 4: 48 dB/octave after forward-backward).
    """
    if not (math.isfinite(cutoff_wavelength) and cutoff_wavelength > 2 * roughness.dx):
        raise WheelrailError(
            f"high-pass cut-off wavelength must exceed 2 dx = {2 * roughness.dx:g} m, got {cutoff_wavelength!r}"
        )
    if cutoff_wavelength > roughness.length:
        raise WheelrailError(
            f"high-pass cut-off wavelength {cutoff_wavelength:g} m exceeds the data length {roughness.length:g} m"
        )
    z = roughness.heights
    if roughness.periodic:
        k = np.fft.rfftfreq(roughness.n_samples, d=roughness.dx)
        out = np.fft.irfft(np.fft.rfft(z, axis=1) * highpass_gain(k, cutoff_wavelength, order), n=z.shape[1], axis=1)
    else:
        kc = _butterworth_cutoff_for_zero_phase(1.0 / cutoff_wavelength, order)
        sos = scipy.signal.butter(order, kc, btype="highpass", fs=1.0 / roughness.dx, output="sos")
        out = scipy.signal.sosfiltfilt(sos, z, axis=1)
    return roughness.with_heights(out, note=f"high-passed at {cutoff_wavelength:g} m")


def preprocess(
    roughness: RoughnessSet,
    *,
    detrend: bool = True,
    despike: bool = True,
    demean: bool = True,
    highpass_wavelength: float | None = None,
    curvature_limit: float | None = None,
) -> RoughnessSet:
    """Preprocess raw roughness as in the paper (section 3.1) and EN 15610.

    Steps, in order: (1) linear detrend (:func:`detrend_linear`), (2) spike removal by the curvature
    criterion (:func:`remove_spikes`), (3) optional zero-phase high-pass at ``highpass_wavelength`` m
    (:func:`highpass`), (4) mean removal (:func:`remove_mean`), last so that the result has exactly zero
    mean (the padded forward-backward filter of open rail data leaves a small mean). Wheel data is
    treated as periodic.
    """
    out = roughness
    if detrend:
        out = detrend_linear(out)
    if despike:
        out = remove_spikes(out, curvature_limit=curvature_limit)
    if highpass_wavelength is not None:
        out = highpass(out, highpass_wavelength)
    if demean:
        out = remove_mean(out)
    return out


def resample_longitudinal(roughness: RoughnessSet, dx: float) -> RoughnessSet:
    """Linear interpolation of every line to spacing ``dx`` (m), e.g. 0.5 mm -> 1 mm (paper section 3).

    Rail: samples at ``0, dx, ...`` up to the last original position. Wheel: the circumference is kept
    exactly; ``dx`` is adjusted to ``length / round(length / dx)`` and interpolation wraps around.
    No anti-alias filter is applied, as in the paper (linear interpolation only).
    """
    dx = float(dx)
    if not (math.isfinite(dx) and dx > 0):
        raise WheelrailError(f"resample: longitudinal spacing must be positive (m), got {dx!r}")
    x_old = roughness.x
    if roughness.periodic:
        n = max(2, round(roughness.length / dx))
        dx = roughness.length / n
        x_new = np.arange(n) * dx
        z = np.stack([np.interp(x_new, x_old, line, period=roughness.length) for line in roughness.heights])
    else:
        n = int(math.floor(x_old[-1] / dx + 1e-9)) + 1
        if n < 2:
            raise WheelrailError(f"resample: spacing {dx:g} m leaves fewer than 2 samples in {x_old[-1]:g} m")
        x_new = np.arange(n) * dx
        z = np.stack([np.interp(x_new, x_old, line) for line in roughness.heights])
    return roughness.with_heights(z, dx=dx, note=f"interpolated to dx {dx * 1e3:g} mm")


def resample_lateral(roughness: RoughnessSet, dy: float) -> RoughnessSet:
    """Linear interpolation across the lines to lateral spacing ``dy`` (m), e.g. 2 mm -> 1 mm for 3D.

    New lines are at integer multiples of ``dy`` (so y = 0 stays a line) within the original lateral
    extent.
    """
    dy = float(dy)
    if not (math.isfinite(dy) and dy > 0):
        raise WheelrailError(f"resample: lateral spacing must be positive (m), got {dy!r}")
    if roughness.n_lines < 2:
        raise WheelrailError("resample: lateral interpolation needs at least 2 lines")
    y = roughness.y
    tol = 1e-9 * max(1.0, abs(y).max() / dy)
    first = math.ceil(y[0] / dy - tol)
    last = math.floor(y[-1] / dy + tol)
    y_new = np.arange(first, last + 1) * dy
    if y_new.size < 1:
        raise WheelrailError(f"resample: lateral spacing {dy:g} m leaves no line in [{y[0]:g}, {y[-1]:g}] m")
    # interpolate each sample column across y (vectorised through index/weight arrays)
    idx = np.clip(np.searchsorted(y, y_new, side="right") - 1, 0, y.size - 2)
    w = np.clip((y_new - y[idx]) / (y[idx + 1] - y[idx]), 0.0, 1.0)
    z = roughness.heights
    z_new = (1 - w)[:, None] * z[idx] + w[:, None] * z[idx + 1]
    return roughness.with_heights(z_new, y=y_new, note=f"interpolated to {dy * 1e3:g} mm lines")


def to_model_grid(roughness: RoughnessSet, dx: float, dy: float | None = None) -> RoughnessSet:
    """Interpolate to the model grid: longitudinal ``dx`` and, for the 3D model, lateral ``dy`` (m)."""
    out = resample_longitudinal(roughness, dx) if not math.isclose(dx, roughness.dx, rel_tol=1e-12) else roughness
    if dy is not None and not (
        roughness.n_lines > 1 and np.allclose(np.diff(out.y), dy, rtol=1e-9) and np.any(np.isclose(out.y, 0))
    ):
        out = resample_lateral(out, dy)
    return out


def lines_along_track(roughness: RoughnessSet, lines, length: float, dx: float | None = None) -> np.ndarray:
    """Heights of several lines covering a run of ``length`` m at spacing ``dx`` m, shape (lines, samples).

    Sample ``i`` is at ``x = i dx`` for ``i = 0 .. round(length / dx)``. Wheel data is repeated around the
    circumference as often as needed (periodic linear interpolation); rail data must be long enough.
    """
    dx = roughness.dx if dx is None else float(dx)
    if not (math.isfinite(dx) and dx > 0):
        raise WheelrailError(f"spacing dx must be positive (m), got {dx!r}")
    if not (math.isfinite(length) and length >= 0):
        raise WheelrailError(f"run length must be zero or positive (m), got {length!r}")
    n = int(round(length / dx)) + 1
    x = np.arange(n) * dx
    rows = [roughness.row_of_line(line) for line in lines]
    if roughness.periodic:
        return np.stack([np.interp(x, roughness.x, roughness.heights[r], period=roughness.length) for r in rows])
    available = roughness.x[-1]
    if x[-1] > available * (1 + 1e-12):
        raise WheelrailError(
            f"run length {length:g} m exceeds the rail roughness data ({available:g} m); "
            "shorten the run or use longer data"
        )
    return np.stack([np.interp(x, roughness.x, roughness.heights[r]) for r in rows])


def line_along_track(roughness: RoughnessSet, line: int, length: float, dx: float | None = None) -> np.ndarray:
    """Heights of one line over a run of ``length`` m at spacing ``dx`` m (see :func:`lines_along_track`)."""
    return lines_along_track(roughness, [line], length, dx)[0]


# --------------------------------------------------------------------------------------------------
# Roughness analyses (paper section 3.1 Fig. 6, section 3.2 Fig. 9)
# --------------------------------------------------------------------------------------------------
ROUGHNESS_REFERENCE = 1e-6  # m: roughness levels are in dB re 1 µm
DEFAULT_LINES = tuple(range(-3, 4))  # the paper averages the 7 lines -3..3
FREQUENCY_RANGE = (50.0, 8000.0)  # Hz, the band range of the paper's figures and SPEC.md §4
WAVELENGTH_RANGE = (0.8, 0.00315)  # m, EN 15610 / CNOSSOS-EU wavelength bands 800 mm .. 3.15 mm


@dataclass(frozen=True, kw_only=True, eq=False)
class RoughnessSpectrum:
    """Third-octave roughness spectrum.

    Attributes
    ----------
    band_centres : numpy.ndarray
        Exact base-10 band centres: Hz (``axis == "frequency"``) or m (``axis == "wavelength"``).
    wavelengths : numpy.ndarray
        Wavelength of each band centre, m (``v / f`` for frequency bands).
    levels_db : numpy.ndarray
        Band level, dB re 1 µm, averaged energetically over ``lines``; NaN where the band is outside what
        the data resolves.
    lines : tuple of int
        Line numbers averaged (Figure 8 numbering).
    axis : str
        ``"frequency"`` or ``"wavelength"``.
    speed : float or None
        Speed used for the frequency axis, m/s.
    """

    band_centres: np.ndarray
    wavelengths: np.ndarray
    levels_db: np.ndarray
    lines: tuple
    axis: str
    speed: float | None = None


def _rows(roughness: RoughnessSet, lines) -> list[int]:
    lines = tuple(int(line) for line in lines)
    if not lines:
        raise WheelrailError("choose at least one roughness line")
    return [roughness.row_of_line(line) for line in lines]


def _check_speed(speed: float) -> float:
    if not (isinstance(speed, int | float) and math.isfinite(speed) and speed > 0):
        raise WheelrailError(f"speed must be a positive number in m/s, got {speed!r}")
    return float(speed)


def _spatial_levels(roughness: RoughnessSet, rows, k_lower, k_upper) -> np.ndarray:
    levels = third_octave_levels(roughness.heights[rows], 1.0 / roughness.dx, k_lower, k_upper, ROUGHNESS_REFERENCE)
    # A band is only resolved when it lies between the record's fundamental and the Nyquist wavenumber.
    resolved = (k_lower >= 1.0 / roughness.length) & (k_upper <= 0.5 / roughness.dx)
    return np.where(resolved, levels, np.nan)


def roughness_spectrum(
    roughness: RoughnessSet,
    *,
    speed: float | None = None,
    lines=DEFAULT_LINES,
    frequency_range: tuple[float, float] = FREQUENCY_RANGE,
    wavelength_range: tuple[float, float] = WAVELENGTH_RANGE,
) -> RoughnessSpectrum:
    """Third-octave roughness spectrum in dB re 1 µm (paper section 3.1, Figure 6).

    A single Hann-windowed FFT of each chosen line, integrated into third-octave bands and averaged over
    the lines (:func:`wheelrail.core.spectra.third_octave_levels`).

    Parameters
    ----------
    speed : float, optional
        Train speed, m/s. Given: bands in frequency ``f = v / λ`` over ``frequency_range`` (Hz).
        Omitted: EN 15610 / CNOSSOS-EU wavelength bands over ``wavelength_range`` (m, long to short).
    lines : iterable of int
        Line numbers to average (default -3..3, as in the paper).
    """
    rows = _rows(roughness, lines)
    if speed is not None:
        speed = _check_speed(speed)
        centres, lower, upper = third_octave_bands(*frequency_range)
        levels = _spatial_levels(roughness, rows, lower / speed, upper / speed)
        return RoughnessSpectrum(
            band_centres=centres,
            wavelengths=speed / centres,
            levels_db=levels,
            lines=tuple(int(line) for line in lines),
            axis="frequency",
            speed=speed,
        )
    long, short = max(wavelength_range), min(wavelength_range)
    centres, lower, upper = third_octave_bands(short, long)
    centres, lower, upper = centres[::-1], lower[::-1], upper[::-1]  # long wavelengths first (EN 15610)
    levels = _spatial_levels(roughness, rows, 1.0 / upper, 1.0 / lower)
    return RoughnessSpectrum(
        band_centres=centres,
        wavelengths=centres,
        levels_db=levels,
        lines=tuple(int(line) for line in lines),
        axis="wavelength",
    )


def lateral_coherence(
    roughness: RoughnessSet,
    speed: float,
    *,
    half_lines: int = 3,
    blocks: int = 20,
    frequency_range: tuple[float, float] = FREQUENCY_RANGE,
) -> tuple[np.ndarray, np.ndarray]:
    """Lateral coherence parameter γ²(f0) of eqs. (15)-(18) (paper section 3.2, Figure 9).

    Line 0 against lines m = -M..M (m != 0), each line cut into B consecutive blocks; see
    :func:`wheelrail.core.spectra.band_coherence` for the estimator and its bias (~1/(2 M B L)).

    Parameters
    ----------
    speed : float
        Train speed, m/s; band frequency ``f = v / λ``.
    half_lines : int
        M (paper: 3, so that the lines cover the nominal contact area).
    blocks : int
        B (paper: 20).

    Returns
    -------
    band_centres : numpy.ndarray
        Hz.
    coherence : numpy.ndarray
        γ², dimensionless in [0, 1]; NaN in bands that hold no bin of the block spectra (block length
        ``length / B`` sets the resolution ``v B / length``).
    """
    speed = _check_speed(speed)
    if isinstance(half_lines, bool) or int(half_lines) != half_lines or half_lines < 1:
        raise WheelrailError(f"M (half the number of other lines) must be an integer >= 1, got {half_lines!r}")
    others = [m for m in range(-int(half_lines), int(half_lines) + 1) if m != 0]
    centre_row = roughness.row_of_line(0)
    other_rows = _rows(roughness, others)
    centres, lower, upper = third_octave_bands(*frequency_range)
    gamma2 = band_coherence(
        roughness.heights[centre_row],
        roughness.heights[other_rows],
        1.0 / roughness.dx,
        lower / speed,
        upper / speed,
        blocks=blocks,
    )
    return centres, gamma2
