"""Time of the roughness prefilters on an 8 m line (8000 samples at 1 mm): the Winkler-equivalent roughness
(numba kernel, eqs. 12-13) and the contact-length average. The timing that tests/physics/
test_contact_hertz_winkler.py once asserted (0.2 s; ~2 ms expected) is printed here instead.

    python3 benchmarks/prefilter.py
"""

from __future__ import annotations

import os
import time

import numpy as np

from wheelrail.core.contact import average_roughness, winkler_equivalent_roughness


def main() -> None:
    x = np.arange(8000) * 1e-3
    line = 5e-6 * np.sin(2 * np.pi * x / 0.055) + 20e-6 * np.sin(2 * np.pi * x / 0.3)
    winkler_equivalent_roughness(line[:100], 1e-3)  # compile or load numba's cache
    for name, call in (
        ("winkler_equivalent_roughness", lambda: winkler_equivalent_roughness(line, 1e-3)),
        ("average_roughness", lambda: average_roughness(line, 1e-3)),
    ):
        times = []
        for _ in range(20):
            start = time.perf_counter()
            call()
            times.append(time.perf_counter() - start)
        print(f"{name:30s} 8 m line: best {min(times) * 1e3:6.2f} ms, median {np.median(times) * 1e3:6.2f} ms")
    print(f"load (1 min): {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
