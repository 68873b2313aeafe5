"""Finite-element modal analysis of the wheel (scikit-fem)."""

from .axisym import solve_axisymmetric
from .eigen import available_factorizations, solve_eigen
from .render import render_mode, render_modes, to_pyvista, write_modes_vtu
from .solid import solve_solid

__all__ = [
    "available_factorizations",
    "render_mode",
    "render_modes",
    "solve_axisymmetric",
    "solve_eigen",
    "solve_solid",
    "to_pyvista",
    "write_modes_vtu",
]
