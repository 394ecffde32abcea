"""What a study does once, or beside its runs, rather than after them: Fig. 10's reference filters worked out once
for the sets on the same bands (their module imported beside the runs), and a figure cut from the tight boxes of the
two rows beside the cut."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.spectra.bands import frequency_bands
from wheelrail.core.study import forked, plans
from wheelrail.core.study.plans import plan_study
from wheelrail.core.study.specs import RunSummary

SETS = ["corrugated-rail", "cast-iron-wheel"]


def _summaries(plan) -> dict[str, RunSummary]:
    """Every run's summary on the force spectra's bands (levels made up, the same bands for every run)."""
    centres = frequency_bands(plan.speed).centres
    rng = np.random.default_rng(3)
    return {
        spec.key: RunSummary(
            key=spec.key,
            band_centres=centres,
            levels=80 + 10 * rng.random(len(centres)),
            force_mean=1.0,
            force_std=0.1,
            force_min=0.5,
            force_max=1.5,
            loss_of_contact_steps=0,
            n_steps=100,
            run_time=0.0,
        )  # fmt: skip
        for spec in plan.specs
    }


def test_fig10_tables_work_out_the_reference_filters_once_for_sets_on_the_same_bands(monkeypatch):
    plan = plan_study("filters", SETS)
    summaries = _summaries(plan)
    reference = plan.tabulate(summaries)
    calls = []
    columns = plans._reference_columns
    monkeypatch.setattr(plans, "_reference_columns", lambda *args: calls.append(args) or columns(*args))
    tables = plan.tabulate(summaries)
    assert len(calls) == 1  # two sets, one band range
    assert [t.name for t in tables] == [t.name for t in reference]
    for table, before in zip(tables, reference, strict=True):
        assert table.columns.keys() == before.columns.keys()
        for name, values in table.columns.items():
            np.testing.assert_array_equal(values, before.columns[name])
    filters = [t for t in tables if t.name.endswith("contact_filters")]
    assert filters[0].columns["ref_cnossos_db"] is not filters[1].columns["ref_cnossos_db"]  # each table its own


def test_fig10_plan_imports_the_reference_filters_beside_the_runs():
    plan = plan_study("filters", SETS[:1])
    assert plans._import_reference_filters in plan.beside
    plans._import_reference_filters()  # imports, returns nothing


def _fig10_tables(sets: int) -> list:
    """Fig. 10's tables, one pair a set (one row of two panels each), levels made up."""
    from wheelrail.core.study.tables import Table

    centres = frequency_bands(None).centres
    rng = np.random.default_rng(2)
    return [
        Table(
            name=f"fig10_s{k}_{kind}",
            figure="10",
            panel=f"set {k}",
            title=kind,
            band_centres=centres,
            columns={f"{m}_db": 80 + 20 * rng.random(len(centres)) for m in ("3d", "hertz", "2d")},
        )  # fmt: skip
        for k in range(sets)
        for kind in ("force_levels", "contact_filters")
    ]


@pytest.mark.skipif(forked.fork_refusal() == "forked workers need Linux", reason="forks on Linux only")
def test_a_figure_is_cut_from_the_tight_boxes_of_the_two_rows_beside_the_cut_and_its_png_is_savefigs(monkeypatch):
    import io

    from matplotlib.axes import Axes

    from wheelrail.core.study import figure_workers, shutdown_pools
    from wheelrail.core.study.figures import study_figures

    shutdown_pools()  # no kept pool's manager thread: the figure's halves are drawn on a fork
    (figure,) = study_figures("filters", _fig10_tables(4), "caption").values()
    figure.dpi = 110
    figure.get_layout_engine().execute(figure)  # laid out here: the cut alone is counted
    figure.set_layout_engine("none")
    boxes = []
    tight = Axes.get_tightbbox
    monkeypatch.setattr(
        Axes, "get_tightbbox", lambda ax, *args, **kwargs: boxes.append(ax) or tight(ax, *args, **kwargs)
    )
    row, above, below = figure_workers._cut(figure, 110)
    assert len(boxes) == 4  # rows 2 and 3 of 4, two panels each
    assert len(below) == 4 and sum(ax in figure.axes for ax in above) == 4
    monkeypatch.undo()
    (whole,) = study_figures("filters", _fig10_tables(4), "caption").values()
    handle = io.BytesIO()
    whole.savefig(handle, format="png", dpi=110)
    (drawn,) = figure_workers.png_files(study_figures("filters", _fig10_tables(4), "caption"), 110, workers=2).values()
    assert drawn == handle.getvalue()
