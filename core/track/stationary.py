"""Stationary track response: the impulse responses of the FE track integrated once in time (Newmark,
average acceleration, banded solves in numba) on the wedge a wheel can reach, and their disk cache.
See ``wheelrail.core.track``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np
from numba import njit

if TYPE_CHECKING:
    pass

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import TrackNumerics, TrackParameters
from wheelrail.core.track.fe import POINT_PAD_WIDTH, TrackFEModel, assemble_track, rail_relaxation, to_upper_band
from wheelrail.core.track.progress import Progress, current_progress

NEGLIGIBLE_LOSS_FACTOR = 1e-12
"""A rail loss factor below this is the undamped rail in the time domain: its relaxation terms (weights of the
order of the loss factor) would change the response by about that fraction, round-off, and below about 1e-300
they are subnormal numbers, on which every floating-point operation of the Newmark loop is many times
slower."""


def _upper_band_arrays(model: TrackFEModel, time_step: float):
    """Upper band forms of M, C, the rail's stiffness K_rail, the Cholesky factors of the Newmark effective
    stiffness and of M, and the rail's relaxation terms for this step (``_relaxation_terms``)."""
    from scipy.linalg import cholesky_banded

    dt = time_step
    u = model.half_bandwidth
    c0, weights, b = _relaxation_terms(model.params.rail.loss_factor, dt)
    stiffness = model.K
    if len(weights):  # K_rail (c0 + sum_j g_j / (1 + b_j)) in place of K_rail: _newmark_block
        stiffness = model.K + (c0 - 1.0 + float(np.sum(weights / (1.0 + b)))) * model.K_rail
    keff = stiffness + (2.0 / dt) * model.C + (4.0 / dt**2) * model.M
    mb = to_upper_band(model.M, u)
    cb = to_upper_band(model.C, u)
    krb = to_upper_band(model.K_rail, u) if len(weights) else np.zeros((u + 1, 0))
    k_chol = cholesky_banded(to_upper_band(keff, u), check_finite=False)
    m_chol = cholesky_banded(mb, check_finite=False)
    return mb, cb, krb, k_chol, m_chol, weights, b


def _relaxation_terms(loss_factor: float, dt: float) -> tuple[float, np.ndarray, np.ndarray]:
    """The rail's c0, relaxation weights g_j and b_j = dt / (2 tau_j) for the trapezoidal rule (no terms when
    undamped or nearly, ``NEGLIGIBLE_LOSS_FACTOR``), from ``fe.rail_relaxation``.

    Internal variables q_j (one per DOF and term) with tau_j dq_j/dt = u - q_j add the force
    K_rail sum_j g_j (u - q_j) to the rail's K_rail c0 u. The trapezoidal rule, as the Newmark average
    acceleration scheme is for u, gives q_j' = ((1 - b_j) q_j + b_j (u + u')) / (1 + b_j) over a step (u' the
    new displacement): the effective stiffness gains K_rail g_j / (1 + b_j) and the right-hand side
    K_rail z with z = sum_j g_j ((1 - b_j) q_j + b_j u) / (1 + b_j).
    """
    if loss_factor < NEGLIGIBLE_LOSS_FACTOR:
        return 1.0, np.zeros(0), np.zeros(0)
    relax = rail_relaxation(loss_factor)
    return relax.c0, np.asarray(relax.weights, dtype=float), dt / (2.0 * relax.times)


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
def _band_matvec2(ab1, x1, ab2, x2, out):
    """out = A1 x1 + A2 x2 for symmetric A1, A2 in LAPACK upper band form of the same bandwidth; (n, m)."""
    u = ab1.shape[0] - 1
    n, m = x1.shape
    for i in range(n):
        d1 = ab1[u, i]
        d2 = ab2[u, i]
        for c in range(m):
            out[i, c] = d1 * x1[i, c] + d2 * x2[i, c]
    for j in range(1, n):
        for d in range(1, min(u, j) + 1):
            a1 = ab1[u - d, j]
            a2 = ab2[u - d, j]
            i = j - d
            for c in range(m):
                out[i, c] += a1 * x1[j, c] + a2 * x2[j, c]
                out[j, c] += a1 * x1[i, c] + a2 * x2[i, c]


@njit(cache=True, fastmath=True)
def _relaxation_load(krb, weights, b, q, u, z, extra, out):
    """out += K_rail z with z = sum_j g_j ((1 - b_j) q_j + b_j u) / (1 + b_j) (``_relaxation_terms``)."""
    n, m = u.shape
    for i in range(n):
        for c in range(m):
            z[i, c] = 0.0
    for j in range(len(weights)):
        s = weights[j] / (1.0 + b[j])
        for i in range(n):
            for c in range(m):
                z[i, c] += s * ((1.0 - b[j]) * q[j, i, c] + b[j] * u[i, c])
    _band_matvec(krb, z, extra)
    for i in range(n):
        for c in range(m):
            out[i, c] += extra[i, c]


@njit(cache=True, fastmath=True)
def _relaxation_update(b, q, u_old, u_new):
    """q_j <- ((1 - b_j) q_j + b_j (u_old + u_new)) / (1 + b_j): the trapezoidal rule on tau_j dq_j/dt = u - q_j."""
    n, m = u_new.shape
    for j in range(len(b)):
        for i in range(n):
            for c in range(m):
                q[j, i, c] = ((1.0 - b[j]) * q[j, i, c] + b[j] * (u_old[i, c] + u_new[i, c])) / (1.0 + b[j])


# A numba loop over time steps: 18 arguments because every array it reads or fills is one, so that the whole
# loop compiles to one function numba caches on disk (a structure or a jitted callable would defeat the cache).
# Without the GIL: blocks of columns run in parallel Python threads (``_integrate``).
@njit(cache=True, fastmath=True, nogil=True)
def _newmark_block(
    mb, cb, krb, k_chol, m_chol, weights, b, load, dt, n_steps, stride, w_dof, th_dof, nodes, counts, offsets, out,
    impulse,
):  # fmt: skip
    """Newmark (average acceleration) responses to the loads in the columns of ``load``.

    ``impulse``: a unit impulse at t = 0 (the continuous impulse response, sampled); otherwise a unit
    force at step 0 only, the track at rest before (the discrete impulse response of the trapezoidal rule).
    The rail's relaxation terms (``weights``, ``b``; none for an undamped rail) act through ``krb``, K_rail's band.
    Recorded on the wedge: stored step s = k / stride keeps, for column e, w and theta of the nodes
    nodes[e, 0 .. counts[e, s] - 1] in out[offsets[e, s] + r, 0:2].
    A few columns at a time (``COLUMN_BLOCK``, from ``_integrate``) keep the work arrays in the processor's cache.
    """
    n, m = load.shape
    c1 = 4.0 / dt**2
    c2 = 4.0 / dt
    c3 = 2.0 / dt
    a = np.empty((n, m))
    q = np.zeros((len(weights), n, m))
    z = np.empty((n, m))
    extra = np.empty((n, m))
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
        _relaxation_update(b, q, np.zeros((n, m)), u)
    tm = np.empty((n, m))
    tc = np.empty((n, m))
    rhs = np.empty((n, m))
    for k in range(n_steps):
        if k > 0:
            for i in range(n):
                for c in range(m):
                    tm[i, c] = c1 * u[i, c] + c2 * v[i, c] + a[i, c]
                    tc[i, c] = c3 * u[i, c] + v[i, c]
            _band_matvec2(mb, tm, cb, tc, rhs)
            if len(weights):
                _relaxation_load(krb, weights, b, q, u, z, extra, rhs)
            _band_cho_solve(k_chol, rhs)  # K_eff u_k = M (..) + C (..) [+ K_rail z]
            if len(weights):
                _relaxation_update(b, q, u, rhs)
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
                base = offsets[e, s]
                for r in range(counts[e, s]):
                    node = nodes[e, r]
                    out[base + r, 0] = u[w_dof[node], e]
                    out[base + r, 1] = u[th_dof[node], e]


# Columns integrated together: 16 doubles per row, so that the compiler vectorises the loops over the columns
# (with 8 it does not: ``benchmarks/track_green.py`` times the integration; the numbers are the same), and
# the work arrays of a 70-bay track (a few thousand DOFs) stay within the processor's cache. The blocks run in
# parallel threads (``_integrate``; numba's own parallel loop compiles far more slowly on a fresh install).
COLUMN_BLOCK = 16


# --------------------------------------------------------------------------------------------------
# Stationary responses on the wedge, and moving Green's functions for any speed
# --------------------------------------------------------------------------------------------------

_WEDGE_ARRAYS = ("data", "counts", "offsets", "stored_x", "excitation_positions")


@dataclass(frozen=True)
class StationaryTrackResponse:
    """Impulse responses of the track, stored on the wedge a moving wheel can reach.

    For excitation position e, the response is kept at the rail nodes ``stored_x[e]`` (m from x_e,
    increasing): every node of the refined mesh from one position spacing before x_e to
    ``TrackNumerics.near_field`` after it, then the nodes of the coarse grid (``elements_per_bay`` per bay).
    At stored sample s the first ``counts[e, s]`` of them are kept (those a wheel at up to ``max_speed`` can
    reach, a position spacing beyond, and one spare), from ``data[offsets[e, s]]`` on.

    Attributes
    ----------
    track : TrackParameters
    numerics : TrackNumerics
    time_step : float
        Spacing of the stored samples, s (integration step times ``store_every``).
    excitation_positions : ndarray (P,)
        Excitation points x_e measured from the sleeper at the start of the central bay, m, in [0, L_S).
    stored_x : ndarray (P, N)
        Stored rail points relative to x_e, m (padded with +inf).
    counts, offsets : ndarray of int (P, S)
        Number of stored points and their start in ``data`` for each position and stored time sample.
    data : ndarray float32 (sum(counts), 2)
        Rail displacement w (m/(N s)) and rotation theta (1/(N s)) at the stored points.
    cache_path : str
        The disk cache file ('' when not cached).
    """

    track: TrackParameters
    numerics: TrackNumerics
    time_step: float
    excitation_positions: np.ndarray
    stored_x: np.ndarray
    counts: np.ndarray
    offsets: np.ndarray
    data: np.ndarray
    cache_path: str = ""

    @property
    def n_samples(self) -> int:
        return self.counts.shape[1]


def numerics_model(track: TrackParameters, numerics: TrackNumerics) -> TrackFEModel:
    """The FE track of these numerics: ``elements_per_bay`` elements per bay, ``refined_elements_per_bay`` in
    the central bay (where the excitation positions are) and the ``refined_bays - 1`` bays after it."""
    return assemble_track(
        track,
        numerics.elements_per_bay,
        refined=(track.n_bays // 2, numerics.refined_bays, numerics.refined_elements_per_bay),
    )


def excitation_nodes(model: TrackFEModel, numerics: TrackNumerics):
    """Excitation positions within the central bay (m from its first sleeper), on the track (m), and their
    FE nodes (the positions are nodes of the refined mesh: TrackNumerics checks)."""
    track = model.params
    L = track.support.sleeper_spacing
    positions = np.arange(numerics.positions_per_bay) * (L / numerics.positions_per_bay)
    x_e = (track.n_bays // 2) * L + positions
    nodes = np.searchsorted(model.node_x, x_e - 1e-9 * L)
    if np.any(np.abs(model.node_x[nodes] - x_e) > 1e-9 * L):
        raise WheelrailError("excitation positions must be FE nodes")  # TrackNumerics guarantees it
    return positions, x_e, nodes


def stored_nodes(model: TrackFEModel, numerics: TrackNumerics, x_e: np.ndarray, speed: float, t_samples: np.ndarray):
    """Which rail nodes are stored for each excitation position, and how many at each sample."""
    L = model.params.support.sleeper_spacing
    spacing = L / numerics.positions_per_bay
    coarse = L / numerics.elements_per_bay
    x = model.node_x
    on_grid = np.abs(x / coarse - np.rint(x / coarse)) < 1e-6
    lists = []
    for xe in x_e:
        # from the last node at or before x_e - spacing (so that offsets down to -spacing can be read)
        first = np.searchsorted(x, xe - spacing + 1e-9 * L, side="right") - 1
        if first < 0:
            raise WheelrailError("excitation position too close to the start of the track model")
        near = (x >= x[first]) & (x <= xe + numerics.near_field)
        lists.append(np.flatnonzero(near | (on_grid & (x > xe + numerics.near_field))))
    width = max(len(k) for k in lists)
    nodes = np.zeros((len(x_e), width), dtype=np.int64)
    stored_x = np.full((len(x_e), width), np.inf)
    counts = np.empty((len(x_e), len(t_samples)), dtype=np.int64)
    reach = speed * t_samples + spacing
    for e, keep in enumerate(lists):
        nodes[e, : len(keep)] = keep
        stored_x[e, : len(keep)] = x[keep] - x_e[e]
        # the stored points up to the first at or beyond the reach, and a spare
        counts[e] = np.searchsorted(stored_x[e, : len(keep)], reach - 1e-9 * L) + 2
        if counts[e, -1] > len(keep):
            raise WheelrailError(
                f"track model too short: a wheel at {speed * 3.6:.0f} km/h travels {speed * t_samples[-1]:.2f} m "
                f"within the {t_samples[-1]:.3g} s Green's functions, beyond the end of the "
                f"{model.params.n_bays}-bay track; use more bays or a shorter duration"
            )
    offsets = (np.cumsum(counts.ravel()) - counts.ravel()).reshape(counts.shape)
    return nodes, stored_x, counts, offsets


def integrate_responses(
    model: TrackFEModel,
    x_e,
    dt: float,
    n_steps: int,
    stride: int,
    nodes,
    counts,
    offsets,
    *,
    impulse: bool,
    progress: Progress | None = None,
) -> np.ndarray:
    """Newmark responses to unit loads at x_e, stored at ``nodes`` (see _newmark_block): blocks of
    ``COLUMN_BLOCK`` columns in as many threads as numba would use (all cores, or ``NUMBA_NUM_THREADS``).
    With ``progress``, ``progress("integrating ...", done, total)`` is called at the start and as each block
    ends (``done`` columns of ``total``)."""
    from concurrent.futures import ThreadPoolExecutor, as_completed

    mb, cb, krb, k_chol, m_chol, weights, b = _upper_band_arrays(model, dt)
    loads = np.stack([model.load_vector(float(x)) for x in x_e], axis=1)
    out = np.zeros((int(counts.sum()), 2))
    m = loads.shape[1]

    def block(c0: int, c1: int, steps: int, into: np.ndarray) -> int:
        load = np.ascontiguousarray(loads[:, c0:c1])
        _newmark_block(
            mb, cb, krb, k_chol, m_chol, weights, b, load, dt, steps, stride, model.w_dof, model.theta_dof,
            nodes[c0:c1], counts[c0:c1], offsets[c0:c1], into, impulse,
        )  # fmt: skip
        return c1 - c0

    if progress is not None:  # numba's code for the loop loaded (compiled on a fresh install) as a phase of its own
        progress(LOADING_PHASE, 0, 1)
        block(0, 1, 1, np.zeros((int(counts[0, 0]), 2)))  # one step of one column (offsets[0, 0] is 0), scratch
        progress(LOADING_PHASE, 1, 1)
        phase = _integrating_phase(m, n_steps, len(model.node_x))
        progress(phase, 0, m)
    done = 0
    with ThreadPoolExecutor(max_workers=max(1, numba.config.NUMBA_NUM_THREADS)) as pool:
        futures = [pool.submit(block, c0, min(m, c0 + COLUMN_BLOCK), n_steps, out) for c0 in range(0, m, COLUMN_BLOCK)]
        for future in as_completed(futures):
            done += future.result()
            if progress is not None:
                progress(phase, done, m)
    return out


LOADING_PHASE = "loading the integration's compiled code (compiled once after installation)"


def _integrating_phase(columns: int, n_steps: int, n_nodes: int) -> str:
    """The integration announced: its size and, if the cache knows this machine's speed, its time."""
    from wheelrail.core.track.progress import estimate_s

    estimate = estimate_s(float(columns) * n_steps * n_nodes)
    about = f", about {estimate:.0f} s" if estimate is not None else ""
    return f"integrating the track's impulse responses ({columns} load positions x {n_steps} steps{about})"


def stored_times(numerics: TrackNumerics) -> tuple[np.ndarray, int]:
    """The stored sample times (s) of the impulse responses and the number of integration steps behind them."""
    n_steps = int(round(numerics.duration / numerics.time_step)) + 1
    reach = numerics.max_speed * numerics.duration
    if not reach < 1e6:  # m: beyond 1000 km the node counts overflow int64 (e.g. at 1e308 km/h)
        raise WheelrailError(
            f"a wheel at {numerics.max_speed * 3.6:.3g} km/h travels {reach:.3g} m within "
            f"the {numerics.duration} s Green's functions, beyond any track model"
        )
    return np.arange(0, n_steps, numerics.store_every) * numerics.time_step, n_steps


def compute_stationary_response(
    track: TrackParameters, numerics: TrackNumerics, progress: Progress | None = None
) -> StationaryTrackResponse:
    """Integrate the impulse responses of the FE track for all excitation points of the central bay.

    See the module docstring for the method and ``benchmarks/track_green.py`` for its cost; ``progress``:
    see ``wheelrail.core.track.progress``.
    """
    if progress is not None:
        progress("assembling the FE track", 0, 1)
    model = numerics_model(track, numerics)
    positions, x_e, _ = excitation_nodes(model, numerics)
    t_stored, n_steps = stored_times(numerics)
    nodes, stored_x, counts, offsets = stored_nodes(model, numerics, x_e, numerics.max_speed, t_stored)
    out = integrate_responses(
        model,
        x_e,
        numerics.time_step,
        n_steps,
        numerics.store_every,
        nodes,
        counts,
        offsets,
        impulse=True,
        progress=progress,
    )
    return StationaryTrackResponse(
        track=track,
        numerics=numerics,
        time_step=numerics.time_step * numerics.store_every,
        excitation_positions=positions,
        stored_x=stored_x,
        counts=counts,
        offsets=offsets,
        data=out.astype(np.float32),
    )


def track_key(track: TrackParameters, numerics: TrackNumerics) -> str:
    """The disk-cache key of the stationary responses of this track and these numerics."""
    from dataclasses import asdict

    from wheelrail.core.files.cache import cache_key

    stored = asdict(numerics)
    del stored["rows_per_position"]  # how the stored responses are read, not what is stored
    params = asdict(track)
    del params["lateral"]  # the lateral rail's inputs (track.lateral) change no vertical response
    if params["support"]["pad_width"] < POINT_PAD_WIDTH:  # the point support's responses (fe.pad_couplings)
        params["support"]["pad_width"] = 0.0
    return cache_key("track-wedge", {"track": params, "numerics": stored})


def track_cache_path(track: TrackParameters, numerics: TrackNumerics):
    """Path of the disk-cache entry for these parameters (it may not exist yet)."""
    from wheelrail.core.files.cache import entry_path

    return entry_path("track-wedge", track_key(track, numerics))


_MEMORY: dict[str, StationaryTrackResponse] = {}


def clear_memory() -> None:
    """Forget the track response held in memory, so that the next call reads the disk cache (or computes)."""
    _MEMORY.clear()


def stationary_track_response(
    track: TrackParameters | None = None,
    numerics: TrackNumerics | None = None,
    *,
    use_cache: bool = True,
    progress: Progress | None = None,
) -> StationaryTrackResponse:
    """The track's stationary impulse responses: from memory, the disk cache, or computed and cached.

    Parameters
    ----------
    track : TrackParameters, optional
        Default: the paper's track.
    numerics : TrackNumerics, optional
        Default: ``TrackNumerics()``.
    use_cache : bool
        Read and write the disk cache (``wheelrail.core.files.cache``).
    progress : callable, optional
        Told the phases of a computation, if one is needed (``wheelrail.core.track.progress``); default: the
        callable of an enclosing ``track_progress`` block.

    Returns
    -------
    StationaryTrackResponse
        The impulse responses h(x, x0, t) on the wedge a wheel can reach, m/N per N s.
    """
    from wheelrail.core.files import cache

    track = TrackParameters() if track is None else track
    numerics = TrackNumerics() if numerics is None else numerics
    key = track_key(track, numerics)
    if use_cache and key in _MEMORY:
        return _MEMORY[key]
    arrays = cache.load_entry("track-wedge", key, _WEDGE_ARRAYS) if use_cache else None
    if arrays is not None:
        shape = (numerics.positions_per_bay, len(stored_times(numerics)[0]))
        if (
            arrays["counts"].shape != shape
            or arrays["offsets"].shape != shape
            or arrays["data"].shape != (int(arrays["counts"].sum()), 2)
            or not np.all(np.isfinite(arrays["data"]))
        ):
            arrays = None  # inconsistent with its own key: rebuild
    if arrays is not None:
        response = StationaryTrackResponse(
            track=track,
            numerics=numerics,
            time_step=numerics.time_step * numerics.store_every,
            excitation_positions=arrays["excitation_positions"],
            stored_x=arrays["stored_x"],
            counts=arrays["counts"],
            offsets=arrays["offsets"],
            data=arrays["data"],
            cache_path=str(cache.entry_path("track-wedge", key)),
        )
    else:
        response = _computed(track, numerics, key, use_cache, progress or current_progress())
    if use_cache:
        _MEMORY.clear()  # keep one track in memory (tens of MB)
        _MEMORY[key] = response
    return response


def _computed(track, numerics, key: str, use_cache: bool, progress: Progress | None) -> StationaryTrackResponse:
    """The responses computed and, with ``use_cache``, written to the cache (its path kept if written)."""
    import time

    from wheelrail.core.files import cache

    start = time.perf_counter()
    response = compute_stationary_response(track, numerics, progress)
    if not use_cache:
        return response
    if progress is not None:
        progress("writing the cache entry", 0, 1)
    info = {
        "compute_s": time.perf_counter() - start,
        # what the estimate of the next track scales with (``track.progress.estimate_s``)
        "work": float(len(response.excitation_positions)) * stored_times(numerics)[1] * _node_count(track, numerics),
    }
    path = cache.save_entry("track-wedge", key, {name: getattr(response, name) for name in _WEDGE_ARRAYS}, info=info)
    if progress is not None:
        progress("writing the cache entry", 1, 1)
    return StationaryTrackResponse(**{**response.__dict__, "cache_path": str(path) if path is not None else ""})


def _node_count(track: TrackParameters, numerics: TrackNumerics) -> int:
    """Rail nodes of ``numerics_model`` (without assembling it)."""
    refined = min(numerics.refined_bays, track.n_bays - track.n_bays // 2)
    return (track.n_bays - refined) * numerics.elements_per_bay + refined * numerics.refined_elements_per_bay + 1


def rail_impulse_responses(
    model: TrackFEModel, x_excitation: float, response_nodes, time_step: float, duration: float
) -> np.ndarray:
    """Rail displacement per unit impulse at ``x_excitation`` (m), at the rail nodes ``response_nodes``, by the
    Newmark integration the Green's functions use (the rail's loss factor by its relaxation terms).

    Returns
    -------
    ndarray (n_samples, len(response_nodes))
        h(t_k) at t_k = k ``time_step``, k = 0 .. duration / time_step, m/(N s).
    """
    nodes = np.atleast_1d(np.asarray(response_nodes, dtype=np.int64))
    n_steps = int(round(duration / time_step)) + 1
    counts = np.full((1, n_steps), len(nodes), dtype=np.int64)
    offsets = (np.arange(n_steps, dtype=np.int64) * len(nodes))[None, :]
    out = integrate_responses(
        model, [x_excitation], time_step, n_steps, 1, nodes[None, :], counts, offsets, impulse=True
    )
    return out[:, 0].reshape(n_steps, len(nodes))
