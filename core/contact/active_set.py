"""The active-set solver of the 3D half-space contact (paper section 2.3.2, eqs. 8-11), compiled by numba.

An exact active-set method (Kalker's scheme with the load, or the coupling delta = delta_known - c F, as an
extra equation). Each iteration solves on the contact set A, ``C_AA p_A = delta - h_A`` with one Cholesky
factor C_AA = U^T U (:func:`_pressure_on_set`); drops the elements in tension (eq. 10: p >= 0); if none,
adds the elements that penetrate (eq. 10: d >= 0) until neither happens. The factor is updated, not
recomputed, when few elements change (a new row per added element, rotations per dropped one), and
z = U^-T 1 is kept with it, so a warm-started solve costs one forward and one backward substitution per
iteration. :class:`ActiveSetSolver` holds the warm state (set, factor, z, pressure) in arrays that the
``3d`` model's compiled loop steps in place (``halfspace_model``) and that one-off solves
(``window.HalfSpaceWindow``) fill from a start. Design and measurements: ``docs/benchmarks.md``, "The 3D
contact solver".

Conventions of the compiled functions (no input checks: ``window`` does them): the window of ny x nx
elements is flattened row by row (element i is row i // nx, column i % nx); the contact set is ``order[:m]``
in the order of the rows of the upper factor ``upper[:m, :m]``, ``active`` its mask.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "FULL_MATRIX_ELEMENTS",
    "STEP_AT_EDGE",
    "STEP_CONVERGED",
    "STEP_MAX_ITER",
    "STEP_NEEDS_ROOM",
    "STEP_NOT_DEFINITE",
    "ActiveSetSolver",
    "displacement",
    "influence_grid",
]

STEP_CONVERGED = 0
STEP_MAX_ITER = 1  # no convergence within the iterations allowed
STEP_NOT_DEFINITE = 2  # the set's influence matrix lost positive definiteness in round-off
STEP_AT_EDGE = 3  # converged, but the set touches the window's border
STEP_NEEDS_ROOM = 4  # the set outgrew the factor's buffer: grow it and repeat the step
CAUTIOUS_AFTER = 30  # iterations; then one element at a time is dropped or added (against add/drop cycling)
FULL_MATRIX_ELEMENTS = 2601  # largest window (elements) whose influence matrix is built (51 x 51: 54 MB)


@njit(cache=True)
def _coordinates(ny, nx):
    """Row and column of every element of the flattened window."""
    rows = np.empty(ny * nx, dtype=np.int64)
    columns = np.empty(ny * nx, dtype=np.int64)
    for i in range(ny * nx):
        rows[i] = i // nx
        columns[i] = i - rows[i] * nx
    return rows, columns


@njit(cache=True, fastmath=True)
def _factor_full(grid, order, m, upper):
    """Upper Cholesky factor U (C_AA = U^T U) of the contact set ``order[:m]`` into ``upper[:m, :m]``.

    ``grid`` = (kernel, rows, columns). Computed as the lower factor L = U^T with row-wise dot products, then
    transposed. Returns False if C_AA is not positive definite.
    """
    kernel, rows, columns = grid
    ny = (kernel.shape[0] + 1) // 2
    nx = (kernel.shape[1] + 1) // 2
    lower = np.empty((m, m))
    for a in range(m):
        row = rows[order[a]] + ny - 1
        column = columns[order[a]] + nx - 1
        for b in range(a + 1):
            lower[a, b] = kernel[row - rows[order[b]], column - columns[order[b]]]
    for j in range(m):
        pivot = lower[j, j]
        for k in range(j):
            pivot -= lower[j, k] * lower[j, k]
        if pivot <= 0.0:
            return False
        d = math.sqrt(pivot)
        lower[j, j] = d
        for i in range(j + 1, m):
            t = lower[i, j]
            for k in range(j):
                t -= lower[i, k] * lower[j, k]
            lower[i, j] = t / d
    for a in range(m):
        for b in range(a + 1):
            upper[b, a] = lower[a, b]
    return True


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


def influence_grid(kernel: np.ndarray, full_matrix: bool | None = None) -> tuple:
    """The solver's view of a window's influence coefficients: (kernel, kernel reversed, influence matrix C or
    0 x 0, row and column of each element).

    ``C[i, j] = kernel[row_i - row_j + ny - 1, column_i - column_j + nx - 1]`` (eq. 8) is built for windows up
    to ``FULL_MATRIX_ELEMENTS`` elements (default) or as ``full_matrix`` says: the deformed gap outside the
    set is then one contiguous dot product per element.
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

    Notes
    -----
    ``law`` is the tuple the compiled functions take: (grid, state, work, track, limits) with state = (set
    in factor order, its mask, z = U^-T 1, [m, factored], factor buffer) and work = (pressure, gap, three
    scratch vectors); ``pressure`` is the current pressure on the flattened window (Pa; stale after a
    coupled solve without contact, whose pressure is zero) and ``gap`` the gap a solve reads (m).
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
        work = (self.pressure, self.gap, np.empty(n), np.empty(n, dtype=np.int64), np.empty(n), np.empty(n))
        if track is None:  # the one-off solves' placeholder (of the types of the model's)
            track = (np.zeros(1), np.zeros((1, 1)), np.zeros(1, dtype=np.int64), np.zeros(1), 0, 0)
        tolerance, max_iterations, area, *cautious = limits
        limits = (float(tolerance), int(max_iterations), float(area), int(cautious[0] if cautious else CAUTIOUS_AFTER))
        self._parts = (grid, work, track, limits)
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
        self.law = (grid, (order, active, z, counts, np.empty((capacity, capacity))), work, track, limits)

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
        if counts[1] != 1 or m == 0:
            return None
        return self.law[1][4][:m, :m].copy(), z[:m].copy()


# --- Triangular solves and the factor's updates, z = U^-T 1 kept with the factor ---------------------


@njit(cache=True, fastmath=True)
def _forward(upper, m, rhs):
    """Solve U^T y = rhs in place: rows of U contiguous, axpys on the unsolved tail, four rows at a time."""
    k = 0
    while k + 4 <= m:
        y0 = rhs[k] / upper[k, k]
        y1 = (rhs[k + 1] - upper[k, k + 1] * y0) / upper[k + 1, k + 1]
        y2 = (rhs[k + 2] - upper[k, k + 2] * y0 - upper[k + 1, k + 2] * y1) / upper[k + 2, k + 2]
        y3 = (rhs[k + 3] - upper[k, k + 3] * y0 - upper[k + 1, k + 3] * y1 - upper[k + 2, k + 3] * y2) / upper[
            k + 3, k + 3
        ]
        rhs[k], rhs[k + 1], rhs[k + 2], rhs[k + 3] = y0, y1, y2, y3
        r0, r1, r2, r3 = upper[k, k + 4 : m], upper[k + 1, k + 4 : m], upper[k + 2, k + 4 : m], upper[k + 3, k + 4 : m]
        tail = rhs[k + 4 : m]
        for j in range(tail.size):
            tail[j] -= r0[j] * y0 + r1[j] * y1 + r2[j] * y2 + r3[j] * y3
        k += 4
    for i in range(k, m):
        y = rhs[i] / upper[i, i]
        rhs[i] = y
        row = upper[i, i + 1 : m]
        tail = rhs[i + 1 : m]
        for j in range(tail.size):
            tail[j] -= row[j] * y


@njit(cache=True, fastmath=True)
def _backward(upper, m, rhs):
    """Solve U x = rhs in place: dot products of rows of U with the solved tail, four rows at a time."""
    k = m
    while k >= 4:
        r0, r1, r2, r3 = upper[k - 4, k:m], upper[k - 3, k:m], upper[k - 2, k:m], upper[k - 1, k:m]
        tail = rhs[k:m]
        s0 = s1 = s2 = s3 = 0.0
        for j in range(tail.size):
            x = tail[j]
            s0 += r0[j] * x
            s1 += r1[j] * x
            s2 += r2[j] * x
            s3 += r3[j] * x
        x3 = (rhs[k - 1] - s3) / upper[k - 1, k - 1]
        x2 = (rhs[k - 2] - s2 - upper[k - 2, k - 1] * x3) / upper[k - 2, k - 2]
        x1 = (rhs[k - 3] - s1 - upper[k - 3, k - 2] * x2 - upper[k - 3, k - 1] * x3) / upper[k - 3, k - 3]
        x0 = (rhs[k - 4] - s0 - upper[k - 4, k - 3] * x1 - upper[k - 4, k - 2] * x2 - upper[k - 4, k - 1] * x3) / upper[
            k - 4, k - 4
        ]
        rhs[k - 4], rhs[k - 3], rhs[k - 2], rhs[k - 1] = x0, x1, x2, x3
        k -= 4
    for i in range(k - 1, -1, -1):
        row = upper[i, i + 1 : m]
        tail = rhs[i + 1 : m]
        s = 0.0
        for j in range(tail.size):
            s += row[j] * tail[j]
        rhs[i] = (rhs[i] - s) / upper[i, i]


@njit(cache=True, fastmath=True)
def _append(grid, order, m, upper, z, column, element):
    """Add ``element`` as row/column m of the factor and entry m of z = U^-T 1, O(m^2): U^T w = C_Ae,
    U[m, m] = sqrt(C_ee - w.w), z_m = (1 - w.z) / U[m, m]. Returns False if not positive definite."""
    kernel, _, full, rows, columns = grid
    ny = (kernel.shape[0] + 1) // 2
    nx = (kernel.shape[1] + 1) // 2
    if full.shape[0] > 0:
        row = full[element]
        for a in range(m):
            column[a] = row[order[a]]
    else:
        for a in range(m):
            column[a] = kernel[rows[element] - rows[order[a]] + ny - 1, columns[element] - columns[order[a]] + nx - 1]
    _forward(upper, m, column)
    square = kernel[ny - 1, nx - 1]
    s = 1.0
    for k in range(m):
        upper[k, m] = column[k]
        square -= column[k] * column[k]
        s -= column[k] * z[k]
    if square <= 0.0:
        return False
    upper[m, m] = math.sqrt(square)
    z[m] = s / upper[m, m]
    order[m] = element
    return True


@njit(cache=True, fastmath=True)
def _remove(order, m, upper, z, scratch, position):
    """Remove the element at ``position`` from the factor of size m and from z = U^-T 1, O(m^2).

    The factor's trailing block gets the rank-1 update U33^T U33 + u u^T (u = U[position, position+1:]) by
    rotations (Golub and Van Loan, *Matrix Computations*, 4th ed., section 6.5.4); the same rotations applied
    to (z3, z_position) give the new trailing part of z.
    """
    p = position
    x = scratch
    for j in range(p + 1, m):
        x[j] = upper[p, j]
    t = z[p]
    for i in range(p + 1, m):
        diagonal = upper[i, i]
        xi = x[i]
        r = math.sqrt(diagonal * diagonal + xi * xi)
        c = r / diagonal
        s = xi / diagonal
        upper[i, i] = r
        row = upper[i, i + 1 : m]
        rest = x[i + 1 : m]
        for j in range(row.size):
            updated = (row[j] + s * rest[j]) / c
            row[j] = updated
            rest[j] = c * rest[j] - s * updated
        zi = (z[i] + s * t) / c
        z[i] = zi
        t = c * t - s * zi
    for i in range(p):
        row = upper[i, p:m]
        for j in range(row.size - 1):
            row[j] = row[j + 1]
    for i in range(p, m - 1):
        target = upper[i, i : m - 1]
        source = upper[i + 1, i + 1 : m]
        for j in range(target.size):
            target[j] = source[j]
        z[i] = z[i + 1]
        order[i] = order[i + 1]


# --- The active-set steps on the persistent state ---------------------------------------------------


@njit(cache=True, fastmath=True)
def _pressure_on_set(upper, order, m, gap, z, y, pressure, law):
    """Pressure on the set with d = 0 there (eqs. 8, 11) and the approach from ``law``; returns (delta, max
    pressure).

    With y = U^-T h_A: sum(p) = delta z.z - z.y and p_A = U^-1 (delta z - y). ``law`` = (coupled, target,
    c A_e): coupled, delta = delta_known - c A_e sum(p) (``target`` = delta_known, m); else A_e sum(p) = F
    (eq. 9; ``target`` = F / A_e, Pa).
    """
    coupled, target, compliance_area = law
    for a in range(m):
        y[a] = gap[order[a]]
    _forward(upper, m, y)
    zz = 0.0
    zy = 0.0
    for a in range(m):
        zz += z[a] * z[a]
        zy += z[a] * y[a]
    if coupled:
        delta = (target + compliance_area * zy) / (1.0 + compliance_area * zz)
    else:
        delta = (target + zy) / zz
    for a in range(m):
        y[a] = delta * z[a] - y[a]
    _backward(upper, m, y)
    pmax = 0.0
    for a in range(m):
        pressure[order[a]] = y[a]
        pmax = max(pmax, y[a])
    return delta, pmax


@njit(cache=True, fastmath=True)
def _displacement_matrix(full, order, m, pressure, candidates, count, u):
    """u = C p at ``candidates[:count]`` from C's rows over the span of flat indices the set covers (zero
    between its elements), four rows at a time."""
    lo, hi = pressure.size, 0
    for a in range(m):
        lo = min(lo, order[a])
        hi = max(hi, order[a] + 1)
    span = pressure[lo : max(lo, hi)]
    size = span.size
    for c in range(0, count, 4):
        i0, i1 = candidates[c], candidates[min(c + 1, count - 1)]
        i2, i3 = candidates[min(c + 2, count - 1)], candidates[min(c + 3, count - 1)]
        r0, r1, r2, r3 = (
            full[i0, lo : lo + size],
            full[i1, lo : lo + size],
            full[i2, lo : lo + size],
            full[i3, lo : lo + size],
        )
        u0 = u1 = u2 = u3 = 0.0
        for k in range(size):
            x = span[k]
            u0 += r0[k] * x
            u1 += r1[k] * x
            u2 += r2[k] * x
            u3 += r3[k] * x
        u[c] = u0
        for b, value in ((1, u1), (2, u2), (3, u3)):
            if c + b < count:
                u[c + b] = value


@njit(cache=True, fastmath=True)
def _displacement_kernel(grid, order, m, pressure, candidates, count, u):
    """u = C p at ``candidates[:count]`` from the reversed kernel, row by row of the set's bounding box."""
    kernel, flipped, _, rows, columns = grid
    ny = (kernel.shape[0] + 1) // 2
    nx = (kernel.shape[1] + 1) // 2
    r0, r1, c0, c1 = ny, -1, nx, -1
    for a in range(m):
        r0 = min(r0, rows[order[a]])
        r1 = max(r1, rows[order[a]])
        c0 = min(c0, columns[order[a]])
        c1 = max(c1, columns[order[a]])
    width = max(0, c1 + 1 - c0)
    for c in range(count):
        i = candidates[c]
        offset = c0 - columns[i] + nx - 1
        total = 0.0
        for rj in range(r0, r1 + 1):
            # K[row_i - rj, column_i - cj] = reversed[rj - row_i + ny - 1, cj - column_i + nx - 1]
            k = flipped[rj - rows[i] + ny - 1, offset : offset + width]
            p = pressure[rj * nx + c0 : rj * nx + c0 + width]
            for t in range(width):
                total += k[t] * p[t]
        u[c] = total


@njit(cache=True, inline="always")
def _penetrating(grid, order, m, work, active, limits):
    """Elements outside the set that penetrate (eq. 10: d >= 0, d below ``glimit``) into ``work[3]``; their
    count. d = h - delta + C p (eq. 11) is computed where h - delta < ``margin`` only (u = C p >= 0
    elsewhere). ``limits`` = (delta, margin, glimit, one_at_a_time): as in :func:`_solve_step`.
    """
    pressure, gap, _, changes, _, u = work
    delta, margin, glimit, one_at_a_time = limits
    count = 0
    for i in range(gap.size):
        if not active[i] and gap[i] - delta < margin:
            changes[count] = i
            count += 1
    if grid[2].shape[0] > 0:
        _displacement_matrix(grid[2], order, m, pressure, changes, count, u)
    else:
        _displacement_kernel(grid, order, m, pressure, changes, count, u)
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
def _drop(state, m, pressure, changes, n_drop, scratch):
    """Drop the elements at positions ``changes[:n_drop]`` (ascending); returns (m, factored).

    Few: downdates of the factor and z. Many (more than m / 8): compact the set, factor afresh next time.
    """
    order, active, z, counts, upper = state
    for r in range(n_drop):
        active[order[changes[r]]] = False
        pressure[order[changes[r]]] = 0.0
    if 8 * n_drop > m:
        kept = 0
        for a in range(m):
            if active[order[a]]:
                order[kept] = order[a]
                kept += 1
        return kept, False
    for r in range(n_drop - 1, -1, -1):
        _remove(order, m, upper, z, scratch, changes[r])
        m -= 1
    return m, True


@njit(cache=True, inline="always")
def _add(grid, state, m, factored, changes, n_add, scratch):
    """Add the elements ``changes[:n_add]`` to the set; returns (m, factored).

    Few, to a factored set with room in its buffer: new rows of the factor (O(m^2) each) and new entries of
    z. Many, or no room: factor afresh next time.
    """
    order, active, z, counts, upper = state
    for r in range(n_add):
        active[changes[r]] = True
    if factored and 8 * n_add <= m and m + n_add <= upper.shape[0]:
        for r in range(n_add):
            if not (factored and _append(grid, order, m, upper, z, scratch, changes[r])):
                factored = False  # (numerically) not positive definite: factor afresh next time
                order[m] = changes[r]
            m += 1
        return m, factored
    for r in range(n_add):
        order[m] = changes[r]
        m += 1
    return m, False


@njit(cache=True, inline="always")
def _solve_step(law, coupled, target, compliance):
    """Eqs. 8-11 on the gap in ``work[1]`` from the warm state: coupled (``target`` = delta_known, m; delta =
    delta_known - c F) or load-controlled (``target`` = F, N; ``compliance`` unused).

    Returns (status, F (N), delta (m), iterations); the pressure is in ``work[0]`` (stale if F = 0).
    """
    grid, state, work, _, limits = law
    grid3 = (grid[0], grid[3], grid[4])
    order, active, z, counts, upper = state
    pressure, gap, y, changes, scratch, _ = work
    tol, max_iter, area, cautious_after = limits
    gap_min = gap.min()
    if coupled and target <= gap_min:  # no element penetrates at delta = delta_known: F = 0 (module docstring)
        return STEP_CONVERGED, 0.0, target, 0
    on_set = (coupled, target, compliance * area) if coupled else (coupled, target / area, 0.0)
    m, factored = counts[0], counts[1] == 1  # factored: upper and z hold the set's factor and U^-T 1
    delta = target
    iterations = 0
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
                if not _factor_full(grid3, order, m, upper):
                    status = STEP_NOT_DEFINITE
                    break
                for a in range(m):
                    z[a] = 1.0
                _forward(upper, m, z)
                factored = True
            delta, pmax = _pressure_on_set(upper, order, m, gap, z, y, pressure, on_set)
            n_drop = _tension_elements(pressure, order, m, pmax, tol, one_at_a_time, changes)
            if n_drop > 0:
                m, factored = _drop(state, m, pressure, changes, n_drop, scratch)
                continue
        scale = max(delta - gap_min, 1e-30)
        n_add = _penetrating(grid, order, m, work, active, (delta, 1e-6 * scale, -tol * scale, one_at_a_time))
        if n_add == 0:
            status = STEP_CONVERGED
            break
        m, factored = _add(grid, state, m, factored, changes, n_add, scratch)
    counts[0], counts[1] = m, 1 if factored else 0
    total = 0.0
    for i in range(pressure.size):
        total += pressure[i]
    return status, total * area, delta, iterations


@njit(cache=True)
def _solve_gap(law, coupled, target, compliance):
    """:func:`_solve_step` called from Python (:class:`ActiveSetSolver`'s one-off solves)."""
    return _solve_step(law, coupled, target, compliance)


def displacement(grid: tuple, pressure: np.ndarray) -> np.ndarray:
    """u = C p (eq. 8) on the whole flattened window for the flattened pressure (Pa), m."""
    pressure = np.ascontiguousarray(pressure, dtype=np.float64)
    order = np.flatnonzero(pressure)
    n = pressure.size
    u = np.empty(n)
    everywhere = np.arange(n, dtype=np.int64)
    if grid[2].shape[0] > 0:
        _displacement_matrix(grid[2], order, order.size, pressure, everywhere, n, u)
    else:
        _displacement_kernel(grid, order, order.size, pressure, everywhere, n, u)
    return u
