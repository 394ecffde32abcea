"""A contact-model plug-in for wheelrail: a linear contact spring on the chosen line.

F = k (delta + r), with k the tangent stiffness of the Hertz spring at the preload (dF/d delta = 1.5 C
sqrt(delta(P)), eq. 13 differentiated), so that it equals Hertz for small roughness and differs from it
where the roughness is large (no loss of contact below F = 0 other than by clipping). It is a per-step law
(``ModelTraits()``: no compiled kernel), declared in this package's pyproject.toml under the entry-point group
``wheelrail.contact_models``.
"""

import math

from wheelrail.core.models import ContactModel, ContactState, ModelEntry, ModelTraits


class LinearSpring(ContactModel):
    def prepare(self, inputs):
        contact = inputs.params.contact
        self.stiffness = 1.5 * contact.hertz_constant * math.sqrt(contact.hertz_approach())
        self.inputs = inputs
        self.equivalent_line = inputs.centre_line
        return contact.preload / self.stiffness  # static approach under the preload, m

    def solve(self, s, approach_known, compliance):
        r = self.inputs.ramp[s] * self.inputs.centre_line[self.inputs.start_index[s]]
        # delta = approach_known - c F and F = k (delta + r)  =>  F = k (approach_known + r) / (1 + k c)
        force = max(0.0, self.stiffness * (approach_known + r) / (1.0 + self.stiffness * compliance))
        return ContactState(force=force, contact_length=0.0, contact_area=math.nan)


LINEAR_SPRING = ModelEntry(
    name="linear-spring",
    label="linear contact spring (the test plug-in)",
    traits=ModelTraits(),
    implementation=LinearSpring,
)
