"""A triangle mesh of a cross-section: 6-node (quadratic) triangles filling a closed (r, z) outline.

The outline's edges are cut into pieces of at most ``element_size``; a triangular lattice of points of that
spacing fills the inside, without the points closer to the outline than ``CLEARANCE`` element sizes (so that
every piece of the outline is an edge of the Delaunay triangulation: no point falls in a piece's diametral
circle, of radius at most half an element size); the Delaunay triangles whose centroids lie outside are
dropped, and a mid-side node is added on every edge. The outline must then be exactly the mesh's boundary;
a mesh that misses it (an outline with a gap narrower than the element size) is refused in one line.

Before that the outline is simplified to the element size (:func:`simplified`: the Douglas-Peucker vertices
within ``SIMPLIFY`` element sizes of it, the contact kept), so that a densely measured outline is meshed
with as many elements as a drawn one (:func:`estimated_elements`, known before meshing) and the tables of
points against outline edges stay small (taken ``_CHUNK`` points at a time).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import Delaunay

from wheelrail.core.errors import Blame, WheelrailError

__all__ = ["Mesh", "estimated_elements", "mesh_outline", "simplified"]

CLEARANCE = 0.6  # interior points at least this many element sizes from the outline (> 1/2: see the docstring)
SIMPLIFY = 0.01  # the simplified outline is within this many element sizes of the given one
_CHUNK = 2_000_000  # points x outline edges per table at most (16 MB a float table)


@dataclass(frozen=True)
class Mesh:
    """A 6-node triangle mesh of a cross-section.

    Attributes
    ----------
    nodes : ndarray (n_nodes, 2)
        (r, z) of the nodes, m.
    triangles : ndarray (n_elements, 6) of int
        Corner nodes (counter-clockwise) then the mid-side nodes of edges (0-1), (1-2), (2-0).
    boundary : ndarray (n_edges, 3) of int
        The outline's edges: start corner, mid-side node, end corner (the inside on the left).
    """

    nodes: np.ndarray
    triangles: np.ndarray
    boundary: np.ndarray


def _resampled(outline: np.ndarray, size: float) -> np.ndarray:
    """The outline's vertices with points added so that no piece is longer than ``size``."""
    points = []
    for a, b in zip(outline, np.roll(outline, -1, axis=0), strict=True):
        pieces = max(1, int(np.ceil(np.hypot(*(b - a)) / size - 1e-9)))
        points.extend(a + (b - a) * (k / pieces) for k in range(pieces))
    return np.array(points)


def simplified(outline: np.ndarray, element_size: float, keep=None) -> np.ndarray:
    """The closed ``outline``'s vertices needed to stay within ``SIMPLIFY`` x ``element_size`` of it
    (Douglas-Peucker from the vertex nearest ``keep``, (r, z) in m, and the vertex farthest from it), in order."""
    outline = np.asarray(outline, dtype=float)
    n = len(outline)
    if n <= 4:
        return outline
    first = 0 if keep is None else int(np.argmin(np.hypot(*(outline - np.asarray(keep, dtype=float)).T)))
    ordered = np.roll(outline, -first, axis=0)
    closed = np.vstack([ordered, ordered[:1]])
    far = max(1, int(np.argmax(np.hypot(*(ordered - ordered[0]).T))))
    kept = np.zeros(n + 1, dtype=bool)
    kept[[0, far, n]] = True
    stack, tolerance = [(0, far), (far, n)], SIMPLIFY * element_size
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        distance = _distance_to_segment(closed[i + 1 : j], closed[i], closed[j])
        k = int(np.argmax(distance))
        if distance[k] > tolerance:
            kept[i + 1 + k] = True
            stack += [(i, i + 1 + k), (i + 1 + k, j)]
    return ordered[kept[:n]]


def _distance_to_segment(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = b - a
    t = np.clip((points - a) @ d / max(float(d @ d), 1e-300), 0.0, 1.0)
    return np.hypot(*(points - a - t[:, None] * d).T)


def estimated_elements(outline: np.ndarray, element_size: float) -> int:
    """The number of triangles :func:`mesh_outline` makes of ``outline`` (simplified), without meshing it: 2 I + B - 2
    (Euler's formula for a triangulated polygon of B boundary and I interior points), I the lattice points of
    the area farther than ``CLEARANCE`` element sizes from the outline, B the outline's pieces (within 10 % of
    the mesh's count from 2 to 50 mm elements, tests/unit)."""
    outline = np.asarray(outline, dtype=float)
    length = np.hypot(*(np.roll(outline, -1, axis=0) - outline).T)
    border = int(np.sum(np.maximum(1, np.ceil(length / element_size - 1e-9))))
    r, z = outline[:, 0], outline[:, 1]
    area = abs(0.5 * float(np.sum(r * np.roll(z, -1) - np.roll(r, -1) * z)))
    interior = max(0.0, area - CLEARANCE * element_size * float(length.sum())) / (np.sqrt(3) / 2 * element_size**2)
    return int(round(2 * interior + border - 2))


def _rows(outline: np.ndarray) -> int:
    return max(1, _CHUNK // max(1, len(outline)))


def inside(points: np.ndarray, outline: np.ndarray) -> np.ndarray:
    """Whether each point lies inside the closed outline (even-odd ray casting), ``_CHUNK`` pairs at a time."""
    step = _rows(outline)
    if len(points) > step:
        return np.concatenate([inside(points[i : i + step], outline) for i in range(0, len(points), step)])
    r, z = points[:, 0:1], points[:, 1:2]
    r0, z0 = outline[None, :, 0], outline[None, :, 1]
    r1, z1 = np.roll(outline[:, 0], -1)[None, :], np.roll(outline[:, 1], -1)[None, :]
    crosses = (z0 > z) != (z1 > z)
    with np.errstate(divide="ignore", invalid="ignore"):
        r_cross = r0 + (z - z0) * (r1 - r0) / (z1 - z0)
    return np.sum(crosses & (r < r_cross), axis=1) % 2 == 1


def _distance_to_outline(points: np.ndarray, outline: np.ndarray) -> np.ndarray:
    step = _rows(outline)
    if len(points) > step:
        parts = [_distance_to_outline(points[i : i + step], outline) for i in range(0, len(points), step)]
        return np.concatenate(parts)
    a = outline[None, :, :]
    d = np.roll(outline, -1, axis=0)[None, :, :] - a
    p = points[:, None, :]
    t = np.clip(np.sum((p - a) * d, axis=2) / np.maximum(np.sum(d * d, axis=2), 1e-300), 0.0, 1.0)
    return np.min(np.hypot(*np.moveaxis(p - a - t[..., None] * d, 2, 0)), axis=1)


def _lattice(outline: np.ndarray, size: float) -> np.ndarray:
    (r_min, z_min), (r_max, z_max) = outline.min(axis=0), outline.max(axis=0)
    rows = np.arange(z_min, z_max + size, size * np.sqrt(3) / 2)
    points = [
        np.column_stack([np.arange(r_min + (i % 2) * size / 2, r_max + size, size), np.full_like(np.arange(
            r_min + (i % 2) * size / 2, r_max + size, size), z)]) for i, z in enumerate(rows)
    ]  # fmt: skip
    points = np.concatenate(points)
    keep = inside(points, outline)
    points = points[keep]
    return points[_distance_to_outline(points, outline) > CLEARANCE * size]


def mesh_outline(outline, element_size: float, keep=None) -> Mesh:
    """Quadratic triangles filling ``outline`` ((m, 2) of (r, z), m) with elements of about ``element_size`` (m).

    See the module docstring: the outline is simplified first (:func:`simplified`, ``keep`` (r, z) kept as a
    node); a WheelrailError if the triangles do not fill the outline exactly.
    """
    if not element_size > 0:
        raise WheelrailError("the element size must be > 0", Blame("element_size", element_size, unit="m"))
    outline = simplified(np.asarray(outline, dtype=float), element_size, keep)
    border = _resampled(outline, element_size)
    points = np.concatenate([border, _lattice(outline, element_size)])
    simplices = Delaunay(points).simplices
    centroids = points[simplices].mean(axis=1)
    corners = points[simplices]
    area = 0.5 * (
        (corners[:, 1, 0] - corners[:, 0, 0]) * (corners[:, 2, 1] - corners[:, 0, 1])
        - (corners[:, 2, 0] - corners[:, 0, 0]) * (corners[:, 1, 1] - corners[:, 0, 1])
    )
    keep = inside(centroids, outline) & (np.abs(area) > 1e-6 * element_size**2)
    simplices = np.where((area < 0)[:, None], simplices[:, [0, 2, 1]], simplices)[keep]
    total = np.sum(np.abs(area[keep]))
    r, z = outline[:, 0], outline[:, 1]
    expected = abs(0.5 * np.sum(r * np.roll(z, -1) - np.roll(r, -1) * z))
    if abs(total - expected) > 1e-6 * expected:
        raise WheelrailError(
            f"the cross-section could not be meshed with {element_size * 1e3:g} mm elements (its triangles cover "
            f"{total / expected:.4f} of its area): an outline with parts thinner than an element? use smaller elements",
            Blame("element_size", element_size, unit="m"),
        )
    return _quadratic(points, simplices)


def _quadratic(points: np.ndarray, simplices: np.ndarray) -> Mesh:
    """Mid-side nodes added to 3-node triangles; the boundary's edges found (those of one triangle only)."""
    used = np.unique(simplices)
    renumber = np.full(len(points), -1)
    renumber[used] = np.arange(len(used))
    corners = renumber[simplices]
    edges = np.concatenate([corners[:, [0, 1]], corners[:, [1, 2]], corners[:, [2, 0]]])
    ordered = np.sort(edges, axis=1)
    unique, index, counts = np.unique(ordered, axis=0, return_inverse=True, return_counts=True)
    index = index.reshape(-1)
    mid = len(used) + index
    nodes = np.concatenate([points[used], 0.5 * (points[used][unique[:, 0]] + points[used][unique[:, 1]])])
    n = len(corners)
    triangles = np.column_stack([corners, mid[:n], mid[n : 2 * n], mid[2 * n :]])
    on_boundary = counts[index] == 1
    boundary = np.column_stack([edges[on_boundary, 0], mid[on_boundary], edges[on_boundary, 1]])
    return Mesh(nodes=nodes, triangles=triangles.astype(np.int64), boundary=boundary.astype(np.int64))
