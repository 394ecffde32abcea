"""The track study: the same runs on several tracks, any track input swept (core/study/track_plan.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import model_parameters
from wheelrail.core.study import plan_study
from wheelrail.core.study.noise_plan import noise_models
from wheelrail.core.study.track_plan import swept_inputs


def _tracks(*stiffnesses):
    return [model_parameters({"pad_stiffness": k}) for k in stiffnesses]


def test_the_plan_runs_every_model_on_every_track():
    tracks = _tracks(60e6, 300e6, 1000e6)
    plan = plan_study("track", ["corrugated-rail"], length=1.0, params=tracks)
    assert len(plan.specs) == len(noise_models()) * 3
    assert {spec.params.track for spec in plan.specs} == {p.track for p in tracks}
    assert len({spec.key for spec in plan.specs}) == len(plan.specs)  # the track is in every run key
    assert [entry.key for entry in swept_inputs(plan.tracks)] == ["pad_stiffness"]
    with pytest.raises(WheelrailError, match="runs on one set of parameters; several tracks: the track study"):
        plan_study("filters", ["corrugated-rail"], length=1.0, params=tracks)
    with pytest.raises(WheelrailError, match="must differ"):
        plan_study("track", ["corrugated-rail"], length=1.0, params=_tracks(60e6, 60e6))
    with pytest.raises(WheelrailError, match="differ in their track only"):
        plan_study("track", ["corrugated-rail"], length=1.0, params=[tracks[0], model_parameters({"preload": 9e4})])


def test_several_values_sweep_the_track_study_only(capsys, tmp_path):
    assert (
        main(["study", "filters", "--set", "corrugated-rail", "--out", str(tmp_path), "--sleeper-mass-kg", "40", "80"])
        == 2
    )
    err = capsys.readouterr().err
    assert "--sleeper-mass-kg: one value each for study filters; several values sweep `study track`" in err
    assert (
        main(["study", "track", "--set", "corrugated-rail", "--out", str(tmp_path), "--pad-stiffness-mn-m", "5", "60"])
        == 2
    )
    assert "--pad-stiffness-mn-m 5 is outside the accepted 10 to 3000 MN/m" in capsys.readouterr().err


@pytest.mark.slow
def test_stiff_pads_make_the_sleepers_radiate_more(tmp_path, capsys):
    # two tracks, two precomputes (about 15-30 s each) and the noise model's track for each; 1 m runs
    argv = ["study", "track", "--set", "corrugated-rail", "--length-m", "1", "--out", str(tmp_path)]
    assert main([*argv, "--pad-stiffness-mn-m", "60", "1000", "--workers", "2", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert [t["pad_stiffness"] for t in summary["tracks"]] == [60e6, 1000e6]
    table = summary["tables"]["track_corrugated-rail_noise"]
    assert table["pad_stiffness_mn_m"] == [60.0, 1000.0]
    # a stiff pad ties the sleepers to the rail: they vibrate and radiate far more (Thompson, Railway Noise and
    # Vibration, 2009, section 6.4); the rail's own power moves less, as the force rises where its decay does
    # (docs/examples/plot_07: sleepers 94.2 against 102.6 dB(A) per wheel, rail 110.3 against 109.3)
    sleeper = np.array(table["hertz_sleeper_LWA_dBA"])
    assert sleeper[1] > sleeper[0] + 5.0, sleeper  # margin: measured 8.4 dB on a 2 m run
    assert (tmp_path / "track_corrugated-rail_force_levels.csv").is_file()
    assert (tmp_path / "track_track.png").is_file()


@pytest.mark.slow
def test_the_track_study_on_dask_gives_the_pools_tables(tmp_path):
    # two tracks' runs spread over a local Dask cluster (each worker loads or computes its track's Green's
    # functions, shared through the disk cache) give the process pool's tables to round-off
    distributed = pytest.importorskip("distributed")
    from wheelrail.core.study import run_study

    tracks = _tracks(60e6, 1000e6)
    pool = run_study("track", ["corrugated-rail"], tmp_path / "pool", length=0.6, params=tracks, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        dask = run_study(
            "track",
            ["corrugated-rail"],
            tmp_path / "dask",
            length=0.6,
            params=tracks,
            progress=False,
            figures=False,
            dask_address=cluster.scheduler_address,
        )
    assert dask.report.backend.startswith("dask") and dask.report.computed == pool.report.computed
    for mine, theirs in zip(pool.tables, dask.tables, strict=True):
        for column in mine.columns:
            # equal to rounding, 1e-9 dB: a process whose numba cache was cold compiles the kernels itself and
            # gives levels ~1e-12 relative apart from one that loaded them (docs/limitations.md)
            np.testing.assert_allclose(theirs.columns[column], mine.columns[column], atol=1e-9, equal_nan=True)


def _values(start: float, count: int) -> list[str]:
    return [f"{start + 10 * k:g}" for k in range(count)]


@pytest.mark.parametrize(
    ("sweep", "words"),
    [
        (  # 10 values of three inputs: 1 000 tracks
            [
                "--pad-stiffness-mn-m",
                *_values(60, 10),
                "--sleeper-mass-kg",
                *_values(100, 10),
                "--ballast-stiffness-mn-m",
                *_values(100, 10),
            ],
            "a track study of 1000 tracks (each a Green's-function precompute of about 4.5 s of CPU and a 208 MB "
            "cache entry: 1.2 h, 208 GB) is over the limit of 100 tracks; sweep fewer values",
        ),
        (  # within the limit of tracks, beyond what the disk cache holds
            ["--pad-stiffness-mn-m", *_values(60, 5), "--sleeper-mass-kg", *_values(100, 4)],
            "needs 4.2 GB of disk cache, over its limit of 4 GB (WHEELRAIL_CACHE_MAX_GB), which holds 19: each new "
            "track would evict another; sweep at most 19 tracks, or set WHEELRAIL_CACHE_MAX_GB to at least 5",
        ),
    ],
)
def test_a_track_study_over_its_limits_is_refused_before_any_work(tmp_path, capsys, monkeypatch, sweep, words):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path / "cache"))
    out = tmp_path / "study"
    assert main(["study", "track", "--set", "corrugated-rail", "--out", str(out), *sweep]) == 2
    err = capsys.readouterr().err
    assert err.startswith("wheelrail study: error: a track study of") and len(err.splitlines()) == 1
    assert words in err
    assert not out.exists() and not any((tmp_path / "cache").glob("track-*"))


def test_a_track_study_says_what_it_will_cost_before_it_starts(tmp_path, capsys, monkeypatch):
    import wheelrail.core.study as study

    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path / "cache"))  # empty: every track is new

    def started(*args, **kwargs):
        print("started", file=__import__("sys").stderr)
        raise WheelrailError("stopped here")

    monkeypatch.setattr(study, "run_study", started)
    argv = ["study", "track", "--set", "corrugated-rail", "--out", str(tmp_path / "s"), "--workers", "1"]
    assert main([*argv, "--pad-stiffness-mn-m", "60", "120", "300"]) == 2
    err = capsys.readouterr().err.splitlines()
    runs = 3 * len(noise_models())
    assert err[0] == (
        f"wheelrail study: 3 tracks, {runs} runs; 3 not in the disk cache: about 0.2 min of CPU for their Green's "
        "functions (0.2 min on 1 worker), 0.6 GB of cache (limit 4 GB)"
    )
    assert err[1] == "started"  # said before the study starts
    # the API is bounded too
    with pytest.raises(WheelrailError, match="over the limit of 100 tracks"):
        plan_study("track", ["corrugated-rail"], length=1.0, params=_tracks(*(10e6 + 1e6 * k for k in range(101))))
