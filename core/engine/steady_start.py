"""The start of a run from the moving load's steady state (``run.InteractionRun``, ``history``).

During the run-in the wheel stays on the gap of step 0 (the roughness under it, not faded in: ``history``) while
the track moves under it: a wheel at constant speed on a periodically supported track, whose steady state is
periodic with one sleeper bay, n = L_S / dx steps (a whole number of steps: :func:`bay_steps`). With a force
periodic in n steps, the loop's own equations are linear maps of the bay's n forces:

* eq. 2, the rail: xi_R = A F, the moving Green's functions over the loop's lags with the source's position in
  the bay, the lags folded modulo n (each row of the moving Green's functions folded once, ``_fold_lags``);
* eq. 1, the wheel's exact discrete system: xi_W = xi_W0 - B (F - P), its impulse response summed over all
  periods in closed form with (I - Phi^n)^-1 (:func:`folded_wheel`);

and the model's own law on the gap of step 0 closes them: F = law(xi_W0 - B (F - P) - A F), n unknowns
(:func:`steady_state`: chord iterations preconditioned with the circulant part of A + B by FFT, with Anderson
mixing). :func:`fill_history` puts that force into the history the loop convolves, the rail's displacement it
causes and the wheel's state at the phase of the first step: a run started there stays on the steady state to
round-off (``tests/physics/test_run_in.py``); the recorded force is that of a 40 m run-in from the preload
within 0.0006 N at 100-300 km/h (``validation/run_in.py``), and 0 to 5 ms of run-in after it record the same.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from wheelrail.core.errors import WheelrailError

__all__ = [
    "SteadyState",
    "bay_steps",
    "fill_history",
    "folded_wheel",
    "start_state",
    "steady_state",
]

STEADY_TOLERANCE = 1e-11  # x P: the iterations stop when F - law(delta) is within this everywhere (round-off)
STEADY_ITERATIONS = 100  # the most iterations (measured: 11-15 at 5-400 km/h)
ANDERSON_DEPTH = 5  # differences kept by the Anderson mixing of the chord iterations
# where those stall, a deeper mixing and its most iterations (a tabulated 3d law on a track of 3000 MN/m pads and
# 300 kg sleepers, whose bay varies much more than C holds: 5 differences stalled at 1e-6 to 1e-3 P on a
# corrugated rail and took 112 iterations on a smooth one; 20 converged in 50 and 45, measured)
DEEP_ANDERSON = (20, 300)


@dataclass(frozen=True)
class SteadyState:
    """The periodic steady state over one bay: phase i is history index n_hist + i (mod n).

    force, approach: F (N) and delta (m) at each phase; state: the wheel's state after phase n - 1's step (the
    state the loop holds before the step of phase 0); iterations: the iterations taken."""

    force: np.ndarray
    approach: np.ndarray
    state: np.ndarray
    iterations: int


def bay_steps(sleeper_spacing: float, element_size: float) -> int | None:
    """Steps per sleeper bay, if the bay is a whole number of elements (within 1e-6 of one), else None."""
    ratio = sleeper_spacing / element_size
    n = int(round(ratio))
    return n if n >= 2 and abs(ratio - n) <= 1e-6 * ratio else None


@njit(cache=True, nogil=True)
def _fold_lags(weights, n):
    """Each row of the moving Green's functions with its lags summed modulo n: (rows, n)."""
    rows, lags = weights.shape
    out = np.zeros((rows, n))
    for r in range(rows):
        for start in range(0, lags, n):
            for d in range(min(n, lags - start)):
                out[r, d] += weights[r, start + d]
    return out


@njit(cache=True, fastmath=True, nogil=True)
def _circulant_part(folded, lo, hi, frac, wheel):
    """The circulant part of A + B (its mean along each wrapped diagonal d = i - k mod n): the mean over the
    source phases k of (1 - f_k) folded[lo_k, d] + f_k folded[hi_k, d], plus the wheel's wheel[d]."""
    n = wheel.size
    column = np.zeros(n)
    for k in range(n):
        f = frac[k]
        a, b = folded[lo[k]], folded[hi[k]]
        for d in range(n):
            column[d] += (1.0 - f) * a[d] + f * b[d]
    return column / n + wheel


@njit(cache=True, fastmath=True, nogil=True)
def _history_tail(weights, lo, hi, frac, force, out):
    """out[t] (t = 0..lags-1): the rail's displacement at history index n_hist + t due to the periodic force
    ``force`` (phase k at the indices n_hist + k - q n, q >= 1) before n_hist: eq. 2 as ``scatter_history``
    scatters it, row by row of the moving Green's functions: the row's lags summed over the periods
    (tail[u + n] = sum_q>=1 weights[r, u + q n], suffix sums of stride n), then added for each phase whose
    position reads that row (weight (1 - frac) F below, frac F above). Each row is read once."""
    rows, lags = weights.shape
    n = force.size
    first = np.zeros(rows + 1, dtype=np.int64)  # the (phase, weight) pairs of each row, by row
    for k in range(n):
        first[lo[k] + 1] += 1
        first[hi[k] + 1] += 1
    for r in range(rows):
        first[r + 1] += first[r]
    filled = first[:rows].copy()
    phase = np.empty(2 * n, dtype=np.int64)
    weight = np.empty(2 * n)
    for k in range(n):
        for r, w in ((lo[k], (1.0 - frac[k]) * force[k]), (hi[k], frac[k] * force[k])):
            phase[filled[r]], weight[filled[r]] = k, w
            filled[r] += 1
    tail = np.zeros(lags + 2 * n)
    for r in range(rows):
        if first[r + 1] == first[r]:
            continue
        row = weights[r]
        for idx in range(lags + n - 1, -1, -1):  # idx = u + n: the lag of q = 1
            tail[idx] = (row[idx] if idx < lags else 0.0) + tail[idx + n]
        for p in range(first[r], first[r + 1]):
            k, w = phase[p], weight[p]
            segment = tail[n - k : n - k + lags]
            for t in range(lags):  # a view from index 0: no negative-index wraparound, so it vectorises
                out[t] += w * segment[t]


@njit(cache=True, fastmath=True, nogil=True)
def _product(folded, lo, hi, frac, wheel, x):
    """(A + B) x from the folded rows (no dense matrix: the bay's rows, 256 x n, stay in cache across the
    iterations, where a dense n x n map would be streamed from memory every product):
    out[(k + d) mod n] += x_k ((1 - f_k) folded[lo_k, d] + f_k folded[hi_k, d] + wheel[d])."""
    n = x.size
    out = np.zeros(n)
    for k in range(n):
        a, b, c = (1.0 - frac[k]) * x[k], frac[k] * x[k], x[k]
        row_a, row_b = folded[lo[k]], folded[hi[k]]
        head = out[k:]
        for d in range(n - k):
            head[d] += a * row_a[d] + b * row_b[d] + c * wheel[d]
        tail_a, tail_b, tail_w = row_a[n - k :], row_b[n - k :], wheel[n - k :]
        for d in range(k):
            out[d] += a * tail_a[d] + b * tail_b[d] + c * tail_w[d]
    return out


@njit(cache=True, nogil=True)
def _powers(phi, first, n):
    """first, phi first, phi^2 first, ... (n + 1 of them). Loops, not ``phi @`` and slice assignments: those
    would make numba compile BLAS's matrix product and the shape checks' error messages for a 4 x 4 product."""
    size = first.size
    out = np.empty((n + 1, size))
    for i in range(size):
        out[0, i] = first[i]
    for d in range(1, n + 1):
        for i in range(size):
            total = 0.0
            for k in range(size):
                total += phi[i, k] * out[d - 1, k]
            out[d, i] = total
    return out


def folded_wheel(phi: np.ndarray, gamma0: np.ndarray, gamma1: np.ndarray, n: int) -> np.ndarray:
    """H (n, states): the wheel's state d steps after a unit force deviation, summed over every period (d, d + n,
    ...), from the loop's s_j = Phi s_j-1 + Gamma0 e_j-1 + Gamma1 e_j: h_0 = Gamma1, h_m = Phi^(m-1) v with
    v = Phi Gamma1 + Gamma0, so H_d = Phi^(d-1) (I - Phi^n)^-1 v (d >= 1) and H_0 = Gamma1 + H_n."""
    size = len(phi)
    periodic = np.linalg.solve(np.eye(size) - np.linalg.matrix_power(phi, n), phi @ gamma1 + gamma0)
    h = np.empty((n + 1, size))
    h[1:] = _powers(np.ascontiguousarray(phi), periodic, n - 1)
    h[0] = gamma1 + h[n]
    return h[:n]


def _circulant_inverse(column: np.ndarray, stiffness: float) -> np.ndarray:
    """The first column of (I + k C)^-1 for the circulant C of first column ``column`` (by FFT, once a start): the
    preconditioner's circulant, applied by :func:`_circular`."""
    n = column.size
    return np.fft.irfft(1.0 / (1.0 + stiffness * np.fft.rfft(column)), n)


@njit(cache=True, fastmath=True, nogil=True)
def _circular(kernel, x):
    """The circular convolution of ``kernel`` (a circulant's first column) with x: out[(k + d) mod n] +=
    x_k kernel[d] (as :func:`_product`, a view from index 0 so that it vectorises)."""
    n = x.size
    out = np.zeros(n)
    for k in range(n):
        c = x[k]
        head = out[k:]
        for d in range(n - k):
            head[d] += c * kernel[d]
        tail = kernel[n - k :]
        for d in range(k):
            out[d] += c * tail[d]
    return out


_EPS = float(np.finfo(np.float64).eps)


@njit(cache=True, nogil=True)
def _least_squares(a, b):
    """The least-squares solution of a x = b of least norm, a (n, m) with m small: numpy's ``lstsq`` (singular
    values below eps max(n, m) of the largest taken as zero), by one-sided Jacobi rotations of a's columns
    (a's SVD: U S = a V). Plain loops (no LAPACK, no array expressions: numba compiles them quickly)."""
    n, m = a.shape
    u = a.copy()
    v = np.zeros((m, m))
    for i in range(m):
        v[i, i] = 1.0
    for _ in range(60):
        rotated = False
        for p in range(m - 1):
            for q in range(p + 1, m):
                alpha = beta = gamma = 0.0
                for i in range(n):
                    alpha += u[i, p] * u[i, p]
                    beta += u[i, q] * u[i, q]
                    gamma += u[i, p] * u[i, q]
                if gamma == 0.0 or abs(gamma) <= 1e-15 * np.sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = 1.0 / (abs(zeta) + np.sqrt(1.0 + zeta * zeta))
                if zeta < 0.0:
                    t = -t
                c = 1.0 / np.sqrt(1.0 + t * t)
                s = c * t
                for i in range(n):
                    up, uq = u[i, p], u[i, q]
                    u[i, p] = c * up - s * uq
                    u[i, q] = s * up + c * uq
                for i in range(m):
                    vp, vq = v[i, p], v[i, q]
                    v[i, p] = c * vp - s * vq
                    v[i, q] = s * vp + c * vq
        if not rotated:
            break
    sigma = np.zeros(m)
    for j in range(m):
        total = 0.0
        for i in range(n):
            total += u[i, j] * u[i, j]
        sigma[j] = np.sqrt(total)
    cutoff = _EPS * max(n, m) * sigma.max()
    x = np.zeros(m)
    for j in range(m):
        if sigma[j] > cutoff:
            coefficient = 0.0
            for i in range(n):
                coefficient += u[i, j] * b[i]
            coefficient /= sigma[j] * sigma[j]
            for i in range(m):
                x[i] += v[i, j] * coefficient
    return x


@njit(cache=True, nogil=True)
def _iterate(deviation, forces, preload, limit, inverse, mixing, iteration):
    """One chord iteration of :func:`steady_state` with Anderson mixing, in place: False when the residual
    R = F - law(delta) (``forces`` = law(delta) at ``deviation``) is within ``limit`` everywhere (converged), else
    ``deviation`` moved to the next iterate and True. ``mixing`` = (steps, changes, last, count): the last
    differences of the deviation and of the preconditioned residual (rows, oldest first; as many rows as the
    mixing's depth), the previous deviation and change (rows 0 and 1 of ``last``) and how many differences are
    held (``count[0]``). Plain loops, as numpy's expressions would compute each value."""
    steps, changes, last, count = mixing
    n = deviation.size
    residual = np.empty(n)
    largest = 0.0
    for i in range(n):
        residual[i] = deviation[i] + preload - forces[i]
        largest = max(largest, abs(residual[i]))
    if largest <= limit:
        return False
    change = _circular(inverse, residual)
    for i in range(n):
        change[i] = -change[i]
    depth = steps.shape[0]
    if iteration and depth:
        if count[0] == depth:  # the oldest difference out
            for r in range(depth - 1):
                for i in range(n):
                    steps[r, i] = steps[r + 1, i]
                    changes[r, i] = changes[r + 1, i]
            count[0] -= 1
        row = count[0]
        for i in range(n):
            steps[row, i] = deviation[i] - last[0, i]
            changes[row, i] = change[i] - last[1, i]
        count[0] += 1
    for i in range(n):
        last[0, i] = deviation[i]
        last[1, i] = change[i]
    held = count[0]
    mix = np.zeros(0)
    if held:
        columns = np.empty((n, held))
        for r in range(held):
            for i in range(n):
                columns[i, r] = changes[r, i]
        mix = _least_squares(columns, change)
    for i in range(n):
        total = 0.0
        for r in range(held):
            total += (steps[r, i] + changes[r, i]) * mix[r]
        deviation[i] += change[i] - total
    return True


@njit(cache=True, fastmath=True, nogil=True)
def _approach(folded, lo, hi, frac, wheel, known, deviation):
    """The approach at ``deviation``: xi_W0 - M (F - P) - A P (``known``) less (A + B) times the deviation."""
    return known - _product(folded, lo, hi, frac, wheel, deviation)


def steady_state(
    history, law, preload: float, depth: int = ANDERSON_DEPTH, iterations: int = STEADY_ITERATIONS
) -> SteadyState:
    """The periodic steady state of a run's history (``history.History``) under ``law`` (approaches (n,) m ->
    forces (n,) N: the model's law on the run-in's gap), the wheel's rest position ``history.xi_w0``; ``depth``
    differences in the Anderson mixing (0: the plain chord iterations), at most ``iterations`` of them.

    Solves R(F) = F - law(xi_W0 + B P - (A + B) F) = 0 by chord iterations F -= (I + k C)^-1 R(F) (k the law's
    slope at the preload, C the circulant part of A + B: the track's mean over the bay, its inverse worked out by
    FFT once), with Anderson mixing of the last ``ANDERSON_DEPTH`` iterations (the bay's variation of the
    supports, which C leaves out, slows the plain iteration to a factor 0.4 a step: 24 iterations, measured). An
    iteration is two compiled calls that release the GIL (:func:`_approach`, :func:`_iterate`) around the law's.

    Raises WheelrailError if they do not converge (a law without a steady state near the preload)."""
    n = bay_steps_of(history)
    h = folded_wheel(history.phi, history.gamma0, history.gamma1, n)
    wheel = np.ascontiguousarray(h[:, 1])
    folded = _fold_lags(history.weights, n)
    lo, hi, frac = history.phases
    column = _circulant_part(folded, lo, hi, frac, wheel)
    # the approach xi_W0 - M (F - P) - A P: the deviation from the preload times M (the wheel's folded response
    # is large, ~1/k_S per step; its product with F itself would cancel to 1e-7 N)
    known = history.xi_w0 - preload * (_product(folded, lo, hi, frac, wheel, np.ones(n)) - wheel.sum())
    deviation = np.zeros(n)
    step = 1e-9 * float(np.mean(np.abs(known))) + 1e-15
    stiffness = float(np.mean(law(known + step) - law(known - step))) / (2 * step)
    inverse = _circulant_inverse(column, stiffness)
    mixing = (np.zeros((depth, n)), np.zeros((depth, n)), np.zeros((2, n)), np.zeros(1, dtype=np.int64))
    limit = STEADY_TOLERANCE * preload
    for iteration in range(iterations):
        approach = _approach(folded, lo, hi, frac, wheel, known, deviation)
        if not _iterate(deviation, np.asarray(law(approach), dtype=float), preload, limit, inverse, mixing, iteration):
            state = h[(n - 1 - np.arange(n)) % n].T @ deviation
            return SteadyState(force=deviation + preload, approach=approach, state=state, iterations=iteration)
    raise WheelrailError(
        "the run's steady state on the run-in's gap could not be found (its iterations did not converge on this "
        "track and contact); the Python API starts such a run from the preload at rest instead: "
        "prepare_run(..., run_in_length=L) with L about 0.3 s of travel (the command line and the explorer "
        "take only the steady start)"
    )


def start_state(history, law, preload: float) -> SteadyState:
    """The steady state a run starts from, on the model's law F(delta) on the run-in's gap (``law``, approaches
    (m) -> forces (N): ``ContactLaw.steady_law``): :func:`steady_state` with ``ANDERSON_DEPTH``, else (its
    iterations stalled) with ``DEEP_ANDERSON``."""
    try:
        return steady_state(history, law, preload)
    except WheelrailError:
        return steady_state(history, law, preload, *DEEP_ANDERSON)


def bay_steps_of(history) -> int:
    """:func:`bay_steps` of a history (``history.History.bay``); WheelrailError if it has none."""
    if history.bay is None:
        raise WheelrailError("the sleeper bay is not a whole number of elements: no steady start")
    return history.bay


def fill_history(history, steady: SteadyState) -> None:
    """Put the steady state into the history before step 0: the force at every history index before it (phase
    (j - n_hist) mod n), the rail displacement it causes later (eq. 2, scattered as ``prepare_run`` scatters the
    preload's), and the wheel's state after index n_hist - 1 (phase n - 1)."""
    n = len(steady.force)
    n_hist = history.n_hist
    history.force[:n_hist] = steady.force[(np.arange(n_hist) - n_hist) % n]
    history.acc[:] = 0.0
    lags = history.weights.shape[1]
    _history_tail(history.weights, *history.phases, steady.force, history.acc[n_hist : n_hist + lags])
    history.state[:] = steady.state
