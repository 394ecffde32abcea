"""The contact patch as the rerun recording and the explorer draw it: colour ramp, grid triangles, circles.

numpy only (no rerun, no viser): both front ends draw the same pressure colours, the same triangulation
of a window of elements and the same Hertz circle, and each passes the arrays to its own library.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "PRESSURE_RANGE_P0",
    "VIRIDIS_ANCHORS",
    "circle_points",
    "circle_segments",
    "colour_table",
    "grid_triangles",
    "packed_rgba",
    "table_colours",
]

PRESSURE_RANGE_P0 = 2.0
"""Top of the pressure colour ramp in both front ends (the recording's image and surface, the explorer's heat map
and colour bar), times the Hertz peak pressure p0 at the preload: rough contacts exceed p0, so the ramp runs on
to twice it and p0 sits at its middle."""

# viridis (matplotlib's default colour map) at 0, 1/4, 1/2, 3/4 and 1, sRGB 0..255; linear interpolation
# between these five stays within 26/255 of the full map in every channel, enough for a readable ramp
VIRIDIS_ANCHORS = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], dtype=float)


def colour_table(levels: int = 256) -> np.ndarray:
    """The viridis ramp as ``levels`` RGB colours, uint8 array (levels, 3), dark (low) to yellow (high)."""
    anchors = VIRIDIS_ANCHORS
    u = np.linspace(0.0, len(anchors) - 1, levels)
    low = np.minimum(u.astype(np.int64), len(anchors) - 2)
    frac = (u - low)[:, None]
    return np.round(anchors[low] * (1.0 - frac) + anchors[low + 1] * frac).astype(np.uint8)


def packed_rgba(rgb: np.ndarray) -> np.ndarray:
    """RGB uint8 rows (n, 3) as opaque packed 0xRRGGBBAA uint32 colours (rerun's ``Rgba32``)."""
    rgb = np.asarray(rgb).astype(np.uint32)
    return (rgb[:, 0] << 24) | (rgb[:, 1] << 16) | (rgb[:, 2] << 8) | np.uint32(0xFF)


def table_colours(values: np.ndarray, top: float, table: np.ndarray) -> np.ndarray:
    """Colours of ``values`` from a colour ``table`` spanning 0..top (a table look-up per value).

    Values below 0 take the first entry, above ``top`` the last; the result has the shape of ``values``
    followed by the shape of one table entry.
    """
    index = np.clip(values * np.float32((len(table) - 1) / top), 0, len(table) - 1)
    return table[index.astype(np.uint8 if len(table) <= 256 else np.int64)]


def grid_triangles(ny: int, nx: int) -> np.ndarray:
    """Triangles (uint32, (2 (ny-1)(nx-1), 3)) of a row-major ny x nx vertex grid, two per cell.

    Cell (i, j) with corner v = i nx + j gives (v, v+1, v+nx) and (v+1, v+nx+1, v+nx), cell by cell,
    both counter-clockwise seen from +z when x grows along a row and y down the rows.
    """
    v = (np.arange(ny - 1)[:, None] * nx + np.arange(nx - 1)[None, :]).ravel()
    first = np.stack([v, v + 1, v + nx], axis=1)
    second = np.stack([v + 1, v + nx + 1, v + nx], axis=1)
    return np.stack([first, second], axis=1).reshape(-1, 3).astype(np.uint32)


def circle_points(radius: float, n: int = 96, radius_y: float | None = None) -> np.ndarray:
    """Closed polyline (n + 1, 2) of a circle of ``radius`` about the origin (first point repeated last), or of
    the ellipse of semi-axes ``radius`` along x and ``radius_y`` along y."""
    angle = np.linspace(0.0, 2 * np.pi, n + 1)
    return np.c_[radius * np.cos(angle), (radius if radius_y is None else radius_y) * np.sin(angle)]


def circle_segments(radius: float, z: float, n: int = 96, radius_y: float | None = None) -> np.ndarray:
    """The circle (or ellipse) of :func:`circle_points` as n line segments (n, 2, 3) float32 at height ``z``."""
    points = np.c_[circle_points(radius, n, radius_y), np.full(n + 1, z)]
    return np.stack([points[:-1], points[1:]], axis=1).astype(np.float32)
