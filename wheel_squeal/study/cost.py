"""What a study will cost, estimated from its spec before any case runs.

One case is one design: its modal solve (``fem.cost``, on the base design: the varied
designs are of its size), the stability map (an eigen-solve per operating point), a
limit cycle per operating point and, with sound, the radiation of a few modes. The
per-point and per-case constants were measured on the shipped specs (serial loop on a
shared 2-core machine); the whole is meant to be right within a factor of 2, which is
what refusing a runaway study needs.
"""

from __future__ import annotations

from dataclasses import dataclass

from .spec import StudySpec

__all__ = ["StudyCost", "estimate_study"]

#: One operating point's limit cycle (a compiled RK4 run to saturation and its analysis)
#: [s]: measured 12 ms per point on rim_web_grid (48 designs x 15 points).
SIMULATION_SECONDS_PER_POINT = 0.012
#: The same where the base design names its squeal mode: that mode is simulated as asked
#: wherever it grows, and a named mode that grows slowly runs long (to 4.8 s) before its
#: outcome is known: measured 72 ms per point on rim_web_grid (Table 1 names (3,0)).
NAMED_SIMULATION_SECONDS_PER_POINT = 0.05
#: Modes whose sound a case radiates (those that squeal over its operating grid, each
#: once): one, sometimes two, on the shipped specs.
RADIATED_MODES = 1
#: The frequency of a radiated mode, as a fraction of the band's top: the modes that
#: grow fastest are the low ones ((1,0) at 261 Hz and (2,0) at 471 Hz below 3 kHz on
#: the shipped specs).
RADIATED_FRACTION = 0.1
#: Bytes the results hold per case and operating point (the per-point fields, the mode
#: label, and their copies in the Dataset, the CSV and NetCDF writers).
RESULT_BYTES_PER_POINT = 400


@dataclass(frozen=True)
class StudyCost:
    """The estimated cost of a study's cases: ``case_seconds`` of one case (one worker,
    one thread), ``memory_bytes`` of the results, and the modal solve of one case as
    ``fem.cost.SolveCost``."""

    case_seconds: float
    memory_bytes: float
    solve: object

    def seconds(self, cases: int, workers: int) -> float:
        """The wall time of ``cases`` cases on ``workers`` parallel workers [s]."""
        return cases * self.case_seconds / max(workers, 1)


def estimate_study(spec: StudySpec) -> StudyCost:
    """The per-case cost of ``spec`` and the size of its results (see the module
    docstring)."""
    from fem.cost import estimate_cost
    from geometry.mesh import mesh_size
    from reduced import ModalDOF
    from reduced.stability import eigen_solve_seconds

    from ..presets import fidelity_for

    fid = fidelity_for(spec.fidelity)
    h = mesh_size(spec.base.wheel, elements_through_web=fid.elements_through_web)
    solve = estimate_cost(spec.base.wheel, fid.solver, h, spec.fmax_hz)
    points = spec.n_points
    seconds = solve.seconds
    if "stability" in spec.compute:
        modes = [ModalDOF(1.0, 1.0, 0.0)] * max(solve.modes, 1)
        seconds += points * eigen_solve_seconds(modes)
    if "limit_cycle" in spec.compute:
        named = bool(spec.base.squeal.mode)
        seconds += points * (NAMED_SIMULATION_SECONDS_PER_POINT if named else SIMULATION_SECONDS_PER_POINT)
    if "sound" in spec.compute:
        seconds += min(RADIATED_MODES, points) * _radiation_seconds(spec, h)
    return StudyCost(seconds, spec.n_cases * points * RESULT_BYTES_PER_POINT, solve)


def _radiation_seconds(spec: StudySpec, h: float) -> float:
    """One mode's radiation for the base wheel at :data:`RADIATED_FRACTION` of the band's
    top frequency, its outline sampled as the FE mesh's vertices are (every element)."""
    import numpy as np

    from acoustics import Surface, radiation_cost
    from geometry.profile import boundary_samples

    points = boundary_samples(spec.base.wheel, h)
    surface = Surface(points, np.zeros_like(points, dtype=complex), 0)
    return radiation_cost(surface, RADIATED_FRACTION * spec.fmax_hz).seconds
