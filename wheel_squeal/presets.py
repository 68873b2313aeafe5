"""Every default and preset of the application, in one place.

- the default wheel: ``designs/table1.toml`` (installed as package data, so the tool
  works from any folder), equal to ``geometry.WheelDesign()``;
- the band: modes up to :data:`DEFAULT_FMAX_HZ` (``fem.modes.DEFAULT_FMAX_HZ``);
- the operating point of the paper's Fig. 6: 800 RPM and a crabbing velocity of
  0.39 m/s;
- the fidelity presets (solver, element order, mesh): fast, balanced, accurate, chosen by
  the convergence study (README "Fidelity presets"); the solvers are named by the
  registry :data:`fem.solvers.SOLVERS`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from importlib.resources import files
from pathlib import Path

from fem.modes import DEFAULT_FMAX_HZ
from fem.solvers import SOLVERS, method_label
from reduced.model import rpm_to_speed

from .runtime.request_errors import RequestError
from .types import FidelityName, SolverName

__all__ = [
    "DEFAULT_CRAB_VELOCITY_M_S",
    "DEFAULT_DESIGN",
    "DEFAULT_ENVELOPE_CRAB_VELOCITIES",
    "DEFAULT_FIDELITY",
    "DEFAULT_FMAX_HZ",
    "DEFAULT_RPM",
    "DEFAULT_SPEEDS_RPM",
    "DEFAULT_SWEEP_CRAB_VELOCITIES",
    "FIDELITIES",
    "MAX_MULTIMODE",
    "Fidelity",
    "designs_folder",
    "fidelity_for",
    "rpm_to_speed",
]

DEFAULT_RPM = 800.0
DEFAULT_CRAB_VELOCITY_M_S = 0.39
#: The paper's three wheel speeds [rev/min] (Fig. 5): the axis of sweeps and envelopes.
DEFAULT_SPEEDS_RPM = (400.0, 600.0, 800.0)
#: Crabbing velocities (start, stop, points) [m/s] of a sweep (Fig. 5's range) and of
#: the stability map and mitigation envelope.
DEFAULT_SWEEP_CRAB_VELOCITIES = (0.0, 0.5, 26)
DEFAULT_ENVELOPE_CRAB_VELOCITIES = (0.0, 0.6, 50)
#: Most modes a multi-mode run integrates together.
MAX_MULTIMODE = 12


def designs_folder() -> Path:
    """The folder of the designs shipped with the tool."""
    return Path(str(files("designs")))


DEFAULT_DESIGN = designs_folder() / "table1.toml"


@dataclass(frozen=True)
class Fidelity:
    """A solver (a name of ``fem.solvers.SOLVERS``), element order and mesh, chosen
    together (README "Fidelity presets")."""

    name: FidelityName
    solver: SolverName
    order: int  # element order (2 = quadratic)
    elements_through_web: int
    mesh_order: int = 1  # geometry order of the mesh (1: straight P2 elements on it)

    @property
    def method(self) -> str:
        """The method label (``fem.solvers.method_label``): ``axisym-P2``, ``3d-P2``..."""
        return method_label(self.solver, self.order, self.mesh_order)


FIDELITIES: dict[str, Fidelity] = {
    "fast": Fidelity("fast", "axisym", 2, 1),
    "balanced": Fidelity("balanced", "axisym", 2, 2),
    "accurate": Fidelity("accurate", "axisym", 2, 4),
}
DEFAULT_FIDELITY: FidelityName = "balanced"


def fidelity_for(name: FidelityName, solver: SolverName | None = None) -> Fidelity:
    """The preset ``name``, optionally with another solver (a name of
    ``fem.solvers.SOLVERS``) at the same element order and mesh density, on the mesh
    order that solver uses for P2 (the 3-D solvers: curved, which converges from above;
    straight tets facet the tread and bore: +0.34 % vs +0.26 % at 1 element per web)."""
    if name not in FIDELITIES:
        raise RequestError(f"unknown fidelity {name!r}; choose from {', '.join(FIDELITIES)}")
    f = FIDELITIES[name]
    if solver is None or solver == f.solver:
        return f
    if solver not in SOLVERS:
        raise RequestError(f"unknown solver {solver!r}; choose {', '.join(SOLVERS)}")
    mesh_order = SOLVERS[solver].p2_mesh_order if f.order == 2 else 1
    return replace(f, solver=solver, mesh_order=mesh_order)
