"""Discrete irregularities (a wheel flat, a rail joint, a dipped weld, a squat): their geometry, the surface
deviation they add to the roughness, and the wheel-centre trajectory a rigid wheel follows over them.

``shapes``: the four as validated dataclasses and their check against a run. ``surface``: the deviation on the
3D model's lines and on the running line (the "raw" profile). ``trajectory``: the rigid wheel's envelope, what
the Hertz models are to be driven by. The method: the documentation's physics page, "Discrete irregularities".
"""

from wheelrail.core.irregularities.shapes import (
    FLAT_SHAPES,
    RAILHEAD_HALF_WIDTH,
    DippedWeld,
    RailJoint,
    Squat,
    WheelFlat,
    check_irregularities,
    flat_depth,
    flat_meetings,
)
from wheelrail.core.irregularities.surface import raw_profile, surface_deviation
from wheelrail.core.irregularities.trajectory import wheel_centre_trajectory

__all__ = [
    "FLAT_SHAPES",
    "RAILHEAD_HALF_WIDTH",
    "DippedWeld",
    "RailJoint",
    "Squat",
    "WheelFlat",
    "check_irregularities",
    "flat_depth",
    "flat_meetings",
    "raw_profile",
    "surface_deviation",
    "wheel_centre_trajectory",
]
