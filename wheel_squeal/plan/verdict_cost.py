"""The cost plan of a verdict (``run``, ``stability``, ``simulate``, ``compare``, a sweep's
points): in two steps, since which modes squeal is known only once the stability is
solved (:func:`stability_plan`, then :func:`verdict_plan`); and the ``stability``
command's bounds and envelope (:func:`stability_request_plan`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from reduced.integration_cost import simulation_seconds, simulation_steps

from ..design import Design
from ..mode_stability import body_of, excitable, mode_dofs, stability_seconds
from ..runtime.budget import CostPlan
from ..simulation import SIMULATION_HINT
from ..sound import sound_cost
from ..verdict_remedy import bounds_seconds, remedy_seconds

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, ModalDOF, OperatingPoint

__all__ = ["NO_REMEDY_HINT", "stability_plan", "stability_request_plan", "verdict_plan"]

#: How a user asks for less when a verdict's parts exceed the budget.
NO_REMEDY_HINT = "lower fmax_hz, or leave out the remedy (remedy=False) or the sound"


# --------------------------------------------------------------------------------------
# a verdict
# --------------------------------------------------------------------------------------
def stability_plan(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    rotation: bool,
    remedy: bool,
    dofs: Sequence[ModalDOF] | None = None,
) -> CostPlan:
    """The linear stability of every excitable mode (time and memory) and, when asked
    for (``remedy``), one mode's bounds among them (``dofs``: their ``mode_dofs``, when
    the caller has them)."""
    from reduced.stability import eigen_solve_bytes

    plan = CostPlan()
    if dofs is None:
        dofs = mode_dofs(excitable(modeset, contact), design)
    body = design.counter_body.states()
    if design.counter_body.model_seconds():
        plan.add(f"the {design.counter_body.KIND}'s model", design.counter_body.model_seconds())
    plan.add(
        f"stability of {len(dofs)} modes" + (f" and {body} states of the counter-body" if body else ""),
        stability_seconds(design, modeset, contact, rotation, dofs=dofs),
        eigen_solve_bytes(dofs, rotation, body),
    )
    if remedy:
        plan.add(
            "remedy or margin",
            max(bounds_seconds(dofs, rotation, body), remedy_seconds(dofs, 1, rotation, body)),
        )
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
    balanced = getattr(opts, "amplitude", "time domain") == "harmonic balance"
    body = body_of(design)
    states = 0 if body is None else body.states
    for m, together in [] if balanced else simulated:
        dofs = mode_dofs(together, design)
        steps = simulation_steps(dofs, contact, op, body=body)
        plan.add(
            f"squeal model of {m.label()} ({steps:,} steps)",
            simulation_seconds(dofs, contact, op, body=body),
            remedy=SIMULATION_HINT,
        )
    if opts.remedy and growing:
        dofs = mode_dofs(rows, design)
        n_growing = len(simulated[-1][1]) if simulated else 1
        plan.add("remedy", remedy_seconds(dofs, n_growing, opts.rotation, states))
        # its check: the largest group integrated once more with the remedy's damping
        biggest = max((mode_dofs(together, design) for _, together in simulated), key=len, default=None)
        if biggest is not None and not balanced:
            checked = simulation_seconds(biggest, contact, op, body=body)
            plan.add("the remedy checked in the time domain", checked)
    elif opts.remedy:
        plan.add("margin", bounds_seconds(mode_dofs(rows, design), opts.rotation, states))
    if sound:
        for m, _ in simulated:
            cost = sound_cost(design, modeset, m, opts.listener)
            if cost is not None:
                plan.add(f"sound of {m.label()}", cost.seconds, cost.memory_bytes)
    return plan


def stability_request_plan(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    rotation: bool,
    bounds: bool,
    envelope: tuple[int, int] | None = None,
) -> CostPlan:
    """The ``stability`` command: every mode's stability (with each mode's bounds when
    ``bounds``) and, with ``envelope`` (crabbing velocities, speeds), the map and both
    mitigations."""
    from reduced.stability import eigen_solve_bytes

    from ..envelope import envelope_seconds

    dofs = mode_dofs(excitable(modeset, contact), design)
    n = len(dofs)
    body = design.counter_body.states()
    plan = CostPlan()
    what = f"the linear stability of {n} modes and {body} counter-body states" + (
        f" with the critical damping and friction slope of {n}" if bounds else ""
    )
    plan.add(
        what,
        stability_seconds(design, modeset, contact, rotation, n if bounds else 0),
        eigen_solve_bytes(dofs, rotation, body),
        remedy="lower fmax_hz" + (", or leave out the bounds" if bounds else ""),
    )
    if envelope is not None:
        plan.add(
            f"the stability envelope ({envelope[0]} x {envelope[1]} points, {n} modes) and its mitigation",
            envelope_seconds(design, modeset, contact, *envelope),
            remedy="use fewer envelope points or a lower fmax_hz",
        )
    return plan
