"""The active set's capacitance solve (``contact.capacitance``) against the set's own factor.

Both solve eqs. 8-11 on the same set exactly; what may differ is round-off (sums in another order, a reference
factor and a small bordered system instead of a factor updated row by row), far below the solver's tolerance
of eq. 10 (1e-9 of the pressures, as ``tests/physics/test_halfspace_fine_reference.py``): the pressures are
compared at 1e-9 of the largest, the forces at 1e-9 relative, the sets exactly.
"""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.contact import active_set
from wheelrail.core.contact.capacitance import CAPACITANCE_MEMBERS
from wheelrail.core.contact.influence import influence_kernel

TOLERANCE = 1e-9
ELEMENT = 5e-4  # m
RADIUS = 0.39  # m, relative radius of the paraboloid


def _window(shape):
    ny, nx = shape
    y = (np.arange(ny) - ny // 2) * ELEMENT
    x = (np.arange(nx) - nx // 2) * ELEMENT
    base = (x[None, :] ** 2 + y[:, None] ** 2) / (2 * RADIUS)
    grid = active_set.influence_grid(influence_kernel(shape, ELEMENT))
    return base.ravel(), grid


def _solvers(grid, start):
    limits = (TOLERANCE, 200, ELEMENT**2)
    solvers = [active_set.ActiveSetSolver(grid, start, limits) for _ in range(2)]
    assert solvers[1].use_capacitance(True) is False
    return solvers


def _roughness(rng, shape, length):
    """Rows of a smooth random roughness (m), ``length`` samples long: a few sines along and across."""
    ny, _ = shape
    x = np.arange(length) * ELEMENT
    y = np.arange(ny)[:, None] * ELEMENT
    lines = np.zeros((ny, length))
    for _ in range(6):
        wavelength = rng.uniform(3e-3, 2e-2)
        across = rng.uniform(1e-2, 5e-2)
        lines += rng.uniform(0.2e-6, 1.0e-6) * np.sin(2 * np.pi * (x / wavelength + y / across) + rng.uniform(0, 7))
    return lines


def _same(factor, capacitance, force_f, force_c):
    assert np.isfinite(capacitance.pressure).all()
    scale = max(np.abs(factor.pressure).max(), 1.0)
    assert np.abs(capacitance.pressure - factor.pressure).max() <= TOLERANCE * scale
    assert abs(force_c - force_f) <= TOLERANCE * max(abs(force_f), 1.0)
    np.testing.assert_array_equal(np.sort(capacitance.contact_set()), np.sort(factor.contact_set()))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_rolling_solves_equal_the_factor_solves(seed):
    """A rolling run's solves (the roughness moves one element a step) from the same warm starts."""
    rng = np.random.default_rng(seed)
    shape = (21, 27)
    base, grid = _window(shape)
    ny, nx = shape
    lines = _roughness(rng, shape, nx + 120)
    start = np.flatnonzero(base <= 1.2e-5)
    solvers = _solvers(grid, start)
    approach = rng.uniform(1.5e-5, 2.5e-5)
    for step in range(120):
        gap = base - lines[:, step : step + nx].ravel()
        answers = []
        for solver in solvers:
            solver.gap[:] = gap
            status, force, delta, _ = solver.solve(True, approach + gap.min(), 2e-10)
            assert status in (active_set.STEP_CONVERGED, active_set.STEP_AT_EDGE)
            answers.append(force)
        _same(*solvers, *answers)
    counts = solvers[1].capacitance_counts()
    assert counts["references"] >= 1 and counts["vectors"] > 0  # the capacitance path did the solves


def test_loss_of_contact_and_back():
    """F = 0 (no NaN) where the wheel lifts off; the next loaded solve as the factor path's."""
    shape = (15, 19)
    base, grid = _window(shape)
    solvers = _solvers(grid, np.flatnonzero(base <= 5e-6))
    for approach in (1e-5, -2e-6, 0.0, 1.4e-5):
        forces = []
        for solver in solvers:
            solver.gap[:] = base
            status, force, _, _ = solver.solve(True, approach, 1e-10)
            assert status == active_set.STEP_CONVERGED
            forces.append(force)
        if approach <= 0.0:
            assert forces == [0.0, 0.0]
        else:
            _same(*solvers, *forces)


def test_reference_factored_afresh_when_the_set_moves_past_the_bound():
    """From one element to a set of more than ``CAPACITANCE_MEMBERS``: the reference is factored again."""
    shape = (25, 25)
    base, grid = _window(shape)
    centre = int(np.argmin(base))
    solvers = _solvers(grid, [centre])
    forces = []
    for solver in solvers:
        solver.gap[:] = base
        status, force, _, _ = solver.solve(True, 4.5e-5, 0.0)
        assert status == active_set.STEP_CONVERGED
        forces.append(force)
    assert solvers[0].contact_set().size > CAPACITANCE_MEMBERS + 1
    assert solvers[1].capacitance_counts()["references"] >= 2
    _same(*solvers, *forces)


def _reference_inverse_error(solver, kernel):
    """max |M - C_RR^-1| / max |C_RR^-1| for the reference's kept inverse M (``capacitance`` state)."""
    cap = solver.law[1][5]
    m = int(cap[0][1])
    reference = cap[1][:m]
    rows, columns = solver.law[0][3][reference], solver.law[0][4][reference]
    cy, cx = kernel.shape[0] // 2, kernel.shape[1] // 2
    c_rr = kernel[rows[:, None] - rows[None, :] + cy, columns[:, None] - columns[None, :] + cx]
    exact = np.linalg.inv(c_rr)
    return np.abs(cap[14][:m, :m] - exact).max() / np.abs(exact).max()


def test_reference_inverse_computed_again_with_each_reference():
    """The kept C_RR^-1 is that of the reference now, after the reference is factored again."""
    shape = (25, 25)
    base, grid = _window(shape)
    solver = _solvers(grid, [int(np.argmin(base))])[1]
    references = []
    for approach in (1.0e-5, 4.5e-5):  # the second set exceeds CAPACITANCE_MEMBERS changes: a new reference
        solver.gap[:] = base
        status, _, _, _ = solver.solve(True, approach, 0.0)
        assert status == active_set.STEP_CONVERGED
        assert _reference_inverse_error(solver, grid[0]) < 1e-12
        references.append(solver.capacitance_counts()["references"])
    assert references[1] > references[0]
