"""A process's start-up: what numba's first cached load imports, cut to what it uses.

numba's first call of a compiled function in a process, even one read from its disk cache, loads its whole
CPU target (``numba.core.cpu.CPUContext.load_additional_registries``); its ``numba.np.arraymath`` checks
for BLAS by importing ``scipy.linalg.cython_blas`` (``numba.np.linalg.ensure_blas``). Importing a submodule
imports its package first, so that check would run all of ``scipy.linalg`` (far more than the extension module
itself), whose ``scipy._lib.array_api_compat.numpy`` copies every public name of numpy
(``from numpy import *``): numpy then imports, on demand, ``numpy.f2py`` (with ``charset_normalizer``),
``numpy.ma`` and ``numpy.testing`` (with ``unittest``). These imports are a large share of a cached
``wheelrail run``'s start-up (``python -X importtime`` shows them; ``benchmarks/startup.py`` times the start-up).

:func:`fast_start` does two things, both the standard library's import machinery, nothing of numba's:

- :func:`load_cython_blas_alone` loads the extension module ``scipy.linalg.cython_blas`` from its file into
  ``sys.modules`` without running ``scipy/linalg/__init__.py``. It is the same module (numba reads its
  ``__pyx_capi__`` function pointers from it when a compiled function calls BLAS); the BLAS integer width numba
  checks is still read from ``scipy.__config__``. ``import scipy.linalg`` later loads the whole package as
  usual; ``from scipy.linalg import cython_blas`` then gives this module.
- :func:`defer_numpy_submodules` gives numpy the sub-packages above as modules that load themselves on their
  first attribute access (``importlib.util.LazyLoader``): copying a name costs nothing, and any use
  (``numpy.ma.masked_array``, ``import numpy.ma``) loads the real module then. It still counts when
  something imports ``scipy.linalg`` (the noise model's banded solves do).

A study's worker processes, which always run compiled code, call :func:`fast_start` first thing. The command
line calls :func:`fast_start_on_import` instead: its steps run only when numba or scipy is first imported, so
that a command that uses neither (``wheelrail spectra``, ``datasets``, ``cache``) imports neither. A library
user's process is left as it is.
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import importlib.util
import os
import sys
import threading

__all__ = [
    "DEFERRED_NUMPY_SUBMODULES",
    "defer_numpy_submodules",
    "fast_start",
    "fast_start_on_import",
    "load_cython_blas_alone",
]

_CYTHON_BLAS = "scipy.linalg.cython_blas"


def fast_start() -> None:
    """Start-up of a command-line or worker process: :func:`load_cython_blas_alone`, then
    :func:`defer_numpy_submodules` (before numba's first load)."""
    load_cython_blas_alone()
    defer_numpy_submodules()


class _OnFirstImport(importlib.abc.MetaPathFinder):
    """A finder first on ``sys.meta_path`` that sees the first import of numba (then :func:`fast_start` runs) and of
    scipy (then :func:`defer_numpy_submodules` runs), before the package's own code. It returns the spec the other
    finders give with its loader wrapped (:class:`_WorkFirst`): the work runs when the package's module is executed,
    under that module's import lock like the package's own imports, never in ``find_spec``, which the import system
    calls holding its global lock (an import there waits on every other thread's import, and one of those may wait
    on it: a deadlock). It stays on ``sys.meta_path`` (the import system iterates that list while it asks each
    finder), its work done once."""

    def __init__(self) -> None:
        self._lock = threading.Lock()  # held only to claim the work, never around an import
        self.started = False  # fast_start claimed
        self.deferred = False  # defer_numpy_submodules claimed

    def run_work(self, fullname: str) -> None:
        """The work of the first import of ``fullname``, if not claimed yet (claimed under the lock, run outside it)."""
        with self._lock:
            work = None
            if fullname == "numba" and not self.started:
                self.started = self.deferred = True
                work = fast_start
            elif fullname == "scipy" and not self.deferred:
                self.deferred = True
                work = defer_numpy_submodules
        if work is not None:
            work()

    def find_spec(self, fullname, path=None, target=None):
        if fullname == "numba" and self.started or fullname == "scipy" and self.deferred:
            return None
        if fullname not in ("numba", "scipy"):
            return None
        spec = _spec_of_others(self, fullname, path, target)
        if spec is None or spec.loader is None:
            return None
        spec.loader = _WorkFirst(spec.loader, lambda: self.run_work(fullname))
        return spec


def _spec_of_others(finder, fullname, path, target):
    """The spec the finders on ``sys.meta_path`` after ``finder`` give for ``fullname`` (None if none does)."""
    for other in list(sys.meta_path):
        if other is finder:
            continue
        find_spec = getattr(other, "find_spec", None)
        if find_spec is None:
            continue
        spec = find_spec(fullname, path, target)
        if spec is not None:
            return spec
    return None


class _WorkFirst(importlib.abc.Loader):
    """A package's loader that runs ``work`` before the package's own code (then hands the module its own loader)."""

    def __init__(self, loader, work) -> None:
        self._loader = loader
        self._work = work

    def create_module(self, spec):
        return self._loader.create_module(spec)

    def exec_module(self, module) -> None:
        self._work()
        module.__loader__ = self._loader
        if module.__spec__ is not None:
            module.__spec__.loader = self._loader
        self._loader.exec_module(module)

    def __getattr__(self, name):
        return getattr(self._loader, name)


def fast_start_on_import() -> None:
    """Start-up of the command line: :func:`fast_start` when numba is first imported (before its first load, which
    comes with the first call of a compiled function), :func:`defer_numpy_submodules` when scipy is, if first;
    nothing for a process that imports neither. At once if numba is imported already."""
    if "numba" in sys.modules:
        fast_start()
        return
    if any(isinstance(finder, _OnFirstImport) for finder in sys.meta_path):
        return
    finder = _OnFirstImport()
    sys.meta_path.insert(0, finder)
    if "scipy" in sys.modules:
        finder.deferred = True
        defer_numpy_submodules()


def load_cython_blas_alone() -> None:
    """Load the extension module ``scipy.linalg.cython_blas`` from its file, without ``scipy.linalg``'s package
    (numba's first load imports it to see that a BLAS is there). Does nothing if it or ``scipy.linalg`` is
    loaded already, or if the file is not found or does not load (the usual import then loads it with its package)."""
    if _CYTHON_BLAS in sys.modules or "scipy.linalg" in sys.modules:
        return
    scipy = importlib.util.find_spec("scipy")
    if scipy is None or not scipy.submodule_search_locations:
        return
    loaders = (importlib.machinery.ExtensionFileLoader, importlib.machinery.EXTENSION_SUFFIXES)
    for folder in scipy.submodule_search_locations:
        spec = importlib.machinery.FileFinder(os.path.join(folder, "linalg"), loaders).find_spec(_CYTHON_BLAS)
        if spec is not None:
            break
    else:
        return
    module = importlib.util.module_from_spec(spec)
    sys.modules[_CYTHON_BLAS] = module
    try:
        spec.loader.exec_module(module)
    except ImportError:
        del sys.modules[_CYTHON_BLAS]


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
