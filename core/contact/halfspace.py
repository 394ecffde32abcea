"""3D non-Hertzian normal contact of two elastic half-spaces (paper section 2.3.2, eqs. 8-11).

Geometry and sign convention (z positive downwards into the rail, as in the paper)
-----------------------------------------------------------------------------------
The potential contact area is a window of ``ny x nx`` square elements of side ``element_size``
(rows = lateral y', columns = rolling direction x'). For each element the *undeformed gap* is

    h_e = z_Re - z_We - r_e                                   (the x-independent part of eq. 11)

in m, positive where the surfaces are apart. For crossed cylinders of equal radius R (the paper's wheel
and railhead) ``z_Re - z_We = (x'^2 + y'^2) / (2 R)``: a sphere of radius R on a flat. ``r = r_W - r_R`` is the
combined roughness (r_W, r_R positive downwards), so a bump on the wheel (r_W > 0) or on the rail (r_R < 0)
*reduces* the gap. With the approach ``delta = xi_W - xi_R`` (m, positive when wheel and rail move
towards each other) the deformed gap of eq. (11) is

    d_e = h_e - delta + u_e,     u = C p   (eq. 8),     F = A_e sum(p)   (eq. 9),

and the contact conditions (10) are d >= 0, p >= 0, d p = 0.

Influence coefficients
----------------------
Uniform pressure on a rectangle (Love's solution, Johnson, *Contact Mechanics*, eq. 3.25): the combined
normal displacement of two bodies of the same material is

    u(x, y) = 1 / (pi E*) * integral over the element of p / rho dA,    E* = E / (2 (1 - nu^2)),

i.e. twice the single-body value (1 - nu^2) / (pi E). The matrix C is block-Toeplitz (it only depends on
the offset between two elements), so only the kernel of offsets (2 ny - 1, 2 nx - 1) is stored and cached
per (shape, element size, material).

Solver
------
An exact active-set method (Kalker's scheme with the load as an extra equation): on the current set A of
contact elements it solves the dense system ``C_AA p_A = delta - h_A`` together with the load equation
(given load, or ``delta = delta_known - c F`` in the coupled form) with one Cholesky factor of ``C_AA``;
then it drops all elements in tension or, if none, adds all elements that penetrate, until neither
happens (after 30 iterations one element at a time, the worst, against cycling). The factor is updated
rather than recomputed when few elements change (O(m^2) per element:
a new row for an added element, a rank-1 update for a dropped one), and a result carries it to the next
solve, so a warm start from the previous time step typically costs one or two triangular solves and one
or two passes of u = C p. Everything runs in numba; the Cholesky loops are hand-written (measured faster
than numba's LAPACK call at these sizes). A direct solve was chosen over FFT-based conjugate gradients
(Polonsky-Keer) by measurement: ``benchmarks/contact_solver.py`` compares with tamaas' PKR solver.

Failures are reported: by default a solve that does not converge within ``max_iterations`` or whose
contact set reaches the window edge raises :class:`WheelrailError`; with ``raise_on_failure=False``
the result is returned with ``converged=False`` / ``at_edge=True`` and the caller must check them.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from wheelrail.core.checks import poisson_ratio as _poisson
from wheelrail.core.checks import positive as _positive
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import reduced_modulus

__all__ = [
    "NormalContactResult",
    "influence_kernel",
    "solve_coupled_contact",
    "solve_normal_contact",
]

_STATUS_CONVERGED = 0
_STATUS_MAX_ITER = 1
_STATUS_NOT_DEFINITE = 2
_CAUTIOUS_AFTER = 30  # iterations; then one element at a time (guards against add/drop cycling)


@dataclass(frozen=True, eq=False)
class NormalContactResult:
    """Solution of one normal-contact problem (eqs. 8-11) on a window of square elements.

    Attributes
    ----------
    pressure : ndarray, shape (ny, nx)
        Element pressures p_e, Pa (uniform over each element).
    contact : ndarray of bool, shape (ny, nx)
        Elements in contact (the final active set).
    force : float
        Total normal force F_n = A_e sum(p), eq. (9), N.
    approach : float
        Rigid-body approach delta = xi_W - xi_R, m (positive = bodies pressed together).
    iterations : int
        Number of active-set iterations (linear solves).
    converged : bool
        True when the contact conditions (10) hold to the tolerance.
    at_edge : bool
        True when the contact set touches the outermost row or column of the window, i.e. the window
        may be too small and the answer would be wrong.
    max_gap_violation : float
        max(0, -min(d)), m: the largest penetration left.
    min_pressure : float
        Smallest element pressure, Pa (negative only within the tolerance).
    element_size : float
        Side of the square elements, m.
    separation : ndarray, shape (ny, nx)
        Deformed gap d = h - delta + C p, eq. (11), m (zero, up to round-off, where in contact). Computed
        on first access (the solver itself only needs it where the surfaces overlap).
    """

    pressure: np.ndarray
    contact: np.ndarray
    force: float
    approach: float
    iterations: int
    converged: bool
    at_edge: bool
    max_gap_violation: float
    min_pressure: float
    element_size: float
    _warm: object = field(default=None, repr=False)
    _gap: np.ndarray | None = field(default=None, repr=False)
    _kernel: np.ndarray | None = field(default=None, repr=False)

    @functools.cached_property
    def separation(self) -> np.ndarray:
        """Deformed gap d = h - delta + C p of eq. (11) on the whole window, m."""
        ny, nx = self.pressure.shape
        rows, columns = _coordinates(ny, nx)
        flat = self.pressure.ravel()
        order = np.flatnonzero(flat)
        u = np.empty(ny * nx)
        _displacement(self._kernel, ny, nx, rows, columns, order, order.size, flat, u)
        separation = (self._gap - self.approach + u).reshape(ny, nx)
        separation.setflags(write=False)
        return separation

    @property
    def contact_area(self) -> float:
        """Area of the contact elements, m^2."""
        return float(np.count_nonzero(self.contact)) * self.element_size**2


# ---------------------------------------------------------------------------------------------------
# Influence coefficients
# ---------------------------------------------------------------------------------------------------


def _rect_integral(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Antiderivative of 1/sqrt(x^2 + y^2) in x and y: x asinh(y/|x|) + y asinh(x/|y|) (0 on the axes).

    This is x ln(y + rho) + y ln(x + rho) less terms in x or y alone, which cancel in the corner sum.
    """
    ax = np.where(x != 0.0, np.abs(x), 1.0)
    ay = np.where(y != 0.0, np.abs(y), 1.0)
    first = np.where(x != 0.0, x * np.arcsinh(y / ax), 0.0)
    second = np.where(y != 0.0, y * np.arcsinh(x / ay), 0.0)
    return first + second


@functools.lru_cache(maxsize=32)
def _cached_kernel(ny: int, nx: int, element_size: float, youngs_modulus: float, poisson_ratio: float):
    half = 0.5 * element_size
    oy = np.arange(-(ny - 1), ny, dtype=float)[:, None] * element_size
    ox = np.arange(-(nx - 1), nx, dtype=float)[None, :] * element_size
    # Johnson eq. 3.25 (Love): integral of 1/rho over the element centred at offset (ox, oy)
    integral = (
        _rect_integral(ox + half, oy + half)
        - _rect_integral(ox + half, oy - half)
        - _rect_integral(ox - half, oy + half)
        + _rect_integral(ox - half, oy - half)
    )
    kernel = np.ascontiguousarray(integral / (math.pi * reduced_modulus(youngs_modulus, poisson_ratio)))
    kernel.setflags(write=False)
    return kernel


def influence_kernel(
    shape: tuple[int, int],
    element_size: float,
    *,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
) -> np.ndarray:
    """Influence coefficients of eq. (8) as a kernel of element offsets (Johnson eq. 3.25).

    Parameters
    ----------
    shape : (int, int)
        Window size (ny, nx) in elements.
    element_size : float
        Side of the square elements, m.
    youngs_modulus, poisson_ratio : float
        E in Pa and nu of both bodies (same material).

    Returns
    -------
    ndarray, shape (2 ny - 1, 2 nx - 1), read-only
        ``K[dy + ny - 1, dx + nx - 1]`` is the combined normal displacement (m) at an element centre per
        unit uniform pressure (Pa) on an element offset by (dy, dx) elements, m/Pa. Cached per arguments.
    """
    ny, nx = (int(shape[0]), int(shape[1]))
    if ny < 1 or nx < 1:
        raise WheelrailError(f"influence_kernel: shape must be two positive integers, got {shape!r}")
    element_size = _positive("influence_kernel", "element_size", element_size, "m")
    youngs_modulus, poisson_ratio = _material("influence_kernel", youngs_modulus, poisson_ratio)
    return _cached_kernel(ny, nx, element_size, youngs_modulus, poisson_ratio)


# ---------------------------------------------------------------------------------------------------
# numba kernel: active-set solve
# ---------------------------------------------------------------------------------------------------


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
def _factor_full(kernel, ny, nx, rows, columns, order, m, upper):
    """Upper Cholesky factor U (C_AA = U^T U) of the contact set ``order[:m]`` into ``upper[:m, :m]``.

    Computed as the lower factor L = U^T with row-wise dot products (contiguous, vectorised by fastmath),
    then transposed. These hand-written loops measured faster than numba's LAPACK call
    (``np.linalg.cholesky``) for the 100-400 contact elements of the 1 mm and 0.5 mm windows (37 us vs
    44 us at 96 elements). Returns False if C_AA is not positive definite.
    """
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
def _factor_append(kernel, ny, nx, rows, columns, order, m, upper, element):
    """Add ``element`` as row/column m of the factor: O(m^2). Returns False if not positive definite."""
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


@njit(cache=True, fastmath=True)
def _displacement(kernel, ny, nx, rows, columns, order, m, pressure, out):
    """u = C p (eq. 8) for pressure on the elements order[:m]; Toeplitz kernel, contiguous inner loop."""
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
def _candidate_separation(kernel, ny, nx, rows, columns, order, m, pressure, gap, delta, margin, candidates, values):
    """Deformed gap d = h - delta + C p (eq. 11) on the elements that can penetrate; returns their count.

    With p >= 0 the displacement u = C p is >= 0, so d >= h - delta: only elements with h - delta below a
    small ``margin`` (which covers pressures that are negative within the tolerance) can have d < 0. For a
    Hertz-like patch these are about twice the contact area, a third of the 1 mm window.
    """
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


@njit(cache=True)
def _grow(upper, order, m, needed):
    """Reallocate the factor buffer when the contact set outgrows it."""
    if needed <= upper.shape[0]:
        return upper
    size = needed + needed // 4 + 8
    bigger = np.empty((size, size))
    bigger[:m, :m] = upper[:m, :m]
    return bigger


@njit(cache=True)
def _active_set_solve(
    kernel, ny, nx, gap, order0, m0, factor0, coupled, target, compliance, area, tol, max_iter, cautious_after
):
    """Active-set solution of eqs. (8)-(11) on a window (no input checks: the wrapper does them).

    kernel : (2ny-1, 2nx-1) influence kernel, m/Pa; gap : flat (ny*nx) undeformed gap h, m;
    order0[:m0] : initial contact set (element indices); factor0 : its upper Cholesky factor in that order
    (m0 x m0), or a 0 x 0 array to factor from scratch; coupled : False -> ``target`` is the load F (N);
    True -> ``target`` is delta_known (m) and delta = delta_known - compliance * F; area : A_e, m^2;
    tol : relative tolerance of eq. (10); cautious_after : iterations after which one element at a time
    is added or dropped (anti-cycling).

    Each iteration solves C_AA p_A = delta - h_A with the load (or coupled) equation using one Cholesky
    factor: p = delta x1 - x2 with C_AA x1 = 1, C_AA x2 = h_A. Then all elements in tension are dropped or,
    if none, all penetrating elements are added. The factor is updated (O(m^2) per element) rather than
    recomputed when few elements change.

    Returns (pressure (flat, Pa), approach (m), iterations, status, factor of the final set (m x m), final
    set in factor order, contact mask (flat), (force N, min pressure Pa, max penetration m, at edge)).
    """
    n = ny * nx
    rows, columns = _coordinates(ny, nx)
    pressure = np.zeros(n)
    active = np.zeros(n, dtype=np.bool_)
    order = np.empty(n, dtype=np.int64)
    m = m0
    for a in range(m):
        order[a] = order0[a]
        active[order0[a]] = True
    capacity = min(n, m + 8 + m // 8)  # no larger than needed: a big buffer costs page faults per call
    upper = np.empty((capacity, capacity))
    factored = factor0.shape[0] == m and m > 0
    if factored:
        upper[:m, :m] = factor0
    candidates = np.empty(n, dtype=np.int64)
    values = np.empty(n)
    n_candidates = 0
    removals = np.empty(n, dtype=np.int64)
    additions = np.empty(n, dtype=np.int64)
    x1 = np.empty(n)
    x2 = np.empty(n)
    delta = 0.0
    iterations = 0
    status = _STATUS_MAX_ITER
    gap_min = gap.min()
    while iterations < max_iter:
        iterations += 1
        for a in range(m):
            pressure[order[a]] = 0.0
        if m == 0:
            if coupled:
                delta = target
            else:
                # a load needs contact: start from the lowest point
                j = np.argmin(gap)
                order[0] = j
                active[j] = True
                m = 1
                factored = False
                continue
        else:
            if not factored:
                upper = _grow(upper, order, 0, m)
                if not _factor_full(kernel, ny, nx, rows, columns, order, m, upper):
                    status = _STATUS_NOT_DEFINITE
                    break
                factored = True
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
            # drop elements in tension (eq. 10: p >= 0)
            plimit = -tol * pmax
            n_remove = 0
            worst = 0.0
            for a in range(m):
                value = pressure[order[a]]
                if value < plimit or (pmax <= 0.0 and value <= 0.0):
                    if iterations <= cautious_after:
                        removals[n_remove] = a
                        n_remove += 1
                    elif n_remove == 0 or value < worst:
                        # anti-cycling: one element at a time, the one in most tension
                        removals[0] = a
                        n_remove = 1
                        worst = value
            if n_remove > 0:
                for r in range(n_remove):
                    active[order[removals[r]]] = False
                    pressure[order[removals[r]]] = 0.0
                if 8 * n_remove > m:
                    # many changes: compact the set and factor afresh
                    kept = 0
                    for a in range(m):
                        if active[order[a]]:
                            order[kept] = order[a]
                            kept += 1
                    m = kept
                    factored = False
                else:
                    for r in range(n_remove - 1, -1, -1):
                        _factor_remove(order, m, upper, removals[r])
                        m -= 1
                continue
        # deformed gap where it can be negative (eq. 11); add penetrating elements (eq. 10: d >= 0)
        scale = max(delta - gap_min, 1e-30)
        glimit = -tol * scale
        n_candidates = _candidate_separation(
            kernel, ny, nx, rows, columns, order, m, pressure, gap, delta, 1e-6 * scale, candidates, values
        )
        n_add = 0
        worst = 0.0
        for c in range(n_candidates):
            i = candidates[c]
            if not active[i] and values[c] < glimit:
                if iterations <= cautious_after:
                    additions[n_add] = i
                    n_add += 1
                elif n_add == 0 or values[c] < worst:
                    # anti-cycling: one element at a time, the most penetrating
                    additions[0] = i
                    n_add = 1
                    worst = values[c]
        if n_add == 0:
            status = _STATUS_CONVERGED
            break
        for r in range(n_add):
            active[additions[r]] = True
        if factored and 8 * n_add <= m:
            upper = _grow(upper, order, m, m + n_add)
            for r in range(n_add):
                if not (factored and _factor_append(kernel, ny, nx, rows, columns, order, m, upper, additions[r])):
                    factored = False  # (numerically) not positive definite: factor afresh next time
                    order[m] = additions[r]
                m += 1
        else:
            for r in range(n_add):
                order[m] = additions[r]
                m += 1
            factored = False
    if status != _STATUS_CONVERGED:
        # the gaps of the returned pressure (the last iteration may have changed it after its gap pass)
        scale = max(delta - gap_min, 1e-30)
        n_candidates = _candidate_separation(
            kernel, ny, nx, rows, columns, order, m, pressure, gap, delta, 1e-6 * scale, candidates, values
        )
    final = np.empty((0, 0))
    if status == _STATUS_CONVERGED and factored and m > 0:
        final = upper[:m, :m].copy()
    # summary: eq. (9), the smallest pressure and gap, and whether the set touches the window's border
    total = 0.0
    min_pressure = 0.0
    min_separation = 0.0
    for i in range(n):
        total += pressure[i]
        min_pressure = min(min_pressure, pressure[i])
    for c in range(n_candidates):
        min_separation = min(min_separation, values[c])
    at_edge = False
    for a in range(m):
        j = order[a]
        if rows[j] == 0 or rows[j] == ny - 1 or columns[j] == 0 or columns[j] == nx - 1:
            at_edge = True
    summary = (total * area, min_pressure, -min_separation, at_edge)
    return pressure, delta, iterations, status, final, order[:m].copy(), active, summary


# ---------------------------------------------------------------------------------------------------
# Python wrappers
# ---------------------------------------------------------------------------------------------------


def _material(where: str, youngs_modulus, poisson_ratio) -> tuple[float, float]:
    return _positive(where, "youngs_modulus", youngs_modulus, "Pa"), _poisson(where, poisson_ratio)


def _check_gap(where: str, gap) -> np.ndarray:
    try:
        array = np.asarray(gap, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: gap must be a 2D array of numbers in m") from None
    if array.ndim != 2:
        raise WheelrailError(f"{where}: gap must be a 2D array (ny, nx) in m, got shape {array.shape}")
    if array.shape[0] < 2 or array.shape[1] < 2:
        raise WheelrailError(f"{where}: gap window must be at least 2 x 2 elements, got shape {array.shape}")
    if not np.all(np.isfinite(array)):
        bad = np.argwhere(~np.isfinite(array))[0]
        raise WheelrailError(
            f"{where}: gap must be finite (m), got {array[tuple(bad)]} at element {tuple(int(i) for i in bad)}"
        )
    return np.ascontiguousarray(array)


def _initial_set(where: str, initial, shape, key):
    """Warm start: the contact set (element indices) and, for a result of the same problem class
    (shape, element size, material), its Cholesky factor in the same order."""
    if initial is None:
        return None, _NO_FACTOR
    if isinstance(initial, NormalContactResult) and initial._warm is not None and initial._warm[0] == key:
        return initial._warm[2], initial._warm[1]
    mask = initial.contact if isinstance(initial, NormalContactResult) else initial
    mask = np.asarray(mask)
    if mask.shape != shape or mask.dtype != bool:
        raise WheelrailError(
            f"{where}: initial must be a NormalContactResult or bool mask of shape {shape}, "
            f"got {type(initial).__name__} of shape {mask.shape}"
        )
    return np.flatnonzero(mask), _NO_FACTOR


_NO_FACTOR = np.empty((0, 0))


def _cold_start_set(
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


def _solve(
    where,
    gap,
    element_size,
    coupled,
    target,
    compliance,
    initial,
    youngs_modulus,
    poisson_ratio,
    tolerance,
    max_iterations,
    raise_on_failure,
) -> NormalContactResult:
    gap = _check_gap(where, gap)
    element_size = _positive(where, "element_size", element_size, "m")
    youngs_modulus, poisson_ratio = _material(where, youngs_modulus, poisson_ratio)
    tolerance = _positive(where, "tolerance", tolerance, "relative")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, int | np.integer) or max_iterations < 1:
        raise WheelrailError(f"{where}: max_iterations must be an integer >= 1, got {max_iterations!r}")
    ny, nx = gap.shape
    key = (ny, nx, element_size, youngs_modulus, poisson_ratio)
    kernel = _cached_kernel(*key)
    flat = gap.ravel()
    if not flat.flags.writeable:
        flat = flat.copy()  # one numba specialisation for all callers
    area = element_size**2
    order, factor = _initial_set(where, initial, gap.shape, key)
    if order is None:
        modulus = reduced_modulus(youngs_modulus, poisson_ratio)
        order = np.flatnonzero(_cold_start_set(flat, area, modulus, coupled, float(target), float(compliance)))
    pressure, delta, iterations, status, upper, order, contact, summary = _active_set_solve(
        kernel,
        ny,
        nx,
        flat,
        order,
        order.size,
        factor,
        coupled,
        float(target),
        float(compliance),
        area,
        tolerance,
        int(max_iterations),
        _CAUTIOUS_AFTER,
    )
    contact = contact.reshape(ny, nx)
    pressure = pressure.reshape(ny, nx)
    # the factor and its order stay writable (private to the result): read-only arrays would make numba
    # compile a second specialisation of the kernel for warm starts
    for array in (contact, pressure):
        array.setflags(write=False)
    force, min_pressure, max_gap_violation, at_edge = summary
    converged = status == _STATUS_CONVERGED
    warm = (key, upper, order) if converged and order.size > 0 and upper.shape[0] == order.size else None
    result = NormalContactResult(
        pressure=pressure,
        contact=contact,
        force=force,
        approach=delta,
        iterations=iterations,
        converged=converged,
        at_edge=at_edge,
        max_gap_violation=max_gap_violation,
        min_pressure=min_pressure,
        element_size=element_size,
        _warm=warm,
        _gap=flat.copy(),  # the caller may reuse its gap array; separation is computed later
        _kernel=kernel,
    )
    if raise_on_failure:
        if status == _STATUS_NOT_DEFINITE:
            raise WheelrailError(
                f"{where}: the influence matrix of the contact set lost positive definiteness in round-off "
                f"after {iterations} iterations; the solve failed"
            )
        if not converged:
            raise WheelrailError(
                f"{where}: active-set solver did not converge in {iterations} iterations "
                f"(max_iterations={max_iterations}); the gap may be ill-posed or the tolerance too tight"
            )
        if at_edge:
            raise WheelrailError(
                f"{where}: contact reaches the edge of the {ny} x {nx} window "
                f"({ny * element_size * 1e3:.3g} x {nx * element_size * 1e3:.3g} mm); "
                "the window is too small for the load, use a larger window"
            )
    return result


def solve_normal_contact(
    gap,
    element_size: float,
    *,
    load: float,
    initial: NormalContactResult | np.ndarray | None = None,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    tolerance: float = 1e-9,
    max_iterations: int = 100,
    raise_on_failure: bool = True,
) -> NormalContactResult:
    """Load-controlled normal contact of two elastic half-spaces, eqs. (8)-(11).

    Finds the pressure p >= 0 and the approach delta such that the deformed gap d = h - delta + C p
    is >= 0, zero where p > 0 (eq. 10), and A_e sum(p) equals the load (eq. 9).

    Parameters
    ----------
    gap : array_like, shape (ny, nx)
        Undeformed gap h between the surfaces at the element centres, m (module docstring: for the paper's
        crossed cylinders ``(x^2 + y^2) / (2 R) - r`` with r = r_W - r_R positive downwards).
    element_size : float
        Side of the square elements, m (1e-3 in the paper).
    load : float
        Total normal force F_n, N (> 0).
    initial : NormalContactResult or bool ndarray, optional
        Warm start: a previous result on the same window shape, or a contact mask (e.g. the previous one
        shifted by the caller). Only the contact set is reused; the answer does not depend on it.
    youngs_modulus, poisson_ratio : float
        E (Pa) and nu of both bodies (same material): E* = E / (2 (1 - nu^2)).
    tolerance : float
        Relative tolerance of the contact conditions: pressures down to ``-tolerance * max(p)`` and gaps
        down to ``-tolerance * (delta - min(h))`` count as zero.
    max_iterations : int
        Maximum number of active-set iterations (one Cholesky factorisation each).
    raise_on_failure : bool
        If True (default) non-convergence or contact at the window edge raises :class:`WheelrailError`;
        if False the result is returned and ``converged`` / ``at_edge`` must be checked.

    Returns
    -------
    NormalContactResult
    """
    where = "solve_normal_contact"
    load = _positive(where, "load", load, "N")
    return _solve(
        where,
        gap,
        element_size,
        False,
        load,
        0.0,
        initial,
        youngs_modulus,
        poisson_ratio,
        tolerance,
        max_iterations,
        raise_on_failure,
    )


def solve_coupled_contact(
    gap,
    element_size: float,
    *,
    approach_known: float,
    compliance: float,
    initial: NormalContactResult | np.ndarray | None = None,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    tolerance: float = 1e-9,
    max_iterations: int = 100,
    raise_on_failure: bool = True,
) -> NormalContactResult:
    """Normal contact coupled to the wheel and rail dynamics: one solve per time step.

    The approach is not given but follows from the force as in the time-stepping loop (eqs. 1, 2, 11):

        delta = approach_known - compliance * F,    F = A_e sum(p),

    where ``approach_known`` is the part of xi_W - xi_R known from the history (the convolution with earlier
    forces, the preload response and the static position) and ``compliance`` = g_W(0) + g_R(0) >= 0 the
    instantaneous wheel + rail compliance. Contact may be lost: if the surfaces do not touch at
    ``approach_known`` the result has F = 0 and no contact elements (this is physics, not an error).

    Parameters
    ----------
    gap : array_like, shape (ny, nx)
        Undeformed gap h, m (see :func:`solve_normal_contact`).
    element_size : float
        Side of the square elements, m.
    approach_known : float
        delta_known, m (positive = towards each other).
    compliance : float
        c >= 0, m/N.
    initial, youngs_modulus, poisson_ratio, tolerance, max_iterations, raise_on_failure
        As in :func:`solve_normal_contact`.

    Returns
    -------
    NormalContactResult
        ``approach`` is the consistent delta = approach_known - compliance * force.
    """
    where = "solve_coupled_contact"
    try:
        approach_known = float(approach_known)
        compliance = float(compliance)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: approach_known (m) and compliance (m/N) must be numbers") from None
    if not math.isfinite(approach_known):
        raise WheelrailError(f"{where}: approach_known must be finite (m), got {approach_known!r}")
    if not math.isfinite(compliance) or compliance < 0.0:
        raise WheelrailError(f"{where}: compliance must be finite and >= 0 (m/N), got {compliance!r}")
    return _solve(
        where,
        gap,
        element_size,
        True,
        approach_known,
        compliance,
        initial,
        youngs_modulus,
        poisson_ratio,
        tolerance,
        max_iterations,
        raise_on_failure,
    )
