"""A study's runs in threads of one process (the compiled laws release the GIL) and its new tracks prepared once,
side by side, before their runs (``core.study.threads``, ``core.study.precompute``, ``core.study.execution``)."""

from __future__ import annotations

import dataclasses
import functools
import threading

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import MODELS, ModelEntry, ModelTraits, register, unregister
from wheelrail.core.parameters import ModelParameters, RunParameters
from wheelrail.core.study import RunSpec, execute, plan_study
from wheelrail.core.study import execution as study_execution
from wheelrail.core.study import precompute as study_precompute
from wheelrail.core.study import threads as study_threads
from wheelrail.core.study.precompute import TrackTask, track_tasks
from wheelrail.core.study.specs import RunCancelled
from wheelrail.core.study.threads import releases_gil


def _spec(model="hertz", line=0, params=None, source="sinter-wheel-1"):
    return RunSpec(
        source=source, set_label="w", set_digest="0" * 64, model=model, line=line, params=params or ModelParameters()
    )


def test_threads_give_the_summaries_of_one_process(tmp_path):
    # every bundled model (3d's window too) on a short piece of a wheel set: the same numbers, bit for bit
    plan = plan_study("filters", ["sinter-wheel-1"], length=0.6)
    specs = [spec for spec in plan.specs if spec.line in (0, 1)]
    assert {spec.model for spec in specs} == set(MODELS)
    one = execute(specs, cache=tmp_path / "one", workers=1, progress=False)
    two = execute(specs, cache=tmp_path / "two", workers=2, progress=False, backend="threads")
    assert one.backend == "in-process" and two.backend == "threads (2 workers)"
    assert two.computed == len(specs) == len(one.summaries)
    for key, summary in one.summaries.items():
        other = two.summaries[key]
        np.testing.assert_array_equal(summary.levels, other.levels)
        assert (summary.force_max, summary.force_min, summary.force_std) == (
            other.force_max,
            other.force_min,
            other.force_std,
        )


def test_the_bundled_laws_release_the_gil_and_a_law_stepped_from_python_does_not():
    from wheelrail.core.contact.hertz_model import HertzModel

    assert all(releases_gil(_spec(model)) for model in MODELS)
    # a model registered with no law: its Python solve once per step (engine.laws.base.PerStepLaw)
    entry = register(ModelEntry(name="spring-per-step", label="x", traits=ModelTraits(), implementation=HertzModel))
    try:
        assert not releases_gil(_spec("spring-per-step"))
    finally:
        unregister(entry.name)


def test_an_unknown_backend_is_refused(tmp_path):
    with pytest.raises(WheelrailError, match="backend must be one of auto, fork, threads, processes, got 'gpu'"):
        execute([_spec()], cache=tmp_path, workers=2, progress=False, backend="gpu")


def test_a_failed_run_stops_the_running_ones_and_drops_the_queued(tmp_path, monkeypatch):
    # run 0 waits (on its cancel event) until run 1 has failed; the others are queued behind them: dropped, or,
    # should a thread take one before the failure is seen, stopped by the same event
    specs = [_spec(line=line) for line in (0, 1, 2, 3)]
    waiting, started, stopped = threading.Event(), [], []

    def compute(spec, cancel):
        started.append(spec.line)
        if spec.line == 1:
            assert waiting.wait(60)
            raise WheelrailError("run 1 failed")
        waiting.set()
        assert cancel.wait(60)  # set by the failure of run 1
        stopped.append(spec.line)
        raise RunCancelled(spec.label())

    monkeypatch.setattr(study_threads, "compute_run", compute)
    monkeypatch.setattr(study_threads, "read_once", list)
    monkeypatch.setattr(study_execution, "track_tasks", lambda specs: [])
    with pytest.raises(WheelrailError, match="run 1 failed"):
        execute(specs, cache=tmp_path, workers=2, progress=False, backend="threads")
    assert 0 in stopped and sorted(stopped) == sorted(set(started) - {1}) and len(started) < 4
    assert not list(tmp_path.glob("run-*.npz"))


def _track(pad_stiffness: float):
    from wheelrail.core.inputs.declared import model_parameters

    return model_parameters({"pad_stiffness": pad_stiffness})


def test_runs_are_grouped_by_track_and_the_new_tracks_come_first(monkeypatch):
    held = {}  # (pad stiffness, speed) -> what the disk cache holds

    def cached_reading(speed, time_step, track, numerics=None):
        return held[track.support.pad_stiffness, speed]

    monkeypatch.setattr("wheelrail.core.track.moving.cached_reading", cached_reading)
    a, b, c = _track(60e6), _track(200e6), _track(1000e6)
    fast = RunParameters(speed=40.0)
    specs = [
        _spec(params=a),
        _spec("2d", params=a),  # the same track and speed: one reading
        _spec(params=ModelParameters(track=a.track, run=fast)),
        _spec(params=b),
        _spec(params=c),
    ]
    held.update({(60e6, a.run.speed): "responses", (60e6, 40.0): "weights", (200e6, b.run.speed): "weights"})
    held[1000e6, c.run.speed] = ""
    tasks = track_tasks(specs)
    assert tasks == [
        TrackTask(c.track, ((c.run.speed, c.run.time_step),), new=True),
        TrackTask(a.track, ((a.run.speed, a.run.time_step),), new=False),
    ]


@pytest.mark.parametrize("new_tracks", [1, 2])
def test_two_new_tracks_are_prepared_side_by_side_in_the_pool_one_in_this_process(monkeypatch, new_tracks):
    tasks = [TrackTask(_track(v).track, ((30.0, 3.6e-5),), new=True) for v in (60e6, 80e6)[:new_tracks]]
    tasks.append(TrackTask(_track(100e6).track, ((30.0, 3.6e-5),), new=False))
    pooled, here, started = [], [], []
    monkeypatch.setattr(study_execution, "_pool_map", lambda task, items, workers: pooled.extend(items))
    monkeypatch.setattr(study_execution, "prepare_track", here.append)
    study_execution._prepare_tracks(tasks, 2, lambda: started.append(len(pooled)))
    assert started == [0]  # the work beside the runs starts with a precompute, before the pool's or this process's
    if new_tracks == 2:
        assert pooled == tasks[:2] and here == tasks[2:]
    else:
        assert pooled == [] and here == tasks


@pytest.mark.parametrize("workers", [1, 2])
def test_a_new_track_in_this_process_integrates_on_the_workers_cores(monkeypatch, tmp_path, workers):
    # workers are the cores a study may use: one worker's precompute integrates in one thread, not all cores
    from numba import config

    from wheelrail.core.track import stationary

    monkeypatch.setattr(config, "NUMBA_NUM_THREADS", 2)
    seen, blas = [], []
    monkeypatch.setattr(study_threads, "_openblas_libraries", lambda: ())
    monkeypatch.setattr(study_threads, "set_blas_threads_local", lambda n: blas.append(n) or [])
    monkeypatch.setattr(study_execution, "compute_run", lambda spec: seen.append(stationary._threads()))
    study_execution._dispatch([_spec()], workers, None, lambda summary: None)
    assert seen == [workers] and stationary._threads() == 2
    assert blas == ([1] if workers == 1 else [])  # and BLAS in one thread


def test_precomputes_in_two_threads_integrate_in_their_own_numbers_of_threads(monkeypatch):
    # two precomputes side by side in a study's threads: each thread's number, not a process-wide one
    from numba import config

    from wheelrail.core.track import stationary

    monkeypatch.setattr(config, "NUMBA_NUM_THREADS", 4)
    both, seen = threading.Barrier(2, timeout=60), {}

    def precompute(threads):
        with stationary.integration_threads(threads):
            both.wait()  # the other thread's number set too
            seen[threads] = (stationary._threads(), len(stationary.column_blocks(8)))

    workers = [threading.Thread(target=precompute, args=(n,)) for n in (1, 2)]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join()
    assert seen == {1: (1, 1), 2: (2, 2)} and stationary._threads() == 4


def test_with_threads_a_tracks_runs_start_once_it_is_ready_while_the_next_is_prepared(monkeypatch, tmp_path):
    # two new tracks, two workers: the tracks are prepared in the study's threads (no process pool), one
    # integrating thread each, and the second track's precompute is still going when the first track's run starts
    from wheelrail.core.track import stationary

    a, b = _track(60e6), _track(200e6)
    tasks = [TrackTask(p.track, ((p.run.speed, p.run.time_step),), new=True) for p in (a, b)]
    first_run, prepared, ran = threading.Event(), [], []

    def prepare(task):
        prepared.append((task.track, stationary._threads()))
        if task.track == b.track:
            assert first_run.wait(60)  # a's run started while b is prepared
        return task

    def compute(spec, cancel):
        ran.append(spec.params.track)
        first_run.set()
        return spec

    monkeypatch.setattr(study_execution, "track_tasks", lambda specs: tasks)
    monkeypatch.setattr(study_execution, "_pool_map", lambda *args: pytest.fail("the process pool was used"))
    monkeypatch.setattr(study_precompute, "prepare_track", prepare)
    monkeypatch.setattr(study_threads, "compute_run", compute)
    monkeypatch.setattr(study_threads, "read_once", list)
    done = []
    used = study_execution._dispatch([_spec(params=b), _spec(params=a)], 2, None, done.append, "threads")
    assert used == "threads (2 workers)" and sorted(p[1] for p in prepared) == [1, 1]
    assert ran == [a.track, b.track] and len(done) == 2


@pytest.mark.slow
def test_a_track_study_in_threads_gives_the_process_pools_numbers(monkeypatch, tmp_path):
    # the tracks prepared in the study's threads give the same tables as prepared in the process pool
    # (each in a fresh cache holding no track, so each study computes both tracks)
    import os
    import shutil

    from wheelrail.core.files import cache
    from wheelrail.core.files.cache import cache_dir
    from wheelrail.core.study import run_study, runner
    from wheelrail.core.track import stationary

    shared = cache_dir()
    tables, computed = {}, []  # the precomputes in this process
    compute = stationary.compute_stationary_response
    monkeypatch.setattr(stationary, "compute_stationary_response", lambda *a: computed.append(1) or compute(*a))
    for backend in ("threads", "processes"):
        folder = tmp_path / f"cache-{backend}"
        folder.mkdir()
        for entry in shared.glob("*.npz"):
            if not entry.name.startswith("track-"):
                shutil.copy2(entry, folder / entry.name)
        monkeypatch.setenv("WHEELRAIL_CACHE_DIR", os.fspath(folder))
        stationary.clear_memory()
        computed.clear()
        monkeypatch.setattr(runner, "execute", functools.partial(study_execution.execute, backend=backend))
        result = run_study(
            "track", ["corrugated-rail"], tmp_path / backend, length=0.6, params=[_track(60e6), _track(1000e6)],
            workers=2, progress=False, figures=False,
        )  # fmt: skip
        assert result.report.backend == {"threads": "threads", "processes": "process pool"}[backend] + " (2 workers)"
        cache.wait_for_writes()  # a new track's entry is written in the background (cache.save_entry_behind)
        assert len(list(folder.glob("track-wedge*"))) == 2  # both tracks computed here, each once
        assert len(computed) == (2 if backend == "threads" else 0)  # (the pool's in its worker processes)
        tables[backend] = result.tables
    # to 1e-9 dB, as the other backends' tests: a process that compiled numba's kernels and one that loaded them from
    # its cache give levels ~1e-12 relative apart (docs/limitations.md), e.g. the pool's fresh workers on a new machine
    for mine, theirs in zip(tables["threads"], tables["processes"], strict=True):
        for column in mine.columns:
            np.testing.assert_allclose(mine.columns[column], theirs.columns[column], atol=1e-9, equal_nan=True)
    stationary.clear_memory()


def test_prepare_track_reads_off_each_speed(monkeypatch):
    calls = []
    monkeypatch.setattr("wheelrail.core.track.moving_weights", lambda *args: calls.append(args[:3]))
    track = _track(60e6).track
    study_precompute.prepare_track(TrackTask(track, ((30.0, 3.3e-5), (40.0, 2.5e-5)), new=True))
    assert calls == [(30.0, 3.3e-5, track), (40.0, 2.5e-5, track)]


def test_a_studys_noise_chains_are_worked_out_beside_its_runs(monkeypatch, tmp_path):
    # the track study's tables go through each track's noise chain (a second or two of CPU a track, in the parent
    # after the runs); with workers to spare they are worked out while the runs go, the last track first
    from wheelrail.core.study import plans, runner

    chains, during = [], threading.Event()
    monkeypatch.setattr(
        plans, "_noise_chain", lambda params, numerics: chains.append(params.track.support.pad_stiffness)
    )
    tracks = [_track(v) for v in (60e6, 200e6, 1000e6)]
    plan = plan_study("track", ["corrugated-rail"], params=tracks, length=0.6)

    def tabulate(summaries):  # beyond what this test follows
        raise KeyError("no runs")

    plan = dataclasses.replace(plan, tabulate=tabulate)
    beside_filters = plan_study("filters", ["corrugated-rail"], length=0.6).beside
    assert [task.__name__ for task in beside_filters] == ["_import_reference_filters"]  # no chain: Fig. 10's import

    def execute(specs, **options):  # the runs: done once the chains are, whichever comes first
        during.set()
        return study_execution.ExecutionReport({}, 0, 0, 0.0, "test")

    monkeypatch.setattr(runner, "plan_study", lambda *args, **options: plan)
    monkeypatch.setattr(runner, "execute", execute)
    monkeypatch.setattr(runner, "_load_matplotlib", lambda: chains.append("matplotlib"))
    with pytest.raises(KeyError):
        runner.run_study("track", ["corrugated-rail"], tmp_path, workers=2, progress=False)
    assert during.is_set() and chains == [1000e6, 200e6, 60e6, "matplotlib"]
    chains.clear()
    with pytest.raises(KeyError):
        runner.run_study("track", ["corrugated-rail"], tmp_path, workers=1, progress=False)
    assert chains == []  # one worker: the tabulation works them out itself


def test_work_beside_the_runs_waits_for_a_finished_run(monkeypatch, tmp_path):
    # the first runs load numba's compiled code, holding the GIL, before any step runs in parallel: the study's own
    # work beside them (matplotlib's import, the noise chains), which holds it too, starts once a run has finished
    from wheelrail.core.study import runner

    ran, seen = threading.Event(), []
    monkeypatch.setattr(runner, "_load_matplotlib", ran.set)

    def execute(specs, *, started, **options):
        seen.append(ran.is_set())
        started()
        seen.append(ran.wait(60))
        raise KeyError("no runs")

    monkeypatch.setattr(runner, "execute", execute)
    with pytest.raises(KeyError):
        runner.run_study("filters", ["corrugated-rail"], tmp_path, workers=2, progress=False, length=0.6)
    assert seen == [False, True]


def test_a_study_thread_calls_blas_in_one_thread(monkeypatch):
    # workers are the study's cores: OpenBLAS's own threads under each study thread would oversubscribe them
    seen = []
    monkeypatch.setattr(study_threads, "set_blas_threads_local", lambda n: seen.append(n) or [])
    monkeypatch.setattr(study_threads, "compute_run", lambda spec, cancel: spec.key)
    study_threads.execute_threads([_spec(line=k) for k in range(4)], 2, lambda summary: None)
    assert seen and set(seen) == {1}


def test_blas_threads_are_this_threads_and_restored():
    if not study_threads._openblas_libraries():
        pytest.skip("no OpenBLAS that sets a thread's own number")
    before = study_threads.set_blas_threads_local(3)
    try:
        with study_threads.blas_threads(1):
            assert study_threads.set_blas_threads_local(1) == [1] * len(before)
        assert study_threads.set_blas_threads_local(3) == [3] * len(before)
    finally:
        for setter, value in zip(study_threads._openblas_libraries(), before, strict=True):
            setter(value)


def test_work_beside_the_runs_is_left_at_an_interrupt():
    from wheelrail.core.study.runner import _beside

    release, finished = threading.Event(), []

    def slow():
        assert release.wait(60)
        finished.append(True)

    with pytest.raises(KeyboardInterrupt), _beside([slow, lambda: finished.append("next")]):
        raise KeyboardInterrupt  # not waited for: the study stops at once
    release.set()
    assert finished in ([], [True])  # the thread ends by itself, without its next item


def test_sets_are_read_once_and_interpolated_along_once_with_the_same_runs():
    from wheelrail.core.study import compute_run
    from wheelrail.core.study.threads import read_once

    plan = plan_study("filters", ["sinter-wheel-1"], length=0.6)  # 0.5 mm samples: the runs interpolate to 1 mm
    specs = [spec for spec in plan.specs if spec.line == 0]
    shared = read_once(specs)
    assert len({id(spec.source) for spec in shared}) == 1 and shared[0].source.dx == pytest.approx(1e-3, rel=1e-3)
    assert [spec.key for spec in shared] == [spec.key for spec in specs]
    for named, read in zip(specs, shared, strict=True):  # hertz..., 3d: bit for bit the runs of the named set
        a, b = compute_run(named), compute_run(read)
        np.testing.assert_array_equal(a.levels, b.levels)
        assert (a.force_max, a.force_min, a.force_mean) == (b.force_max, b.force_min, b.force_mean)


def test_ctrl_c_stops_the_running_threads_at_their_next_chunk(monkeypatch):
    # Ctrl-C (or SIGTERM, turned into it) arrives in the study's thread while it waits for the runs: here as the
    # first finished run is handed back; the other running run sees its cancel event and ends
    from wheelrail.core.study.threads import execute_threads

    stopped, second = [], threading.Event()

    def compute(spec, cancel):
        if spec.line == 0:
            assert second.wait(60)  # both runs going
            return spec.line
        second.set()
        assert cancel.wait(60)
        stopped.append(spec.line)
        raise RunCancelled(spec.label())

    def finished(summary):
        raise KeyboardInterrupt

    monkeypatch.setattr(study_threads, "compute_run", compute)
    monkeypatch.setattr(study_threads, "read_once", list)
    with pytest.raises(KeyboardInterrupt):
        execute_threads([_spec(line=line) for line in (0, 1)], 2, finished)
    assert stopped == [1]
