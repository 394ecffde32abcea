"""The compiled one-line laws: the Hertz spring on an equivalent roughness (``hertz``, ``hertz-winkler``,
``hertz-average``; eqs. 12-14) and the Winkler bedding on the line under the wheel (``2d``; eqs. 3-6).

Both run in one compiled chunk loop, :data:`run_chunk`, which selects the kernel by a constant (``HERTZ`` or
``BEDDING``: numba caches compiled code on disk only when no jitted function is passed as an argument), with eqs.
1-2 inlined from ``engine.kernels``; :data:`law_curve` is the same kernel at compliance 0, F(delta), for the steady
start.
"""

from __future__ import annotations

import sys

import numpy as np
from numba import njit

from wheelrail.core.contact import hertz_law as hertz_kernels
from wheelrail.core.contact import winkler
from wheelrail.core.contact.hertz_law import hertz_law
from wheelrail.core.contact.winkler import bedding_law
from wheelrail.core.engine import kernels
from wheelrail.core.engine.compiled import sources_stamp
from wheelrail.core.engine.kernels import commit_force, known_approach
from wheelrail.core.engine.laws.base import CompiledLaw

__all__ = ["BEDDING", "HERTZ", "BeddingLaw", "HertzLaw", "law_curve", "run_chunk"]

HERTZ = 0  # Hertz spring on an equivalent roughness (eqs. 12-14): contact.hertz_law.hertz_law
BEDDING = 1  # Winkler bedding on the line under the wheel (eqs. 3-6): contact.winkler.bedding_law


@njit(cache=True, inline="always")
def _law(law, approach_known, compliance, roughness, s, shape, constants):
    """A one-line law (``HERTZ`` or ``BEDDING``) at step s: (F, contact length, contact area, reached the window's
    end)."""
    if law == HERTZ:
        f, length, area = hertz_law(
            approach_known, compliance, roughness[s, 0], constants[0], constants[1], constants[2]
        )
        return f, length, area, False
    return bedding_law(approach_known, compliance, roughness[s], shape, constants[0], constants[1])


def _define_law_curve(stamp):
    @njit(cache=True, nogil=True)
    def law_curve(law, approaches, law_inputs, s):
        """A compiled one-line law's force at step s at the given approaches (compliance 0: F(delta)), N: the
        contact law of the run-in's steady state (``steady_start``)."""
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called
        roughness, shape, constants = law_inputs
        forces = np.empty(approaches.size)
        for k in range(approaches.size):
            forces[k] = _law(law, approaches[k], 0.0, roughness, s, shape, constants)[0]
        return forces

    return law_curve


# The chunk loop calls compiled code of other modules: numba's cache keys it on those sources too
# (wheelrail.core.engine.compiled).
def _define_run_chunk(stamp):
    @njit(cache=True, nogil=True)
    def run_chunk(law, j0, j1, track, wheel, preload, xi_w0, law_inputs, out):
        """Advance a one-line law over history indices j0..j1-1: one compiled function, not a Python loop over
        the steps (the hot loop). ``law`` = ``HERTZ`` or ``BEDDING``; ``law_inputs`` = (roughness, shape,
        constants) of models.LawInputs; ``out`` = (xi_wheel, xi_rail, contact_length, contact_area) per step s.

        Returns -1 if all went well, else the index j at which the law reached its window's end.
        """
        stamp  # noqa: B018 - keys numba's cache on the sources of the modules called
        roughness, shape, constants = law_inputs
        xi_wheel, xi_rail, length, area = out
        offset = track[0].shape[0] - roughness.shape[0]
        for j in range(j0, j1):
            delta_known, c, q, w0, s_pred = known_approach(j, track, wheel, preload, xi_w0)
            s = j - offset
            f, contact_length, contact_area, edge = _law(law, delta_known, c, roughness, s, shape, constants)
            if edge:
                return j
            length[s] = contact_length
            area[s] = contact_area
            xi_wheel[s], xi_rail[s] = commit_force(j, f, track, wheel, s_pred, preload, xi_w0, q, w0)
        return -1

    return run_chunk


_STAMP = sources_stamp(hertz_kernels, winkler, kernels, sys.modules[__name__])
run_chunk = _define_run_chunk(_STAMP)
law_curve = _define_law_curve(_STAMP)


class _OneLineLaw(CompiledLaw):
    """A one-line law in :data:`run_chunk`, selected by ``kind``: ``CompiledLaw``'s stepping on it."""

    kind: int
    nogil = True  # run_chunk and law_curve release the GIL

    def chunk_loop(self, *args):
        """:data:`run_chunk` of this law's ``kind``."""
        return run_chunk(self.kind, *args)

    def curve(self, *args):
        """:data:`law_curve` of this law's ``kind``."""
        return law_curve(self.kind, *args)


class HertzLaw(_OneLineLaw):
    """The Hertz spring on the model's equivalent roughness r_eq (``ContactModel.equivalent_line``)."""

    kind = HERTZ

    @classmethod
    def irregular_surface(cls, lines, deviation, centre_input):
        """The Hertz spring meets the irregularities through its equivalent roughness: the lines as they are (the
        model's pre-filter sees the roughness alone) and ``centre_input()`` (the wheel-centre trajectory of the
        irregularities alone, or their raw profile) added to r_eq: a superposition, exact where the roughness
        and the irregularity do not overlap (the documentation's physics page, "Discrete irregularities")."""
        return lines, centre_input()


class BeddingLaw(_OneLineLaw):
    """The Winkler bedding of 2 half_x + 1 springs on the chosen line under the wheel."""

    kind = BEDDING

    @classmethod
    def memory_columns(cls, window_width: int) -> int:
        """The bedding's window of each step (and its temporary): ``window_width`` columns."""
        return window_width
