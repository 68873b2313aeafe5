"""A squeal simulation from rest, run until its outcome is known.

:func:`simulate_to_limit_cycle` integrates the model (:func:`reduced.simulate`)
from rest for the paper's 0.6 s, or longer when the harmonic-balance prediction says the
oscillation needs longer to saturate (growth from the start transient to the predicted
amplitude at the linear rate, with margin), and doubles the run while the oscillation
is still growing, up to ``max_duration``. The record keeps
``samples_per_period`` samples per period of the highest mode (every RK4 step at the
default step), so a stiff contact that shortens the step does not lengthen the record.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable

import numpy as np

from contact.creep import ContactLaw

from .counter_body import BodyModel
from .integrate import choose_method, simulate
from .limit_cycle import LimitCycle, limit_cycle
from .model import (
    MAX_STORED_SAMPLES,
    ModalDOF,
    Modes,
    OperatingPoint,
    TimeHistory,
    as_modes,
    highest_frequency_hz,
)
from .predictor import predict_limit_cycle

__all__ = [
    "FIRST_DURATION_S",
    "MAX_DURATION_S",
    "RECORD_SAMPLES_PER_PERIOD",
    "longest_record_s",
    "simulate_to_limit_cycle",
]

#: Samples per period of the highest mode kept in the record.
RECORD_SAMPLES_PER_PERIOD = 48
#: The first run's length [s] (the paper's Fig. 6), and the longest a run is extended to.
FIRST_DURATION_S = 0.6
MAX_DURATION_S = 4.8


def longest_record_s(
    modes: Modes, samples_per_period: int = RECORD_SAMPLES_PER_PERIOD, wheel_speed_rad_s: float = 0.0
) -> float:
    """The longest duration [s] whose record fits ``MAX_STORED_SAMPLES`` samples."""
    return MAX_STORED_SAMPLES / (samples_per_period * highest_frequency_hz(modes, wheel_speed_rad_s))


def simulate_to_limit_cycle(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    duration: float | None = None,
    max_duration: float = MAX_DURATION_S,
    samples_per_period: int = RECORD_SAMPLES_PER_PERIOD,
    wheel_speed_rad_s: float = 0.0,
    may_extend: Callable[[float], bool] | None = None,
    initial_state: tuple[np.ndarray, np.ndarray] | None = None,
    body: BodyModel | None = None,
    preload_body: bool = False,
) -> tuple[TimeHistory, LimitCycle]:
    """Integrate from rest; returns the history and its limit-cycle metrics.

    ``duration`` [s]: a fixed length; None chooses it as the module docstring says.
    ``wheel_speed_rad_s``: the wheel's rotation (:func:`reduced.simulate`).
    ``may_extend``: asked before each longer run with its estimated time [s] (twice the
    last run's); False keeps the last record (a caller's time budget). ``initial_state``:
    (y0, v0) per coordinate instead of rest (:func:`reduced.model.preloaded_state`).
    ``body``: the counter-body in series (``preload_body``: starting in its static
    deflection); with it, or a stiff contact, the exponential integrator runs
    (:func:`reduced.choose_method`) and a longer run continues the last one instead
    of starting again. Raises ValueError for a ``duration`` that is not positive or whose
    record would not fit (:func:`longest_record_s`).
    """
    longest = longest_record_s(modes, samples_per_period, wheel_speed_rad_s)
    if duration is not None:
        if not (math.isfinite(duration) and duration > 0):
            raise ValueError(f"duration must be positive, got {duration:g}")
        if duration > longest:
            f_top = highest_frequency_hz(modes, wheel_speed_rad_s)
            raise ValueError(
                f"duration {duration:g} s is too long to record: {samples_per_period} samples "
                f"per period of the {f_top:.4g} Hz mode fit at most {longest:.3g} s"
            )
    if duration is None:
        first = _first_duration(modes, contact, op, wheel_speed_rad_s)
        max_duration = min(max(max_duration, 2.0 * first), longest)
        t = min(first, max_duration)
    else:
        t = duration
    if choose_method(modes, contact, op, wheel_speed_rad_s, body) == "exponential":
        return _continued(
            modes,
            contact,
            op,
            t,
            duration is not None,
            max_duration,
            wheel_speed_rad_s,
            may_extend,
            initial_state,
            body,
            preload_body,
        )
    while True:
        started = time.perf_counter()
        history = simulate(
            modes,
            contact,
            op,
            t,
            initial_state,
            samples_per_period=samples_per_period,
            wheel_speed_rad_s=wheel_speed_rad_s,
        )
        lc = limit_cycle(history)
        settled = lc.saturated or (not lc.squeal and lc.growth_rate_analytic_1_s <= 0)
        if duration is not None or settled or t * 2 > max_duration:
            return history, lc
        if may_extend is not None and not may_extend(2.0 * (time.perf_counter() - started)):
            return history, lc
        t *= 2


def _continued(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    first: float,
    fixed: bool,
    max_duration: float,
    wheel_speed_rad_s: float,
    may_extend: Callable[[float], bool] | None,
    initial_state: tuple[np.ndarray, np.ndarray] | None,
    body: BodyModel | None,
    preload_body: bool,
) -> tuple[TimeHistory, LimitCycle]:
    """The exponential integrator's run: ``first`` seconds, then (unless ``fixed``) as
    long again while the outcome is not known, continuing the record, to ``max_duration``."""
    from .stepping import ExponentialRun

    run = ExponentialRun(
        as_modes(modes),
        contact,
        op,
        wheel_speed_rad_s,
        body,
        initial_state,
        preload_body,
        first if fixed else max(first, max_duration),
    )
    started = time.perf_counter()
    run.advance(first)
    while True:
        history = run.history()
        lc = limit_cycle(history)
        settled = lc.saturated or (not lc.squeal and lc.growth_rate_analytic_1_s <= 0)
        if fixed or settled or run.t * 2 > max_duration + 1e-9:
            return history, lc
        if may_extend is not None and not may_extend(time.perf_counter() - started):
            return history, lc
        started = time.perf_counter()
        run.advance(run.t)


def _first_duration(
    modes: Modes, contact: ContactLaw, op: OperatingPoint, wheel_speed_rad_s: float = 0.0
) -> float:
    """The paper's 0.6 s, or the predicted time to saturate with margin (one mode; a
    rotating pair as the travelling wave it becomes: twice the mass, stiffness and
    damping at the contact)."""
    t = FIRST_DURATION_S
    modes = as_modes(modes)
    if len(modes) != 1:  # the predictor takes one mode
        return t
    md = modes[0]
    if wheel_speed_rad_s != 0.0 and md.nodal_diameters >= 1:
        md = ModalDOF(2 * md.mass_kg, 2 * md.stiffness_n_m, 2 * md.damping_ns_m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # distortion warning: only an estimate here
        pred = predict_limit_cycle(md, contact, op)
    sigma = pred.growth_rate_analytic_1_s
    if pred.squeal and sigma > 0 and pred.initial_amplitude_m_s > 0:
        grow = math.log(max(pred.velocity_amplitude_m_s / pred.initial_amplitude_m_s, 1.0)) / sigma
        t = max(t, 1.5 * grow + 60.0 / pred.frequency_hz)
    return t
