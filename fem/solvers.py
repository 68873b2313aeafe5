"""The modal solvers by name: the one vocabulary of the CLI, the presets, the cache keys,
the convergence study and the benchmarks.

========  ==========================================================================
name      what it solves
========  ==========================================================================
axisym    axisymmetric harmonics: one 2-D problem per number of nodal diameters on
          the (r, z) profile (P2 triangles); the fast path of every preset
3d        3-D P2 tetrahedra on the profile revolved in identical sectors, split
          exactly by cyclic symmetry into one small problem per harmonic
3d-tet    3-D P2 (or P1) on gmsh's unstructured tetrahedra: one large eigen-solve,
          sharing nothing with the profile mesh (the independent check; 20-60x slower)
========  ==========================================================================

A *method* names a solver with its element order and mesh order:
:func:`method_label` (``axisym-P2``, ``axisym-P2-curved``, ``3d-P2``, ``3d-tet-P1``,
``3d-tet-P2``, ``3d-tet-P2-straight``) and :func:`parse_method` (its inverse).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .modes import DEFAULT_FMAX_HZ, ModeSet

if TYPE_CHECKING:
    from contact.frames import ContactFrame

__all__ = ["SOLVERS", "Solver", "get_solver", "method_label", "parse_method", "solve_modes"]


@dataclass(frozen=True)
class Solver:
    """A modal solver: its ``name``, a one-line ``description``, the dimension of the
    mesh it starts from (``mesh_dim``: 2, the profile, or 3, a gmsh solid) and the mesh
    order it uses for P2 by default (``p2_mesh_order``: 1 straight, 2 curved)."""

    name: str
    description: str
    mesh_dim: int
    p2_mesh_order: int


SOLVERS: dict[str, Solver] = {
    s.name: s
    for s in (
        Solver("axisym", "axisymmetric harmonics on the profile", 2, 1),
        Solver("3d", "3-D P2, the profile revolved in sectors, cyclic symmetry", 2, 2),
        Solver("3d-tet", "3-D on a gmsh tetrahedral mesh (slow; the independent check)", 3, 2),
    )
}


def get_solver(name: str) -> Solver:
    """The solver called ``name``; ValueError naming the choices otherwise."""
    try:
        return SOLVERS[name]
    except KeyError:
        raise ValueError(f"unknown solver {name!r}; choose {', '.join(SOLVERS)}") from None


def method_label(solver: str, order: int, mesh_order: int) -> str:
    """``axisym-P2``, ``axisym-P2-curved``, ``3d-P2``, ``3d-tet-P2-straight``, ...: the
    solver, the element order and, where it differs from the solver's usual one, the
    mesh order."""
    label = f"{get_solver(solver).name}-P{order}"
    if order == 2 and mesh_order != SOLVERS[solver].p2_mesh_order:
        label += "-curved" if mesh_order == 2 else "-straight"
    return label


def parse_method(label: str) -> tuple[str, int, int]:
    """(solver, element order, mesh order) of a :func:`method_label`."""
    base, _, variant = label.partition("-P")
    order_text, _, mesh = variant.partition("-")
    if base not in SOLVERS or order_text not in ("1", "2") or mesh not in ("", "curved", "straight"):
        raise ValueError(f"unknown method {label!r} (e.g. axisym-P2, axisym-P2-curved, 3d-P2, 3d-tet-P1)")
    order = int(order_text)
    usual = SOLVERS[base].p2_mesh_order if order == 2 else 1
    mesh_order = {"": usual, "curved": 2, "straight": 1}[mesh]
    return base, order, mesh_order


def solve_modes(
    design,
    mesh,
    solver: str,
    *,
    order: int = 2,
    fmax_hz: float = DEFAULT_FMAX_HZ,
    n_sectors: int | None = None,
    contact: ContactFrame | None = None,
) -> ModeSet:
    """Modes up to ``fmax_hz`` [Hz] of ``solver`` on a mesh from :mod:`geometry.mesh`: a
    ``ProfileMesh`` for "axisym" (curved elements if it is second order) and "3d"
    (revolved in ``n_sectors``, default :func:`fem.cyclic.default_sectors`), a
    ``SolidMesh`` for "3d-tet"; ``contact``: the contact frame of the modes' contact
    components (``contact.frames``; default the design's)."""
    get_solver(solver)
    if solver == "axisym":
        from .axisym import solve_axisymmetric

        return solve_axisymmetric(
            design, mesh, order=order, fmax_hz=fmax_hz, curved=mesh.order == 2, contact=contact
        )
    if solver == "3d":
        from geometry.revolve import revolve_profile

        from .cyclic import default_sectors, solve_cyclic

        solid = revolve_profile(mesh, n_sectors or default_sectors(design, mesh.size))
        return solve_cyclic(design, solid, fmax_hz=fmax_hz, contact=contact)
    from .solid import solve_solid

    return solve_solid(design, mesh, order=order, fmax_hz=fmax_hz, contact=contact)
