"""A whole study: plan, execute, tabulate, then write the CSV tables, PNG figure(s) and JSON summary."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wheelrail.core.atomic import atomic_write
from wheelrail.core.errors import WheelrailError
from wheelrail.core.jsonready import strict_json
from wheelrail.core.parameters import KMH, ContactParameters, as_dict
from wheelrail.core.study.execution import ExecutionReport, execute, parse_dask_address
from wheelrail.core.study.figures import plot_study
from wheelrail.core.study.plans import StudyPlan, plan_study
from wheelrail.core.study.tables import Table, write_table


@dataclass(frozen=True)
class StudyResult:
    """A finished study: its tables, the files written and how the runs were obtained."""

    name: str
    tables: list[Table]
    files: list[Path]
    report: ExecutionReport
    summary: dict


@dataclass(frozen=True, kw_only=True)
class StudyContact:
    """What every run of a study has at the contact: the contact parameters (material, preload, geometry) and
    the wheel set added to the rail sets (a bundled name, CSV/NPZ path or RoughnessSet; None: a smooth wheel).
    ``run_study(contact=StudyContact(contact=ContactParameters(wheel_radius=0.46), wheel_set="sinter-wheel-1"))``.
    """

    contact: ContactParameters = field(default_factory=ContactParameters)
    wheel_set: object = None


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
    sets: Sequence,
    out: str | os.PathLike,
    *,
    speed: float = 100.0 * KMH,
    length: float | None = None,
    workers: int = 2,
    dask_address: str | None = None,
    contact: StudyContact | ContactParameters | None = None,
    progress: bool = True,
    figures: bool = True,
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
    speed : float
        Train speed, m/s (100 km/h).
    length : float, optional
        Run length, m (default: the whole set).
    workers : int
        Local worker processes (1: in this process).
    dask_address : str, optional
        Dask scheduler address; runs go to that cluster instead of the local pool.
    contact : StudyContact or ContactParameters, optional
        Contact material, preload and geometry of every run (default: the paper's), and the wheel set added
        to every rail set (:class:`StudyContact`; a ContactParameters alone: a smooth wheel); see
        :func:`plan_study`.
    progress : bool
        tqdm bar of runs done on stderr.
    figures : bool
        Draw the PNG figure(s) (about 1 s each with matplotlib); the CSV tables and JSON are always written.

    Returns
    -------
    StudyResult
    """
    created = _missing_folders(Path(out))
    folder = check_output_folder(out)
    try:
        return _run_study(name, sets, folder, speed, length, workers, dask_address, contact, progress, figures)
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


def _run_study(name, sets, folder, speed, length, workers, dask_address, contact, progress, figures) -> StudyResult:
    """:func:`run_study` in its checked output folder."""
    if dask_address is not None:
        dask_address = parse_dask_address(dask_address)
    if contact is not None and not isinstance(contact, StudyContact | ContactParameters):
        raise WheelrailError(
            "contact must be a wheelrail.core.study.StudyContact or wheelrail.core.parameters.ContactParameters"
        )
    contact = contact if isinstance(contact, StudyContact) else StudyContact(contact=contact or ContactParameters())
    plan = plan_study(name, sets, speed=speed, length=length, contact=contact.contact, wheel_set=contact.wheel_set)
    report = execute(
        plan.specs,
        cache=folder / "runs",
        workers=workers,
        dask_address=dask_address,
        progress=progress,
        description=f"study {name}",
    )
    tables = plan.tabulate(report.summaries)
    files = [write_table(table, folder) for table in tables]
    if figures:
        files += plot_study(name, tables, folder)
    summary = _summary_document(name, plan, report, tables, speed=speed, folder=folder, files=files)
    summary_path = folder / f"{name}_summary.json"
    atomic_write(summary_path, lambda handle: handle.write(strict_json(summary, indent=2)), mode="w")
    files.append(summary_path)
    summary["files"].append(str(summary_path))
    return StudyResult(name=name, tables=tables, files=files, report=report, summary=summary)


def _summary_document(
    name: str,
    plan: StudyPlan,
    report: ExecutionReport,
    tables: list[Table],
    *,
    speed: float,
    folder: Path,
    files: list[Path],
) -> dict:
    """The JSON summary of a study (SI units; what ``wheelrail study --json`` prints)."""
    from wheelrail.core.spectra import band_labels

    summaries = [report.summaries[spec.key] for spec in plan.specs]
    summary = {
        "study": name,
        "sets": [info.label for info in plan.sets],
        "wheel_set": None if plan.wheel_set is None else plan.wheel_set.label,
        "speed_m_per_s": speed,
        "speed_kmh": speed / KMH,
        "length_m": {info.label: info.length for info in plan.sets},
        "contact": as_dict(plan.contact),
        "runs": len({spec.key for spec in plan.specs}),
        "runs_computed": report.computed,
        "runs_cached": report.cached,
        "backend": report.backend,
        "wall_time_s": report.wall_time,
        "worker_run_time_s": float(sum(s.run_time for s in summaries)),
        "loss_of_contact_steps": int(sum(s.loss_of_contact_steps for s in summaries)),
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
