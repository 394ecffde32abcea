"""A wheel's modes for every harmonic n = 0..N up to a frequency, with their damping, cached on disk like the track.

:func:`wheel_modes` meshes the cross-section (``mesh``), assembles the harmonic matrices (``fem``) and solves
each harmonic; the result goes through :mod:`wheelrail.core.files.cache` (kind ``"wheel-modes"``, keyed by the
profile, the mesh size, the material, the boundary condition, the frequency range and ``MODES_VERSION``) and a
small in-memory cache, so a second call for the same wheel reads it back.

Modal damping (:func:`modal_loss_factor`): a solid steel wheel's modes are very lightly damped; following
Thompson (*Railway Noise and Vibration*, Elsevier 2009, section 5.2.3, and TWINS's defaults it describes), the
loss factor is taken as 1e-3 for the n = 0 and n = 1 modes, which move the hub and are damped by their coupling
to the axle, and 1e-4 for the modes of n >= 2 (all families; the text gives damping ratios of order 1e-4 for a
free wheel's n >= 2 modes: these values are typical, not measured for a given wheel). An added damper's loss
factor (``added_loss_factor``) adds to every mode's.

Cost (:func:`modes_cost`): the work is the mesh's elements (``mesh.estimated_elements``, known before meshing) x
the harmonics x max(1, ``max_frequency`` / 10 kHz) (more modes to find per harmonic); measured on the project's
2-core machine, shared, ``SECONDS_PER_WORK`` of CPU per unit for meshes of 3 000 to 12 000 elements (fewer
elements cost less per unit). A computation of more than ``WORK_LIMIT`` units (about two minutes; the default
wheel's is 3 400 units, 1.5 s) is refused before anything is assembled, saying what it would cost; so is a mesh
of more than ``MAX_ELEMENTS`` (the assembly holds about 45 kB per element, measured: 20 000 elements, ~0.9 GB).

Modes below ``MIN_MODE_FREQUENCY`` (1 Hz) are motions without strain: a clamped wheel has none (its lowest
modes are tens of Hz or more), so one found is a mechanism of the mesh and refused; a free hub has the two
rigid-body motions of n = 0 (along and about the axle) and two of n = 1 (across it, rocking), kept in the
modal sums (they carry the wheel's mass) and flagged by ``WheelModes.rigid_body``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.modal_wheel.fem import FAMILIES, STEEL, Material, harmonic_matrices, harmonic_modes
from wheelrail.core.modal_wheel.mesh import Mesh, estimated_elements, mesh_outline, simplified
from wheelrail.core.modal_wheel.section import check_element_size

__all__ = [
    "DEFAULT_ELEMENT_SIZE",
    "MIN_MODE_FREQUENCY",
    "MODES_VERSION",
    "MAX_ELEMENTS",
    "WORK_LIMIT",
    "ModesCost",
    "WheelModes",
    "modal_loss_factor",
    "modes_cost",
    "wheel_modes",
]

MODES_VERSION = 3  # bump when the meshing, the elements or the stored arrays change (the cache's key)
WORK_LIMIT = 200_000  # elements x harmonics x max(1, f / 10 kHz): about two minutes (module docstring)
MAX_ELEMENTS = 20_000  # the assembly's memory (module docstring)
BYTES_PER_ELEMENT = 45e3  # the assembly's peak memory per element, measured (11 700 elements: 625 MB)
SECONDS_PER_WORK = 6.7e-4  # CPU s per unit of work, measured (module docstring)
MIN_MODE_FREQUENCY = 1.0  # Hz: below, a motion without strain (module docstring)
_RIGID_BODY_MODES = {0: 2, 1: 2}  # a free hub's rigid-body motions per harmonic
DEFAULT_ELEMENT_SIZE = 0.012  # m: frequencies up to 10 kHz within 1 % of a mesh twice as fine (tests/physics)
LOSS_FACTOR_HUB = 1e-3  # n = 0, 1: coupled to the axle (module docstring)
LOSS_FACTOR_WHEEL = 1e-4  # n >= 2
_ARRAYS = ("frequency", "harmonic", "family", "shapes", "nodes", "triangles", "boundary", "static", "static_fields",
           "contact_node")  # fmt: skip


@dataclass(frozen=True)
class WheelModes:
    """A wheel's modes (module docstring).

    Attributes
    ----------
    profile : WheelProfile or OutlineProfile
        The cross-section.
    mesh : Mesh
        Its 6-node triangles (m).
    frequency : ndarray (n_modes,)
        Natural frequencies, Hz, ordered by harmonic then frequency.
    harmonic : ndarray (n_modes,) of int
        n, the number of nodal diameters.
    family : ndarray (n_modes,) of str
        "axial", "radial" or "circumferential" (the component with the most kinetic energy).
    shapes : ndarray (n_modes, 3 n_nodes)
        Mass-normalised shapes (U_r, U_z, U_theta per node), m per unit modal coordinate (kg^-1/2).
    static : ndarray (N + 1, 2, 2)
        Static flexibility at the contact per harmonic, (radial, axial) x (radial, axial), m/N.
    static_fields : ndarray (N + 1, 2, 3 n_nodes)
        Static displacement of every node per unit radial and axial force at the contact, per harmonic, m/N (zero
        for a free hub's n = 0, 1).
    contact_node : int
        The mesh node at the contact.
    max_frequency, max_harmonic, element_size, material, clamped :
        What was computed (Hz, -, m, Material, the bore held or free).
    """

    profile: object
    mesh: Mesh
    frequency: np.ndarray
    harmonic: np.ndarray
    family: np.ndarray
    shapes: np.ndarray
    static: np.ndarray
    static_fields: np.ndarray
    contact_node: int
    max_frequency: float
    max_harmonic: int
    element_size: float
    material: Material = STEEL
    clamped: bool = True
    cache_path: str = ""

    @property
    def rigid_body(self) -> np.ndarray:
        """(n_modes,) of bool: the free hub's rigid-body motions (module docstring), not natural frequencies."""
        return self.frequency < MIN_MODE_FREQUENCY

    def loss_factor(self, added_loss_factor: float = 0.0) -> np.ndarray:
        """Each mode's loss factor (:func:`modal_loss_factor`)."""
        return modal_loss_factor(self.harmonic, self.family, added_loss_factor)

    def contact_shapes(self) -> np.ndarray:
        """(n_modes, 2): each mode's radial and axial displacement at the contact (kg^-1/2)."""
        return self.shapes[:, [3 * self.contact_node, 3 * self.contact_node + 1]]


def modal_loss_factor(harmonic, family, added_loss_factor: float = 0.0) -> np.ndarray:
    """Loss factors of modes by harmonic: 1e-3 for n = 0, 1 and 1e-4 for n >= 2, plus a damper's.

    Parameters
    ----------
    harmonic : array_like of int
        n of each mode.
    family : array_like of str
        Family of each mode (kept for per-family values; the defaults depend on n alone, module docstring).
    added_loss_factor : float
        A damper's loss factor added to every mode's, 0 to 1.

    Returns
    -------
    numpy.ndarray
        One loss factor per mode.

    Raises
    ------
    WheelrailError
        An added loss factor outside 0 to 1, in one line.
    """
    if not (isinstance(added_loss_factor, int | float) and 0.0 <= added_loss_factor <= 1.0):
        raise WheelrailError(
            None,
            Blame(
                "added_loss_factor",
                added_loss_factor,
                unit="",
                minimum=0.0,
                maximum=1.0,
                reason="a loss factor added by a damper, up to 1",
            ),
        )
    n = np.asarray(harmonic)
    base = np.where(n <= 1, LOSS_FACTOR_HUB, LOSS_FACTOR_WHEEL)
    return base + float(added_loss_factor) + 0.0 * np.zeros(np.shape(family))


@dataclass(frozen=True)
class ModesCost:
    """What computing a wheel's modes costs (module docstring): ``elements`` (estimated), ``harmonics`` (N + 1),
    ``work`` (units), ``seconds`` (CPU s, estimated)."""

    elements: int
    harmonics: int
    max_frequency: float
    work: float
    seconds: float

    def describe(self) -> str:
        """One sentence: the work and its estimated time."""
        return (f"about {self.elements} elements x {self.harmonics} harmonics up to {self.max_frequency:g} Hz: "
                f"{self.work:,.0f} units of work, about {self.seconds:.0f} s of CPU")  # fmt: skip


def modes_cost(profile, max_frequency: float, max_harmonic: int, element_size: float) -> ModesCost:
    """The cost of :func:`wheel_modes` for these settings, from the mesh's size before it is made.

    Parameters
    ----------
    profile : WheelProfile or OutlineProfile
        The cross-section.
    max_frequency : float
        Hz.
    max_harmonic : int
        N (harmonics 0..N).
    element_size : float
        m.

    Returns
    -------
    ModesCost
        Elements, harmonics, work units and the estimated CPU seconds (``SECONDS_PER_WORK`` per unit).
    """
    outline = simplified(profile.outline(), element_size, profile.contact_point())
    elements = estimated_elements(outline, element_size)
    work = float(elements) * (max_harmonic + 1) * max(1.0, max_frequency / 10e3)
    return ModesCost(elements, max_harmonic + 1, float(max_frequency), work, work * SECONDS_PER_WORK)


def _check_cost(cost: ModesCost, element_size: float) -> None:
    if cost.elements > MAX_ELEMENTS:
        raise WheelrailError(
            f"a mesh of about {cost.elements:,} elements is more than the {MAX_ELEMENTS:,} allowed (the assembly holds "
            f"about {MAX_ELEMENTS * BYTES_PER_ELEMENT / 1e9:.1f} GB at that size; the 920 mm wheel at 2 mm has "
            "11 700): use larger elements",
            Blame("wheel_element_size", element_size, unit="m"),
        )
    if cost.work > WORK_LIMIT:
        limit_s = WORK_LIMIT * SECONDS_PER_WORK
        raise WheelrailError(
            f"these modes are {cost.describe()}, more than the {WORK_LIMIT:,} units (about {limit_s / 60:.0f} minutes) "
            "allowed; use larger elements, fewer harmonics or a lower maximum frequency",
            Blame("wheel_element_size", element_size, unit="m"),
        )


def _key(profile, element_size: float, max_frequency: float, max_harmonic: int, material: Material, clamped: bool):
    from wheelrail.core.files.cache import cache_key

    description = {
        "profile": profile.describe(),
        "element_size": element_size,
        "max_frequency": max_frequency,
        "max_harmonic": max_harmonic,
        "material": asdict(material),
        "clamped": clamped,
        "version": MODES_VERSION,
    }
    return cache_key("wheel-modes", description)


_MEMORY: dict[str, WheelModes] = {}


def wheel_modes(
    profile,
    *,
    max_frequency: float = 10e3,
    max_harmonic: int = 10,
    element_size: float = DEFAULT_ELEMENT_SIZE,
    material: Material = STEEL,
    clamped: bool = True,
    use_cache: bool = True,
    announce: Callable[[ModesCost], None] | None = None,
) -> WheelModes:
    """Every mode of the wheel ``profile`` with n = 0..``max_harmonic`` up to ``max_frequency`` (Hz).

    Parameters
    ----------
    profile : WheelProfile or OutlineProfile
        The cross-section (``wheelrail.core.modal_wheel.profile``).
    max_frequency : float
        Hz, 100 to 30 000.
    max_harmonic : int
        N, 0 to 40.
    element_size : float
        The mesh's element size, m, 2 to 50 mm (``section.ELEMENT_SIZE``; default: ``DEFAULT_ELEMENT_SIZE``).
    material : Material
        Default: steel.
    clamped : bool
        Hold the bore (the axle seat), as TWINS does; False: a free wheel.
    use_cache : bool
        Read and write the disk cache (module docstring).
    announce : callable, optional
        Called with the :class:`ModesCost` just before modes not found in a cache are computed.

    Returns
    -------
    WheelModes
        Frequencies, harmonics, families, mode shapes and static corrections (read from the cache when there).

    Raises
    ------
    WheelrailError
        A profile, range or mesh outside what is accepted, more work than ``WORK_LIMIT`` (said before anything is
        assembled), a mechanism (a mode below ``MIN_MODE_FREQUENCY`` that is no free hub's rigid-body motion), in
        one line.
    """
    if not (isinstance(max_harmonic, int | np.integer) and 0 <= max_harmonic <= 40):
        raise WheelrailError(None, Blame("max_harmonic", max_harmonic, unit="", minimum=0, maximum=40))
    if not (isinstance(max_frequency, int | float) and 100.0 <= max_frequency <= 30e3):
        raise WheelrailError(None, Blame("max_frequency", max_frequency, unit="Hz", minimum=100.0, maximum=30e3))
    max_frequency, element_size = float(max_frequency), check_element_size(element_size)
    key = _key(profile, element_size, max_frequency, int(max_harmonic), material, clamped)
    if use_cache and key in _MEMORY:
        return _MEMORY[key]
    modes = _from_cache(profile, key, material, clamped) if use_cache else None
    if modes is None:
        cost = modes_cost(profile, max_frequency, int(max_harmonic), element_size)
        _check_cost(cost, element_size)
        if announce is not None:
            announce(cost)
        start = time.perf_counter()
        modes = _computed(profile, max_frequency, int(max_harmonic), element_size, material, clamped)
        if use_cache:
            modes = _saved(modes, key, time.perf_counter() - start)
    if use_cache:
        while len(_MEMORY) >= 8:
            del _MEMORY[next(iter(_MEMORY))]
        _MEMORY[key] = modes
    return modes


def _computed(profile, max_frequency, max_harmonic, element_size, material, clamped) -> WheelModes:
    mesh = mesh_outline(profile.outline(), element_size, keep=profile.contact_point())
    contact = int(np.argmin(np.hypot(*(mesh.nodes - np.asarray(profile.contact_point())).T)))
    model = harmonic_matrices(mesh, material)
    bore = profile.bore_radius if clamped else None
    parts = [harmonic_modes(model, n, max_frequency, bore, contact) for n in range(max_harmonic + 1)]
    for n, part in enumerate(parts):
        _check_strain_free(part.frequency, n, clamped)
    return WheelModes(
        profile=profile,
        mesh=mesh,
        frequency=np.concatenate([p.frequency for p in parts]),
        harmonic=np.concatenate([np.full(len(p.frequency), n) for n, p in enumerate(parts)]).astype(np.int64),
        family=np.array(FAMILIES)[np.concatenate([p.family for p in parts]).astype(np.int64)],
        shapes=np.concatenate([p.shapes for p in parts]),
        static=np.stack([p.static for p in parts]),
        static_fields=np.stack([p.static_fields for p in parts]),
        contact_node=contact,
        max_frequency=max_frequency,
        max_harmonic=max_harmonic,
        element_size=element_size,
        material=material,
        clamped=clamped,
    )


def _check_strain_free(frequency: np.ndarray, harmonic: int, clamped: bool) -> None:
    """Refuse modes below ``MIN_MODE_FREQUENCY`` but a free hub's rigid-body motions (module docstring)."""
    low = frequency[frequency < MIN_MODE_FREQUENCY]
    allowed = 0 if clamped else _RIGID_BODY_MODES.get(harmonic, 0)
    if len(low) > allowed:
        raise WheelrailError(
            f"the wheel's mesh moves without strain: {len(low)} mode(s) of n = {harmonic} below "
            f"{MIN_MODE_FREQUENCY:g} Hz ({float(low.max()):.2g} Hz), where a {'clamped' if clamped else 'free'} wheel "
            f"has {allowed}; a part hangs on too thin a link: use smaller elements or a thicker part"
        )


def _saved(modes: WheelModes, key: str, compute_s: float) -> WheelModes:
    from wheelrail.core.files import cache

    arrays = {
        "frequency": modes.frequency,
        "harmonic": modes.harmonic,
        "family": np.array([FAMILIES.index(f) for f in modes.family], dtype=np.int64),
        "shapes": modes.shapes,
        "nodes": modes.mesh.nodes,
        "triangles": modes.mesh.triangles,
        "boundary": modes.mesh.boundary,
        "static": modes.static,
        "static_fields": modes.static_fields,
        "contact_node": np.array(modes.contact_node),
        "settings": np.array([modes.max_frequency, modes.max_harmonic, modes.element_size]),
    }
    path = cache.save_entry("wheel-modes", key, arrays, info={"compute_s": compute_s})
    return WheelModes(**{**modes.__dict__, "cache_path": str(path) if path is not None else ""})


def _from_cache(profile, key: str, material: Material, clamped: bool) -> WheelModes | None:
    from wheelrail.core.files import cache

    arrays = cache.load_entry("wheel-modes", key, (*_ARRAYS, "settings"))
    if arrays is None:
        return None
    max_frequency, max_harmonic, element_size = arrays["settings"]
    return WheelModes(
        profile=profile,
        mesh=Mesh(nodes=arrays["nodes"], triangles=arrays["triangles"], boundary=arrays["boundary"]),
        frequency=arrays["frequency"],
        harmonic=arrays["harmonic"],
        family=np.array(FAMILIES)[arrays["family"]],
        shapes=arrays["shapes"],
        static=arrays["static"],
        static_fields=arrays["static_fields"],
        contact_node=int(arrays["contact_node"]),
        max_frequency=float(max_frequency),
        max_harmonic=int(max_harmonic),
        element_size=float(element_size),
        material=material,
        clamped=clamped,
        cache_path=str(cache.entry_path("wheel-modes", key)),
    )
