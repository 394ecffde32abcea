"""The ``track`` study: the same runs on several tracks (any track input swept), their force and their noise.

Runs: every contact model of the noise study (:func:`~wheelrail.core.study.noise_plan.noise_models`) on line 0
of each set at the study's speed, once per track. Each track is a full set of ``ModelParameters.track`` (the
study's parameters with the swept inputs set); each costs its own precompute of the Green's functions (the
runs are spread over the workers like any others, so the precomputes of different tracks run in parallel).
From each run's force levels the TWINS-like chain of :mod:`wheelrail.core.noise.twins` on that track gives the
rail, sleeper and wheel sound power of one wheel, the A-weighted sound power per axle and the pass-by level of
the default train (as ``wheelrail noise --run``).

Tables per set: ``track_<set>_noise`` (first column the track's number 1..N, then the swept inputs' values in
their command-line units, then per model the overall force level, dB re 1 N, and the A-weighted sound powers
and pass-by level, dB(A)) and ``track_<set>_force_levels`` (the force spectra, one column per model and track).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import inputs_of
from wheelrail.core.study.noise_plan import noise_models
from wheelrail.core.study.tables import Table

__all__ = ["MAX_TRACKS", "check_track_count", "plan_track", "swept_inputs", "track_description", "track_study_cost"]

MAX_TRACKS = 100
"""The most tracks one track study takes: each is a precompute (``track.progress.PRECOMPUTE_CPU_S``) and a cache
entry (``ENTRY_BYTES``), so 100 are 100 precomputes and 21 GB of cache."""


def swept_inputs(tracks) -> list:
    """The declared track inputs whose value differs between ``tracks`` (all of them when there is one track)."""
    entries = inputs_of("track")
    if len(tracks) == 1:
        return list(entries)
    return [entry for entry in entries if len({_value(track, entry) for track in tracks}) > 1]


def track_description(params, tracks) -> dict:
    """The tracks of a study as its JSON summary records them (SI, the keys of
    :func:`wheelrail.core.inputs.declared.describe`).

    Returns
    -------
    dict
        ``track``: the inputs every track shares (one track: all of them); ``tracks``: per track, its own values of
        the inputs that differ between the tracks (one track: all of them); ``swept_track_inputs``: their keys.
    """
    from wheelrail.core.inputs.declared import describe

    each = [describe(replace(params, track=track), "track")["track"] for track in tracks or (params.track,)]
    swept = [entry.key for entry in swept_inputs(tracks)] if len(each) > 1 else []
    return {
        "track": {key: value for key, value in each[0].items() if key not in swept},
        "tracks": [{key: values[key] for key in swept} if swept else values for values in each],
        "swept_track_inputs": swept,
    }


def track_study_cost(tracks, sets: int = 1, workers: int = 1, numerics=None) -> dict:
    """What a track study on ``tracks`` will cost, from the project's own figures (``core.track.progress``).

    Returns
    -------
    dict
        ``tracks``; ``runs`` (every model of the study on each track and set); ``new_tracks`` (not in the disk
        cache at ``numerics``, a TrackNumerics, default the default: each a precompute, costed at the default
        numerics'); ``precompute_cpu_s`` and ``precompute_wall_s`` (on
        ``workers`` processes, at most one per core); ``cache_bytes`` (every track's entry) and
        ``cache_limit_bytes`` (``WHEELRAIL_CACHE_MAX_GB``).
    """
    import os

    from wheelrail.core.files.cache import max_bytes
    from wheelrail.core.parameters import TrackNumerics
    from wheelrail.core.track import track_cache_path
    from wheelrail.core.track.progress import ENTRY_BYTES, PRECOMPUTE_CPU_S

    new = sum(not track_cache_path(track, numerics or TrackNumerics()).exists() for track in tracks)
    parallel = max(1, min(workers, os.cpu_count() or 1))
    return {
        "tracks": len(tracks),
        "runs": len(tracks) * len(noise_models()) * sets,
        "new_tracks": new,
        "precompute_cpu_s": new * PRECOMPUTE_CPU_S,
        "precompute_wall_s": math.ceil(new / parallel) * PRECOMPUTE_CPU_S,
        "cache_bytes": len(tracks) * ENTRY_BYTES,
        "cache_limit_bytes": max_bytes(),
    }


def check_track_count(tracks) -> None:
    """Refuse, before any work, a track study of more than :data:`MAX_TRACKS` tracks, or of more tracks than the
    disk cache holds (each track's entry would evict another's, the study's own among them, and every entry of
    other work): one WheelrailError saying the cost, the limit and what to do."""
    from wheelrail.core.files.cache import max_bytes
    from wheelrail.core.track.progress import ENTRY_BYTES, PRECOMPUTE_CPU_S

    count = len(tracks)
    cost = (
        f"each a Green's-function precompute of about {PRECOMPUTE_CPU_S:g} s of CPU and a "
        f"{ENTRY_BYTES / 1e6:.0f} MB cache entry"
    )
    if count > MAX_TRACKS:
        raise WheelrailError(
            f"a track study of {count} tracks ({cost}: {count * PRECOMPUTE_CPU_S / 3600:.1f} h, "
            f"{count * ENTRY_BYTES / 1e9:.0f} GB) is over the limit of {MAX_TRACKS} tracks; sweep fewer values"
        )
    fit = int(max_bytes() // ENTRY_BYTES)
    if count > fit:
        raise WheelrailError(
            f"a track study of {count} tracks ({cost}) needs {count * ENTRY_BYTES / 1e9:.1f} GB of disk cache, over "
            f"its limit of {max_bytes() / 1e9:g} GB (WHEELRAIL_CACHE_MAX_GB), which holds {fit}: each new track would "
            f"evict another; sweep at most {fit} tracks, or set WHEELRAIL_CACHE_MAX_GB to at least "
            f"{math.ceil(count * ENTRY_BYTES / 1e9)}"
        )


def _value(track, entry) -> float:
    from wheelrail.core.parameters import ModelParameters

    return float(entry.value_in(ModelParameters(track=track)))


def _column(model: str) -> str:
    return model.replace("-", "_")


def plan_track(infos, params, tracks, spec_of):
    """Specs and the table builder of the ``track`` study (``spec_of(info, model, params, line)`` is the study's
    own helper); ``tracks`` as ``plans.study_parameters`` gives them."""
    models = noise_models()
    on_track = [replace(params, track=track) for track in tracks]
    layout = {
        info.label: (info, {(model, k): spec_of(info, model, p, 0) for model in models for k, p in enumerate(on_track)})
        for info in infos
    }
    specs = [spec for _, runs in layout.values() for spec in runs.values()]

    def tabulate(summaries):
        from wheelrail.core.noise.components import component_names, noise_components
        from wheelrail.core.noise.run_noise import AXLE_DB, DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH, pass_by_level
        from wheelrail.core.noise.run_noise import sound_power_from_force as power
        from wheelrail.core.noise.twins import chain_numerics, track_noise_model

        numerics = chain_numerics(specs[0].track_numerics)  # the runs' track
        noise_tracks = [track_noise_model(p, numerics) for p in on_track]
        swept = swept_inputs(tracks)
        labels = [part.label for part in noise_components()]
        parts = ", ".join(labels[:-1]) + f" and {labels[-1]}"  # "rail, sleeper and wheel"
        tables = []
        for label, (_, runs) in layout.items():
            number = np.arange(1, len(tracks) + 1, dtype=float)
            noise = {entry.dest: np.array([_value(t, entry) * entry.shown.scale for t in tracks]) for entry in swept}
            force_columns = {}
            for model in models:
                found = [summaries[runs[model, k].key] for k in range(len(tracks))]
                centres = found[0].band_centres
                for k, summary in enumerate(found):
                    force_columns[f"{_column(model)}_track{k + 1}_db"] = np.asarray(summary.levels, dtype=float)
                levels = [np.concatenate([np.asarray(s.levels, dtype=float), [np.nan]]) for s in found]
                chains = [power(level, noise_tracks[k]) for k, level in enumerate(levels)]
                noise[f"{_column(model)}_force_dB"] = np.array([_total(s.levels) for s in found])
                for part in component_names():
                    noise[f"{_column(model)}_{part}_LWA_dBA"] = np.array([c["dba"][part] + AXLE_DB for c in chains])
                noise[f"{_column(model)}_LWA_dBA"] = np.array([c["axle_dba"] for c in chains])
                noise[f"{_column(model)}_LpAeq_dBA"] = np.array(
                    [pass_by_level(c["axle_dba"], DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH) for c in chains]
                )
            tables.append(
                Table(
                    name=f"track_{label}_noise",
                    figure="track",
                    panel=label,
                    band_centres=number,
                    columns=noise,
                    axis_name="track",
                    title=f"{label}, line 0: per track (swept inputs in their option's units), the overall force "
                    f"level (dB re 1 N), {parts} sound power per axle and their total (dB(A) re 1 "
                    f"pW), pass-by L_pAeq,Tp ({DEFAULT_TRAIN_AXLES} axles, {DEFAULT_TRAIN_LENGTH:g} m, dB(A))",
                )
            )
            tables.append(
                Table(
                    name=f"track_{label}_force_levels",
                    figure="track-force",
                    panel=label,
                    band_centres=np.asarray(centres, dtype=float),
                    columns=force_columns,
                    title=f"{label}, line 0: contact-force levels per model and track, dB re 1 N",
                )
            )
        return tables

    return specs, tabulate


def _total(levels) -> float:
    """The energy sum of band levels (dB), unresolved (NaN) bands left out."""
    from wheelrail.core.spectra.levels import energy_sum

    values = np.asarray(levels, dtype=float)
    values = values[np.isfinite(values)]
    return float(energy_sum(values, axis=0)) if values.size else float("nan")
