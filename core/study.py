"""Studies: batches of independent runs, their force spectra, contact filters and model differences.

This reproduces the paper's section 3.3-3.5 on any roughness set (Pieringer, Kropp & Thompson, Wear 271,
2011; SPEC.md §4-§6). A study is a list of independent :class:`RunSpec` (set, line, model, speed, wheel
mass, length, input transform) -> one :class:`RunSummary` each (third-octave force spectrum of
:func:`wheelrail.core.spectra.force_spectrum` plus a few force statistics, no pressure maps) -> tables of
levels and level differences in dB -> CSV files, a figure laid out like the paper's, a JSON summary.

Named studies (``STUDIES``):

``filters`` (Fig. 10)
    Force spectra and contact filters of all five models: the one-line models on lines -3..3, the 3D model
    once, centred on line 0. Spectra of the one-line models are averaged over the lines in dB; the
    contact filter of a model is its level minus the level of ``hertz`` on the same line (no roughness
    filtering), averaged over the per-line filter curves (3D: L_3D - L_hertz,l averaged over l).
``line-spread`` (Figs 12-14)
    Per-line and mean differences L_3D - L_2D,l, L_2D,l - L_hertz-winkler,l, L_2D,l - L_hertz-average,l.
``averaged-input`` (Fig. 16)
    L_3D - L_2D,av: the 2D model fed with the mean of lines -3..3.
``lateral-resolution`` (Fig. 17)
    L_3D - L_3D,low: the 3D model on the original lines vs only the lines at -8, -4, 0, 4, 8 mm (4 mm
    resolution, the paper's lines -4, -2, 0, 2, 4 of its 2 mm numbering) and -8, 0, 8 mm (8 mm), linearly
    re-interpolated to the 1 mm model grid across the track.
``speeds`` (Fig. 11)
    The 2D model on line 0 at 75, 100, 140 and 200 km/h and at the reference speed with half the
    unsprung wheel mass (M_W = 296.3 kg): the sleeper-passing peaks move with v / L_S, not with M_W.

Runs are executed by :func:`execute`: already cached runs are read back, the missing ones run on a local
process pool (``concurrent.futures.ProcessPoolExecutor``) or on a Dask cluster (``dask.distributed``), and
each finished run is written at once, atomically, to ``<cache>/<key>.npz`` where the key is a SHA-256
hash of the full run spec (roughness content, model, line, input transform, all model parameters, run
and spectrum settings). An interrupted study therefore resumes and only computes the missing runs.
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import json
import math
import os
import re
import sys
import time
import zipfile
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from wheelrail.core.atomic import atomic_write
from wheelrail.core.errors import WheelrailError
from wheelrail.core.jsonready import json_ready
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters, WheelParameters, as_dict
from wheelrail.core.results import MODELS

__all__ = [
    "STUDIES", "PAPER_LINES", "ONE_LINE_MODELS", "RunSpec", "RunSummary", "Table", "StudyPlan",
    "StudyResult", "ExecutionReport", "roughness_digest", "study_roughness", "compute_run", "execute",
    "contact_filter", "mean_level", "level_difference", "plan_study", "run_study", "write_table",
    "parse_dask_address", "shutdown_pools",
]

STUDIES = ("filters", "line-spread", "averaged-input", "lateral-resolution", "speeds")
PAPER_LINES = tuple(range(-3, 4))  # the seven lines -3..3 the paper averages over (section 3.3)
ONE_LINE_MODELS = ("2d", "hertz", "hertz-winkler", "hertz-average")
REFERENCE_MODEL = "hertz"  # no roughness filtering: the reference of the contact filter (section 3.3)
LOW_RESOLUTION_LINES_MM = {  # Fig. 17: lateral offsets from line 0 kept, mm
    4: (-8.0, -4.0, 0.0, 4.0, 8.0),
    8: (-8.0, 0.0, 8.0),
}
PAPER_SPEEDS_KMH = (75.0, 100.0, 140.0, 200.0)  # Fig. 11
HALF_WHEEL_MASS = 296.3  # kg, Fig. 11: half of M_W = 592.5 kg
STUDY_FORMAT_VERSION = 1  # part of every run key: bump when a run's summary changes meaning
_MARGIN = 0.020  # m: largest window margin of the models at 1 mm (hertz-winkler), see interaction.prepare_run
_SUMMARY_SCALARS = ("force_mean", "force_std", "force_min", "force_max", "loss_of_contact_steps", "n_steps",
                    "run_time")


# --------------------------------------------------------------------------------------------------
# Run specs and their results
# --------------------------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True, eq=False)
class RunSpec:
    """One independent run of a study.

    Attributes
    ----------
    source : str or RoughnessSet
        Bundled set name, CSV/NPZ path, or the set itself (as accepted by ``simulate``).
    set_label : str
        Short name of the set in tables (bundled name or file stem).
    set_digest : str
        SHA-256 of the set's content (:func:`roughness_digest`); part of the run key, so a changed file
        is never matched with an old result.
    model : str
        One of ``MODELS``.
    line : int
        Roughness line (-M..M); for ``3d`` the line the window is centred on. Ignored (0) with
        ``averaged_lines``.
    params : ModelParameters
        All model parameters (speed in ``params.run.speed``, m/s; wheel mass in
        ``params.wheel.unsprung_mass``, kg).
    length : float or None
        Run length, m (None: the whole set, see ``prepare_run``).
    averaged_lines : tuple of int
        If not empty, the model runs on one line: the mean of these lines (paper Fig. 16).
    lateral_lines_mm : tuple of float
        If not empty, only lines at these lateral offsets from line 0 (mm) are kept, linearly interpolated
        across the track from the original lines when they do not fall on one (paper Fig. 17).
    run_in_length : float
        Smooth run-in before the first step, m.
    """

    source: object
    set_label: str
    set_digest: str
    model: str
    line: int = 0
    params: ModelParameters = field(default_factory=ModelParameters)
    length: float | None = None
    averaged_lines: tuple[int, ...] = ()
    lateral_lines_mm: tuple[float, ...] = ()
    run_in_length: float = 1.0

    def __post_init__(self) -> None:
        if self.model not in MODELS:
            raise WheelrailError(f"unknown contact model {self.model!r}; choose one of {', '.join(MODELS)}")
        object.__setattr__(self, "averaged_lines", tuple(int(v) for v in self.averaged_lines))
        object.__setattr__(self, "lateral_lines_mm", tuple(float(v) for v in self.lateral_lines_mm))

    def description(self) -> dict:
        """Everything that determines the run's summary (JSON-able); the key hashes this."""
        from wheelrail.core.spectra import FORCE_BAND_RANGE, FORCE_SKIP

        return {
            "version": STUDY_FORMAT_VERSION,
            "set_digest": self.set_digest,
            "model": self.model,
            "line": int(self.line),
            "length_m": None if self.length is None else float(self.length),
            "averaged_lines": list(self.averaged_lines),
            "lateral_lines_mm": list(self.lateral_lines_mm),
            "run_in_length_m": float(self.run_in_length),
            "params": as_dict(self.params),
            "spectrum": {"skip_s": FORCE_SKIP, "band_range_hz": list(FORCE_BAND_RANGE)},
        }

    @property
    def key(self) -> str:
        """SHA-256 hex digest of :meth:`description` (sorted keys, floats by repr)."""
        text = json.dumps(self.description(), sort_keys=True, default=repr)
        return hashlib.sha256(text.encode()).hexdigest()

    @property
    def speed_kmh(self) -> float:
        return self.params.run.speed / KMH

    def label(self) -> str:
        """Human-readable one-liner (progress messages and errors)."""
        what = f"{self.model} on {self.set_label}"
        if self.averaged_lines:
            what += f" mean of lines {self.averaged_lines[0]}..{self.averaged_lines[-1]}"
        elif self.lateral_lines_mm:
            what += f" lines at {', '.join(f'{v:g}' for v in self.lateral_lines_mm)} mm"
        else:
            what += f" line {self.line}"
        return f"{what}, {self.speed_kmh:g} km/h, M_W {self.params.wheel.unsprung_mass:g} kg"


@dataclass(frozen=True, kw_only=True)
class RunSummary:
    """What a worker sends back for one run: the force spectrum and a few numbers (no time series).

    Attributes
    ----------
    key : str
        The run's :attr:`RunSpec.key`.
    band_centres : ndarray
        Exact third-octave band centres, Hz (50 Hz - 8 kHz).
    levels : ndarray
        Dynamic contact-force levels, dB re 1 N (NaN where a band is not resolved).
    force_mean, force_std, force_min, force_max : float
        Contact-force statistics over the run, N.
    loss_of_contact_steps, n_steps : int
        Steps with F = 0; steps in the run.
    run_time : float
        Wall time of the run in its worker, s (preparation included).
    """

    key: str
    band_centres: np.ndarray
    levels: np.ndarray
    force_mean: float
    force_std: float
    force_min: float
    force_max: float
    loss_of_contact_steps: int
    n_steps: int
    run_time: float

    def to_arrays(self) -> dict[str, np.ndarray]:
        arrays = {"run_key": np.array(self.key), "band_centres_hz": self.band_centres, "levels_db": self.levels}
        arrays.update({name: np.array(getattr(self, name)) for name in _SUMMARY_SCALARS})
        return arrays

    @classmethod
    def from_arrays(cls, arrays) -> RunSummary:
        scalars = {name: arrays[name].item() for name in _SUMMARY_SCALARS}
        return cls(key=str(arrays["run_key"]), band_centres=np.asarray(arrays["band_centres_hz"], dtype=float),
                   levels=np.asarray(arrays["levels_db"], dtype=float), **scalars)


def roughness_digest(roughness) -> str:
    """SHA-256 of a roughness set's content (heights, dx, y, kind), hex."""
    digest = hashlib.sha256()
    digest.update(np.ascontiguousarray(roughness.heights, dtype="<f8").tobytes())
    digest.update(np.ascontiguousarray(roughness.y, dtype="<f8").tobytes())
    digest.update(f"{roughness.dx!r} {roughness.kind}".encode())
    return digest.hexdigest()


def study_roughness(spec: RunSpec):
    """The roughness set a run actually uses: the source, or its line mean (Fig. 16), or its lines at
    the ``lateral_lines_mm`` offsets (Fig. 17). Returns ``(roughness, line)`` for ``simulate``."""
    from wheelrail.core.roughness import RoughnessSet, load_roughness

    rough = spec.source if isinstance(spec.source, RoughnessSet) else load_roughness(spec.source)
    if spec.averaged_lines:
        rows = [rough.row_of_line(line) for line in spec.averaged_lines]
        mean = rough.heights[rows].mean(axis=0)
        note = f"mean of lines {', '.join(str(v) for v in spec.averaged_lines)}"
        return rough.with_heights(mean[np.newaxis, :], y=np.zeros(1), note=note), 0
    if spec.lateral_lines_mm:
        offsets = np.asarray(spec.lateral_lines_mm) * 1e-3
        y_wanted = float(rough.y[rough.centre_row]) + offsets
        tol = 1e-9
        if rough.n_lines < 2 or y_wanted.min() < rough.y[0] - tol or y_wanted.max() > rough.y[-1] + tol:
            raise WheelrailError(
                f"{spec.set_label}: lines at {', '.join(f'{v:g}' for v in spec.lateral_lines_mm)} mm from line 0 "
                f"need lateral data over that range; the set spans {rough.y[0] * 1e3:g} .. {rough.y[-1] * 1e3:g} mm"
            )
        # linear interpolation across the lines (exact selection where a wanted line exists)
        idx = np.clip(np.searchsorted(rough.y, y_wanted - tol, side="right") - 1, 0, rough.n_lines - 2)
        w = np.clip((y_wanted - rough.y[idx]) / (rough.y[idx + 1] - rough.y[idx]), 0.0, 1.0)
        heights = (1 - w)[:, None] * rough.heights[idx] + w[:, None] * rough.heights[idx + 1]
        note = f"only lines at {', '.join(f'{v:g}' for v in spec.lateral_lines_mm)} mm"
        return rough.with_heights(heights, y=offsets, note=note), 0
    return rough, spec.line


def compute_run(spec: RunSpec) -> RunSummary:
    """Run one spec (``keep_pressure=False``) and reduce it to its :class:`RunSummary` (the worker task)."""
    from wheelrail.core.interaction import simulate
    from wheelrail.core.spectra import force_spectrum

    start = time.perf_counter()
    rough, line = study_roughness(spec)
    result = simulate(rough, model=spec.model, line=line, params=spec.params, length=spec.length,
                      run_in_length=spec.run_in_length, keep_pressure=False)
    centres, levels = force_spectrum(result)
    force = result.force
    return RunSummary(key=spec.key, band_centres=centres, levels=levels, force_mean=float(force.mean()),
                      force_std=float(force.std()), force_min=float(force.min()), force_max=float(force.max()),
                      loss_of_contact_steps=int(result.loss_of_contact_steps), n_steps=int(result.n_steps),
                      run_time=time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# Execution: cache, process pool, Dask
# --------------------------------------------------------------------------------------------------


def _cache_path(cache: Path, key: str) -> Path:
    return cache / f"run-{key[:32]}.npz"


def _load_cached(cache: Path, spec: RunSpec) -> RunSummary | None:
    path = _cache_path(cache, spec.key)
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            summary = RunSummary.from_arrays({name: data[name] for name in data.files})
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
        return None  # unreadable: recompute (and overwrite atomically)
    return summary if summary.key == spec.key else None


def _save_cached(cache: Path, summary: RunSummary) -> None:
    atomic_write(_cache_path(cache, summary.key), lambda handle: np.savez(handle, **summary.to_arrays()))


DASK_CONNECT_TIMEOUT = "10s"  # how long to try reaching a Dask scheduler before giving up
_ADDRESS = re.compile(r"^(tcp|tls|inproc|ucx)://[^\s:/]+(:\d{1,5})?$")


def parse_dask_address(address: str) -> str:
    """Check a Dask scheduler address (``tcp://HOST:PORT``); returns it or raises WheelrailError."""
    text = str(address).strip()
    if "://" not in text:
        text = f"tcp://{text}"
    match = _ADDRESS.match(text)
    port = match.group(2) if match else None
    if match is None or (port is not None and not 0 < int(port[1:]) < 65536):
        raise WheelrailError(f"--dask {address!r} is not a scheduler address; expected tcp://HOST:PORT")
    return text


@dataclass(frozen=True)
class ExecutionReport:
    """What :func:`execute` did: summaries by run key, and how many runs were computed vs read back."""

    summaries: dict[str, RunSummary]
    computed: int
    cached: int
    wall_time: float
    backend: str


def _cost(spec: RunSpec) -> float:
    """Rough relative cost, to start the long runs first (3D ~50x slower per step than one line)."""
    return (50.0 if spec.model == "3d" else 1.0) * (spec.length or 3.0)


def execute(
    specs: Sequence[RunSpec],
    *,
    cache: str | os.PathLike,
    workers: int = 2,
    dask_address: str | None = None,
    progress: bool = True,
    description: str = "runs",
) -> ExecutionReport:
    """Run every spec not yet in ``cache`` and return all summaries.

    Parameters
    ----------
    specs : sequence of RunSpec
        Independent runs; duplicates (same key) run once.
    cache : path
        Folder of finished runs (``run-<key>.npz``, written atomically as each run finishes).
    workers : int
        Local worker processes (``ProcessPoolExecutor``); 1 runs in this process. Ignored with Dask.
    dask_address : str, optional
        Scheduler address of a running Dask cluster (``tcp://HOST:PORT``); runs are submitted there with
        ``dask.distributed.Client(address)``. Results come back to this process, which writes the cache.
    progress : bool
        Show a tqdm bar of runs done on stderr.

    Returns
    -------
    ExecutionReport
    """
    from tqdm import tqdm

    if isinstance(workers, bool) or int(workers) != workers or workers < 1:
        raise WheelrailError(f"workers must be a positive integer, got {workers!r}")
    cache = Path(cache)
    cache.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    unique: dict[str, RunSpec] = {}
    for spec in specs:
        unique.setdefault(spec.key, spec)
    summaries: dict[str, RunSummary] = {}
    missing = []
    for key, spec in unique.items():
        found = _load_cached(cache, spec)
        if found is None:
            missing.append(spec)
        else:
            summaries[key] = found
    n_cached = len(summaries)
    missing.sort(key=_cost, reverse=True)
    bar = tqdm(total=len(unique), initial=n_cached, unit="run", desc=description, disable=not progress,
               file=sys.stderr)

    def finished(summary: RunSummary) -> None:
        _save_cached(cache, summary)
        summaries[summary.key] = summary
        bar.update(1)

    try:
        if dask_address is not None:  # connect even when all runs are cached: a bad address is an error
            backend = f"dask {dask_address}"
            _execute_dask(missing, dask_address, finished)
        elif not missing:
            backend = "cache"
        elif workers == 1 or len(missing) == 1:
            backend = "in-process"
            for spec in missing:
                finished(compute_run(spec))
        else:
            backend = f"process pool ({int(workers)} workers)"
            _execute_pool(missing, int(workers), finished)
    finally:
        bar.close()
    return ExecutionReport(summaries=summaries, computed=len(summaries) - n_cached, cached=n_cached,
                           wall_time=time.perf_counter() - start, backend=backend)


_BLAS_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


@contextlib.contextmanager
def _single_threaded_blas():
    """One BLAS thread in worker processes started inside this block (unless the user set a number).

    The workers already run in parallel; OpenBLAS's own threads on top oversubscribe the cores, and the
    3D solver's many small factorisations then run several times slower (measured 3x with 2 workers on
    2 cores). Dask's nanny sets the same variables for its workers. The variables are read when the
    library loads, so they are set in this process while the pool spawns its workers, then restored.
    """
    saved = {name: os.environ.get(name) for name in _BLAS_THREAD_VARIABLES}
    for name, value in saved.items():
        if value is None:
            os.environ[name] = "1"
    try:
        yield
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)


_POOLS: dict[int, ProcessPoolExecutor] = {}


def _pool(workers: int) -> ProcessPoolExecutor:
    """The process pool of ``workers`` workers, kept for later studies in this process (their start-up,
    about 1-2 s per worker for imports and numba's cached kernels, is paid once)."""
    import multiprocessing

    pool = _POOLS.get(workers)
    if pool is None or getattr(pool, "_broken", False):
        # spawn, not fork: the parent may hold threads (tqdm monitor, a Dask client, the GUI's server)
        # that a forked child would inherit in an undefined state
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))
        _POOLS[workers] = pool
    return pool


def shutdown_pools() -> None:
    """Stop the worker processes kept by :func:`execute` (also done at interpreter exit)."""
    while _POOLS:
        _, pool = _POOLS.popitem()
        pool.shutdown(wait=True, cancel_futures=True)


atexit.register(shutdown_pools)


def _execute_pool(missing: list[RunSpec], workers: int, finished: Callable[[RunSummary], None]) -> None:
    pool = _pool(workers)
    pending = set()
    try:
        with _single_threaded_blas():  # new workers start (and read these variables) on the first submits
            pending = {pool.submit(compute_run, spec) for spec in missing}
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                finished(future.result())
    except BrokenProcessPool:
        _POOLS.pop(workers, None)
        pool.shutdown(wait=False, cancel_futures=True)
        raise WheelrailError(
            "a study worker process died; in a script, call the study API under "
            "`if __name__ == '__main__':` (workers are spawned and import the main module)"
        ) from None
    except BaseException:
        # interrupted or a run failed: drop the queued runs; the finished ones are already cached
        for future in pending:
            future.cancel()
        if not isinstance(sys.exc_info()[1], Exception):  # KeyboardInterrupt: stop the workers too
            _POOLS.pop(workers, None)
            pool.shutdown(wait=False, cancel_futures=True)
        raise


def _portable(spec: RunSpec, loaded: dict) -> RunSpec:
    """The spec with a user file's roughness loaded into it: Dask workers may run on other machines that
    see the installed bundled sets but not this machine's files (the key is unchanged: it hashes content)."""
    from wheelrail.core.roughness import bundled_names, load_roughness

    if isinstance(spec.source, str | os.PathLike) and str(spec.source) not in bundled_names():
        key = str(spec.source)
        if key not in loaded:
            loaded[key] = load_roughness(spec.source)
        return replace(spec, source=loaded[key])
    return spec


def _execute_dask(missing: list[RunSpec], address: str, finished: Callable[[RunSummary], None]) -> None:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise WheelrailError("--dask needs dask.distributed: pip install 'dask[distributed]'") from None
    address = parse_dask_address(address)
    try:
        client = Client(address, timeout=DASK_CONNECT_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as error:
        first = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise WheelrailError(f"cannot reach the Dask scheduler at {address}: {first}") from None
    try:
        if not missing:
            return
        loaded: dict = {}
        missing = [_portable(spec, loaded) for spec in missing]
        keys = [f"wheelrail-run-{spec.key[:32]}" for spec in missing]
        futures = client.map(compute_run, missing, key=keys, pure=False)
        for future in as_completed(futures):
            finished(future.result())
    finally:
        client.close()


# --------------------------------------------------------------------------------------------------
# Level arithmetic (paper section 3.3)
# --------------------------------------------------------------------------------------------------


def mean_level(levels: Iterable[np.ndarray]) -> np.ndarray:
    """Arithmetic mean of band levels in dB over runs (the paper's averaged spectra of Fig. 10), dB."""
    stack = np.vstack([np.asarray(v, dtype=float) for v in levels])
    return stack.mean(axis=0)


def level_difference(levels_a: np.ndarray, levels_b: np.ndarray) -> np.ndarray:
    """L_a - L_b per band, dB (Figs 12-14, 16, 17)."""
    return np.asarray(levels_a, dtype=float) - np.asarray(levels_b, dtype=float)


def contact_filter(levels_model: np.ndarray, levels_hertz: np.ndarray) -> np.ndarray:
    """Contact filter of a model: its level minus that of ``hertz`` (r_eq = r) on the same line, dB.

    Section 3.3: the Hertz spring without roughness pre-filtering has no contact filtering, so the level
    difference characterises the filtering of the other models (Fig. 10, right column).
    """
    return level_difference(levels_model, levels_hertz)


# --------------------------------------------------------------------------------------------------
# Tables, plans and the named studies
# --------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Table:
    """One CSV table: band centres in Hz and one column per curve, in dB.

    Attributes
    ----------
    name : str
        File stem (``fig10_corrugated-rail_contact_filters``).
    figure : str
        Paper figure it reproduces (``"10"``).
    title : str
        What is tabulated, with units.
    band_centres : ndarray
        Hz.
    columns : dict of str -> ndarray
        Column name (with unit suffix ``_db``) -> values, dB.
    panel : str
        Panel of the figure this table is drawn in (set label, or resolution for Fig. 17).
    """

    name: str
    figure: str
    title: str
    band_centres: np.ndarray
    columns: dict[str, np.ndarray]
    panel: str = ""

    def header(self) -> list[str]:
        return ["band_centre_hz", *self.columns]


def write_table(table: Table, folder: Path) -> Path:
    """Write ``table`` as ``folder/<name>.csv`` atomically (header row, then one row per band)."""
    path = folder / f"{table.name}.csv"

    def write(handle):
        handle.write(",".join(table.header()) + "\n")
        for i, centre in enumerate(table.band_centres):
            cells = [f"{centre:.2f}"] + [("nan" if not np.isfinite(v[i]) else f"{v[i]:.3f}")
                                         for v in table.columns.values()]
            handle.write(",".join(cells) + "\n")

    atomic_write(path, write, mode="w", encoding="utf-8")
    return path


@dataclass(frozen=True, kw_only=True)
class SetInfo:
    """A roughness set as used by a study: source, label, digest, lines, default length."""

    source: object
    label: str
    digest: str
    kind: str
    line_numbers: tuple[int, ...]
    lines: tuple[int, ...]  # the paper's lines -3..3 present in the set
    length: float | None


@dataclass(frozen=True, kw_only=True)
class StudyPlan:
    """A named study: its run specs, and how to turn their summaries into tables and figures."""

    name: str
    sets: tuple[SetInfo, ...]
    specs: tuple[RunSpec, ...]
    tabulate: Callable[[dict[str, RunSummary]], list[Table]]
    speed: float
    length: float | None


def _set_info(source, length: float | None) -> SetInfo:
    from wheelrail.core.roughness import RoughnessSet, load_roughness

    rough = source if isinstance(source, RoughnessSet) else load_roughness(source)
    if isinstance(source, RoughnessSet):
        label = (rough.description.splitlines()[0][:40] if rough.description else "roughness") or "roughness"
    else:
        text = str(source)
        label = Path(text).stem if (os.sep in text or text.endswith((".csv", ".npz"))) else text
    label = re.sub(r"[^A-Za-z0-9_.-]+", "-", label).strip("-") or "roughness"
    numbers = tuple(int(v) for v in rough.line_numbers)
    lines = tuple(v for v in PAPER_LINES if v in numbers)
    if not rough.periodic:
        # one common length for every model: the longest window margin (hertz-winkler's) on both sides
        dx = 1e-3
        usable = math.floor(((rough.n_samples - 1) * rough.dx - 2 * _MARGIN - 2 * dx) / dx + 1e-9) * dx
        if usable <= 0:
            raise WheelrailError(f"{label}: rail data of {rough.length:g} m is too short for a study run")
        if length is None:
            length = usable
        elif length > usable + 1e-9:
            raise WheelrailError(f"run length {length:g} m exceeds the {usable:g} m of {label} usable by every model "
                                 f"(rail data less {_MARGIN * 1e3:g} mm margins)")
    return SetInfo(source=source, label=label, digest=roughness_digest(rough), kind=rough.kind,
                   line_numbers=numbers, lines=lines, length=length)


def _params(speed: float, wheel_mass: float | None = None) -> ModelParameters:
    wheel = WheelParameters() if wheel_mass is None else WheelParameters(unsprung_mass=wheel_mass)
    return ModelParameters(wheel=wheel, run=RunParameters(speed=speed))


def _spec(info: SetInfo, model: str, params: ModelParameters, line: int = 0, **extra) -> RunSpec:
    return RunSpec(source=info.source, set_label=info.label, set_digest=info.digest, model=model, line=line,
                   params=params, length=info.length, **extra)


def _column(line: int) -> str:
    return f"line_{line}_db"


def plan_study(name: str, sets: Sequence, *, speed: float = 100.0 * KMH, length: float | None = None) -> StudyPlan:
    """Build a named study's run specs and table builder.

    Parameters
    ----------
    name : str
        One of ``STUDIES``.
    sets : sequence
        Roughness sets (bundled names, CSV/NPZ paths or ``RoughnessSet``); each gives its own panel.
    speed : float
        Train speed v, m/s (paper: 100 km/h). For ``speeds`` the reference speed of the half-mass case.
    length : float, optional
        Run length, m. Default: the whole set (rail: the data less the largest window margin, the same for
        every model; wheel: one circumference).

    Returns
    -------
    StudyPlan
    """
    if name not in STUDIES:
        raise WheelrailError(f"unknown study {name!r}; choose one of {', '.join(STUDIES)}")
    if not (isinstance(speed, int | float) and math.isfinite(speed) and speed > 0):
        raise WheelrailError(f"speed must be a positive number of m/s, got {speed!r}")
    if length is not None and not (isinstance(length, int | float) and math.isfinite(length) and length > 0):
        raise WheelrailError(f"length must be a positive number of m, got {length!r}")
    if not sets:
        raise WheelrailError("a study needs at least one roughness set")
    infos = tuple(_set_info(source, length) for source in sets)
    labels = [info.label for info in infos]
    if len(set(labels)) != len(labels):
        raise WheelrailError(f"roughness sets must have distinct names, got {', '.join(labels)}")
    builder = _BUILDERS[name]
    specs, tabulate = builder(infos, speed)
    _check_durations(specs, infos)
    return StudyPlan(name=name, sets=infos, specs=tuple(specs), tabulate=tabulate, speed=speed, length=length)


def _check_durations(specs: Sequence[RunSpec], infos: Sequence[SetInfo]) -> None:
    """Every run must outlast the force spectrum's start-up skip by 16 steps (``force_spectrum``)."""
    from wheelrail.core.roughness import RoughnessSet, load_roughness
    from wheelrail.core.spectra import FORCE_SKIP

    circumference = {}
    for info in infos:
        if info.length is None:
            rough = info.source if isinstance(info.source, RoughnessSet) else load_roughness(info.source)
            circumference[info.label] = rough.length
    for spec in specs:
        length = spec.length if spec.length is not None else circumference[spec.set_label]
        dx = spec.params.run.element_size
        needed = FORCE_SKIP * spec.params.run.speed + 16 * dx
        if length < needed:
            raise WheelrailError(
                f"run length {length:g} m at {spec.speed_kmh:g} km/h is too short for a force spectrum, which "
                f"skips the first {FORCE_SKIP:g} s; use at least {math.ceil(needed * 100) / 100:g} m"
            )


def _levels(summaries, spec: RunSpec) -> np.ndarray:
    return summaries[spec.key].levels


def _centres(summaries, spec: RunSpec) -> np.ndarray:
    return summaries[spec.key].band_centres


def _plan_filters(infos, speed):
    params = _params(speed)
    specs, layout = [], {}
    for info in infos:
        one_line = {(model, line): _spec(info, model, params, line) for model in ONE_LINE_MODELS
                    for line in info.lines}
        three_d = _spec(info, "3d", params, 0)
        layout[info.label] = (info, one_line, three_d)
        specs += [*one_line.values(), three_d]

    def tabulate(summaries):
        tables = []
        for label, (info, one_line, three_d) in layout.items():
            centres = _centres(summaries, three_d)
            level = {model: [_levels(summaries, one_line[model, line]) for line in info.lines]
                     for model in ONE_LINE_MODELS}
            l3d = _levels(summaries, three_d)
            spectra = {"3d_db": l3d, **{f"{m.replace('-', '_')}_db": mean_level(level[m]) for m in ONE_LINE_MODELS}}
            filters = {"3d_db": mean_level([contact_filter(l3d, h) for h in level["hertz"]])}
            for model in ("2d", "hertz-winkler", "hertz-average"):
                filters[f"{model.replace('-', '_')}_db"] = mean_level(
                    [contact_filter(v, h) for v, h in zip(level[model], level["hertz"], strict=True)])
            lines = f"lines {info.lines[0]}..{info.lines[-1]}"
            tables.append(Table(name=f"fig10_{label}_force_levels", figure="10", panel=label, columns=spectra,
                                title=f"{label}: contact-force levels, dB re 1 N (one-line models: mean of {lines})",
                                band_centres=centres))
            tables.append(Table(name=f"fig10_{label}_contact_filters", figure="10", panel=label, columns=filters,
                                title=f"{label}: contact filter L - L_hertz, dB (mean over {lines})",
                                band_centres=centres))
        return tables

    return specs, tabulate


_PAIRS = (  # Figs 12-14: (figure, model a, model b)
    ("12", "3d", "2d"),
    ("13", "2d", "hertz-winkler"),
    ("14", "2d", "hertz-average"),
)


def _plan_line_spread(infos, speed):
    params = _params(speed)
    specs, layout = [], {}
    for info in infos:
        runs = {(model, line): _spec(info, model, params, line) for model in ("2d", "hertz-winkler", "hertz-average")
                for line in info.lines}
        runs["3d", None] = _spec(info, "3d", params, 0)
        layout[info.label] = (info, runs)
        specs += list(runs.values())

    def tabulate(summaries):
        tables = []
        for label, (info, runs) in layout.items():
            centres = _centres(summaries, runs["3d", None])
            for figure, a, b in _PAIRS:
                columns = {}
                for line in info.lines:
                    la = _levels(summaries, runs[a, None if a == "3d" else line])
                    columns[_column(line)] = level_difference(la, _levels(summaries, runs[b, line]))
                columns["mean_db"] = mean_level(columns.values())
                stem = f"{a}_minus_{b}".replace("-", "_")
                tables.append(Table(name=f"fig{figure}_{label}_{stem}", figure=figure, panel=label,
                                    title=f"{label}: L_{a} - L_{b} per line and mean, dB",
                                    band_centres=centres, columns=columns))
        return tables

    return specs, tabulate


def _plan_averaged_input(infos, speed):
    params = _params(speed)
    layout = {info.label: (_spec(info, "3d", params, 0), _spec(info, "2d", params, 0, averaged_lines=info.lines))
              for info in infos}

    def tabulate(summaries):
        columns, centres = {}, None
        for label, (three_d, averaged) in layout.items():
            centres = _centres(summaries, three_d)
            columns[f"{label}_db"] = level_difference(_levels(summaries, three_d), _levels(summaries, averaged))
        return [Table(name="fig16_3d_minus_2d_averaged_input", figure="16", band_centres=centres, columns=columns,
                      title="L_3D - L_2D,av: 2D fed with the mean of lines -3..3, dB")]

    return [spec for pair in layout.values() for spec in pair], tabulate


def _mm(values) -> str:
    return ", ".join(f"{v:g}" for v in values)


def _plan_lateral_resolution(infos, speed):
    params = _params(speed)
    layout = {}
    for info in infos:
        runs = {"original": _spec(info, "3d", params, 0)}
        for resolution, kept in LOW_RESOLUTION_LINES_MM.items():
            runs[resolution] = _spec(info, "3d", params, 0, lateral_lines_mm=kept)
        layout[info.label] = runs

    def tabulate(summaries):
        tables = []
        for resolution, kept in LOW_RESOLUTION_LINES_MM.items():
            columns, centres = {}, None
            for label, runs in layout.items():
                centres = _centres(summaries, runs["original"])
                columns[f"{label}_db"] = level_difference(_levels(summaries, runs["original"]),
                                                          _levels(summaries, runs[resolution]))
            tables.append(Table(name=f"fig17_3d_minus_3d_{resolution}mm", figure="17", band_centres=centres,
                                columns=columns, panel=f"{resolution} mm",
                                title=f"L_3D - L_3D,{resolution}mm (lines at {_mm(kept)} mm), dB"))
        return tables

    return [spec for runs in layout.values() for spec in runs.values()], tabulate


def _speed_cases(speed):
    cases = [(f"{v:g}_kmh_db", v * KMH, None) for v in PAPER_SPEEDS_KMH]
    cases.append((f"{speed / KMH:g}_kmh_half_mass_db", speed, HALF_WHEEL_MASS))
    return cases


def _plan_speeds(infos, speed):
    layout = {info.label: {column: _spec(info, "2d", _params(v, mass), 0) for column, v, mass in _speed_cases(speed)}
              for info in infos}

    def tabulate(summaries):
        tables = []
        for label, runs in layout.items():
            columns = {column: _levels(summaries, spec) for column, spec in runs.items()}
            centres = _centres(summaries, next(iter(runs.values())))
            tables.append(Table(name=f"fig11_{label}_speeds", figure="11", panel=label, band_centres=centres,
                                columns=columns,
                                title=f"{label}: 2D on line 0, contact-force levels at several speeds, dB re 1 N"))
        return tables

    return [spec for runs in layout.values() for spec in runs.values()], tabulate


_BUILDERS = {
    "filters": _plan_filters,
    "line-spread": _plan_line_spread,
    "averaged-input": _plan_averaged_input,
    "lateral-resolution": _plan_lateral_resolution,
    "speeds": _plan_speeds,
}


# --------------------------------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------------------------------

_STYLES = {  # Fig. 10's legend: thick grey 3D, then the one-line models
    "3d_db": {"color": "0.55", "linewidth": 3.0, "label": "3D"},
    "2d_db": {"color": "k", "linewidth": 1.2, "label": "2D"},
    "hertz_db": {"color": "tab:red", "linewidth": 1.0, "linestyle": ":", "label": "Hertz, no pre-filter"},
    "hertz_winkler_db": {"color": "tab:blue", "linewidth": 1.0, "linestyle": "--",
                         "label": "Hertz, Winkler pre-filter"},
    "hertz_average_db": {"color": "tab:green", "linewidth": 1.0, "linestyle": "-.",
                         "label": "Hertz, averaging pre-filter"},
}
_SET_STYLES = ("-", "--", "-.", ":")


def _axes_grid(n_rows: int, n_cols: int, *, height: float = 2.6):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(5.0 * n_cols, height * n_rows + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(n_rows, n_cols, squeeze=False)
    return figure, axes


def _frequency_axis(ax, table: Table, ylabel: str) -> None:
    from wheelrail.core.spectra import nominal_band_label

    ax.set_xscale("log")
    ticks = [c for c in table.band_centres if nominal_band_label(c) in ("63", "125", "250", "500", "1000", "2000",
                                                                          "4000", "8000")]
    ax.set_xticks(ticks, [nominal_band_label(c) for c in ticks])
    ax.minorticks_off()
    ax.set_xlabel("third-octave band centre frequency (Hz)")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)


def plot_study(name: str, tables: list[Table], folder: Path) -> list[Path]:
    """Draw the study's figure(s) like the paper's (Agg backend, PNG) into ``folder``; returns the paths."""
    by_figure: dict[str, list[Table]] = {}
    for table in tables:
        by_figure.setdefault(table.figure, []).append(table)
    paths = []
    for figure_id, group in by_figure.items():
        if figure_id == "10":
            panels = sorted({t.panel for t in group}, key=[t.panel for t in group].index)
            figure, axes = _axes_grid(len(panels), 2)
            for row, panel in enumerate(panels):
                levels = next(t for t in group if t.panel == panel and t.name.endswith("force_levels"))
                filters = next(t for t in group if t.panel == panel and t.name.endswith("contact_filters"))
                for ax, table, ylabel in ((axes[row, 0], levels, "L_F (dB re 1 N)"),
                                          (axes[row, 1], filters, "contact filter (dB)")):
                    for column, values in table.columns.items():
                        ax.plot(table.band_centres, values, **_STYLES.get(column, {"label": column}))
                    _frequency_axis(ax, table, ylabel)
                    ax.set_title(panel, fontsize=9)
                axes[row, 0].legend(fontsize=7)
        elif figure_id in ("12", "13", "14", "11"):
            figure, axes = _axes_grid(len(group), 1)
            for ax, table in zip(axes[:, 0], group, strict=True):
                for column, values in table.columns.items():
                    if column == "mean_db":
                        ax.plot(table.band_centres, values, color="k", linewidth=2.5, label="mean")
                    else:
                        ax.plot(table.band_centres, values, linewidth=0.9,
                                label=column.removesuffix("_db").replace("_", " "),
                                marker="x" if column.startswith("100_kmh") else None)
                _frequency_axis(ax, table, "L_F (dB re 1 N)" if figure_id == "11" else "level difference (dB)")
                ax.set_title(table.title, fontsize=9)
                ax.legend(fontsize=6, ncol=2)
        else:  # 16, 17: one curve per set, one panel per table
            figure, axes = _axes_grid(len(group), 1)
            for ax, table in zip(axes[:, 0], group, strict=True):
                for i, (column, values) in enumerate(table.columns.items()):
                    ax.plot(table.band_centres, values, color="k", linestyle=_SET_STYLES[i % len(_SET_STYLES)],
                            label=column.removesuffix("_db"))
                ax.axhline(0.0, color="0.7", linewidth=0.8)
                _frequency_axis(ax, table, "level difference (dB)")
                ax.set_title(table.title, fontsize=9)
                ax.legend(fontsize=7)
        figure.suptitle(f"wheelrail study {name}: paper Fig. {figure_id}", fontsize=10)
        path = folder / f"fig{figure_id}_{name}.png"
        atomic_write(path, lambda handle, fig=figure: fig.savefig(handle, format="png", dpi=110))
        paths.append(path)
    return paths


# --------------------------------------------------------------------------------------------------
# The whole study
# --------------------------------------------------------------------------------------------------


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
    cache: str | os.PathLike | None = None,
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
    cache : path, optional
        Folder of finished runs (default ``out/runs``), so an interrupted study resumes.
    progress : bool
        tqdm bar of runs done on stderr.
    figures : bool
        Draw the PNG figure(s) (about 1 s each with matplotlib); the CSV tables and JSON are always written.

    Returns
    -------
    StudyResult
    """
    folder = check_output_folder(out)
    if dask_address is not None:
        dask_address = parse_dask_address(dask_address)
    plan = plan_study(name, sets, speed=speed, length=length)
    report = execute(plan.specs, cache=folder / "runs" if cache is None else Path(cache), workers=workers,
                     dask_address=dask_address, progress=progress, description=f"study {name}")
    tables = plan.tabulate(report.summaries)
    files = [write_table(table, folder) for table in tables]
    if figures:
        files += plot_study(name, tables, folder)
    summaries = [report.summaries[spec.key] for spec in plan.specs]
    summary = {
        "study": name,
        "sets": [info.label for info in plan.sets],
        "speed_m_per_s": speed,
        "speed_kmh": speed / KMH,
        "length_m": {info.label: info.length for info in plan.sets},
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
                "band_centres_hz": table.band_centres,
                **{column: [None if not np.isfinite(v) else round(float(v), 3) for v in values]
                   for column, values in table.columns.items()},
            }
            for table in tables
        },
    }
    summary_path = folder / f"{name}_summary.json"
    atomic_write(summary_path, lambda handle: json.dump(json_ready(summary), handle, indent=2), mode="w")
    files.append(summary_path)
    summary["files"].append(str(summary_path))
    return StudyResult(name=name, tables=tables, files=files, report=report, summary=summary)
