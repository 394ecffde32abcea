"""Rail damping: the model track's L_H,tr converges at 4 and 8 kHz with a rail loss factor.

With the paper's undamped rail, L_H,tr of the TWINS-like track (``core/noise/twins.py``) is not converged in the
4 and 8 kHz bands: doubling the frequencies per band moves them by up to 3.3 dB and doubling the elements per
bay by up to 5.2 dB (the undamped rail's pinned-pinned modes are too sharp for any fixed sampling). This prints,
for loss factors 0 and 0.02, L_H,tr per band at the default resolution (16 elements per bay, 20 frequencies per
band) and its change when each is doubled, and the largest change at 4 and 8 kHz.

Run: ``python3 validation/track_damping.py``.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from wheelrail.core.noise.twins import NoiseNumerics, track_noise_model
from wheelrail.core.parameters import ModelParameters, RailParameters


def main() -> None:
    base = NoiseNumerics()
    resolutions = {
        "default (16 el/bay, 20 f/band)": base,
        "elements doubled (32 el/bay)": replace(base, elements_per_bay=32),
        "frequencies doubled (40 f/band)": replace(base, points_per_band=40),
    }
    for eta in (0.0, 0.02):
        params = ModelParameters(track=replace(ModelParameters().track, rail=RailParameters(loss_factor=eta)))
        levels = {}
        for name, numerics in resolutions.items():
            start = time.perf_counter()
            model = track_noise_model(params, numerics)
            levels[name] = model.track_transfer_db
            print(f"eta = {eta}: {name}: {time.perf_counter() - start:.1f} s")
        f = model.frequency_hz
        ref = levels["default (16 el/bay, 20 f/band)"]
        print(f"\nrail loss factor {eta}: L_H,tr (dB) and its change when a resolution is doubled")
        print("  band Hz   L_H,tr   +elements  +frequencies")
        for i, fc in enumerate(f):
            diffs = [levels[name][i] - ref[i] for name in list(resolutions)[1:]]
            print(f"  {fc:7.0f}  {ref[i]:7.2f}   {diffs[0]:+7.2f}    {diffs[1]:+7.2f}")
        for fc in (4000, 8000):
            i = int(np.argmin(np.abs(f - fc)))
            worst = max(abs(levels[name][i] - ref[i]) for name in list(resolutions)[1:])
            print(f"  {fc} Hz band: largest change {worst:.2f} dB")
        print()


if __name__ == "__main__":
    main()
