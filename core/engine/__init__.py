"""The run engine: a run prepared, stepped and returned (paper section 2, eqs. 1-14).

Its pieces, by what they do:

* ``prepare``: :func:`prepare_run` and :func:`simulate`, the inputs checked and the run built from the pieces below;
* ``track_lines``: the roughness along the track (the window's size, the margins, the lines a model runs on);
* ``history``: the run-in, the loop's history arrays (Green's functions, the wheel's system, the bay) and the
  contact model prepared on them;
* ``steady_start``: the moving load's periodic steady state a run starts from;
* ``run``: :class:`~wheelrail.core.engine.run.InteractionRun`, the stepping and its results by step or by chunk;
* ``kernels``: the compiled eqs. 1-2 of a step, inlined into every law's chunk loop;
* ``memory``: a run's memory estimated before it is allocated;
* ``compiled``: numba's cache keyed on the sources a compiled function calls;
* ``results``: the run's header, its per-step state and its whole-run result;
* ``impacts``: a run's impacts (peak and minimum force, time without contact, each impact's position).

``prepare_run``, ``simulate`` and ``InteractionRun`` are importable from here, loaded on first use (this package's
own import loads no numerical library: ``results`` is read without numba).
"""

from __future__ import annotations

import importlib

__all__ = ["InteractionRun", "impact_summary", "prepare_run", "simulate"]

_WHERE = {"prepare_run": "prepare", "simulate": "prepare", "InteractionRun": "run", "impact_summary": "impacts"}


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)


def __dir__() -> list[str]:
    return sorted(__all__)
