"""The radiating components of the rolling-noise chain: one entry each (name, label, colour, excitation, radiation).

A component is driven by one of two quantities of the TWINS-like chain (:mod:`wheelrail.core.noise.twins`):

- ``driven_by="force"``: a run's contact force drives it through a receptance. The track's parts (rail,
  sleepers): its ``response`` reads a vibration measure of the lengthened FE track from :class:`TrackResponse`
  (one frequency, one excitation position, a unit force at the contact), and its ``radiation`` turns that measure
  into sound power, W/N^2 per unit of the measure; the chain takes the band mean of their product as the
  component's sound power per unit mean-square force. The rail's lateral vibration (``rail_lateral``, a part of the
  track driven through the contact's offset on the railhead, :mod:`wheelrail.core.noise.rail_lateral`) reads the
  unit force itself as its measure and gives its sound power per unit force^2 from the lateral track's receptance
  in its ``radiation`` (zero for a centred contact). A part with its own receptance (the modal wheel) gives
  that band mean itself (``power_per_force``) and its sound power per axle for 0 dB re 1 um effective roughness
  (``transfer``, computed on its own band sampling). A run's force level times the band mean is the component's
  sound power.
- ``driven_by="roughness"`` (the directive's wheel, which has no receptance): its ``transfer`` gives its sound
  power per axle for 0 dB re 1 um effective roughness, dB re 1 pW per band (L_H,veh); a run's effective roughness
  plus it, less 3 dB (one wheel of the axle), is the component's sound power.

The wheel's entry follows the chain's wheel model (:func:`chain_components`): the directive's (driven by the
roughness, the registered one) or the modal wheel's (driven by the force through the modal wheel's receptance and
radiation, :mod:`wheelrail.core.noise.wheel_power`).

Every part of the project reads this list at the call: the chain and a run's noise
(:func:`wheelrail.core.noise.run_noise.run_noise`), its outputs (the JSON keys, the CSV columns, the recording's
sound-power entities, the command line's tables), the track study's table and figure, and the explorer's curves,
colours and table. Adding a component is one :func:`register_component` (or one entry of the built-in list);
:func:`unregister_component` removes it.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from wheelrail.core.drawing.palette import OKABE_ITO, TOL_INDIGO, TOL_WINE
from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise.radiation import (
    AIR_DENSITY,
    SOUND_SPEED,
    decaying_rail_radiation,
    piston_radiation_efficiency,
    rail_section,
)

__all__ = [
    "DRIVEN_BY",
    "TOTAL",
    "NoiseChain",
    "NoiseComponent",
    "TrackResponse",
    "chain_components",
    "component",
    "component_names",
    "noise_components",
    "register_component",
    "sound_power_parts",
    "unregister_component",
]

TOTAL = "total"  # the energetic sum of the components' sound powers, listed after them
DRIVEN_BY = ("force", "roughness")  # what excites a component (module docstring)


class TrackResponse:
    """The lengthened FE track's response to a unit force at the contact, at one frequency and one excitation
    position: what a force-driven component's ``response`` reads.

    Parameters
    ----------
    model : TrackModel
        The lengthened FE track (:func:`wheelrail.core.track.assemble_track`).
    displacement : numpy.ndarray
        Its displacements (every degree of freedom) for a unit force, m/N.
    frequency : float
        Hz.
    """

    def __init__(self, model, displacement: np.ndarray, frequency: float) -> None:
        self.model = model
        self.displacement = displacement
        self.frequency = frequency
        self.angular_frequency = 2 * np.pi * frequency
        self.rail = displacement[model.w_dof]  # the rail's vertical displacement at every node, m/N

    @functools.cached_property
    def rail_radiated(self) -> float:
        """The rail's field radiated in the wavenumber domain (:func:`~wheelrail.core.noise.radiation.
        decaying_rail_radiation`), (m/s)^2 m per N^2."""
        w = self.angular_frequency
        return decaying_rail_radiation(w * self.rail, self.model.element_length, self.frequency)

    @functools.cached_property
    def sleeper_velocity_sq(self) -> float:
        """Sum over the sleepers of their squared velocity, (m/s)^2 per N^2."""
        return self.angular_frequency**2 * np.sum(np.abs(self.displacement[self.model.sleeper_dof]) ** 2)


@dataclass(frozen=True, kw_only=True, eq=False)
class NoiseChain:
    """What a component's ``radiation`` or ``transfer`` may read of the chain.

    Attributes
    ----------
    params : ModelParameters
        The wheel, track and contact of the chain.
    numerics : NoiseNumerics
        Its numerics (:class:`wheelrail.core.noise.twins.NoiseNumerics`).
    frequencies : numpy.ndarray
        (bands, points) frequencies of the band means, Hz.
    wheel : dict
        The wheel model's chain: ``db`` its transfer per axle (dB re 1 pW for 0 dB re 1 um), ``power_per_force``
        (the modal wheel's band means of W / F^2, W/N^2; None for the directive's), ``source`` in words.
    contact_position : ContactPosition or None
        The contact's lateral position on the railhead and the wheel's tread
        (:class:`wheelrail.core.inputs.contact_position.ContactPosition`; None: centred).
    """

    params: object
    numerics: object
    frequencies: np.ndarray
    wheel: dict
    contact_position: object = None


@dataclass(frozen=True, kw_only=True)
class NoiseComponent:
    """One radiating component of the noise chain (module docstring).

    Attributes
    ----------
    name : str
        Its key in the outputs: ``sound_power_dB[name]``, the CSV column ``<name>_dB``, the JSON key
        ``<name>_transfer_dB`` and the recording's ``spectra/sound_power/<name>``; lower case, digits and ``_``.
    label : str
        Its words in tables and legends.
    colour : str
        Its curve's colour, sRGB hex, from :mod:`wheelrail.core.drawing.palette`.
    driven_by : str
        ``"force"`` or ``"roughness"`` (:data:`DRIVEN_BY`).
    response : callable, optional
        ``"force"``, a part of the track: ``response(TrackResponse) -> float``, the vibration measure it radiates
        from.
    radiation : callable, optional
        ``"force"``, a part of the track: ``radiation(NoiseChain)`` -> sound power per unit of the response, W/N^2
        per unit, a float or an array that broadcasts to (bands, points, positions).
    power_per_force : callable, optional
        ``"force"``, a part with its own receptance: ``power_per_force(NoiseChain)`` -> band means of its sound
        power per unit mean-square contact force, W/N^2 per band (given with ``transfer``).
    transfer : callable, optional
        ``"roughness"``, or ``"force"`` with ``power_per_force``: ``transfer(NoiseChain)`` -> sound power per axle
        for 0 dB re 1 um, dB re 1 pW per band.

    Raises
    ------
    WheelrailError
        If the name is not lower case, digits and ``_``, or is ``total``; if ``driven_by`` is neither excitation;
        if a callable its excitation needs is missing.
    """

    name: str
    label: str
    colour: str
    driven_by: str
    response: Callable | None = None
    radiation: Callable | None = None
    power_per_force: Callable | None = None
    transfer: Callable | None = None

    def __post_init__(self) -> None:
        name = self.name
        if not (isinstance(name, str) and name and name.replace("_", "").isalnum() and name == name.lower()):
            raise WheelrailError(f"noise component name {name!r}: lower-case letters, digits and _ only")
        if name == TOTAL:
            raise WheelrailError(f"noise component name {name!r}: the name of the sum of the components")
        if self.driven_by not in DRIVEN_BY:
            raise WheelrailError(f"noise component {name!r}: driven_by {self.driven_by!r}; one of {DRIVEN_BY}")
        needed = ("transfer",)
        if self.driven_by == "force":
            needed = ("power_per_force", "transfer") if callable(self.power_per_force) else ("response", "radiation")
        missing = [key for key in needed if not callable(getattr(self, key))]
        if missing:
            raise WheelrailError(f"noise component {name!r} driven by {self.driven_by}: give {' and '.join(missing)}")

    @property
    def track_part(self) -> bool:
        """Whether it radiates from the track's vibration (``response``): a part of L_H,tr."""
        return self.driven_by == "force" and callable(self.response)


def _rail_radiation(chain: NoiseChain) -> float:
    """rho c P <n_y^2>: the rail section's perimeter and the mean square of its normals' vertical component."""
    section = rail_section()
    return AIR_DENSITY * SOUND_SPEED * section["perimeter_m"] * section["mean_normal_y_squared"]


def _sleeper_radiation(chain: NoiseChain) -> np.ndarray:
    """rho c S sigma(f): baffled pistons of the half sleeper's area S per rail."""
    area = chain.numerics.sleeper_area
    return AIR_DENSITY * SOUND_SPEED * area * piston_radiation_efficiency(chain.frequencies, area)[..., None]


def _rail_response(state: TrackResponse) -> float:
    return state.rail_radiated


def _unit_force_response(state: TrackResponse) -> float:
    """The mean-square contact force per unit force (1): a part whose vibration comes from a receptance of its own
    (the rail's lateral, :mod:`wheelrail.core.noise.rail_lateral`), read by its ``radiation``."""
    return 1.0


def _rail_lateral_radiation(chain: NoiseChain) -> np.ndarray:
    from wheelrail.core.noise.rail_lateral import lateral_rail_power

    return lateral_rail_power(chain)


def _sleeper_response(state: TrackResponse) -> float:
    return state.sleeper_velocity_sq


def _wheel_transfer(chain: NoiseChain) -> np.ndarray:
    return chain.wheel["db"]


def _wheel_power_per_force(chain: NoiseChain) -> np.ndarray:
    return chain.wheel["power_per_force"]


_BUILTIN = (
    NoiseComponent(
        name="rail",
        label="rail",
        colour=OKABE_ITO["orange"],
        driven_by="force",
        response=_rail_response,
        radiation=_rail_radiation,
    ),
    NoiseComponent(
        name="rail_lateral",
        label="rail, lateral",
        colour=TOL_INDIGO,
        driven_by="force",
        response=_unit_force_response,
        radiation=_rail_lateral_radiation,
    ),
    NoiseComponent(
        name="sleeper",
        label="sleeper",
        colour=OKABE_ITO["sky blue"],
        driven_by="force",
        response=_sleeper_response,
        radiation=_sleeper_radiation,
    ),
    NoiseComponent(name="wheel", label="wheel", colour=TOL_WINE, driven_by="roughness", transfer=_wheel_transfer),
)
_REGISTRY: dict[str, NoiseComponent] = {entry.name: entry for entry in _BUILTIN}
# the wheel of each wheel model (module docstring): the directive's is the registered entry above
_WHEELS = {
    "directive": _BUILTIN[-1],
    "modal": NoiseComponent(
        name="wheel",
        label="wheel",
        colour=TOL_WINE,
        driven_by="force",
        power_per_force=_wheel_power_per_force,
        transfer=_wheel_transfer,
    ),
}


def noise_components() -> tuple[NoiseComponent, ...]:
    """The registered components, in the order outputs list them.

    Returns
    -------
    tuple of NoiseComponent
        The built-in rail (vertical), rail (lateral), sleeper and wheel, then those registered with
        :func:`register_component`.
    """
    return tuple(_REGISTRY.values())


def chain_components(components: tuple, wheel_model: str) -> tuple[NoiseComponent, ...]:
    """``components`` (e.g. :func:`noise_components`) with the built-in wheel as ``wheel_model``'s.

    Parameters
    ----------
    components : tuple of NoiseComponent
        The chain's components.
    wheel_model : str
        "directive" (the wheel driven by the roughness through L_H,veh) or "modal" (driven by the contact force
        through the modal wheel's receptance and radiation).

    Returns
    -------
    tuple of NoiseComponent
        The same entries in the same order, the built-in wheel replaced by ``wheel_model``'s.
    """
    wheel = _WHEELS[wheel_model]
    return tuple(wheel if entry is _WHEELS["directive"] else entry for entry in components)


def component_names() -> tuple[str, ...]:
    """Their names."""
    return tuple(_REGISTRY)


def sound_power_parts() -> tuple[str, ...]:
    """Every sound power of a run's noise: the components' names, then :data:`TOTAL`."""
    return (*_REGISTRY, TOTAL)


def component(name: str) -> NoiseComponent:
    """The registered component ``name``, else one WheelrailError naming those there are."""
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise WheelrailError(f"unknown noise component {name!r}; one of {', '.join(_REGISTRY)}") from None


def register_component(entry: NoiseComponent) -> NoiseComponent:
    """Add a component to the chain, listed after those there are.

    Parameters
    ----------
    entry : NoiseComponent
        The component; its name must be new.

    Returns
    -------
    NoiseComponent
        ``entry``, registered.

    Raises
    ------
    WheelrailError
        If ``entry`` is not a NoiseComponent or its name is taken.

    Examples
    --------
    A damper on the rail radiating a quarter of the rail's sound power, in the chain until it is removed:

    >>> from wheelrail.core.noise.components import (
    ...     NoiseComponent, component, component_names, register_component, unregister_component)
    >>> rail = component("rail")
    >>> damper = NoiseComponent(name="rail_damper", label="rail damper", colour="#009E73", driven_by="force",
    ...                         response=rail.response, radiation=lambda chain: 0.25 * rail.radiation(chain))
    >>> register_component(damper).name, component_names()[-1]
    ('rail_damper', 'rail_damper')
    >>> unregister_component("rail_damper")
    >>> "rail_damper" in component_names()
    False
    """
    if not isinstance(entry, NoiseComponent):
        raise WheelrailError(f"register_component() takes a NoiseComponent, got {type(entry).__name__}")
    if entry.name in _REGISTRY:
        raise WheelrailError(f"a noise component named {entry.name!r} is already registered")
    _REGISTRY[entry.name] = entry
    return entry


def unregister_component(name: str) -> None:
    """Remove a component added with :func:`register_component` (the built-in ones stay).

    Parameters
    ----------
    name : str
        The component's name; a name not registered is nothing to remove.

    Raises
    ------
    WheelrailError
        If ``name`` is a built-in component's.
    """
    if any(entry.name == name for entry in _BUILTIN):
        raise WheelrailError(f"the built-in noise component {name!r} cannot be removed")
    _REGISTRY.pop(name, None)
