"""The cost of the FE's own work as the plans take it: meshing (:func:`mesh_plan`), the
modes a band holds before they are solved, and one mode's radiation."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..design import Design
from ..runtime.budget import CostPlan

if TYPE_CHECKING:
    from ..presets import Fidelity

__all__ = [
    "MESH_BYTES_PER_ELEMENT",
    "MESH_SECONDS_PER_ELEMENT",
    "estimated_modes",
    "mesh_plan",
    "radiation_seconds",
]

#: gmsh per element [s, bytes] (a fit on the shipped wheels up to 2e5 elements).
MESH_SECONDS_PER_ELEMENT = 7e-5
MESH_BYTES_PER_ELEMENT = 3e3


def mesh_plan(elements: float) -> CostPlan:
    """Meshing ``elements`` elements with gmsh."""
    plan = CostPlan()
    plan.add(
        f"meshing about {elements:,.0f} elements",
        MESH_SECONDS_PER_ELEMENT * elements,
        MESH_BYTES_PER_ELEMENT * elements,
        remedy="use larger elements or fewer through the web",
    )
    return plan


def estimated_modes(design: Design, fidelity: Fidelity, fmax_hz: float) -> int:
    """The modes below ``fmax_hz`` the FE's estimate counts (``fem.cost``)."""
    from fem.cost import estimate_cost
    from geometry.mesh import mesh_size

    h = mesh_size(design.wheel, elements_through_web=fidelity.elements_through_web)
    return max(estimate_cost(design.wheel, fidelity.solver, h, fmax_hz).modes, 1)


def radiation_seconds(design: Design, fidelity: Fidelity, fmax_hz: float, fraction: float) -> float:
    """One mode's radiation for the wheel at ``fraction`` of the band's top frequency,
    its outline sampled as the FE mesh's vertices are (every element)."""
    import numpy as np

    from acoustics import Surface, radiation_cost
    from geometry.mesh import mesh_size
    from geometry.profile import boundary_samples

    h = mesh_size(design.wheel, elements_through_web=fidelity.elements_through_web)
    points = boundary_samples(design.wheel, h)
    surface = Surface(points, np.zeros_like(points, dtype=complex), 0)
    return radiation_cost(surface, fraction * fmax_hz).seconds
