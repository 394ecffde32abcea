"""The rail's lateral vibration and its radiation in the noise chain: the ``rail_lateral`` component.

The contact carries no lateral force (the interaction is vertical), but a vertical force F that acts a distance d
off the rail's centreline (``contact_offset_rail``, :mod:`wheelrail.core.inputs.contact_position`) is also a
torque F d about the rail's axis: it twists the rail, and the twist moves the railhead sideways. Per unit
mean-square contact force, at each frequency of the chain's band sampling and each excitation position (above a
sleeper, midspan: the vertical chain's):

1. the railhead's lateral velocity at the contact, v_0 = i w alpha_vl F, with alpha_vl the lateral track's
   ``vertical_to_lateral`` receptance (:func:`wheelrail.core.track.lateral.lateral_receptances`: lateral bending
   and torsion of the rail on the pads' lateral and rotational stiffness, the load at that position of the bay);
   alpha_vl is proportional to d, so the component's power to d^2 (+6 dB per doubling; none at d = 0): the
   lateral track is solved once per track, at ``LATERAL_CROSS_OFFSET``, and scaled to d;
2. its decay along the rail, the lateral track decay rate Delta (dB/m, EN 15461's formula on the railhead's
   lateral transfer receptances, :func:`wheelrail.core.track.lateral.lateral_decay_rate`, per band): a field
   |v(x)|^2 = |v_0|^2 10^(-Delta |x| / 10) either side of the contact, whose integral along the rail is
   |v_0|^2 2 (10 lg e) / Delta (TWINS's rail: Thompson, *Railway Noise and Vibration*, 2009, section 6.5 and
   eq. 6.21, the rail's sound power from its velocity at the contact and its decay rate);
3. its radiation, the rail's section moving rigidly side to side in free field (the railhead's velocity taken as
   the whole section's): W = rho c P <n_x^2> sigma_lat(f) |v_0|^2 2 (10 lg e) / Delta, with P the section's
   perimeter, <n_x^2> the mean square of its normals' lateral component and sigma_lat the 2D boundary-element
   radiation efficiency of the 60E1 section in lateral motion
   (:func:`wheelrail.core.noise.radiation.lateral_rail_radiation_efficiency`; the same BEM as the vertical rail's,
   Thompson 2009, section 6.5).

The plain 2D estimate of step 3 applies the section's ratio to the whole field (the vertical rail's chain radiates
its field in the wavenumber domain, which takes 1.5-4 dB off at 50-100 Hz where the field decays within an acoustic
wavelength; the lateral field decays faster, so this estimate is an upper bound there). Left out: the lateral
(creep) force of the contact, which drives the rail laterally directly and which TWINS includes; the rail's
cross-section deformation above about 1.5 kHz (web bending, foot flapping: the lateral track is a beam with a rigid
section); the section's rotation (the head's velocity is taken for the whole section, an overestimate where the
foot moves less); the ground's reflection.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from wheelrail.core.noise.radiation import AIR_DENSITY, SOUND_SPEED, lateral_rail_radiation_efficiency, rail_section

__all__ = [
    "LATERAL_CROSS_OFFSET",
    "LOG10_E",
    "clear_lateral_cache",
    "lateral_power_per_force",
    "lateral_rail_power",
    "lateral_velocity_integral",
]

LOG10_E = 10.0 * math.log10(math.e)  # 4.343 dB per neper of energy decay
LATERAL_CROSS_OFFSET = 0.01
"""m: the contact offset at which the lateral track's vertical-to-lateral receptance is computed and stated (the
chain's, scaled to the contact's offset, and ``noise.decay.lateral_band_receptances``'): it is proportional to it."""


def lateral_velocity_integral(frequency, vertical_to_lateral, decay_rate_db_per_m) -> np.ndarray:
    """int |v(x)|^2 dx along the rail per unit mean-square contact force, (m/s)^2 m / N^2 (step 2 of the module
    docstring): |w alpha_vl|^2 2 (10 lg e) / Delta, elementwise (broadcast)."""
    w = 2 * np.pi * np.asarray(frequency, dtype=float)
    return np.abs(w * np.asarray(vertical_to_lateral)) ** 2 * 2 * LOG10_E / np.asarray(decay_rate_db_per_m, float)


def lateral_power_per_force(frequency, vertical_to_lateral, decay_rate_db_per_m) -> np.ndarray:
    """The rail's lateral sound power per unit mean-square vertical contact force, W/N^2 (module docstring):
    rho c P <n_x^2> sigma_lat(f) |w alpha_vl|^2 2 (10 lg e) / Delta, elementwise.

    Parameters
    ----------
    frequency : array_like
        Hz, > 0.
    vertical_to_lateral : array_like
        alpha_vl, the railhead's lateral displacement per unit vertical force at the contact, m/N (complex).
    decay_rate_db_per_m : array_like
        The lateral decay rate at each frequency's band, dB/m, > 0.

    Returns
    -------
    numpy.ndarray
        W/N^2, the broadcast shape.

    Examples
    --------
    A cross receptance of 1e-11 m/N at 1 kHz decaying at 1 dB/m, then twice the receptance (a contact twice as far
    off the centreline) and twice the decay rate:

    >>> import numpy as np
    >>> from wheelrail.core.noise.rail_lateral import lateral_power_per_force
    >>> w = lateral_power_per_force(1000.0, [1e-11, 2e-11, 1e-11], [1.0, 1.0, 2.0])   # W/N^2
    >>> np.round(10 * np.log10(w / w[0]), 2)   # dB: the receptance squared, the decay's inverse
    array([ 0.  ,  6.02, -3.01])
    """
    f = np.asarray(frequency, dtype=float)
    section = rail_section()
    rho_c_p = AIR_DENSITY * SOUND_SPEED * section["perimeter_m"] * section["mean_normal_x_squared"]
    sigma = lateral_rail_radiation_efficiency(f.ravel()).reshape(f.shape)
    return rho_c_p * sigma * lateral_velocity_integral(f, vertical_to_lateral, decay_rate_db_per_m)


def lateral_rail_power(chain) -> np.ndarray:
    """The ``rail_lateral`` component's sound power per unit mean-square contact force at the chain's frequencies
    and both excitation positions, (bands, points, 2) W/N^2 (module docstring); zeros for a contact on the rail's
    centreline (no torque: no lateral vibration, nothing computed).

    Parameters
    ----------
    chain : NoiseChain
        ``params.track``, ``numerics`` (the lateral track takes the chain's bays, elements per bay, points per band
        and decay length, and its own absorbing ends: ``LateralNumerics.absorbing_bays``, at most a quarter of the
        bays), ``frequencies`` (bands, points) and ``contact_position``.
    """
    from wheelrail.core.inputs.contact_position import ContactPosition

    f = np.asarray(chain.frequencies, dtype=float)
    position = chain.contact_position or ContactPosition()
    if position.rail_offset == 0.0:
        return np.zeros((*f.shape, 2))
    from wheelrail.core.track.lateral import LateralNumerics

    numerics = chain.numerics
    lateral = LateralNumerics(
        track_bays=numerics.track_bays,
        # its absorbing ends (20 bays each on the default 240), fewer on a short test track: a quarter of it at most
        absorbing_bays=min(LateralNumerics().absorbing_bays, (numerics.track_bays - 4) // 4),
        elements_per_bay=numerics.elements_per_bay,
        points_per_band=numerics.points_per_band,
        decay_length=numerics.decay_length,
    )
    decay, receptance = _lateral_track(chain.params.track, lateral, f.shape, f.tobytes())
    scale = position.rail_offset / LATERAL_CROSS_OFFSET  # alpha_vl is proportional to the offset (step 1)
    return lateral_power_per_force(f[..., None], receptance * scale, decay[:, None, None])


@functools.lru_cache(maxsize=4)
def _lateral_track(track, lateral, shape: tuple, frequencies: bytes) -> tuple[np.ndarray, np.ndarray]:
    """The lateral track's decay rate per band (bands,) and its vertical-to-lateral receptance for a contact
    ``LATERAL_CROSS_OFFSET`` off the centreline at the chain's frequencies (bytes of a float array of ``shape``:
    (bands, points)) and both excitation positions, (bands, points, 2) m/N: what the lateral rail needs of the
    track, kept per process, so that another offset on the railhead only scales it."""
    from wheelrail.core.track.lateral import lateral_decay_rate, lateral_receptances

    f = np.frombuffer(frequencies).reshape(shape)
    decay = lateral_decay_rate(track, _band_centres(f), numerics=lateral)
    receptance = np.stack(
        [
            lateral_receptances(
                track, f.ravel(), contact_offset=LATERAL_CROSS_OFFSET, excitation=where, numerics=lateral
            ).vertical_to_lateral.reshape(f.shape)
            for where in (0.0, 0.5)  # above a sleeper, midspan: the vertical chain's excitation positions
        ],
        axis=-1,
    )
    return decay, receptance


def clear_lateral_cache() -> None:
    """Empty the lateral track's entries this process keeps (:func:`lateral_rail_power`)."""
    _lateral_track.cache_clear()


def _band_centres(frequencies: np.ndarray) -> np.ndarray:
    """The exact centre of each band (row) of the chain's (bands, points) sampling: the geometric mean of a row."""
    return np.exp(np.mean(np.log(frequencies), axis=1))
