"""Small helpers shared by the sub-commands: JSON output and unit conversion at the edge."""

from __future__ import annotations

import json
import math
import sys

from wheelrail.core.errors import WheelrailError
from wheelrail.core.jsonready import json_ready
from wheelrail.core.parameters import KMH


def speed_from_kmh(speed_kmh: float, option: str = "--speed-kmh") -> float:
    """Convert a speed given in km/h on the command line to m/s, rejecting nonsense."""
    if not math.isfinite(speed_kmh) or speed_kmh <= 0:
        raise WheelrailError(f"{option} must be a positive speed in km/h, got {speed_kmh}")
    return speed_kmh * KMH


_GEOMETRY_OPTIONS = {"wheel_radius_mm": "wheel_radius", "rail_crown_radius_mm": "rail_crown_radius",
                     "wheel_transverse_radius_mm": "wheel_transverse_radius"}


def geometry_from_mm(args) -> dict:
    """``ContactParameters`` geometry keywords (m) from the ``--wheel-radius-mm``, ``--rail-crown-radius-mm`` and
    ``--wheel-transverse-radius-mm`` options a command has (unset ones omitted: the paper's defaults)."""
    geometry = {}
    for option, name in _GEOMETRY_OPTIONS.items():
        value = getattr(args, option, None)
        if value is None:
            continue
        flag = "--" + option.replace("_", "-")
        if not math.isfinite(value) or value == 0 or (value < 0 and name != "wheel_transverse_radius"):
            words = "a non-zero radius in mm (negative: concave)" if name == "wheel_transverse_radius" else (
                "a positive radius in mm")
            raise WheelrailError(f"{flag} must be {words}, got {value}")
        geometry[name] = value * 1e-3
    return geometry


def writable_output(path: str, option: str, suffix: str | None = None):
    """Check, before any work, that ``path`` can be written: its folder exists and is writable, and
    its name ends in ``suffix`` when given. Returns it as a Path; else a one-line WheelrailError."""
    import os
    from pathlib import Path

    target = Path(path)
    if suffix is not None and target.suffix != suffix:
        raise WheelrailError(f"{option} {path}: the file name must end in {suffix}")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise WheelrailError(f"{option} {path}: folder {folder} does not exist")
    if not os.access(folder, os.W_OK):
        raise WheelrailError(f"{option} {path}: folder {folder} is not writable")
    return target


def print_json(summary: dict) -> None:
    """Print a machine-readable summary on stdout (SI units; non-SI keys carry their unit; NaN as null)."""
    json.dump(json_ready(summary), sys.stdout, indent=2)
    sys.stdout.write("\n")
