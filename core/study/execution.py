"""Running a study's runs: read back the cached ones, compute the missing ones in this process, on forked copies of
it (:mod:`wheelrail.core.study.forked`, Linux), in threads of it (:mod:`wheelrail.core.study.threads`: the compiled
laws release the GIL), on a local process pool
(``concurrent.futures.ProcessPoolExecutor``, spawned workers) or on a Dask cluster (``dask.distributed``), and write
each finished run at once (:mod:`wheelrail.core.study.store`). The tracks the runs need that the disk cache does not
hold are prepared before their runs, one task per track, side by side on the workers
(:mod:`wheelrail.core.study.precompute`).

Shutdown: pool workers exit by themselves within ``PARENT_POLL_INTERVAL`` when the process that started
them dies (even by kill -9), so no worker and no multiprocessing resource tracker outlives a study; a
SIGTERM during :func:`execute` is handled like Ctrl-C (queued runs dropped, workers stopped, finished runs
kept) unless the program installed its own SIGTERM handler.
"""

from __future__ import annotations

import atexit
import contextlib
import functools
import importlib.util
import os
import re
import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, replace
from pathlib import Path

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.models import model_entry
from wheelrail.core.study.forked import execute_forked, fork_refusal, watch_parent
from wheelrail.core.study.precompute import TrackTask, integration_threads, prepare_track, track_tasks
from wheelrail.core.study.specs import RunSpec, RunSummary, compute_run
from wheelrail.core.study.store import load_cached, save_cached
from wheelrail.core.study.threads import blas_threads, execute_threads, read_once, releases_gil

DASK_CONNECT_TIMEOUT = "10s"  # how long to try reaching a Dask scheduler before giving up
_ADDRESS = re.compile(r"^(tcp|tls|inproc|ucx)://[^\s:/]+(:\d{1,5})?$")
# Dask is an optional extra (pyproject.toml: cluster); the process pool needs nothing more
NO_DASK = "needs Dask, an optional part of wheelrail: pip install 'wheelrail[cluster]'"
# the local workers: auto = forked processes where this process may fork (forked.fork_refusal), else threads when every
# run's law releases the GIL, else the process pool
BACKENDS = ("auto", "fork", "threads", "processes")


class StudyTerminated(KeyboardInterrupt):
    """SIGTERM arrived while a study ran: unwinds like Ctrl-C (the CLI reports ``interrupted``)."""


def parse_dask_address(address: str) -> str:
    """Check a Dask scheduler address (``tcp://HOST:PORT``) and that Dask is installed; returns the address or
    raises WheelrailError."""
    if importlib.util.find_spec("distributed") is None:
        raise _no_dask()
    text = str(address).strip()
    if "://" not in text:
        text = f"tcp://{text}"
    match = _ADDRESS.match(text)
    port = match.group(2) if match else None
    if match is None or (port is not None and not 0 < int(port[1:]) < 65536):
        raise WheelrailError(
            "not a scheduler address; expected tcp://HOST:PORT", Blame("dask", address, argument="dask_address")
        )
    return text


def _no_dask() -> WheelrailError:
    """Dask asked for (a scheduler address given) but not installed: keyed to the address's input."""
    return WheelrailError(NO_DASK, Blame("dask", argument="dask_address"))


@dataclass(frozen=True)
class ExecutionReport:
    """What :func:`execute` did: summaries by run key, and how many runs were computed vs read back."""

    summaries: dict[str, RunSummary]
    computed: int
    cached: int
    wall_time: float
    backend: str


def _cost(spec: RunSpec) -> float:
    """Rough relative cost, to start the long runs first (a 3D step costs ~30 one-line steps; a per-step law
    called from Python more)."""
    traits = model_entry(spec.model).traits
    per_step = 50.0 if not traits.compiled else 30.0 if traits.lateral_window else 1.0
    return per_step * (spec.length or 3.0)


def execute(
    specs: Sequence[RunSpec],
    *,
    cache: str | os.PathLike,
    workers: int = 2,
    dask_address: str | None = None,
    progress: bool = True,
    description: str = "runs",
    backend: str = "auto",
    started: Callable[[], None] | None = None,
) -> ExecutionReport:
    """Run every spec not yet in ``cache`` and return all summaries.

    Parameters
    ----------
    specs : sequence of RunSpec
        Independent runs; duplicates (same key) run once.
    cache : path
        Folder of finished runs (``run-<key>.npz``, written atomically as each run finishes; an unusable
        file is recomputed with a warning).
    workers : int
        Local workers (threads of this process or worker processes, ``backend``); 1 runs in this process. Ignored
        with Dask.
    dask_address : str, optional
        Scheduler address of a running Dask cluster (``tcp://HOST:PORT``); runs are submitted there with
        ``dask.distributed.Client(address)``. Results come back to this process, which writes the cache.
    progress : bool
        Show a tqdm bar of runs done on stderr.
    backend : str
        The local workers: ``"fork"`` (this process and ``workers - 1`` forked copies of it, which start in
        milliseconds with what it has loaded: :mod:`~wheelrail.core.study.forked`; Linux, from the main thread
        with no other thread alive, else a WheelrailError), ``"threads"`` (threads of this process, sharing its
        compiled code, sets and tracks, and its GIL), ``"processes"`` (a kept pool of spawned processes) or
        ``"auto"``: fork where it can be used (:func:`~wheelrail.core.study.forked.fork_refusal`), else threads
        when every missing run's law releases the GIL (``ContactLaw.nogil``: the bundled models), else processes.
        The tracks not in the disk cache are prepared before their runs: forked or on threads, by the same workers
        (a precompute in each, integrating in one thread), each track's runs taken as soon as it is ready; with
        processes, first, two or more new ones side by side in the process pool.
    started : callable, optional
        Called when this process has GIL to spare for the caller's own work beside the runs (``runner.run_study``),
        which may start a thread: once a run has finished where the runs are computed in this process (their first
        load of numba's compiled code holds the GIL), once the forked workers run (never before the fork), at once
        where a new track's precompute comes first or the runs go to worker processes or Dask, and at the end; it
        may be called more than once.

    Returns
    -------
    ExecutionReport
    """
    from tqdm import tqdm

    class Bar(tqdm):
        monitor_interval = 0  # no monitor thread: the study's process may fork its workers

    if isinstance(workers, bool) or int(workers) != workers or workers < 1:
        raise WheelrailError(f"workers must be a positive integer, got {workers!r}")
    if backend not in BACKENDS:
        raise WheelrailError(f"backend must be one of {', '.join(BACKENDS)}, got {backend!r}")
    cache = Path(cache)
    cache.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    unique: dict[str, RunSpec] = {}
    for spec in specs:
        unique.setdefault(spec.key, spec)
    summaries = {key: found for key, spec in unique.items() if (found := load_cached(cache, spec)) is not None}
    missing = sorted((spec for key, spec in unique.items() if key not in summaries), key=_cost, reverse=True)
    n_cached = len(summaries)
    bar = Bar(total=len(unique), initial=n_cached, unit="run", desc=description, disable=not progress, file=sys.stderr)

    def finished(summary: RunSummary, saved: bool = False) -> None:
        if not saved:  # forked workers write their own
            save_cached(cache, summary)
        summaries[summary.key] = summary
        bar.update(1)
        if started is not None:
            started()

    try:
        used = _dispatch(missing, int(workers), dask_address, finished, backend, started, cache)
    finally:
        bar.close()
        if started is not None:
            started()
    return ExecutionReport(
        summaries=summaries,
        computed=len(summaries) - n_cached,
        cached=n_cached,
        wall_time=time.perf_counter() - start,
        backend=used,
    )


def _dispatch(
    missing: list[RunSpec],
    workers: int,
    dask_address: str | None,
    finished: Callable[[RunSummary], None],
    backend: str = "auto",
    started: Callable[[], None] | None = None,
    cache: Path | None = None,
) -> str:
    """Compute the missing runs where asked; returns the backend's name for the report. ``started``: as
    :func:`execute`'s, called here where this process only waits (Dask, worker processes). ``cache``: the folder
    of run files, which forked workers write themselves (``finished(summary, saved=True)`` then)."""
    started = started or (lambda: None)
    if dask_address is not None:  # connect even when all runs are cached: a bad address is an error
        started()
        _execute_dask(missing, dask_address, finished)
        return f"dask {dask_address}"
    if not missing:
        return "cache"
    if workers == 1 or len(missing) == 1:
        # one worker, one core: a new track's precompute (in its first run) in one thread, BLAS in one
        with integration_threads(workers), blas_threads(1 if workers == 1 else None):
            for spec in read_once(missing):
                finished(compute_run(spec))
        return "in-process"
    refusal = fork_refusal() if backend in ("auto", "fork") else backend
    if backend == "fork" and refusal is not None:
        raise WheelrailError(f"the fork backend cannot be used here: {refusal}")
    threads = backend == "threads" or (backend == "auto" and all(releases_gil(spec) for spec in missing))
    with _terminate_as_interrupt():
        if refusal is None:  # copies of this process, started in milliseconds with what it has loaded
            save = None if cache is None else functools.partial(save_cached, cache)  # each worker its run files
            done = finished if cache is None else functools.partial(finished, saved=True)
            execute_forked(missing, workers, done, track_tasks(missing), started, save)
            return f"forked processes ({workers} workers)"
        if threads:  # the tracks prepared in the same threads, each track's runs started once it is ready
            tasks = track_tasks(missing)
            if any(task.new for task in tasks):
                started()  # a precompute takes seconds, mostly in compiled code that leaves the GIL free
            execute_threads(missing, workers, finished, tasks)
            return f"threads ({workers} workers)"
        _prepare_tracks(track_tasks(missing), workers, started)
        started()
        _execute_pool(missing, workers, finished)
    return f"process pool ({workers} workers)"


def _prepare_tracks(tasks: list[TrackTask], workers: int, started: Callable[[], None] | None = None) -> None:
    """The tracks the runs need and the disk cache lacks, before the runs on the process pool (``workers``, two or
    more): two or more new ones (each a precompute) side by side in the pool, one thread each; the others (a reading
    off a cached track, or one new track) in this process, a precompute there in at most ``workers`` threads
    (``workers`` are the cores the study may use)."""
    new = [task for task in tasks if task.new]
    pooled = new if len(new) >= 2 else []
    if new and started is not None:
        started()  # a precompute takes seconds, mostly in threads or processes that leave the GIL free
    if pooled:
        _pool_map(prepare_track, pooled, workers)
    with integration_threads(workers):
        for task in tasks:
            if task not in pooled:
                prepare_track(task)


# --------------------------------------------------------------------------------------------------
# Local process pool
# --------------------------------------------------------------------------------------------------

_BLAS_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")


@contextlib.contextmanager
def _single_threaded_blas():
    """One BLAS thread, and one thread for a track's precompute, in worker processes started inside this block
    (unless the user set a number).

    The workers already run in parallel; OpenBLAS's own threads on top oversubscribe the cores, and the
    3D solver's many small factorisations then wait on each other's threads. Dask's nanny sets the same
    BLAS variables for its workers. A new track's precompute integrates in ``NUMBA_NUM_THREADS`` threads
    (``track.stationary``); the pool gets two or more tracks side by side, one a worker, which with one thread
    each keep the cores busy (one precompute's two threads keep about one core busy, at the same CPU time). The
    variables are read when the library loads, so they are set in this process while the pool spawns its workers,
    then restored.
    """
    saved = {name: os.environ.get(name) for name in _BLAS_THREAD_VARIABLES}
    for name, value in saved.items():
        if value is None:
            os.environ[name] = "1"
    try:
        yield
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)


def _raise_terminated(signum, frame):
    raise StudyTerminated()


@contextlib.contextmanager
def _terminate_as_interrupt():
    """Turn SIGTERM into :class:`StudyTerminated` while the block runs, so it unwinds like Ctrl-C.

    Only in the main thread (where Python runs signal handlers) and only over the default action (which
    would end the process without stopping the workers); a handler the program installed is left alone.
    """
    if (
        threading.current_thread() is not threading.main_thread()
        or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL
    ):
        yield
        return
    signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _start_worker(parent_pid: int) -> None:
    """Pool initializer: a daemon thread watches the parent, so that the worker does not outlive it.

    A spawned worker is a child of the process that submitted the runs; when that process dies without
    stopping the pool (kill -9, a crash), the worker would otherwise wait for tasks forever, keeping
    ~250 MB and the multiprocessing resource tracker (which waits for every holder of its pipe) alive.
    Polling ``os.getppid()`` works on every POSIX system; Linux's ``PR_SET_PDEATHSIG`` is not used because it
    fires when the parent *thread* that spawned the worker ends, which in a threaded program (the
    explorer) is not the end of the process.
    """
    threading.Thread(target=watch_parent, args=(parent_pid,), name="wheelrail-parent-watch", daemon=True).start()
    from wheelrail.core.startup import fast_start

    fast_start()  # the worker's first numba load without scipy.linalg's package and numpy.f2py (core/startup.py)


_POOLS: dict[tuple[int, str], ProcessPoolExecutor] = {}


def _pool_key(workers: int) -> tuple[int, str]:
    """A kept pool's key: its workers and the disk cache its workers read and write (the folder is read from the
    environment when a worker starts: a process that changes it needs new workers)."""
    from wheelrail.core.files.cache import cache_dir

    return workers, os.fspath(cache_dir())


def _pool(workers: int) -> ProcessPoolExecutor:
    """The process pool of ``workers`` workers, kept for later studies in this process (their start-up,
    imports and numba's cached kernels, is paid once) while the disk cache folder is the same."""
    import multiprocessing

    key = _pool_key(workers)
    pool = _POOLS.get(key)
    if pool is None or getattr(pool, "_broken", False):
        # spawn, not fork: the parent may hold threads (tqdm monitor, a Dask client, the GUI's server)
        # that a forked child would inherit in an undefined state
        pool = ProcessPoolExecutor(
            max_workers=workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=_start_worker,
            initargs=(os.getpid(),),
        )
        _POOLS[key] = pool
    return pool


def _stop_pool(workers: int, pool: ProcessPoolExecutor) -> None:
    """Drop the pool and end its workers now, including those in the middle of a run."""
    for key, kept in list(_POOLS.items()):
        if kept is pool:
            del _POOLS[key]
    # the executor has no public way to end a running task: its worker processes are stopped directly
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.terminate()
    for process in processes:
        process.join()


def shutdown_pools() -> None:
    """Stop the worker processes kept by :func:`execute` (also done at interpreter exit)."""
    while _POOLS:
        _, pool = _POOLS.popitem()
        pool.shutdown(wait=True, cancel_futures=True)


atexit.register(shutdown_pools)


def _execute_pool(missing: list[RunSpec], workers: int, finished: Callable[[RunSummary], None]) -> None:
    _pool_map(compute_run, missing, workers, finished)


def _pool_map(task: Callable, items: list, workers: int, finished: Callable | None = None) -> None:
    """``task`` of each item on the process pool of ``workers`` (in the order given), ``finished(result)`` in this
    process as each ends."""
    pool = _pool(workers)
    pending = set()
    try:
        with _single_threaded_blas():  # new workers start (and read these variables) on the first submits
            pending = {pool.submit(task, item) for item in items}
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                result = future.result()
                if finished is not None:
                    finished(result)
    except BrokenProcessPool:
        _stop_pool(workers, pool)
        raise WheelrailError(
            "a study worker process died; in a script, call the study API under "
            "`if __name__ == '__main__':` (workers are spawned and import the main module)"
        ) from None
    except BaseException:
        # interrupted or a run failed: drop the queued runs; the finished ones are already cached
        for future in pending:
            future.cancel()
        if not isinstance(sys.exc_info()[1], Exception):  # Ctrl-C or SIGTERM: stop the workers too
            _stop_pool(workers, pool)
        raise


# --------------------------------------------------------------------------------------------------
# Dask
# --------------------------------------------------------------------------------------------------


def _portable(spec: RunSpec, loaded: dict) -> RunSpec:
    """The spec with a user file's roughness loaded into it: Dask workers may run on other machines that
    see the installed bundled sets but not this machine's files (the key is unchanged: it hashes content)."""
    from wheelrail.core.roughness import bundled_names, load_roughness

    if isinstance(spec.source, str | os.PathLike) and str(spec.source) not in bundled_names():
        key = str(spec.source)
        if key not in loaded:
            loaded[key] = load_roughness(spec.source)
        return replace(spec, source=loaded[key])
    return spec


def _execute_dask(missing: list[RunSpec], address: str, finished: Callable[[RunSummary], None]) -> None:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise _no_dask() from None
    address = parse_dask_address(address)
    try:
        client = Client(address, timeout=DASK_CONNECT_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as error:
        first = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise WheelrailError(f"cannot reach the Dask scheduler at {address}: {first}") from None
    try:
        if not missing:
            return
        tracks = track_tasks(missing)  # each new track once, side by side, before the runs that read it
        for future in as_completed(client.map(prepare_track, tracks, pure=False)):
            future.result()
        loaded: dict = {}
        missing = [_portable(spec, loaded) for spec in missing]
        keys = [f"wheelrail-run-{spec.key[:32]}" for spec in missing]
        futures = client.map(compute_run, missing, key=keys, pure=False)
        for future in as_completed(futures):
            finished(future.result())
    finally:
        client.close()
