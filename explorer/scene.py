"""The explorer's 3D view: the contact patch as a pressure heat map with the Hertz ellipse on top.

Scale: 1 scene unit = 10 mm (``SCENE_PER_MM``); +z up, x along the rail, y across. The camera looks down at
the patch. For ``3d`` (a model with a pressure map) the window's pressure is a heat map (viridis, 0 to 1.5
times the Hertz peak pressure p0 at the preload, the colour bar of :func:`colour_bar_image`) and, when
switched on, the same pressure as a raised surface; for the one-line models the contact length is a strip
and the Hertz ellipse at the current force is drawn. The nominal Hertz ellipse at the preload lies on top
(semi-axes a along and b across from ``ContactParameters.hertz_semi_axes``: a circle in the paper's case).
Rail and wheel surfaces with their roughness (exaggerated) and curvatures are off unless switched on.
Handles are created once and updated in place; nothing is sent that did not change.
"""

from __future__ import annotations

import numpy as np
import viser

from wheelrail.core.drawing import circle_segments, colour_table, grid_triangles, table_colours
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.roughness import at_lateral_positions, covers

__all__ = ["PRESSURE_TOP", "SCENE_PER_MM", "PatchScene", "colour_bar_image"]

SCENE_PER_MM = 0.1
PRESSURE_TOP = 1.5  # colour scale top, times the Hertz peak pressure p0 at the preload
PRESSURE_HEIGHT = 3.0  # mm of raised surface per GPa
ROUGHNESS_EXAGGERATION = 200.0  # roughness surfaces drawn 200 times their size (10 um -> 2 mm)
SURFACE_GAP = 1.5  # mm: rail and wheel surfaces drawn this far below/above the patch
SURFACE_HALF_LENGTH = 40.0  # mm of rail and wheel surface drawn either side of the contact
STRIP_WIDTH = 1.0  # mm: width of the contact-length strip of the one-line models
NO_SHADOW = {"cast_shadow": False, "receive_shadow": False}
HERTZ_COLOUR = (255, 60, 60)


def colour_bar_image(top_mpa: float) -> np.ndarray:
    """The pressure colour bar, 0 .. ``top_mpa`` MPa, as an RGB image (matplotlib, drawn once per preload)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

    fig = Figure(figsize=(3.6, 0.7), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.05, 0.55, 0.9, 0.3))
    ax.imshow(np.linspace(0, top_mpa, 256)[None, :], aspect="auto", extent=(0, top_mpa, 0, 1),
              cmap=ListedColormap(colour_table() / 255.0))
    ax.set_yticks([])
    ax.tick_params(labelsize=7, length=2)
    ax.set_xlabel("contact pressure (MPa)", fontsize=7, labelpad=1)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()


class PatchScene:
    """The scene's handles and how a run state is drawn on them."""

    def __init__(self, server: viser.ViserServer) -> None:
        scene = server.scene
        self._scene = scene
        self._table = colour_table()
        scene.set_up_direction("+z")
        server.initial_camera.position = (0.0, -2.4, 2.6)  # framed on the +-12 mm window
        server.initial_camera.look_at = (0.0, 0.0, 0.0)
        scene.configure_default_lights(cast_shadow=False)  # shadows cost most of a frame in software WebGL
        scene.configure_environment_map(None)
        self._patch_shape = (2, 2)
        self.heatmap = scene.add_image("/contact/heatmap", np.zeros((2, 2, 3), np.uint8), 2.4, 2.4, format="png",
                                       visible=False, **NO_SHADOW)
        self.surface = scene.add_mesh_simple("/contact/surface", np.zeros((4, 3), np.float32), grid_triangles(2, 2),
                                             color=(120, 160, 200), side="double", opacity=0.45, visible=False,
                                             **NO_SHADOW)
        strip = np.array([[-1, -0.5, 0], [1, -0.5, 0], [1, 0.5, 0], [-1, 0.5, 0]], np.float32) * SCENE_PER_MM
        self.strip = scene.add_mesh_simple("/contact/strip", strip, np.array([[0, 1, 2], [0, 2, 3]], np.uint32),
                                           color=(214, 39, 40), side="double", visible=False, **NO_SHADOW)
        self.force_circle = scene.add_line_segments("/contact/hertz_at_force", circle_segments(0.5, 0.02),
                                                    (214, 39, 40), thickness=0.02, visible=False)
        self.nominal_circle = scene.add_line_segments("/contact/hertz_nominal", circle_segments(0.548, 0.03),
                                                      HERTZ_COLOUR, thickness=0.03)
        self._surface_x = np.arange(-SURFACE_HALF_LENGTH, SURFACE_HALF_LENGTH + 0.5, 1.0)  # mm
        self.rail_mesh = self.wheel_mesh = None
        self._across_cache = ((None, b""), None)  # ((wheel set, positions), what _wheel_across found for them)
        self.show_surfaces = False
        self.show_raised = False
        self.frames_drawn = 0

    def set_contact(self, contact: ContactParameters) -> None:
        """The nominal Hertz ellipse (semi-axes a, b at the preload and geometry of ``contact``) on the patch."""
        a, b = contact.hertz_semi_axes()
        self.nominal_circle.points = circle_segments(a * 1e3 * SCENE_PER_MM, 0.03,
                                                     radius_y=b * 1e3 * SCENE_PER_MM)

    def draw(self, state, view) -> None:
        """One step of a run: heat map (and raised surface) or strip and force ellipse; the surfaces if shown."""
        contact = view.config.contact()
        if state.pressure is not None:
            self._draw_pressure(np.asarray(state.pressure, dtype=np.float64), view, contact)
        else:
            half = 0.5 * state.contact_length * 1e3  # mm
            self.strip.vertices = (np.array(
                [[-half, -STRIP_WIDTH / 2, 0.01], [half, -STRIP_WIDTH / 2, 0.01],
                 [half, STRIP_WIDTH / 2, 0.01], [-half, STRIP_WIDTH / 2, 0.01]]) * SCENE_PER_MM).astype(np.float32)
            a, b = contact.hertz_semi_axes(state.force) if state.force > 0 else (0.0, 0.0)
            self.force_circle.points = circle_segments(a * 1e3 * SCENE_PER_MM, 0.02,
                                                       radius_y=b * 1e3 * SCENE_PER_MM)
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
            self.surface.faces = grid_triangles(ny, nx)
            self._patch_shape = (ny, nx)
        if self.show_raised:
            x, y = np.meshgrid(wx, wy)
            z = pressure / 1e9 * PRESSURE_HEIGHT
            self.surface.vertices = (np.stack([x, y, z], axis=-1).reshape(-1, 3) * SCENE_PER_MM).astype(np.float32)
        self._visible(strip=False)

    def _visible(self, *, strip: bool) -> None:
        """Switch between the 3d patch and the one-line strip, sending only a change."""
        wanted = ((self.strip, strip), (self.force_circle, strip), (self.heatmap, not strip),
                  (self.surface, not strip and self.show_raised))
        for handle, visible in wanted:
            if handle.visible != visible:
                handle.visible = visible

    def draw_surfaces(self, rough, position: float | None, line: int, contact: ContactParameters | None = None,
                      wheel=None) -> None:
        """Rail and wheel surfaces of ``rough`` (and of the wheel set ``wheel`` added to it, if any) around
        ``position`` (None: the start of the data), curved as ``contact``'s geometry (default: the paper's)."""
        if not self.show_surfaces:
            for handle in (self.rail_mesh, self.wheel_mesh):
                if handle is not None and handle.visible:
                    handle.visible = False
            return
        if position is None:
            position = 0.0 if rough.periodic else 0.05
        contact = ContactParameters() if contact is None else contact
        rail, wheel = self._surface_vertices(rough, position, line, contact, wheel)
        if self.rail_mesh is not None and rail.shape == self.rail_mesh.vertices.shape:
            self.rail_mesh.vertices, self.wheel_mesh.vertices = rail, wheel
            self.rail_mesh.visible = self.wheel_mesh.visible = True
            return
        faces = grid_triangles(rail.shape[0] // self._surface_x.size, self._surface_x.size)
        for handle in (self.rail_mesh, self.wheel_mesh):
            if handle is not None:
                handle.remove()
        self.rail_mesh = self._scene.add_mesh_simple("/rail/surface", rail, faces, color=(150, 150, 160),
                                                     side="double", opacity=0.6, **NO_SHADOW)
        self.wheel_mesh = self._scene.add_mesh_simple("/wheel/surface", wheel, faces, color=(120, 90, 60),
                                                      side="double", opacity=0.3, **NO_SHADOW)

    def _surface_vertices(self, rough, position: float, line: int, contact: ContactParameters,
                          wheel_set=None) -> tuple[np.ndarray, np.ndarray]:
        ylat = (rough.y - float(rough.y[rough.row_of_line(line)])) * 1e3  # mm, relative to the chosen line
        rows = np.nonzero(np.abs(ylat) <= 15.0)[0]
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
        rail_z = -SURFACE_GAP - y**2 / (2 * crown_mm) + (heights if rough.kind == "rail" else 0.0)
        wheel_z = (SURFACE_GAP + x**2 / (2 * contact.radius_along * 1e3) + y**2 / (2 * tread_mm)
                   + (heights if rough.kind == "wheel" else wheel_heights))
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
