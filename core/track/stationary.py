"""Stationary track response: the impulse responses of the FE track integrated once in time (Newmark,
average acceleration, ``newmark``) on the wedge a wheel can reach, and their disk cache.
See ``wheelrail.core.track``."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numba
import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import TrackNumerics, TrackParameters
from wheelrail.core.track.fe import POINT_PAD_WIDTH, TrackFEModel, assemble_track, rail_relaxation, track_mesh
from wheelrail.core.track.newmark import newmark_responses, step_operators
from wheelrail.core.track.progress import Progress, current_progress

if TYPE_CHECKING:
    from wheelrail.core.files.cache import PendingEntry

NEGLIGIBLE_LOSS_FACTOR = 1e-12
"""A rail loss factor below this is the undamped rail in the time domain: its relaxation terms (weights of the
order of the loss factor) would change the response by about that fraction, round-off, and below about 1e-300
they are subnormal numbers, on which every floating-point operation of the Newmark loop is many times
slower."""


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


# Columns integrated together at most: the loops over a row's columns vectorise, and the longer they are, the
# less each sparse term's loop overhead weighs (``benchmarks/track_green.py`` times the integration); the work
# arrays of a 70-bay track (a few thousand DOFs) stay within a core's cache. The blocks run in parallel threads
# (``integrate_responses``; numba's own parallel loop compiles far more slowly on a fresh install).
COLUMN_BLOCK = 32


_LOCAL = threading.local()  # this thread's integration threads (``integration_threads``)


def _threads() -> int:
    """The threads a precompute in this thread integrates in: ``integration_threads``'s number, else all cores (or
    ``NUMBA_NUM_THREADS``)."""
    return max(1, getattr(_LOCAL, "threads", None) or numba.config.NUMBA_NUM_THREADS)


@contextlib.contextmanager
def integration_threads(threads: int) -> Iterator[None]:
    """A precompute started in this thread while the block runs integrates in at most ``threads`` threads (at most
    ``NUMBA_NUM_THREADS``); other threads' precomputes are not affected (two can run side by side)."""
    saved = getattr(_LOCAL, "threads", None)
    _LOCAL.threads = max(1, min(numba.config.NUMBA_NUM_THREADS, int(threads)))
    try:
        yield
    finally:
        _LOCAL.threads = saved


def column_blocks(columns: int, threads: int | None = None) -> list[tuple[int, int]]:
    """The blocks (first, end) of columns ``integrate_responses`` runs: as many as the threads (``_threads``: this
    thread's ``integration_threads``, else all cores or ``NUMBA_NUM_THREADS``) or more, of at most ``COLUMN_BLOCK``
    columns and about equal."""
    threads = max(1, _threads() if threads is None else threads)
    size = max(1, min(COLUMN_BLOCK, -(-columns // threads)))
    return [(c0, min(columns, c0 + size)) for c0 in range(0, columns, size)]


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
    cache_entry : str or PendingEntry
        The disk cache file ('' when not cached), or its write under way (``cache.save_entry_behind``): read
        ``cache_path``.
    """

    track: TrackParameters
    numerics: TrackNumerics
    time_step: float
    excitation_positions: np.ndarray
    stored_x: np.ndarray
    counts: np.ndarray
    offsets: np.ndarray
    data: np.ndarray
    cache_entry: str | PendingEntry = ""

    @property
    def n_samples(self) -> int:
        return self.counts.shape[1]

    @property
    def cache_path(self) -> str:
        """The disk cache file ('' when not cached); if it is being written in the background, once written."""
        if isinstance(self.cache_entry, str):
            return self.cache_entry
        path = self.cache_entry.wait()
        return "" if path is None else str(path)


def numerics_model(track: TrackParameters, numerics: TrackNumerics) -> TrackFEModel:
    """The FE track of these numerics: ``elements_per_bay`` elements per bay, ``refined_elements_per_bay`` in
    the central bay (where the excitation positions are), the ``refined_bays - 1`` bays after it and the one
    before it; ``model_bays`` bays, ``track.n_bays // 2`` on either side of the central bay, so that the model
    is its own mirror image about the central bay's middle when the refined bays are too (``refined_bays`` 2,
    the default: ``mirror_plan``)."""
    bays = model_bays(track)
    return assemble_track(replace(track, n_bays=bays), numerics.elements_per_bay, _refined(track, numerics))


def _refined(track: TrackParameters, numerics: TrackNumerics) -> tuple[int, int, int]:
    """``assemble_track``'s ``refined`` of ``numerics_model``: the central bay first."""
    return (track.n_bays // 2, numerics.refined_bays, numerics.refined_elements_per_bay)


def numerics_mesh(track: TrackParameters, numerics: TrackNumerics) -> np.ndarray:
    """The rail nodes' positions of ``numerics_model`` (m), without assembling it (``fe.track_mesh``)."""
    bays = model_bays(track)
    return track_mesh(bays, track.support.sleeper_spacing, numerics.elements_per_bay, _refined(track, numerics))[1]


def model_bays(track: TrackParameters) -> int:
    """Bays of ``numerics_model``: ``track.n_bays``, or one more at the far end when it is even (a central bay
    with as many bays before it as after it)."""
    return 2 * (track.n_bays // 2) + 1


def excitation_nodes(model: TrackFEModel, numerics: TrackNumerics):
    """Excitation positions within the central bay (m from its first sleeper), on the track (m), and their
    FE nodes (the positions are nodes of the refined mesh: TrackNumerics checks)."""
    L = model.params.support.sleeper_spacing
    positions, x_e = _excitation_x(model.params, numerics)
    nodes = np.searchsorted(model.node_x, x_e - 1e-9 * L)
    if np.any(np.abs(model.node_x[nodes] - x_e) > 1e-9 * L):
        raise WheelrailError("excitation positions must be FE nodes")  # TrackNumerics guarantees it
    return positions, x_e, nodes


def _excitation_x(track: TrackParameters, numerics: TrackNumerics) -> tuple[np.ndarray, np.ndarray]:
    """The excitation positions within the central bay and on the track, m (``excitation_nodes``); ``track``
    the model's or the one it is made for (their central bay is the same: ``model_bays``)."""
    L = track.support.sleeper_spacing
    positions = np.arange(numerics.positions_per_bay) * (L / numerics.positions_per_bay)
    return positions, (track.n_bays // 2) * L + positions


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
    """Newmark responses to unit loads at x_e, stored at ``nodes`` (see ``newmark._newmark_steps``), float64:
    the ``column_blocks`` in ``_threads()`` threads (``integration_threads``, else all cores or
    ``NUMBA_NUM_THREADS``). The loads whose mirror images are among them on a mirror-symmetric model are not
    integrated but read from their images (``mirror_plan``; every load with ``MIRROR_SYMMETRY`` False). With
    ``progress``, ``progress("integrating ...", done, total)`` is called at the start and as each block ends
    (``done`` columns of ``total`` integrated)."""
    return _integrate(model, x_e, (dt, n_steps, stride), (nodes, counts, offsets), impulse, progress, np.float64)


MIRROR_SYMMETRY = True
"""Integrate only the loads whose mirror images are not among them (``mirror_plan``); False: every load (the
reference of ``tests/physics/test_track_mirror.py`` and ``validation/track_newmark_identity.py --full``)."""


def mirror_plan(model: TrackFEModel, x_e, nodes=None, *, symmetry: bool = True):
    """Which loads to integrate, and each wedge's source: (columns, source, sign, nodes).

    On a model that is its own mirror image about its middle x_c (its rail nodes at x and 2 x_c - x: the bays,
    supports and pads are all alike, so the mesh decides), the response to a load at 2 x_c - x_e at the node at
    2 x_c - x is the response to the load at x_e at x, w equal and theta = dw/dx of the opposite sign. A load
    whose image is an earlier load of ``x_e`` is then not integrated: its wedge is read from its image's column
    at the mirrored nodes, its theta negated. ``columns`` are the indices of the loads integrated, ``source[e]``
    the column (an index into ``columns``) wedge e is read from, ``sign[e]`` -1 for a mirror image and 1
    otherwise, ``nodes`` the wedges' nodes in the source's frame (``nodes`` as given, rows of images mirrored).
    On a model that is not symmetric (or for a single load, or with ``symmetry`` False), every load is integrated.
    """
    return _mirror_plan(model.node_x, model.params.support.sleeper_spacing, x_e, nodes, symmetry)


def _mirror_plan(x: np.ndarray, L: float, x_e, nodes, symmetry: bool):
    """``mirror_plan`` on rail nodes at ``x`` (m) with sleepers ``L`` apart: the mesh alone decides."""
    x_e = np.asarray(x_e, dtype=float)
    m = len(x_e)
    columns, source, sign = list(range(m)), np.arange(m, dtype=np.int64), np.ones(m)
    mirrored = None if nodes is None else np.array(nodes, dtype=np.int64, copy=True)
    if not symmetry or m < 2 or np.max(np.abs(x + x[::-1] - x[-1])) > 1e-9 * L:
        return np.asarray(columns, dtype=np.int64), source, sign, mirrored
    columns = []
    for e in range(m):
        image = np.flatnonzero(np.abs(x_e[:e] + x_e[e] - x[-1]) <= 1e-9 * L)
        if len(image):
            source[e], sign[e] = columns.index(int(image[0])), -1.0
            if mirrored is not None:
                mirrored[e] = len(x) - 1 - mirrored[e]
        else:
            source[e] = len(columns)
            columns.append(e)
    return np.asarray(columns, dtype=np.int64), source, sign, mirrored


def _integrate(model, x_e, steps, wedge, impulse: bool, progress: Progress | None, dtype) -> np.ndarray:
    """``integrate_responses`` with ``steps`` = (dt, n_steps, stride) and ``wedge`` = (nodes, counts, offsets),
    stored as ``dtype`` (each value rounded once from the integration's float64)."""
    from concurrent.futures import ThreadPoolExecutor, as_completed

    dt, n_steps, stride = steps
    nodes, counts, offsets = wedge
    operators = step_operators(model, dt, _relaxation_terms(model.params.rail.loss_factor, dt))
    columns, source, sign, nodes = mirror_plan(model, x_e, nodes, symmetry=MIRROR_SYMMETRY)
    loads = np.stack([model.load_vector(float(x_e[c])) for c in columns], axis=1)
    out = np.zeros((int(counts.sum()), 2), dtype=dtype)
    m = loads.shape[1]

    def block(c0: int, c1: int, steps: int, into: np.ndarray) -> int:
        mine = np.flatnonzero((source >= c0) & (source < c1))  # the wedges read from these columns
        wedge = (nodes[mine], counts[mine], offsets[mine], source[mine] - c0, sign[mine])
        newmark_responses(
            operators, loads[:, c0:c1], dt, steps, stride, model.w_dof, model.theta_dof, wedge, into, impulse
        )
        return c1 - c0

    if progress is not None:  # numba's code for the loop loaded (compiled on a fresh install) as a phase of its own
        progress(LOADING_PHASE, 0, 1)
        scratch = np.zeros((int(counts[0, 0]), 2), dtype=dtype)
        newmark_responses(
            operators, loads[:, :1], dt, 1, stride, model.w_dof, model.theta_dof,
            (nodes[:1], counts[:1], offsets[:1]), scratch, impulse,
        )  # fmt: skip  # one step of one column (offsets[0, 0] is 0; wedge 0 is column 0's)
        progress(LOADING_PHASE, 1, 1)
        phase = _integrating_phase(m, len(x_e), n_steps, len(model.node_x))
        progress(phase, 0, m)
    done = 0
    with ThreadPoolExecutor(max_workers=_threads()) as pool:
        futures = [pool.submit(block, c0, c1, n_steps, out) for c0, c1 in column_blocks(m)]
        for future in as_completed(futures):
            done += future.result()
            if progress is not None:
                progress(phase, done, m)
    return out


LOADING_PHASE = "loading the integration's compiled code (compiled once after installation)"


def _integrating_phase(columns: int, positions: int, n_steps: int, n_nodes: int) -> str:
    """The integration announced: its size and, if the cache knows this machine's speed, its time."""
    from wheelrail.core.track.progress import estimate_s

    estimate = estimate_s(float(columns) * n_steps * n_nodes)
    about = f", about {estimate:.0f} s" if estimate is not None else ""
    images = f", the other {positions - columns} their mirror images" if positions > columns else ""
    return f"integrating the track's impulse responses ({columns} load positions x {n_steps} steps{images}{about})"


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
    steps = (numerics.time_step, n_steps, numerics.store_every)
    out = _integrate(model, x_e, steps, (nodes, counts, offsets), True, progress, np.float32)
    return StationaryTrackResponse(
        track=track,
        numerics=numerics,
        time_step=numerics.time_step * numerics.store_every,
        excitation_positions=positions,
        stored_x=stored_x,
        counts=counts,
        offsets=offsets,
        data=out,
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
            cache_entry=str(cache.entry_path("track-wedge", key)),
        )
    else:
        response = _computed(track, numerics, key, use_cache, progress or current_progress())
    if use_cache:
        _MEMORY.clear()  # keep one track in memory (tens of MB)
        _MEMORY[key] = response
    return response


WRITING_PHASE = "writing the cache entry (in the background)"


def _computed(track, numerics, key: str, use_cache: bool, progress: Progress | None) -> StationaryTrackResponse:
    """The responses computed and, with ``use_cache``, their cache entry written in the background (the response
    returned at once: its ``cache_path`` waits for the write)."""
    import time

    from wheelrail.core.files import cache

    start = time.perf_counter()
    response = compute_stationary_response(track, numerics, progress)
    if not use_cache:
        return response
    if progress is not None:
        progress(WRITING_PHASE, 0, 1)
    info = {
        "compute_s": time.perf_counter() - start,
        # what the estimate of the next track scales with (``track.progress.estimate_s``)
        "work": float(integrated_positions(track, numerics)) * stored_times(numerics)[1] * _node_count(track, numerics),
    }
    arrays = {name: getattr(response, name) for name in _WEDGE_ARRAYS}
    pending = cache.save_entry_behind("track-wedge", key, arrays, info=info)
    return StationaryTrackResponse(**{**response.__dict__, "cache_entry": pending})


def _node_count(track: TrackParameters, numerics: TrackNumerics) -> int:
    """Rail nodes of ``numerics_model`` (without assembling it)."""
    return len(numerics_mesh(track, numerics))


def integrated_positions(track: TrackParameters, numerics: TrackNumerics) -> int:
    """Excitation positions ``compute_stationary_response`` integrates: the columns of ``mirror_plan``'s plan on
    ``numerics_model``'s mesh (``numerics_mesh``: without assembling the model), as the integration reads it
    (``MIRROR_SYMMETRY``). On a mirror-symmetric mesh (the refined bays symmetric about the central one)
    positions 0 .. P / 2, the others being their mirror images; otherwise all P."""
    x_e = _excitation_x(track, numerics)[1]
    plan = _mirror_plan(numerics_mesh(track, numerics), track.support.sleeper_spacing, x_e, None, MIRROR_SYMMETRY)
    return len(plan[0])


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
