"""Fast limit-cycle predictor without time integration (harmonic balance).

Assume the contact velocity is harmonic at the natural frequency,
y' = V sin(omega t). The mean power input per cycle (Eq. 7 averaged)::

    Pbar(V) = < Q(Vc + V sin th) V sin th >_th - c V^2 / 2,   Q(.) = -mu((Vc + .)/V0) W

is a describing-function energy balance. Limit cycles are the roots V > 0 of
Pbar(V) = 0 (V = 0 is always a trivial root). A root is **stable** if
dPbar/dV < 0 there (a larger amplitude loses energy, a smaller one gains it),
**unstable** otherwise. The phase average uses the midpoint rule on ``n_phase``
points (spectrally accurate for smooth periodic integrands; the kinks of the creep
law make it algebraic, 1024 points give < 1e-5 relative).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from .creep import ContactLaw, adhesion_ratio
from .limit_cycle import analytic_growth_rate
from .model import ModalDOF, OperatingPoint

__all__ = ["LimitCyclePrediction", "mean_power_per_cycle", "predict_limit_cycle"]


@dataclass(frozen=True)
class LimitCyclePrediction:
    """Harmonic-balance prediction.

    stable_amplitudes_m_s, unstable_amplitudes_m_s : velocity amplitudes V (m/s) of
        the stable / unstable limit cycles, ascending.
    frequency_hz : assumed oscillation frequency (undamped natural frequency), Hz.
    growth_rate_analytic_1_s : linear growth rate of the equilibrium, 1/s
        (> 0: V = 0 unstable).
    initial_amplitude_m_s : velocity amplitude excited by the force step when
        starting from rest, |Q(Vc)| / sqrt(k m), m/s.
    velocity_amplitude_m_s : predicted amplitude reached from rest (0 if none), m/s.
    squeal : velocity_amplitude_m_s > 0.
    """

    stable_amplitudes_m_s: tuple
    unstable_amplitudes_m_s: tuple
    frequency_hz: float
    growth_rate_analytic_1_s: float
    initial_amplitude_m_s: float
    velocity_amplitude_m_s: float
    squeal: bool


def mean_power_per_cycle(amplitude_m_s, mode: ModalDOF, contact: ContactLaw, op: OperatingPoint,
                         n_phase: int = 1024):
    """Pbar(V) in W for velocity amplitude(s) V in m/s (array-broadcast)."""
    V = np.asarray(amplitude_m_s, dtype=float)
    th = 2.0 * np.pi * (np.arange(n_phase) + 0.5) / n_phase
    sin = np.sin(th)
    vel = V[..., None] * sin
    zeta = (op.crabbing_velocity_m_s + vel) / op.rolling_speed_m_s
    Q = -adhesion_ratio(zeta, contact, op.rolling_speed_m_s) * contact.normal_load_n
    return (Q * vel).mean(axis=-1) - 0.5 * mode.damping_ns_m * V * V


def predict_limit_cycle(mode: ModalDOF, contact: ContactLaw, op: OperatingPoint, *,
                        n_phase: int = 1024, n_grid: int = 240) -> LimitCyclePrediction:
    """Limit-cycle amplitudes from the mean-power balance (see module docstring).

    Roots of Pbar(V)/V are bracketed on a geometric grid of ``n_grid`` amplitudes
    from 1e-5 m/s up to the amplitude beyond which damping alone outweighs the largest
    possible friction input (4 mu_s W / (pi c), at most 100 m/s), then refined with brentq.
    """
    if not isinstance(mode, ModalDOF):
        raise TypeError("predict_limit_cycle takes one ModalDOF")
    W = contact.normal_load_n
    mus = contact.friction_coefficient
    v_hi = 100.0 if mode.damping_ns_m == 0.0 else min(100.0, 4.0 * mus * W / (math.pi * mode.damping_ns_m))
    v_hi = max(v_hi, 3.0 * abs(op.crabbing_velocity_m_s), 1e-3)
    grid = np.geomspace(1e-5, v_hi, n_grid)
    g = mean_power_per_cycle(grid, mode, contact, op, n_phase) / grid

    def g_scalar(v: float) -> float:
        return float(mean_power_per_cycle(v, mode, contact, op, n_phase)) / v

    stable, unstable = [], []
    for i in np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0)[0]:
        root = brentq(g_scalar, grid[i], grid[i + 1], xtol=1e-12, rtol=1e-10)
        # Pbar = V g(V); at a root dPbar/dV = V g'(V): the sign of g's change
        (stable if g[i] > 0 else unstable).append(float(root))
    sigma = analytic_growth_rate(mode, contact, op)
    q0 = abs(float(adhesion_ratio(op.creepage, contact, op.rolling_speed_m_s))) * W
    a0 = q0 / math.sqrt(mode.stiffness_n_m * mode.mass_kg)
    # from rest: the oscillation starts at a0 and moves towards the nearest stable
    # state in the direction of the power balance
    if a0 > 0.0 and g_scalar(a0) > 0.0:
        above = [r for r in stable if r > a0]
        amp = above[0] if above else float("nan")
    elif a0 > 0.0:
        below = [r for r in stable if r < a0]
        amp = below[-1] if below else 0.0
    else:  # Vc = 0: exactly at rest, nothing excites the mode
        amp = 0.0
    return LimitCyclePrediction(tuple(stable), tuple(unstable), mode.frequency_hz, sigma, a0, amp,
                                bool(amp > 0.0))
