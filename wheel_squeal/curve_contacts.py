"""Each wheel of a curve at its own contacts: the design's running surface on its rail
(:func:`contact_geometry`) and each contact the steady curving finds as the design at that
contact (:func:`wheel_sites`: its frame, ellipse, load, C22, friction and sliding speed),
what :mod:`wheel_squeal.curve` runs the chain on."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .api import contact_law
from .context import memo_get, memo_put
from .design import Design
from .runtime.request_errors import RequestError

if TYPE_CHECKING:
    from collections.abc import Callable

    from contact.frames import ContactFrame
    from contact.wheel_rail import ContactGeometry
    from fem.modes import ModeSet
    from reduced import ContactLaw, OperatingPoint
    from track.bogie_curving import ContactState, WheelContact

__all__ = [
    "LEAST_LOAD_SHARE",
    "MOVED_MODES_KEPT",
    "ContactSiteAnalysis",
    "contact_geometry",
    "modes_at_contacts",
    "wheel_sites",
]

#: A contact carrying less than this share of its wheel's load is not analysed (it is
#: the first touch of a two-point contact, about to lift)
LEAST_LOAD_SHARE = 0.01


@dataclass(frozen=True)
class ContactSiteAnalysis:
    """One contact of a wheel in a curve: the design at that contact
    (:class:`~wheel_squeal.design.ContactSite`), its operating point and contact law."""

    state: ContactState
    design: Design
    op: OperatingPoint

    @functools.cached_property
    def law(self) -> ContactLaw:
        """The contact's creep law (its Hertz ellipse found when first asked: the chain
        finds its own, a curve map's pricing reads this one)."""
        return contact_law(self.design)


def contact_geometry(design: Design) -> ContactGeometry:
    """The design's wheel (its outline's running surface, or the standard profile of
    ``[contact] wheel_profile``) on its rail (UIC60 at 1:40): where each wheel of a wheelset
    touches for each lateral shift (``contact.wheel_rail``)."""
    from contact.profiles import running_surface, standard_wheel
    from contact.wheel_rail import ContactGeometry

    outline = design.wheel.profile
    if outline is None:
        raise RequestError(
            f"{design.name} is a parametric wheel: a curve needs its running surface and flange, "
            "a design with a [profile] outline"
        )
    r0 = design.rolling_radius
    name = design.contact.wheel_profile
    wheel = running_surface(outline, r0) if name == "outline" else standard_wheel(name)
    return ContactGeometry(wheel=wheel, rolling_radius_m=r0)


def wheel_sites(
    design: Design, wheel: WheelContact, train_speed_km_h: float, c22: float | None = None
) -> list[ContactSiteAnalysis]:
    """Each contact of ``wheel`` as the design there (module docstring); contacts with
    less than :data:`LEAST_LOAD_SHARE` of the wheel's load left out; ``c22`` replaces
    each contact's own Kalker coefficient (None: its ellipse's)."""
    from dataclasses import replace

    from contact.frames import frame_on_running_surface
    from reduced import OperatingPoint

    from .design import ContactSite

    assert design.wheel.profile is not None  # contact_geometry refused a parametric wheel
    speed = train_speed_km_h / 3.6
    tread_mu = design.contact.friction_coefficient
    flange_mu = design.contact.flange_friction_coefficient
    sites = []
    for c in wheel.contacts:
        if c.load_share < LEAST_LOAD_SHARE or c.normal_force_n <= 0.0:
            continue
        mu = flange_mu if c.on_flange and flange_mu is not None else tread_mu
        frame = frame_on_running_surface(design.wheel.profile, c.point.wheel_lateral_m)
        if design.contact.wheel_profile != "outline":  # the force's direction is the profile's
            frame = replace(frame, angle_rad=c.point.contact_angle_rad)
        at = design.replace(
            normal_load=c.normal_force_n,
            c22=c.c22 if c22 is None else c22,
            friction_coefficient=c.lateral_friction_coefficient(mu),
        )
        at = replace(at, contact_site=ContactSite(frame, c.point.relative_transverse_radius_m))
        op = OperatingPoint(speed, speed * c.crabbing_velocity_fraction)
        sites.append(ContactSiteAnalysis(c, at, op))
    return sites


#: The contacts whose modes a process keeps read (each a list of the modes' contact values)
MOVED_MODES_KEPT = 4096


def modes_at_contacts(modes: ModeSet, memo: dict[Any, Any]) -> Callable[[ContactFrame], ModeSet]:
    """The modes read at a contact frame: the mesh's meridian slice found once per mode set
    in ``memo`` (a run context's), each frame read once (a curving's contacts lie on the contact
    table's points, so that curves and friction states share them)."""
    from fem.moved_contact import MeridianSlice

    key = ("meridian slice", id(modes))
    held = memo_get(memo, key, modes.shapes)
    if held is None or held[0] is not modes:
        read: dict[ContactFrame, ModeSet] = {}
        held = memo_put(memo, key, modes.shapes, (modes, MeridianSlice(modes), read))
    _, meridian, read = held

    def at(frame: ContactFrame) -> ModeSet:
        if frame not in read:
            if len(read) >= MOVED_MODES_KEPT:
                read.clear()
            read[frame] = meridian.modes_at(frame)
        return read[frame]

    return at
