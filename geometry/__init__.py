"""Wheel designs and their geometry: parameters, half-profile, gmsh meshes.

Knows nothing of finite elements: meshes leave this package as numpy arrays.
"""

from .design import SECTIONS, STRUCTURAL_FIELDS, DesignError, WheelDesign, load_design, tread_radius
from .profile import Profile, half_profile, profile_area, revolved_volume, wheel_mass

__all__ = [
    "DesignError",
    "Profile",
    "SECTIONS",
    "STRUCTURAL_FIELDS",
    "WheelDesign",
    "half_profile",
    "load_design",
    "profile_area",
    "revolved_volume",
    "tread_radius",
    "wheel_mass",
]
