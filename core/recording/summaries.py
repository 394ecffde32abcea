"""What a recording adds when the run is over: the force spectrum (``spectra/force``) and, when asked for, the
run's rolling-noise sound power (``spectra/sound_power/*`` and a summary document)."""

from __future__ import annotations

import warnings

import numpy as np

from wheelrail.core.engine.results import RunResult
from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.recording.options import RecordingOptions
from wheelrail.core.recording.schema import (
    FORCE_SPECTRUM,
    SOUND_POWER,
    band_chart,
    rerun_module,
)

__all__ = ["log_force_spectrum", "log_sound_power"]


def log_force_spectrum(stream, force, time_step: float | None) -> None:
    """The one-third octave force levels of ``force`` (N, one value a step ``time_step`` s apart); nothing for
    a run too short for a spectrum."""
    from wheelrail.core.spectra.force import force_spectrum

    if time_step is None or len(force) < 2:
        return
    try:
        centres, levels = force_spectrum(np.asarray(force), time_step)
    except WheelrailError:
        return  # run too short for a spectrum (fewer than 16 steps after the start-up skip)
    stream.log(FORCE_SPECTRUM, band_chart(centres, levels), static=True, strict=True)


def log_sound_power(stream, result: RunResult, options: RecordingOptions) -> None:
    """``spectra/sound_power/<component>`` bar charts and a summary document (wheelrail.core.noise.run_noise),
    the wheel's power as ``options.sound_power_wheel`` says; a run whose sound power cannot be computed gets a
    summary saying why, and a warning worded with ``options.names``."""
    from wheelrail.core.noise.run_noise import run_noise

    rr = rerun_module()
    try:
        noise = run_noise(result, wheel_model=options.sound_power_wheel)  # a modal run's own wheel, if modal
    except WheelrailError as error:  # e.g. a run too short for a force spectrum: said, in the file and aloud
        reason = error.render(options.names)
        document = strict_json({"sound_power": "not computed", "reason": reason}, indent=2)
        stream.log(f"{SOUND_POWER}/summary", rr.TextDocument(document), static=True, strict=True)
        names = options.names
        option = names["sound_power"].label if "sound_power" in names else "sound_power"
        warnings.warn(f"{option}: no sound power recorded: {reason}", stacklevel=3)
        return
    for component in noise.sound_power_db:  # its parts (wheelrail.core.noise.components) and their total
        chart = band_chart(noise.frequency_hz, noise.sound_power_db[component])
        stream.log(f"{SOUND_POWER}/{component}", chart, static=True, strict=True)
    totals = {
        "sound_power_dBA_per_wheel": noise.sound_power_dba,
        "axle_dBA": noise.axle_dba,
        "pass_by_LpAeq_dBA": noise.pass_by_laeq_dba,
        "train_axles": noise.configuration["train_axles"],
        "train_length_m": noise.configuration["train_length_m"],
        "wheel_model": noise.configuration["wheel_model"],
        "wheel_transfer_source": noise.configuration["wheel"],
    }
    stream.log(f"{SOUND_POWER}/summary", rr.TextDocument(strict_json(totals, indent=2)), static=True, strict=True)
