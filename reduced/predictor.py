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

Validity: the harmonic assumption needs the contact force to be a weak perturbation
of the mode. Its measure here is the **distortion** at a predicted amplitude V: the
rms of Q(theta) minus its mean and fundamental, over the modal force amplitude
sqrt(k m) V. Measured amplitude errors against the time domain: 0.3 % distortion
(Table 1) -> 0.01 %; 5 % -> 0.7-1 %; 16 % -> 5 %; 50-60 % -> 33 % (very light modes,
where the mode sticks to the roller for part of the cycle and the frequency drops).
Above ``DISTORTION_WARNING`` (10 %) a RuntimeWarning says so: use the time domain.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from contact.creep import ContactLaw, adhesion_ratio, adhesion_ratio_slope
from contact.numerics import find_root

from .model import ModalDOF, OperatingPoint
from .stability import largest_growth_rate

__all__ = [
    "LimitCyclePrediction",
    "equivalent_mode",
    "harmonic_contact_velocities",
    "mean_power_per_cycle",
    "predict_limit_cycle",
]

#: harmonic distortion of the contact force above which the prediction is flagged
DISTORTION_WARNING = 0.1


def harmonic_distortion(
    amplitude_m_s: float, mode: ModalDOF, contact: ContactLaw, op: OperatingPoint, n_phase: int = 1024
) -> float:
    """rms of Q(V sin th) without its mean and fundamental, over sqrt(k m) V (dimensionless)."""
    th = 2.0 * np.pi * (np.arange(n_phase) + 0.5) / n_phase
    sin, cos = np.sin(th), np.cos(th)
    vel = amplitude_m_s * sin
    Q = (
        -adhesion_ratio(
            (op.crabbing_velocity_m_s + vel) / op.rolling_speed_m_s, contact, op.rolling_speed_m_s
        )
        * contact.normal_load_n
    )
    rest = Q - Q.mean() - 2.0 * (Q * sin).mean() * sin - 2.0 * (Q * cos).mean() * cos
    return float(
        np.sqrt((rest * rest).mean()) / (math.sqrt(mode.stiffness_n_m * mode.mass_kg) * amplitude_m_s)
    )


@dataclass(frozen=True)
class LimitCyclePrediction:
    """Harmonic-balance prediction.

    stable_amplitudes_m_s, unstable_amplitudes_m_s : velocity amplitudes V (m/s) of
        the stable / unstable limit cycles, ascending.
    frequency_hz : assumed oscillation frequency (undamped natural frequency), Hz.
    growth_rate_analytic_1_s : linear growth rate of the equilibrium, 1/s
        (> 0: V = 0 unstable).
    initial_amplitude_m_s : velocity amplitude at the contact excited by the force step
        when starting from rest, |Q(Vc)| l^2 / sqrt(k m) (l the mode's lateral
        displacement at the contact), m/s.
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


def equivalent_mode(
    mode: ModalDOF, contact: ContactLaw, op: OperatingPoint, growth_rate_1_s: float
) -> tuple[ModalDOF, bool]:
    """``mode`` alone on a rigid counter-body with its damping changed so that its linear
    growth rate at ``op`` is ``growth_rate_1_s`` [1/s] (what the mode has among the others
    and on a compliant counter-body, from the full linear analysis): the counter-body's
    and the other modes' linear effect lumped into the mode's damping,
    c_eq = c - 2 m (sigma - sigma_1), sigma_1 the mode's own growth rate alone.

    Returns the mode and whether c_eq had to be clipped at zero (the rest of the
    system adds more than the mode's own damping removes: the lumped mode then grows
    slower than asked, and the prediction is a lower bound).

    Examples
    --------
    >>> import reduced as r
    >>> law = r.ContactLaw.from_hertz(r.hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0),
    ...                               friction_coefficient=0.3)
    >>> op = r.OperatingPoint.from_rpm(800, 0.213, 0.39)
    >>> eq, clipped = equivalent_mode(r.ModalDOF(3.1, 1.6e8, 42.0), law, op, 5.0)
    >>> round(largest_growth_rate(eq, law, op), 9), clipped
    (5.0, False)
    """
    sigma_1 = largest_growth_rate(mode, contact, op)
    c_eq = mode.damping_ns_m - 2.0 * mode.mass_kg * (growth_rate_1_s - sigma_1)
    clipped = c_eq < 0.0
    eq = ModalDOF(
        mode.mass_kg, mode.stiffness_n_m, max(c_eq, 0.0), mode.nodal_diameters, mode.lateral, mode.normal
    )
    return eq, clipped


def _midpoint_sines(n_phase: int) -> np.ndarray:
    """sin(th) at the ``n_phase`` midpoints th = 2 pi (k + 1/2) / n, each value once where
    it comes twice (th and pi - th; ``n_phase`` a multiple of 4): an average of a function
    of sin(th) over them is the midpoint rule's, at half the evaluations."""
    if n_phase % 4:
        return np.sin(2.0 * np.pi * (np.arange(n_phase) + 0.5) / n_phase)
    quarter = np.sin(2.0 * np.pi * (np.arange(n_phase // 4) + 0.5) / n_phase)
    return np.concatenate([quarter, -quarter])


#: Amplitude-and-phase pairs evaluated at a time by :func:`mean_power_per_cycle`: its
#: temporaries stay in the processor's cache (a whole grid's, a megabyte each, cost four
#: times as much in fresh memory's page faults)
PHASE_BLOCK = 16384


def mean_power_per_cycle(
    amplitude_m_s: ArrayLike, mode: ModalDOF, contact: ContactLaw, op: OperatingPoint, n_phase: int = 1024
) -> np.ndarray:
    """Pbar(V) in W for velocity amplitude(s) V in m/s (array-broadcast)."""
    V = np.asarray(amplitude_m_s, dtype=float)
    return _friction_power(V, contact, op, n_phase) - 0.5 * mode.damping_ns_m * V * V


#: The grids of :func:`_friction_power_on_grid` a process keeps (each a few kB)
GRIDS_KEPT = 256


@functools.lru_cache(maxsize=GRIDS_KEPT)
def _friction_power_on_grid(
    contact: ContactLaw, op: OperatingPoint, v_hi: float, n_grid: int, n_phase: int
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`predict_limit_cycle`'s amplitude grid and the friction's mean power on it:
    the modes balanced at one contact (a competition's, the verdict's) share it where
    their grids end at the same amplitude (read-only arrays)."""
    grid = np.geomspace(1e-5, v_hi, n_grid)
    power = _friction_power(grid, contact, op, n_phase)
    grid.flags.writeable = False
    power.flags.writeable = False
    return grid, power


def _friction_power(V: np.ndarray, contact: ContactLaw, op: OperatingPoint, n_phase: int) -> np.ndarray:
    """The friction's mean power per cycle [W] into a contact velocity of amplitude(s) V,
    the mode's own damping left out."""
    sines = _midpoint_sines(n_phase)
    flat = V.reshape(-1)
    out = np.empty(flat.shape)
    rows = max(1, PHASE_BLOCK // len(sines))
    for i in range(0, flat.size, rows):
        vel = flat[i : i + rows, None] * sines
        zeta = (op.crabbing_velocity_m_s + vel) / op.rolling_speed_m_s
        Q = -adhesion_ratio(zeta, contact, op.rolling_speed_m_s) * contact.normal_load_n
        out[i : i + rows] = (Q * vel).mean(axis=-1)
    return out.reshape(V.shape)


def initial_amplitude(mode: ModalDOF, contact: ContactLaw, op: OperatingPoint) -> float:
    """The contact velocity amplitude [m/s] the creep force's step gives ``mode`` at a start
    from rest: its modal force is Q l and the contact sees l q', so a0 = |Q| l^2 / sqrt(k m)
    (Q = mu(zeta0) W the steady creep force, l the mode's lateral displacement at the
    contact)."""
    q0 = abs(float(adhesion_ratio(op.creepage, contact, op.rolling_speed_m_s))) * contact.normal_load_n
    return q0 * mode.lateral**2 / math.sqrt(mode.stiffness_n_m * mode.mass_kg)


def predict_limit_cycle(
    mode: ModalDOF, contact: ContactLaw, op: OperatingPoint, *, n_phase: int = 1024, n_grid: int = 240
) -> LimitCyclePrediction:
    """Limit-cycle amplitudes from the mean-power balance (see module docstring).

    Roots of Pbar(V)/V are bracketed on a geometric grid of ``n_grid`` amplitudes
    from 1e-5 m/s up to the amplitude beyond which damping alone outweighs the largest
    possible friction input (4 mu_s W / (pi c), at most 100 m/s), then refined with Brent's method.
    """
    if not isinstance(mode, ModalDOF):
        raise TypeError("predict_limit_cycle takes one ModalDOF")
    W = contact.normal_load_n
    mus = contact.friction_coefficient
    v_hi = 100.0 if mode.damping_ns_m == 0.0 else min(100.0, 4.0 * mus * W / (math.pi * mode.damping_ns_m))
    v_hi = max(v_hi, 3.0 * abs(op.crabbing_velocity_m_s), 1e-3)
    grid, power = _friction_power_on_grid(contact, op, v_hi, n_grid, n_phase)
    g = (power - 0.5 * mode.damping_ns_m * grid * grid) / grid

    def g_scalar(v: float) -> float:
        return float(mean_power_per_cycle(v, mode, contact, op, n_phase)) / v

    stable: list[float] = []
    unstable: list[float] = []
    for i in np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0)[0]:
        root = find_root(g_scalar, grid[i], grid[i + 1], xtol=1e-12, rtol=1e-10)
        # Pbar = V g(V); at a root dPbar/dV = V g'(V): the sign of g's change
        (stable if g[i] > 0 else unstable).append(float(root))
    sigma = largest_growth_rate(mode, contact, op)
    a0 = initial_amplitude(mode, contact, op)
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
    checked = [v for v in ([amp] if amp > 0.0 else stable) if math.isfinite(v) and v > 0.0]
    if checked:
        worst = max(checked, key=lambda v: harmonic_distortion(v, mode, contact, op, n_phase))
        dist = harmonic_distortion(worst, mode, contact, op, n_phase)
        if dist > DISTORTION_WARNING:
            warnings.warn(
                f"harmonic-balance prediction unreliable: the contact force at V = {worst:.3g} m/s is "
                f"{100 * dist:.0f} % distorted relative to the modal force sqrt(k m) V = "
                f"{math.sqrt(mode.stiffness_n_m * mode.mass_kg) * worst:.3g} N (limit "
                f"{100 * DISTORTION_WARNING:.0f} %; errors of 5 % and more): the contact dominates "
                f"this mode (light or soft mode, high load); use the time-domain simulate()",
                RuntimeWarning,
                stacklevel=2,
            )
    return LimitCyclePrediction(
        tuple(stable), tuple(unstable), mode.frequency_hz, sigma, a0, amp, bool(amp > 0.0)
    )


def harmonic_contact_velocities(
    amplitude_m_s: float,
    frequency_hz: float,
    modes: Sequence[ModalDOF],
    contact: ContactLaw,
    op: OperatingPoint,
    orders: int,
    n_phase: int = 1024,
) -> np.ndarray:
    """The contact velocity's harmonics 1..``orders`` [m/s] of a harmonic-balance cycle
    of amplitude ``amplitude_m_s`` at ``frequency_hz``: the first is the cycle's own; the
    k-th is the contact force's k-th harmonic F_k (of Q(Vc + V sin th)) through the
    modes' lateral mobility at k omega, sum_j l_j^2 i k omega / (k_j - m_j (k omega)^2 +
    i c_j' k omega): the other modes' response to the force's distortion, what a time
    domain of the same modes shows beyond the fundamental. On the cycle each mode's
    damping c_j' is its own plus the friction's, (W / V0) l_j^2 <dmu/dzeta>, the creep
    curve's slope averaged over the slip's sweep (never below its own: a mode that the
    cycle does not damp is left at its own damping). The counter-body's mobility and the
    harmonics' feedback on the force are left out.

    Examples
    --------
    A creep force without distortion (a linear creep curve, small cycle) has no harmonics:

    >>> import reduced as r
    >>> law = r.ContactLaw.from_hertz(r.hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0),
    ...                               friction_coefficient=0.3, friction_law="constant")
    >>> op = r.OperatingPoint(10.0, 0.0)
    >>> v = harmonic_contact_velocities(1e-6, 1000.0, [r.ModalDOF(3.1, 1.2e8, 42.0)], law, op, 3)
    >>> float(abs(v[0])), bool(abs(v[1]) < 1e-12 and abs(v[2]) < 1e-9)
    (1e-06, True)
    """
    th = 2.0 * np.pi * (np.arange(n_phase) + 0.5) / n_phase
    zeta = (op.crabbing_velocity_m_s + amplitude_m_s * np.sin(th)) / op.rolling_speed_m_s
    q = -adhesion_ratio(zeta, contact, op.rolling_speed_m_s) * contact.normal_load_n
    # on the cycle every mode feels the creep curve's slope averaged over the slip's sweep
    slope = float(np.mean(adhesion_ratio_slope(zeta, contact, op.rolling_speed_m_s)))
    friction = contact.normal_load_n / op.rolling_speed_m_s * slope
    damping = [max(m.damping_ns_m + friction * m.lateral**2, m.damping_ns_m) for m in modes]
    out = np.zeros(orders, complex)
    out[0] = amplitude_m_s
    for k in range(2, orders + 1):
        force = 2.0 * np.mean(q * np.exp(-1j * k * th))
        w = 2.0 * math.pi * frequency_hz * k
        mobility = sum(
            m.lateral**2 * 1j * w / (m.stiffness_n_m - m.mass_kg * w * w + 1j * c * w)
            for m, c in zip(modes, damping)
        )
        out[k - 1] = mobility * force
    return out
