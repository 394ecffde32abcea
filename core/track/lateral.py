"""The rail's lateral bending and torsion on the discrete supports, in the frequency domain: receptances at the
railhead and the lateral decay rate.

The model (the vertical track's layout of :mod:`wheelrail.core.track.fe`: the same bays, sleepers and pad width;
its element routines):

- **Rail**: a chain of elements with four DOFs per node, (v, psi, phi, phi'): v the lateral displacement of the
  shear centre and psi its Timoshenko rotation about the vertical axis (``fe.timoshenko_element_matrices`` with
  E I_z, kappa G A, m' and rho I_z), phi the twist about the shear centre and phi' = d phi / dx (Hermite cubics:
  the same routine with shear rigid, for E I_w, rho I_p and the warping inertia rho I_w, plus St Venant's
  G J int phi'^2 dx). The rail's mass acts at the centroid, e_c = z_c - z_s above the shear centre: a point at
  height z moves laterally by v - (z - z_s) phi, so the kinetic energy is (m'/2)(v' - e_c phi')^2 +
  (rho I_p / 2) phi'^2 (the coupling mass -m' e_c int N_v^T N_phi dx). Lateral bending about the vertical axis and
  torsion about the shear centre are otherwise uncoupled (the section is symmetric about its vertical axis).
  The rail's loss factor (``RailParameters.loss_factor``) multiplies its stiffness, as in the vertical model.
- **Supports** (:class:`~wheelrail.core.lateral_parameters.LateralParameters`): the pad's lateral stiffness
  between the rail foot (v + z_s phi at its underside) and the half sleeper's mass, which rides on the ballast's
  lateral stiffness; the pad's rotational stiffness between the rail's twist and the sleeper, rigid in roll.
  A pad of width w spreads both over x_S -+ w / 2 (Winkler layers of k / w per metre), as the vertical pad.
  Loss factors on each (hysteretic).
- **Loads** at x0: a lateral force at the railhead (height z_h: generalised forces N_v on v, -(z_h - z_s) N_phi
  on phi); a vertical force F downwards at ``contact_offset`` d from the rail's centreline, whose torque -F d
  twists the rail (generalised force -d N_phi on phi) and so moves the head laterally; a unit torque.

Responses are the railhead's lateral displacement, v - (z_h - z_s) phi, and the twist. The track is the noise
model's: ``track_bays`` bays (240: 78 m each side of the load) so that waves reflected at its free ends come back
attenuated, the load in the central bay. The decay rate is EN 15461's on the railhead's lateral transfer
receptances, as ``wheelrail.core.noise.twins`` does for the vertical one.

A single beam with a rigid cross-section: above about 1.5-2 kHz a real rail's web bends and its foot flaps
(Wu & Thompson, J. Acoust. Soc. Am. 106 (1999) 1369-1376), which this model does not hold.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import TrackParameters
from wheelrail.core.track.fe import POINT_PAD_WIDTH, timoshenko_element_matrices, timoshenko_shape_functions

__all__ = [
    "LateralFEModel",
    "LateralNumerics",
    "LateralReceptances",
    "assemble_lateral_track",
    "lateral_band_frequencies",
    "lateral_decay_rate",
    "lateral_element_matrices",
    "lateral_receptances",
]

DOFS_PER_NODE = 4  # v, psi, phi, phi'
BENDING = np.array([0, 1, 4, 5])  # the element's (v1, psi1, v2, psi2) among its 8 DOFs
TORSION = np.array([2, 3, 6, 7])  # (phi1, phi1', phi2, phi2')
LOG10_E = 10.0 * math.log10(math.e)  # 4.343 dB per neper of energy decay
ABSORBING_LOSS_FACTOR = 0.3
"""The rail's extra loss factor at the very ends of a track with absorbing ends (``assemble_lateral_track``)."""
_GAUSS = np.polynomial.legendre.leggauss(6)  # exact for the products of the elements' cubics (degree 6)


@dataclass(frozen=True, kw_only=True)
class LateralNumerics:
    """How the lateral track is discretised.

    Attributes
    ----------
    track_bays : int
        Sleeper bays of the track model (240, the noise model's: 78 m of rail each side of the load); >= 8.
    absorbing_bays : int
        Bays at each end that absorb the waves reaching them (``assemble_lateral_track``; 20: 13 m, beyond the
        decay rate's 60 m). A rail's lateral waves decay by as little as 0.1 dB/m: free ends 78 m away would
        return them 16 dB down, enough to move the point receptance by +-5 dB above 500 Hz (an undamped rail);
        with these ends it is within 0.2 dB of the infinite track's at the tested frequencies and 0.4 dB near the
        undamped rail's pass-band edges (``tests/physics/test_track_lateral.py``).
    elements_per_bay : int
        Elements per bay (16: 40.6 mm on 0.65 m, >= 9 per lateral bending or torsional wavelength up to 5 kHz): the
        point receptance within 0.07 dB per band of 32 elements', the decay rate within 5 % of theirs at
        250 Hz-5 kHz and within 3 % of a 360-bay track's but in the 500 Hz band of an undamped rail (+40 %: see
        ``points_per_band``) (``validation/lateral_convergence.py``).
    points_per_band : int
        Frequencies per one-third octave band of the decay rate, evenly spread in lg f (as the vertical's). An
        undamped rail has pass-band edges where a wave hardly decays (0.03 dB/m at 449 Hz on the paper's track):
        the value of the band holding one depends on where the points fall (0.28, 0.70 and 0.49 dB/m at 20, 40
        and 80 points in the 500 Hz band); a rail loss factor of 0.01 removes it (1.27-1.29 dB/m).
    decay_length : float
        m of rail over which EN 15461's sum is taken (60, as the vertical's).
    """

    track_bays: int = 240
    absorbing_bays: int = 20
    elements_per_bay: int = 16
    points_per_band: int = 20
    decay_length: float = 60.0

    def __post_init__(self) -> None:
        from wheelrail.core.inputs.checks import integer

        integer("LateralNumerics.track_bays", self.track_bays, 8)
        integer("LateralNumerics.elements_per_bay", self.elements_per_bay, 2)
        integer("LateralNumerics.absorbing_bays", self.absorbing_bays, 0)
        if 2 * self.absorbing_bays > self.track_bays - 4:
            raise WheelrailError(
                f"LateralNumerics.absorbing_bays ({self.absorbing_bays}) leaves under 4 bays of track between the "
                f"absorbing ends of {self.track_bays} bays"
            )
        integer("LateralNumerics.points_per_band", self.points_per_band, 1)
        if not (isinstance(self.decay_length, int | float) and 0 < self.decay_length < math.inf):
            raise WheelrailError(
                f"LateralNumerics.decay_length must be a positive number of m, got {self.decay_length!r}"
            )


@dataclass(frozen=True, eq=False)
class LateralReceptances:
    """The lateral track's receptances (``lateral_receptances``), convention x(t) = Re(X e^{i 2 pi f t}).

    Attributes
    ----------
    frequency : ndarray (F,)
        Hz.
    lateral_point : ndarray of complex
        The railhead's lateral displacement per unit lateral force at the railhead, m/N.
    vertical_to_lateral : ndarray of complex
        The railhead's lateral displacement per unit vertical (downward) force applied ``contact_offset`` from the
        rail's centreline, m/N (positive offset: the head moves towards it under a static load).
    torsional_point : ndarray of complex
        The rail's twist per unit torque about its axis, rad/(N m).

    Each of shape (F,) for a scalar ``x_response``, else (F, len(x_response)).
    """

    frequency: np.ndarray
    lateral_point: np.ndarray
    vertical_to_lateral: np.ndarray
    torsional_point: np.ndarray


def lateral_element_matrices(track: TrackParameters, length: float) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness (undamped) and consistent mass of one lateral rail element, DOFs (v, psi, phi, phi') per node.

    Returns
    -------
    K, M : ndarray (8, 8)
        SI (N/m, N, N m and N m^2 blocks; kg, kg m, kg m^2).
    """
    sec, m = track.lateral.section, track.rail.mass_per_length
    rho = m / sec.area  # the rail's density: its mass per metre over the section's area
    e_c = sec.centroid_height - sec.shear_centre_height
    E, L = sec.youngs_modulus, length
    bending = SimpleNamespace(
        bending_stiffness=E * sec.lateral_second_moment,
        shear_stiffness=sec.lateral_shear_coefficient * sec.shear_modulus * sec.area,
        mass_per_length=m,
        rotary_inertia_per_length=rho * sec.lateral_second_moment,
    )
    torsion = SimpleNamespace(  # Hermite cubics: shear rigid; rho I_p about the shear centre, warping inertia
        bending_stiffness=E * sec.warping_constant,
        shear_stiffness=math.inf,
        mass_per_length=rho * sec.polar_second_moment + m * e_c**2,
        rotary_inertia_per_length=rho * sec.warping_constant,
    )
    kb, mb = timoshenko_element_matrices(bending, L)
    kt, mt = timoshenko_element_matrices(torsion, L)
    kt = kt + (sec.shear_modulus * sec.torsion_constant / (30 * L)) * np.array(
        [
            [36, 3 * L, -36, 3 * L],
            [3 * L, 4 * L**2, -3 * L, -(L**2)],
            [-36, -3 * L, 36, -3 * L],
            [3 * L, -(L**2), -3 * L, 4 * L**2],
        ]
    )
    xi, weight = 0.5 * (_GAUSS[0] + 1), 0.5 * L * _GAUSS[1]
    n_v = timoshenko_shape_functions(xi, L, 12 * bending.bending_stiffness / (bending.shear_stiffness * L**2))
    n_phi = timoshenko_shape_functions(xi, L, 0.0)
    coupling = -m * e_c * (n_v * weight[:, None]).T @ n_phi
    K, M = np.zeros((8, 8)), np.zeros((8, 8))
    K[np.ix_(BENDING, BENDING)], K[np.ix_(TORSION, TORSION)] = kb, kt
    M[np.ix_(BENDING, BENDING)], M[np.ix_(TORSION, TORSION)] = mb, mt
    M[np.ix_(BENDING, TORSION)], M[np.ix_(TORSION, BENDING)] = coupling, coupling.T
    return K, M


@dataclass(frozen=True, eq=False)
class LateralFEModel:
    """The assembled lateral track (``assemble_lateral_track``).

    Attributes
    ----------
    params : TrackParameters
        The track, ``n_bays`` as assembled.
    node_x : ndarray
        Rail node positions, m (0 .. n_bays L_S), ``elements_per_bay`` equal elements per bay.
    node_dofs : ndarray of int (nodes, 4)
        Each node's (v, psi, phi, phi') DOFs, numbered node by node with each support's sleeper DOF right after
        its node (the matrices stay banded).
    sleeper_dof : ndarray of int
        DOF of each sleeper's lateral displacement (one per support at x = j L_S).
    parts : dict
        "rail", "pad", "ballast" (stiffness), "absorber" (the absorbing ends' rail stiffness, weighted) and "mass":
        each in LAPACK general band form (``half_bandwidth`` both sides); the dynamic stiffness at w is the sum
        over the stiffness parts of (1 + i eta_part) K_part, plus i ``ABSORBING_LOSS_FACTOR`` K_absorber, minus
        w^2 M.
    loss_factors : dict
        eta of each stiffness part: the rail's, the pad's lateral, the ballast's lateral.
    half_bandwidth : int
    """

    params: TrackParameters
    node_x: np.ndarray
    node_dofs: np.ndarray
    sleeper_dof: np.ndarray
    parts: dict
    loss_factors: dict
    half_bandwidth: int

    @property
    def n_dof(self) -> int:
        return self.parts["mass"].shape[1]

    @functools.cached_property
    def _stiffness(self) -> np.ndarray:
        damped = sum((1 + 1j * eta) * self.parts[name] for name, eta in self.loss_factors.items())
        return damped + 1j * ABSORBING_LOSS_FACTOR * self.parts["absorber"]

    def dynamic_stiffness(self, frequency: float) -> np.ndarray:
        """The dynamic stiffness at ``frequency`` (Hz), band form."""
        return self._stiffness - (2 * np.pi * frequency) ** 2 * self.parts["mass"]

    def solve(self, frequency: float, loads: np.ndarray) -> np.ndarray:
        """Displacements (DOFs, complex) for ``loads`` (DOFs, or DOFs x loads) at ``frequency`` (Hz)."""
        from scipy.linalg import solve_banded

        u = self.half_bandwidth
        return solve_banded((u, u), self.dynamic_stiffness(frequency), loads, check_finite=False)

    def shapes(self, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The element DOFs at rail positions ``x`` (m) and the shape functions of v and phi there: (dofs (n, 8),
        N_v (n, 4), N_phi (n, 4)); N_v over the element's (v1, psi1, v2, psi2), N_phi over its (phi1, phi1', phi2,
        phi2')."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        end = self.node_x[-1]
        if np.any(x < 0) or np.any(x > end * (1 + 1e-12)):
            raise WheelrailError(f"position outside the lateral track model [0, {end:.3f}] m")
        n_el = len(self.node_x) - 1
        element = np.clip(np.searchsorted(self.node_x, x, side="right") - 1, 0, n_el - 1)
        h = self.node_x[1] - self.node_x[0]
        xi = (x - self.node_x[element]) / h
        dofs = np.concatenate([self.node_dofs[element], self.node_dofs[element + 1]], axis=-1)
        return (
            dofs,
            timoshenko_shape_functions(xi, h, _shear_parameter(self.params, h)),
            timoshenko_shape_functions(xi, h, 0.0),
        )

    def railhead_load(self, x: float) -> np.ndarray:
        """Nodal loads of a unit lateral force at the railhead at ``x`` (m)."""
        sec = self.params.lateral.section
        return self._load(x, 1.0, -(sec.head_height - sec.shear_centre_height))

    def torque_load(self, x: float) -> np.ndarray:
        """Nodal loads of a unit torque about the rail's axis at ``x`` (m)."""
        return self._load(x, 0.0, 1.0)

    def _load(self, x: float, on_v: float, on_phi: float) -> np.ndarray:
        dofs, n_v, n_phi = self.shapes(x)
        f = np.zeros(self.n_dof)
        f[dofs[0, BENDING]] += on_v * n_v[0]
        f[dofs[0, TORSION]] += on_phi * n_phi[0]
        return f

    def railhead_and_twist(self, u: np.ndarray, x) -> tuple[np.ndarray, np.ndarray]:
        """The railhead's lateral displacement and the twist at positions ``x`` (m) of the solution ``u``
        (DOFs, or DOFs x loads): arrays (len(x),) or (len(x), loads)."""
        sec = self.params.lateral.section
        dofs, n_v, n_phi = self.shapes(x)
        v = np.einsum("nk,nk...->n...", n_v, u[dofs[:, BENDING]])
        phi = np.einsum("nk,nk...->n...", n_phi, u[dofs[:, TORSION]])
        return v - (sec.head_height - sec.shear_centre_height) * phi, phi


def _shear_parameter(track: TrackParameters, length: float) -> float:
    sec = track.lateral.section
    return (
        12
        * sec.lateral_second_moment
        * sec.youngs_modulus
        / (sec.lateral_shear_coefficient * sec.shear_modulus * sec.area * length**2)
    )


def assemble_lateral_track(
    track: TrackParameters, elements_per_bay: int = 16, absorbing_bays: int = 0
) -> LateralFEModel:
    """Assemble the lateral track of ``track`` (module docstring) on ``elements_per_bay`` elements per bay.

    Parameters
    ----------
    track : TrackParameters
        Its ``n_bays`` bays, supports, rail mass and loss factor, and ``lateral`` (section, lateral supports).
    elements_per_bay : int
        Equal elements per sleeper bay.
    absorbing_bays : int
        Bays at each end whose rail elements take an extra loss factor ``ABSORBING_LOSS_FACTOR`` s^2, s rising
        from 0 to 1 towards the end (the part "absorber"): waves reaching the ends die there instead of coming
        back (0: free ends).

    Returns
    -------
    LateralFEModel
    """
    import scipy.sparse as sp

    n_bays, spacing = track.n_bays, track.support.sleeper_spacing
    h = spacing / elements_per_bay
    n_nodes = n_bays * elements_per_bay + 1
    node_x = np.arange(n_nodes) * h
    node_x[-1] = n_bays * spacing
    n_dof = DOFS_PER_NODE * n_nodes + n_bays + 1
    support_nodes = np.arange(n_bays + 1) * elements_per_bay
    sleeper_dof = DOFS_PER_NODE * (support_nodes + 1) + np.arange(n_bays + 1)
    supports_before = (np.arange(n_nodes) + elements_per_bay - 1) // elements_per_bay  # support nodes before each
    nodes = (DOFS_PER_NODE * np.arange(n_nodes) + supports_before)[:, None] + np.arange(DOFS_PER_NODE)
    ke, me = lateral_element_matrices(track, h)
    dofs = np.concatenate([nodes[:-1], nodes[1:]], axis=1)  # (elements, 8)
    rows, cols = np.repeat(dofs, 8, axis=1).ravel(), np.tile(dofs, (1, 8)).ravel()
    n_el = len(dofs)

    def matrix(r, c, values):
        return sp.coo_matrix((values, (r, c)), shape=(n_dof, n_dof)).tocsr()

    rail = matrix(rows, cols, np.tile(ke.ravel(), n_el))
    layer = absorbing_bays * spacing  # the absorbing ends: a loss factor rising as s^2 over their length
    centre = 0.5 * (node_x[:-1] + node_x[1:])
    depth = np.clip(np.maximum(layer - centre, centre - (node_x[-1] - layer)) / max(layer, 1e-300), 0.0, 1.0)
    absorber = matrix(rows, cols, np.repeat(depth**2, 64) * np.tile(ke.ravel(), n_el))
    mass = matrix(rows, cols, np.tile(me.ravel(), n_el)) + matrix(
        sleeper_dof, sleeper_dof, np.full(len(sleeper_dof), track.support.sleeper_mass)
    )
    pad = _pad_matrix(track, node_x, nodes, support_nodes, sleeper_dof, n_dof)
    ballast = matrix(sleeper_dof, sleeper_dof, np.full(len(sleeper_dof), track.lateral.ballast_lateral_stiffness))
    coo = (rail + pad + mass).tocoo()
    half = int(np.max(np.abs(coo.row - coo.col)))
    lat = track.lateral
    return LateralFEModel(
        params=track,
        node_x=node_x,
        node_dofs=nodes,
        sleeper_dof=sleeper_dof,
        parts={
            name: _band(m, half)
            for name, m in (("rail", rail), ("pad", pad), ("ballast", ballast), ("mass", mass), ("absorber", absorber))
        },
        loss_factors={
            "rail": track.rail.loss_factor,
            "pad": lat.pad_lateral_loss_factor,
            "ballast": lat.ballast_lateral_loss_factor,
        },
        half_bandwidth=half,
    )


def _band(matrix, half: int) -> np.ndarray:
    """A sparse matrix in LAPACK general band form, ``half`` diagonals each side."""
    coo = matrix.tocoo()
    out = np.zeros((2 * half + 1, matrix.shape[0]))
    np.add.at(out, (half + coo.row - coo.col, coo.col), coo.data)
    return out


def _pad_matrix(track, node_x, nodes, support_nodes, sleeper_dof, n_dof):
    """The pads' lateral and rotational stiffness (undamped): at each support, the foot's lateral displacement
    v + z_s phi against the sleeper's, and the twist against the sleeper's (none: rigid in roll); spread over the
    pad's width as ``fe.pad_couplings`` spreads the vertical pad (clipped at the rail's ends), or at the node."""
    import scipy.sparse as sp

    lat, width = track.lateral, track.support.pad_width
    z_s = lat.section.shear_centre_height
    out = sp.lil_matrix((n_dof, n_dof))
    h = node_x[1] - node_x[0]
    phi_v = _shear_parameter(track, h)
    for node, s in zip(support_nodes, sleeper_dof, strict=True):
        if width < POINT_PAD_WIDTH:
            point = (np.array([nodes[node, 0], nodes[node, 2]]), np.array([[1.0, z_s]]), np.array([[0.0, 1.0]]))
            pieces = [(*point, np.ones(1), 1.0)]
        else:
            pieces = _pad_pieces(node_x, nodes, node, width, h, phi_v, z_s)
        for dofs, foot, twist, quadrature, share in pieces:
            k_y = lat.pad_lateral_stiffness * share
            k_r = lat.pad_rotational_stiffness * share
            block = k_y * (foot * quadrature[:, None]).T @ foot + k_r * (twist * quadrature[:, None]).T @ twist
            coupling = k_y * quadrature @ foot
            for i, di in enumerate(dofs):
                for j, dj in enumerate(dofs):
                    out[di, dj] += block[i, j]
                out[di, s] -= coupling[i]
                out[s, di] -= coupling[i]
            out[s, s] += k_y
    return out.tocsr()


def _pad_pieces(node_x, nodes, node, width, h, phi_v, z_s):
    """The pad over x_S -+ w / 2 as (element DOFs, foot rows, twist rows, quadrature weights, share) per element it
    covers: the rows are the foot's lateral displacement and the twist at Gauss points, the weights (summing to 1)
    average over the piece, the share is the piece's part of the pad's length."""
    xs = node_x[node]
    start, end = max(xs - width / 2, node_x[0]), min(xs + width / 2, node_x[-1])
    points, weights = _GAUSS
    pieces = []
    e = max(int(np.searchsorted(node_x, start, side="right")) - 1, 0)
    while e < len(node_x) - 1 and node_x[e] < end:
        a, b = max(start, node_x[e]), min(end, node_x[e + 1])
        if b > a:
            xi = (0.5 * (a + b) + 0.5 * (b - a) * points - node_x[e]) / h
            n_v, n_phi = timoshenko_shape_functions(xi, h, phi_v), timoshenko_shape_functions(xi, h, 0.0)
            foot, twist = np.zeros((len(xi), 8)), np.zeros((len(xi), 8))
            foot[:, BENDING], foot[:, TORSION], twist[:, TORSION] = n_v, z_s * n_phi, n_phi
            dofs = np.concatenate([nodes[e], nodes[e + 1]])
            pieces.append((dofs, foot, twist, weights / 2, (b - a) / (end - start)))
        e += 1
    return pieces


@functools.lru_cache(maxsize=4)
def _model(track: TrackParameters, numerics: LateralNumerics) -> LateralFEModel:
    """The lateral model of ``track`` lengthened to ``numerics.track_bays`` bays (kept: the FE assembly is most of a
    few frequencies' cost)."""
    return assemble_lateral_track(
        replace(track, n_bays=numerics.track_bays), numerics.elements_per_bay, numerics.absorbing_bays
    )


def _checked(track, numerics, where: str) -> LateralNumerics:
    if not isinstance(track, TrackParameters):
        raise WheelrailError(f"{where}: track must be TrackParameters, got {type(track).__name__}")
    numerics = LateralNumerics() if numerics is None else numerics
    if not isinstance(numerics, LateralNumerics):
        raise WheelrailError(f"{where}: numerics must be LateralNumerics, got {type(numerics).__name__}")
    return numerics


def lateral_receptances(
    track: TrackParameters,
    frequency,
    *,
    contact_offset: float = 0.0,
    x_response=0.0,
    excitation: float = 0.5,
    numerics: LateralNumerics | None = None,
) -> LateralReceptances:
    """The railhead's lateral and torsional receptances of the lateral track (module docstring).

    Parameters
    ----------
    track : TrackParameters
        The track; ``track.lateral`` holds the rail's section and the supports' lateral stiffness.
    frequency : array_like
        f, Hz (finite, >= 0).
    contact_offset : float
        d, the vertical force's lateral distance from the rail's centreline, m (``|d|`` <= half the head's width,
        0.036 m for 60E1); 0: no torque, ``vertical_to_lateral`` is zero.
    x_response : float or array_like
        Where the response is read: m along the rail from the load (either way, within the model); 0: the point
        receptances.
    excitation : float
        Where in its sleeper bay the load acts, a fraction of the spacing (0: above a sleeper, 0.5: midspan).
    numerics : LateralNumerics, optional
        The model's bays and elements; default ``LateralNumerics()``.

    Returns
    -------
    LateralReceptances
        ``lateral_point`` and ``vertical_to_lateral`` in m/N, ``torsional_point`` in rad/(N m).

    Raises
    ------
    WheelrailError
        For a frequency that is negative or not finite, an offset beyond the head, a position outside the model.

    Examples
    --------
    At 100 Hz, near the rail's lateral resonance on its supports, a vertical force 10 mm off the centreline moves
    the railhead laterally by a twenty-fifth of what the same force applied laterally does:

    >>> from wheelrail.core.parameters import TrackParameters
    >>> from wheelrail.core.track.lateral import LateralNumerics, lateral_receptances
    >>> short = LateralNumerics(track_bays=60)                      # 39 m of track: quicker, the same at 100 Hz
    >>> r = lateral_receptances(TrackParameters(), [100.0], contact_offset=0.01, numerics=short)
    >>> print(f"{abs(r.lateral_point[0]):.2g} m/N, ratio {abs(r.vertical_to_lateral[0] / r.lateral_point[0]):.2f}")
    1e-07 m/N, ratio 0.04
    """
    numerics = _checked(track, numerics, "lateral_receptances")
    f = np.atleast_1d(np.asarray(frequency, dtype=float))
    if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise WheelrailError("lateral_receptances: frequencies must be finite and >= 0 Hz")
    half_head = 0.036
    if not (isinstance(contact_offset, int | float) and abs(contact_offset) <= half_head):
        raise WheelrailError(
            f"lateral_receptances: contact_offset {contact_offset!r} m is off the railhead (at most {half_head} m "
            "either side of its centreline)"
        )
    if not (isinstance(excitation, int | float) and 0.0 <= excitation <= 1.0):
        raise WheelrailError(
            f"lateral_receptances: excitation must be a fraction of the bay in [0, 1], got {excitation!r}"
        )
    model = _model(track, numerics)
    x0 = (numerics.track_bays // 2 + excitation) * track.support.sleeper_spacing
    x = x0 + np.atleast_1d(np.asarray(x_response, dtype=float))
    loads = np.stack([model.railhead_load(x0), model.torque_load(x0)], axis=1)
    out = np.empty((3, len(f), len(x)), dtype=complex)
    for i, fi in enumerate(f):
        head, twist = model.railhead_and_twist(model.solve(fi, loads), x)
        out[:, i] = head[:, 0], -contact_offset * head[:, 1], twist[:, 1]
    if np.ndim(x_response) == 0:
        out = out[:, :, 0]
    return LateralReceptances(f, out[0], out[1], out[2])


def lateral_band_frequencies(points_per_band: int) -> np.ndarray:
    """(24, points) frequencies, Hz, within the 24 one-third octave bands 50 Hz-10 kHz: each band's width split
    evenly in lg f, the middle of each part (the vertical decay rate's sampling)."""
    from wheelrail.core.spectra.bands import BAND_HALF_WIDTH, noise_bands

    parts = (np.arange(points_per_band) + 0.5) / points_per_band
    return noise_bands()[:, None] / BAND_HALF_WIDTH * BAND_HALF_WIDTH ** (2 * parts[None, :])


def lateral_decay_rate(
    track: TrackParameters, frequency=None, *, numerics: LateralNumerics | None = None
) -> np.ndarray:
    """The lateral track decay rate of the railhead, EN 15461's formula, dB/m.

    ``DR = 10 lg(e) / sum_n (|A(x_n)|^2 / |A(x_0)|^2) dx_n`` on the railhead's lateral transfer receptances A for a
    lateral force at the railhead at midspan of the central bay, summed over the model's nodes along
    ``numerics.decay_length`` of rail on one side; band values from ``|A|^2`` summed over ``points_per_band``
    frequencies across each band.

    Parameters
    ----------
    track : TrackParameters
    frequency : array_like, optional
        Centres of the one-third octave bands wanted, Hz (exact or nominal: each taken as the band it lies in,
        50 Hz-10 kHz); default all 24 bands' exact centres.
    numerics : LateralNumerics, optional

    Returns
    -------
    ndarray
        dB/m per band, the shape of ``frequency``.

    Raises
    ------
    WheelrailError
        For a frequency outside the bands 50 Hz-10 kHz.
    """
    from wheelrail.core.spectra.bands import noise_bands

    numerics = _checked(track, numerics, "lateral_decay_rate")
    centres = noise_bands()
    wanted = centres if frequency is None else np.asarray(frequency, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):  # a frequency <= 0 or NaN: no band, refused below
        index = np.rint(10 * np.log10(np.atleast_1d(wanted) / centres[0]))
    inside = np.isfinite(index) & (index >= 0) & (index < len(centres))
    if not np.all(inside):
        raise WheelrailError("lateral_decay_rate: frequencies must lie in the one-third octave bands 50 Hz-10 kHz")
    index = index.astype(int)
    model = _model(track, numerics)
    x0 = (numerics.track_bays // 2 + 0.5) * track.support.sleeper_spacing
    step = model.node_x[1] - model.node_x[0]
    x = x0 + np.arange(0.0, numerics.decay_length + 0.5 * step, step)
    x = x[x <= model.node_x[-1]]
    load = model.railhead_load(x0)
    freqs = lateral_band_frequencies(numerics.points_per_band)
    rates = {}
    for band in np.unique(index):
        power = np.zeros(len(x))
        for fi in freqs[band]:
            power += np.abs(model.railhead_and_twist(model.solve(fi, load), x)[0]) ** 2
        ratio = power / power[0]
        rates[band] = LOG10_E / (step * (np.sum(ratio) - 0.5 * (ratio[0] + ratio[-1])))
    out = np.array([rates[i] for i in index.ravel()])
    return out.reshape(np.shape(wanted))
