"""Study run specs: what one run of a study is (:class:`RunSpec`), what it gives back (:class:`RunSummary`),
the roughness it uses (:func:`study_roughness`) and the worker task (:func:`compute_run`)."""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import REFERENCE_MODEL, model_entry, model_names  # noqa: F401 - REFERENCE_MODEL re-exported
from wheelrail.core.parameters import KMH, ModelParameters, TrackNumerics, as_dict

if TYPE_CHECKING:  # the roughness package is imported when a set is read
    from wheelrail.core.roughness import RoughnessLike

STUDIES = ("filters", "line-spread", "averaged-input", "lateral-resolution", "speeds", "noise", "track", "impact")
PAPER_LINES = tuple(range(-3, 4))  # the seven lines -3..3 the paper averages over (section 3.3)
LOW_RESOLUTION_LINES_MM = {  # Fig. 17: lateral offsets from line 0 kept, mm
    4: (-8.0, -4.0, 0.0, 4.0, 8.0),
    8: (-8.0, 0.0, 8.0),
}
PAPER_SPEEDS_KMH = (75.0, 100.0, 140.0, 200.0)  # Fig. 11
HALF_WHEEL_MASS = 296.3  # kg, Fig. 11: half of M_W = 592.5 kg
STUDY_FORMAT_VERSION = 4  # part of every run key: bump when a run's summary changes meaning (2: wheel sets paired
# by lateral position; 3: a band resolved by its width against the analysed record, core.spectra.record; 4: a set
# finer than the grid low-passed before it is read, roughness.grid.anti_alias)
SUMMARY_SCALARS = ("force_mean", "force_std", "force_min", "force_max", "loss_of_contact_steps", "n_steps", "run_time")


@dataclass(frozen=True, kw_only=True, eq=False)
class RunSpec:
    """One independent run of a study.

    Attributes
    ----------
    source : RoughnessLike
        Bundled set name, CSV/NPZ path, or the set itself (as accepted by ``simulate``).
    set_label : str
        Short name of the set in tables (bundled name or file stem).
    set_digest : str
        SHA-256 of the set's content (:func:`roughness_digest`); part of the run key, so a changed file
        is never matched with an old result.
    model : str
        A registered model (``wheelrail.core.models.model_names()``, plug-ins included).
    line : int
        Roughness line (-M..M); for ``3d`` the line the window is centred on. Ignored (0) with
        ``averaged_lines``.
    params : ModelParameters
        All model parameters (speed in ``params.run.speed``, m/s; wheel mass in
        ``params.wheel.unsprung_mass``, kg).
    length : float or None
        Run length, m (None: the whole set, see ``prepare_run``).
    averaged_lines : tuple of int
        If not empty, the model runs on one line: the mean of these lines (paper Fig. 16).
    lateral_lines_mm : tuple of float
        If not empty, only lines at these lateral offsets from line 0 (mm) are kept, linearly interpolated
        across the track from the original lines when they do not fall on one (paper Fig. 17).
    run_in_length : float or None
        Smooth run-in before the first step, m (None: the interaction's default,
        ``history.default_run_in_length``; the key holds the length used).
    wheel_source, wheel_label, wheel_digest : RoughnessLike, str, str or None
        A wheel set added to the rail set (combined roughness, ``simulate(wheel_roughness=...)``): as
        ``source``, ``set_label`` and ``set_digest``; None: a smooth wheel (the paper's case). Its label and
        digest are part of the run key when given (a run without one keeps the key it always had).
    track_numerics : TrackNumerics or None
        The track's numerics (``prepare_run``'s); None: the default. The fields that differ from the default are
        part of the run key (a run at the default keeps the key it always had).
    """

    source: RoughnessLike
    set_label: str
    set_digest: str
    model: str
    line: int = 0
    params: ModelParameters = field(default_factory=ModelParameters)
    length: float | None = None
    averaged_lines: tuple[int, ...] = ()
    lateral_lines_mm: tuple[float, ...] = ()
    run_in_length: float | None = None
    wheel_source: RoughnessLike | None = None
    wheel_label: str | None = None
    wheel_digest: str | None = None
    track_numerics: TrackNumerics | None = None

    def __post_init__(self) -> None:
        model_entry(self.model)  # an unknown name: one WheelrailError listing the registered models
        checked_numerics(self.track_numerics)
        object.__setattr__(self, "averaged_lines", tuple(int(v) for v in self.averaged_lines))
        object.__setattr__(self, "lateral_lines_mm", tuple(float(v) for v in self.lateral_lines_mm))
        if (self.wheel_source is None) != (self.wheel_digest is None) or (self.wheel_source is None) != (
            self.wheel_label is None
        ):
            raise WheelrailError("a study run's wheel set needs its source, label and digest together")

    def description(self) -> dict:
        """Everything that determines the run's summary (JSON-able); the key hashes this."""
        from wheelrail.core.inputs.numerics import numerics_changes
        from wheelrail.core.spectra.bands import FORCE_BAND_RANGE
        from wheelrail.core.spectra.force import FORCE_SKIP

        wheel = (
            {} if self.wheel_source is None else {"wheel_set": {"label": self.wheel_label, "digest": self.wheel_digest}}
        )
        numerics = numerics_changes(self.track_numerics)
        return {
            **wheel,
            **({"track_numerics": numerics} if numerics else {}),
            "version": STUDY_FORMAT_VERSION,
            "set_digest": self.set_digest,
            "model": self.model,
            "line": int(self.line),
            "length_m": None if self.length is None else float(self.length),
            "averaged_lines": list(self.averaged_lines),
            "lateral_lines_mm": list(self.lateral_lines_mm),
            "run_in_length_m": float(self.used_run_in_length),
            "params": as_dict(self.params),
            "spectrum": {"skip_s": FORCE_SKIP, "band_range_hz": list(FORCE_BAND_RANGE)},
        }

    @property
    def used_run_in_length(self) -> float:
        """The run-in the run uses, m (``run_in_length`` or the interaction's default at this speed)."""
        from wheelrail.core.engine.history import default_run_in_length

        return default_run_in_length(self.params) if self.run_in_length is None else float(self.run_in_length)

    @cached_property
    def key(self) -> str:
        """SHA-256 hex digest of :meth:`description` (sorted keys, floats by repr), worked out once a spec (a
        study reads it several times a run; everything it hashes is frozen)."""
        text = json.dumps(self.description(), sort_keys=True, default=repr)
        return hashlib.sha256(text.encode()).hexdigest()

    @property
    def speed_kmh(self) -> float:
        return self.params.run.speed / KMH

    def label(self) -> str:
        """Human-readable one-liner (progress messages and errors)."""
        what = f"{self.model} on {self.set_label}"
        if self.wheel_label is not None:
            what += f" + {self.wheel_label}"
        if self.averaged_lines:
            what += f" mean of lines {self.averaged_lines[0]}..{self.averaged_lines[-1]}"
        elif self.lateral_lines_mm:
            what += f" lines at {', '.join(f'{v:g}' for v in self.lateral_lines_mm)} mm"
        else:
            what += f" line {self.line}"
        return f"{what}, {self.speed_kmh:g} km/h, M_W {self.params.wheel.unsprung_mass:g} kg"


@dataclass(frozen=True, kw_only=True)
class RunSummary:
    """What a worker sends back for one run: the force spectrum and a few numbers (no time series).

    Attributes
    ----------
    key : str
        The run's :attr:`RunSpec.key`.
    band_centres : ndarray
        Exact third-octave band centres, Hz (50 Hz - 8 kHz).
    levels : ndarray
        Dynamic contact-force levels, dB re 1 N (NaN where a band is not resolved).
    force_mean, force_std, force_min, force_max : float
        Contact-force statistics over the run, N.
    loss_of_contact_steps, n_steps : int
        Steps with F = 0; steps in the run.
    run_time : float
        Wall time of the run in its worker, s (preparation included).
    """

    key: str
    band_centres: np.ndarray
    levels: np.ndarray
    force_mean: float
    force_std: float
    force_min: float
    force_max: float
    loss_of_contact_steps: int
    n_steps: int
    run_time: float

    def to_arrays(self) -> dict[str, np.ndarray]:
        arrays = {"run_key": np.array(self.key), "band_centres_hz": self.band_centres, "levels_db": self.levels}
        arrays.update({name: np.array(getattr(self, name)) for name in SUMMARY_SCALARS})
        return arrays

    @classmethod
    def from_arrays(cls, arrays) -> RunSummary:
        scalars = {name: arrays[name].item() for name in SUMMARY_SCALARS}
        return cls(
            key=str(arrays["run_key"]),
            band_centres=np.asarray(arrays["band_centres_hz"], dtype=float),
            levels=np.asarray(arrays["levels_db"], dtype=float),
            **scalars,
        )


def one_line_models() -> tuple[str, ...]:
    """The registered models that see one line (the paper averages them over ``PAPER_LINES``), plug-ins
    included, in registry order (``wheelrail.core.models.model_names``)."""
    return tuple(name for name in model_names() if not model_entry(name).traits.lateral_window)


def roughness_digest(roughness) -> str:
    """SHA-256 of a roughness set's content (heights, dx, y, kind), hex."""
    digest = hashlib.sha256()
    digest.update(np.ascontiguousarray(roughness.heights, dtype="<f8").tobytes())
    digest.update(np.ascontiguousarray(roughness.y, dtype="<f8").tobytes())
    digest.update(f"{roughness.dx!r} {roughness.kind}".encode())
    return digest.hexdigest()


def study_roughness(spec: RunSpec):
    """The roughness set a run actually uses: the source, or its line mean (Fig. 16), or its lines at
    the ``lateral_lines_mm`` offsets (Fig. 17). Returns ``(roughness, line)`` for ``simulate``."""
    return _as_used(spec, spec.source, spec.set_label)


def study_wheel_roughness(spec: RunSpec):
    """The wheel set added to the run's rail set, or None. Taken as :func:`study_roughness` takes the rail set
    (the same line mean or lateral lines) at the rail set's lateral positions, the wheel set interpolated across
    onto them (``simulate`` then pairs the two by position, as it pairs whole sets)."""
    if spec.wheel_source is None:
        return None
    return _as_used(spec, spec.wheel_source, spec.wheel_label, positions_of=_loaded(spec.source))[0]


def _loaded(source):
    from wheelrail.core.roughness import RoughnessSet, load_roughness

    return source if isinstance(source, RoughnessSet) else load_roughness(source)


def _as_used(spec: RunSpec, source, label: str, positions_of=None):
    """``source`` as the run uses it; line numbers and offsets are those of ``positions_of`` (default: the set
    itself), the lines taken at its lateral positions."""
    from wheelrail.core.roughness import at_lateral_positions, covers, lateral_extent_mm

    rough = _loaded(source)
    ref = rough if positions_of is None else positions_of
    if spec.averaged_lines:
        y_lines = np.array([ref.y[ref.row_of_line(line)] for line in spec.averaged_lines])
        if not covers(rough, float(y_lines.min()), float(y_lines.max())):
            raise WheelrailError(
                f"{label}: lines {', '.join(str(v) for v in spec.averaged_lines)} lie at "
                f"{y_lines.min() * 1e3:g} .. {y_lines.max() * 1e3:g} mm, where the set has no "
                f"data ({lateral_extent_mm(rough)})"
            )
        mean = at_lateral_positions(rough, y_lines).heights.mean(axis=0)
        note = f"mean of lines {', '.join(str(v) for v in spec.averaged_lines)}"
        return rough.with_heights(mean[np.newaxis, :], y=np.zeros(1), note=note), 0
    if spec.lateral_lines_mm:
        offsets = np.asarray(spec.lateral_lines_mm) * 1e-3
        y_wanted = float(ref.y[ref.centre_row]) + offsets
        if rough.n_lines < 2 or not covers(rough, float(y_wanted.min()), float(y_wanted.max())):
            raise WheelrailError(
                f"{label}: lines at {', '.join(f'{v:g}' for v in spec.lateral_lines_mm)} mm from line 0 "
                f"need lateral data over that range; the set spans {rough.y[0] * 1e3:g} .. {rough.y[-1] * 1e3:g} mm"
            )
        # linear interpolation across the lines (exact selection where a wanted line exists)
        heights = at_lateral_positions(rough, y_wanted).heights
        note = f"only lines at {', '.join(f'{v:g}' for v in spec.lateral_lines_mm)} mm"
        return rough.with_heights(heights, y=offsets, note=note), 0
    return rough, spec.line


def checked_numerics(track_numerics) -> TrackNumerics | None:
    """``track_numerics`` if a TrackNumerics or None, else one WheelrailError."""
    if track_numerics is not None and not isinstance(track_numerics, TrackNumerics):
        raise WheelrailError(
            f"a study's track_numerics must be TrackNumerics or None, got {type(track_numerics).__name__}"
        )
    return track_numerics


class RunCancelled(Exception):
    """A run stopped by its ``cancel`` event before its end (:func:`compute_run`): it has no summary."""


def compute_run(spec: RunSpec, cancel=None) -> RunSummary:
    """Run one spec (``keep_pressure=False``) and reduce it to its :class:`RunSummary` (the worker task).

    ``cancel``: a ``threading.Event`` that stops the run between two chunks of steps when set (from another
    thread); the run then raises :class:`RunCancelled`."""
    from wheelrail.core.engine import simulate
    from wheelrail.core.spectra.force import force_spectrum

    start = time.perf_counter()
    rough, line = study_roughness(spec)
    result = simulate(
        rough,
        wheel_roughness=study_wheel_roughness(spec),
        model=spec.model,
        line=line,
        params=spec.params,
        length=spec.length,
        run_in_length=spec.run_in_length,
        keep_pressure=False,
        cancel=cancel,
        track_numerics=spec.track_numerics,
    )
    if cancel is not None and cancel.is_set():
        raise RunCancelled(spec.label())
    centres, levels = force_spectrum(result)
    force = result.force
    return RunSummary(
        key=spec.key,
        band_centres=centres,
        levels=levels,
        force_mean=float(force.mean()),
        force_std=float(force.std()),
        force_min=float(force.min()),
        force_max=float(force.max()),
        loss_of_contact_steps=int(result.loss_of_contact_steps),
        n_steps=int(result.n_steps),
        run_time=time.perf_counter() - start,
    )
