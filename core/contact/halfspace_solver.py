"""Active-set solver of the 3D half-space contact model (paper section 2.3.2, eqs. 8-11), compiled by numba.

An exact active-set method (Kalker's scheme with the load as an extra equation). Each iteration

1. solves on the contact set A (:func:`_solve_on_set`): ``C_AA p_A = delta - h_A`` (eqs. 8, 11 with d = 0)
   together with the load equation F = A_e sum(p) (eq. 9) or, coupled to the wheel and rail,
   ``delta = delta_known - c F``, using one Cholesky factor of ``C_AA``;
2. drops the elements in tension (:func:`_tension_elements`, :func:`_drop_elements`; eq. 10: p >= 0);
3. if none, adds the elements that penetrate (:func:`_penetrating_elements`, :func:`_add_elements`;
   eq. 10: d >= 0), until neither happens.

After ``cautious_after`` iterations only one element at a time, the worst, is dropped or added (against
add/drop cycling). The factor is updated rather than recomputed when few elements change (O(m^2) per
element: a new row for an added element, a rank-1 update for a dropped one), so a warm start from the
previous time step typically costs one or two triangular solves and one or two passes of u = C p. The
Cholesky loops are hand-written (measured faster than numba's LAPACK call at these sizes).

Conventions of the compiled functions (no input checks: :mod:`wheelrail.core.contact.halfspace` does them):
the window of ny x nx elements is flattened row by row (element i is row i // nx, column i % nx);
``grid = (kernel, rows, columns)`` holds the influence kernel (2 ny - 1, 2 nx - 1) in m/Pa and the row and
column of every element; the contact set is ``order[:m]`` (element indices, in the order of the rows of
the upper Cholesky factor ``upper[:m, :m]``, C_AA = U^T U) and ``active`` its mask.

Every function that :func:`_active_set_solve` calls lives in this one module on purpose: numba's on-disk
cache (``cache=True``) is invalidated by a change to the file of the cached function only, not by a change
to a function it calls in another module. The steps of the active set (and ``_window_shape``) are inlined
by numba (``inline="always"``): as separate compiled functions they cost 4-6 us of a 95 us warm-started
1 mm solve (measured); inlined they cost nothing measurable, and since neither they nor :func:`_active_set_solve` use
fastmath, inlining does not change their arithmetic (the results are bit-identical to the single function
they were cut from). The fastmath kernels (Cholesky, u = C p) stay separate functions: inlining them
into a non-fastmath caller would drop their fastmath flag.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_STATUS_CONVERGED = 0
_STATUS_MAX_ITER = 1
_STATUS_NOT_DEFINITE = 2
_CAUTIOUS_AFTER = 30  # iterations; then one element at a time (guards against add/drop cycling)
_NO_FACTOR = np.empty((0, 0))


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
def _window_shape(kernel):
    """(ny, nx) of the window whose kernel of offsets is ``kernel`` (2 ny - 1, 2 nx - 1)."""
    return (kernel.shape[0] + 1) // 2, (kernel.shape[1] + 1) // 2


# ---------------------------------------------------------------------------------------------------
# Cholesky factor of C_AA and u = C p
# ---------------------------------------------------------------------------------------------------


@njit(cache=True, fastmath=True)
def _factor_full(grid, order, m, upper):
    """Upper Cholesky factor U (C_AA = U^T U) of the contact set ``order[:m]`` into ``upper[:m, :m]``.

    Computed as the lower factor L = U^T with row-wise dot products (contiguous, vectorised by fastmath),
    then transposed. These hand-written loops measured faster than numba's LAPACK call
    (``np.linalg.cholesky``) for the 100-400 contact elements of the 1 mm and 0.5 mm windows (37 us vs
    44 us at 96 elements). Returns False if C_AA is not positive definite.
    """
    kernel, rows, columns = grid
    ny, nx = _window_shape(kernel)
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


@njit(cache=True, fastmath=True)
def _factor_append(grid, order, m, upper, element):
    """Add ``element`` as row/column m of the factor: O(m^2). Returns False if not positive definite."""
    kernel, rows, columns = grid
    ny, nx = _window_shape(kernel)
    column = np.empty(m)
    row_e = rows[element] + ny - 1
    column_e = columns[element] + nx - 1
    for a in range(m):
        column[a] = kernel[row_e - rows[order[a]], column_e - columns[order[a]]]
    # solve U^T y = c column by column (contiguous rows of U)
    for k in range(m):
        y = column[k] / upper[k, k]
        column[k] = y
        for j in range(k + 1, m):
            column[j] -= upper[k, j] * y
    square = kernel[ny - 1, nx - 1]
    for k in range(m):
        upper[k, m] = column[k]
        square -= column[k] * column[k]
    if square <= 0.0:
        return False
    upper[m, m] = math.sqrt(square)
    order[m] = element
    return True


@njit(cache=True, fastmath=True)
def _factor_remove(order, m, upper, position):
    """Remove the element at ``position`` from the factor of size m: rank-1 update of the trailing block
    (U33^T U33 + u u^T with u = U[position, position+1:]) and a shift, O(m^2)."""
    p = position
    x = upper[p, p + 1 : m].copy()
    for i in range(p + 1, m):
        diagonal = upper[i, i]
        xi = x[i - p - 1]
        r = math.sqrt(diagonal * diagonal + xi * xi)
        c = r / diagonal
        s = xi / diagonal
        upper[i, i] = r
        for j in range(i + 1, m):
            updated = (upper[i, j] + s * x[j - p - 1]) / c
            upper[i, j] = updated
            x[j - p - 1] = c * x[j - p - 1] - s * updated
    # drop row p and column p
    for i in range(p):
        for j in range(p, m - 1):
            upper[i, j] = upper[i, j + 1]
    for i in range(p, m - 1):
        for j in range(i, m - 1):
            upper[i, j] = upper[i + 1, j + 1]
    for a in range(p, m - 1):
        order[a] = order[a + 1]


@njit(cache=True, fastmath=True)
def _cho_solve_two(upper, m, rhs1, rhs2):
    """Solve U^T U x = rhs for two right-hand sides (rhs overwritten with x), contiguous access."""
    for k in range(m):
        y1 = rhs1[k] / upper[k, k]
        y2 = rhs2[k] / upper[k, k]
        rhs1[k] = y1
        rhs2[k] = y2
        for j in range(k + 1, m):
            rhs1[j] -= upper[k, j] * y1
            rhs2[j] -= upper[k, j] * y2
    for k in range(m - 1, -1, -1):
        s1 = rhs1[k]
        s2 = rhs2[k]
        for j in range(k + 1, m):
            s1 -= upper[k, j] * rhs1[j]
            s2 -= upper[k, j] * rhs2[j]
        rhs1[k] = s1 / upper[k, k]
        rhs2[k] = s2 / upper[k, k]


@njit(cache=True)
def _grow(upper, m, needed):
    """The factor buffer, reallocated (keeping ``upper[:m, :m]``) when the contact set outgrows it."""
    if needed <= upper.shape[0]:
        return upper
    size = needed + needed // 4 + 8
    bigger = np.empty((size, size))
    bigger[:m, :m] = upper[:m, :m]
    return bigger


@njit(cache=True, fastmath=True)
def _displacement(grid, order, m, pressure, out):
    """u = C p (eq. 8) for pressure on the elements order[:m]; Toeplitz kernel, contiguous inner loop."""
    kernel, rows, columns = grid
    ny, nx = _window_shape(kernel)
    for i in range(ny * nx):
        out[i] = 0.0
    for a in range(m):
        j = order[a]
        yj = rows[j]
        xj = columns[j]
        pj = pressure[j]
        off = nx - 1 - xj
        for yi in range(ny):
            krow = kernel[yi - yj + ny - 1]
            base = yi * nx
            for xi in range(nx):
                out[base + xi] += krow[xi + off] * pj


@njit(cache=True, fastmath=True)
def _candidate_separation(grid, order, m, pressure, gap, delta, margin, candidates, values):
    """Deformed gap d = h - delta + C p (eq. 11) on the elements that can penetrate; returns their count.

    With p >= 0 the displacement u = C p is >= 0, so d >= h - delta: only elements with h - delta below a
    small ``margin`` (which covers pressures that are negative within the tolerance) can have d < 0. For a
    Hertz-like patch these are about twice the contact area, a third of the 1 mm window.
    """
    kernel, rows, columns = grid
    ny, nx = _window_shape(kernel)
    active_rows = np.empty(m, dtype=np.int64)
    active_columns = np.empty(m, dtype=np.int64)
    active_pressure = np.empty(m)
    for a in range(m):
        j = order[a]
        active_rows[a] = rows[j]
        active_columns[a] = columns[j]
        active_pressure[a] = pressure[j]
    count = 0
    for i in range(ny * nx):
        if gap[i] - delta < margin:
            ri = rows[i] + ny - 1
            ci = columns[i] + nx - 1
            u = 0.0
            for a in range(m):
                u += kernel[ri - active_rows[a], ci - active_columns[a]] * active_pressure[a]
            candidates[count] = i
            values[count] = gap[i] - delta + u
            count += 1
    return count


# ---------------------------------------------------------------------------------------------------
# Active-set steps named after the paper
# ---------------------------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def _solve_on_set(upper, order, m, gap, law, pressure, x1, x2):
    """Pressure on the contact set, eqs. (8), (9), (11) with d = 0 there; returns (delta, max pressure).

    p_A = delta x1 - x2 with C_AA x1 = 1 and C_AA x2 = h_A (one factor, two right-hand sides), and delta
    from ``law = (coupled, target, compliance, area)``: A_e sum(p) = F (``target`` = F, N) or, coupled,
    delta = delta_known - c A_e sum(p) (``target`` = delta_known, m; ``compliance`` = c, m/N).
    Writes p into ``pressure`` at ``order[:m]``.
    """
    coupled, target, compliance, area = law
    for a in range(m):
        x1[a] = 1.0
        x2[a] = gap[order[a]]
    _cho_solve_two(upper, m, x1, x2)
    sum1 = 0.0
    sum2 = 0.0
    for a in range(m):
        sum1 += x1[a]
        sum2 += x2[a]
    if coupled:
        # delta = delta_known - c A_e (delta sum1 - sum2)
        delta = (target + compliance * area * sum2) / (1.0 + compliance * area * sum1)
    else:
        # A_e sum(p) = F with p = delta x1 - x2
        delta = (target / area + sum2) / sum1
    pmax = 0.0
    for a in range(m):
        value = delta * x1[a] - x2[a]
        pressure[order[a]] = value
        if value > pmax:
            pmax = value
    return delta, pmax


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


@njit(cache=True, inline="always")
def _drop_elements(order, m, upper, active, pressure, removals, n_remove):
    """Drop the elements at positions ``removals[:n_remove]`` (ascending) from the set; returns (m, factored).

    Few changes: rank-1 downdates of the factor. Many (more than m / 8): compact the set and factor afresh.
    """
    for r in range(n_remove):
        active[order[removals[r]]] = False
        pressure[order[removals[r]]] = 0.0
    if 8 * n_remove > m:
        kept = 0
        for a in range(m):
            if active[order[a]]:
                order[kept] = order[a]
                kept += 1
        return kept, False
    for r in range(n_remove - 1, -1, -1):
        _factor_remove(order, m, upper, removals[r])
        m -= 1
    return m, True


@njit(cache=True, inline="always")
def _penetrating_elements(candidates, values, n_candidates, active, glimit, one_at_a_time, additions):
    """Elements outside the set that penetrate (eq. 10: d >= 0, d below ``glimit``), into ``additions``; their count.

    ``values[:n_candidates]`` is the deformed gap d of the elements ``candidates[:n_candidates]``. With
    ``one_at_a_time`` only the most penetrating one.
    """
    n_add = 0
    worst = 0.0
    for c in range(n_candidates):
        i = candidates[c]
        if not active[i] and values[c] < glimit:
            if not one_at_a_time:
                additions[n_add] = i
                n_add += 1
            elif n_add == 0 or values[c] < worst:
                additions[0] = i
                n_add = 1
                worst = values[c]
    return n_add


@njit(cache=True, inline="always")
def _add_elements(grid, order, m, upper, factored, active, additions, n_add):
    """Add the elements ``additions[:n_add]`` to the set; returns (factor buffer, m, factored).

    Few changes to a factored set: new rows of the factor (O(m^2) each). Many: factor afresh next time.
    """
    for r in range(n_add):
        active[additions[r]] = True
    if factored and 8 * n_add <= m:
        upper = _grow(upper, m, m + n_add)
        for r in range(n_add):
            if not (factored and _factor_append(grid, order, m, upper, additions[r])):
                factored = False  # (numerically) not positive definite: factor afresh next time
                order[m] = additions[r]
            m += 1
        return upper, m, factored
    for r in range(n_add):
        order[m] = additions[r]
        m += 1
    return upper, m, False


@njit(cache=True, inline="always")
def _initial_state(n, start, factor0):
    """Set buffers from the warm start: (order, active, m, factor buffer, whether it holds the set's factor)."""
    m = start.size
    order = np.empty(n, dtype=np.int64)
    active = np.zeros(n, dtype=np.bool_)
    for a in range(m):
        order[a] = start[a]
        active[start[a]] = True
    capacity = min(n, m + 8 + m // 8)  # no larger than needed: a big buffer costs page faults per call
    upper = np.empty((capacity, capacity))
    factored = factor0.shape[0] == m and m > 0
    if factored:
        upper[:m, :m] = factor0
    return order, active, m, upper, factored


@njit(cache=True, inline="always")
def _summary(grid, pressure, order, m, separations, area):
    """(force N (eq. 9), smallest pressure Pa, largest penetration m, whether the set touches the border)."""
    kernel, rows, columns = grid
    ny, nx = _window_shape(kernel)
    total = 0.0
    min_pressure = 0.0
    min_separation = 0.0
    for i in range(pressure.size):
        total += pressure[i]
        min_pressure = min(min_pressure, pressure[i])
    for c in range(separations.size):
        min_separation = min(min_separation, separations[c])
    at_edge = False
    for a in range(m):
        j = order[a]
        if rows[j] == 0 or rows[j] == ny - 1 or columns[j] == 0 or columns[j] == nx - 1:
            at_edge = True
    return (total * area, min_pressure, -min_separation, at_edge)


@njit(cache=True)
def _active_set_solve(kernel, gap, start, factor0, law, limits):
    """Active-set solution of eqs. (8)-(11) on a window (steps in the module docstring).

    kernel : (2ny-1, 2nx-1) influence kernel, m/Pa; gap : flat (ny*nx) undeformed gap h, m; start : initial
    contact set (element indices); factor0 : its upper Cholesky factor in that order, or 0 x 0 to factor
    afresh; law : (coupled, target, compliance, area) as in :func:`_solve_on_set`; limits : (relative
    tolerance of eq. 10, maximum iterations, iterations after which one element at a time changes).

    Returns (pressure (flat, Pa), approach (m), iterations, status, factor of the final set (m x m, or 0 x 0),
    final set in factor order, contact mask (flat), :func:`_summary`).
    """
    tol, max_iter, cautious_after = limits
    coupled, target = law[0], law[1]
    ny, nx = _window_shape(kernel)
    n = ny * nx
    rows, columns = _coordinates(ny, nx)
    grid = (kernel, rows, columns)
    order, active, m, upper, factored = _initial_state(n, start, factor0)
    pressure = np.zeros(n)
    candidates = np.empty(n, dtype=np.int64)
    values = np.empty(n)
    changes = np.empty(n, dtype=np.int64)  # the elements dropped or added in one iteration
    x1 = np.empty(n)
    x2 = np.empty(n)
    n_candidates = 0
    delta = 0.0
    iterations = 0
    status = _STATUS_MAX_ITER
    gap_min = gap.min()
    while iterations < max_iter:
        iterations += 1
        one_at_a_time = iterations > cautious_after
        for a in range(m):
            pressure[order[a]] = 0.0
        if m == 0 and not coupled:
            # a load needs contact: start from the lowest point
            order[0] = np.argmin(gap)
            active[order[0]] = True
            m = 1
            factored = False
            continue
        if m == 0:
            delta = target  # coupled, no contact: delta = delta_known
        else:
            if not factored:
                upper = _grow(upper, 0, m)
                if not _factor_full(grid, order, m, upper):
                    status = _STATUS_NOT_DEFINITE
                    break
                factored = True
            delta, pmax = _solve_on_set(upper, order, m, gap, law, pressure, x1, x2)
            n_drop = _tension_elements(pressure, order, m, pmax, tol, one_at_a_time, changes)
            if n_drop > 0:
                m, factored = _drop_elements(order, m, upper, active, pressure, changes, n_drop)
                continue
        # deformed gap where it can be negative (eq. 11)
        scale = max(delta - gap_min, 1e-30)
        n_candidates = _candidate_separation(grid, order, m, pressure, gap, delta, 1e-6 * scale, candidates, values)
        n_add = _penetrating_elements(candidates, values, n_candidates, active, -tol * scale, one_at_a_time, changes)
        if n_add == 0:
            status = _STATUS_CONVERGED
            break
        upper, m, factored = _add_elements(grid, order, m, upper, factored, active, changes, n_add)
    if status != _STATUS_CONVERGED:
        # the gaps of the returned pressure (the last iteration may have changed it after its gap pass)
        scale = max(delta - gap_min, 1e-30)
        n_candidates = _candidate_separation(grid, order, m, pressure, gap, delta, 1e-6 * scale, candidates, values)
    final = np.empty((0, 0))
    if status == _STATUS_CONVERGED and factored and m > 0:
        final = upper[:m, :m].copy()
    summary = _summary(grid, pressure, order, m, values[:n_candidates], law[3])
    return pressure, delta, iterations, status, final, order[:m].copy(), active, summary
