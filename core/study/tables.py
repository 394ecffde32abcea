"""Study tables: one CSV per figure table, band centres in Hz and one column per curve in dB."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wheelrail.core.atomic import atomic_write


@dataclass(frozen=True)
class Table:
    """One CSV table: band centres in Hz and one column per curve, in dB.

    Attributes
    ----------
    name : str
        File stem (``fig10_corrugated-rail_contact_filters``).
    figure : str
        Paper figure it reproduces (``"10"``).
    title : str
        What is tabulated, with units.
    band_centres : ndarray
        Hz.
    columns : dict of str -> ndarray
        Column name (with unit suffix ``_db``) -> values, dB.
    panel : str
        Panel of the figure this table is drawn in (set label, or resolution for Fig. 17).
    axis_name : str
        Name (with unit) of the first column: ``band_centre_hz``, or e.g. ``speed_kmh`` for a table against speed
        (then ``band_centres`` holds those values).
    """

    name: str
    figure: str
    title: str
    band_centres: np.ndarray
    columns: dict[str, np.ndarray]
    panel: str = ""
    axis_name: str = "band_centre_hz"

    def header(self) -> list[str]:
        return [self.axis_name, *self.columns]


def write_table(table: Table, folder: Path) -> Path:
    """Write ``table`` as ``folder/<name>.csv`` atomically (header row, then one row per band)."""
    path = folder / f"{table.name}.csv"

    def write(handle):
        handle.write(",".join(table.header()) + "\n")
        for i, centre in enumerate(table.band_centres):
            cells = [f"{centre:.2f}"] + [
                ("nan" if not np.isfinite(v[i]) else f"{v[i]:.3f}") for v in table.columns.values()
            ]
            handle.write(",".join(cells) + "\n")

    atomic_write(path, write, mode="w", encoding="utf-8")
    return path
