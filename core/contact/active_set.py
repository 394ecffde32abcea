"""The active-set solver of the 3D half-space contact (paper section 2.3.2, eqs. 8-11), compiled by numba.

An exact active-set method (Kalker's scheme with the load, or the coupling delta = delta_known - c F, as an
extra equation). Each iteration solves on the contact set A, ``C_AA p_A = delta - h_A`` with one Cholesky
factor C_AA = U^T U (:func:`_pressure_on_set`); drops the elements in tension (eq. 10: p >= 0); if none,
adds the elements that penetrate (eq. 10: d >= 0) until neither happens. The factor is updated, not
recomputed, when few elements change (a new row per added element, rotations per dropped one), and
z = U^-T 1 and, within a step, y = U^-T h_A are kept with it, so a warm-started solve costs one forward
substitution per step and one backward substitution per iteration. The deformed gap outside the set is
``contact.deformed_gap``'s; on windows without the influence matrix u = C p is summed in float32 where a
rigorous bound shows that float64 would decide the same (``deformed_gap.displacement_decided``), and a step's later
checks keep lower bounds of u from its earlier ones (``deformed_gap.displacement_kept``). With ``capacitance``
on (the ``3d`` model on windows without the influence matrix) the set is solved through a reference set's factor
and a small capacitance system instead of its own factor (``contact.capacitance``). :class:`ActiveSetSolver`
holds the warm state (set, factor, z, pressure) in arrays that the ``3d`` model's compiled loop steps in place
(``halfspace_model``) and that one-off solves (``window.HalfSpaceWindow``) fill from a start. Design and
measurements: ``docs/benchmarks.md``, "The 3D contact solver".

Conventions of the compiled functions (no input checks: ``window`` does them): the window of ny x nx
elements is flattened row by row (element i is row i // nx, column i % nx); the contact set is ``order[:m]``
in the order of the rows of the upper factor ``upper[:m, :m]``, ``active`` its mask.
"""

from __future__ import annotations

import numpy as np
from numba import njit

import wheelrail.core.contact.capacitance as capacitance
import wheelrail.core.contact.cholesky as cholesky  # (not `from the package import`: the package imports this lazily)
import wheelrail.core.contact.deformed_gap as deformed_gap
from wheelrail.core.contact.capacitance import (
    capacitance_on,
    capacitance_state,
    change,
    prepare_gap,
    pressure_on_set,
    rebase,
)
from wheelrail.core.contact.cholesky import append, backward, factorize, forward, remove
from wheelrail.core.contact.deformed_gap import displacement_kept, displacement_kernel, displacement_matrix, screen
from wheelrail.core.engine.compiled import sources_stamp

__all__ = [
    "FULL_MATRIX_ELEMENTS",
    "STEP_AT_EDGE",
    "STEP_CONVERGED",
    "STEP_MAX_ITER",
    "STEP_NEEDS_ROOM",
    "STEP_NOT_DEFINITE",
    "ActiveSetSolver",
    "cached_grid",
    "cold_start_set",
    "displacement",
    "influence_grid",
    "solve_step",
]

STEP_CONVERGED = 0
STEP_MAX_ITER = 1  # no convergence within the iterations allowed
STEP_NOT_DEFINITE = 2  # the set's influence matrix lost positive definiteness in round-off
STEP_AT_EDGE = 3  # converged, but the set touches the window's border
STEP_NEEDS_ROOM = 4  # the set outgrew the factor's buffer: grow it and repeat the step
CAUTIOUS_AFTER = 30  # iterations; then one element at a time is dropped or added (against add/drop cycling)
FULL_MATRIX_ELEMENTS = 1024  # largest window (elements) whose influence matrix is built (8 MB; docs/benchmarks.md)


@njit(cache=True)
def _coordinates(ny, nx):
    """Row and column of every element of the flattened window."""
    rows = np.empty(ny * nx, dtype=np.int64)
    columns = np.empty(ny * nx, dtype=np.int64)
    for i in range(ny * nx):
        rows[i] = i // nx
        columns[i] = i - rows[i] * nx
    return rows, columns


@njit(cache=True, inline="always")
def _tension_elements(pressure, order, m, pmax, tol, one_at_a_time, removals):
    """Positions in ``order`` of the set's elements in tension (eq. 10: p >= 0), into ``removals``; their count.

    Pressures down to ``-tol * pmax`` count as zero. With ``one_at_a_time`` only the most tensile one.
    """
    plimit = -tol * pmax
    n_remove = 0
    worst = 0.0
    for a in range(m):
        value = pressure[order[a]]
        if value < plimit or (pmax <= 0.0 and value <= 0.0):
            if not one_at_a_time:
                removals[n_remove] = a
                n_remove += 1
            elif n_remove == 0 or value < worst:
                removals[0] = a
                n_remove = 1
                worst = value
    return n_remove


@njit(cache=True, fastmath=True)
def _lowest(values):
    """min(values), exactly (a minimum does not round), in four independent chains of comparisons."""
    n = values.size
    a0 = a1 = a2 = a3 = np.inf
    i = 0
    while i + 4 <= n:
        v0, v1, v2, v3 = values[i], values[i + 1], values[i + 2], values[i + 3]
        a0 = v0 if v0 < a0 else a0
        a1 = v1 if v1 < a1 else a1
        a2 = v2 if v2 < a2 else a2
        a3 = v3 if v3 < a3 else a3
        i += 4
    for j in range(i, n):
        a0 = values[j] if values[j] < a0 else a0
    a0 = a1 if a1 < a0 else a0
    a2 = a3 if a3 < a2 else a2
    return a2 if a2 < a0 else a0


@njit(cache=True, fastmath=True)
def _sum(values):
    """sum(values), vectorised (fastmath: the additions in any order)."""
    total = 0.0
    for i in range(values.size):
        total += values[i]
    return total


def influence_grid(kernel: np.ndarray, full_matrix: bool | None = None) -> tuple:
    """The solver's view of a window's influence coefficients: (kernel, kernel reversed, influence matrix C or
    0 x 0, row and column of each element).

    Parameters
    ----------
    kernel : ndarray, shape (2 ny - 1, 2 nx - 1)
        Influence kernel of eq. (8), m/Pa (``contact.influence.influence_kernel``).
    full_matrix : bool, optional
        Build the influence matrix C (default: for windows up to ``FULL_MATRIX_ELEMENTS`` elements).

    Returns
    -------
    tuple
        (kernel, kernel reversed, C (n x n) or 0 x 0, row of each element, column of each element).

    Notes
    -----
    ``C[i, j] = kernel[row_i - row_j + ny - 1, column_i - column_j + nx - 1]``: with it the deformed gap
    outside the set is one contiguous dot product per element (``docs/benchmarks.md``, "The contact solver").
    """
    kernel = np.array(kernel, dtype=np.float64)  # writable: one numba specialisation
    ny, nx = (kernel.shape[0] + 1) // 2, (kernel.shape[1] + 1) // 2
    rows, columns = _coordinates(ny, nx)
    full = np.empty((0, 0))
    if full_matrix or (full_matrix is None and ny * nx <= FULL_MATRIX_ELEMENTS):
        full = np.ascontiguousarray(
            kernel[rows[:, None] - rows[None, :] + ny - 1, columns[:, None] - columns[None, :] + nx - 1]
        )
    return kernel, np.ascontiguousarray(kernel[::-1, ::-1]), full, rows, columns


_GRIDS: dict = {}  # window key -> the solver's influence grid (the last few windows')


def cached_grid(key: tuple, kernel: np.ndarray) -> tuple:
    """The influence grid (:func:`influence_grid`) of the window ``key`` (any hashable naming its shape, element
    size and material) with this kernel, cached for the last few windows."""
    grid = _GRIDS.pop(key, None)
    if grid is None:
        grid = influence_grid(kernel)
        while len(_GRIDS) >= 4:
            _GRIDS.pop(next(iter(_GRIDS)))
    _GRIDS[key] = grid  # (re)inserted last: the oldest is dropped first
    return grid


class ActiveSetSolver:
    """The warm state of the active-set solver on one window and its solves (eqs. 8-11).

    Parameters
    ----------
    grid : tuple
        The window's influence coefficients, from :func:`influence_grid`.
    start : array_like of int
        The first solve's contact set (element indices of the flattened window).
    limits : (float, int, float) or (float, int, float, int)
        Relative tolerance of eq. (10), maximum iterations per solve, element area (m^2) and, optionally, the
        iterations after which one element at a time changes (default ``CAUTIOUS_AFTER``).
    factor : (ndarray, ndarray), optional
        The upper Cholesky factor of ``start`` in its order (m x m) and z = U^-T 1 (m): a warm start that
        skips the first factorisation. By default ``start`` is factored afresh.
    track : tuple, optional
        What the ``3d`` model's step reads besides the solver (``halfspace_model.track_inputs``); the solver
        itself does not use it.
    capacity : int, optional
        Rows of the factor's first buffer (default: twice the start set plus 64, at most the window).

    See Also
    --------
    wheelrail.core.contact.window.HalfSpaceWindow : one-off solves that fill a solver from a start.
    wheelrail.core.contact.halfspace_model.HalfSpaceModel : the ``3d`` model, which steps one in its loop.

    Notes
    -----
    ``law`` is the tuple the compiled functions take: (grid, state, work, track, limits) with state = (set
    in factor order, its mask, z = U^-T 1, [m, factored], factor buffer, ``contact.capacitance``'s state; with
    it on, the buffer holds the reference's factor and z is not kept) and work = (pressure, gap, five
    scratch vectors, the bounds of u kept across a step's checks: ``deformed_gap.displacement_kept``); ``pressure`` is
    the current pressure on the flattened window (Pa; stale after a coupled solve without contact, whose
    pressure is zero) and ``gap`` the gap a solve reads (m).
    """

    def __init__(self, grid, start, limits, *, factor=None, track=None, capacity=None) -> None:
        n = grid[3].size
        order = np.zeros(n, dtype=np.int64)
        active = np.zeros(n, dtype=np.bool_)
        start = np.asarray(start, dtype=np.int64)
        order[: start.size] = start
        active[start] = True
        z = np.zeros(n)
        counts = np.array([start.size, 0], dtype=np.int64)  # m, whether the buffer and z hold the set's factor
        self._state = (order, active, z, counts)
        self.pressure = np.zeros(n)
        self.gap = np.empty(n)
        work = (
            self.pressure,
            self.gap,
            np.empty(n),
            np.empty(n, dtype=np.int64),
            np.empty(n),
            np.empty(n),
            np.empty(n),
            (np.full(n, np.nan), np.empty(n, dtype=np.int64), np.zeros(2)),  # kept bounds (_penetrating)
        )
        if track is None:  # the one-off solves' placeholder (of the types of the model's)
            track = (np.zeros(1), np.zeros((1, 1)), np.zeros(1, dtype=np.int64), np.zeros(1), 0, 0)
        tolerance, max_iterations, area, *cautious = limits
        limits = (float(tolerance), int(max_iterations), float(area), int(cautious[0] if cautious else CAUTIOUS_AFTER))
        self._parts = (grid, work, track, limits)
        self._capacitance = False  # whether the law holds the capacitance solve's arrays (use_capacitance)
        self.grow(min(n, 2 * start.size + 64) if capacity is None else int(capacity))
        if factor is not None:
            m = start.size
            self.law[1][4][:m, :m] = factor[0]
            z[:m] = factor[1]
            counts[1] = 1

    def grow(self, capacity: int | None = None) -> None:
        """A new factor buffer of ``capacity`` rows (default: half as many again as the set, at most the
        window's elements); the set is factored afresh in it."""
        order, active, z, counts = self._state
        m = int(counts[0])
        capacity = min(order.size, m + m // 2 + 8) if capacity is None else int(capacity)
        counts[1] = 0
        grid, work, track, limits = self._parts
        cap = capacitance_state(order.size, capacity, self._capacitance)
        if hasattr(self, "law"):  # the switch and the counters carry over
            cap[0][[0, 5, 6]] = self.law[1][5][0][[0, 5, 6]]
        else:
            cap[0][0] = int(self._capacitance)
        self.law = (grid, (order, active, z, counts, np.empty((capacity, capacity)), cap), work, track, limits)

    def use_capacitance(self, on: bool) -> bool:
        """Solve on the set through a reference factor and a small capacitance system (``contact.capacitance``)
        or, ``on`` False, through the set's own factor (the default); the next solve factors afresh. Returns
        whether it was on."""
        was = self._capacitance and bool(self.law[1][5][0][0])
        if bool(on) == was:
            return was
        if on and not self._capacitance:
            self._capacitance = True
            self.grow(self.law[1][4].shape[0])  # the same buffer's size, with the capacitance solve's arrays
        self.law[1][5][0][0] = int(bool(on))
        self._state[3][1] = 0
        return was

    def capacitance_counts(self) -> dict:
        """The capacitance solve's counters: references factored, kept vectors computed, members now."""
        info = self.law[1][5][0]
        return {"references": int(info[5]), "vectors": int(info[6]), "members": int(info[2])}

    def solve(self, coupled: bool, target: float, compliance: float = 0.0) -> tuple[int, float, float, int]:
        """Solve on the gap in :attr:`gap` from the warm state: coupled (``target`` = delta_known, m;
        ``compliance`` c, m/N) or load-controlled (``target`` = F, N). Returns (status, F (N), delta (m),
        iterations); the pressure is in :attr:`pressure` (stale if F = 0)."""
        iterations = 0
        while True:
            status, force, delta, count = _solve_gap(self.law, bool(coupled), float(target), float(compliance))
            iterations += count
            if status != STEP_NEEDS_ROOM:
                return status, force, delta, iterations
            self.grow()

    @property
    def shape(self) -> tuple[int, int]:
        """(ny, nx) of the window, elements."""
        kernel = self._parts[0][0]
        return (kernel.shape[0] + 1) // 2, (kernel.shape[1] + 1) // 2

    @property
    def track(self) -> tuple:
        """The ``track`` given (or the placeholder)."""
        return self._parts[2]

    def contact_set(self) -> np.ndarray:
        """The current set (element indices, in the factor's order), a copy."""
        return self._state[0][: self._state[3][0]].copy()

    def factor(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(U, z) of the current set, copies, or None if the buffer does not hold its factor."""
        order, _, z, counts = self._state
        m = int(counts[0])
        if counts[1] != 1 or m == 0 or self.law[1][5][0][0]:
            return None
        return self.law[1][4][:m, :m].copy(), z[:m].copy()


# --- The active-set steps on the persistent state ---------------------------------------------------


@njit(cache=True, fastmath=True)
def _pressure_on_set(upper, order, m, gap, z, vectors, pressure, law):
    """Pressure on the set with d = 0 there (eqs. 8, 11) and the approach from ``law``; returns (delta, max
    pressure, the sum of the decreases of the pressures it changed).

    With y = U^-T h_A: sum(p) = delta z.z - z.y and p_A = U^-1 (delta z - y). ``vectors`` = (y, its state,
    scratch): y is computed here unless its state is 1 (kept from this step's last solve and updated with the
    factor: ``cholesky.append`` and ``remove``). ``law`` = (coupled, target, c A_e): coupled, delta =
    delta_known - c A_e sum(p) (``target`` = delta_known, m); else A_e sum(p) = F (eq. 9; ``target`` = F / A_e,
    Pa).
    """
    coupled, target, compliance_area = law
    kept, valid, y = vectors
    if not valid:
        for a in range(m):
            kept[a] = gap[order[a]]
        forward(upper, m, kept)
    zz = 0.0
    zy = 0.0
    for a in range(m):
        zz += z[a] * z[a]
        zy += z[a] * kept[a]
    if coupled:
        delta = (target + compliance_area * zy) / (1.0 + compliance_area * zz)
    else:
        delta = (target + zy) / zz
    for a in range(m):
        y[a] = delta * z[a] - kept[a]
    backward(upper, m, y)
    pmax = 0.0
    decrease = 0.0
    for a in range(m):
        decrease += max(pressure[order[a]] - y[a], 0.0)
        pressure[order[a]] = y[a]
        pmax = max(pmax, y[a])
    return delta, pmax, decrease


@njit(cache=True, inline="always")
def _penetrating(grid, order, m, work, active, limits):
    """Elements outside the set that penetrate (eq. 10: d >= 0, d below ``glimit``) into ``work[3]``; their
    count. d = h - delta + C p (eq. 11) is computed where h - delta < ``margin`` only (u = C p >= 0
    elsewhere). ``limits`` = (delta, margin, glimit, one_at_a_time): as in :func:`solve_step`.
    """
    pressure, gap, _, changes, _, u, _, _ = work
    delta, margin, glimit, one_at_a_time = limits
    count = 0
    for i in range(gap.size):
        if not active[i] and gap[i] - delta < margin:
            changes[count] = i
            count += 1
    count = screen(grid, order, m, pressure, gap, changes, np.int64(count), delta + glimit)
    if grid[2].shape[0] > 0:
        displacement_matrix(grid[2], order, m, pressure, changes, count, u)
    else:
        displacement_kept(grid, order, m, work, count, (delta, glimit))
    n_add = 0
    worst = 0.0
    for c in range(count):
        i = changes[c]
        d = gap[i] - delta + u[c]
        if d < glimit:  # (n_add <= c: the candidates still to read are not overwritten)
            if not one_at_a_time:
                changes[n_add] = i
                n_add += 1
            elif n_add == 0 or d < worst:
                changes[0] = i
                n_add = 1
                worst = d
    return n_add


@njit(cache=True, inline="always")
def _drop(grid, state, m, pressure, changes, n_drop, vectors):
    """Drop the elements at positions ``changes[:n_drop]`` (ascending); returns (m, factored).

    Few: downdates of the factor and z. Many (more than m / 8): compact the set, factor afresh next time. With
    the capacitance solve on: compact the set, the elements leave its small system.
    """
    order, active, z, counts, upper, cap = state
    for r in range(n_drop):
        active[order[changes[r]]] = False
        pressure[order[changes[r]]] = 0.0
    factored = True
    if capacitance_on(cap):  # capacitance: the reference's factor stays; each element leaves the small system
        for r in range(n_drop):
            factored = factored and change(grid, upper, cap, order[changes[r]], False)
    if capacitance_on(cap) or 8 * n_drop > m:
        kept = 0
        for a in range(m):
            if active[order[a]]:
                order[kept] = order[a]
                kept += 1
        return kept, capacitance_on(cap) and factored
    for r in range(n_drop - 1, -1, -1):
        remove(order, m, upper, (z, vectors[0]), vectors[1], changes[r])
        m -= 1
    return m, True


@njit(cache=True, inline="always")
def _add(grid, state, m, factored, changes, n_add, vectors):
    """Add the elements ``changes[:n_add]`` to the set; returns (m, factored).

    Few, to a factored set with room in its buffer: new rows of the factor (O(m^2) each) and new entries of
    z. Many, or no room: factor afresh next time. With the capacitance solve on: the elements join its small
    system (the reference factored afresh next time where one has no room).
    """
    order, active, z, counts, upper, cap = state
    for r in range(n_add):
        active[changes[r]] = True
    if capacitance_on(cap):  # capacitance: each element joins the set's small system
        for r in range(n_add):
            factored = factored and change(grid, upper, cap, changes[r], True)
            order[m] = changes[r]
            m += 1
        return m, factored
    if factored and 8 * n_add <= m and m + n_add <= upper.shape[0]:
        for r in range(n_add):
            if not (factored and append(grid, order, m, upper, (z, vectors[0], vectors[2]), vectors[1], changes[r])):
                factored = False  # (numerically) not positive definite: factor afresh next time
                order[m] = changes[r]
            m += 1
        return m, factored
    for r in range(n_add):
        order[m] = changes[r]
        m += 1
    return m, False


@njit(cache=True, inline="always")
def solve_step(law, coupled, target, compliance):
    """Eqs. 8-11 on the gap in ``work[1]`` from the warm state: coupled (``target`` = delta_known, m; delta =
    delta_known - c F) or load-controlled (``target`` = F, N; ``compliance`` unused).

    Returns (status, F (N), delta (m), iterations); the pressure is in ``work[0]`` (stale if F = 0).
    """
    grid, state, work, _, limits = law
    grid3 = (grid[0], grid[3], grid[4])
    order, active, z, counts, upper, cap = state
    pressure, gap, y, changes, scratch, _, kept, bounds = work
    tol, max_iter, area, cautious_after = limits
    known, listed, since = bounds  # a new gap: no bound of u kept (displacement_kept)
    for k in range(int(since[1])):
        known[listed[k]] = np.nan
    since[0] = 0.0
    since[1] = 0.0
    gap_min = _lowest(gap)
    if coupled and target <= gap_min:  # no element penetrates at delta = delta_known: F = 0 (module docstring)
        return STEP_CONVERGED, 0.0, target, 0
    on_set = (coupled, target, compliance * area) if coupled else (coupled, target / area, 0.0)
    m, factored = counts[0], counts[1] == 1  # factored: upper and z hold the set's factor and U^-T 1
    delta = target
    iterations = 0
    valid = False  # kept = U^-T h_A holds this step's gap on the set
    status = STEP_MAX_ITER
    while iterations < max_iter:
        iterations += 1
        one_at_a_time = iterations > cautious_after
        if m == 0 and not coupled:  # a load needs contact: start from the lowest point
            order[0] = np.argmin(gap)
            active[order[0]] = True
            m, factored = 1, False
            continue
        if m == 0:
            delta = target
        else:
            if not factored:
                if m > upper.shape[0]:
                    status = STEP_NEEDS_ROOM
                    break
                if not (
                    rebase(grid3, order, m, upper, cap) if capacitance_on(cap) else factorize(grid3, order, m, upper)
                ):
                    status = STEP_NOT_DEFINITE
                    break
                if not capacitance_on(cap):
                    for a in range(m):
                        z[a] = 1.0
                    forward(upper, m, z)
                factored = True
                valid = False
            if capacitance_on(cap):  # through the reference's factor (contact.capacitance); valid: x_h of this gap
                if not valid:
                    prepare_gap(gap, upper, cap)
                delta, pmax, decrease = pressure_on_set(cap, gap, active, pressure, on_set)
            else:
                delta, pmax, decrease = _pressure_on_set(upper, order, m, gap, z, (kept, valid, y), pressure, on_set)
            since[0] += decrease
            valid = True
            n_drop = _tension_elements(pressure, order, m, pmax, tol, one_at_a_time, changes)
            if n_drop > 0:
                for r in range(n_drop):
                    since[0] += max(pressure[order[changes[r]]], 0.0)
                m, factored = _drop(grid, state, m, pressure, changes, n_drop, (kept, scratch))
                valid = valid and factored
                continue
        scale = max(delta - gap_min, 1e-30)
        n_add = _penetrating(grid, order, m, work, active, (delta, 1e-6 * scale, -tol * scale, one_at_a_time))
        if n_add == 0:
            status = STEP_CONVERGED
            break
        for r in range(n_add):  # in the set now: a kept bound no longer holds (computed again if it leaves)
            if known[changes[r]] == known[changes[r]]:
                known[changes[r]] = -np.inf
        m, factored = _add(grid, state, m, factored, changes, n_add, (kept, scratch, gap))
        valid = valid and factored
    counts[0], counts[1] = m, 1 if factored else 0
    return status, _sum(pressure) * area, delta, iterations


def _define_solve_gap(stamp):
    @njit(cache=True)
    def solve_gap(law, coupled, target, compliance):
        """:func:`solve_step` called from Python (:class:`ActiveSetSolver`'s one-off solves)."""
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called (wheelrail.core.engine.compiled)
        return solve_step(law, coupled, target, compliance)

    return solve_gap


_solve_gap = _define_solve_gap(sources_stamp(capacitance, cholesky, deformed_gap))


def cold_start_set(
    flat: np.ndarray, area: float, modulus: float, coupled: bool, target: float, compliance: float
) -> np.ndarray:
    """First guess of the contact set: the rigid overlap at half the approach, as for Hertz.

    For quadratic surfaces Hertz gives a contact area half the rigid overlap area at the same approach
    (the overlap at depth delta/2) and F = (4/3) E* a delta. Taking A_g(t) = overlap area at depth t
    below the lowest point, a_c = sqrt(A_g(t) / pi) and delta = 2 t, the guess solves F(t) = load
    (or 2 t + c F(t) = delta_known - min h in the coupled form). Any set works; a good one saves
    factorisations.
    """
    order = np.sort(flat - flat.min())
    count = np.arange(1, order.size + 1)
    # test depth t = order[k]: overlap count k+1 (approximately), estimated force and approach
    force = (4.0 / 3.0) * modulus * np.sqrt(count * area / np.pi) * 2.0 * order
    if coupled:
        lhs = 2.0 * order + compliance * force
        available = target - flat.min()
        if available <= 0.0:
            return np.zeros(flat.size, dtype=bool)
        k = int(np.searchsorted(lhs, available))
    else:
        k = int(np.searchsorted(force, target))
    k = min(max(k, 0), order.size - 1)
    return (flat - flat.min()) <= order[k]


def displacement(grid: tuple, pressure: np.ndarray) -> np.ndarray:
    """u = C p (eq. 8) on the whole flattened window for the flattened pressure (Pa), m.

    Parameters
    ----------
    grid : tuple
        The window's influence grid (:func:`influence_grid`).
    pressure : ndarray, shape (ny nx,)
        Element pressures, Pa.

    Returns
    -------
    ndarray, shape (ny nx,)
        Combined normal displacement u at the element centres, m.
    """
    pressure = np.ascontiguousarray(pressure, dtype=np.float64)
    order = np.flatnonzero(pressure)
    n = pressure.size
    u = np.empty(n)
    everywhere = np.arange(n, dtype=np.int64)
    if grid[2].shape[0] > 0:
        displacement_matrix(grid[2], order, order.size, pressure, everywhere, n, u)
    else:
        displacement_kernel(grid, order, order.size, pressure, everywhere, n, u)
    return u
