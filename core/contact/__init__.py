"""Contact models of paper section 2.3: Hertz spring, Winkler bedding, 3D elastic half-space, prefilters.

Sign convention throughout (z positive downwards into the rail, as in the paper): the approach
delta = xi_W - xi_R is positive when wheel and rail are pressed together; the combined roughness
r = r_W - r_R is positive when it pushes the surfaces together; the 3D gap is h = z_R - z_W - r, positive
where the surfaces are apart. All quantities are SI.
"""

import importlib

from wheelrail.core.contact.hertz import hertz_approach, hertz_force, hertz_stiffness

# The rest is imported on first use of one of its names: ``parameters.ContactParameters`` imports Hertz's
# solution from ``contact.hertz`` (so this package must not import ``parameters`` on the way), and the 3D
# half-space's ~20 compiled functions would cost a run of a one-line model numba's set-up at start.
_LAZY = {
    "HalfSpaceWindow": "window",
    "NormalContactResult": "window",
    "influence_kernel": "influence",
    "solve_coupled_contact": "window",
    "solve_normal_contact": "window",
    "hertz_constant": "hertz_model",
    "average_roughness": "prefilter",
    "averaging_weights": "prefilter",
    "winkler_equivalent_roughness": "prefilter",
    "WinklerContact": "winkler",
    "bedding_stiffness": "winkler",
    "wheel_profile": "winkler",
    "winkler_contact": "winkler",
}


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
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
