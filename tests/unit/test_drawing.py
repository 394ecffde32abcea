"""Drawing helpers shared by the recording and the explorer (core/drawing/patch.py)."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.drawing.patch import (
    VIRIDIS_ANCHORS,
    circle_points,
    circle_segments,
    colour_table,
    grid_triangles,
    packed_rgba,
    table_colours,
)


@pytest.mark.parametrize(("ny", "nx"), [(2, 2), (3, 7), (25, 25)])
def test_grid_triangles_tile_the_grid_once_counter_clockwise(ny, nx):
    triangles = grid_triangles(ny, nx)
    assert triangles.dtype == np.uint32 and triangles.shape == (2 * (ny - 1) * (nx - 1), 3)
    x, y = np.meshgrid(np.arange(nx, dtype=float), np.arange(ny, dtype=float))
    points = np.c_[x.ravel(), y.ravel()]
    a, b, c = (points[triangles[:, k]] for k in range(3))
    twice_area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    # exact: unit cells of integer coordinates, each split in two halves of area 1/2, none flipped
    np.testing.assert_array_equal(twice_area, np.ones(len(triangles)))
    assert twice_area.sum() / 2 == (nx - 1) * (ny - 1)  # the whole grid, once
    assert len({tuple(sorted(t)) for t in triangles.tolist()}) == len(triangles)  # no triangle twice


def test_circle_has_the_radius_and_closes():
    points = circle_points(5.48e-3)
    assert points.shape == (97, 2)
    # 1e-15 m: cos^2 + sin^2 = 1 to round-off
    np.testing.assert_allclose(np.hypot(points[:, 0], points[:, 1]), 5.48e-3, rtol=0, atol=1e-15)
    np.testing.assert_allclose(points[-1], points[0], atol=1e-15)
    segments = circle_segments(2.0, 0.5, n=12)
    assert segments.shape == (12, 2, 3) and segments.dtype == np.float32
    np.testing.assert_array_equal(segments[1:, 0], segments[:-1, 1])  # joined end to start
    assert np.all(segments[..., 2] == 0.5)


def test_colour_table_runs_through_the_viridis_anchors():
    table = colour_table(257)  # 257 levels put the anchors on entries 0, 64, 128, 192, 256
    np.testing.assert_array_equal(table[::64], VIRIDIS_ANCHORS.astype(np.uint8))
    packed = packed_rgba(table[:1])
    assert packed[0] == (68 << 24) | (1 << 16) | (84 << 8) | 0xFF  # 0xRRGGBBAA, opaque


def test_table_colours_clip_to_the_range():
    table = colour_table()
    colours = table_colours(np.array([-1.0, 0.0, 0.5, 1.0, 3.0]), 1.0, table)
    np.testing.assert_array_equal(colours[[0, 1]], table[[0, 0]])  # below 0: the first colour
    np.testing.assert_array_equal(colours[[3, 4]], table[[255, 255]])  # at and above top: the last
    np.testing.assert_array_equal(colours[2], table[127])  # 0.5 * 255 = 127.5, truncated
