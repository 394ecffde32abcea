"""Axisymmetric finite elements with circumferential harmonics: the wheel's natural frequencies and mode shapes.

The wheel is a solid of revolution; its displacement is a sum over circumferential harmonics n = 0, 1, 2, ...
(n nodal diameters), each of the form (the "symmetric" set; the "antisymmetric" set, cos and sin swapped, has
the same frequencies and is not excited by a radial or axial force at theta = 0)::

    u_r = U_r(r, z) cos(n theta),  u_z = U_z(r, z) cos(n theta),  u_theta = U_theta(r, z) sin(n theta)

(at n = 0 the second set is the torsional one, u_theta = U_theta(r, z), kept with it). The harmonics are
uncoupled: each has its own stiffness and mass matrices on the cross-section (Zienkiewicz & Taylor, *The
Finite Element Method*, vol. 1, ch. 9 "axisymmetric solids under non-symmetric load"), from the strains::

    eps_r = dU_r/dr,  eps_z = dU_z/dz,  eps_theta = (U_r + n U_theta) / r,  gamma_rz = dU_r/dz + dU_z/dr,
    gamma_r_theta = -n U_r / r + dU_theta/dr - U_theta / r,  gamma_z_theta = -n U_z / r + dU_theta/dz

(times cos or sin), linear isotropic elasticity, and the integral over theta (2 pi at n = 0, pi otherwise)::

    K_n = c_n int B_n^T D B_n r dr dz,   M_n = c_n int rho N^T N r dr dz,   B_n = B_0 + n B_1

so K_n = K_00 + n (K_01 + K_10) + n^2 K_11 is assembled once for all n. Elements: 6-node triangles
(``mesh``), a 6-point Gauss rule (exact for the mass matrix). Boundary condition: the bore (the axle seat) is
clamped, as TWINS constrains the hub's inner edge (the axle is much stiffer than the web), or free. Nodes on
the axis (an outline reaching r = 0) get the conditions that keep the displacement single-valued there.

Natural frequencies by shift-invert Lanczos (``scipy.sparse.linalg.eigsh``) per n, every mode up to
``max_frequency``; modes are mass-normalised (phi^T M_n phi = 1, kg^-1/2 m ... i.e. displacement per unit
modal coordinate). Families: the displacement component with the largest kinetic energy: "axial"
(out-of-plane, U_z), "radial" (in-plane, U_r), "circumferential" (U_theta).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh, splu

from wheelrail.core.errors import WheelrailError
from wheelrail.core.modal_wheel.mesh import Mesh

__all__ = ["FAMILIES", "STEEL", "Material", "harmonic_matrices", "HarmonicModel", "harmonic_modes"]

FAMILIES = ("axial", "radial", "circumferential")


@dataclass(frozen=True)
class Material:
    """Linear isotropic elastic material: ``young`` (Pa), ``poisson`` (-), ``density`` (kg/m^3)."""

    young: float = 2.1e11
    poisson: float = 0.3
    density: float = 7850.0

    def elasticity(self) -> np.ndarray:
        """D (6 x 6) for strains (eps_r, eps_z, eps_theta, gamma_rz, gamma_r_theta, gamma_z_theta), Pa."""
        e, nu = self.young, self.poisson
        lam, mu = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
        d = np.zeros((6, 6))
        d[:3, :3] = lam
        d[np.arange(3), np.arange(3)] = lam + 2 * mu
        d[np.arange(3, 6), np.arange(3, 6)] = mu
        return d


STEEL = Material()  # wheel steel as the track's rail: E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3

# 6-point Gauss rule on the reference triangle (degree 4; Dunavant 1985), weights summing to 1/2
_A, _B = 0.445948490915965, 0.091576213509771
_GAUSS = np.array([[_A, _A], [1 - 2 * _A, _A], [_A, 1 - 2 * _A], [_B, _B], [1 - 2 * _B, _B], [_B, 1 - 2 * _B]])
_WEIGHTS = 0.5 * np.array([0.223381589678011] * 3 + [0.109951743655322] * 3)


def _shape(xi: np.ndarray, eta: np.ndarray):
    """6-node triangle shape functions (corners, then mid-sides 0-1, 1-2, 2-0) and their derivatives."""
    l1 = 1 - xi - eta
    corners = [l1 * (2 * l1 - 1), xi * (2 * xi - 1), eta * (2 * eta - 1)]
    n = np.stack([*corners, 4 * l1 * xi, 4 * xi * eta, 4 * eta * l1], -1)
    zero = np.zeros_like(xi)
    d_xi = np.stack([1 - 4 * l1, 4 * xi - 1, zero, 4 * (l1 - xi), 4 * eta, -4 * eta], -1)
    d_eta = np.stack([1 - 4 * l1, zero, 4 * eta - 1, -4 * xi, 4 * xi, 4 * (l1 - eta)], -1)
    return n, np.stack([d_xi, d_eta], -1)  # (G, 6), (G, 6, 2)


def _gauss_fields(mesh: Mesh):
    """Shape functions, their (r, z) derivatives, r and weight x |J| at each element's Gauss points."""
    n, dn_ref = _shape(_GAUSS[:, 0], _GAUSS[:, 1])
    x = mesh.nodes[mesh.triangles]  # (E, 6, 2)
    jac = np.einsum("gia,eib->egab", dn_ref, x)
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    if np.any(det <= 0):
        raise WheelrailError("the cross-section's mesh has inverted elements")
    inv = np.linalg.inv(jac)
    dn = np.einsum("egba,gia->egib", inv, dn_ref)  # (E, G, 6, 2): dN/dr, dN/dz
    r = np.einsum("gi,ei->eg", n, x[..., 0])
    return n, dn, r, det * _WEIGHTS


def _strain_parts(n, dn, r):
    """B_0 and B_1 (B_n = B_0 + n B_1) at each Gauss point: (E, G, 6, 18)."""
    e, g = r.shape
    b0, b1 = np.zeros((e, g, 6, 18)), np.zeros((e, g, 6, 18))
    n_over_r = n[None, :, :] / r[..., None]
    dr, dz = dn[..., 0], dn[..., 1]
    ur, uz, ut = slice(0, 18, 3), slice(1, 18, 3), slice(2, 18, 3)
    b0[..., 0, ur] = dr
    b0[..., 1, uz] = dz
    b0[..., 2, ur] = n_over_r
    b1[..., 2, ut] = n_over_r
    b0[..., 3, ur] = dz
    b0[..., 3, uz] = dr
    b1[..., 4, ur] = -n_over_r
    b0[..., 4, ut] = dr - n_over_r
    b1[..., 5, uz] = -n_over_r
    b0[..., 5, ut] = dz
    return b0, b1


def _assemble(mesh: Mesh, blocks: np.ndarray) -> sp.csr_matrix:
    dofs = (3 * mesh.triangles[:, :, None] + np.arange(3)).reshape(len(mesh.triangles), 18)
    rows = np.broadcast_to(dofs[:, :, None], blocks.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], blocks.shape).ravel()
    size = 3 * len(mesh.nodes)
    return sp.coo_matrix((blocks.ravel(), (rows, cols)), shape=(size, size)).tocsr()


@dataclass(frozen=True)
class HarmonicModel:
    """The cross-section's matrices without the theta integral: K_n / c_n = k00 + n k01 + n^2 k11, M_n / c_n = m."""

    mesh: Mesh
    k00: sp.csr_matrix
    k01: sp.csr_matrix
    k11: sp.csr_matrix
    m: sp.csr_matrix

    def matrices(self, harmonic: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """(K_n, M_n) with the theta integral c_n (2 pi at n = 0, else pi), N/m and kg."""
        c = 2 * np.pi if harmonic == 0 else np.pi
        return c * (self.k00 + harmonic * self.k01 + harmonic**2 * self.k11), c * self.m


def harmonic_matrices(mesh: Mesh, material: Material = STEEL) -> HarmonicModel:
    """The stiffness and mass matrices of every harmonic (module docstring); DOFs 3 per node (U_r, U_z, U_theta)."""
    n, dn, r, weight = _gauss_fields(mesh)
    b0, b1 = _strain_parts(n, dn, r)
    d = material.elasticity()
    w = weight * r
    k = {}
    for name, (ba, bb) in {"00": (b0, b0), "01": (b0, b1), "11": (b1, b1)}.items():
        k[name] = np.einsum("egki,kl,eglj,eg->eij", ba, d, bb, w, optimize=True)
    k["01"] = k["01"] + np.transpose(k["01"], (0, 2, 1))
    scalar = material.density * np.einsum("gi,gj,eg->eij", n, n, w)
    mass = np.einsum("eij,ab->eiajb", scalar, np.eye(3)).reshape(-1, 18, 18)
    return HarmonicModel(mesh, _assemble(mesh, k["00"]), _assemble(mesh, k["01"]), _assemble(mesh, k["11"]),
                         _assemble(mesh, mass))  # fmt: skip


def fixed_dofs(mesh: Mesh, harmonic: int, bore_radius: float | None) -> np.ndarray:
    """DOFs held at zero: every DOF of the bore's nodes (``bore_radius``; None: a free hub) and the axis's."""
    r = mesh.nodes[:, 0]
    fixed = []
    if bore_radius is not None:
        bore = np.flatnonzero(r <= bore_radius + 1e-9)
        fixed += [3 * bore, 3 * bore + 1, 3 * bore + 2]
    axis = np.flatnonzero(r <= 1e-9)
    components = {0: (0, 2), 1: (1,)}.get(harmonic, (0, 1, 2))
    fixed += [3 * axis + c for c in components]
    return np.unique(np.concatenate(fixed)) if fixed else np.zeros(0, dtype=np.int64)


@dataclass(frozen=True)
class HarmonicModes:
    """Modes of one harmonic: ``frequency`` (k,) Hz; ``shapes`` (k, 3 n_nodes), mass-normalised; ``family``
    (k,) indices into FAMILIES; ``static`` (2, 2): static flexibility at the contact (radial, axial), m/N;
    ``static_fields`` (2, 3 n_nodes): the static displacement per unit radial and axial force there, m/N."""

    frequency: np.ndarray
    shapes: np.ndarray
    family: np.ndarray
    static: np.ndarray
    static_fields: np.ndarray


def harmonic_modes(
    model: HarmonicModel, harmonic: int, max_frequency: float, bore_radius: float | None, contact_node: int
) -> HarmonicModes:
    """Every mode of harmonic ``harmonic`` up to ``max_frequency`` (Hz), and the static flexibility at the contact."""
    stiffness, mass = model.matrices(harmonic)
    size = stiffness.shape[0]
    free = np.setdiff1d(np.arange(size), fixed_dofs(model.mesh, harmonic, bore_radius))
    k, m = stiffness[free][:, free].tocsc(), mass[free][:, free].tocsc()
    shift = -((2 * np.pi * 1.0) ** 2)  # below zero: the free hub's rigid-body modes are found too
    count = min(12, len(free) - 2)
    while True:
        values, vectors = eigsh(k, count, m, sigma=shift, which="LM")
        order = np.argsort(values)
        values, vectors = values[order], vectors[:, order]
        if values[-1] > (2 * np.pi * max_frequency) ** 2 or count >= len(free) - 2:
            break
        count = min(2 * count, len(free) - 2)
    keep = values <= (2 * np.pi * max_frequency) ** 2
    shapes = np.zeros((int(keep.sum()), size))
    shapes[:, free] = vectors[:, keep].T
    shapes *= np.sign(shapes[np.arange(len(shapes)), np.argmax(np.abs(shapes), axis=1)])[:, None]
    frequency = np.sqrt(np.maximum(values[keep], 0.0)) / (2 * np.pi)
    singular = bore_radius is None and harmonic < 2  # a free hub's rigid-body motions: no static flexibility
    fields = np.zeros((2, size))
    if not singular:
        fields[:, free] = _static(k, free, contact_node).T
    static = fields[:, [3 * contact_node, 3 * contact_node + 1]].T
    return HarmonicModes(frequency, shapes, _families(shapes, mass), static, fields)


def _families(shapes: np.ndarray, mass: sp.csr_matrix) -> np.ndarray:
    energy = np.stack([np.einsum("ki,ki->k", shapes[:, c::3], (mass[c::3, c::3] @ shapes[:, c::3].T).T) for c in
                       (1, 0, 2)], axis=1)  # fmt: skip
    return np.argmax(energy, axis=1) if len(shapes) else np.zeros(0, dtype=np.int64)


def _static(k, free: np.ndarray, contact_node: int) -> np.ndarray:
    """(free DOFs, 2): static displacements per unit radial and axial force at the contact, m/N."""
    where = np.searchsorted(free, [3 * contact_node, 3 * contact_node + 1])
    load = np.zeros((len(free), 2))
    load[where, [0, 1]] = 1.0
    return splu(k).solve(load)
