"""The modal wheel's cost: meshing, assembling and solving every harmonic n = 0..10 up to 10 kHz for each named
wheel on the default 12 mm mesh (the target: under 10 s on 2 cores), a cached read, and the receptance and the
surface velocities over 1000 frequencies.

Run: python3 benchmarks/modal_wheel.py   (a private temporary cache; ~30 s on 2 cores)
"""

from __future__ import annotations

import os
import tempfile
import time

import numpy as np

os.environ["WHEELRAIL_CACHE_DIR"] = tempfile.mkdtemp(prefix="wheelrail-bench-cache-")

from wheelrail.core.modal_wheel import (  # noqa: E402
    NAMED_WHEELS,
    contact_receptance,
    mean_square_velocity,
    wheel_modes,
)
from wheelrail.core.modal_wheel import modes as modes_module  # noqa: E402


def timed(function):
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def main() -> None:
    print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores; other work slows the eigen-solves)")
    frequencies = np.linspace(10.0, 10e3, 1000)
    for name, profile in NAMED_WHEELS.items():
        modes, computed = timed(lambda profile=profile: wheel_modes(profile))
        modes_module._MEMORY.clear()  # the next call reads the disk cache
        _, cached = timed(lambda profile=profile: wheel_modes(profile))
        _, receptance = timed(lambda modes=modes: contact_receptance(modes, frequencies))
        _, velocity = timed(lambda modes=modes: mean_square_velocity(modes, frequencies))
        print(
            f"{name:12s} {len(modes.mesh.nodes):5d} nodes, {len(modes.frequency):3d} modes to 10 kHz (n <= 10): "
            f"computed in {computed:5.2f} s, read from the cache in {cached * 1e3:5.1f} ms; 1000 frequencies: "
            f"receptance {receptance * 1e3:5.1f} ms, surface velocities {velocity * 1e3:6.1f} ms"
        )


if __name__ == "__main__":
    main()
