"""A run's steps a chunk at a time, in arrays: what :class:`~wheelrail.core.interaction.InteractionRun` gives a
recorder (``RecordingSink.log_block``) instead of a :class:`~wheelrail.core.results.StepState` a step.

Building a StepState costs ~4 us a step (seven floats read one by one and a generator's resume), a fifth of a
step of the 3D model; a recorder that stores columns takes the chunk's arrays at once (benchmarks/recording.py).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator

import numpy as np

from wheelrail.core.results import RunResult, StepState

# the arrays of a RunResult that make a StepState's fields after ``step``, in StepState's order
_STATE_ARRAYS = ("time", "x", "force", "xi_wheel", "xi_rail", "roughness", "contact_length", "contact_area")

__all__ = ["BlockSteps"]


class BlockSteps:
    """:class:`~wheelrail.core.interaction.InteractionRun`'s chunked stepping and its chunks as RunResults."""

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

        What a live view draws: a chunk is 256 steps of the ``3d`` model (5-10 ms) or 2048 of a one-line model;
        the steps in between are in :meth:`result`. Saves the ~3 us a step that a StepState of every step costs
        (:meth:`steps`).

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
            stop = min(loop.n_total, s + self._chunk)
            self._advance_to(stop)
            yield s, min(stop, self._done)
            s = stop

    def _chunk_states(self, s0: int, s1: int) -> Iterator[StepState]:
        """The StepStates of the chunk just stepped, s0 .. s1 - 1 (run-in counted): its arrays read once, as Python
        floats (2.4 us a step where reading each number from its array took 7 us), the same numbers."""
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
        pressure = None
        if self.pressure is not None:  # kept: a view of the run's maps (never written again)
            pressure = self.pressure[s0 - self.loop.n_run_in : s1 - self.loop.n_run_in]
        elif self._maps is not None:  # not kept: the chunk's buffer, which the next chunk reuses
            pressure = self._maps[s0 - self._maps_first : s1 - self._maps_first].copy()
        elif self.last_pressure is not None:  # a law stepped one by one (chunks of one step)
            pressure = np.asarray(self.last_pressure, dtype=np.float32)[None]
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
            xi_wheel=self.xi_wheel[sl].copy(),
            xi_rail=self.xi_rail[sl].copy(),
            roughness=self.track.lines[self.track.centre_row][idx].copy(),
            contact_length=self.contact_length[sl].copy(),
            contact_area=self.contact_area[sl].copy(),
            equivalent_roughness=self.contact.equivalent_line[idx].copy(),
            pressure=pressure,
            window_x=self.window_x,
            window_y=self.window_y,
            loss_of_contact_steps=int(np.count_nonzero(force <= 0.0)),
        )
