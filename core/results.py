"""What a wheel/rail interaction run produces: one state per step (streamed) and the whole-run result.

These types are the contract between the time-stepping loop (``wheelrail.core.interaction``) and its
consumers: the recording sink (rerun), the command line, studies and the explorer. All SI.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wheelrail.core.atomic import atomic_write
from wheelrail.core.errors import WheelrailError

MODELS = ("3d", "2d", "hertz", "hertz-winkler", "hertz-average")


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
        Contact area, m^2 (3D: contact elements times element area; Hertz: pi a^2; 2D: nan).
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


@dataclass(frozen=True, eq=False)
class RunResult:
    """Whole-run result of the interaction loop (arrays over steps, SI units).

    Attributes
    ----------
    model : str
        One of ``MODELS``.
    line : int
        Roughness line number (-M..M; for 3D the line the window is centred on).
    speed, element_size, time_step : float
        v (m/s), Delta x (m), dt = Delta x / v (s).
    roughness_name : str
        Bundled set name or file path the roughness came from.
    time, x, force, xi_wheel, xi_rail, roughness, contact_length, contact_area : ndarray (steps,)
        As in :class:`StepState`.
    equivalent_roughness : ndarray (steps,)
        Roughness the contact model actually saw on the line (Hertz variants: r_eq; 2D/3D: r).
    pressure : ndarray (steps, ny, nx) float32 or None
        3D pressure maps, Pa (None for other models, or when not kept).
    window_x, window_y : ndarray or None
        3D window element centres relative to the wheel centre, m.
    loss_of_contact_steps : int
        Number of steps with F = 0.
    run_in_length : float
        Length run before step 0 on smooth surfaces to reach dynamic equilibrium (discarded), m.
    parameters : dict
        All model parameters (nested, SI), for provenance.
    """

    model: str
    line: int
    speed: float
    element_size: float
    time_step: float
    roughness_name: str
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
    run_in_length: float = 0.0
    parameters: dict = field(default_factory=dict)

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
        """Write the arrays (SPEC.md §4: time, x, force, xi_wheel, xi_rail, pressure for 3D) atomically."""
        import json

        target = Path(path)
        if not target.parent.is_dir():
            raise WheelrailError(f"cannot write {target}: folder {target.parent} does not exist")
        arrays = {
            "time": self.time, "x": self.x, "force": self.force, "xi_wheel": self.xi_wheel,
            "xi_rail": self.xi_rail, "roughness": self.roughness, "contact_length": self.contact_length,
            "contact_area": self.contact_area, "equivalent_roughness": self.equivalent_roughness,
        }
        if self.pressure is not None:
            arrays["pressure"] = self.pressure
            arrays["window_x"] = self.window_x
            arrays["window_y"] = self.window_y
        meta = {
            "model": self.model, "line": self.line, "speed_m_per_s": self.speed,
            "element_size_m": self.element_size, "time_step_s": self.time_step,
            "roughness": self.roughness_name, "loss_of_contact_steps": self.loss_of_contact_steps,
            "run_in_length_m": self.run_in_length, "parameters": self.parameters,
        }
        return atomic_write(target, lambda handle: np.savez(handle, metadata=np.array(json.dumps(meta)), **arrays))
