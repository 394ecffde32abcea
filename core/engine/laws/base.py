"""The interface between the run engine and a contact law: :class:`ContactLaw`, and the two ways a law steps.

The loop (``engine.run.InteractionRun``) owns eqs. 1-2 and asks the law of its model, whichever it is, to
advance a chunk of steps (:meth:`ContactLaw.advance`), where a chunk may stop (:meth:`ContactLaw.chunk_end`), for
its law F(delta) on the run-in's gap (:meth:`ContactLaw.steady_law`, which ``steady_start`` solves the moving
load's steady state on) and to start from that state (:meth:`ContactLaw.start_steady`), for the pressure maps of
the last chunk, and, before the run, for its memory per element (:meth:`ContactLaw.memory_columns`). What the law
reads of the surface is its own (:meth:`ContactLaw.surface_input`): an equivalent roughness under a Hertz spring,
the window's lines under a bedding or the half-space.

Two kinds of law, on one base:

* :class:`CompiledLaw`: a numba chunk loop over the steps (``chunk_loop``), eqs. 1-2 inlined from
  ``engine.kernels``; its module defines the law's kernel and the loop (numba caches compiled code on disk only
  when no jitted function is passed as an argument, so each law has its own loop);
* :class:`PerStepLaw`: the model's Python ``solve`` once per step (a model registered with no law).

:func:`law_class` resolves a registry entry's ``ModelTraits.law`` to its class.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import replace
from typing import NamedTuple

import numpy as np

from wheelrail.core.engine.kernels import commit_force, known_approach
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import ContactModel, ModelInputs, ModelTraits

__all__ = ["CHUNK", "CompiledLaw", "ContactLaw", "PerStepLaw", "StepArrays", "law_class"]

CHUNK = 2048  # steps per call of a compiled chunk loop (streaming and cancellation granularity)


class StepArrays(NamedTuple):
    """The run's outputs per step s (run-in included): wheel and rail displacements (m), contact length (m) and
    area (m^2); a law writes the steps it advances."""

    xi_wheel: np.ndarray
    xi_rail: np.ndarray
    contact_length: np.ndarray
    contact_area: np.ndarray


class ContactLaw:
    """A contact model's law as the loop steps it, for one run.

    Parameters
    ----------
    contact : ContactModel
        The model, prepared on ``inputs``.
    inputs : ModelInputs
        What the model was prepared on (the roughness on the model grid, its window, the steps' samples).
    history : History
        The loop's arrays (``engine.history.History``), its static equilibrium set.
    outputs : StepArrays
        The arrays the law writes each step into.
    keep_pressure : bool
        Keep every recorded step's pressure map (a model with maps); else only the last chunk's.

    Attributes
    ----------
    chunk : int
        Steps per call of :meth:`advance` (streaming and cancellation granularity).
    nogil : bool
        Whether :meth:`advance` spends its time in compiled code that releases the GIL (numba's ``nogil=True``):
        then runs of this law in parallel threads of one process use every core (``core.study.execution`` runs a
        study's runs so, sharing the loaded track and compiled code); else each needs a process of its own.
    pressure : numpy.ndarray or None
        The recorded steps' pressure maps (steps, ny, nx) float32, where kept.

    See Also
    --------
    CompiledLaw, PerStepLaw : the two kinds.
    """

    chunk: int = 1
    nogil: bool = False

    def __init__(
        self,
        contact: ContactModel,
        inputs: ModelInputs,
        history,
        outputs: StepArrays,
        keep_pressure: bool = True,
    ) -> None:
        self.contact = contact
        self.inputs = inputs
        self.history = history
        self.outputs = outputs
        self.preload = inputs.params.contact.preload
        self.pressure = None
        self.map_shape = None if contact.window_x is None else (len(inputs.window_y), len(contact.window_x))
        if self.map_shape is not None and keep_pressure:
            self.pressure = np.zeros((history.n_steps, *self.map_shape), dtype=np.float32)

    @classmethod
    def memory_columns(cls, window_width: int) -> int:
        """Values held per element of the run and per roughness line beyond the loop's own (``engine.memory``):
        0, or a window's columns for a law that keeps one per step. ``window_width``: the least window's
        columns."""
        return 0

    @classmethod
    def irregular_surface(
        cls, lines: np.ndarray, deviation: np.ndarray, centre_input: Callable[[], np.ndarray]
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """How the model meets a run's discrete irregularities: the lines it is prepared on and the line added to
        its equivalent roughness (``ModelInputs.equivalent_offset``, or None).

        ``lines``: the roughness along the track (rows, samples, as ``ModelInputs.lines``, m); ``deviation``: the
        irregularities' surface deviation on the same rows and samples, m; ``centre_input()``: the Hertz models'
        input on the chosen line (the wheel-centre trajectory, or the raw profile: ``RunParameters.
        irregularity_input``), m. Here the surface as it is: the deviation added to every line, by position."""
        return lines + deviation, None

    def surface_input(self, lines: np.ndarray) -> np.ndarray:
        """What this law's kernel reads of a surface, per step: the surface ``lines`` (rows, samples on the model
        grid, as ``ModelInputs.lines``, m) under the model's treatment. Here the lines themselves (a per-step
        model reads what it reads)."""
        return lines

    def chunk_end(self, s0: int, s_end: int) -> int:
        """The last step (exclusive) of the chunk that starts at step s0, the run to go to s_end."""
        return min(s_end, s0 + self.chunk)

    def advance(self, s0: int, s1: int) -> None:
        """Steps s0..s1-1 (run-in included) into ``outputs`` and the history; WheelrailError if the law fails."""
        raise NotImplementedError

    def chunk_pressure(self, s0: int, s1: int) -> np.ndarray | None:
        """The pressure maps of steps s0..s1-1 of the chunk just advanced (float32, its own array or a view of
        the kept maps never written again), or None for a law without maps."""
        if self.pressure is None:
            return None
        n_run_in = self.history.n_run_in
        return self.pressure[s0 - n_run_in : s1 - n_run_in]

    def steady_law(self, band=None):
        """The law F(delta) on the run-in's gap (that of step 0, not faded in), approaches (m) -> forces (N), for
        ``steady_start``; ``band``: a law tabulated over a band says which (``halfspace``)."""
        s = self.history.n_run_in
        return lambda d: np.array([self.contact.solve(s, float(x), 0.0).force for x in d])

    def start_steady(self):
        """The moving load's steady state the run starts from (``steady_start.SteadyState``), solved on
        :meth:`steady_law` and put into the history."""
        from wheelrail.core.engine.steady_start import fill_history, start_state

        steady = start_state(self.history, self.steady_law(), self.preload)
        fill_history(self.history, steady)
        return steady


class PerStepLaw(ContactLaw):
    """A model's law solved from Python once per step (``ContactModel.solve``)."""

    def advance(self, s0: int, s1: int) -> None:
        loop, out = self.history, self.outputs
        track, wheel, preload, xi_w0 = loop.track, loop.wheel, self.preload, loop.xi_w0
        for s in range(s0, s1):
            j = loop.n_hist + s
            delta_known, compliance, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
            state = self.contact.solve(s, delta_known, compliance)
            out.xi_wheel[s], out.xi_rail[s] = commit_force(j, state.force, track, wheel, s_pred, preload, xi_w0, q, w0)
            out.contact_length[s] = state.contact_length
            out.contact_area[s] = state.contact_area
            if state.pressure is not None:
                if self.pressure is not None and s >= loop.n_run_in:
                    self.pressure[s - loop.n_run_in] = state.pressure
                self._last = state.pressure

    def chunk_pressure(self, s0: int, s1: int) -> np.ndarray | None:
        if self.pressure is not None:
            return super().chunk_pressure(s0, s1)
        last = getattr(self, "_last", None)  # chunks of one step: the step's own map
        return None if last is None else np.asarray(last, dtype=np.float32)[None]


class CompiledLaw(ContactLaw):
    """A law stepped by a compiled chunk loop: ``CHUNK`` steps a call.

    A subclass gives ``chunk_loop``, a numba function ``(j0, j1, track, wheel, preload, xi_w0, law_inputs, out)``
    that advances history indices j0..j1-1 (``engine.kernels.known_approach`` and ``commit_force`` inlined) and
    returns -1, or the index at which its law failed; and ``curve(approaches, law_inputs, s)``, the law's forces at
    compliance 0 (F(delta), for the steady start). ``law_inputs`` is the model's ``law_inputs()`` as the tuple
    (roughness, shape, constants) of ``models.LawInputs``.
    """

    chunk = CHUNK

    def __init__(self, contact, inputs, history, outputs, keep_pressure=True) -> None:
        super().__init__(contact, inputs, history, outputs, keep_pressure)
        law = contact.law_inputs()
        self.law_inputs = (law.roughness, law.shape, law.constants)

    @staticmethod
    def chunk_loop(j0, j1, track, wheel, preload, xi_w0, law_inputs, out):  # pragma: no cover - a subclass's
        raise NotImplementedError

    @staticmethod
    def curve(approaches, law_inputs, s):  # pragma: no cover - a subclass's
        raise NotImplementedError

    def surface_input(self, lines: np.ndarray) -> np.ndarray:
        """What the kernel reads of the surface ``lines`` at every step: the roughness of the law's inputs
        (``LawInputs.roughness``, faded in over the run-in) of a fresh model of the same kind prepared on
        ``lines`` (``ContactModel.prepare``: the one statement of the model's treatment of the surface, r_eq
        under a Hertz spring or the bedding's window on the chosen line), m."""
        model = type(self.contact)()
        model.prepare(replace(self.inputs, lines=lines))
        return model.law_inputs().roughness

    def advance(self, s0: int, s1: int) -> None:
        loop = self.history
        j = self.chunk_loop(
            loop.n_hist + s0,
            loop.n_hist + s1,
            loop.track,
            loop.wheel,
            self.preload,
            loop.xi_w0,
            self.law_inputs,
            tuple(self.outputs),
        )
        if j != -1:
            raise WheelrailError(self.contact.edge_message(j - loop.n_hist))

    def steady_law(self, band=None):
        s, inputs = self.history.n_run_in, self.law_inputs
        return lambda d: self.curve(d, inputs, s)


def law_class(traits: ModelTraits) -> type[ContactLaw]:
    """The law class a model's traits name (``ModelTraits.law``): a :class:`ContactLaw` subclass, one named
    ``"module:Class"`` (imported here), or :class:`PerStepLaw` for None."""
    law = traits.law
    if law is None:
        return PerStepLaw
    if isinstance(law, str):
        module, _, attribute = law.partition(":")
        law = getattr(importlib.import_module(module), attribute)
    if not (isinstance(law, type) and issubclass(law, ContactLaw)):
        raise WheelrailError(f"ModelTraits.law must name a ContactLaw subclass, got {law!r}")
    return law
