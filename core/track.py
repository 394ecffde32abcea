"""Discretely supported track: FE model, receptances and moving Green's functions (paper section 2.2).

Model
-----
The rail is a chain of undamped Rayleigh-Timoshenko beam elements (Friedman & Kosmatka's shear-
dependent interpolation, consistent translational and rotary mass) over ``n_bays`` sleeper bays,
free at both ends. At every sleeper position x = j L_S (j = 0..n_bays) a rail pad (k_P, c_P) joins
the rail to a (half) sleeper mass, which rests on ballast (k_B, c_B) on rigid ground.

DOFs are numbered node by node (w_i, theta_i[, sleeper_i]) so that every matrix is banded with
half-bandwidth 4; all solves are banded.

Moving Green's functions (eq. 2)
--------------------------------
The stationary track does not depend on speed. For ``positions_per_bay`` excitation points x_e in
the central bay (FE nodes: a load between nodes has a poorly converged early response), the impulse
response h(x, x_e, t) of the FE model is integrated once in time
(Newmark, average acceleration, step ``TrackNumerics.time_step``) and stored on the wedge
x_e <= x <= x_e + v_max t that a wheel at up to ``max_speed`` can reach. The moving Green's function
for any speed v <= v_max is then read off that wedge, g_{R,v}^{x_e}(t) = h(x_e + v t, x_e, t), with
the element's own shape functions between nodes: no new integration, a few milliseconds per speed.
Between the x_e the functions vary smoothly, with period L_S: they are refined ``BAY_REFINEMENT`` times
across the bay by trigonometric interpolation and then interpolated linearly (the loop's two-row mix).
Steps longer than ``parameters.FOH_MAX_STEP`` use weights of the trapezoidal rule integrated at the
loop's own step (``trapezoidal_weights``). Truncation: the functions are cut at
``TrackNumerics.duration``; the test suite and ``benchmarks/track_green.py`` show the truncation error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

if TYPE_CHECKING:
    import scipy.sparse as sp

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import FOH_MAX_STEP, TrackNumerics, TrackParameters

HALF_BANDWIDTH = 4
# The moving Green's functions of the FE excitation positions are refined this many times across the bay by
# trigonometric interpolation (they are periodic in x0 with period L_S) before the loop interpolates linearly
# between them. Linear interpolation straight between the 16 positions put tones of 32 N at (16 +- 1) v/L_S
# (641 and 727 Hz at 100 km/h) on a smooth rail; refined 4 times they are 0.07 and 0.02 N
# (tests/physics/test_track.py).
BAY_REFINEMENT = 4


def timoshenko_element_matrices(rail, length: float) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass of one Rayleigh-Timoshenko element, DOFs (w1, th1, w2, th2).

    Friedman & Kosmatka (1993) / Przemieniecki with the shear parameter
    Phi = 12 EI / (kGA L^2); mass = translational (m') + rotary (rho I) parts.

    Returns
    -------
    K : ndarray (4, 4), N/m (N, N m for rotations)
    M : ndarray (4, 4), kg (kg m, kg m^2 for rotations)
    """
    EI, kGA = rail.bending_stiffness, rail.shear_stiffness
    m, rI = rail.mass_per_length, rail.rotary_inertia_per_length
    L = length
    phi = 12.0 * EI / (kGA * L**2)
    K = (EI / ((1 + phi) * L**3)) * np.array(
        [
            [12, 6 * L, -12, 6 * L],
            [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
            [-12, -6 * L, 12, -6 * L],
            [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2],
        ]
    )
    a = 13 / 35 + 7 * phi / 10 + phi**2 / 3
    b = (11 / 210 + 11 * phi / 120 + phi**2 / 24) * L
    c = 9 / 70 + 3 * phi / 10 + phi**2 / 6
    d = (13 / 420 + 3 * phi / 40 + phi**2 / 24) * L
    e = (1 / 105 + phi / 60 + phi**2 / 120) * L**2
    f = (1 / 140 + phi / 60 + phi**2 / 120) * L**2
    Mt = (m * L / (1 + phi) ** 2) * np.array(
        [[a, b, c, -d], [b, e, d, -f], [c, d, a, -b], [-d, -f, -b, e]]
    )
    g = 6 / 5
    h = (1 / 10 - phi / 2) * L
    i = (2 / 15 + phi / 6 + phi**2 / 3) * L**2
    j = (-1 / 30 - phi / 6 + phi**2 / 6) * L**2
    Mr = (rI / ((1 + phi) ** 2 * L)) * np.array(
        [[g, h, -g, h], [h, i, -h, j], [-g, -h, g, -h], [h, j, -h, i]]
    )
    return K, Mt + Mr


def timoshenko_shape_functions(xi, length: float, phi: float) -> np.ndarray:
    """Displacement shape functions N1..N4 of the element at xi = x / L in [0, 1].

    Friedman & Kosmatka's interdependent interpolation: w(xi) = N1 w1 + N2 th1 + N3 w2 + N4 th2.
    Also the consistent load vector of a unit point force at xi. Returns shape (..., 4).
    """
    xi = np.asarray(xi, dtype=float)
    L = length
    s = 1.0 / (1.0 + phi)
    n1 = s * (2 * xi**3 - 3 * xi**2 - phi * xi + 1 + phi)
    n2 = s * L * (xi**3 - (2 + phi / 2) * xi**2 + (1 + phi / 2) * xi)
    n3 = s * (-2 * xi**3 + 3 * xi**2 + phi * xi)
    n4 = s * L * (xi**3 - (1 - phi / 2) * xi**2 - (phi / 2) * xi)
    return np.stack([n1, n2, n3, n4], axis=-1)


@dataclass(frozen=True)
class TrackFEModel:
    """Assembled FE model of the finite track.

    Attributes
    ----------
    params : TrackParameters
    element_length : float
        m.
    node_x : ndarray
        Rail node positions, m (0 .. n_bays L_S).
    w_dof, theta_dof : ndarray of int
        DOF index of each rail node's displacement and rotation.
    sleeper_dof : ndarray of int
        DOF index of each sleeper (one per support at x = j L_S).
    M, C, K : scipy.sparse.csr_matrix
        Mass, damping, stiffness (SI).
    """

    params: TrackParameters
    element_length: float
    node_x: np.ndarray
    w_dof: np.ndarray
    theta_dof: np.ndarray
    sleeper_dof: np.ndarray
    M: sp.csr_matrix
    C: sp.csr_matrix
    K: sp.csr_matrix

    @property
    def n_dof(self) -> int:
        return self.M.shape[0]

    @property
    def shear_parameter(self) -> float:
        rail = self.params.rail
        return 12.0 * rail.bending_stiffness / (rail.shear_stiffness * self.element_length**2)

    def locate(self, x) -> tuple[np.ndarray, np.ndarray]:
        """Element index and local coordinate xi in [0, 1] of rail positions x (m)."""
        x = np.asarray(x, dtype=float)
        h = self.element_length
        n_el = len(self.node_x) - 1
        if np.any(x < 0) or np.any(x > n_el * h * (1 + 1e-12)):
            raise WheelrailError(f"position outside the track model [0, {n_el * h:.3f}] m")
        element = np.minimum((x / h).astype(int), n_el - 1)
        return element, x / h - element

    def load_vector(self, x: float) -> np.ndarray:
        """Consistent nodal load vector of a unit vertical force at rail position x (m)."""
        element, xi = self.locate(x)
        N = timoshenko_shape_functions(xi, self.element_length, self.shear_parameter)
        f = np.zeros(self.n_dof)
        e = int(element)
        dofs = [self.w_dof[e], self.theta_dof[e], self.w_dof[e + 1], self.theta_dof[e + 1]]
        f[dofs] = N
        return f

    def banded(self, matrix) -> np.ndarray:
        """Matrix in LAPACK general band form (for ``scipy.linalg.solve_banded``)."""
        return _to_band(matrix, HALF_BANDWIDTH, HALF_BANDWIDTH)


def _to_band(matrix, lower: int, upper: int) -> np.ndarray:
    import scipy.sparse as sp  # scipy imported where used: a cached `wheelrail track` never needs it

    A = sp.coo_matrix(matrix)
    n = A.shape[0]
    ab = np.zeros((lower + upper + 1, n), dtype=A.dtype)
    if np.any(A.row - A.col > lower) or np.any(A.col - A.row > upper):
        raise AssertionError("matrix is wider than its band")
    np.add.at(ab, (upper + A.row - A.col, A.col), A.data)
    return ab


def _to_upper_band(matrix, upper: int) -> np.ndarray:
    """Symmetric matrix in LAPACK upper band form (for ``cholesky_banded``)."""
    import scipy.sparse as sp

    return _to_band(sp.triu(matrix), 0, upper)


def assemble_track(track: TrackParameters, elements_per_bay: int = 16) -> TrackFEModel:
    """Assemble mass, damping and stiffness of the discretely supported track.

    Parameters
    ----------
    track : TrackParameters
    elements_per_bay : int
        Beam elements per sleeper bay.

    Returns
    -------
    TrackFEModel
    """
    import scipy.sparse as sp

    rail, sup = track.rail, track.support
    n_el = track.n_bays * elements_per_bay
    h = sup.sleeper_spacing / elements_per_bay
    node_x = np.arange(n_el + 1) * h
    # DOF numbering node by node keeps the matrices banded
    w_dof = np.empty(n_el + 1, dtype=np.int64)
    th_dof = np.empty(n_el + 1, dtype=np.int64)
    sleeper_dof = []
    k = 0
    for node in range(n_el + 1):
        w_dof[node], th_dof[node] = k, k + 1
        k += 2
        if node % elements_per_bay == 0:
            sleeper_dof.append(k)
            k += 1
    n_dof = k
    Ke, Me = timoshenko_element_matrices(rail, h)
    rows, cols, kv, mv = [], [], [], []
    for e in range(n_el):
        dofs = np.array([w_dof[e], th_dof[e], w_dof[e + 1], th_dof[e + 1]])
        rows.append(np.repeat(dofs, 4))
        cols.append(np.tile(dofs, 4))
        kv.append(Ke.ravel())
        mv.append(Me.ravel())
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    K = sp.coo_matrix((np.concatenate(kv), (rows, cols)), shape=(n_dof, n_dof)).tolil()
    M = sp.coo_matrix((np.concatenate(mv), (rows, cols)), shape=(n_dof, n_dof)).tolil()
    C = sp.lil_matrix((n_dof, n_dof))
    support_nodes = np.arange(0, n_el + 1, elements_per_bay)
    for node, s in zip(support_nodes, sleeper_dof, strict=True):
        r = w_dof[node]
        for mat, pad, ballast in ((K, sup.pad_stiffness, sup.ballast_stiffness),
                                  (C, sup.pad_damping, sup.ballast_damping)):
            mat[r, r] += pad
            mat[r, s] -= pad
            mat[s, r] -= pad
            mat[s, s] += pad + ballast
        M[s, s] += sup.sleeper_mass
    return TrackFEModel(
        params=track,
        element_length=h,
        node_x=node_x,
        w_dof=w_dof,
        theta_dof=th_dof,
        sleeper_dof=np.array(sleeper_dof, dtype=np.int64),
        M=M.tocsr(),
        C=C.tocsr(),
        K=K.tocsr(),
    )


def track_receptance(model: TrackFEModel, frequency, x_excitation: float, x_response=None) -> np.ndarray:
    """Rail receptance of the FE track: displacement at ``x_response`` per force at ``x_excitation``.

    Parameters
    ----------
    model : TrackFEModel
    frequency : array_like
        f, Hz (>= 0).
    x_excitation : float
        Position of the unit vertical force on the rail, m (0 .. track length).
    x_response : float or array_like, optional
        Response positions, m; default the excitation point (point receptance).

    Returns
    -------
    ndarray of complex, shape (len(frequency),) + shape(x_response)
        alpha_R in m/N, convention x(t) = Re(X e^{i 2 pi f t}).
    """
    from scipy.linalg import solve_banded

    f = np.atleast_1d(np.asarray(frequency, dtype=float))
    if not np.all(np.isfinite(f)) or np.any(f < 0):
        raise WheelrailError("track_receptance: frequencies must be finite and >= 0 Hz")
    x_resp = np.atleast_1d(np.asarray(x_excitation if x_response is None else x_response, dtype=float))
    load = model.load_vector(float(x_excitation))
    element, xi = model.locate(x_resp)
    N = timoshenko_shape_functions(xi, model.element_length, model.shear_parameter)
    dofs = np.stack(
        [model.w_dof[element], model.theta_dof[element], model.w_dof[element + 1],
         model.theta_dof[element + 1]], axis=-1
    )
    Kb, Cb, Mb = model.banded(model.K), model.banded(model.C), model.banded(model.M)
    out = np.empty((len(f), len(x_resp)), dtype=complex)
    for i, fi in enumerate(f):
        w = 2 * np.pi * fi
        u = solve_banded((HALF_BANDWIDTH, HALF_BANDWIDTH), Kb - w**2 * Mb + 1j * w * Cb, load,
                         check_finite=False)
        out[i] = np.sum(N * u[dofs], axis=-1)
    if x_response is None or np.ndim(x_response) == 0:
        return out[:, 0]
    return out


def _upper_band_arrays(model: TrackFEModel, time_step: float):
    """Upper band forms of M, C and the Cholesky factor of the Newmark effective stiffness."""
    from scipy.linalg import cholesky_banded

    dt = time_step
    keff = model.K + (2.0 / dt) * model.C + (4.0 / dt**2) * model.M
    mb = _to_upper_band(model.M, HALF_BANDWIDTH)
    cb = _to_upper_band(model.C, HALF_BANDWIDTH)
    k_chol = cholesky_banded(_to_upper_band(keff, HALF_BANDWIDTH), check_finite=False)
    m_chol = cholesky_banded(mb, check_finite=False)
    return mb, cb, k_chol, m_chol


@njit(cache=True, fastmath=True)
def _band_matvec(ab, x, out):
    """out = A x for a symmetric A in LAPACK upper band form ``ab``; x and out are (n, m)."""
    u = ab.shape[0] - 1
    n, m = x.shape
    for i in range(n):
        d0 = ab[u, i]
        for c in range(m):
            out[i, c] = d0 * x[i, c]
    for j in range(1, n):
        for d in range(1, min(u, j) + 1):
            a = ab[u - d, j]
            i = j - d
            for c in range(m):
                out[i, c] += a * x[j, c]
                out[j, c] += a * x[i, c]


@njit(cache=True, fastmath=True)
def _band_cho_solve(ab, b):
    """Solve U^T U x = b in place (b is (n, m)); U upper band Cholesky factor, LAPACK 'U' form."""
    u = ab.shape[0] - 1
    n, m = b.shape
    for j in range(n):
        for d in range(1, min(u, j) + 1):
            a = ab[u - d, j]
            for c in range(m):
                b[j, c] -= a * b[j - d, c]
        inv = 1.0 / ab[u, j]
        for c in range(m):
            b[j, c] *= inv
    for i in range(n - 1, -1, -1):
        for d in range(1, min(u, n - 1 - i) + 1):
            a = ab[u - d, i + d]
            for c in range(m):
                b[i, c] -= a * b[i + d, c]
        inv = 1.0 / ab[u, i]
        for c in range(m):
            b[i, c] *= inv


@njit(cache=True, fastmath=True)
def _newmark_block(mb, cb, k_chol, m_chol, load, dt, n_steps, stride, w_dof, th_dof, first_node,
                   wedge_nodes, offsets, out, impulse):
    """Newmark (average acceleration) responses to the loads in the columns of ``load``.

    ``impulse``: a unit impulse at t = 0 (the continuous impulse response, sampled); otherwise a unit
    force at step 0 only, the track at rest before (the discrete impulse response of the trapezoidal rule).
    Recorded on the wedge: stored step s = k / stride keeps, for column e, w and theta of the nodes
    first_node[e] .. first_node[e] + wedge_nodes[s] - 1 in out[e, offsets[s] + r, 0:2].
    """
    n, m = load.shape
    c1 = 4.0 / dt**2
    c2 = 4.0 / dt
    c3 = 2.0 / dt
    a = np.empty((n, m))
    if impulse:
        u = np.zeros((n, m))
        v = load.copy()
        _band_cho_solve(m_chol, v)  # the impulse sets the initial velocity: M v0 = f
        _band_matvec(cb, v, a)
        _band_cho_solve(m_chol, a)
        a *= -1.0  # M a0 = -C v0 - K u0 with u0 = 0
    else:
        u = load.copy()
        _band_cho_solve(k_chol, u)  # one step from rest: K_eff u0 = f
        v = c3 * u
        a[:, :] = c1 * u
    tmp = np.empty((n, m))
    rhs = np.empty((n, m))
    damp = np.empty((n, m))
    for k in range(n_steps):
        if k > 0:
            for i in range(n):
                for c in range(m):
                    tmp[i, c] = c1 * u[i, c] + c2 * v[i, c] + a[i, c]
            _band_matvec(mb, tmp, rhs)
            for i in range(n):
                for c in range(m):
                    tmp[i, c] = c3 * u[i, c] + v[i, c]
            _band_matvec(cb, tmp, damp)
            for i in range(n):
                for c in range(m):
                    rhs[i, c] += damp[i, c]
            _band_cho_solve(k_chol, rhs)  # K_eff u_k = rhs
            for i in range(n):
                for c in range(m):
                    du = rhs[i, c] - u[i, c]
                    a_new = c1 * du - c2 * v[i, c] - a[i, c]
                    v[i, c] = c3 * du - v[i, c]
                    a[i, c] = a_new
                    u[i, c] = rhs[i, c]
        if k % stride == 0:
            s = k // stride
            for e in range(m):
                for r in range(wedge_nodes[s]):
                    node = first_node[e] + r
                    out[e, offsets[s] + r, 0] = u[w_dof[node], e]
                    out[e, offsets[s] + r, 1] = u[th_dof[node], e]




# --------------------------------------------------------------------------------------------------
# Stationary responses on the wedge, and moving Green's functions for any speed
# --------------------------------------------------------------------------------------------------

_WEDGE_ARRAYS = ("data", "wedge_nodes", "offsets", "excitation_positions", "first_node_offsets")


@dataclass(frozen=True)
class StationaryTrackResponse:
    """Impulse responses of the track, stored on the wedge a moving wheel can reach.

    Attributes
    ----------
    track : TrackParameters
    numerics : TrackNumerics
    element_length : float
        m.
    shear_parameter : float
        Phi of the beam elements (for the shape functions).
    time_step : float
        Spacing of the stored samples, s (integration step times ``store_every``).
    excitation_positions : ndarray (P,)
        Excitation points x_e measured from the sleeper at the start of the central bay, m, in [0, L_S).
    first_node_offsets : ndarray (P,)
        Position of the first stored node relative to x_e, m, in (-h, 0].
    wedge_nodes, offsets : ndarray of int (S,)
        Number of stored nodes and their start in ``data`` for each stored time sample.
    data : ndarray float32 (P, sum(wedge_nodes), 2)
        Rail displacement w (m/(N s)) and rotation theta (1/(N s)) of the stored nodes.
    cache_path : str
        The disk cache file ('' when not cached).
    """

    track: TrackParameters
    numerics: TrackNumerics
    element_length: float
    shear_parameter: float
    time_step: float
    excitation_positions: np.ndarray
    first_node_offsets: np.ndarray
    wedge_nodes: np.ndarray
    offsets: np.ndarray
    data: np.ndarray
    cache_path: str = ""

    @property
    def n_samples(self) -> int:
        return len(self.wedge_nodes)


def _wedge_layout(numerics: TrackNumerics, element_length: float) -> tuple[np.ndarray, np.ndarray, int]:
    dt = numerics.time_step
    n_steps = int(round(numerics.duration / dt)) + 1
    stride = numerics.store_every
    t_stored = np.arange(0, n_steps, stride) * dt
    reach = numerics.max_speed * numerics.duration
    if not reach < 1e6:  # m: beyond 1000 km the node counts below overflow int64 (issue 13: 1e308 km/h)
        raise WheelrailError(f"a wheel at {numerics.max_speed * 3.6:.3g} km/h travels {reach:.3g} m within "
                             f"the {numerics.duration} s Green's functions, beyond any track model")
    # nodes from the one at or before x_e up to the first at or beyond x_e + v_max t, plus one spare
    wedge_nodes = np.ceil(numerics.max_speed * t_stored / element_length).astype(np.int64) + 2
    offsets = np.concatenate([[0], np.cumsum(wedge_nodes)[:-1]]).astype(np.int64)
    return wedge_nodes, offsets, n_steps


def _excitation_nodes(model: TrackFEModel, numerics: TrackNumerics):
    """Excitation positions within the central bay (m from its first sleeper), on the track (m), and
    their FE nodes (the positions are nodes: TrackNumerics checks)."""
    track = model.params
    L = track.support.sleeper_spacing
    positions = np.arange(numerics.positions_per_bay) * (L / numerics.positions_per_bay)
    x_e = (track.n_bays // 2) * L + positions
    return positions, x_e, np.rint(x_e / model.element_length).astype(np.int64)


def _check_reach(model: TrackFEModel, first_node, wedge_nodes, speed: float, duration: float) -> None:
    if first_node.max() + wedge_nodes[-1] - 1 >= len(model.node_x) - 1:
        raise WheelrailError(
            f"track model too short: a wheel at {speed * 3.6:.0f} km/h travels {speed * duration:.2f} m "
            f"within the {duration} s Green's functions, beyond the end of the "
            f"{model.params.n_bays}-bay track; use more bays or a shorter duration"
        )


def _integrate(model: TrackFEModel, x_e, first_node, dt: float, n_steps: int, stride: int, wedge_nodes, offsets,
               *, impulse: bool) -> np.ndarray:
    """Newmark responses to unit loads at x_e, stored on the wedge from ``first_node`` (see _newmark_block)."""
    mb, cb, k_chol, m_chol = _upper_band_arrays(model, dt)
    loads = np.stack([model.load_vector(float(x)) for x in x_e], axis=1)
    out = np.zeros((len(first_node), int(wedge_nodes.sum()), 2))
    _newmark_block(mb, cb, k_chol, m_chol, loads, dt, n_steps, stride, model.w_dof, model.theta_dof, first_node,
                   wedge_nodes, offsets, out, impulse)
    return out


def compute_stationary_response(track: TrackParameters, numerics: TrackNumerics) -> StationaryTrackResponse:
    """Integrate the impulse responses of the FE track for all excitation points of the central bay.

    See the module docstring for the method; takes about 10 s with the defaults.
    """
    model = assemble_track(track, numerics.elements_per_bay)
    h = model.element_length
    positions, x_e, first_node = _excitation_nodes(model, numerics)
    wedge_nodes, offsets, n_steps = _wedge_layout(numerics, h)
    _check_reach(model, first_node, wedge_nodes, numerics.max_speed, numerics.duration)
    out = _integrate(model, x_e, first_node, numerics.time_step, n_steps, numerics.store_every, wedge_nodes,
                     offsets, impulse=True)
    return StationaryTrackResponse(
        track=track,
        numerics=numerics,
        element_length=h,
        shear_parameter=model.shear_parameter,
        time_step=numerics.time_step * numerics.store_every,
        excitation_positions=positions,
        first_node_offsets=model.node_x[first_node] - x_e,
        wedge_nodes=wedge_nodes,
        offsets=offsets,
        data=out.astype(np.float32),
    )


def _track_key(track: TrackParameters, numerics: TrackNumerics) -> str:
    from dataclasses import asdict

    from wheelrail.core.cache import cache_key

    return cache_key("track-wedge", {"track": asdict(track), "numerics": asdict(numerics)})


def track_cache_path(track: TrackParameters, numerics: TrackNumerics):
    """Path of the disk-cache entry for these parameters (it may not exist yet)."""
    from wheelrail.core.cache import entry_path

    return entry_path("track-wedge", _track_key(track, numerics))


_MEMORY: dict[str, StationaryTrackResponse] = {}


def stationary_track_response(
    track: TrackParameters | None = None, numerics: TrackNumerics | None = None, *, use_cache: bool = True
) -> StationaryTrackResponse:
    """The track's stationary impulse responses: from memory, the disk cache, or computed and cached.

    Parameters
    ----------
    track : TrackParameters, optional
        Default: the paper's track.
    numerics : TrackNumerics, optional
        Default: ``TrackNumerics()``.
    use_cache : bool
        Read and write the disk cache (``wheelrail.core.cache``).
    """
    from wheelrail.core import cache

    track = TrackParameters() if track is None else track
    numerics = TrackNumerics() if numerics is None else numerics
    key = _track_key(track, numerics)
    if use_cache and key in _MEMORY:
        return _MEMORY[key]
    arrays = cache.load_entry("track-wedge", key, _WEDGE_ARRAYS) if use_cache else None
    if arrays is not None:
        h = track.support.sleeper_spacing / numerics.elements_per_bay
        wedge_nodes, offsets, _ = _wedge_layout(numerics, h)
        if (arrays["wedge_nodes"].shape != wedge_nodes.shape or np.any(arrays["wedge_nodes"] != wedge_nodes)
                or arrays["data"].shape != (numerics.positions_per_bay, int(wedge_nodes.sum()), 2)
                or not np.all(np.isfinite(arrays["data"]))):
            arrays = None  # inconsistent with its own key: rebuild
    if arrays is not None:
        rail = track.rail
        response = StationaryTrackResponse(
            track=track,
            numerics=numerics,
            element_length=h,
            shear_parameter=12.0 * rail.bending_stiffness / (rail.shear_stiffness * h**2),
            time_step=numerics.time_step * numerics.store_every,
            excitation_positions=arrays["excitation_positions"],
            first_node_offsets=arrays["first_node_offsets"],
            wedge_nodes=arrays["wedge_nodes"],
            offsets=arrays["offsets"],
            data=arrays["data"],
            cache_path=str(cache.entry_path("track-wedge", key)),
        )
    else:
        response = compute_stationary_response(track, numerics)
        if use_cache:
            path = cache.save_entry(
                "track-wedge", key, {name: getattr(response, name) for name in _WEDGE_ARRAYS}
            )
            response = StationaryTrackResponse(**{**response.__dict__, "cache_path": str(path)})
    if use_cache:
        _MEMORY.clear()  # keep one track in memory (tens of MB)
        _MEMORY[key] = response
    return response


@njit(cache=True)
def _read_wedge(data, wedge_nodes, offsets, first_offsets, h, phi, dt, speed, out):
    """g[e, s] = w at x_e + v t_s from the stored nodes, with the element's shape functions."""
    n_exc, n_samples = out.shape
    inv = 1.0 / (1.0 + phi)
    for e in range(n_exc):
        for s in range(n_samples):
            x_rel = speed * s * dt - first_offsets[e]
            r = int(x_rel / h)
            if r > wedge_nodes[s] - 2:
                r = wedge_nodes[s] - 2
            xi = x_rel / h - r
            n1 = inv * (2 * xi**3 - 3 * xi**2 - phi * xi + 1 + phi)
            n2 = inv * h * (xi**3 - (2 + phi / 2) * xi**2 + (1 + phi / 2) * xi)
            n3 = inv * (-2 * xi**3 + 3 * xi**2 + phi * xi)
            n4 = inv * h * (xi**3 - (1 - phi / 2) * xi**2 - (phi / 2) * xi)
            o = offsets[s] + r
            out[e, s] = (n1 * data[e, o, 0] + n2 * data[e, o, 1]
                         + n3 * data[e, o + 1, 0] + n4 * data[e, o + 1, 1])


@dataclass(frozen=True)
class MovingGreenFunctions:
    """Moving Green's functions g_{R,v}^{x0}(t) of eq. (2) for one speed.

    Attributes
    ----------
    speed : float
        v, m/s.
    sleeper_spacing : float
        L_S, m (the functions are periodic in x0 with this period).
    excitation_positions : ndarray (P,)
        x0 within the bay, measured from a sleeper, m.
    time_step : float
        Sample spacing of ``values``, s.
    values : ndarray (P, S)
        g(t_s) in m/(N s): rail displacement at x0 + v t per unit impulse at x0 at t = 0.
    track, numerics : optional
        The track they come from (needed by ``weights`` for steps longer than ``FOH_MAX_STEP``).
    """

    speed: float
    sleeper_spacing: float
    excitation_positions: np.ndarray
    time_step: float
    values: np.ndarray
    track: TrackParameters | None = None
    numerics: TrackNumerics | None = None

    @property
    def duration(self) -> float:
        return (self.values.shape[1] - 1) * self.time_step

    @property
    def time(self) -> np.ndarray:
        return np.arange(self.values.shape[1]) * self.time_step

    def _bay_interpolation(self, x0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        P = len(self.excitation_positions)
        pos = np.mod(np.asarray(x0, dtype=float), self.sleeper_spacing) / self.sleeper_spacing * P
        lo = np.floor(pos).astype(int) % P
        return lo, (lo + 1) % P, pos - np.floor(pos)

    def _across_bay(self, values: np.ndarray, x0) -> np.ndarray:
        lo, hi, frac = self._bay_interpolation(np.atleast_1d(x0))
        return (1 - frac)[..., None] * values[lo] + frac[..., None] * values[hi]

    def at(self, x0) -> np.ndarray:
        """g^{x0}(t_s) for excitation positions x0 (m, any value; periodic in L_S), shape (..., S).

        Linear interpolation between the stored excitation positions.
        """
        lo, hi, frac = self._bay_interpolation(x0)
        return (1 - frac)[..., None] * self.values[lo] + frac[..., None] * self.values[hi]

    def sample(self, time_step: float, n_samples: int, x0=None) -> np.ndarray:
        """g(m dt), m = 0..n-1 (linear in time between stored samples; zero beyond the duration).

        Returns shape (P, n) for the stored positions, or (len(x0), n) for ``x0``.
        """
        values = self.values if x0 is None else self.at(np.atleast_1d(x0))
        t = np.arange(n_samples) * time_step
        return np.stack([np.interp(t, self.time, row, right=0.0) for row in values])

    def weights(self, time_step: float, n_lags: int | None = None, x0=None, method: str = "auto") -> np.ndarray:
        """Convolution weights w_m^{x0} of eq. (2) at the loop's time step: ``xi_R(t_n) = sum_m F(t_{n-m})
        w_m^{x(t_{n-m})}``, with w_0 > 0 (the current force acts on the current displacement, so an
        interaction loop using these weights is implicit).

        ``method="foh"`` (first-order hold, used up to ``FOH_MAX_STEP``): exact for a force varying linearly
        between samples, ``w_m = int g(tau) Lambda(tau / dt - m) dtau`` (Lambda the unit hat), evaluated
        exactly for the piecewise-linear g between its stored samples. ``"trapezoidal"`` (used above
        ``FOH_MAX_STEP``): the discrete impulse responses of the FE track integrated by the trapezoidal rule
        at this step (:func:`trapezoidal_weights`), which keeps the coupled loop stable at long steps (see
        ``parameters.FOH_MAX_STEP``). ``"auto"`` chooses by the step.

        Parameters
        ----------
        time_step : float
            dt of the run, s.
        n_lags : int, optional
            Number of weights; default enough to cover the duration.
        x0 : array_like, optional
            Excitation positions, m (default: the stored ones).
        method : {"auto", "foh", "trapezoidal"}

        Returns
        -------
        ndarray (P or len(x0), n_lags), m/N.
        """
        if not np.isfinite(time_step) or time_step <= 0:
            raise WheelrailError(f"time_step must be positive (s), got {time_step}")
        if method not in ("auto", "foh", "trapezoidal"):
            raise WheelrailError(f"weights: method must be auto, foh or trapezoidal, got {method!r}")
        if n_lags is None:
            n_lags = int(math.ceil(self.duration / time_step)) + 1
        if method == "trapezoidal" or (method == "auto" and time_step > FOH_MAX_STEP):
            if self.track is None or self.numerics is None:
                raise WheelrailError("trapezoidal weights need the track these Green's functions come from")
            values = trapezoidal_weights(self.track, self.numerics, self.speed, time_step, n_lags)
            values = refine_across_bay(values, len(self.excitation_positions) // len(values))
            return values if x0 is None else self._across_bay(values, x0)
        values = self.values if x0 is None else self.at(np.atleast_1d(x0))
        edges = (np.arange(-1, n_lags + 1)) * time_step
        G1, G2 = _piecewise_linear_moments(values, self.time_step, edges)
        # hat over [(m-1)dt, (m+1)dt]: rising half uses (tau - (m-1)dt)/dt, falling ((m+1)dt - tau)/dt
        left = slice(0, n_lags)
        mid = slice(1, n_lags + 1)
        right = slice(2, n_lags + 2)
        rise = (G2[:, mid] - G2[:, left]) - edges[left] * (G1[:, mid] - G1[:, left])
        fall = edges[right] * (G1[:, right] - G1[:, mid]) - (G2[:, right] - G2[:, mid])
        return (rise + fall) / time_step


_MODELS: dict[tuple, TrackFEModel] = {}


def refine_across_bay(values: np.ndarray, factor: int = BAY_REFINEMENT) -> np.ndarray:
    """Rows at P equally spaced positions of a period -> rows at factor * P positions (the first P * k kept).

    Trigonometric (band-limited) interpolation along axis 0: exact for the harmonics of the bay up to P/2,
    the P/2 one split evenly between +-P/2. Returns ``values`` itself for ``factor == 1``.
    """
    if factor == 1:
        return values
    P = values.shape[0]
    spectrum = np.fft.rfft(values, axis=0)
    fine = np.zeros((factor * P // 2 + 1,) + values.shape[1:], dtype=complex)
    fine[: P // 2 + 1] = spectrum
    if P % 2 == 0:
        fine[P // 2] *= 0.5
    return np.fft.irfft(fine, n=factor * P, axis=0) * factor


def trapezoidal_weights(track: TrackParameters, numerics: TrackNumerics, speed: float, time_step: float,
                        n_lags: int) -> np.ndarray:
    """Convolution weights of eq. (2) from the FE track integrated by the trapezoidal rule at ``time_step``.

    Newmark's average-acceleration rule (the trapezoidal rule) at the loop's own step: w_m^{x_e} is the rail
    displacement at x_e + v m dt at step m after a unit force at x_e at step 0 only, the track at rest
    before. Its transfer function is the track's receptance at s = 2/dt (z - 1)/(z + 1), so the coupled
    loop keeps the physical system's stability at any step (``parameters.FOH_MAX_STEP``). Cost: n_lags
    banded steps of the FE model for the ``numerics.positions_per_bay`` positions (tens of ms for the
    200 lags of 0.25 ms steps).

    Returns
    -------
    ndarray (positions_per_bay, n_lags), m/N.
    """
    key = (track, numerics.elements_per_bay)
    if key not in _MODELS:
        _MODELS.clear()
        _MODELS[key] = assemble_track(track, numerics.elements_per_bay)
    model = _MODELS[key]
    h = model.element_length
    positions, x_e, first_node = _excitation_nodes(model, numerics)
    t = np.arange(n_lags) * time_step
    wedge_nodes = np.ceil(speed * t / h).astype(np.int64) + 2
    offsets = np.concatenate([[0], np.cumsum(wedge_nodes)[:-1]]).astype(np.int64)
    _check_reach(model, first_node, wedge_nodes, speed, float(t[-1]))
    out = _integrate(model, x_e, first_node, time_step, n_lags, 1, wedge_nodes, offsets, impulse=False)
    values = np.empty((len(positions), n_lags))
    _read_wedge(out, wedge_nodes, offsets, model.node_x[first_node] - x_e, h, model.shear_parameter, time_step,
                float(speed), values)
    return values


def _piecewise_linear_moments(values: np.ndarray, step: float, tau: np.ndarray):
    """Exact G1(tau) = int_0^tau g and G2(tau) = int_0^tau t g(t) dt for g linear between samples
    (g = 0 before 0 and after the last sample). Returns two arrays of shape (rows, len(tau))."""
    n = values.shape[1]
    t = np.arange(n) * step
    g0, g1 = values[:, :-1], values[:, 1:]
    seg1 = 0.5 * step * (g0 + g1)
    seg2 = step / 6.0 * (2 * t[:-1] * g0 + t[:-1] * g1 + t[1:] * g0 + 2 * t[1:] * g1)
    c1 = np.concatenate([np.zeros((len(values), 1)), np.cumsum(seg1, axis=1)], axis=1)
    c2 = np.concatenate([np.zeros((len(values), 1)), np.cumsum(seg2, axis=1)], axis=1)
    tq = np.clip(tau, 0.0, t[-1])
    k = np.minimum((tq / step).astype(int), n - 2)
    u = tq - t[k]
    a = values[:, k]
    d = (values[:, k + 1] - a) / step
    G1 = c1[:, k] + a * u + d * u**2 / 2
    G2 = c2[:, k] + t[k] * (a * u + d * u**2 / 2) + a * u**2 / 2 + d * u**3 / 3
    return G1, G2


def moving_green_functions(
    speed: float,
    track: TrackParameters | None = None,
    numerics: TrackNumerics | None = None,
    *,
    use_cache: bool = True,
) -> MovingGreenFunctions:
    """Moving Green's functions of the track for train speed ``speed`` (eq. 2).

    Read off the cached stationary responses (see the module docstring): about a millisecond per
    speed once those are in memory. A speed above ``numerics.max_speed`` widens the wedge, which
    means a new one-off precompute.

    Parameters
    ----------
    speed : float
        v, m/s (> 0).
    track, numerics : optional
        Default: the paper's track, ``TrackNumerics()``.
    use_cache : bool
        Use the disk cache.
    """
    if not (isinstance(speed, int | float) and math.isfinite(speed) and speed > 0):
        raise WheelrailError(f"speed must be positive (m/s), got {speed!r}")
    numerics = TrackNumerics() if numerics is None else numerics
    if speed > numerics.max_speed:
        from dataclasses import replace

        numerics = replace(numerics, max_speed=float(speed))
    response = stationary_track_response(track, numerics, use_cache=use_cache)
    return moving_from_stationary(response, speed)


def moving_from_stationary(response: StationaryTrackResponse, speed: float) -> MovingGreenFunctions:
    """Read the moving Green's functions for ``speed`` (m/s) off stored stationary responses."""
    if speed > response.numerics.max_speed * (1 + 1e-12):
        raise WheelrailError(
            f"speed {speed * 3.6:.1f} km/h exceeds the {response.numerics.max_speed * 3.6:.1f} km/h "
            "the stored responses cover"
        )
    values = np.empty((len(response.excitation_positions), response.n_samples))
    _read_wedge(response.data, response.wedge_nodes, response.offsets, response.first_node_offsets,
                response.element_length, response.shear_parameter, response.time_step, float(speed), values)
    L = response.track.support.sleeper_spacing
    n_fine = BAY_REFINEMENT * len(values)
    return MovingGreenFunctions(
        speed=float(speed),
        sleeper_spacing=L,
        excitation_positions=np.arange(n_fine) * (L / n_fine),
        time_step=response.time_step,
        values=refine_across_bay(values, BAY_REFINEMENT),
        track=response.track,
        numerics=response.numerics,
    )


# --------------------------------------------------------------------------------------------------
# Receptance peaks
# --------------------------------------------------------------------------------------------------

def receptance_peaks(model: TrackFEModel) -> dict[str, float]:
    """Resonance frequencies of the track, Hz, read off its receptance in the central bay.

    ``sleeper_on_ballast_hz`` and ``rail_on_pad_hz``: the two most prominent peaks of the point
    receptance above a sleeper below 700 Hz (track mass on ballast; rail on pads with sleepers
    nearly at rest). ``pinned_pinned_hz``: the highest peak of the midspan point receptance between
    700 and 1500 Hz (bending wavelength twice the sleeper spacing).
    """
    from scipy.signal import find_peaks

    L = model.params.support.sleeper_spacing
    x_sleeper = (model.params.n_bays // 2) * L
    f_low = np.arange(20.0, 700.0, 1.0)
    a = np.abs(track_receptance(model, f_low, x_sleeper))
    peaks, props = find_peaks(a, prominence=0.0)
    top = peaks[np.argsort(props["prominences"])[-2:]]
    if len(top) < 2:
        raise WheelrailError("could not find two support resonances below 700 Hz in the receptance")
    f_sb, f_rp = sorted(f_low[top])
    f_pp = np.arange(700.0, 1500.0, 0.5)
    a_mid = np.abs(track_receptance(model, f_pp, x_sleeper + L / 2))
    return {
        "sleeper_on_ballast_hz": float(f_sb),
        "rail_on_pad_hz": float(f_rp),
        "pinned_pinned_hz": float(f_pp[np.argmax(a_mid)]),
    }
