"""Finite-element modal analysis of the wheel (scikit-fem)."""

from .axisym import solve_axisymmetric
from .render import render_mode, render_modes, to_pyvista, write_modes_vtu

__all__ = [
    "render_mode",
    "render_modes",
    "solve_axisymmetric",
    "to_pyvista",
    "write_modes_vtu",
]
