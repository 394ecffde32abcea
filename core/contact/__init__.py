"""Contact models of paper section 2.3: Hertz spring, Winkler bedding, 3D elastic half-space, prefilters.

Sign convention throughout (z positive downwards into the rail, as in the paper): the approach
delta = xi_W - xi_R is positive when wheel and rail are pressed together; the combined roughness
r = r_W - r_R is positive when it pushes the surfaces together; the 3D gap is h = z_R - z_W - r, positive
where the surfaces are apart. All quantities are SI.
"""

from wheelrail.core.contact.hertz import hertz_approach, hertz_constant, hertz_force, hertz_stiffness
from wheelrail.core.contact.prefilter import average_roughness, averaging_weights, winkler_equivalent_roughness
from wheelrail.core.contact.winkler import WinklerContact, bedding_stiffness, wheel_profile, winkler_contact

# The 3D half-space (its solver: ~20 compiled functions, whose set-up by numba a run of a one-line model
# would pay at start) is imported on first use of one of its names.
_HALFSPACE = (
    "HalfSpaceWindow",
    "NormalContactResult",
    "influence_kernel",
    "solve_coupled_contact",
    "solve_normal_contact",
)


def __getattr__(name: str):
    if name in _HALFSPACE:
        from wheelrail.core.contact import window

        return getattr(window, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "HalfSpaceWindow",
    "NormalContactResult",
    "WinklerContact",
    "average_roughness",
    "averaging_weights",
    "bedding_stiffness",
    "hertz_approach",
    "hertz_constant",
    "hertz_force",
    "hertz_stiffness",
    "influence_kernel",
    "solve_coupled_contact",
    "solve_normal_contact",
    "wheel_profile",
    "winkler_contact",
    "winkler_equivalent_roughness",
]
