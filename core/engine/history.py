"""The loop's history: the moving Green's functions, the wheel's discrete system, the positions in the sleeper bay
and the preload's force history (eqs. 1-2), and the run-in that leads to the first recorded step; a run's run-in
(:func:`run_in`) and its history with the contact model prepared on it (:func:`run_history`).

Start-up: from the moving load's steady state on the gap of step 0 (``steady_start``), then a run-in of
``DEFAULT_RUN_IN_TIME`` (discarded). An explicit run-in, or a bay of no whole number of elements, starts from the
preload in static equilibrium, the roughness faded in over the run-in's first half, which must let the
transient decay: ``PRELOAD_RUN_IN_TIME``. What each leaves: the physics page, "How a step is solved".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from wheelrail.core.engine.track_lines import TrackRoughness
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import real
from wheelrail.core.models import ModelInputs
from wheelrail.core.parameters import ModelParameters, TrackNumerics

__all__ = [
    "DEFAULT_RUN_IN_TIME",
    "PRELOAD_RUN_IN_TIME",
    "History",
    "check_step_stability",
    "default_run_in_length",
    "history_arrays",
    "model_inputs",
    "run_history",
    "run_in",
    "starts_steady",
]

DEFAULT_RUN_IN_TIME = 0.0005  # s of run-in from the moving load's steady state (discarded); see the module docstring
PRELOAD_RUN_IN_TIME = 0.3  # s of smooth run-in from the preload at rest: where no steady start is taken


def starts_steady(params: ModelParameters) -> bool:
    """Whether a run with the default run-in starts from the steady state: the bay is whole elements."""
    from wheelrail.core.engine.steady_start import bay_steps

    return bay_steps(params.track.support.sleeper_spacing, params.run.element_size) is not None


def default_run_in_length(params: ModelParameters | None = None) -> float:
    """The default run-in at the run's speed in whole elements, m (:func:`starts_steady`: which time)."""
    params = ModelParameters() if params is None else params
    dx = params.run.element_size
    time = DEFAULT_RUN_IN_TIME if starts_steady(params) else PRELOAD_RUN_IN_TIME
    return math.ceil(time * params.run.speed / dx - 1e-9) * dx


def run_in(params: ModelParameters, run_in_length: float | None = None) -> tuple[float, bool]:
    """A run's run-in, m, and whether the run starts from the moving load's steady state.

    None: :func:`default_run_in_length`, from the steady state where the bay is whole elements
    (:func:`starts_steady`); a run-in given (m, zero or more) starts from the preload at rest. The run-in's length
    is asked for before the lines are laid (the run's memory check takes it), its arrays after
    (:func:`run_history`)."""
    steady = run_in_length is None and starts_steady(params)
    if run_in_length is None:
        run_in_length = default_run_in_length(params)
    return real("run_in_length", run_in_length, "m", sign="nonnegative"), steady


@dataclass
class History:
    """The loop's arrays (history index j = n_hist + s; s counts the run-in too).

    The track part (``force``, ``lo``, ``hi``, ``frac``, ``weights``, ``acc``) and the wheel part (``phi``,
    ``gamma0``, ``gamma1``, ``state``) are also held as the tuples ``track`` and ``wheel`` that the compiled
    kernels take. ``xi_w0`` and the ``static_approach`` it stands on are set last (:meth:`History.settle`).
    """

    dt: float
    n_steps: int
    n_run_in: int
    n_hist: int  # lags before the first step (history prefilled with P)
    force: np.ndarray  # (n_hist + n_run_in + n_steps,)
    acc: np.ndarray  # rail displacement due to earlier forces, per history index (+ n_lags spare)
    lo: np.ndarray  # excitation positions below and above each history index's rail position
    hi: np.ndarray
    frac: np.ndarray
    weights: np.ndarray  # (positions, lags) first-order-hold weights of the moving Green's functions
    phi: np.ndarray  # wheel's discrete-time system (wheel_discrete_system)
    gamma0: np.ndarray
    gamma1: np.ndarray
    state: np.ndarray
    ramp: np.ndarray  # (n_total,) roughness fade-in factor
    start_index: np.ndarray  # (n_total,) sample index of the wheel centre in the roughness lines
    xi_w0: float = 0.0
    static_approach: float = 0.0  # the model's static approach delta(P), m (:meth:`settle`: xi_w0's part)
    bay: int | None = None  # steps per sleeper bay (steady_start.bay_steps), None if not a whole number
    steady: bool = False  # the run starts from the moving load's steady state (no fade-in; steady_start)
    phases: tuple | None = None  # steady: (lo, hi, frac) of the bay's phases, index n_hist + k for phase k

    @property
    def n_total(self) -> int:
        return self.n_run_in + self.n_steps

    @cached_property
    def track(self) -> tuple:
        return (self.force, self.lo, self.hi, self.frac, self.weights, self.acc)

    @cached_property
    def wheel(self) -> tuple:
        return (self.phi, self.gamma0, self.gamma1, self.state)

    def settle(self, static_approach: float, preload: float) -> None:
        """Put the wheel at rest: ``xi_w0`` the model's static approach delta(P) (m) above the bay-averaged static
        rail deflection under the preload (eq. 1's xi_S(P))."""
        self.static_approach = static_approach
        self.xi_w0 = static_approach + preload * float(np.mean(self.weights.sum(axis=1)))


def _fade_in(n_run_in: int, n_total: int) -> np.ndarray:
    ramp = np.ones(n_total)
    if n_run_in:
        fade = np.arange(n_run_in) / max(1, n_run_in // 2)
        ramp[:n_run_in] = np.where(fade < 1, 0.5 - 0.5 * np.cos(np.pi * np.minimum(fade, 1)), 1.0)
    return ramp


def _bay_positions(x: np.ndarray, spacing: float, n_positions: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows (``track.bay_rows``) below and above rail positions ``x`` (m) and the upper's weight: lo, hi, frac."""
    pos = np.mod(x, spacing) / spacing * n_positions
    lo = np.floor(pos).astype(np.int64) % n_positions
    return lo, (lo + 1) % n_positions, pos - np.floor(pos)


def check_step_stability(params: ModelParameters, weights: np.ndarray, wheel_system: tuple) -> float:
    """The coupled step's period-two mode (z = -1) must be damped: with the contact's compliance 1/k_H at the
    preload (k_H = 1.5 P / delta), rail and wheel's sampled compliance at the Nyquist frequency H(-1) (the weights
    at every position in the bay, alternating in sign, and the wheel's discrete system) must leave
    1/k_H + H(-1) > 0 (``tests/physics/test_stability.py``: where it is negative the implicit update diverges
    with period two steps). On the accepted tracks and speeds it holds with a margin (k_H (1/k_H + H(-1)) of
    0.34-0.85, ``validation/step_stability.py``); a track whose supports ring longer than the responses the loop
    keeps could break it, and is refused here rather than run. Returns that margin, k_H (1/k_H + H(-1))."""
    phi, gamma0, gamma1 = wheel_system
    rail = float(np.min(weights @ (-1.0) ** np.arange(weights.shape[1])))
    wheel = float(np.linalg.solve(-np.eye(len(phi)) - phi, gamma0 - gamma1)[1])
    stiffness = 1.5 * params.contact.preload / params.contact.hertz_approach()
    margin = 1.0 + stiffness * (rail + wheel)
    if not margin > 0.0:
        raise WheelrailError(
            f"on this track at {params.run.speed * 3.6:g} km/h the time stepping would be unstable (its period-two "
            f"mode undamped: margin {margin:.2f}): the track's supports ring longer than the responses the loop "
            "keeps; raise the pad or ballast damping, or the speed"
        )
    return margin


def history_arrays(
    track_roughness: TrackRoughness,
    params: ModelParameters,
    run_in_length: float,
    track_numerics: TrackNumerics | None = None,
    wheel_system: tuple | None = None,
    steady: bool = False,
) -> History:
    """Green's functions and wheel system, positions in the bay, the preload's force history (eqs. 1-2).

    ``wheel_system``: the wheel's ``(Phi, Gamma0, Gamma1)``, state 1 the contact's displacement (default the paper's
    2-DOF wheel, ``wheel_discrete_system``; ``modal_wheel.time_domain.modal_wheel_system`` gives the modal wheel's).

    The rail displacement that history causes (``acc``) is left at zero: :func:`run_history` scatters it before
    the first step (the compiled eq. 2, ``engine.kernels.scatter_history``). ``steady``:
    the run starts from the moving load's steady state on the gap of step 0 (``steady_start``), so the run-in
    keeps the roughness under step 0 as it is (no fade-in); else it is faded in from the preload at rest."""
    from wheelrail.core.engine.steady_start import bay_steps
    from wheelrail.core.track import moving_weights
    from wheelrail.core.wheel import wheel_discrete_system

    dx, dt = params.run.element_size, params.run.time_step
    # the weights alone, cached per speed and step: a cached run never reads the stationary responses
    weights = moving_weights(params.run.speed, dt, params.track, track_numerics)
    n_lags = weights.shape[1]
    phi, gamma0, gamma1 = wheel_discrete_system(params.wheel, dt) if wheel_system is None else wheel_system
    check_step_stability(params, weights, (phi, gamma0, gamma1))
    n_steps = track_roughness.n_steps
    n_run_in = int(round(run_in_length / dx))
    n_hist = n_lags
    n_total = n_run_in + n_steps
    # rail position of history index j (sleeper at x = 0 of the roughness data)
    x_hist = track_roughness.x_start + (np.arange(n_hist + n_total) - n_hist - n_run_in) * dx
    spacing = params.track.support.sleeper_spacing
    lo, hi, frac = _bay_positions(x_hist, spacing, len(weights))
    bay = bay_steps(spacing, dx)
    phases = None  # steady: one bay of phases from index n_hist on, however short the run (steady_start)
    if steady:
        phases = _bay_positions(track_roughness.x_start + (np.arange(bay) - n_run_in) * dx, spacing, len(weights))
    first = track_roughness.first
    history = History(
        dt=dt,
        n_steps=n_steps,
        n_run_in=n_run_in,
        n_hist=n_hist,
        force=np.full(n_hist + n_total, params.contact.preload),
        acc=np.zeros(n_hist + n_total + n_lags),
        lo=lo,
        hi=hi,
        frac=frac,
        weights=weights,
        phi=phi,
        gamma0=gamma0,
        gamma1=gamma1,
        state=np.zeros(len(phi)),
        ramp=np.ones(n_total) if steady else _fade_in(n_run_in, n_total),
        start_index=np.concatenate([np.full(n_run_in, first), first + np.arange(n_steps)]).astype(np.int64),
        bay=bay,
        steady=steady,
        phases=phases,
    )
    return history


def model_inputs(
    track_roughness: TrackRoughness,
    history: History,
    params: ModelParameters,
    surface: tuple[np.ndarray, np.ndarray | None] | None = None,
) -> ModelInputs:
    """What the contact model is given to prepare the run: the roughness on the model grid, its window and, at
    every step, the sample under the wheel and the run-in's fade-in. ``surface``: the lines the model is
    prepared on and the line added to its equivalent roughness, as ``engine.prepare.irregular_surface`` gives
    a run's irregularities (default: the track's lines, nothing added)."""
    dx = params.run.element_size
    lines, equivalent_offset = (track_roughness.lines, None) if surface is None else surface

    def position_of(s: int) -> float:
        return track_roughness.x_start + (s - history.n_run_in) * dx

    return ModelInputs(
        params=params,
        element_size=dx,
        lines=lines,
        centre_row=track_roughness.centre_row,
        window_y=track_roughness.window_y,
        half_x=track_roughness.half_x,
        start_index=history.start_index,
        ramp=history.ramp,
        position_of=position_of,
        equivalent_offset=equivalent_offset,
    )


def run_history(
    track_roughness: TrackRoughness,
    params: ModelParameters,
    run_in_length: float,
    steady: bool,
    contact,
    track_numerics: TrackNumerics | None = None,
    wheel_system: tuple | None = None,
    surface: tuple[np.ndarray, np.ndarray | None] | None = None,
) -> tuple[History, ModelInputs]:
    """The loop's history of a run with its contact model prepared on it, and the model's inputs.

    The arrays (:func:`history_arrays`); where the run does not start steady, the rail's response to the
    preload's history (eq. 2, ``engine.kernels.scatter_history``; a steady start fills its own at the first
    step); the model's inputs (:func:`model_inputs`) and ``contact.prepare`` on them, whose static approach
    settles the wheel (:meth:`History.settle`). ``run_in_length`` and ``steady`` are :func:`run_in`'s; ``surface``
    is :func:`model_inputs`'s."""
    from wheelrail.core.engine.kernels import scatter_history

    history = history_arrays(track_roughness, params, run_in_length, track_numerics, wheel_system, steady)
    if not steady:
        scatter_history(0, history.n_hist, history.track)
    inputs = model_inputs(track_roughness, history, params, surface)
    history.settle(contact.prepare(inputs), params.contact.preload)
    return history, inputs
