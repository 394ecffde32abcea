"""Small helpers shared by the sub-commands: JSON output and unit conversion at the edge."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from wheelrail.core.accepted import ACCEPTED, PATCH_FRACTION
from wheelrail.core.errors import Name, WheelrailError

# What the command line calls each input an error can name (WheelrailError.parameter): its option, the unit it
# takes and that unit per SI unit. ``wheelrail.core.cli`` renders every error with it, so core's messages never
# name an option and nothing rewrites them.
CLI_NAMES: dict[str, Name] = {
    "speed": Name("--speed-kmh", "km/h", 3.6, True),
    "preload": Name("--preload-kn", "kN", 1e-3, True),
    "wheel_radius": Name("--wheel-radius-mm", "mm", 1e3, True),
    "radius": Name("--wheel-radius-mm", "mm", 1e3, True),  # the paper's R: the wheel's, as the CLI sets it
    "rail_crown_radius": Name("--rail-crown-radius-mm", "mm", 1e3, True),
    "wheel_transverse_radius": Name("--wheel-transverse-radius-mm", "mm", 1e3, True),
    "length": Name("--length-m", "m", 1.0, True),
    "line": Name("--line", unit_in_label=True),
    "skip": Name("--skip-ms", "ms", 1e3, True),
    "record_every": Name("--record-every", unit_in_label=True),
    "connect": Name("--connect", unit_in_label=True),
    "dask": Name("--dask", unit_in_label=True),
    "workers": Name("--workers", unit_in_label=True),
    "model": Name("--model", unit_in_label=True),
    "set": Name("--set", unit_in_label=True),
    "wheel_set": Name("--wheel-set", unit_in_label=True),
    "wheel_diameter": Name("--wheel-diameter-mm", "mm", 1e3, True),  # wheelrail noise
    "axles": Name("--axles", unit_in_label=True),
    "train_axles": Name("--train-axles", unit_in_label=True),
    "train_length": Name("--train-length-m", "m", 1.0, True),
}


def accepted_help(key: str) -> str:
    """An input's accepted range in the command line's unit, for its help: "accepted 5 to 400"."""
    name = CLI_NAMES[key]
    low, high = ACCEPTED[key].in_unit(name.scale)
    return f"accepted {low:g} to {high:g}"


def speed_from_kmh(speed_kmh: float) -> float:
    """A speed given in km/h on the command line, in m/s, within the accepted range (``core.accepted``)."""
    from wheelrail.core.parameters import KMH

    return ACCEPTED["speed"].check(speed_kmh * KMH, "speed")


def add_speed_option(parser, help_text: str = "train speed, km/h") -> None:
    """``--speed-kmh``, default 100 (the paper's), its accepted range in the help."""
    parser.add_argument(
        "--speed-kmh", type=float, default=100.0, help=f"{help_text} (default 100; {accepted_help('speed')})"
    )


def add_preload_option(parser) -> None:
    """``--preload-kn``, default ``ContactParameters().preload``, its accepted range in the help."""
    from wheelrail.core.parameters import ContactParameters

    preload_kn = ContactParameters().preload / 1e3
    parser.add_argument(
        "--preload-kn",
        type=float,
        default=preload_kn,
        help=f"static wheel load, kN (default {preload_kn:g}; {accepted_help('preload')})",
    )


_GEOMETRY_OPTIONS = {
    "wheel_radius_mm": "wheel_radius",
    "rail_crown_radius_mm": "rail_crown_radius",
    "wheel_transverse_radius_mm": "wheel_transverse_radius",
}


def add_geometry_options(parser, *, crown_follows_wheel: bool = False) -> None:
    """The contact-geometry options of ``run``, ``study`` and ``filters`` (read back by :func:`geometry_from_mm`);
    their defaults and ranges, named in the help, are ``ContactParameters``' and ``core.accepted``'s.
    ``crown_follows_wheel``: the command takes an unset crown radius as the wheel radius (``filters``: a
    circular patch, as the CNOSSOS table assumes)."""
    from wheelrail.core.parameters import ContactParameters

    radius_mm = ContactParameters().radius * 1e3
    crown = "the wheel radius, a circle" if crown_follows_wheel else f"{radius_mm:g}: the paper's R"
    tread_mm = ACCEPTED["wheel_transverse_radius"].minimum * 1e3
    parser.add_argument(
        "--wheel-radius-mm",
        type=float,
        default=None,
        help=f"wheel rolling radius, along the rail, mm (default {radius_mm:g}: the paper's R; "
        f"{accepted_help('wheel_radius')})",
    )
    parser.add_argument(
        "--rail-crown-radius-mm",
        type=float,
        default=None,
        help=f"rail head (crown) radius across the rail, mm (default {crown}; {accepted_help('rail_crown_radius')})",
    )
    parser.add_argument(
        "--wheel-transverse-radius-mm",
        type=float,
        default=None,
        help=f"wheel tread radius across the rail, mm (default: a cylindrical tread; negative: "
        f"concave, worn; at least {tread_mm:g} in magnitude; the Hertz patch at the preload "
        f"must stay within {PATCH_FRACTION * 100:g} %% of the radii)",
    )


def geometry_from_mm(args) -> dict:
    """``ContactParameters`` geometry keywords (m) from the ``--wheel-radius-mm``, ``--rail-crown-radius-mm`` and
    ``--wheel-transverse-radius-mm`` options a command has (unset ones omitted: the paper's defaults). Their
    ranges are checked by ``ContactParameters``, whose errors the command line words with ``CLI_NAMES``."""
    return {
        name: getattr(args, option) * 1e-3
        for option, name in _GEOMETRY_OPTIONS.items()
        if getattr(args, option, None) is not None
    }


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

    if not str(path).strip():  # Path("") is the current folder: an empty option would write nothing, silently
        raise WheelrailError(f"{option} is empty; give a file name")
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
            raise WheelrailError(
                f"{option} {path} is the input file {source}: writing it would destroy the "
                "input; choose another output name"
            )
    try:
        temporary_beside(target).unlink()
    except OSError as error:
        raise WheelrailError(f"{option} {path}: cannot write in folder {folder} ({error.strerror})") from None
    return target


def print_json(summary: dict) -> None:
    """Print a machine-readable summary on stdout (SI units; non-SI keys carry their unit; NaN as null)."""
    from wheelrail.core.jsonready import strict_json

    sys.stdout.write(strict_json(summary, indent=2))
    sys.stdout.write("\n")
