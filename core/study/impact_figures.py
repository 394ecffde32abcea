"""The impact study's figure: per set and irregularity case, the peak force against speed per model (the first
speed with loss of contact marked) and the sound power per axle against speed with its slope in dB per doubling."""

from __future__ import annotations

import numpy as np

from wheelrail.core.drawing.palette import model_colour
from wheelrail.core.models import model_names
from wheelrail.core.study.tables import Table

__all__ = ["draw_impact"]


def _models(table: Table) -> list[str]:
    return [m for m in model_names() if f"{m.replace('-', '_')}_peak_force_n" in table.columns]


def draw_impact(group: list[Table], axes_grid):
    """One row per case table of ``group`` (``impact_<set>_case<k>``): left the peak force (kN) against speed
    per model, an open ring on the first speed with loss of contact (a dotted line to the axis), the preload
    dashed; right the sound power per axle against speed with its least-squares slope in the legend.
    ``axes_grid(rows, cols, height=...)`` is the study figures' own."""
    from wheelrail.core.study.impact_plan import first_loss_speed, noise_slope

    figure, axes = axes_grid(len(group), 2, height=3.2)
    figure.set_size_inches(11.0, 3.4 * len(group) + 1.0)
    for row, table in enumerate(group):
        v = np.asarray(table.band_centres, dtype=float)
        force_ax, noise_ax = axes[row]
        for model in _models(table):
            name, colour = model.replace("-", "_"), model_colour(model, model_names())
            peak = np.asarray(table.columns[f"{name}_peak_force_n"]) / 1e3
            force_ax.plot(v, peak, marker="o", ms=3, lw=1.4, color=colour, label=model)
            lost = first_loss_speed(v, np.asarray(table.columns[f"{name}_time_without_contact_ms"]))
            if np.isfinite(lost):
                k = int(np.flatnonzero(v == lost)[0])
                force_ax.plot([lost], [peak[k]], marker="o", ms=9, mfc="none", mec=colour, lw=0)
                force_ax.axvline(lost, color=colour, ls=":", lw=0.8, label=f"{model}: contact lost from {lost:g} km/h")
            lwa = np.asarray(table.columns[f"{name}_LWA_dBA"])
            slope = noise_slope(v, lwa)
            words = f"{model}: {slope:+.1f} dB per doubling" if np.isfinite(slope) else model
            noise_ax.plot(v, lwa, marker="o", ms=3, lw=1.4, color=colour, label=words)
        title = f"{table.panel}\npeak force"
        force_ax.set(xlabel="speed (km/h)", ylabel="peak force (kN)", title=title, ylim=(0, None))
        noise_ax.set(
            xlabel="speed (km/h)",
            ylabel="L_WA per axle (dB(A) re 1 pW)",
            title=f"{table.panel}\nsound power per axle (run's force as stationary)",
            xscale="log",
        )
        noise_ax.set_xticks(v, [f"{x:g}" for x in v])
        noise_ax.minorticks_off()
        for ax in (force_ax, noise_ax):
            ax.grid(True, alpha=0.3)
            ax.title.set_fontsize(9)
            ax.legend(fontsize=6)
    return figure
