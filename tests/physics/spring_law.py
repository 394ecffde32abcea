"""A compiled contact law added from outside wheelrail: one module and one registry entry.

A linear spring F = k max(0, delta + r) on the chosen line (k: the Hertz spring's tangent at the preload), its
kernel compiled with numba and stepped in a chunk loop of its own (eqs. 1-2 inlined from ``engine.kernels``), on
the engine's ``CompiledLaw``. ``SPRING`` is its registry entry (``models.register(SPRING)``).
"""

from __future__ import annotations

import math
import sys

import numpy as np
from numba import njit

from wheelrail.core.engine import kernels
from wheelrail.core.engine.compiled import sources_stamp
from wheelrail.core.engine.kernels import commit_force, known_approach
from wheelrail.core.engine.laws.base import CompiledLaw
from wheelrail.core.models import ContactModel, LawInputs, ModelEntry, ModelTraits


@njit(cache=True, inline="always")
def spring_force(approach_known, compliance, roughness, stiffness):
    """F = k max(0, delta + r) with delta = approach_known - c F: F = k (approach_known + r) / (1 + k c), or 0."""
    force = stiffness * (approach_known + roughness) / (1.0 + stiffness * compliance)
    return force if force > 0.0 else 0.0


def _define(stamp):
    @njit(cache=True)
    def chunk_loop(j0, j1, track, wheel, preload, xi_w0, law_inputs, out):
        """The spring over history indices j0..j1-1; returns -1 (it has no window to leave)."""
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called
        roughness, _, constants = law_inputs
        xi_wheel, xi_rail, length, area = out
        offset = track[0].shape[0] - roughness.shape[0]
        for j in range(j0, j1):
            delta_known, c, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
            s = j - offset
            f = spring_force(delta_known, c, roughness[s, 0], constants[0])
            length[s] = 0.0
            area[s] = np.nan
            xi_wheel[s], xi_rail[s] = commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0)
        return -1

    @njit(cache=True)
    def curve(approaches, law_inputs, s):
        """F(delta) at step s, compliance 0."""
        stamp  # noqa: B018
        roughness, _, constants = law_inputs
        forces = np.empty(approaches.size)
        for k in range(approaches.size):
            forces[k] = spring_force(approaches[k], 0.0, roughness[s, 0], constants[0])
        return forces

    return chunk_loop, curve


_CHUNK_LOOP, _CURVE = _define(sources_stamp(kernels, sys.modules[__name__]))


class SpringLaw(CompiledLaw):
    """The spring's law on the engine: its compiled chunk loop and its curve."""

    chunk_loop = staticmethod(_CHUNK_LOOP)
    curve = staticmethod(_CURVE)


class SpringModel(ContactModel):
    """The spring's inputs: r under the wheel at every step (faded in over the run-in) and k."""

    def prepare(self, inputs):
        contact = inputs.params.contact
        stiffness = 1.5 * contact.hertz_constant * math.sqrt(contact.hertz_approach())
        self.equivalent_line = inputs.centre_line
        roughness = np.ascontiguousarray((inputs.centre_line[inputs.start_index] * inputs.ramp)[:, None])
        self._law = LawInputs(roughness=roughness, shape=np.zeros(1), constants=np.array([stiffness]))
        return contact.preload / stiffness

    def law_inputs(self) -> LawInputs:
        return self._law


SPRING = ModelEntry(
    name="spring", label="linear spring, compiled (test)", traits=ModelTraits(law=SpringLaw), implementation=SpringModel
)
