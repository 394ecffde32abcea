"""Discretely supported track: FE model, receptances and moving Green's functions (paper section 2.2).

Model
-----
The rail is a chain of Rayleigh-Timoshenko beam elements (Friedman & Kosmatka's shear-dependent
interpolation, consistent translational and rotary mass) over ``n_bays`` sleeper bays, free at both
ends; undamped as in the paper, or with a loss factor on its bending and shear stiffness
(``RailParameters.loss_factor``: exact in the frequency domain, relaxation terms in the time domain,
``fe.rail_relaxation``). At every sleeper position x = j L_S (j = 0..n_bays) a rail pad (k_P, c_P) joins
the rail to a (half) sleeper mass, which rests on ballast (k_B, c_B) on rigid ground; the pad acts at a
point as in the paper, or spread over its width (``SupportParameters.pad_width``).

DOFs are numbered node by node (w_i, theta_i[, sleeper_i]) so that every matrix is banded with
half-bandwidth 4 (wider under pads of a width: ``TrackFEModel.half_bandwidth``); all solves are banded.

Moving Green's functions (eq. 2)
--------------------------------
The stationary track does not depend on speed. For ``positions_per_bay`` excitation points x_e in
the central bay (FE nodes: a load between nodes has a poorly converged early response), the impulse
response h(x, x_e, t) of the FE model is integrated once in time
(Newmark, average acceleration, step ``TrackNumerics.time_step``) and stored on the wedge
x_e <= x <= x_e + v_max t that a wheel at up to ``max_speed`` can reach. The moving Green's function
for any speed v <= v_max is then read off that wedge, g_{R,v}^{x_e}(t) = h(x_e + v t, x_e, t), with
the element's own shape functions between nodes: no new integration, a few milliseconds per speed.
Between the x_e the functions vary smoothly, with period L_S: they are refined ``BAY_REFINEMENT`` times
across the bay by trigonometric interpolation and then interpolated linearly (the loop's two-row mix).
Steps longer than ``parameters.FOH_MAX_STEP`` use weights of the trapezoidal rule integrated at the
loop's own step (``trapezoidal_weights``). Truncation: the functions are cut at
``TrackNumerics.duration``; the test suite and ``benchmarks/track_green.py`` show the truncation error.
What a run reads of them is cached on disk per speed, bit-identical: the functions (``moving_green_functions``)
and their weights at the run's step (``moving_weights``, all ``prepare_run`` reads: milliseconds, without the
stationary responses).
"""

# The package by concern: ``fe`` (the FE model, receptances, resonances), ``stationary`` (the impulse
# responses integrated once and their disk cache), ``moving`` (the moving Green's functions and weights).
from wheelrail.core.track.fe import (
    HALF_BANDWIDTH,
    TrackFEModel,
    assemble_track,
    receptance_peaks,
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
    "ROWS_PER_POSITION",
    "HALF_BANDWIDTH",
    "MovingGreenFunctions",
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
