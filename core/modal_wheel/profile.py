"""The wheel's cross-section: a parametric profile, named standard-like wheels, an outline read from a CSV file.

Coordinates of a cross-section: r, the distance from the axle's axis, and z, along the axle (m), with z = 0 at
the web's midplane where the web meets the rim, z < 0 towards the flange (the inner, flange side of the
wheel) and z > 0 towards the field side. The contact point is on the tread at the running circle, r = R (the
wheel radius), z = ``contact_offset``: its lateral offset from the web couples radial and axial motion
(``receptance``).

The parametric profile (:class:`WheelProfile`) is the cross-section of a solid wheel made of three parts: a
rectangular rim (tyre) of ``tyre_width`` x ``tyre_depth`` under the tread, with an optional rectangular
flange on its inner side; a web of constant ``web_thickness`` from the hub to the rim, whose midline runs from
z = ``web_offset`` at the hub to z = 0 at the rim and bulges by ``web_curvature`` (a sagitta) at mid-height;
a rectangular hub from the bore (``hub_inner_radius``) to ``hub_outer_radius``, ``hub_width`` wide, centred on
the web's midline. Fillets, the tread's conicity and the flange's shape are not modelled. Accepted ranges
are in :data:`wheelrail.core.inputs.ranges.ACCEPTED` (keys ``"wheel_" + field``), with their reasons.

:func:`outline_profile` takes any closed outline of (r, z) points instead (:func:`read_outline` reads one
from a CSV file). Both are checked by the same rules of what a wheel is (``section.check_section``: bore,
tread, area, thickness), so the shape options and an outline accept the same cross-sections.
"""

from __future__ import annotations

import csv
import math
import os
import stat
from dataclasses import asdict, dataclass, fields
from pathlib import Path

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.modal_wheel.section import (
    MAX_OUTLINE_BYTES,
    MAX_OUTLINE_POINTS,
    check_section,
    signed_area,
    simple_outline,
)

__all__ = [
    "NAMED_WHEELS",
    "OutlineProfile",
    "WheelProfile",
    "describe_wheel",
    "named_profile",
    "outline_profile",
    "read_outline",
    "profile_from_description",
    "section_mass",
    "wheel_profile_for",
]

_WEB_POINTS = 16  # points along each face of the web (its curvature); the mesher adds its own between them


@dataclass(frozen=True, kw_only=True)
class WheelProfile:
    """A parametric solid wheel's cross-section (module docstring). All lengths in m.

    Attributes
    ----------
    wheel_radius : float
        Radius of the running circle (the tread at the contact), m.
    tyre_width : float
        Axial width of the rim (tyre), flange excluded, m.
    tyre_depth : float
        Radial depth of the rim below the tread, m.
    web_thickness : float
        Axial thickness of the web, m.
    web_offset : float
        Axial position of the web's midline at the hub relative to the rim (the wheel's dish), m.
    web_curvature : float
        Axial bulge of the web's midline at mid-height (a sagitta; 0: a straight web), m.
    hub_inner_radius, hub_outer_radius : float
        The bore (the axle seat) and the hub's outer radius, m.
    hub_width : float
        Axial width of the hub, m.
    contact_offset : float
        Axial position of the running circle (the contact) from the web's midplane at the rim, m.
    flange_height, flange_thickness : float
        Radial height of the flange above the tread and its axial thickness, m (0, 0: no flange).
    """

    wheel_radius: float
    tyre_width: float = 0.135
    tyre_depth: float = 0.05
    web_thickness: float = 0.025
    web_offset: float = 0.0
    web_curvature: float = 0.0
    hub_inner_radius: float = 0.095
    hub_outer_radius: float = 0.125
    hub_width: float = 0.18
    contact_offset: float = 0.0
    flange_height: float = 0.0
    flange_thickness: float = 0.0

    def __post_init__(self):
        for item in fields(self):
            ACCEPTED[f"wheel_{item.name}" if item.name != "wheel_radius" else "wheel_radius"].check(
                getattr(self, item.name), f"WheelProfile.{item.name}"
            )
        self._check_parts_fit()
        self._check_section()

    def _check_section(self):
        """The rules of every wheel's cross-section (``section``), a part found too thin blamed on its field."""
        check_section(self.outline(), self.contact_point(), parameter=None, blame=self._field_at)

    def _field_at(self, r: float, z: float) -> Blame:
        """The error's blame naming the field that shapes the part at (r, z) (m): flange, rim, web or hub."""
        if r > self.wheel_radius:
            field = "flange_thickness"
        elif r >= self.wheel_radius - self.tyre_depth:
            field = "tyre_depth"
        else:
            field = "web_thickness" if r > self.hub_outer_radius else "hub_outer_radius"
        return Blame(f"wheel_{field}", getattr(self, field), "m", argument=f"WheelProfile.{field}")

    def _check_parts_fit(self):
        rim_inner = self.wheel_radius - self.tyre_depth
        mm = 1e3
        if self.hub_outer_radius <= self.hub_inner_radius:
            raise WheelrailError(
                f"the hub's outer radius must exceed its bore ({self.hub_inner_radius * mm:.4g} mm)",
                Blame("wheel_hub_outer_radius", self.hub_outer_radius, unit="m"),
            )
        if rim_inner - self.hub_outer_radius < 2 * self.web_thickness:
            raise WheelrailError(
                "the web must span at least twice its thickness between the hub and the rim (hub outer radius "
                f"{self.hub_outer_radius * mm:.4g} mm, rim inner radius "
                f"{rim_inner * mm:.4g} mm: wheel radius {self.wheel_radius * mm:.4g} mm less the tyre depth "
                f"{self.tyre_depth * mm:.4g} mm, web {self.web_thickness * mm:.4g} mm); these parts fit a wheel radius "
                f"of at least {(self.hub_outer_radius + 2 * self.web_thickness + self.tyre_depth) * mm:.4g} mm",
                Blame("wheel_hub_outer_radius", self.hub_outer_radius, unit="m"),
            )
        if self.web_thickness >= min(self.hub_width, self.tyre_width):
            raise WheelrailError(
                "the web must be thinner than the hub and the rim are wide",
                Blame("wheel_web_thickness", self.web_thickness, unit="m"),
            )
        if abs(self.contact_offset) > self.tyre_width / 2 - 0.005 or (
            self.flange_thickness > 0 and self.contact_offset < -self.tyre_width / 2 + self.flange_thickness + 0.005
        ):
            raise WheelrailError(
                "the contact must be on the tread, at least 5 mm from its edges and the flange",
                Blame("wheel_contact_offset", self.contact_offset, unit="m"),
            )

    @property
    def bore_radius(self) -> float:
        """The hub's inner radius, m (where the wheel sits on the axle)."""
        return self.hub_inner_radius

    def contact_point(self) -> tuple[float, float]:
        """(r, z) of the contact, m."""
        return self.wheel_radius, self.contact_offset

    def web_midline(self, r) -> np.ndarray:
        """z of the web's midline at radii ``r`` (hub to rim), m."""
        s = (np.asarray(r, dtype=float) - self.hub_outer_radius) / (
            self.wheel_radius - self.tyre_depth - self.hub_outer_radius
        )
        return self.web_offset * (1 - s) + self.web_curvature * 4 * s * (1 - s)

    def outline(self) -> np.ndarray:
        """The closed outline, (m, 2) of (r, z), counter-clockwise in the (r, z) plane, the contact a vertex."""
        R, half = self.wheel_radius, self.tyre_width / 2
        rim_inner = R - self.tyre_depth
        hub_z, hub_half, t = self.web_offset, self.hub_width / 2, self.web_thickness / 2
        web_r = np.linspace(self.hub_outer_radius, rim_inner, _WEB_POINTS)
        web_z = self.web_midline(web_r)
        points = [(self.hub_inner_radius, hub_z + hub_half), (self.hub_inner_radius, hub_z - hub_half)]
        points += [(self.hub_outer_radius, hub_z - hub_half)]
        points += list(zip(web_r, web_z - t, strict=True))
        points += [(rim_inner, -half)]
        if self.flange_height > 0 and self.flange_thickness > 0:
            points += [(R + self.flange_height, -half), (R + self.flange_height, -half + self.flange_thickness)]
            points += [(R, -half + self.flange_thickness)]
        else:
            points += [(R, -half)]
        points += [(R, self.contact_offset), (R, half), (rim_inner, half)]
        points += list(zip(web_r[::-1], web_z[::-1] + t, strict=True))
        points += [(self.hub_outer_radius, hub_z + hub_half)]
        return _counter_clockwise(np.array(points, dtype=float))

    def describe(self) -> dict:
        """What defines the cross-section (the cache's key, a result's record)."""
        return {"kind": "parametric", **asdict(self)}


@dataclass(frozen=True)
class OutlineProfile:
    """A cross-section given as a closed outline of (r, z) points, m, and the contact point on it (module
    docstring); made by :func:`outline_profile`, checked as every wheel (``section.check_section``)."""

    points: tuple[tuple[float, float], ...]
    contact: tuple[float, float]
    name: str = "outline"

    def __post_init__(self):
        if len(self.points) > MAX_OUTLINE_POINTS + 1:
            raise WheelrailError(
                f"a wheel outline has at most {MAX_OUTLINE_POINTS} points, not {len(self.points)}", Blame("outline")
            )
        outline = simple_outline(self.points)
        if len(outline) != len(self.points) or not np.array_equal(outline[0], self.points[0]):
            raise WheelrailError("an outline's points are kept counter-clockwise, each once", Blame("outline"))
        if not any(tuple(p) == tuple(self.contact) for p in self.points):
            raise WheelrailError("the contact is a point of the outline", Blame("contact_z"))
        check_section(outline, self.contact)

    @property
    def wheel_radius(self) -> float:
        return self.contact[0]

    @property
    def bore_radius(self) -> float:
        return min(r for r, _ in self.points)

    def contact_point(self) -> tuple[float, float]:
        return self.contact

    def outline(self) -> np.ndarray:
        return np.array(self.points, dtype=float)

    def describe(self) -> dict:
        return {"kind": "outline", "name": self.name, "points": [list(p) for p in self.points], "contact": self.contact}


def profile_from_description(description: dict):
    """The cross-section a ``describe()`` dict records (a run's header, a cache key): a ``WheelProfile`` or an
    ``OutlineProfile``, checked again; anything else is one WheelrailError."""
    values = dict(description) if isinstance(description, dict) else {}
    kind = values.pop("kind", None)
    try:
        if kind == "parametric":
            return WheelProfile(**values)
        if kind == "outline":
            points = tuple((float(r), float(z)) for r, z in values["points"])
            contact = tuple(float(v) for v in values["contact"])
            return OutlineProfile(points=points, contact=contact, name=str(values.get("name", "outline")))
    except WheelrailError as error:  # recorded, but not a wheel by the rules of ``section``
        raise WheelrailError(f"the recorded wheel profile is not a wheel: {error}") from None
    except (KeyError, TypeError, ValueError):
        raise WheelrailError(
            "the recorded wheel profile is damaged (a field missing, unknown or not a number)"
        ) from None
    raise WheelrailError(f"the recorded wheel profile is not a wheel cross-section (kind {kind!r})")


def section_mass(profile, density: float = 7850.0) -> float:
    """The mass of the wheel of revolution ``profile`` describes, kg: density x 2 pi x the first moment of its
    cross-section's area about the axis (Pappus), from its outline."""
    r, z = profile.outline().T
    r1, z1 = np.roll(r, -1), np.roll(z, -1)
    return float(density * 2 * np.pi * abs(np.sum((r + r1) * (r * z1 - r1 * z))) / 6)


def _counter_clockwise(points: np.ndarray) -> np.ndarray:
    return points if signed_area(points) > 0 else points[::-1].copy()


def outline_profile(points, contact_z: float, name: str = "outline") -> OutlineProfile:
    """A cross-section from a closed outline of (r, z) points (m) and the axial position of the contact.

    The contact is put on the outline where the vertical line z = ``contact_z`` meets it at its largest r (the
    tread); it becomes a vertex. Points may go either way round; a point repeated at once is dropped. Refused in
    one WheelrailError line: more than ``section.MAX_OUTLINE_POINTS`` points, values not finite, r <= 0, an
    outline that is not one closed curve (``section.simple_outline``), a ``contact_z`` outside the outline, a
    cross-section that is not a wheel (``section.check_section``: bore, tread, area, thickness).

    Parameters
    ----------
    points : array_like, shape (n, 2)
        (r, z) of the outline, m, in order around it.
    contact_z : float
        Axial position of the contact, m.
    name : str
        Name the profile carries.

    Returns
    -------
    OutlineProfile
        The cross-section with its contact point.

    Raises
    ------
    WheelrailError
        Any of the cases above, in one line.
    """
    array = np.asarray(points, dtype=float) if _numeric(points) else None
    if array is None or array.ndim != 2 or array.shape[1] != 2:
        raise WheelrailError("a wheel outline is (r, z) points, two numbers each", Blame("outline"))
    if len(array) > MAX_OUTLINE_POINTS + 1:  # + 1: the first point repeated at the end
        raise WheelrailError(f"a wheel outline has at most {MAX_OUTLINE_POINTS} points, not {len(array)} (a "
                             "measured profile has a few thousand)", Blame("outline"))  # fmt: skip
    if len(array) and np.all(np.isfinite(array)):  # points within 1 nm of the one before are the same point
        array = array[np.r_[True, np.any(np.abs(np.diff(array, axis=0)) > 1e-9, axis=1)]]
    array = simple_outline(array)
    if np.any(array[:, 0] <= 0):
        raise WheelrailError("a wheel outline's points have r > 0 (no point on the axle's axis)", Blame("outline"))
    array, contact = _insert_contact(array, float(contact_z))
    return OutlineProfile(tuple(map(tuple, array.tolist())), contact, name)


def _numeric(points) -> bool:
    try:
        np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def _insert_contact(array: np.ndarray, z: float) -> tuple[np.ndarray, tuple[float, float]]:
    """The outline with the tread point at axial position z inserted; that point."""
    a, b = array, np.roll(array, -1, axis=0)
    best = None
    for i in range(len(array)):
        (r0, z0), (r1, z1) = a[i], b[i]
        if min(z0, z1) <= z <= max(z0, z1) and z0 != z1:
            r = r0 + (r1 - r0) * (z - z0) / (z1 - z0)
            if best is None or r > best[1]:
                best = (i, r)
    if not math.isfinite(z) or best is None:
        raise WheelrailError("the contact's axial position must be within the outline", Blame("contact_z", z, unit="m"))
    i, r = best
    point = np.array([r, z])
    distance = np.hypot(*(array - point).T)
    if np.min(distance) < 1e-9:  # a vertex already: the contact is that vertex
        return array, tuple(float(v) for v in array[int(np.argmin(distance))])
    return np.insert(array, i + 1, point, axis=0), (float(r), float(z))


def read_outline(path, contact_z_mm: float) -> OutlineProfile:
    """A cross-section from a CSV file of (r, z) points in mm.

    One point per line, in order around the outline; a header line of words is skipped.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.
    contact_z_mm : float
        Axial position of the contact on the tread, mm.

    Returns
    -------
    OutlineProfile
        The cross-section, SI (see :func:`outline_profile`).

    Raises
    ------
    WheelrailError
        A file that cannot be read or holds no valid outline, in one line.

    See Also
    --------
    outline_profile : the same from points in metres.
    """
    path = Path(path)
    text = _outline_text(path)
    rows = []
    for number, row in enumerate(csv.reader(text.splitlines()), start=1):
        cells = [cell.strip() for cell in row if cell.strip()]
        if not cells or cells[0].startswith("#"):
            continue
        try:
            values = [float(cell) for cell in cells]
        except ValueError:
            if not rows and number == 1:
                continue  # a header
            raise WheelrailError(f"{path}: line {number} is not two numbers (r, z in mm)") from None
        if len(values) != 2:
            raise WheelrailError(f"{path}: line {number} has {len(values)} values, not two (r, z in mm)")
        if len(rows) > MAX_OUTLINE_POINTS:
            raise WheelrailError(f"{path}: a wheel outline has at most {MAX_OUTLINE_POINTS} points (a measured "
                                 "profile has a few thousand)", Blame("outline"))  # fmt: skip
        rows.append(values)
    tread = ACCEPTED["wheel_radius"]
    largest = max((abs(r) for r, _ in rows), default=math.nan)
    if largest < tread.minimum * 1e3:  # a wheel's outline in metres, inches or cm
        raise WheelrailError(f"{path}: the largest r is {largest:g} mm, below the smallest tread's "
                             f"{tread.minimum * 1e3:g} mm; the outline is read in mm (were its values metres, inches "
                             "or cm?)", Blame("outline"))  # fmt: skip
    return outline_profile(np.array(rows) * 1e-3 if rows else np.zeros((0, 2)), contact_z_mm * 1e-3, name=path.stem)


def _outline_text(path: Path) -> str:
    """The text of the outline file ``path``: a regular file (checked before it is opened, so that a FIFO or a
    device is not waited on or read without end) of at most ``MAX_OUTLINE_BYTES``, read with that limit."""
    try:
        if not stat.S_ISREG(path.stat().st_mode):
            raise WheelrailError(f"the wheel outline {path} is not a regular file (a folder, FIFO or device): give "
                                 "a CSV file", Blame("outline"))  # fmt: skip
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(descriptor, "rb") as handle:
            if not stat.S_ISREG(os.fstat(handle.fileno()).st_mode):  # replaced since it was looked at
                raise WheelrailError(f"the wheel outline {path} is not a regular file", Blame("outline"))
            data = handle.read(MAX_OUTLINE_BYTES + 1)
    except OSError as error:
        raise WheelrailError(f"cannot read the wheel outline {path}: {error.strerror or error}") from None
    if len(data) > MAX_OUTLINE_BYTES:
        raise WheelrailError(f"the wheel outline {path} is larger than {MAX_OUTLINE_BYTES / 1e6:g} MB (an outline "
                             f"of {MAX_OUTLINE_POINTS} points takes about 0.13 MB)", Blame("outline"))  # fmt: skip
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise WheelrailError(f"the wheel outline {path} is not UTF-8 text", Blame("outline")) from None


# Named standard-like wheels: approximate dimensions of common solid wheels, rounded to 5 mm. The 920 mm freight
# wheel follows the UIC/BR freight wheel Thompson analysed (Thompson, "Wheel-rail noise generation, part II:
# wheel vibration", J. Sound Vib. 161 (1993) 401-419; Thompson, "Railway Noise and Vibration", Elsevier 2009,
# chapter 5): 920 mm new diameter, a rim about 135 mm wide and 50 mm deep, a dished web about 25 mm thick; the
# 840 mm and 640 mm wheels are scaled versions with the rims of passenger-coach and small wagon wheels. None is a
# drawing of a real wheel: they are plausible shapes for comparing designs, not certified geometries.
NAMED_WHEELS: dict[str, WheelProfile] = {
    "freight_920": WheelProfile(
        wheel_radius=0.46, tyre_width=0.135, tyre_depth=0.05, web_thickness=0.025, web_offset=0.06,
        web_curvature=0.0, hub_inner_radius=0.095, hub_outer_radius=0.13, hub_width=0.18, contact_offset=0.0,
        flange_height=0.028, flange_thickness=0.03,
    ),
    "wheel_840": WheelProfile(
        wheel_radius=0.42, tyre_width=0.135, tyre_depth=0.045, web_thickness=0.022, web_offset=0.05,
        web_curvature=0.01, hub_inner_radius=0.095, hub_outer_radius=0.13, hub_width=0.175, contact_offset=0.0,
        flange_height=0.028, flange_thickness=0.03,
    ),
    "wheel_640": WheelProfile(
        wheel_radius=0.32, tyre_width=0.135, tyre_depth=0.04, web_thickness=0.022, web_offset=0.03,
        web_curvature=0.0, hub_inner_radius=0.08, hub_outer_radius=0.11, hub_width=0.16, contact_offset=0.0,
        flange_height=0.028, flange_thickness=0.03,
    ),
}  # fmt: skip


def named_profile(name: str) -> WheelProfile:
    """The named wheel ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`NAMED_WHEELS` (``freight_920``, ``wheel_840``, ``wheel_640``).

    Returns
    -------
    WheelProfile
        Its cross-section, SI.

    Raises
    ------
    WheelrailError
        An unknown name, in one line listing the names.

    Examples
    --------
    >>> from wheelrail.core.modal_wheel import named_profile
    >>> round(named_profile("freight_920").wheel_radius, 3)
    0.46
    """
    if name not in NAMED_WHEELS:
        names = ", ".join(NAMED_WHEELS)
        raise WheelrailError(f"unknown wheel {name!r}; named wheels are {names}", Blame("wheel_name"))
    return NAMED_WHEELS[name]


def wheel_profile_for(wheel_radius: float, name: str | None = None) -> WheelProfile:
    """A named wheel at the rolling radius ``wheel_radius`` (m; the run's or the noise chain's wheel radius): ``name``,
    or else the named wheel nearest in radius, its other dimensions kept (checked as any profile: a radius too
    small for its hub and rim is one WheelrailError naming it)."""
    from dataclasses import replace

    radius = ACCEPTED["wheel_radius"].check(wheel_radius, "wheel_radius")
    if name is None:
        name = min(NAMED_WHEELS, key=lambda key: abs(NAMED_WHEELS[key].wheel_radius - radius))
    return replace(named_profile(name), wheel_radius=radius)


def describe_wheel(profile) -> str:
    """A wheel as figures name it: its named wheel at its diameter ("wheel freight_920, diameter 780 mm") with the
    dimensions in which it differs from it ("..., web thickness 30 mm"; the named wheel it differs least from, then
    the nearest in radius), or its outline ("wheel outline o1, diameter 920 mm at the contact")."""
    if isinstance(profile, OutlineProfile):
        return f"wheel outline {profile.name}, diameter {2e3 * profile.wheel_radius:.6g} mm at the contact"

    def changed(named: WheelProfile) -> list[str]:
        return [
            f"{item.name.replace('_', ' ')} {1e3 * getattr(profile, item.name):.6g} mm"
            for item in fields(WheelProfile)
            if item.name != "wheel_radius" and getattr(profile, item.name) != getattr(named, item.name)
        ]

    name = min(
        NAMED_WHEELS,
        key=lambda key: (len(changed(NAMED_WHEELS[key])), abs(NAMED_WHEELS[key].wheel_radius - profile.wheel_radius)),
    )
    return ", ".join([f"wheel {name}", f"diameter {2e3 * profile.wheel_radius:.6g} mm", *changed(NAMED_WHEELS[name])])
