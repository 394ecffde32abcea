"""A wheel's modes for every harmonic n = 0..N up to a frequency, with their damping, cached on disk like the track.

:func:`wheel_modes` meshes the cross-section (``mesh``), assembles the harmonic matrices (``fem``) and solves
each harmonic; the result goes through :mod:`wheelrail.core.cache` (kind ``"wheel-modes"``, keyed by the
profile, the mesh size, the material, the boundary condition, the frequency range and ``MODES_VERSION``) and a
small in-memory cache, so a second call for the same wheel reads it back.

Modal damping (:func:`modal_loss_factor`): a solid steel wheel's modes are very lightly damped; following
Thompson (*Railway Noise and Vibration*, Elsevier 2009, section 5.2.3, and TWINS's defaults it describes), the
loss factor is taken as 1e-3 for the n = 0 and n = 1 modes, which move the hub and are damped by their coupling
to the axle, and 1e-4 for the modes of n >= 2 (all families; the text gives damping ratios of order 1e-4 for a
free wheel's n >= 2 modes: these values are typical, not measured for a given wheel). An added damper's loss
factor (``added_loss_factor``) adds to every mode's.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.modal_wheel.fem import FAMILIES, STEEL, Material, harmonic_matrices, harmonic_modes
from wheelrail.core.modal_wheel.mesh import Mesh, mesh_outline

__all__ = [
    "DEFAULT_ELEMENT_SIZE",
    "MODES_VERSION",
    "WheelModes",
    "modal_loss_factor",
    "wheel_modes",
]

MODES_VERSION = 2  # bump when the meshing, the elements or the stored arrays change (the cache's key)
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

    def loss_factor(self, added_loss_factor: float = 0.0) -> np.ndarray:
        """Each mode's loss factor (:func:`modal_loss_factor`)."""
        return modal_loss_factor(self.harmonic, self.family, added_loss_factor)

    def contact_shapes(self) -> np.ndarray:
        """(n_modes, 2): each mode's radial and axial displacement at the contact (kg^-1/2)."""
        return self.shapes[:, [3 * self.contact_node, 3 * self.contact_node + 1]]


def modal_loss_factor(harmonic, family, added_loss_factor: float = 0.0) -> np.ndarray:
    """Loss factors of modes of harmonics ``harmonic`` (families ``family``, kept for per-family values): 1e-3 for
    n = 0, 1, 1e-4 for n >= 2 (module docstring), plus ``added_loss_factor`` (0 to 1: a damper's)."""
    if not (isinstance(added_loss_factor, int | float) and 0.0 <= added_loss_factor <= 1.0):
        raise WheelrailError(
            None, parameter="added_loss_factor", value=added_loss_factor, minimum=0.0, maximum=1.0, unit="",
            reason="a loss factor added by a damper, up to 1",
        )  # fmt: skip
    n = np.asarray(harmonic)
    base = np.where(n <= 1, LOSS_FACTOR_HUB, LOSS_FACTOR_WHEEL)
    return base + float(added_loss_factor) + 0.0 * np.zeros(np.shape(family))


def _key(profile, element_size: float, max_frequency: float, max_harmonic: int, material: Material, clamped: bool):
    from wheelrail.core.cache import cache_key

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
        The mesh's element size, m (default: ``DEFAULT_ELEMENT_SIZE``).
    material : Material
        Default: steel.
    clamped : bool
        Hold the bore (the axle seat), as TWINS does; False: a free wheel.
    use_cache : bool
        Read and write the disk cache (module docstring).
    """
    if not (isinstance(max_harmonic, int | np.integer) and 0 <= max_harmonic <= 40):
        raise WheelrailError(None, parameter="max_harmonic", value=max_harmonic, minimum=0, maximum=40, unit="")
    if not (isinstance(max_frequency, int | float) and 100.0 <= max_frequency <= 30e3):
        raise WheelrailError(None, parameter="max_frequency", value=max_frequency, minimum=100.0, maximum=30e3,
                             unit="Hz")  # fmt: skip
    max_frequency, element_size = float(max_frequency), float(element_size)
    key = _key(profile, element_size, max_frequency, int(max_harmonic), material, clamped)
    if use_cache and key in _MEMORY:
        return _MEMORY[key]
    modes = _from_cache(profile, key, material, clamped) if use_cache else None
    if modes is None:
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
    mesh = mesh_outline(profile.outline(), element_size)
    contact = int(np.argmin(np.hypot(*(mesh.nodes - np.asarray(profile.contact_point())).T)))
    model = harmonic_matrices(mesh, material)
    bore = profile.bore_radius if clamped else None
    parts = [harmonic_modes(model, n, max_frequency, bore, contact) for n in range(max_harmonic + 1)]
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


def _saved(modes: WheelModes, key: str, compute_s: float) -> WheelModes:
    from wheelrail.core import cache

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
    from wheelrail.core import cache

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
