"""A study's runs on forked copies of its process (``core.study.forked``): the same numbers as in one process, a
child's error raised in the study's process (no hang), and the fallback where forking is not safe."""

from __future__ import annotations

import functools
import multiprocessing
import os
import subprocess
import sys
import threading

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.study import RunSpec, execute, forked, plan_study, specs
from wheelrail.core.study import execution as study_execution
from wheelrail.core.study import threads as study_threads
from wheelrail.core.study.precompute import TrackTask
from wheelrail.core.study.specs import RunCancelled

pytestmark = pytest.mark.skipif(forked.fork_refusal() == "forked workers need Linux", reason="forks on Linux only")


@pytest.fixture(autouse=True)
def no_kept_pool():
    """No process pool kept by an earlier test (its manager thread would rule the fork out)."""
    from wheelrail.core.study import shutdown_pools

    shutdown_pools()


_HERE = "WHEELRAIL_TEST_FORK_HERE"


def _where_it_can_fork(test):
    """Run ``test`` in this process where it may fork a study's workers, else in a fresh interpreter of its own.

    An earlier test may leave threads alive in the process (a Dask client's: its IO loop and offload threads live as
    long as the process), and a study then rightly refuses to fork (``forked.fork_refusal``); the test is then run
    alone by a new pytest, which has none, instead of being skipped.
    """

    @functools.wraps(test)
    def wrapper(*args, **kwargs):
        if forked.fork_refusal() is None or os.environ.get(_HERE):
            return test(*args, **kwargs)
        node = f"{__file__}::{test.__name__}"
        command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", node]
        done = subprocess.run(command, env={**os.environ, _HERE: "1"}, capture_output=True, text=True, check=False)
        assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-2000:]
        return None

    return wrapper


def _spec(line=0, model="hertz"):
    return RunSpec(source="sinter-wheel-1", set_label="w", set_digest="0" * 64, model=model, line=line)


def _summary(spec, run_time=0.0):
    return specs.RunSummary(
        key=spec.key,
        band_centres=np.array([100.0]),
        levels=np.array([float(spec.line)]),
        force_mean=1.0,
        force_std=0.0,
        force_min=1.0,
        force_max=1.0,
        loss_of_contact_steps=0,
        n_steps=1,
        run_time=run_time,
    )


@_where_it_can_fork
def test_forked_workers_give_the_summaries_of_one_process(tmp_path):
    # every bundled model (3d's window too) on a short piece of a wheel set; to 1e-9 dB as the other backends' tests
    # (a process that compiled numba's kernels and one that loaded them differ ~1e-12)
    plan = plan_study("filters", ["sinter-wheel-1"], length=0.6)
    chosen = [spec for spec in plan.specs if spec.line in (0, 1)]
    one = execute(chosen, cache=tmp_path / "one", workers=1, progress=False)
    two = execute(chosen, cache=tmp_path / "two", workers=2, progress=False)  # auto: fork where it can
    assert one.backend == "in-process" and two.backend == "forked processes (2 workers)"
    assert two.computed == len(chosen) == len(one.summaries) == len(list((tmp_path / "two").glob("run-*.npz")))
    for key, summary in one.summaries.items():
        other = two.summaries[key]
        np.testing.assert_allclose(other.levels, summary.levels, atol=1e-9, equal_nan=True)
        for name in ("force_max", "force_min", "force_std", "force_mean"):
            assert getattr(other, name) == pytest.approx(getattr(summary, name), rel=1e-12)


def test_every_task_is_done_once_by_some_worker(tmp_path, monkeypatch):
    # three workers share one board: each run computed once, wherever; a run whose track is new waits for it
    track = ModelParameters().track
    task = TrackTask(track, ((30.0, 3.6e-5),), new=True)
    monkeypatch.setattr("wheelrail.core.study.precompute.prepare_track", lambda task: task)
    monkeypatch.setattr(specs, "compute_run", lambda spec, cancel=None: _summary(spec, run_time=os.getpid()))
    monkeypatch.setattr("wheelrail.core.study.threads.read_once", list)
    done = []
    forked.execute_forked([_spec(line) for line in range(-3, 4)], 3, done.append, [task])
    assert sorted(float(s.levels[0]) for s in done) == list(range(-3, 4))


@_where_it_can_fork
def test_a_failed_run_in_a_child_is_raised_here_and_stops_this_process_run(tmp_path, monkeypatch):
    # this process's own run waits on its cancel event; the child fails its first run: the error comes back here,
    # the board stops, this process's run is cancelled and the child ended (no hang, no sleep)
    parent = os.getpid()

    def compute(spec, cancel=None):
        if os.getpid() != parent:
            raise WheelrailError(f"line {spec.line} failed in a child")
        assert cancel.wait(60)
        raise RunCancelled(spec.label())

    monkeypatch.setattr(specs, "compute_run", compute)
    monkeypatch.setattr(study_execution, "track_tasks", lambda missing: [])
    monkeypatch.setattr("wheelrail.core.study.threads.read_once", list)
    with pytest.raises(WheelrailError, match=r"line -?\d failed in a child"):
        execute([_spec(line) for line in (0, 1, 2, 3)], cache=tmp_path, workers=2, progress=False, backend="fork")
    assert not list(tmp_path.glob("run-*.npz"))
    assert not [child for child in multiprocessing.active_children() if child.name.startswith("wheelrail")]


@_where_it_can_fork
def test_a_child_that_dies_is_a_clear_error(tmp_path, monkeypatch):
    parent = os.getpid()

    def compute(spec, cancel=None):
        if os.getpid() != parent:
            os._exit(3)  # as a crash or the out-of-memory killer would end it
        assert cancel.wait(60)
        raise RunCancelled(spec.label())

    monkeypatch.setattr(specs, "compute_run", compute)
    monkeypatch.setattr(study_execution, "track_tasks", lambda missing: [])
    monkeypatch.setattr("wheelrail.core.study.threads.read_once", list)
    with pytest.raises(WheelrailError, match=r"a study worker process ended before its runs \(exit code 3\)"):
        execute([_spec(line) for line in (0, 1)], cache=tmp_path, workers=2, progress=False, backend="fork")


@_where_it_can_fork
def test_another_thread_alive_means_no_fork(tmp_path, monkeypatch):
    # a thread of the caller's (a server, a client, a progress monitor) could hold a lock at the fork: the study
    # falls back to threads (auto) or refuses the fork backend in words
    release = threading.Event()
    other = threading.Thread(target=release.wait, name="caller-server")
    other.start()
    monkeypatch.setattr(study_threads, "compute_run", lambda spec, cancel=None: _summary(spec))
    monkeypatch.setattr(study_threads, "read_once", list)
    monkeypatch.setattr(study_execution, "track_tasks", lambda missing: [])
    try:
        assert forked.fork_refusal() == "other threads run in this process (caller-server)"
        report = execute([_spec(line) for line in (0, 1)], cache=tmp_path, workers=2, progress=False)
        assert report.backend == "threads (2 workers)"
        with pytest.raises(WheelrailError, match=r"the fork backend cannot be used here: other threads run"):
            execute([_spec(line) for line in (2, 3)], cache=tmp_path, workers=2, progress=False, backend="fork")
    finally:
        release.set()
        other.join()
    assert forked.fork_refusal() is None


def test_no_fork_from_a_thread_other_than_the_main_thread():
    found = []
    thread = threading.Thread(target=lambda: found.append(forked.fork_refusal()))
    thread.start()
    thread.join()
    assert found == ["the study runs in a thread other than the main thread"]


@_where_it_can_fork
def test_work_beside_the_runs_starts_after_the_fork(tmp_path, monkeypatch):
    # the runner's work beside the runs is a thread: it starts only when execute calls started, after the fork
    from wheelrail.core.study import runner

    seen, beside = [], threading.Event()
    monkeypatch.setattr(runner, "_load_matplotlib", beside.set)

    def execute_fork(specs_, workers, finished, tracks=(), started=None, save=None):
        seen.append(forked.fork_refusal())  # no thread of the study's at the fork
        started()
        seen.append(beside.wait(60))
        raise KeyError("no runs")

    monkeypatch.setattr(study_execution, "execute_forked", execute_fork)
    with pytest.raises(KeyError):
        runner.run_study("filters", ["corrugated-rail"], tmp_path, workers=2, progress=False, length=0.6)
    assert seen == [None, True]


def test_this_process_prepares_a_track_beside_its_other_work_and_takes_runs_after_it(monkeypatch):
    # the work beside the runs (the tables' noise chains) holds this process's GIL: a precompute, in compiled code,
    # goes on beside it at once, but this process takes no run before it has ended (the child takes them meanwhile)
    from wheelrail.core.inputs.declared import model_parameters

    context, parent = multiprocessing.get_context("fork"), os.getpid()
    took, release = context.Event(), threading.Event()
    beside = threading.Thread(target=release.wait, args=(60,))
    seen, ran_here = [], []

    def prepare(task):
        if os.getpid() == parent:
            seen.append(beside.is_alive())
            took.set()
            release.set()  # the work beside ends now
        else:
            assert took.wait(60)  # the child holds its track until this process has taken the other
        return task

    def compute(spec, cancel=None):
        if os.getpid() == parent:
            ran_here.append(beside.is_alive())
        return _summary(spec)

    monkeypatch.setattr("wheelrail.core.study.precompute.prepare_track", prepare)
    monkeypatch.setattr(specs, "compute_run", compute)
    monkeypatch.setattr(study_threads, "read_once", list)
    params = [model_parameters({"pad_stiffness": value}) for value in (60e6, 200e6)]
    tracks = [TrackTask(p.track, ((p.run.speed, p.run.time_step),), new=True) for p in params]
    runs = [RunSpec(source="sinter-wheel-1", set_label="w", set_digest="0" * 64, model="hertz", line=line, params=p)
            for p in params for line in (0, 1, 2)]  # fmt: skip
    done = []
    forked.execute_forked(runs, 2, done.append, tracks, started=lambda: beside.start() or beside)
    assert seen[0] and not any(ran_here) and len(done) == len(runs)  # (it may prepare both tracks)


def test_the_boards_runs_are_grouped_by_model_in_the_order_given():
    given = [_spec(0, "3d"), _spec(0), _spec(0, "2d"), _spec(1), _spec(1, "2d"), _spec(1, "3d")]
    grouped = forked._by_model(given)
    assert [(s.model, s.line) for s in grouped] == [("3d", 0), ("3d", 1), ("hertz", 0), ("hertz", 1), ("2d", 0),
                                                    ("2d", 1)]  # fmt: skip


def test_a_worker_ended_while_it_waits_for_a_track_leaves_the_board_working(monkeypatch):
    # a stopped study ends its children (SIGTERM), one perhaps waiting for a track this process prepares: the board's
    # cross-process condition variable then hung this process's track_ready for good (notify_all waits for every
    # waiter to wake); the board is now looked at again, and a track made ready reaches the runs still to take
    context = multiprocessing.get_context("fork")
    task = TrackTask(ModelParameters().track, (), True)
    board = forked.Board(context, [("track", task), ("run", _spec())], [-1, 0])
    assert board.take(0) == 0  # this process prepares the track
    reader, writer = context.Pipe(duplex=False)

    def waiting():  # in the child: tell this process it is in the board's waiting loop, then wait there
        writer.send("waiting")
        monkeypatch.setattr(forked, "_look_again", lambda: threading.Event().wait())

    monkeypatch.setattr(forked, "_look_again", waiting)
    child = context.Process(target=board.take, args=(0,), daemon=True)
    child.start()
    assert reader.recv() == "waiting"
    child.terminate()
    child.join()
    board.track_ready(0)
    assert board.take(0) == 1 and board.take(0) is None
