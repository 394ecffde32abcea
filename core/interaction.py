"""Time-domain vertical wheel/rail interaction (paper section 2, eqs. 1-14) with five contact variants.

The wheel moves along the rail one element per step (x = v t, eq. 7; dt = Delta x / v). Each step:

* the **wheel** (eq. 1) is advanced with its exact discrete-time form for a force linear between steps
  (``wheel_discrete_system``), equivalent to convolving with g_W but without truncating its slowly
  decaying suspension mode; the wheel responds to the dynamic force F - P around its static position;
* the **rail** displacement at the contact point (eq. 2) is the convolution of the force history with the
  moving Green's functions, using the first-order-hold weights w_m^{x0} of
  :meth:`MovingGreenFunctions.weights` at each past force's excitation position x0 (interpolated between
  the stored positions of the bay);
* both are split into a part known from the history and a part proportional to the current force:
  ``delta = xi_W - xi_R = delta_known - c F`` with the instantaneous compliance c = Gamma1 + w_0 > 0; the
  contact model solves its own nonlinear law together with this relation, so the current force is
  consistent with the current displacements (implicit, one solve per step).

Contact variants (``MODELS``): ``3d`` (elastic half-space on a window of 1 mm elements over the roughness
lines, eqs. 8-11, warm-started active set), ``2d`` (Winkler bedding on one line, eqs. 3-6), ``hertz``
(eqs. 12-14 with r_eq = r), ``hertz-winkler`` (r_eq from the Ford & Thompson bedding pre-filter) and
``hertz-average`` (r_eq = mean of r over the nominal contact length 2a). Each variant is a class below
with ``prepare`` and ``advance``: adding a model means adding one class to ``VARIANTS``.

Start-up: before step 0 the history is filled with the preload P, the wheel sits at the static approach of
the chosen contact model plus the bay-averaged static rail deflection, and a run-in on smooth surfaces
(``run_in_length``, default 1 m) lets the sleeper-passing response settle; the roughness is faded in
over the run-in with a raised cosine and the run-in is discarded.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np
from numba import njit

from wheelrail.core.contact.winkler import _winkler_force
from wheelrail.core.errors import WheelrailError
from wheelrail.core.limits import check_run_memory
from wheelrail.core.parameters import ModelParameters, TrackNumerics
from wheelrail.core.results import MODELS, RunHeader, RunResult, StepState
from wheelrail.core.track import moving_green_functions
from wheelrail.core.wheel import wheel_discrete_system

__all__ = ["MODELS", "InteractionRun", "prepare_run", "run_margin", "simulate", "usable_length"]

WINDOW_HALF_WIDTH = 0.012  # m: half side of the 3D window and of the 2D bedding (2.2 a at 65 kN)
DEFAULT_RUN_IN = 1.0  # m of smooth run-in before step 0 (discarded)
RUN_MARGIN = 0.020  # m of roughness kept before the first and after the last wheel position
CHUNK = 2048  # steps per compiled chunk of the 1D models (streaming and cancellation granularity)

# --------------------------------------------------------------------------------------------------
# Compiled pieces shared by all variants
# --------------------------------------------------------------------------------------------------


@njit(cache=True)
def _history(j, force, lo, hi, frac, weights, acc, phi, gamma0, gamma1, state, preload, xi_w0):
    """Known part of the approach at history index j: returns (delta_known, compliance, q_rail, w0, s_pred).

    ``acc[j]`` already holds the rail displacement due to all earlier forces (see ``_scatter``).
    """
    q = acc[j]
    w0 = (1.0 - frac[j]) * weights[lo[j], 0] + frac[j] * weights[hi[j], 0]
    s_pred = np.empty(4)
    df = force[j - 1] - preload
    for a in range(4):
        v = gamma0[a] * df
        for b in range(4):
            v += phi[a, b] * state[b]
        s_pred[a] = v
    delta_known = xi_w0 - s_pred[1] + gamma1[1] * preload - q
    return delta_known, gamma1[1] + w0, q, w0, s_pred


@njit(cache=True, fastmath=True)
def _scatter(j, f, lo, hi, frac, weights, acc):
    """Add the rail displacement that force f at index j causes at the later steps (eq. 2, scattered
    forward: contiguous memory, so the n_lags multiply-adds vectorise)."""
    n_lags = weights.shape[1]
    a = (1.0 - frac[j]) * f
    b = frac[j] * f
    row_lo = weights[lo[j]]
    row_hi = weights[hi[j]]
    for m in range(1, n_lags):
        acc[j + m] += a * row_lo[m] + b * row_hi[m]


@njit(cache=True)
def _scatter_range(j0, j1, force, lo, hi, frac, weights, acc):
    for j in range(j0, j1):
        _scatter(j, force[j], lo, hi, frac, weights, acc)


@njit(cache=True)
def _hertz_solve(a, c, constant):
    """Solve u + c C_H u^1.5 = a for the compression u >= 0 (a <= 0: no contact). Newton from u = a,
    monotone for this increasing convex function."""
    if a <= 0.0:
        return 0.0
    u = a
    for _ in range(60):
        su = math.sqrt(u)
        phi = u + c * constant * u * su - a
        dphi = 1.0 + 1.5 * c * constant * su
        step = phi / dphi
        u -= step
        if u <= 0.0:
            u = 1e-300
        if abs(step) <= 1e-15 * a + 1e-22:
            break
    return u


@njit(cache=True)
def _winkler_solve(a, c, window, profile, k_dx):
    """Solve delta + c F(delta) = a for the bedding (F piecewise linear, convex): Newton from delta = a.

    F, dF/d delta and the edge flag are those of ``contact.winkler._winkler_force`` (eqs. 3-5).
    Returns (delta, force, n_compressed, edge).
    """
    delta = a
    force, stiffness, count, edge = _winkler_force(delta, window, profile, k_dx)
    for _ in range(200):
        phi = delta + c * force - a
        if phi <= 1e-18 * (abs(a) + 1e-9) and phi >= -1e-18:
            break
        delta -= phi / (1.0 + c * stiffness)
        force, stiffness, count, edge = _winkler_force(delta, window, profile, k_dx)
    return delta, force, count, edge


@njit(cache=True)
def _run_1d(law, j0, j1, force, lo, hi, frac, weights, acc, phi, gamma0, gamma1, state, preload, xi_w0,
            r_eq, r_window, profile, constant, k_dx, radius, out_xiw, out_xir, out_length):
    """Advance a one-line model over history indices j0..j1-1 (law 0: Hertz on r_eq; 1: Winkler).

    Returns -1 if all went well, else the index j at which the 2D contact reached its window's edge.
    """
    offset = force.shape[0] - r_eq.shape[0]
    for j in range(j0, j1):
        delta_known, c, q, w0, s_pred = _history(j, force, lo, hi, frac, weights, acc, phi, gamma0, gamma1,
                                                 state, preload, xi_w0)
        s = j - offset
        if law == 0:
            u = _hertz_solve(delta_known + r_eq[s], c, constant)
            f = constant * u * math.sqrt(u)
            out_length[s] = 2.0 * math.sqrt(radius * u)
        else:
            delta, f, count, edge = _winkler_solve(delta_known, c, r_window[s], profile, k_dx)
            if edge:
                return j
            out_length[s] = count
        force[j] = f
        _scatter(j, f, lo, hi, frac, weights, acc)
        for i in range(4):
            state[i] = s_pred[i] + gamma1[i] * (f - preload)
        out_xiw[s] = xi_w0 - state[1]
        out_xir[s] = q + w0 * f
    return -1


@njit(cache=True)
def _commit(j, f, force, lo, hi, frac, weights, acc, gamma1, s_pred, state, preload):
    force[j] = f
    _scatter(j, f, lo, hi, frac, weights, acc)
    for i in range(4):
        state[i] = s_pred[i] + gamma1[i] * (f - preload)


# --------------------------------------------------------------------------------------------------
# The run
# --------------------------------------------------------------------------------------------------


@dataclass
class _Loop:
    """Everything the loop needs, resolved and in SI (built by ``prepare_run``)."""

    dt: float
    n_steps: int
    n_run_in: int
    n_hist: int  # lags before the first step (history prefilled with P)
    force: np.ndarray  # (n_hist + n_run_in + n_steps,)
    acc: np.ndarray  # rail displacement due to earlier forces, per history index (+ n_lags spare)
    lo: np.ndarray
    hi: np.ndarray
    frac: np.ndarray
    weights: np.ndarray
    phi: np.ndarray
    gamma0: np.ndarray
    gamma1: np.ndarray
    state: np.ndarray
    xi_w0: float
    ramp: np.ndarray  # (n_run_in + n_steps,) roughness fade-in factor
    start_index: np.ndarray  # (n_run_in + n_steps,) sample index of the wheel centre in the lines array

    @property
    def n_total(self) -> int:
        return self.n_run_in + self.n_steps


class ContactVariant:
    """A contact model inside the loop. Subclasses set ``name`` and implement the two methods."""

    name = ""

    def prepare(self, run: InteractionRun) -> float:
        """Precompute inputs; return the static approach delta(P) of this model on smooth surfaces, m."""
        raise NotImplementedError

    def advance(self, run: InteractionRun, s0: int, s1: int) -> None:
        """Step s0..s1-1 (run-in included; s = 0 is the first run-in step), filling ``run``'s arrays."""
        raise NotImplementedError


class _HertzVariant(ContactVariant):
    """Hertz spring (eqs. 12-14) on an equivalent roughness r_eq of the line.

    The pre-filters run on the line along the track (wheel data already repeated around the
    circumference); the run's margins (>= 16 mm) exceed their half-lengths (3a = 16.4 mm for the bedding
    is covered by the 20 mm margin of ``hertz-winkler``; a + 1 mm for the average), so their default end
    treatment never reaches a step of the run.
    """

    name = "hertz"

    def equivalent_roughness(self, run: InteractionRun, line: np.ndarray) -> np.ndarray:
        return line

    def prepare(self, run):
        c = run.params.contact
        self.constant = c.hertz_constant
        line = run.lines[run.centre_row]
        req = self.equivalent_roughness(run, line)
        run.equivalent_line = req
        self.r_eq = np.ascontiguousarray(req[run.loop.start_index] * run.loop.ramp)
        return c.hertz_approach()

    def advance(self, run, s0, s1):
        loop = run.loop
        r_eq = self.r_eq
        status = _run_1d(0, loop.n_hist + s0, loop.n_hist + s1, loop.force, loop.lo, loop.hi, loop.frac,
                         loop.weights, loop.acc, loop.phi, loop.gamma0, loop.gamma1, loop.state,
                         run.params.contact.preload, loop.xi_w0, r_eq, _EMPTY2, _EMPTY1, self.constant,
                         0.0, run.params.contact.radius, run.xi_wheel, run.xi_rail, run.contact_length)
        assert status == -1
        length = run.contact_length[s0:s1]
        run.contact_area[s0:s1] = math.pi * (length / 2) ** 2


_EMPTY1 = np.zeros(1)
_EMPTY2 = np.zeros((1, 1))


class _HertzWinkler(_HertzVariant):
    name = "hertz-winkler"

    def equivalent_roughness(self, run, line):
        from wheelrail.core.contact import winkler_equivalent_roughness

        c = run.params.contact
        return winkler_equivalent_roughness(line, run.dx, preload=c.preload, radius=c.radius,
                                            youngs_modulus=c.youngs_modulus, poisson_ratio=c.poisson_ratio)


class _HertzAverage(_HertzVariant):
    name = "hertz-average"

    def equivalent_roughness(self, run, line):
        from wheelrail.core.contact import average_roughness

        c = run.params.contact
        return average_roughness(line, run.dx, contact_length=2 * c.hertz_radius())


class _Winkler2D(ContactVariant):
    name = "2d"

    def prepare(self, run):
        from wheelrail.core.contact import bedding_stiffness, wheel_profile
        from wheelrail.core.contact.prefilter import _bedding_approach

        c = run.params.contact
        self.half = run.half_x
        self.profile = wheel_profile(2 * self.half + 1, run.dx, c.radius)
        self.k_dx = bedding_stiffness(c.youngs_modulus, c.poisson_ratio) * run.dx
        line = run.lines[run.centre_row]
        run.equivalent_line = line
        offsets = np.arange(-self.half, self.half + 1)
        loop = run.loop
        self.r_window = np.ascontiguousarray(line[loop.start_index[:, None] + offsets[None, :]] * loop.ramp[:, None])
        self.no_r_eq = np.zeros(loop.n_total)
        delta, _ = _bedding_approach(-self.profile, self.k_dx, c.preload)
        return float(delta)

    def advance(self, run, s0, s1):
        loop = run.loop
        status = _run_1d(1, loop.n_hist + s0, loop.n_hist + s1, loop.force, loop.lo, loop.hi, loop.frac,
                         loop.weights, loop.acc, loop.phi, loop.gamma0, loop.gamma1, loop.state,
                         run.params.contact.preload, loop.xi_w0, self.no_r_eq, self.r_window,
                         self.profile, 0.0, self.k_dx, run.params.contact.radius, run.xi_wheel,
                         run.xi_rail, run.contact_length)
        if status != -1:
            s = status - loop.n_hist
            raise WheelrailError(
                f"2d: the contact reaches the end of the {2 * self.half + 1}-element bedding at "
                f"x = {run.position_of(s):.4f} m (roughness too large for the "
                f"+-{self.half * run.dx * 1e3:.0f} mm window)"
            )
        run.contact_length[s0:s1] *= run.dx
        run.contact_area[s0:s1] = np.nan


class _HalfSpace3D(ContactVariant):
    name = "3d"

    def prepare(self, run):
        from wheelrail.core.contact import solve_normal_contact

        c = run.params.contact
        hx = run.half_x
        x = np.arange(-hx, hx + 1) * run.dx
        y = run.window_y
        self.base_gap = (x[None, :] ** 2 + y[:, None] ** 2) / (2 * c.radius)
        self.x = x
        smooth = solve_normal_contact(self.base_gap, run.dx, load=c.preload, youngs_modulus=c.youngs_modulus,
                                      poisson_ratio=c.poisson_ratio)
        self.warm = smooth.contact
        run.equivalent_line = run.lines[run.centre_row]
        run.window_x = x
        return float(smooth.approach)

    def advance(self, run, s0, s1):
        from wheelrail.core.contact import solve_coupled_contact

        loop = run.loop
        c = run.params.contact
        hx = run.half_x
        area = run.dx * run.dx
        preload = c.preload
        centre = run.centre_window_row
        for s in range(s0, s1):
            j = loop.n_hist + s
            delta_known, comp, q, w0, s_pred = _history(j, loop.force, loop.lo, loop.hi, loop.frac, loop.weights,
                                                        loop.acc, loop.phi, loop.gamma0, loop.gamma1, loop.state,
                                                        preload, loop.xi_w0)
            i = loop.start_index[s]
            gap = self.base_gap - loop.ramp[s] * run.lines[:, i - hx:i + hx + 1]
            result = solve_coupled_contact(gap, run.dx, approach_known=delta_known, compliance=comp,
                                           initial=self.warm, youngs_modulus=c.youngs_modulus,
                                           poisson_ratio=c.poisson_ratio, raise_on_failure=False)
            if result.at_edge:
                raise WheelrailError(
                    f"3d: the contact reaches the edge of the {gap.shape[0]} x {gap.shape[1]} window at "
                    f"x = {run.position_of(s):.4f} m; the roughness or load is too large for the window"
                )
            if not result.converged:
                raise WheelrailError(f"3d: the contact solve did not converge at x = {run.position_of(s):.4f} m")
            f = float(result.force)
            _commit(j, f, loop.force, loop.lo, loop.hi, loop.frac, loop.weights, loop.acc, loop.gamma1, s_pred,
                    loop.state, preload)
            run.xi_wheel[s] = loop.xi_w0 - loop.state[1]
            run.xi_rail[s] = q + w0 * f
            mask = result.contact
            run.contact_area[s] = mask.sum() * area
            run.contact_length[s] = mask[centre].sum() * run.dx
            if run.pressure is not None and s >= loop.n_run_in:
                run.pressure[s - loop.n_run_in] = result.pressure
            run.last_pressure = result.pressure
            # warm start from the previous result itself (its contact set and Cholesky factor): the window
            # moves with the wheel, so the patch stays centred; this took 1.8 instead of 5 active-set
            # iterations per step compared with shifting the contact set by one element
            if result.force > 0:
                self.warm = result


VARIANTS: dict[str, type[ContactVariant]] = {
    cls.name: cls for cls in (_HalfSpace3D, _Winkler2D, _HertzVariant, _HertzWinkler, _HertzAverage)
}


class InteractionRun:
    """One prepared run: iterate :meth:`steps` (streaming) or call :meth:`run`; then :meth:`result`.

    Create it with :func:`prepare_run`. :meth:`cancel` (from any thread) stops it between steps.

    Public attributes (read-only by convention): ``model``, ``line``, ``params`` (ModelParameters),
    ``roughness_name``, ``dx`` (m), ``x_start`` (m, wheel position of step 0), ``n_steps``, and for the 3D
    model ``window_x`` / ``window_y``: the element centres of the contact window relative to the wheel
    centre, m (columns along the rail, rows across it), the grid of every ``StepState.pressure``.
    """

    def __init__(self) -> None:
        self._cancel = threading.Event()
        self._done = 0  # steps done, run-in included
        self.last_pressure = None

    # set by prepare_run -----------------------------------------------------------------------------
    params: ModelParameters
    model: str
    line: int
    roughness_name: str
    dx: float
    lines: np.ndarray  # (rows, samples) roughness on the model grid along the track
    centre_row: int
    half_x: int
    x_start: float
    loop: _Loop
    variant: ContactVariant
    window_x: np.ndarray | None  # 3D: element centres along the rail relative to the wheel, m
    window_y: np.ndarray  # 3D: element centres across the rail relative to the chosen line, m

    def position_of(self, s: int) -> float:
        """Wheel position of step s (run-in included: s = n_run_in is step 0), m."""
        return self.x_start + (s - self.loop.n_run_in) * self.dx

    def cancel(self) -> None:
        """Ask the run to stop at the next step (thread-safe)."""
        self._cancel.set()

    @property
    def cancelled(self) -> bool:
        return self._cancel.is_set()

    @property
    def n_steps(self) -> int:
        return self.loop.n_steps

    def _advance_to(self, s_end: int, progress: Callable[[int, int], None] | None = None) -> None:
        chunk = CHUNK if self.model != "3d" else 1
        while self._done < s_end:
            if self._cancel.is_set():
                return
            stop = min(s_end, self._done + chunk)
            self.variant.advance(self, self._done, stop)
            self._done = stop
            if progress is not None and (chunk > 1 or stop % 64 == 0 or stop == s_end):
                progress(max(0, stop - self.loop.n_run_in), self.loop.n_steps)

    def _state(self, s: int) -> StepState:
        loop = self.loop
        k = s - loop.n_run_in
        return StepState(
            step=k,
            time=k * loop.dt,
            position=self.position_of(s),
            force=float(loop.force[loop.n_hist + s]),
            xi_wheel=float(self.xi_wheel[s]),
            xi_rail=float(self.xi_rail[s]),
            roughness=float(self.lines[self.centre_row][loop.start_index[s]]),
            contact_length=float(self.contact_length[s]),
            contact_area=float(self.contact_area[s]),
            pressure=None if self.model != "3d" else (
                self.pressure[k] if self.pressure is not None else self.last_pressure),
        )

    def steps(self) -> Iterator[StepState]:
        """Run (run-in first, not yielded) and yield the :class:`StepState` of every step.

        Stops early, without error, if :meth:`cancel` was called.
        """
        loop = self.loop
        self._advance_to(loop.n_run_in)
        s = loop.n_run_in
        while s < loop.n_total and not self._cancel.is_set():
            stop = min(loop.n_total, s + (CHUNK if self.model != "3d" else 1))
            self._advance_to(stop)
            for t in range(s, min(stop, self._done)):
                yield self._state(t)
            s = stop

    def run(
        self,
        callback: Callable[[StepState], None] | None = None,
        progress: Callable[[int, int], None] | None = None,
    ) -> RunResult:
        """Run to the end (or until cancelled); return :meth:`result`.

        ``callback(state)`` is called for every step (streaming); ``progress(done, total)`` is called now
        and then with the number of steps done (cheap: use it for progress bars).
        """
        if callback is None:
            self._advance_to(self.loop.n_total, progress)
        else:
            for state in self.steps():
                callback(state)
                if progress is not None and (state.step % 256 == 0 or state.step == self.loop.n_steps - 1):
                    progress(state.step + 1, self.loop.n_steps)
        return self.result()

    def result(self) -> RunResult:
        """Arrays of the steps done so far (all of them after a complete run)."""
        loop = self.loop
        done = max(0, self._done - loop.n_run_in)
        sl = slice(loop.n_run_in, loop.n_run_in + done)
        k = np.arange(done)
        force = loop.force[loop.n_hist + loop.n_run_in: loop.n_hist + loop.n_run_in + done].copy()
        idx = loop.start_index[sl]
        return RunResult(
            header=self.header,
            time=k * loop.dt,
            x=self.x_start + k * self.dx,
            force=force,
            xi_wheel=self.xi_wheel[sl].copy(),
            xi_rail=self.xi_rail[sl].copy(),
            roughness=self.lines[self.centre_row][idx].copy(),
            contact_length=self.contact_length[sl].copy(),
            contact_area=self.contact_area[sl].copy(),
            equivalent_roughness=self.equivalent_line[idx].copy(),
            pressure=None if self.pressure is None else self.pressure[:done],
            window_x=getattr(self.variant, "x", None),
            window_y=self.window_y if self.model == "3d" else None,
            loss_of_contact_steps=int(np.count_nonzero(force <= 0.0)),
        )

    @property
    def header(self) -> RunHeader:
        """What produced this run (model, line, roughness, parameters, run-in)."""
        return RunHeader(model=self.model, line=self.line, roughness_name=self.roughness_name, params=self.params,
                         run_in_length=self.loop.n_run_in * self.dx)


def run_margin(element_size: float) -> float:
    """Roughness kept before the first and after the last wheel position, m.

    One margin for every model (the 3D window's half-width plus 4 elements, the bedding pre-filter's
    3a = 16.4 mm within ``RUN_MARGIN``), so that runs of different models on the same data start at the same
    position and compare sample by sample.
    """
    half_x = int(round(WINDOW_HALF_WIDTH / element_size))
    return max(half_x + 4, int(math.ceil(RUN_MARGIN / element_size))) * element_size


def usable_length(roughness, element_size: float) -> float:
    """Longest run on a roughness set, m: the rail data less a ``run_margin`` at each end (every model can
    run it), or one circumference for wheel data (it repeats). The default run length of :func:`prepare_run`
    and of the studies.

    Raises WheelrailError when rail data are too short for one element beyond the margins.
    """
    if roughness.periodic:
        return float(roughness.length)
    margin = run_margin(element_size)
    span = (roughness.n_samples - 1) * roughness.dx
    n_steps = math.floor((span - 2 * margin) / element_size + 1e-9)
    if n_steps < 1:
        raise WheelrailError(f"rail data of {span:g} m are too short for a run: the model keeps "
                             f"{margin * 1e3:g} mm of roughness before and after the wheel")
    return n_steps * element_size


def _resolve_roughness(roughness):
    from wheelrail.core.roughness import RoughnessSet, load_roughness

    if isinstance(roughness, RoughnessSet):
        return roughness, roughness.description.splitlines()[0] if roughness.description else "roughness"
    if isinstance(roughness, str) or hasattr(roughness, "__fspath__"):
        return load_roughness(roughness), str(roughness)
    raise WheelrailError(f"roughness must be a RoughnessSet, a bundled set name or a file path, got {roughness!r}")


def prepare_run(
    roughness,
    *,
    model: str = "hertz",
    line: int = 0,
    params: ModelParameters | None = None,
    length: float | None = None,
    run_in_length: float = DEFAULT_RUN_IN,
    keep_pressure: bool = True,
    track_numerics: TrackNumerics | None = None,
) -> InteractionRun:
    """Set up a wheel/rail interaction run.

    Parameters
    ----------
    roughness : RoughnessSet, str or path
        Combined roughness r = r_W - r_R as a set of lines (a bundled set name, a CSV/NPZ path, or a
        ``RoughnessSet``); one set is used at a time, the other surface being smooth (paper 3.3). Heights
        are taken positive where the surface stands out, so for either kind r = height.
    model : str
        One of ``MODELS``.
    line : int
        Roughness line -M..M for the one-line models; for ``3d`` the line the window is centred on.
    params : ModelParameters, optional
        Default: the paper's values (65 kN, 100 km/h, 1 mm elements).
    length : float, optional
        Run length, m. Default: the roughness length less the window margins (rail), or one wheel
        circumference (wheel data repeats around it).
    run_in_length : float
        Smooth run-in before step 0, m (discarded); default 1 m.
    keep_pressure : bool
        Keep every 3D pressure map in the result (steps x ny x nx float32).
    track_numerics : TrackNumerics, optional
        Numerics of the track's Green's functions.

    Returns
    -------
    InteractionRun
    """
    from wheelrail.core.roughness import lines_along_track, to_model_grid

    if model not in MODELS:
        raise WheelrailError(f"unknown contact model {model!r}; choose one of {', '.join(MODELS)}")
    params = ModelParameters() if params is None else params
    if not isinstance(params, ModelParameters):
        raise WheelrailError("params must be a wheelrail.core.parameters.ModelParameters")
    if isinstance(line, bool) or not isinstance(line, int | np.integer):
        raise WheelrailError(f"line must be an integer line number, got {line!r}")
    if not (isinstance(run_in_length, int | float) and math.isfinite(run_in_length) and run_in_length >= 0):
        raise WheelrailError(f"run_in_length must be zero or positive (m), got {run_in_length!r}")
    rough, name = _resolve_roughness(roughness)
    numbers = list(rough.line_numbers)
    if int(line) not in numbers:
        raise WheelrailError(
            f"line {line} is not in the roughness set (lines {min(numbers)}..{max(numbers)})"
        )
    dx = params.run.element_size
    dt = params.run.time_step
    run = InteractionRun()
    run.params, run.model, run.line, run.roughness_name = params, model, int(line), name
    run.dx = dx
    half_x = int(round(WINDOW_HALF_WIDTH / dx))
    run.half_x = half_x
    margin = run_margin(dx)

    # roughness on the model grid along the track ------------------------------------------------------
    y_line = float(rough.y[rough.row_of_line(int(line))])
    if model == "3d":
        grid = to_model_grid(rough, dx, dx)
        keep = np.abs(grid.y - y_line) <= WINDOW_HALF_WIDTH + 1e-9
        rows = np.nonzero(keep)[0]
        if rows.size < 3:
            raise WheelrailError("3d: the roughness set is too narrow for the contact window")
        run.window_y = grid.y[rows] - y_line
        wanted = [grid.line_of_row(int(r)) for r in rows]
        run.centre_window_row = int(np.argmin(np.abs(run.window_y)))
        if abs(run.window_y[run.centre_window_row]) > 1e-9:
            raise WheelrailError(f"3d: line {line} does not fall on the 1 mm lateral grid")
    else:
        grid = to_model_grid(rough, dx)
        wanted = [int(line)]
        run.window_y = np.zeros(1)
    if length is None:
        length = usable_length(rough, dx)
    if not (isinstance(length, int | float) and math.isfinite(length) and length > 0):
        raise WheelrailError(f"run length must be positive (m), got {length!r}")
    check_run_memory(model, n_elements=(length + 2 * margin + run_in_length) / dx, n_steps=length / dx,
                     n_lines=len(wanted), window_columns=2 * half_x + 1, keep_pressure=keep_pressure)
    n_steps = int(round(length / dx))
    if n_steps < 1:
        raise WheelrailError(f"run length {length} m is shorter than one element ({dx} m)")
    total_length = margin + n_steps * dx + margin
    if not grid.periodic and total_length > grid.x[-1] + 1e-12:
        raise WheelrailError(
            f"run length {length:g} m plus the {margin * 1e3:.0f} mm window margins exceeds the "
            f"{grid.x[-1]:g} m of rail roughness data; use --length-m <= {grid.x[-1] - 2 * margin:.3f}"
        )
    lines = lines_along_track(grid, wanted, total_length, dx)
    if not np.all(np.isfinite(lines)):
        raise WheelrailError("roughness contains NaN or infinite heights")
    run.lines = lines
    run.centre_row = run.centre_window_row if model == "3d" else 0
    first = int(round(margin / dx))
    run.x_start = first * dx

    # Green's functions and wheel -------------------------------------------------------------------------
    speed = params.run.speed
    green = moving_green_functions(speed, params.track, track_numerics)
    weights = green.weights(dt)
    n_lags = weights.shape[1]
    phi, gamma0, gamma1 = wheel_discrete_system(params.wheel, dt)

    n_run_in = int(round(run_in_length / dx))
    n_hist = n_lags
    n_total = n_run_in + n_steps
    # rail position of history index j (sleeper at x = 0 of the roughness data)
    x_hist = run.x_start + (np.arange(n_hist + n_total) - n_hist - n_run_in) * dx
    P = len(green.excitation_positions)
    pos = np.mod(x_hist, green.sleeper_spacing) / green.sleeper_spacing * P
    lo = np.floor(pos).astype(np.int64) % P
    frac = pos - np.floor(pos)
    hi = (lo + 1) % P

    preload = params.contact.preload
    force = np.full(n_hist + n_total, preload)
    ramp = np.ones(n_total)
    if n_run_in:
        fade = np.arange(n_run_in) / max(1, n_run_in // 2)
        ramp[:n_run_in] = np.where(fade < 1, 0.5 - 0.5 * np.cos(np.pi * np.minimum(fade, 1)), 1.0)
    start_index = np.concatenate([np.full(n_run_in, first), first + np.arange(n_steps)]).astype(np.int64)
    weights = np.ascontiguousarray(weights)
    acc = np.zeros(n_hist + n_total + n_lags)
    _scatter_range(0, n_hist, force, lo, hi, frac, weights, acc)  # the preload's history
    run.loop = _Loop(dt=dt, n_steps=n_steps, n_run_in=n_run_in, n_hist=n_hist,
                     force=force, acc=acc, lo=lo, hi=hi, frac=frac, weights=weights, phi=phi,
                     gamma0=gamma0, gamma1=gamma1, state=np.zeros(4), xi_w0=0.0, ramp=ramp,
                     start_index=start_index)
    run.xi_wheel = np.zeros(n_total)
    run.xi_rail = np.zeros(n_total)
    run.contact_length = np.zeros(n_total)
    run.contact_area = np.zeros(n_total)
    run.pressure = None
    run.window_x = None
    variant = VARIANTS[model]()
    run.variant = variant
    static_approach = variant.prepare(run)
    if model == "3d" and keep_pressure:
        run.pressure = np.zeros((n_steps, len(run.window_y), 2 * half_x + 1), dtype=np.float32)
    # static equilibrium: the wheel sits at the model's static approach above the bay-averaged static
    # rail deflection under the preload (eq. 1's xi_S(P))
    run.loop.xi_w0 = static_approach + preload * float(np.mean(weights.sum(axis=1)))
    return run


def simulate(
    roughness,
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
    """Run the wheel/rail interaction and return the whole-run result (see :func:`prepare_run`).

    ``callback(state)`` is called for every step; setting the ``cancel`` event stops the run between
    steps and returns the steps done so far; ``progress(done, total)`` is called now and then.
    """
    run = prepare_run(roughness, model=model, line=line, params=params, length=length, **options)
    if cancel is not None:
        run._cancel = cancel
    return run.run(callback, progress)
