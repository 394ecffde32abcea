"""Non-linear Hertzian contact spring (paper section 2.3.3, eqs. 12-14).

Sign convention: the spring compression is Delta zeta = xi_W - xi_R + r_eq (eq. 14), m, with z positive
downwards into the rail; the wheel pressing into the rail (or roughness sticking out of the wheel) is a
positive compression. F = C_H Delta zeta^1.5 for Delta zeta >= 0 and F = 0 otherwise (loss of contact).

The ``_``-prefixed functions are numba kernels for the time-stepping loop (scalar in, scalar out, no
checks); the public functions check their input and work on arrays.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from wheelrail.core import checks
from wheelrail.core.checks import finite_array
from wheelrail.core.contact.winkler import checked_contact
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import ContactModel, LawInputs, ModelInputs
from wheelrail.core.parameters import ContactParameters

__all__ = [
    "HertzAverageModel",
    "HertzModel",
    "HertzWinklerModel",
    "hertz_approach",
    "hertz_constant",
    "hertz_force",
    "hertz_stiffness",
]


@njit(cache=True)
def _hertz_force(compression, constant):
    """F = C_H compression^1.5 for compression >= 0 else 0 (eq. 12), N."""
    if compression <= 0.0:
        return 0.0
    return constant * compression * math.sqrt(compression)


@njit(cache=True)
def _hertz_force_and_stiffness(compression, constant):
    """(F, dF/d compression) of eq. (12): (C_H c^1.5, 1.5 C_H c^0.5), or (0, 0) out of contact."""
    if compression <= 0.0:
        return 0.0, 0.0
    root = math.sqrt(compression)
    return constant * compression * root, 1.5 * constant * root


@njit(cache=True)
def _hertz_compression(target, compliance, constant):
    """Solve u + c C_H u^1.5 = target for the compression u >= 0 (target <= 0: no contact). Newton from
    u = target, monotone for this increasing convex function."""
    if target <= 0.0:
        return 0.0
    u = target
    for _ in range(60):
        root = math.sqrt(u)
        residual = u + compliance * constant * u * root - target
        step = residual / (1.0 + 1.5 * compliance * constant * root)
        u -= step
        if u <= 0.0:
            u = 1e-300
        if abs(step) <= 1e-15 * target + 1e-22:
            break
    return u


@njit(cache=True, inline="always")
def _hertz_law(approach_known, compliance, roughness, constant, radius_along, radius_across):
    """The interaction loop's Hertz law (eqs. 12-14 coupled with delta = delta_known - c F).

    The compression is u = delta + r_eq, so u + c C u^1.5 = delta_known + r_eq. Returns (F = C u^1.5,
    contact length 2a = 2 sqrt(rho_x u), area pi a b with b = sqrt(rho_y u)) for the equivalent roughness
    r_eq at this step; rho_x, rho_y: ``ContactParameters.patch_radii`` (both R for the paper's circle).
    """
    u = _hertz_compression(approach_known + roughness, compliance, constant)
    length = 2.0 * math.sqrt(radius_along * u)
    half = length / 2.0
    return _hertz_force(u, constant), length, math.pi * (half * math.sqrt(radius_across * u))


class HertzModel(ContactModel):
    """``hertz``: the Hertz spring on the roughness of the line itself (r_eq = r); elliptic for unequal radii
    (``ContactParameters.hertz``: C of F = C delta^1.5, contact length 2a along the rail, area pi a b)."""

    def equivalent_roughness(self, inputs: ModelInputs, line: np.ndarray) -> np.ndarray:
        """r_eq along the track for the line r (here r itself)."""
        return line

    def prepare(self, inputs: ModelInputs) -> float:
        contact = inputs.params.contact
        self.equivalent_line = self.equivalent_roughness(inputs, inputs.centre_line)
        r_eq = np.ascontiguousarray(self.equivalent_line[inputs.start_index] * inputs.ramp)
        self._law = LawInputs(
            roughness=r_eq.reshape(-1, 1),
            shape=np.zeros(1),
            constants=np.array([contact.hertz_constant, *contact.patch_radii()]),
        )
        return contact.hertz_approach()

    def law_inputs(self) -> LawInputs:
        return self._law


class HertzWinklerModel(HertzModel):
    """``hertz-winkler``: r_eq from the Ford & Thompson bedding pre-filter (``contact.prefilter``).

    The bedding is the ``2d`` model's (``contact.winkler.calibrated_bedding``: the paper's for the circle).
    The pre-filter runs on the line along the track; the run's margins (``run_setup.run_margin``, 20 mm at
    1 mm elements, at least 3a) cover its half-length 3a (16.4 mm at the defaults), so its end treatment never
    reaches a step of the run.
    """

    def equivalent_roughness(self, inputs, line):
        from wheelrail.core.contact.prefilter import winkler_equivalent_roughness

        try:
            return winkler_equivalent_roughness(line, inputs.element_size, inputs.params.contact)
        except WheelrailError as error:
            if error.parameter != "half_window":
                raise
            # a run sizes the pre-filter's window itself (3a): what its user can change is the roughness
            raise WheelrailError(
                error.problem,
                parameter="model",
                value="hertz-winkler",
                advice="use a smoother line or set, or the hertz model",
            ) from None


class HertzAverageModel(HertzModel):
    """``hertz-average``: r_eq = mean of r over the nominal contact length 2a along the rail (a the Hertz
    semi-axis along the rail at the preload; a + 1 mm < the run margin)."""

    def equivalent_roughness(self, inputs, line):
        from wheelrail.core.contact.prefilter import average_roughness

        a, _ = inputs.params.contact.hertz_semi_axes()
        return average_roughness(line, inputs.element_size, contact_length=2 * a)


def hertz_constant(contact: ContactParameters | None = None) -> float:
    """Hertzian constant C_H of F = C_H delta^1.5, eq. (13), N/m^1.5.

    Parameters
    ----------
    contact : ContactParameters, optional
        Material and radii; default ``ContactParameters()`` (the paper's crossed cylinders, R = 0.39 m).

    Returns
    -------
    float
        C_H in N/m^1.5: (2/3) E / (1 - nu^2) sqrt(R) for the paper's circle (9.608e10 at its values), Hertz's
        elliptic constant (``ContactParameters.hertz``) otherwise.

    Raises
    ------
    WheelrailError
        If ``contact`` is not ContactParameters.

    See Also
    --------
    hertz_force, hertz_approach : the spring law with this constant.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eq. (13).

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_constant
    >>> f"{hertz_constant():.4g}"
    '9.608e+10'
    """
    return checked_contact("hertz_constant", contact).hertz_constant


def hertz_force(compression, constant: float) -> np.ndarray:
    """Contact force of the Hertzian spring, eq. (12).

    Parameters
    ----------
    compression : array_like
        Delta zeta of eq. (14), m (negative = no contact).
    constant : float
        C_H of eq. (13), N/m^1.5.

    Returns
    -------
    ndarray
        F_n in N, same shape as ``compression``; 0 where compression < 0.

    Raises
    ------
    WheelrailError
        If ``compression`` is not finite numbers or ``constant`` not a positive number.

    See Also
    --------
    hertz_constant, hertz_stiffness, hertz_approach

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eq. (12).

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_constant, hertz_force
    >>> round(float(hertz_force(77.07e-6, hertz_constant())) / 1e3, 1)   # kN at the static approach
    65.0
    """
    compression = finite_array("hertz_force: compression", compression, "m")
    constant = checks.positive("hertz_force", "constant", constant, "N/m^1.5")
    positive = np.maximum(compression, 0.0)
    return constant * positive * np.sqrt(positive)


def hertz_stiffness(compression, constant: float) -> np.ndarray:
    """Tangent stiffness dF/d(Delta zeta) = 1.5 C_H Delta zeta^0.5 of eq. (12), N/m (0 out of contact).

    Parameters
    ----------
    compression : array_like
        Delta zeta, m.
    constant : float
        C_H, N/m^1.5.

    Returns
    -------
    ndarray
        N/m, same shape as ``compression``.

    Raises
    ------
    WheelrailError
        As :func:`hertz_force`.

    See Also
    --------
    hertz_force

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_constant, hertz_stiffness
    >>> f"{float(hertz_stiffness(77.07e-6, hertz_constant())):.3g}"   # N/m: 1.5 F / delta
    '1.27e+09'
    """
    compression = finite_array("hertz_stiffness: compression", compression, "m")
    constant = checks.positive("hertz_stiffness", "constant", constant, "N/m^1.5")
    return 1.5 * constant * np.sqrt(np.maximum(compression, 0.0))


def hertz_approach(force, constant: float) -> np.ndarray:
    """Inverse of eq. (12): compression Delta zeta = (F / C_H)^(2/3), m, for F >= 0.

    Parameters
    ----------
    force : array_like
        F_n >= 0, N.
    constant : float
        C_H, N/m^1.5.

    Returns
    -------
    ndarray
        Delta zeta in m (77.07 um at 65 kN with the paper's values).

    Raises
    ------
    WheelrailError
        If ``force`` is not finite numbers >= 0 or ``constant`` not a positive number.

    See Also
    --------
    hertz_force

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_approach, hertz_constant
    >>> round(float(hertz_approach(65e3, hertz_constant())) * 1e6, 2)   # um
    77.07
    """
    force = finite_array("hertz_approach: force", force, "N")
    constant = checks.positive("hertz_approach", "constant", constant, "N/m^1.5")
    if np.any(force < 0.0):
        raise WheelrailError(f"hertz_approach: force must be >= 0 N, got minimum {force.min()!r}")
    return (force / constant) ** (2.0 / 3.0)
