"""Finite-element modal analysis of the wheel (scikit-fem)."""

from .axisym import solve_axisymmetric

__all__ = ["solve_axisymmetric"]
