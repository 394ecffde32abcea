"""Discrete irregularities (a wheel flat, a rail joint, a dipped weld, a squat): their geometry, the surface
deviation they add to the roughness, and the wheel-centre trajectory a rigid wheel follows over them.

``shapes``: the four as validated dataclasses and their check against a run. ``surface``: the deviation on the
3D model's lines and on the running line (the "raw" profile). ``trajectory``: the rigid wheel's envelope, what
the Hertz models are to be driven by. The method: the documentation's physics page, "Discrete irregularities".
``surface``'s and ``trajectory``'s functions load on first use (the trajectory is compiled: importing the shapes
alone loads no numba).
"""

from __future__ import annotations

import importlib

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

_LAZY = {"raw_profile": "surface", "surface_deviation": "surface", "wheel_centre_trajectory": "trajectory"}


def __getattr__(name: str):
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)


def __dir__() -> list[str]:
    return sorted(__all__)
