"""The explorer's 3D view: the contact patch as a pressure heat map with the Hertz ellipse on top.

Scale: 1 scene unit = 10 mm (``SCENE_PER_MM``); +z up, x along the rail (the rolling direction, +x), y
across. The view opens from straight above (:func:`top_view`: an ellipse keeps its proportions on screen);
*Oblique view* tilts it; both are fitted to the 3D view's width and height. Beside the patch: a 1 mm grid
(5 mm sections) under it, arrows for x (rolling direction) and y (across the rail), and the nominal Hertz
ellipse at the preload with its semi-axes a (along) and b (across) drawn and labelled
(``ContactParameters.hertz_semi_axes``; a circle in the paper's case).

For ``3d`` (a model with a pressure map) the window's pressure is a heat map (viridis, 0 to ``PRESSURE_TOP``
times the Hertz peak pressure p0 at the preload, as recordings draw it; the colour bar of :func:`colour_bar_image`,
which marks p0) and,
when switched on, the same pressure as a raised surface; for the one-line models the contact length is a
strip and the Hertz ellipse at the current force is drawn. :meth:`PatchScene.clear` takes every drawn run
away (a configuration without a run). Rail and wheel surfaces with their roughness (exaggerated) and
curvatures are off unless switched on; they are drawn at the step shown, the rail below the patch's plane
and the wheel as lines above it, so neither hides the patch. Handles are created once and updated in place.
"""

from __future__ import annotations

import math

import numpy as np
import viser

from wheelrail.core.drawing.patch import PRESSURE_RANGE_P0, circle_segments, colour_table, grid_triangles, table_colours
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.roughness import at_lateral_positions, covers

__all__ = [
    "PRESSURE_TOP",
    "SCENE_PER_MM",
    "PatchScene",
    "colour_bar_image",
    "oblique_view",
    "set_initial_camera",
    "top_view",
]

SCENE_PER_MM = 0.1
PRESSURE_TOP = PRESSURE_RANGE_P0  # colour scale top, times the Hertz peak pressure p0 at the preload (core's)
PRESSURE_HEIGHT = 3.0  # mm of raised surface per GPa
ROUGHNESS_EXAGGERATION = 200.0  # roughness surfaces drawn 200 times their size (10 um -> 2 mm)
SURFACE_GAP = 1.5  # mm: the rail surface's highest point this far below the patch, the wheel's lowest above
SURFACE_HALF_LENGTH = 40.0  # mm of rail and wheel surface drawn either side of the contact
SURFACE_HALF_WIDTH = 15.0  # mm of rail and wheel surface drawn either side of the line
STRIP_WIDTH = 1.0  # mm: width of the contact-length strip of the one-line models
GRID_HALF = (20.0, 15.0)  # mm: the grid under the patch, along x and across y
NO_SHADOW = {"cast_shadow": False, "receive_shadow": False}
HERTZ_COLOUR = (255, 60, 60)
AXIS_COLOUR = (40, 40, 40)
FOV = math.radians(40.0)  # vertical field of view
VIEW_HALF = (2.5, 2.0)  # scene units kept in a view either side of the patch: grid, arrows and their labels
NARROWEST_VIEW = 0.47  # width / height of the 3D view between the panels at 1280 x 800


def top_view(aspect: float = NARROWEST_VIEW) -> dict:
    """Camera from straight above, x (the rolling direction) to the right and y up on screen, as far as it
    takes to keep ``VIEW_HALF`` in a view of this width / height (scene units)."""
    tan = math.tan(FOV / 2)
    distance = max(VIEW_HALF[1] / tan, VIEW_HALF[0] / (tan * max(aspect, 0.1)))
    return {"position": (0.0, 0.0, distance), "look_at": (0.0, 0.0, 0.0), "up": (0.0, 1.0, 0.0)}


def oblique_view(aspect: float = NARROWEST_VIEW) -> dict:
    """The top view's camera tilted 55 degrees towards -y, z up."""
    distance = top_view(aspect)["position"][2]
    tilt = math.radians(55.0)
    return {
        "position": (0.0, -distance * math.sin(tilt), distance * math.cos(tilt)),
        "look_at": (0.0, 0.0, 0.0),
        "up": (0.0, 0.0, 1.0),
    }


def colour_bar_image(top_mpa: float, p0_mpa: float | None = None) -> np.ndarray:
    """The pressure colour bar, 0 .. ``top_mpa`` MPa, with the Hertz peak pressure ``p0_mpa`` marked, as an RGB
    image (matplotlib, drawn once per preload and geometry)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.2, 0.62), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.03, 0.5, 0.94, 0.3))
    ax.imshow(
        np.linspace(0, top_mpa, 256)[None, :],
        aspect="auto",
        extent=(0, top_mpa, 0, 1),
        cmap=ListedColormap(colour_table() / 255.0),
    )
    if p0_mpa is not None:
        ax.axvline(p0_mpa, color="#d62728", lw=1.5)
        ax.text(
            p0_mpa,
            1.08,
            f"p0 = {p0_mpa:.0f}",
            color="#d62728",
            fontsize=7,
            ha="center",
            va="bottom",
            transform=ax.get_xaxis_transform(),
        )
    ax.set_yticks([])
    ax.tick_params(labelsize=7, length=2, pad=1)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


def set_initial_camera(server: viser.ViserServer) -> None:
    """Every page's first camera: the top view at the explorer's field of view."""
    camera, view = server.initial_camera, top_view()
    camera.position, camera.look_at, camera.up = view["position"], view["look_at"], view["up"]
    camera.fov = FOV


class PatchScene:
    """The scene's handles and how a run state is drawn on them."""

    def __init__(self, scene: viser.SceneApi) -> None:
        """``scene``: one browser tab's 3D view (``client.scene``); its camera is set by :func:`set_initial_camera`
        and fitted by the page."""
        self._scene = scene
        self._table = colour_table()
        scene.set_up_direction("+z")
        scene.configure_default_lights(cast_shadow=False)  # shadows cost most of a frame in software WebGL
        scene.configure_environment_map(None)
        self._add_guides()
        self._patch_shape = (2, 2)
        self.heatmap = scene.add_image(
            "/contact/heatmap", np.zeros((2, 2, 3), np.uint8), 2.4, 2.4, format="png", visible=False, **NO_SHADOW
        )
        self.surface = scene.add_mesh_simple(
            "/contact/surface",
            np.zeros((4, 3), np.float32),
            grid_triangles(2, 2),
            color=(120, 160, 200),
            side="double",
            opacity=0.45,
            visible=False,
            **NO_SHADOW,
        )
        strip = np.array([[-1, -0.5, 0], [1, -0.5, 0], [1, 0.5, 0], [-1, 0.5, 0]], np.float32) * SCENE_PER_MM
        self.strip = scene.add_mesh_simple(
            "/contact/strip",
            strip,
            np.array([[0, 1, 2], [0, 2, 3]], np.uint32),
            color=(214, 39, 40),
            side="double",
            visible=False,
            **NO_SHADOW,
        )
        self.force_circle = scene.add_line_segments(
            "/contact/hertz_at_force", circle_segments(0.5, 0.02), (214, 39, 40), thickness=0.02, visible=False
        )
        self.nominal_circle = scene.add_line_segments(
            "/contact/hertz_nominal", circle_segments(0.548, 0.03), HERTZ_COLOUR, thickness=0.03
        )
        self.semi_axes = scene.add_line_segments(
            "/contact/hertz_semi_axes", np.zeros((2, 2, 3), np.float32), AXIS_COLOUR, thickness=0.015
        )
        self.a_label = scene.add_label("/contact/hertz_a", "a", position=(0.0, 0.0, 0.05), anchor="bottom-left")
        self.b_label = scene.add_label("/contact/hertz_b", "b", position=(0.0, 0.0, 0.05), anchor="bottom-left")
        self._surface_x = np.arange(-SURFACE_HALF_LENGTH, SURFACE_HALF_LENGTH + 0.5, 1.0)  # mm
        self.rail_mesh = self.wheel_lines = None
        self._across_cache = ((None, b""), None)  # ((wheel set, positions), what _wheel_across found for them)
        self.show_surfaces = False
        self.show_raised = False
        self.frames_drawn = 0
        self._last_pressure: tuple | None = None  # (pressure Pa, window_x mm, window_y mm) of the step shown
        self._surface_shape: tuple[int, int] | None = None  # grid of the raised surface's vertices and faces

    def _add_guides(self) -> None:
        """Grid (1 mm cells, 5 mm sections), axes with the rolling direction, and their labels."""
        scene, s = self._scene, SCENE_PER_MM
        gx, gy = GRID_HALF
        scene.add_grid(
            "/guides/grid_mm",
            width=2 * gx * s,
            height=2 * gy * s,
            plane="xy",
            cell_size=1.0 * s,
            section_size=5.0 * s,
            cell_color=(225, 225, 225),
            section_color=(170, 170, 170),
            position=(0.0, 0.0, -0.01),
            shadow_opacity=0.0,
        )
        y_axis = -gy - 2.0
        x_axis = -gx - 2.0
        arrows = (
            np.array(
                [[[-gx, y_axis, 0.0], [gx, y_axis, 0.0]], [[x_axis, -gy, 0.0], [x_axis, gy, 0.0]]], dtype=np.float32
            )
            * s
        )
        scene.add_arrows("/guides/axes", arrows, AXIS_COLOUR, shaft_radius=0.012, head_radius=0.05, head_length=0.12)
        scene.add_label(
            "/guides/x_label",
            "x, rolling direction (grid: 1 mm, bold every 5 mm)",
            position=(-gx * s, (y_axis - 1.0) * s, 0.0),
            anchor="top-left",
        )
        scene.add_label(
            "/guides/y_label", "y, across the rail", position=(x_axis * s, (gy + 0.5) * s, 0.0), anchor="bottom-left"
        )

    def set_contact(self, contact: ContactParameters) -> None:
        """The nominal Hertz ellipse (semi-axes a, b at the preload and geometry of ``contact``), its semi-axes
        and their lengths on the patch."""
        a, b = (v * 1e3 for v in contact.hertz_semi_axes())  # mm
        s = SCENE_PER_MM
        self.nominal_circle.points = circle_segments(a * s, 0.03, radius_y=b * s)
        self.semi_axes.points = np.array(
            [[[0, 0, 0.04], [a * s, 0, 0.04]], [[0, 0, 0.04], [0, b * s, 0.04]]], dtype=np.float32
        )
        self.a_label.text, self.a_label.position = f"a = {a:.2f} mm", (a * s, 0.0, 0.05)
        self.b_label.text, self.b_label.position = f"b = {b:.2f} mm", (0.0, b * s, 0.05)

    def clear(self) -> None:
        """No run shown: take away the heat map, raised surface, strip and force ellipse."""
        self._last_pressure = None
        for handle in (self.heatmap, self.surface, self.strip, self.force_circle):
            if handle.visible:
                handle.visible = False

    def draw(self, state, view) -> None:
        """One step of a run: heat map (and raised surface) or strip and force ellipse; the surfaces if shown."""
        contact = view.config.contact()
        if state.pressure is not None:
            self._draw_pressure(np.asarray(state.pressure, dtype=np.float64), view, contact)
        else:
            self._last_pressure = None
            half = 0.5 * state.contact_length * 1e3  # mm
            self.strip.vertices = (
                np.array(
                    [
                        [-half, -STRIP_WIDTH / 2, 0.01],
                        [half, -STRIP_WIDTH / 2, 0.01],
                        [half, STRIP_WIDTH / 2, 0.01],
                        [-half, STRIP_WIDTH / 2, 0.01],
                    ]
                )
                * SCENE_PER_MM
            ).astype(np.float32)
            a, b = contact.hertz_semi_axes(state.force) if state.force > 0 else (0.0, 0.0)
            self.force_circle.points = circle_segments(a * 1e3 * SCENE_PER_MM, 0.02, radius_y=b * 1e3 * SCENE_PER_MM)
            self._visible(strip=True)
        if self.show_surfaces:
            self.draw_surfaces(view.roughness, state.position, view.config.line, contact, view.wheel_roughness)
        self.frames_drawn += 1

    def _draw_pressure(self, pressure: np.ndarray, view, contact: ContactParameters) -> None:
        ny, nx = pressure.shape
        wx, wy = np.asarray(view.window_x) * 1e3, np.asarray(view.window_y) * 1e3  # mm
        colours = table_colours(pressure, PRESSURE_TOP * contact.hertz_peak_pressure(), self._table)
        self.heatmap.image = np.ascontiguousarray(colours[::-1])  # image rows run top (+y) to bottom
        if self._patch_shape != (ny, nx):
            dx, dy = (wx[-1] - wx[0]) / max(nx - 1, 1), (wy[-1] - wy[0]) / max(ny - 1, 1)
            self.heatmap.render_width = (wx[-1] - wx[0] + dx) * SCENE_PER_MM
            self.heatmap.render_height = (wy[-1] - wy[0] + dy) * SCENE_PER_MM
            self.heatmap.position = (0.5 * (wx[0] + wx[-1]) * SCENE_PER_MM, 0.5 * (wy[0] + wy[-1]) * SCENE_PER_MM, 0)
            self._patch_shape = (ny, nx)
        self._last_pressure = (pressure, wx, wy)
        if self.show_raised:
            self._raise()
        self._visible(strip=False)

    def _raise(self) -> None:
        """The raised surface's vertices (and, for a new window, its faces) from the step shown: vertices first,
        so that no face ever points past them."""
        pressure, wx, wy = self._last_pressure
        x, y = np.meshgrid(wx, wy)
        z = pressure / 1e9 * PRESSURE_HEIGHT
        self.surface.vertices = (np.stack([x, y, z], axis=-1).reshape(-1, 3) * SCENE_PER_MM).astype(np.float32)
        if self._surface_shape != pressure.shape:
            self.surface.faces = grid_triangles(*pressure.shape)
            self._surface_shape = pressure.shape

    def set_raised(self, on: bool) -> None:
        """Show or hide the raised pressure surface; shown, it is drawn from the step shown before it appears."""
        self.show_raised = bool(on)
        wanted = self.show_raised and self._last_pressure is not None and self.heatmap.visible
        if wanted:
            self._raise()
        if self.surface.visible != wanted:
            self.surface.visible = wanted

    def _visible(self, *, strip: bool) -> None:
        """Switch between the 3d patch and the one-line strip, sending only a change."""
        wanted = (
            (self.strip, strip),
            (self.force_circle, strip),
            (self.heatmap, not strip),
            (self.surface, not strip and self.show_raised),
        )
        for handle, visible in wanted:
            if handle.visible != visible:
                handle.visible = visible

    def draw_surfaces(
        self, rough, position: float | None, line: int, contact: ContactParameters | None = None, wheel=None
    ) -> None:
        """Rail and wheel surfaces of ``rough`` (and of the wheel set ``wheel`` added to it, if any) around
        ``position`` (m; None: the start of the data), curved as ``contact``'s geometry (default: the paper's).
        The rail is a mesh whose highest point lies ``SURFACE_GAP`` below the patch, the wheel its lines
        along the rail whose lowest point lies as far above: neither hides the patch."""
        if not self.show_surfaces:
            for handle in (self.rail_mesh, self.wheel_lines):
                if handle is not None and handle.visible:
                    handle.visible = False
            return
        if position is None:
            position = 0.0 if rough.periodic else 0.05
        contact = ContactParameters() if contact is None else contact
        rail, wheel = self._surface_vertices(rough, position, line, contact, wheel)
        n_rows = rail.shape[0] // self._surface_x.size
        lines = wheel.reshape(n_rows, self._surface_x.size, 3)
        segments = np.stack([lines[:, :-1], lines[:, 1:]], axis=2).reshape(-1, 2, 3)
        if self.rail_mesh is not None and rail.shape == self.rail_mesh.vertices.shape:
            self.rail_mesh.vertices, self.wheel_lines.points = rail, segments
            self.rail_mesh.visible = self.wheel_lines.visible = True
            return
        faces = grid_triangles(n_rows, self._surface_x.size)
        for handle in (self.rail_mesh, self.wheel_lines):
            if handle is not None:
                handle.remove()
        self.rail_mesh = self._scene.add_mesh_simple(
            "/rail/surface", rail, faces, color=(150, 150, 160), side="double", opacity=0.6, **NO_SHADOW
        )
        self.wheel_lines = self._scene.add_line_segments("/wheel/surface", segments, (150, 100, 50), thickness=0.01)

    def _surface_vertices(
        self, rough, position: float, line: int, contact: ContactParameters, wheel_set=None
    ) -> tuple[np.ndarray, np.ndarray]:
        ylat = (rough.y - float(rough.y[rough.row_of_line(line)])) * 1e3  # mm, relative to the chosen line
        rows = np.nonzero(np.abs(ylat) <= SURFACE_HALF_WIDTH)[0]
        x, y = np.meshgrid(self._surface_x, ylat[rows])
        heights = self._heights(rough, rows, position)
        wheel_heights = 0.0
        if wheel_set is not None:  # combined roughness: the wheel set at the rail rows' positions (as core pairs
            # them: interpolated across; 0 where the wheel set has no data)
            covered, across = self._wheel_across(wheel_set, rough.y[rows])
            wheel_heights = np.zeros_like(heights)
            if across is not None:
                wheel_heights[covered] = self._heights(across, np.arange(across.n_lines), position)
        crown_mm = contact.crown_radius * 1e3
        tread_mm = contact.wheel_transverse_radius * 1e3
        # the rail head curves across (y, its crown radius), the wheel along (x, its rolling radius) and across
        # (its tread radius: flat for a cylindrical tread, hollow for a concave one)
        rail_z = -(y**2) / (2 * crown_mm) + (heights if rough.kind == "rail" else 0.0)
        wheel_z = (
            x**2 / (2 * contact.radius_along * 1e3)
            + y**2 / (2 * tread_mm)
            + (heights if rough.kind == "wheel" else wheel_heights)
        )
        rail_z = rail_z - rail_z.max() - SURFACE_GAP  # wholly below the patch's plane
        wheel_z = wheel_z - np.min(wheel_z) + SURFACE_GAP  # wholly above it
        rail = np.stack([x, y, rail_z], axis=-1).reshape(-1, 3) * SCENE_PER_MM
        wheel = np.stack([x, y, wheel_z], axis=-1).reshape(-1, 3) * SCENE_PER_MM
        return rail.astype(np.float32), wheel.astype(np.float32)

    def _wheel_across(self, wheel_set, y: np.ndarray):
        """(rows of ``y`` the wheel set covers, the wheel set at those positions or None), kept for the next frame."""
        (held, positions), found = self._across_cache
        if held is not wheel_set or positions != y.tobytes():
            covered = np.array([covers(wheel_set, v, v) for v in y])
            found = (covered, at_lateral_positions(wheel_set, y[covered]) if covered.any() else None)
            self._across_cache = ((wheel_set, y.tobytes()), found)
        return found

    def _heights(self, rough, rows, position: float) -> np.ndarray:
        """Heights of ``rows`` of ``rough`` around ``position``, mm as drawn (exaggerated)."""
        idx = np.rint((position + self._surface_x * 1e-3) / rough.dx).astype(np.int64)
        idx = idx % rough.n_samples if rough.periodic else np.clip(idx, 0, rough.n_samples - 1)
        return rough.heights[rows][:, idx] * 1e3 * ROUGHNESS_EXAGGERATION
