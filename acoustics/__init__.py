"""Sound radiated by a vibrating axisymmetric body (docs/theory.md, sound radiation).

One circumferential harmonic at a time: the exterior Helmholtz problem on the meridian
half-plane, quadratic triangles, a perfectly matched layer outside. The input is plain
data, the body's outline and its velocity (:class:`Surface`); this package knows
nothing of the modal or squeal models. Checked against the exact radiation of a sphere
(:mod:`acoustics.exact`). SI units throughout.
"""

from .air_mesh import AirMesh, air_mesh
from .exact import sphere_pressure, sphere_sound_power, sphere_surface
from .helmholtz import (
    BodyTraces,
    RadiationCost,
    RadiationSettings,
    SoundField,
    forget_air_meshes,
    kirchhoff_pressure,
    radiate,
    radiation_cost,
)
from .medium import AIR, P_REF_PA, W_REF_W, Air, sound_power_level_db, spl_db
from .surface import Surface

__all__ = [
    "AIR",
    "Air",
    "AirMesh",
    "BodyTraces",
    "RadiationCost",
    "P_REF_PA",
    "RadiationSettings",
    "SoundField",
    "Surface",
    "W_REF_W",
    "air_mesh",
    "kirchhoff_pressure",
    "forget_air_meshes",
    "radiate",
    "radiation_cost",
    "sound_power_level_db",
    "sphere_pressure",
    "sphere_sound_power",
    "sphere_surface",
    "spl_db",
]
