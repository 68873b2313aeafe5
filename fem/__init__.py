"""Finite-element modal analysis of the wheel (scikit-fem).

Solvers: :func:`solve_axisymmetric` (axisymmetric-harmonic, the fast path),
:func:`solve_cyclic` (3-D P2 tetrahedra on the profile revolved in identical sectors,
solved exactly by cyclic symmetry: the 3-D check) and :func:`solve_solid` (3-D
tetrahedra on any mesh, e.g. gmsh's unstructured one; one large eigen-solve); the
registry :data:`fem.solvers.SOLVERS` names them. All return a :class:`ModeSet` of
:class:`Mode` objects with contact-point modal parameters.

Importing ``fem`` is cheap: each name is imported on first use, so reading modes back
(:mod:`fem.modes`) does not pay for scikit-fem, and the solvers do not pay for VTK.
"""

from __future__ import annotations

import importlib

#: public name -> module that defines it
_EXPORTS = {
    "solve_axisymmetric": "axisym",
    "solve_cyclic": "cyclic",
    "solve_solid": "solid",
    "available_factorizations": "eigen",
    "solve_eigen": "eigen",
    "EigenError": "eigen",
    "SOLVERS": "solvers",
    "solve_modes": "solvers",
    "DEFAULT_FMAX_HZ": "modes",
    "EmptyBandWarning": "modes",
    "FidelityWarning": "modes",
    "LockingWarning": "modes",
    "Mode": "modes",
    "ModeSelection": "modes",
    "ModeSet": "modes",
    "ResolutionWarning": "modes",
    "contact_modal_mass": "modes",
    "SelectedMode": "modes",
    "select_mode": "modes",
    "RenderStyle": "render",
    "render_mode": "render",
    "render_modes": "render",
    "to_pyvista": "render",
    "write_modes_vtu": "render",
    "modes_vtu_bytes": "render",
}


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'fem' has no attribute {name!r}")
    return getattr(importlib.import_module(f".{module}", __name__), name)


def __dir__() -> list[str]:
    return sorted(_EXPORTS)


__all__ = sorted(_EXPORTS)
