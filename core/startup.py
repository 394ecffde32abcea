"""A process's start-up: numpy's rarely used sub-packages loaded on first use, not by numba's first cached load.

numba's first call of a compiled function in a process, even one read from its disk cache, loads its whole
CPU target (``numba.core.cpu.CPUContext.load_additional_registries``); its ``numba.np.arraymath`` checks
for BLAS by importing ``scipy.linalg.cython_blas``, hence all of ``scipy.linalg``, whose
``scipy._lib.array_api_compat.numpy`` copies every public name of numpy (``from numpy import *``): numpy then
imports, on demand, ``numpy.f2py`` (with ``charset_normalizer``), ``numpy.ma`` and ``numpy.testing`` (with
``unittest``). None of them is used by wheelrail; together they were 0.2-0.3 s of a cached ``wheelrail run``
of 1.1-1.7 s (``python -X importtime``; ``benchmarks/startup.py``).

:func:`defer_numpy_submodules` gives numpy these sub-packages as modules that load themselves on their first
attribute access (``importlib.util.LazyLoader``, the standard library's lazy import): copying the name costs
nothing, and any use (``numpy.ma.masked_array``, ``import numpy.ma``) loads the real module as before.
The command line and the study's worker processes call it first thing; a library user's process is left as
it is.
"""

from __future__ import annotations

import importlib.util
import sys

__all__ = ["DEFERRED_NUMPY_SUBMODULES", "defer_numpy_submodules"]

DEFERRED_NUMPY_SUBMODULES = ("numpy.f2py", "numpy.ma", "numpy.testing")


def defer_numpy_submodules() -> None:
    """Make each of ``DEFERRED_NUMPY_SUBMODULES`` not imported yet load on its first attribute access."""
    import numpy

    for name in DEFERRED_NUMPY_SUBMODULES:
        if name in sys.modules:
            continue
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None:
            continue
        loader = importlib.util.LazyLoader(spec.loader)
        spec.loader = loader
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        loader.exec_module(module)  # LazyLoader: only marks the module to execute on first attribute access
        # numpy's module __getattr__ imports a sub-package on first access: give it the lazy one instead
        setattr(numpy, name.rpartition(".")[2], module)
