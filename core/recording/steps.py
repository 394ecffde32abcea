"""The steps a recording is given, buffered into blocks (:class:`StepBuffer`): one by one from the loop's per-step
callback, or as arrays from its chunks (``InteractionRun.run`` gives a sink its steps this way); either way the
same rows reach the streams, ``chunk_steps`` steps at a time."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from wheelrail.core.engine.results import RunResult, StepState
from wheelrail.core.recording.schema import STEP_FIELDS

__all__ = ["ROW_NAMES", "StepBuffer", "whole_run_columns"]

ROW_NAMES = ("step", "time", *(field.name for field in STEP_FIELDS))
# one StepState -> one buffered row, in ROW_NAMES order. Compiled from the field list: attribute reads
# in a function are specialised by Python 3.11+, so this is cheaper per step than operator.attrgetter
# (benchmarks/recording.py times the sink)
_ROW = eval(  # noqa: S307 - the source is built from this package's own constant field names
    "lambda state: (state.step, state.time, " + ", ".join(f"state.{field.state}" for field in STEP_FIELDS) + ")"
)


def whole_run_columns(result: RunResult, block: slice) -> tuple[dict, np.ndarray | None]:
    """The scalar columns of a block of a finished run, and r_eq where it differs from r (else None)."""
    columns = {"time": np.asarray(result.time, dtype=float)[block]}
    for field in STEP_FIELDS:
        columns[field.name] = np.asarray(getattr(result, field.name), dtype=float)[block]
    equivalent = result.equivalent_roughness[block]
    if np.array_equal(equivalent, result.roughness[block]):
        equivalent = None  # r_eq = r (hertz, 2d, 3d): not repeated
    return columns, equivalent


class StepBuffer:
    """Steps waiting to be sent, and the pressure maps to record among them (every ``record_every``-th step).

    ``send(steps, columns, pressure_steps, pressure)`` is called with each block: ``columns`` holds ``time``
    and every ``STEP_FIELDS`` name (arrays over the block, SI), the maps float32 (maps, ny, nx).
    """

    def __init__(self, chunk_steps: int, record_every: int, send: Callable) -> None:
        self.chunk_steps, self.record_every, self._send = chunk_steps, record_every, send
        self.clear()

    def clear(self) -> None:
        """Drop what is buffered (a recording aborted)."""
        self._rows: list[tuple] = []  # buffered steps: (step, time, the STEP_FIELDS of StepState)
        self._map_steps: list[int] = []  # steps of the buffered pressure maps to record
        self._block: np.ndarray | None = None  # (capacity, ny, nx) float32: the buffered maps, in _map_steps order
        self._blocks: list[tuple] = []  # buffered blocks of add_block: (steps, columns, map steps, maps)

    def add_step(self, state: StepState) -> None:
        """Buffer one step; sends a block every ``chunk_steps`` steps (blocks given before go first)."""
        if self._blocks:
            self.flush()
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

    def add_block(self, first: int, block: RunResult) -> None:
        """Buffer the consecutive steps ``first``, ``first + 1``, ... of ``block`` at once (steps given one by one
        before go first). A block's arrays are not kept: its pressure maps to record are copied."""
        if self._rows:
            self.flush()
        columns, _ = whole_run_columns(block, slice(None))  # r_eq is not streamed, as step by step
        steps = first + np.arange(block.n_steps, dtype=np.int64)
        pressure_steps = pressure = None
        if block.pressure is not None:
            keep = steps % self.record_every == 0
            pressure_steps, pressure = steps[keep], np.array(block.pressure[keep], dtype=np.float32)
        self._blocks.append((steps, columns, pressure_steps, pressure))
        if sum(len(steps) for steps, *_ in self._blocks) >= self.chunk_steps:
            self.flush()

    def flush(self) -> None:
        """Send what is buffered: the blocks given, then the steps given one by one, each as one block."""
        if self._blocks:
            blocks, self._blocks = self._blocks, []
            steps = np.concatenate([block[0] for block in blocks])
            columns = {name: np.concatenate([block[1][name] for block in blocks]) for name in blocks[0][1]}
            pressure_steps = pressure = None
            if blocks[0][3] is not None:
                pressure_steps = np.concatenate([block[2] for block in blocks])
                pressure = np.concatenate([block[3] for block in blocks])
            self._send(steps, columns, pressure_steps, pressure)
        if not self._rows:
            return
        table = np.array(self._rows, dtype=float)  # (steps, fields): one conversion for the whole block
        count = len(self._map_steps)
        pressure_steps = np.array(self._map_steps, dtype=np.int64)
        pressure = self._block[:count] if count else None
        self._rows, self._map_steps, self._block = [], [], None
        columns = {name: np.ascontiguousarray(table[:, i]) for i, name in enumerate(ROW_NAMES)}
        steps = columns.pop("step").astype(np.int64)
        self._send(steps, columns, pressure_steps, pressure)
