"""
Model differences on the wheel sets (paper Figs 12-14, 16 and 17)
=================================================================

The studies behind the paper's section 3.4-3.5, on the bundled sinter wheel 1 with short runs (1 m of each
line instead of the whole 2.9 m circumference, so the levels scatter more than in the paper):

* Fig. 12: L_3D - L_2D on each of the lines -3..3 and their mean (the 3D model sees the lateral
  variation of the roughness, the 2D model one line);
* Figs 13 and 14: L_2D - L_hertz-winkler and L_2D - L_hertz-average (the pre-filtered Hertz springs);
* Fig. 16: L_3D - L_2D,av, the 2D model fed with the mean of the lines;
* Fig. 17: L_3D on every line against the 3D model on lines 4 mm and 8 mm apart.

The runs go through :func:`wheelrail.core.study.run_study` in this process (``workers=1``); the studies
share one folder, so a run that two studies need is computed once. ``wheelrail study NAME --set SET`` runs
the same on a process pool or a Dask cluster, over whole sets.
"""

import os
from pathlib import Path

import matplotlib.pyplot as plt

from wheelrail.core.study import run_study

out = Path(os.environ.get("WHEELRAIL_GALLERY_OUT", "gallery-output")) / "model-differences"
tables = []
for study in ("line-spread", "averaged-input", "lateral-resolution"):
    result = run_study(study, ["sinter-wheel-1"], out, length=1.0, workers=1, progress=False, figures=False)
    tables += result.tables

fig, axes = plt.subplots(2, 3, figsize=(12, 6.4), sharex=True)
for ax, table in zip(axes.flat, tables, strict=True):
    for column, values in table.columns.items():
        mean = column == "mean_db"
        ax.semilogx(
            table.band_centres,
            values,
            color="k" if mean else None,
            linewidth=2.2 if mean else 0.8,
            label=column.removesuffix("_db"),
        )
    ax.axhline(0.0, color="0.7", linewidth=0.8)
    ax.set_title(f"Fig. {table.figure}: {table.title}".replace(": ", ":\n", 1), fontsize=8)
    ax.set_ylim(-15, 15)
axes[0, 0].legend(fontsize=6, ncol=2)
for ax in axes[1]:
    ax.set_xlabel("frequency (Hz)")
for ax in axes[:, 0]:
    ax.set_ylabel("level difference (dB)")
fig.tight_layout()
