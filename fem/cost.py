"""What a modal solve will cost, estimated from the design before anything is meshed.

:func:`estimate_cost` predicts the size (DOFs, as ``ModeSet.dofs`` reports it), the
peak memory and the wall time of one solver on one mesh density, from closed-form
counts: the elements gmsh will make (:func:`geometry.mesh.estimate_element_count`), the
nodes of a P2 mesh, the number of circumferential harmonics and of modes in the band
(from the web as a Kirchhoff plate), and per-element / per-DOF costs measured on this
project's 2-core machines. It is meant to be right within a factor of 2 (tested on the
presets), which is what refusing a runaway request needs, not a benchmark.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from geometry.mesh import estimate_element_count
from geometry.wheel_design import WheelDesign

from .solvers import get_solver

__all__ = ["SolveCost", "estimate_cost", "harmonics_in_band", "modes_in_band"]

#: Memory of a solve that does almost nothing (bases, probes, temporaries) [bytes], by
#: solver: measured as the peak resident memory above the imports in a fresh process.
_BASE_MEMORY = {"axisym": 25e6, "3d": 45e6, "3d-tet": 40e6}
#: Axisymmetric solver: bytes per profile triangle (vectorised assembly temporaries at
#: quadrature order 7) and per mode and revolved-mesh node (the expanded shapes: 64
#: angles x 3 components x 2 members x 8 bytes).
_AXISYM_BYTES_PER_TRIANGLE = 38e3
_SHAPE_BYTES_PER_NODE = 3e3
#: P2 nodes per triangle of a gmsh profile mesh, corner nodes per triangle.
_P2_NODES_PER_TRIANGLE = 2.2
_CORNERS_PER_TRIANGLE = 0.6
#: One harmonic problem of N DOFs: 0.01 s + 2.2e-9 N^2 s (SuperLU factorisation and
#: shift-invert Lanczos; a fit from 4k to 70k DOFs).
_HARMONIC_SECONDS = (0.01, 2.2e-9)
#: Cyclic 3-D solver: bytes per DOF of the equivalent full problem.
_CYCLIC_BYTES_PER_DOF = 145.0
#: gmsh tetrahedra: P2 nodes per tet; one sparse factorisation of the whole wheel costs
#: about 16 kB per DOF at 41k DOFs, growing like N^1.5 (fill of a 3-D problem); the
#: eigen-solve takes _TET_SECONDS [s] at _TET_REFERENCE_DOFS, growing like N^2.
_TET_NODES_PER_TET = 1.9
_TET_BYTES_PER_DOF = 16e3
_TET_SECONDS = 6.0
_TET_REFERENCE_DOFS = 41e3


@dataclass(frozen=True)
class SolveCost:
    """Predicted cost of one modal solve.

    elements: elements of the mesh gmsh will make; dofs: as ``ModeSet.dofs`` (summed
    over the harmonic problems for the axisymmetric solver, the whole wheel's for the
    3-D ones); memory_bytes: peak memory of mesh and solve [bytes]; seconds: wall time
    [s]; modes: modes in the band.
    """

    elements: int
    dofs: int
    memory_bytes: float
    seconds: float
    modes: int


def _bending_wavenumber(design: WheelDesign, f_hz: float) -> float:
    """Kirchhoff bending wavenumber of the web at ``f_hz`` [1/m]."""
    t, E, nu, rho = design.wall_thickness, design.youngs_modulus, design.poissons_ratio, design.density
    D = E * t**3 / (12 * (1 - nu * nu))
    omega = 2 * math.pi * f_hz
    return (omega * omega * rho * t / D) ** 0.25


def harmonics_in_band(design: WheelDesign, fmax_hz: float) -> int:
    """Harmonic problems a harmonic solver solves up to ``fmax_hz``: n = 0 up to one
    past the highest nodal diameter in the band, ``0.8 k_b R`` (k_b the web's bending
    wavenumber at fmax, R the rim's inner radius; within 25 % of the solver on webs from
    1 to 15 mm)."""
    n_top = 0.8 * _bending_wavenumber(design, fmax_hz) * design.rim_inner_radius
    return max(3, int(math.ceil(n_top)) + 2)


def modes_in_band(design: WheelDesign, fmax_hz: float) -> int:
    """Modes (a pair counted once) up to ``fmax_hz``: 0.6 S k_b^2 / 4 pi + 5, the
    plate's modal count on the web's area S (within 20 % on webs from 1 to 15 mm)."""
    area = math.pi * (design.rim_inner_radius**2 - design.bore_radius**2)
    return int(0.6 * area * _bending_wavenumber(design, fmax_hz) ** 2 / (4 * math.pi) + 5)


def estimate_cost(
    design: WheelDesign, solver: str, h: float, fmax_hz: float, n_sectors: int | None = None
) -> SolveCost:
    """Estimated cost of ``solver`` ("axisym", "3d" for the cyclic 3-D solver, "3d-tet"
    for gmsh tetrahedra) at element size ``h`` [m] for the modes up to ``fmax_hz``."""
    modes = modes_in_band(design, fmax_hz)
    harmonics = harmonics_in_band(design, fmax_hz)
    a, b = _HARMONIC_SECONDS
    if solver == "axisym":
        tri = estimate_element_count(design, h, 2)
        per_harmonic = 3 * _P2_NODES_PER_TRIANGLE * tri
        memory = (
            _BASE_MEMORY["axisym"]
            + _AXISYM_BYTES_PER_TRIANGLE * tri
            + _SHAPE_BYTES_PER_NODE * modes * _CORNERS_PER_TRIANGLE * tri
        )
        seconds = 0.1 + harmonics * (a + b * per_harmonic**2)
        return SolveCost(tri, int(per_harmonic * harmonics), memory, seconds, modes)
    if solver == "3d":
        from .cyclic import default_sectors

        tri = estimate_element_count(design, h, 2)
        sectors = n_sectors or default_sectors(design, h)
        owned = 2 * _P2_NODES_PER_TRIANGLE * tri  # face-0 nodes plus the sector interior
        dofs = 3 * owned * sectors
        seconds = 0.3 + harmonics * (a + b * (2 * 3 * owned) ** 2)
        return SolveCost(
            3 * tri * sectors, int(dofs), _BASE_MEMORY["3d"] + _CYCLIC_BYTES_PER_DOF * dofs, seconds, modes
        )
    if solver == "3d-tet":
        tets = estimate_element_count(design, h, 3)
        dofs = 3 * _TET_NODES_PER_TET * tets
        ratio = dofs / _TET_REFERENCE_DOFS
        memory = _BASE_MEMORY["3d-tet"] + _TET_BYTES_PER_DOF * dofs * math.sqrt(ratio)
        return SolveCost(tets, int(dofs), memory, _TET_SECONDS * ratio**2, modes)
    get_solver(solver)  # raises for an unknown name
    raise NotImplementedError(f"no cost model for solver {solver!r}")
