"""Speed of one static 3D normal-contact solve: wheelrail vs tamaas vs Hertz.

Problem: crossed cylinders of equal radius R = 0.39 m (sphere on a flat), E = 210 GPa, nu = 0.3, 65 kN,
on the 1 mm window (24 x 24) and the 0.5 mm window (48 x 48). For each window:

* cold      no initial guess;
* warm 98 % warm-started from the solution at 98 % of the load;
* rolling   the gap of the next step of a rolling run (sphere + a 1 um rms roughness moved on by one
            element), warm-started from the previous step's solution.

tamaas (optional, ``pip install .[bench]``) solves the same problem with its non-periodic ``dcfft``
operator and the Polonsky-Keer-Rey solver (relative tolerance 1e-10); its warm start is its own traction
field left from the previous solve. Times are medians of repeated solves (the set-up, e.g. the tamaas model,
is outside the timing). Run: ``python3 benchmarks/contact_solver.py``.
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from wheelrail.core.contact import solve_normal_contact
from wheelrail.core.parameters import ContactParameters

CONTACT = ContactParameters()
LOAD = CONTACT.preload
E, NU, R = CONTACT.youngs_modulus, CONTACT.poisson_ratio, CONTACT.radius
REPEATS = {24: 200, 48: 20}


def sphere(n: int, dx: float) -> np.ndarray:
    c = (np.arange(n) - (n - 1) / 2) * dx
    return (c[:, None] ** 2 + c[None, :] ** 2) / (2 * R)


def rolling_pair(n: int, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """Gaps of two successive steps: the roughness (1 um rms, seeded) moves by one element along x."""
    rng = np.random.default_rng(2011)
    roughness = rng.normal(size=(n, n + 1))
    roughness = (roughness + np.roll(roughness, 1, 1) + np.roll(roughness, 1, 0)) / 3
    roughness *= 1e-6 / roughness.std()
    return sphere(n, dx) - roughness[:, :n], sphere(n, dx) - roughness[:, 1:]


def median_time(function, repeats: int) -> float:
    """Median wall time of ``repeats`` calls, s (the median, not the minimum: the VM's CPU can be stolen)."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def ours(n: int, dx: float) -> dict:
    gap = sphere(n, dx)
    repeats = REPEATS[n]
    solve_normal_contact(gap, dx, load=LOAD)  # compile / load the numba cache and the kernel cache
    cold = median_time(lambda: solve_normal_contact(gap, dx, load=LOAD), max(5, repeats // 4))
    near = solve_normal_contact(gap, dx, load=0.98 * LOAD)
    warm = median_time(lambda: solve_normal_contact(gap, dx, load=LOAD, initial=near), repeats)
    before, after = rolling_pair(n, dx)
    previous = solve_normal_contact(before, dx, load=LOAD)
    rolling = median_time(lambda: solve_normal_contact(after, dx, load=LOAD, initial=previous), repeats)
    result = solve_normal_contact(gap, dx, load=LOAD)
    iterations = (
        solve_normal_contact(gap, dx, load=LOAD).iterations,
        solve_normal_contact(gap, dx, load=LOAD, initial=near).iterations,
        solve_normal_contact(after, dx, load=LOAD, initial=previous).iterations,
    )
    return {
        "cold": cold,
        "warm": warm,
        "rolling": rolling,
        "iterations": iterations,
        "p0": result.pressure.max(),
        "radius": np.sqrt(result.contact_area / np.pi),
        "approach": result.approach,
        "elements": int(result.contact.sum()),
    }


def tamaas_available() -> str | None:
    try:
        import tamaas  # noqa: F401
    except Exception as error:  # any import failure means: print ours alone
        return f"{type(error).__name__}: {error}"
    return None


def with_tamaas(n: int, dx: float) -> dict:
    import tamaas as tm

    tm.set_log_level(tm.LogLevel.error)
    side = n * dx
    mean_pressure = LOAD / side**2

    def make(surface: np.ndarray):
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [side, side], [n, n])
        model.E = E / 2  # tamaas' E* = E / (1 - nu^2) of one body on a rigid one; two equal bodies: E / 2
        model.nu = NU
        tm.ModelFactory.registerNonPeriodic(model, "dcfft")
        solver = tm.PolonskyKeerRey(model, surface, 1e-10)
        solver.setIntegralOperator("dcfft")
        return model, solver

    repeats = max(5, REPEATS[n] // 10)
    surface = -sphere(n, dx)  # tamaas takes the surface height of a rigid body against a flat

    def cold_solve():
        model, solver = make(surface)
        start = time.perf_counter()
        solver.solve(mean_pressure)
        return time.perf_counter() - start

    cold_solve()
    cold = statistics.median(cold_solve() for _ in range(repeats))

    model, solver = make(surface)
    solver.solve(0.98 * mean_pressure)
    near = np.array(model.traction).copy()

    def warm_solve():
        model.traction[...] = near
        start = time.perf_counter()
        solver.solve(mean_pressure)
        return time.perf_counter() - start

    warm = statistics.median(warm_solve() for _ in range(repeats))
    pressure = np.array(model.traction).copy()

    before, after = rolling_pair(n, dx)
    rolling_surface = -before
    model_r, solver_r = make(rolling_surface)
    solver_r.solve(mean_pressure)
    previous = np.array(model_r.traction).copy()

    def rolling_solve():
        model_r.traction[...] = previous
        rolling_surface[...] = -after  # the solver holds this array: update in place
        start = time.perf_counter()
        solver_r.solve(mean_pressure)
        elapsed = time.perf_counter() - start
        rolling_surface[...] = -before
        return elapsed

    rolling = statistics.median(rolling_solve() for _ in range(repeats))
    return {
        "cold": cold,
        "warm": warm,
        "rolling": rolling,
        "p0": pressure.max(),
        "radius": np.sqrt(np.count_nonzero(pressure > 0) * dx * dx / np.pi),
        "elements": int(np.count_nonzero(pressure > 0)),
    }


def main() -> None:
    a, p0, delta = CONTACT.hertz_radius(), CONTACT.hertz_peak_pressure(), CONTACT.hertz_approach()
    print(f"Hertz: a = {a * 1e3:.3f} mm, p0 = {p0 / 1e6:.1f} MPa, approach = {delta * 1e6:.2f} um at {LOAD / 1e3:g} kN")
    problem = "tamaas not available ({}); printing wheelrail alone"
    reason = tamaas_available()
    if reason:
        print(problem.format(reason))
    print()
    header = f"{'window':>16} {'solver':>9} {'cold ms':>9} {'warm98 ms':>10} {'rolling ms':>11} "
    header += f"{'p0 MPa':>8} {'a mm':>7} {'approach um':>12} {'elements':>9}"
    print(header)
    for n, dx in ((24, 1e-3), (48, 0.5e-3)):
        label = f"{n}x{n} @ {dx * 1e3:g} mm"
        ours_ = ours(n, dx)
        print(
            f"{label:>16} {'wheelrail':>9} {ours_['cold'] * 1e3:9.3f} {ours_['warm'] * 1e3:10.3f} "
            f"{ours_['rolling'] * 1e3:11.3f} {ours_['p0'] / 1e6:8.1f} {ours_['radius'] * 1e3:7.3f} "
            f"{ours_['approach'] * 1e6:12.2f} {ours_['elements']:9d}   iterations {ours_['iterations']}"
        )
        if not reason:
            try:
                theirs = with_tamaas(n, dx)
            except Exception as error:  # report and go on with ours alone
                print(f"{label:>16} {'tamaas':>9} failed: {type(error).__name__}: {error}")
                continue
            print(
                f"{label:>16} {'tamaas':>9} {theirs['cold'] * 1e3:9.3f} {theirs['warm'] * 1e3:10.3f} "
                f"{theirs['rolling'] * 1e3:11.3f} {theirs['p0'] / 1e6:8.1f} {theirs['radius'] * 1e3:7.3f} "
                f"{'':>12} {theirs['elements']:9d}"
            )
            speedup = [theirs[case] / ours_[case] for case in ("cold", "warm", "rolling")]
            print(f"{'':>16} {'speed-up':>9} {speedup[0]:8.1f}x {speedup[1]:9.1f}x {speedup[2]:10.1f}x")
    print()
    print("targets: warm 1 mm <= 0.25 ms and >= 8x faster than tamaas warm; 0.5 mm no slower than tamaas")


if __name__ == "__main__":
    main()
