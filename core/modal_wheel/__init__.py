"""The modal wheel: a solid wheel's cross-section, its axisymmetric finite-element modes, receptances at the
contact and the surface velocities its radiation needs (``profile``, ``mesh``, ``fem``, ``modes``,
``receptance``). The paper's 2-DOF wheel (``wheelrail.core.wheel``) stays the interaction's default."""

from wheelrail.core.modal_wheel.fem import FAMILIES, STEEL, Material
from wheelrail.core.modal_wheel.modes import WheelModes, modal_loss_factor, wheel_modes
from wheelrail.core.modal_wheel.profile import (
    NAMED_WHEELS,
    OutlineProfile,
    WheelProfile,
    describe_wheel,
    named_profile,
    outline_profile,
    profile_from_description,
    read_outline,
    section_mass,
    wheel_profile_for,
)
from wheelrail.core.modal_wheel.receptance import (
    SurfaceVelocity,
    WheelReceptance,
    contact_receptance,
    mean_square_velocity,
)

__all__ = [
    "FAMILIES",
    "NAMED_WHEELS",
    "STEEL",
    "Material",
    "OutlineProfile",
    "SurfaceVelocity",
    "WheelModes",
    "WheelProfile",
    "WheelReceptance",
    "contact_receptance",
    "describe_wheel",
    "mean_square_velocity",
    "modal_loss_factor",
    "named_profile",
    "outline_profile",
    "profile_from_description",
    "read_outline",
    "section_mass",
    "wheel_modes",
    "wheel_profile_for",
]
