"""Track Green's functions: one-off precompute, a new speed, reload, cache size, truncation error.

Run: python3 benchmarks/track_green.py   (uses a private temporary cache, so the precompute is real)
Targets: precompute < 60 s, new speed < 1 s, reload < 0.2 s.
"""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

os.environ["WHEELRAIL_CACHE_DIR"] = tempfile.mkdtemp(prefix="wheelrail-bench-")

from wheelrail.core import track  # noqa: E402
from wheelrail.core.parameters import TrackNumerics, TrackParameters  # noqa: E402


def band_errors(values, dt, model, x, centres):
    t = np.arange(values.shape[-1]) * dt
    out = []
    for fc in centres:
        f = np.linspace(fc * 2 ** (-1 / 6), fc * 2 ** (1 / 6), 60)
        ours = np.exp(-2j * np.pi * np.outer(f, t)) @ values * dt
        exact = track.track_receptance(model, f, x)
        out.append(10 * np.log10(np.sum(np.abs(ours) ** 2) / np.sum(np.abs(exact) ** 2)))
    return np.array(out)


def main() -> None:
    params, numerics = TrackParameters(), TrackNumerics()
    # warm the numba caches on a tiny problem so the figures below are compute, not compilation
    track.stationary_track_response(params, replace(numerics, duration=0.001, positions_per_bay=1), use_cache=False)
    track.moving_from_stationary(
        track.stationary_track_response(
            params, replace(numerics, duration=0.001, positions_per_bay=1), use_cache=False
        ),
        10.0,
    )

    start = time.perf_counter()
    response = track.stationary_track_response(params, numerics)
    t_build = time.perf_counter() - start
    size = Path(response.cache_path).stat().st_size
    print(
        f"one-off precompute (70 bays, {numerics.positions_per_bay} positions, "
        f"{numerics.duration * 1e3:.0f} ms at {numerics.time_step * 1e6:.0f} us): {t_build:6.2f} s   target < 60 s"
    )
    print(f"cache on disk: {size / 1e6:.1f} MB  ({response.cache_path})")

    times = []
    for kmh in (75, 100, 140, 200):
        start = time.perf_counter()
        green = track.moving_from_stationary(response, kmh / 3.6)
        green.weights(1e-3 / green.speed)
        times.append(time.perf_counter() - start)
    print(f"new speed from memory (+ FOH weights): {max(times) * 1e3:6.1f} ms worst of 4   target < 1 s")

    reloads = []
    for _ in range(3):
        track._MEMORY.clear()
        start = time.perf_counter()
        response = track.stationary_track_response(params, numerics)
        reloads.append(time.perf_counter() - start)
    start = time.perf_counter()
    green = track.moving_from_stationary(response, 120 / 3.6)
    t_speed = time.perf_counter() - start
    print(
        f"reload from disk: {min(reloads) * 1e3:6.1f} ms best of 3 ({max(reloads) * 1e3:.0f} worst)   target < 0.2 s;"
        f" then one speed {t_speed * 1e3:.0f} ms"
    )

    # truncation error: third-octave band level of the point Green's function (walking pace) against
    # the exact frequency-domain receptance, for truncations of 20, 30 and 50 ms
    model = track.numerics_model(params, numerics)
    L = params.support.sleeper_spacing
    x_sleeper = (params.n_bays // 2) * L
    slow = track.moving_from_stationary(response, 0.05 / 3.6)
    centres = 1000 * 10 ** (np.arange(-13, 10) / 10)
    print("truncation error, dB per third-octave band (point GF vs frequency-domain receptance):")
    print("  band Hz      " + " ".join(f"{c:6.0f}" for c in centres))
    for label, index, x in (
        ("above sleeper", 0, x_sleeper),
        ("midspan", len(slow.excitation_positions) // 2, x_sleeper + L / 2),
    ):
        for duration in (0.02, 0.03, 0.05):
            n = int(round(duration / slow.time_step)) + 1
            err = band_errors(slow.values[index, :n], slow.time_step, model, x, centres)
            print(f"  {label:13s} {duration * 1e3:2.0f} ms " + " ".join(f"{e:+6.2f}" for e in err))


if __name__ == "__main__":
    main()
