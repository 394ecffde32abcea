"""The compiled pieces of the interaction loop: eqs. 1-2 of a step.

``known_approach`` (the wheel predicted with the last force, eq. 1 in its exact discrete form, and the rail's
displacement from all earlier forces, eq. 2) and ``commit_force`` (the step's force into the rail's history and
the wheel state) are inlined into every loop that steps a law: each compiled law's chunk loop (``laws.one_line``,
``laws.halfspace``, a plug-in's) and the ``3d`` run-in's in ``contact.run_in_law``.
``track`` = (force, lo, hi, frac, weights, acc) and ``wheel`` = (phi, gamma0, gamma1, state): see
``history.History``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["commit_force", "known_approach", "scatter_history"]


@njit(cache=True, inline="always")
def known_approach(j, track, wheel, preload, xi_w0):
    """Known part of the approach at history index j: returns (delta_known, compliance, q_rail, w0, s_pred).

    The wheel state is predicted with the force still at F[j-1] (eq. 1 in its exact discrete form), the
    rail displacement ``acc[j]`` holds the response to all earlier forces (eq. 2, see ``_scatter``);
    delta = xi_W - xi_R = delta_known - c F[j] with the compliance c = Gamma1 + w_0.
    """
    force, lo, hi, frac, weights, acc = track
    phi, gamma0, gamma1, state = wheel
    q = acc[j]
    w0 = (1.0 - frac[j]) * weights[lo[j], 0] + frac[j] * weights[hi[j], 0]
    n = state.size  # 4 for the paper's wheel; more for the modal wheel (modal_wheel.time_domain)
    s_pred = np.empty(n)
    df = force[j - 1] - preload
    for a in range(n):
        v = gamma0[a] * df
        for b in range(n):
            v += phi[a, b] * state[b]
        s_pred[a] = v
    delta_known = xi_w0 - s_pred[1] + gamma1[1] * preload - q
    return delta_known, gamma1[1] + w0, q, w0, s_pred


@njit(cache=True, fastmath=True)
def _scatter(j, f, lo, hi, frac, weights, acc):
    """Add the rail displacement that force f at index j causes at the later steps (eq. 2, scattered
    forward: contiguous memory, so the n_lags multiply-adds vectorise; over views from index 0, which numba
    indexes without negative-index wraparound, faster than indexing from j + 1: docs, benchmarks page)."""
    n_lags = weights.shape[1]
    a = (1.0 - frac[j]) * f
    b = frac[j] * f
    row_lo = weights[lo[j], 1:]
    row_hi = weights[hi[j], 1:]
    later = acc[j + 1 : j + n_lags]
    for m in range(later.size):
        later[m] += a * row_lo[m] + b * row_hi[m]


@njit(cache=True, nogil=True)
def scatter_history(j0, j1, track):
    force, lo, hi, frac, weights, acc = track
    for j in range(j0, j1):
        _scatter(j, force[j], lo, hi, frac, weights, acc)


@njit(cache=True, inline="always")
def commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0):
    """Make f the force of index j: into the rail's history (eq. 2) and the wheel state (eq. 1).
    Returns (xi_W, xi_R) at this step."""
    force, lo, hi, frac, weights, acc = track
    phi, gamma0, gamma1, state = wheel
    force[j] = f
    _scatter(j, f, lo, hi, frac, weights, acc)
    for i in range(state.size):
        state[i] = s_pred[i] + gamma1[i] * (f - preload)
    return xi_w0 - state[1], q + w0 * f
