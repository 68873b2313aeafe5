"""A circumferential harmonic seen by a fixed microphone: a standing wave
``P(r, z) cos(n theta)``, or a travelling one (the two members of a pair a quarter
period apart, as a turning wheel's pair of modes is seen from the contact).

A travelling wave passes every angle with the standing wave's antinode amplitude, and
radiates the power of both members: twice a standing wave's (n >= 1; an n = 0 wave has
no partner and does not travel)."""

from __future__ import annotations

import math

__all__ = ["pressure_amplitude", "radiated_power"]


def pressure_amplitude(
    pressure_pa: complex, harmonic: int, theta_rad: float, travelling: bool = False
) -> float:
    """The peak pressure [Pa] at angle ``theta_rad`` of a harmonic whose cos(n theta)
    amplitude at that (r, z) is ``pressure_pa``."""
    angular = 1.0 if travelling else abs(math.cos(harmonic * theta_rad))
    return abs(pressure_pa) * angular


def radiated_power(standing_power_w: float, harmonic: int, travelling: bool = False) -> float:
    """The power [W] of the wave whose standing (cos n theta) form radiates
    ``standing_power_w``."""
    return standing_power_w * (2.0 if travelling and harmonic >= 1 else 1.0)
