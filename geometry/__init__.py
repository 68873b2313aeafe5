"""Wheels and their geometry: parameters or an outline, half-profile, meshes.

Knows nothing of finite elements: meshes leave this package as numpy arrays
(:mod:`geometry.mesh`), made by gmsh (:mod:`geometry.gmsh_mesh`) or by revolving the
profile mesh in identical sectors (:mod:`geometry.revolve`).
"""

from .gmsh_mesh import mesh_profile, mesh_wheel
from .mesh import (
    DEFAULT_ELEMENTS_THROUGH_WEB,
    PHYSICAL_TAGS,
    MeshError,
    ProfileMesh,
    SectorLayout,
    SolidMesh,
    estimate_element_count,
    mesh_size,
)
from .outline import Outline, OutlineError
from .profile import half_profile, profile_area, revolved_volume, wheel_mass
from .revolve import revolve_profile
from .wheel_design import SECTIONS, STRUCTURAL_FIELDS, DesignError, WheelDesign, tread_radius

__all__ = [
    "DEFAULT_ELEMENTS_THROUGH_WEB",
    "DesignError",
    "MeshError",
    "PHYSICAL_TAGS",
    "Outline",
    "OutlineError",
    "ProfileMesh",
    "SECTIONS",
    "STRUCTURAL_FIELDS",
    "SectorLayout",
    "SolidMesh",
    "WheelDesign",
    "estimate_element_count",
    "half_profile",
    "mesh_profile",
    "mesh_size",
    "mesh_wheel",
    "profile_area",
    "revolve_profile",
    "revolved_volume",
    "tread_radius",
    "wheel_mass",
]
