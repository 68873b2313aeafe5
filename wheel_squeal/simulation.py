"""The time-domain stage: the squeal model integrated from rest at one operating point
until its outcome is known (``reduced.simulate_to_limit_cycle``), priced before it runs
(its steps, its seconds, its record's memory) and refused beyond the request's budget."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .runtime.budget import Budget
from .runtime.request_errors import RequestError
from .runtime.stage_cache import StageCache

if TYPE_CHECKING:
    from reduced import BodyModel, ContactLaw, ModalDOF, OperatingPoint
    from reduced.model import Modes

__all__ = [
    "MIN_RECORD_STEPS",
    "SIMULATION_HINT",
    "Simulation",
    "simulate",
]


@dataclass
class Simulation:
    """A time-domain run and its limit-cycle metrics (plain objects from ``reduced``)."""

    history: Any
    limit_cycle: Any
    contact: Any
    operating_point: Any

    def tail(self, seconds: float) -> Simulation:
        """The run with its record cut to the last ``seconds`` and its modal coordinates
        and counter-body states to their final values (its metrics kept)."""
        history = self.history.tail(seconds, 0.0)
        return Simulation(history, self.limit_cycle, self.contact, self.operating_point)

    def summary(self) -> dict:
        """JSON-ready {limit_cycle, operating_point, contact} (SI units, NaN -> None); the
        limit cycle says over which share of its last quarter the wheel and the roller
        lost contact (N = 0)."""
        from reduced import summary_dicts

        out = summary_dicts(self.limit_cycle, self.operating_point, self.contact)
        separated = self.history.separated
        out["limit_cycle"]["contact_lost_fraction"] = float(separated[3 * len(separated) // 4 :].mean())
        return out


def simulate(
    dof: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    duration: float | None = None,
    wheel_speed_rad_s: float = 0.0,
    budget: Budget | None = None,
    body: BodyModel | None = None,
    preload_body: bool = False,
    cache: StageCache | None = None,
) -> Simulation:
    """Integrate the squeal model from rest (``reduced.simulate_to_limit_cycle``): one
    mode or several together (a list), ``duration`` [s] fixed or None to run until the
    outcome is known, on a wheel turning at ``wheel_speed_rad_s`` (0: the paper's model),
    with the counter-body ``body`` in series (``preload_body``: it starts in its static
    deflection under the steady creep force, a track's); an unchanged request's record
    is read from ``cache`` (:mod:`wheel_squeal.records`). Its steps are counted first
    (``reduced.integration_cost``) and the run refused beyond ``budget`` (default:
    :meth:`Budget.from_environment`)."""
    from reduced import longest_record_s, simulate_to_limit_cycle
    from reduced.saturate import FIRST_DURATION_S

    dofs: list[ModalDOF] = list(dof) if isinstance(dof, list | tuple) else [dof]  # type: ignore[list-item]
    for d in dofs:
        split = d.nodal_diameters * abs(wheel_speed_rad_s)
        if split >= d.angular_frequency_rad_s:
            raise RequestError(
                f"a mode of {d.frequency_hz:.4g} Hz with {d.nodal_diameters} nodal diameters on a wheel "
                f"turning at {wheel_speed_rad_s:.4g} rad/s would split by +-{split / (2 * math.pi):.4g} Hz, "
                "more than its frequency: give the mode's true nodal diameters"
            )
    if duration is not None:
        if not (math.isfinite(duration) and duration > 0):
            raise RequestError(f"duration must be positive, got {duration:g}")
        longest = longest_record_s(dof, wheel_speed_rad_s=wheel_speed_rad_s)
        if duration > longest:
            raise RequestError(
                f"duration {duration:g} s is too long to record: at most {longest:.3g} s "
                "fit (48 samples per period of the highest mode, 10 million samples)"
            )
    from reduced.integration_cost import simulation_bytes, simulation_seconds, simulation_steps

    first = duration or FIRST_DURATION_S
    steps = simulation_steps(dofs, contact, op, first, body, wheel_speed_rad_s)
    if steps < MIN_RECORD_STEPS:
        raise RequestError(
            f"duration {first:g} s is {steps} step(s) of {first / steps:.3g} s: a record needs "
            f"at least {MIN_RECORD_STEPS} ({MIN_RECORD_STEPS * first / steps:.3g} s)"
        )
    from reduced import limit_cycle

    from .records import load_record, record_key, store_record

    key = record_key(dofs, contact, op, duration, wheel_speed_rad_s, body, preload_body)
    kept = load_record(cache, key, dofs, contact, op, wheel_speed_rad_s, body) if cache is not None else None
    if kept is not None:
        return Simulation(kept, limit_cycle(kept), contact, op)
    budget = budget or Budget.from_environment()
    budget.check_work(
        f"the squeal model ({steps:,} steps)",
        simulation_seconds(dofs, contact, op, first, body, wheel_speed_rad_s),
        SIMULATION_HINT,
        simulation_bytes(dofs, contact, op, body, wheel_speed_rad_s),
    )

    cut_short: list[bool] = []

    def may_extend(seconds: float) -> bool:
        # a longer run only where it fits the time left (else the record stays as it is,
        # reported as still growing: a result, not a refusal, and not kept)
        fits = seconds < 0.8 * budget.seconds_left()
        if not fits:
            cut_short.append(True)
        return fits

    try:
        history, lc = simulate_to_limit_cycle(
            dof,
            contact,
            op,
            duration,
            wheel_speed_rad_s=wheel_speed_rad_s,
            may_extend=may_extend,
            body=body,
            preload_body=preload_body,
        )
    except ValueError as exc:  # the model refuses what it cannot integrate, in its own words
        raise RequestError(str(exc)) from None
    if cache is not None and not cut_short:
        store_record(cache, key, history)
    return Simulation(history, lc, contact, op)


#: The fewest RK4 steps a simulated record may have (its analysis needs samples).
MIN_RECORD_STEPS = 16


#: What makes a squeal model's run cheaper
SIMULATION_HINT = "a higher rolling speed (the contact stiffens as it falls) or a shorter duration"
