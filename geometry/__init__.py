"""Wheel designs and their geometry: parameters, half-profile, gmsh meshes.

Knows nothing of finite elements: meshes leave this package as numpy arrays.
"""

from .design import SECTIONS, STRUCTURAL_FIELDS, DesignError, WheelDesign, load_design, tread_radius
from .mesh import (
    DEFAULT_ELEMENTS_THROUGH_WEB,
    PHYSICAL_TAGS,
    MeshError,
    ProfileMesh,
    SolidMesh,
    mesh_profile,
    mesh_size,
    mesh_wheel,
    revolve_profile,
    SectorLayout,
)
from .profile import Profile, half_profile, profile_area, revolved_volume, wheel_mass

__all__ = [
    "DEFAULT_ELEMENTS_THROUGH_WEB",
    "DesignError",
    "MeshError",
    "PHYSICAL_TAGS",
    "ProfileMesh",
    "SolidMesh",
    "mesh_profile",
    "mesh_size",
    "mesh_wheel",
    "revolve_profile",
    "SectorLayout",
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
