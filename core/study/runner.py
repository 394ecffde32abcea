"""A whole study: plan, execute, tabulate, then write the CSV tables, PNG figure(s) and JSON summary."""

from __future__ import annotations

import contextlib
import os
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.atomic import all_or_none, atomic_write, refuse_inputs
from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.inputs.declared import caption
from wheelrail.core.parameters import KMH, ModelParameters, as_dict
from wheelrail.core.study.execution import ExecutionReport, execute, parse_dask_address
from wheelrail.core.study.figures import plot_study
from wheelrail.core.study.plans import StudyPlan, plan_study
from wheelrail.core.study.tables import Table, write_table
from wheelrail.core.study.threads import blas_threads
from wheelrail.core.study.track_plan import swept_inputs, track_description

if TYPE_CHECKING:  # the roughness package is imported when a set is read
    from wheelrail.core.roughness import RoughnessLike


@dataclass(frozen=True)
class StudyResult:
    """A finished study: its tables, the files written and how the runs were obtained."""

    name: str
    tables: list[Table]
    files: list[Path]
    report: ExecutionReport
    summary: dict


def check_output_folder(out: str | os.PathLike) -> Path:
    """Create ``out`` if needed and check it is a writable folder (WheelrailError otherwise)."""
    if not str(out).strip():  # Path("") is the current folder: the study would write there unasked
        raise WheelrailError("the output folder is empty; give a folder name")
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        raise WheelrailError(f"output {folder} exists and is not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise WheelrailError(f"cannot create output folder {folder}: {error.strerror or error}") from None
    if not folder.is_dir():
        raise WheelrailError(f"output {folder} is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise WheelrailError(f"output folder {folder} is not writable")
    return folder


def run_study(
    name: str,
    sets: Sequence[RoughnessLike],
    out: str | os.PathLike,
    *,
    params: ModelParameters | Sequence[ModelParameters] | None = None,
    wheel_set: RoughnessLike | None = None,
    length: float | None = None,
    workers: int = 2,
    dask_address: str | None = None,
    progress: bool = True,
    figures: bool = True,
    **plan,
) -> StudyResult:
    """Plan, execute and tabulate a named study; write its CSV tables, PNG figure(s) and JSON summary.

    Parameters
    ----------
    name : str
        One of ``STUDIES``.
    sets : sequence
        Roughness sets (bundled names, CSV/NPZ paths or ``RoughnessSet``).
    out : path
        Output folder (created if missing): ``<table>.csv``, ``fig<N>_<study>.png``, ``<study>_summary.json``.
    params : ModelParameters or sequence of them, optional
        The parameters of every run, as ``prepare_run`` takes them (default: the paper's), but for what the
        study varies: speed, contact, track and wheel; the ``track`` study takes several that differ in their
        track only (see :func:`plan_study`).
    wheel_set : bundled name, CSV/NPZ path or RoughnessSet, optional
        A wheel set added to every rail set (combined roughness); default: a smooth wheel (see
        :func:`plan_study`).
    length : float, optional
        Run length, m (default: the whole set).
    workers : int
        Local workers (1: in this process): threads of this process when every run's law releases the GIL, else
        worker processes (:func:`~wheelrail.core.study.execution.execute`).
    dask_address : str, optional
        Dask scheduler address; runs go to that cluster instead of the local pool.
    progress : bool
        tqdm bar of runs done on stderr.
    figures : bool
        Draw the PNG figure(s) (matplotlib); the CSV tables and JSON are always written.
    **plan
        The other keywords of :func:`plan_study`: ``track_numerics``, the track's numerics of every run and of the
        tables' noise chains (the summary's ``track_numerics`` states those that differ from the default).

    Returns
    -------
    StudyResult
        Its tables (levels and level differences per band, dB), the files written and how the runs were
        obtained (computed, read from the study's run cache).

    Raises
    ------
    WheelrailError
        For an unknown study, a set that cannot be read or does not fit the study, parameters outside their
        ranges, an output folder that cannot be written, or a run that fails.

    See Also
    --------
    plan_study : the runs and tables of a study, without running them.
    wheelrail.core.spectra.levels.contact_filter : the level arithmetic of the tables.

    Notes
    -----
    Each run's spectrum is cached in the output folder under a hash of everything that defines it, so an
    interrupted study resumes where it stopped.

    References
    ----------
    .. [1] A. Pieringer, W. Kropp, D.J. Thompson, Wear 271 (2011) 328-338, sections 3.3-3.5 (Figs 10-17).
    """
    created = _missing_folders(Path(out))
    folder = check_output_folder(out)
    try:
        plan.update(params=params, wheel_set=wheel_set, length=length)
        return _run_study(name, sets, folder, plan, workers, dask_address, progress, figures)
    except BaseException:
        _remove_if_empty(created)  # a refused or failed study leaves no empty folder of its own behind
        raise


def _missing_folders(folder: Path) -> list[Path]:
    """``folder`` and those of its parents that do not exist yet, deepest first."""
    missing = []
    while not folder.exists() and folder != folder.parent:
        missing.append(folder)
        folder = folder.parent
    return missing


def _remove_if_empty(created: list[Path]) -> None:
    """Remove the folders this study created (deepest first, with its ``runs`` folder) if they hold nothing."""
    for folder in [created[0] / "runs", *created] if created else []:
        try:
            folder.rmdir()  # only an empty folder is removed: nothing a user or a finished run wrote
        except OSError:
            pass


def _run_study(name, sets, folder, planned: dict, workers, dask_address, progress, figures) -> StudyResult:
    """:func:`run_study` in its checked output folder (``planned``: :func:`plan_study`'s keywords)."""
    if dask_address is not None:
        dask_address = parse_dask_address(dask_address)
    plan = plan_study(name, sets, **planned)
    spare = workers > 1 or dask_address is not None  # the tables' own work beside the runs, on a core of its own
    with _beside((*plan.beside, *((_load_matplotlib,) if figures else ())) if spare else ()) as start_beside:
        report = execute(
            plan.specs,
            cache=folder / "runs",
            workers=workers,
            dask_address=dask_address,
            progress=progress,
            description=f"study {name}",
            started=start_beside,
        )
    with blas_threads(1 if workers == 1 and dask_address is None else None):  # one worker, one core
        tables = plan.tabulate(report.summaries)
    with all_or_none():  # the tables, figures and summary appear together, and none over an input
        files = [write_table(table, folder) for table in tables]
        if figures:
            files += plot_study(name, tables, folder, caption=study_caption(name, plan), workers=workers)
        summary = _summary_document(name, plan, report, tables, folder=folder, files=files)
        summary_path = folder / f"{name}_summary.json"
        atomic_write(summary_path, lambda handle: handle.write(strict_json(summary, indent=2)), mode="w")
        files.append(summary_path)
        summary["files"].append(str(summary_path))
        refuse_inputs(files, [*sets, planned["wheel_set"]])
    return StudyResult(name=name, tables=tables, files=files, report=report, summary=summary)


@contextlib.contextmanager
def _beside(work):
    """Call each of ``work`` in a thread while the block runs (its results are kept where they are cached), started
    when the block calls the callable it is given (``execute``'s ``started``: once a run has finished, so that the
    work, which holds the GIL, does not lengthen the first runs' load of numba's compiled code, which holds it too and
    comes before any parallel step; never before ``execute`` forks its workers, whose process must have no other
    thread) or when the block ends; that callable returns the thread (forked workers' share in this process waits
    for it before it takes runs). Leaving the block waits for it, but for an error or interrupt. A failure is left
    to the tabulation, which does the same work again and reports it."""
    if not work:
        yield lambda: None
        return
    stop, lock, threads = threading.Event(), threading.Lock(), []

    def call_each():
        from wheelrail.core.study.threads import set_blas_threads_local

        set_blas_threads_local(1)  # beside the runs' threads, on the study's cores
        for call in work:
            if stop.is_set():
                return
            try:
                call()
            except Exception:  # noqa: BLE001 - the tabulation repeats it and reports its error
                pass

    def start() -> threading.Thread:
        with lock:
            if not threads:
                threads.append(threading.Thread(target=call_each, name="wheelrail-study-beside", daemon=True))
                threads[0].start()
        return threads[0]

    try:
        yield start
    except BaseException:
        stop.set()
        raise
    start()
    threads[0].join()


def _load_matplotlib() -> None:
    """The figures' matplotlib modules, imported before the tables are ready."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: F401
    from matplotlib.figure import Figure  # noqa: F401


def study_caption(name: str, plan: StudyPlan) -> str:
    """What every run of a study shares, as its figures name it (core's
    :func:`~wheelrail.core.inputs.declared.caption`): the speed unless the study sweeps it, the preload, the contact
    geometry and the track (the track study: what its tracks share) and the wheel set added to every set."""
    swept = [entry.key for entry in swept_inputs(plan.tracks)] if len(plan.tracks) > 1 else []
    if name in ("speeds", "noise", "impact"):  # their figures put the speed on an axis or a curve per speed
        swept.append("speed")
    words = caption(plan.params, leave_out=tuple(swept))
    if plan.impact is not None:  # what the Hertz models are driven by over the irregularities
        words += f"; Hertz models on the {plan.impact.params.run.irregularity_input} (irregularity input)"
    return words if plan.wheel_set is None else f"{words}; wheel set {plan.wheel_set.label}"


def _spectrum_records(plan: StudyPlan, summaries) -> list[dict]:
    """Each distinct record the study's force spectra analysed (speed, steps, the start left out, the duration
    analysed and the bands it resolves: :meth:`wheelrail.core.spectra.record.SpectrumRecord.to_dict`), with the
    line :meth:`~wheelrail.core.spectra.record.SpectrumRecord.words` says."""
    from wheelrail.core.spectra.force import record_of_steps

    records: dict = {}
    for spec, summary in zip(plan.specs, summaries, strict=True):
        key = (int(summary.n_steps), spec.params.run.time_step)
        if key not in records:
            record = record_of_steps(*key)
            records[key] = {
                "speed_m_per_s": spec.params.run.speed,
                "steps": key[0],
                **record.to_dict(),
                "words": record.words(),
            }
    return list(records.values())


def _summary_document(
    name: str,
    plan: StudyPlan,
    report: ExecutionReport,
    tables: list[Table],
    *,
    folder: Path,
    files: list[Path],
) -> dict:
    """The JSON summary of a study (SI units; what ``wheelrail study --json`` prints)."""
    from wheelrail.core.inputs.numerics import numerics_changes
    from wheelrail.core.spectra.bands import band_labels

    summaries = [report.summaries[spec.key] for spec in plan.specs]
    speed = plan.speed
    summary = {
        "study": name,
        "sets": [info.label for info in plan.sets],
        "wheel_set": None if plan.wheel_set is None else plan.wheel_set.label,
        "speed_m_per_s": speed,
        "speed_kmh": speed / KMH,
        "element_size_m": plan.params.run.element_size,  # every run's contact grid and step along the rail
        "track_numerics": numerics_changes(plan.track_numerics),  # those of every run that differ from the default
        "length_m": {info.label: info.length for info in plan.sets},
        "contact": as_dict(plan.contact),
        **track_description(plan.params, plan.tracks),  # what the tracks share, and each one's swept values
        "runs": len({spec.key for spec in plan.specs}),
        "runs_computed": report.computed,
        "runs_cached": report.cached,
        "backend": report.backend,
        "wall_time_s": report.wall_time,
        "worker_run_time_s": float(sum(s.run_time for s in summaries)),
        "loss_of_contact_steps": int(sum(s.loss_of_contact_steps for s in summaries)),
        "spectrum_records": _spectrum_records(plan, summaries),
        **_impact_description(plan),
        "out": str(folder),
        "files": [str(path) for path in files],
        "tables": {
            table.name: {
                "figure": table.figure,
                "title": table.title,
                **(
                    {"band_labels": band_labels(table.band_centres), "band_centres_hz": table.band_centres}
                    if table.axis_name == "band_centre_hz"
                    else {table.axis_name: table.band_centres}
                ),
                **{
                    column: [None if not np.isfinite(v) else round(float(v), 3) for v in values]
                    for column, values in table.columns.items()
                },
            }
            for table in tables
        },
    }
    return summary


def _impact_description(plan: StudyPlan) -> dict:
    """The impact study's sweep as its JSON summary records it (SI): ``irregularity_cases`` (each a list of
    records, ``irregularities.shapes.as_record``), ``irregularity_input``, ``models``, ``speeds_m_per_s``; other
    studies: nothing."""
    if plan.impact is None:
        return {}
    from wheelrail.core.irregularities.shapes import as_record

    sweep = plan.impact
    return {
        "irregularity_cases": [[as_record(item) for item in case] for case in sweep.cases],
        "irregularity_input": sweep.params.run.irregularity_input,
        "models": list(sweep.models),
        "speeds_m_per_s": list(sweep.speeds),
    }
