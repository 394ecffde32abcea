"""The ``3d`` law as the engine steps it: the elastic half-space on a window that moves with the wheel (eqs. 8-11).

:class:`HalfSpaceLaw` owns what only this law has: its compiled chunk loop :data:`run_chunk_3d` (the active-set
step of ``contact.halfspace_model`` with eqs. 1-2 inlined, without the GIL, ``CHUNK_3D`` steps a call), the
pressure map of every step (kept for the record, or a buffer of the last chunk's), the run-in on its tabulated law
(``contact.run_in_law``: a run-in from the preload of ``TABULATED_RUN_IN_TIME`` or more, in one call), the warm
state put at the run-in's last approach, and the steady start on its law tabulated over a band of forces.
"""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np
from numba import njit

from wheelrail.core.contact import active_set, capacitance, cholesky, deformed_gap, halfspace_model
from wheelrail.core.contact.active_set import STEP_CONVERGED, STEP_NEEDS_ROOM
from wheelrail.core.contact.halfspace_model import halfspace_step
from wheelrail.core.contact.run_in_law import run_in_chunk, run_in_table, step_law, warm_start
from wheelrail.core.engine import kernels
from wheelrail.core.engine.compiled import sources_stamp
from wheelrail.core.engine.kernels import commit_force, known_approach
from wheelrail.core.engine.laws.base import ContactLaw
from wheelrail.core.errors import WheelrailError

__all__ = ["CHUNK_3D", "STEADY_TABLE", "TABULATED_RUN_IN_TIME", "WIDE_TABLE", "HalfSpaceLaw", "run_chunk_3d"]

CHUNK_3D = 256  # steps per call of the 3D chunk loop, so a live view gets them in time
# s: a 3d run-in from the preload (an explicit one) this long or longer runs on the law tabulated
# (contact.run_in_law); its fade-in's blend then leaves at most 0.014 N (0.108 s at 100 km/h), 0.2-2.4 N after
# a run-in of 1-36 ms, which the 3D solver steps; the steady start's run-in (0.5 ms) is stepped by it too
TABULATED_RUN_IN_TIME = 0.1
# the steady start's law tabulated exactly within 0.92-1.08 P (run_in_law.step_law), the table from 0.8 of the
# static approach beyond first contact (the steady force on the corrugated rail stays within 0.968-1.048 P at
# 100-400 km/h)
STEADY_TABLE = ((0.92, 1.08), 0.8)
WIDE_TABLE = ((0.05, 2.0), 0.0)  # where STEADY_TABLE's law has no steady state, 0.05-2 P from first contact


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
                if f > 0.0:
                    for i in range(n):
                        flat[i] = pressure[i]
                else:
                    for i in range(n):
                        flat[i] = 0.0
            xi_wheel[s], xi_rail[s] = commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0)
        return -1, STEP_CONVERGED

    return run_chunk_3d


run_chunk_3d = _define_run_chunk_3d(
    sources_stamp(halfspace_model, active_set, capacitance, cholesky, deformed_gap, kernels)
)


@contextmanager
def _factor_path(solver):
    """The solver on its set's own factor meanwhile: ``contact.run_in_law`` reads z = U^-T 1, which the
    capacitance solve does not keep."""
    was = solver.use_capacitance(False)
    try:
        yield
    finally:
        solver.use_capacitance(was)


class HalfSpaceLaw(ContactLaw):
    """The ``3d`` law: the model's ``ActiveSetSolver`` stepped by :data:`run_chunk_3d`.

    Attributes
    ----------
    solver : ActiveSetSolver
        The model's warm state (set, factor, pressure), stepped in place.
    tabulated_run_in : bool
        A run-in from the preload of ``TABULATED_RUN_IN_TIME`` or more runs on the tabulated law (else the 3D
        solver steps it).
    table : tuple or None
        The run-in's tabulated law (breakpoints, T_0, T_1; ``run_in_law.run_in_table``), built on first use.
    """

    chunk = CHUNK_3D
    nogil = True  # run_chunk_3d releases the GIL
    tabulated_run_in = True

    def __init__(self, contact, inputs, history, outputs, keep_pressure=True) -> None:
        super().__init__(contact, inputs, history, outputs, keep_pressure)
        self.solver = contact.law_inputs()
        self.table = None
        self._segment = np.zeros(1, dtype=np.int64)  # the table's segment of the last run-in step
        self._maps = self._maps_first = None  # not kept: the last chunk's maps and its first step
        if self.pressure is None:
            self._maps = np.zeros((CHUNK_3D, *self.map_shape), dtype=np.float32)

    def surface_input(self, lines: np.ndarray) -> np.ndarray:
        """The window's rows of ``lines`` as the compiled step reads them (it takes each step's window from them,
        faded in over the run-in): (rows, samples), m."""
        return np.ascontiguousarray(lines, dtype=np.float64)

    @property
    def _tabulated(self) -> bool:
        loop = self.history
        return self.tabulated_run_in and loop.n_run_in * loop.dt >= TABULATED_RUN_IN_TIME

    def chunk_end(self, s0: int, s_end: int) -> int:
        """A tabulated run-in in one call; else ``CHUNK_3D`` steps."""
        if s0 < self.history.n_run_in and self._tabulated:
            return min(s_end, self.history.n_run_in)
        return super().chunk_end(s0, s_end)

    def advance(self, s0: int, s1: int) -> None:
        loop = self.history
        if s0 < loop.n_run_in and self._tabulated:
            self._run_in(s0, min(s1, loop.n_run_in))
            s0 = min(s1, loop.n_run_in)
            if s0 == s1:
                return
        maps, first = (self.pressure, loop.n_run_in) if self._maps is None else (self._maps, s0)
        outputs = (*self.outputs, maps)
        j = loop.n_hist + s0
        while True:
            j, status = run_chunk_3d(
                j,
                loop.n_hist + s1,
                loop.track,
                loop.wheel,
                (self.preload, loop.xi_w0, loop.n_hist, first, self.inputs.element_size),
                self.solver.law,
                outputs,
            )
            if status != STEP_NEEDS_ROOM:
                break
            self.solver.grow()  # the set outgrew the factor's buffer: repeat step j with a larger one
        self._maps_first = s0
        if j >= 0:
            raise WheelrailError(self.contact.failure_message(status, j - loop.n_hist))

    def _run_in(self, s0: int, s1: int) -> None:
        """Run-in steps s0..s1-1 on the tabulated law (``contact.run_in_law``); at the run-in's end the warm
        state is put at the last approach, on the first recorded step's gap."""
        loop, preload = self.history, self.preload
        if self.table is None:  # the static approach under the preload as scale
            with _factor_path(self.solver):
                self.table = run_in_table(self.solver, loop.n_run_in, preload, loop.static_approach)
        j0, j1, constants = loop.n_hist + s0, loop.n_hist + s1, (preload, loop.xi_w0, loop.n_hist)
        approach = run_in_chunk(
            j0, j1, loop.track, loop.wheel, constants, self.table, loop.ramp, self._segment, self.outputs[:2]
        )
        if s1 == loop.n_run_in:
            with _factor_path(self.solver):
                warm_start(self.solver, loop.n_run_in, approach)

    def chunk_pressure(self, s0: int, s1: int) -> np.ndarray | None:
        if self._maps is None:
            return super().chunk_pressure(s0, s1)
        return self._maps[s0 - self._maps_first : s1 - self._maps_first].copy()  # the buffer the next reuses

    def steady_law(self, band=STEADY_TABLE):
        """The law tabulated exactly within ``band`` = ((low, high) x P, start x static approach) on the run-in's
        gap (``run_in_law.step_law``), extended linearly above."""
        with _factor_path(self.solver):
            delta, force = step_law(
                self.solver, self.history.n_run_in, self.preload, self.history.static_approach, *band
            )
        slope = (force[-1] - force[-2]) / (delta[-1] - delta[-2])
        return lambda d: np.where(d > delta[-1], force[-1] + slope * (d - delta[-1]), np.interp(d, delta, force))

    def start_steady(self):
        """The steady state on the law tabulated within ``STEADY_TABLE``'s band; should the steady force leave it,
        tabulated again over the force's range with a margin, from first contact; where that band's law holds no
        steady state (3d at 1 kN: its iterations stall), over ``WIDE_TABLE``. The warm state is then put at the
        approach of the first phase."""
        from wheelrail.core.engine.steady_start import fill_history, start_state

        loop, preload = self.history, self.preload
        try:
            steady = start_state(loop, self.steady_law(), preload)
        except WheelrailError:
            steady = start_state(loop, self.steady_law(WIDE_TABLE), preload)
        else:
            low, high = float(steady.force.min()) / preload, float(steady.force.max()) / preload
            band = STEADY_TABLE[0]
            if not (band[0] <= low and high <= band[1]):
                steady = start_state(loop, self.steady_law(((max(0.05, low - 0.1), high + 0.1), 0.0)), preload)
        fill_history(loop, steady)
        with _factor_path(self.solver):
            warm_start(self.solver, 0, float(steady.approach[0]))
        return steady
