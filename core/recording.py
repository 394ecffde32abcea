"""Rerun recordings of wheel/rail interaction runs: a streaming sink, whole-run export and a reader.

Why rerun: one open format (``.rrd``) that a free viewer replays with synchronised time series, images and
3D meshes on several timelines, streamable live from the loop and readable back from Python (SPEC.md §4:
"every run can stream to a rerun .rrd file or a live viewer"). Built on rerun-sdk 0.41; every call used
here was checked against that version (``send_columns`` with ``TimeColumn``, ``FileSink``/``GrpcSink`` in
``RecordingStream.set_sinks``, ``rerun.chunk.RrdReader`` to read files back).

Entity tree (mirrors the physical system; SI units, m, s, N, Pa)::

    parameters                 TextDocument (markdown + JSON): model, line, speed, time step, window, all
                               model parameters; logged at the start and again at the end (final counts)
    wheel/position             Scalars, wheel position along the rail x, m
    wheel/displacement         Scalars, xi_W, m (positive downwards)
    rail/displacement          Scalars, xi_R at the contact point, m
    roughness/under_wheel      Scalars, r under the wheel centre on the run's line, m
    roughness/equivalent       Scalars, r_eq the contact model saw (whole-run export only), m
    roughness/lines            Scalars, one series per roughness line near the run's line (heights of the
                               set sampled at the wheel position), m
    contact/force              Scalars, normal contact force F_n, N
    contact/length             Scalars, contact length in the rolling direction, m
    contact/area               Scalars, contact area, m² (absent for 2d)
    contact/pressure           DepthImage (float32, Pa, colour map 0..2 p0), 3D model only; rows = y',
                               columns = x', pixel (i, j) = element (row i, column j) of the window
    contact/pressure_surface   Mesh3D: the window raised by pressure, z = a p / p0 (the Hertz peak p0
                               rises to the Hertz radius a), coloured by pressure; x', y' in m; at every
                               ``surface_every``-th recorded map (see below)
    contact/nominal_circle     Hertz circle of radius a at the preload (5.48 mm at 65 kN), computed from the
                               contact parameters: LineStrips2D in the image's pixels and LineStrips3D in m
    spectra/force              BarChart, third-octave contact-force levels 50 Hz-8 kHz, dB re 1 N, abscissa
                               = band centre, Hz (:func:`wheelrail.core.spectra.force_spectrum`); at the end

Timelines: ``step`` (sequence, step index), ``time`` (duration, t = step dt, stored in whole ns) and
``position_um`` (sequence, wheel position x in µm). Rerun timelines are integers (sequence, nanosecond
duration or timestamp), so a position in metres cannot be a timeline; micrometres keep it exact to 1 µm
and say their unit. The exact x is the ``wheel/position`` series.

Scalars are sent as columns (``rr.send_columns``) in blocks of ``chunk_steps`` steps; pressure maps are
sent as a column of image buffers (one static ``ImageFormat``), decimated with ``record_every``. The
pressure surface is a visual aid and costs ~4x the image (rerun encodes its vertices at ~50 µs a mesh),
so it is recorded at every ``surface_every``-th recorded map only (default 4, i.e. every 4 mm at 1 mm
steps); the exact maps are the images.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
import uuid
import warnings
import weakref
from pathlib import Path

import numpy as np

from wheelrail.core.atomic import publish, temporary_beside
from wheelrail.core.errors import WheelrailError
from wheelrail.core.jsonready import json_ready
from wheelrail.core.results import RunHeader, RunResult, StepState

__all__ = [
    "APPLICATION_ID",
    "ENTITY_PATHS",
    "RecordingSink",
    "add_recording_arguments",
    "check_recording_path",
    "default_blueprint",
    "read_recording",
    "record_result",
    "sink_from_args",
]

APPLICATION_ID = "wheelrail"
DEFAULT_CHUNK_STEPS = 500  # steps buffered before one columnar send (a few ms of work per block)
DEFAULT_VIEWER_PORT = 9876  # rerun's default gRPC port
PRESSURE_RANGE_P0 = 2.0  # colour map of the pressure image spans 0 .. 2 p0 (rough contacts exceed p0)
SURFACE_EVERY = 4  # the pressure surface mesh is recorded at every 4th recorded pressure map
ROUGHNESS_LINES_SHOWN = 3  # roughness/lines shows the set's lines k-3 .. k+3 around the run's line k

SCALAR_PATHS = {
    "x": "wheel/position",
    "xi_wheel": "wheel/displacement",
    "xi_rail": "rail/displacement",
    "roughness": "roughness/under_wheel",
    "force": "contact/force",
    "contact_length": "contact/length",
    "contact_area": "contact/area",
}
ENTITY_PATHS = (
    "parameters",
    *SCALAR_PATHS.values(),
    "roughness/equivalent",
    "roughness/lines",
    "contact/pressure",
    "contact/pressure_surface",
    "contact/nominal_circle",
    "spectra/force",
)
_SERIES = {  # entity -> (legend name with unit, colour RGB)
    "wheel/position": ("wheel position x (m)", (120, 120, 120)),
    "wheel/displacement": ("wheel displacement ξ_W (m)", (31, 119, 180)),
    "rail/displacement": ("rail displacement ξ_R (m)", (214, 39, 40)),
    "roughness/under_wheel": ("roughness r under the wheel (m)", (44, 160, 44)),
    "roughness/equivalent": ("equivalent roughness r_eq (m)", (148, 103, 189)),
    "contact/force": ("contact force F (N)", (23, 23, 23)),
    "contact/length": ("contact length (m)", (255, 127, 14)),
    "contact/area": ("contact area (m²)", (140, 86, 75)),
}
# viridis at 0, 1/4, 1/2, 3/4, 1 (sRGB), enough for a readable colour ramp of the pressure surface
_VIRIDIS = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], dtype=float)


def _rr():
    """Import rerun on first use: the package stays importable (and the CLI fast) without recording."""
    import rerun

    return rerun


# --------------------------------------------------------------------------------------------------
# Paths and command-line options
# --------------------------------------------------------------------------------------------------


def check_recording_path(path: str | os.PathLike) -> Path:
    """Check, before a run starts, that a ``.rrd`` recording can be written at ``path``.

    The folder must exist and accept a new file (probed by creating and removing a temporary file, which
    also catches read-only file systems and permissions that ``os.access`` misjudges for root); the path
    must end in ``.rrd`` and must not be a folder. An existing file is replaced at the end of the run.

    Returns
    -------
    pathlib.Path
        The path, unchanged.

    Raises
    ------
    WheelrailError
        One line naming the path and the reason.
    """
    target = Path(path)
    if target.suffix.lower() != ".rrd":
        raise WheelrailError(f"recording file {str(target)!r} must end in .rrd")
    if target.is_dir():
        raise WheelrailError(f"cannot write recording {target}: it is a folder")
    folder = target.parent
    if not folder.is_dir():
        raise WheelrailError(f"cannot write recording {target}: folder {folder} does not exist")
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".wheelrail-probe-", suffix=".tmp"):
            pass
    except OSError as error:
        reason = error.strerror or type(error).__name__
        raise WheelrailError(f"cannot write recording {target}: folder {folder} is not writable ({reason})") from None
    return target


def _grpc_url(address: str) -> str:
    """``HOST:PORT`` or a ``rerun+http(s)://`` / ``rerun://`` URL -> the viewer's proxy URL."""
    address = address.strip()
    if "://" in address:
        if not address.startswith(("rerun://", "rerun+http://", "rerun+https://")):
            raise WheelrailError(
                f"--connect {address!r}: use HOST:PORT or a rerun+http://HOST:PORT/proxy URL"
            )
        return address
    host, _, port = address.rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise WheelrailError(f"--connect {address!r}: use HOST:PORT (e.g. 127.0.0.1:9876)")
    return f"rerun+http://{host}:{int(port)}/proxy"


def add_recording_arguments(parser) -> None:
    """Add ``--rrd FILE.rrd``, ``--spawn``, ``--connect ADDR`` and ``--record-every N`` to an argparse parser."""
    group = parser.add_argument_group("recording (rerun)")
    group.add_argument("--rrd", metavar="FILE.rrd", help="write a rerun recording of the run to this file")
    group.add_argument("--spawn", action="store_true", help="start a rerun viewer and stream the run to it")
    group.add_argument(
        "--connect", metavar="ADDR", help="stream the run to a running rerun viewer at HOST:PORT or a rerun+http URL"
    )
    group.add_argument(
        "--record-every",
        type=int,
        default=1,
        metavar="N",
        help="record the 3D pressure map every N-th step (default 1: every step; scalars are always every step)",
    )


def sink_from_args(args, *, description: str = "") -> RecordingSink | None:
    """The recording sink the parsed options ask for, or None when no recording option was given.

    Call it before the run: a bad ``--rrd`` path, ``--connect`` address or ``--record-every`` raises a
    :class:`WheelrailError` at once, so no run is wasted. ``description`` becomes the recording's name.
    """
    rrd = getattr(args, "rrd", None)
    spawn = bool(getattr(args, "spawn", False))
    connect = getattr(args, "connect", None)
    record_every = getattr(args, "record_every", 1)
    if rrd is None and not spawn and connect is None:
        if record_every != 1:
            raise WheelrailError("--record-every needs --rrd, --spawn or --connect")
        return None
    return RecordingSink(rrd=rrd, spawn=spawn, connect=connect, record_every=record_every, description=description)


# --------------------------------------------------------------------------------------------------
# Blueprint
# --------------------------------------------------------------------------------------------------


def default_blueprint(*, pressure: bool = True):
    """The layout a replay opens with: time series left, pressure map and surface right, spectrum, parameters.

    Parameters
    ----------
    pressure : bool
        Include the pressure views (3D model); without them the time series take the whole width.
    """
    rrb = _rr().blueprint
    series = rrb.Vertical(
        rrb.TimeSeriesView(origin="/", contents=["contact/force"], name="Contact force (N)"),
        rrb.TimeSeriesView(
            origin="/", contents=["wheel/displacement", "rail/displacement"], name="Displacements (m)"
        ),
        rrb.TimeSeriesView(
            origin="/",
            contents=["roughness/under_wheel", "roughness/equivalent", "roughness/lines"],
            name="Roughness (m)",
        ),
        rrb.Tabs(
            rrb.TimeSeriesView(origin="/", contents=["contact/length"], name="Contact length (m)"),
            rrb.TimeSeriesView(origin="/", contents=["contact/area"], name="Contact area (m²)"),
        ),
    )
    side = [
        rrb.Tabs(
            rrb.BarChartView(origin="spectra/force", name="Force spectrum (dB re 1 N)"),
            rrb.TextDocumentView(origin="parameters", name="Parameters"),
        )
    ]
    if pressure:
        side = [
            rrb.Spatial2DView(
                origin="contact",
                contents=["$origin/pressure", "$origin/nominal_circle"],
                name="Contact pressure (Pa), Hertz circle",
            ),
            rrb.Spatial3DView(
                origin="contact",
                contents=["$origin/pressure_surface", "$origin/nominal_circle"],
                name="Pressure surface (z = a p/p0)",
            ),
            *side,
        ]
    layout = rrb.Horizontal(series, rrb.Vertical(*side), column_shares=[3, 2])
    return rrb.Blueprint(layout, rrb.TimePanel(timeline="time"), collapse_panels=False)


# --------------------------------------------------------------------------------------------------
# The sink
# --------------------------------------------------------------------------------------------------


def _hertz_geometry(parameters: dict) -> tuple[float, float]:
    """(Hertz radius a in m, Hertz peak pressure p0 in Pa) at the preload of a parameters dict."""
    from dataclasses import fields

    from wheelrail.core.parameters import ContactParameters

    given = parameters.get("contact", {}) if isinstance(parameters, dict) else {}
    names = {f.name for f in fields(ContactParameters)}
    contact = ContactParameters(**{k: v for k, v in given.items() if k in names})
    return contact.hertz_radius(), contact.hertz_peak_pressure()


def _colour_table(levels: int = 256) -> np.ndarray:
    """Viridis ramp as packed 0xRRGGBBAA colours (rerun's Rgba32), ``levels`` entries."""
    u = np.linspace(0.0, len(_VIRIDIS) - 1, levels)
    low = np.minimum(u.astype(np.int64), len(_VIRIDIS) - 2)
    frac = (u - low)[:, None]
    rgb = np.round(_VIRIDIS[low] * (1.0 - frac) + _VIRIDIS[low + 1] * frac).astype(np.uint32)
    return (rgb[:, 0] << 24) | (rgb[:, 1] << 16) | (rgb[:, 2] << 8) | np.uint32(0xFF)


_COLOUR_TABLE = _colour_table()


def _colours(values: np.ndarray, top: float) -> np.ndarray:
    """Packed RGBA colours of ``values`` on the viridis ramp over 0..top (a table look-up: ~1 ns a value)."""
    index = np.clip(values * np.float32((len(_COLOUR_TABLE) - 1) / top), 0, len(_COLOUR_TABLE) - 1)
    return _COLOUR_TABLE[index.astype(np.uint8)]


class RecordingSink:
    """Records a run to a ``.rrd`` file and/or a live rerun viewer, step by step or from a finished result.

    Use it as the loop's per-step callback: ``sink(state)`` buffers the :class:`StepState` and every
    ``chunk_steps`` steps the block is sent as columns. Typical use::

        sink = RecordingSink(rrd="run.rrd")            # path checked here, before the run
        run = prepare_run("corrugated-rail", model="3d", length=0.5)
        sink.start(run)                                 # parameters, window, Hertz circle (optional)
        result = run.run(sink)                          # or simulate(..., callback=sink)
        sink.finish(result)                             # last block, force spectrum, file closed

    :func:`record_result` writes a finished :class:`RunResult` in one go.

    Parameters
    ----------
    rrd : str or path, optional
        ``.rrd`` file to write. It is written under a temporary name in the same folder and renamed on
        :meth:`finish`, so an interrupted run never leaves a half-written file under the final name.
    spawn : bool
        Start a rerun viewer (``rerun`` executable of rerun-sdk) and stream to it.
    connect : str, optional
        Address of a running viewer, ``HOST:PORT`` or a ``rerun+http://HOST:PORT/proxy`` URL.
    record_every : int
        Record the pressure map (image) of every N-th step; scalars are recorded every step.
    surface_every : int
        Record the pressure surface mesh at every M-th recorded map, i.e. every ``record_every * M`` steps.
    chunk_steps : int
        Steps per columnar send.
    description : str
        Name of the recording shown by the viewer.
    """

    def __init__(
        self,
        *,
        rrd: str | os.PathLike | None = None,
        spawn: bool = False,
        connect: str | None = None,
        record_every: int = 1,
        surface_every: int = SURFACE_EVERY,
        chunk_steps: int = DEFAULT_CHUNK_STEPS,
        description: str = "",
    ) -> None:
        checks = (("record_every", record_every), ("surface_every", surface_every), ("chunk_steps", chunk_steps))
        for name, value in checks:
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
                option = "--record-every" if name == "record_every" else name
                raise WheelrailError(f"{option} must be a whole number >= 1, got {value!r}")
        if rrd is None and not spawn and connect is None:
            raise WheelrailError("a recording needs a .rrd file, a viewer to spawn or an address to connect to")
        self.path = None if rrd is None else check_recording_path(rrd)
        url = None if connect is None else _grpc_url(connect)
        self.record_every = int(record_every)
        self.surface_every = int(surface_every)
        self.chunk_steps = int(chunk_steps)
        self.description = description
        rr = _rr()
        self._rr = rr
        self.recording_id = str(uuid.uuid4())
        self.stream = rr.RecordingStream(APPLICATION_ID, recording_id=self.recording_id)
        sinks = []
        self._temporary = None
        if self.path is not None:
            self._temporary = temporary_beside(self.path, suffix=".partial")
            # a sink dropped without finish() or abort() (e.g. the run raised) leaves no partial file behind
            self._finalizer = weakref.finalize(self, _remove, self._temporary)
            sinks.append(rr.FileSink(str(self._temporary)))
        self._spawned = bool(spawn)
        if spawn:
            try:
                self.stream.spawn(port=DEFAULT_VIEWER_PORT, connect=False)
            except Exception as error:  # noqa: BLE001 - rerun raises several types; report one line
                self._discard()
                raise WheelrailError(f"could not start the rerun viewer: {error}") from None
            spawned = f"rerun+http://127.0.0.1:{DEFAULT_VIEWER_PORT}/proxy"
            if spawned != url:
                sinks.append(rr.GrpcSink(spawned))
        if url is not None:
            try:
                sinks.append(rr.GrpcSink(url))
            except Exception as error:  # noqa: BLE001
                self._discard()
                raise WheelrailError(f"--connect {connect!r}: {error}") from None
        self.stream.set_sinks(*sinks, default_blueprint=default_blueprint())
        if description:
            self.stream.send_recording_name(description)
        self._meta: dict = {}
        self._started = False
        self._closed = False
        self._window: tuple[np.ndarray, np.ndarray] | None = None
        self._geometry: tuple[float, float] | None = None
        self._roughness = None  # (line numbers, rows of the set, RoughnessSet) for roughness/lines
        self._roughness_tried = False
        self._rows: list[tuple] = []  # buffered steps: the scalar fields of StepState, in _ROW_FIELDS order
        self._maps: list[tuple[int, np.ndarray]] = []  # buffered (step, pressure map) to record
        self._pressure_format_sent = False
        self._steps_recorded = 0
        self._pressure_maps_recorded = 0
        self._force: list[float] = []
        self._time_step: float | None = None
        self._first_time: float | None = None

    # -- context manager: a failure inside discards the partial file -----------------------------------
    def __enter__(self) -> RecordingSink:
        return self

    def __exit__(self, kind, value, traceback) -> None:
        if kind is None:
            if not self._closed:
                self.finish()
        else:
            self.abort()

    # -- run description ---------------------------------------------------------------------------------
    def start(self, run=None, *, roughness=None, **metadata) -> None:
        """Log the once-per-run data: parameters document, Hertz circle, pressure-window geometry.

        Parameters
        ----------
        run : InteractionRun or RunResult, optional
            Source of ``model``, ``line``, ``speed`` (m/s), ``element_size`` (m), ``time_step`` (s),
            ``roughness_name``, ``parameters`` (nested dict, SI) and the 3D window ``window_x``,
            ``window_y`` (m, element centres relative to the wheel centre).
        roughness : RoughnessSet, optional
            Set whose lines around the run's line are recorded as ``roughness/lines``. Default: loaded
            from the run's ``roughness_name`` when that is a bundled set or a file; else not recorded.
        **metadata
            Overrides of the fields above (same names).
        """
        if self._closed:
            raise WheelrailError("the recording is already finished")
        try:
            self._start(run, roughness, metadata)
        except BaseException:
            self.abort()
            raise

    def _start(self, run, roughness, metadata: dict) -> None:
        meta = _run_metadata(run)
        meta.update({k: v for k, v in metadata.items() if v is not None})
        self._meta.update(meta)
        if meta.get("window_x") is not None and meta.get("window_y") is not None:
            self._window = (np.asarray(meta["window_x"], float), np.asarray(meta["window_y"], float))
        self._geometry = _hertz_geometry(self._meta.get("parameters", {}))
        self._set_roughness(roughness)
        self._log_parameters()
        self._log_nominal_circle()
        self._started = True

    def _set_roughness(self, roughness) -> None:
        if roughness is None:
            name = self._meta.get("roughness_name")
            if not name:
                return  # not known yet: finish(result) tries again
            self._roughness_tried = True
            from wheelrail.core.roughness import bundled_names, load_roughness

            try:
                loadable = name in bundled_names() or Path(str(name)).is_file()
                roughness = load_roughness(name) if loadable else None
            except (OSError, WheelrailError):  # a description rather than a name, or a file gone since
                roughness = None
            if roughness is None:
                return
        self._roughness_tried = True
        line = int(self._meta.get("line", 0))
        numbers = [int(k) for k in roughness.line_numbers]
        shown = [k for k in range(line - ROUGHNESS_LINES_SHOWN, line + ROUGHNESS_LINES_SHOWN + 1) if k in numbers]
        if not shown:
            return
        self._roughness = (shown, [roughness.row_of_line(k) for k in shown], roughness)
        self.stream.log(
            "roughness/lines",
            self._rr.SeriesLines(names=[f"line {k} height (m)" for k in shown]),
            static=True,
            strict=True,
        )

    def _log_parameters(self) -> None:
        rr = self._rr
        meta = {k: v for k, v in self._meta.items()}
        document = {
            "model": meta.get("model"),
            "line": meta.get("line"),
            "speed_m_per_s": meta.get("speed"),
            "element_size_m": meta.get("element_size"),
            "time_step_s": meta.get("time_step", self._time_step),
            "roughness": meta.get("roughness_name"),
            "loss_of_contact_steps": meta.get("loss_of_contact_steps"),
            "run_in_length_m": meta.get("run_in_length"),
            "record_every": self.record_every,
            "surface_every": self.surface_every,
            "window_x_m": None if self._window is None else self._window[0],
            "window_y_m": None if self._window is None else self._window[1],
            "hertz_radius_m": None if self._geometry is None else self._geometry[0],
            "hertz_peak_pressure_pa": None if self._geometry is None else self._geometry[1],
            "parameters": meta.get("parameters", {}),
        }
        text = (
            f"# wheelrail run{': ' + self.description if self.description else ''}\n\n"
            "SI units (m, s, N, Pa, kg) unless a key names its unit.\n\n"
            f"```json\n{json.dumps(json_ready(document), indent=2)}\n```\n"
        )
        self.stream.log("parameters", rr.TextDocument(text, media_type="text/markdown"), static=True, strict=True)

    def _log_nominal_circle(self) -> None:
        rr = self._rr
        a = self._geometry[0]
        angle = np.linspace(0.0, 2 * np.pi, 97)
        circle = np.c_[a * np.cos(angle), a * np.sin(angle)]
        label = f"Hertz circle a = {a * 1e3:.2f} mm"
        self.stream.log(
            "contact/nominal_circle",
            rr.LineStrips3D([np.c_[circle, np.zeros(len(angle))]], colors=[(255, 255, 255)], labels=[label]),
            static=True,
            strict=True,
        )
        if self._window is not None:
            self._log_circle_pixels(circle)

    def _log_circle_pixels(self, circle: np.ndarray) -> None:
        # pixel (column j, row i) covers [j, j+1] x [i, i+1]: element centre x_j sits at j + 0.5
        x, y = self._window
        dx = float(x[1] - x[0]) if len(x) > 1 else 1.0
        dy = float(y[1] - y[0]) if len(y) > 1 else dx
        pixels = np.c_[(circle[:, 0] - x[0]) / dx + 0.5, (circle[:, 1] - y[0]) / dy + 0.5]
        self.stream.log(
            "contact/nominal_circle",
            self._rr.LineStrips2D([pixels], colors=[(255, 255, 255)], draw_order=10.0),
            static=True,
            strict=True,
        )

    # -- per step -------------------------------------------------------------------------------------------
    def __call__(self, state: StepState) -> None:
        """Buffer one step (the loop's callback); sends a block every ``chunk_steps`` steps."""
        if self._closed:
            raise WheelrailError("the recording is already finished")
        self._rows.append((state.step, state.time, state.position, state.force, state.xi_wheel, state.xi_rail,
                           state.roughness, state.contact_length, state.contact_area))
        if state.pressure is not None and state.step % self.record_every == 0:
            # the loop may reuse its pressure buffer: keep a float32 copy
            self._maps.append((state.step, np.array(state.pressure, dtype=np.float32)))
        if len(self._rows) >= self.chunk_steps:
            self.flush()

    log_step = __call__  # the same, under a name that reads well as ``callback=sink.log_step``

    _ROW_FIELDS = ("step", "time", "x", "force", "xi_wheel", "xi_rail", "roughness", "contact_length",
                   "contact_area")

    def flush(self) -> None:
        """Send the buffered steps as one block of columns."""
        if not self._rows:
            return
        table = np.array(self._rows, dtype=float)  # (steps, fields): one conversion for the whole block
        maps = self._maps
        self._rows, self._maps = [], []
        columns = {name: np.ascontiguousarray(table[:, i]) for i, name in enumerate(self._ROW_FIELDS)}
        steps = columns.pop("step").astype(np.int64)
        pressure_steps = np.array([k for k, _ in maps], dtype=np.int64)
        pressure = np.stack([p for _, p in maps]) if maps else None
        self._send_block(steps, columns, pressure_steps, pressure)

    def _send_block(self, steps, columns: dict, pressure_steps=None, pressure=None, equivalent=None) -> None:
        """Send one block of steps: scalars at every step, pressure maps at ``pressure_steps``."""
        if not self._started:
            self.start()
        rr = self._rr
        time, x = columns["time"], columns["x"]
        if self._first_time is None and len(time):
            self._first_time = float(time[0])
        if self._time_step is None and len(time) > 1:
            self._time_step = float(time[1] - time[0])
        self._force.extend(columns["force"].tolist())
        if self._steps_recorded == 0:
            for path, (name, colour) in _SERIES.items():
                self.stream.log(path, rr.SeriesLines(names=[name], colors=[colour]), static=True, strict=True)
        indexes = self._indexes(steps, time, x)  # shared by every entity of the block
        for name, path in SCALAR_PATHS.items():
            values = columns[name]
            finite = np.isfinite(values)
            if finite.all():
                self.stream.send_columns(path, indexes, rr.Scalars.columns(scalars=values), strict=True)
            elif finite.any():  # e.g. no contact area in 2D: leave those steps out rather than log NaN
                self.stream.send_columns(
                    path, self._indexes(steps[finite], time[finite], x[finite]),
                    rr.Scalars.columns(scalars=values[finite]), strict=True,
                )
        if equivalent is not None:
            self.stream.send_columns("roughness/equivalent", indexes, rr.Scalars.columns(scalars=equivalent),
                                     strict=True)
        if self._roughness is not None:
            self._send_roughness_lines(steps, time, x, indexes)
        self._steps_recorded += len(steps)
        if pressure is not None and len(pressure):
            self._send_pressure(steps, time, x, pressure_steps, pressure)

    def _send_roughness_lines(self, steps, time, x, indexes=None) -> None:
        """Heights of the shown lines of the set at the wheel positions x (periodic for a wheel), m."""
        _, rows, rough = self._roughness
        period = rough.length if rough.periodic else None
        heights = np.stack([np.interp(x, rough.x, rough.heights[r], period=period) for r in rows], axis=1)
        self.stream.send_columns(
            "roughness/lines", indexes or self._indexes(steps, time, x), self._rr.Scalars.columns(scalars=heights),
            strict=True,
        )

    def _indexes(self, steps, time, x) -> list:
        rr = self._rr
        return [
            rr.TimeColumn("step", sequence=steps),
            rr.TimeColumn("time", duration=np.round(np.asarray(time) * 1e9).astype("timedelta64[ns]")),
            rr.TimeColumn("position_um", sequence=np.round(np.asarray(x) * 1e6).astype(np.int64)),
        ]

    def _send_pressure(self, steps, time, x, pressure_steps, pressure) -> None:
        rr = self._rr
        pressure = np.ascontiguousarray(pressure, dtype=np.float32)
        n, ny, nx = pressure.shape
        a, p0 = self._geometry
        if self._window is None:  # no window given: element centres of a grid centred on the wheel
            dx = float(self._meta.get("element_size") or 1e-3)
            self._window = ((np.arange(nx) - (nx - 1) / 2) * dx, (np.arange(ny) - (ny - 1) / 2) * dx)
            angle = np.linspace(0.0, 2 * np.pi, 97)
            self._log_circle_pixels(np.c_[a * np.cos(angle), a * np.sin(angle)])
        wx, wy = self._window
        if (len(wy), len(wx)) != (ny, nx):
            raise WheelrailError(f"pressure maps are {ny} x {nx} but the window is {len(wy)} x {len(wx)}")
        if not self._pressure_format_sent:
            self.stream.log(
                "contact/pressure",
                rr.DepthImage.from_fields(
                    format=rr.components.ImageFormat(width=nx, height=ny, channel_datatype="F32", color_model="L"),
                    colormap="viridis",
                    depth_range=(0.0, PRESSURE_RANGE_P0 * p0),
                    meter=1.0,
                ),
                static=True,
                strict=True,
            )
            gx, gy = np.meshgrid(wx, wy)
            triangles = []
            for i in range(ny - 1):
                for j in range(nx - 1):
                    v = i * nx + j
                    triangles += [(v, v + 1, v + nx), (v + 1, v + nx + 1, v + nx)]
            self._surface_xy = np.c_[gx.ravel(), gy.ravel()].astype(np.float32)
            self.stream.log(
                "contact/pressure_surface",
                rr.Mesh3D(
                    vertex_positions=np.c_[self._surface_xy, np.zeros(nx * ny, np.float32)],
                    triangle_indices=np.array(triangles, dtype=np.uint32),
                ),
                static=True,
                strict=True,
            )
            self._pressure_format_sent = True
        where = np.searchsorted(steps, pressure_steps)
        indexes = self._indexes(pressure_steps, time[where], x[where])
        self.stream.send_columns(
            "contact/pressure", indexes, rr.DepthImage.columns(buffer=pressure.reshape(n, -1).view(np.uint8)),
            strict=True,
        )
        surface = pressure_steps % (self.record_every * self.surface_every) == 0
        if surface.any():
            self._send_surface(pressure[surface], indexes if surface.all() else self._indexes(
                pressure_steps[surface], time[where][surface], x[where][surface]))
        self._pressure_maps_recorded += n

    def _send_surface(self, pressure: np.ndarray, indexes: list) -> None:
        """The pressure surface meshes (z = a p / p0, viridis colours) of the given maps."""
        rr = self._rr
        n, ny, nx = pressure.shape
        a, p0 = self._geometry
        vertices = np.empty((n, ny * nx, 3), dtype=np.float32)
        vertices[:, :, :2] = self._surface_xy
        vertices[:, :, 2] = pressure.reshape(n, -1) * (a / p0)
        colours = _colours(pressure.reshape(n, -1), PRESSURE_RANGE_P0 * p0)
        lengths = np.full(n, ny * nx)
        surface = rr.Mesh3D.columns(vertex_positions=vertices.reshape(-1, 3), vertex_colors=colours.reshape(-1))
        self.stream.send_columns(
            "contact/pressure_surface", indexes, [column.partition(lengths) for column in surface], strict=True
        )

    # -- end --------------------------------------------------------------------------------------------------
    def finish(self, result: RunResult | None = None) -> Path | None:
        """Send the last block, the force spectrum and the final parameters; close and rename the file.

        Parameters
        ----------
        result : RunResult, optional
            The finished run: its metadata (e.g. ``loss_of_contact_steps``) completes the parameters
            document and its force gives the spectrum (else the recorded steps' force is used).

        Returns
        -------
        pathlib.Path or None
            The ``.rrd`` file written, if any.
        """
        if self._closed:
            return self.path
        try:
            self.flush()
            if result is not None:
                self._meta.update(_run_metadata(result))
                if self._window is None and result.window_x is not None and result.window_y is not None:
                    self._window = (np.asarray(result.window_x, float), np.asarray(result.window_y, float))
                geometry = _hertz_geometry(self._meta.get("parameters", {}))
                if geometry != self._geometry:  # started without the run's parameters: correct the circle
                    self._geometry = geometry
                    self._log_nominal_circle()
                if self._roughness is None and not self._roughness_tried:
                    self._set_roughness(None)  # sent once here, over the whole run
                    if self._roughness is not None:
                        for first in range(0, result.n_steps, self.chunk_steps):
                            block = slice(first, first + self.chunk_steps)
                            self._send_roughness_lines(np.arange(result.n_steps)[block], result.time[block],
                                                       result.x[block])
            if self._geometry is None:
                self._geometry = _hertz_geometry(self._meta.get("parameters", {}))
            self._log_parameters()
            self._log_spectrum(result)
        except BaseException:
            self.abort()
            raise
        unreachable = self._close()
        if self._temporary is not None:
            self._finalizer.detach()
            publish(self._temporary, self.path)
            self._temporary = None
        if unreachable:
            written = f"the recording was written to {self.path}, but " if self.path is not None else ""
            hint = " (--spawn needs a desktop session for the viewer window)" if self._spawned else ""
            raise WheelrailError(f"{written}the rerun viewer could not be reached{hint}: {unreachable}")
        return self.path

    def _log_spectrum(self, result: RunResult | None) -> None:
        from wheelrail.core.spectra import force_spectrum

        force = result.force if result is not None else np.asarray(self._force)
        time_step = result.time_step if result is not None else (self._meta.get("time_step") or self._time_step)
        if time_step is None or len(force) < 2:
            return
        try:
            centres, levels = force_spectrum(force, time_step)
        except WheelrailError:
            return  # run too short for a spectrum (fewer than 16 steps after the start-up skip)
        self.stream.log(
            "spectra/force",
            self._rr.BarChart(np.nan_to_num(levels, nan=0.0), abscissa=centres),
            static=True,
            strict=True,
        )

    def abort(self) -> None:
        """Stop recording after a failure or cancellation: close the streams and delete the partial file."""
        if self._closed:
            return
        self._rows, self._maps = [], []
        self._close()
        self._discard()

    def _close(self) -> str:
        """Flush and close every sink; returns why a viewer could not be reached ('' if all went out)."""
        self._closed = True
        problem = ""
        try:
            self.stream.flush()
        except RuntimeError as error:  # rerun gives up on an unreachable viewer after ~7 s
            problem = str(error).splitlines()[0] if str(error) else type(error).__name__
        finally:
            self.stream.disconnect()  # drops the file sink: the file is completed (footer) and closed
        return problem

    def _discard(self) -> None:
        if self._temporary is not None:
            self._temporary.unlink(missing_ok=True)
            self._temporary = None


def _remove(path: Path) -> None:
    path.unlink(missing_ok=True)


def _run_metadata(run) -> dict:
    """Metadata of an InteractionRun or a RunResult (duck-typed) as the sink's dict."""
    if run is None:
        return {}
    meta = {}
    for name in ("model", "line", "roughness_name", "window_x", "window_y", "speed", "element_size", "time_step",
                 "loss_of_contact_steps", "run_in_length"):
        value = getattr(run, name, None)
        if value is not None:
            meta[name] = value
    if isinstance(getattr(run, "parameters", None), dict):
        meta["parameters"] = run.parameters
    elif getattr(run, "params", None) is not None:  # an InteractionRun: ModelParameters
        from dataclasses import asdict

        params = run.params
        meta["parameters"] = asdict(params)
        meta.setdefault("speed", params.run.speed)
        meta.setdefault("element_size", params.run.element_size)
        meta.setdefault("time_step", params.run.time_step)
    if "element_size" not in meta and getattr(run, "dx", None) is not None:
        meta["element_size"] = run.dx
    return meta


# --------------------------------------------------------------------------------------------------
# Whole-run export
# --------------------------------------------------------------------------------------------------


def record_result(
    result: RunResult,
    path: str | os.PathLike | None = None,
    *,
    roughness=None,
    record_every: int = 1,
    surface_every: int = SURFACE_EVERY,
    spawn: bool = False,
    connect: str | None = None,
    description: str = "",
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
) -> Path | None:
    """Write a finished :class:`RunResult` as a recording (file and/or viewer) in one go.

    Parameters
    ----------
    result : RunResult
        The run (arrays over steps, SI).
    path : str or path, optional
        ``.rrd`` file to write (atomically: temporary name, then rename).
    roughness : RoughnessSet, optional
        For ``roughness/lines`` (default: loaded from ``result.roughness_name`` when possible).
    record_every, surface_every, spawn, connect, description, chunk_steps
        As for :class:`RecordingSink`.

    Returns
    -------
    pathlib.Path or None
        The file written, if any.
    """
    if not isinstance(result, RunResult):
        raise WheelrailError(f"record_result needs a RunResult, got {type(result).__name__}")
    sink = RecordingSink(
        rrd=path, spawn=spawn, connect=connect, record_every=record_every, surface_every=surface_every,
        chunk_steps=chunk_steps,
        description=description,
    )
    try:
        sink.start(result, roughness=roughness)
        steps = np.arange(result.n_steps, dtype=np.int64)
        for first in range(0, result.n_steps, sink.chunk_steps):
            block = slice(first, min(result.n_steps, first + sink.chunk_steps))
            columns = {name: np.asarray(getattr(result, name), dtype=float)[block] for name in
                       ("time", "x", "force", "xi_wheel", "xi_rail", "roughness", "contact_length", "contact_area")}
            equivalent = result.equivalent_roughness[block]
            if np.array_equal(equivalent, result.roughness[block]):
                equivalent = None  # r_eq = r (hertz, 2d, 3d): not repeated
            pressure_steps = pressure = None
            if result.pressure is not None:
                pressure_steps = steps[block][steps[block] % sink.record_every == 0]
                pressure = result.pressure[pressure_steps]
            sink._send_block(steps[block], columns, pressure_steps, pressure, equivalent)
        return sink.finish(result)
    except BaseException:
        sink.abort()
        raise


# --------------------------------------------------------------------------------------------------
# Reader
# --------------------------------------------------------------------------------------------------


def _component(batch, name: str):
    index = batch.schema.get_field_index(name)
    return None if index < 0 else batch.column(index)


def read_recording(path: str | os.PathLike) -> RunResult:
    """Read a ``.rrd`` written by this module back into a :class:`RunResult`, with rerun's own reader.

    Uses ``rerun.chunk.RrdReader`` (rerun-sdk 0.41): the chunks of each entity are decoded from Arrow and
    ordered by the ``step`` timeline. Scalars come back exactly (float64); ``time`` is the ``time``
    timeline (whole nanoseconds); ``pressure`` is filled only if a map was recorded at every step
    (``record_every`` 1), else None; ``equivalent_roughness`` equals ``roughness`` unless
    ``roughness/equivalent`` was recorded.

    Raises
    ------
    WheelrailError
        The file is missing, not a rerun recording, or not a wheelrail recording.
    """
    source = Path(path)
    if not source.is_file():
        raise WheelrailError(f"recording {source} does not exist or is not a file")
    rr = _rr()
    try:
        with warnings.catch_warnings():
            # a file without footer (e.g. a run killed while recording) warns before being scanned: the
            # scan below either works or raises, so the warning would only add a second line
            warnings.simplefilter("ignore")
            reader = rr.chunk.RrdReader(source)
            recordings = [entry for entry in reader.recordings() if entry.application_id == APPLICATION_ID]
            if not recordings:
                raise WheelrailError(f"{source} holds no wheelrail recording")
            chunks = list(reader.stream(store=recordings[0]))
    except WheelrailError:
        raise
    except Exception as error:  # noqa: BLE001 - the Rust reader raises various types on a corrupt file
        text = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise WheelrailError(f"cannot read recording {source}: {text}") from None

    scalars: dict[str, list] = {}
    static: dict[str, dict] = {}
    images: list = []
    for chunk in chunks:
        entity = chunk.entity_path.lstrip("/")
        batch = chunk.to_record_batch()
        if chunk.is_static:
            for field in batch.schema.names:
                if ":" in field:
                    column = batch.column(field)
                    value = column[len(column) - 1].as_py()  # each row is a batch: one value here
                    static.setdefault(entity, {})[field] = value[0] if isinstance(value, list) and value else value
            continue
        step_column = _component(batch, "step")
        if step_column is None:
            continue
        steps = np.asarray(step_column.to_numpy(zero_copy_only=False), dtype=np.int64)
        if entity in SCALAR_PATHS.values() or entity == "roughness/equivalent":
            values = _component(batch, "Scalars:scalars")
            time = _component(batch, "time")
            time_ns = np.asarray(time.cast("int64").to_numpy(zero_copy_only=False)) if time is not None else None
            flat = np.asarray(values.flatten().to_numpy(zero_copy_only=False), dtype=float)
            scalars.setdefault(entity, []).append((steps, flat, time_ns))
        elif entity == "contact/pressure":
            buffers = _component(batch, "DepthImage:buffer")
            if buffers is not None:
                images.append((steps, buffers))

    document = static.get("parameters", {}).get("TextDocument:text")
    if not document or "```json" not in document:
        raise WheelrailError(f"{source} is not a wheelrail recording (no parameters document)")
    meta = json.loads(document.split("```json", 1)[1].split("```", 1)[0])
    if "contact/force" not in scalars:
        raise WheelrailError(f"{source} holds no contact force steps")

    force_parts = scalars["contact/force"]
    all_steps = np.unique(np.concatenate([s for s, _, _ in force_parts]))
    n = len(all_steps)
    if not np.array_equal(all_steps, np.arange(n)):
        raise WheelrailError(f"{source}: the recorded steps are not 0..{n - 1} (incomplete recording)")

    def series(entity: str, fill: float = np.nan) -> np.ndarray:
        out = np.full(n, fill)
        for steps, values, _ in scalars.get(entity, []):
            out[steps] = values
        return out

    time = np.full(n, np.nan)
    for steps, _, time_ns in force_parts:
        time[steps] = time_ns * 1e-9
    roughness = series("roughness/under_wheel")
    equivalent = series("roughness/equivalent") if "roughness/equivalent" in scalars else roughness.copy()

    pressure = None
    window_x = None if meta.get("window_x_m") is None else np.asarray(meta["window_x_m"], float)
    window_y = None if meta.get("window_y_m") is None else np.asarray(meta["window_y_m"], float)
    image_format = static.get("contact/pressure", {}).get("DepthImage:format")
    if images and image_format is not None:
        width, height = int(image_format["width"]), int(image_format["height"])
        maps = np.full((n, height, width), np.nan, dtype=np.float32)
        seen = np.zeros(n, dtype=bool)
        for steps, buffers in images:
            blobs = buffers.flatten()  # one image buffer (blob) per row
            if len(blobs) != len(steps):
                raise WheelrailError(f"{source}: contact/pressure rows hold {len(blobs)} images for {len(steps)} steps")
            raw = np.asarray(blobs.flatten().to_numpy(zero_copy_only=False), dtype=np.uint8)
            inside = steps < n
            maps[steps[inside]] = raw.view(np.float32).reshape(len(steps), height, width)[inside]
            seen[steps[inside]] = True
        if seen.all():
            pressure = maps

    def number(key, default=math.nan):
        value = meta.get(key)
        return default if value is None else value

    try:
        header = RunHeader.from_dict(meta)
    except WheelrailError as error:
        raise WheelrailError(f"{source}: {error}") from None
    return RunResult(
        header=header,
        time=time,
        x=series("wheel/position"),
        force=series("contact/force"),
        xi_wheel=series("wheel/displacement"),
        xi_rail=series("rail/displacement"),
        roughness=roughness,
        contact_length=series("contact/length"),
        contact_area=series("contact/area"),
        equivalent_roughness=equivalent,
        pressure=pressure,
        window_x=window_x,
        window_y=window_y,
        loss_of_contact_steps=int(number("loss_of_contact_steps", 0)),
    )
