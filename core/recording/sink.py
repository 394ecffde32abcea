"""Writing a run into a recording while it streams (:class:`RecordingSink`) or in one go (:func:`record_result`).

The sink records what it is given: the run's :class:`~wheelrail.core.results.RunHeader`, the steps, and
(optionally) the :class:`~wheelrail.core.roughness.RoughnessSet` whose lines around the run's line become
``roughness/lines``; it never loads anything from disk itself.

Scalars are sent as columns (``rr.send_columns``) in blocks of ``chunk_steps`` steps; pressure maps are
sent as a column of image buffers (one static ``ImageFormat``), decimated with ``record_every``.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from wheelrail.core.errors import Name, WheelrailError
from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.inputs.declared import choice
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.recording.columns import scalar_column
from wheelrail.core.recording.digest import DIGEST_KEY, RecordingDigest
from wheelrail.core.recording.outputs import Outputs, ViewerUnreachable
from wheelrail.core.recording.pressure import ContactPatch, hertz_geometry, hertz_semi_axes
from wheelrail.core.recording.schema import (
    EQUIVALENT,
    FORCE_SPECTRUM,
    PARAMETERS,
    ROUGHNESS_LINES,
    ROUGHNESS_LINES_SHOWN,
    SCALAR_FIELDS,
    SOUND_POWER,
    SOUND_POWER_COMPONENTS,
    STEP_FIELDS,
    band_chart,
    default_blueprint,
    parameters_document,
    parameters_text,
    rerun_module,
    time_columns,
)
from wheelrail.core.results import RunHeader, RunResult, StepState

__all__ = ["RecordingSink", "record_result"]

DEFAULT_CHUNK_STEPS = 2048  # steps buffered before one columnar send (~10 ms of work; 70 ms of a 3D run)
SURFACE_EVERY = 4  # the pressure surface mesh is recorded at every 4th recorded pressure map

_ROW_NAMES = ("step", "time", *(field.name for field in STEP_FIELDS))
# one StepState -> one buffered row, in _ROW_NAMES order. Compiled from the field list: attribute reads
# in a function are specialised by Python 3.11+, so this takes 0.30 us a step where operator.attrgetter
# takes 0.45 us (measured on the 8 000 synthetic steps of benchmarks/recording.py)
_ROW = eval(  # noqa: S307 - the source is built from this package's own constant field names
    "lambda state: (state.step, state.time, " + ", ".join(f"state.{field.state}" for field in STEP_FIELDS) + ")"
)


def _check_counts(record_every, surface_every, chunk_steps) -> None:
    checks = (("record_every", record_every), ("surface_every", surface_every), ("chunk_steps", chunk_steps))
    for name, value in checks:
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise WheelrailError("not a whole number of at least 1", parameter=name, value=value, minimum=1)


class _RoughnessLines:
    """The lines k-3 .. k+3 of a roughness set around the run's line k, sampled at the wheel positions."""

    def __init__(self, roughness, line: int) -> None:
        numbers = [int(k) for k in roughness.line_numbers]
        self.shown = [k for k in range(line - ROUGHNESS_LINES_SHOWN, line + ROUGHNESS_LINES_SHOWN + 1) if k in numbers]
        self.rows = [roughness.row_of_line(k) for k in self.shown]
        self.roughness = roughness

    def heights(self, x: np.ndarray) -> np.ndarray:
        """Heights (steps, lines) of the shown lines at wheel positions x (periodic for a wheel), m."""
        rough = self.roughness
        period = rough.length if rough.periodic else None
        return np.stack([np.interp(x, rough.x, rough.heights[r], period=period) for r in self.rows], axis=1)


class RecordingSink:
    """Records a run to a ``.rrd`` file and/or a live rerun viewer, step by step or from a finished result.

    Use it as the loop's callback: ``InteractionRun.run(sink)`` hands it each chunk of steps as arrays
    (:meth:`log_block`), a callback that takes a :class:`StepState` (``sink(state)``, :meth:`log_step`) buffers one
    step; every ``chunk_steps`` steps the block is sent as columns, the same rows either way. Typical use::

        sink = RecordingSink(rrd="run.rrd")            # path checked here, before the run
        run = prepare_run(roughness, model="3d", length=0.5)
        sink.start(run, roughness=roughness)            # header, window, Hertz circle, roughness lines
        result = run.run(sink)                          # or simulate(..., callback=sink)
        sink.finish(result)                             # last block, force spectrum, file closed

    :func:`record_result` writes a finished :class:`RunResult` in one go.

    Parameters
    ----------
    rrd : str or path, optional
        ``.rrd`` file to write. It is written under a temporary name in the same folder and renamed on
        :meth:`finish`, so an interrupted run never leaves a half-written file under the final name.
    spawn : bool
        Start a rerun viewer (``rerun`` executable of rerun-sdk) and stream to it.
    connect : str, optional
        Address of a running viewer, ``HOST:PORT`` or a ``rerun+http://HOST:PORT/proxy`` URL.
    record_every : int
        Record the pressure map (image) of every N-th step; scalars are recorded every step.
    surface_every : int
        Record the pressure surface mesh at every M-th recorded map, i.e. every ``record_every * M`` steps.
    chunk_steps : int
        Steps per columnar send.
    description : str
        Name of the recording shown by the viewer.
    sound_power : bool or str
        Add the run's rolling-noise sound-power spectra at :meth:`finish` (``--sound-power``), and their views;
        a value of the ``noise_wheel_model`` choice (``wheelrail.core.inputs.declared.CHOICES``: "directive", "modal")
        also says whose wheel power (True: the directive's L_H,veh), stated as ``wheel_transfer_source``.
    pressure_maps : bool
        The run has pressure maps (a model with ``ModelTraits.pressure_map``: ``3d``): the layout the viewer opens
        with has the pressure views (:func:`~.schema.default_blueprint`).
    names : mapping of str to Name, optional
        How the front end names the inputs (``WheelrailError.render``), for the warning when the sound power
        asked for cannot be computed (the run too short); None: the API's names.
    """

    def __init__(
        self,
        *,
        rrd: str | os.PathLike | None = None,
        spawn: bool = False,
        connect: str | None = None,
        record_every: int = 1,
        surface_every: int = SURFACE_EVERY,
        chunk_steps: int = DEFAULT_CHUNK_STEPS,
        description: str = "",
        sound_power: bool = False,
        pressure_maps: bool = True,
        names: Mapping[str, Name] | None = None,
    ) -> None:
        _check_counts(record_every, surface_every, chunk_steps)
        self.names = dict(names or {})  # how the front end names its options, for the warnings it is given
        self.sound_power = bool(sound_power)  # finish() adds the run's sound-power spectra (needs the RunResult)
        wheel = sound_power if isinstance(sound_power, str) else "directive"
        self.sound_power_wheel = choice("noise_wheel_model").check(wheel)  # whose wheel power the noise takes
        self.record_every = int(record_every)
        self.surface_every = int(surface_every)
        self.chunk_steps = int(chunk_steps)
        self.description = description
        blueprint = default_blueprint(pressure=pressure_maps, sound_power=self.sound_power)
        self._outputs = Outputs(rrd=rrd, spawn=spawn, connect=connect, description=description, blueprint=blueprint)
        self.path = self._outputs.path
        self.recording_id = self._outputs.recording_id
        self.stream = self._outputs.stream
        self._rr = rerun_module()
        self._patch = ContactPatch(self.stream, record_every=self.record_every, surface_every=self.surface_every)
        self._header: RunHeader | None = None
        self._loss_of_contact_steps: int | None = None
        self._started = False
        self._closed = False
        self._lines: _RoughnessLines | None = None  # roughness/lines, when a set was given
        self._rows: list[tuple] = []  # buffered steps: (step, time, the STEP_FIELDS of StepState)
        self._map_steps: list[int] = []  # steps of the buffered pressure maps to record
        self._block: np.ndarray | None = None  # (capacity, ny, nx) float32: the buffered maps, in _map_steps order
        self._blocks: list[tuple] = []  # buffered blocks of log_block: (steps, columns, map steps, maps)
        self._steps_recorded = 0
        self._force: list[float] = []
        self._time_step: float | None = None  # measured from the recorded times (when no header says it)
        self._digest = RecordingDigest()  # of every series sent, sealed in the final parameters document

    @property
    def header(self) -> RunHeader | None:
        """What produced the run being recorded (None until :meth:`start` or :meth:`finish` gave it)."""
        return self._header

    # -- context manager: a failure inside discards the partial file -----------------------------------
    def __enter__(self) -> RecordingSink:
        return self

    def __exit__(self, kind, value, traceback) -> None:
        if kind is None:
            if not self._closed:
                self.finish()
        else:
            self.abort()

    # -- run description ---------------------------------------------------------------------------------
    def start(self, run=None, *, roughness=None) -> None:
        """Log the once-per-run data: parameters document, Hertz circle, pressure-window geometry.

        Parameters
        ----------
        run : InteractionRun, RunResult or RunHeader, optional
            What is recorded: its ``header`` (model, line, speed, element size, roughness name, every
            parameter) and, for a run with a lateral window, ``window_x`` / ``window_y`` (m, element
            centres relative to the wheel centre).
        roughness : RoughnessSet, optional
            The set the run rolls over: its lines around the run's line are recorded as
            ``roughness/lines``. Without it that entity is not recorded.

        Raises
        ------
        WheelrailError
            If the recording is already finished.
        """
        if self._closed:
            raise WheelrailError("the recording is already finished")
        try:
            self._describe(run)
            self._set_roughness(roughness)
            self._log_parameters()
            self._patch.log_circle()
            self._started = True
        except BaseException:
            self.abort()
            raise

    def _describe(self, run) -> None:
        """Take the header and window of ``run`` (an InteractionRun, a RunResult or a RunHeader)."""
        if run is not None:
            header = run if isinstance(run, RunHeader) else run.header
            if not isinstance(header, RunHeader):
                raise WheelrailError(f"a recording needs a run or its RunHeader, got {type(run).__name__}")
            self._header = header
            if not isinstance(run, RunHeader):
                self._patch.set_window(run.window_x, run.window_y)
            if isinstance(run, RunResult):
                self._loss_of_contact_steps = run.loss_of_contact_steps
        self._patch.set_geometry(self._geometry(), log=False, semi_axes=self._semi_axes())

    def _contact(self) -> ContactParameters:
        return self._header.params.contact if self._header is not None else ContactParameters()

    def _geometry(self) -> tuple[float, float]:
        return hertz_geometry(self._contact())

    def _semi_axes(self) -> tuple[float, float] | None:
        return hertz_semi_axes(self._contact())

    def _set_roughness(self, roughness) -> None:
        if roughness is None or self._lines is not None:
            return
        lines = _RoughnessLines(roughness, self._header.line if self._header is not None else 0)
        if not lines.shown:
            return
        self._lines = lines
        self.stream.log(
            ROUGHNESS_LINES,
            self._rr.SeriesLines(names=[f"line {k} height (m)" for k in lines.shown]),
            static=True,
            strict=True,
        )

    def _log_parameters(self, *, final: bool = False) -> None:
        """The parameters document; ``final``: with the steps recorded, the mark of a finished recording."""
        patch = self._patch
        document = parameters_document(
            self._header,
            time_step=self._time_step,
            loss_of_contact_steps=self._loss_of_contact_steps,
            decimation=(self.record_every, self.surface_every),
            window=patch.window,
            geometry=patch.geometry,
            recorded_steps=self._steps_recorded if final else None,
        )
        if final:
            document[DIGEST_KEY] = self._digest.seal(document)
        text = parameters_text(document, self.description)
        self.stream.log(PARAMETERS, self._rr.TextDocument(text, media_type="text/markdown"), static=True, strict=True)

    # -- per step -------------------------------------------------------------------------------------------
    def __call__(self, state: StepState) -> None:
        """Buffer one step (the loop's callback); sends a block every ``chunk_steps`` steps."""
        if self._closed:
            raise WheelrailError("the recording is already finished")
        if self._blocks:
            self.flush()  # blocks given before go first
        self._rows.append(_ROW(state))
        if state.pressure is not None and state.step % self.record_every == 0:
            self._keep_map(state.step, state.pressure)
        if len(self._rows) >= self.chunk_steps:
            self.flush()

    def _keep_map(self, step: int, pressure: np.ndarray) -> None:
        """Copy one map into the block of maps to send (float32; the loop may reuse its buffer). A new block
        is allocated after each send: rerun holds the sent one until it is encoded (:mod:`.columns`)."""
        count = len(self._map_steps)
        if self._block is None or count == len(self._block) or self._block.shape[1:] != np.shape(pressure):
            if count:
                self.flush()
            capacity = self.chunk_steps // self.record_every + 1
            self._block = np.empty((capacity, *np.shape(pressure)), dtype=np.float32)
            count = 0
        self._block[count] = pressure
        self._map_steps.append(step)

    log_step = __call__  # the same, under a name that reads well as ``callback=sink.log_step``

    def log_block(self, first: int, block: RunResult) -> None:
        """Buffer the consecutive steps ``first``, ``first + 1``, ... of ``block`` at once; what the steps one by
        one would record (``InteractionRun.run`` gives a sink its steps this way, :meth:`InteractionRun.blocks`).
        A block's arrays are not kept: its pressure maps to record are copied."""
        if self._closed:
            raise WheelrailError("the recording is already finished")
        if self._rows:
            self.flush()  # steps given one by one before go first
        columns, _ = _whole_run_columns(block, slice(None))  # r_eq is not streamed, as step by step
        steps = first + np.arange(block.n_steps, dtype=np.int64)
        pressure_steps = pressure = None
        if block.pressure is not None:
            keep = steps % self.record_every == 0
            pressure_steps, pressure = steps[keep], np.array(block.pressure[keep], dtype=np.float32)
        self._blocks.append((steps, columns, pressure_steps, pressure))
        if sum(len(steps) for steps, *_ in self._blocks) >= self.chunk_steps:
            self.flush()

    def flush(self) -> None:
        """Send the buffered steps as one block of columns."""
        if self._blocks:
            self._flush_blocks()
        if not self._rows:
            return
        table = np.array(self._rows, dtype=float)  # (steps, fields): one conversion for the whole block
        count = len(self._map_steps)
        pressure_steps = np.array(self._map_steps, dtype=np.int64)
        pressure = self._block[:count] if count else None
        self._rows, self._map_steps, self._block = [], [], None
        columns = {name: np.ascontiguousarray(table[:, i]) for i, name in enumerate(_ROW_NAMES)}
        steps = columns.pop("step").astype(np.int64)
        self._send_block(steps, columns, pressure_steps, pressure)

    def _flush_blocks(self) -> None:
        """Send the blocks given to :meth:`log_block` as one block of columns."""
        blocks, self._blocks = self._blocks, []
        steps = np.concatenate([block[0] for block in blocks])
        columns = {name: np.concatenate([block[1][name] for block in blocks]) for name in blocks[0][1]}
        pressure_steps = pressure = None
        if blocks[0][3] is not None:
            pressure_steps = np.concatenate([block[2] for block in blocks])
            pressure = np.concatenate([block[3] for block in blocks])
        self._send_block(steps, columns, pressure_steps, pressure)

    def _send_block(self, steps, columns: dict, pressure_steps=None, pressure=None, equivalent=None) -> None:
        """Send one block of steps: scalars at every step, pressure maps at ``pressure_steps``.

        ``columns`` holds ``time`` and every ``STEP_FIELDS`` name (arrays over the block, SI);
        ``equivalent`` is r_eq where it differs from r (whole-run export).
        """
        if not self._started:
            self.start()
        rr = self._rr
        time, x = columns["time"], columns["x"]
        if self._time_step is None and len(time) > 1:
            self._time_step = float(time[1] - time[0])
        self._force.extend(columns["force"].tolist())
        if self._steps_recorded == 0:
            for field in SCALAR_FIELDS:
                self.stream.log(
                    field.path, rr.SeriesLines(names=[field.legend], colors=[field.colour]), static=True, strict=True
                )
        indexes = time_columns(steps, time, x)  # shared by every entity of the block
        self._digest.add("time_ns", np.round(np.asarray(time) * 1e9).astype(np.int64))
        for field in STEP_FIELDS:
            values = columns[field.name]
            self._digest.add(field.name, values)
            finite = np.isfinite(values)
            if finite.all():
                self.stream.send_columns(field.path, indexes, [scalar_column(values)], strict=True)
            elif finite.any():  # e.g. no contact area in 2D: leave those steps out rather than log NaN
                self.stream.send_columns(
                    field.path,
                    time_columns(steps[finite], time[finite], x[finite]),
                    [scalar_column(values[finite])],
                    strict=True,
                )
        if equivalent is not None:
            self.stream.send_columns(EQUIVALENT.path, indexes, [scalar_column(equivalent)], strict=True)
        if self._lines is not None:
            self._send_roughness_lines(x, indexes)
        self._steps_recorded += len(steps)
        if pressure is not None and len(pressure):
            self._digest.add("pressure", pressure)
            where = np.searchsorted(steps, pressure_steps)
            element_size = self._header.element_size if self._header is not None else 1e-3
            self._patch.send(pressure_steps, time[where], x[where], pressure, element_size=element_size)

    def _send_roughness_lines(self, x, indexes) -> None:
        self.stream.send_columns(ROUGHNESS_LINES, indexes, [scalar_column(self._lines.heights(x))], strict=True)

    # -- end --------------------------------------------------------------------------------------------------
    def finish(self, result: RunResult | None = None, *, roughness=None) -> Path | None:
        """Send the last block, the force spectrum and the final parameters; close and rename the file.

        Parameters
        ----------
        result : RunResult, optional
            The finished run: its header and ``loss_of_contact_steps`` complete the parameters document
            and its force gives the spectrum (else the recorded steps' force is used).
        roughness : RoughnessSet, optional
            For a sink started without one: ``roughness/lines`` is then sent over the whole run.

        Returns
        -------
        pathlib.Path or None
            The ``.rrd`` file written, if any.

        Raises
        ------
        WheelrailError
            If the ``.rrd`` file could not be written (one line naming it and why: "no space left on device
            writing r.rrd"; nothing is left under its name), or, as :class:`~.outputs.ViewerUnreachable`, if the
            rerun viewer the sink streams to could not be reached (the file is written all the same).
        """
        if self._closed:
            return self.path
        try:
            self.flush()
            if result is not None:
                self._complete(result, roughness)
            elif self._patch.geometry is None:
                self._patch.set_geometry(self._geometry(), log=False, semi_axes=self._semi_axes())
            self._log_parameters(final=True)
            self._log_spectrum(result)
            if self.sound_power and result is not None:
                self._log_sound_power(result)
        except BaseException:
            self.abort()
            raise
        self._closed = True
        unreachable = self._outputs.disconnect()
        failed = self._outputs.file_failure(unreachable)
        if failed is not None:  # e.g. a full disk: no recording, and no viewer blamed for it
            self._outputs.discard()
            raise failed
        self._outputs.publish()
        if unreachable and self._outputs.viewers:
            written = f"the recording was written to {self.path}, but " if self.path is not None else ""
            hint = " (a spawned viewer needs a desktop session for its window)" if self._outputs.spawned else ""
            raise ViewerUnreachable(f"{written}the rerun viewer could not be reached{hint}: {unreachable}")
        return self.path

    def _complete(self, result: RunResult, roughness) -> None:
        """What only the finished run knows: its header (if not given at the start), loss of contact, the
        window, the Hertz circle at the run's preload, and roughness lines over the whole run."""
        self._header = result.header
        self._loss_of_contact_steps = result.loss_of_contact_steps
        self._patch.set_window(result.window_x, result.window_y)
        # started without the run's parameters: correct the circle
        self._patch.set_geometry(self._geometry(), semi_axes=self._semi_axes())
        if roughness is not None and self._lines is None:
            self._set_roughness(roughness)
            if self._lines is not None:
                steps = np.arange(result.n_steps)
                for first in range(0, result.n_steps, self.chunk_steps):
                    block = slice(first, first + self.chunk_steps)
                    self._send_roughness_lines(
                        result.x[block], time_columns(steps[block], result.time[block], result.x[block])
                    )

    def _log_spectrum(self, result: RunResult | None) -> None:
        from wheelrail.core.spectra.force import force_spectrum

        force = result.force if result is not None else np.asarray(self._force)
        time_step = (
            result.time_step
            if result is not None
            else (self._header.time_step if self._header is not None else self._time_step)
        )
        if time_step is None or len(force) < 2:
            return
        try:
            centres, levels = force_spectrum(force, time_step)
        except WheelrailError:
            return  # run too short for a spectrum (fewer than 16 steps after the start-up skip)
        self.stream.log(FORCE_SPECTRUM, band_chart(centres, levels), static=True, strict=True)

    def _log_sound_power(self, result: RunResult) -> None:
        """``spectra/sound_power/<component>`` bar charts and a summary document (wheelrail.core.noise.run_noise)."""

        from wheelrail.core.noise.run_noise import run_noise

        try:
            noise = run_noise(result, wheel_model=self.sound_power_wheel)  # a modal run's own wheel, if modal
        except WheelrailError as error:  # e.g. a run too short for a force spectrum: said, in the file and aloud
            reason = error.render(self.names)
            document = strict_json({"sound_power": "not computed", "reason": reason}, indent=2)
            self.stream.log(f"{SOUND_POWER}/summary", self._rr.TextDocument(document), static=True, strict=True)
            option = self.names["sound_power"].label if "sound_power" in self.names else "sound_power"
            warnings.warn(f"{option}: no sound power recorded: {reason}", stacklevel=3)
            return
        for component in SOUND_POWER_COMPONENTS:
            chart = band_chart(noise.frequency_hz, noise.sound_power_db[component])
            self.stream.log(f"{SOUND_POWER}/{component}", chart, static=True, strict=True)
        totals = {
            "sound_power_dBA_per_wheel": noise.sound_power_dba,
            "axle_dBA": noise.axle_dba,
            "pass_by_LpAeq_dBA": noise.pass_by_laeq_dba,
            "train_axles": noise.configuration["train_axles"],
            "train_length_m": noise.configuration["train_length_m"],
            "wheel_model": noise.configuration["wheel_model"],
            "wheel_transfer_source": noise.configuration["wheel"],
        }
        self.stream.log(
            f"{SOUND_POWER}/summary", self._rr.TextDocument(strict_json(totals, indent=2)), static=True, strict=True
        )

    def abort(self) -> None:
        """Stop recording after a failure or cancellation: close the streams and delete the partial file."""
        if self._closed:
            return
        self._rows, self._map_steps, self._block, self._blocks = [], [], None, []
        self._closed = True
        self._outputs.disconnect()
        self._outputs.discard()


def _whole_run_columns(result: RunResult, block: slice) -> tuple[dict, np.ndarray | None]:
    """The scalar columns of a block of a finished run, and r_eq where it differs from r (else None)."""
    columns = {"time": np.asarray(result.time, dtype=float)[block]}
    for field in STEP_FIELDS:
        columns[field.name] = np.asarray(getattr(result, field.name), dtype=float)[block]
    equivalent = result.equivalent_roughness[block]
    if np.array_equal(equivalent, result.roughness[block]):
        equivalent = None  # r_eq = r (hertz, 2d, 3d): not repeated
    return columns, equivalent


def record_result(
    result: RunResult,
    path: str | os.PathLike | None = None,
    *,
    roughness=None,
    record_every: int = 1,
    surface_every: int = SURFACE_EVERY,
    spawn: bool = False,
    connect: str | None = None,
    description: str = "",
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
    sound_power: bool = False,
) -> Path | None:
    """Write a finished :class:`RunResult` as a recording (file and/or viewer) in one go.

    Parameters
    ----------
    result : RunResult
        The run (arrays over steps, SI).
    path : str or path, optional
        ``.rrd`` file to write (atomically: temporary name, then rename).
    roughness : RoughnessSet, optional
        The set the run rolled over, for ``roughness/lines`` (not recorded without it).
    record_every, surface_every, spawn, connect, description, chunk_steps, sound_power
        As for :class:`RecordingSink` (``sound_power``: add ``spectra/sound_power/*``, the run's rolling noise).

    Returns
    -------
    pathlib.Path or None
        The file written, if any.

    Raises
    ------
    WheelrailError
        If ``result`` is not a RunResult, or the viewer could not be reached.
    """
    if not isinstance(result, RunResult):
        raise WheelrailError(f"record_result needs a RunResult, got {type(result).__name__}")
    sink = RecordingSink(
        rrd=path,
        spawn=spawn,
        connect=connect,
        record_every=record_every,
        surface_every=surface_every,
        chunk_steps=chunk_steps,
        description=description,
        sound_power=sound_power,
        pressure_maps=result.pressure is not None,
    )
    try:
        sink.start(result, roughness=roughness)
        steps = np.arange(result.n_steps, dtype=np.int64)
        for first in range(0, result.n_steps, sink.chunk_steps):
            block = slice(first, min(result.n_steps, first + sink.chunk_steps))
            columns, equivalent = _whole_run_columns(result, block)
            pressure_steps = pressure = None
            if result.pressure is not None:
                pressure_steps = steps[block][steps[block] % sink.record_every == 0]
                pressure = result.pressure[pressure_steps]
            sink._send_block(steps[block], columns, pressure_steps, pressure, equivalent)
        return sink.finish(result)
    except BaseException:
        sink.abort()
        raise
