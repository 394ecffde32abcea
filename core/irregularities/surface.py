"""The surface deviation of a set of irregularities, to be added to the combined roughness r = r_W - r_R.

Heights as in :mod:`wheelrail.core.irregularities.shapes`: positive where the surfaces are pushed together,
negative for a flat or a dip. Several irregularities superpose by position (their heights add), as wheel and rail
roughness do. A wheel's deviation is written where the rail meets it: a flat at each meeting x_F + k 2 pi R; a new
flat's chord as a round wheel of radius R sees it, -(D - (R - sqrt(R^2 - s^2))) for |s| < L/2, so that a rigid
wheel resting on the chord has its centre exactly D low (the wheel-centre trajectory of
:mod:`wheelrail.core.irregularities.trajectory`). A joint's gap is a floor deeper than any wheel can reach
(below the lower end by g^2 / (4 R) + 1 mm): the wheel bridges it.
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.irregularities.shapes import (
    DippedWeld,
    RailJoint,
    Squat,
    WheelFlat,
    flat_depth,
    flat_meetings,
)
from wheelrail.core.irregularities.trajectory import positive_length

__all__ = ["GAP_CLEARANCE", "raw_profile", "surface_deviation"]

GAP_CLEARANCE = 1e-3  # m the gap's floor lies below the deepest a rigid wheel could sag into it


def _raised_cosine(s: np.ndarray, length: float) -> np.ndarray:
    """c(s, L) = (1 + cos(2 pi s / L)) / 2 for |s| < L/2, else 0."""
    inside = np.abs(s) < 0.5 * length
    return np.where(inside, 0.5 * (1.0 + np.cos(2.0 * np.pi * s / length)), 0.0)


def _flat(flat: WheelFlat, x: np.ndarray, radius: float) -> np.ndarray:
    depth = flat_depth(flat, radius)
    out = np.zeros_like(x)
    for centre in flat_meetings(flat, radius, float(x.max()) if x.size else 0.0):
        s = x - centre
        inside = np.abs(s) < 0.5 * flat.length
        if flat.shape == "new":
            sag = s[inside] ** 2 / (radius + np.sqrt(radius**2 - s[inside] ** 2))  # R - sqrt(R^2 - s^2), exact
            out[inside] -= depth - sag
        else:
            out -= depth * _raised_cosine(s, flat.length)
    return out


def _joint(joint: RailJoint, x: np.ndarray, radius: float) -> np.ndarray:
    before = (joint.position - 0.5 * joint.gap) - x
    after = x - (joint.position + 0.5 * joint.gap)
    dip = joint.dip_angle * np.maximum(0.0, joint.dip_length - np.maximum(before, after))
    height = np.where(after >= 0.0, joint.step, 0.0) - dip
    floor = min(0.0, joint.step) - joint.dip_angle * joint.dip_length - joint.gap**2 / (4.0 * radius)
    return np.where((before > 0.0) | (after >= 0.0), height, floor - GAP_CLEARANCE)


def surface_deviation(irregularities, x, y=(0.0,), *, wheel_radius: float) -> np.ndarray:
    """The irregularities' surface deviation on a grid: x along the rail by y across the railhead.

    Parameters
    ----------
    irregularities : iterable of WheelFlat, RailJoint, DippedWeld or Squat
        Checked against the run by :func:`~wheelrail.core.irregularities.shapes.check_irregularities`.
    x : array_like, 1-D
        Positions along the rail, m (the run's grid; a flat is written at each of its meetings up to max(x)).
    y : array_like, 1-D
        Lateral positions of the lines, m (the 3D model's lines; y = 0 the running line). A flat, a joint and a
        weld span the running band; a squat only its width.
    wheel_radius : float
        R, m: a flat's default depth, its chord and its repeat 2 pi R; a joint's gap floor.

    Returns
    -------
    ndarray, shape (len(y), len(x))
        Height to add to the combined roughness, m (one row per line, as ``RoughnessSet.heights``).

    Raises
    ------
    WheelrailError
        If x or y is not a 1-D array of finite numbers or the radius is not positive.

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.irregularities import DippedWeld, Squat, surface_deviation
    >>> x = np.linspace(0.0, 1.0, 11)
    >>> weld, squat = DippedWeld(position=0.5, length=0.4, depth=1e-4), Squat(
    ...     position=0.5, length=0.04, width=0.02, depth=5e-5, lateral_position=0.01)
    >>> surface_deviation([weld, squat], x, [0.0, 0.01], wheel_radius=0.46)[:, 5] * 1e6    # um, at x = 0.5 m
    array([-100., -150.])
    """
    x_values, y_values = _axis("x", x), _axis("y", y)
    wheel_radius = positive_length("wheel_radius", wheel_radius)
    along = np.zeros_like(x_values)
    out = np.zeros((y_values.size, x_values.size))
    for item in irregularities:
        if isinstance(item, WheelFlat):
            along += _flat(item, x_values, wheel_radius)
        elif isinstance(item, RailJoint):
            along += _joint(item, x_values, wheel_radius)
        elif isinstance(item, DippedWeld):
            along -= item.depth * _raised_cosine(x_values - item.position, item.length)
        elif isinstance(item, Squat):
            across = _raised_cosine(y_values - item.lateral_position, item.width)
            out -= item.depth * np.outer(across, _raised_cosine(x_values - item.position, item.length))
        else:
            raise WheelrailError(
                f"an irregularity must be a WheelFlat, RailJoint, DippedWeld or Squat, got {type(item).__name__}"
            )
    return out + along


def raw_profile(irregularities, x, *, wheel_radius: float) -> np.ndarray:
    """The deviation on the running line y = 0: what a Hertz spring on the "raw" profile sees (no bridging).

    Parameters
    ----------
    irregularities : iterable of WheelFlat, RailJoint, DippedWeld or Squat
    x : array_like, 1-D
        Positions along the rail, m.
    wheel_radius : float
        R, m (:func:`surface_deviation`).

    Returns
    -------
    ndarray, shape (len(x),)
        Height to add to the combined roughness's running line, m; the Hertz models are to be driven by its
        :func:`~wheelrail.core.irregularities.trajectory.wheel_centre_trajectory` instead, or by this (the "raw"
        choice).
    """
    return surface_deviation(irregularities, x, (0.0,), wheel_radius=wheel_radius)[0]


def _axis(name: str, values) -> np.ndarray:
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError(f"{name} must be a 1-D array of positions in m") from None
    if array.ndim != 1 or not np.all(np.isfinite(array)):
        raise WheelrailError(f"{name} must be a 1-D array of finite positions in m, got shape {array.shape}")
    return array
