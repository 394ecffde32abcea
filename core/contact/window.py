"""3D non-Hertzian normal contact of two elastic half-spaces (paper section 2.3.2, eqs. 8-11).

The window is ``ny x nx`` square elements of side ``element_size`` (rows across the rail, columns along
it); a solve takes the undeformed gap h (m, positive where the surfaces are apart: for the paper's crossed
cylinders (x^2 + y^2) / (2 R) - r) and finds the pressure p >= 0 with the deformed gap d = h - delta + C p
>= 0, d p = 0 (eqs. 8, 10, 11) under a load F = A_e sum(p) (eq. 9) or with delta = delta_known - c F.
Sign convention: ``wheelrail.core.contact``.

How
---
:class:`HalfSpaceWindow` holds one window's geometry, material and influence kernel (``contact.influence``,
eq. 8), the solver's settings and its warm state; each solve fills an
:class:`~wheelrail.core.contact.active_set.ActiveSetSolver` (the one active-set method, also the ``3d``
model's) from that state and solves ``solve(gap, load=...)`` or ``solve_coupled(gap, approach_known=...,
compliance=...)``. A window warm-starts from the contact set and Cholesky factor of its last solve that
carried load (a lift-off leaves it as it was); the answer does not depend on the start beyond round-off.
:func:`solve_normal_contact` and :func:`solve_coupled_contact` are the one-off forms on a fresh window, their
``initial`` (a previous result or a contact mask) the warm start.

Failures are reported: by default a solve that does not converge within ``max_iterations`` or whose
contact set reaches the window edge raises :class:`WheelrailError`; with ``raise_on_failure=False``
the result is returned with ``converged=False`` / ``at_edge=True`` and the caller must check them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from wheelrail.core.contact.active_set import (
    CAUTIOUS_AFTER,
    STEP_CONVERGED,
    STEP_NOT_DEFINITE,
    ActiveSetSolver,
    cached_grid,
    cold_start_set,
    displacement,
)
from wheelrail.core.contact.influence import influence_kernel
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import integer as _integer
from wheelrail.core.inputs.checks import positive as _positive
from wheelrail.core.parameters import ContactParameters, reduced_modulus

__all__ = [
    "HalfSpaceWindow",
    "NormalContactResult",
    "influence_kernel",
    "solve_coupled_contact",
    "solve_normal_contact",
]


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
        Deformed gap d = h - delta + C p, eq. (11), m (zero, up to round-off, where in contact).

    See Also
    --------
    HalfSpaceWindow.solve, solve_normal_contact, solve_coupled_contact : the solves that return it.
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
    separation: np.ndarray
    # (window key, final set in factor order, (its Cholesky factor, z = U^-T 1)) of a converged solve, for
    # the ``initial=`` of the one-off functions; a HalfSpaceWindow keeps its own warm state
    _warm: object = field(default=None, repr=False)

    @property
    def contact_area(self) -> float:
        """Area of the contact elements (p > 0) times the element area, m^2: a staircase around the patch, above
        Hertz's pi a b on a smooth gap (2.3-8.5 % at 65 kN on the 1 mm grid; see ``RunResult.contact_area``)."""
        return float(np.count_nonzero(self.contact)) * self.element_size**2


class HalfSpaceWindow:
    """A contact window on two elastic half-spaces and its solver: eqs. (8)-(11) with a warm start.

    Holds the model (window shape, element size, material and the influence kernel of eq. 8) and the
    active-set solver's settings and warm state. Each solve starts from the contact set (and its Cholesky
    factor) of the last solve of this window whose force was > 0 (module docstring); :meth:`reset`
    forgets it. A solve that raises changes nothing.

    Parameters
    ----------
    shape : (int, int)
        Window size (ny, nx) in elements, each >= 2 (rows across the rail, columns along it).
    element_size : float
        Side of the square elements, m (1e-3 in the paper).
    contact : ContactParameters, optional
        The material: E (Pa) and nu of both bodies (same material), E* = E / (2 (1 - nu^2)); default
        ``ContactParameters()`` (steel).
    tolerance : float
        Relative tolerance of the contact conditions: pressures down to ``-tolerance * max(p)`` and gaps
        down to ``-tolerance * (delta - min(h))`` count as zero.
    max_iterations : int
        Maximum number of active-set iterations (linear solves) per solve.

    Raises
    ------
    WheelrailError
        If the shape is not two integers of at least 2, the element size, tolerance or iteration count not
        positive, or ``contact`` not ContactParameters.

    See Also
    --------
    solve_normal_contact, solve_coupled_contact : one-off solves on a fresh window.
    wheelrail.core.contact.halfspace_model.HalfSpaceModel : the ``3d`` model, which steps the same solver.

    Notes
    -----
    The solver is :class:`~wheelrail.core.contact.active_set.ActiveSetSolver` (module docstring of
    ``contact.active_set``); a window fills one from its warm state for each solve.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, section 2.3.2, eqs. (8)-(11).
    J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer, 1990 (the active set).

    Examples
    --------
    The paper's crossed cylinders (R = 0.39 m) on 1 mm elements, then two steps of a rolling run:

    >>> import numpy as np
    >>> from wheelrail.core.contact import HalfSpaceWindow
    >>> c = (np.arange(24) - 11.5) * 1e-3
    >>> gap = (c[:, None] ** 2 + c[None, :] ** 2) / (2 * 0.39)
    >>> window = HalfSpaceWindow(gap.shape, 1e-3)
    >>> static = window.solve(gap, load=65e3)
    >>> round(static.approach * 1e6, 1), int(static.contact.sum())   # um (Hertz: 77.07), elements
    (77.1, 96)
    >>> for known in (80e-6, 82e-6):
    ...     step = window.solve_coupled(gap, approach_known=known, compliance=1e-9)
    >>> bool(abs(step.approach - (82e-6 - 1e-9 * step.force)) < 1e-15)
    True
    """

    def __init__(
        self,
        shape: tuple[int, int],
        element_size: float,
        *,
        contact: ContactParameters | None = None,
        tolerance: float = 1e-9,
        max_iterations: int = 100,
    ) -> None:
        where = "HalfSpaceWindow"
        try:
            ny, nx = (int(shape[0]), int(shape[1]))
            if len(shape) != 2:
                raise ValueError
        except (TypeError, ValueError, IndexError):
            raise WheelrailError(f"{where}: shape must be two integers (ny, nx), got {shape!r}") from None
        if ny < 2 or nx < 2:
            raise WheelrailError(f"{where}: the window must be at least 2 x 2 elements, got shape {shape!r}")
        self._configure(where, (ny, nx), element_size, contact, tolerance, max_iterations)

    def _configure(self, where, shape, element_size, contact, tolerance, max_iterations):
        element_size = _positive(where, "element_size", element_size, "m")
        contact = ContactParameters() if contact is None else contact
        if not isinstance(contact, ContactParameters):
            raise WheelrailError(f"{where}: contact must be ContactParameters, got {type(contact).__name__}")
        self._tolerance = _positive(where, "tolerance", tolerance, "relative")
        self._max_iterations = _integer(f"{where}: max_iterations", max_iterations, 1)
        self._key = (shape[0], shape[1], element_size, float(contact.youngs_modulus), float(contact.poisson_ratio))
        self._kernel = influence_kernel(shape, element_size, contact)
        self._warm = None  # (contact set in factor order, (its upper Cholesky factor, z) or None)
        self._last = None

    @classmethod
    def _for_gap(cls, where, gap, element_size, contact, tolerance, max_iterations):
        """A fresh window for the checked ``gap``, its errors named after the one-off function ``where``."""
        window = cls.__new__(cls)
        window._configure(where, gap.shape, element_size, contact, tolerance, max_iterations)
        return window

    # model and settings (read-only) ------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int]:
        """(ny, nx), elements."""
        return self._key[0], self._key[1]

    @property
    def element_size(self) -> float:
        """Side of the square elements, m."""
        return self._key[2]

    @property
    def youngs_modulus(self) -> float:
        """E of both bodies, Pa."""
        return self._key[3]

    @property
    def poisson_ratio(self) -> float:
        """nu of both bodies."""
        return self._key[4]

    @property
    def tolerance(self) -> float:
        """Relative tolerance of the contact conditions (10)."""
        return self._tolerance

    @property
    def max_iterations(self) -> int:
        """Maximum active-set iterations per solve."""
        return self._max_iterations

    @property
    def kernel(self) -> np.ndarray:
        """Influence kernel of eq. (8), m/Pa, read-only (see :func:`influence_kernel`)."""
        return self._kernel

    @property
    def last(self) -> NormalContactResult | None:
        """The result of the last solve that returned (None before the first or after :meth:`reset`)."""
        return self._last

    @property
    def warm(self) -> bool:
        """True when the next solve starts from a previous contact set (else from the Hertz-like guess)."""
        return self._warm is not None

    def reset(self) -> None:
        """Forget the warm state and the last result: the next solve starts cold."""
        self._warm = None
        self._last = None

    def start_from(self, contact) -> None:
        """Make ``contact`` (bool mask of the window's shape, e.g. a set shifted by the caller) the warm state.

        The next solve starts from that set and factors it afresh, as ``initial=mask`` of the one-off
        functions does.
        """
        self._warm = _initial_set("HalfSpaceWindow.start_from", np.asarray(contact), self.shape, self._key, "contact")

    # solves ------------------------------------------------------------------------------------------
    def solve(self, gap, *, load: float, raise_on_failure: bool = True) -> NormalContactResult:
        """Load-controlled normal contact, eqs. (8)-(11): p >= 0 and delta with A_e sum(p) = load.

        Parameters
        ----------
        gap : array_like, shape (ny, nx)
            Undeformed gap h at the element centres, m (module docstring: for the paper's crossed
            cylinders ``(x^2 + y^2) / (2 R) - r`` with r = r_W - r_R positive downwards).
        load : float
            Total normal force F_n, N (> 0).
        raise_on_failure : bool
            If True (default) non-convergence or contact at the window edge raises
            :class:`WheelrailError`; if False the result is returned and ``converged`` / ``at_edge`` must
            be checked.

        Returns
        -------
        NormalContactResult
        """
        where = "HalfSpaceWindow.solve"
        load = _positive(where, "load", load, "N")
        gap = self._checked_gap(where, gap)
        return self._solve(where, gap, (False, load, 0.0), raise_on_failure, self._warm)

    def solve_coupled(
        self, gap, *, approach_known: float, compliance: float, raise_on_failure: bool = True
    ) -> NormalContactResult:
        """Normal contact coupled to the wheel and rail dynamics (eqs. 1, 2, 11): one solve per time step.

        The approach follows from the force as in the time-stepping loop:
        ``delta = approach_known - compliance * F`` with F = A_e sum(p), where ``approach_known`` (m) is the
        part of xi_W - xi_R known from the history and ``compliance`` = g_W(0) + g_R(0) >= 0 (m/N) the
        instantaneous wheel + rail compliance. If the surfaces do not touch at ``approach_known`` the
        result has F = 0 and no contact elements (loss of contact is physics, not an error).

        Parameters
        ----------
        gap : array_like, shape (ny, nx)
            Undeformed gap h, m (see :meth:`solve`).
        approach_known : float
            delta_known, m (positive = towards each other).
        compliance : float
            c >= 0, m/N.
        raise_on_failure : bool
            As in :meth:`solve`.

        Returns
        -------
        NormalContactResult
            ``approach`` is the consistent delta = approach_known - compliance * force.
        """
        where = "HalfSpaceWindow.solve_coupled"
        approach_known, compliance = _coupling(where, approach_known, compliance)
        gap = self._checked_gap(where, gap)
        return self._solve(where, gap, (True, approach_known, compliance), raise_on_failure, self._warm)

    def _checked_gap(self, where: str, gap) -> np.ndarray:
        gap = _check_gap(where, gap)
        if gap.shape != self.shape:
            raise WheelrailError(f"{where}: gap must have the window's shape {self.shape}, got {gap.shape}")
        return gap

    def _solve(self, where, gap, law, raise_on_failure, start) -> NormalContactResult:
        """Solve with ``law = (coupled, target, compliance)`` from ``start = (set, factor)`` or cold (None)."""
        coupled, target, compliance = law
        ny, nx, element_size = self._key[:3]
        flat = gap.ravel()
        area = element_size**2
        order, factor = start if start is not None else (None, None)
        if order is None:
            modulus = reduced_modulus(self.youngs_modulus, self.poisson_ratio)
            order = np.flatnonzero(cold_start_set(flat, area, modulus, coupled, float(target), float(compliance)))
        solver = ActiveSetSolver(
            cached_grid(self._key, self._kernel),
            order,
            (self._tolerance, self._max_iterations, area, self._cautious),
            factor=factor,
        )
        solver.gap[:] = flat
        status, force, delta, iterations = solver.solve(coupled, float(target), float(compliance))
        pressure = solver.pressure if force > 0.0 else np.zeros(ny * nx)
        contact = np.zeros(ny * nx, dtype=bool)
        if force > 0.0:
            contact[solver.contact_set()] = True
        separation = flat - delta + displacement(cached_grid(self._key, self._kernel), pressure)
        contact, pressure, separation = (a.reshape(ny, nx) for a in (contact, pressure, separation))
        for array in (contact, pressure, separation):
            array.setflags(write=False)
        converged = status == STEP_CONVERGED
        factor = solver.factor() if converged and force > 0.0 else None
        result = NormalContactResult(
            pressure=pressure,
            contact=contact,
            force=force,
            approach=delta,
            iterations=iterations,
            converged=converged,
            at_edge=bool(contact[[0, -1], :].any() or contact[:, [0, -1]].any()),
            max_gap_violation=max(0.0, -float(separation.min())),
            min_pressure=float(pressure.min()),
            element_size=element_size,
            separation=separation,
            _warm=(self._key, solver.contact_set(), factor) if factor is not None else None,
        )
        if raise_on_failure:
            self._raise_failure(where, result, status)
        if result.force > 0:
            # the new warm state: this set and its factor, or (not converged) its contact set alone
            self._warm = (result._warm[1], factor) if factor is not None else (np.flatnonzero(contact), None)
        self._last = result
        return result

    _cautious = CAUTIOUS_AFTER  # iterations after which one element at a time changes (tests: 0)

    def _raise_failure(self, where: str, result: NormalContactResult, status: int) -> None:
        iterations = result.iterations
        if status == STEP_NOT_DEFINITE:
            raise WheelrailError(
                f"{where}: the influence matrix of the contact set lost positive definiteness in round-off "
                f"after {iterations} iterations; the solve failed"
            )
        if not result.converged:
            raise WheelrailError(
                f"{where}: active-set solver did not converge in {iterations} iterations "
                f"(max_iterations={self._max_iterations}); the gap may be ill-posed or the tolerance too tight"
            )
        if result.at_edge:
            ny, nx, element_size = self._key[:3]
            raise WheelrailError(
                f"{where}: contact reaches the edge of the {ny} x {nx} window "
                f"({ny * element_size * 1e3:.3g} x {nx * element_size * 1e3:.3g} mm); "
                "the window is too small for the load, use a larger window"
            )


# ---------------------------------------------------------------------------------------------------
# Input checks and the cold start
# ---------------------------------------------------------------------------------------------------


def _check_gap(where: str, gap) -> np.ndarray:
    try:
        array = np.asarray(gap, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: gap must be a 2D array of numbers in m") from None
    if array.ndim != 2:
        raise WheelrailError(f"{where}: gap must be a 2D array (ny, nx) in m, got shape {array.shape}")
    if array.shape[0] < 2 or array.shape[1] < 2:
        raise WheelrailError(f"{where}: gap window must be at least 2 x 2 elements, got shape {array.shape}")
    if not np.isfinite(array).all():  # the array method: no dispatch through np.all
        bad = np.argwhere(~np.isfinite(array))[0]
        raise WheelrailError(
            f"{where}: gap must be finite (m), got {array[tuple(bad)]} at element {tuple(int(i) for i in bad)}"
        )
    return np.ascontiguousarray(array)


def _coupling(where: str, approach_known, compliance) -> tuple[float, float]:
    """delta_known (m, finite) and the compliance c (m/N, finite, >= 0) of the coupled form."""
    try:
        approach_known = float(approach_known)
        compliance = float(compliance)
    except (TypeError, ValueError):
        raise WheelrailError(f"{where}: approach_known (m) and compliance (m/N) must be numbers") from None
    if not math.isfinite(approach_known):
        raise WheelrailError(f"{where}: approach_known must be finite (m), got {approach_known!r}")
    if not math.isfinite(compliance) or compliance < 0.0:
        raise WheelrailError(f"{where}: compliance must be finite and >= 0 (m/N), got {compliance!r}")
    return approach_known, compliance


def _initial_set(where: str, initial, shape, key, name: str = "initial"):
    """Warm start (set, factor): the contact set (element indices) and, for a result of the same problem
    class (shape, element size, material), its Cholesky factor in the same order; None for a cold start."""
    if initial is None:
        return None
    if isinstance(initial, NormalContactResult) and initial._warm is not None and initial._warm[0] == key:
        return initial._warm[1], initial._warm[2]
    mask = initial.contact if isinstance(initial, NormalContactResult) else initial
    mask = np.asarray(mask)
    if mask.shape != shape or mask.dtype != bool:
        raise WheelrailError(
            f"{where}: {name} must be a NormalContactResult or bool mask of shape {shape}, "
            f"got {type(initial).__name__} of shape {mask.shape}"
        )
    return np.flatnonzero(mask), None


# ---------------------------------------------------------------------------------------------------
# One-off solves
# ---------------------------------------------------------------------------------------------------


def solve_normal_contact(
    gap,
    element_size: float,
    *,
    load: float,
    initial: NormalContactResult | np.ndarray | None = None,
    contact: ContactParameters | None = None,
    tolerance: float = 1e-9,
    max_iterations: int = 100,
    raise_on_failure: bool = True,
) -> NormalContactResult:
    """Load-controlled normal contact of two elastic half-spaces, eqs. (8)-(11), as a one-off solve.

    Finds the pressure p >= 0 and the approach delta such that the deformed gap d = h - delta + C p
    is >= 0, zero where p > 0 (eq. 10), and A_e sum(p) equals the load (eq. 9). The same as
    :meth:`HalfSpaceWindow.solve` on a fresh window, warm-started from ``initial``.

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
    contact, tolerance, max_iterations
        As in :class:`HalfSpaceWindow`.
    raise_on_failure : bool
        If True (default) non-convergence or contact at the window edge raises :class:`WheelrailError`;
        if False the result is returned and ``converged`` / ``at_edge`` must be checked.

    Returns
    -------
    NormalContactResult

    Raises
    ------
    WheelrailError
        On bad input; unless ``raise_on_failure`` is False, also when the solve does not converge or the
        contact reaches the window's edge.

    See Also
    --------
    HalfSpaceWindow.solve : the same on a window that keeps its warm state.
    solve_coupled_contact : the approach coupled to the wheel and rail instead of a load.

    Notes
    -----
    An exact active-set method (module docstring of ``contact.active_set``): the answer satisfies eq. (10)
    to ``tolerance`` relative, whatever the start.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eqs. (8)-(11).

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.contact import solve_normal_contact
    >>> c = (np.arange(24) - 11.5) * 1e-3
    >>> gap = (c[:, None] ** 2 + c[None, :] ** 2) / (2 * 0.39)   # the paper's crossed cylinders, m
    >>> result = solve_normal_contact(gap, 1e-3, load=65e3)
    >>> round(result.pressure.max() / 1e6), round(result.force)   # MPa (Hertz p0: 1033), N
    (1027, 65000)
    """
    where = "solve_normal_contact"
    load = _positive(where, "load", load, "N")
    gap = _check_gap(where, gap)
    window = HalfSpaceWindow._for_gap(where, gap, element_size, contact, tolerance, max_iterations)
    start = _initial_set(where, initial, gap.shape, window._key)
    return window._solve(where, gap, (False, load, 0.0), raise_on_failure, start)


def solve_coupled_contact(
    gap,
    element_size: float,
    *,
    approach_known: float,
    compliance: float,
    initial: NormalContactResult | np.ndarray | None = None,
    contact: ContactParameters | None = None,
    tolerance: float = 1e-9,
    max_iterations: int = 100,
    raise_on_failure: bool = True,
) -> NormalContactResult:
    """Normal contact coupled to the wheel and rail dynamics, as a one-off solve.

    The approach follows from the force as in the time-stepping loop (eqs. 1, 2, 11):

        delta = approach_known - compliance * F,    F = A_e sum(p),

    where ``approach_known`` is the part of xi_W - xi_R known from the history (the convolution with earlier
    forces, the preload response and the static position) and ``compliance`` = g_W(0) + g_R(0) >= 0 the
    instantaneous wheel + rail compliance. Contact may be lost: if the surfaces do not touch at
    ``approach_known`` the result has F = 0 and no contact elements (this is physics, not an error).
    The same as :meth:`HalfSpaceWindow.solve_coupled` on a fresh window, warm-started from ``initial``.

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
    initial, contact, tolerance, max_iterations, raise_on_failure
        As in :func:`solve_normal_contact`.

    Returns
    -------
    NormalContactResult
        ``approach`` is the consistent delta = approach_known - compliance * force.

    Raises
    ------
    WheelrailError
        As :func:`solve_normal_contact`.

    See Also
    --------
    HalfSpaceWindow.solve_coupled : the same on a window that keeps its warm state.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eqs. (1), (2), (8)-(11).

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.contact import solve_coupled_contact
    >>> c = (np.arange(24) - 11.5) * 1e-3
    >>> gap = (c[:, None] ** 2 + c[None, :] ** 2) / (2 * 0.39)
    >>> step = solve_coupled_contact(gap, 1e-3, approach_known=80e-6, compliance=1e-9)
    >>> round(step.force / 1e3, 1), round(step.approach * 1e6, 2)   # kN, um
    (32.0, 48.02)
    >>> solve_coupled_contact(gap, 1e-3, approach_known=-1e-6, compliance=1e-9).force   # lifted off
    0.0
    """
    where = "solve_coupled_contact"
    approach_known, compliance = _coupling(where, approach_known, compliance)
    gap = _check_gap(where, gap)
    window = HalfSpaceWindow._for_gap(where, gap, element_size, contact, tolerance, max_iterations)
    start = _initial_set(where, initial, gap.shape, window._key)
    return window._solve(where, gap, (True, approach_known, compliance), raise_on_failure, start)
