"""The ``noise`` study: rolling noise against speed for the contact models and CNOSSOS-EU, and the dynamic
contact filter in the place of CNOSSOS-EU's A3.

Runs: every contact model (:func:`noise_models`: the one-line models of the registry, plug-ins included, and
``3d``) on line 0 of each set at each of :data:`NOISE_SPEEDS_KMH` (and at the study's speed).
From each run's contact-force levels (the study's run summaries: 50 Hz - 8 kHz, so the 10 kHz band is left out)
the sound power of the TWINS-like chain (:func:`wheelrail.core.noise.run_noise.sound_power_from_force`, per axle:
two wheels on two rails) and the pass-by level (40 axles, 200 m, ISO 3095 position), with the directive's wheel
(L_H,veh), and for the reference model also with the modal wheel's L_H,veh-equivalent in its place
(``hertz_modal_wheel_...``, :func:`wheelrail.core.noise.twins.with_modal_wheel`). Beside them the CNOSSOS-EU
source by the rule of :mod:`wheelrail.core.noise.cnossos_run` (one axle; track type ``mono-block-soft``, the Table G-3b
wheel diameter nearest 2R, A3 for the preload and 2R), on the same roughness: the set's line 0 as the combined
roughness (its spectrum at the speed, dB re 1 um; the directive allows measured roughness); once with A3 and once
with each model's dynamic contact filter L_F(model) - L_F(hertz) (same set, line, speed) in its place. The 10 kHz
band is left out of every column.

Tables per set: ``noise_<set>_lwa_vs_speed`` and ``noise_<set>_lpaeq_vs_speed`` (first column the speed in km/h),
``noise_<set>_filters_<V>kmh`` (per band at the study's speed: A3, every model's filter, and the CNOSSOS-EU sound
power per band with each).
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.models import HALFSPACE_MODEL
from wheelrail.core.noise.cnossos_run import CNOSSOS_TRACK_TYPE
from wheelrail.core.parameters import KMH
from wheelrail.core.study.specs import REFERENCE_MODEL, one_line_models
from wheelrail.core.study.tables import Table

NOISE_SPEEDS_KMH = (50.0, 75.0, 100.0, 140.0, 200.0, 250.0, 300.0)
MODAL_COLUMN = f"{REFERENCE_MODEL}_modal_wheel_LWA_dBA"  # the reference model with the modal wheel's transfer


def noise_models() -> tuple[str, ...]:
    """The models the study runs: the reference (hertz) first, the other one-line models of the registry (plug-ins
    included, as the ``filters`` study), then ``3d``."""
    return (REFERENCE_MODEL, *(m for m in one_line_models() if m != REFERENCE_MODEL), HALFSPACE_MODEL)


def _column(name: str) -> str:
    return name.replace("-", "_")


def _roughness_levels(info, speed: float) -> np.ndarray:
    """Line 0 of the set (plus its wheel set's line 0, if any) as the combined roughness on the 24 bands at ``speed``,
    dB re 1 um (the one-Hann-window band levels of the force spectra, NaN where the record is too short)."""
    from wheelrail.core.roughness import RoughnessSet, load_roughness
    from wheelrail.core.spectra.bands import NOISE_BAND_RANGE
    from wheelrail.core.spectra.force import force_spectrum

    def line0(source):
        rough = source if isinstance(source, RoughnessSet) else load_roughness(source)
        return rough.line(0), rough.dx

    heights, dx = line0(info.source)
    levels_m = 10 ** (np.asarray(force_spectrum(heights, dx / speed, skip=0.0, band_range=NOISE_BAND_RANGE)[1]) / 10)
    if info.wheel is not None:
        w_heights, w_dx = line0(info.wheel.source)
        levels_m = levels_m + 10 ** (
            np.asarray(force_spectrum(w_heights, w_dx / speed, skip=0.0, band_range=NOISE_BAND_RANGE)[1]) / 10
        )
    return 10 * np.log10(levels_m) + 120.0  # dB re 1 m -> dB re 1 um


def _force_24(levels: np.ndarray) -> np.ndarray:
    """Force levels of a run summary (50 Hz - 8 kHz, 23 bands) on the 24 noise bands (10 kHz: NaN)."""
    return np.concatenate([np.asarray(levels, dtype=float), [np.nan]])


def plan_noise(infos, study_params, spec_of, params_of):
    """Specs and the table builder of the ``noise`` study on the parameters ``study_params`` (its speed the study's own;
    ``spec_of(info, model, params, line)`` and ``params_of(study_params, speed)`` are the study's own helpers)."""
    speed, contact = study_params.run.speed, study_params.contact
    speeds = sorted({*NOISE_SPEEDS_KMH, round(speed / KMH, 9)})
    models = noise_models()
    layout = {
        info.label: (
            info,
            {(model, v): spec_of(info, model, params_of(study_params, v * KMH), 0) for model in models for v in speeds},
        )
        for info in infos
    }
    specs = [spec for _, runs in layout.values() for spec in runs.values()]

    def tabulate(summaries):
        from wheelrail.core.noise.cnossos import contact_filter_a3
        from wheelrail.core.noise.cnossos_run import cnossos_beside
        from wheelrail.core.noise.run_noise import sound_power_from_force
        from wheelrail.core.noise.twins import chain_numerics, track_noise_model, with_modal_wheel

        numerics = chain_numerics(specs[0].track_numerics)  # the runs' track
        track = track_noise_model(study_params, numerics)
        # the modal wheel's L_H,veh-equivalent in the place of the table
        modal = with_modal_wheel(track, study_params, numerics=numerics)
        tables = []
        for label, (info, runs) in layout.items():
            lwa = {f"{_column(m)}_LWA_dBA": np.full(len(speeds), np.nan) for m in models}
            lwa[MODAL_COLUMN] = np.full(len(speeds), np.nan)
            lwa["cnossos_a3_LWA_dBA"] = np.full(len(speeds), np.nan)
            lwa.update(
                {
                    f"cnossos_{_column(m)}_filter_LWA_dBA": np.full(len(speeds), np.nan)
                    for m in models
                    if m != REFERENCE_MODEL
                }
            )
            per_band = {}
            for i, v in enumerate(speeds):
                force = {m: _force_24(summaries[runs[m, v].key].levels) for m in models}
                for m in models:
                    lwa[f"{_column(m)}_LWA_dBA"][i] = sound_power_from_force(force[m], track)["axle_dba"]
                lwa[MODAL_COLUMN][i] = sound_power_from_force(force[REFERENCE_MODEL], modal)["axle_dba"]
                roughness = (f"{label} line 0", _roughness_levels(info, v * KMH))
                params = params_of(study_params, v * KMH)
                a3 = contact_filter_a3(contact.preload, 2 * contact.radius_along, v * KMH)
                a3[-1] = np.nan  # 10 kHz: left out as in the model columns (run summaries stop at 8 kHz)
                base = cnossos_beside(params, *roughness, contact_filter=("A3", a3))
                lwa["cnossos_a3_LWA_dBA"][i] = base.total_dba
                filters = {m: force[m] - force[REFERENCE_MODEL] for m in models if m != REFERENCE_MODEL}
                with_filter = {
                    m: cnossos_beside(params, *roughness, contact_filter=(f"{m} dynamic filter", f))
                    for m, f in filters.items()
                }
                for m, result in with_filter.items():
                    lwa[f"cnossos_{_column(m)}_filter_LWA_dBA"][i] = result.total_dba
                if abs(v * KMH - speed) < 1e-9:
                    per_band = {
                        "a3_db": base.contact_filter_db,
                        **{f"{_column(m)}_filter_db": f for m, f in filters.items()},
                        "cnossos_a3_LW_db": base.total_db,
                        **{f"cnossos_{_column(m)}_filter_LW_db": r.total_db for m, r in with_filter.items()},
                    }
            tables.extend(_noise_tables(label, speeds, lwa, per_band, track.frequency_hz, speed))
        return tables

    return specs, tabulate


def _noise_tables(label, speeds, lwa, per_band, frequency_hz, speed):
    """The three tables of one set: L_WA and L_pAeq against speed, and the filters at the study's speed."""
    from wheelrail.core.noise.run_noise import DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH, pass_by_level

    tables = []
    lpaeq = {
        name.replace("LWA", "LpAeq"): np.array(
            [pass_by_level(x, DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH) for x in values]
        )
        for name, values in lwa.items()
    }
    axis = np.asarray(speeds, dtype=float)
    tables.append(
        Table(
            name=f"noise_{label}_lwa_vs_speed",
            figure="noise",
            panel=label,
            band_centres=axis,
            columns=lwa,
            axis_name="speed_kmh",
            title=f"{label}: A-weighted sound power per axle, dB(A) re 1 pW: the models "
            f"(TWINS-like chain) and CNOSSOS-EU ({CNOSSOS_TRACK_TYPE}, the set's line 0 as "
            "roughness) with A3 or a model's dynamic filter",
        )
    )
    tables.append(
        Table(
            name=f"noise_{label}_lpaeq_vs_speed",
            figure="noise-lpaeq",
            panel=label,
            band_centres=axis,
            columns=lpaeq,
            axis_name="speed_kmh",
            title=f"{label}: pass-by L_pAeq,Tp at 7.5 m / 1.2 m, {DEFAULT_TRAIN_AXLES} axles, "
            f"{DEFAULT_TRAIN_LENGTH:g} m, dB(A)",
        )
    )
    tables.append(
        Table(
            name=f"noise_{label}_filters_{speed / KMH:g}kmh",
            figure="noise-filters",
            panel=label,
            band_centres=frequency_hz,
            columns=per_band,
            title=f"{label}, {speed / KMH:g} km/h: contact filters (A3 and L_F(model) - "
            "L_F(hertz)), dB, and the CNOSSOS-EU sound power per axle with each, dB re 1 pW",
        )
    )
    return tables
