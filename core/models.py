"""The contact models: one registry, one interface (paper section 2.3).

The interaction loop (``wheelrail.core.engine``) owns the wheel and track of eqs. 1-2 and asks a contact
model only for its law: given the part of the approach known from the history, delta_known, and the
instantaneous compliance c (delta = delta_known - c F), return the force and the contact state. A model
declares what the loop must know about it as :class:`ModelTraits` in its registry entry; nothing outside this
registry tests a model's name.

Each model names the law that steps it (``ModelTraits.law``): a ``ContactLaw`` of the run engine
(``wheelrail.core.engine.laws``), given as the class or as ``"module:Class"`` imported on first use. The built-in
ones: ``LAW_HERTZ`` and ``LAW_BEDDING`` (compiled one-line laws), ``LAW_HALFSPACE`` (the 3D half-space and its
window). A compiled law runs in its own numba chunk loop and reads the model's :class:`LawInputs` (or, for the
3D half-space, its stepping state); a model with no law (None) has its Python ``solve`` called once per step (any
model registered from outside without a law of its own, e.g. in a test, and the 3D half-space's per-step
reference). Adding a compiled law is one module (its kernel, its chunk loop and a ``CompiledLaw`` subclass) and
one registry entry.

This module is cheap to import (no numba, no SciPy): the command line, the studies and the explorer read the
model names and traits from it (:func:`model_names`, :func:`model_entry`); the implementation is imported on
first use.

Adding a model: one :class:`ContactModel` class and one :class:`ModelEntry`, added to ``_BUILTIN`` below, declared
by another package as an entry point of the group ``wheelrail.contact_models`` (a plug-in, named as its model: found
the first time a model is asked for; one that fails to load is skipped with a :class:`PluginWarning`), or given to
:func:`register` (this process only). The user guide's "Adding a contact model" shows one.
"""

from __future__ import annotations

import importlib
import re
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ModelParameters

__all__ = [
    "AVERAGE_FILTER_MODEL",
    "BEDDING_MODEL",
    "ENTRY_POINT_GROUP",
    "HALFSPACE_MODEL",
    "LAW_BEDDING",
    "LAW_HALFSPACE",
    "LAW_HERTZ",
    "MODELS",
    "REFERENCE_MODEL",
    "WINKLER_FILTER_MODEL",
    "ContactModel",
    "ContactState",
    "LawInputs",
    "ModelEntry",
    "ModelInputs",
    "ModelTraits",
    "PluginWarning",
    "model_entry",
    "model_names",
    "register",
    "unregister",
]

# the built-in laws (engine.laws): Hertz spring on an equivalent roughness (eqs. 12-14), Winkler bedding on the line
# under the wheel (eqs. 3-6), 3D half-space on the window (eqs. 8-11)
LAW_HERTZ = "wheelrail.core.engine.laws.one_line:HertzLaw"
LAW_BEDDING = "wheelrail.core.engine.laws.one_line:BeddingLaw"
LAW_HALFSPACE = "wheelrail.core.engine.laws.halfspace:HalfSpaceLaw"
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*")
_CLASS_PATH = re.compile(r"[A-Za-z_][\w.]*:[A-Za-z_]\w*")


@dataclass(frozen=True, kw_only=True)
class ModelTraits:
    """What the loop must know about a contact model.

    Attributes
    ----------
    lateral_window : bool
        The model sees a window of roughness lines across the rail (1 mm apart, centred on the chosen line)
        instead of the chosen line alone.
    law : type, str or None
        The ``ContactLaw`` (``wheelrail.core.engine.laws``) that steps the model: the class, or ``"module:Class"``
        imported on first use (``LAW_HERTZ``, ``LAW_BEDDING``, ``LAW_HALFSPACE``, a plug-in's); None: the model's
        ``solve`` is called from Python once per step (streamed step by step).
    pressure_map : bool
        Every step has a pressure map on the window (``StepState.pressure``); needs ``lateral_window``.

    Raises
    ------
    WheelrailError
        For a ``law`` that is neither a class, a ``"module:Class"`` nor None, or a pressure map without a lateral
        window.
    """

    lateral_window: bool = False
    law: type | str | None = None
    pressure_map: bool = False

    def __post_init__(self) -> None:
        law = self.law
        if not (law is None or isinstance(law, type) or isinstance(law, str) and _CLASS_PATH.fullmatch(law)):
            raise WheelrailError(
                f"ModelTraits.law must be a ContactLaw class, its 'module:Class' or None, got {self.law!r}"
            )
        if self.pressure_map and not self.lateral_window:
            raise WheelrailError("ModelTraits: a pressure map needs a lateral window")

    @property
    def compiled(self) -> bool:
        """The law runs in the compiled chunk loop (else per step from Python)."""
        return self.law is not None


@dataclass(frozen=True, kw_only=True)
class ModelInputs:
    """What a model is given to prepare a run (built by ``wheelrail.core.engine.history.model_inputs``).

    Step index s counts the run-in too: s = 0 is the first run-in step, ``n_total`` steps in all.

    Attributes
    ----------
    params : ModelParameters
    element_size : float
        Delta x, m (also the lateral spacing of ``lines`` for a lateral window).
    lines : ndarray (rows, samples)
        Roughness along the track on the model grid, m (one row, or the window's rows).
    centre_row : int
        Row of ``lines`` that is the chosen line.
    window_y : ndarray (rows,)
        Lateral position of each row relative to the chosen line, m.
    half_x : int
        Half-width of the window along the rail (and of the bedding), elements.
    start_index : ndarray (n_total,) int
        Sample of ``lines`` under the wheel centre at each step.
    ramp : ndarray (n_total,)
        Fade-in factor of the roughness over the run-in (1 afterwards).
    position_of : callable
        Wheel position of step s, m (for messages).
    equivalent_offset : ndarray (samples,) or None
        Added to the model's equivalent roughness along the track, m: a run's discrete irregularities as a Hertz
        model meets them (``ContactLaw.irregular_surface``); None without.
    """

    params: ModelParameters
    element_size: float
    lines: np.ndarray
    centre_row: int
    window_y: np.ndarray
    half_x: int
    start_index: np.ndarray
    ramp: np.ndarray
    position_of: Callable[[int], float]
    equivalent_offset: np.ndarray | None = None

    @property
    def n_total(self) -> int:
        return int(self.start_index.shape[0])

    @property
    def centre_line(self) -> np.ndarray:
        """The chosen line along the track, m."""
        return self.lines[self.centre_row]


@dataclass(frozen=True)
class LawInputs:
    """Inputs of a compiled law for every step: ``roughness[s]`` (row of floats), ``shape``, ``constants``.

    ``LAW_HERTZ``: roughness (n_total, 1) = r_eq faded in; shape unused; constants = (C, rho_x, rho_y) (the Hertz
    constant and ``ContactParameters.patch_radii``: (C_H, R, R) for the paper's circle).
    ``LAW_BEDDING``: roughness (n_total, 2 half_x + 1) = r under the bedding; shape = wheel profile x'^2/(2 R_m);
    constants = (k dx, dx) (``contact.winkler.calibrated_bedding``).
    """

    roughness: np.ndarray
    shape: np.ndarray
    constants: np.ndarray


class ContactState(NamedTuple):
    """A per-step law's answer (a NamedTuple: one is made per step).

    Attributes
    ----------
    force : float
        Contact force F, N.
    contact_length : float
        Contact length along the chosen line, m.
    contact_area : float
        Contact area, m^2 (NaN where the model has none).
    pressure : numpy.ndarray or None
        Pressure map on the window, Pa (models with one).
    """

    force: float
    contact_length: float
    contact_area: float
    pressure: np.ndarray | None = None


class ContactModel:
    """A contact model inside the loop. Subclasses implement :meth:`prepare` and, by their traits, either
    :meth:`law_inputs` (compiled law) or :meth:`solve` (per step).

    Attributes
    ----------
    equivalent_line : numpy.ndarray
        After :meth:`prepare`: the roughness the model sees on the chosen line along the track, m (r_eq for
        the Hertz variants, r otherwise).
    window_x : numpy.ndarray or None
        The element centres of its window along the rail relative to the wheel, m; None without a window.

    See Also
    --------
    ModelEntry : registers a model under a name.
    """

    equivalent_line: np.ndarray
    window_x: np.ndarray | None = None

    def prepare(self, inputs: ModelInputs) -> float:
        """Precompute; return the static approach delta(P) on smooth surfaces under the preload, m."""
        raise NotImplementedError

    def law_inputs(self) -> LawInputs:
        """Compiled law: the kernel's inputs for every step (the 3D half-space: a
        ``contact.active_set.ActiveSetSolver``)."""
        raise NotImplementedError

    def solve(self, s: int, approach_known: float, compliance: float) -> ContactState:
        """Per-step law: solve the contact with delta = approach_known - compliance F at step s."""
        raise NotImplementedError

    def edge_message(self, s: int) -> str:
        """Why the compiled law stopped at step s (it reached the end of its window)."""
        return f"the contact reached the edge of the {type(self).__name__} window at step {s}"


@dataclass(frozen=True, kw_only=True)
class ModelEntry:
    """One registered contact model.

    Attributes
    ----------
    name : str
        As users type it (letters, digits, ``-``, ``_``): it becomes part of file names and table columns.
    label : str
        One line describing the model.
    traits : ModelTraits
        What the model computes and how the loop runs it.
    implementation : str or type
        A :class:`ContactModel` subclass, or ``"module:Class"`` imported on first use.

    Raises
    ------
    WheelrailError
        For a name that is not a plain word, a label that is not one line, or traits of the wrong type.

    See Also
    --------
    register : adds an entry at run time (plug-ins: the module docstring).
    """

    name: str
    label: str
    traits: ModelTraits
    implementation: str | type

    def __post_init__(self) -> None:
        # the name is typed on the command line and becomes part of file names and table columns
        if not (isinstance(self.name, str) and _NAME.fullmatch(self.name)):
            raise WheelrailError(
                f"ModelEntry.name must be letters, digits, '-' or '_' (starting with a letter or "
                f"digit), got {self.name!r}"
            )
        if not (isinstance(self.label, str) and self.label.strip() and "\n" not in self.label):
            raise WheelrailError(f"ModelEntry.label must be one line of text, got {self.label!r}")
        if not isinstance(self.traits, ModelTraits):
            raise WheelrailError(f"ModelEntry.traits must be a ModelTraits, got {type(self.traits).__name__}")

    def create(self) -> ContactModel:
        """A fresh model instance for one run."""
        target = self.implementation
        if isinstance(target, str):
            module, _, attribute = target.partition(":")
            target = getattr(importlib.import_module(module), attribute)
        return target()


_BUILTIN = (
    ModelEntry(
        name="3d",
        label="3D elastic half-space on a window of lines (eqs. 8-11)",
        traits=ModelTraits(lateral_window=True, law=LAW_HALFSPACE, pressure_map=True),
        implementation="wheelrail.core.contact.halfspace_model:HalfSpaceModel",
    ),
    ModelEntry(
        name="2d",
        label="2D Winkler bedding on one line (eqs. 3-6)",
        traits=ModelTraits(law=LAW_BEDDING),
        implementation="wheelrail.core.contact.winkler:BeddingModel",
    ),
    ModelEntry(
        name="hertz",
        label="Hertz spring, unfiltered roughness (eqs. 12-14)",
        traits=ModelTraits(law=LAW_HERTZ),
        implementation="wheelrail.core.contact.hertz_model:HertzModel",
    ),
    ModelEntry(
        name="hertz-winkler",
        label="Hertz spring, roughness pre-filtered by the Winkler bedding",
        traits=ModelTraits(law=LAW_HERTZ),
        implementation="wheelrail.core.contact.hertz_model:HertzWinklerModel",
    ),
    ModelEntry(
        name="hertz-average",
        label="Hertz spring, roughness averaged over the contact length 2a",
        traits=ModelTraits(law=LAW_HERTZ),
        implementation="wheelrail.core.contact.hertz_model:HertzAverageModel",
    ),
)

MODELS: tuple[str, ...] = tuple(entry.name for entry in _BUILTIN)  # the built-in models, in menu order
REFERENCE_MODEL = "hertz"  # no roughness filtering: the reference of every contact filter (paper section 3.3)
# the paper's other models by their part in its figures (section 3), for the studies that reproduce them
HALFSPACE_MODEL = "3d"  # the 3D model the others are compared with (Figs 10, 12, 16, 17)
BEDDING_MODEL = "2d"  # the 2D Winkler bedding (Figs 12-16, 18)
WINKLER_FILTER_MODEL = "hertz-winkler"  # Hertz on the roughness pre-filtered by the bedding (Fig. 13)
AVERAGE_FILTER_MODEL = "hertz-average"  # Hertz on the roughness averaged over 2a (Fig. 14)
ENTRY_POINT_GROUP = "wheelrail.contact_models"  # plug-ins: entry points that load a ModelEntry
_REGISTRY: dict[str, ModelEntry] = {entry.name: entry for entry in _BUILTIN}
_plugins_loaded = False


class PluginWarning(UserWarning):
    """A contact-model plug-in could not be used (it is skipped; the message names it)."""


def _load_plugins() -> None:
    """Add the installed plug-ins (entry points of ``ENTRY_POINT_GROUP``) to the registry, once per process.

    Each entry point is loaded on its own: one that raises, does not give a ``ModelEntry``, is named other
    than its entry or takes a name already used is skipped with one :class:`PluginWarning`, and the others
    still load.
    """
    global _plugins_loaded
    if _plugins_loaded:
        return
    _plugins_loaded = True
    import importlib.metadata  # here, not at import: a command that asks for no model does not load it

    for point in sorted(importlib.metadata.entry_points(group=ENTRY_POINT_GROUP), key=lambda p: p.name):
        problem = _plugin_problem(point)
        if problem:
            where = f" from {point.dist.name} {point.dist.version}" if point.dist is not None else ""
            warnings.warn(
                f"contact-model plug-in {point.name!r} ({point.value}{where}) is skipped: {problem}",
                PluginWarning,
                stacklevel=3,
            )


def _plugin_problem(point) -> str | None:
    """Register one entry point's model; what is wrong with it (None: registered)."""
    try:
        entry = point.load()
    except Exception as error:  # noqa: BLE001 - a plug-in's own failure, whatever it is, must not stop us
        return f"loading it raised {type(error).__name__}: {error}"
    if not isinstance(entry, ModelEntry):
        return f"it gives a {type(entry).__name__}, not a wheelrail.core.models.ModelEntry"
    if entry.name != point.name:
        return f"the entry point's name must be the model's name, {entry.name!r}"
    if entry.name in _REGISTRY:
        return "a contact model of that name is already registered"
    _REGISTRY[entry.name] = entry
    return None


def register(entry: ModelEntry) -> ModelEntry:
    """Add a model to the registry at run time (e.g. from a test).

    A model meant for other people is better a plug-in (the module docstring): it then reaches a study's
    worker processes too.

    Parameters
    ----------
    entry : ModelEntry
        The model; its name must be new.

    Returns
    -------
    ModelEntry
        ``entry``, registered.

    Raises
    ------
    WheelrailError
        If ``entry`` is not a ModelEntry or its name is taken.

    See Also
    --------
    model_names, model_entry
    """
    if not isinstance(entry, ModelEntry):
        raise WheelrailError(f"register() takes a ModelEntry, got {type(entry).__name__}")
    _load_plugins()
    if not entry.name or entry.name in _REGISTRY:
        raise WheelrailError(f"a contact model named {entry.name!r} is already registered (or the name is empty)")
    _REGISTRY[entry.name] = entry
    return entry


def unregister(name: str) -> None:
    """Remove a model added with :func:`register` or by a plug-in (the built-in ones stay)."""
    if name in MODELS:
        raise WheelrailError(f"the built-in model {name!r} cannot be removed")
    _REGISTRY.pop(name, None)


def model_names() -> tuple[str, ...]:
    """The names of the registered contact models.

    Returns
    -------
    tuple of str
        The built-in models first (``MODELS``), then the plug-ins and those added by :func:`register`.

    Examples
    --------
    >>> from wheelrail.core.models import model_names
    >>> model_names()[:5]
    ('3d', '2d', 'hertz', 'hertz-winkler', 'hertz-average')
    """
    _load_plugins()
    return tuple(_REGISTRY)


def model_entry(name: str) -> ModelEntry:
    """The registry entry of a model.

    Parameters
    ----------
    name : str
        A registered model's name (:func:`model_names`).

    Returns
    -------
    ModelEntry
        Its label, traits and implementation.

    Raises
    ------
    WheelrailError
        For an unknown name, listing the choices.
    """
    _load_plugins()
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise WheelrailError(f"unknown contact model {name!r}; choose one of {', '.join(_REGISTRY)}") from None
