"""``wheelrail study``: the paper's studies (Figs 10-14, 16, 17, 11), noise, tracks and impacts as batches of runs."""

from __future__ import annotations

import math
import sys
from dataclasses import replace

from wheelrail.cli.commands._common import (
    RUN_INPUT_GROUPS,
    Files,
    add_input_options,
    add_irregularity_options,
    add_track_numerics_option,
    irregularities_from_args,
    params_from_args,
    print_json,
    print_track_numerics,
    track_numerics_from_args,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import describe_contact, describe_track, describe_words
from wheelrail.core.study import STUDIES

FILES = Files(reads=("sets", "wheel_set"))
"""The roughness sets read (the outputs go into the folder --out)."""


def add_parser(sub):
    parser = sub.add_parser(
        "study",
        help="run one of the paper's studies (force spectra, contact filters, model differences)",
        description=(
            "Batch of independent runs reproducing a figure of the paper on any roughness set: filters "
            "(Fig. 10), line-spread (Figs 12-14), averaged-input (Fig. 16), lateral-resolution (Fig. 17), "
            "speeds (Fig. 11); noise (rolling noise against speed); track (force and noise on several tracks: give "
            "a track option several values, e.g. --pad-stiffness-mn-m 60 120 300 1000); impact (peak force, contact "
            "loss and impact noise against speed: give an irregularity, its inputs one or more values, e.g. "
            "--flat-length-mm 20 50 100 --flat-position-m 1). Writes one CSV per "
            "figure table (band name, exact centre in Hz, levels in dB), a PNG "
            "laid out like the paper's figure and a JSON summary into --out; finished runs are kept in "
            "OUT/runs, so an interrupted study resumes with the missing runs only."
        ),
    )
    parser.add_argument("name", metavar="NAME", help=f"study: {', '.join(STUDIES)}")
    parser.add_argument(
        "--set",
        required=True,
        action="append",
        metavar="SET",
        dest="sets",
        help="bundled roughness set name or CSV/NPZ file; repeat for several sets (one panel each)",
    )
    parser.add_argument(
        "--wheel-set",
        metavar="WHEEL_SET",
        default=None,
        help="a wheel roughness set added to every rail set --set in every run (combined roughness "
        "r_rail + r_wheel; part of every run key); default none",
    )
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument(
        "--length-m",
        type=float,
        default=None,
        help="run length, m (default: the whole set: rail data less margins, one wheel turn)",
    )
    where = parser.add_mutually_exclusive_group()
    # default None, not 2: argparse lets an option of a mutually exclusive group through when its value
    # equals the default, so `--dask ADDR --workers 2` would be accepted
    where.add_argument(
        "--workers",
        type=int,
        default=None,
        help="local workers, the cores the study may use (default 2): threads of this process for the bundled models, "
        "else worker processes; a new track's precompute integrates in at most that many threads",
    )
    where.add_argument(
        "--dask", metavar="ADDR", default=None, help="run on a Dask cluster: scheduler address tcp://HOST:PORT"
    )
    parser.add_argument("--json", action="store_true", help="print the machine-readable summary (SI units)")
    parser.add_argument(
        "--models",
        nargs="+",
        metavar="MODEL",
        default=None,
        help="impact study: the contact models (default: every registered model)",
    )
    parser.add_argument(
        "--speeds-kmh",
        nargs="+",
        type=float,
        metavar="V",
        default=None,
        help="impact study: the speeds, km/h (default 30 60 100 140 200)",
    )
    add_input_options(
        parser,
        *RUN_INPUT_GROUPS,
        helps={"speed": "train speed, km/h (for `speeds` the half-mass case's)"},
        several=("track",),
    )
    add_irregularity_options(parser, several=True)
    add_track_numerics_option(parser)
    return parser


def _impact(args, params):
    """The impact study's sweep (``core.study.impact_plan.ImpactSweep``): every combination of the values given to
    the irregularity options, the models and the speeds; other studies: ``params`` with the irregularities given
    (one value each). The namespace is left with one value per irregularity option (the first)."""
    import itertools

    from wheelrail.core.inputs.irregular import IRREGULARITY_INPUTS
    from wheelrail.core.parameters import KMH
    from wheelrail.core.study.impact_plan import ImpactSweep

    given = {e: getattr(args, e.dest) for e in IRREGULARITY_INPUTS if getattr(args, e.dest) is not None}
    swept = {e: values for e, values in given.items() if len(values) > 1}
    if args.name != "impact":
        extra = [o for o, v in (("--models", args.models), ("--speeds-kmh", args.speeds_kmh)) if v is not None]
        if swept or extra:
            options = ", ".join([*(e.option for e in swept), *extra])
            raise WheelrailError(
                f"{options}: for study impact only (study {args.name} takes one irregularity value each)"
            )
    cases = []
    for combination in itertools.product(*given.values()):
        for entry, value in zip(given, combination, strict=True):
            setattr(args, entry.dest, value)
        cases.append(irregularities_from_args(args, params))
    if args.name != "impact":
        return cases[0]
    speeds = () if args.speeds_kmh is None else tuple(v * KMH for v in args.speeds_kmh)
    base = cases[0]
    return ImpactSweep(
        base, cases=tuple(case.run.irregularities for case in cases), models=tuple(args.models or ()), speeds=speeds
    )


def _tracks(args):
    """The track study's tracks: every combination of the values given to the track options (each input swept
    over its values, the others the paper's or as given once); None for one track. The namespace is left with
    one value per option (the first), so that ``params_from_args`` reads the base track."""
    import itertools

    from wheelrail.core.inputs.declared import inputs_of, model_parameters

    values = {}
    for entry in inputs_of("track"):
        given = getattr(args, entry.dest)
        given = list(given) if isinstance(given, list) else [given]
        values[entry] = given
        setattr(args, entry.dest, given[0])
    swept = {entry: given for entry, given in values.items() if len(given) > 1}
    if not swept:
        return None
    if args.name != "track":
        options = ", ".join(entry.option for entry in swept)
        raise WheelrailError(f"{options}: one value each for study {args.name}; several values sweep `study track`")
    base = params_from_args(args, "track")
    tracks = []
    for combination in itertools.product(*swept.values()):
        chosen = {entry.key: value * entry.shown.si for entry, value in zip(swept, combination, strict=True)}
        tracks.append(model_parameters(chosen, base).track)
    return tracks


def _say_track_cost(tracks, sets: int, workers: int, quiet: bool, numerics=None) -> None:
    """Refuse a track study over its limits, else say on stderr what it will cost before it starts."""
    from wheelrail.core.study.track_plan import check_track_count, track_study_cost

    check_track_count(tracks)
    cost = track_study_cost(tracks, sets, workers, numerics)
    if quiet:
        return
    new = cost["new_tracks"]
    work = (
        f"{new} not in the disk cache: about {cost['precompute_cpu_s'] / 60:.1f} min of CPU for their Green's "
        f"functions ({cost['precompute_wall_s'] / 60:.1f} min on {workers} worker{'s' * (workers > 1)}), "
        if new
        else "all in the disk cache, "
    )
    print(
        f"wheelrail study: {cost['tracks']} tracks, {cost['runs']} runs; {work}"
        f"{cost['cache_bytes'] / 1e9:.1f} GB of cache (limit {cost['cache_limit_bytes'] / 1e9:g} GB)",
        file=sys.stderr,
    )


def run(args) -> int:
    from wheelrail.core.study import parse_dask_address, run_study

    if args.name not in STUDIES:
        raise WheelrailError(f"unknown study {args.name!r}; choose one of {', '.join(STUDIES)}")
    numerics = track_numerics_from_args(args)  # every run's (and the tables' noise chains')
    tracks = _tracks(args)  # several values of a track input: the track study's sweep
    sweep = _impact(args, params_from_args(args, *RUN_INPUT_GROUPS))  # impact: the irregularities' sweep
    params = getattr(sweep, "params", sweep)  # the parameters every run shares (but for what is swept)
    if args.length_m is not None and (not math.isfinite(args.length_m) or args.length_m <= 0):
        raise WheelrailError(f"--length-m must be a positive length in m, got {args.length_m}")
    workers = 2 if args.workers is None else args.workers
    if workers < 1:
        raise WheelrailError(f"--workers must be at least 1, got {workers}")
    address = parse_dask_address(args.dask) if args.dask is not None else None
    if tracks is not None:
        _say_track_cost(tracks, len(args.sets), workers, args.json, numerics)
    result = run_study(
        args.name,
        args.sets,
        args.out,
        params=sweep if tracks is None else [replace(params, track=track) for track in tracks],
        wheel_set=args.wheel_set,
        length=args.length_m,
        workers=workers,
        dask_address=address,
        progress=not args.json and sys.stderr.isatty(),
        track_numerics=numerics,
    )
    summary = result.summary
    if args.json:
        print_json(summary)
        return 0
    wheel = f" + wheel set {summary['wheel_set']}" if summary["wheel_set"] else ""
    print(
        f"study {args.name} on {', '.join(summary['sets'])}{wheel}{_speed_words(args, summary)}: {summary['runs']} "
        "runs "
        f"({summary['runs_computed']} computed, {summary['runs_cached']} from {args.out}/runs) "
        f"in {summary['wall_time_s']:.1f} s on {summary['backend']}"
    )
    if tracks is None:
        print(f"  track: {describe_words(params, 'track')}")
    else:  # the sweep: each track by the inputs that differ, the rest once
        from wheelrail.core.study.track_plan import swept_inputs

        swept = swept_inputs(tracks)
        for number, track in enumerate(tracks, 1):
            words = describe_words(replace(params, track=track), "track").split(", ")
            print(
                f"  track {number}: " + ", ".join(w for w in words if any(w.startswith(e.label.lower()) for e in swept))
            )
        print(f"  {describe_track(params, leave_out=tuple(entry.key for entry in swept))}")
    print(f"  contact geometry: {describe_contact(params)}")
    print_track_numerics(summary.get("track_numerics"))  # those of every run that differ from the default
    if summary.get("irregularity_cases"):
        _say_impact(result)
    if summary["loss_of_contact_steps"]:
        print(f"  loss of contact in {summary['loss_of_contact_steps']} steps over all runs")
    records = summary["spectrum_records"]
    for record in records:  # what the force spectra analysed, per speed when the study has several
        speed = f"at {record['speed_m_per_s'] * 3.6:.4g} km/h: " if len(records) > 1 else ""
        print(f"  force {speed}{record['words']}")
    for table in result.tables:
        print(f"  {table.title}")
    for path in summary["files"]:
        print(f"  wrote {path}")
    return 0


def _say_impact(result) -> None:
    """The impact study's cases and, per set, case and model, the first speed with loss of contact and the slope of
    the sound power against speed."""
    from wheelrail.core.irregularities.shapes import from_record
    from wheelrail.core.study.impact_plan import case_words

    summary = result.summary
    print(f"  Hertz models on the {summary['irregularity_input']} (irregularity input)")
    for table in (t for t in result.tables if t.figure == "impact-loss"):
        for k, case in enumerate(summary["irregularity_cases"]):
            print(f"  {table.panel}, case {k + 1}: {case_words([from_record(item) for item in case])}")
            for model in summary["models"]:
                name = model.replace("-", "_")
                lost = table.columns[f"{name}_first_loss_speed_kmh"][k]
                slope = table.columns[f"{name}_slope_dB_per_doubling"][k]
                where = f"contact lost from {lost:g} km/h" if math.isfinite(lost) else "contact kept at every speed"
                rise = f"{slope:+.1f} dB per doubling of speed" if math.isfinite(slope) else "no slope (one speed)"
                print(f"    {model}: {where}; sound power {rise}")


def _speed_words(args, summary) -> str:
    """ ", 100 km/h, element 1 mm": the study's speed (the impact study, which sweeps it: its speeds) and element
    size."""
    element = f", element {args.element_mm:g} mm"
    if "speeds_m_per_s" not in summary:
        return f", {args.speed_kmh:g} km/h{element}"
    return f", {', '.join(f'{v * 3.6:g}' for v in summary['speeds_m_per_s'])} km/h{element}"
