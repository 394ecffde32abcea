"""Study tables: one CSV per figure table, the bands (nominal name and exact centre in Hz) and one column per
curve in dB."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wheelrail.core.files.atomic import atomic_write


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
        """The CSV header: ``band,centre_hz`` (nominal name, exact centre) for bands, else the axis's name."""
        axis = ["band", "centre_hz"] if self.axis_name == "band_centre_hz" else [self.axis_name]
        return [*axis, *self.columns]


def write_table(table: Table, folder: Path) -> Path:
    """Write ``table`` as ``folder/<name>.csv`` atomically (header row, then one row per band)."""
    path = folder / f"{table.name}.csv"

    from wheelrail.core.spectra.bands import nominal_band_label

    bands = table.axis_name == "band_centre_hz"

    def write(handle):
        handle.write(",".join(table.header()) + "\n")
        for i, centre in enumerate(table.band_centres):
            axis = [nominal_band_label(centre), f"{centre:.6g}"] if bands else [f"{centre:.6g}"]
            cells = axis + [("nan" if not np.isfinite(v[i]) else f"{v[i]:.3f}") for v in table.columns.values()]
            handle.write(",".join(cells) + "\n")

    atomic_write(path, write, mode="w", encoding="utf-8")
    return path
