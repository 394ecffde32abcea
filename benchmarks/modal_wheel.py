"""The modal wheel's cost: meshing, assembling and solving every harmonic n = 0..10 up to 10 kHz for each named
wheel on the default 12 mm mesh (the target: under 10 s on 2 cores), a cached read, and the receptance and the
surface velocities over 1000 frequencies; then one harmonic of the 920 mm wheel by shift-invert Lanczos (the
method used) against a dense generalized eigen-solve (``scipy.linalg.eigh``) of the same matrices; last, the CPU
seconds per unit of work (``modes.modes_cost``) of finer meshes, against ``modes.SECONDS_PER_WORK``, which the
refusal of runaway modes (``modes.WORK_LIMIT``) and the estimate said before computing are scaled from.

Run: python3 benchmarks/modal_wheel.py   (a private temporary cache; ~90 s on 2 cores)
"""

from __future__ import annotations

import os
import tempfile
import time

import numpy as np

os.environ["WHEELRAIL_CACHE_DIR"] = tempfile.mkdtemp(prefix="wheelrail-bench-cache-")

from wheelrail.core.modal_wheel import (  # noqa: E402
    NAMED_WHEELS,
    contact_receptance,
    mean_square_velocity,
    wheel_modes,
)
from wheelrail.core.modal_wheel import modes as modes_module  # noqa: E402


def timed(function):
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def main() -> None:
    print(f"load average before: {os.getloadavg()[0]:.2f} (2 cores; other work slows the eigen-solves)")
    frequencies = np.linspace(10.0, 10e3, 1000)
    for name, profile in NAMED_WHEELS.items():
        modes, computed = timed(lambda profile=profile: wheel_modes(profile))
        modes_module._MEMORY.clear()  # the next call reads the disk cache
        _, cached = timed(lambda profile=profile: wheel_modes(profile))
        _, receptance = timed(lambda modes=modes: contact_receptance(modes, frequencies))
        _, velocity = timed(lambda modes=modes: mean_square_velocity(modes, frequencies))
        print(
            f"{name:12s} {len(modes.mesh.nodes):5d} nodes, {len(modes.frequency):3d} modes to 10 kHz (n <= 10): "
            f"computed in {computed:5.2f} s, read from the cache in {cached * 1e3:5.1f} ms; 1000 frequencies: "
            f"receptance {receptance * 1e3:5.1f} ms, surface velocities {velocity * 1e3:6.1f} ms"
        )


def sparse_against_dense() -> None:
    from scipy.linalg import eigh

    from wheelrail.core.modal_wheel.fem import fixed_dofs, harmonic_matrices, harmonic_modes
    from wheelrail.core.modal_wheel.mesh import mesh_outline

    profile = NAMED_WHEELS["freight_920"]
    mesh = mesh_outline(profile.outline(), modes_module.DEFAULT_ELEMENT_SIZE)
    model = harmonic_matrices(mesh)
    contact = int(np.argmin(np.hypot(*(mesh.nodes - np.asarray(profile.contact_point())).T)))
    sparse, t_sparse = timed(lambda: harmonic_modes(model, 2, 10e3, profile.bore_radius, contact))
    stiffness, mass = model.matrices(2)
    free = np.setdiff1d(np.arange(stiffness.shape[0]), fixed_dofs(mesh, 2, profile.bore_radius))
    k, m = stiffness[free][:, free].toarray(), mass[free][:, free].toarray()
    values, t_dense = timed(lambda: eigh(k, m, eigvals_only=True, subset_by_value=(-1.0, (2 * np.pi * 10e3) ** 2)))
    worst = np.max(np.abs(np.sqrt(values) / (2 * np.pi) / sparse.frequency - 1))
    print(
        f"n = 2 of the 920 mm wheel ({len(free)} DOFs, {len(values)} modes to 10 kHz): eigsh {t_sparse:.2f} s, dense "
        f"eigh {t_dense:.2f} s; frequencies agree within {worst:.1e}"
    )


def cost_per_unit() -> None:
    profile = NAMED_WHEELS["freight_920"]
    for size, harmonic, frequency in ((0.006, 10, 10e3), (0.003, 2, 5e3), (0.002, 2, 3e3)):
        cost = modes_module.modes_cost(profile, frequency, harmonic, size)
        start = time.process_time()
        modes = wheel_modes(profile, max_frequency=frequency, max_harmonic=harmonic, element_size=size, use_cache=False)
        seconds = time.process_time() - start
        print(
            f"{size * 1e3:g} mm, n <= {harmonic}, {frequency:g} Hz: {len(modes.mesh.triangles)} elements (estimated "
            f"{cost.elements}), {cost.work:,.0f} units in {seconds:.1f} s of CPU: {seconds / cost.work * 1e3:.2f} ms "
            f"per unit (SECONDS_PER_WORK {modes_module.SECONDS_PER_WORK * 1e3:.2f} ms)"
        )


if __name__ == "__main__":
    main()
    sparse_against_dense()
    cost_per_unit()
