"""The free wave's decay on the noise model's track against the continuously supported beam (docs/noise.md).

Known answer: an Euler-Bernoulli beam on a continuous support of the same pads, sleepers and ballast per unit length,
EI k^4 = m' w^2 - s(w), s = k_P (k_B - m_S w^2) / (k_P + k_B - m_S w^2) / L_S (complex stiffnesses with their
damping); decay 20 lg(e) |Im k| of the propagating wave. The model's free-wave decay is the slope of the rail's band
level at the sleepers 3 to 20 bays from a midspan load (``twins.free_wave_decay_dB_per_m``), on the default
numerics (240 bays, 16 elements per bay, 20 frequencies per band) and the tests' small ones (60, 8, 2).

    WHEELRAIL_CACHE_DIR=/tmp/cache python3 validation/free_wave_decay.py
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.noise.twins import NoiseNumerics, track_decay_rates
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.spectra.bands import noise_bands


def continuous_beam_decay(params: ModelParameters) -> np.ndarray:
    """dB/m at the 24 band centres (module docstring)."""
    rail, sup = params.track.rail, params.track.support
    w = 2 * np.pi * noise_bands()
    kp = sup.pad_stiffness + 1j * w * sup.pad_damping
    kb = sup.ballast_stiffness + 1j * w * sup.ballast_damping
    s = kp * (kb - sup.sleeper_mass * w**2) / (kp + kb - sup.sleeper_mass * w**2) / sup.sleeper_spacing
    k4 = (rail.mass_per_length * w**2 - s) / rail.bending_stiffness
    roots = k4**0.25 * np.exp(0.5j * np.pi * np.arange(4))[:, None]
    return 20 * math.log10(math.e) * np.min(np.abs(roots.imag), axis=0)


def main() -> None:
    params = ModelParameters()
    beam = continuous_beam_decay(params)
    f = noise_bands()
    small = NoiseNumerics(track_bays=60, elements_per_bay=8, points_per_band=2)
    for name, numerics in (("default 240 x 16 x 20", NoiseNumerics()), ("small 60 x 8 x 2", small)):
        _, _, free = track_decay_rates(params.track, numerics)
        print(f"{name}: band, model, beam (dB/m), difference")
        for fi, model, known in zip(f, free, beam, strict=True):
            if fi < 1000:
                print(f"  {fi:6.0f} Hz {model:7.3f} {known:7.3f} {100 * (model / known - 1):+6.1f} %")
        bands = (f < 270) | ((f > 350) & (f < 900))
        worst = np.max(np.abs(free[bands] / beam[bands] - 1))
        print(f"  largest difference at 50-250 and 400-800 Hz: {100 * worst:.1f} %")


if __name__ == "__main__":
    main()
