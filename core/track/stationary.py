"""Stationary track response: the impulse responses of the FE track integrated once in time (Newmark,
average acceleration, banded solves in numba) on the wedge a wheel can reach, and their disk cache.
See ``wheelrail.core.track``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

if TYPE_CHECKING:
    pass

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import TrackNumerics, TrackParameters
from wheelrail.core.track.fe import HALF_BANDWIDTH, TrackFEModel, _to_upper_band, assemble_track


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


# A numba loop over time steps: 15 arguments because every array it reads or fills is one, so that the whole
# loop compiles to one function numba caches on disk (a structure or a jitted callable would defeat the cache).
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
    if not reach < 1e6:  # m: beyond 1000 km the node counts below overflow int64 (1e308 km/h was once asked)
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


