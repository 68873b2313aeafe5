"""The wheel half-profile in the (r, z) plane: outline, exact area and revolved volume.

The outline is a closed loop of straight segments and one circular arc (the crowned
tread). Exact area and volume (Pappus: V = 2 pi * integral of r dA) are closed-form, so
the meshes can be checked against them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .design import WheelDesign, tread_radius


@dataclass(frozen=True)
class Profile:
    """Closed half-profile outline in (r, z) [m], clockwise with r as abscissa and z as
    ordinate (counter-clockwise in (z, r)).

    ``vertices[i] -> vertices[i+1]`` is a straight segment except the one listed in
    ``arc``: ``(i, centre)`` means the segment from vertex i to vertex i+1 is a circular
    arc about ``centre`` (the tread). ``bore`` and ``tread`` give the indices of the
    segments lying on the bore (clamped) and on the tread (contact surface).
    """

    vertices: np.ndarray  # (n, 2) [r, z]
    arc: tuple[int, tuple[float, float]]
    bore: tuple[int, ...]
    tread: tuple[int, ...]
    contact_point: tuple[float, float]  # (r, z) of the tread apex [m]


def half_profile(d: WheelDesign) -> Profile:
    """Outline of the wheel cross-section (web + rim + crowned tread)."""
    rb, ri = d.bore_radius, d.rim_inner_radius
    hw = d.rim_width / 2
    z_lo, z_hi = d.web_offset - d.web_thickness / 2, d.web_offset + d.web_thickness / 2
    re = tread_radius(d, hw)
    # Clockwise in the (r, z) plane: along the bore upwards (+z), out along the upper web
    # face, up the rim face, over the tread (arc, from +z to -z), down the other rim
    # face, back along the lower web face.
    pts = [(rb, z_lo), (rb, z_hi), (ri, z_hi), (ri, hw), (re, hw), (re, -hw), (ri, -hw), (ri, z_lo)]
    kinds = ["bore", "line", "line", "line", "arc", "line", "line", "line"]
    # A web flush with a rim face makes a zero-length segment: drop repeated vertices.
    keep_pts, keep_kinds = [], []
    n = len(pts)
    for i in range(n):
        if math.dist(pts[i], pts[(i + 1) % n]) < 1e-12 * d.rolling_radius:
            continue
        keep_pts.append(pts[i])
        keep_kinds.append(kinds[i])
    arc_index = keep_kinds.index("arc")
    centre = (d.rolling_radius - d.crown_radius, 0.0)
    return Profile(
        vertices=np.array(keep_pts, dtype=float),
        arc=(arc_index, centre),
        bore=(keep_kinds.index("bore"),),
        tread=(arc_index,),
        contact_point=(d.rolling_radius, 0.0),
    )


def _tread_integrals(d: WheelDesign) -> tuple[float, float]:
    """Integrals over z in [-w/2, w/2] of r_t(z) and r_t(z)^2, r_t the tread radius."""
    R, h = d.crown_radius, d.rim_width / 2
    c = d.rolling_radius - R
    # int sqrt(R^2 - z^2) dz from -h to h
    s_int = h * math.sqrt(R * R - h * h) + R * R * math.asin(h / R)
    int_r = 2 * h * c + s_int
    # r_t^2 = c^2 + 2 c s + R^2 - z^2
    int_r2 = 2 * h * (c * c + R * R) + 2 * c * s_int - 2 * h**3 / 3
    return int_r, int_r2


def profile_area(d: WheelDesign) -> float:
    """Exact area of the half-profile [m^2]."""
    ri = d.rim_inner_radius
    int_r, _ = _tread_integrals(d)
    web = d.web_thickness * (ri - d.bore_radius)
    rim = int_r - d.rim_width * ri
    return web + rim


def revolved_volume(d: WheelDesign) -> float:
    """Exact volume of the wheel, the profile revolved about the axis [m^3] (Pappus)."""
    ri = d.rim_inner_radius
    _, int_r2 = _tread_integrals(d)
    web = math.pi * d.web_thickness * (ri**2 - d.bore_radius**2)
    rim = math.pi * (int_r2 - d.rim_width * ri**2)
    return web + rim


def wheel_mass(d: WheelDesign) -> float:
    """Mass of the wheel [kg]."""
    return d.density * revolved_volume(d)


__all__ = ["Profile", "half_profile", "profile_area", "revolved_volume", "wheel_mass"]
