"""Two-degree-of-freedom wheel (paper section 2.1, Figure 1): receptance and Green's function.

Degrees of freedom (z positive downwards, into the rail, as in the paper): the unsprung mass M_W,
held by the primary suspension (k_S, c_S) to the bogie at rest, and the small contact mass m_W, joined
to M_W by (k_W, c_W). The contact force acts on m_W. The preload P acts through the suspension and only
sets the static position xi_S(P); the dynamics around it are linear.
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import FOH_MAX_STEP, WheelParameters


def wheel_matrices(wheel: WheelParameters) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mass, damping and stiffness matrices of the 2-DOF wheel, DOFs (M_W, m_W).

    Returns
    -------
    M, C, K : ndarray, shape (2, 2)
        In kg, N s/m and N/m.
    """
    M = np.diag([wheel.unsprung_mass, wheel.contact_mass])
    C = np.array(
        [
            [wheel.suspension_damping + wheel.wheel_damping, -wheel.wheel_damping],
            [-wheel.wheel_damping, wheel.wheel_damping],
        ]
    )
    K = np.array(
        [
            [wheel.suspension_stiffness + wheel.wheel_stiffness, -wheel.wheel_stiffness],
            [-wheel.wheel_stiffness, wheel.wheel_stiffness],
        ]
    )
    return M, C, K


def wheel_receptance(wheel: WheelParameters, frequency) -> np.ndarray:
    """Point receptance of the wheel at the contact point (displacement of m_W per force on m_W).

    Parameters
    ----------
    wheel : WheelParameters
    frequency : array_like
        Frequencies f, Hz (>= 0).

    Returns
    -------
    ndarray of complex
        alpha_W(f) in m/N, convention x(t) = Re(X e^{i 2 pi f t}).

    Raises
    ------
    WheelrailError
        For a negative or non-finite frequency.

    See Also
    --------
    wheel_green_function : its inverse Fourier transform.

    Examples
    --------
    At 0 Hz the receptance is the static flexibility of the suspension and the contact spring in series:

    >>> from wheelrail.core.parameters import WheelParameters
    >>> from wheelrail.core.wheel import wheel_receptance
    >>> wheel = WheelParameters()
    >>> static = 1 / wheel.suspension_stiffness + 1 / wheel.wheel_stiffness    # m/N
    >>> bool(abs(wheel_receptance(wheel, 0.0) - static) < 1e-9 * static)
    True
    """
    f = np.asarray(frequency, dtype=float)
    if not np.all(np.isfinite(f)) or np.any(f < 0):
        raise WheelrailError("wheel_receptance: frequencies must be finite and >= 0 Hz")
    M, C, K = wheel_matrices(wheel)
    w = 2 * np.pi * f[..., None, None]
    D = K - w**2 * M + 1j * w * C
    # alpha_22 = D_11 / det(D) for a 2 x 2 dynamic stiffness
    det = D[..., 0, 0] * D[..., 1, 1] - D[..., 0, 1] * D[..., 1, 0]
    return D[..., 0, 0] / det


def _wheel_state_space(wheel: WheelParameters) -> tuple[np.ndarray, np.ndarray]:
    M, C, K = wheel_matrices(wheel)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ K, -Minv @ C]])
    B = np.concatenate([np.zeros(2), Minv[:, 1]])  # unit force on m_W
    return A, B


def wheel_green_function(wheel: WheelParameters, time) -> np.ndarray:
    """Green's function g_W(t) of eq. (1): displacement of m_W after a unit impulse on m_W.

    Evaluated exactly from the eigen-decomposition of the 4 x 4 state matrix (the model is linear
    and time invariant).

    Parameters
    ----------
    wheel : WheelParameters
    time : array_like
        Times t >= 0 after the impulse, s.

    Returns
    -------
    ndarray
        g_W(t) in m/(N s). ``xi_W(t) = -int F(tau) g_W(t - tau) dtau + xi_S(P)`` (eq. 1).

    Raises
    ------
    WheelrailError
        For a negative or non-finite time.

    See Also
    --------
    wheel_discrete_system : the exact discrete form the interaction loop uses instead.
    """
    t = np.asarray(time, dtype=float)
    if not np.all(np.isfinite(t)) or np.any(t < 0):
        raise WheelrailError("wheel_green_function: times must be finite and >= 0 s")
    A, B = _wheel_state_space(wheel)
    lam, V = np.linalg.eig(A)
    coeff = np.linalg.solve(V, B)
    # displacement of m_W is state 1: sum_n V[1, n] coeff[n] exp(lam_n t)
    g = (V[1, :] * coeff) @ np.exp(np.multiply.outer(lam, t))
    return g.real


def wheel_static_compliance(wheel: WheelParameters) -> float:
    """Static compliance of the wheel at the contact point, 1/k_S + 1/k_W, m/N."""
    return 1.0 / wheel.suspension_stiffness + 1.0 / wheel.wheel_stiffness


def wheel_discrete_system(wheel: WheelParameters, time_step: float, method: str = "auto"):
    """Discrete-time form of the wheel: ``s_{n+1} = Phi s_n + Gamma0 F_n + Gamma1 F_{n+1}``.

    For the state s = (x_M, x_m, v_M, v_m) and a contact force F_n at t_n (unit impulse response of eq. 1).
    ``method="foh"`` (first-order hold, used up to ``FOH_MAX_STEP``): exact when F varies linearly over each
    step; the interaction loop uses it instead of convolving with g_W: same result, no truncation of the
    slowly decaying suspension mode. ``"trapezoidal"`` (used above ``FOH_MAX_STEP``, like the track's
    weights): the trapezoidal rule, Phi = (I - A dt/2)^-1 (I + A dt/2), Gamma0 = Gamma1 = (I - A dt/2)^-1 B
    dt/2, which keeps the coupled loop stable at long steps (see ``parameters.FOH_MAX_STEP``). ``"auto"``
    chooses by the step.

    Parameters
    ----------
    wheel : WheelParameters
    time_step : float
        dt, s.
    method : {"auto", "foh", "trapezoidal"}

    Returns
    -------
    Phi : ndarray (4, 4)
    Gamma0, Gamma1 : ndarray (4,)
        Response to the force at the start and at the end of the step, per N.

    Raises
    ------
    WheelrailError
        For a time step that is not positive or an unknown ``method``.

    See Also
    --------
    wheel_green_function : the continuous response it discretises.
    """
    if not np.isfinite(time_step) or time_step <= 0:
        raise WheelrailError(f"wheel_discrete_system: time_step must be positive (s), got {time_step}")
    if method not in ("auto", "foh", "trapezoidal"):
        raise WheelrailError(f"wheel_discrete_system: method must be auto, foh or trapezoidal, got {method!r}")
    A, B = _wheel_state_space(wheel)
    n = A.shape[0]
    if method == "trapezoidal" or (method == "auto" and time_step > FOH_MAX_STEP):
        left = np.eye(n) - 0.5 * time_step * A
        Phi = np.linalg.solve(left, np.eye(n) + 0.5 * time_step * A)
        Gamma = np.linalg.solve(left, 0.5 * time_step * B)
        return Phi, Gamma, Gamma.copy()
    return _first_order_hold(wheel, float(time_step))


_FOH_MEMORY: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}


def _first_order_hold(wheel: WheelParameters, time_step: float):
    """The FOH system of :func:`wheel_discrete_system`, from memory, the disk cache or computed and cached.

    Computed with ``scipy.linalg.expm``; cached (``wheelrail.core.files.cache``, keyed by the wheel and the step)
    because importing ``scipy.linalg`` costs a command-line run half a second, more than the run itself.
    The cached arrays are the computed ones, so results do not depend on whether they were cached.
    """
    from dataclasses import asdict

    from wheelrail.core.files import cache

    key = cache.cache_key("wheel-foh", {"wheel": asdict(wheel), "time_step": time_step})
    if key in _FOH_MEMORY:
        return tuple(array.copy() for array in _FOH_MEMORY[key])
    arrays = cache.load_entry("wheel-foh", key, ("phi", "gamma0", "gamma1"))
    if (
        arrays is not None
        and arrays["phi"].shape == (4, 4)
        and all(np.all(np.isfinite(arrays[name])) for name in ("phi", "gamma0", "gamma1"))
    ):
        system = (arrays["phi"], arrays["gamma0"], arrays["gamma1"])
    else:
        system = _first_order_hold_expm(wheel, time_step)
        cache.save_entry("wheel-foh", key, dict(zip(("phi", "gamma0", "gamma1"), system, strict=True)))
    _FOH_MEMORY[key] = system
    return tuple(array.copy() for array in system)


def _first_order_hold_expm(wheel: WheelParameters, time_step: float):
    from scipy.linalg import expm

    A, B = _wheel_state_space(wheel)
    n = A.shape[0]
    # Van Loan block exponential: [[A, B, 0], [0, 0, 1/dt], [0, 0, 0]] gives the FOH integrals.
    big = np.zeros((n + 2, n + 2))
    big[:n, :n] = A * time_step
    big[:n, n] = B * time_step
    big[n, n + 1] = 1.0
    E = expm(big)
    Phi = E[:n, :n]
    G1 = E[:n, n]  # int_0^dt e^{A s} B ds
    G2 = E[:n, n + 1]  # int_0^dt e^{A u} B (1 - u/dt) du
    # The state at t_{n+1} integrates e^{A u} B F(t_{n+1} - u) du with
    # F(t_{n+1} - u) = F_{n+1} (1 - u/dt) + F_n u/dt: G2 is the weight of F_{n+1}.
    Gamma1 = G2
    Gamma0 = G1 - G2
    return np.ascontiguousarray(Phi), Gamma0, np.ascontiguousarray(Gamma1)


def checked_wheel_system(system) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A caller's discrete-time wheel ``(Phi, Gamma0, Gamma1)`` as :func:`wheel_discrete_system` gives it: Phi
    n x n and Gamma0, Gamma1 of n finite numbers, n >= 2 (state 1 is the contact point's displacement); else
    one WheelrailError."""
    problem = (
        "prepare_run: wheel_system must be None, a modal wheel's cross-section or (Phi, Gamma0, Gamma1) "
        "(Phi n x n, Gamma0 and Gamma1 of n finite numbers, n >= 2)"
    )
    if not isinstance(system, tuple | list) or len(system) != 3:
        raise WheelrailError(f"{problem}, got {type(system).__name__}")
    try:
        phi, gamma0, gamma1 = (np.asarray(part, dtype=float) for part in system)
    except (TypeError, ValueError):
        raise WheelrailError(f"{problem}; its parts are not arrays of numbers") from None
    n = len(gamma0) if gamma0.ndim == 1 else 0
    if n < 2 or phi.shape != (n, n) or gamma1.shape != (n,):
        raise WheelrailError(f"{problem}; got shapes {phi.shape}, {gamma0.shape}, {gamma1.shape}")
    if not all(np.all(np.isfinite(part)) for part in (phi, gamma0, gamma1)):
        raise WheelrailError(f"{problem}; it holds a NaN or infinity")
    return phi, gamma0, gamma1
