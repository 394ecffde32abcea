"""The command line's account of a track precompute: a track not yet in the disk cache costs a one-off precompute
of its Green's functions (``wheelrail.core.track.progress``, its estimate ``PRECOMPUTE_CPU_S``); on a terminal
each phase is announced as it starts, the integration with a progress bar and its time estimate, like the run's
own bar (nothing when stderr is not a terminal: pipes and ``--json`` stay clean)."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator


@contextlib.contextmanager
def announce_track_precompute(command: str, stream=None) -> Iterator[None]:
    """Within this block, a track precompute is reported on ``stream`` (default stderr) if it is a terminal."""
    from wheelrail.core.track.progress import track_progress

    stream = sys.stderr if stream is None else stream
    if not stream.isatty():
        yield
        return
    state: dict = {"phase": None, "bar": None}

    def close_bar() -> None:
        if state["bar"] is not None:
            state["bar"].close()
            state["bar"] = None

    def progress(phase: str, done: int, total: int) -> None:
        if phase != state["phase"]:
            close_bar()
            if state["phase"] is None:
                print(f"wheelrail {command}: {_first_line()}", file=stream, flush=True)
            state["phase"] = phase
            print(f"wheelrail {command}: {phase}", file=stream, flush=True)
            if total > 1:
                from tqdm import tqdm

                state["bar"] = tqdm(total=total, unit="load position", file=stream, leave=False)
        if state["bar"] is not None:
            state["bar"].update(done - state["bar"].n)

    try:
        with track_progress(progress):
            yield
    finally:
        close_bar()


def _first_line() -> str:
    from wheelrail.core.files import cache

    try:
        where = f"in {cache.cache_dir()}"
    except ValueError:  # a WheelrailError about the folder is raised by the cache itself, in one line
        where = "on disk"
    return (
        "this track is not in the disk cache: computing its Green's functions once "
        f"(kept {where}, about 208 MB per track; `wheelrail cache` lists the entries)"
    )
