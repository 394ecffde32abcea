"""A prepared run, stepped (paper section 2, eqs. 1-14): :class:`InteractionRun`.

The wheel moves one element per step (eq. 7). Each step the contact law is solved together with the wheel (eq. 1)
and the rail (eq. 2), both written as a part known from the history plus the current force times a compliance:
implicit, one solve per step (the documentation's physics page, "How a step is solved"). The loop owns eqs. 1-2
(``kernels``); a contact model (``models``) gives its law: compiled laws run ``CHUNK`` or ``CHUNK_3D``
steps per call of a compiled loop, a per-step law is called from Python. The run gives its steps one by one
(:meth:`InteractionRun.steps`), a chunk at a time in arrays (:meth:`InteractionRun.blocks`, what a recorder
takes) or whole (:meth:`InteractionRun.run`). How a run is built: ``prepare``.
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Callable, Iterator

import numpy as np

from wheelrail.core.engine.history import History
from wheelrail.core.engine.laws.base import StepArrays, law_class
from wheelrail.core.engine.results import HeaderView, RunHeader, RunResult, StepState
from wheelrail.core.engine.track_lines import TrackRoughness
from wheelrail.core.models import ContactModel, ModelInputs, model_entry
from wheelrail.core.parameters import ModelParameters

# the arrays of a RunResult that make a StepState's fields after ``step``, in StepState's order
_STATE_ARRAYS = ("time", "x", "force", "xi_wheel", "xi_rail", "roughness", "contact_length", "contact_area")

__all__ = ["InteractionRun"]


class InteractionRun(HeaderView):
    """One prepared run: iterate :meth:`steps` (streaming) or call :meth:`run`; then :meth:`result`.

    Built by :func:`prepare_run`, not by hand. :meth:`cancel` (from any thread) stops it between steps.

    Attributes
    ----------
    header : RunHeader
        Also through its shortcuts ``model``, ``line``, ``params``, ``roughness_name`` and ``dx`` (m).
    traits : ModelTraits
        What the model computes.
    x_start : float
        Wheel position of step 0, m.
    window_x, window_y : ndarray or None
        For a model with a pressure map: the element centres of the contact window relative to the wheel
        centre, m (columns along the rail, rows across it), the grid of every ``StepState.pressure``.

    See Also
    --------
    simulate : prepares and runs in one call.
    """

    def __init__(
        self,
        *,
        header: RunHeader,
        contact: ContactModel,
        inputs: ModelInputs,
        track: TrackRoughness,
        history: History,
        keep_pressure: bool = True,
    ) -> None:
        self.header = header
        self.traits = traits = model_entry(header.model).traits  # what the model computes (the registry's)
        self.contact = contact
        self.track = track
        self.loop = history
        self._cancel = threading.Event()
        self._done = 0  # steps done, run-in included
        n_total = history.n_total
        self.outputs = StepArrays(np.zeros(n_total), np.zeros(n_total), np.zeros(n_total), np.zeros(n_total))
        self.law = law_class(traits)(contact, inputs, history, self.outputs, keep_pressure)
        self.window_x = contact.window_x if traits.pressure_map else None
        self.window_y = track.window_y if traits.pressure_map else None
        self.steady = None  # the steady state the run starts from (steady_start.SteadyState), found on first use

    # what produced the run ------------------------------------------------------------------------------
    @property
    def params(self) -> ModelParameters:
        return self.header.params

    @property
    def dx(self) -> float:
        return self.header.element_size

    @property
    def x_start(self) -> float:
        return self.track.x_start

    @property
    def n_steps(self) -> int:
        """Number of recorded steps (the run-in not counted)."""
        return self.loop.n_steps

    def position_of(self, s: int) -> float:
        """Wheel position of a step, counting the run-in's steps.

        Parameters
        ----------
        s : int
            Step index, run-in included: ``s = n_run_in`` is recorded step 0.

        Returns
        -------
        float
            Wheel position along the track, m.
        """
        return self.x_start + (s - self.loop.n_run_in) * self.dx

    def cancel(self) -> None:
        """Ask the run to stop at the next step (thread-safe): :meth:`steps` ends, :meth:`run` returns the steps
        done so far."""
        self._cancel.set()

    @property
    def cancelled(self) -> bool:
        """Whether :meth:`cancel` was called."""
        return self._cancel.is_set()

    # stepping -------------------------------------------------------------------------------------------
    @property
    def pressure(self) -> np.ndarray | None:
        """The recorded steps' pressure maps (steps, ny, nx) float32, where kept (``keep_pressure``)."""
        return self.law.pressure

    def _advance_to(self, s_end: int, progress: Callable[[int, int], None] | None = None) -> None:
        """Steps up to s_end (exclusive, run-in counted), a chunk of the law's at a time; the steady start first."""
        if self.loop.steady and self.steady is None and self._done == 0 and s_end > 0:
            self.steady = self.law.start_steady()
        law = self.law
        while self._done < s_end:
            if self._cancel.is_set():
                return
            stop = law.chunk_end(self._done, s_end)
            law.advance(self._done, stop)
            self._done = stop
            if progress is not None and (law.chunk > 1 or stop % 64 == 0 or stop == s_end):
                progress(max(0, stop - self.loop.n_run_in), self.loop.n_steps)

    def steps(self) -> Iterator[StepState]:
        """Run (run-in first, not yielded) and yield the state of every recorded step, as it is computed.

        Yields
        ------
        StepState
            One step's force, displacements, contact size and pressure map; none after :meth:`cancel`.

        Raises
        ------
        WheelrailError
            If the contact model fails (e.g. the contact leaves the 3D model's window).
        """
        for s, end in self._stepped():
            yield from self._chunk_states(s, end)

    def run(
        self,
        callback: Callable[[StepState], None] | None = None,
        progress: Callable[[int, int], None] | None = None,
    ) -> RunResult:
        """Run to the end (or until cancelled).

        Parameters
        ----------
        callback : callable, optional
            ``callback(state)`` with the :class:`StepState` of every step (streaming); a callback with a method
            ``log_block`` (``RecordingSink``) gets ``log_block(first, block)`` of :meth:`blocks` instead.
        progress : callable, optional
            ``progress(done, total)`` now and then with the number of steps done (cheap: for progress bars).

        Returns
        -------
        RunResult
            :meth:`result`: every step, or those done before :meth:`cancel`.

        Raises
        ------
        WheelrailError
            If the contact model fails (e.g. the contact leaves the 3D model's window).
        """
        if callback is None:
            self._advance_to(self.loop.n_total, progress)
        elif hasattr(callback, "log_block"):  # a recorder of arrays: no StepState a step
            self._log_blocks(callback.log_block, progress)
        else:
            for state in self.steps():
                callback(state)
                if progress is not None and (state.step % 256 == 0 or state.step == self.loop.n_steps - 1):
                    progress(state.step + 1, self.loop.n_steps)
        return self.result()

    def result(self) -> RunResult:
        """The arrays of the steps done so far.

        Returns
        -------
        RunResult
            All recorded steps after a complete run; fewer after :meth:`cancel` (or before :meth:`run`).
        """
        start = self.loop.n_run_in
        done = max(0, self._done - start)
        return self._steps_result(start, start + done, None if self.pressure is None else self.pressure[:done])

    def blocks(self) -> Iterator[tuple[int, RunResult]]:
        """Run (run-in first, not yielded) and yield the recorded steps a chunk at a time, as they are computed.

        Yields
        ------
        (int, RunResult)
            The number of the chunk's first recorded step and the chunk's steps: the steps ``steps()`` yields, in
            arrays (``time`` and ``x`` those of the whole run; the pressure maps a copy, or a view of the maps
            the run keeps).
        """
        for s, end in self._stepped():
            if end > s:
                yield s - self.loop.n_run_in, self._chunk_result(s, end)

    def chunk_states(self) -> Iterator[StepState]:
        """Run (run-in first, not yielded) and yield the state of the last step of every chunk, as it is computed.

        What a live view draws: a chunk is the law's (``ContactLaw.chunk``: 256 steps of the ``3d`` model, 2048 of a
        one-line model); the steps in between are in :meth:`result`, with no StepState built for them (as
        :meth:`steps` builds one for every step).

        Yields
        ------
        StepState
            The chunk's last step (its ``step`` counted from the record's start); none after :meth:`cancel`.
        """
        for first, block in self.blocks():
            last = block.n_steps - 1
            yield dataclasses.replace(block.state(last), step=first + last)

    def _stepped(self) -> Iterator[tuple[int, int]]:
        """Run (run-in first) and yield each chunk's steps s .. end - 1 (run-in counted) as they are computed."""
        loop = self.loop
        self._advance_to(loop.n_run_in)
        s = loop.n_run_in
        while s < loop.n_total and not self._cancel.is_set():
            stop = self.law.chunk_end(s, loop.n_total)
            self._advance_to(stop)
            yield s, min(stop, self._done)
            s = stop

    def _chunk_states(self, s0: int, s1: int) -> Iterator[StepState]:
        """The StepStates of the chunk just stepped, s0 .. s1 - 1 (run-in counted): its arrays read once, as Python
        floats (each column converted at once, not each number read from its array), the same numbers."""
        if s1 <= s0:
            return iter(())
        block = self._chunk_result(s0, s1)
        first = s0 - self.loop.n_run_in
        maps = [None] * block.n_steps if block.pressure is None else list(block.pressure)  # each its own step's
        columns = [getattr(block, name).tolist() for name in _STATE_ARRAYS]
        return (StepState(*row) for row in zip(range(first, first + block.n_steps), *columns, maps, strict=True))

    def _log_blocks(self, log_block: Callable, progress: Callable[[int, int], None] | None) -> None:
        """``log_block(first, block)`` for every chunk (``run(callback)`` with a recorder of arrays)."""
        for first, block in self.blocks():
            log_block(first, block)
            if progress is not None:
                progress(first + block.n_steps, self.loop.n_steps)

    def _chunk_result(self, s0: int, s1: int) -> RunResult:
        """The steps s0 .. s1 - 1 (run-in counted) of the chunk just stepped, as a RunResult (its own arrays)."""
        pressure = self.law.chunk_pressure(s0, s1)
        return self._steps_result(s0, s1, pressure)

    def _steps_result(self, s0: int, s1: int, pressure) -> RunResult:
        """The steps s0 .. s1 - 1 (run-in counted) as a RunResult of their own arrays, with ``pressure`` (their maps
        or None): what a chunk and the whole run (:meth:`InteractionRun.result`) both return."""
        loop, sl = self.loop, slice(s0, s1)
        k = np.arange(s0 - loop.n_run_in, s1 - loop.n_run_in)
        force = loop.force[loop.n_hist + s0 : loop.n_hist + s1].copy()
        idx = loop.start_index[sl]
        return RunResult(
            header=self.header,
            time=k * loop.dt,
            x=self.x_start + k * self.dx,
            force=force,
            xi_wheel=self.outputs.xi_wheel[sl].copy(),
            xi_rail=self.outputs.xi_rail[sl].copy(),
            roughness=self.track.lines[self.track.centre_row][idx].copy(),
            contact_length=self.outputs.contact_length[sl].copy(),
            contact_area=self.outputs.contact_area[sl].copy(),
            equivalent_roughness=self.contact.equivalent_line[idx].copy(),
            pressure=pressure,
            window_x=self.window_x,
            window_y=self.window_y,
            loss_of_contact_steps=int(np.count_nonzero(force <= 0.0)),
        )
