"""Small helpers shared by the sub-commands: JSON output and unit conversion at the edge."""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

from wheelrail.core.errors import WheelrailError


def speed_from_kmh(speed_kmh: float, option: str = "--speed-kmh") -> float:
    """Convert a speed given in km/h on the command line to m/s, rejecting nonsense."""
    if not math.isfinite(speed_kmh) or speed_kmh <= 0:
        raise WheelrailError(f"{option} must be a positive speed in km/h, got {speed_kmh}")
    from wheelrail.core.parameters import KMH

    return speed_kmh * KMH


_GEOMETRY_OPTIONS = {"wheel_radius_mm": "wheel_radius", "rail_crown_radius_mm": "rail_crown_radius",
                     "wheel_transverse_radius_mm": "wheel_transverse_radius"}


def add_geometry_options(parser, *, crown_follows_wheel: bool = False) -> None:
    """The contact-geometry options of ``run``, ``study`` and ``filters`` (read back by :func:`geometry_from_mm`);
    their defaults, named in the help, are ``ContactParameters``'. ``crown_follows_wheel``: the command takes an
    unset crown radius as the wheel radius (``filters``: a circular patch, as the CNOSSOS table assumes)."""
    from wheelrail.core.parameters import ContactParameters

    radius_mm = ContactParameters().radius * 1e3
    crown = "the wheel radius, a circle" if crown_follows_wheel else f"{radius_mm:g}: the paper's R"
    parser.add_argument("--wheel-radius-mm", type=float, default=None,
                        help=f"wheel rolling radius, along the rail, mm (default {radius_mm:g}: the paper's R)")
    parser.add_argument("--rail-crown-radius-mm", type=float, default=None,
                        help=f"rail head (crown) radius across the rail, mm (default {crown})")
    parser.add_argument("--wheel-transverse-radius-mm", type=float, default=None,
                        help="wheel tread radius across the rail, mm (default: a cylindrical tread; negative: "
                             "concave, worn)")


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


def same_file(a, b) -> bool:
    """Whether paths ``a`` and ``b`` name the same file (any spelling, links followed)."""
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet): compare where they would be
        return Path(a).resolve() == Path(b).resolve()


def input_files(*names) -> list[Path]:
    """The arguments that name existing files (a roughness set may also be a bundled name)."""
    return [Path(name) for name in names if name is not None and Path(name).is_file()]


def writable_output(path: str, option: str, suffix: str | None = None, inputs=()) -> Path:
    """Check, before any work, that ``path`` can be written and is none of ``inputs``.

    Its name ends in ``suffix`` when given, it is not a folder nor the same file as one of ``inputs``
    (an output written over its own input would destroy it), and a file can be created in its folder
    (tried with a temporary file, so /proc or a read-only mount fails now, not after the run).
    Returns it as a Path; else a one-line WheelrailError.
    """
    from wheelrail.core.atomic import temporary_beside

    target = Path(path)
    if suffix is not None and target.suffix.lower() != suffix:
        raise WheelrailError(f"{option} {path}: the file name must end in {suffix}")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise WheelrailError(f"{option} {path}: folder {folder} does not exist")
    if target.is_dir():
        raise WheelrailError(f"{option} {path} is a folder; give a file name")
    for source in inputs:
        if same_file(target, source):
            raise WheelrailError(f"{option} {path} is the input file {source}: writing it would destroy the "
                                 "input; choose another output name")
    try:
        temporary_beside(target).unlink()
    except OSError as error:
        raise WheelrailError(f"{option} {path}: cannot write in folder {folder} ({error.strerror})") from None
    return target


def print_json(summary: dict) -> None:
    """Print a machine-readable summary on stdout (SI units; non-SI keys carry their unit; NaN as null)."""
    from wheelrail.core.jsonready import json_ready

    json.dump(json_ready(summary), sys.stdout, indent=2)
    sys.stdout.write("\n")
