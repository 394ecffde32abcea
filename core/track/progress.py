"""Progress of a track's Green's-function precompute (a one-off for a track not yet in the disk cache; its cost
estimated by :data:`PRECOMPUTE_CPU_S`).

``compute_stationary_response`` and ``stationary_track_response`` take ``progress``, a callable
``progress(phase, done, total)``: ``phase`` a short sentence saying what is being done (it names the work and,
when the cache knows how fast this machine computed an earlier track, an estimate of the time), ``done`` of
``total`` units of that phase. It is called a few times per phase, never per time step (cheap). The phases
are ``PHASES``: the FE track assembled and factorised, the integration's compiled code loaded (numba compiles it
on a fresh install: that wait is named, not counted in the integration), the impulse responses integrated (one
call at the start and one as each block of excitation positions, integrated in parallel threads, ends), the
entry's write to the cache started (it goes on in the background: ``cache.save_entry_behind``).

A caller that does not call these functions itself (the command line prepares a run through
``prepare_run``) sets the callable for everything below it with ``with track_progress(callback): ...``.
"""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Callable, Iterator

PRECOMPUTE_CPU_S = 4.5
"""CPU seconds of one track's precompute at the default numerics (``docs/benchmarks.md``): what a job that
needs new tracks is estimated at before it starts."""
ENTRY_BYTES = 208e6
"""Bytes of one track's disk-cache entry at the default numerics (``wheelrail cache`` lists them)."""

Progress = Callable[[str, int, int], None]
PHASES = ("assembling", "loading", "integrating", "saving")
_CURRENT: contextvars.ContextVar[Progress | None] = contextvars.ContextVar("wheelrail_track_progress", default=None)


@contextlib.contextmanager
def track_progress(callback: Progress | None) -> Iterator[None]:
    """Report the progress of any track precompute started in this block (this thread) to ``callback``."""
    token = _CURRENT.set(callback)
    try:
        yield
    finally:
        _CURRENT.reset(token)


def current_progress() -> Progress | None:
    """The callable set by the innermost ``track_progress`` block, or None."""
    return _CURRENT.get()


def estimate_s(work: float) -> float | None:
    """Seconds this machine should take for ``work`` (excitation positions x time steps x DOFs), scaled from the
    newest track entry in the disk cache that recorded its own; None if there is none."""
    from wheelrail.core.files import cache

    try:
        found = cache.entries()
    except (OSError, ValueError):  # no usable cache folder: no estimate
        return None
    for entry in reversed(found):  # most recently used first
        meta = (cache.stored_meta(entry.path) if entry.kind == "track-wedge" else None) or {}
        if meta.get("compute_s", 0) > 0 and meta.get("work", 0) > 0:
            return float(meta["compute_s"]) * work / float(meta["work"])
    return None
