"""The lengthened FE track's vibration at the noise chain's frequencies: the track part of the TWINS-like chain
(:mod:`wheelrail.core.noise.twins`, steps 1-3), solved in the frequency domain on a banded matrix.

:func:`track_vibration` solves the track (``NoiseNumerics.track_bays`` bays of ``elements_per_bay`` elements) at
every frequency for a unit force above a sleeper and at midspan, and reads what the chain needs of it: each
force-driven component's response, the rail's velocity integral and its radiated field, the receptance at the
contact and the transfer along the rail; :func:`banded_solver` and :func:`decay_grid` are its solver and its points,
which EN 15461's decay rate (``twins.track_decay_rates``) reads too.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from wheelrail.core.noise.components import TrackResponse
from wheelrail.core.parameters import ModelParameters


def banded_solver(model):
    """Displacements for loads at a frequency; the rail's loss factor exact (hysteretic, K_rail (1 + i eta))."""
    bands = model.frequency_domain_bands()

    def solve(frequency: float, load: np.ndarray) -> np.ndarray:
        return model.solve(*bands, frequency, load)

    return solve


def track_vibration(
    params: ModelParameters,
    numerics,
    k_hertz: float,
    freqs: np.ndarray,
    components: tuple,
) -> dict:
    """Steps 1-3 of :mod:`~wheelrail.core.noise.twins`' docstring (``numerics`` a ``NoiseNumerics``) for the
    track at every frequency of ``freqs`` (bands, points) and both excitation positions: each force-driven part's
    ``response`` (``responses``), the rail's velocity integral and its field radiated in the wavenumber domain,
    alpha_R + alpha_C (``alpha_track``; each (b, p, 2)), and per band the midspan transfer |u|^2 along the rail
    (EN 15461) and at the sleepers 3..20 bays on."""
    from wheelrail.core.track import assemble_track
    from wheelrail.core.track.fe import timoshenko_shape_functions

    model = assemble_track(replace(params.track, n_bays=numerics.track_bays), numerics.elements_per_bay)
    solve = banded_solver(model)
    positions, decay_nodes, free_nodes, free_distance = decay_grid(model, numerics)
    weights = np.gradient(model.node_x)  # trapezoid weights on the uniform node grid (half at the ends)
    weights[[0, -1]] *= 0.5
    point_dofs = []
    for x0 in positions:
        element, xi = model.locate(x0)
        e = int(element)
        point_dofs.append(
            (
                timoshenko_shape_functions(xi, model.element_length, model.shear_parameter),
                [model.w_dof[e], model.theta_dof[e], model.w_dof[e + 1], model.theta_dof[e + 1]],
            )
        )
    loads = np.stack([model.load_vector(x) for x in positions], axis=1)
    shape = (*freqs.shape, len(positions))
    driven = [c for c in components if c.track_part]
    out = {
        "responses": {c.name: np.empty(shape) for c in driven},
        "rail": np.empty(shape),
        "rail_radiated": np.empty(shape),
        "alpha_track": np.empty(shape, dtype=complex),
        "contact_stiffness": k_hertz,  # alpha_C = 1 / k_hertz in alpha_track
        "transfer_sq": np.zeros((freqs.shape[0], decay_nodes.stop - decay_nodes.start)),
        "free_sq": np.zeros((freqs.shape[0], len(free_nodes))),
        "free_distance": free_distance,
        "dx": model.element_length,
    }
    for (b, p), f in np.ndenumerate(freqs):
        w = 2 * np.pi * f
        solutions = solve(f, loads)  # one factorisation for both excitation positions
        for j, (shape_n, dofs) in enumerate(point_dofs):
            u = solutions[:, j]
            state = TrackResponse(model, u, f)
            rail = state.rail
            out["rail"][b, p, j] = w**2 * np.sum(weights * np.abs(rail) ** 2)
            out["rail_radiated"][b, p, j] = state.rail_radiated
            for c in driven:
                out["responses"][c.name][b, p, j] = c.response(state)
            out["alpha_track"][b, p, j] = shape_n @ u[dofs] + 1.0 / k_hertz
            if j == 1:  # midspan excitation: EN 15461 and the free wave
                out["transfer_sq"][b] += np.abs(rail[decay_nodes]) ** 2
                out["free_sq"][b] += np.abs(rail[free_nodes]) ** 2
    return out


def decay_grid(model, numerics):
    """The excitation positions (above the central sleeper, midspan), the rail nodes of EN 15461's sum (from
    midspan over ``decay_length``), the sleeper nodes 3 to 20 bays on (the free wave) and their distances."""
    spacing = model.params.support.sleeper_spacing
    centre_bay = model.params.n_bays // 2
    positions = (centre_bay * spacing, (centre_bay + 0.5) * spacing)
    x_nodes = model.node_x
    decay_nodes = slice(
        np.searchsorted(x_nodes, positions[1]), np.searchsorted(x_nodes, positions[1] + numerics.decay_length)
    )
    free_bays = np.arange(3, 21)
    free_nodes = np.arange(0, len(x_nodes), numerics.elements_per_bay)[centre_bay + free_bays]
    return positions, decay_nodes, free_nodes, free_bays * spacing
