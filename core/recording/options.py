"""How a run is recorded (:class:`RecordingOptions`): the decimation, the block size, the name, the sound power and
the layout the viewer opens with; checked when made, so that a bad value fails before a run starts."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from wheelrail.core.errors import Blame, Name, WheelrailError
from wheelrail.core.inputs.declared import choice

__all__ = ["DEFAULT_CHUNK_STEPS", "SURFACE_EVERY", "RecordingOptions"]

DEFAULT_CHUNK_STEPS = 2048  # steps buffered before one columnar send
SURFACE_EVERY = 4  # the pressure surface mesh is recorded at every 4th recorded pressure map


@dataclass(frozen=True, kw_only=True)
class RecordingOptions:
    """What a :class:`~wheelrail.core.recording.RecordingSink` records besides where it writes.

    Attributes
    ----------
    record_every : int
        Record the pressure map (image) of every N-th step; scalars are recorded every step.
    surface_every : int
        Record the pressure surface mesh at every M-th recorded map, i.e. every ``record_every * M`` steps.
    chunk_steps : int
        Steps per columnar send.
    description : str
        Name of the recording shown by the viewer.
    sound_power : bool or str
        Add the run's rolling-noise sound-power spectra at the end (``--sound-power``), and their views; a value
        of the ``noise_wheel_model`` choice (``wheelrail.core.inputs.declared.CHOICES``: "directive", "modal") also says
        whose wheel power (True: the directive's L_H,veh), stated as ``wheel_transfer_source``.
    pressure_maps : bool
        The run has pressure maps (a model with ``ModelTraits.pressure_map``): the layout the viewer opens with
        has the pressure views (:func:`~wheelrail.core.recording.schema.default_blueprint`).
    names : mapping of str to Name, optional
        How the front end names the inputs (``WheelrailError.render``), for the warning when the sound power
        asked for cannot be computed (the run too short); None: the API's names.

    Raises
    ------
    WheelrailError
        For a count that is not a whole number of at least 1, or a sound power's wheel that is not a choice.
    """

    record_every: int = 1
    surface_every: int = SURFACE_EVERY
    chunk_steps: int = DEFAULT_CHUNK_STEPS
    description: str = ""
    sound_power: bool | str = False
    pressure_maps: bool = True
    names: Mapping[str, Name] | None = None

    def __post_init__(self) -> None:
        for name in ("record_every", "surface_every", "chunk_steps"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
                raise WheelrailError("not a whole number of at least 1", Blame(name, value, minimum=1))
            object.__setattr__(self, name, int(value))
        object.__setattr__(self, "names", dict(self.names or {}))
        self.sound_power_wheel  # noqa: B018 - checked here, before a run

    @property
    def sound_power_wheel(self) -> str:
        """Whose wheel power the sound power takes: the ``noise_wheel_model`` choice ("directive" unless named)."""
        wheel = self.sound_power if isinstance(self.sound_power, str) else "directive"
        return choice("noise_wheel_model").check(wheel)
