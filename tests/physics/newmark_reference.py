"""Reference integration of the FE track: Newmark's average-acceleration scheme in its three-vector form
(u, v, a), with band matrices and LAPACK's band Cholesky, in plain numpy/scipy. The algorithm the track's
Green's functions used before the displacement recurrence of ``core/track/newmark.py``; the tests compare the
two. Slow: small tracks and short runs only."""

from __future__ import annotations

import numpy as np
from scipy.linalg import cho_solve_banded, cholesky_banded

from wheelrail.core.track.fe import to_upper_band
from wheelrail.core.track.stationary import _relaxation_terms


def reference_responses(model, loads: np.ndarray, dt: float, n_steps: int, *, impulse: bool) -> np.ndarray:
    """Displacements u_k (n_steps, n_dof, columns) for the unit loads in the columns of ``loads`` (n_dof, m):
    a unit impulse at t = 0, or (``impulse`` False) a unit force at step 0 only, the track at rest before."""
    u_band = model.half_bandwidth
    c0, weights, b = _relaxation_terms(model.params.rail.loss_factor, dt)
    stiffness = model.K
    if len(weights):
        stiffness = model.K + (c0 - 1.0 + float(np.sum(weights / (1.0 + b)))) * model.K_rail
    keff = stiffness + (2.0 / dt) * model.C + (4.0 / dt**2) * model.M
    k_chol = (cholesky_banded(to_upper_band(keff, u_band)), False)
    m_chol = (cholesky_banded(to_upper_band(model.M, u_band)), False)
    M, C, K_rail = model.M.tocsr(), model.C.tocsr(), model.K_rail.tocsr()
    c1, c2, c3 = 4.0 / dt**2, 4.0 / dt, 2.0 / dt
    n, m = loads.shape
    q = np.zeros((len(weights), n, m))

    def relaxation_update(u_old, u_new):
        for j in range(len(weights)):
            q[j] = ((1.0 - b[j]) * q[j] + b[j] * (u_old + u_new)) / (1.0 + b[j])

    if impulse:
        u = np.zeros((n, m))
        v = cho_solve_banded(m_chol, loads)
        a = -cho_solve_banded(m_chol, C @ v)
    else:
        u = cho_solve_banded(k_chol, loads)
        v, a = c3 * u, c1 * u
        relaxation_update(np.zeros((n, m)), u)
    out = np.empty((n_steps, n, m))
    for k in range(n_steps):
        if k > 0:
            rhs = M @ (c1 * u + c2 * v + a) + C @ (c3 * u + v)
            if len(weights):
                z = sum(weights[j] * ((1.0 - b[j]) * q[j] + b[j] * u) / (1.0 + b[j]) for j in range(len(weights)))
                rhs += K_rail @ z
            new = cho_solve_banded(k_chol, rhs)
            relaxation_update(u, new)
            du = new - u
            a = c1 * du - c2 * v - a
            v = c3 * du - v
            u = new
        out[k] = u
    return out
