"""The ``3d`` law of one window tabulated, for the run-in: F(delta) exact where the run-in's end needs it.

During the run-in the window stays on the roughness under step 0 (faded in), so the discretised 3D law is a
function of the approach (and the fade) alone. On a fixed contact set it is exactly linear in the approach
(``active_set._pressure_on_set``: p_A = C_AA^-1 (delta 1 - h_A)), with a kink where the set changes:
:func:`tabulate_law` finds it with the 3D solver itself (displacement-controlled solves with their slopes),
:func:`run_in_table` builds the run-in's law from two such tables, and the compiled :data:`run_in_chunk`
steps the run-in on it (``run.InteractionRun``; ``docs/physics.md``, "How a step is solved").
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from wheelrail.core.contact import active_set, capacitance, cholesky, deformed_gap, halfspace_model
from wheelrail.core.contact.active_set import STEP_AT_EDGE, STEP_CONVERGED, STEP_NEEDS_ROOM, ActiveSetSolver
from wheelrail.core.contact.halfspace_model import halfspace_step
from wheelrail.core.engine import kernels
from wheelrail.core.engine.compiled import sources_stamp
from wheelrail.core.engine.kernels import commit_force, known_approach
from wheelrail.core.errors import WheelrailError

__all__ = ["run_in_chunk", "run_in_table", "step_gap", "step_law", "tabulate_law", "warm_start"]

# 3d's run-in law (run_in_table), in units of the static approach: T_0 and T_1 solved every 8 %, T_1 also every
# 4 % where F is within RUN_IN_TABLE_BAND x P and again at its kinks there (exact), both up to RUN_IN_TABLE_FORCE
# x P and extended linearly beyond (the run-in's F stays within 0.79-1.05 P at 100-300 km/h on the corrugated rail)
RUN_IN_TABLE_SPACING = (0.08, (0.08, 0.04))
RUN_IN_TABLE_BAND = (0.8, 1.25)
RUN_IN_TABLE_FORCE = 1.3


def _define_sweep(stamp):
    @njit(cache=True)
    def sweep(s, deltas, force_stop, law, out):
        """Displacement-controlled solves (compliance 0: delta = the given approach) of step s's gap at the
        approaches ``deltas`` (m, ascending), each warm-started from the last, until F reaches ``force_stop``.
        ``out`` = (F, dF/ddelta, elements in the set, sum of their indices) per approach.

        On a fixed set F = A_e (delta z.z - z.y) (:func:`_pressure_on_set`): linear in delta, slope A_e z.z.
        Returns (points solved, status of the solve that stopped it or ``STEP_CONVERGED``).
        """
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called (wheelrail.core.engine.compiled)
        forces, slopes, sizes, sums = out
        state = law[1]
        order, z, counts = state[0], state[2], state[3]
        area = law[4][2]
        for k in range(deltas.size):
            status, force, _, _ = halfspace_step(s, deltas[k], 0.0, law)
            if status != STEP_CONVERGED and status != STEP_AT_EDGE:
                return k, status
            m = counts[0] if force > 0.0 else 0
            zz = 0.0
            total = 0
            for a in range(m):
                zz += z[a] * z[a]
                total += order[a]
            forces[k], slopes[k], sizes[k], sums[k] = force, area * zz, m, total
            if force >= force_stop:
                return k + 1, STEP_CONVERGED
        return deltas.size, STEP_CONVERGED

    return sweep


_sweep = _define_sweep(sources_stamp(halfspace_model, active_set, capacitance, cholesky, deformed_gap))


def _solve_at(steps: ActiveSetSolver, s: int, deltas: np.ndarray, force_stop: float = math.inf):
    """:func:`_sweep` from Python (the factor's buffer grown where the set outgrew it): the approaches
    solved and (F, slope, set size, set index sum) at them."""
    n = deltas.size
    out = (np.empty(n), np.empty(n), np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64))
    done = 0
    while done < n:
        count, status = _sweep(s, deltas[done:], force_stop, steps.law, tuple(a[done:] for a in out))
        done += count
        if status == STEP_NEEDS_ROOM:
            steps.grow()  # repeat that point with a larger factor buffer
            continue
        if status != STEP_CONVERGED:
            raise WheelrailError(f"3d: the contact solve of the run-in's law did not converge (status {status})")
        break
    return deltas[:done], *(a[:done] for a in out)


def warm_start(steps: ActiveSetSolver, s: int, approach: float) -> None:
    """Leave the warm state (set and factor) at the solution of step s's gap at this approach (m): the state
    the next step starts from."""
    _solve_at(steps, s, np.array([approach]))


def step_gap(steps: ActiveSetSolver, s: int) -> np.ndarray:
    """The undeformed gap of step s's window (ny, nx), m (as :func:`halfspace_step` builds it)."""
    base, lines, start_index, ramp, half_x, _ = steps.track
    i = int(start_index[s])
    return base.reshape(-1, 2 * half_x + 1) - ramp[s] * lines[:, i - half_x : i + half_x + 1]


def tabulate_law(
    steps: ActiveSetSolver,
    s: int,
    spacing: tuple[float, float],
    band: tuple[float, float] | None,
    force_stop: float,
    start: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """The ``3d`` law on step s's gap as a function of the approach alone: breakpoints (delta, F) of the
    piecewise-linear F(delta), m and N, from delta = min h (F = 0) until F >= ``force_stop`` (N).

    On a fixed contact set the discretised law is exactly linear in delta (:func:`_sweep`); it has a kink
    where the set changes. The law is solved with its slope every ``spacing[0]`` (m), and every ``spacing[1]``
    where F is within ``band`` (N, optional); where the set differs between two neighbouring solves, a kink is
    put where their two lines meet: exact for one change of set between them (F is continuous). Within the
    band, where the sets differ by more than one element, the law is solved again there
    (:func:`_resolve_kinks`), so the table is the law there to the solver's tolerance; elsewhere it is off by
    at most (slope change) x (spacing) / 4. ``start`` (m): the first solve this far beyond first contact (the
    table then holds nothing below it). Leaves the warm state at the last solve.
    """
    first = float(step_gap(steps, s).min()) + start
    coarse, fine = spacing
    points = _solve_at(steps, s, first + coarse * np.arange(4096), force_stop)
    if band is not None:
        lo, hi = np.interp(band, points[1], points[0])
        points = _merged(points, _solve_at(steps, s, np.arange(lo, hi + fine, fine)))
        points = _resolve_kinks(steps, s, points, (lo, hi), 1e-9 * force_stop)
    delta, force, slope, size, total = points
    x = _meeting_points(points)
    inside = ((size[1:] != size[:-1]) | (total[1:] != total[:-1])) & (x > delta[:-1]) & (x < delta[1:])
    kink_x = x[inside]
    kink_f = force[:-1][inside] + slope[:-1][inside] * (kink_x - delta[:-1][inside])
    order = np.argsort(np.concatenate([delta, kink_x]), kind="stable")
    return np.concatenate([delta, kink_x])[order], np.concatenate([force, kink_f])[order]


def _merged(points, more):
    """Two sets of solves (delta, F, slope, set size, set index sum) as one, sorted by delta."""
    joined = tuple(np.concatenate(pair) for pair in zip(points, more, strict=True))
    order = np.argsort(joined[0], kind="stable")
    return tuple(a[order] for a in joined)


def _meeting_points(points) -> np.ndarray:
    """Where the lines F_k + s_k (x - delta_k) of neighbouring solves meet (nan where parallel)."""
    delta, force, slope = points[:3]
    with np.errstate(divide="ignore", invalid="ignore"):
        return (force[1:] - force[:-1] + slope[:-1] * delta[:-1] - slope[1:] * delta[1:]) / (slope[:-1] - slope[1:])


def _resolve_kinks(steps: ActiveSetSolver, s: int, points, span: tuple[float, float], tolerance: float, rounds=8):
    """Solve again where neighbouring solves within ``span`` (m) have sets that differ by more than one
    element (several kinks may lie between): at the point where their lines meet. If the law is on both
    lines there (within ``tolerance``, N), that point is the only kink (several elements joining at once, as
    on a symmetric gap); else it splits the interval, which is looked at again, up to ``rounds`` times."""
    exact = np.zeros(points[0].size, dtype=bool)  # the interval to the right of a solve holds at most one kink
    for _ in range(rounds):
        delta, force, slope, size, total = points
        x = _meeting_points(points)
        several = (np.abs(size[1:] - size[:-1]) != 1) & (total[1:] != total[:-1]) & ~exact[:-1]
        several &= (x > delta[:-1]) & (x < delta[1:]) & (delta[1:] >= span[0]) & (delta[:-1] <= span[1])
        if not several.any():
            break
        at = np.flatnonzero(several)
        more = _solve_at(steps, s, x[at])
        on_lines = np.abs(more[1] - (force[at] + slope[at] * (x[at] - delta[at]))) <= tolerance
        exact[at[on_lines]] = True
        points = _merged(points, more)
        exact = np.concatenate([exact, on_lines])[np.argsort(np.concatenate([delta, x[at]]), kind="stable")]
    return points


def step_law(
    steps: ActiveSetSolver, s: int, preload: float, static: float, band=RUN_IN_TABLE_BAND, start: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """The ``3d`` law on step s's gap, tabulated exactly within ``band`` x P (:func:`tabulate_law`; the
    default: T_1 of :func:`run_in_table`; ``steady_start`` solves the run's steady state on a narrower band):
    (delta, F), m and N, from ``start`` x ``static`` beyond first contact up to ``RUN_IN_TABLE_FORCE`` x P
    (another band: 0.05 P beyond it). ``static``: the static approach under the preload (m; the spacings' scale)."""
    rough = RUN_IN_TABLE_SPACING[1]
    stop = (RUN_IN_TABLE_FORCE if band == RUN_IN_TABLE_BAND else band[1] + 0.05) * preload
    spacing = (rough[0] * static, rough[1] * static)
    return tabulate_law(steps, s, spacing, (band[0] * preload, band[1] * preload), stop, start * static)


def run_in_table(steps: ActiveSetSolver, n_run_in: int, preload: float, static: float) -> tuple:
    """The run-in's law of the ``3d`` model, tabulated: during the run-in the window stays on the roughness
    under step 0, faded in (gap h_0 - w r, w from 0 to 1), so the 3D law is F(delta, w). Tabulated exactly
    (:func:`tabulate_law`) at w = 0 (T_0, smooth) and w = 1 (T_1, the first recorded step's
    gap) up to ``RUN_IN_TABLE_FORCE`` x P; in between (the fade's first half of the run-in)
    (1 - w) T_0 + w T_1 stands for it (its error decays before the record). ``static``: the static approach
    under the preload (m; the spacing's scale). Returns (breakpoints, T_0, T_1 at them): the table that
    :func:`_tabulated_force` takes."""
    smooth = RUN_IN_TABLE_SPACING[0]
    stop = RUN_IN_TABLE_FORCE * preload
    tables = (
        tabulate_law(steps, 0, (smooth * static, smooth * static), None, stop),
        step_law(steps, n_run_in, preload, static),
    )
    far = max(delta[-1] for delta, _ in tables) + 1.0  # m: the last segments extended (beyond any approach)
    grid = np.union1d(np.concatenate([delta for delta, _ in tables]), [far])
    values = []
    for delta, force in tables:
        slope = (force[-1] - force[-2]) / (delta[-1] - delta[-2])
        values.append(np.interp(grid, [*delta, far], [*force, force[-1] + slope * (far - delta[-1])], left=0.0))
    return grid, values[0], values[1]


@njit(cache=True, inline="always")
def _tabulated_force(table, weight, approach_known, compliance, segment):
    """F solving F = T(delta_known - c F) for the piecewise-linear law T = (1 - w) T_0 + w T_1 on the breakpoints
    ``grid`` (``table`` = (grid, T_0, T_1) at them; T = 0 at the first, the last segment extended).

    H(delta) = delta + c T(delta) increases strictly, so the segment with H(lo) <= delta_known <= H(hi) is
    found by walking from the last step's (``segment[0]``, a few moves at most) and the linear equation
    on it solved exactly. Returns (F, delta)."""
    grid, smooth, rough = table
    if approach_known <= grid[0]:
        return 0.0, approach_known
    i = segment[0]
    while True:
        lo, hi = grid[i], grid[i + 1]
        low = (1.0 - weight) * smooth[i] + weight * rough[i]
        high = (1.0 - weight) * smooth[i + 1] + weight * rough[i + 1]
        if approach_known < lo + compliance * low and i > 0:
            i -= 1
        elif approach_known > hi + compliance * high and i < grid.size - 2:
            i += 1
        else:
            break
    segment[0] = i
    slope = (high - low) / (hi - lo)
    delta = lo + (approach_known - lo - compliance * low) / (1.0 + compliance * slope)
    return low + slope * (delta - lo), delta


def _define_run_in_chunk(stamp):
    @njit(cache=True)
    def run_in_chunk(j0, j1, track, wheel, constants, table, ramp, segment, out):
        """The run-in of the ``3d`` law over history indices j0..j1-1 on its tabulated law
        (:func:`_tabulated_force` with w = the step's fade-in factor). ``constants`` = (preload, xi_w0, n_hist);
        ``out`` = (xi_wheel, xi_rail). Returns the approach of the last step, m."""
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called (wheelrail.core.engine.compiled)
        preload, xi_w0, offset = constants
        xi_wheel, xi_rail = out
        delta = 0.0
        for j in range(j0, j1):
            delta_known, c, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
            s = j - offset
            f, delta = _tabulated_force(table, ramp[s], delta_known, c, segment)
            xi_wheel[s], xi_rail[s] = commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0)
        return delta

    return run_in_chunk


run_in_chunk = _define_run_in_chunk(sources_stamp(kernels))
