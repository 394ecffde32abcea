"""Time-domain vertical wheel/rail interaction (paper section 2, eqs. 1-14): :func:`prepare_run`, :func:`simulate`.

The wheel moves one element per step (eq. 7). Each step the contact law is solved together with the wheel (eq. 1)
and the rail (eq. 2), both written as a part known from the history plus the current force times a compliance:
implicit, one solve per step (the documentation's physics page, "How a step is solved"). The loop owns eqs. 1-2
(``loop_kernels``); a contact model (``models``) gives its law: compiled laws run ``CHUNK`` or ``CHUNK_3D``
steps per call of a compiled loop, a per-step law is called from Python. How a run is built: ``run_setup``.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from wheelrail.core import loop_kernels
from wheelrail.core.compiled import sources_stamp
from wheelrail.core.errors import WheelrailError
from wheelrail.core.limits import check_run_memory
from wheelrail.core.loop_kernels import commit_force, known_approach, run_chunk, scatter_history
from wheelrail.core.models import LAW_HALFSPACE, MODELS, ContactModel, ModelTraits
from wheelrail.core.parameters import ModelParameters, TrackNumerics
from wheelrail.core.results import HeaderView, RunHeader, RunResult, StepState

if TYPE_CHECKING:  # the roughness package is imported with the first set a run reads
    from wheelrail.core.roughness import RoughnessLike
from wheelrail.core.run_blocks import BlockSteps
from wheelrail.core.run_setup import (
    DEFAULT_RUN_IN_TIME,
    RUN_MARGIN,
    WINDOW_HALF_WIDTH,
    History,
    TrackRoughness,
    checked_inputs,
    history_arrays,
    interaction_wheel,
    model_inputs,
    resolve_surfaces,
    roughness_along_track,
    run_margin,
    starts_steady,
    static_equilibrium,
    usable_length,
    window_lines,
)
from wheelrail.core.wheel import checked_wheel_system

__all__ = [
    "DEFAULT_RUN_IN_TIME",
    "MODELS",
    "RUN_MARGIN",
    "WINDOW_HALF_WIDTH",
    "InteractionRun",
    "prepare_run",
    "run_margin",
    "simulate",
    "usable_length",
    "window_lines",
]

CHUNK = 2048  # steps per call of the compiled chunk loop (streaming and cancellation granularity)
CHUNK_3D = 256  # the same for the 3D law: 5-10 ms of steps, so a live view gets them in time
# s: a 3d run-in from the preload (an explicit one) this long or longer runs on the law tabulated
# (contact.run_in_law); its fade-in's blend then leaves at most 0.014 N (0.108 s at 100 km/h), 0.2-2.4 N after
# a run-in of 1-36 ms, which the 3D solver steps; the steady start's run-in (0.5 ms) is stepped by it too
TABULATED_RUN_IN_TIME = 0.1

# --------------------------------------------------------------------------------------------------
# The 3D law's chunk loop (the one-line laws': loop_kernels.run_chunk)
# --------------------------------------------------------------------------------------------------


@functools.cache
def _run_chunk_3d():
    """The 3D chunk loop, defined on first use: a run of a one-line model does not import the 3D law's
    compiled functions (numba's set-up of each costs a command-line run time).

    The law's names become globals of this module, not values the loop closes over: numba's cache key
    includes the closure's values, and a compiled function pickles differently in every process.
    """
    global STEP_CONVERGED, halfspace_step
    from wheelrail.core.contact import active_set, cholesky, deformed_gap, halfspace_model
    from wheelrail.core.contact.active_set import STEP_CONVERGED
    from wheelrail.core.contact.halfspace_model import halfspace_step

    return _define_run_chunk_3d(sources_stamp(halfspace_model, active_set, cholesky, deformed_gap, loop_kernels))


def _define_run_chunk_3d(stamp):
    @njit(cache=True, nogil=True)
    def run_chunk_3d(j0, j1, track, wheel, constants, law, out):
        """Advance the compiled 3D law (``contact.halfspace_model``) over history indices j0..j1-1, without
        the GIL (a live view's threads run meanwhile). ``constants`` = (preload, xi_w0, n_hist, first step of
        ``maps``, element size); ``law`` = ``ActiveSetSolver.law``; ``out`` = (xi_wheel, xi_rail,
        contact_length, contact_area per step s, and ``maps``: the float32 pressure map of steps
        first..first + len - 1).

        Returns (-1, converged) if all went well, else (j, status) of the step whose solve failed.
        """
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called
        preload, xi_w0, offset, first_map, dx = constants
        xi_wheel, xi_rail, length, area, maps = out
        n = maps.shape[1] * maps.shape[2]
        pressure = law[2][0]
        for j in range(j0, j1):
            delta_known, c, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
            s = j - offset
            status, f, on_centre, count = halfspace_step(s, delta_known, c, law)
            if status != STEP_CONVERGED:
                return j, status
            length[s] = on_centre * dx
            area[s] = count * (dx * dx)
            k = s - first_map
            if 0 <= k < maps.shape[0]:
                flat = maps[k].reshape(n)
                for i in range(n):
                    flat[i] = pressure[i] if f > 0.0 else 0.0
            xi_wheel[s], xi_rail[s] = commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0)
        return -1, STEP_CONVERGED

    return run_chunk_3d


# --------------------------------------------------------------------------------------------------
# The run
# --------------------------------------------------------------------------------------------------


class InteractionRun(BlockSteps, HeaderView):
    """One prepared run: iterate :meth:`steps` (streaming) or call :meth:`run`; then :meth:`result`.

    Built by :func:`prepare_run`, not by hand. :meth:`cancel` (from any thread) stops it between steps.

    Attributes
    ----------
    header : RunHeader
        Also through its shortcuts ``model``, ``line``, ``params``, ``roughness_name`` and ``dx`` (m).
    traits : ModelTraits
        What the model computes.
    x_start : float
        Wheel position of step 0, m.
    window_x, window_y : ndarray or None
        For a model with a pressure map: the element centres of the contact window relative to the wheel
        centre, m (columns along the rail, rows across it), the grid of every ``StepState.pressure``.

    See Also
    --------
    simulate : prepares and runs in one call.
    """

    def __init__(
        self,
        *,
        header: RunHeader,
        traits: ModelTraits,
        contact: ContactModel,
        track: TrackRoughness,
        history: History,
        keep_pressure: bool = True,
    ) -> None:
        self.header = header
        self.traits = traits
        self.contact = contact
        self.track = track
        self.loop = history
        self._cancel = threading.Event()
        self._done = 0  # steps done, run-in included
        n_total = history.n_total
        self.xi_wheel = np.zeros(n_total)
        self.xi_rail = np.zeros(n_total)
        self.contact_length = np.zeros(n_total)
        self.contact_area = np.zeros(n_total)
        self.last_pressure = None
        self.window_x = contact.window_x if traits.pressure_map else None
        self.window_y = track.window_y if traits.pressure_map else None
        self.pressure = None
        if traits.pressure_map and keep_pressure:
            self.pressure = np.zeros((history.n_steps, len(self.window_y), len(self.window_x)), dtype=np.float32)
        self._law = contact.law_inputs() if traits.compiled else None
        self._chunk = (CHUNK_3D if traits.law == LAW_HALFSPACE else CHUNK) if traits.compiled else 1
        self._maps = self._maps_first = None  # the compiled 3D law's pressure maps of the last chunk, if not kept
        self._table = None  # the 3d law's run-in law (breakpoints, T_0, T_1), built on first use
        self._segment = np.zeros(1, dtype=np.int64)  # its segment of the last run-in step
        self.steady = None  # the steady state the run starts from (steady_start.SteadyState), found on first use
        if traits.law == LAW_HALFSPACE and self.pressure is None:
            self._maps = np.zeros((CHUNK_3D, len(self.window_y), len(self.window_x)), dtype=np.float32)

    tabulated_run_in = True  # 3d: a run-in from the preload of TABULATED_RUN_IN_TIME or more on the tabulated law

    @property
    def _tabulated(self) -> bool:
        loop = self.loop
        return (
            self.tabulated_run_in
            and self.traits.law == LAW_HALFSPACE
            and loop.n_run_in * loop.dt >= TABULATED_RUN_IN_TIME
        )

    # what produced the run ------------------------------------------------------------------------------
    @property
    def params(self) -> ModelParameters:
        return self.header.params

    @property
    def dx(self) -> float:
        return self.header.element_size

    @property
    def x_start(self) -> float:
        return self.track.x_start

    @property
    def n_steps(self) -> int:
        """Number of recorded steps (the run-in not counted)."""
        return self.loop.n_steps

    def position_of(self, s: int) -> float:
        """Wheel position of a step, counting the run-in's steps.

        Parameters
        ----------
        s : int
            Step index, run-in included: ``s = n_run_in`` is recorded step 0.

        Returns
        -------
        float
            Wheel position along the track, m.
        """
        return self.x_start + (s - self.loop.n_run_in) * self.dx

    def cancel(self) -> None:
        """Ask the run to stop at the next step (thread-safe): :meth:`steps` ends, :meth:`run` returns the steps
        done so far."""
        self._cancel.set()

    @property
    def cancelled(self) -> bool:
        """Whether :meth:`cancel` was called."""
        return self._cancel.is_set()

    # stepping -------------------------------------------------------------------------------------------
    def _advance(self, s0: int, s1: int) -> None:
        """Steps s0..s1-1 (run-in included)."""
        loop = self.loop
        if self.traits.law == LAW_HALFSPACE:
            self._advance_3d(s0, s1)
            return
        if self._law is not None:
            law = self._law
            status = run_chunk(
                self.traits.law,
                loop.n_hist + s0,
                loop.n_hist + s1,
                loop.track,
                loop.wheel,
                self.params.contact.preload,
                loop.xi_w0,
                (law.roughness, law.shape, law.constants),
                (self.xi_wheel, self.xi_rail, self.contact_length, self.contact_area),
            )
            if status != -1:
                raise WheelrailError(self.contact.edge_message(status - loop.n_hist))
            return
        track, wheel, preload, xi_w0 = loop.track, loop.wheel, self.params.contact.preload, loop.xi_w0
        for s in range(s0, s1):
            j = loop.n_hist + s
            delta_known, compliance, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
            state = self.contact.solve(s, delta_known, compliance)
            self.xi_wheel[s], self.xi_rail[s] = commit_force(
                j, state.force, track, wheel, s_pred, preload, xi_w0, q, w0
            )
            self.contact_length[s] = state.contact_length
            self.contact_area[s] = state.contact_area
            if state.pressure is not None:
                if self.pressure is not None and s >= loop.n_run_in:
                    self.pressure[s - loop.n_run_in] = state.pressure
                self.last_pressure = state.pressure

    def _advance_3d(self, s0: int, s1: int) -> None:
        from wheelrail.core.contact.active_set import STEP_NEEDS_ROOM

        loop = self.loop
        if s0 < loop.n_run_in and self._tabulated:
            self._run_in_3d(s0, min(s1, loop.n_run_in))
            s0 = min(s1, loop.n_run_in)
            if s0 == s1:
                return
        maps, first = (self.pressure, loop.n_run_in) if self._maps is None else (self._maps, s0)
        outputs = (self.xi_wheel, self.xi_rail, self.contact_length, self.contact_area, maps)
        j = loop.n_hist + s0
        while True:
            j, status = _run_chunk_3d()(
                j,
                loop.n_hist + s1,
                loop.track,
                loop.wheel,
                (self.params.contact.preload, loop.xi_w0, loop.n_hist, first, self.dx),
                self._law.law,
                outputs,
            )
            if status != STEP_NEEDS_ROOM:
                break
            self._law.grow()  # the set outgrew the factor's buffer: repeat step j with a larger one
        self._maps_first = s0
        if j >= 0:
            raise WheelrailError(self.contact.failure_message(status, j - loop.n_hist))

    def _run_in_3d(self, s0: int, s1: int) -> None:
        """Run-in steps s0..s1-1 of the ``3d`` law on its tabulated law (``contact.run_in_law``); at the
        run-in's end the 3D law's warm state is put at the last approach, on the first recorded step's gap."""
        from wheelrail.core.contact.run_in_law import run_in_chunk, run_in_table, warm_start

        loop, preload = self.loop, self.params.contact.preload
        if self._table is None:  # the static approach under the preload as scale
            self._table = run_in_table(self._law, loop.n_run_in, preload, loop.static_approach)
        j0, j1, constants = loop.n_hist + s0, loop.n_hist + s1, (preload, loop.xi_w0, loop.n_hist)
        outputs = (self.xi_wheel, self.xi_rail)
        approach = run_in_chunk(
            j0, j1, loop.track, loop.wheel, constants, self._table, loop.ramp, self._segment, outputs
        )
        if s1 == loop.n_run_in:
            warm_start(self._law, loop.n_run_in, approach)

    def _start_steady(self) -> None:
        """Fill the history with the moving load's steady state on the run-in's gap (``steady_start``) before the
        first step; the ``3d`` law's warm state put at its approach."""
        from wheelrail.core.steady_start import fill_history, start_state

        loop = self.loop
        self.steady = start_state(self.traits.law, self._law, self.contact, loop, self.params.contact.preload)
        fill_history(loop, self.steady)
        if self.traits.law == LAW_HALFSPACE:
            from wheelrail.core.contact.run_in_law import warm_start

            warm_start(self._law, 0, float(self.steady.approach[0]))

    def _advance_to(self, s_end: int, progress: Callable[[int, int], None] | None = None) -> None:
        if self.loop.steady and self.steady is None and self._done == 0 and s_end > 0:
            self._start_steady()
        chunk = self._chunk
        while self._done < s_end:
            if self._cancel.is_set():
                return
            stop = min(s_end, self._done + chunk)
            if self._done < self.loop.n_run_in and self._tabulated:
                stop = min(s_end, self.loop.n_run_in)  # the tabulated run-in in one call (1-3 us a step)
            self._advance(self._done, stop)
            self._done = stop
            if progress is not None and (chunk > 1 or stop % 64 == 0 or stop == s_end):
                progress(max(0, stop - self.loop.n_run_in), self.loop.n_steps)

    def steps(self) -> Iterator[StepState]:
        """Run (run-in first, not yielded) and yield the state of every recorded step, as it is computed.

        Yields
        ------
        StepState
            One step's force, displacements, contact size and pressure map; none after :meth:`cancel`.

        Raises
        ------
        WheelrailError
            If the contact model fails (e.g. the contact leaves the 3D model's window).
        """
        for s, end in self._stepped():
            yield from self._chunk_states(s, end)

    def run(
        self,
        callback: Callable[[StepState], None] | None = None,
        progress: Callable[[int, int], None] | None = None,
    ) -> RunResult:
        """Run to the end (or until cancelled).

        Parameters
        ----------
        callback : callable, optional
            ``callback(state)`` with the :class:`StepState` of every step (streaming); a callback with a method
            ``log_block`` (``RecordingSink``) gets ``log_block(first, block)`` of :meth:`blocks` instead.
        progress : callable, optional
            ``progress(done, total)`` now and then with the number of steps done (cheap: for progress bars).

        Returns
        -------
        RunResult
            :meth:`result`: every step, or those done before :meth:`cancel`.

        Raises
        ------
        WheelrailError
            If the contact model fails (e.g. the contact leaves the 3D model's window).
        """
        if callback is None:
            self._advance_to(self.loop.n_total, progress)
        elif hasattr(callback, "log_block"):  # a recorder of arrays: no StepState a step
            self._log_blocks(callback.log_block, progress)
        else:
            for state in self.steps():
                callback(state)
                if progress is not None and (state.step % 256 == 0 or state.step == self.loop.n_steps - 1):
                    progress(state.step + 1, self.loop.n_steps)
        return self.result()

    def result(self) -> RunResult:
        """The arrays of the steps done so far.

        Returns
        -------
        RunResult
            All recorded steps after a complete run; fewer after :meth:`cancel` (or before :meth:`run`).
        """
        start = self.loop.n_run_in
        done = max(0, self._done - start)
        return self._steps_result(start, start + done, None if self.pressure is None else self.pressure[:done])


def prepare_run(
    roughness: RoughnessLike,
    *,
    wheel_roughness: RoughnessLike | None = None,
    model: str = "hertz",
    line: int = 0,
    params: ModelParameters | None = None,
    length: float | None = None,
    run_in_length: float | None = None,
    keep_pressure: bool = True,
    track_numerics: TrackNumerics | None = None,
    wheel_system: tuple | None = None,
) -> InteractionRun:
    """Set up a wheel/rail interaction run.

    Parameters
    ----------
    roughness : RoughnessSet, str or path
        Roughness as a set of lines (a bundled set name, a CSV/NPZ path, or a ``RoughnessSet``): a rail set
        or a wheel set, the other surface smooth (paper 3.3), or the rail set when ``wheel_roughness`` is
        given. Heights are taken positive where the surface stands out, so for either kind r = height.
    wheel_roughness : RoughnessSet, str or path, optional
        A wheel set on the same wheel: the combined roughness r = r_rail + r_wheel (paper eq. 3's
        r = r_W - r_R with z downwards), paired by lateral position: the wheel set interpolated across onto
        the rail's lines (refused where it has no data, see ``run_setup.run_lines``); its lines repeat with
        its circumference, which must be within 1 % of 2 pi R of the rolling radius R
        (``accepted.check_wheel_circumference``). ``roughness`` must then be a rail set and this a wheel set
        (else one WheelrailError).
    model : str
        A registered contact model (``wheelrail.core.models.model_names()``).
    line : int
        Roughness line -M..M (of the rail set when a wheel set is added); for a model with a lateral window
        the line it is centred on.
    params : ModelParameters, optional
        Default: the paper's values (65 kN, 100 km/h, 1 mm elements).
    length : float, optional
        Run length, m. Default: ``run_setup.usable_length`` (the rail data less the margins, or one wheel
        circumference: wheel data repeats around it).
    run_in_length : float, optional
        Run-in before step 0 on the roughness under step 0, m (discarded). Default: the run starts from the
        moving load's periodic steady state (``steady_start``: no start-up transient) and runs in for
        ``DEFAULT_RUN_IN_TIME`` (0.5 ms) at its speed. A run-in given starts from the preload at rest (history
        filled with P, the roughness faded in over its first half), as every run did before; so does the default
        where the sleeper bay is no whole number of elements, with 0.3 s (``run_setup.default_run_in_length``).
    keep_pressure : bool
        Keep every pressure map in the result (steps x ny x nx float32), for models that have them.
    track_numerics : TrackNumerics, optional
        Numerics of the track's Green's functions.
    wheel_system : WheelProfile, OutlineProfile or tuple, optional
        Default the paper's 2-DOF wheel; a modal wheel's cross-section, or a ``(Phi, Gamma0, Gamma1)``
        (``modal_wheel.time_domain.modal_wheel_system``); the header says which (``run_setup.interaction_wheel``).

    Returns
    -------
    InteractionRun
        The run; no step computed yet (a steady start fills its history at the first step).

    Raises
    ------
    WheelrailError
        For an unknown model, a line outside the set, parameters outside the accepted ranges, a run that would
        not fit in memory or whose coupled step would be unstable, or a rail and wheel set that do not pair.

    See Also
    --------
    simulate : prepares and runs in one call.
    wheelrail.core.models.model_names : the registered contact models.
    wheelrail.core.roughness.load_roughness : reads a roughness set.

    References
    ----------
    .. [1] A. Pieringer, W. Kropp, D.J. Thompson, "Investigation of the dynamic contact filter effect in vertical
       wheel/rail interaction using a 2D and a 3D non-Hertzian contact model", Wear 271 (2011) 328-338.

    Examples
    --------
    A run prepared but not started; its steps are computed as they are asked for:

    >>> from wheelrail.core.interaction import prepare_run
    >>> run = prepare_run("corrugated-rail", model="2d", line=0, length=0.2)
    >>> run.n_steps
    200
    >>> forces = [state.force for state in run.steps()]   # one StepState per step, N
    >>> len(forces), min(forces) > 0.0
    (200, True)
    """
    if track_numerics is not None and not isinstance(track_numerics, TrackNumerics):
        raise WheelrailError(
            f"prepare_run: track_numerics must be TrackNumerics or None, got {type(track_numerics).__name__}"
        )
    if wheel_system is not None:  # the modal wheel's modules (and scipy's) load only for a run that uses them
        from wheelrail.core.modal_wheel.profile import OutlineProfile, WheelProfile

        if not isinstance(wheel_system, WheelProfile | OutlineProfile):
            wheel_system = checked_wheel_system(wheel_system)  # a caller's (Phi, Gamma0, Gamma1)
    steady = run_in_length is None  # the default run-in follows the steady start (where the bay allows it)
    entry, params, line, run_in_length = checked_inputs(model, line, params, run_in_length)
    steady = steady and starts_steady(params)
    rough, name, wheel, wheel_name = resolve_surfaces(roughness, wheel_roughness, params)
    dx = params.run.element_size
    check_run_memory(
        entry, params, usable_length(rough, dx) if length is None else length, run_in_length, keep_pressure
    )
    track = roughness_along_track(rough, entry.traits, line, params, length, wheel=wheel)
    wheel_system, wheel_model, wheel_profile = interaction_wheel(wheel_system, params)
    history = history_arrays(track, params, run_in_length, track_numerics, wheel_system, steady)
    if not steady:  # the rail's response to the preload's history (eq. 2); a steady start fills its own
        scatter_history(0, history.n_hist, history.track)
    header = RunHeader(
        model=entry.name,
        line=line,
        roughness_name=name,
        params=params,
        run_in_length=history.n_run_in * dx,
        wheel_roughness_name=wheel_name,
        wheel_model=wheel_model,
        wheel_profile=wheel_profile,
    )
    contact = entry.create()
    static_approach = contact.prepare(model_inputs(track, history, params))
    history.static_approach = static_approach
    history.xi_w0 = static_equilibrium(static_approach, params.contact.preload, history.weights)
    return InteractionRun(
        header=header, traits=entry.traits, contact=contact, track=track, history=history, keep_pressure=keep_pressure
    )


def simulate(
    roughness: RoughnessLike,
    *,
    model: str = "hertz",
    line: int = 0,
    params: ModelParameters | None = None,
    length: float | None = None,
    callback: Callable[[StepState], None] | None = None,
    cancel: threading.Event | None = None,
    progress: Callable[[int, int], None] | None = None,
    **options,
) -> RunResult:
    """Run the wheel/rail interaction and return the whole-run result.

    Parameters
    ----------
    roughness, model, line, params, length
        As for :func:`prepare_run`.
    callback : callable, optional
        ``callback(state)`` with the :class:`StepState` of every step.
    cancel : threading.Event, optional
        Setting it stops the run between steps; the steps done so far are returned.
    progress : callable, optional
        ``progress(done, total)`` now and then.
    **options
        The other keywords of :func:`prepare_run`.

    Returns
    -------
    RunResult
        Force, displacements, roughness, contact size (and pressure maps) per step, SI units.

    Raises
    ------
    WheelrailError
        For any input :func:`prepare_run` refuses, or if the contact model fails during the run.

    See Also
    --------
    prepare_run : the same run, stepped on demand.
    wheelrail.core.spectra.force_spectrum : the force's third-octave spectrum.

    Examples
    --------
    Half a metre of the bundled corrugated rail under the Hertz spring, at the paper's 100 km/h and 65 kN:

    >>> from wheelrail.core.interaction import simulate
    >>> result = simulate("corrugated-rail", model="hertz", line=0, length=0.5)
    >>> result.force.size, result.time_step          # one step per 1 mm element: dt = 1 mm / (100 km/h), s
    (500, 3.6e-05)
    >>> round(float(result.force.mean()) / 1e3, 1)     # kN: the preload and the roughness's dynamic force
    65.2
    >>> result.loss_of_contact_steps, result.run_in_length   # the run-in after the steady start: 0.5 ms, m
    (0, 0.014)
    """
    run = prepare_run(roughness, model=model, line=line, params=params, length=length, **options)
    if cancel is not None:
        run._cancel = cancel
    return run.run(callback, progress)
