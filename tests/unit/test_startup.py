"""The command line's start-up (``wheelrail.core.startup``): numpy's unused sub-packages are not loaded by
numba's first cached load, and still work when used."""

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
