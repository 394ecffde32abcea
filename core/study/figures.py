"""Study figures: each study's tables drawn like the paper's figure (matplotlib, Agg backend, PNG)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wheelrail.core.drawing.palette import CNOSSOS_COLOURS, model_colour
from wheelrail.core.files.atomic import atomic_write
from wheelrail.core.models import model_names
from wheelrail.core.parameters import KMH, RunParameters
from wheelrail.core.study.tables import Table

__all__ = ["model_of", "model_style", "plot_study", "study_figures"]

# the columns at the paper's speed (the dataclass default, 100 km/h) are marked in the speed figure
_REFERENCE_SPEED_COLUMN = f"{RunParameters().speed / KMH:g}_kmh"

_MODEL_LINES = {  # Fig. 10's legend: thick 3D, then the one-line models; colours: core's palette
    "3d": {"linewidth": 3.0, "label": "3D"},
    "2d": {"linewidth": 1.2, "label": "2D"},
    "hertz": {"linewidth": 1.0, "linestyle": ":", "label": "Hertz, no pre-filter"},
    "hertz-winkler": {"linewidth": 1.0, "linestyle": "--", "label": "Hertz, Winkler pre-filter"},
    "hertz-average": {"linewidth": 1.0, "linestyle": "-.", "label": "Hertz, averaging pre-filter"},
}
_STYLES = {
    # reference filters for the runs' load and wheel (dashed, thin), beside the dynamic ones
    "ref_cnossos_db": {  # black as in the explorer's Spectra tab (dashed here, so apart from the solid 2D)
        "color": CNOSSOS_COLOURS["total"],
        "linewidth": 1.0,
        "linestyle": (0, (5, 2)),
        "label": "CNOSSOS-EU A3",
    },
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


def model_of(column: str) -> str | None:
    """The contact model whose name begins a table column ("hertz_winkler_LWA_dBA": hertz-winkler), or None."""
    for model in sorted(model_names(), key=len, reverse=True):  # hertz_winkler_... before hertz_...
        if column.startswith(model.replace("-", "_") + "_"):
            return model
    return None


def model_style(column: str) -> dict:
    """matplotlib keywords of a model's level column ("hertz_winkler_db"): the model's colour of core's palette,
    its Fig. 10 line and label; other columns: their reference style, or just their name as the label."""
    if column in _STYLES:
        return _STYLES[column]
    model = model_of(column)
    if model is None:
        return {"label": column}
    return {"color": model_colour(model, model_names()), **_MODEL_LINES.get(model, {"label": model})}


def _axes_grid(n_rows: int, n_cols: int, *, height: float = 2.6):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(5.0 * n_cols, height * n_rows + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(n_rows, n_cols, squeeze=False)
    return figure, axes


_OCTAVES = ("63", "125", "250", "500", "1000", "2000", "4000", "8000")


def _frequency_axis(ax, table: Table, ylabel: str, names: tuple[str, ...] = _OCTAVES) -> None:
    """A log band axis ticked at the bands ``names`` (nominal), its label and ``ylabel``."""
    from wheelrail.core.spectra.bands import nominal_band_label

    ax.set_xscale("log")
    ticks = [c for c in table.band_centres if nominal_band_label(c) in names]
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
                ax.plot(table.band_centres, values, **model_style(column))
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
    "track": "per track, on line 0: force level, sound power per axle and pass-by level",
    "track-force": "contact-force levels per track, one panel per model, on line 0",
    "impact": "peak force and sound power per axle against speed per model and irregularity case, on line 0",
}
_TITLE_CHARACTERS = 150  # a suptitle line at 9 pt fits a 14 inch figure


def _noise_style(column: str) -> dict:
    """A noise study column's line: its model's palette colour (black: A3), solid for the model, dashed for
    CNOSSOS-EU with the model's filter, dotted for a variant (the modal wheel's transfer)."""
    cnossos = column.startswith("cnossos_")
    body = column.removeprefix("cnossos_")
    model = model_of(body)
    exact = model is not None and body.removeprefix(model.replace("-", "_") + "_") in ("LWA_dBA", "LpAeq_dBA")
    return {
        "color": "k" if model is None else model_colour(model, model_names()),
        "linestyle": "--" if cnossos else ("-" if exact else ":"),
        "label": column.removesuffix("_dBA").removesuffix("_db").replace("_", " "),
    }


def _draw_noise(group: list[Table], figure_id: str):
    """The noise study: one panel per set; levels against speed (or per band for the filters table)."""
    fig, axes = _axes_grid(1, len(group), height=3.4)
    for ax, table in zip(np.ravel(axes), group, strict=False):
        x = np.asarray(table.band_centres, dtype=float)
        levels = {c: v for c, v in table.columns.items() if c.lower().endswith(("_db", "_dba"))}  # not the inputs
        for column, values in levels.items():
            ax.plot(x, values, marker="o", ms=2.5, lw=1.2, **_noise_style(column))
        if table.axis_name == "band_centre_hz":
            ax.set_xscale("log")
            ax.set_xlabel("frequency (Hz)")
        else:
            ax.set_xlabel({"speed_kmh": "speed (km/h)"}.get(table.axis_name, table.axis_name))
        ax.set_title(table.panel, fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=5, ncol=2)
    return fig


def _track_axis(table: Table) -> tuple[np.ndarray, list[str], str]:
    """The tracks of a track study's noise table on an x axis: (positions, tick labels, axis label). One swept
    input: its values in its option's units; several: one position per track, ticked with each one's values."""
    from wheelrail.core.inputs.declared import inputs_of

    swept = [entry for entry in inputs_of("track") if entry.dest in table.columns]
    if len(table.band_centres) == 1:
        swept = []  # one track: nothing is swept (the columns hold every input)
    values = [np.asarray(table.columns[entry.dest], dtype=float) for entry in swept]
    units = [f"{entry.label.lower()}{f' ({entry.shown.name})' if entry.shown.name else ''}" for entry in swept]
    if len(swept) == 1:
        return values[0], [f"{v:g}" for v in values[0]], units[0]
    ticks = ["\n".join(f"{v[k]:g}" for v in values) for k in range(len(table.band_centres))] if swept else ["track"]
    return np.arange(1.0, len(table.band_centres) + 1), ticks, "track: " + ", ".join(units) if swept else "track"


def track_labels(table: Table) -> list[str]:
    """Each track of a track study's noise table by its swept values ("pad stiffness 60 MN/m")."""
    from wheelrail.core.inputs.declared import inputs_of

    swept = [entry for entry in inputs_of("track") if entry.dest in table.columns]
    if len(table.band_centres) == 1 or not swept:
        return ["the track"] * len(table.band_centres)
    return [
        ", ".join(entry.words(table.columns[entry.dest][k] * entry.shown.si) for entry in swept)
        for k in range(len(table.band_centres))
    ]


_TRACK_PANELS = (  # the summary figure of the track study: (column suffix, panel title, y label)
    ("force_dB", "overall dynamic contact force", "L_F (dB re 1 N)"),
    ("LWA_dBA", "sound power per axle", "L_WA (dB(A) re 1 pW)"),
    ("LpAeq_dBA", "pass-by level at 7.5 m", "L_pAeq,Tp (dB(A))"),
)
_PARTS_MODEL = "3d"  # whose rail, sleeper and wheel the last panel splits (the paper's full model; else the first)


def _draw_track(group: list[Table]):
    """The track study's summary: one row per set; force, sound power and pass-by level per model against the
    swept input, and one model's rail, sleeper and wheel sound power (colour: the part)."""
    from wheelrail.core.noise.components import noise_components

    figure, axes = _axes_grid(len(group), len(_TRACK_PANELS) + 1, height=3.6)
    figure.set_size_inches(14.0, 3.8 * len(group) + 1.0)
    for row, table in enumerate(group):
        x, ticks, x_label = _track_axis(table)
        models = [m for m in model_names() if f"{m.replace('-', '_')}_LWA_dBA" in table.columns]
        for ax, (suffix, title, y_label) in zip(axes[row], _TRACK_PANELS, strict=False):
            for model in models:
                values = table.columns[f"{model.replace('-', '_')}_{suffix}"]
                ax.plot(x, values, marker="o", ms=3, lw=1.4, color=model_colour(model, model_names()), label=model)
            ax.set(ylabel=y_label, title=f"{table.panel}\n{title}")
        ax = axes[row, -1]
        split = _PARTS_MODEL if _PARTS_MODEL in models else models[0]
        column = {part: f"{split.replace('-', '_')}_{part.name}_LWA_dBA" for part in noise_components()}
        parts = [part for part in noise_components() if column[part] in table.columns]
        for part in parts:
            values = table.columns[column[part]]
            ax.plot(x, values, color=part.colour, marker="o", ms=3, lw=1.4, label=part.label)
        words = ", ".join(part.label for part in parts)
        ax.set(ylabel="L_WA (dB(A) re 1 pW)", title=f"{table.panel}\n{words} per axle ({split})")
        for ax in axes[row]:
            ax.set_xticks(x, ticks)
            ax.set_xlabel(x_label)
            ax.grid(True, alpha=0.3)
            ax.title.set_fontsize(9)
            ax.legend(fontsize=7)
    return figure


def _draw_track_force(group: list[Table], noise: dict[str, Table]):
    """The track study's force spectra: per set a row, per model a panel, one curve per track (its values)."""
    from wheelrail.core.drawing.patch import colour_table

    models = sorted({model_of(c) for t in group for c in t.columns} - {None}, key=list(model_names()).index)
    figure, axes = _axes_grid(len(group), len(models), height=3.2)
    figure.set_size_inches(max(3.2 * len(models), 8.0), 3.2 * len(group) + 1.0)
    for row, table in enumerate(group):
        labels = track_labels(noise[table.panel]) if table.panel in noise else []
        for ax, model in zip(axes[row], models, strict=True):
            columns = [c for c in table.columns if model_of(c) == model]
            # tracks in order along viridis (dark to green-yellow; its palest end is too faint on white)
            colours = colour_table()[np.linspace(0, 200, max(len(columns), 2)).astype(int)] / 255.0
            for k, column in enumerate(columns):
                label = labels[k] if k < len(labels) else column
                ax.plot(table.band_centres, table.columns[column], color=colours[k], lw=1.2, label=label)
            _frequency_axis(ax, table, "L_F (dB re 1 N)", names=("63", "250", "1000", "4000"))
            ax.set_title(f"{table.panel}: {model}", fontsize=9)
            ax.legend(fontsize=6)
    return figure


def study_figures(name: str, tables: list[Table], caption: str = "") -> dict[str, object]:
    """The study's figures (matplotlib Figures, Agg) by file name, each titled with the study and ``caption``
    (what its runs share: :func:`wheelrail.core.study.runner.study_caption`)."""
    import textwrap

    by_figure: dict[str, list[Table]] = {}
    for table in tables:
        by_figure.setdefault(table.figure, []).append(table)
    noise = {t.panel: t for t in by_figure.get("track", [])}
    figures = {}
    for figure_id, group in by_figure.items():
        if figure_id == "impact-loss":
            continue  # its numbers are drawn in the impact figure
        if figure_id == "impact":
            from wheelrail.core.study.impact_figures import draw_impact

            figure, what = draw_impact(group, _axes_grid), _NOISE_TITLES[figure_id]
        elif figure_id == "track":
            figure, what = _draw_track(group), _NOISE_TITLES[figure_id]
        elif figure_id == "track-force":
            figure, what = _draw_track_force(group, noise), _NOISE_TITLES[figure_id]
        elif figure_id.startswith("noise"):
            figure, what = _draw_noise(group, figure_id), _NOISE_TITLES[figure_id]
        elif figure_id == "10":
            figure, what = _draw_filters(group), f"paper Fig. {figure_id}"
        elif figure_id in ("12", "13", "14", "11"):
            figure, what = _draw_per_line(group, figure_id), f"paper Fig. {figure_id}"
        else:
            figure, what = _draw_per_set(group), f"paper Fig. {figure_id}"
        title = f"wheelrail study {name}: {what}" + (f". {caption}" if caption else "")
        width = max(60, int(_TITLE_CHARACTERS * figure.get_figwidth() / 14.0))
        figure.suptitle("\n".join(textwrap.wrap(title, width)), fontsize=9)
        own = figure_id.startswith(("noise", "track", "impact"))  # the project's own figures; the others the paper's
        stem = f"{figure_id.replace('-', '_')}_{name}" if own else f"fig{figure_id}_{name}"
        figures[f"{stem}.png"] = figure
    return figures


def plot_study(name: str, tables: list[Table], folder: Path, caption: str = "", workers: int = 1) -> list[Path]:
    """Draw the study's figure(s) like the paper's (:func:`study_figures`; Agg backend, PNG) into ``folder``;
    returns the paths. With two or more ``workers`` they are drawn on two processes where the study's process may
    fork (:func:`~wheelrail.core.study.figure_workers.png_files`: the same bytes)."""
    from wheelrail.core.study.figure_workers import png_files

    paths = []
    for file_name, png in png_files(study_figures(name, tables, caption), dpi=110, workers=workers).items():
        path = folder / file_name
        atomic_write(path, lambda handle, data=png: handle.write(data))
        paths.append(path)
    return paths
