"""The CNOSSOS-EU rolling-noise tables as cited data files (``core/noise/data``).

Each file is one table of Appendix G of Annex II of Directive 2002/49/EC as replaced by Commission Directive
(EU) 2015/996, with the corrigendum of OJ L 5, 10.1.2018, and as amended by Commission Delegated Directive
(EU) 2021/1226; its header names the table, the edition and the print it was transcribed from. The contact
filter A3 (Table G-2) is not here: it lives in :mod:`wheelrail.core.reference_filters` (one source of truth).

A table is read into :class:`Table`: the grid it is printed on (wavelengths in m, long first, or band
centre frequencies in Hz as printed: 50, 63, 80, ... 10 000) and one column of levels (dB) per name.
"""

from __future__ import annotations

import csv
import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wheelrail.core.errors import WheelrailError

DATA = Path(__file__).parent / "data"

# The 24 one-third octave bands of the CNOSSOS-EU railway source, nominal centres as the directive prints them.
NOMINAL_FREQUENCIES_HZ = (
    50.0,
    63.0,
    80.0,
    100.0,
    125.0,
    160.0,
    200.0,
    250.0,
    315.0,
    400.0,
    500.0,
    630.0,
    800.0,
    1000.0,
    1250.0,
    1600.0,
    2000.0,
    2500.0,
    3150.0,
    4000.0,
    5000.0,
    6300.0,
    8000.0,
    10000.0,
)

TABLE_FILES = {
    "wheel_roughness": "cnossos_g1a_wheel_roughness.csv",
    "rail_roughness": "cnossos_g1b_rail_roughness.csv",
    "track_transfer": "cnossos_g3a_track_transfer.csv",
    "vehicle_transfer": "cnossos_g3b_vehicle_transfer.csv",
    "superstructure_transfer": "cnossos_g3c_superstructure_transfer.csv",
}


@dataclass(frozen=True, eq=False)
class Table:
    """One printed table.

    Attributes
    ----------
    name : str
        Key of :data:`TABLE_FILES`.
    axis : str
        ``"wavelength"`` (grid in m, long first) or ``"frequency"`` (grid in Hz, low first).
    grid : numpy.ndarray
        The printed grid: wavelengths in m or band centres in Hz, as printed (nominal).
    columns : dict of str to numpy.ndarray
        Column name -> levels in dB, one per grid point.
    source : str
        The file's comment header (what the table is and where it was transcribed from).
    """

    name: str
    axis: str
    grid: np.ndarray
    columns: dict
    source: str

    def column(self, key: str) -> np.ndarray:
        """The levels of column ``key`` (dB); a clear error naming the columns there are."""
        if key not in self.columns:
            raise WheelrailError(
                f"CNOSSOS-EU {self.name.replace('_', ' ')}: no column {key!r}; the table has {', '.join(self.columns)}"
            )
        return self.columns[key]


def load_table(name: str) -> Table:
    """Read the table ``name`` (a key of :data:`TABLE_FILES`) from its data file (once per process)."""
    if not isinstance(name, str) or name not in TABLE_FILES:
        raise WheelrailError(f"unknown CNOSSOS-EU table {name!r}; choose one of {', '.join(TABLE_FILES)}")
    return _load_table(name)


@functools.cache
def _load_table(name: str) -> Table:
    path = DATA / TABLE_FILES[name]
    comments, rows = [], []
    with path.open(encoding="utf-8", newline="") as handle:
        for line in handle:
            if line.startswith("#"):
                comments.append(line[1:].strip())
            elif line.strip():
                rows.append(line)
    header, *body = list(csv.reader(rows))
    values = np.array([[float(cell) for cell in row] for row in body])
    axis = "wavelength" if header[0] == "wavelength_mm" else "frequency"
    grid = values[:, 0] * (1e-3 if axis == "wavelength" else 1.0)
    columns = {key: values[:, i + 1].copy() for i, key in enumerate(header[1:])}
    return Table(name=name, axis=axis, grid=grid, columns=columns, source=" ".join(comments))
