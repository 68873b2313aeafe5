"""The cost plan of a study (``study``, :func:`study_plan`): its cases on the workers
found, each estimated from its spec before any case runs (:func:`estimate_study`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from ..design import Design
from ..runtime.budget import CostPlan
from ..types import FidelityName
from .fe_cost import radiation_seconds

__all__ = ["StudyCost", "StudyShape", "estimate_study", "study_plan"]


class StudyShape(Protocol):
    """What a study's plan reads of its spec (``study.spec.StudySpec``)."""

    @property
    def base(self) -> Design: ...

    @property
    def fidelity(self) -> FidelityName: ...

    @property
    def fmax_hz(self) -> float: ...

    @property
    def compute(self) -> tuple[str, ...]: ...

    @property
    def n_cases(self) -> int: ...

    @property
    def n_points(self) -> int: ...


#: One operating point's limit cycle (a compiled RK4 run to saturation and its analysis)
#: [s] (studies/rim_web_grid.toml; ``benchmarks/bench_study.py``)
SIMULATION_SECONDS_PER_POINT = 0.012
#: The same where the base design names its squeal mode: that mode is simulated as asked
#: wherever it grows, and a named mode that grows slowly runs long (to 4.8 s) before its
#: outcome is known (Table 1 names (3,0); studies/smoke.toml and rim_web_grid.toml).
NAMED_SIMULATION_SECONDS_PER_POINT = 0.08
#: With sound, a squealing point's microphone signal, harmonics and levels beyond the
#: radiation solves (studies/smoke.toml).
SIGNAL_SECONDS_PER_POINT = 0.02
#: Bytes the results hold per case and operating point (the per-point fields, the mode
#: label, and their copies in the Dataset, the CSV and NetCDF writers).
RESULT_BYTES_PER_POINT = 400
#: The frequency of a radiated mode, as a fraction of the band's top: the modes that grow
#: fastest are the low ones ((1,0) at 261 Hz and (2,0) at 471 Hz below 3 kHz on the
#: shipped specs)
STUDY_RADIATED_FRACTION = 0.1
#: Modes whose sound a study's case radiates (those that squeal over its operating grid,
#: each once): one, sometimes two, on the shipped specs.
STUDY_RADIATED_MODES = 1


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


def estimate_study(spec: StudyShape) -> StudyCost:
    """The per-case cost of ``spec`` and the size of its results: one case is one design,
    its modal solve (``fem.cost``, on the base design: the varied designs are of its
    size), the stability map (an eigen-solve per operating point), a limit cycle per
    operating point and, with sound, the radiation of a few modes (meant to be right
    within a factor of 2, which is what refusing a runaway study needs)."""
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
        one = radiation_seconds(spec.base, fid, spec.fmax_hz, STUDY_RADIATED_FRACTION)
        seconds += min(STUDY_RADIATED_MODES, points) * one + points * SIGNAL_SECONDS_PER_POINT
    return StudyCost(seconds, spec.n_cases * points * RESULT_BYTES_PER_POINT, solve)


def study_plan(spec: StudyShape, cost: StudyCost, workers: int, cases: int) -> CostPlan:
    """The ``study`` command: ``cases`` of its designs (those not stored by an earlier
    run) on ``workers`` parallel workers, and the results of all of them."""
    plan = CostPlan()
    plan.add(
        f"{cases:,} designs x {spec.n_points:,} operating points, about {cost.case_seconds:.2g} s each, "
        f"on {workers} worker(s)",
        cost.seconds(cases, workers),
        remedy="use fewer designs or operating points, a faster fidelity, or more workers (a cluster)",
    )
    plan.add(
        f"the results of {spec.n_cases:,} designs x {spec.n_points:,} operating points",
        0.0,
        cost.memory_bytes,
        remedy="use fewer designs or operating points",
    )
    return plan
