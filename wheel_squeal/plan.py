"""The cost plan of a verdict: every part of the request estimated before any of it
runs (``budget.CostPlan``), in two steps, since which modes squeal is known only once the
stability is solved: the stability and the remedy's bounds (:func:`stability_plan`), then
the time domain of the modes the verdict simulates and their sound (:func:`verdict_plan`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from .api import SIMULATION_HINT, simulation_seconds, simulation_steps
from .budget import CostPlan
from .design import Design
from .remedy import bounds_seconds, remedy_seconds
from .sound import sound_cost
from .stability import contact_dofs, excitable, stability_seconds

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, OperatingPoint

__all__ = ["NO_REMEDY_HINT", "stability_plan", "verdict_plan"]

#: How a user asks for less when a verdict's parts exceed the budget.
NO_REMEDY_HINT = "lower fmax_hz, or leave out the remedy (remedy=False) or the sound"


def stability_plan(
    design: Design, modeset: ModeSet, contact: ContactLaw, rotation: bool, remedy: bool
) -> CostPlan:
    """The linear stability of every excitable mode (time and memory) and, when asked
    for (``remedy``), one mode's bounds among them."""
    from reduced.stability import eigen_solve_bytes

    plan = CostPlan()
    dofs = contact_dofs(excitable(modeset, contact), design)
    plan.add(
        f"stability of {len(dofs)} degrees of freedom",
        stability_seconds(design, modeset, contact, rotation),
        eigen_solve_bytes(dofs, rotation),
    )
    if remedy:
        plan.add("remedy or margin", max(bounds_seconds(dofs, rotation), remedy_seconds(dofs, 1, rotation)))
    return plan


def verdict_plan(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    op: OperatingPoint,
    opts: Any,
    rows: Sequence[Mode],
    simulated: Sequence[tuple[Mode, Sequence[Mode]]],
    growing: bool,
    sound: bool,
) -> CostPlan:
    """The verdict's parts after the stability: the time domain of each group the
    decision integrates (``simulated``: (the mode named for it, the modes integrated
    together)), the remedy's or margin's bounds among ``rows`` (``opts.remedy``) and,
    with ``sound``, each named mode's radiation."""
    plan = CostPlan()
    for m, together in simulated:
        dofs = contact_dofs(together, design)
        steps = simulation_steps(dofs, contact, op)
        plan.add(
            f"squeal model of {m.label()} ({steps:,} RK4 steps)",
            simulation_seconds(dofs, contact, op),
            remedy=SIMULATION_HINT,
        )
    if opts.remedy and growing:
        dofs = contact_dofs(rows, design)
        n_growing = len(simulated[-1][1]) if simulated else 1
        plan.add("remedy", remedy_seconds(dofs, n_growing, opts.rotation))
        # its check: the largest group integrated once more with the remedy's damping
        biggest = max((contact_dofs(together, design) for _, together in simulated), key=len, default=None)
        if biggest is not None:
            plan.add("the remedy checked in the time domain", simulation_seconds(biggest, contact, op))
    elif opts.remedy:
        plan.add("margin", bounds_seconds(contact_dofs(rows, design), opts.rotation))
    if sound:
        for m, _ in simulated:
            cost = sound_cost(design, modeset, m, opts.listener)
            if cost is not None:
                plan.add(f"sound of {m.label()}", cost.seconds, cost.memory_bytes)
    return plan
