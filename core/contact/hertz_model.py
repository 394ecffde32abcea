"""The ``hertz``, ``hertz-winkler`` and ``hertz-average`` contact models: the Hertz spring of eqs. 12-14 on the
line's roughness, on the Ford & Thompson pre-filtered roughness or on its mean over the contact length.
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.contact.winkler import checked_contact
from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.models import ContactModel, LawInputs, ModelInputs
from wheelrail.core.parameters import ContactParameters

__all__ = ["HertzAverageModel", "HertzModel", "HertzWinklerModel", "hertz_constant"]


class HertzModel(ContactModel):
    """``hertz``: the Hertz spring on the roughness of the line itself (r_eq = r); elliptic for unequal radii
    (``ContactParameters.hertz``: C of F = C delta^1.5, contact length 2a along the rail, area pi a b)."""

    def equivalent_roughness(self, inputs: ModelInputs, line: np.ndarray) -> np.ndarray:
        """r_eq along the track for the line r (here r itself)."""
        return line

    def prepare(self, inputs: ModelInputs) -> float:
        contact = inputs.params.contact
        self.equivalent_line = self.equivalent_roughness(inputs, inputs.centre_line)
        if inputs.equivalent_offset is not None:  # a run's irregularities (ContactLaw.irregular_surface)
            self.equivalent_line = self.equivalent_line + inputs.equivalent_offset
        r_eq = np.ascontiguousarray(self.equivalent_line[inputs.start_index] * inputs.ramp)
        self._law = LawInputs(
            roughness=r_eq.reshape(-1, 1),
            shape=np.zeros(1),
            constants=np.array([contact.hertz_constant, *contact.patch_radii()]),
        )
        return contact.hertz_approach()

    def law_inputs(self) -> LawInputs:
        return self._law


class HertzWinklerModel(HertzModel):
    """``hertz-winkler``: r_eq from the Ford & Thompson bedding pre-filter (``contact.prefilter``).

    The bedding is the ``2d`` model's (``contact.winkler.calibrated_bedding``: the paper's for the circle).
    The pre-filter runs on the line along the track; the run's margins (``track_lines.run_margin``, 20 mm at
    1 mm elements, at least 3a) cover its half-length 3a (16.4 mm at the defaults), so its end treatment never
    reaches a step of the run.
    """

    def equivalent_roughness(self, inputs, line):
        from wheelrail.core.contact.prefilter import winkler_equivalent_roughness

        try:
            return winkler_equivalent_roughness(line, inputs.element_size, inputs.params.contact)
        except WheelrailError as error:
            if error.parameter != "half_window":
                raise
            # a run sizes the pre-filter's window itself (3a): what its user can change is the roughness
            raise WheelrailError(
                error.problem, Blame("model", "hertz-winkler"), advice="use a smoother line or set, or the hertz model"
            ) from None


class HertzAverageModel(HertzModel):
    """``hertz-average``: r_eq = mean of r over the nominal contact length 2a along the rail (a the Hertz
    semi-axis along the rail at the preload; a + 1 mm < the run margin)."""

    def equivalent_roughness(self, inputs, line):
        from wheelrail.core.contact.prefilter import average_roughness

        a, _ = inputs.params.contact.hertz_semi_axes()
        return average_roughness(line, inputs.element_size, contact_length=2 * a)


def hertz_constant(contact: ContactParameters | None = None) -> float:
    """Hertzian constant C_H of F = C_H delta^1.5, eq. (13), N/m^1.5.

    Parameters
    ----------
    contact : ContactParameters, optional
        Material and radii; default ``ContactParameters()`` (the paper's crossed cylinders, R = 0.39 m).

    Returns
    -------
    float
        C_H in N/m^1.5: (2/3) E / (1 - nu^2) sqrt(R) for the paper's circle (9.608e10 at its values), Hertz's
        elliptic constant (``ContactParameters.hertz``) otherwise.

    Raises
    ------
    WheelrailError
        If ``contact`` is not ContactParameters.

    See Also
    --------
    hertz_force, hertz_approach : the spring law with this constant.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eq. (13).

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_constant
    >>> f"{hertz_constant():.4g}"
    '9.608e+10'
    """
    return checked_contact("hertz_constant", contact).hertz_constant
