"""The pass-by level of a train from the A-weighted sound power of its axles, at the ISO 3095 position.

Every axle a point source of the axle's sound power W radiating into the half space above a rigid ground
(p^2 = rho c W / (2 pi r^2)), moving at speed v past the microphone at d = sqrt(7.5^2 + 1.2^2) m; the derivation
and its train-length correction are in :mod:`wheelrail.core.noise.run_noise`'s docstring. Held apart so that both a
run's stationary noise (:mod:`~wheelrail.core.noise.run_noise`) and an impact's
(:mod:`~wheelrail.core.noise.impact_noise`) use the one formula.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.noise.radiation import AIR_DENSITY, SOUND_SPEED
from wheelrail.core.spectra.levels import PRESSURE_REFERENCE

__all__ = [
    "DEFAULT_TRAIN_AXLES",
    "DEFAULT_TRAIN_LENGTH",
    "ISO3095_DISTANCE",
    "ISO3095_HEIGHT",
    "pass_by_level",
    "receiver_distance",
]

ISO3095_DISTANCE = 7.5  # m from the track centre line
ISO3095_HEIGHT = 1.2  # m above the rail head
DEFAULT_TRAIN_AXLES = 40
DEFAULT_TRAIN_LENGTH = 200.0  # m


def receiver_distance() -> float:
    """Distance (m) from the rail head on the track centre to the ISO 3095 microphone."""
    return math.hypot(ISO3095_DISTANCE, ISO3095_HEIGHT)


def pass_by_level(l_wa_axle: float, axles: int, train_length: float, distance: float | None = None) -> float:
    """L_pAeq,Tp (dB(A)) of ``axles`` axles of A-weighted sound power ``l_wa_axle`` (dB re 1 pW) in a train of
    ``train_length`` m (module docstring)."""
    d = receiver_distance() if distance is None else distance
    constant = 10 * math.log10(AIR_DENSITY * SOUND_SPEED * 1e-12 / PRESSURE_REFERENCE**2)
    return l_wa_axle + 10 * math.log10(_exposure_within_tp(axles, train_length, d) / (2 * d * train_length)) + constant


def _exposure_within_tp(axles: int, train_length: float, distance: float) -> float:
    """sum_k [atan(s_k / d) + atan((l - s_k) / d)] / pi over axles at s_k evenly from 0 to l: the number of
    axles' whole sound exposures that arrive within T_p (each axle's exposure is spread over its whole passage,
    and the first and last ones are only half inside; N for a train much longer than d)."""
    s = np.linspace(0.0, train_length, int(axles))
    return float(np.sum(np.arctan(s / distance) + np.arctan((train_length - s) / distance)) / math.pi)
