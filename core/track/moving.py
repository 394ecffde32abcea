"""Moving Green's functions g_R (eq. 2) read off the stationary response for any speed, refined across the
bay, and the first-order-hold / trapezoidal weights the interaction loop uses. See ``wheelrail.core.track``."""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    pass

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import FOH_MAX_STEP, TrackNumerics, TrackParameters
from wheelrail.core.track.fe import TrackFEModel, shear_parameter_of, timoshenko_shape_functions
from wheelrail.core.track.stationary import (
    StationaryTrackResponse,
    excitation_nodes,
    integrate_responses,
    numerics_model,
    stationary_track_response,
    stored_nodes,
    stored_times,
)

# Rows of the moving Green's functions per stored excitation position: the functions handed to the loop are
# read at ROWS_PER_POSITION x positions_per_bay points of the bay, each between its two neighbouring stored
# excitation positions at the same rail point (see ``bay_rows``); the loop interpolates linearly between rows.
ROWS_PER_POSITION = 4

# A row between two stored positions reads both at its own offset from their loads for the first
# SHEAR_CROSSINGS[0] times the shear wave's crossing of the spacing, at its own rail point after
# SHEAR_CROSSINGS[1] of them, blended in between (see ``_rows_between``); never shorter than NEAR_FIELD_TIME.
# Both chosen by measurement (the tone at v P / L_S on a smooth rail, validation/bay_convergence.py).
SHEAR_CROSSINGS = (10.0, 20.0)
NEAR_FIELD_TIME = (50e-6, 100e-6)  # s: and for at least this long (finer spacings need it: 128 positions)


def _read_wedge(data, counts, offsets, stored_x, rail, source, offset, out):
    """out[i, s] = rail displacement of stored excitation position ``source[i]`` at ``offset[i, s]`` m from
    its excitation point at stored sample s, with the shape functions of the element (or, beyond the near
    field, the coarse-grid span) between the two stored points around it.

    ``offset`` may be negative down to one position spacing. Vectorised numpy, not a numba kernel:
    a kernel's first call in a process loads numba's compiled target even from its cache, which would be most of
    a cached ``wheelrail track``.
    """
    source = np.asarray(source, dtype=np.int64)
    n_samples = counts.shape[1]
    for e in np.unique(source):
        rows = np.flatnonzero(source == e)
        d = offset[rows]
        points = stored_x[e]
        r = np.searchsorted(points, d, side="right") - 1
        r = np.clip(r, 0, counts[e][None, :] - 2)
        x_a = points[r]
        h = points[r + 1] - x_a
        n1, n2, n3, n4 = np.moveaxis(timoshenko_shape_functions((d - x_a) / h, h, shear_parameter_of(rail, h)), -1, 0)
        o = offsets[e][None, :n_samples] + r
        out[rows] = n1 * data[o, 0] + n2 * data[o, 1] + n3 * data[o + 1, 0] + n4 * data[o + 1, 1]


def bay_rows(n_positions: int, rows_per_position: int = ROWS_PER_POSITION):
    """Where each row of the moving Green's functions lies between the stored excitation positions.

    Row i is at x0 = i L_S / R (R = n_positions * rows_per_position). It is read from the two stored
    positions around it, lo and hi = lo + 1 (hi = n_positions stands for position 0 of the next bay), at the
    *same rail point* x0 + v t, and mixed linearly: g(x0, t) = (1 - f) h(x0 + v t, x_lo, t)
    + f h(x0 + v t, x_hi, t). Interpolating the source at a fixed receiver keeps the kinks of the response
    where the receiver crosses a support (x0 + v t = j L_S) at their places; interpolating g at a fixed
    time between the rows of two sources would smear them across the bay and lose the sleeper-passing
    harmonics they carry (see ``validation/bay_convergence.py``).

    Returns
    -------
    lo : ndarray of int (R,), frac : ndarray (R,), offset_lo, offset_hi : ndarray (R,)
        The stored positions, the weight of hi, and x0 - x_lo, x0 - x_hi in units of the position spacing.
    """
    n_rows = n_positions * rows_per_position
    pos = np.arange(n_rows) / rows_per_position
    lo = np.floor(pos).astype(np.int64)
    frac = pos - lo
    return lo, frac, pos - lo, pos - (lo + 1)


def _rows_from_wedge(data, counts, offsets, stored_x, rail, sample_step, speed, sleeper_spacing, rows_per_position):
    """The moving Green's functions at the rows of ``bay_rows`` from responses stored for P positions."""
    n_positions, n_samples = counts.shape
    spacing = sleeper_spacing / n_positions
    lo, frac, d_lo, d_hi = bay_rows(n_positions, rows_per_position)
    time = np.arange(n_samples) * sample_step
    travel = speed * time
    values = np.empty((len(lo), n_samples))
    on_positions = np.flatnonzero(frac == 0)  # rows on a stored position are read as they are
    stored_rows = np.empty((len(on_positions), n_samples))
    _read_wedge(
        data, counts, offsets, stored_x, rail, lo[on_positions], np.broadcast_to(travel, stored_rows.shape), stored_rows
    )
    values[on_positions] = stored_rows
    shear_time = spacing / math.sqrt(rail.shear_stiffness / rail.mass_per_length)
    between_all = np.flatnonzero(frac > 0)
    for start in range(0, len(between_all), _ROW_BLOCK):  # a block at a time: a few MB of temporaries
        between = between_all[start : start + _ROW_BLOCK]
        values[between] = _rows_between(
            (data, counts, offsets, stored_x),
            rail,
            lo[between],
            frac[between],
            d_lo[between] * spacing,
            d_hi[between] * spacing,
            time,
            travel,
            shear_time,
        )
    return values


def _rows_between(stored, rail, lo, frac, d_lo, d_hi, time, travel, shear_time):
    """Rows between stored positions lo and lo + 1 (see ``bay_rows``), offsets d_lo, d_hi in m; ``stored`` is
    (data, counts, offsets, stored_x) of the stored responses."""
    data, counts, offsets, stored_x = stored
    n_positions = counts.shape[0]
    hi = (lo + 1) % n_positions
    f = frac[:, None]
    shape = (len(lo), len(time))
    lower, upper = np.empty(shape), np.empty(shape)
    _read_wedge(data, counts, offsets, stored_x, rail, lo, d_lo[:, None] + travel, lower)
    _read_wedge(data, counts, offsets, stored_x, rail, hi, d_hi[:, None] + travel, upper)
    same_point = (1 - f) * lower + f * upper
    # The first samples: the near field of the impulse around the load itself, which two loads a position
    # spacing apart do not reproduce at a point between them (the row's first sample came out 5 times too
    # small, its w_0 too, and on the default track the rows' dip between positions put a tone of 200 N at
    # v P / L_S into the force on a smooth rail). For the first SHEAR_CROSSINGS times the shear wave takes
    # to cross the spacing (50-100 us at 10.2 mm; the wheel moves 1.4-2.8 mm at 100 km/h) both neighbours
    # are read at the row's own offset from their load: the tone drops to 2.7 N (0.3 N with no reading at
    # the rail point at all, whose low-frequency bands converge more slowly).
    first, last = (max(c * shear_time, t) for c, t in zip(SHEAR_CROSSINGS, NEAR_FIELD_TIME, strict=True))
    early = np.flatnonzero(time < last)
    if len(early):
        own_lo, own_hi = np.empty((len(lo), len(early))), np.empty((len(lo), len(early)))
        at_own_offset = np.broadcast_to(travel[early], own_lo.shape)
        _read_wedge(data, counts[:, early], offsets[:, early], stored_x, rail, lo, at_own_offset, own_lo)
        _read_wedge(data, counts[:, early], offsets[:, early], stored_x, rail, hi, at_own_offset, own_hi)
        same_offset = (1 - f) * own_lo + f * own_hi
        u = np.clip((time[early] - first) / (last - first), 0.0, 1.0)
        blend = 0.5 - 0.5 * np.cos(np.pi * u)
        same_point[:, early] = (1 - blend) * same_offset + blend * same_point[:, early]
    return same_point


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
            values = trapezoidal_weights(
                self.track,
                self.numerics,
                self.speed,
                time_step,
                n_lags,
                len(self.excitation_positions) // self.numerics.positions_per_bay,
            )
            if len(values) != len(self.excitation_positions):
                raise WheelrailError("trapezoidal weights: the rows do not match the stored positions")
            return values if x0 is None else self._across_bay(values, x0)
        values = self.values if x0 is None else self.at(np.atleast_1d(x0))
        edges = (np.arange(-1, n_lags + 1)) * time_step
        out = np.empty((len(values), n_lags))
        # a block of rows at a time keeps the moments' temporaries to a few MB (256 rows of 5000 samples would
        # take ~100 MB at once, more than a whole run's arrays)
        for start in range(0, len(values), _ROW_BLOCK):
            rows = slice(start, start + _ROW_BLOCK)
            G1, G2 = _piecewise_linear_moments(values[rows], self.time_step, edges)
            # hat over [(m-1)dt, (m+1)dt]: rising half uses (tau - (m-1)dt)/dt, falling ((m+1)dt - tau)/dt
            left = slice(0, n_lags)
            mid = slice(1, n_lags + 1)
            right = slice(2, n_lags + 2)
            rise = (G2[:, mid] - G2[:, left]) - edges[left] * (G1[:, mid] - G1[:, left])
            fall = edges[right] * (G1[:, right] - G1[:, mid]) - (G2[:, right] - G2[:, mid])
            out[rows] = (rise + fall) / time_step
        return out


_ROW_BLOCK = 16
_MODELS: dict[tuple, TrackFEModel] = {}


def trapezoidal_weights(
    track: TrackParameters,
    numerics: TrackNumerics,
    speed: float,
    time_step: float,
    n_lags: int,
    rows_per_position: int = ROWS_PER_POSITION,
) -> np.ndarray:
    """Convolution weights of eq. (2) from the FE track integrated by the trapezoidal rule at ``time_step``.

    Newmark's average-acceleration rule (the trapezoidal rule) at the loop's own step: w_m^{x_e} is the rail
    displacement at x_e + v m dt at step m after a unit force at x_e at step 0 only, the track at rest
    before. Its transfer function is the track's receptance at s = 2/dt (z - 1)/(z + 1), so the coupled
    loop keeps the physical system's stability at any step (``parameters.FOH_MAX_STEP``). Cost: n_lags
    banded steps of the FE model for the ``numerics.positions_per_bay`` positions (tens of ms for the
    200 lags of 0.25 ms steps).

    Returns
    -------
    ndarray (positions_per_bay * rows_per_position, n_lags), m/N: the rows of ``bay_rows``.
    """
    key = (track, numerics)
    if key not in _MODELS:
        _MODELS.clear()
        _MODELS[key] = numerics_model(track, numerics)
    model = _MODELS[key]
    _, x_e, _ = excitation_nodes(model, numerics)
    t = np.arange(n_lags) * time_step
    nodes, stored_x, counts, offsets = stored_nodes(model, numerics, x_e, speed, t)
    out = integrate_responses(model, x_e, time_step, n_lags, 1, nodes, counts, offsets, impulse=False)
    return _rows_from_wedge(
        out,
        counts,
        offsets,
        stored_x,
        track.rail,
        time_step,
        float(speed),
        track.support.sleeper_spacing,
        rows_per_position,
    )


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
    """Moving Green's functions of the track for a train speed (eq. 2).

    Read off the cached stationary responses (see the module docstring) and cached on disk per speed
    (``core.files.cache``, kind ``track-moving``; bit-identical). A speed above ``numerics.max_speed`` widens the
    wedge, which means a new one-off precompute.

    Parameters
    ----------
    speed : float
        v, m/s (> 0).
    track : TrackParameters, optional
        Default: the paper's track.
    numerics : TrackNumerics, optional
        Default: ``TrackNumerics()``.
    use_cache : bool
        Use the disk cache.

    Returns
    -------
    MovingGreenFunctions
        g_{R,v}^{x0}(t) at the bay's excitation positions, m/N, and their first-order-hold weights.

    Raises
    ------
    WheelrailError
        For a speed that is not a positive number or out of the accepted range.

    See Also
    --------
    stationary_track_response : the responses they are read off.
    """
    track, numerics = _resolved(speed, track, numerics)
    n_samples = len(stored_times(numerics)[0])
    shape = (numerics.positions_per_bay * numerics.rows_per_position, n_samples)
    key = _reading_key("track-moving", track, numerics, speed)
    values = _cached_array("track-moving", key, shape) if use_cache else None
    if values is None:
        response = stationary_track_response(track, numerics, use_cache=use_cache)
        green = moving_from_stationary(response, speed, numerics.rows_per_position)
        if use_cache:
            _save_array("track-moving", key, green.values, shape)
        return green
    L = track.support.sleeper_spacing
    return MovingGreenFunctions(
        speed=float(speed),
        sleeper_spacing=L,
        excitation_positions=np.arange(len(values)) * (L / len(values)),
        time_step=numerics.time_step * numerics.store_every,
        values=values,
        track=track,
        numerics=numerics,
    )


# The reading of the rows and of their weights as the per-speed cache entries hold them: bump when either
# changes (the constants of the reading are in the key too), so that no entry of an earlier reading is trusted.
READING_VERSION = 1


def _resolved(speed: float, track: TrackParameters | None, numerics: TrackNumerics | None):
    """The track and numerics ``moving_green_functions`` reads ``speed`` (m/s) with (the wedge widened to it)."""
    if not (isinstance(speed, int | float) and math.isfinite(speed) and speed > 0):
        raise WheelrailError(f"speed must be positive (m/s), got {speed!r}")
    track = TrackParameters() if track is None else track
    numerics = TrackNumerics() if numerics is None else numerics
    if speed > numerics.max_speed:
        from dataclasses import replace

        numerics = replace(numerics, max_speed=float(speed))
    return track, numerics


def _reading_key(kind: str, track: TrackParameters, numerics: TrackNumerics, speed: float, **more) -> str:
    """Cache key of what is read off the stationary responses of ``track`` for ``speed``: their key, the speed,
    the rows per position, the reading's version and constants, and ``more``."""
    from wheelrail.core.files.cache import cache_key
    from wheelrail.core.track.stationary import track_key

    description = {
        "wedge": track_key(track, numerics),
        "speed": float(speed),
        "rows_per_position": numerics.rows_per_position,
        "reading": [READING_VERSION, SHEAR_CROSSINGS, NEAR_FIELD_TIME, FOH_MAX_STEP],
        **more,
    }
    return cache_key(kind, description)


def _cached_array(kind: str, key: str, shape: tuple[int, int]) -> np.ndarray | None:
    """The array of a cache entry if it has the expected shape and is finite, else None (then rebuilt)."""
    from wheelrail.core.files import cache

    arrays = cache.load_entry(kind, key, ("values",))
    if arrays is None or arrays["values"].shape != shape or not np.all(np.isfinite(arrays["values"])):
        return None
    return arrays["values"]


def _save_array(kind: str, key: str, values: np.ndarray, shape: tuple[int, int]) -> None:
    from wheelrail.core.files import cache

    if values.shape == shape and np.all(np.isfinite(values)):
        cache.save_entry(kind, key, {"values": values})


def moving_weights(
    speed: float,
    time_step: float,
    track: TrackParameters | None = None,
    numerics: TrackNumerics | None = None,
    *,
    method: str = "auto",
    use_cache: bool = True,
) -> np.ndarray:
    """``moving_green_functions(speed, track, numerics).weights(time_step, method=method)``, the rows of
    ``bay_rows`` at the loop's step, cached on disk per track, speed, step and method (``core.files.cache``, kind
    ``track-weights``): what a run needs of its track, a few MB read back in milliseconds; bit-identical
    (the entry holds the very array). The last ``WEIGHTS_IN_MEMORY`` entries read are kept in memory while their
    disk entry is unchanged, and the same array is returned again: read it, do not write to it.

    Returns
    -------
    ndarray (positions_per_bay * rows_per_position, lags), m/N.
    """
    track, numerics = _resolved(speed, track, numerics)
    if not (isinstance(time_step, int | float) and math.isfinite(time_step) and time_step > 0):
        raise WheelrailError(f"time_step must be positive (s), got {time_step!r}")
    if method not in ("auto", "foh", "trapezoidal"):
        raise WheelrailError(f"weights: method must be auto, foh or trapezoidal, got {method!r}")
    shape = (numerics.positions_per_bay * numerics.rows_per_position, int(math.ceil(numerics.duration / time_step)) + 1)
    key = _reading_key("track-weights", track, numerics, speed, time_step=float(time_step), method=method)
    if use_cache and (remembered := _remembered_weights(key)) is not None:
        return remembered
    weights = _cached_array("track-weights", key, shape) if use_cache else None
    if weights is None:
        green = moving_green_functions(float(speed), track, numerics, use_cache=use_cache)
        weights = np.ascontiguousarray(green.weights(float(time_step), method=method))
        if use_cache:
            _save_array("track-weights", key, weights, shape)
    if use_cache:
        _remember_weights(key, weights)
    return weights


# The weights last read, by cache key, with the signature (path, inode, size, modification time) of their disk entry:
# a study's runs (in threads of one process, or one after another) read the same few entries again and again
# (each read: the file and its digest). An entry rewritten, removed or in another cache folder is read again.
# The arrays are shared: the loop only reads them.
WEIGHTS_IN_MEMORY = 8  # entries (a few MB each at the paper's speeds)
_WEIGHTS: OrderedDict[str, tuple[tuple, np.ndarray]] = OrderedDict()
_WEIGHTS_LOCK = threading.Lock()


def _entry_signature(key: str) -> tuple | None:
    from wheelrail.core.files.cache import entry_path

    path = entry_path("track-weights", key)
    try:
        stat = path.stat()
    except OSError:
        return None
    return str(path), stat.st_ino, stat.st_size, stat.st_mtime_ns  # an entry is replaced by a rename: a new inode


def _remembered_weights(key: str) -> np.ndarray | None:
    with _WEIGHTS_LOCK:
        found = _WEIGHTS.get(key)
    if found is None or found[0] != _entry_signature(key):
        return None
    with _WEIGHTS_LOCK:
        if key in _WEIGHTS:
            _WEIGHTS.move_to_end(key)
    return found[1]


def _remember_weights(key: str, weights: np.ndarray) -> None:
    signature = _entry_signature(key)
    if signature is None:  # not on disk (a cache that cannot be written): nothing to check a later call against
        return
    with _WEIGHTS_LOCK:
        _WEIGHTS[key] = (signature, weights)
        _WEIGHTS.move_to_end(key)
        while len(_WEIGHTS) > WEIGHTS_IN_MEMORY:
            _WEIGHTS.popitem(last=False)


def cached_reading(
    speed: float,
    time_step: float,
    track: TrackParameters | None = None,
    numerics: TrackNumerics | None = None,
    *,
    method: str = "auto",
) -> str:
    """What the disk cache holds towards :func:`moving_weights` of these arguments, without reading it.

    Returns
    -------
    str
        ``"weights"`` (the weights themselves: read back in milliseconds), ``"responses"`` (the track's stationary
        responses: the weights are read off them) or ``""`` (neither: the track's one-off precompute).
    """
    from wheelrail.core.files.cache import entry_path
    from wheelrail.core.track.stationary import track_cache_path

    track, numerics = _resolved(speed, track, numerics)
    key = _reading_key("track-weights", track, numerics, speed, time_step=float(time_step), method=method)
    if entry_path("track-weights", key).exists():
        return "weights"
    return "responses" if track_cache_path(track, numerics).exists() else ""


def moving_from_stationary(
    response: StationaryTrackResponse, speed: float, rows_per_position: int | None = None
) -> MovingGreenFunctions:
    """Read the moving Green's functions for a speed off stored stationary responses.

    Parameters
    ----------
    response : StationaryTrackResponse
        The stored responses (:func:`stationary_track_response`).
    speed : float
        v, m/s, up to the responses' ``numerics.max_speed``.
    rows_per_position : int, optional
        Rows per stored excitation position (``bay_rows``); default from the response's numerics.

    Returns
    -------
    MovingGreenFunctions
        g_{R,v}^{x0}(t) = h(x0 + v t, x0, t), m/N.

    Raises
    ------
    WheelrailError
        For a speed above the one the stored responses cover.
    """
    if rows_per_position is None:
        rows_per_position = response.numerics.rows_per_position
    if speed > response.numerics.max_speed * (1 + 1e-12):
        raise WheelrailError(
            f"speed {speed * 3.6:.1f} km/h exceeds the {response.numerics.max_speed * 3.6:.1f} km/h "
            "the stored responses cover"
        )
    L = response.track.support.sleeper_spacing
    values = _rows_from_wedge(
        response.data,
        response.counts,
        response.offsets,
        response.stored_x,
        response.track.rail,
        response.time_step,
        float(speed),
        L,
        rows_per_position,
    )
    return MovingGreenFunctions(
        speed=float(speed),
        sleeper_spacing=L,
        excitation_positions=np.arange(len(values)) * (L / len(values)),
        time_step=response.time_step,
        values=values,
        track=response.track,
        numerics=response.numerics,
    )
