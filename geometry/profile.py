"""The half-profile of a design: its own outline, or the one its parameters make.

The parametric shape is a closed loop of straight segments, the crowned tread arc and
optional fillet arcs (:class:`geometry.outline.Outline`); area and revolved volume are
the outline's exact ones, so the meshes can be checked against them.
"""

from __future__ import annotations

import numpy as np

from .outline import Outline
from .parametric import parametric_outline
from .wheel_design import WheelDesign

__all__ = ["boundary_samples", "half_profile", "profile_area", "revolved_volume", "wheel_mass"]


def half_profile(d: WheelDesign) -> Outline:
    """The wheel's cross-section in (r, z): the design's [profile], or the parametric
    web + (hub) + rim + crowned tread. Raises OutlineError when the parameters make an
    impossible shape (a fillet that does not fit)."""
    return d.profile if d.profile is not None else parametric_outline(d)


def profile_area(d: WheelDesign) -> float:
    """Exact area of the half-profile [m^2]."""
    return half_profile(d).area()


def revolved_volume(d: WheelDesign) -> float:
    """Exact volume of the wheel, the profile revolved about the axis [m^3] (Pappus)."""
    return half_profile(d).revolved_volume()


def wheel_mass(d: WheelDesign) -> float:
    """Mass of the wheel [kg]."""
    return d.density * revolved_volume(d)


def boundary_samples(d: WheelDesign, spacing_m: float) -> np.ndarray:
    """Points (n, 2) in (r, z) along the half-profile's boundary, ``spacing_m`` apart
    by arc length (at least 8), as a mesh of that size has its boundary vertices."""
    poly, _ = half_profile(d).polygon()
    closed = np.vstack([poly, poly[:1]])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    at = np.linspace(0.0, arc[-1], max(8, int(arc[-1] / spacing_m)), endpoint=False)
    return np.stack([np.interp(at, arc, closed[:, 0]), np.interp(at, arc, closed[:, 1])], axis=1)
