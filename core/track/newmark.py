"""Newmark (average acceleration) integration of the FE track's responses, in numba: the scheme's displacement
recurrence with a profile (skyline) Cholesky factor of its effective stiffness and row-stored sparse matrices.
See ``wheelrail.core.track``.

With gamma = 1/2 and beta = 1/4, Newmark's scheme is the trapezoidal rule on (u, v): u_{k+1} - u_k =
dt (v_k + v_{k+1}) / 2 and v_{k+1} - v_k = dt (a_k + a_{k+1}) / 2 with M a_k + C v_k + F_k = f_k. Eliminating
v and a gives the displacement recurrence the loop steps,

    M (u_{k+1} - 2 u_k + u_{k-1}) / dt^2 + C (u_{k+1} - u_{k-1}) / (2 dt) + (F_{k+1} + 2 F_k + F_{k-1}) / 4
        = (f_{k+1} + 2 f_k + f_{k-1}) / 4,

the same sequence u_k as the three-vector form in exact arithmetic. With u_{k+1} = 2 u_k - u_{k-1} - x and an
elastic force F = K u, each step solves K_eff x = 4 K u_k + (4 C / dt)(u_k - u_{k-1}) with K_eff = K + 2 C / dt +
4 M / dt^2: one sparse product with K (M is not needed once K_eff is factored), one with C (a few hundred terms:
pads and ballast) and the two triangular solves. The rail's relaxation terms (``stationary._relaxation_terms``)
add K_rail w to the right-hand side (``_relaxation_rhs``).

The factor U (K_eff = U^T U) is stored by columns, each from its first structural non-zero row (the profile:
Cholesky keeps its fill inside it): the rail's columns are a few entries long, a pad's sleeper reaches back over
its pad's rail nodes alone, instead of a band as wide as the widest pad's everywhere.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from wheelrail.core.errors import WheelrailError


@dataclass(frozen=True)
class RowMatrix:
    """A sparse matrix stored by rows (CSR arrays: ``indptr``, ``indices``, ``data``)."""

    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray

    @classmethod
    def of(cls, matrix, scale: float = 1.0) -> RowMatrix:
        import scipy.sparse as sp

        csr = sp.csr_matrix(matrix * scale)
        csr.eliminate_zeros()
        csr.sort_indices()
        return cls(csr.indptr.astype(np.int64), csr.indices.astype(np.int64), csr.data.astype(float))

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self.indptr, self.indices, self.data


@dataclass(frozen=True)
class ProfileFactor:
    """Upper Cholesky factor U of a symmetric positive definite matrix A = U^T U, by columns from each column's
    first structural non-zero row: U[i, j] for first[j] <= i <= j at ``off[start[j] + i - first[j]]``,
    1 / U[j, j] at ``inverse_diagonal[j]``, and the off-diagonal entries again by rows in ``rows`` (U[i, j] for
    j > i: the back substitution gathers each row's terms)."""

    first: np.ndarray
    start: np.ndarray
    off: np.ndarray
    inverse_diagonal: np.ndarray
    rows: RowMatrix

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.first, self.start, self.off, self.inverse_diagonal

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """x with A x = rhs (rhs: (n,) or (n, m))."""
        x = np.array(rhs, dtype=float, order="C", ndmin=2).reshape(len(self.first), -1).copy()
        _forward(*self.arrays, x)
        _backward(*self.arrays, x)
        return x.reshape(np.shape(rhs))


def profile_cholesky(matrix) -> ProfileFactor:
    """The profile Cholesky factor of a symmetric positive definite sparse ``matrix``.

    Raises
    ------
    WheelrailError
        If the matrix is not positive definite.
    """
    rows = RowMatrix.of(matrix)
    n = len(rows.indptr) - 1
    first = np.arange(n, dtype=np.int64)
    for i in range(n):  # the first column of row i (its lower triangle's): column i's first row of U
        cols = rows.indices[rows.indptr[i] : rows.indptr[i + 1]]
        if len(cols):
            first[i] = min(i, int(cols[0]))
    lengths = np.arange(n) - first + 1
    start = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    values = np.zeros(int(lengths.sum()))
    failed = _factor(*rows.arrays, first, start, values)
    if failed >= 0:
        raise WheelrailError(f"the track's effective stiffness is not positive definite (pivot {failed})")
    import scipy.sparse as sp

    diagonal = start + np.arange(n) - first
    column = np.repeat(np.arange(n), lengths)
    row = np.arange(len(values)) - np.repeat(start, lengths) + np.repeat(first, lengths)
    off = row != column
    upper = sp.coo_matrix((values[off], (row[off], column[off])), shape=(n, n))
    return ProfileFactor(first, start, values, 1.0 / values[diagonal], RowMatrix.of(upper))


@njit(cache=True)
def _factor(indptr, indices, data, first, start, values):
    """U in place of A's upper triangle in profile storage (left-looking, column by column); the first column
    whose pivot is not positive, or -1."""
    n = len(first)
    for i in range(n):
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j >= i:
                values[start[j] + i - first[j]] += data[p]
    for j in range(n):
        fj, sj = first[j], start[j]
        for i in range(fj, j):
            fi, si = first[i], start[i]
            s = values[sj + i - fj]
            for k in range(max(fi, fj), i):
                s -= values[si + k - fi] * values[sj + k - fj]
            values[sj + i - fj] = s / values[si + i - fi]
        s = values[sj + j - fj]
        for k in range(fj, j):
            s -= values[sj + k - fj] ** 2
        if not s > 0.0:
            return j
        values[sj + j - fj] = np.sqrt(s)
    return -1


@njit(cache=True, fastmath=True)
def _forward(first, start, off, inv_diag, b):
    """b <- U^-T b in place (b: (n, m))."""
    n, m = b.shape
    for j in range(n):
        fj, sj = first[j], start[j]
        for i in range(fj, j):
            a = off[sj + i - fj]
            for c in range(m):
                b[j, c] -= a * b[i, c]
        for c in range(m):
            b[j, c] *= inv_diag[j]


@njit(cache=True, fastmath=True)
def _backward(first, start, off, inv_diag, b):
    """b <- U^-1 b in place (b: (n, m))."""
    n, m = b.shape
    for j in range(n - 1, -1, -1):
        fj, sj = first[j], start[j]
        for c in range(m):
            b[j, c] *= inv_diag[j]
        for i in range(fj, j):
            a = off[sj + i - fj]
            for c in range(m):
                b[i, c] -= a * b[j, c]


@dataclass(frozen=True)
class StepOperators:
    """What one Newmark step needs (module docstring): 4 K_e by rows, 4 C / dt by rows, K_rail by rows (empty
    for an undamped rail), the profile factor of K_eff, and the relaxation terms' g_j and b_j."""

    stiffness: RowMatrix
    damping: RowMatrix
    rail: RowMatrix
    factor: ProfileFactor
    weights: np.ndarray
    b: np.ndarray


def step_operators(model, time_step: float, relaxation) -> StepOperators:
    """The step's operators for the FE track ``model`` at ``time_step`` (s); ``relaxation`` = (c0, g_j, b_j)
    of the rail (``stationary._relaxation_terms``; no terms for an undamped rail).

    With relaxation terms the rail's elastic force is K_rail (c0 u + sum_j g_j (u - q_j)); the trapezoidal
    rule on q_j makes the effective stiffness K_e = K + K_rail (c0 - 1 + sum_j g_j / (1 + b_j)).
    """
    dt = time_step
    c0, weights, b = relaxation
    stiffness = model.K
    if len(weights):
        stiffness = model.K + (c0 - 1.0 + float(np.sum(weights / (1.0 + b)))) * model.K_rail
    keff = stiffness + (2.0 / dt) * model.C + (4.0 / dt**2) * model.M
    rail = RowMatrix.of(model.K_rail) if len(weights) else RowMatrix.of(model.K_rail[:0, :0])
    return StepOperators(
        stiffness=RowMatrix.of(stiffness, 4.0),
        damping=RowMatrix.of(model.C, 4.0 / dt),
        rail=rail,
        factor=profile_cholesky(keff),
        weights=np.asarray(weights, dtype=float),
        b=np.asarray(b, dtype=float),
    )


@njit(cache=True, fastmath=True)
def _record(u, s, w_dof, th_dof, nodes, counts, offsets, source, sign, out):
    """u's w and theta at the wedge's nodes into ``out`` as stored sample s (``_newmark_steps``): wedge e from
    column source[e], its theta times sign[e] (-1 for a mirror image: ``stationary.mirror_plan``)."""
    for e in range(len(source)):
        base = offsets[e, s]
        col = source[e]
        g = sign[e]
        for r in range(counts[e, s]):
            node = nodes[e, r]
            out[base + r, 0] = u[w_dof[node], col]
            out[base + r, 1] = g * u[th_dof[node], col]


@njit(cache=True, fastmath=True)
def _relaxation_state(weights, b, q, u_old, u_new, r):
    """q_j <- ((1 - b_j) q_j + b_j (u_old + u_new)) / (1 + b_j) (the trapezoidal rule on tau_j dq_j/dt = u - q_j)
    and r = sum_j g_j q_j."""
    n, m = u_new.shape
    r[:, :] = 0.0
    for j in range(len(b)):
        for i in range(n):
            for c in range(m):
                q[j, i, c] = ((1.0 - b[j]) * q[j, i, c] + b[j] * (u_old[i, c] + u_new[i, c])) / (1.0 + b[j])
                r[i, c] += weights[j] * q[j, i, c]


@njit(cache=True, fastmath=True)
def _relaxation_rhs(weights, b, q, u, u_prev, r, r_prev, w):
    """w = beta (2 u_k + u_{k-1}) - (z_k + 2 r_k + r_{k-1}), the vector K_rail multiplies on the right-hand side,
    with z_k = sum_j g_j ((1 - b_j) q_j + b_j u_k) / (1 + b_j) and beta = sum_j g_j b_j / (1 + b_j) (so that
    r_{k+1} = z_k + beta u_{k+1})."""
    n, m = u.shape
    beta = 0.0
    for j in range(len(b)):
        beta += weights[j] * b[j] / (1.0 + b[j])
    for i in range(n):
        for c in range(m):
            w[i, c] = beta * (2.0 * u[i, c] + u_prev[i, c]) - 2.0 * r[i, c] - r_prev[i, c]
    for j in range(len(b)):
        s = weights[j] / (1.0 + b[j])
        for i in range(n):
            for c in range(m):
                w[i, c] -= s * ((1.0 - b[j]) * q[j, i, c] + b[j] * u[i, c])


# A numba loop over time steps: every array it reads or fills is an argument, so that the whole loop compiles to
# one function numba caches on disk (a structure or a jitted callable would defeat the cache). Without the GIL:
# blocks of columns run in parallel Python threads (``stationary.integrate_responses``).
@njit(cache=True, fastmath=True, nogil=True)
def _newmark_steps(
    k_ptr, k_idx, k_val, c_ptr, c_idx, c_val, r_ptr, r_idx, r_val, first, start, off, inv_diag, u_ptr, u_idx,
    u_val, weights, b, load, dt, n_steps, stride, w_dof, th_dof, nodes, counts, offsets, source, sign, out,
    impulse,
):  # fmt: skip
    """Newmark (average acceleration) responses to the loads in the columns of ``load``, steps 0 .. n_steps - 1.

    ``impulse``: a unit impulse at t = 0 (u_0 = 0 and M v_0 = f, so K_eff u_1 = 4 f / dt); otherwise a unit
    force at step 0 only, the track at rest before (K_eff u_0 = f; the recurrence's right-hand side then has
    the force's (f_{k+1} + 2 f_k + f_{k-1}) / 4 at k = 0 and 1). The stiffness (k_*), damping (c_*) and rail
    (r_*) matrices are by rows, the factor by profile (first, start, off, inv_diag) for the forward substitution
    and by rows (u_*) for the back substitution (``StepOperators``). Each step makes two passes over the rows: the
    right-hand side and the forward substitution row by row, then the back substitution and the update of u.
    The responses are stored as ``out``'s dtype (float32: each value rounded once). Recorded on the wedge: stored
    step s = k / stride keeps, for wedge e, w and theta (times sign[e]) of column source[e] at the nodes
    nodes[e, 0 .. counts[e, s] - 1] in out[offsets[e, s] + r, 0:2].
    """
    n, m = load.shape
    relax = len(weights) > 0
    # u, u_prev and y padded to rows of a multiple of 8 values (64 bytes), the m columns used: each row's loads and
    # stores are then aligned vectors (docs/benchmarks.md); the arithmetic is the same
    width = (m + 7) // 8 * 8
    u_prev = np.zeros((n, width))[:, :m]
    u = np.zeros((n, width))[:, :m]
    u[:, :] = load * (4.0 / dt) if impulse else load
    _forward(first, start, off, inv_diag, u)
    _backward(first, start, off, inv_diag, u)
    q = np.zeros((len(weights), n, m))
    r = np.zeros((n, m))
    r_prev = np.zeros((n, m))
    w = np.zeros((n, m))
    if relax:
        _relaxation_state(weights, b, q, u_prev, u, r)
    k0 = 1 if impulse else 0
    if impulse:
        _record(u_prev, 0, w_dof, th_dof, nodes, counts, offsets, source, sign, out)
    if k0 < n_steps and k0 % stride == 0:
        _record(u, k0 // stride, w_dof, th_dof, nodes, counts, offsets, source, sign, out)
    y = np.empty((n, width))[:, :m]
    for k in range(k0, n_steps - 1):  # u_{k+1} from u_k (u) and u_{k-1} (u_prev)
        if relax:
            _relaxation_rhs(weights, b, q, u, u_prev, r, r_prev, w)
        # right-hand side row by row, and forward substitution as each row is complete
        for i in range(n):
            for c in range(m):
                y[i, c] = 0.0
            for p in range(k_ptr[i], k_ptr[i + 1]):
                a = k_val[p]
                col = k_idx[p]
                for c in range(m):
                    y[i, c] += a * u[col, c]
            for p in range(c_ptr[i], c_ptr[i + 1]):
                a = c_val[p]
                col = c_idx[p]
                for c in range(m):
                    y[i, c] += a * (u[col, c] - u_prev[col, c])
            if relax:
                for p in range(r_ptr[i], r_ptr[i + 1]):
                    a = r_val[p]
                    col = r_idx[p]
                    for c in range(m):
                        y[i, c] += a * w[col, c]
            if not impulse and k < 2:
                g = 2.0 if k == 0 else 1.0
                for c in range(m):
                    y[i, c] -= g * load[i, c]
            fi, si = first[i], start[i]
            for t in range(fi, i):
                a = off[si + t - fi]
                for c in range(m):
                    y[i, c] -= a * y[t, c]
            for c in range(m):
                y[i, c] *= inv_diag[i]
        # back substitution by U's rows, and u_{k+1} = 2 u_k - u_{k-1} - x into u_prev as each row is final
        for i in range(n - 1, -1, -1):
            for p in range(u_ptr[i], u_ptr[i + 1]):
                a = u_val[p]
                col = u_idx[p]
                for c in range(m):
                    y[i, c] -= a * y[col, c]
            for c in range(m):
                y[i, c] *= inv_diag[i]
                u_prev[i, c] = 2.0 * u[i, c] - u_prev[i, c] - y[i, c]
        if relax:
            r_prev[:, :] = r
            _relaxation_state(weights, b, q, u, u_prev, r)
        u, u_prev = u_prev, u
        if (k + 1) % stride == 0:
            _record(u, (k + 1) // stride, w_dof, th_dof, nodes, counts, offsets, source, sign, out)


def newmark_responses(operators: StepOperators, load, dt, n_steps, stride, w_dof, th_dof, wedge, out, impulse):
    """Run ``_newmark_steps`` for the columns of ``load`` (n, m), recording into ``out``; ``wedge`` =
    (nodes, counts, offsets) of these columns, or (nodes, counts, offsets, source, sign) of wedges recorded from
    them (``_record``)."""
    nodes, counts, offsets = wedge[:3]
    if len(wedge) == 3:
        source, sign = np.arange(len(nodes), dtype=np.int64), np.ones(len(nodes))
    else:
        source, sign = np.asarray(wedge[3], dtype=np.int64), np.asarray(wedge[4], dtype=float)
    load = np.ascontiguousarray(load, dtype=float)
    _newmark_steps(
        *operators.stiffness.arrays, *operators.damping.arrays, *operators.rail.arrays, *operators.factor.arrays,
        *operators.factor.rows.arrays, operators.weights, operators.b, load, float(dt), int(n_steps), int(stride),
        w_dof, th_dof, nodes, counts, offsets, source, sign, out, bool(impulse),
    )  # fmt: skip
