"""How close the discretised contact models come to Hertz's ellipse, over several geometries (not a timing).

Prints, for the paper's circle (R = 0.39 m), a 0.46 m wheel on a 0.30 m crown with a cylindrical, a concave
(-0.5 m) and convex (+0.3, +0.5, +1 m) tread, and a 0.2 m wheel on a 0.8 m crown:

* the calibrated ``2d`` bedding (``contact.winkler.calibrated_bedding``): the worst |F / (C delta^1.5) - 1|
  over approaches of 40-150 um on the 1 mm grid, swept every 0.01 um (a coarse sweep misses the worst point);
* the 3D half-space solver on the smooth gap at 65 kN, 1 mm and 0.5 mm elements: signed errors of the peak
  pressure, the approach, the semi-axes a and b from the pressure's second moments (a^2/5 and b^2/5 per unit
  load for an ellipsoidal pressure) and of the contact area counted by elements (elements with p > 0 times
  dx^2) against pi a b;
* that counted area against pi a b at 1 mm for loads of 20 to 200 kN.

Run: ``python3 validation/contact_geometry_accuracy.py`` (about a minute).
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.contact.window import solve_normal_contact
from wheelrail.core.contact.winkler import _winkler_force, calibrated_bedding, wheel_profile
from wheelrail.core.parameters import ContactParameters

GEOMETRIES = {
    "circle 0.39 m": ContactParameters(),
    "0.46 on 0.30 m": ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30),
    "tread -0.5 m": ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=-0.5),
    "tread +0.3 m": ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=0.3),
    "tread +0.5 m": ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=0.5),
    "tread +1 m": ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=1.0),
    "0.2 on 0.8 m": ContactParameters(wheel_radius=0.2, rail_crown_radius=0.8),
}
LOADS = (20e3, 40e3, 65e3, 100e3, 150e3, 200e3)


def bedding_worst(contact: ContactParameters) -> tuple[float, float]:
    """Worst relative deviation of the 1 mm bedding from C delta^1.5 over 40-150 um, and where (m)."""
    stiffness, radius = calibrated_bedding(contact)
    profile = wheel_profile(81, 1e-3, radius)
    worst, where = 0.0, 0.0
    for approach in np.linspace(40e-6, 150e-6, 11001):
        force, _, _, edge = _winkler_force(approach, np.zeros(81), profile, stiffness * 1e-3)
        assert not edge
        deviation = abs(force / (contact.hertz_constant * approach**1.5) - 1)
        if deviation > worst:
            worst, where = deviation, approach
    return worst, where


def solver_errors(contact: ContactParameters, dx: float, load: float | None = None) -> dict[str, float]:
    """Signed relative errors of the 3D solver against Hertz on the smooth gap."""
    load = contact.preload if load is None else load
    hertz = contact.hertz(load)
    a, b = hertz.semi_axis_along, hertz.semi_axis_across
    nx, ny = math.ceil(1.3 * a / dx), math.ceil(1.3 * b / dx)
    x, y = np.arange(-nx, nx + 1) * dx, np.arange(-ny, ny + 1) * dx
    gap = x[None, :] ** 2 / (2 * contact.radius_along) + y[:, None] ** 2 / (2 * contact.radius_across)
    result = solve_normal_contact(gap, dx, load=load, contact=contact)
    p = result.pressure
    total = p.sum() * dx * dx
    return {
        "p0": p.max() / hertz.peak_pressure - 1,
        "approach": result.approach / hertz.approach - 1,
        "a": math.sqrt(5 * (p * x[None, :] ** 2).sum() * dx * dx / total) / a - 1,
        "b": math.sqrt(5 * (p * y[:, None] ** 2).sum() * dx * dx / total) / b - 1,
        "area": result.contact_area / (math.pi * a * b) - 1,
    }


def main() -> None:
    print("2d bedding on the 1 mm grid, worst |F / (C delta^1.5) - 1| over 40-150 um (0.01 um sweep):")
    for name, contact in GEOMETRIES.items():
        worst, where = bedding_worst(contact)
        print(f"  {name:15s} {worst * 100:5.2f} % at {where * 1e6:6.2f} um", flush=True)
    print("3D solver against Hertz at 65 kN, signed %: p0, approach, a and b (second moments), counted area:")
    for name, contact in GEOMETRIES.items():
        for dx in (1e-3, 0.5e-3):
            errors = solver_errors(contact, dx)
            print(
                f"  {name:15s} {dx * 1e3:.1f} mm " + "  ".join(f"{k} {v * 100:+5.2f}" for k, v in errors.items()),
                flush=True,
            )
    print(
        "3D contact area counted by elements / (pi a b) - 1 at 1 mm, %, loads "
        + ", ".join(f"{load / 1e3:g}" for load in LOADS)
        + " kN:"
    )
    for name, contact in GEOMETRIES.items():
        values = [solver_errors(contact, 1e-3, load)["area"] * 100 for load in LOADS]
        print(f"  {name:15s} " + " ".join(f"{v:+6.2f}" for v in values), flush=True)


if __name__ == "__main__":
    main()
