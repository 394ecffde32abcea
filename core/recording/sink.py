"""Writing a run into a recording while it streams (:class:`RecordingSink`) or in one go (:func:`record_result`).

The sink records what it is given: the run's :class:`~wheelrail.core.engine.results.RunHeader`, the steps, and
(optionally) the :class:`~wheelrail.core.roughness.RoughnessSet` whose lines around the run's line become
``roughness/lines``; it never loads anything from disk itself.

Scalars are sent as columns (``rr.send_columns``) in blocks of ``chunk_steps`` steps; pressure maps are
sent as a column of image buffers (one static ``ImageFormat``), decimated with ``record_every``.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from wheelrail.core.engine.results import RunHeader, RunResult, StepState
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.recording.digest import DIGEST_KEY
from wheelrail.core.recording.options import DEFAULT_CHUNK_STEPS, SURFACE_EVERY, RecordingOptions
from wheelrail.core.recording.outputs import Outputs, ViewerUnreachable
from wheelrail.core.recording.pressure import ContactPatch, hertz_geometry, hertz_semi_axes
from wheelrail.core.recording.schema import (
    PARAMETERS,
    default_blueprint,
    parameters_document,
    parameters_text,
    rerun_module,
    time_columns,
)
from wheelrail.core.recording.steps import StepBuffer, whole_run_columns
from wheelrail.core.recording.streams import StepStreams
from wheelrail.core.recording.summaries import log_force_spectrum, log_sound_power

__all__ = ["DEFAULT_CHUNK_STEPS", "SURFACE_EVERY", "RecordingOptions", "RecordingSink", "record_result"]


class RecordingSink:
    """Records a run to a ``.rrd`` file and/or a live rerun viewer, step by step or from a finished result.

    Use it as the loop's callback: ``InteractionRun.run(sink)`` hands it each chunk of steps as arrays
    (:meth:`log_block`), a callback that takes a :class:`StepState` (``sink(state)``, :meth:`log_step`) buffers one
    step; every ``chunk_steps`` steps the block is sent as columns, the same rows either way. Typical use::

        sink = RecordingSink(rrd="run.rrd")            # path checked here, before the run
        run = prepare_run(roughness, model=name, length=0.5)  # any model (its maps recorded if it has them)
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
    options : RecordingOptions, optional
        What is recorded besides where: the decimation of the pressure maps and surfaces, the steps per send,
        the recording's name, the sound power, the viewer's layout, the front end's names (default: all
        defaults).
    """

    def __init__(
        self,
        *,
        rrd: str | os.PathLike | None = None,
        spawn: bool = False,
        connect: str | None = None,
        options: RecordingOptions | None = None,
    ) -> None:
        self.options = options = RecordingOptions() if options is None else options
        blueprint = default_blueprint(pressure=options.pressure_maps, sound_power=bool(options.sound_power))
        self._outputs = Outputs(
            rrd=rrd, spawn=spawn, connect=connect, description=options.description, blueprint=blueprint
        )
        self.path = self._outputs.path
        self.recording_id = self._outputs.recording_id
        self.stream = self._outputs.stream
        self._rr = rerun_module()
        self._patch = ContactPatch(self.stream, record_every=options.record_every, surface_every=options.surface_every)
        self._streams = StepStreams(self.stream, self._patch)
        self._buffer = StepBuffer(options.chunk_steps, options.record_every, self._send_block)
        self._header: RunHeader | None = None
        self._loss_of_contact_steps: int | None = None
        self._impacts: dict | None = None  # a finished run over irregularities: impact_summary(...).to_dict()
        self._started = False
        self._closed = False

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
        if roughness is not None and self._streams.lines is None:
            self._streams.show_lines(roughness, self._header.line if self._header is not None else 0)

    def _log_parameters(self, *, final: bool = False) -> None:
        """The parameters document; ``final``: with the steps recorded, the mark of a finished recording."""
        patch, streams, options = self._patch, self._streams, self.options
        document = parameters_document(
            self._header,
            time_step=streams.time_step,
            loss_of_contact_steps=self._loss_of_contact_steps,
            decimation=(options.record_every, options.surface_every),
            window=patch.window,
            geometry=patch.geometry,
            recorded_steps=streams.steps_recorded if final else None,
        )
        if final and self._impacts is not None:  # a run over irregularities: its impacts (engine.impacts)
            document["impacts"] = self._impacts
        if final:
            document[DIGEST_KEY] = streams.digest.seal(document)
        text = parameters_text(document, options.description)
        self.stream.log(PARAMETERS, self._rr.TextDocument(text, media_type="text/markdown"), static=True, strict=True)

    # -- per step -------------------------------------------------------------------------------------------
    def __call__(self, state: StepState) -> None:
        """Buffer one step (the loop's callback); sends a block every ``chunk_steps`` steps."""
        if self._closed:
            raise WheelrailError("the recording is already finished")
        self._buffer.add_step(state)

    log_step = __call__  # the same, under a name that reads well as ``callback=sink.log_step``

    def log_block(self, first: int, block: RunResult) -> None:
        """Buffer the consecutive steps ``first``, ``first + 1``, ... of ``block`` at once; what the steps one by
        one would record (``InteractionRun.run`` gives a sink its steps this way, :meth:`InteractionRun.blocks`).
        A block's arrays are not kept: its pressure maps to record are copied."""
        if self._closed:
            raise WheelrailError("the recording is already finished")
        self._buffer.add_block(first, block)

    def flush(self) -> None:
        """Send the buffered steps as one block of columns."""
        self._buffer.flush()

    def _send_block(self, steps, columns: dict, pressure_steps=None, pressure=None, equivalent=None) -> None:
        """Send one block of steps (:meth:`StepStreams.send`), the recording's description first."""
        if not self._started:
            self.start()
        element_size = self._header.element_size if self._header is not None else 1e-3
        self._streams.send(steps, columns, pressure_steps, pressure, equivalent, element_size=element_size)

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
            if self.options.sound_power and result is not None:
                log_sound_power(self.stream, result, self.options)
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
        """What only the finished run knows: its header (if not given at the start), loss of contact, over
        irregularities its impacts, the window, the Hertz circle at the run's preload, and roughness lines over
        the whole run."""
        self._header = result.header
        self._loss_of_contact_steps = result.loss_of_contact_steps
        if result.header is not None and result.header.params.run.irregularities:
            from wheelrail.core.engine.impacts import impact_summary

            self._impacts = impact_summary(result).to_dict()
        self._patch.set_window(result.window_x, result.window_y)
        # started without the run's parameters: correct the circle
        self._patch.set_geometry(self._geometry(), semi_axes=self._semi_axes())
        if roughness is not None and self._streams.lines is None:
            self._set_roughness(roughness)
            if self._streams.lines is not None:
                steps, chunk = np.arange(result.n_steps), self.options.chunk_steps
                for first in range(0, result.n_steps, chunk):
                    block = slice(first, first + chunk)
                    self._streams.send_lines(
                        result.x[block], time_columns(steps[block], result.time[block], result.x[block])
                    )

    def _log_spectrum(self, result: RunResult | None) -> None:
        if result is not None:
            log_force_spectrum(self.stream, result.force, result.time_step)
        else:
            time_step = self._header.time_step if self._header is not None else self._streams.time_step
            log_force_spectrum(self.stream, self._streams.force, time_step)

    def abort(self) -> None:
        """Stop recording after a failure or cancellation: close the streams and delete the partial file."""
        if self._closed:
            return
        self._buffer.clear()
        self._closed = True
        self._outputs.disconnect()
        self._outputs.discard()


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
        As for :class:`RecordingSink` and :class:`RecordingOptions` (``sound_power``: add
        ``spectra/sound_power/*``, the run's rolling noise).

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
    options = RecordingOptions(
        record_every=record_every,
        surface_every=surface_every,
        chunk_steps=chunk_steps,
        description=description,
        sound_power=sound_power,
        pressure_maps=result.pressure is not None,
    )
    sink = RecordingSink(rrd=path, spawn=spawn, connect=connect, options=options)
    try:
        sink.start(result, roughness=roughness)
        steps = np.arange(result.n_steps, dtype=np.int64)
        for first in range(0, result.n_steps, options.chunk_steps):
            block = slice(first, min(result.n_steps, first + options.chunk_steps))
            columns, equivalent = whole_run_columns(result, block)
            pressure_steps = pressure = None
            if result.pressure is not None:
                pressure_steps = steps[block][steps[block] % options.record_every == 0]
                pressure = result.pressure[pressure_steps]
            sink._send_block(steps[block], columns, pressure_steps, pressure, equivalent)
        return sink.finish(result)
    except BaseException:
        sink.abort()
        raise
