"""The roughness a run meets along the track: the contact window's size, the margins, the lines a model can run
on, the rail and wheel sets paired across, and the chosen line (or window of lines) on the model grid.

:func:`track_roughness` is what ``prepare.prepare_run`` asks for: the sets read and paired
(:func:`resolve_surfaces`), the run's memory checked, then the lines laid along the track
(:func:`roughness_along_track`). :func:`usable_length` is the one rule for margins and default lengths;
:func:`run_lines` the lines the command line and the explorer offer.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.checks import real
from wheelrail.core.inputs.ranges import check_wheel_circumference
from wheelrail.core.models import ModelTraits, model_entry
from wheelrail.core.parameters import ModelParameters

if TYPE_CHECKING:  # the roughness package is imported when a set is read
    from wheelrail.core.roughness import RoughnessLike, RoughnessSet

__all__ = [
    "RUN_MARGIN",
    "WINDOW_HALF_WIDTH",
    "WINDOW_SEMI_AXES",
    "TrackRoughness",
    "check_roughness_pair",
    "roughness_along_track",
    "run_lines",
    "run_margin",
    "resolve_surfaces",
    "track_roughness",
    "usable_length",
    "window_half_elements",
    "window_lines",
    "window_width",
]

WINDOW_HALF_WIDTH = 0.012  # m: least half side of the 3D window and of the 2D bedding (2.2 a at 65 kN, R = 0.39 m)
WINDOW_SEMI_AXES = 2.2  # half side of the window in Hertz semi-axes at the preload (along and across)
RUN_MARGIN = 0.020  # m of roughness kept before the first and after the last wheel position


def window_half_elements(params: ModelParameters | None = None) -> tuple[int, int]:
    """Half sides of the 3D window (and, along the rail, of the 2D bedding), elements: (along, across).

    ``WINDOW_SEMI_AXES`` Hertz semi-axes at the preload (a along the rail, b across), never less than the
    paper's window ``WINDOW_HALF_WIDTH`` (12 mm: the roughness widens the patch and the dynamic load
    exceeds the preload; a light wheel keeps that room), so a long or a wide elliptic patch gets its own room.
    A run's discrete irregularities widen it along the rail by how far ahead of or behind the wheel's centre they
    move the contact (``irregularities.shapes.contact_reach``: over a flat the patch sits on its flanks).
    """
    params = ModelParameters() if params is None else params
    dx = params.run.element_size
    least = int(round(WINDOW_HALF_WIDTH / dx))
    a, b = params.contact.hertz_semi_axes()
    along = max(least, int(round(WINDOW_SEMI_AXES * a / dx)))
    if params.run.irregularities:
        from wheelrail.core.irregularities.shapes import contact_reach

        reach = max(contact_reach(item, params.contact.radius_along) for item in params.run.irregularities)
        along += int(math.ceil(reach / dx - 1e-9))
    return along, max(least, int(round(WINDOW_SEMI_AXES * b / dx)))


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
    """The roughness the wheel meets, on the model grid along the track.

    lines (rows, samples): the chosen line (one row) or the rows of a lateral window; ``centre_row`` is the
    chosen line; ``window_y`` the rows' lateral offsets from it, m; sample ``first`` is under the wheel at
    step 0, at ``x_start`` (m) from the start of the data; ``n_steps`` steps follow; ``half_x``: the half-length
    of a model's window along the rail (and of the bedding), elements (:func:`window_half_elements`).
    """

    lines: np.ndarray
    centre_row: int
    window_y: np.ndarray
    first: int
    n_steps: int
    element_size: float
    half_x: int

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
    blame = Blame("line", int(line), reason=reason)
    if lines and lines[-1] - lines[0] == len(lines) - 1:
        return WheelrailError(problem, blame._replace(minimum=lines[0], maximum=lines[-1]))
    words = f"only lines {', '.join(map(str, lines))} can be run" if lines else "no line can be run"
    return WheelrailError(problem, blame, advice=words)


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
    """The chosen line (or lateral window) on the model grid, long enough for the run and its margins.

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
            Blame("element_size", dx, unit="m"),
        )
    if not grid.periodic and total_length > grid.x[-1] + 1e-12:
        raise WheelrailError(
            f"with the {margin * 1e3:.0f} mm window margins at each end the run needs more than the "
            f"{grid.x[-1]:g} m of rail roughness data",
            Blame("length", length, unit="m", maximum=math.floor((grid.x[-1] - 2 * margin) / dx + 1e-9) * dx),
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
        half_x=window_half_elements(params)[0],
    )


def track_roughness(
    roughness: RoughnessLike,
    wheel_roughness: RoughnessLike | None,
    traits: ModelTraits,
    line: int,
    params: ModelParameters,
    length: float | None,
    check_memory: Callable[[float], object],
) -> tuple[TrackRoughness, str, str | None]:
    """The roughness of a run along the track and the names of its rail (or wheel) set and wheel set.

    The sets are read and paired (:func:`resolve_surfaces`); ``check_memory(length)`` is called with the run's
    length, m (:func:`usable_length` where none is given), before anything that grows with it is allocated;
    then the lines are laid along the track (:func:`roughness_along_track`).
    """
    rough, name, wheel, wheel_name = resolve_surfaces(roughness, wheel_roughness, params)
    check_memory(usable_length(rough, params.run.element_size) if length is None else length)
    return roughness_along_track(rough, traits, line, params, length, wheel=wheel), name, wheel_name
