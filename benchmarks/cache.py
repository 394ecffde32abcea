"""The disk cache's own costs on the paper's track entry: the digest checked on every load, the write, the
entry's size, and what reporting the precompute's progress costs (the integration in groups of load positions).

Run: python3 benchmarks/cache.py   (a private temporary cache: the precompute is real, twice, ~1 min on 2 cores)
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import time
from pathlib import Path

import numpy as np

os.environ["WHEELRAIL_CACHE_DIR"] = tempfile.mkdtemp(prefix="wheelrail-bench-cache-")

from wheelrail.core import track  # noqa: E402
from wheelrail.core.files import cache
from wheelrail.core.parameters import TrackNumerics, TrackParameters  # noqa: E402
from wheelrail.core.track.stationary import _WEDGE_ARRAYS, track_key  # noqa: E402


def best(function, repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    params, numerics = TrackParameters(), TrackNumerics()
    small = TrackNumerics(duration=0.001, positions_per_bay=8)
    track.compute_stationary_response(params, small, progress=lambda *_: None)  # numba compiled, not timed

    events = []
    start = time.perf_counter()
    response = track.stationary_track_response(params, numerics, progress=lambda *event: events.append(event))
    t_reported = time.perf_counter() - start
    start = time.perf_counter()
    track.compute_stationary_response(params, numerics)
    t_quiet = time.perf_counter() - start
    groups = sum(1 for phase, done, total in events if phase.startswith("integrating") and done < total)
    print(
        f"precompute with progress ({groups} groups, then written): {t_reported:6.2f} s; "
        f"computed in one call without progress (not written): {t_quiet:6.2f} s"
    )

    path = Path(response.cache_path)
    print(f"entry: {path.stat().st_size / 1e6:.1f} MB ({path.name})")
    key = track_key(params, numerics)
    arrays = {name: getattr(response, name) for name in _WEDGE_ARRAYS}
    data = memoryview(np.ascontiguousarray(response.data)).cast("B")
    for name in ("sha256", "blake2b"):
        t = best(lambda name=name: hashlib.new(name, data).hexdigest())
        print(f"{name} of the {len(data) / 1e6:.0f} MB data array: {t * 1e3:6.0f} ms ({len(data) / t / 1e9:.2f} GB/s)")
    t_load = best(lambda: cache.load_entry("track-wedge", key, _WEDGE_ARRAYS))
    t_read = best(lambda: dict(np.load(path)))
    print(f"load_entry (read + SHA-256 check): {t_load * 1e3:6.0f} ms; np.load alone: {t_read * 1e3:6.0f} ms")
    t_save = best(lambda: cache.save_entry("track-wedge", key, arrays), repeats=2)
    print(f"save_entry (digest + write + rename): {t_save * 1e3:6.0f} ms")


if __name__ == "__main__":
    main()
