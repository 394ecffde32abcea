"""The contact force's sleeper-passing harmonics, shared by ``bay_convergence.py`` and ``pad_harmonics.py``.

On a smooth rail the force on a wheel rolling over discrete supports varies with its place in the bay: the
parametric excitation, at the sleeper-passing harmonics k v / L_S. :func:`harmonics` reads their amplitudes off a
run's force over a whole number of bays (so that each harmonic is one bin of the record's Fourier series).
Imported by the two scripts (run from the repository root as ``python3 validation/pad_harmonics.py``, which puts this
folder on the import path); it prints nothing itself.
"""

from __future__ import annotations

import numpy as np


def whole_bays(result, sleeper_spacing: float, skip: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The force of ``result`` over the most whole bays after ``skip`` s, its mean removed (N), and its times from
    the segment's start (s)."""
    force = np.asarray(result.force)
    dt = result.time[1] - result.time[0]
    v = result.header.params.run.speed
    start = int(np.ceil(skip / dt))
    per_bay = sleeper_spacing / (v * dt)
    n = int(round(int((len(force) - start) / per_bay) * per_bay))
    seg = force[start : start + n] - np.mean(force[start : start + n])
    return seg, np.arange(n) * dt


def harmonics(result, sleeper_spacing: float, orders, skip: float = 0.0) -> np.ndarray:
    """Amplitudes (N) of the force of ``result`` at k v / L_S for the ``orders`` k, over the most whole bays after
    ``skip`` s (:func:`whole_bays`)."""
    seg, t = whole_bays(result, sleeper_spacing, skip)
    v = result.header.params.run.speed
    return np.array([2 * abs(np.mean(seg * np.exp(-2j * np.pi * k * v / sleeper_spacing * t))) for k in orders])
