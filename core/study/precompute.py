"""The tracks a study's runs need that the disk cache does not hold yet, each prepared once before the runs.

A run reads its track's moving Green's functions (``track.moving_weights``) from the disk cache, computing them on
a miss: a new track's one-off precompute. Left to the runs, two workers taking runs on the same new track would
both compute it, and a study of several new tracks would compute them in whatever order its runs come. So
:func:`track_tasks` groups the runs by track, and :func:`prepare_track` (a worker task) computes a track's
responses once and reads off the weights at every speed and time step its runs use; the tracks go to the workers
(processes or Dask workers) side by side, then the runs read them back.

A study's ``workers`` are the cores it may use: a precompute in the study's own process integrates in at most that
many threads (:func:`integration_threads`; one worker, one thread), the pool's workers in one thread each. With the
thread backend (``study.threads``) the new tracks are prepared in the study's threads, one integrating thread each,
and each track's runs start as soon as it is ready.
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from dataclasses import dataclass

from wheelrail.core.parameters import TrackNumerics, TrackParameters
from wheelrail.core.study.specs import RunSpec

__all__ = ["TrackTask", "integration_threads", "prepare_track", "track_tasks"]


@dataclass(frozen=True)
class TrackTask:
    """One track to prepare: its parameters, the (speed m/s, time step s) pairs whose weights its runs read, and
    whether its stationary responses are to be computed (``new``: the one-off precompute) or only read off."""

    track: TrackParameters
    readings: tuple[tuple[float, float], ...]
    new: bool
    numerics: TrackNumerics | None = None  # the runs' track numerics (None: the default)


def track_tasks(specs: Sequence[RunSpec]) -> list[TrackTask]:
    """The tracks of ``specs`` whose weights are not all in the disk cache, new ones (a precompute) first, in the
    order their runs come."""
    from wheelrail.core.track.moving import cached_reading

    readings: dict[tuple, dict[tuple[float, float], None]] = {}
    for spec in specs:
        run, track = spec.params.run, (spec.params.track, spec.track_numerics)
        readings.setdefault(track, {})[(float(run.speed), float(run.time_step))] = None
    tasks = []
    for (track, numerics), pairs in readings.items():
        held = {pair: cached_reading(*pair, track, numerics) for pair in pairs}
        missing = tuple(pair for pair, what in held.items() if what != "weights")
        if missing:
            tasks.append(TrackTask(track, missing, new=any(held[pair] == "" for pair in missing), numerics=numerics))
    return sorted(tasks, key=lambda task: not task.new)


def prepare_track(task: TrackTask) -> TrackTask:
    """Compute (or read off) the track's weights at each of its readings into the disk cache (the worker task);
    returns the task once every entry it wrote is on disk (a new track's responses are written in the
    background: another process reads them from the disk, ``cache.wait_for_writes``)."""
    from wheelrail.core.files import cache
    from wheelrail.core.track import moving_weights

    for speed, time_step in task.readings:
        moving_weights(speed, time_step, task.track, task.numerics)
    cache.wait_for_writes()
    return task


def integration_threads(cores: int) -> contextlib.AbstractContextManager[None]:
    """A new track's precompute started in this thread integrates in at most ``cores`` threads while the block runs
    (``track.stationary.integration_threads``: this thread's number, so that precomputes in other threads of the
    study, each in its own number of threads, run side by side; imported when used, as the precompute is)."""
    from wheelrail.core.track.stationary import integration_threads as threads

    return threads(cores)
