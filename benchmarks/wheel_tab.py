"""The explorer's Wheel tab's cost for the default configuration's wheel (the named wheel nearest the paper's
R = 390 mm, at that radius) in a fresh cache: its modes (the noise chain's settings, n = 0..10 up to 12.5 kHz), the
radiation table (the first time for a radius, tyre width and bore), the band power (24 bands, 1000 frequencies per
band), the modes read back from the disk cache, and one redraw's receptance (3000 frequencies and the natural
frequencies in range).

Run: python3 benchmarks/wheel_tab.py   (a private temporary cache; one to three minutes on 2 cores)
"""

from __future__ import annotations

import os
import tempfile
import time

import numpy as np

os.environ["WHEELRAIL_CACHE_DIR"] = tempfile.mkdtemp(prefix="wheelrail-bench-cache-")

from wheelrail.core.modal_wheel import contact_receptance, wheel_modes, wheel_profile_for  # noqa: E402
from wheelrail.core.modal_wheel import modes as modes_module  # noqa: E402
from wheelrail.core.noise.wheel_power import radiation_table  # noqa: E402
from wheelrail.explorer.wheel_tab import GRID_POINTS, MODE_SETTINGS, RECEPTANCE_RANGE_HZ, wheel_band_power  # noqa: E402


def timed(function):
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def main() -> None:
    print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores)")
    profile = wheel_profile_for(0.39)
    modes, seconds = timed(lambda: wheel_modes(profile, **MODE_SETTINGS))
    print(
        f"modes ({len(modes.frequency)} up to {modes.max_frequency:g} Hz, n = 0..{modes.max_harmonic}): {seconds:.1f} s"
    )
    _, seconds = timed(lambda: radiation_table(profile))
    print(f"radiation table (first time): {seconds:.1f} s")
    _, seconds = timed(lambda: wheel_band_power(profile))
    print(f"band power (24 bands x 1000 frequencies): {seconds:.1f} s")
    modes_module._MEMORY.clear()
    _, seconds = timed(lambda: wheel_modes(profile, **MODE_SETTINGS))
    print(f"modes read from the disk cache: {1e3 * seconds:.0f} ms")
    low, high = RECEPTANCE_RANGE_HZ
    f = np.unique(np.concatenate([np.geomspace(low, high, GRID_POINTS), modes.frequency[modes.frequency < high]]))
    _, seconds = timed(lambda: contact_receptance(modes, f))
    print(f"receptance of one redraw ({len(f)} frequencies): {1e3 * seconds:.0f} ms")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
