"""The command line's start-up (``wheelrail.core.startup``): numba's first cached load imports neither
``scipy.linalg``'s package nor numpy's unused sub-packages, and each still works when used."""

from __future__ import annotations

import subprocess
import sys

_CHECK = """
import sys
from wheelrail.core.startup import defer_numpy_submodules
defer_numpy_submodules()
import numpy as np
from numba.np.linalg import ensure_blas
ensure_blas()  # what numba's first load (even from its cache) does: scipy.linalg, its copy of numpy's names
loaded = [name for name in ("numpy.f2py", "numpy.ma", "numpy.testing", "charset_normalizer")
          if type(sys.modules.get(name)).__name__ == "module"]
print("loaded:", loaded)
masked = np.ma.masked_array([1.0, 2.0], mask=[True, False])  # first use loads numpy.ma
import numpy.testing
numpy.testing.assert_allclose(masked.sum(), 2.0)
import numpy.f2py
print("f2py:", callable(numpy.f2py.run_main), "ma:", type(sys.modules["numpy.ma"]).__name__)
"""


def test_deferred_numpy_submodules_load_on_first_use_only():
    done = subprocess.run([sys.executable, "-c", _CHECK], capture_output=True, text=True, check=True, timeout=120)
    lines = done.stdout.splitlines()
    # numba's first load no longer pulls in numpy.f2py (and charset_normalizer), numpy.ma, numpy.testing
    assert lines[0] == "loaded: []", done.stdout
    # and each still works as before once used (LazyLoader loads the real module on first attribute access)
    assert lines[1] == "f2py: True ma: module", done.stdout


_BLAS = """
import sys
from wheelrail.core.startup import fast_start
fast_start()
import numpy as np
from numba import njit
from numba.np.linalg import ensure_blas
ensure_blas()  # numba's BLAS check, as its first load does
print("package:", "scipy.linalg" in sys.modules, type(sys.modules["scipy.linalg.cython_blas"]).__name__)

@njit
def product(a, b):
    return np.dot(a, b)  # numba calls BLAS through the module's function pointers

a = np.arange(9.0).reshape(3, 3)
print("dot:", np.array_equal(product(a, a.T), a @ a.T))
import scipy.linalg
from scipy.linalg import cython_blas
same = cython_blas is sys.modules["scipy.linalg.cython_blas"]
print("later:", scipy.linalg.solve(np.eye(2) * 2.0, np.ones(2)).tolist(), same)
"""


def test_numbas_blas_check_loads_the_blas_module_without_scipy_linalg():
    done = subprocess.run([sys.executable, "-c", _BLAS], capture_output=True, text=True, check=True, timeout=300)
    lines = done.stdout.splitlines()
    assert lines[0] == "package: False module", done.stdout  # the extension module alone, not its package
    assert lines[1] == "dot: True", done.stdout  # and it is the real one: compiled BLAS calls work through it
    assert lines[2] == "later: [0.5, 0.5] True", done.stdout  # scipy.linalg, imported later, is whole


def test_reading_a_result_does_not_import_numba():
    """``wheelrail spectra`` reads a saved run: parameters (Hertz's solution), results and spectra load without
    numba (its import is ~0.2 s; the loop's compiled Hertz kernels are in contact.hertz_law)."""
    code = "import sys, wheelrail.core.engine.results, wheelrail.core.spectra.force; print('numba' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    assert done.stdout.strip() == "False", done.stdout


_ON_IMPORT = """
import sys
from wheelrail.core.startup import fast_start_on_import
fast_start_on_import()
import numpy as np
print("before:", sorted(name for name in sys.modules if name.startswith(("numba", "scipy"))))
import numba
from numba.np.linalg import ensure_blas
ensure_blas()
print("numba:", "scipy.linalg" in sys.modules, type(sys.modules["scipy.linalg.cython_blas"]).__name__,
      type(sys.modules["numpy.f2py"]).__name__)
"""

_SCIPY_FIRST = """
import sys
from wheelrail.core.startup import fast_start_on_import
fast_start_on_import()
import scipy.special
print("scipy:", type(sys.modules["numpy.f2py"]).__name__, "scipy.linalg.cython_blas" in sys.modules)
"""


def test_the_command_lines_start_up_runs_when_numba_or_scipy_is_first_imported():
    """``fast_start_on_import``: nothing until numba is imported, then the BLAS module alone and numpy's deferred
    sub-packages before numba's first load; scipy imported first defers numpy's sub-packages only."""
    done = subprocess.run([sys.executable, "-c", _ON_IMPORT], capture_output=True, text=True, check=True, timeout=300)
    assert done.stdout.splitlines() == ["before: []", "numba: False module _LazyModule"], done.stdout
    done = subprocess.run([sys.executable, "-c", _SCIPY_FIRST], capture_output=True, text=True, check=True, timeout=300)
    assert done.stdout.splitlines() == ["scipy: _LazyModule False"], done.stdout


_BESIDE = """
import sys, threading
from wheelrail.core import startup
startup.fast_start_on_import()
inside, other_done = threading.Event(), threading.Event()
real = startup.fast_start

def held():  # numba's start-up, waiting for the other thread's import before it goes on
    inside.set()
    print("other import done during the start-up:", other_done.wait(60))
    real()

startup.fast_start = held
assert "colorsys" not in sys.modules

def other():
    inside.wait(60)
    import colorsys  # any import in another thread needs the import system's global lock for a moment
    other_done.set()

thread = threading.Thread(target=other)
thread.start()
import numba
thread.join(60)
print("numba:", type(sys.modules["scipy.linalg.cython_blas"]).__name__, "scipy.linalg" in sys.modules)
"""


def test_the_start_up_lets_other_threads_import_while_it_runs():
    """The start-up's imports run as numba's package executes (under its module lock), not inside the finder's
    ``find_spec``, which the import system calls holding its global lock: there, a study thread importing scipy
    while the main thread's first ``import numba`` loaded the BLAS module deadlocked the two (the BLAS module waited
    on scipy's module lock, the other thread on the global lock). The other thread's import here finishes while the
    start-up waits for it (``Event.wait`` returns at once when it does; its 60 s only bound a regression)."""
    done = subprocess.run([sys.executable, "-c", _BESIDE], capture_output=True, text=True, check=True, timeout=300)
    assert done.stdout.splitlines() == [
        "other import done during the start-up: True",
        "numba: module False",
    ], done.stdout
