"""``3d``: the elastic half-space on a window of roughness lines as a contact model of the loop (eqs. 8-11).

The window (2 half_x + 1 elements along the rail, the rows of ``ModelInputs.lines`` across it) moves with
the wheel. Each step solves the coupled contact of ``contact.halfspace`` on the undeformed gap
h = x^2 / (2 R_x) + y^2 / (2 R_y) - r with the relative radii of ``ContactParameters`` (along: the wheel's
rolling radius; across: rail crown and tread), (x^2 + y^2) / (2 R) for the paper's crossed cylinders, with
delta = delta_known - c F.
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.contact.halfspace import HalfSpaceWindow
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import ContactModel, ContactState, ModelInputs

__all__ = ["HalfSpaceModel", "HalfSpaceReferenceModel"]


class HalfSpaceReferenceModel(ContactModel):
    """Per-step law: warm-started active set on the moving window, pressure map at every step."""

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
        self._window = HalfSpaceWindow(self._base_gap.shape, dx, youngs_modulus=contact.youngs_modulus,
                                       poisson_ratio=contact.poisson_ratio)
        smooth = self._window.solve(self._base_gap, load=contact.preload)
        self._window.start_from(smooth.contact)  # the first step from the preload's set, factored afresh
        return float(smooth.approach)

    def solve(self, s: int, approach_known: float, compliance: float) -> ContactState:
        inputs = self._inputs
        dx, hx = inputs.element_size, inputs.half_x
        i = inputs.start_index[s]
        gap = self._base_gap - inputs.ramp[s] * inputs.lines[:, i - hx:i + hx + 1]
        # the window warm-starts from its last solve with F > 0 (contact set and Cholesky factor: the window
        # moves with the wheel, so the patch stays centred; 1.8 instead of 5 active-set iterations per step)
        # and keeps this one as its warm state only if it carries load
        result = self._window.solve_coupled(gap, approach_known=approach_known, compliance=compliance,
                                            raise_on_failure=False)
        if result.at_edge:
            raise WheelrailError(
                f"3d: the contact reaches the edge of the {gap.shape[0]} x {gap.shape[1]} window at "
                f"x = {inputs.position_of(s):.4f} m; the roughness or load is too large for the window"
            )
        if not result.converged:
            raise WheelrailError(f"3d: the contact solve did not converge at x = {inputs.position_of(s):.4f} m")
        mask = result.contact
        return ContactState(force=float(result.force), contact_length=mask[inputs.centre_row].sum() * dx,
                            contact_area=mask.sum() * (dx * dx), pressure=result.pressure)


HalfSpaceModel = HalfSpaceReferenceModel
