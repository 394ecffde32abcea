"""``wheelrail noise``: rolling noise by the CNOSSOS-EU source model, by this project's physics chain, and from a run.

- ``--method cnossos``: Directive 2002/49/EC Annex II 2.3 (as replaced by (EU) 2015/996 and amended by
  (EU) 2021/1226) with the Appendix G tables (:mod:`wheelrail.core.noise.cnossos`);
- ``--method twins``: the model track's transfer function, decay rate and rail radiation efficiency
  (:mod:`wheelrail.core.noise.twins`);
- ``--run RESULT.npz``: a finished run (any contact model) to sound power, dB(A), pass-by level and a WAV
  (:mod:`wheelrail.core.noise.run_noise`).

Options carry their unit (km/h, kN, mm); everything inside is SI.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wheelrail.cli.commands._common import (
    Files,
    Output,
    accepted_help,
    add_choice_option,
    add_input_options,
    add_track_numerics_option,
    params_from_args,
    print_json,
    speed_from_kmh,
    track_numerics_from_args,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.contact_position import CONTACT_POSITION_INPUTS
from wheelrail.core.inputs.declared import describe, describe_track, describe_words, inputs_of
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.spectra.bands import nominal_band_label

FILES = Files(reads=("run",), writes=(Output("wav", "--wav", ".wav"), Output("csv", "--csv", ".csv")))
"""The run read and the files written (checked by the dispatcher: ``_common.check_files``)."""

METHODS = ("cnossos", "twins")
_TRACK_HELP = {  # the track and contact-geometry options name the method that uses them
    entry.key: f"--method twins: {entry.help}{', ' + entry.shown.name if entry.shown.name else ''}"
    for entry in inputs_of("track", "geometry")
}


def add_parser(sub):
    parser = sub.add_parser(
        "noise",
        help="rolling noise: CNOSSOS-EU source, the model track's transfer function, or a run's sound power and WAV",
        description=(
            "Rolling noise in the 24 one-third octave bands 50 Hz-10 kHz. --method cnossos: the CNOSSOS-EU source "
            "(Directive 2002/49/EC Annex II 2.3, (EU) 2015/996 as amended by (EU) 2021/1226, Appendix G tables). "
            "--method twins: this project's track model as a TWINS-like transfer function. --run RESULT.npz: a "
            "finished run to sound power per component, dB(A), pass-by level (and --wav)."
        ),
    )
    # every option added, with its default: run() refuses one a mode does not use (given, even if invalid)
    added = [
        parser.add_argument(
            "--method",
            choices=METHODS,
            default=None,
            help="cnossos (the directive's source model) or twins (the model track's transfer function)",
        ),
        parser.add_argument("--run", metavar="RESULT.npz", help="a run saved with `wheelrail run --out` (any model)"),
        *_add_source_options(parser),
        *_add_train_options(parser),
        add_choice_option(parser, "noise_wheel_model", "--method twins and --run: "),
        *_add_contact_position_options(parser),
        *add_input_options(parser, "geometry", "track", helps=_TRACK_HELP),
        add_track_numerics_option(parser, frequency_domain="--method twins"),
        parser.add_argument("--json", action="store_true", help="print a machine-readable summary on stdout"),
    ]
    parser.set_defaults(_options={action.dest: (action.option_strings[-1], action.default) for action in added})
    return parser


_ALWAYS = {"method", "run", "json", "help"}
_POSITION_DESTS = {entry.dest for entry in CONTACT_POSITION_INPUTS}
_USED_BY = {  # the options each mode uses (besides _ALWAYS); any other given is refused, naming the mode
    "cnossos": {
        "speed_kmh",
        "rail_roughness",
        "wheel_roughness",
        "track_type",
        "wheel_diameter_mm",
        "preload_kn",
        "axles",
        "roughness_interpolation",
    },
    "twins": {"wheel_model", "track_numerics", *_POSITION_DESTS},  # and the track's and contact geometry's inputs
    "run": {"train_axles", "train_length_m", "wav", "csv", "wheel_model", *_POSITION_DESTS},
}


def _refuse_unused(args) -> None:
    """One WheelrailError naming every option given that the chosen mode does not use (``--method twins
    --preload-kn nan`` was accepted and ignored), with the mode."""
    mode = "run" if args.run is not None else args.method
    if mode is None:
        return
    twins_inputs = {entry.dest for entry in inputs_of("track", "geometry")}
    used = _ALWAYS | _USED_BY[mode] | (twins_inputs if mode == "twins" else set())
    given = []
    for dest, (option, default) in args._options.items():
        value = getattr(args, dest, default)
        if dest not in used and value != default:  # NaN given is never its default: refused too
            given.append(option)
    if given:
        words = "--run (a run's sound power and pass-by)" if mode == "run" else f"--method {mode}"
        raise WheelrailError(
            f"{', '.join(given)}: not used by {words}; leave {'it' if len(given) == 1 else 'them'} out"
        )


def _add_source_options(parser) -> list:
    """Speed, load and the CNOSSOS-EU tables' choices: the argparse actions added."""
    from wheelrail.core.noise.cnossos import (
        INTERPOLATION_RULES,
        RAIL_ROUGHNESS,
        TRACK_TYPES,
        WHEEL_DIAMETERS_MM,
        WHEEL_ROUGHNESS,
    )
    from wheelrail.core.parameters import KMH, ContactParameters, RunParameters

    speed_kmh, preload_kn = RunParameters().speed / KMH, ContactParameters().preload / 1e3
    return [
        parser.add_argument(
            "--speed-kmh",
            type=float,
            default=None,
            help=f"train speed, km/h (default {speed_kmh:g}; with --run the run's own speed; {accepted_help('speed')})",
        ),
        parser.add_argument(
            "--rail-roughness",
            choices=RAIL_ROUGHNESS,
            default="iso3095",
            help="CNOSSOS rail roughness, Table G-1b: iso3095 (class E) or network-average (class M)",
        ),
        parser.add_argument(
            "--wheel-roughness",
            choices=WHEEL_ROUGHNESS,
            default="cast-iron",
            help="CNOSSOS wheel roughness, Table G-1a (none: the rail's roughness alone, e.g. where the "
            "combined roughness was measured)",
        ),
        parser.add_argument(
            "--track-type",
            choices=TRACK_TYPES,
            default="mono-block-medium",
            help="CNOSSOS track transfer function, Table G-3a (default mono-block-medium)",
        ),
        parser.add_argument(
            "--wheel-diameter-mm",
            type=float,
            default=920.0,
            help=f"wheel diameter, mm: one of {', '.join(map(str, WHEEL_DIAMETERS_MM))} (Table G-3b; default 920)",
        ),
        parser.add_argument(
            "--preload-kn",
            type=float,
            default=None,
            help=f"static wheel load, kN, for the contact filter A3 (default {preload_kn:g}: the model's preload; "
            f"{accepted_help('preload')})",
        ),
        parser.add_argument("--axles", type=int, default=4, help="axles per vehicle, N_a (default 4)"),
        parser.add_argument(
            "--roughness-interpolation",
            choices=INTERPOLATION_RULES,
            default="proportional",
            help="wavelength-to-frequency rule: proportional (the Commission's reference source module; "
            "default) or energy-log-frequency",
        ),
    ]


def _add_contact_position_options(parser) -> list:
    """The contact's lateral position on the railhead and the wheel's tread (declared once:
    ``wheelrail.core.inputs.contact_position``), mm: the argparse actions added."""
    options = parser.add_argument_group("contact position (--method twins and --run)")
    return [
        options.add_argument(
            entry.option,
            type=float,
            default=entry.shown_default(),
            help=f"{entry.help}, {entry.shown.name} (default {entry.shown_default():g}; accepted "
            f"{entry.accepted_text()})",
        )
        for entry in CONTACT_POSITION_INPUTS
    ]


def contact_position_from_args(args):
    """The :class:`~wheelrail.core.inputs.contact_position.ContactPosition` of the options (mm at the edge, SI
    inside; each checked against its declared range)."""
    from wheelrail.core.inputs.contact_position import ContactPosition

    values = {entry.field: getattr(args, entry.dest) * entry.shown.si for entry in CONTACT_POSITION_INPUTS}
    return ContactPosition(**values)


def _add_train_options(parser) -> list:
    """The train of a run's pass-by and its WAV: the argparse actions added."""
    return [
        parser.add_argument(
            "--train-axles",
            type=int,
            default=None,
            help="--run: axles of the whole train for the pass-by level (default 40: ten 4-axle vehicles)",
        ),
        parser.add_argument(
            "--train-length-m",
            type=float,
            default=None,
            help="--run: train length, m, for the pass-by level (default 200)",
        ),
        parser.add_argument("--wav", metavar="FILE.wav", help="--run: write the pass-by as a WAV file"),
        parser.add_argument(
            "--csv",
            metavar="FILE.csv",
            help="--run: write the sound power per band as CSV (band, centre_hz, force and each component's: rail, "
            "rail_lateral, sleeper, wheel, total dB re 1 pW), headed by a comment naming the run",
        ),
    ]


def _speed(args) -> float:
    """--speed-kmh in m/s within core's accepted range (default: the model's speed, ``RunParameters().speed``)."""
    from wheelrail.core.parameters import RunParameters

    return RunParameters().speed if args.speed_kmh is None else speed_from_kmh(args.speed_kmh)


def _load(args) -> float:
    """--preload-kn in N within core's accepted range (default: the model's preload)."""
    from wheelrail.core.parameters import ContactParameters

    if args.preload_kn is None:
        return ContactParameters().preload
    return ACCEPTED["preload"].check(args.preload_kn * 1e3, "preload")


def _cnossos(args) -> dict:
    from wheelrail.core.noise.cnossos import cnossos_rolling_noise

    result = cnossos_rolling_noise(
        _speed(args),
        rail=args.rail_roughness,
        wheel=args.wheel_roughness,
        track_type=args.track_type,
        wheel_diameter=args.wheel_diameter_mm * 1e-3,
        load=_load(args),
        axles=args.axles,
        rule=args.roughness_interpolation,
    )
    from wheelrail.core.spectra.bands import band_labels

    return {
        "band_labels": band_labels(result.frequency_hz),
        "frequency_hz": result.frequency_hz,
        "cnossos": result.to_dict(),
    }


def _level(value: float) -> str:
    """A level to one decimal, "-" where there is none (a component that does not radiate: -inf dB)."""
    return f"{value:.1f}" if np.isfinite(value) else "-"


def _fmt(value: float) -> str:
    return "    -" if not np.isfinite(value) else f"{value:5.1f}"


def _print_table(title: str, frequency, columns: dict, totals: dict) -> None:
    print(title)
    names = list(columns)
    print("  band Hz " + " ".join(f"{name:>11}" for name in names))
    for i, f in enumerate(frequency):
        print(f"  {nominal_band_label(f):>7} " + " ".join(f"{_fmt(columns[n][i]):>11}" for n in names))
    print("  " + ", ".join(f"{name} {_fmt(value).strip()}" for name, value in totals.items()))


def run(args) -> int:
    if args.run is not None and args.method is not None:
        raise WheelrailError("--run and --method exclude each other: --run uses the run's own model and track")
    _refuse_unused(args)
    if args.run is not None:
        return _run_file(args)
    if args.wav is not None:
        raise WheelrailError("--wav needs --run RESULT.npz (the pass-by is synthesised from a run's contact force)")
    if args.csv is not None:
        raise WheelrailError("--csv needs --run RESULT.npz (the sound power per band of a run)")
    if args.method is None:
        raise WheelrailError("choose --method cnossos, --method twins or --run RESULT.npz")
    if args.method == "cnossos":
        summary = _cnossos(args)
        if args.json:
            print_json(summary)
            return 0
        c = summary["cnossos"]
        cfg = c["configuration"]
        _print_table(
            f"CNOSSOS-EU rolling noise at {cfg['speed_m_s'] * 3.6:g} km/h: rail {cfg['rail_roughness']}, wheel "
            f"{cfg['wheel_roughness']}, track {cfg['track_type']}, wheel {cfg['wheel_diameter_m'] * 1e3:g} mm, "
            f"{cfg['wheel_load_n'] / 1e3:g} kN, {cfg['axles']} axles, {cfg['roughness_interpolation']} "
            "(roughness dB re 1 um, sound power dB re 1 pW per vehicle)",
            summary["frequency_hz"],
            {
                "L_R,TOT": c["total_roughness_dB"],
                "track": c["track_dB"],
                "vehicle": c["vehicle_dB"],
                "superstr.": c["superstructure_dB"],
                "total": c["total_dB"],
            },
            {"track dB(A)": c["track_dBA"], "vehicle dB(A)": c["vehicle_dBA"], "total dB(A)": c["total_dBA"]},
        )
        return 0
    return _twins(args)


def _run_file(args) -> int:
    """``wheelrail noise --run RESULT.npz [--json] [--wav FILE.wav]``."""
    from wheelrail.core.engine.results import RunResult
    from wheelrail.core.files.atomic import atomic_write
    from wheelrail.core.noise.run_noise import (
        DEFAULT_TRAIN_AXLES,
        DEFAULT_TRAIN_LENGTH,
        WAV_RATE,
        run_noise,
    )
    from wheelrail.core.noise.tables import NOMINAL_FREQUENCIES_HZ

    wav_path = None if args.wav is None else Path(args.wav)  # checked by the dispatcher: FILES
    csv_path = None if args.csv is None else Path(args.csv)
    if args.speed_kmh is not None:
        raise WheelrailError("--speed-kmh does not apply with --run: the run's own speed is used")
    result = RunResult.load_npz(args.run)
    axles = DEFAULT_TRAIN_AXLES if args.train_axles is None else args.train_axles
    length = DEFAULT_TRAIN_LENGTH if args.train_length_m is None else args.train_length_m
    if wav_path is not None:  # before any work: a WAV's length is bounded (core.noise.wav.MAX_WAV_S)
        from wheelrail.core.noise.run_noise import checked_train
        from wheelrail.core.noise.wav import check_wav_duration, check_wav_work

        axles, length = checked_train(axles, length)  # the train's own limits first
        duration = check_wav_duration(length, result.speed, 1.0, WAV_RATE)
        check_wav_work(axles, length, result.speed, result.time_step, 1.0)
    position = contact_position_from_args(args)
    noise = run_noise(
        result, train_axles=axles, train_length=length, wheel_model=args.wheel_model, contact_position=position
    )
    summary = noise.to_dict()
    if wav_path is not None:
        summary["wav"] = _write_wav(noise, wav_path, duration)
    if csv_path is not None:
        text = noise.csv_text(result.header.csv_comment(f"rolling noise of {args.run}"))
        atomic_write(csv_path, lambda handle: handle.write(text), mode="w", encoding="utf-8")
        summary["csv"] = str(csv_path)
    if args.json:
        print_json(summary)
        return 0
    cfg = summary["configuration"]["run"]
    print(
        f"Rolling noise of {args.run}: model {cfg['model']}, {cfg['roughness']} line {cfg['line']}, "
        f"{cfg['speed_m_s'] * 3.6:g} km/h; sound power of one wheel on one rail, dB re 1 pW"
    )
    print(f"  the run's wheel (its force): {result.header.wheel_words()}{result.header.irregularity_words()}")
    print(f"  track (its force and the rail's and sleepers' sound): {describe_track(result.header.params)}")
    print(f"  {position.words()} (the rail's lateral vibration and the wheel's axial modes)")
    track = noise.configuration["track"]
    print(
        f"  track numerics: {result.header.numerics_words()} (the run's; the noise chain's track "
        f"{track['track_bays']} bays, {track['elements_per_bay']} elements per bay)"
    )
    widths = {name: max(6, len(name)) for name in noise.sound_power_db}
    print("  band Hz   force dB " + " ".join(f"{name:>{width}}" for name, width in widths.items()))
    for i, f in enumerate(NOMINAL_FREQUENCIES_HZ):
        row = [(levels[i], widths[name]) for name, levels in noise.sound_power_db.items()]
        cells = " ".join(f"{_level(v):>{width}}" for v, width in row)
        force = "     -" if not np.isfinite(noise.force_db[i]) else f"{noise.force_db[i]:8.1f}"
        print(f"  {nominal_band_label(f):>7} {force}   {cells}")
    print(
        "  L_WA per wheel: "
        + ", ".join(f"{k} {_level(v)}" for k, v in noise.sound_power_dba.items())
        + f" dB(A); per axle {noise.axle_dba:.1f} dB(A)"
    )
    print(f"  pass-by L_pAeq,Tp at 7.5 m / 1.2 m: {noise.pass_by_laeq_dba:.1f} dB(A) ({axles} axles, {length:g} m)")
    _print_impact_and_beside(noise)
    if csv_path is not None:
        print(f"  wrote {csv_path}")
    if wav_path is not None:
        wav = summary["wav"]
        print(
            f"  wrote {wav_path} ({wav['duration_s']:.1f} s, {wav['size_bytes'] / 1e6:.1f} MB; full scale = "
            f"{wav['full_scale_pa']:.3g} Pa)"
        )
        if noise.impact is not None and noise.impact.flat_rate_hz is not None:
            print(f"  the WAV's wheels: {noise.wav_fill}; its level {noise.wav_level_dba:.1f} dB(A)")
    return 0


def _write_wav(noise, wav_path: Path, duration: float) -> dict:
    """Write the run's pass-by to ``wav_path`` (atomically); its entry of the summary."""
    from wheelrail.core.files.atomic import atomic_write
    from wheelrail.core.noise.run_noise import WAV_RATE

    written = {}
    atomic_write(wav_path, lambda handle: written.setdefault("full_scale", noise.write_wav(handle)))
    return {
        "path": str(wav_path),
        "full_scale_pa": written["full_scale"],
        "sample_rate_hz": WAV_RATE,
        "duration_s": duration,
        "size_bytes": wav_path.stat().st_size,
        "calibration": "sample value 1.0 (32767) = full_scale_pa Pa at the ISO 3095 position",
        "level_dBA": noise.wav_level_dba,
        "fill": noise.wav_fill,
    }


def _print_impact_and_beside(noise) -> None:
    """The text of ``noise --run`` after the pass-by: the impact's exposure and rate (a run with irregularities),
    the wheel's transfer and the CNOSSOS-EU source beside the run."""
    if noise.impact is not None:
        for line in noise.impact.lines():
            print(line)
    print("  wheel: " + noise.configuration["wheel"])
    beside = noise.cnossos
    print(f"  CNOSSOS-EU beside it ({beside_words(beside.configuration)}): L_WA per axle {beside.total_dba:.1f} dB(A) "
          f"(track {beside.track_dba:.1f}, vehicle {beside.vehicle_dba:.1f}); "
          f"pass-by {noise.cnossos_pass_by_dba():.1f} dB(A)")  # fmt: skip


def beside_words(cfg: dict) -> str:
    """What the CNOSSOS-EU source beside a run used, in words: its roughness, the contact filter with the wheel
    diameter it took (the model's 2R) and the L_H,veh column (the tabulated diameter nearest 2R)."""
    filter_diameter = cfg.get("contact_filter_wheel_diameter_m")
    contact_filter = cfg["contact_filter"]
    if filter_diameter is not None:
        contact_filter += f" for the model's 2R = {filter_diameter * 1e3:g} mm"
    return (
        f"the run's roughness, {contact_filter}, {cfg['track_type']}, L_H,veh of the "
        f"{cfg['vehicle_transfer_wheel_diameter_m'] * 1e3:g} mm column"
    )


def _twins(args) -> int:
    """``wheelrail noise --method twins``: print the model track's transfer function beside the directive's."""
    from wheelrail.core.inputs.numerics import frequency_domain_fields, numerics_changes, numerics_words
    from wheelrail.core.noise.cnossos import TRACK_TYPES, track_transfer, vehicle_transfer
    from wheelrail.core.noise.tables import NOMINAL_FREQUENCIES_HZ
    from wheelrail.core.noise.twins import NoiseNumerics, track_noise_model

    params = params_from_args(args, "track", "geometry")
    position = contact_position_from_args(args)
    numerics = track_numerics_from_args(args)
    chain = NoiseNumerics(**frequency_domain_fields(numerics, only="--method twins"))
    result = track_noise_model(params, chain, wheel_model=args.wheel_model, contact_position=position)
    summary = {
        "frequency_hz": np.asarray(NOMINAL_FREQUENCIES_HZ),
        "track_numerics": numerics_changes(numerics),
        "twins": result.to_dict(),
        "cnossos_track_transfer_dB": {name: track_transfer(name) for name in TRACK_TYPES},
        "cnossos_vehicle_transfer_dB": vehicle_transfer(result.wheel_diameter_mm),
        **describe(params, "track", "geometry"),
    }
    if args.json:
        print_json(summary)
        return 0
    cn = summary["cnossos_track_transfer_dB"]["mono-block-soft"]
    print(
        "Model track (lengthened to 240 bays) as a TWINS-like transfer function; rail + sleepers per "
        "axle for 0 dB re 1 um effective roughness (dB re 1 pW), beside CNOSSOS-EU L_H,tr mono-block-soft"
    )
    print(f"  track: {describe_words(params, 'track')}; contact: {describe_words(params, 'geometry')}")
    print(f"  {position.words()}")
    print(
        f"  track numerics: {numerics_words(summary['track_numerics'])} ({chain.track_bays} bays, "
        f"{chain.elements_per_bay} elements per bay, {chain.points_per_band} frequencies per band)"
    )
    veh = summary["cnossos_vehicle_transfer_dB"]
    # the components' transfers (wheelrail.core.noise.components): the track's beside L_H,tr, the wheel's beside L_H,veh
    track_parts = {name: max(6, len(name) + 1) for name in result.track_parts}
    wheel_parts = {name: max(7, len(name) + 2) for name in result.transfer_db if name not in track_parts}
    print(
        "  band Hz  L_H,tr model "
        + " ".join(f"{name:>{width}}" for name, width in track_parts.items())
        + "  CNOSSOS  decay EN15461  free wave  sigma rail  sigma sleeper "
        + " ".join(f"{name:>{width}}" for name, width in wheel_parts.items())
        + f"  L_H,veh {result.wheel_diameter_mm}"
    )
    for i, f in enumerate(NOMINAL_FREQUENCIES_HZ):
        track = " ".join(f"{_level(result.transfer_db[name][i]):>{width}}" for name, width in track_parts.items())
        wheel = " ".join(f"{_level(result.transfer_db[name][i]):>{width}}" for name, width in wheel_parts.items())
        print(
            f"  {f:7g}  {result.track_transfer_db[i]:12.1f} {track} {cn[i]:8.1f} {result.decay_rate_db_per_m[i]:14.2f} "
            f"{result.free_wave_decay_db_per_m[i]:10.2f} {result.rail_radiation_efficiency[i]:11.3f} "
            f"{result.sleeper_radiation_efficiency[i]:14.3f} {wheel} {veh[i]:12.1f}"
        )
    print(f"  wheel ({result.wheel_model}): {result.wheel_source}")
    return 0
