"""What a wheel's cross-section is: the rules every cross-section meets, a parametric profile's and an outline's alike.

:func:`check_section` applies them to a closed outline of (r, z) points (m) and its contact point; the parametric
profile (``profile.WheelProfile``) and an outline (``profile.outline_profile``, a CSV file through
``profile.read_outline``) both pass through it, so the shape options and an outline accept the same wheels. Each
rule, with its reason:

* **One closed curve** (:func:`simple_outline`): at least 3 distinct corners, no edge crossing or touching another
  (a point repeated further along the outline is a touch), enclosing an area. A point repeated at once (and the
  first point repeated at the end) is dropped; either direction is taken (a clockwise outline is reversed). A
  curve that crosses itself has no inside to mesh.
* **Off the axis, around a bore**: every r > 0, the smallest r (the bore, where the axle holds the wheel) within
  ``ACCEPTED["wheel_hub_inner_radius"]`` (axles of 60 to 400 mm).
* **A tread**: the contact's r (the running circle) within ``ACCEPTED["wheel_radius"]``, and nothing more than
  ``ACCEPTED["wheel_flange_height"].maximum`` (a flange's height) above it.
* **Area** at least :data:`MIN_AREA` (10 cm^2): the smallest rim the shape options describe (80 x 15 mm) is 12 cm^2
  alone; a smaller section is a ring or a wire, not a wheel that carries an axle load.
* **Thickness** at least :data:`MIN_THICKNESS` (10 mm, the thinnest web ``ACCEPTED["wheel_web_thickness"]``
  takes) everywhere (:func:`thinnest_part`): a web, rim, flange or hub thinner than that is a membrane whose
  modes fall towards 0 Hz (a 0.2 mm web hangs the rim on a mechanism), not a wheel's.
* **Elements** (:data:`ELEMENT_SIZE`, checked by ``modes.wheel_modes``): 2 to 50 mm; the largest is
  :data:`MAX_ASPECT` x the thinnest part, so a triangle spanning the thinnest part is at most 5 times longer than
  it is wide (a 10 mm web's lowest axial modes at 50 mm elements within 1.5 % of a 4 mm mesh's); below 2 mm the
  cost (``modes.modes_cost``) grows beyond what a wheel needs (12 mm converges to 1 % up to 10 kHz).
* **Outline files** (``profile.read_outline``): a regular file (not a FIFO, a device, a folder) of at most
  :data:`MAX_OUTLINE_BYTES` and :data:`MAX_OUTLINE_POINTS` points: a measured or drawn wheel profile has a few
  thousand points at most (a profilometer's tread scan: about 1 000), and the checks above cost the square of
  the number of points.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.ranges import ACCEPTED, ROUND_OFF

__all__ = [
    "ELEMENT_SIZE",
    "MAX_ASPECT",
    "MAX_OUTLINE_BYTES",
    "MAX_OUTLINE_POINTS",
    "MIN_AREA",
    "MIN_THICKNESS",
    "check_element_size",
    "check_section",
    "simple_outline",
    "thinnest_part",
]

MIN_AREA = 10e-4  # m^2 (module docstring)
MIN_THICKNESS = ACCEPTED["wheel_web_thickness"].minimum  # m: 10 mm
MAX_ASPECT = 5.0  # largest element size / thinnest part
ELEMENT_SIZE = (0.002, MAX_ASPECT * MIN_THICKNESS)  # m: 2 to 50 mm
OUTLINE_REACH = 2 * ACCEPTED["wheel_radius"].maximum  # m: no coordinate of a wheel's outline is larger
MAX_OUTLINE_POINTS = 5000
MAX_OUTLINE_BYTES = 1_000_000  # 5 000 points of two numbers with 9 digits each and a header take ~125 kB
_ACROSS = 3.0  # two boundary points face each other across the material if the boundary between them is longer
_SAMPLES = 4000  # the thickness is measured between this many boundary points at most (every MIN_THICKNESS / 5)
_PAIRS = 1_000_000  # edge pairs compared at a time


def simple_outline(points) -> np.ndarray:
    """``points`` ((n, 2) of (r, z), m) as one closed curve, counter-clockwise, without repeated points.

    Raises
    ------
    WheelrailError
        Fewer than 3 distinct corners, values not finite, an outline that crosses or touches itself or encloses
        no area (parameter ``outline``), in one line.
    """
    array = np.asarray(points, dtype=float)
    if array.ndim != 2 or array.shape[1] != 2 or not np.all(np.isfinite(array)):
        raise WheelrailError("a wheel outline is (r, z) points of two finite numbers each", Blame("outline"))
    keep = np.r_[True, np.any(np.diff(array, axis=0) != 0, axis=1)] if len(array) else np.zeros(0, bool)
    array = array[keep]
    if len(array) > 1 and np.array_equal(array[0], array[-1]):
        array = array[:-1]
    if len(array) < 3:
        raise WheelrailError("a wheel outline needs at least 3 distinct (r, z) points", Blame("outline"))
    if np.max(np.abs(array)) > OUTLINE_REACH:  # before any product of coordinates (no overflow)
        raise WheelrailError(f"a point of the outline is {np.max(np.abs(array)) * 1e3:.6g} mm from the axle's axis or "
                             f"the web's midplane; a wheel's are within {OUTLINE_REACH * 1e3:g} mm (twice the largest "
                             "wheel radius)", Blame("outline"))  # fmt: skip
    if _crossing(array):
        raise WheelrailError("the outline crosses or touches itself: a wheel outline is one closed curve, each "
                             "point once", Blame("outline"))  # fmt: skip
    area = signed_area(array)
    if area == 0:
        raise WheelrailError("the outline encloses no area", Blame("outline"))
    return array if area > 0 else array[::-1].copy()


def signed_area(points: np.ndarray) -> float:
    """The area enclosed by the closed polygon, m^2, > 0 when counter-clockwise in the (r, z) plane."""
    r, z = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(r * np.roll(z, -1) - np.roll(r, -1) * z))


def _orientation(p, q, s) -> np.ndarray:
    turn = (q[..., 0] - p[..., 0]) * (s[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (s[..., 0] - p[..., 0])
    return np.sign(turn)


def _crossing(points: np.ndarray) -> bool:
    """Whether two non-adjacent edges of the closed polygon cross or touch (collinear overlaps included).

    Only edges whose r ranges overlap are compared (the edges sorted by their smallest r, each against those
    starting before it ends), ``_PAIRS`` pairs at a time.
    """
    m = len(points)
    a, b = points, np.roll(points, -1, axis=0)
    low, high = np.minimum(a, b), np.maximum(a, b)
    order = np.argsort(low[:, 0], kind="stable")
    ends = np.searchsorted(low[order, 0], high[order, 0], side="right")  # edges order[k + 1 : ends[k]] overlap
    counts = np.maximum(ends - np.arange(m) - 1, 0)
    first = np.repeat(np.arange(m), counts)
    offset = np.arange(len(first)) - np.repeat(np.cumsum(counts) - counts, counts)
    second = first + 1 + offset
    for start in range(0, len(first), _PAIRS):
        i, j = order[first[start : start + _PAIRS]], order[second[start : start + _PAIRS]]
        gap = np.abs(i - j)
        apart = (gap > 1) & (gap < m - 1)  # neighbours share a corner
        boxes = np.all((low[i] <= high[j]) & (low[j] <= high[i]), axis=-1)  # nearly collinear edges apart
        i, j = i[apart & boxes], j[apart & boxes]
        o1, o2 = _orientation(a[i], b[i], a[j]), _orientation(a[i], b[i], b[j])
        o3, o4 = _orientation(a[j], b[j], a[i]), _orientation(a[j], b[j], b[i])
        if np.any((o1 * o2 <= 0) & (o3 * o4 <= 0)):  # each edge's ends on both sides of the other, or on it
            return True
    return False


def _boundary_samples(outline: np.ndarray):
    """Points evenly spaced along the outline (at most ``_SAMPLES``), their arc positions, the inward normals and
    the perimeter."""
    d = np.roll(outline, -1, axis=0) - outline
    length = np.hypot(d[:, 0], d[:, 1])
    ends = np.cumsum(length)
    total = float(ends[-1])
    count = int(min(_SAMPLES, max(8, math.ceil(total / (MIN_THICKNESS / 5)))))
    arc = (np.arange(count) + 0.5) * total / count
    edge = np.minimum(np.searchsorted(ends, arc, side="right"), len(outline) - 1)
    t = (arc - (ends[edge] - length[edge])) / length[edge]
    points = outline[edge] + t[:, None] * d[edge]
    tangent = d[edge] / length[edge][:, None]
    return points, arc, np.column_stack([-tangent[:, 1], tangent[:, 0]]), total, edge


def thinnest_part(outline: np.ndarray, below: float = 0.1) -> tuple[float, tuple[float, float]]:
    """The thickness of the section's thinnest part, m, and where it is ((r, z) of its middle, m), if it is
    thinner than ``below`` (m; else inf and NaNs).

    Measured between boundary points that face each other across the material: each in front of the other
    (within 60 degrees of its inward normal), the boundary between them at least 3 times longer than the gap (a
    corner's two sides are not a thickness). ``outline`` is counter-clockwise (:func:`simple_outline`); a part
    no longer than about its thickness (a short bump) is not counted as thin. Only the pairs of boundary points
    closer than ``below`` are compared (a k-d tree's).
    """
    from scipy.spatial import cKDTree

    points, arc, normal, total, edge = _boundary_samples(outline)
    i, j = cKDTree(points).query_pairs(below, output_type="ndarray").T.astype(np.int64)
    gap = points[j] - points[i]
    distance = np.hypot(gap[:, 0], gap[:, 1])
    along = np.abs(arc[j] - arc[i])
    along = np.minimum(along, total - along)
    facing = (np.sum(gap * normal[i], axis=1) > 0.5 * distance) & (np.sum(-gap * normal[j], axis=1) > 0.5 * distance)
    distance = np.where(facing & (along > _ACROSS * distance), distance, np.inf)
    if not len(distance) or not np.isfinite(distance.min()):
        return math.inf, (math.nan, math.nan)
    k = int(np.argmin(distance))
    pair = int(i[k]), int(j[k])
    # the samples are up to half a spacing apart along the boundary: the thickness is from each to the other's edge
    ends = np.roll(outline, -1, axis=0)
    (i, j), closest = pair, []
    for here, there in ((i, j), (j, i)):
        a, b = outline[edge[there]], ends[edge[there]]
        t = np.clip(np.dot(points[here] - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
        closest.append((float(np.hypot(*(points[here] - a - t * (b - a)))), points[here], a + t * (b - a)))
    thickness, p, q = min(closest, key=lambda item: item[0])
    return thickness, tuple(float(v) for v in 0.5 * (p + q))


def _mm(value: float) -> str:
    return f"{round(value * 1e3, 1):g}"


def check_section(outline: np.ndarray, contact: tuple[float, float], parameter: str | None = "outline",
                  blame=None) -> float:  # fmt: skip
    """Check that the counter-clockwise simple ``outline`` with the ``contact`` point (m) is a wheel (module
    docstring); returns its thinnest part's thickness, m (inf: none thinner than 10 cm).

    Parameters
    ----------
    outline : ndarray (n, 2)
        (r, z) of the outline, m, from :func:`simple_outline`.
    contact : (float, float)
        (r, z) of the contact on the tread, m.
    parameter : str, optional
        The input the errors name (``outline``; None for a parametric profile, which names its own fields).
    blame : callable, optional
        ``blame(r, z)``: the error's :class:`~wheelrail.core.errors.Blame` (the field to blame) for a part too thin
        at (r, z) (m), naming the input that shapes it (a parametric profile's field); None: ``parameter``.

    Raises
    ------
    WheelrailError
        The first rule broken, in one line with the value found and the limit (mm, cm^2).
    """
    r = outline[:, 0]
    if np.any(r <= 0):
        raise WheelrailError("a wheel outline's points have r > 0 (no point on the axle's axis)", Blame(parameter))
    area = signed_area(outline)
    if area < MIN_AREA:
        raise WheelrailError(
            f"the cross-section's area is {area * 1e4:.3g} cm^2; a wheel's is at least "
            f"{MIN_AREA * 1e4:g} cm^2 (the smallest rim alone, 80 x 15 mm, is 12 cm^2)",
            Blame(parameter),
        )
    bore, tread = ACCEPTED["wheel_hub_inner_radius"], ACCEPTED["wheel_radius"]
    if not bore.minimum * (1 - ROUND_OFF) <= r.min() <= bore.maximum * (1 + ROUND_OFF):
        raise WheelrailError(f"the bore (the smallest r) is at {_mm(r.min())} mm; accepted {_mm(bore.minimum)} to "
                             f"{_mm(bore.maximum)} mm ({bore.reason})", Blame(parameter))  # fmt: skip
    if not tread.minimum * (1 - ROUND_OFF) <= contact[0] <= tread.maximum * (1 + ROUND_OFF):
        raise WheelrailError(f"the tread (the contact's r) is at {_mm(contact[0])} mm; accepted {_mm(tread.minimum)} "
                             f"to {_mm(tread.maximum)} mm ({tread.reason})", Blame(parameter))  # fmt: skip
    flange = ACCEPTED["wheel_flange_height"].maximum
    if r.max() > contact[0] + flange * (1 + 1e-9):
        raise WheelrailError(f"the outline reaches {_mm(r.max() - contact[0])} mm above the tread (the contact's r); "
                             f"at most {_mm(flange)} mm (a flange's height)", Blame(parameter))  # fmt: skip
    thickness, (r_thin, z_thin) = thinnest_part(outline)
    if thickness < MIN_THICKNESS * (1 - 1e-9):
        raise WheelrailError(f"the cross-section is {_mm(thickness)} mm thick at r = {_mm(r_thin)} mm, z = "
                             f"{_mm(z_thin)} mm; every part of a wheel is at least {_mm(MIN_THICKNESS)} mm thick "
                             "(a thinner web or flange is a membrane, its modes near 0 Hz)",
                             blame(r_thin, z_thin) if blame is not None else Blame(parameter))  # fmt: skip
    return thickness


def check_element_size(element_size) -> float:
    """``element_size`` (m) as a float within :data:`ELEMENT_SIZE`, else one WheelrailError (parameter
    ``wheel_element_size``)."""
    low, high = ELEMENT_SIZE
    if (
        isinstance(element_size, bool)
        or not isinstance(element_size, int | float | np.floating)
        or not (low * (1 - 1e-12) <= element_size <= high * (1 + 1e-12))
    ):
        raise WheelrailError(
            None,
            Blame(
                "wheel_element_size",
                element_size,
                unit="m",
                minimum=low,
                maximum=high,
                reason=f"at most {MAX_ASPECT:g} times the thinnest part a wheel may have, {_mm(MIN_THICKNESS)} mm; "
                f"below {_mm(low)} mm the modes cost more than a wheel needs",
            ),
        )
    return float(element_size)
