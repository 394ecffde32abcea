"""Building a run, in named steps: inputs checked, roughness along the track, history arrays, static equilibrium.

``interaction.prepare_run`` composes them; each step is a function of what the previous ones returned, so
a study or a test can reuse one (``usable_length`` is the one rule for margins and default lengths).

Start-up: from the moving load's steady state on the gap of step 0 (``steady_start``), then a run-in of
``DEFAULT_RUN_IN_TIME`` (discarded). An explicit run-in, or a bay of no whole number of elements, starts from the
preload in static equilibrium, the roughness faded in over the run-in's first half, which must let the
transient decay: ``PRELOAD_RUN_IN_TIME``. What each leaves: the physics page, "How a step is solved".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import real
from wheelrail.core.inputs.ranges import check_wheel_circumference
from wheelrail.core.models import ModelEntry, ModelInputs, ModelTraits, model_entry
from wheelrail.core.parameters import ModelParameters, TrackNumerics

if TYPE_CHECKING:  # the roughness package is imported when a set is read
    from wheelrail.core.roughness import RoughnessLike, RoughnessSet

__all__ = [
    "DEFAULT_RUN_IN_TIME",
    "PRELOAD_RUN_IN_TIME",
    "RUN_MARGIN",
    "WINDOW_HALF_WIDTH",
    "WINDOW_SEMI_AXES",
    "History",
    "TrackRoughness",
    "check_roughness_pair",
    "check_step_stability",
    "checked_inputs",
    "default_run_in_length",
    "history_arrays",
    "interaction_wheel",
    "model_inputs",
    "roughness_along_track",
    "starts_steady",
    "run_lines",
    "run_margin",
    "static_equilibrium",
    "usable_length",
    "window_half_elements",
    "window_lines",
    "window_width",
]

WINDOW_HALF_WIDTH = 0.012  # m: least half side of the 3D window and of the 2D bedding (2.2 a at 65 kN, R = 0.39 m)
WINDOW_SEMI_AXES = 2.2  # half side of the window in Hertz semi-axes at the preload (along and across)
DEFAULT_RUN_IN_TIME = 0.0005  # s of run-in from the moving load's steady state (discarded); see the module docstring
PRELOAD_RUN_IN_TIME = 0.3  # s of smooth run-in from the preload at rest: where no steady start is taken
RUN_MARGIN = 0.020  # m of roughness kept before the first and after the last wheel position


def window_half_elements(params: ModelParameters | None = None) -> tuple[int, int]:
    """Half sides of the 3D window (and, along the rail, of the 2D bedding), elements: (along, across).

    ``WINDOW_SEMI_AXES`` Hertz semi-axes at the preload (a along the rail, b across), never less than the
    paper's window ``WINDOW_HALF_WIDTH`` (12 mm: the roughness widens the patch and the dynamic load
    exceeds the preload; a light wheel keeps that room), so a long or a wide elliptic patch gets its own room.
    """
    params = ModelParameters() if params is None else params
    dx = params.run.element_size
    least = int(round(WINDOW_HALF_WIDTH / dx))
    a, b = params.contact.hertz_semi_axes()
    return max(least, int(round(WINDOW_SEMI_AXES * a / dx))), max(least, int(round(WINDOW_SEMI_AXES * b / dx)))


def run_margin(element_size: float, params: ModelParameters | None = None) -> float:
    """Roughness kept before the first and after the last wheel position, m.

    One margin for every model (the 3D window's half-width along the rail plus 4 elements, and the bedding
    pre-filter's 3a (16.4 mm at the defaults), within ``RUN_MARGIN`` for the paper's geometry), so that runs of
    different models on the same data start at the same position and compare sample by sample. ``params``
    (default: the paper's, at this element size) sizes the window and a.
    """
    params = ModelParameters() if params is None else params
    if params.run.element_size != element_size:
        params = replace(params, run=replace(params.run, element_size=element_size))
    half_x, _ = window_half_elements(params)
    prefilter = int(math.ceil(3.0 * params.contact.hertz_semi_axes()[0] / element_size - 1e-9))
    return max(half_x + 4, prefilter, int(math.ceil(RUN_MARGIN / element_size))) * element_size


def usable_length(roughness, element_size: float, params: ModelParameters | None = None) -> float:
    """Longest run on a roughness set, m: the rail data less a ``run_margin`` at each end (every model can
    run it), or one circumference for wheel data (it repeats). The default run length of ``prepare_run``
    and of the studies.

    Raises WheelrailError when rail data are too short for one element beyond the margins.
    """
    if roughness.periodic:
        return float(roughness.length)
    margin = run_margin(element_size, params)
    span = (roughness.n_samples - 1) * roughness.dx
    n_steps = math.floor((span - 2 * margin) / element_size + 1e-9)
    if n_steps < 1:
        raise WheelrailError(
            f"rail data of {span:g} m are too short for a run: the model keeps "
            f"{margin * 1e3:g} mm of roughness before and after the wheel"
        )
    return n_steps * element_size


def starts_steady(params: ModelParameters) -> bool:
    """Whether a run with the default run-in starts from the steady state: the bay is whole elements."""
    from wheelrail.core.steady_start import bay_steps

    return bay_steps(params.track.support.sleeper_spacing, params.run.element_size) is not None


def default_run_in_length(params: ModelParameters | None = None) -> float:
    """The default run-in at the run's speed in whole elements, m (:func:`starts_steady`: which time)."""
    params = ModelParameters() if params is None else params
    dx = params.run.element_size
    time = DEFAULT_RUN_IN_TIME if starts_steady(params) else PRELOAD_RUN_IN_TIME
    return math.ceil(time * params.run.speed / dx - 1e-9) * dx


def checked_inputs(
    model: str, line, params: ModelParameters | None, run_in_length
) -> tuple[ModelEntry, ModelParameters, int, float]:
    """Step 1: the model's registry entry, the parameters (default: the paper's), the line number and the
    run-in length, m (None: :func:`default_run_in_length`)."""
    entry = model_entry(model)
    params = ModelParameters() if params is None else params
    if not isinstance(params, ModelParameters):
        raise WheelrailError("params must be a wheelrail.core.parameters.ModelParameters")
    if isinstance(line, bool) or not isinstance(line, int | np.integer):
        raise WheelrailError(f"line must be an integer line number, got {line!r}")
    if run_in_length is None:
        run_in_length = default_run_in_length(params)
    run_in_length = real("run_in_length", run_in_length, "m", sign="nonnegative")
    return entry, params, int(line), run_in_length


def resolve_roughness(roughness: RoughnessLike) -> tuple[RoughnessSet, str]:
    """A RoughnessSet and its name from a set, a bundled set name or a file path."""
    from wheelrail.core.roughness import RoughnessSet, load_roughness

    if isinstance(roughness, RoughnessSet):
        return roughness, roughness.description.splitlines()[0] if roughness.description else "roughness"
    if isinstance(roughness, str) or hasattr(roughness, "__fspath__"):
        return load_roughness(roughness), str(roughness)
    raise WheelrailError(f"roughness must be a RoughnessSet, a bundled set name or a file path, got {roughness!r}")


def resolve_surfaces(roughness: RoughnessLike, wheel_roughness: RoughnessLike | None, params: ModelParameters):
    """The rail (or wheel) set and the optional wheel set with their names, checked as a pair: a rail set and a
    wheel set going round this wheel (``ranges.check_wheel_circumference``)."""
    rough, name = resolve_roughness(roughness)
    wheel, wheel_name = resolve_roughness(wheel_roughness) if wheel_roughness is not None else (None, None)
    if wheel is not None:
        check_roughness_pair(rough, wheel)
        check_wheel_circumference(wheel.length, params.contact.radius_along, wheel_name)
    return rough, name, wheel, wheel_name


@dataclass(frozen=True)
class TrackRoughness:
    """Step 2: the roughness the wheel meets, on the model grid along the track.

    lines (rows, samples): the chosen line (one row) or the rows of a lateral window; ``centre_row`` is the
    chosen line; ``window_y`` the rows' lateral offsets from it, m; sample ``first`` is under the wheel at
    step 0, at ``x_start`` (m) from the start of the data; ``n_steps`` steps follow.
    """

    lines: np.ndarray
    centre_row: int
    window_y: np.ndarray
    first: int
    n_steps: int
    element_size: float

    @property
    def x_start(self) -> float:
        return self.first * self.element_size


def _lateral_room(grid, y_line: float) -> float:
    """Data across the rail on the narrower side of a line, m."""
    return float(min(y_line - grid.y.min(), grid.y.max() - y_line))


def _patch_room(params: ModelParameters, element_size: float) -> float:
    """Data needed on each side of a line by a lateral window: the Hertz semi-axis across the rail (b) at the
    preload rounded up to the grid, plus one element that stays out of contact (the roughness widens the patch)."""
    _, b = params.contact.hertz_semi_axes()
    return (math.ceil(b / element_size - 1e-9) + 1) * element_size


def window_lines(roughness, params: ModelParameters | None = None) -> tuple[int, ...]:
    """The lines a model with a lateral window (``3d``) can be centred on for this set and these parameters.

    A line must fall on the lateral model grid (``element_size`` apart) and have data for the Hertz
    semi-axis across the rail (b) at the preload plus one element on both sides: nearer the edge of the set
    the window is cut and the patch, widened by the roughness, reaches its edge mid-run (the bundled
    corrugated rail, 19 lines over +-9 mm, allows lines -2..2 at 65 kN). The explorer and the CLI offer only these.
    """
    from wheelrail.core.roughness import to_model_grid

    params = ModelParameters() if params is None else params
    if roughness.n_lines < 2:  # one line has no width: no window fits (nor can it be interpolated across)
        return ()
    dx = params.run.element_size
    return _window_lines_on(roughness, to_model_grid(roughness, dx, dx), params)


def window_width(params: ModelParameters | None = None) -> float:
    """The narrowest set (m across the rail) that a model with a lateral window (``3d``) can run on at these
    parameters: the Hertz semi-axis b at the preload, rounded up to the grid, plus one element, on each side of
    the line (at the paper's 65 kN and 1 mm elements: 14 mm)."""
    params = ModelParameters() if params is None else params
    return 2.0 * _patch_room(params, params.run.element_size)


def _window_lines_on(roughness, grid, params: ModelParameters) -> tuple[int, ...]:
    """:func:`window_lines` on the set's lateral model grid ``grid``, already interpolated."""
    need = _patch_room(params, params.run.element_size)
    usable = []
    for line in roughness.line_numbers:
        y_line = float(roughness.y[roughness.row_of_line(int(line))])
        on_grid = np.any(np.abs(grid.y - y_line) <= 1e-9)
        if on_grid and _lateral_room(grid, y_line) >= need - 1e-9:
            usable.append(int(line))
    return tuple(usable)


def _window_rows(grid, y_line: float, line: int, half_width: float) -> tuple[list[int], np.ndarray, int]:
    """Lines of the model grid within ``half_width`` (m) across ``y_line``; their offsets; the centre row."""
    keep = np.abs(grid.y - y_line) <= half_width + 1e-9
    rows = np.nonzero(keep)[0]
    if rows.size < 3:
        raise WheelrailError("3d: the roughness set is too narrow for the contact window")
    window_y = grid.y[rows] - y_line
    centre = int(np.argmin(np.abs(window_y)))
    if abs(window_y[centre]) > 1e-9:
        raise WheelrailError(f"3d: line {line} does not fall on the 1 mm lateral grid")
    return [grid.line_of_row(int(r)) for r in rows], window_y, centre


def _line_error(problem: str, line: int, lines, reason: str | None = None) -> WheelrailError:
    """One WheelrailError blaming the line ``line`` (key ``"line"``): ``problem`` in words that name no input,
    the lines that can be run as its accepted range (``-2 to 2``), or in words when they are not contiguous."""
    lines = list(lines)
    fields = {"parameter": "line", "value": int(line), "reason": reason}
    if lines and lines[-1] - lines[0] == len(lines) - 1:
        return WheelrailError(problem, minimum=lines[0], maximum=lines[-1], **fields)
    words = f"only lines {', '.join(map(str, lines))} can be run" if lines else "no line can be run"
    return WheelrailError(problem, advice=words, **fields)


def _rows_of(rough, traits: ModelTraits, line: int, params: ModelParameters):
    """The model grid of a set and its rows for ``line``: (grid, line numbers, offsets across, centre row)."""
    from wheelrail.core.roughness import to_model_grid

    numbers = list(rough.line_numbers)
    if line not in numbers:
        raise _line_error("not in the roughness set", line, sorted(numbers))
    dx = params.run.element_size
    y_line = float(rough.y[rough.row_of_line(line)])
    if not traits.lateral_window:
        return (to_model_grid(rough, dx), [line], np.zeros(1), 0)
    if rough.n_lines < 2:
        raise _line_error(
            "a set of one line has no width, and a model with a lateral window (3d) needs data "
            f"{window_width(params) * 1e3:.3g} mm across the rail (the patch and one element on each side of "
            "the line); give a set of several lines or a one-line model",
            line,
            (),
        )
    grid = to_model_grid(rough, dx, dx)
    usable = _window_lines_on(rough, grid, params)
    if line not in usable and np.any(np.abs(grid.y - y_line) <= 1e-9):
        raise _line_error(
            f"too close to the side of the roughness data for 3d: the contact patch at "
            f"{params.contact.preload / 1e3:g} kN needs {_patch_room(params, dx) * 1e3:g} mm of data on each side "
            "of its line",
            line,
            usable,
        )
    return (grid, *_window_rows(grid, y_line, line, window_half_elements(params)[1] * dx))


def run_lines(roughness, model: str = "hertz", params: ModelParameters | None = None, wheel=None) -> tuple[int, ...]:
    """The lines of ``roughness`` a run of ``model`` can take (with the wheel set ``wheel`` added, if given).

    A model with a lateral window (``3d``): :func:`window_lines`; a one-line model: every line. With a wheel
    set, which is paired with the rail by lateral position (:func:`roughness_along_track`), only the lines
    whose lateral position the wheel set has data at, and for a lateral window the contact patch's room
    (the Hertz semi-axis b plus one element) on each side of it. The command line's messages and the
    explorer's line menu use this list.
    """
    params = ModelParameters() if params is None else params
    return _run_lines(roughness, model_entry(model).traits, params, wheel)


def _run_lines(roughness, traits: ModelTraits, params: ModelParameters, wheel) -> tuple[int, ...]:
    from wheelrail.core.roughness import covers

    lines = window_lines(roughness, params) if traits.lateral_window else tuple(int(n) for n in roughness.line_numbers)
    if wheel is None:
        return lines
    need = _patch_room(params, params.run.element_size) if traits.lateral_window else 0.0
    y_of = {int(n): float(y) for n, y in zip(roughness.line_numbers, roughness.y, strict=True)}
    return tuple(n for n in lines if covers(wheel, y_of[n] - need, y_of[n] + need))


def _wheel_across(wheel, rough, traits: ModelTraits, line: int, params: ModelParameters, grid, wanted):
    """The wheel set at the lateral positions of the rail's rows ``wanted`` (line numbers of the rail's model
    grid ``grid``), on the longitudinal model grid: (wheel rows as a set, the indices of ``wanted`` kept).

    One-line models: the rail line's position must lie within the wheel's data. A lateral window keeps the
    rows the wheel has data for; the patch's room on each side of the line must be among them.
    """
    from wheelrail.core.roughness import at_lateral_positions, covers, lateral_extent_mm, to_model_grid

    dx = params.run.element_size
    y_line = float(rough.y[rough.row_of_line(line)])
    extent = lateral_extent_mm(wheel)

    paired = "the wheel set is paired with the rail set by lateral position"
    if not traits.lateral_window and not covers(wheel, y_line, y_line):
        raise _line_error(
            f"the rail set's line lies at y = {y_line * 1e3:g} mm, where the wheel set has no data ({extent})",
            line,
            _run_lines(rough, traits, params, wheel),
            paired,
        )
    need = _patch_room(params, dx)
    if traits.lateral_window and not covers(wheel, y_line - need, y_line + need):
        raise _line_error(
            f"the rail set's line (y = {y_line * 1e3:g} mm) is too close to the side of the wheel roughness data "
            f"({extent}) for 3d: the contact patch at {params.contact.preload / 1e3:g} kN needs {need * 1e3:g} mm "
            "of the wheel's data on each side of its line",
            line,
            _run_lines(rough, traits, params, wheel),
            paired,
        )
    y_rows = np.array([grid.y[grid.row_of_line(int(n))] for n in wanted])
    keep = np.flatnonzero([covers(wheel, y, y) for y in y_rows])
    return at_lateral_positions(to_model_grid(wheel, dx), y_rows[keep]), keep


def check_roughness_pair(rail, wheel) -> None:
    """Combined roughness takes a rail set and a wheel set: a set of the other kind is one WheelrailError."""
    if wheel.kind != "wheel":
        raise WheelrailError(
            f"the wheel roughness is a {wheel.kind} set (kind: {wheel.kind}); give a wheel set, "
            "or give this set as the rail roughness"
        )
    if rail.kind != "rail":
        raise WheelrailError(
            f"with a wheel roughness, the rail roughness must be a rail set, got a {rail.kind} "
            "set (kind: wheel); give it as the wheel roughness"
        )


def roughness_along_track(
    rough, traits: ModelTraits, line: int, params: ModelParameters, length: float | None, wheel=None
) -> TrackRoughness:
    """Step 2: the chosen line (or lateral window) on the model grid, long enough for the run and its margins.

    ``wheel`` (a wheel set, optional) is added to the rail set ``rough``: r = r_rail + r_wheel, heights
    positive where a surface stands out (so a bump on either pushes wheel and rail together). The surfaces
    are paired where they touch, by lateral position: ``line`` is the rail set's line, and the wheel set is
    interpolated across onto the lateral positions of the rail's rows (between its own two neighbouring
    lines), never extrapolated: a line outside the wheel's data is refused, and a 3D window keeps the rows
    the wheel has data for (the patch's room on each side must be among them; see :func:`run_lines`). The
    wheel's lines repeat with its circumference along the track (its sample 0 at the start of the rail data).
    """
    from wheelrail.core.roughness import lines_along_track

    dx = params.run.element_size
    margin = run_margin(dx, params)
    if wheel is not None:
        check_roughness_pair(rough, wheel)
    grid, wanted, window_y, centre_row = _rows_of(rough, traits, line, params)
    if wheel is not None:
        wheel_rows, keep = _wheel_across(wheel, rough, traits, line, params, grid, wanted)
        wanted, window_y = [wanted[i] for i in keep], window_y[keep]
        centre_row = int(np.flatnonzero(keep == centre_row)[0])
    if length is None:
        length = usable_length(rough, dx, params)
    length = real("run length", length, "m")
    n_steps = int(round(length / dx))
    if n_steps < 1:
        raise WheelrailError(f"run length {length} m is shorter than one element ({dx} m)")
    total_length = margin + n_steps * dx + margin
    if not grid.periodic and 2 * margin + dx > grid.x[-1] + 1e-12:  # not even one step fits: no length to offer
        raise WheelrailError(
            f"the {grid.x[-1]:g} m of rail roughness data hold no run at an element size of {dx:g} m: the "
            f"window margins take {margin:g} m at each end",
            parameter="element_size",
            value=dx,
            unit="m",
        )
    if not grid.periodic and total_length > grid.x[-1] + 1e-12:
        raise WheelrailError(
            f"with the {margin * 1e3:.0f} mm window margins at each end the run needs more than the "
            f"{grid.x[-1]:g} m of rail roughness data",
            parameter="length",
            value=length,
            unit="m",
            maximum=math.floor((grid.x[-1] - 2 * margin) / dx + 1e-9) * dx,
        )
    lines = lines_along_track(grid, wanted, total_length, dx)
    if wheel is not None:
        lines = lines + lines_along_track(wheel_rows, wheel_rows.line_numbers, total_length, dx)
    if not np.all(np.isfinite(lines)):
        raise WheelrailError("roughness contains NaN or infinite heights")
    return TrackRoughness(
        lines=lines,
        centre_row=centre_row,
        window_y=window_y,
        first=int(round(margin / dx)),
        n_steps=n_steps,
        element_size=dx,
    )


@dataclass
class History:
    """Step 3: the loop's arrays (history index j = n_hist + s; s counts the run-in too).

    The track part (``force``, ``lo``, ``hi``, ``frac``, ``weights``, ``acc``) and the wheel part (``phi``,
    ``gamma0``, ``gamma1``, ``state``) are also held as the tuples ``track`` and ``wheel`` that the compiled
    kernels take. ``xi_w0`` (static equilibrium, step 4) and the ``static_approach`` it stands on are set last.
    """

    dt: float
    n_steps: int
    n_run_in: int
    n_hist: int  # lags before the first step (history prefilled with P)
    force: np.ndarray  # (n_hist + n_run_in + n_steps,)
    acc: np.ndarray  # rail displacement due to earlier forces, per history index (+ n_lags spare)
    lo: np.ndarray  # excitation positions below and above each history index's rail position
    hi: np.ndarray
    frac: np.ndarray
    weights: np.ndarray  # (positions, lags) first-order-hold weights of the moving Green's functions
    phi: np.ndarray  # wheel's discrete-time system (wheel_discrete_system)
    gamma0: np.ndarray
    gamma1: np.ndarray
    state: np.ndarray
    ramp: np.ndarray  # (n_total,) roughness fade-in factor
    start_index: np.ndarray  # (n_total,) sample index of the wheel centre in the roughness lines
    xi_w0: float = 0.0
    static_approach: float = 0.0  # the model's static approach delta(P), m (static_equilibrium: xi_w0's part)
    bay: int | None = None  # steps per sleeper bay (steady_start.bay_steps), None if not a whole number
    steady: bool = False  # the run starts from the moving load's steady state (no fade-in; steady_start)
    phases: tuple | None = None  # steady: (lo, hi, frac) of the bay's phases, index n_hist + k for phase k

    @property
    def n_total(self) -> int:
        return self.n_run_in + self.n_steps

    @cached_property
    def track(self) -> tuple:
        return (self.force, self.lo, self.hi, self.frac, self.weights, self.acc)

    @cached_property
    def wheel(self) -> tuple:
        return (self.phi, self.gamma0, self.gamma1, self.state)


def _fade_in(n_run_in: int, n_total: int) -> np.ndarray:
    ramp = np.ones(n_total)
    if n_run_in:
        fade = np.arange(n_run_in) / max(1, n_run_in // 2)
        ramp[:n_run_in] = np.where(fade < 1, 0.5 - 0.5 * np.cos(np.pi * np.minimum(fade, 1)), 1.0)
    return ramp


def _bay_positions(x: np.ndarray, spacing: float, n_positions: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows (``track.bay_rows``) below and above rail positions ``x`` (m) and the upper's weight: lo, hi, frac."""
    pos = np.mod(x, spacing) / spacing * n_positions
    lo = np.floor(pos).astype(np.int64) % n_positions
    return lo, (lo + 1) % n_positions, pos - np.floor(pos)


def check_step_stability(params: ModelParameters, weights: np.ndarray, wheel_system: tuple) -> float:
    """The coupled step's period-two mode (z = -1) must be damped: with the contact's compliance 1/k_H at the
    preload (k_H = 1.5 P / delta), rail and wheel's sampled compliance at the Nyquist frequency H(-1) (the weights
    at every position in the bay, alternating in sign, and the wheel's discrete system) must leave
    1/k_H + H(-1) > 0 (``tests/physics/test_stability.py``: where it is negative the implicit update diverges
    with period two steps). On the accepted tracks and speeds it holds with a margin (k_H (1/k_H + H(-1)) of
    0.34-0.85, ``validation/step_stability.py``); a track whose supports ring longer than the responses the loop
    keeps could break it, and is refused here rather than run. Returns that margin, k_H (1/k_H + H(-1))."""
    phi, gamma0, gamma1 = wheel_system
    rail = float(np.min(weights @ (-1.0) ** np.arange(weights.shape[1])))
    wheel = float(np.linalg.solve(-np.eye(len(phi)) - phi, gamma0 - gamma1)[1])
    stiffness = 1.5 * params.contact.preload / params.contact.hertz_approach()
    margin = 1.0 + stiffness * (rail + wheel)
    if not margin > 0.0:
        raise WheelrailError(
            f"on this track at {params.run.speed * 3.6:g} km/h the time stepping would be unstable (its period-two "
            f"mode undamped: margin {margin:.2f}): the track's supports ring longer than the responses the loop "
            "keeps; raise the pad or ballast damping, or the speed"
        )
    return margin


def history_arrays(
    track_roughness: TrackRoughness,
    params: ModelParameters,
    run_in_length: float,
    track_numerics: TrackNumerics | None = None,
    wheel_system: tuple | None = None,
    steady: bool = False,
) -> History:
    """Step 3: Green's functions and wheel system, positions in the bay, the preload's force history (eqs. 1-2).

    ``wheel_system``: the wheel's ``(Phi, Gamma0, Gamma1)``, state 1 the contact's displacement (default the paper's
    2-DOF wheel, ``wheel_discrete_system``; ``modal_wheel.time_domain.modal_wheel_system`` gives the modal wheel's).

    The rail displacement that history causes (``acc``) is left at zero: the interaction loop, which owns the
    compiled eq. 2, scatters it before the first step (``wheelrail.core.interaction.prepare_run``). ``steady``:
    the run starts from the moving load's steady state on the gap of step 0 (``steady_start``), so the run-in
    keeps the roughness under step 0 as it is (no fade-in); else it is faded in from the preload at rest."""
    from wheelrail.core.steady_start import bay_steps
    from wheelrail.core.track import moving_weights
    from wheelrail.core.wheel import wheel_discrete_system

    dx, dt = params.run.element_size, params.run.time_step
    # the weights alone, cached per speed and step: a cached run never reads the stationary responses
    weights = moving_weights(params.run.speed, dt, params.track, track_numerics)
    n_lags = weights.shape[1]
    phi, gamma0, gamma1 = wheel_discrete_system(params.wheel, dt) if wheel_system is None else wheel_system
    check_step_stability(params, weights, (phi, gamma0, gamma1))
    n_steps = track_roughness.n_steps
    n_run_in = int(round(run_in_length / dx))
    n_hist = n_lags
    n_total = n_run_in + n_steps
    # rail position of history index j (sleeper at x = 0 of the roughness data)
    x_hist = track_roughness.x_start + (np.arange(n_hist + n_total) - n_hist - n_run_in) * dx
    spacing = params.track.support.sleeper_spacing
    lo, hi, frac = _bay_positions(x_hist, spacing, len(weights))
    bay = bay_steps(spacing, dx)
    phases = None  # steady: one bay of phases from index n_hist on, however short the run (steady_start)
    if steady:
        phases = _bay_positions(track_roughness.x_start + (np.arange(bay) - n_run_in) * dx, spacing, len(weights))
    first = track_roughness.first
    history = History(
        dt=dt,
        n_steps=n_steps,
        n_run_in=n_run_in,
        n_hist=n_hist,
        force=np.full(n_hist + n_total, params.contact.preload),
        acc=np.zeros(n_hist + n_total + n_lags),
        lo=lo,
        hi=hi,
        frac=frac,
        weights=weights,
        phi=phi,
        gamma0=gamma0,
        gamma1=gamma1,
        state=np.zeros(len(phi)),
        ramp=np.ones(n_total) if steady else _fade_in(n_run_in, n_total),
        start_index=np.concatenate([np.full(n_run_in, first), first + np.arange(n_steps)]).astype(np.int64),
        bay=bay,
        steady=steady,
        phases=phases,
    )
    return history


def model_inputs(track_roughness: TrackRoughness, history: History, params: ModelParameters) -> ModelInputs:
    """What the contact model is given to prepare the run: the roughness on the model grid, its window and, at
    every step, the sample under the wheel and the run-in's fade-in."""
    dx = params.run.element_size

    def position_of(s: int) -> float:
        return track_roughness.x_start + (s - history.n_run_in) * dx

    return ModelInputs(
        params=params,
        element_size=dx,
        lines=track_roughness.lines,
        centre_row=track_roughness.centre_row,
        window_y=track_roughness.window_y,
        half_x=window_half_elements(params)[0],
        start_index=history.start_index,
        ramp=history.ramp,
        position_of=position_of,
    )


def static_equilibrium(static_approach: float, preload: float, weights: np.ndarray) -> float:
    """Step 4: wheel position xi_W0 at rest: the model's static approach delta(P) above the bay-averaged
    static rail deflection under the preload (eq. 1's xi_S(P)), m."""
    return static_approach + preload * float(np.mean(weights.sum(axis=1)))


def interaction_wheel(wheel, params) -> tuple[tuple | None, str, dict | None]:
    """What ``prepare_run``'s ``wheel_system`` gives the loop and records in the run's header:
    ``(system, wheel_model, profile description)``.

    ``wheel``: None (the paper's 2-DOF wheel: ``(None, "2dof", None)``), a modal wheel's cross-section (a
    ``WheelProfile`` or ``OutlineProfile``: its clamped modes to 10 kHz, n = 0..10, cached as ``wheel_modes``,
    as ``modal_wheel.time_domain.modal_wheel_system`` at the run's time step, recorded as ``"modal"`` with
    ``profile.describe()``) or a ``(Phi, Gamma0, Gamma1)`` built by the caller (recorded as ``"given"``: its wheel
    is not known here).
    """
    if wheel is None:
        return None, "2dof", None
    from wheelrail.core.modal_wheel.modes import wheel_modes
    from wheelrail.core.modal_wheel.profile import OutlineProfile, WheelProfile
    from wheelrail.core.modal_wheel.time_domain import modal_wheel_system

    if isinstance(wheel, WheelProfile | OutlineProfile):
        return modal_wheel_system(wheel_modes(wheel), params.wheel, params.run.time_step), "modal", wheel.describe()
    return wheel, "given", None
