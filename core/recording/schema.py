"""What a wheelrail recording holds: entity paths, the one list of scalar series, the parameters document
and the default blueprint. The sink writes, and the reader reads, exactly what is declared here.

Changing a path or a component here changes the file format: recordings already written must still read
(``tests/recording/test_compatibility.py`` reads files kept from a fixed commit, ``tests/data/recording``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from wheelrail.core.drawing.patch import PRESSURE_RANGE_P0  # noqa: F401 - the colour ramp the recording draws with
from wheelrail.core.engine.results import RunHeader
from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.noise.components import sound_power_parts

__all__ = [
    "APPLICATION_ID",
    "BAR_WIDTH",
    "ENTITY_PATHS",
    "SCALAR_FIELDS",
    "STEP_FIELDS",
    "ScalarField",
    "band_chart",
    "band_numbers",
    "default_blueprint",
    "parameters_document",
    "parameters_from_text",
    "parameters_text",
    "rerun_module",
    "time_columns",
]

APPLICATION_ID = "wheelrail"
TIMELINES = ("step", "time", "position_um")
ROUGHNESS_LINES_SHOWN = 3  # roughness/lines shows the set's lines k-3 .. k+3 around the run's line k

PARAMETERS = "parameters"
ROUGHNESS_LINES = "roughness/lines"
PRESSURE = "contact/pressure"
PRESSURE_SURFACE = "contact/pressure_surface"
NOMINAL_CIRCLE = "contact/nominal_circle"  # LineStrips3D, m (the 3D view)
# LineStrips2D in the pressure image's pixels (the 2D view): an entity of its own, as a view draws only its own
# kind (a 3D strip in a 2D view, or a 2D one in a 3D view, is an error badge without a camera between them)
NOMINAL_CIRCLE_IMAGE = "contact/nominal_circle_image"
FORCE_SPECTRUM = "spectra/force"
# optional (``--sound-power``, ``record_result(sound_power=True)``): the run's rolling noise, one wheel on one rail,
# dB re 1 pW per band 50 Hz-10 kHz (wheelrail.core.noise.run_noise), one entity per part
# (spectra/sound_power/<part>, wheelrail.core.noise.components.sound_power_parts), and a document with the totals
SOUND_POWER = "spectra/sound_power"

# titles of the blueprint's time-series views
FORCE_VIEW = "Contact force (N)"
DISPLACEMENT_VIEW = "Displacements (m)"
ROUGHNESS_VIEW = "Roughness (m)"
LENGTH_VIEW = "Contact length (m)"
AREA_VIEW = "Contact area (m²)"


@dataclass(frozen=True)
class ScalarField:
    """One scalar series of a run: where it is recorded and how it is drawn.

    Attributes
    ----------
    name : str
        Attribute of :class:`~wheelrail.core.engine.results.RunResult` (an array over steps, SI).
    path : str
        Entity path of its ``Scalars``.
    legend : str
        Series name shown by the viewer, with its unit.
    colour : tuple of int
        Series colour, sRGB 0..255.
    view : str or None
        Title of the default blueprint's time-series view that shows it (None: in no view).
    state : str or None
        Attribute of :class:`~wheelrail.core.engine.results.StepState` streamed at every step; None for a series
        that only a finished run has (recorded by the whole-run export).
    """

    name: str
    path: str
    legend: str
    colour: tuple[int, int, int]
    view: str | None
    state: str | None


SCALAR_FIELDS = (
    ScalarField("x", "wheel/position", "wheel position x (m)", (120, 120, 120), None, "position"),
    ScalarField(
        "xi_wheel", "wheel/displacement", "wheel displacement ξ_W (m)", (31, 119, 180), DISPLACEMENT_VIEW, "xi_wheel"
    ),
    ScalarField(
        "xi_rail", "rail/displacement", "rail displacement ξ_R (m)", (214, 39, 40), DISPLACEMENT_VIEW, "xi_rail"
    ),
    ScalarField(
        "roughness",
        "roughness/under_wheel",
        "roughness r under the wheel (m)",
        (44, 160, 44),
        ROUGHNESS_VIEW,
        "roughness",
    ),
    # r_eq of the Hertz variants: recorded by the whole-run export where it differs from r
    ScalarField(
        "equivalent_roughness",
        "roughness/equivalent",
        "equivalent roughness r_eq (m)",
        (148, 103, 189),
        ROUGHNESS_VIEW,
        None,
    ),
    ScalarField("force", "contact/force", "contact force F (N)", (23, 23, 23), FORCE_VIEW, "force"),
    ScalarField(
        "contact_length", "contact/length", "contact length (m)", (255, 127, 14), LENGTH_VIEW, "contact_length"
    ),
    ScalarField("contact_area", "contact/area", "contact area (m²)", (140, 86, 75), AREA_VIEW, "contact_area"),
)
STEP_FIELDS = tuple(field for field in SCALAR_FIELDS if field.state is not None)  # streamed every step
EQUIVALENT = next(field for field in SCALAR_FIELDS if field.name == "equivalent_roughness")
FIELD_OF_PATH = {field.path: field for field in SCALAR_FIELDS}
SCALAR_PATHS = {field.name: field.path for field in STEP_FIELDS}  # name -> entity path, streamed series

ENTITY_PATHS = (
    PARAMETERS,
    *SCALAR_PATHS.values(),
    EQUIVALENT.path,
    ROUGHNESS_LINES,
    PRESSURE,
    PRESSURE_SURFACE,
    NOMINAL_CIRCLE,
    NOMINAL_CIRCLE_IMAGE,
    FORCE_SPECTRUM,
)


def rerun_module():
    """Import rerun on first use: the package stays importable (and the CLI fast) without recording."""
    import rerun

    return rerun


# --------------------------------------------------------------------------------------------------
# Parameters document
# --------------------------------------------------------------------------------------------------


def parameters_document(
    header: RunHeader | None,
    *,
    time_step: float | None,
    loss_of_contact_steps: int | None,
    decimation: tuple[int, int],
    window: tuple[np.ndarray, np.ndarray] | None,
    geometry: tuple[float, float] | None,
    recorded_steps: int | None = None,
) -> dict:
    """The run's description as recorded (keys in file order; SI, keys name their unit).

    It is logged when a recording starts (``recorded_steps`` None) and again when it is finished, with the
    number of steps recorded: only a finished recording holds ``recorded_steps`` (the reader's mark of a
    complete file; a recording killed before its end keeps the first document). A finished run over discrete
    irregularities adds ``impacts`` (``engine.impacts.impact_summary``'s dict) to the last one (the sink does).

    Parameters
    ----------
    header : RunHeader or None
        What produced the run (None: not known, e.g. a sink used without ``start``).
    time_step : float or None
        dt, s, when there is no header (measured from the recorded times).
    loss_of_contact_steps : int or None
        Steps with F = 0 (known at the end of a run).
    decimation : (int, int)
        ``record_every`` and ``surface_every`` of the sink.
    window : (ndarray, ndarray) or None
        Pressure-window element centres x', y' relative to the wheel centre, m.
    geometry : (float, float) or None
        Hertz radius a (m) and peak pressure p0 (Pa) at the preload.
    """
    head = header.to_dict() if header is not None else {}
    return {
        "model": head.get("model"),
        "line": head.get("line"),
        "speed_m_per_s": head.get("speed_m_per_s"),
        "element_size_m": head.get("element_size_m"),
        "time_step_s": head.get("time_step_s", time_step),
        "roughness": head.get("roughness"),
        **({"wheel_roughness": head["wheel_roughness"]} if "wheel_roughness" in head else {}),
        "wheel_model": head.get("wheel_model"),  # the interaction's wheel: "2dof" (the paper's) or "modal"
        **({"wheel_profile": head["wheel_profile"]} if "wheel_profile" in head else {}),
        "loss_of_contact_steps": loss_of_contact_steps,
        "run_in_length_m": head.get("run_in_length_m"),
        "run_in_time_s": head.get("run_in_time_s"),
        "record_every": decimation[0],
        "surface_every": decimation[1],
        "window_x_m": None if window is None else window[0],
        "window_y_m": None if window is None else window[1],
        "hertz_radius_m": None if geometry is None else geometry[0],
        "hertz_peak_pressure_pa": None if geometry is None else geometry[1],
        "parameters": head.get("parameters", {}),
        "recorded_steps": recorded_steps,
    }


def parameters_text(document: dict, description: str = "") -> str:
    """The ``parameters`` TextDocument: a markdown title and the document as a JSON block."""
    return (
        f"# wheelrail run{': ' + description if description else ''}\n\n"
        "SI units (m, s, N, Pa, kg) unless a key names its unit.\n\n"
        f"```json\n{strict_json(document, indent=2)}\n```\n"
    )


def parameters_from_text(text: str | None) -> dict | None:
    """Inverse of :func:`parameters_text`: the JSON document, or None if ``text`` holds none."""
    if not text or "```json" not in text:
        return None
    return json.loads(text.split("```json", 1)[1].split("```", 1)[0])


# --------------------------------------------------------------------------------------------------
# Blueprint
# --------------------------------------------------------------------------------------------------


def _series_view(title: str, *extra: str):
    contents = [field.path for field in SCALAR_FIELDS if field.view == title]
    return rerun_module().blueprint.TimeSeriesView(origin="/", contents=[*contents, *extra], name=title)


BAR_WIDTH = 0.9  # of a band: the bars of a band chart stand side by side, a gap between them
BANDS_NOTE = "bands 10 lg f: 17 = 50 Hz, 30 = 1 kHz"  # the bars' abscissa (band_numbers), in a view's title


def band_numbers(centres: np.ndarray) -> np.ndarray:
    """The band numbers n = 10 lg(f / 1 Hz) of third-octave band centres (IEC 61260-1: 17 for 50 Hz, 30 for
    1 kHz), whole numbers: a bar chart's abscissa on which the bands are equally spaced."""
    return np.round(10.0 * np.log10(np.asarray(centres, dtype=float)))


def band_chart(centres: np.ndarray, levels: np.ndarray):
    """A ``BarChart`` of band levels (dB; NaN and -inf drawn as 0) over their band numbers (:func:`band_numbers`).

    The viewer draws bars ``widths`` wide in abscissa units (1 by default): over band centres in Hz the bars of a
    50 Hz-8 kHz spectrum would be 1 Hz slivers on an 8 kHz axis, an empty-looking panel."""
    values = np.nan_to_num(np.asarray(levels, dtype=float), nan=0.0, neginf=0.0)
    return rerun_module().BarChart(values, abscissa=band_numbers(centres), widths=np.full(values.size, BAR_WIDTH))


def _spectra_views(sound_power: bool) -> list:
    rrb = rerun_module().blueprint
    views = [rrb.BarChartView(origin=FORCE_SPECTRUM, name=f"Force spectrum (dB re 1 N; {BANDS_NOTE})")]
    if sound_power:
        views += [
            rrb.BarChartView(origin=f"{SOUND_POWER}/{part}", name=f"Sound power, {part} (dB re 1 pW; {BANDS_NOTE})")
            for part in sound_power_parts()  # spectra/sound_power/<part>: wheelrail.core.noise.components's
        ]
        views.append(rrb.TextDocumentView(origin=f"{SOUND_POWER}/summary", name="Sound power, totals"))
    return views


def default_blueprint(*, pressure: bool = True, sound_power: bool = False):
    """The layout a replay opens with: time series left, pressure map and surface right, spectra, parameters.

    Every view shows only the entities of its own kind (``tests/recording/test_blueprint.py`` checks it against
    recordings): the pressure image and the Hertz circle in pixels in the 2D view, the surface and the circle in
    metres in the 3D view, scalars in the time series, one bar chart per bar chart view.

    Parameters
    ----------
    pressure : bool
        Include the pressure views (a model with pressure maps: ``3d``); without them the time series and the
        spectra share the width.
    sound_power : bool
        Include the sound-power spectra and their totals (``--sound-power``).
    """
    rrb = rerun_module().blueprint
    series = rrb.Vertical(
        _series_view(FORCE_VIEW),
        _series_view(DISPLACEMENT_VIEW),
        _series_view(ROUGHNESS_VIEW, ROUGHNESS_LINES),
        rrb.Tabs(_series_view(LENGTH_VIEW), _series_view(AREA_VIEW)),
    )
    side = [rrb.Tabs(*_spectra_views(sound_power), rrb.TextDocumentView(origin=PARAMETERS, name="Parameters"))]
    if pressure:
        side = [
            rrb.Spatial2DView(
                origin="contact",
                contents=[f"/{PRESSURE}", f"/{NOMINAL_CIRCLE_IMAGE}"],
                name="Contact pressure (Pa), Hertz circle",
            ),
            rrb.Spatial3DView(
                origin="contact",
                contents=[f"/{PRESSURE_SURFACE}", f"/{NOMINAL_CIRCLE}"],
                name="Pressure surface (z = a p/p0)",
            ),
            *side,
        ]
    layout = rrb.Horizontal(series, rrb.Vertical(*side), column_shares=[3, 2])
    return rrb.Blueprint(layout, rrb.TimePanel(timeline="time"), collapse_panels=False)


def time_columns(steps: np.ndarray, time: np.ndarray, x: np.ndarray) -> list:
    """The three timelines of a block of steps: ``step``, ``time`` (whole ns) and ``position_um`` (µm).

    Rerun timelines are integers (sequence, nanosecond duration or timestamp), so a position in metres
    cannot be a timeline; micrometres keep it exact to 1 µm and say their unit.
    """
    rr = rerun_module()
    return [
        rr.TimeColumn("step", sequence=steps),
        rr.TimeColumn("time", duration=np.round(np.asarray(time) * 1e9).astype("timedelta64[ns]")),
        rr.TimeColumn("position_um", sequence=np.round(np.asarray(x) * 1e6).astype(np.int64)),
    ]
