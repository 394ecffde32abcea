"""2D Winkler bedding between wheel and rail (paper section 2.3.1, eqs. 3-6; Ford & Thompson).

Sign convention (z positive downwards into the rail, as in the paper)
---------------------------------------------------------------------
For the wheel centre at x, the spring at x' (relative to the wheel centre) is compressed by eq. (3)

    Delta zeta(x') = delta + r(x') - x'^2 / (2 R_m),      delta = xi_W - xi_R,

where ``r = r_W - r_R`` is the combined roughness under the wheel (r_W and r_R positive downwards, so a
positive r pushes the surfaces together: a bump on the wheel, r_W > 0, or on the rail, r_R < 0) and
``z_W(x') = -x'^2 / (2 R_m)`` is the wheel profile with the modified radius R_m = R / 2 of eq. (6).
Springs with Delta zeta < 0 carry nothing; the others have the stiffness per unit length
k = E / (2 (1 - nu^2)) of eq. (5). The force of eq. (4) is integrated with one spring per roughness
sample (midpoint rule on the grid of spacing dx):

    F = k dx sum(max(Delta zeta_j, 0)),   dF/d delta = k dx n_c,   contact length = n_c dx,

with n_c the number of compressed springs. For smooth surfaces the continuous bedding gives exactly
Hertz: F = (4/3) k sqrt(2 R_m) delta^1.5 = C_H delta^1.5 and contact length 2 sqrt(R delta) = 2a.

Elliptic patches (``calibrated_bedding``): Ford & Thompson's criterion, which the paper takes from them
(2006) for eq. 6 (choose the bedding so that, on smooth surfaces, contact length, load and deflection are
Hertz's; stated there for the circle), applied to an ellipse, the elliptic Hertz contact of
``ContactParameters.hertz`` (the extension is this project's): its semi-axis along the rail grows as
a = sqrt(rho_x delta) and its load as F = C delta^1.5, so 2 R_m = rho_x and (4/3) k sqrt(rho_x) = C, i.e.
R_m = rho_x / 2, k = 3 C / (4 sqrt(rho_x)). Both laws go as delta^1.5 and a as delta^0.5, so the continuous
bedding then equals Hertz at every approach, not only at the preload (load-approach slope included); what
is left is the midpoint rule on the 1 mm grid, as for the circle: over approaches of 40-150 um at most
1.56 % from C delta^1.5 for the paper's circle, 1.00 % for 0.46 m on 0.30 m (with a cylindrical, concave or
convex tread) and 2.78 % for a 0.2 m wheel on a 0.8 m crown, whose shorter patch spans fewer springs
(``validation/contact_geometry_accuracy.py``; ``tests/physics/test_contact_geometry.py`` bounds it at 2 % for
the first two). The circle gives back eqs. 5-6 exactly (rho_x = R, k = E*).

The ``_``-prefixed numba kernels are for the time-stepping loop (no checks); the public functions check.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import positive as _positive
from wheelrail.core.models import ContactModel, LawInputs, ModelInputs
from wheelrail.core.parameters import ContactParameters, reduced_modulus

__all__ = [
    "BeddingModel",
    "WinklerContact",
    "bedding_stiffness",
    "checked_contact",
    "calibrated_bedding",
    "wheel_profile",
    "winkler_contact",
]


@dataclass(frozen=True, eq=False)
class WinklerContact:
    """Result of :func:`winkler_contact` (arrays of the shape of ``approach``).

    Attributes
    ----------
    force : ndarray
        F_n of eq. (4), N.
    contact_length : ndarray
        Length of the compressed part of the bedding, n_c dx, m.
    stiffness : ndarray
        dF/d delta = k dx n_c, N/m (the Newton derivative; piecewise constant in delta).
    """

    force: np.ndarray
    contact_length: np.ndarray
    stiffness: np.ndarray


@njit(cache=True)
def _winkler_force(approach, roughness, profile, stiffness_dx):
    """Bedding force of eqs. (3)-(5) for one wheel position.

    approach : delta, m; roughness : r(x'_j) under the wheel, m; profile : x'_j^2 / (2 R_m), m;
    stiffness_dx : k dx, N/m. Returns (force N, dF/d delta N/m, number of compressed springs,
    True if an end spring of the segment is compressed).
    """
    force = 0.0
    count = 0
    m = roughness.shape[0]
    for j in range(m):
        compression = approach + roughness[j] - profile[j]
        if compression > 0.0:
            force += compression
            count += 1
    edge = (approach + roughness[0] - profile[0] > 0.0) or (approach + roughness[m - 1] - profile[m - 1] > 0.0)
    return stiffness_dx * force, stiffness_dx * count, count, edge


@njit(cache=True, inline="always")
def bedding_law(approach_known, compliance, roughness, profile, stiffness_dx, element_size):
    """The interaction loop's bedding law: solve delta + c F(delta) = delta_known (eqs. 3-5 coupled with
    delta = delta_known - c F). F is piecewise linear and convex in delta: Newton from delta = delta_known.

    Returns (F N, contact length n_c dx m, area NaN (a line model has none), True if an end spring of the
    bedding is compressed: the contact reached the end of the window and the answer is not valid).
    """
    delta = approach_known
    force, stiffness, count, edge = _winkler_force(delta, roughness, profile, stiffness_dx)
    for _ in range(200):
        residual = delta + compliance * force - approach_known
        if residual <= 1e-18 * (abs(approach_known) + 1e-9) and residual >= -1e-18:
            break
        delta -= residual / (1.0 + compliance * stiffness)
        force, stiffness, count, edge = _winkler_force(delta, roughness, profile, stiffness_dx)
    return force, count * element_size, math.nan, edge


def calibrated_bedding(contact) -> tuple[float, float]:
    """(k, R) of the bedding for a ``ContactParameters``: stiffness per unit length k (N/m^2) and the radius R
    whose half is the modified radius R_m of eq. 6 (m). The paper's circle: (E*, R), eqs. 5-6 exactly; an
    elliptic patch: (3 C / (4 sqrt(rho_x)), rho_x), the module docstring's rule."""
    if contact.circular:
        return bedding_stiffness(contact), contact.radius_along
    rho_x, _ = contact.patch_radii()
    return 3.0 * contact.hertz_constant / (4.0 * math.sqrt(rho_x)), rho_x


@njit(cache=True)
def bedding_approach(values, k_dx, load):
    """Approach delta with k_dx * sum(max(delta + s_j, 0)) = load, exactly (the force is piecewise linear).

    values : s_j = r_j - x'_j^2 / (2 R_m), m. Returns (delta, count of springs in contact).
    """
    order = np.argsort(-values)
    target = load / k_dx
    total = 0.0
    m = values.shape[0]
    for count in range(1, m + 1):
        total += values[order[count - 1]]
        # with the `count` highest springs compressed: count * delta + total = target
        delta = (target - total) / count
        if count == m or delta + values[order[count]] <= 0.0:
            return delta, count
    return (target - total) / m, m


class BeddingModel(ContactModel):
    """``2d``: the Winkler bedding of 2 half_x + 1 springs under the wheel on the chosen line
    (:func:`calibrated_bedding`: the paper's eqs. 5-6, or its calibration for an elliptic patch)."""

    def prepare(self, inputs: ModelInputs) -> float:
        contact = inputs.params.contact
        dx, half = inputs.element_size, inputs.half_x
        stiffness, radius = calibrated_bedding(contact)
        profile = wheel_profile(2 * half + 1, dx, radius)
        k_dx = stiffness * dx
        line = inputs.centre_line
        self.equivalent_line = line
        offsets = np.arange(-half, half + 1)
        window = np.ascontiguousarray(line[inputs.start_index[:, None] + offsets[None, :]] * inputs.ramp[:, None])
        self._law = LawInputs(roughness=window, shape=profile, constants=np.array([k_dx, dx]))
        self._half, self._dx, self._position_of = half, dx, inputs.position_of
        delta, _ = bedding_approach(-profile, k_dx, contact.preload)
        return float(delta)

    def law_inputs(self) -> LawInputs:
        return self._law

    def edge_message(self, s: int) -> str:
        return (
            f"2d: the contact reaches the end of the {2 * self._half + 1}-element bedding at "
            f"x = {self._position_of(s):.4f} m (roughness too large for the "
            f"+-{self._half * self._dx * 1e3:.0f} mm bedding)"
        )


def checked_contact(where: str, contact) -> ContactParameters:
    """``contact``, or ``ContactParameters()`` (the paper's case) for None; one WheelrailError naming ``where``
    for anything else."""
    if contact is None:
        return ContactParameters()
    if not isinstance(contact, ContactParameters):
        raise WheelrailError(f"{where}: contact must be ContactParameters, got {type(contact).__name__}")
    return contact


def bedding_stiffness(contact: ContactParameters | None = None) -> float:
    """Stiffness per unit length of the bedding, k = E / (2 (1 - nu^2)) of eq. (5), N/m^2.

    Parameters
    ----------
    contact : ContactParameters, optional
        The material (E, nu); default ``ContactParameters()`` (steel).

    Returns
    -------
    float
        k in N/m per m of bedding (= E*, Pa).

    Raises
    ------
    WheelrailError
        If ``contact`` is not ContactParameters.

    See Also
    --------
    calibrated_bedding : the bedding of an elliptic patch.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eq. (5).

    Examples
    --------
    >>> from wheelrail.core.contact import bedding_stiffness
    >>> f"{bedding_stiffness():.4g}"
    '1.154e+11'
    """
    contact = checked_contact("bedding_stiffness", contact)
    return reduced_modulus(contact.youngs_modulus, contact.poisson_ratio)


def wheel_profile(n_samples: int, element_size: float, radius: float) -> np.ndarray:
    """Height of the wheel above its lowest point at the bedding springs, x'^2 / (2 R_m), R_m = R / 2.

    Parameters
    ----------
    n_samples : int
        Number of springs (>= 3); spring j sits at x'_j = (j - (n_samples - 1) / 2) dx.
    element_size : float
        dx, m.
    radius : float
        R (not R_m), m (``calibrated_bedding``'s radius; the paper's 0.39 m); the modified radius R_m = R / 2
        of eq. (6) is applied here.

    Returns
    -------
    ndarray, shape (n_samples,)
        -z_W(x'_j) in m.

    Raises
    ------
    WheelrailError
        If ``n_samples`` is not an integer >= 3 or a length is not a positive number.
    """
    where = "wheel_profile"
    if isinstance(n_samples, bool) or not isinstance(n_samples, int | np.integer) or n_samples < 3:
        raise WheelrailError(f"{where}: n_samples must be an integer >= 3, got {n_samples!r}")
    element_size = _positive(where, "element_size", element_size, "m")
    radius = _positive(where, "radius", radius, "m")
    x = (np.arange(n_samples) - (n_samples - 1) / 2.0) * element_size
    return x**2 / (2.0 * (radius / 2.0))


def winkler_contact(
    approach, roughness, element_size: float, contact: ContactParameters | None = None
) -> WinklerContact:
    """Force, contact length and dF/d delta of the Winkler bedding, eqs. (3)-(6).

    Parameters
    ----------
    approach : float or array_like
        delta = xi_W - xi_R, m (positive = wheel pressed into the rail).
    roughness : array_like, shape (m,)
        Combined roughness r = r_W - r_R under the wheel, m, sampled every ``element_size`` and centred
        on the wheel (sample j at x'_j = (j - (m - 1) / 2) dx). Must be long enough that the end springs
        stay uncompressed (the integration domain [-a', a'] of eq. 4).
    element_size : float
        dx, m (1e-3 in the paper).
    contact : ContactParameters, optional
        Material and radii; default ``ContactParameters()``. The bedding is :func:`calibrated_bedding`'s
        (eqs. 5-6 exactly for the paper's circle: k = E*, R_m = R / 2).

    Returns
    -------
    WinklerContact
        force (N), contact_length (m), stiffness (N/m), each of the shape of ``approach``.

    Raises
    ------
    WheelrailError
        On bad input, or if the contact reaches the end of the roughness segment.

    See Also
    --------
    wheelrail.core.contact.prefilter.winkler_equivalent_roughness : the bedding as a pre-filter.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eqs. (3)-(6).

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.contact import winkler_contact
    >>> result = winkler_contact(77e-6, np.zeros(41), 1e-3)
    >>> round(float(result.force) / 1e3, 1), round(float(result.contact_length) * 1e3)   # kN, mm
    (65.2, 11)
    """
    where = "winkler_contact"
    delta = np.asarray(approach, dtype=float) if _numeric(approach) else None
    if delta is None or not np.all(np.isfinite(delta)):
        raise WheelrailError(f"{where}: approach must be finite numbers in m, got {approach!r}")
    r = checked_roughness(where, roughness)
    element_size = _positive(where, "element_size", element_size, "m")
    stiffness, radius = calibrated_bedding(checked_contact(where, contact))
    k_dx = stiffness * element_size
    profile = wheel_profile(r.size, element_size, radius)
    force = np.empty(delta.shape)
    stiffness = np.empty(delta.shape)
    length = np.empty(delta.shape)
    for i, value in np.ndenumerate(delta):
        f, s, count, edge = _winkler_force(float(value), r, profile, k_dx)
        if edge:
            raise WheelrailError(
                f"{where}: contact reaches the end of the {r.size}-sample roughness segment at approach "
                f"{float(value):.4g} m; pass a longer segment"
            )
        force[i], stiffness[i], length[i] = f, s, count * element_size
    return WinklerContact(force=force, contact_length=length, stiffness=stiffness)


def _numeric(value) -> bool:
    try:
        np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def checked_roughness(where: str, roughness) -> np.ndarray:
    if not _numeric(roughness):
        raise WheelrailError(f"{where}: roughness must be a 1D array of numbers in m")
    r = np.ascontiguousarray(roughness, dtype=float)
    if r.ndim != 1 or r.size < 3:
        raise WheelrailError(f"{where}: roughness must be a 1D array of at least 3 samples, got shape {r.shape}")
    if not np.all(np.isfinite(r)):
        raise WheelrailError(
            f"{where}: roughness must be finite (m), got a NaN or infinity at sample {int(np.argmin(np.isfinite(r)))}"
        )
    return r
