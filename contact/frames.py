"""Where the wheel touches its counter-body: the contact point on the tread and the
contact frame there.

In the meridian plane (r, z) at angle 0 the contact point P carries the unit normal
``n = (cos g, sin g)``, out of the wheel towards the counter-body, at the *contact
angle* g from the radial direction, and the lateral tangent ``t = (-sin g, cos g)``
(axial at g = 0); rolling is circumferential. A parametric wheel's tread is a crown
arc of radius R1t about (R1 - R1t, 0): a contact angle g puts P where that arc's
normal makes the angle g, ``(R1 - R1t (1 - cos g), R1t sin g)``, as far as the arc
reaches across the rim. An outline names its contact point, and its own outward normal
there sets the angle. Beyond :data:`geometry.outline.MAX_CONTACT_ANGLE_DEG` lies flange
contact, a different regime.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from geometry.outline import MAX_CONTACT_ANGLE_DEG

if TYPE_CHECKING:
    from geometry.outline import Outline
    from geometry.wheel_design import WheelDesign

__all__ = [
    "ContactFrame",
    "ContactPointError",
    "contact_frame",
    "frame_on_running_surface",
    "largest_contact_angle_rad",
]

#: Angles below this [rad] are the apex's exactly (an outline's normal computed as
#: (1, 1e-17) must not tilt the frame by rounding).
ZERO_ANGLE_RAD = 1e-12
#: The axial step [m] of the differences that give the running surface's slope and curvature
#: (well below the smallest fillet a wheel's running surface has, a few mm)
SURFACE_STEP_M = 2.0e-5
#: A running surface curved less than this [1/m] (a radius over 1 km, the differences'
#: round-off on a straight cone) is straight across
FLAT_CURVATURE_1_M = 1.0e-3
#: The contact stays this fraction of the crown arc's reach inside the tread's edge
#: (a contact on the rim's corner has no single normal).
EDGE_MARGIN = 0.999
#: The frames a process keeps found, per function (a wheel's frames are pure functions of
#: its outline and the point: a curve map's contacts, on the contact table's points,
#: repeat them over curves and friction states)
FRAMES_KEPT = 1024


class ContactPointError(ValueError):
    """A contact angle the wheel's tread cannot take; the message names the limit.

    Examples
    --------
    >>> issubclass(ContactPointError, ValueError)
    True
    """


@dataclass(frozen=True)
class ContactFrame:
    """The contact point and its frame (see the module docstring).

    Attributes
    ----------
    r_m, z_m : float
        The point P in the meridian plane [m].
    angle_rad : float
        The contact angle g [rad] (positive: the normal leans towards +z).
    crown_radius_m : float
        The tread's transverse radius at P [m] (inf on a straight tread).

    Examples
    --------
    >>> f = ContactFrame(0.213, 0.0)
    >>> f.angle_rad, f.crown_radius_m
    (0.0, inf)
    """

    r_m: float
    z_m: float
    angle_rad: float = 0.0
    crown_radius_m: float = math.inf

    @property
    def normal(self) -> tuple[float, float]:
        """n = (n_r, n_z), out of the wheel."""
        return math.cos(self.angle_rad), math.sin(self.angle_rad)

    @property
    def tangent(self) -> tuple[float, float]:
        """t = (t_r, t_z), the lateral direction (axial at angle 0)."""
        return -math.sin(self.angle_rad), math.cos(self.angle_rad)

    @property
    def rolling_radius_m(self) -> float:
        """The radius P rolls on [m] (V0 = Omega r)."""
        return self.r_m

    @property
    def rolling_curvature_radius_m(self) -> float:
        """The tread's radius of curvature in the rolling direction at P, r / cos(g) [m]
        (Meusnier: the circumferential normal section of a surface of revolution)."""
        return self.r_m / math.cos(self.angle_rad)

    def components(self, u_r, u_z):
        """(u_t, u_n): a displacement (u_r, u_z) along the tangent and the normal (arrays
        or numbers; at angle 0 exactly (u_z, u_r))."""
        (t_r, t_z), (n_r, n_z) = self.tangent, self.normal
        return t_z * u_z + t_r * u_r, n_r * u_r + n_z * u_z

    def to_dict(self) -> dict:
        return {
            "r_m": self.r_m,
            "z_m": self.z_m,
            "contact_angle_rad": self.angle_rad,
            "contact_angle_deg": math.degrees(self.angle_rad),
            "crown_radius_m": self.crown_radius_m if math.isfinite(self.crown_radius_m) else None,
        }


def largest_contact_angle_rad(wheel: WheelDesign) -> float:
    """The largest contact angle [rad] a parametric wheel's crown arc reaches on its
    tread (inside its edge), and no more than the model's limit.

    Parameters
    ----------
    wheel : geometry.wheel_design.WheelDesign
        A parametric wheel.

    Returns
    -------
    float
        The angle [rad] (0 on a straight tread).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> largest_contact_angle_rad(ws.load_design("table1").wheel) > 0
    True"""
    reach = math.asin(min(1.0, wheel.rim_width / 2 / wheel.crown_radius)) * EDGE_MARGIN
    return min(reach, math.radians(MAX_CONTACT_ANGLE_DEG))


@functools.lru_cache(maxsize=FRAMES_KEPT)
def contact_frame(wheel: WheelDesign, contact_angle_rad: float = 0.0) -> ContactFrame:
    """The contact frame of ``wheel`` at ``contact_angle_rad`` [rad] (parametric wheels;
    an outline's contact point sets its own angle, so it takes 0 here). Raises
    :class:`ContactPointError` for an angle the tread cannot take."""
    g = float(contact_angle_rad)
    if not math.isfinite(g):
        raise ContactPointError(f"contact_angle must be a finite angle in rad, got {g!r}")
    if wheel.profile is not None:
        o = wheel.profile
        if abs(g) > ZERO_ANGLE_RAD:
            n_r, n_z = o.contact_normal()
            own = math.degrees(math.atan2(n_z, n_r))
            raise ContactPointError(
                f"contact_angle: an outline's contact point sets its own angle (here {own:.3g} deg); "
                "move [profile] contact instead"
            )
        n_r, n_z = o.contact_normal()
        angle = math.atan2(n_z, n_r)
        angle = 0.0 if abs(angle) < ZERO_ANGLE_RAD else angle
        return ContactFrame(o.contact[0], o.contact[1], angle, o.contact_crown_radius())
    if abs(g) < ZERO_ANGLE_RAD:
        return ContactFrame(wheel.rolling_radius, 0.0, 0.0, wheel.crown_radius)
    top = largest_contact_angle_rad(wheel)
    if abs(g) > top:
        why = (
            f"the model's limit (beyond {MAX_CONTACT_ANGLE_DEG:g} deg: flange contact)"
            if top >= math.radians(MAX_CONTACT_ANGLE_DEG)
            else f"the reach of its {wheel.crown_radius:g} m crown across the {wheel.rim_width:g} m rim"
        )
        raise ContactPointError(
            f"contact_angle {math.degrees(g):.3g} deg is off the tread: at most {math.degrees(top):.3g} deg, "
            f"{why}; a smaller crown_radius or an outline reaches further"
        )
    rt = wheel.crown_radius
    return ContactFrame(wheel.rolling_radius - rt * (1.0 - math.cos(g)), rt * math.sin(g), g, rt)


@functools.lru_cache(maxsize=FRAMES_KEPT)
def frame_on_running_surface(outline: Outline, z_m: float) -> ContactFrame:
    """The contact frame on an outline's running surface (its largest radius,
    ``Outline.outer_radius``) at the axial position ``z_m`` [m]: the point, the angle of
    its outward normal, atan(-dr/dz), and its transverse radius of curvature (negative
    where the surface is concave, as in a flange root's fillet). Anywhere on the tread or
    the flange: where a curving puts the contact, not where a design may put its own.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> f = frame_on_running_surface(ws.load_design("railway_920_track").wheel.profile, 0.0)
    >>> round(f.r_m, 4), round(math.degrees(f.angle_rad), 2)  # the 1:20 cone
    (0.46, 2.86)
    """
    h = SURFACE_STEP_M
    r_minus, r, r_plus = outline.outer_radius(np.array([z_m - h, z_m, z_m + h]))
    if not np.isfinite([r_minus, r, r_plus]).all():
        raise ContactPointError(f"z = {z_m:.4g} m is not on the wheel's running surface")
    slope = (r_plus - r_minus) / (2.0 * h)
    second = (r_plus - 2.0 * r + r_minus) / (h * h)
    curvature = -second / (1.0 + slope * slope) ** 1.5  # convex positive
    crown = 1.0 / curvature if abs(curvature) > FLAT_CURVATURE_1_M else math.inf
    return ContactFrame(float(r), float(z_m), math.atan(-slope), crown)
