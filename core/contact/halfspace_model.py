"""``3d``: the elastic half-space on a window of roughness lines as a contact model of the loop (eqs. 8-11).

The window (2 half_x + 1 elements along the rail, the rows of ``ModelInputs.lines`` across it) moves with
the wheel. Each step solves the coupled contact of ``contact.halfspace`` on the undeformed gap
h = x^2 / (2 R_x) + y^2 / (2 R_y) - r with the relative radii of ``ContactParameters`` (along: the wheel's
rolling radius; across: rail crown and tread), (x^2 + y^2) / (2 R) for the paper's crossed cylinders, with
delta = delta_known - c F.

Two implementations of the same law:

* :class:`HalfSpaceModel` (the registered ``3d``): compiled, stepped inside the loop's compiled chunk
  (``contact.halfspace_steps``), tens of microseconds a step;
* :class:`HalfSpaceReferenceModel`: the per-step form it replaced, one Python call of
  ``HalfSpaceWindow.solve_coupled`` per step; kept as the reference the compiled law is tested against
  (``tests/physics/test_halfspace_loop.py``).
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.contact.halfspace import HalfSpaceWindow
from wheelrail.core.contact.halfspace_steps import (
    STEP_AT_EDGE,
    STEP_CONVERGED,
    STEP_NEEDS_ROOM,
    HalfSpaceSteps,
    _python_step,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import ContactModel, ContactState, ModelInputs

__all__ = ["HalfSpaceModel", "HalfSpaceReferenceModel"]


class _HalfSpaceBase(ContactModel):
    """The window's geometry and the static solve under the preload (shared by both implementations)."""

    def prepare(self, inputs: ModelInputs) -> float:
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
        self._window = HalfSpaceWindow(
            self._base_gap.shape, dx, youngs_modulus=contact.youngs_modulus, poisson_ratio=contact.poisson_ratio
        )
        smooth = self._window.solve(self._base_gap, load=contact.preload)
        self._start(smooth.contact)  # the first step from the preload's set, factored afresh
        return float(smooth.approach)

    def _start(self, contact: np.ndarray) -> None:
        raise NotImplementedError

    def failure_message(self, status: int, s: int) -> str:
        """Why the law stopped at step s (``halfspace_steps`` status)."""
        inputs = self._inputs
        ny, nx = self._base_gap.shape
        if status == STEP_AT_EDGE:
            return (
                f"3d: the contact reaches the edge of the {ny} x {nx} window at x = {inputs.position_of(s):.4f} m; "
                "the roughness or load is too large for the window"
            )
        return f"3d: the contact solve did not converge at x = {inputs.position_of(s):.4f} m"


class HalfSpaceModel(_HalfSpaceBase):
    """Compiled law (``LAW_HALFSPACE``): the warm state lives in :class:`HalfSpaceSteps`' arrays and every step
    runs inside the loop's compiled chunk; :meth:`solve` steps it once from Python (the same arithmetic)."""

    def _start(self, contact: np.ndarray) -> None:
        inputs, window = self._inputs, self._window
        self._steps = HalfSpaceSteps(
            window.kernel,
            self._base_gap,
            (inputs.lines, inputs.start_index, inputs.ramp, inputs.half_x, inputs.centre_row),
            np.flatnonzero(contact),
            (window.tolerance, window.max_iterations, inputs.element_size**2),
            **self.step_options,
        )

    step_options: dict = {}  # HalfSpaceSteps' keyword options (tests: full_matrix, capacity)

    def law_inputs(self) -> HalfSpaceSteps:
        return self._steps

    def solve(self, s: int, approach_known: float, compliance: float) -> ContactState:
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


class HalfSpaceReferenceModel(_HalfSpaceBase):
    """Per-step law: warm-started active set on the moving window, pressure map at every step (the form the
    compiled :class:`HalfSpaceModel` replaced, kept as its reference)."""

    def _start(self, contact: np.ndarray) -> None:
        self._window.start_from(contact)

    def solve(self, s: int, approach_known: float, compliance: float) -> ContactState:
        inputs = self._inputs
        dx, hx = inputs.element_size, inputs.half_x
        i = inputs.start_index[s]
        gap = self._base_gap - inputs.ramp[s] * inputs.lines[:, i - hx : i + hx + 1]
        # the window warm-starts from its last solve with F > 0 (contact set and Cholesky factor: the window
        # moves with the wheel, so the patch stays centred; 1.8 instead of 5 active-set iterations per step)
        # and keeps this one as its warm state only if it carries load
        result = self._window.solve_coupled(
            gap, approach_known=approach_known, compliance=compliance, raise_on_failure=False
        )
        if result.at_edge:
            raise WheelrailError(self.failure_message(STEP_AT_EDGE, s))
        if not result.converged:
            raise WheelrailError(self.failure_message(-1, s))
        mask = result.contact
        return ContactState(
            force=float(result.force),
            contact_length=mask[inputs.centre_row].sum() * dx,
            contact_area=mask.sum() * (dx * dx),
            pressure=result.pressure,
        )
