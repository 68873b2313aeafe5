"""Finite-element modal analysis of the wheel (scikit-fem).

Solvers: :func:`solve_axisymmetric` (axisymmetric-harmonic, the fast path),
:func:`solve_cyclic` (3-D P2 tetrahedra on the profile revolved in identical sectors,
solved exactly by cyclic symmetry: the 3-D check) and :func:`solve_solid` (3-D
tetrahedra on any mesh, e.g. gmsh's unstructured one; one large eigen-solve). All return
a :class:`ModeSet` of :class:`Mode` objects with contact-point modal parameters. Rendering (pyvista) is imported on first
use, so the solvers do not pay for VTK.
"""

from .axisym import solve_axisymmetric
from .cyclic import solve_cyclic
from .eigen import available_factorizations, solve_eigen
from .modes import (EmptyBandWarning, FidelityWarning, LockingWarning, Mode, ModeSelection,
                    ModeSet, ResolutionWarning, contact_modal_mass, select_mode)
from .solid import solve_solid

_RENDER = ("render_mode", "render_modes", "to_pyvista", "write_modes_vtu")


def __getattr__(name: str):
    if name in _RENDER:
        from . import render

        return getattr(render, name)
    raise AttributeError(f"module 'fem' has no attribute {name!r}")


__all__ = [
    "EmptyBandWarning",
    "FidelityWarning",
    "LockingWarning",
    "Mode",
    "ModeSelection",
    "ModeSet",
    "ResolutionWarning",
    "available_factorizations",
    "contact_modal_mass",
    "render_mode",
    "render_modes",
    "select_mode",
    "solve_axisymmetric",
    "solve_cyclic",
    "solve_eigen",
    "solve_solid",
    "to_pyvista",
    "write_modes_vtu",
]
