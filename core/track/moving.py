"""Moving Green's functions g_R (eq. 2) read off the stationary response for any speed, refined across the
bay, and the first-order-hold / trapezoidal weights the interaction loop uses. See ``wheelrail.core.track``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    pass

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import FOH_MAX_STEP, TrackNumerics, TrackParameters
from wheelrail.core.track.fe import TrackFEModel, assemble_track
from wheelrail.core.track.stationary import (
    StationaryTrackResponse,
    _check_reach,
    _excitation_nodes,
    _integrate,
    stationary_track_response,
)

# The moving Green's functions of the FE excitation positions are refined this many times across the bay by
# trigonometric interpolation (they are periodic in x0 with period L_S) before the loop interpolates linearly
# between them. Linear interpolation straight between the 16 positions put tones of 32 N at (16 +- 1) v/L_S
# (641 and 727 Hz at 100 km/h) on a smooth rail; refined 4 times they are 0.07 and 0.02 N
# (tests/physics/test_track.py).
BAY_REFINEMENT = 4


def _read_wedge(data, wedge_nodes, offsets, first_offsets, h, phi, dt, speed, out):
    """g[e, s] = w at x_e + v t_s from the stored nodes, with the element's shape functions.

    Vectorised numpy (a few ms per speed): a numba kernel cost 0.4 s at its first call in a process even
    when loaded from numba's cache, most of a cached ``wheelrail track``.
    """
    n_exc, n_samples = out.shape
    inv = 1.0 / (1.0 + phi)
    steps = np.arange(n_samples)
    x_rel = speed * steps * dt - np.asarray(first_offsets, dtype=float)[:, None]
    r = np.minimum((x_rel / h).astype(np.int64), np.asarray(wedge_nodes)[None, :] - 2)
    xi = x_rel / h - r
    xi2 = xi * xi
    xi3 = xi2 * xi
    n1 = inv * (2 * xi3 - 3 * xi2 - phi * xi + 1 + phi)
    n2 = inv * h * (xi3 - (2 + phi / 2) * xi2 + (1 + phi / 2) * xi)
    n3 = inv * (-2 * xi3 + 3 * xi2 + phi * xi)
    n4 = inv * h * (xi3 - (1 - phi / 2) * xi2 - (phi / 2) * xi)
    o = np.asarray(offsets)[None, :] + r
    e = np.arange(n_exc)[:, None]
    out[...] = n1 * data[e, o, 0] + n2 * data[e, o, 1] + n3 * data[e, o + 1, 0] + n4 * data[e, o + 1, 1]


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
