"""The compiled pieces of the interaction loop: eqs. 1-2 of a step and the one-line laws' chunk loop.

``known_approach`` (the wheel predicted with the last force, eq. 1 in its exact discrete form, and the rail's
displacement from all earlier forces, eq. 2) and ``commit_force`` (the step's force into the rail's history and
the wheel state) are inlined into every loop that steps a law: :data:`run_chunk` here (``hertz`` and bedding
laws), the 3D law's in ``wheelrail.core.interaction`` and the ``3d`` run-in's in ``contact.run_in_law``.
``track`` = (force, lo, hi, frac, weights, acc) and ``wheel`` = (phi, gamma0, gamma1, state): see
``run_setup.History``.
"""

from __future__ import annotations

import sys

import numpy as np
from numba import njit

from wheelrail.core.compiled import sources_stamp
from wheelrail.core.contact import hertz_law as hertz_kernels
from wheelrail.core.contact import winkler
from wheelrail.core.contact.hertz_law import hertz_law
from wheelrail.core.contact.winkler import bedding_law
from wheelrail.core.models import LAW_HERTZ

__all__ = ["commit_force", "known_approach", "law_curve", "run_chunk", "scatter_history"]


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


@njit(cache=True)
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


# --------------------------------------------------------------------------------------------------
# The one-line laws' chunk loop (models.LAW_HERTZ, LAW_BEDDING); eqs. 1-2 above, inlined
# --------------------------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def _law(law, approach_known, compliance, roughness, s, shape, constants):
    """A compiled law (models.LAW_*) at step s: (F, contact length, contact area, reached the window's end)."""
    if law == LAW_HERTZ:
        f, length, area = hertz_law(
            approach_known, compliance, roughness[s, 0], constants[0], constants[1], constants[2]
        )
        return f, length, area, False
    return bedding_law(approach_known, compliance, roughness[s], shape, constants[0], constants[1])


def _define_law_curve(stamp):
    @njit(cache=True)
    def law_curve(law, approaches, law_inputs, s):
        """A compiled one-line law's force at step s at the given approaches (compliance 0: F(delta)), N: the
        contact law of the run-in's steady state (``steady_start``)."""
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called
        roughness, shape, constants = law_inputs
        forces = np.empty(approaches.size)
        for k in range(approaches.size):
            forces[k] = _law(law, approaches[k], 0.0, roughness, s, shape, constants)[0]
        return forces

    return law_curve


# The chunk loop calls compiled code of other modules: numba's cache keys it on those sources too
# (wheelrail.core.compiled).
def _define_run_chunk(stamp):
    @njit(cache=True)
    def run_chunk(law, j0, j1, track, wheel, preload, xi_w0, law_inputs, out):
        """Advance a compiled law over history indices j0..j1-1. One function, not a Python loop over steps:
        the steps are the hot loop (1 us each). ``law_inputs`` = (roughness, shape, constants) of
        models.LawInputs; ``out`` = (xi_wheel, xi_rail, contact_length, contact_area) per step s.

        Returns -1 if all went well, else the index j at which the law reached its window's end.
        """
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called
        roughness, shape, constants = law_inputs
        xi_wheel, xi_rail, length, area = out
        offset = track[0].shape[0] - roughness.shape[0]
        for j in range(j0, j1):
            delta_known, c, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
            s = j - offset
            f, contact_length, contact_area, edge = _law(law, delta_known, c, roughness, s, shape, constants)
            if edge:
                return j
            length[s] = contact_length
            area[s] = contact_area
            xi_wheel[s], xi_rail[s] = commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0)
        return -1

    return run_chunk


_STAMP = sources_stamp(hertz_kernels, winkler, sys.modules[__name__])
run_chunk = _define_run_chunk(_STAMP)
law_curve = _define_law_curve(_STAMP)
