"""Which of several growing modes carries the limit cycle, without a time domain: each
mode's harmonic-balance cycle tested against the others' growth on it (mode competition).

A single mode's harmonic balance (:mod:`reduced.predictor`) answers for the system only
if its cycle is an attractor: once the mode k oscillates at its limit-cycle amplitude A_k,
the contact's slip velocity sweeps Vc + A_k sin(theta), and every other oscillation, at
its own (incommensurate) frequency, sees the creep curve's slope averaged over that sweep,
<dmu/dzeta>_theta, instead of its slope at steady sliding. Their growth rates on the cycle
are the eigenvalues of the same linear model (the modes, the counter-body, the normal
contact) with the friction damping g = (W / V0) <dmu/dzeta>_theta (W the normal load, V0
the rolling speed). On a falling creep curve a large cycle reaches the steep branch near
zero slip and damps the others; a small one may leave another mode growing, which then
takes the cycle over. The modes that share the cycle's eigenvalue (a coupled pair) are
the cycle itself.

:func:`surviving_cycle` follows the invasion from the mode that reaches its cycle first from
rest (not always the fastest-growing: the creep force's step sets a low mode going harder
than a high one, by its 1 / (m omega)): while some mode grows on the present cycle, the one
growing fastest on it takes over; the first
cycle on which nothing else grows is the answer. A cycle visited twice (no mode's cycle
resists the others) means no single-mode cycle answers: the time domain must.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from contact.creep import ContactLaw, adhesion_ratio_slope

from .model import ModalDOF, OperatingPoint
from .predictor import equivalent_mode, harmonic_distortion, initial_amplitude, predict_limit_cycle
from .stability import LinearContact, growth_rates

if TYPE_CHECKING:
    from .counter_body import BodyModel

__all__ = [
    "ModeCycle",
    "averaged_slope",
    "growth_on_cycle",
    "mode_cycle",
    "saturation_time_s",
    "surviving_cycle",
]

#: Phase points of the averages (the creep law's kinks make the midpoint rule algebraic:
#: 1024 points hold the averaged slope to about 1e-5)
N_PHASE = 1024


@dataclass(frozen=True)
class ModeCycle:
    """One mode's harmonic-balance cycle among the others.

    Attributes
    ----------
    index : int
        The mode's position in the modes given.
    amplitude_m_s : float
        Its contact velocity amplitude [m/s] (0: no cycle from rest).
    distortion : float
        The contact force's rms beyond its fundamental over the modal force.
    clipped : bool
        The rest of the system adds more than the mode's damping: a lower bound.
    growth_on_cycle_1_s : tuple of float
        Every mode's growth rate on this cycle [1/s] (0 for the modes of its eigenvalue).
    """

    index: int
    amplitude_m_s: float
    distortion: float
    clipped: bool
    growth_on_cycle_1_s: tuple[float, ...]

    @property
    def invader(self) -> int | None:
        """The mode that grows fastest on this cycle (None: none grows: an attractor)."""
        rates = np.asarray(self.growth_on_cycle_1_s)
        j = int(np.argmax(rates))
        return j if rates[j] > 0.0 else None


def averaged_slope(amplitude_m_s: float, contact: ContactLaw, op: OperatingPoint) -> float:
    """<dmu/dzeta> over a cycle of contact velocity amplitude ``amplitude_m_s`` [m/s]."""
    theta = 2.0 * np.pi * (np.arange(N_PHASE) + 0.5) / N_PHASE
    zeta = (op.crabbing_velocity_m_s + amplitude_m_s * np.sin(theta)) / op.rolling_speed_m_s
    return float(np.mean(adhesion_ratio_slope(zeta, contact, op.rolling_speed_m_s)))


def growth_on_cycle(
    amplitude_m_s: float,
    modes: Sequence[ModalDOF],
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> np.ndarray:
    """Each mode's growth rate [1/s] on a cycle of contact velocity amplitude
    ``amplitude_m_s`` (module docstring); at 0, its linear growth rate at steady sliding.

    Examples
    --------
    At zero amplitude a mode keeps its linear growth rate:

    >>> import reduced as r
    >>> law = r.ContactLaw.from_hertz(r.hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0),
    ...                               friction_coefficient=0.3)
    >>> op = r.OperatingPoint.from_rpm(800, 0.213, 0.39)
    >>> mode = r.ModalDOF(3.1, 1.6e8, 42.0)
    >>> sigma = growth_on_cycle(0.0, [mode], law, op)[0]
    >>> bool(abs(sigma - r.linear_stability([mode], law, op).modes[0].growth_rate_1_s) < 1e-9)
    True
    """
    linear = LinearContact.at(contact, op)
    g = contact.normal_load_n / op.rolling_speed_m_s * averaged_slope(amplitude_m_s, contact, op)
    damping = np.array([m.damping_ns_m for m in modes])
    lin = replace(linear, friction_damping_ns_m=g)
    return growth_rates(modes, damping, lin, wheel_speed_rad_s, body, speaking=True)


def _balance(
    k: int, modes: Sequence[ModalDOF], contact: ContactLaw, op: OperatingPoint, linear_rates: np.ndarray
) -> tuple[ModalDOF, bool, float]:
    """Mode ``k``'s equivalent mode (``reduced.equivalent_mode``), whether it is clipped and
    its cycle's amplitude [m/s] (0: none)."""
    eq, clipped = equivalent_mode(modes[k], contact, op, float(linear_rates[k]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the distortion is reported instead
        prediction = predict_limit_cycle(eq, contact, op)
    amplitude = prediction.velocity_amplitude_m_s
    if not (math.isfinite(amplitude) and amplitude > 0.0):
        amplitude = 0.0
    return eq, clipped, float(amplitude)


def saturation_time_s(
    k: int,
    modes: Sequence[ModalDOF],
    contact: ContactLaw,
    op: OperatingPoint,
    linear_rates: np.ndarray,
    amplitude_m_s: float,
) -> float:
    """How long mode ``k`` takes from rest to a cycle of ``amplitude_m_s`` [s]:
    ln(A / a0) / sigma, a0 the amplitude the creep force's step gives it
    (``reduced.predictor.initial_amplitude``), sigma its linear growth rate among the others
    (``linear_rates``); inf where it does not grow."""
    sigma = float(linear_rates[k])
    initial = initial_amplitude(modes[k], contact, op)
    if sigma <= 0.0 or amplitude_m_s <= 0.0 or initial <= 0.0:
        return math.inf
    return math.log(max(amplitude_m_s / initial, 1.0)) / sigma


def mode_cycle(
    k: int,
    modes: Sequence[ModalDOF],
    eigenvalues: Sequence[int],
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
    linear_rates: np.ndarray | None = None,
    balance: tuple[ModalDOF, bool, float] | None = None,
) -> ModeCycle:
    """Mode ``k``'s harmonic-balance cycle (its damping lumped so that it grows as the
    whole linear model says, ``reduced.equivalent_mode``) and every mode's growth rate on it
    (0 for the modes of its eigenvalue, ``eigenvalues`` naming each mode's);
    ``linear_rates``: the modes' growth rates at steady sliding, and ``balance`` its
    equivalent mode, clipping and amplitude on them, where already solved."""
    if linear_rates is None:
        linear_rates = growth_on_cycle(0.0, modes, contact, op, wheel_speed_rad_s, body)
    eq, clipped, amplitude = balance or _balance(k, modes, contact, op, linear_rates)
    if amplitude == 0.0:
        return ModeCycle(k, 0.0, 0.0, clipped, tuple(float(x) for x in linear_rates))
    rates = growth_on_cycle(amplitude, modes, contact, op, wheel_speed_rad_s, body)
    rates[[j for j, e in enumerate(eigenvalues) if e == eigenvalues[k]]] = 0.0
    distortion = harmonic_distortion(amplitude, eq, contact, op)
    return ModeCycle(k, amplitude, float(distortion), clipped, tuple(float(x) for x in rates))


def surviving_cycle(
    modes: Sequence[ModalDOF],
    eigenvalues: Sequence[int],
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
    start: int | None = None,
) -> tuple[ModeCycle | None, tuple[ModeCycle, ...]]:
    """The cycle the invasion from mode ``start`` settles on (module docstring), and every
    cycle visited in order; None where the invasion returns to a cycle it left (no
    single-mode cycle resists the others) or a mode has no cycle from rest. ``start``
    None: the mode that reaches its cycle first from rest (:func:`saturation_time_s`: of
    two modes growing about as fast, the lower one, which the creep force's step sets
    going harder). ``eigenvalues`` names each mode's eigenvalue (modes that share one are
    one oscillation)."""
    visited: list[ModeCycle] = []
    linear_rates = growth_on_cycle(0.0, modes, contact, op, wheel_speed_rad_s, body)
    balances: dict[int, tuple[ModalDOF, bool, float]] = {}  # each mode's on the linear rates
    if start is None:
        # the cycles' amplitudes are the creep curve's more than the modes' (within a quarter
        # of each other on the railway wheel's maps): the fastest-growing mode's stands for
        # all, and the time goes with its logarithm (a quarter: 0.22 against ln(A/a0) of 3-10)
        fastest = int(np.argmax(linear_rates))
        balances[fastest] = _balance(fastest, modes, contact, op, linear_rates)
        reference = balances[fastest][2]
        times = [saturation_time_s(j, modes, contact, op, linear_rates, reference) for j in range(len(modes))]
        start = int(np.argmin(times)) if math.isfinite(min(times)) else fastest
    k: int | None = start
    while k is not None and all(c.index != k for c in visited):
        cycle = mode_cycle(
            k, modes, eigenvalues, contact, op, wheel_speed_rad_s, body, linear_rates, balances.get(k)
        )
        visited.append(cycle)
        if cycle.amplitude_m_s == 0.0:
            return None, tuple(visited)
        k = cycle.invader
        if k is None:
            return cycle, tuple(visited)
    return None, tuple(visited)
