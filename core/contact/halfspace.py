"""3D non-Hertzian normal contact of two elastic half-spaces (paper section 2.3.2, eqs. 8-11).

Geometry and sign convention (z positive downwards into the rail, as in the paper)
-----------------------------------------------------------------------------------
The potential contact area is a window of ``ny x nx`` square elements of side ``element_size``
(rows = lateral y', columns = rolling direction x'). For each element the *undeformed gap* is

    h_e = z_Re - z_We - r_e                                   (the x-independent part of eq. 11)

in m, positive where the surfaces are apart. For crossed cylinders of equal radius R (the paper's wheel
and railhead) ``z_Re - z_We = (x'^2 + y'^2) / (2 R)``: a sphere of radius R on a flat. ``r = r_W - r_R`` is the
combined roughness, positive downwards, so roughness that sticks out of the wheel (or a dip in the rail)
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
(given load, or ``delta = delta_known - c F`` in the coupled form) through one Cholesky factorisation of
``C_AA``; then it drops elements with negative pressure, or else adds elements that penetrate, until
neither happens. A warm start (the previous contact set) usually needs one or two factorisations.
The kernel is compiled with numba and uses LAPACK (``np.linalg.cholesky``); choosing this over FFT-based
conjugate gradients was done by measurement (see ``benchmarks/contact_solver.py``): on the 1 mm window
(~95 contact elements) a direct solve is exact and much faster than any iterative scheme.

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

from wheelrail.core.errors import WheelrailError

__all__ = [
    "NormalContactResult",
    "influence_kernel",
    "solve_coupled_contact",
    "solve_normal_contact",
]

_STATUS_CONVERGED = 0
_STATUS_MAX_ITER = 1
_STATUS_NOT_DEFINITE = 2
_LAPACK_ABOVE = 700  # contact elements; LAPACK's blocked Cholesky wins above this (measured)


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
    separation : ndarray, shape (ny, nx)
        Deformed gap d = h - delta + C p, eq. (11), m (zero, up to round-off, where in contact).
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
    """

    pressure: np.ndarray
    contact: np.ndarray
    force: float
    approach: float
    separation: np.ndarray
    iterations: int
    converged: bool
    at_edge: bool
    max_gap_violation: float
    min_pressure: float
    element_size: float
    _warm: object = field(default=None, repr=False)

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
    reduced_modulus = youngs_modulus / (2.0 * (1.0 - poisson_ratio**2))
    kernel = np.ascontiguousarray(integral / (math.pi * reduced_modulus))
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


@njit(cache=True, fastmath=True)
def _cholesky_in_place(a):
    """Lower Cholesky factor of the SPD matrix ``a`` in place (upper triangle left as is).

    Plain loops with fastmath (vectorised dot products) measured faster than numba's LAPACK call
    (``np.linalg.cholesky``) for the 100-400 contact elements of the 1 mm and 0.5 mm windows
    (37 us vs 44 us at 96, 1.5 ms vs 2.3 ms at 392). Returns False if ``a`` is not positive definite.
    """
    m = a.shape[0]
    for j in range(m):
        s = a[j, j]
        for k in range(j):
            s -= a[j, k] * a[j, k]
        if s <= 0.0:
            return False
        d = math.sqrt(s)
        a[j, j] = d
        for i in range(j + 1, m):
            t = a[i, j]
            for k in range(j):
                t -= a[i, k] * a[j, k]
            a[i, j] = t / d
    return True


@njit(cache=True, fastmath=True)
def _cho_solve_two(chol, rhs1, rhs2):
    """Solve (L L^T) x = rhs for two right-hand sides, row-oriented for contiguous access."""
    m = chol.shape[0]
    x1 = rhs1.copy()
    x2 = rhs2.copy()
    for a in range(m):
        s1 = x1[a]
        s2 = x2[a]
        for b in range(a):
            s1 -= chol[a, b] * x1[b]
            s2 -= chol[a, b] * x2[b]
        x1[a] = s1 / chol[a, a]
        x2[a] = s2 / chol[a, a]
    for a in range(m - 1, -1, -1):
        x1[a] /= chol[a, a]
        x2[a] /= chol[a, a]
        v1 = x1[a]
        v2 = x2[a]
        for b in range(a):
            x1[b] -= chol[a, b] * v1
            x2[b] -= chol[a, b] * v2
    return x1, x2


@njit(cache=True, fastmath=True)
def _displacement(kernel, ny, nx, idx, m, pressure, out):
    """u = C p (eq. 8) for pressure on the elements idx[:m]; Toeplitz kernel, contiguous inner loop."""
    for i in range(ny * nx):
        out[i] = 0.0
    for a in range(m):
        j = idx[a]
        yj = j // nx
        xj = j - yj * nx
        pj = pressure[j]
        for yi in range(ny):
            krow = kernel[yi - yj + ny - 1]
            base = yi * nx
            off = nx - 1 - xj
            for xi in range(nx):
                out[base + xi] += krow[xi + off] * pj


@njit(cache=True)
def _active_set_solve(kernel, ny, nx, gap, active, coupled, target, compliance, area, tol, max_iter, factor):
    """Active-set solution of eqs. (8)-(11) on a window (no input checks: the wrapper does them).

    kernel : (2ny-1, 2nx-1) influence kernel, m/Pa; gap : flat (ny*nx) undeformed gap h, m;
    active : flat bool initial active set (modified in place to the final set);
    coupled : False -> ``target`` is the load F (N); True -> ``target`` is delta_known (m) and
    delta = delta_known - compliance * F; area : element area A_e, m^2; tol : relative tolerance;
    factor : Cholesky factor of C_AA for the initial active set, or a 0 x 0 array.

    Returns (pressure (flat, Pa), separation (flat, m), approach (m), iterations, status, factor of the
    final set).
    """
    n = ny * nx
    pressure = np.zeros(n)
    separation = np.empty(n)
    idx = np.empty(n, dtype=np.int64)
    chol = np.empty((0, 0))
    delta = 0.0
    iterations = 0
    status = _STATUS_MAX_ITER
    gap_min = gap.min()
    reuse = factor.shape[0] > 0
    m = 0
    while iterations < max_iter:
        iterations += 1
        m = 0
        for i in range(n):
            if active[i]:
                idx[m] = i
                m += 1
        for i in range(n):
            pressure[i] = 0.0
        if m == 0:
            if coupled:
                delta = target
            else:
                # a load needs contact: start from the lowest point
                active[np.argmin(gap)] = True
                continue
        else:
            if reuse and factor.shape[0] == m:
                chol = factor
            else:
                c_aa = np.empty((m, m))
                for a in range(m):
                    ia = idx[a]
                    ya = ia // nx
                    xa = ia - ya * nx
                    for b in range(a + 1):
                        ib = idx[b]
                        yb = ib // nx
                        value = kernel[ya - yb + ny - 1, xa - (ib - yb * nx) + nx - 1]
                        c_aa[a, b] = value
                        c_aa[b, a] = value
                if m > _LAPACK_ABOVE:
                    chol = np.ascontiguousarray(np.linalg.cholesky(c_aa))
                elif _cholesky_in_place(c_aa):
                    chol = c_aa
                else:
                    status = _STATUS_NOT_DEFINITE
                    break
            reuse = False
            ones = np.ones(m)
            h_a = np.empty(m)
            for a in range(m):
                h_a[a] = gap[idx[a]]
            x1, x2 = _cho_solve_two(chol, ones, h_a)
            sum1 = x1.sum()
            sum2 = x2.sum()
            if coupled:
                # delta = delta_known - c A_e (delta sum1 - sum2)
                delta = (target + compliance * area * sum2) / (1.0 + compliance * area * sum1)
            else:
                # A_e sum(p) = F with p = delta x1 - x2
                delta = (target / area + sum2) / sum1
            pmax = 0.0
            for a in range(m):
                value = delta * x1[a] - x2[a]
                pressure[idx[a]] = value
                if value > pmax:
                    pmax = value
            # drop elements in tension (eq. 10: p >= 0)
            dropped = False
            plimit = -tol * pmax
            for a in range(m):
                value = pressure[idx[a]]
                if value < plimit or (pmax <= 0.0 and value <= 0.0):
                    active[idx[a]] = False
                    dropped = True
            if dropped:
                continue
        # deformed gap everywhere (eq. 11); add penetrating elements (eq. 10: d >= 0)
        _displacement(kernel, ny, nx, idx, m, pressure, separation)
        glimit = -tol * max(delta - gap_min, 1e-30)
        added = False
        for i in range(n):
            d = gap[i] - delta + separation[i]
            separation[i] = d
            if not active[i] and d < glimit:
                active[i] = True
                added = True
        if not added:
            status = _STATUS_CONVERGED
            break
    if status != _STATUS_CONVERGED:
        # make separation consistent with the returned pressure
        m = 0
        for i in range(n):
            if pressure[i] != 0.0:
                idx[m] = i
                m += 1
        _displacement(kernel, ny, nx, idx, m, pressure, separation)
        for i in range(n):
            separation[i] += gap[i] - delta
    return pressure, separation, delta, iterations, status, chol


# ---------------------------------------------------------------------------------------------------
# Python wrappers
# ---------------------------------------------------------------------------------------------------


def _positive(where: str, name: str, value, unit: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: {name} must be a number in {unit}, got {value!r}") from None
    if not math.isfinite(number) or number <= 0.0:
        raise WheelrailError(f"{where}: {name} must be positive and finite ({unit}), got {value!r}")
    return number


def _material(where: str, youngs_modulus, poisson_ratio) -> tuple[float, float]:
    youngs_modulus = _positive(where, "youngs_modulus", youngs_modulus, "Pa")
    try:
        nu = float(poisson_ratio)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: poisson_ratio must be a number, got {poisson_ratio!r}") from None
    if not (math.isfinite(nu) and 0.0 <= nu < 0.5):
        raise WheelrailError(f"{where}: poisson_ratio must be in [0, 0.5), got {poisson_ratio!r}")
    return youngs_modulus, nu


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
    """Warm-start contact mask and, when it is a result on the same problem class, its Cholesky factor."""
    if initial is None:
        return None, _NO_FACTOR
    mask = initial.contact if isinstance(initial, NormalContactResult) else initial
    mask = np.asarray(mask)
    if mask.shape != shape or mask.dtype != bool:
        raise WheelrailError(
            f"{where}: initial must be a NormalContactResult or bool mask of shape {shape}, "
            f"got {type(initial).__name__} of shape {mask.shape}"
        )
    factor = _NO_FACTOR
    if isinstance(initial, NormalContactResult) and initial._warm is not None and initial._warm[0] == key:
        factor = initial._warm[1]
    return mask.ravel().copy(), factor


_NO_FACTOR = np.empty((0, 0))


def _cold_start_set(
    flat: np.ndarray, area: float, reduced_modulus: float, coupled: bool, target: float, compliance: float
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
    force = (4.0 / 3.0) * reduced_modulus * np.sqrt(count * area / np.pi) * 2.0 * order
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
    area = element_size**2
    active, factor = _initial_set(where, initial, gap.shape, key)
    if active is None:
        reduced_modulus = youngs_modulus / (2.0 * (1.0 - poisson_ratio**2))
        active = _cold_start_set(flat, area, reduced_modulus, coupled, float(target), float(compliance))
    pressure, separation, delta, iterations, status, chol = _active_set_solve(
        kernel,
        ny,
        nx,
        flat,
        active,
        coupled,
        float(target),
        float(compliance),
        area,
        tolerance,
        int(max_iterations),
        factor,
    )
    contact = active.reshape(ny, nx)
    pressure = pressure.reshape(ny, nx)
    separation = separation.reshape(ny, nx)
    for array in (contact, pressure, separation):
        array.setflags(write=False)
    at_edge = bool(contact[0].any() or contact[-1].any() or contact[:, 0].any() or contact[:, -1].any())
    converged = status == _STATUS_CONVERGED
    n_contact = int(np.count_nonzero(contact))
    warm = (key, chol) if converged and n_contact > 0 and chol.shape[0] == n_contact else None
    result = NormalContactResult(
        pressure=pressure,
        contact=contact,
        force=float(pressure.sum() * area),
        approach=float(delta),
        separation=separation,
        iterations=int(iterations),
        converged=converged,
        at_edge=at_edge,
        max_gap_violation=float(max(0.0, -separation.min())),
        min_pressure=float(pressure.min()),
        element_size=element_size,
        _warm=warm,
    )
    if raise_on_failure:
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
