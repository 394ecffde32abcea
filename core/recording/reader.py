"""Reading a recording back into a :class:`~wheelrail.core.engine.results.RunResult`, with rerun's own reader.

Uses ``rerun.chunk.RrdReader`` (rerun-sdk 0.41): the chunks of each entity are decoded from Arrow and
ordered by the ``step`` timeline. Only the entities declared in :mod:`wheelrail.core.recording.schema` are
read; anything else in the file is ignored.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.run_file import check_run
from wheelrail.core.recording.digest import DIGEST_KEY, RecordingDigest
from wheelrail.core.recording.schema import (
    APPLICATION_ID,
    EQUIVALENT,
    FIELD_OF_PATH,
    PARAMETERS,
    PRESSURE,
    SCALAR_PATHS,
    STEP_FIELDS,
    parameters_from_text,
    rerun_module,
)

__all__ = ["read_recording"]

FORCE_PATH = SCALAR_PATHS["force"]  # the series every recording has at every step: it defines the steps


@dataclass
class _Decoded:
    """What the chunks of a file hold, by entity: scalar blocks, pressure blocks, static components."""

    scalars: dict[str, list] = field(default_factory=dict)  # path -> [(steps, values, time_ns)]
    images: list = field(default_factory=list)  # [(steps, image buffers)]
    static: dict[str, dict] = field(default_factory=dict)  # path -> {component: last value}


def _component(batch, name: str):
    index = batch.schema.get_field_index(name)
    return None if index < 0 else batch.column(index)


def _chunks(source: Path) -> list:
    """The chunks of the file's wheelrail recording (one-line WheelrailErrors for bad files)."""
    rr = rerun_module()
    try:
        with warnings.catch_warnings():
            # a file without footer (e.g. a run killed while recording) warns before being scanned: the
            # scan below either works or raises, so the warning would only add a second line
            warnings.simplefilter("ignore")
            reader = rr.chunk.RrdReader(source)
            recordings = [entry for entry in reader.recordings() if entry.application_id == APPLICATION_ID]
            if not recordings:
                raise WheelrailError(f"{source} holds no wheelrail recording")
            return list(reader.stream(store=recordings[0]))
    except WheelrailError:
        raise
    except Exception as error:  # noqa: BLE001 - the Rust reader raises various types on a corrupt file
        text = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise WheelrailError(f"cannot read recording {source}: {text}") from None


def _decode(chunks: list) -> _Decoded:
    """Sort the chunks' Arrow columns by entity (static components keep their last row)."""
    decoded = _Decoded()
    for chunk in chunks:
        entity = chunk.entity_path.lstrip("/")
        batch = chunk.to_record_batch()
        if chunk.is_static:
            for name in batch.schema.names:
                if ":" in name:
                    column = batch.column(name)
                    value = column[len(column) - 1].as_py()  # each row is a batch: one value here
                    value = value[0] if isinstance(value, list) and value else value
                    decoded.static.setdefault(entity, {})[name] = value
            continue
        step_column = _component(batch, "step")
        if step_column is None:
            continue
        steps = np.asarray(step_column.to_numpy(zero_copy_only=False), dtype=np.int64)
        if entity in FIELD_OF_PATH:
            values = _component(batch, "Scalars:scalars")
            time = _component(batch, "time")
            time_ns = np.asarray(time.cast("int64").to_numpy(zero_copy_only=False)) if time is not None else None
            flat = np.asarray(values.flatten().to_numpy(zero_copy_only=False), dtype=float)
            decoded.scalars.setdefault(entity, []).append((steps, flat, time_ns))
        elif entity == PRESSURE:
            buffers = _component(batch, "DepthImage:buffer")
            if buffers is not None:
                decoded.images.append((steps, buffers))
    return decoded


def _pressure_maps(source: Path, decoded: _Decoded, n: int) -> np.ndarray | None:
    """The pressure maps (n, ny, nx) float32 if one was recorded at every step, else None."""
    image_format = decoded.static.get(PRESSURE, {}).get("DepthImage:format")
    if not decoded.images or image_format is None:
        return None
    width, height = int(image_format["width"]), int(image_format["height"])
    maps = np.full((n, height, width), np.nan, dtype=np.float32)
    seen = np.zeros(n, dtype=bool)
    for steps, buffers in decoded.images:
        blobs = buffers.flatten()  # one image buffer (blob) per row
        if len(blobs) != len(steps):
            raise WheelrailError(f"{source}: contact/pressure rows hold {len(blobs)} images for {len(steps)} steps")
        raw = np.asarray(blobs.flatten().to_numpy(zero_copy_only=False), dtype=np.uint8)
        inside = steps < n
        maps[steps[inside]] = raw.view(np.float32).reshape(len(steps), height, width)[inside]
        seen[steps[inside]] = True
    return maps if seen.all() else None


def _series(decoded: _Decoded, path: str, n: int) -> np.ndarray:
    out = np.full(n, np.nan)
    for steps, values, _ in decoded.scalars.get(path, []):
        if len(steps) != len(values) or (len(steps) and (steps.min() < 0 or steps.max() >= n)):
            raise WheelrailError(f"{path} holds values at steps outside the recorded 0..{n - 1} (damaged recording)")
        out[steps] = values
    return out


def _warn_if_incomplete(source: Path, meta: dict, n: int) -> None:
    """Warn (one line) when the file is not a finished recording of ``n`` steps.

    A finished recording's last parameters document holds ``recorded_steps`` (schema.parameters_document);
    files written before that key existed hold instead the run's ``loss_of_contact_steps``, which is known
    only at the end. A recording whose writer was killed (its hidden ``.partial`` file renamed by hand)
    holds neither: it reads as the steps it got, with this warning.
    """
    recorded = meta.get("recorded_steps")
    finished = recorded == n if "recorded_steps" in meta else meta.get("loss_of_contact_steps") is not None
    if not finished:
        of = "" if recorded is None else f" of the {recorded} recorded"
        warnings.warn(
            f"{source} is an incomplete recording: it holds {n} steps{of} and no mark of a finished run "
            "(its writer was stopped before the end); what is read is only the part of the run recorded",
            stacklevel=3,
        )


def read_recording(path: str | os.PathLike) -> RunResult:
    """Read a ``.rrd`` written by this package back into a :class:`RunResult`.

    Scalars come back exactly (float64); ``time`` is the ``time`` timeline (whole nanoseconds);
    ``pressure`` is filled only if a map was recorded at every step (``record_every`` 1), else None;
    ``equivalent_roughness`` equals ``roughness`` unless ``roughness/equivalent`` was recorded.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.rrd`` file.

    Returns
    -------
    RunResult
        The recorded run: header, per-step force, displacements, roughness and contact size, SI units.

    Raises
    ------
    WheelrailError
        The file is missing, not a rerun recording, or not a wheelrail recording.
    """
    source = Path(path)
    if not source.is_file():
        raise WheelrailError(f"recording {source} does not exist or is not a file")
    decoded = _decode_file(source)
    try:
        meta = parameters_from_text(decoded.static.get(PARAMETERS, {}).get("TextDocument:text"))
    except ValueError as error:  # the JSON of the parameters document is damaged
        raise WheelrailError(f"{source}: its parameters document is damaged ({error})") from None
    if not isinstance(meta, dict):
        raise WheelrailError(f"{source} is not a wheelrail recording (no parameters document)")
    if FORCE_PATH not in decoded.scalars:
        raise WheelrailError(f"{source} holds no contact force steps")
    force_parts = decoded.scalars[FORCE_PATH]
    all_steps = np.unique(np.concatenate([s for s, _, _ in force_parts]))
    n = len(all_steps)
    if not np.array_equal(all_steps, np.arange(n)):
        raise WheelrailError(f"{source}: the recorded steps are not 0..{n - 1} (incomplete recording)")
    _warn_if_incomplete(source, meta, n)
    time_ns = np.zeros(n, dtype=np.int64)
    for steps, _, part_ns in force_parts:
        if part_ns is None:
            raise WheelrailError(f"{source}: the contact force steps have no times (damaged recording)")
        time_ns[steps] = part_ns
    try:
        arrays = {field.name: _series(decoded, field.path, n) for field in STEP_FIELDS}
    except WheelrailError as error:
        raise WheelrailError(f"{source}: {error}") from None
    _check_digest(source, meta, decoded, time_ns, arrays)
    equivalent = _series(decoded, EQUIVALENT.path, n) if EQUIVALENT.path in decoded.scalars else arrays["roughness"]
    # a block whose r_eq equals r is not sent (steps.whole_run_columns): r there
    arrays[EQUIVALENT.name] = np.where(np.isnan(equivalent), arrays["roughness"], equivalent)
    try:
        header = RunHeader.from_dict(meta)
        window = [
            None if meta.get(key) is None else np.asarray(meta[key], float) for key in ("window_x_m", "window_y_m")
        ]
        loss = meta.get("loss_of_contact_steps")
        # an unfinished recording has no count: the steps of F = 0 it holds
        loss = int(np.count_nonzero(arrays["force"] == 0)) if loss is None else _count(loss)
    except (WheelrailError, ValueError, TypeError) as error:
        raise WheelrailError(f"{source}: {error}") from None
    result = RunResult(
        header=header,
        time=time_ns * 1e-9,
        **arrays,
        pressure=_pressure_maps(source, decoded, n),
        window_x=window[0],
        window_y=window[1],
        loss_of_contact_steps=loss,
    )
    check_run(result, source)
    return result


def _count(value) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"loss_of_contact_steps {value!r} is not a whole number")
    return value


def _decode_file(source: Path) -> _Decoded:
    """The file's chunks sorted by entity (one WheelrailError for a file whose columns do not decode)."""
    chunks = _chunks(source)
    try:
        return _decode(chunks)
    except Exception as error:  # noqa: BLE001 - a damaged column: pyarrow and numpy raise various types
        text = str(error).splitlines()[0] if str(error) else "a column does not decode"
        raise WheelrailError(f"cannot read recording {source}: {text} (damaged recording)") from None


def _check_digest(source: Path, meta: dict, decoded: _Decoded, time_ns: np.ndarray, arrays: dict) -> None:
    """The series read match the digest of the finished recording (``recording.digest``); a recording written
    before digests, or not finished, has none to check."""
    if DIGEST_KEY not in meta:
        return
    digest = RecordingDigest()
    digest.add("time_ns", time_ns)
    for series in STEP_FIELDS:
        digest.add(series.name, arrays[series.name])
    if decoded.images:
        rows = []
        for steps, buffers in decoded.images:
            raw = np.asarray(buffers.flatten().flatten().to_numpy(zero_copy_only=False), dtype=np.uint8)
            rows += list(zip(steps.tolist(), np.split(raw, len(steps)) if len(steps) else [], strict=True))
        rows.sort(key=lambda row: row[0])
        digest.add("pressure", np.concatenate([row[1] for row in rows]).view(np.float32))
    if meta[DIGEST_KEY] != digest.seal(meta):
        raise WheelrailError(
            f"{source}: its content does not match the SHA-256 digest written with it (damaged or edited recording)"
        )
