"""Influence coefficients of the 3D half-space contact model, eq. (8) of the paper (Boussinesq-Love kernel).

Uniform pressure on a rectangle (Love's solution, Johnson, *Contact Mechanics*, eq. 3.25): the combined
normal displacement of two bodies of the same material is

    u(x, y) = 1 / (pi E*) * integral over the element of p / rho dA,    E* = E / (2 (1 - nu^2)),

i.e. twice the single-body value (1 - nu^2) / (pi E). The matrix C of u = C p is block-Toeplitz (it only
depends on the offset between two elements), so only the kernel of offsets (2 ny - 1, 2 nx - 1) is stored
and cached per (shape, element size, material). E* comes from :func:`wheelrail.core.parameters.reduced_modulus`.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import positive as _positive
from wheelrail.core.parameters import ContactParameters, reduced_modulus

__all__ = ["influence_kernel"]


def _rect_integral(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Antiderivative of 1/sqrt(x^2 + y^2) in x and y: x asinh(y/|x|) + y asinh(x/|y|) (0 on the axes).

    This is x ln(y + rho) + y ln(x + rho) less terms in x or y alone, which cancel in the corner sum.
    """
    ax = np.where(x != 0.0, np.abs(x), 1.0)
    ay = np.where(y != 0.0, np.abs(y), 1.0)
    first = np.where(x != 0.0, x * np.arcsinh(y / ax), 0.0)
    second = np.where(y != 0.0, y * np.arcsinh(x / ay), 0.0)
    return first + second


@functools.lru_cache(maxsize=32)
def _cached_kernel(ny: int, nx: int, element_size: float, youngs_modulus: float, poisson_ratio: float):
    half = 0.5 * element_size
    oy = np.arange(-(ny - 1), ny, dtype=float)[:, None] * element_size
    ox = np.arange(-(nx - 1), nx, dtype=float)[None, :] * element_size
    # Johnson eq. 3.25 (Love): integral of 1/rho over the element centred at offset (ox, oy)
    integral = (
        _rect_integral(ox + half, oy + half)
        - _rect_integral(ox + half, oy - half)
        - _rect_integral(ox - half, oy + half)
        + _rect_integral(ox - half, oy - half)
    )
    kernel = np.ascontiguousarray(integral / (math.pi * reduced_modulus(youngs_modulus, poisson_ratio)))
    kernel.setflags(write=False)
    return kernel


def influence_kernel(
    shape: tuple[int, int], element_size: float, contact: ContactParameters | None = None
) -> np.ndarray:
    """Influence coefficients of eq. (8) as a kernel of element offsets (Johnson eq. 3.25).

    Parameters
    ----------
    shape : (int, int)
        Window size (ny, nx) in elements.
    element_size : float
        Side of the square elements, m.
    contact : ContactParameters, optional
        The material E (Pa) and nu of both bodies; default ``ContactParameters()`` (steel).

    Returns
    -------
    ndarray, shape (2 ny - 1, 2 nx - 1), read-only
        ``K[dy + ny - 1, dx + nx - 1]`` is the combined normal displacement (m) at an element centre per
        unit uniform pressure (Pa) on an element offset by (dy, dx) elements, m/Pa. Cached per arguments.

    Raises
    ------
    WheelrailError
        If the shape is not two positive integers, the element size not a positive number or ``contact`` not
        ContactParameters.

    See Also
    --------
    wheelrail.core.contact.window.HalfSpaceWindow : solves eqs. (8)-(11) with this kernel.

    Notes
    -----
    For uniform pressure on a square of side s the displacement at its centre is 4 s asinh(1) / (pi E*)
    (two bodies, E* = E / (2 (1 - nu^2))).

    References
    ----------
    K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985, eq. (3.25).

    Examples
    --------
    >>> from wheelrail.core.contact import influence_kernel
    >>> kernel = influence_kernel((3, 3), 1e-3)
    >>> kernel.shape, f"{kernel[2, 2]:.4e}"
    ((5, 5), '9.7257e-15')
    """
    ny, nx = (int(shape[0]), int(shape[1]))
    if ny < 1 or nx < 1:
        raise WheelrailError(f"influence_kernel: shape must be two positive integers, got {shape!r}")
    element_size = _positive("influence_kernel", "element_size", element_size, "m")
    contact = ContactParameters() if contact is None else contact
    if not isinstance(contact, ContactParameters):
        raise WheelrailError(f"influence_kernel: contact must be ContactParameters, got {type(contact).__name__}")
    return _cached_kernel(ny, nx, element_size, float(contact.youngs_modulus), float(contact.poisson_ratio))
