"""Study figures: each study's tables drawn like the paper's figure (matplotlib, Agg backend, PNG)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wheelrail.core.atomic import atomic_write
from wheelrail.core.parameters import KMH, RunParameters
from wheelrail.core.study.tables import Table

# the columns at the paper's speed (the dataclass default, 100 km/h) are marked in the speed figure
_REFERENCE_SPEED_COLUMN = f"{RunParameters().speed / KMH:g}_kmh"

_STYLES = {  # Fig. 10's legend: thick grey 3D, then the one-line models
    "3d_db": {"color": "0.55", "linewidth": 3.0, "label": "3D"},
    "2d_db": {"color": "k", "linewidth": 1.2, "label": "2D"},
    "hertz_db": {"color": "tab:red", "linewidth": 1.0, "linestyle": ":", "label": "Hertz, no pre-filter"},
    "hertz_winkler_db": {
        "color": "tab:blue",
        "linewidth": 1.0,
        "linestyle": "--",
        "label": "Hertz, Winkler pre-filter",
    },
    "hertz_average_db": {
        "color": "tab:green",
        "linewidth": 1.0,
        "linestyle": "-.",
        "label": "Hertz, averaging pre-filter",
    },
    # reference filters for the runs' load and wheel (dashed, thin), beside the dynamic ones
    "ref_cnossos_db": {"color": "tab:purple", "linewidth": 1.0, "linestyle": (0, (5, 2)), "label": "CNOSSOS-EU A3"},
    "ref_averaging_db": {
        "color": "0.3",
        "linewidth": 0.8,
        "linestyle": (0, (3, 2)),
        "label": "analytic: averaging over 2a",
    },
    "ref_patch_correlated_db": {
        "color": "tab:olive",
        "linewidth": 0.8,
        "linestyle": (0, (3, 2)),
        "label": "analytic: circular patch, correlated",
    },
    "ref_patch_incoherent_db": {
        "color": "tab:cyan",
        "linewidth": 0.8,
        "linestyle": (0, (3, 2)),
        "label": "circular patch, incoherent (this project's construction)",
    },
}
_SET_STYLES = ("-", "--", "-.", ":")


def _axes_grid(n_rows: int, n_cols: int, *, height: float = 2.6):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(5.0 * n_cols, height * n_rows + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(n_rows, n_cols, squeeze=False)
    return figure, axes


def _frequency_axis(ax, table: Table, ylabel: str) -> None:
    from wheelrail.core.spectra import nominal_band_label

    ax.set_xscale("log")
    ticks = [
        c
        for c in table.band_centres
        if nominal_band_label(c) in ("63", "125", "250", "500", "1000", "2000", "4000", "8000")
    ]
    ax.set_xticks(ticks, [nominal_band_label(c) for c in ticks])
    ax.minorticks_off()
    ax.set_xlabel("third-octave band centre frequency (Hz)")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)


def _draw_filters(group: list[Table]):
    """Fig. 10: one row per set, force levels left, contact filters right."""
    panels = sorted({t.panel for t in group}, key=[t.panel for t in group].index)
    figure, axes = _axes_grid(len(panels), 2)
    for row, panel in enumerate(panels):
        levels = next(t for t in group if t.panel == panel and t.name.endswith("force_levels"))
        filters = next(t for t in group if t.panel == panel and t.name.endswith("contact_filters"))
        for ax, table, ylabel in (
            (axes[row, 0], levels, "L_F (dB re 1 N)"),
            (axes[row, 1], filters, "contact filter (dB)"),
        ):
            for column, values in table.columns.items():
                ax.plot(table.band_centres, values, **_STYLES.get(column, {"label": column}))
            _frequency_axis(ax, table, ylabel)
            ax.set_title(panel, fontsize=9)
        axes[row, 0].legend(fontsize=7)
        axes[row, 1].legend(fontsize=6)
    return figure


def _draw_per_line(group: list[Table], figure_id: str):
    """Figs 12-14 (one curve per line and the mean) and 11 (one curve per speed): one panel per set."""
    figure, axes = _axes_grid(len(group), 1)
    for ax, table in zip(axes[:, 0], group, strict=True):
        for column, values in table.columns.items():
            if column == "mean_db":
                ax.plot(table.band_centres, values, color="k", linewidth=2.5, label="mean")
            else:
                ax.plot(
                    table.band_centres,
                    values,
                    linewidth=0.9,
                    label=column.removesuffix("_db").replace("_", " "),
                    marker="x" if column.startswith(_REFERENCE_SPEED_COLUMN) else None,
                )
        _frequency_axis(ax, table, "L_F (dB re 1 N)" if figure_id == "11" else "level difference (dB)")
        ax.set_title(table.title, fontsize=9)
        ax.legend(fontsize=6, ncol=2)
    return figure


def _draw_per_set(group: list[Table]):
    """Figs 16, 17: one curve per set, one panel per table."""
    figure, axes = _axes_grid(len(group), 1)
    for ax, table in zip(axes[:, 0], group, strict=True):
        for i, (column, values) in enumerate(table.columns.items()):
            ax.plot(
                table.band_centres,
                values,
                color="k",
                linestyle=_SET_STYLES[i % len(_SET_STYLES)],
                label=column.removesuffix("_db"),
            )
        ax.axhline(0.0, color="0.7", linewidth=0.8)
        _frequency_axis(ax, table, "level difference (dB)")
        ax.set_title(table.title, fontsize=9)
        ax.legend(fontsize=7)
    return figure


_NOISE_TITLES = {
    "noise": "A-weighted sound power per axle, dB(A) re 1 pW (dashed: CNOSSOS-EU)",
    "noise-lpaeq": "pass-by L_pAeq,Tp at 7.5 m / 1.2 m, dB(A) (dashed: CNOSSOS-EU)",
    "noise-filters": "contact filters (dB) and CNOSSOS-EU sound power per axle (dB re 1 pW) per band",
    "track": "per track: force level (dB re 1 N), sound power per axle and pass-by level (dB(A))",
    "track-force": "contact-force levels per model and track, dB re 1 N",
}


def _draw_noise(group: list[Table], figure_id: str):
    """The noise study: one panel per set; levels against speed (or per band for the filters table)."""
    fig, axes = _axes_grid(1, len(group), height=3.4)
    for ax, table in zip(np.ravel(axes), group, strict=False):
        x = np.asarray(table.band_centres, dtype=float)
        levels = {c: v for c, v in table.columns.items() if c.lower().endswith(("_db", "_dba"))}  # not the inputs
        for i, (column, values) in enumerate(levels.items()):
            style = "--" if column.startswith("cnossos") else "-"
            ax.plot(x, values, style, color=f"C{i % 10}", marker="o", ms=2.5, lw=1.2, label=column)
        if table.axis_name == "band_centre_hz":
            ax.set_xscale("log")
            ax.set_xlabel("frequency (Hz)")
        else:
            ax.set_xlabel({"speed_kmh": "speed (km/h)", "track": "track number"}.get(table.axis_name, table.axis_name))
        ax.set_title(table.panel, fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=5, ncol=2)
    return fig


def plot_study(name: str, tables: list[Table], folder: Path) -> list[Path]:
    """Draw the study's figure(s) like the paper's (Agg backend, PNG) into ``folder``; returns the paths."""
    by_figure: dict[str, list[Table]] = {}
    for table in tables:
        by_figure.setdefault(table.figure, []).append(table)
    paths = []
    for figure_id, group in by_figure.items():
        if figure_id.startswith(("noise", "track")):
            figure = _draw_noise(group, figure_id)
            figure.suptitle(f"wheelrail study {name}: {_NOISE_TITLES[figure_id]}", fontsize=9)
            path = folder / f"{figure_id.replace('-', '_')}_{name}.png"
            atomic_write(path, lambda handle, fig=figure: fig.savefig(handle, format="png", dpi=110))
            paths.append(path)
            continue
        if figure_id == "10":
            figure = _draw_filters(group)
        elif figure_id in ("12", "13", "14", "11"):
            figure = _draw_per_line(group, figure_id)
        else:
            figure = _draw_per_set(group)
        figure.suptitle(f"wheelrail study {name}: paper Fig. {figure_id}", fontsize=10)
        path = folder / f"fig{figure_id}_{name}.png"
        atomic_write(path, lambda handle, fig=figure: fig.savefig(handle, format="png", dpi=110))
        paths.append(path)
    return paths
