"""Time of the wheel-centre trajectory (core/irregularities/trajectory.py) on a 100 m run sampled at 0.1 mm
(1 000 001 samples): smooth, with a 50 mm rounded flat every revolution (R = 0.46 m), and the same with a dipped
joint (a 0.5 mm step up) half way on 10 um rms roughness: band-limited (white noise averaged over 5 mm) and, the
worst case, white noise at 0.1 mm (every sample a peak: the scan reaches ~5 mm either way).

    python3 benchmarks/trajectory.py
"""

from __future__ import annotations

import time

import numpy as np

from wheelrail.core.irregularities import RailJoint, WheelFlat, raw_profile, wheel_centre_trajectory

RADIUS, SPACING, LENGTH = 0.46, 1e-4, 100.0


def main() -> None:
    x = np.arange(int(round(LENGTH / SPACING)) + 1) * SPACING
    flat = WheelFlat(length=0.05, position=0.5)
    joint = RailJoint(position=50.0, gap=0.01, step=0.5e-3, dip_angle=2e-3, dip_length=0.3)
    white = np.random.default_rng(1).standard_normal(x.size)
    smooth = np.convolve(white, np.ones(50) / 50, mode="same")
    smooth *= 10e-6 / smooth.std()
    cases = {
        "smooth": np.zeros(x.size),
        "flat every revolution": raw_profile([flat], x, wheel_radius=RADIUS),
        "flat, joint, roughness": raw_profile([flat, joint], x, wheel_radius=RADIUS) + smooth,
        "flat, joint, white noise": raw_profile([flat, joint], x, wheel_radius=RADIUS) + 10e-6 * white,
    }
    wheel_centre_trajectory(np.zeros(10), SPACING, RADIUS)  # compile or load numba's cache
    print(f"wheel_centre_trajectory, {LENGTH:.0f} m at {SPACING * 1e3:.1f} mm ({x.size} samples), R = {RADIUS} m")
    for name, profile in cases.items():
        times = []
        for _ in range(3):
            start = time.perf_counter()
            wheel_centre_trajectory(profile, SPACING, RADIUS)
            times.append(time.perf_counter() - start)
        print(f"  {name:28s} best of 3: {min(times):.3f} s")


if __name__ == "__main__":
    main()
