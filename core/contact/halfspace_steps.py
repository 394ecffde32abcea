"""The ``3d`` law stepped in compiled code: one contact solve per time step, its warm state kept in arrays.

The interaction loop's compiled chunk of steps (``wheelrail.core.interaction._run_chunk_3d``) calls
:func:`_halfspace_step` once per step: the gap of the window under the wheel (eq. 11's h = x^2 / (2 R_x) +
y^2 / (2 R_y) - r) and the solve of eqs. 8-11 coupled with delta = delta_known - c F, without a Python call.

The method, its decisions and its tolerance are those of ``halfspace_solver._active_set_solve`` (the one-off
solves; the per-step model it replaced, ``HalfSpaceReferenceModel``): an active set warm-started from the
last loaded step's set and Cholesky factor, drops of elements in tension before additions of penetrating ones,
all at once (one at a time after ``_CAUTIOUS_AFTER`` iterations), downdates and new rows of the factor for
few changes (a fresh factor for more than m / 8). What makes a step cheaper (``benchmarks/step_split_3d.py``
itemises a step):

* the warm state (set, factor, mask, pressures) stays in place from step to step: nothing is allocated,
  copied or checked per step, and the factor is not touched when the set does not change (most steps);
* with the factor C_AA = U^T U the vector z = U^-T 1 is kept with it: a new element adds one entry, a
  dropped one applies the downdate's rotations to it (the same rotations as to the rows of U). Then with
  y = U^-T h_A the coupled law needs 1^T C_AA^-1 1 = z.z, 1^T C_AA^-1 h_A = z.y and p_A = U^-1 (delta z - y):
  one forward and one backward substitution per iteration instead of two of each (an exact reformulation
  of p = delta C^-1 1 - C^-1 h: it changes round-off only, ~1e-15 relative);
* the window's influence matrix C (n x n, from the kernel of eq. 8) is built once per run, up to
  ``FULL_MATRIX_ELEMENTS`` elements (1.8 MB for the paper's 19 x 25 window): the deformed gap
  d = h - delta + C p, needed only where it can be negative outside the set (inside, d = 0 by
  construction), is then one contiguous dot product per element, C's row against the pressure over the span
  of flat indices the set covers, four rows at a time. A larger window reads the kernel instead, row by row
  of the set's bounding box (measured 4.1 instead of 2.9 us per iteration at 1 mm);
* every inner loop runs over views that start at index 0, which numba vectorises;
* loss of contact is recognised before the solve: the coupled law has F = 0 exactly when no element
  penetrates at delta = delta_known, i.e. delta_known <= min h; then nothing is solved and the warm state
  stays that of the last loaded step, as the per-step model kept it.

The factor's buffer starts at twice the first set plus 64 rows; a set that outgrows it stops the step before
its factor is rebuilt (``STEP_NEEDS_ROOM``: nothing committed, the set consistent), the caller gives a larger
buffer (:meth:`HalfSpaceSteps.grow`) and repeats the step from that set.

:func:`_solve_step` and :func:`_halfspace_step` are inlined into their callers: the compiled entry points
(``interaction._run_chunk_3d`` and :data:`_python_step` here) are keyed in numba's cache by the sources of the
modules they reach (``wheelrail.core.compiled``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from wheelrail.core.compiled import sources_stamp
from wheelrail.core.contact import halfspace_solver
from wheelrail.core.contact.halfspace_solver import (
    _CAUTIOUS_AFTER,
    _STATUS_CONVERGED,
    _STATUS_MAX_ITER,
    _STATUS_NOT_DEFINITE,
    _coordinates,
    _factor_full,
    _tension_elements,
)

__all__ = [
    "FULL_MATRIX_ELEMENTS",
    "STEP_AT_EDGE",
    "STEP_CONVERGED",
    "STEP_MAX_ITER",
    "STEP_NEEDS_ROOM",
    "STEP_NOT_DEFINITE",
    "HalfSpaceSteps",
]

STEP_CONVERGED = _STATUS_CONVERGED
STEP_MAX_ITER = _STATUS_MAX_ITER
STEP_NOT_DEFINITE = _STATUS_NOT_DEFINITE
STEP_AT_EDGE = 3  # converged, but the set touches the window's border
STEP_NEEDS_ROOM = 4  # the set outgrew the factor's buffer: grow it and repeat the step
FULL_MATRIX_ELEMENTS = 2601  # largest window (elements) whose influence matrix is built (51 x 51: 54 MB)


class HalfSpaceSteps:
    """The arrays of the compiled ``3d`` law: window, roughness along the track and the warm state.

    Parameters
    ----------
    kernel : ndarray (2 ny - 1, 2 nx - 1)
        Influence kernel of eq. (8), m/Pa (``halfspace_kernel``).
    base_gap : ndarray (ny, nx)
        The window's gap on smooth surfaces, m.
    track : (lines, start_index, ramp, half_x, centre_row)
        Roughness rows along the track (m), the sample under the wheel centre per step, the run-in's fade-in
        factor per step, the window's half side along the rail (elements) and the chosen line's row
        (``models.ModelInputs``).
    start : ndarray of int
        The first step's contact set (element indices of the flattened window), factored afresh.
    limits : (float, int, float)
        Relative tolerance of eq. (10), maximum active-set iterations per step, element area (m^2).
    full_matrix : bool, optional
        Build the window's influence matrix (default: for windows up to ``FULL_MATRIX_ELEMENTS``).
    capacity : int, optional
        Rows of the factor's first buffer (default: twice the start set plus 64, at most the window).

    ``law`` is the tuple the compiled functions take: (grid, state, work, track, limits) with grid = (kernel,
    kernel reversed, influence matrix C or 0 x 0, row and column of each element) and state = (set in factor
    order, its mask, z = U^-T 1, [m, factored], factor buffer); ``pressure`` is the current pressure on the
    flattened window (Pa; stale after a step without contact, whose pressure is zero).
    """

    def __init__(self, kernel, base_gap, track, start, limits, *, full_matrix=None, capacity=None) -> None:
        ny, nx = base_gap.shape
        n = ny * nx
        kernel = np.array(kernel, dtype=np.float64)  # writable: one numba specialisation
        rows, columns = _coordinates(ny, nx)
        full = np.empty((0, 0))
        if full_matrix or (full_matrix is None and n <= FULL_MATRIX_ELEMENTS):
            # C[i, j] = kernel[row_i - row_j + ny - 1, column_i - column_j + nx - 1] (eq. 8)
            full = np.ascontiguousarray(
                kernel[rows[:, None] - rows[None, :] + ny - 1, columns[:, None] - columns[None, :] + nx - 1]
            )
        grid = (kernel, np.ascontiguousarray(kernel[::-1, ::-1]), full, rows, columns)
        order = np.zeros(n, dtype=np.int64)
        active = np.zeros(n, dtype=np.bool_)
        start = np.asarray(start, dtype=np.int64)
        order[: start.size] = start
        active[start] = True
        counts = np.array([start.size, 0], dtype=np.int64)  # m, whether the buffer and z hold the set's factor
        self._state = (order, active, np.zeros(n), counts)
        self.pressure = np.zeros(n)
        work = (self.pressure, np.empty(n), np.empty(n), np.empty(n, dtype=np.int64), np.empty(n), np.empty(n))
        lines, start_index, ramp, half_x, centre_row = track
        track = (
            np.ascontiguousarray(base_gap, dtype=np.float64).ravel(),
            np.ascontiguousarray(lines, dtype=np.float64),
            np.ascontiguousarray(start_index, dtype=np.int64),
            np.ascontiguousarray(ramp, dtype=np.float64),
            int(half_x),
            int(centre_row),
        )
        tolerance, max_iterations, area = limits
        self._parts = (grid, work, track, (float(tolerance), int(max_iterations), float(area)))
        self.shape = (ny, nx)
        self.grow(min(n, 2 * start.size + 64) if capacity is None else int(capacity))

    def grow(self, capacity: int | None = None) -> None:
        """A new factor buffer of ``capacity`` rows (default: half as many again as the set, at most the
        window's elements); the set is factored afresh in it."""
        order, active, z, counts = self._state
        m = int(counts[0])
        capacity = min(order.size, m + m // 2 + 8) if capacity is None else int(capacity)
        counts[1] = 0
        grid, work, track, limits = self._parts
        self.law = (grid, (order, active, z, counts, np.empty((capacity, capacity))), work, track, limits)

    @property
    def contact_count(self) -> int:
        """Elements in the current warm set."""
        return int(self._state[3][0])

    @property
    def capacity(self) -> int:
        """Rows of the factor's buffer."""
        return int(self.law[1][4].shape[0])


# ---------------------------------------------------------------------------------------------------
# Triangular solves and the factor's updates, z = U^-T 1 kept with the factor
# ---------------------------------------------------------------------------------------------------


# (The inner loops run over views that start at index 0: numba then needs no negative-index wraparound
# and LLVM vectorises them, 2-3x faster than indexing the whole arrays from k + 1; four rows at a time share
# the loads of the vector they meet, another 1.2-2x. Measured at 97-99 contact elements: forward 3.1 ->
# 1.1 us, backward 4.5 -> 1.3 us.)


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
    rotations, as ``halfspace_solver._factor_remove``; the same rotations applied to (z3, z_position) give the
    new trailing part of z (module docstring).
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


# ---------------------------------------------------------------------------------------------------
# The active-set steps on the persistent state
# ---------------------------------------------------------------------------------------------------


@njit(cache=True, fastmath=True)
def _pressure_on_set(upper, order, m, gap, z, y, pressure, approach_known, compliance_area):
    """Pressure on the set with d = 0 there and delta = delta_known - c A_e sum(p) (eqs. 8, 9, 11); returns
    (delta, max pressure). With y = U^-T h_A: sum(p) = delta z.z - z.y, p_A = U^-1 (delta z - y)."""
    for a in range(m):
        y[a] = gap[order[a]]
    _forward(upper, m, y)
    zz = 0.0
    zy = 0.0
    for a in range(m):
        zz += z[a] * z[a]
        zy += z[a] * y[a]
    delta = (approach_known + compliance_area * zy) / (1.0 + compliance_area * zz)
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
    elsewhere). ``limits`` = (delta, margin, glimit, one_at_a_time): as in ``halfspace_solver``.
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
def _solve_step(law, approach_known, compliance):
    """Eqs. 8-11 coupled with delta = delta_known - c F on the gap in ``work[1]``, from the warm state.

    Returns (status, F (N), delta (m), iterations); the pressure is in ``work[0]`` (stale if F = 0).
    """
    grid, state, work, _, limits = law
    grid3 = (grid[0], grid[3], grid[4])
    order, active, z, counts, upper = state
    pressure, gap, y, changes, scratch, _ = work
    tol, max_iter, area = limits
    gap_min = gap.min()
    if approach_known <= gap_min:  # no element penetrates at delta = delta_known: F = 0 (module docstring)
        return STEP_CONVERGED, 0.0, approach_known, 0
    m, factored = counts[0], counts[1] == 1  # factored: upper and z hold the set's factor and U^-T 1
    delta = approach_known
    iterations = 0
    status = STEP_MAX_ITER
    while iterations < max_iter:
        iterations += 1
        one_at_a_time = iterations > _CAUTIOUS_AFTER
        if m == 0:
            delta = approach_known
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
            delta, pmax = _pressure_on_set(upper, order, m, gap, z, y, pressure, approach_known, compliance * area)
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


@njit(cache=True, inline="always")
def _halfspace_step(s, approach_known, compliance, law):
    """Step s of the ``3d`` law: the window's gap under the wheel, then :func:`_solve_step`.

    Returns (status, F (N), elements in contact on the centre row, elements in contact); ``STEP_AT_EDGE`` when
    the converged set touches the window's border, ``STEP_NEEDS_ROOM`` when the step must be repeated with a
    larger factor buffer.
    """
    grid, state, work, track, _ = law
    base, lines, start_index, ramp, half_x, centre_row = track
    gap = work[1]
    nx = 2 * half_x + 1
    ny = base.size // nx
    first = start_index[s] - half_x
    fade = ramp[s]
    for row in range(ny):
        for column in range(nx):
            gap[row * nx + column] = base[row * nx + column] - fade * lines[row, first + column]
    status, force, _, _ = _solve_step(law, approach_known, compliance)
    if force == 0.0 or status != STEP_CONVERGED:
        return status, force, 0, 0
    rows, columns = grid[3], grid[4]
    order, m = state[0], state[3][0]
    on_centre = 0
    for a in range(m):
        i = order[a]
        if rows[i] == 0 or rows[i] == ny - 1 or columns[i] == 0 or columns[i] == nx - 1:
            status = STEP_AT_EDGE
        if rows[i] == centre_row:
            on_centre += 1
    return status, force, on_centre, m


def _define_python_step(stamp):
    @njit(cache=True)
    def python_step(s, approach_known, compliance, law):
        """:func:`_halfspace_step` called from Python (``HalfSpaceModel.solve``)."""
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called (wheelrail.core.compiled)
        return _halfspace_step(s, approach_known, compliance, law)

    return python_step


_python_step = _define_python_step(sources_stamp(halfspace_solver))
