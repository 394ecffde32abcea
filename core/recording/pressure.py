"""The contact entities of a recording: pressure maps (images), the pressure surface (meshes) and the
nominal Hertz circle, on the window of elements of a model with a lateral window (3D).

The pressure surface is a visual aid and costs several times the image (rerun encodes each of its vertices), so
it is recorded at every ``surface_every``-th recorded map only; the exact maps are the images.
"""

from __future__ import annotations

import functools

import numpy as np

from wheelrail.core.drawing.patch import PRESSURE_RANGE_P0, circle_points, colour_table, grid_triangles, packed_rgba
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.recording.columns import blob_column, colour_column, position_column
from wheelrail.core.recording.schema import (
    NOMINAL_CIRCLE,
    NOMINAL_CIRCLE_IMAGE,
    PRESSURE,
    PRESSURE_SURFACE,
    rerun_module,
    time_columns,
)

__all__ = ["ContactPatch", "hertz_geometry", "hertz_semi_axes", "surface_kernel"]

_COLOUR_TABLE = packed_rgba(colour_table())  # viridis as rerun's packed Rgba32


def hertz_geometry(contact: ContactParameters) -> tuple[float, float]:
    """(Hertz radius a in m, Hertz peak pressure p0 in Pa) at the preload."""
    return contact.hertz_radius(), contact.hertz_peak_pressure()


def hertz_semi_axes(contact: ContactParameters) -> tuple[float, float] | None:
    """Semi-axes (along, across the rail) of an elliptic Hertz patch at the preload, m; None for a circle."""
    return None if contact.circular else contact.hertz_semi_axes()


@functools.cache
def surface_kernel():
    """The compiled fill of the surface meshes: vertices (x', y', a p / p0) and their viridis colours, in one pass.

    The same numbers as numpy's ``vertices[..., 2] = p * np.float32(a / p0)`` and ``table_colours`` (float32
    products; the colour index truncated, clipped to the table), written in one pass over the interleaved vertices,
    where numpy's strided writes cost most (``tests/recording/test_recording.py`` compares them;
    ``benchmarks/recording.py`` times them).
    """
    from numba import njit

    @njit(cache=True)
    def fill(pressure, xy, height, scale, table, vertices, colours):
        top = np.float32(len(table) - 1)
        for i in range(pressure.shape[0]):
            for j in range(pressure.shape[1]):
                p = pressure[i, j]
                vertices[i, j, 0] = xy[j, 0]
                vertices[i, j, 1] = xy[j, 1]
                vertices[i, j, 2] = p * height
                u = min(max(p * scale, np.float32(0.0)), top)
                colours[i, j] = table[np.uint8(u)]

    return fill


class ContactPatch:
    """Writes the contact entities of one recording stream.

    Parameters
    ----------
    stream : rerun.RecordingStream
        Where to log.
    record_every, surface_every : int
        A pressure surface is sent for the maps of steps that are multiples of ``record_every *
        surface_every``.
    """

    def __init__(self, stream, *, record_every: int, surface_every: int) -> None:
        self.stream = stream
        self.surface_period = record_every * surface_every
        self.window: tuple[np.ndarray, np.ndarray] | None = None  # element centres x', y' (m)
        self.geometry: tuple[float, float] | None = None  # (a, p0) at the preload
        self.semi_axes: tuple[float, float] | None = None  # Hertz semi-axes along/across (elliptic patch)
        self._surface_xy: np.ndarray | None = None  # (ny nx, 2) float32 vertices of the window
        self.maps_recorded = 0

    def set_window(self, window_x, window_y) -> None:
        """The window's element centres relative to the wheel centre, m (kept if already known)."""
        if self.window is None and window_x is not None and window_y is not None:
            self.window = (np.asarray(window_x, float), np.asarray(window_y, float))

    def set_geometry(
        self, geometry: tuple[float, float], *, log: bool = True, semi_axes: tuple[float, float] | None = None
    ) -> None:
        """Hertz radius and peak pressure (and the semi-axes of an elliptic patch); the nominal circle or
        ellipse is logged again when they changed."""
        changed = geometry != self.geometry or semi_axes != self.semi_axes
        self.geometry = geometry
        self.semi_axes = semi_axes
        if log and changed:
            self.log_circle()

    def log_circle(self) -> None:
        """The Hertz circle of radius a: in m (3D view) and, once the window is known, in image pixels."""
        rr = rerun_module()
        a = self.geometry[0]
        circle = circle_points(a)
        label = f"Hertz circle a = {a * 1e3:.2f} mm"
        if self.semi_axes is not None:  # elliptic patch: a along the rail, b across
            along, across = self.semi_axes
            circle = circle_points(along, radius_y=across)
            label = f"Hertz ellipse a = {along * 1e3:.2f} mm, b = {across * 1e3:.2f} mm"
        self.stream.log(
            NOMINAL_CIRCLE,
            rr.LineStrips3D([np.c_[circle, np.zeros(len(circle))]], colors=[(255, 255, 255)], labels=[label]),
            static=True,
            strict=True,
        )
        if self.window is not None:
            self._log_circle_pixels(circle)

    def _log_circle_pixels(self, circle: np.ndarray) -> None:
        # pixel (column j, row i) covers [j, j+1] x [i, i+1]: element centre x_j sits at j + 0.5
        x, y = self.window
        dx = float(x[1] - x[0]) if len(x) > 1 else 1.0
        dy = float(y[1] - y[0]) if len(y) > 1 else dx
        pixels = np.c_[(circle[:, 0] - x[0]) / dx + 0.5, (circle[:, 1] - y[0]) / dy + 0.5]
        self.stream.log(
            NOMINAL_CIRCLE_IMAGE,
            rerun_module().LineStrips2D([pixels], colors=[(255, 255, 255)], draw_order=10.0),
            static=True,
            strict=True,
        )

    def send(self, pressure_steps, time, x, pressure, *, element_size: float) -> None:
        """Send the maps ``pressure`` (n, ny, nx; Pa) of ``pressure_steps`` at wheel positions x, times time.

        Without a known window the maps are taken on a grid of ``element_size`` (m) centred on the wheel.
        """
        pressure = np.ascontiguousarray(pressure, dtype=np.float32)
        n, ny, nx = pressure.shape
        if self.window is None:  # no window given: element centres of a grid centred on the wheel
            self.window = ((np.arange(nx) - (nx - 1) / 2) * element_size, (np.arange(ny) - (ny - 1) / 2) * element_size)
            self._log_circle_pixels(
                circle_points(self.geometry[0])
                if self.semi_axes is None
                else circle_points(self.semi_axes[0], radius_y=self.semi_axes[1])
            )
        wx, wy = self.window
        if (len(wy), len(wx)) != (ny, nx):
            raise WheelrailError(f"pressure maps are {ny} x {nx} but the window is {len(wy)} x {len(wx)}")
        if self._surface_xy is None:
            self._log_formats(nx, ny)
        indexes = time_columns(pressure_steps, time, x)
        self.stream.send_columns(PRESSURE, indexes, [blob_column(pressure)], strict=True)
        surface = pressure_steps % self.surface_period == 0
        if surface.any():
            self._send_surface(
                pressure[surface],
                indexes if surface.all() else time_columns(pressure_steps[surface], time[surface], x[surface]),
            )
        self.maps_recorded += n

    def _log_formats(self, nx: int, ny: int) -> None:
        """The static parts: image format and colour range, and the surface mesh's (x', y') and triangles."""
        rr = rerun_module()
        p0 = self.geometry[1]
        self.stream.log(
            PRESSURE,
            rr.DepthImage.from_fields(
                format=rr.components.ImageFormat(width=nx, height=ny, channel_datatype="F32", color_model="L"),
                colormap="viridis",
                depth_range=(0.0, PRESSURE_RANGE_P0 * p0),
                meter=1.0,
            ),
            static=True,
            strict=True,
        )
        gx, gy = np.meshgrid(*self.window)
        self._surface_xy = np.c_[gx.ravel(), gy.ravel()].astype(np.float32)
        self.stream.log(
            PRESSURE_SURFACE,
            rr.Mesh3D(
                vertex_positions=np.c_[self._surface_xy, np.zeros(nx * ny, np.float32)],
                triangle_indices=grid_triangles(ny, nx),
            ),
            static=True,
            strict=True,
        )

    def _send_surface(self, pressure: np.ndarray, indexes: list) -> None:
        """The pressure surface meshes (z = a p / p0, viridis colours) of the given maps."""
        n, ny, nx = pressure.shape
        a, p0 = self.geometry
        vertices = np.empty((n, ny * nx, 3), dtype=np.float32)
        colours = np.empty((n, ny * nx), dtype=np.uint32)
        scale = np.float32((len(_COLOUR_TABLE) - 1) / (PRESSURE_RANGE_P0 * p0))  # as table_colours scales
        fill = surface_kernel()
        fill(pressure.reshape(n, -1), self._surface_xy, np.float32(a / p0), scale, _COLOUR_TABLE, vertices, colours)
        self.stream.send_columns(
            PRESSURE_SURFACE, indexes, [position_column(vertices), colour_column(colours)], strict=True
        )
