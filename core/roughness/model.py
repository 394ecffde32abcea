"""The roughness data model: :class:`RoughnessSet` and the limits every set obeys.

A roughness set holds the heights of several parallel longitudinal lines of a rail or a wheel running
surface (Pieringer, Kropp & Thompson 2011, section 3.1 and Figure 8). Everything is SI inside: heights and
positions in m.

Heights must lie within ``MAX_HEIGHT`` = 10 mm of zero. Wheel/rail roughness is at most some hundred µm
(corrugation tens of µm, paper section 1: "from below 1 up to 50 µm"), so a larger height is a unit
mistake (mm or m read as µm), not roughness.

A roughness file's sample spacing must lie in ``SPACING_RANGE`` = 1 µm to 10 mm and its lateral positions
within ``MAX_LATERAL`` = 0.2 m of the centre (:func:`check_file_geometry`). Profilometers sample every few µm
to a millimetre; a spacing over 10 mm resolves no wavelength below 20 mm, leaving out most of the EN 15610
bands (800 to 3.15 mm) and putting one sample under the ~10 mm contact patch; a rail head (72 mm wide,
60E1) and a wheel tread (about 140 mm) lie well within 0.2 m. A value outside is a unit mistake or damage.

A set, as read or as interpolated onto a model grid, holds at most ``MAX_VALUES`` heights (see
:func:`check_value_count`): enough for 19 lines of 1 km at 1 mm, and small enough (160 MB as float64) that
the few copies a run makes stay well inside a workstation's memory. Larger requests are refused with the
figure before anything is allocated.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
from typing import TypeAlias

import numpy as np

from wheelrail.core.errors import WheelrailError

KINDS = ("rail", "wheel")
MAX_HEIGHT = 10e-3  # m; see the module docstring for why larger heights are refused
SPACING_RANGE = (1e-6, 10e-3)  # m: a file's accepted sample spacing (module docstring)
MAX_LATERAL = 0.2  # m: largest |lateral position| of a file's line (module docstring)
MAX_VALUES = 20_000_000  # heights in one set or one interpolated grid (160 MB as float64); module docstring
_BYTES_PER_VALUE = 8  # float64


def check_value_count(count: int, what: str) -> int:
    """Refuse ``count`` heights above :data:`MAX_VALUES`, naming ``what`` and the memory it would take.

    Returns ``count`` unchanged when it is within the limit, so that a caller can check before allocating.
    """
    if count > MAX_VALUES:
        raise WheelrailError(
            f"{what} would hold {count:.4g} heights ({count * _BYTES_PER_VALUE / 1e9:.3g} GB as float64), "
            f"more than the limit of {MAX_VALUES:,} ({MAX_VALUES * _BYTES_PER_VALUE / 1e6:.0f} MB)"
        )
    return count


def check_file_geometry(dx: float, y_m, line_names) -> None:
    """Refuse a file's spacing ``dx`` (m) outside :data:`SPACING_RANGE` or a lateral position (m) beyond
    :data:`MAX_LATERAL`; ``line_names[i]`` names line i in the file ("column 3 (y_mm=5)", "row 0")."""
    low, high = SPACING_RANGE
    if not low <= dx <= high:
        raise WheelrailError(
            f"sample spacing {dx:g} m is outside the accepted {low:g} to {high:g} m (a profilometer's µm to a "
            "10 mm spacing that still resolves the roughness bands; check the unit of x)"
        )
    for name, position in zip(line_names, np.asarray(y_m, dtype=float).tolist(), strict=True):
        if not abs(position) <= MAX_LATERAL:
            raise WheelrailError(
                f"{name}: lateral position {position:g} m is outside ±{MAX_LATERAL:g} m (no rail head or wheel "
                "tread is wider; check the unit)"
            )


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

    Raises
    ------
    WheelrailError
        For a kind other than ``"rail"`` or ``"wheel"``, a spacing that is not positive, heights that are not a
        finite (lines x samples) array within ``MAX_HEIGHT``, or lateral positions that are not strictly
        increasing, one per line.

    See Also
    --------
    wheelrail.core.roughness.load_roughness : a bundled set or a file.

    Notes
    -----
    Lines are numbered -M..M as in the paper's Figure 8: number 0 is the row whose lateral position is
    closest to y = 0, and number n is row ``centre_row + n`` (see :meth:`row_of_line`).

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.roughness import RoughnessSet
    >>> x = np.arange(1000) * 1e-3                                      # m
    >>> rail = RoughnessSet(heights=5e-6 * np.sin(2 * np.pi * x / 0.05), dx=1e-3, y=[0.0], kind="rail")
    >>> rail.heights.shape, rail.length                                # one line of 1 m, 5 um at 50 mm
    ((1, 1000), 1.0)
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

    @classmethod
    def smooth(
        cls,
        length: float,
        *,
        dx: float = 1e-3,
        lines: int = 1,
        line_spacing: float = 1e-3,
        kind: str = "rail",
        description: str = "smooth",
    ) -> RoughnessSet:
        """A set of zero heights: a smooth rail (or wheel) for runs that study the track or an irregularity alone.

        Parameters
        ----------
        length : float
            What the heights cover, m: a rail's samples reach x = ``length`` (``round(length / dx) + 1`` of them);
            a wheel's are one circumference of ``length`` (``round(length / dx)``).
        dx : float
            Longitudinal sample spacing, m.
        lines : int
            Number of lines; ``line_spacing`` apart, line 0 at y = 0 with ``lines // 2`` lines before it (a
            3D window needs the lines its rows reach).
        line_spacing : float
            Lateral spacing of the lines, m.
        kind, description : str
            As for :class:`RoughnessSet`.

        Returns
        -------
        RoughnessSet

        Raises
        ------
        WheelrailError
            For a length or a spacing that is not a positive finite number of m, a line count that is not a
            positive integer, fewer than 2 samples, or more heights than :data:`MAX_VALUES`.

        Examples
        --------
        >>> from wheelrail.core.roughness import RoughnessSet
        >>> rail = RoughnessSet.smooth(0.5, lines=3)
        >>> rail.heights.shape, rail.y.tolist(), float(rail.heights.max())
        ((3, 501), [-0.001, 0.0, 0.001], 0.0)
        """
        where = "RoughnessSet.smooth"
        for name, value in (("length", length), ("dx", dx), ("line_spacing", line_spacing)):
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise WheelrailError(f"{where}: {name} must be a positive number of m, got {value!r}")
            if not (math.isfinite(value) and value > 0):
                raise WheelrailError(f"{where}: {name} must be a positive finite number of m, got {value!r}")
        if isinstance(lines, bool) or not isinstance(lines, (int, np.integer)) or lines < 1:
            raise WheelrailError(f"{where}: lines must be a positive whole number, got {lines!r}")
        if kind not in KINDS:
            raise WheelrailError(f"{where}: kind must be one of {', '.join(KINDS)}, got {kind!r}")
        check_value_count(int(lines) * (length / dx + 1), "a smooth set")  # before rounding: an infinite ratio
        samples = int(round(length / dx)) + (0 if kind == "wheel" else 1)
        if samples < 2:
            raise WheelrailError(
                f"{where}: length {length:g} m holds {samples} sample(s) at dx {dx:g} m; at least 2 are needed"
            )
        return cls(
            heights=np.zeros((int(lines), samples)),
            dx=dx,
            y=(np.arange(int(lines)) - int(lines) // 2) * line_spacing,
            kind=kind,
            description=description,
        )

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


RoughnessLike: TypeAlias = RoughnessSet | str | os.PathLike
"""What a run takes as roughness: a set, a bundled set's name or the path of a ``.csv``/``.npz`` file."""
