"""Study plans: the named studies (``STUDIES``) as lists of :class:`RunSpec` and the function that turns
their summaries into :class:`Table` objects (paper Figs 10-14, 16, 17 and 11)."""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from wheelrail.core.engine.track_lines import run_lines
from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.ranges import check_wheel_circumference
from wheelrail.core.models import AVERAGE_FILTER_MODEL, BEDDING_MODEL, HALFSPACE_MODEL, WINKLER_FILTER_MODEL
from wheelrail.core.parameters import KMH, ContactParameters, ModelParameters
from wheelrail.core.spectra.force import check_spectrum_length
from wheelrail.core.spectra.levels import contact_filter, level_difference, mean_level
from wheelrail.core.study.specs import (
    HALF_WHEEL_MASS,
    LOW_RESOLUTION_LINES_MM,
    PAPER_LINES,
    PAPER_SPEEDS_KMH,
    REFERENCE_MODEL,
    STUDIES,
    RunSpec,
    RunSummary,
    checked_numerics,
    one_line_models,
    roughness_digest,
)
from wheelrail.core.study.tables import Table

if TYPE_CHECKING:  # the roughness package is imported when a set is read
    from wheelrail.core.roughness import RoughnessLike


@dataclass(frozen=True, kw_only=True)
class SetInfo:
    """A roughness set as used by a study: source, label, digest, lines, default length."""

    source: RoughnessLike
    label: str
    digest: str
    kind: str
    line_numbers: tuple[int, ...]
    lines: tuple[int, ...]  # the paper's lines -3..3 present in the set
    length: float | None
    wheel: SetInfo | None = None  # the wheel set added to this (rail) set in every run, if any


@dataclass(frozen=True, kw_only=True)
class StudyPlan:
    """A named study: its run specs, and how to turn their summaries into tables and figures."""

    name: str
    sets: tuple[SetInfo, ...]
    specs: tuple[RunSpec, ...]
    tabulate: Callable[[dict[str, RunSummary]], list[Table]]
    length: float | None
    params: ModelParameters = field(default_factory=ModelParameters)  # of every run, but for what the study varies
    wheel_set: SetInfo | None = None  # the wheel set added to every set (combined roughness), if any
    tracks: tuple = ()  # the tracks the runs are on (the track study: several; the others: params.track)
    impact: object = None  # the impact study's ImpactSweep (irregularity cases, models, speeds); else None
    track_numerics: object = None  # the TrackNumerics of every run (None: the default)
    # the tabulation's own work that needs no run (each track's noise chain: a second or two of CPU a track), done
    # beside the runs when the study has workers to spare (runner.run_study); the tabulation then finds it cached
    beside: tuple[Callable[[], object], ...] = ()

    @property
    def speed(self) -> float:
        """The study's speed, m/s (``params.run.speed``)."""
        return self.params.run.speed

    @property
    def contact(self) -> ContactParameters:
        """The contact of every run (``params.contact``)."""
        return self.params.contact


def _set_info(
    source, length: float | None, contact: ContactParameters, wheel: SetInfo | None = None, element_size: float = 1e-3
) -> SetInfo:
    rough = _loaded(source)
    label = _label(source, rough)
    if wheel is not None and rough.kind != "rail":
        raise WheelrailError(
            f"with the wheel set {wheel.label}, every set must be a rail set; {label} is a "
            f"{rough.kind} set: give it as the wheel set, or run it without one"
        )
    numbers = tuple(int(v) for v in rough.line_numbers)
    lines = tuple(v for v in PAPER_LINES if v in numbers)
    if wheel is not None:  # the lines the wheel set has data at (paired by lateral position)
        from wheelrail.core.roughness import lateral_extent_mm

        wheel_rough = _loaded(wheel.source)
        covered = run_lines(rough, REFERENCE_MODEL, wheel=wheel_rough)
        lines = tuple(v for v in lines if v in covered)
        if not lines:
            raise WheelrailError(
                f"no data at the lateral positions of {label}'s lines {PAPER_LINES[0]} to "
                f"{PAPER_LINES[-1]}; its data span {lateral_extent_mm(wheel_rough)}",
                Blame(
                    "wheel_set",
                    wheel.label,
                    argument="wheel_set",
                    reason="the wheel set is paired with the rail set by lateral position",
                ),
            )
    length = _run_length(rough, label, length, contact, element_size)
    return SetInfo(
        source=source,
        label=label,
        digest=roughness_digest(rough),
        kind=rough.kind,
        line_numbers=numbers,
        lines=lines,
        length=length,
        wheel=wheel,
    )


def _loaded(source):
    from wheelrail.core.roughness import RoughnessSet, load_roughness

    return source if isinstance(source, RoughnessSet) else load_roughness(source)


def _wheel_info(source) -> SetInfo:
    """The wheel set of combined-roughness runs (a wheel set: checked with each rail set)."""
    rough = _loaded(source)
    numbers = tuple(int(v) for v in rough.line_numbers)
    return SetInfo(
        source=source,
        label=_label(source, rough),
        digest=roughness_digest(rough),
        kind=rough.kind,
        line_numbers=numbers,
        lines=tuple(v for v in PAPER_LINES if v in numbers),
        length=None,
    )


def _label(source, rough) -> str:
    """A set's short name in tables: its bundled name or file stem (an object: its description's start)."""
    from wheelrail.core.roughness import RoughnessSet

    if isinstance(source, RoughnessSet):
        label = (rough.description.splitlines()[0][:40] if rough.description else "roughness") or "roughness"
    else:
        text = str(source)
        label = Path(text).stem if (os.sep in text or text.endswith((".csv", ".npz"))) else text
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", label).strip("-") or "roughness"


def _run_length(
    rough, label: str, length: float | None, contact: ContactParameters, element_size: float
) -> float | None:
    """The run length of a set: ``length`` checked against the rail data every model can run (the
    interaction's :func:`~wheelrail.core.engine.track_lines.usable_length` at the study's element size, m), or by
    default all of it; wheel data (periodic): ``length`` as given, None for one circumference."""
    from wheelrail.core.engine.track_lines import run_margin, usable_length

    if rough.periodic:
        return length
    try:
        usable = usable_length(rough, element_size, ModelParameters(contact=contact))
    except WheelrailError as error:
        raise WheelrailError(f"{label}: {error}") from None
    if length is None:
        return usable
    if length > usable + 1e-9:
        margin = run_margin(element_size, ModelParameters(contact=contact))
        raise WheelrailError(
            f"longer than the rail data of {label} less the {margin * 1e3:g} mm margins every model keeps",
            Blame("length", length, unit="m", maximum=usable),
        )
    return length


def _params(base: ModelParameters, speed: float | None = None, wheel_mass: float | None = None) -> ModelParameters:
    """The study's parameters ``base`` at another speed (m/s) or wheel mass (kg), where a study varies them."""
    params = base if speed is None else replace(base, run=replace(base.run, speed=speed))
    return params if wheel_mass is None else replace(params, wheel=replace(params.wheel, unsprung_mass=wheel_mass))


def _spec(info: SetInfo, model: str, params: ModelParameters, line: int = 0, **extra) -> RunSpec:
    if info.wheel is not None:
        extra.update(wheel_source=info.wheel.source, wheel_label=info.wheel.label, wheel_digest=info.wheel.digest)
    return RunSpec(
        source=info.source,
        set_label=info.label,
        set_digest=info.digest,
        model=model,
        line=line,
        params=params,
        length=info.length,
        **extra,
    )


def _column(line: int) -> str:
    return f"line_{line}_db"


def plan_study(
    name: str,
    sets: Sequence,
    *,
    params: ModelParameters | Sequence[ModelParameters] | None = None,
    length: float | None = None,
    wheel_set=None,
    track_numerics=None,
) -> StudyPlan:
    """Build a named study's run specs and table builder.

    Parameters
    ----------
    name : str
        One of ``STUDIES``.
    sets : sequence
        Roughness sets (bundled names, CSV/NPZ paths or ``RoughnessSet``); each gives its own panel.
    params : ModelParameters or sequence of them, optional
        The parameters of every run, as ``prepare_run`` takes them (default: the paper's), but for what the
        study varies: the speed ``params.run.speed`` (m/s; for ``speeds`` the reference speed of the
        half-mass case), the contact (material, preload, geometry: e.g.
        ``ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30)`` for an elliptic patch), the track
        and the wheel; e.g. ``wheelrail.core.inputs.declared.model_parameters({"pad_stiffness": 60e6})``. The ``track``
        study takes several that differ in their track only: each is a track of the study. The ``impact`` study
        takes a :class:`~wheelrail.core.study.impact_plan.ImpactSweep` (the irregularity cases, models and speeds)
        or one ModelParameters whose irregularities are its one case.
    length : float, optional
        Run length, m. Default: the whole set (rail: the data less the largest window margin, the same for
        every model; wheel: one circumference).
    wheel_set : bundled name, CSV/NPZ path or RoughnessSet, optional
        A wheel set added to every (rail) set in every run: the combined roughness r_rail + r_wheel
        (``simulate(wheel_roughness=...)``, paired by lateral position); a line mean or lateral lines of a
        study are taken of both sets at the rail set's lateral positions.
        Its label and digest are part of every run key. Default: a smooth wheel (the paper's case).
    track_numerics : TrackNumerics, optional
        The track's numerics of every run (``prepare_run``'s) and of the tables' noise chains (their
        frequency-domain fields); part of every run key when not the default. Default ``TrackNumerics()``.

    Returns
    -------
    StudyPlan
        The runs (:class:`RunSpec`) and how their spectra become the study's tables.

    Raises
    ------
    WheelrailError
        For an unknown study, no sets, a length that is not positive, or a set or parameters the study cannot
        use.

    See Also
    --------
    run_study : plans, runs and tabulates.
    """
    if name not in STUDIES:
        raise WheelrailError(f"unknown study {name!r}; choose one of {', '.join(STUDIES)}")
    sweep = None
    if name == "impact":  # the irregularity cases, models and speeds (core.study.impact_plan)
        from wheelrail.core.study.impact_plan import impact_sweep

        sweep = impact_sweep(params)
        params = sweep.params
    params, tracks = study_parameters(name, params)
    contact = params.contact
    if length is not None and not (isinstance(length, int | float) and math.isfinite(length) and length > 0):
        raise WheelrailError(f"length must be a positive number of m, got {length!r}")
    if not sets:
        raise WheelrailError("a study needs at least one roughness set")
    wheel = None if wheel_set is None else _wheel_info(wheel_set)
    if wheel is not None and wheel.kind != "wheel":
        raise WheelrailError(
            f"the wheel set {wheel.label} is a {wheel.kind} set (kind: {wheel.kind}); give a wheel "
            "set as the wheel set, and a rail set as the set"
        )
    infos = tuple(_set_info(source, length, contact, wheel, params.run.element_size) for source in sets)
    if wheel is not None:  # it goes round the wheel of every run (inputs/ranges.py), checked before any run
        check_wheel_circumference(_loaded(wheel.source).length, contact.radius_along, wheel.label)
    labels = [info.label for info in infos]
    if len(set(labels)) != len(labels):
        raise WheelrailError(f"roughness sets must have distinct names, got {', '.join(labels)}")
    numerics = checked_numerics(track_numerics)
    spec_of = partial(_spec, track_numerics=numerics)  # every run on the same numerics
    if name == "track":
        from wheelrail.core.study.track_plan import plan_track

        specs, tabulate = plan_track(infos, params, tracks, spec_of)
    elif sweep is not None:
        from wheelrail.core.study.impact_plan import plan_impact

        specs, tabulate = plan_impact(infos, sweep, spec_of, _params)
    else:
        specs, tabulate = _BUILDERS[name](infos, params, spec_of)
    _check_durations(specs, infos)
    noise = name in ("track", "impact", "noise")  # their tables go through each track's noise chain
    beside = tuple(partial(_noise_chain, replace(params, track=t), numerics) for t in tracks[::-1]) if noise else ()
    return StudyPlan(
        name=name,
        sets=infos,
        specs=tuple(specs),
        tabulate=tabulate,
        length=length,
        params=params,
        wheel_set=wheel,
        tracks=tracks,
        impact=sweep,
        track_numerics=numerics,
        # the last track first: where the chains' cache keeps fewer than all, it keeps those the tables ask first;
        # Fig. 10's reference filters import scipy.special
        beside=beside if name != "filters" else (_import_reference_filters,),
    )


def _import_reference_filters() -> None:
    """The reference filters' modules (scipy.special), imported before Fig. 10's tables are made."""
    import wheelrail.core.reference_filters  # noqa: F401


def _noise_chain(params: ModelParameters, track_numerics=None) -> None:
    """The track's noise chain the study's tables use (``noise.twins.track_noise_model`` on the runs' numerics,
    kept in this process)."""
    from wheelrail.core.noise.twins import chain_numerics, track_noise_model

    track_noise_model(params, chain_numerics(track_numerics))


def study_parameters(name: str, params) -> tuple[ModelParameters, tuple]:
    """A study's parameters and its tracks: ``params`` one ModelParameters (default: the paper's; its track the
    one track), or, for the ``track`` study, several that differ in their track only (each a track)."""
    if params is None or isinstance(params, ModelParameters):
        params = ModelParameters() if params is None else params
        return params, (params.track,)
    many = tuple(params) if isinstance(params, list | tuple) else ()
    if not many or not all(isinstance(p, ModelParameters) for p in many):
        raise WheelrailError("params must be a wheelrail.core.parameters.ModelParameters (a sequence of them: tracks)")
    if name != "track" and len(many) > 1:
        raise WheelrailError(f"the {name} study runs on one set of parameters; several tracks: the track study")
    base = many[0]
    if any(replace(p, track=base.track) != base for p in many):
        raise WheelrailError("the parameters of a track study may differ in their track only")
    tracks = tuple(p.track for p in many)
    if len(set(tracks)) != len(tracks):
        raise WheelrailError("the tracks of a track study must differ from each other")
    from wheelrail.core.study.track_plan import check_track_count

    check_track_count(tracks)  # before any work: bounded by a limit and by the disk cache
    return base, tracks


def _check_durations(specs: Sequence[RunSpec], infos: Sequence[SetInfo]) -> None:
    """Every run must be long enough for a force spectrum (``spectra.force.check_spectrum_length``)."""
    from wheelrail.core.roughness import RoughnessSet, load_roughness

    circumference = {}
    for info in infos:
        if info.length is None:
            rough = info.source if isinstance(info.source, RoughnessSet) else load_roughness(info.source)
            circumference[info.label] = rough.length
    for spec in specs:
        length = spec.length if spec.length is not None else circumference[spec.set_label]
        check_spectrum_length(length, spec.params.run.speed, spec.params.run.element_size)


def _levels(summaries, spec: RunSpec) -> np.ndarray:
    return summaries[spec.key].levels


def _centres(summaries, spec: RunSpec) -> np.ndarray:
    return summaries[spec.key].band_centres


def _reference_columns(params: ModelParameters, centres: np.ndarray) -> dict[str, np.ndarray]:
    """The reference filters (CNOSSOS-EU A3, analytic) for the runs' load, geometry and speed on the bands of the
    force spectra, as ``ref_<name>_db`` columns (NaN where a filter is not defined)."""
    from wheelrail.core.reference_filters import run_reference_filters

    refs = run_reference_filters(params.contact, params.run.speed, (float(centres[0]), float(centres[-1])))
    if not np.allclose(refs.frequency_bands.centres, centres, rtol=1e-9):
        raise WheelrailError("reference filters: the bands differ from those of the force spectra")
    return {
        f"ref_{name.replace('-', '_')}_db": np.asarray(values, dtype=float)
        for name, values in refs.by_frequency.items()
    }


def _plan_filters(infos, params, spec_of):
    models = one_line_models()  # the registry's, plug-ins included; the reference (hertz) among them
    specs, layout = [], {}
    for info in infos:
        one_line = {(model, line): spec_of(info, model, params, line) for model in models for line in info.lines}
        three_d = spec_of(info, HALFSPACE_MODEL, params, 0)
        layout[info.label] = (info, one_line, three_d)
        specs += [*one_line.values(), three_d]

    def tabulate(summaries):
        tables, references = [], {}  # the reference filters by band range: the same for sets on the same bands
        for label, (info, one_line, three_d) in layout.items():
            centres = _centres(summaries, three_d)
            level = {model: [_levels(summaries, one_line[model, line]) for line in info.lines] for model in models}
            l3d = _levels(summaries, three_d)
            three_d_column = f"{HALFSPACE_MODEL.replace('-', '_')}_db"
            spectra = {three_d_column: l3d, **{f"{m.replace('-', '_')}_db": mean_level(level[m]) for m in models}}
            filters = {three_d_column: mean_level([contact_filter(l3d, h) for h in level[REFERENCE_MODEL]])}
            for model in (m for m in models if m != REFERENCE_MODEL):
                filters[f"{model.replace('-', '_')}_db"] = mean_level(
                    [contact_filter(v, h) for v, h in zip(level[model], level[REFERENCE_MODEL], strict=True)]
                )
            bands = tuple(float(f) for f in centres)
            if bands not in references:
                references[bands] = _reference_columns(params, centres)
            filters.update({column: values.copy() for column, values in references[bands].items()})
            lines = f"lines {info.lines[0]}..{info.lines[-1]}"
            tables.append(
                Table(
                    name=f"fig10_{label}_force_levels",
                    figure="10",
                    panel=label,
                    columns=spectra,
                    title=f"{label}: contact-force levels, dB re 1 N (one-line models: mean of {lines})",
                    band_centres=centres,
                )
            )
            tables.append(
                Table(
                    name=f"fig10_{label}_contact_filters",
                    figure="10",
                    panel=label,
                    columns=filters,
                    title=f"{label}: contact filter L - L_hertz, dB (mean over {lines}); ref_*: "
                    f"CNOSSOS-EU A3 and analytic filters for the run's load and wheel",
                    band_centres=centres,
                )
            )
        return tables

    return specs, tabulate


_PAIRS = (  # Figs 12-14: (figure, model a, model b)
    ("12", HALFSPACE_MODEL, BEDDING_MODEL),
    ("13", BEDDING_MODEL, WINKLER_FILTER_MODEL),
    ("14", BEDDING_MODEL, AVERAGE_FILTER_MODEL),
)


def _plan_line_spread(infos, params, spec_of):
    specs, layout = [], {}
    for info in infos:
        runs = {
            (model, line): spec_of(info, model, params, line)
            for model in (BEDDING_MODEL, WINKLER_FILTER_MODEL, AVERAGE_FILTER_MODEL)
            for line in info.lines
        }
        runs[HALFSPACE_MODEL, None] = spec_of(info, HALFSPACE_MODEL, params, 0)
        layout[info.label] = (info, runs)
        specs += list(runs.values())

    def tabulate(summaries):
        tables = []
        for label, (info, runs) in layout.items():
            centres = _centres(summaries, runs[HALFSPACE_MODEL, None])
            for figure, a, b in _PAIRS:
                columns = {}
                for line in info.lines:
                    la = _levels(summaries, runs[a, None if a == HALFSPACE_MODEL else line])
                    columns[_column(line)] = level_difference(la, _levels(summaries, runs[b, line]))
                columns["mean_db"] = mean_level(columns.values())
                stem = f"{a}_minus_{b}".replace("-", "_")
                tables.append(
                    Table(
                        name=f"fig{figure}_{label}_{stem}",
                        figure=figure,
                        panel=label,
                        title=f"{label}: L_{a} - L_{b} per line and mean, dB",
                        band_centres=centres,
                        columns=columns,
                    )
                )
        return tables

    return specs, tabulate


def _plan_averaged_input(infos, params, spec_of):
    layout = {
        info.label: (
            spec_of(info, HALFSPACE_MODEL, params, 0),
            spec_of(info, BEDDING_MODEL, params, 0, averaged_lines=info.lines),
        )
        for info in infos
    }

    def tabulate(summaries):
        columns, centres = {}, None
        for label, (three_d, averaged) in layout.items():
            centres = _centres(summaries, three_d)
            columns[f"{label}_db"] = level_difference(_levels(summaries, three_d), _levels(summaries, averaged))
        return [
            Table(
                name="fig16_3d_minus_2d_averaged_input",
                figure="16",
                band_centres=centres,
                columns=columns,
                title="L_3D - L_2D,av: 2D fed with the mean of lines -3..3, dB",
            )
        ]

    return [spec for pair in layout.values() for spec in pair], tabulate


def _mm(values) -> str:
    return ", ".join(f"{v:g}" for v in values)


def _plan_lateral_resolution(infos, params, spec_of):
    layout = {}
    for info in infos:
        runs = {"original": spec_of(info, HALFSPACE_MODEL, params, 0)}
        for resolution, kept in LOW_RESOLUTION_LINES_MM.items():
            runs[resolution] = spec_of(info, HALFSPACE_MODEL, params, 0, lateral_lines_mm=kept)
        layout[info.label] = runs

    def tabulate(summaries):
        tables = []
        for resolution, kept in LOW_RESOLUTION_LINES_MM.items():
            columns, centres = {}, None
            for label, runs in layout.items():
                centres = _centres(summaries, runs["original"])
                columns[f"{label}_db"] = level_difference(
                    _levels(summaries, runs["original"]), _levels(summaries, runs[resolution])
                )
            tables.append(
                Table(
                    name=f"fig17_3d_minus_3d_{resolution}mm",
                    figure="17",
                    band_centres=centres,
                    columns=columns,
                    panel=f"{resolution} mm",
                    title=f"L_3D - L_3D,{resolution}mm (lines at {_mm(kept)} mm), dB",
                )
            )
        return tables

    return [spec for runs in layout.values() for spec in runs.values()], tabulate


def _speed_cases(speed):
    cases = [(f"{v:g}_kmh_db", v * KMH, None) for v in PAPER_SPEEDS_KMH]
    cases.append((f"{speed / KMH:g}_kmh_half_mass_db", speed, HALF_WHEEL_MASS))
    return cases


def _plan_speeds(infos, params, spec_of):
    layout = {
        info.label: {
            column: spec_of(info, BEDDING_MODEL, _params(params, v, mass), 0)
            for column, v, mass in _speed_cases(params.run.speed)
        }
        for info in infos
    }

    def tabulate(summaries):
        tables = []
        for label, runs in layout.items():
            columns = {column: _levels(summaries, spec) for column, spec in runs.items()}
            centres = _centres(summaries, next(iter(runs.values())))
            tables.append(
                Table(
                    name=f"fig11_{label}_speeds",
                    figure="11",
                    panel=label,
                    band_centres=centres,
                    columns=columns,
                    title=f"{label}: 2D on line 0, contact-force levels at several speeds, dB re 1 N",
                )
            )
        return tables

    return [spec for runs in layout.values() for spec in runs.values()], tabulate


def _plan_noise(infos, params, spec_of):
    from wheelrail.core.study.noise_plan import plan_noise

    return plan_noise(infos, params, spec_of, _params)


_BUILDERS = {
    "noise": _plan_noise,
    "filters": _plan_filters,
    "line-spread": _plan_line_spread,
    "averaged-input": _plan_averaged_input,
    "lateral-resolution": _plan_lateral_resolution,
    "speeds": _plan_speeds,
}
