"""The modal wheel in the interaction loop: its radial receptance at the contact as a discrete-time system.

The loop steps the wheel as ``s_{k+1} = Phi s_k + Gamma0 F_k + Gamma1 F_{k+1}`` and reads the contact's
displacement as state 1 (``wheelrail.core.wheel.wheel_discrete_system``, ``history.History``). Here the wheel
is the paper's rigid wheelset (the unsprung mass M_W on the primary suspension k_S, c_S, ``WheelParameters``)
with the modal wheel's radial point receptance at the contact in series::

    alpha(omega) = 1 / (k_S + i omega c_S - omega^2 M_W) + sum_m phi_m^2 / (omega_m^2 + i omega eta_m omega_m
                   - omega^2)

(modal coordinates q_m, q_m'' + eta_m omega_m q_m' + omega_m^2 q_m = phi_m F; phi_m the radial displacement at
the contact of the clamped wheel's mode m, mass-normalised; no static residual: the contact zone's local
flexibility is the contact model's, as in ``receptance.contact_receptance``). The
series connection takes the force on the hub to be the contact force (the wheel's own inertia loads the hub
only through the modes' reactions, left out: the usual approximation of a wheel's receptance as its rigid-body
part plus its flexible modes). The hysteretic loss factor eta_m is replaced by a viscous one of the same
damping at the mode's resonance (2 zeta_m = eta_m); away from its resonance a lightly damped mode's damping does
not matter. Discrete form: first-order hold (exact for a force linear over each step), as the 2-DOF wheel's.
The contact displacement is kept as an output state: state 1 holds C s after each step and nothing depends on
its previous value (column 1 of Phi is zero).
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.errors import WheelrailError

__all__ = ["modal_wheel_receptance", "modal_wheel_system"]


def _continuous(modes, wheel, added_loss_factor: float):
    """(A, B, C) of the rigid wheelset plus the radial modes, states (x_M, v_M, q_1.., q_1'..)."""
    keep = modes.frequency > 1.0  # a clamped wheel has no rigid-body modes; a free one's are the wheelset's
    phi = modes.contact_shapes()[keep, 0]
    omega = 2 * np.pi * modes.frequency[keep]
    eta = modes.loss_factor(added_loss_factor)[keep]
    k = len(phi)
    a = np.zeros((2 + 2 * k, 2 + 2 * k))
    a[0, 1] = 1.0
    a[1, 0] = -wheel.suspension_stiffness / wheel.unsprung_mass
    a[1, 1] = -wheel.suspension_damping / wheel.unsprung_mass
    modal = slice(2, 2 + k)
    rates = slice(2 + k, 2 + 2 * k)
    a[modal, rates] = np.eye(k)
    a[rates, modal] = -np.diag(omega**2)
    a[rates, rates] = -np.diag(eta * omega)
    b = np.zeros(2 + 2 * k)
    b[1] = 1.0 / wheel.unsprung_mass
    b[rates] = phi
    c = np.zeros(2 + 2 * k)
    c[0] = 1.0
    c[modal] = phi
    return a, b, c


def modal_wheel_receptance(modes, wheel, frequency, added_loss_factor: float = 0.0) -> np.ndarray:
    """The receptance (m/N) :func:`modal_wheel_system` discretises, at ``frequency`` (Hz): the rigid wheelset plus
    the modes with viscous damping (module docstring)."""
    a, b, c = _continuous(modes, wheel, added_loss_factor)
    omega = 2 * np.pi * np.atleast_1d(np.asarray(frequency, dtype=float))
    eye = np.eye(len(a))
    return np.array([c @ np.linalg.solve(1j * w * eye - a, b) for w in omega])


def modal_wheel_system(modes, wheel, time_step: float, added_loss_factor: float = 0.0):
    """``(Phi, Gamma0, Gamma1)`` of the modal wheel for the interaction loop (module docstring), state 1 the contact.

    Parameters
    ----------
    modes : WheelModes
        A clamped wheel's modes (``wheel_modes``).
    wheel : WheelParameters
        The rigid wheelset: ``unsprung_mass``, ``suspension_stiffness``, ``suspension_damping``.
    time_step : float
        dt, s.
    added_loss_factor : float
        A damper's loss factor added to every mode's.
    """
    from scipy.linalg import expm

    if not modes.clamped:
        raise WheelrailError("the interaction's modal wheel sits on the axle: give the modes of a clamped wheel")
    if not (np.isfinite(time_step) and time_step > 0):
        raise WheelrailError(f"modal_wheel_system: time_step must be positive (s), got {time_step}")
    a, b, c = _continuous(modes, wheel, added_loss_factor)
    n = len(a)
    # Van Loan's block exponential gives the first-order-hold integrals (as core.wheel._first_order_hold_expm)
    big = np.zeros((n + 2, n + 2))
    big[:n, :n] = a * time_step
    big[:n, n] = b * time_step
    big[n, n + 1] = 1.0
    e = expm(big)
    phi, g1, g2 = e[:n, :n], e[:n, n], e[:n, n + 1]
    gamma1, gamma0 = g2, g1 - g2
    # the augmented state: index 1 is the contact displacement (an output)
    true = [0, *range(2, n + 1)]  # where the true states go: x_M first (as the 2-DOF wheel's), then v_M, q, q'
    big_phi = np.zeros((n + 1, n + 1))
    big_phi[np.ix_(true, true)] = phi
    big_phi[1, true] = c @ phi
    out0, out1 = np.zeros(n + 1), np.zeros(n + 1)
    out0[true], out1[true] = gamma0, gamma1
    out0[1], out1[1] = c @ gamma0, c @ gamma1
    return np.ascontiguousarray(big_phi), out0, out1
