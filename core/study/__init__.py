"""Studies: batches of independent runs, their force spectra, contact filters and model differences.

This reproduces the paper's section 3.3-3.5 on any roughness set (Pieringer, Kropp & Thompson, Wear 271,
2011). A study is a list of independent :class:`RunSpec` (set, line, model, speed, wheel
mass, length, input transform) -> one :class:`RunSummary` each (third-octave force spectrum of
:func:`wheelrail.core.spectra.force.force_spectrum` plus a few force statistics, no pressure maps) -> tables of
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
``noise`` (beyond the paper)
    The one-line models (plug-ins included) and ``3d`` on line 0 at 50-300 km/h: A-weighted sound power per
    axle and pass-by level by this project's TWINS-like chain, beside the CNOSSOS-EU source with A3 and with
    each model's dynamic contact filter in its place (:mod:`wheelrail.core.study.noise_plan`).
``impact`` (beyond the paper)
    Discrete irregularities (a wheel flat, a rail joint, a dipped weld, a squat; any of their inputs swept) per
    model and speed on line 0: peak and minimum force, time without contact, the lowest speed with loss of contact,
    the run's sound power and its slope in dB per doubling of speed (:mod:`wheelrail.core.study.impact_plan`).

Runs are executed by :func:`execute`: already cached runs are read back, the missing ones run on forked copies of
this process (Linux, where no other thread is alive), in threads of it (the compiled laws release the GIL), on a
local process pool (``concurrent.futures.ProcessPoolExecutor``)
or on a Dask cluster (``dask.distributed``), the new tracks they need prepared once each beforehand, and
each finished run is written at once, atomically, to ``<cache>/<key>.npz`` where the key is a SHA-256
hash of the full run spec (roughness content, model, line, input transform, all model parameters, run
and spectrum settings). An interrupted study therefore resumes and only computes the missing runs; an
unusable run file (damaged, wrong shapes, NaN) is computed again with a warning.

Modules, by concern: ``specs`` (run specs, summaries, the worker task), ``store`` (run files),
``execution`` (the choice of workers, process pool, Dask, shutdown), ``forked`` (runs on forked copies of the
study's process), ``figure_workers`` (figures on two processes), ``threads`` (runs in threads of one process),
``precompute`` (new tracks, once each), ``plans`` (the named studies and their tables), ``tables``
(CSV), ``figures`` (PNG), ``runner`` (:func:`run_study`). The level arithmetic (:func:`mean_level`,
:func:`contact_filter`, :func:`level_difference`) lives in :mod:`wheelrail.core.spectra.levels` and is re-exported.
"""

from wheelrail.core.spectra.levels import contact_filter, level_difference, mean_level
from wheelrail.core.study.execution import (
    ExecutionReport,
    StudyTerminated,
    execute,
    parse_dask_address,
    shutdown_pools,
)
from wheelrail.core.study.figures import plot_study
from wheelrail.core.study.plans import SetInfo, StudyPlan, plan_study
from wheelrail.core.study.runner import StudyResult, check_output_folder, run_study
from wheelrail.core.study.specs import (
    HALF_WHEEL_MASS,
    LOW_RESOLUTION_LINES_MM,
    PAPER_LINES,
    PAPER_SPEEDS_KMH,
    REFERENCE_MODEL,
    STUDIES,
    STUDY_FORMAT_VERSION,
    RunSpec,
    RunSummary,
    compute_run,
    one_line_models,
    roughness_digest,
    study_roughness,
    study_wheel_roughness,
)
from wheelrail.core.study.tables import Table, write_table

__all__ = [
    "STUDIES",
    "PAPER_LINES",
    "one_line_models",
    "REFERENCE_MODEL",
    "LOW_RESOLUTION_LINES_MM",
    "PAPER_SPEEDS_KMH",
    "HALF_WHEEL_MASS",
    "STUDY_FORMAT_VERSION",
    "RunSpec",
    "RunSummary",
    "Table",
    "SetInfo",
    "StudyPlan",
    "StudyResult",
    "ExecutionReport",
    "StudyTerminated",
    "roughness_digest",
    "study_roughness",
    "compute_run",
    "study_wheel_roughness",
    "execute",
    "contact_filter",
    "mean_level",
    "level_difference",
    "plan_study",
    "run_study",
    "write_table",
    "plot_study",
    "check_output_folder",
    "parse_dask_address",
    "shutdown_pools",
]
