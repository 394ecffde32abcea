"""``wheelrail spectra FILE``: third-octave contact-force spectrum of a saved run.

FILE is a ``.npz`` written by ``wheelrail run --out`` (``RunResult.save_npz``) or a ``.rrd`` recording
(read back with rerun's own reader, :func:`wheelrail.core.recording.read_recording`); both give the same
levels because both hold the run's force exactly. The spectrum is
:func:`wheelrail.core.spectra.force.force_spectrum`: start-up skipped, mean removed, one Hann-windowed FFT,
third-octave bands 50 Hz-8 kHz, dB re 1 N.
"""

from __future__ import annotations

import math
import zipfile
from pathlib import Path

import numpy as np

from wheelrail.cli.commands._common import Files, print_json
from wheelrail.core.engine.results import RunResult
from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.run_file import check_fluctuating
from wheelrail.core.spectra.bands import nominal_band_label
from wheelrail.core.spectra.force import FORCE_SKIP, force_spectrum, spectrum_record

FILES = Files(reads=("file",))
"""The run read (nothing is written)."""


def add_parser(sub):
    parser = sub.add_parser(
        "spectra",
        help="third-octave contact-force spectrum of a saved run (.npz or .rrd)",
        description=(
            "Third-octave band levels of the dynamic contact force (50 Hz-8 kHz, dB re 1 N; start-up skipped, "
            "mean removed, Hann window) of a run saved with 'wheelrail run --out F.npz' or '--rrd F.rrd'."
        ),
    )
    parser.add_argument("file", metavar="FILE", help="a run saved as .npz (wheelrail run --out) or .rrd (--rrd)")
    parser.add_argument(
        "--skip-ms",
        type=float,
        default=FORCE_SKIP * 1e3,
        help=f"start of the run left out, ms (default {FORCE_SKIP * 1e3:g})",
    )
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary on stdout")
    return parser


def load_force(path: str | Path) -> dict:
    """Force (N), time step (s) and run metadata of a saved run (.npz from ``save_npz`` or .rrd)."""
    source = Path(path)
    if not source.is_file():
        raise WheelrailError(f"run file {source} does not exist or is not a file")
    suffix = source.suffix.lower()
    if suffix == ".rrd":
        from wheelrail.core.recording import read_recording

        return _run_fields(read_recording(source))
    if suffix != ".npz":
        raise WheelrailError(f"run file {source} must be a .npz (wheelrail run --out) or a .rrd recording")
    if not zipfile.is_zipfile(source):
        raise WheelrailError(f"cannot read run file {source}: not a NumPy .npz archive (corrupt or another format)")
    try:
        with zipfile.ZipFile(source) as archive:
            members = archive.namelist()
    except (OSError, zipfile.BadZipFile, ValueError) as error:
        raise WheelrailError(f"cannot read run file {source}: {error}") from None
    if "force.npy" not in members:
        raise WheelrailError(f"{source} holds no 'force' array: not a run saved by wheelrail run --out")
    try:
        result = RunResult.load_npz(source)  # every array 1D, one length, a valid header; else one line
    except WheelrailError as error:
        raise WheelrailError(f"cannot read run file {error}") from None
    if not np.all(np.isfinite(result.force)):
        raise WheelrailError(f"cannot read run file {source}: the force holds NaN or infinite values")
    return _run_fields(result)


def _run_fields(result: RunResult) -> dict:
    """What ``spectra`` reads of a run, from a .npz or a recording alike."""
    return {
        "force": result.force,
        "time_step": result.time_step,
        "model": result.model,
        "line": result.line,
        "speed": result.speed,
        "roughness": result.roughness_name,
        "wheel_model": result.header.wheel_model,  # the interaction's wheel (RunHeader.wheel_model)
        "wheel": result.header.wheel_words(),
    }


def run(args) -> int:
    skip_ms = args.skip_ms
    if not (math.isfinite(skip_ms) and skip_ms >= 0):
        raise WheelrailError(f"--skip-ms must be zero or a positive number of milliseconds, got {skip_ms}")
    saved = load_force(args.file)
    centres, levels = force_spectrum(saved["force"], saved["time_step"], skip=skip_ms * 1e-3)
    record = spectrum_record(saved["force"], saved["time_step"], skip=skip_ms * 1e-3)
    check_fluctuating(saved["force"], record.skipped_steps, str(args.file))  # else every level is -inf dB
    rms = float(np.std(saved["force"][record.skipped_steps :]))
    if args.json:
        print_json(
            {
                "file": str(args.file),
                "model": saved["model"],
                "line": saved["line"],
                "speed_m_s": saved["speed"],
                "roughness": saved["roughness"],
                "wheel_model": saved["wheel_model"],
                "wheel": saved["wheel"],
                "time_step_s": saved["time_step"],
                "steps": int(len(saved["force"])),
                "skip_s": skip_ms * 1e-3,
                # the start left out in whole steps, the record analysed and the bands it resolves
                "spectrum_record": record.to_dict(),
                "dynamic_force_rms_n": rms,
                "band_centres_hz": centres.tolist(),
                "band_labels": [nominal_band_label(c) for c in centres],
                "levels_db": levels,
            }
        )
        return 0
    print(
        f"{args.file}: model {saved['model']}, line {saved['line']}, {len(saved['force'])} steps of "
        f"{saved['time_step'] * 1e6:.4g} us; first {skip_ms:g} ms skipped; dynamic force rms {rms:.4g} N"
    )
    print(f"  wheel: {saved['wheel']}")
    print(f"  {record.words()}")
    print(f"{'band (Hz)':>10} {'level (dB re 1 N)':>18}")
    for centre, level in zip(centres, levels, strict=True):
        text = "n/a" if not math.isfinite(level) else f"{level:.1f}"
        print(f"{nominal_band_label(centre):>10} {text:>18}")
    return 0
