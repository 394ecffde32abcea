"""The lateral track's convergence and its decay rates against EN ISO 3095's lateral limit (docs/track.md, Lateral).

Convergence: the lateral decay rate per band (EN 15461, 250 Hz-5 kHz) and the railhead's lateral point receptance
at midspan at the band centres on the default numerics (240 bays with 20 absorbing at each end, 16 elements per
bay, 20 frequencies per band) against 8 and 32 elements per bay and 120 and 360 bays; then the decay rate of a few
tracks (the paper's undamped rail, a rail loss factor of 0.02, stiffer and softer lateral pads) against the limit.
The independent check (the infinite periodic rail solved exactly in each bay) is tests/physics/test_track_lateral.py.

    python3 validation/lateral_convergence.py
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from wheelrail.core.noise.decay import lateral_decay_limit
from wheelrail.core.parameters import RailParameters, TrackParameters
from wheelrail.core.track.lateral import LateralNumerics, lateral_decay_rate, lateral_receptances

BANDS = lateral_decay_limit().frequency_hz


def _row(name: str, values, unit: str = "") -> None:
    print(f"{name:<34}" + "".join(f"{v:7.3f}" for v in values) + unit)


def convergence() -> None:
    base = LateralNumerics()
    cases = {
        "8 elements per bay": replace(base, elements_per_bay=8),
        "32 elements per bay": replace(base, elements_per_bay=32),
        "120 bays (10 absorbing)": replace(base, track_bays=120, absorbing_bays=10),
        "360 bays (30 absorbing)": replace(base, track_bays=360, absorbing_bays=30),
    }
    track = TrackParameters()
    print("band (Hz)                         " + "".join(f"{f:7.0f}" for f in BANDS))
    rate = lateral_decay_rate(track, BANDS, numerics=base)
    point = np.abs(lateral_receptances(track, BANDS, numerics=base).lateral_point)
    _row("decay rate, default (dB/m)", rate)
    for name, numerics in cases.items():
        other = lateral_decay_rate(track, BANDS, numerics=numerics)
        _row(f"  {name}: change (%)", 100 * (other / rate - 1))
    for name, numerics in cases.items():
        other = np.abs(lateral_receptances(track, BANDS, numerics=numerics).lateral_point)
        _row(f"  point receptance, {name} (dB)", 20 * np.log10(other / point))


def against_limit() -> None:
    paper = TrackParameters()
    tracks = {
        "paper's track (undamped rail)": paper,
        "rail loss factor 0.02": replace(paper, rail=RailParameters(loss_factor=0.02)),
        "lateral pads 60 MN/m": replace(paper, lateral=replace(paper.lateral, pad_lateral_stiffness=60e6)),
        "lateral pads 15 MN/m": replace(paper, lateral=replace(paper.lateral, pad_lateral_stiffness=15e6)),
    }
    print("\nLateral decay rate (dB/m) against EN ISO 3095:2013's lower limit (Figure 3, curve B)")
    print("band (Hz)                         " + "".join(f"{f:7.0f}" for f in BANDS))
    _row("limit", lateral_decay_limit().limit_db_per_m)
    for name, track in tracks.items():
        _row(name, lateral_decay_rate(track, BANDS))


if __name__ == "__main__":
    convergence()
    against_limit()
