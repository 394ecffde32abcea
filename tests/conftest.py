"""Shared test set-up: the tests' own Green's-function cache, never the user's, kept between sessions.

The track's Green's functions take 15-45 s to compute per track; a private cache per session made every
session compute them again (most of the fast suite's time). The tests' cache is a folder of the checkout,
``.pytest_cache/wheelrail-cache/<code>``, where ``<code>`` is a hash of the source files whose code decides
what a cache entry holds (``CACHED_CODE``: the track, the wheel, the rail's radiation): entries are keyed by
their parameters (``core.files.cache``), the folder by the code that computed them, so a change of the track's code
starts an empty folder and no test ever reads an entry an older code wrote. The folders of other code are
removed but for the last one used (a branch switched back and forth keeps its entries). A fresh clone (CI)
starts empty: the first session computes the tracks it needs. ``WHEELRAIL_TEST_CACHE_DIR`` puts the folders
elsewhere (an empty folder gives a cold session, as on a fresh clone).
"""

import dataclasses
import hashlib
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from wheelrail.core.engine.results import RunResult

ROOT = Path(__file__).resolve().parents[1]
# the sources whose code decides the content of a cache entry (its key holds only the parameters): every module
# that writes entries, with what it computes them from (tests/unit/test_tests_cache.py checks the writers)
CACHED_CODE = (
    "core/files/cache.py",
    "core/parameters.py",
    "core/track/*.py",
    "core/wheel.py",
    "core/modal_wheel/*.py",
    "core/noise/radiation.py",
    "core/noise/decay.py",
    "core/noise/twins.py",
    "core/noise/track_part_store.py",
    "core/noise/track_vibration.py",
    "core/noise/wheel_power.py",
    "cli/commands/track.py",
)
KEEP_FOLDERS = 2  # code versions whose entries are kept (the whole suite fills ~570 MB per version)


def code_hash() -> str:
    digest = hashlib.sha256()
    for pattern in CACHED_CODE:
        for path in sorted(ROOT.glob(pattern)):
            digest.update(path.relative_to(ROOT).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def _test_cache_folder() -> Path:
    chosen = os.environ.get("WHEELRAIL_TEST_CACHE_DIR")
    base = Path(chosen).expanduser() if chosen else ROOT / ".pytest_cache" / "wheelrail-cache"
    folder = base / code_hash()
    folder.mkdir(parents=True, exist_ok=True)
    folder.touch()  # its time of last use, for the clean-up below
    others = sorted((p for p in base.iterdir() if p.is_dir() and p != folder), key=lambda p: p.stat().st_mtime)
    for stale in others[: max(0, len(others) - (KEEP_FOLDERS - 1))]:
        shutil.rmtree(stale, ignore_errors=True)
    return folder


@pytest.fixture(autouse=True, scope="session")
def _tests_cache():
    path = _test_cache_folder()
    old = os.environ.get("WHEELRAIL_CACHE_DIR")
    os.environ["WHEELRAIL_CACHE_DIR"] = str(path)
    yield path
    if old is None:
        os.environ.pop("WHEELRAIL_CACHE_DIR", None)
    else:
        os.environ["WHEELRAIL_CACHE_DIR"] = old


# the arrays a run holds over its steps (time, x, force, ...): RunResult's fields typed as one array, read from the
# class so that a test comparing two runs array by array compares every one, a new one included
STEP_ARRAYS = tuple(f.name for f in dataclasses.fields(RunResult) if f.type in ("np.ndarray", np.ndarray))


@pytest.fixture(scope="session")
def step_arrays() -> tuple[str, ...]:
    """The names of a run's arrays over its steps (:data:`STEP_ARRAYS`)."""
    return STEP_ARRAYS
