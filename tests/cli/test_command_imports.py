"""Each command's start-up imports only what it uses: every command run on a tiny input in a fresh process, then
the heavy packages (numba, scipy, matplotlib, rerun, viser, dask) found in ``sys.modules`` compared with the
ones that command uses. A command that never calls compiled code imports neither numba nor scipy's BLAS module
(``wheelrail.core.startup.fast_start_on_import``); one that does loads that module alone, not ``scipy.linalg``."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.parameters import ModelParameters

HEAVY = ("numba", "scipy", "matplotlib", "rerun", "viser", "dask")

_PROBE = """
import sys
from wheelrail.cli import main
code = main(sys.argv[1:])
heavy = sorted({name.partition(".")[0] for name in sys.modules} & set(HEAVY))
scipy = sorted(name for name in ("scipy.linalg", "scipy.linalg.cython_blas", "scipy.spatial") if name in sys.modules)
modal = "wheelrail.core.modal_wheel" in sys.modules
print("LOADED", code, ",".join(heavy), ",".join(scipy), modal)
"""


def _loaded(tmp_path, *argv: str) -> tuple[int, set[str], set[str], bool]:
    """Run ``wheelrail *argv`` in a fresh process in ``tmp_path``: its exit code, the heavy packages it imported,
    which of scipy's linear-algebra modules, and whether the modal wheel's package."""
    code = f"HEAVY = {HEAVY!r}\n{_PROBE}"
    done = subprocess.run(
        [sys.executable, "-c", code, *argv], capture_output=True, text=True, cwd=tmp_path, timeout=600, check=False
    )
    line = next((line for line in done.stdout.splitlines() if line.startswith("LOADED ")), None)
    assert line is not None, done.stderr
    _, exit_code, heavy, scipy, modal = line.split(" ")
    return int(exit_code), set(filter(None, heavy.split(","))), set(filter(None, scipy.split(","))), modal == "True"


def _run_file(path) -> str:
    n = 2000
    t = np.arange(n) * 1e-3 / (100 / 3.6)
    zeros = np.zeros(n)
    result = RunResult(
        header=RunHeader(model="hertz", line=0, roughness_name="corrugated-rail", params=ModelParameters()),
        time=t,
        x=np.arange(n) * 1e-3,
        force=65e3 + 2e3 * np.sin(2 * np.pi * 501.187 * t),
        xi_wheel=zeros,
        xi_rail=zeros,
        roughness=zeros,
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5),
        equivalent_roughness=zeros,
    )
    return str(result.save_npz(path / "run.npz"))


def test_spectra_imports_neither_numba_nor_scipy(tmp_path):
    """``wheelrail spectra`` reads a saved run and takes numpy's FFT: no numba, no scipy (not even the BLAS module
    numba's first load wants, which a start-up that loads it for every command would bring)."""
    assert _loaded(tmp_path, "spectra", _run_file(tmp_path)) == (0, set(), set(), False)


@pytest.mark.parametrize(
    ("argv", "uses"),
    [
        (("datasets",), set()),
        (("cache", "list"), set()),
        (("filters",), {"scipy"}),  # the analytic filters' Bessel functions (scipy.special)
        (("noise", "--method", "cnossos"), {"scipy"}),  # scipy.special
        (("roughness", "--set", "corrugated-rail"), {"scipy"}),  # the coherence's cross spectra (scipy.signal)
        # stopped by their own input checks: the command's module and its checks, nothing heavy
        (("study", "filters", "--set", "corrugated-rail", "--length-m", "0", "--out", "out"), set()),
        (("explore", "--port", "70000"), set()),
    ],
    ids=lambda value: value[0] if isinstance(value, tuple) else None,
)
def test_commands_without_compiled_code_import_no_numba(tmp_path, argv, uses):
    code, heavy, scipy, modal = _loaded(tmp_path, *argv)
    assert code == (2 if argv[0] in ("study", "explore") else 0)
    assert heavy == uses, argv
    assert not modal, argv
    # numba's BLAS module is not loaded for it (scipy.signal's imports load all of scipy.linalg: roughness)
    assert "scipy.linalg.cython_blas" not in scipy or "scipy.linalg" in scipy, argv


@pytest.mark.slow
def test_wheel_imports_scipy_but_not_numba(tmp_path):
    """The modal wheel's finite elements are scipy's sparse eigen-solves; nothing of it is compiled."""
    code, heavy, _scipy, modal = _loaded(tmp_path, "wheel", "--json")
    assert (code, heavy, modal) == (0, {"scipy"}, True)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("argv", "scipy_modules"),
    [
        # a cached run: numba and its BLAS module alone, not scipy.linalg's package nor the modal wheel's modules
        (("run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "0.5", "--out", "r.npz"), set()),
        # a cached track: its receptances are FE solves with scipy.linalg
        (("track", "--json"), {"scipy.linalg"}),
    ],
    ids=["run", "track"],
)
def test_commands_with_compiled_code_import_numba_and_only_what_they_use(tmp_path, argv, scipy_modules):
    _loaded(tmp_path, *argv)  # the track's Green's functions computed and cached if they are not yet
    code, heavy, scipy, modal = _loaded(tmp_path, *argv)
    assert (code, heavy, modal) == (0, {"numba", "scipy"}, False), argv
    assert scipy == {"scipy.linalg.cython_blas", *scipy_modules}, argv
