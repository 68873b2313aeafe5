"""What a time-domain run to its limit cycle costs before it runs: its steps, its seconds
and its record's memory (by the integrator :func:`~reduced.integrate.choose_method` takes),
so that a request can be priced and refused before any work."""

from __future__ import annotations

import math

from contact.creep import ContactLaw

from .counter_body import BodyModel
from .integrate import choose_method
from .model import MAX_STORED_SAMPLES, Modes, OperatingPoint
from .saturate import FIRST_DURATION_S, MAX_DURATION_S, RECORD_SAMPLES_PER_PERIOD
from .stepping import SAMPLES_PER_PERIOD, TAIL_S, exponential_step_s
from .sweep import sweep_steps

__all__ = [
    "EXPONENTIAL_SECONDS_PER_STEP",
    "SWEEP_SECONDS_PER_STEP",
    "simulation_bytes",
    "simulation_seconds",
    "simulation_steps",
]

#: One RK4 step of one mode in a sweep, per thread, with the per-case reduction [s]
#: (``benchmarks/bench_estimates.py`` checks it).
SWEEP_SECONDS_PER_STEP = 1.7e-7
#: One step of the exponential integrator (:mod:`reduced.stepping`), compiled: per block (a
#: mode's coordinate, a counter-body's term) and for the contact's forces [s] (fitted on
#: railway_920_track with the rail's 32 terms, ``benchmarks/bench_time_domain.py``)
EXPONENTIAL_SECONDS_PER_STEP = (2.5e-8, 2e-7)


def simulation_steps(
    dof: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    duration: float | None = None,
    body: BodyModel | None = None,
    wheel_speed_rad_s: float = 0.0,
) -> int:
    """The steps of a run to its limit cycle's first stretch (``duration`` [s], default
    :data:`~reduced.saturate.FIRST_DURATION_S`), by the method it takes
    (:func:`~reduced.integrate.choose_method`)."""
    seconds = duration or FIRST_DURATION_S
    if choose_method(dof, contact, op, wheel_speed_rad_s, body) == "exponential":
        modes = tuple(dof) if isinstance(dof, list | tuple) else (dof,)
        return int(math.ceil(seconds / exponential_step_s(modes, contact, op, wheel_speed_rad_s)))
    return sweep_steps(dof, contact, op, seconds)


def simulation_seconds(
    dof: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    duration: float | None = None,
    body: BodyModel | None = None,
    wheel_speed_rad_s: float = 0.0,
) -> float:
    """The estimated time of a run's first stretch [s] (a longer run follows only where the
    time left allows it): its steps times each block's (a mode's coordinate, a
    counter-body's term) and the contact's cost per step."""
    n = len(dof) if isinstance(dof, list | tuple) else 1
    steps = simulation_steps(dof, contact, op, duration, body, wheel_speed_rad_s)
    if choose_method(dof, contact, op, wheel_speed_rad_s, body) == "exponential":
        per_block, per_step = EXPONENTIAL_SECONDS_PER_STEP
        return steps * (per_step + per_block * (n + (0 if body is None else body.terms)))
    return steps * n * SWEEP_SECONDS_PER_STEP


def simulation_bytes(
    dof: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    body: BodyModel | None = None,
    wheel_speed_rad_s: float = 0.0,
) -> float:
    """The record's memory at its longest run [bytes]: the contact's eight quantities per
    stored sample, and with the exponential integrator every block's states over its
    tail; with RK4 every coordinate over the whole record."""

    modes = tuple(dof) if isinstance(dof, list | tuple) else (dof,)
    f = max(m.frequency_hz for m in modes)
    if choose_method(dof, contact, op, wheel_speed_rad_s, body) == "exponential":
        blocks = len(modes) + (0 if body is None else body.terms)
        rate = SAMPLES_PER_PERIOD * f
        return 8.0 * rate * (8 * MAX_DURATION_S + 2 * blocks * TAIL_S)
    samples = min(MAX_STORED_SAMPLES, RECORD_SAMPLES_PER_PERIOD * f * MAX_DURATION_S)
    return 8.0 * samples * (2 * len(modes) + 12)
