"""Running a study's runs on forked copies of the study's process (Linux): the local backend of
:func:`~wheelrail.core.study.execution.execute` where it can fork safely.

A forked child starts in milliseconds with everything the study's process holds: its imports, the sets read (and
interpolated along) once, the tracks' weights and numba's compiled code it has loaded, shared copy-on-write; the
children and the study's process (its share in a thread of its own) take the study's tasks from one board in shared
memory (:class:`Board`): the new tracks to prepare first, then the runs, each run once its track is ready. Each
worker scans the board from a start of its own (the study's process from the first task, the others spread over the
list), so that consecutive runs of a worker tend to share a model, and steals what is left elsewhere when its stretch
is done. Finished runs come back to the study's process as :class:`~wheelrail.core.study.specs.RunSummary` through a
pipe a worker, where the caller's ``finished`` writes them.

Fork is used only where it is safe (:func:`fork_refusal`): on Linux, from the main thread, and while no other
thread of the process is alive (a thread holding a lock at the fork would leave that lock held for ever in the child:
the work beside the runs, a progress bar's monitor, a Dask client, a server, a kept process pool's manager). The
study's runs call no numba parallel kernel (a track's precompute integrates in threads of Python's own, ended with
it) and each child calls BLAS in one thread (OpenBLAS's own threads are re-created after a fork by its fork
handler). A child ignores Ctrl-C (the study's process stops the children), ends with SIGTERM and ends by itself
when the study's process is gone (:func:`watch_parent`).
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from multiprocessing.connection import wait

from wheelrail.core.errors import WheelrailError
from wheelrail.core.study.specs import RunSpec, RunSummary

__all__ = ["Board", "PARENT_POLL_INTERVAL", "execute_forked", "fork_refusal", "forked_call", "watch_parent"]

PARENT_POLL_INTERVAL = 0.5  # s, how often a worker process checks that the process that started it lives
_WAIT = 0.5  # s, the longest a worker waits for the board's lock before it looks at the stop flag again
_POLL = 0.01  # s, how often a worker waiting for a track looks at the board again


def _look_again() -> None:
    """Wait ``_POLL`` s before a waiting worker looks at the board again."""
    time.sleep(_POLL)


def watch_parent(parent_pid: int) -> None:
    """Worker side: end this process as soon as its parent is gone (its parent pid changes)."""
    while os.getppid() == parent_pid:
        time.sleep(PARENT_POLL_INTERVAL)
    os._exit(1)  # no clean-up to do: the run in progress is lost anyway and its parent wrote the rest


def fork_refusal() -> str | None:
    """Why this process cannot fork a study's workers now, in words; None when it can: on Linux (where ``fork`` is a
    start method and the study's libraries survive it), from the main thread, with no other thread alive (this
    process's cache writes under way are waited for first)."""
    if not sys.platform.startswith("linux") or "fork" not in multiprocessing.get_all_start_methods():
        return "forked workers need Linux"
    if threading.current_thread() is not threading.main_thread():
        return "the study runs in a thread other than the main thread"
    from wheelrail.core.files import cache

    cache.wait_for_writes()  # a write's thread leaves the list just before it ends: joined below
    others = [thread for thread in threading.enumerate() if thread is not threading.current_thread()]
    for thread in others:
        if thread.name.startswith("wheelrail-cache-write"):
            thread.join()
    alive = sorted(thread.name for thread in others if thread.is_alive())
    if alive:
        return f"other threads run in this process ({', '.join(alive)})"
    return None


class Board:
    """A study's tasks shared by its forked workers (shared memory, made before the fork): which are taken, which
    tracks are ready, and a stop flag.

    ``tasks`` are ``("track", TrackTask)`` or ``("run", RunSpec)``; ``needs[k]`` is the index of the track task task
    ``k`` waits for (-1: none).
    """

    def __init__(self, context, tasks: Sequence[tuple[str, object]], needs: Sequence[int]) -> None:
        self.tasks = list(tasks)
        self.needs = list(needs)
        self.taken = context.RawArray("b", max(1, len(self.tasks)))
        self.ready = context.RawArray("b", max(1, len(self.tasks)))  # by task index: a track task done
        self.stopped = context.RawValue("b", 0)
        self.lock = context.Lock()  # a claim's scan and mark; no condition variable (see take)

    def take(self, start: int, runs: bool = True) -> int | None:
        """Claim the first free task from ``start`` on (wrapping round) whose track is ready, and return its index;
        wait while the only free tasks are runs on tracks still being prepared; None when none is left or the board
        is stopped. ``runs`` False: tracks only (None when no track is left).

        A waiting worker looks at the board again every ``_POLL`` s (a track takes seconds): a cross-process
        condition variable's ``notify_all`` waits for every waiter to wake, and hung for good on a worker ended while
        it waited (a stopped study's SIGTERM); the lock is taken with a timeout, so that a worker ended while it held
        it leaves the others the stop flag to see."""
        count = len(self.tasks)
        while not self.stopped.value:
            if not self.lock.acquire(timeout=_WAIT):
                continue
            try:
                waiting = False
                for k in (*range(start, count), *range(start)):
                    if self.taken[k] or (not runs and self.tasks[k][0] != "track"):
                        continue
                    if self.needs[k] >= 0 and not self.ready[self.needs[k]]:
                        waiting = runs
                        continue
                    self.taken[k] = 1
                    return k
            finally:
                self.lock.release()
            if not waiting:
                return None
            _look_again()
        return None

    def track_ready(self, k: int) -> None:
        """Task ``k``, a track, is done: its runs may start (one byte, which :meth:`take` reads under its lock)."""
        self.ready[k] = 1

    def stop(self) -> None:
        """No task is taken any more (a waiting worker sees it within ``_POLL``; ``_WAIT`` while the lock is held)."""
        self.stopped.value = 1


def _work(board: Board, start: int, connection, cancel=None, threads: int = 1, save=None, beside=None) -> None:
    """Take tasks from ``board`` (from ``start`` on) and do them, sending ``("run", k, summary)`` (the summary first
    given to ``save``, if any) or ``("track", k, None)`` for each, ``("end", None, None)`` when none is left,
    ``("failed", k, error)`` on an error (the board then stopped). A new track's precompute integrates in ``threads``
    threads. Runs are taken once the thread ``beside`` (if any) has ended (a precompute, in compiled code that leaves
    the GIL free, goes on beside it)."""
    from wheelrail.core.study.precompute import integration_threads, prepare_track
    from wheelrail.core.study.specs import compute_run

    k = None
    try:
        while (k := board.take(start, runs=beside is None or not beside.is_alive())) is not None:
            kind, item = board.tasks[k]
            if kind == "track":
                with integration_threads(threads):
                    prepare_track(item)
                board.track_ready(k)
                connection.send(("track", k, None))
            else:
                summary = compute_run(item, cancel)
                if save is not None:
                    save(summary)
                connection.send(("run", k, summary))
        connection.send(("end", None, None))
    except BaseException as error:  # noqa: BLE001 - every failure goes back to the study's process
        board.stop()
        _send_failed(connection, ("failed", k), error)
    finally:
        connection.close()


def _send_failed(connection, head: tuple, error: BaseException) -> None:
    """Send ``(*head, error)`` to the study's process; an error that does not pickle as its words."""
    try:
        connection.send((*head, error))
    except Exception:  # noqa: BLE001 - an error that does not pickle: its words
        connection.send((*head, WheelrailError(f"{type(error).__name__}: {error}")))


def _become_child(parent_pid: int) -> None:
    """A forked child's signals and watch: Ctrl-C left to the study's process (which ends this one), SIGTERM ends
    it (not the study's own handler, inherited), and it ends by itself when the study's process is gone."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    threading.Thread(target=watch_parent, args=(parent_pid,), name="wheelrail-parent-watch", daemon=True).start()


def _child(board: Board, start: int, connection, parent_pid: int, threads: int, save=None) -> None:
    """A forked worker: Ctrl-C left to the study's process (which ends this one), SIGTERM ends it, and it ends by
    itself when the study's process is gone; BLAS in one thread."""
    from wheelrail.core.study.threads import set_blas_threads_local

    _become_child(parent_pid)
    set_blas_threads_local(1)
    _work(board, start, connection, None, threads, save)


def execute_forked(
    specs: Sequence[RunSpec],
    workers: int,
    finished: Callable[[RunSummary], None],
    tracks: Sequence = (),
    started: Callable[[], None] | None = None,
    save: Callable[[RunSummary], None] | None = None,
) -> None:
    """Compute ``specs`` on ``workers`` workers: this process (a thread of its own) and ``workers - 1`` forked
    children, ``finished(summary)`` called in this thread as each run ends (``save(summary)`` first, in the worker
    that computed it: each writes its own run files). ``tracks`` (``precompute.TrackTask``: the
    tracks the disk cache lacks) are prepared first, one a worker (one integrating thread each; a single new track in
    ``workers`` threads), each track's runs taken once it is ready. ``started`` (:func:`execute`'s) is called once the
    children run, when this process may start threads again; a thread it returns (the caller's work beside the runs)
    is waited for before this process takes tasks. Call it only where :func:`fork_refusal` is None.

    A failed task, Ctrl-C or SIGTERM stops the board, ends the children (SIGTERM), stops this process's run at its next
    chunk of steps and re-raises; a child that dies without a word is a WheelrailError.
    """
    from wheelrail.core.study.threads import read_once

    context = multiprocessing.get_context("fork")
    runs = read_once(_by_model(specs))  # read before the fork: the children share them
    index = {(task.track, task.numerics): k for k, task in enumerate(tracks)}
    board = Board(
        context,
        [*(("track", task) for task in tracks), *(("run", spec) for spec in runs)],
        [*(-1 for _ in tracks), *(index.get((spec.params.track, spec.track_numerics), -1) for spec in runs)],
    )
    threads = workers if sum(task.new for task in tracks) == 1 else 1  # one new track: on every core
    workers = max(1, min(workers, len(board.tasks)))  # no child without a task to take
    children, readers = [], {}
    cancel = threading.Event()
    own = None
    try:
        for worker in range(1, workers):
            reader, writer = context.Pipe(duplex=False)
            start = worker * len(board.tasks) // workers
            child = context.Process(
                target=_child,
                args=(board, start, writer, os.getpid(), threads, save),
                name=f"wheelrail-study-{worker}",
                daemon=True,
            )
            child.start()
            writer.close()  # the child's alone: its end of file is the child's end
            children.append(child)
            readers[reader] = child
        reader, writer = context.Pipe(duplex=False)
        beside = started() if started is not None else None
        own = threading.Thread(
            target=_own_share, args=(board, writer, cancel, threads, save, beside), name="wheelrail-study-0"
        )
        own.start()
        readers[reader] = None
        _collect(board, readers, finished)
    except BaseException:
        board.stop()
        cancel.set()
        for child in children:
            child.terminate()
        raise
    finally:
        for child in children:
            child.join()
        if own is not None:
            own.join()
        for reader in readers:
            reader.close()


def _by_model(specs: Sequence[RunSpec]) -> list[RunSpec]:
    """The runs grouped by model, each model's in the order given, the models in the order of their first run: a
    worker's stretch of the board then holds few models, and it loads fewer models' compiled code."""
    first: dict[str, int] = {}
    for spec in specs:
        first.setdefault(spec.model, len(first))
    return sorted(specs, key=lambda spec: first[spec.model])


def _own_share(board: Board, connection, cancel, threads: int, save, beside=None) -> None:
    """This process's share of the board, in a thread of its own, BLAS in one thread: the new tracks at once, the
    runs once the thread ``beside`` (the caller's own work beside the runs, if ``started`` returned it) has ended, so
    that the work beside them does not share this process's GIL with runs (the children take them meanwhile)."""
    from wheelrail.core.study.threads import set_blas_threads_local

    set_blas_threads_local(1)
    if isinstance(beside, threading.Thread):
        _work(board, 0, _Kept(connection), cancel, threads, save, beside)  # the tracks, while it goes on
        beside.join()
    _work(board, 0, connection, cancel, threads, save)


class _Kept:
    """A connection whose ``close`` and end message wait for the last pass (:func:`_own_share`'s two passes)."""

    def __init__(self, connection) -> None:
        self.connection = connection

    def send(self, message) -> None:
        if message[0] != "end":
            self.connection.send(message)

    def close(self) -> None:
        pass


def _collect(board: Board, readers: dict, finished: Callable[[RunSummary], None]) -> None:
    """Hand each run's summary to ``finished`` as the workers send them, until every worker has ended; a worker's
    error is raised here, a child's end without a word is a WheelrailError."""
    open_readers = set(readers)
    while open_readers:
        for reader in wait(list(open_readers)):
            try:
                kind, k, payload = reader.recv()
            except EOFError:
                child = readers[reader]
                if child is not None:
                    child.join()
                board.stop()
                code = "" if child is None else f" (exit code {child.exitcode})"
                raise WheelrailError(f"a study worker process ended before its runs{code}") from None
            if kind == "failed":
                raise payload
            if kind == "end":
                open_readers.discard(reader)
            elif kind == "run":
                finished(payload)


@contextlib.contextmanager
def forked_call(call: Callable[[], object]) -> Iterator[Callable[[], object]]:
    """``call()`` in a forked child started now (only where :func:`fork_refusal` is None), while the block runs;
    yields a function that waits for its result (raising its error, or a WheelrailError if it died). Leaving the block
    before the result came back (an error, Ctrl-C) ends the child."""
    context = multiprocessing.get_context("fork")
    reader, writer = context.Pipe(duplex=False)
    child = context.Process(
        target=_call_child, args=(call, writer, os.getpid()), name="wheelrail-study-call", daemon=True
    )
    child.start()
    writer.close()
    received = []

    def result():
        try:
            kind, payload = reader.recv()
        except EOFError:
            child.join()
            raise WheelrailError(f"a study worker process ended before its work (exit code {child.exitcode})") from None
        received.append(kind)
        if kind == "failed":
            raise payload
        return payload

    try:
        yield result
    finally:
        if not received:
            child.terminate()
        child.join()
        reader.close()


def _call_child(call: Callable[[], object], connection, parent_pid: int) -> None:
    """A forked child's one call, its result or error sent back (as :func:`_child`'s tasks)."""
    _become_child(parent_pid)
    try:
        connection.send(("done", call()))
    except BaseException as error:  # noqa: BLE001 - every failure goes back to the study's process
        _send_failed(connection, ("failed",), error)
    finally:
        connection.close()
