"""The deformed gap outside the contact set on large windows (``contact.active_set``), and the ``3d`` law at 0.5 mm.

* The screen of the rigid overlap (``deformed_gap.screen``) keeps every element that penetrates: its bound of
  u = C p is a lower bound (the kernel of eq. 8 decreases with each offset), checked against u computed in full
  on random sets and pressures, window shapes down to one row;
* u = C p from the kernel (``deformed_gap.displacement_kernel``: one contiguous slice per element, the candidates in
  groups of columns) equals u from the full influence matrix: tolerance 1e-12 of max u, round-off of
  reordered sums of positive terms (measured below 5e-16);
* u in float32 (``deformed_gap.displacement_kernel32``) lies within its error bound (``deformed_gap.float32_error``)
  of u in float64, and the solver's penetration decisions made from it (``deformed_gap.displacement_decided``:
  float64 again where the bound cannot decide) are float64's, on gaps put at the decision's edge; so are those of
  a later check that keeps the earlier one's bounds (``deformed_gap.displacement_kept``) after the pressure changed;
* steps of the ``3d`` law on a 31 x 41 window at 0.5 mm (over ``FULL_MATRIX_ELEMENTS``: the kernel path and the
  screen) agree with the dense NNLS oracle (``halfspace_oracle``) to 1e-9 of the preload, as the 1 mm runs in
  ``test_halfspace_loop.py``: the same equations, round-off of reordered sums left.
"""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.contact import active_set, deformed_gap
from wheelrail.core.contact.halfspace_model import HalfSpaceModel
from wheelrail.core.contact.influence import influence_kernel
from wheelrail.core.models import ModelInputs
from wheelrail.core.parameters import ModelParameters, RunParameters

TOLERANCE = 1e-9  # of the preload, as tests/physics/test_halfspace_loop.py (module docstring)


def _random_state(rng, shape):
    """A random contact set (a blob of the window, some pressures slightly negative) and its pressure."""
    ny, nx = shape
    rows, columns = np.divmod(np.arange(ny * nx), nx)
    centre = rng.uniform(0, ny - 1), rng.uniform(0, nx - 1)
    radius = rng.uniform(0.5, max(ny, nx) / 2)
    inside = (rows - centre[0]) ** 2 + (columns - centre[1]) ** 2 <= radius**2
    inside[rng.integers(ny * nx)] = True
    pressure = np.where(inside, rng.uniform(-1e-3, 1.0, ny * nx) * 1e9, 0.0)
    return np.flatnonzero(inside), pressure


@pytest.mark.parametrize("shape", [(1, 7), (3, 5), (4, 9), (19, 25), (37, 49)])
def test_screen_keeps_every_penetrating_element(shape):
    rng = np.random.default_rng(sum(shape))
    grid = active_set.influence_grid(influence_kernel(shape, 5e-4), full_matrix=True)
    for _ in range(20):
        order, pressure = _random_state(rng, shape)
        u = active_set.displacement(grid, pressure)
        outside = np.setdiff1d(np.arange(pressure.size), order)
        gap = rng.uniform(0.0, 2.0, pressure.size) * u.max()
        limit = rng.uniform(0.5, 1.5) * u.max()
        candidates = np.zeros(pressure.size, dtype=np.int64)
        candidates[: outside.size] = outside
        kept = deformed_gap.screen(grid, order, order.size, pressure, gap, candidates, outside.size, limit)
        penetrating = outside[gap[outside] + u[outside] < limit]
        # every element that penetrates is kept (exactly: the bound is a lower bound)
        assert set(penetrating) <= set(candidates[:kept])


@pytest.mark.parametrize("shape", [(1, 7), (4, 9), (37, 49)])
def test_kernel_displacement_equals_the_matrix(shape):
    rng = np.random.default_rng(7)
    kernel = influence_kernel(shape, 5e-4)
    by_kernel = active_set.influence_grid(kernel, full_matrix=False)
    by_matrix = active_set.influence_grid(kernel, full_matrix=True)
    for _ in range(10):
        order, pressure = _random_state(rng, shape)
        pressure = np.abs(pressure)
        candidates = rng.permutation(pressure.size)[: rng.integers(1, pressure.size + 1)]
        u = np.empty(candidates.size)
        deformed_gap.displacement_kernel(by_kernel, order, order.size, pressure, candidates, candidates.size, u)
        expected = active_set.displacement(by_matrix, pressure)[candidates]
        # round-off of reordered sums of positive terms (module docstring)
        assert np.max(np.abs(u - expected)) <= 1e-12 * expected.max()


def test_kernel_displacement_of_no_candidates():
    grid = active_set.influence_grid(influence_kernel((19, 25), 5e-4), full_matrix=False)
    order, pressure = _random_state(np.random.default_rng(1), (19, 25))
    for products in (deformed_gap.displacement_kernel, deformed_gap.displacement_kernel32):
        products(grid, order, order.size, pressure, np.zeros(0, dtype=np.int64), 0, np.empty(0))  # no error


@pytest.mark.parametrize("shape", [(4, 9), (37, 49)])
def test_float32_displacement_within_its_bound(shape):
    rng = np.random.default_rng(11)
    kernel = influence_kernel(shape, 5e-4)
    by_kernel = active_set.influence_grid(kernel, full_matrix=False)
    by_matrix = active_set.influence_grid(kernel, full_matrix=True)
    centre = kernel[kernel.shape[0] // 2, kernel.shape[1] // 2]
    for _ in range(10):
        order, pressure = _random_state(rng, shape)  # some pressures slightly negative
        candidates = rng.permutation(pressure.size)[: rng.integers(1, pressure.size + 1)]
        u = np.empty(candidates.size)
        deformed_gap.displacement_kernel32(by_kernel, order, order.size, pressure, candidates, candidates.size, u)
        expected = active_set.displacement(by_matrix, pressure)[candidates]
        negative = -np.minimum(pressure[order], 0.0).sum()
        bound = np.array([deformed_gap.float32_error(value, order.size, 2 * centre * negative) for value in u])
        assert np.all(np.abs(u - expected) <= bound)
        assert np.max(np.abs(u - expected)) > 1e-12 * np.abs(expected).max()  # float32 indeed (not float64)


def test_penetration_decided_in_float32_as_in_float64():
    shape = (37, 49)
    rng = np.random.default_rng(5)
    grid = active_set.influence_grid(influence_kernel(shape, 5e-4), full_matrix=False)
    n = shape[0] * shape[1]
    flipped = 0
    for _ in range(10):
        order, pressure = _random_state(rng, shape)
        outside = np.setdiff1d(np.arange(n), order)
        u = active_set.displacement(grid, pressure)
        delta, glimit = 1e-5, -1e-9 * 1e-5
        # gaps that put d = h - delta + u at glimit within a few float32 roundings of u, on either side
        gap = glimit + delta - u + rng.choice([-1, 1], n) * rng.uniform(0, 3e-7, n) * np.abs(u)
        values, lower = np.empty(outside.size), np.empty(outside.size)
        limits = (delta, glimit)
        deformed_gap.displacement_decided(
            grid, order, order.size, pressure, gap, outside, outside.size, values, lower, limits
        )
        decided = gap[outside] - delta + values < glimit
        expected = gap[outside] - delta + u[outside] < glimit
        np.testing.assert_array_equal(decided, expected)
        assert np.all(lower <= u[outside])  # the lower bounds a step's later checks keep
        single = np.empty(outside.size)
        deformed_gap.displacement_kernel32(grid, order, order.size, pressure, outside, outside.size, single)
        flipped += np.count_nonzero((gap[outside] - delta + single < glimit) != expected)
    assert flipped > 0  # float32 alone would have decided some of them otherwise


def test_a_later_check_keeps_bounds_and_decides_as_float64():
    shape = (37, 49)
    rng = np.random.default_rng(9)
    grid = active_set.influence_grid(influence_kernel(shape, 5e-4), full_matrix=False)
    n = shape[0] * shape[1]
    for _ in range(5):
        order, pressure = _random_state(rng, shape)
        outside = np.setdiff1d(np.arange(n), order)
        delta, glimit = 1e-5, -1e-11
        u = active_set.displacement(grid, pressure)
        # none penetrates; half near the edge (d within 1e-3 of max u), half farther (within 0.1)
        gap = glimit + delta - u + rng.uniform(0, 1.0, n) * rng.choice([1e-3, 0.1], n) * u.max()
        bounds = (np.full(n, np.nan), np.empty(n, dtype=np.int64), np.zeros(2))
        changes = np.zeros(n, dtype=np.int64)
        work = (pressure, gap, None, changes, None, np.empty(n), None, bounds)
        changes[: outside.size] = outside
        deformed_gap.displacement_kept(grid, order, order.size, work, outside.size, (delta, glimit))  # a first check
        # the pressure changes (some of it decreases, as when elements join the set); the gap stays
        before = pressure[order].copy()
        pressure[order] *= 1.0 - rng.uniform(-1e-3, 2e-3, order.size)
        bounds[2][0] = np.sum(np.maximum(before - pressure[order], 0.0))
        changes[: outside.size] = outside
        deformed_gap.displacement_kept(grid, order, order.size, work, outside.size, (delta, glimit))
        u = active_set.displacement(grid, pressure)
        decided = gap[outside] - delta + work[5][: outside.size] < glimit
        np.testing.assert_array_equal(decided, gap[outside] - delta + u[outside] < glimit)
        assert decided.any()  # some penetrate now
        assert np.all(bounds[0][outside] <= u[outside])  # the bounds kept hold
        # some were decided by the bounds kept (not computed again)
        assert np.count_nonzero(work[5][: outside.size] < u[outside] - 1e-6 * u.max()) > outside.size // 10


@pytest.mark.slow  # ~5 s: the oracle's dense NNLS on ~700 elements per step
def test_3d_law_at_half_a_millimetre_agrees_with_the_oracle():
    from halfspace_oracle import coupled_pressure, influence_matrix

    dx = 5e-4
    params = ModelParameters(run=RunParameters(element_size=dx))
    ny, half_x, steps = 31, 20, 3
    window_y = (np.arange(ny) - ny // 2) * dx
    samples = np.arange(2 * half_x + steps + 1) * dx
    rng = np.random.default_rng(3)
    # a corrugation 50 um deep and 40 mm long, with a lateral tilt and small random roughness (m)
    lines = 25e-6 * np.sin(2 * np.pi * samples / 0.04)[None, :] * (1 + 10 * window_y[:, None])
    lines = lines + rng.normal(0.0, 0.3e-6, lines.shape)
    inputs = ModelInputs(
        params=params,
        element_size=dx,
        lines=lines,
        centre_row=ny // 2,
        window_y=window_y,
        half_x=half_x,
        start_index=half_x + np.arange(steps),
        ramp=np.ones(steps),
        position_of=lambda s: s * dx,
    )
    model = HalfSpaceModel()
    approach = model.prepare(inputs)
    assert model.law_inputs().law[0][2].size == 0  # the kernel path (window over FULL_MATRIX_ELEMENTS)
    matrix = influence_matrix((ny, 2 * half_x + 1), dx, params.contact)
    base_gap = model.law_inputs().track[0].reshape(ny, -1)
    compliance = 1e-10  # m/N: a coupled step, delta = delta_known - c F
    preload = params.contact.preload
    for s in range(steps):
        known = approach + compliance * preload + 20e-6 * np.sin(s)
        ours = model.solve(s, known, compliance)
        gap = base_gap - lines[:, s : s + 2 * half_x + 1]
        theirs = coupled_pressure(matrix, gap, known, compliance, dx * dx)[0]
        assert theirs.sum() > 0.0
        assert abs(ours.force - theirs.sum() * dx * dx) <= TOLERANCE * preload
        assert np.max(np.abs(ours.pressure.ravel() - theirs)) <= TOLERANCE * theirs.max()


@pytest.mark.parametrize("size", [1, 2, 3, 4, 5, 7, 8, 9, 1813])
def test_the_solvers_minimum_and_sum_of_a_window(size):
    """The gap's minimum a step starts from (four chains of comparisons) is numpy's to the bit, wherever the lowest
    element lies; the window's pressure summed in any order is numpy's sum to round-off."""
    rng = np.random.default_rng(size)
    values = rng.normal(size=size) * 1e-4
    for where in {0, size // 2, size - 1}:
        trial = values.copy()
        trial[where] = -1.0
        assert active_set._lowest(trial) == trial.min()
    assert active_set._lowest(values) == values.min()
    assert active_set._sum(values) == pytest.approx(values.sum(), rel=0, abs=1e-15 * size * np.abs(values).max())
