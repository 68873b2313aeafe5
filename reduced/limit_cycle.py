"""Limit-cycle metrics of a squeal time history.

Definitions (all on the contact-point lateral velocity v = sum_i y_i'):

* **cycle**: the interval between two upward zero crossings of v (linearly
  interpolated). Per cycle: amplitude (max - min)/2 with parabolic refinement of
  the sampled extrema (m/s), period (s), mean power P of Eq. 7 (W), mean |Q v| (W).
* **saturated**: over the last ``window_cycles`` cycles (default 50, about 44 ms at
  1.1 kHz) the envelope varies by less than ``saturation_tolerance`` (default 1 %)
  of its mean, that mean exceeds the squeal threshold below, and the envelope's
  log-slope over the window is below ``LINEAR_RATE_FRACTION`` (10 %) of the magnitude
  of the analytic linear growth rate. A decaying oscillation is not "saturated": the
  last condition separates a limit cycle (envelope flat although the linearised
  equilibrium grows or decays at sigma) from a slow linear growth or decay (envelope
  slope = sigma) near the stability boundary (Vc ~ 0.62-0.64 m/s for Table 1, or c
  close to the friction's negative damping), whose envelope changes by less than
  the tolerance over a short window. Exactly at the boundary (sigma = 0) nothing is
  reported saturated.
* **velocity amplitude**: mean envelope over that final window. If not saturated
  it is the value reached at the end of the run (still growing or decaying). If the
  oscillation has died out (no zero crossing of v over the last 3 periods of the
  record: decayed to round-off, or a non-oscillating creep/stick state), it is 0.
* **squeal**: the final amplitude exceeds ``squeal_threshold`` * max(|Vc|, 1 mm/s)
  (default 1e-3) and the oscillation is self-sustained: saturated, its envelope still
  grows over the final window, or steady sliding is linearly unstable (analytic growth
  rate > 0): the motion cannot come back to rest then, so an oscillation that has not
  settled into a clean limit cycle (two modes beating, a light counter-body mode
  chattering) is still a squeal, never "quiet".
* **state**: "limit cycle" (saturated), "still growing" (the envelope's log-slope over the
  final window is above ``LINEAR_RATE_FRACTION`` of |sigma|), "not settled" (a squeal
  neither: its amplitude and frequency are then the record's, see below) or "quiet".
* **amplitude and frequency of a record that has not settled**: sqrt(2) times the rms of
  the contact velocity (about its mean) over the last quarter of the record, and the
  frequency of its largest spectral line there (:func:`limit_cycle` only; a sweep keeps
  no record and reports its cycles' mean).
* **time to saturation**: start of the first cycle after which every envelope value
  stays within ``saturation_tolerance`` of the final amplitude (NaN if not saturated).
* **envelope growth rate**: what the record shows of the linear growth: the
  least-squares slope of ln(envelope) against time over its exponential phase, 1/s.
  The envelope is the largest cycle amplitude in blocks of a few cycles (the upper
  envelope: two waves of a turning wheel's pair, or a growing and a decaying eigenvalue,
  beat in the cycle-by-cycle amplitude, and its maximum follows the growing one); the
  phase runs from where the envelope has doubled from its lowest block after the first
  (by then a decaying part of the start transient has died out beside the growing one)
  until it first exceeds 30 % of its final value (a record still growing at its end:
  to its end). If it decays, the whole record down to 1e-9 of
  the largest envelope, above the round-off floor. NaN where no such phase holds three
  blocks. It measures the record; the verdict's growth rate is the linear eigenvalue's.
* **mean power per cycle**: mean of P (Eq. 7) over each cycle, from the running
  integral of P (trapezoid on stored samples; RK4 stage quadrature in sweeps).
* **growth rate (analytic)**: the largest linear growth rate of steady sliding at the
  quasi-static creepage, the counter-body's own eigenvalues included
  (:func:`reduced.stability.largest_growth_rate`; for one mode
  sigma = -(c + W/V0 dmu/dzeta(Vc/V0)) / (2 m)), 1/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np

from . import _engine
from .model import TimeHistory
from .stability import largest_growth_rate

__all__ = [
    "Cycles",
    "LimitCycle",
    "State",
    "cycles",
    "limit_cycle",
    "envelope_growth_rate",
    "record_tail_level",
]

#: What a record shows at its end (see the module docstring).
State = Literal["limit cycle", "still growing", "not settled", "quiet"]

WINDOW_CYCLES = 50
SATURATION_TOLERANCE = 0.01
SQUEAL_THRESHOLD = 1e-3
#: at a limit cycle the envelope's log-slope must be below this fraction of |sigma|
LINEAR_RATE_FRACTION = 0.1
#: a decay is fitted down to this fraction of the largest envelope (round-off floor ~1e-15)
DECAY_FIT_FLOOR = 1e-9
#: the oscillation has died out if the last cycle ends this many periods before the record
CEASED_PERIODS = 3.0


@dataclass(frozen=True, eq=False)
class Cycles:
    """Per-cycle reduction of a time history (arrays of equal length).

    start_s : cycle start time, s. amplitude_m_s : (max v - min v)/2, m/s.
    period_s : s. mean_power_w : mean of P = Q v - c v^2 over the cycle, W.
    mean_abs_qv_w : mean of |Q v| over the cycle, W (scale for the power balance).
    """

    start_s: np.ndarray
    amplitude_m_s: np.ndarray
    period_s: np.ndarray
    mean_power_w: np.ndarray
    mean_abs_qv_w: np.ndarray


@dataclass(frozen=True, eq=False)
class LimitCycle:
    """Limit-cycle metrics (see the module docstring for the definitions).

    squeal : bool. saturated : bool. state : "limit cycle", "still growing", "not
        settled" or "quiet" (see the module docstring).
    velocity_amplitude_m_s : m/s.
    frequency_hz : mean over the final window, Hz (NaN if fewer than 2 cycles or if the
        final amplitude is below the squeal threshold).
    time_to_saturation_s : s (NaN if not saturated).
    envelope_growth_rate_1_s : the record's exponential phase, fitted, 1/s (NaN where it
        has none).
    growth_rate_analytic_1_s : the linear growth rate of steady sliding, 1/s.
    cycles : per-cycle times, amplitudes and mean power (Cycles).
    """

    squeal: bool
    saturated: bool
    velocity_amplitude_m_s: float
    frequency_hz: float
    time_to_saturation_s: float
    envelope_growth_rate_1_s: float
    growth_rate_analytic_1_s: float
    cycles: Cycles = field(repr=False)
    state: State = "quiet"


def cycles(history: TimeHistory) -> Cycles:
    """Split a TimeHistory into cycles of the contact velocity (see module docstring)."""
    t = np.ascontiguousarray(history.t, dtype=float)
    v = np.ascontiguousarray(history.v, dtype=float)
    dt = np.diff(t)
    p = np.concatenate([[0.0], np.cumsum(0.5 * (history.P[1:] + history.P[:-1]) * dt)])
    aqv = np.abs(history.Q * history.v)
    qv = np.concatenate([[0.0], np.cumsum(0.5 * (aqv[1:] + aqv[:-1]) * dt)])
    cap = max(1, len(t) // 2 + 1)
    out = [np.empty(cap) for _ in range(5)]
    n = _engine.cycle_kernels(len(t)).extract_cycles(t, v, p, qv, *out)
    return Cycles(*(a[:n].copy() for a in out))


def _fit_log_slope(t: np.ndarray, a: np.ndarray) -> float:
    ok = a > 0.0
    t, a = t[ok], a[ok]
    if len(t) < 3:
        return float("nan")
    return float(np.polyfit(t, np.log(a), 1)[0])


def metrics_from_cycles(
    cyc: Cycles,
    crabbing_velocity_m_s: float,
    growth_rate_analytic_1_s: float,
    *,
    window_cycles: int = WINDOW_CYCLES,
    saturation_tolerance: float = SATURATION_TOLERANCE,
    squeal_threshold: float = SQUEAL_THRESHOLD,
    record_end_s: float | None = None,
) -> LimitCycle:
    """Compute LimitCycle from per-cycle data (shared by limit_cycle and sweep).

    ``record_end_s`` (s): end time of the record; with it, an oscillation whose zero
    crossings stopped well before the end (died out) is reported with amplitude 0.
    """
    amp = cyc.amplitude_m_s
    n = len(amp)
    nan = float("nan")
    if n < 2:
        final = float(amp[-1]) if n else 0.0
        return LimitCycle(False, False, final, nan, nan, nan, growth_rate_analytic_1_s, cyc)
    w = min(window_cycles, n)
    tail = amp[n - w :]
    final = float(tail.mean())
    spread = float(tail.max() - tail.min())
    ceased = bool(
        record_end_s is not None
        and record_end_s - (cyc.start_s[-1] + cyc.period_s[-1]) > CEASED_PERIODS * cyc.period_s[-1]
    )
    if ceased:
        final = 0.0
    threshold = squeal_threshold * max(abs(crabbing_velocity_m_s), 1e-3)
    # the period of an oscillation decayed to round-off level means nothing
    frequency = float(1.0 / cyc.period_s[n - w :].mean()) if final > threshold else nan
    late_slope = _fit_log_slope(cyc.start_s[n - w :], tail)
    # a flat envelope is a limit cycle only if it is flat compared with the linear rate:
    # a slow linear growth/decay near the stability boundary has slope ~ sigma
    flat = not math.isfinite(late_slope) or abs(late_slope) <= LINEAR_RATE_FRACTION * abs(
        growth_rate_analytic_1_s
    )
    saturated = bool(
        n >= window_cycles and final > threshold and spread <= saturation_tolerance * final and flat
    )
    growing = math.isfinite(late_slope) and late_slope > 0.0
    squeal = bool(final > threshold and (saturated or growing or growth_rate_analytic_1_s > 0.0))
    state: State = (
        "quiet"
        if not squeal
        else "limit cycle"
        if saturated
        else "still growing"
        if growing and not flat
        else "not settled"
    )
    t_sat = nan
    if saturated:
        outside = np.nonzero(np.abs(amp - final) > saturation_tolerance * final)[0]
        first_in = 0 if len(outside) == 0 else int(outside[-1]) + 1
        t_sat = float(cyc.start_s[min(first_in, n - 1)])
    growth = envelope_growth_rate(cyc, final, saturated)
    return LimitCycle(
        squeal, saturated, final, frequency, t_sat, growth, growth_rate_analytic_1_s, cyc, state
    )


#: The exponential phase is fitted from where the envelope is this many times its lowest
GROWN_FROM_LOWEST = 2.0
#: The exponential phase is fitted on at least this many blocks of the envelope, each of
#: at most MAX_BLOCK_CYCLES cycles (a turning wheel's waves beat every 10-20 cycles)
MIN_BLOCKS, MAX_BLOCK_CYCLES = 8, 25
#: The exponential phase ends where the envelope first reaches this fraction of its final
#: value (beyond it the friction's saturation slows the growth)
LINEAR_PHASE_END = 0.3


def envelope_growth_rate(cyc: Cycles, final: float, saturated: bool = True) -> float:
    """The record's envelope growth rate [1/s] over its exponential phase (the module
    docstring): the slope of ln(block maximum of the cycle amplitudes) against time; a
    record that has not ``saturated`` is exponential to its end."""
    amp, start = cyc.amplitude_m_s, cyc.start_s
    n = len(amp)
    if n < 3:
        return float("nan")
    if not final > amp[0]:  # decaying: down to the round-off floor
        keep = amp >= DECAY_FIT_FLOOR * amp.max()
        return _fit_log_slope(start[keep], amp[keep])
    above = np.nonzero(amp >= LINEAR_PHASE_END * final)[0] if saturated else np.zeros(0, dtype=int)
    stop = int(above[0]) if len(above) else n
    size = int(min(MAX_BLOCK_CYCLES, max(1, stop // (2 * MIN_BLOCKS))))
    blocks = stop // size
    if blocks < 3:
        return float("nan")
    env = amp[: blocks * size].reshape(blocks, size).max(axis=1)
    times = start[: blocks * size].reshape(blocks, size).mean(axis=1)
    lo = 1 + int(np.argmin(env[1:])) if blocks > 3 else 0
    # from where it has doubled from its lowest: by then a decaying part of the start
    # transient (a coupled pair's other eigenvalue) has died out beside the growing one
    doubled = np.nonzero(env[lo:] >= GROWN_FROM_LOWEST * env[lo])[0]
    if len(doubled) and blocks - (lo + int(doubled[0])) >= 3:
        lo += int(doubled[0])
    if blocks - lo < 3:
        lo = max(0, blocks - 3)
    return _fit_log_slope(times[lo:], env[lo:])


def limit_cycle(
    history: TimeHistory,
    *,
    window_cycles: int = WINDOW_CYCLES,
    saturation_tolerance: float = SATURATION_TOLERANCE,
    squeal_threshold: float = SQUEAL_THRESHOLD,
) -> LimitCycle:
    """Limit-cycle metrics of a TimeHistory (definitions in the module docstring)."""
    cyc = cycles(history)
    sigma = largest_growth_rate(
        history.modes, history.contact, history.operating_point, history.wheel_speed_rad_s, history.body
    )
    lc = metrics_from_cycles(
        cyc,
        history.operating_point.crabbing_velocity_m_s,
        sigma,
        window_cycles=window_cycles,
        saturation_tolerance=saturation_tolerance,
        squeal_threshold=squeal_threshold,
        record_end_s=float(history.t[-1]) if len(history.t) else None,
    )
    if lc.state != "not settled":
        return lc
    amplitude, frequency = record_tail_level(history)
    return replace(lc, velocity_amplitude_m_s=amplitude, frequency_hz=frequency)


def record_tail_level(history: TimeHistory, fraction: float = 0.25) -> tuple[float, float]:
    """(sqrt(2) x rms of the contact velocity about its mean [m/s], frequency of its
    largest spectral line [Hz]) over the last ``fraction`` of the record: the level and
    tone of an oscillation that is not a clean limit cycle."""
    t, v = np.asarray(history.t, float), np.asarray(history.v, float)
    tail = t >= t[-1] - fraction * (t[-1] - t[0])
    x = v[tail] - v[tail].mean()
    if len(x) < 8:
        return float("nan"), float("nan")
    dt = float(np.mean(np.diff(t[tail])))
    spectrum = np.abs(np.fft.rfft(x * np.hanning(len(x))))
    spectrum[0] = 0.0
    k = int(np.argmax(spectrum))
    shift = 0.0
    if 0 < k < len(spectrum) - 1:  # the peak between bins: a parabola through log magnitudes
        a, b, c = np.log(np.maximum(spectrum[k - 1 : k + 2], 1e-300))
        shift = 0.5 * (a - c) / (a - 2 * b + c) if a - 2 * b + c < 0 else 0.0
    return float(np.sqrt(2.0 * np.mean(x * x))), float((k + shift) / (len(x) * dt))
