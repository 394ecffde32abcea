"""Discretely supported track: FE model, receptances and moving Green's functions (paper section 2.2).

The rail is a chain of Rayleigh-Timoshenko beam elements over ``n_bays`` sleeper bays, free at both ends, on a
rail pad, (half) sleeper and ballast at every sleeper (``fe``: banded matrices, DOFs numbered node by node). The
impulse responses h(x, x_e, t) to loads at ``positions_per_bay`` points x_e of the central bay are integrated once
(Newmark's displacement recurrence, a profile Cholesky factor: ``newmark``) on the wedge a wheel at up to
``max_speed`` can reach (``stationary``); the moving Green's function of any lower speed is read off that wedge,
g(t) = h(x_e + v t, x_e, t), and cached per speed with its weights at the run's step (``moving``). The method and
its convergence: the documentation's physics page, "Wheel and track".
"""

# The package by concern: ``fe`` (the FE model, receptances), ``resonances`` (which peaks are which), ``newmark``
# (the time integration's kernel), ``stationary`` (the impulse responses integrated once and their disk cache),
# ``moving`` (the moving Green's functions, weights).
from wheelrail.core.track.fe import (
    HALF_BANDWIDTH,
    TrackFEModel,
    assemble_track,
    timoshenko_element_matrices,
    timoshenko_shape_functions,
    track_receptance,
)
from wheelrail.core.track.moving import (
    ROWS_PER_POSITION,
    MovingGreenFunctions,
    bay_rows,
    moving_from_stationary,
    moving_green_functions,
    moving_weights,
    trapezoidal_weights,
)
from wheelrail.core.track.resonances import RESONANCE_KINDS, Resonance, receptance_peaks
from wheelrail.core.track.stationary import (
    StationaryTrackResponse,
    clear_memory,
    compute_stationary_response,
    numerics_model,
    stationary_track_response,
    track_cache_path,
    track_key,
)

__all__ = [
    "RESONANCE_KINDS",
    "ROWS_PER_POSITION",
    "HALF_BANDWIDTH",
    "MovingGreenFunctions",
    "Resonance",
    "StationaryTrackResponse",
    "TrackFEModel",
    "assemble_track",
    "bay_rows",
    "clear_memory",
    "compute_stationary_response",
    "moving_from_stationary",
    "moving_green_functions",
    "moving_weights",
    "numerics_model",
    "receptance_peaks",
    "stationary_track_response",
    "timoshenko_element_matrices",
    "timoshenko_shape_functions",
    "track_cache_path",
    "track_key",
    "track_receptance",
    "trapezoidal_weights",
]
