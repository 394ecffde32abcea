"""What a wheel/rail interaction run produces: one state per step (streamed) and the whole-run result.

These types are the contract between the time-stepping loop (``wheelrail.core.engine``) and its
consumers: the recording sink (rerun), the command line, studies and the explorer. All SI.
"""

from __future__ import annotations

import json
import math
import os
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.atomic import atomic_write
from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.files.run_file import check_run, content_digest
from wheelrail.core.models import MODELS  # noqa: F401 - re-exported: the registry holds the one list
from wheelrail.core.parameters import ModelParameters, as_dict, from_dict


@dataclass(frozen=True, kw_only=True)
class RunHeader:
    """What produced a run: the configuration every result, recording and plot carries.

    Attributes
    ----------
    model : str
        Contact model name (the registry in ``wheelrail.core.models``).
    line : int
        Roughness line number (-M..M; for a model with a lateral window the line it is centred on).
    roughness_name : str
        Bundled set name or file path the roughness came from.
    params : ModelParameters
        Every model parameter (SI): speed and element size are ``params.run``.
    run_in_length : float
        Length run before step 0 on smooth surfaces (discarded), m; ``run_in_time`` is its duration, s.
    wheel_roughness_name : str or None
        The wheel set added to the rail set ``roughness_name`` (combined roughness), or None: one set.
    wheel_model : str
        The wheel in the interaction (:data:`WHEEL_MODELS`): "2dof" (the paper's 2-DOF wheel), "modal" (a modal
        wheel's Green's function, ``wheelrail.core.modal_wheel.time_domain``) or "given" (a caller's system).
    wheel_profile : dict or None
        The modal wheel's cross-section (``WheelProfile.describe()``, SI; ``modal_wheel.profile_from_description``
        reads it back), or None (the 2-DOF wheel, or a modal wheel system given without its profile).
    track_numerics : dict
        The fields of the track's numerics that differ from ``TrackNumerics()``, as ``--track-numerics`` names
        them (``wheelrail.core.inputs.numerics.numerics_changes``); empty: the default numerics.
    """

    model: str
    line: int
    roughness_name: str
    params: ModelParameters = field(default_factory=ModelParameters)
    run_in_length: float = 0.0
    wheel_roughness_name: str | None = None
    wheel_model: str = "2dof"
    wheel_profile: dict | None = None
    track_numerics: dict = field(default_factory=dict)

    @property
    def speed(self) -> float:
        """Train speed v, m/s."""
        return self.params.run.speed

    @property
    def element_size(self) -> float:
        """Element length Delta x (the step along the rail), m."""
        return self.params.run.element_size

    @property
    def time_step(self) -> float:
        """dt = Delta x / v, s."""
        return self.params.run.time_step

    @property
    def run_in_time(self) -> float:
        """Duration of the run-in, s."""
        return self.run_in_length / self.speed

    def to_dict(self) -> dict:
        """Plain, JSON-ready view (keys carry their unit where it is not obvious)."""
        values = {
            "model": self.model,
            "line": self.line,
            "roughness": self.roughness_name,
            "speed_m_per_s": self.speed,
            "element_size_m": self.element_size,
            "time_step_s": self.time_step,
            "run_in_length_m": self.run_in_length,
            "run_in_time_s": self.run_in_time,
            "parameters": as_dict(self.params),
            "wheel_model": self.wheel_model,
        }
        if self.wheel_profile is not None:
            values["wheel_profile"] = self.wheel_profile
        if self.wheel_roughness_name is not None:
            values["wheel_roughness"] = self.wheel_roughness_name
        if self.track_numerics:
            values["track_numerics"] = dict(self.track_numerics)
        return values

    def wheel_words(self) -> str:
        """The interaction's wheel in words: the paper's 2-DOF wheel, or the modal wheel and its cross-section."""
        if self.wheel_model == "2dof":
            return "the paper's 2-DOF wheel"
        if self.wheel_model == "given":
            return "a wheel system given to prepare_run (not recorded)"
        shape = self.wheel_profile or {}
        if shape.get("kind") == "parametric":
            return (
                f"modal wheel {shape['wheel_radius'] * 2e3:g} mm (rim {shape['tyre_width'] * 1e3:g} x "
                f"{shape['tyre_depth'] * 1e3:g} mm, web {shape['web_thickness'] * 1e3:g} mm)"
            )
        if shape.get("kind") == "outline":
            return f"modal wheel from the outline {shape.get('name', 'outline')}"
        return "modal wheel (its cross-section damaged)"

    def description(self) -> str:
        """One line for people: set, line, model, speed, preload, contact radii and the track's supports."""
        contact, support = self.params.contact, self.params.track.support
        wheel = f" + wheel set {self.wheel_roughness_name}" if self.wheel_roughness_name is not None else ""
        tread = contact.wheel_transverse_radius
        return (
            f"{self.roughness_name}{wheel} line {self.line}, model {self.model}, {self.speed * 3.6:g} km/h, "
            f"preload {contact.preload / 1e3:g} kN, element {self.element_size * 1e3:g} mm; wheel radius "
            f"{contact.radius_along * 1e3:g} mm, rail crown {contact.crown_radius * 1e3:g} mm, tread "
            f"{'flat' if tread == float('inf') else f'{tread * 1e3:g} mm'}; track {self.params.track.n_bays} bays "
            f"of {support.sleeper_spacing:g} m, pads {support.pad_stiffness / 1e6:g} MN/m, ballast "
            f"{support.ballast_stiffness / 1e6:g} MN/m, sleepers {support.sleeper_mass:g} kg; {self.wheel_words()}"
            f"{self.irregularity_words()}{'; track numerics ' + self.numerics_words() if self.track_numerics else ''}"
        )

    def numerics_words(self) -> str:
        """The track's numerics that differ from the default, as ``--track-numerics`` takes them
        ("elements_per_bay=32, time_step_us=2.5"), or "the default"."""
        from wheelrail.core.inputs.numerics import numerics_words

        return numerics_words(self.track_numerics)

    def irregularity_words(self) -> str:
        """The run's discrete irregularities in words ("; irregularities (Hertz on the trajectory): flat 50 mm
        ..."), or "" for a run without."""
        run = self.params.run
        if not run.irregularities:
            return ""
        from wheelrail.core.irregularities.shapes import words

        return f"; irregularities (Hertz on the {run.irregularity_input}): {', '.join(map(words, run.irregularities))}"

    def csv_comment(self, what: str) -> str:
        """Two ``#`` comment lines heading a CSV export: ``what`` and :meth:`description`, then the whole
        configuration (:meth:`to_dict`) as strict JSON."""
        return f"# wheelrail {what}: {self.description()}\n# configuration (SI): {strict_json(self.to_dict())}\n"

    @classmethod
    def from_dict(cls, values: dict) -> RunHeader:
        """Inverse of :meth:`to_dict` (parameters validated again; headers written before a field existed read
        with its default); a damaged header is a WheelrailError."""
        if not isinstance(values, dict):
            raise WheelrailError(f"run header is damaged: a JSON object expected, got {type(values).__name__}")
        wheel, profile = values.get("wheel_roughness"), values.get("wheel_profile")
        missing = [key for key in ("model", "line", "roughness") if key not in values]
        if missing:
            raise WheelrailError(f"run header is incomplete: no {', '.join(missing)}")
        try:
            header = cls(
                model=_checked_model(values["model"]),
                line=_whole_number("line", values["line"]),
                roughness_name=str(values["roughness"]),
                params=from_dict(ModelParameters, values.get("parameters", {})),
                run_in_length=_length("run_in_length_m", values.get("run_in_length_m", 0.0)),
                wheel_roughness_name=None if wheel is None else str(wheel),
                wheel_model=_checked_wheel_model(values.get("wheel_model") or "2dof"),
                wheel_profile=None if profile is None else dict(profile),
                track_numerics=_numerics_changes(values.get("track_numerics")),
            )
        except WheelrailError as error:
            raise WheelrailError(f"run header is damaged: {error}") from None
        except (TypeError, ValueError) as error:
            raise WheelrailError(f"run header is damaged: {error}") from None
        header._check_derived(values)
        return header

    def _check_derived(self, values: dict) -> None:
        """The header's derived values (speed, element, time step, run-in time) agree with its parameters."""
        for key, own in (
            ("speed_m_per_s", self.speed),
            ("element_size_m", self.element_size),
            ("time_step_s", self.time_step),
            ("run_in_time_s", self.run_in_time),
        ):
            given = values.get(key, own)
            number = isinstance(given, int | float) and not isinstance(given, bool)
            if not number or not math.isclose(given, own, rel_tol=1e-9):
                raise WheelrailError(
                    f"run header is damaged: its {key} {given!r} disagrees with its parameters' {own:.10g}"
                )


WHEEL_MODELS = ("2dof", "modal", "given")
"""The interaction's wheels (``RunHeader.wheel_model``): the paper's 2-DOF wheel, the modal wheel of a recorded
cross-section, a wheel system the caller built (``prepare.interaction_wheel``)."""


def _checked_wheel_model(value) -> str:
    if value not in WHEEL_MODELS:
        raise ValueError(f"wheel_model {value!r} is not one of {', '.join(WHEEL_MODELS)}")
    return str(value)


def _checked_model(value) -> str:
    """A contact model's name the registry knows (the built-in ones and the installed plug-ins)."""
    from wheelrail.core.models import model_names

    if not isinstance(value, str) or value not in model_names():
        raise ValueError(f"model {value!r} is not a known contact model ({', '.join(model_names())})")
    return value


def _numerics_changes(value) -> dict:
    """A header's ``track_numerics`` checked as ``--track-numerics`` checks them (None, as before they were
    recorded: the default)."""
    from wheelrail.core.inputs.numerics import numerics_changes, numerics_from_changes

    if value is None:
        return {}
    if not isinstance(value, dict):
        raise ValueError(f"track_numerics {value!r} is not a JSON object")
    return numerics_changes(numerics_from_changes(value))


def _whole_number(key: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value) or value != int(value):
        raise ValueError(f"{key} {value!r} is not a whole number")
    return int(value)


def _length(key: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value) or value < 0:
        raise ValueError(f"{key} {value!r} is not a length of zero or more (m)")
    return float(value)


@dataclass(frozen=True, slots=True)
class StepState:
    """State of one time step, as streamed while a run goes on.

    Attributes
    ----------
    step : int
        Step index from 0 (after the run-in).
    time : float
        t = step * dt, s.
    position : float
        Wheel position along the rail, x = v t (plus the start position), m.
    force : float
        Normal contact force F_n, N (0 when contact is lost).
    xi_wheel, xi_rail : float
        Wheel and rail displacement at the contact point, m, positive downwards (paper's z-axis).
        xi_wheel - xi_rail is the approach.
    roughness : float
        Combined roughness r = r_W - r_R under the wheel centre on the chosen line, m (model input;
        for ``hertz-winkler``/``hertz-average`` the unfiltered line, see ``RunResult.equivalent_roughness``).
    contact_length : float
        Length of the contact in the rolling direction, m (2D: compressed bedding; Hertz variants: 2a of
        the Hertz law at the current force; 3D: extent of the contact elements along x on the centre row).
    contact_area : float
        Contact area, m^2. 3D: the elements in contact (p > 0) times the element area, a staircase of whole
        elements around the patch that exceeds Hertz's pi a b on smooth surfaces by 2.3-8.5 % at 65 kN on the
        1 mm grid (0.5-16 % over 20-200 kN and the geometries of validation/contact_geometry_accuracy.py;
        0.5-3.7 % at 0.5 mm); Hertz variants: pi a b of the Hertz law at the step's force; 2D: nan.
    pressure : ndarray or None
        3D only: contact pressure on the window, Pa, shape (ny, nx), rows = lateral y', columns = x'.
    """

    step: int
    time: float
    position: float
    force: float
    xi_wheel: float
    xi_rail: float
    roughness: float
    contact_length: float
    contact_area: float
    pressure: np.ndarray | None = None


class HeaderView:
    """What produced a run, read from its ``header`` (a :class:`RunHeader`): shared by ``RunResult`` and the
    interaction's ``InteractionRun``."""

    header: RunHeader

    @property
    def model(self) -> str:
        return self.header.model

    @property
    def line(self) -> int:
        return self.header.line

    @property
    def roughness_name(self) -> str:
        return self.header.roughness_name

    @property
    def wheel_roughness_name(self) -> str | None:
        return self.header.wheel_roughness_name

    @property
    def speed(self) -> float:
        return self.header.speed

    @property
    def element_size(self) -> float:
        return self.header.element_size

    @property
    def time_step(self) -> float:
        return self.header.time_step

    @property
    def run_in_length(self) -> float:
        return self.header.run_in_length

    @property
    def run_in_time(self) -> float:
        return self.header.run_in_time


@dataclass(frozen=True, eq=False)
class RunResult(HeaderView):
    """Whole-run result of the interaction loop (arrays over steps, SI units).

    Attributes
    ----------
    header : RunHeader
        What produced the run (model, line, roughness, every parameter); ``model``, ``line``, ``speed``,
        ``element_size``, ``time_step``, ``roughness_name``, ``run_in_length``, ``run_in_time`` and
        ``parameters`` (a plain nested dict) read it.
    time, x, force, xi_wheel, xi_rail, roughness, contact_length, contact_area : ndarray (steps,)
        As in :class:`StepState`.
    equivalent_roughness : ndarray (steps,)
        Roughness the contact model actually saw on the line (Hertz variants: r_eq; 2D/3D: r).
    pressure : ndarray (steps, ny, nx) float32 or None
        Pressure maps of a model with a lateral window (3D), Pa (None for other models, or when not kept).
    window_x, window_y : ndarray or None
        Window element centres relative to the wheel centre, m (3D).
    loss_of_contact_steps : int
        Number of steps with F = 0.
    """

    header: RunHeader
    time: np.ndarray
    x: np.ndarray
    force: np.ndarray
    xi_wheel: np.ndarray
    xi_rail: np.ndarray
    roughness: np.ndarray
    contact_length: np.ndarray
    contact_area: np.ndarray
    equivalent_roughness: np.ndarray
    pressure: np.ndarray | None = None
    window_x: np.ndarray | None = None
    window_y: np.ndarray | None = None
    loss_of_contact_steps: int = 0

    @property
    def parameters(self) -> dict:
        """All model parameters as a nested plain dict (SI), for provenance."""
        return as_dict(self.header.params)

    @property
    def n_steps(self) -> int:
        return len(self.time)

    def state(self, step: int) -> StepState:
        """The :class:`StepState` of one step (e.g. to replay a finished run)."""
        if not 0 <= step < self.n_steps:
            raise WheelrailError(f"step {step} outside the run (0..{self.n_steps - 1})")
        return StepState(
            step=step,
            time=float(self.time[step]),
            position=float(self.x[step]),
            force=float(self.force[step]),
            xi_wheel=float(self.xi_wheel[step]),
            xi_rail=float(self.xi_rail[step]),
            roughness=float(self.roughness[step]),
            contact_length=float(self.contact_length[step]),
            contact_area=float(self.contact_area[step]),
            pressure=None if self.pressure is None else self.pressure[step],
        )

    def save_npz(self, path: str | os.PathLike) -> Path:
        """Write the arrays (time, x, force, xi_wheel, xi_rail, pressure for 3D) and the header atomically."""
        target = Path(path)
        if not target.parent.is_dir():
            raise WheelrailError(f"cannot write {target}: folder {target.parent} does not exist")
        arrays = {name: getattr(self, name) for name in _STEP_ARRAYS}
        if self.pressure is not None:
            arrays["pressure"] = self.pressure
            arrays["window_x"] = self.window_x
            arrays["window_y"] = self.window_y
        metadata = strict_json({**self.header.to_dict(), "loss_of_contact_steps": self.loss_of_contact_steps})
        digest = content_digest(metadata, arrays)  # checked on reading: a flipped byte or an edit is refused
        return atomic_write(
            target, lambda handle: np.savez(handle, metadata=np.array(metadata), digest=np.array(digest), **arrays)
        )

    def save_csv(self, path: str | os.PathLike) -> Path:
        """Write the time history as CSV atomically: a comment naming the configuration
        (:meth:`RunHeader.csv_comment`), then ``time_s, x_m, force_N, xi_wheel_m, xi_rail_m, roughness_m,
        equivalent_roughness_m`` per step (the roughness under the wheel as given, and as the contact model
        sees it), 10 significant digits."""
        target = Path(path)
        columns = ("time_s", "x_m", "force_N", "xi_wheel_m", "xi_rail_m", "roughness_m", "equivalent_roughness_m")
        table = np.column_stack(
            [self.time, self.x, self.force, self.xi_wheel, self.xi_rail, self.roughness, self.equivalent_roughness]
        )

        def write(handle) -> None:
            handle.write(self.header.csv_comment("run time history"))
            handle.write(",".join(columns) + "\n")
            np.savetxt(handle, table, fmt="%.10g", delimiter=",")

        return atomic_write(target, write, mode="w", encoding="utf-8")

    @classmethod
    def load_npz(cls, path: str | os.PathLike) -> RunResult:
        """Read a file written by :meth:`save_npz`; anything else is one WheelrailError naming the file.

        The file's content must match the SHA-256 digest written with it (files written before digests read
        without that check) and hold a run the package could have made
        (:func:`wheelrail.core.files.run_file.check_run`).
        """
        target = Path(path)
        stored = _npz_arrays(target)
        metadata, digest = stored.pop("metadata"), stored.pop("digest", None)
        if metadata.shape != () or metadata.dtype.kind != "U":
            raise WheelrailError(f"{target}: its metadata is not text; not a wheelrail run file (damaged or edited)")
        if digest is not None and (digest.shape != () or str(digest) != content_digest(str(metadata), stored)):
            raise WheelrailError(
                f"{target}: its content does not match the SHA-256 digest written with it (damaged or edited)"
            )
        try:
            meta = json.loads(str(metadata))
        except ValueError as error:
            raise WheelrailError(f"{target}: its metadata is not JSON ({error}); damaged or edited") from None
        arrays = {}
        for name in _STEP_ARRAYS:
            if name not in stored:
                raise WheelrailError(f"{target}: no {name!r} array; not a wheelrail run file")
            if stored[name].dtype.kind not in "fiu":
                raise WheelrailError(f"{target}: the {name!r} array holds {stored[name].dtype} values, not numbers")
            arrays[name] = np.asarray(stored[name], dtype=float)
        lengths = {array.shape for array in arrays.values()}
        if len(lengths) != 1 or len(next(iter(lengths))) != 1:
            raise WheelrailError(f"{target}: the run's arrays have different lengths or are not 1D")
        optional = {name: stored[name] for name in ("pressure", "window_x", "window_y") if name in stored}
        try:
            header = RunHeader.from_dict(meta)
            loss = _whole_number("loss_of_contact_steps", meta.get("loss_of_contact_steps", 0))
        except (WheelrailError, ValueError) as error:
            raise WheelrailError(f"{target}: {error}") from None
        result = cls(header=header, loss_of_contact_steps=loss, **arrays, **optional)
        check_run(result, target)
        return result


def _npz_arrays(target: Path) -> dict:
    """Every array of a run's ``.npz`` (one WheelrailError naming the file, in words, if it cannot be read)."""
    known = {"metadata", "digest", *_STEP_ARRAYS, "pressure", "window_x", "window_y"}
    try:
        with np.load(target, allow_pickle=False) as data:
            unknown = sorted(set(data.files) - known)
            if unknown:
                raise WheelrailError(f"{target}: holds {', '.join(map(repr, unknown))}, which no run file has")
            if "metadata" not in data.files:
                raise WheelrailError(f"{target}: no run metadata; not a wheelrail run file")
            return {name: data[name] for name in data.files}
    except WheelrailError:
        raise
    except FileNotFoundError:
        raise WheelrailError(f"run file {target} does not exist") from None
    except IsADirectoryError:
        raise WheelrailError(f"run file {target} is a folder, not a file") from None
    except Exception as error:  # noqa: BLE001 - any unreadable file is the user's, named in one line
        if not zipfile.is_zipfile(target):  # numpy's reason would be its pickle advice or zipfile's words
            raise WheelrailError(
                f"{target}: not a readable wheelrail run file: not a NumPy .npz archive (corrupt or another format)"
            ) from None
        reason = str(error).splitlines()[0] if str(error) else "unreadable"
        raise WheelrailError(
            f"{target}: not a readable wheelrail run file ({reason}); damaged or another format"
        ) from None


def result_of_run(label: str, value) -> RunResult:
    """``value`` if it is a finished run (:class:`RunResult`), else one WheelrailError naming ``label``."""
    if not isinstance(value, RunResult):
        raise WheelrailError(f"{label} must be a finished run (RunResult), got {type(value).__name__}")
    return value


_STEP_ARRAYS = (
    "time",
    "x",
    "force",
    "xi_wheel",
    "xi_rail",
    "roughness",
    "contact_length",
    "contact_area",
    "equivalent_roughness",
)
