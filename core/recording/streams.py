"""The per-step entities of a recording, sent a block of steps at a time (:class:`StepStreams`): the scalar
series of ``STEP_FIELDS``, r_eq where it differs from r, the roughness lines around the run's line
(:class:`RoughnessLines`) and the pressure maps (:class:`~wheelrail.core.recording.pressure.ContactPatch`); each
series is fed to the recording's digest as it is sent."""

from __future__ import annotations

import numpy as np

from wheelrail.core.recording.columns import scalar_column
from wheelrail.core.recording.digest import RecordingDigest
from wheelrail.core.recording.pressure import ContactPatch
from wheelrail.core.recording.schema import (
    EQUIVALENT,
    ROUGHNESS_LINES,
    ROUGHNESS_LINES_SHOWN,
    SCALAR_FIELDS,
    STEP_FIELDS,
    rerun_module,
    time_columns,
)

__all__ = ["RoughnessLines", "StepStreams"]


class RoughnessLines:
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


class StepStreams:
    """Sends blocks of steps to a recording's stream and keeps what the end of the recording needs: the steps
    recorded, the time step measured from the recorded times, the force (for the spectrum) and the digest."""

    def __init__(self, stream, patch: ContactPatch) -> None:
        self.stream, self.patch = stream, patch
        self.lines: RoughnessLines | None = None  # roughness/lines, when a set was given
        self.digest = RecordingDigest()  # of every series sent, sealed in the final parameters document
        self.force: list[float] = []
        self.time_step: float | None = None  # measured from the recorded times (when no header says it)
        self.steps_recorded = 0
        self._rr = rerun_module()

    def show_lines(self, roughness, line: int) -> None:
        """Record ``roughness/lines``: the set's lines around ``line`` (none if it has none of them)."""
        lines = RoughnessLines(roughness, line)
        if not lines.shown:
            return
        self.lines = lines
        names = [f"line {k} height (m)" for k in lines.shown]
        self.stream.log(ROUGHNESS_LINES, self._rr.SeriesLines(names=names), static=True, strict=True)

    def send(self, steps, columns: dict, pressure_steps, pressure, equivalent, *, element_size: float) -> None:
        """Send one block of steps: scalars at every step, pressure maps at ``pressure_steps``.

        ``columns`` holds ``time`` and every ``STEP_FIELDS`` name (arrays over the block, SI); ``equivalent``
        is r_eq where it differs from r (whole-run export), else None; ``element_size`` (m) sizes the maps.
        """
        time, x = columns["time"], columns["x"]
        if self.time_step is None and len(time) > 1:
            self.time_step = float(time[1] - time[0])
        self.force.extend(columns["force"].tolist())
        if self.steps_recorded == 0:
            for field in SCALAR_FIELDS:
                series = self._rr.SeriesLines(names=[field.legend], colors=[field.colour])
                self.stream.log(field.path, series, static=True, strict=True)
        indexes = time_columns(steps, time, x)  # shared by every entity of the block
        self.digest.add("time_ns", np.round(np.asarray(time) * 1e9).astype(np.int64))
        for field in STEP_FIELDS:
            values = columns[field.name]
            self.digest.add(field.name, values)
            finite = np.isfinite(values)
            if finite.all():
                self.stream.send_columns(field.path, indexes, [scalar_column(values)], strict=True)
            elif finite.any():  # e.g. no contact area in 2D: leave those steps out rather than log NaN
                kept = time_columns(steps[finite], time[finite], x[finite])
                self.stream.send_columns(field.path, kept, [scalar_column(values[finite])], strict=True)
        if equivalent is not None:
            self.stream.send_columns(EQUIVALENT.path, indexes, [scalar_column(equivalent)], strict=True)
        if self.lines is not None:
            self.send_lines(x, indexes)
        self.steps_recorded += len(steps)
        if pressure is not None and len(pressure):
            self.digest.add("pressure", pressure)
            where = np.searchsorted(steps, pressure_steps)
            self.patch.send(pressure_steps, time[where], x[where], pressure, element_size=element_size)

    def send_lines(self, x, indexes) -> None:
        """The roughness lines at the wheel positions ``x`` of a block (its time columns ``indexes``)."""
        self.stream.send_columns(ROUGHNESS_LINES, indexes, [scalar_column(self.lines.heights(x))], strict=True)
