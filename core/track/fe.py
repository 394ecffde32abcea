"""Track FE model (paper section 2.2): Rayleigh-Timoshenko rail elements on discrete supports, banded
assembly, receptances and the resonance frequencies read off them. See ``wheelrail.core.track``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import scipy.sparse as sp

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import TrackParameters

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


def shear_parameter_of(rail, length: float):
    """Phi = 12 EI / (kGA l^2) of a Rayleigh-Timoshenko element of length ``length`` (m)."""
    return 12.0 * rail.bending_stiffness / (rail.shear_stiffness * np.asarray(length) ** 2)


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
        excitation positions and the response near them are: ``TrackNumerics.refined_elements_per_bay``).

    Returns
    -------
    TrackFEModel
    """
    import scipy.sparse as sp

    rail, sup = track.rail, track.support
    L = sup.sleeper_spacing
    per_bay = np.full(track.n_bays, elements_per_bay, dtype=np.int64)
    if refined is not None:
        first, count, fine = refined
        per_bay[first : first + count] = fine
    node_x = np.concatenate([j * L + np.arange(n) * (L / n) for j, n in enumerate(per_bay)] + [[track.n_bays * L]])
    n_el = len(node_x) - 1
    support_nodes = np.concatenate([[0], np.cumsum(per_bay)])
    is_support = np.zeros(n_el + 1, dtype=bool)
    is_support[support_nodes] = True
    # DOF numbering node by node keeps the matrices banded
    w_dof = np.empty(n_el + 1, dtype=np.int64)
    th_dof = np.empty(n_el + 1, dtype=np.int64)
    sleeper_dof = []
    k = 0
    for node in range(n_el + 1):
        w_dof[node], th_dof[node] = k, k + 1
        k += 2
        if is_support[node]:
            sleeper_dof.append(k)
            k += 1
    n_dof = k
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
    K = sp.coo_matrix((np.concatenate(kv), (rows, cols)), shape=(n_dof, n_dof)).tolil()
    M = sp.coo_matrix((np.concatenate(mv), (rows, cols)), shape=(n_dof, n_dof)).tolil()
    C = sp.lil_matrix((n_dof, n_dof))
    for node, s in zip(support_nodes, sleeper_dof, strict=True):
        r = w_dof[node]
        for mat, pad, ballast in (
            (K, sup.pad_stiffness, sup.ballast_stiffness),
            (C, sup.pad_damping, sup.ballast_damping),
        ):
            mat[r, r] += pad
            mat[r, s] -= pad
            mat[s, r] -= pad
            mat[s, s] += pad + ballast
        M[s, s] += sup.sleeper_mass
    return TrackFEModel(
        params=track,
        element_length=L / elements_per_bay,
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
    h = np.diff(model.node_x)[element]
    N = timoshenko_shape_functions(xi, h, shear_parameter_of(model.params.rail, h))
    dofs = np.stack(
        [model.w_dof[element], model.theta_dof[element], model.w_dof[element + 1], model.theta_dof[element + 1]],
        axis=-1,
    )
    Kb, Cb, Mb = model.banded(model.K), model.banded(model.C), model.banded(model.M)
    out = np.empty((len(f), len(x_resp)), dtype=complex)
    for i, fi in enumerate(f):
        w = 2 * np.pi * fi
        u = solve_banded((HALF_BANDWIDTH, HALF_BANDWIDTH), Kb - w**2 * Mb + 1j * w * Cb, load, check_finite=False)
        out[i] = np.sum(N * u[dofs], axis=-1)
    if x_response is None or np.ndim(x_response) == 0:
        return out[:, 0]
    return out


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
