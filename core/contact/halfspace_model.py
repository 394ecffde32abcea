"""``3d``: the elastic half-space on a window of roughness lines as a contact model of the loop (eqs. 8-11).

The window (2 half_x + 1 elements along the rail, the rows of ``ModelInputs.lines`` across it) moves with
the wheel. Each step builds the window's undeformed gap h = x^2 / (2 R_x) + y^2 / (2 R_y) - r (eq. 11; the
relative radii of ``ContactParameters``, (x^2 + y^2) / (2 R) for the paper's crossed cylinders) and solves
eqs. 8-11 coupled with delta = delta_known - c F by the active set of ``contact.active_set``, warm-started
from the last loaded step. :func:`halfspace_step` is that step in compiled code, inlined into the loop's
compiled chunk (``engine.laws.halfspace.run_chunk_3d``) and into :data:`_python_step` (:meth:`HalfSpaceModel.solve`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from wheelrail.core.contact import active_set, capacitance, cholesky, deformed_gap
from wheelrail.core.contact.active_set import (
    STEP_AT_EDGE,
    STEP_CONVERGED,
    STEP_NEEDS_ROOM,
    ActiveSetSolver,
    influence_grid,
    solve_step,
)
from wheelrail.core.contact.window import HalfSpaceWindow
from wheelrail.core.engine.compiled import sources_stamp
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import ContactModel, ContactState, ModelInputs

__all__ = ["HalfSpaceModel", "halfspace_step", "track_inputs"]


class HalfSpaceModel(ContactModel):
    """The ``3d`` contact model (``LAW_HALFSPACE``): eqs. 8-11 on a window that moves with the wheel.

    The warm state lives in an :class:`~wheelrail.core.contact.active_set.ActiveSetSolver`'s arrays and every
    step runs inside the loop's compiled chunk; :meth:`solve` steps it once from Python (the same arithmetic).

    See Also
    --------
    wheelrail.core.contact.window.HalfSpaceWindow : one-off solves of the same equations.
    """

    step_options: dict = {}  # the solver's options (tests: full_matrix, capacity, capacitance)

    def prepare(self, inputs: ModelInputs) -> float:
        """The window's geometry, the static solve under the preload and the solver's first state; returns the
        static approach, m."""
        contact = inputs.params.contact
        dx, hx = inputs.element_size, inputs.half_x
        x = np.arange(-hx, hx + 1) * dx
        y = inputs.window_y
        if contact.circular:  # the paper's expression, kept as it was (results unchanged to the bit)
            self._base_gap = (x[None, :] ** 2 + y[:, None] ** 2) / (2 * contact.radius_along)
        else:
            rx, ry = contact.radius_along, contact.radius_across
            self._base_gap = x[None, :] ** 2 / (2 * rx) + y[:, None] ** 2 / (2 * ry)
        self._inputs = inputs
        self.window_x = x
        self.equivalent_line = inputs.centre_line
        window = HalfSpaceWindow(self._base_gap.shape, dx, contact=contact)
        smooth = window.solve(self._base_gap, load=contact.preload)
        options = dict(self.step_options)
        grid = influence_grid(window.kernel, options.pop("full_matrix", None))
        capacitance_on = options.pop("capacitance", grid[2].shape[0] == 0)  # windows without C: contact.capacitance
        self._steps = ActiveSetSolver(
            grid,
            np.flatnonzero(smooth.contact),  # the first step from the preload's set, factored afresh
            (window.tolerance, window.max_iterations, dx**2),
            track=track_inputs(self._base_gap, inputs),
            **options,
        )
        self._steps.use_capacitance(capacitance_on)
        return float(smooth.approach)

    def law_inputs(self) -> ActiveSetSolver:
        """The solver whose ``law`` the compiled loop steps."""
        return self._steps

    def failure_message(self, status: int, s: int) -> str:
        """Why the law stopped at step s (``active_set`` status)."""
        inputs = self._inputs
        ny, nx = self._base_gap.shape
        if status == STEP_AT_EDGE:
            return (
                f"3d: the contact reaches the edge of the {ny} x {nx} window at x = {inputs.position_of(s):.4f} m; "
                "the roughness or load is too large for the window"
            )
        return f"3d: the contact solve did not converge at x = {inputs.position_of(s):.4f} m"

    def solve(self, s: int, approach_known: float, compliance: float) -> ContactState:
        """Step s from Python: the contact state for this known approach (m) and compliance (m/N)."""
        status = STEP_NEEDS_ROOM
        while status == STEP_NEEDS_ROOM:
            status, force, on_centre, count = _python_step(
                int(s), float(approach_known), float(compliance), self._steps.law
            )
            if status == STEP_NEEDS_ROOM:
                self._steps.grow()
        if status != STEP_CONVERGED:
            raise WheelrailError(self.failure_message(status, s))
        dx = self._inputs.element_size
        shape = self._base_gap.shape
        pressure = np.zeros(shape) if force == 0.0 else self._steps.pressure.reshape(shape).copy()
        return ContactState(
            force=force, contact_length=on_centre * dx, contact_area=count * (dx * dx), pressure=pressure
        )


def track_inputs(base_gap: np.ndarray, inputs: ModelInputs) -> tuple:
    """What :func:`halfspace_step` reads of the track: (smooth gap flattened (m), roughness rows (m), sample
    under the wheel centre per step, the run-in's fade-in factor per step, half_x, the chosen line's row)."""
    return (
        np.ascontiguousarray(base_gap, dtype=np.float64).ravel(),
        np.ascontiguousarray(inputs.lines, dtype=np.float64),
        np.ascontiguousarray(inputs.start_index, dtype=np.int64),
        np.ascontiguousarray(inputs.ramp, dtype=np.float64),
        int(inputs.half_x),
        int(inputs.centre_row),
    )


@njit(cache=True, inline="always")
def halfspace_step(s, approach_known, compliance, law):
    """Step s of the ``3d`` law: the window's gap under the wheel, then the coupled solve.

    Returns (status, F (N), elements in contact on the centre row, elements in contact); ``STEP_AT_EDGE`` when
    the converged set touches the window's border, ``STEP_NEEDS_ROOM`` when the step must be repeated with a
    larger factor buffer.
    """
    grid, state, work, track, _ = law
    base, lines, start_index, ramp, half_x, centre_row = track
    gap = work[1]
    nx = 2 * half_x + 1
    ny = base.size // nx
    first = start_index[s] - half_x
    fade = ramp[s]
    for row in range(ny):
        for column in range(nx):
            gap[row * nx + column] = base[row * nx + column] - fade * lines[row, first + column]
    status, force, _, _ = solve_step(law, True, approach_known, compliance)
    if force == 0.0 or status != STEP_CONVERGED:
        return status, force, 0, 0
    rows, columns = grid[3], grid[4]
    order, m = state[0], state[3][0]
    on_centre = 0
    for a in range(m):
        i = order[a]
        if rows[i] == 0 or rows[i] == ny - 1 or columns[i] == 0 or columns[i] == nx - 1:
            status = STEP_AT_EDGE
        if rows[i] == centre_row:
            on_centre += 1
    return status, force, on_centre, m


def _define_python_step(stamp):
    @njit(cache=True)
    def python_step(s, approach_known, compliance, law):
        """:func:`halfspace_step` called from Python (``HalfSpaceModel.solve``)."""
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called (wheelrail.core.engine.compiled)
        return halfspace_step(s, approach_known, compliance, law)

    return python_step


_python_step = _define_python_step(sources_stamp(active_set, capacitance, cholesky, deformed_gap))
