"""Dense smooth-rail speed scan for period-two chatter, 5-400 km/h.

Run: python3 validation/speed_scan.py [STEP_KMH]   (default 0.05 km/h up to 20 km/h, then 1 km/h)
Prints, per speed, the largest second difference of the force on a smooth rail (N; chatter of amplitude A
gives 4 A) and the worst speeds; tests/physics/test_stability.py runs a sparse version of this scan.
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace

import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.parameters import KMH, MAX_SPEED_KMH, MIN_SPEED_KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import RoughnessSet


def main() -> None:
    fine = float(sys.argv[1]) if len(sys.argv) > 1 else 0.05
    speeds = np.concatenate([np.arange(MIN_SPEED_KMH, 20.0, fine), np.arange(20.0, MAX_SPEED_KMH + 1e-9, 1.0)])
    smooth = RoughnessSet.smooth(0.5)
    start = time.perf_counter()
    worst = []
    for kmh in speeds:
        params = replace(ModelParameters(), run=RunParameters(speed=float(kmh) * KMH))
        force = simulate(smooth, model="hertz", params=params, length=0.3, run_in_length=0.3).force
        worst.append(np.inf if not np.all(np.isfinite(force)) else float(np.max(np.abs(np.diff(force, 2)))))
    worst = np.array(worst)
    order = np.argsort(worst)[::-1][:10]
    print(f"{len(speeds)} speeds {speeds[0]:g}-{speeds[-1]:g} km/h in {time.perf_counter() - start:.1f} s")
    print("worst max|d2 F| (N): " + ", ".join(f"{speeds[i]:.2f} km/h {worst[i]:.1f}" for i in order))
    print(f"chatter (> 500 N) at: {speeds[worst > 500.0]}")


if __name__ == "__main__":
    main()
