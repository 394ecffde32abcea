"""Track FE model (paper section 2.2): Rayleigh-Timoshenko rail elements on discrete supports, banded
assembly and receptances (their resonances: ``resonances``). See ``wheelrail.core.track``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import scipy.sparse as sp

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import TrackParameters
from wheelrail.core.spectra.bands import FORCE_BAND_RANGE

HALF_BANDWIDTH = 4


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
    Mt = (m * L / (1 + phi) ** 2) * np.array([[a, b, c, -d], [b, e, d, -f], [c, d, a, -b], [-d, -f, -b, e]])
    g = 6 / 5
    h = (1 / 10 - phi / 2) * L
    i = (2 / 15 + phi / 6 + phi**2 / 3) * L**2
    j = (-1 / 30 - phi / 6 + phi**2 / 6) * L**2
    Mr = (rI / ((1 + phi) ** 2 * L)) * np.array([[g, h, -g, h], [h, i, -h, j], [-g, -h, g, -h], [h, j, -h, i]])
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


# --------------------------------------------------------------------------------------------------
# Rail damping in the time domain: a constant loss factor fitted by relaxation terms
# --------------------------------------------------------------------------------------------------

RELAXATION_FREQUENCIES_HZ = (20.0, 100.0, 490.0, 2450.0, 12000.0)
"""Relaxation frequencies 1 / (2 pi tau_j) of the rail's time-domain damping, spaced evenly in lg f around the
fitted band (one per 0.7 decade: the loss factor's ripple is then within 4 %, more terms change nothing)."""
RELAXATION_FIT_BAND_HZ = FORCE_BAND_RANGE
"""Band over which the relaxation terms fit the constant loss factor (the force spectra's 50 Hz-8 kHz)."""


@dataclass(frozen=True)
class RailRelaxation:
    """The rail's complex stiffness in the time domain, a standard linear solid with several relaxation terms:
    K_rail(w) = K_rail (c0 + sum_j g_j i w tau_j / (1 + i w tau_j)) (``rail_relaxation``).

    Attributes
    ----------
    c0 : float
        Static fraction of the rail's stiffness.
    weights : ndarray (J,)
        g_j, the fractions relaxing with each tau_j.
    times : ndarray (J,)
        tau_j, s.
    """

    c0: float
    weights: np.ndarray
    times: np.ndarray

    def modulus(self, frequency) -> np.ndarray:
        """The complex stiffness factor c0 + sum_j g_j i w tau_j / (1 + i w tau_j) at ``frequency`` (Hz)."""
        iwt = 2j * np.pi * np.asarray(frequency, dtype=float)[..., None] * self.times
        return self.c0 + np.sum(self.weights * iwt / (1 + iwt), axis=-1)


def rail_relaxation(loss_factor: float) -> RailRelaxation:
    """Relaxation terms whose loss factor Im/Re stays close to ``loss_factor`` over ``RELAXATION_FIT_BAND_HZ``.

    A constant loss factor, K (1 + i eta) at every frequency, is not causal and has no time-domain form. Terms
    g_j i w tau_j / (1 + i w tau_j) at the ``RELAXATION_FREQUENCIES_HZ`` have a causal one (each an internal
    variable q_j with tau_j dq_j/dt = u - q_j): their weights g_j >= 0 are fitted by non-negative least squares
    so that Im = eta Re across the band (three passes, as Re depends on them), and c0 so that Re averages 1 in
    lg f over the band. Causality ties Re to Im (Kramers-Kronig): Re then rises across the band by about
    (2 eta / pi) ln(f_2 / f_1), +-3 % at eta = 0.02, +-16 % at 0.1. Measured: Im/Re within 4 % of eta
    (``tests/physics/test_track_damping.py``).
    """
    from scipy.optimize import nnls

    times = 1.0 / (2 * np.pi * np.asarray(RELAXATION_FREQUENCIES_HZ))
    f = np.geomspace(*RELAXATION_FIT_BAND_HZ, 200)
    wt = 2 * np.pi * f[:, None] * times
    d_re, d_im = wt**2 / (1 + wt**2), wt / (1 + wt**2)
    real = np.ones(len(f))
    for _ in range(3):
        weights, _ = nnls(d_im, loss_factor * real)
        c0 = 1.0 - float(np.mean(d_re @ weights))
        real = c0 + d_re @ weights
    return RailRelaxation(c0=c0, weights=weights, times=times)


@dataclass(frozen=True)
class TrackFEModel:
    """Assembled FE model of the finite track.

    Attributes
    ----------
    params : TrackParameters
    element_length : float
        Length of the elements outside the refined bays, m.
    node_x : ndarray
        Rail node positions, m (0 .. n_bays L_S), increasing; elements are finer in the refined bays.
    w_dof, theta_dof : ndarray of int
        DOF index of each rail node's displacement and rotation.
    sleeper_dof : ndarray of int
        DOF index of each sleeper (one per support at x = j L_S).
    M, C, K : scipy.sparse.csr_matrix
        Mass, damping, stiffness (SI), the rail's stiffness undamped.
    K_rail : scipy.sparse.csr_matrix
        The rail elements' part of K (bending and shear), which the rail's loss factor multiplies.
    half_bandwidth : int
        Half-bandwidth of the matrices (``HALF_BANDWIDTH`` for point supports; wider pads couple more nodes
        to their sleeper).
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
    K_rail: sp.csr_matrix
    half_bandwidth: int = HALF_BANDWIDTH

    @property
    def n_dof(self) -> int:
        return self.M.shape[0]

    @property
    def shear_parameter(self) -> float:
        """Phi of the elements outside the refined bays (``shear_parameter_of`` for any length)."""
        return shear_parameter_of(self.params.rail, self.element_length)

    def locate(self, x) -> tuple[np.ndarray, np.ndarray]:
        """Element index and local coordinate xi in [0, 1] of rail positions x (m)."""
        x = np.asarray(x, dtype=float)
        n_el = len(self.node_x) - 1
        end = self.node_x[-1]
        if np.any(x < 0) or np.any(x > end * (1 + 1e-12)):
            raise WheelrailError(f"position outside the track model [0, {end:.3f}] m")
        element = np.clip(np.searchsorted(self.node_x, x, side="right") - 1, 0, n_el - 1)
        return element, (x - self.node_x[element]) / np.diff(self.node_x)[element]

    def load_vector(self, x: float) -> np.ndarray:
        """Consistent nodal load vector of a unit vertical force at rail position x (m)."""
        element, xi = self.locate(x)
        h = float(self.node_x[int(element) + 1] - self.node_x[int(element)])
        N = timoshenko_shape_functions(xi, h, shear_parameter_of(self.params.rail, h))
        f = np.zeros(self.n_dof)
        e = int(element)
        dofs = [self.w_dof[e], self.theta_dof[e], self.w_dof[e + 1], self.theta_dof[e + 1]]
        f[dofs] = N
        return f

    def banded(self, matrix) -> np.ndarray:
        """Matrix in LAPACK general band form (for ``scipy.linalg.solve_banded``)."""
        return _to_band(matrix, self.half_bandwidth, self.half_bandwidth)

    def frequency_domain_bands(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(K + i eta K_rail, C, M) in LAPACK general band form: the dynamic stiffness at w is
        K + i eta K_rail - w^2 M + i w C, the rail's loss factor eta exact (hysteretic) in the frequency domain.
        K is real (the band form of ``self.K``) for an undamped rail."""
        kb = self.banded(self.K)
        eta = self.params.rail.loss_factor
        if eta > 0:
            kb = kb + 1j * eta * self.banded(self.K_rail)
        return kb, self.banded(self.C), self.banded(self.M)

    def solve(self, kb, cb, mb, frequency: float, load: np.ndarray) -> np.ndarray:
        """Displacements for ``load`` at ``frequency`` (Hz) from ``frequency_domain_bands``' arrays."""
        from scipy.linalg import solve_banded

        w = 2 * np.pi * frequency
        u = self.half_bandwidth
        return solve_banded((u, u), kb - w**2 * mb + 1j * w * cb, load, check_finite=False)


def _to_band(matrix, lower: int, upper: int) -> np.ndarray:
    import scipy.sparse as sp  # scipy imported where used: a cached `wheelrail track` never needs it

    A = sp.coo_matrix(matrix)
    n = A.shape[0]
    ab = np.zeros((lower + upper + 1, n), dtype=A.dtype)
    if np.any(A.row - A.col > lower) or np.any(A.col - A.row > upper):
        raise AssertionError("matrix is wider than its band")
    np.add.at(ab, (upper + A.row - A.col, A.col), A.data)
    return ab


def to_upper_band(matrix, upper: int) -> np.ndarray:
    """Symmetric matrix in LAPACK upper band form (for ``cholesky_banded``)."""
    import scipy.sparse as sp

    return _to_band(sp.triu(matrix), 0, upper)


def shear_parameter_of(rail, length: float):
    """Phi = 12 EI / (kGA l^2) of a Rayleigh-Timoshenko element of length ``length`` (m)."""
    return 12.0 * rail.bending_stiffness / (rail.shear_stiffness * np.asarray(length) ** 2)


def _number_dofs(n_nodes: int, support_nodes):
    """DOF numbering node by node (w, theta, then the sleeper at a support node): the matrices stay banded."""
    is_support = np.zeros(n_nodes, dtype=bool)
    is_support[support_nodes] = True
    w_dof = np.empty(n_nodes, dtype=np.int64)
    th_dof = np.empty(n_nodes, dtype=np.int64)
    sleeper_dof = []
    k = 0
    for node in range(n_nodes):
        w_dof[node], th_dof[node] = k, k + 1
        k += 2
        if is_support[node]:
            sleeper_dof.append(k)
            k += 1
    return w_dof, th_dof, sleeper_dof


REFINED_LEAD_IN_BAYS = 1
"""Bays before the refined bays of ``assemble_track`` meshed with the refined elements too. The first excitation
position is the first refined bay's first sleeper: at the edge of the refined mesh (coarse elements on one side)
its impulse response would begin unlike every other position's (its first sample 1.5 times theirs), and that one
row's error, met once per bay, would put 5-16 N into every sleeper-passing harmonic k = 8-20 with a 150 mm pad,
where the first-order estimate is 0.1-2 N (``validation/pad_harmonics.py``, docs/validation.md)."""


def track_mesh(
    n_bays: int, sleeper_spacing: float, elements_per_bay: int, refined: tuple[int, int, int] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The mesh of :func:`assemble_track` (its arguments), without the matrices: the elements of each bay and the
    rail nodes' positions, m (bay j's ``per_bay[j]`` equal elements from its sleeper at j ``sleeper_spacing``)."""
    L = sleeper_spacing
    per_bay = np.full(n_bays, elements_per_bay, dtype=np.int64)
    if refined is not None:
        first, count, fine = refined
        per_bay[max(first - REFINED_LEAD_IN_BAYS, 0) : first + count] = fine
    node_x = np.concatenate([j * L + np.arange(n) * (L / n) for j, n in enumerate(per_bay)] + [[n_bays * L]])
    return per_bay, node_x


def assemble_track(
    track: TrackParameters, elements_per_bay: int = 16, refined: tuple[int, int, int] | None = None
) -> TrackFEModel:
    """Assemble mass, damping and stiffness of the discretely supported track.

    Parameters
    ----------
    track : TrackParameters
    elements_per_bay : int
        Beam elements per sleeper bay.
    refined : (first_bay, n_bays, elements_per_bay), optional
        Bays first_bay .. first_bay + n_bays - 1 meshed with this many elements instead (where the
        excitation positions and the response near them are: ``TrackNumerics.refined_elements_per_bay``),
        and the ``REFINED_LEAD_IN_BAYS`` bays before them.

    Returns
    -------
    TrackFEModel
    """
    import scipy.sparse as sp

    rail, sup = track.rail, track.support
    L = sup.sleeper_spacing
    per_bay, node_x = track_mesh(track.n_bays, L, elements_per_bay, refined)
    n_el = len(node_x) - 1
    support_nodes = np.concatenate([[0], np.cumsum(per_bay)])
    w_dof, th_dof, sleeper_dof = _number_dofs(n_el + 1, support_nodes)
    n_dof = int(sleeper_dof[-1]) + 1
    element_matrices = {n: timoshenko_element_matrices(rail, L / n) for n in set(per_bay.tolist())}
    rows, cols, kv, mv = [], [], [], []
    for j, n in enumerate(per_bay):
        Ke, Me = element_matrices[int(n)]
        for e in range(support_nodes[j], support_nodes[j + 1]):
            dofs = np.array([w_dof[e], th_dof[e], w_dof[e + 1], th_dof[e + 1]])
            rows.append(np.repeat(dofs, 4))
            cols.append(np.tile(dofs, 4))
            kv.append(Ke.ravel())
            mv.append(Me.ravel())
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    K_rail = sp.coo_matrix((np.concatenate(kv), (rows, cols)), shape=(n_dof, n_dof)).tocsr()
    K = K_rail.tolil()
    M = sp.coo_matrix((np.concatenate(mv), (rows, cols)), shape=(n_dof, n_dof)).tolil()
    C = sp.lil_matrix((n_dof, n_dof))
    for node, s in zip(support_nodes, sleeper_dof, strict=True):
        for dofs, stiffness, damping in pad_couplings(track, node_x, w_dof, th_dof, node):
            for mat, (P, p, total) in ((K, stiffness), (C, damping)):
                # the pad's layer between the rail (dofs) and the rigid sleeper s: [[P, -p], [-p^T, total]]
                for i, di in enumerate(dofs):
                    for j, dj in enumerate(dofs):
                        mat[di, dj] += P[i, j]
                    mat[di, s] -= p[i]
                    mat[s, di] -= p[i]
                mat[s, s] += total
        K[s, s] += sup.ballast_stiffness
        C[s, s] += sup.ballast_damping
        M[s, s] += sup.sleeper_mass
    K = K.tocsr()
    coo = K.tocoo()
    return TrackFEModel(
        params=track,
        element_length=L / elements_per_bay,
        node_x=node_x,
        w_dof=w_dof,
        theta_dof=th_dof,
        sleeper_dof=np.array(sleeper_dof, dtype=np.int64),
        M=M.tocsr(),
        C=C.tocsr(),
        K=K,
        K_rail=K_rail,
        half_bandwidth=max(HALF_BANDWIDTH, int(np.max(np.abs(coo.row - coo.col)))),
    )


_GAUSS_POINTS = 4  # Gauss-Legendre points: exact for N^T N, of degree 6 in x
POINT_PAD_WIDTH = 1e-9
"""A pad narrower than this (m) is a point support: its blocks differ from the point support's by about (w / h)^2,
under 1e-14 on elements h of 1 cm and more (round-off), and a narrower one is not resolved around a sleeper tens of
metres along the rail (1e-311 m vanished there, and k_P / w overflowed)."""


def pad_couplings(track: TrackParameters, node_x, w_dof, th_dof, node: int):
    """The pad at the support ``node`` as (rail dofs, (k, c) parts) blocks: for each part, the rail block
    P = (k_P / w) int N^T N dx, the coupling p = (k_P / w) int N dx to the sleeper and the sleeper's
    (k_P / w) x (length covered); over the element parts within x_S -+ w / 2 (clipped to the rail's ends: the
    two end sleepers' pads cover the half within the rail with the whole k_P, so that w -> 0 is the point
    support everywhere). A point support (w below ``POINT_PAD_WIDTH``): the rail's w DOF at the node, k_P and c_P."""
    sup = track.support
    width = sup.pad_width
    if width < POINT_PAD_WIDTH:
        one = np.ones((1, 1))
        k, c = sup.pad_stiffness, sup.pad_damping
        return [(np.array([w_dof[node]]), (k * one, k * one[0], k), (c * one, c * one[0], c))]
    xs = node_x[node]
    start, end = max(xs - width / 2, node_x[0]), min(xs + width / 2, node_x[-1])
    points, weights = np.polynomial.legendre.leggauss(_GAUSS_POINTS)
    blocks = []
    e = max(int(np.searchsorted(node_x, start, side="right")) - 1, 0)
    while e < len(node_x) - 1 and node_x[e] < end:
        a, b = max(start, node_x[e]), min(end, node_x[e + 1])
        h = node_x[e + 1] - node_x[e]
        if b > a:
            x = 0.5 * (a + b) + 0.5 * (b - a) * points
            N = timoshenko_shape_functions((x - node_x[e]) / h, h, shear_parameter_of(track.rail, h))
            wq = 0.5 * (b - a) * weights
            block = ((N * wq[:, None]).T @ N, wq @ N, b - a)
            dofs = np.array([w_dof[e], th_dof[e], w_dof[e + 1], th_dof[e + 1]])
            k, c = sup.pad_stiffness / (end - start), sup.pad_damping / (end - start)
            blocks.append((dofs, tuple(k * part for part in block), tuple(c * part for part in block)))
        e += 1
    return blocks


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
        alpha_R in m/N, convention x(t) = Re(X e^{i 2 pi f t}); the rail's loss factor exact (hysteretic).

    Raises
    ------
    WheelrailError
        For a negative or non-finite frequency.

    See Also
    --------
    assemble_track : the model.
    wheelrail.core.track.resonances.receptance_peaks : its resonances.

    Examples
    --------
    At the pinned-pinned frequency (943 Hz) the rail is stiff above a sleeper and soft at midspan:

    >>> from wheelrail.core.parameters import TrackParameters
    >>> from wheelrail.core.track import assemble_track, track_receptance
    >>> model = assemble_track(TrackParameters(n_bays=20))
    >>> sleeper = 10 * TrackParameters().support.sleeper_spacing             # m, the central sleeper
    >>> [f"{abs(track_receptance(model, [943.0], x)[0]):.2g}" for x in (sleeper, sleeper + 0.325)]   # m/N
    ['3.4e-10', '1.7e-09']
    """
    f = np.atleast_1d(np.asarray(frequency, dtype=float))
    if not np.all(np.isfinite(f)) or np.any(f < 0):
        raise WheelrailError("track_receptance: frequencies must be finite and >= 0 Hz")
    x_resp = np.atleast_1d(np.asarray(x_excitation if x_response is None else x_response, dtype=float))
    load = model.load_vector(float(x_excitation))
    element, xi = model.locate(x_resp)
    h = np.diff(model.node_x)[element]
    N = timoshenko_shape_functions(xi, h, shear_parameter_of(model.params.rail, h))
    dofs = np.stack(
        [model.w_dof[element], model.theta_dof[element], model.w_dof[element + 1], model.theta_dof[element + 1]],
        axis=-1,
    )
    bands = model.frequency_domain_bands()
    out = np.empty((len(f), len(x_resp)), dtype=complex)
    for i, fi in enumerate(f):
        u = model.solve(*bands, fi, load)
        out[i] = np.sum(N * u[dofs], axis=-1)
    if x_response is None or np.ndim(x_response) == 0:
        return out[:, 0]
    return out
