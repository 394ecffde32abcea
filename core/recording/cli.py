"""Command-line glue: the recording options of a command and the sink they ask for."""

from __future__ import annotations

from collections.abc import Mapping

from wheelrail.core.errors import Name, WheelrailError
from wheelrail.core.models import model_entry
from wheelrail.core.recording.sink import RecordingOptions, RecordingSink

__all__ = ["add_recording_arguments", "sink_from_args"]


def add_recording_arguments(parser) -> None:
    """Add ``--rrd FILE.rrd``, ``--spawn``, ``--connect ADDR`` and ``--record-every N`` to an argparse parser."""
    group = parser.add_argument_group("recording (rerun)")
    group.add_argument("--rrd", metavar="FILE.rrd", help="write a rerun recording of the run to this file")
    group.add_argument("--spawn", action="store_true", help="start a rerun viewer and stream the run to it")
    group.add_argument(
        "--connect", metavar="ADDR", help="stream the run to a running rerun viewer at HOST:PORT or a rerun+http URL"
    )
    group.add_argument(
        "--record-every",
        type=int,
        default=1,
        metavar="N",
        help="record the 3D pressure map every N-th step (default 1: every step; scalars are always every step)",
    )
    group.add_argument(
        "--sound-power",
        action="store_true",
        help="add the run's rolling-noise sound-power spectra (as `wheelrail noise --run`) at the end",
    )


def sink_from_args(args, *, description: str = "", names: Mapping[str, Name] | None = None) -> RecordingSink | None:
    """The recording sink the parsed options ask for, or None when no recording option was given.

    ``args`` is the namespace of a parser given :func:`add_recording_arguments`. Call it before the run: a
    bad ``--rrd`` path, ``--connect`` address or ``--record-every`` raises a :class:`WheelrailError` at once,
    so no run is wasted. ``description`` becomes the recording's name; ``names`` word the sink's warnings as the
    command names its options (``WheelrailError.render``).
    """
    sound_power = bool(getattr(args, "sound_power", False))
    if args.rrd is None and not args.spawn and args.connect is None:
        if args.record_every != 1:
            raise WheelrailError("--record-every needs --rrd, --spawn or --connect")
        if sound_power:
            raise WheelrailError("--sound-power needs --rrd, --spawn or --connect")
        return None
    model = getattr(args, "model", None)
    options = RecordingOptions(
        pressure_maps=model is None or model_entry(model).traits.pressure_map,
        record_every=args.record_every,
        description=description,
        # whose wheel power: the noise_wheel_model choice (``run --noise-wheel-model``), the directive's by default
        sound_power=getattr(args, "noise_wheel_model", "directive") if sound_power else False,
        names=names,
    )
    return RecordingSink(rrd=args.rrd, spawn=args.spawn, connect=args.connect, options=options)
