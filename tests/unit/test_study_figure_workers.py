"""A study's figures drawn on two processes (``core.study.figure_workers``): byte for byte the PNGs ``savefig``
writes, for one figure cut between two rows of panels, for several figures shared out, and for one row drawn whole."""

from __future__ import annotations

import io
import multiprocessing
import os

import numpy as np
import pytest

from wheelrail.core.study import figure_workers, forked
from wheelrail.core.study.figures import study_figures
from wheelrail.core.study.tables import Table

pytestmark = pytest.mark.skipif(forked.fork_refusal() == "forked workers need Linux", reason="forks on Linux only")


@pytest.fixture(autouse=True)
def no_kept_pool():
    """No process pool kept by an earlier test (its manager thread would rule the fork out)."""
    from wheelrail.core.study import shutdown_pools

    shutdown_pools()


CENTRES = 1000.0 * 10.0 ** (np.arange(-13, 10) / 10)


def _filters_tables(sets: int) -> list[Table]:
    """Fig. 10's tables, one pair a set: one row of two panels each in the figure."""
    rng = np.random.default_rng(2)
    tables = []
    for k in range(sets):
        for kind in ("force_levels", "contact_filters"):
            columns = {f"{m}_db": 80 + 20 * rng.random(len(CENTRES)) for m in ("3d", "hertz", "2d")}
            tables.append(Table(name=f"fig10_s{k}_{kind}", figure="10", panel=f"set {k}", columns=columns,
                                title=kind, band_centres=CENTRES))  # fmt: skip
    return tables


def _reference(figures: dict) -> dict[str, bytes]:
    out = {}
    for name, figure in figures.items():
        handle = io.BytesIO()
        figure.savefig(handle, format="png", dpi=110)
        out[name] = handle.getvalue()
    return out


@pytest.mark.parametrize("sets", [1, 3])
def test_one_figure_is_cut_between_rows_and_put_back_together_to_the_byte(sets, monkeypatch):
    cuts = []
    cut = figure_workers._cut
    monkeypatch.setattr(figure_workers, "_cut", lambda *args: cuts.append(cut(*args)) or cuts[-1])
    reference = _reference(study_figures("filters", _filters_tables(sets), "caption"))
    drawn = figure_workers.png_files(study_figures("filters", _filters_tables(sets), "caption"), dpi=110, workers=2)
    assert drawn == reference
    assert [cut is not None for cut in cuts] == [sets > 1]  # one row: drawn whole here
    assert not multiprocessing.active_children()


def test_several_figures_are_shared_out_whole(monkeypatch):
    from tests.unit.test_study_figures import _track_tables

    drawn_here = []
    png = figure_workers._png
    monkeypatch.setattr(figure_workers, "_png", lambda figure, dpi: drawn_here.append(figure) or png(figure, dpi))
    reference = _reference(study_figures("track", _track_tables(), "caption"))
    figures = study_figures("track", _track_tables(), "caption")
    drawn_here.clear()
    assert figure_workers.png_files(figures, dpi=110, workers=2) == reference
    assert len(drawn_here) == 1  # the other in the child (whose calls this process does not see)


def test_a_failure_in_the_figure_child_is_raised_here(monkeypatch):
    from wheelrail.core.errors import WheelrailError

    parent = os.getpid()

    def drawn(figure, hidden):
        if os.getpid() != parent:
            raise WheelrailError("the child could not draw")
        return np.zeros((2000, 2000, 4), dtype=np.uint8)

    monkeypatch.setattr(figure_workers, "_drawn", drawn)
    with pytest.raises(WheelrailError, match="the child could not draw"):
        figure_workers.png_files(study_figures("filters", _filters_tables(2), "caption"), dpi=110, workers=2)
    assert not multiprocessing.active_children()
