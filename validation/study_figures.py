"""The figures the README quotes from the five studies on the bundled sets, read off the study tables.

Run the studies into one folder first, then this script on it:

    for s in filters line-spread averaged-input lateral-resolution speeds; do
        wheelrail study $s --set corrugated-rail --set cast-iron-wheel --set sinter-wheel-1 \
            --set sinter-wheel-2 --out DIR
    done
    python3 validation/study_figures.py DIR

Prints, per set: L_3D - L_2D (Fig. 12: the mean over lines -3..3 and single lines, min and max over the bands),
2D against the Winkler and averaging pre-filters (Figs 13-14: largest |mean|), the averaged input (Fig. 16:
largest |L_3D - L_2D,av| up to 2 kHz, and in the 2.5 and 5 kHz bands) and the lateral resolution (Fig. 17:
largest |difference| up to 2 kHz for 4 and 8 mm).
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

SETS = ("corrugated-rail", "cast-iron-wheel", "sinter-wheel-1", "sinter-wheel-2")


def _table(path: Path) -> dict[str, np.ndarray]:
    with open(path) as handle:
        rows = list(csv.reader(handle))
    columns = list(zip(*rows[1:], strict=True))
    return {
        name: np.array([float(v) if v not in ("", "nan") else np.nan for v in col])
        for name, col in zip(rows[0], columns, strict=True)
    }


def _lines(table: dict[str, np.ndarray]) -> np.ndarray:
    return np.array([v for k, v in table.items() if k.startswith("line_")])


def main() -> None:
    folder = Path(sys.argv[1])
    print("Fig. 12, L_3D - L_2D (dB): mean over lines min..max | single lines min..max")
    for name in SETS:
        t = _table(folder / f"fig12_{name}_3d_minus_2d.csv")
        print(
            f"  {name:16s} {np.nanmin(t['mean_db']):6.1f} .. {np.nanmax(t['mean_db']):5.1f} | "
            f"{np.nanmin(_lines(t)):6.1f} .. {np.nanmax(_lines(t)):5.1f}"
        )
    for fig, what in (("13", "hertz_winkler"), ("14", "hertz_average")):
        print(f"Fig. {fig}, L_2D - L_{what} (dB): largest |mean over lines|")
        for name in SETS:
            t = _table(folder / f"fig{fig}_{name}_2d_minus_{what}.csv")
            print(f"  {name:16s} {np.nanmax(np.abs(t['mean_db'])):5.1f}")
    t = _table(folder / "fig16_3d_minus_2d_averaged_input.csv")
    f = t["centre_hz"]
    print("Fig. 16, |L_3D - L_2D,av| (dB): largest up to 2 kHz (its band) | 2.5 kHz | 5 kHz")
    for name in SETS:
        column = next(v for k, v in t.items() if k.startswith(name))
        low = f < 2100
        worst = int(np.nanargmax(np.abs(np.where(low, column, np.nan))))
        at = [float(np.abs(column[np.argmin(np.abs(f - c))])) for c in (2512, 5012)]
        print(f"  {name:16s} {abs(column[worst]):5.1f} ({f[worst]:.0f} Hz) | {at[0]:5.1f} | {at[1]:5.1f}")
    for spacing in ("4mm", "8mm"):
        t = _table(folder / f"fig17_3d_minus_3d_{spacing}.csv")
        f = t["centre_hz"]
        print(f"Fig. 17, 3D on all lines - 3D on lines {spacing} apart (dB): largest |difference| up to 2 kHz")
        for name in SETS:
            column = next(v for k, v in t.items() if k.startswith(name))
            print(f"  {name:16s} {np.nanmax(np.abs(column[f < 2100])):5.1f}")


if __name__ == "__main__":
    main()
