"""Grid of operating points (crabbing velocity x rolling speed) in one call.

All cases run from rest in a numba ``prange`` loop (one case per thread at a time), in
chunks of a few cases per thread so that memory stays bounded and a long sweep can
report progress; each time history is reduced on the fly to its cycles and then to
LimitCycle metrics with the same definitions as :func:`reduced.limit_cycle.limit_cycle`.
A case whose integration is flagged unstable (non-finite state or energy balance
violated) is re-run through :func:`reduced.model.simulate_rk4`, which refines the step.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from contact.creep import ContactLaw

from . import _engine
from .limit_cycle import Cycles, limit_cycle, metrics_from_cycles
from .model import (
    STEPS_PER_PERIOD,
    Modes,
    OperatingPoint,
    as_modes,
    choose_time_step,
    highest_frequency_hz,
    law_vector,
    mode_arrays,
    simulate_rk4,
)
from .stability import largest_growth_rate


def numba_threads() -> int:
    """Threads the compiled sweep kernel runs on."""
    import numba

    return int(numba.get_num_threads())


__all__ = ["SweepResult", "sweep", "sweep_points", "sweep_steps"]

#: cases per thread in one call of the compiled kernel (bounds the per-chunk buffers)
CHUNK_PER_THREAD = 16

#: largest number of RK4 steps per sweep case (the kernel keeps t, v and two running
#: integrals per step for each running case: 32 bytes/step, 0.8 GB at the limit)
MAX_SWEEP_STEPS = 25_000_000


@dataclass(frozen=True, eq=False)
class SweepResult:
    """Metrics on the grid; 2-D arrays have shape (n_crabbing, n_speeds).

    crabbing_velocities_m_s (n_crabbing,), rolling_speeds_m_s (n_speeds,): axes, m/s.
    velocity_amplitude_m_s : m/s. frequency_hz : Hz. growth_rate_1_s : fitted, 1/s.
    growth_rate_analytic_1_s : 1/s. squeal, saturated : bool.
    time_to_saturation_s : s (NaN if not saturated). duration_s : simulated time, s.
    """

    crabbing_velocities_m_s: np.ndarray
    rolling_speeds_m_s: np.ndarray
    velocity_amplitude_m_s: np.ndarray
    frequency_hz: np.ndarray
    growth_rate_1_s: np.ndarray
    growth_rate_analytic_1_s: np.ndarray
    squeal: np.ndarray
    saturated: np.ndarray
    time_to_saturation_s: np.ndarray
    duration_s: float


def sweep_steps(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    duration: float,
    steps_per_period: int = STEPS_PER_PERIOD,
) -> int:
    """RK4 steps one sweep case at ``op`` takes over ``duration`` s."""
    return int(math.ceil(duration / choose_time_step(modes, contact, op, steps_per_period) - 1e-9))


def sweep(
    modes: Modes,
    contact: ContactLaw,
    crabbing_velocities: ArrayLike,
    rolling_speeds: ArrayLike,
    duration: float,
    *,
    steps_per_period: int = STEPS_PER_PERIOD,
    energy_tolerance: float = 1e-2,
    progress: Callable[[int, int], None] | None = None,
) -> SweepResult:
    """Run every (Vc, V0) pair from rest for ``duration`` s and return the metrics.

    Parameters
    ----------
    modes : ModalDOF or sequence (shared contact force, as in simulate).
    contact : creep-law parameters.
    crabbing_velocities : Vc values, m/s (1-D).
    rolling_speeds : V0 values, m/s (1-D, > 0).
    duration : simulated time per case, s (slow growth near Vc = 0.5 m/s needs > 1 s).
    progress : called as ``progress(done, total)`` after each chunk of cases.
    """
    vcs = np.atleast_1d(np.asarray(crabbing_velocities, dtype=float))
    v0s = np.atleast_1d(np.asarray(rolling_speeds, dtype=float))
    ops = [OperatingPoint(v0, vc) for vc in vcs for v0 in v0s]  # validates every pair
    out = sweep_points(
        modes,
        contact,
        ops,
        duration,
        steps_per_period=steps_per_period,
        energy_tolerance=energy_tolerance,
        progress=progress,
    )
    shape = (len(vcs), len(v0s))
    return SweepResult(
        crabbing_velocities_m_s=vcs,
        rolling_speeds_m_s=v0s,
        velocity_amplitude_m_s=out["amp"].reshape(shape),
        frequency_hz=out["freq"].reshape(shape),
        growth_rate_1_s=out["growth"].reshape(shape),
        growth_rate_analytic_1_s=out["sigma"].reshape(shape),
        squeal=out["squeal"].reshape(shape),
        saturated=out["saturated"].reshape(shape),
        time_to_saturation_s=out["tsat"].reshape(shape),
        duration_s=float(duration),
    )


def sweep_points(
    modes: Modes,
    contact: ContactLaw,
    ops: Sequence[OperatingPoint],
    duration: float,
    *,
    steps_per_period: int = STEPS_PER_PERIOD,
    energy_tolerance: float = 1e-2,
    progress: Callable[[int, int], None] | None = None,
) -> dict[str, np.ndarray]:
    """:func:`sweep` at any list of operating points: flat arrays ``amp`` (m/s),
    ``freq`` (Hz), ``growth`` and ``sigma`` (fitted and analytic growth, 1/s), ``tsat``
    (s), ``squeal`` and ``saturated`` (bool), one entry per point."""
    modes = as_modes(modes)
    duration = float(duration)
    if not (math.isfinite(duration) and duration > 0):
        raise ValueError(f"duration must be positive and finite (s), got {duration!r}")
    m, c, k = mode_arrays(modes)
    a = np.array([md.lateral for md in modes])
    b = np.array([md.normal for md in modes])
    n_cases = len(ops)
    out = {name: np.full(n_cases, np.nan) for name in ("amp", "freq", "growth", "sigma", "tsat")}
    out["squeal"] = np.zeros(n_cases, dtype=bool)
    out["saturated"] = np.zeros(n_cases, dtype=bool)
    if not n_cases:
        return out
    laws = np.array([law_vector(contact, op, modes) for op in ops])
    h_nominal = np.array([choose_time_step(modes, contact, op, steps_per_period) for op in ops])
    n_steps = np.ceil(duration / h_nominal - 1e-9).astype(np.int64)
    worst = int(np.argmax(n_steps))
    if n_steps[worst] > MAX_SWEEP_STEPS:
        raise ValueError(
            f"sweep case Vc = {ops[worst].crabbing_velocity_m_s:g} m/s, "
            f"V0 = {ops[worst].rolling_speed_m_s:g} m/s needs {int(n_steps[worst]):,} RK4 steps of "
            f"{h_nominal[worst]:.3g} s over {duration:g} s (each running case keeps 4 arrays of that "
            f"length; limit MAX_SWEEP_STEPS = {MAX_SWEEP_STEPS:,}): "
            f"a very stiff or very light mode, or a very low rolling speed; shorten the duration "
            f"or run the case with simulate(..., store_every=...)"
        )
    h = duration / n_steps
    f_max = highest_frequency_hz(modes, 0.0, contact.normal_stiffness_n_m)
    cap = int(duration * f_max * 2.0) + 16
    ncyc = np.zeros(n_cases, dtype=np.int64)
    status = np.zeros(n_cases, dtype=np.int64)
    mismatch = np.zeros(n_cases)
    emax = np.zeros(n_cases)
    chunk = CHUNK_PER_THREAD * max(1, numba_threads())
    for lo in range(0, n_cases, chunk):
        hi = min(lo + chunk, n_cases)
        bufs = [np.zeros((hi - lo, cap)) for _ in range(5)]
        _engine.compiled().sweep_kernel(
            m,
            c,
            k,
            a,
            b,
            laws[lo:hi],
            h[lo:hi],
            n_steps[lo:hi],
            cap,
            *bufs,
            ncyc[lo:hi],
            status[lo:hi],
            mismatch[lo:hi],
            emax[lo:hi],
        )
        for i in range(lo, hi):
            op = ops[i]
            if status[i] != 0 or mismatch[i] > energy_tolerance * emax[i] + 1e-300:
                lc = limit_cycle(
                    simulate_rk4(
                        modes,
                        contact,
                        op,
                        duration,
                        steps_per_period=steps_per_period,
                        energy_tolerance=energy_tolerance,
                    )
                )
            else:
                cyc = Cycles(*(b[i - lo, : int(ncyc[i])] for b in bufs))
                lc = metrics_from_cycles(
                    cyc,
                    op.crabbing_velocity_m_s,
                    largest_growth_rate(modes, contact, op),
                    record_end_s=float(n_steps[i] * h[i]),
                )
            out["amp"][i] = lc.velocity_amplitude_m_s
            out["freq"][i] = lc.frequency_hz
            out["growth"][i] = lc.envelope_growth_rate_1_s
            out["sigma"][i] = lc.growth_rate_analytic_1_s
            out["tsat"][i] = lc.time_to_saturation_s
            out["squeal"][i] = lc.squeal
            out["saturated"][i] = lc.saturated
        if progress is not None:
            progress(hi, n_cases)
    return out
