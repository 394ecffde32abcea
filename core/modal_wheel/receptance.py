"""The modal wheel's receptances at the contact and the mean-square velocity of its surfaces (for its radiation).

Receptance by modal summation. A force F at the contact (theta = 0) excites, in every harmonic n, the modes
of the symmetric set (``fem``), each with a full weight cos(0) = 1; the displacement at the contact, in
direction a, per unit force in direction b (a, b: radial r, axial z) is::

    alpha_ab(omega) = sum_modes phi_a phi_b / (omega_m^2 (1 + i eta_m) - omega^2)

with mass-normalised shapes phi, loss factors eta_m (``modes.modal_loss_factor``), convention
x = Re(X e^{i omega t}), over every mode computed (up to ``modes.max_frequency``, harmonics 0..N).

What the receptance leaves out: the contact zone's local flexibility. Under a point force the elastic field near the
load is Boussinesq's, displacement ~ 1 / distance, without bound at the load point; each harmonic n is a ring load
cos(n theta) concentrated at one point of the cross-section, whose field there is a line load's, ~ log(1 /
distance). A finite-element solve puts the load on a node, so its static flexibility there, G_n, holds that singular
part, cut off at the element size h: it grows as log(1 / h) in every harmonic alike and its sum over n grows with
the number of harmonics (it builds the 1 / distance of a point load). The residual of each harmonic, R_n = G_n -
sum_{modes of n} phi_a phi_b / omega_m^2 (the static flexibility its computed modes leave out, the usual "static
correction"), is this local part: for the 920 mm wheel (12 mm elements, modes to 12.5 kHz) it is 7.3-7.5e-12 m/N in
every harmonic n = 1..11 and 7.2-8.0e-12 m/N up to n = 20 (half of it at n = 0, whose ring load has half the
amplitude), 8.8-9.1e-12 m/N with 6 mm elements and 6.1e-12 m/N with modes to 25 kHz: it does not fall with n, as the
wheel's global (web and rim bending) flexibility does, steeply, and it moves with the mesh, as a global flexibility
does not; the modes' share of each G_n is the same within 0.3 % at 12 and 6 mm. That local deformation is the
contact's: the Hertz spring (or the Winkler and half-space contact models) holds it, the wheel and rail being taken
as elastic half-spaces near the contact (Pieringer, Kropp & Thompson 2011, section 2.3.2). Adding it to the wheel's
receptance counts it twice, and it made the receptance depend on the mesh and on the number of harmonics (radial, at
100 Hz: +4 % from 12 to 3 mm; +6 % and +16 % with 20 and 40 harmonics against 10). TWINS's wheel separates them the
same way (Thompson, *Wheel-rail noise generation, part II: wheel vibration*, J. Sound Vib. 161 (1993) 401-419, and
*Railway Noise and Vibration*, Elsevier 2009, ch. 5): the wheel's receptance at the contact is a sum over its
finite-element modes, and the contact zone's local flexibility is the contact spring's, in series with the wheel's
and the rail's receptances.

The options weighed: (1) subtract a half-space (Boussinesq/Cerruti) field from each harmonic's static residual or
evaluate the residual at a distance from the load: the subtraction needs the field at the contact node, which the
mesh does not resolve (a log singularity cut off at h), and at a distance d the sum over harmonics needs n up to
about 3 R / d (80 for d = 20 mm on a 460 mm wheel), beyond the modes' harmonics; (2) a load spread over the Hertz
patch: the patch (about 11 mm) is smaller than the elements and, around the circumference, it smooths only harmonics
n > R / a (about 80), so the sum still grows with n up to there; (3) truncate the residual consistently: keep every
mode up to the maximum frequency in every harmonic that has one, and no static residual at the contact. (3) is
chosen: the residual measured above is the local part (it is the same in every harmonic), the modal sum converges
with the harmonics and with the mesh, and the global flexibility of the modes above the maximum frequency is small
(the modal sum to 25 kHz is within 0.1-0.6 dB of the one to 12.5 kHz below 1 kHz, away from antiresonances). Per
third-octave band, 50 Hz-10 kHz (``validation/wheel_receptance.py``, :func:`band_mean_square`): doubling the
harmonics changes nothing (0.00 dB) once every harmonic with a mode below the maximum frequency is in (n <= 16 at
12.5 kHz for the 920 mm wheel: ``max_harmonic`` 20); halving the elements (12 to 6 mm) moves the radial, axial and
cross bands by <= 0.3 dB (920 mm wheel) and <= 0.4 dB (the 840 mm wheel at R = 390 mm) except in a band that holds
only the tail of a mode just beyond its edge, where the mode's frequency moving by 0.5-0.7 % (the mesh's frequency
convergence) moves the tail: 920 mm, 160 Hz band, -0.6 to -0.7 dB (n = 1 at 134.7 Hz); 840 mm, 200 Hz band, -1.5 to
-1.7 dB (n = 1 at 174.1 Hz) and 315 Hz, +1.0 to +3.8 dB (n = 0 at 357.5 Hz, 355.6 Hz at 6 mm, the band's edge 355.0
Hz). :func:`static_residual` still gives the left-out part, for a comparison with a direct solve (which holds it).

Why the radial and axial motions couple: the contact lies on the tread at the running circle, at an axial
distance ``contact_offset`` from the web's midplane (and the web itself is dished). A radial force there does
not act in the web's plane: about the web's junction with the rim it is also a moment, F_r times the offset,
that bends the web out of its plane and moves the rim axially; and the dished web turns radial load into
bending too. So the axial modes (web bending) appear in the radial receptance and the cross receptance
alpha_rz = alpha_zr (reciprocity) is not zero; for a flat web with the contact on its midplane it vanishes for
every mode whose shape is symmetric about the midplane. TWINS's wheel (Thompson 1993, part II) is built the
same way.

The contact off the nominal rolling circle (``tread_offset``, :func:`tread_shapes`): the contact moved axially along
the tread by y. A radial force there drives each mode through the mode's radial displacement at that point, not at
the rolling circle: for a rim whose cross-section turns by theta in a mode (an axial, web-bending mode), the radial
displacement at y is about phi_r(0) + theta y, so the axial modes, which a radial force on the web's midplane hardly
excites, are driven in proportion to y (Thompson 1993, part II: TWINS drives the wheel at the contact point's own
position, the lateral offset of the contact coupling the radial force to the axial modes). The shapes at the point
are the mesh's own: its quadratic boundary edge on the tread that holds the point, interpolated with the edge's shape
functions (exact at the nodes: at y = 0 the contact node's). The static correction of the surface velocity keeps the
rolling circle's field (the mesh holds no static field for a force elsewhere): it matters only for the harmonics
driven far below their first mode, where the rail and sleepers dominate.

Surfaces for radiation (:func:`mean_square_velocity`): the outline's edges facing axially (|n_z| >= |n_r|:
both faces of the web, the rim's and the hub's sides) and the outward-facing radial ones in the outer half of
the wheel (the tread and the flange's top, n_r > |n_z|); the bore (on the axle) and the inward-facing cylinders
(under the rim) are left out, as in Thompson's wheel radiation model (radial motion radiates from the tyre's
outer surface, axial motion from the wheel's sides). Their normal velocity is averaged over the surface of
revolution (a factor 1/2 for n > 0: the mean of cos^2 around the circumference). Each harmonic's static
correction (its static field less its modes' static share) moves with the force and is included: averaged over
the surfaces, the local field's singularity is integrable (its share converges with the mesh), unlike at the
contact point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError

__all__ = [
    "SurfaceVelocity",
    "WheelReceptance",
    "band_mean_square",
    "contact_receptance",
    "mean_square_velocity",
    "static_residual",
    "surfaces",
    "tread_point",
    "tread_shapes",
]


@dataclass(frozen=True)
class WheelReceptance:
    """Receptances at the contact: ``frequency`` (nf,) Hz; ``radial``, ``axial``, ``cross`` (nf,) complex, m/N
    (displacement per force at the contact; radial positive away from the axle, axial towards the field side)."""

    frequency: np.ndarray
    radial: np.ndarray
    axial: np.ndarray
    cross: np.ndarray


@dataclass(frozen=True)
class SurfaceVelocity:
    """The wheel's surface velocity per harmonic (module docstring).

    Attributes
    ----------
    frequency : ndarray (nf,)
        Hz.
    harmonic : ndarray (N + 1,)
        n = 0..N.
    axial, radial : ndarray (nf, N + 1)
        Spatial and time mean-square normal velocity over the axially facing surfaces and over the radially
        facing (tread) surface, per harmonic, m^2/s^2 (for RMS forces; they add up over n).
    area_axial, area_radial : float
        The surfaces' areas, m^2 (both sides of the wheel counted).
    """

    frequency: np.ndarray
    harmonic: np.ndarray
    axial: np.ndarray
    radial: np.ndarray
    area_axial: float
    area_radial: float


def _frequencies(frequencies) -> np.ndarray:
    f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise WheelrailError("the wheel's frequencies must be finite and >= 0 Hz", Blame("frequency"))
    return f


def tread_point(modes, tread_offset: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Where the contact ``tread_offset`` m along the tread from the rolling circle lies on the mesh: the three
    nodes of the boundary edge that holds it and their quadratic shape functions there (module docstring).

    Parameters
    ----------
    modes : WheelModes
    tread_offset : float
        Axial offset from the profile's contact point, m (+ towards the field side): ``contact_offset_wheel``'s
        range, and on the tread (for a parametric wheel: at least 5 mm from its edges and the flange).

    Returns
    -------
    (nodes, weights) : ndarrays (3,)
        Node indices and their shape functions at the point (at 0: the contact node, weight 1).

    Raises
    ------
    WheelrailError
        An offset outside its range or off the tread, in one line.
    """
    from wheelrail.core.inputs.ranges import ACCEPTED

    offset = ACCEPTED["contact_offset_wheel"].check(tread_offset, "tread_offset")
    if offset == 0.0:
        return np.array([modes.contact_node] * 3), np.array([1.0, 0.0, 0.0])
    r0, z0 = modes.profile.contact_point()
    z = z0 + offset
    _check_on_tread(modes.profile, offset)
    nodes, edges = modes.mesh.nodes, modes.mesh.boundary
    za, zb = nodes[edges[:, 0], 1], nodes[edges[:, 2], 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = 2 * (z - za) / (zb - za) - 1
    inside = (zb != za) & (np.abs(s) <= 1 + 1e-9)
    s = np.clip(np.where(inside, s, 0.0), -1, 1)
    shape = np.stack([s * (s - 1) / 2, 1 - s**2, s * (s + 1) / 2], axis=1)  # (edges, 3)
    r = np.einsum("ek,ek->e", shape, nodes[edges, 0])
    outward = zb > za  # counter-clockwise in (r, z), the inside on the left: an outer face runs towards +z
    found = np.flatnonzero(inside & outward & (np.abs(r - r0) <= _TREAD_TOLERANCE))
    if not len(found):
        raise WheelrailError(
            "the contact moved so far is off the wheel's tread (no outer face within "
            f"{_TREAD_TOLERANCE * 1e3:g} mm of the rolling circle's radius there)",
            Blame("contact_offset_wheel", offset, "m"),
        )
    edge = found[np.argmin(np.abs(r[found] - r0))]
    return edges[edge], shape[edge]


_TREAD_TOLERANCE = 0.01  # m: a tread point's radius within this of the rolling circle's (a worn or conical tread)
_TREAD_MARGIN = 0.005  # m: the contact at least this far from the tread's edges and the flange (WheelProfile's rule)


def _check_on_tread(profile, offset: float) -> None:
    """A parametric wheel's contact moved by ``offset`` stays on its tread, :data:`_TREAD_MARGIN` from its edges
    and the flange (the rule of ``WheelProfile.contact_offset``), else one WheelrailError with the range."""
    from wheelrail.core.modal_wheel.profile import WheelProfile

    if not isinstance(profile, WheelProfile):
        return
    half = profile.tyre_width / 2
    low = -half + (profile.flange_thickness if profile.flange_thickness > 0 else 0.0) + _TREAD_MARGIN
    high = half - _TREAD_MARGIN
    if not low <= profile.contact_offset + offset <= high:
        raise WheelrailError(
            None,
            Blame(
                "contact_offset_wheel",
                offset,
                "m",
                minimum=low - profile.contact_offset,
                maximum=high - profile.contact_offset,
                reason="the contact on this wheel's tread, at least 5 mm from its edges and the flange",
            ),
        )


def tread_shapes(modes, tread_offset: float = 0.0) -> np.ndarray:
    """(n_modes, 2): each mode's radial and axial displacement (kg^-1/2) at the contact ``tread_offset`` m along
    the tread from the rolling circle (:func:`tread_point`; at 0, ``modes.contact_shapes()``)."""
    if tread_offset == 0.0:
        return modes.contact_shapes()
    nodes, weights = tread_point(modes, tread_offset)
    radial = modes.shapes[:, 3 * nodes] @ weights
    axial = modes.shapes[:, 3 * nodes + 1] @ weights
    return np.stack([radial, axial], axis=1)


def _modal_denominator(modes, f: np.ndarray, added_loss_factor: float) -> np.ndarray:
    """(nf, n_modes): omega_m^2 (1 + i eta_m) - omega^2, rad^2/s^2."""
    wm2 = (2 * np.pi * modes.frequency) ** 2 * (1 + 1j * modes.loss_factor(added_loss_factor))
    denominator = wm2[None, :] - (2 * np.pi * f[:, None]) ** 2
    if np.any(denominator == 0):  # a free wheel's rigid-body modes at 0 Hz
        raise WheelrailError("a free wheel moves without bound at 0 Hz; give frequencies above 0")
    return denominator


def static_residual(modes) -> np.ndarray:
    """(2, 2): the static flexibility at the contact node that the computed modes leave out, summed over the
    harmonics, m/N: the contact zone's local flexibility under a point load on the mesh (module docstring), which
    :func:`contact_receptance` leaves to the contact model. A direct solve at the node holds it."""
    total = np.zeros((2, 2))
    shapes = modes.contact_shapes()
    for n in range(modes.max_harmonic + 1):
        static = modes.static[n]
        if not np.any(static):
            continue  # a free hub's n = 0, 1: no static flexibility
        mine = (modes.harmonic == n) & (modes.frequency > 1.0)
        phi = shapes[mine]
        total += static - np.einsum("ma,mb,m->ab", phi, phi, 1 / (2 * np.pi * modes.frequency[mine]) ** 2)
    return total


def contact_receptance(
    modes, frequencies, added_loss_factor: float = 0.0, *, tread_offset: float = 0.0
) -> WheelReceptance:
    """The radial, axial and cross receptances at the contact, without the contact zone's local flexibility
    (module docstring).

    Parameters
    ----------
    modes : WheelModes
        From ``wheel_modes``.
    frequencies : array_like
        Hz, >= 0.
    added_loss_factor : float
        A damper's loss factor added to every mode's.
    tread_offset : float
        The contact's axial position on the tread from the rolling circle, m (:func:`tread_shapes`; default 0).

    Returns
    -------
    WheelReceptance
        ``radial``, ``axial`` and ``cross`` (complex, m/N) at each frequency: the sum over every mode computed.

    Raises
    ------
    WheelrailError
        An input outside its accepted range (the frequencies, the added loss factor), in one line.
    """
    f = _frequencies(frequencies)
    phi = tread_shapes(modes, tread_offset)
    denominator = _modal_denominator(modes, f, added_loss_factor)
    terms = np.einsum("ma,mb->mab", phi, phi)
    alpha = np.einsum("fm,mab->fab", 1 / denominator, terms)
    return WheelReceptance(frequency=f, radial=alpha[:, 0, 0], axial=alpha[:, 1, 1], cross=alpha[:, 0, 1])


def band_mean_square(modes, lower, upper, added_loss_factor: float = 0.0, points: int = 200) -> WheelReceptance:
    """Band means of |alpha|^2 at the contact (:func:`contact_receptance`), each mode's resonance resolved.

    A lightly damped mode's peak is eta f wide (1e-4 f for n >= 2), narrower than any fixed sampling of a band; the
    mean is the integral of |alpha|^2 over the band (trapezoids) on ``points`` frequencies spread evenly in lg f
    and, around each mode in or near the band, 141 more from 1 100 half-widths below to 1 100 above its frequency
    (spaced as sinh, densest at the peak), divided by the band's width.

    Parameters
    ----------
    modes : WheelModes
    lower, upper : array_like (nb,)
        The bands' edges, Hz, 0 < lower < upper.
    added_loss_factor : float
        A damper's loss factor added to every mode's.
    points : int
        Frequencies per band besides those around the modes.

    Returns
    -------
    WheelReceptance
        ``frequency``: the bands' geometric centres, Hz; ``radial``, ``axial``, ``cross``: the band means of
        |alpha|^2, m^2/N^2 (real).
    """
    lower, upper = np.atleast_1d(np.asarray(lower, dtype=float)), np.atleast_1d(np.asarray(upper, dtype=float))
    if lower.shape != upper.shape or not np.all(np.isfinite(upper)) or not np.all((lower > 0) & (upper > lower)):
        raise WheelrailError("the bands' edges must be finite with 0 < lower < upper (Hz)", Blame("frequency"))
    eta = modes.loss_factor(added_loss_factor)
    around = np.sinh(np.linspace(-7.7, 7.7, 141))  # half-widths from the peak: +-1 100
    out = np.zeros((len(lower), 3))
    for b, (lo, hi) in enumerate(zip(lower, upper, strict=True)):
        near = (modes.frequency > 0.9 * lo) & (modes.frequency < 1.1 * hi)
        grid = [np.geomspace(lo, hi, points), *(fm * (1 + 0.5 * e * around) for fm, e in
                zip(modes.frequency[near], eta[near], strict=True))]  # fmt: skip
        f = np.unique(np.clip(np.concatenate(grid), lo, hi))
        alpha = contact_receptance(modes, f, added_loss_factor)
        for k, name in enumerate(("radial", "axial", "cross")):
            out[b, k] = np.trapezoid(np.abs(getattr(alpha, name)) ** 2, f) / (hi - lo)
    return WheelReceptance(np.sqrt(lower * upper), out[:, 0], out[:, 1], out[:, 2])


def surfaces(modes) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The radiating surfaces' Gauss points (module docstring): for "axial" and "radial", (element indices into the
    boundary's edges per Gauss point, normal (n_r, n_z) per Gauss point, the area weight 2 pi r ds per Gauss point,
    m^2), with the shape functions applied by :func:`_normal_displacements`."""
    nodes, edges = modes.mesh.nodes, modes.mesh.boundary
    s, w = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]), np.array([5.0, 8.0, 5.0]) / 9.0
    shape = np.stack([s * (s - 1) / 2, 1 - s**2, s * (s + 1) / 2], axis=1)  # (3 points, 3 edge nodes)
    d_shape = np.stack([s - 0.5, -2 * s, s + 0.5], axis=1)
    x = nodes[edges]  # (E, 3, 2)
    position = np.einsum("gk,ekc->egc", shape, x)
    tangent = np.einsum("gk,ekc->egc", d_shape, x)
    length = np.hypot(tangent[..., 0], tangent[..., 1])
    normal = np.stack([tangent[..., 1], -tangent[..., 0]], axis=-1) / length[..., None]
    area = 2 * np.pi * position[..., 0] * length * w[None, :]
    r_mid = 0.5 * (nodes[:, 0].min() + modes.profile.wheel_radius)
    edge_normal = normal.mean(axis=1)
    axial = np.abs(edge_normal[:, 1]) >= np.abs(edge_normal[:, 0])
    radial = ~axial & (edge_normal[:, 0] > 0) & (position[:, 1, 0] > r_mid)
    found = {}
    for name, chosen in (("axial", axial), ("radial", radial)):
        found[name] = (np.flatnonzero(chosen), normal[chosen], area[chosen], shape)
    return found


def _normal_displacements(modes, shapes, chosen, normal, shape) -> np.ndarray:
    """(n_shapes, n_edges * 3): each shape's normal displacement at the chosen edges' Gauss points."""
    edges = modes.mesh.boundary[chosen]  # (E, 3)
    at_r = np.einsum("gk,mek->meg", shape, shapes[:, 3 * edges])
    at_z = np.einsum("gk,mek->meg", shape, shapes[:, 3 * edges + 1])
    return (at_r * normal[None, ..., 0] + at_z * normal[None, ..., 1]).reshape(len(shapes), -1)


def _residual_fields(modes, harmonic: int) -> np.ndarray:
    """(2, 3 n_nodes): harmonic n's static displacement per unit radial and axial contact force that its modes
    leave out (the field of the receptance's static correction), m/N."""
    mine = (modes.harmonic == harmonic) & (modes.frequency > 1.0)
    if not np.any(modes.static_fields[harmonic]):
        return np.zeros_like(modes.static_fields[harmonic])
    weights = modes.contact_shapes()[mine] / ((2 * np.pi * modes.frequency[mine]) ** 2)[:, None]  # (m, 2)
    return modes.static_fields[harmonic] - weights.T @ modes.shapes[mine]


def mean_square_velocity(
    modes,
    frequencies,
    force_radial=1.0,
    force_axial=0.0,
    added_loss_factor: float = 0.0,
    residual: bool = True,
    *,
    tread_offset: float = 0.0,
) -> SurfaceVelocity:
    """Mean-square normal velocity of the wheel's axially and radially facing surfaces, per harmonic.

    Parameters
    ----------
    modes : WheelModes
    frequencies : array_like
        Hz, >= 0.
    force_radial, force_axial : complex or array_like (nf,)
        RMS forces at the contact, N (radial: away from the axle; axial: towards the field side).
    added_loss_factor : float
        A damper's loss factor added to every mode's.
    residual : bool
        Add each harmonic's static correction (the field of the modes above ``modes.max_frequency``, moving with
        the force): it matters for the harmonics driven far below their first mode.
    tread_offset : float
        The contact's axial position on the tread from the rolling circle, m (:func:`tread_shapes`; default 0; the
        static correction stays the rolling circle's, module docstring).

    Returns
    -------
    SurfaceVelocity
        <v_n^2> per harmonic and direction (module docstring).

    Raises
    ------
    WheelrailError
        An input outside its accepted range (the frequencies, the forces, the added loss factor), in one line.
    """
    f = _frequencies(frequencies)
    force = np.stack(np.broadcast_arrays(np.asarray(force_radial, dtype=complex), np.asarray(force_axial,
                     dtype=complex), f), axis=-1)[..., :2]  # fmt: skip
    if not np.all(np.isfinite(force)):
        raise WheelrailError("the forces on the wheel must be finite", Blame("force"))
    modal_force = force @ tread_shapes(modes, tread_offset).T  # (nf, n_modes)
    velocity = 1j * 2 * np.pi * f[:, None] * modal_force / _modal_denominator(modes, f, added_loss_factor)
    harmonics = np.arange(modes.max_harmonic + 1)
    out, areas = {}, {}
    for name, (chosen, normal, area, shape) in surfaces(modes).items():
        areas[name] = float(area.sum())
        weight = area.reshape(-1) / max(areas[name], 1e-300)
        u = _normal_displacements(modes, modes.shapes, chosen, normal, shape)  # (n_modes, n_points)
        result = np.zeros((len(f), len(harmonics)))
        for n in harmonics:
            mine = modes.harmonic == n
            field = velocity[:, mine] @ u[mine]  # (nf, n_points)
            if residual:
                static = _normal_displacements(modes, _residual_fields(modes, n), chosen, normal, shape)  # (2, points)
                field = field + 1j * 2 * np.pi * f[:, None] * (force @ static)
            result[:, n] = (np.abs(field) ** 2 @ weight) * (1.0 if n == 0 else 0.5)
        out[name] = result
    return SurfaceVelocity(f, harmonics, out["axial"], out["radial"], areas["axial"], areas["radial"])
