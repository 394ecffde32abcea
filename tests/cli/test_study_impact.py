"""The impact study: irregularity inputs swept, per model and speed the peak force, contact loss and impact noise
(core/study/impact_plan.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.errors import WheelrailError
from wheelrail.core.irregularities import WheelFlat
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.study import plan_study
from wheelrail.core.study.impact_plan import ImpactSweep, impact_models, noise_slope, swept_irregularity_inputs


def _flat(length_mm: float) -> tuple:
    return (WheelFlat(length=length_mm * 1e-3, position=0.3),)


def test_the_plan_runs_every_model_speed_and_case():
    sweep = ImpactSweep(
        ModelParameters(), cases=(_flat(20), _flat(50), _flat(100)), models=("hertz", "2d"), speeds=(60 * KMH, 30 * KMH)
    )
    plan = plan_study("impact", ["corrugated-rail"], length=1.0, params=sweep)
    assert len(plan.specs) == 3 * 2 * 2
    assert len({spec.key for spec in plan.specs}) == len(plan.specs)  # the irregularities are in every run key
    assert {spec.params.run.irregularities for spec in plan.specs} == {_flat(20), _flat(50), _flat(100)}
    assert sorted({round(spec.speed_kmh, 9) for spec in plan.specs}) == [30.0, 60.0]
    assert plan.impact.speeds == (30 * KMH, 60 * KMH) and plan.params.run.irregularities == ()
    assert [entry.key for entry in swept_irregularity_inputs(plan.impact.cases)] == ["flat_length"]
    # one ModelParameters with irregularities: its one case, the default models and speeds
    one = ModelParameters(run=RunParameters(irregularities=_flat(50)))
    assert plan_study("impact", ["corrugated-rail"], length=1.2, params=one).impact.models == impact_models()


def test_noise_only_where_the_analysed_record_holds_the_irregularity():
    from wheelrail.core.study.impact_plan import in_record

    sweep = ImpactSweep(ModelParameters(), cases=(_flat(50),), models=("hertz",), speeds=(30 * KMH, 100 * KMH))
    for length, heard in ((0.8, [True, False]), (3.0, [True, True])):  # 100 km/h: the first 0.56 m left out
        plan = plan_study("impact", ["corrugated-rail"], length=length, params=sweep)
        assert [in_record(_flat(50), spec) for spec in plan.specs] == heard  # 3 m: the flat's next turn, 2.75 m


@pytest.mark.parametrize(
    ("sweep", "message"),
    [
        (ModelParameters(), "needs an irregularity in every case"),
        (ImpactSweep(ModelParameters(), cases=(_flat(50), _flat(50))), "must differ"),
        (ImpactSweep(ModelParameters(), cases=(_flat(50),), models=("hertz", "hertz")), "each model once"),
        (ImpactSweep(ModelParameters(), cases=(_flat(50),), models=("nosuch",)), "nosuch"),
        (ImpactSweep(ModelParameters(), cases=(_flat(50),), speeds=(-1.0,)), "must be positive"),
    ],
)
def test_a_bad_sweep_is_refused(sweep, message):
    with pytest.raises(WheelrailError, match=message):
        plan_study("impact", ["corrugated-rail"], length=1.0, params=sweep)


def test_the_noise_slope_is_a_least_squares_line_per_doubling():
    v = np.array([50.0, 100.0, 200.0])
    assert noise_slope(v, 90 + 20 * np.log10(v)) == pytest.approx(20 * np.log10(2))  # 20 lg v: 6.02 dB
    assert np.isnan(noise_slope([50.0], [90.0]))


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--flat-length-mm", "50"], "a flat needs its position as well"),
        (["--flat-length-mm", "50", "-1", "--flat-position-m", "0.3"], "--flat-length-mm -1"),
        ([], "needs an irregularity in every case"),
        (["--flat-length-mm", "50", "--flat-position-m", "0.3", "--speeds-kmh", "0"], "must be positive"),
        (["--flat-length-mm", "50", "--flat-position-m", "0.3", "--models", "nosuch"], "nosuch"),
    ],
)
def test_bad_input_is_one_line(argv, message, tmp_path, capsys):
    base = ["study", "impact", "--set", "corrugated-rail", "--length-m", "0.8", "--out", str(tmp_path / "o")]
    assert main([*base, *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1 and "Traceback" not in err, err


def test_sweeps_and_models_are_for_the_impact_study_only(tmp_path, capsys):
    base = ["study", "filters", "--set", "corrugated-rail", "--out", str(tmp_path / "o")]
    assert main([*base, "--flat-length-mm", "20", "50", "--flat-position-m", "0.3"]) == 2
    assert "--flat-length-mm: for study impact only" in capsys.readouterr().err
    assert main([*base, "--speeds-kmh", "30", "60"]) == 2
    assert "--speeds-kmh: for study impact only" in capsys.readouterr().err


@pytest.mark.slow
def test_a_tiny_impact_study_through_the_cli(tmp_path, capsys):
    # hertz at 2 speeds, one 100 mm flat, 1 m runs: the flat lifts the wheel off the rail at both speeds
    # (the flat 0.7 m in: past the 20 ms each force spectrum leaves out, 0.56 m at 100 km/h, so both runs' noise has it)
    argv = ["study", "impact", "--set", "corrugated-rail", "--length-m", "1", "--out", str(tmp_path), "--json"]
    argv += ["--models", "hertz", "--speeds-kmh", "30", "100", "--flat-length-mm", "100", "--flat-position-m", "0.7"]
    assert main([*argv, "--workers", "1"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["runs"] == 2 and summary["models"] == ["hertz"]
    assert summary["irregularity_cases"][0][0]["length"] == pytest.approx(0.1)
    table = summary["tables"]["impact_corrugated-rail_case1"]
    assert table["speed_kmh"] == [30.0, 100.0]
    assert min(table["hertz_peak_force_n"]) > 2 * 65e3  # an impact: more than twice the preload
    assert table["hertz_min_force_n"] == [0.0, 0.0] and min(table["hertz_time_without_contact_ms"]) > 0
    loss = summary["tables"]["impact_corrugated-rail_contact_loss"]
    assert loss["flat_length_mm"] == [100.0] and loss["hertz_first_loss_speed_kmh"] == [30.0]
    assert np.isfinite(loss["hertz_slope_dB_per_doubling"][0]) and all(np.isfinite(table["hertz_LWA_dBA"]))
    for name in ("impact_corrugated-rail_case1.csv", "impact_corrugated-rail_contact_loss.csv", "impact_impact.png"):
        assert (tmp_path / name).is_file()
    # again: every run read back from OUT/runs
    assert main([*argv, "--workers", "1"]) == 0
    assert json.loads(capsys.readouterr().out)["runs_cached"] == 2


def test_the_figure_marks_the_first_contact_loss_and_draws_one_speed():
    from wheelrail.core.study.figures import study_figures
    from wheelrail.core.study.tables import Table

    def table(speeds, lost_ms):
        n = len(speeds)
        columns = {
            "hertz_peak_force_n": np.linspace(1e5, 2e5, n),
            "hertz_min_force_n": np.zeros(n),
            "hertz_time_without_contact_ms": np.asarray(lost_ms, dtype=float),
            "hertz_LWA_dBA": np.linspace(100.0, 110.0, n),
            "hertz_LpAeq_dBA": np.linspace(80.0, 90.0, n),
        }
        return Table(name=f"impact_s_case{n}", figure="impact", title="t", band_centres=np.asarray(speeds, float),
                     columns=columns, panel=f"s: case {n}", axis_name="speed_kmh")  # fmt: skip

    loss = Table(name="impact_s_contact_loss", figure="impact-loss", title="t", band_centres=np.array([1.0]),
                 columns={"hertz_first_loss_speed_kmh": np.array([60.0])}, axis_name="case")  # fmt: skip
    figures = study_figures("impact", [table([30.0, 60.0, 100.0], [0.0, 0.2, 0.3]), table([50.0], [0.0]), loss])
    assert list(figures) == ["impact_impact.png"]  # the loss table's numbers are in the impact figure
    force_ax = figures["impact_impact.png"].axes[0]
    assert "hertz: contact lost from 60 km/h" in [text.get_text() for text in force_ax.get_legend().get_texts()]
    legend = [text.get_text() for text in figures["impact_impact.png"].axes[1].get_legend().get_texts()]
    slope = noise_slope([30.0, 60.0, 100.0], [100.0, 105.0, 110.0])  # least squares in log2 v: 5.7 dB
    assert legend == [f"hertz: {slope:+.1f} dB per doubling"] and 5.6 < slope < 5.8
    one_speed = [text.get_text() for text in figures["impact_impact.png"].axes[3].get_legend().get_texts()]
    assert one_speed == ["hertz"]  # no slope of one speed


@pytest.mark.slow
def test_the_impact_study_on_dask_gives_the_pools_tables(tmp_path):
    # the same runs (two flats, hertz, 30 km/h) on a process pool and on a local Dask cluster: the same tables
    distributed = pytest.importorskip("distributed")
    from wheelrail.core.study import run_study

    sweep = ImpactSweep(ModelParameters(), cases=(_flat(50), _flat(100)), models=("hertz",), speeds=(30 * KMH,))
    common = {"length": 0.5, "params": sweep, "progress": False, "figures": False}
    pool = run_study("impact", ["corrugated-rail"], tmp_path / "pool", workers=2, **common)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        address = cluster.scheduler_address
        dask = run_study("impact", ["corrugated-rail"], tmp_path / "dask", dask_address=address, **common)
    assert dask.report.backend.startswith("dask") and dask.report.computed == pool.report.computed == 2
    for mine, theirs in zip(pool.tables, dask.tables, strict=True):
        for column in mine.columns:
            np.testing.assert_allclose(theirs.columns[column], mine.columns[column], rtol=1e-12, equal_nan=True)
