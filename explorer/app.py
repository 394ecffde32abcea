"""The wheelrail explorer: a viser browser GUI over ``wheelrail.core`` (SPEC.md §5, §6, §7).

The script reads top to bottom like a viser example: :class:`ExplorerApp` creates the server, declares the
controls in folders, attaches small callbacks that call into ``wheelrail.core`` and draws what comes back.
It never computes physics or spectra itself: runs come from :func:`wheelrail.core.interaction.prepare_run`,
spectra from :func:`wheelrail.core.spectra.force_spectrum` and the roughness analyses of
:mod:`wheelrail.core.roughness`, contact filters (model minus ``hertz``, SPEC.md §4) from
:func:`wheelrail.core.spectra.contact_filter`; the only arithmetic here is unit conversion and display scaling.

Threads: a run goes in a background thread (one at a time; a new run cancels the old one through
:meth:`InteractionRun.cancel` and a generation counter keeps a superseded run from drawing). The GUI and the
scene are the server's, so every browser tab sees the same state. Scene handles are created once and
updated in place (``handle.vertices = ...``), at most ``1 / DRAW_INTERVAL`` frames per second.
"""

from __future__ import annotations

import csv
import io
import math
import re
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import viser

from wheelrail.core.drawing import circle_segments, colour_table, grid_triangles, table_colours
from wheelrail.core.errors import WheelrailError
from wheelrail.core.interaction import prepare_run
from wheelrail.core.models import MODELS, REFERENCE_MODEL, model_entry
from wheelrail.core.parameters import (
    KMH,
    MAX_SPEED_KMH,
    MIN_SPEED_KMH,
    ContactParameters,
    ModelParameters,
    RunParameters,
)
from wheelrail.core.roughness import (
    RoughnessSet,
    bundled_names,
    lateral_coherence,
    load_roughness,
    read_roughness,
    roughness_spectrum,
)
from wheelrail.core.spectra import contact_filter, force_spectrum

__all__ = ["ExplorerApp", "RunConfig", "serve"]

COMPARE = "compare"
# the reference first (every contact filter needs it), then the others from the cheapest to the costliest
COMPARE_ORDER = (REFERENCE_MODEL, *(m for m in reversed(MODELS) if m != REFERENCE_MODEL))
MODEL_CHOICES = (*MODELS, COMPARE)
DRAW_INTERVAL = 0.05  # s between live 3D frames (<= 20 fps)
PLOT_INTERVAL = 0.25  # s between live plot updates
MAX_UPLOAD_BYTES = 20 * 1024 * 1024  # largest roughness file accepted from a browser
UPLOAD_SUFFIXES = (".csv", ".npz")
DEFAULT_SET = "corrugated-rail"
DEFAULT_LENGTH = 3.0  # m

# Display scales (the scene is in centimetres: 1 unit = 10 mm)
SCENE_PER_MM = 0.1
PRESSURE_HEIGHT = 3.0  # mm of patch height per GPa
ROUGHNESS_EXAGGERATION = 200.0  # roughness drawn 200 times its size (10 um -> 2 mm)
SURFACE_GAP = 1.5  # mm: rail and wheel surfaces drawn this far below/above the patch (exploded view)
SURFACE_HALF_LENGTH = 40.0  # mm of rail and wheel surface drawn either side of the contact
STRIP_WIDTH = 1.0  # mm: width of the contact-length strip of the one-line models
NO_SHADOW = {"cast_shadow": False, "receive_shadow": False}
MODEL_COLOURS = {
    "3d": "#d62728", "2d": "#1f77b4", "hertz": "#2ca02c", "hertz-winkler": "#9467bd", "hertz-average": "#ff7f0e",
}


@dataclass(frozen=True)
class RunConfig:
    """What one press of Run asks for (SI inside; the GUI fields are km/h, kN and m)."""

    model: str
    set_label: str
    line: int
    speed: float  # m/s
    preload: float  # N
    length: float  # m

    def key(self) -> tuple:
        """Everything but the model: runs with the same key can be compared (spectra, contact filters)."""
        return (self.set_label, self.line, self.speed, self.preload, self.length)

    def as_dict(self) -> dict:
        return {"model": self.model, "set": self.set_label, "line": self.line, "speed_kmh": self.speed / KMH,
                "preload_kn": self.preload / 1e3, "length_m": self.length}


def _finite_bands(centres: np.ndarray, columns: list[np.ndarray]) -> tuple[np.ndarray, ...]:
    """Keep the bands where every column is finite (uPlot draws numbers only)."""
    keep = np.ones(centres.shape, dtype=bool)
    for column in columns:
        keep &= np.isfinite(column)
    return (centres[keep], *(column[keep] for column in columns))


def _size(n_bytes: int) -> str:
    """A file size for people: kB below 1 MB, else MB (binary units)."""
    return f"{n_bytes / 1024:.0f} kB" if n_bytes < 2**20 else f"{n_bytes / 2**20:.3g} MB"


def _safe_label(name: str) -> str:
    """A file name from a browser, reduced to a harmless display label (never used as a path)."""
    base = re.split(r"[\\/]", str(name))[-1]
    return re.sub(r"[^A-Za-z0-9._ -]", "_", base)[:60] or "upload"


class ExplorerApp:
    """The explorer around one :class:`viser.ViserServer` (create it, open the page, press Run).

    State for tests and scripts: :attr:`config` (the last run's :class:`RunConfig`), :attr:`last_result`,
    :attr:`results` (model -> RunResult of the current comparison), :attr:`frames_drawn` (3D frames drawn
    for the current run), :attr:`time_to_first_frame` (s from pressing Run), :attr:`last_error`,
    :attr:`running`, :attr:`progress` (0..1), :attr:`status`.
    """

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        *,
        roughness: str = DEFAULT_SET,
        length: float = DEFAULT_LENGTH,
        max_upload_bytes: int = MAX_UPLOAD_BYTES,
        verbose: bool = False,
    ) -> None:
        self.server = viser.ViserServer(host=host, port=port, label="wheelrail explorer", verbose=verbose)
        self.host = host
        self.port = self.server.get_port()
        self.max_upload_bytes = int(max_upload_bytes)
        self._lock = threading.RLock()
        self._generation = 0
        self._stop_generation = -1
        self._worker: threading.Thread | None = None
        self._run = None
        self._pressed_at = 0.0
        self._colours = colour_table()
        self._uploads: dict[str, RoughnessSet] = {}
        self._sets: dict[str, RoughnessSet] = {}

        self.roughness: RoughnessSet | None = None
        self.roughness_label = ""
        self.config: RunConfig | None = None
        self.last_result = None
        self.last_roughness: RoughnessSet | None = None
        self.results: dict[str, object] = {}
        self.spectra: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self._results_key: tuple | None = None
        self.frames_drawn = 0
        self.time_to_first_frame: float | None = None
        self.last_error: str | None = None
        self.running = False
        self.progress = 0.0
        self.status = ""
        self.last_download: tuple[str, int] | None = None
        self.runs_finished = 0

        try:
            self._build_gui(roughness, length)
            self._build_scene()
            self._refuse_large_uploads_early()
            self.select_set(roughness)
        except BaseException:
            self.server.stop()
            raise
        self._set_status("Ready: choose a set, a line and a model, then press **Run**.")

    # ----------------------------------------------------------------------------------------------
    # Controls
    # ----------------------------------------------------------------------------------------------
    def _build_gui(self, roughness: str, length: float) -> None:
        gui = self.server.gui
        gui.configure_theme(control_width="large", show_share_button=False)
        gui.add_markdown("**wheelrail explorer**: vertical wheel/rail interaction (Pieringer, Kropp & "
                         "Thompson, Wear 2011).")
        self.status_md = gui.add_markdown("")

        with gui.add_folder("Roughness"):
            names = bundled_names()
            self.set_dropdown = gui.add_dropdown("Set", names, initial_value=roughness if roughness in names
                                                 else names[0])
            self.upload_button = gui.add_upload_button(
                f"Upload CSV/NPZ (<= {_size(self.max_upload_bytes)})", icon=viser.Icon.UPLOAD,
                hint="A roughness file in the CSV or NPZ format of the README; read in memory, never from a path.")
            self.line_slider = gui.add_slider("Line", min=-1, max=1, step=1, initial_value=0)
            self.line_map = gui.add_image(np.full((10, 10, 3), 255, dtype=np.uint8),
                                          label="Lines across the running surface", format="png")
            self.roughness_md = gui.add_markdown("")

        with gui.add_folder("Run"):
            self.model_dropdown = gui.add_dropdown("Contact model", MODEL_CHOICES, initial_value="3d",
                                                   hint="compare: hertz, hertz-average, hertz-winkler, 2d "
                                                        "and 3d one after another")
            self.speed_number = gui.add_number("Speed (km/h)", 100.0, min=MIN_SPEED_KMH, max=MAX_SPEED_KMH,
                                                step=1.0)
            self.preload_number = gui.add_number("Preload (kN)", 65.0, min=0.0, max=500.0, step=1.0)
            self.length_number = gui.add_number("Run length (m)", float(length), min=0.0, max=100.0, step=0.1)
            self.run_button = gui.add_button("Run", icon=viser.Icon.PLAYER_PLAY, color="green")
            self.stop_button = gui.add_button("Stop", icon=viser.Icon.PLAYER_STOP, color="red", disabled=True)
            self.progress_bar = gui.add_progress_bar(0.0, animated=False)

        with gui.add_folder("Replay and save"):
            self.time_slider = gui.add_slider("Step", min=0, max=1, step=1, initial_value=0, disabled=True)
            self.readout_md = gui.add_markdown("")
            self.rrd_button = gui.add_button("Download run (.rrd)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.csv_button = gui.add_button("Download spectra (.csv)", icon=viser.Icon.DOWNLOAD, disabled=True)

        self.plot_folder = gui.add_folder("Plots")
        self._plots: dict[str, viser.GuiUplotHandle] = {}
        self._plot_series: dict[str, tuple] = {}
        self._plot_order: dict[str, float] = {}
        with self.plot_folder:
            gui.add_markdown(
                f"3D view (1 unit = 10 mm): contact patch raised {PRESSURE_HEIGHT:g} mm per GPa and coloured by "
                f"pressure; rail and wheel surfaces {SURFACE_GAP:g} mm below/above it, roughness drawn "
                f"x{ROUGHNESS_EXAGGERATION:g}; yellow: nominal Hertz circle at the preload.")
        empty = (np.zeros(0), np.zeros(0))
        self._plot("force", empty, ("position (m)", "force (kN)"), title="Contact force")
        self._plot("displacement", (np.zeros(0),) * 3, ("position (m)", "wheel (um)", "rail (um)"),
                   title="Wheel and rail displacement (downwards)", ylabel="displacement (um)")
        self._plot("spectra", empty, ("band (Hz)", "no run yet"), title="Force spectra, dB re 1 N", log_x=True)
        self._plot("filters", empty, ("band (Hz)", "run hertz too (or compare)"),
                   title="Contact filter: model - hertz, dB",
                   log_x=True)
        self._plot("roughness", empty, ("band (Hz)", "roughness"), title="Roughness spectrum, dB re 1 um",
                   log_x=True)
        self._plot("coherence", empty, ("band (Hz)", "coherence"), title="Lateral coherence (eqs. 15-18)",
                   log_x=True)

        self.set_dropdown.on_update(lambda event: self._guarded(self.select_set, self.set_dropdown.value,
                                                                client_for_error=event.client))
        self.line_slider.on_update(lambda event: self._guarded(self._update_line_map))
        self.speed_number.on_update(lambda event: self._guarded(self._update_roughness_plots))
        self.preload_number.on_update(lambda event: self._guarded(self._on_preload))
        self.upload_button.on_upload(self._on_upload)
        self.run_button.on_click(lambda event: self.start_run(client=event.client))
        self.stop_button.on_click(lambda event: self.stop())
        self.time_slider.on_update(lambda event: self._guarded(self.scrub, self.time_slider.value))
        self.rrd_button.on_click(lambda event: self._guarded(self.download_rrd, client=event.client,
                                                             client_for_error=event.client))
        self.csv_button.on_click(lambda event: self._guarded(self.download_spectra_csv, client=event.client,
                                                             client_for_error=event.client))

    def _plot(self, key: str, data: tuple, labels: tuple, *, title: str | None = None, log_x: bool = False,
              colours: tuple | None = None, ylabel: str | None = None) -> None:
        """Create or update the uPlot chart ``key``; a new set of series re-creates it in place."""
        with self._lock:  # the run's thread and the callbacks both plot
            self._plot_locked(key, data, labels, title=title, log_x=log_x, colours=colours, ylabel=ylabel)

    def _plot_locked(self, key, data, labels, *, title, log_x, colours, ylabel) -> None:
        handle = self._plots.get(key)
        if handle is not None and self._plot_series.get(key) == labels:
            handle.data = tuple(np.asarray(d, dtype=np.float64) for d in data)
            return
        colours = colours or ("#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")
        series = [{"label": labels[0]}]
        series += [{"label": label, "stroke": colours[i % len(colours)], "width": 1.5}
                   for i, label in enumerate(labels[1:])]
        scales = {"x": {"time": False, **({"distr": 3} if log_x else {})}}
        axes = [{"label": labels[0]}, {"label": ylabel or (labels[1] if len(labels) == 2 else "")}]
        if handle is not None:
            order = self._plot_order[key]
            title = title or handle.title
            handle.remove()
        else:
            order = None
        with self.plot_folder:
            handle = self.server.gui.add_uplot(tuple(np.asarray(d, dtype=np.float64) for d in data), tuple(series),
                                               title=title, scales=scales, axes=tuple(axes), aspect=1.6,
                                               order=order)
        self._plots[key] = handle
        self._plot_series[key] = labels
        self._plot_order[key] = handle.order

    # ----------------------------------------------------------------------------------------------
    # Scene
    # ----------------------------------------------------------------------------------------------
    def _build_scene(self) -> None:
        scene = self.server.scene
        scene.set_up_direction("+z")
        self.server.initial_camera.position = (1.5, -2.1, 1.4)
        self.server.initial_camera.look_at = (0.0, 0.0, 0.0)
        # no shadows: nothing here needs them, and they cost most of a frame in software WebGL
        scene.configure_default_lights(cast_shadow=False)
        scene.configure_environment_map(None)
        s = SCENE_PER_MM
        # contact patch (3d): one mesh raised by pressure + the same vertices as coloured points
        self._patch_shape = (1, 1)
        self.patch_mesh = scene.add_mesh_simple("/contact/patch", np.zeros((3, 3), np.float32),
                                                np.array([[0, 1, 2]], np.uint32), color=(120, 160, 200),
                                                side="double", opacity=0.55, visible=False, **NO_SHADOW)
        self.patch_points = scene.add_point_cloud("/contact/pressure", np.zeros((1, 3), np.float32),
                                                  np.zeros((1, 3), np.uint8), point_size=0.9 * s,
                                                  point_shape="square", precision="float32",
                                                  point_shading="flat", visible=False)
        # one-line models: contact length as a strip, Hertz circle of the current force
        strip = np.array([[-1, -0.5, 0], [1, -0.5, 0], [1, 0.5, 0], [-1, 0.5, 0]], np.float32) * s
        self.strip_mesh = scene.add_mesh_simple("/contact/strip", strip, np.array([[0, 1, 2], [0, 2, 3]], np.uint32),
                                                color=(214, 39, 40), side="double", visible=False, **NO_SHADOW)
        self.force_circle = scene.add_line_segments("/contact/hertz_at_force", circle_segments(0.5, 0.01),
                                                    (214, 39, 40), thickness=0.02, visible=False)
        self.nominal_circle = scene.add_line_segments("/contact/hertz_nominal", circle_segments(0.548, 0.005),
                                                      (240, 200, 0), thickness=0.03)
        # rail and wheel surfaces with their roughness (exaggerated), moved with the wheel
        self._surface_x = np.arange(-SURFACE_HALF_LENGTH, SURFACE_HALF_LENGTH + 0.5, 1.0)  # mm
        self.rail_mesh = None
        self.wheel_mesh = None
        self.position_label = scene.add_label("/contact/label", "x = 0 m", position=(0.0, 0.0, -1.2))

    def _surface_heights(self, rough: RoughnessSet, rows: np.ndarray, position: float) -> np.ndarray:
        """Roughness heights (m) of ``rows`` at position + the drawn x offsets (data lookup, wrap for wheels)."""
        idx = np.rint((position + self._surface_x * 1e-3) / rough.dx).astype(np.int64)
        if rough.periodic:
            idx %= rough.n_samples
        else:
            idx = np.clip(idx, 0, rough.n_samples - 1)
        return rough.heights[rows][:, idx]

    def _surface_vertices(self, rough: RoughnessSet, position: float, line: int) -> tuple[np.ndarray, np.ndarray]:
        y_line = float(rough.y[rough.row_of_line(line)])
        ylat = (rough.y - y_line) * 1e3  # mm, relative to the chosen line
        rows = np.nonzero(np.abs(ylat) <= 15.0)[0]
        x, y = np.meshgrid(self._surface_x, ylat[rows])
        radius_mm = ContactParameters().radius * 1e3
        heights = self._surface_heights(rough, rows, position) * 1e3 * ROUGHNESS_EXAGGERATION  # mm drawn
        # crossed cylinders: the rail head curves across (y), the wheel along (x); both radius R (SPEC §2)
        rail_z = -SURFACE_GAP - y**2 / (2 * radius_mm) + (heights if rough.kind == "rail" else 0.0)
        wheel_z = SURFACE_GAP + x**2 / (2 * radius_mm) + (heights if rough.kind == "wheel" else 0.0)
        rail = np.stack([x, y, rail_z], axis=-1).reshape(-1, 3) * SCENE_PER_MM
        wheel = np.stack([x, y, wheel_z], axis=-1).reshape(-1, 3) * SCENE_PER_MM
        return rail.astype(np.float32), wheel.astype(np.float32)

    def _draw_surfaces(self, rough: RoughnessSet, position: float | None, line: int) -> None:
        """Rail and wheel surfaces of ``rough`` around ``position`` (None: the start of the data).

        Updated in place; re-created only when the number of lines drawn changes (another set or line).
        """
        if position is None:
            position = 0.0 if rough.periodic else 0.05
        rail, wheel = self._surface_vertices(rough, position, line)
        with self._lock:  # the run's thread and the callbacks both draw
            if self.rail_mesh is not None and rail.shape == self.rail_mesh.vertices.shape:
                self.rail_mesh.vertices = rail
                self.wheel_mesh.vertices = wheel
                return
            faces = grid_triangles(rail.shape[0] // self._surface_x.size, self._surface_x.size)
            for handle in (self.rail_mesh, self.wheel_mesh):
                if handle is not None:
                    handle.remove()
            scene = self.server.scene
            self.rail_mesh = scene.add_mesh_simple("/rail/surface", rail, faces, color=(150, 150, 160),
                                                   side="double", **NO_SHADOW)
            self.wheel_mesh = scene.add_mesh_simple("/wheel/surface", wheel, faces, color=(120, 90, 60),
                                                    side="double", opacity=0.35, **NO_SHADOW)

    def draw_state(self, state, result_like) -> None:
        """Draw one step: the patch (3d) or strip and Hertz circle (one-line models) and the surfaces.

        ``result_like`` carries ``model``, ``line``, ``window_x``/``window_y`` (3d) and the run's parameters.
        """
        s = SCENE_PER_MM
        contact = self._contact_parameters(result_like.preload)
        if state.pressure is not None:
            pressure = np.asarray(state.pressure, dtype=np.float64)
            ny, nx = pressure.shape
            x, y = np.meshgrid(np.asarray(result_like.window_x) * 1e3, np.asarray(result_like.window_y) * 1e3)
            z = pressure / 1e9 * PRESSURE_HEIGHT
            vertices = (np.stack([x, y, z], axis=-1).reshape(-1, 3) * s).astype(np.float32)
            top = 1.5 * contact.hertz_peak_pressure()
            colours = table_colours(pressure, top, self._colours).reshape(-1, 3)
            # elements out of contact: their points are stacked on the peak's point (a fixed point count keeps
            # the handle's arrays in step), so only the contact shows as coloured squares on the raised mesh
            points = vertices + np.float32([0, 0, 0.002])
            flat = pressure.reshape(-1)
            outside = flat <= 0
            peak = int(np.argmax(flat))
            points[outside] = points[peak]
            colours[outside] = colours[peak]
            if self._patch_shape != (ny, nx):
                self.patch_mesh.faces = grid_triangles(ny, nx)
                self._patch_shape = (ny, nx)
            self.patch_mesh.vertices = vertices
            self.patch_points.points = points
            self.patch_points.colors = colours
            self.patch_mesh.visible = self.patch_points.visible = True
            self.strip_mesh.visible = self.force_circle.visible = False
        else:
            half = 0.5 * state.contact_length * 1e3  # mm
            height = PRESSURE_HEIGHT * max(state.force, 0.0) / contact.preload * 0.5
            self.strip_mesh.vertices = (np.array(
                [[-half, -STRIP_WIDTH / 2, height], [half, -STRIP_WIDTH / 2, height],
                 [half, STRIP_WIDTH / 2, height], [-half, STRIP_WIDTH / 2, height]]) * s).astype(np.float32)
            radius = contact.hertz_radius(max(state.force, 0.0)) * 1e3 if state.force > 0 else 0.0
            self.force_circle.points = circle_segments(radius * s, 0.01)
            self.strip_mesh.visible = self.force_circle.visible = True
            self.patch_mesh.visible = self.patch_points.visible = False
        self._draw_surfaces(result_like.roughness, state.position, result_like.line)
        self.position_label.text = (f"{result_like.model}: x = {state.position:.3f} m, "
                                    f"F = {state.force / 1e3:.1f} kN")
        with self._lock:
            self.frames_drawn += 1
            if self.time_to_first_frame is None and self._pressed_at:
                self.time_to_first_frame = time.perf_counter() - self._pressed_at

    # ----------------------------------------------------------------------------------------------
    # Roughness set and line
    # ----------------------------------------------------------------------------------------------
    def select_set(self, name: str) -> None:
        """Make ``name`` (a bundled set or an uploaded file's label) the current roughness set."""
        if name in self._uploads:
            rough = self._uploads[name]
        elif name in bundled_names():  # only names: a value sent by a browser is never opened as a path
            if name not in self._sets:
                self._sets[name] = load_roughness(name)
            rough = self._sets[name]
        else:
            raise WheelrailError(f"unknown roughness set {name!r}; choose a bundled set or upload a file")
        self.roughness = rough
        self.roughness_label = name
        if self.set_dropdown.value != name:
            self.set_dropdown.value = name  # re-enters here once with the same name: harmless
            return
        numbers = rough.line_numbers
        lo, hi = int(numbers[0]), int(numbers[-1])
        if lo == hi:  # a one-line set: an inert slider
            lo, hi = lo - 1, hi + 1
        self.line_slider.min, self.line_slider.max = lo, hi
        if self.line_slider.value not in numbers:
            self.line_slider.value = 0
        desc = rough.description.splitlines()[0] if rough.description else ""
        desc = desc if len(desc) <= 140 else desc[:137].rstrip() + "..."
        self.roughness_md.content = (
            f"{rough.kind}, {rough.n_lines} lines {rough.lateral_spacing * 1e3:.3g} mm apart, "
            f"{rough.length:.3g} m at {rough.dx * 1e3:.3g} mm. {desc}")
        self._draw_surfaces(rough, None, self._current_line_or_zero())
        self._update_line_map()
        self._update_roughness_plots()

    def _current_line_or_zero(self) -> int:
        line = int(self.line_slider.value)
        return line if line in self.roughness.line_numbers else 0

    def _contact_parameters(self, preload: float | None = None) -> ContactParameters:
        if preload is None:
            kn = float(self.preload_number.value)
            preload = kn * 1e3 if math.isfinite(kn) and kn > 0 else ContactParameters().preload
        return ContactParameters(preload=preload)

    def _on_preload(self) -> None:
        a = self._contact_parameters().hertz_radius()
        self.nominal_circle.points = circle_segments(a * 1e3 * SCENE_PER_MM, 0.005)
        self._update_line_map()

    def _update_line_map(self) -> None:
        """Small map of the lines across the rail with the chosen line and the nominal contact width 2a."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        rough = self.roughness
        line = self._current_line_or_zero()
        y = rough.y * 1e3
        y_line = float(y[rough.row_of_line(line)])
        a = self._contact_parameters().hertz_radius() * 1e3
        fig = Figure(figsize=(3.6, 0.95), dpi=100)
        FigureCanvasAgg(fig)
        ax = fig.add_axes((0.04, 0.42, 0.92, 0.4))
        ax.axvspan(y_line - a, y_line + a, color="#f0c800", alpha=0.35, lw=0)
        ax.vlines(y, 0, 1, color="#777777", lw=1)
        ax.vlines([y_line], 0, 1, color="#d62728", lw=2.5)
        ax.set_yticks([])
        ax.set_xlim(y[0] - 1.5, y[-1] + 1.5)
        ax.tick_params(labelsize=7, length=2)
        ax.set_xlabel(f"lateral position (mm); line {line} red, 2a = {2 * a:.1f} mm yellow", fontsize=7,
                      labelpad=1)
        canvas = fig.canvas
        canvas.draw()
        self.line_map.image = np.asarray(canvas.buffer_rgba())[..., :3].copy()

    def _update_roughness_plots(self) -> None:
        rough = self.roughness
        speed = float(self.speed_number.value) * KMH
        if not (math.isfinite(speed) and speed > 0):
            return  # reported when Run is pressed
        lines = [k for k in range(-3, 4) if k in rough.line_numbers] or [0]
        spectrum = roughness_spectrum(rough, speed=speed, lines=lines)
        centres, levels = _finite_bands(spectrum.band_centres, [spectrum.levels_db])
        self._plot("roughness", (centres, levels), ("band (Hz)", f"lines {lines[0]}..{lines[-1]}"), log_x=True,
                   ylabel="dB re 1 um")
        half = min(3, int(rough.line_numbers[-1]), -int(rough.line_numbers[0]))
        if half >= 1:
            centres, gamma2 = lateral_coherence(rough, speed, half_lines=half)
            centres, gamma2 = _finite_bands(centres, [gamma2])
            self._plot("coherence", (centres, gamma2), ("band (Hz)", f"gamma^2, M = {half}"), log_x=True,
                       ylabel="gamma^2")
        else:
            self._plot("coherence", (np.zeros(0), np.zeros(0)), ("band (Hz)", "one line only"), log_x=True)

    def _on_upload(self, event) -> None:
        uploaded = event.target.value
        self._guarded(self.load_upload, uploaded.name, uploaded.content, client=event.client,
                      client_for_error=event.client)

    def load_upload(self, name: str, content: bytes, *, client=None) -> str:
        """Read an uploaded roughness file (bytes from the browser) and select it; returns its label.

        The bytes go to a temporary file of our own naming; the browser's file name is only shown.
        """
        if len(content) > self.max_upload_bytes:
            raise WheelrailError(f"upload {_safe_label(name)!r} ({_size(len(content))}) is over the "
                                 f"{_size(self.max_upload_bytes)} limit")
        suffix = Path(str(name)).suffix.lower()
        if suffix not in UPLOAD_SUFFIXES:
            raise WheelrailError(f"upload {_safe_label(name)!r}: expected a .csv or .npz roughness file")
        with tempfile.TemporaryDirectory(prefix="wheelrail-upload-") as folder:
            path = Path(folder) / f"roughness{suffix}"
            path.write_bytes(content)
            try:
                rough = read_roughness(path)
            except WheelrailError as error:
                raise WheelrailError(f"upload {_safe_label(name)!r}: {error}".replace(str(path), "file")) from None
        label = f"upload: {_safe_label(name)}"
        with self._lock:
            self._uploads[label] = rough
            options = tuple(self.set_dropdown.options)
            if label not in options:
                self.set_dropdown.options = (*options, label)
        self.select_set(label)
        self._set_status(f"Loaded {label}: {rough.kind}, {rough.n_lines} lines, {rough.length:.3g} m.")
        self._notify("Roughness loaded", f"{label} ({rough.n_lines} lines)", client=client, error=False)
        return label

    def _refuse_large_uploads_early(self) -> None:
        """Drop an upload announced larger than the limit before its bytes are buffered.

        viser 1.1 has no public size limit; its upload state lives in ``GuiApi._current_file_upload_states``,
        and our handler runs after viser's for the same start message. If these private names change, the
        size is still checked when the upload completes (:meth:`load_upload`), after viser has buffered it.
        """
        from viser import _messages

        gui = self.server.gui
        states = getattr(gui, "_current_file_upload_states", None)
        server = getattr(self.server, "_websock_server", None)
        if states is None or server is None or not hasattr(_messages, "FileTransferStartUpload"):
            return

        def refuse(client_id, message) -> None:
            if message.size_bytes <= self.max_upload_bytes:
                return
            states.pop(message.transfer_uuid, None)  # its parts are now ignored by viser
            # tell the page the transfer is over, so that its upload button works again
            server.queue_message(_messages.FileTransferPartAck(
                source_component_uuid=message.source_component_uuid, transfer_uuid=message.transfer_uuid,
                transferred_bytes=message.size_bytes, total_bytes=message.size_bytes))
            self._report_error(
                f"upload {_safe_label(message.filename)!r} ({_size(message.size_bytes)}) is over the "
                f"{_size(self.max_upload_bytes)} limit; refused before sending",
                client=self.server.get_clients().get(client_id))

        server.register_handler(_messages.FileTransferStartUpload, refuse)

    # ----------------------------------------------------------------------------------------------
    # Runs
    # ----------------------------------------------------------------------------------------------
    def read_config(self) -> RunConfig:
        """The run the controls ask for, validated (raises WheelrailError with a one-line message)."""
        model = str(self.model_dropdown.value)
        if model not in MODEL_CHOICES:
            raise WheelrailError(f"unknown contact model {model!r}; choose one of {', '.join(MODEL_CHOICES)}")
        speed_kmh = float(self.speed_number.value)
        if not (math.isfinite(speed_kmh) and MIN_SPEED_KMH <= speed_kmh <= MAX_SPEED_KMH):
            raise WheelrailError(f"speed must be {MIN_SPEED_KMH:g}-{MAX_SPEED_KMH:g} km/h, got {speed_kmh:g} km/h")
        preload_kn = float(self.preload_number.value)
        if not (math.isfinite(preload_kn) and preload_kn > 0):
            raise WheelrailError(f"preload must be a positive load in kN, got {preload_kn:g} kN")
        length = float(self.length_number.value)
        if not (math.isfinite(length) and length > 0):
            raise WheelrailError(f"run length must be a positive length in m, got {length:g} m")
        line = self.line_slider.value
        if int(line) != line:
            raise WheelrailError(f"line must be an integer, got {line}")
        self.roughness.row_of_line(int(line))  # one-line message naming the set's lines
        return RunConfig(model=model, set_label=self.roughness_label, line=int(line), speed=speed_kmh * KMH,
                         preload=preload_kn * 1e3, length=length)

    def start_run(self, client=None) -> bool:
        """What the Run button does: read the controls, replace any running run, start in the background."""
        pressed = time.perf_counter()
        try:
            config = self.read_config()
        except WheelrailError as error:
            self._report_error(str(error), client=client)
            return False
        roughness = self.roughness
        self._cancel_current()
        with self._lock:
            self._generation += 1
            generation = self._generation
            self._pressed_at = pressed
            self.config = config
            self.frames_drawn = 0
            self.time_to_first_frame = None
            self.running = True
            self.progress = 0.0
            self.last_error = None
            if self._results_key != config.key():
                self.results, self.spectra, self._results_key = {}, {}, config.key()
            worker = threading.Thread(target=self._work, args=(generation, config, roughness, client), daemon=True,
                                      name=f"wheelrail-explorer-run-{generation}")
            self._worker = worker
        self.progress_bar.value = 0.0
        self.progress_bar.animated = True
        self.stop_button.disabled = False
        self.time_slider.disabled = True
        self._set_status(f"Preparing {config.model} on line {config.line} ...")
        worker.start()
        return True

    def stop(self) -> None:
        """What the Stop button does: cancel the current run (it keeps the steps done so far)."""
        with self._lock:
            run = self._run
            self._stop_generation = self._generation  # also stops a run still being prepared
        if run is not None:
            run.cancel()

    def _cancel_current(self) -> None:
        with self._lock:
            run, worker = self._run, self._worker
            self._generation += 1  # whatever still runs is superseded: it stops drawing
        if run is not None:
            run.cancel()
        if worker is not None and worker.is_alive() and worker is not threading.current_thread():
            worker.join(timeout=2.0)

    def wait(self, timeout: float | None = None) -> bool:
        """Wait for the current run to end; True if it did within ``timeout`` s."""
        worker = self._worker
        if worker is not None:
            worker.join(timeout)
            return not worker.is_alive()
        return True

    def _current(self, generation: int) -> bool:
        return generation == self._generation

    def _work(self, generation: int, config: RunConfig, roughness: RoughnessSet, client) -> None:
        models = COMPARE_ORDER if config.model == COMPARE else (config.model,)
        params = ModelParameters(contact=ContactParameters(preload=config.preload),
                                 run=RunParameters(speed=config.speed))
        source = config.set_label if config.set_label in bundled_names() else roughness
        try:
            for number, model in enumerate(models):
                if not self._current(generation):
                    return
                run = prepare_run(source, model=model, line=config.line, params=params, length=config.length)
                with self._lock:
                    if not self._current(generation):
                        return
                    self._run = run
                    if self._stop_generation == generation:
                        run.cancel()
                self._set_status(f"Running {model} ({number + 1}/{len(models)}), line {config.line}, "
                                 f"{config.speed / KMH:g} km/h, {config.preload / 1e3:g} kN ...")
                view = _View(model=model, line=config.line, preload=config.preload, roughness=roughness)
                if model_entry(model).traits.pressure_map:
                    view.window_x, view.window_y = run.window_x, run.window_y
                last_draw = last_plot = 0.0
                state = None
                for state in run.steps():
                    now = time.perf_counter()
                    if now - last_draw >= DRAW_INTERVAL:
                        if not self._current(generation):
                            run.cancel()
                            return
                        self.draw_state(state, view)
                        last_draw = time.perf_counter()
                    if now - last_plot >= PLOT_INTERVAL:
                        self._live_plots(run.result())
                        self._set_progress((number + (state.step + 1) / run.n_steps) / len(models))
                        last_plot = time.perf_counter()
                result = run.result()
                if not self._current(generation):
                    return
                if state is not None:
                    self.draw_state(state, view)
                self._finish_model(result, config, roughness, cancelled=run.cancelled)
                if run.cancelled:
                    self._set_status(f"Stopped {model} after {result.n_steps} of {run.n_steps} steps "
                                     f"(x = {result.x[-1] if result.n_steps else 0:.3f} m).")
                    return
            self._set_progress(1.0)
            self._set_status(f"Done: {', '.join(models)} on line {config.line}, {config.speed / KMH:g} km/h, "
                             f"{config.preload / 1e3:g} kN, {config.length:g} m. Scrub with the Step slider.")
        except WheelrailError as error:
            if self._current(generation):
                self._report_error(str(error), client=client)
        except Exception as error:  # keep serving after anything: report it in the page
            if self._current(generation):
                self._report_error(f"unexpected error: {type(error).__name__}: {error}", client=client)
        finally:
            with self._lock:
                if self._current(generation):
                    self.running = False
                    self._run = None
            if self._current(generation):
                self.progress_bar.animated = False
                self.stop_button.disabled = True

    def _finish_model(self, result, config: RunConfig, roughness: RoughnessSet, *, cancelled: bool) -> None:
        with self._lock:
            self.last_result = result
            self.last_roughness = roughness
            self.results[result.model] = result
        self._live_plots(result)
        if result.n_steps:
            self.time_slider.max = max(1, result.n_steps - 1)
            self.time_slider.value = result.n_steps - 1
            self.time_slider.disabled = False
            self.rrd_button.disabled = False
        if not cancelled:
            try:
                centres, levels = force_spectrum(result)
            except WheelrailError as error:
                self._report_error(f"{result.model}: {error}")
            else:
                with self._lock:
                    self.spectra[result.model] = (centres, levels)
                self._spectra_plots()
                self.csv_button.disabled = False
            with self._lock:
                self.runs_finished += 1

    def _live_plots(self, result) -> None:
        step = max(1, result.n_steps // 4000)  # at most ~4000 points per line on screen
        x = result.x[::step]
        self._plot("force", (x, result.force[::step] / 1e3), ("position (m)", f"{result.model} force (kN)"),
                   colours=(MODEL_COLOURS[result.model],))
        self._plot("displacement", (x, result.xi_wheel[::step] * 1e6, result.xi_rail[::step] * 1e6),
                   ("position (m)", "wheel (um)", "rail (um)"))

    def contact_filters(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Contact filter of every model run on the current configuration: its level minus hertz's, dB."""
        with self._lock:
            spectra = dict(self.spectra)
        if REFERENCE_MODEL not in spectra:
            return {}
        centres, reference = spectra[REFERENCE_MODEL]
        return {model: (centres, contact_filter(levels, reference)) for model, (c, levels) in spectra.items()
                if model != REFERENCE_MODEL and np.array_equal(c, centres)}

    def _spectra_plots(self) -> None:
        with self._lock:
            spectra = dict(self.spectra)
        models = [m for m in MODELS if m in spectra]
        if models:
            centres = spectra[models[0]][0]
            cols = [spectra[m][1] for m in models]
            self._plot("spectra", _finite_bands(centres, cols), ("band (Hz)", *models), log_x=True,
                       colours=tuple(MODEL_COLOURS[m] for m in models), ylabel="dB re 1 N")
        filters = self.contact_filters()
        if filters:
            names = [m for m in MODELS if m in filters]
            centres = filters[names[0]][0]
            self._plot("filters", _finite_bands(centres, [filters[m][1] for m in names]), ("band (Hz)", *names),
                       log_x=True, colours=tuple(MODEL_COLOURS[m] for m in names), ylabel="dB")

    def scrub(self, step: int) -> None:
        """Show step ``step`` of the finished run (the Step slider)."""
        with self._lock:
            result, running = self.last_result, self.running
        if result is None or running or result.n_steps == 0:
            return
        step = int(min(max(step, 0), result.n_steps - 1))
        state = result.state(step)
        with self._lock:
            roughness = self.last_roughness
        view = _View(model=result.model, line=result.line, preload=result.parameters["contact"]["preload"],
                     roughness=roughness, window_x=result.window_x, window_y=result.window_y)
        self.draw_state(state, view)
        self.readout_md.content = (
            f"step {step}: x = {state.position:.4f} m, t = {state.time * 1e3:.2f} ms, F = {state.force / 1e3:.2f} kN, "
            f"wheel {state.xi_wheel * 1e6:.2f} um, rail {state.xi_rail * 1e6:.2f} um, "
            f"contact length {state.contact_length * 1e3:.1f} mm")

    # ----------------------------------------------------------------------------------------------
    # Saving (downloads through the browser, never a server path)
    # ----------------------------------------------------------------------------------------------
    def download_rrd(self, client=None) -> tuple[str, bytes]:
        """The current run as a rerun recording, sent to ``client`` (or every open page)."""
        from wheelrail.core.recording import record_result

        with self._lock:
            result, roughness = self.last_result, self.last_roughness
        if result is None or result.n_steps == 0:
            raise WheelrailError("no run to save yet: press Run first")
        name = f"wheelrail-{result.model}-line{result.line}.rrd"
        with tempfile.TemporaryDirectory(prefix="wheelrail-rrd-") as folder:
            path = Path(folder) / name
            record_result(result, path, roughness=roughness, description=f"wheelrail explorer: {result.model}")
            content = path.read_bytes()
        self._send(name, content, client)
        return name, content

    def spectra_csv(self) -> str:
        """Force spectra of the models run so far and their contact filters, as CSV text."""
        with self._lock:
            spectra = dict(self.spectra)
        if not spectra:
            raise WheelrailError("no force spectrum yet: finish a run first")
        models = [m for m in MODELS if m in spectra]
        filters = self.contact_filters()
        names = [m for m in MODELS if m in filters]
        centres = spectra[models[0]][0]
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(["band_centre_hz", *(f"{m}_level_db" for m in models),
                         *(f"{m}_contact_filter_db" for m in names)])
        for i, f in enumerate(centres):
            values = [spectra[m][1][i] for m in models] + [filters[m][1][i] for m in names]
            writer.writerow([f"{f:.6g}", *("" if not np.isfinite(v) else f"{v:.3f}" for v in values)])
        return out.getvalue()

    def download_spectra_csv(self, client=None) -> tuple[str, bytes]:
        content = self.spectra_csv().encode()
        config = self.config
        name = f"wheelrail-spectra-line{config.line if config else 0}.csv"
        self._send(name, content, client)
        return name, content

    def _send(self, name: str, content: bytes, client) -> None:
        self.last_download = (name, len(content))
        if client is not None:
            client.send_file_download(name, content, save_immediately=True)
        else:
            self.server.send_file_download(name, content, save_immediately=True)

    # ----------------------------------------------------------------------------------------------
    # Messages
    # ----------------------------------------------------------------------------------------------
    def _guarded(self, function, *args, client_for_error=None, **kwargs):
        """Call a callback's work; a WheelrailError (bad input) becomes a message in the page."""
        try:
            return function(*args, **kwargs)
        except WheelrailError as error:
            self._report_error(str(error), client=client_for_error)
        except Exception as error:  # keep serving after anything
            self._report_error(f"unexpected error: {type(error).__name__}: {error}", client=client_for_error)
        return None

    def _set_status(self, text: str) -> None:
        self.status = text
        self.status_md.content = text

    def _set_progress(self, fraction: float) -> None:
        self.progress = float(min(max(fraction, 0.0), 1.0))
        self.progress_bar.value = round(100.0 * self.progress, 1)

    def _report_error(self, message: str, *, client=None) -> None:
        self.last_error = message
        self._set_status(f"**Error:** {message}")
        self._notify("wheelrail", message, client=client, error=True)

    def _notify(self, title: str, body: str, *, client=None, error: bool) -> None:
        clients = [client] if client is not None else list(self.server.get_clients().values())
        for target in clients:
            try:
                target.add_notification(title, body, color="red" if error else "green",
                                        auto_close_seconds=None if error else 4.0)
            except Exception:  # a tab that closed meanwhile
                pass

    def close(self) -> None:
        """Cancel any run and stop the server."""
        self._cancel_current()
        self.server.stop()


@dataclass
class _View:
    """What :meth:`ExplorerApp.draw_state` needs about the run a state belongs to."""

    model: str
    line: int
    preload: float
    roughness: RoughnessSet
    window_x: np.ndarray | None = None
    window_y: np.ndarray | None = None


def serve(host: str = "127.0.0.1", port: int = 8080, *, roughness: str = DEFAULT_SET,
          length: float = DEFAULT_LENGTH) -> int:
    """Start the explorer and serve until interrupted (Ctrl-C); returns the exit code."""
    app = ExplorerApp(host, port, roughness=roughness, length=length, verbose=False)
    shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
    print(f"wheelrail explorer: http://{shown}:{app.port}  (Ctrl-C to stop)", flush=True)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        pass
    finally:
        app.close()
    return 0
