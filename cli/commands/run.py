"""``wheelrail run``: one wheel/rail interaction run on a roughness line."""

from __future__ import annotations

import math
import signal
import sys
import threading
import time
from pathlib import Path

from wheelrail.cli.commands._common import (
    CLI_NAMES,
    RUN_INPUT_GROUPS,
    Files,
    Output,
    add_choice_option,
    add_input_options,
    add_irregularity_options,
    add_track_numerics_option,
    cli_error_names,
    irregularities_from_args,
    params_from_args,
    print_json,
    print_track_numerics,
    track_numerics_from_args,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import describe, describe_contact, describe_words
from wheelrail.core.models import model_names
from wheelrail.core.recording.cli import add_recording_arguments, sink_from_args

FILES = Files(
    reads=("set", "wheel_set"),
    writes=(Output("out", "--out", ".npz"), Output("csv", "--csv", ".csv"), Output("rrd", "--rrd", ".rrd")),
)
"""The roughness sets read and the files written (checked by the dispatcher: ``_common.check_files``)."""


def add_parser(sub):
    parser = sub.add_parser(
        "run",
        help="simulate the wheel rolling over a roughness set with one contact model",
        description=(
            "Time-domain vertical wheel/rail interaction (paper eqs. 1-14). Prints a summary and the "
            "third-octave force spectrum; --out writes the arrays (time, x, force, xi_wheel, xi_rail, and "
            "pressure for 3d) to an .npz file."
        ),
    )
    parser.add_argument(
        "--set",
        required=True,
        metavar="SET",
        help="bundled roughness set name (see `wheelrail datasets`) or a CSV/NPZ file",
    )
    parser.add_argument(
        "--wheel-set",
        metavar="WHEEL_SET",
        default=None,
        help="a wheel roughness set added to the rail set --set (combined roughness r_rail + "
        "r_wheel, paired by lateral position: the wheel set interpolated across onto the "
        "rail's lines; its lines repeat with the circumference); default none",
    )
    parser.add_argument(
        "--line", type=int, default=0, help="roughness line -M..M of --set (3d: window centre), default 0"
    )
    parser.add_argument(
        "--model",
        default="hertz",
        choices=model_names(),
        help="contact model (default hertz; installed plug-ins included)",
    )
    parser.add_argument(
        "--length-m",
        type=float,
        default=None,
        help="run length, m (default: the whole set: rail data less margins, one wheel turn)",
    )
    parser.add_argument(
        "--out",
        metavar="F.npz",
        help="write the run's arrays to this .npz file (3d: with every pressure map, so it is "
        "held in memory for the whole run; --rrd records the maps without that)",
    )
    parser.add_argument(
        "--csv",
        metavar="F.csv",
        help="write the time history as CSV: time_s, x_m, force_N, xi_wheel_m, xi_rail_m, roughness_m, "
        "equivalent_roughness_m, headed by a comment naming the configuration",
    )
    parser.add_argument(
        "--wheel-model",
        choices=("2dof", "modal"),
        default="2dof",
        help="the wheel: the paper's 2-DOF wheel (default) or the modal wheel (the named wheel nearest the run's "
        "radius, at that radius, clamped on the axle, modes to 10 kHz, in series with the paper's wheelset mass "
        "and suspension: see wheelrail wheel); --out, --csv and --rrd record it. The sound power's wheel "
        "(--sound-power) is --noise-wheel-model",
    )
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary (SI units)")
    add_input_options(parser, *RUN_INPUT_GROUPS)
    add_irregularity_options(parser)
    add_track_numerics_option(parser)
    add_recording_arguments(parser)
    add_choice_option(  # the sound power's wheel: one declaration (CHOICES), named apart from --wheel-model here
        parser, "noise_wheel_model", "with --sound-power, the recorded sound power's wheel: ", "--noise-wheel-model"
    )
    return parser


class _StopOnCtrlC:
    """Ctrl-C during the run asks it to stop between steps, then raises KeyboardInterrupt.

    The default handler raises KeyboardInterrupt wherever the interpreter is, also inside numba-compiled
    code calling back into Python, which turns it into a ``SystemError`` (`3d` runs reported
    `internal error: SystemError: CPUDispatcher(...)`). A second Ctrl-C interrupts at once.
    """

    def __init__(self, interaction) -> None:
        self.interaction = interaction
        self.pressed = False
        self.previous = None

    def _handler(self, signum, frame) -> None:
        self.pressed = True
        self.interaction.cancel()
        signal.signal(signal.SIGINT, self.previous)

    def __enter__(self):
        if (
            threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler
        ):
            self.previous = signal.signal(signal.SIGINT, self._handler)
        return self

    def __exit__(self, exc_type, exc, traceback) -> None:
        if self.previous is not None:
            signal.signal(signal.SIGINT, self.previous)
        if self.pressed and exc_type is None:
            raise KeyboardInterrupt


def _checked_args(args):
    """The run's parameters, track numerics and output paths, checked before any work: (params, numerics, out)."""
    params = irregularities_from_args(args, params_from_args(args, *RUN_INPUT_GROUPS))
    if args.length_m is not None and (not math.isfinite(args.length_m) or args.length_m <= 0):
        raise WheelrailError(f"--length-m must be a positive length in m, got {args.length_m}")
    out = Path(args.out) if args.out is not None else None  # the files: checked by the dispatcher (FILES)
    if args.noise_wheel_model != "directive" and not getattr(args, "sound_power", False):
        raise WheelrailError("--noise-wheel-model needs --sound-power (the recording's sound power)")
    return params, track_numerics_from_args(args), out


def modal_wheel_of(params):
    """The cross-section of ``--wheel-model modal``: the named wheel nearest the run's rolling radius, at that
    radius (``modal_wheel.wheel_profile_for``); ``prepare_run`` builds its Green's function at the run's step."""
    from wheelrail.core.modal_wheel import wheel_profile_for

    return wheel_profile_for(params.contact.radius_along)


def _prepare(args, params, numerics, out, sink):
    """The prepared run, and the recording started on it (aborted if preparing fails)."""
    from wheelrail.cli.commands._progress import announce_track_precompute
    from wheelrail.core.engine import prepare_run

    wheel_system = modal_wheel_of(params) if args.wheel_model == "modal" else None
    try:
        # 3d: every pressure map is kept only for --out (a recording takes them step by step)
        with announce_track_precompute("run"):  # a track not yet cached: its phases and progress on a terminal
            interaction = prepare_run(
                args.set,
                wheel_roughness=args.wheel_set,
                model=args.model,
                line=args.line,
                params=params,
                length=args.length_m,
                keep_pressure=out is not None,
                wheel_system=wheel_system,
                track_numerics=numerics,
            )
        if sink is not None and sink.options.record_every > interaction.n_steps:
            raise WheelrailError(
                f"--record-every {sink.options.record_every} exceeds the run's {interaction.n_steps} steps"
            )
        if sink is not None:
            from wheelrail.core.roughness import load_roughness

            # the recording shows the set's lines around the run's line (roughness/lines); the sink records
            # what it is given and loads nothing itself
            sink.start(interaction, roughness=load_roughness(args.set))
    except BaseException:
        if sink is not None:
            sink.abort()
        raise
    return interaction


def _execute(args, interaction, sink):
    """Run with a progress bar on a terminal; Ctrl-C stops between steps (the recording aborted on any error)."""
    bar = None
    if not args.json and sys.stderr.isatty():  # tqdm imported only when it is shown
        from tqdm import tqdm

        bar = tqdm(
            total=interaction.n_steps, unit="step", desc=f"{args.model} {args.speed_kmh:g} km/h", file=sys.stderr
        )

    def progress(done, total):
        bar.update(done - bar.n)

    try:
        with _StopOnCtrlC(interaction):
            result = interaction.run(callback=sink, progress=progress if bar is not None else None)
    except BaseException:
        if sink is not None:
            sink.abort()
        raise
    finally:
        if bar is not None:
            bar.close()
    return result


def _summary(args, result, params, times) -> dict:
    """What ``--json`` prints (SI; keys name their unit), the force spectrum included when the run allows one."""
    import numpy as np

    from wheelrail.core.files.run_file import check_fluctuating
    from wheelrail.core.spectra.bands import band_labels
    from wheelrail.core.spectra.force import check_spectrum_length, force_spectrum, spectrum_record

    start, prepared, finished = times
    try:
        check_spectrum_length(result.n_steps * result.element_size, result.speed, result.element_size)
        check_fluctuating(result.force, spectrum_record(result).skipped_steps, f"the {result.model} run")
        centres, levels = force_spectrum(result)
        record, spectrum_note = spectrum_record(result).to_dict(), ""
    except WheelrailError as error:  # a run shorter than the spectrum's start-up skip: no spectrum
        centres, levels, record = np.array([]), np.array([]), None
        spectrum_note = error.render(CLI_NAMES)
    force = result.force
    summary = {
        "model": result.model,
        "set": args.set,
        "wheel_set": args.wheel_set,
        "line": result.line,
        "speed_m_per_s": result.speed,
        "speed_kmh": args.speed_kmh,
        "preload_n": params.contact.preload,
        "wheel_model": result.header.wheel_model,
        **({"modal_wheel": result.header.wheel_profile} if result.header.wheel_profile is not None else {}),
        **describe(params, "geometry", "track"),  # the contact geometry and track it ran on, SI
        # the track's numerics that differ from the default, as --track-numerics names them ({}: the default)
        "track_numerics": dict(result.header.track_numerics),
        "hertz_semi_axes_m": list(params.contact.hertz_semi_axes()),  # a along the rail, b across, at the preload
        "element_size_m": result.element_size,  # the contact grid and step along the rail (--element-mm)
        "steps": result.n_steps,
        "length_m": result.n_steps * result.element_size,
        "time_step_s": result.time_step,
        "force_mean_n": float(force.mean()),
        "force_std_n": float(force.std()),
        "force_min_n": float(force.min()),
        "force_max_n": float(force.max()),
        "loss_of_contact_steps": result.loss_of_contact_steps,
        "run_in_length_m": result.run_in_length,
        "run_in_time_s": result.run_in_time,
        "prepare_time_s": prepared - start,
        "run_time_s": finished - prepared,
        "steps_per_s": result.n_steps / max(finished - prepared, 1e-9),
        "band_labels": band_labels(centres),
        "band_centres_hz": centres,
        "levels_db": levels,
        # the start left out, the record analysed and the bands it resolves (SpectrumRecord.to_dict)
        "spectrum_record": record,
    }
    if spectrum_note:
        summary["spectrum_note"] = spectrum_note
    from wheelrail.core.engine.impacts import impact_summary

    if params.run.irregularities:
        from wheelrail.core.irregularities.shapes import as_record

        summary["irregularities"] = [as_record(item) for item in params.run.irregularities]
        summary["irregularity_input"] = params.run.irregularity_input
    summary["impacts"] = impact_summary(result).to_dict() if result.n_steps else None
    return summary


def _print_summary(args, result, params, summary, sink) -> None:
    import numpy as np

    force = result.force
    wheel_set = f" + wheel {args.wheel_set}" if args.wheel_set else ""
    print(
        f"{result.model} on {args.set}{wheel_set} line {result.line}, {args.speed_kmh:g} km/h, "
        f"{summary['preload_n'] / 1e3:g} kN, element {result.element_size * 1e3:g} mm: {result.n_steps} steps over "
        f"{summary['length_m']:.3f} m"
    )
    print(f"  track: {describe_words(params, 'track')}")
    print_track_numerics(result.header.track_numerics)
    modal = result.header.wheel_model == "modal"
    wheel = ", with the paper's wheelset mass and suspension (wheelrail wheel shows it)" if modal else ""
    print(f"  wheel: {result.header.wheel_words()}{wheel}")
    print(f"  contact geometry: {describe_contact(params)}")
    print(
        f"  contact force: mean {force.mean() / 1e3:.3f} kN, std {force.std() / 1e3:.3f} kN, "
        f"min {force.min() / 1e3:.3f} kN, max {force.max() / 1e3:.3f} kN"
    )
    print(f"  loss of contact: {result.loss_of_contact_steps} steps")
    if result.header.params.run.irregularities:
        print(f"  irregularities{result.header.irregularity_words().partition('irregularities')[2]}")
    if summary["impacts"] is not None:
        from wheelrail.core.engine.impacts import impact_summary

        for text in impact_summary(result).lines():
            print(f"  {text}")
    print(f"  run-in before the record (discarded): {result.run_in_length:.3f} m, {result.run_in_time * 1e3:.1f} ms")
    print(
        f"  {summary['steps_per_s']:.0f} steps/s (prepare {summary['prepare_time_s']:.2f} s, "
        f"run {summary['run_time_s']:.2f} s)"
    )
    if "spectrum_note" in summary:
        print(f"  no force spectrum: {summary['spectrum_note']}")
    else:
        from wheelrail.core.spectra.force import spectrum_record

        print(f"  {spectrum_record(result).words()}")
        print("  third-octave force levels, dB re 1 N:")
    for label, level in zip(summary["band_labels"], summary["levels_db"], strict=True):
        text = "   n/a" if not np.isfinite(level) else f"{level:6.1f}"
        print(f"    {label:>7} Hz {text}")
    if "out" in summary:
        print(f"  arrays written to {summary['out']}")
    if "csv" in summary:
        print(f"  time history written to {summary['csv']}")
    if sink is not None and sink.path is not None:
        print(f"  recording written to {sink.path}")


def _write_outputs(args, result, out, sink) -> None:
    """--out, --csv and --rrd all or none (``core.files.atomic.all_or_none``): a full disk while writing any of them
    leaves none (one line naming the file and why); a viewer lost during the run costs none of them."""
    from wheelrail.core.files.atomic import all_or_none
    from wheelrail.core.recording.outputs import ViewerUnreachable

    lost = None
    try:
        with all_or_none():
            if out is not None:
                result.save_npz(out)
            if getattr(args, "csv", None) is not None:
                result.save_csv(args.csv)
            if sink is not None:
                try:
                    sink.finish(result)
                except ViewerUnreachable as error:  # the files are written all the same
                    lost = error
    except BaseException:
        if sink is not None:
            sink.abort()
        raise
    if lost is not None:
        raise lost


def run(args) -> int:
    params, numerics, out = _checked_args(args)
    sink = sink_from_args(args, description=f"{args.model} on {args.set} line {args.line}", names=cli_error_names())

    start = time.perf_counter()
    interaction = _prepare(args, params, numerics, out, sink)
    prepared = time.perf_counter()
    result = _execute(args, interaction, sink)
    finished = time.perf_counter()
    _write_outputs(args, result, out, sink)
    summary = _summary(args, result, params, (start, prepared, finished))
    if out is not None:
        summary["out"] = str(out)
    if getattr(args, "csv", None) is not None:
        summary["csv"] = str(args.csv)
    if args.json:
        print_json(summary)
        return 0
    _print_summary(args, result, params, summary, sink)
    return 0
