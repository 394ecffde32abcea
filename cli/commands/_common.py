"""Small helpers shared by the sub-commands: JSON output and unit conversion at the edge."""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from wheelrail.core.errors import Name, WheelrailError
from wheelrail.core.files.atomic import same_file
from wheelrail.core.inputs.contact_position import contact_position_cli_names
from wheelrail.core.inputs.declared import CHOICES, GROUPS, by_key, choice, cli_names, inputs_of
from wheelrail.core.inputs.ranges import ACCEPTED, PATCH_FRACTION

WHEEL_SHAPE_KEYS = tuple(k for k in ACCEPTED if k.startswith("wheel_") and k != "wheel_transverse_radius")
"""The modal wheel's profile inputs (``wheelrail wheel``): ``wheel_radius`` and the ``wheel_<field>`` ranges."""


def wheel_shape_option(key: str) -> str:
    """The option of a profile input: ``--wheel-radius-mm``, ``--tyre-width-mm`` (``wheel_tyre_width``), ..."""
    field = key if key == "wheel_radius" else key.removeprefix("wheel_")
    return f"--{field.replace('_', '-')}-mm"


# What the command line calls each input an error can name (WheelrailError.parameter): its option, the unit it
# takes and that unit per SI unit. The declared inputs' names come from their declaration
# (``wheelrail.core.inputs.declared``); the rest are the commands' own options. ``wheelrail.cli.dispatch`` renders every
# error with it, so core's messages never name an option and nothing rewrites them.
CLI_NAMES: dict[str, Name] = {
    **cli_names(),
    "radius": cli_names()["wheel_radius"],  # the paper's R: the wheel's, as the CLI sets it
    "length": Name("--length-m", "m", 1.0, True),
    "line": Name("--line", unit_in_label=True),
    "lines": Name("--lines", unit_in_label=True),  # wheelrail roughness: the lines averaged, the coherence's M, B
    "half_lines": Name("--m", unit_in_label=True),
    "blocks": Name("--blocks", unit_in_label=True),
    "skip": Name("--skip-ms", "ms", 1e3, True),
    "record_every": Name("--record-every", unit_in_label=True),
    "connect": Name("--connect", unit_in_label=True),
    "spawn": Name("--spawn", unit_in_label=True),
    "sound_power": Name("--sound-power", unit_in_label=True),
    "dask": Name("--dask", unit_in_label=True),
    "workers": Name("--workers", unit_in_label=True),
    "model": Name("--model", unit_in_label=True),
    "set": Name("--set", unit_in_label=True),
    "wheel_set": Name("--wheel-set", unit_in_label=True),
    "wheel_diameter": Name("--wheel-diameter-mm", "mm", 1e3, True),  # wheelrail noise
    "axles": Name("--axles", unit_in_label=True),
    "train_axles": Name("--train-axles", unit_in_label=True),
    "train_length": Name("--train-length-m", "m", 1.0, True),
    # wheelrail wheel: the modal wheel's shape (core.inputs.ranges' wheel_<field> ranges) and settings
    **{key: Name(wheel_shape_option(key), "mm", 1e3, True) for key in WHEEL_SHAPE_KEYS if key != "wheel_radius"},
    "wheel_name": Name("--wheel", unit_in_label=True),
    "outline": Name("--outline", unit_in_label=True),
    "contact_z": Name("--contact-z-mm", "mm", 1e3, True),
    "wheel_element_size": Name("--element-size-mm", "mm", 1e3, True),
    "max_frequency": Name("--max-frequency-hz", "Hz", 1.0, True),
    "max_harmonic": Name("--max-harmonic", unit_in_label=True),
    "added_loss_factor": Name("--added-loss-factor", unit_in_label=True),
    **{entry.key: Name(entry.option, unit_in_label=True) for entry in CHOICES},  # the declared choices
    **contact_position_cli_names(),  # wheelrail noise: the contact's lateral position (mm)
}


def cli_error_names() -> dict[str, Name]:
    """``CLI_NAMES`` with the declared inputs' names as declared now (``wheelrail.cli.dispatch`` words errors so)."""
    from wheelrail.core.inputs.irregular import irregularity_cli_names

    return {**CLI_NAMES, **cli_names(), **irregularity_cli_names()}


# an argument group's description is printed as written (not %-formatted, unlike an option's help)
_GEOMETRY_NOTE = f"the Hertz patch at the preload must stay within {PATCH_FRACTION * 100:g} % of the radii"


def accepted_help(key: str) -> str:
    """An input's accepted range in the command line's unit, for its help: "accepted 5 to 400"."""
    name = CLI_NAMES[key]
    low, high = ACCEPTED[key].in_unit(name.scale)
    return f"accepted {low:g} to {high:g}"


def speed_from_kmh(speed_kmh: float) -> float:
    """A speed given in km/h on the command line, in m/s, within the accepted range (``core.inputs.ranges``)."""
    entry = by_key("speed")
    return entry.check(speed_kmh * entry.shown.si, "speed")


def add_speed_option(parser, help_text: str | None = None) -> None:
    """The declared speed's option alone (``--speed-kmh``), for commands that take no other input;
    ``help_text`` instead of its declared help."""
    entry = by_key("speed")
    text = help_text or f"{entry.help}, {entry.shown.name}"
    parser.add_argument(
        entry.option,
        type=float,
        default=entry.shown_default(),
        help=f"{text} (default {entry.default_text()}; {_accepted_words(entry)})",
    )


RUN_INPUT_GROUPS = tuple(GROUPS)  # the declared input groups a run takes, and so each run of a study: all of them


def add_input_options(
    parser,
    *groups: str,
    helps: dict[str, str] | None = None,
    unset: dict[str, str] | None = None,
    several: tuple[str, ...] = (),
    leave_out: tuple[str, ...] = (),
) -> list:
    """The options of the declared inputs of ``groups`` (``wheelrail.core.inputs.declared.GROUPS``), one argparse group
    each, named, documented and ranged by their declaration; read back by :func:`params_from_args`.

    ``helps``: key -> the command's own help sentence for an input (its default and range are appended);
    ``unset``: key -> what the command takes an absent option as, where it differs from the declaration's;
    ``several``: groups whose options take one or more values (a sweep; a list in the namespace when given);
    ``leave_out``: keys of inputs the command has no use for (``filters`` makes no run: no element size).
    An option's default is its dataclass default in the option's unit (None where that is not a number).
    Returns the argparse actions added (their ``dest``, ``option_strings`` and ``default``)."""
    helps, unset = helps or {}, unset or {}
    added = []
    for group in groups:
        note = _GEOMETRY_NOTE if group == "geometry" else None
        options = parser.add_argument_group(f"{GROUPS[group].lower()} inputs", description=note)
        for entry in (e for e in inputs_of(group) if e.key not in leave_out):
            default = unset.get(entry.key) or entry.default_text()
            unit = f", {entry.shown.name}" if entry.shown.name else ""
            text = f"{helps.get(entry.key, entry.help + unit)} (default {default}; {_accepted_words(entry)})"
            nargs = "+" if group in several else None
            added.append(
                options.add_argument(entry.option, type=float, nargs=nargs, default=entry.shown_default(), help=text)
            )
    return added


def add_track_numerics_option(parser, *, frequency_domain: str | None = None):
    """``--track-numerics``: the track's numerics as comma-separated ``name=value`` pairs (declared once in
    ``wheelrail.core.inputs.numerics``); read back by :func:`track_numerics_from_args`. ``frequency_domain``: the
    mode of a command whose track is solved in the frequency domain ("--method twins"), which takes only the
    fields marked so. Returns the argparse action."""
    from wheelrail.core.inputs.numerics import NUMERICS_FIELDS, NUMERICS_OPTION

    fields = [entry for entry in NUMERICS_FIELDS if entry.frequency_domain or frequency_domain is None]
    names = "; ".join(f"{entry.name} ({entry.help}; {entry.accepted_text()})".replace("%", "%%") for entry in fields)
    what = (
        "the track's numerics, to check a result against finer ones (each change is a new one-off precompute "
        "of the track, longer for finer numerics; default the converged defaults of docs/validation.md)"
        if frequency_domain is None
        else f"{frequency_domain}: the track's numerics, to check a result against finer ones (default the "
        "converged defaults of docs/validation.md)"
    )
    return parser.add_argument(NUMERICS_OPTION, metavar="NAME=VALUE,...", default=None, help=f"{what}: {names}")


def track_numerics_from_args(args):
    """The ``TrackNumerics`` of ``--track-numerics`` (:func:`add_track_numerics_option`); the default when absent."""
    from wheelrail.core.inputs.numerics import parse_track_numerics

    return parse_track_numerics(getattr(args, "track_numerics", None))


def print_track_numerics(changes: dict) -> None:
    """The summary's line of the track numerics that differ from the default (``inputs.numerics.numerics_changes``),
    none when there are none."""
    from wheelrail.core.inputs.numerics import numerics_words

    if changes:
        print(f"  track numerics: {numerics_words(changes)} (the others the default)")


def add_irregularity_options(parser, several: bool = False) -> None:
    """The options of the discrete irregularities (``wheelrail.core.inputs.irregular``: each number declared once,
    with --flat-shape and --irregularity-input), one argparse group; read back by :func:`irregularities_from_args`.
    ``several``: each number takes one or more values (a sweep; a list in the namespace when given)."""
    from wheelrail.core.inputs.irregular import FLAT_SHAPE_HELP, IRREGULARITY_INPUTS
    from wheelrail.core.irregularities.shapes import FLAT_SHAPES

    options = parser.add_argument_group(
        "irregularity inputs",
        description="a wheel flat, a rail joint, a dipped weld and a squat, each on top of the roughness (by "
        "position; one of each at most); positions along the run in m, as the run's x",
    )
    for entry in IRREGULARITY_INPUTS:
        unit = f", {entry.shown.name}" if entry.shown.name else ""
        needed = "; needed for one" if entry.required else ""
        nargs = "+" if several else None
        options.add_argument(entry.option, type=float, nargs=nargs, default=None, help=f"{entry.help}{unit}{needed}")
    options.add_argument("--flat-shape", choices=FLAT_SHAPES, default=None, help=f"{FLAT_SHAPE_HELP} "
                         f"(default {FLAT_SHAPES[0]})")  # fmt: skip
    entry = choice("irregularity_input")
    options.add_argument(entry.option, choices=entry.values, default=entry.default, help=entry.help_text())


def irregularities_from_args(args, params):
    """``params`` with the irregularities and the irregularity input the command line gave
    (:func:`add_irregularity_options`), in SI; unchanged where none is given (cache keys stay the same)."""
    from dataclasses import replace

    from wheelrail.core.inputs.irregular import IRREGULARITY_INPUTS, irregularities_from_values

    values = {
        e.key: getattr(args, e.dest) * e.shown.si for e in IRREGULARITY_INPUTS if getattr(args, e.dest) is not None
    }
    items = irregularities_from_values(values, args.flat_shape)
    if not items and args.irregularity_input == choice("irregularity_input").default:
        return params
    return replace(params, run=replace(params.run, irregularities=items, irregularity_input=args.irregularity_input))


def add_choice_option(parser, key: str, help_prefix: str = "", option: str | None = None):
    """The option of a declared choice (``wheelrail.core.inputs.declared.CHOICES``): its values, default and help from
    the declaration; ``help_prefix`` says which mode uses it ("--method twins, --run: "); ``option``: the command's
    own name for it where the declared one means something else there (``run --noise-wheel-model``). Returns
    the argparse action added."""
    entry = choice(key)
    return parser.add_argument(
        option or entry.option, choices=entry.values, default=entry.default, help=help_prefix + entry.help_text()
    )


def _accepted_words(entry) -> str:
    low, high = entry.in_shown()
    return f"at least {low:g} in magnitude" if entry.accepted.magnitude else f"accepted {low:g} to {high:g}"


def given_inputs(args, *groups: str) -> list:
    """The declared inputs of ``groups`` whose option the command line set to other than its default."""
    found = []
    for entry in inputs_of(*groups):
        given = getattr(args, entry.dest, None)
        if given is not None and given != entry.shown_default():
            found.append(entry)
    return found


def params_from_args(args, *groups: str, base=None):
    """``ModelParameters`` with the declared inputs of ``groups`` the command line set (in their option's unit,
    converted to SI here) on ``base`` (default: the paper's). An option left at its default changes nothing
    (the parameters, and every cache key made of them, stay the dataclass's to the bit). A value outside its
    range is one WheelrailError keyed by the input, worded with the option by ``CLI_NAMES``."""
    from wheelrail.core.inputs.declared import model_parameters

    values = {entry.key: getattr(args, entry.dest) * entry.shown.si for entry in given_inputs(args, *groups)}
    return model_parameters(values, base)


def input_files(*names) -> list[Path]:
    """The arguments that name existing files (a roughness set may also be a bundled name; a list of them, as
    ``study --set`` repeated gives, counts each)."""
    flat = [name for given in names for name in (given if isinstance(given, list | tuple) else [given])]
    return [Path(name) for name in flat if name is not None and Path(name).is_file()]


@dataclass(frozen=True)
class Output:
    """An option naming a file a command writes.

    Attributes
    ----------
    dest : str
        The option's attribute in the parsed namespace (``csv``).
    option : str
        The option as typed (``--csv``).
    suffix : str, optional
        The ending its name must have (``.png``); None: any.
    beside : callable, optional
        ``beside(path)`` -> the files the command writes next to it under names derived from it (``wheel --csv
        r.csv`` also writes ``r_modes.csv``).
    """

    dest: str
    option: str
    suffix: str | None = None
    beside: Callable[[Path], tuple[Path, ...]] | None = None


@dataclass(frozen=True)
class Files:
    """The files a command reads (``reads``: namespace attributes naming input files, or bundled names, or lists
    of them) and writes (``writes``). A command module declares them as ``FILES``; the dispatcher checks them
    with :func:`check_files` before the command runs."""

    reads: tuple[str, ...] = ()
    writes: tuple[Output, ...] = ()


def check_files(args, files: Files) -> dict[str, Path]:
    """Check, before any work, every output a command was asked for against its inputs and each other.

    Each output (and each file it writes beside it) must be writable (:func:`writable_output`), must not be any
    input however either is spelled (:func:`same_file`: relative paths, ``..``, symbolic and hard links), and
    no two outputs may be the same file. Returns option dest -> its path, for the outputs given; else one
    WheelrailError naming the options and files.
    """
    inputs = input_files(*(getattr(args, dest, None) for dest in files.reads))
    targets: list[tuple[Path, str]] = []  # (file, how the command came to write it), in option order
    chosen = {}
    for output in files.writes:
        given = getattr(args, output.dest, None)
        if given is None:
            continue
        path = chosen[output.dest] = Path(given)
        targets.append((path, f"{output.option} {given}"))
        for derived in output.beside(path) if output.beside is not None else ():
            targets.append((derived, f"{derived} (written beside {output.option} {given})"))
    for number, (path, what) in enumerate(targets):
        for source in inputs:
            if same_file(path, source):
                raise WheelrailError(
                    f"{what} is the input file {source}: writing it would destroy the input; choose another output name"
                )
        for other, other_what in targets[:number]:
            if same_file(path, other):
                raise WheelrailError(f"{other_what} and {what} name the same file; give each output its own name")
    for output in files.writes:  # an input named first: the worse mistake than a wrong ending or folder
        if output.dest in chosen:
            writable_output(getattr(args, output.dest), output.option, output.suffix)
    return chosen


def writable_output(path: str, option: str, suffix: str | None = None, inputs=()) -> Path:
    """Check, before any work, that ``path`` can be written and is none of ``inputs``.

    Its name ends in ``suffix`` when given, it is not a folder nor the same file as one of ``inputs``
    (an output written over its own input would destroy it), and a file can be created in its folder
    (tried with a temporary file, so /proc or a read-only mount fails now, not after the run).
    Returns it as a Path; else a one-line WheelrailError.
    """
    from wheelrail.core.files.atomic import temporary_beside

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
        temporary_beside(target).unlink()  # its name says it is ours, should a kill -9 fall in between
    except OSError as error:
        raise WheelrailError(f"{option} {path}: cannot write in folder {folder} ({error.strerror})") from None
    return target


def print_json(summary: dict) -> None:
    """Print a machine-readable summary on stdout (SI units; non-SI keys carry their unit; NaN as null)."""
    from wheelrail.core.files.jsonready import strict_json

    sys.stdout.write(strict_json(summary, indent=2))
    sys.stdout.write("\n")
