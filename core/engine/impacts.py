"""The impacts of a run: where the force rises well above the preload or the wheel leaves the rail.

:func:`impact_summary` reads a :class:`~wheelrail.core.engine.results.RunResult` (any model, any irregularity):
the peak and the minimum force, the time without contact, and each impact. The rule: a step is *impact-like*
where F > ``peak_ratio`` P (1.2 P by default) or F = 0 (contact lost); impact-like stretches closer than
``join_length`` (0.1 m) along the rail are one impact (a wheel leaving the rail and landing again is one event).
Each impact gives the position and value of its peak force, its minimum force and its time without contact.

The time without contact is measured between the crossings of F = 0, each placed within its step by
extrapolating F^(2/3) (the Hertz law's approach, linear in time near a crossing) from the two steps in contact
next to it, so that it converges with the step rather than in whole steps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wheelrail.core.errors import WheelrailError

__all__ = ["IMPACT_JOIN_LENGTH", "IMPACT_PEAK_RATIO", "Impact", "ImpactSummary", "impact_summary"]

IMPACT_PEAK_RATIO = 1.2  # a step is impact-like above this many preloads (or without contact)
IMPACT_JOIN_LENGTH = 0.1  # m: impact-like stretches closer than this along the rail are one impact


@dataclass(frozen=True)
class Impact:
    """One impact (module docstring): its peak force ``peak`` (N) at ``position`` (m) and ``time`` (s), its
    minimum force ``minimum`` (N), its time without contact (s) and where its stretch starts and ends (m)."""

    position: float
    time: float
    peak: float
    minimum: float
    time_without_contact: float
    start: float
    end: float

    def to_dict(self) -> dict:
        """Plain, JSON-ready view (SI; keys name their unit)."""
        return {
            "position_m": self.position,
            "time_s": self.time,
            "peak_force_n": self.peak,
            "min_force_n": self.minimum,
            "time_without_contact_s": self.time_without_contact,
            "start_m": self.start,
            "end_m": self.end,
        }


@dataclass(frozen=True)
class ImpactSummary:
    """A run's peak force, minimum force (N), time without contact (s) and its impacts, by the rule of
    ``peak_ratio`` and ``join_length`` (m) (module docstring)."""

    peak: float
    minimum: float
    time_without_contact: float
    impacts: tuple[Impact, ...]
    preload: float
    peak_ratio: float = IMPACT_PEAK_RATIO
    join_length: float = IMPACT_JOIN_LENGTH

    @property
    def rule(self) -> str:
        """The rule in words."""
        return (
            f"an impact: the force above {self.peak_ratio:g} P or without contact, stretches closer than "
            f"{self.join_length * 1e3:g} mm joined"
        )

    def to_dict(self) -> dict:
        """Plain, JSON-ready view (SI; keys name their unit)."""
        return {
            "peak_force_n": self.peak,
            "min_force_n": self.minimum,
            "time_without_contact_s": self.time_without_contact,
            "peak_ratio": self.peak_ratio,
            "join_length_m": self.join_length,
            "rule": self.rule,
            "impacts": [impact.to_dict() for impact in self.impacts],
        }

    def lines(self) -> list[str]:
        """What ``wheelrail run`` prints: the summary, then one line per impact."""
        out = [
            f"impacts: peak {self.peak / 1e3:.2f} kN ({self.peak / self.preload:.2f} P), minimum "
            f"{self.minimum / 1e3:.2f} kN, without contact {self.time_without_contact * 1e3:.4f} ms; "
            f"{len(self.impacts)} impact(s) ({self.rule})"
        ]
        for impact in self.impacts:
            out.append(
                f"  at x = {impact.position:.4f} m: peak {impact.peak / 1e3:.2f} kN, minimum "
                f"{impact.minimum / 1e3:.2f} kN, without contact {impact.time_without_contact * 1e3:.4f} ms"
            )
        return out


def _crossing(g: np.ndarray, inside: int, step: int) -> float:
    """Where within the step between ``inside`` (in contact) and ``inside + step`` (not) F^(2/3) = ``g``
    reaches 0, as a fraction of the step from ``inside``, extrapolated from ``inside`` and the step before it."""
    before = inside - step
    if not 0 <= before < g.size or g[before] <= g[inside]:
        return 0.5  # no slope towards the crossing: half a step
    return float(np.clip(g[inside] / (g[before] - g[inside]), 0.0, 1.0))


def _without_contact(force: np.ndarray, first: int, last: int, dt: float) -> float:
    """Time without contact over steps first..last (inclusive) of ``force``, s, the crossings placed within
    their steps (module docstring)."""
    g = np.cbrt(np.maximum(force, 0.0)) ** 2
    lost = force <= 0.0
    total = 0.0
    k = first
    while k <= last:
        if not lost[k]:
            k += 1
            continue
        end = k
        while end + 1 <= last and lost[end + 1]:
            end += 1
        begin = k - 1 + _crossing(g, k - 1, 1) if k > 0 else float(k)  # the crossings, in steps
        finish = end + 1 - _crossing(g, end + 1, -1) if end + 1 < force.size else float(end)
        total += (finish - begin) * dt
        k = end + 1
    return total


def impact_summary(
    result, *, peak_ratio: float = IMPACT_PEAK_RATIO, join_length: float = IMPACT_JOIN_LENGTH
) -> ImpactSummary:
    """The impacts of a run (module docstring: the rule).

    Parameters
    ----------
    result : RunResult
        A run (any model).
    peak_ratio : float
        A step is impact-like where F exceeds this many preloads (or F = 0); default 1.2.
    join_length : float
        Impact-like stretches closer than this along the rail are one impact, m; default 0.1.

    Returns
    -------
    ImpactSummary
        Peak and minimum force, the time without contact (crossings placed within their steps) and the impacts.

    Raises
    ------
    WheelrailError
        For a run without steps, or a ratio or length that is not positive.

    Examples
    --------
    >>> from wheelrail.core.engine import impact_summary, simulate
    >>> summary = impact_summary(simulate("corrugated-rail", model="hertz", length=0.5))
    >>> len(summary.impacts), summary.time_without_contact        # the corrugation stays below 1.2 P
    (0, 0.0)
    """
    if not (np.isfinite(peak_ratio) and peak_ratio > 0 and np.isfinite(join_length) and join_length > 0):
        raise WheelrailError(f"impact_summary: peak_ratio and join_length must be positive, got {peak_ratio}, "
                             f"{join_length}")  # fmt: skip
    force = np.asarray(result.force, dtype=float)
    if force.size == 0:
        raise WheelrailError("impact_summary: the run has no steps")
    preload, dt, x, time = result.header.params.contact.preload, result.time_step, result.x, result.time
    marked = np.flatnonzero((force > peak_ratio * preload) | (force <= 0.0))
    impacts = []
    if marked.size:
        gap = int(np.ceil(join_length / result.element_size - 1e-9))
        breaks = np.flatnonzero(np.diff(marked) > gap)
        for first, last in zip(np.r_[marked[0], marked[breaks + 1]], np.r_[marked[breaks], marked[-1]], strict=True):
            stretch = force[first : last + 1]
            top = first + int(np.argmax(stretch))
            impacts.append(
                Impact(
                    position=float(x[top]),
                    time=float(time[top]),
                    peak=float(force[top]),
                    minimum=float(stretch.min()),
                    time_without_contact=_without_contact(force, first, last, dt) if stretch.min() <= 0 else 0.0,
                    start=float(x[first]),
                    end=float(x[last]),
                )
            )
    lost = _without_contact(force, 0, force.size - 1, dt) if np.any(force <= 0.0) else 0.0
    return ImpactSummary(
        peak=float(force.max()),
        minimum=float(force.min()),
        time_without_contact=lost,
        impacts=tuple(impacts),
        preload=float(preload),
        peak_ratio=float(peak_ratio),
        join_length=float(join_length),
    )
