"""An impact simulation written apart from the project's loop: the reference for the wired Hertz models.

A rigid-geometry wheel flat (50 mm, rounded, D = L^2 / (16 R)) on a smooth rail at 30, 60 and 100 km/h: the
paper's 2-DOF wheel (``core.wheel.wheel_matrices``) on a Hertz spring (C_H of ``ContactParameters``) driven by
the wheel-centre trajectory (``core.irregularities.wheel_centre_trajectory``), with loss of contact (F = 0), on
the paper's FE track (``core.track.assemble_track``: the same rail, pads, sleepers and ballast the Green's
functions are integrated on). Nothing of the project's time loop is used (no Green's functions, no convolution,
no ``core.engine``): the track's full FE model is stepped directly with a moving load (the contact force
spread on the element under the wheel by its shape functions) by the implicit Newmark average-acceleration rule,
wheel and track in one system; each step's contact force solves the Hertz law on the step's condensed
compliance (wheel plus track) exactly, F = 0 when the spring would stretch.

The run starts from the static solution two bays before the flat's centre (a midspan) and runs 1.5 bays past
it. Printed per speed: peak force, minimum force (0 when the wheel leaves the rail), the time without contact,
and the peak's change when the step is halved. ``--walking`` prints the quasi-static check: a long gentle dip at
5 km/h and the flat at 5, 1 and 0.2 km/h against the static solution of the same geometry (the wheel's and the
track's static compliances and the Hertz spring in series at each position).

Run: ``python3 validation/impact_reference.py`` (about a minute of CPU; ``--walking``: a few minutes). The figures:
the documentation's Validation page, "Impact of a wheel flat: the independent reference".
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg import cho_solve_banded, cholesky_banded, solve

from wheelrail.core.irregularities import DippedWeld, WheelFlat, raw_profile, wheel_centre_trajectory
from wheelrail.core.parameters import ContactParameters, TrackParameters, WheelParameters
from wheelrail.core.track import assemble_track
from wheelrail.core.track.fe import shear_parameter_of, timoshenko_shape_functions, to_upper_band
from wheelrail.core.wheel import wheel_matrices

SPEEDS_KMH = (30.0, 60.0, 100.0)
FLAT_LENGTH = 0.05  # m
PROFILE_SPACING = 1e-4  # m, the trajectory's grid
# the quasi-static check: (irregularity, km/h, time step s); slow runs take long steps (their forces change slowly)
WALKING = (("weld", 5.0, 50e-6), ("flat", 5.0, 50e-6), ("flat", 1.0, 200e-6), ("flat", 0.2, 500e-6))


@dataclass
class ImpactResult:
    """One run: time (s), wheel position (m), contact force (N) at every step, and the static force (N)."""

    time: np.ndarray
    position: np.ndarray
    force: np.ndarray
    preload: float

    @property
    def peak(self) -> float:
        return float(self.force.max())

    @property
    def minimum(self) -> float:
        return float(self.force.min())

    @property
    def time_without_contact(self) -> float:
        """Time with F = 0, s (steps without contact times the step)."""
        return float(np.count_nonzero(self.force <= 0.0) * (self.time[1] - self.time[0]))


class _Track:
    """The FE track's matrices, its Newmark effective stiffness factored in band form, and the contact's DOFs."""

    def __init__(self, track: TrackParameters, elements_per_bay: int, time_step: float):
        self.model = assemble_track(track, elements_per_bay)
        self.M, self.C, self.K = (sp.csr_matrix(m) for m in (self.model.M, self.model.C, self.model.K))
        dt = time_step
        effective = self.K + (2.0 / dt) * self.C + (4.0 / dt**2) * self.M
        self.factor = cholesky_banded(to_upper_band(effective, self.model.half_bandwidth))
        self.static_factor = cholesky_banded(to_upper_band(self.K, self.model.half_bandwidth))

    def contact(self, x: float) -> tuple[np.ndarray, np.ndarray]:
        """The DOFs of the element under x and the shape functions' values there (the load and the readout)."""
        model = self.model
        element, xi = model.locate(x)
        e = int(element)
        h = float(model.node_x[e + 1] - model.node_x[e])
        values = timoshenko_shape_functions(float(xi), h, shear_parameter_of(model.params.rail, h))
        dofs = np.array([model.w_dof[e], model.theta_dof[e], model.w_dof[e + 1], model.theta_dof[e + 1]])
        return dofs, np.asarray(values, dtype=float).reshape(-1)

    def solve(self, rhs: np.ndarray, static: bool = False) -> np.ndarray:
        return cho_solve_banded((self.static_factor if static else self.factor, False), rhs, check_finite=False)

    def static_compliance(self, x: float) -> float:
        dofs, shape = self.contact(x)
        load = np.zeros(self.model.n_dof)
        load[dofs] = shape
        return float(shape @ self.solve(load, static=True)[dofs])


def _hertz_force(target: float, compliance: float, constant: float) -> float:
    """F = C u^1.5 with u + compliance C u^1.5 = target (u >= 0; target <= 0: no contact), by bisection-safe
    Newton on u."""
    if target <= 0.0:
        return 0.0
    u = target
    for _ in range(100):
        residual = u + compliance * constant * u**1.5 - target
        step = residual / (1.0 + 1.5 * compliance * constant * math.sqrt(u))
        u = max(u - step, 0.5 * u)
        if abs(step) <= 1e-14 * target:
            break
    return constant * u**1.5


IRREGULARITIES = {  # each centred at a given position (m)
    "flat": lambda at: WheelFlat(length=FLAT_LENGTH, position=at),
    # a long gentle dip, 3 mm deep over 1.8 m (curving at most 2 pi^2 D / L^2 = 0.018 / m, far below 1/R): nothing
    # to bridge, no impact; the suspension lets the wheel follow it, the static force changes by ~k_S D
    "weld": lambda at: DippedWeld(position=at, length=1.8, depth=3e-3),
}


def layout(n_bays: int) -> tuple[float, float, float]:
    """(start, irregularity's centre, end) of a run on an ``n_bays`` track, m: from a midspan two bays before the
    centre (a midspan) to 1.5 bays after it."""
    bay = TrackParameters().support.sleeper_spacing
    centre = (n_bays // 2) * bay
    return centre - 1.5 * bay, centre + 0.5 * bay, centre + 2.0 * bay


def trajectory(kind: str, wheel_radius: float, n_bays: int) -> tuple[np.ndarray, np.ndarray]:
    """The wheel-centre trajectory over the run's irregularity (``IRREGULARITIES[kind]``): (x, z_c), m."""
    start, at, end = layout(n_bays)
    x = np.arange(start - 0.1, end + 0.1, PROFILE_SPACING)
    profile = raw_profile([IRREGULARITIES[kind](at)], x, wheel_radius=wheel_radius)
    return x, wheel_centre_trajectory(profile, PROFILE_SPACING, wheel_radius)


def simulate_impact(
    speed: float,
    *,
    n_bays: int = 70,
    elements_per_bay: int = 16,
    time_step: float = 10e-6,
    kind: str = "flat",
    contact: ContactParameters | None = None,
    wheel: WheelParameters | None = None,
) -> ImpactResult:
    """Run the wheel at ``speed`` (m/s) over the irregularity ``kind`` (the flat); see the module docstring."""
    contact = contact or ContactParameters()
    wheel = wheel or WheelParameters()
    start, _, end = layout(n_bays)
    grid, lift = trajectory(kind, contact.radius_along, n_bays)
    track = _Track(TrackParameters(n_bays=n_bays), elements_per_bay, time_step)
    constant, preload, dt = contact.hertz_constant, contact.preload, time_step

    # wheel: dead load P on M_W (the suspension carries nothing statically), contact force on m_W
    mw, cw, kw = wheel_matrices(wheel)
    wheel_effective = kw + (2.0 / dt) * cw + (4.0 / dt**2) * mw
    wheel_inverse = np.linalg.inv(wheel_effective)
    wheel_unit = wheel_inverse[:, 1]  # m per N of contact force on m_W (pushes it up)

    # the static state at the start: rail under P, wheel under P, the spring compressed by Hertz's approach
    dofs, shape = track.contact(start)
    load = np.zeros(track.model.n_dof)
    load[dofs] = shape * preload
    u = track.solve(load, static=True)
    q = solve(kw, np.array([preload, -preload]))
    offset = (preload / constant) ** (2.0 / 3.0) - (q[1] - shape @ u[dofs] + np.interp(start, grid, lift))
    v_t, a_t, v_w, a_w = np.zeros_like(u), np.zeros_like(u), np.zeros(2), np.zeros(2)

    steps = int(round((end - start) / (speed * dt)))
    time = np.arange(steps + 1) * dt
    position = start + speed * time
    force = np.empty(steps + 1)
    force[0] = preload
    for n in range(1, steps + 1):
        x = position[n]
        dofs, shape = track.contact(x)
        rhs = track.M @ ((4.0 / dt**2) * u + (4.0 / dt) * v_t + a_t) + track.C @ ((2.0 / dt) * u + v_t)
        unit = np.zeros(track.model.n_dof)
        unit[dofs] = shape
        free, per_newton = track.solve(np.column_stack([rhs, unit])).T
        rhs_w = mw @ ((4.0 / dt**2) * q + (4.0 / dt) * v_w + a_w) + cw @ ((2.0 / dt) * q + v_w)
        free_w = wheel_inverse @ (rhs_w + np.array([preload, 0.0]))
        # compression = wheel - rail + trajectory: known part minus (wheel + rail compliance) F
        target = free_w[1] - shape @ free[dofs] + np.interp(x, grid, lift) + offset
        f = _hertz_force(target, wheel_unit[1] + shape @ per_newton[dofs], constant)
        u_new, q_new = free + f * per_newton, free_w - f * wheel_unit
        v_t, a_t = (2.0 / dt) * (u_new - u) - v_t, (4.0 / dt**2) * (u_new - u) - (4.0 / dt) * v_t - a_t
        v_w, a_w = (2.0 / dt) * (q_new - q) - v_w, (4.0 / dt**2) * (q_new - q) - (4.0 / dt) * v_w - a_w
        u, q, force[n] = u_new, q_new, f
    return ImpactResult(time=time, position=position, force=force, preload=preload)


def static_force(
    position: np.ndarray, *, kind: str = "flat", n_bays: int = 70, elements_per_bay: int = 16
) -> np.ndarray:
    """The static solution of the geometry at each position (N): wheel (suspension and k_W) and track (the FE
    model's static point compliance there) in series with the Hertz spring on the trajectory, the same datum as
    :func:`simulate_impact`'s start."""
    contact, wheel = ContactParameters(), WheelParameters()
    start, _, _ = layout(n_bays)
    grid, lift = trajectory(kind, contact.radius_along, n_bays)
    track = _Track(TrackParameters(n_bays=n_bays), elements_per_bay, 1e-5)
    _, _, kw = wheel_matrices(wheel)
    preload, constant = contact.preload, contact.hertz_constant
    dead = solve(kw, np.array([preload, 0.0]))[1]
    wheel_compliance = solve(kw, np.array([0.0, 1.0]))[1]
    rail0 = track.static_compliance(start)
    offset = (preload / constant) ** (2.0 / 3.0) - (dead - wheel_compliance * preload - rail0 * preload)
    offset -= float(np.interp(start, grid, lift))
    out = np.empty(len(position))
    for i, x in enumerate(position):
        compliance = wheel_compliance + track.static_compliance(float(x))
        out[i] = _hertz_force(dead + float(np.interp(x, grid, lift)) + offset, compliance, constant)
    return out


def main(argv: list[str]) -> None:
    preload = ContactParameters().preload
    if "--walking" in argv:
        for kind, speed_kmh, step in WALKING:
            run = simulate_impact(speed_kmh / 3.6, time_step=step, kind=kind)
            sample = slice(None, None, max(1, len(run.force) // 400))
            reference = static_force(run.position[sample], kind=kind)
            worst = np.max(np.abs(run.force[sample] - reference))
            print(
                f"{kind} at {speed_kmh:3.1f} km/h: force {run.minimum / 1e3:.2f} to {run.peak / 1e3:.2f} kN, static "
                f"solution {reference.min() / 1e3:.2f} to {reference.max() / 1e3:.2f} kN, largest difference "
                f"{worst / 1e3:.3f} kN ({100 * worst / preload:.2f} % of P)"
            )
        return
    print(f"50 mm rounded flat, R = {ContactParameters().radius_along} m, preload {preload / 1e3:.0f} kN, smooth rail")
    for speed_kmh in SPEEDS_KMH:
        run = simulate_impact(speed_kmh / 3.6)
        half = simulate_impact(speed_kmh / 3.6, time_step=5e-6)
        print(
            f"{speed_kmh:5.0f} km/h: peak {run.peak / 1e3:6.1f} kN ({run.peak / preload:.2f} P), minimum "
            f"{run.minimum / 1e3:5.1f} kN, without contact {run.time_without_contact * 1e3:.2f} ms; half step: peak "
            f"{half.peak / 1e3:6.1f} kN ({100 * (half.peak / run.peak - 1):+.2f} %), without contact "
            f"{half.time_without_contact * 1e3:.2f} ms"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
