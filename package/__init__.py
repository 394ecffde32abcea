"""wheelrail: time-domain vertical wheel/rail interaction and the dynamic contact filter.

The model of Pieringer, Kropp & Thompson, "Investigation of the dynamic contact filter effect in vertical
wheel/rail interaction using a 2D and a 3D non-Hertzian contact model", Wear 271 (2011) 328-338.

The names most scripts need are here (``from wheelrail import simulate, ContactParameters``); each is imported
from its module in ``wheelrail.core`` on first use (PEP 562), so that ``import wheelrail`` loads neither numpy
nor numba and the command line starts fast. Everything else is in the sub-packages: ``wheelrail.core``
(physics and data, no GUI), ``wheelrail.explorer`` (the browser GUI), ``wheelrail.sample_data`` (the bundled
roughness sets); ``wheelrail.cli`` is the ``wheelrail`` command.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

__version__ = "0.1.0"  # the one place the version is written (pyproject.toml reads it)

# public name -> the module that defines it
_PUBLIC = {
    "simulate": "wheelrail.core.engine.prepare",
    "prepare_run": "wheelrail.core.engine.prepare",
    "ModelParameters": "wheelrail.core.parameters",
    "ContactParameters": "wheelrail.core.parameters",
    "force_spectrum": "wheelrail.core.spectra.force",
    "contact_filter": "wheelrail.core.spectra.levels",
    "run_study": "wheelrail.core.study",
    "run_noise": "wheelrail.core.noise.run_noise",
    "WheelrailError": "wheelrail.core.errors",
}

__all__ = [
    "ContactParameters",
    "ModelParameters",
    "WheelrailError",
    "__version__",
    "contact_filter",
    "force_spectrum",
    "prepare_run",
    "run_noise",
    "run_study",
    "simulate",
]

if TYPE_CHECKING:  # what type checkers and editors see; at run time __getattr__ imports on first use
    from wheelrail.core.engine import prepare_run, simulate
    from wheelrail.core.errors import WheelrailError
    from wheelrail.core.noise.run_noise import run_noise
    from wheelrail.core.parameters import ContactParameters, ModelParameters
    from wheelrail.core.spectra.force import force_spectrum
    from wheelrail.core.spectra.levels import contact_filter
    from wheelrail.core.study import run_study


def __getattr__(name: str):
    """Import a public name from its module on first access (PEP 562) and keep it in the package."""
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'wheelrail' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups find it directly
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
