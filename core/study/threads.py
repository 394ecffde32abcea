"""Running a study's runs in threads of this process: the compiled laws' loops release the GIL, so parallel threads
use every core while sharing what a process loads once (the compiled code, the roughness sets, the track), with
no worker process to start.

:func:`execute_threads` is the local backend of :func:`~wheelrail.core.study.execution.execute` for runs whose law
releases the GIL (:func:`releases_gil`); :func:`read_once` gives every run of a study its set already read.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import os
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import replace
from pathlib import Path

from wheelrail.core.study.specs import RunSpec, RunSummary, compute_run

__all__ = ["blas_threads", "execute_threads", "read_once", "releases_gil"]


def releases_gil(spec: RunSpec) -> bool:
    """Whether the run's contact law steps in compiled code without the GIL (``ContactLaw.nogil``): runs of it in
    parallel threads then use every core; a law stepped from Python (a plug-in's per-step ``solve``) needs a
    process per worker."""
    from wheelrail.core.engine.laws.base import law_class
    from wheelrail.core.models import model_entry

    return bool(law_class(model_entry(spec.model).traits).nogil)


def read_once(specs: Sequence[RunSpec]) -> list[RunSpec]:
    """The specs with each roughness set named by a file or bundled name read once and shared (a run reads its
    set again otherwise), and, for a run that takes the set as it is (no line mean, no lateral lines, no wheel set
    added), already interpolated along to the run's element size, as the run would interpolate it
    (``roughness.to_model_grid``; once, not once a run). The run keys are unchanged: they hash the sets' content."""
    from wheelrail.core.roughness import load_roughness, to_model_grid

    loaded: dict[object, object] = {}

    def read(source):
        if not isinstance(source, str | os.PathLike):
            return source
        key = os.fspath(source)
        if key not in loaded:
            loaded[key] = load_roughness(source)
        return loaded[key]

    def on_grid(rough, dx: float):
        key = (id(rough), dx)
        if key not in loaded:
            loaded[key] = (rough, to_model_grid(rough, dx))  # the set kept alive with its id
        return loaded[key][1]

    out = []
    for spec in specs:
        if spec.wheel_source is not None:
            out.append(replace(spec, source=read(spec.source), wheel_source=read(spec.wheel_source)))
        elif spec.averaged_lines or spec.lateral_lines_mm:
            out.append(replace(spec, source=read(spec.source)))
        else:
            out.append(replace(spec, source=on_grid(read(spec.source), spec.params.run.element_size)))
    return out


@functools.cache
def _openblas_libraries() -> tuple:
    """numpy's and scipy's OpenBLAS (the wheels' ``numpy.libs`` and ``scipy.libs``) that can set a thread's own
    number of BLAS threads (``openblas_set_num_threads_local``, OpenBLAS 0.3.27 on); none elsewhere (another BLAS)."""
    import numpy

    found = []
    site = Path(numpy.__file__).resolve().parent.parent
    for folder in ("numpy.libs", "scipy.libs"):
        for path in sorted((site / folder).glob("*openblas*.so*")):
            try:
                setter = ctypes.CDLL(str(path)).openblas_set_num_threads_local
            except (OSError, AttributeError):
                continue
            setter.restype, setter.argtypes = ctypes.c_int, [ctypes.c_int]
            found.append(setter)
    return tuple(found)


def set_blas_threads_local(threads: int) -> list[int]:
    """This thread's BLAS calls in ``threads`` threads of OpenBLAS's (numpy's and scipy's); returns the numbers they
    had (for :func:`blas_threads` to restore)."""
    return [setter(int(threads)) for setter in _openblas_libraries()]


@contextlib.contextmanager
def blas_threads(threads: int | None) -> Iterator[None]:
    """This thread's BLAS calls in ``threads`` threads while the block runs (None: as they are), restored after it:
    a study's ``workers`` are the cores it may use, and OpenBLAS's own threads on top of a study's threads would
    oversubscribe them (the noise chain's solves, the ``3d`` model's factorisations)."""
    if threads is None:
        yield
        return
    saved = set_blas_threads_local(threads)
    try:
        yield
    finally:
        for setter, value in zip(_openblas_libraries(), saved, strict=True):
            setter(max(1, value))


def execute_threads(
    specs: Sequence[RunSpec], workers: int, finished: Callable[[RunSummary], None], tracks: Sequence = ()
) -> None:
    """Compute ``specs`` in ``workers`` threads of this process, in the order given (longest first), calling
    ``finished(summary)`` in this thread as each run ends. Each thread's BLAS calls run in one thread.

    ``tracks`` (``precompute.TrackTask``: the tracks the disk cache lacks) are prepared first, in the same threads,
    a new track's precompute integrating in one thread (:func:`~wheelrail.core.study.precompute.integration_threads`)
    and sharing this process's compiled code: a run on such a track is queued as soon as its track is ready, while
    the next tracks are being prepared (the runs whose tracks are all held start at once, after the tracks queued).

    A failed run, Ctrl-C or SIGTERM (``execution``) stops the others at their next chunk of steps (their
    ``cancel`` event) and drops the queued ones; the runs already finished stay cached.
    """
    from wheelrail.core.study.precompute import prepare_track

    cancel = threading.Event()
    one = functools.partial(set_blas_threads_local, 1)
    waiting: dict[tuple, list[RunSpec]] = {(task.track, task.numerics): [] for task in tracks}
    ready = []
    for spec in read_once(specs):
        waiting.get((spec.params.track, spec.track_numerics), ready).append(spec)
    with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="wheelrail-study", initializer=one) as pool:
        preparing = {pool.submit(_prepared, prepare_track, task): task for task in tracks}
        pending = set(preparing) | {pool.submit(compute_run, spec, cancel) for spec in ready}
        try:
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    result = future.result()
                    if future in preparing:  # a track ready: its runs
                        task = preparing.pop(future)
                        runs = waiting.pop((task.track, task.numerics))
                        pending |= {pool.submit(compute_run, spec, cancel) for spec in runs}
                    else:
                        finished(result)
        except BaseException:
            cancel.set()  # the running runs end within a chunk; leaving the block waits for them
            for future in pending:
                future.cancel()
            raise


def _prepared(prepare: Callable, task):
    """``prepare(task)`` in this thread, a precompute integrating in one thread (a study's thread is one core)."""
    from wheelrail.core.study.precompute import integration_threads

    with integration_threads(1):
        return prepare(task)
