"""The ``impact`` study: discrete irregularities swept (any irregularity input), per model and speed, the impact.

Runs: each contact model of the sweep (default: those of the noise study, :func:`impact_models`) on line 0 of each
set at each speed (default :data:`IMPACT_SPEEDS_KMH`), once per irregularity case (:class:`ImpactSweep`: each case
the run's irregularities, e.g. a wheel flat of 20, 50 and 100 mm). Each run's summary gives the peak force, the
minimum force and the steps without contact; the time without contact is those steps times the time step (to one
step). The speed at which contact is first lost is the lowest speed of the sweep with a step without contact (so
known to the sweep's spacing). From each run's force levels the TWINS-like chain of
:mod:`wheelrail.core.noise.twins` gives the A-weighted sound power per axle and the pass-by level (as ``wheelrail
noise --run``: the run's force taken as stationary, so the impact's level depends on how often it comes in the
run: a flat once per wheel turn); the slope of the sound power against speed is a least-squares line in lg v, in
dB per doubling of speed (Wu & Thompson: an impact's noise rises about 6 dB, 20 lg v, per doubling).

Tables per set: ``impact_<set>_case<k>`` (first column the speed in km/h; per model the peak and minimum force,
N, the time without contact, ms, the sound power per axle and the pass-by level, dB(A)) and
``impact_<set>_contact_loss`` (first column the case's number 1..N, then the swept inputs in their options' units;
per model the first speed with loss of contact, km/h (NaN: none in the sweep), and the noise slope, dB per
doubling). A run whose analysed record (the first 20 ms left out) holds none of its case's irregularities has no
sound power (NaN): its noise would be the roughness's alone.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.parameters import KMH, ModelParameters
from wheelrail.core.study.noise_plan import noise_models
from wheelrail.core.study.tables import Table

__all__ = [
    "IMPACT_SPEEDS_KMH",
    "MAX_IMPACT_CASES",
    "ImpactSweep",
    "impact_models",
    "impact_sweep",
    "noise_slope",
    "plan_impact",
    "swept_irregularity_inputs",
]

IMPACT_SPEEDS_KMH = (30.0, 60.0, 100.0, 140.0, 200.0)
MAX_IMPACT_CASES = 50  # irregularity cases in one impact study (each models x speeds runs)


def impact_models() -> tuple[str, ...]:
    """The impact study's default models: those of the noise study (hertz first, the other one-line models of
    the registry, then ``3d``)."""
    return noise_models()


@dataclass(frozen=True)
class ImpactSweep:
    """What the impact study sweeps: the parameters of every run ``params`` (but for the speed and the
    irregularities), the irregularity ``cases`` (each a tuple of ``WheelFlat``, ``RailJoint``, ``DippedWeld``,
    ``Squat``), the ``models`` and the ``speeds`` (m/s). Empty ``models`` or ``speeds``: the defaults
    (:func:`impact_models`, :data:`IMPACT_SPEEDS_KMH`)."""

    params: ModelParameters
    cases: tuple = ()
    models: tuple[str, ...] = ()
    speeds: tuple[float, ...] = field(default=())


def impact_sweep(params) -> ImpactSweep:
    """The impact study's sweep from ``params`` (an :class:`ImpactSweep`, or one ``ModelParameters`` whose
    irregularities are the one case), checked: at least one case, each with an irregularity, distinct cases, known
    models, positive finite speeds; one WheelrailError otherwise."""
    from wheelrail.core.models import model_entry

    if params is None or isinstance(params, ModelParameters):
        base = ModelParameters() if params is None else params
        params = ImpactSweep(base, cases=(base.run.irregularities,) if base.run.irregularities else ())
    if not isinstance(params, ImpactSweep) or not isinstance(params.params, ModelParameters):
        raise WheelrailError("the impact study takes an ImpactSweep or one ModelParameters with irregularities")
    cases = tuple(tuple(case) for case in params.cases)
    if not cases or any(not case for case in cases):
        raise WheelrailError(
            "the impact study needs an irregularity in every case: a wheel flat, a rail joint, a dipped weld or a squat"
        )
    if len(cases) > MAX_IMPACT_CASES:
        raise WheelrailError(f"{len(cases)} irregularity cases is over the limit of {MAX_IMPACT_CASES}; sweep fewer")
    if len(set(cases)) != len(cases):
        raise WheelrailError("the irregularity cases of an impact study must differ from each other")
    models = tuple(params.models) or impact_models()
    for model in models:
        model_entry(model)  # an unknown name: one WheelrailError listing the registered models
    if len(set(models)) != len(models):
        raise WheelrailError(f"each model once, got {', '.join(models)}")
    speeds = tuple(float(v) for v in params.speeds) or tuple(v * KMH for v in IMPACT_SPEEDS_KMH)
    for speed in speeds:
        if not (np.isfinite(speed) and speed > 0):
            raise WheelrailError("must be positive", Blame("speed", value=speed / KMH, unit="km/h"))
    if len(set(speeds)) != len(speeds):
        raise WheelrailError(f"each speed once, got {', '.join(f'{v / KMH:g}' for v in speeds)} km/h")
    for case in cases:  # each case's irregularities checked as RunParameters checks them
        replace(params.params, run=replace(params.params.run, irregularities=case))
    base = replace(params.params, run=replace(params.params.run, irregularities=()))
    return ImpactSweep(base, cases=cases, models=models, speeds=tuple(sorted(speeds)))


def _value(case, entry) -> float:
    """The value of an irregularity input in a case (SI), NaN where the case has no irregularity of its kind or
    the field is unset."""
    from wheelrail.core.irregularities.shapes import as_record

    for item in case:
        record = as_record(item)
        if record.get("kind") == entry.kind:
            value = record.get(entry.field)
            return float("nan") if value is None else float(value)
    return float("nan")


def swept_irregularity_inputs(cases) -> list:
    """The irregularity inputs (``core.inputs.irregular.IRREGULARITY_INPUTS``) whose value differs between
    ``cases`` (one case: those it sets)."""
    from wheelrail.core.inputs.irregular import IRREGULARITY_INPUTS

    def values(entry):
        return [_value(case, entry) for case in cases]

    if len(cases) == 1:
        return [entry for entry in IRREGULARITY_INPUTS if np.isfinite(values(entry)[0])]
    return [e for e in IRREGULARITY_INPUTS if len({repr(v) for v in values(e)}) > 1]


def case_words(case) -> str:
    """A case's irregularities in words ("flat 50 mm rounded at x = 0.5 m")."""
    from wheelrail.core.irregularities.shapes import words

    return ", ".join(words(item) for item in case)


def noise_slope(speeds_kmh, levels) -> float:
    """The least-squares slope of ``levels`` (dB) against log2 of the speed: dB per doubling of speed (NaN for
    fewer than two finite levels)."""
    v, level = np.asarray(speeds_kmh, dtype=float), np.asarray(levels, dtype=float)
    keep = np.isfinite(level) & (v > 0)
    if keep.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log2(v[keep]), level[keep], 1)[0])


def first_loss_speed(speeds_kmh, loss_steps) -> float:
    """The lowest speed with a step without contact, km/h (NaN: none)."""
    lost = [v for v, steps in zip(speeds_kmh, loss_steps, strict=True) if steps > 0]
    return float(min(lost)) if lost else float("nan")


def in_record(case, spec) -> bool:
    """Whether an irregularity of ``case`` lies in the record a run's force spectrum analyses (from the first
    ``FORCE_SKIP`` s after the run's first position, taken as its margin ``track_lines.run_margin``, to its end;
    a flat at any of its meetings): else the run's sound power has no impact in it. A run of unknown length
    (a wheel set's turn): True."""
    from wheelrail.core.engine.track_lines import run_margin
    from wheelrail.core.irregularities.shapes import WheelFlat, extent, flat_meetings
    from wheelrail.core.spectra.force import FORCE_SKIP

    if spec.length is None:
        return True
    run = spec.params.run
    start = run_margin(run.element_size, spec.params)
    first, last = start + FORCE_SKIP * run.speed, start + spec.length
    for item in case:
        if isinstance(item, WheelFlat):
            meetings = flat_meetings(item, spec.params.contact.radius_along, last)
            if any(first - 0.5 * item.length <= x <= last + 0.5 * item.length for x in meetings):
                return True
        elif extent(item)[1] >= first and extent(item)[0] <= last:
            return True
    return False


def _column(model: str) -> str:
    return model.replace("-", "_")


def plan_impact(infos, sweep: ImpactSweep, spec_of, params_of):
    """Specs and the table builder of the ``impact`` study (``spec_of(info, model, params, line)`` and
    ``params_of(params, speed)`` are the study's own helpers); ``sweep`` as :func:`impact_sweep` gives it."""
    base = sweep.params
    on_case = [replace(base, run=replace(base.run, irregularities=case)) for case in sweep.cases]
    layout = {
        info.label: {
            (model, k, v): spec_of(info, model, params_of(p, v), 0)
            for k, p in enumerate(on_case)
            for model in sweep.models
            for v in sweep.speeds
        }
        for info in infos
    }
    specs = [spec for runs in layout.values() for spec in runs.values()]

    def tabulate(summaries):
        from wheelrail.core.noise.run_noise import DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH, pass_by_level
        from wheelrail.core.noise.run_noise import sound_power_from_force as power
        from wheelrail.core.noise.twins import chain_numerics, track_noise_model

        noise_track = track_noise_model(base, chain_numerics(specs[0].track_numerics))  # on the runs' track
        speeds_kmh = np.array([v / KMH for v in sweep.speeds])
        swept = swept_irregularity_inputs(sweep.cases)
        tables = []
        for label, runs in layout.items():
            loss = {e.dest: np.array([_value(c, e) / e.shown.si for c in sweep.cases]) for e in swept}
            for model in sweep.models:
                loss[f"{_column(model)}_first_loss_speed_kmh"] = np.full(len(sweep.cases), np.nan)
                loss[f"{_column(model)}_slope_dB_per_doubling"] = np.full(len(sweep.cases), np.nan)
            for k, case in enumerate(sweep.cases):
                columns = {}
                for model in sweep.models:
                    found = [summaries[runs[model, k, v].key] for v in sweep.speeds]
                    steps = [s.loss_of_contact_steps for s in found]
                    dt = [runs[model, k, v].params.run.time_step for v in sweep.speeds]
                    chains = [power(np.append(np.asarray(s.levels, float), np.nan), noise_track) for s in found]
                    heard = [in_record(case, runs[model, k, v]) for v in sweep.speeds]
                    lwa = np.array([c["axle_dba"] if h else np.nan for c, h in zip(chains, heard, strict=True)])
                    name = _column(model)
                    columns[f"{name}_peak_force_n"] = np.array([s.force_max for s in found])
                    columns[f"{name}_min_force_n"] = np.array([s.force_min for s in found])
                    columns[f"{name}_time_without_contact_ms"] = np.array(steps) * np.array(dt) * 1e3
                    columns[f"{name}_LWA_dBA"] = lwa
                    columns[f"{name}_LpAeq_dBA"] = np.array(
                        [pass_by_level(x, DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH) for x in lwa]
                    )
                    loss[f"{name}_first_loss_speed_kmh"][k] = first_loss_speed(speeds_kmh, steps)
                    loss[f"{name}_slope_dB_per_doubling"][k] = noise_slope(speeds_kmh, lwa)
                tables.append(
                    Table(
                        name=f"impact_{label}_case{k + 1}",
                        figure="impact",
                        panel=f"{label}: {case_words(case)}",
                        band_centres=speeds_kmh,
                        columns=columns,
                        axis_name="speed_kmh",
                        title=f"{label}, line 0, {case_words(case)}: per model and speed the peak and minimum force "
                        "(N), the time without contact (ms, steps with F = 0), the sound power per axle (dB(A) re "
                        f"1 pW) and pass-by L_pAeq,Tp ({DEFAULT_TRAIN_AXLES} axles, {DEFAULT_TRAIN_LENGTH:g} m, "
                        "dB(A)), the run's force taken as stationary (nan: no irregularity in the record the "
                        "spectrum analyses, which leaves out the first 20 ms)",
                    )
                )
            tables.append(
                Table(
                    name=f"impact_{label}_contact_loss",
                    figure="impact-loss",
                    panel=label,
                    band_centres=np.arange(1.0, len(sweep.cases) + 1),
                    columns=loss,
                    axis_name="case",
                    title=f"{label}: per irregularity case (swept inputs in their options' units) and model, the "
                    "lowest speed of the sweep with loss of contact (km/h; nan: none) and the slope of the sound "
                    "power against speed (dB per doubling, least squares)",
                )
            )
        return tables

    return specs, tabulate
