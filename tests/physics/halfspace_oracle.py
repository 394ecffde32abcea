"""A deliberately simple oracle of the 3D half-space contact (paper eqs. 8-11): the dense linear
complementarity problem, solved as non-negative least squares. Not a production solver: it builds the
dense influence matrix and solves each contact from scratch, no warm state, no factor updates.

With the coupling delta = delta_known - c A_e sum(p), the deformed gap of eq. (11) is
d = (C + c A_e 1 1^T) p + (h - delta_known) = M p + q with M symmetric positive definite, and eq. (10)
(p >= 0, d >= 0, p d = 0) is the KKT system of min 1/2 p^T M p + q^T p over p >= 0. With M = L L^T that is
min ||L^T p - b|| over p >= 0 with L b = -q: Lawson-Hanson NNLS (``scipy.optimize.nnls``). Only elements with
h < delta_known can carry pressure (u = C p >= 0 and delta <= delta_known), so M is restricted to them.
A load-controlled solve (eq. 9: A_e sum(p) = F) finds delta by Brent's method on the displacement-controlled
force, which is continuous and increasing in delta.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq, nnls

from wheelrail.core.contact import influence_kernel
from wheelrail.core.models import ContactModel, ContactState, ModelInputs


def influence_matrix(shape: tuple[int, int], element_size: float, contact) -> np.ndarray:
    """The dense C of u = C p (eq. 8) on the flattened window, m/Pa."""
    ny, nx = shape
    kernel = influence_kernel(shape, element_size, contact)
    rows, columns = np.divmod(np.arange(ny * nx), nx)
    return kernel[rows[:, None] - rows[None, :] + ny - 1, columns[:, None] - columns[None, :] + nx - 1]


def _cholesky_lower(matrix: np.ndarray) -> np.ndarray:
    """L with L L^T = matrix, by the outer-product algorithm in elementwise numpy (LAPACK's threaded potrf
    stalls for a second at these sizes on a loaded 2-core machine)."""
    work = np.array(matrix, dtype=float)
    n = work.shape[0]
    for j in range(n):
        work[j, j] = np.sqrt(work[j, j])
        work[j + 1 :, j] /= work[j, j]
        column = work[j + 1 :, j]
        work[j + 1 :, j + 1 :] -= column[:, None] * column[None, :]
    return np.tril(work)


def _forward(lower: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """y with L y = rhs, row by row (elementwise numpy)."""
    y = np.empty(rhs.size)
    for i in range(rhs.size):
        y[i] = (rhs[i] - (lower[i, :i] * y[:i]).sum()) / lower[i, i]
    return y


def coupled_pressure(matrix, gap, approach_known: float, compliance: float, area: float):
    """(p (Pa, flattened), delta (m)) of eqs. 8-11 with delta = delta_known - c A_e sum(p)."""
    flat = np.ravel(gap)
    pressure = np.zeros(flat.size)
    possible = flat < approach_known
    if not possible.any():
        return pressure, approach_known
    m = matrix[np.ix_(possible, possible)] + compliance * area
    lower = _cholesky_lower(m)
    b = -_forward(lower, flat[possible] - approach_known)
    pressure[possible] = nnls(lower.T, b, maxiter=50 * b.size)[0]
    return pressure, approach_known - compliance * area * pressure.sum()


def loaded_pressure(matrix, gap, load: float, area: float):
    """(p, delta) of eqs. 8-11 under the load F (N): delta from F(delta) = load, F displacement-controlled."""
    lowest = float(np.min(gap))

    def excess(delta):
        return area * coupled_pressure(matrix, gap, delta, 0.0, area)[0].sum() - load

    high = lowest + 1e-6
    while excess(high) < 0.0:
        high = lowest + 2.0 * (high - lowest)
    delta = brentq(excess, lowest, high, xtol=1e-18, rtol=1e-15)
    return coupled_pressure(matrix, gap, delta, 0.0, area)[0], delta


class OracleModel(ContactModel):
    """The ``3d`` model's equations stepped by the oracle: the window's gap h = x^2 / (2 R_x) + y^2 / (2 R_y)
    - r under the wheel, one dense NNLS solve per step (a per-step model of the loop)."""

    def prepare(self, inputs: ModelInputs) -> float:
        contact = inputs.params.contact
        dx, hx = inputs.element_size, inputs.half_x
        x = np.arange(-hx, hx + 1) * dx
        y = inputs.window_y
        self._base_gap = x[None, :] ** 2 / (2 * contact.radius_along) + y[:, None] ** 2 / (2 * contact.radius_across)
        self._matrix = influence_matrix(self._base_gap.shape, dx, contact)
        self._inputs = inputs
        self.window_x = x
        self.equivalent_line = inputs.centre_line
        return loaded_pressure(self._matrix, self._base_gap, contact.preload, dx * dx)[1]

    def solve(self, s: int, approach_known: float, compliance: float) -> ContactState:
        inputs = self._inputs
        dx, hx, i = inputs.element_size, inputs.half_x, inputs.start_index[s]
        gap = self._base_gap - inputs.ramp[s] * inputs.lines[:, i - hx : i + hx + 1]
        pressure, _ = coupled_pressure(self._matrix, gap, approach_known, compliance, dx * dx)
        pressure = pressure.reshape(gap.shape)
        return ContactState(
            force=float(pressure.sum() * dx * dx),
            contact_length=np.count_nonzero(pressure[inputs.centre_row]) * dx,
            contact_area=np.count_nonzero(pressure) * (dx * dx),
            pressure=pressure,
        )
