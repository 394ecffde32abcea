"""Resonances of the discretely supported track (paper section 2.2): what each one is, from the mode shapes of
the infinite periodic track, and where it is, from the peaks of the finite FE track's point receptances.

A track designer reads three resonances off the rail's receptance (Thompson, *Railway Noise and Vibration*,
Elsevier 2009, sections 3.4-3.6): the sleeper bouncing on the ballast, the rail bouncing on its pads, and the
pinned-pinned resonance (a bending wave twice the sleeper spacing long, its nodes at the sleepers). Which is which,
and where to look for it, is read off the infinite periodic track: one bay centred on its sleeper, its ends tied by
the Bloch-Floquet condition u(x + L) = exp(-i k L) u(x), gives the band edges at k = 0 (every bay in phase: the two
support resonances, each named by the spring holding most of its supports' strain energy, the ballast or the pad)
and at k = pi / L (neighbouring bays in antiphase: the pinned-pinned mode is the lowest whose supports hold almost
none of its strain energy). The frequency reported is a peak of the finite, damped track's point receptance
(above the central sleeper for the support resonances, at its midspan for the pinned-pinned one) that belongs to
that band edge: a local maximum, never the end of a search range, whose nearest band edge is that one, nearness
above an edge counting three times (damping moves a peak below its undamped frequency: a single oscillator's
displacement with damping ratio zeta peaks at sqrt(1 - 2 zeta^2) of its natural frequency, and has no peak above
zeta = 0.71). A resonance the damping smooths out has no peak: it is reported as not resolved, with its band edge.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wheelrail.core.parameters import TrackParameters
from wheelrail.core.track.fe import (
    TrackFEModel,
    pad_couplings,
    shear_parameter_of,
    timoshenko_element_matrices,
    timoshenko_shape_functions,
)

__all__ = [
    "RESONANCE_KINDS",
    "BandEdge",
    "Resonance",
    "band_edges",
    "named_band_edges",
    "receptance_peaks",
    "track_resonances",
]

RESONANCE_KINDS = {
    "sleeper_on_ballast": ("sleeper-on-ballast", "above a sleeper"),
    "rail_on_pad": ("rail-on-pad", "above a sleeper"),
    "pinned_pinned": ("pinned-pinned", "at midspan"),
}
"""Each resonance's key, its name in text and the point receptance its peak is read from."""

PINNED_SUPPORT_SHARE = 0.05  # a k = pi/L mode whose supports hold under 5 % of its strain energy: pinned-pinned
RAIL_MODE_SLEEPER_SHARE = 0.5  # a k = pi/L mode whose sleepers hold under half its kinetic energy moves the rail
DAMPED_SHIFT = 4.0  # a damped peak is looked for down to its band edge / 4 (zeta = 0.70 puts it at 0.14 of it)
ABOVE_EDGE = 1.05  # the search above a sleeper ends 5 % above the upper support resonance's band edge
ABOVE_EDGE_WEIGHT = 3.0  # a peak above a band edge is that far from it (``_owner``)
SUPPORT_GRID_RATIO = 1.01  # steps of the search above a sleeper: 1 % (a support resonance is damped by its pad)
PINNED_GRID_RATIO = 1.002  # steps around the pinned-pinned band edge: 0.2 % (an undamped rail's peak is sharp)
PINNED_SEARCH = (1 / 1.1, 1.05)  # the midspan search range around the pinned-pinned band edge
REFINE_STEPS = 24  # golden-section steps on a peak's grid neighbours: 0.618^24 = 1e-5 of their 2 % interval


@dataclass(frozen=True)
class BandEdge:
    """One natural frequency of the infinite periodic track at a band edge (undamped, one bay, Bloch-Floquet).

    Attributes
    ----------
    frequency_hz : float
        Natural frequency, Hz.
    bays_in_phase : bool
        True: wave number 0 (every bay in phase); False: pi / L (neighbouring bays in antiphase).
    support_share : float
        Fraction of the mode's strain energy held by the pad and the ballast (the rest bends the rail).
    ballast_share : float
        The ballast's fraction of the supports' strain energy (the rest is the pad's).
    sleeper_share : float
        The sleeper's fraction of the mode's kinetic energy (the rest is the rail's).
    """

    frequency_hz: float
    bays_in_phase: bool
    support_share: float
    ballast_share: float
    sleeper_share: float


@dataclass(frozen=True)
class Resonance:
    """One resonance of the track: its kind, its band edge and the receptance peak that belongs to it, if any.

    Attributes
    ----------
    kind : str
        A key of :data:`RESONANCE_KINDS` (``"rail_on_pad"``).
    band_edge_hz : float
        The undamped infinite periodic track's natural frequency of this kind, Hz (:func:`named_band_edges`).
    frequency_hz : float or None
        The peak of the damped finite track's point receptance, Hz; None when the receptance has no peak of this
        kind (:attr:`reason` says why).
    """

    kind: str
    band_edge_hz: float
    frequency_hz: float | None

    @property
    def label(self) -> str:
        """The kind in words ("rail-on-pad")."""
        return RESONANCE_KINDS[self.kind][0]

    @property
    def receptance(self) -> str:
        """Where its peak is read: "above a sleeper" or "at midspan"."""
        return RESONANCE_KINDS[self.kind][1]

    @property
    def reason(self) -> str | None:
        """Why there is no frequency (None when there is one)."""
        if self.frequency_hz is not None:
            return None
        return (
            f"not resolved: the point receptance {self.receptance} has no peak of its own near this resonance of "
            f"the undamped track ({self.band_edge_hz:.0f} Hz); the damping smooths it out"
        )

    def in_words(self) -> str:
        """Its frequency ("941.0 Hz") or why it has none, with its band edge."""
        if self.frequency_hz is not None:
            return f"{self.frequency_hz:.1f} Hz"
        return f"not resolved (no peak {self.receptance}; the undamped track's is at {self.band_edge_hz:.0f} Hz)"

    def as_dict(self) -> dict:
        """The JSON form: ``label``, ``frequency_hz`` (null when not resolved), ``band_edge_hz``, ``receptance``
        and ``reason`` (null when resolved)."""
        return {
            "label": self.label,
            "frequency_hz": self.frequency_hz,
            "band_edge_hz": self.band_edge_hz,
            "receptance": self.receptance,
            "reason": self.reason,
        }


def _bay(track: TrackParameters, elements: int):
    """Stiffness and mass of one bay centred on its sleeper, -L/2 .. L/2 (nodes w, theta; the sleeper last), and
    the pad's blocks (``fe.pad_couplings``). ``elements`` is even: the sleeper sits on the middle node."""
    L = track.support.sleeper_spacing
    h = L / elements
    node_x = -L / 2 + h * np.arange(elements + 1)
    w_dof = 2 * np.arange(elements + 1)
    th_dof = w_dof + 1
    sleeper = 2 * (elements + 1)
    K = np.zeros((sleeper + 1, sleeper + 1))
    M = np.zeros_like(K)
    Ke, Me = timoshenko_element_matrices(track.rail, h)
    for e in range(elements):
        dofs = np.ix_(*(2 * [[w_dof[e], th_dof[e], w_dof[e + 1], th_dof[e + 1]]]))
        K[dofs] += Ke
        M[dofs] += Me
    K_rail = K.copy()
    pads = pad_couplings(track, node_x, w_dof, th_dof, elements // 2)
    for dofs, (P, p, total), _ in pads:
        K[np.ix_(dofs, dofs)] += P
        K[dofs, sleeper] -= p
        K[sleeper, dofs] -= p
        K[sleeper, sleeper] += total
    K[sleeper, sleeper] += track.support.ballast_stiffness
    M[sleeper, sleeper] += track.support.sleeper_mass
    return K, M, K_rail, (w_dof, th_dof, sleeper)


def band_edges(track: TrackParameters, elements_per_bay: int = 16, count: int = 4) -> tuple[BandEdge, ...]:
    """The ``count`` lowest natural frequencies of the infinite periodic track at wave numbers 0 and pi / L.

    One bay centred on its sleeper, ``elements_per_bay`` Rayleigh-Timoshenko elements (rounded up to even) and the
    track's pad (of its width), sleeper and ballast, undamped; its end node tied to its first by the Bloch-Floquet
    condition u(L/2) = +-u(-L/2) (``T``: K_k = T^T K T, M_k = T^T M T, real for k = 0 and pi / L), solved by
    ``scipy.linalg.eigh``.

    Returns
    -------
    tuple of BandEdge
        Sorted by frequency, 2 ``count`` of them.

    Examples
    --------
    >>> from wheelrail.core.parameters import TrackParameters
    >>> from wheelrail.core.track.resonances import named_band_edges
    >>> {kind: round(edge.frequency_hz) for kind, edge in named_band_edges(TrackParameters()).items()}
    {'sleeper_on_ballast': 141, 'rail_on_pad': 328, 'pinned_pinned': 944}
    """
    from scipy.linalg import eigh

    elements = max(2, elements_per_bay + elements_per_bay % 2)
    K, M, K_rail, (w_dof, th_dof, sleeper) = _bay(track, elements)
    kept = np.array([i for i in range(len(K)) if i not in (w_dof[-1], th_dof[-1])])
    edges = []
    for sign in (1.0, -1.0):
        T = np.zeros((len(K), len(kept)))
        T[kept, np.arange(len(kept))] = 1.0
        T[w_dof[-1]], T[th_dof[-1]] = sign * T[w_dof[0]], sign * T[th_dof[0]]
        values, vectors = eigh(T.T @ K @ T, T.T @ M @ T, subset_by_index=(0, count - 1))
        for value, vector in zip(values, vectors.T, strict=True):
            u = T @ vector
            strain, rail = u @ K @ u, u @ K_rail @ u
            ballast = track.support.ballast_stiffness * u[sleeper] ** 2
            support = max(strain - rail, 0.0)
            edges.append(
                BandEdge(
                    frequency_hz=float(np.sqrt(max(value, 0.0)) / (2 * np.pi)),
                    bays_in_phase=sign > 0,
                    support_share=float(support / strain),
                    ballast_share=float(min(ballast / support, 1.0)) if support > 0 else 0.0,
                    sleeper_share=float(track.support.sleeper_mass * u[sleeper] ** 2 / (u @ M @ u)),
                )
            )
    return tuple(sorted(edges, key=lambda edge: edge.frequency_hz))


def named_band_edges(track: TrackParameters, elements_per_bay: int = 16) -> dict[str, BandEdge]:
    """The band edges of the three resonances (:data:`RESONANCE_KINDS`), named by their mode shapes.

    Of the wave number 0 modes, the two whose supports hold the most strain energy are the support resonances:
    the one whose ballast holds the larger share of it is the sleeper on the ballast, the other the rail on its
    pads. The pinned-pinned mode is the lowest wave number pi / L mode whose supports hold under
    ``PINNED_SUPPORT_SHARE`` of its strain energy (the least, if none does: a wide pad).
    """
    edges = band_edges(track, elements_per_bay)
    in_phase = sorted((e for e in edges if e.bays_in_phase), key=lambda e: e.support_share)[-2:]
    sleeper, rail = sorted(in_phase, key=lambda e: e.ballast_share, reverse=True)
    antiphase = [e for e in edges if not e.bays_in_phase]
    free = [e for e in antiphase if e.support_share < PINNED_SUPPORT_SHARE]
    pinned = free[0] if free else min(antiphase, key=lambda e: e.support_share)
    return {"sleeper_on_ballast": sleeper, "rail_on_pad": rail, "pinned_pinned": pinned}


class _PointReceptance:
    """The FE track's point receptance at ``x`` (m) as a function of one frequency (Hz)."""

    def __init__(self, model: TrackFEModel, x: float) -> None:
        self.model, self.load = model, model.load_vector(x)
        element, xi = model.locate(x)
        e = int(element)
        h = float(model.node_x[e + 1] - model.node_x[e])
        self.shape = timoshenko_shape_functions(xi, h, shear_parameter_of(model.params.rail, h))
        self.dofs = [model.w_dof[e], model.theta_dof[e], model.w_dof[e + 1], model.theta_dof[e + 1]]
        self.bands = model.frequency_domain_bands()

    def magnitude(self, frequency: float) -> float:
        u = self.model.solve(*self.bands, frequency, self.load)
        return float(abs(self.shape @ u[self.dofs]))

    def peaks(self, low: float, high: float, ratio: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list]:
        """Grid low .. high (Hz, steps of ``ratio``), the magnitudes on it, and its interior local maxima with
        their prominences (dB)."""
        from scipy.signal import find_peaks

        grid = np.geomspace(low, high, max(3, int(np.ceil(np.log(high / low) / np.log(ratio))) + 1))
        level = 20 * np.log10([self.magnitude(f) for f in grid])
        index, props = find_peaks(level, prominence=0.0)
        return grid, level, index, list(props["prominences"])

    def refine(self, grid: np.ndarray, i: int) -> float:
        """The maximum of the magnitude between grid points i - 1 and i + 1, by golden-section search."""
        a, b = float(grid[i - 1]), float(grid[i + 1])
        g = (np.sqrt(5) - 1) / 2
        c, d = b - g * (b - a), a + g * (b - a)
        fc, fd = self.magnitude(c), self.magnitude(d)
        for _ in range(REFINE_STEPS):
            if fc > fd:
                b, d, fd = d, c, fc
                c = b - g * (b - a)
                fc = self.magnitude(c)
            else:
                a, c, fc = c, d, fd
                d = a + g * (b - a)
                fd = self.magnitude(d)
        return float((a + b) / 2)


def _owner(frequency: float, edges: list[float]) -> float:
    """The band edge a receptance peak at ``frequency`` belongs to: the nearest in lg f, a distance above an edge
    counting ``ABOVE_EDGE_WEIGHT`` times one below it (damping moves a peak below its band edge by up to a factor
    of a few, the finite track and the pads' damping above it by a few per cent)."""

    def distance(edge: float) -> float:
        return np.log(edge / frequency) if edge >= frequency else ABOVE_EDGE_WEIGHT * np.log(frequency / edge)

    return min(edges, key=distance)


def receptance_peaks(model: TrackFEModel) -> dict[str, Resonance]:
    """The track's resonances (module docstring): each kind's band edge and its receptance peak, if it has one.

    Parameters
    ----------
    model : TrackFEModel
        The finite track (``assemble_track``); the receptances are read at its central sleeper and the midspan
        after it.

    Returns
    -------
    dict
        :data:`RESONANCE_KINDS` key -> :class:`Resonance` (``frequency_hz`` None: no peak of its own).

    Examples
    --------
    >>> from wheelrail.core.parameters import TrackParameters
    >>> from wheelrail.core.track import assemble_track, receptance_peaks
    >>> peaks = receptance_peaks(assemble_track(TrackParameters()))
    >>> {kind: round(peak.frequency_hz) for kind, peak in peaks.items()}    # Hz; the paper: pinned-pinned 943
    {'sleeper_on_ballast': 111, 'rail_on_pad': 285, 'pinned_pinned': 941}
    """
    track = model.params
    L = track.support.sleeper_spacing
    x_sleeper = (track.n_bays // 2) * L
    named = named_band_edges(track, max(2, round(L / model.element_length)))
    others = [
        e.frequency_hz
        for e in band_edges(track, max(2, round(L / model.element_length)))
        if not e.bays_in_phase and e.sleeper_share < RAIL_MODE_SLEEPER_SHARE
    ]
    named_edges = [edge.frequency_hz for edge in named.values()]
    edges = sorted({*others, *named_edges})  # above a sleeper; at midspan only the named ones show (see below)
    found: dict[str, float | None] = {}
    above = _PointReceptance(model, x_sleeper)
    support = [named["sleeper_on_ballast"].frequency_hz, named["rail_on_pad"].frequency_hz]
    grid, _, index, prominence = above.peaks(min(support) / DAMPED_SHIFT, max(support) * ABOVE_EDGE, SUPPORT_GRID_RATIO)
    for kind in ("sleeper_on_ballast", "rail_on_pad"):
        edge = named[kind].frequency_hz
        own = [(p, i) for i, p in zip(index, prominence, strict=True) if _owner(grid[i], edges) == edge]
        found[kind] = above.refine(grid, max(own)[1]) if own else None
    midspan = _PointReceptance(model, x_sleeper + L / 2)
    pinned = named["pinned_pinned"].frequency_hz
    grid, level, index, _ = midspan.peaks(pinned * PINNED_SEARCH[0], pinned * PINNED_SEARCH[1], PINNED_GRID_RATIO)
    # the other pi / L modes have their nodes at midspan (antinodes at the sleepers): the midspan shows none of them
    own = [(level[i], i) for i in index if _owner(grid[i], named_edges) == pinned]
    found["pinned_pinned"] = midspan.refine(grid, max(own)[1]) if own else None
    return {kind: Resonance(kind, named[kind].frequency_hz, found[kind]) for kind in RESONANCE_KINDS}


def track_resonances(track: TrackParameters, elements_per_bay: int = 16) -> dict[str, Resonance]:
    """:func:`receptance_peaks` of ``track`` assembled with ``elements_per_bay`` elements per bay."""
    from wheelrail.core.track.fe import assemble_track

    return receptance_peaks(assemble_track(track, elements_per_bay))
